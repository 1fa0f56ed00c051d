//! File to image, across the crates, as `strata render --lod` does it: the sample deck
//! of `data/` -> its layer surfaces -> decimation -> the global wireframe on the
//! decimated surface, measured against the wireframe of the original (Celes & Abraham
//! 2011, Fig. 12: the original grid lines stay where they were on the simplified
//! surface, while the simplified triangles' own edges do not).

use std::path::Path;

use strata::grid::SurfaceMesh;
use strata::lod::{Options, decimate};
use strata::metrics::{f1, line_mask};
use strata::render::glam::Vec3;
use strata::render::{Camera, Renderer, Style, View, WireMode};
use strata::surfaces::{SceneOptions, build};

const WIDTH: u32 = 500;
const HEIGHT: u32 = 400;
const Z_SCALE: f32 = 5.0;

/// The line mask of `mesh` drawn with `mode` alone (isolation, solid colour on black)
/// from `view`.
fn lines(renderer: &mut Renderer, mesh: &SurfaceMesh, mode: WireMode, view: &View) -> Vec<bool> {
    let drawable = renderer.prepare(mesh, mode).expect("prepare");
    let style = Style {
        isolation: true,
        background: [0.0, 0.0, 0.0, 1.0],
        ..Style::default()
    };
    let image = renderer
        .render(&[drawable.as_ref()], view, &style)
        .expect("render");
    let c = style.solid_color;
    let luma =
        255.0 * (0.299 * f64::from(c[0]) + 0.587 * f64::from(c[1]) + 0.114 * f64::from(c[2]));
    line_mask(image.as_raw(), luma)
}

#[test]
fn the_original_grid_lines_stay_on_the_decimated_sample() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/sample.grdecl");
    let grid = strata::grid::open(&path).expect("the sample deck reads");
    let (original, _) = build(&grid, &SceneOptions::default()).expect("surfaces");
    let decimated = decimate(
        &original,
        &Options {
            z_scale: Z_SCALE,
            ..Options::fraction(&original, 0.1)
        },
    )
    .expect("decimate")
    .mesh;
    let share = decimated.triangle_count() as f64 / original.triangle_count() as f64;
    assert!(
        share <= 0.101,
        "{} of {} triangles left",
        decimated.triangle_count(),
        original.triangle_count()
    );

    let mut renderer = Renderer::headless().expect("a wgpu adapter");
    let (lo, hi) = original.bounds().expect("non-empty");
    let mut rows = Vec::new();
    for angles in [(30.0, 35.0), (210.0, 60.0)] {
        let view = View {
            camera: Camera::fit_points(
                original.positions.iter().map(|&p| Vec3::from(p)),
                Z_SCALE,
                WIDTH as f32 / HEIGHT as f32,
                angles,
                1.0,
            ),
            width: WIDTH,
            height: HEIGHT,
            bounds: (Vec3::from(lo), Vec3::from(hi)),
        };
        let want = lines(&mut renderer, &original, WireMode::Global, &view);
        let kept = lines(&mut renderer, &decimated, WireMode::Global, &view);
        let own = lines(&mut renderer, &decimated, WireMode::Tex, &view);
        let drawn = want.iter().filter(|&&p| p).count();
        let (_, _, f_kept) = f1(&kept, &want, WIDTH as usize, 1);
        let (_, _, f_own) = f1(&own, &want, WIDTH as usize, 1);
        eprintln!(
            "view {angles:?}: {drawn} line pixels; F1 within 1 px of the original wireframe: \
             original lines on the decimated surface {f_kept:.3}, its own edges {f_own:.3}"
        );
        rows.push((drawn, f_kept, f_own));
    }
    for (drawn, f_kept, f_own) in rows {
        // The grid is drawn: its lines cover a fair share of the frame.
        assert!(
            drawn > (WIDTH * HEIGHT / 50) as usize,
            "{drawn} line pixels"
        );
        assert!(
            f_kept >= 0.9,
            "original lines on the decimated surface: F1 {f_kept}"
        );
        assert!(
            f_own < f_kept - 0.2,
            "the decimated triangles' own edges should not pass for the grid: F1 {f_own}"
        );
    }
}
