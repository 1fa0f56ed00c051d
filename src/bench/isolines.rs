//! `strata bench isolines`: isoline quality against an analytic reference, and
//! frame times, for the texture isolines (texture and analytic coverage, range adjust
//! on and off) and the marching-triangles baseline (CPU extraction, line primitives),
//! all in one run on one adapter.
//!
//! The scene is the plane [-1, 1]² in 256 x 256 cells carrying f = x² + y², seen
//! head-on so that the screen is an exact similarity of the plane, with isolines every
//! 0.05 (about 30 circles). The reference is the ideal anti-aliased image: each pixel's
//! coverage by lines `sigma` px wide centred on the exact circles, from 16 x 16
//! subsamples. Every method draws white lines on a black surface, so red / 255 is its
//! coverage; the score is the RMS difference over the surface's pixels. Frame times
//! are the fastest of several frames drawn and waited for (on a shared machine the
//! fastest is the one least disturbed by other work); the baseline's extraction
//! (marching triangles on the CPU and upload) is timed apart, since it is paid again
//! whenever the field or the spacing changes.

use std::time::Instant;

use anyhow::Result;
use serde::Serialize;
use strata_grid::SurfaceMesh;
use strata_render::contour::{ContourTechnique, levels, marching_triangles};
use strata_render::glam::Vec3;
use strata_render::wire::Drawable;
use strata_render::{
    Camera, Coverage, IsolineOptions, Isolines, RangeAdjust, Renderer, Style, View, WireMode,
};

const SIZE: u32 = 800;
const CELLS: usize = 256;
const SPACING: f32 = 0.05;
const SIGMA: f32 = 2.0;
const SUBSAMPLES: u32 = 16;
const FRAMES: usize = 7;

/// One method's score and times.
#[derive(Debug, Serialize)]
pub struct Method {
    /// The method: `texture` or `analytic` coverage on the fragment path, the same
    /// with the isoline technique's range-adjust prepass `off` or `on`, or the
    /// `marching triangles + lines` baseline.
    pub name: String,
    /// RMS coverage difference to the reference over surface pixels (0..1).
    pub rms: f64,
    /// The same over pixels within 2 sigma of a line (where lines are).
    pub rms_near_lines: f64,
    /// Fastest of the frames drawn, milliseconds.
    pub frame_ms: f64,
    /// Time to extract and upload the polylines (baseline only), milliseconds.
    pub extract_ms: Option<f64>,
}

/// What `strata bench isolines` measured; `--json` prints it as is.
#[derive(Debug, Serialize)]
pub struct Report {
    /// The GPU adapter that drew the frames (name, backend, driver).
    pub adapter: String,
    /// Frame width, pixels.
    pub width: u32,
    /// Frame height, pixels.
    pub height: u32,
    /// Triangles of the plane drawn.
    pub triangles: usize,
    /// Polylines the marching-triangles baseline extracted (a circle cut by the
    /// plane's edge may give several).
    pub isolines: usize,
    /// Line width of every method and of the reference, pixels.
    pub sigma: f32,
    /// Subsamples per pixel side of the reference coverage (this squared per pixel).
    pub subsamples: u32,
    /// The shaded surface alone, for the ratio of every method to it.
    pub surface_only_ms: f64,
    /// One row per method, in the order above.
    pub methods: Vec<Method>,
}

/// The plane carrying f = x² + y², and the head-on view of it.
fn scene() -> (SurfaceMesh, View) {
    let h = 2.0 / CELLS as f32;
    let mut mesh = SurfaceMesh::structured(CELLS, CELLS, |i, j| {
        [i as f32 * h - 1.0, j as f32 * h - 1.0, 0.0]
    });
    mesh.scalars = mesh
        .positions
        .iter()
        .map(|p| p[0] * p[0] + p[1] * p[1])
        .collect();
    let fov: f32 = 35.0;
    // A little margin around the plane.
    let distance = 1.05 / (0.5 * fov.to_radians()).tan();
    let mut camera = Camera::look_at(Vec3::new(0.0, 0.0, distance), Vec3::ZERO, Vec3::Y);
    camera.fov_y_deg = fov;
    let view = View {
        camera,
        width: SIZE,
        height: SIZE,
        bounds: (Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)),
    };
    (mesh, view)
}

