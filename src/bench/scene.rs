//! `strata bench scene`: what the retained scene renderer costs per frame.
//!
//! A window turns the camera many times a second; the engine must then draw from what
//! it holds, not read and build again. For the sample, Reek (when `../shared/data` is
//! there) and a generated 500 x 500 x 20 model, this measures the first frame (read,
//! build, upload, draw), then frames of new cameras drawn by the engine beside the
//! same meshes drawn straight by the renderer (`Renderer::render` of a drawable
//! prepared once, the same view and style), camera by camera in one run: on a CPU
//! rasterizer only such ratios mean something.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
use serde::Serialize;
use strata_grid::synth::{SynthParams, generate};
use strata_render::glam::Vec3;
use strata_render::wgpu::DeviceType;
use strata_render::{Coverage, Style, View, WireMode};

use crate::scene::{CameraSpec, ModelSource, Scene};
use crate::surfaces::{SceneOptions, build, framing_of};
use crate::{SceneRenderer, engine::Model};

/// Frames of new cameras timed per model, after the first.
const FRAMES: usize = 6;
/// The generated model: large enough that drawing, not bookkeeping, is the cost.
const SYNTH: SynthParams = SynthParams {
    nx: 500,
    ny: 500,
    nz: 20,
    faults: 4,
    seed: 1,
};
/// Picture size of every frame.
const SIZE: [u32; 2] = [1000, 800];

/// What `strata bench scene` measured; `--json` prints it as is.
#[derive(Debug, Serialize)]
pub struct SceneReport {
    /// The adapter that drew, in words.
    pub adapter: String,
    /// Picture size.
    pub size: [u32; 2],
    /// One row per model.
    pub models: Vec<SceneTiming>,
    /// What was left out and why.
    pub notes: Vec<String>,
}

/// One model's frames.
#[derive(Debug, Serialize)]
pub struct SceneTiming {
    /// The model's name.
    pub model: String,
    /// Triangles drawn per frame.
    pub triangles: usize,
    /// Seconds of the first frame: reading, building, uploading and drawing.
    pub first_frame_s: f64,
    /// Seconds of each next frame the engine drew (a new camera each).
    pub next_frames_s: Vec<f64>,
    /// Seconds of the renderer drawing the same meshes for the same cameras.
    pub draw_frames_s: Vec<f64>,
    /// Median of `next_frames_s` (the upper one of an even count), seconds.
    pub next_frame_median_s: f64,
    /// Median of `draw_frames_s`, likewise, seconds.
    pub draw_median_s: f64,
    /// Next frame over the renderer's draw (medians): 1 is the draw alone.
    pub next_over_draw: f64,
    /// Contents the engine built over all the frames (1: built once).
    pub contents_built: usize,
}

/// Runs the benchmark with the models of `data_dir` that are there.
pub fn run(data_dir: &Path) -> Result<SceneReport> {
    let tmp = tempfile::tempdir().context("creating a temporary folder")?;
    let generated = tmp.path().join("synth-500x500x20.egrid");
    let grid = generate(&SYNTH).context("generating the benchmark model")?;
    strata_grid::save(&grid, &generated)?;
    drop(grid);
    let reek = data_dir.join("reek");
    let mut models = vec![(
        "sample".to_string(),
        ModelSource::new(crate::sample_model()),
    )];
    let mut notes = Vec::new();
    if reek.is_dir() {
        let mut source = ModelSource::new(reek.join("REEK.EGRID"));
        source.props.push(reek.join("reek_sim_poro.grdecl"));
        models.push(("reek".to_string(), source));
    } else {
        notes.push(format!("{}: not found, Reek left out", reek.display()));
    }
    models.push(("synth-500x500x20".to_string(), ModelSource::new(generated)));
    let mut report = SceneReport {
        adapter: String::new(),
        size: SIZE,
        models: Vec::new(),
        notes,
    };
    for (name, source) in models {
        let (timing, adapter) = time_model(&name, source)?;
        report.adapter = adapter;
        report.models.push(timing);
    }
    Ok(report)
}

