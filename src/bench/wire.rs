//! `strata bench wire`: frame times of every wireframe technique against the shaded
//! surface alone, on meshes of about 0.1, 0.4, 1 and 4 million triangles, in retained
//! mode (geometry resident) and immediate mode (vertex data sent every frame), as
//! Tables 3 and 2 of Celes & Abraham (2011).
//!
//! Each frame is 1000 x 800 with the camera turning 360° around the model. The modes
//! take turns frame by frame (every mode draws angle 1, then every mode angle 2 ...),
//! so that whatever else loads the machine weighs on all of them alike: only ratios
//! between modes of one run mean anything on a CPU rasterizer (DESIGN.md section 5).
//! Retained frames are timed by GPU timestamps around the frame's commands where the
//! adapter has them, else by the wall clock around submit and wait; immediate frames
//! by the wall clock around the upload, submit and wait, since the upload is the point.
//! Immediate mode sends each mesh's `Drawable::bytes()` through the queue before
//! drawing (`FrameTimer::upload`).
//!
//! The texture modes run with both forms of coverage (DESIGN.md section 3): `tex`,
//! `texgs`, `global` with the mip-mapped texture and `tex-analytic` ... evaluated in
//! the shader; the benchmark shows which form wins on the adapter. `none` runs in both
//! forms too, and the cheaper is the reference of `ratio_to_none`.

use std::time::Instant;

use anyhow::{Context, Result};
use serde::Serialize;
use strata_render::glam::Vec3;
use strata_render::wire::{Drawable, Family, Needs};
use strata_render::{Camera, Coverage, FrameTimer, MajorLines, Renderer, Style, View, WireMode};

use super::meshes::{self, Kind};

const WIDTH: u32 = 1000;
const HEIGHT: u32 = 800;
/// Camera elevation above the horizon, degrees.
const ELEVATION: f32 = 30.0;

/// What `--json` prints.
#[derive(Debug, Serialize)]
pub struct WireReport {
    /// The GPU adapter's name.
    pub adapter: String,
    /// Its graphics API (`vulkan`, `metal`, `dx12`, `gl`), lower case.
    pub backend: String,
    /// Per mesh (sizes, then kinds, in the plan's order), upload and mode.
    pub results: Vec<WireResult>,
}

/// One mesh, mode and upload.
#[derive(Debug, Serialize)]
pub struct WireResult {
    /// The mesh: kind and size label, e.g. `terrain-1m`.
    pub mesh: String,
    /// Its triangles.
    pub triangles: usize,
    /// The wireframe technique (`WireMode::name`, `none` for the shaded surface
    /// alone), `-analytic` appended for the texture modes' analytic coverage.
    pub mode: String,
    /// `retained` or `immediate`.
    pub upload: &'static str,
    /// Median frame time over the timed frames (each from a camera further round),
    /// milliseconds to 3 decimals: GPU timestamps around the frame's commands for
    /// `retained` where the adapter has them, else the wall clock around submit and
    /// wait; for `immediate` the wall clock around upload, submit and wait.
    pub ms_median: f64,
    /// The 10th percentile of the same frame times (interpolated between ranks), ms.
    pub ms_p10: f64,
    /// The 90th percentile of the same frame times, ms.
    pub ms_p90: f64,
    /// Median over the median of `none` for the same mesh and upload (the cheaper of
    /// its two coverage forms, `none` and `none-analytic`).
    pub ratio_to_none: f64,
}

/// A timed mode: a technique and, for the texture ones, the coverage form; `plain`
/// leaves out the plan's major lines.
#[derive(Clone, Copy, Debug)]
struct Variant {
    mode: WireMode,
    coverage: Coverage,
    plain: bool,
}

impl Variant {
    fn name(self) -> String {
        let name = match (self.mode.family(), self.coverage) {
            (Family::Texture, Coverage::Analytic) => format!("{}-analytic", self.mode.name()),
            _ => self.mode.name().to_string(),
        };
        if self.plain {
            format!("{name}-nomajor")
        } else {
            name
        }
    }
}

