//! `strata` as a shell runs it: piped into a reader that stops early.

/// Runs the `strata` binary with `args`: whether it succeeded, what it said on
/// standard error and what it printed.
fn strata(args: &[&str]) -> (bool, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_strata"))
        .args(args)
        .output()
        .expect("the strata binary runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
    )
}

/// `strata info ... | head` stops strata as it stops `cat`, by SIGPIPE, not with a
/// panic and a backtrace on standard error.
#[cfg(unix)]
#[test]
fn a_closed_output_pipe_ends_strata_quietly() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::{Command, Stdio};

    let (reader, writer) = std::io::pipe().expect("a pipe");
    // Nobody reads: the first line strata prints meets a closed pipe.
    drop(reader);
    let sample = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/sample.grdecl");
    let out = Command::new(env!("CARGO_BIN_EXE_strata"))
        .arg("info")
        .arg(&sample)
        .stdout(writer)
        .stderr(Stdio::piped())
        .output()
        .expect("the strata binary runs");
    let said = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        out.status.signal(),
        Some(libc::SIGPIPE),
        "{:?}: {said}",
        out.status
    );
    assert!(said.is_empty(), "{said}");
}

/// A deck whose property INCLUDE is missing (as a `.DATA` deck shipped without its
/// property files): refused at that INCLUDE line, and read with `--grid-only` by
/// `render`, `info` and `lod build`, each naming the skipped file.
#[test]
fn grid_only_reads_a_deck_whose_property_include_is_missing() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let sample = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/sample.grdecl");
    let deck = dir.path().join("model.grdecl");
    std::fs::write(
        &deck,
        format!(
            "INCLUDE\n '{}' /\nINCLUDE\n 'missing_poro.inc' /\n",
            sample.display()
        ),
    )
    .expect("written");
    let deck = deck.to_str().expect("a UTF-8 path");
    let png = dir.path().join("model.png");
    let lod = dir.path().join("model.lod");
    let (ok, said, _) = strata(&["info", deck]);
    assert!(!ok, "{said}");
    assert!(
        said.contains("model.grdecl:3: keyword INCLUDE: cannot read"),
        "{said}"
    );

    let skipped = "missing_poro.inc' skipped";
    let (ok, _, printed) = strata(&["info", deck, "--grid-only"]);
    assert!(ok && printed.contains("36 x 24 x 6"), "{printed}");
    assert!(printed.contains(skipped), "{printed}");

    let png_path = png.to_str().expect("a UTF-8 path");
    let (ok, said, _) = strata(&[
        "render",
        deck,
        "--grid-only",
        "--size",
        "240x180",
        "-o",
        png_path,
    ]);
    assert!(
        ok && said.contains(&format!("warning: {deck}:3: INCLUDE")),
        "{said}"
    );
    assert!(said.contains(skipped), "{said}");
    // The grid is drawn: most of the frame's middle differs from its corner.
    let image = strata::render::image::open(&png).expect("a PNG").to_rgba8();
    let corner = *image.get_pixel(0, 0);
    let middle = (60..180)
        .flat_map(|x| (45..135).map(move |y| (x, y)))
        .filter(|&(x, y)| *image.get_pixel(x, y) != corner)
        .count();
    assert!(
        middle > 120 * 90 / 2,
        "{middle} of the middle's pixels drawn"
    );

    let lod_path = lod.to_str().expect("a UTF-8 path");
    let (ok, said, _) = strata(&["lod", "build", deck, "--grid-only", "-o", lod_path]);
    assert!(ok && said.contains(skipped), "{said}");
    let (ok, said, _) = strata(&["info", lod_path, "--grid-only"]);
    assert!(!ok && said.contains("--grid-only need a model"), "{said}");
}

