//! Silhouette edges: cell edges where a folded surface turns away from the eye, found
//! on the CPU every frame and drawn by the outline pass (`outline.rs`) as outline
//! edges of that frame.
//!
//! # How it works
//! Where a surface folds over as seen, the cell line along the fold is drawn only on
//! the side that faces the eye: what lies beyond it on screen is the background or
//! something further away, as beyond the outline. An edge is on the silhouette when
//! its two triangles' far corners lie on the same side of the plane through the edge
//! and the eye (the test of Rossignac and van Emmerik's contour edges, `is_contour` in
//! lines.wgsl). The edges between two faces of one surface (found with the outline,
//! `strata_grid::outline::surface_edges`) are kept in clusters of [`CLUSTER`], from
//! tiles of columns, with a bounding sphere and a cone holding their triangles' normals; a
//! frame tests only the clusters whose triangles may face both ways from the eye, so
//! a surface that nowhere turns away (a layer seen from above) costs a test per
//! cluster.
//!
//! Vertical exaggeration stretches z before viewing; facing is tested in the
//! unexaggerated frame with the eye's z divided by it, which gives the same signs.
//!
//! # Why not the obvious way
//! Testing every edge in the vertex shader, as the contour techniques do, runs the
//! shader for every edge of the mesh every frame: a second pass over the whole mesh,
//! what the texture techniques exist to avoid.

use glam::Vec3;
use rayon::prelude::*;
use strata_grid::SurfaceMesh;
use strata_grid::outline::{InteriorEdge, OutlineEdge};

use super::FrameProjection;

/// Edges a cluster holds, taken from tiles of 8 x 8 columns: few enough that its
/// sphere and cone stay tight (256 edges in rows of cells left nearly every cluster
/// tested at the bench's view of its 1 M reservoir), many enough that testing the
/// clusters costs little beside their edges (docs/performance.md).
const CLUSTER: usize = 64;

/// A cell edge with a triangle of the same surface on either side.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    /// Its ends, then the far corner of the triangle on each side (vertex indices).
    vertices: [u32; 4],
    /// The grid line it lies on: its index, and whether it runs along i.
    line: u32,
    along_i: bool,
}

/// Clustered edges, a sphere around them and a cone around their triangles' normals.
#[derive(Clone, Copy, Debug)]
struct Cluster {
    /// Its edges: `start..end` of the candidates.
    start: u32,
    end: u32,
    centre: Vec3,
    radius: f32,
    /// The cone's axis (unit), and its half angle's cosine and sine.
    axis: Vec3,
    spread: (f32, f32),
}

/// The silhouette candidates of a mesh.
pub struct Silhouettes {
    positions: Vec<Vec3>,
    candidates: Vec<Candidate>,
    clusters: Vec<Cluster>,
}

impl Silhouettes {
    /// The sides the faces of `mesh` share (`interior`, `strata_grid::outline::
    /// surface_edges`), each of which can be on a silhouette; `None` when there are
    /// none (meshes without cell faces: decimated surfaces).
    pub fn new(mesh: &SurfaceMesh, interior: &[InteriorEdge]) -> Option<Silhouettes> {
        if interior.is_empty() {
            return None;
        }
        // Clusters of nearby edges, so that their spheres are small and their normals
        // alike: the edges in tiles of 8 x 8 columns (a counting sort, keeping each
        // surface's edges together within a tile), cut in runs of CLUSTER.
        let tile = |e: &InteriorEdge| [e.cell[0] >> 3, e.cell[1] >> 3];
        let tiles_i = interior.iter().map(|e| tile(e)[0] + 1).max().unwrap_or(1) as usize;
        let tiles_j = interior.iter().map(|e| tile(e)[1] + 1).max().unwrap_or(1) as usize;
        let key = |e: &InteriorEdge| {
            let [ti, tj] = tile(e);
            tj as usize * tiles_i + ti as usize
        };
        let mut start = vec![0usize; tiles_i * tiles_j + 1];
        for e in interior {
            start[key(e) + 1] += 1;
        }
        for t in 1..start.len() {
            start[t] += start[t - 1];
        }
        let mut order = vec![0u32; interior.len()];
        for (n, e) in interior.iter().enumerate() {
            let at = &mut start[key(e)];
            order[*at] = n as u32;
            *at += 1;
        }
        let candidates: Vec<Candidate> = order
            .iter()
            .map(|&n| {
                let e = &interior[n as usize];
                Candidate {
                    vertices: [e.ends[0], e.ends[1], e.far[0], e.far[1]],
                    line: e.line,
                    along_i: e.along_i,
                }
            })
            .collect();
        let positions: Vec<Vec3> = mesh.positions.iter().map(|&p| Vec3::from(p)).collect();
        let clusters = candidates
            .par_chunks(CLUSTER)
            .enumerate()
            .map(|(n, edges)| cluster(&positions, edges, (n * CLUSTER) as u32))
            .collect();
        Some(Silhouettes {
            positions,
            candidates,
            clusters,
        })
    }

