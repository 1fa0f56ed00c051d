//! `strata synth`: writes a generated model.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use strata::grid::synth::{SynthParams, generate};

#[derive(Args)]
pub struct SynthArgs {
    /// Cells along i.
    #[arg(long, default_value_t = 60)]
    nx: usize,
    /// Cells along j.
    #[arg(long, default_value_t = 40)]
    ny: usize,
    /// Layers.
    #[arg(long, default_value_t = 10)]
    nz: usize,
    /// Number of faults.
    #[arg(long, default_value_t = 4)]
    faults: usize,
    /// Seed; the same seed gives the same model.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output file; the extension picks the format (.grdecl or .egrid).
    #[arg(short, long)]
    output: PathBuf,
}

/// Bytes `synth` holds per cell at its peak: ZCORN, ACTNUM, PORO and PERMX, and what
/// the writer buffers. Measured on EGRID and GRDECL output; the figures are in
/// docs/performance.md ("Reading and writing models").
const PEAK_BYTES_PER_CELL: f64 = 48.0;

pub fn run(args: &SynthArgs) -> Result<()> {
    let start = Instant::now();
    let cells = (args.nx as f64) * (args.ny as f64) * (args.nz as f64);
    super::check_memory(
        cells * PEAK_BYTES_PER_CELL,
        &format!("{} x {} x {} cells", args.nx, args.ny, args.nz),
        "to generate",
    )?;
    let grid = generate(&SynthParams {
        nx: args.nx,
        ny: args.ny,
        nz: args.nz,
        faults: args.faults,
        seed: args.seed,
    })
    .context("generating the model")?;
    let generated = start.elapsed();
    strata::grid::save(&grid, &args.output)?;
    eprintln!(
        "{}: {} x {} x {} cells, {} active; generated in {:.2} s, written in {:.2} s",
        args.output.display(),
        args.nx,
        args.ny,
        args.nz,
        grid.active_count(),
        generated.as_secs_f64(),
        (start.elapsed() - generated).as_secs_f64()
    );
    Ok(())
}
