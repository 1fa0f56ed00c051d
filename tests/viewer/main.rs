//! The window for real: `strata view` under Xvfb, driven by its script, its pictures
//! measured, and the X display's own screenshot compared with the window's capture.
//! Needs `xvfb-run` and `xwd` (Debian's xvfb and x11-apps; `.ci/run` installs them);
//! the adapter comes from `WGPU_BACKEND` as for every image test.

mod xwd;

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;
use strata::render::Colormap;
use strata::render::image::{self, RgbaImage};

fn sample() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/sample.grdecl")
}

/// Runs `strata view ARGS --script SCRIPT` on a fresh X display; when `xshot` is
/// given, the display is dumped to it once the window's capture `capture` exists.
/// Returns what the viewer printed.
fn view(dir: &Path, args: &[&str], script: &str, xshot: Option<(&str, &str)>) -> String {
    for tool in ["xvfb-run", "xwd"] {
        let found = Command::new("sh")
            .args(["-c", &format!("command -v {tool}")])
            .output();
        assert!(
            found.is_ok_and(|o| o.status.success()),
            "{tool} is needed to test the window: apt-get install xvfb x11-apps"
        );
    }
    std::fs::write(dir.join("script.txt"), script).expect("script written");
    let mut shell = format!(
        "'{}' view {} --script script.txt > out.txt 2> err.txt & pid=$!\n",
        env!("CARGO_BIN_EXE_strata"),
        args.join(" ")
    );
    if let Some((capture, dump)) = xshot {
        shell += &format!(
            "for n in $(seq 600); do [ -f {capture} ] && break; kill -0 $pid 2>/dev/null || break; sleep 0.1; done\n\
             sleep 0.5; xwd -root -silent > {dump}\n"
        );
    }
    shell += "wait $pid";
    let status = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x900x24", "sh", "-c", &shell])
        .current_dir(dir)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .status()
        .expect("xvfb-run runs");
    let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap_or_default();
    assert!(
        status.success(),
        "strata view failed: {}\n{}",
        read("err.txt"),
        read("out.txt")
    );
    read("out.txt")
}

/// The line a script's `pick` printed (`{"pick": ...}`) among the viewer's output.
fn printed_pick(out: &str) -> Value {
    out.lines()
        .find_map(|l| {
            serde_json::from_str::<Value>(l)
                .ok()
                .filter(|v| v.get("pick").is_some())
        })
        .unwrap_or_else(|| panic!("no pick printed: {out}"))
}

fn open(path: &Path) -> RgbaImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
}

/// Where `capture` lies in the display dump, and the mean absolute difference of its
/// bytes there.
fn find_in_dump(dump: &xwd::Dump, capture: &RgbaImage) -> ((usize, usize), f64) {
    let (w, h) = (capture.width() as usize, capture.height() as usize);
    let diff = |ox: usize, oy: usize, rows: &mut dyn Iterator<Item = usize>| {
        let (mut sum, mut n) = (0.0, 0usize);
        for y in rows {
            for x in 0..w {
                let d = dump.rgb[(oy + y) * dump.width + ox + x];
                let c = capture.get_pixel(x as u32, y as u32).0;
                sum += (0..3).map(|a| f64::from(d[a].abs_diff(c[a]))).sum::<f64>();
                n += 3;
            }
        }
        sum / n as f64
    };
    let mut best = ((0, 0), f64::INFINITY);
    for oy in 0..=dump.height.saturating_sub(h).min(120) {
        for ox in 0..=dump.width.saturating_sub(w).min(120) {
            let d = diff(ox, oy, &mut (0..h).step_by(h / 8));
            if d < best.1 {
                best = ((ox, oy), d);
            }
        }
    }
    let (ox, oy) = best.0;
    (best.0, diff(ox, oy, &mut (0..h)))
}

