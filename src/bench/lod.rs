//! `strata bench lod`: how faithfully decimated surfaces still carry the original
//! wireframe, ours beside meshoptimizer's simplifiers, and how fast each decimates.
//!
//! Fidelity, for every real model of the shared data folder (all its layer surfaces,
//! as `strata render` draws them: the top of every layer and the bottom of the last)
//! and budgets of 50, 20, 10, 5 and 2 % of the triangles (the model's budget split
//! among its layer surfaces by how much of each is seen, `strata_lod::share_budget`
//! as `strata render --lod` splits it, for every simplifier alike; `strata_even`
//! is `strata` with the budget split evenly, each surface at that share of its own):
//! * geometric: points along every original cell edge (4 per edge) against the point
//!   of the decimated surface with the same texture coordinates, in the display frame
//!   with the vertical exaggeration of the views (5): largest and RMS distance, also
//!   as a fraction of the model's extent (its bounding box diagonal in that frame);
//! * image: the original mesh and each decimated one drawn with the global wireframe
//!   at 1000 x 800 from two fixed views. Line pixels come from frames of the lines
//!   alone (isolation, solid colour on black: a pixel is a line pixel where the line
//!   covers at least half of it); F1 of the decimated frame's line pixels against the
//!   original's, each pixel matching within one pixel (8-neighbourhood: a line moved
//!   by under a pixel is where it was), and strictly; RMS colour difference of the
//!   shaded frames (0-255 per channel, surface coloured by PORO when the model has it:
//!   the original's cell faces painted flat, as `strata render` draws them, and every
//!   decimated surface coloured cell by cell by its global coordinates and trimmed
//!   to the original's cells (the cell mask, `CellDraw::mask`: what decimation moved
//!   beyond its piece's cells is not drawn), its layer surfaces kept in their order
//!   in the depth test by their vertical deviations (`CellDraw::stacking`: a surface
//!   that rose through the one above it stays under it), as `strata render --lod`
//!   draws it: `Renderer::prepare_cells`; every simplifier's result alike).
//!
//! Outlines: per real model, the corners of its layer outlines and the fewest
//! triangles that keep them all (`strata_lod::measure::outline_bound`), against the
//! goal's 10 % budget: where the budget is smaller, every simplifier must cut outline
//! corners, and the line-pixel F1 drops where they are cut inward (the cell mask trims
//! what is cut outward), for a reason no simplifier can help.
//!
//! `strata` is what strata draws with (`strata_lod::decimate_chosen`): ours, fitted
//! to the grid lines (`strata_lod::fit`) where the budget is under 2.5 times its
//! outline bound, or, on a layer surface whose budget is under 1.5 times that bound,
//! meshopt_simplify's result fitted to them (the rows count those layers). Ours
//! alone runs with both placements of new vertices: `strata_alone` (on the original
//! surface, the default) and `strata_optimal` (at the quadric optimum off it, with the
//! texture coordinates of the nearest original point), and as `strata_cover`: outlines
//! that only grow outward (`Options::cover`), so that with the cell mask outline
//! corners cost no triangles, and fitted to the grid lines, as
//! `strata render --lod PERCENT --cover` draws it.
//!
//! `meshopt_clusterlod` is meshoptimizer's cluster LOD DAG cut at one error where it
//! fits the budget (`strata_lod::baseline`): its cuts come in steps of a group of
//! clusters, so it may keep well under the budget, and over it on a layer too small to
//! simplify (rows over the budget are not compared with ours); its speed rows time
//! building the whole DAG, every level, where the simplifiers make one.
//!
//! Hierarchies: on a generated layer of about 0.5 (quick) or 2 million triangles a
//! surface, `strata lod build`'s tiled quadtree against the clusterlod DAG, both cut
//! at 1 px of projected error from the fidelity views and a close-up: triangles
//! stored and drawn, build CPU time, line-pixel F1 and RMS colour against the
//! full-resolution surface; `--images DIR` writes those frames.
//!
//! Speed: input triangles per second for ours and each meshopt simplifier at 10 %,
//! on the real models and on generated faulted layers of about 0.5, 2 and 8 million
//! triangles, all in one thread (so per core; decimation itself is sequential) and ours
//! also on all cores across layer surfaces; CPU seconds beside wall seconds, since the
//! machine may be shared, and each row's rate per CPU second over meshopt_simplify's
//! on the same input (the ratio a slower or busier machine changes least). An input
//! that takes under [`MIN_CPU_SECONDS`] runs again until it has taken that much, and
//! that sample gives the mean per run; the rows of ours and meshopt_simplify in one
//! thread are the median of [`GOAL_SAMPLES`] samples, with the range of their rates.
//! Every input runs once untimed before its rows, as warm-up. Our stages
//! (reference, setup, evaluating, collapsing, the final lift) are timed for
//! profiling. Peak memory is the process's VmHWM at the end.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Result;
use serde::Serialize;

use crate::memory::peak_memory_kb;
use crate::metrics::{f1, line_mask};
use strata_grid::synth::{SynthParams, generate};
use strata_grid::{CornerPointGrid, Face, ReadOptions, SurfaceMesh, Surfaces, layer_surfaces};
use strata_lod::baseline::{ClusterLod, Simplifier, simplify, submesh};
use strata_lod::measure::{Deviation, OutlineBound, deviation, outline_bound};
use strata_lod::{
    BuildOptions, CellCover, Decimated, LodFile, Maker, Options, Placement, ViewPoint, build_file,
    decimate, decimate_chosen, share_surfaces,
};
use strata_render::glam::Vec3;
use strata_render::{
    Camera, CellDraw, Renderer, Stacking, Style, TiledCells, View, WireMode, stack_pushes,
};

const WIDTH: u32 = 1000;
const HEIGHT: u32 = 800;
/// Vertical exaggeration of the views (`strata render`'s default).
const Z_SCALE: f32 = 5.0;
/// Points sampled along each original cell edge for the geometric measure.
const SAMPLES_PER_EDGE: usize = 4;

/// What to run.
pub struct Config {
    /// Budgets of the fidelity rows, percent of the model's triangles.
    budgets: &'static [f64],
    /// Views as (azimuth, elevation) in degrees.
    views: &'static [(f32, f32)],
    /// Triangle counts of the generated layers.
    generated: &'static [usize],
    /// Triangle counts of the generated layers whose hierarchies are compared.
    hierarchy: &'static [usize],
}

/// The whole benchmark: five budgets, two views, generated layers of 0.5, 2 and 8
/// million triangles, hierarchies on the 2-million one.
pub const FULL: Config = Config {
    budgets: &[50.0, 20.0, 10.0, 5.0, 2.0],
    views: &[(30.0, 35.0), (210.0, 60.0)],
    generated: &[500_000, 2_000_000, 8_000_000],
    hierarchy: &[2_000_000],
};

/// `--quick`, to try a change without the whole run: 10 % only, one view, the
/// smallest generated layer.
pub const QUICK: Config = Config {
    budgets: &[10.0],
    views: &[(30.0, 35.0)],
    generated: &[500_000],
    hierarchy: &[500_000],
};

/// The speed goal is checked on inputs of at least this many triangles: below, a run
/// is dominated by what every call costs whatever its size (simpleb8's 58 triangles
/// run far below the goal in every simplifier; docs/performance.md).
const GOAL_RATE_MIN_TRIANGLES: usize = 10_000;

/// A speed row runs its input until it has taken at least this much CPU time (the
/// process CPU clock counts in 10 ms ticks), at most `MAX_REPEATS` times (a bound
/// for a clock that does not advance, well above the repeats the smallest real model
/// needs). Long enough that the row of the generated 0.5-million-triangle layer is
/// the mean of several runs, not one: single runs of it vary widely between bench runs
/// on a shared machine (figures: docs/performance.md, "How `bench lod` measures
/// speed").
const MIN_CPU_SECONDS: f64 = 1.5;
const MAX_REPEATS: usize = 100_000;

/// Samples of the rows the speed goal and the ratios rest on (ours and
/// meshopt_simplify, one thread): a run of a large generated layer can outlast
/// [`MIN_CPU_SECONDS`], so that its sample is a single run, and on a shared machine
/// one run can be well slower than the next with the same code (figures:
/// docs/performance.md, "How `bench lod` measures speed").
const GOAL_SAMPLES: usize = 3;

/// The budget the goals are stated at.
const GOAL_BUDGET: f64 = 10.0;
const GOAL_F1: f64 = 0.95;
const GOAL_RATE: f64 = 1e6;

/// What `--json` prints.
#[derive(Debug, Serialize)]
pub struct LodReport {
    /// The GPU adapter that drew the frames, in words.
    pub adapter: String,
    /// Cores available to the process: the threads of the all-cores speed rows.
    pub cores: usize,
    /// Per real model, what keeping its layer outlines costs at the goal's budget.
    pub outlines: Vec<Outline>,
    /// Per real model, simplifier and budget, in that order.
    pub fidelity: Vec<Fidelity>,
    /// Per input (real models, then generated layers) and simplifier.
    pub speed: Vec<Speed>,
    /// Per generated layer and hierarchy.
    pub hierarchy: Vec<HierarchyRow>,
    /// The goals checked against the rows above.
    pub goals: Vec<Goal>,
    /// Peak resident memory of the run (VmHWM), MB.
    pub peak_memory_mb: f64,
    /// The load average at start and end, models left out and why, rows over their
    /// budget, layers whose budget is below their outline bound.
    pub notes: Vec<String>,
}

