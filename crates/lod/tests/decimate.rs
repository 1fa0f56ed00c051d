//! Decimation keeps the original wireframe where it was: attributes at kept vertices
//! untouched, new vertices on the original surface (or, lifted, off it by at most the
//! error) with the original's texture coordinates there, nothing folded, holes and
//! faults kept.

mod common;

use common::{faulted_grid, layer, one_tile_top, shared_data, topology};
use strata_grid::{Face, ReadOptions, SurfaceMesh, Surfaces, layer_surfaces};
use strata_lod::measure::{UvIndex, components, deviation};
use strata_lod::{Decimated, Options, Placement, closest_on_triangle, decimate};

/// Position tolerance for "on the original surface": f32 rounding of coordinates of a
/// few kilometres is about 1e-4 m.
const ON_SURFACE_M: f64 = 1e-3;
/// Texture tolerance: a cell is 2 units wide, so this is 1/20000 of a cell.
const TEXCOORD: f64 = 1e-4;
/// The vertical exaggeration the tests decimate for (distances below scale z by it).
const Z_SCALE: f64 = 5.0;

fn decimate_with(mesh: &SurfaceMesh, fraction: f64, placement: Placement, lift: bool) -> Decimated {
    let options = Options {
        z_scale: Z_SCALE as f32,
        placement,
        lift,
        ..Options::fraction(mesh, fraction)
    };
    decimate(mesh, &options).expect("decimate")
}

/// The second layer surface of a generated faulted 40 x 30 grid.
fn faulted_layer() -> SurfaceMesh {
    layer(&faulted_grid(40, 30), 1)
}

fn decimate_to(mesh: &SurfaceMesh, fraction: f64) -> Decimated {
    decimate_with(mesh, fraction, Placement::Surface, true)
}

/// Where a decimation puts the new vertices, relative to the original surface.
#[derive(Clone, Copy, Debug)]
enum Rule {
    /// At the original's point of their texture coordinates, with its scalar
    /// ([`Placement::Surface`] without the lift).
    OnSurface,
    /// Off that point by at most the reported error (the default: lifted along the
    /// normal there).
    Lifted,
    /// Off the surface by at most the error, with the texture coordinates and scalar of
    /// the original's point nearest them ([`Placement::Optimal`]).
    Nearest,
}

/// Every check of the module on one decimation with the default options; returns the
/// number of new vertices.
fn check(original: &SurfaceMesh, out: &Decimated) -> usize {
    check_placed(original, out, Rule::Lifted)
}

/// [`check`], new vertices placed by `rule`.
fn check_placed(original: &SurfaceMesh, out: &Decimated, rule: Rule) -> usize {
    let mesh = &out.mesh;
    mesh.validate().unwrap();
    assert_eq!(out.source.len(), mesh.vertex_count());
    assert_eq!(out.home.len(), mesh.vertex_count());

    // Surviving original vertices: attributes bit for bit.
    for (v, s) in out.source.iter().enumerate() {
        if let Some(s) = s.get() {
            let s = s as usize;
            assert_eq!(mesh.texcoords[v], original.texcoords[s], "vertex {v}");
            assert_eq!(mesh.positions[v], original.positions[s], "vertex {v}");
        }
    }
    let labels = components(original);
    let index = UvIndex::new(original, labels.clone());
    let new = check_new_vertices(original, out, rule, (&labels, &index));
    check_unfolded(original, out, (&labels, &index));
    check_topology(original, out, &labels);
    new
}

