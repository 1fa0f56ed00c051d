//! `strata synth`: writes a generated model.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
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
/// the writer buffers. Measured: 4.07 GB for 100 M cells to EGRID, 469 MB for 10 M to
/// GRDECL.
const PEAK_BYTES_PER_CELL: f64 = 48.0;

/// Memory the system can still give this process without swapping (Linux's
/// MemAvailable), `None` where that is not known.
fn available_memory() -> Option<f64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kb = info
        .lines()
        .find_map(|l| l.strip_prefix("MemAvailable:"))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse::<f64>()
        .ok()?;
    Some(1024.0 * kb)
}

pub fn run(args: &SynthArgs) -> Result<()> {
    let start = Instant::now();
    // Refused before allocating: past the memory there is, the allocator aborts or the
    // system's OOM killer ends the run long after it started.
    let cells = (args.nx as f64) * (args.ny as f64) * (args.nz as f64);
    let needed = cells * PEAK_BYTES_PER_CELL;
    if let Some(available) = available_memory()
        && needed > available
    {
        bail!(
            "{} x {} x {} cells need about {:.1} GB to generate, and {:.1} GB of memory is \
             available",
            args.nx,
            args.ny,
            args.nz,
            needed / 1e9,
            available / 1e9
        );
    }
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
