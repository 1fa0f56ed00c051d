//! The one error type of strata-grid. Every message names the file and, where the
//! problem lies in its content, the keyword and the line (text) or record (binary).

use std::path::PathBuf;

/// Result alias used throughout strata-grid.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// What went wrong while reading, writing or building a grid.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The operating system refused a file operation.
    #[error("{path}: {source}", path = .path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A text deck (GRDECL, DATA, INCLUDE file) is malformed.
    #[error("{path}:{line}: keyword {keyword}: {message}", path = .path.display())]
    Text {
        path: PathBuf,
        line: usize,
        keyword: String,
        message: String,
    },
    /// A Fortran unformatted file (EGRID, INIT, UNRST, Xnnnn) is malformed.
    #[error("{path}: record {record} (keyword {keyword}, byte offset {offset}): {message}", path = .path.display())]
    Binary {
        path: PathBuf,
        record: usize,
        keyword: String,
        offset: u64,
        message: String,
    },
    /// The file parsed, but the model it describes is incomplete or inconsistent
    /// (missing ZCORN, wrong array length, NaN coordinates, ...).
    #[error("{path}: keyword {keyword}: {message}", path = .path.display())]
    Model {
        path: PathBuf,
        keyword: String,
        message: String,
    },
    /// The file holds something other than what was asked of it (binary data where a
    /// text deck was expected, a strata hierarchy where a model was): the message says
    /// what it is and what reads it.
    #[error("{path}: {message}", path = .path.display())]
    Content { path: PathBuf, message: String },
    /// A grid built in memory (generator, API caller) is inconsistent.
    #[error("invalid grid: {0}")]
    Invalid(String),
}

impl Error {
    /// Wraps an I/O error with the file it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }

    /// A model-level problem in `path` concerning `keyword`.
    pub fn model(path: impl Into<PathBuf>, keyword: &str, message: impl Into<String>) -> Self {
        Error::Model {
            path: path.into(),
            keyword: keyword.to_string(),
            message: message.into(),
        }
    }
}