#[test]
fn the_window_orbits_edits_picks_and_shows_what_it_captures() {
    let dir = tempfile::tempdir().expect("temp dir");
    let script = "orbit 40 4\n\
                  set layers [1,3]\n\
                  set colour.property \"PERMX\"\n\
                  set isolines {\"property\":\"PORO\"}\n\
                  frames 2\n\
                  pick 250 330\n\
                  screenshot app.png\n\
                  frames 30\n";
    let sample = sample();
    let out = view(
        dir.path(),
        &[&format!("'{}'", sample.display()), "--size", "900x700"],
        script,
        Some(("app.png", "x.xwd")),
    );
    // The pick names a cell of the layers shown, with the values `info --cell` gives.
    let pick = printed_pick(&out);
    let cell = &pick["pick"]["cell"];
    let ijk: Vec<u64> = cell["cell"]
        .as_array()
        .unwrap_or_else(|| panic!("no cell picked: {pick}"))
        .iter()
        .filter_map(Value::as_u64)
        .collect();
    assert!(
        (1..=3).contains(&ijk[2]),
        "picked {ijk:?} outside layers 1..3"
    );
    let info = Command::new(env!("CARGO_BIN_EXE_strata"))
        .args(["info", &sample.display().to_string(), "--json", "--cell"])
        .arg(format!("{},{},{}", ijk[0], ijk[1], ijk[2]))
        .output()
        .expect("info runs");
    let info: Value = serde_json::from_slice(&info.stdout).expect("info's JSON");
    assert_eq!(cell["values"], info["values"], "picked {ijk:?}");
    assert_eq!(cell["corners"], info["corners"], "picked {ijk:?}");
    // The display shows the window's capture, byte for byte but for rounding.
    let capture = open(&dir.path().join("app.png"));
    let dump = xwd::read(&std::fs::read(dir.path().join("x.xwd")).expect("the X dump"));
    let (at, diff) = find_in_dump(&dump, &capture);
    assert!(
        diff < 1.0,
        "the display differs from the capture by {diff:.2} per byte at {at:?}"
    );
    // The picked cell is marked in the window, over the frame (so not in the
    // capture): magenta around the pixel picked, nowhere else.
    let (ox, oy) = at;
    let magenta: Vec<(usize, usize)> = (0..dump.height)
        .flat_map(|y| (0..dump.width).map(move |x| (x, y)))
        .filter(|&(x, y)| dump.rgb[y * dump.width + x] == [255, 0, 255])
        .collect();
    let xs = || magenta.iter().map(|&(x, _)| x as f64 - ox as f64);
    let ys = || magenta.iter().map(|&(_, y)| y as f64 - oy as f64);
    let (x0, x1) = (xs().fold(f64::MAX, f64::min), xs().fold(f64::MIN, f64::max));
    let (y0, y1) = (ys().fold(f64::MAX, f64::min), ys().fold(f64::MIN, f64::max));
    assert!(
        magenta.len() >= 40 && (x0..=x1).contains(&250.5) && (y0..=y1).contains(&330.5),
        "{} marked pixels spanning x {x0}..{x1}, y {y0}..{y1} around the pick at (250, 330)",
        magenta.len()
    );
    assert!(
        x1 - x0 < 200.0 && y1 - y0 < 200.0,
        "the mark spans x {x0}..{x1}, y {y0}..{y1}: more than the cell"
    );
    assert!(!capture.pixels().any(|p| p.0[..3] == [255, 0, 255]));
    // The legend's colour bar: a column of the capture that runs down the whole
    // colour map, from its high end to its low end, never turning back.
    let bar = colour_bar(&capture, Colormap::Viridis);
    assert!(bar.is_some(), "no colour bar found in the capture");
    // And the capture is a picture of the model, not the background alone.
    let drawn = capture
        .pixels()
        .filter(|p| p.0[..3].iter().any(|&c| c < 200))
        .count();
    assert!(
        drawn > capture.pixels().len() / 10,
        "only {drawn} pixels drawn"
    );
    eprintln!("display against capture: {diff:.3} per byte at {at:?}; picked {ijk:?}");
}

