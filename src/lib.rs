//! strata: reservoir simulation grids, from file to anti-aliased wireframe.
//!
//! This facade re-exports the three crates of the workspace; the `strata` binary is
//! the command-line tool built on them.

pub use strata_grid as grid;
pub use strata_lod as lod;
pub use strata_render as render;

pub mod bench;
pub mod scene;
