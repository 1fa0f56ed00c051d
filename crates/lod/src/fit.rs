//! Moves a simplified surface's vertices, texture coordinates fixed, to where it draws
//! the original grid lines nearest to where the original draws them.
//!
//! Where a sample of the grid lines (texture coordinates `uv`, position `x` on the
//! original) lies in a simplified triangle with barycentric weights `w`, the simplified
//! surface draws it at `w0 p0 + w1 p1 + w2 p2`: linear in the vertex positions `p`,
//! which leaves the weights alone as long as the texture coordinates stay. The sum of
//! squared distances to the `x` is then a linear least-squares problem in the
//! positions, which Gauss-Seidel sweeps solve (each vertex in turn to its optimum, the
//! others held). Unlike [`crate::Options::lift`] (one sweep, interior vertices along
//! the normal, within their collapse error) every vertex moves, outline vertices too
//! (the two sides of a seam as one), in any direction: below the
//! [`crate::measure::outline_bound`] outlines are cut anyway, and a vertex on a cut
//! outline stands for a stretch of it. On emerald's and simpleb8's layers at 10 % the
//! fit raised the bench's line-pixel F1 (both views) of meshopt_simplify's results and
//! of ours, where moving the interior vertices alone did next to nothing. Above the
//! bound it helps ours too, at a cost in time that [`crate::decimate_chosen`] weighs.
//! With [`crate::Options::cover`] the renderer's cell mask draws outlines where their
//! cells' texture coordinates fall, which the fit does not move, and there it helps at
//! every budget. A fit costs a fraction of what locating its samples by a search of
//! the whole surface and measuring them does. Figures: `docs/performance.md`
//! ("Decimation internals"). Near its outline bound, ours is fitted to its input
//! vertices, which it locates as it decimates ([`crate::decimate_chosen`]).

use strata_grid::SurfaceMesh;

use crate::Decimated;
use crate::MaybeIndex;
use crate::decimate::{coincident, cross3, dot3, sub3p};
use crate::measure::Located;
use crate::reference::{NONE, VertexTriangles, boundary_edges, triangle_adjacency};

/// Most Gauss-Seidel sweeps; on emerald's layers the line-pixel F1 stopped changing
/// well before this many (`docs/performance.md`).
const MAX_SWEEPS: usize = 8;

/// A sweep that moves no vertex further than this fraction of the surface's extent
/// is the last.
const SETTLED: f64 = 1e-6;

/// Weight, in squared barycentric weight (a sample at the vertex weighs 1), that
/// holds a vertex to where it was before the fit: a vertex whose samples all lie far
/// from it (weights near 0) would otherwise move far on little evidence.
const HOLD: f64 = 1e-2;

