//! Costing a collapse and choosing where its vertex goes: the quadric's best point on
//! the texture plane, on the edge or at an endpoint, resolved on the reference
//! surface.

use super::Placement;
use super::collapser::{BOUNDARY, Collapser, LOCKED};
use super::frame::Frame;
use super::vector::{cross3, dot3, spatial, sub3, sub3p};
use crate::quadric::Point;
use crate::reference::{NONE, SurfacePoint, closest_on_triangle, cross2};

/// A candidate collapse of a pass.
#[derive(Clone, Copy, Debug)]
pub(super) struct Candidate {
    pub(super) cost: f32,
    pub(super) a: u32,
    pub(super) b: u32,
    pub(super) choice: Choice,
}

/// Where a collapse puts the surviving vertex.
#[derive(Clone, Copy, Debug)]
pub(super) enum Choice {
    /// Onto `a` (b goes).
    KeepA,
    /// Onto `b` (a goes).
    KeepB,
    /// At texture coordinate `uv` of the reference surface, moved `lift` along the
    /// surface normal there (in the joint frame, z scaled). Single precision, as the
    /// vertex data it becomes: a pass holds a candidate per edge, and at 28 bytes
    /// instead of 48 they take much less memory to fill and stream.
    Point { uv: [f32; 2], lift: f32 },
}

impl Choice {
    pub(super) fn point(uv: [f64; 2], lift: f64) -> Choice {
        Choice::Point {
            uv: uv.map(|c| c as f32),
            lift: lift as f32,
        }
    }
}

/// A resolved placement: the joint-space point and the output attributes.
#[derive(Clone, Copy)]
pub(super) struct Spot {
    pub(super) x: Point,
    pub(super) position: [f32; 3],
    pub(super) texcoord: [f32; 2],
    pub(super) scalar: f32,
    pub(super) home: u32,
}

