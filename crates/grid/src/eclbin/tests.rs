use std::path::{Path, PathBuf};

use ndarray::Array3;

use super::*;
use crate::{Dims, Error, MapAxes, ReportStep, Units};

fn shared_data() -> Option<PathBuf> {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"));
    if dir.is_dir() {
        Some(dir.to_path_buf())
    } else {
        println!("skipping: ../shared/data not found");
        None
    }
}

/// A scratch directory removed when dropped.
struct Scratch(tempfile::TempDir);

impl Scratch {
    fn new(tag: &str) -> Self {
        let dir = tempfile::Builder::new()
            .prefix(&format!("strata-eclbin-{tag}-"))
            .tempdir()
            .unwrap();
        Scratch(dir)
    }

    fn path(&self, name: &str) -> PathBuf {
        self.0.path().join(name)
    }
}

/// A 3 x 2 x 2 grid with leaning pillars, a fault, one inactive cell, map axes and feet.
fn small_grid() -> CornerPointGrid {
    let dims = Dims::new(3, 2, 2).unwrap();
    let mut coord = Vec::new();
    for j in 0..3 {
        for i in 0..4 {
            let (x, y) = (i as f64 * 100.0, j as f64 * 50.0);
            coord.extend([x, y, 1000.0, x + 7.5, y - 2.5, 1100.0]);
        }
    }
    let mut zcorn = Vec::new();
    for z in 0..4 {
        for _ in 0..4 {
            for x in 0..6 {
                let throw = if x >= 4 { 3.25 } else { 0.0 };
                zcorn.push(1010.0 + 10.0 * ((z + 1) / 2) as f32 + throw + 0.5 * x as f32);
            }
        }
    }
    let mut actnum = vec![true; 12];
    actnum[4] = false;
    let mut g = CornerPointGrid::from_arrays(dims, coord, zcorn, Some(actnum)).unwrap();
    g.mapaxes = Some(MapAxes::from_values([
        456000.0, 5930000.0, 456000.0, 5929000.0, 457000.0, 5929000.0,
    ]));
    g.units = Units::Feet;
    g
}

/// An array over all cells of `g`, NaN at inactive cells, so it survives an
/// active-cell round trip unchanged.
fn active_field(g: &CornerPointGrid, f: impl Fn(usize) -> f32) -> Array3<f32> {
    let d = g.dims();
    let mut n = 0;
    Array3::from_shape_fn((d.nz, d.ny, d.nx), |(k, j, i)| {
        n += 1;
        if g.is_active(i, j, k) { f(n) } else { f32::NAN }
    })
}

/// Equal, NaN matching NaN.
fn same(a: &Array3<f32>, b: &Array3<f32>) -> bool {
    a.dim() == b.dim()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x == y || (x.is_nan() && y.is_nan()))
}

/// The payload lengths of the Fortran records of `bytes`, read independently of
/// the reader under test.
fn fortran_lengths(bytes: &[u8]) -> Vec<usize> {
    let mut out = Vec::new();
    let mut pos = 0;
    while pos < bytes.len() {
        let n = i32::from_be_bytes(bytes[pos..pos + 4].try_into().unwrap()) as usize;
        out.push(n);
        pos += n + 8;
    }
    out
}

fn written(tag: &str, write: impl FnOnce(&mut RecordWriter<Vec<u8>>)) -> Vec<u8> {
    let mut w = RecordWriter::new(Vec::new(), tag);
    write(&mut w);
    w.finish().unwrap()
}

