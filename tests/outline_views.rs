//! The outline at full width wherever strata draws a layer: a flat 40 x 30 grid of
//! 25 m cells with a 4 x 4 hole, seen from above at 1000 x 800 with black lines 1, 2, 3
//! and 5 px thick, at full resolution, decimated to a fifth of its triangles and from
//! its hierarchy. Across the outline and the hole's rim, the lines' coverage sums to
//! the thickness within 0.5 px, as it does across the interior lines; without the
//! outline's outer half it sums to about half of it.

use std::path::{Path, PathBuf};

use strata::render::image::RgbaImage;
use strata::scene::Lod;
use strata::{Scene, SceneRenderer};

const NX: usize = 40;
const NY: usize = 30;
const CELL: f64 = 25.0;
const DEPTH: f64 = 1000.0;
/// Inactive cells: the hole, west of the picture's middle.
const HOLE_I: std::ops::Range<usize> = 6..10;
const HOLE_J: std::ops::Range<usize> = 13..17;
const THICKNESS: [f32; 4] = [1.0, 2.0, 3.0, 5.0];
const TOL: f32 = 0.5;

/// The grid as a GRDECL deck: one flat layer, 10 m thick, the hole inactive.
fn model(dir: &Path) -> PathBuf {
    let mut deck = format!("SPECGRID\n{NX} {NY} 1 1 F /\nCOORD\n");
    for j in 0..=NY {
        for i in 0..=NX {
            let (x, y) = (CELL * i as f64, CELL * j as f64);
            deck += &format!("{x} {y} {DEPTH} {x} {y} {}\n", DEPTH + 10.0);
        }
    }
    deck += "/\nZCORN\n";
    for top in [DEPTH, DEPTH + 10.0] {
        deck += &format!("{}*{top}\n", 4 * NX * NY);
    }
    deck += "/\nACTNUM\n";
    for j in 0..NY {
        for i in 0..NX {
            let hole = HOLE_I.contains(&i) && HOLE_J.contains(&j);
            deck += if hole { "0 " } else { "1 " };
        }
        deck += "\n";
    }
    deck += "/\n";
    let path = dir.join("flat.grdecl");
    std::fs::write(&path, deck).expect("model written");
    path
}

/// A line of the grid on screen to measure across: map x of a line of constant i
/// (scanned along pixel rows) at the middle of the cells `rows`, and on which side of
/// it the surface stops (`Some(-1.0)`: west of it; `None`: inside the surface).
struct Line {
    x: f64,
    rows: std::ops::Range<usize>,
    outside: Option<f64>,
}

/// The coverage summed across each line at the middle of each of its cells: a pixel
/// darkened from its base colour (white beyond the outline, the surface's colour on
/// it) by the black line covering it.
fn across(engine: &SceneRenderer, image: &RgbaImage, line: &Line, reach: f32) -> Vec<f32> {
    let px = |x: f64, y: f64| engine.pixel_of([x, y, DEPTH]).expect("in the picture");
    // The surface's colour at the middle of a cell far from any line.
    let [sx, sy] = px(5.5 * CELL, 20.5 * CELL);
    let surface = f32::from(image.get_pixel(sx as u32, sy as u32).0[1]);
    let mut sums = Vec::new();
    for j in line.rows.clone() {
        let y = (j as f64 + 0.5) * CELL;
        let [x0, row] = px(line.x, y);
        // Which way on screen the outside lies.
        let out_dir = line
            .outside
            .map(|dx| (px(line.x + dx * CELL, y)[0] - x0).signum());
        let mut sum = 0.0;
        for x in (x0 - reach).floor() as i64..=(x0 + reach).ceil() as i64 {
            let centre = x as f32 + 0.5;
            let outside = out_dir.is_some_and(|s| (centre - x0) * s > 0.0);
            let base = if outside { 255.0 } else { surface };
            let g = f32::from(image.get_pixel(x as u32, row as u32).0[1]);
            sum += (1.0 - g / base).clamp(0.0, 1.0);
        }
        sums.push(sum);
    }
    sums
}

fn scene(model: &Path, lod: Lod, thickness: f32) -> Scene {
    let mut scene = Scene::of_model(model);
    scene.lod = lod;
    scene.size = [1000, 800];
    scene.legend = false;
    scene.camera.elevation = 90.0;
    scene.camera.azimuth = 0.0;
    scene.wire.thickness = thickness;
    scene.wire.color = "#000000".into();
    scene.wire.major = 0;
    scene
}

#[test]
fn the_outline_has_the_full_width_at_full_resolution_decimated_and_from_a_hierarchy() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let model = model(dir.path());
    let grid = strata::grid::open(&model).expect("the model");
    let lod = dir.path().join("flat.lod");
    strata::lod::build_file(&grid, None, &lod, &strata::lod::BuildOptions::default())
        .expect("the hierarchy");
    let line =
        |x: f64, rows: std::ops::Range<usize>, outside: Option<f64>| Line { x, rows, outside };
    // The west and east outline, the hole's east rim and two interior lines; rows
    // clear of corners. (Through the hole the layer's bottom shows its own rim, where
    // perspective moves it into the hole, towards the picture's middle: the hole's
    // west rim is not measured.)
    let lines = [
        line(0.0, 3..27, Some(-1.0)),
        line(CELL * NX as f64, 3..27, Some(1.0)),
        line(CELL * 10.0, 14..16, Some(-1.0)),
        line(CELL * 20.0, 3..27, None),
        line(CELL * 30.0, 3..27, None),
    ];
    let views: [(&str, Lod); 3] = [
        ("full resolution", Lod::Full),
        (
            "decimated",
            Lod::Decimated {
                percent: 20.0,
                cover: false,
                stitch: false,
            },
        ),
        (
            "hierarchy",
            Lod::Hierarchy {
                file: lod.clone(),
                pixels: 1.0,
            },
        ),
    ];
    for (name, view) in views {
        for thickness in THICKNESS {
            let mut scene = scene(&model, view.clone(), thickness);
            if matches!(view, Lod::Hierarchy { .. }) {
                scene.model = None;
            }
            let mut engine = SceneRenderer::new(scene).expect("a scene");
            let frame = engine.render().expect("a frame");
            let reach = 0.5 * thickness + 3.0;
            let (mut outline, mut inside) = (Vec::new(), Vec::new());
            for line in &lines {
                let sums = across(&engine, &frame.image, line, reach);
                match line.outside {
                    Some(_) => outline.extend(sums),
                    None => inside.extend(sums),
                }
            }
            let range = |v: &[f32]| {
                v.iter()
                    .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &s| {
                        (lo.min(s), hi.max(s))
                    })
            };
            let ((olo, ohi), (ilo, ihi)) = (range(&outline), range(&inside));
            println!(
                "{name}, {thickness} px: across the outline {olo:.2}..{ohi:.2} px, inside \
                 {ilo:.2}..{ihi:.2} px ({} and {} scans)",
                outline.len(),
                inside.len()
            );
            for (what, lo, hi) in [("the outline", olo, ohi), ("an interior line", ilo, ihi)] {
                assert!(
                    lo >= thickness - TOL && hi <= thickness + TOL,
                    "{name}, {thickness} px: {what} measures {lo:.2}..{hi:.2} px"
                );
            }
        }
    }
}
