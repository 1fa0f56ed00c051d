//! Making a collapse, and keeping the vertex-to-triangle lists and the dense
//! numbering of the live vertices up to date between passes.

use super::collapser::{ALIVE, Collapser, DEAD, MOVED};
use super::evaluate::Spot;
use crate::quadric::Local;
use crate::reference::NONE;

/// A pass starts by renumbering the live vertices densely ([`Collapser::compact`])
/// when fewer than this fraction (numerator, denominator) of the vertex slots are
/// live: later passes then stream through arrays of live data only, instead of one
/// live vertex in every few cache lines. On generated layers to 10 %, renumbering
/// below 1/2 live was faster than never, and below 0.7 or 0.9 (alike) faster still
/// (`docs/performance.md`, "Decimation internals").
pub(super) const COMPACT_BELOW: (usize, usize) = (7, 10);

impl Collapser<'_> {
    /// Moves `gone` onto `keep`, which takes placement `p` and `q`, the sum of both
    /// ends' quadrics around `p`.
    pub(super) fn collapse(&mut self, keep: u32, gone: u32, q: Local, p: &Spot, moved: bool) {
        let (gs, ge) = (
            self.start[gone as usize] as usize,
            self.start[gone as usize + 1] as usize,
        );
        for i in gs..ge {
            let t = self.refs[i] as usize;
            if !self.uses(t as u32, gone) {
                continue;
            }
            if self.tris[t].contains(&keep) {
                self.tris[t][0] = DEAD;
                self.live -= 1;
            } else {
                for c in self.tris[t].iter_mut() {
                    if *c == gone {
                        *c = keep;
                    }
                }
            }
        }
        let (k, g) = (keep as usize, gone as usize);
        self.q[k] = q;
        self.x[k] = p.x;
        self.position[k] = p.position;
        self.texcoord[k] = p.texcoord;
        self.scalar[k] = p.scalar;
        self.home[k] = p.home;
        if moved {
            self.flags[k] |= MOVED;
        }
        self.flags[g] &= !ALIVE;
        self.live_vertices -= 1;
        let gone_input = self.original[g] as usize;
        self.merged_into[gone_input] = self.original[k];
        self.current[gone_input] = NONE;
        // `keep`'s list now misses `gone`'s triangles: leave it alone until rebuilt.
        self.busy[k] = true;
        self.busy[g] = true;
        self.collapses += 1;
    }

    /// Renumbers the live vertices and triangles densely, in their order, once fewer
    /// than [`COMPACT_BELOW`] of the vertex slots are live. Order is kept, so the
    /// result is the same, bit for bit, as without it.
    pub(super) fn compact(&mut self) {
        let n = self.flags.len();
        let (num, den) = self.compact_below;
        if den * self.live_vertices >= num * n {
            return;
        }
        let mut new_index = std::mem::take(&mut self.mark);
        // The survivors in order, so that each array moves without a branch per
        // vertex (a third of them died, scattered: the branch mispredicts). They go
        // in the pass's list of open candidates, which is not in use yet.
        let mut survivors = std::mem::take(&mut self.scratch.open);
        survivors.clear();
        survivors.reserve(self.flags.len());
        for (v, f) in self.flags.iter().enumerate() {
            if f & ALIVE != 0 {
                new_index[v] = survivors.len() as u32;
                survivors.push(v as u32);
            } else {
                new_index[v] = NONE;
                // Unused input vertices (in no triangle) leave too.
                self.current[self.original[v] as usize] = NONE;
            }
        }
        let m = survivors.len();
        fn squeeze<T: Copy>(data: &mut Vec<T>, survivors: &[u32]) {
            for (to, &from) in survivors.iter().enumerate() {
                data[to] = data[from as usize];
            }
            data.truncate(survivors.len());
        }
        squeeze(&mut self.x, &survivors);
        squeeze(&mut self.q, &survivors);
        squeeze(&mut self.position, &survivors);
        squeeze(&mut self.texcoord, &survivors);
        squeeze(&mut self.scalar, &survivors);
        squeeze(&mut self.home, &survivors);
        squeeze(&mut self.flags, &survivors);
        squeeze(&mut self.original, &survivors);
        if !self.twin.is_empty() {
            squeeze(&mut self.twin, &survivors);
            // Twins go together: a live vertex's twin is live.
            for t in self.twin.iter_mut().filter(|t| **t != NONE) {
                *t = new_index[*t as usize];
            }
        }
        self.scratch.open = survivors;
        for (v, &o) in self.original.iter().enumerate() {
            self.current[o as usize] = v as u32;
        }
        let mut t_new = 0;
        for t in 0..self.tris.len() {
            let tri = self.tris[t];
            if tri[0] != DEAD {
                self.tris[t_new] = tri.map(|v| new_index[v as usize]);
                self.uv_sign[t_new] = self.uv_sign[t];
                t_new += 1;
            }
        }
        self.tris.truncate(t_new);
        self.uv_sign.truncate(t_new);
        self.busy.truncate(m);
        self.cheapest.truncate(m);
        self.start.truncate(m + 1);
        new_index.truncate(m);
        new_index.fill(0);
        self.mark = new_index;
    }

    /// Rebuilds the vertex lists from the live triangles, into the same buffers.
    pub(super) fn rebuild_lists(&mut self) {
        self.start.iter_mut().for_each(|s| *s = 0);
        for tri in self.tris.iter().filter(|t| t[0] != DEAD) {
            for &v in tri {
                self.start[v as usize + 1] += 1;
            }
        }
        for v in 1..self.start.len() {
            self.start[v] += self.start[v - 1];
        }
        let total = self.start[self.start.len() - 1] as usize;
        self.refs.clear();
        self.refs.resize(total, 0);
        // Fill back to front so that `start` ends where it began.
        for (t, tri) in self.tris.iter().enumerate().rev() {
            if tri[0] == DEAD {
                continue;
            }
            for &v in tri {
                let s = &mut self.start[v as usize + 1];
                *s -= 1;
                self.refs[*s as usize] = t as u32;
            }
        }
        // Now start[v + 1] holds v's first entry: shift down by one vertex.
        self.start.rotate_left(1);
        let n = self.start.len();
        self.start[n - 1] = total as u32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Options, Reference};
    use strata_grid::SurfaceMesh;

    #[test]
    fn renumbering_the_live_vertices_changes_nothing() {
        // A bumpy grid with a hole, so that vertices of no triangle and boundaries are
        // renumbered too; the fit follows the merges across renumberings.
        let mut mesh = SurfaceMesh::structured(60, 60, |i, j| {
            let (x, y) = (i as f32, j as f32);
            [10.0 * x, 10.0 * y, 6.0 * (0.3 * x).sin() * (0.2 * y).cos()]
        });
        let hole = |v: u32| {
            let p = mesh.positions[v as usize];
            (200.0..=300.0).contains(&p[0]) && (250.0..=350.0).contains(&p[1])
        };
        let kept: Vec<[u32; 3]> = (mesh.triangles.iter().copied())
            .filter(|t| !t.iter().all(|&v| hole(v)))
            .collect();
        mesh.triangles = kept;
        mesh.cell_faces.clear();
        let options = Options::fraction(&mesh, 0.1);
        let reference = Reference::new(&mesh).unwrap();
        let home = reference.vertex_triangle.clone();
        let run = |compact_below: (usize, usize)| {
            let mut collapser =
                Collapser::new(&mesh, &home, &reference, &[], &options, None).unwrap();
            collapser.compact_below = compact_below;
            collapser.run(false).unwrap().0
        };
        let (never, always) = (run((0, 1)), run((1, 1)));
        assert!(never.mesh.triangle_count() <= options.target_triangles);
        assert_eq!(never.mesh.positions, always.mesh.positions);
        assert_eq!(never.mesh.texcoords, always.mesh.texcoords);
        assert_eq!(never.mesh.triangles, always.mesh.triangles);
        assert_eq!(never.source, always.source);
        assert_eq!(never.home, always.home);
        assert_eq!(never.error, always.error);
        // The fit moved vertices (else it would not test the merges' bookkeeping).
        assert!(always.source.iter().filter(|s| s.is_none()).count() > 10);
    }
}
