//! strata-render: wgpu rendering of strata surfaces with texture-based wireframes
//! (Celes & Abraham) and the techniques they are measured against (DESIGN.md
//! section 3). Headless by default; frames come back as RGBA pixels and PNG files.

#![warn(missing_docs)]

mod camera;
pub mod contour;
mod error;
mod gpu;
mod gridlines;
mod isoline;
mod renderer;
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
pub use renderer::sampling::{SHARE_SIZE, SHARE_VIEWS, Sampling};
pub use renderer::{Renderer, View};
pub use style::{Colormap, Coverage, HiddenLines, Style, parse_color};
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
