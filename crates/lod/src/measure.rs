//! How far a simplified surface draws the original grid lines from where the
//! original surface draws them.
//!
//! The global wireframe draws a line wherever a texture coordinate is odd. A point of
//! the original surface with texture coordinates `uv` is therefore drawn, on the
//! simplified surface, at the point that has the same `uv` there; the distance
//! between the two is how far that bit of line moved. [`deviation`] samples the
//! original's grid lines (its cell edges) and measures that distance for each sample.
//!
//! Texture coordinates name a point only within one connected piece of a surface
//! (stacked layers share them, and so do the two sides of a fault along its trace),
//! so samples are matched within their piece ("component") only, and where both sides
//! of a fault draw the same coordinate, the nearer one counts.

use rayon::prelude::*;
use strata_grid::SurfaceMesh;

use crate::reference::{NONE, SurfacePoint, VertexTriangles, cross2, triangle_adjacency};

/// Connected components of a mesh's triangles (through shared vertices), as one label
/// per triangle, numbered in order of first appearance.
pub fn components(mesh: &SurfaceMesh) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..mesh.vertex_count() as u32).collect();
    fn find(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            let p = parent[parent[v as usize] as usize];
            parent[v as usize] = p;
            v = p;
        }
        v
    }
    for t in &mesh.triangles {
        let r0 = find(&mut parent, t[0]);
        for &v in &t[1..] {
            let r = find(&mut parent, v);
            if r != r0 {
                let (lo, hi) = (r.min(r0), r.max(r0));
                parent[hi as usize] = lo;
            }
        }
    }
    let mut label = vec![NONE; mesh.vertex_count()];
    let mut next = 0;
    mesh.triangles
        .iter()
        .map(|t| {
            let r = find(&mut parent, t[0]) as usize;
            if label[r] == NONE {
                label[r] = next;
                next += 1;
            }
            label[r]
        })
        .collect()
}

/// A bucket grid over texture space: which triangles of a mesh (with a component
/// label each) cover a texture coordinate.
pub struct UvIndex<'m> {
    mesh: &'m SurfaceMesh,
    labels: Vec<u32>,
    /// Per triangle, its first two barycentric coordinates as affine functions of
    /// texture coordinates (`None` without texture area): testing a candidate
    /// triangle then reads none of its vertices.
    affine: Vec<Option<[[f64; 3]; 2]>>,
    /// Per triangle, its [`texture_bounds`]: the nearest-point search turns most
    /// triangles of its rings away by them, without reading a vertex.
    bounds: Vec<[f32; 4]>,
    lo: [f64; 2],
    cell: f64,
    dims: [usize; 2],
    start: Vec<u32>,
    items: Vec<u32>,
}

/// Most buckets per triangle of the mesh; bounds the index's memory whatever the
/// shape of the texture domain.
const BUCKETS_PER_TRIANGLE: f64 = 2.0;

impl<'m> UvIndex<'m> {
    /// Indexes `mesh`, whose triangle `t` belongs to component `labels[t]` (a
    /// triangle without a label belongs to none: it is never found).
    pub fn new(mesh: &'m SurfaceMesh, mut labels: Vec<u32>) -> Self {
        labels.resize(mesh.triangle_count(), NONE);
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for t in mesh
            .texcoords
            .iter()
            .filter(|t| t[0].is_finite() && t[1].is_finite())
        {
            for a in 0..2 {
                lo[a] = lo[a].min(f64::from(t[a]));
                hi[a] = hi[a].max(f64::from(t[a]));
            }
        }
        let n = mesh.triangle_count().max(1) as f64;
        let (w, h) = ((hi[0] - lo[0]).max(1e-9), (hi[1] - lo[1]).max(1e-9));
        let cell = if lo[0] <= hi[0] {
            (w * h * BUCKETS_PER_TRIANGLE.recip() / n).sqrt().max(1e-9)
        } else {
            lo = [0.0; 2];
            1.0
        };
        let dims = [
            ((w / cell).ceil() as usize).clamp(1, 1 << 15),
            ((h / cell).ceil() as usize).clamp(1, 1 << 15),
        ];
        let cell = (w / dims[0] as f64).max(h / dims[1] as f64);
        let grid = Grid { lo, cell, dims };
        let bounds: Vec<[f32; 4]> = mesh
            .triangles
            .iter()
            .map(|t| texture_bounds(mesh, t))
            .collect();
        // Two sweeps: count, then fill (compressed rows).
        let mut start = vec![0u32; dims[0] * dims[1] + 1];
        for b in &bounds {
            grid.buckets(b, |b| start[b + 1] += 1);
        }
        for b in 0..dims[0] * dims[1] {
            start[b + 1] += start[b];
        }
        let mut fill = start.clone();
        let mut items = vec![0; start[dims[0] * dims[1]] as usize];
        for (i, b) in bounds.iter().enumerate() {
            grid.buckets(b, |b| {
                items[fill[b] as usize] = i as u32;
                fill[b] += 1;
            });
        }
        let affine = mesh
            .triangles
            .iter()
            .map(|t| affine_barycentric(t.map(|v| mesh.texcoords[v as usize].map(f64::from))))
            .collect();
        UvIndex {
            mesh,
            labels,
            affine,
            bounds,
            lo,
            cell,
            dims,
            start,
            items,
        }
    }

    /// The bucket of `uv`, clamped into the grid (points outside the indexed domain
    /// look at the border buckets, whose triangles then reject them).
    fn bucket_of(&self, uv: [f64; 2]) -> Option<[usize; 2]> {
        if !(uv[0].is_finite() && uv[1].is_finite()) {
            return None;
        }
        let at = |x: f64, lo: f64, n: usize| {
            (((x - lo) / self.cell).floor() as i64).clamp(0, n as i64 - 1) as usize
        };
        Some([
            at(uv[0], self.lo[0], self.dims[0]),
            at(uv[1], self.lo[1], self.dims[1]),
        ])
    }

