//! The ASCII form (`roff-asc`): tokens separated by blanks, `#...#` comments anywhere
//! between them, strings in double quotes, numbers in decimal text.

use super::parse::{Lexer, Type};
use super::tags::Values;

/// The header of an ASCII ROFF file.
pub const MAGIC: &[u8] = b"roff-asc";

/// Reads the tokens of an ASCII ROFF file held in memory.
pub struct Ascii<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Ascii<'a> {
    /// A lexer after the header; `bytes` must start with [`MAGIC`].
    pub fn new(bytes: &'a [u8]) -> Self {
        Ascii {
            bytes,
            pos: MAGIC.len().min(bytes.len()),
        }
    }

    fn skip(&mut self) {
        loop {
            match self.bytes.get(self.pos) {
                Some(b) if b.is_ascii_whitespace() => self.pos += 1,
                Some(b'#') => match memchr::memchr(b'#', &self.bytes[self.pos + 1..]) {
                    Some(end) => self.pos += end + 2,
                    None => self.pos = self.bytes.len(), // an unclosed comment ends the file
                },
                _ => return,
            }
        }
    }

    /// The next blank-separated token, empty at the end of the file.
    fn token(&mut self) -> &'a [u8] {
        self.skip();
        let start = self.pos;
        while self
            .bytes
            .get(self.pos)
            .is_some_and(|b| !b.is_ascii_whitespace())
        {
            self.pos += 1;
        }
        &self.bytes[start..self.pos]
    }

    fn string(&mut self) -> Result<String, String> {
        self.skip();
        if self.bytes.get(self.pos) != Some(&b'"') {
            let t = self.token();
            return Err(format!(
                "expected a quoted string, found '{}'",
                String::from_utf8_lossy(t)
            ));
        }
        let rest = &self.bytes[self.pos + 1..];
        let end = memchr::memchr(b'"', rest).ok_or("a string is not closed")?;
        self.pos += end + 2;
        Ok(String::from_utf8_lossy(&rest[..end]).into_owned())
    }

    fn integer(&mut self) -> Result<i64, String> {
        let t = self.token();
        std::str::from_utf8(t)
            .ok()
            .and_then(|s| s.parse::<i64>().ok())
            .ok_or_else(|| {
                format!(
                    "expected an integer, found '{}'",
                    String::from_utf8_lossy(t)
                )
            })
    }

    fn float<T: fast_float2::FastFloat>(&mut self) -> Result<T, String> {
        let t = self.token();
        fast_float2::parse::<T, _>(t)
            .map_err(|_| format!("expected a number, found '{}'", String::from_utf8_lossy(t)))
    }

    fn collect<T>(
        &mut self,
        count: usize,
        mut one: impl FnMut(&mut Self) -> Result<T, String>,
    ) -> Result<Vec<T>, String> {
        // Every value takes at least two bytes (a digit and a blank): no more room than that.
        let room = (self.bytes.len() - self.pos) / 2 + 1;
        if count > room {
            return Err(format!(
                "{count} values cannot fit in the {} bytes left",
                self.bytes.len() - self.pos
            ));
        }
        let mut out = Vec::with_capacity(count);
        for _ in 0..count {
            out.push(one(self)?);
        }
        Ok(out)
    }
}

fn small<T: TryFrom<i64>>(v: i64, ty: &str) -> Result<T, String> {
    T::try_from(v).map_err(|_| format!("{v} is out of range for {ty}"))
}

impl Lexer for Ascii<'_> {
    fn pos(&mut self) -> usize {
        self.skip();
        self.pos
    }

    fn at_end(&mut self) -> bool {
        self.skip();
        self.pos >= self.bytes.len()
    }

    fn word(&mut self) -> Result<String, String> {
        let t = self.token();
        if t.is_empty() {
            return Err("the file ends inside a tag".into());
        }
        Ok(String::from_utf8_lossy(t).into_owned())
    }

    fn count(&mut self) -> Result<usize, String> {
        let n = self.integer()?;
        usize::try_from(n).map_err(|_| format!("array count {n} is negative"))
    }

    fn values(&mut self, ty: Type, count: usize) -> Result<Values, String> {
        Ok(match ty {
            Type::Char => Values::Char(self.collect(count, Self::string)?),
            Type::Bool => Values::Bool(self.collect(count, |s| small(s.integer()?, "bool"))?),
            Type::Byte => Values::Byte(self.collect(count, |s| small(s.integer()?, "byte"))?),
            Type::Int => Values::Int(self.collect(count, |s| small(s.integer()?, "int"))?),
            Type::Float => Values::Float(self.collect(count, Self::float::<f32>)?),
            Type::Double => Values::Double(self.collect(count, Self::float::<f64>)?),
        })
    }

    fn byteswaptest(&mut self) -> Result<i32, String> {
        small(self.integer()?, "int")
    }
}
