//! `strata bench io`: how fast our readers load grids, next to resdata and xtgeo.
//!
//! Read throughput is what decides whether a user waits for a big model to open, and
//! the Python readers are what our users would otherwise use, so both are measured in
//! the same run on the same files: a generated 200 x 200 x 50 model written as GRDECL
//! and as EGRID (big enough for throughput to dominate start-up costs), and every grid
//! file of the shared data folder (real files, with their comments, repeats and
//! INCLUDEs). Each time is the median of several loads after an untimed one, so the
//! page cache is warm and disk speed is out of the comparison; ours are geometry-only
//! reads (`grid_only`), as the reference readers load no properties either.
//!
//! The reference times come from `scripts/bench_io_reference.py`, run with `python3`.
//! When Python, the script or a package is missing, or a file is not one they read,
//! their times are `null` and the report's notes say why: the benchmark still runs.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};
use strata_grid::ReadOptions;
use strata_grid::synth::{SynthParams, generate};

/// Timed loads per file with our reader; the median is reported.
const RUNS: usize = 5;
/// Timed loads per file and Python reader: fewer, as they are slower on big files.
const PYTHON_RUNS: usize = 3;
/// Seconds after which the Python script stops timing one reader on one file (it
/// still reports the median of the loads done, at least one).
const PYTHON_BUDGET_S: f64 = 60.0;
/// The generated model.
const SYNTH: SynthParams = SynthParams {
    nx: 200,
    ny: 200,
    nz: 50,
    faults: 4,
    seed: 1,
};
/// Megabyte as used for throughput: 10^6 bytes.
const MB: f64 = 1e6;

/// What `strata bench io` measured; `--json` prints it as is.
#[derive(Debug, Serialize)]
pub struct IoReport {
    /// One row per file read: the generated model as GRDECL and EGRID, then every grid
    /// file of the data folder that our reader loaded.
    pub files: Vec<FileTiming>,
    /// How the numbers were taken and everything that was left out, and why.
    pub notes: Vec<String>,
}

/// One file's load times.
#[derive(Debug, Serialize)]
pub struct FileTiming {
    /// Path relative to the data folder, or the generated file's name.
    pub file: String,
    /// `grdecl` (text decks, `.DATA` included), `egrid`, `fegrid`, `grid` or `roff`.
    pub format: &'static str,
    /// Size of the named file (INCLUDEd files not counted).
    pub bytes: u64,
    /// Cells of the grid (nx * ny * nz, inactive ones included), as our reader loads it.
    pub cells: usize,
    /// Median seconds of our geometry-only read.
    pub strata_s: f64,
    /// Our read throughput: `bytes` in MB (10^6 bytes) over `strata_s`.
    pub strata_mb_s: f64,
    /// Our read throughput in cells per second: `cells` over `strata_s`.
    pub strata_cells_s: f64,
    /// Median seconds of resdata's load, `null` when it could not be timed.
    pub resdata_s: Option<f64>,
    /// Median seconds of xtgeo's load, `null` when it could not be timed.
    pub xtgeo_s: Option<f64>,
}

/// A file to time: what to call it in the report, and where it is.
struct Input {
    label: String,
    path: PathBuf,
}

/// Runs the benchmark: the generated model (written to a temporary folder) and every
/// grid file under `data_dir` (skipped, with a note, when the folder is absent).
pub fn run(data_dir: &Path) -> Result<IoReport> {
    let mut notes = vec![
        format!(
            "times are medians of {RUNS} loads (strata) and up to {PYTHON_RUNS} loads \
             (resdata, xtgeo; fewer past {PYTHON_BUDGET_S} s) after one untimed load, \
             page cache warm; strata reads with grid_only (geometry and ACTNUM)"
        ),
        "MB is 10^6 bytes of the named file; INCLUDEd files are not counted, so for a \
         deck that includes its data cells/s is the figure to compare"
            .to_string(),
    ];
    let tmp = tempfile::tempdir().context("creating a temporary folder")?;
    let mut inputs = synthetic_inputs(tmp.path())?;
    if data_dir.is_dir() {
        inputs.extend(model_files(data_dir)?);
    } else {
        notes.push(format!(
            "{}: not found, only the generated model is measured",
            data_dir.display()
        ));
    }

    let mut files = Vec::new();
    let mut timed = Vec::new();
    for input in inputs {
        match time_strata(&input.path) {
            Ok((seconds, cells)) => {
                let bytes = std::fs::metadata(&input.path)
                    .with_context(|| input.path.display().to_string())?
                    .len();
                files.push(FileTiming {
                    file: input.label,
                    format: format_name(&input.path),
                    bytes,
                    cells,
                    strata_s: seconds,
                    strata_mb_s: bytes as f64 / MB / seconds,
                    strata_cells_s: cells as f64 / seconds,
                    resdata_s: None,
                    xtgeo_s: None,
                });
                timed.push(input.path);
            }
            Err(e) => notes.push(format!(
                "{}: not read as a grid, left out: {e}",
                input.label
            )),
        }
    }

    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/bench_io_reference.py");
    let reference = python_reference("python3", &script, &timed);
    notes.extend(reference.notes);
    for (file, (resdata, xtgeo)) in files.iter_mut().zip(reference.times) {
        file.resdata_s = resdata;
        file.xtgeo_s = xtgeo;
    }
    Ok(IoReport { files, notes })
}

