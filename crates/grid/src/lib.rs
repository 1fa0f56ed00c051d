//! strata-grid: the reservoir model. Corner-point grids, their readers and writers
//! (GRDECL text decks, Eclipse EGRID/INIT/UNRST binaries), a synthetic generator, and
//! the extraction of layer and side surfaces as attributed triangle meshes.
//!
//! This crate knows nothing about rendering; everything downstream consumes
//! [`SurfaceMesh`].

pub mod eclbin;
mod error;
pub mod grdecl;
mod grid;
mod mesh;
pub mod surface;
pub mod synth;
pub mod terrain;

use std::path::Path;

pub use error::{Error, Result};
pub use grid::{BoundingBox, CornerPointGrid, Dims, MapAxes, ReportStep, Units};
pub use mesh::{CellFace, SurfaceMesh};
/// The array crate of the public API (grid arrays are `ndarray::Array3`).
pub use ndarray;
pub use surface::{Face, layer_surface, layer_surfaces, side_surfaces};
pub use terrain::{Terrain, TerrainInput, TerrainSynth};

/// What to read besides the grid geometry.
#[derive(Clone, Debug)]
pub struct ReadOptions {
    /// Read geometry and ACTNUM only: skip properties and results, and let a text deck
    /// go on past INCLUDE files that are missing (each one is listed in
    /// [`CornerPointGrid::warnings`]); without it a missing INCLUDE is an error.
    pub grid_only: bool,
    /// For an EGRID, also read the INIT beside it and the restart files (UNRST, or the
    /// non-unified `.Xnnnn`) when they exist.
    pub load_results: bool,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            grid_only: false,
            load_results: true,
        }
    }
}

/// The file formats strata reads and writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Text decks: `.grdecl`, `.inc`, `.DATA` and anything that is not binary.
    Grdecl,
    /// Eclipse binary grid: `.EGRID`.
    Egrid,
}

impl Format {
    /// The format a path's extension names (text is the fallback).
    pub fn from_path(path: &Path) -> Format {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("egrid") => Format::Egrid,
            _ => Format::Grdecl,
        }
    }
}

/// Opens a model with the default options: geometry, properties and, for EGRID, the
/// INIT and restart files beside it.
pub fn open(path: &Path) -> Result<CornerPointGrid> {
    open_with(path, &ReadOptions::default())
}

/// Opens a model, choosing the reader from the file extension.
pub fn open_with(path: &Path, options: &ReadOptions) -> Result<CornerPointGrid> {
    match Format::from_path(path) {
        Format::Egrid => eclbin::read_egrid(path, options),
        Format::Grdecl => grdecl::read(path, options),
    }
}

/// Writes a model in the format its extension names.
pub fn save(grid: &CornerPointGrid, path: &Path) -> Result<()> {
    match Format::from_path(path) {
        Format::Egrid => eclbin::write_egrid(grid, path),
        Format::Grdecl => grdecl::write(grid, path),
    }
}
