//! The retained scene renderer: a new camera or line style draws from what is held,
//! new layers or a new property build the surfaces again, new files read the model
//! again; and every frame is the picture a fresh engine draws of the same scene.

use std::path::PathBuf;

use strata::scene::{CameraSpec, IsolineSpec};
use strata::{Counters, Scene, SceneRenderer};

fn sample() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/sample.grdecl")
}

fn small(scene: Scene) -> Scene {
    Scene {
        size: [240, 180],
        ..scene
    }
}

/// `scene` without fault traces, for pictures drawn in parts compared with the whole to
/// the pixel: traces are drawn after each part in parts, after everything in one mesh,
/// so their anti-aliased edges blend over other colours where side walls meet them
/// (tests/cli.rs compares the traces' pixels on their own).
fn without_fault_traces(mut scene: Scene) -> Scene {
    scene.wire.fault_thickness = 0.0;
    scene
}

/// The counters of an engine that read `models`, built `contents` and drew `frames`.
fn counted(models: usize, contents: usize, frames: usize) -> Counters {
    Counters {
        models_read: models,
        contents_built: contents,
        frames,
    }
}

#[test]
fn twenty_cameras_build_the_surfaces_once() {
    let scene = small(Scene {
        sides: true,
        ..Scene::of_model(sample())
    });
    let mut engine = SceneRenderer::new(scene.clone()).expect("a scene");
    let mut pictures = Vec::new();
    for n in 0..20 {
        let camera = CameraSpec {
            azimuth: 18.0 * n as f32,
            elevation: 20.0 + n as f32,
            ..scene.camera
        };
        engine
            .set_scene(Scene {
                camera,
                ..scene.clone()
            })
            .expect("a new camera");
        let frame = engine.render().expect("a frame");
        assert_eq!(frame.report.triangles, 13_762);
        pictures.push(frame.image);
    }
    assert_eq!(engine.counters(), counted(1, 1, 20));
    // The frames are the views asked for: each differs from the one before, and the
    // last is what a fresh engine draws of the last scene.
    for pair in pictures.windows(2) {
        assert!(pair[0] != pair[1], "two cameras drew the same picture");
    }
    let fresh = SceneRenderer::new(engine.scene().clone())
        .and_then(|mut e| e.render())
        .expect("a fresh frame");
    assert!(
        fresh.image == pictures[19],
        "the held surfaces drew another picture"
    );
}

#[test]
fn a_change_rebuilds_only_what_it_invalidates() {
    let scene = small(Scene::of_model(sample()));
    let mut engine = SceneRenderer::new(scene.clone()).expect("a scene");
    engine.render().expect("a frame");
    let mut next = scene.clone();
    // Line style, colours, isoline spacing and size: drawn from what is held.
    next.wire.thickness = 3.0;
    next.wire.color = "red".into();
    next.colour.range = Some([0.1, 0.2]);
    next.size = [320, 200];
    engine.set_scene(next.clone()).expect("a new style");
    let frame = engine.render().expect("a frame");
    assert_eq!(frame.image.dimensions(), (320, 200));
    assert_eq!(engine.counters(), counted(1, 1, 2));
    // New layers: the surfaces again, from the model held.
    next.layers = Some([2, 3]);
    engine.set_scene(next.clone()).expect("new layers");
    let frame = engine.render().expect("a frame");
    assert!(
        frame.report.triangles < 13_762 / 2,
        "{}",
        frame.report.drawn
    );
    assert_eq!(engine.counters(), counted(1, 2, 3));
    // Isolines need their field: the content again; their spacing then does not.
    next.isolines = Some(IsolineSpec::of(Some("PORO")));
    engine.set_scene(next.clone()).expect("isolines");
    engine.render().expect("a frame");
    next.isolines = Some(IsolineSpec {
        spacing: Some(0.01),
        ..IsolineSpec::of(Some("PORO"))
    });
    engine.set_scene(next.clone()).expect("another spacing");
    engine.render().expect("a frame");
    assert_eq!(engine.counters(), counted(1, 3, 5));
    // The model read another way: read again.
    next.model = next.model.map(|mut m| {
        m.grid_only = true;
        m
    });
    next.isolines = None;
    engine.set_scene(next).expect("new files");
    engine.render().expect("a frame");
    assert_eq!(engine.counters(), counted(2, 4, 6));
}

