//! `strata bench quality`: how close each wireframe technique's lines come to the exact
//! coverage of the visible edges (`strata_render::wire::reference`, 16 x 16 samples per
//! pixel), over a fixed set of views: a plane head-on, tilted and at a grazing angle,
//! steep terrain, a sphere's silhouettes and a reservoir's stacked layers seen almost
//! edge-on, each at line widths of 1, 2 and 3 pixels.
//!
//! Frames are drawn with a black surface, white lines and a pure blue background, so
//! that a pixel's red channel is its line coverage whether the line lies over the
//! surface or over the background. Per view and technique:
//! - `rms`: root mean square of (technique - reference) coverage over the pixels where
//!   either has some line;
//! - `missing`: the fraction of edge pixels (reference coverage at least 3/4: the line
//!   passes near the pixel's centre, so even an aliased line lights it) that the
//!   technique leaves below 1/4: gaps, stippling, lost outer halves of outlines;
//! - `extra`: the fraction of the technique's line pixels (at least 1/2) where the
//!   reference has none (below 1/20): hidden lines showing through, saturation.
//!
//! `bias` is expected to show stippling on steep slopes and grazing views: its depth
//! bias does not cover a wide line's half width there (see wire/bias.rs). This is a
//! measurement, not a failure.

use std::path::Path;

use anyhow::{Context, Result};
use serde::Serialize;
use strata_grid::SurfaceMesh;
use strata_render::glam::Vec3;
use strata_render::image;
use strata_render::wire::reference::{CoverageImage, line_coverage};
use strata_render::wire::{Family, Needs};
use strata_render::{Camera, Coverage, Renderer, Style, View, WireMode};

use super::meshes;

const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;
/// Samples per pixel along each axis of the reference.
const SAMPLES: u32 = 16;
const SIGMAS: [f32; 3] = [1.0, 2.0, 3.0];

/// What `--json` prints.
#[derive(Debug, Serialize)]
pub struct QualityReport {
    /// The GPU adapter's name.
    pub adapter: String,
    /// Its graphics API (`vulkan`, `metal`, `dx12`, `gl`), lower case.
    pub backend: String,
    /// Samples per pixel of the exact reference coverage (16 x 16).
    pub samples_per_pixel: u32,
    /// Per view, line width and technique.
    pub results: Vec<QualityResult>,
    /// Per technique and width, over all views' pixels together.
    pub summary: Vec<QualityResult>,
    /// Isolines against their analytic reference, with the marching-triangles
    /// baseline timed beside the texture method (`strata bench isolines`).
    pub isolines: super::isolines::Report,
}

/// One technique's line coverage against the reference, at one width.
#[derive(Debug, Serialize)]
pub struct QualityResult {
    /// The wireframe technique (`WireMode::name`), `-analytic` appended for analytic
    /// coverage.
    pub technique: String,
    /// The view, or `all` in the summary.
    pub view: String,
    /// Line width, pixels.
    pub sigma: f32,
    /// RMS of (technique - reference) coverage (0..1) over the pixels where either
    /// has some line; rounded to 4 decimals.
    pub rms: f64,
    /// Fraction of edge pixels (`edge_pixels`) the technique leaves below 1/4
    /// coverage: gaps, stippling, lost outer halves of outlines; 4 decimals.
    pub missing: f64,
    /// Fraction of the technique's line pixels (coverage at least 1/2) where the
    /// reference has none (below 1/20): hidden lines showing through; 4 decimals.
    pub extra: f64,
    /// Pixels with reference coverage of at least 3/4.
    pub edge_pixels: usize,
}

/// A view of the fixed set.
struct QualityView {
    name: &'static str,
    mesh: SurfaceMesh,
    /// Whether the mesh is made of cell faces with global coordinates (`global` and
    /// `quad` apply).
    global: bool,
    view: View,
}

/// A flat 12 x 12 grid of 10 m cells centred on the origin.
fn plane() -> SurfaceMesh {
    SurfaceMesh::structured(12, 12, |i, j| {
        [i as f32 * 10.0 - 60.0, j as f32 * 10.0 - 60.0, 0.0]
    })
}

/// A camera looking at the plane's centre, tilted `tilt` degrees from head-on.
fn plane_view(tilt: f32) -> View {
    let (s, c) = tilt.to_radians().sin_cos();
    let eye = Vec3::new(0.0, -s, c) * 180.0;
    let camera = Camera::look_at(eye, Vec3::ZERO, Vec3::new(0.0, c, s));
    View {
        camera,
        width: WIDTH,
        height: HEIGHT,
        bounds: (Vec3::new(-60.0, -60.0, 0.0), Vec3::new(60.0, 60.0, 0.0)),
    }
}

/// A camera fitted to `mesh` from (`azimuth`, `elevation`) degrees.
fn fitted(mesh: &SurfaceMesh, z_scale: f32, azimuth: f32, elevation: f32) -> Result<View> {
    let (lo, hi) = mesh.bounds().context("empty quality mesh")?;
    let bounds = (Vec3::from(lo), Vec3::from(hi));
    Ok(View {
        camera: Camera::fit(
            bounds.0,
            bounds.1,
            z_scale,
            WIDTH as f32 / HEIGHT as f32,
            (azimuth, elevation),
            1.0,
        ),
        width: WIDTH,
        height: HEIGHT,
        bounds,
    })
}

