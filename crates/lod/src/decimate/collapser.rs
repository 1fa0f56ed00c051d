//! The state of a decimation in progress, per vertex and per triangle, the reads every
//! stage shares, and the run from first pass to the simplified mesh.

use std::time::Instant;

use strata_grid::SurfaceMesh;

use super::evaluate::Candidate;
use super::frame::Frame;
use super::passes::{MAX_PASSES, Scratch, next_floor};
use super::{Decimated, Options, Timings};
use crate::cover::CellCover;
use crate::measure::Located;
use crate::quadric::{Local, Point, Quadric};
use crate::reference::{NONE, Reference};
use crate::{MaybeIndex, Result};

/// Per-vertex flags.
pub(super) const ALIVE: u8 = 1;
pub(super) const BOUNDARY: u8 = 2;
pub(super) const LOCKED: u8 = 4;
/// The vertex was placed by a collapse (its data is no longer the input's).
pub(super) const MOVED: u8 = 8;
/// A boundary vertex at the same position as one other, its twin, on another
/// boundary ([`super::setup::seam_twins`]).
pub(super) const SEAM: u8 = 16;

/// Marks a dead triangle in its first corner.
pub(super) const DEAD: u32 = u32::MAX;

/// A decimation in progress: what every stage reads and changes, in flat arrays that
/// the passes stream through.
pub(super) struct Collapser<'a> {
    /// The mesh being simplified: its vertices are the samples of the final fit.
    pub(super) input: &'a SurfaceMesh,
    pub(super) reference: &'a Reference<'a>,
    pub(super) options: &'a Options,
    pub(super) frame: Frame,
    pub(super) has_scalars: bool,
    /// The input's cells, with [`Options::cover`].
    pub(super) cover: Option<CellCover>,
    // Per vertex.
    /// The joint point, derivable from `position`, `texcoord` and `scalar` (it is
    /// exactly `Frame::point` of them) but kept: fetching it from one array was
    /// measured faster than deriving it from three, in both the evaluate and the
    /// collapse stage (`docs/performance.md`, "Decimation internals").
    pub(super) x: Vec<Point>,
    /// Each written around its vertex's `x` ([`Local`]), in single precision.
    pub(super) q: Vec<Local>,
    pub(super) position: Vec<[f32; 3]>,
    pub(super) texcoord: Vec<[f32; 2]>,
    pub(super) scalar: Vec<f32>,
    pub(super) home: Vec<u32>,
    pub(super) flags: Vec<u8>,
    /// [`super::setup::seam_twins`].
    pub(super) twin: Vec<u32>,
    /// Set on both ends of a collapse: left alone for the rest of the pass.
    pub(super) busy: Vec<bool>,
    /// Per vertex, in a round of local minima, the cheapest open candidate at it.
    pub(super) cheapest: Vec<u32>,
    /// Per vertex, the input vertex it began as: passes renumber the live vertices
    /// ([`Collapser::compact`]).
    pub(super) original: Vec<u32>,
    // Per input vertex.
    /// Its index now, or [`NONE`] once it is removed.
    pub(super) current: Vec<u32>,
    /// Per removed input vertex, the input vertex it was collapsed onto: the way to a
    /// live vertex near where it was, for the final fit.
    pub(super) merged_into: Vec<u32>,
    /// [`COMPACT_BELOW`].
    pub(super) compact_below: (usize, usize),
    /// Rounds of local minima per pass: [`LOCAL_ROUNDS`] on meshes of more than
    /// [`LOCAL_VERTICES`], else none.
    pub(super) rounds: usize,
    /// Buffers of a pass, kept between passes: fresh ones of this size would be
    /// page-faulted in every pass.
    pub(super) scratch: Scratch,
    // Per triangle.
    pub(super) tris: Vec<[u32; 3]>,
    pub(super) uv_sign: Vec<i8>,
    pub(super) live: usize,
    /// Vertices in a live triangle.
    pub(super) live_vertices: usize,
    /// See [`Decimated::outline_vertices`].
    pub(super) outline_vertices: usize,
    /// Vertex-to-triangle lists of live triangles, in compressed rows, rebuilt at the
    /// start of each pass. During a pass a list can hold triangles that died or no
    /// longer use the vertex (they are skipped), and never misses one, except for the
    /// busy vertices, which are not looked at again in the pass.
    pub(super) start: Vec<u32>,
    pub(super) refs: Vec<u32>,
    pub(super) candidates: Vec<Candidate>,
    /// Costs below this are ties (rounding noise on flat, affine regions).
    pub(super) tie: f64,
    /// Bound of the collapses [`Options::free_past_target`] makes.
    pub(super) free_cost: f64,
    pub(super) max_cost: f64,
    pub(super) collapses: usize,
    /// Per vertex, the stamp of the last link check that marked it.
    pub(super) mark: Vec<u32>,
    pub(super) stamp: u32,
    pub(super) timings: Timings,
}

