//! Terrain: a triangulated irregular network (TIN) from scattered points such as
//! horizon or well-top picks, by constrained Delaunay triangulation (`spade`).
//!
//! Where a boundary polygon is given, its edges are constraints and the triangles
//! outside it are dropped (the Delaunay triangulation alone would fill the convex
//! hull, bridging concave bays); where fault traces are given, their segments are
//! constraints so that no triangle straddles a fault. Constraint vertices that are not
//! picks get their elevation by natural-neighbour interpolation of the picks.
//!
//! A TIN has no structured parameterisation, so its vertices carry no global
//! wireframe coordinates (they are all 0); map grid lines are drawn on it from object
//! space instead. The per-vertex scalar is the elevation.

use std::io::BufRead;
use std::path::Path;

use spade::{
    ConstrainedDelaunayTriangulation, DelaunayTriangulation, HasPosition, Point2, Triangulation,
};

use crate::{Error, Result, SurfaceMesh};

/// What to triangulate: picks and optional constraints, in map coordinates.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TerrainInput {
    /// Map x, map y, elevation (up positive).
    pub points: Vec<[f64; 3]>,
    /// A closed outline (the last vertex joins the first); triangles outside are
    /// dropped.
    pub boundary: Option<Vec<[f64; 2]>>,
    /// Fault traces: open polylines that triangle edges must follow.
    pub faults: Vec<Vec<[f64; 2]>>,
}

/// A triangulated terrain and what the triangulation had to leave out.
#[derive(Clone, Debug, PartialEq)]
pub struct Terrain {
    /// The TIN: positions relative to its origin, elevation as the scalar, texture
    /// coordinates all 0.
    pub mesh: SurfaceMesh,
    /// Picks dropped because another pick had the same map position.
    pub duplicates: usize,
    /// Constraint segments dropped because they crossed another constraint.
    pub conflicting_constraints: usize,
}

#[derive(Clone, Copy, Debug)]
struct Pick {
    x: f64,
    y: f64,
    z: f64,
}

impl HasPosition for Pick {
    type Scalar = f64;

    fn position(&self) -> Point2<f64> {
        Point2::new(self.x, self.y)
    }
}