/// A 16 x 16 grid of 10 m cells over ridges whose flanks slope at up to about 70°.
fn steep_terrain() -> SurfaceMesh {
    SurfaceMesh::structured(16, 16, |i, j| {
        let (x, y) = (i as f32 * 10.0 - 80.0, j as f32 * 10.0 - 80.0);
        let h =
            28.0 * (x * 0.06).sin() * (y * 0.045 + 0.5).cos() + 6.0 * (x * 0.21 - y * 0.17).sin();
        [x, y, h]
    })
}

/// The fixed set of views, in the order of the report.
fn views() -> Result<Vec<QualityView>> {
    let terrain = steep_terrain();
    let sphere = meshes::sphere(500);
    let reservoir = meshes::reservoir(1500)?;
    Ok(vec![
        QualityView {
            name: "plane-head-on",
            mesh: plane(),
            global: true,
            view: plane_view(0.0),
        },
        QualityView {
            name: "plane-tilt-60",
            mesh: plane(),
            global: true,
            view: plane_view(60.0),
        },
        QualityView {
            name: "plane-grazing-80",
            mesh: plane(),
            global: true,
            view: plane_view(80.0),
        },
        QualityView {
            name: "terrain-steep",
            view: fitted(&terrain, 1.0, 30.0, 20.0)?,
            mesh: terrain,
            global: true,
        },
        QualityView {
            name: "sphere-silhouette",
            view: fitted(&sphere, 1.0, 20.0, 20.0)?,
            mesh: sphere,
            global: false,
        },
        QualityView {
            name: "reservoir-grazing",
            view: fitted(&reservoir, 5.0, 60.0, 8.0)?,
            mesh: reservoir,
            global: true,
        },
    ])
}

/// The techniques measured on a view: name, mode and coverage form.
fn techniques(global: bool) -> Vec<(String, WireMode, Coverage)> {
    let mut out: Vec<(String, WireMode, Coverage)> = WireMode::of_family(Family::Edges)
        .map(|m| (m.name().to_string(), m, Coverage::Texture))
        .collect();
    let mut texture: Vec<WireMode> = WireMode::of_family(Family::Texture)
        .filter(|&m| m != WireMode::None && (global || m.needs() == Needs::Triangles))
        .collect();
    texture.sort_by_key(|m| m.needs());
    for m in texture {
        out.push((m.name().to_string(), m, Coverage::Texture));
        out.push((format!("{}-analytic", m.name()), m, Coverage::Analytic));
    }
    out
}

/// Running sums of one technique's errors.
#[derive(Default, Clone, Copy)]
struct Tally {
    squares: f64,
    compared: usize,
    edge: usize,
    missing: usize,
    drawn: usize,
    extra: usize,
}

impl Tally {
    fn add(&mut self, other: Tally) {
        self.squares += other.squares;
        self.compared += other.compared;
        self.edge += other.edge;
        self.missing += other.missing;
        self.drawn += other.drawn;
        self.extra += other.extra;
    }

    fn result(&self, technique: &str, view: &str, sigma: f32) -> QualityResult {
        let frac = |a: usize, b: usize| if b == 0 { 0.0 } else { a as f64 / b as f64 };
        QualityResult {
            technique: technique.to_string(),
            view: view.to_string(),
            sigma,
            rms: round4(if self.compared == 0 {
                0.0
            } else {
                (self.squares / self.compared as f64).sqrt()
            }),
            missing: round4(frac(self.missing, self.edge)),
            extra: round4(frac(self.extra, self.drawn)),
            edge_pixels: self.edge,
        }
    }
}

/// `x` rounded to 4 decimals, as the report gives its fractions.
fn round4(x: f64) -> f64 {
    (x * 1e4).round() / 1e4
}

/// Compares a technique's frame (red channel = coverage) with the reference.
fn compare(image: &image::RgbaImage, reference: &CoverageImage) -> Tally {
    let mut t = Tally::default();
    for (p, r) in image.pixels().zip(&reference.coverage) {
        let c = f64::from(p.0[0]) / 255.0;
        let r = f64::from(*r);
        if r > 0.0 || c > 2.0 / 255.0 {
            t.squares += (c - r) * (c - r);
            t.compared += 1;
        }
        if r >= 0.75 {
            t.edge += 1;
            if c < 0.25 {
                t.missing += 1;
            }
        }
        if c >= 0.5 {
            t.drawn += 1;
            if r < 0.05 {
                t.extra += 1;
            }
        }
    }
    t
}

/// The measuring style: black surface, white lines, blue background.
fn measuring(sigma: f32, coverage: Coverage) -> Style {
    Style {
        thickness: sigma,
        coverage,
        wire_color: [1.0, 1.0, 1.0, 1.0],
        solid_color: [0.0, 0.0, 0.0, 1.0],
        background: [0.0, 0.0, 1.0, 1.0],
        scalar_range: None,
        isolation: false,
        ..Style::default()
    }
}