    fn bucket(&self, b: [usize; 2]) -> &[u32] {
        let i = b[1] * self.dims[0] + b[0];
        &self.items[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// The surface searched.
    pub fn mesh(&self) -> &'m SurfaceMesh {
        self.mesh
    }

    /// Barycentric coordinates of `uv` in triangle `t` (texture space).
    fn barycentric(&self, t: u32, uv: [f64; 2]) -> Option<[f64; 3]> {
        let [w0, w1] = self.affine[t as usize]?.map(|[a, b, c]| a * uv[0] + b * uv[1] + c);
        Some([w0, w1, 1.0 - w0 - w1])
    }

    /// The points of component `label` with texture coordinates `uv` (up to rounding:
    /// barycentric coordinates down to `-1e-7`), into `out`.
    pub fn find(&self, uv: [f64; 2], label: u32, out: &mut Vec<SurfacePoint>) {
        out.clear();
        let Some(b) = self.bucket_of(uv) else {
            return;
        };
        for &t in self.bucket(b) {
            if self.labels[t as usize] != label {
                continue;
            }
            if let Some(w) = self.barycentric(t, uv)
                && w.iter().all(|&x| x >= -1e-7)
            {
                out.push(SurfacePoint {
                    triangle: t,
                    barycentric: w,
                });
            }
        }
    }

    /// The point of component `label` whose texture coordinates are nearest `uv`,
    /// searching up to `rings` buckets around it (for samples just outside a
    /// simplified boundary); `None` when no triangle of the component is that near.
    pub fn nearest(&self, uv: [f64; 2], label: u32, rings: usize) -> Option<SurfacePoint> {
        let x = ((uv[0] - self.lo[0]) / self.cell).floor() as i64;
        let y = ((uv[1] - self.lo[1]) / self.cell).floor() as i64;
        let mut best: Option<(f64, SurfacePoint)> = None;
        // Triangles already measured: a large one is in several buckets of the rings,
        // and its distance, measured again, could not beat the best (at most it).
        let mut measured = [NONE; 16];
        let mut count = 0;
        let r = rings as i64;
        for by in (y - r).max(0)..=(y + r).min(self.dims[1] as i64 - 1) {
            for bx in (x - r).max(0)..=(x + r).min(self.dims[0] as i64 - 1) {
                for &t in self.bucket([bx as usize, by as usize]) {
                    if self.labels[t as usize] != label {
                        continue;
                    }
                    // No nearer than its box: most triangles of the rings end here.
                    let b = self.bounds[t as usize].map(f64::from);
                    let gap = |a: usize| (b[a] - uv[a]).max(uv[a] - b[a + 2]).max(0.0);
                    if best
                        .as_ref()
                        .is_some_and(|(bd, _)| gap(0).powi(2) + gap(1).powi(2) >= *bd)
                        || measured[..count].contains(&t)
                    {
                        continue;
                    }
                    if count < measured.len() {
                        measured[count] = t;
                        count += 1;
                    }
                    let c = self.mesh.triangles[t as usize]
                        .map(|v| self.mesh.texcoords[v as usize].map(f64::from));
                    let (d2, w) = closest_in_triangle(uv, c);
                    if best.as_ref().is_none_or(|(bd, _)| d2 < *bd) {
                        best = Some((
                            d2,
                            SurfacePoint {
                                triangle: t,
                                barycentric: w,
                            },
                        ));
                    }
                }
            }
        }
        best.map(|(_, p)| p)
    }

    /// Position at a point of the indexed mesh.
    pub fn position(&self, p: &SurfacePoint) -> [f64; 3] {
        point_position(self.mesh, p)
    }
}

/// The first two barycentric coordinates in the texture-space triangle `c` as affine
/// functions `a u + b v + c` of texture coordinates; `None` when it has no area.
fn affine_barycentric(c: [[f64; 2]; 3]) -> Option<[[f64; 3]; 2]> {
    let area = cross2(c[0], c[1], c[2]);
    if area == 0.0 || !area.is_finite() {
        return None;
    }
    // Of `p` opposite the edge `q r`: cross2(uv, q, r) / area, expanded.
    let row = |q: [f64; 2], r: [f64; 2]| {
        [
            (q[1] - r[1]) / area,
            (r[0] - q[0]) / area,
            (q[0] * r[1] - r[0] * q[1]) / area,
        ]
    };
    Some([row(c[1], c[2]), row(c[2], c[0])])
}

/// The bucket layout of a [`UvIndex`].
struct Grid {
    lo: [f64; 2],
    cell: f64,
    dims: [usize; 2],
}

impl Grid {
    /// Calls `f` with every bucket that the [`texture_bounds`] `b` of a triangle touch.
    fn buckets(&self, b: &[f32; 4], mut f: impl FnMut(usize)) {
        if b.iter().any(|x| !x.is_finite()) {
            return;
        }
        let at = |x: f32, lo: f64, n: usize| {
            (((f64::from(x) - lo) / self.cell).floor() as i64).clamp(0, n as i64 - 1) as usize
        };
        for y in at(b[1], self.lo[1], self.dims[1])..=at(b[3], self.lo[1], self.dims[1]) {
            for x in at(b[0], self.lo[0], self.dims[0])..=at(b[2], self.lo[0], self.dims[0]) {
                f(y * self.dims[0] + x);
            }
        }
    }
}

/// The texture-space bounds of triangle `t` of `mesh`: lowest u and v, then highest;
/// NaN where a corner's texture coordinates are not finite (such a triangle is in no
/// bucket).
fn texture_bounds(mesh: &SurfaceMesh, t: &[u32; 3]) -> [f32; 4] {
    let c = t.map(|v| mesh.texcoords[v as usize]);
    if c.iter().any(|p| !(p[0].is_finite() && p[1].is_finite())) {
        return [f32::NAN; 4];
    }
    let lo = |a: usize| c[0][a].min(c[1][a]).min(c[2][a]);
    let hi = |a: usize| c[0][a].max(c[1][a]).max(c[2][a]);
    [lo(0), lo(1), hi(0), hi(1)]
}

/// Squared distance from `p` to triangle `c` (2D) and the barycentric coordinates
/// of the closest point.
fn closest_in_triangle(p: [f64; 2], c: [[f64; 2]; 3]) -> (f64, [f64; 3]) {
    let area = cross2(c[0], c[1], c[2]);
    if area != 0.0 && area.is_finite() {
        let w = [
            cross2(p, c[1], c[2]) / area,
            cross2(c[0], p, c[2]) / area,
            cross2(c[0], c[1], p) / area,
        ];
        if w.iter().all(|&x| x >= 0.0) {
            return (0.0, w);
        }
    }
    // Outside (or degenerate): the closest point of the three edges.
    let mut best = (f64::INFINITY, [1.0, 0.0, 0.0]);
    for k in 0..3 {
        let (a, b) = (c[k], c[(k + 1) % 3]);
        let e = [b[0] - a[0], b[1] - a[1]];
        let len2 = e[0] * e[0] + e[1] * e[1];
        let s = if len2 > 0.0 {
            (((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1]) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = [a[0] + s * e[0], a[1] + s * e[1]];
        let d2 = (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2);
        if d2 < best.0 {
            let mut w = [0.0; 3];
            w[k] = 1.0 - s;
            w[(k + 1) % 3] = s;
            best = (d2, w);
        }
    }
    best
}

/// Distances from the original grid lines to where the simplified surface draws them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Deviation {
    /// Samples taken (points along the original cell edges).
    pub samples: usize,
    /// Largest distance, in display length units (z scaled).
    pub max: f64,
    /// Root-mean-square distance, in the same units.
    pub rms: f64,
    /// Samples whose texture coordinate the simplified surface does not draw at all
    /// (outside its simplified boundary); their distance to the nearest point it does
    /// draw is included in `max` and `rms`.
    pub outside: usize,
    /// Largest vertical distance (z scaled) of a sample the simplified surface draws
    /// from where it draws it: how far the surface may rise through the one above it
    /// or sink through the one below (see strata-render's `Stacking`).
    pub vertical: f64,
    /// Samples with no point of their piece of surface near enough to measure (the
    /// piece kept no triangle, or shrank far from them); left out of `samples`.
    pub missed: usize,
}

/// Edges longer than this many times the upper quartile of a surface's edge lengths
/// (for decimation, of their lengths per texture unit) reach a stray corner (a
/// corrupt depth or pillar coordinate, see strata-grid's
/// `CornerPointGrid::stray_corners`). Decimation leaves them out of the mean lengths
/// that scale texture coordinates, scalar and ties: with them, a curved surface of
/// 40 x 40 cells with one corner at a depth of 1e11, decimated to 10 %, drew its grid
/// lines several times further from the original's (RMS) than without them, and
/// without them nearly as near as with no stray corner at all. [`GridLines`] leaves
/// them out of the lines it samples, and a
/// simplified surface's triangles at a stray corner ([`Strays::holds`]) out of those
/// that draw the samples: where a simplified surface draws a texture coordinate
/// along a 1e11 m edge is no measure of the rest of it, and the top of a generated
/// 40 x 30 x 3 model with such a corner had a `vertical` deviation of the corner's
/// order, which pushed every layer below it out of `render --lod`'s depth test. The
/// real models in the project's data have no edge near this bound, and measure and
/// decimate as before (`docs/performance.md`, "Decimation internals").
const STRAY_EDGE_QUARTILES: f64 = 1.0 + strata_grid::STRAY_SPREADS;

/// Edges whose upper quartile [`STRAY_EDGE_QUARTILES`] is taken from: at most this
/// many, evenly spread over the triangles.
const STRAY_EDGE_SAMPLES: usize = 1 << 14;

/// [`STRAY_EDGE_QUARTILES`] times the upper quartile of `length` (a length, or a
/// length per texture unit) over `mesh`'s edges (from at most [`STRAY_EDGE_SAMPLES`]
/// of them); infinite without edges.
pub(crate) fn stray_limit(mesh: &SurfaceMesh, length: impl Fn(usize, usize) -> f64) -> f64 {
    let stride = mesh.triangle_count().div_ceil(STRAY_EDGE_SAMPLES).max(1);
    let mut lengths: Vec<f64> = mesh
        .triangles
        .iter()
        .step_by(stride)
        .map(|t| length(t[0] as usize, t[1] as usize))
        .collect();
    let Some(last) = lengths.len().checked_sub(1) else {
        return f64::INFINITY;
    };
    let upper = *lengths
        .select_nth_unstable_by(3 * last / 4, f64::total_cmp)
        .1;
    // Mostly edges of no length (a pinched surface): nothing to judge by.
    if upper > 0.0 {
        STRAY_EDGE_QUARTILES * upper
    } else {
        f64::INFINITY
    }
}

/// What of a surface reaches a stray corner: its edges over [`stray_limit`]
/// (plain lengths), the triangles with one, and the vertices most of whose edges are
/// such (the corners themselves). Nearly always nothing; measures of a simplified
/// surface leave it out ([`GridLines`], the hierarchy's node errors).
pub(crate) struct Strays {
    /// Edges longer than this reach a stray corner.
    pub edge: f64,
    /// The triangles and the corners, both in order.
    triangles: Vec<u32>,
    corners: Vec<u32>,
}

impl Strays {
    pub fn of(mesh: &SurfaceMesh) -> Strays {
        let length = |a: usize, b: usize| plain_distance(mesh.positions[a], mesh.positions[b]);
        let edge = stray_limit(mesh, length);
        let stray = |a: u32, b: u32| length(a as usize, b as usize) > edge;
        let triangles: Vec<u32> = (0..mesh.triangle_count() as u32)
            .filter(|&t| {
                let tri = mesh.triangles[t as usize];
                (0..3).any(|k| stray(tri[k], tri[(k + 1) % 3]))
            })
            .collect();
        let mut corners = Vec::new();
        if !triangles.is_empty() {
            // Per vertex, its stray edges and all its edges (an inner one twice).
            let mut edges = vec![(0u32, 0u32); mesh.vertex_count()];
            for tri in &mesh.triangles {
                for k in 0..3 {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    let long = u32::from(stray(a, b));
                    for v in [a, b] {
                        edges[v as usize].0 += long;
                        edges[v as usize].1 += 1;
                    }
                }
            }
            corners = (0..mesh.vertex_count() as u32)
                .filter(|&v| 2 * edges[v as usize].0 > edges[v as usize].1)
                .collect();
        }
        Strays {
            edge,
            triangles,
            corners,
        }
    }

    /// Whether the edge `a b` of `mesh` (the surface these are of) reaches a stray
    /// corner.
    pub fn has_edge(&self, mesh: &SurfaceMesh, a: u32, b: u32) -> bool {
        plain_distance(mesh.positions[a as usize], mesh.positions[b as usize]) > self.edge
    }

    /// Whether a point `p` at home on triangle `home` of `mesh` (the surface these are
    /// of) is at a stray corner: `home` reaches one, and `p` lies further than a
    /// stray edge from its other corners.
    pub fn holds(&self, mesh: &SurfaceMesh, home: u32, p: [f32; 3]) -> bool {
        if self.triangles.binary_search(&home).is_err() {
            return false;
        }
        mesh.triangles[home as usize]
            .iter()
            .filter(|&u| self.corners.binary_search(u).is_err())
            .all(|&u| plain_distance(mesh.positions[u as usize], p) > self.edge)
    }
}

/// Cell edges (or triangles) from which [`GridLines`] work on the thread pool.
const PARALLEL_EDGES: usize = 1 << 14;

/// The fixed share of cell edges (or triangles) one task of the pool takes: fixed, so
/// that results come out in the same order, and sum alike, on any pool.
const EDGES_PER_TASK: usize = PARALLEL_EDGES / 4;

/// The original grid lines a [`deviation`] samples: every cell edge of a surface
/// (every edge along which one texture coordinate is constant: the diagonals that
/// split cell quads are no grid lines) once, with the component it lies in. Built
/// once, it measures any number of simplifications of the same surface.
pub struct GridLines<'m> {
    original: &'m SurfaceMesh,
    /// Component of each original triangle.
    labels: Vec<u32>,
    /// Ends of each cell edge, and its component.
    edges: Vec<[u32; 3]>,
    per_edge: usize,
    /// What reaches a stray corner: not sampled, and drawing no sample.
    strays: Strays,
}

impl<'m> GridLines<'m> {
    /// The cell edges of `original`, to be sampled at `per_edge` points each (at least
    /// one: the edge's first end).
    pub fn of(original: &'m SurfaceMesh, per_edge: usize) -> Self {
        let vt = VertexTriangles::new(original.vertex_count(), &original.triangles);
        let adjacency = triangle_adjacency(&original.triangles, &vt);
        GridLines::of_parts(original, &vt, &adjacency, components(original), per_edge)
    }