/// Triangulates `input` into a mesh relative to a map origin at the floor of the
/// points' smallest x and y (elevation stays absolute).
pub fn triangulate(input: &TerrainInput) -> Result<Terrain> {
    let finite = |v: &[f64]| v.iter().all(|c| c.is_finite());
    if let Some(p) = input.points.iter().find(|p| !finite(&p[..])) {
        return Err(Error::Invalid(format!("terrain point {p:?} is not finite")));
    }
    let constraints = input.boundary.iter().chain(&input.faults);
    if constraints.clone().flatten().any(|p| !finite(&p[..])) {
        return Err(Error::Invalid(
            "a boundary or fault vertex is not finite".into(),
        ));
    }
    if input.points.len() < 3 {
        return Err(Error::Invalid(format!(
            "a terrain needs at least 3 points, got {}",
            input.points.len()
        )));
    }
    let picks: Vec<Pick> = input
        .points
        .iter()
        .map(|p| Pick {
            x: p[0],
            y: p[1],
            z: p[2],
        })
        .collect();
    // Elevations of constraint vertices from the picks alone.
    let delaunay = DelaunayTriangulation::<Pick>::bulk_load(picks.clone())
        .map_err(|e| Error::Invalid(format!("triangulating the terrain points: {e}")))?;
    if delaunay.num_inner_faces() == 0 {
        return Err(Error::Invalid(
            "the terrain points are collinear: nothing to triangulate".into(),
        ));
    }
    let natural = delaunay.natural_neighbor();
    let elevation = |x: f64, y: f64| {
        let at = Point2::new(x, y);
        natural
            .interpolate(|v| v.data().z, at)
            .or_else(|| delaunay.nearest_neighbor(at).map(|v| v.data().z))
    };
    let mut vertices = picks;
    let mut edges = Vec::new();
    let mut add_polyline = |line: &[[f64; 2]], closed: bool| -> Result<()> {
        let first = vertices.len();
        for p in line {
            let z = elevation(p[0], p[1])
                .ok_or_else(|| Error::Invalid("no elevation for a constraint vertex".into()))?;
            vertices.push(Pick {
                x: p[0],
                y: p[1],
                z,
            });
        }
        let n = line.len();
        let segments = if closed && n > 2 {
            n
        } else {
            n.saturating_sub(1)
        };
        edges.extend((0..segments).map(|s| [first + s, first + (s + 1) % n]));
        Ok(())
    };
    if let Some(b) = &input.boundary {
        if b.len() < 3 {
            return Err(Error::Invalid(format!(
                "the boundary needs at least 3 vertices, got {}",
                b.len()
            )));
        }
        add_polyline(b, true)?;
    }
    for fault in &input.faults {
        add_polyline(fault, false)?;
    }
    let given = vertices.len();
    let mut conflicting = 0;
    let cdt = ConstrainedDelaunayTriangulation::<Pick>::try_bulk_load_cdt(vertices, edges, |_| {
        conflicting += 1
    })
    .map_err(|e| Error::Invalid(format!("triangulating the terrain: {e}")))?;
    let duplicates = given - cdt.num_vertices();

    let (min_x, min_y) = input
        .points
        .iter()
        .fold((f64::INFINITY, f64::INFINITY), |(x, y), p| {
            (x.min(p[0]), y.min(p[1]))
        });
    let origin = [min_x.floor(), min_y.floor(), 0.0];
    let mut mesh = SurfaceMesh::with_origin(origin);
    // Output index of each triangulation vertex, once a kept triangle uses it.
    let mut index = vec![u32::MAX; cdt.num_vertices()];
    for face in cdt.inner_faces() {
        let corners = face.vertices();
        if let Some(b) = &input.boundary {
            let c = face.center();
            if !inside(b, c.x, c.y) {
                continue;
            }
        }
        let tri = corners.map(|v| {
            let slot = &mut index[v.fix().index()];
            if *slot == u32::MAX {
                *slot = mesh.positions.len() as u32;
                let p = v.data();
                mesh.positions.push([
                    (p.x - origin[0]) as f32,
                    (p.y - origin[1]) as f32,
                    p.z as f32,
                ]);
                mesh.texcoords.push([0.0, 0.0]);
                mesh.scalars.push(p.z as f32);
            }
            *slot
        });
        mesh.triangles.push(tri);
    }
    if mesh.triangles.is_empty() {
        return Err(Error::Invalid(
            "no triangle lies inside the terrain boundary".into(),
        ));
    }
    Ok(Terrain {
        mesh,
        duplicates,
        conflicting_constraints: conflicting,
    })
}

/// Even-odd rule: is (x, y) inside the closed polygon?
fn inside(polygon: &[[f64; 2]], x: f64, y: f64) -> bool {
    let mut odd = false;
    let n = polygon.len();
    for i in 0..n {
        let [xa, ya] = polygon[i];
        let [xb, yb] = polygon[(i + 1) % n];
        if (ya > y) != (yb > y) && x < xa + (y - ya) / (yb - ya) * (xb - xa) {
            odd = !odd;
        }
    }
    odd
}

/// Reads picks from a text file: one `x, y, z` per line (commas, semicolons, tabs
/// or spaces between the numbers); blank lines, lines starting with `#`, and a first
/// line that is not numeric (a header) are skipped. `z_is_depth` flips depths
/// (positive down) to elevations.
pub fn read_points(path: &Path, z_is_depth: bool) -> Result<Vec<[f64; 3]>> {
    Ok(read_table(path, 3)?
        .into_iter()
        .map(|v| [v[0], v[1], if z_is_depth { -v[2] } else { v[2] }])
        .collect())
}

/// Reads a polyline (a boundary or a fault trace) as `x, y` lines, in the format of
/// [`read_points`] (further columns are ignored).
pub fn read_polyline(path: &Path) -> Result<Vec<[f64; 2]>> {
    Ok(read_table(path, 2)?
        .into_iter()
        .map(|v| [v[0], v[1]])
        .collect())
}

/// Rows of at least `columns` finite numbers (only the first `columns` are kept).
fn read_table(path: &Path, columns: usize) -> Result<Vec<Vec<f64>>> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut rows = Vec::new();
    for (n, line) in std::io::BufReader::new(file).lines().enumerate() {
        let line = line.map_err(|e| Error::io(path, e))?;
        let text = line.trim();
        if text.is_empty() || text.starts_with('#') {
            continue;
        }
        let numbers: Option<Vec<f64>> = text
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .map(|f| f.parse::<f64>().ok())
            .collect();
        let bad = |message: String| Error::Text {
            path: path.to_path_buf(),
            line: n + 1,
            keyword: if columns == 3 { "x,y,z" } else { "x,y" }.into(),
            message,
        };
        match numbers {
            Some(mut v) if v.len() >= columns => {
                v.truncate(columns);
                if !v.iter().all(|c| c.is_finite()) {
                    return Err(bad(format!("{text:?} is not finite")));
                }
                rows.push(v);
            }
            Some(v) => {
                return Err(bad(format!("expected {columns} numbers, got {}", v.len())));
            }
            // A header line.
            None if rows.is_empty() && n == 0 => {}
            None => return Err(bad(format!("{text:?} is not {columns} numbers"))),
        }
    }
    Ok(rows)
}

