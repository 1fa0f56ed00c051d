//! Damaged model files, as they reach a user (bytes overwritten, values replaced by
//! others, a file cut short), end in an error that names the file, or they read and
//! go on through what `strata render --sides --lod --stitch` does before it draws:
//! the layer and side surfaces, each decimated, their shared outlines stitched. Never
//! a panic. So do damaged hierarchy files: an error naming the file, or a view of
//! them. The damage is a fixed sequence, the same on every run.

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use strata::grid::eclbin::{write_init, write_unrst};
use strata::grid::ndarray::Array3;
use strata::grid::synth::{SynthParams, generate};
use strata::grid::{CornerPointGrid, ReadOptions, ReportStep, open_with, save};
use strata::lod::{BuildOptions, LodFile, Options, ViewPoint, build_file, decimate_chosen, stitch};
use strata::surfaces::{SceneOptions, build_stacked_surfaces};

/// A fixed linear congruential sequence.
struct Sequence(u64);

impl Sequence {
    fn next(&mut self) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 33) as usize
    }

    fn below(&mut self, n: usize) -> usize {
        self.next() % n.max(1)
    }
}

/// A small faulted model with PORO and one report step of PRESSURE.
fn model() -> CornerPointGrid {
    let mut grid = generate(&SynthParams {
        nx: 6,
        ny: 5,
        nz: 3,
        faults: 2,
        seed: 11,
    })
    .expect("a synthetic grid");
    let dims = grid.dims();
    let pressure = Array3::from_shape_fn((dims.nz, dims.ny, dims.nx), |(k, j, i)| {
        200.0 + (k * 7 + j * 3 + i) as f32
    });
    grid.report_steps.push(ReportStep {
        number: 1,
        date: Some((2001, 2, 3)),
        arrays: BTreeMap::from([("PRESSURE".to_string(), pressure)]),
    });
    grid
}

/// A model that read: its warnings, and whether every later stage took it.
struct Read {
    warnings: Vec<String>,
    through: bool,
}

/// What reading and preparing `path` came to: what was read, or the reader's error.
/// Panics (the test fails) when any stage panics, naming `what`.
fn survive(path: &Path, what: &str) -> Result<Read, String> {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let grid = open_with(path, &ReadOptions::default()).map_err(|e| e.to_string())?;
        let refused = Read {
            warnings: grid.warnings.clone(),
            through: false,
        };
        let scene = SceneOptions {
            layers: None,
            sides: true,
            property: grid.property("PORO").map(|_| "PORO".to_string()),
            flat_cells: false,
            cut: None,
            inactive: false,
        };
        let Ok((surfaces, _)) = build_stacked_surfaces(&grid, &scene) else {
            return Ok(refused);
        };
        let mut decimated = Vec::new();
        for (n, mesh) in surfaces.iter().enumerate() {
            let options = Options {
                z_scale: 5.0,
                ..if n % 2 == 0 {
                    Options::fraction(mesh, 0.1)
                } else {
                    Options::covering(mesh, 0.1)
                }
            };
            match decimate_chosen(mesh, &options) {
                Ok(chosen) => decimated.push(chosen.decimated),
                Err(_) => return Ok(refused),
            }
        }
        stitch(
            &surfaces.iter().collect::<Vec<_>>(),
            &mut decimated.iter_mut().collect::<Vec<_>>(),
        );
        Ok(Read {
            through: true,
            ..refused
        })
    }));
    outcome.unwrap_or_else(|_| panic!("{what}: a stage panicked"))
}

/// Tallies the outcomes of damaged files; an error or warning must say where.
#[derive(Default)]
struct Tally {
    read: usize,
    /// Reads with a warning.
    warned: usize,
    refused_later: usize,
    errors: usize,
}

impl Tally {
    fn count(
        &mut self,
        outcome: Result<Read, String>,
        says_where: impl Fn(&str) -> bool,
        what: &str,
    ) {
        match outcome {
            Ok(read) => {
                self.warned += usize::from(!read.warnings.is_empty());
                for warning in &read.warnings {
                    assert!(
                        says_where(warning),
                        "{what}: the warning does not say where: {warning}"
                    );
                }
                if read.through {
                    self.read += 1;
                } else {
                    self.refused_later += 1;
                }
            }
            Err(message) => {
                assert!(
                    says_where(&message),
                    "{what}: the error does not say where: {message}"
                );
                self.errors += 1;
            }
        }
    }
}

/// Does `message` name `file`, a line of it and the keyword, as the deck reader's
/// errors do (`deck.grdecl:12: keyword ZCORN: ...`)?
fn names_line_and_keyword(message: &str, file: &str) -> bool {
    message
        .split_once(&format!("{file}:"))
        .is_some_and(|(_, rest)| {
            let digits = rest.chars().take_while(char::is_ascii_digit).count();
            digits > 0 && rest[digits..].starts_with(": keyword ")
        })
}

