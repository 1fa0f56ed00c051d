//! Synthetic reservoir generator: a folded, faulted layer cake with pinch-outs, an
//! inactive region and smooth property fields. Deterministic by seed.

use crate::{CornerPointGrid, Error, Result};

/// What to generate.
#[derive(Clone, Debug)]
pub struct SynthParams {
    pub nx: usize,
    pub ny: usize,
    pub nz: usize,
    /// Number of faults (vertical and inclined, each with a throw).
    pub faults: usize,
    pub seed: u64,
}

/// Generates a grid with PORO and PERMX.
pub fn generate(_params: &SynthParams) -> Result<CornerPointGrid> {
    Err(Error::Invalid("generator not yet written".into()))
}
