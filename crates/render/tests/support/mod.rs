//! Shared helpers of the measured image tests of the wireframe.
//!
//! # Measuring convention
//!
//! Frames are drawn over the surface (`isolation: false`) with [`measuring_style`]:
//! `solid_color` black, `wire_color` white, `background` pure blue and
//! `scalar_range: None`. Shading multiplies the base colour, so a black surface stays
//! black and a surface pixel is `mix(black, white, coverage)`: its red channel / 255
//! is the line coverage of that pixel, and its three channels are equal. Background
//! pixels are (0, 0, 255); [`Frame`] tells them apart from the surface by blue minus
//! red.
//!
//! Screen positions come from the renderer's own transform:
//! `camera.view_proj(width / height, near, far)` with
//! `(near, far) = camera.depth_range(bounds.0, bounds.1)`, NDC mapped to pixels with x
//! to the right and y down, so that pixel `(i, j)` spans `[i, i + 1] x [j, j + 1]` and
//! its centre is `(i + 0.5, j + 0.5)` ([`Projector`]).
//!
//! The width of a line is its full width at half coverage, perpendicular to the line
//! on screen. It is measured along a pixel row (for lines closer to vertical) or a
//! pixel column (closer to horizontal): the coverage of the pixels of that row is the
//! line's cross profile stretched by `1 / |n_x|` (`n` the line's unit normal on
//! screen), so the two half-coverage crossings, found by linear interpolation between
//! pixel centres, are `width / |n_x|` apart, and their midpoint is the line's centre
//! on that row. The coverage summed over the scan times `|n_x|` is a second estimate of
//! the width (the integral of the profile). A scan is only taken where the line is
//! measurable: the local cell width `1 / |grad a|` (a the cell index across the line,
//! from the exact Jacobian of the projection) is at least 3 sigma pixels on both sides,
//! so the saturation cap does not apply; every pixel of the scan is on the surface and
//! at least `sigma / 2 + 1.5` px from every other grid line (no crossings); the border
//! lines of the surface are never measured (there one polygon draws half the line).
//!
//! Resolution: along the normal, a box-filtered edge is a ramp one pixel long between
//! the line's plateau and the background. When both ends of the ramp are sampled
//! (sigma >= 2), linear interpolation puts the half-coverage point within 0.09 px of
//! the true one. A 1 px line has no plateau (its profile is a triangle 2 px wide at
//! the base), and the interpolated width depends on where the pixel centres fall:
//! from 1.0 down to about 0.6 px with exactly computed coverage. The integral, which
//! is sigma for any box-filtered line, is the sharper check there. The half-coverage
//! level is taken as 0.5 - 1.5/255 so that a 1 px line centred between two pixel
//! centres, both at 127/255, still has crossings; this widens the measure by 0.01 px.

#![allow(dead_code)]

use std::fmt;
use std::sync::{Mutex, MutexGuard, OnceLock, PoisonError};

use image::RgbaImage;
use strata_grid::SurfaceMesh;
use strata_lod::{BuildOptions, LodFile, build_file};
use strata_render::glam::{Mat2, Mat4, Vec2, Vec3};
use strata_render::{Camera, Coverage, Renderer, Style, View, WireMode};

/// The texture techniques: all draw their lines from texture coordinates, major lines
/// and the outline's outer half from the global ones.
pub const TEXTURE_MODES: [WireMode; 4] = [
    WireMode::Global,
    WireMode::Quad,
    WireMode::Tex,
    WireMode::TexGs,
];

/// Both coverage forms.
pub const FORMS: [Coverage; 2] = [Coverage::Texture, Coverage::Analytic];

/// The background of measured frames: pure blue, never a surface colour.
pub const BACKGROUND: [f32; 4] = [0.0, 0.0, 1.0, 1.0];

/// The renderer of this test binary, on the adapter the environment selects
/// (`WGPU_BACKEND`); fails with the renderer's own error when there is none: these
/// tests never skip. One device for the whole binary, lent to one test at a time:
/// tests that each opened a device and dropped it while others drew hung NVIDIA's
/// Vulkan driver (580, on an H200) about one run in ten, `vkDestroyDevice`
/// deadlocked with the other threads' submissions. A test that changes the
/// renderer's limits puts them back before it asserts.
pub fn renderer() -> MutexGuard<'static, Renderer> {
    static SHARED: OnceLock<Mutex<Renderer>> = OnceLock::new();
    SHARED
        .get_or_init(|| match Renderer::headless() {
            Ok(r) => {
                eprintln!("adapter: {}", r.gpu.describe());
                Mutex::new(r)
            }
            Err(e) => panic!("cannot open a renderer: {e}"),
        })
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
}

