//! Outline edges: where a layer surface ends, at the model's outline, holes and
//! inactive cells, the cell edges that have no neighbouring face of the same surface.
//! A wireframe drawn from texture coordinates paints only the half of such an edge's
//! line that falls on the surface; renderers draw the other half from these.
//!
//! Edges where a neighbouring face exists but lies elsewhere (a fault split) are not
//! outline edges: fault traces draw them ([`crate::faults`]). Each edge keeps what a
//! renderer needs to draw the outer half exactly as the surface draws the inner one:
//! the point one cell inward (the cell's size across the line, on screen) and the
//! grid line's index (whether it is a major line); and its neighbours along the
//! outline, so that edges meeting at a corner split the pixels around it instead of
//! both covering them.

use std::collections::{HashMap, HashSet};

use crate::SurfaceMesh;
use crate::faults::layer_corners;

/// One edge of a surface's outline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutlineEdge {
    /// Its ends, ordered so that the surface lies on the left going from the first to
    /// the second in the (i, j) index plane.
    pub ends: [[f32; 3]; 2],
    /// The middle of the cell's opposite edge: one cell inward from this one.
    pub inward: [f32; 3],
    /// The grid line the edge lies on: its node index along j for an edge along i
    /// (`along_i`), along i for one along j.
    pub line: u32,
    /// Whether the edge runs along i (on a line of constant j).
    pub along_i: bool,
    /// The first end of the outline's edge before this one and the second end of the
    /// one after it; where none joins, the edge continued straight by its own length.
    pub before: [f32; 3],
    /// See `before`.
    pub after: [f32; 3],
}

/// A side two faces of one surface share with no fault between them: where a folded
/// surface may turn away from the eye (a silhouette), the edge between a triangle that
/// faces the eye and one that does not.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InteriorEdge {
    /// The (i, j) column of the face on its west or south side.
    pub cell: [u32; 2],
    /// Its ends (vertex indices, of that face).
    pub ends: [u32; 2],
    /// The far corner of the triangle on each side, west or south first.
    pub far: [u32; 2],
    /// The grid line it lies on, as [`OutlineEdge::line`].
    pub line: u32,
    /// Whether it runs along i.
    pub along_i: bool,
}

/// The edges of a mesh's layer surfaces that renderers draw lines on beyond what the
/// surface draws: [`surface_edges`].
#[derive(Clone, Debug, Default)]
pub struct SurfaceEdges {
    /// The outline: [`outline_edges`].
    pub outline: Vec<OutlineEdge>,
    /// The sides shared by two faces of one surface, each once.
    pub interior: Vec<InteriorEdge>,
}

/// A side of a layer face, as [`outline_edges`] walks them.
struct Side {
    /// The neighbouring cell's column offset.
    step: [i64; 2],
    /// The side's corners (in `layer_corners` order, (0, 0) (1, 0) (0, 1) (1, 1)), in
    /// outline order: the face on the left.
    corners: [usize; 2],
    /// The opposite side's corners.
    opposite: [usize; 2],
    /// Whether the side lies on a line of constant i (else of constant j), at node
    /// offset `offset` from the cell.
    on_i_line: bool,
    offset: u32,
}

const SIDES: [Side; 4] = [
    // South, along i.
    Side {
        step: [0, -1],
        corners: [0, 1],
        opposite: [2, 3],
        on_i_line: false,
        offset: 0,
    },
    // East, along j.
    Side {
        step: [1, 0],
        corners: [1, 3],
        opposite: [0, 2],
        on_i_line: true,
        offset: 1,
    },
    // North.
    Side {
        step: [0, 1],
        corners: [3, 2],
        opposite: [0, 1],
        on_i_line: false,
        offset: 1,
    },
    // West.
    Side {
        step: [-1, 0],
        corners: [2, 0],
        opposite: [1, 3],
        on_i_line: true,
        offset: 0,
    },
];