    /// [`GridLines::of`] `original` with its vertex triangles, [`triangle_adjacency`]
    /// and the [`components`] of its triangles, where the caller has them already.
    pub(crate) fn of_parts(
        original: &'m SurfaceMesh,
        vt: &VertexTriangles,
        adjacency: &[[u32; 3]],
        labels: Vec<u32>,
        per_edge: usize,
    ) -> Self {
        let strays = Strays::of(original);
        // The cell edges of triangles `first..` (`triangles`), in order, into `out`,
        // but those that reach a stray corner.
        let cell_edges = |first: usize, triangles: &[[u32; 3]], out: &mut Vec<[u32; 3]>| {
            for (t, tri) in (first..).zip(triangles) {
                for k in 0..3 {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    let (ta, tb) = (
                        original.texcoords[a as usize],
                        original.texcoords[b as usize],
                    );
                    // Each cell edge once (from the triangle where it runs a -> b with
                    // a < b, or from its only triangle on a boundary either way). A
                    // neighbour across it says it is none; without one, another
                    // triangle may still have it (where several do), and only a
                    // search tells.
                    let on_line = ta[0] == tb[0] || ta[1] == tb[1];
                    let boundary = || {
                        adjacency[t][(k + 2) % 3] == NONE
                            && !vt.of(a).iter().any(|&s| {
                                s as usize != t && original.triangles[s as usize].contains(&b)
                            })
                    };
                    if on_line && (a < b || boundary()) && !strays.has_edge(original, a, b) {
                        out.push([a, b, labels[t]]);
                    }
                }
            }
        };
        let of_part = |first: usize, part: &[[u32; 3]]| {
            let mut edges = Vec::with_capacity(part.len() * 3 / 2 + 8);
            cell_edges(first, part, &mut edges);
            edges
        };
        let triangles = &original.triangles;
        let edges = if triangles.len() < PARALLEL_EDGES {
            of_part(0, triangles)
        } else {
            let parts: Vec<Vec<[u32; 3]>> = triangles
                .par_chunks(EDGES_PER_TASK)
                .enumerate()
                .map(|(i, part)| of_part(i * EDGES_PER_TASK, part))
                .collect();
            parts.concat()
        };
        GridLines {
            original,
            labels,
            edges,
            per_edge: per_edge.max(1),
            strays,
        }
    }