impl Collapser<'_> {
    #[inline]
    pub(super) fn flag(&self, v: u32, f: u8) -> bool {
        self.flags[v as usize] & f != 0
    }

    #[inline]
    pub(super) fn star(&self, v: u32) -> &[u32] {
        &self.refs[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }

    /// Is triangle `t` alive and does it use `v`?
    #[inline]
    pub(super) fn uses(&self, t: u32, v: u32) -> bool {
        let tri = &self.tris[t as usize];
        tri[0] != DEAD && tri.contains(&v)
    }

    /// Number of live triangles with edge `a b`, and one of them.
    #[inline]
    pub(super) fn edge_triangles(&self, a: u32, b: u32) -> (usize, u32) {
        let (mut n, mut first) = (0, NONE);
        for &t in self.star(a) {
            if self.uses(t, a) && self.tris[t as usize].contains(&b) {
                if n == 0 {
                    first = t;
                }
                n += 1;
            }
        }
        (n, first)
    }

    /// Derivative of the joint point along texture coordinates in triangle `t` (its
    /// linear interpolation), as two columns; `None` when the triangle has no texture
    /// area.
    pub(super) fn jacobian(&self, t: u32) -> Option<[Point; 2]> {
        let tri = self.tris[t as usize];
        let [x0, x1, x2] = tri.map(|v| self.x[v as usize]);
        let [u0, u1, u2] = tri.map(|v| self.texcoord[v as usize].map(f64::from));
        let (du1, du2) = (
            [u1[0] - u0[0], u1[1] - u0[1]],
            [u2[0] - u0[0], u2[1] - u0[1]],
        );
        let det = du1[0] * du2[1] - du2[0] * du1[1];
        if det.abs() < 1e-12 {
            return None;
        }
        let inv = 1.0 / det;
        let e1: Point = std::array::from_fn(|k| x1[k] - x0[k]);
        let e2: Point = std::array::from_fn(|k| x2[k] - x0[k]);
        Some([
            std::array::from_fn(|k| (e1[k] * du2[1] - e2[k] * du1[1]) * inv),
            std::array::from_fn(|k| (e2[k] * du1[0] - e1[k] * du2[0]) * inv),
        ])
    }

    /// The sum of the quadrics of `a` and `b`, written around `a`'s joint point: the
    /// points it is evaluated at are then [`Collapser::from`] `a`, of the size of an
    /// edge, and only `b`'s quadric moves.
    #[inline]
    pub(super) fn pair(&self, a: u32, b: u32) -> Quadric {
        let offset = self.from(b, &self.x[a as usize]);
        self.q[a as usize].plus_moved(&self.q[b as usize], &offset)
    }

    /// Joint point `x` relative to `v`'s.
    #[inline]
    pub(super) fn from(&self, v: u32, x: &Point) -> Point {
        let o = &self.x[v as usize];
        std::array::from_fn(|k| x[k] - o[k])
    }

    /// The passes, then [`Options::lift`]; with `locate_input`, also the input's
    /// vertices located on the result ([`Collapser::located`]).
    pub(super) fn run(mut self, locate_input: bool) -> Result<(Decimated, Option<Located>)> {
        let target = self.options.target_triangles;
        let max_cost = f64::from(self.options.max_error).powi(2);
        let mut floor = 0.0;
        for _ in 0..MAX_PASSES {
            if self.live <= target {
                break;
            }
            let goal = (self.live - target).div_ceil(2);
            let (made, own) = self.pass(target, goal, max_cost, floor);
            if made == 0 && floor == f64::INFINITY {
                break;
            }
            floor = next_floor(made, goal, own);
        }
        if self.options.free_past_target {
            let free = max_cost.min(self.free_cost);
            for _ in 0..MAX_PASSES {
                let goal = self.live.div_ceil(2);
                if self.pass(0, goal, free, 0.0).0 == 0 {
                    break;
                }
            }
        }
        let mut located = None;
        if self.options.lift || locate_input {
            let start = Instant::now();
            self.rebuild_lists();
            // The lift moves vertices along the normal only: texture coordinates, and
            // so which triangle each sample lies in, stay.
            let samples = self.samples_by_triangle();
            if self.options.lift {
                self.lift(max_cost, &samples);
            }
            if locate_input {
                located = Some(self.located(&samples));
            }
            self.timings.lift = start.elapsed().as_secs_f64();
        }
        Ok((self.finish(), located))
    }

    fn finish(self) -> Decimated {
        let n = self.flags.len();
        let mut remap = vec![NONE; n];
        let mut out = SurfaceMesh::with_origin(self.reference.mesh().origin);
        let mut source = Vec::new();
        let mut home = Vec::new();
        let mut used = vec![false; n];
        for tri in self.tris.iter().filter(|t| t[0] != DEAD) {
            for &v in tri {
                used[v as usize] = true;
            }
        }
        for v in (0..n).filter(|&v| used[v]) {
            remap[v] = out.positions.len() as u32;
            out.positions.push(self.position[v]);
            out.texcoords.push(self.texcoord[v]);
            if self.has_scalars {
                out.scalars.push(self.scalar[v]);
            }
            source.push(if self.flags[v] & MOVED != 0 {
                MaybeIndex::NONE
            } else {
                MaybeIndex::some(self.original[v])
            });
            home.push(self.home[v]);
        }
        out.triangles = self
            .tris
            .iter()
            .filter(|t| t[0] != DEAD)
            .map(|t| t.map(|v| remap[v as usize]))
            .collect();
        Decimated {
            mesh: out,
            source,
            home,
            error: self.max_cost.sqrt() as f32,
            collapses: self.collapses,
            outline_vertices: self.outline_vertices,
            cover: self.cover,
            timings: self.timings,
        }
    }
}
