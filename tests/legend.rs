//! The colour legend and colour scales, measured in the engine's pictures: the
//! legend's bar follows the colour map from high to low with labels beside it, a
//! log scale and a categorical one colour cells of known values as they should, and
//! with the legend off its area is the plain picture.

use std::path::{Path, PathBuf};

use strata::grid::ndarray::Array3;
use strata::grid::{CornerPointGrid, Dims};
use strata::legend::{Entries, Layout, Legend};
use strata::render::image::RgbaImage;
use strata::render::{Colormap, Scale, WireMode, categorical_colour};
use strata::scene::Lod;
use strata::{Scene, SceneRenderer};

fn sample() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/sample.grdecl")
}

fn draw(scene: &Scene) -> RgbaImage {
    let mut engine = SceneRenderer::new(scene.clone()).expect("a scene");
    engine.render().expect("a frame").image
}

/// A flat model of `values.len()` columns along I, 2 rows, 1 layer, each column's
/// cells holding its value of `property`, written as GRDECL into `dir`.
fn striped(dir: &Path, property: &str, values: &[f32]) -> PathBuf {
    let (nx, ny) = (values.len(), 2);
    let coord = (0..=ny)
        .flat_map(|j| (0..=nx).map(move |i| (i, j)))
        .flat_map(|(i, j)| {
            let (x, y) = (100.0 * i as f64, 100.0 * j as f64);
            [x, y, 0.0, x, y, 10.0]
        })
        .collect();
    let zcorn = (0..2 * 2 * ny * 2 * nx)
        .map(|n| if n < 4 * ny * nx { 1000.0 } else { 1010.0 })
        .collect();
    let mut grid = CornerPointGrid::from_arrays(Dims { nx, ny, nz: 1 }, coord, zcorn, None)
        .expect("a flat grid");
    let field = Array3::from_shape_fn((1, ny, nx), |(_, _, i)| values[i]);
    grid.set_property(property, field).expect("the property");
    let path = dir.join(format!("{property}.grdecl"));
    strata::grid::save(&grid, &path).expect("written");
    path
}

/// The scene of `model` seen from straight above, without lines.
fn from_above(model: PathBuf, property: &str, scale: Scale) -> Scene {
    let mut scene = Scene::of_model(model);
    scene.colour.property = Some(property.into());
    scene.colour.scale = scale;
    scene.camera.elevation = 90.0;
    scene.camera.azimuth = 0.0;
    scene.wire.technique = WireMode::None;
    scene.size = [600, 400];
    scene
}

/// The unit RGB direction of a colour: shading scales the channels alike.
fn direction(c: [u8; 3]) -> [f64; 3] {
    let v = c.map(f64::from);
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-9);
    v.map(|x| x / n)
}

fn cosine(a: [u8; 3], b: [u8; 3]) -> f64 {
    let (a, b) = (direction(a), direction(b));
    a.iter().zip(&b).map(|(x, y)| x * y).sum()
}

fn rgb(image: &RgbaImage, x: u32, y: u32) -> [u8; 3] {
    let p = image.get_pixel(x, y).0;
    [p[0], p[1], p[2]]
}

/// The colour map's entry nearest `c`.
fn nearest_entry(table: &[u8], c: [u8; 3]) -> usize {
    (0..256)
        .min_by_key(|&i| {
            (0..3)
                .map(|k| (i32::from(table[4 * i + k]) - i32::from(c[k])).pow(2))
                .sum::<i32>()
        })
        .unwrap_or(0)
}

/// The legend the engine draws for the sample's PORO on a frame `height` high, and
/// where it lies.
fn poro_layout(height: u32) -> (Legend, Layout) {
    let legend = Legend::new(
        "PORO",
        Some("fraction"),
        (Colormap::Viridis, Scale::Linear),
        (0.0615, 0.2968),
        &[],
    );
    let layout = legend.layout(height).expect("a layout");
    (legend, layout)
}

