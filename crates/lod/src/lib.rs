//! strata-lod: level of detail for strata surfaces (DESIGN.md section 4).
//!
//! * [`decimate()`]: edge-collapse simplification of a [`strata_grid::SurfaceMesh`] that
//!   keeps every vertex on the original surface (or lifted off it along the normal by
//!   at most the error) with the original surface's texture coordinates and scalar
//!   there, so the original grid wireframe (global coordinates) is still drawn where
//!   it was on the simplified surface (Celes & Abraham 2011, section 5, Fig. 12).
//! * [`decimate_chosen`]: ours, or meshoptimizer's `simplify`, fitted, where a budget
//!   too small to keep the outlines makes it draw the grid lines nearer.
//! * [`fit`]: moves a simplified surface's vertices, texture coordinates fixed, to
//!   where it draws the original grid lines nearest to where the original does
//!   (what [`decimate_chosen`] does to meshoptimizer's result).
//! * [`CellCover`]: the cells each piece of a surface covers, for decimation that lets
//!   outlines grow only outward and a renderer that masks fragments by their cell.
//! * [`baseline`]: meshoptimizer's simplifiers on the same meshes, to compare with,
//!   and its vertex-cache and vertex-fetch ordering for GPU buffers.
//! * [`build_layer`], [`build_file`], [`LodFile`]: a quadtree of tiles per layer with
//!   crack-free borders and per-node geometric error, saved to a file that is memory
//!   mapped back, and the per-frame choice of nodes by projected error.
//! * [`share_budget`]: one budget for a model's surfaces, split by how much of each
//!   is seen.
//! * [`measure`]: how far the simplified surface draws each texture coordinate from
//!   where the original draws it.

#![warn(missing_docs)]

pub mod baseline;
mod choose;
mod cover;
mod decimate;
mod error;
mod file;
pub mod fit;
mod hierarchy;
mod index;
pub mod measure;
mod quadric;
mod reference;
mod share;
mod stitch;

pub use choose::{Chosen, Maker, decimate_chosen};
pub use cover::{CellCover, CoverPiece, cell_of};
pub use decimate::{Decimated, Options, Placement, Timings, decimate, decimate_on};
pub use error::{Error, Result};
pub use file::{
    BuildReport, Indices, LayerRecord, LodFile, NodeRecord, Vertex, ViewPoint, build_file,
};
pub use hierarchy::{BuildOptions, LayerTree, Node, Progress, ProgressFn, build_layer};
pub use index::MaybeIndex;
pub use reference::{Reference, SurfacePoint, closest_on_triangle};
pub use share::{MIN_VISIBLE, SurfaceShare, share_budget, share_surfaces};
pub use stitch::{Stitched, stitch};
