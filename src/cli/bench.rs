//! `strata bench`: the benchmarks, in builds with `--features bench` (they are
//! measuring programs, not part of the library's API); other builds say how to get
//! them.

use anyhow::Result;
use clap::Args;
#[cfg(feature = "bench")]
use clap::Subcommand;
#[cfg(feature = "bench")]
use std::path::PathBuf;

/// `strata bench` and what follows it.
#[derive(Args)]
pub struct BenchArgs {
    #[cfg(feature = "bench")]
    #[command(subcommand)]
    command: BenchCommand,
    /// What was asked of the benchmarks this build does not have.
    #[cfg(not(feature = "bench"))]
    #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
    asked: Vec<String>,
}

#[cfg(feature = "bench")]
#[derive(Subcommand)]
pub enum BenchCommand {
    /// Read throughput of GRDECL and EGRID, ours beside resdata and xtgeo.
    Io {
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
        /// Folder of real models (default: ../shared/data beside the repository).
        #[arg(long)]
        data: Option<PathBuf>,
    },
    /// Decimation: fidelity of the original wireframe on decimated surfaces (geometric
    /// and in pixels) and speed, ours beside meshoptimizer's simplifiers.
    Lod {
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
        /// Folder of real models (default: ../shared/data beside the repository).
        #[arg(long)]
        data: Option<PathBuf>,
        /// 10 % only, one view, the smallest generated layer.
        #[arg(long)]
        quick: bool,
        /// Also write the frames of the hierarchy comparison as PNG into this folder.
        #[arg(long)]
        images: Option<PathBuf>,
    },
    /// Frame times of every wireframe technique against the shaded surface alone, in
    /// retained and immediate mode (Celes & Abraham's Tables 3 and 2).
    Wire {
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
        /// One 1M-triangle model and a few frames, not the full run.
        #[arg(long)]
        quick: bool,
        /// Only these mesh sizes, in this order (0.1m, 0.4m, 1m, 4m; default: all).
        #[arg(long, value_delimiter = ',')]
        sizes: Vec<String>,
        /// Only these mesh kinds, in this order (sphere, terrain, reservoir; default:
        /// all).
        #[arg(long, value_delimiter = ',')]
        kinds: Vec<String>,
        /// Major cell lines every N cells, as `render --major` (0: none).
        #[arg(long, value_name = "N", default_value_t = 10)]
        major: u32,
    },
    /// Line coverage of every wireframe technique against the exact coverage of the
    /// visible edges (16 x 16 samples per pixel): RMS error, missing and extra pixels.
    Quality {
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
        /// Also write every frame and reference as PNG into this folder.
        #[arg(long)]
        images: Option<PathBuf>,
    },
    /// Frame times of the retained scene renderer: the first frame (read, build,
    /// draw), and next frames of new cameras beside the renderer's own draw.
    Scene {
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
        /// Folder of real models (default: ../shared/data beside the repository).
        #[arg(long)]
        data: Option<PathBuf>,
    },
    /// Isoline quality against an analytic reference (16x16 supersampled) and frame
    /// times: texture isolines (adjust on/off) beside marching triangles + lines.
    Isolines {
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
    },
}

/// Runs the benchmark asked for and prints its report: a table, or JSON.
#[cfg(feature = "bench")]
pub fn run(args: BenchArgs) -> Result<()> {
    use strata::bench::{io, isolines, lod, quality, scene, wire};
    match args.command {
        BenchCommand::Io { json, data } => {
            let report = io::run(&data.unwrap_or_else(shared_data))?;
            print(&report, json, io::print_table)
        }
        BenchCommand::Lod {
            json,
            data,
            quick,
            images,
        } => {
            let config = if quick { &lod::QUICK } else { &lod::FULL };
            let data = data.unwrap_or_else(lod::default_data);
            let report = lod::run(&data, config, images.as_deref())?;
            print(&report, json, lod::print_table)
        }
        BenchCommand::Isolines { json } => print(&isolines::run()?, json, isolines::print_table),
        BenchCommand::Scene { json, data } => {
            let report = scene::run(&data.unwrap_or_else(shared_data))?;
            print(&report, json, scene::print_table)
        }
        BenchCommand::Wire {
            json,
            quick,
            sizes,
            kinds,
            major,
        } => {
            let plan = if quick {
                wire::Plan::quick()
            } else {
                wire::Plan::full()
            };
            let report = wire::run(&plan.major(major).select(&sizes, &kinds)?)?;
            print(&report, json, wire::print_table)
        }
        BenchCommand::Quality { json, images } => {
            let report = quality::run(images.as_deref())?;
            print(&report, json, quality::print_table)
        }
    }
}

/// Says how to build the benchmarks this build leaves out.
#[cfg(not(feature = "bench"))]
pub fn run(args: BenchArgs) -> Result<()> {
    anyhow::bail!(
        "this strata was built without its benchmarks; run them with `cargo run --release \
         --features bench -- bench {}`",
        args.asked.join(" ")
    )
}

/// The shared folder of real models beside the repository.
#[cfg(feature = "bench")]
fn shared_data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data")
}

/// Prints `report` as JSON, or as `table` prints it.
#[cfg(feature = "bench")]
fn print<R: serde::Serialize>(report: &R, json: bool, table: fn(&R)) -> Result<()> {
    if json {
        println!("{}", serde_json::to_string_pretty(report)?);
    } else {
        table(report);
    }
    Ok(())
}