/// What keeping a real model's layer outlines costs, against the goal's budget.
#[derive(Debug, Serialize)]
pub struct Outline {
    /// The model's label (`reek`, `spe9` ...).
    pub model: String,
    /// Triangles of all its layer surfaces.
    pub triangles: usize,
    /// Corners of the outlines of all layer surfaces (`strata_lod::measure::outline_bound`).
    pub corners: usize,
    /// The fewest triangles that keep every corner, summed over the layer surfaces.
    pub min_triangles: usize,
    /// Triangles at the goal's budget (10 %), summed as the surfaces are decimated.
    pub goal_budget_triangles: usize,
    /// Layer surfaces whose share of the 10 % budget is below their own
    /// `min_triangles`: there any simplifier must cut outline corners.
    pub layers_below: usize,
    /// Layer surfaces of the model.
    pub layers: usize,
    /// Per layer surface (tops, then the bottom of the last), the fraction of it seen
    /// from around the model (`Renderer::visible_fractions`).
    pub visible: Vec<f64>,
    /// Per layer surface, its share of the 10 % budget.
    pub goal_split: Vec<usize>,
}

/// One model, simplifier and budget.
#[derive(Debug, Serialize)]
pub struct Fidelity {
    /// The model's label.
    pub model: String,
    /// Who decimated: `strata`, `strata_even`, `strata_alone`, `strata_optimal`,
    /// `strata_cover`, or a meshopt simplifier's name (see the module's doc).
    pub simplifier: String,
    /// The budget, percent of the model's triangles.
    pub budget_percent: f64,
    /// Triangles of the original layer surfaces.
    pub triangles: usize,
    /// The budget in triangles, summed over the layer surfaces.
    pub budget_triangles: usize,
    /// Triangles of the decimated layer surfaces.
    pub kept_triangles: usize,
    /// Largest distance of the original grid lines (4 points per cell edge) from the
    /// decimated surface's point of the same texture coordinates, in display units
    /// (metres, depth times [`Z_SCALE`]).
    pub line_max: f64,
    /// RMS of the same distances over all samples of all layer surfaces.
    pub line_rms: f64,
    /// `line_max` over the model's extent (its bounding box diagonal, depth scaled).
    pub line_max_rel: f64,
    /// `line_rms` over the model's extent.
    pub line_rms_rel: f64,
    /// Share of samples whose texture coordinate the decimated surface no longer
    /// draws (outside its simplified boundary).
    pub outside: f64,
    /// Layer surfaces that meshoptimizer decimated (`strata` only: under 1.5 times
    /// the outline bound).
    pub meshopt_layers: usize,
    /// Worst view's F1 of the decimated frame's line pixels against the original's,
    /// each matching within one pixel (0..1).
    pub f1: f64,
    /// Worst view's F1 with pixels matching only where they are (0..1).
    pub f1_strict: f64,
    /// Worst view's RMS colour difference of the shaded frames (0-255 per channel).
    pub rms_colour: f64,
    /// Per view.
    pub views: Vec<ViewScore>,
}

/// One view's comparison of a decimated model's frames with the original's, at
/// 1000 x 800 pixels.
#[derive(Debug, Serialize)]
pub struct ViewScore {
    /// Camera azimuth, degrees.
    pub azimuth: f32,
    /// Camera elevation, degrees.
    pub elevation: f32,
    /// Share of the decimated frame's line pixels with an original one within one
    /// pixel (0..1).
    pub precision: f64,
    /// Share of the original's line pixels with a decimated one within one pixel.
    pub recall: f64,
    /// Harmonic mean of `precision` and `recall` (0 where nothing was drawn).
    pub f1: f64,
    /// The same with pixels matching only where they are.
    pub f1_strict: f64,
    /// RMS colour difference of the shaded frames (0-255 per channel; NaN where
    /// nothing was drawn).
    pub rms_colour: f64,
}

/// One input and simplifier at 10 %.
#[derive(Debug, Serialize)]
pub struct Speed {
    /// The input: a real model's label, or `generated NxN`.
    pub input: String,
    /// Triangles of the input, all its layer surfaces.
    pub triangles: usize,
    /// Who decimated, named as in [`Fidelity`].
    pub simplifier: String,
    /// Threads decimating the layer surfaces (1, or every core for ours).
    pub threads: usize,
    /// Samples taken ([`GOAL_SAMPLES`] for the rows the speed goal and the ratios rest
    /// on, else one); the row is the median sample by CPU time.
    pub samples: usize,
    /// Runs measured together in that sample (inputs too small for one run to
    /// register on the CPU clock run again); the times below are per run.
    pub repeats: usize,
    /// Wall seconds of one run (the sample's mean).
    pub seconds: f64,
    /// CPU seconds of one run, user and system, all threads of the process.
    pub cpu_seconds: f64,
    /// The part of `cpu_seconds` spent in the kernel: mostly first touches of fresh
    /// memory, which a virtual machine makes costly (docs/performance.md, "How
    /// `bench lod` measures speed").
    pub system_seconds: f64,
    /// Input triangles per wall second.
    pub triangles_per_s: f64,
    /// Input triangles per CPU second: per core.
    pub triangles_per_cpu_s: f64,
    /// The slowest and the fastest sample's `triangles_per_cpu_s`.
    pub triangles_per_cpu_s_range: [f64; 2],
    /// `triangles_per_cpu_s` over meshopt_simplify's, one thread, on the same input in
    /// the same run: what a shared or slower machine changes least.
    pub per_cpu_s_over_meshopt_simplify: Option<f64>,
    /// Our stages, seconds summed over the layer surfaces (ours only).
    pub stages: Option<Stages>,
}

/// One generated layer's top surface, drawn through a hierarchy.
#[derive(Debug, Serialize)]
pub struct HierarchyRow {
    /// The generated layer, `generated NxN`.
    pub input: String,
    /// `strata` (`strata lod build`'s tiled quadtree), `meshopt_clusterlod`, or
    /// `meshopt_clusterlod_same_triangles` (its cut at as many triangles as ours).
    pub hierarchy: String,
    /// Full-resolution triangles of the top surface.
    pub triangles: usize,
    /// Triangles over all levels of the surfaces built: ours builds the layer's top
    /// and bottom as `lod build` does, clusterlod the top alone.
    pub stored_triangles: usize,
    /// CPU seconds of building them on one thread.
    pub build_cpu_seconds: f64,
    /// Full-resolution triangles of the surfaces built.
    pub built_triangles: usize,
    /// Per view: the fidelity views of the whole layer, then the close-up.
    pub views: Vec<HierarchyView>,
}

/// What one hierarchy draws from one view at `HIERARCHY_PIXELS`.
#[derive(Debug, Serialize)]
pub struct HierarchyView {
    /// The view: `AZIMUTH,ELEVATION whole`, or `30,20 close-up xZOOM`.
    pub view: String,
    /// Line pixels of the full-resolution surface from this view: where they cover
    /// most of the surface (a whole view of a large layer), F1 says little.
    pub line_pixels: usize,
    /// Triangles the hierarchy's cut draws from this view.
    pub drawn_triangles: usize,
    /// Line pixels against the full-resolution surface's, as in [`Fidelity`].
    pub f1: f64,
    /// The same with pixels matching only where they are.
    pub f1_strict: f64,
    /// RMS colour difference of the shaded frames (0-255 per channel).
    pub rms_colour: f64,
}

/// Our decimation's stages (`strata_lod::Timings`): seconds of one run, summed over
/// the layer surfaces.
#[derive(Debug, Default, Serialize)]
pub struct Stages {
    /// Preparing the reference surface (triangle adjacency).
    pub reference: f64,
    /// Quadrics, boundary and vertex lists.
    pub setup: f64,
    /// Evaluating every edge, each pass.
    pub evaluate: f64,
    /// Choosing and making the collapses, each pass.
    pub collapse: f64,
    /// The final fit to the grid lines, where made.
    pub lift: f64,
    /// The most passes any layer surface took.
    pub passes: usize,
}

/// One goal, and whether this run met it.
#[derive(Debug, Serialize)]
pub struct Goal {
    /// What is measured, and on which model or input.
    pub goal: String,
    /// The measured value: an F1 (0..1) or input triangles per CPU second.
    pub value: f64,
    /// The least value that meets the goal.
    pub threshold: f64,
    /// Whether `value` is at least `threshold`.
    pub met: bool,
}

/// A real model to measure.
struct Model {
    label: &'static str,
    file: &'static str,
    grid_only: bool,
}

