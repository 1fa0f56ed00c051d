//! The GRDECL / DATA text reader on arbitrary bytes, with and without `grid_only`.
//! The deck "lives" in a folder that does not exist, so relative INCLUDEs exercise
//! the missing-file paths (an error, or a warning with `grid_only`).
//! Any panic, abort, timeout or out-of-memory is a bug; errors are the expected
//! outcome. A grid that parses must be consistent.

#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use strata_grid::{ReadOptions, grdecl};

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
            assert!(grid.properties.values().all(|p| p.dim() == (d.nz, d.ny, d.nx)));
            assert!(!grid_only || grid.properties.is_empty());
        }
    }
});