/// Writes picks as `x,y,z` lines (elevation), with a header.
pub fn write_points(path: &Path, points: &[[f64; 3]]) -> Result<()> {
    let mut text = String::from("x,y,z\n");
    for p in points {
        text.push_str(&format!("{:.3},{:.3},{:.3}\n", p[0], p[1], p[2]));
    }
    std::fs::write(path, text).map_err(|e| Error::io(path, e))
}

/// A synthetic horizon to pick from: a dome on a gentle regional dip with folds,
/// thrown down by `throw` metres beyond a fault.
#[derive(Clone, Debug)]
pub struct TerrainSynth {
    /// Number of scattered picks.
    pub points: usize,
    /// Draws the pick positions (the fault and outline are fixed): the same seed gives
    /// the same picks.
    pub seed: u64,
    /// Map position of the area's south-west corner.
    pub origin: [f64; 2],
    /// Size of the area (metres).
    pub size: [f64; 2],
    /// Metres the horizon drops east of the fault trace (a negative throw raises it).
    pub throw: f64,
}

impl Default for TerrainSynth {
    fn default() -> Self {
        TerrainSynth {
            points: 2000,
            seed: 1,
            origin: [456_000.0, 6_780_000.0],
            size: [6000.0, 4000.0],
            throw: 40.0,
        }
    }
}

impl TerrainSynth {
    /// The fault trace: a straight line across the area from south-south-west to
    /// north-north-east, in map coordinates.
    fn fault(&self) -> [[f64; 2]; 2] {
        let [x0, y0] = self.origin;
        let [w, h] = self.size;
        [
            [x0 + 0.35 * w, y0 - 0.02 * h],
            [x0 + 0.6 * w, y0 + 1.02 * h],
        ]
    }

    /// Elevation of the horizon at map (x, y).
    pub fn elevation(&self, x: f64, y: f64) -> f64 {
        let [x0, y0] = self.origin;
        let [w, h] = self.size;
        let (u, v) = ((x - x0) / w, (y - y0) / h);
        let dome = 120.0 * (-((u - 0.55).powi(2) / 0.08 + (v - 0.5).powi(2) / 0.12)).exp();
        let folds = 15.0 * (7.0 * u + 2.0 * v).sin() * (5.0 * v).cos();
        let dip = -60.0 * u - 25.0 * v;
        // East of the fault (on its right going north) is thrown down.
        let [[ax, ay], [bx, by]] = self.fault();
        let east = (bx - ax) * (y - ay) - (by - ay) * (x - ax) < 0.0;
        -1600.0 + dome + folds + dip - if east { self.throw } else { 0.0 }
    }

