//! Which grid cells each connected piece of a surface covers, so that a renderer can
//! draw a simplified surface only over the cells of the original.
//!
//! With global coordinates (node `(i, j)` at `(2i + 1, 2j + 1)`), the texture
//! coordinates of a fragment name its cell. A decimation that only lets outlines and
//! holes grow outward over cells their piece does not cover ([`crate::Options::cover`])
//! keeps every covered cell under the simplified surface, and the renderer discards
//! the fragments whose cell its piece does not cover: the outlines, holes and fault
//! traces are drawn exactly where the original draws them, at any budget, while the
//! triangles spent on their staircases go to the surface inside.

use strata_grid::SurfaceMesh;

use crate::{Error, Result};

/// The cells that one connected piece of a surface covers: a bit per cell of its
/// bounding box of cells, row by row.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CoverPiece {
    /// Cell of the box's first corner.
    pub origin: [i32; 2],
    /// Cells across and down the box.
    pub size: [u32; 2],
    /// Bit `y * size[0] + x` of these words: is cell `origin + (x, y)` covered?
    pub bits: Vec<u32>,
}

impl CoverPiece {
    /// Cells in the box, covered or not.
    pub fn box_cells(&self) -> usize {
        self.size[0] as usize * self.size[1] as usize
    }

    /// Does this piece cover `cell`?
    pub fn covers(&self, cell: [i32; 2]) -> bool {
        self.slot(cell)
            .is_some_and(|bit| self.bits[bit / 32] >> (bit % 32) & 1 != 0)
    }

    /// The place of `cell` in the box, row by row; `None` outside it.
    pub fn slot(&self, cell: [i32; 2]) -> Option<usize> {
        let x = i64::from(cell[0]) - i64::from(self.origin[0]);
        let y = i64::from(cell[1]) - i64::from(self.origin[1]);
        if x < 0 || y < 0 || x >= i64::from(self.size[0]) || y >= i64::from(self.size[1]) {
            return None;
        }
        Some((y * i64::from(self.size[0]) + x) as usize)
    }

    /// Tiles across and down the box cut into squares of `side` cells from its origin
    /// (the last ones clipped to it): a view that shows a few of a large piece's cells
    /// is given a field's values for the tiles it shows only. One tile with `side` as
    /// large as the box.
    pub fn tiles(&self, side: u32) -> [u32; 2] {
        let side = side.max(1);
        self.size.map(|s| s.div_ceil(side))
    }

    /// Tiles in the box, see [`CoverPiece::tiles`].
    pub fn tile_count(&self, side: u32) -> usize {
        let [x, y] = self.tiles(side);
        x as usize * y as usize
    }

    /// The cells of tile `t` (row by row, see [`CoverPiece::tiles`]) relative to the
    /// origin: `x0, y0, x1, y1`, ends excluded.
    pub fn tile_box(&self, side: u32, t: usize) -> [u32; 4] {
        let side = side.max(1);
        let across = self.tiles(side)[0].max(1) as usize;
        let (tx, ty) = ((t % across) as u32, (t / across) as u32);
        let lo = [tx, ty].map(|c| c.saturating_mul(side));
        [
            lo[0],
            lo[1],
            lo[0].saturating_add(side).min(self.size[0]),
            lo[1].saturating_add(side).min(self.size[1]),
        ]
    }

    /// Cells in tile `t`, see [`CoverPiece::tile_box`].
    pub fn tile_cells(&self, side: u32, t: usize) -> usize {
        let [x0, y0, x1, y1] = self.tile_box(side, t);
        (x1 - x0) as usize * (y1 - y0) as usize
    }

    /// The tile of `cell` and its place in the tile, row by row; `None` outside the
    /// box.
    pub fn tile_slot(&self, side: u32, cell: [i32; 2]) -> Option<(usize, usize)> {
        let slot = self.slot(cell)?;
        let side = side.max(1);
        let x = (slot % self.size[0] as usize) as u32;
        let y = (slot / self.size[0] as usize) as u32;
        let t = (y / side) as usize * self.tiles(side)[0] as usize + (x / side) as usize;
        let [x0, y0, x1, _] = self.tile_box(side, t);
        Some((
            t,
            (y - y0) as usize * (x1 - x0) as usize + (x - x0) as usize,
        ))
    }
}

