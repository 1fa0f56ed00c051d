//! Building a model's hierarchy file: every layer surface's tree, in batches that fit
//! in memory, written in layer order, with progress told as tiles are built.

use std::path::Path;
use std::time::Instant;

use rayon::prelude::*;
use strata_grid::faults::{Segment, fault_traces};
use strata_grid::outline::{OutlineEdge, outline_edges};
use strata_grid::{
    CellFace, CornerPointGrid, Face, SurfaceMesh, Surfaces, has_faces, layer_surfaces,
    side_surfaces,
};

use super::writer::{LayerCells, StoredNode, StoredTree, Writer};
use crate::hierarchy::{build_layer_with, layer_work};
use crate::{BuildOptions, Error, Progress, Result};

/// What [`build_file`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BuildReport {
    /// Layer surfaces with a tree in the file (empty ones have none).
    pub layers: usize,
    /// Nodes over all layer surfaces.
    pub nodes: usize,
    /// Triangles of the layer surfaces.
    pub input_triangles: usize,
    /// Triangles stored over all levels.
    pub stored_triangles: usize,
    /// Triangles of the side faces (stored at full resolution).
    pub side_triangles: usize,
    /// Highest level (the roots').
    pub levels: u32,
    /// Size of the file.
    pub bytes: u64,
    /// Wall-clock time of the build.
    pub seconds: f64,
}

/// One layer surface built for the file.
struct BuiltSurface {
    input_triangles: usize,
    k: usize,
    face: Face,
    tree: StoredTree,
    cells: Option<LayerCells>,
    /// Its fault traces and outline edges, found before the tree drops the cell
    /// faces.
    faults: Vec<Segment>,
    outline: Vec<OutlineEdge>,
}

/// Bytes one layer surface's hierarchy holds per active cell while it is built: the
/// surface, its reference index and its tree: the measured need per cell, rounded up
/// (`docs/performance.md`, "Hierarchy build and view").
const BUILD_BYTES_PER_CELL: f64 = 160.0;

/// How many layer surfaces to build at once: one per thread, fewer when `memory` (bytes)
/// cannot hold that many of the largest; an error when it cannot hold one.
fn batch_size(grid: &CornerPointGrid, memory: Option<u64>) -> Result<usize> {
    let threads = rayon::current_num_threads().max(1);
    let Some(memory) = memory else {
        return Ok(threads);
    };
    let d = grid.dims();
    let largest = (0..d.nz)
        .map(|k| grid.active_count_in(k, 0..d.ny))
        .max()
        .unwrap_or(0);
    let each = largest as f64 * BUILD_BYTES_PER_CELL;
    if each > memory as f64 {
        return Err(Error::Option(format!(
            "a layer of {largest} active cells needs about {:.1} GB to build its hierarchy, \
             and {:.1} GB of memory is available",
            each / 1e9,
            memory as f64 / 1e9
        )));
    }
    Ok(((memory as f64 / each.max(1.0)) as usize).clamp(1, threads))
}

