//! Isolines true to the cell field where the field is cut off: a cell-centred quadratic
//! field on a flat grid with a hole and a fault, seen from above, its isolines measured
//! against the analytic contours in the outermost ring of cells, next to the hole, on
//! both sides of the fault, and inside.

use std::path::{Path, PathBuf};

use strata::render::WireMode;
use strata::render::image::RgbaImage;
use strata::scene::IsolineSpec;
use strata::{Scene, SceneRenderer};

/// Cells along I and J, and their size in metres.
const NX: usize = 60;
const NY: usize = 45;
const CELL: f64 = 25.0;
/// The field's centre (map metres) and scale: F = r^2 / SCALE at each cell's centre.
const CENTRE: [f64; 2] = [610.0, 470.0];
const SCALE: f64 = 1000.0;
/// Value between isolines.
const SPACING: f64 = 40.0;
/// Inactive cells: the hole.
const HOLE_I: std::ops::Range<usize> = 18..24;
const HOLE_J: std::ops::Range<usize> = 28..34;
/// Cells from this column on are thrown down: the fault runs along its west side.
const FAULT_I: usize = 36;

fn field(x: f64, y: f64) -> f64 {
    ((x - CENTRE[0]).powi(2) + (y - CENTRE[1]).powi(2)) / SCALE
}

fn in_hole(i: usize, j: usize) -> bool {
    HOLE_I.contains(&i) && HOLE_J.contains(&j)
}

/// The grid as a GRDECL deck: one flat layer at 1000 m, thrown 20 m down east of the
/// fault, the hole inactive, F at each cell's centre.
fn model(dir: &Path) -> PathBuf {
    let mut deck = format!("SPECGRID\n{NX} {NY} 1 1 F /\nCOORD\n");
    for j in 0..=NY {
        for i in 0..=NX {
            let (x, y) = (CELL * i as f64, CELL * j as f64);
            deck += &format!("{x} {y} 1000 {x} {y} 1030\n");
        }
    }
    deck += "/\nZCORN\n";
    for top in [1000.0, 1010.0] {
        for _ in 0..2 * NY {
            for i in 0..2 * NX {
                let throw = if i / 2 >= FAULT_I { 20.0 } else { 0.0 };
                deck += &format!("{} ", top + throw);
            }
            deck += "\n";
        }
    }
    deck += "/\nACTNUM\n";
    for j in 0..NY {
        for i in 0..NX {
            deck += if in_hole(i, j) { "0 " } else { "1 " };
        }
        deck += "\n";
    }
    deck += "/\nF\n";
    for j in 0..NY {
        for i in 0..NX {
            let (x, y) = (CELL * (i as f64 + 0.5), CELL * (j as f64 + 0.5));
            deck += &format!("{:.4} ", field(x, y));
        }
        deck += "\n";
    }
    deck += "/\n";
    let path = dir.join("quadratic.grdecl");
    std::fs::write(&path, deck).expect("model written");
    path
}

/// Where a line pixel lies: the outermost ring of cells, next to the hole, next to the
/// fault, or inside.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Place {
    Ring,
    Hole,
    Fault,
    Inside,
}

fn place(i: usize, j: usize) -> Place {
    let near_hole =
        (i.saturating_sub(1)..=i + 1).any(|a| (j.saturating_sub(1)..=j + 1).any(|b| in_hole(a, b)));
    if i == 0 || j == 0 || i == NX - 1 || j == NY - 1 {
        Place::Ring
    } else if near_hole {
        Place::Hole
    } else if i == FAULT_I - 1 || i == FAULT_I {
        Place::Fault
    } else {
        Place::Inside
    }
}

fn luma(image: &RgbaImage, x: u32, y: u32) -> f64 {
    let p = image.get_pixel(x, y).0;
    0.299 * f64::from(p[0]) + 0.587 * f64::from(p[1]) + 0.114 * f64::from(p[2])
}

