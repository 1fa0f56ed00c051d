//! Isolines of f = x² + y² on a tilted plane with map grid lines, with the range
//! adjust off and on, beside the marching-triangles baseline:
//! `cargo run --release --example isolines -- OUT_DIR`.

use std::path::PathBuf;

use strata::grid::SurfaceMesh;
use strata::render::contour::{ContourTechnique, levels, marching_triangles};
use strata::render::glam::Vec3;
use strata::render::{
    Camera, GridLines, IsolineOptions, Isolines, RangeAdjust, Renderer, Style, View,
};

fn main() -> anyhow::Result<()> {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    std::fs::create_dir_all(&out)?;
    // 100 m x 100 m, 20 x 20 cells; the field is flat at the centre.
    let mut mesh = SurfaceMesh::structured(20, 20, |i, j| {
        [i as f32 * 5.0 - 50.0, j as f32 * 5.0 - 50.0, 0.0]
    });
    mesh.scalars = mesh
        .positions
        .iter()
        .map(|p| p[0] * p[0] + p[1] * p[1])
        .collect();
    let mut renderer = Renderer::headless()?;
    eprintln!("adapter: {}", renderer.gpu.describe());
    let bounds = (Vec3::new(-50.0, -50.0, 0.0), Vec3::new(50.0, 50.0, 0.0));
    let view = View {
        camera: Camera::fit(bounds.0, bounds.1, 1.0, 4.0 / 3.0, (20.0, 55.0), 1.0),
        width: 800,
        height: 600,
        bounds,
    };
    let isolines = Isolines {
        major_every: 4,
        ..Isolines::new(250.0)
    };
    let style = Style {
        thickness: 2.0,
        wire_color: [1.0, 1.0, 1.0, 0.35],
        scalar_range: Some((0.0, 5000.0)),
        isolines: Some(isolines),
        grid_lines: Some(GridLines {
            color: [0.9, 0.3, 0.1, 0.9],
            ..GridLines::new(25.0, [0.0, 0.0])
        }),
        ..Style::default()
    };
    for (name, adjust) in RangeAdjust::ALL {
        let drawable =
            renderer.prepare_isolines(&mesh, None, IsolineOptions { adjust, wire: true })?;
        let image = renderer.render(&[drawable.as_ref()], &view, &style)?;
        let path = out.join(format!("isolines-adjust-{name}.png"));
        strata::render::save_png(&image, &path)?;
        eprintln!("wrote {}", path.display());
    }
    // The baseline: the plain surface, then contour polylines as line primitives.
    let surface = renderer.prepare_isolines(&mesh, None, IsolineOptions::default())?;
    let lines = marching_triangles(&mesh, &mesh.scalars, &levels(&isolines, 0.0, 5000.0, 1000));
    let contours = ContourTechnique::new(&renderer.context()).prepare(&renderer.gpu, &lines)?;
    let plain = Style {
        isolines: None,
        ..style.clone()
    };
    // The contour pipeline takes its colour from the isolines' uniform.
    let image = renderer.render(
        &[surface.as_ref(), &contours],
        &view,
        &Style {
            isolines: Some(Isolines {
                color: [0.02, 0.02, 0.02, 1.0],
                ..isolines
            }),
            ..plain
        },
    )?;
    let path = out.join("isolines-marching-triangles.png");
    strata::render::save_png(&image, &path)?;
    eprintln!("wrote {}", path.display());
    Ok(())
}
