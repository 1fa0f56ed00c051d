//! Fault traces: where a layer surface is split because two neighbouring cells' corner
//! depths differ, both sides' cell edges there. Renderers draw them in a style of
//! their own; a hierarchy stores each layer surface's, found at full resolution.
//!
//! The traces are found from the cell faces of a mesh: a face of a layer surface has
//! the global coordinates `(2i + 1 + 2di, 2j + 1 + 2dj)` at its corners, and its
//! neighbour across an edge is the face of the next cell of the same surface; where the
//! two edges are not at the same place, the surface is split there. Meshes appended
//! one after another (the tops of several layers, the bottom of the last, side walls)
//! are told apart by the order of their faces: a surface holds each cell once, so a
//! cell seen again starts the next surface. Meshes without cell faces (decimated
//! surfaces) have no traces here.

use crate::SurfaceMesh;

/// One trace segment: its two ends, in the mesh's frame.
pub type Segment = [[f32; 3]; 2];

/// The corners of a layer surface's cell face, `[(0, 0), (1, 0), (0, 1), (1, 1)]` in
/// cell steps along i and j, or `None` for a face whose coordinates are not those
/// of a layer face of its cell (a side wall).
pub(crate) fn layer_corners(
    mesh: &SurfaceMesh,
    cell: [u32; 3],
    triangles: [u32; 2],
) -> Option<[u32; 4]> {
    let mut corners = [u32::MAX; 4];
    for t in triangles {
        for &v in mesh.triangles.get(t as usize)? {
            let [u, w] = *mesh.texcoords.get(v as usize)?;
            let di = (u - (2 * cell[0] + 1) as f32) * 0.5;
            let dj = (w - (2 * cell[1] + 1) as f32) * 0.5;
            let at = match (di, dj) {
                (0.0, 0.0) => 0,
                (1.0, 0.0) => 1,
                (0.0, 1.0) => 2,
                (1.0, 1.0) => 3,
                _ => return None,
            };
            corners[at] = v;
        }
    }
    corners.iter().all(|&v| v != u32::MAX).then_some(corners)
}

/// A layer face: its cell and its corners (`layer_corners`).
type LayerFace = ([u32; 3], [u32; 4]);

/// The fault trace segments of `mesh`: both sides' edges wherever neighbouring cell
/// faces of one layer surface do not meet. The faces of a surface are found in a dense
/// table over (i, j), not a hash map: a part of a large model holds millions.
pub fn fault_traces(mesh: &SurfaceMesh) -> Vec<Segment> {
    traces(mesh, None)
}

/// The fault traces of `mesh` between its cells of row `j - 1` and those of row `j`
/// alone: where a surface drawn in bands of rows is split on the border of two bands,
/// which neither band finds alone. `mesh` holds (at least) both rows.
pub fn fault_traces_across_row(mesh: &SurfaceMesh, j: u32) -> Vec<Segment> {
    traces(mesh, Some(j))
}

/// The traces of `mesh`, or with `across_row`, those across that row's lower edge.
fn traces(mesh: &SurfaceMesh, across_row: Option<u32>) -> Vec<Segment> {
    let faces: Vec<LayerFace> = mesh
        .cell_faces
        .iter()
        .filter_map(|f| Some((f.cell, layer_corners(mesh, f.cell, f.triangles)?)))
        .collect();
    // The box of the faces' columns (a part of a large layer is a band of it).
    let range = |axis: usize| {
        let values = faces.iter().map(|(c, _)| c[axis] as usize);
        let lo = values.clone().min().unwrap_or(0);
        (lo, values.max().map_or(0, |hi| hi + 1 - lo))
    };
    let ((i0, ni), (j0, nj)) = (range(0), range(1));
    let mut table = Surface {
        faces: &faces,
        ni,
        slot: vec![u32::MAX; ni * nj],
        members: Vec::new(),
    };
    let mut out = Vec::new();
    for (n, (cell, _)) in faces.iter().enumerate() {
        let at = (cell[1] as usize - j0) * ni + cell[0] as usize - i0;
        if table.slot[at] != u32::MAX {
            // The column again: the next surface starts here.
            table.flush(mesh, across_row, &mut out);
        }
        table.slot[at] = n as u32;
        table.members.push(at);
    }
    table.flush(mesh, across_row, &mut out);
    out
}

/// The faces of the surface being read, by column.
struct Surface<'f> {
    faces: &'f [LayerFace],
    ni: usize,
    /// Per column (i, j), the index of its face, `u32::MAX` for none.
    slot: Vec<u32>,
    /// The columns filled.
    members: Vec<usize>,
}

