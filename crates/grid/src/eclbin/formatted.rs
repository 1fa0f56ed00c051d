//! Formatted Eclipse files (FEGRID, FINIT, FUNRST, Fnnnn, formatted GRID): the same
//! keywords as the binary files, in text. Each keyword is a header line
//! (`'NAME    '  count 'TYPE'`) and its values. The text is turned into the binary
//! records in memory, so that one reader serves both; errors in the text name the
//! line, errors found after conversion name the keyword's number as in a binary file.

use std::path::Path;

use super::record::{Record, RecordData, RecordKind};
use super::writer::RecordWriter;
use crate::{Error, Result};

/// Whether a file's first bytes are a formatted Eclipse keyword header.
pub fn looks_formatted(head: &[u8]) -> bool {
    let mut t = Text {
        bytes: head,
        pos: 0,
    };
    let (Some(name), Some(count), Some(kind)) = (t.quoted(), t.token(), t.quoted()) else {
        return false;
    };
    name.len() <= 8
        && !name.trim_ascii().is_empty()
        && count.iter().all(u8::is_ascii_digit)
        && !count.is_empty()
        && <[u8; 4]>::try_from(kind).is_ok_and(|k| RecordKind::from_code(k).is_some())
}

struct Text<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Text<'a> {
    fn skip(&mut self) {
        while self
            .bytes
            .get(self.pos)
            .is_some_and(u8::is_ascii_whitespace)
        {
            self.pos += 1;
        }
    }

    fn at_end(&mut self) -> bool {
        self.skip();
        self.pos >= self.bytes.len()
    }

    /// The content of a `'...'` string, or `None` when the next token is not one.
    fn quoted(&mut self) -> Option<&'a [u8]> {
        self.skip();
        if self.bytes.get(self.pos) != Some(&b'\'') {
            return None;
        }
        let rest = &self.bytes[self.pos + 1..];
        let end = memchr::memchr(b'\'', rest)?;
        self.pos += end + 2;
        Some(&rest[..end])
    }

    fn token(&mut self) -> Option<&'a [u8]> {
        self.skip();
        let start = self.pos;
        while self
            .bytes
            .get(self.pos)
            .is_some_and(|b| !b.is_ascii_whitespace())
        {
            self.pos += 1;
        }
        (self.pos > start).then(|| &self.bytes[start..self.pos])
    }
}

fn number<T: fast_float2::FastFloat>(t: &[u8]) -> Option<T> {
    // Fortran writes double exponents with D.
    let fixed: Vec<u8> = t
        .iter()
        .map(|&b| if b == b'D' || b == b'd' { b'E' } else { b })
        .collect();
    fast_float2::parse(&fixed).ok()
}

/// Reads `count` values of `kind`.
fn values(t: &mut Text, kind: RecordKind, count: usize) -> std::result::Result<RecordData, String> {
    // Every value takes two bytes at least (itself and a blank): no more room than that.
    if count > (t.bytes.len() - t.pos) / 2 + 1 {
        return Err(format!(
            "{count} values cannot fit in the {} bytes left",
            t.bytes.len() - t.pos
        ));
    }
    fn each<T>(
        t: &mut Text,
        count: usize,
        what: &str,
        f: impl Fn(&[u8]) -> Option<T>,
    ) -> std::result::Result<Vec<T>, String> {
        (0..count)
            .map(|n| {
                let tok = t
                    .token()
                    .ok_or_else(|| format!("the file ends after {n} of {count} values"))?;
                f(tok).ok_or_else(|| {
                    format!(
                        "value {} '{}' is not {what}",
                        n + 1,
                        String::from_utf8_lossy(tok)
                    )
                })
            })
            .collect()
    }
    Ok(match kind {
        RecordKind::Inte => RecordData::Inte(each(t, count, "an integer", |b| {
            std::str::from_utf8(b).ok()?.parse().ok()
        })?),
        RecordKind::Real => RecordData::Real(each(t, count, "a number", number::<f32>)?),
        RecordKind::Doub => RecordData::Doub(each(t, count, "a number", number::<f64>)?),
        RecordKind::Logi => {
            RecordData::Logi(each(t, count, "T or F", |b| match b.trim_ascii_start() {
                b"T" | b"'T'" => Some(true),
                b"F" | b"'F'" => Some(false),
                _ => None,
            })?)
        }
        RecordKind::Char | RecordKind::C0nn(_) => {
            let strings = (0..count)
                .map(|n| {
                    t.quoted()
                        .map(|s| String::from_utf8_lossy(s).trim_end().to_string())
                        .ok_or_else(|| {
                            format!("string {} of {count} is missing or not quoted", n + 1)
                        })
                })
                .collect::<std::result::Result<Vec<_>, _>>()?;
            match kind {
                RecordKind::C0nn(width) => RecordData::C0nn {
                    width,
                    values: strings,
                },
                _ => RecordData::Char(strings),
            }
        }
        RecordKind::Mess => RecordData::Mess,
    })
}

/// The binary records (big-endian Fortran, as Eclipse writes them) of formatted text.
pub fn to_binary(path: &Path, text: &[u8]) -> Result<Vec<u8>> {
    let mut t = Text {
        bytes: text,
        pos: 0,
    };
    let mut out = RecordWriter::new(Vec::with_capacity(text.len()), path);
    let mut keyword = String::new();
    let err = |t: &Text, keyword: &str, message: String| Error::Text {
        path: path.to_path_buf(),
        line: 1 + memchr::memchr_iter(b'\n', &text[..t.pos.min(text.len())]).count(),
        keyword: keyword.to_string(),
        message,
    };
    while !t.at_end() {
        let name = t
            .quoted()
            .ok_or_else(|| err(&t, &keyword, "expected a quoted keyword name".into()))?;
        keyword = String::from_utf8_lossy(name).trim_end().to_string();
        let count = t
            .token()
            .and_then(|c| std::str::from_utf8(c).ok()?.parse::<usize>().ok())
            .ok_or_else(|| err(&t, &keyword, "expected a count of values".into()))?;
        let kind = t
            .quoted()
            .and_then(|k| RecordKind::from_code(k.try_into().ok()?))
            .ok_or_else(|| {
                err(
                    &t,
                    &keyword,
                    "expected a type (INTE, REAL, DOUB, LOGI, CHAR, C0nn, MESS)".into(),
                )
            })?;
        let data = values(&mut t, kind, count).map_err(|m| err(&t, &keyword, m))?;
        out.write(&Record::new(keyword.clone(), data))?;
    }
    out.finish()
}

/// Reads a formatted file and returns its binary records.
pub fn read(path: &Path) -> Result<Vec<u8>> {
    let text = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    to_binary(path, &text)
}