/// The modes timed on a mesh of `kind`: `none` in both coverage forms first (the
/// shaded-only pipeline carries the texture techniques' disabled isoline and grid-line
/// code, which costs the CPU rasterizers more in the texture form; see common.wgsl),
/// then the edge techniques, then the texture ones the mesh carries coordinates for
/// (`quad`'s cell faces aside) in both forms, those any mesh can draw first. With major
/// lines, `global` is timed without them too (`-nomajor`), in the same run: only ratios
/// within one run compare on a CPU rasterizer.
fn variants(kind: Kind, major: bool) -> Vec<Variant> {
    let textured = |mode| Variant {
        mode,
        coverage: Coverage::Texture,
        plain: false,
    };
    let mut out = vec![
        textured(WireMode::None),
        Variant {
            mode: WireMode::None,
            coverage: Coverage::Analytic,
            plain: false,
        },
    ];
    out.extend(WireMode::of_family(Family::Edges).map(textured));
    let timed = |mode: &WireMode| match mode.needs() {
        Needs::Triangles => *mode != WireMode::None,
        Needs::GlobalCoordinates => kind.has_global(),
        Needs::CellFaces => false,
    };
    let mut texture: Vec<WireMode> = WireMode::of_family(Family::Texture).filter(timed).collect();
    texture.sort_by_key(|m| m.needs());
    for mode in texture {
        for coverage in [Coverage::Texture, Coverage::Analytic] {
            out.push(Variant {
                mode,
                coverage,
                plain: false,
            });
        }
    }
    if major && kind.has_global() {
        for coverage in [Coverage::Texture, Coverage::Analytic] {
            out.push(Variant {
                mode: WireMode::Global,
                coverage,
                plain: true,
            });
        }
    }
    out
}

/// How much to run.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Mesh sizes: triangles and label.
    sizes: Vec<(usize, &'static str)>,
    /// Mesh kinds, each at every size.
    kinds: Vec<Kind>,
    /// Untimed frames per mesh and upload before the timed ones.
    warmup: usize,
    /// Timed frames per mesh and upload.
    frames: usize,
    /// Major cell lines every this many cells, as `render --major` draws them by
    /// default (0: none, every line alike).
    major: u32,
}

/// The sizes of the full benchmark, by label.
const SIZES: [(usize, &str); 4] = [
    (100_000, "0.1m"),
    (400_000, "0.4m"),
    (1_000_000, "1m"),
    (4_000_000, "4m"),
];

impl Plan {
    /// The full benchmark: every size and kind, 60 timed frames after 3 of warm-up.
    pub fn full() -> Plan {
        Plan {
            sizes: SIZES.to_vec(),
            kinds: Kind::ALL.to_vec(),
            warmup: 3,
            frames: 60,
            major: 10,
        }
    }

    /// `--quick`: the 1 M reservoir, 4 timed frames after one of warm-up, short enough
    /// to try a change on a CPU rasterizer, where the full run takes far longer
    /// (docs/performance.md, "Wireframe techniques").
    pub fn quick() -> Plan {
        Plan {
            sizes: vec![SIZES[2]],
            kinds: vec![Kind::Reservoir],
            warmup: 1,
            frames: 4,
            major: 10,
        }
    }

    /// This plan with major cell lines every `every` cells (0: none).
    pub fn major(self, every: u32) -> Plan {
        Plan {
            major: every,
            ..self
        }
    }

    /// Keeps only the sizes labelled in `sizes` and the kinds named in `kinds`, in the
    /// order given (empty: all), so that a long run can be split over several calls.
    pub fn select(mut self, sizes: &[String], kinds: &[String]) -> Result<Plan> {
        if !sizes.is_empty() {
            self.sizes = sizes
                .iter()
                .map(|label| {
                    SIZES
                        .iter()
                        .find(|(_, l)| l == label)
                        .copied()
                        .with_context(|| {
                            format!("unknown mesh size {label:?} (known: 0.1m, 0.4m, 1m, 4m)")
                        })
                })
                .collect::<Result<_>>()?;
        }
        if !kinds.is_empty() {
            self.kinds = kinds
                .iter()
                .map(|name| {
                    Kind::ALL
                        .into_iter()
                        .find(|k| k.name() == name)
                        .with_context(|| {
                            format!(
                                "unknown mesh kind {name:?} (known: sphere, terrain, reservoir)"
                            )
                        })
                })
                .collect::<Result<_>>()?;
        }
        Ok(self)
    }
}