/// Builds the hierarchy of every layer surface of `grid` (the top faces of each layer
/// and the bottom faces of the last, like `strata render`), with `property` as scalar,
/// and writes it to `path`. Layers are built on all cores, in batches whose results
/// are written in layer order, so the file does not depend on the thread count.
/// [`BuildOptions::progress`] is told the tiles built, each weighed by its work (a
/// leaf's, or a parent's several times that).
pub fn build_file(
    grid: &CornerPointGrid,
    property: Option<&str>,
    path: &Path,
    options: &BuildOptions,
) -> Result<BuildReport> {
    options.check()?;
    let start = Instant::now();
    let d = grid.dims();
    let dims = [
        u32::try_from(d.nx).map_err(|_| Error::Option(format!("nx = {} is too large", d.nx)))?,
        u32::try_from(d.ny).map_err(|_| Error::Option(format!("ny = {} is too large", d.ny)))?,
    ];
    let (view_box, stray) = grid.view_box_and_stray_corners();
    let origin = view_box.display_centre();
    let surfaces: Vec<(usize, Face)> = (0..d.nz)
        .map(|k| (k, Face::Top))
        .chain((d.nz > 0).then_some((d.nz - 1, Face::Bottom)))
        .collect();
    let tell = |progress: Progress| {
        if let Some(f) = &options.progress {
            f(progress);
        }
    };
    tell(Progress::Started {
        work: surfaces.len() as u64 * layer_work(dims, options.tile_cells),
        surfaces: surfaces.len(),
    });
    let built = |units: u64| tell(Progress::Worked(units));
    // The side faces of all layers at once, so that a vertex between two layers
    // averages the property over both, as `strata render --sides` draws it.
    let sides = sides_by_layer(
        &side_surfaces(grid, &Surfaces::new(0..d.nz, origin).property(property))?,
        d.nz,
    );
    let batch = batch_size(grid, options.memory)?;
    let mut writer = Writer::create(path)?;
    let mut report = BuildReport::default();
    let mut written = 0;
    for chunk in surfaces.chunks(batch) {
        let built: Vec<BuiltSurface> = chunk
            .par_iter()
            .map(|&(k, face)| {
                let mut mesh =
                    layer_surfaces(grid, face, &Surfaces::layer(k, origin).property(property))?;
                let cells = property.map(|_| LayerCells::of(&mesh, dims));
                // Found at full resolution, which the nodes, without cell faces, lose.
                let faults = fault_traces(&mesh);
                let outline = outline_edges(&mesh);
                // The tree needs no cell faces: 24 bytes a cell less while it is built.
                mesh.cell_faces = Vec::new();
                let mut tree = build_layer_with(&mesh, dims, options, &built, &StoredNode::of)?;
                count_exposed(&mut tree, &ExposedFaces::of(grid, k, face));
                Ok(BuiltSurface {
                    input_triangles: mesh.triangle_count(),
                    k,
                    face,
                    tree,
                    cells,
                    faults,
                    outline,
                })
            })
            .collect::<Result<_>>()?;
        for s in built {
            let tree = &s.tree;
            // A grid layer's side faces go with its top surface.
            let sides = match s.face {
                Face::Top => sides.get(s.k),
                Face::Bottom => None,
            };
            report.input_triangles += s.input_triangles;
            report.stored_triangles += tree
                .iter()
                .map(|(n, _)| n.record.index_count as usize / 3)
                .sum::<usize>();
            report.levels = report
                .levels
                .max(tree.first().map_or(0, |(n, _)| n.record.level));
            report.nodes += tree.len();
            report.layers += usize::from(!tree.is_empty());
            report.side_triangles += sides.map_or(0, SurfaceMesh::triangle_count);
            writer.layer(
                s.k as u32,
                s.face,
                tree,
                s.cells.as_ref(),
                sides,
                (&s.faults, &s.outline),
            )?;
            written += 1;
            tell(Progress::Written {
                written,
                surfaces: surfaces.len(),
                input_triangles: report.input_triangles,
                stored_triangles: report.stored_triangles,
            });
        }
    }
    let scalar_range = property.map(|name| cell_range(grid, name));
    let framed = stray.map(|s| s.rest.to_display(origin));
    report.bytes = writer.finish(origin, dims, options.tile_cells, scalar_range, framed)?;
    report.seconds = start.elapsed().as_secs_f64();
    Ok(report)
}

/// A layer surface's faces that its closed stack may show, counted over the (i, j)
/// domain so that any block of cells has its count at once: a summed-area table.
struct ExposedFaces {
    nx: usize,
    /// `(nx + 1) (ny + 1)` partial sums: row `j`, column `i` holds the exposed faces
    /// of the cells before `i` in the rows before `j`.
    sums: Vec<u32>,
}

impl ExposedFaces {
    /// The faces of grid layer `k`'s surface `face` not covered by a face of the layer
    /// above or below in the same column: with side faces drawn, the others are
    /// inside the stack, seen from nowhere outside it. The bottom surface and the top
    /// of the first layer stand for the stack's outside: all their faces count.
    fn of(grid: &CornerPointGrid, k: usize, face: Face) -> Self {
        let d = grid.dims();
        let has = |i: usize, j: usize, k: usize| has_faces(grid, i, j, k);
        let exposed = |i: usize, j: usize| {
            has(i, j, k)
                && match face {
                    Face::Bottom => true,
                    Face::Top => k == 0 || !has(i, j, k - 1) || (k + 1 < d.nz && !has(i, j, k + 1)),
                }
        };
        let mut sums = vec![0u32; (d.nx + 1) * (d.ny + 1)];
        for j in 0..d.ny {
            let mut row = 0;
            for i in 0..d.nx {
                row += u32::from(exposed(i, j));
                sums[(j + 1) * (d.nx + 1) + i + 1] = sums[j * (d.nx + 1) + i + 1] + row;
            }
        }
        ExposedFaces { nx: d.nx, sums }
    }

    /// Exposed faces of the cells `i0..i1` by `j0..j1`.
    fn within(&self, [i0, j0, i1, j1]: [u32; 4]) -> u32 {
        let at = |i: u32, j: u32| self.sums[j as usize * (self.nx + 1) + i as usize];
        at(i1, j1) + at(i0, j0) - at(i0, j1) - at(i1, j0)
    }
}