#[test]
fn every_item_type_round_trips_with_eclipse_block_sizes() {
    let records = vec![
        Record::new(
            "INTS",
            RecordData::Inte((0..2500).map(|i| i * 7 - 900).collect()),
        ),
        Record::new(
            "REALS",
            RecordData::Real((0..1000).map(|i| i as f32 * 0.25).collect()),
        ),
        Record::new(
            "DOUBS",
            RecordData::Doub((0..1001).map(|i| i as f64 / 3.0).collect()),
        ),
        Record::new(
            "LOGIS",
            RecordData::Logi((0..7).map(|i| i % 3 == 0).collect()),
        ),
        Record::new(
            "CHARS",
            RecordData::Char((0..230).map(|i| format!("W{i}")).collect()),
        ),
        Record::new(
            "LONGNAME",
            RecordData::C0nn {
                width: 12,
                values: (0..106).map(|i| format!("WELL-{i:06}")).collect(),
            },
        ),
        Record::new("STARTSOL", RecordData::Mess),
        Record::new("EMPTY", RecordData::Inte(vec![])),
    ];
    let bytes = written("mem", |w| {
        for r in &records {
            w.write(r).unwrap();
        }
    });
    assert_eq!(
        fortran_lengths(&bytes),
        [
            16, 4000, 4000, 2000, // INTE 2500: 1000 + 1000 + 500
            16, 4000, // REAL 1000 fits one record
            16, 8000, 8, // DOUB 1001: 1000 + 1
            16, 28, // LOGI 7
            16, 840, 840, 160, // CHAR 230: 105 + 105 + 20, 8 bytes each
            16, 1260, 12, // C012 106: 105 + 1, 12 bytes each
            16, // MESS
            16  // empty INTE: no data record
        ]
    );
    // Eclipse writes -1 for true.
    let logi = bytes.windows(5).position(|w| w == b"LOGIS").unwrap();
    assert_eq!(&bytes[logi + 24..logi + 28], &[0xff; 4]);
    assert_eq!(&bytes[logi + 28..logi + 32], &[0; 4]);
    assert_eq!(parse_records(Path::new("mem"), &bytes).unwrap(), records);
}

#[test]
fn logicals_read_any_non_zero_as_true() {
    let mut bytes = written("mem", |w| w.inte("FLAGS", &[0, 1, -1, 7]).unwrap());
    bytes[16..20].copy_from_slice(b"LOGI");
    let r = parse_records(Path::new("mem"), &bytes).unwrap();
    assert_eq!(r[0].data, RecordData::Logi(vec![false, true, true, true]));
}

#[test]
fn writer_refuses_what_cannot_be_read_back() {
    let mut w = RecordWriter::new(Vec::new(), "out.EGRID");
    let e = w.real("TOOLONGNAME", &[1.0]).unwrap_err().to_string();
    assert!(e.contains("out.EGRID") && e.contains("TOOLONGNAME"), "{e}");
    let e = w
        .strings("NAMES", RecordKind::Char, &["NINECHARS"])
        .unwrap_err();
    assert!(e.to_string().contains("at most 8"), "{e}");
}

/// Offset of the header of the first keyword `name` in `bytes`.
fn header_at(bytes: &[u8], name: &str) -> usize {
    Records::new(Path::new("x"), bytes)
        .map(Result::unwrap)
        .find(|v| v.name() == name)
        .unwrap()
        .offset() as usize
}

fn egrid_bytes(g: &CornerPointGrid) -> Vec<u8> {
    let dir = Scratch::new("bytes");
    let path = dir.path("G.EGRID");
    write_egrid(g, &path).unwrap();
    std::fs::read(path).unwrap()
}

fn parse_err(bytes: &[u8]) -> String {
    parse_egrid_bytes(Path::new("bad/CASE.EGRID"), bytes, &ReadOptions::default())
        .unwrap_err()
        .to_string()
}

/// The keyword number of `name` in a file written by `write_egrid` for `small_grid`:
/// FILEHEAD MAPUNITS MAPAXES GRIDUNIT GRIDHEAD COORD ZCORN ACTNUM ENDGRID.
fn number_of(name: &str) -> usize {
    [
        "FILEHEAD", "MAPUNITS", "MAPAXES", "GRIDUNIT", "GRIDHEAD", "COORD", "ZCORN", "ACTNUM",
        "ENDGRID",
    ]
    .iter()
    .position(|n| *n == name)
    .unwrap()
        + 1
}

fn assert_names(msg: &str, keyword: &str) {
    let want = format!(
        "bad/CASE.EGRID: record {} (keyword {keyword},",
        number_of(keyword)
    );
    assert!(msg.starts_with(&want), "{msg:?} should start with {want:?}");
}

#[test]
fn egrid_round_trips() {
    let g = small_grid();
    let bytes = egrid_bytes(&g);
    let r = parse_egrid_bytes(Path::new("G.EGRID"), &bytes, &ReadOptions::default()).unwrap();
    assert_eq!(r.dims(), g.dims());
    assert_eq!(r.coord, g.coord);
    assert_eq!(r.zcorn, g.zcorn);
    assert_eq!(r.actnum, g.actnum);
    assert_eq!(r.units, Units::Feet);
    assert_eq!(r.mapaxes, g.mapaxes);
    assert_eq!(r.active_count(), 11);
    let names: Vec<_> = Records::new(Path::new("G"), &bytes)
        .map(|v| v.unwrap().name().to_string())
        .collect();
    assert_eq!(
        names,
        [
            "FILEHEAD", "MAPUNITS", "MAPAXES", "GRIDUNIT", "GRIDHEAD", "COORD", "ZCORN", "ACTNUM",
            "ENDGRID"
        ]
    );
}

