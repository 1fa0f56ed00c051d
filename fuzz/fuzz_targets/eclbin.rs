//! Eclipse binary readers on arbitrary bytes: the record scanner and decoder, the
//! EGRID parser, and the INIT and restart parsers against a fixed grid with the
//! dimensions and ACTNUM of simpleb8 (so that its files make useful seeds).
//! Any panic, abort or out-of-memory is a bug; errors are the expected outcome.

#![no_main]

use std::path::Path;
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use strata_grid::{CornerPointGrid, Dims, ReadOptions, eclbin};

/// 4 x 2 x 3 unit cells, cells 9 and 21 (1-based) inactive, as in E100_BO.EGRID.
fn simpleb8_like() -> &'static CornerPointGrid {
    static GRID: OnceLock<CornerPointGrid> = OnceLock::new();
    GRID.get_or_init(|| {
        let dims = Dims::new(4, 2, 3).expect("valid dims");
        let coord = (0..3)
            .flat_map(|j| {
                (0..5).flat_map(move |i| [i as f64, j as f64, 0.0, i as f64, j as f64, 3.0])
            })
            .collect();
        let zcorn = (0..6)
            .flat_map(|z| std::iter::repeat_n(((z + 1) / 2) as f32, 32))
            .collect();
        let actnum = (0..24).map(|c| c != 8 && c != 20).collect();
        CornerPointGrid::from_arrays(dims, coord, zcorn, Some(actnum)).expect("valid grid")
    })
}

fuzz_target!(|data: &[u8]| {
    let path = Path::new("fuzz.EGRID");
    let _ = eclbin::parse_records(path, data);
    for view in eclbin::Records::new(path, data).flatten() {
        let _ = (
            view.to_f32(),
            view.to_f64(),
            view.to_i32(),
            view.to_strings(),
        );
    }
    if let Ok(grid) = eclbin::parse_egrid_bytes(path, data, &ReadOptions::default()) {
        assert!(grid.active_count() <= grid.cell_count());
    }
    let mut grid = simpleb8_like().clone();
    let _ = eclbin::parse_init_bytes(&mut grid, Path::new("fuzz.INIT"), data);
    let _ = eclbin::parse_restart_bytes(&mut grid, Path::new("fuzz.X0001"), data);
});
