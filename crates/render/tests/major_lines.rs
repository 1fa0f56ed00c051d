//! Measured image tests of major cell lines (`Style::major`): on a flat 400 x 300 grid
//! of 5 m cells seen from above at 1000 x 800, the cell lines fade out where cells are
//! a few pixels wide while every 10th line keeps its width and place, every line is
//! back at full width where cells are 12 px wide, and the zoom between the two changes
//! the coverage between major lines smoothly, one way. Frames use the measuring
//! convention of support/mod.rs, major lines white like the others; run with
//! `--nocapture` for the numbers. CI runs this file with `WGPU_BACKEND=gl` (llvmpipe)
//! and `WGPU_BACKEND=vulkan` (lavapipe).

mod support;

use strata_grid::SurfaceMesh;
use strata_render::glam::{Mat2, Vec2, Vec3};
use strata_render::{Camera, Coverage, FaultLines, MajorLines, Renderer, Style, View, WireMode};
use support::*;

const WIDTH: u32 = 1000;
const HEIGHT: u32 = 800;
const SIGMA: f32 = 1.5;
const CELL: f32 = 5.0;
const EVERY: usize = 10;
/// Tolerance of widths and centres (pixels).
const TOL: f32 = 0.5;
/// Cell widths on screen of the whole grid in view, and of the close-up.
const WHOLE_PX: f32 = 2.25;
const CLOSE_PX: f32 = 12.0;

fn flat() -> PlaneGrid {
    PlaneGrid {
        ni: 400,
        nj: 300,
        origin: Vec3::new(-200.0 * CELL, -150.0 * CELL, 0.0),
        du: Vec3::X * CELL,
        dv: Vec3::Y * CELL,
    }
}

/// The grid seen from straight above, its cells `cell_px` pixels wide, centred on
/// node (203, 152) so that major lines do not sit on the frame's middle row.
fn top_view(grid: &PlaneGrid, cell_px: f32) -> View {
    let camera = Camera::look_at(Vec3::Z, Vec3::ZERO, Vec3::Y);
    let tan = (0.5 * camera.fov_y_deg.to_radians()).tan();
    let distance = CELL * 0.5 * HEIGHT as f32 / (tan * cell_px);
    let centre = grid.point(203.0, 152.0);
    View {
        camera: Camera::look_at(centre + Vec3::Z * distance, centre, Vec3::Y),
        width: WIDTH,
        height: HEIGHT,
        bounds: grid.bounds(),
    }
}

fn style(coverage: Coverage) -> Style {
    Style {
        major: Some(MajorLines {
            color: [1.0; 4],
            ..MajorLines::default()
        }),
        ..measuring_style(SIGMA, coverage)
    }
}

fn draw(r: &mut Renderer, mesh: &SurfaceMesh, mode: WireMode, view: &View, style: &Style) -> Frame {
    let drawable = r
        .prepare(mesh, mode)
        .unwrap_or_else(|e| panic!("prepare {}: {e}", mode.name()));
    let image = r
        .render(&[drawable.as_ref()], view, style)
        .unwrap_or_else(|e| panic!("render {}: {e}", mode.name()));
    Frame::new(&image)
}

/// Number and mean coverage of the surface pixels between major lines: inside the
/// grid and at least sigma / 2 + 1.5 px from every major line.
fn between_major(frame: &Frame, proj: &Projector, grid: &PlaneGrid) -> (usize, f64, f32) {
    let origin = proj.to_px(grid.point(0.0, 0.0));
    let jacobian = Mat2::from_cols(
        proj.to_px(grid.point(1.0, 0.0)) - origin,
        proj.to_px(grid.point(0.0, 1.0)) - origin,
    );
    let to_grid = jacobian.inverse();
    let clear = 0.5 * SIGMA + 1.5;
    let e = EVERY as f32;
    let (mut n, mut sum, mut max) = (0, 0.0, 0.0f32);
    for y in 0..frame.height {
        for x in 0..frame.width {
            let (c, on) = frame.at(x as i64, y as i64).unwrap_or((0.0, false));
            let ab = to_grid * (Vec2::new(x as f32 + 0.5, y as f32 + 0.5) - origin);
            let inside = ab.x > 0.0 && ab.y > 0.0 && ab.x < grid.ni as f32 && ab.y < grid.nj as f32;
            let off_a = (ab.x - e * (ab.x / e).round()).abs() * jacobian.x_axis.length();
            let off_b = (ab.y - e * (ab.y / e).round()).abs() * jacobian.y_axis.length();
            if on && inside && off_a > clear && off_b > clear {
                n += 1;
                sum += f64::from(c);
                max = max.max(c);
            }
        }
    }
    (n, sum / n.max(1) as f64, max)
}