#[test]
fn a_scene_in_parts_is_framed_and_drawn_from_what_is_held() {
    let scene = without_fault_traces(small(Scene {
        sides: true,
        part_cells: 500,
        ..Scene::of_model(sample())
    }));
    let mut engine = SceneRenderer::new(scene.clone()).expect("a scene");
    let first = engine.render().expect("a frame");
    assert!(
        first.report.drawn.contains("of 20 parts"),
        "{}",
        first.report.drawn
    );
    for azimuth in [60.0, 90.0] {
        let mut next = scene.clone();
        next.camera.azimuth = azimuth;
        engine.set_scene(next).expect("a new camera");
        engine.render().expect("a frame");
    }
    assert_eq!(engine.counters(), counted(1, 1, 3));
    // Drawn in parts, the picture is the one mesh's.
    let whole = SceneRenderer::new(Scene {
        part_cells: 2_000_000,
        ..scene
    })
    .and_then(|mut e| e.render())
    .expect("the whole mesh");
    assert!(whole.image == first.image, "parts and the whole differ");
}

#[test]
fn a_refused_scene_keeps_the_last_good_one() {
    let scene = small(Scene::of_model(sample()));
    let mut engine = SceneRenderer::new(scene.clone()).expect("a scene");
    engine.render().expect("a frame");
    let mut bad = scene.clone();
    bad.wire.thickness = f32::NAN;
    assert!(engine.set_scene(bad).is_err());
    assert_eq!(engine.scene(), &scene);
    // One the model refuses fails its frame, and the engine draws the next good one.
    let mut beyond = scene.clone();
    beyond.layers = Some([9, 9]);
    engine
        .set_scene(beyond)
        .expect("checked against the model when drawn");
    let said = engine
        .render()
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert_eq!(said, "layer 9 is not within the model's 1..6");
    engine.set_scene(scene).expect("the good scene again");
    assert!(engine.render().is_ok());
    assert_eq!(engine.counters().models_read, 1);
}

/// A generated model with two report steps whose PRESSURE grows east (step 1) and
/// north (step 2), written as EGRID and UNRST into `dir`.
fn stepped_model(dir: &std::path::Path) -> PathBuf {
    use strata::grid::ReportStep;
    use strata::grid::synth::{SynthParams, generate};
    let mut grid = generate(&SynthParams {
        nx: 30,
        ny: 20,
        nz: 2,
        faults: 0,
        seed: 5,
    })
    .expect("a generated grid");
    let d = grid.dims();
    let field = |east: bool| {
        strata::grid::ndarray::Array3::from_shape_fn((d.nz, d.ny, d.nx), |(_, j, i)| {
            if east { i as f32 } else { j as f32 }
        })
    };
    for (number, east) in [(1, true), (2, false)] {
        let mut step = ReportStep {
            number,
            ..ReportStep::default()
        };
        step.arrays.insert("PRESSURE".into(), field(east));
        grid.report_steps.push(step);
    }
    let egrid = dir.join("STEPS.EGRID");
    strata::grid::save(&grid, &egrid).expect("the grid written");
    strata::grid::eclbin::write_unrst(&grid, &dir.join("STEPS.UNRST")).expect("the steps written");
    egrid
}

