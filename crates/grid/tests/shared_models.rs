//! Our readers against independent readings of the real models in `../shared/data`.
//!
//! The reference values in `tests/reference/` were written by
//! `tests/reference/make_reference.py` with `resdata` (every corner-point file, EGRID and
//! GRDECL; cross-checked there against `xtgeo`) and, for the block-centred SPE10 model 2
//! deck, which neither package reads with its PHI/PERM INCLUDE files missing, by that
//! script's own numpy reading of DX/DY/DZ/TOPS (cross-checked against
//! `xtgeo.create_box_grid`). Every model is checked on **every** cell, SPE10 model 2's
//! 1.1 M included: dimensions, ACTNUM cell by cell and active count (and the counts in
//! the data folder's README), bounding box, and the 8 map-coordinate corners of each
//! cell to 1e-3 of the model's extent (its active bounding-box diagonal), and that no
//! corner counts as stray ([`CornerPointGrid::stray_corners`]). The stored
//! corners are quantized to 1/65535 of the bounding box per axis, below 1e-5 of the
//! extent; the resdata reading holds coordinates in float32 as Eclipse does, a few 1e-5
//! of the extent for text decks in UTM coordinates. Each assertion message gives the
//! largest deviation found and where, so a passing run's margin can be read with
//! `cargo test --test shared_models -- --nocapture`.
//!
//! When `../shared/data` is absent every test prints `skipping: ../shared/data not
//! found` and returns.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::Read;
use std::path::Path;

use flate2::read::GzDecoder;
use serde::Deserialize;
use strata_grid::{CornerPointGrid, ReadOptions};

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data");
const REFERENCE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/reference");

/// Largest corner deviation allowed, as a fraction of the model's extent.
const TOLERANCE: f64 = 1e-3;

/// The rows of `../shared/data/README.md`'s table: file, dimensions, active cells.
/// The emerald row's numbers are those of `eme_small_w_hole_grid_params.grdecl`;
/// `emerald.grdecl` is a 4 x 4 x 3 grid the table does not describe (checked against
/// the reference only).
const README_TABLE: &[(&str, [usize; 3], usize)] = &[
    ("reek/REEK.EGRID", [40, 64, 14], 35_838),
    ("reek/reek_sim_grid.grdecl", [40, 64, 14], 35_838),
    ("spe9/BENCH_SPE9.EGRID", [24, 25, 15], 9_000),
    ("spe9/xtgeo_SPE9.GRDECL", [24, 25, 15], 9_000),
    (
        "emerald/eme_small_w_hole_grid_params.grdecl",
        [21, 41, 18],
        7_157,
    ),
    ("simpleb8/E100_BO.EGRID", [4, 2, 3], 22),
    ("simpleb8/simpleb8.grdecl", [4, 2, 3], 22),
    ("spe10model2/SPE10_MODEL2.DATA", [60, 220, 85], 1_122_000),
];

#[derive(Deserialize)]
struct Reference {
    models: BTreeMap<String, Model>,
}

#[derive(Deserialize)]
struct Model {
    file: String,
    dims: [usize; 3],
    cells: usize,
    active: usize,
    bbox_min: [f64; 3],
    bbox_max: [f64; 3],
    extent: f64,
    corners_file: String,
    actnum_file: String,
    quant_lo: [f64; 3],
    quant_hi: [f64; 3],
    #[serde(default)]
    missing_includes: Vec<String>,
    #[serde(default)]
    report_steps: Vec<Step>,
    init_poro: Option<PropertySummary>,
}

#[derive(Deserialize)]
struct Step {
    number: i32,
    date: (i32, u32, u32),
    /// Array name -> (global cell index, value) for every active cell.
    arrays: BTreeMap<String, Vec<(usize, f64)>>,
}

#[derive(Deserialize)]
struct PropertySummary {
    count: usize,
    sum: f64,
    sum_sq: f64,
    min: f64,
    max: f64,
    /// (global cell index, value).
    samples: Vec<(usize, f64)>,
}

/// The data folder, or `None` after saying the tests are skipped.
fn data_dir() -> Option<&'static Path> {
    let dir = Path::new(DATA);
    if dir.is_dir() {
        Some(dir)
    } else {
        println!("skipping: ../shared/data not found");
        None
    }
}

