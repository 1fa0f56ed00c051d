//! The `strata` command-line tool.

mod cli;

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
    /// The interactive window: turn the model, edit the scene in a side panel, pick
    /// cells (`--script` runs it unattended).
    #[cfg(feature = "viewer")]
    View(Box<cli::view::ViewArgs>),
    /// Benchmarks (on demand; print a table, or JSON with --json); in builds with
    /// `--features bench`.
    Bench(cli::bench::BenchArgs),
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
        Command::Bench(args) => cli::bench::run(args),
        #[cfg(feature = "viewer")]
        Command::View(args) => cli::view::run(&args),
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
