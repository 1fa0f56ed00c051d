//! The attributed triangle mesh every other strata crate consumes: positions in the
//! display frame, global texture coordinates, an optional per-vertex scalar, and, for
//! meshes made of cell faces, which two triangles form each cell quad.

use serde::Serialize;

/// One cell face (quad) of a structured mesh: its two triangles, the cell it belongs
/// to and that cell's property value (NaN when no property was chosen).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CellFace {
    /// Indices into [`SurfaceMesh::triangles`] of the quad's two halves; the edge they
    /// share is the diagonal, which wireframes must not draw.
    pub triangles: [u32; 2],
    /// The cell `[i, j, k]` (0-based), for picking and for colouring by cell.
    pub cell: [u32; 3],
    /// The cell's property value, NaN when no property was chosen or it is undefined.
    pub value: f32,
}

/// A triangle mesh with attributes.
///
/// * `positions` are in the display frame (map x, map y, elevation) relative to
///   `origin`, so that `f32` keeps centimetre precision on UTM-sized coordinates;
/// * `texcoords` are the global wireframe coordinates: on a structured surface, grid
///   lines lie on odd values (node `(a, b)` gets `(2a + 1, 2b + 1)`) and cell
///   interiors on even ones, so they can be interpolated anywhere on the surface;
/// * `scalars` is empty or holds one value per vertex (for isolines and colour maps);
/// * `cell_faces` is empty for plain triangle meshes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceMesh {
    /// Display-frame point (map x, map y, elevation) that positions are relative to.
    pub origin: [f64; 3],
    /// Vertex positions relative to `origin`.
    pub positions: Vec<[f32; 3]>,
    /// Global wireframe coordinates, one pair per vertex (odd on grid lines).
    pub texcoords: Vec<[f32; 2]>,
    /// One scalar per vertex, or empty when the mesh carries none.
    pub scalars: Vec<f32>,
    /// Vertex indices, three per triangle.
    pub triangles: Vec<[u32; 3]>,
    /// The cell quads, each made of two of `triangles`; empty for plain meshes.
    pub cell_faces: Vec<CellFace>,
}

impl SurfaceMesh {
    /// An empty mesh whose positions will be relative to `origin`.
    pub fn with_origin(origin: [f64; 3]) -> Self {
        SurfaceMesh {
            origin,
            ..Default::default()
        }
    }

    /// A structured surface of `ni` x `nj` cells whose node `(i, j)` lies at
    /// `position(i, j)`, with the global coordinates `(2i + 1, 2j + 1)`, each cell face
    /// split along its `(i, j)`-`(i + 1, j + 1)` diagonal as layer surfaces are.
    /// For tests, examples and benchmarks that need a grid without a reservoir model.
    pub fn structured(ni: usize, nj: usize, position: impl Fn(usize, usize) -> [f32; 3]) -> Self {
        let mut mesh = SurfaceMesh::default();
        for j in 0..=nj {
            for i in 0..=ni {
                mesh.positions.push(position(i, j));
                mesh.texcoords
                    .push([(2 * i + 1) as f32, (2 * j + 1) as f32]);
            }
        }
        let node = |i: usize, j: usize| (j * (ni + 1) + i) as u32;
        for j in 0..nj {
            for i in 0..ni {
                let t = mesh.triangles.len() as u32;
                mesh.triangles
                    .push([node(i, j), node(i + 1, j), node(i + 1, j + 1)]);
                mesh.triangles
                    .push([node(i, j), node(i + 1, j + 1), node(i, j + 1)]);
                mesh.cell_faces.push(CellFace {
                    triangles: [t, t + 1],
                    cell: [i as u32, j as u32, 0],
                    value: f32::NAN,
                });
            }
        }
        mesh
    }