/// A short name of the adapter's backend for reports ("Gl", "Vulkan", ...).
pub fn backend(r: &Renderer) -> String {
    format!("{:?}", r.gpu.info.backend)
}

/// The style of the measuring convention (see the module docs).
pub fn measuring_style(sigma: f32, coverage: Coverage) -> Style {
    Style {
        thickness: sigma,
        coverage,
        wire_color: [1.0, 1.0, 1.0, 1.0],
        solid_color: [0.0, 0.0, 0.0, 1.0],
        scalar_range: None,
        isolation: false,
        background: BACKGROUND,
        ..Style::default()
    }
}

/// The renderer's clip transform, mapped to pixels.
#[derive(Clone, Copy, Debug)]
pub struct Projector {
    pub view_proj: Mat4,
    pub width: f32,
    pub height: f32,
}

impl Projector {
    pub fn new(view: &View) -> Self {
        let (near, far) = view.camera.depth_range(view.bounds.0, view.bounds.1);
        let aspect = view.width as f32 / view.height.max(1) as f32;
        Projector {
            view_proj: view.camera.view_proj(aspect, near, far),
            width: view.width as f32,
            height: view.height as f32,
        }
    }

    /// Pixel position of a world point (x right, y down, pixel centres at +0.5).
    pub fn to_px(self, p: Vec3) -> Vec2 {
        let ndc = self.view_proj.project_point3(p);
        Vec2::new(
            (ndc.x + 1.0) * 0.5 * self.width,
            (1.0 - ndc.y) * 0.5 * self.height,
        )
    }
}

/// A frame's coverage: red / 255 on surface pixels, and which pixels are surface.
pub struct Frame {
    pub width: usize,
    pub height: usize,
    pub coverage: Vec<f32>,
    pub surface: Vec<bool>,
}

impl Frame {
    /// Reads a frame drawn with [`measuring_style`]. Checks that surface pixels are
    /// grey (the convention holds). The outline's outer half, drawn beyond the surface,
    /// blends the white wire into the blue background: such pixels (equal red and
    /// green, full blue) are off the surface.
    pub fn new(image: &RgbaImage) -> Self {
        let (width, height) = (image.width() as usize, image.height() as usize);
        let mut coverage = Vec::with_capacity(width * height);
        let mut surface = Vec::with_capacity(width * height);
        for p in image.pixels() {
            let [r, g, b, _] = p.0;
            let over_background = b >= 254 && r.abs_diff(g) <= 2 && b > r.saturating_add(2);
            let on = !over_background && i32::from(b) - i32::from(r) < 128;
            if on {
                assert!(
                    r.abs_diff(g) <= 2 && r.abs_diff(b) <= 2,
                    "surface pixel {:?} is not grey: the measuring convention does not hold",
                    p.0
                );
            }
            surface.push(on);
            coverage.push(if on { f32::from(r) / 255.0 } else { 0.0 });
        }
        Frame {
            width,
            height,
            coverage,
            surface,
        }
    }

    pub fn at(&self, x: i64, y: i64) -> Option<(f32, bool)> {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            return None;
        }
        let i = y as usize * self.width + x as usize;
        Some((self.coverage[i], self.surface[i]))
    }

    /// Number of surface pixels and their mean coverage.
    pub fn surface_mean(&self) -> (usize, f64) {
        let (mut n, mut sum) = (0usize, 0f64);
        for (c, s) in self.coverage.iter().zip(&self.surface) {
            if *s {
                n += 1;
                sum += f64::from(*c);
            }
        }
        (n, if n == 0 { 0.0 } else { sum / n as f64 })
    }

    /// Number of surface pixels whose coverage is above `threshold`.
    pub fn count_above(&self, threshold: f32) -> usize {
        self.coverage
            .iter()
            .zip(&self.surface)
            .filter(|(c, s)| **s && **c > threshold)
            .count()
    }
}

/// A planar structured grid of `ni` x `nj` cells: node `(i, j)` at
/// `origin + i du + j dv`, drawn from `SurfaceMesh::structured` (global coordinates
/// `(2i + 1, 2j + 1)`).
#[derive(Clone, Copy, Debug)]
pub struct PlaneGrid {
    pub ni: usize,
    pub nj: usize,
    pub origin: Vec3,
    pub du: Vec3,
    pub dv: Vec3,
}