/// Fits the positions of `decimated` to the samples `located` on it, z scaled by
/// `z_scale` as the surface is viewed: each vertex moves by at most `reach` (display
/// length units; the largest distance the samples had before is a natural one) and
/// only where no triangle around it turns over. A vertex that moved is no longer
/// its input vertex ([`Decimated::source`] becomes none); texture coordinates,
/// scalars, [`Decimated::home`] and [`Decimated::error`] (the simplifier's) stay.
/// Returns how many vertices moved.
pub fn fit(located: &Located, decimated: &mut Decimated, z_scale: f64, reach: f64) -> usize {
    let mesh = &decimated.mesh;
    let n = mesh.vertex_count();
    if n == 0 || located.samples.is_empty() || !(z_scale.is_finite() && z_scale > 0.0) {
        return 0;
    }
    // A reach that is no number moves nothing.
    let reach = reach.max(0.0);
    // The normal equations, gathered by triangle: for triangle t, the sums over its
    // samples of `w_j w_k` and of `w_k x`, so that a sweep costs the triangles, not
    // the samples. Only samples the surface draws count: one outside it stands for a
    // stretch of line the surface lost, and pulling the outline towards those
    // (at the nearest point drawn) ruined simpleb8's line-pixel F1 (`docs/performance.md`).
    let display = |p: [f64; 3]| [p[0], p[1], p[2] * z_scale];
    let mut normal_equations = vec![([[0.0; 3]; 3], [[0.0; 3]; 3]); mesh.triangle_count()];
    for s in located.samples.iter().filter(|s| s.inside) {
        // Samples located on another surface (no such triangle) are left out.
        let Some((weights, sums)) = normal_equations.get_mut(s.point.triangle as usize) else {
            continue;
        };
        let (w, x) = (s.point.barycentric, display(s.target));
        for j in 0..3 {
            for k in 0..3 {
                weights[j][k] += w[j] * w[k];
            }
            for a in 0..3 {
                sums[j][a] += w[j] * x[a];
            }
        }
    }
    let star = VertexTriangles::new(n, &mesh.triangles);
    // Display space (z scaled), so that `reach` and the orientations are as seen.
    let mut x: Vec<[f64; 3]> = mesh
        .positions
        .iter()
        .map(|p| display(p.map(f64::from)))
        .collect();
    let start = x.clone();
    let normal = |x: &[[f64; 3]], t: usize| triangle_normal(x, mesh.triangles[t]);
    let facing: Vec<[f64; 3]> = (0..mesh.triangle_count()).map(|t| normal(&x, t)).collect();
    let extent = mesh.bounds().map_or(0.0, |(lo, hi)| {
        let d = display(std::array::from_fn(|a| f64::from(hi[a] - lo[a])));
        d.iter().map(|c| c * c).sum::<f64>().sqrt()
    });
    let partner = seam_partners(mesh, &star);
    for _ in 0..MAX_SWEEPS {
        let mut largest_move: f64 = 0.0;
        for v in 0..n {
            let twin = partner[v];
            if twin == HELD || (twin != NONE && (twin as usize) < v) {
                continue;
            }
            let pair = [v, twin as usize];
            let group = if twin == NONE { &pair[..1] } else { &pair[..] };
            let (mut num, mut den) = ([0.0; 3], 0.0);
            for &u in group {
                for a in 0..3 {
                    num[a] += HOLD * start[u][a];
                }
                den += HOLD;
                for &t in star.of(u as u32) {
                    let tri = mesh.triangles[t as usize];
                    let Some(k) = tri.iter().position(|&w| w as usize == u) else {
                        continue;
                    };
                    // The vertex's row: what it must make up for, the samples less
                    // the other corners' share.
                    let (weights, sums) = &normal_equations[t as usize];
                    for a in 0..3 {
                        num[a] += sums[k][a];
                    }
                    for j in (0..3).filter(|&j| j != k) {
                        let p = x[tri[j] as usize];
                        for a in 0..3 {
                            num[a] -= weights[k][j] * p[a];
                        }
                    }
                    den += weights[k][k];
                }
            }
            if den == HOLD * group.len() as f64 {
                // No sample on any of its triangles.
                continue;
            }
            let mut to = num.map(|c| c / den);
            let off = sub3p(to, start[v]);
            let len = dot3(off, off).sqrt();
            if len > reach {
                to = std::array::from_fn(|a| start[v][a] + off[a] * reach / len);
            }
            let before = x[v];
            group.iter().for_each(|&u| x[u] = to);
            let folds = group.iter().any(|&u| {
                star.of(u as u32)
                    .iter()
                    .any(|&t| dot3(normal(&x, t as usize), facing[t as usize]) <= 0.0)
            });
            if folds {
                group.iter().for_each(|&u| x[u] = before);
            } else {
                let step = sub3p(to, before);
                largest_move = largest_move.max(dot3(step, step).sqrt());
            }
        }
        if largest_move <= SETTLED * extent {
            break;
        }
    }
    let mut moved = 0;
    for v in 0..n {
        if x[v] == start[v] {
            continue;
        }
        moved += 1;
        decimated.mesh.positions[v] = [x[v][0], x[v][1], x[v][2] / z_scale].map(|c| c as f32);
        decimated.source[v] = MaybeIndex::NONE;
    }
    moved
}

/// [`seam_partners`]: a vertex that does not move.
const HELD: u32 = NONE - 1;

