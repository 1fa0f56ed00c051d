//! Layer and side surfaces of a grid as attributed triangle meshes with global
//! texture coordinates (Celes & Abraham 2011, section 5, Fig. 11b).
//!
//! A layer surface is the top (or bottom) face of every active cell of one layer.
//! Node `(i, j)` gets texture coordinates `(2i + 1, 2j + 1)`, so every grid line lies
//! on an odd value. A vertex is shared by the cells around a node only where they are
//! edge neighbours with the same corner depth there: faults split the surface,
//! inactive cells leave holes, and faces of pinched-out cells (zero thickness at all
//! four pillars) or of zero area are dropped.
//!
//! Side surfaces are the i and j faces on the outer shell of the active cells and on
//! fault planes, with coordinates `(2j + 1, 2k + 1)` on i faces and `(2i + 1, 2k + 1)`
//! on j faces (node levels `k` = top of layer `k`, `k + 1` its bottom).

use std::collections::HashMap;
use std::ops::Range;

use ndarray::Array3;
use rayon::prelude::*;

use crate::mesh::triangle_area;
use crate::{CellFace, CornerPointGrid, Dims, Error, Result, SurfaceMesh};

/// Which horizontal face of the cells a layer surface is made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Face {
    /// The upper face (ZCORN's first corner level of the layer): what a view from
    /// above sees.
    Top,
    /// The lower face (ZCORN's second corner level): the base of the layer.
    Bottom,
}

impl Face {
    fn dk(self) -> usize {
        match self {
            Face::Top => 0,
            Face::Bottom => 1,
        }
    }
}

/// Faces whose area is below this (m², or squared grid unit) are dropped as degenerate.
const MIN_FACE_AREA: f32 = 1e-6;

/// The per-cell values of `property`, or an error listing what the grid has.
fn cell_values<'g>(
    grid: &'g CornerPointGrid,
    property: Option<&str>,
) -> Result<Option<&'g Array3<f32>>> {
    let Some(name) = property else {
        return Ok(None);
    };
    grid.property(name).map(Some).ok_or_else(|| {
        let mut names: Vec<&str> = grid.properties.keys().map(String::as_str).collect();
        if let Some(step) = grid.report_steps.last() {
            names.extend(step.arrays.keys().map(String::as_str));
        }
        Error::Invalid(format!(
            "no property {name}; the model has: {}",
            if names.is_empty() {
                "none".to_string()
            } else {
                names.join(", ")
            }
        ))
    })
}

/// Is the cell pinched out: zero thickness along all four of its pillars?
fn is_pinched(grid: &CornerPointGrid, i: usize, j: usize, k: usize) -> bool {
    (0..4).all(|c| grid.corner_depth(i, j, k, c) == grid.corner_depth(i, j, k, c + 4))
}

/// Which faces of a grid a surface holds and what its vertices carry: the one request
/// that [`layer_surfaces`] and [`side_surfaces`] take. `property` (static, or from the
/// last report step) gives the per-cell values and, averaged onto nodes on each side
/// of a fault, the per-vertex scalar. Positions are relative to `origin` (display
/// frame, see [`CornerPointGrid::to_display`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Surfaces<'a> {
    /// Layers, 0-based, end exclusive.
    pub layers: Range<usize>,
    /// The property the cells and vertices carry; none when `None`.
    pub property: Option<&'a str>,
    /// Display-frame origin the positions are relative to.
    pub origin: [f64; 3],
    /// The columns whose faces are built, for a layer too large to hold at once or a
    /// close-up; every column when `None`. The nodes on the rectangle's edges take
    /// their values, as in the whole surface, from the cells on both sides, and bands
    /// of whole rows one after another make the whole surface's faces in its order.
    pub columns: Option<Columns>,
    /// Side faces of a run of the layers a scene draws: the scene's layers, whose cells
    /// just outside the run still lend values to the run's nodes, so that runs drawn
    /// one after another colour their shared nodes as the whole scene does; `layers`
    /// when `None`.
    pub scene: Option<Range<usize>>,
    /// A range filter's columns: cells outside them count as absent, so no face is
    /// built there, they lend no value to a node, and the side faces they leave are
    /// open walls (the model cut open, as reservoir tools show a range filter). Unlike
    /// `columns`, which only picks the part of the surfaces to build.
    pub cut: Option<Columns>,
    /// Inactive cells get faces too (not pinched-out ones), with no value (drawn in
    /// the undefined colour): where the model has cells the simulation leaves out.
    pub inactive: bool,
}

impl<'a> Surfaces<'a> {
    /// The faces of `layers` in every column, positions relative to `origin`, carrying
    /// no property.
    pub fn new(layers: Range<usize>, origin: [f64; 3]) -> Self {
        Surfaces {
            layers,
            property: None,
            origin,
            columns: None,
            scene: None,
            cut: None,
            inactive: false,
        }
    }

    /// The faces of layer `k` alone.
    pub fn layer(k: usize, origin: [f64; 3]) -> Self {
        Self::new(k..k + 1, origin)
    }

    /// These faces carrying `property`.
    pub fn property(self, property: Option<&'a str>) -> Self {
        Surfaces { property, ..self }
    }

    /// These faces in `columns` only.
    pub fn columns(self, columns: Columns) -> Self {
        Surfaces {
            columns: Some(columns),
            ..self
        }
    }

    /// These side faces as a run of the layers `scene` draws.
    pub fn among(self, scene: Range<usize>) -> Self {
        Surfaces {
            scene: Some(scene),
            ..self
        }
    }

    /// These faces with inactive cells' too, when `inactive` ([`Surfaces::inactive`]).
    pub fn inactive(self, inactive: bool) -> Self {
        Surfaces { inactive, ..self }
    }

    /// Whether cell `(i, j, k)` has faces on these surfaces: within the cut, not
    /// pinched out, and active unless inactive cells are shown.
    fn shows(&self, grid: &CornerPointGrid, i: usize, j: usize, k: usize) -> bool {
        self.cut.as_ref().is_none_or(|cut| cut.contains(i, j))
            && drawn_cell(grid, [i, j, k], self.inactive)
    }

    /// The value these surfaces give cell `(i, j, k)` of `values`: none for an inactive
    /// cell, whatever a deck says of it.
    fn value_of(&self, grid: &CornerPointGrid, values: &Array3<f32>, [i, j, k]: [usize; 3]) -> f32 {
        if self.inactive && !grid.is_active(i, j, k) {
            f32::NAN
        } else {
            values[[k, j, i]]
        }
    }

    /// These faces cut to the range filter `cut` ([`Surfaces::cut`]); none when `None`.
    pub fn cut(self, cut: Option<Columns>) -> Self {
        Surfaces { cut, ..self }
    }

    /// The columns whose faces are built, of a grid of `dims`: those asked for (refused
    /// when empty or beyond the grid), within the cut (empty where they miss it).
    fn columns_of(&self, dims: Dims) -> Result<Columns> {
        let asked = self.columns.clone().unwrap_or_else(|| Columns::all(dims));
        asked.check(dims)?;
        Ok(match &self.cut {
            Some(cut) => asked.within(cut),
            None => asked,
        })
    }
}

/// A rectangle of columns of cells (0-based, ends exclusive): the part of a layer
/// surface that a band of rows, or a close-up, needs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Columns {
    /// Cell columns along `i`.
    pub i: Range<usize>,
    /// Cell rows along `j`.
    pub j: Range<usize>,
}

impl Columns {
    /// Every column of a grid of `dims`.
    pub fn all(dims: Dims) -> Self {
        Columns {
            i: 0..dims.nx,
            j: 0..dims.ny,
        }
    }

    /// Whether no column is in the rectangle.
    pub fn is_empty(&self) -> bool {
        self.i.is_empty() || self.j.is_empty()
    }

