//! `Renderer::prepare_cells`: a decimated surface drawn against the cells of the one
//! it was simplified from. With the mask, a surface decimated with outlines that only
//! grow outward (strata-lod's `Options::cover`) is drawn over the cells of the
//! original only, so its outline and its grid lines are the original's; with the
//! cells' values, it is coloured cell by cell as the original's faces are. Frames use
//! the measuring convention of support/mod.rs where they measure lines; CI runs this
//! file on llvmpipe (GL) and lavapipe (Vulkan).

mod support;

use strata_grid::{Face, SurfaceMesh, Surfaces, layer_surfaces};
use strata_lod::{CellCover, LodFile, Options, decimate};
use strata_render::glam::Vec3;
use strata_render::{
    Camera, CellDraw, Coverage, Stacking, Style, TiledCells, View, WireMode, stack_pushes,
};
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
    let view = top_view(&mesh);
    let frame = |r: &mut strata_render::Renderer, d: &dyn strata_render::wire::Drawable| {
        render_frame(r, &[d], &view, 1.0, Coverage::Analytic)
    };
    // Without the outline's outer half (drawn over the background, off the measuring
    // convention): cells drawn over a decimated surface draw the lines' halves on the
    // surface, and a scene adds the original's outline edges apart
    // (`Renderer::prepare_outline_edges`).
    let original = r
        .prepare_band(&mesh, WireMode::Global, None)
        .expect("original");
    let original = frame(&mut r, original.as_ref());
    let mut masked_with = |wire: bool| {
        let drawable = r
            .prepare_cells(
                &out.mesh,
                &CellDraw {
                    pieces: &pieces,
                    cover: &cover,
                    values: None,
                    corners: None,
                    mask: true,
                    wire,
                    stacking: None,
                },
            )
            .expect("covered");
        frame(&mut r, drawable.as_ref())
    };
    let masked = masked_with(true);
    let bare = masked_with(false);
    let unmasked = r.prepare(&out.mesh, WireMode::Global).expect("unmasked");
    let unmasked = frame(&mut r, unmasked.as_ref());

    let (surface, _) = original.surface_mean();
    let with_mask = surface_difference(&original, &masked);
    let without = surface_difference(&original, &unmasked);
    let lines = |f: &Frame| f.count_above(0.5);
    // The lines' ink: their coverage summed over the frame. The top view puts many
    // edges half a pixel from pixel centres, where coverage sits at 0.5, so a count
    // of pixels above 0.5 swings with rounding: on an NVIDIA H200 by a few percent for
    // nearly the same ink (docs/performance.md, "Test runs on a GPU").
    let ink = |f: &Frame| {
        let (n, mean) = f.surface_mean();
        n as f64 * mean
    };
    eprintln!(
        "{} -> {} triangles on {}: {surface} surface pixels; differing with the mask \
         {with_mask}, without {without}; line pixels {} original, {} masked; ink {:.1} \
         original, {:.1} masked",
        mesh.triangle_count(),
        out.mesh.triangle_count(),
        backend(&r),
        lines(&original),
        lines(&masked),
        ink(&original),
        ink(&masked)
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
    // Without the wire, the same mask and no line.
    assert_eq!(surface_difference(&masked, &bare), 0);
    assert_eq!(lines(&bare), 0, "grid lines without the wire");
    assert!(
        (ink(&original) - ink(&masked)).abs() * 50.0 < ink(&original),
        "line ink {:.1} -> {:.1}",
        ink(&original),
        ink(&masked)
    );
}

/// A view straight down on the triangles of `mesh`.
fn top_view(mesh: &SurfaceMesh) -> View {
    let (lo, hi) = mesh.bounds().expect("bounds");
    View {
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
    }
}

