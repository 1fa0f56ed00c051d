//! An index that may be absent, in the four bytes of a `u32`.
//!
//! Per-vertex tables (which input vertex a simplified vertex is, a triangle that uses
//! a vertex, a vertex's new number) hold one entry per vertex of meshes of tens of
//! millions: an `Option<u32>` would make them 8 bytes an entry. `u32::MAX` marks the
//! absent index instead, which no mesh reaches (vertex and triangle counts are `u32`
//! and the last value is never an index), behind a type so that it can't be taken for
//! one.

/// A vertex or triangle index, or none: an `Option<u32>` in 4 bytes.
#[repr(transparent)]
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct MaybeIndex(u32);

impl MaybeIndex {
    /// No index: where a table has no entry (a vertex a collapse placed, a vertex no
    /// triangle uses, one that is dropped).
    pub const NONE: MaybeIndex = MaybeIndex(u32::MAX);

    /// Index `i`, which must not be `u32::MAX`.
    #[inline]
    pub const fn some(i: u32) -> MaybeIndex {
        debug_assert!(i != u32::MAX, "u32::MAX is no index");
        MaybeIndex(i)
    }

    /// The index, if there is one.
    #[inline]
    pub const fn get(self) -> Option<u32> {
        if self.0 == u32::MAX {
            None
        } else {
            Some(self.0)
        }
    }

    /// Whether there is no index.
    #[inline]
    pub const fn is_none(self) -> bool {
        self.0 == u32::MAX
    }

    /// Whether there is an index.
    #[inline]
    pub const fn is_some(self) -> bool {
        self.0 != u32::MAX
    }
}

impl From<Option<u32>> for MaybeIndex {
    #[inline]
    fn from(i: Option<u32>) -> MaybeIndex {
        i.map_or(MaybeIndex::NONE, MaybeIndex::some)
    }
}

impl From<MaybeIndex> for Option<u32> {
    #[inline]
    fn from(i: MaybeIndex) -> Option<u32> {
        i.get()
    }
}

impl Default for MaybeIndex {
    /// No index, as a table of entries still to fill starts.
    fn default() -> MaybeIndex {
        MaybeIndex::NONE
    }
}

impl std::fmt::Debug for MaybeIndex {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.get().fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_index_keeps_the_size_of_a_u32_and_reads_back_as_an_option() {
        assert_eq!(std::mem::size_of::<MaybeIndex>(), 4);
        assert_eq!(MaybeIndex::some(7).get(), Some(7));
        assert_eq!(MaybeIndex::NONE.get(), None);
        assert_eq!(MaybeIndex::from(Some(0)), MaybeIndex::some(0));
        assert_eq!(MaybeIndex::from(None), MaybeIndex::NONE);
        assert!(MaybeIndex::default().is_none());
        assert_eq!(format!("{:?}", MaybeIndex::some(3)), "Some(3)");
    }
}