/// New vertices of `out`: the original point they stand for is the one of their
/// texture coordinates (found in texture space), or with `Rule::Nearest` the nearest
/// one (brute force over all triangles of the vertex's component); distances with z
/// scaled as the decimation measured them. `labels` are the original's components,
/// `index` finds its points. Returns how many there are.
fn check_new_vertices(
    original: &SurfaceMesh,
    out: &Decimated,
    rule: Rule,
    (labels, index): (&[u32], &UvIndex),
) -> usize {
    let mesh = &out.mesh;
    let mut found = Vec::new();
    let scaled = |p: [f32; 3]| [f64::from(p[0]), f64::from(p[1]), f64::from(p[2]) * Z_SCALE];
    let tri = |t: &[u32; 3]| t.map(|v| scaled(original.positions[v as usize]));
    let within_error = f64::from(out.error) + ON_SURFACE_M * Z_SCALE;
    let mut new = 0;
    for (v, _) in out.source.iter().enumerate().filter(|(_, s)| s.is_none()) {
        new += 1;
        let p = scaled(mesh.positions[v]);
        let label = labels[out.home[v] as usize];
        let got = mesh.texcoords[v].map(f64::from);
        let (dist, t, w) = match rule {
            Rule::OnSurface | Rule::Lifted => {
                index.find(got, label, &mut found);
                let at = found.first().unwrap_or_else(|| {
                    panic!("new vertex {v}: texture {got:?} is not on the original")
                });
                let t = &original.triangles[at.triangle as usize];
                let c = tri(t);
                let foot: [f64; 3] =
                    std::array::from_fn(|k| (0..3).map(|i| at.barycentric[i] * c[i][k]).sum());
                let d2: f64 = (0..3).map(|k| (p[k] - foot[k]).powi(2)).sum();
                (d2.sqrt(), t, at.barycentric)
            }
            Rule::Nearest => original
                .triangles
                .iter()
                .zip(labels)
                .filter(|&(_, &l)| l == label)
                .map(|(t, _)| {
                    let (d2, w) = closest_on_triangle(p, tri(t));
                    (d2.sqrt(), t, w)
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .unwrap(),
        };
        let allowed = match rule {
            Rule::OnSurface => ON_SURFACE_M * Z_SCALE,
            Rule::Lifted | Rule::Nearest => within_error,
        };
        assert!(
            dist < allowed,
            "new vertex {v} is {dist} off its point of the original (allowed {allowed})"
        );
        let uv: [f64; 2] = std::array::from_fn(|a| {
            (0..3)
                .map(|k| w[k] * f64::from(original.texcoords[t[k] as usize][a]))
                .sum()
        });
        assert!(
            (uv[0] - got[0]).abs() < TEXCOORD && (uv[1] - got[1]).abs() < TEXCOORD,
            "new vertex {v}: texture {got:?}, the original has {uv:?} there"
        );
        if !original.scalars.is_empty() {
            let s: f64 = (0..3)
                .map(|k| w[k] * f64::from(original.scalars[t[k] as usize]))
                .sum();
            let got = f64::from(mesh.scalars[v]);
            assert!(
                (s - got).abs() <= 1e-4 * s.abs().max(1.0),
                "scalar {got} vs {s}"
            );
        }
    }
    new
}

/// Nothing of `out` folded: every triangle keeps the texture-space orientation of the
/// original (counter-clockwise in layer surfaces) and faces the way the original
/// faces at its centroid.
fn check_unfolded(original: &SurfaceMesh, out: &Decimated, (labels, index): (&[u32], &UvIndex)) {
    let mesh = &out.mesh;
    let mut found = Vec::new();
    for (i, t) in mesh.triangles.iter().enumerate() {
        let uv = t.map(|v| mesh.texcoords[v as usize].map(f64::from));
        let area = (uv[1][0] - uv[0][0]) * (uv[2][1] - uv[0][1])
            - (uv[1][1] - uv[0][1]) * (uv[2][0] - uv[0][0]);
        assert!(
            area > 0.0,
            "triangle {i} is folded in texture space ({area})"
        );
        let p = t.map(|v| mesh.positions[v as usize].map(f64::from));
        let cross = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
            let (u, w) = (
                [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
                [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
            );
            [
                u[1] * w[2] - u[2] * w[1],
                u[2] * w[0] - u[0] * w[2],
                u[0] * w[1] - u[1] * w[0],
            ]
        };
        let n = cross(p[0], p[1], p[2]);
        let centre = [
            (uv[0][0] + uv[1][0] + uv[2][0]) / 3.0,
            (uv[0][1] + uv[1][1] + uv[2][1]) / 3.0,
        ];
        let label = labels[out.home[t[0] as usize] as usize];
        index.find(centre, label, &mut found);
        if let Some(f) = found.first() {
            let o = original.triangles[f.triangle as usize]
                .map(|v| original.positions[v as usize].map(f64::from));
            let m = cross(o[0], o[1], o[2]);
            let dot = n[0] * m[0] + n[1] * m[1] + n[2] * m[2];
            assert!(dot > 0.0, "triangle {i} faces away from the original");
        }
    }
}

/// Holes and faults of `out`: the same components (`labels`) as the original, each
/// with the same boundary loops and Euler characteristic (a hole closed, a fault
/// stitched or a strip pinched would change one of them), and boundary vertices only
/// from the original boundary.
fn check_topology(original: &SurfaceMesh, out: &Decimated, labels: &[u32]) {
    let mesh = &out.mesh;
    let before = topology(original, labels);
    let after_labels: Vec<u32> = mesh
        .triangles
        .iter()
        .map(|t| labels[out.home[t[0] as usize] as usize])
        .collect();
    assert_eq!(
        components(mesh).iter().max(),
        labels.iter().max(),
        "components merged or split"
    );
    let after = topology(mesh, &after_labels);
    assert_eq!(before.len(), after.len());
    for (c, (b, a)) in before.iter().zip(&after).enumerate() {
        assert_eq!(b.loops, a.loops, "component {c}: boundary loops");
        assert_eq!(b.euler(), a.euler(), "component {c}: Euler characteristic");
    }
    let original_boundary: std::collections::HashSet<u32> = common::edge_uses(original)
        .into_iter()
        .filter(|&(_, u)| u == 1)
        .flat_map(|((a, b), _)| [a, b])
        .collect();
    for ((a, b), u) in common::edge_uses(mesh) {
        if u == 1 {
            for v in [a, b] {
                let s = out.source[v as usize].get();
                assert!(
                    s.is_some_and(|s| original_boundary.contains(&s)),
                    "boundary vertex {v} is not an original boundary vertex"
                );
            }
        }
    }
}

#[test]
fn faulted_layer_keeps_its_wireframe_at_ten_percent() {
    let original = faulted_layer();
    let out = decimate_to(&original, 0.1);
    let target = (original.triangle_count() as f64 * 0.1).round() as usize;
    assert!(
        out.mesh.triangle_count() <= target + target / 5,
        "{} triangles for a target of {target}",
        out.mesh.triangle_count()
    );
    assert!(out.error > 0.0 && out.error.is_finite());
    let new = check(&original, &out);
    assert!(new > 10, "collapses should place new vertices ({new})");
    // The grid lines moved by little, in the view's exaggerated frame (z x 5): under
    // a cell (50 m) everywhere, and under a quarter of one on average.
    let d = deviation(&original, &out.mesh, &out.home, 4, 5.0);
    assert!(d.max < 50.0 && d.rms < 12.5, "{d:?}");
}

#[test]
fn optimal_placement_keeps_texture_coordinates_of_the_nearest_original_point() {
    let original = faulted_layer();
    let out = decimate_with(&original, 0.1, Placement::Optimal, true);
    let new = check_placed(&original, &out, Rule::Nearest);
    assert!(new > 10, "collapses should place new vertices ({new})");
    let d = deviation(&original, &out.mesh, &out.home, 4, Z_SCALE);
    assert!(d.max < 50.0 && d.rms < 12.5, "{d:?}");
}

#[test]
fn surface_placement_without_the_lift_keeps_every_vertex_on_the_original() {
    let original = faulted_layer();
    let out = decimate_with(&original, 0.1, Placement::Surface, false);
    let new = check_placed(&original, &out, Rule::OnSurface);
    assert!(new > 10, "collapses should place new vertices ({new})");
}

#[test]
fn the_lift_brings_the_grid_lines_closer_to_the_original() {
    let original = faulted_layer();
    for placement in [Placement::Surface, Placement::Optimal] {
        let flat = decimate_with(&original, 0.1, placement, false);
        let lifted = decimate_with(&original, 0.1, placement, true);
        // The same collapses; the lift only moves vertices, each within the error of
        // its point of the original.
        assert_eq!(flat.mesh.triangles, lifted.mesh.triangles);
        let rule = match placement {
            Placement::Surface => Rule::Lifted,
            Placement::Optimal => Rule::Nearest,
        };
        check_placed(&original, &lifted, rule);
        let moved = (flat.mesh.positions.iter().zip(&lifted.mesh.positions))
            .filter(|(a, b)| a != b)
            .count();
        assert!(moved > 10, "{placement:?}: {moved} vertices lifted");
        let before = deviation(&original, &flat.mesh, &flat.home, 4, Z_SCALE);
        let after = deviation(&original, &lifted.mesh, &lifted.home, 4, Z_SCALE);
        assert!(
            after.rms < before.rms,
            "{placement:?}: RMS line distance {} -> {}",
            before.rms,
            after.rms
        );
    }
}

#[test]
fn deterministic() {
    let grid = faulted_grid(30, 20);
    let original = layer(&grid, 0);
    let a = decimate_to(&original, 0.2);
    let b = decimate_to(&original, 0.2);
    assert_eq!(a.mesh, b.mesh);
    assert_eq!(a.source, b.source);
}

#[test]
fn error_bound_stops_early_and_is_reported() {
    let grid = faulted_grid(30, 20);
    let original = layer(&grid, 0);
    let loose = decimate_to(&original, 0.05);
    let options = Options {
        z_scale: 5.0,
        max_error: loose.error / 4.0,
        ..Options::fraction(&original, 0.05)
    };
    let tight = decimate(&original, &options).unwrap();
    assert!(
        tight.error <= options.max_error,
        "{} > {}",
        tight.error,
        options.max_error
    );
    assert!(tight.mesh.triangle_count() > loose.mesh.triangle_count());
    check(&original, &tight);
}

#[test]
fn real_models_keep_their_wireframe() {
    let Some(data) = shared_data("real_models_keep_their_wireframe") else {
        return;
    };
    for (file, k) in [
        ("reek/REEK.EGRID", 0),
        ("emerald/eme_small_w_hole_grid_params.grdecl", 5),
    ] {
        let options = ReadOptions {
            grid_only: true,
            ..ReadOptions::default()
        };
        let grid = strata_grid::open_with(&data.join(file), &options).unwrap();
        let original =
            layer_surfaces(&grid, Face::Top, &Surfaces::layer(k, grid.display_origin())).unwrap();
        let out = decimate_to(&original, 0.1);
        let new = check(&original, &out);
        eprintln!(
            "{file} layer {}: {} -> {} triangles, {new} new vertices, error {}",
            k + 1,
            original.triangle_count(),
            out.mesh.triangle_count(),
            out.error
        );
    }
}

#[test]
fn samples_a_simplified_surface_draws_next_to_a_stray_corner_are_left_out() {
    let measured = |mesh: &SurfaceMesh| {
        let options = Options {
            z_scale: 5.0,
            ..Options::fraction(mesh, 0.1)
        };
        let d = decimate(mesh, &options).expect("decimated");
        deviation(mesh, &d.mesh, &d.home, 2, 5.0)
    };
    // Without leaving out the triangles that reach it, the samples the simplified
    // surface draws on them were 5e11 off: the surface next to it is drawn further
    // from the original than without it (35 against 17 at most), but nothing like that.
    let (without, with) = (
        measured(&one_tile_top(false)),
        measured(&one_tile_top(true)),
    );
    assert!(
        with.vertical < 4.0 * without.vertical && with.rms < 2.0 * without.rms,
        "with the stray corner {with:?}, without {without:?}"
    );
}