#[test]
fn truncated_file_names_file_record_and_keyword() {
    let bytes = egrid_bytes(&small_grid());
    let zcorn = header_at(&bytes, "ZCORN");
    // Too short for the 96 values the header announces: refused before reading on.
    let msg = parse_err(&bytes[..zcorn + 24 + 100]);
    assert_names(&msg, "ZCORN");
    assert!(msg.contains(&format!("byte offset {zcorn})")), "{msg}");
    assert!(
        msg.contains("header announces 96 REAL items (384 bytes), only 100 bytes follow"),
        "{msg}"
    );
    // Long enough for the values but not for the trailing marker.
    let msg = parse_err(&bytes[..zcorn + 24 + 4 + 384 + 2]);
    assert_names(&msg, "ZCORN");
    assert!(
        msg.contains(&format!("byte offset {})", zcorn + 24)),
        "{msg}"
    );
    assert!(
        msg.contains("record of 384 bytes runs past the end of the file (390 bytes left)"),
        "{msg}"
    );
}

#[test]
fn disagreeing_markers_are_refused() {
    let mut bytes = egrid_bytes(&small_grid());
    let coord = header_at(&bytes, "COORD");
    // Trailing marker of COORD's only data record (72 values).
    let end = coord + 24 + 4 + 72 * 4;
    bytes[end..end + 4].copy_from_slice(&71i32.to_be_bytes());
    let msg = parse_err(&bytes);
    assert_names(&msg, "COORD");
    assert!(
        msg.contains("leading length marker 288 and trailing marker 71 disagree"),
        "{msg}"
    );
}

#[test]
fn negative_length_and_garbage_are_refused() {
    let mut bytes = egrid_bytes(&small_grid());
    let grid = header_at(&bytes, "GRIDHEAD");
    bytes[grid..grid + 4].copy_from_slice(&(-16i32).to_be_bytes());
    let msg = parse_err(&bytes);
    assert!(
        msg.starts_with("bad/CASE.EGRID: record 5 (keyword ,"),
        "{msg}"
    );
    assert!(msg.contains("negative record length -16"), "{msg}");

    let msg = parse_err(b"this is not an EGRID file at all, just text");
    assert!(
        msg.starts_with("bad/CASE.EGRID: record 1 (keyword , byte offset 0)"),
        "{msg}"
    );
    assert!(msg.contains("runs past the end"), "{msg}");

    let mut bytes = egrid_bytes(&small_grid());
    bytes.extend_from_slice(&[1, 2, 3]);
    let msg = parse_records(Path::new("bad/CASE.EGRID"), &bytes)
        .unwrap_err()
        .to_string();
    assert!(
        msg.starts_with("bad/CASE.EGRID: record 10 (keyword ,"),
        "{msg}"
    );
    assert!(msg.contains("3 stray bytes"), "{msg}");

    let mut bytes = egrid_bytes(&small_grid());
    let grid = header_at(&bytes, "GRIDHEAD");
    bytes[grid + 5] = 0x07;
    let msg = parse_err(&bytes);
    assert!(
        msg.contains("record 5 (keyword ,") && msg.contains("not printable"),
        "{msg}"
    );
}

#[test]
fn header_that_is_not_16_bytes_is_refused() {
    let mut bytes = egrid_bytes(&small_grid());
    let grid = header_at(&bytes, "GRIDHEAD");
    // Make the GRIDHEAD header record 12 bytes long, markers consistent.
    bytes[grid..grid + 4].copy_from_slice(&12i32.to_be_bytes());
    bytes[grid + 16..grid + 20].copy_from_slice(&12i32.to_be_bytes());
    let msg = parse_err(&bytes);
    assert!(msg.contains("record 5 (keyword ,"), "{msg}");
    assert!(
        msg.contains("expected a 16-byte keyword header, found a record of 12 bytes"),
        "{msg}"
    );
}

