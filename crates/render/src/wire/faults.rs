//! Fault traces (`strata_grid::faults`) drawn in the fault style (`Style::faults`), as
//! screen-aligned quads of constant thickness over the surfaces. Unlike the cell
//! lines, which come from the texture coordinates and thin out or fade with the cells'
//! size on screen, these are geometry: they keep their width at every zoom. A mesh
//! with cell faces finds its own ([`Edged`], with its outline edges); a hierarchy
//! gives the ones it stored ([`FaultTraces`]).

use strata_grid::SurfaceMesh;
use strata_grid::faults::{Segment, fault_traces};
use strata_grid::outline::{OutlineEdge, surface_edges};
use wgpu::util::DeviceExt;

use super::lines::{PassSpec, shader};
use super::outline::{OutlineLines, outline_pipeline};
use super::silhouette::Silhouettes;
use super::{Drawable, FrameTargets, PipelineContext};
use crate::Gpu;

const SEGMENT_ATTRIBUTES: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];

/// The pipeline that draws fault traces, shared by a technique's drawables.
pub(crate) fn fault_pipeline(ctx: &PipelineContext) -> wgpu::RenderPipeline {
    let module = shader(&ctx.gpu.device, "fault traces", include_str!("faults.wgsl"));
    let buffers = [Some(wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Segment>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &SEGMENT_ATTRIBUTES,
    })];
    PassSpec {
        buffers: &buffers,
        // Drawn nearer than the surfaces they lie on (EDGE_PULL), so they pass; written,
        // so that a trace drawn again over the same pixels (the other side's, the next
        // segment's end) with less coverage fails instead of blending its edges twice
        // (COVERAGE_DEPTH).
        depth: Some((wgpu::CompareFunction::Greater, true)),
        ..PassSpec::new("fault traces", &module, "vs_fault", "fs_fault")
    }
    .build(&ctx.gpu.device, ctx.frame_layout)
}

/// Fault traces uploaded for drawing: after what is drawn before them, when the
/// frame's style asks for them.
pub(crate) struct FaultTraces {
    pipeline: wgpu::RenderPipeline,
    buffer: wgpu::Buffer,
    count: u32,
}

impl FaultTraces {
    /// `segments` uploaded, drawn by `pipeline` ([`fault_pipeline`]); `None` when
    /// there are none.
    pub fn new(gpu: &Gpu, segments: &[Segment], pipeline: &wgpu::RenderPipeline) -> Option<Self> {
        (!segments.is_empty()).then(|| {
            let buffer = gpu
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("fault traces"),
                    contents: bytemuck::cast_slice(segments),
                    usage: wgpu::BufferUsages::VERTEX,
                });
            FaultTraces {
                pipeline: pipeline.clone(),
                buffer,
                count: segments.len() as u32,
            }
        })
    }
}

impl Drawable for FaultTraces {
    fn encode(&self, frame: &FrameTargets, encoder: &mut wgpu::CommandEncoder) {
        if frame.style.faults.is_some() {
            let mut pass = frame.begin_pass(encoder, "fault traces");
            self.draw_in_pass(frame, &mut pass);
        }
    }

    fn single_pass(&self) -> bool {
        true
    }

    fn draw_in_pass(&self, frame: &FrameTargets, pass: &mut wgpu::RenderPass<'_>) {
        if frame.style.faults.is_some() {
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, frame.frame_bind_group, &[]);
            pass.set_vertex_buffer(0, self.buffer.slice(..));
            pass.draw(0..6, 0..self.count);
        }
    }

    fn triangles(&self) -> usize {
        0
    }

    fn bytes(&self) -> u64 {
        self.buffer.size()
    }
}

/// The pipelines of the lines drawn as geometry after a surface: its fault traces and
/// the outer half of its outline's lines.
pub(crate) struct EdgePipelines {
    pub faults: wgpu::RenderPipeline,
    pub outline: wgpu::RenderPipeline,
}

impl EdgePipelines {
    pub fn new(ctx: &PipelineContext) -> Self {
        EdgePipelines {
            faults: fault_pipeline(ctx),
            outline: outline_pipeline(ctx),
        }
    }
}

/// A drawable and what of its mesh's edges is drawn after it: the outer half of the
/// lines on its outline and silhouette, then the fault traces. What a texture
/// technique's drawable is wrapped in (`Renderer::prepare`).
pub(crate) struct Edged {
    inner: Box<dyn Drawable>,
    outline: Option<OutlineLines>,
    traces: Option<FaultTraces>,
}

impl Edged {
    /// `inner` with the fault traces of `mesh` and, where it draws the outline
    /// (`outline` given: no side walls carry it), its silhouettes and its outline
    /// edges but those on the lines of constant j at the node rows `outline` lists
    /// (where the mesh was cut from the rest of its surface).
    pub fn new(
        gpu: &Gpu,
        inner: Box<dyn Drawable>,
        mesh: &SurfaceMesh,
        pipelines: &EdgePipelines,
        outline: Option<&[u32]>,
    ) -> Self {
        let outline = outline.and_then(|cut_rows| {
            let found = surface_edges(mesh);
            let edges: Vec<OutlineEdge> = found
                .outline
                .into_iter()
                .filter(|e| !(e.along_i && cut_rows.contains(&e.line)))
                .collect();
            let silhouettes = Silhouettes::new(mesh, &found.interior);
            OutlineLines::new(gpu, &edges, silhouettes, &pipelines.outline)
        });
        let traces = FaultTraces::new(gpu, &fault_traces(mesh), &pipelines.faults);
        Edged {
            inner,
            outline,
            traces,
        }
    }

    /// Draws the outline and traces into `pass`.
    fn edges_in_pass(&self, frame: &FrameTargets, pass: &mut wgpu::RenderPass<'_>) {
        if let Some(outline) = &self.outline {
            outline.draw_in_pass(frame, pass);
        }
        if let Some(traces) = &self.traces {
            traces.draw_in_pass(frame, pass);
        }
    }
}

impl Drawable for Edged {
    fn encode(&self, frame: &FrameTargets, encoder: &mut wgpu::CommandEncoder) {
        if self.inner.single_pass() {
            let mut pass = frame.begin_pass(encoder, "surface and its edges");
            self.draw_in_pass(frame, &mut pass);
            return;
        }
        self.inner.encode(frame, encoder);
        let traced = self.traces.is_some() && frame.style.faults.is_some();
        if self.outline.is_some() || traced {
            let mut pass = frame.begin_pass(encoder, "edges");
            self.edges_in_pass(frame, &mut pass);
        }
    }

    fn single_pass(&self) -> bool {
        self.inner.single_pass()
    }

    fn draw_in_pass(&self, frame: &FrameTargets, pass: &mut wgpu::RenderPass<'_>) {
        self.inner.draw_in_pass(frame, pass);
        self.edges_in_pass(frame, pass);
    }

    fn triangles(&self) -> usize {
        self.inner.triangles()
    }

    fn bytes(&self) -> u64 {
        self.inner.bytes()
            + self.outline.as_ref().map_or(0, OutlineLines::bytes)
            + self.traces.as_ref().map_or(0, FaultTraces::bytes)
    }

    fn supports(&self, hidden: crate::HiddenLines) -> bool {
        self.inner.supports(hidden)
    }

    fn draws_alone(&self) -> bool {
        self.inner.draws_alone()
    }
}