/// The first frame of the model at `source`, then [`FRAMES`] cameras each drawn by the
/// engine and by the renderer straight.
fn time_model(name: &str, source: ModelSource) -> Result<(SceneTiming, String)> {
    let scene = Scene {
        model: Some(source.clone()),
        size: SIZE,
        // Whole, as a window holds it: a scene in parts is built part by part each
        // frame, by design, to draw in the memory of one part.
        part_cells: u64::MAX,
        ..Scene::default()
    };
    let start = Instant::now();
    let mut engine = SceneRenderer::new(scene.clone())?;
    let first = engine.render()?;
    let first_frame_s = start.elapsed().as_secs_f64();
    // The same meshes, built and uploaded once, for the renderer to draw straight.
    let (model, _) = Model::open(&source)?;
    let options = SceneOptions {
        layers: None,
        sides: false,
        property: model.colouring_property(None, false),
        flat_cells: true,
        cut: None,
        inactive: false,
    };
    let (mesh, range) = build(&model.grid, &options)?;
    drop(model);
    let renderer = engine.renderer()?;
    let drawable = renderer.prepare(&mesh, WireMode::Global)?;
    let style = Style {
        coverage: match renderer.gpu.info.device_type {
            DeviceType::Cpu => Coverage::Analytic,
            _ => Coverage::Texture,
        },
        scalar_range: range,
        ..Style::default()
    };
    let (mut next_frames_s, mut draw_frames_s) = (Vec::new(), Vec::new());
    for n in 1..=FRAMES {
        let camera = CameraSpec {
            azimuth: scene.camera.azimuth + 60.0 * n as f32,
            ..scene.camera
        };
        engine.set_scene(Scene {
            camera,
            ..scene.clone()
        })?;
        let start = Instant::now();
        engine.render()?;
        next_frames_s.push(start.elapsed().as_secs_f64());
        let mut framing = framing_of(
            None,
            camera.z_scale,
            SIZE[0] as f32 / SIZE[1] as f32,
            (camera.azimuth, camera.elevation),
        );
        framing.add(mesh.positions.iter().map(|&p| Vec3::from(p)));
        let bounds = framing.bounds().context("an empty mesh")?;
        let view = View {
            camera: framing.camera(camera.distance),
            width: SIZE[0],
            height: SIZE[1],
            bounds,
        };
        let renderer = engine.renderer()?;
        let start = Instant::now();
        renderer.render(&[drawable.as_ref()], &view, &style)?;
        draw_frames_s.push(start.elapsed().as_secs_f64());
    }
    let adapter = engine.renderer()?.gpu.describe();
    let (next, draw) = (median(&next_frames_s), median(&draw_frames_s));
    let timing = SceneTiming {
        model: name.to_string(),
        triangles: first.report.triangles,
        first_frame_s,
        next_frame_median_s: next,
        draw_median_s: draw,
        next_over_draw: next / draw,
        next_frames_s,
        draw_frames_s,
        contents_built: engine.counters().contents_built,
    };
    Ok((timing, adapter))
}

/// The median of `values` (the upper middle one of an even count), NaN when empty.
fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN)
}

/// Prints the report as a table.
pub fn print_table(report: &SceneReport) {
    println!(
        "scene frames at {}x{} on {}",
        report.size[0], report.size[1], report.adapter
    );
    println!(
        "{:<18} {:>10} {:>10} {:>10} {:>10} {:>8} {:>6}",
        "model", "triangles", "first s", "next s", "draw s", "next/draw", "built"
    );
    for m in &report.models {
        println!(
            "{:<18} {:>10} {:>10.3} {:>10.3} {:>10.3} {:>8.3} {:>6}",
            m.model,
            m.triangles,
            m.first_frame_s,
            m.next_frame_median_s,
            m.draw_median_s,
            m.next_over_draw,
            m.contents_built
        );
    }
    for note in &report.notes {
        println!("note: {note}");
    }
}
