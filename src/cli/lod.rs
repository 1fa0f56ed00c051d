//! `strata lod`: build a level-of-detail hierarchy file of a model, and view one
//! (a scene of the hierarchy, drawn by the library's engine).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use strata::SceneRenderer;
use strata::lod::{BuildOptions, Options, Progress, ProgressFn, build_file};
use strata::scene::{Lod, Scene};

use super::ReadArgs;
use super::parse::{IsoSpacing, parse_iso_spacing, parse_zscale};
use super::style::{FrameArgs, LayerArgs, StyleArgs};

#[derive(Subcommand)]
pub enum LodCommand {
    /// Build the hierarchy of every layer surface of a model (on all cores) and save it.
    Build(BuildArgs),
    /// Open a saved hierarchy (memory mapped), choose the nodes a view needs for a
    /// given pixel error, print what was chosen, and draw it to a PNG with the lines
    /// and colours of `strata render`. With --wire global the original grid is drawn
    /// on whatever level is chosen, each cell in its own colour as the model's faces
    /// are (as with none, without the grid); with the others colours are interpolated
    /// between nodes. A layer is its top surface (and the model's bottom with the last
    /// layer), as the hierarchy stores them; its side faces are stored at full
    /// resolution and painted cell by cell as `strata render --sides` paints them.
    View(Box<ViewArgs>),
}

#[derive(Args)]
pub struct BuildArgs {
    /// Model file (.grdecl, .DATA, .EGRID).
    model: PathBuf,
    /// Output hierarchy file.
    #[arg(short, long)]
    output: PathBuf,
    /// Cells along each side of a leaf tile.
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=4096))]
    tile: u32,
    /// Vertical exaggeration the hierarchy will be viewed with (weighs vertical error).
    #[arg(long, default_value_t = 5.0, value_parser = parse_zscale)]
    zscale: f32,
    #[command(flatten)]
    read: ReadArgs,
    /// Property stored as the vertices' scalar (default: PORO when the model has it).
    #[arg(long)]
    property: Option<String>,
    /// Store no scalar.
    #[arg(long, conflicts_with = "property")]
    no_property: bool,
}

#[derive(Args)]
pub struct ViewArgs {
    /// Hierarchy file written by `strata lod build`.
    file: PathBuf,
    /// Largest projected error of a chosen node, in pixels (0: full resolution; inf:
    /// the coarsest level).
    #[arg(long, default_value_t = 1.0, value_parser = parse_pixels)]
    pixels: f32,
    #[command(flatten)]
    drawn: LayerArgs,
    #[command(flatten)]
    style: StyleArgs,
    /// Isolines of the stored property: [SPACING[:MAJOR_EVERY]] (about ten lines over
    /// its range when no spacing is given; every fifth line major). On whatever level is
    /// chosen they are the model's, evaluated from the full-resolution tiles under the
    /// chosen nodes, which this reads only for the tiles the view shows (as the cells'
    /// values), found by a first pass (--wire global or none).
    #[arg(long, value_name = "SPACING[:MAJOR_EVERY]", num_args = 0..=1, default_missing_value = "", value_parser = parse_iso_spacing)]
    iso: Option<IsoSpacing>,
    #[command(flatten)]
    frame: FrameArgs,
    /// Output PNG; only the selection is printed when omitted.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also write the scene, as JSON, to this file: `strata render --scene` draws it.
    #[arg(long, value_name = "FILE.json")]
    save_scene: Option<PathBuf>,
}

pub fn run(command: &LodCommand) -> Result<()> {
    match command {
        LodCommand::Build(args) => build(args),
        LodCommand::View(args) => view(args),
    }
}