    /// `simplified` indexed by texture coordinates, each triangle labelled with the
    /// component of the original it lies in: `home[v]` is a triangle of the original
    /// that simplified vertex `v` lies on (or comes from). A triangle with a vertex at
    /// a stray corner ([`Strays::holds`]) is in none.
    fn index<'s>(&self, simplified: &'s SurfaceMesh, home: &[u32]) -> UvIndex<'s> {
        let labels = &self.labels;
        let stray = |v: u32| {
            home.get(v as usize).is_some_and(|&h| {
                self.strays
                    .holds(self.original, h, simplified.positions[v as usize])
            })
        };
        let simplified_labels: Vec<u32> = simplified
            .triangles
            .iter()
            .map(|t| {
                if t.iter().any(|&v| stray(v)) {
                    return NONE;
                }
                t.iter()
                    .map(|&v| home.get(v as usize).copied().unwrap_or(NONE))
                    .find(|&h| h != NONE && (h as usize) < labels.len())
                    .map_or(NONE, |h| labels[h as usize])
            })
            .collect();
        UvIndex::new(simplified, simplified_labels)
    }

    /// The samples of cell edge `[a, b, label]`: texture coordinates and position on
    /// the original, from its first end on.
    fn samples(&self, &[a, b, _]: &[u32; 3]) -> impl Iterator<Item = ([f64; 2], [f64; 3])> {
        let original = self.original;
        let (ta, tb) = (
            original.texcoords[a as usize],
            original.texcoords[b as usize],
        );
        let (pa, pb) = (
            original.positions[a as usize],
            original.positions[b as usize],
        );
        let per_edge = self.per_edge;
        (0..per_edge).map(move |i| {
            let s = i as f64 / per_edge as f64;
            let lerp = |x: f32, y: f32| f64::from(x) + s * (f64::from(y) - f64::from(x));
            (
                [lerp(ta[0], tb[0]), lerp(ta[1], tb[1])],
                [lerp(pa[0], pb[0]), lerp(pa[1], pb[1]), lerp(pa[2], pb[2])],
            )
        })
    }

    /// Measures each sample's distance to the point of `simplified` with the same
    /// texture coordinates in the same component (see `GridLines::index` for
    /// `home`); where several points have them (the two sides of a fault), the
    /// nearest.
    pub fn deviation(&self, simplified: &SurfaceMesh, home: &[u32], z_scale: f64) -> Deviation {
        let index = self.index(simplified, home);
        let measure = |found: &mut Vec<SurfacePoint>, edge: &[u32; 3]| {
            let mut sums = Sums::default();
            for (uv, p) in self.samples(edge) {
                let inside = locate(&index, uv, edge[2], found);
                let (d, dz) = found
                    .iter()
                    .map(|f| {
                        let at = index.position(f);
                        (distance(at, p, z_scale), (at[2] - p[2]).abs() * z_scale)
                    })
                    .fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a });
                sums.add(inside.map(|inside| (d, dz, inside)));
            }
            sums
        };
        let measure_all = |edges: &[[u32; 3]]| {
            let mut found = Vec::new();
            edges
                .iter()
                .fold(Sums::default(), |acc, e| acc.merge(measure(&mut found, e)))
        };
        // Small surfaces (a layer the bench measures at a small budget) are measured on the
        // calling thread: handing them to the pool cost more than the work. Large ones are
        // summed task by task in order (a reduction in the pool's own order changed the
        // last digit between runs).
        let sums = if self.edges.len() < PARALLEL_EDGES {
            measure_all(&self.edges)
        } else {
            self.edges
                .par_chunks(EDGES_PER_TASK)
                .map(measure_all)
                .collect::<Vec<_>>()
                .into_iter()
                .fold(Sums::default(), Sums::merge)
        };
        sums.deviation()
    }

    /// Where `simplified` draws each sample (see `GridLines::index` for `home`):
    /// the point of the same texture coordinates nearest it with z scaled by
    /// `z_scale` (the side of a fault that [`GridLines::deviation`] measures), or
    /// the nearest point outside its boundary; the points stay where they are in
    /// texture space when the simplified surface's positions change ([`crate::fit`]).
    pub fn locate(&self, simplified: &SurfaceMesh, home: &[u32], z_scale: f64) -> Located {
        let index = self.index(simplified, home);
        // Collected straight into one list, with room for all: the list is large
        // (every sample of the surface's grid lines), and collecting each edge's
        // samples, misses included, on their own first was measured much slower
        // (`docs/performance.md`).
        let place = |edges: &[[u32; 3]], out: &mut Vec<LocatedSample>| {
            let mut found = Vec::new();
            for edge in edges {
                out.extend(self.samples(edge).filter_map(|(uv, target)| {
                    let inside = locate(&index, uv, edge[2], &mut found)?;
                    let nearest = found.iter().min_by(|f, g| {
                        let d = |p: &SurfacePoint| distance(index.position(p), target, z_scale);
                        d(f).total_cmp(&d(g))
                    })?;
                    Some(LocatedSample {
                        point: *nearest,
                        target,
                        inside,
                    })
                }));
            }
        };
        let count = self.edges.len() * self.per_edge;
        let mut samples = Vec::with_capacity(count);
        if self.edges.len() < PARALLEL_EDGES {
            place(&self.edges, &mut samples);
        } else {
            let chunks: Vec<Vec<LocatedSample>> = self
                .edges
                .par_chunks(EDGES_PER_TASK)
                .map(|edges| {
                    let mut out = Vec::with_capacity(edges.len() * self.per_edge);
                    place(edges, &mut out);
                    out
                })
                .collect();
            for chunk in chunks {
                samples.extend(chunk);
            }
        }
        Located {
            missed: count - samples.len(),
            samples,
        }
    }
}