#[test]
fn a_report_step_and_a_colour_range_colour_the_cells() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut scene = small(Scene::of_model(stepped_model(dir.path())));
    scene.colour.property = Some("PRESSURE".into());
    scene.camera.elevation = 90.0;
    scene.camera.azimuth = 0.0;
    let mut engine = SceneRenderer::new(scene.clone()).expect("a scene");
    let mut draw = |step: Option<i32>, range: Option<[f32; 2]>| {
        let mut next = scene.clone();
        next.colour.step = step;
        next.colour.range = range;
        engine.set_scene(next).expect("a scene");
        engine.render().expect("a frame")
    };
    let last = draw(None, None);
    let first = draw(Some(1), None);
    let second = draw(Some(2), None);
    assert!(last.image == second.image, "the last step is the default");
    assert!(
        first.image != second.image,
        "the steps colour the cells apart"
    );
    // Step 1 grows east: seen from above, a row's colours change along it, a
    // column's do not (and the other way round for step 2).
    let (w, h) = first.image.dimensions();
    let px = |f: &strata::Frame, x: u32, y: u32| f.image.get_pixel(x, y).0;
    let (mid_x, mid_y) = (w / 2, h / 2);
    assert!(px(&first, mid_x - 40, mid_y) != px(&first, mid_x + 40, mid_y));
    assert!(px(&second, mid_x, mid_y - 30) != px(&second, mid_x, mid_y + 30));
    assert_eq!(
        second.report.colouring,
        Some(("PRESSURE".to_string(), (0.0, 19.0)))
    );
    // A range of our own is what the colour map spans.
    let ranged = draw(Some(2), Some([-10.0, 50.0]));
    assert_eq!(
        ranged.report.colouring,
        Some(("PRESSURE".to_string(), (-10.0, 50.0)))
    );
    assert!(ranged.image != second.image);
    // A step the model does not have is named with those it has.
    let mut missing = scene.clone();
    missing.colour.step = Some(7);
    engine.set_scene(missing).expect("checked when drawn");
    let said = engine
        .render()
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(
        said.ends_with("no report step 7; its steps are 1, 2"),
        "{said}"
    );
}

/// The faces a range filter keeps of the sample, counted cell by cell from the grid:
/// the layer surfaces' faces in the cut (every top, and the last layer's bottom), and
/// the side faces open once the cells outside the cut count as absent.
fn faces_in_cut(cut: &strata::grid::Columns) -> (usize, usize) {
    use strata::grid::{Face, has_faces, open_sides, side_face_corners, surface_face_corners};
    let grid = strata::grid::open(&sample()).expect("the sample");
    let d = grid.dims();
    let origin = grid.display_origin();
    let kept = |i: usize, j: usize, k: usize| cut.contains(i, j) && has_faces(&grid, i, j, k);
    let cells = |k: usize| {
        cut.j
            .clone()
            .flat_map(move |j| cut.i.clone().map(move |i| [i, j, k]))
    };
    let surfaces = (0..d.nz)
        .map(|k| (k, Face::Top))
        .chain([(d.nz - 1, Face::Bottom)]);
    let layer_faces = surfaces
        .flat_map(|(k, face)| cells(k).map(move |c| (c, face)))
        .filter(|&(c, face)| surface_face_corners(&grid, c, face, origin).is_some())
        .count();
    let side_faces = (0..d.nz)
        .flat_map(cells)
        .filter(|&[i, j, k]| kept(i, j, k))
        .map(|[i, j, k]| {
            let open = open_sides(&grid, [i, j, k], |i, j| kept(i, j, k));
            (0..4)
                .filter(|&s| open[s] && side_face_corners(&grid, [i, j, k], s, origin).1)
                .count()
        })
        .sum();
    (layer_faces, side_faces)
}

