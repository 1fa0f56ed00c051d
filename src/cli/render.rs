//! `strata render`: a model's layers (and sides) shaded by a property with the cell
//! wireframe, to a PNG. The options become a [`Scene`] (or one is read from a file),
//! which the library's engine draws.

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;
use strata::render::RangeAdjust;
use strata::scene::{Lod, ModelSource, Scene};
use strata::{Frame, Note, SceneRenderer};

use super::ReadArgs;
use super::parse::{IsoSpacing, parse_iso};
use super::style::{FrameArgs, LayerArgs, StyleArgs};

/// The options that describe a scene, which a scene file replaces.
const SCENE_OPTIONS: [&str; 35] = [
    "model",
    "props",
    "grid_only",
    "layer",
    "layers",
    "i_range",
    "j_range",
    "inactive",
    "sides",
    "wire",
    "hidden",
    "thickness",
    "wire_color",
    "attenuate",
    "coverage",
    "isolation",
    "colormap",
    "grid_lines",
    "property",
    "no_property",
    "smooth",
    "step",
    "range",
    "scale",
    "no_legend",
    "zscale",
    "view",
    "centre",
    "size",
    "iso",
    "iso_adjust",
    "lod",
    "cover",
    "stitch",
    "part_cells",
];

#[derive(Args)]
pub struct RenderArgs {
    /// Model file (.grdecl, .DATA, .EGRID); the sample in data/ when omitted.
    model: Option<PathBuf>,
    /// Draw the scene saved in this JSON file (by --save-scene, a window or a script)
    /// instead of one the options describe; only -o and --save-scene go with it.
    #[arg(long, value_name = "FILE.json", conflicts_with_all = SCENE_OPTIONS)]
    scene: Option<PathBuf>,
    /// Also write the scene drawn, as JSON, to this file: `--scene` draws it again.
    #[arg(long, value_name = "FILE.json")]
    save_scene: Option<PathBuf>,
    #[command(flatten)]
    read: ReadArgs,
    #[command(flatten)]
    drawn: LayerArgs,
    #[command(flatten)]
    style: StyleArgs,
    /// Property colouring the cells (default: PORO when the model has it).
    #[arg(long)]
    property: Option<String>,
    /// Solid colour instead of a property.
    #[arg(long, conflicts_with = "property")]
    no_property: bool,
    /// Interpolate the property between nodes instead of painting cells flat.
    #[arg(long)]
    smooth: bool,
    /// Report step (its number, as `strata info` lists them) whose solution arrays
    /// colour the cells and draw isolines; the last step by default.
    #[arg(long, value_name = "N")]
    step: Option<i32>,
    #[command(flatten)]
    frame: FrameArgs,
    /// Output PNG.
    #[arg(short, long, default_value = "strata.png")]
    output: PathBuf,
    /// Isolines of a property: PROPERTY[:SPACING[:MAJOR_EVERY]] (spacing: about ten
    /// lines over the range when omitted; every fifth line major by default). Drawn
    /// with the global wireframe or none.
    #[arg(long, value_parser = parse_iso)]
    iso: Option<(String, IsoSpacing)>,
    /// Range adjust of the isolines: on, off, or the papers' formulas paper2010 and
    /// paper2011 (the latter moves lines: kept to show it).
    #[arg(long, default_value = "on", value_parser = parse_adjust)]
    iso_adjust: RangeAdjust,
    /// Decimate the drawn surfaces (strata-lod) to PERCENT of their triangles in all,
    /// split among them by how much of each the views around the model show (the tops
    /// between the first and the last hide under the others and keep fewer), and draw
    /// the wireframe on the result: global draws the original grid lines, tex/texgs
    /// the decimated triangles (quad, which needs cell faces, is refused). With global
    /// or none, each cell keeps its own colour (looked up by the global coordinates),
    /// and what the decimation moved beyond the original's cells (an outline corner
    /// cut outward) is not drawn, and the layers keep their order where they are
    /// thinner than the decimation's error (a surface that rose through the one above
    /// it stays hidden under it); with the others, colours are interpolated between
    /// nodes (decimated triangles are no longer cells). Says when a surface's share is
    /// below the triangles that keep every corner of its outlines, holes and fault
    /// traces; there meshoptimizer's simplify decimates instead, its result fitted to
    /// the original grid lines (as strata's is up to 2.5 times above that). With --iso the isolines are the original's:
    /// each fragment evaluates the original surface's field from its global
    /// coordinates, as it takes its cell's colour (--wire global or none).
    #[arg(long, value_name = "PERCENT", value_parser = parse_percent)]
    lod: Option<f64>,
    /// With --lod: let the outlines, holes and fault traces grow only outward in the
    /// decimation, never inward, so that drawn over the original's cells only (as
    /// every decimated surface is) those lines stay exactly the original's at any
    /// budget; the result is fitted to the original grid lines. Global wireframe only.
    #[arg(long, requires = "lod")]
    cover: bool,
    /// With --lod: close the slivers between surfaces that share an outline (the top
    /// and bottom against the side walls with --sides, a layer against the walls of a
    /// hole or fault): each surface is decimated on its own, keeping different nodes
    /// of the shared outline; each node one of them kept is put back into the others,
    /// a triangle each (where its own place would fold one: there all the same, as a
    /// triangle of its own, beyond an edge that cut its corner off, else on the edge
    /// it splits). It adds triangles: a share of those the decimation kept.
    #[arg(long, requires = "lod")]
    stitch: bool,
    /// Hold at most this many active cells' surfaces at a time. A scene with more is
    /// drawn in parts (runs of layers, a larger layer in bands of rows; tops, then the
    /// bottom, then sides), each dropped once drawn, so that a model of any size draws
    /// in about the memory of one part; the picture is the same. Parts leave out what
    /// needs the whole scene at once: --lod, --cover, --wire bias and idbuffer, and
    /// hidden-line styles other than tehs.
    #[arg(long, value_name = "CELLS", default_value_t = 2_000_000,
          value_parser = clap::value_parser!(u64).range(1..))]
    part_cells: u64,
}