/// The simplified surface's points of `uv` in component `label`, into `found`:
/// `Some(true)` where it draws `uv`, `Some(false)` with its point nearest in texture
/// space where `uv` is just outside its boundary, `None` where it has no point near.
fn locate(
    index: &UvIndex,
    uv: [f64; 2],
    label: u32,
    found: &mut Vec<SurfacePoint>,
) -> Option<bool> {
    index.find(uv, label, found);
    if !found.is_empty() {
        return Some(true);
    }
    let nearest = index.nearest(uv, label, 2)?;
    found.push(nearest);
    Some(false)
}

/// Distance between two points of a mesh, z unscaled.
fn plain_distance(p: [f32; 3], q: [f32; 3]) -> f64 {
    distance(p.map(f64::from), q.map(f64::from), 1.0)
}

/// Distance between two points, their z difference scaled by `z_scale`.
fn distance(p: [f64; 3], q: [f64; 3], z_scale: f64) -> f64 {
    let dz = (q[2] - p[2]) * z_scale;
    ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2) + dz * dz).sqrt()
}

/// What a [`Deviation`] sums over samples.
#[derive(Clone, Copy, Default)]
struct Sums {
    squares: f64,
    max: f64,
    vertical: f64,
    samples: usize,
    outside: usize,
    missed: usize,
}