    /// The edges on the silhouette as `frame` sees them, as outline edges (`out`,
    /// cleared first): the surface on the side of their triangles' far corners, the
    /// neighbours found among them.
    pub fn choose(&self, frame: &FrameProjection, out: &mut Vec<OutlineEdge>) {
        out.clear();
        let eye = Vec3::new(frame.eye.x, frame.eye.y, frame.eye.z / frame.z_scale);
        for c in &self.clusters {
            if !c.may_turn_away(eye) {
                continue;
            }
            for e in &self.candidates[c.start as usize..c.end as usize] {
                let [a, b, o0, o1] = e.vertices.map(|v| self.positions[v as usize]);
                let normal = (b - a).cross(eye - a);
                let (s0, s1) = (normal.dot(o0 - a), normal.dot(o1 - a));
                if s0 * s1 <= 0.0 {
                    continue;
                }
                // The far corners on the left going from the first end to the second,
                // as outline edges have their surface.
                let (p, q) = if s0 > 0.0 { (a, b) } else { (b, a) };
                // One cell inward: the far corner of the triangle nearer the eye, on
                // the side seen (its distance from the edge is the cell's width).
                let inward = if o0.distance_squared(eye) <= o1.distance_squared(eye) {
                    o0
                } else {
                    o1
                };
                out.push(OutlineEdge {
                    ends: [p.into(), q.into()],
                    inward: inward.into(),
                    line: e.line,
                    along_i: e.along_i,
                    before: (p + (p - q)).into(),
                    after: (q + (q - p)).into(),
                });
            }
        }
        join(out);
    }
}

/// Joins silhouette edges that meet end to end: each one's `before` and `after` are
/// the far ends of its neighbours, where it has them.
fn join(edges: &mut [OutlineEdge]) {
    let key = |p: [f32; 3]| p.map(f32::to_bits);
    let starts: std::collections::HashMap<[u32; 3], usize> = edges
        .iter()
        .enumerate()
        .map(|(n, e)| (key(e.ends[0]), n))
        .collect();
    let ends: std::collections::HashMap<[u32; 3], usize> = edges
        .iter()
        .enumerate()
        .map(|(n, e)| (key(e.ends[1]), n))
        .collect();
    for n in 0..edges.len() {
        if let Some(&m) = ends.get(&key(edges[n].ends[0])) {
            edges[n].before = edges[m].ends[0];
        }
        if let Some(&m) = starts.get(&key(edges[n].ends[1])) {
            edges[n].after = edges[m].ends[1];
        }
    }
}

