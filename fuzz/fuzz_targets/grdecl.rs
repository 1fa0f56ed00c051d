//! The GRDECL / DATA text reader on arbitrary bytes, with and without `grid_only`.
//! The deck "lives" in a folder that does not exist, so relative INCLUDEs exercise
//! the missing-file paths (an error, or a warning with `grid_only`).
//! Any panic, abort, timeout or out-of-memory is a bug; errors are the expected
//! outcome. A grid that parses must be consistent, and (when small) must survive
//! the writer: written and read back, every array is identical.

#![no_main]

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use strata_grid::{CornerPointGrid, ReadOptions, grdecl};

/// Grids up to this many cells are written and read back on every input.
const ROUND_TRIP_CELLS: usize = 20_000;

fn scratch() -> &'static PathBuf {
    static PATH: OnceLock<PathBuf> = OnceLock::new();
    PATH.get_or_init(|| {
        std::env::temp_dir().join(format!("strata-fuzz-grdecl-{}.grdecl", std::process::id()))
    })
}

fn same(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn round_trip(grid: &CornerPointGrid) {
    let path = scratch();
    grdecl::write(grid, path).expect("a grid the reader built can be written");
    let back = grdecl::read(path, &ReadOptions::default()).expect("written grid reads back");
    assert_eq!(back.dims(), grid.dims());
    assert_eq!(back.coord, grid.coord);
    assert_eq!(back.zcorn, grid.zcorn);
    assert_eq!(back.actnum, grid.actnum);
    assert_eq!(back.mapaxes, grid.mapaxes);
    assert_eq!(back.units, grid.units);
    assert_eq!(
        back.properties.keys().collect::<Vec<_>>(),
        grid.properties.keys().collect::<Vec<_>>()
    );
    for (name, a) in &grid.properties {
        assert!(
            a.iter()
                .zip(&back.properties[name])
                .all(|(&x, &y)| same(x, y)),
            "{name}"
        );
    }
}

fuzz_target!(|data: &[u8]| {
    let path = Path::new("/nonexistent-strata-fuzz/deck.grdecl");
    for grid_only in [false, true] {
        let options = ReadOptions {
            grid_only,
            load_results: false,
        };
        if let Ok(grid) = grdecl::parse_bytes(path, data, &options) {
            let d = grid.dims();
            assert_eq!(grid.zcorn.len(), 8 * grid.cell_count());
            assert_eq!(grid.coord.len(), 6 * (d.nx + 1) * (d.ny + 1));
            assert!(grid.active_count() <= grid.cell_count());
            assert!(grid.zcorn.iter().all(|z| z.is_finite()));
            assert!(
                grid.properties
                    .values()
                    .all(|p| p.dim() == (d.nz, d.ny, d.nx))
            );
            assert!(!grid_only || grid.properties.is_empty());
            if !grid_only && grid.cell_count() <= ROUND_TRIP_CELLS {
                round_trip(&grid);
            }
        }
    }
});