    /// Whether column `(i, j)` is in the rectangle.
    pub fn contains(&self, i: usize, j: usize) -> bool {
        self.i.contains(&i) && self.j.contains(&j)
    }

    /// The columns of both rectangles (empty when they do not meet).
    pub fn within(&self, other: &Columns) -> Columns {
        let meet = |a: &Range<usize>, b: &Range<usize>| {
            let start = a.start.max(b.start);
            start..a.end.min(b.end).max(start)
        };
        Columns {
            i: meet(&self.i, &other.i),
            j: meet(&self.j, &other.j),
        }
    }

    /// These columns and `by` more on every side, within a grid of `dims`.
    pub fn around(&self, by: usize, dims: Dims) -> Columns {
        let widen = |r: &Range<usize>, n: usize| r.start.saturating_sub(by)..(r.end + by).min(n);
        Columns {
            i: widen(&self.i, dims.nx),
            j: widen(&self.j, dims.ny),
        }
    }

    /// Refuses an empty rectangle, or one beyond a grid of `dims`.
    fn check(&self, Dims { nx, ny, .. }: Dims) -> Result<()> {
        let Columns { i, j } = self;
        if self.is_empty() || i.end > nx || j.end > ny {
            return Err(Error::Invalid(format!(
                "columns {}..{} of rows {}..{} are not within the grid's 1..{nx} of 1..{ny}",
                i.start + 1,
                i.end,
                j.start + 1,
                j.end
            )));
        }
        Ok(())
    }

    /// The columns of these in rows `rows`.
    pub fn in_rows(&self, rows: Range<usize>) -> Columns {
        Columns {
            i: self.i.clone(),
            j: self.j.start.max(rows.start)..self.j.end.min(rows.end),
        }
    }
}

/// Corner `(di, dj)` of cell `(i, j)`'s `face` in layer `k`, relative to `origin`
/// (display frame).
fn face_corner(
    grid: &CornerPointGrid,
    [i, j, k]: [usize; 3],
    face: Face,
    [di, dj]: [usize; 2],
    origin: [f64; 3],
) -> [f32; 3] {
    let depth = grid.zcorn[[2 * k + face.dk(), 2 * j + dj, 2 * i + di]];
    let local = grid.point_on_pillar(i + di, j + dj, f64::from(depth));
    CornerPointGrid::to_display(origin, grid.to_map(local))
}

/// The corners (SW, SE, NE, NW; display frame, relative to `origin`) of cell
/// `(i, j, k)`'s `face` where its layer surface has that face: the cell is active,
/// not pinched out, and the face not degenerate. They are the face's vertex
/// positions in the surface, so what frames them frames the surface.
pub fn surface_face_corners(
    grid: &CornerPointGrid,
    cell: [usize; 3],
    face: Face,
    origin: [f64; 3],
) -> Option<[[f32; 3]; 4]> {
    face_corners(grid, cell, face, origin, false)
}

/// [`surface_face_corners`] on surfaces that show inactive cells (`inactive`) or not.
fn face_corners(
    grid: &CornerPointGrid,
    cell: [usize; 3],
    face: Face,
    origin: [f64; 3],
    inactive: bool,
) -> Option<[[f32; 3]; 4]> {
    if !drawn_cell(grid, cell, inactive) {
        return None;
    }
    let [a, b, c, d] =
        [[0, 0], [1, 0], [1, 1], [0, 1]].map(|at| face_corner(grid, cell, face, at, origin));
    face_has_area([a, b, c, d]).then_some([a, b, c, d])
}

/// Visits the faces in `columns` (cells along i) of row `j` of layer `k`'s `face`
/// surface that [`surface_face_corners`] gives (with inactive cells' where
/// `inactive`), in i order, with their corners,
/// computing a corner shared with the face before once. `visit` also hears whether the face's west
/// corners (SW, NW) are those of the face it was given just before: a pass over the
/// corners of a whole model, as a framing, then takes each shared one once.
pub fn visit_row_faces(
    grid: &CornerPointGrid,
    ([j, k], columns, inactive): ([usize; 2], Range<usize>, bool),
    face: Face,
    origin: [f64; 3],
    mut visit: impl FnMut(usize, [[f32; 3]; 4], bool),
) {
    let dk = face.dk();
    let depth = |i: usize, [di, dj]: [usize; 2]| grid.zcorn[[2 * k + dk, 2 * j + dj, 2 * i + di]];
    /// The east corners of the cell before: its i, their depths and places, and
    /// whether it was visited.
    struct East {
        i: usize,
        depths: [u32; 2],
        corners: [[f32; 3]; 2],
        visited: bool,
    }
    let mut east: Option<East> = None;
    for i in columns {
        if !drawn_cell(grid, [i, j, k], inactive) {
            continue;
        }
        let corner = |at: [usize; 2]| face_corner(grid, [i, j, k], face, at, origin);
        let west_depths = [depth(i, [0, 0]), depth(i, [0, 1])].map(f32::to_bits);
        let (sw, nw, west_given) = match east {
            Some(e) if e.i + 1 == i && e.depths == west_depths => {
                (e.corners[0], e.corners[1], e.visited)
            }
            _ => (corner([0, 0]), corner([0, 1]), false),
        };
        let (se, ne) = (corner([1, 0]), corner([1, 1]));
        let corners = [sw, se, ne, nw];
        let visited = face_has_area(corners);
        if visited {
            visit(i, corners, west_given);
        }
        east = Some(East {
            i,
            depths: [depth(i, [1, 0]), depth(i, [1, 1])].map(f32::to_bits),
            corners: [se, ne],
            visited,
        });
    }
}

