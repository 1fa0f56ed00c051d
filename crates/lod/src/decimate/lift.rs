//! The last step: the input's vertices located on the simplified surface, and
//! interior vertices moved along the normal, within their error, to pass through
//! them.

use super::Placement;
use super::collapser::{ALIVE, BOUNDARY, Collapser, DEAD, LOCKED, MOVED};
use super::evaluate::{Choice, Spot};
use super::frame::Frame;
use super::vector::{cross3, dot3, sub3};
use crate::measure::{Located, LocatedSample};
use crate::reference::{NONE, SurfacePoint, barycentric};

/// The input's vertices located on the live triangles
/// ([`Collapser::samples_by_triangle`]).
pub(super) struct InputSamples {
    /// The vertices by triangle, in compressed rows: triangle `t`'s are
    /// `vertices[first[t]..first[t + 1]]`.
    first: Vec<u32>,
    vertices: Vec<u32>,
}

impl InputSamples {
    /// The input vertices on triangle `t`.
    fn of(&self, t: usize) -> &[u32] {
        &self.vertices[self.first[t] as usize..self.first[t + 1] as usize]
    }
}

impl Collapser<'_> {
    /// The live vertex that input vertex `v` was merged into, through the chain of
    /// collapses (shortened on the way), or [`NONE`] for a vertex of no triangle.
    fn representative(&mut self, v: u32) -> u32 {
        let mut r = v;
        while self.current[r as usize] == NONE {
            r = self.merged_into[r as usize];
            if r == NONE {
                return NONE;
            }
        }
        let mut w = v;
        while w != r {
            let next = self.merged_into[w as usize];
            self.merged_into[w as usize] = r;
            w = next;
        }
        let live = self.current[r as usize];
        if self.flags[live as usize] & ALIVE == 0 {
            NONE
        } else {
            live
        }
    }

    /// Texture-space barycentric coordinates of `uv` in live triangle `t`, when it is
    /// inside (up to rounding).
    fn texture_barycentric(&self, t: u32, uv: [f64; 2]) -> Option<[f64; 3]> {
        barycentric(
            self.tris[t as usize].map(|v| self.texcoord[v as usize].map(f64::from)),
            uv,
        )
        .filter(|w| w.iter().all(|&x| x >= -1e-9))
    }

    /// The input's vertices by the live triangle each lies in (texture space). Each is
    /// looked for among the triangles of the live vertex it was merged into, and left
    /// out when in none of them. Needs the vertex lists rebuilt.
    pub(super) fn samples_by_triangle(&mut self) -> InputSamples {
        let input = self.input;
        // Buffers of the passes, done with, hold the samples (fresh ones of the mesh's
        // size would be page-faulted in): per input vertex its triangle (`mark`), the
        // triangles' rows of samples (`scratch.costs`, filled through `scratch.open`)
        // and the samples by triangle (`cheapest`).
        let mut in_triangle = std::mem::take(&mut self.mark);
        in_triangle.clear();
        in_triangle.resize(input.vertex_count(), NONE);
        for o in 0..input.vertex_count() as u32 {
            let r = self.representative(o);
            if r == NONE {
                continue;
            }
            let uv = input.texcoords[o as usize].map(f64::from);
            if let Some(t) = self
                .star(r)
                .iter()
                .copied()
                .find(|&t| self.uses(t, r) && self.texture_barycentric(t, uv).is_some())
            {
                in_triangle[o as usize] = t;
            }
        }
        let mut first = std::mem::take(&mut self.scratch.costs);
        first.clear();
        first.resize(self.tris.len() + 1, 0);
        for &t in in_triangle.iter().filter(|&&t| t != NONE) {
            first[t as usize + 1] += 1;
        }
        for t in 1..first.len() {
            first[t] += first[t - 1];
        }
        let mut cursor = std::mem::take(&mut self.scratch.open);
        cursor.clear();
        cursor.extend_from_slice(&first);
        let mut samples = std::mem::take(&mut self.cheapest);
        samples.clear();
        samples.resize(first[self.tris.len()] as usize, 0);
        for (o, &t) in in_triangle.iter().enumerate().filter(|&(_, &t)| t != NONE) {
            samples[cursor[t as usize] as usize] = o as u32;
            cursor[t as usize] += 1;
        }
        InputSamples {
            first,
            vertices: samples,
        }
    }

    /// [`Options::lift`], no vertex's quadric error going over `max_cost`. The samples
    /// are the input's vertices ([`Collapser::samples_by_triangle`]; a few are left
    /// out, `docs/performance.md`). Each interior vertex in turn moves
    /// along the original's normal at its texture point (that of its home triangle)
    /// to where the simplified surface, linear in its triangles, is nearest the
    /// samples in them (one Gauss-Seidel sweep of the least-squares fit), when that
    /// stays within the vertex's error of the original and folds nothing.
    pub(super) fn lift(&mut self, max_cost: f64, samples: &InputSamples) {
        let input = self.input;
        let mesh = self.reference.mesh();
        for v in 0..self.flags.len() as u32 {
            let (f, home) = (self.flags[v as usize], self.home[v as usize]);
            if f & ALIVE == 0 || f & (BOUNDARY | LOCKED) != 0 || home == NONE {
                continue;
            }
            let c = mesh.triangles[home as usize]
                .map(|w| Frame::of_mesh(mesh, w as usize, &self.frame));
            let n = cross3(sub3(&c[1], &c[0]), sub3(&c[2], &c[0]));
            let len = dot3(n, n).sqrt();
            if len == 0.0 {
                continue;
            }
            let normal = [n[0] / len, n[1] / len, n[2] / len];
            // Least squares along the normal: each sample's distance to the surface,
            // and how much of the vertex's move reaches it (its barycentric weight).
            let (mut num, mut den) = (0.0, 0.0);
            for &t in self.star(v) {
                if !self.uses(t, v) {
                    continue;
                }
                let tri = self.tris[t as usize];
                let k = tri.iter().position(|&w| w == v).unwrap_or(0);
                let corners = tri.map(|w| self.x[w as usize]);
                for &o in samples.of(t as usize) {
                    let uv = input.texcoords[o as usize].map(f64::from);
                    let Some(w) = self.texture_barycentric(t, uv) else {
                        continue;
                    };
                    let at = Frame::of_mesh(input, o as usize, &self.frame);
                    let off: f64 = (0..3)
                        .map(|a| {
                            let surface =
                                w[0] * corners[0][a] + w[1] * corners[1][a] + w[2] * corners[2][a];
                            (at[a] - surface) * normal[a]
                        })
                        .sum();
                    num += w[k] * off;
                    den += w[k] * w[k];
                }
            }
            if den <= 0.0 {
                continue;
            }
            let step = num / den;
            if step * step <= self.tie {
                continue;
            }
            // The lift counts from the original's point of the vertex's texture
            // coordinates: where the vertex is, unless an earlier lift (a level of a
            // hierarchy is decimated from the one below) or `Placement::Optimal` put it
            // off the surface.
            // Around the vertex's own point.
            let q = self.q[v as usize].widened();
            let x = self.x[v as usize];
            let uv = self.texcoord[v as usize];
            let Some(foot) = self.place(v, v, Choice::Point { uv, lift: 0.0 }) else {
                continue;
            };
            let bound = q.error_at_origin().sqrt();
            let lift = (dot3(sub3(&x, &foot.x), normal) + step).clamp(-bound, bound);
            let p = match self.options.placement {
                // The vertex keeps its texture point and scalar and moves along the
                // normal there.
                Placement::Surface => {
                    let i = v as usize;
                    let at = foot.position.map(f64::from);
                    let position = [
                        (at[0] + lift * normal[0]) as f32,
                        (at[1] + lift * normal[1]) as f32,
                        (at[2] + lift * normal[2] / self.frame.z_scale) as f32,
                    ];
                    let (texcoord, scalar) = (self.texcoord[i], self.scalar[i]);
                    let x = self.frame.point(
                        position.map(f64::from),
                        texcoord.map(f64::from),
                        f64::from(scalar),
                    );
                    Spot {
                        x,
                        position,
                        texcoord,
                        scalar,
                        home,
                    }
                }
                // It takes the texture point nearest it, as its placement did.
                Placement::Optimal => {
                    let Some(p) = self.place(v, v, Choice::point(uv.map(f64::from), lift)) else {
                        continue;
                    };
                    p
                }
            };
            let exact = q.error(&self.from(v, &p.x));
            if exact <= max_cost
                && self
                    .star(v)
                    .iter()
                    .all(|&t| !self.uses(t, v) || self.keeps_orientation(t, v, &p))
            {
                let i = v as usize;
                self.max_cost = self.max_cost.max(exact);
                self.q[i] = q.around(&self.from(v, &p.x));
                self.x[i] = p.x;
                self.position[i] = p.position;
                self.texcoord[i] = p.texcoord;
                self.scalar[i] = p.scalar;
                self.home[i] = p.home;
                self.flags[i] |= MOVED;
            }
        }
    }

    /// The input's vertices, the nodes of its grid lines, where the result draws
    /// their texture coordinates ([`Collapser::samples_by_triangle`]: no search of
    /// the whole surface), each with its position on the input as target, in the
    /// result's triangle numbering ([`Collapser::finish`] keeps the live triangles in
    /// order). Vertices not found there are left out, not counted as missed: the
    /// result has not lost them.
    pub(super) fn located(&self, samples: &InputSamples) -> Located {
        let input = self.input;
        // The result's number of each live triangle.
        let mut live = 0;
        let kept: Vec<u32> = self
            .tris
            .iter()
            .map(|tri| {
                let k = live;
                live += u32::from(tri[0] != DEAD);
                k
            })
            .collect();
        let mut out = Vec::with_capacity(samples.vertices.len());
        for (t, &triangle) in kept.iter().enumerate() {
            for &o in samples.of(t) {
                let o = o as usize;
                let uv = input.texcoords[o].map(f64::from);
                if let Some(barycentric) = self.texture_barycentric(t as u32, uv) {
                    out.push(LocatedSample {
                        point: SurfacePoint {
                            triangle,
                            barycentric,
                        },
                        target: input.positions[o].map(f64::from),
                        inside: true,
                    });
                }
            }
        }
        Located {
            samples: out,
            missed: 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::decimate_prepared;
    use crate::reference::SurfacePoint;
    use crate::{Options, Reference};

    #[test]
    fn the_grid_nodes_are_located_where_a_search_of_the_whole_surface_finds_them() {
        use crate::measure::{GridLines, point_position};
        use std::collections::HashMap;
        use strata_grid::synth::{SynthParams, generate};
        use strata_grid::{Face, Surfaces, layer_surfaces};

        let grid = generate(&SynthParams {
            nx: 40,
            ny: 30,
            nz: 1,
            faults: 3,
            seed: 7,
        })
        .unwrap();
        let mesh = layer_surfaces(
            &grid,
            Face::Top,
            &Surfaces::layer(0, grid.display_origin()).property(Some("PORO")),
        )
        .unwrap();
        let (reference, vt) = Reference::with_vertex_triangles(&mesh).unwrap();
        let options = Options {
            z_scale: 5.0,
            ..Options::fraction(&mesh, 0.1)
        };
        let (out, located) = decimate_prepared(&reference, vt, &options, 0.0, true).unwrap();
        let located = located.expect("located samples");
        assert_eq!(located.missed, 0);
        // The grid lines sampled at their nodes (the first end of each cell edge),
        // each found by searching the whole result by texture coordinates.
        let searched = GridLines::of(&mesh, 1).locate(&out.mesh, &out.home, 5.0);
        let key = |p: [f64; 3]| p.map(f64::to_bits);
        let found: HashMap<_, _> = searched
            .samples
            .iter()
            .filter(|s| s.inside)
            .map(|s| (key(s.target), s.point))
            .collect();
        let texcoord = |p: &SurfacePoint| {
            let tri = out.mesh.triangles[p.triangle as usize];
            std::array::from_fn::<f64, 2, _>(|a| {
                (0..3)
                    .map(|k| p.barycentric[k] * f64::from(out.mesh.texcoords[tri[k] as usize][a]))
                    .sum()
            })
        };
        let extent = mesh.bounds().map_or(0.0, |(lo, hi)| {
            (0..3)
                .map(|a| f64::from(hi[a] - lo[a]).powi(2))
                .sum::<f64>()
                .sqrt()
        });
        // Texture coordinates the input has at more than one vertex: a fault's two
        // sides along its trace.
        let mut at_texcoord: HashMap<[u32; 2], usize> = HashMap::new();
        let mut texcoord_of_node = HashMap::new();
        for (p, uv) in mesh.positions.iter().zip(&mesh.texcoords) {
            let uv = uv.map(f32::to_bits);
            *at_texcoord.entry(uv).or_default() += 1;
            texcoord_of_node.insert(key(p.map(f64::from)), uv);
        }
        let mut compared = 0;
        for s in &located.samples {
            assert!(s.inside);
            let Some(there) = found.get(&key(s.target)) else {
                continue;
            };
            compared += 1;
            // The same texture coordinates; on a fault whose sides the result joins
            // around its tip, the search may take the other side there (the one
            // nearer the sample), this the sample's own.
            let (a, b) = (texcoord(&s.point), texcoord(there));
            assert!(
                (a[0] - b[0]).abs() + (a[1] - b[1]).abs() < 1e-9,
                "{a:?} against {b:?}"
            );
            let (here, there) = (
                point_position(&out.mesh, &s.point),
                point_position(&out.mesh, there),
            );
            let d = (0..3)
                .map(|a| (here[a] - there[a]).powi(2))
                .sum::<f64>()
                .sqrt();
            let on_fault = at_texcoord[&texcoord_of_node[&key(s.target)]] > 1;
            assert!(
                d <= 1e-9 * extent || on_fault,
                "node {:?} (texture {a:?}, off any fault) located {d} from where the search \
                 put it",
                s.target
            );
        }
        let (ours, theirs) = (located.samples.len(), found.len());
        // 1234 of the search's 1243 with vertex values averaged over the cells around
        // each node; 1229 since border nodes' values are extrapolated (the simplified
        // surface, which weighs the values, differs near the outline).
        assert!(
            compared * 100 >= 98 * theirs.max(ours),
            "{compared} of {ours} located nodes are among the {theirs} the search found"
        );
    }
}
