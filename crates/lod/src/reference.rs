//! The original surface that every simplified vertex is kept on.
//!
//! A layer surface is parameterised by its global texture coordinates: each cell
//! appears once, so within a connected piece of the surface a texture coordinate names
//! one point. Decimation chooses the new vertex of a collapse as a texture coordinate
//! and looks the point up here, by walking from a triangle known to lie near it
//! across the triangles' neighbours (texture space, straight towards the target).
//! The new vertex then lies *on* the original surface and its texture coordinates and
//! scalar are, by construction, the interpolation of the original surface at that
//! point; grid lines drawn through it are where they were. The walk never crosses a
//! boundary edge, so it can't jump over a fault trace or a hole to the other side:
//! when the target is not reachable from the collapse's neighbourhood it fails and the
//! collapse falls back to keeping an endpoint.

use strata_grid::SurfaceMesh;

use crate::{Error, MaybeIndex, Result};

/// "No triangle" in the crate's raw `u32` tables (adjacency across a boundary edge,
/// a vertex no triangle uses), where the hot loops of decimation compare it
/// directly; what leaves the crate says it with [`MaybeIndex`].
pub(crate) const NONE: u32 = u32::MAX;

/// Most triangles a walk visits before giving up (a walk in a valid triangulation
/// reaches its target in about as many steps as triangles lie between; the cap only
/// stops the rare cycles of the greedy rule on badly shaped triangles).
const MAX_STEPS: usize = 4096;

/// A point of the reference surface: the triangle it lies in and its barycentric
/// coordinates there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Index of the triangle of the reference surface.
    pub triangle: u32,
    /// Weights of the triangle's corners.
    pub barycentric: [f64; 3],
}

/// A mesh prepared for point location by texture coordinates.
pub struct Reference<'m> {
    mesh: &'m SurfaceMesh,
    /// Per triangle, the neighbour across the edge opposite each corner ([`NONE`] on a
    /// boundary or non-manifold edge).
    pub(crate) adjacency: Vec<[u32; 3]>,
    /// Per vertex, a triangle that uses it.
    pub(crate) vertex_triangle: Vec<u32>,
}

/// Vertex-to-triangle adjacency in compressed rows: the triangles of vertex `v` are
/// `triangles[start[v]..start[v + 1]]`, in increasing order.
pub(crate) struct VertexTriangles {
    pub start: Vec<u32>,
    pub triangles: Vec<u32>,
}

impl VertexTriangles {
    pub fn new(vertex_count: usize, triangles: &[[u32; 3]]) -> Self {
        let mut start = vec![0u32; vertex_count + 1];
        for t in triangles {
            for &v in t {
                start[v as usize + 1] += 1;
            }
        }
        for v in 0..vertex_count {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut list = vec![0u32; start[vertex_count] as usize];
        for (i, t) in triangles.iter().enumerate() {
            for &v in t {
                list[fill[v as usize] as usize] = i as u32;
                fill[v as usize] += 1;
            }
        }
        VertexTriangles {
            start,
            triangles: list,
        }
    }

    pub fn of(&self, v: u32) -> &[u32] {
        &self.triangles[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }
}

/// The boundary edges of `triangles` (those with no neighbour in `adjacency`, their
/// [`triangle_adjacency`]), in the triangles' winding, each with its triangle, in
/// triangle order.
pub(crate) fn boundary_edges(
    triangles: &[[u32; 3]],
    adjacency: &[[u32; 3]],
) -> Vec<((u32, u32), u32)> {
    let mut edges = Vec::new();
    for (t, (tri, across)) in triangles.iter().zip(adjacency).enumerate() {
        for k in (0..3).filter(|&k| across[k] == NONE) {
            edges.push(((tri[(k + 1) % 3], tri[(k + 2) % 3]), t as u32));
        }
    }
    edges
}

/// Per triangle, the neighbour across each edge (opposite each corner): the one other
/// triangle that has both its ends, [`NONE`] when none or several do.
/// Sequential: decimation runs in one thread (callers parallelise across meshes), so
/// that its speed per core is what it seems.
/// An edge's search fills both of its triangles, so each interior edge is searched
/// once, not from both sides: the search was a noticeable share of the instructions
/// of a decimation (callgrind; `docs/performance.md`, "Decimation internals").
pub(crate) fn triangle_adjacency(triangles: &[[u32; 3]], vt: &VertexTriangles) -> Vec<[u32; 3]> {
    /// Not searched yet.
    const UNKNOWN: u32 = NONE - 1;
    let mut adjacency = vec![[UNKNOWN; 3]; triangles.len()];
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            if adjacency[t][k] != UNKNOWN {
                continue;
            }
            let (p, q) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
            let mut found = NONE;
            let mut several = false;
            for &s in vt.of(p) {
                if s as usize != t && triangles[s as usize].contains(&q) {
                    if found != NONE {
                        several = true;
                        break;
                    }
                    found = s;
                }
            }
            if several {
                adjacency[t][k] = NONE;
                continue;
            }
            adjacency[t][k] = found;
            // Only `t` and `found` have the edge: `found` needs no search for it.
            if let Some(other) = triangles.get(found as usize)
                && let Some(j) = (0..3).find(|&j| other[j] != p && other[j] != q)
            {
                adjacency[found as usize][j] = t as u32;
            }
        }
    }
    adjacency
}

