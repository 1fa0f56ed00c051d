//! Benchmarks behind `strata bench`: programs that measure and print (a table, or JSON
//! with `--json`), run on demand and never as pass/fail timing in CI.

pub mod io;
pub mod isolines;
pub mod lod;
pub mod meshes;
pub mod quality;
pub mod scene;
pub mod wire;
