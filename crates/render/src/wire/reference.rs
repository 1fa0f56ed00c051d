//! The quality reference of `strata bench quality`: the exact coverage of each pixel
//! by the visible parts of a mesh's real edges drawn as lines of width σ, by heavy
//! supersampling on the CPU. It is used only to measure the techniques, never to draw.
//!
//! The right picture, in Bærentzen et al.'s words, is "to first find the visible set of
//! line segments and then to draw only these segments". Here the surface is rasterized
//! at `n` x `n` samples per pixel keeping each sample's nearest triangle and depth; a
//! sample is on a line when it is within σ/2 pixels of a real edge's projection and the
//! nearest point of that projection (the foot) is visible: the samples at the foot
//! belong to one of the edge's own triangles, or the edge is in front of what is there
//! (silhouettes and outlines, whose lines stick out over what lies behind). A pixel's
//! coverage is the fraction of its samples on a line: a box filter, as the texture
//! techniques' coverage is.

use glam::{Vec2, Vec4};
use strata_grid::SurfaceMesh;

use super::lines::{EdgeTable, NONE};
use crate::{Error, Result, View};

/// Per-pixel line coverage, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct CoverageImage {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Coverage in 0..1 per pixel, row after row.
    pub coverage: Vec<f32>,
}

impl CoverageImage {
    /// The coverage at pixel (`x`, `y`).
    pub fn at(&self, x: u32, y: u32) -> f32 {
        self.coverage[(y * self.width + x) as usize]
    }
}

/// The surface sampled `n` x `n` times per pixel: nearest triangle (plus one; 0 where
/// there is none) and its depth (reversed: greater is nearer).
struct Samples {
    n: u32,
    width: usize,
    height: usize,
    id: Vec<u32>,
    depth: Vec<f32>,
}

impl Samples {
    fn at(&self, x: i64, y: i64) -> Option<usize> {
        (x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height)
            .then(|| y as usize * self.width + x as usize)
    }
}

/// A clip-space point and where it lands in the window (pixels, y down).
#[derive(Clone, Copy)]
struct Projected {
    window: Vec2,
    depth: f32,
}

fn project(c: Vec4, width: f32, height: f32) -> Projected {
    let ndc = c / c.w;
    Projected {
        window: Vec2::new((0.5 + 0.5 * ndc.x) * width, (0.5 - 0.5 * ndc.y) * height),
        depth: ndc.z,
    }
}

/// Clips the polygon `poly` to the visible side of the near plane (reversed depth:
/// z <= w), as the rasterizer does.
fn clip_near(poly: &[Vec4]) -> Vec<Vec4> {
    let mut out = Vec::with_capacity(poly.len() + 1);
    for (i, &a) in poly.iter().enumerate() {
        let b = poly[(i + 1) % poly.len()];
        let (fa, fb) = (a.z - a.w, b.z - b.w);
        if fa <= 0.0 {
            out.push(a);
        }
        if (fa <= 0.0) != (fb <= 0.0) {
            out.push(a + (b - a) * (fa / (fa - fb)));
        }
    }
    out
}