/// The first column of `image` with a run of at least 100 pixels down the whole of
/// `map` (from within 5 entries of its top to within 5 of its bottom, each pixel
/// within a few levels of an entry, never turning back), as `(x, top, bottom)`.
fn colour_bar(image: &RgbaImage, map: Colormap) -> Option<(u32, u32, u32)> {
    let table = map.table();
    let mut known = std::collections::HashMap::new();
    let mut entry = |x: u32, y: u32| {
        let p = image.get_pixel(x, y).0;
        let c = [p[0], p[1], p[2]];
        *known.entry(c).or_insert_with(|| nearest(&table, c))
    };
    (0..image.width()).find_map(|x| {
        let mut run: Vec<(u32, usize)> = Vec::new();
        for y in 0..image.height() {
            match entry(x, y) {
                Some(e) if run.last().is_none_or(|&(_, last)| e <= last) => run.push((y, e)),
                Some(e) => run = vec![(y, e)],
                None => run.clear(),
            }
            if let (Some(&(top, high)), Some(&(bottom, low))) = (run.first(), run.last())
                && run.len() >= 100
                && high >= 250
                && low <= 5
            {
                return Some((x, top, bottom));
            }
        }
        None
    })
}

/// The entry of the colour `table` (RGBA rows) within a few levels of `c`, if any.
fn nearest(table: &[u8], c: [u8; 3]) -> Option<usize> {
    let (best, distance) = (0..256)
        .map(|i| {
            let d: i32 = (0..3)
                .map(|k| (i32::from(table[4 * i + k]) - i32::from(c[k])).pow(2))
                .sum();
            (i, d)
        })
        .min_by_key(|&(_, d)| d)
        .unwrap_or((0, i32::MAX));
    (distance <= 48).then_some(best)
}

/// A flat 16 x 12 grid of 50 m cells at 1000 m depth, with FX, each cell's centre x.
fn flat_model(dir: &Path) -> PathBuf {
    let (nx, ny) = (16, 12);
    let mut deck = format!("SPECGRID\n{nx} {ny} 1 1 F /\nCOORD\n");
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (50 * i, 50 * j);
            deck += &format!("{x} {y} 1000 {x} {y} 1010\n");
        }
    }
    deck += "/\nZCORN\n";
    deck += &format!("{}*1000 {}*1010 /\n", 4 * nx * ny, 4 * nx * ny);
    deck += "FX\n";
    for _ in 0..ny {
        for i in 0..nx {
            deck += &format!("{} ", 50 * i + 25);
        }
        deck += "\n";
    }
    deck += "/\n";
    let path = dir.join("flat.grdecl");
    std::fs::write(&path, deck).expect("model written");
    path
}

/// Line coverage along row `y` of `image`: 1 - luma / the surface's luma.
fn coverage_row(image: &RgbaImage, y: u32) -> Vec<f64> {
    let luma = |x: u32| {
        let p = image.get_pixel(x, y).0;
        0.299 * f64::from(p[0]) + 0.587 * f64::from(p[1]) + 0.114 * f64::from(p[2])
    };
    let mut lumas: Vec<f64> = (0..image.width()).map(luma).collect();
    let surface = {
        let mut sorted = lumas.clone();
        sorted.sort_by(f64::total_cmp);
        sorted[sorted.len() * 3 / 4]
    };
    for l in &mut lumas {
        *l = (1.0 - *l / surface).max(0.0);
    }
    lumas
}