#[test]
fn the_legend_bar_runs_from_high_to_low_with_labels_beside_it() {
    for isolation in [false, true] {
        let mut scene = Scene::of_model(sample());
        scene.size = [1000, 800];
        scene.wire.isolation = isolation;
        let image = draw(&scene);
        let (legend, layout) = poro_layout(800);
        let [left, top] = layout.origin(1000, 800).map(|v| v as u32);
        let [x0, y0, x1, y1] = layout.bar.expect("a colour bar");
        // The bar's centre column, top to bottom: the colour map from its high end
        // to its low end, never turning back.
        let table = Colormap::Viridis.table();
        let x = left + (x0 + x1) / 2;
        let entries: Vec<usize> = (top + y0..top + y1)
            .map(|y| nearest_entry(&table, rgb(&image, x, y)))
            .collect();
        assert!(
            entries[0] >= 250 && entries[entries.len() - 1] <= 5,
            "{entries:?}"
        );
        assert!(entries.windows(2).all(|w| w[0] >= w[1]), "{entries:?}");
        // A thin dark border left of the bar.
        let border = rgb(&image, left + x0 - 1, top + (y0 + y1) / 2);
        assert!(border.iter().all(|&c| c < 80), "border {border:?}");
        // Dark text beside the bar at each tick's height, on the light panel.
        let Entries::Ticks(ticks) = &legend.entries else {
            panic!("PORO has ticks");
        };
        assert!(layout.ticks.iter().filter(|t| t.1).count() >= 4);
        let (w, h) = (layout.size[0], layout.size[1]);
        for (t, _) in ticks.iter().zip(&layout.ticks).filter(|(_, row)| row.1) {
            let y = top + y1 - 1 - (t.fraction * f64::from(y1 - y0 - 1)).round() as u32;
            let dark = (y.saturating_sub(4)..y + 4)
                .flat_map(|y| (left + x1 + 8..left + w).map(move |x| (x, y)))
                .filter(|&(x, y)| rgb(&image, x, y).iter().all(|&c| c < 110))
                .count();
            assert!(dark >= 6, "tick {} at row {y}: {dark} dark pixels", t.label);
        }
        let panel = rgb(&image, left + 2, top + h - 3);
        assert!(
            panel.iter().all(|&c| c > 225),
            "panel {panel:?} (isolation {isolation})"
        );
    }
}

#[test]
fn without_the_legend_its_area_is_the_plain_picture() {
    let mut scene = Scene::of_model(sample());
    scene.size = [600, 400];
    let with = draw(&scene);
    scene.legend = false;
    let without = draw(&scene);
    let (_, layout) = poro_layout(400);
    let [left, top] = layout.origin(600, 400);
    let inside = |x: u32, y: u32| {
        let (x, y) = (i64::from(x), i64::from(y));
        x >= left && y >= top && y < top + i64::from(layout.size[1])
    };
    let mut differ = 0;
    for (x, y, p) in with.enumerate_pixels() {
        if p != without.get_pixel(x, y) {
            assert!(inside(x, y), "pixel {x},{y} outside the legend changed");
            differ += 1;
        }
    }
    assert!(differ > 1000, "the legend changed only {differ} pixels");
    // The model does not reach the right edge: without a legend, the background.
    let right =
        (left as u32 + 10..600).flat_map(|x| (top as u32..top as u32 + 100).map(move |y| (x, y)));
    assert!(
        right
            .clone()
            .all(|(x, y)| without.get_pixel(x, y).0 == [255; 4])
    );
    // Seen from so far that the model covers no pixel, the frame is blank though
    // its legend is drawn.
    let mut far = scene.clone();
    far.legend = true;
    far.camera.distance = 1.0e6;
    let mut engine = SceneRenderer::new(far).expect("a scene");
    let frame = engine.render().expect("a frame");
    assert!(
        frame.report.blank && frame.image != without,
        "a blank frame with a legend"
    );
    // A solid colour has no legend.
    scene.colour.solid = true;
    let solid = draw(&scene);
    scene.legend = true;
    assert!(draw(&scene) == solid, "a solid colour drew a legend");
}

#[test]
fn a_log_scale_colours_a_cell_by_its_decade() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let model = striped(dir.path(), "PERMX", &[1.0, 10.0, 1000.0]);
    let table = Colormap::Viridis.table();
    let entry = |i: usize| [table[4 * i], table[4 * i + 1], table[4 * i + 2]];
    let decimated = Lod::Decimated {
        percent: 50.0,
        cover: false,
        stitch: false,
    };
    let cases = [
        (Scale::Log, Lod::Full, 85),
        (Scale::Log, decimated.clone(), 85),
        (Scale::Linear, Lod::Full, 2),
        (Scale::Linear, decimated, 2),
    ];
    for (scale, lod, expect) in cases {
        let scene = Scene {
            lod: lod.clone(),
            ..from_above(model.clone(), "PERMX", scale)
        };
        let image = draw(&scene);
        // Whole or decimated, the middle column's centre is the picture's: 10 mD, a third of the way up
        // three decades on a log scale, near the bottom on a linear one.
        let got = rgb(&image, 300, 200);
        let best = (0..256)
            .max_by(|&a, &b| cosine(entry(a), got).total_cmp(&cosine(entry(b), got)))
            .unwrap_or(0);
        assert!(
            best.abs_diff(expect) <= 6,
            "{scale:?} {lod:?}: entry {best}, not {expect}"
        );
    }
    // A range reaching zero is refused for a log scale, naming the property.
    let model = striped(dir.path(), "PORO", &[0.0, 0.1, 0.2]);
    let message = SceneRenderer::new(from_above(model, "PORO", Scale::Log))
        .and_then(|mut e| e.render())
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(
        message.contains("log scale") && message.contains("PORO spans 0 .. 0.2"),
        "{message}"
    );
}