#[test]
fn the_cells_values_colour_a_decimated_surface_as_the_original_faces() {
    // A flat grid (so shading is the same everywhere) of cells valued 0..4 in a
    // pattern no smooth field follows, with those values averaged onto the nodes.
    let value = |i: usize, j: usize| ((7 * i + 3 * j) % 5) as f32;
    let mut mesh =
        SurfaceMesh::structured(CELLS, CELLS, |i, j| [i as f32 * 10.0, j as f32 * 10.0, 0.0]);
    for face in &mut mesh.cell_faces {
        face.value = value(face.cell[0] as usize, face.cell[1] as usize);
    }
    mesh.scalars = (0..=CELLS)
        .flat_map(|j| (0..=CELLS).map(move |i| (i, j)))
        .map(|(i, j)| {
            let around: Vec<f32> = [(i, j), (i.wrapping_sub(1), j), (i, j.wrapping_sub(1))]
                .into_iter()
                .chain([(i.wrapping_sub(1), j.wrapping_sub(1))])
                .filter(|&(a, b)| a < CELLS && b < CELLS)
                .map(|(a, b)| value(a, b))
                .collect();
            around.iter().sum::<f32>() / around.len() as f32
        })
        .collect();
    let out = decimate(&mesh, &Options::fraction(&mesh, 0.02)).expect("decimate");
    let cover = CellCover::of(&mesh).expect("cell faces");
    let values = cover.values(&mesh).expect("values");
    let pieces = out.pieces(&mesh, &cover);

    // Compare the colour at every cell's centre, far from its lines, where the
    // decimated surface is drawn (below the outline's bound it cuts corners).
    let CellColours {
        compared,
        with_cells,
        interpolated,
        backend,
    } = compare_cell_colours(
        &mesh,
        &out.mesh,
        &pieces,
        &cover,
        TiledCells::boxes(&values),
    );
    eprintln!(
        "{} -> {} triangles on {backend}: of {compared} cell centres drawn ({} cells), \
         {with_cells} differ from the original's flat colour with the cells' values, \
         {interpolated} with the vertex scalars",
        mesh.triangle_count(),
        out.mesh.triangle_count(),
        CELLS * CELLS
    );
    assert!(compared * 100 >= CELLS * CELLS * 95, "the surface is drawn");
    assert!(out.mesh.triangle_count() * 20 < mesh.triangle_count());
    assert_eq!(with_cells, 0, "cells coloured otherwise than the original");
    assert!(
        interpolated > compared / 2,
        "the vertex scalars alone lose the cell pattern"
    );
}

#[test]
fn a_hierarchy_selection_is_coloured_as_the_model_faces() {
    // A flat layer of 24 x 24 cells of 10 m, valued 0..4 in a pattern no smooth field
    // follows; its hierarchy's roots are a few triangles per tile.
    let n = CELLS;
    let value = |i: usize, j: usize| ((7 * i + 3 * j) % 5) as f32;
    let dir = tempfile::tempdir().expect("a temporary folder");
    let (grid, file) = square_hierarchy(
        &dir.path().join("flat.lod"),
        (n, 1),
        |_, _, level| 1000.0 + 10.0 * level as f32,
        |i, j, _| value(i, j),
    );
    let roots: Vec<u32> = file.layers().iter().map(|l| l.root).collect();
    let drawn = file.selection_mesh(&roots).expect("selection");
    let cover = file
        .selection_cover(&roots)
        .expect("cells")
        .expect("a property");
    let values = file
        .selection_values(&roots, None)
        .expect("values")
        .expect("a property");
    let original = layer_surfaces(
        &grid,
        Face::Top,
        &Surfaces::layer(0, file.origin()).property(Some("PORO")),
    )
    .expect("top surface");
    let values = TiledCells {
        values: &values,
        tile: file.tile_cells(),
        of: None,
    };

    let CellColours {
        compared,
        with_cells,
        interpolated,
        backend,
    } = compare_cell_colours(&original, &drawn, &cover.vertex_piece, &cover, values);
    eprintln!(
        "{} triangles in {} roots of {} layer surfaces for {} on {backend}: {with_cells} cell \
         centres differ from the model's flat colour with the cells' values, {interpolated} \
         with the vertex scalars",
        drawn.triangle_count(),
        roots.len(),
        file.layers().len(),
        original.triangle_count(),
    );
    assert_eq!(compared, n * n, "every cell drawn");
    assert!(drawn.triangle_count() * 10 < 2 * original.triangle_count());
    assert_eq!(with_cells, 0, "cells coloured otherwise than the model");
    assert!(
        interpolated > n * n / 2,
        "the vertex scalars alone lose the cell pattern"
    );
}