#[test]
fn unknown_and_wrong_types_are_refused() {
    let mut bytes = egrid_bytes(&small_grid());
    let zcorn = header_at(&bytes, "ZCORN");
    bytes[zcorn + 16..zcorn + 20].copy_from_slice(b"XXXX");
    let msg = parse_err(&bytes);
    assert_names(&msg, "ZCORN");
    assert!(msg.contains("unknown item type \"XXXX\""), "{msg}");

    // LOGI has the size of REAL, so the records stay consistent; the type is wrong.
    bytes[zcorn + 16..zcorn + 20].copy_from_slice(b"LOGI");
    let msg = parse_err(&bytes);
    assert_names(&msg, "ZCORN");
    assert!(
        msg.contains("has type LOGI, expected INTE, REAL or DOUB"),
        "{msg}"
    );
}

#[test]
fn counts_that_disagree_with_the_data_are_refused() {
    let bytes = egrid_bytes(&small_grid());
    let zcorn = header_at(&bytes, "ZCORN");
    let set_count = |n: i32| {
        let mut b = bytes.clone();
        b[zcorn + 12..zcorn + 16].copy_from_slice(&n.to_be_bytes());
        b
    };
    let msg = parse_err(&set_count(95));
    assert_names(&msg, "ZCORN");
    assert!(
        msg.contains("data record holds 96 items, only 95 remain of the 95"),
        "{msg}"
    );

    // One more than written: the next keyword's 16-byte header is taken for 4 items.
    let msg = parse_err(&set_count(97));
    assert_names(&msg, "ZCORN");
    assert!(
        msg.contains("data record holds 4 items, only 1 remain"),
        "{msg}"
    );

    let msg = parse_err(&set_count(i32::MAX));
    assert_names(&msg, "ZCORN");
    assert!(
        msg.contains("header announces 2147483647 REAL items (8589934588 bytes)"),
        "{msg}"
    );

    let msg = parse_err(&set_count(-5));
    assert!(msg.contains("negative item count -5"), "{msg}");

    // The last keyword announces data the file does not have.
    let mut b = bytes.clone();
    let end = header_at(&b, "ENDGRID");
    b[end + 12..end + 16].copy_from_slice(&1i32.to_be_bytes());
    let msg = parse_records(Path::new("bad/CASE.EGRID"), &b)
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("header announces 1 INTE items (4 bytes), only 0 bytes follow"),
        "{msg}"
    );
}

#[test]
fn gridhead_overflow_and_wrong_lengths_are_refused() {
    let bytes = egrid_bytes(&small_grid());
    let grid = header_at(&bytes, "GRIDHEAD");
    let mut b = bytes.clone();
    for item in 1..4 {
        let at = grid + 24 + 4 + 4 * item;
        b[at..at + 4].copy_from_slice(&i32::MAX.to_be_bytes());
    }
    let msg = parse_err(&b);
    assert_names(&msg, "GRIDHEAD");
    assert!(msg.contains("overflow"), "{msg}");

    // nx = 2 instead of 3: COORD has 72 values, 2 x 2 x 2 needs 54.
    let mut b = bytes.clone();
    b[grid + 32..grid + 36].copy_from_slice(&2i32.to_be_bytes());
    let msg = parse_err(&b);
    assert_names(&msg, "COORD");
    assert!(
        msg.contains("72 values, a 2 x 2 x 2 grid needs 54"),
        "{msg}"
    );

    let mut b = bytes.clone();
    b[grid + 28..grid + 32].copy_from_slice(&2i32.to_be_bytes());
    let msg = parse_err(&b);
    assert!(
        msg.contains("grid type 2 is not a corner-point grid"),
        "{msg}"
    );
}

#[test]
fn zcorn_and_actnum_of_the_wrong_length_are_refused() {
    let g = small_grid();
    let write = |zcorn: &[f32], actnum: &[i32]| {
        written("mem", |w| {
            w.inte("GRIDHEAD", &[1, 3, 2, 2]).unwrap();
            w.real_from_f64("COORD", g.coord.as_slice().unwrap())
                .unwrap();
            w.real("ZCORN", zcorn).unwrap();
            w.inte("ACTNUM", actnum).unwrap();
        })
    };
    let z = g.zcorn.as_slice().unwrap();
    let msg = parse_err(&write(&z[..95], &[1; 12]));
    assert!(
        msg.contains("record 3 (keyword ZCORN,") && msg.contains("95 values"),
        "{msg}"
    );
    let msg = parse_err(&write(z, &[1; 13]));
    assert!(
        msg.contains("record 4 (keyword ACTNUM,") && msg.contains("13 values"),
        "{msg}"
    );
}

