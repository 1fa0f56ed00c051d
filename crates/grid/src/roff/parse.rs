//! The grammar both ROFF forms share, over a [`Lexer`] that knows how one form spells
//! words, strings and numbers: `tag NAME` keys `endtag`, a key being `TYPE NAME VALUE`
//! or `array TYPE NAME COUNT VALUES`, as xtgeo's `roffio` reads them.

use std::path::Path;

use super::tags::{Form, Key, Place, Roff, Tag, Values};
use crate::Result;

/// The simple types a key or array can have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Type {
    /// `char`
    Char,
    /// `bool`
    Bool,
    /// `byte`
    Byte,
    /// `int`
    Int,
    /// `float`
    Float,
    /// `double`
    Double,
}

impl Type {
    fn parse(word: &str) -> Option<Type> {
        Some(match word {
            "char" => Type::Char,
            "bool" => Type::Bool,
            "byte" => Type::Byte,
            "int" => Type::Int,
            "float" => Type::Float,
            "double" => Type::Double,
            _ => return None,
        })
    }

    /// Bytes per value in a binary file (a `char` at least its terminating zero).
    pub fn size(self) -> usize {
        match self {
            Type::Char | Type::Bool | Type::Byte => 1,
            Type::Int | Type::Float => 4,
            Type::Double => 8,
        }
    }
}

/// How one form of ROFF spells its tokens. Messages are plain strings; the grammar
/// adds file, tag, key and position.
pub trait Lexer {
    /// Byte offset of the next token (after comments and blanks).
    fn pos(&mut self) -> usize;
    /// Whether only comments and blanks remain.
    fn at_end(&mut self) -> bool;
    /// A keyword or a name.
    fn word(&mut self) -> Result<String, String>;
    /// The count of an array.
    fn count(&mut self) -> Result<usize, String>;
    /// `count` values of type `ty` (one for a simple key).
    fn values(&mut self, ty: Type, count: usize) -> Result<Values, String>;
    /// The value of `filedata/byteswaptest`, which sets a binary file's byte order.
    fn byteswaptest(&mut self) -> Result<i32, String>;
}

/// Parses a whole file after its header.
pub fn parse(path: &Path, bytes: &[u8], form: Form, lexer: &mut impl Lexer) -> Result<Roff> {
    let place = Place { path, bytes, form };
    let mut tags = Vec::new();
    while !lexer.at_end() {
        let no = tags.len() + 1;
        let at = lexer.pos();
        let word = lexer.word().map_err(|m| place.error(no, "", at, m))?;
        if word != "tag" {
            return Err(place.error(no, &word, at, format!("expected 'tag', found '{word}'")));
        }
        let name = lexer.word().map_err(|m| place.error(no, "tag", at, m))?;
        let keys = tag_keys(&place, no, &name, lexer)?;
        tags.push(Tag { name, keys, at });
    }
    Ok(Roff { form, tags })
}

/// The keys of tag number `no` called `tag`, up to its `endtag`.
fn tag_keys(place: &Place, no: usize, tag: &str, lexer: &mut impl Lexer) -> Result<Vec<Key>> {
    let mut keys = Vec::new();
    loop {
        let at = lexer.pos();
        let err = |key: &str, m: String| {
            let keyword = if key.is_empty() {
                tag.to_string()
            } else {
                format!("{tag}/{key}")
            };
            place.error(no, &keyword, at, m)
        };
        let word = lexer.word().map_err(|m| err("", m))?;
        if word == "endtag" {
            return Ok(keys);
        }
        if word == "tag" {
            return Err(err(
                "",
                format!("tag {tag} is not closed: 'tag' where a key or 'endtag' should be"),
            ));
        }
        let array = word == "array";
        let ty_word = if array {
            lexer.word().map_err(|m| err("", m))?
        } else {
            word
        };
        let ty = Type::parse(&ty_word).ok_or_else(|| {
            err(
                "",
                format!("expected a type, 'array' or 'endtag', found '{ty_word}'"),
            )
        })?;
        let name = lexer.word().map_err(|m| err("", m))?;
        let values = if array {
            let count = lexer.count().map_err(|m| err(&name, m))?;
            lexer.values(ty, count).map_err(|m| err(&name, m))?
        } else if tag == "filedata" && name == "byteswaptest" && ty == Type::Int {
            Values::Int(vec![lexer.byteswaptest().map_err(|m| err(&name, m))?])
        } else {
            lexer.values(ty, 1).map_err(|m| err(&name, m))?
        };
        keys.push(Key { name, values, at });
    }
}