    /// Number of vertices (the length of every per-vertex attribute).
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles: two per cell face on a surface made of cell quads.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Whether there is nothing to draw: no triangle (vertices alone draw nothing).
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// Checks the invariants: attribute lengths match, indices are in range, cell
    /// faces name existing triangles.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.positions.len();
        if self.texcoords.len() != n {
            return Err(format!(
                "{} texcoords for {n} vertices",
                self.texcoords.len()
            ));
        }
        if !self.scalars.is_empty() && self.scalars.len() != n {
            return Err(format!("{} scalars for {n} vertices", self.scalars.len()));
        }
        if let Some(t) = self
            .triangles
            .iter()
            .find(|t| t.iter().any(|&v| v as usize >= n))
        {
            return Err(format!("triangle {t:?} indexes past {n} vertices"));
        }
        let nt = self.triangles.len() as u32;
        if let Some(f) = self
            .cell_faces
            .iter()
            .find(|f| f.triangles.iter().any(|&t| t >= nt))
        {
            return Err(format!("cell face {:?} names a missing triangle", f.cell));
        }
        Ok(())
    }

    /// Per triangle, bit `e` set when edge `e` (from corner `e` to corner `(e + 1) % 3`)
    /// is a real edge of the model, clear when it is the diagonal that splits a cell
    /// quad in two. Techniques that draw triangle edges use this so that quad meshes
    /// show cell edges only.
    pub fn edge_mask(&self) -> Vec<u8> {
        let mut mask = vec![0b111u8; self.triangles.len()];
        for face in &self.cell_faces {
            let [a, b] = face.triangles.map(|t| self.triangles[t as usize]);
            for (t, tri, other) in [(face.triangles[0], a, b), (face.triangles[1], b, a)] {
                for e in 0..3 {
                    let (u, v) = (tri[e], tri[(e + 1) % 3]);
                    if other.contains(&u) && other.contains(&v) {
                        mask[t as usize] &= !(1 << e);
                    }
                }
            }
        }
        mask
    }

    /// Appends `other`, re-expressing its positions relative to this mesh's origin.
    pub fn append(&mut self, other: &SurfaceMesh) {
        let base = self.positions.len() as u32;
        let tbase = self.triangles.len() as u32;
        let shift: [f32; 3] = std::array::from_fn(|a| (other.origin[a] - self.origin[a]) as f32);
        self.positions.extend(
            other
                .positions
                .iter()
                .map(|p| [p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]]),
        );
        self.texcoords.extend_from_slice(&other.texcoords);
        if !self.scalars.is_empty() || !other.scalars.is_empty() {
            self.scalars.resize(base as usize, f32::NAN);
            if other.scalars.is_empty() {
                self.scalars.resize(self.positions.len(), f32::NAN);
            } else {
                self.scalars.extend_from_slice(&other.scalars);
            }
        }
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|v| v + base)));
        self.cell_faces
            .extend(other.cell_faces.iter().map(|f| CellFace {
                triangles: f.triangles.map(|t| t + tbase),
                ..*f
            }));
    }

    /// A copy in which every cell face has its own vertices carrying the face's cell
    /// value as scalar, so that colouring by the scalar paints each cell flat (as
    /// reservoir engineers expect), while positions and global texture coordinates,
    /// and so the wireframe, stay the same. Triangles not in a cell face are dropped.
    pub fn with_cell_values(&self) -> SurfaceMesh {
        let mut out = SurfaceMesh::with_origin(self.origin);
        for face in &self.cell_faces {
            let t0 = out.triangles.len() as u32;
            // The face's own vertices, shared by its two triangles: (original, copy).
            let mut copies: Vec<(u32, u32)> = Vec::with_capacity(4);
            for t in face.triangles {
                let tri =
                    self.triangles[t as usize].map(|v| match copies.iter().find(|c| c.0 == v) {
                        Some(&(_, w)) => w,
                        None => {
                            let w = out.positions.len() as u32;
                            out.positions.push(self.positions[v as usize]);
                            out.texcoords.push(self.texcoords[v as usize]);
                            out.scalars.push(face.value);
                            copies.push((v, w));
                            w
                        }
                    });
                out.triangles.push(tri);
            }
            out.cell_faces.push(CellFace {
                triangles: [t0, t0 + 1],
                ..*face
            });
        }
        out
    }

    /// The centre of cell `(i, j)`'s face on a surface of cell faces carrying the
    /// global coordinates (a layer surface at full resolution): the mean of the
    /// corners of the triangles whose texture coordinates lie in that cell. `None`
    /// where the surface has no face of the cell.
    pub fn cell_centre(&self, [i, j]: [u32; 2]) -> Option<[f32; 3]> {
        let (u0, v0) = (2.0 * i as f32 + 1.0, 2.0 * j as f32 + 1.0);
        let inside = |c: f32, lo: f32| c > lo && c < lo + 2.0;
        let mut corners: Vec<u32> = Vec::with_capacity(4);
        for tri in &self.triangles {
            let centroid = |a: usize| {
                tri.iter()
                    .map(|&v| self.texcoords[v as usize][a])
                    .sum::<f32>()
                    / 3.0
            };
            if inside(centroid(0), u0) && inside(centroid(1), v0) {
                for &v in tri {
                    if !corners.contains(&v) {
                        corners.push(v);
                    }
                }
            }
        }
        if corners.is_empty() {
            return None;
        }
        let n = corners.len() as f32;
        Some(std::array::from_fn(|a| {
            corners
                .iter()
                .map(|&v| self.positions[v as usize][a])
                .sum::<f32>()
                / n
        }))
    }

    /// A mesh of only the cell faces that `keep` keeps, their triangles and the
    /// vertices those use, in the order they had (triangles of no cell face go).
    pub fn cell_faces_where(&self, mut keep: impl FnMut(&CellFace) -> bool) -> SurfaceMesh {
        let kept: Vec<&CellFace> = self.cell_faces.iter().filter(|f| keep(f)).collect();
        let mut renumbered = vec![u32::MAX; self.vertex_count()];
        for face in &kept {
            for t in face.triangles {
                for v in self.triangles[t as usize] {
                    renumbered[v as usize] = 0;
                }
            }
        }
        let mut out = SurfaceMesh::with_origin(self.origin);
        for (v, number) in renumbered.iter_mut().enumerate() {
            if *number == u32::MAX {
                continue;
            }
            *number = out.positions.len() as u32;
            out.positions.push(self.positions[v]);
            out.texcoords.push(self.texcoords[v]);
            if let Some(&s) = self.scalars.get(v) {
                out.scalars.push(s);
            }
        }
        for face in kept {
            let t0 = out.triangles.len() as u32;
            out.triangles.extend(
                face.triangles
                    .map(|t| self.triangles[t as usize].map(|v| renumbered[v as usize])),
            );
            out.cell_faces.push(CellFace {
                triangles: [t0, t0 + 1],
                ..*face
            });
        }
        out
    }

    /// Axis-aligned bounds of the positions (relative to `origin`); `None` when empty.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let first = *self.positions.first()?;
        Some(self.positions.iter().fold((first, first), |(lo, hi), p| {
            (
                std::array::from_fn(|a| lo[a].min(p[a])),
                std::array::from_fn(|a| hi[a].max(p[a])),
            )
        }))
    }

    /// Area of triangle `t`.
    pub fn triangle_area(&self, t: usize) -> f32 {
        let [a, b, c] = self.triangles[t].map(|v| self.positions[v as usize]);
        triangle_area(a, b, c)
    }
}

