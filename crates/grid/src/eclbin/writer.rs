//! Writing keywords as Eclipse big-endian Fortran records.
//!
//! Data records are encoded in parallel, a bounded group of them at a time, and
//! streamed out: writing a 3 GB ZCORN needs a few megabytes beyond the array itself.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::record::{Record, RecordData, RecordKind};
use crate::{Error, Result};

/// Data records encoded per parallel group before they are written out: about 1 MB.
const BLOCKS_PER_GROUP: usize = 256;

/// Writes keywords to `W`; `path` names the destination in errors.
pub struct RecordWriter<W: Write> {
    out: W,
    path: PathBuf,
    buf: Vec<u8>,
}

impl RecordWriter<BufWriter<File>> {
    /// Creates (or truncates) `path`.
    pub fn create(path: &Path) -> Result<Self> {
        let file = File::create(path).map_err(|e| Error::io(path, e))?;
        Ok(RecordWriter::new(
            BufWriter::with_capacity(1 << 20, file),
            path,
        ))
    }
}

impl<W: Write> RecordWriter<W> {
    /// Writes to any destination (a buffer in tests); `path` only names it in errors.
    pub fn new(out: W, path: impl Into<PathBuf>) -> Self {
        RecordWriter {
            out,
            path: path.into(),
            buf: Vec::new(),
        }
    }

    /// Flushes and returns the destination.
    pub fn finish(mut self) -> Result<W> {
        self.out.flush().map_err(|e| Error::io(&self.path, e))?;
        Ok(self.out)
    }

    /// Writes one decoded keyword.
    pub fn write(&mut self, record: &Record) -> Result<()> {
        let name = record.name.as_str();
        match &record.data {
            RecordData::Inte(v) => self.inte(name, v),
            RecordData::Real(v) => self.real(name, v),
            RecordData::Doub(v) => self.doub(name, v),
            RecordData::Logi(v) => self.logi(name, v),
            RecordData::Char(v) => self.strings(name, RecordKind::Char, v),
            RecordData::C0nn { width, values } => {
                self.strings(name, RecordKind::C0nn(*width), values)
            }
            RecordData::Mess => self.mess(name),
        }
    }

    /// An INTE keyword, in data records of 1000 items as Eclipse writes them.
    pub fn inte(&mut self, name: &str, values: &[i32]) -> Result<()> {
        self.items(name, RecordKind::Inte, values, |v, o| {
            o.copy_from_slice(&v.to_be_bytes())
        })
    }

    /// A REAL keyword (ZCORN, properties, solution arrays).
    pub fn real(&mut self, name: &str, values: &[f32]) -> Result<()> {
        self.items(name, RecordKind::Real, values, |v, o| {
            o.copy_from_slice(&v.to_be_bytes())
        })
    }

    /// A DOUB keyword, for values that `f32` would round.
    pub fn doub(&mut self, name: &str, values: &[f64]) -> Result<()> {
        self.items(name, RecordKind::Doub, values, |v, o| {
            o.copy_from_slice(&v.to_be_bytes())
        })
    }

    /// Logicals as Eclipse writes them: -1 for true, 0 for false.
    pub fn logi(&mut self, name: &str, values: &[bool]) -> Result<()> {
        self.items(name, RecordKind::Logi, values, |&v, o| {
            o.copy_from_slice(&(-i32::from(v)).to_be_bytes())
        })
    }

    /// Flags as INTE 1/0 (ACTNUM), without building an integer array first.
    pub fn flags(&mut self, name: &str, values: &[bool]) -> Result<()> {
        self.items(name, RecordKind::Inte, values, |&v, o| {
            o.copy_from_slice(&i32::from(v).to_be_bytes())
        })
    }

    /// `f64` values written as REAL (COORD, MAPAXES): the precision Eclipse keeps.
    pub fn real_from_f64(&mut self, name: &str, values: &[f64]) -> Result<()> {
        self.items(name, RecordKind::Real, values, |&v, o| {
            o.copy_from_slice(&(v as f32).to_be_bytes())
        })
    }

