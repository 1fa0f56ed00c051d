//! Whether a collapse may be made: the link condition, orientation of the normal and
//! of the texture image, boundaries sliding only along themselves (and outward with a
//! cover), and seams collapsing with their twins.

use super::collapser::{ALIVE, BOUNDARY, Collapser, LOCKED, SEAM};
use super::evaluate::{Choice, Spot};
use super::vector::{cross3, dot3, sub3};
use crate::quadric::Local;
use crate::reference::{NONE, cross2};

impl Collapser<'_> {
    /// Would moving `keep` (when `keep_moves`) and `gone` onto `p`, removing the
    /// triangles with both, keep the surface manifold (the link condition: the two
    /// ends share no neighbour but the triangles' third corners), non-empty, and every
    /// changed triangle unfolded in space and in texture space?
    pub(super) fn can_collapse(
        &mut self,
        keep: u32,
        gone: u32,
        p: &Spot,
        keep_moves: bool,
    ) -> bool {
        // Mark the neighbours of `keep`, then count those of `gone` that are marked
        // (unmarking each, so that it counts once), checking `gone`'s triangles on the
        // way: each star is read once, and `keep`'s once more only when it moves.
        self.stamp = self.stamp.wrapping_add(1).max(1);
        let stamp = self.stamp;
        let star = |v: u32| self.start[v as usize] as usize..self.start[v as usize + 1] as usize;
        let mut remaining = 0;
        for i in star(keep) {
            let t = self.refs[i];
            if self.uses(t, keep) {
                let tri = self.tris[t as usize];
                for w in tri {
                    self.mark[w as usize] = stamp;
                }
                if !tri.contains(&gone) {
                    remaining += 1;
                }
            }
        }
        let (mut shared_vertices, mut shared_tris) = (0, 0);
        for i in star(gone) {
            let t = self.refs[i];
            if !self.uses(t, gone) {
                continue;
            }
            let tri = self.tris[t as usize];
            if tri.contains(&keep) {
                shared_tris += 1;
            } else {
                remaining += 1;
                if !self.keeps_orientation(t, gone, p) {
                    return false;
                }
            }
            for w in tri {
                if w != keep && w != gone && self.mark[w as usize] == stamp {
                    self.mark[w as usize] = 0;
                    shared_vertices += 1;
                }
            }
        }
        if shared_vertices != shared_tris || remaining == 0 {
            return false;
        }
        !keep_moves
            || star(keep).all(|i| {
                let t = self.refs[i];
                !self.uses(t, keep)
                    || self.tris[t as usize].contains(&gone)
                    || self.keeps_orientation(t, keep, p)
            })
    }

    /// With [`Options::cover`], may `gone` go onto `keep`? Always, but for a boundary
    /// vertex going onto its neighbour along the boundary: the boundary then runs
    /// from `gone`'s other neighbour `c` straight to `keep`, and the surface loses the
    /// triangle `c gone keep` where the boundary turns towards it at `gone`, or gains
    /// it where it turns away. Only a gain over cells its piece does not cover is let
    /// through (or no turn).
    pub(super) fn grows_outward(&self, gone: u32, keep: u32) -> bool {
        let Some(cover) = &self.cover else {
            return true;
        };
        if !self.flag(gone, BOUNDARY) {
            return true;
        }
        // `gone`'s neighbours along the boundary are those of one live triangle only.
        let mut neighbours = [NONE; 2];
        let mut found = 0;
        let mut edge_triangle = NONE;
        for &t in self.star(gone) {
            if !self.uses(t, gone) {
                continue;
            }
            for w in self.tris[t as usize] {
                if w == gone {
                    continue;
                }
                let sharing = self
                    .star(gone)
                    .iter()
                    .filter(|&&s| self.uses(s, gone) && self.tris[s as usize].contains(&w))
                    .count();
                if sharing == 1 {
                    if w == keep {
                        edge_triangle = t;
                    } else if found < 2 {
                        neighbours[found] = w;
                        found += 1;
                    }
                }
            }
        }
        if edge_triangle == NONE {
            // An interior edge: the boundary does not change.
            return true;
        }
        if found != 1 {
            return false;
        }
        let c = neighbours[0];
        let tri = self.tris[edge_triangle as usize];
        let at = |v: u32| tri.iter().position(|&w| w == v).unwrap_or(0);
        // The surface lies left of the boundary walked c -> gone -> keep when the
        // triangle runs gone -> keep in a positive texture orientation.
        let forward = (at(gone) + 1) % 3 == at(keep);
        let sign =
            f64::from(self.uv_sign[edge_triangle as usize]) * if forward { 1.0 } else { -1.0 };
        let uv = [c, gone, keep].map(|v| self.texcoord[v as usize].map(f64::from));
        let turn = cross2(uv[0], uv[1], uv[2]) * sign;
        if sign == 0.0 || turn > 0.0 {
            return false;
        }
        turn == 0.0
            || !cover.triangle_overlaps(
                cover.vertex_piece[self.original[gone as usize] as usize],
                uv,
            )
    }

    /// As far as seams go, may boundary vertex `gone` go onto its neighbour `keep`
    /// along the boundary? Always off a seam; on one, only with its twin
    /// ([`Collapser::twin_edge`]).
    pub(super) fn seam_allows(&self, gone: u32, keep: u32) -> bool {
        !self.flag(gone, SEAM) || self.twin_edge(gone, keep).is_some()
    }

    /// For seam vertex `gone` going onto `keep` along the boundary, the collapse on
    /// the other side of the seam that must go with it: `gone`'s twin onto `keep`'s,
    /// as (twin of `gone`, twin of `keep`). `None` where the seam ends at `keep` (it has
    /// no twin, or the twins are not neighbours along their boundary) or the twin is
    /// locked: `gone` then stays.
    fn twin_edge(&self, gone: u32, keep: u32) -> Option<(u32, u32)> {
        if !self.flag(keep, SEAM) {
            return None;
        }
        let (gone_twin, keep_twin) = (self.twin[gone as usize], self.twin[keep as usize]);
        let usable = |v: u32| v != NONE && v != gone && v != keep && self.flag(v, ALIVE);
        (usable(gone_twin)
            && usable(keep_twin)
            && !self.flag(gone_twin, LOCKED)
            && self.edge_triangles(gone_twin, keep_twin).0 == 1)
            .then_some((gone_twin, keep_twin))
    }

    /// The collapse of `gone`'s twin onto `keep`'s that goes with that of seam vertex
    /// `gone` onto `keep` ([`Collapser::twin_edge`]), checked as any collapse onto an
    /// endpoint is, within `bound`: (keep, gone, their summed quadric, where they go,
    /// its cost). `None` when it may not be made; then neither is. The two sides must
    /// share no triangle, so that making one leaves the other's checks as they were.
    pub(super) fn twin_collapse(
        &mut self,
        gone: u32,
        keep: u32,
        bound: f64,
    ) -> Option<(u32, u32, Local, Spot, f64)> {
        let (gone_twin, keep_twin) = self.twin_edge(gone, keep)?;
        if self.busy[gone_twin as usize] || self.busy[keep_twin as usize] {
            return None;
        }
        let touches = |v: u32| {
            self.star(v).iter().any(|&t| {
                self.uses(t, v)
                    && self.tris[t as usize]
                        .iter()
                        .any(|&w| w == gone_twin || w == keep_twin)
            })
        };
        if touches(gone) || touches(keep) {
            return None;
        }
        let q = self.pair(keep_twin, gone_twin);
        let p = self.place(keep_twin, gone_twin, Choice::KeepA)?;
        let at = self.from(keep_twin, &p.x);
        let exact = q.error(&at);
        self.endpoint_allows(keep_twin, gone_twin, &p, exact, bound)
            .then(|| (keep_twin, gone_twin, q.around(&at), p, exact))
    }

    /// May `gone` go onto `keep`, which stays at `p`, at cost `exact` within `bound`?
    /// Checked again when tried: earlier collapses of the pass may have moved `gone`'s
    /// neighbours on the boundary since the edge was evaluated.
    pub(super) fn endpoint_allows(
        &mut self,
        keep: u32,
        gone: u32,
        p: &Spot,
        exact: f64,
        bound: f64,
    ) -> bool {
        exact <= bound && self.grows_outward(gone, keep) && self.can_collapse(keep, gone, p, false)
    }

    /// Does triangle `t` keep the direction of its normal and the sign of its texture
    /// area, with no degeneracy, when its corner `v` moves to `p`?
    pub(super) fn keeps_orientation(&self, t: u32, v: u32, p: &Spot) -> bool {
        let tri = self.tris[t as usize];
        let old = tri.map(|w| self.x[w as usize]);
        let new = tri.map(|w| if w == v { p.x } else { self.x[w as usize] });
        let n_old = cross3(sub3(&old[1], &old[0]), sub3(&old[2], &old[0]));
        let n_new = cross3(sub3(&new[1], &new[0]), sub3(&new[2], &new[0]));
        let (l_old, l_new) = (dot3(n_old, n_old), dot3(n_new, n_new));
        if l_new <= 1e-12 * l_old || dot3(n_old, n_new) <= 0.0 {
            return false;
        }
        let uv = tri.map(|w| {
            if w == v {
                p.texcoord.map(f64::from)
            } else {
                self.texcoord[w as usize].map(f64::from)
            }
        });
        let area = cross2(uv[0], uv[1], uv[2]);
        let sign = self.uv_sign[t as usize];
        sign != 0 && area * f64::from(sign) > 1e-9
    }
}
