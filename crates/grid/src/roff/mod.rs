//! ROFF (Roxar Open File Format), the native format of RMS and xtgeo: grids and their
//! parameters, binary (either byte order) and ASCII, read as xtgeo reads them; binary
//! written.
//!
//! A file is a header (`roff-bin` or `roff-asc`) and tags of typed keys ([`tags`]),
//! parsed by one grammar ([`parse`]) over the form's lexer ([`binary`], [`ascii`]); the
//! grid and its parameters are read from the tags ([`model`], [`zcorn`]). The whole file
//! is read into memory, and every array's count is checked against the bytes left
//! before anything is allocated for it.
//!
//! Errors name the file, the tag and key (`zvalues/splitEnz`) and, for a binary file,
//! the tag's number as the record with the byte offset, for an ASCII file the line.
//! Subgrids become per-layer zone names ([`CornerPointGrid::zones`]); discrete
//! parameters keep their code names ([`CornerPointGrid::codes`]).

mod ascii;
mod binary;
mod model;
mod params;
mod parse;
pub mod tags;
#[cfg(test)]
mod tests;
mod write;
mod zcorn;

use std::path::Path;

pub use tags::{Form, Roff};
pub use write::{to_bytes, write};

use crate::{CornerPointGrid, Error, ReadOptions, Result};

/// Whether the first bytes of a file are a ROFF header, and which form.
pub fn form_of(head: &[u8]) -> Option<Form> {
    if head.starts_with(binary::MAGIC) {
        Some(Form::Binary)
    } else if head.starts_with(ascii::MAGIC) {
        Some(Form::Ascii)
    } else {
        None
    }
}

/// Parses the tags of a ROFF file held in memory; errors name `path`.
pub fn parse_tags(path: &Path, bytes: &[u8]) -> Result<Roff> {
    match form_of(bytes) {
        Some(Form::Binary) => {
            parse::parse(path, bytes, Form::Binary, &mut binary::Binary::new(bytes))
        }
        Some(Form::Ascii) => parse::parse(path, bytes, Form::Ascii, &mut ascii::Ascii::new(bytes)),
        None => Err(Error::Content {
            path: path.to_path_buf(),
            message: "no ROFF header ('roff-bin' or 'roff-asc')".into(),
        }),
    }
}

fn read_file(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|e| Error::io(path, e))
}

/// Reads a ROFF grid file, with its parameters unless `options.grid_only`.
pub fn read(path: &Path, options: &ReadOptions) -> Result<CornerPointGrid> {
    parse_bytes(path, &read_file(path)?, options)
}

/// Reads a ROFF grid held in memory as if it were the file `path`.
pub fn parse_bytes(path: &Path, bytes: &[u8], options: &ReadOptions) -> Result<CornerPointGrid> {
    let roff = parse_tags(path, bytes)?;
    let place = tags::Place {
        path,
        bytes,
        form: roff.form,
    };
    match model::filetype(&roff) {
        Some("grid") | None => {}
        Some("parameter") => {
            return Err(Error::Content {
                path: path.to_path_buf(),
                message: "a ROFF parameter file, without geometry: add it to its grid \
                          (`--props` on the command line)"
                    .into(),
            });
        }
        Some(other) => {
            return Err(Error::Content {
                path: path.to_path_buf(),
                message: format!("a ROFF file of type '{other}', not a grid"),
            });
        }
    }
    model::grid(&place, &roff, !options.grid_only)
}

/// Adds the parameters of the ROFF file `path` (a parameter file, or a grid file whose
/// parameters are wanted) to `grid`, whose dimensions they must have. Returns their names.
pub fn read_properties(grid: &mut CornerPointGrid, path: &Path) -> Result<Vec<String>> {
    let bytes = read_file(path)?;
    let roff = parse_tags(path, &bytes)?;
    let place = tags::Place {
        path,
        bytes: &bytes,
        form: roff.form,
    };
    let d = model::dims(&place, &roff)?;
    if d != grid.dims() {
        let g = grid.dims();
        return Err(Error::model(
            path,
            "dimensions",
            format!(
                "{} x {} x {} cells, the grid has {} x {} x {}",
                d.nx, d.ny, d.nz, g.nx, g.ny, g.nz
            ),
        ));
    }
    let mut names = Vec::new();
    for p in params::parameters(&place, &roff, d)? {
        names.push(p.name.clone());
        params::add(grid, p, path)?;
    }
    if names.is_empty() {
        return Err(Error::model(path, "parameter", "no parameter in the file"));
    }
    Ok(names)
}
