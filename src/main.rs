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
    /// Render layers shaded by a property with the cell wireframe to a PNG.
    Render(Box<cli::render::RenderArgs>),
    /// Triangulate scattered picks (or generated ones) into a terrain and render it
    /// with map grid lines to a PNG.
    Terrain(Box<cli::terrain::TerrainArgs>),
    /// Levels of detail: build a model's hierarchy file, or view one.
    #[command(subcommand)]
    Lod(cli::lod::LodCommand),
    /// Benchmarks (on demand; print a table, or JSON with --json).
    #[command(subcommand)]
    Bench(BenchCommand),
}

#[derive(Subcommand)]
enum BenchCommand {
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
        /// One 1M-triangle model and a few frames (under two minutes), not the full run.
        #[arg(long)]
        quick: bool,
        /// Only these mesh sizes, in this order (0.1m, 0.4m, 1m, 4m; default: all).
        #[arg(long, value_delimiter = ',')]
        sizes: Vec<String>,
        /// Only these mesh kinds, in this order (sphere, terrain, reservoir; default:
        /// all).
        #[arg(long, value_delimiter = ',')]
        kinds: Vec<String>,
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

fn main() -> ExitCode {
    quiet_on_closed_pipe();
    quiet_device_probe();
    let cli = Cli::parse();
    if matches!(cli.command, Command::Render(_) | Command::Bench(_)) {
        keep_freed_memory();
    }
    let result = match cli.command {
        Command::Info(args) => cli::info::run(&args),
        Command::Synth(args) => cli::synth::run(&args),
        Command::Render(args) => cli::render::run(&args),
        Command::Terrain(args) => cli::terrain::run(&args),
        Command::Lod(command) => cli::lod::run(&command),
        Command::Bench(BenchCommand::Io { json, data }) => bench_io(json, data),
        Command::Bench(BenchCommand::Lod {
            json,
            data,
            quick,
            images,
        }) => bench_lod(json, data, quick, images),
        Command::Bench(BenchCommand::Isolines { json }) => bench_isolines(json),
        Command::Bench(BenchCommand::Scene { json, data }) => bench_scene(json, data),
        Command::Bench(BenchCommand::Wire {
            json,
            quick,
            sizes,
            kinds,
        }) => bench_wire(json, quick, &sizes, &kinds),
        Command::Bench(BenchCommand::Quality { json, images }) => bench_quality(json, images),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("strata: {}", message(&e));
            ExitCode::FAILURE
        }
    }
}

/// Ends the process quietly, as Unix tools do, when whoever reads its output stops
/// (`strata info MODEL.lod | head`): Rust starts programs ignoring SIGPIPE, and the
/// next `println!` then panics on the closed pipe.
fn quiet_on_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: called first thing in `main`, before any other thread exists; SIG_DFL is
    // a valid disposition for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Keeps Mesa's Vulkan device-select layer from probing for a Wayland display where
/// there can be none: with `XDG_RUNTIME_DIR` unset (a headless machine, a CI job)
/// libwayland prints `error: XDG_RUNTIME_DIR is invalid or not set in the
/// environment.` twice before a correct picture, and a newcomer reads "error" as
/// failure. The layer only reorders adapters for a display's GPU; strata chooses its
/// adapter itself (`Gpu::new`), so nothing is lost. A user's own setting stands.
fn quiet_device_probe() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_none()
        && std::env::var_os("NODEVICE_SELECT").is_none()
    {
        // SAFETY: called first thing in `main`, before any other thread exists, so no
        // other thread reads the environment while it changes.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
}

/// Keeps freed memory in the process for the next allocation of about its size, for
/// the commands that make such allocations one after another: `render`, which draws a
/// large model in parts of about the same size, and the benchmarks, which repeat each
/// run (without it, every `bench lod` run paid system time to fault in fresh pages,
/// for ours and meshoptimizer's simplifiers alike).
///
/// glibc serves blocks above its mmap threshold (32 MiB at most when it adapts it)
/// with fresh maps and unmaps them when freed, so every part of a model drawn in
/// parts faults in newly zeroed pages. With large blocks taken from the heap and the
/// heap never trimmed, a large model's whole view was measured faster, with less
/// system time, at a slightly higher resident peak.
///
/// Not for `lod build`: its threads allocate from arenas of their own, which cannot
/// reuse what another thread's arena kept, so the kept memory only adds to the peak
/// (measured higher, at the same time). The figures are in docs/performance.md
/// ("Drawing in parts, and memory"; "How `bench lod` measures speed").
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: called from `main` before any other thread exists; mallopt only sets the
    // allocator's thresholds, and a refused value leaves glibc's default.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, i32::MAX);
        libc::mallopt(libc::M_TRIM_THRESHOLD, i32::MAX);
    }
}

/// The error and its causes, each after a colon, leaving out a cause whose text the
/// message already holds (the readers' I/O errors name their cause in their own text).
fn message(e: &anyhow::Error) -> String {
    let mut out = e.to_string();
    for cause in e.chain().skip(1) {
        let cause = cause.to_string();
        if !out.contains(&cause) {
            out = format!("{out}: {cause}");
        }
    }
    out
}

fn bench_lod(
    json: bool,
    data: Option<PathBuf>,
    quick: bool,
    images: Option<PathBuf>,
) -> anyhow::Result<()> {
    use strata::bench::lod;
    let data = data.unwrap_or_else(lod::default_data);
    let config = if quick { &lod::QUICK } else { &lod::FULL };
    let report = lod::run(&data, config, images.as_deref())?;
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        lod::print_table(&report);
    }
    Ok(())
}

fn bench_io(json: bool, data: Option<PathBuf>) -> anyhow::Result<()> {
    let data =
        data.unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data"));
    let report = strata::bench::io::run(&data)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        strata::bench::io::print_table(&report);
    }
    Ok(())
}

fn bench_wire(json: bool, quick: bool, sizes: &[String], kinds: &[String]) -> anyhow::Result<()> {
    use strata::bench::wire::{self, Plan};
    let plan = if quick { Plan::quick() } else { Plan::full() };
    let report = wire::run(&plan.select(sizes, kinds)?)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        wire::print_table(&report);
    }
    Ok(())
}

fn bench_isolines(json: bool) -> anyhow::Result<()> {
    let report = strata::bench::isolines::run()?;
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        strata::bench::isolines::print_table(&report);
    }
    Ok(())
}

fn bench_scene(json: bool, data: Option<PathBuf>) -> anyhow::Result<()> {
    let data =
        data.unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data"));
    let report = strata::bench::scene::run(&data)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        strata::bench::scene::print_table(&report);
    }
    Ok(())
}

fn bench_quality(json: bool, images: Option<PathBuf>) -> anyhow::Result<()> {
    use strata::bench::quality;
    let report = quality::run(images.as_deref())?;
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        quality::print_table(&report);
    }
    Ok(())
}