/// The exact coverage of the visible real edges of `mesh` seen in `view`, as lines of
/// width `sigma` pixels, from `n` x `n` samples per pixel (16 or more for the bench).
pub fn line_coverage(mesh: &SurfaceMesh, view: &View, sigma: f32, n: u32) -> Result<CoverageImage> {
    if view.width == 0 || view.height == 0 || n == 0 || sigma.is_nan() || sigma <= 0.0 {
        return Err(Error::Invalid(format!(
            "reference of {}x{} pixels, {n} x {n} samples, width {sigma}",
            view.width, view.height
        )));
    }
    mesh.validate().map_err(Error::Invalid)?;
    let (w, h) = (view.width as f32, view.height as f32);
    let (near, far) = view.camera.depth_range(view.bounds.0, view.bounds.1);
    let to_clip = view.camera.view_proj(w / h, near, far);
    let clip: Vec<Vec4> = mesh
        .positions
        .iter()
        .map(|p| to_clip * Vec4::new(p[0], p[1], p[2], 1.0))
        .collect();
    let mut samples = Samples {
        n,
        width: (view.width * n) as usize,
        height: (view.height * n) as usize,
        id: Vec::new(),
        depth: Vec::new(),
    };
    samples.id = vec![0; samples.width * samples.height];
    samples.depth = vec![f32::NEG_INFINITY; samples.width * samples.height];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let poly = clip_near(&tri.map(|v| clip[v as usize]));
        for k in 1..poly.len().saturating_sub(1) {
            let corners = [poly[0], poly[k], poly[k + 1]].map(|c| project(c, w, h));
            rasterize(&mut samples, corners, t as u32 + 1);
        }
    }
    let table = EdgeTable::new(mesh);
    let mut on_line = vec![false; samples.width * samples.height];
    for (edge, tris) in table.edges.iter().zip(&table.triangles) {
        let ids = [tris[0], tris[1]].map(|t| if t == NONE { 0 } else { t + 1 });
        let ends = clip_near(&[clip[edge[0] as usize], clip[edge[1] as usize]]);
        // A segment clipped to a point or nothing draws nothing.
        if ends.len() < 2 {
            continue;
        }
        let (a, b) = (project(ends[0], w, h), project(ends[1], w, h));
        draw_edge(&samples, &mut on_line, a, b, ids, 0.5 * sigma);
    }
    let mut coverage = vec![0f32; (view.width * view.height) as usize];
    let per_pixel = (n * n) as f32;
    for (i, on) in on_line.iter().enumerate() {
        if *on {
            let (sx, sy) = (i % samples.width, i / samples.width);
            let p = (sy / n as usize) * view.width as usize + sx / n as usize;
            coverage[p] += 1.0 / per_pixel;
        }
    }
    Ok(CoverageImage {
        width: view.width,
        height: view.height,
        coverage,
    })
}

/// Rasterizes a window-space triangle into the samples, nearest depth winning.
fn rasterize(s: &mut Samples, c: [Projected; 3], id: u32) {
    let n = s.n as f32;
    let p = c.map(|q| q.window * n);
    let area = (p[1] - p[0]).perp_dot(p[2] - p[0]);
    if area == 0.0 || !area.is_finite() {
        return;
    }
    let lo = p[0].min(p[1]).min(p[2]).floor().max(Vec2::ZERO);
    let hi = p[0]
        .max(p[1])
        .max(p[2])
        .ceil()
        .min(Vec2::new(s.width as f32, s.height as f32));
    for y in lo.y as usize..hi.y as usize {
        for x in lo.x as usize..hi.x as usize {
            let q = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            // Barycentric weights, signed like the area so both windings fill.
            let b0 = (p[2] - p[1]).perp_dot(q - p[1]) / area;
            let b1 = (p[0] - p[2]).perp_dot(q - p[2]) / area;
            let b2 = 1.0 - b0 - b1;
            if b0 < 0.0 || b1 < 0.0 || b2 < 0.0 {
                continue;
            }
            let depth = b0 * c[0].depth + b1 * c[1].depth + b2 * c[2].depth;
            let i = y * s.width + x;
            if depth >= s.depth[i] && (0.0..=1.0).contains(&depth) {
                s.depth[i] = depth;
                s.id[i] = id;
            }
        }
    }
}