#[test]
fn a_range_filter_cuts_the_model_open() {
    let cut = strata::grid::Columns { i: 7..30, j: 4..18 };
    let (layer_faces, side_faces) = faces_in_cut(&cut);
    let scene = small(Scene {
        i: Some([8, 30]),
        j: Some([5, 18]),
        ..Scene::of_model(sample())
    });
    let mut engine = SceneRenderer::new(scene.clone()).expect("a scene");
    let tops = engine.render().expect("a frame");
    assert_eq!(tops.report.triangles, 2 * layer_faces);
    let with_sides = without_fault_traces(Scene {
        sides: true,
        ..scene.clone()
    });
    engine.set_scene(with_sides.clone()).expect("sides");
    let walls = engine.render().expect("a frame");
    assert_eq!(walls.report.triangles, 2 * (layer_faces + side_faces));
    // The cut's own walls: more side faces than the same columns have uncut.
    let whole = SceneRenderer::new(small(Scene {
        sides: true,
        ..Scene::of_model(sample())
    }))
    .and_then(|mut e| e.render())
    .expect("the whole model");
    assert!(walls.report.triangles < whole.report.triangles);
    // Drawn in parts, the cut model is the one mesh's picture, framed the same.
    let parts = SceneRenderer::new(Scene {
        part_cells: 300,
        ..with_sides
    })
    .and_then(|mut e| e.render())
    .expect("in parts");
    assert!(
        parts.report.drawn.contains("parts"),
        "{}",
        parts.report.drawn
    );
    assert!(
        parts.image == walls.image,
        "parts and the whole cut model differ"
    );
    // A range beyond the model is named.
    let mut beyond = scene;
    beyond.j = Some([20, 30]);
    engine.set_scene(beyond).expect("checked when drawn");
    let said = engine
        .render()
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert_eq!(said, "cells J 20..30 are not within the model's 1..24");
}

#[test]
fn inactive_cells_are_drawn_grey_on_request() {
    use strata::grid::drawn_cell;
    let grid = strata::grid::open(&sample()).expect("the sample");
    let d = grid.dims();
    // Layer 3 seen from above: its top and bottom surfaces (the bottom closes the
    // stack), each inactive cell two triangles on each.
    // Without the legend, whose grey text would count among the grey pixels.
    let scene = small(Scene {
        layers: Some([3, 3]),
        camera: strata::scene::CameraSpec {
            azimuth: 0.0,
            elevation: 90.0,
            ..Default::default()
        },
        legend: false,
        ..Scene::of_model(sample())
    });
    let inactive: usize = (0..d.ny)
        .flat_map(|j| (0..d.nx).map(move |i| [i, j, 2]))
        .filter(|&c| drawn_cell(&grid, c, true) && !drawn_cell(&grid, c, false))
        .count();
    assert!(inactive > 50, "{inactive} inactive cells in layer 3");
    // Grey pixels inside grey patches (with 8 grey neighbours): not the anti-aliased
    // edge of a dark line over the white background, such as the outline's.
    let grey = |f: &strata::Frame| {
        let is_grey = |x: u32, y: u32| {
            let [r, g, b, _] = f.image.get_pixel(x, y).0;
            r == g && g == b && (90..200).contains(&r)
        };
        let (w, h) = f.image.dimensions();
        (1..h - 1)
            .flat_map(|y| (1..w - 1).map(move |x| (x, y)))
            .filter(|&(x, y)| (x - 1..=x + 1).all(|a| (y - 1..=y + 1).all(|b| is_grey(a, b))))
            .count()
    };
    let mut engine = SceneRenderer::new(scene.clone()).expect("a scene");
    let active = engine.render().expect("a frame");
    engine
        .set_scene(Scene {
            inactive: true,
            ..scene
        })
        .expect("inactive cells");
    let all = engine.render().expect("a frame");
    assert_eq!(all.report.triangles, active.report.triangles + 4 * inactive);
    assert_eq!(grey(&active), 0);
    // The inactive corner of the layer (8 % of its cells) shows grey, lines aside.
    assert!(grey(&all) > 240 * 180 / 100, "{} grey pixels", grey(&all));
}

