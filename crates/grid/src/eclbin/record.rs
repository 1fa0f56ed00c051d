//! Reading Fortran unformatted sequential records in Eclipse's big-endian layout.
//!
//! Every record is `len (i32 BE) | len bytes | len (i32 BE)`. A keyword is a 16-byte
//! header record (8-char name, i32 item count, 4-char type) followed by as many data
//! records as it takes to hold `count` items. [`Records`] walks a byte slice and checks
//! that structure completely before handing out a [`RecordView`], so decoding a view
//! cannot fail and never allocates more than the file itself holds.

use std::path::{Path, PathBuf};

use memmap2::{Mmap, MmapOptions};
use rayon::prelude::*;

use crate::pages::Pages;
use crate::{Error, Result};

/// Item type of a keyword, from the 4 type characters of its header.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RecordKind {
    /// `INTE`: 4-byte signed integers.
    Inte,
    /// `REAL`: 4-byte IEEE floats.
    Real,
    /// `DOUB`: 8-byte IEEE floats.
    Doub,
    /// `LOGI`: 4-byte logicals, 0 false and anything else true.
    Logi,
    /// `CHAR`: 8-byte blank-padded strings.
    Char,
    /// `C0nn`: `nn`-byte blank-padded strings (the type is `C` and three digits).
    C0nn(u16),
    /// `MESS`: a bare marker keyword with no data.
    Mess,
}

impl RecordKind {
    /// Parses the 4 type characters of a header.
    pub fn from_code(code: [u8; 4]) -> Option<Self> {
        Some(match &code {
            b"INTE" => RecordKind::Inte,
            b"REAL" => RecordKind::Real,
            b"DOUB" => RecordKind::Doub,
            b"LOGI" => RecordKind::Logi,
            b"CHAR" => RecordKind::Char,
            b"MESS" => RecordKind::Mess,
            [b'C', digits @ ..] if digits.iter().all(u8::is_ascii_digit) => {
                let width = digits
                    .iter()
                    .fold(0u16, |w, d| w * 10 + u16::from(d - b'0'));
                if width == 0 {
                    return None;
                }
                RecordKind::C0nn(width)
            }
            _ => return None,
        })
    }

    /// The 4 type characters written in a header.
    pub fn code(&self) -> [u8; 4] {
        match self {
            RecordKind::Inte => *b"INTE",
            RecordKind::Real => *b"REAL",
            RecordKind::Doub => *b"DOUB",
            RecordKind::Logi => *b"LOGI",
            RecordKind::Char => *b"CHAR",
            RecordKind::Mess => *b"MESS",
            RecordKind::C0nn(w) => {
                let w = w.min(&999);
                [
                    b'C',
                    b'0' + (w / 100) as u8,
                    b'0' + (w / 10 % 10) as u8,
                    b'0' + (w % 10) as u8,
                ]
            }
        }
    }

    /// Bytes per item (0 for `MESS`).
    pub fn item_size(&self) -> usize {
        match self {
            RecordKind::Inte | RecordKind::Real | RecordKind::Logi => 4,
            RecordKind::Doub | RecordKind::Char => 8,
            RecordKind::C0nn(w) => usize::from(*w),
            RecordKind::Mess => 0,
        }
    }

    /// Items per data record as Eclipse writes them: 1000 numbers, 105 strings.
    pub fn block_items(&self) -> usize {
        match self {
            RecordKind::Char | RecordKind::C0nn(_) => 105,
            _ => 1000,
        }
    }

    /// The type as it appears in a file, for messages.
    pub fn name(&self) -> String {
        String::from_utf8_lossy(&self.code()).into_owned()
    }
}

/// The values of one keyword, decoded.
#[derive(Clone, Debug, PartialEq)]
pub enum RecordData {
    /// `INTE` values (dimensions, ACTNUM, INTEHEAD, ...).
    Inte(Vec<i32>),
    /// `REAL` values (ZCORN, properties, solution arrays, ...).
    Real(Vec<f32>),
    /// `DOUB` values (DOUBHEAD, double-precision solution arrays, ...).
    Doub(Vec<f64>),
    /// `LOGI` values (LOGIHEAD, ...), any non-zero word read as true.
    Logi(Vec<bool>),
    /// 8-character strings, trailing blanks removed.
    Char(Vec<String>),
    /// Strings of `width` characters (type `C0nn`), trailing blanks removed.
    C0nn {
        /// Characters per string, 1 to 999: the `nn` of the type code.
        width: u16,
        /// The strings, each at most `width` characters.
        values: Vec<String>,
    },
    /// No values: the keyword is a marker (STARTSOL, ENDSOL, ...).
    Mess,
}

