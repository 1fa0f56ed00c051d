//! Formatted Eclipse files on arbitrary text: the conversion to binary records, then
//! the EGRID/GRID and INIT readers on what it gives. Any panic, abort or out-of-memory
//! is a bug; errors are the expected outcome.

#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use strata_grid::{ReadOptions, eclbin};

fuzz_target!(|data: &[u8]| {
    let path = Path::new("fuzz.FEGRID");
    let _ = eclbin::looks_formatted(data);
    if let Ok(bytes) = eclbin::formatted_to_binary(path, data) {
        if let Ok(mut grid) = eclbin::parse_egrid_bytes(path, &bytes, &ReadOptions::default()) {
            let _ = eclbin::parse_init_bytes(&mut grid, Path::new("fuzz.FINIT"), &bytes);
        }
    }
});
