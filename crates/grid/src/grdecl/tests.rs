//! Reader and writer tests over whole decks: syntax, errors, INCLUDE, DATA decks,
//! block-centred input, round trips and the real models in `../shared/data`.

use std::path::{Path, PathBuf};

use super::{parse_bytes, read, write};
use crate::synth::{SynthParams, generate};
use crate::{CornerPointGrid, Error, MapAxes, ReadOptions, Units};

const GRID_ONLY: ReadOptions = ReadOptions {
    grid_only: true,
    load_results: false,
};

fn parse(text: &str) -> crate::Result<CornerPointGrid> {
    parse_bytes(
        Path::new("mem/deck.grdecl"),
        text.as_bytes(),
        &ReadOptions::default(),
    )
}

fn error(text: &str) -> String {
    match parse(text) {
        Ok(_) => panic!("deck parsed but should not:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// Asserts that an error names the file, line and keyword, and says `what`.
fn assert_error(text: &str, line: usize, keyword: &str, what: &str) {
    let e = error(text);
    let head = format!("mem/deck.grdecl:{line}: keyword {keyword}: ");
    assert!(
        e.starts_with(&head) && e.contains(what),
        "got: {e}\nwant: {head}...{what}"
    );
}

/// A fresh scratch folder for tests that need files, removed when dropped.
fn scratch(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("strata-grdecl-{name}-"))
        .tempdir()
        .unwrap()
}

/// Pillars of a 2 x 1 grid of unit columns, vertical, x = 0, 1, 2.
const COORD_2X1: &str = "COORD
 0 0 0  0 0 10   1 0 0  1 0 10   2 0 0  2 0 10
 0 1 0  0 1 10   1 1 0  1 1 10   2 1 0  2 1 10 /
";

/// A complete 2 x 1 x 1 corner-point deck (the cells span depths 100 to 101).
fn deck_2x1(extra: &str) -> String {
    format!("SPECGRID\n 2 1 1 1 F /\n{COORD_2X1}ZCORN\n 8*100 8*101 /\n{extra}")
}

#[test]
fn syntax_features() {
    let text = "NOECHO
-- a comment / with a slash
MAPUNITS
  'METRES  ' /
MAPAXES
 0.0 1.0D+02, 0 0
 100 0 /
GRIDUNIT
'FEET    ' '        ' /
specgrid
  2 1 1 1 F /
GDORIENT
INC INC INC DOWN LEFT /
COORDSYS
 1 1 'INCOMP' /
COORD -- data after a comment
 0 0 0  0 0 10   1 0 0  1 0 10   2,0,0,2,0,10
 0 1 0  0 1 10   1 1 0  1 1 10   2 1 0  2 1 10/
ZCORN
 4*1.0E2 4*100.0 -- 8 tops
 8*1.01d2/
ACTNUM
 0 1* /
PORO
 1* 0.25 /
FACIES 2*3 /
ECHO
";
    let g = parse(text).unwrap();
    assert_eq!(g.units, Units::Feet);
    assert_eq!(
        g.mapaxes,
        Some(MapAxes::from_values([0.0, 100.0, 0.0, 0.0, 100.0, 0.0]))
    );
    assert_eq!(g.coord[[0, 2, 3]], 2.0);
    assert!(g.zcorn.iter().take(8).all(|&z| z == 100.0));
    assert!(g.zcorn.iter().skip(8).all(|&z| z == 101.0));
    assert_eq!(g.active_count(), 1);
    assert!(!g.is_active(0, 0, 0) && g.is_active(1, 0, 0));
    let poro = g.property("PORO").unwrap();
    assert!(poro[[0, 0, 0]].is_nan() && poro[[0, 0, 1]] == 0.25);
    assert_eq!(g.property("FACIES").unwrap()[[0, 0, 1]], 3.0);
    assert!(g.warnings.is_empty());
}

#[test]
fn only_data_with_one_value_per_cell_is_a_property() {
    let g = parse(&deck_2x1(
        "MESSAGES\n 3* 100 5* 100 /\nFIPNUM\n 1 2 /\nMULTFLT\n F1 0.5 /\n 'F2' 1 /\n/\n\
         FAULTS\n 'F1' 1 1 1 1 1 1 I /\n/\nNOTES\n 'a' 1 2 /\n",
    ))
    .unwrap();
    let names: Vec<&String> = g.properties.keys().collect();
    assert_eq!(names, ["FIPNUM"]);
}

#[test]
fn grid_only_skips_properties() {
    let text = deck_2x1("PORO\n 0.1 0.2 /\nFOO\n 1 2 /\n");
    let g = parse_bytes(Path::new("d.grdecl"), text.as_bytes(), &GRID_ONLY).unwrap();
    assert!(g.properties.is_empty());
    assert_eq!(g.cell_count(), 2);
}

#[test]
fn syntax_errors_name_file_keyword_and_line() {
    assert_error(
        &deck_2x1("PORO\n 0.1\n 0.x2 /\n"),
        10,
        "PORO",
        "'0.x2' is not a number",
    );
    assert_error(
        &deck_2x1("PORO\n 0.1 \u{00ff}\u{00fe} /\n"),
        9,
        "PORO",
        "is not a number",
    );
    assert_error(
        "SPECGRID\n 2 1 1 /\nCOORD\n 0 0 0 0 0 nan 1 0 0 1 0 10 /",
        4,
        "COORD",
        "'nan' is not a finite number",
    );
    assert_error(
        "SPECGRID\n 2 1 1 /\nZCORN\n 99999999999999999999999*1 /",
        4,
        "ZCORN",
        "too large",
    );
    assert_error(
        "SPECGRID\n 2 1 1 /\nZCORN\n 17*1 /",
        4,
        "ZCORN",
        "more values than the 16",
    );
    assert_error(
        &deck_2x1("PORO\n 1 2 3\n"),
        8,
        "PORO",
        "not terminated by '/'",
    );
    assert_error(
        &format!("SPECGRID\n 2 1 1 1 F /\n{COORD_2X1}\n\nZCORN\n 15*100 /\n"),
        8,
        "ZCORN",
        "has 15 values, the grid needs 16",
    );
    assert_error(
        &deck_2x1("PORO\n 0.1 0.2 0.3 /\n"),
        8,
        "PORO",
        "has 3 values, the grid needs 2",
    );
    assert_error(
        "SPECGRID\n 1000000000 1000000000 1 1 F /\nZCORN\n 1 /",
        1,
        "SPECGRID",
        "more than a deck of",
    );
    assert_error(
        "SPECGRID\n 4611686018427387904 4 1 /",
        1,
        "SPECGRID",
        "overflow",
    );
    assert_error(
        "SPECGRID\n 2 x 1 /",
        2,
        "SPECGRID",
        "'x' is not a positive integer",
    );
    assert_error(
        "SPECGRID\n 2 1 1\nCOORD\n 1 2 3 4 5 6 7 8 /",
        1,
        "SPECGRID",
        "is the '/' missing?",
    );
    assert_error("COORD\n 1 2 3 /", 1, "COORD", "before SPECGRID");
    assert_error(
        &deck_2x1("\u{00ff}garbage\n"),
        8,
        "ZCORN",
        "is not a keyword after the data of ZCORN",
    );
    assert_error(&deck_2x1("/\n"), 8, "ZCORN", "'/' is not a keyword");
    assert_error(
        &deck_2x1("GRIDUNIT\n 'PARSECS' /"),
        8,
        "GRIDUNIT",
        "unknown unit",
    );
    assert_error(
        &deck_2x1("MAPAXES\n 1 2 3 4 5 /"),
        8,
        "MAPAXES",
        "has 5 values",
    );
    assert_error(
        &deck_2x1("GRIDUNIT\n 'METRES /"),
        9,
        "GRIDUNIT",
        "unterminated",
    );
}

#[test]
fn bytes_that_are_not_utf8_do_not_crash() {
    let mut text = deck_2x1("").into_bytes();
    text.extend_from_slice(b"-- \xff\xfe comment\nPORO\n 2*0.5 -- \x80\n/\n");
    let g = parse_bytes(Path::new("x"), &text, &ReadOptions::default()).unwrap();
    assert_eq!(g.property("PORO").unwrap()[[0, 0, 1]], 0.5);
    let e = parse_bytes(Path::new("x"), b"\xff\xfe\x00", &ReadOptions::default());
    let said = e.unwrap_err().to_string();
    assert!(said.contains("x: binary data (byte 2 is zero)"), "{said}");
}

#[test]
fn missing_geometry_is_a_model_error() {
    let e = parse("NOECHO\n").unwrap_err();
    assert!(
        matches!(e, Error::Model { ref keyword, .. } if keyword == "SPECGRID"),
        "{e}"
    );
    let e = parse(&format!("SPECGRID\n 2 1 1 /\n{COORD_2X1}")).unwrap_err();
    assert!(
        matches!(e, Error::Model { ref keyword, .. } if keyword == "ZCORN"),
        "{e}"
    );
    assert!(e.to_string().contains("no ZCORN"));
    let e = parse("SPECGRID\n 2 1 1 /\nZCORN\n 16*1 /").unwrap_err();
    assert!(e.to_string().contains("no COORD"), "{e}");
}

#[test]
fn includes_resolve_from_the_root_folder() {
    let dir = scratch("include");
    std::fs::create_dir_all(dir.path().join("sub")).unwrap();
    std::fs::write(dir.path().join("sub/coord.inc"), COORD_2X1).unwrap();
    // Included from sub/, but named relative to the root deck's folder.
    std::fs::write(
        dir.path().join("sub/grid.inc"),
        "INCLUDE\n sub/coord.inc /\nINCLUDE\n'z.inc'/\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("z.inc"), "ZCORN\n 16*5 /\n").unwrap();
    std::fs::write(
        dir.path().join("root.grdecl"),
        "SPECGRID\n 2 1 1 /\nINCLUDE\n  'sub/grid.inc'  -- the grid\n/\n",
    )
    .unwrap();
    let g = read(&dir.path().join("root.grdecl"), &ReadOptions::default()).unwrap();
    assert_eq!(g.zcorn[[1, 1, 3]], 5.0);
    assert_eq!(g.coord[[1, 2, 0]], 2.0);

    // In memory, includes resolve from the folder of the path given.
    let g = parse_bytes(
        &dir.path().join("virtual.grdecl"),
        b"SPECGRID\n 2 1 1 /\nINCLUDE\n 'sub/grid.inc' /",
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(g.cell_count(), 2);
}

#[test]
fn include_cycles_are_refused() {
    let dir = scratch("cycle");
    std::fs::write(dir.path().join("a.inc"), "NOECHO\nINCLUDE\n 'b.inc' /\n").unwrap();
    std::fs::write(dir.path().join("b.inc"), "\n\nINCLUDE\n 'a.inc' /\n").unwrap();
    std::fs::write(dir.path().join("self.inc"), "INCLUDE\n 'self.inc' /\n").unwrap();
    std::fs::write(dir.path().join("root.grdecl"), "INCLUDE\n 'a.inc' /\n").unwrap();
    let e = read(&dir.path().join("root.grdecl"), &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("b.inc:3: keyword INCLUDE: include cycle"), "{e}");
    assert!(e.contains("a.inc -> ") && e.ends_with("a.inc"), "{e}");
    let e = read(&dir.path().join("self.inc"), &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("self.inc:1: keyword INCLUDE: include cycle"),
        "{e}"
    );
    // Reading the same file twice is not a cycle.
    std::fs::write(dir.path().join("n.inc"), "NOECHO\n").unwrap();
    std::fs::write(
        dir.path().join("twice.grdecl"),
        format!("INCLUDE\n 'n.inc' /\nINCLUDE\n 'n.inc' /\n{}", deck_2x1("")),
    )
    .unwrap();
    assert!(read(&dir.path().join("twice.grdecl"), &ReadOptions::default()).is_ok());
}

#[test]
fn missing_include_is_an_error_unless_grid_only() {
    let dir = scratch("missing");
    let root = dir.path().join("root.grdecl");
    std::fs::write(&root, deck_2x1("\nINCLUDE\n 'poro.inc' /\nNTG\n 2*1 /\n")).unwrap();
    let e = read(&root, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("root.grdecl:9: keyword INCLUDE: cannot read"),
        "{e}"
    );
    assert!(e.contains("poro.inc"), "{e}");
    let g = read(&root, &GRID_ONLY).unwrap();
    assert_eq!(g.warnings.len(), 1);
    assert!(g.warnings[0].contains("root.grdecl:9: INCLUDE") && g.warnings[0].contains("poro.inc"));
    assert!(g.properties.is_empty());
    let e = parse(&deck_2x1("INCLUDE\n 'x.inc'\nNTG\n"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("not followed by '/'"), "{e}");
    // A directory is not a file to include.
    let e = read(&dir.path().join("r2.grdecl"), &ReadOptions::default());
    assert!(e.is_err());
    std::fs::create_dir_all(dir.path().join("d.inc")).unwrap();
    std::fs::write(dir.path().join("r2.grdecl"), "INCLUDE\n 'd.inc' /\n").unwrap();
    let e = read(&dir.path().join("r2.grdecl"), &ReadOptions::default()).unwrap_err();
    assert!(e.to_string().contains("not a regular file"), "{e}");
}

#[test]
fn block_centred_deck_becomes_corner_point() {
    let text = "DIMENS
 2 1 2 /
DX
 10 20 /
DY
 4*5 /
DZ
 2*1 1* 3 /
TOPS
 100 101 /
PORO
 4*0.2 /
";
    let g = parse(text).unwrap();
    // Cell (2,1,2) (1-based): x from 10 to 30, y 0 to 5; its top is where the
    // layer above ends (101 + 1).
    let c = g.cell_corners(1, 0, 1);
    assert_eq!(c[0], [10.0, 0.0, 102.0]);
    assert_eq!(c[3], [30.0, 5.0, 102.0]);
    assert_eq!(c[7], [30.0, 5.0, 105.0]);
    // Cell (1,1,2): its defaulted DZ is the layer above's.
    let c = g.cell_corners(0, 0, 1);
    assert_eq!(c[4], [0.0, 0.0, 102.0]);
    assert!(g.properties.contains_key("PORO") && !g.properties.contains_key("DX"));

    let e = parse("DIMENS\n 2 1 2 /\nDX\n 3*10 /\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("keyword DX: has 3 values, the grid needs 4"),
        "{e}"
    );
    let e = parse("DIMENS\n 2 1 1 /\nDX\n 2*10 /\nDY\n 2*1 /\nDZ\n 2*1 /\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("keyword TOPS: no TOPS"), "{e}");
}

/// Pillar positions are running sums: a grid a few hundred thousand cells wide
/// converts at once (summing each pillar's row from scratch would take minutes).
#[test]
fn wide_block_centred_grid_converts_in_linear_time() {
    let n = 300_000;
    let text =
        format!("DIMENS\n {n} 1 1 /\nDX\n {n}*2 /\nDY\n {n}*1 /\nDZ\n {n}*1 /\nTOPS\n {n}*0 /\n");
    let g = parse(&text).unwrap();
    assert_eq!(g.cell_corners(n - 1, 0, 0)[7], [2.0 * n as f64, 1.0, 1.0]);
}

#[test]
fn boxes_and_edits() {
    let text = "DIMENS
 2 2 1 /
DXV
 2*10 /
DYV
 1.5D1 5 /
DZV
 2 /
EQUALS
 'TOPS' 1000 /
 PORO 0.1 /
 'PORO' 0.25 2 2 1* 1* 1 1 /
/
BOX
 1 1 1 2 1 1 /
NTG
 0.5 0.6 /
ENDBOX
MULTIPLY
 'PORO' 2 1 1 /
/
ADD
 PORO 1 2 2 2 2 /
/
COPY
 'PORO' 'PERMX' /
/
EQUALS
 'ACTNUM' 0 2 2 2 2 /
/
";
    let g = parse(text).unwrap();
    let poro = g.property("PORO").unwrap();
    assert_eq!(poro.as_slice().unwrap(), &[0.2, 0.25, 0.2, 1.25]);
    assert_eq!(g.property("PERMX").unwrap(), poro);
    let ntg = g.property("NTG").unwrap();
    assert!(ntg[[0, 0, 0]] == 0.5 && ntg[[0, 1, 0]] == 0.6 && ntg[[0, 0, 1]].is_nan());
    assert_eq!(g.active_count(), 3);
    assert_eq!(g.cell_corners(1, 1, 0)[7], [20.0, 20.0, 1002.0]);

    assert_error(
        "DIMENS\n 2 2 1 /\nEQUALS\n 'PORO' 1 3 3 /\n/\n",
        3,
        "EQUALS",
        "box I3..3 is not within 1..2",
    );
    assert_error(
        "DIMENS\n 2 2 1 /\nMULTIPLY\n 'PORO' 1 /\n/\n",
        3,
        "MULTIPLY",
        "PORO is not defined",
    );
    assert_error(
        "DIMENS\n 2 2 1 /\nEQUALS\n 'PORO' 1 /\n",
        3,
        "EQUALS",
        "not terminated",
    );
    assert_error(
        "DIMENS\n 2 2 1 /\nBOX\n 1 1 1 1 1 1 /\nPORO\n 1 1 1 1 /",
        5,
        "PORO",
        "the grid's BOX needs 1",
    );
}

#[test]
fn data_deck_sections() {
    let text = "RUNSPEC
TITLE
 DIMENS OF A TEST -- not the keyword
DIMENS
 2 1 1 /
METRIC
START
 1 JAN 2000 /
EQLDIMS
/
GRID ==================
INIT
INCLUDE
 'coord.inc' /
ZCORN
 16*10 /
PROPS
SWOF
 0.2 0 1 0
 1.0 1 0 0 /
PORO
 0.1 0.2 /
REGIONS
SATNUM
 2*1 /
SOLUTION
EQUIL
 100 200 /
SCHEDULE
INCLUDE
 'missing-schedule.inc' /
TUNING
/
/
2* 300 1* 12 /
WELSPECS
'P1' 'G1' 1 1 1* 'OIL' /
/
COMPDAT
 P1 1 1 1 1 OPEN 2* 2 /
/
DATES
 1 'FEB' 2000 /
/
END
ZCORN
 garbage after END
";
    let dir = scratch("data");
    std::fs::write(dir.path().join("coord.inc"), COORD_2X1).unwrap();
    std::fs::write(dir.path().join("CASE.DATA"), text).unwrap();
    let g = read(&dir.path().join("CASE.DATA"), &ReadOptions::default()).unwrap();
    assert_eq!(g.cell_count(), 2);
    assert_eq!(g.units, Units::Metres);
    assert_eq!(g.zcorn[[0, 0, 0]], 10.0);
    let names: Vec<&String> = g.properties.keys().collect();
    assert_eq!(names, ["PORO"]);
    assert!(g.warnings.is_empty());

    let field = text.replace("METRIC", "FIELD");
    std::fs::write(dir.path().join("FIELD.DATA"), field).unwrap();
    let g = read(&dir.path().join("FIELD.DATA"), &ReadOptions::default()).unwrap();
    assert_eq!(g.units, Units::Feet);
}

/// Writes a generated model and reads it back: every array identical.
#[test]
fn round_trip_is_exact() {
    let mut g = generate(&SynthParams {
        nx: 13,
        ny: 7,
        nz: 5,
        faults: 3,
        seed: 11,
    })
    .unwrap();
    g.mapaxes = Some(MapAxes::from_values([0.5, 1e6, 0.1, 0.2, 3e5, -0.125]));
    g.units = Units::Feet;
    let mut odd = g.property("PORO").unwrap().clone();
    odd[[0, 0, 0]] = f32::NAN;
    odd[[0, 0, 1]] = f32::NAN;
    odd[[1, 0, 0]] = 1e-30;
    odd[[1, 0, 1]] = -3.4e38;
    odd[[1, 0, 2]] = f32::MIN_POSITIVE;
    odd[[1, 0, 3]] = -0.0;
    odd[[0, 0, 2]] = f32::NEG_INFINITY;
    odd[[1, 0, 4]] = f32::INFINITY;
    g.set_property("ODD", odd).unwrap();
    // A property whose first value is infinite must still look like numeric data.
    let mut inf = g.property("PORO").unwrap().clone();
    inf[[0, 0, 0]] = f32::INFINITY;
    g.set_property("INF", inf).unwrap();
    g.coord[[0, 0, 0]] = 0.1 + 0.2;
    let dir = scratch("roundtrip");
    let path = dir.path().join("model.grdecl");
    write(&g, &path).unwrap();
    let back = read(&path, &ReadOptions::default()).unwrap();
    assert_eq!(back.dims(), g.dims());
    assert_eq!(back.coord, g.coord);
    assert_eq!(back.zcorn, g.zcorn);
    assert_eq!(back.actnum, g.actnum);
    assert_eq!(back.mapaxes, g.mapaxes);
    assert_eq!(back.units, g.units);
    assert_eq!(back.properties.len(), g.properties.len());
    for (name, a) in &g.properties {
        let b = &back.properties[name];
        let same = a
            .iter()
            .zip(b)
            .all(|(x, y)| x.to_bits() == y.to_bits() || x.is_nan() && y.is_nan());
        assert!(same, "{name} differs");
    }
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.lines().all(|l| l.len() <= 132));
    assert!(text.contains("SPECGRID\n  13 7 5 1 F /"));

    let mut bad = g.clone();
    bad.set_property("TOO_LONG_NAME", g.property("PORO").unwrap().clone())
        .unwrap();
    let e = write(&bad, &dir.path().join("bad.grdecl")).unwrap_err();
    assert!(e.to_string().contains("TOO_LONG_NAME"), "{e}");
    for name in ["ZCORN", "A--B", "FAULTS", "GRID"] {
        let mut bad = g.clone();
        bad.properties.clear();
        bad.set_property(name, g.property("PORO").unwrap().clone())
            .unwrap();
        assert!(
            write(&bad, &dir.path().join("bad.grdecl")).is_err(),
            "{name}"
        );
    }
}

/// The models in `../shared/data`, or `None` (with a message) when it is absent.
fn shared_data() -> Option<PathBuf> {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"));
    if dir.is_dir() {
        Some(dir)
    } else {
        println!("skipping: ../shared/data not found");
        None
    }
}

#[test]
fn spe10_block_centred_data_deck() {
    let Some(data) = shared_data() else { return };
    let path = data.join("spe10model2/SPE10_MODEL2.DATA");
    let g = read(&path, &GRID_ONLY).unwrap();
    let d = g.dims();
    assert_eq!((d.nx, d.ny, d.nz), (60, 220, 85));
    assert_eq!(g.active_count(), 1_122_000);
    assert_eq!(g.units, Units::Feet);
    assert_eq!(g.warnings.len(), 2, "{:?}", g.warnings);
    assert!(g.warnings[0].contains("SPE10MODEL2_PHI.INC"));
    assert!(g.warnings[1].contains("SPE10MODEL2_PERM.INC"));
    assert_eq!(g.cell_corners(0, 0, 0)[0], [0.0, 0.0, 12000.0]);
    assert_eq!(g.cell_corners(59, 219, 84)[7], [1200.0, 2200.0, 12170.0]);

    let e = read(&path, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("SPE10_MODEL2.DATA:91: keyword INCLUDE: cannot read")
            && e.contains("SPE10MODEL2_PHI.INC"),
        "{e}"
    );
}

#[test]
fn real_grdecl_files() {
    let Some(data) = shared_data() else { return };
    let cases = [
        ("reek/reek_sim_grid.grdecl", (40, 64, 14), 35_838),
        ("spe9/xtgeo_SPE9.GRDECL", (24, 25, 15), 9_000),
        ("simpleb8/simpleb8.grdecl", (4, 2, 3), 22),
        ("emerald/emerald.grdecl", (4, 4, 3), 48),
        (
            "emerald/eme_small_w_hole_grid_params.grdecl",
            (21, 41, 18),
            7_157,
        ),
    ];
    for (file, (nx, ny, nz), active) in cases {
        let g = read(&data.join(file), &ReadOptions::default()).unwrap();
        let d = g.dims();
        assert_eq!((d.nx, d.ny, d.nz), (nx, ny, nz), "{file}");
        assert_eq!(g.active_count(), active, "{file}");
    }
    let g = read(
        &data.join("reek/reek_sim_grid.grdecl"),
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(g.units, Units::Metres);
    assert_eq!(g.mapaxes.unwrap().origin, [456510.625, 5926880.172]);
    assert_eq!(g.coord[[0, 0, 0]], 0.448);
    // The first two corners of cell (1,1,1) in map coordinates, as xtgeo 4.27 gives
    // them (`get_xyz_corners`) for the same file.
    let c = g.cell_corners(0, 0, 0);
    let xtgeo = [
        [456511.073, 5935688.224, 1726.187],
        [456651.256, 5935769.156, 1726.715],
    ];
    for (got, want) in c.iter().zip(xtgeo) {
        assert!(
            (0..3).all(|a| (got[a] - want[a]).abs() < 2e-3),
            "{got:?} vs {want:?}"
        );
    }
    let g = read(
        &data.join("emerald/eme_small_w_hole_grid_params.grdecl"),
        &ReadOptions::default(),
    )
    .unwrap();
    let names: Vec<&String> = g.properties.keys().collect();
    assert_eq!(names, ["FACIES", "PORO"]);
}

/// A property deck beside a grid of more cells than any deck may allocate from its
/// text alone (2^26 values) fills the grid however briefly it is written, and still
/// refuses a repeat beyond the grid's cells.
#[test]
fn a_brief_property_deck_fills_a_large_grid() {
    let dims = crate::Dims {
        nx: 9000,
        ny: 8000,
        nz: 1,
    };
    let path = Path::new("mem/poro.grdecl");
    let arrays =
        super::deck::parse_properties(path, b"PORO\n72000000*0.25 /\n", Default::default(), dims)
            .expect("a deck for 72 million cells");
    let poro = &arrays["PORO"];
    assert_eq!(poro.len(), 72_000_000);
    assert!(poro.iter().all(|&v| v == 0.25));
    let err =
        super::deck::parse_properties(path, b"PORO\n72000001*0.25 /\n", Default::default(), dims)
            .expect_err("one value too many")
            .to_string();
    assert!(
        err.contains("mem/poro.grdecl") && err.contains("PORO"),
        "{err}"
    );
}