fn check_lines(label: &str, scans: &[Scan], min_scans: usize) {
    let width = Summary::of(scans.iter().map(|s| s.width));
    let integral = Summary::of(scans.iter().map(|s| s.integral));
    let offset = Summary::of(scans.iter().map(|s| s.offset.abs()));
    eprintln!("{label}: width {width}, integral {integral}, |offset| {offset}");
    assert!(scans.len() >= min_scans, "{label}: {} scans", scans.len());
    for s in scans {
        assert!(
            (s.width - SIGMA).abs() <= TOL && (s.integral - SIGMA).abs() <= TOL,
            "{label}: line {:?} {} at {} is {} px wide (integral {}), not {SIGMA}",
            s.family,
            s.index,
            s.at,
            s.width,
            s.integral
        );
        assert!(
            s.offset.abs() <= TOL,
            "{label}: line {:?} {} at {} is {} px off",
            s.family,
            s.index,
            s.at,
            s.offset
        );
    }
}

#[test]
fn seen_whole_the_cell_lines_fade_and_every_tenth_keeps_its_width_and_place() {
    let grid = flat();
    let mesh = grid.mesh();
    let view = top_view(&grid, WHOLE_PX);
    let proj = Projector::new(&view);
    let mut r = renderer();
    let backend = backend(&r);
    for mode in TEXTURE_MODES {
        for coverage in FORMS {
            let label = format!("{backend} {} {coverage:?}", mode.name());
            let frame = draw(&mut r, &mesh, mode, &view, &style(coverage));
            let scans = measure_grid_every(&frame, &proj, &grid, SIGMA, 3, EVERY);
            assert!(scans.iter().all(|s| s.index % EVERY == 0));
            check_lines(&label, &scans, 1000);
            let (n, mean, max) = between_major(&frame, &proj, &grid);
            eprintln!("{label}: between major lines {n} px, mean {mean:.4}, max {max:.3}");
            assert!(n > 300_000, "{label}: {n} pixels between major lines");
            assert!(max <= 0.1, "{label}: coverage {max} between major lines");
        }
    }
}

#[test]
fn close_up_every_cell_line_is_back_at_full_width() {
    let grid = flat();
    let mesh = grid.mesh();
    let view = top_view(&grid, CLOSE_PX);
    let proj = Projector::new(&view);
    let mut r = renderer();
    let backend = backend(&r);
    for mode in TEXTURE_MODES {
        for coverage in FORMS {
            let label = format!("{backend} {} {coverage:?}", mode.name());
            let frame = draw(&mut r, &mesh, mode, &view, &style(coverage));
            let scans = measure_grid(&frame, &proj, &grid, SIGMA, 1);
            let minor = scans.iter().filter(|s| s.index % EVERY != 0).count();
            assert!(minor > 5000, "{label}: {minor} minor lines measured");
            check_lines(&label, &scans, 5000);
        }
    }
}

#[test]
fn zooming_in_changes_the_coverage_between_major_lines_one_way_in_small_steps() {
    const STEPS: usize = 30;
    let grid = flat();
    let mesh = grid.mesh();
    let mut r = renderer();
    let backend = backend(&r);
    for coverage in FORMS {
        let drawable = r
            .prepare(&mesh, WireMode::Global)
            .unwrap_or_else(|e| panic!("prepare global: {e}"));
        let means: Vec<f64> = (0..=STEPS)
            .map(|step| {
                let cell_px = WHOLE_PX * (CLOSE_PX / WHOLE_PX).powf(step as f32 / STEPS as f32);
                let view = top_view(&grid, cell_px);
                let image = r
                    .render(&[drawable.as_ref()], &view, &style(coverage))
                    .unwrap_or_else(|e| panic!("render: {e}"));
                between_major(&Frame::new(&image), &Projector::new(&view), &grid).1
            })
            .collect();
        let shown: Vec<String> = means.iter().map(|m| format!("{m:.3}")).collect();
        eprintln!(
            "{backend} {coverage:?}: mean coverage between major lines {}",
            shown.join(" ")
        );
        for (step, pair) in means.windows(2).enumerate() {
            let change = pair[1] - pair[0];
            assert!(
                (-0.002..=0.05).contains(&change),
                "{backend} {coverage:?}: step {step} changes the coverage by {change:.4}"
            );
        }
        assert!(
            means[0] < 0.02 && means[STEPS] > 0.15,
            "{backend} {coverage:?}: {shown:?}"
        );
    }
}