/// Per vertex of `mesh` (`star`: its vertex-to-triangle lists), the other boundary
/// vertex at its position, with which it moves as one, so that the two sides of a
/// seam stay together (see [`crate::decimate()`]); [`NONE`] for none, [`HELD`] where
/// more than two boundary vertices meet.
fn seam_partners(mesh: &SurfaceMesh, star: &VertexTriangles) -> Vec<u32> {
    let n = mesh.vertex_count();
    let mut on_boundary = vec![false; n];
    let adjacency = triangle_adjacency(&mesh.triangles, star);
    for ((p, q), _) in boundary_edges(&mesh.triangles, &adjacency) {
        on_boundary[p as usize] = true;
        on_boundary[q as usize] = true;
    }
    let (pairs, crowded) = coincident(
        &mesh.positions,
        (0..n as u32).filter(|&v| on_boundary[v as usize]),
    );
    let mut partner = vec![NONE; n];
    for [a, b] in pairs {
        partner[a as usize] = b;
        partner[b as usize] = a;
    }
    for v in crowded {
        partner[v as usize] = HELD;
    }
    partner
}

/// Normal (not normalised) of triangle `t` of points `x`.
fn triangle_normal(x: &[[f64; 3]], t: [u32; 3]) -> [f64; 3] {
    let [a, b, c] = t.map(|v| x[v as usize]);
    cross3(sub3p(b, a), sub3p(c, a))
}

#[cfg(test)]
mod tests {
    use strata_grid::SurfaceMesh;

    use super::*;
    use crate::decimate::{Options, decimate};
    use crate::measure::{GridLines, LocatedSample, curved};
    use crate::reference::SurfacePoint;

    /// Normals of every triangle, z scaled by 5 as the fits below view them.
    fn normals(mesh: &SurfaceMesh) -> Vec<[f64; 3]> {
        let x: Vec<[f64; 3]> = mesh
            .positions
            .iter()
            .map(|p| [p[0], p[1], p[2] * 5.0].map(f64::from))
            .collect();
        mesh.triangles
            .iter()
            .map(|&t| triangle_normal(&x, t))
            .collect()
    }

    #[test]
    fn a_displaced_surface_is_fitted_back_within_reach() {
        // A tilted plane: every decimation of it draws the grid lines exactly, until
        // moved off it.
        let plane = SurfaceMesh::structured(12, 10, |i, j| {
            [i as f32 * 10.0, j as f32 * 10.0, (i + 2 * j) as f32]
        });
        let lines = GridLines::of(&plane, 2);
        let options = Options {
            target_triangles: 12,
            z_scale: 5.0,
            ..Options::default()
        };
        let decimated = decimate(&plane, &options).unwrap();
        let mut displaced = decimated.clone();
        for p in &mut displaced.mesh.positions {
            p[0] += 3.0;
            p[2] -= 0.4;
        }
        let located = lines.locate(&displaced.mesh, &displaced.home, 5.0);
        let before = located.deviation(&displaced.mesh, 5.0);
        // 3 across and 0.4 * 5 down, as viewed.
        let off = (9.0f64 + 4.0).sqrt();
        assert!((before.rms - off).abs() < 1e-4, "{before:?}");
        assert_eq!(before.outside, 0);

        // Within a reach of 1, every vertex moves 1 and no further.
        let mut held = displaced.clone();
        let moved = fit(&located, &mut held, 5.0, 1.0);
        assert_eq!(moved, held.mesh.vertex_count());
        for (p, q) in held.mesh.positions.iter().zip(&displaced.mesh.positions) {
            let d = [p[0] - q[0], p[1] - q[1], (p[2] - q[2]) * 5.0].map(f64::from);
            assert!((dot3(d, d).sqrt() - 1.0).abs() < 1e-4, "moved {d:?}");
        }
        let held_rms = located.deviation(&held.mesh, 5.0).rms;
        assert!((held_rms - (off - 1.0)).abs() < 1e-3, "{held_rms}");

        // Within reach, the plane again (but for what `HOLD` holds back: a vertex's
        // samples weigh far more than 1), every vertex a new one.
        let moved = fit(&located, &mut displaced, 5.0, 2.0 * off);
        assert_eq!(moved, displaced.mesh.vertex_count());
        let after = located.deviation(&displaced.mesh, 5.0);
        assert!(after.max < HOLD * off, "{after:?}");
        assert!(displaced.source.iter().all(|s| s.is_none()));
        assert_eq!(displaced.mesh.texcoords, decimated.mesh.texcoords);
        assert_eq!(
            normals(&displaced.mesh).len(),
            decimated.mesh.triangle_count()
        );
    }