/// Runs the benchmark; with `images`, writes every frame and reference there as PNG.
pub fn run(images: Option<&Path>) -> Result<QualityReport> {
    let mut renderer = Renderer::headless()?;
    eprintln!("bench quality on {}", renderer.gpu.describe());
    let renderer_name = (
        renderer.gpu.info.name.clone(),
        format!("{:?}", renderer.gpu.info.backend).to_lowercase(),
    );
    if let Some(dir) = images {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let mut results = Vec::new();
    let mut totals: Vec<(String, f32, Tally)> = Vec::new();
    for qv in views()? {
        let techniques = techniques(qv.global);
        let mut prepared = Vec::new();
        for (_, mode, _) in &techniques {
            if prepared.iter().all(|(m, _)| m != mode) {
                let d = renderer
                    .prepare(&qv.mesh, *mode)
                    .with_context(|| format!("{}: preparing {}", qv.name, mode.name()))?;
                prepared.push((*mode, d));
            }
        }
        for sigma in SIGMAS {
            let reference = line_coverage(&qv.mesh, &qv.view, sigma, SAMPLES)?;
            if let Some(dir) = images {
                let grey = image::GrayImage::from_fn(WIDTH, HEIGHT, |x, y| {
                    image::Luma([(reference.at(x, y) * 255.0).round() as u8])
                });
                let path = dir.join(format!("{}-{sigma}-reference.png", qv.name));
                grey.save(&path)
                    .with_context(|| format!("writing {}", path.display()))?;
            }
            for (name, mode, coverage) in &techniques {
                let Some((_, d)) = prepared.iter().find(|(m, _)| m == mode) else {
                    continue;
                };
                let frame =
                    renderer.render(&[d.as_ref()], &qv.view, &measuring(sigma, *coverage))?;
                if let Some(dir) = images {
                    let path = dir.join(format!("{}-{sigma}-{name}.png", qv.name));
                    strata_render::save_png(&frame, &path)?;
                }
                let tally = compare(&frame, &reference);
                results.push(tally.result(name, qv.name, sigma));
                match totals.iter_mut().find(|(n, s, _)| n == name && *s == sigma) {
                    Some((_, _, t)) => t.add(tally),
                    None => totals.push((name.clone(), sigma, tally)),
                }
            }
        }
        eprintln!("  {} done", qv.name);
    }
    drop(renderer);
    let isolines = super::isolines::run()?;
    Ok(QualityReport {
        isolines,
        adapter: renderer_name.0,
        backend: renderer_name.1,
        samples_per_pixel: SAMPLES * SAMPLES,
        results,
        summary: totals
            .iter()
            .map(|(n, s, t)| t.result(n, "all", *s))
            .collect(),
    })
}

/// Prints the report as a table: per view, then the summary.
pub fn print_table(report: &QualityReport) {
    println!(
        "{} ({}), reference at {} samples per pixel",
        report.adapter, report.backend, report.samples_per_pixel
    );
    println!(
        "{:<20} {:<16} {:>5} {:>8} {:>8} {:>8} {:>7}",
        "view", "technique", "sigma", "rms", "missing", "extra", "edge px"
    );
    for r in report.results.iter().chain(&report.summary) {
        println!(
            "{:<20} {:<16} {:>5} {:>8.4} {:>8.4} {:>8.4} {:>7}",
            r.view, r.technique, r.sigma, r.rms, r.missing, r.extra, r.edge_pixels
        );
    }
    println!();
    super::isolines::print_table(&report.isolines);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edge_techniques_come_first_then_those_any_mesh_carries() {
        let names = |global| -> Vec<String> {
            techniques(global)
                .into_iter()
                .map(|(name, _, _)| name)
                .collect()
        };
        let plain = [
            "bias",
            "dist",
            "idbuffer",
            "tex",
            "tex-analytic",
            "texgs",
            "texgs-analytic",
        ];
        assert_eq!(names(false), plain);
        let global = ["global", "global-analytic", "quad", "quad-analytic"];
        assert_eq!(names(true), [&plain[..], &global[..]].concat());
    }

    #[test]
    fn compare_counts_gaps_and_extras() {
        let reference = CoverageImage {
            width: 3,
            height: 1,
            coverage: vec![1.0, 0.8, 0.0],
        };
        // A gap where the reference is full, exact in the middle, a line where there is none.
        let image = image::RgbaImage::from_fn(3, 1, |x, _| {
            image::Rgba([[0, 204, 255][x as usize], 0, 255, 255])
        });
        let t = compare(&image, &reference);
        assert_eq!((t.edge, t.missing), (2, 1));
        assert_eq!((t.drawn, t.extra), (2, 1));
        assert_eq!(t.compared, 3);
        let rms = (t.squares / 3.0).sqrt();
        assert!((rms - (2.0f64 / 3.0).sqrt()).abs() < 0.01, "{rms}");
    }
}