/// A hierarchy's nodes are cut from one surface at several levels, each with the
/// global coordinates interpolated: the major lines drawn on a cut that takes leaves
/// in the near half of an oblique view and ever coarser nodes beyond run on across
/// the nodes' borders and the change of level, at their width and place all along.
#[test]
fn major_lines_run_on_across_the_nodes_and_levels_of_a_hierarchy() {
    let n = 160;
    let dir = tempfile::tempdir().expect("a temporary folder");
    let (_, file) = square_hierarchy(
        &dir.path().join("flat.lod"),
        (n, 1),
        |_, _, level| 1000.0 + 10.0 * level as f32,
        |_, _, _| 0.2,
    );
    let nodes = file.nodes();
    let (mut cut, mut stack) = (Vec::new(), vec![file.layers()[0].root]);
    while let Some(i) = stack.pop() {
        let node = &nodes[i as usize];
        if node.child_count > 0 && (node.cells[1] as usize) < n / 2 {
            stack.extend(node.first_child..node.first_child + node.child_count);
        } else {
            cut.push(i);
        }
    }
    let mut levels: Vec<u32> = cut.iter().map(|&i| nodes[i as usize].level).collect();
    levels.sort_unstable();
    levels.dedup();
    assert!(levels.len() >= 3, "levels {levels:?}");
    let mesh = file.selection_mesh(&cut).expect("selection");
    let cover = file
        .selection_cover(&cut)
        .expect("cells")
        .expect("a property");
    // The surface is flat: the grid's corners, which every level keeps, place it.
    let corner = |i: usize, j: usize| {
        let t = [(2 * i + 1) as f32, (2 * j + 1) as f32];
        let v = mesh
            .texcoords
            .iter()
            .position(|&c| c == t)
            .expect("a corner vertex");
        Vec3::from(mesh.positions[v])
    };
    let origin = corner(0, 0);
    let plane = PlaneGrid {
        ni: n,
        nj: n,
        origin,
        du: (corner(n, 0) - origin) / n as f32,
        dv: (corner(0, n) - origin) / n as f32,
    };
    let view = View {
        width: WIDTH,
        height: HEIGHT,
        ..grid_view(&plane, grid_camera(&plane, 55.0, 2200.0), WIDTH)
    };
    let proj = Projector::new(&view);
    let cells = strata_render::CellDraw {
        pieces: &cover.vertex_piece,
        cover: &cover,
        values: None,
        corners: None,
        mask: false,
        wire: true,
        stacking: None,
    };
    let mut r = renderer();
    let backend = backend(&r);
    let drawable = r.prepare_cells(&mesh, &cells).expect("prepare");
    for coverage in FORMS {
        let label = format!(
            "{backend} hierarchy {coverage:?} (levels {levels:?}, {} nodes)",
            cut.len()
        );
        let image = r
            .render(&[drawable.as_ref()], &view, &style(coverage))
            .unwrap_or_else(|e| panic!("render: {e}"));
        let frame = Frame::new(&image);
        let scans = measure_grid_every(&frame, &proj, &plane, SIGMA, 10, EVERY);
        check_lines(&label, &scans, 2000);
        // Every major line is measured in the leaves and in the coarser nodes alike.
        for k in (EVERY..n).step_by(EVERY) {
            let on_line: Vec<&Scan> = scans
                .iter()
                .filter(|s| s.family == Family::I && s.index == k)
                .collect();
            let near = proj.to_px(plane.point(k as f32, 0.25 * n as f32)).y;
            let far = proj.to_px(plane.point(k as f32, 0.75 * n as f32)).y;
            let mid = 0.5 * (near + far);
            let (in_leaves, beyond) = (
                on_line
                    .iter()
                    .filter(|s| (s.at.y - mid) * (near - mid) > 0.0)
                    .count(),
                on_line
                    .iter()
                    .filter(|s| (s.at.y - mid) * (far - mid) > 0.0)
                    .count(),
            );
            assert!(
                in_leaves >= 20 && beyond >= 20,
                "{label}: line I {k}: {in_leaves} scans in the leaves, {beyond} beyond"
            );
        }
    }
}

