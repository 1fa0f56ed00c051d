//! Frames: the shared uniforms and textures, targets, and readback to RGBA pixels.

pub(crate) mod sampling;

use std::collections::HashMap;

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};
use image::RgbaImage;
use strata_grid::SurfaceMesh;

use crate::isoline::{IsolineOptions, IsolineTechnique, RangeAdjust};
use crate::overlay::Overlay;
use crate::timing::{FrameTime, FrameTimer};
use crate::wire::{
    self, COLOR_FORMAT, CellDraw, DEPTH_FORMAT, Drawable, FrameProjection, FrameTargets,
    PipelineContext, Technique, WireMode, WireTextureSpec,
};
use crate::{Camera, Colormap, Coverage, Error, Gpu, HiddenLines, Result, Scale, Style};

/// What a drawn frame leaves behind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// Its pixels, read back to memory: files, tests, screenshots.
    Pixels,
    /// Only the frame texture ([`Renderer::frame_texture`]), which a window shows
    /// without the wait and copy of a readback.
    Texture,
}

/// What to look at: camera, image size, and the scene's bounds (unscaled display
/// frame) from which the depth range is fitted.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// Where the frame looks from.
    pub camera: Camera,
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// The scene's bounds (unscaled display frame), from which the depth range is fitted.
    pub bounds: (Vec3, Vec3),
}

