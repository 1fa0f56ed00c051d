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
    let scene = small(Scene {
        sides: true,
        part_cells: 500,
        ..Scene::of_model(sample())
    });
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