impl<'m> Reference<'m> {
    /// Prepares `mesh`; fails when it breaks the mesh invariants.
    pub fn new(mesh: &'m SurfaceMesh) -> Result<Self> {
        Ok(Self::with_vertex_triangles(mesh)?.0)
    }

    /// [`Reference::new`], and the vertex-to-triangle lists it was built from, for a
    /// caller that needs them too (decimating the mesh on itself).
    pub(crate) fn with_vertex_triangles(mesh: &'m SurfaceMesh) -> Result<(Self, VertexTriangles)> {
        mesh.validate().map_err(Error::Mesh)?;
        let vt = VertexTriangles::new(mesh.vertex_count(), &mesh.triangles);
        let adjacency = triangle_adjacency(&mesh.triangles, &vt);
        let vertex_triangle = (0..mesh.vertex_count() as u32)
            .map(|v| vt.of(v).first().copied().unwrap_or(NONE))
            .collect();
        let reference = Reference {
            mesh,
            adjacency,
            vertex_triangle,
        };
        Ok((reference, vt))
    }

    /// A triangle using each vertex of `mesh` (none for unused vertices), without
    /// preparing the mesh.
    pub fn vertex_triangles(mesh: &SurfaceMesh) -> Vec<MaybeIndex> {
        let mut out = vec![MaybeIndex::NONE; mesh.vertex_count()];
        for (t, tri) in mesh.triangles.iter().enumerate().rev() {
            for &v in tri {
                out[v as usize] = MaybeIndex::some(t as u32);
            }
        }
        out
    }

    /// The prepared surface.
    pub fn mesh(&self) -> &'m SurfaceMesh {
        self.mesh
    }

    /// A triangle using vertex `v`, if any does.
    pub fn triangle_of(&self, v: u32) -> Option<u32> {
        let t = self.vertex_triangle[v as usize];
        (t != NONE).then_some(t)
    }

    /// Barycentric coordinates of `uv` in triangle `t`, in texture space; `None` for
    /// a triangle of zero texture area.
    pub fn barycentric(&self, t: u32, uv: [f64; 2]) -> Option<[f64; 3]> {
        texture_barycentric(self.mesh, t, uv)
    }

    /// The point of texture coordinates `uv`, reached by walking from triangle `start`
    /// without crossing a boundary; `None` when the walk meets a boundary, a triangle
    /// without texture area, or takes too long.
    pub fn locate(&self, start: u32, uv: [f64; 2]) -> Option<SurfacePoint> {
        /// Points this far outside a triangle (in barycentric terms) count as inside:
        /// they are on its edge up to rounding.
        const INSIDE: f64 = -1e-9;
        let mut t = start;
        if t as usize >= self.mesh.triangles.len() {
            return None;
        }
        for _ in 0..MAX_STEPS {
            let b = self.barycentric(t, uv)?;
            let (k, worst) = (0..3)
                .map(|k| (k, b[k]))
                .fold((0, f64::INFINITY), |m, x| if x.1 < m.1 { x } else { m });
            if worst >= INSIDE {
                return Some(SurfacePoint {
                    triangle: t,
                    barycentric: b,
                });
            }
            t = self.adjacency[t as usize][k];
            if t == NONE {
                return None;
            }
        }
        None
    }

    /// Position, texture coordinates and scalar of the surface at `p` (the scalar
    /// interpolates the defined corner values only; NaN when none is defined).
    pub fn evaluate(&self, p: &SurfacePoint) -> ([f64; 3], [f64; 2], f64) {
        let tri = self.mesh.triangles[p.triangle as usize];
        let mut pos = [0f64; 3];
        let mut uv = [0f64; 2];
        let (mut s, mut sw) = (0f64, 0f64);
        for (k, &v) in tri.iter().enumerate() {
            let w = p.barycentric[k];
            let x = self.mesh.positions[v as usize];
            let t = self.mesh.texcoords[v as usize];
            for a in 0..3 {
                pos[a] += w * f64::from(x[a]);
            }
            for a in 0..2 {
                uv[a] += w * f64::from(t[a]);
            }
            if let Some(&sv) = self.mesh.scalars.get(v as usize)
                && !sv.is_nan()
            {
                s += w * f64::from(sv);
                sw += w;
            }
        }
        let s = if sw > 0.0 { s / sw } else { f64::NAN };
        (pos, uv, s)
    }
}

