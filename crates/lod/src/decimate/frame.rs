//! The joint space in which errors are measured: positions about a centre with z
//! exaggerated, texture coordinates and scalar scaled into lengths, and which edges
//! are too stretched to measure (they reach a stray corner).

use strata_grid::SurfaceMesh;

use super::Options;
use super::vector::dot3;
use crate::measure::stray_limit;
use crate::quadric::Point;

/// Display length (z scaled by `z_scale`) and texture length of the edge `p q` of
/// `mesh`.
fn edge_lengths(mesh: &SurfaceMesh, z_scale: f64, p: usize, q: usize) -> (f64, f64) {
    let d: [f64; 3] = std::array::from_fn(|a| {
        let scale = if a == 2 { z_scale } else { 1.0 };
        f64::from(mesh.positions[q][a] - mesh.positions[p][a]) * scale
    });
    let t: [f64; 2] =
        std::array::from_fn(|a| f64::from(mesh.texcoords[q][a] - mesh.texcoords[p][a]));
    (dot3(d, d).sqrt(), (t[0] * t[0] + t[1] * t[1]).sqrt())
}

/// Whether an edge of length `l` and texture length `t` is longer than `limit` per
/// texture unit; one of no texture length is not judged.
fn stretched(l: f64, t: f64, limit: f64) -> bool {
    t > 0.0 && l > limit * t
}

/// The joint space: coordinates relative to a centre, z exaggerated, texture
/// coordinates and scalar scaled into length units.
#[derive(Clone, Copy)]
pub(crate) struct Frame {
    pub(super) centre: [f64; 3],
    pub(super) z_scale: f64,
    pub uv_scale: f64,
    pub s_mean: f64,
    pub s_scale: f64,
    /// Edges longer than this per unit of their texture length (display length) reach
    /// a stray corner ([`stray_limit`]): the surface's scales leave them out. Per
    /// texture unit, not plain lengths: a hierarchy's node merges coarse insides with
    /// borders kept whole, and the long edges of the insides are no strays.
    pub(super) stray_stretch: f64,
}

impl Frame {
    /// The joint space of `mesh`: its centre, and the scales that make texture
    /// coordinates and scalar comparable to lengths.
    pub(crate) fn new(mesh: &SurfaceMesh, options: &Options) -> Frame {
        let n = mesh.vertex_count().max(1) as f64;
        let mut centre = [0f64; 3];
        for p in &mesh.positions {
            for a in 0..3 {
                centre[a] += f64::from(p[a]) / n;
            }
        }
        let zs = f64::from(options.z_scale);
        let stray_stretch = stray_limit(mesh, |p, q| {
            let (l, t) = edge_lengths(mesh, zs, p, q);
            if t > 0.0 { l / t } else { 0.0 }
        });
        // Length per texture unit: mean edge length over mean texture edge length.
        let (mut len, mut tex, mut edges) = (0f64, 0f64, 0usize);
        for tri in mesh.triangles.iter().step_by(3) {
            for k in 0..3 {
                let (p, q) = (tri[k] as usize, tri[(k + 1) % 3] as usize);
                let (l, t) = edge_lengths(mesh, zs, p, q);
                if stretched(l, t, stray_stretch) {
                    continue;
                }
                len += l;
                tex += t;
                edges += 1;
            }
        }
        let uv_scale = if tex > 0.0 && len > 0.0 {
            f64::from(options.texcoord_weight) * len / tex
        } else {
            0.0
        };
        let (mut lo, mut hi, mut sum, mut k) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0usize);
        for &s in mesh.scalars.iter().filter(|s| s.is_finite()) {
            let s = f64::from(s);
            lo = lo.min(s);
            hi = hi.max(s);
            sum += s;
            k += 1;
        }
        let (s_mean, s_scale) = if k > 0 && hi > lo && edges > 0 {
            let mean_edge = len / edges as f64;
            (
                sum / k as f64,
                f64::from(options.scalar_weight) * mean_edge / (hi - lo),
            )
        } else {
            (0.0, 0.0)
        };
        Frame {
            centre,
            z_scale: zs,
            uv_scale,
            s_mean,
            s_scale,
            stray_stretch,
        }
    }

    /// Whether the edge `p q` of `mesh` (the surface of this frame) reaches a stray
    /// corner.
    #[inline]
    pub(super) fn reaches_stray(&self, mesh: &SurfaceMesh, p: usize, q: usize) -> bool {
        let (l, t) = edge_lengths(mesh, self.z_scale, p, q);
        stretched(l, t, self.stray_stretch)
    }

    #[inline]
    pub(super) fn point(&self, p: [f64; 3], uv: [f64; 2], s: f64) -> Point {
        [
            p[0] - self.centre[0],
            p[1] - self.centre[1],
            (p[2] - self.centre[2]) * self.z_scale,
            uv[0] * self.uv_scale,
            uv[1] * self.uv_scale,
            if s.is_nan() {
                0.0
            } else {
                (s - self.s_mean) * self.s_scale
            },
        ]
    }

    #[inline]
    pub(super) fn of_mesh(mesh: &SurfaceMesh, v: usize, f: &Frame) -> Point {
        let p = mesh.positions[v].map(f64::from);
        let t = mesh.texcoords[v].map(f64::from);
        let s = mesh.scalars.get(v).map_or(f64::NAN, |&s| f64::from(s));
        f.point(p, t, s)
    }
}
