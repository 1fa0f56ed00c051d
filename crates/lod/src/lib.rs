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
//!
//! ```
//! use strata_grid::synth::{SynthParams, generate};
//! use strata_grid::{Face, Surfaces, layer_surfaces};
//! use strata_lod::{Options, decimate};
//!
//! let grid = generate(&SynthParams { nx: 60, ny: 40, nz: 1, faults: 2, seed: 3 })?;
//! let layer = Surfaces::layer(0, grid.display_origin()).property(Some("PORO"));
//! let top = layer_surfaces(&grid, Face::Top, &layer)?;
//! let simplified = decimate(&top, &Options::fraction(&top, 0.1))?;
//! // A tenth of the triangles, each vertex still carrying the original surface's
//! // global texture coordinates and porosity where it lies.
//! assert!(simplified.mesh.triangle_count() <= top.triangle_count() / 10 + 2);
//! assert_eq!(simplified.mesh.texcoords.len(), simplified.mesh.vertex_count());
//! assert_eq!(simplified.mesh.scalars.len(), simplified.mesh.vertex_count());
//! // The outline's corners stay: the texture coordinates still span the whole grid.
//! let span = |mesh: &strata_grid::SurfaceMesh| {
//!     mesh.texcoords.iter().fold([f32::MAX, f32::MIN], |[lo, hi], t| [lo.min(t[0]), hi.max(t[0])])
//! };
//! assert_eq!(span(&simplified.mesh), span(&top));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

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
    partial_path,
};
pub use hierarchy::{BuildOptions, LayerTree, Node, Progress, ProgressFn, build_layer};
pub use index::MaybeIndex;
pub use reference::{Reference, SurfacePoint, closest_on_triangle};
pub use share::{MIN_VISIBLE, SurfaceShare, share_budget, share_surfaces};
pub use stitch::{Stitched, stitch};