/// How `drawn`, whose vertices lie on `pieces` of `cover` (`original`'s cells, with
/// their `values`), colours the cells of `original` (a flat surface), seen from
/// straight above at each cell face's centre.
struct CellColours {
    /// Centres where `drawn` is drawn.
    compared: usize,
    /// Of those, centres whose colour differs from `original`'s faces painted flat,
    /// with `drawn` coloured by the cells' values, and by its vertex scalars alone.
    with_cells: usize,
    interpolated: usize,
    backend: String,
}

fn compare_cell_colours(
    original: &SurfaceMesh,
    drawn: &SurfaceMesh,
    pieces: &[u32],
    cover: &CellCover,
    values: TiledCells,
) -> CellColours {
    let cells = CellDraw {
        pieces,
        cover,
        values: Some(values),
        corners: None,
        mask: false,
        wire: true,
        stacking: None,
    };
    let mut r = renderer();
    let view = top_view(original);
    let style = Style {
        scalar_range: Some((0.0, 4.0)),
        background: BACKGROUND,
        ..Style::default()
    };
    let flat = shaded(&mut r, &original.with_cell_values(), None, &view, &style);
    let coloured = shaded(&mut r, drawn, Some(cells), &view, &style);
    let smooth = shaded(&mut r, drawn, None, &view, &style);
    let proj = Projector::new(&view);
    let background = BACKGROUND.map(|c| (c * 255.0) as u8);
    // A parallelogram's centre: the mean of its two triangles' corners.
    let centres: Vec<(u32, u32)> = original
        .cell_faces
        .iter()
        .map(|face| {
            let corners = face
                .triangles
                .iter()
                .flat_map(|&t| original.triangles[t as usize]);
            let centre = corners
                .map(|v| Vec3::from(original.positions[v as usize]))
                .sum::<Vec3>()
                / 6.0;
            let c = proj.to_px(centre);
            (c.x as u32, c.y as u32)
        })
        .collect();
    let differing = |image: &strata_render::image::RgbaImage| {
        let (mut compared, mut differ) = (0, 0);
        for &(x, y) in &centres {
            let (a, b) = (flat.get_pixel(x, y).0, image.get_pixel(x, y).0);
            if b == background {
                continue;
            }
            compared += 1;
            differ += usize::from((0..3).any(|k| a[k].abs_diff(b[k]) > 6));
        }
        (compared, differ)
    };
    let ((compared, with_cells), (_, interpolated)) = (differing(&coloured), differing(&smooth));
    CellColours {
        compared,
        with_cells,
        interpolated,
        backend: backend(&r),
    }
}

/// `mesh` drawn with the global wireframe, against `cells` when given.
fn shaded(
    r: &mut strata_render::Renderer,
    mesh: &SurfaceMesh,
    cells: Option<CellDraw>,
    view: &View,
    style: &Style,
) -> strata_render::image::RgbaImage {
    let drawable = match cells {
        Some(cells) => r.prepare_cells(mesh, &cells),
        None => r.prepare(mesh, WireMode::Global),
    }
    .expect("prepare");
    r.render(&[drawable.as_ref()], view, style)
        .unwrap_or_else(|e| panic!("render failed: {e}"))
}

#[test]
fn pieces_that_do_not_match_the_mesh_are_refused() {
    let mesh = staircase();
    let cover = CellCover::of(&mesh).expect("cell faces");
    let mut r = renderer();
    let draw = |pieces| CellDraw {
        pieces,
        cover: &cover,
        values: None,
        corners: None,
        mask: true,
        wire: true,
        stacking: None,
    };
    let err = r
        .prepare_cells(&mesh, &draw(&cover.vertex_piece[1..]))
        .err()
        .expect("one piece short");
    assert!(err.to_string().contains("pieces for"), "{err}");
    let mut wrong = cover.vertex_piece.clone();
    wrong[0] = 7;
    let err = r
        .prepare_cells(&mesh, &draw(&wrong))
        .err()
        .expect("no piece 7");
    assert!(err.to_string().contains("piece 7"), "{err}");
    let err = r
        .prepare_cells(
            &mesh,
            &CellDraw {
                values: Some(TiledCells::boxes(&[1.0; 3])),
                corners: None,
                ..draw(&cover.vertex_piece)
            },
        )
        .err()
        .expect("three values for a box of cells");
    assert!(err.to_string().contains("3 cell values"), "{err}");
}

