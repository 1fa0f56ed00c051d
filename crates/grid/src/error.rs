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
        /// The file that could not be opened, read, mapped or written.
        path: PathBuf,
        /// The operating system's reason.
        #[source]
        source: std::io::Error,
    },
    /// A text deck (GRDECL, DATA, INCLUDE file) is malformed.
    #[error("{path}:{line}: keyword {keyword}: {message}", path = .path.display())]
    Text {
        /// The deck or INCLUDE file that holds the line.
        path: PathBuf,
        /// 1-based line of that file.
        line: usize,
        /// The keyword being read, as the file spells it, so the user can find it.
        keyword: String,
        /// What is wrong there.
        message: String,
    },
    /// A Fortran unformatted file (EGRID, INIT, UNRST, Xnnnn) is malformed.
    #[error("{path}: record {record} (keyword {keyword}, byte offset {offset}): {message}", path = .path.display())]
    Binary {
        /// The binary file.
        path: PathBuf,
        /// 1-based number of the keyword (its header and data records) in the file.
        record: usize,
        /// That keyword's name, trailing blanks removed (empty when its header is unreadable).
        keyword: String,
        /// Byte offset of the Fortran record where the problem was found, for a hex dump.
        offset: u64,
        /// What is wrong there.
        message: String,
    },
    /// The file parsed, but the model it describes is incomplete or inconsistent
    /// (missing ZCORN, wrong array length, NaN coordinates, ...).
    #[error("{path}: keyword {keyword}: {message}", path = .path.display())]
    Model {
        /// The file that describes the model (or the one being written).
        path: PathBuf,
        /// The keyword that is missing or inconsistent (empty when none applies).
        keyword: String,
        /// What is missing or inconsistent.
        message: String,
    },
    /// The file holds something other than what was asked of it (binary data where a
    /// text deck was expected, a strata hierarchy where a model was): the message says
    /// what it is and what reads it.
    #[error("{path}: {message}", path = .path.display())]
    Content {
        /// The file whose content is not what was asked for.
        path: PathBuf,
        /// What the file is and what reads it.
        message: String,
    },
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