impl RecordData {
    /// The item type these values are written as.
    pub fn kind(&self) -> RecordKind {
        match self {
            RecordData::Inte(_) => RecordKind::Inte,
            RecordData::Real(_) => RecordKind::Real,
            RecordData::Doub(_) => RecordKind::Doub,
            RecordData::Logi(_) => RecordKind::Logi,
            RecordData::Char(_) => RecordKind::Char,
            RecordData::C0nn { width, .. } => RecordKind::C0nn(*width),
            RecordData::Mess => RecordKind::Mess,
        }
    }

    /// Number of items.
    pub fn len(&self) -> usize {
        match self {
            RecordData::Inte(v) => v.len(),
            RecordData::Real(v) => v.len(),
            RecordData::Doub(v) => v.len(),
            RecordData::Logi(v) => v.len(),
            RecordData::Char(v) | RecordData::C0nn { values: v, .. } => v.len(),
            RecordData::Mess => 0,
        }
    }

    /// Whether there are no items (always so for `Mess`).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// One keyword: its name (at most 8 characters, trailing blanks removed) and values.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// The keyword (ZCORN, PORO, SEQNUM, ...); the writer refuses one longer than 8
    /// characters or not printable ASCII.
    pub name: String,
    /// Its values; their variant is the type written in the header.
    pub data: RecordData,
}

impl Record {
    /// A keyword to write, or to compare with what a reader decoded.
    pub fn new(name: impl Into<String>, data: RecordData) -> Self {
        Record {
            name: name.into(),
            data,
        }
    }
}

/// Builds the error for a malformed binary file. `record` is the 1-based number of the
/// keyword (header plus data records) in the file, `offset` the byte offset of the
/// Fortran record where the problem was found.
pub(crate) fn binary_error(
    path: &Path,
    record: usize,
    keyword: &str,
    offset: u64,
    message: impl Into<String>,
) -> Error {
    Error::Binary {
        path: path.to_path_buf(),
        record,
        keyword: keyword.to_string(),
        offset,
        message: message.into(),
    }
}

/// An Eclipse binary file mapped into memory, read through [`EclFile::records`].
pub struct EclFile {
    path: PathBuf,
    map: Option<Mmap>,
}

impl EclFile {
    /// Maps `path` read-only. The whole file is prefaulted because every reader here
    /// walks it from start to end; the pages of what [`Self::records`] decodes are
    /// given back as they are decoded.
    pub fn open(path: &Path) -> Result<Self> {
        let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
        let len = file.metadata().map_err(|e| Error::io(path, e))?.len();
        let map = if len == 0 {
            // Mapping an empty file is an error on some systems; nothing to map anyway.
            None
        } else {
            // SAFETY: the map is read-only and only ever read as bytes. Another process
            // truncating or rewriting the file while it is mapped would change what we
            // read (or fault); that is the accepted contract of memory-mapped reading,
            // taken here because copying a multi-gigabyte grid first would cost time
            // and double the memory.
            Some(
                unsafe { MmapOptions::new().populate().map(&file) }
                    .map_err(|e| Error::io(path, e))?,
            )
        };
        Ok(EclFile {
            path: path.to_path_buf(),
            map,
        })
    }

    /// The file that was mapped, for messages.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The file's bytes.
    pub fn bytes(&self) -> &[u8] {
        self.map.as_deref().unwrap_or(&[])
    }

    /// The keywords of the file, in order. What their views decode is given back to
    /// the page cache as it is decoded ([`RecordView::to_f32`] and the like).
    pub fn records(&self) -> Records<'_> {
        Records {
            pages: self.map.as_ref().map(Pages::of).unwrap_or_default(),
            ..Records::new(&self.path, self.bytes())
        }
    }
}

/// Reads every keyword of a file and decodes its values.
pub fn read_records(path: &Path) -> Result<Vec<Record>> {
    let file = EclFile::open(path)?;
    parse_records(path, file.bytes())
}

/// Decodes every keyword of an in-memory file; `path` only names it in errors.
pub fn parse_records(path: &Path, bytes: &[u8]) -> Result<Vec<Record>> {
    Records::new(path, bytes)
        .map(|r| r.map(|view| view.decode()))
        .collect()
}

