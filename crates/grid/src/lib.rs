//! strata-grid: the reservoir model. Corner-point grids, their readers and writers
//! (GRDECL text decks, Eclipse EGRID/INIT/UNRST binaries), a synthetic generator, and
//! the extraction of layer and side surfaces as attributed triangle meshes.
//!
//! This crate knows nothing about rendering; everything downstream consumes
//! [`SurfaceMesh`].
//!
//! * [`CornerPointGrid`]: pillars (COORD), corner depths (ZCORN), activity (ACTNUM),
//!   properties and report steps, checked when built ([`CornerPointGrid::from_arrays`]).
//! * [`open`] / [`open_with`] read a model, the reader chosen by the file's content
//!   ([`grdecl`] for text decks, [`eclbin`] for EGRID with its INIT and restarts);
//!   [`save`] writes one in the format its extension names.
//! * [`synth::generate`] makes a faulted, folded model of any size, deterministic by
//!   seed, for tests, examples and benchmarks.
//! * [`layer_surfaces`] and [`side_surfaces`], asked with [`Surfaces`], turn cells into a
//!   [`SurfaceMesh`] whose global texture coordinates put every grid line on an odd
//!   value, so the original wireframe survives decimation; [`terrain`] triangulates
//!   scattered picks instead.
//! * [`Error`]: every failure, naming the file, keyword and line or record.
//!
//! ```
//! use strata_grid::synth::{SynthParams, generate};
//! use strata_grid::{Face, Surfaces, layer_surfaces, open, save};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let grid = generate(&SynthParams { nx: 20, ny: 12, nz: 3, faults: 2, seed: 7 })?;
//!
//! // The top of the first layer, coloured by porosity, near the display origin.
//! let layer = Surfaces::layer(0, grid.display_origin()).property(Some("PORO"));
//! let top = layer_surfaces(&grid, Face::Top, &layer)?;
//! top.validate().expect("a consistent mesh");
//! // One quad (two triangles) per active cell of the layer: inactive cells are holes.
//! assert_eq!(top.cell_faces.len(), grid.active_count_in(0, 0..12));
//! assert!(top.cell_faces.len() < 20 * 12);
//! assert_eq!(top.triangle_count(), 2 * top.cell_faces.len());
//! // Every vertex is a grid node, so both its texture coordinates are odd integers.
//! assert!(top.texcoords.iter().flatten().all(|&t| t.fract() == 0.0 && t % 2.0 == 1.0));
//! // Faults split the surface: some nodes are more than one vertex.
//! let mut nodes: Vec<[u32; 2]> = top.texcoords.iter().map(|t| t.map(|v| v as u32)).collect();
//! nodes.sort();
//! nodes.dedup();
//! assert!(nodes.len() < top.vertex_count());
//!
//! // Written as an EGRID and read back, the model keeps its shape and holes.
//! let dir = tempfile::tempdir()?;
//! let path = dir.path().join("SYNTH.EGRID");
//! save(&grid, &path)?;
//! let back = open(&path)?;
//! assert_eq!(back.dims(), grid.dims());
//! assert_eq!(back.active_count(), grid.active_count());
//! # Ok(())
//! # }
//! ```

pub mod eclbin;
mod error;
pub mod faults;
pub mod grdecl;
mod grid;
mod mesh;
pub mod outline;
mod pages;
pub mod roff;
pub mod surface;
pub mod synth;
pub mod terrain;

use std::path::Path;

pub use error::{Error, Result};
pub use grid::{
    BoundingBox, CornerPointGrid, Dims, MapAxes, ReportStep, STRAY_QUARTILE_SAMPLES, STRAY_SPREADS,
    StrayCorner, StrayCorners, Units,
};
pub use mesh::{CellFace, SurfaceMesh};
/// The array crate of the public API (grid arrays are `ndarray::Array3`).
pub use ndarray;
pub use surface::{
    Columns, Face, Surfaces, drawn_cell, has_faces, layer_surfaces, open_sides, side_face_corners,
    side_surfaces, surface_face_corners, visit_row_faces,
};
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
    /// ROFF binary grid: `.roff`, `.roffbin` (`.roffasc` is read, never written).
    Roff,
}

impl Format {
    /// The format a path's extension names (text is the fallback).
    pub fn from_path(path: &Path) -> Format {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("egrid") => Format::Egrid,
            Some(e) if e.to_ascii_lowercase().starts_with("roff") => Format::Roff,
            _ => Format::Grdecl,
        }
    }
}

/// The first bytes of a strata level-of-detail hierarchy (`strata lod build`), so that
/// a hierarchy handed to a model reader is named as one.
pub const HIERARCHY_MAGIC: [u8; 8] = *b"STRATLOD";

/// Bytes looked at to tell a file's content; a text deck has no zero byte in them.
const SNIFF_BYTES: usize = 4096;