/// Three pieces stacked: 0 the square [-1, 1]² of 4 x 4 cells at z = 1, 1 the same at
/// z = 0, and 2 a strip of 8 x 4 cells over x in [0.6, 1.6] at z = 0.5, which sticks out
/// beside the squares from x = 1.1 (seen from above) or 1.08 (from below). In tiles of
/// 2 x 2 cells the strip's first column, x up to 0.85, stays hidden; the second, up to
/// 1.1, is hidden from above too, but the visible pixels beside it take derivatives
/// across it.
#[test]
fn visible_tiles_are_those_the_nearest_surface_shows_and_only_those() {
    let mut r = renderer();
    let plane = |(x0, x1): (f32, f32), across: usize, z: f32| {
        SurfaceMesh::structured(across, 4, |i, j| {
            [
                x0 + (x1 - x0) * i as f32 / across as f32,
                -1.0 + 0.5 * j as f32,
                z,
            ]
        })
    };
    let mut mesh = SurfaceMesh::with_origin([0.0; 3]);
    for part in [
        plane((-1.0, 1.0), 4, 1.0),
        plane((-1.0, 1.0), 4, 0.0),
        plane((0.6, 1.6), 8, 0.5),
    ] {
        mesh.append(&part);
    }
    let cover = CellCover::of(&mesh).expect("cells");
    assert_eq!(cover.pieces.len(), 3);
    let view = |z: f32| View {
        camera: Camera::look_at(Vec3::new(0.0, 0.0, z), Vec3::ZERO, Vec3::Y),
        width: 200,
        height: 200,
        bounds: (Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.6, 1.0, 1.0)),
    };
    let style = Style::default();
    let strip = [false, true, true, true, false, true, true, true];
    let above = r
        .visible_tiles(&mesh, (&cover, 2), &view(6.0), &style)
        .expect("visible tiles");
    assert_eq!(above[..4], [true; 4], "the top square from above");
    assert_eq!(above[4..8], [false; 4], "the bottom square from above");
    assert_eq!(above[8..], strip, "the strip from above");
    let below = r
        .visible_tiles(&mesh, (&cover, 2), &view(-6.0), &style)
        .expect("visible tiles");
    assert_eq!(below[..8], [[false; 4], [true; 4]].concat(), "from below");
    assert_eq!(below[8..], strip, "the strip from below");
    // Tiles as large as the boxes: a flag per piece.
    let pieces = r
        .visible_tiles(&mesh, (&cover, u32::MAX), &view(6.0), &style)
        .expect("visible tiles");
    assert_eq!(pieces, [true, false, true]);

    let mut short = cover.clone();
    short.vertex_piece.pop();
    assert!(
        r.visible_tiles(&mesh, (&short, 2), &view(6.0), &style)
            .is_err(),
        "a piece list that does not match the vertices is refused"
    );
    let mut fewer = cover.clone();
    fewer.pieces.pop();
    assert!(
        r.visible_tiles(&mesh, (&fewer, 2), &view(6.0), &style)
            .is_err(),
        "a vertex of a piece the cover does not have is refused"
    );
}

/// A stack of four layers of 48 x 48 cells of 10 m on a dome, their porosity rising
/// across the map and down the stack, in a hierarchy of 8-cell tiles.
fn dome_hierarchy(dir: &std::path::Path) -> LodFile {
    let n = 48;
    let dome = |i: usize, j: usize| {
        let (x, y) = (i as f32 / n as f32 - 0.5, j as f32 / n as f32 - 0.5);
        1000.0 + 20.0 * (x * x + y * y)
    };
    let (_, file) = square_hierarchy(
        &dir.join("dome.lod"),
        (n, 4),
        |i, j, level| dome(i, j) + 4.0 * level as f32,
        |i, j, k| 0.1 + 0.004 * i as f32 + 0.002 * j as f32 + 0.01 * k as f32,
    );
    file
}

