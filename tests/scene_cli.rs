//! A scene saved by `--save-scene` draws, with `strata render --scene`, the picture
//! its flags drew: the sample, Reek with its property deck, decimated, with
//! isolines, with map grid lines, and a hierarchy's `lod view`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use strata::Scene;
use strata::render::image::{self, RgbaImage};
use strata::scene::Lod;

fn strata(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_strata"))
        .args(args)
        .output()
        .expect("the strata binary runs")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn text(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

/// Reek's grid and porosity deck in `../shared/data`, or `None` (said) without it.
fn reek() -> Option<(PathBuf, PathBuf)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/reek");
    if !dir.is_dir() {
        eprintln!("skipping: ../shared/data not found");
        return None;
    }
    Some((dir.join("REEK.EGRID"), dir.join("reek_sim_poro.grdecl")))
}

/// Runs `command` with `flags` and `--save-scene`, then `render --scene` of what it
/// saved; asserts both succeed and draw the same picture (within 1/255 per
/// channel), and that the picture shows the model. Returns the scene saved.
fn same_picture_from_scene(name: &str, command: &[&str], flags: &[&str]) -> Scene {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let (scene, flagged, saved) = (
        dir.path().join("scene.json"),
        dir.path().join("flags.png"),
        dir.path().join("scene.png"),
    );
    let mut args = command.to_vec();
    args.extend_from_slice(flags);
    args.extend_from_slice(&["--size", "400x300", "--save-scene", text(&scene)]);
    args.extend_from_slice(&["-o", text(&flagged)]);
    let out = strata(&args);
    assert!(out.status.success(), "{name}: {}", stderr(&out));
    let out = strata(&["render", "--scene", text(&scene), "-o", text(&saved)]);
    assert!(
        out.status.success(),
        "{name} from its scene: {}",
        stderr(&out)
    );
    let picture = |p: &Path| -> RgbaImage { image::open(p).expect("a PNG").to_rgba8() };
    let (a, b) = (picture(&flagged), picture(&saved));
    assert_eq!(a.dimensions(), (400, 300), "{name}");
    assert_eq!(a.dimensions(), b.dimensions(), "{name}");
    let worst = a
        .pixels()
        .zip(b.pixels())
        .flat_map(|(p, q)| (0..4).map(move |c| p.0[c].abs_diff(q.0[c])))
        .max()
        .unwrap_or(0);
    assert!(worst <= 1, "{name}: channels differ by up to {worst}");
    let model = a.pixels().filter(|p| p.0 != [255; 4]).count();
    assert!(
        model > 400 * 300 / 10,
        "{name}: {model} pixels show the model"
    );
    let json = std::fs::read_to_string(&scene).expect("the scene was saved");
    Scene::from_json(&json).expect("the saved scene reads back")
}

#[test]
fn the_sample_from_its_scene() {
    let flags = ["--sides", "--view", "60,30", "--i-range", "3..30"];
    let scene = same_picture_from_scene("sample", &["render"], &flags);
    assert!(scene.sides);
    assert_eq!((scene.i, scene.j), (Some([3, 30]), None));
    assert_eq!(scene.camera.azimuth, 60.0);
    let model = scene.model.expect("a model");
    assert!(model.path.ends_with("data/sample.grdecl"), "{model:?}");
}

#[test]
fn reek_with_its_property_deck_from_its_scene() {
    let Some((grid, poro)) = reek() else { return };
    let flags = ["--props", text(&poro), "--layers", "2..9"];
    let scene = same_picture_from_scene("Reek", &["render", text(&grid)], &flags);
    assert_eq!(scene.layers, Some([2, 9]));
    assert_eq!(scene.model.map(|m| m.props), Some(vec![poro]));
}

#[test]
fn a_decimated_scene_from_its_scene() {
    let Some((grid, poro)) = reek() else { return };
    let flags = ["--props", text(&poro), "--lod", "10"];
    let scene = same_picture_from_scene("Reek --lod 10", &["render", text(&grid)], &flags);
    let decimated = Lod::Decimated {
        percent: 10.0,
        cover: false,
        stitch: false,
    };
    assert_eq!(scene.lod, decimated);
}

#[test]
fn isolines_from_their_scene() {
    let flags = ["--iso", "PORO:0.02:4", "--sides", "--smooth"];
    let scene = same_picture_from_scene("--iso", &["render"], &flags);
    let iso = scene.isolines.expect("isolines");
    assert_eq!(
        (iso.property.as_deref(), iso.spacing, iso.major_every),
        (Some("PORO"), Some(0.02), 4)
    );
    assert!(scene.colour.smooth);
}

#[test]
fn map_grid_lines_from_their_scene() {
    let flags = [
        "--grid-lines",
        "200,50,25",
        "--view",
        "0,90",
        "--no-property",
    ];
    let scene = same_picture_from_scene("--grid-lines", &["render"], &flags);
    let lines = scene.grid_lines.expect("grid lines");
    assert_eq!((lines.spacing, lines.origin), (200.0, [50.0, 25.0]));
    assert!(scene.colour.solid);
}

#[test]
fn a_hierarchy_view_from_its_scene() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let lod = dir.path().join("sample.lod");
    let sample = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/sample.grdecl");
    let built = strata(&["lod", "build", text(&sample), "-o", text(&lod)]);
    assert!(built.status.success(), "lod build: {}", stderr(&built));
    let flags = [
        "--pixels",
        "3",
        "--sides",
        "--iso",
        "--wire-color",
        "#202060",
    ];
    let scene = same_picture_from_scene("lod view", &["lod", "view", text(&lod)], &flags);
    assert_eq!(
        scene.lod,
        Lod::Hierarchy {
            file: lod,
            pixels: 3.0
        }
    );
    assert_eq!(scene.wire.color, "#202060");
}

#[test]
fn a_scene_file_goes_alone_and_a_wrong_one_is_named() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let scene = dir.path().join("scene.json");
    let png = dir.path().join("out.png");
    std::fs::write(
        &scene,
        r#"{"model": {"path": "x.grdecl"}, "colour": {"map": "x"}}"#,
    )
    .expect("written");
    let out = strata(&["render", "--scene", text(&scene), "-o", text(&png)]);
    assert!(!out.status.success());
    let said = stderr(&out);
    assert!(
        said.contains("scene.json") && said.contains("unknown field `map`"),
        "{said}"
    );
    let out = strata(&[
        "render",
        "--scene",
        text(&scene),
        "--sides",
        "-o",
        text(&png),
    ]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("cannot be used with"),
        "{}",
        stderr(&out)
    );
    assert!(!png.exists(), "no picture of a refused scene");
}
