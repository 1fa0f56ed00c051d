//! Measured image tests of outline edges (`wire/outline.rs`): on a flat 12 x 12 grid
//! of 10 m cells, seen from above and tilted 60 degrees, and around a 2 x 2 hole in
//! it, the outline's lines measure the thickness set (1, 2, 3 and 5 px) as the
//! interior lines do, in every texture technique and both coverage forms, and around
//! the outline's corners no pixel off the surface is covered more than a pixel as far
//! from the straight outline (the lines of two edges are never both drawn there). A
//! layer folded along a grid line and seen from a low angle has its fold's line, its
//! silhouette, as wide; and where the cap thins the lines of cells seen edge on, the
//! outline leaves no band beyond the surface.
//! Frames use the measuring convention of support/mod.rs over a black background, so
//! that the red channel is the line coverage outside the surface too; run with
//! `--nocapture` for the numbers. CI runs this file with `WGPU_BACKEND=gl` (llvmpipe)
//! and `WGPU_BACKEND=vulkan` (lavapipe).

mod support;

use strata_grid::{CellFace, SurfaceMesh};
use strata_render::glam::{Vec2, Vec3};
use strata_render::{Coverage, Renderer, Style, View, WireMode};
use support::*;

const SIZE: u32 = 600;
const CELLS: usize = 12;
const CELL: f32 = 10.0;
const THICKNESS: [f32; 4] = [1.0, 2.0, 3.0, 5.0];
/// Widths within this of the thickness (pixels), as the issue asks of every line.
const TOL: f32 = 0.5;
/// The hole's cells.
const HOLE: [[u32; 2]; 4] = [[5, 5], [6, 5], [5, 6], [6, 6]];

/// The grid, turned 10 degrees in its plane so that its lines cross pixel rows at
/// every phase: the coverage beside the outline is then sampled at every distance.
fn grid() -> PlaneGrid {
    PlaneGrid::square(CELLS, CELL, 10.0)
}

/// `mesh` without the faces (and triangles) of the cells `holes`.
fn without(mesh: &SurfaceMesh, holes: &[[u32; 2]]) -> SurfaceMesh {
    let gone = |f: &CellFace| holes.contains(&[f.cell[0], f.cell[1]]);
    let mut kept = vec![true; mesh.triangles.len()];
    for f in mesh.cell_faces.iter().filter(|f| gone(f)) {
        for t in f.triangles {
            kept[t as usize] = false;
        }
    }
    let mut index = vec![u32::MAX; mesh.triangles.len()];
    let mut out = SurfaceMesh {
        triangles: Vec::new(),
        cell_faces: Vec::new(),
        ..mesh.clone()
    };
    for (t, tri) in mesh.triangles.iter().enumerate().filter(|(t, _)| kept[*t]) {
        index[t] = out.triangles.len() as u32;
        out.triangles.push(*tri);
    }
    for f in mesh.cell_faces.iter().filter(|f| !gone(f)) {
        out.cell_faces.push(CellFace {
            triangles: f.triangles.map(|t| index[t as usize]),
            ..*f
        });
    }
    out
}

/// A surface over the grid, how it is seen, and where its grid point `(a, b)` lies.
struct Scene {
    mesh: SurfaceMesh,
    view: View,
    point: Box<dyn Fn(f32, f32) -> Vec3>,
}

impl Scene {
    /// The flat grid `mesh` seen from `tilt_deg` off the vertical (towards -y),
    /// filling most of the frame.
    fn flat(mesh: SurfaceMesh, tilt_deg: f32) -> Scene {
        let grid = grid();
        Scene {
            mesh,
            view: grid_view(&grid, grid_camera(&grid, tilt_deg, 260.0), SIZE),
            point: Box::new(move |a, b| grid.point(a, b)),
        }
    }
}

