//! GRDECL text decks (and `.DATA` decks): reader and writer.
//!
//! The reader memory-maps the deck and each INCLUDE file and works on their bytes
//! (decks are often not UTF-8). The keyword level (`grdecl/deck.rs`) is sequential;
//! the bulk data of COORD, ZCORN, ACTNUM and properties (`grdecl/numbers.rs`) is
//! parsed in parallel pieces cut at newlines. What it understands:
//!
//! * SPECGRID / DIMENS, COORD, ZCORN, ACTNUM, MAPAXES, GRIDUNIT (and METRIC, FIELD,
//!   LAB in RUNSPEC); MAPUNITS, GDORIENT, COORDSYS, ECHO/NOECHO and other keywords are
//!   skipped; any other keyword with one number per cell becomes a property;
//! * `N*v` and `N*` repeats (a default is NaN in a property, 1 in ACTNUM), `--`
//!   comments, commas, Fortran `D` exponents, `/` glued to data, quoted strings;
//! * INCLUDE relative to the root deck's folder, with cycles refused; a missing file
//!   is an error, or with [`ReadOptions::grid_only`] a warning in
//!   [`CornerPointGrid::warnings`];
//! * `.DATA` decks: GRID and PROPS are read, DIMENS and the unit system from RUNSPEC,
//!   the other sections skimmed;
//! * block-centred DX/DY/DZ/TOPS (or DXV/DYV/DZV), converted to corner-point
//!   (`grdecl/block.rs`), with BOX/ENDBOX and EQUALS/MULTIPLY/ADD/COPY over boxes
//!   (`grdecl/cells.rs`).
//!
//! Errors are [`Error::Text`] naming the file, keyword and line, or
//! [`Error::Model`] when something the grid needs is missing. No count read from a
//! deck sizes an allocation unchecked: see the budget in `grdecl/deck.rs`.

mod block;
mod cells;
mod deck;
mod lex;
mod numbers;
#[cfg(test)]
mod tests;
mod writer;

use std::path::Path;

use memmap2::Mmap;

use crate::pages::Pages;
use crate::{CornerPointGrid, Error, ReadOptions, Result};

/// Reads a GRDECL or DATA deck.
pub fn read(path: &Path, options: &ReadOptions) -> Result<CornerPointGrid> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    // SAFETY: the map is only read, and lives until parsing returns. Another process
    // truncating the file meanwhile is the accepted risk of every memory-mapped reader.
    let map = unsafe { Mmap::map(&file) }.map_err(|e| Error::io(path, e))?;
    deck::parse(path, &map, Pages::of(&map), options)
}

/// Reads a deck held in memory as if it were the file `path`: errors name `path`,
/// and INCLUDE files are looked for relative to its folder.
pub fn parse_bytes(path: &Path, bytes: &[u8], options: &ReadOptions) -> Result<CornerPointGrid> {
    deck::parse(path, bytes, Pages::default(), options)
}

/// Adds the per-cell arrays of the property deck `path` (PORO, PERMX, ...; no grid
/// keywords needed) to `grid`, as for an EGRID whose properties come in a separate
/// GRDECL file. ACTNUM in such a deck is refused: it would change which cells exist.
/// Returns the names added.
pub fn read_properties(grid: &mut CornerPointGrid, path: &Path) -> Result<Vec<String>> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    // SAFETY: as in `read`.
    let map = unsafe { Mmap::map(&file) }.map_err(|e| Error::io(path, e))?;
    let dims = grid.dims();
    let arrays = deck::parse_properties(path, &map, Pages::of(&map), dims)?;
    let mut names = Vec::new();
    for (name, values) in arrays {
        if name == "ACTNUM" {
            return Err(Error::model(
                path,
                "ACTNUM",
                "a property deck may not redefine ACTNUM",
            ));
        }
        let array = ndarray::Array3::from_shape_vec((dims.nz, dims.ny, dims.nx), values)
            .map_err(|e| Error::model(path, &name, e.to_string()))?;
        grid.set_property(&name, array)
            .map_err(|e| Error::model(path, &name, e.to_string()))?;
        names.push(name);
    }
    if names.is_empty() {
        return Err(Error::model(path, "", "no per-cell property in the deck"));
    }
    Ok(names)
}

/// Writes a grid as a GRDECL deck: MAPUNITS and MAPAXES when the grid has map axes,
/// GRIDUNIT, SPECGRID, COORD, ZCORN, ACTNUM and every property.
pub fn write(grid: &CornerPointGrid, path: &Path) -> Result<()> {
    writer::write(grid, path)
}