fn parse_adjust(s: &str) -> Result<RangeAdjust, String> {
    RangeAdjust::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = RangeAdjust::ALL.iter().map(|(n, _)| *n).collect();
        format!("unknown range adjust {s:?}; one of {}", names.join(", "))
    })
}

/// `--lod PERCENT`: a share of the triangles in (0, 100].
pub fn parse_percent(s: &str) -> Result<f64, String> {
    s.trim()
        .trim_end_matches('%')
        .parse::<f64>()
        .ok()
        .filter(|p| *p > 0.0 && *p <= 100.0)
        .ok_or_else(|| format!("{s:?} is not a percentage in (0, 100]"))
}

impl RenderArgs {
    /// The scene these options describe.
    fn scene(&self) -> Result<Scene> {
        let path = self.model.clone().unwrap_or_else(strata::sample_model);
        let mut scene = Scene {
            model: Some(ModelSource {
                path,
                props: self.read.props.clone(),
                grid_only: self.read.grid_only,
            }),
            part_cells: self.part_cells,
            ..Scene::default()
        };
        self.drawn.apply(&mut scene);
        self.style.apply(&mut scene)?;
        self.frame.apply(&mut scene);
        scene.colour.property = self.property.clone();
        scene.colour.solid = self.no_property;
        scene.colour.smooth = self.smooth;
        scene.colour.step = self.step;
        scene.isolines = self.iso.as_ref().map(|(name, spacing)| {
            let mut spec = spacing.spec(Some(name));
            spec.adjust = self.iso_adjust;
            spec
        });
        if let Some(percent) = self.lod {
            scene.lod = Lod::Decimated {
                percent,
                cover: self.cover,
                stitch: self.stitch,
            };
        }
        Ok(scene)
    }
}

pub fn run(args: &RenderArgs) -> Result<()> {
    let scene = match &args.scene {
        Some(path) => Scene::load(path)?,
        None => args.scene()?,
    };
    let mut inputs = scene.inputs();
    inputs.extend(args.scene.clone());
    for output in std::iter::once(&args.output).chain(&args.save_scene) {
        super::refuse_overwriting(
            output,
            &inputs.iter().map(PathBuf::as_path).collect::<Vec<_>>(),
        )?;
    }
    if let Some(path) = &args.save_scene {
        scene.save(path)?;
    }
    let frame = draw(scene)?;
    super::save_picture(&frame, &args.output)?;
    report(&args.output, &frame);
    Ok(())
}

/// Draws `scene` with the library's engine, a bar on a terminal showing the passes
/// over a scene drawn in parts, and prints what reading and building had to say.
pub fn draw(scene: Scene) -> Result<Frame> {
    let mut engine = SceneRenderer::new(scene)?;
    engine.on_progress(super::progress_bars());
    let frame = engine.render()?;
    print_notes(&frame.report.notes);
    Ok(frame)
}

/// Prints the engine's notes on standard error as the command line words them.
pub fn print_notes(notes: &[Note]) {
    for note in notes {
        match note {
            Note::Warning(text) => eprintln!("strata: warning: {text}"),
            Note::Note(text) => eprintln!("note: {text}"),
            Note::Info(text) => eprintln!("{text}"),
        }
    }
}

/// Prints what a frame drew into `output`, in how long and on what.
pub fn report(output: &Path, frame: &Frame) {
    let r = &frame.report;
    eprintln!(
        "{}: {}, {} wireframe ({} coverage), {}; model read in {:.2} s, frame in {:.2} s on {}",
        output.display(),
        r.drawn,
        r.technique,
        match r.coverage {
            strata::render::Coverage::Texture => "texture",
            strata::render::Coverage::Analytic => "analytic",
        },
        match &r.colouring {
            Some((p, (lo, hi))) => format!("{p} {lo:.4}..{hi:.4}"),
            None => "solid colour".to_string(),
        },
        r.build_seconds,
        r.draw_seconds,
        r.adapter,
    );
}
