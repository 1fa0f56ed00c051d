//! The GRID format (per-cell COORDS/CORNERS) on arbitrary bytes, seeded with GRID
//! files: any panic, abort or out-of-memory is a bug; errors are expected.

#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use strata_grid::{ReadOptions, eclbin};

fuzz_target!(|data: &[u8]| {
    if let Ok(grid) = eclbin::parse_egrid_bytes(Path::new("fuzz.GRID"), data, &ReadOptions::default()) {
        assert!(grid.active_count() <= grid.cell_count());
    }
});
