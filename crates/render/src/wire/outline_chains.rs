//! Which outline edges a frame draws, and merged into how long pieces: the outline's
//! levels of detail, chosen on the CPU every frame (`outline.rs` draws what is chosen).
//!
//! # How it works
//! Outline edges that follow one another along one grid line form a chain. Each chain
//! is cut in halves, again and again down to single edges; every piece keeps how far
//! its edges' corners lie from its chord (the straight segment from its first corner
//! to its last). A frame walks each chain from the whole down and takes the first
//! piece whose corners lie within [`MERGE_TOLERANCE_PX`] of its chord on screen: on a
//! model seen whole, a chain of hundreds of one-pixel edges becomes a few long quads.
//! Pieces wholly outside the frame, and pieces whose grid line is not drawn at the
//! level the cells' size on screen gives (`outline_level` in outline.wgsl: minor lines
//! of small cells), are left out.
//!
//! # Why not the obvious way
//! One quad per edge, each culled in the vertex shader, cost the bench's 1 M reservoir
//! its 10 000 edges' 21 000 small triangles every frame, most of them one pixel long:
//! on the CPU rasterizers the triangles' setup, not their shading, is what an outline
//! costs. Choosing in the vertex shader would still run it for every edge.

use glam::{Vec2, Vec3};
use strata_grid::outline::OutlineEdge;

use super::FrameProjection;
use crate::Style;

/// How far (pixels) a merged piece may put the outline from where its edges' corners
/// are.
pub const MERGE_TOLERANCE_PX: f32 = 0.1;

/// A run of consecutive chain edges and how far their corners lie from its chord.
#[derive(Clone, Copy, Debug)]
struct Piece {
    /// Its edges: `start..end` in [`OutlineChains::edges`].
    start: u32,
    end: u32,
    /// How far its corners lie from its chord (display frame, unexaggerated):
    /// horizontally and vertically at most, which vertical exaggeration scales apart.
    deviation: [f32; 2],
    /// The index of its second half among the pieces (its first follows it); 0 for a
    /// single edge.
    second: u32,
}

/// One piece a frame draws: edges `start..end` as one segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Chosen {
    /// The first edge, in [`OutlineChains::edges`].
    pub start: u32,
    /// One past the last.
    pub end: u32,
}

/// The outline edges in chains with their pieces.
pub struct OutlineChains {
    /// The edges, each chain's in order along the outline.
    pub edges: Vec<OutlineEdge>,
    /// Every chain's pieces, the whole chain first, each piece's halves after it.
    pieces: Vec<Piece>,
    /// Each chain's whole piece.
    roots: Vec<u32>,
    /// Whether each edge follows the one before it in its chain.
    follows: Vec<bool>,
}

/// Bit patterns of a point, to find the edge that starts where another ends.
fn key(p: [f32; 3]) -> [u32; 3] {
    p.map(f32::to_bits)
}

impl OutlineChains {
    /// `edges` put in chains: runs of edges on one grid line, each starting where the
    /// one before ends (the next edge of the outline is the one from an edge's second
    /// end to its `after`).
    pub fn new(edges: &[OutlineEdge]) -> OutlineChains {
        let by_ends: std::collections::HashMap<([u32; 3], [u32; 3]), usize> = edges
            .iter()
            .enumerate()
            .map(|(n, e)| ((key(e.ends[0]), key(e.ends[1])), n))
            .collect();
        let next: Vec<Option<usize>> = edges
            .iter()
            .enumerate()
            .map(|(n, e)| {
                by_ends
                    .get(&(key(e.ends[1]), key(e.after)))
                    .copied()
                    .filter(|&m| m != n && edges[m].line == e.line && edges[m].along_i == e.along_i)
            })
            .collect();
        let mut has_before = vec![false; edges.len()];
        for &m in next.iter().flatten() {
            has_before[m] = true;
        }
        let mut chains = OutlineChains {
            edges: Vec::with_capacity(edges.len()),
            pieces: Vec::with_capacity(2 * edges.len()),
            roots: Vec::new(),
            follows: Vec::with_capacity(edges.len()),
        };
        let mut taken = vec![false; edges.len()];
        // Chains start where no edge of the same line leads in; a closed loop on one
        // line cannot be (an outline turns), but what is left is taken as it comes.
        let starts = (0..edges.len())
            .filter(|&n| !has_before[n])
            .chain(0..edges.len());
        for first in starts {
            if taken[first] {
                continue;
            }
            let start = chains.edges.len() as u32;
            let mut at = Some(first);
            while let Some(n) = at.filter(|&n| !taken[n]) {
                taken[n] = true;
                chains.follows.push(n != first);
                chains.edges.push(edges[n]);
                at = next[n];
            }
            let end = chains.edges.len() as u32;
            let root = chains.pieces.len() as u32;
            chains.roots.push(root);
            chains.split(start, end);
        }
        chains
    }

