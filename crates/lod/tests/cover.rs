//! Decimation with outlines that only grow outward (`Options::cover`): every cell of
//! the original stays under exactly one triangle of its own piece, so that a renderer
//! masking fragments by cell draws the original outlines, holes and fault traces.

mod common;

use common::{faulted_grid, layer, shared_data};
use strata_grid::{Face, ReadOptions, SurfaceMesh, Surfaces, layer_surfaces};
use strata_lod::measure::outline_bound;
use strata_lod::{CellCover, Decimated, Options, decimate};

/// Points inside a cell, as fractions of it, off its diagonals and off any line
/// through two grid nodes of small integer offsets (so no decimated edge runs through
/// them exactly).
const SAMPLES: [[f64; 2]; 4] = [
    [0.3137, 0.4271],
    [0.7129, 0.6043],
    [0.2417, 0.8311],
    [0.8233, 0.1571],
];

fn decimate_covering(mesh: &SurfaceMesh, fraction: f64) -> Decimated {
    let options = Options {
        z_scale: 5.0,
        ..Options::covering(mesh, fraction)
    };
    decimate(mesh, &options).expect("decimate")
}

/// How many samples of the original's cells lie under no triangle of their piece, and
/// how many under more than one, and how many samples there are.
fn coverage(original: &SurfaceMesh, out: &Decimated) -> (usize, usize, usize) {
    let cover = CellCover::of(original).expect("cell faces");
    let pieces = out.pieces(original, &cover);
    let (mut uncovered, mut doubled, mut samples) = (0, 0, 0);
    for (p, piece) in cover.pieces.iter().enumerate() {
        let triangles: Vec<[[f64; 2]; 3]> = out
            .mesh
            .triangles
            .iter()
            .filter(|t| pieces[t[0] as usize] as usize == p)
            .map(|t| t.map(|v| out.mesh.texcoords[v as usize].map(f64::from)))
            .collect();
        for y in 0..piece.size[1] as i32 {
            for x in 0..piece.size[0] as i32 {
                let cell = [piece.origin[0] + x, piece.origin[1] + y];
                if !piece.covers(cell) {
                    continue;
                }
                for [fx, fy] in SAMPLES {
                    let uv = [
                        2.0 * f64::from(cell[0]) + 1.0 + 2.0 * fx,
                        2.0 * f64::from(cell[1]) + 1.0 + 2.0 * fy,
                    ];
                    let under = triangles.iter().filter(|t| contains(t, uv)).count();
                    samples += 1;
                    uncovered += usize::from(under == 0);
                    doubled += usize::from(under > 1);
                }
            }
        }
    }
    (uncovered, doubled, samples)
}

fn contains(t: &[[f64; 2]; 3], p: [f64; 2]) -> bool {
    let side =
        |a: [f64; 2], b: [f64; 2]| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
    let s = [side(t[0], t[1]), side(t[1], t[2]), side(t[2], t[0])];
    s.iter().all(|&v| v > 0.0) || s.iter().all(|&v| v < 0.0)
}

/// The cells (i, j) with i + j < n, a staircase along the diagonal, on a gently
/// curved surface: every other corner of its outline is a reflex one.
fn staircase(n: usize) -> SurfaceMesh {
    let mut mesh = SurfaceMesh::with_origin([0.0; 3]);
    let node = |i: usize, j: usize| i * (n + 1) + j;
    for i in 0..=n {
        for j in 0..=n {
            let (x, y) = (i as f32 * 10.0, j as f32 * 10.0);
            mesh.positions
                .push([x, y, 0.002 * (x - 50.0) * (x - 50.0) + 0.001 * x * y]);
            mesh.texcoords
                .push([2.0 * i as f32 + 1.0, 2.0 * j as f32 + 1.0]);
            mesh.scalars.push(0.0);
        }
    }
    for i in 0..n {
        for j in 0..n - i {
            let [a, b, c, d] = [
                node(i, j),
                node(i + 1, j),
                node(i + 1, j + 1),
                node(i, j + 1),
            ]
            .map(|v| v as u32);
            mesh.triangles.push([a, b, c]);
            mesh.triangles.push([a, c, d]);
        }
    }
    // Drop the nodes no triangle uses (beyond the staircase), keeping the order.
    let mut used = vec![u32::MAX; mesh.positions.len()];
    let mut kept = SurfaceMesh::with_origin([0.0; 3]);
    for t in &mut mesh.triangles {
        for v in t.iter_mut() {
            if used[*v as usize] == u32::MAX {
                used[*v as usize] = kept.positions.len() as u32;
                kept.positions.push(mesh.positions[*v as usize]);
                kept.texcoords.push(mesh.texcoords[*v as usize]);
                kept.scalars.push(mesh.scalars[*v as usize]);
            }
            *v = used[*v as usize];
        }
    }
    kept.triangles = mesh.triangles;
    kept
}