fn reference(name: &str) -> Model {
    let path = Path::new(REFERENCE).join("reference.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut all: Reference =
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    all.models
        .remove(name)
        .unwrap_or_else(|| panic!("{path:?} has no model {name}"))
}

fn gunzip(name: &str) -> Vec<u8> {
    let path = Path::new(REFERENCE).join(name);
    let file = File::open(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut bytes = Vec::new();
    GzDecoder::new(file)
        .read_to_end(&mut bytes)
        .unwrap_or_else(|e| panic!("{path:?}: {e}"));
    bytes
}

/// The reference corners of a model, decoded from the layout `make_reference.py`
/// documents: 24 planes (3 * corner + axis), each `n` high bytes then `n` low bytes of
/// the wrapping u16 delta from the previous cell's quantized value.
struct Corners {
    cells: usize,
    q: Vec<u16>,
    lo: [f64; 3],
    scale: [f64; 3],
}

impl Corners {
    fn load(model: &Model) -> Self {
        let n = model.cells;
        let bytes = gunzip(&model.corners_file);
        assert_eq!(bytes.len(), 48 * n, "{}: size", model.corners_file);
        let mut q = Vec::with_capacity(24 * n);
        for plane in bytes.chunks_exact(2 * n) {
            let (hi, lo) = plane.split_at(n);
            let mut value = 0u16;
            for (&h, &l) in hi.iter().zip(lo) {
                value = value.wrapping_add(u16::from_be_bytes([h, l]));
                q.push(value);
            }
        }
        let scale = std::array::from_fn(|a| (model.quant_hi[a] - model.quant_lo[a]) / 65535.0);
        Corners {
            cells: n,
            q,
            lo: model.quant_lo,
            scale,
        }
    }

    fn corner(&self, cell: usize, c: usize) -> [f64; 3] {
        std::array::from_fn(|a| {
            let q = self.q[(3 * c + a) * self.cells + cell];
            self.lo[a] + f64::from(q) * self.scale[a]
        })
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

/// The largest corner distance between `grid` and `other(i, j, k, c)` over all cells,
/// with the cell and corner where it occurs and both points.
struct Worst {
    dev: f64,
    at: (usize, usize, usize, usize),
    ours: [f64; 3],
    theirs: [f64; 3],
}

fn worst_corner(
    grid: &CornerPointGrid,
    other: impl Fn(usize, [usize; 3], usize) -> [f64; 3],
) -> Worst {
    let d = grid.dims();
    let mut worst = Worst {
        dev: 0.0,
        at: (0, 0, 0, 0),
        ours: [0.0; 3],
        theirs: [0.0; 3],
    };
    for cell in 0..d.cell_count() {
        let (i, j, k) = d.cell_ijk(cell);
        for (c, ours) in grid.cell_corners(i, j, k).into_iter().enumerate() {
            let theirs = other(cell, [i, j, k], c);
            let dev = distance(ours, theirs);
            // A NaN corner is the worst there is: it stays, and fails the assertion.
            if dev > worst.dev || dev.is_nan() {
                worst = Worst {
                    dev,
                    at: (i, j, k, c),
                    ours,
                    theirs,
                };
            }
        }
    }
    worst
}

fn open_grid_only(path: &Path) -> CornerPointGrid {
    let options = ReadOptions {
        grid_only: true,
        ..ReadOptions::default()
    };
    strata_grid::open_with(path, &options).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Reads the model `name` of the reference with our reader (geometry only) and checks
/// dimensions, active counts, ACTNUM, bounding box and every cell's corners. Returns
/// the grid for model-specific checks.
fn check_model(data: &Path, name: &str) -> CornerPointGrid {
    let model = reference(name);
    let path = data.join(&model.file);
    let grid = open_grid_only(&path);
    let d = grid.dims();
    let file = &model.file;
    assert_eq!([d.nx, d.ny, d.nz], model.dims, "{file}: dimensions");
    assert_eq!(grid.active_count(), model.active, "{file}: active cells");
    if let Some((_, dims, active)) = README_TABLE.iter().find(|row| row.0 == file) {
        assert_eq!(
            [d.nx, d.ny, d.nz],
            *dims,
            "{file}: dimensions in the README"
        );
        assert_eq!(
            grid.active_count(),
            *active,
            "{file}: active cells in the README"
        );
    }

    let actnum = gunzip(&model.actnum_file);
    assert_eq!(actnum.len(), model.cells, "{}", model.actnum_file);
    let differing: Vec<_> = (0..model.cells)
        .filter(|&cell| {
            let (i, j, k) = d.cell_ijk(cell);
            grid.is_active(i, j, k) != (actnum[cell] == 1)
        })
        .map(|cell| d.cell_ijk(cell))
        .collect();
    assert!(
        differing.is_empty(),
        "{file}: ACTNUM differs in {} cells, first (i, j, k) from 0: {:?}",
        differing.len(),
        &differing[..differing.len().min(5)]
    );

    let tol = TOLERANCE * model.extent;
    let reference = Corners::load(&model);
    let worst = worst_corner(&grid, |cell, _, c| reference.corner(cell, c));
    let (i, j, k, c) = worst.at;
    let message = format!(
        "{file}: max corner deviation {:.6} ({:.3e} of extent {:.3}) at cell (i, j, k) = \
         ({i}, {j}, {k}) from 0, corner {c}: ours {:?}, reference {:?}",
        worst.dev,
        worst.dev / model.extent,
        model.extent,
        worst.ours,
        worst.theirs
    );
    assert!(worst.dev <= tol, "{message}");
    println!("{message}");

    let bbox = grid.bounding_box();
    let bbox_dev = (0..3)
        .map(|a| {
            (bbox.min[a] - model.bbox_min[a])
                .abs()
                .max((bbox.max[a] - model.bbox_max[a]).abs())
        })
        .fold(0.0, f64::max);
    assert!(
        bbox_dev <= tol,
        "{file}: bounding box {bbox:?} vs reference min {:?} max {:?}",
        model.bbox_min,
        model.bbox_max
    );
    // The stray-corner warning's threshold holds on every real model.
    assert_eq!(grid.stray_corners(), None, "{file}: no corner is stray");
    assert_eq!(grid.view_box(), bbox, "{file}: views frame the whole model");
    grid
}

#[test]
fn reference_agrees_with_the_readme_table() {
    let names = [
        "reek_egrid",
        "reek_grdecl",
        "spe9_egrid",
        "spe9_grdecl",
        "emerald_hole_grdecl",
        "simpleb8_egrid",
        "simpleb8_grdecl",
        "spe10model2_data",
    ];
    for (name, (file, dims, active)) in names.iter().zip(README_TABLE) {
        let model = reference(name);
        assert_eq!(&model.file, file);
        assert_eq!(&model.dims, dims, "{file}");
        assert_eq!(&model.active, active, "{file}");
    }
}

#[test]
fn reek_egrid_corners() {
    if let Some(data) = data_dir() {
        check_model(data, "reek_egrid");
    }
}

#[test]
fn reek_grdecl_corners() {
    if let Some(data) = data_dir() {
        check_model(data, "reek_grdecl");
    }
}

#[test]
fn spe9_egrid_corners() {
    if let Some(data) = data_dir() {
        check_model(data, "spe9_egrid");
    }
}

#[test]
fn spe9_grdecl_corners() {
    if let Some(data) = data_dir() {
        check_model(data, "spe9_grdecl");
    }
}

#[test]
fn emerald_grdecl_corners() {
    if let Some(data) = data_dir() {
        check_model(data, "emerald_grdecl");
    }
}

#[test]
fn emerald_with_hole_grdecl_corners() {
    if let Some(data) = data_dir() {
        check_model(data, "emerald_hole_grdecl");
    }
}

#[test]
fn simpleb8_egrid_corners() {
    if let Some(data) = data_dir() {
        check_model(data, "simpleb8_egrid");
    }
}

#[test]
fn simpleb8_grdecl_corners() {
    if let Some(data) = data_dir() {
        check_model(data, "simpleb8_grdecl");
    }
}

/// The deck's PHI and PERM INCLUDE files are absent on purpose: read with `grid_only`
/// it must still give the whole grid, and list each missing file among its warnings.
#[test]
fn spe10model2_grid_only_corners() {
    let Some(data) = data_dir() else { return };
    let model = reference("spe10model2_data");
    let grid = check_model(data, "spe10model2_data");
    assert!(!model.missing_includes.is_empty());
    for missing in &model.missing_includes {
        let name = Path::new(missing).file_name().unwrap().to_string_lossy();
        assert!(
            grid.warnings.iter().any(|w| w.contains(name.as_ref())),
            "no warning names the missing {name}: {:?}",
            grid.warnings
        );
    }
}

/// Without `grid_only`, a missing INCLUDE is an error that names the file.
#[test]
fn spe10model2_missing_include_is_an_error() {
    let Some(data) = data_dir() else { return };
    let model = reference("spe10model2_data");
    let path = data.join(&model.file);
    let first = Path::new(&model.missing_includes[0])
        .file_name()
        .unwrap()
        .to_string_lossy()
        .into_owned();
    match strata_grid::open(&path) {
        Ok(_) => panic!("{}: read without its missing {first}", path.display()),
        Err(e) => assert!(
            e.to_string().contains(&first),
            "the error does not name {first}: {e}"
        ),
    }
}

/// Reek's EGRID and GRDECL store the same grid with mirrored local y and opposite
/// MAPAXES: read by our two readers they must agree cell by cell in map coordinates.
#[test]
fn reek_egrid_and_grdecl_agree_in_map_coordinates() {
    let Some(data) = data_dir() else { return };
    let egrid = open_grid_only(&data.join("reek/REEK.EGRID"));
    let grdecl = open_grid_only(&data.join("reek/reek_sim_grid.grdecl"));
    assert_eq!(egrid.dims(), grdecl.dims());
    assert_eq!(egrid.actnum, grdecl.actnum, "ACTNUM differs");
    let extent = egrid.bounding_box().extent();
    let worst = worst_corner(&egrid, |_, [i, j, k], c| grdecl.cell_corners(i, j, k)[c]);
    let (i, j, k, c) = worst.at;
    let message = format!(
        "Reek EGRID vs GRDECL: max corner deviation {:.6} ({:.3e} of extent {extent:.3}) at \
         cell ({i}, {j}, {k}) from 0, corner {c}: EGRID {:?}, GRDECL {:?}",
        worst.dev,
        worst.dev / extent,
        worst.ours,
        worst.theirs
    );
    assert!(worst.dev <= TOLERANCE * extent, "{message}");
    println!("{message}");
}

/// The relative difference of two values, safe at zero.
fn rel_diff(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(f64::MIN_POSITIVE)
}

/// E100_BO's restart: the report steps' numbers and dates, and every active cell's
/// PRESSURE and RS at each step (RS, unlike PRESSURE, changes between the two steps, so
/// it shows each step's own arrays are read); inactive cells must be NaN.
#[test]
fn simpleb8_report_steps_and_solution_arrays() {
    let Some(data) = data_dir() else { return };
    let model = reference("simpleb8_egrid");
    let path = data.join(&model.file);
    let grid = strata_grid::open(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let got: Vec<_> = grid
        .report_steps
        .iter()
        .map(|s| (s.number, s.date))
        .collect();
    let want: Vec<_> = model
        .report_steps
        .iter()
        .map(|s| (s.number, Some(s.date)))
        .collect();
    assert_eq!(got, want, "report steps (number, date)");
    let d = grid.dims();
    for (step, reference) in grid.report_steps.iter().zip(&model.report_steps) {
        for (name, values) in &reference.arrays {
            let array = step
                .arrays
                .get(name)
                .unwrap_or_else(|| panic!("step {}: no {name}", step.number));
            let mut active = vec![false; d.cell_count()];
            for &(cell, want) in values {
                active[cell] = true;
                let (i, j, k) = d.cell_ijk(cell);
                let ours = f64::from(array[[k, j, i]]);
                assert!(
                    rel_diff(ours, want) <= 1e-6,
                    "step {} {name} at cell ({i}, {j}, {k}): ours {ours}, resdata {want}",
                    step.number
                );
            }
            for (cell, _) in active.iter().enumerate().filter(|(_, a)| !**a) {
                let (i, j, k) = d.cell_ijk(cell);
                assert!(
                    array[[k, j, i]].is_nan(),
                    "step {} {name}: inactive cell ({i}, {j}, {k}) is not NaN",
                    step.number
                );
            }
        }
    }
}

/// BENCH_SPE9's INIT PORO: count, sum, sum of squares, range and samples at known cells.
#[test]
fn spe9_init_poro() {
    let Some(data) = data_dir() else { return };
    let model = reference("spe9_egrid");
    let want = model.init_poro.expect("reference has init_poro");
    let path = data.join(&model.file);
    let grid = strata_grid::open(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let poro = grid
        .property("PORO")
        .unwrap_or_else(|| panic!("{}: no PORO read from the INIT", path.display()));
    let values: Vec<f64> = poro
        .iter()
        .filter(|v| !v.is_nan())
        .map(|&v| f64::from(v))
        .collect();
    assert_eq!(values.len(), want.count, "PORO values over active cells");
    let sum: f64 = values.iter().sum();
    let sum_sq: f64 = values.iter().map(|v| v * v).sum();
    let min = values.iter().copied().fold(f64::INFINITY, f64::min);
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    for (what, ours, theirs) in [
        ("sum", sum, want.sum),
        ("sum of squares", sum_sq, want.sum_sq),
        ("min", min, want.min),
        ("max", max, want.max),
    ] {
        assert!(
            rel_diff(ours, theirs) <= 1e-9,
            "PORO {what}: ours {ours}, resdata {theirs}"
        );
    }
    let d = grid.dims();
    for &(cell, theirs) in &want.samples {
        let (i, j, k) = d.cell_ijk(cell);
        let ours = f64::from(poro[[k, j, i]]);
        assert!(
            rel_diff(ours, theirs) <= 1e-6,
            "PORO at ({i}, {j}, {k}): ours {ours}, resdata {theirs}"
        );
    }
}