    /// Scattered picks over an irregular outline, the outline itself, and the fault
    /// trace (clipped to the area).
    pub fn generate(&self) -> TerrainInput {
        let mut state = self.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        let mut uniform = || {
            // xorshift64*: reproducible and independent of any crate.
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            (state.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
        };
        let [x0, y0] = self.origin;
        let [w, h] = self.size;
        let points = (0..self.points)
            .map(|_| {
                let (x, y) = (x0 + uniform() * w, y0 + uniform() * h);
                [x, y, self.elevation(x, y)]
            })
            .collect();
        // A wobbly ellipse inside the area.
        let boundary = (0..40)
            .map(|k| {
                let t = k as f64 / 40.0 * std::f64::consts::TAU;
                let r = 0.46 + 0.03 * (3.0 * t).sin() + 0.02 * (5.0 * t).cos();
                [x0 + w * (0.5 + r * t.cos()), y0 + h * (0.5 + r * t.sin())]
            })
            .collect();
        let [a, b] = self.fault();
        let fault = (0..=10)
            .map(|k| {
                let t = 0.1 + 0.08 * k as f64;
                [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
            })
            .collect();
        TerrainInput {
            points,
            boundary: Some(boundary),
            faults: vec![fault],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_of_picks_makes_two_triangles() {
        let input = TerrainInput {
            points: vec![
                [100.5, 200.0, -10.0],
                [110.5, 200.0, -11.0],
                [110.5, 210.0, -12.0],
                [100.5, 210.0, -13.0],
            ],
            ..Default::default()
        };
        let t = triangulate(&input).unwrap();
        assert_eq!(t.mesh.triangle_count(), 2);
        assert_eq!(t.mesh.origin, [100.0, 200.0, 0.0]);
        assert!(t.mesh.positions.contains(&[0.5, 0.0, -10.0]));
        assert_eq!(t.mesh.scalars.len(), 4);
        t.mesh.validate().unwrap();
    }

    #[test]
    fn boundary_drops_outside_triangles_and_faults_become_edges() {
        let synth = TerrainSynth {
            points: 600,
            ..Default::default()
        };
        let input = synth.generate();
        let t = triangulate(&input).unwrap();
        t.mesh.validate().unwrap();
        assert_eq!(t.conflicting_constraints, 0);
        let o = t.mesh.origin;
        let outline = input.boundary.as_ref().unwrap();
        for tri in &t.mesh.triangles {
            let c = tri.iter().fold([0.0f64; 2], |a, &v| {
                let p = t.mesh.positions[v as usize];
                [a[0] + f64::from(p[0]) / 3.0, a[1] + f64::from(p[1]) / 3.0]
            });
            assert!(inside(outline, c[0] + o[0], c[1] + o[1]));
        }
        // Every fault segment is an edge of the mesh: no triangle straddles it.
        let fault = &input.faults[0];
        let vertex_at = |p: [f64; 2]| {
            t.mesh.positions.iter().position(|q| {
                (f64::from(q[0]) + o[0] - p[0]).abs() < 1e-2
                    && (f64::from(q[1]) + o[1] - p[1]).abs() < 1e-2
            })
        };
        for seg in fault.windows(2) {
            let (Some(a), Some(b)) = (vertex_at(seg[0]), vertex_at(seg[1])) else {
                panic!("fault vertex missing from the mesh");
            };
            let (a, b) = (a as u32, b as u32);
            let shared = t
                .mesh
                .triangles
                .iter()
                .filter(|tri| tri.contains(&a) && tri.contains(&b))
                .count();
            assert!(shared >= 1, "fault segment {seg:?} is not a mesh edge");
        }
        // Picks inside the outline keep their elevation.
        let mut checked = 0;
        for p in input.points.iter().filter(|p| inside(outline, p[0], p[1])) {
            let vertex = t.mesh.positions.iter().find(|q| {
                (f64::from(q[0]) + o[0] - p[0]).abs() < 1e-2
                    && (f64::from(q[1]) + o[1] - p[1]).abs() < 1e-2
            });
            if let Some(q) = vertex {
                assert!((f64::from(q[2]) - p[2]).abs() < 1e-3, "{q:?} vs {p:?}");
                checked += 1;
            }
        }
        assert!(checked > 300, "only {checked} picks found in the mesh");
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let collinear = TerrainInput {
            points: vec![[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 2.0, 0.0]],
            ..Default::default()
        };
        assert!(triangulate(&collinear).is_err());
        let nan = TerrainInput {
            points: vec![[0.0, 0.0, 0.0], [1.0, f64::NAN, 0.0], [2.0, 0.0, 0.0]],
            ..Default::default()
        };
        assert!(triangulate(&nan).is_err());
        assert!(triangulate(&TerrainInput::default()).is_err());
    }

    #[test]
    fn points_round_trip_through_text() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("picks.csv");
        let points = vec![[456_000.25, 6_780_000.5, -1600.125], [1.0, 2.0, 3.0]];
        write_points(&path, &points).unwrap();
        assert_eq!(read_points(&path, false).unwrap(), points);
        let depth = read_points(&path, true).unwrap();
        assert_eq!(depth[0][2], 1600.125);
        std::fs::write(&path, "x y z\n1 2 3\n# note\n\n4;5;6\n7,8\n").unwrap();
        let err = read_points(&path, false).unwrap_err().to_string();
        assert!(err.contains(":6:"), "{err}");
        std::fs::write(&path, "1 2\n3 4 5\n").unwrap();
        assert_eq!(read_polyline(&path).unwrap(), vec![[1.0, 2.0], [3.0, 4.0]]);
    }
}