/// The faces in `columns` of layer `k`'s surface ([`layer_surfaces`]), cells outside
/// `cut` counted as absent.
fn one_layer(
    grid: &CornerPointGrid,
    (k, face): (usize, Face),
    request: &Surfaces,
    columns: &Columns,
) -> Result<SurfaceMesh> {
    let Surfaces {
        property, origin, ..
    } = *request;
    let nz = grid.dims().nz;
    if k >= nz {
        return Err(Error::Invalid(format!(
            "layer {} does not exist: the grid has {nz} layers",
            k + 1
        )));
    }
    columns.check(grid.dims())?;
    let Columns { i: cols, j: rows } = columns;
    let values = cell_values(grid, property)?;
    let dk = face.dk();
    let depth =
        |i: usize, j: usize, di: usize, dj: usize| grid.zcorn[[2 * k + dk, 2 * j + dj, 2 * i + di]];

    // Which cells contribute a face: the rectangle's, and those around it, whose
    // cells share the nodes of its edges or lend their values to them (two rings: a
    // node's value at a border is extrapolated from cells up to two away).
    let Columns {
        i: seen_i,
        j: seen_j,
    } = columns.around(2, grid.dims());
    let width = seen_i.len();
    let kept: Vec<bool> = (0..width * seen_j.len())
        .into_par_iter()
        .map(|c| {
            let cell = [seen_i.start + c % width, seen_j.start + c / width, k];
            request.shows(grid, cell[0], cell[1], k)
                && face_corners(grid, cell, face, origin, request.inactive).is_some()
        })
        .collect();
    let is_kept = |i: isize, j: isize| {
        i >= 0
            && j >= 0
            && seen_i.contains(&(i as usize))
            && seen_j.contains(&(j as usize))
            && kept[(j as usize - seen_j.start) * width + i as usize - seen_i.start]
    };
    let within = |(i, j): (isize, isize)| {
        i >= 0 && j >= 0 && cols.contains(&(i as usize)) && rows.contains(&(j as usize))
    };

    let mut mesh = SurfaceMesh::with_origin(origin);
    // Vertex of each cell corner of the rectangle, laid out like a ZCORN layer:
    // [2 rows][2 columns].
    let row_corners = 2 * cols.len();
    let mut corner_vertex = vec![u32::MAX; 2 * row_corners * rows.len()];
    let corner_at = |i: usize, j: usize, di: usize, dj: usize| {
        (2 * (j - rows.start) + dj) * row_corners + 2 * (i - cols.start) + di
    };
    for pj in rows.start..=rows.end {
        for pi in cols.start..=cols.end {
            // The up to four cells around the node: SW, SE, NW, NE.
            let around: [(isize, isize); 4] = [(-1, -1), (0, -1), (-1, 0), (0, 0)]
                .map(|(a, b)| (pi as isize + a, pj as isize + b));
            let present = around.map(|(i, j)| is_kept(i, j));
            let node_depth = |n: usize| {
                let (i, j) = (around[n].0 as usize, around[n].1 as usize);
                depth(i, j, pi - i, pj - j)
            };
            // Union of edge neighbours that agree on the node's depth.
            let mut group = [0usize, 1, 2, 3];
            for (a, b) in [(0, 1), (0, 2), (1, 3), (2, 3)] {
                if present[a] && present[b] && node_depth(a) == node_depth(b) {
                    let (ga, gb) = (group[a], group[b]);
                    for g in group.iter_mut() {
                        if *g == gb {
                            *g = ga;
                        }
                    }
                }
            }
            let mut vertex_of_group = [u32::MAX; 4];
            // Cells of the rectangle only: those around it lend their values.
            for n in (0..4).filter(|&n| present[n] && within(around[n])) {
                let g = group[n];
                let (i, j) = (around[n].0 as usize, around[n].1 as usize);
                let (di, dj) = (pi - i, pj - j);
                if vertex_of_group[g] == u32::MAX {
                    vertex_of_group[g] = mesh.positions.len() as u32;
                    mesh.positions
                        .push(face_corner(grid, [i, j, k], face, [di, dj], origin));
                    mesh.texcoords
                        .push([(2 * pi + 1) as f32, (2 * pj + 1) as f32]);
                    if let Some(v) = values {
                        let members: Vec<(isize, isize)> = (0..4)
                            .filter(|&m| present[m] && group[m] == g)
                            .map(|m| around[m])
                            .collect();
                        let value = |i: isize, j: isize| {
                            request.value_of(grid, v, [i as usize, j as usize, k])
                        };
                        let joined = |a: (isize, isize), b: (isize, isize)| {
                            let at = |c: (isize, isize), di, dj| {
                                depth(c.0 as usize, c.1 as usize, di, dj).to_bits()
                            };
                            if b.0 > a.0 {
                                at(a, 1, 0) == at(b, 0, 0) && at(a, 1, 1) == at(b, 0, 1)
                            } else {
                                at(a, 0, 1) == at(b, 0, 0) && at(a, 1, 1) == at(b, 1, 0)
                            }
                        };
                        mesh.scalars.push(node_value(
                            [pi as isize, pj as isize],
                            &members,
                            &is_kept,
                            &joined,
                            &value,
                        ));
                    }
                }
                corner_vertex[corner_at(i, j, di, dj)] = vertex_of_group[g];
            }
        }
    }

    for j in rows.clone() {
        for i in cols.clone() {
            if !is_kept(i as isize, j as isize) {
                continue;
            }
            let v = |di: usize, dj: usize| corner_vertex[corner_at(i, j, di, dj)];
            let (v00, v10, v11, v01) = (v(0, 0), v(1, 0), v(1, 1), v(0, 1));
            let t = mesh.triangles.len() as u32;
            mesh.triangles.push([v00, v10, v11]);
            mesh.triangles.push([v00, v11, v01]);
            mesh.cell_faces.push(CellFace {
                triangles: [t, t + 1],
                cell: [i as u32, j as u32, k as u32],
                value: values.map_or(f32::NAN, |v| request.value_of(grid, v, [i, j, k])),
            });
        }
    }
    Ok(mesh)
}

/// The value at node `(pi, pj)` of the side of a layer surface whose cells around it
/// are `members` (one to four of the cells touching it, on one side of any fault).
/// With four, their average. With fewer (the node on an outline, at a hole or an
/// inactive cell, or on a fault), a plane through the members and, where they do
/// not fix one, the cells that continue them away from the node (the next row beyond
/// a pair, the 2 x 2 block beyond a lone cell; each reached across an edge whose
/// corners are `joined`, no fault between), least squares on their centres, taken
/// at the node: an average of fewer cells would take the field half a cell inward,
/// and the isolines of a border cell off by as much. The cells nearest the node only,
/// so that a curved field is no more biased than by the four-cell average inside.
/// Where no plane is fixed (a lone strip of cells), the members' average.
fn node_value(
    [pi, pj]: [isize; 2],
    members: &[(isize, isize)],
    is_kept: &dyn Fn(isize, isize) -> bool,
    joined: &dyn Fn((isize, isize), (isize, isize)) -> bool,
    value: &dyn Fn(isize, isize) -> f32,
) -> f32 {
    let (sum, count) = members
        .iter()
        .map(|&(i, j)| value(i, j))
        .filter(|x| !x.is_nan())
        .fold((0f64, 0u32), |(s, c), x| (s + f64::from(x), c + 1));
    let average = if count == 0 {
        f32::NAN
    } else {
        (sum / f64::from(count)) as f32
    };
    if members.len() == 4 || count == 0 {
        return average;
    }
    // Away from the node, per axis, for a cell touching it.
    let away = |(i, j): (isize, isize)| (if i < pi { -1 } else { 1 }, if j < pj { -1 } else { 1 });
    let mut cells: Vec<(isize, isize)> = members.to_vec();
    let extend = |cells: &mut Vec<(isize, isize)>, from: (isize, isize), to: (isize, isize)| {
        let (a, b) = if to.0 + to.1 > from.0 + from.1 {
            (from, to)
        } else {
            (to, from)
        };
        if cells.contains(&from) && !cells.contains(&to) && is_kept(to.0, to.1) && joined(a, b) {
            cells.push(to);
        }
    };
    match members {
        [a, b] => {
            // A pair along a row continues in the next row away, along a column in the
            // next column.
            for &m in [a, b] {
                let (di, dj) = away(m);
                let next = if a.1 == b.1 {
                    (m.0, m.1 + dj)
                } else {
                    (m.0 + di, m.1)
                };
                extend(&mut cells, m, next);
            }
        }
        [m] => {
            let (di, dj) = away(*m);
            let (across, up, beyond) = ((m.0 + di, m.1), (m.0, m.1 + dj), (m.0 + di, m.1 + dj));
            extend(&mut cells, *m, across);
            extend(&mut cells, *m, up);
            extend(&mut cells, across, beyond);
            extend(&mut cells, up, beyond);
        }
        _ => {}
    }
    // Least squares plane a + b x + c y on the cell centres, relative to the node.
    let mut normal = [[0f64; 3]; 3];
    let mut rhs = [0f64; 3];
    for &(i, j) in &cells {
        let f = value(i, j);
        if f.is_nan() {
            continue;
        }
        let row = [1.0, i as f64 + 0.5 - pi as f64, j as f64 + 0.5 - pj as f64];
        for r in 0..3 {
            for c in 0..3 {
                normal[r][c] += row[r] * row[c];
            }
            rhs[r] += row[r] * f64::from(f);
        }
    }
    match solve3(normal, rhs) {
        Some([a, _, _]) => a as f32,
        None => average,
    }
}

/// The solution of the 3 x 3 system `m x = rhs` (Cramer's rule), `None` where `m` is
/// near singular (points in a line, or fewer than three).
fn solve3(m: [[f64; 3]; 3], rhs: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(m);
    let scale = m.iter().flatten().fold(0f64, |s, v| s.max(v.abs()));
    // (NaN fails too.)
    if d.abs().partial_cmp(&(1e-9 * scale.powi(3))) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    Some(std::array::from_fn(|col| {
        let mut mc = m;
        for r in 0..3 {
            mc[r][col] = rhs[r];
        }
        det(mc) / d
    }))
}