/// Coverage across the line through `at` of unit normal `normal` on screen, scanned
/// down a pixel column (a line closer to horizontal) or along a row, rescaled to the
/// normal: the sum over the pixels within `reach` and the full width at half
/// coverage, where both edges are found.
fn across(frame: &Frame, at: Vec2, normal: Vec2, reach: f32) -> (f32, Option<f32>) {
    let down = normal.y.abs() >= normal.x.abs();
    let (fixed, centre, scale) = if down {
        (at.x, at.y, normal.y.abs())
    } else {
        (at.y, at.x, normal.x.abs())
    };
    let fixed = fixed.floor() as i64;
    let lo = (centre - reach / scale).floor() as i64;
    let hi = (centre + reach / scale).ceil() as i64;
    let (mut pos, mut cov) = (Vec::new(), Vec::new());
    for s in lo..=hi {
        let (x, y) = if down { (fixed, s) } else { (s, fixed) };
        if let Some((c, _)) = frame.at(x, y) {
            pos.push(s as f32 + 0.5);
            cov.push(c);
        }
    }
    let (_, edges) = half_coverage_edges(&pos, &cov);
    (
        cov.iter().sum::<f32>() * scale,
        edges.map(|(a, b)| (b - a) * scale),
    )
}

/// Distance from `p` to the segment `a b`.
fn to_segment(p: Vec2, a: Vec2, b: Vec2) -> f32 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared().max(1e-12)).clamp(0.0, 1.0);
    p.distance(a + t * ab)
}

/// Coverage against distance from a line, sampled off the surface beside the
/// outline's straight parts: `at_least(d)` is the most any pixel at least `d` px from
/// its line has, what a pixel `d` px from the outline may have anywhere.
struct Profile(Vec<(f32, f32)>);

impl Profile {
    fn at_least(&self, d: f32) -> f32 {
        self.0
            .iter()
            .filter(|(di, _)| *di >= d - 0.1)
            .map(|(_, c)| *c)
            .fold(0.0, f32::max)
    }
}

/// The pixels of `view` whose centres `mesh` covers.
fn surface_mask(r: &mut Renderer, mesh: &SurfaceMesh, view: &View) -> Vec<bool> {
    let plain = r.prepare(mesh, WireMode::None).unwrap();
    let style = Style {
        solid_color: [1.0, 1.0, 1.0, 1.0],
        background: [0.0, 0.0, 0.0, 1.0],
        ..measuring_style(1.0, Coverage::Analytic)
    };
    let image = r.render(&[plain.as_ref()], view, &style).unwrap();
    image.pixels().map(|p| p.0[0] > 8).collect()
}

/// One measured line: whether it lies on the outline, its coverage integral and width.
struct Measure {
    outline: bool,
    integral: f32,
    width: Option<f32>,
}

/// A line of the grid to measure, from grid point `from` to `to` (horizontal on
/// screen when both have the same b), and whether it lies on the outline.
type Line = ([f32; 2], [f32; 2], bool);

/// A corner of the outline: the grid point and the two outline edges' other ends.
type Corner = [[f32; 2]; 3];