    #[test]
    fn a_curved_surface_is_drawn_nearer_and_nothing_turns_over() {
        let curved = curved(30);
        let lines = GridLines::of(&curved, 2);
        let options = Options {
            target_triangles: 60,
            z_scale: 5.0,
            ..Options::default()
        };
        let mut decimated = decimate(&curved, &options).unwrap();
        let (kept, facing) = (decimated.clone(), normals(&decimated.mesh));
        let located = lines.locate(&decimated.mesh, &decimated.home, 5.0);
        let before = located.deviation(&decimated.mesh, 5.0);
        let moved = fit(&located, &mut decimated, 5.0, before.max);
        let after = located.deviation(&decimated.mesh, 5.0);
        assert!(moved > 0);
        assert!(after.rms < 0.8 * before.rms, "{before:?} -> {after:?}");
        for (n, m) in normals(&decimated.mesh).iter().zip(&facing) {
            assert!(dot3(*n, *m) > 0.0);
        }
        // A vertex that did not move keeps what it was.
        for v in 0..kept.mesh.vertex_count() {
            if decimated.mesh.positions[v] == kept.mesh.positions[v] {
                assert_eq!(decimated.source[v], kept.source[v]);
            } else {
                assert_eq!(decimated.source[v], MaybeIndex::NONE);
            }
        }
    }

    #[test]
    fn a_move_that_would_turn_a_triangle_over_is_not_made() {
        // Four triangles around a centre vertex 4 of a unit square.
        let mut square = SurfaceMesh::default();
        square.positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.5, 0.0],
        ];
        square.texcoords = square.positions.iter().map(|p| [p[0], p[1]]).collect();
        square.triangles = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
        let fan = Decimated {
            mesh: square,
            source: (0..5).map(MaybeIndex::some).collect(),
            home: vec![0; 5],
            error: 0.0,
            collapses: 0,
            outline_vertices: 4,
            cover: None,
            timings: Default::default(),
        };
        // One sample at the centre, drawn at `target` on the original.
        let at_centre = |target: [f64; 3]| Located {
            samples: vec![LocatedSample {
                point: SurfacePoint {
                    triangle: 0,
                    barycentric: [0.0, 0.0, 1.0],
                },
                target,
                inside: true,
            }],
            missed: 0,
        };
        // Beyond the square's right side: the left triangle would turn over.
        let mut beyond = fan.clone();
        assert_eq!(fit(&at_centre([1.5, 0.5, 0.0]), &mut beyond, 5.0, 10.0), 0);
        // No view (z scale 0), no reach, or a sample of another surface: nothing moves.
        let to = at_centre([0.7, 0.6, 0.1]);
        assert_eq!(fit(&to, &mut beyond, 0.0, 10.0), 0);
        assert_eq!(fit(&to, &mut beyond, 5.0, f64::NAN), 0);
        let mut elsewhere = to.clone();
        elsewhere.samples[0].point.triangle = 4;
        assert_eq!(fit(&elsewhere, &mut beyond, 5.0, 10.0), 0);
        assert_eq!(beyond.mesh.positions, fan.mesh.positions);
        assert_eq!(beyond.source, fan.source);
        // Inside it: the centre goes to the sample, held back by `HOLD` (of the
        // sample's weight 1) towards where it was.
        let mut inside = fan.clone();
        assert_eq!(fit(&at_centre([0.7, 0.6, 0.1]), &mut inside, 5.0, 10.0), 1);
        let c = inside.mesh.positions[4].map(f64::from);
        let want = [0.7, 0.6, 0.1 * 5.0]
            .iter()
            .zip([0.5, 0.5, 0.0])
            .map(|(x, s)| (x + HOLD * s) / (1.0 + HOLD))
            .collect::<Vec<_>>();
        assert!(
            (c[0] - want[0]).abs() < 1e-6
                && (c[1] - want[1]).abs() < 1e-6
                && (c[2] * 5.0 - want[2]).abs() < 1e-6,
            "{c:?} {want:?}"
        );
        assert_eq!(inside.source[4], MaybeIndex::NONE);
        assert_eq!(inside.source[..4], fan.source[..4]);
    }
}