/// The flat grid split along line I `FAULT_AT` (not a major line), the cells beyond
/// it `THROW` lower: the two sides' edges are the fault's traces.
const FAULT_AT: usize = 205;
const THROW: f32 = 2.0;

fn faulted(grid: &PlaneGrid) -> SurfaceMesh {
    let mut mesh = grid.mesh();
    let row = grid.ni + 1;
    for (v, p) in mesh.positions.iter_mut().enumerate() {
        if v % row > FAULT_AT {
            p[2] -= THROW;
        }
    }
    let first = mesh.positions.len();
    for j in 0..=grid.nj {
        let [x, y, z] = mesh.positions[j * row + FAULT_AT];
        mesh.positions.push([x, y, z - THROW]);
        mesh.texcoords.push(mesh.texcoords[j * row + FAULT_AT]);
    }
    for face in mesh.cell_faces.clone() {
        if face.cell[0] as usize >= FAULT_AT {
            for t in face.triangles {
                for v in &mut mesh.triangles[t as usize] {
                    let at = *v as usize;
                    if at < first && at % row == FAULT_AT {
                        *v = (first + at / row) as u32;
                    }
                }
            }
        }
    }
    mesh
}

#[test]
fn fault_traces_keep_their_own_width_over_the_cell_lines_at_every_zoom() {
    const THICK: f32 = 2.5;
    let grid = flat();
    let mesh = faulted(&grid);
    let mut r = renderer();
    let backend = backend(&r);
    for mode in TEXTURE_MODES {
        let drawable = r
            .prepare(&mesh, mode)
            .unwrap_or_else(|e| panic!("prepare {}: {e}", mode.name()));
        // Seen whole the cell line under the trace has faded; close up it is drawn,
        // thinner, under it.
        for (cell_px, every) in [(WHOLE_PX, 5), (CLOSE_PX, 1)] {
            let (lo, hi) = grid.bounds();
            let view = View {
                bounds: (lo - Vec3::Z * THROW, hi),
                ..top_view(&grid, cell_px)
            };
            let proj = Projector::new(&view);
            let style = Style {
                faults: Some(FaultLines {
                    thickness: THICK,
                    color: [1.0; 4],
                }),
                ..style(Coverage::Analytic)
            };
            let image = r
                .render(&[drawable.as_ref()], &view, &style)
                .unwrap_or_else(|e| panic!("render: {e}"));
            // The traces' round ends reach past the outline, over the background, where
            // a white line of coverage c is (c, c, 1): red / 255 is the coverage there
            // too (as techniques.rs reads its frames).
            let frame = Frame {
                width: image.width() as usize,
                height: image.height() as usize,
                coverage: image.pixels().map(|p| f32::from(p.0[0]) / 255.0).collect(),
                surface: image.pixels().map(|p| p.0[0] > 2 || p.0[2] < 250).collect(),
            };
            let scans = measure_line(&frame, &proj, &grid, (THICK, 3, every), Family::I, FAULT_AT);
            let width = Summary::of(scans.iter().map(|s| s.width));
            let offset = Summary::of(scans.iter().map(|s| s.offset.abs()));
            let label = format!("{backend} {} fault at {cell_px} px cells", mode.name());
            eprintln!("{label}: width {width}, |offset| {offset}");
            assert!(scans.len() >= 50, "{label}: {} scans", scans.len());
            for s in &scans {
                assert!(
                    (s.width - THICK).abs() <= TOL && s.offset.abs() <= TOL,
                    "{label}: at {} {} px wide, {} px off",
                    s.at,
                    s.width,
                    s.offset
                );
            }
        }
    }
}