/// The outline edges of `mesh`'s layer surfaces: every side of a cell face whose
/// neighbouring cell has no face on the same surface, unless a side face of the mesh
/// (a wall going down from it) has that edge too. Meshes appended one after another
/// (several layers) are told apart as [`crate::faults::fault_traces`] tells them.
/// Meshes without cell faces (decimated surfaces) have none.
pub fn outline_edges(mesh: &SurfaceMesh) -> Vec<OutlineEdge> {
    surface_edges(mesh).outline
}

/// One layer face as the walk holds it: its cell, corners (`layer_corners` order) and
/// triangles.
type Face = ([u32; 3], [u32; 4], [u32; 2]);

/// The outline edges of `mesh`'s layer surfaces ([`outline_edges`]) and the sides
/// their faces share ([`InteriorEdge`]), found in one walk over the faces.
pub fn surface_edges(mesh: &SurfaceMesh) -> SurfaceEdges {
    let mut faces: Vec<Face> = Vec::with_capacity(mesh.cell_faces.len());
    let mut walls: HashSet<[[u32; 3]; 2]> = HashSet::new();
    let key = |p: [f32; 3], q: [f32; 3]| {
        let (p, q) = (p.map(f32::to_bits), q.map(f32::to_bits));
        if p <= q { [p, q] } else { [q, p] }
    };
    for f in &mesh.cell_faces {
        match layer_corners(mesh, f.cell, f.triangles) {
            Some(corners) => faces.push((f.cell, corners, f.triangles)),
            None => {
                for t in f.triangles {
                    let Some(tri) = mesh.triangles.get(t as usize) else {
                        continue;
                    };
                    for e in 0..3 {
                        let at = |v: u32| mesh.positions[v as usize];
                        walls.insert(key(at(tri[e]), at(tri[(e + 1) % 3])));
                    }
                }
            }
        }
    }
    // The faces of a surface are found in a dense table over the (i, j) box of all
    // faces, not a hash map: a part of a large model holds millions.
    let range = |axis: usize| {
        let values = faces.iter().map(|(c, _, _)| c[axis]);
        let lo = values.clone().min().unwrap_or(0);
        (lo, values.max().map_or(0, |hi| hi + 1 - lo) as usize)
    };
    let mut table = Columns {
        origin: [range(0).0, range(1).0],
        ni: range(0).1,
        slot: vec![u32::MAX; range(0).1 * range(1).1],
    };
    let mut out = SurfaceEdges::default();
    let mut start = 0;
    for n in 0..faces.len() {
        let at = table.at(faces[n].0).unwrap_or(0);
        if table.slot[at] != u32::MAX {
            // The column again: the next surface starts here.
            surface_edges_of(mesh, &faces, start..n, &table, &mut out);
            table.clear(&faces[start..n]);
            start = n;
        }
        table.slot[at] = n as u32;
    }
    surface_edges_of(mesh, &faces, start..faces.len(), &table, &mut out);
    out.outline
        .retain(|e| !walls.contains(&key(e.ends[0], e.ends[1])));
    out
}

/// Per column of the faces' (i, j) box, the index of the current surface's face there.
struct Columns {
    origin: [u32; 2],
    ni: usize,
    slot: Vec<u32>,
}

impl Columns {
    /// Where column `(i, j)` of `cell` is held; `None` outside the box.
    fn at(&self, cell: [u32; 3]) -> Option<usize> {
        let i = cell[0].checked_sub(self.origin[0])? as usize;
        let j = cell[1].checked_sub(self.origin[1])? as usize;
        (i < self.ni && (j + 1) * self.ni <= self.slot.len()).then_some(j * self.ni + i)
    }

    /// Empties the columns of `faces`.
    fn clear(&mut self, faces: &[Face]) {
        for (cell, _, _) in faces {
            if let Some(at) = self.at(*cell) {
                self.slot[at] = u32::MAX;
            }
        }
    }
}

