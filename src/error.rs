//! The one error type of the facade: the crates' errors, a scene that cannot be drawn,
//! and what the engine was doing when either happened.

/// Result alias of the facade.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// What went wrong while reading a model, building a scene's surfaces or drawing it.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Reading or extracting the model (file, keyword and line or record named).
    #[error(transparent)]
    Grid(#[from] crate::grid::Error),
    /// Decimating, or reading a hierarchy file.
    #[error(transparent)]
    Lod(#[from] crate::lod::Error),
    /// The GPU: no adapter, a device refused, a frame that failed.
    #[error(transparent)]
    Render(#[from] crate::render::Error),
    /// A scene asks for something the model or the engine cannot give (a layer beyond
    /// the model, a property it does not have, options that do not go together).
    #[error("{0}")]
    Scene(String),
    /// A scene file that is not a scene: the path and serde's line and column.
    #[error("{path}: {message}", path = .path.display())]
    SceneFile {
        /// The scene file.
        path: std::path::PathBuf,
        /// What reading or parsing it said.
        message: String,
    },
    /// The window: no display, an event loop or surface that failed.
    #[error("window: {0}")]
    Window(String),
    /// A file the engine writes or a script names: its path and what went wrong.
    #[error("{path}: {message}", path = .path.display())]
    File {
        /// The file.
        path: std::path::PathBuf,
        /// What went wrong.
        message: String,
    },
    /// A step of the engine failed; `doing` says which, `source` why.
    #[error("{doing}: {source}")]
    While {
        /// The step, in words.
        doing: String,
        /// Why it failed.
        #[source]
        source: Box<Error>,
    },
}

impl Error {
    /// A scene the engine refuses, with the reason.
    pub fn scene(message: impl Into<String>) -> Self {
        Error::Scene(message.into())
    }
}

/// Names the step that failed, as `anyhow::Context` does, for the facade's own error.
pub trait Context<T> {
    /// Wraps the error with `doing`.
    fn context(self, doing: impl Into<String>) -> Result<T>;
    /// Wraps the error with what `doing` returns, made only on failure.
    fn with_context<S: Into<String>>(self, doing: impl FnOnce() -> S) -> Result<T>;
}

impl<T, E: Into<Error>> Context<T> for std::result::Result<T, E> {
    fn context(self, doing: impl Into<String>) -> Result<T> {
        self.map_err(|e| Error::While {
            doing: doing.into(),
            source: Box::new(e.into()),
        })
    }

    fn with_context<S: Into<String>>(self, doing: impl FnOnce() -> S) -> Result<T> {
        self.map_err(|e| Error::While {
            doing: doing().into(),
            source: Box::new(e.into()),
        })
    }
}