#[test]
fn non_finite_coordinates_are_refused() {
    let bytes = egrid_bytes(&small_grid());
    let mut b = bytes.clone();
    let coord = header_at(&b, "COORD") + 28;
    b[coord + 8..coord + 12].copy_from_slice(&f32::NAN.to_be_bytes());
    let msg = parse_err(&b);
    assert_names(&msg, "COORD");
    assert!(
        msg.contains("value 3 (pillar 1) is not a finite number"),
        "{msg}"
    );

    let mut b = bytes.clone();
    let zcorn = header_at(&b, "ZCORN") + 28;
    b[zcorn + 40..zcorn + 44].copy_from_slice(&f32::INFINITY.to_be_bytes());
    let msg = parse_err(&b);
    assert_names(&msg, "ZCORN");
    assert!(
        msg.contains("ZCORN value 11 is not a finite number"),
        "{msg}"
    );
}

#[test]
fn missing_keywords_are_model_errors() {
    let bytes = written("mem", |w| {
        w.inte("GRIDHEAD", &[1, 1, 1, 1]).unwrap();
        w.real("COORD", &[0.0; 24]).unwrap();
        w.inte("ENDGRID", &[]).unwrap();
        // After ENDGRID: belongs to nothing the reader uses.
        w.real("ZCORN", &[0.0; 8]).unwrap();
    });
    let e =
        parse_egrid_bytes(Path::new("x/NOZ.EGRID"), &bytes, &ReadOptions::default()).unwrap_err();
    assert!(matches!(e, Error::Model { .. }), "{e:?}");
    assert_eq!(
        e.to_string(),
        "x/NOZ.EGRID: keyword ZCORN: no ZCORN in the EGRID main grid"
    );
}

#[test]
fn lgr_blocks_are_skipped() {
    let g = small_grid();
    let bytes = written("mem", |w| {
        w.strings("LGR", RecordKind::Char, &["LOCAL"]).unwrap();
        w.inte("GRIDHEAD", &[1, 1, 1, 1]).unwrap();
        w.real("COORD", &[0.0; 24]).unwrap();
        w.mess("ENDLGR").unwrap();
        w.inte("GRIDHEAD", &[1, 3, 2, 2]).unwrap();
        w.real_from_f64("COORD", g.coord.as_slice().unwrap())
            .unwrap();
        w.real("ZCORN", g.zcorn.as_slice().unwrap()).unwrap();
        w.inte("ENDGRID", &[]).unwrap();
    });
    let r = parse_egrid_bytes(Path::new("LGR.EGRID"), &bytes, &ReadOptions::default()).unwrap();
    assert_eq!(r.dims(), g.dims());
    assert_eq!(r.active_count(), 12);
}

/// `small_grid` with properties and two report steps.
fn grid_with_results() -> CornerPointGrid {
    let mut g = small_grid();
    g.set_property("PORO", active_field(&g, |n| 0.01 * n as f32))
        .unwrap();
    g.set_property("PERMX", active_field(&g, |n| 100.0 + n as f32))
        .unwrap();
    g.set_property(
        "PORV",
        active_field(&g, |n| 1000.0 * n as f32).mapv(|v| if v.is_nan() { 0.0 } else { v }),
    )
    .unwrap();
    for (number, date, base) in [
        (0, Some((2020, 1, 1)), 250.0),
        (7, Some((2021, 12, 31)), 240.0),
    ] {
        let mut step = ReportStep {
            number,
            date,
            ..ReportStep::default()
        };
        step.arrays
            .insert("PRESSURE".into(), active_field(&g, |n| base - n as f32));
        step.arrays
            .insert("SWAT".into(), active_field(&g, |n| 0.05 * n as f32));
        g.report_steps.push(step);
    }
    g
}