impl PlaneGrid {
    /// A square grid of `n` x `n` cells of side `cell`, centred at the origin of the
    /// z = 0 plane and rotated by `angle_deg` about z.
    pub fn square(n: usize, cell: f32, angle_deg: f32) -> Self {
        let (s, c) = angle_deg.to_radians().sin_cos();
        let du = Vec3::new(c, s, 0.0) * cell;
        let dv = Vec3::new(-s, c, 0.0) * cell;
        let half = 0.5 * n as f32;
        PlaneGrid {
            ni: n,
            nj: n,
            origin: -(du + dv) * half,
            du,
            dv,
        }
    }

    /// The world point of grid parameters `(a, b)` (node `(i, j)` at `(i, j)`).
    pub fn point(&self, a: f32, b: f32) -> Vec3 {
        self.origin + self.du * a + self.dv * b
    }

    pub fn mesh(&self) -> SurfaceMesh {
        SurfaceMesh::structured(self.ni, self.nj, |i, j| {
            self.point(i as f32, j as f32).to_array()
        })
    }

    /// Bounds of the grid (the `View::bounds` to draw it with).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let corners = [
            self.point(0.0, 0.0),
            self.point(self.ni as f32, 0.0),
            self.point(0.0, self.nj as f32),
            self.point(self.ni as f32, self.nj as f32),
        ];
        let lo = corners
            .iter()
            .fold(Vec3::splat(f32::INFINITY), |a, &b| a.min(b));
        let hi = corners
            .iter()
            .fold(Vec3::splat(f32::NEG_INFINITY), |a, &b| a.max(b));
        (lo, hi)
    }

    pub fn centre(&self) -> Vec3 {
        self.point(0.5 * self.ni as f32, 0.5 * self.nj as f32)
    }
}

/// A camera looking at `grid`'s centre (a grid in the z = 0 plane) from `distance`,
/// tilted `tilt_deg` from the vertical (0: head-on) towards -y, with +y up on screen:
/// a grid rotated in its plane shows its lines rotated on screen.
pub fn grid_camera(grid: &PlaneGrid, tilt_deg: f32, distance: f32) -> Camera {
    let (s, c) = tilt_deg.to_radians().sin_cos();
    let dir = Vec3::new(0.0, -s, c);
    Camera::look_at(grid.centre() + dir * distance, grid.centre(), Vec3::Y)
}

/// A view of `grid` with `camera` at `size` x `size` pixels.
pub fn grid_view(grid: &PlaneGrid, camera: Camera, size: u32) -> View {
    View {
        camera,
        width: size,
        height: size,
        bounds: grid.bounds(),
    }
}

/// One line family of a grid: lines of constant `a` (index `i`, along dv) or of
/// constant `b` (index `j`, along du).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    I,
    J,
}

/// One measurement across a line.
#[derive(Clone, Copy, Debug)]
pub struct Scan {
    pub family: Family,
    pub index: usize,
    /// Where the scan crosses the projected line (pixels).
    pub at: Vec2,
    /// Angle of the line on screen, degrees in [0, 180).
    pub angle_deg: f32,
    /// Local cell width across the line, pixels.
    pub cell_px: f32,
    /// Full width at half coverage, perpendicular to the line (pixels).
    pub width: f32,
    /// Integral of coverage across the line (pixels).
    pub integral: f32,
    /// Signed perpendicular distance of the measured centre from the projected line.
    pub offset: f32,
    /// Largest coverage on the scan.
    pub peak: f32,
    /// A pixel with coverage in (0.05, 0.95) on each side of the projected line.
    pub partial_before: bool,
    pub partial_after: bool,
}

/// Infinite line through two screen points, as point + unit direction.
#[derive(Clone, Copy, Debug)]
struct ScreenLine {
    p: Vec2,
    t: Vec2,
}

impl ScreenLine {
    fn through(a: Vec2, b: Vec2) -> Self {
        ScreenLine {
            p: a,
            t: (b - a).normalize(),
        }
    }

    fn distance(&self, q: Vec2) -> f32 {
        (q - self.p).perp_dot(self.t).abs()
    }
}

/// Measures every measurable line of `grid` in `frame` at about `per_cell` places per
/// cell edge (between crossings), for lines `sigma` pixels wide.
pub fn measure_grid(
    frame: &Frame,
    proj: &Projector,
    grid: &PlaneGrid,
    sigma: f32,
    per_cell: usize,
) -> Vec<Scan> {
    measure_grid_every(frame, proj, grid, sigma, per_cell, 1)
}

