//! The meshes of `strata bench wire` and `strata bench quality`: a displaced sphere (a
//! true triangle mesh, the kind of the papers' test models: no quads, no global
//! coordinates, vertex labels that conflict), a noisy terrain (a structured quad grid
//! with global coordinates) and a generated reservoir model's stacked layer surfaces
//! (what strata is for: quads with global coordinates, faults, pinch-outs, holes).
//! Every one is deterministic and sized by its triangle count.

use std::collections::HashMap;

use anyhow::Result;
use strata_grid::synth::{ICOSAHEDRON_CORNERS, ICOSAHEDRON_FACES, SynthParams, generate};
use strata_grid::{Face, SurfaceMesh, Surfaces, layer_surfaces};

/// The kinds of benchmark mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A displaced sphere ([`sphere`]).
    Sphere,
    /// A noisy terrain: a structured quad grid with global coordinates.
    Terrain,
    /// A generated reservoir's layer surfaces ([`reservoir`]).
    Reservoir,
}

impl Kind {
    /// Every kind, in the order of the reports.
    pub const ALL: [Kind; 3] = [Kind::Sphere, Kind::Terrain, Kind::Reservoir];

    /// The kind's name in reports and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Sphere => "sphere",
            Kind::Terrain => "terrain",
            Kind::Reservoir => "reservoir",
        }
    }

    /// Whether the mesh carries global coordinates (the `global` technique applies).
    pub fn has_global(self) -> bool {
        self != Kind::Sphere
    }

    /// Vertical exaggeration to look at it with: reservoirs are thin.
    pub fn z_scale(self) -> f32 {
        match self {
            Kind::Reservoir => 5.0,
            _ => 1.0,
        }
    }
}

/// A benchmark mesh.
pub struct BenchMesh {
    /// What kind of mesh it is.
    pub kind: Kind,
    /// Name in reports: kind and size, e.g. `terrain-1m`.
    pub name: String,
    /// The mesh itself.
    pub mesh: SurfaceMesh,
}

/// The mesh of `kind` with about `triangles` triangles, named with `label` (`0.1m` ...).
pub fn make(kind: Kind, triangles: usize, label: &str) -> Result<BenchMesh> {
    let mesh = match kind {
        Kind::Sphere => sphere(triangles),
        Kind::Terrain => terrain(triangles),
        Kind::Reservoir => reservoir(triangles)?,
    };
    Ok(BenchMesh {
        kind,
        name: format!("{}-{label}", kind.name()),
        mesh,
    })
}

/// Smooth pseudo-random relief: a few sines of the point at incommensurate
/// frequencies, in [-1, 1].
fn relief(x: f32, y: f32, z: f32) -> f32 {
    let waves = [
        (1.0f32, [0.9f32, 0.3, 0.2], 0.3f32),
        (0.5, [-0.4, 1.7, 0.6], 1.1),
        (0.25, [2.3, -1.9, 1.3], 2.0),
        (0.125, [-4.1, 3.7, -3.3], 0.7),
        (0.0625, [7.9, 6.7, -8.3], 2.9),
    ];
    let sum: f32 = waves
        .iter()
        .map(|(a, k, p)| a * (k[0] * x + k[1] * y + k[2] * z + p).sin())
        .sum();
    sum / 1.9375
}

