//! `strata view`: the interactive window on the scene engine.
//!
//! # How it works
//! A winit window holds a wgpu surface, and egui draws a side panel and the picture
//! beside it. Each frame runs the panel, the mouse and the keys (or the next lines of
//! a script), which all edit one [`Scene`]; the [`SceneRenderer`] takes the edited
//! scene (rebuilding only what the change invalidates, see [`crate::engine`]) and
//! draws it into its frame texture, which egui shows as an image. Nothing is read
//! back for the window; a screenshot draws the same scene once more with a readback.
//! A scene the engine refuses (a missing file, a property the model lacks) is shown
//! as an error in the panel and the last good scene stays.
//!
//! # Why the frame is an egui image
//! The engine draws into an RGBA texture of its own for files and tests; showing that
//! texture costs one textured quad, keeps the window's picture the same bytes as a
//! rendered PNG (measured so by the window tests), and lets egui lay the panel out
//! beside it on any surface format.

mod app;
mod background;
mod controls;
mod panel;
mod script;
mod stats;
mod window;

use std::path::PathBuf;

pub use controls::KEYS;
pub use script::{Command, set_field};
pub use stats::{FrameStat, Summary};

use crate::{Error, Result, Scene};

/// What a window opens with.
#[derive(Clone, Debug)]
pub struct Options {
    /// The scene shown first.
    pub scene: Scene,
    /// Lines to run instead of waiting for the user ([`script`](self) module docs).
    pub script: Option<PathBuf>,
    /// Write per-frame statistics here.
    pub stats_file: Option<PathBuf>,
    /// Inner size of the window in pixels.
    pub size: [u32; 2],
}

/// Opens the window and runs it until it is closed (or its script ends); returns
/// the frame statistics.
pub fn run(options: Options) -> Result<Summary> {
    let commands = match &options.script {
        Some(path) => Some(script::read(path)?),
        None => None,
    };
    let event_loop = winit::event_loop::EventLoop::new()
        .map_err(|e| Error::Window(format!("no event loop (is there a display?): {e}")))?;
    let mut app = app::App::new(options, commands);
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::Window(e.to_string()))?;
    app.finish()
}
