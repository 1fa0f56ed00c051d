//! The ROFF and Eclipse-variant files of `../shared/data` against xtgeo's and resdata's
//! readings (`scripts/make_formats_reference.py`, stored in `tests/reference/`):
//! dimensions, ACTNUM cell by cell, every cell's 8 corners within 1e-5 of the extent
//! (plus the reference's own quantization step where that is larger), zones,
//! properties (checksums, samples and code names) and report steps.
//!
//! When `../shared/data` is absent every test prints `skipping: ../shared/data not
//! found` and returns.

#[path = "common/corners.rs"]
mod corners;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use corners::{Corners, REFERENCE, gunzip};
use serde::Deserialize;
use strata_grid::CornerPointGrid;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data");

/// Corner deviation allowed, as a fraction of the model's extent.
const TOLERANCE: f64 = 1e-5;

#[derive(Deserialize)]
struct Reference {
    models: BTreeMap<String, Model>,
    strata_written: Option<Written>,
}

#[derive(Deserialize)]
struct Written {
    dims: [usize; 3],
    active: usize,
    corners_sum: f64,
}

#[derive(Deserialize)]
struct Model {
    file: String,
    dims: [usize; 3],
    cells: usize,
    active: usize,
    extent: f64,
    corners_file: String,
    actnum_file: String,
    quant_lo: [f64; 3],
    quant_hi: [f64; 3],
    quant_max_error: f64,
    zones: Option<Vec<String>>,
    /// Cells a GRID file leaves out (inactive; resdata gives them zero corners).
    #[serde(default)]
    unlisted_cells: Vec<usize>,
    /// A property file read onto the grid, as `--props` does.
    props_file: Option<String>,
    #[serde(default)]
    properties: BTreeMap<String, Summary>,
    #[serde(default)]
    report_steps: Vec<Step>,
}

#[derive(Deserialize)]
struct Summary {
    count: usize,
    sum: f64,
    min: f64,
    max: f64,
    samples: Vec<(usize, f64)>,
    codes: Option<BTreeMap<String, String>>,
}

#[derive(Deserialize)]
struct Step {
    number: i32,
    date: (i32, u32, u32),
    pressure: Summary,
}

fn data_dir() -> Option<PathBuf> {
    let dir = Path::new(DATA);
    if dir.is_dir() {
        Some(dir.to_path_buf())
    } else {
        println!("skipping: ../shared/data not found");
        None
    }
}

fn reference() -> Reference {
    let path = Path::new(REFERENCE).join("formats.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path:?}: {e}"))
}

fn open(path: &Path) -> CornerPointGrid {
    strata_grid::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-5 * scale.max(1.0)
}

/// Our values of a per-cell array against a reference summary (defined cells only).
fn check_values(what: &str, values: &[f32], want: &Summary) {
    let defined: Vec<(usize, f64)> = values
        .iter()
        .enumerate()
        .filter(|(_, v)| !v.is_nan())
        .map(|(c, &v)| (c, f64::from(v)))
        .collect();
    assert_eq!(defined.len(), want.count, "{what}: defined cells");
    let sum: f64 = defined.iter().map(|v| v.1).sum();
    let scale = want.sum.abs().max(want.max.abs());
    assert!(
        close(sum, want.sum, scale),
        "{what}: sum {sum} vs {}",
        want.sum
    );
    let min = defined.iter().map(|v| v.1).fold(f64::INFINITY, f64::min);
    let max = defined
        .iter()
        .map(|v| v.1)
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(
        close(min, want.min, want.min.abs()),
        "{what}: min {min} vs {}",
        want.min
    );
    assert!(
        close(max, want.max, want.max.abs()),
        "{what}: max {max} vs {}",
        want.max
    );
    for &(cell, v) in &want.samples {
        let ours = f64::from(values[cell]);
        assert!(
            close(ours, v, v.abs()),
            "{what}: cell {cell}: {ours} vs {v}"
        );
    }
}