/// Seen obliquely, a stack shows its top surface and the others' edges: the cells'
/// colours and isolines drawn from the values of the tiles the view shows are those
/// drawn from all of them.
#[test]
fn cells_and_isolines_from_the_tiles_a_view_shows_are_those_from_all_tiles() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let file = dome_hierarchy(dir.path());
    let roots: Vec<u32> = file.layers().iter().map(|l| l.root).collect();
    let mesh = file.selection_mesh(&roots).expect("selection");
    let cover = file
        .selection_cover(&roots)
        .expect("cells")
        .expect("a property");
    let (lo, hi) = mesh.bounds().expect("bounds");
    let view = View {
        camera: Camera::fit_points(
            mesh.positions.iter().map(|&p| Vec3::from(p)),
            5.0,
            4.0 / 3.0,
            (30.0, 25.0),
            1.0,
        ),
        width: 400,
        height: 300,
        bounds: (Vec3::from(lo), Vec3::from(hi)),
    };
    let plain = Style {
        scalar_range: Some((0.1, 0.25)),
        ..Style::default()
    };
    let style = Style {
        isolines: Some(strata_render::Isolines::new(0.01)),
        ..plain
    };
    let mut r = renderer();
    let tile = file.tile_cells();
    let shown = r
        .visible_tiles(&mesh, (&cover, tile), &view, &style)
        .expect("visible tiles");
    let read = |wanted: Option<&[bool]>| {
        let values = file.selection_values(&roots, wanted).expect("values");
        let corners = file.selection_corners(&roots, wanted).expect("corners");
        values.zip(corners).expect("a property")
    };
    let (all_values, all_corners) = read(None);
    let (some_values, some_corners) = read(Some(&shown));
    let tiled = |values, of| TiledCells { values, tile, of };
    let mut frame = |fields: Option<[TiledCells; 2]>, style: &Style| {
        let cells = CellDraw {
            pieces: &cover.vertex_piece,
            cover: &cover,
            values: fields.map(|f| f[0]),
            corners: fields.map(|f| f[1]),
            mask: false,
            wire: true,
            stacking: None,
        };
        shaded(&mut r, &mesh, Some(cells), &view, style)
    };
    let all = [tiled(&all_values, None), tiled(&all_corners, None)];
    let from_all = frame(Some(all), &style);
    let from_shown = frame(
        Some([
            tiled(&some_values, Some(&shown)),
            tiled(&some_corners, Some(&shown)),
        ]),
        &style,
    );
    let without = frame(Some(all), &plain);
    let differing = |a: &strata_render::image::RgbaImage, b: &strata_render::image::RgbaImage| {
        a.pixels().zip(b.pixels()).filter(|(x, y)| x != y).count()
    };
    let marked = shown.iter().filter(|&&s| s).count();
    let isoline_pixels = differing(&from_all, &without);
    eprintln!(
        "{marked} of {} tiles shown on {}; {isoline_pixels} pixels of isolines",
        shown.len(),
        backend(&r)
    );
    // Five surfaces (four tops and the bottom) of 6 x 6 tiles: the top's and the
    // others' edges. The lower ones' middles, two tiles in from their edges, are hidden.
    assert_eq!(shown.len(), 5 * 36);
    let middle = |t: usize| (2..4).contains(&(t % 6)) && (2..4).contains(&(t % 36 / 6));
    for s in 0..5 {
        let rows: Vec<String> = shown[36 * s..36 * (s + 1)]
            .chunks(6)
            .map(|r| r.iter().map(|&v| if v { '#' } else { '.' }).collect())
            .collect();
        eprintln!("surface {s}: {}", rows.join(" "));
    }
    assert!(
        shown[..36].iter().all(|&s| s),
        "the top surface is shown whole"
    );
    for s in 1..5 {
        let tiles = &shown[36 * s..36 * (s + 1)];
        assert!(tiles.iter().any(|&v| v), "surface {s}: no edge shown");
        assert!(
            !tiles.iter().enumerate().any(|(t, &v)| v && middle(t)),
            "surface {s}: its hidden middle is shown"
        );
    }
    assert!(marked < shown.len() / 2, "{marked} tiles shown");
    assert!(isoline_pixels > 1000, "isolines are drawn");
    assert_eq!(
        differing(&from_all, &from_shown),
        0,
        "the tiles the view shows draw otherwise than all tiles"
    );
}