/// Draws `mesh` in every technique, form and thickness from `tilt_deg` and measures
/// `lines` at the middle of each cell along them. Around each of `corners`, every
/// pixel off the surface must be covered no more than a pixel as far from the straight
/// outline: where two edges meet, their lines are not both drawn.
fn check(r: &mut Renderer, label: &str, scene: &Scene, lines: &[Line], corners: &[Corner]) {
    let (mesh, view) = (&scene.mesh, &scene.view);
    let proj = Projector::new(view);
    let px = |[a, b]: [f32; 2]| proj.to_px((scene.point)(a, b));
    let surface = surface_mask(r, mesh, view);
    let on_surface = |x: i64, y: i64| surface[y as usize * SIZE as usize + x as usize];
    for mode in TEXTURE_MODES {
        let drawable = r.prepare(mesh, mode).unwrap();
        for form in FORMS {
            for sigma in THICKNESS {
                let style = Style {
                    background: [0.0, 0.0, 0.0, 1.0],
                    ..measuring_style(sigma, form)
                };
                let image = r.render(&[drawable.as_ref()], view, &style).unwrap();
                let frame = Frame::new(&image);
                let reach = 0.5 * sigma + 3.0;
                let mut measures = Vec::new();
                let mut profile = Profile(Vec::new());
                for &(from, to, outline) in lines {
                    let cells = (to[0] - from[0]).abs().max((to[1] - from[1]).abs()) as usize;
                    let (a, b) = (px(from), px(to));
                    let normal = (b - a).perp().normalize();
                    let step = if from[1] == to[1] {
                        [0.0, 1.0]
                    } else {
                        [1.0, 0.0]
                    };
                    for c in 0..cells {
                        let f = (c as f32 + 0.5) / cells as f32;
                        let param = [
                            from[0] + f * (to[0] - from[0]),
                            from[1] + f * (to[1] - from[1]),
                        ];
                        let at = px(param);
                        // Where cells are under 3 thicknesses wide on screen, every
                        // line is thinned by the saturation cap (support/mod.rs); and
                        // the scan must end before the middle of the cell, where `tex`
                        // draws the quads' diagonals.
                        let cell_px = [-1.0, 1.0]
                            .map(|s| {
                                let q = px([param[0] + s * step[0], param[1] + s * step[1]]);
                                (q - at).dot(normal).abs()
                            })
                            .into_iter()
                            .fold(f32::INFINITY, f32::min);
                        if cell_px < (3.0 * sigma).max(2.0 * (reach + 0.5 * sigma + 1.0)) {
                            continue;
                        }
                        let (integral, width) = across(&frame, at, normal, reach);
                        measures.push(Measure {
                            outline,
                            integral,
                            width,
                        });
                    }
                    if !outline {
                        continue;
                    }
                    // The profile beside the outline, off the surface, along its cells'
                    // middle halves (clear of the lines that meet it).
                    let r = reach.ceil() as i64 + 1;
                    let (lo, hi) = (a.min(b), a.max(b));
                    for y in lo.y.floor() as i64 - r..=hi.y.ceil() as i64 + r {
                        for x in lo.x.floor() as i64 - r..=hi.x.ceil() as i64 + r {
                            let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                            let t = (centre - a).dot(b - a) / (b - a).length_squared();
                            let in_cell = (t * cells as f32).fract();
                            if !(0.0..1.0).contains(&t)
                                || !(0.25..0.75).contains(&in_cell)
                                || frame.at(x, y).is_none()
                                || on_surface(x, y)
                            {
                                continue;
                            }
                            let d = to_segment(centre, a, b);
                            if d <= reach {
                                profile.0.push((d, frame.at(x, y).map_or(0.0, |c| c.0)));
                            }
                        }
                    }
                }
                let tag = format!("{label} {} {form:?} {sigma} px", mode.name());
                let summary = |outline: bool, f: &dyn Fn(&Measure) -> Option<f32>| {
                    Summary::of(
                        measures
                            .iter()
                            .filter(|m| m.outline == outline)
                            .filter_map(f),
                    )
                };
                let (outline_sum, inside_sum) = (
                    summary(true, &|m| Some(m.integral)),
                    summary(false, &|m| Some(m.integral)),
                );
                let (outline_width, inside_width) =
                    (summary(true, &|m| m.width), summary(false, &|m| m.width));
                println!(
                    "{tag}: coverage across, outline {outline_sum}, inside {inside_sum}; \
                     width at half, outline {outline_width}, inside {inside_width}"
                );
                assert!(
                    outline_sum.n > 0 && inside_sum.n > 0,
                    "{tag}: nothing measured"
                );
                assert!(
                    outline_sum.min >= sigma - TOL && outline_sum.max <= sigma + TOL,
                    "{tag}: the outline measures {outline_sum}"
                );
                // Half-coverage widths of a 1 px line depend on where pixel centres
                // fall (support/mod.rs): from 2 px up, as the interior lines'.
                if sigma >= 2.0 {
                    assert_eq!(outline_width.n, outline_sum.n, "{tag}: an edge not found");
                    assert!(
                        outline_width.min >= sigma - TOL && outline_width.max <= sigma + TOL,
                        "{tag}: the outline's width {outline_width}"
                    );
                }
                let mut checked = 0;
                for &[corner, end_a, end_b] in corners {
                    let (c, ea, eb) = (px(corner), px(end_a), px(end_b));
                    let r = reach.ceil() as i64;
                    for y in c.y.floor() as i64 - r..=c.y.floor() as i64 + r {
                        for x in c.x.floor() as i64 - r..=c.x.floor() as i64 + r {
                            if on_surface(x, y) {
                                continue;
                            }
                            let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                            let d = to_segment(centre, c, ea).min(to_segment(centre, c, eb));
                            let got = frame.at(x, y).map_or(0.0, |c| c.0);
                            let most = profile.at_least(d);
                            assert!(
                                got <= most + 3.0 / 255.0,
                                "{tag}: pixel ({x}, {y}) {d:.2} px from the corner at {c} has \
                                 {got}, the straight outline at most {most} that far"
                            );
                            checked += usize::from(got > 0.0);
                        }
                    }
                }
                assert!(
                    corners.is_empty() || checked > 0,
                    "{tag}: no line pixel off the surface at a corner"
                );
            }
        }
    }
}