#[test]
fn a_staircase_outline_goes_below_its_corner_bound_and_keeps_its_cells() {
    let mesh = staircase(30);
    let bound = outline_bound(&mesh);
    let out = decimate_covering(&mesh, 0.02);
    let (uncovered, doubled, samples) = coverage(&mesh, &out);
    eprintln!(
        "staircase: {} -> {} triangles (outline bound {} triangles for {} corners); \
         {samples} samples, {uncovered} uncovered, {doubled} doubled",
        mesh.triangle_count(),
        out.mesh.triangle_count(),
        bound.min_triangles,
        bound.corners
    );
    assert!(
        out.mesh.triangle_count() < bound.min_triangles / 2,
        "the staircase's reflex corners should go"
    );
    assert_eq!((uncovered, doubled), (0, 0));
    // The outline grew outward over the notches of the staircase: each of its 29
    // reflex corners cut off holds half a cell (2 squared texture units).
    let area = |m: &SurfaceMesh| -> f64 {
        m.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| m.texcoords[v as usize].map(f64::from));
                0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs()
            })
            .sum()
    };
    let grown = area(&out.mesh) - area(&mesh);
    assert!(grown > 2.0 * 25.0, "grew by {grown}");
    // Without cover, the same budget (under the outline bound) cuts some of the
    // staircase's corners inward, and the samples there are lost.
    let options = Options {
        z_scale: 5.0,
        ..Options::fraction(&mesh, 0.02)
    };
    let kept = decimate(&mesh, &options).expect("decimate");
    assert!(kept.mesh.triangle_count() < bound.min_triangles);
    let (lost, _, _) = coverage(&mesh, &kept);
    assert!(lost > 0, "no sample lost without cover");
}

#[test]
fn faults_and_holes_keep_their_cells() {
    let mesh = layer(&faulted_grid(40, 30), 1);
    let cover = CellCover::of(&mesh).expect("cell faces");
    assert!(cover.pieces.len() > 1, "the faults split the layer");
    for fraction in [0.2, 0.05] {
        let out = decimate_covering(&mesh, fraction);
        let (uncovered, doubled, samples) = coverage(&mesh, &out);
        eprintln!(
            "faulted layer at {fraction}: {} -> {} triangles, {samples} samples, \
             {uncovered} uncovered, {doubled} doubled",
            mesh.triangle_count(),
            out.mesh.triangle_count()
        );
        assert_eq!((uncovered, doubled), (0, 0), "at {fraction}");
    }
}

#[test]
fn emerald_reaches_ten_percent_and_keeps_its_cells() {
    let Some(data) = shared_data("emerald_reaches_ten_percent_and_keeps_its_cells") else {
        return;
    };
    let path = data.join("emerald/eme_small_w_hole_grid_params.grdecl");
    let grid = strata_grid::open_with(
        &path,
        &ReadOptions {
            grid_only: true,
            ..ReadOptions::default()
        },
    )
    .expect("emerald");
    let mesh = layer_surfaces(&grid, Face::Top, &Surfaces::layer(1, grid.display_origin()))
        .expect("layer");
    let out = decimate_covering(&mesh, 0.1);
    let target = Options::fraction(&mesh, 0.1).target_triangles;
    let (uncovered, doubled, samples) = coverage(&mesh, &out);
    eprintln!(
        "emerald layer 2: {} -> {} triangles (target {target}, outline bound {}), \
         {samples} samples, {uncovered} uncovered, {doubled} doubled",
        mesh.triangle_count(),
        out.mesh.triangle_count(),
        outline_bound(&mesh).min_triangles
    );
    assert!(out.mesh.triangle_count() <= target + 2);
    assert!(target < outline_bound(&mesh).min_triangles);
    assert_eq!((uncovered, doubled), (0, 0));
}

#[test]
fn a_mesh_not_made_of_cells_is_refused() {
    let mut mesh = staircase(4);
    mesh.texcoords[0] = [0.0, 0.0];
    let options = Options {
        cover: true,
        ..Options::fraction(&mesh, 0.5)
    };
    let err = decimate(&mesh, &options).expect_err("not cell faces");
    assert!(err.to_string().contains("cell"), "{err}");
}