/// Picking names the cell under a pixel: the ray's point lies in the cell's column and
/// between its top and bottom, at full resolution, on decimated surfaces (by their
/// global coordinates) and in a hierarchy (by its nodes' layers) alike.
#[test]
fn a_pick_names_the_cell_under_the_pixel_at_every_level_of_detail() {
    use strata::grid::open;
    use strata::lod::{BuildOptions, build_file};
    use strata::scene::Lod;

    let dir = tempfile::tempdir().expect("temp dir");
    let grid = open(&sample()).expect("the sample reads");
    let lod = dir.path().join("sample.lod");
    build_file(&grid, Some("PORO"), &lod, &BuildOptions::default()).expect("hierarchy built");
    let camera = CameraSpec {
        azimuth: 20.0,
        elevation: 60.0,
        ..CameraSpec::default()
    };
    let model = Scene {
        camera,
        ..small(Scene::of_model(sample()))
    };
    let decimated = Scene {
        lod: Lod::Decimated {
            percent: 20.0,
            cover: false,
            stitch: false,
        },
        ..model.clone()
    };
    let hierarchy = Scene {
        camera,
        ..small(Scene::of_hierarchy(&lod))
    };
    for (name, scene) in [
        ("full", model),
        ("decimated", decimated),
        ("hierarchy", hierarchy),
    ] {
        let mut engine = SceneRenderer::new(scene).expect("scene");
        assert!(
            engine.pick(120.0, 90.0).is_err(),
            "{name}: a pick before any frame"
        );
        engine.render().expect("a frame");
        let mut picked = 0;
        for (x, y) in [(120.0, 90.0), (90.0, 100.0), (150.0, 80.0), (110.0, 60.0)] {
            let Some(pick) = engine.pick(x, y).expect("a pick") else {
                continue;
            };
            picked += 1;
            let [i, j, k] = pick.cell;
            let corners = grid.cell_corners(i, j, k);
            let (lo, hi) = corners.iter().fold(
                ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
                |(lo, hi), c| {
                    (
                        std::array::from_fn(|a| lo[a].min(c[a])),
                        std::array::from_fn(|a| hi[a].max(c[a])),
                    )
                },
            );
            // Within the cell's box, with a margin for the simplified surfaces' error
            // (a pixel of a 240-pixel picture of a 2 km model is 8 m).
            let margin = [10.0, 10.0, 10.0];
            for a in 0..3 {
                assert!(
                    pick.point[a] >= lo[a] - margin[a] && pick.point[a] <= hi[a] + margin[a],
                    "{name}: pixel ({x}, {y}) picked cell {:?} at {:?}, outside {lo:?}..{hi:?}",
                    pick.cell,
                    pick.point
                );
            }
        }
        assert!(
            picked >= 3,
            "{name}: only {picked} of 4 pixels picked a cell"
        );
        // A pixel in a corner of the picture shows the background.
        assert_eq!(engine.pick(0.0, 0.0).expect("a pick"), None, "{name}");
    }
}

#[test]
fn a_model_in_memory_is_drawn_as_the_file_is_and_held_across_cameras() {
    use strata::engine::Model;
    use strata::scene::ModelSource;
    let scene = small(Scene {
        sides: true,
        ..Scene::of_model(sample())
    });
    let from_file = SceneRenderer::new(scene.clone())
        .and_then(|mut e| e.render())
        .expect("a frame of the file");
    let mut grid = strata::grid::open(&sample()).expect("the sample");
    let source = ModelSource::new("<in memory>");
    let (model, _) = Model::from_grid(source.clone(), grid.clone());
    let mut engine = SceneRenderer::new(scene.clone()).expect("a scene");
    engine.set_model(model, Vec::new());
    assert_eq!(engine.scene().model.as_ref(), Some(&source));
    let first = engine.render().expect("a frame of the grid");
    assert!(
        first.image == from_file.image,
        "the grid drew another picture"
    );
    // A new camera on the same source draws from what is held.
    let mut turned = engine.scene().clone();
    turned.camera.azimuth += 90.0;
    engine.set_scene(turned).expect("a new camera");
    let second = engine.render().expect("a turned frame");
    assert!(second.image != first.image, "the camera did not turn");
    assert_eq!(engine.counters(), counted(0, 1, 2));
    // A changed grid handed over again is drawn anew: the model is what was given.
    grid.properties
        .get_mut("PORO")
        .expect("PORO")
        .mapv_inplace(|v| 0.3 - v);
    let (model, _) = Model::from_grid(source, grid);
    engine.set_model(model, Vec::new());
    let third = engine.render().expect("a frame of the changed grid");
    assert!(
        third.image != second.image,
        "the changed grid drew the same picture"
    );
    assert_eq!(engine.counters(), counted(0, 2, 3));
}