/// Iterator over the keywords of an in-memory file, yielding zero-copy, fully
/// validated [`RecordView`]s. After the first error it yields nothing more.
pub struct Records<'a> {
    path: &'a Path,
    bytes: &'a [u8],
    pos: usize,
    index: usize,
    failed: bool,
    /// The file map `bytes` are, when they are one.
    pages: Pages<'a>,
}

/// One keyword of a file, checked but not decoded.
#[derive(Clone, Copy, Debug)]
pub struct RecordView<'a> {
    path: &'a Path,
    name: &'a str,
    kind: RecordKind,
    count: usize,
    index: usize,
    offset: u64,
    /// The data records, markers included.
    body: &'a [u8],
    /// The file map `body` lies in, when it does.
    pages: Pages<'a>,
}

/// Reads the 4-byte big-endian length marker at `pos`.
fn marker(bytes: &[u8], pos: usize) -> Option<i32> {
    let m = bytes.get(pos..pos.checked_add(4)?)?;
    Some(i32::from_be_bytes([m[0], m[1], m[2], m[3]]))
}

impl<'a> Records<'a> {
    /// Walks `bytes`; `path` only names the file in errors.
    pub fn new(path: &'a Path, bytes: &'a [u8]) -> Self {
        Records {
            path,
            bytes,
            pos: 0,
            index: 0,
            failed: false,
            pages: Pages::default(),
        }
    }

    /// The Fortran record at `pos`: its payload range and the position after it.
    fn fortran_record(&self, pos: usize, keyword: &str) -> Result<(std::ops::Range<usize>, usize)> {
        let err = |msg: String| binary_error(self.path, self.index, keyword, pos as u64, msg);
        let left = self.bytes.len() - pos;
        let len = marker(self.bytes, pos).ok_or_else(|| {
            err(format!(
                "{left} stray bytes at the end of the file, too few for a record length"
            ))
        })?;
        let len = usize::try_from(len).map_err(|_| err(format!("negative record length {len}")))?;
        let start = pos + 4;
        if len + 8 > left {
            return Err(err(format!(
                "record of {len} bytes runs past the end of the file ({left} bytes left): truncated?"
            )));
        }
        let end = start + len;
        let trailing = marker(self.bytes, end).unwrap_or(-1);
        if usize::try_from(trailing).ok() != Some(len) {
            return Err(err(format!(
                "leading length marker {len} and trailing marker {trailing} disagree"
            )));
        }
        Ok((start..end, end + 4))
    }

    fn next_view(&mut self) -> Result<RecordView<'a>> {
        self.index += 1;
        let offset = self.pos;
        let (head, mut pos) = self.fortran_record(offset, "")?;
        let head = &self.bytes[head];
        let err = |keyword: &str, at: usize, msg: String| {
            binary_error(self.path, self.index, keyword, at as u64, msg)
        };
        if head.len() != 16 {
            return Err(err(
                "",
                offset,
                format!(
                    "expected a 16-byte keyword header, found a record of {} bytes",
                    head.len()
                ),
            ));
        }
        let printable = |b: &[u8]| b.iter().all(|c| (b' '..=b'~').contains(c));
        if !printable(&head[..8]) {
            return Err(err(
                "",
                offset,
                format!("keyword name {:?} is not printable text", &head[..8]),
            ));
        }
        // Checked printable ASCII just above, so this cannot fail.
        let name = std::str::from_utf8(&head[..8]).unwrap_or("").trim_end();
        let kind =
            RecordKind::from_code([head[12], head[13], head[14], head[15]]).ok_or_else(|| {
                err(
                    name,
                    offset,
                    format!(
                        "unknown item type {:?}",
                        String::from_utf8_lossy(&head[12..16])
                    ),
                )
            })?;
        let count = i32::from_be_bytes([head[8], head[9], head[10], head[11]]);
        let count = usize::try_from(count)
            .map_err(|_| err(name, offset, format!("negative item count {count}")))?;
        let size = kind.item_size();
        if size == 0 && count != 0 {
            return Err(err(
                name,
                offset,
                format!(
                    "a {} keyword holds no data, yet its header counts {count} items",
                    kind.name()
                ),
            ));
        }
        let left = self.bytes.len() - pos;
        if count.saturating_mul(size) > left {
            return Err(err(
                name,
                offset,
                format!(
                    "header announces {count} {} items ({} bytes), only {left} bytes follow",
                    kind.name(),
                    count as u128 * size as u128
                ),
            ));
        }
        let body_start = pos;
        let mut remaining = count;
        while remaining > 0 {
            if pos == self.bytes.len() {
                return Err(err(
                    name,
                    pos,
                    format!(
                        "file ends after {} of the {count} items the header announces",
                        count - remaining
                    ),
                ));
            }
            let (data, next) = self.fortran_record(pos, name)?;
            let bytes = data.len();
            if bytes == 0 || bytes % size != 0 {
                return Err(err(
                    name,
                    pos,
                    format!(
                        "data record of {bytes} bytes is not a whole, non-zero number of {size}-byte items"
                    ),
                ));
            }
            let items = bytes / size;
            if items > remaining {
                return Err(err(
                    name,
                    pos,
                    format!(
                        "data record holds {items} items, only {remaining} remain of the {count} the header announces"
                    ),
                ));
            }
            remaining -= items;
            pos = next;
        }
        self.pos = pos;
        Ok(RecordView {
            path: self.path,
            name,
            kind,
            count,
            index: self.index,
            offset: offset as u64,
            body: &self.bytes[body_start..pos],
            pages: self.pages,
        })
    }
}