/// The connected pieces of a surface (triangles joined by shared vertices) and the
/// cells each covers.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CellCover {
    /// Per vertex of the surface it was made from: its piece (`u32::MAX` for a
    /// vertex no triangle uses).
    pub vertex_piece: Vec<u32>,
    /// The pieces, each with the cells it covers.
    pub pieces: Vec<CoverPiece>,
}

/// The cell whose square holds texture coordinate `uv` (global coordinates).
pub fn cell_of(uv: [f64; 2]) -> [i32; 2] {
    uv.map(|c| ((c - 1.0) * 0.5).floor() as i32)
}

/// The cell whose square holds the centre of the triangle of texture coordinates `uv`.
fn centre_cell(uv: [[f64; 2]; 3]) -> [i32; 2] {
    cell_of([0, 1].map(|k| (uv[0][k] + uv[1][k] + uv[2][k]) / 3.0))
}

/// The cell of a triangle of texture coordinates `uv` and, per vertex, the corner of
/// the cell's square it is at: 0 (0, 0), 1 (1, 0), 2 (1, 1), 3 (0, 1). `None` unless
/// the triangle is a half of its cell split along the (0, 0)-(1, 1) diagonal, as every
/// strata-grid surface's cell faces are.
pub(crate) fn cell_corners(uv: [[f32; 2]; 3]) -> Option<([i32; 2], [usize; 3])> {
    let uv = uv.map(|p| p.map(f64::from));
    let cell = centre_cell(uv);
    let lo = cell.map(|c| 2.0 * f64::from(c) + 1.0);
    let mut corners = [0; 3];
    for (corner, p) in corners.iter_mut().zip(uv) {
        let at = [0, 1].map(|k| (p[k] - lo[k]) * 0.5);
        *corner = match at.map(|a| a.round() as i32) {
            [0, 0] => 0,
            [1, 0] => 1,
            [1, 1] => 2,
            [0, 1] => 3,
            _ => return None,
        };
    }
    let mut sorted = corners;
    sorted.sort_unstable();
    matches!(sorted, [0, 1, 2] | [0, 2, 3]).then_some((cell, corners))
}