    /// Whether edge `n` follows the one before it in its chain: whether a piece
    /// starting at `n` has a neighbour of its chain before it.
    pub fn follows(&self, n: u32) -> bool {
        self.follows.get(n as usize).copied().unwrap_or(false)
    }

    /// Adds the piece of edges `start..end` and its halves, depth first.
    fn split(&mut self, start: u32, end: u32) {
        let at = self.pieces.len();
        self.pieces.push(Piece {
            start,
            end,
            deviation: self.deviation(start, end),
            second: 0,
        });
        if end - start > 1 {
            let middle = start + (end - start) / 2;
            self.split(start, middle);
            self.pieces[at].second = self.pieces.len() as u32;
            self.split(middle, end);
        }
    }

    /// The chord of edges `start..end`: the first's first end to the last's second.
    fn chord(&self, start: u32, end: u32) -> [[f32; 3]; 2] {
        [
            self.edges[start as usize].ends[0],
            self.edges[end as usize - 1].ends[1],
        ]
    }

    /// How far the corners between edges `start..end` lie from their chord,
    /// horizontally and vertically at most.
    fn deviation(&self, start: u32, end: u32) -> [f32; 2] {
        let [a, b] = self.chord(start, end).map(Vec3::from);
        (start + 1..end)
            .map(|n| offset_from_segment(Vec3::from(self.edges[n as usize].ends[0]), a, b))
            .fold([0.0, 0.0], |m, d| {
                [m[0].max(d.truncate().length()), m[1].max(d.z.abs())]
            })
    }

    /// The pieces to draw in `frame` with `style`'s lines, each chain's in order along
    /// it, into `out` (cleared first).
    pub fn choose(&self, frame: &FrameProjection, style: &Style, out: &mut Vec<Chosen>) {
        out.clear();
        for &root in &self.roots {
            self.descend(root, frame, style, out);
        }
    }

    fn descend(&self, at: u32, frame: &FrameProjection, style: &Style, out: &mut Vec<Chosen>) {
        let piece = self.pieces[at as usize];
        let [a, b] = self.chord(piece.start, piece.end);
        let (ca, cb) = (frame.clip(a), frame.clip(b));
        // The corners' distance from the chord as drawn, exaggerated: at most that of
        // the exaggerated offsets.
        let [h, v] = piece.deviation;
        let deviation = h.hypot(v * frame.z_scale);
        let near = ca.w.min(cb.w) - deviation;
        let single = piece.second == 0;
        if near <= 1.0e-6 {
            // Reaching behind the eye: its halves decide, single edges the shader.
            if single {
                out.push(Chosen {
                    start: piece.start,
                    end: piece.end,
                });
            } else {
                self.descend(at + 1, frame, style, out);
                self.descend(piece.second, frame, style, out);
            }
            return;
        }
        let deviation_px = deviation * frame.pixels_per_unit(near);
        let (wa, wb) = (frame.window(ca), frame.window(cb));
        // Whatever the piece or its halves draw lies within the line's reach of the
        // chord, the corners' distance further.
        let margin = 0.5 * style.thickness + 2.0 + deviation_px;
        let outside = |axis: usize, size: f32| {
            (wa[axis] < -margin && wb[axis] < -margin)
                || (wa[axis] > size + margin && wb[axis] > size + margin)
        };
        if outside(0, frame.size.x) || outside(1, frame.size.y) {
            return;
        }
        if !single && deviation_px > MERGE_TOLERANCE_PX {
            self.descend(at + 1, frame, style, out);
            self.descend(piece.second, frame, style, out);
            return;
        }
        if self.line_drawn(piece, frame, style, (wa, wb)) {
            out.push(Chosen {
                start: piece.start,
                end: piece.end,
            });
        }
    }