/// Area of the triangle `a b c`.
pub(crate) fn triangle_area(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> f32 {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_quad() -> SurfaceMesh {
        SurfaceMesh {
            origin: [0.0; 3],
            positions: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            texcoords: vec![[1.0, 1.0], [3.0, 1.0], [3.0, 3.0], [1.0, 3.0]],
            scalars: vec![],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            cell_faces: vec![CellFace {
                triangles: [0, 1],
                cell: [0, 0, 0],
                value: f32::NAN,
            }],
        }
    }

    #[test]
    fn structured_grid_has_global_coordinates() {
        let m = SurfaceMesh::structured(3, 2, |i, j| [i as f32, j as f32, 0.0]);
        m.validate().unwrap();
        assert_eq!(
            (m.vertex_count(), m.triangle_count(), m.cell_faces.len()),
            (12, 12, 6)
        );
        assert_eq!(m.texcoords[5], [3.0, 3.0]);
        assert!(m.edge_mask().iter().all(|&e| e.count_ones() == 2));
    }

    #[test]
    fn a_cells_centre_and_a_choice_of_faces() {
        let m = SurfaceMesh::structured(3, 2, |i, j| [i as f32, 2.0 * j as f32, (i * j) as f32]);
        // Corners (1, 1), (2, 1), (1, 2), (2, 2): z 1, 2, 2, 4.
        assert_eq!(m.cell_centre([1, 1]), Some([1.5, 3.0, 2.25]));
        assert_eq!(m.cell_centre([3, 0]), None);
        let column = m.cell_faces_where(|f| f.cell[0] == 1);
        column.validate().unwrap();
        assert_eq!((column.triangle_count(), column.cell_faces.len()), (4, 2));
        // Only the column's own nodes, (1..=2) x (0..=2), and their coordinates.
        assert_eq!(column.vertex_count(), 6);
        assert_eq!(column.texcoords[0], [3.0, 1.0]);
        assert_eq!(column.cell_centre([1, 0]), m.cell_centre([1, 0]));
        assert_eq!(column.cell_centre([0, 0]), None);
    }

    #[test]
    fn cell_values_get_their_own_vertices() {
        let mut m = SurfaceMesh::structured(2, 1, |i, j| [i as f32, j as f32, 0.0]);
        m.cell_faces[0].value = 0.1;
        m.cell_faces[1].value = 0.2;
        let c = m.with_cell_values();
        c.validate().unwrap();
        assert_eq!((c.vertex_count(), c.triangle_count()), (8, 4));
        assert_eq!(c.scalars, vec![0.1, 0.1, 0.1, 0.1, 0.2, 0.2, 0.2, 0.2]);
        // Same geometry and coordinates, triangle by triangle.
        for (a, b) in m.triangles.iter().zip(&c.triangles) {
            for k in 0..3 {
                assert_eq!(m.positions[a[k] as usize], c.positions[b[k] as usize]);
                assert_eq!(m.texcoords[a[k] as usize], c.texcoords[b[k] as usize]);
            }
        }
        assert_eq!(c.edge_mask(), m.edge_mask());
    }

    #[test]
    fn quad_diagonal_is_masked() {
        let m = unit_quad();
        // Triangle 0: edges 0-1, 1-2 real, 2-0 diagonal. Triangle 1: 0-2 diagonal.
        assert_eq!(m.edge_mask(), vec![0b011, 0b110]);
        assert!(m.validate().is_ok());
    }

    #[test]
    fn append_rebases_positions_and_indices() {
        let mut a = unit_quad();
        let mut b = unit_quad();
        b.origin = [10.0, 0.0, 0.0];
        b.scalars = vec![1.0; 4];
        a.append(&b);
        assert_eq!(a.positions[4], [10.0, 0.0, 0.0]);
        assert_eq!(a.triangles[2], [4, 5, 6]);
        assert_eq!(a.cell_faces[1].triangles, [2, 3]);
        assert!(a.scalars[0].is_nan() && a.scalars[4] == 1.0);
        assert!(a.validate().is_ok());
        assert_eq!(a.edge_mask(), vec![0b011, 0b110, 0b011, 0b110]);
    }
}