impl<'a> Iterator for Records<'a> {
    type Item = Result<RecordView<'a>>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed || self.pos >= self.bytes.len() {
            return None;
        }
        let view = self.next_view();
        self.failed = view.is_err();
        Some(view)
    }
}

/// Iterator over the payloads of the (already validated) data records of a keyword.
struct Blocks<'a> {
    body: &'a [u8],
    pos: usize,
}

impl<'a> Iterator for Blocks<'a> {
    type Item = &'a [u8];

    fn next(&mut self) -> Option<&'a [u8]> {
        let len = usize::try_from(marker(self.body, self.pos)?).ok()?;
        let start = self.pos + 4;
        let payload = self.body.get(start..start + len)?;
        self.pos = start + len + 4;
        Some(payload)
    }
}

/// Data records per parallel task when decoding: enough work to pay for the task.
const BLOCKS_PER_TASK: usize = 8;

/// Data records decoded before their file pages are given back (about 64 MiB).
const BLOCKS_PER_RELEASE: usize = 16 * 1024;

impl<'a> RecordView<'a> {
    /// The keyword name, trailing blanks removed.
    pub fn name(&self) -> &'a str {
        self.name
    }

    /// The item type its header declares, which decides the `to_*` that applies.
    pub fn kind(&self) -> RecordKind {
        self.kind
    }

    /// Number of items the header announces (and the data records hold).
    pub fn len(&self) -> usize {
        self.count
    }

    /// Whether the header counts no items (a `MESS` marker, or an empty array).
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// 1-based number of this keyword in the file.
    pub fn index(&self) -> usize {
        self.index
    }

    /// Byte offset of the header record.
    pub fn offset(&self) -> u64 {
        self.offset
    }

    /// An error about this keyword, located at its header.
    pub fn error(&self, message: impl Into<String>) -> Error {
        binary_error(self.path, self.index, self.name, self.offset, message)
    }

    /// The bytes of the body from address `from` to `to`, when both lie in it.
    fn body_range(&self, from: usize, to: usize) -> Option<&'a [u8]> {
        let start = from.checked_sub(self.body.as_ptr() as usize)?;
        let end = to.checked_sub(self.body.as_ptr() as usize)?;
        self.body.get(start..end)
    }

    fn blocks(&self) -> Blocks<'a> {
        Blocks {
            body: self.body,
            pos: 0,
        }
    }

    /// Decodes every `N`-byte item with `conv`, one parallel task per few data
    /// records, each writing straight into its part of the output. `N` is a constant
    /// so that the byte swapping compiles to vector shuffles.
    fn decode_with<T, const N: usize, F>(&self, conv: F) -> Vec<T>
    where
        T: Copy + Default + Send,
        F: Fn([u8; N]) -> T + Sync,
    {
        let mut out = vec![T::default(); self.count];
        let mut jobs = Vec::new();
        let mut rest = out.as_mut_slice();
        for block in self.blocks() {
            let (head, tail) = rest.split_at_mut(block.len() / N);
            jobs.push((block, head));
            rest = tail;
        }
        // A piece at a time, whose file pages then go back.
        for piece in jobs.chunks_mut(BLOCKS_PER_RELEASE) {
            piece
                .par_iter_mut()
                .with_min_len(BLOCKS_PER_TASK)
                .for_each(|(src, dst)| {
                    for (d, s) in dst.iter_mut().zip(src.chunks_exact(N)) {
                        // chunks_exact(N) yields N bytes, so this always converts.
                        if let Ok(item) = <[u8; N]>::try_from(s) {
                            *d = conv(item);
                        }
                    }
                });
            if let (Some((first, _)), Some((last, _))) = (piece.first(), piece.last()) {
                let from = first.as_ptr() as usize;
                let to = last.as_ptr() as usize + last.len();
                // The piece's blocks are contiguous in the map, markers between them.
                if let Some(bytes) = self.body_range(from, to) {
                    self.pages.give_back_bytes(bytes);
                }
            }
        }
        out
    }

    fn decode_strings(&self) -> Vec<String> {
        let size = self.kind.item_size();
        self.blocks()
            .flat_map(|b| b.chunks_exact(size))
            .map(|s| {
                s.iter()
                    .map(|&c| char::from(c))
                    .collect::<String>()
                    .trim_end()
                    .to_string()
            })
            .collect()
    }

    fn wrong_type(&self, wanted: &str) -> Error {
        self.error(format!("has type {}, expected {wanted}", self.kind.name()))
    }

    /// Numeric values as `f32` (INTE, REAL or DOUB).
    pub fn to_f32(&self) -> Result<Vec<f32>> {
        Ok(match self.kind {
            RecordKind::Real => self.decode_with(f32::from_be_bytes),
            RecordKind::Doub => self.decode_with(|b| f64::from_be_bytes(b) as f32),
            RecordKind::Inte => self.decode_with(|b| i32::from_be_bytes(b) as f32),
            _ => return Err(self.wrong_type("INTE, REAL or DOUB")),
        })
    }

    /// Numeric values as `f64` (INTE, REAL or DOUB).
    pub fn to_f64(&self) -> Result<Vec<f64>> {
        Ok(match self.kind {
            RecordKind::Real => self.decode_with(|b| f64::from(f32::from_be_bytes(b))),
            RecordKind::Doub => self.decode_with(f64::from_be_bytes),
            RecordKind::Inte => self.decode_with(|b| f64::from(i32::from_be_bytes(b))),
            _ => return Err(self.wrong_type("INTE, REAL or DOUB")),
        })
    }

    /// Integer values (INTE only).
    pub fn to_i32(&self) -> Result<Vec<i32>> {
        match self.kind {
            RecordKind::Inte => Ok(self.decode_with(i32::from_be_bytes)),
            _ => Err(self.wrong_type("INTE")),
        }
    }

    /// Integer values as flags, `> 0` true: ACTNUM, where 2 and 3 mark dual-porosity
    /// activity and negative values never mean active.
    pub fn to_positive_flags(&self) -> Result<Vec<bool>> {
        match self.kind {
            RecordKind::Inte => Ok(self.decode_with(|b| i32::from_be_bytes(b) > 0)),
            _ => Err(self.wrong_type("INTE")),
        }
    }

    /// String values (CHAR or C0nn), trailing blanks removed.
    pub fn to_strings(&self) -> Result<Vec<String>> {
        match self.kind {
            RecordKind::Char | RecordKind::C0nn(_) => Ok(self.decode_strings()),
            _ => Err(self.wrong_type("CHAR or C0nn")),
        }
    }

    /// All values, in the type the file holds.
    pub fn decode(&self) -> Record {
        let data = match self.kind {
            RecordKind::Inte => RecordData::Inte(self.decode_with(i32::from_be_bytes)),
            RecordKind::Real => RecordData::Real(self.decode_with(f32::from_be_bytes)),
            RecordKind::Doub => RecordData::Doub(self.decode_with(f64::from_be_bytes)),
            RecordKind::Logi => RecordData::Logi(self.decode_with(|b| u32::from_be_bytes(b) != 0)),
            RecordKind::Char => RecordData::Char(self.decode_strings()),
            RecordKind::C0nn(width) => RecordData::C0nn {
                width,
                values: self.decode_strings(),
            },
            RecordKind::Mess => RecordData::Mess,
        };
        Record::new(self.name, data)
    }
}