/// The layer surfaces (top or bottom faces, `face`) of what `request` asks for,
/// stacked into one mesh in layer order (built in parallel).
pub fn layer_surfaces(
    grid: &CornerPointGrid,
    face: Face,
    request: &Surfaces,
) -> Result<SurfaceMesh> {
    let columns = request.columns_of(grid.dims())?;
    let origin = request.origin;
    if columns.is_empty() {
        return Ok(SurfaceMesh::with_origin(origin));
    }
    if request.layers.len() == 1 {
        return one_layer(grid, (request.layers.start, face), request, &columns);
    }
    let meshes = request
        .layers
        .clone()
        .into_par_iter()
        .map(|k| one_layer(grid, (k, face), request, &columns))
        .collect::<Result<Vec<_>>>()?;
    let mut all = SurfaceMesh::with_origin(origin);
    for m in &meshes {
        all.append(m);
    }
    Ok(all)
}

/// Side faces of the cells of `request`'s layers: every i or j face of an active,
/// non-pinched cell whose neighbour across it is missing, inactive or pinched, or
/// split from it by a fault. Fault walls thus show both cells' faces, each with its
/// own wireframe.
pub fn side_surfaces(grid: &CornerPointGrid, request: &Surfaces) -> Result<SurfaceMesh> {
    let columns = request.columns_of(grid.dims())?;
    let scene = request
        .scene
        .clone()
        .unwrap_or_else(|| request.layers.clone());
    if columns.is_empty() {
        return Ok(SurfaceMesh::with_origin(request.origin));
    }
    side_faces_among(grid, request, scene, &columns)
}

/// Whether cell `(i, j, k)` has faces on the surfaces: active and not pinched out.
pub fn has_faces(grid: &CornerPointGrid, i: usize, j: usize, k: usize) -> bool {
    drawn_cell(grid, [i, j, k], false)
}

/// Whether cell `(i, j, k)` has faces on surfaces that show inactive cells
/// (`inactive`) or not: not pinched out, and active unless inactive cells are shown.
pub fn drawn_cell(grid: &CornerPointGrid, [i, j, k]: [usize; 3], inactive: bool) -> bool {
    (inactive || grid.is_active(i, j, k)) && !is_pinched(grid, i, j, k)
}

/// Which side faces of cell `(i, j, k)`, one that [`has_faces`], are open (west,
/// east, south, north, on pillar lines i, i + 1, j, j + 1): those whose neighbour is
/// missing, has no faces (`has_faces(i, j)` on layer k), or is split from it by a
/// fault.
pub fn open_sides(
    grid: &CornerPointGrid,
    [i, j, k]: [usize; 3],
    has_faces: impl Fn(usize, usize) -> bool,
) -> [bool; 4] {
    let Dims { nx, ny, .. } = grid.dims();
    [
        i == 0 || !has_faces(i - 1, j) || grid.i_face_faulted(i - 1, j, k),
        i + 1 == nx || !has_faces(i + 1, j) || grid.i_face_faulted(i, j, k),
        j == 0 || !has_faces(i, j - 1) || grid.j_face_faulted(i, j - 1, k),
        j + 1 == ny || !has_faces(i, j + 1) || grid.j_face_faulted(i, j, k),
    ]
}

/// The planes and sides of the faces [`open_sides`] lists, in its order.
const SIDES: [(Plane, usize); 4] = [(Plane::I, 0), (Plane::I, 1), (Plane::J, 0), (Plane::J, 1)];

/// The corners of cell `(i, j, k)`'s side face `side` (in [`open_sides`]' order;
/// display frame, relative to `origin`), as the side surfaces place its vertices, and
/// whether they keep it as a face: a degenerate one leaves its vertices alone.
pub fn side_face_corners(
    grid: &CornerPointGrid,
    cell: [usize; 3],
    side: usize,
    origin: [f64; 3],
) -> ([[f32; 3]; 4], bool) {
    let (plane, facing) = SIDES[side];
    let corners =
        SideBuilder::corners(plane, cell, facing, grid).map(|key| key_point(grid, key, origin));
    (corners, face_has_area(corners))
}

/// Whether a face of corners `[a, b, c, d]` (two triangles, a b c and a c d) is not
/// degenerate.
fn face_has_area([a, b, c, d]: [[f32; 3]; 4]) -> bool {
    triangle_area(a, b, c) + triangle_area(a, c, d) >= MIN_FACE_AREA
}

/// The side faces of `layers` in `columns`, as a run of `scene` ([`Surfaces::scene`]),
/// cells outside `cut` counted as absent.
fn side_faces_among(
    grid: &CornerPointGrid,
    request: &Surfaces,
    scene: Range<usize>,
    columns: &Columns,
) -> Result<SurfaceMesh> {
    let Surfaces {
        property, origin, ..
    } = *request;
    let layers = request.layers.clone();
    let nz = grid.dims().nz;
    if scene.end > nz || layers.is_empty() || layers.start < scene.start || layers.end > scene.end {
        return Err(Error::Invalid(format!(
            "layers {}..{} are not within the {}..{} drawn of the grid's 1..{nz}",
            layers.start + 1,
            layers.end,
            scene.start + 1,
            scene.end
        )));
    }
    columns.check(grid.dims())?;
    let Columns { i: cols, j: rows } = columns;
    let values = cell_values(grid, property)?;
    let mut builder = SideBuilder {
        grid,
        origin,
        mesh: SurfaceMesh::with_origin(origin),
        vertices: HashMap::new(),
        sums: Vec::new(),
        with_scalar: values.is_some(),
    };
    // With values, the cells beside the columns share nodes with their faces and
    // lend them values. Which cells have open sides depends on the cells beside them.
    let lending = usize::from(builder.with_scalar);
    let Columns {
        i: seen_i,
        j: seen_j,
    } = columns.around(lending, grid.dims());
    let Columns {
        i: tested_i,
        j: tested_j,
    } = columns.around(lending + 1, grid.dims());
    let width = tested_i.len();
    let open_cells = |k: usize| -> Vec<(Cell, [bool; 4])> {
        // Which cells have faces, found in parallel: most cells have no open side,
        // and testing them is most of the work. The faces are then added in (j, i)
        // order.
        let with_faces: Vec<bool> = (0..width * tested_j.len())
            .into_par_iter()
            .map(|c| {
                let (i, j) = (tested_i.start + c % width, tested_j.start + c / width);
                request.shows(grid, i, j, k)
            })
            .collect();
        let with_faces =
            |i: usize, j: usize| with_faces[(j - tested_j.start) * width + i - tested_i.start];
        seen_j
            .clone()
            .into_par_iter()
            .flat_map_iter(|j| {
                seen_i.clone().filter_map(move |i| {
                    if !with_faces(i, j) {
                        return None;
                    }
                    let open = open_sides(grid, [i, j, k], with_faces);
                    open.contains(&true).then(|| {
                        let cell = Cell {
                            ijk: [i, j, k],
                            centre: cell_centre(grid, origin, [i, j, k]),
                            value: values
                                .map_or(f32::NAN, |v| request.value_of(grid, v, [i, j, k])),
                        };
                        (cell, open)
                    })
                })
            })
            .collect()
    };
    // The run's own faces in the columns first; then, for the values alone, those of
    // the cells beside the columns, and of the scene's layers just outside the run.
    let inside = |cell: &Cell| cols.contains(&cell.ijk[0]) && rows.contains(&cell.ijk[1]);
    let mut lenders: Vec<(Cell, [bool; 4])> = Vec::new();
    for k in layers.clone() {
        for (cell, open) in open_cells(k) {
            if !inside(&cell) {
                lenders.push((cell, open));
                continue;
            }
            for ((plane, side), _) in SIDES.into_iter().zip(open).filter(|(_, o)| *o) {
                builder.face(plane, &cell, side);
            }
        }
    }
    if builder.with_scalar {
        let neighbours = [
            (layers.start > scene.start).then(|| layers.start - 1),
            (layers.end < scene.end).then_some(layers.end),
        ];
        for k in neighbours.into_iter().flatten() {
            lenders.extend(open_cells(k));
        }
        for (cell, open) in &lenders {
            for ((plane, side), _) in SIDES.into_iter().zip(*open).filter(|(_, o)| *o) {
                builder.add_value(plane, cell, side);
            }
        }
    }
    Ok(builder.finish())
}