/// White lines of [`SIGMA`] px on a black surface, the isolines drawn or not.
fn style(coverage: Coverage, isolines: bool) -> Style {
    Style {
        thickness: SIGMA,
        coverage,
        wire_color: [1.0, 1.0, 1.0, 1.0],
        solid_color: [0.0, 0.0, 0.0, 1.0],
        background: [0.0, 0.0, 1.0, 1.0],
        isolines: Some(Isolines {
            color: [1.0, 1.0, 1.0, if isolines { 1.0 } else { 0.0 }],
            major_every: 0,
            ..Isolines::new(SPACING)
        }),
        ..Style::default()
    }
}

/// Pixel centre -> plane point of the head-on view: centre and pixels per unit.
fn similarity(view: &View) -> (f32, f32, f32) {
    let (near, far) = view.camera.depth_range(view.bounds.0, view.bounds.1);
    let vp = view.camera.view_proj(1.0, near, far);
    let px = |p: Vec3| {
        let n = vp.project_point3(p);
        (
            (n.x + 1.0) * 0.5 * SIZE as f32,
            (1.0 - n.y) * 0.5 * SIZE as f32,
        )
    };
    let (cx, cy) = px(Vec3::ZERO);
    let (ux, _) = px(Vec3::X);
    (cx, cy, ux - cx)
}

/// Reference coverage per pixel (NaN off the plane) and whether it is near a line.
fn reference(view: &View, radii: &[f32]) -> (Vec<f32>, Vec<bool>) {
    let (cx, cy, scale) = similarity(view);
    let half = 0.5 * SIGMA / scale;
    let mut cov = vec![f32::NAN; (SIZE * SIZE) as usize];
    let mut near = vec![false; cov.len()];
    let nearest = |r: f32| {
        radii
            .iter()
            .map(|rk| (r - rk).abs())
            .fold(f32::INFINITY, f32::min)
    };
    for py in 0..SIZE {
        for px in 0..SIZE {
            let (x0, y0) = (
                (px as f32 + 0.5 - cx) / scale,
                -(py as f32 + 0.5 - cy) / scale,
            );
            if x0.abs() > 1.0 || y0.abs() > 1.0 {
                continue;
            }
            let i = (py * SIZE + px) as usize;
            let d = nearest((x0 * x0 + y0 * y0).sqrt());
            near[i] = d < 2.0 * SIGMA / scale;
            if d > half + 1.0 / scale {
                cov[i] = 0.0;
                continue;
            }
            let mut inside = 0u32;
            for sy in 0..SUBSAMPLES {
                for sx in 0..SUBSAMPLES {
                    let x = (px as f32 + (sx as f32 + 0.5) / SUBSAMPLES as f32 - cx) / scale;
                    let y = -(py as f32 + (sy as f32 + 0.5) / SUBSAMPLES as f32 - cy) / scale;
                    if nearest((x * x + y * y).sqrt()) <= half {
                        inside += 1;
                    }
                }
            }
            cov[i] = inside as f32 / (SUBSAMPLES * SUBSAMPLES) as f32;
        }
    }
    (cov, near)
}

/// RMS over the plane's pixels, and over those near lines.
fn score(rgba: &[u8], reference: &[f32], near: &[bool]) -> (f64, f64) {
    let (mut all, mut n_all, mut close, mut n_close) = (0f64, 0usize, 0f64, 0usize);
    for (i, p) in rgba.chunks_exact(4).enumerate() {
        let want = reference[i];
        if want.is_nan() {
            continue;
        }
        let got = f32::from(p[0]) / 255.0;
        let e = f64::from(got - want).powi(2);
        all += e;
        n_all += 1;
        if near[i] {
            close += e;
            n_close += 1;
        }
    }
    (
        (all / n_all.max(1) as f64).sqrt(),
        (close / n_close.max(1) as f64).sqrt(),
    )
}

/// Milliseconds of the fastest of [`FRAMES`] frames of `items`, each waited for,
/// after an untimed one.
fn frame_ms(r: &mut Renderer, items: &[&dyn Drawable], view: &View, style: &Style) -> Result<f64> {
    r.draw(items, view, style)?;
    let times: Vec<f64> = (0..FRAMES)
        .map(|_| {
            let t = Instant::now();
            r.draw(items, view, style)
                .map(|()| t.elapsed().as_secs_f64() * 1e3)
        })
        .collect::<Result<_, _>>()?;
    Ok(times.into_iter().fold(f64::INFINITY, f64::min))
}