const MODELS: [Model; 5] = [
    Model {
        label: "reek",
        file: "reek/REEK.EGRID",
        grid_only: false,
    },
    Model {
        label: "spe9",
        file: "spe9/BENCH_SPE9.EGRID",
        grid_only: false,
    },
    Model {
        label: "emerald",
        file: "emerald/eme_small_w_hole_grid_params.grdecl",
        grid_only: false,
    },
    Model {
        label: "simpleb8",
        file: "simpleb8/E100_BO.EGRID",
        grid_only: false,
    },
    Model {
        label: "spe10model2",
        file: "spe10model2/SPE10_MODEL2.DATA",
        grid_only: true,
    },
];

/// Who decimates.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Method {
    /// What strata draws with ([`decimate_chosen`]): ours (fitted to the grid lines
    /// near the outline bound), or meshopt_simplify's fitted to them below it or just
    /// above it.
    Strata,
    /// The same, with the budget split evenly among the layer surfaces (each keeps the
    /// same share of its triangles) instead of by how much of each is seen.
    StrataEven,
    /// Ours alone.
    Ours(Placement),
    /// Ours with outlines that only grow outward, drawn with the cell mask.
    OursCover,
    Meshopt(Simplifier),
}

impl Method {
    fn all() -> Vec<Method> {
        [
            Method::Strata,
            Method::StrataEven,
            Method::Ours(Placement::Surface),
            Method::Ours(Placement::Optimal),
            Method::OursCover,
        ]
        .into_iter()
        .chain(Simplifier::ALL.into_iter().map(Method::Meshopt))
        .collect()
    }

    fn name(self) -> &'static str {
        match self {
            Method::Strata => "strata",
            Method::StrataEven => "strata_even",
            Method::Ours(Placement::Surface) => "strata_alone",
            Method::Ours(Placement::Optimal) => "strata_optimal",
            Method::OursCover => "strata_cover",
            Method::Meshopt(s) => s.name(),
        }
    }

    /// The decimation of `mesh` to `target` triangles, and whether meshoptimizer made
    /// it for [`Method::Strata`].
    fn run(self, mesh: &SurfaceMesh, target: usize) -> Result<(Decimated, bool)> {
        let fraction = target as f64 / mesh.triangle_count().max(1) as f64;
        let ours = |placement| Options {
            target_triangles: target,
            z_scale: Z_SCALE,
            placement,
            ..Options::default()
        };
        Ok(match self {
            Method::Strata | Method::StrataEven => {
                let chosen = decimate_chosen(mesh, &ours(Placement::Surface))?;
                (chosen.decimated, chosen.maker == Maker::Meshopt)
            }
            Method::Ours(placement) => (decimate(mesh, &ours(placement))?, false),
            Method::OursCover => (
                decimate_chosen(
                    mesh,
                    &Options {
                        target_triangles: target,
                        z_scale: Z_SCALE,
                        ..Options::covering(mesh, fraction)
                    },
                )?
                .decimated,
                false,
            ),
            Method::Meshopt(s) => (simplify(mesh, s, target, Z_SCALE)?, false),
        })
    }
}

/// The triangles a layer surface is decimated to at `fraction` of its own.
fn budget_of(mesh: &SurfaceMesh, fraction: f64) -> usize {
    (mesh.triangle_count() as f64 * fraction).round() as usize
}

/// Per layer surface, its triangles at `fraction` of the model's: split by how much of
/// each is seen (`strata_lod::share_surfaces`, as `strata render --lod` splits it), or
/// evenly, each at `fraction` of its own.
fn targets(layers: &[SurfaceMesh], visible: &[f64], fraction: f64, even: bool) -> Vec<usize> {
    if even {
        return layers.iter().map(|m| budget_of(m, fraction)).collect();
    }
    share_surfaces(fraction, layers, visible)
}

/// The layer surfaces of `grid` as `strata render` draws them, with PORO as scalar
/// when the model has it.
fn surfaces(grid: &CornerPointGrid) -> Result<Vec<SurfaceMesh>> {
    let nz = grid.dims().nz;
    let property = grid.property("PORO").map(|_| "PORO");
    let origin = grid.display_origin();
    (0..nz)
        .map(|k| (k, Face::Top))
        .chain((nz > 0).then_some((nz - 1, Face::Bottom)))
        .map(|(k, face)| {
            Ok(layer_surfaces(
                grid,
                face,
                &Surfaces::layer(k, origin).property(property),
            )?)
        })
        .collect()
}

/// `f` over `items` on `threads` threads (each takes the next item when done), results
/// in the order of `items`. One thread is the calling one: a speed row of a small
/// input would otherwise time starting a thread each run.
fn par_map<T: Sync, R: Send>(items: &[T], threads: usize, f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    if threads <= 1 {
        return items.iter().map(f).collect();
    }
    use std::sync::Mutex;
    use std::sync::atomic::{AtomicUsize, Ordering};
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<R>>> = Mutex::new((0..items.len()).map(|_| None).collect());
    std::thread::scope(|scope| {
        for _ in 0..threads.clamp(1, items.len().max(1)) {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(item) = items.get(i) else {
                        break;
                    };
                    let r = f(item);
                    if let Ok(mut all) = results.lock() {
                        all[i] = Some(r);
                    }
                }
            });
        }
    });
    results
        .into_inner()
        .unwrap_or_default()
        .into_iter()
        .flatten()
        .collect()
}

fn append_all(meshes: &[SurfaceMesh], origin: [f64; 3]) -> SurfaceMesh {
    let mut all = SurfaceMesh::with_origin(origin);
    for m in meshes {
        all.append(m);
    }
    all
}

/// Process CPU seconds so far: user and system.
fn cpu_times() -> (f64, f64) {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return (f64::NAN, f64::NAN);
    };
    // Fields after the command name (which may hold spaces) start past the last ')'.
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map_or("", |(_, rest)| rest)
        .split_whitespace()
        .collect();
    let ticks = |i: usize| fields.get(i).and_then(|v| v.parse::<f64>().ok());
    // utime and stime are fields 14 and 15 of the line, 12 and 13 after the name.
    match (ticks(11), ticks(12)) {
        (Some(u), Some(s)) => (u / 100.0, s / 100.0),
        _ => (f64::NAN, f64::NAN),
    }
}

fn rms_colour(a: &[u8], b: &[u8]) -> f64 {
    let (sum, n) =
        a.chunks_exact(4)
            .zip(b.chunks_exact(4))
            .fold((0f64, 0usize), |(s, n), (p, q)| {
                let d: f64 = (0..3)
                    .map(|c| (f64::from(p[c]) - f64::from(q[c])).powi(2))
                    .sum();
                (s + d, n + 3)
            });
    (sum / n.max(1) as f64).sqrt()
}

/// The two frames compared per view: lines alone (for the line pixels) and shaded.
struct Frames {
    lines: Vec<bool>,
    shaded: Vec<u8>,
}

struct Scene {
    views: Vec<View>,
    range: Option<(f32, f32)>,
}

impl Scene {
    fn new(original: &SurfaceMesh, config: &Config) -> Option<Self> {
        let (lo, hi) = original.bounds()?;
        let bounds = (Vec3::from(lo), Vec3::from(hi));
        let views = config
            .views
            .iter()
            .map(|&(az, el)| View {
                camera: Camera::fit_points(
                    original.positions.iter().map(|&p| Vec3::from(p)),
                    Z_SCALE,
                    WIDTH as f32 / HEIGHT as f32,
                    (az, el),
                    1.0,
                ),
                width: WIDTH,
                height: HEIGHT,
                bounds,
            })
            .collect();
        let range = crate::surfaces::colour_range(original.scalars.iter().copied());
        Some(Scene { views, range })
    }

    /// Frames of `mesh` from the scene's views, drawn against the original's `cells`
    /// when given.
    fn draw(
        &self,
        renderer: &mut Renderer,
        mesh: &SurfaceMesh,
        cells: Option<&CellDraw>,
    ) -> Result<Vec<Frames>> {
        self.draw_from(renderer, mesh, cells, &self.views)
    }

    /// Frames of `mesh` from `views`, in the scene's colours.
    fn draw_from(
        &self,
        renderer: &mut Renderer,
        mesh: &SurfaceMesh,
        cells: Option<&CellDraw>,
        views: &[View],
    ) -> Result<Vec<Frames>> {
        let drawable = match cells {
            Some(cells) => renderer.prepare_cells(mesh, cells)?,
            None => renderer.prepare(mesh, WireMode::Global)?,
        };
        let solid = Style::default().solid_color;
        let line_luma = 255.0
            * (0.299 * f64::from(solid[0])
                + 0.587 * f64::from(solid[1])
                + 0.114 * f64::from(solid[2]));
        views
            .iter()
            .map(|view| {
                let lines = renderer.render(
                    &[drawable.as_ref()],
                    view,
                    &Style {
                        isolation: true,
                        background: [0.0, 0.0, 0.0, 1.0],
                        ..Style::default()
                    },
                )?;
                let shaded = renderer.render(
                    &[drawable.as_ref()],
                    view,
                    &Style {
                        scalar_range: self.range,
                        ..Style::default()
                    },
                )?;
                Ok(Frames {
                    lines: line_mask(lines.as_raw(), line_luma),
                    shaded: shaded.into_raw(),
                })
            })
            .collect()
    }
}