#[test]
fn a_categorical_scale_gives_each_code_its_colour_unblended() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let codes = [1.0, 2.0, 3.0, 7.0];
    let model = striped(dir.path(), "FIPNUM", &codes);
    let mut scene = from_above(model, "FIPNUM", Scale::Categorical);
    scene.legend = false;
    let image = draw(&scene);
    // The model spans the picture's middle; its columns are a quarter of it each.
    let row: Vec<[u8; 3]> = (0..600).map(|x| rgb(&image, x, 200)).collect();
    let model: Vec<usize> = (0..600).filter(|&x| row[x] != [255; 3]).collect();
    let (first, last) = (model[0], model[model.len() - 1]);
    let width = (last - first + 1) as f64;
    let centres: Vec<[u8; 3]> = (0..4)
        .map(|c| row[first + ((c as f64 + 0.5) * width / 4.0) as usize])
        .collect();
    for (code, got) in codes.iter().zip(&centres) {
        let want = categorical_colour(*code as i64);
        assert!(
            cosine(want, *got) > 0.999,
            "code {code}: {got:?}, not {want:?}"
        );
    }
    for (i, a) in centres.iter().enumerate() {
        assert!(centres[i + 1..].iter().all(|b| b != a), "{centres:?}");
    }
    // Every pixel of the model is one of the four colours: no blend between codes.
    let close = |a: [u8; 3], b: [u8; 3]| a.iter().zip(&b).all(|(x, y)| x.abs_diff(*y) <= 2);
    for (x, pixel) in row.iter().enumerate().take(last + 1).skip(first) {
        assert!(
            centres.iter().any(|c| close(*c, *pixel)),
            "pixel {x}: {pixel:?}"
        );
    }
    // Its legend lists the codes with their colours.
    scene.legend = true;
    let image = draw(&scene);
    let legend = Legend::new(
        "FIPNUM",
        None,
        (Colormap::Viridis, Scale::Categorical),
        (1.0, 7.0),
        &[1, 2, 3, 7],
    );
    let layout = legend.layout(400).expect("a layout");
    let [left, top] = layout.origin(600, 400).map(|v| v as u32);
    assert_eq!(layout.swatches.len(), 4);
    for (sw, code) in layout.swatches.iter().zip([1, 2, 3, 7]) {
        let got = rgb(
            &image,
            left + (sw[0] + sw[2]) / 2,
            top + (sw[1] + sw[3]) / 2,
        );
        assert_eq!(got, categorical_colour(code), "swatch of code {code}");
    }
    // A property that is not codes is refused for a categorical scale.
    let poro = Scene {
        colour: strata::scene::Colouring {
            property: Some("PORO".into()),
            scale: Scale::Categorical,
            ..Default::default()
        },
        ..Scene::of_model(sample())
    };
    let message = draw_error(&poro);
    assert!(
        message.contains("categorical") && message.contains("PORO"),
        "{message}"
    );
}

fn draw_error(scene: &Scene) -> String {
    SceneRenderer::new(scene.clone())
        .and_then(|mut e| e.render())
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default()
}

#[test]
fn a_scene_in_parts_shows_the_same_legend() {
    let mut scene = Scene::of_model(sample());
    scene.size = [500, 360];
    let whole = draw(&scene);
    scene.part_cells = 2000;
    let parts = draw(&scene);
    let (_, layout) = poro_layout(360);
    let [left, top] = layout.origin(500, 360).map(|v| v as u32);
    let [w, h] = layout.size;
    for y in top..top + h {
        for x in left + w / 2..left + w {
            assert_eq!(
                whole.get_pixel(x, y),
                parts.get_pixel(x, y),
                "pixel {x},{y}"
            );
        }
    }
}
