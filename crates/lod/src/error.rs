//! The one error type of strata-lod.

use std::path::PathBuf;

/// What can go wrong while decimating, building, saving or reading a hierarchy.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The input mesh breaks an invariant of [`strata_grid::SurfaceMesh`] or is not
    /// something this crate can simplify (named in the message).
    #[error("invalid mesh: {0}")]
    Mesh(String),
    /// An option is out of its range.
    #[error("invalid option: {0}")]
    Option(String),
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// A hierarchy file is not one this version wrote, or is damaged; `at` is the byte
    /// offset of the field that failed.
    #[error("{path}: not a valid strata LOD file at byte {at}: {message}")]
    Format {
        /// The file.
        path: PathBuf,
        /// Byte offset of the field that failed.
        at: u64,
        /// What is wrong there.
        message: String,
    },
    /// Extracting a layer surface from the model failed.
    #[error(transparent)]
    Grid(#[from] strata_grid::Error),
}

impl Error {
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}

/// `Result` with [`Error`].
pub type Result<T> = std::result::Result<T, Error>;