/// Marks the samples within `half` pixels of segment a b whose foot is visible.
fn draw_edge(s: &Samples, on: &mut [bool], a: Projected, b: Projected, ids: [u32; 2], half: f32) {
    let n = s.n as f32;
    let (pa, pb) = (a.window * n, b.window * n);
    let reach = half * n;
    let d = pb - pa;
    let len2 = d.length_squared();
    let lo = (pa.min(pb) - Vec2::splat(reach)).floor().max(Vec2::ZERO);
    let hi = (pa.max(pb) + Vec2::splat(reach))
        .ceil()
        .min(Vec2::new(s.width as f32, s.height as f32));
    for y in lo.y as usize..hi.y as usize {
        for x in lo.x as usize..hi.x as usize {
            let i = y * s.width + x;
            if on[i] {
                continue;
            }
            let q = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let t = if len2 > 0.0 {
                ((q - pa).dot(d) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let foot = pa + d * t;
            if q.distance(foot) > reach {
                continue;
            }
            on[i] = foot_visible(s, foot, a.depth + t * (b.depth - a.depth), ids);
        }
    }
}

/// Whether the edge point at sample position `foot` with depth `depth` is visible: a
/// sample next to it shows one of the edge's triangles, or the edge is in front of what
/// the sample at it shows.
fn foot_visible(s: &Samples, foot: Vec2, depth: f32, ids: [u32; 2]) -> bool {
    let (fx, fy) = (foot.x.floor() as i64, foot.y.floor() as i64);
    for dy in -1..=1 {
        for dx in -1..=1 {
            if let Some(i) = s.at(fx + dx, fy + dy) {
                if s.id[i] != 0 && (s.id[i] == ids[0] || s.id[i] == ids[1]) {
                    return true;
                }
            }
        }
    }
    match s.at(fx, fy) {
        Some(i) => depth >= s.depth[i] - 1e-5 * s.depth[i].abs(),
        None => true,
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::Camera;

    /// A head-on view of a 4 x 4 grid of 20-unit cells, 1 unit per pixel.
    fn head_on() -> (SurfaceMesh, View) {
        let mesh = SurfaceMesh::structured(4, 4, |i, j| {
            [i as f32 * 20.0 - 40.0, j as f32 * 20.0 - 40.0, 0.0]
        });
        let fov = 35f32;
        let distance = 50.0 / (0.5 * fov.to_radians()).tan();
        let mut camera = Camera::look_at(Vec3::new(0.0, 0.0, distance), Vec3::ZERO, Vec3::Y);
        camera.fov_y_deg = fov;
        let view = View {
            camera,
            width: 100,
            height: 100,
            bounds: (Vec3::new(-40.0, -40.0, 0.0), Vec3::new(40.0, 40.0, 0.0)),
        };
        (mesh, view)
    }

    #[test]
    fn a_line_covers_its_width_across_and_no_diagonal() {
        let (mesh, view) = head_on();
        let image = line_coverage(&mesh, &view, 3.0, 16).unwrap();
        // Interior vertical line x = 0 at pixel column 50 (window x = 50): the coverage
        // summed across a row is the width, 3 pixels.
        let across: f32 = (40..60).map(|x| image.at(x, 35)).sum();
        assert!((across - 3.0).abs() < 0.05, "row sum {across}");
        // The outline line at x = -40 (window 10) sticks out over the background: full
        // width there too.
        let outline: f32 = (0..20).map(|x| image.at(x, 35)).sum();
        assert!((outline - 3.0).abs() < 0.05, "outline {outline}");
        // Cell (0, 0)'s diagonal runs through window (20, 80) .. (30, 70): nothing there.
        assert_eq!(image.at(25, 75), 0.0);
        assert_eq!(image.at(26, 74), 0.0);
    }

    #[test]
    fn hidden_edges_are_not_drawn() {
        let (mut mesh, mut view) = head_on();
        view.bounds.1.z = 10.0;
        // A square 10 units nearer the eye hides the middle of the grid.
        let cover = SurfaceMesh::structured(1, 1, |i, j| {
            [i as f32 * 50.0 - 25.0, j as f32 * 50.0 - 25.0, 10.0]
        });
        mesh.append(&cover);
        let image = line_coverage(&mesh, &view, 2.0, 16).unwrap();
        // Line x = 0 is under the square (window 50, rows ~ 26 .. 74) but visible
        // further down.
        assert_eq!(image.at(50, 50), 0.0);
        assert!(image.at(49, 85) + image.at(50, 85) > 0.9);
    }

    #[test]
    fn refuses_an_empty_view() {
        let (mesh, mut view) = head_on();
        view.width = 0;
        assert!(line_coverage(&mesh, &view, 1.0, 16).is_err());
    }
}