    /// Strings (CHAR or C0nn), blank-padded to the type's width; a string that is
    /// longer or not ASCII is refused, since it could not be read back as written.
    pub fn strings<S: AsRef<str> + Sync>(
        &mut self,
        name: &str,
        kind: RecordKind,
        values: &[S],
    ) -> Result<()> {
        let width = kind.item_size();
        if !matches!(kind, RecordKind::Char | RecordKind::C0nn(1..=999)) {
            return Err(Error::model(
                &self.path,
                name,
                format!("type {} does not hold strings", kind.name()),
            ));
        }
        if let Some(bad) = values
            .iter()
            .map(AsRef::as_ref)
            .find(|s| s.len() > width || !s.is_ascii())
        {
            return Err(Error::model(
                &self.path,
                name,
                format!("{bad:?} is not ASCII of at most {width} characters"),
            ));
        }
        self.items(name, kind, values, |s, o| {
            let s = s.as_ref().as_bytes();
            o[..s.len()].copy_from_slice(s);
            o[s.len()..].fill(b' ');
        })
    }

    /// A bare marker keyword (STARTSOL, ENDSOL, ...).
    pub fn mess(&mut self, name: &str) -> Result<()> {
        self.header(name, RecordKind::Mess, 0)
    }

    fn io(&self, e: std::io::Error) -> Error {
        Error::io(&self.path, e)
    }

    fn header(&mut self, name: &str, kind: RecordKind, count: usize) -> Result<()> {
        if name.len() > 8 || !name.bytes().all(|c| (b' '..=b'~').contains(&c)) {
            return Err(Error::model(
                &self.path,
                name,
                "keyword names are at most 8 printable ASCII characters",
            ));
        }
        let count = i32::try_from(count).map_err(|_| {
            Error::model(
                &self.path,
                name,
                format!("{count} items are more than a header can count (2^31 - 1)"),
            )
        })?;
        let mut head = [b' '; 24];
        head[..4].copy_from_slice(&16i32.to_be_bytes());
        head[4..4 + name.len()].copy_from_slice(name.as_bytes());
        head[12..16].copy_from_slice(&count.to_be_bytes());
        head[16..20].copy_from_slice(&kind.code());
        head[20..].copy_from_slice(&16i32.to_be_bytes());
        self.out.write_all(&head).map_err(|e| self.io(e))
    }

    /// Writes a header and the data records of `values`, `encode` filling one item's
    /// bytes. Groups of data records are encoded in parallel into a reused buffer.
    fn items<T: Sync>(
        &mut self,
        name: &str,
        kind: RecordKind,
        values: &[T],
        encode: impl Fn(&T, &mut [u8]) + Sync,
    ) -> Result<()> {
        self.header(name, kind, values.len())?;
        let size = kind.item_size();
        let per_block = kind.block_items();
        let stride = per_block * size + 8;
        for group in values.chunks(per_block * BLOCKS_PER_GROUP) {
            let blocks = group.len().div_ceil(per_block);
            self.buf.resize(group.len() * size + 8 * blocks, 0);
            self.buf
                .par_chunks_mut(stride)
                .zip(group.par_chunks(per_block))
                .with_min_len(16)
                .for_each(|(out, items)| {
                    // A block is at most 1000 x 8 bytes, so its length fits an i32.
                    let marker = ((items.len() * size) as i32).to_be_bytes();
                    let end = out.len() - 4;
                    out[..4].copy_from_slice(&marker);
                    out[end..].copy_from_slice(&marker);
                    for (o, v) in out[4..end].chunks_exact_mut(size).zip(items) {
                        encode(v, o);
                    }
                });
            let (out, buf) = (&mut self.out, &self.buf);
            out.write_all(buf).map_err(|e| Error::io(&self.path, e))?;
        }
        Ok(())
    }
}
