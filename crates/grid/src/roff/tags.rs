//! What a ROFF file holds once parsed, whichever its form: tags of named keys, each a
//! single value or an array. Both parsers produce this; the model is read from it.

use std::path::Path;

use crate::Error;

/// Binary (`roff-bin`) or ASCII (`roff-asc`): decides how positions are named in errors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// `roff-bin`: positions are byte offsets.
    Binary,
    /// `roff-asc`: positions are lines.
    Ascii,
}

/// The values of one key, in the type the file gives them.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    /// `char`: strings.
    Char(Vec<String>),
    /// `bool`: one byte each, 0 or 1.
    Bool(Vec<u8>),
    /// `byte`: unsigned bytes (discrete codes, split counts).
    Byte(Vec<u8>),
    /// `int`: 32-bit integers.
    Int(Vec<i32>),
    /// `float`: 32-bit floats.
    Float(Vec<f32>),
    /// `double`: 64-bit floats.
    Double(Vec<f64>),
}

impl Values {
    /// Number of values.
    pub fn len(&self) -> usize {
        match self {
            Values::Char(v) => v.len(),
            Values::Bool(v) | Values::Byte(v) => v.len(),
            Values::Int(v) => v.len(),
            Values::Float(v) => v.len(),
            Values::Double(v) => v.len(),
        }
    }

    /// Whether there are no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The ROFF type name, for messages.
    pub fn type_name(&self) -> &'static str {
        match self {
            Values::Char(_) => "char",
            Values::Bool(_) => "bool",
            Values::Byte(_) => "byte",
            Values::Int(_) => "int",
            Values::Float(_) => "float",
            Values::Double(_) => "double",
        }
    }
}

/// One key of a tag: `int nX 4` or `array float data 90 ...`.
#[derive(Clone, Debug, PartialEq)]
pub struct Key {
    /// The key's name.
    pub name: String,
    /// Its value (one for a simple key) or values (an array).
    pub values: Values,
    /// Byte offset of the key in the file.
    pub at: usize,
}

/// One `tag NAME ... endtag` group.
#[derive(Clone, Debug, PartialEq)]
pub struct Tag {
    /// The tag's name (`dimensions`, `cornerLines`, `parameter`, ...).
    pub name: String,
    /// Its keys in file order; a name may repeat.
    pub keys: Vec<Key>,
    /// Byte offset of the tag in the file.
    pub at: usize,
}

impl Tag {
    /// The first key called `name`.
    pub fn key(&self, name: &str) -> Option<&Key> {
        self.keys.iter().find(|k| k.name == name)
    }
}

/// A parsed ROFF file.
#[derive(Clone, Debug)]
pub struct Roff {
    /// Binary or ASCII.
    pub form: Form,
    /// The tags in file order.
    pub tags: Vec<Tag>,
}

/// Where a problem lies, for an error naming file, tag/key and byte offset or line.
pub struct Place<'a> {
    /// The file.
    pub path: &'a Path,
    /// The whole file, to turn an offset into a line for ASCII files.
    pub bytes: &'a [u8],
    /// Binary or ASCII.
    pub form: Form,
}

impl Place<'_> {
    /// An error at byte `at`, in tag number `tag` (1-based, 0 before the first),
    /// concerning `keyword` (`tag` or `tag/key`).
    pub fn error(&self, tag: usize, keyword: &str, at: usize, message: impl Into<String>) -> Error {
        match self.form {
            Form::Binary => Error::Binary {
                path: self.path.to_path_buf(),
                record: tag,
                keyword: keyword.to_string(),
                offset: at as u64,
                message: message.into(),
            },
            Form::Ascii => Error::Text {
                path: self.path.to_path_buf(),
                line: line_of(self.bytes, at),
                keyword: keyword.to_string(),
                message: message.into(),
            },
        }
    }
}

/// The 1-based line of byte `at`.
pub fn line_of(bytes: &[u8], at: usize) -> usize {
    1 + memchr::memchr_iter(b'\n', &bytes[..at.min(bytes.len())]).count()
}