    /// Whether the piece's grid line may be drawn at the level its cells' size on
    /// screen gives, its chord at window positions `wa` `wb`: `outline_level` in
    /// outline.wgsl, from the same cell size (the point one cell inward from the
    /// piece's middle edge, from the chord), taken a little larger (larger cells
    /// draw more lines) so that nothing the shader would draw is left out.
    fn line_drawn(
        &self,
        piece: Piece,
        frame: &FrameProjection,
        style: &Style,
        (wa, wb): (Vec2, Vec2),
    ) -> bool {
        let Some(major) = style.major.filter(|m| m.every > 1) else {
            return true;
        };
        let middle = &self.edges[((piece.start + piece.end) / 2) as usize];
        let ci = frame.clip(middle.inward);
        if ci.w <= 1.0e-6 || wa.distance_squared(wb) < 1.0e-8 {
            return true;
        }
        let e = (wb - wa).normalize();
        let cell = (frame.window(ci) - wa).perp_dot(e).abs() * 1.02;
        let n = major.every;
        let level = if cell > major.fade {
            0
        } else if n as f32 * cell > major.fade {
            1
        } else {
            2
        };
        let line = middle.line;
        let step = n.saturating_pow(level);
        if line % step != 0 {
            return false;
        }
        // The coarsest level the line belongs to fades it out with its spacing.
        let rank = if level < 2 && (line / step) % n == 0 {
            if level < 1 && (line / step) % (n * n) == 0 {
                2
            } else {
                level + 1
            }
        } else {
            level
        };
        rank >= 2 || n.saturating_pow(rank) as f32 * cell > major.fade
    }
}

