//! strata: reservoir simulation grids, from file to anti-aliased wireframe.
//!
//! The facade of the workspace and its scene engine. A [`Scene`] says everything a
//! picture depends on (model, layers, colours, lines, level of detail, camera, size);
//! a [`SceneRenderer`] reads the model, builds the surfaces once and draws a frame
//! for each new camera or style, rebuilding only what a change of scene invalidates.
//! Every front end (the `strata` command line, and the viewer and Python package to
//! come) only turns its input into a `Scene` and shows the frames.
//!
//! ```
//! use strata::{Scene, SceneRenderer};
//! use strata::scene::IsolineSpec;
//!
//! let mut scene = Scene::of_model(strata::sample_model());
//! scene.layers = Some([1, 3]);
//! scene.isolines = Some(IsolineSpec::of(Some("PORO")));
//! let mut engine = SceneRenderer::new(scene.clone())?;
//! let frame = engine.render()?;
//! assert_eq!(frame.image.dimensions(), (1200, 900));
//! // Saved as JSON, the scene reads back as it was.
//! assert_eq!(Scene::from_json(&scene.to_json())?, scene);
//! # Ok::<(), strata::Error>(())
//! ```
//!
//! The crates underneath are re-exported: [`grid`] (the model, readers, layer
//! surfaces), [`lod`] (decimation and hierarchies) and [`render`] (wgpu).

pub use strata_grid as grid;
pub use strata_lod as lod;
pub use strata_render as render;

#[cfg(feature = "bench")]
pub mod bench;
pub mod cell;
pub mod engine;
mod error;
pub mod memory;
pub mod metrics;
pub mod progress;
pub mod scene;
pub mod surfaces;

pub use engine::{Counters, Frame, FrameReport, Note, SceneRenderer};
pub use error::{Context, Error, Result};
pub use scene::Scene;

/// The README's Rust examples, run as doctests so that they stay true.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// The sample model shipped in the repository's `data/` (a faulted synthetic
/// reservoir): what the command line draws when given no model.
pub fn sample_model() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/sample.grdecl")
}
