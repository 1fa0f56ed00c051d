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

mod active;
mod egrid;
mod formatted;
mod gridfile;
mod record;
mod results;
#[cfg(test)]
mod tests;
mod writer;

use std::path::{Path, PathBuf};

pub use egrid::{parse_egrid_bytes, write_egrid};
pub use formatted::{looks_formatted, to_binary as formatted_to_binary};
pub use record::{
    EclFile, Record, RecordData, RecordKind, RecordView, Records, parse_records, read_records,
};
pub use results::{parse_init_bytes, parse_restart_bytes, write_init, write_unrst};
pub use writer::RecordWriter;

use crate::{CornerPointGrid, ReadOptions, Result};

/// The keywords of an Eclipse file: binary ones mapped, formatted ones converted to
/// binary records in memory (see [`formatted_to_binary`]). Which is told by content.
enum Source {
    Mapped(EclFile),
    Converted(PathBuf, Vec<u8>),
}

impl Source {
    fn open(path: &Path) -> Result<Source> {
        let head = crate::Content::of_file(path)?;
        if head == crate::Content::EclipseText {
            Ok(Source::Converted(
                path.to_path_buf(),
                formatted::read(path)?,
            ))
        } else {
            EclFile::open(path).map(Source::Mapped)
        }
    }

    fn records(&self) -> Records<'_> {
        match self {
            Source::Mapped(f) => f.records(),
            Source::Converted(path, bytes) => Records::new(path, bytes),
        }
    }
}

/// Reads an EGRID or a GRID file (per-cell corners, see [`gridfile`]), binary or
/// formatted, and unless `options.grid_only` is set or `options.load_results` is not,
/// the INIT and restart files beside it (see [`ResultFiles`]).
///
/// A result file that fails to read does not fail the grid: the geometry is what was
/// asked for, and a simulation killed mid-write leaves a truncated UNRST behind that
/// should not hide its grid. The failure is listed in
/// [`CornerPointGrid::warnings`] with the file, record and keyword.
pub fn read_egrid(path: &Path, options: &ReadOptions) -> Result<CornerPointGrid> {
    let source = Source::open(path)?;
    refuse_other_kinds(path, source.records())?;
    let mut grid = if gridfile::is_grid_file(source.records()) {
        gridfile::grid_from_records(path, source.records())?
    } else {
        egrid::egrid_from_records(path, source.records(), options)?
    };
    drop(source);
    if options.load_results && !options.grid_only {
        load_results(&mut grid, path);
    }
    Ok(grid)
}

/// Names an Eclipse file that is not a grid by what its first keywords say it is:
/// results, a summary, or an EGRID of local grids only.
fn refuse_other_kinds(path: &Path, records: Records<'_>) -> Result<()> {
    let mut names = Vec::new();
    for view in records.take(16) {
        let Ok(view) = view else { break };
        names.push(view.name().to_string());
    }
    let has = |n: &str| names.iter().any(|m| m == n);
    if let Some(g) = names.iter().position(|n| n == "GRIDHEAD" || n == "COORDS") {
        if !names[..g].iter().any(|n| n == "LGR") {
            return Ok(()); // a main grid comes first
        }
    }
    let kind = match names.first().map(String::as_str) {
        Some("SEQNUM") => "an Eclipse restart file (UNRST, Xnnnn): results, read beside its EGRID",
        Some("INTEHEAD") if has("LOGIHEAD") => {
            "an Eclipse INIT file: static results, read beside its EGRID"
        }
        Some("INTEHEAD") => "Eclipse results (INIT or restart), read beside their EGRID",
        Some("DIMENS") if has("KEYWORDS") => {
            "an Eclipse summary specification (SMSPEC), not a grid"
        }
        Some("SEQHDR" | "MINISTEP" | "PARAMS") => {
            "Eclipse summary data (UNSMRY, Snnnn), not a grid"
        }
        _ if has("LGR") => "an EGRID of local grids (LGR) only, without a main grid: not read",
        _ => return Ok(()),
    };
    Err(crate::Error::Content {
        path: path.to_path_buf(),
        message: kind.to_string(),
    })
}

/// Reads an INIT file's static properties into `grid` (see [`parse_init_bytes`]),
/// binary or formatted (FINIT).
pub fn read_init(grid: &mut CornerPointGrid, path: &Path) -> Result<()> {
    let source = Source::open(path)?;
    results::init_from_records(grid, path, source.records())
}

/// Appends the report steps of a restart file to `grid`: a unified `.UNRST`, or one
/// non-unified `.Xnnnn` (numbered by its extension when it has no SEQNUM), binary or
/// formatted (`.FUNRST`, `.Fnnnn`).
pub fn read_restart(grid: &mut CornerPointGrid, path: &Path) -> Result<()> {
    let source = Source::open(path)?;
    results::restart_from_records(grid, path, source.records())
}

/// The result files that belong to an EGRID: same directory and base name, extension
/// matched without regard to case (`E100_BO.EGRID` -> `E100_BO.INIT`, `E100_BO.UNRST`,
/// `E100_BO.X0001`, ...). Formatted ones (`FINIT`, `FUNRST`, `Fnnnn`) are taken where
/// no binary one of the kind is there.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ResultFiles {
    /// The INIT file (static properties over active cells), when there is one.
    pub init: Option<PathBuf>,
    /// The unified restart file (every report step in one file), when there is one.
    pub unrst: Option<PathBuf>,
    /// Non-unified restarts `.Xnnnn`, by report number.
    pub restarts: Vec<(i32, PathBuf)>,
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
        let mut formatted = (None, None, Vec::new());
        for entry in std::fs::read_dir(dir)? {
            let path = entry?.path();
            if path.file_stem() != stem {
                continue;
            }
            let Some(ext) = path.extension().and_then(|e| e.to_str()) else {
                continue;
            };
            let ext = ext.to_ascii_uppercase();
            match ext.as_str() {
                "INIT" => found.init = Some(path),
                "FINIT" => formatted.0 = Some(path),
                "UNRST" => found.unrst = Some(path),
                "FUNRST" => formatted.1 = Some(path),
                _ => match results::xnnnn_number(&path) {
                    Some(n) if ext.starts_with('X') => found.restarts.push((n, path)),
                    Some(n) => formatted.2.push((n, path)),
                    None => {}
                },
            }
        }
        found.init = found.init.or(formatted.0);
        found.unrst = found.unrst.or(formatted.1);
        if found.restarts.is_empty() {
            found.restarts = formatted.2;
        }
        found.restarts.sort();
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
}