/// `p` less the nearest point of segment `a` `b`.
fn offset_from_segment(p: Vec3, a: Vec3, b: Vec3) -> Vec3 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p - (a + t * ab)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Camera, MajorLines, View};

    /// A chain of `n` edges of width `cell` along x on grid line `line`, bent up as
    /// the parabola z = x² / 2000 (the surface on the left, y > 0), and one more
    /// chain beside it along y, joined to it at a corner.
    fn bent_outline(n: usize, cell: f32, line: u32) -> Vec<OutlineEdge> {
        let at = |k: usize| {
            let x = k as f32 * cell;
            [x, 0.0, x * x / 2000.0]
        };
        let corner = at(n);
        let up = |k: usize| [corner[0], k as f32 * cell, corner[2]];
        let mut edges: Vec<OutlineEdge> = (0..n)
            .map(|k| OutlineEdge {
                ends: [at(k), at(k + 1)],
                inward: [(k as f32 + 0.5) * cell, cell, at(k)[2]],
                line,
                along_i: true,
                before: if k == 0 { [-cell, 0.0, 0.0] } else { at(k - 1) },
                after: if k + 1 == n { up(1) } else { at(k + 2) },
            })
            .collect();
        edges.extend((0..n).map(|k| OutlineEdge {
            ends: [up(k), up(k + 1)],
            inward: [corner[0] - cell, (k as f32 + 0.5) * cell, corner[2]],
            line: n as u32,
            along_i: false,
            before: if k == 0 { at(n - 1) } else { up(k - 1) },
            after: up(k + 2),
        }));
        // Chains must not depend on the order the edges come in.
        edges.reverse();
        edges
    }

    fn frame(distance: f32, elevation: f32) -> FrameProjection {
        View {
            camera: Camera::orbit(Vec3::new(500.0, 500.0, 0.0), 0.0, elevation, distance),
            width: 1000,
            height: 800,
            bounds: (Vec3::new(0.0, 0.0, 0.0), Vec3::new(1000.0, 1000.0, 500.0)),
        }
        .projection()
    }

    fn no_levels() -> Style {
        Style {
            major: None,
            ..Style::default()
        }
    }

    #[test]
    fn chains_follow_the_outline_along_each_grid_line() {
        let chains = OutlineChains::new(&bent_outline(100, 10.0, 0));
        assert_eq!(chains.roots.len(), 2);
        for (n, e) in chains.edges.iter().enumerate() {
            let follows = chains.follows(n as u32);
            assert_eq!(follows, n % 100 != 0, "edge {n}");
            if follows {
                assert_eq!(chains.edges[n - 1].ends[1], e.ends[0]);
            }
        }
    }

    #[test]
    fn merged_pieces_keep_the_corners_within_the_tolerance_on_screen() {
        let chains = OutlineChains::new(&bent_outline(100, 10.0, 0));
        let style = no_levels();
        let mut chosen = Vec::new();
        let mut counts = Vec::new();
        for distance in [400.0, 1500.0, 6000.0, 30000.0] {
            let frame = frame(distance, 30.0);
            chains.choose(&frame, &style, &mut chosen);
            // No edge is drawn twice; in order; all of them where all are in view.
            let mut next = 0;
            let mut drawn = 0;
            for piece in &chosen {
                assert!(piece.start >= next, "{chosen:?}");
                next = piece.end;
                drawn += piece.end - piece.start;
                let [a, b] = chains
                    .chord(piece.start, piece.end)
                    .map(|p| frame.window(frame.clip(p)));
                for k in piece.start + 1..piece.end {
                    let p = frame.window(frame.clip(chains.edges[k as usize].ends[0]));
                    let off = (p - a).perp_dot((b - a).normalize());
                    assert!(
                        off.abs() <= MERGE_TOLERANCE_PX,
                        "a corner {off} px off its piece at distance {distance}"
                    );
                }
            }
            if distance >= 6000.0 {
                assert_eq!(drawn, 200);
                // The straight chain is one piece.
                assert!(chosen.iter().any(|p| p.end - p.start == 100), "{chosen:?}");
            }
            counts.push(chosen.len());
        }
        // Closer views draw more pieces; seen whole (40 px across), the bent chain
        // is a few.
        assert!(counts.windows(2).all(|c| c[0] >= c[1]), "{counts:?}");
        assert!(counts[0] > 100, "{counts:?}");
        assert!(counts[3] <= 16, "{counts:?}");
    }

    #[test]
    fn pieces_outside_the_frame_are_left_out() {
        let edges: Vec<OutlineEdge> = bent_outline(100, 10.0, 0)
            .into_iter()
            .map(|e| {
                let away = |p: [f32; 3]| [p[0] + 5000.0, p[1], p[2]];
                OutlineEdge {
                    ends: e.ends.map(away),
                    inward: away(e.inward),
                    before: away(e.before),
                    after: away(e.after),
                    ..e
                }
            })
            .collect();
        let mut chosen = Vec::new();
        OutlineChains::new(&edges).choose(&frame(1500.0, 30.0), &no_levels(), &mut chosen);
        assert!(chosen.is_empty(), "{chosen:?}");
    }

    #[test]
    fn minor_lines_of_small_cells_are_left_out_as_the_shader_leaves_them() {
        let style = Style {
            major: Some(MajorLines::default()),
            ..Style::default()
        };
        let mut chosen = Vec::new();
        // Cells of 10 units, about 1.5 px seen from 6000: a minor line (3) is not
        // drawn, a major one (10) is; from 400 (cells of 20 px) both are.
        for (line, distance, drawn) in [(3, 6000.0, false), (10, 6000.0, true), (3, 400.0, true)] {
            let edges: Vec<OutlineEdge> = bent_outline(100, 10.0, line)
                .into_iter()
                .filter(|e| e.along_i)
                .collect();
            OutlineChains::new(&edges).choose(&frame(distance, 60.0), &style, &mut chosen);
            assert_eq!(!chosen.is_empty(), drawn, "line {line} from {distance}");
        }
    }
}