/// Runs the benchmark on the models of `data_dir` (skipped, with a note, when absent);
/// with `images`, writes the frames of the hierarchy comparison there as PNG.
pub fn run(data_dir: &Path, config: &Config, images: Option<&Path>) -> Result<LodReport> {
    let mut renderer = Renderer::headless()?;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut notes = vec![load_average("start")];
    let models = read_models(data_dir, &mut notes)?;

    let mut outlines = Vec::new();
    let mut fidelity = Vec::new();
    for (label, layers) in &models {
        let visible = visible_fractions(&mut renderer, layers)?;
        let outline = outline_of(label, layers, &visible);
        notes.extend(outline_note(&outline));
        outlines.push(outline);
        match Original::new(&mut renderer, config, label, layers, visible)? {
            Some(original) => {
                fidelity.extend(original.fidelity_rows(&mut renderer, config, cores)?)
            }
            None => notes.push(format!("{label}: no triangle")),
        }
    }
    notes.extend(over_budget_notes(&fidelity));

    let speed = measure_speed(models, config, cores)?;
    let hierarchy = compare_hierarchies(&mut renderer, config, images)?;
    let goals = goals(&fidelity, &speed);
    notes.push(load_average("end"));
    notes.push(
        "CPU seconds are the process's (all threads); per-core rates divide input triangles by them. \
         Rates of tiny models (simpleb8) are dominated by fixed costs."
            .to_string(),
    );
    Ok(LodReport {
        adapter: renderer.gpu.describe(),
        cores,
        outlines,
        fidelity,
        speed,
        hierarchy,
        goals,
        peak_memory_mb: peak_memory_kb().map_or(f64::NAN, |kb| kb as f64 / 1e3),
        notes,
    })
}

/// The note of the machine's load average (`/proc/loadavg`) at `when`.
fn load_average(when: &str) -> String {
    format!(
        "load average at {when}: {}",
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .trim()
    )
}

/// The layer surfaces of every model of [`MODELS`] under `data_dir`, with its label;
/// a model that does not read, or a missing folder, is left out with a note.
fn read_models(
    data_dir: &Path,
    notes: &mut Vec<String>,
) -> Result<Vec<(String, Vec<SurfaceMesh>)>> {
    let mut models = Vec::new();
    if !data_dir.is_dir() {
        notes.push(format!(
            "{}: no such folder, real models skipped",
            data_dir.display()
        ));
        return Ok(models);
    }
    for m in &MODELS {
        let path = data_dir.join(m.file);
        let options = ReadOptions {
            grid_only: m.grid_only,
            ..ReadOptions::default()
        };
        match strata_grid::open_with(&path, &options) {
            Ok(grid) => models.push((m.label.to_string(), surfaces(&grid)?)),
            Err(e) => notes.push(format!("{}: not measured: {e}", path.display())),
        }
    }
    Ok(models)
}

/// Per layer surface, the fraction of it seen from around the model (all of it when
/// there is one).
fn visible_fractions(renderer: &mut Renderer, layers: &[SurfaceMesh]) -> Result<Vec<f64>> {
    Ok(if layers.len() > 1 {
        renderer.visible_fractions(&layers.iter().collect::<Vec<_>>(), Z_SCALE, None)?
    } else {
        vec![1.0; layers.len()]
    })
}

/// What keeping the outlines of `layers` costs against the goal's budget, split by
/// `visible` as the fidelity rows split it.
fn outline_of(label: &str, layers: &[SurfaceMesh], visible: &[f64]) -> Outline {
    let goal_split = targets(layers, visible, GOAL_BUDGET / 100.0, false);
    let bounds: Vec<(usize, OutlineBound)> = layers
        .iter()
        .zip(&goal_split)
        .map(|(m, &budget)| (budget, outline_bound(m)))
        .collect();
    Outline {
        model: label.to_string(),
        triangles: layers.iter().map(SurfaceMesh::triangle_count).sum(),
        corners: bounds.iter().map(|(_, b)| b.corners).sum(),
        min_triangles: bounds.iter().map(|(_, b)| b.min_triangles).sum(),
        goal_budget_triangles: bounds.iter().map(|(n, _)| n).sum(),
        layers_below: bounds.iter().filter(|(n, b)| *n < b.min_triangles).count(),
        layers: layers.len(),
        visible: visible.to_vec(),
        goal_split,
    }
}

/// The note of a model some of whose layer surfaces must lose outline corners at the
/// goal's budget, if any must.
fn outline_note(outline: &Outline) -> Option<String> {
    (outline.layers_below > 0).then(|| {
        format!(
            "{}: at {GOAL_BUDGET} % the budget of {} of its {} layer surfaces is below the \
             triangles that keep their outline corners ({} triangles for {} corners in all, \
             budget {}): there every simplifier cuts corners of the outline, and the \
             lines it cuts inward are lost (the cell mask trims what it cuts outward)",
            outline.model,
            outline.layers_below,
            outline.layers,
            outline.min_triangles,
            outline.corners,
            outline.goal_budget_triangles
        )
    })
}

/// A real model ready for its fidelity rows: its layer surfaces, the frames of the
/// original, and its cells, which every decimated surface is drawn against.
struct Original<'a> {
    label: &'a str,
    layers: &'a [SurfaceMesh],
    /// Per layer surface, the fraction of it seen: how the budget is split.
    visible: Vec<f64>,
    /// The display origin of the first layer surface, shared by the appended meshes.
    origin: [f64; 3],
    /// The layer surfaces appended.
    mesh: SurfaceMesh,
    scene: Scene,
    /// The bounding box diagonal, depth exaggerated: what the relative line distances
    /// are over.
    extent: f64,
    /// The original's frames from the scene's views.
    reference: Vec<Frames>,
    cells: ModelCells,
}

impl<'a> Original<'a> {
    /// The model of `layers`, its original drawn from the views of `config`; `None`
    /// when it has no triangle.
    fn new(
        renderer: &mut Renderer,
        config: &Config,
        label: &'a str,
        layers: &'a [SurfaceMesh],
        visible: Vec<f64>,
    ) -> Result<Option<Self>> {
        let origin = layers.first().map_or([0.0; 3], |m| m.origin);
        let mesh = append_all(layers, origin);
        let Some(scene) = Scene::new(&mesh, config) else {
            return Ok(None);
        };
        let extent = extent(&mesh);
        let reference = scene.draw(renderer, &mesh.with_cell_values(), None)?;
        let cells = ModelCells::of(layers, !mesh.scalars.is_empty())?;
        eprintln!(
            "{label}: {} triangles in {} layer surfaces",
            mesh.triangle_count(),
            layers.len()
        );
        Ok(Some(Original {
            label,
            layers,
            visible,
            origin,
            mesh,
            scene,
            extent,
            reference,
            cells,
        }))
    }

    /// Every simplifier's row at every budget of `config`, reported on stderr as
    /// they come.
    fn fidelity_rows(
        &self,
        renderer: &mut Renderer,
        config: &Config,
        cores: usize,
    ) -> Result<Vec<Fidelity>> {
        let mut rows = Vec::new();
        for method in Method::all() {
            for &budget in config.budgets {
                let row = self.fidelity_row(renderer, config, cores, method, budget)?;
                log_fidelity(&row);
                rows.push(row);
            }
        }
        Ok(rows)
    }

    /// `method`'s decimation of the model at `budget` percent of its triangles,
    /// measured against the original: its grid lines' distances and its frames.
    fn fidelity_row(
        &self,
        renderer: &mut Renderer,
        config: &Config,
        cores: usize,
        method: Method,
        budget: f64,
    ) -> Result<Fidelity> {
        let even = method == Method::StrataEven;
        let split = targets(self.layers, &self.visible, budget / 100.0, even);
        let (decimated, by_meshopt) = decimate_layers(self.layers, &split, method, cores)?;
        let mesh = append_all(
            &decimated.iter().map(|d| d.mesh.clone()).collect::<Vec<_>>(),
            self.origin,
        );
        let devs = self.deviations(&decimated, cores);
        let lines = LineDistances::of(&devs);
        let frames = if mesh.is_empty() {
            None
        } else {
            Some(self.draw_decimated(renderer, &mesh, &decimated, &devs)?)
        };
        let views = view_scores(config, &self.reference, frames.as_deref());
        Ok(Fidelity {
            model: self.label.to_string(),
            simplifier: method.name().to_string(),
            budget_percent: budget,
            triangles: self.mesh.triangle_count(),
            budget_triangles: split.iter().sum(),
            kept_triangles: mesh.triangle_count(),
            line_max: lines.max,
            line_rms: lines.rms,
            line_max_rel: lines.max / self.extent,
            line_rms_rel: lines.rms / self.extent,
            outside: lines.outside,
            meshopt_layers: by_meshopt.iter().filter(|&&b| b).count(),
            f1: views.iter().map(|v| v.f1).fold(1.0, f64::min),
            f1_strict: views.iter().map(|v| v.f1_strict).fold(1.0, f64::min),
            rms_colour: views.iter().map(|v| v.rms_colour).fold(0.0, f64::max),
            views,
        })
    }

