//! The cell mask of `Renderer::prepare_covered`: a surface decimated with outlines
//! that only grow outward (strata-lod's `Options::cover`) is drawn over the cells of
//! the original only, so its outline and its grid lines are the original's. Frames use
//! the measuring convention of support/mod.rs; CI runs this file on llvmpipe (GL) and
//! lavapipe (Vulkan).

mod support;

use strata_grid::SurfaceMesh;
use strata_lod::{CellCover, Options, decimate};
use strata_render::glam::Vec3;
use strata_render::{Camera, Coverage, View, WireMode};
use support::*;

const SIZE: u32 = 400;
const CELLS: usize = 24;

/// The cells (i, j) with i + j < CELLS of a gently curved grid: a staircase outline
/// along the diagonal.
fn staircase() -> SurfaceMesh {
    let full = SurfaceMesh::structured(CELLS, CELLS, |i, j| {
        let (x, y) = (i as f32 * 10.0, j as f32 * 10.0);
        [x, y, 0.01 * (x - 120.0) * (y - 120.0) / 12.0]
    });
    let mut mesh = full.clone();
    mesh.triangles.clear();
    mesh.cell_faces.clear();
    for face in &full.cell_faces {
        if (face.cell[0] + face.cell[1]) as usize >= CELLS {
            continue;
        }
        let t = mesh.triangles.len() as u32;
        for old in face.triangles {
            mesh.triangles.push(full.triangles[old as usize]);
        }
        mesh.cell_faces.push(strata_grid::CellFace {
            triangles: [t, t + 1],
            ..*face
        });
    }
    mesh
}

/// Pixels where exactly one of two frames shows the surface.
fn surface_difference(a: &Frame, b: &Frame) -> usize {
    a.surface
        .iter()
        .zip(&b.surface)
        .filter(|(x, y)| x != y)
        .count()
}

#[test]
fn the_mask_draws_the_original_outline_on_a_decimated_surface() {
    let mesh = staircase();
    let options = Options::covering(&mesh, 0.05);
    let out = decimate(&mesh, &options).expect("decimate");
    let cover = CellCover::of(&mesh).expect("cell faces");
    let pieces = out.pieces(&mesh, &cover);

    let mut r = renderer();
    let (lo, hi) = mesh.bounds().expect("bounds");
    let view = View {
        camera: Camera::fit_points(
            mesh.triangles
                .iter()
                .flatten()
                .map(|&v| Vec3::from(mesh.positions[v as usize])),
            1.0,
            1.0,
            (0.0, 89.0),
            1.0,
        ),
        width: SIZE,
        height: SIZE,
        bounds: (Vec3::from(lo), Vec3::from(hi)),
    };
    let frame = |r: &mut strata_render::Renderer, d: &dyn strata_render::wire::Drawable| {
        render_frame(r, &[d], &view, 1.0, Coverage::Analytic)
    };
    let original = r.prepare(&mesh, WireMode::Global).expect("original");
    let original = frame(&mut r, original.as_ref());
    let masked = r
        .prepare_covered(&out.mesh, &pieces, &cover)
        .expect("covered");
    let masked = frame(&mut r, masked.as_ref());
    let unmasked = r.prepare(&out.mesh, WireMode::Global).expect("unmasked");
    let unmasked = frame(&mut r, unmasked.as_ref());

    let (surface, _) = original.surface_mean();
    let with_mask = surface_difference(&original, &masked);
    let without = surface_difference(&original, &unmasked);
    let lines = |f: &Frame| f.count_above(0.5);
    eprintln!(
        "{} -> {} triangles on {}: {surface} surface pixels; differing with the mask \
         {with_mask}, without {without}; line pixels {} original, {} masked",
        mesh.triangle_count(),
        out.mesh.triangle_count(),
        backend(&r),
        lines(&original),
        lines(&masked)
    );
    assert!(surface > 20_000, "the staircase fills the frame");
    // The decimated surface grew over the notches; the mask takes them away again,
    // up to a pixel along the edges.
    assert!(
        without > surface / 50,
        "the decimated surface covers the notches"
    );
    assert!(
        with_mask < surface / 500,
        "{with_mask} pixels differ with the mask"
    );
    let line_change = lines(&original).abs_diff(lines(&masked));
    assert!(
        line_change * 50 < lines(&original),
        "line pixels {} -> {}",
        lines(&original),
        lines(&masked)
    );
}

#[test]
fn pieces_that_do_not_match_the_mesh_are_refused() {
    let mesh = staircase();
    let cover = CellCover::of(&mesh).expect("cell faces");
    let mut r = renderer();
    let err = r
        .prepare_covered(&mesh, &cover.vertex_piece[1..], &cover)
        .err()
        .expect("one piece short");
    assert!(err.to_string().contains("pieces for"), "{err}");
    let mut wrong = cover.vertex_piece.clone();
    wrong[0] = 7;
    let err = r
        .prepare_covered(&mesh, &wrong, &cover)
        .err()
        .expect("no piece 7");
    assert!(err.to_string().contains("piece 7"), "{err}");
}