#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum Plane {
    /// A face on a pillar line of constant i (coordinates from j and k).
    I,
    /// A face on a pillar line of constant j (coordinates from i and k).
    J,
}

/// What a side vertex is shared by: (plane, facing side, pillar i, pillar j, node
/// level, depth bits).
type VertexKey = (Plane, usize, usize, usize, usize, u32);

/// Accumulates side faces, sharing vertices between faces of the same plane and
/// facing whose corners coincide.
struct SideBuilder<'g> {
    grid: &'g CornerPointGrid,
    origin: [f64; 3],
    mesh: SurfaceMesh,
    vertices: HashMap<VertexKey, u32>,
    /// Per vertex: sum and count of the cell values around it.
    sums: Vec<(f64, u32)>,
    with_scalar: bool,
}

/// Where the side vertex of `key` lies, relative to `origin` (display frame).
fn key_point(grid: &CornerPointGrid, key: VertexKey, origin: [f64; 3]) -> [f32; 3] {
    let (_, _, pi, pj, _, depth) = key;
    let local = grid.point_on_pillar(pi, pj, f64::from(f32::from_bits(depth)));
    CornerPointGrid::to_display(origin, grid.to_map(local))
}

/// A cell whose side faces are being added: its indices, the centre its faces turn
/// away from, and its property value.
struct Cell {
    ijk: [usize; 3],
    centre: [f64; 3],
    value: f32,
}

/// The centre of cell `(i, j, k)` in the display frame of `origin`: the mean of its
/// corners.
fn cell_centre(grid: &CornerPointGrid, origin: [f64; 3], [i, j, k]: [usize; 3]) -> [f64; 3] {
    grid.cell_corners(i, j, k).iter().fold([0.0; 3], |sum, c| {
        let p = CornerPointGrid::to_display(origin, *c);
        std::array::from_fn(|a| sum[a] + f64::from(p[a]) / 8.0)
    })
}

