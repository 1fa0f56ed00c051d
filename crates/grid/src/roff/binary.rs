//! The binary form (`roff-bin`): words and strings end with a zero byte, numbers are
//! raw, in the byte order `filedata/byteswaptest` (the value 1) shows; little-endian
//! until then. Comments (`#...#`, then a zero) may stand before words, as roffio allows.

use super::parse::{Lexer, Type};
use super::tags::Values;

/// The header of a binary ROFF file, its zero included.
pub const MAGIC: &[u8] = b"roff-bin\0";

/// Reads the tokens of a binary ROFF file held in memory.
pub struct Binary<'a> {
    bytes: &'a [u8],
    pos: usize,
    big: bool,
}

impl<'a> Binary<'a> {
    /// A lexer after the header; `bytes` must start with [`MAGIC`].
    pub fn new(bytes: &'a [u8]) -> Self {
        Binary {
            bytes,
            pos: MAGIC.len().min(bytes.len()),
            big: false,
        }
    }

    fn skip_comments(&mut self) {
        while self.bytes.get(self.pos) == Some(&b'#') {
            let rest = &self.bytes[self.pos + 1..];
            match memchr::memchr(b'#', rest) {
                Some(end) if rest.get(end + 1) == Some(&0) => self.pos += end + 3,
                _ => return, // not a comment: the word reader reports it
            }
        }
    }

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        let rest = self.bytes.len() - self.pos;
        if n > rest {
            return Err(format!("{what} needs {n} bytes, the file has {rest} left"));
        }
        let out = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(out)
    }

    fn cstring(&mut self) -> Result<String, String> {
        let rest = &self.bytes[self.pos..];
        let end = memchr::memchr(0, rest)
            .ok_or_else(|| "a string runs to the end of the file (no zero byte)".to_string())?;
        self.pos += end + 1;
        Ok(String::from_utf8_lossy(&rest[..end]).into_owned())
    }

    fn int(&self, b: &[u8]) -> i32 {
        let a = [b[0], b[1], b[2], b[3]];
        if self.big {
            i32::from_be_bytes(a)
        } else {
            i32::from_le_bytes(a)
        }
    }
}

impl Lexer for Binary<'_> {
    fn pos(&mut self) -> usize {
        self.skip_comments();
        self.pos
    }

    fn at_end(&mut self) -> bool {
        self.skip_comments();
        self.pos >= self.bytes.len()
    }

    fn word(&mut self) -> Result<String, String> {
        self.skip_comments();
        if self.pos >= self.bytes.len() {
            return Err("the file ends inside a tag".into());
        }
        self.cstring()
    }

    fn count(&mut self) -> Result<usize, String> {
        let b = self.take(4, "an array count")?;
        let n = self.int(b);
        usize::try_from(n).map_err(|_| format!("array count {n} is negative"))
    }

    fn values(&mut self, ty: Type, count: usize) -> Result<Values, String> {
        let what = format!("{count} {ty:?} values");
        if ty == Type::Char {
            if count > self.bytes.len() - self.pos {
                return Err(format!(
                    "{what} cannot fit in the {} bytes left",
                    self.bytes.len() - self.pos
                ));
            }
            return (0..count)
                .map(|_| self.cstring())
                .collect::<Result<_, _>>()
                .map(Values::Char);
        }
        let n = count
            .checked_mul(ty.size())
            .ok_or_else(|| format!("{what} overflow"))?;
        let b = self.take(n, &what)?;
        let big = self.big;
        macro_rules! decode {
            ($t:ty, $w:literal) => {
                b.chunks_exact($w)
                    .map(|c| {
                        let a: [u8; $w] = c.try_into().unwrap_or([0; $w]);
                        if big {
                            <$t>::from_be_bytes(a)
                        } else {
                            <$t>::from_le_bytes(a)
                        }
                    })
                    .collect()
            };
        }
        Ok(match ty {
            Type::Bool => Values::Bool(b.to_vec()),
            Type::Byte => Values::Byte(b.to_vec()),
            Type::Int => Values::Int(decode!(i32, 4)),
            Type::Float => Values::Float(decode!(f32, 4)),
            Type::Double => Values::Double(decode!(f64, 8)),
            Type::Char => unreachable!("handled above"),
        })
    }

    fn byteswaptest(&mut self) -> Result<i32, String> {
        let b = self.take(4, "byteswaptest")?;
        let a = [b[0], b[1], b[2], b[3]];
        if i32::from_le_bytes(a) == 1 {
            self.big = false;
        } else if i32::from_be_bytes(a) == 1 {
            self.big = true;
        } else {
            return Err(format!("byteswaptest is {a:?}, not 1 in either byte order"));
        }
        Ok(1)
    }
}