/// Runs the benchmark: every method's score against the reference and its frame
/// time, on the headless renderer's adapter.
pub fn run() -> Result<Report> {
    let (mesh, view) = scene();
    let iso = Isolines::new(SPACING);
    let values = levels(&iso, 1e-6, 2.0, 10_000);
    // Circles wholly or partly on the plane.
    let radii: Vec<f32> = values.iter().map(|v| v.sqrt()).collect();
    let (reference, near) = reference(&view, &radii);
    let mut r = Renderer::headless()?;
    let mut methods = Vec::new();

    let surface = r.prepare(&mesh, WireMode::None)?;
    let surface_only_ms = frame_ms(
        &mut r,
        &[surface.as_ref()],
        &view,
        &style(Coverage::Texture, false),
    )?;

    for coverage in [Coverage::Texture, Coverage::Analytic] {
        let name = match coverage {
            Coverage::Texture => "texture",
            Coverage::Analytic => "analytic",
        };
        // Isolines on the fragment path of `none` (no prepass) ...
        let s = style(coverage, true);
        let image = r.render(&[surface.as_ref()], &view, &s)?;
        let (rms, rms_near_lines) = score(image.as_raw(), &reference, &near);
        methods.push(Method {
            name: format!("{name} (fragment path)"),
            rms,
            rms_near_lines,
            frame_ms: frame_ms(&mut r, &[surface.as_ref()], &view, &s)?,
            extract_ms: None,
        });
        // ... and with the isoline technique's range-adjust prepass.
        for (adjust_name, adjust) in [("off", RangeAdjust::Off), ("on", RangeAdjust::On)] {
            let d = r.prepare_isolines(
                &mesh,
                None,
                IsolineOptions {
                    adjust,
                    wire: false,
                },
            )?;
            let image = r.render(&[d.as_ref()], &view, &s)?;
            let (rms, rms_near_lines) = score(image.as_raw(), &reference, &near);
            methods.push(Method {
                name: format!("{name}, adjust {adjust_name}"),
                rms,
                rms_near_lines,
                frame_ms: frame_ms(&mut r, &[d.as_ref()], &view, &s)?,
                extract_ms: None,
            });
        }
    }

    // The baseline: marching triangles on the CPU, line primitives over the surface.
    let technique = ContourTechnique::new(&r.context());
    let t = Instant::now();
    let polylines = marching_triangles(&mesh, &mesh.scalars, &values);
    let lines = technique.prepare(&r.gpu, &polylines)?;
    r.gpu.wait()?;
    let extract_ms = t.elapsed().as_secs_f64() * 1e3;
    // The surface without isolines (their colour's alpha is 0); the line primitives
    // take that colour, opaque.
    let s = style(Coverage::Texture, false);
    let items: [&dyn Drawable; 2] = [surface.as_ref(), &lines];
    let image = r.render(&items, &view, &s)?;
    let (rms, rms_near_lines) = score(image.as_raw(), &reference, &near);
    methods.push(Method {
        name: "marching triangles + lines".into(),
        rms,
        rms_near_lines,
        frame_ms: frame_ms(&mut r, &items, &view, &s)?,
        extract_ms: Some(extract_ms),
    });
    Ok(Report {
        adapter: r.gpu.describe(),
        width: SIZE,
        height: SIZE,
        triangles: mesh.triangle_count(),
        isolines: polylines.len(),
        sigma: SIGMA,
        subsamples: SUBSAMPLES,
        surface_only_ms,
        methods,
    })
}

/// Prints the report as a table: the scene, then a row per method.
pub fn print_table(report: &Report) {
    println!(
        "{} | {}x{} | {} triangles | {} polylines | sigma {} px | reference {}x{} subsamples | surface alone {:.1} ms",
        report.adapter,
        report.width,
        report.height,
        report.triangles,
        report.isolines,
        report.sigma,
        report.subsamples,
        report.subsamples,
        report.surface_only_ms
    );
    println!(
        "{:<30} {:>8} {:>10} {:>10} {:>8} {:>11}",
        "method", "rms", "rms(lines)", "frame ms", "x surf", "extract ms"
    );
    for m in &report.methods {
        println!(
            "{:<30} {:>8.4} {:>10.4} {:>10.1} {:>8.2} {:>11}",
            m.name,
            m.rms,
            m.rms_near_lines,
            m.frame_ms,
            m.frame_ms / report.surface_only_ms,
            m.extract_ms.map_or("-".into(), |e| format!("{e:.1}"))
        );
    }
}
