//! A model file is read by what it holds, not by its name, and a file that is not a
//! model is named for what it is.

use std::path::Path;

use strata_grid::synth::{SynthParams, generate};
use strata_grid::{Content, Error, HIERARCHY_MAGIC, ReadOptions, grdecl, open_with, save};

fn message(path: &Path) -> String {
    match open_with(path, &ReadOptions::default()) {
        Ok(_) => panic!("{} was read as a model", path.display()),
        Err(e @ Error::Content { .. }) => e.to_string(),
        Err(e) => panic!("{}: not a content error: {e}", path.display()),
    }
}

#[test]
fn an_eclipse_binary_grid_is_read_whatever_its_name() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let grid = generate(&SynthParams {
        nx: 6,
        ny: 5,
        nz: 3,
        faults: 1,
        seed: 7,
    })
    .expect("a synthetic grid");
    let egrid = dir.path().join("model.egrid");
    save(&grid, &egrid).expect("the EGRID is written");
    // EGRID stores coordinates as f32: the renamed copies must read as the original does.
    let grid = open_with(&egrid, &ReadOptions::default()).expect("the EGRID reads back");
    for name in ["model.bin", "model.grdecl"] {
        let renamed = dir.path().join(name);
        std::fs::copy(&egrid, &renamed).expect("a copy");
        assert_eq!(
            Content::of_file(&renamed).expect("readable"),
            Content::EclipseBinary
        );
        let read = open_with(&renamed, &ReadOptions::default()).expect("read as an EGRID");
        assert_eq!(read.dims(), grid.dims(), "{name}");
        assert_eq!(read.active_count(), grid.active_count(), "{name}");
        for (i, j, k) in [(0, 0, 0), (5, 4, 2), (3, 2, 1)] {
            assert_eq!(
                read.cell_corners(i, j, k),
                grid.cell_corners(i, j, k),
                "{name}"
            );
        }
    }
}

#[test]
fn a_hierarchy_or_other_binary_data_is_named_not_parsed() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let lod = dir.path().join("model.grdecl");
    let mut bytes = HIERARCHY_MAGIC.to_vec();
    bytes.extend_from_slice(&[4, 0, 0, 0, 1, 0, 0, 0]);
    std::fs::write(&lod, &bytes).expect("written");
    let said = message(&lod);
    assert!(said.contains("level-of-detail hierarchy"), "{said}");
    assert!(said.contains("strata lod view"), "{said}");

    let blob = dir.path().join("blob.grdecl");
    std::fs::write(&blob, b"SPECGRID\n 2 2 1 \x00\x01\x02 /\n").expect("written");
    let said = message(&blob);
    assert!(said.contains("binary data (byte 16 is zero)"), "{said}");
    assert!(said.contains("neither a text deck"), "{said}");

    // An INCLUDE of binary data is named by the included file's path, and the
    // INCLUDE by its deck and line.
    let deck = dir.path().join("deck.grdecl");
    std::fs::write(&deck, b"-- top\nINCLUDE\n 'blob.grdecl' /\n").expect("written");
    let said = open_with(&deck, &ReadOptions::default())
        .map(|_| ())
        .expect_err("a binary include is refused")
        .to_string();
    assert!(said.contains("blob.grdecl"), "{said}");
    assert!(said.contains("not a text deck"), "{said}");
    let head = format!("{}:2: keyword INCLUDE: ", deck.display());
    assert!(said.starts_with(&head), "{said}");
}

#[test]
fn a_property_deck_that_is_an_eclipse_binary_is_refused_by_name() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut grid = generate(&SynthParams {
        nx: 4,
        ny: 3,
        nz: 2,
        faults: 0,
        seed: 1,
    })
    .expect("a synthetic grid");
    let egrid = dir.path().join("props.GRDECL");
    strata_grid::eclbin::write_egrid(&grid, &egrid).expect("written");
    let said = grdecl::read_properties(&mut grid, &egrid)
        .expect_err("an EGRID is no property deck")
        .to_string();
    assert!(said.contains("props.GRDECL"), "{said}");
    assert!(said.contains("an Eclipse binary file"), "{said}");
    assert!(said.contains("not a text deck"), "{said}");
}

#[test]
fn text_and_empty_files_are_text() {
    assert_eq!(Content::of(b""), Content::Text);
    assert_eq!(Content::of(b"SPECGRID\n 2 2 1 1 F /\n"), Content::Text);
    // A zero byte past the first 4 KiB is not looked at.
    let mut late = vec![b' '; 5000];
    late[4500] = 0;
    assert_eq!(Content::of(&late), Content::Text);
    late[100] = 0;
    assert_eq!(Content::of(&late), Content::Binary { zero_at: 100 });
    // A record header whose type is not one of Eclipse's is not taken for one.
    let mut header = 16u32.to_be_bytes().to_vec();
    header.extend_from_slice(b"FILEHEAD");
    header.extend_from_slice(&[0, 0, 0, 1]);
    header.extend_from_slice(b"INTE");
    header.extend_from_slice(&[0; 4]);
    assert_eq!(Content::of(&header), Content::EclipseBinary);
    header[16..20].copy_from_slice(b"ABCD");
    assert_eq!(Content::of(&header), Content::Binary { zero_at: 0 });
}