/// An icosahedron whose faces are split into `k`² triangles each (20 k² in all), pushed
/// onto a sphere of radius 100 and displaced by up to 6 % along the radius.
pub fn sphere(triangles: usize) -> SurfaceMesh {
    let k = ((triangles as f64 / 20.0).sqrt().round() as usize).max(1);
    let mut mesh = SurfaceMesh::default();
    // A point of a face's grid is shared with neighbouring faces on their common edge
    // or corner: it is keyed by its icosahedron corners and integer weights.
    let mut index: HashMap<[(u32, usize); 3], u32> = HashMap::new();
    let mut vertex = |face: [u32; 3], w: [usize; 3], mesh: &mut SurfaceMesh| -> u32 {
        let mut key = [(u32::MAX, 0); 3];
        for c in 0..3 {
            if w[c] > 0 {
                key[c] = (face[c], w[c]);
            }
        }
        key.sort_unstable();
        *index.entry(key).or_insert_with(|| {
            let p: [f32; 3] = std::array::from_fn(|a| {
                (0..3)
                    .map(|c| ICOSAHEDRON_CORNERS[face[c] as usize][a] * w[c] as f32)
                    .sum::<f32>()
            });
            let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            let d = [p[0] / len, p[1] / len, p[2] / len];
            let r = 100.0 * (1.0 + 0.06 * relief(3.0 * d[0], 3.0 * d[1], 3.0 * d[2]));
            mesh.positions.push([r * d[0], r * d[1], r * d[2]]);
            mesh.texcoords.push([0.0, 0.0]);
            (mesh.positions.len() - 1) as u32
        })
    };
    for face in ICOSAHEDRON_FACES {
        // Row i from corner 0 towards the edge 1-2, j along the row.
        let at = |i: usize, j: usize| [k - i, i - j, j];
        for i in 0..k {
            for j in 0..=i {
                let a = vertex(face, at(i, j), &mut mesh);
                let b = vertex(face, at(i + 1, j), &mut mesh);
                let c = vertex(face, at(i + 1, j + 1), &mut mesh);
                mesh.triangles.push([a, b, c]);
                if j < i {
                    let d = vertex(face, at(i, j + 1), &mut mesh);
                    mesh.triangles.push([a, c, d]);
                }
            }
        }
    }
    mesh
}

/// A square structured grid of `n` x `n` cells of 10 m (2 n² triangles) with hills,
/// ridges and steep small-scale roughness.
fn terrain(triangles: usize) -> SurfaceMesh {
    let n = ((triangles as f64 / 2.0).sqrt().round() as usize).max(1);
    let cell = 10.0;
    let size = n as f32 * cell;
    SurfaceMesh::structured(n, n, |i, j| {
        let (x, y) = (i as f32 * cell, j as f32 * cell);
        let (u, v) = (x / size * 12.0, y / size * 12.0);
        let h =
            0.08 * size * relief(u, v, 0.5 * (u - v)) + 0.01 * size * relief(9.0 * u, 9.0 * v, 1.0);
        [x - 0.5 * size, y - 0.5 * size, h]
    })
}

/// The top surfaces of the layers of a generated 10-layer model with faults, about
/// `triangles` triangles in all (inactive and pinched cells make it a little less).
pub fn reservoir(triangles: usize) -> Result<SurfaceMesh> {
    let nz = 10;
    let cells = (triangles / (2 * nz)).max(2);
    // Twice as long as wide, like the generator's default models.
    let ny = ((cells as f64 / 2.0).sqrt().round() as usize).max(1);
    let nx = (cells / ny).max(1);
    let grid = generate(&SynthParams {
        nx,
        ny,
        nz,
        faults: 4,
        seed: 7,
    })?;
    Ok(layer_surfaces(
        &grid,
        Face::Top,
        &Surfaces::new(0..nz, grid.display_origin()),
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_near_the_request_and_meshes_valid() {
        for kind in Kind::ALL {
            let m = make(kind, 20_000, "20k").unwrap();
            let t = m.mesh.triangle_count() as f64;
            assert!((14_000.0..24_000.0).contains(&t), "{} has {t}", m.name);
            m.mesh.validate().unwrap();
        }
    }

    #[test]
    fn the_sphere_is_closed() {
        // Closed: every edge has two triangles, so V - E + F = 2 with E = 3F / 2.
        let m = sphere(2000);
        let (v, f) = (m.vertex_count() as i64, m.triangle_count() as i64);
        assert_eq!(v - 3 * f / 2 + f, 2);
    }
}