    /// Per layer surface, its original grid lines measured on its decimation.
    fn deviations(&self, decimated: &[Decimated], cores: usize) -> Vec<Deviation> {
        let pairs: Vec<(&SurfaceMesh, &Decimated)> = self.layers.iter().zip(decimated).collect();
        par_map(&pairs, cores, |(o, d)| {
            deviation(o, &d.mesh, &d.home, SAMPLES_PER_EDGE, f64::from(Z_SCALE))
        })
    }

    /// Frames of the decimated `mesh` (the layer surfaces' `decimated` appended) as
    /// `render --lod` draws it: coloured cell by cell and trimmed to the original's
    /// cells, the layer surfaces kept in their order in the depth test.
    fn draw_decimated(
        &self,
        renderer: &mut Renderer,
        mesh: &SurfaceMesh,
        decimated: &[Decimated],
        devs: &[Deviation],
    ) -> Result<Vec<Frames>> {
        let pieces = self.pieces(decimated, mesh.vertex_count());
        let push = self.cells.pushes(devs);
        let cells = CellDraw {
            pieces: &pieces,
            cover: &self.cells.cover,
            values: self.cells.values.as_deref().map(TiledCells::boxes),
            corners: None,
            mask: true,
            wire: true,
            stacking: Some(Stacking { push: &push }),
        };
        self.scene.draw(renderer, mesh, Some(&cells))
    }

    /// Per vertex of the decimated layer surfaces appended (`vertices` in all), its
    /// piece of the model's cover.
    fn pieces(&self, decimated: &[Decimated], vertices: usize) -> Vec<u32> {
        let mut pieces = Vec::with_capacity(vertices);
        for (((layer, c), d), first) in self
            .layers
            .iter()
            .zip(&self.cells.layers)
            .zip(decimated)
            .zip(&self.cells.first_piece)
        {
            // An unknown piece stays unknown, which the renderer refuses.
            pieces.extend(
                d.pieces(layer, c)
                    .into_iter()
                    .map(|p| p.saturating_add(*first)),
            );
        }
        pieces
    }
}

/// A model's cells as its decimated surfaces are drawn against them: each layer
/// surface's cover, and one cover of the model's as its meshes are appended.
struct ModelCells {
    /// Per layer surface, its cells.
    layers: Vec<CellCover>,
    /// The layer surfaces' covers appended.
    cover: CellCover,
    /// Per layer surface, the index of its first piece in `cover`.
    first_piece: Vec<u32>,
    /// The cells' scalar values, piece by piece of `cover`, when the model has them.
    values: Option<Vec<f32>>,
}

impl ModelCells {
    /// The cells of `layers`, with their values when `with_values`.
    fn of(layers: &[SurfaceMesh], with_values: bool) -> Result<Self> {
        let layer_covers = layers
            .iter()
            .map(CellCover::of)
            .collect::<strata_lod::Result<Vec<_>>>()?;
        let mut cover = CellCover::default();
        let mut first_piece = Vec::with_capacity(layers.len());
        for c in &layer_covers {
            first_piece.push(cover.pieces.len() as u32);
            cover.append(c);
        }
        let values = if with_values {
            let per_layer = layers
                .iter()
                .zip(&layer_covers)
                .map(|(layer, c)| c.values(layer))
                .collect::<strata_lod::Result<Vec<_>>>()?;
            Some(per_layer.concat())
        } else {
            None
        };
        Ok(ModelCells {
            layers: layer_covers,
            cover,
            first_piece,
            values,
        })
    }

    /// Per piece of the cover, the push of its layer surface in the depth test
    /// (`stack_pushes` of the surfaces' vertical deviations), as `render --lod` keeps
    /// the layers' order.
    fn pushes(&self, devs: &[Deviation]) -> Vec<Option<f32>> {
        let surface_push =
            stack_pushes(&devs.iter().map(|d| d.vertical as f32).collect::<Vec<_>>());
        let mut push = vec![None; self.cover.pieces.len()];
        for (k, &first) in self.first_piece.iter().enumerate() {
            let end = self
                .first_piece
                .get(k + 1)
                .map_or(push.len(), |&e| e as usize);
            push[first as usize..end].fill(Some(surface_push[k]));
        }
        push
    }
}

