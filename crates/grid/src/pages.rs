//! The memory-mapped file a reader walks, whose pages it gives back to the page cache
//! once read: a multi-gigabyte array then is not resident twice, as file pages and as
//! values.

use memmap2::Mmap;

/// The map a reader's bytes are, when they are one (`None` for bytes held in memory,
/// which are left alone).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Pages<'a> {
    map: Option<&'a Mmap>,
}

/// What goes back at a time: a whole number of pages on every common page size.
const PIECE: usize = 64 * 1024;

impl<'a> Pages<'a> {
    /// The pages of `map`.
    pub(crate) fn of(map: &'a Mmap) -> Self {
        Pages { map: Some(map) }
    }

    /// Gives back the whole pieces of bytes `from..to` of the map and returns where
    /// the next call may start: `to` rounded down to a piece, so that what is left of
    /// a piece goes with the next call's bytes. A failure leaves the pages resident,
    /// which is harmless.
    pub(crate) fn give_back(&self, from: usize, to: usize) -> usize {
        let Some(map) = self.map else {
            return from;
        };
        let (start, end) = (
            from.next_multiple_of(PIECE),
            to.min(map.len()) / PIECE * PIECE,
        );
        if end > start {
            #[cfg(unix)]
            // SAFETY: the map is private and read-only, so dropping its pages loses
            // nothing: a later read of them faults them in from the file again.
            let _ = unsafe {
                map.unchecked_advise_range(memmap2::UncheckedAdvice::DontNeed, start, end - start)
            };
        }
        end.max(from)
    }

    /// [`Self::give_back`] for `bytes`, a part of the map.
    pub(crate) fn give_back_bytes(&self, bytes: &[u8]) {
        if let Some(map) = self.map {
            let base = map.as_ptr() as usize;
            if let Some(from) = (bytes.as_ptr() as usize).checked_sub(base) {
                self.give_back(from, from + bytes.len());
            }
        }
    }
}