/// Squared distance from `p` to triangle `t` and the barycentric coordinates of the
/// closest point (Ericson, Real-Time Collision Detection, 5.1.5).
pub fn closest_on_triangle(p: [f64; 3], t: [[f64; 3]; 3]) -> (f64, [f64; 3]) {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let [a, b, c] = t;
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    let (va, vb, vc) = (d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2);
    let w = if d1 <= 0.0 && d2 <= 0.0 {
        [1.0, 0.0, 0.0]
    } else if d3 >= 0.0 && d4 <= d3 {
        [0.0, 1.0, 0.0]
    } else if d6 >= 0.0 && d5 <= d6 {
        [0.0, 0.0, 1.0]
    } else if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        [1.0 - v, v, 0.0]
    } else if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        [1.0 - w, 0.0, w]
    } else if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        [0.0, 1.0 - w, w]
    } else {
        let denom = 1.0 / (va + vb + vc);
        let (v, w) = (vb * denom, vc * denom);
        [1.0 - v - w, v, w]
    };
    let q: [f64; 3] = std::array::from_fn(|k| w[0] * a[k] + w[1] * b[k] + w[2] * c[k]);
    let d = sub(q, p);
    (dot(d, d), w)
}

/// Barycentric coordinates of `uv` in triangle `t` of `mesh`, in texture space;
/// `None` for a triangle of zero texture area.
pub(crate) fn texture_barycentric(mesh: &SurfaceMesh, t: u32, uv: [f64; 2]) -> Option<[f64; 3]> {
    barycentric(
        mesh.triangles[t as usize].map(|v| mesh.texcoords[v as usize].map(f64::from)),
        uv,
    )
}

/// Barycentric coordinates of `uv` in the texture-space triangle `c`, `None` when it
/// has no area.
pub(crate) fn barycentric(c: [[f64; 2]; 3], uv: [f64; 2]) -> Option<[f64; 3]> {
    let area = cross2(c[0], c[1], c[2]);
    if area == 0.0 || !area.is_finite() {
        return None;
    }
    Some([
        cross2(uv, c[1], c[2]) / area,
        cross2(c[0], uv, c[2]) / area,
        cross2(c[0], c[1], uv) / area,
    ])
}

/// Twice the signed area of the texture-space triangle `a b c`.
pub(crate) fn cross2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours_across_edges_are_the_one_other_triangle_with_both_ends() {
        // Four triangles on edge 1-2 (0 to 3: none has a neighbour across it), and two
        // (4, 5) of opposite orientations on edge 0-7, hanging off vertex 0; every
        // other edge is on the boundary.
        let triangles = vec![
            [0, 1, 2],
            [2, 1, 3],
            [1, 4, 2],
            [2, 5, 1],
            [0, 6, 7],
            [0, 8, 7],
        ];
        let vt = VertexTriangles::new(9, &triangles);
        let adjacency = triangle_adjacency(&triangles, &vt);
        // Brute force: the other triangles with both ends of each corner's edge.
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (p, q) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let others: Vec<u32> = (0..triangles.len() as u32)
                    .filter(|&s| s as usize != t)
                    .filter(|&s| triangles[s as usize].contains(&p))
                    .filter(|&s| triangles[s as usize].contains(&q))
                    .collect();
                let expected = if others.len() == 1 { others[0] } else { NONE };
                assert_eq!(adjacency[t][k], expected, "triangle {t} corner {k}");
            }
        }
        assert_eq!(adjacency[0], [NONE, NONE, NONE]);
        assert_eq!(adjacency[4][1], 5);
        assert_eq!(adjacency[5][1], 4);
    }

    #[test]
    fn walk_finds_points_and_stops_at_holes() {
        let mut mesh = SurfaceMesh::structured(8, 8, |i, j| [i as f32, j as f32, (i * j) as f32]);
        let r = Reference::new(&mesh).unwrap();
        // Node (5, 3) has texture coordinates (11, 7) and position (5, 3, 15).
        let p = r.locate(0, [11.0, 7.0]).unwrap();
        let (pos, uv, _) = r.evaluate(&p);
        assert!((pos[0] - 5.0).abs() < 1e-9 && (pos[2] - 15.0).abs() < 1e-9);
        assert_eq!(uv, [11.0, 7.0]);
        // The middle of cell (2, 6): texture (6, 14), bilinear-ish position.
        let p = r.locate(5, [6.0, 14.0]).unwrap();
        let (pos, _, _) = r.evaluate(&p);
        assert!((pos[0] - 2.5).abs() < 1e-9 && (pos[1] - 6.5).abs() < 1e-9);
        // Outside the grid: no point.
        assert_eq!(r.locate(0, [20.0, 3.0]), None);

        // Cut a hole of 2 x 2 cells around (3..5, 3..5): a walk straight across fails,
        // while the cells beside the hole are still found.
        mesh.cell_faces.clear();
        mesh.triangles.retain(|t| {
            let c = t.map(|v| mesh.texcoords[v as usize]);
            let (u, v) = (
                (c[0][0] + c[1][0] + c[2][0]) / 3.0,
                (c[0][1] + c[1][1] + c[2][1]) / 3.0,
            );
            !((7.0..11.0).contains(&u) && (7.0..11.0).contains(&v))
        });
        let r = Reference::new(&mesh).unwrap();
        let west = r.locate(0, [2.0, 9.0]).unwrap();
        assert_eq!(r.locate(west.triangle, [9.0, 9.0]), None);
        assert_eq!(r.locate(west.triangle, [16.0, 9.0]), None);
        assert!(r.locate(0, [16.0, 2.0]).is_some());
    }
}