/// The cluster of `edges`, the first at `start` among the candidates.
fn cluster(positions: &[Vec3], edges: &[Candidate], start: u32) -> Cluster {
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let mut normals = [Vec3::ZERO; 2 * CLUSTER];
    let mut sum = Vec3::ZERO;
    for (e, pair) in edges.iter().zip(normals.chunks_exact_mut(2)) {
        let [a, b, o0, o1] = e.vertices.map(|v| positions[v as usize]);
        for p in [a, b, o0, o1] {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        // The triangles' normals, the second turned to face with the first (their
        // windings across the edge run opposite ways); degenerate ones left at zero.
        pair[0] = (b - a).cross(o0 - a).normalize_or_zero();
        pair[1] = (a - b).cross(o1 - b).normalize_or_zero();
        sum += pair[0] + pair[1];
    }
    // The widest normal's cosine; a cone past 90 degrees (cosine 0 or less) holds
    // triangles facing every way.
    let (axis, cos_spread) = match sum.try_normalize() {
        Some(axis) => (
            axis,
            normals[..2 * edges.len()]
                .iter()
                .filter(|n| **n != Vec3::ZERO)
                .map(|n| n.dot(axis).clamp(-1.0, 1.0))
                .fold(1.0, f32::min),
        ),
        None => (Vec3::Z, -1.0),
    };
    Cluster {
        start,
        end: start + edges.len() as u32,
        centre: 0.5 * (lo + hi),
        radius: 0.5 * lo.distance(hi),
        axis,
        spread: (cos_spread, (1.0 - cos_spread * cos_spread).max(0.0).sqrt()),
    }
}

impl Cluster {
    /// Whether some of its triangles may face the eye at `eye` and others not: the
    /// angle between a normal and the way to the eye, from any point of the sphere,
    /// may reach 90 degrees. With `spread` the cone's half angle and `seen` the
    /// sphere's from the eye, all face one way when the angle between the axis and
    /// the eye stays `spread + seen` short of 90 degrees on either side: when the
    /// cosine of that angle exceeds sin(spread + seen) in size.
    fn may_turn_away(&self, eye: Vec3) -> bool {
        let to_eye = eye - self.centre;
        let distance = to_eye.length();
        if distance <= self.radius || self.spread.0 <= 0.0 {
            return true;
        }
        let (sin_seen, cos_seen) = {
            let s = self.radius / distance;
            (s, (1.0 - s * s).max(0.0).sqrt())
        };
        let (cos_spread, sin_spread) = self.spread;
        let cos_sum = cos_spread * cos_seen - sin_spread * sin_seen;
        let sin_sum = sin_spread * cos_seen + cos_spread * sin_seen;
        cos_sum <= 0.0 || (to_eye.dot(self.axis) / distance).abs() <= sin_sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Camera, View};

    /// An `n` x `n` grid of 10 m cells whose height is `z(x, y)`.
    fn surface(n: usize, z: impl Fn(f32, f32) -> f32) -> SurfaceMesh {
        SurfaceMesh::structured(n, n, |i, j| {
            let (x, y) = (10.0 * i as f32, 10.0 * j as f32);
            [x, y, z(x, y)]
        })
    }

    /// Folded along j = 6 into flanks rising 40 degrees to it.
    fn fold() -> SurfaceMesh {
        let slope = 40f32.to_radians().tan();
        surface(12, |_, y| slope * (60.0 - (y - 60.0).abs()))
    }

    /// The frame seen from the south at `elevation` degrees, `z_scale` exaggerated.
    fn frame(azimuth: f32, elevation: f32, z_scale: f32) -> FrameProjection {
        let mut camera = Camera::orbit(Vec3::new(60.0, 60.0, 0.0), azimuth, elevation, 400.0);
        camera.z_scale = z_scale;
        View {
            camera,
            width: 800,
            height: 800,
            bounds: (Vec3::ZERO, Vec3::new(120.0, 120.0, 60.0)),
        }
        .projection()
    }

    fn silhouettes(mesh: &SurfaceMesh) -> Option<Silhouettes> {
        Silhouettes::new(mesh, &strata_grid::outline::surface_edges(mesh).interior)
    }

    fn silhouette(mesh: &SurfaceMesh, frame: &FrameProjection) -> Vec<OutlineEdge> {
        let mut out = Vec::new();
        if let Some(s) = silhouettes(mesh) {
            s.choose(frame, &mut out);
        }
        out
    }

    #[test]
    fn a_fold_turning_away_is_the_silhouette_along_its_grid_line() {
        let edges = silhouette(&fold(), &frame(0.0, 20.0, 1.0));
        assert_eq!(edges.len(), 12, "{edges:?}");
        for e in &edges {
            assert!(e.along_i && e.line == 6, "{e:?}");
            assert!(e.ends.iter().all(|p| p[1] == 60.0), "{e:?}");
            // One cell inward on the flank seen (the south one, nearer the eye).
            assert_eq!(e.inward[1], 50.0, "{e:?}");
        }
        // Joined end to end: a corner's neighbour is the edge that meets it.
        let joined = edges
            .iter()
            .filter(|e| {
                edges
                    .iter()
                    .any(|f| f.ends[0] == e.ends[1] && f.ends[1] == e.after)
            })
            .count();
        assert_eq!(joined, 11);
    }

    #[test]
    fn nothing_is_on_the_silhouette_where_the_surface_faces_the_eye() {
        // From above the flanks' slope, or flattened below the elevation.
        assert!(silhouette(&fold(), &frame(0.0, 60.0, 1.0)).is_empty());
        assert!(silhouette(&fold(), &frame(0.0, 20.0, 0.3)).is_empty());
        assert_eq!(silhouette(&fold(), &frame(0.0, 20.0, 2.0)).len(), 12);
        // A flat grid from a low angle.
        assert!(silhouette(&surface(12, |_, _| 0.0), &frame(30.0, 2.0, 1.0)).is_empty());
    }

    #[test]
    fn clusters_left_out_hold_no_silhouette_edge() {
        // Hills seen from all round at low angles: the silhouette found through the
        // clusters is the one found by testing every edge.
        let hills = surface(48, |x, y| 12.0 * (x / 40.0).sin() * (y / 50.0).cos());
        let s = silhouettes(&hills).unwrap();
        let mut found = Vec::new();
        let (mut total, mut left_out) = (0, 0);
        for (azimuth, elevation) in [(0.0, 5.0), (70.0, 12.0), (145.0, 30.0), (260.0, 45.0)] {
            let frame = frame(azimuth, elevation, 1.5);
            s.choose(&frame, &mut found);
            let eye = Vec3::new(frame.eye.x, frame.eye.y, frame.eye.z / frame.z_scale);
            let every = s
                .candidates
                .iter()
                .filter(|e| {
                    let [a, b, o0, o1] = e.vertices.map(|v| s.positions[v as usize]);
                    let n = (b - a).cross(eye - a);
                    n.dot(o0 - a) * n.dot(o1 - a) > 0.0
                })
                .count();
            assert_eq!(found.len(), every, "from {azimuth} {elevation}");
            total += every;
            left_out += s.clusters.iter().filter(|c| !c.may_turn_away(eye)).count();
        }
        // Both cases are met: edges on the silhouette, and clusters left out.
        assert!(total > 20 && left_out > 20, "{total} {left_out}");
    }
}
