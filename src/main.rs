//! The `strata` command-line tool.

mod cli;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Reservoir simulation grids: inspect, generate, render.
#[derive(Parser)]
#[command(name = "strata", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Dimensions, cell counts, extent, properties and report steps of a model, or one cell.
    Info(cli::info::InfoArgs),
    /// Write a synthetic faulted reservoir model (.grdecl or .egrid).
    Synth(cli::synth::SynthArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Info(args) => cli::info::run(&args),
        Command::Synth(args) => cli::synth::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("strata: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// The sample model shipped in `data/`, used when a command is given no model.
pub fn sample_model() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/sample.grdecl")
}
