//! Colour scales, measured in the engine's pictures of flat striped models seen
//! from above: a log scale colours a cell by its decade, whole or decimated; a
//! categorical one gives each code its palette colour, never a blend; values a
//! scale cannot map are refused, naming the property.

use std::path::{Path, PathBuf};

use strata::grid::ndarray::Array3;
use strata::grid::{CornerPointGrid, Dims};
use strata::legend::Legend;
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

fn draw_error(scene: &Scene) -> String {
    SceneRenderer::new(scene.clone())
        .and_then(|mut e| e.render())
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default()
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