impl Surface<'_> {
    /// Adds the traces of the surface read so far to `out` (with `across_row`, only
    /// those between that row and the one before) and empties the table.
    fn flush(&mut self, mesh: &SurfaceMesh, across_row: Option<u32>, out: &mut Vec<Segment>) {
        let at = |v: u32| mesh.positions[v as usize];
        let same = |x: u32, y: u32| at(x).map(f32::to_bits) == at(y).map(f32::to_bits);
        for &column in &self.members {
            let ([_, j, k], c) = self.faces[self.slot[column] as usize];
            // Across +i: this face's corners (1, 0), (1, 1) against the next's (0, 0),
            // (0, 1); across +j: (0, 1), (1, 1) against (0, 0), (1, 0).
            let next_i =
                ((column + 1) % self.ni != 0 && across_row.is_none()).then_some(column + 1);
            let next_j = Some(column + self.ni)
                .filter(|&n| n < self.slot.len())
                .filter(|_| across_row.is_none_or(|row| j + 1 == row));
            for (next, mine, theirs) in [(next_i, [1, 3], [0, 2]), (next_j, [2, 3], [0, 1])] {
                let Some(&face) = next.and_then(|n| self.slot.get(n)) else {
                    continue;
                };
                let Some(&(cell, n)) = self.faces.get(face as usize) else {
                    continue;
                };
                if cell[2] != k {
                    continue;
                }
                let (a, b) = (mine.map(|m| c[m]), theirs.map(|t| n[t]));
                if same(a[0], b[0]) && same(a[1], b[1]) {
                    continue;
                }
                for [p, q] in [a, b] {
                    out.push([at(p), at(q)]);
                }
            }
        }
        for &column in &self.members {
            self.slot[column] = u32::MAX;
        }
        self.members.clear();
    }
}

/// `segments` joined into chains where they meet end to end (at points where exactly
/// two meet) and each chain simplified (Douglas-Peucker) so that no point of it moves
/// more than `tolerance` (with heights counted `z_scale` times): the traces a view
/// that sees a cell as a fraction of a pixel draws, a few segments a fault instead of
/// one a cell edge. A tolerance of 0 gives the segments back as they are.
pub fn simplified_traces(segments: &[Segment], tolerance: f32, z_scale: f32) -> Vec<Segment> {
    if tolerance <= 0.0 {
        return segments.to_vec();
    }
    let key = |p: [f32; 3]| p.map(f32::to_bits);
    let mut ends: std::collections::HashMap<[u32; 3], Vec<usize>> =
        std::collections::HashMap::with_capacity(2 * segments.len());
    for (n, s) in segments.iter().enumerate() {
        for p in s {
            ends.entry(key(*p)).or_default().push(n);
        }
    }
    // The other segment at point `p` of a chain through it, where exactly two meet.
    let onward = |p: [f32; 3], from: usize| match ends.get(&key(p)).map(Vec::as_slice) {
        Some(&[a, b]) if a != b => Some(if a == from { b } else { a }),
        _ => None,
    };
    let mut used = vec![false; segments.len()];
    let mut out = Vec::new();
    for start in 0..segments.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        let [a, b] = segments[start];
        // Walk on from each end, then join the two halves at the start.
        let mut halves = [vec![a], vec![b]];
        for (half, mut at) in halves.iter_mut().zip([a, b]) {
            let mut from = start;
            while let Some(next) = onward(at, from).filter(|&n| !used[n]) {
                used[next] = true;
                let [p, q] = segments[next];
                at = if key(p) == key(at) { q } else { p };
                half.push(at);
                from = next;
            }
        }
        let [mut back, forth] = halves;
        back.reverse();
        back.extend(forth);
        let kept = douglas_peucker(&back, tolerance, z_scale);
        out.extend(kept.windows(2).map(|w| [w[0], w[1]]));
    }
    out
}

/// The points of `line` Douglas-Peucker keeps at `tolerance`, heights counted
/// `z_scale` times.
fn douglas_peucker(line: &[[f32; 3]], tolerance: f32, z_scale: f32) -> Vec<[f32; 3]> {
    let scaled = |p: [f32; 3]| [p[0], p[1], p[2] * z_scale];
    let mut keep = vec![false; line.len()];
    if let (Some(first), Some(last)) = (keep.first_mut(), line.len().checked_sub(1)) {
        *first = true;
        keep[last] = true;
    }
    let mut stack = vec![(0, line.len().saturating_sub(1))];
    while let Some((i, j)) = stack.pop() {
        if j <= i + 1 {
            continue;
        }
        let (a, b) = (scaled(line[i]), scaled(line[j]));
        let (far, distance) = (i + 1..j)
            .map(|k| (k, point_line_distance(scaled(line[k]), a, b)))
            .fold((i, -1.0f32), |best, c| if c.1 > best.1 { c } else { best });
        if distance > tolerance {
            keep[far] = true;
            stack.push((i, far));
            stack.push((far, j));
        }
    }
    line.iter()
        .zip(&keep)
        .filter(|(_, k)| **k)
        .map(|(p, _)| *p)
        .collect()
}