impl View {
    /// The frame's projection as the shaders apply it: the vertical exaggeration, then
    /// the view and projection, the depth range fitted to the bounds.
    pub fn projection(&self) -> FrameProjection {
        let cam = &self.camera;
        let (near, far) = cam.depth_range(self.bounds.0, self.bounds.1);
        let aspect = self.width as f32 / self.height.max(1) as f32;
        FrameProjection {
            view_proj: cam.projection(aspect, near, far) * cam.view(),
            z_scale: cam.z_scale,
            eye: cam.eye,
            size: Vec2::new(self.width as f32, self.height as f32),
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FrameUniforms {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    light: [f32; 4],
    wire_color: [f32; 4],
    solid_color: [f32; 4],
    viewport: [f32; 4],
    line: [f32; 4],
    atten: [f32; 4],
    scalar: [f32; 4],
    // Isolines and map grid lines (isoline.rs, gridlines.rs); w = 0: not drawn.
    iso: [f32; 4],
    iso_color: [f32; 4],
    grid: [f32; 4],
    grid_color: [f32; 4],
    // Major cell lines (style.rs, `MajorLines`); x = 0: none.
    major: [f32; 4],
    major_color: [f32; 4],
    // Fault traces (wire/faults.rs); x = 0: none.
    faults: [f32; 4],
    fault_color: [f32; 4],
}

impl FrameUniforms {
    fn new(view: &View, style: &Style, layers: u32) -> Self {
        let cam = &view.camera;
        let (near, far) = cam.depth_range(view.bounds.0, view.bounds.1);
        // Light from behind the viewer's right shoulder and above.
        let forward = (cam.target - cam.eye).normalize_or(Vec3::NEG_Z);
        let right = forward.cross(cam.up).normalize_or(Vec3::X);
        let light = (-forward + 0.4 * right + 0.6 * cam.up).normalize_or(Vec3::Z);
        // Attenuation spans the scene's depth as seen from the eye.
        let (a_near, a_far) = (near, far.max(near * 1.0001));
        FrameUniforms {
            // The shader applies the vertical exaggeration itself (`world` in common.wgsl,
            // which also feeds lighting and attenuation), so no model matrix here.
            view_proj: view.projection().view_proj.to_cols_array_2d(),
            eye: [cam.eye.x, cam.eye.y, cam.eye.z, cam.z_scale],
            light: [light.x, light.y, light.z, 0.35],
            wire_color: style.wire_color,
            solid_color: style.solid_color,
            viewport: [
                view.width as f32,
                view.height as f32,
                1.0 / view.width as f32,
                1.0 / view.height as f32,
            ],
            line: [
                style.thickness,
                style.cap,
                if style.coverage == Coverage::Analytic {
                    1.0
                } else {
                    0.0
                },
                if style.isolation { 1.0 } else { 0.0 },
            ],
            atten: [
                a_near,
                1.0 / (a_far - a_near),
                style.attenuation.code(),
                layers as f32,
            ],
            scalar: style.scale.uniform(style.scalar_range),
            iso: style.isolines.map_or([0.0; 4], |i| i.uniform()),
            iso_color: style.isolines.map_or([0.0; 4], |i| i.color),
            grid: style.grid_lines.map_or([0.0; 4], |g| g.uniform()),
            grid_color: style.grid_lines.map_or([0.0; 4], |g| g.color),
            major: style
                .major
                .map_or([0.0; 4], |m| [m.every as f32, m.fade, 0.0, 0.0]),
            major_color: style.major.map_or([0.0; 4], |m| m.color),
            faults: style
                .faults
                .map_or([0.0; 4], |f| [f.thickness, 0.0, 0.0, 0.0]),
            fault_color: style.faults.map_or([0.0; 4], |f| f.color),
        }
    }
}

struct Targets {
    width: u32,
    height: u32,
    color: wgpu::Texture,
    color_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    readback: wgpu::Buffer,
    padded_row: u32,
}

/// Draws prepared meshes into offscreen frames.
pub struct Renderer {
    /// The device, for callers that prepare their own drawables.
    pub gpu: Gpu,
    frame_layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    wire_sampler: wgpu::Sampler,
    colormap_sampler: wgpu::Sampler,
    wire_spec: WireTextureSpec,
    wire_view: wgpu::TextureView,
    colormap: (Colormap, Scale),
    colormap_view: wgpu::TextureView,
    bind_group: wgpu::BindGroup,
    techniques: HashMap<WireMode, Box<dyn Technique>>,
    isolines: Option<IsolineTechnique>,
    /// Without and with the mask, then both without the wire.
    cells: [Option<wire::CellTechnique>; 4],
    /// Draws fault traces given as segments (a hierarchy's).
    edges: Option<wire::EdgePipelines>,
    targets: Option<Targets>,
    /// Blended over the end of every frame (the colour legend).
    overlay: Option<Overlay>,
}

/// A renderer moves between threads (a viewer's render thread; a test binary's one
/// renderer, lent to its tests in turn).
const _: fn() = || {
    fn send<T: Send>() {}
    send::<Renderer>();
};

/// The one renderer of a unit-test binary, lent to one test at a time. Tests that each
/// open a device and drop it while others draw hung NVIDIA's Vulkan driver (580, on
/// an H200): `vkDestroyDevice` deadlocked with other threads' submissions.
#[cfg(test)]
pub(crate) fn test_renderer() -> std::sync::MutexGuard<'static, Renderer> {
    static SHARED: std::sync::OnceLock<std::sync::Mutex<Renderer>> = std::sync::OnceLock::new();
    SHARED
        .get_or_init(|| std::sync::Mutex::new(Renderer::headless().expect("renderer")))
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// `f`, with a GPU validation error it raises returned as an error.
fn validated<T>(gpu: &Gpu, f: impl FnOnce() -> Result<T>) -> Result<T> {
    let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let result = f();
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(Error::Gpu(e.to_string()));
    }
    result
}

impl Renderer {
    /// Sets up the shared frame state on `gpu`; techniques are built on first use.
    pub fn new(gpu: Gpu) -> Result<Self> {
        let device = &gpu.device;
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    // Compute too: the isoline range adjust projects triangles.
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT
                        .union(wgpu::ShaderStages::COMPUTE),
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                texture_entry(1, wgpu::TextureViewDimension::D2Array),
                sampler_entry(2),
                texture_entry(3, wgpu::TextureViewDimension::D2),
                sampler_entry(4),
            ],
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame uniforms"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        // Mirrored repeat puts a line at every odd coordinate (global, quad) and
        // behaves as clamping on [0, 1] (tex, texgs).
        let wire_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("wireframe"),
            address_mode_u: wgpu::AddressMode::MirrorRepeat,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let colormap_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("colour map"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let wire_spec = WireTextureSpec::default();
        let wire_view =
            wire_spec
                .upload(device, &gpu.queue)
                .create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2Array),
                    ..Default::default()
                });
        let colormap = (Colormap::default(), Scale::default());
        let colormap_view = upload_colormap(&gpu, &colormap.1.table(colormap.0));
        let bind_group = make_bind_group(
            &gpu,
            &frame_layout,
            &uniforms,
            &wire_view,
            &wire_sampler,
            &colormap_view,
            &colormap_sampler,
        );
        Ok(Renderer {
            gpu,
            frame_layout,
            uniforms,
            wire_sampler,
            colormap_sampler,
            wire_spec,
            wire_view,
            colormap,
            colormap_view,
            bind_group,
            techniques: HashMap::new(),
            isolines: None,
            cells: [None, None, None, None],
            edges: None,
            targets: None,
            overlay: None,
        })
    }

    /// Blends `image` (RGBA8, straight alpha; `None`: nothing) over the end of every
    /// frame from now on, one texel per pixel at the frame's right edge, vertically
    /// centred: the colour legend. It is drawn into the frame's target, so it is in
    /// what [`Renderer::render`] reads back and in the target a window shows.
    pub fn set_overlay(&mut self, image: Option<&RgbaImage>) {
        self.overlay = image.map(|image| Overlay::new(&self.gpu, image));
    }

    /// Records the overlay's pass over the frame, if there is one.
    fn encode_overlay(&self, encoder: &mut wgpu::CommandEncoder) -> Result<()> {
        let targets = self
            .targets
            .as_ref()
            .ok_or_else(|| Error::Gpu("no render targets".into()))?;
        if let Some(overlay) = &self.overlay {
            let size = (targets.width, targets.height);
            overlay.encode(&self.gpu, encoder, &targets.color_view, size);
        }
        Ok(())
    }

    /// Opens the best adapter (see [`Gpu::new`]) and a renderer on it.
    pub fn headless() -> Result<Self> {
        Self::new(Gpu::new()?)
    }

    /// Uploads `mesh` for drawing with `mode` (retained mode). The texture techniques
    /// but `none` draw, after the surface, the outer half of its outline's lines and
    /// its fault traces.
    pub fn prepare(&mut self, mesh: &SurfaceMesh, mode: WireMode) -> Result<Box<dyn Drawable>> {
        self.prepare_band(mesh, mode, Some(&[]))
    }

    /// [`Renderer::prepare`] for a mesh cut from its surface along the lines of
    /// constant j at the node rows `cut_rows` (a band of rows of a larger layer):
    /// there it has no outline, the surface going on. `None`: no outline at all, side
    /// walls drawn apart carrying the lines there.
    pub fn prepare_band(
        &mut self,
        mesh: &SurfaceMesh,
        mode: WireMode,
        cut_rows: Option<&[u32]>,
    ) -> Result<Box<dyn Drawable>> {
        self.ensure_technique(mode);
        self.build_edge_pipelines();
        let technique = &self.techniques[&mode];
        let edges = self.edges.as_ref();
        validated(&self.gpu, || {
            let draw = technique.prepare(&self.gpu, mesh)?;
            // The shaded surface alone draws no lines at all.
            Ok(match edges {
                Some(edges) if mode.draws_edges() => {
                    Box::new(wire::Edged::new(&self.gpu, draw, mesh, edges, cut_rows))
                }
                _ => draw,
            })
        })
    }

    /// Uploads a decimated `mesh` for drawing with the global wireframe (without it
    /// unless `cells.wire`) against the cells of the surface it was simplified from,
    /// with the original's isolines where `cells.corners` are given: coloured cell by
    /// cell as the
    /// original's faces are (with `cells.values`), and with `cells.mask` only over the
    /// original's cells, so that a surface decimated with `strata_lod::Options::cover`
    /// draws the original's outlines, holes and fault traces. Cells of any number of
    /// pieces are drawn: more than one texture holds go in batches of pieces.
    pub fn prepare_cells(
        &mut self,
        mesh: &SurfaceMesh,
        cells: &CellDraw,
    ) -> Result<Box<dyn Drawable>> {
        validated(&self.gpu, || {
            let slot = usize::from(cells.mask) + 2 * usize::from(!cells.wire);
            let technique = self.cells[slot].get_or_insert_with(|| {
                wire::CellTechnique::new(
                    &PipelineContext {
                        gpu: &self.gpu,
                        frame_layout: &self.frame_layout,
                    },
                    cells.mask,
                    cells.wire,
                )
            });
            technique.prepare(&self.gpu, mesh, cells)
        })
    }

    /// Uploads fault trace `segments` (`strata_grid::faults`, in the display frame of
    /// the meshes they lie on) to draw in the fault style over what is drawn before
    /// them: a hierarchy's, stored at full resolution, whose nodes carry no cell faces
    /// to find them from. `None` when there are none.
    pub fn prepare_fault_traces(
        &mut self,
        segments: &[strata_grid::faults::Segment],
    ) -> Result<Option<Box<dyn Drawable>>> {
        self.build_edge_pipelines();
        let pipeline = self.edges.as_ref().map(|e| &e.faults);
        let traces = validated(&self.gpu, || {
            Ok(pipeline.and_then(|p| wire::FaultTraces::new(&self.gpu, segments, p)))
        })?;
        Ok(traces.map(|t| Box::new(t) as Box<dyn Drawable>))
    }

    /// Uploads outline `edges` (`strata_grid::outline`, in the display frame of the
    /// meshes they bound) to draw the outer half of their lines over what is drawn
    /// before them: those on the border of two bands of rows, which neither band
    /// finds alone. `None` when there are none.
    pub fn prepare_outline_edges(
        &mut self,
        edges: &[strata_grid::outline::OutlineEdge],
    ) -> Result<Option<Box<dyn Drawable>>> {
        self.prepare_border_edges(edges, None)
    }

    /// [`Renderer::prepare_outline_edges`], with the silhouettes among `shared`: sides
    /// two faces of `mesh` share (`strata_grid::outline::surface_edges`), those on the
    /// border of two bands of rows, found on a strip of rows across it.
    pub fn prepare_border_edges(
        &mut self,
        edges: &[strata_grid::outline::OutlineEdge],
        shared: Option<(&SurfaceMesh, &[strata_grid::outline::InteriorEdge])>,
    ) -> Result<Option<Box<dyn Drawable>>> {
        self.build_edge_pipelines();
        let pipeline = self.edges.as_ref().map(|e| &e.outline);
        let silhouettes = shared.and_then(|(mesh, shared)| wire::Silhouettes::new(mesh, shared));
        let lines = validated(&self.gpu, || {
            Ok(pipeline.and_then(|p| wire::OutlineLines::new(&self.gpu, edges, silhouettes, p)))
        })?;
        Ok(lines.map(|l| Box::new(l) as Box<dyn Drawable>))
    }

    /// What a technique outside the wire registry (e.g. the contour baseline) needs
    /// to build pipelines that draw into this renderer's frames.
    pub fn context(&self) -> PipelineContext<'_> {
        PipelineContext {
            gpu: &self.gpu,
            frame_layout: &self.frame_layout,
        }
    }

    /// Uploads `mesh` for drawing with range-adjusted isolines (isoline.rs): the
    /// shaded surface, the isolines of `field` (3 values per triangle, one per corner,
    /// in triangle order; `None`: `mesh.scalars`) and, with `options.wire`, the
    /// wireframe of the global coordinates. The frame's `Style::isolines` says which
    /// lines; without it only the surface (and wire) is drawn.
    pub fn prepare_isolines(
        &mut self,
        mesh: &SurfaceMesh,
        field: Option<&[f32]>,
        options: IsolineOptions,
    ) -> Result<Box<dyn Drawable>> {
        self.prepare_isolines_band(mesh, field, options, Some(&[]))
    }

    /// [`Renderer::prepare_isolines`] for a band of rows, as [`Renderer::prepare_band`].
    pub fn prepare_isolines_band(
        &mut self,
        mesh: &SurfaceMesh,
        field: Option<&[f32]>,
        options: IsolineOptions,
        cut_rows: Option<&[u32]>,
    ) -> Result<Box<dyn Drawable>> {
        let scope = self
            .gpu
            .device
            .push_error_scope(wgpu::ErrorFilter::Validation);
        let technique = match self.isolines.take() {
            Some(t) => t,
            None => IsolineTechnique::new(&PipelineContext {
                gpu: &self.gpu,
                frame_layout: &self.frame_layout,
            }),
        };
        let prepared = technique.prepare(&self.gpu, mesh, field, options);
        self.isolines = Some(technique);
        // With the traces of the mesh's faults and, with the wireframe, its outline,
        // as the wireframe techniques draw them.
        self.build_edge_pipelines();
        let faulted: Result<Box<dyn Drawable>> = match (prepared, &self.edges) {
            (Ok(draw), Some(edges)) => Ok(Box::new(wire::Edged::new(
                &self.gpu,
                Box::new(draw),
                mesh,
                edges,
                cut_rows.filter(|_| options.wire),
            ))),
            (Ok(draw), None) => Ok(Box::new(draw)),
            (Err(e), _) => Err(e),
        };
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(e.to_string()));
        }
        faulted
    }

    /// Builds the pipelines drawing fault traces and outline edges, once.
    fn build_edge_pipelines(&mut self) {
        if self.edges.is_none() {
            self.edges = Some(wire::EdgePipelines::new(&self.context()));
        }
    }

    /// Runs the isoline range adjust alone for `view` and `style` and returns the
    /// adjusted coordinate of every triangle corner (3 per triangle): what the
    /// isoline technique draws, for checking the adjust and timing it.
    pub fn isoline_coordinates(
        &mut self,
        mesh: &SurfaceMesh,
        field: Option<&[f32]>,
        adjust: RangeAdjust,
        view: &View,
        style: &Style,
    ) -> Result<Vec<f32>> {
        let technique = match self.isolines.take() {
            Some(t) => t,
            None => IsolineTechnique::new(&PipelineContext {
                gpu: &self.gpu,
                frame_layout: &self.frame_layout,
            }),
        };
        let prepared = technique.prepare(
            &self.gpu,
            mesh,
            field,
            IsolineOptions {
                adjust,
                wire: false,
            },
        );
        self.isolines = Some(technique);
        let draw = prepared?;
        self.set_frame(view, style)?;
        let size = draw.chunks.iter().map(|c| c.adjusted.size()).sum();
        let readback = self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("isoline coordinates readback"),
            size,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        draw.encode_prepass(&self.bind_group, &mut encoder);
        let mut at = 0;
        for chunk in &draw.chunks {
            let size = chunk.adjusted.size();
            encoder.copy_buffer_to_buffer(&chunk.adjusted, 0, &readback, at, size);
            at += size;
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.map_read(&readback)?;
        let slice = readback.slice(..);
        let values = bytemuck::cast_slice::<u8, f32>(
            &slice
                .get_mapped_range()
                .map_err(|e| Error::Gpu(e.to_string()))?,
        )
        .to_vec();
        Ok(values)
    }

    /// Creates the technique of `mode` on first use.
    fn ensure_technique(&mut self, mode: WireMode) {
        if !self.techniques.contains_key(&mode) {
            let ctx = PipelineContext {
                gpu: &self.gpu,
                frame_layout: &self.frame_layout,
            };
            let technique = wire::create(mode, &ctx);
            self.techniques.insert(mode, technique);
        }
    }

    /// Makes the shared textures match `style` and writes the frame uniforms.
    fn set_frame(&mut self, view: &View, style: &Style) -> Result<()> {
        if view.width == 0 || view.height == 0 {
            return Err(Error::Invalid(format!(
                "image size {}x{} is empty",
                view.width, view.height
            )));
        }
        if !(style.thickness >= 0.5 && style.thickness.is_finite()) {
            return Err(Error::Invalid(format!(
                "line thickness {} px: it must be a finite number of at least 0.5",
                style.thickness
            )));
        }
        if style.isolines.is_some_and(|i| i.validate().is_none()) {
            return Err(Error::Invalid(format!(
                "isolines {:?}: the spacing must be positive and finite",
                style.isolines
            )));
        }
        if style.grid_lines.is_some_and(|g| g.validate().is_none()) {
            return Err(Error::Invalid(format!(
                "grid lines {:?}: the spacing must be positive and the origins finite",
                style.grid_lines
            )));
        }
        let spec = WireTextureSpec {
            width: style
                .texture_width
                .next_power_of_two()
                .clamp(1, self.gpu.limits.max_texture_dimension_2d),
            thickness: style.thickness,
            cap: style.cap,
            attenuation: style.attenuation,
        };
        let mut rebind = false;
        if spec != self.wire_spec {
            self.wire_spec = spec;
            self.wire_view = spec.upload(&self.gpu.device, &self.gpu.queue).create_view(
                &wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2Array),
                    ..Default::default()
                },
            );
            rebind = true;
        }
        if (style.colormap, style.scale) != self.colormap {
            self.colormap = (style.colormap, style.scale);
            self.colormap_view = upload_colormap(&self.gpu, &style.scale.table(style.colormap));
            rebind = true;
        }
        if rebind {
            self.bind_group = make_bind_group(
                &self.gpu,
                &self.frame_layout,
                &self.uniforms,
                &self.wire_view,
                &self.wire_sampler,
                &self.colormap_view,
                &self.colormap_sampler,
            );
        }
        let uniforms = FrameUniforms::new(view, style, spec.layers());
        self.gpu
            .queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&uniforms));
        if self
            .targets
            .as_ref()
            .is_none_or(|t| t.width != view.width || t.height != view.height)
        {
            self.targets = Some(make_targets(&self.gpu, view.width, view.height));
        }
        Ok(())
    }

    /// Records a frame: clear, then every item. The caller submits.
    fn encode_frame(
        &mut self,
        items: &[&dyn Drawable],
        view: &View,
        style: &Style,
    ) -> Result<wgpu::CommandEncoder> {
        check_hidden(items, style)?;
        self.set_frame(view, style)?;
        let targets = self
            .targets
            .as_ref()
            .ok_or_else(|| Error::Gpu("no render targets".into()))?;
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        let [r, g, b, a] = style.background.map(f64::from);
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("clear"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &targets.color_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &targets.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        self.encode_items(&mut encoder, items, view, style)?;
        Ok(encoder)
    }

    /// Records `items` into the frame's targets as they are (no clear).
    fn encode_items(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        items: &[&dyn Drawable],
        view: &View,
        style: &Style,
    ) -> Result<()> {
        let targets = self
            .targets
            .as_ref()
            .ok_or_else(|| Error::Gpu("no render targets".into()))?;
        let frame = FrameTargets {
            color: &targets.color_view,
            depth: &targets.depth_view,
            frame_bind_group: &self.bind_group,
            width: view.width,
            height: view.height,
            style,
            projection: view.projection(),
            gpu: &self.gpu,
        };
        for item in items {
            item.encode(&frame, encoder);
        }
        Ok(())
    }

    /// Draws a frame and waits for it, without reading it back (for timing).
    pub fn draw(&mut self, items: &[&dyn Drawable], view: &View, style: &Style) -> Result<()> {
        let mut encoder = self.encode_frame(items, view, style)?;
        self.encode_overlay(&mut encoder)?;
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.wait()
    }

    /// Draws a frame and waits for it, timed by `timer` (benchmarks).
    pub fn draw_timed(
        &mut self,
        items: &[&dyn Drawable],
        view: &View,
        style: &Style,
        timer: &FrameTimer,
    ) -> Result<FrameTime> {
        let mut encoder = self.encode_frame(items, view, style)?;
        self.encode_overlay(&mut encoder)?;
        timer.submit(&self.gpu, encoder)
    }

    /// Draws a frame and returns its pixels (RGBA8, rows top to bottom).
    pub fn render(
        &mut self,
        items: &[&dyn Drawable],
        view: &View,
        style: &Style,
    ) -> Result<RgbaImage> {
        self.render_to(items, view, style, Output::Pixels)?
            .ok_or_else(|| Error::Gpu("no pixels read back".into()))
    }

    /// Draws a frame into [`Renderer::frame_texture`], and with [`Output::Pixels`]
    /// returns its pixels too.
    pub fn render_to(
        &mut self,
        items: &[&dyn Drawable],
        view: &View,
        style: &Style,
        output: Output,
    ) -> Result<Option<RgbaImage>> {
        let scope = self
            .gpu
            .device
            .push_error_scope(wgpu::ErrorFilter::Validation);
        let submitted = self
            .encode_frame(items, view, style)
            .and_then(|mut encoder| {
                self.encode_overlay(&mut encoder)?;
                self.finish_frame(encoder, output)
            });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(e.to_string()));
        }
        submitted?;
        match output {
            Output::Pixels => self.read_pixels().map(Some),
            Output::Texture => Ok(None),
        }
    }

    /// The texture the last frame was drawn into (RGBA8, not sRGB-encoded:
    /// [`crate::wire::COLOR_FORMAT`]), `None` before the first frame. A window shows
    /// it; it is replaced when the frame size changes.
    pub fn frame_texture(&self) -> Option<&wgpu::Texture> {
        self.targets.as_ref().map(|t| &t.color)
    }

    /// Submits `encoder`, with the copy into the readback buffer for `Output::Pixels`.
    fn finish_frame(&self, encoder: wgpu::CommandEncoder, output: Output) -> Result<()> {
        match output {
            Output::Pixels => self.submit_with_copy(encoder),
            Output::Texture => {
                self.gpu.queue.submit([encoder.finish()]);
                Ok(())
            }
        }
    }

    /// Draws a frame of parts that `next` makes one at a time (`None` when there are
    /// no more) and returns its pixels. Each part is drawn and waited for before the
    /// next is made, and then dropped: a scene too large to hold at once draws in the
    /// memory of its largest part. The frame is the one [`Renderer::render`] draws of
    /// all the parts at once wherever no part's drawing looks at what another drew, as
    /// with hidden lines suppressed; [`Renderer::render`]'s other styles dash the lines
    /// behind the depth of everything drawn before them, which parts cannot know.
    pub fn render_parts<E: From<Error>>(
        &mut self,
        view: &View,
        style: &Style,
        next: impl FnMut(&mut Renderer) -> std::result::Result<Option<Box<dyn Drawable>>, E>,
    ) -> std::result::Result<RgbaImage, E> {
        self.render_parts_to(view, style, Output::Pixels, next)?
            .ok_or_else(|| Error::Gpu("no pixels read back".into()).into())
    }

    /// [`Renderer::render_parts`] into [`Renderer::frame_texture`], returning the
    /// pixels with [`Output::Pixels`] only.
    pub fn render_parts_to<E: From<Error>>(
        &mut self,
        view: &View,
        style: &Style,
        output: Output,
        mut next: impl FnMut(&mut Renderer) -> std::result::Result<Option<Box<dyn Drawable>>, E>,
    ) -> std::result::Result<Option<RgbaImage>, E> {
        if style.hidden != HiddenLines::Suppressed {
            return Err(Error::Invalid(format!(
                "hidden lines {} need the whole scene at once; a scene drawn in parts suppresses them (tehs)",
                style.hidden.name()
            ))
            .into());
        }
        let scope = self
            .gpu
            .device
            .push_error_scope(wgpu::ErrorFilter::Validation);
        let cleared = self.encode_frame(&[], view, style).map(|encoder| {
            self.gpu.queue.submit([encoder.finish()]);
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(e.to_string()).into());
        }
        cleared?;
        while let Some(part) = next(self)? {
            if !part.draws_alone() {
                return Err(Error::Invalid(format!(
                    "the wireframe technique of a {}-triangle part draws it with the others at once, not in parts",
                    part.triangles()
                ))
                .into());
            }
            let scope = self
                .gpu
                .device
                .push_error_scope(wgpu::ErrorFilter::Validation);
            let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
            let drawn = self
                .encode_items(&mut encoder, &[part.as_ref()], view, style)
                .map(|()| self.gpu.queue.submit([encoder.finish()]));
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(Error::Gpu(e.to_string()).into());
            }
            drawn?;
            self.gpu.wait()?;
        }
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        self.encode_overlay(&mut encoder)?;
        self.finish_frame(encoder, output)?;
        match output {
            Output::Pixels => Ok(Some(self.read_pixels()?)),
            Output::Texture => Ok(None),
        }
    }

    /// Submits `encoder` with the copy of the frame into the readback buffer after
    /// what it records.
    fn submit_with_copy(&self, mut encoder: wgpu::CommandEncoder) -> Result<()> {
        let targets = self
            .targets
            .as_ref()
            .ok_or_else(|| Error::Gpu("no render targets".into()))?;
        encoder.copy_texture_to_buffer(
            targets.color.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &targets.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(targets.padded_row),
                    rows_per_image: Some(targets.height),
                },
            },
            wgpu::Extent3d {
                width: targets.width,
                height: targets.height,
                depth_or_array_layers: 1,
            },
        );
        self.gpu.queue.submit([encoder.finish()]);
        Ok(())
    }

    /// Waits for the frame in the readback buffer and returns its pixels.
    fn read_pixels(&self) -> Result<RgbaImage> {
        let targets = self
            .targets
            .as_ref()
            .ok_or_else(|| Error::Gpu("no render targets".into()))?;
        self.gpu.map_read(&targets.readback)?;
        let slice = targets.readback.slice(..);
        let (w, h, row) = (
            targets.width as usize,
            targets.height as usize,
            targets.padded_row as usize,
        );
        let mut pixels = Vec::with_capacity(w * h * 4);
        {
            let data = slice
                .get_mapped_range()
                .map_err(|e| Error::Gpu(e.to_string()))?;
            for y in 0..h {
                pixels.extend_from_slice(&data[y * row..y * row + 4 * w]);
            }
        }
        targets.readback.unmap();
        RgbaImage::from_raw(targets.width, targets.height, pixels)
            .ok_or_else(|| Error::Gpu("readback size mismatch".into()))
    }
}