impl Sums {
    /// A sample's distance, vertical distance and whether it is inside, or `None`
    /// when missed.
    fn add(&mut self, sample: Option<(f64, f64, bool)>) {
        match sample {
            Some((d, dz, inside)) => {
                self.squares += d * d;
                self.max = self.max.max(d);
                if inside {
                    self.vertical = self.vertical.max(dz);
                }
                self.samples += 1;
                self.outside += usize::from(!inside);
            }
            None => self.missed += 1,
        }
    }

    fn merge(self, other: Sums) -> Sums {
        Sums {
            squares: self.squares + other.squares,
            max: self.max.max(other.max),
            vertical: self.vertical.max(other.vertical),
            samples: self.samples + other.samples,
            outside: self.outside + other.outside,
            missed: self.missed + other.missed,
        }
    }

    fn deviation(self) -> Deviation {
        Deviation {
            samples: self.samples,
            max: self.max,
            rms: if self.samples > 0 {
                (self.squares / self.samples as f64).sqrt()
            } else {
                0.0
            },
            outside: self.outside,
            vertical: self.vertical,
            missed: self.missed,
        }
    }
}

/// A sample of the original grid lines and the point of a simplified surface that
/// draws it.
#[derive(Clone, Copy, Debug)]
pub struct LocatedSample {
    /// On the simplified surface.
    pub point: SurfacePoint,
    /// The sample's position on the original.
    pub target: [f64; 3],
    /// Whether `point` draws the sample's texture coordinates (else it is the
    /// nearest point that the simplified surface draws).
    pub inside: bool,
}

/// The samples of [`GridLines`] located on one simplified surface
/// ([`GridLines::locate`]).
#[derive(Clone, Debug, Default)]
pub struct Located {
    /// The samples, each with the point of the surface found for it.
    pub samples: Vec<LocatedSample>,
    /// Samples with no point of their piece near enough ([`Deviation::missed`]).
    pub missed: usize,
}

impl Located {
    /// The [`Deviation`] of the samples on `simplified` (the surface they were
    /// located on, with its positions as they are now).
    pub fn deviation(&self, simplified: &SurfaceMesh, z_scale: f64) -> Deviation {
        let mut sums = Sums {
            missed: self.missed,
            ..Sums::default()
        };
        for s in &self.samples {
            let at = point_position(simplified, &s.point);
            let dz = (at[2] - s.target[2]).abs() * z_scale;
            sums.add(Some((distance(at, s.target, z_scale), dz, s.inside)));
        }
        sums.deviation()
    }
}

/// Position of a point of `mesh`.
pub(crate) fn point_position(mesh: &SurfaceMesh, p: &SurfacePoint) -> [f64; 3] {
    let tri = mesh.triangles[p.triangle as usize];
    let mut out = [0f64; 3];
    for (&v, &w) in tri.iter().zip(&p.barycentric) {
        let x = mesh.positions[v as usize];
        for a in 0..3 {
            out[a] += w * f64::from(x[a]);
        }
    }
    out
}

/// Samples every cell edge of `original` at `per_edge` points and measures each
/// sample's distance to where `simplified` draws it ([`GridLines::deviation`]).
pub fn deviation(
    original: &SurfaceMesh,
    simplified: &SurfaceMesh,
    home: &[u32],
    per_edge: usize,
    z_scale: f64,
) -> Deviation {
    GridLines::of(original, per_edge).deviation(simplified, home, z_scale)
}

/// What keeping a surface's outline costs: its corners and the fewest triangles that
/// can hold them all.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OutlineBound {
    /// Outline vertices (on outer borders, holes and fault traces) where the outline
    /// turns in texture space, or where it meets itself.
    pub corners: usize,
    /// A lower bound on the triangles of any simplification that keeps every corner:
    /// a connected piece whose boundary has `c` vertices has at least `c - 2`
    /// triangles (a disc; each hole would add two, not counted here), and every
    /// piece at least one.
    pub min_triangles: usize,
}

/// The [`OutlineBound`] of `mesh`. A reservoir layer's outline follows the cell
/// edges of its active region, a staircase in (i, j): a budget below
/// `min_triangles` must cut corners of it, moving those outline lines by a cell,
/// whatever the simplifier.
pub fn outline_bound(mesh: &SurfaceMesh) -> OutlineBound {
    let vt = VertexTriangles::new(mesh.vertex_count(), &mesh.triangles);
    let adjacency = triangle_adjacency(&mesh.triangles, &vt);
    outline_bound_of(mesh, &vt, &adjacency, &components(mesh))
}