/// Checks file `name` of the reference against `grid`; returns the worst deviation
/// over the extent.
fn check(name: &str, model: &Model, grid: &CornerPointGrid) -> f64 {
    let d = grid.dims();
    let file = &model.file;
    assert_eq!([d.nx, d.ny, d.nz], model.dims, "{file}: dimensions");
    assert_eq!(grid.active_count(), model.active, "{file}: active cells");
    let actnum = gunzip(&model.actnum_file);
    let act: Vec<bool> = grid.actnum.iter().copied().collect();
    assert!(
        act.iter().zip(&actnum).all(|(&a, &r)| a == (r == 1)),
        "{file}: ACTNUM"
    );
    let reference = Corners::load(
        &model.corners_file,
        model.cells,
        model.quant_lo,
        model.quant_hi,
    );
    let mut worst = 0.0f64;
    for cell in (0..model.cells).filter(|c| !model.unlisted_cells.contains(c)) {
        let (i, j, k) = d.cell_ijk(cell);
        for (c, ours) in grid.cell_corners(i, j, k).into_iter().enumerate() {
            let theirs = reference.corner(cell, c);
            let dev = (0..3)
                .map(|a| (ours[a] - theirs[a]).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!(!dev.is_nan(), "{file}: cell {cell} corner {c} is NaN");
            worst = worst.max(dev);
        }
    }
    let tol = (TOLERANCE * model.extent).max(model.quant_max_error * 1.01);
    assert!(
        worst <= tol,
        "{file}: corner deviation {worst} > {tol} (extent {})",
        model.extent
    );
    if let Some(zones) = &model.zones {
        assert_eq!(&grid.zones, zones, "{file}: zones");
    }
    for (prop, want) in &model.properties {
        let values = grid
            .property(prop)
            .unwrap_or_else(|| panic!("{file}: no {prop}"));
        let values: Vec<f32> = values.iter().copied().collect();
        // xtgeo masks inactive cells; compare over active ones.
        let masked: Vec<f32> = values
            .iter()
            .zip(&act)
            .map(|(&v, &a)| if a { v } else { f32::NAN })
            .collect();
        check_values(&format!("{file}: {prop}"), &masked, want);
        if let Some(codes) = &want.codes {
            let ours = grid
                .codes
                .get(prop)
                .unwrap_or_else(|| panic!("{file}: {prop} has no codes"));
            let ours: BTreeMap<String, String> = ours
                .iter()
                .map(|(k, v)| (k.to_string(), v.clone()))
                .collect();
            assert_eq!(&ours, codes, "{file}: {prop} code names");
        }
    }
    if !model.report_steps.is_empty() {
        assert_eq!(
            grid.report_steps.len(),
            model.report_steps.len(),
            "{file}: report steps"
        );
    }
    for (ours, want) in grid.report_steps.iter().zip(&model.report_steps) {
        assert_eq!(ours.number, want.number, "{file}: step number");
        assert_eq!(
            ours.date,
            Some(want.date),
            "{file}: step {} date",
            want.number
        );
        let p: Vec<f32> = ours.arrays["PRESSURE"].iter().copied().collect();
        check_values(
            &format!("{file}: step {} PRESSURE", want.number),
            &p,
            &want.pressure,
        );
    }
    println!(
        "{name}: {file}: worst corner {:.3e} of extent",
        worst / model.extent
    );
    worst / model.extent
}

fn check_all(prefix: &str) {
    let Some(data) = data_dir() else { return };
    let all = reference();
    let mut n = 0;
    for (name, model) in all.models.iter().filter(|(n, _)| n.starts_with(prefix)) {
        let mut grid = open(&data.join(&model.file));
        if let Some(props) = &model.props_file {
            strata_grid::read_properties(&mut grid, &data.join(props))
                .unwrap_or_else(|e| panic!("{props}: {e}"));
        }
        check(name, model, &grid);
        n += 1;
    }
    assert!(n >= 7, "{prefix}: only {n} models in the reference");
}

#[test]
fn roff_files_match_xtgeo() {
    check_all("roff_");
}

#[test]
fn eclipse_variants_match_resdata() {
    check_all("ecl_");
}

/// Reads `a` and `b` and checks they hold the same grid, bit for bit.
fn same_grid(data: &Path, a: &str, b: &str) -> (CornerPointGrid, CornerPointGrid) {
    let (ga, gb) = (open(&data.join(a)), open(&data.join(b)));
    assert_eq!(ga.dims(), gb.dims(), "{a} vs {b}: dimensions");
    assert_eq!(ga.coord, gb.coord, "{a} vs {b}: pillars");
    assert_eq!(ga.zcorn, gb.zcorn, "{a} vs {b}: corner depths");
    assert_eq!(ga.actnum, gb.actnum, "{a} vs {b}: ACTNUM");
    (ga, gb)
}

#[test]
fn roff_byte_orders_give_the_same_grid() {
    let Some(data) = data_dir() else { return };
    let (_, big) = same_grid(
        &data,
        "roff/emerald_litend.roffbin",
        "roff/emerald_bigend.roffbin",
    );
    // Only the big-endian copy carries a parameter: a discrete one with code names.
    let layer = &big.codes["LAYER"];
    assert_eq!(layer.get(&2).map(String::as_str), Some("2"), "{layer:?}");
    let values = &big.properties["LAYER"];
    assert!(
        (1..=3).all(|k| values.iter().any(|&v| v == k as f32)),
        "layers 1 to 3 present"
    );
}

#[test]
fn roff_ascii_and_binary_give_the_same_grid() {
    let Some(data) = data_dir() else { return };
    let (bin, asc) = same_grid(
        &data,
        "roff/reek_grd_w_props.roff",
        "roff/reek_grd_w_props.roffasc",
    );
    assert_eq!(
        bin.properties.keys().collect::<Vec<_>>(),
        ["EQLNUM", "FIPNUM", "PORO", "PORV"]
    );
    for (name, values) in &bin.properties {
        let other = &asc.properties[name];
        let same = values
            .iter()
            .zip(other)
            .all(|(a, b)| a == b || (a.is_nan() && b.is_nan()));
        assert!(same, "{name}: ASCII values differ from binary");
    }
    assert_eq!(bin.codes, asc.codes, "code names");
    assert_eq!(bin.codes["FIPNUM"][&2], "FIPB");
}

#[test]
fn roff_property_file_is_added_to_its_grid() {
    let Some(data) = data_dir() else { return };
    let all = reference();
    let model = &all.models["roff_b_grid"];
    let mut grid = open(&data.join("roff/b_grid.roff"));
    let names = strata_grid::read_properties(&mut grid, &data.join("roff/b_poro.roff"))
        .unwrap_or_else(|e| panic!("b_poro.roff: {e}"));
    assert_eq!(names, ["PORO"]);
    let act: Vec<bool> = grid.actnum.iter().copied().collect();
    let poro: Vec<f32> = grid.properties["PORO"]
        .iter()
        .zip(&act)
        .map(|(&v, &a)| if a { v } else { f32::NAN })
        .collect();
    check_values(
        "b_poro.roff on b_grid.roff",
        &poro,
        &model.properties["PORO"],
    );
    // Opened on its own, the property file says what it is and how to use it.
    let err = strata_grid::open(&data.join("roff/b_poro.roff")).expect_err("no geometry");
    assert!(err.to_string().contains("--props"), "{err}");
    // On a grid of other dimensions it is refused, naming both.
    let mut other = open(&data.join("roff/twocell.roff"));
    let err = strata_grid::read_properties(&mut other, &data.join("roff/b_poro.roff"))
        .expect_err("dimensions differ");
    assert!(
        err.to_string()
            .contains("20 x 15 x 8 cells, the grid has 1 x 2 x 1"),
        "{err}"
    );
}

#[test]
fn damaged_roff_gives_a_clear_error() {
    let Some(data) = data_dir() else { return };
    let path = data.join("roff/reek2_grid_w_zerolayer.roff.invalid");
    let err = strata_grid::open(&path).expect_err("damaged").to_string();
    println!("{err}");
    assert!(
        err.starts_with(&path.display().to_string()),
        "names the file: {err}"
    );
    assert!(
        err.contains("record") && err.contains("byte offset"),
        "says where: {err}"
    );
}

/// Every array and attribute of two grids equal; pillars to float32 precision.
fn assert_same(a: &CornerPointGrid, b: &CornerPointGrid, what: &str) {
    assert_eq!(a.dims(), b.dims(), "{what}");
    assert_eq!(a.zcorn, b.zcorn, "{what}: ZCORN");
    assert_eq!(a.actnum, b.actnum, "{what}: ACTNUM");
    for (p, q) in a.coord.iter().zip(&b.coord) {
        assert!(
            (p - q).abs() <= 1e-7 * p.abs().max(1e3),
            "{what}: pillar {p} vs {q}"
        );
    }
    assert_eq!(a.zones, b.zones, "{what}: zones");
    assert_eq!(a.codes, b.codes, "{what}: codes");
    assert_eq!(a.properties.len(), b.properties.len(), "{what}: properties");
    for (name, values) in &a.properties {
        let same = values
            .iter()
            .zip(&b.properties[name])
            .all(|(x, y)| x == y || (x.is_nan() && y.is_nan()));
        assert!(same, "{what}: {name}");
    }
}

#[test]
fn roff_written_by_strata_reads_back_equal() {
    let Some(data) = data_dir() else { return };
    let dir = tempfile::tempdir().expect("temp dir");
    for file in [
        "roff/reek_grd_w_props.roff",
        "roff/reek2_grid_w_zerolayer.roff",
        "roff/banal6.roff",
        "roff/emerald_bigend.roffbin",
    ] {
        let grid = open(&data.join(file));
        let out = dir.path().join("back.roff");
        strata_grid::save(&grid, &out).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_same(&grid, &open(&out), file);
    }
}

/// The synthetic grid whose ROFF xtgeo read once (`strata_written` in the reference).
fn synth() -> CornerPointGrid {
    let params = strata_grid::synth::SynthParams {
        nx: 12,
        ny: 9,
        nz: 4,
        faults: 2,
        seed: 74,
    };
    let mut grid = strata_grid::synth::generate(&params).expect("synth");
    grid.zones = ["A", "A", "B", "B"].map(String::from).to_vec();
    grid
}

#[test]
fn roff_written_by_strata_is_read_by_xtgeo() {
    let grid = synth();
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("strata_written.roff");
    strata_grid::save(&grid, &out).expect("write");
    let back = open(&out);
    let mut expected = grid.clone();
    expected.zones = ["subgrid_0", "subgrid_0", "subgrid_1", "subgrid_1"]
        .map(String::from)
        .to_vec();
    assert_same(&expected, &back, "synthetic grid");
    let written = reference()
        .strata_written
        .expect("strata_written in formats.json");
    let d = back.dims();
    assert_eq!([d.nx, d.ny, d.nz], written.dims);
    assert_eq!(back.active_count(), written.active);
    let sum: f64 = (0..d.cell_count())
        .flat_map(|c| {
            let (i, j, k) = d.cell_ijk(c);
            back.cell_corners(i, j, k)
        })
        .flatten()
        .sum();
    assert!(
        close(sum, written.corners_sum, written.corners_sum.abs()),
        "{sum} vs xtgeo's {}",
        written.corners_sum
    );
}

#[test]
fn intersect_results_are_mapped_through_pore_volume_and_said() {
    let Some(data) = data_dir() else { return };
    let grid = open(&data.join("eclipse_variants/IX_BO.EGRID"));
    assert_eq!(grid.active_count(), 23, "the EGRID's ACTNUM is kept");
    assert_eq!(grid.result_count(), 22);
    let warning = grid
        .warnings
        .iter()
        .find(|w| w.contains("mapped through PORV > 0"));
    let warning = warning.unwrap_or_else(|| panic!("no mapping warning in {:?}", grid.warnings));
    assert!(
        warning.contains("results hold 22 cells, ACTNUM has 23 active"),
        "{warning}"
    );
    assert_eq!(grid.report_steps.len(), 2, "{:?}", grid.warnings);
}

#[test]
fn result_files_opened_as_grids_are_named() {
    let Some(data) = data_dir() else { return };
    for (file, kind) in [
        ("eclipse_variants/IX_BO.INIT", "an Eclipse INIT file"),
        ("eclipse_variants/E300_BO.UNRST", "an Eclipse restart file"),
        ("eclipse_variants/E100_BO.FINIT", "an Eclipse INIT file"),
    ] {
        let err = strata_grid::open(&data.join(file))
            .expect_err("not a grid")
            .to_string();
        assert!(err.contains(kind), "{file}: {err}");
    }
}