/// A scene of more active cells than `--part-cells` is drawn a run of layers at a time,
/// each part dropped once drawn: the picture is the one mesh's, pixel for pixel, in
/// every style that parts can draw, and what needs the whole scene at once is refused
/// with the way out.
#[test]
fn a_scene_beyond_one_part_is_drawn_in_parts_as_one_mesh() {
    use std::process::Command;

    let dir = tempfile::tempdir().expect("a temporary folder");
    let sample = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/sample.grdecl");
    let sample = sample.to_str().expect("a UTF-8 path");
    let render = |png: &str, options: &[&str]| {
        let png = dir.path().join(png);
        let png = png.to_str().expect("a UTF-8 path");
        let out = Command::new(env!("CARGO_BIN_EXE_strata"))
            .args(["render", sample, "--size", "320x240", "-o", png])
            // Fault traces are drawn after each part in parts, after everything in one
            // mesh: their anti-aliased edges blend over other colours where side walls
            // meet them. Compared without them here, and on their own below.
            .args(["--fault-thickness", "0"])
            .args(options)
            .output()
            .expect("the strata binary runs");
        let said = String::from_utf8_lossy(&out.stderr).into_owned();
        let picture = out
            .status
            .success()
            .then(|| strata::render::image::open(png).expect("a PNG").to_rgba8());
        (picture, said)
    };
    // No two of the sample's six layers hold 500 active cells or fewer: a run each,
    // and those with more than 500 are cut into bands of rows.
    let cases: [&[&str]; 7] = [
        &["--sides"],
        &["--sides", "--smooth", "--iso", "PORO"],
        &["--sides", "--wire", "dist", "--thickness", "2.5"],
        &["--layers", "2..5", "--sides", "--wire", "texgs"],
        &["--sides", "--wire", "tex", "--view", "200,-30"],
        &["--sides", "--centre", "10,10", "--view", "30,35,0.3"],
        &["--layers", "3..3", "--sides", "--smooth", "--iso", "PORO"],
    ];
    // "N triangles" of one mesh; "N triangles (of M in the scene)" in parts.
    let number_before = |s: &str, word: &str| -> usize {
        let before = s.split(word).next().unwrap_or_default();
        let number = before.rsplit(' ').next().unwrap_or_default();
        number
            .parse()
            .unwrap_or_else(|_| panic!("no number before {word:?}: {s}"))
    };
    for options in cases {
        let (whole, said_whole) = render("whole.png", options);
        let with_parts = [options, &["--part-cells", "500"]].concat();
        let (parts, said) = render("parts.png", &with_parts);
        let (Some(whole), Some(parts)) = (whole, parts) else {
            panic!("{options:?}:\n{said_whole}\n{said}");
        };
        let scene = number_before(&said_whole, " triangles");
        assert_eq!(number_before(&said, " in the scene"), scene, "{said}");
        // Faces wholly off the picture are left out: in the close-up, many.
        let in_view = number_before(&said, " triangles");
        if options.contains(&"--centre") {
            assert!(4 * in_view < 3 * scene, "{said}");
        } else {
            assert_eq!(in_view, scene, "{said}");
        }
        // At least a run or band of the tops per layer, the bottom, and the sides.
        let layers = match options {
            [.., "2..5", _, _, _] => 4,
            ["--layers", "3..3", ..] => 1,
            _ => 6,
        };
        let count = number_before(&said, " parts");
        assert!(count >= 2 * layers + 2, "{options:?}: {said}");
        assert!(said.contains(&format!(" of {count} parts")), "{said}");
        assert!(!said_whole.contains(" parts"), "{said_whole}");
        let background = whole.get_pixel(0, 0).0;
        let drawn = whole.pixels().filter(|p| p.0 != background).count();
        assert!(drawn > 10_000, "{options:?}: {drawn} pixels drawn");
        let differ = whole
            .pixels()
            .zip(parts.pixels())
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(differ, 0, "{options:?}: pixels drawn otherwise in parts");
    }
    // The fault traces in parts are the whole's, those on the borders of bands of rows
    // included (found across the border): the same pixels are red.
    let traced = |png: &str, options: &[&str]| {
        let png = dir.path().join(png);
        let out = Command::new(env!("CARGO_BIN_EXE_strata"))
            .args(["render", sample, "--sides", "--size", "320x240", "-o"])
            .arg(&png)
            .args(options)
            .output()
            .expect("the strata binary runs");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let picture = strata::render::image::open(&png).expect("a PNG").to_rgba8();
        picture
            .pixels()
            .map(|p| p[0] > p[1].saturating_add(60) && p[0] > p[2].saturating_add(60))
            .collect::<Vec<bool>>()
    };
    let whole = traced("traced-whole.png", &[]);
    let parts = traced("traced-parts.png", &["--part-cells", "500"]);
    let count = |red: &[bool]| red.iter().filter(|&&r| r).count();
    let both = whole.iter().zip(&parts).filter(|(a, b)| **a && **b).count();
    let (in_whole, in_parts) = (count(&whole), count(&parts));
    eprintln!("fault trace pixels: {in_whole} whole, {in_parts} in parts, {both} in both");
    assert!(
        in_whole > 500
            && both as f64 > 0.95 * in_whole as f64
            && both as f64 > 0.9 * in_parts as f64,
        "fault trace pixels: {in_whole} whole, {in_parts} in parts, {both} in both"
    );
    for (options, refused) in [
        (
            &["--wire", "bias"][..],
            "--wire bias draws the whole scene at once",
        ),
        (
            &["--wire", "dist", "--hidden", "tehd"],
            "--hidden tehd needs the whole scene",
        ),
        (&["--lod", "10"], "`strata lod build`"),
    ] {
        let (picture, said) = render("refused.png", &[options, &["--part-cells", "500"]].concat());
        assert!(picture.is_none(), "{options:?} drew in parts");
        assert!(
            said.contains(refused) && said.contains("--part-cells 500"),
            "{said}"
        );
        let (picture, said) = render("whole.png", options);
        assert!(picture.is_some(), "{options:?} in one part: {said}");
    }
}