/// [`outline_bound`] of `mesh` with its vertex triangles, triangle adjacency and the
/// [`components`] of its triangles.
pub(crate) fn outline_bound_of(
    mesh: &SurfaceMesh,
    vt: &VertexTriangles,
    adjacency: &[[u32; 3]],
    labels: &[u32],
) -> OutlineBound {
    let n = mesh.vertex_count();
    // The outline neighbours of every vertex (edges with no single neighbour).
    let mut ends = vec![[NONE; 2]; n];
    let mut degree = vec![0usize; n];
    for (tri, across) in mesh.triangles.iter().zip(adjacency) {
        for k in 0..3 {
            if across[k] != NONE {
                continue;
            }
            let (p, q) = (tri[(k + 1) % 3] as usize, tri[(k + 2) % 3] as usize);
            for (v, w) in [(p, q), (q, p)] {
                if degree[v] < 2 {
                    ends[v][degree[v]] = w as u32;
                }
                degree[v] += 1;
            }
        }
    }
    let uv = |v: usize| mesh.texcoords[v].map(f64::from);
    let is_corner = |v: usize| match degree[v] {
        0 => false,
        2 => {
            let (a, b) = (uv(ends[v][0] as usize), uv(ends[v][1] as usize));
            let p = uv(v);
            let len = |x: [f64; 2]| ((x[0] - p[0]).powi(2) + (x[1] - p[1]).powi(2)).sqrt();
            cross2(a, p, b).abs() > 1e-9 * len(a) * len(b)
        }
        _ => true,
    };
    let pieces = labels.iter().map(|&l| l as usize + 1).max().unwrap_or(0);
    let mut corners = vec![0usize; pieces];
    for v in (0..n).filter(|&v| is_corner(v)) {
        if let Some(&t) = vt.of(v as u32).first() {
            corners[labels[t as usize] as usize] += 1;
        }
    }
    OutlineBound {
        corners: corners.iter().sum(),
        min_triangles: corners.iter().map(|&c| c.max(3) - 2).sum(),
    }
}