/// Records in each node of `tree` how many of its cells' faces `exposed` counts.
fn count_exposed(tree: &mut StoredTree, exposed: &ExposedFaces) {
    for (node, _) in tree.iter_mut() {
        node.record.exposed = exposed.within(node.record.cells);
    }
}

/// `sides`, the side faces of grid layers in layer order, cut into one mesh per grid
/// layer of `nz`; each vertex keeps its scalar.
fn sides_by_layer(sides: &SurfaceMesh, nz: usize) -> Vec<SurfaceMesh> {
    let mut out: Vec<SurfaceMesh> = (0..nz)
        .map(|_| SurfaceMesh::with_origin(sides.origin))
        .collect();
    // Per input vertex: the layer it was last taken into, and its index there.
    let mut taken = vec![(u32::MAX, 0u32); sides.vertex_count()];
    for face in &sides.cell_faces {
        let k = face.cell[2];
        let Some(mesh) = out.get_mut(k as usize) else {
            continue;
        };
        let first = mesh.triangles.len() as u32;
        for t in face.triangles {
            let triangle = sides.triangles[t as usize].map(|v| {
                let (layer, index) = &mut taken[v as usize];
                if *layer != k {
                    *layer = k;
                    *index = mesh.positions.len() as u32;
                    mesh.positions.push(sides.positions[v as usize]);
                    mesh.texcoords.push(sides.texcoords[v as usize]);
                    if let Some(&s) = sides.scalars.get(v as usize) {
                        mesh.scalars.push(s);
                    }
                }
                *index
            });
            mesh.triangles.push(triangle);
        }
        mesh.cell_faces.push(CellFace {
            triangles: [first, first + 1],
            ..*face
        });
    }
    out
}

/// Smallest and largest finite value of property `name` over the active cells (NaN
/// when there is none).
fn cell_range(grid: &CornerPointGrid, name: &str) -> [f32; 2] {
    grid.active_values(name, 0..grid.dims().nz)
        .into_iter()
        .flatten()
        .filter(|v| v.is_finite())
        .fold([f32::NAN; 2], |[lo, hi], v| [lo.min(v), hi.max(v)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};
    use strata_grid::synth::{SynthParams, generate};
    #[test]
    fn the_build_counts_every_tile_of_every_layer_surface_once() {
        // 10 x 7 cells in tiles of 4: 3 x 2 leaves, 2 x 1 parents, then the root and
        // the levels above it.
        assert_eq!(layer_work([10, 7], 4), 6 + 20 * (2 + 1 + 1));
        let mut grid = generate(&SynthParams {
            nx: 30,
            ny: 20,
            nz: 3,
            faults: 2,
            seed: 3,
        })
        .expect("a generated grid");
        // An empty layer still counts all its tiles, so the bar ends full.
        grid.actnum
            .slice_mut(strata_grid::ndarray::s![1, .., ..])
            .fill(false);
        let dir = tempfile::tempdir().expect("a temporary folder");
        let log = Arc::new(Mutex::new(Vec::new()));
        let tell = Arc::clone(&log);
        let options = BuildOptions {
            tile_cells: 4,
            progress: Some(Arc::new(move |p| {
                tell.lock().expect("not poisoned").push(p)
            })),
            ..BuildOptions::default()
        };
        let path = dir.path().join("counted.lod");
        let report = build_file(&grid, None, &path, &options).expect("the hierarchy is built");
        assert_eq!(report.layers, 3, "the empty layer has no surface");
        let whole = 4 * layer_work([30, 20], 4);
        let told = std::mem::take(&mut *log.lock().expect("not poisoned"));
        assert_eq!(
            told.first(),
            Some(&Progress::Started {
                work: whole,
                surfaces: 4
            })
        );
        let worked: u64 = told
            .iter()
            .map(|p| match p {
                Progress::Worked(units) => *units,
                _ => 0,
            })
            .sum();
        assert_eq!(worked, whole);
        assert!(matches!(
            told.last(),
            Some(Progress::Written {
                written: 4,
                surfaces: 4,
                ..
            })
        ));

        // Tiles of no cells are refused before anything is told.
        let none = BuildOptions {
            tile_cells: 0,
            ..options
        };
        let err = build_file(&grid, None, &path, &none).err();
        assert!(
            err.as_ref()
                .is_some_and(|e| e.to_string().contains("tile_cells must be in 1..=4096")),
            "{err:?}"
        );
        assert!(log.lock().expect("not poisoned").is_empty());
    }
}
