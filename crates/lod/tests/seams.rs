//! Side walls stay closed: where two boundaries of a surface coincide (a layer pinched
//! out between two walls, a wall of constant i meeting one of constant j at a corner
//! pillar), their vertices coincide in position but not in texture coordinates, and
//! decimation moves both boundaries together or neither.

mod common;

use std::collections::HashMap;
use std::path::Path;

use common::{edge_uses, faulted_grid, shared_data};
use strata_grid::{
    CornerPointGrid, Face, ReadOptions, SurfaceMesh, Surfaces, layer_surfaces, side_surfaces,
};
use strata_lod::{Decimated, Options, decimate, decimate_chosen, stitch};

/// A position, bit for bit.
type Key = [u32; 3];

fn key(mesh: &SurfaceMesh, v: u32) -> Key {
    mesh.positions[v as usize].map(f32::to_bits)
}

/// The boundary edges of `mesh` (in one triangle), as pairs of vertices.
fn boundary_edges(mesh: &SurfaceMesh) -> Vec<(u32, u32)> {
    edge_uses(mesh)
        .into_iter()
        .filter(|&(_, n)| n == 1)
        .map(|(e, _)| e)
        .collect()
}

/// The seams of `mesh`: the boundary edges that run twice between the same two
/// positions (bit for bit), once on either side, as segments.
fn seams(mesh: &SurfaceMesh) -> Vec<[[f64; 3]; 2]> {
    let mut sides: HashMap<(Key, Key), usize> = HashMap::new();
    for (a, b) in boundary_edges(mesh) {
        let (ka, kb) = (key(mesh, a), key(mesh, b));
        if ka != kb {
            *sides.entry((ka.min(kb), ka.max(kb))).or_default() += 1;
        }
    }
    sides
        .into_iter()
        .filter(|&(_, n)| n == 2)
        .map(|((a, b), _)| [a, b].map(|k| k.map(|c| f64::from(f32::from_bits(c)))))
        .collect()
}

fn distance_to_segment(p: [f64; 3], segment: [[f64; 3]; 2]) -> f64 {
    distance(p, nearest_on_segment(p, segment))
}

/// The boundary edges of `mesh` that lie on `seams` (both ends and the middle within
/// `tolerance` of a seam; a face thin to nothing at one end has an edge of no
/// length there, which is left out), and how many of them have no boundary edge between the
/// same two places (within `tolerance`) on the other side: the cracks. A seam vertex
/// that moved off its seam alone leaves the edges of its twin, still on the seam,
/// open.
fn open_seam_edges(mesh: &SurfaceMesh, seams: &[[[f64; 3]; 2]], tolerance: f64) -> (usize, usize) {
    let point = |v: u32| mesh.positions[v as usize].map(f64::from);
    let on_seam = |p: [f64; 3]| {
        seams
            .iter()
            .any(|&s| distance_to_segment(p, s) <= tolerance)
    };
    let near = |p: [f64; 3], q: [f64; 3]| (0..3).all(|k| (p[k] - q[k]).abs() <= tolerance);
    let edges: Vec<[[f64; 3]; 2]> = boundary_edges(mesh)
        .into_iter()
        .map(|(a, b)| [point(a), point(b)])
        .filter(|&[a, b]| {
            let middle = std::array::from_fn(|k| 0.5 * (a[k] + b[k]));
            !near(a, b) && on_seam(a) && on_seam(b) && on_seam(middle)
        })
        .collect();
    let open = edges
        .iter()
        .enumerate()
        .filter(|&(i, &[a, b])| {
            !edges.iter().enumerate().any(|(j, &[c, d])| {
                j != i && ((near(a, c) && near(b, d)) || (near(a, d) && near(b, c)))
            })
        })
        .count();
    (edges.len(), open)
}

