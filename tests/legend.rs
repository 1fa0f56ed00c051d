//! The colour legend, measured in the engine's pictures: its bar follows the colour
//! map from high to low with labels beside it, on white and on black; with the
//! legend off its area is the plain picture; a scene in parts shows the same legend.

use std::path::PathBuf;

use strata::legend::{Entries, Layout, Legend};
use strata::render::image::RgbaImage;
use strata::render::{Colormap, Scale};
use strata::{Scene, SceneRenderer};

fn sample() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/sample.grdecl")
}

fn draw(scene: &Scene) -> RgbaImage {
    let mut engine = SceneRenderer::new(scene.clone()).expect("a scene");
    engine.render().expect("a frame").image
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
    // Fault traces keep their width in pixels however far: a speck of them is drawn.
    far.wire.fault_thickness = 0.0;
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