#[test]
fn egrid_init_and_unrst_round_trip_through_read_egrid() {
    let g = grid_with_results();
    let dir = Scratch::new("roundtrip");
    // Extensions in mixed case: the reader matches them without regard to case.
    write_egrid(&g, &dir.path("CASE.EGRID")).unwrap();
    write_init(&g, &dir.path("CASE.Init")).unwrap();
    write_unrst(&g, &dir.path("CASE.unrst")).unwrap();
    // Another case's files in the same directory are not picked up.
    write_unrst(&grid_with_results(), &dir.path("OTHER.UNRST")).unwrap();

    let r = read_egrid(&dir.path("CASE.EGRID"), &ReadOptions::default()).unwrap();
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    assert_eq!(
        r.properties.keys().collect::<Vec<_>>(),
        ["PERMX", "PORO", "PORV"]
    );
    for (name, values) in &g.properties {
        assert!(same(&r.properties[name], values), "{name}");
    }
    assert_eq!(r.report_steps.len(), 2);
    for (a, b) in r.report_steps.iter().zip(&g.report_steps) {
        assert_eq!((a.number, a.date), (b.number, b.date));
        assert_eq!(a.arrays.keys().collect::<Vec<_>>(), ["PRESSURE", "SWAT"]);
        assert!(same(&a.arrays["PRESSURE"], &b.arrays["PRESSURE"]));
        assert!(same(&a.arrays["SWAT"], &b.arrays["SWAT"]));
    }
    // Cell 4, (1, 1, 0), is the inactive one.
    assert!(r.report_steps[1].arrays["PRESSURE"][[0, 1, 1]].is_nan());

    let geometry = ReadOptions {
        grid_only: true,
        ..ReadOptions::default()
    };
    let r = read_egrid(&dir.path("CASE.EGRID"), &geometry).unwrap();
    assert!(r.properties.is_empty() && r.report_steps.is_empty());
}

#[test]
fn non_unified_restarts_are_numbered_by_extension() {
    let g = grid_with_results();
    let dir = Scratch::new("xnnnn");
    write_egrid(&g, &dir.path("X.EGRID")).unwrap();
    // Each Xnnnn holds one step without SEQNUM, as some simulators write them.
    for (n, step) in [(3, &g.report_steps[1]), (0, &g.report_steps[0])] {
        let mut one = g.clone();
        one.report_steps = vec![step.clone()];
        let full = dir.path("full");
        write_unrst(&one, &full).unwrap();
        let kept: Vec<Record> = read_records(&full)
            .unwrap()
            .into_iter()
            .filter(|r| r.name != "SEQNUM")
            .collect();
        let mut w = RecordWriter::create(&dir.path(&format!("X.x{n:04}"))).unwrap();
        for r in &kept {
            w.write(r).unwrap();
        }
        w.finish().unwrap();
        std::fs::remove_file(full).unwrap();
    }
    let r = read_egrid(&dir.path("X.EGRID"), &ReadOptions::default()).unwrap();
    let steps: Vec<_> = r.report_steps.iter().map(|s| (s.number, s.date)).collect();
    assert_eq!(steps, [(0, Some((2020, 1, 1))), (3, Some((2021, 12, 31)))]);
    assert!(same(
        &r.report_steps[1].arrays["SWAT"],
        &g.report_steps[1].arrays["SWAT"]
    ));
}

#[test]
fn broken_result_files_become_warnings_and_wrong_grids_errors() {
    let g = grid_with_results();
    let dir = Scratch::new("broken");
    write_egrid(&g, &dir.path("B.EGRID")).unwrap();
    write_unrst(&g, &dir.path("B.UNRST")).unwrap();
    let unrst = std::fs::read(dir.path("B.UNRST")).unwrap();
    std::fs::write(dir.path("B.UNRST"), &unrst[..unrst.len() - 30]).unwrap();
    // An INIT written for another grid.
    let mut other = small_grid();
    other.actnum.fill(true);
    write_init(&other, &dir.path("B.INIT")).unwrap();

    let r = read_egrid(&dir.path("B.EGRID"), &ReadOptions::default()).unwrap();
    assert_eq!(r.dims(), g.dims());
    assert!(r.report_steps.is_empty() && r.properties.is_empty());
    assert_eq!(r.warnings.len(), 2, "{:?}", r.warnings);
    assert!(r.warnings[0].contains("B.INIT: keyword INTEHEAD: written for a 3 x 2 x 2 grid with 12 active cells, the grid is 3 x 2 x 2 with 11"), "{}", r.warnings[0]);
    assert!(
        r.warnings[1].contains("B.UNRST: record"),
        "{}",
        r.warnings[1]
    );
    assert!(
        r.warnings[1].contains("runs past the end"),
        "{}",
        r.warnings[1]
    );

    let mut g2 = small_grid();
    let e = read_restart(&mut g2, &dir.path("B.UNRST")).unwrap_err();
    assert!(matches!(e, Error::Binary { .. }), "{e:?}");
    assert!(
        g2.report_steps.is_empty(),
        "a failed read leaves the grid unchanged"
    );
}