/// Runs `plan`, reporting progress on stderr.
pub fn run(plan: &Plan) -> Result<WireReport> {
    let mut renderer = Renderer::headless()?;
    let timer = FrameTimer::new(&renderer.gpu);
    eprintln!(
        "bench wire on {}, {}",
        renderer.gpu.describe(),
        if timer.has_timestamps() {
            "retained frames timed by GPU timestamps"
        } else {
            "retained frames timed by the wall clock"
        }
    );
    let mut results = Vec::new();
    for &(size, label) in &plan.sizes {
        for &kind in &plan.kinds {
            let started = Instant::now();
            let bench = meshes::make(kind, size, label)?;
            let timed = time_mesh(&mut renderer, &timer, &bench, plan)?;
            eprintln!(
                "  {}: {} triangles in {:.0} s",
                bench.name,
                bench.mesh.triangle_count(),
                started.elapsed().as_secs_f64()
            );
            // Each mesh's rows as they come, so that a long run cut short still tells.
            for r in &timed {
                eprintln!("    {}", row(r));
            }
            results.extend(timed);
        }
    }
    Ok(WireReport {
        adapter: renderer.gpu.info.name.clone(),
        backend: format!("{:?}", renderer.gpu.info.backend).to_lowercase(),
        results,
    })
}

/// Every variant's frame times on `bench`, retained then immediate: the frames go
/// round the mesh, every variant drawing each camera in turn.
fn time_mesh(
    renderer: &mut Renderer,
    timer: &FrameTimer,
    bench: &meshes::BenchMesh,
    plan: &Plan,
) -> Result<Vec<WireResult>> {
    let mesh = &bench.mesh;
    let variants = variants(bench.kind, plan.major > 0);
    let mut drawables: Vec<(WireMode, Box<dyn Drawable>)> = Vec::new();
    for v in &variants {
        if drawables.iter().all(|(m, _)| *m != v.mode) {
            let d = renderer
                .prepare(mesh, v.mode)
                .with_context(|| format!("{}: preparing {}", bench.name, v.mode.name()))?;
            drawables.push((v.mode, d));
        }
    }
    let drawable = |mode: WireMode| {
        drawables
            .iter()
            .find(|(m, _)| *m == mode)
            .map(|(_, d)| d.as_ref())
    };
    let (lo, hi) = mesh
        .bounds()
        .with_context(|| format!("{} is empty", bench.name))?;
    let bounds = (Vec3::from(lo), Vec3::from(hi));
    let largest = drawables.iter().map(|(_, d)| d.bytes()).max().unwrap_or(0);
    let payload = vec![0u8; largest as usize];
    let mut results = Vec::new();
    for upload in ["retained", "immediate"] {
        let mut samples = vec![Vec::with_capacity(plan.frames); variants.len()];
        for f in 0..plan.warmup + plan.frames {
            let azimuth = 360.0 * f as f32 / (plan.warmup + plan.frames) as f32;
            let view = View {
                camera: Camera::fit(
                    bounds.0,
                    bounds.1,
                    bench.kind.z_scale(),
                    WIDTH as f32 / HEIGHT as f32,
                    (azimuth, ELEVATION),
                    1.0,
                ),
                width: WIDTH,
                height: HEIGHT,
                bounds,
            };
            for (k, v) in variants.iter().enumerate() {
                let Some(item) = drawable(v.mode) else {
                    continue;
                };
                let style = Style {
                    coverage: v.coverage,
                    major: (plan.major > 0 && !v.plain).then(|| MajorLines {
                        every: plan.major,
                        ..MajorLines::default()
                    }),
                    ..Style::default()
                };
                let ms = if upload == "immediate" {
                    let start = Instant::now();
                    timer.upload(&renderer.gpu, &payload[..item.bytes() as usize]);
                    renderer.draw_timed(&[item], &view, &style, timer)?;
                    start.elapsed().as_secs_f64() * 1e3
                } else {
                    renderer
                        .draw_timed(&[item], &view, &style, timer)?
                        .best_ms()
                };
                if f >= plan.warmup {
                    samples[k].push(ms);
                }
            }
        }
        // The cheaper of the two shaded-only frames is the reference.
        let none = median(&mut samples[0].clone()).min(median(&mut samples[1].clone()));
        for (v, mut s) in variants.iter().zip(samples) {
            s.sort_by(f64::total_cmp);
            let m = percentile(&s, 0.5);
            results.push(WireResult {
                mesh: bench.name.clone(),
                triangles: mesh.triangle_count(),
                mode: v.name(),
                upload,
                ms_median: round3(m),
                ms_p10: round3(percentile(&s, 0.1)),
                ms_p90: round3(percentile(&s, 0.9)),
                ratio_to_none: round3(m / none),
            });
        }
    }
    Ok(results)
}

