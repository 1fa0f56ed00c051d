//! Wireframe techniques. Each family lives in its own module with its WGSL beside it;
//! they all implement [`Technique`], and [`TECHNIQUES`] is the one registration table the
//! renderer, the command line, the tests and the benchmarks iterate over.

mod bias;
mod cells;
mod distance;
mod faults;
pub(crate) use faults::{EdgePipelines, Edged, FaultTraces};
pub(crate) use outline::OutlineLines;
pub(crate) use silhouette::Silhouettes;
mod idbuffer;
pub mod labels;
mod lines;
mod outline;
mod outline_chains;
pub mod reference;
mod registry;
mod silhouette;
mod texture;
mod wire_texture;

pub(crate) use cells::CellTechnique;
pub use cells::{CellDraw, Stacking, TiledCells, stack_pushes};
pub(crate) use lines::chunks;
pub use registry::{
    CellBytes, Family, Needs, Registration, TECHNIQUES, WireMode, create, wire_mode_names,
};
pub use wire_texture::{ATTENUATION_LAYERS, Attenuation, WireTextureSpec};

use strata_grid::SurfaceMesh;

use crate::{Coverage, Gpu, HiddenLines, Result, Style};

/// What every pipeline of a frame shares: the device, the frame bind group layout
/// (uniforms, wireframe texture, colour map) and the target formats.
pub struct PipelineContext<'a> {
    /// The device pipelines are built on.
    pub gpu: &'a Gpu,
    /// The frame bind group's layout (group 0 of every pipeline).
    pub frame_layout: &'a wgpu::BindGroupLayout,
}

/// Colour format of every frame: what pipelines drawing into it must declare.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// Depth format of every frame: what pipelines testing against it must declare.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The frame's colour target with `blend`.
pub(crate) fn frame_target(blend: Option<wgpu::BlendState>) -> Option<wgpu::ColorTargetState> {
    Some(wgpu::ColorTargetState {
        format: COLOR_FORMAT,
        blend,
        write_mask: wgpu::ColorWrites::ALL,
    })
}

/// The targets and shared bindings of the frame being drawn.
pub struct FrameTargets<'a> {
    /// The colour target.
    pub color: &'a wgpu::TextureView,
    /// The depth target, reversed (near is 1).
    pub depth: &'a wgpu::TextureView,
    /// Uniforms, wireframe texture and colour map (group 0).
    pub frame_bind_group: &'a wgpu::BindGroup,
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// The frame's style, for techniques whose passes depend on it (hidden lines).
    pub style: &'a Style,
    /// The frame's projection as the shaders apply it, for drawables that choose on
    /// the CPU what to draw (outline edges).
    pub projection: FrameProjection,
    /// The device and queue, for what such drawables write before the frame is
    /// submitted.
    pub gpu: &'a Gpu,
}

/// The projection of a frame: display-frame points to clip space and window pixels,
/// exactly as `world`, `clip` and `window` in the shaders (common.wgsl, lines.wgsl).
#[derive(Clone, Copy, Debug)]
pub struct FrameProjection {
    /// The view and projection matrix, of exaggerated points.
    pub view_proj: glam::Mat4,
    /// The vertical exaggeration.
    pub z_scale: f32,
    /// The eye, in the exaggerated display frame.
    pub eye: glam::Vec3,
    /// The frame's size in pixels.
    pub size: glam::Vec2,
}

impl FrameProjection {
    /// Clip position of display-frame point `p`.
    pub fn clip(&self, p: [f32; 3]) -> glam::Vec4 {
        self.view_proj * glam::Vec4::new(p[0], p[1], p[2] * self.z_scale, 1.0)
    }

    /// Window position in pixels of clip position `c` (in front of the eye).
    pub fn window(&self, c: glam::Vec4) -> glam::Vec2 {
        let ndc = c.truncate().truncate() / c.w;
        glam::Vec2::new(
            (0.5 + 0.5 * ndc.x) * self.size.x,
            (0.5 - 0.5 * ndc.y) * self.size.y,
        )
    }

    /// An upper bound of the pixels a displacement of one unit of the exaggerated
    /// frame (any direction) moves a point on screen at clip depth `w`, for points
    /// within the frame: the matrix rows' lengths, the depth row's for how perspective
    /// moves points off the axis.
    pub fn pixels_per_unit(&self, w: f32) -> f32 {
        let m = self.view_proj.transpose();
        let row = |r: glam::Vec4| r.truncate().length();
        let depth = row(m.w_axis);
        ((row(m.x_axis) + depth) * 0.5 * self.size.x)
            .max((row(m.y_axis) + depth) * 0.5 * self.size.y)
            / w
    }
}

impl FrameTargets<'_> {
    /// A render pass over the frame's targets that keeps what is already drawn.
    pub fn begin_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        label: &str,
    ) -> wgpu::RenderPass<'e> {
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: self.color,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: self.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }
}

/// A wireframe technique: turns a mesh into what it draws. `Send`, so that a
/// [`Renderer`](crate::Renderer) holding its techniques can move between threads.
pub trait Technique: Send {
    /// Which technique this is, so a renderer can key its techniques by mode.
    fn mode(&self) -> WireMode;
    /// Uploads `mesh` in this technique's form (retained mode). Fails when the mesh
    /// lacks what the technique needs (e.g. cell faces for `quad`).
    fn prepare(&self, gpu: &Gpu, mesh: &SurfaceMesh) -> Result<Box<dyn Drawable>>;
}