/// Numbers that keep a deck readable and its geometry strange: below, on and far
/// beyond the model, tiny and huge.
const VALUES: [&str; 8] = [
    "-1",
    "0",
    "3.5",
    "1e30",
    "-1e30",
    "1e-30",
    "99999999999",
    "1.5D+3",
];

/// Words that break a deck: numbers out of range, repeats that claim more values than
/// there are, keywords out of place, terminators, an include of nothing.
const WORDS: [&str; 16] = [
    "1e308",
    "nan",
    "inf",
    "3*",
    "1000000000*1",
    "0*",
    "*",
    "/",
    "--",
    "COORD",
    "ZCORN",
    "SPECGRID",
    "ACTNUM",
    "INCLUDE",
    "'nowhere.inc'",
    "PORO",
];

#[test]
fn a_damaged_deck_is_an_error_naming_it_or_reads_and_goes_through() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("deck.grdecl");
    save(&model(), &path).expect("the deck is written");
    let deck = std::fs::read(&path).expect("the deck reads back");
    assert!(survive(&path, "the undamaged deck").is_ok_and(|r| r.through));
    let mut sequence = Sequence(0x5eed);
    let mut tally = Tally::default();
    for round in 0..400 {
        let mut damaged = deck.clone();
        for _ in 0..1 + round % 3 {
            let at = sequence.below(damaged.len());
            match sequence.below(10) {
                0..=6 => {
                    // The word around `at`, replaced by a number or a breaking word.
                    let blank = |b: &u8| b.is_ascii_whitespace();
                    let start = damaged[..at].iter().rposition(blank).map_or(0, |p| p + 1);
                    let end = damaged[at..]
                        .iter()
                        .position(blank)
                        .map_or(damaged.len(), |p| at + p);
                    let word = if sequence.below(3) > 0 {
                        VALUES[sequence.below(VALUES.len())]
                    } else {
                        WORDS[sequence.below(WORDS.len())]
                    };
                    damaged.splice(start..end, word.bytes());
                }
                7 => damaged[at] = sequence.next() as u8,
                8 => damaged.truncate(at),
                _ => {
                    let end = (at + 1 + sequence.below(200)).min(damaged.len());
                    damaged.drain(at..end);
                }
            }
            if damaged.is_empty() {
                break;
            }
        }
        std::fs::write(&path, &damaged).expect("the damaged deck is written");
        let what = format!("round {round}");
        tally.count(
            survive(&path, &what),
            |m| names_line_and_keyword(m, "deck.grdecl"),
            &what,
        );
    }
    // Numbers replaced by numbers read; broken words and counts do not.
    assert!(
        tally.read > 0 && tally.errors > 0,
        "{} read, {} refused after reading, {} errors",
        tally.read,
        tally.refused_later,
        tally.errors
    );
}

#[test]
fn damaged_eclipse_binaries_are_errors_naming_them_or_read_and_go_through() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let grid = model();
    let files = ["CASE.EGRID", "CASE.INIT", "CASE.UNRST"];
    save(&grid, &dir.path().join(files[0])).expect("the EGRID is written");
    write_init(&grid, &dir.path().join(files[1])).expect("the INIT is written");
    write_unrst(&grid, &dir.path().join(files[2])).expect("the UNRST is written");
    let egrid = dir.path().join(files[0]);
    let read = open_with(&egrid, &ReadOptions::default()).expect("the undamaged EGRID reads");
    assert!(read.property("PORO").is_some() && read.report_steps.len() == 1);
    let originals: Vec<Vec<u8>> = files
        .iter()
        .map(|f| std::fs::read(dir.path().join(f)).expect("a written file reads back"))
        .collect();
    let mut sequence = Sequence(0xec1);
    let mut tally = Tally::default();
    for round in 0..400 {
        let which = round % files.len();
        let mut damaged = originals[which].clone();
        for _ in 0..1 + round % 4 {
            let at = sequence.below(damaged.len());
            match sequence.below(8) {
                0..=3 => damaged[at] = sequence.next() as u8,
                4..=6 => {
                    // A length, count or value replaced by one a reader must check.
                    let word: [u8; 4] = [
                        [0xff; 4],
                        [0x7f, 0xff, 0xff, 0xff],
                        [0x80, 0, 0, 0],
                        [0; 4],
                        [0x7f, 0xc0, 0, 0],
                        [0, 0, 0x10, 0],
                    ][sequence.below(6)];
                    let end = (at + 4).min(damaged.len());
                    damaged[at..end].copy_from_slice(&word[..end - at]);
                }
                _ => damaged.truncate(at),
            }
            if damaged.is_empty() {
                break;
            }
        }
        std::fs::write(dir.path().join(files[which]), &damaged).expect("damage is written");
        let what = format!("round {round}, {}", files[which]);
        let says_where = |m: &str| {
            files.iter().any(|f| {
                m.contains(&format!("{f}: record ")) || m.contains(&format!("{f}: keyword "))
            })
        };
        tally.count(survive(&egrid, &what), says_where, &what);
        std::fs::write(dir.path().join(files[which]), &originals[which]).expect("restored");
    }
    // A broken INIT or UNRST is a warning and the grid still reads; a broken EGRID
    // is an error.
    assert!(
        tally.read > 0 && tally.warned > 0 && tally.errors > 0,
        "{} read ({} with a warning), {} refused after reading, {} errors",
        tally.read,
        tally.warned,
        tally.refused_later,
        tally.errors
    );
}