#[test]
fn real_reek_egrid() {
    let Some(data) = shared_data() else { return };
    let path = data.join("reek/REEK.EGRID");
    let g = read_egrid(&path, &ReadOptions::default()).unwrap();
    assert_eq!(g.dims(), Dims::new(40, 64, 14).unwrap());
    assert_eq!(g.active_count(), 35_838);
    assert_eq!(g.units, Units::Metres);
    assert_eq!(g.mapaxes.unwrap().values()[0], 456510.625);
    // First ZCORN value and second COORD pillar x, as the records hold them.
    assert_eq!(g.zcorn[[0, 0, 0]], 1726.187);
    assert_eq!(g.coord[[0, 1, 0]], f64::from(140.631f32));
    assert!(g.report_steps.is_empty() && g.properties.is_empty());

    // Writing and reading back gives the same grid.
    let dir = Scratch::new("reek");
    write_egrid(&g, &dir.path("REEK.EGRID")).unwrap();
    let r = read_egrid(&dir.path("REEK.EGRID"), &ReadOptions::default()).unwrap();
    assert_eq!(
        (r.coord == g.coord, r.zcorn == g.zcorn, r.actnum == g.actnum),
        (true, true, true)
    );
    assert_eq!(r.mapaxes, g.mapaxes);
}

#[test]
fn real_spe9_egrid_and_init() {
    let Some(data) = shared_data() else { return };
    let g = read_egrid(&data.join("spe9/BENCH_SPE9.EGRID"), &ReadOptions::default()).unwrap();
    assert_eq!(g.dims(), Dims::new(24, 25, 15).unwrap());
    assert_eq!(g.active_count(), 9000);
    assert_eq!(g.units, Units::Feet);
    assert!(g.warnings.is_empty(), "{:?}", g.warnings);
    assert_eq!(g.properties["PORO"][[0, 0, 0]], 0.087);
    assert_eq!(g.properties["PERMX"][[0, 0, 1]], 162.25308);
    // SATNUM is INTE in the file and f32 here.
    assert_eq!(g.properties["SATNUM"][[14, 24, 23]], 1.0);
    assert!(g.properties.contains_key("PORV") && !g.properties.contains_key("TAB"));
}

#[test]
fn real_simpleb8_results() {
    let Some(data) = shared_data() else { return };
    let g = read_egrid(
        &data.join("simpleb8/E100_BO.EGRID"),
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(g.dims(), Dims::new(4, 2, 3).unwrap());
    assert_eq!(g.active_count(), 22);
    assert!(g.warnings.is_empty(), "{:?}", g.warnings);
    assert_eq!(g.properties["PORV"][[0, 0, 0]], 458.37943);
    assert_eq!(g.properties["PORO"][[0, 0, 0]], 0.27289566);
    let steps: Vec<_> = g.report_steps.iter().map(|s| (s.number, s.date)).collect();
    assert_eq!(steps, [(0, Some((2022, 1, 1))), (1, Some((2022, 1, 11)))]);
    let p = &g.report_steps[0].arrays["PRESSURE"];
    // Cell (0,0,1), the 9th, is inactive; the 10th takes the 9th PRESSURE value.
    assert_eq!(p[[0, 0, 0]], 269.945_3);
    assert!(p[[1, 0, 0]].is_nan());
    assert_eq!(p[[1, 0, 1]], 270.03787);
    for name in ["SWAT", "SGAS", "RS"] {
        assert!(g.report_steps[1].arrays.contains_key(name), "{name}");
    }
    assert!(!g.report_steps[0].arrays.contains_key("REGRPT"));

    // The record level sees every keyword, typed.
    let recs = read_records(&data.join("simpleb8/E100_BO.UNRST")).unwrap();
    assert_eq!(recs.iter().filter(|r| r.name == "SEQNUM").count(), 2);
    let hidden = recs.iter().find(|r| r.name == "HIDDEN").unwrap();
    assert!(matches!(&hidden.data, RecordData::Char(v) if v.len() == 58 && v[0] == "ISTHGGI"));
    assert!(
        recs.iter()
            .any(|r| r.name == "STARTSOL" && r.data == RecordData::Mess)
    );
}