/// The median of `v` (interpolated for an even count); sorts it.
fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    percentile(v, 0.5)
}

/// The `q` quantile of sorted values (nearest rank, interpolated).
fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let x = q * (sorted.len() - 1) as f64;
    let (i, f) = (x.floor() as usize, x.fract());
    let next = sorted[(i + 1).min(sorted.len() - 1)];
    sorted[i] + f * (next - sorted[i])
}

/// `x` rounded to 3 decimals, as the report gives its times and ratios.
fn round3(x: f64) -> f64 {
    (x * 1e3).round() / 1e3
}

/// Prints the report as a table, one line per mesh, mode and upload.
pub fn print_table(report: &WireReport) {
    println!("{} ({})", report.adapter, report.backend);
    println!(
        "{:<16} {:>9} {:<16} {:<9} {:>10} {:>10} {:>10} {:>7}",
        "mesh", "triangles", "mode", "upload", "median ms", "p10", "p90", "x none"
    );
    for r in &report.results {
        println!("{}", row(r));
    }
}

/// One result as a line of the table.
fn row(r: &WireResult) -> String {
    format!(
        "{:<16} {:>9} {:<16} {:<9} {:>10.1} {:>10.1} {:>10.1} {:>7.2}",
        r.mesh, r.triangles, r.mode, r.upload, r.ms_median, r.ms_p10, r.ms_p90, r.ratio_to_none
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_interpolate_between_ranks() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(percentile(&v, 0.5), 3.0);
        assert_eq!(percentile(&v, 0.1), 1.4);
        assert_eq!(percentile(&v, 0.9), 4.6);
        assert!(percentile(&[], 0.5).is_nan());
    }

    #[test]
    fn global_is_timed_only_where_the_mesh_has_global_coordinates() {
        let has = |kind| {
            variants(kind, true)
                .iter()
                .any(|v| v.mode == WireMode::Global)
        };
        assert!(!has(Kind::Sphere));
        assert!(has(Kind::Terrain) && has(Kind::Reservoir));
        assert_eq!(variants(Kind::Sphere, true)[0].name(), "none");
        assert_eq!(variants(Kind::Sphere, true)[1].name(), "none-analytic");
        let names = |major| -> Vec<String> {
            variants(Kind::Reservoir, major)
                .iter()
                .map(|v| v.name())
                .collect()
        };
        let expected = [
            "none",
            "none-analytic",
            "bias",
            "dist",
            "idbuffer",
            "tex",
            "tex-analytic",
            "texgs",
            "texgs-analytic",
            "global",
            "global-analytic",
        ];
        assert_eq!(names(false), expected);
        let with_major = names(true);
        assert_eq!(with_major[..expected.len()], expected);
        assert_eq!(
            with_major[expected.len()..],
            ["global-nomajor", "global-analytic-nomajor"]
        );
    }

    #[test]
    fn a_plan_keeps_the_selected_sizes_and_kinds_in_the_order_given() {
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let plan = Plan::full()
            .select(&names(&["4m", "1m"]), &names(&["reservoir"]))
            .unwrap();
        assert_eq!(plan.sizes, vec![(4_000_000, "4m"), (1_000_000, "1m")]);
        assert_eq!(plan.kinds, vec![Kind::Reservoir]);
        assert_eq!(plan.frames, 60);
        let all = Plan::full().select(&[], &[]).unwrap();
        assert_eq!((all.sizes.len(), all.kinds.len()), (4, 3));
        let err = Plan::full().select(&names(&["2m"]), &[]).unwrap_err();
        assert!(format!("{err}").contains("\"2m\""), "{err}");
        assert!(Plan::full().select(&[], &names(&["cube"])).is_err());
    }
}