impl Collapser<'_> {
    /// Cost and placement of collapsing edge `a b` (for a new point, the cost of the
    /// texture plane's linear model; exact for endpoints), `None` when the rules
    /// forbid it. `endpoints_only` leaves out new points. `hint` is a live triangle
    /// with the edge, or [`NONE`].
    pub(super) fn evaluate(
        &self,
        a: u32,
        b: u32,
        endpoints_only: bool,
        hint: u32,
    ) -> Option<(f64, Choice)> {
        let (la, lb) = (self.flag(a, LOCKED), self.flag(b, LOCKED));
        if la && lb {
            return None;
        }
        let (ba, bb) = (self.flag(a, BOUNDARY), self.flag(b, BOUNDARY));
        // An edge with an end off the boundary is interior: two triangles (vertices on
        // non-manifold edges are locked), no need to count them.
        let (shared, first) = if hint != NONE && !(ba && bb) {
            (2, hint)
        } else {
            self.edge_triangles(a, b)
        };
        if shared == 0 {
            return None;
        }
        let mut keep_a = !lb;
        let mut keep_b = !la;
        let mut free = !la && !lb && !ba && !bb && !endpoints_only;
        if shared >= 2 {
            if ba && bb {
                // An interior edge across two boundaries: collapsing it would pinch a
                // hole or a narrow strip shut, or stitch a fault's two sides.
                return None;
            }
            keep_b &= !ba;
            keep_a &= !bb;
        } else {
            free = false;
            keep_a &= self.grows_outward(b, a) && self.seam_allows(b, a);
            keep_b &= self.grows_outward(a, b) && self.seam_allows(a, b);
        }
        // Around `a`'s point, where `a` is the origin: there the quadric's value is
        // its constant and its gradient its linear part, without a product by `A`.
        let q = self.pair(a, b);
        let xb = &self.from(a, &self.x[b as usize]);
        let (ua, ub) = (
            self.texcoord[a as usize].map(f64::from),
            self.texcoord[b as usize].map(f64::from),
        );
        let edge = [ub[0] - ua[0], ub[1] - ua[1]];
        // Every cost below is expanded around `a`. Where the texture plane is formed
        // (a new point may be placed), they all come from the quadric on that plane
        // (`A J` and five dot products): the edge lies in it, `xb = J (ub - ua)`, so
        // keeping `b` and the segment's minimum need no product in the joint space
        // of their own.
        // Nothing beats keeping `a` by more than a tie when that costs a tie or less
        // (costs are never negative): on flat, affine regions most edges end here,
        // before the texture plane is formed.
        // Choices compare by the quadric's value, the tie scaled to it: only the chosen
        // one is divided by the weight.
        let weight = q.weight();
        let tie = self.tie * weight;
        let keep_a_value = q.value_at_origin();
        if keep_a && keep_a_value <= tie {
            return Some((keep_a_value / weight, Choice::KeepA));
        }
        let plane = if free {
            self.jacobian(first).map(|j| {
                let aj = [q.apply(&j[0]), q.apply(&j[1])];
                (j, aj, q.on_plane(&j, &aj))
            })
        } else {
            None
        };
        let mut best: Option<(f64, Choice)> = None;
        let mut consider = |value: f64, choice: Choice| {
            if best.is_none_or(|(v, _)| value + tie < v) {
                best = Some((value, choice));
            }
        };
        if keep_a {
            consider(keep_a_value, Choice::KeepA);
        }
        if keep_b {
            let value = match &plane {
                Some((_, _, on_plane)) => on_plane.value(edge),
                None => q.value(xb),
            };
            consider(value, Choice::KeepB);
        }
        if let Some((j, aj, on_plane)) = plane {
            let len2 = edge[0] * edge[0] + edge[1] * edge[1];
            let mid = [0.5 * (ua[0] + ub[0]), 0.5 * (ua[1] + ub[1])];
            // The plane's minimum is trusted within the disk on the edge, and only on the
            // triangle's own side of it: across the edge the surface follows the
            // neighbour's plane, and there the estimate is under the exact cost (on a
            // generated layer, many of a first pass's new points then failed the pass
            // bound when tried; `docs/performance.md`). The minimum on the edge, in
            // both planes, is the fallback.
            let third = self.tris[first as usize]
                .into_iter()
                .find(|&v| v != a && v != b)
                .map_or(ua, |v| self.texcoord[v as usize].map(f64::from));
            let side = cross2(ua, ub, third);
            let inside = |d: [f64; 2]| {
                let uv = [ua[0] + d[0], ua[1] + d[1]];
                let off = [uv[0] - mid[0], uv[1] - mid[1]];
                (off[0] * off[0] + off[1] * off[1] <= 0.25 * len2
                    && cross2(ua, ub, uv) * side >= 0.0)
                    .then_some(uv)
            };
            let mut placed = false;
            if self.options.placement == Placement::Optimal {
                // Off the surface along its normal too: the third direction.
                let [t0, t1, t2] = self.tris[first as usize].map(|v| self.x[v as usize]);
                let n = cross3(sub3(&t1, &t0), sub3(&t2, &t0));
                let len = dot3(n, n).sqrt();
                if len > 0.0 {
                    let normal: Point = [n[0] / len, n[1] / len, n[2] / len, 0.0, 0.0, 0.0];
                    let cols = [j[0], j[1], normal];
                    let acols = [aj[0], aj[1], q.apply(&normal)];
                    if let Some((d, value)) = q.minimize_in_space(&cols, &acols)
                        && let Some(uv) = inside([d[0], d[1]])
                        // No further off than the edge is long: beyond, the linear model
                        // of the surface means nothing.
                        && d[2] * d[2] <= dot3(spatial(xb), spatial(xb))
                    {
                        consider(value.max(0.0), Choice::point(uv, d[2]));
                        placed = true;
                    }
                }
            }
            // The plane holds the edge (its triangle interpolates both ends exactly), so
            // its minimum is never worse than the edge's: the edge's is the fallback
            // for when the plane's is too far away to trust.
            if !placed
                && let Some((d, value)) = on_plane.minimum()
                && let Some(uv) = inside(d)
            {
                consider(value, Choice::point(uv, 0.0));
                placed = true;
            }
            if !placed {
                let (t, value) = on_plane.minimum_on_segment(edge);
                if t > 0.0 && t < 1.0 {
                    let uv = [ua[0] + t * edge[0], ua[1] + t * edge[1]];
                    consider(value, Choice::point(uv, 0.0));
                }
            }
        }
        best.map(|(value, choice)| (value / weight, choice))
    }

    /// The placement of `choice` for edge `a b`; `None` when its texture coordinate is
    /// not on the reference surface next to the edge.
    pub(super) fn place(&self, a: u32, b: u32, choice: Choice) -> Option<Spot> {
        let vertex = |v: u32| Spot {
            x: self.x[v as usize],
            position: self.position[v as usize],
            texcoord: self.texcoord[v as usize],
            scalar: self.scalar[v as usize],
            home: self.home[v as usize],
        };
        match choice {
            Choice::KeepA => Some(vertex(a)),
            Choice::KeepB => Some(vertex(b)),
            Choice::Point { uv, lift } => {
                let (uv, lift) = (uv.map(f64::from), f64::from(lift));
                // From the home of the nearer end (in texture space): a shorter walk.
                let nearer_b = {
                    let d2 = |v: u32| {
                        let t = self.texcoord[v as usize];
                        (f64::from(t[0]) - uv[0]).powi(2) + (f64::from(t[1]) - uv[1]).powi(2)
                    };
                    d2(b) < d2(a)
                };
                let (first, second) = if nearer_b { (b, a) } else { (a, b) };
                let found: SurfacePoint = [self.home[first as usize], self.home[second as usize]]
                    .into_iter()
                    .filter(|&h| h != NONE)
                    .find_map(|h| self.reference.locate(h, uv))?;
                let mesh = self.reference.mesh();
                // Joint-frame positions (z scaled) of a reference triangle's corners.
                let corners = |t: u32| {
                    mesh.triangles[t as usize].map(|v| {
                        let x = Frame::of_mesh(mesh, v as usize, &self.frame);
                        [x[0], x[1], x[2]]
                    })
                };
                let mut point = found;
                let (position, texcoord, s) = if lift == 0.0 {
                    let (p, t, s) = self.reference.evaluate(&found);
                    (p.map(|c| c as f32), [t[0] as f32, t[1] as f32], s)
                } else {
                    let c = corners(found.triangle);
                    let mut target: [f64; 3] = std::array::from_fn(|k| {
                        (0..3).map(|i| found.barycentric[i] * c[i][k]).sum()
                    });
                    let n = cross3(sub3p(c[1], c[0]), sub3p(c[2], c[0]));
                    let len = dot3(n, n).sqrt();
                    if len == 0.0 {
                        return None;
                    }
                    target = std::array::from_fn(|k| target[k] + lift * n[k] / len);
                    // Texture coordinates from the nearest point of the original: the
                    // triangle under it or one around it (two rings).
                    let mut best = (f64::INFINITY, found);
                    let mut near = [NONE; 13];
                    near[0] = found.triangle;
                    let mut count = 1;
                    for ring in 0..2 {
                        let end = count;
                        for i in if ring == 0 { 0..1 } else { 1..end } {
                            for &nb in &self.reference.adjacency[near[i] as usize] {
                                if nb != NONE && !near[..count].contains(&nb) && count < near.len()
                                {
                                    near[count] = nb;
                                    count += 1;
                                }
                            }
                        }
                    }
                    for &t in &near[..count] {
                        let (d2, w) = closest_on_triangle(target, corners(t));
                        if d2 < best.0 {
                            best = (
                                d2,
                                SurfacePoint {
                                    triangle: t,
                                    barycentric: w,
                                },
                            );
                        }
                    }
                    point = best.1;
                    let (_, tex, s) = self.reference.evaluate(&point);
                    let centre = self.frame.centre;
                    let position = [
                        (target[0] + centre[0]) as f32,
                        (target[1] + centre[1]) as f32,
                        (target[2] / self.frame.z_scale + centre[2]) as f32,
                    ];
                    (position, [tex[0] as f32, tex[1] as f32], s)
                };
                let scalar = if self.has_scalars { s as f32 } else { f32::NAN };
                // The joint point from the stored (f32) values, so that later quadric
                // costs see exactly what is drawn.
                let x = self.frame.point(
                    position.map(f64::from),
                    texcoord.map(f64::from),
                    f64::from(scalar),
                );
                Some(Spot {
                    x,
                    position,
                    texcoord,
                    scalar,
                    home: point.triangle,
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decimate::collapser::{ALIVE, MOVED};
    use crate::{Options, Reference};
    use strata_grid::SurfaceMesh;

    #[test]
    fn candidates_stay_small() {
        // A pass holds one per edge: see `Choice::Point`.
        assert_eq!(std::mem::size_of::<Candidate>(), 28);
    }

    #[test]
    fn a_new_point_over_the_bound_falls_back_to_an_endpoint_within_it() {
        // On a curved surface the texture plane's estimate of a new point can be well
        // under its exact cost on the original, and above an endpoint's (exact) cost.
        let mesh = SurfaceMesh::structured(30, 30, |i, j| {
            let (x, y) = (i as f32, j as f32);
            [10.0 * x, 10.0 * y, 8.0 * (0.3 * x).sin() * (0.23 * y).cos()]
        });
        let options = Options::default();
        let reference = Reference::new(&mesh).unwrap();
        let home = reference.vertex_triangle.clone();
        let mut c = Collapser::new(&mesh, &home, &reference, &[], &options, None).unwrap();
        c.rebuild_lists();
        let edges: Vec<(u32, u32, u32)> = (0..c.tris.len() as u32)
            .flat_map(|t| {
                let tri = c.tris[t as usize];
                (0..3).map(move |k| (t, tri[k], tri[(k + 1) % 3]))
            })
            .collect();
        let found = edges.into_iter().find_map(|(t, a, b)| {
            let (_, point) = c.evaluate(a, b, false, t)?;
            if !matches!(point, Choice::Point { .. }) {
                return None;
            }
            let exact = c.pair(a, b).error(&c.from(a, &c.place(a, b, point)?.x));
            let (endpoint, keep) = c.evaluate(a, b, true, t)?;
            let spot = c.place(a, b, keep)?;
            let (kept, gone) = if matches!(keep, Choice::KeepB) {
                (b, a)
            } else {
                (a, b)
            };
            (endpoint < exact && c.can_collapse(kept, gone, &spot, false))
                .then_some((a, b, point, endpoint, exact, kept))
        });
        let (a, b, point, endpoint, exact, kept) =
            found.expect("an edge whose new point costs more than an endpoint");
        let bound = 0.5 * (endpoint + exact);
        c.try_collapse(a, b, point, bound);
        assert_eq!(c.collapses, 1, "no collapse under bound {bound}");
        assert!(c.flag(kept, ALIVE) && !c.flag(kept, MOVED));
        assert!(c.max_cost <= bound, "{} > {bound}", c.max_cost);
    }

    #[test]
    fn new_points_stay_on_the_side_of_the_triangle_that_models_them() {
        let mesh = SurfaceMesh::structured(30, 30, |i, j| {
            let (x, y) = (i as f32, j as f32);
            [10.0 * x, 10.0 * y, 8.0 * (0.3 * x).sin() * (0.23 * y).cos()]
        });
        let options = Options::default();
        let reference = Reference::new(&mesh).unwrap();
        let home = reference.vertex_triangle.clone();
        let mut c = Collapser::new(&mesh, &home, &reference, &[], &options, None).unwrap();
        c.rebuild_lists();
        // How far under the exact cost an estimate may be: meshoptimizer's pass
        // margin, tighter than ours.
        const UNDER_BY: f64 = 1.5;
        let (mut points, mut underestimated) = (0, 0);
        for t in 0..c.tris.len() as u32 {
            let tri = c.tris[t as usize];
            for k in 0..3 {
                let (a, b, third) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let Some((estimate, point @ Choice::Point { uv, .. })) = c.evaluate(a, b, false, t)
                else {
                    continue;
                };
                let [ua, ub, uc] = [a, b, third].map(|v| c.texcoord[v as usize].map(f64::from));
                // Signed distance from the edge's line towards the triangle (texture
                // units; single-precision rounding of a point on the edge aside).
                let len = ((ub[0] - ua[0]).powi(2) + (ub[1] - ua[1]).powi(2)).sqrt();
                let towards = cross2(ua, ub, uv.map(f64::from)) * cross2(ua, ub, uc).signum();
                assert!(
                    towards / len >= -1e-4,
                    "edge {a} {b} of triangle {t}: {uv:?} across"
                );
                let exact = c
                    .pair(a, b)
                    .error(&c.from(a, &c.place(a, b, point).unwrap().x));
                points += 1;
                if exact > UNDER_BY * estimate + c.tie {
                    underestimated += 1;
                }
            }
        }
        // Off the triangle's side, a third of the estimates would be that far under.
        assert!(points > 1000, "{points} new points");
        assert!(
            underestimated * 10 < points,
            "{underestimated} of {points} estimates under the exact cost by more than {UNDER_BY} times"
        );
    }
}