/// The runs of coverage above 0.02 along a row: their summed coverage (the line's
/// width in pixels) and their centre.
fn runs(coverage: &[f64]) -> Vec<(f64, f64)> {
    let mut found = Vec::new();
    let mut x = 0;
    while x < coverage.len() {
        if coverage[x] <= 0.02 {
            x += 1;
            continue;
        }
        let start = x;
        while x < coverage.len() && coverage[x] > 0.02 {
            x += 1;
        }
        let width: f64 = coverage[start..x].iter().sum();
        let centre = (start..x).map(|i| i as f64 * coverage[i]).sum::<f64>() / width;
        found.push((width, centre + 0.5));
    }
    found
}

#[test]
fn on_a_flat_model_from_above_lines_measure_their_thickness_and_isolines_sit_on_the_field() {
    let dir = tempfile::tempdir().expect("temp dir");
    let model = flat_model(dir.path());
    let script = "set colour.solid true\n\
                  set camera {\"azimuth\":0,\"elevation\":90,\"distance\":1,\"z_scale\":1}\n\
                  set wire.color \"#000000\"\n\
                  set wire.major_color \"#000000\"\n\
                  set wire.thickness 1\nscreenshot w1.png\n\
                  set wire.thickness 2\nscreenshot w2.png\n\
                  set wire.thickness 3\nscreenshot w3.png\n\
                  set wire.technique \"none\"\n\
                  set isolines {\"property\":\"FX\",\"spacing\":80}\n\
                  screenshot iso.png\n";
    view(
        dir.path(),
        &[&format!("'{}'", model.display()), "--size", "900x700"],
        script,
        None,
    );
    let mut nodes = Vec::new();
    for thickness in [1.0, 2.0, 3.0] {
        let image = open(&dir.path().join(format!("w{thickness}.png")));
        // A row through the middle of a row of cells, away from the J lines.
        let y = image.height() / 2 + 8;
        let lines = runs(&coverage_row(&image, y));
        assert_eq!(
            lines.len(),
            17,
            "{thickness} px: {} lines across 16 cells",
            lines.len()
        );
        // The outline (issue 73) is left out: the interior lines only.
        for (width, centre) in &lines[1..16] {
            assert!(
                (width - thickness).abs() <= 0.5,
                "{thickness} px: a line at x {centre:.1} is {width:.2} px wide"
            );
        }
        let widths: Vec<String> = lines[1..16].iter().map(|l| format!("{:.2}", l.0)).collect();
        eprintln!("{thickness} px lines measure {}", widths.join(" "));
        nodes = lines.iter().map(|l| l.1).collect();
    }
    // Pixels per metre from the cell lines (at x = 50 i), then the isolines of
    // FX = x every 80 m must sit at their x, inside the outer ring of cells.
    // (From the interior lines: the outline's coverage is centred inside it, issue 73.)
    let (first, last) = (nodes[1], nodes[15]);
    let at = |x: f64| first + (last - first) * (x - 50.0) / 700.0;
    let image = open(&dir.path().join("iso.png"));
    let y = image.height() / 2 + 8;
    let isolines = runs(&coverage_row(&image, y));
    for x in [80.0, 160.0, 240.0, 320.0, 400.0, 480.0, 560.0, 640.0, 720.0] {
        let nearest = isolines
            .iter()
            .map(|(_, c)| (c - at(x)).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest <= 1.0,
            "the isoline FX = {x} is {nearest:.2} px from x = {x} m"
        );
        eprintln!("isoline FX = {x}: {nearest:.2} px from where the field puts it");
    }
}