/// The bounding box diagonal of `mesh` in the display frame (depth times
/// [`Z_SCALE`]), never 0.
fn extent(mesh: &SurfaceMesh) -> f64 {
    let (lo, hi) = mesh.bounds().unwrap_or(([0.0; 3], [0.0; 3]));
    let d = [hi[0] - lo[0], hi[1] - lo[1], (hi[2] - lo[2]) * Z_SCALE];
    f64::from(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        .sqrt()
        .max(f64::MIN_POSITIVE)
}

/// `method`'s decimation of each of `layers` to its triangles of `split`, on `cores`
/// threads, and whether meshoptimizer made it.
fn decimate_layers(
    layers: &[SurfaceMesh],
    split: &[usize],
    method: Method,
    cores: usize,
) -> Result<(Vec<Decimated>, Vec<bool>)> {
    let jobs: Vec<(&SurfaceMesh, usize)> = layers.iter().zip(split.iter().copied()).collect();
    Ok(par_map(&jobs, cores, |&(m, target)| method.run(m, target))
        .into_iter()
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .unzip())
}

/// The original grid lines' distances over all layer surfaces.
struct LineDistances {
    /// Largest, display units.
    max: f64,
    /// RMS over all samples, display units.
    rms: f64,
    /// Share of the samples outside the decimated surfaces.
    outside: f64,
}

impl LineDistances {
    /// The layer surfaces' deviations together.
    fn of(devs: &[Deviation]) -> Self {
        let samples: usize = devs.iter().map(|d| d.samples).sum();
        let max = devs.iter().map(|d| d.max).fold(0.0, f64::max);
        let rms = (devs
            .iter()
            .map(|d| d.rms * d.rms * d.samples as f64)
            .sum::<f64>()
            / samples.max(1) as f64)
            .sqrt();
        let outside = devs.iter().map(|d| d.outside).sum::<usize>() as f64 / samples.max(1) as f64;
        LineDistances { max, rms, outside }
    }
}

/// Per view of `config`, the decimated `frames` (`None`: nothing drawn) against the
/// original's `reference`.
fn view_scores(config: &Config, reference: &[Frames], frames: Option<&[Frames]>) -> Vec<ViewScore> {
    config
        .views
        .iter()
        .enumerate()
        .map(|(v, &(azimuth, elevation))| {
            let want = &reference[v];
            let (precision, recall, f, strict, rms) = match frames {
                Some(f) => {
                    let (p, r, f1v) = f1(&f[v].lines, &want.lines, WIDTH as usize, 1);
                    let (_, _, s) = f1(&f[v].lines, &want.lines, WIDTH as usize, 0);
                    (p, r, f1v, s, rms_colour(&f[v].shaded, &want.shaded))
                }
                None => (0.0, 0.0, 0.0, 0.0, f64::NAN),
            };
            ViewScore {
                azimuth,
                elevation,
                precision,
                recall,
                f1: f,
                f1_strict: strict,
                rms_colour: rms,
            }
        })
        .collect()
}

/// A fidelity row on stderr, as it comes.
fn log_fidelity(row: &Fidelity) {
    eprintln!(
        "  {:<20} {:>5.1} %: {:>8} triangles, lines max {:.2e} rms {:.2e} of the extent, F1 {:.3} (strict {:.3}), RMS colour {:.2}",
        row.simplifier,
        row.budget_percent,
        row.kept_triangles,
        row.line_max_rel,
        row.line_rms_rel,
        row.f1,
        row.f1_strict,
        row.rms_colour
    );
}

/// A note for every fidelity row with more triangles than its budget.
fn over_budget_notes(fidelity: &[Fidelity]) -> Vec<String> {
    fidelity
        .iter()
        .filter(|f| f.kept_triangles > f.budget_triangles)
        .map(|f| {
            format!(
                "{} {} at {} %: {} triangles, over its budget of {}",
                f.model, f.simplifier, f.budget_percent, f.kept_triangles, f.budget_triangles
            )
        })
        .collect()
}

/// The speed rows: the real `models` (all their layer surfaces), then the generated
/// layers of `config`.
fn measure_speed(
    models: Vec<(String, Vec<SurfaceMesh>)>,
    config: &Config,
    cores: usize,
) -> Result<Vec<Speed>> {
    let mut inputs = models;
    for &n in config.generated {
        let (label, grid) = generated_layer(n)?;
        inputs.push((label, vec![top_surface(&grid)?]));
    }
    let mut speed = Vec::new();
    for (label, layers) in &inputs {
        // One untimed run first. A fresh process's first run on a large input pays for
        // the virtual machine backing its new memory, which is not decimation: its
        // system time and rate would skew the row (figures: docs/performance.md, "How
        // `bench lod` measures speed").
        for layer in layers {
            Method::Strata.run(layer, budget_of(layer, GOAL_BUDGET / 100.0))?;
        }
        for (method, threads) in speed_runs(layers.len(), cores) {
            let row = speed_row(label, layers, method, threads)?;
            log_speed(&row);
            speed.push(row);
        }
        set_ratios(&mut speed, label);
    }
    Ok(speed)
}

/// The rows timed on an input of `layers` surfaces: every method on one thread, and
/// ours on all `cores` where there are several surfaces to share among them.
fn speed_runs(layers: usize, cores: usize) -> Vec<(Method, usize)> {
    let mut runs: Vec<(Method, usize)> = Method::all().into_iter().map(|m| (m, 1)).collect();
    if layers > 1 && cores > 1 {
        runs.push((Method::Ours(Placement::Surface), cores));
    }
    runs
}

/// `method` timed on the input `layers` in `threads`: the median of its samples
/// ([`GOAL_SAMPLES`] for the rows the goal and the ratios rest on, else one).
fn speed_row(label: &str, layers: &[SurfaceMesh], method: Method, threads: usize) -> Result<Speed> {
    let triangles: usize = layers.iter().map(SurfaceMesh::triangle_count).sum();
    let goal_row = threads == 1
        && matches!(
            method,
            Method::Strata | Method::Meshopt(Simplifier::Simplify)
        );
    let samples = (0..if goal_row { GOAL_SAMPLES } else { 1 })
        .map(|_| speed_sample(layers, method, threads))
        .collect::<Result<Vec<_>>>()?;
    let count = samples.len();
    let (median, [slowest, fastest]) = median_sample(samples);
    let rate = |cpu: f64| triangles as f64 / cpu;
    Ok(Speed {
        input: label.to_string(),
        triangles,
        simplifier: method.name().to_string(),
        threads,
        samples: count,
        repeats: median.repeats,
        seconds: median.seconds,
        cpu_seconds: median.cpu(),
        system_seconds: median.system,
        triangles_per_s: triangles as f64 / median.seconds,
        triangles_per_cpu_s: rate(median.cpu()),
        triangles_per_cpu_s_range: [rate(slowest), rate(fastest)],
        per_cpu_s_over_meshopt_simplify: None,
        stages: median.stages,
    })
}

/// A speed row on stderr, as it comes.
fn log_speed(row: &Speed) {
    eprintln!(
        "  {:<24} {:>9} triangles {:<20} {} thread(s), median of {} sample(s) of {} run(s): {:.3} s ({:.3} CPU s, {:.3} system) a run, {:.2} M/s, {:.2} M/CPU s ({:.2}-{:.2})",
        row.input,
        row.triangles,
        row.simplifier,
        row.threads,
        row.samples,
        row.repeats,
        row.seconds,
        row.cpu_seconds,
        row.system_seconds,
        row.triangles_per_s / 1e6,
        row.triangles_per_cpu_s / 1e6,
        row.triangles_per_cpu_s_range[0] / 1e6,
        row.triangles_per_cpu_s_range[1] / 1e6
    );
}

/// Sets every row of the input `label` to its rate over meshopt_simplify's on one
/// thread, where that row is there.
fn set_ratios(speed: &mut [Speed], label: &str) {
    let simplify = Simplifier::Simplify.name();
    let rows: Vec<&mut Speed> = speed.iter_mut().filter(|s| s.input == label).collect();
    if let Some(theirs) = rows
        .iter()
        .find(|s| s.simplifier == simplify && s.threads == 1)
        .map(|s| s.triangles_per_cpu_s)
    {
        for row in rows {
            row.per_cpu_s_over_meshopt_simplify = Some(row.triangles_per_cpu_s / theirs);
        }
    }
}

/// A generated faulted layer of about `n` triangles a surface, and its label.
fn generated_layer(n: usize) -> Result<(String, CornerPointGrid)> {
    let side = ((n as f64 / 2.0).sqrt().round() as usize).max(2);
    let grid = generate(&SynthParams {
        nx: side,
        ny: side,
        nz: 1,
        faults: 6,
        seed: 5,
    })?;
    Ok((format!("generated {side}x{side}"), grid))
}

/// The top surface of a generated layer, coloured by PORO.
fn top_surface(grid: &CornerPointGrid) -> Result<SurfaceMesh> {
    Ok(layer_surfaces(
        grid,
        Face::Top,
        &Surfaces::layer(0, grid.display_origin()).property(Some("PORO")),
    )?)
}

/// The largest projected error both hierarchies are cut at: `strata lod view`'s
/// default.
const HIERARCHY_PIXELS: f32 = 1.0;

/// The close-up of the hierarchy comparison is the whole view's distance times this
/// over the cells across the layer.
const CLOSE_UP_CELLS: f32 = 75.0;

/// Our tiled hierarchy against meshoptimizer's cluster LOD on generated layers. Each
/// is built, then cut at [`HIERARCHY_PIXELS`] from the fidelity views of the whole
/// layer and from a close-up over its middle, nodes or clusters outside the view left
/// out; the rows give the triangles drawn and the line-pixel F1 and RMS colour against
/// the full-resolution top surface from the same view. The two measure error apart
/// (ours the largest distance to the original surface, clusterlod meshoptimizer's
/// quadric error), so clusterlod is also cut at the projected error that draws as many
/// triangles as ours from each view (`meshopt_clusterlod_same_triangles`). With
/// `images`, the shaded frames go there as PNG.
fn compare_hierarchies(
    renderer: &mut Renderer,
    config: &Config,
    images: Option<&Path>,
) -> Result<Vec<HierarchyRow>> {
    if let Some(dir) = images {
        std::fs::create_dir_all(dir)?;
    }
    let mut rows = Vec::new();
    for &n in config.hierarchy {
        let (label, grid) = generated_layer(n)?;
        let top = top_surface(&grid)?;
        let Some(mut scene) = Scene::new(&top, config) else {
            continue;
        };
        let aspect = WIDTH as f32 / HEIGHT as f32;
        let (lo, hi) = scene.views[0].bounds;
        // Near enough that the nearest cells span several pixels whatever the layer's
        // size (the whole views of a large layer show no line: they fade out).
        let zoom = (CLOSE_UP_CELLS / grid.dims().nx as f32).min(1.0);
        let close = Camera::fit_points(
            top.positions.iter().map(|&p| Vec3::from(p)),
            Z_SCALE,
            aspect,
            (30.0, 20.0),
            zoom,
        )
        .centred_on((lo + hi) / 2.0);
        scene.views.push(View {
            camera: close,
            ..scene.views[0]
        });
        let mut names: Vec<String> = config
            .views
            .iter()
            .map(|(az, el)| format!("{az},{el} whole"))
            .collect();
        names.push(format!("30,20 close-up x{zoom:.3}"));
        let reference = scene.draw(renderer, &top, None)?;

        let dir = tempfile::tempdir()?;
        let path = dir.path().join("layer.lod");
        // On one thread, as clusterlod builds: rayon's idle threads spin for a while
        // before they sleep, which a build on all cores counts as CPU time.
        let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
        let before = cpu_times();
        let report = one_thread
            .install(|| build_file(&grid, Some("PORO"), &path, &BuildOptions::default()))?;
        let ours_cpu = cpu_since(before);
        let file = LodFile::open(&path)?;
        let before = cpu_times();
        let dag = ClusterLod::build(&top, Z_SCALE)?;
        let theirs_cpu = cpu_since(before);

        let mut ours = Vec::new();
        let mut theirs = Vec::new();
        let mut theirs_matched = Vec::new();
        for (v, view) in scene.views.iter().enumerate() {
            let camera = &view.camera;
            let point = ViewPoint {
                eye: camera.eye.to_array(),
                z_scale: Z_SCALE,
                fov_y_deg: camera.fov_y_deg,
                height_px: HEIGHT,
                frustum: Some(camera.frustum(aspect)),
            };
            let chosen: Vec<u32> = file
                .select(&point, HIERARCHY_PIXELS)
                .into_iter()
                .filter(|&i| file.nodes()[i as usize].layer == 0)
                .collect();
            let cut = |pixels: f64| dag.cut_in_view(&point, pixels);
            let selection = file.selection_mesh(&chosen)?;
            if let Some(dir) = images {
                save_frame(dir, &format!("{label}_view{v}_full"), &reference[v].shaded)?;
            }
            let matched = pixels_for_triangles(cut, selection.triangle_count());
            for (mesh, out, name) in [
                (selection, &mut ours, "strata"),
                (
                    submesh(&top, &cut(f64::from(HIERARCHY_PIXELS))),
                    &mut theirs,
                    "clusterlod",
                ),
                (
                    submesh(&top, &cut(matched)),
                    &mut theirs_matched,
                    "clusterlod_same",
                ),
            ] {
                let frames = scene.draw_from(renderer, &mesh, None, std::slice::from_ref(view))?;
                let (got, want) = (&frames[0], &reference[v]);
                if let Some(dir) = images {
                    save_frame(dir, &format!("{label}_view{v}_{name}"), &got.shaded)?;
                }
                out.push(HierarchyView {
                    view: names[v].clone(),
                    line_pixels: want.lines.iter().filter(|&&l| l).count(),
                    drawn_triangles: mesh.triangle_count(),
                    f1: f1(&got.lines, &want.lines, WIDTH as usize, 1).2,
                    f1_strict: f1(&got.lines, &want.lines, WIDTH as usize, 0).2,
                    rms_colour: rms_colour(&got.shaded, &want.shaded),
                });
            }
        }
        for (name, stored, cpu, built, views) in [
            (
                "strata",
                report.stored_triangles,
                ours_cpu,
                report.input_triangles,
                ours,
            ),
            (
                "meshopt_clusterlod",
                dag.stored_triangles(),
                theirs_cpu,
                top.triangle_count(),
                theirs,
            ),
            (
                "meshopt_clusterlod_same_triangles",
                dag.stored_triangles(),
                theirs_cpu,
                top.triangle_count(),
                theirs_matched,
            ),
        ] {
            for v in &views {
                eprintln!(
                    "  {label} {name:<34} {:<22} {:>9} triangles drawn, F1 {:.3} (strict {:.3}) of {} line pixels, RMS colour {:.2}",
                    v.view, v.drawn_triangles, v.f1, v.f1_strict, v.line_pixels, v.rms_colour
                );
            }
            rows.push(HierarchyRow {
                input: label.clone(),
                hierarchy: name.to_string(),
                triangles: top.triangle_count(),
                stored_triangles: stored,
                build_cpu_seconds: cpu,
                built_triangles: built,
                views,
            });
        }
    }
    Ok(rows)
}

/// The projected error at which `cut` (indices at a largest error in pixels) draws
/// the most triangles not above `triangles`: triangles only fall as the error rises.
fn pixels_for_triangles(cut: impl Fn(f64) -> Vec<u32>, triangles: usize) -> f64 {
    let (mut fine, mut coarse) = (1e-3f64, 1e6f64);
    for _ in 0..40 {
        let mid = (fine * coarse).sqrt();
        if cut(mid).len() / 3 > triangles {
            fine = mid;
        } else {
            coarse = mid;
        }
    }
    coarse
}

/// Writes a frame of [`WIDTH`] x [`HEIGHT`] RGBA bytes to `dir/name.png`.
fn save_frame(dir: &Path, name: &str, rgba: &[u8]) -> Result<()> {
    let frame = strata_render::image::RgbaImage::from_raw(WIDTH, HEIGHT, rgba.to_vec())
        .ok_or_else(|| anyhow::anyhow!("{name}: a frame of the wrong size"))?;
    let name = name.replace([' ', ','], "_");
    strata_render::save_png(&frame, &dir.join(format!("{name}.png")))?;
    Ok(())
}

/// One speed measurement ([`speed_sample`]); times per run.
struct SpeedSample {
    repeats: usize,
    seconds: f64,
    user: f64,
    system: f64,
    /// Ours only.
    stages: Option<Stages>,
}

impl SpeedSample {
    fn cpu(&self) -> f64 {
        self.user + self.system
    }
}

/// The median of `samples` by CPU time, and the largest and the smallest CPU time.
fn median_sample(mut samples: Vec<SpeedSample>) -> (SpeedSample, [f64; 2]) {
    samples.sort_by(|a, b| b.cpu().total_cmp(&a.cpu()));
    let extremes = [samples[0].cpu(), samples[samples.len() - 1].cpu()];
    let median = samples.swap_remove(samples.len() / 2);
    (median, extremes)
}

/// Times `method` on `layers` at the goal's budget, in `threads`, its runs repeated
/// while under [`MIN_CPU_SECONDS`].
fn speed_sample(layers: &[SurfaceMesh], method: Method, threads: usize) -> Result<SpeedSample> {
    // The threads take no more CPU time than wall time together, so the CPU clock is
    // read (from /proc, which costs a small input's run) only once the wall clock
    // says it may be due.
    let (wall, cpu) = (Instant::now(), cpu_times());
    let mut repeats = 0;
    let (results, user, system) = loop {
        let results: Vec<Decimated> = par_map(layers, threads, |m| {
            method.run(m, budget_of(m, GOAL_BUDGET / 100.0))
        })
        .into_iter()
        .map(|r| r.map(|(d, _)| d))
        .collect::<Result<_>>()?;
        repeats += 1;
        let due = wall.elapsed().as_secs_f64() * threads as f64 >= MIN_CPU_SECONDS;
        if !due && repeats < MAX_REPEATS {
            continue;
        }
        let now = cpu_times();
        let (user, system) = (now.0 - cpu.0, now.1 - cpu.1);
        if user + system >= MIN_CPU_SECONDS || repeats == MAX_REPEATS || user.is_nan() {
            break (results, user / repeats as f64, system / repeats as f64);
        }
    };
    let seconds = wall.elapsed().as_secs_f64() / repeats as f64;
    let stages =
        matches!(method, Method::Strata | Method::Ours(_) | Method::OursCover).then(|| {
            results.iter().fold(Stages::default(), |s, r| Stages {
                reference: s.reference + r.timings.reference,
                setup: s.setup + r.timings.setup,
                evaluate: s.evaluate + r.timings.evaluate,
                collapse: s.collapse + r.timings.collapse,
                lift: s.lift + r.timings.lift,
                passes: s.passes.max(r.timings.passes),
            })
        });
    Ok(SpeedSample {
        repeats,
        seconds,
        user,
        system,
        stages,
    })
}

/// CPU seconds (user and system) this process spent since `before` ([`cpu_times`]).
fn cpu_since(before: (f64, f64)) -> f64 {
    let now = cpu_times();
    now.0 - before.0 + now.1 - before.1
}

/// The goals: at 10 %, F1 >= 0.95 on every real model and at least the best
/// meshopt simplifier's at the same budget (a result with more triangles than the
/// budget is not: clusterlod's cut of a layer too small to simplify); at least a
/// million input triangles per second per core.
fn goals(fidelity: &[Fidelity], speed: &[Speed]) -> Vec<Goal> {
    let mut out = Vec::new();
    let mut models: Vec<&str> = fidelity.iter().map(|f| f.model.as_str()).collect();
    models.dedup();
    for model in models {
        let at = |name: &str| {
            fidelity.iter().find(|f| {
                f.model == model && f.simplifier == name && f.budget_percent == GOAL_BUDGET
            })
        };
        let Some(ours) = at("strata").map(|f| f.f1) else {
            continue;
        };
        out.push(Goal {
            goal: format!("{model}: line-pixel F1 at 10 %"),
            value: ours,
            threshold: GOAL_F1,
            met: ours >= GOAL_F1,
        });
        let best = Simplifier::ALL
            .iter()
            .filter_map(|s| at(s.name()))
            .filter(|f| f.kept_triangles <= f.budget_triangles)
            .map(|f| f.f1)
            .fold(0.0, f64::max);
        out.push(Goal {
            goal: format!("{model}: F1 at 10 % against the best meshopt simplifier"),
            value: ours,
            threshold: best,
            met: ours >= best,
        });
    }
    for s in speed.iter().filter(|s| {
        s.simplifier == "strata" && s.threads == 1 && s.triangles >= GOAL_RATE_MIN_TRIANGLES
    }) {
        out.push(Goal {
            goal: format!("{}: input triangles per CPU second, one thread", s.input),
            value: s.triangles_per_cpu_s,
            threshold: GOAL_RATE,
            met: s.triangles_per_cpu_s >= GOAL_RATE,
        });
    }
    out
}

/// Prints the report as tables: outlines, fidelity, speed, hierarchies, then the
/// goals, peak memory and notes.
pub fn print_table(report: &LodReport) {
    println!("{} ({} cores)", report.adapter, report.cores);
    println!(
        "{:<12} {:>9} {:>8} {:>12} {:>12} {:>12}",
        "model", "triangles", "corners", "keep them", "10 % budget", "layers below"
    );
    for o in &report.outlines {
        println!(
            "{:<12} {:>9} {:>8} {:>12} {:>12} {:>9}/{}",
            o.model,
            o.triangles,
            o.corners,
            o.min_triangles,
            o.goal_budget_triangles,
            o.layers_below,
            o.layers
        );
    }
    println!();
    println!(
        "{:<12} {:<20} {:>6} {:>9} {:>9} {:>10} {:>10} {:>7} {:>7} {:>7} {:>7} {:>8}",
        "model",
        "simplifier",
        "budget",
        "of tri",
        "triangles",
        "max/ext",
        "rms/ext",
        "outside",
        "F1",
        "strict",
        "RMS col",
        "meshopt"
    );
    for f in &report.fidelity {
        println!(
            "{:<12} {:<20} {:>5.0}% {:>9} {:>9} {:>10.2e} {:>10.2e} {:>7.4} {:>7.3} {:>7.3} {:>7.2} {:>8}",
            f.model,
            f.simplifier,
            f.budget_percent,
            f.budget_triangles,
            f.kept_triangles,
            f.line_max_rel,
            f.line_rms_rel,
            f.outside,
            f.f1,
            f.f1_strict,
            f.rms_colour,
            f.meshopt_layers
        );
    }
    println!();
    println!(
        "{:<24} {:>9} {:<20} {:>7} {:>7} {:>5} {:>9} {:>9} {:>9} {:>9} {:>11} {:>11} {:>10}",
        "input",
        "triangles",
        "simplifier",
        "threads",
        "samples",
        "runs",
        "s",
        "CPU s",
        "system s",
        "M tri/s",
        "M tri/CPU s",
        "range",
        "x simplify"
    );
    for s in &report.speed {
        println!(
            "{:<24} {:>9} {:<20} {:>7} {:>7} {:>5} {:>9.3} {:>9.3} {:>9.3} {:>9.2} {:>11.2} {:>11} {:>10}",
            s.input,
            s.triangles,
            s.simplifier,
            s.threads,
            s.samples,
            s.repeats,
            s.seconds,
            s.cpu_seconds,
            s.system_seconds,
            s.triangles_per_s / 1e6,
            s.triangles_per_cpu_s / 1e6,
            if s.samples > 1 {
                format!(
                    "{:.2}-{:.2}",
                    s.triangles_per_cpu_s_range[0] / 1e6,
                    s.triangles_per_cpu_s_range[1] / 1e6
                )
            } else {
                String::new()
            },
            s.per_cpu_s_over_meshopt_simplify
                .map_or_else(String::new, |r| format!("{r:.2}"))
        );
        if let Some(st) = &s.stages {
            println!(
                "{:>26} stages: reference {:.3} s, setup {:.3} s, evaluate {:.3} s, collapse {:.3} s, lift {:.3} s, {} passes",
                "", st.reference, st.setup, st.evaluate, st.collapse, st.lift, st.passes
            );
        }
    }
    println!();
    println!(
        "{:<22} {:<34} {:>9} {:>9} {:>9} {:<24} {:>9} {:>9} {:>7} {:>7}",
        "hierarchy input",
        "hierarchy",
        "stored",
        "build s",
        "M/CPU s",
        "view",
        "drawn",
        "lines",
        "F1",
        "RMS col"
    );
    for h in &report.hierarchy {
        for v in &h.views {
            println!(
                "{:<22} {:<34} {:>9} {:>9.2} {:>9.2} {:<24} {:>9} {:>9} {:>7.3} {:>7.2}",
                h.input,
                h.hierarchy,
                h.stored_triangles,
                h.build_cpu_seconds,
                h.built_triangles as f64 / h.build_cpu_seconds / 1e6,
                v.view,
                v.drawn_triangles,
                v.line_pixels,
                v.f1,
                v.rms_colour
            );
        }
    }
    println!();
    for g in &report.goals {
        println!(
            "{} {}: {:.3} (goal {:.3})",
            if g.met { "MET   " } else { "MISSED" },
            g.goal,
            g.value,
            g.threshold
        );
    }
    println!("peak memory {:.0} MB", report.peak_memory_mb);
    for n in &report.notes {
        println!("note: {n}");
    }
}

/// The shared data folder beside the repository.
pub fn default_data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(simplifier: &str, f1: f64, kept_triangles: usize) -> Fidelity {
        Fidelity {
            model: "m".into(),
            simplifier: simplifier.into(),
            budget_percent: GOAL_BUDGET,
            triangles: 100,
            budget_triangles: 10,
            kept_triangles,
            line_max: 0.0,
            line_rms: 0.0,
            line_max_rel: 0.0,
            line_rms_rel: 0.0,
            outside: 0.0,
            meshopt_layers: 0,
            f1,
            f1_strict: f1,
            rms_colour: 0.0,
            views: Vec::new(),
        }
    }

    #[test]
    fn ours_is_compared_with_meshopt_results_within_the_budget_only() {
        let fidelity = [
            row("strata", 0.9, 10),
            row("meshopt_simplify", 0.8, 9),
            row("meshopt_clusterlod", 1.0, 58),
        ];
        let against_meshopt = |rows: &[Fidelity]| {
            goals(rows, &[])
                .into_iter()
                .find(|g| g.goal.contains("best meshopt"))
                .map(|g| (g.threshold, g.met))
        };
        assert_eq!(against_meshopt(&fidelity), Some((0.8, true)));
        let within = [row("strata", 0.9, 10), row("meshopt_clusterlod", 0.95, 10)];
        assert_eq!(against_meshopt(&within), Some((0.95, false)));
    }

    #[test]
    fn the_error_matching_a_triangle_count_draws_at_most_that_many() {
        // Cuts in steps, as a DAG's are: 500 triangles below 2 px, 200 below 5, 90
        // below 20, then 10.
        let cut = |pixels: f64| {
            let triangles = [(2.0, 500), (5.0, 200), (20.0, 90)]
                .iter()
                .find(|(below, _)| pixels < *below)
                .map_or(10, |&(_, n)| n);
            vec![0u32; 3 * triangles]
        };
        let pixels = pixels_for_triangles(cut, 100);
        assert_eq!(cut(pixels).len() / 3, 90);
        assert!((5.0..5.001).contains(&pixels), "{pixels}");
        assert_eq!(cut(pixels_for_triangles(cut, 600)).len() / 3, 500);
        assert_eq!(cut(pixels_for_triangles(cut, 5)).len() / 3, 10);
    }

    #[test]
    fn a_speed_row_is_its_median_sample_with_the_extremes() {
        let sample = |user: f64, system: f64| SpeedSample {
            repeats: 1,
            seconds: user + system,
            user,
            system,
            stages: None,
        };
        let (median, extremes) =
            median_sample(vec![sample(2.0, 0.5), sample(1.0, 0.2), sample(3.0, 0.1)]);
        assert_eq!(median.cpu(), 2.5);
        assert_eq!(extremes, [3.1, 1.2]);
        let (only, extremes) = median_sample(vec![sample(1.5, 0.0)]);
        assert_eq!((only.cpu(), extremes), (1.5, [1.5, 1.5]));
    }

    #[test]
    fn par_map_keeps_the_order() {
        let items: Vec<usize> = (0..100).collect();
        for threads in [1, 3] {
            assert_eq!(
                par_map(&items, threads, |&i| i * 2),
                (0..100).map(|i| i * 2).collect::<Vec<_>>()
            );
        }
    }

    #[test]
    fn one_thread_is_the_calling_one() {
        let caller = std::thread::current().id();
        let ids = par_map(&[(); 4], 1, |_| std::thread::current().id());
        assert!(ids.iter().all(|&id| id == caller), "{ids:?}");
        let ids = par_map(&[(); 4], 2, |_| std::thread::current().id());
        assert!(ids.iter().all(|&id| id != caller), "{ids:?}");
    }
    #[test]
    fn line_distances_weigh_each_layer_surface_by_its_samples() {
        let dev = |samples, max, rms, outside| Deviation {
            samples,
            max,
            rms,
            outside,
            ..Deviation::default()
        };
        let lines = LineDistances::of(&[dev(3, 2.0, 0.0, 1), dev(1, 5.0, 4.0, 0)]);
        assert_eq!(lines.max, 5.0);
        // (3 * 0² + 1 * 4²) / 4 samples = 2²: each surface weighs by its samples.
        assert_eq!(lines.rms, 2.0);
        assert_eq!(lines.outside, 0.25);
        let none = LineDistances::of(&[]);
        assert_eq!((none.max, none.rms, none.outside), (0.0, 0.0, 0.0));
    }

    #[test]
    fn speed_rows_are_rated_against_meshopt_simplify_on_one_thread_of_their_input() {
        let speed = |input: &str, simplifier: &str, threads, rate| Speed {
            input: input.into(),
            triangles: 100,
            simplifier: simplifier.into(),
            threads,
            samples: 1,
            repeats: 1,
            seconds: 1.0,
            cpu_seconds: 1.0,
            system_seconds: 0.0,
            triangles_per_s: rate,
            triangles_per_cpu_s: rate,
            triangles_per_cpu_s_range: [rate, rate],
            per_cpu_s_over_meshopt_simplify: None,
            stages: None,
        };
        let mut rows = vec![
            speed("a", "meshopt_simplify", 1, 4.0),
            speed("b", "strata", 1, 1.0),
            speed("b", "meshopt_simplify", 1, 2.0),
            speed("b", "strata", 2, 3.0),
        ];
        set_ratios(&mut rows, "b");
        let ratios: Vec<_> = rows
            .iter()
            .map(|r| r.per_cpu_s_over_meshopt_simplify)
            .collect();
        assert_eq!(ratios, [None, Some(0.5), Some(1.0), Some(1.5)]);
    }

    #[test]
    fn ours_runs_on_every_core_only_where_several_surfaces_share_them() {
        let all = |layers, cores| {
            speed_runs(layers, cores)
                .into_iter()
                .filter(|&(_, threads)| threads > 1)
                .count()
        };
        assert_eq!(speed_runs(1, 1).len(), Method::all().len());
        assert_eq!((all(1, 8), all(5, 1), all(5, 8)), (0, 0, 1));
    }
}