/// [`measure_grid`] for the lines every `every` cells alone (major lines), as if
/// they were the only ones: `per_cell` places between two crossing lines of theirs,
/// clear of their neighbours; the cell width of a scan is theirs (`every` cells).
pub fn measure_grid_every(
    frame: &Frame,
    proj: &Projector,
    grid: &PlaneGrid,
    sigma: f32,
    per_cell: usize,
    every: usize,
) -> Vec<Scan> {
    let mut scans = Vec::new();
    for family in [Family::I, Family::J] {
        let n_lines = match family {
            Family::I => grid.ni,
            Family::J => grid.nj,
        };
        // Interior lines only: the border lines are half lines by design.
        for k in (every..n_lines).step_by(every) {
            scans.extend(measure_line(
                frame,
                proj,
                grid,
                (sigma, per_cell, every),
                family,
                k,
            ));
        }
    }
    scans
}

/// The scans of [`measure_grid_every`] across line `k` of `family` alone, for lines
/// `sigma` px wide, `per_cell` of them between crossings `every` cells apart.
pub fn measure_line(
    frame: &Frame,
    proj: &Projector,
    grid: &PlaneGrid,
    (sigma, per_cell, every): (f32, usize, usize),
    family: Family,
    k: usize,
) -> Vec<Scan> {
    let screen_line = |family: Family, k: usize| -> ScreenLine {
        let k = k as f32;
        match family {
            Family::I => ScreenLine::through(
                proj.to_px(grid.point(k, 0.0)),
                proj.to_px(grid.point(k, grid.nj as f32)),
            ),
            Family::J => ScreenLine::through(
                proj.to_px(grid.point(0.0, k)),
                proj.to_px(grid.point(grid.ni as f32, k)),
            ),
        }
    };
    let n_along = match family {
        Family::I => grid.nj,
        Family::J => grid.ni,
    };
    let across = match family {
        Family::I => Family::J,
        Family::J => Family::I,
    };
    let mut scans = Vec::new();
    let line = screen_line(family, k);
    let neighbours = [
        screen_line(family, k - every),
        screen_line(family, k + every),
    ];
    for m in (0..n_along).step_by(every) {
        let end = (m + every).min(n_along);
        let crossings = [screen_line(across, m), screen_line(across, end)];
        for s in 0..per_cell {
            let f = (s as f32 + 0.5) / per_cell as f32;
            let along = m as f32 + f * (end - m) as f32;
            let (a, b) = match family {
                Family::I => (k as f32, along),
                Family::J => (along, k as f32),
            };
            let cell_px = every as f32 * cell_width_px(proj, grid, family, a, b);
            if cell_px < 3.0 * sigma {
                continue;
            }
            let at = proj.to_px(grid.point(a, b));
            let others: Vec<ScreenLine> = neighbours.iter().chain(&crossings).copied().collect();
            if let Some(scan) = scan_across(frame, line, at, sigma, &others) {
                scans.push(Scan {
                    family,
                    index: k,
                    cell_px,
                    ..scan
                });
            }
        }
    }
    scans
}

/// Width in pixels of the cells across a line of `family` at grid parameters (a, b):
/// `1 / |grad c|` where c is the grid parameter across the line (the shader's cap is
/// in units of the global coordinate 2c + 1, so this is the width the cap refers to).
pub fn cell_width_px(proj: &Projector, grid: &PlaneGrid, family: Family, a: f32, b: f32) -> f32 {
    let h = 1e-3;
    let p = proj.to_px(grid.point(a, b));
    let da = (proj.to_px(grid.point(a + h, b)) - p) / h;
    let db = (proj.to_px(grid.point(a, b + h)) - p) / h;
    // Screen = J (a, b); grad a and grad b are the rows of J^-1.
    let inv = Mat2::from_cols(da, db).inverse();
    let row = match family {
        Family::I => Vec2::new(inv.x_axis.x, inv.y_axis.x),
        Family::J => Vec2::new(inv.x_axis.y, inv.y_axis.y),
    };
    1.0 / row.length()
}