/// The corners of the grid's outline, each with its two edges' far ends.
fn square_corners() -> Vec<Corner> {
    let n = CELLS as f32;
    vec![
        [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
        [[n, 0.0], [n - 1.0, 0.0], [n, 1.0]],
        [[0.0, n], [1.0, n], [0.0, n - 1.0]],
        [[n, n], [n - 1.0, n], [n, n - 1.0]],
    ]
}

#[test]
fn the_outline_of_a_flat_grid_has_the_full_width() {
    let mut r = renderer();
    let grid = grid();
    let n = CELLS as f32;
    // The four sides and two interior lines of each family, seen from above.
    let lines = [
        ([0.0, 0.0], [n, 0.0], true),
        ([0.0, n], [n, n], true),
        ([0.0, 0.0], [0.0, n], true),
        ([n, 0.0], [n, n], true),
        ([0.0, 4.0], [n, 4.0], false),
        ([8.0, 0.0], [8.0, n], false),
    ];
    check(
        &mut r,
        "flat",
        &Scene::flat(grid.mesh(), 0.0),
        &lines,
        &square_corners(),
    );
}

#[test]
fn the_outline_of_a_grid_tilted_60_degrees_has_the_full_width() {
    let mut r = renderer();
    let grid = grid();
    let n = CELLS as f32;
    // The near and far sides, horizontal on screen, and two interior lines.
    let lines = [
        ([0.0, 0.0], [n, 0.0], true),
        ([0.0, n], [n, n], true),
        ([0.0, 2.0], [n, 2.0], false),
        ([0.0, 9.0], [n, 9.0], false),
    ];
    check(
        &mut r,
        "tilted",
        &Scene::flat(grid.mesh(), 60.0),
        &lines,
        &square_corners(),
    );
}

#[test]
fn the_rim_of_a_hole_has_the_full_width() {
    let mut r = renderer();
    let mesh = without(&grid().mesh(), &HOLE);
    // The hole's four sides and the interior lines through its middle's row and
    // column, away from it.
    let lines = [
        ([5.0, 5.0], [7.0, 5.0], true),
        ([5.0, 7.0], [7.0, 7.0], true),
        ([5.0, 5.0], [5.0, 7.0], true),
        ([7.0, 5.0], [7.0, 7.0], true),
        ([0.0, 6.0], [5.0, 6.0], false),
        ([6.0, 0.0], [6.0, 5.0], false),
    ];
    let corners = [
        [[5.0, 5.0], [6.0, 5.0], [5.0, 6.0]],
        [[7.0, 5.0], [6.0, 5.0], [7.0, 6.0]],
        [[5.0, 7.0], [6.0, 7.0], [5.0, 6.0]],
        [[7.0, 7.0], [6.0, 7.0], [7.0, 6.0]],
    ];
    check(&mut r, "hole", &Scene::flat(mesh, 0.0), &lines, &corners);
}

#[test]
fn the_silhouette_of_a_folded_layer_has_the_full_width() {
    let mut r = renderer();
    let grid = grid();
    let n = CELLS as f32;
    let ridge = 0.5 * n;
    // Folded along the grid line j = 6 into two flanks rising 40 degrees to it, seen
    // from 20 degrees above the horizon on the side of the first: the second flank
    // turns away, and the fold is the layer's silhouette.
    let slope = 40f32.to_radians().tan();
    let point = move |a: f32, b: f32| {
        grid.point(a, b) + Vec3::Z * slope * CELL * (ridge - (b - ridge).abs())
    };
    let mesh = SurfaceMesh::structured(CELLS, CELLS, |i, j| point(i as f32, j as f32).to_array());
    let (lo, hi) = grid.bounds();
    let view = View {
        camera: grid_camera(&grid, 70.0, 260.0),
        width: SIZE,
        height: SIZE,
        bounds: (lo, hi + Vec3::Z * slope * CELL * ridge),
    };
    // The fold, and two lines on the flank seen.
    let lines = [
        ([0.0, ridge], [n, ridge], true),
        ([0.0, 2.0], [n, 2.0], false),
        ([0.0, 4.0], [n, 4.0], false),
    ];
    let scene = Scene {
        mesh,
        view,
        point: Box::new(point),
    };
    check(&mut r, "fold", &scene, &lines, &[]);
}

#[test]
fn lines_thinned_by_the_cap_leave_no_band_beyond_the_outline() {
    // Seen from 88 degrees off the vertical, the grid's far cells are under a pixel
    // deep: the cap thins every line to a fraction of its cell and their mean covers
    // the surface evenly. Beyond the far outline only the edge's own line, as thin, is
    // drawn: nothing two pixels or more above the surface.
    let mut r = renderer();
    let scene = Scene::flat(grid().mesh(), 88.0);
    let surface = surface_mask(&mut r, &scene.mesh, &scene.view);
    let size = SIZE as usize;
    // The topmost surface pixel of each column the surface reaches, away from the
    // corners.
    let tops: Vec<(usize, usize)> = (0..size)
        .filter_map(|x| (0..size).find(|&y| surface[y * size + x]).map(|y| (x, y)))
        .collect();
    let middle = &tops[tops.len() / 4..3 * tops.len() / 4];
    assert!(middle.len() > 100 && middle.iter().all(|&(_, y)| y > 4));
    for mode in TEXTURE_MODES {
        let drawable = r.prepare(&scene.mesh, mode).unwrap();
        for form in FORMS {
            let style = Style {
                background: [0.0, 0.0, 0.0, 1.0],
                ..measuring_style(2.0, form)
            };
            let image = r.render(&[drawable.as_ref()], &scene.view, &style).unwrap();
            let frame = Frame::new(&image);
            let above = |k: usize| {
                middle
                    .iter()
                    .map(|&(x, y)| frame.at(x as i64, (y - k) as i64).map_or(0.0, |c| c.0))
                    .fold(0.0f32, f32::max)
            };
            let (next, further) = (above(1), above(2).max(above(3)));
            println!(
                "{} {form:?}: above the far outline, next to it {next}, further {further}",
                mode.name()
            );
            assert!(
                further <= 0.02,
                "{} {form:?}: a band of {further} beyond the outline",
                mode.name()
            );
        }
    }
}
