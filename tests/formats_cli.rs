//! `strata render`, `strata lod build` and `strata info` take ROFF, formatted Eclipse,
//! GRID and Intersect files as they take an EGRID, and `--props` a ROFF parameter file.
//! Skipped (with a message) when `../shared/data` is absent.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn strata(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_strata"))
        .args(args)
        .output()
        .expect("the strata binary runs")
}

fn data() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data");
    if dir.is_dir() {
        Some(dir)
    } else {
        println!("skipping: ../shared/data not found");
        None
    }
}

fn ok(out: &Output, what: &str) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{what}: {err}");
    String::from_utf8_lossy(&out.stdout).into_owned() + &err
}

/// (model, property files, property to colour by; none: the GRID file has none)
const CASES: &[(&str, &[&str], Option<&str>)] = &[
    ("roff/b_grid.roff", &["roff/b_poro.roff"], Some("PORO")),
    ("roff/reek_grd_w_props.roffasc", &[], Some("PORO")),
    ("roff/emerald_bigend.roffbin", &[], Some("LAYER")),
    ("eclipse_variants/E100_BO.FEGRID", &[], Some("PORO")),
    ("eclipse_variants/B.GRID", &[], None),
    ("eclipse_variants/IX_BO.EGRID", &[], Some("PORO")),
];

#[test]
fn render_and_lod_build_take_every_format() {
    let Some(data) = data() else { return };
    let dir = tempfile::tempdir().expect("a temporary folder");
    for (model, props, property) in CASES {
        let path = data.join(model);
        let path = path.to_str().expect("UTF-8");
        let props: Vec<String> = props
            .iter()
            .map(|p| data.join(p).display().to_string())
            .collect();
        let png = dir.path().join("out.png");
        let mut args = vec![
            "render",
            path,
            "--size",
            "160x120",
            "-o",
            png.to_str().expect("UTF-8"),
        ];
        if let Some(property) = property {
            args.extend(["--property", property]);
        }
        props
            .iter()
            .for_each(|p| args.extend(["--props", p.as_str()]));
        ok(&strata(&args), &format!("render {model}"));
        assert!(png.is_file(), "{model}: no picture");
        let lod = dir.path().join("out.lod");
        let mut args = vec!["lod", "build", path, "-o", lod.to_str().expect("UTF-8")];
        match property {
            Some(property) => args.extend(["--property", property]),
            None => args.push("--no-property"),
        }
        props
            .iter()
            .for_each(|p| args.extend(["--props", p.as_str()]));
        ok(&strata(&args), &format!("lod build {model}"));
        std::fs::remove_file(&lod).expect("the hierarchy was written");
    }
}

#[test]
fn info_says_how_intersect_results_are_mapped() {
    let Some(data) = data() else { return };
    let path = data.join("eclipse_variants/IX_BO.EGRID");
    let printed = ok(&strata(&["info", path.to_str().expect("UTF-8")]), "info");
    assert!(printed.contains("mapped through PORV > 0"), "{printed}");
}