/// Refuses items whose technique cannot draw hidden lines as `style` asks.
fn check_hidden(items: &[&dyn Drawable], style: &Style) -> Result<()> {
    match items.iter().find(|i| !i.supports(style.hidden)) {
        Some(item) => Err(Error::Invalid(format!(
            "the wireframe technique of a {}-triangle mesh cannot draw hidden lines as {} (the texture techniques draw tehs only)",
            item.triangles(),
            style.hidden.name()
        ))),
        None => Ok(()),
    }
}

fn texture_entry(binding: u32, dim: wgpu::TextureViewDimension) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: dim,
            multisampled: false,
        },
        count: None,
    }
}

fn sampler_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        count: None,
    }
}

fn make_bind_group(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    uniforms: &wgpu::Buffer,
    wire_view: &wgpu::TextureView,
    wire_sampler: &wgpu::Sampler,
    colormap_view: &wgpu::TextureView,
    colormap_sampler: &wgpu::Sampler,
) -> wgpu::BindGroup {
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("frame"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(wire_view),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(wire_sampler),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(colormap_view),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: wgpu::BindingResource::Sampler(colormap_sampler),
            },
        ],
    })
}

/// The colour-map texture of 256 RGBA8 texels, `table`.
fn upload_colormap(gpu: &Gpu, table: &[u8]) -> wgpu::TextureView {
    let size = wgpu::Extent3d {
        width: 256,
        height: 1,
        depth_or_array_layers: 1,
    };
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("colour map"),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    gpu.queue.write_texture(
        texture.as_image_copy(),
        table,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(1024),
            rows_per_image: Some(1),
        },
        size,
    );
    texture.create_view(&Default::default())
}

/// A buffer to read back a `width` x `height` texture of `texel_bytes`-byte texels, and
/// its row pitch in bytes (rows padded to the copy alignment).
pub(crate) fn readback_buffer(
    gpu: &Gpu,
    label: &str,
    (width, height): (u32, u32),
    texel_bytes: u32,
) -> (wgpu::Buffer, u32) {
    let padded_row = (texel_bytes * width).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
        * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: u64::from(padded_row) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    (buffer, padded_row)
}

/// A `width` x `height` single-sample 2D texture.
pub(crate) fn frame_texture(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

fn make_targets(gpu: &Gpu, width: u32, height: u32) -> Targets {
    let target =
        |format, usage| frame_texture(&gpu.device, "frame target", (width, height), format, usage);
    let color = target(
        COLOR_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::TEXTURE_BINDING,
    );
    let depth = target(
        DEPTH_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
    );
    let (readback, padded_row) = readback_buffer(gpu, "readback", (width, height), 4);
    Targets {
        width,
        height,
        color_view: color.create_view(&Default::default()),
        color,
        depth_view: depth.create_view(&Default::default()),
        readback,
        padded_row,
    }
}
