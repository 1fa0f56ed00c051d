//! One module per subcommand of the `strata` binary.

pub mod info;
pub mod render;
pub mod synth;
pub mod terrain;
