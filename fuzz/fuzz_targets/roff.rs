//! The ROFF reader on arbitrary bytes, binary and ASCII (the header chooses): tags,
//! grid and parameters; a grid that reads is written and must read back.
//! Any panic, abort or out-of-memory is a bug; errors are the expected outcome.

#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use strata_grid::{ReadOptions, roff};

fuzz_target!(|data: &[u8]| {
    let path = Path::new("fuzz.roff");
    let _ = roff::parse_tags(path, data);
    if let Ok(grid) = roff::parse_bytes(path, data, &ReadOptions::default()) {
        let bytes = roff::to_bytes(&grid, path).expect("a grid that reads can be written");
        let back = roff::parse_bytes(path, &bytes, &ReadOptions::default()).expect("reads back");
        assert_eq!(back.dims(), grid.dims());
    }
});