/// The corner of whichever of `triangles` holds both `p` and `q` that is neither.
fn far_corner(mesh: &SurfaceMesh, triangles: [u32; 2], p: u32, q: u32) -> Option<u32> {
    triangles
        .iter()
        .filter_map(|&t| mesh.triangles.get(t as usize))
        .find(|tri| tri.contains(&p) && tri.contains(&q))
        .and_then(|tri| tri.iter().copied().find(|&v| v != p && v != q))
}

/// Adds the edges of one surface, `faces[surface]` (held in `table`), to `out`: its
/// outline edges, linked to their neighbours, and the sides its faces share.
fn surface_edges_of(
    mesh: &SurfaceMesh,
    faces: &[Face],
    surface: std::ops::Range<usize>,
    table: &Columns,
    out: &mut SurfaceEdges,
) {
    let at = |v: u32| mesh.positions[v as usize];
    let SurfaceEdges { outline, interior } = out;
    let first = outline.len();
    // Per edge: its cell and its first and second node in the (i, j) index plane.
    let mut nodes: Vec<([u32; 2], [[u32; 2]; 2])> = Vec::new();
    for &(cell, corners, triangles) in &faces[surface] {
        for Side {
            step,
            corners: side,
            opposite,
            on_i_line,
            offset,
        } in SIDES
        {
            let neighbour = [i64::from(cell[0]) + step[0], i64::from(cell[1]) + step[1]];
            let neighbour_face = u32::try_from(neighbour[0])
                .ok()
                .zip(u32::try_from(neighbour[1]).ok())
                .and_then(|(i, j)| table.at([i, j, cell[2]]))
                .map(|slot| table.slot[slot])
                .and_then(|f| faces.get(f as usize))
                .filter(|(c, _, _)| c[2] == cell[2]);
            if let Some(&(_, their_corners, their_triangles)) = neighbour_face {
                // Each shared side once, from the face west or south of it, where
                // both faces have its ends (no fault between them).
                let forward = step[0] + step[1] > 0;
                let ends = side.map(|c| corners[c]);
                // The neighbour's side: its cell's opposite corners (in either order).
                let theirs = opposite.map(|c| their_corners[c]);
                let [a, b] = ends;
                let (here, there) = (ends.map(at), theirs.map(at));
                if forward && (here == there || here == [there[1], there[0]]) {
                    let far = [
                        far_corner(mesh, triangles, a, b),
                        far_corner(mesh, their_triangles, theirs[0], theirs[1]),
                    ];
                    if let [Some(mine), Some(other)] = far {
                        interior.push(InteriorEdge {
                            cell: [cell[0], cell[1]],
                            ends,
                            far: [mine, other],
                            line: if on_i_line { cell[0] } else { cell[1] } + offset,
                            along_i: !on_i_line,
                        });
                    }
                }
                continue;
            }
            let [p, q] = side.map(|c| at(corners[c]));
            let [r, s] = opposite.map(|c| at(corners[c]));
            let node = |c: usize| [cell[0] + (c as u32 & 1), cell[1] + (c as u32 >> 1)];
            outline.push(OutlineEdge {
                ends: [p, q],
                inward: std::array::from_fn(|a| 0.5 * (r[a] + s[a])),
                line: if on_i_line { cell[0] } else { cell[1] } + offset,
                along_i: !on_i_line,
                before: std::array::from_fn(|a| 2.0 * p[a] - q[a]),
                after: std::array::from_fn(|a| 2.0 * q[a] - p[a]),
            });
            nodes.push(([cell[0], cell[1]], side.map(node)));
        }
    }
    // Link each edge to the one starting where it ends: at a node where two cells
    // touch corner to corner, two edges start and two end there, and each goes on
    // along its own cell.
    let mut starting: HashMap<[u32; 2], Vec<usize>> = HashMap::new();
    for (n, (_, [from, _])) in nodes.iter().enumerate() {
        starting.entry(*from).or_default().push(n);
    }
    for (n, (cell, [_, to])) in nodes.iter().enumerate() {
        let Some(next) = starting.get(to).and_then(|c| match c.as_slice() {
            [only] => Some(*only),
            many => many.iter().copied().find(|&m| nodes[m].0 == *cell),
        }) else {
            continue;
        };
        let (this, that) = (outline[first + n], outline[first + next]);
        // Edges split by a fault at the node do not meet.
        if this.ends[1] == that.ends[0] {
            outline[first + n].after = that.ends[1];
            outline[first + next].before = this.ends[0];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat `nx` x `ny` grid of 10 m cells, without the faces of the cells `holes`.
    fn flat(nx: usize, ny: usize, holes: &[[u32; 2]]) -> SurfaceMesh {
        let mut mesh =
            SurfaceMesh::structured(nx, ny, |i, j| [10.0 * i as f32, 10.0 * j as f32, 0.0]);
        mesh.cell_faces
            .retain(|f| !holes.contains(&[f.cell[0], f.cell[1]]));
        mesh
    }

    /// Whether `p` lies on the left of the edge seen from above (the plane z = 0).
    fn on_left(edge: &OutlineEdge, p: [f32; 3]) -> bool {
        let [a, b] = edge.ends;
        (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) > 0.0
    }

    #[test]
    fn faces_share_every_inner_side_once_but_across_a_fault() {
        let mesh = flat(3, 2, &[]);
        let edges = surface_edges(&mesh);
        // (3 - 1) x 2 sides along j, 3 x (2 - 1) along i.
        assert_eq!(edges.interior.len(), 7);
        for e in &edges.interior {
            let [a, b] = e.ends.map(|v| mesh.positions[v as usize]);
            // On its grid line, the far corners off it on either side.
            let on_line = |p: [f32; 3]| {
                if e.along_i {
                    p[1] == 10.0 * e.line as f32
                } else {
                    p[0] == 10.0 * e.line as f32
                }
            };
            assert!(on_line(a) && on_line(b), "{e:?}");
            let [f, g] = e.far.map(|v| mesh.positions[v as usize]);
            assert!(!on_line(f) && !on_line(g), "{e:?}");
            let axis = usize::from(e.along_i);
            assert!((f[axis] - a[axis]) * (g[axis] - a[axis]) < 0.0, "{e:?}");
        }
        // Cells east of i = 1 on vertices of their own, 5 m lower: a fault, whose
        // sides are not shared.
        let mut faulted = mesh.clone();
        let mut moved = std::collections::HashMap::new();
        for f in mesh.cell_faces.iter().filter(|f| f.cell[0] >= 2) {
            for t in f.triangles {
                for v in &mut faulted.triangles[t as usize] {
                    *v = *moved.entry(*v).or_insert_with(|| {
                        let [x, y, z] = mesh.positions[*v as usize];
                        faulted.positions.push([x, y, z - 5.0]);
                        faulted.texcoords.push(mesh.texcoords[*v as usize]);
                        faulted.positions.len() as u32 - 1
                    });
                }
            }
        }
        let shared = surface_edges(&faulted).interior;
        assert_eq!(shared.len(), 5, "{shared:?}");
        assert!(
            shared.iter().all(|e| e.along_i || e.line != 2),
            "{shared:?}"
        );
    }

    #[test]
    fn the_outline_runs_around_the_surface_with_the_surface_on_its_left() {
        let edges = outline_edges(&flat(6, 4, &[]));
        assert_eq!(edges.len(), 20);
        for e in &edges {
            assert!(on_left(e, e.inward), "{e:?}");
            // One cell inward: 10 m from the edge's line.
            let [a, b] = e.ends;
            let along_x = a[1] == b[1];
            let gap = if along_x {
                (e.inward[1] - a[1]).abs()
            } else {
                (e.inward[0] - a[0]).abs()
            };
            assert_eq!(gap, 10.0);
            // On the line of its node index: x = 10 i for a line along j.
            let at = if along_x { a[1] } else { a[0] };
            assert_eq!(at, 10.0 * e.line as f32, "{e:?}");
            // Closed: every edge's neighbours are edges of the outline.
            assert!(edges.iter().any(|o| o.ends == [e.before, a]), "{e:?}");
            assert!(edges.iter().any(|o| o.ends == [b, e.after]), "{e:?}");
        }
        // At the corner (0, 0): the south edge comes after the west one.
        let south = edges
            .iter()
            .find(|e| e.ends[0] == [0.0, 0.0, 0.0] && e.ends[1] == [10.0, 0.0, 0.0]);
        assert_eq!(south.map(|e| e.before), Some([0.0, 10.0, 0.0]));
    }

    #[test]
    fn holes_are_outlined_and_faults_are_not() {
        let edges = outline_edges(&flat(6, 4, &[[2, 1]]));
        assert_eq!(edges.len(), 24);
        let around_hole: Vec<&OutlineEdge> = edges
            .iter()
            .filter(|e| {
                e.ends
                    .iter()
                    .all(|p| (20.0..=30.0).contains(&p[0]) && (10.0..=20.0).contains(&p[1]))
            })
            .collect();
        assert_eq!(around_hole.len(), 4);
        // The surface on the left is outside the hole: the hole's centre on the right.
        for e in around_hole {
            assert!(!on_left(e, [25.0, 15.0, 0.0]), "{e:?}");
            assert!(on_left(e, e.inward));
        }
        // A split surface (a fault: the next cells' vertices elsewhere) has no outline
        // edge along the split: those are fault traces.
        let mut split = flat(6, 4, &[]);
        for p in &mut split.positions {
            if p[0] > 30.0 {
                p[2] = -5.0;
            }
        }
        assert_eq!(outline_edges(&split).len(), 20);
    }

    #[test]
    fn an_edge_a_wall_goes_down_from_is_no_outline() {
        let mut mesh = flat(6, 4, &[]);
        // The wall under the south edge of cell (0, 0), as side faces carry it: its
        // own vertices, coordinates not those of a layer face.
        let first = mesh.positions.len() as u32;
        for p in [
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            [0.0, 0.0, -5.0],
            [10.0, 0.0, -5.0],
        ] {
            mesh.positions.push(p);
            mesh.texcoords.push([1.0, 0.5]);
        }
        let t = mesh.triangles.len() as u32;
        mesh.triangles.push([first, first + 1, first + 3]);
        mesh.triangles.push([first, first + 3, first + 2]);
        mesh.cell_faces.push(crate::CellFace {
            triangles: [t, t + 1],
            cell: [0, 0, 0],
            value: f32::NAN,
        });
        let edges = outline_edges(&mesh);
        assert_eq!(edges.len(), 19);
        assert!(
            !edges
                .iter()
                .any(|e| e.ends == [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]])
        );
    }

    #[test]
    fn cells_touching_at_a_corner_keep_their_own_outlines() {
        // Two cells of a 2 x 2 grid, diagonal to each other: two squares that share a
        // node, each outline turning at it around its own cell.
        let edges = outline_edges(&flat(2, 2, &[[1, 0], [0, 1]]));
        assert_eq!(edges.len(), 8);
        let centre = [10.0, 10.0, 0.0];
        let ending: Vec<&OutlineEdge> = edges.iter().filter(|e| e.ends[1] == centre).collect();
        assert_eq!(ending.len(), 2);
        for e in ending {
            // The next edge bounds the same cell: that cell's point inward (on its far
            // side) lies on its left too, where the other cell's edge has it on its
            // right.
            let next = edges.iter().find(|o| o.ends == [centre, e.after]);
            assert!(next.is_some_and(|n| on_left(n, e.inward)), "{e:?}");
        }
    }
}