#[test]
fn bad_input_in_the_window_is_shown_and_the_last_good_scene_stays() {
    let dir = tempfile::tempdir().expect("temp dir");
    let script = "screenshot good.png 400x300\n\
                  set colour.property \"NOSUCH\"\n\
                  frames 2\n\
                  set wire.thicknes 2\n\
                  load missing.json\n\
                  screenshot after.png 400x300\n";
    let sample = sample();
    view(
        dir.path(),
        &[&format!("'{}'", sample.display()), "--size", "700x500"],
        script,
        None,
    );
    let err = std::fs::read_to_string(dir.path().join("err.txt")).unwrap_or_default();
    for expected in ["NOSUCH", "thicknes", "missing.json"] {
        assert!(err.contains(expected), "no error naming {expected}: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
    let (good, after) = (
        open(&dir.path().join("good.png")),
        open(&dir.path().join("after.png")),
    );
    assert_eq!(good.dimensions(), after.dimensions());
    assert!(
        good.as_raw() == after.as_raw(),
        "the last good scene is not what is drawn"
    );
}

/// A model larger than a scene draws whole opens on a decimated preview of its top
/// layer while its hierarchy is built beside it; the window then draws the hierarchy,
/// picks in it, and opens on it directly next time.
#[test]
fn a_large_model_opens_on_a_preview_while_its_hierarchy_is_built() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::copy(sample(), dir.path().join("sample.grdecl")).expect("sample copied");
    // The sample's 4714 active cells count as large with parts of 1000.
    let scene = r#"{"model": {"path": "sample.grdecl"}, "part_cells": 1000}"#;
    std::fs::write(dir.path().join("scene.json"), scene).expect("scene written");
    let script = "frames 2\nwait\nframes 2\npick 300 300\n";
    let args = [
        "--scene",
        "scene.json",
        "--size",
        "900x700",
        "--stats",
        "stats.json",
    ];
    let out = view(dir.path(), &args, script, None);
    assert!(
        dir.path().join("sample.lod").is_file(),
        "no hierarchy beside the model"
    );
    let stats: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("stats.json")).expect("stats written"),
    )
    .expect("stats JSON");
    let drawn: Vec<&str> = stats["frames"]
        .as_array()
        .expect("frames")
        .iter()
        .filter_map(|f| f["drawn"].as_str())
        .collect();
    // The preview: the top layer's 36 x 24 cells, its top and bottom faces (at most
    // 3456 triangles, decimated where there are more than the preview keeps); then
    // the hierarchy's nodes.
    let preview: usize = drawn[0]
        .strip_suffix(" triangles")
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("the first frame drew {:?}", drawn[0]));
    assert!(
        preview > 0 && preview <= 3456,
        "the preview drew {preview} triangles"
    );
    let last = drawn.last().expect("frames drawn");
    assert!(
        last.contains("wireframe"),
        "the last frame drew {last:?}, not the hierarchy"
    );
    let pick = printed_pick(&out);
    assert!(
        pick["pick"]["ijk"].is_array(),
        "no cell picked in the hierarchy: {pick}"
    );
    assert!(
        pick["pick"]["cell"]["values"].is_array(),
        "no values picked: {pick}"
    );
    // Next time the hierarchy beside the model is opened at once.
    let out = view(dir.path(), &args, "frames 2\n", None);
    let stats: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("stats.json")).expect("stats written"),
    )
    .expect("stats JSON");
    let first = stats["frames"][0]["drawn"]
        .as_str()
        .unwrap_or_default()
        .to_string();
    assert!(
        first.contains("wireframe"),
        "reopened on {first:?}, not the hierarchy; {out}"
    );
    // The hierarchy opened alone knows the model's layers: the panel takes a range
    // of them, and its statistics name the nodes drawn.
    let script = "set layers [2,5]\nframes 2\nsave layers.json\n";
    view(
        dir.path(),
        &["sample.lod", "--stats", "stats.json"],
        script,
        None,
    );
    let saved: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("layers.json")).expect("scene saved"),
    )
    .expect("scene JSON");
    assert_eq!(saved["layers"], serde_json::json!([2, 5]));
    let stats: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("stats.json")).expect("stats written"),
    )
    .expect("stats JSON");
    let last = stats["frames"].as_array().and_then(|f| f.last());
    let nodes = last.and_then(|f| f["nodes"].as_u64());
    assert!(nodes.is_some_and(|n| n > 0), "no nodes counted: {last:?}");
}