/// Scans across `line` near the screen point `at` (on the line). `None` when the scan
/// leaves the surface or the image, or comes near one of `others`.
fn scan_across(
    frame: &Frame,
    line: ScreenLine,
    at: Vec2,
    sigma: f32,
    others: &[ScreenLine],
) -> Option<Scan> {
    let n = line.t.perp();
    let rows = n.x.abs() >= n.y.abs();
    // Across the scan, one pixel step is |n_x| (rows) or |n_y| (columns) in distance.
    let stretch = if rows { n.x.abs() } else { n.y.abs() };
    let reach = (0.5 * sigma + 2.5) / stretch;
    let clear = 0.5 * sigma + 1.5;
    // The scan line (pixel centres) nearest `at`, and where the line crosses it.
    let (fixed, centre) = if rows {
        let y = at.y.floor() + 0.5;
        (y, at.x + (y - at.y) * line.t.x / line.t.y)
    } else {
        let x = at.x.floor() + 0.5;
        (x, at.y + (x - at.x) * line.t.y / line.t.x)
    };
    let first = (centre - reach - 0.5).floor() as i64;
    let last = (centre + reach - 0.5).ceil() as i64;
    let mut pos = Vec::new();
    let mut cov = Vec::new();
    for k in first..=last {
        let q = k as f32 + 0.5;
        let pixel = if rows {
            Vec2::new(q, fixed)
        } else {
            Vec2::new(fixed, q)
        };
        let (c, on) = if rows {
            frame.at(k, fixed.floor() as i64)?
        } else {
            frame.at(fixed.floor() as i64, k)?
        };
        if !on || others.iter().any(|o| o.distance(pixel) < clear) {
            return None;
        }
        pos.push(q);
        cov.push(c);
    }
    // No crossing (a gap, or a line wider than the scan) reads as width 0 and offset
    // NaN, which every check rejects.
    let (peak, edges) = half_coverage_edges(&pos, &cov);
    let (lo, hi) = edges.unwrap_or((f32::NAN, f32::NAN));
    let width = if lo.is_nan() {
        0.0
    } else {
        (hi - lo) * stretch
    };
    let integral = cov.iter().sum::<f32>() * stretch;
    // Offset along the scan times the stretch is the perpendicular offset; its sign
    // follows the scan axis.
    let offset = (0.5 * (lo + hi) - centre) * stretch;
    let partial = |c: &f32| *c > 0.05 && *c < 0.95;
    let partial_before = pos.iter().zip(&cov).any(|(p, c)| *p < centre && partial(c));
    let partial_after = pos.iter().zip(&cov).any(|(p, c)| *p > centre && partial(c));
    let angle = line.t.y.atan2(line.t.x).to_degrees().rem_euclid(180.0);
    Some(Scan {
        family: Family::I,
        index: 0,
        at: if rows {
            Vec2::new(centre, fixed)
        } else {
            Vec2::new(fixed, centre)
        },
        angle_deg: angle,
        cell_px: 0.0,
        width,
        integral,
        offset,
        peak,
        partial_before,
        partial_after,
    })
}

/// Mean, minimum and maximum of some numbers.
#[derive(Clone, Copy, Debug)]
pub struct Summary {
    pub n: usize,
    pub mean: f32,
    pub min: f32,
    pub max: f32,
}

impl Summary {
    pub fn of(values: impl IntoIterator<Item = f32>) -> Self {
        let (mut n, mut sum, mut min, mut max) = (0, 0f64, f32::INFINITY, f32::NEG_INFINITY);
        for v in values {
            n += 1;
            sum += f64::from(v);
            min = min.min(v);
            max = max.max(v);
        }
        Summary {
            n,
            mean: if n == 0 {
                f32::NAN
            } else {
                (sum / n as f64) as f32
            },
            min,
            max,
        }
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(
            f,
            "n {:4} mean {:6.3} min {:6.3} max {:6.3}",
            self.n, self.mean, self.min, self.max
        )
    }
}

/// Renders `items` with the measuring style and reads the frame.
pub fn render_frame(
    r: &mut Renderer,
    items: &[&dyn strata_render::wire::Drawable],
    view: &View,
    sigma: f32,
    coverage: Coverage,
) -> Frame {
    let image = r
        .render(items, view, &measuring_style(sigma, coverage))
        .unwrap_or_else(|e| panic!("render failed: {e}"));
    Frame::new(&image)
}

/// How two images differ: the largest per-channel difference, and how many pixels
/// differ by more than `tolerance` in some channel.
#[derive(Clone, Copy, Debug)]
pub struct ImageDiff {
    pub max: u8,
    pub over: usize,
    pub pixels: usize,
    pub tolerance: u8,
}

impl ImageDiff {
    pub fn of(a: &RgbaImage, b: &RgbaImage, tolerance: u8) -> Self {
        Self::of_pixels(a, b, tolerance, |_, _| true)
    }