/// What a view of a hierarchy reads, `lod view`'s way: the box it frames, the nodes it
/// selects from a far and a near eye at three pixel errors, their mesh, cells, values
/// and corners, and every layer's cells and sides and the leaf over a cell. The first
/// error, if any.
fn view_hierarchy(path: &Path) -> Result<(), String> {
    let file = LodFile::open(path).map_err(|e| e.to_string())?;
    let [ni, nj] = file.dims();
    if let Some([lo, hi]) = file.framed() {
        assert!((0..3).all(|a| lo[a] <= hi[a]), "a framed box {lo:?} {hi:?}");
    }
    for eye in [[0.0, -1e5, 1e5], [10.0, 10.0, 5.0]] {
        for max_pixels in [0.0, 1.0, f32::INFINITY] {
            let view = ViewPoint {
                eye,
                z_scale: 5.0,
                fov_y_deg: 30.0,
                height_px: 800,
                frustum: None,
            };
            let chosen = file.select(&view, max_pixels);
            let mesh = file.selection_mesh(&chosen).map_err(|e| e.to_string())?;
            mesh.validate().map_err(|e| e.to_string())?;
            file.selection_cover(&chosen).map_err(|e| e.to_string())?;
            file.selection_values(&chosen, None)
                .map_err(|e| e.to_string())?;
            file.selection_corners(&chosen, None)
                .map_err(|e| e.to_string())?;
        }
    }
    for l in 0..file.layers().len() {
        file.layer_cells(l);
        file.layer_sides(l).map_err(|e| e.to_string())?;
        file.leaf_of(l, [ni / 2, nj / 2]);
    }
    Ok(())
}

/// Four bytes a hierarchy reader must check wherever they land: counts, offsets and
/// widths at their extremes, and floats that are not numbers.
const HIERARCHY_WORDS: [u32; 10] = [
    0,
    1,
    3,
    0xffff,
    0x1_0000,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0x7fc0_0000,
    0xff80_0000,
];

#[test]
fn a_damaged_hierarchy_is_an_error_naming_it_or_is_viewed() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("model.lod");
    let options = BuildOptions {
        tile_cells: 2,
        ..BuildOptions::default()
    };
    build_file(&model(), Some("PORO"), &path, &options).expect("the hierarchy is built");
    let built = std::fs::read(&path).expect("the hierarchy reads back");
    assert_eq!(view_hierarchy(&path), Ok(()));
    // The header (112 bytes) names where the layer table starts; the node table
    // follows it to the end of the file. Damage lands in the tables as often as in
    // the header and as in the node data before them.
    const HEADER: usize = 112;
    let tables = built
        .get(64..72)
        .and_then(|b| b.try_into().ok())
        .map(u64::from_le_bytes)
        .expect("a header") as usize;
    assert!(HEADER < tables && tables < built.len());
    let regions = [8..HEADER, HEADER..tables, tables..built.len()];
    let mut sequence = Sequence(0x10d);
    let (mut viewed, mut errors) = (0, 0);
    for round in 0..600 {
        let mut damaged = built.clone();
        for _ in 0..1 + round % 3 {
            let region = &regions[sequence.below(regions.len())];
            // A file cut short earlier in the round has less of the region left.
            let end = region.end.min(damaged.len());
            if end < region.start + 4 {
                continue;
            }
            let at = region.start + 4 * sequence.below((end - region.start) / 4);
            match sequence.below(6) {
                0..=3 => {
                    let word = HIERARCHY_WORDS[sequence.below(HIERARCHY_WORDS.len())];
                    damaged[at..at + 4].copy_from_slice(&word.to_le_bytes());
                }
                4 => damaged[at] = sequence.next() as u8,
                _ => damaged.truncate(at),
            }
            if damaged.len() < HEADER {
                break;
            }
        }
        std::fs::write(&path, &damaged).expect("the damaged hierarchy is written");
        let outcome = catch_unwind(AssertUnwindSafe(|| view_hierarchy(&path)))
            .unwrap_or_else(|_| panic!("round {round}: a stage panicked"));
        match outcome {
            Ok(()) => viewed += 1,
            Err(message) => {
                assert!(
                    message.contains("model.lod"),
                    "round {round}: the error does not name the file: {message}"
                );
                errors += 1;
            }
        }
    }
    // Damaged vertices still draw; damaged tables and indices are refused.
    assert!(viewed > 0 && errors > 0, "{viewed} viewed, {errors} errors");
}