/// A mesh prepared by a technique, ready to be drawn into a frame. `Send`, as wgpu's
/// buffers are (and as [`Technique`] is), so that an engine holding prepared meshes can
/// move to another thread: the Python package draws with the GIL released, from any thread.
pub trait Drawable: Send {
    /// Records the passes that draw this mesh into the frame's targets.
    fn encode(&self, frame: &FrameTargets, encoder: &mut wgpu::CommandEncoder);
    /// Triangles drawn per frame.
    fn triangles(&self) -> usize;
    /// Bytes uploaded for this mesh (what immediate mode sends every frame).
    fn bytes(&self) -> u64;
    /// Whether this drawable can show hidden lines as `hidden` asks; the texture
    /// techniques draw lines only on visible polygon fragments (hidden suppressed).
    fn supports(&self, hidden: HiddenLines) -> bool {
        hidden == HiddenLines::Suppressed
    }
    /// Whether what this drawable draws depends on the others only through the depth
    /// they left (see [`WireMode::draws_alone`]), so that drawables drawn one after
    /// another in separate passes give the frame of all at once.
    fn draws_alone(&self) -> bool {
        true
    }
    /// Whether it draws in one pass of the frame's targets, with the frame's bind
    /// group at 0 ([`Drawable::draw_in_pass`]): then what is drawn over it (its
    /// outline, its fault traces) shares that pass. On the CPU rasterizers a pass of
    /// its own costs a whole frame's worth of tiles.
    fn single_pass(&self) -> bool {
        false
    }
    /// Records its draws into `pass`, where [`Drawable::single_pass`] holds.
    fn draw_in_pass(&self, _frame: &FrameTargets, _pass: &mut wgpu::RenderPass<'_>) {}
}

/// What a triangle-list pipeline is built from beyond the frame's shared layout, so
/// that one [`pipeline`] serves every technique: start from [`PipelineRequest::new`]
/// and override what differs.
pub(crate) struct PipelineRequest<'a> {
    pub label: &'a str,
    pub module: &'a wgpu::ShaderModule,
    /// Vertex and fragment entry points.
    pub entries: (&'a str, &'a str),
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    /// Bind group layouts after the frame's (group 0).
    pub extra_layouts: &'a [&'a wgpu::BindGroupLayout],
    /// Values for the shader's `override` constants.
    pub constants: &'a [(&'a str, f64)],
    /// The colour target; the frame's colour with alpha blending unless changed.
    pub target: Option<wgpu::ColorTargetState>,
}

impl<'a> PipelineRequest<'a> {
    /// A pipeline drawing into the frame's colour with alpha blending, with no vertex
    /// buffers, bind groups or constants of its own.
    pub fn new(
        label: &'a str,
        module: &'a wgpu::ShaderModule,
        entries: (&'a str, &'a str),
    ) -> Self {
        PipelineRequest {
            label,
            module,
            entries,
            buffers: &[],
            extra_layouts: &[],
            constants: &[],
            target: frame_target(Some(wgpu::BlendState::ALPHA_BLENDING)),
        }
    }
}

/// [`pipeline`] once per coverage form (texture, analytic) and with or without
/// isolines and grid lines, the `COVERAGE_FORM` and `EXTRA_LINES` constants of
/// common.wgsl fixed so that each shader holds only what its frames draw (the CPU
/// rasterizers pay for untaken uniform branches); pick one with [`texture_variant`].
pub(crate) fn texture_pipelines(
    ctx: &PipelineContext,
    request: &PipelineRequest,
) -> [wgpu::RenderPipeline; 4] {
    [0, 1, 2, 3].map(|variant| {
        let constants = [
            ("COVERAGE_FORM", f64::from(variant % 2)),
            ("EXTRA_LINES", f64::from(variant / 2)),
        ];
        pipeline(
            ctx,
            &PipelineRequest {
                constants: &constants,
                target: request.target.clone(),
                ..*request
            },
        )
    })
}

/// The index into [`texture_pipelines`] for the frame's style.
pub(crate) fn texture_variant(frame: &FrameTargets) -> usize {
    let form = match frame.style.coverage {
        Coverage::Texture => 0,
        Coverage::Analytic => 1,
    };
    let extra = frame.style.isolines.is_some() || frame.style.grid_lines.is_some();
    form + 2 * usize::from(extra)
}

/// The frame's depth test: reversed depth (near is 1), the nearer or equal surface
/// passing, depth written with `write`.
pub(crate) fn reversed_depth(write: bool) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(write),
        depth_compare: Some(wgpu::CompareFunction::GreaterEqual),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// Builds a triangle-list render pipeline with the frame's formats, reversed depth,
/// no culling (two-sided surfaces) and what `request` asks.
pub(crate) fn pipeline(ctx: &PipelineContext, request: &PipelineRequest) -> wgpu::RenderPipeline {
    let PipelineRequest {
        label,
        module,
        entries: (vs, fs),
        buffers,
        extra_layouts,
        constants,
        ref target,
    } = *request;
    let options = wgpu::PipelineCompilationOptions {
        constants,
        ..Default::default()
    };
    let device = &ctx.gpu.device;
    let mut layouts: Vec<Option<&wgpu::BindGroupLayout>> = vec![Some(ctx.frame_layout)];
    layouts.extend(extra_layouts.iter().map(|l| Some(*l)));
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &layouts,
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(vs),
            compilation_options: options.clone(),
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(reversed_depth(true)),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(fs),
            compilation_options: options,
            targets: std::slice::from_ref(target),
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The WGSL of the texture family, with the shared code in front.
pub(crate) fn texture_shader(device: &wgpu::Device) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("texture wireframe"),
        source: wgpu::ShaderSource::Wgsl(
            concat!(include_str!("common.wgsl"), include_str!("texture.wgsl")).into(),
        ),
    })
}
