//! The one error type of strata-render.

/// Result alias used throughout strata-render.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// What went wrong while setting up the GPU, preparing a scene or rendering.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// No adapter matched: none on this machine, or none for the requested backend/name.
    #[error(
        "no GPU adapter found ({0}); on a machine without a GPU install Mesa's llvmpipe (OpenGL) or lavapipe (mesa-vulkan-drivers)"
    )]
    NoAdapter(String),
    /// Adapters were found, but none can run strata's shaders; says why for each.
    #[error("no adapter found that strata can draw with: {0}")]
    Unsuitable(String),
    /// The adapter refused to create a device with what strata needs.
    #[error("the adapter {adapter} refused a device: {message}")]
    Device {
        /// The adapter's name.
        adapter: String,
        /// What wgpu said.
        message: String,
    },
    /// The GPU reported an error while executing our commands.
    #[error("GPU error: {0}")]
    Gpu(String),
    /// The request cannot be drawn (empty mesh, zero-sized image, missing attribute ...).
    #[error("{0}")]
    Invalid(String),
    /// Writing the image failed.
    #[error("{path}: {message}", path = .path.display())]
    Output {
        /// The file that was being written.
        path: std::path::PathBuf,
        /// Why it failed.
        message: String,
    },
}