/// A square surface of `cells` x `cells` cells of 10, gently curved (by 3 up and
/// down over 40 to 60), for tests of what decimation leaves.
#[cfg(test)]
pub(crate) fn curved(cells: usize) -> SurfaceMesh {
    SurfaceMesh::structured(cells, cells, |i, j| {
        let (x, y) = (i as f32 * 10.0, j as f32 * 10.0);
        [x, y, 3.0 * (x / 40.0).sin() * (y / 60.0).cos()]
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Options, decimate};

    #[test]
    fn a_stray_corner_leaves_the_rest_of_a_surface_decimated_as_without_it() {
        let sound = curved(40);
        let measured = |mesh: &SurfaceMesh| {
            let options = Options {
                z_scale: 5.0,
                ..Options::fraction(mesh, 0.1)
            };
            let d = decimate(mesh, &options).unwrap();
            deviation(mesh, &d.mesh, &d.home, 2, 5.0)
        };
        let without = measured(&sound);
        // Corners of triangles that every sampling of the edges takes (every third,
        // every seventh), on the outline and inside, at a depth as corrupt as a file's
        // can be.
        for t in [21 * 3, 21 * 40] {
            let mut stray = sound.clone();
            let corner = stray.triangles[t][0] as usize;
            stray.positions[corner][2] = 1e11;
            let with = measured(&stray);
            // Left out: the samples of the cell edges at the stray corner, 2 each.
            assert!(
                with.vertical < 2.0 * without.vertical
                    && with.rms < 2.0 * without.rms
                    && with.samples + 8 >= without.samples,
                "with a stray corner on triangle {t}: {with:?}, without {without:?}"
            );
        }
    }

    #[test]
    fn identical_surfaces_deviate_by_nothing_and_a_lift_is_measured() {
        let mesh = SurfaceMesh::structured(6, 4, |i, j| {
            [i as f32 * 10.0, j as f32 * 10.0, (i + j) as f32]
        });
        let home: Vec<u32> = crate::Reference::new(&mesh)
            .unwrap()
            .vertex_triangle
            .clone();
        let same = deviation(&mesh, &mesh, &home, 3, 1.0);
        assert!(same.max < 1e-9, "{same:?}");
        // 6 x 4 cells have 6 x 5 edges along i and 7 x 4 along j; 3 samples each.
        assert_eq!(same.samples, 3 * (6 * 5 + 7 * 4));
        let mut lifted = mesh.clone();
        lifted.positions.iter_mut().for_each(|p| p[2] += 2.0);
        let d = deviation(&mesh, &lifted, &home, 3, 5.0);
        assert!(
            (d.max - 10.0).abs() < 1e-6 && (d.rms - 10.0).abs() < 1e-6,
            "{d:?}"
        );
        assert_eq!(d.outside, 0);
    }

    #[test]
    fn large_surfaces_are_measured_on_the_pool_alike() {
        // 130 x 130 cells: 34 060 cell edges, over the sequential limit.
        let mesh = SurfaceMesh::structured(130, 130, |i, j| {
            [i as f32 * 10.0, j as f32 * 10.0, (i * j) as f32 * 0.01]
        });
        let home = crate::Reference::new(&mesh)
            .unwrap()
            .vertex_triangle
            .clone();
        let lines = GridLines::of(&mesh, 2);
        assert!(lines.edges.len() >= PARALLEL_EDGES);
        let mut lifted = mesh.clone();
        lifted.positions.iter_mut().for_each(|p| p[2] += 2.0);
        let d = lines.deviation(&lifted, &home, 5.0);
        assert_eq!(d.samples, 2 * 2 * 130 * 131);
        assert!(
            (d.max - 10.0).abs() < 1e-4 && (d.rms - 10.0).abs() < 1e-4,
            "{d:?}"
        );
    }

    #[test]
    fn large_surfaces_measure_the_same_on_any_pool() {
        let mesh = curved(130);
        let lines = GridLines::of(&mesh, 2);
        assert!(lines.edges.len() >= PARALLEL_EDGES);
        let simplified = decimate(
            &mesh,
            &Options {
                target_triangles: 2_000,
                ..Options::default()
            },
        )
        .unwrap();
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| lines.deviation(&simplified.mesh, &simplified.home, 5.0))
        };
        let one = on(1);
        assert!(one.rms > 0.0, "{one:?}");
        for threads in [2, 3, 8] {
            let other = on(threads);
            assert_eq!(
                (one.rms.to_bits(), one.max.to_bits(), one.samples),
                (other.rms.to_bits(), other.max.to_bits(), other.samples),
                "{threads} threads: {other:?} against {one:?}"
            );
        }
    }

    #[test]
    fn located_samples_measure_as_the_grid_lines_do() {
        for cells in [20, 130] {
            let mesh = curved(cells);
            let lines = GridLines::of(&mesh, 2);
            let options = Options {
                target_triangles: 40,
                z_scale: 5.0,
                ..Options::default()
            };
            let mut simplified = decimate(&mesh, &options).unwrap();
            // A triangle lost: its samples are drawn outside, at the nearest point.
            simplified.mesh.triangles.remove(7);
            let (m, home) = (&simplified.mesh, &simplified.home);
            let streamed = lines.deviation(m, home, 5.0);
            let located = lines.locate(m, home, 5.0);
            let measured = located.deviation(m, 5.0);
            assert!(streamed.outside > 0, "{streamed:?}");
            assert_eq!(
                located.samples.len() + located.missed,
                2 * 2 * cells * (cells + 1)
            );
            assert_eq!(
                (measured.samples, measured.outside, measured.missed),
                (streamed.samples, streamed.outside, streamed.missed)
            );
            assert!((measured.rms - streamed.rms).abs() <= 1e-9 * streamed.rms);
            assert!((measured.max - streamed.max).abs() <= 1e-9 * streamed.max);
        }
    }

    #[test]
    fn where_two_sides_draw_a_sample_it_is_located_on_the_one_measured() {
        // A simplified surface with two sheets of the same texture coordinates in one
        // piece (as a fault's two sides are): one 10 across, one 5 up. With z scaled
        // by 5 the first is the nearer (10 against 25), unscaled the second.
        let original =
            SurfaceMesh::structured(2, 2, |i, j| [i as f32 * 10.0, j as f32 * 10.0, 0.0]);
        let mut simplified = original.clone();
        simplified.positions.iter_mut().for_each(|p| p[0] += 10.0);
        let mut up = original.clone();
        up.positions.iter_mut().for_each(|p| p[2] += 5.0);
        simplified.append(&up);
        let home = crate::Reference::new(&original)
            .unwrap()
            .vertex_triangle
            .clone();
        let home = [home.clone(), home].concat();
        let lines = GridLines::of(&original, 2);
        for (z_scale, nearest) in [(5.0, 10.0), (1.0, 5.0)] {
            let streamed = lines.deviation(&simplified, &home, z_scale);
            let located = lines
                .locate(&simplified, &home, z_scale)
                .deviation(&simplified, z_scale);
            assert!((streamed.rms - nearest).abs() < 1e-6, "{streamed:?}");
            assert!((located.rms - nearest).abs() < 1e-6, "{located:?}");
        }
    }

    #[test]
    fn components_split_at_faults() {
        // Two separate quads.
        let mut mesh = SurfaceMesh::structured(1, 1, |i, j| [i as f32, j as f32, 0.0]);
        let other = SurfaceMesh::structured(1, 1, |i, j| [i as f32 + 1.0, j as f32, 5.0]);
        mesh.append(&other);
        assert_eq!(components(&mesh), vec![0, 0, 1, 1]);
        // Simplified as far as it goes, each quad keeps a triangle of its own.
        let d = decimate(&mesh, &Options::default()).unwrap();
        assert_eq!(components(&d.mesh), vec![0, 1]);
    }
    #[test]
    fn outline_bound_counts_the_corners_of_borders_holes_and_steps() {
        let flat = |i: usize, j: usize| [i as f32, j as f32, 0.0];
        // A rectangle: 4 corners, 2 triangles.
        let rect = SurfaceMesh::structured(6, 4, flat);
        let b = outline_bound(&rect);
        assert_eq!((b.corners, b.min_triangles), (4, 2));
        // Without the cell (2, 2): a square hole adds 4 corners.
        let mut holed = SurfaceMesh::structured(6, 6, flat);
        let cell = 2 * 6 + 2;
        holed.triangles.drain(2 * cell..2 * cell + 2);
        assert_eq!(outline_bound(&holed).corners, 8);
        // An L (the top-right 2 x 2 cells of 4 x 4 gone): 6 corners, at least 4
        // triangles; a straight border vertex is no corner.
        let mut l = SurfaceMesh::structured(4, 4, flat);
        let gone = |t: usize| {
            let (i, j) = ((t / 2) % 4, (t / 2) / 4);
            i >= 2 && j >= 2
        };
        l.triangles = (0..l.triangles.len())
            .filter(|&t| !gone(t))
            .map(|t| l.triangles[t])
            .collect();
        let b = outline_bound(&l);
        assert_eq!((b.corners, b.min_triangles), (6, 4));
        // Two pieces: each pays for its own.
        let mut two = SurfaceMesh::structured(3, 3, flat);
        two.append(&SurfaceMesh::structured(2, 5, flat));
        let b = outline_bound(&two);
        assert_eq!((b.corners, b.min_triangles), (8, 4));
    }
}