/// Two layer surfaces of one stack, drawn as one decimated scene: the upper at z = 0,
/// the lower at z = -1, but for a patch of one that crossed the other (as decimated
/// surfaces do across a thin layer): the lower's rises to z = 1 (seen from above) or
/// the upper's sinks to z = -2 (seen from below). The lower's nodes sit half a cell
/// off the upper's, so each one's grid lines show where it is seen. With the stacking
/// (each surface's vertical error 1, pushes 0 and 2), the near surface hides the patch
/// as in the flat stack.
#[test]
fn stacking_keeps_crossed_surfaces_in_the_original_order() {
    // A surface at z, at `patch_z` over the patch, its nodes `offset` along x and y.
    let surface = |z: f32, patch_z: f32, offset: f32| {
        SurfaceMesh::structured(CELLS, CELLS, |i, j| {
            let patch = (8..16).contains(&i) && (8..16).contains(&j);
            [
                i as f32 * 10.0 + offset,
                j as f32 * 10.0 + offset,
                if patch { patch_z } else { z },
            ]
        })
    };
    let stack = |(upper, lower): (SurfaceMesh, SurfaceMesh)| {
        let mut scene = upper;
        scene.append(&lower);
        scene
    };
    let upper = surface(0.0, 0.0, 0.0);
    let lower = surface(-1.0, -1.0, 5.0);
    let original = stack((upper.clone(), lower.clone()));
    let mut cover = CellCover::of(&upper).expect("upper cells");
    let lower_cover = CellCover::of(&lower).expect("lower cells");
    let first_lower = cover.pieces.len() as u32;
    let mut pieces = cover.vertex_piece.clone();
    pieces.extend(lower_cover.vertex_piece.iter().map(|p| p + first_lower));
    cover.append(&lower_cover);
    let push = stack_pushes(&[1.0, 1.0]);
    assert_eq!(push, [0.0, 2.0]);
    let piece_push: Vec<Option<f32>> = (0..cover.pieces.len() as u32)
        .map(|p| Some(push[usize::from(p >= first_lower)]))
        .collect();

    let mut r = renderer();
    let mut lines_from = |mesh: &SurfaceMesh, stacking, elevation: f32| {
        let (lo, hi) = original.bounds().expect("bounds");
        let view = View {
            camera: Camera::fit_points(
                original.positions.iter().map(|&p| Vec3::from(p)),
                1.0,
                1.0,
                (0.0, elevation),
                1.0,
            ),
            width: SIZE,
            height: SIZE,
            bounds: (Vec3::from(lo), Vec3::from(hi)),
        };
        let drawable = r
            .prepare_cells(
                mesh,
                &CellDraw {
                    pieces: &pieces,
                    cover: &cover,
                    values: None,
                    corners: None,
                    mask: false,
                    wire: true,
                    stacking,
                },
            )
            .expect("cells");
        let frame = render_frame(&mut r, &[drawable.as_ref()], &view, 1.0, Coverage::Analytic);
        (frame, backend(&r))
    };
    let differing = |a: &Frame, b: &Frame| {
        a.coverage
            .iter()
            .zip(&b.coverage)
            .filter(|(x, y)| (**x > 0.5) != (**y > 0.5))
            .count()
    };
    let stacking = Some(Stacking { push: &piece_push });
    for (elevation, crossed) in [
        (89.0, stack((upper.clone(), surface(-1.0, 1.0, 5.0)))),
        (-89.0, stack((surface(0.0, -2.0, 0.0), lower.clone()))),
    ] {
        let (want, backend) = lines_from(&original, None, elevation);
        let (stacked, _) = lines_from(&crossed, stacking, elevation);
        let (unstacked, _) = lines_from(&crossed, None, elevation);
        let (with, without) = (differing(&stacked, &want), differing(&unstacked, &want));
        eprintln!(
            "elevation {elevation} on {backend}: {} line pixels in the flat stack; with the \
             patch crossed, {with} differ with stacking, {without} without",
            want.count_above(0.5)
        );
        // The patch is 8 x 8 of the 24 x 24 cells: about a ninth of the lines move.
        assert!(
            without * 20 > want.count_above(0.5),
            "without stacking the patch shows the other surface's lines"
        );
        assert!(
            with * 1000 < want.count_above(0.5),
            "with stacking the stack is drawn as the flat one: {with} pixels differ"
        );
    }
}