/// Generates the benchmark model and writes it as GRDECL, EGRID and binary ROFF into
/// `dir`.
fn synthetic_inputs(dir: &Path) -> Result<Vec<Input>> {
    let grid = generate(&SYNTH).context("generating the benchmark model")?;
    let SynthParams {
        nx, ny, nz, faults, ..
    } = SYNTH;
    ["grdecl", "EGRID", "roff"]
        .into_iter()
        .map(|ext| {
            let label = format!("synth-{nx}x{ny}x{nz}-f{faults}.{ext}");
            let path = dir.join(&label);
            strata_grid::save(&grid, &path).with_context(|| format!("writing {label}"))?;
            Ok(Input { label, path })
        })
        .collect()
}

/// The files under `data_dir` (itself and its subfolders, sorted) whose extension names
/// a grid format we read: `.egrid`, `.fegrid`, `.grid`, `.grdecl`, `.data`, `.roff`,
/// `.roffbin`, `.roffasc`, any case. Property-only decks and ROFF parameter files
/// among them are found out when read, and left out with a note.
fn model_files(data_dir: &Path) -> Result<Vec<Input>> {
    let mut paths = Vec::new();
    let mut folders = vec![data_dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).with_context(|| folder.display().to_string())? {
            let path = entry?.path();
            if path.is_dir() {
                folders.push(path);
            } else if is_grid_file(&path) {
                paths.push(path);
            }
        }
    }
    paths.sort();
    Ok(paths
        .into_iter()
        .map(|path| Input {
            label: path
                .strip_prefix(data_dir)
                .unwrap_or(&path)
                .display()
                .to_string(),
            path,
        })
        .collect())
}

/// Whether `path`'s extension names a grid format we read (any case).
fn is_grid_file(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| {
        [
            "egrid", "fegrid", "grid", "grdecl", "data", "roff", "roffbin", "roffasc",
        ]
        .iter()
        .any(|g| e.eq_ignore_ascii_case(g))
    })
}

/// The report's name of `path`'s format: `egrid`, `fegrid`, `grid`, `roff` (binary or
/// ASCII) or `grdecl`.
fn format_name(path: &Path) -> &'static str {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match ext.as_str() {
        "egrid" => "egrid",
        "fegrid" => "fegrid",
        "grid" => "grid",
        e if e.starts_with("roff") => "roff",
        _ => "grdecl",
    }
}

/// Median seconds of [`RUNS`] geometry-only reads after an untimed one, and the
/// number of cells.
fn time_strata(path: &Path) -> strata_grid::Result<(f64, usize)> {
    let options = ReadOptions {
        grid_only: true,
        ..ReadOptions::default()
    };
    let cells = strata_grid::open_with(path, &options)?.cell_count();
    let mut times = Vec::with_capacity(RUNS);
    for _ in 0..RUNS {
        let start = Instant::now();
        let grid = strata_grid::open_with(path, &options)?;
        times.push(start.elapsed().as_secs_f64());
        drop(grid);
    }
    Ok((median(&mut times), cells))
}

/// The median of `values` (the mean of the middle two for an even count); sorts them.
fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

/// What the Python script reported: resdata's and xtgeo's median seconds per file, in
/// the order the files were given.
struct PythonTimes {
    times: Vec<(Option<f64>, Option<f64>)>,
    notes: Vec<String>,
}

/// The JSON `bench_io_reference.py` prints.
#[derive(Deserialize)]
struct ScriptOutput {
    files: Vec<ScriptFile>,
    notes: Vec<String>,
}

#[derive(Deserialize)]
struct ScriptFile {
    path: String,
    resdata_s: Option<f64>,
    xtgeo_s: Option<f64>,
    resdata_runs: usize,
    xtgeo_runs: usize,
}