    /// The difference over the pixels `(x, y)` for which `keep` holds.
    pub fn of_pixels(
        a: &RgbaImage,
        b: &RgbaImage,
        tolerance: u8,
        keep: impl Fn(u32, u32) -> bool,
    ) -> Self {
        assert_eq!(a.dimensions(), b.dimensions());
        let (mut max, mut over, mut pixels) = (0u8, 0usize, 0usize);
        for ((x, y, p), q) in a.enumerate_pixels().zip(b.pixels()) {
            if !keep(x, y) {
                continue;
            }
            pixels += 1;
            let d = (0..4).map(|c| p.0[c].abs_diff(q.0[c])).max().unwrap_or(0);
            max = max.max(d);
            if d > tolerance {
                over += 1;
            }
        }
        ImageDiff {
            max,
            over,
            pixels,
            tolerance,
        }
    }

    pub fn fraction_over(&self) -> f64 {
        self.over as f64 / self.pixels as f64
    }
}

impl fmt::Display for ImageDiff {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(
            f,
            "max |diff| {}/255, {} of {} pixels ({:.4}%) over {}/255",
            self.max,
            self.over,
            self.pixels,
            100.0 * self.fraction_over(),
            self.tolerance
        )
    }
}

/// The peak coverage of a profile sampled at `pos`, and where the coverage crosses
/// one half on either side of the peak (linear interpolation, walking out from the
/// peak; the level sits 1.5/255 below a half so that 8-bit rounding of an exact half
/// counts). `None` when a side never drops below the level or the peak never reaches
/// it: a gap, or a line wider than the scan.
pub fn half_coverage_edges(pos: &[f32], cov: &[f32]) -> (f32, Option<(f32, f32)>) {
    let (peak_i, peak) = cov
        .iter()
        .copied()
        .enumerate()
        .fold((0, f32::MIN), |m, (i, c)| if c > m.1 { (i, c) } else { m });
    let half = 0.5 - 1.5 / 255.0;
    let cross = |range: &mut dyn Iterator<Item = usize>| -> Option<f32> {
        let mut prev = peak_i;
        for i in range {
            if cov[i] < half {
                let (c0, c1) = (cov[prev], cov[i]);
                let t = (c0 - half) / (c0 - c1);
                return Some(pos[prev] + t * (pos[i] - pos[prev]));
            }
            prev = i;
        }
        None
    };
    let edges = match (
        cross(&mut (0..peak_i).rev()),
        cross(&mut (peak_i + 1..cov.len())),
    ) {
        (Some(lo), Some(hi)) if peak >= half => Some((lo, hi)),
        _ => None,
    };
    (peak, edges)
}

/// A grid of `n` x `n` x `nz` cells of 10 m on vertical pillars, its horizon `level`
/// (0 the top) at depth `depth(i, j, level)` at node (i, j), with `poro(i, j, k)` as
/// PORO, and its hierarchy of 8-cell tiles saved at `path`.
pub fn square_hierarchy(
    path: &std::path::Path,
    (n, nz): (usize, usize),
    depth: impl Fn(usize, usize, usize) -> f32 + Copy,
    poro: impl Fn(usize, usize, usize) -> f32,
) -> (strata_grid::CornerPointGrid, LodFile) {
    let coord: Vec<f64> = (0..=n)
        .flat_map(|j| (0..=n).map(move |i| (i, j)))
        .flat_map(|(i, j)| {
            let (x, y) = (10.0 * i as f64, 10.0 * j as f64);
            [x, y, 1000.0, x, y, 1100.0]
        })
        .collect();
    let zcorn: Vec<f32> = (0..nz)
        .flat_map(|k| [k, k + 1])
        .flat_map(|level| {
            (0..n).flat_map(move |j| {
                (0..2).flat_map(move |dj| {
                    (0..n).flat_map(move |i| (0..2).map(move |di| depth(i + di, j + dj, level)))
                })
            })
        })
        .collect();
    let dims = strata_grid::Dims { nx: n, ny: n, nz };
    let mut grid =
        strata_grid::CornerPointGrid::from_arrays(dims, coord, zcorn, None).expect("a grid");
    grid.set_property(
        "PORO",
        strata_grid::ndarray::Array3::from_shape_fn((nz, n, n), |(k, j, i)| poro(i, j, k)),
    )
    .expect("PORO");
    let options = BuildOptions {
        tile_cells: 8,
        ..BuildOptions::default()
    };
    build_file(&grid, Some("PORO"), path, &options).expect("build");
    let file = LodFile::open(path).expect("open");
    (grid, file)
}