/// The nearest point to `p` on segment `a b`.
fn nearest_on_segment(p: [f64; 3], [a, b]: [[f64; 3]; 2]) -> [f64; 3] {
    let ab: [f64; 3] = std::array::from_fn(|k| b[k] - a[k]);
    let ap: [f64; 3] = std::array::from_fn(|k| p[k] - a[k]);
    let len2: f64 = ab.iter().map(|c| c * c).sum();
    let t = if len2 > 0.0 {
        (ab.iter().zip(&ap).map(|(x, y)| x * y).sum::<f64>() / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    std::array::from_fn(|k| a[k] + t * ab[k])
}

/// The widths of the cracks between `outputs` where their `inputs` meet: at the middle
/// of each outline edge that two inputs share (bit for bit), how far the outline of
/// either output nearest there lies off the other's, the nearer of the two. Zero where
/// the outputs' outlines run along the same polyline, wherever the stitch put its
/// nodes.
fn crack_widths(inputs: &[SurfaceMesh], outputs: &[&SurfaceMesh]) -> Vec<f64> {
    let point = |m: &SurfaceMesh, v: u32| m.positions[v as usize].map(f64::from);
    let mut owners: HashMap<(Key, Key), Vec<usize>> = HashMap::new();
    for (s, input) in inputs.iter().enumerate() {
        for (a, b) in boundary_edges(input) {
            let (ka, kb) = (key(input, a), key(input, b));
            let list = owners.entry((ka.min(kb), ka.max(kb))).or_default();
            if !list.contains(&s) {
                list.push(s);
            }
        }
    }
    let outlines: Vec<Vec<[[f64; 3]; 2]>> = outputs
        .iter()
        .map(|m| {
            boundary_edges(m)
                .into_iter()
                .map(|(a, b)| [point(m, a), point(m, b)])
                .collect()
        })
        .collect();
    let nearest = |s: usize, p: [f64; 3]| {
        outlines[s]
            .iter()
            .map(|&e| nearest_on_segment(p, e))
            .min_by(|x, y| distance(*x, p).total_cmp(&distance(*y, p)))
    };
    owners
        .into_iter()
        .filter(|(_, list)| list.len() == 2)
        .filter_map(|((ka, kb), list)| {
            let [a, b] = [ka, kb].map(|k| k.map(|c| f64::from(f32::from_bits(c))));
            let middle = std::array::from_fn(|k| 0.5 * (a[k] + b[k]));
            // From each output's outline point nearest the middle to the other's
            // outline: where the two meet, one of these lies on both. Not between the
            // two nearest points: another outline of the same surface close by (a
            // wall's deeper layers across a fault) can be nearer the middle than the
            // one that meets the other surface there.
            let (on_first, on_second) = (nearest(list[0], middle)?, nearest(list[1], middle)?);
            let first_off = distance(on_first, nearest(list[1], on_first)?);
            let second_off = distance(on_second, nearest(list[0], on_second)?);
            Some(first_off.min(second_off))
        })
        .collect()
}

/// Edges of `mesh` between two triangles of opposite orientation in texture space: a
/// triangle turned over in the drawn grid.
fn texture_folds(mesh: &SurfaceMesh) -> usize {
    let orientation = |t: &[u32; 3]| {
        let [a, b, c] = t.map(|v| mesh.texcoords[v as usize].map(f64::from));
        ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).signum()
    };
    let mut sides: HashMap<(u32, u32), Vec<f64>> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            sides
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push(orientation(t));
        }
    }
    sides
        .values()
        .filter(|s| s.len() == 2 && s[0] != s[1])
        .count()
}