#[test]
fn isolines_in_border_cells_sit_where_the_field_puts_them() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut scene = Scene::of_model(model(dir.path()));
    scene.size = [1200, 900];
    scene.legend = false;
    scene.camera.elevation = 90.0;
    scene.camera.azimuth = 0.0;
    // The throw barely changes the scale from above, and the map position of a pixel
    // is then the same linear function of it on both sides.
    scene.camera.z_scale = 0.01;
    scene.wire.technique = WireMode::None;
    scene.wire.thickness = 1.5;
    scene.wire.fault_thickness = 0.0;
    scene.colour.solid = true;
    scene.isolines = Some(IsolineSpec {
        spacing: Some(SPACING as f32),
        major_every: 0,
        ..IsolineSpec::of(Some("F"))
    });
    let mut engine = SceneRenderer::new(scene).expect("a scene");
    let image = engine.render().expect("a frame").image;
    // The model's pixels (not the white background) and their box: the grid's
    // rectangle seen from above, north up.
    let (w, h) = image.dimensions();
    let model_px: Vec<(u32, u32)> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| luma(&image, x, y) < 250.0)
        .collect();
    let x0 = model_px.iter().map(|p| p.0).min().expect("a model drawn");
    let x1 = model_px.iter().map(|p| p.0).max().expect("a model drawn") + 1;
    let y0 = model_px.iter().map(|p| p.1).min().expect("a model drawn");
    let y1 = model_px.iter().map(|p| p.1).max().expect("a model drawn") + 1;
    let metres_per_px = CELL * NX as f64 / f64::from(x1 - x0);
    let aspect = (CELL * NY as f64 / f64::from(y1 - y0)) / metres_per_px;
    assert!((aspect - 1.0).abs() < 0.01, "pixels not square: {aspect}");
    // The surface's own luma: the most common among the model's pixels.
    let mut counts = std::collections::HashMap::new();
    for &(x, y) in &model_px {
        *counts
            .entry(luma(&image, x, y).round() as i64)
            .or_insert(0usize) += 1;
    }
    let surface = counts
        .into_iter()
        .max_by_key(|&(_, n)| n)
        .map(|(l, _)| l as f64)
        .expect("a surface");
    let tolerance = 0.5 * 1.5 + 1.0;
    let mut tally: std::collections::HashMap<Place, (usize, usize)> = Default::default();
    for &(x, y) in &model_px {
        // Line pixels: at least half covered by a dark line over the surface.
        if luma(&image, x, y) > 0.5 * surface {
            continue;
        }
        let mx = (f64::from(x - x0) + 0.5) * metres_per_px;
        let my = (f64::from(y1 - y) - 0.5) * metres_per_px;
        let (i, j) = ((mx / CELL) as usize, (my / CELL) as usize);
        if i >= NX || j >= NY || in_hole(i, j) {
            continue;
        }
        let f = field(mx, my);
        let level = (f / SPACING).round() * SPACING;
        let gradient = 2.0 * ((mx - CENTRE[0]).hypot(my - CENTRE[1])) / SCALE;
        let off_px = (f - level).abs() / gradient.max(1e-9) / metres_per_px;
        let entry = tally.entry(place(i, j)).or_default();
        entry.1 += 1;
        if off_px <= tolerance {
            entry.0 += 1;
        }
    }
    let share = |p: Place| {
        let (near, all) = tally.get(&p).copied().unwrap_or_default();
        (near as f64 / all.max(1) as f64, all)
    };
    for p in [Place::Inside, Place::Ring, Place::Hole, Place::Fault] {
        let (s, n) = share(p);
        eprintln!(
            "{p:?}: {:.1} % of {n} line pixels within {tolerance} px",
            100.0 * s
        );
    }
    for p in [Place::Inside, Place::Ring, Place::Hole, Place::Fault] {
        let (s, n) = share(p);
        assert!(n > 50, "{p:?}: only {n} line pixels");
        assert!(
            s >= 0.95,
            "{p:?}: {:.1} % of {n} line pixels within {tolerance} px of the contour",
            100.0 * s
        );
    }
}
