//! Eclipse binary files (EGRID, INIT, UNRST, Xnnnn): reader and writer.
//!
//! The files are big-endian Fortran unformatted sequential records: a 16-byte header
//! record per keyword (8-char name, item count, 4-char type) followed by data records
//! of at most 1000 numbers or 105 strings. [`Records`] walks them zero-copy over a
//! memory-mapped file ([`EclFile`]); [`RecordWriter`] writes them.
//!
//! Errors about the file's structure are [`Error::Binary`](crate::Error::Binary) where
//! `record` is the **1-based number of the keyword** in the file (its header record and
//! data records together count as one, as keyword listings number them), `keyword` its
//! name (empty when the header itself is unreadable) and `offset` the byte offset of the
//! Fortran record where the problem was found. No count read from a file is used to
//! allocate before it has been checked against the bytes that really follow.

mod egrid;
mod record;
mod results;
#[cfg(test)]
mod tests;
mod writer;

use std::path::{Path, PathBuf};

pub use egrid::{parse_egrid_bytes, write_egrid};
pub use record::{
    EclFile, Record, RecordData, RecordKind, RecordView, Records, parse_records, read_records,
};
pub use results::{parse_init_bytes, parse_restart_bytes, write_init, write_unrst};
pub use writer::RecordWriter;

use crate::{CornerPointGrid, ReadOptions, Result};

/// Reads an EGRID, and unless `options.grid_only` is set or `options.load_results`
/// is not, the INIT and restart files beside it (see [`ResultFiles`]).
///
/// A result file that fails to read does not fail the grid: the geometry is what was
/// asked for, and a simulation killed mid-write leaves a truncated UNRST behind that
/// should not hide its grid. The failure is listed in
/// [`CornerPointGrid::warnings`] with the file, record and keyword.
pub fn read_egrid(path: &Path, options: &ReadOptions) -> Result<CornerPointGrid> {
    let file = EclFile::open(path)?;
    let mut grid = egrid::egrid_from_records(path, file.records(), options)?;
    drop(file);
    if options.load_results && !options.grid_only {
        load_results(&mut grid, path);
    }
    Ok(grid)
}

/// Reads an INIT file's static properties into `grid` (see [`parse_init_bytes`]).
pub fn read_init(grid: &mut CornerPointGrid, path: &Path) -> Result<()> {
    let file = EclFile::open(path)?;
    results::init_from_records(grid, path, file.records())
}

/// Appends the report steps of a restart file to `grid`: a unified `.UNRST`, or one
/// non-unified binary `.Xnnnn` (numbered by its extension when it has no SEQNUM).
/// Formatted files (`.FUNRST`, `.Fnnnn`) are refused.
pub fn read_restart(grid: &mut CornerPointGrid, path: &Path) -> Result<()> {
    if results::is_formatted(path) {
        return Err(crate::Error::model(
            path,
            "",
            "formatted (text) restart files are not read; ask the simulator for binary output",
        ));
    }
    let file = EclFile::open(path)?;
    results::restart_from_records(grid, path, file.records())
}

/// The result files that belong to an EGRID: same directory and base name, extension
/// matched without regard to case (`E100_BO.EGRID` -> `E100_BO.INIT`, `E100_BO.UNRST`,
/// `E100_BO.X0001`, ...).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ResultFiles {
    /// The INIT file (static properties over active cells), when there is one.
    pub init: Option<PathBuf>,
    /// The unified restart file (every report step in one file), when there is one.
    pub unrst: Option<PathBuf>,
    /// Non-unified restarts `.Xnnnn`, by report number.
    pub restarts: Vec<(i32, PathBuf)>,
    /// Formatted result files found, which are not read.
    pub formatted: Vec<PathBuf>,
}

impl ResultFiles {
    /// Lists the directory of `egrid` for its result files.
    pub fn find(egrid: &Path) -> std::io::Result<ResultFiles> {
        let dir = match egrid.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let stem = egrid.file_stem();
        let mut found = ResultFiles::default();
        for entry in std::fs::read_dir(dir)? {
            let path = entry?.path();
            if path.file_stem() != stem {
                continue;
            }
            let Some(ext) = path.extension().and_then(|e| e.to_str()) else {
                continue;
            };
            if ext.eq_ignore_ascii_case("INIT") {
                found.init = Some(path);
            } else if ext.eq_ignore_ascii_case("UNRST") {
                found.unrst = Some(path);
            } else if let Some(n) = results::xnnnn_number(&path) {
                found.restarts.push((n, path));
            } else if results::is_formatted(&path) {
                found.formatted.push(path);
            }
        }
        found.restarts.sort();
        found.formatted.sort();
        Ok(found)
    }
}

/// Reads the INIT and the restarts (UNRST, else the Xnnnn files) beside `egrid`,
/// turning each failure into a warning (see [`read_egrid`]).
fn load_results(grid: &mut CornerPointGrid, egrid: &Path) {
    let files = match ResultFiles::find(egrid) {
        Ok(f) => f,
        Err(e) => {
            grid.warnings.push(format!(
                "{}: could not list the directory for INIT and restart files: {e}",
                egrid.display()
            ));
            return;
        }
    };
    fn warn(grid: &mut CornerPointGrid, r: Result<()>) {
        if let Err(e) = r {
            grid.warnings.push(format!("results skipped: {e}"));
        }
    }
    if let Some(init) = &files.init {
        let r = read_init(grid, init);
        warn(grid, r);
    }
    if let Some(unrst) = &files.unrst {
        let r = read_restart(grid, unrst);
        warn(grid, r);
    } else {
        for (_, x) in &files.restarts {
            let r = read_restart(grid, x);
            warn(grid, r);
        }
    }
    for f in &files.formatted {
        grid.warnings
            .push(format!("{}: formatted result file not read", f.display()));
    }
}
