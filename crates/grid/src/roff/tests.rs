//! Unit tests of the ROFF reader and writer on small grids made here.

use std::path::Path;

use super::{parse_bytes, to_bytes};
use crate::ReadOptions;
use crate::synth::{SynthParams, generate};

fn synth_bytes() -> (crate::CornerPointGrid, Vec<u8>) {
    let grid = generate(&SynthParams {
        nx: 5,
        ny: 4,
        nz: 3,
        faults: 1,
        seed: 3,
    })
    .expect("synth");
    let bytes = to_bytes(&grid, Path::new("s.roff")).expect("write");
    (grid, bytes)
}

#[test]
fn written_grid_reads_back_with_its_depths_and_properties() {
    let (grid, bytes) = synth_bytes();
    let back = parse_bytes(Path::new("s.roff"), &bytes, &ReadOptions::default()).expect("read");
    assert_eq!(back.zcorn, grid.zcorn);
    assert_eq!(back.actnum, grid.actnum);
    assert_eq!(
        back.properties.keys().collect::<Vec<_>>(),
        grid.properties.keys().collect::<Vec<_>>()
    );
    let grid_only = ReadOptions {
        grid_only: true,
        ..ReadOptions::default()
    };
    let bare = parse_bytes(Path::new("s.roff"), &bytes, &grid_only).expect("read");
    assert!(bare.properties.is_empty(), "grid_only skips parameters");
}

/// One cell, 10 m wide, from 1000 to 1010 m deep, with a split node on top: its four
/// top corners at 1000, 1001, 1002 and 1003 m.
const ONE_CELL: &str = "roff-asc\n#ROFF file#\ntag filedata\nint byteswaptest 1\nchar filetype \"grid\"\nendtag\n\
tag dimensions\nint nX 1\nint nY 1\nint nZ 1\nendtag\n\
tag cornerLines\narray float data 24\n\
0 0 -1010 0 0 -1000  0 10 -1010 0 10 -1000  10 0 -1010 10 0 -1000  10 10 -1010 10 10 -1000\nendtag\n\
tag zvalues\narray byte splitEnz 8\n1 4 1 4 1 4 1 4\n\
array float data 20\n-1010 -1000 -1000 -1000 -1000 -1010 -1001 -1001 -1001 -1001\n\
-1010 -1002 -1002 -1002 -1002 -1010 -1003 -1003 -1003 -1003\nendtag\n\
tag active\narray bool data 1\n1\nendtag\n\
tag parameter\nchar name \"facies\"\narray char codeNames 2\n\"sand\" \"\"\narray int codeValues 2\n1 2\narray int data 1\n2\nendtag\n";

#[test]
fn split_nodes_give_each_cell_its_own_depths() {
    let grid = parse_bytes(
        Path::new("one.roffasc"),
        ONE_CELL.as_bytes(),
        &ReadOptions::default(),
    )
    .expect("read");
    let depths: Vec<f32> = (0..8).map(|c| grid.corner_depth(0, 0, 0, c)).collect();
    // Pillars in ROFF order (i slowest): (0,0) (0,1) (1,0) (1,1), each node's quadrant
    // for the one cell being the one that lies towards it.
    assert_eq!(
        depths,
        [
            1000.0, 1002.0, 1001.0, 1003.0, 1010.0, 1010.0, 1010.0, 1010.0
        ]
    );
    assert_eq!(grid.cell_corners(0, 0, 0)[3], [10.0, 10.0, 1003.0]);
    assert_eq!(grid.properties["FACIES"][[0, 0, 0]], 2.0);
    let codes = &grid.codes["FACIES"];
    assert_eq!((codes[&1].as_str(), codes[&2].as_str()), ("sand", ""));
}

#[test]
fn ascii_errors_name_the_line_and_key() {
    let bad = ONE_CELL.replace("1 4 1 4 1 4 1 4", "1 4 1 4 1 3 1 4");
    let err = parse_bytes(
        Path::new("one.roffasc"),
        bad.as_bytes(),
        &ReadOptions::default(),
    )
    .expect_err("split 3");
    let msg = err.to_string();
    assert!(
        msg.contains("one.roffasc:17: keyword zvalues/splitEnz") && msg.contains("split 3"),
        "{msg}"
    );
    let bad = ONE_CELL.replace("array float data 24", "array float data 2400000000");
    let msg = parse_bytes(
        Path::new("one.roffasc"),
        bad.as_bytes(),
        &ReadOptions::default(),
    )
    .expect_err("count")
    .to_string();
    assert!(
        msg.contains("cornerLines/data") && msg.contains("cannot fit"),
        "{msg}"
    );
}

#[test]
fn a_huge_binary_count_is_refused_before_allocating() {
    let (_, mut bytes) = synth_bytes();
    let key = b"array\0float\0data\0";
    let at = bytes
        .windows(key.len())
        .position(|w| w == key)
        .expect("an array")
        + key.len();
    bytes[at..at + 4].copy_from_slice(&i32::MAX.to_le_bytes());
    let msg = parse_bytes(Path::new("s.roff"), &bytes, &ReadOptions::default())
        .expect_err("count")
        .to_string();
    assert!(
        msg.contains("cornerLines/data") && msg.contains("bytes"),
        "{msg}"
    );
}

#[test]
fn every_truncation_is_an_error_not_a_panic() {
    let (_, bytes) = synth_bytes();
    for len in (0..bytes.len()).step_by(7) {
        assert!(
            parse_bytes(Path::new("s.roff"), &bytes[..len], &ReadOptions::default()).is_err(),
            "{len}"
        );
    }
}