fn build(args: &BuildArgs) -> Result<()> {
    let start = Instant::now();
    let inputs: Vec<&Path> = std::iter::once(args.model.as_path())
        .chain(args.read.props.iter().map(PathBuf::as_path))
        .collect();
    super::refuse_overwriting(&args.output, &inputs)?;
    let (model, notes) = super::open_model(Some(&args.model), &args.read)
        .with_context(|| format!("reading {}", args.model.display()))?;
    super::render::print_notes(&notes);
    let grid = model.grid;
    let read = start.elapsed().as_secs_f64();
    let property = if args.no_property {
        None
    } else {
        match &args.property {
            Some(p) => Some(p.clone()),
            None => grid.property("PORO").map(|_| "PORO".to_string()),
        }
    };
    let d = grid.dims();
    eprintln!(
        "{}: {} x {} x {} cells read in {read:.1} s; building {} layer surfaces on {}",
        args.model.display(),
        d.nx,
        d.ny,
        d.nz,
        d.nz + 1,
        match rayon::current_num_threads() {
            1 => "1 thread".to_string(),
            n => format!("{n} threads"),
        }
    );
    let bar = indicatif::ProgressBar::hidden();
    let options = BuildOptions {
        tile_cells: args.tile,
        decimation: Options {
            z_scale: args.zscale,
            ..Options::default()
        },
        progress: Some(progress_bar(bar.clone())),
        memory: super::available_memory().map(|bytes| bytes as u64),
        ..BuildOptions::default()
    };
    let report = build_file(&grid, property.as_deref(), &args.output, &options);
    bar.finish_and_clear();
    let report = report?;
    drop(grid);
    eprintln!(
        "{}: {} layer surfaces, {} nodes in {} levels, {} triangles in, {} stored, {} side \
         triangles, {}; built in {:.1} s, {:.1} s in all; peak memory {}",
        args.output.display(),
        report.layers,
        report.nodes,
        report.levels + 1,
        report.input_triangles,
        report.stored_triangles,
        report.side_triangles,
        size_text(report.bytes),
        report.seconds,
        start.elapsed().as_secs_f64(),
        strata::memory::peak_memory_kb().map_or("unknown".to_string(), |kb| size_text(kb * 1000)),
    );
    Ok(())
}

/// Draws a hierarchy build's progress on `bar`, on standard error (when it is a
/// terminal) once the build's length is known.
fn progress_bar(bar: indicatif::ProgressBar) -> ProgressFn {
    Arc::new(move |progress| match progress {
        Progress::Started { work, surfaces } => {
            bar.set_length(work);
            bar.set_message(format!("0/{surfaces} layer surfaces"));
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "{elapsed_precise} [{bar:40}] {percent:>3} %, {msg} (eta {eta})",
                )
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            // The clock moves while no tile ends: the side faces come first, and a root
            // takes a while.
            bar.enable_steady_tick(Duration::from_secs(1));
        }
        Progress::Worked(units) => bar.inc(units),
        Progress::Written {
            written,
            surfaces,
            input_triangles,
            stored_triangles,
        } => bar.set_message(format!(
            "{written}/{surfaces} layer surfaces, {:.1} M triangles in, {:.1} M stored",
            input_triangles as f64 / 1e6,
            stored_triangles as f64 / 1e6
        )),
    })
}

/// `bytes` in GB from a gigabyte up, else in MB.
pub fn size_text(bytes: u64) -> String {
    if bytes >= 1_000_000_000 {
        format!("{:.2} GB", bytes as f64 / 1e9)
    } else {
        format!("{:.1} MB", bytes as f64 / 1e6)
    }
}

impl ViewArgs {
    /// The scene these options describe.
    fn scene(&self) -> Result<Scene> {
        let mut scene = Scene {
            lod: Lod::Hierarchy {
                file: self.file.clone(),
                pixels: self.pixels,
            },
            ..Scene::default()
        };
        self.drawn.apply(&mut scene);
        self.style.apply(&mut scene)?;
        self.frame.apply(&mut scene);
        scene.isolines = self.iso.map(|iso| iso.spec(None));
        Ok(scene)
    }
}

fn view(args: &ViewArgs) -> Result<()> {
    let outputs = args.output.iter().chain(&args.save_scene);
    for output in outputs {
        super::refuse_overwriting(output, &[&args.file])?;
    }
    let scene = args.scene()?;
    if let Some(path) = &args.save_scene {
        scene.save(path)?;
    }
    let Some(output) = &args.output else {
        let mut engine = SceneRenderer::new(scene)?;
        super::render::print_notes(&engine.describe_selection()?);
        return Ok(());
    };
    let frame = super::render::draw(scene)?;
    super::save_picture(&frame, output)?;
    eprintln!("{}: {}", output.display(), frame.report.drawn);
    Ok(())
}

/// `--pixels PX`: a projected error of at least 0 pixels. NaN would choose nothing
/// coarser than the leaves (no error compares below it) without saying so.
fn parse_pixels(s: &str) -> Result<f32, String> {
    s.trim()
        .parse::<f32>()
        .ok()
        .filter(|p| *p >= 0.0)
        .ok_or_else(|| format!("{s:?} is not a number of pixels of at least 0"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixel_errors_and_percentages_are_checked() {
        assert_eq!(parse_pixels("0.5"), Ok(0.5));
        assert_eq!(parse_pixels("0"), Ok(0.0));
        assert_eq!(parse_pixels("inf"), Ok(f32::INFINITY));
        for bad in ["-1", "NaN", "nan", "", "1px"] {
            assert!(parse_pixels(bad).is_err(), "{bad}");
        }
    }
}
