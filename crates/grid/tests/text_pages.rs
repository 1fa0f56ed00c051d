//! Reading a large text deck gives its file pages back as it scans and parses them:
//! the deck's text and its values are not resident together. Alone in its test
//! binary, so that no other test changes the process's peak memory meanwhile.

use std::io::Write;

mod common;

/// The depth written for ZCORN value `n` of a grid of `columns` columns: whole
/// metres and ten-thousandths.
fn depth_of(n: usize, columns: usize) -> (u32, u32) {
    let plane = (n / (4 * columns)) as u32;
    let tenths_of_mm = 10_000 * (1000 + plane * 5 / 2) + (plane % 2) * 5_000 + (n % 977) as u32 * 9;
    (tenths_of_mm / 10_000, tenths_of_mm % 10_000)
}

#[cfg(target_os = "linux")]
#[test]
fn a_deck_is_not_resident_beside_its_values() {
    let (nx, ny, nz) = (100usize, 100, 200);
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("big.grdecl");
    let file = std::fs::File::create(&path).expect("the deck is created");
    let mut out = std::io::BufWriter::new(file);
    write!(out, "SPECGRID\n{nx} {ny} {nz} 1 F /\nCOORD\n").expect("the deck is written");
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (i * 50, j * 50);
            writeln!(out, "{x} {y} 1000 {x} {y} 2000").expect("the deck is written");
        }
    }
    // 16 M corner depths, about 10 bytes of text each: plane p of ZCORN (2k, or
    // 2k + 1 for the bottoms) is 1000 + 2.5 p metres deep, give or take 0.9 m.
    writeln!(out, "/\nZCORN").expect("the deck is written");
    let corners = 8 * nx * ny * nz;
    for n in 0..corners {
        let (metres, ten_thousandths) = depth_of(n, nx * ny);
        let end = if n % 8 == 7 { '\n' } else { ' ' };
        write!(out, "{metres}.{ten_thousandths:04}{end}").expect("the deck is written");
    }
    writeln!(out, "/").expect("the deck is written");
    out.flush().expect("the deck is flushed");
    drop(out);
    let text = std::fs::metadata(&path).expect("the deck's size").len();
    let values = 4 * corners as u64;

    // As many threads as a large workstation has: the text in flight must not grow
    // with them.
    let threads = rayon::ThreadPoolBuilder::new()
        .num_threads(64)
        .build()
        .expect("a pool of threads");
    let before = common::status_bytes("VmHWM");
    let grid = threads
        .install(|| strata_grid::grdecl::read(&path, &strata_grid::ReadOptions::default()))
        .expect("the deck reads");
    let grown = common::status_bytes("VmHWM").saturating_sub(before);
    assert_eq!(grid.dims().nz, nz);
    // Corner 0 of cell (3, 4, 5): plane 10, row 8, column 6 of ZCORN.
    let (metres, ten_thousandths) = depth_of(10 * 4 * nx * ny + 8 * 2 * nx + 6, nx * ny);
    let want = f64::from(metres) + f64::from(ten_thousandths) / 1e4;
    assert_eq!(grid.corner_depth(3, 4, 5, 0), want as f32);
    assert!(text > 130_000_000, "{text} bytes of deck");
    assert!(
        grown < values + text / 2,
        "the peak grew by {grown} bytes reading {text} bytes of text into {values} bytes"
    );
}