/// Work far beyond the machine's memory (a generated model, a generated terrain) is
/// refused before anything is allocated, naming what it needs and what there is,
/// instead of aborting in the allocator or growing until the OOM killer ends it.
#[cfg(target_os = "linux")]
#[test]
fn work_beyond_the_memory_there_is_is_refused_before_it_starts() {
    use std::process::Command;

    let dir = tempfile::tempdir().expect("a temporary folder");
    let cases = [
        (
            vec!["synth", "--nx", "100000", "--ny", "100000", "--nz", "100"],
            "huge.egrid",
            "100000 x 100000 x 100 cells need about 48000.0 GB to generate",
        ),
        (
            vec!["terrain", "--generate", "1000000000"],
            "huge.png",
            "1000000000 picks need about 400.0 GB to triangulate",
        ),
    ];
    for (args, file, need) in cases {
        let out = dir.path().join(file);
        let run = Command::new(env!("CARGO_BIN_EXE_strata"))
            .args(&args)
            .arg("-o")
            .arg(&out)
            .output()
            .expect("the strata binary runs");
        let said = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{args:?}: {said}");
        assert!(
            said.contains(need) && said.contains("GB of memory is available"),
            "{said}"
        );
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
}

/// One stray depth in an active cell (a corrupt value of 1e11 m) would stretch the
/// model's extent until the rest is a speck: every command that reads the model names
/// the cell; `render`, drawing the model whole or in parts, and `lod view` of its
/// hierarchy frame the rest of it (the faces that reach the stray corner run out of
/// the picture), which then covers about what the sound model's picture does. A
/// picture of the background alone says why.
#[test]
fn a_stray_corner_is_named_and_render_frames_the_rest_of_the_model() {
    use strata::grid::synth::{SynthParams, generate};

    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut grid = generate(&SynthParams {
        nx: 12,
        ny: 10,
        nz: 2,
        faults: 1,
        seed: 3,
    })
    .expect("a synthetic grid");
    let sound = dir.path().join("sound.grdecl");
    strata::grid::save(&grid, &sound).expect("written");
    let (_, j, i) = grid
        .actnum
        .indexed_iter()
        .find_map(|(at, &active)| active.then_some(at))
        .expect("an active cell");
    grid.zcorn[[0, 2 * j, 2 * i]] = 1e11;
    let stray = dir.path().join("stray.grdecl");
    strata::grid::save(&grid, &stray).expect("written");

    let succeed = |args: &[&str]| {
        let (ok, said, _) = strata(args);
        assert!(ok, "{args:?}: {said}");
        said
    };
    let path = |p: &std::path::Path| p.to_str().expect("a UTF-8 path").to_string();
    let (sound, stray) = (path(&sound), path(&stray));
    let png = path(&dir.path().join("picture.png"));
    // Pixels the model covers, against the white background.
    let covered = || {
        let picture = strata::render::image::open(&png).expect("a PNG").to_rgba8();
        picture.pixels().filter(|p| p.0 != [255; 4]).count()
    };
    // A picture without the legend, which would count among those pixels.
    let draw = |args: &[&str]| {
        succeed(&[args, &["--size", "200x150", "--no-legend", "-o", &png]].concat())
    };
    let note = "the background alone, no part of the model covers a pixel";
    // The cell to mend is named (1-based), with its corner and pillar.
    let named = format!(
        "cell {},{},1 has a corner (number 0, on pillar {},{}) at x",
        i + 1,
        j + 1,
        i + 1,
        j + 1
    );
    let (ok, _, listed) = strata(&["info", &sound]);
    assert!(ok && !listed.contains("far outside"), "{listed}");
    let (ok, _, listed) = strata(&["info", &stray]);
    assert!(ok && listed.contains(&named), "{listed}");
    assert!(
        listed.contains("depth 99999997952.00, far outside"),
        "{listed}"
    );

    let said = draw(&["render", &sound]);
    assert!(
        !said.contains(note) && !said.contains("far outside"),
        "{said}"
    );
    let whole = covered();
    assert!(whole > 200 * 150 / 10, "{whole} pixels of the sound model");
    for options in [&[][..], &["--part-cells", "100"]] {
        let said = draw(&[&["render", &stray][..], options].concat());
        assert!(
            said.contains(&named) && !said.contains(note),
            "{options:?}: {said}"
        );
        let drawn = covered();
        assert!(
            drawn as f64 > 0.8 * whole as f64 && (drawn as f64) < 1.25 * whole as f64,
            "{options:?}: {drawn} pixels against the sound model's {whole}"
        );
    }
    // Decimated, the budget is split by what the views that frame the rest show, as
    // without the stray corner (with its faces counted, every surface was 0 % seen).
    let decimated = |model: &str| {
        let said = draw(&["render", model, "--lod", "10"]);
        let shares = said.find("shares").map(|at| said[at..].lines().next());
        (shares.flatten().map(str::to_string), covered())
    };
    let (sound_shares, whole) = decimated(&sound);
    let (shares, drawn) = decimated(&stray);
    assert!(
        shares.is_some() && shares == sound_shares,
        "{shares:?} against {sound_shares:?}"
    );
    assert!(
        drawn as f64 > 0.8 * whole as f64 && (drawn as f64) < 1.25 * whole as f64,
        "--lod: {drawn} pixels against the sound model's {whole}"
    );
    let lod = path(&dir.path().join("stray.lod"));
    let said = succeed(&["lod", "build", &stray, "-o", &lod]);
    assert!(said.contains(&named), "{said}");
    let sound_lod = path(&dir.path().join("sound.lod"));
    succeed(&["lod", "build", &sound, "-o", &sound_lod]);
    // The hierarchy keeps the box views frame, and says so.
    let framed = "the model has stray corners, which views leave out";
    let (ok, _, listed) = strata(&["info", &lod]);
    assert!(ok && listed.contains(framed), "{listed}");
    let (ok, _, listed) = strata(&["info", &sound_lod]);
    assert!(ok && !listed.contains(framed), "{listed}");
    for wire in ["global", "dist"] {
        let view = |lod: &str| {
            let said = draw(&["lod", "view", lod, "--wire", wire]);
            (said, covered())
        };
        let (said, whole) = view(&sound_lod);
        assert!(
            !said.contains(note) && whole > 200 * 150 / 10,
            "{wire}: {said}"
        );
        let (said, drawn) = view(&lod);
        assert!(
            !said.contains(note)
                && drawn as f64 > 0.8 * whole as f64
                && (drawn as f64) < 1.25 * whole as f64,
            "{wire}: {drawn} pixels against the sound hierarchy's {whole}: {said}"
        );
    }
    // Seen from so far that the model covers no pixel, the picture says why.
    let said = draw(&["lod", "view", &lod, "--view", "30,35,1e6"]);
    assert!(said.contains(note) && covered() == 0, "{said}");
    assert!(!said.contains("hidden behind"), "{said}");
}

/// A first run as a newcomer makes it, on a machine without a display or
/// `XDG_RUNTIME_DIR`: a picture, and no line on standard error that says "error".
#[test]
fn a_first_run_without_a_display_prints_no_error() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let png = dir.path().join("strata.png");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_strata"))
        .args(["render", "--sides", "--size", "300x200", "-o"])
        .arg(&png)
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("NODEVICE_SELECT")
        .output()
        .expect("the strata binary runs");
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{said}");
    assert!(png.exists());
    assert!(
        !said
            .lines()
            .any(|l| l.to_ascii_lowercase().contains("error")),
        "{said}"
    );
}