impl SideBuilder<'_> {
    /// The face of `cell` on its `side` (0: low, 1: high) of `plane`: per corner, in
    /// order around the face, its pillar, node level and depth, the key its vertex is
    /// shared by.
    fn corners(
        plane: Plane,
        [i, j, k]: [usize; 3],
        side: usize,
        grid: &CornerPointGrid,
    ) -> [VertexKey; 4] {
        // Corners (along, level): along runs over the face's two pillars.
        [(0, 0), (1, 0), (1, 1), (0, 1)].map(|(along, dk)| {
            let c = match plane {
                Plane::I => side + 2 * along + 4 * dk,
                Plane::J => along + 2 * side + 4 * dk,
            };
            let (pi, pj) = (i + (c & 1), j + ((c >> 1) & 1));
            let depth = grid.corner_depth(i, j, k, c);
            (plane, side, pi, pj, k + dk, depth.to_bits())
        })
    }

    /// Adds `value` to the nodes of the face of `cell` on its `side` of `plane` that
    /// the faces added so far have, without adding the face.
    fn add_value(&mut self, plane: Plane, cell: &Cell, side: usize) {
        if cell.value.is_nan() {
            return;
        }
        for key in Self::corners(plane, cell.ijk, side, self.grid) {
            if let Some(&id) = self.vertices.get(&key) {
                let s = &mut self.sums[id as usize];
                s.0 += f64::from(cell.value);
                s.1 += 1;
            }
        }
    }

    /// Adds the face of `cell` on its `side` (0: low, 1: high) of `plane`.
    fn face(&mut self, plane: Plane, cell: &Cell, side: usize) {
        let ([i, j, k], value, centre) = (cell.ijk, cell.value, cell.centre);
        let mut ids = [0u32; 4];
        let mut pts = [[0f32; 3]; 4];
        for (n, key) in Self::corners(plane, cell.ijk, side, self.grid)
            .into_iter()
            .enumerate()
        {
            let (_, _, pi, pj, level, _) = key;
            let point = key_point(self.grid, key, self.origin);
            pts[n] = point;
            let along_node = if plane == Plane::I { pj } else { pi };
            let next = self.mesh.positions.len() as u32;
            let id = *self.vertices.entry(key).or_insert(next);
            if id == next {
                self.mesh.positions.push(point);
                self.mesh
                    .texcoords
                    .push([(2 * along_node + 1) as f32, (2 * level + 1) as f32]);
                self.sums.push((0.0, 0));
            }
            if !value.is_nan() {
                let s = &mut self.sums[id as usize];
                s.0 += f64::from(value);
                s.1 += 1;
            }
            ids[n] = id;
        }
        if !face_has_area(pts) {
            return;
        }
        // Wound counter-clockwise seen from outside the cell (the normal by the
        // right-hand rule points away from its centre), whatever the handedness of
        // the grid's axes in map coordinates, so that a viewer can leave out the faces
        // that turn their back to the eye: a closed set of cells hides them.
        let sub = |p: [f32; 3], q: [f32; 3]| -> [f64; 3] {
            std::array::from_fn(|a| f64::from(p[a]) - f64::from(q[a]))
        };
        let (d0, d1) = (sub(pts[2], pts[0]), sub(pts[3], pts[1]));
        let normal = [
            d0[1] * d1[2] - d0[2] * d1[1],
            d0[2] * d1[0] - d0[0] * d1[2],
            d0[0] * d1[1] - d0[1] * d1[0],
        ];
        let outward: f64 = (0..3)
            .map(|a| {
                let face = pts.iter().map(|p| f64::from(p[a])).sum::<f64>() / 4.0;
                normal[a] * (face - centre[a])
            })
            .sum();
        let t = self.mesh.triangles.len() as u32;
        if outward >= 0.0 {
            self.mesh.triangles.push([ids[0], ids[1], ids[2]]);
            self.mesh.triangles.push([ids[0], ids[2], ids[3]]);
        } else {
            self.mesh.triangles.push([ids[0], ids[2], ids[1]]);
            self.mesh.triangles.push([ids[0], ids[3], ids[2]]);
        }
        self.mesh.cell_faces.push(CellFace {
            triangles: [t, t + 1],
            cell: [i as u32, j as u32, k as u32],
            value,
        });
    }

    fn finish(mut self) -> SurfaceMesh {
        if self.with_scalar {
            self.mesh.scalars = self
                .sums
                .iter()
                .map(|&(s, c)| {
                    if c == 0 {
                        f32::NAN
                    } else {
                        (s / f64::from(c)) as f32
                    }
                })
                .collect();
        }
        self.mesh
    }
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::*;
    use crate::synth::{SynthParams, generate};

    fn faulted() -> CornerPointGrid {
        generate(&SynthParams {
            nx: 24,
            ny: 18,
            nz: 5,
            faults: 4,
            seed: 11,
        })
        .unwrap()
    }

    /// Kept cells of layer k: active and not pinched.
    fn kept(g: &CornerPointGrid, i: usize, j: usize, k: usize) -> bool {
        g.is_active(i, j, k) && !is_pinched(g, i, j, k)
    }

    #[test]
    fn texcoords_are_global_odd_values_at_every_corner() {
        let g = faulted();
        let origin = g.display_origin();
        for k in 0..g.dims().nz {
            let m = layer_surfaces(
                &g,
                Face::Top,
                &Surfaces::layer(k, origin).property(Some("PORO")),
            )
            .unwrap();
            m.validate().unwrap();
            assert_eq!(m.scalars.len(), m.vertex_count());
            for f in &m.cell_faces {
                let [i, j, _] = f.cell.map(|c| c as usize);
                let [a, b] = f.triangles.map(|t| m.triangles[t as usize]);
                // [v00, v10, v11] and [v00, v11, v01]
                let corners = [(a[0], 0, 0), (a[1], 1, 0), (a[2], 1, 1), (b[2], 0, 1)];
                for (v, di, dj) in corners {
                    let tc = m.texcoords[v as usize];
                    assert_eq!(tc, [(2 * (i + di) + 1) as f32, (2 * (j + dj) + 1) as f32]);
                    let want =
                        CornerPointGrid::to_display(origin, g.cell_corners(i, j, k)[di + 2 * dj]);
                    let got = m.positions[v as usize];
                    assert!(
                        (0..3).all(|a| (got[a] - want[a]).abs() < 1e-3),
                        "{got:?} vs {want:?}"
                    );
                }
                assert_eq!(f.value, g.property("PORO").unwrap()[[k, j, i]]);
            }
        }
    }

    #[test]
    fn holes_and_pinchouts_leave_no_faces() {
        let g = faulted();
        let d = g.dims();
        let mut saw_hole = false;
        let mut saw_pinch = false;
        for k in 0..d.nz {
            let m = layer_surfaces(&g, Face::Top, &Surfaces::layer(k, [0.0; 3])).unwrap();
            let faces: Vec<[u32; 3]> = m.cell_faces.iter().map(|f| f.cell).collect();
            for j in 0..d.ny {
                for i in 0..d.nx {
                    let has = faces.contains(&[i as u32, j as u32, k as u32]);
                    assert_eq!(has, kept(&g, i, j, k), "cell {i},{j},{k}");
                    saw_hole |= !g.is_active(i, j, k);
                    saw_pinch |= g.is_active(i, j, k) && is_pinched(&g, i, j, k);
                }
            }
            assert_eq!(m.triangle_count(), 2 * m.cell_faces.len());
        }
        assert!(
            saw_hole && saw_pinch,
            "the generator must build holes and pinch-outs"
        );
    }

    #[test]
    fn faults_split_vertices_and_blocks_are_watertight() {
        let g = faulted();
        let d = g.dims();
        let k = 1;
        let m = layer_surfaces(&g, Face::Top, &Surfaces::layer(k, [0.0; 3])).unwrap();
        // Vertex of each (cell, corner).
        let mut corner_vertex = HashMap::new();
        for f in &m.cell_faces {
            let [a, b] = f.triangles.map(|t| m.triangles[t as usize]);
            let (i, j) = (f.cell[0] as usize, f.cell[1] as usize);
            for (v, di, dj) in [(a[0], 0, 0), (a[1], 1, 0), (a[2], 1, 1), (b[2], 0, 1)] {
                corner_vertex.insert((i, j, di, dj), v);
            }
        }
        let mut splits = 0;
        for j in 0..d.ny {
            for i in 0..d.nx - 1 {
                if !(kept(&g, i, j, k) && kept(&g, i + 1, j, k)) {
                    continue;
                }
                for dj in 0..2 {
                    let same_depth =
                        g.corner_depth(i, j, k, 1 + 2 * dj) == g.corner_depth(i + 1, j, k, 2 * dj);
                    let shared = corner_vertex[&(i, j, 1, dj)] == corner_vertex[&(i + 1, j, 0, dj)];
                    assert_eq!(
                        shared,
                        same_depth,
                        "node ({}, {}) between cells {i} and {}",
                        i + 1,
                        j + dj,
                        i + 1
                    );
                    splits += usize::from(!same_depth);
                }
            }
        }
        assert!(splits > 0, "the generated faults must split the layer");

        // Every edge used once lies on the model's border, next to a missing cell or
        // on a faulted face: inside a fault block the surface is closed.
        let mut uses: HashMap<(u32, u32), usize> = HashMap::new();
        for t in &m.triangles {
            for e in 0..3 {
                let (a, b) = (t[e], t[(e + 1) % 3]);
                *uses.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        assert!(uses.values().all(|&n| n <= 2), "non-manifold edge");
        for f in &m.cell_faces {
            let (i, j) = (f.cell[0] as usize, f.cell[1] as usize);
            let v = |di, dj| corner_vertex[&(i, j, di, dj)];
            let edge = |a: u32, b: u32| uses[&(a.min(b), a.max(b))];
            let east_open = i + 1 == d.nx || !kept(&g, i + 1, j, k) || g.i_face_faulted(i, j, k);
            let north_open = j + 1 == d.ny || !kept(&g, i, j + 1, k) || g.j_face_faulted(i, j, k);
            if !east_open {
                assert_eq!(
                    edge(v(1, 0), v(1, 1)),
                    2,
                    "east edge of cell {i},{j} is open"
                );
            }
            if !north_open {
                assert_eq!(
                    edge(v(0, 1), v(1, 1)),
                    2,
                    "north edge of cell {i},{j} is open"
                );
            }
        }
    }

    #[test]
    fn side_faces_wind_outward_from_their_cells() {
        let mut mirrored = faulted();
        // MAPAXES with y pointing south: the grid's axes are left-handed on the map.
        mirrored.mapaxes = Some(crate::MapAxes::from_values([0.0, -1.0, 0.0, 0.0, 1.0, 0.0]));
        for g in [faulted(), mirrored] {
            let origin = g.display_origin();
            let sides = side_surfaces(&g, &Surfaces::new(0..g.dims().nz, origin)).unwrap();
            let (mut outward, mut inward) = (0, 0);
            for f in &sides.cell_faces {
                let [i, j, k] = f.cell.map(|c| c as usize);
                let centre = g.cell_corners(i, j, k).iter().fold([0f32; 3], |sum, c| {
                    let p = CornerPointGrid::to_display(origin, *c);
                    std::array::from_fn(|a| sum[a] + p[a] / 8.0)
                });
                for t in f.triangles {
                    let [a, b, c] =
                        sides.triangles[t as usize].map(|v| sides.positions[v as usize]);
                    let (u, v) = (
                        [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
                        [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
                    );
                    let n = [
                        u[1] * v[2] - u[2] * v[1],
                        u[2] * v[0] - u[0] * v[2],
                        u[0] * v[1] - u[1] * v[0],
                    ];
                    let away: f32 = (0..3)
                        .map(|x| n[x] * ((a[x] + b[x] + c[x]) / 3.0 - centre[x]))
                        .sum();
                    // (A face whose top or bottom edge is pinched has a triangle of
                    // no area, which faces nowhere.)
                    if away > 0.0 {
                        outward += 1;
                    } else if away < 0.0 {
                        inward += 1;
                    }
                }
            }
            assert!(
                outward > 1000 && inward == 0,
                "{outward} triangles wind outward, {inward} inward"
            );
        }
    }

    /// Position, texture coordinates and value (as bits) of vertex `v` of `m`.
    type Corner = ([f32; 3], [f32; 2], u32);

    fn corner(m: &SurfaceMesh, v: u32) -> Corner {
        let v = v as usize;
        (m.positions[v], m.texcoords[v], m.scalars[v].to_bits())
    }

    /// The faces of `m` with their cells and corners, sorted: pieces of a surface
    /// appended in any order give the whole's.
    fn sorted_faces(m: &SurfaceMesh) -> Vec<([u32; 3], Vec<Corner>)> {
        let mut faces: Vec<_> = m
            .cell_faces
            .iter()
            .map(|f| {
                let triangles = f.triangles.iter().flat_map(|&t| m.triangles[t as usize]);
                (f.cell, triangles.map(|v| corner(m, v)).collect())
            })
            .collect();
        faces.sort_by(|a, b| a.partial_cmp(b).expect("finite corners"));
        faces
    }

    /// The rectangles of columns that cuts `across` i and `along` j make.
    fn rectangles<const I: usize, const J: usize>(
        across: [Range<usize>; I],
        along: [Range<usize>; J],
    ) -> impl Iterator<Item = Columns> {
        across
            .into_iter()
            .flat_map(move |i| along.clone().map(|j| Columns { i: i.clone(), j }))
    }

    /// The faces in `columns` of `g`'s layer 2 with PORO, checked, and with every
    /// vertex used: the cells around the columns lend values, not nodes.
    fn layer_2_in(g: &CornerPointGrid, face: Face, columns: &Columns) -> SurfaceMesh {
        let piece = layer_surfaces(
            g,
            face,
            &Surfaces::layer(2, g.display_origin())
                .property(Some("PORO"))
                .columns(columns.clone()),
        );
        let piece = piece.unwrap();
        piece.validate().unwrap();
        let mut used = vec![false; piece.vertex_count()];
        piece
            .triangles
            .iter()
            .flatten()
            .for_each(|&v| used[v as usize] = true);
        assert!(
            used.iter().all(|&u| u),
            "{columns:?}: a vertex no face uses"
        );
        piece
    }

    #[test]
    fn bands_of_rows_make_the_whole_layer_surface() {
        // The faulted grid's layer 2, top and bottom, as bands of 1, 6 and 11 rows: the
        // faces, band after band, carry the whole surface's corners, coordinates and
        // node values (averaged over the faulted nodes' cells across band edges).
        let g = faulted();
        let origin = g.display_origin();
        let corners = |m: &SurfaceMesh| -> Vec<Corner> {
            m.triangles
                .iter()
                .flatten()
                .map(|&v| corner(m, v))
                .collect()
        };
        for face in [Face::Top, Face::Bottom] {
            let whole =
                layer_surfaces(&g, face, &Surfaces::layer(2, origin).property(Some("PORO")))
                    .unwrap();
            let mut bands = SurfaceMesh::with_origin(origin);
            for rows in [0..1, 1..7, 7..18] {
                let columns = Columns::all(g.dims()).in_rows(rows);
                bands.append(&layer_2_in(&g, face, &columns));
            }
            assert!(whole.triangle_count() > 500);
            assert_eq!(bands.cell_faces.len(), whole.cell_faces.len());
            let cells = |m: &SurfaceMesh| m.cell_faces.iter().map(|f| f.cell).collect::<Vec<_>>();
            assert_eq!(cells(&bands), cells(&whole));
            assert!(
                corners(&bands) == corners(&whole),
                "{face:?}: corners differ"
            );
        }
        let beyond = |i, j| {
            layer_surfaces(
                &g,
                Face::Top,
                &Surfaces::layer(2, origin).columns(Columns { i, j }.clone()),
            )
        };
        assert!(beyond(0..24, 10..19).is_err());
        assert!(beyond(3..25, 0..18).is_err());
        assert!(beyond(0..24, 4..4).is_err());
        // A range filter keeps the faces of its cells alone; one that misses the grid
        // keeps none, and that is no error.
        let cut = |i, j| {
            let request = Surfaces::layer(2, origin).cut(Some(Columns { i, j }));
            layer_surfaces(&g, Face::Top, &request).unwrap()
        };
        let kept = cut(5..12, 3..9);
        assert!(!kept.cell_faces.is_empty());
        assert!(kept.cell_faces.iter().all(|f| {
            let [i, j, _] = f.cell.map(|c| c as usize);
            (5..12).contains(&i) && (3..9).contains(&j)
        }));
        assert!(cut(30..40, 0..5).is_empty());
    }

    #[test]
    fn rectangles_of_columns_hold_the_whole_surfaces_faces() {
        // The faulted grid's layer 2 cut into six rectangles of columns, whose edges
        // cross faults: every face of the whole surface is in exactly one, with the
        // same corners, coordinates and node values, and no rectangle holds a vertex
        // none of its faces uses.
        let g = faulted();
        let origin = g.display_origin();
        for face in [Face::Top, Face::Bottom] {
            let whole =
                layer_surfaces(&g, face, &Surfaces::layer(2, origin).property(Some("PORO")))
                    .unwrap();
            let mut pieces = SurfaceMesh::with_origin(origin);
            for columns in rectangles([0..5, 5..17, 17..24], [0..9, 9..18]) {
                pieces.append(&layer_2_in(&g, face, &columns));
            }
            assert!(whole.triangle_count() > 500);
            assert!(
                sorted_faces(&pieces) == sorted_faces(&whole),
                "{face:?}: faces differ"
            );
        }
    }

    #[test]
    fn the_corners_of_a_surface_face_are_its_vertices() {
        // surface_face_corners names the faces a layer surface keeps, with their
        // vertices' positions, bit for bit; pinched and inactive cells have none.
        let g = faulted();
        let origin = g.display_origin();
        let d = g.dims();
        for face in [Face::Top, Face::Bottom] {
            let m = layer_surfaces(&g, face, &Surfaces::layer(3, origin)).unwrap();
            let mut faces = m.cell_faces.iter();
            for j in 0..d.ny {
                for i in 0..d.nx {
                    let Some(corners) = surface_face_corners(&g, [i, j, 3], face, origin) else {
                        assert!(
                            !m.cell_faces
                                .iter()
                                .any(|f| f.cell == [i, j, 3].map(|c| c as u32))
                        );
                        continue;
                    };
                    let f = faces.next().expect("a face for each kept cell");
                    assert_eq!(f.cell, [i as u32, j as u32, 3]);
                    let [a, b] = f.triangles.map(|t| m.triangles[t as usize]);
                    let vertices = [a[0], a[1], a[2], b[2]].map(|v| m.positions[v as usize]);
                    assert_eq!(vertices, corners);
                }
            }
            assert!(faces.next().is_none());
            assert!(m.triangle_count() > 500);
            // Row by row, the same faces and corners; a face's west corners are said
            // to be the one before's exactly where that face is its neighbour and
            // shares those two vertices.
            let mut faces = m.cell_faces.iter();
            let (mut shared, mut before) = (0, None);
            for j in 0..d.ny {
                let row = ([j, 3], 0..g.dims().nx, false);
                visit_row_faces(&g, row, face, origin, |i, corners, west_given| {
                    let f = faces.next().expect("a face for each one visited");
                    assert_eq!(f.cell, [i as u32, j as u32, 3]);
                    assert_eq!(
                        Some(corners),
                        surface_face_corners(&g, [i, j, 3], face, origin)
                    );
                    let [a, b] = f.triangles.map(|t| m.triangles[t as usize]);
                    let west = [a[0], b[2]];
                    let same = matches!(before, Some((bi, bj, east)) if bi + 1 == i && bj == j && east == west);
                    assert_eq!(west_given, same, "cell ({i}, {j})");
                    shared += usize::from(same);
                    before = Some((i, j, [a[1], a[2]]));
                });
            }
            assert!(faces.next().is_none());
            assert!(shared > m.cell_faces.len() / 2 && shared < m.cell_faces.len());
        }
    }

    #[test]
    fn side_faces_of_runs_of_layers_are_those_of_the_whole_scene() {
        // Layers 1..5 of the faulted grid drawn as the runs 1..2, 2..4 and 4..5: each
        // run's faces, corner values and coordinates, run after run, are the scene's.
        let g = faulted();
        let origin = g.display_origin();
        let scene = 1..5;
        let all = Columns::all(g.dims());
        let whole = side_surfaces(
            &g,
            &Surfaces::new(scene.clone(), origin).property(Some("PORO")),
        )
        .unwrap();
        let corners = |m: &SurfaceMesh| -> Vec<([f32; 3], [f32; 2], f32)> {
            m.triangles
                .iter()
                .flatten()
                .map(|&v| {
                    let v = v as usize;
                    (m.positions[v], m.texcoords[v], m.scalars[v])
                })
                .collect()
        };
        let mut runs = SurfaceMesh::with_origin(origin);
        for run in [1..2, 2..4, 4..5] {
            let part = side_surfaces(
                &g,
                &Surfaces::new(run, origin)
                    .property(Some("PORO"))
                    .columns(all.clone())
                    .among(scene.clone()),
            );
            let part = part.unwrap();
            runs.append(&part);
        }
        assert!(whole.triangle_count() > 500);
        assert_eq!(runs.triangle_count(), whole.triangle_count());
        let cells = |m: &SurfaceMesh| m.cell_faces.iter().map(|f| f.cell).collect::<Vec<_>>();
        assert_eq!(cells(&runs), cells(&whole));
        let (got, want) = (corners(&runs), corners(&whole));
        let differ = got
            .iter()
            .zip(&want)
            .filter(|(a, b)| a.0 != b.0 || a.1 != b.1 || a.2.to_bits() != b.2.to_bits())
            .count();
        assert_eq!(differ, 0, "{differ} of {} corners differ", want.len());
        // A run alone averages its own cells only: the shared nodes differ.
        let alone: Vec<_> = [1..2, 2..4, 4..5]
            .into_iter()
            .flat_map(|run| {
                corners(
                    &side_surfaces(&g, &Surfaces::new(run, origin).property(Some("PORO"))).unwrap(),
                )
            })
            .collect();
        assert!(alone.iter().zip(&want).any(|(a, b)| a.2 != b.2));
        // A run outside the scene is refused.
        assert!(
            side_surfaces(
                &g,
                &Surfaces::new(0..2, origin)
                    .columns(all.clone())
                    .among(scene)
            )
            .is_err()
        );
    }

    #[test]
    fn side_faces_in_rectangles_of_columns_are_those_of_the_whole_scene() {
        // Layers 1..5 of the faulted grid as two runs, each cut into four rectangles
        // of columns whose edges cross faults and the outer shell: every side face of
        // the scene is in exactly one piece, with the same corners, coordinates and
        // node values (averaged across the rectangles' and the runs' edges).
        let g = faulted();
        let origin = g.display_origin();
        let scene = 1..5;
        let whole = side_surfaces(
            &g,
            &Surfaces::new(scene.clone(), origin).property(Some("PORO")),
        )
        .unwrap();
        let mut pieces = SurfaceMesh::with_origin(origin);
        for run in [1..3, 3..5] {
            for columns in rectangles([0..7, 7..24], [0..10, 10..18]) {
                let piece = side_surfaces(
                    &g,
                    &Surfaces::new(run.clone(), origin)
                        .property(Some("PORO"))
                        .columns(columns.clone())
                        .among(scene.clone()),
                );
                let piece = piece.unwrap();
                piece.validate().unwrap();
                pieces.append(&piece);
            }
        }
        assert!(whole.triangle_count() > 500);
        assert!(
            sorted_faces(&pieces) == sorted_faces(&whole),
            "side faces differ"
        );
        let beyond = Columns { i: 0..25, j: 0..18 };
        assert!(
            side_surfaces(
                &g,
                &Surfaces::new(1..3, origin)
                    .columns(beyond.clone())
                    .among(scene)
            )
            .is_err()
        );
    }

    #[test]
    fn the_corners_of_a_side_face_are_its_vertices() {
        // open_sides and side_face_corners name the side surfaces' faces, with their
        // vertices' positions, bit for bit, and the degenerate ones they leave out.
        let g = faulted();
        let origin = g.display_origin();
        let d = g.dims();
        let sides = side_surfaces(&g, &Surfaces::new(2..3, origin)).unwrap();
        let mut faces = sides.cell_faces.iter();
        for j in 0..d.ny {
            for i in 0..d.nx {
                if !has_faces(&g, i, j, 2) {
                    continue;
                }
                let open = open_sides(&g, [i, j, 2], |i, j| has_faces(&g, i, j, 2));
                for side in (0..4).filter(|&s| open[s]) {
                    let (corners, kept) = side_face_corners(&g, [i, j, 2], side, origin);
                    if !kept {
                        continue;
                    }
                    let f = faces.next().expect("a face for each open side");
                    assert_eq!(f.cell, [i as u32, j as u32, 2]);
                    let [a, b] = f.triangles.map(|t| sides.triangles[t as usize]);
                    let mut ids: Vec<u32> = a.into_iter().chain(b).collect();
                    ids.sort();
                    ids.dedup();
                    let mut vertices: Vec<[f32; 3]> =
                        ids.iter().map(|&v| sides.positions[v as usize]).collect();
                    vertices.sort_by(|a, b| a.partial_cmp(b).expect("finite"));
                    let mut corners = corners.to_vec();
                    corners.sort_by(|a, b| a.partial_cmp(b).expect("finite"));
                    assert_eq!(vertices, corners);
                }
            }
        }
        assert!(faces.next().is_none());
        assert!(sides.triangle_count() > 200);
    }

    #[test]
    fn stacked_layers_and_sides_carry_their_coordinates() {
        let g = faulted();
        let d = g.dims();
        let origin = g.display_origin();
        let all = layer_surfaces(
            &g,
            Face::Top,
            &Surfaces::new(0..d.nz, origin).property(Some("PERMX")),
        )
        .unwrap();
        let sum: usize = (0..d.nz)
            .map(|k| {
                layer_surfaces(&g, Face::Top, &Surfaces::layer(k, origin))
                    .unwrap()
                    .triangle_count()
            })
            .sum();
        assert_eq!(all.triangle_count(), sum);
        all.validate().unwrap();

        let sides =
            side_surfaces(&g, &Surfaces::new(0..d.nz, origin).property(Some("PORO"))).unwrap();
        sides.validate().unwrap();
        assert!(!sides.is_empty());
        for f in &sides.cell_faces {
            let [i, j, k] = f.cell.map(|c| c as usize);
            for t in f.triangles {
                for v in sides.triangles[t as usize] {
                    let [s, t] = sides.texcoords[v as usize];
                    // The level coordinate is the cell's top (2k + 1) or bottom (2k + 3).
                    assert!(t == (2 * k + 1) as f32 || t == (2 * k + 3) as f32);
                    // The other is odd and belongs to one of the face's two pillars.
                    let odd = [
                        (2 * i + 1) as f32,
                        (2 * i + 3) as f32,
                        (2 * j + 1) as f32,
                        (2 * j + 3) as f32,
                    ];
                    assert!(odd.contains(&s), "side coordinate {s} of cell {i},{j},{k}");
                }
            }
        }
        // The outer shell alone: an unfaulted, fully active box (two layers, so no
        // pinch-out) has 2 (nx + ny) nz side faces.
        let mut plain = generate(&SynthParams {
            nx: 6,
            ny: 4,
            nz: 2,
            faults: 0,
            seed: 1,
        })
        .unwrap();
        plain.actnum.fill(true);
        let shell = side_surfaces(&plain, &Surfaces::new(0..2, [0.0; 3])).unwrap();
        assert_eq!(shell.cell_faces.len(), 2 * (6 + 4) * 2);
    }

    #[test]
    fn unknown_property_lists_the_available_ones() {
        let g = faulted();
        let err = layer_surfaces(
            &g,
            Face::Top,
            &Surfaces::layer(0, [0.0; 3]).property(Some("SWAT")),
        )
        .unwrap_err();
        assert!(err.to_string().contains("PERMX, PORO"), "{err}");
        assert!(layer_surfaces(&g, Face::Top, &Surfaces::layer(9, [0.0; 3])).is_err());
    }
}
