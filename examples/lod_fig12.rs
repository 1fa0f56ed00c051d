//! Celes & Abraham 2011, Fig. 12: the original wireframe drawn on a decimated
//! reservoir surface. Writes three pictures of the top layer of a model:
//!
//! * `fig12a-original.png`: the original mesh with its wireframe (global coordinates);
//! * `fig12b-decimated.png`: the decimated mesh with its own wireframe (`texgs`: the
//!   edges of its triangles);
//! * `fig12c-original-wireframe.png`: the decimated mesh with the original wireframe
//!   (global coordinates, interpolated at the vertices decimation created).
//!
//! `cargo run --release --example lod_fig12 -- OUT_DIR [MODEL] [PERCENT]`; the model
//! defaults to Reek from ../shared/data (a generated faulted model when that is
//! absent) and the share of triangles kept to 10 %.

use std::path::PathBuf;

use strata::grid::synth::{SynthParams, generate};
use strata::grid::{Face, ReadOptions, Surfaces, layer_surfaces};
use strata::lod::{Options, decimate};
use strata::render::glam::Vec3;
use strata::render::{Camera, Renderer, Style, View, WireMode};

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().unwrap_or_else(|| ".".into()));
    let model = args.next().map(PathBuf::from).unwrap_or_else(|| {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/reek/REEK.EGRID")
    });
    let percent: f64 = args.next().map_or(Ok(10.0), |p| p.parse())?;
    std::fs::create_dir_all(&out)?;

    let grid = if model.exists() {
        let options = ReadOptions {
            grid_only: true,
            ..ReadOptions::default()
        };
        strata::grid::open_with(&model, &options)?
    } else {
        eprintln!(
            "{} not found: using a generated faulted model",
            model.display()
        );
        generate(&SynthParams {
            nx: 60,
            ny: 40,
            nz: 1,
            faults: 4,
            seed: 1,
        })?
    };
    let original = layer_surfaces(&grid, Face::Top, &Surfaces::layer(0, grid.display_origin()))?;
    let z_scale = 5.0;
    let options = Options {
        z_scale,
        ..Options::fraction(&original, percent / 100.0)
    };
    let decimated = decimate(&original, &options)?;
    eprintln!(
        "{}: top layer {} -> {} triangles ({:.1} %), error {:.2}",
        model.display(),
        original.triangle_count(),
        decimated.mesh.triangle_count(),
        100.0 * decimated.mesh.triangle_count() as f64 / original.triangle_count() as f64,
        decimated.error
    );

    let mut renderer = Renderer::headless()?;
    let (lo, hi) = original
        .bounds()
        .ok_or_else(|| anyhow::anyhow!("empty layer"))?;
    let bounds = (Vec3::from(lo), Vec3::from(hi));
    let (width, height) = (1000, 800);
    let view = View {
        camera: Camera::fit_points(
            original.positions.iter().map(|&p| Vec3::from(p)),
            z_scale,
            width as f32 / height as f32,
            (20.0, 40.0),
            1.0,
        ),
        width,
        height,
        bounds,
    };
    let style = Style::default();
    for (name, mesh, mode) in [
        ("fig12a-original.png", &original, WireMode::Global),
        ("fig12b-decimated.png", &decimated.mesh, WireMode::TexGs),
        (
            "fig12c-original-wireframe.png",
            &decimated.mesh,
            WireMode::Global,
        ),
    ] {
        let drawable = renderer.prepare(mesh, mode)?;
        let image = renderer.render(&[drawable.as_ref()], &view, &style)?;
        let path = out.join(name);
        strata::render::save_png(&image, &path)?;
        eprintln!(
            "wrote {} ({} wireframe, {} triangles)",
            path.display(),
            mode.name(),
            mesh.triangle_count()
        );
    }
    Ok(())
}
