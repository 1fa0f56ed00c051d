//! strata-render: wgpu rendering of strata surfaces with texture-based wireframes
//! (Celes & Abraham) and the techniques they are measured against (DESIGN.md
//! section 3). Headless by default; frames come back as RGBA pixels and PNG files.
//!
//! A [`Renderer`] uploads a mesh once for a [`WireMode`] (the techniques' table is
//! [`wire::TECHNIQUES`]) and draws it for any [`View`] and [`Style`]:
//!
//! ```
//! use strata_grid::synth::{SynthParams, generate};
//! use strata_grid::{Face, Surfaces, layer_surfaces};
//! use strata_render::glam::Vec3;
//! use strata_render::{Framing, Renderer, Style, View, WireMode};
//!
//! let grid = generate(&SynthParams { nx: 12, ny: 8, nz: 1, faults: 0, seed: 1 })?;
//! let mesh = layer_surfaces(&grid, Face::Top, &Surfaces::layer(0, grid.display_origin()))?;
//! let mut renderer = Renderer::headless()?;
//! let drawable = renderer.prepare(&mesh, WireMode::Global)?;
//! // Seen from straight above, framed on the mesh.
//! let mut framing = Framing::new(1.0, 4.0 / 3.0, (0.0, 90.0));
//! framing.add(mesh.positions.iter().map(|&p| Vec3::from(p)));
//! let bounds = framing.bounds().ok_or("an empty mesh")?;
//! let view = View { camera: framing.camera(1.0), width: 320, height: 240, bounds };
//! let image = renderer.render(&[drawable.as_ref()], &view, &Style::default())?;
//! // The surface covers the middle of the picture, the background the corner, and
//! // the cell lines darken pixels between them.
//! let luma = |x, y| image.get_pixel(x, y).0[..3].iter().map(|&c| u32::from(c)).sum::<u32>();
//! assert_eq!(luma(0, 0), 3 * 255);
//! assert!(image.pixels().any(|p| p.0[..3].iter().all(|&c| c < 60)));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod camera;
pub mod contour;
mod error;
mod gpu;
mod gridlines;
mod isoline;
mod overlay;
mod renderer;
mod scale;
mod style;
mod timing;
mod visibility;
pub mod wire;

pub use camera::{Camera, Framing};
pub use error::{Error, Result};
/// The vector crate of the public API (cameras and bounds are `glam` types).
pub use glam;
pub use gpu::Gpu;
pub use gridlines::GridLines;
/// The image crate of the public API (frames are `image::RgbaImage`).
pub use image;
pub use isoline::{IsolineOptions, Isolines, RangeAdjust};
pub use overlay::overlay_origin;
pub use renderer::sampling::{SHARE_SIZE, SHARE_VIEWS, Sampling};
pub use renderer::{Output, Renderer, View};
pub use scale::{CATEGORICAL, Scale, categorical_colour};
pub use style::{Colormap, Coverage, FaultLines, HiddenLines, MajorLines, Style, parse_color};
pub use timing::{FrameTime, FrameTimer};
/// The graphics crate of the public API (`Gpu` holds its device and adapter info).
pub use wgpu;
pub use wire::{
    Attenuation, CellDraw, Stacking, TiledCells, WireMode, stack_pushes, wire_mode_names,
};

/// Writes pixels as a PNG file.
pub fn save_png(image: &image::RgbaImage, path: &std::path::Path) -> Result<()> {
    image.save(path).map_err(|e| Error::Output {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}