fn distance(p: [f64; 3], q: [f64; 3]) -> f64 {
    (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt()
}

/// How near two places must be to count as one: a millionth of `mesh`'s extent.
fn tolerance(mesh: &SurfaceMesh) -> f64 {
    let extent = mesh
        .positions
        .iter()
        .flat_map(|p| p.map(|c| f64::from(c).abs()))
        .fold(0.0, f64::max);
    1e-6 * extent
}

fn sample() -> CornerPointGrid {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/sample.grdecl");
    strata_grid::open(&path).expect("the sample model")
}

/// The side walls of all of `grid`'s layers, coloured by `property`.
fn sides(grid: &CornerPointGrid, property: Option<&str>) -> SurfaceMesh {
    let nz = grid.dims().nz;
    side_surfaces(
        grid,
        &Surfaces::new(0..nz, grid.display_origin()).property(property),
    )
    .expect("side surfaces")
}

/// `mesh` decimated to `percent` of its triangles as `strata render --lod` does.
fn options(mesh: &SurfaceMesh, percent: f64) -> Options {
    Options {
        z_scale: 5.0,
        ..Options::fraction(mesh, percent / 100.0)
    }
}

/// The seams of `walls`, checked closed, then those its decimation to `percent`
/// leaves open, by [`decimate`] and by [`decimate_chosen`].
fn check(name: &str, walls: &SurfaceMesh, percent: f64) {
    let seams = seams(walls);
    let tolerance = tolerance(walls);
    let (edges, open) = open_seam_edges(walls, &seams, tolerance);
    assert!(
        edges > 50 && open == 0,
        "{name}: {edges} seam edges, {open} open before decimating"
    );
    let options = options(walls, percent);
    let ours = decimate(walls, &options).expect("decimate");
    let chosen = decimate_chosen(walls, &options).expect("decimate_chosen");
    for (how, out) in [("decimate", &ours), ("decimate_chosen", &chosen.decimated)] {
        let kept = out.mesh.triangle_count();
        let (left, open) = open_seam_edges(&out.mesh, &seams, tolerance);
        eprintln!(
            "{name} {how}: {} -> {kept} triangles, seam edges {edges} -> {left}, {open} open",
            walls.triangle_count()
        );
        assert!(left > 0, "{name} {how}: no seam edge left to check");
        assert_eq!(open, 0, "{name} {how}: {open} of {left} seam edges open");
        assert!(
            (kept as f64) < 0.5 * walls.triangle_count() as f64,
            "{name} {how}: {kept} triangles"
        );
    }
}

/// The top of `grid`'s first layer, the bottom of its last and its side walls, as
/// `strata render --sides` draws them, decimated to `percent` each: where their
/// outlines meet, they leave cracks open until stitched. At most `most_cracks` of
/// the shared outline's edges may stay cracked.
fn check_stitched(name: &str, grid: &CornerPointGrid, percent: f64, most_cracks: usize) {
    let (nz, origin) = (grid.dims().nz, grid.display_origin());
    let surfaces = [
        layer_surfaces(grid, Face::Top, &Surfaces::layer(0, origin)).expect("top"),
        layer_surfaces(grid, Face::Bottom, &Surfaces::layer(nz - 1, origin)).expect("bottom"),
        sides(grid, None),
    ];
    let mut input = SurfaceMesh::with_origin(origin);
    surfaces.iter().for_each(|m| input.append(m));
    let tolerance = tolerance(&input);
    // Crack widths over `tolerance`: how many, of how many shared edges, the widest.
    let widths = |meshes: &[&SurfaceMesh]| {
        let widths = crack_widths(&surfaces, meshes);
        let open = widths.iter().filter(|&&w| w > tolerance).count();
        (
            open,
            widths.len(),
            widths.iter().copied().fold(0.0, f64::max),
        )
    };
    let cracks =
        |outputs: &[Decimated]| widths(&outputs.iter().map(|d| &d.mesh).collect::<Vec<_>>());
    let (open, edges, _) = widths(&surfaces.iter().collect::<Vec<_>>());
    assert!(
        edges > 100 && open == 0,
        "{name}: {edges} shared outline edges, {open} cracked before decimating"
    );
    let mut outputs: Vec<Decimated> = surfaces
        .iter()
        .map(|m| {
            decimate_chosen(m, &options(m, percent))
                .expect("decimate_chosen")
                .decimated
        })
        .collect();
    let before = cracks(&outputs);
    let folds =
        |outputs: &[Decimated]| -> usize { outputs.iter().map(|d| texture_folds(&d.mesh)).sum() };
    let folds_before = folds(&outputs);
    let unstitched: usize = outputs.iter().map(|d| d.mesh.triangle_count()).sum();
    let inputs: Vec<&SurfaceMesh> = surfaces.iter().collect();
    let mut again = outputs.clone();
    let stitched = stitch(&inputs, &mut outputs.iter_mut().collect::<Vec<_>>());
    // Deterministic: the same again, bit for bit.
    assert_eq!(
        stitch(&inputs, &mut again.iter_mut().collect::<Vec<_>>()),
        stitched
    );
    for (a, b) in outputs.iter().zip(&again) {
        assert!(a.mesh == b.mesh && a.source == b.source && a.home == b.home);
    }
    let after = cracks(&outputs);
    let triangles =
        |outputs: &[Decimated]| -> usize { outputs.iter().map(|d| d.mesh.triangle_count()).sum() };
    eprintln!(
        "{name}: {} -> {} -> {} triangles, {stitched:?}; cracks (count, of, widest) \
         {before:?} -> {after:?}",
        input.triangle_count(),
        unstitched,
        triangles(&outputs),
    );
    assert!(stitched.inserted > 0, "{name}: {stitched:?}");
    assert!(
        folds(&outputs) <= folds_before,
        "{name}: {} triangles turned over in texture space by stitching, {folds_before} before",
        folds(&outputs)
    );
    assert!(
        after.0 <= most_cracks && after.0 * 10 <= before.0,
        "{name}: {} of {} shared outline edges cracked, {} before stitching",
        after.0,
        after.1,
        before.0
    );
    assert!(
        (triangles(&outputs) as f64) < 0.5 * input.triangle_count() as f64,
        "{name}: {} triangles",
        triangles(&outputs)
    );
}

#[test]
fn the_samples_tops_and_walls_meet_once_stitched() {
    check_stitched("sample", &sample(), 10.0, 0);
}

#[test]
fn a_faulted_models_tops_and_walls_meet_once_stitched() {
    check_stitched("faulted", &faulted_grid(40, 30), 10.0, 0);
}

#[test]
fn the_samples_side_walls_stay_closed() {
    check("sample", &sides(&sample(), Some("PORO")), 10.0);
}

#[test]
fn a_faulted_models_side_walls_stay_closed() {
    check("faulted", &sides(&faulted_grid(40, 30), Some("PORO")), 10.0);
}

/// The shared real models with walls on pinched-out layers and holes, read grid only,
/// each with its file name; none (said so) without the shared data.
fn real_models(test: &str) -> Vec<(&'static str, CornerPointGrid)> {
    let Some(data) = shared_data(test) else {
        return Vec::new();
    };
    let options = ReadOptions {
        grid_only: true,
        ..ReadOptions::default()
    };
    [
        "reek/REEK.EGRID",
        "emerald/eme_small_w_hole_grid_params.grdecl",
    ]
    .into_iter()
    .map(|file| {
        let grid = strata_grid::open_with(&data.join(file), &options).expect("a shared model");
        (file, grid)
    })
    .collect()
}

#[test]
fn real_models_side_walls_stay_closed() {
    for (file, grid) in real_models("real_models_side_walls_stay_closed") {
        check(file, &sides(&grid, None), 10.0);
    }
}

#[test]
fn real_models_tops_and_walls_meet_once_stitched() {
    for (file, grid) in real_models("real_models_tops_and_walls_meet_once_stitched") {
        // Where a node can go neither where the input has it nor anywhere towards the
        // edge it splits without folding a triangle, a crack stays: emerald's layers
        // pinch out next to their walls.
        let most = if file.starts_with("reek") { 0 } else { 4 };
        check_stitched(file, &grid, 10.0, most);
    }
}