impl CellCover {
    /// The cover of `mesh`, whose every triangle lies in one cell's square of texture
    /// space (a surface made of cell faces, as [`strata_grid::layer_surfaces`] makes):
    /// an error names the first triangle that does not.
    pub fn of(mesh: &SurfaceMesh) -> Result<CellCover> {
        let n = mesh.vertex_count();
        let mut parent: Vec<u32> = (0..n as u32).collect();
        fn root(parent: &mut [u32], mut v: u32) -> u32 {
            while parent[v as usize] != v {
                let up = parent[parent[v as usize] as usize];
                parent[v as usize] = up;
                v = up;
            }
            v
        }
        let mut cells = Vec::with_capacity(mesh.triangle_count());
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let uv = tri.map(|v| mesh.texcoords[v as usize].map(f64::from));
            let cell = centre_cell(uv);
            let lo = cell.map(|c| 2.0 * f64::from(c) + 1.0);
            if uv
                .iter()
                .any(|p| (0..2).any(|k| p[k] < lo[k] || p[k] > lo[k] + 2.0))
            {
                return Err(Error::Mesh(format!(
                    "triangle {t} spans more than one cell of the global texture coordinates \
                     (corners {uv:?}): a cell cover needs a surface made of cell faces"
                )));
            }
            cells.push(cell);
            let r = root(&mut parent, tri[0]);
            for &v in &tri[1..] {
                let s = root(&mut parent, v);
                if s != r {
                    parent[s as usize] = r;
                }
            }
        }
        let mut piece_of_root = vec![u32::MAX; n];
        let mut vertex_piece = vec![u32::MAX; n];
        let mut boxes: Vec<([i32; 2], [i32; 2])> = Vec::new();
        for (tri, cell) in mesh.triangles.iter().zip(&cells) {
            let r = root(&mut parent, tri[0]) as usize;
            if piece_of_root[r] == u32::MAX {
                piece_of_root[r] = boxes.len() as u32;
                boxes.push((*cell, *cell));
            }
            let p = piece_of_root[r];
            let (lo, hi) = &mut boxes[p as usize];
            *lo = [lo[0].min(cell[0]), lo[1].min(cell[1])];
            *hi = [hi[0].max(cell[0]), hi[1].max(cell[1])];
            for &v in tri {
                vertex_piece[v as usize] = p;
            }
        }
        let mut pieces: Vec<CoverPiece> = boxes
            .iter()
            .map(|(lo, hi)| {
                let size = [0, 1].map(|k| (hi[k] - lo[k] + 1) as u32);
                CoverPiece {
                    origin: *lo,
                    size,
                    bits: vec![0; (size[0] as usize * size[1] as usize).div_ceil(32)],
                }
            })
            .collect();
        for (tri, cell) in mesh.triangles.iter().zip(&cells) {
            let piece = &mut pieces[vertex_piece[tri[0] as usize] as usize];
            let x = (cell[0] - piece.origin[0]) as usize;
            let y = (cell[1] - piece.origin[1]) as usize;
            let bit = y * piece.size[0] as usize + x;
            piece.bits[bit / 32] |= 1 << (bit % 32);
        }
        Ok(CellCover {
            vertex_piece,
            pieces,
        })
    }

    /// The value of every cell of every piece's box, piece after piece, each box row
    /// by row (as its bits): the cell face's value in `mesh`, the surface this cover was
    /// made of, and NaN where the piece covers no face. Colours a simplified surface
    /// cell by cell, as the original's faces are, wherever its fragments' texture
    /// coordinates fall.
    pub fn values(&self, mesh: &SurfaceMesh) -> Result<Vec<f32>> {
        let mut first = Vec::with_capacity(self.pieces.len());
        let mut cells = 0;
        for p in &self.pieces {
            first.push(cells);
            cells += p.box_cells();
        }
        let mut values = vec![f32::NAN; cells];
        for (f, face) in mesh.cell_faces.iter().enumerate() {
            let slot = mesh
                .triangles
                .get(face.triangles[0] as usize)
                .and_then(|tri| {
                    let p = *self.vertex_piece.get(tri[0] as usize)? as usize;
                    let piece = self.pieces.get(p)?;
                    let uv = tri.map(|v| mesh.texcoords[v as usize].map(f64::from));
                    let cell = centre_cell(uv);
                    let x = usize::try_from(cell[0] - piece.origin[0]).ok()?;
                    let y = usize::try_from(cell[1] - piece.origin[1]).ok()?;
                    (x < piece.size[0] as usize && y < piece.size[1] as usize)
                        .then(|| first[p] + y * piece.size[0] as usize + x)
                })
                .ok_or_else(|| {
                    Error::Mesh(format!(
                        "cell face {f} lies in no piece of the cover: the cover was made of \
                         another surface"
                    ))
                })?;
            values[slot] = face.value;
        }
        Ok(values)
    }

    /// The vertex scalars of `mesh`, the surface this cover was made of, at the four
    /// corners of every cell of every piece's box (in the order of [`Self::values`]),
    /// each cell's corners at texture-space offsets (0, 0), (1, 0), (1, 1), (0, 1) of
    /// its square; NaN where the piece covers no face. With them a renderer evaluates
    /// the original's piecewise-linear field anywhere on a simplified surface from its
    /// texture coordinates, so that isolines stay where the original draws them, as the
    /// grid lines do. Each cell must be split along its (0, 0)-(1, 1) diagonal, as
    /// every strata-grid surface's cells are: the field is linear on each half.
    pub fn corner_values(&self, mesh: &SurfaceMesh) -> Result<Vec<f32>> {
        if mesh.scalars.len() != mesh.vertex_count() {
            return Err(Error::Mesh(format!(
                "{} scalars for {} vertices: corner values need one per vertex",
                mesh.scalars.len(),
                mesh.vertex_count()
            )));
        }
        let mut first = Vec::with_capacity(self.pieces.len());
        let mut cells = 0;
        for p in &self.pieces {
            first.push(cells);
            cells += p.box_cells();
        }
        let mut corners = vec![f32::NAN; 4 * cells];
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let (cell, at) =
                cell_corners(tri.map(|v| mesh.texcoords[v as usize])).ok_or_else(|| {
                    Error::Mesh(format!(
                        "triangle {t} is not a half of its cell split along the (0, 0)-(1, 1) \
                     diagonal of texture space: the field has no corner values"
                    ))
                })?;
            let slot = self
                .vertex_piece
                .get(tri[0] as usize)
                .and_then(|&p| Some(first.get(p as usize)? + self.pieces[p as usize].slot(cell)?))
                .ok_or_else(|| {
                    Error::Mesh(format!(
                        "triangle {t} lies in no piece of the cover: the cover was made of \
                         another surface"
                    ))
                })?;
            for (v, c) in tri.iter().zip(at) {
                corners[4 * slot + c] = mesh.scalars[*v as usize];
            }
        }
        Ok(corners)
    }

    /// Cells in all the pieces' boxes, covered or not.
    pub fn box_cells(&self) -> usize {
        self.pieces.iter().map(CoverPiece::box_cells).sum()
    }

    /// Appends the pieces of `other`, the cover of a surface appended to this one's
    /// ([`SurfaceMesh::append`]), as pieces of their own; a vertex of no piece (in no
    /// triangle) stays in none.
    pub fn append(&mut self, other: &CellCover) {
        let first = self.pieces.len() as u32;
        self.vertex_piece.extend(
            other
                .vertex_piece
                .iter()
                .map(|&p| if p == u32::MAX { p } else { p + first }),
        );
        self.pieces.extend_from_slice(&other.pieces);
    }

    /// Does the open triangle `uv` (texture coordinates) overlap a cell that `piece`
    /// covers? Touching one along an edge or at a corner is no overlap.
    pub fn triangle_overlaps(&self, piece: u32, uv: [[f64; 2]; 3]) -> bool {
        let Some(p) = self.pieces.get(piece as usize) else {
            return false;
        };
        let side = crate::reference::cross2(uv[0], uv[1], uv[2]);
        if side == 0.0 {
            return false;
        }
        let lo = [0, 1].map(|k| uv.iter().map(|c| c[k]).fold(f64::INFINITY, f64::min));
        let hi = [0, 1].map(|k| uv.iter().map(|c| c[k]).fold(f64::NEG_INFINITY, f64::max));
        // Cells whose open square meets the open box of the triangle.
        let first = [0, 1]
            .map(|k| (((lo[k] - 1.0) * 0.5).floor() as i64).max(i64::from(p.origin[k])) as i32);
        let last = [0, 1].map(|k| {
            ((((hi[k] - 1.0) * 0.5).ceil() as i64) - 1)
                .min(i64::from(p.origin[k]) + i64::from(p.size[k]) - 1) as i32
        });
        for y in first[1]..=last[1] {
            for x in first[0]..=last[0] {
                if !p.covers([x, y]) {
                    continue;
                }
                let x0 = 2.0 * f64::from(x) + 1.0;
                let y0 = 2.0 * f64::from(y) + 1.0;
                let corners = [
                    [x0, y0],
                    [x0 + 2.0, y0],
                    [x0 + 2.0, y0 + 2.0],
                    [x0, y0 + 2.0],
                ];
                // Separated when all four corners lie on or outside one edge's line.
                let separated = (0..3).any(|e| {
                    let (a, b) = (uv[e], uv[(e + 1) % 3]);
                    corners
                        .iter()
                        .all(|&c| crate::reference::cross2(a, b, c) * side <= 0.0)
                });
                if !separated {
                    return true;
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two pieces: cells (0..3, 0..2) less cell (1, 1), and cell (5, 0) apart.
    fn two_pieces() -> SurfaceMesh {
        let mut mesh = SurfaceMesh::with_origin([0.0; 3]);
        for (i, j) in [(0, 0), (1, 0), (2, 0), (0, 1), (2, 1), (5, 0)] {
            let base = mesh.positions.len() as u32;
            for (di, dj) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
                let (u, v) = (i + di, j + dj);
                mesh.positions.push([u as f32, v as f32, 0.0]);
                mesh.texcoords
                    .push([2.0 * u as f32 + 1.0, 2.0 * v as f32 + 1.0]);
            }
            mesh.triangles.push([base, base + 1, base + 2]);
            mesh.triangles.push([base, base + 2, base + 3]);
        }
        // Join the first five cells' copies of shared nodes into one piece by welding.
        let mut weld = std::collections::HashMap::new();
        let mut map = Vec::new();
        for (v, uv) in mesh.texcoords.iter().enumerate() {
            let key = (uv[0] as i32, uv[1] as i32);
            map.push(*weld.entry(key).or_insert(v as u32));
        }
        for t in &mut mesh.triangles {
            *t = t.map(|v| map[v as usize]);
        }
        mesh
    }

    #[test]
    fn pieces_cover_the_cells_of_their_triangles() {
        let mesh = two_pieces();
        let cover = CellCover::of(&mesh).expect("cell faces");
        assert_eq!(cover.pieces.len(), 2);
        let first = &cover.pieces[0];
        assert_eq!((first.origin, first.size), ([0, 0], [3, 2]));
        for cell in [[0, 0], [1, 0], [2, 0], [0, 1], [2, 1]] {
            assert!(first.covers(cell), "{cell:?}");
        }
        for cell in [[1, 1], [3, 0], [-1, 0], [5, 0]] {
            assert!(!first.covers(cell), "{cell:?}");
        }
        assert!(cover.pieces[1].covers([5, 0]));
        let a = cover.vertex_piece[mesh.triangles[0][0] as usize];
        let b = cover.vertex_piece[mesh.triangles[10][0] as usize];
        assert_ne!(a, b);
    }

    #[test]
    fn appended_covers_number_their_pieces_on_and_leave_unused_vertices_in_none() {
        let mut mesh = two_pieces();
        // A vertex no triangle uses, as side walls can have.
        mesh.positions.push([0.0; 3]);
        mesh.texcoords.push([0.0; 2]);
        let cover = CellCover::of(&mesh).expect("cell faces");
        let unused = mesh.vertex_count() - 1;
        assert_eq!(cover.vertex_piece[unused], u32::MAX);
        let mut both = cover.clone();
        both.append(&cover);
        assert_eq!(both.pieces.len(), 4);
        assert_eq!(both.vertex_piece[2 * mesh.vertex_count() - 1], u32::MAX);
        let n = mesh.vertex_count();
        for v in 0..n {
            let (p, q) = (both.vertex_piece[v], both.vertex_piece[n + v]);
            if p == u32::MAX {
                assert_eq!(q, u32::MAX, "vertex {v}");
            } else {
                assert_eq!(q, p + 2, "vertex {v}");
            }
        }
    }

    #[test]
    fn a_triangle_overlaps_covered_cells_not_those_it_touches() {
        let cover = CellCover::of(&two_pieces()).expect("cell faces");
        // Half of the uncovered cell (1, 1), corners on grid nodes: touches only.
        let notch = [[3.0, 3.0], [5.0, 3.0], [5.0, 5.0]];
        assert!(!cover.triangle_overlaps(0, notch));
        // The whole of cell (1, 1) and a sliver of (2, 1).
        assert!(cover.triangle_overlaps(0, [[3.0, 3.0], [5.2, 3.0], [5.0, 5.0]]));
        // Over covered cells, either orientation.
        assert!(cover.triangle_overlaps(0, [[1.0, 1.0], [1.0, 3.0], [3.0, 1.0]]));
        assert!(cover.triangle_overlaps(0, [[1.0, 1.0], [3.0, 1.0], [1.0, 3.0]]));
        // Beyond the box, and a flat triangle.
        assert!(!cover.triangle_overlaps(0, [[7.0, 1.0], [9.0, 1.0], [9.0, 3.0]]));
        assert!(!cover.triangle_overlaps(0, [[1.0, 1.0], [3.0, 1.0], [5.0, 1.0]]));
        // Piece 1 covers only cell (5, 0).
        assert!(cover.triangle_overlaps(1, [[11.0, 1.0], [13.0, 1.0], [13.0, 3.0]]));
        assert!(!cover.triangle_overlaps(1, notch));
    }

    #[test]
    fn values_follow_the_cells_of_each_box() {
        let mut mesh = two_pieces();
        mesh.cell_faces = (0..6)
            .map(|f| strata_grid::CellFace {
                triangles: [2 * f, 2 * f + 1],
                cell: [0; 3],
                value: 10.0 + f as f32,
            })
            .collect();
        let cover = CellCover::of(&mesh).expect("cell faces");
        let values = cover.values(&mesh).expect("values");
        // The first box is 3 x 2 cells with (1, 1) uncovered; the second is cell (5, 0).
        assert_eq!(values.len(), 7);
        assert_eq!(&values[..4], &[10.0, 11.0, 12.0, 13.0]);
        assert!(values[4].is_nan());
        assert_eq!(&values[5..], &[14.0, 15.0]);

        // A cover whose first box misses cells of the mesh was made of another surface.
        let mut smaller = cover.clone();
        smaller.pieces[0].size = [1, 1];
        let err = smaller.values(&mesh).expect_err("cells outside the box");
        assert!(err.to_string().contains("cell face 1"), "{err}");
    }

    #[test]
    fn corner_values_are_the_scalars_at_each_cells_corners() {
        let mut mesh = two_pieces();
        // A field of the node (i, j): 10 i + j, from the texture coordinates.
        mesh.scalars = mesh
            .texcoords
            .iter()
            .map(|uv| 10.0 * (uv[0] - 1.0) * 0.5 + (uv[1] - 1.0) * 0.5)
            .collect();
        let cover = CellCover::of(&mesh).expect("cell faces");
        let corners = cover.corner_values(&mesh).expect("corner values");
        assert_eq!(corners.len(), 4 * 7);
        // Cell (2, 1) of the first box (slot 5), then cell (5, 0) (slot 6).
        assert_eq!(&corners[20..24], &[21.0, 31.0, 32.0, 22.0]);
        assert_eq!(&corners[24..], &[50.0, 60.0, 61.0, 51.0]);
        assert!(corners[16..20].iter().all(|c| c.is_nan()), "cell (1, 1)");

        // Split along the other diagonal, the field is not the one corners describe.
        let mut flipped = mesh.clone();
        let [a, b, c] = flipped.triangles[2];
        let d = flipped.triangles[3][2];
        flipped.triangles[2] = [a, b, d];
        flipped.triangles[3] = [b, c, d];
        let err = cover.corner_values(&flipped).expect_err("other diagonal");
        assert!(err.to_string().contains("triangle 2"), "{err}");
        mesh.scalars.clear();
        assert!(cover.corner_values(&mesh).is_err(), "no scalars");
    }

    #[test]
    fn tiles_cut_a_box_from_its_origin_and_number_its_cells_row_by_row() {
        let piece = CoverPiece {
            origin: [10, 20],
            size: [5, 3],
            bits: Vec::new(),
        };
        assert_eq!(piece.tiles(2), [3, 2]);
        assert_eq!(piece.tile_count(2), 6);
        assert_eq!(piece.tile_box(2, 0), [0, 0, 2, 2]);
        assert_eq!(piece.tile_box(2, 2), [4, 0, 5, 2], "clipped to the box");
        assert_eq!(piece.tile_box(2, 5), [4, 2, 5, 3]);
        assert_eq!(piece.tile_cells(2, 5), 1);
        assert_eq!(piece.tile_slot(2, [10, 20]), Some((0, 0)));
        assert_eq!(piece.tile_slot(2, [13, 21]), Some((1, 3)));
        assert_eq!(piece.tile_slot(2, [14, 21]), Some((2, 1)));
        assert_eq!(piece.tile_slot(2, [13, 22]), Some((4, 1)));
        assert_eq!(piece.tile_slot(2, [15, 20]), None);
        // Every cell in exactly one tile, each tile's places 0.. its cell count.
        let mut seen = vec![Vec::new(); 6];
        for y in 20..23 {
            for x in 10..15 {
                let (t, at) = piece.tile_slot(2, [x, y]).expect("in the box");
                seen[t].push(at);
            }
        }
        for (t, places) in seen.iter().enumerate() {
            let cells = piece.tile_cells(2, t);
            assert_eq!(*places, (0..cells).collect::<Vec<_>>(), "tile {t}");
        }
        // A side as large as the box: one tile, its places the box's slots.
        assert_eq!(piece.tiles(u32::MAX), [1, 1]);
        assert_eq!(piece.tile_box(u32::MAX, 0), [0, 0, 5, 3]);
        assert_eq!(piece.tile_slot(u32::MAX, [13, 22]), Some((0, 13)));
    }

    #[test]
    fn a_triangle_across_cells_is_refused() {
        let mut mesh = two_pieces();
        mesh.texcoords[mesh.triangles[0][1] as usize] = [5.0, 1.0];
        let err = CellCover::of(&mesh).expect_err("spans two cells");
        assert!(err.to_string().contains("triangle 0"), "{err}");
    }
}