/// Distance from `p` to the segment `a`-`b`.
fn point_line_distance(p: [f32; 3], a: [f32; 3], b: [f32; 3]) -> f32 {
    let d: [f32; 3] = std::array::from_fn(|k| b[k] - a[k]);
    let w: [f32; 3] = std::array::from_fn(|k| p[k] - a[k]);
    let dd: f32 = d.iter().map(|v| v * v).sum();
    let t = if dd > 0.0 {
        (w.iter().zip(&d).map(|(x, y)| x * y).sum::<f32>() / dd).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (0..3)
        .map(|k| (w[k] - t * d[k]).powi(2))
        .sum::<f32>()
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat 6 x 4 grid of 10 m cells; with `throw`, the cells from i = 3 on lower by
    /// it, split along their line I 3.
    fn split(throw: f32) -> SurfaceMesh {
        let mut mesh = SurfaceMesh::structured(6, 4, |i, j| {
            let drop = if i > 3 { throw } else { 0.0 };
            [10.0 * i as f32, 10.0 * j as f32, -drop]
        });
        let first = mesh.positions.len() as u32;
        for j in 0..=4 {
            let [x, y, z] = mesh.positions[j * 7 + 3];
            mesh.positions.push([x, y, z - throw]);
            mesh.texcoords.push(mesh.texcoords[j * 7 + 3]);
        }
        for face in mesh.cell_faces.clone() {
            if face.cell[0] >= 3 {
                for t in face.triangles {
                    for v in &mut mesh.triangles[t as usize] {
                        if *v < first && *v % 7 == 3 {
                            *v = first + *v / 7;
                        }
                    }
                }
            }
        }
        mesh
    }

    #[test]
    fn both_sides_of_a_split_are_traces_and_nothing_else_is() {
        let traces = fault_traces(&split(5.0));
        // Four cell edges along the fault, on each side.
        assert_eq!(traces.len(), 8);
        for pair in traces.chunks(2) {
            assert!(pair.iter().all(|s| s[0][0] == 30.0 && s[1][0] == 30.0));
            assert_eq!((pair[0][0][2], pair[1][0][2]), (0.0, -5.0));
        }
        // Split vertices that stay at the same place are no fault.
        assert!(fault_traces(&split(0.0)).is_empty());
        // Two surfaces of the same cells appended (a layer's top and bottom) are two
        // surfaces, not one folded onto itself.
        let mut stacked =
            SurfaceMesh::structured(6, 4, |i, j| [10.0 * i as f32, 10.0 * j as f32, 0.0]);
        stacked.append(&SurfaceMesh::structured(6, 4, |i, j| {
            [10.0 * i as f32, 10.0 * j as f32, -3.0]
        }));
        assert!(fault_traces(&stacked).is_empty());
        // Split across a row instead: the traces across that row alone.
        let mut across = split(5.0);
        for p in &mut across.positions {
            p.swap(0, 1);
        }
        for t in &mut across.texcoords {
            t.swap(0, 1);
        }
        for f in &mut across.cell_faces {
            f.cell.swap(0, 1);
        }
        assert_eq!(fault_traces_across_row(&across, 3).len(), 8);
        assert!(fault_traces_across_row(&across, 2).is_empty());
        assert!(fault_traces_across_row(&split(5.0), 3).is_empty());
        let mut two = split(5.0);
        two.append(&split(5.0));
        assert_eq!(fault_traces(&two).len(), 16);
    }

    #[test]
    fn simplified_traces_join_a_fault_into_few_segments_within_the_tolerance() {
        // A fault of 40 cell edges along a gentle curve, both sides, and one lone
        // segment elsewhere.
        let side = |z: f32| -> Vec<Segment> {
            (0..40)
                .map(|n| {
                    let at = |n: usize| {
                        let x = 10.0 * n as f32;
                        [x, 0.002 * x * x, z]
                    };
                    [at(n), at(n + 1)]
                })
                .collect()
        };
        let mut traces = side(0.0);
        traces.extend(side(-5.0));
        traces.push([[0.0, 100.0, 0.0], [10.0, 100.0, 0.0]]);
        assert_eq!(simplified_traces(&traces, 0.0, 5.0), traces);
        let simplified = simplified_traces(&traces, 1.0, 5.0);
        assert!(
            simplified.len() <= traces.len() / 3,
            "{} segments",
            simplified.len()
        );
        // Every original point lies within the tolerance of the simplified lines.
        for p in traces.iter().flatten() {
            let nearest = simplified
                .iter()
                .map(|s| point_line_distance(*p, s[0], s[1]))
                .fold(f32::INFINITY, f32::min);
            assert!(nearest <= 1.0 + 1e-3, "{p:?} is {nearest} away");
        }
        // The two sides stay apart, and the lone segment stays.
        assert!(simplified.contains(&[[0.0, 100.0, 0.0], [10.0, 100.0, 0.0]]));
    }
}
