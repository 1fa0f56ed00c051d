//! A planar structured grid drawn with each texture-based wireframe mode, over a
//! shaded surface and in isolation: `cargo run --release --example wire_plane -- OUT_DIR`.

use std::path::PathBuf;

use strata::grid::SurfaceMesh;
use strata::render::{Camera, Renderer, Style, View, WireMode};

fn main() -> anyhow::Result<()> {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    std::fs::create_dir_all(&out)?;
    let mut mesh = SurfaceMesh::structured(24, 16, |i, j| {
        [i as f32 * 10.0 - 120.0, j as f32 * 10.0 - 80.0, 0.0]
    });
    mesh.scalars = mesh
        .positions
        .iter()
        .map(|p| (p[0] * 0.02).sin() + p[1] * 0.01)
        .collect();
    let mut renderer = Renderer::headless()?;
    eprintln!("adapter: {}", renderer.gpu.describe());
    let bounds = (
        strata::render::glam::Vec3::new(-120.0, -80.0, 0.0),
        strata::render::glam::Vec3::new(120.0, 80.0, 0.0),
    );
    let view = View {
        camera: Camera::fit(bounds.0, bounds.1, 1.0, 800.0 / 600.0, (20.0, 50.0), 1.0),
        width: 800,
        height: 600,
        bounds,
    };
    for mode in WireMode::ALL {
        let drawable = renderer.prepare(&mesh, mode)?;
        for isolation in [false, true] {
            let style = Style {
                thickness: 2.0,
                coverage: if std::env::var("ANALYTIC").is_ok() {
                    strata::render::Coverage::Analytic
                } else {
                    strata::render::Coverage::Texture
                },
                isolation,
                scalar_range: Some((-1.0, 2.0)),
                background: if isolation {
                    [0.0, 0.0, 0.0, 1.0]
                } else {
                    [1.0; 4]
                },
                ..Style::default()
            };
            let image = renderer.render(&[drawable.as_ref()], &view, &style)?;
            let name = format!(
                "{}-{}.png",
                mode.name(),
                if isolation { "isolated" } else { "shaded" }
            );
            strata::render::save_png(&image, &out.join(&name))?;
            eprintln!("wrote {}", out.join(name).display());
        }
    }
    Ok(())
}