/// Runs `script` with the interpreter `python` on `paths`. Never fails: anything that
/// goes wrong leaves the times out and says why in the notes.
fn python_reference(python: &str, script: &Path, paths: &[PathBuf]) -> PythonTimes {
    let none = |note: String| PythonTimes {
        times: Vec::new(),
        notes: vec![format!("{note}: resdata_s and xtgeo_s are null")],
    };
    if paths.is_empty() {
        return none("no file to time".to_string());
    }
    if !script.is_file() {
        return none(format!("{} not found", script.display()));
    }
    let output = Command::new(python)
        .arg(script)
        .args(["--runs", &PYTHON_RUNS.to_string()])
        .args(["--budget", &PYTHON_BUDGET_S.to_string()])
        .args(paths)
        .output();
    let output = match output {
        Ok(o) => o,
        Err(e) => return none(format!("{python} could not be run ({e})")),
    };
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let mut tail: Vec<_> = stderr.lines().rev().take(3).collect();
        tail.reverse();
        return none(format!(
            "{} failed ({}): {}",
            script.display(),
            output.status,
            tail.join(" | ")
        ));
    }
    let parsed = match serde_json::from_slice::<ScriptOutput>(&output.stdout) {
        Ok(parsed) if parsed.files.len() == paths.len() => parsed,
        Ok(parsed) => {
            return none(format!(
                "{} answered for {} files out of {}",
                script.display(),
                parsed.files.len(),
                paths.len()
            ));
        }
        Err(e) => return none(format!("{} printed no valid JSON ({e})", script.display())),
    };
    let mut notes = parsed.notes;
    for f in &parsed.files {
        for (reader, runs) in [("resdata", f.resdata_runs), ("xtgeo", f.xtgeo_runs)] {
            if runs > 0 && runs < PYTHON_RUNS {
                let name = Path::new(&f.path).file_name().unwrap_or_default();
                notes.push(format!(
                    "{reader} on {}: median of {runs} loads (time budget)",
                    name.to_string_lossy()
                ));
            }
        }
    }
    PythonTimes {
        times: parsed
            .files
            .iter()
            .map(|f| (f.resdata_s, f.xtgeo_s))
            .collect(),
        notes,
    }
}

/// Prints the report as a table, then its notes.
pub fn print_table(report: &IoReport) {
    let ms = |s: Option<f64>| s.map_or_else(|| "-".to_string(), |s| format!("{:.2}", s * 1e3));
    println!(
        "{:<48} {:>6} {:>9} {:>9} {:>10} {:>8} {:>9} {:>11} {:>10}",
        "file", "format", "MB", "cells", "strata ms", "MB/s", "Mcells/s", "resdata ms", "xtgeo ms"
    );
    for f in &report.files {
        println!(
            "{:<48} {:>6} {:>9.3} {:>9} {:>10} {:>8.1} {:>9.2} {:>11} {:>10}",
            f.file,
            f.format,
            f.bytes as f64 / MB,
            f.cells,
            ms(Some(f.strata_s)),
            f.strata_mb_s,
            f.strata_cells_s / 1e6,
            ms(f.resdata_s),
            ms(f.xtgeo_s),
        );
    }
    for note in &report.notes {
        println!("note: {note}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
    }

    #[test]
    fn grid_files_are_chosen_by_extension() {
        assert!(is_grid_file(Path::new("a/REEK.EGRID")));
        assert!(is_grid_file(Path::new("x.grdecl")));
        assert!(is_grid_file(Path::new("SPE10_MODEL2.DATA")));
        assert!(!is_grid_file(Path::new("E100_BO.UNRST")));
        assert!(!is_grid_file(Path::new("zones.lyr")));
        assert!(is_grid_file(Path::new("reek_grd_w_props.roffasc")));
        assert!(!is_grid_file(Path::new(
            "reek2_grid_w_zerolayer.roff.invalid"
        )));
    }

    /// A missing interpreter must give null times and a note, not an error.
    #[test]
    fn missing_python_leaves_times_null_with_a_note() {
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/bench_io_reference.py");
        let got = python_reference(
            "strata-no-such-python",
            &script,
            &[PathBuf::from("model.EGRID")],
        );
        assert!(got.times.is_empty());
        assert_eq!(got.notes.len(), 1);
        assert!(got.notes[0].contains("could not be run"), "{:?}", got.notes);
    }

    #[test]
    fn missing_script_leaves_times_null_with_a_note() {
        let got = python_reference(
            "python3",
            Path::new("no/such/script.py"),
            &[PathBuf::from("model.EGRID")],
        );
        assert!(got.times.is_empty());
        assert!(got.notes[0].contains("not found"), "{:?}", got.notes);
    }
}
