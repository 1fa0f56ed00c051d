//! Helpers shared by the integration tests of strata-lod.

#![allow(dead_code)]

use std::collections::HashMap;
use std::path::PathBuf;

use strata_grid::synth::{SynthParams, generate};
use strata_grid::{CornerPointGrid, Face, SurfaceMesh, Surfaces, layer_surfaces};

/// The shared real models, or `None` (with a message saying the test is skipped).
pub fn shared_data(test: &str) -> Option<PathBuf> {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"));
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("{test}: skipped, no shared data at {}", dir.display());
        None
    }
}

/// A faulted model with holes (inactive cells) and pinch-outs.
pub fn faulted_grid(nx: usize, ny: usize) -> CornerPointGrid {
    generate(&SynthParams {
        nx,
        ny,
        nz: 3,
        faults: 5,
        seed: 7,
    })
    .expect("generator")
}

/// The top of the first layer of a generated model of one tile (40 x 30 x 3 cells),
/// with one corner at a depth of 1e11 when `stray`: as corrupt as a file's can be.
pub fn one_tile_top(stray: bool) -> SurfaceMesh {
    let mut grid = generate(&SynthParams {
        nx: 40,
        ny: 30,
        nz: 3,
        faults: 2,
        seed: 3,
    })
    .expect("generator");
    if stray {
        grid.zcorn[[0, 0, 4]] = 1e11;
    }
    layer(&grid, 0)
}

/// Top surface of layer `k` of `grid`, with PORO as scalar.
pub fn layer(grid: &CornerPointGrid, k: usize) -> SurfaceMesh {
    layer_surfaces(
        grid,
        Face::Top,
        &Surfaces::layer(k, grid.display_origin()).property(Some("PORO")),
    )
    .expect("layer surface")
}

/// Topology of a connected component: vertices, edges, triangles, boundary loops.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Topology {
    pub vertices: usize,
    pub edges: usize,
    pub triangles: usize,
    pub loops: usize,
}

impl Topology {
    pub fn euler(&self) -> i64 {
        self.vertices as i64 - self.edges as i64 + self.triangles as i64
    }
}

/// Edges of `mesh` with the number of triangles using each.
pub fn edge_uses(mesh: &SurfaceMesh) -> HashMap<(u32, u32), usize> {
    let mut uses = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    uses
}

/// Per component, its topology; `labels` gives each triangle's component.
pub fn topology(mesh: &SurfaceMesh, labels: &[u32]) -> Vec<Topology> {
    let n = labels.iter().map(|&l| l as usize + 1).max().unwrap_or(0);
    let mut out = vec![
        Topology {
            vertices: 0,
            edges: 0,
            triangles: 0,
            loops: 0
        };
        n
    ];
    let mut vertex_label = vec![u32::MAX; mesh.vertex_count()];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        out[labels[t] as usize].triangles += 1;
        for &v in tri {
            vertex_label[v as usize] = labels[t];
        }
    }
    for &l in vertex_label.iter().filter(|&&l| l != u32::MAX) {
        out[l as usize].vertices += 1;
    }
    for (&(a, _), _) in edge_uses(mesh).iter() {
        out[vertex_label[a as usize] as usize].edges += 1;
    }
    // Boundary loops, followed through the triangle fans (so that a vertex where two
    // boundaries touch is passed through correctly): the boundary half-edge after
    // a -> b is found by turning around b from the triangle of a -> b until an edge
    // without a twin.
    let mut third: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            third.insert((t[k], t[(k + 1) % 3]), t[(k + 2) % 3]);
        }
    }
    let boundary: Vec<(u32, u32)> = {
        let mut b: Vec<(u32, u32)> = third
            .keys()
            .filter(|&&(a, b)| !third.contains_key(&(b, a)))
            .copied()
            .collect();
        b.sort_unstable();
        b
    };
    let mut seen = std::collections::HashSet::new();
    for &start in &boundary {
        if !seen.insert(start) {
            continue;
        }
        let mut edge = start;
        loop {
            let (_, b) = edge;
            let mut c = third[&edge];
            // Turn around b through the fan until the edge b -> c has no twin.
            while let Some(&d) = third.get(&(c, b)) {
                c = d;
            }
            edge = (b, c);
            if !seen.insert(edge) {
                break;
            }
        }
        out[vertex_label[start.0 as usize] as usize].loops += 1;
    }
    out
}