/// What a file's first bytes say it holds, whatever its name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Content {
    /// A Fortran unformatted record of an Eclipse keyword (EGRID, INIT, UNRST, ...).
    EclipseBinary,
    /// A formatted (text) Eclipse file: FEGRID, FINIT, FUNRST, Fnnnn, formatted GRID.
    EclipseText,
    /// A strata level-of-detail hierarchy.
    Hierarchy,
    /// A ROFF file (RMS, xtgeo), binary or ASCII.
    Roff(roff::Form),
    /// Other binary data.
    Binary {
        /// Offset of the first zero byte, which no text deck has: shown in messages
        /// so the user can check the file.
        zero_at: usize,
    },
    /// Text, or empty.
    Text,
}

impl Content {
    /// Tells the content from the first bytes of a file (up to 4 KiB are looked at).
    pub fn of(bytes: &[u8]) -> Content {
        if bytes.starts_with(&HIERARCHY_MAGIC) {
            Content::Hierarchy
        } else if let Some(form) = roff::form_of(bytes) {
            Content::Roff(form)
        } else if bytes.len() >= 24
            && bytes[..4] == 16u32.to_be_bytes()
            && bytes[4..12]
                .iter()
                .all(|b| b.is_ascii_graphic() || *b == b' ')
            && bytes[16..20]
                .try_into()
                .is_ok_and(|code| eclbin::RecordKind::from_code(code).is_some())
        {
            Content::EclipseBinary
        } else if let Some(zero_at) = bytes.iter().take(SNIFF_BYTES).position(|&b| b == 0) {
            Content::Binary { zero_at }
        } else if eclbin::looks_formatted(bytes) {
            Content::EclipseText
        } else {
            Content::Text
        }
    }

    /// Reads the first bytes of `path` and tells its content.
    pub fn of_file(path: &Path) -> Result<Content> {
        use std::io::Read;
        let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
        let mut head = Vec::with_capacity(SNIFF_BYTES);
        file.take(SNIFF_BYTES as u64)
            .read_to_end(&mut head)
            .map_err(|e| Error::io(path, e))?;
        Ok(Content::of(&head))
    }

    /// What the content is, for a message.
    pub fn describe(self) -> String {
        match self {
            Content::EclipseBinary => "an Eclipse binary file (EGRID, INIT, UNRST ...)".into(),
            Content::EclipseText => "a formatted Eclipse file (FEGRID, FINIT, FUNRST ...)".into(),
            Content::Roff(roff::Form::Binary) => "a binary ROFF file".into(),
            Content::Roff(roff::Form::Ascii) => "an ASCII ROFF file".into(),
            Content::Hierarchy => {
                "a strata level-of-detail hierarchy (written by `strata lod build`)".into()
            }
            Content::Binary { zero_at } => format!("binary data (byte {zero_at} is zero)"),
            Content::Text => "text".into(),
        }
    }
}

/// Opens a model with the default options: geometry, properties and, for EGRID, the
/// INIT and restart files beside it.
pub fn open(path: &Path) -> Result<CornerPointGrid> {
    open_with(path, &ReadOptions::default())
}

/// Opens a model, choosing the reader from the file's first bytes (an Eclipse binary
/// file is read as an EGRID whatever its name), else from its extension. A hierarchy
/// or other binary data is refused with a message that says what the file is.
pub fn open_with(path: &Path, options: &ReadOptions) -> Result<CornerPointGrid> {
    let content = Content::of_file(path)?;
    match (content, Format::from_path(path)) {
        (Content::Hierarchy, _) => Err(Error::Content {
            path: path.to_path_buf(),
            message: format!(
                "{}, not a model: draw it with `strata lod view`, summarise it with `strata info`",
                content.describe()
            ),
        }),
        (Content::Roff(_), _) => roff::read(path, options),
        (Content::EclipseBinary | Content::EclipseText, _) | (_, Format::Egrid) => {
            eclbin::read_egrid(path, options)
        }
        (Content::Binary { .. }, _) => Err(Error::Content {
            path: path.to_path_buf(),
            message: format!(
                "{}: neither a text deck (GRDECL, DATA) nor an Eclipse binary grid (EGRID)",
                content.describe()
            ),
        }),
        (Content::Text, Format::Grdecl | Format::Roff) => grdecl::read(path, options),
    }
}

/// Writes a model in the format its extension names.
pub fn save(grid: &CornerPointGrid, path: &Path) -> Result<()> {
    match Format::from_path(path) {
        Format::Egrid => eclbin::write_egrid(grid, path),
        Format::Grdecl => grdecl::write(grid, path),
        Format::Roff => roff::write(grid, path),
    }
}

/// Adds the per-cell properties of `path` to `grid`: a ROFF parameter (or grid) file,
/// else a GRDECL property deck. Returns the names added.
pub fn read_properties(grid: &mut CornerPointGrid, path: &Path) -> Result<Vec<String>> {
    match Content::of_file(path)? {
        Content::Roff(_) => roff::read_properties(grid, path),
        _ => grdecl::read_properties(grid, path),
    }
}
