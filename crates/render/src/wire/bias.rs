//! `bias`: the classic two-pass wireframe (polygon offset; McReynolds & Blythe, and the
//! baseline of every paper we compare with). Pass 1 fills the polygons, pushed back by
//! the pipeline's depth bias; pass 2 draws the real edges (never a quad's diagonal) with
//! the depth test of the frame, so that edges on the visible surface pass and hidden
//! ones fail. wgpu refuses depth bias on line pipelines, so the bias is on the fill;
//! with reversed depth (nearer is greater) "pushed back" is a negative bias.
//!
//! Lines of thickness σ ≤ 1 are line primitives (one pixel, aliased, as the papers'
//! `Bias`); thicker ones are screen-space quads expanded in the vertex shader, with
//! box-filtered coverage from the distance to the segment. The bias is the common
//! `glPolygonOffset(1, 1)`: one unit of depth resolution plus one times the polygon's
//! depth slope. It covers the half pixel by which a line's fragments stray from the
//! edge, not the σ/2 of a wide line, so on steep slopes the near half of a wide line
//! sinks into the surface (the stippling the papers describe); `strata bench quality`
//! measures it.
//!
//! Hidden-line styles are the paper's own (Rossignac & van Emmerik): TEHD and CEHD draw
//! the lines a second time with the depth test inverted ("farther than the surface"),
//! dashed; CEHS and CEHD keep the contour edges, found per frame in the vertex shader
//! from the vertices opposite each edge.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use strata_grid::SurfaceMesh;
use wgpu::util::DeviceExt;

use super::lines::{
    EDGE_VERTICES, EdgeTable, LazyPipelines, PassSpec, PulledMesh, check_mesh, shader, storage,
    storage_layout,
};
use super::texture::scalar_at;
use super::{Drawable, FrameTargets, PipelineContext, Technique, WireMode};
use crate::{Gpu, HiddenLines, Result};

/// The fill's push back: `glPolygonOffset(1, 1)`, negated for reversed depth. No clamp:
/// the GL adapter lacks DEPTH_BIAS_CLAMP.
const FILL_BIAS: wgpu::DepthBiasState = wgpu::DepthBiasState {
    constant: -1,
    slope_scale: -1.0,
    clamp: 0.0,
};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FillVertex {
    position: [f32; 3],
    scalar: f32,
}

const FILL_ATTRIBUTES: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32];

/// The pipelines of the technique.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Pass {
    /// The polygons, pushed back.
    Fill,
    /// One-pixel lines of every edge from the fill's vertex buffer.
    Line,
    /// One-pixel lines pulled from the edge list: contour styles, hidden pass.
    PulledLine { contours: bool, hidden: bool },
    /// Wide lines as quads.
    Quad { contours: bool, hidden: bool },
}

pub struct BiasTechnique {
    pipelines: Arc<LazyPipelines<Pass>>,
    layout: wgpu::BindGroupLayout,
}

impl BiasTechnique {
    pub fn new(ctx: &PipelineContext) -> Self {
        let device = &ctx.gpu.device;
        let layout = storage_layout(device, "bias", &[0, 1, 2], wgpu::ShaderStages::VERTEX);
        let module = shader(device, "bias", include_str!("bias.wgsl"));
        let pulled_layout = layout.clone();
        let pipelines = LazyPipelines::new(ctx, move |pass: Pass, device, frame_layout| {
            let vertex_layout = [Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<FillVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &FILL_ATTRIBUTES,
            })];
            let layouts = [&pulled_layout];
            let (contours, hidden) = match pass {
                Pass::PulledLine { contours, hidden } | Pass::Quad { contours, hidden } => {
                    (contours, hidden)
                }
                Pass::Fill | Pass::Line => (false, false),
            };
            let constants = [
                ("CONTOURS", f64::from(u8::from(contours))),
                ("HIDDEN", f64::from(u8::from(hidden))),
            ];
            let (label, vs, fs) = match pass {
                Pass::Fill => ("bias fill", "vs_fill", "fs_fill"),
                Pass::Line => ("bias lines", "vs_line", "fs_line"),
                Pass::PulledLine { .. } => ("bias pulled lines", "vs_line_pulled", "fs_line"),
                Pass::Quad { .. } => ("bias quads", "vs_quad", "fs_quad"),
            };
            let mut spec = PassSpec::new(label, &module, vs, fs);
            spec.constants = &constants;
            // Lines never write depth: the hidden pass tests against the fill alone.
            let compare = if hidden {
                wgpu::CompareFunction::Less
            } else {
                wgpu::CompareFunction::GreaterEqual
            };
            spec.depth = Some((compare, false));
            match pass {
                Pass::Fill => {
                    spec.buffers = &vertex_layout;
                    spec.bias = FILL_BIAS;
                    spec.depth = Some((wgpu::CompareFunction::GreaterEqual, true));
                }
                Pass::Line => {
                    spec.buffers = &vertex_layout;
                    spec.topology = wgpu::PrimitiveTopology::LineList;
                }
                Pass::PulledLine { .. } => {
                    spec.extra_layouts = &layouts;
                    spec.topology = wgpu::PrimitiveTopology::LineList;
                }
                Pass::Quad { .. } => spec.extra_layouts = &layouts,
            }
            spec.build(device, frame_layout)
        });
        BiasTechnique { pipelines, layout }
    }
}

impl Technique for BiasTechnique {
    fn mode(&self) -> WireMode {
        WireMode::Bias
    }

    fn prepare(&self, gpu: &Gpu, mesh: &SurfaceMesh) -> Result<Box<dyn Drawable>> {
        check_mesh(mesh)?;
        let device = &gpu.device;
        let fill: Vec<FillVertex> = (0..mesh.vertex_count())
            .map(|v| FillVertex {
                position: mesh.positions[v],
                scalar: scalar_at(mesh, v),
            })
            .collect();
        let table = EdgeTable::new(mesh);
        let line_indices: Vec<[u32; 2]> = table.edges.iter().map(|e| [e[0], e[1]]).collect();
        let buffer = |label, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let vertices = buffer(
            "bias vertices",
            bytemuck::cast_slice(&fill),
            wgpu::BufferUsages::VERTEX,
        );
        let indices = buffer(
            "bias triangles",
            bytemuck::cast_slice(&mesh.triangles),
            wgpu::BufferUsages::INDEX,
        );
        // wgpu refuses an empty buffer; a mesh with no real edge draws no line.
        let lines = buffer(
            "bias lines",
            if line_indices.is_empty() {
                &[0; 8]
            } else {
                bytemuck::cast_slice(&line_indices)
            },
            wgpu::BufferUsages::INDEX,
        );
        let mut pulled = PulledMesh::new(gpu, mesh, "bias pulled vertices")?;
        let mut bytes = vertices.size() + indices.size() + lines.size();
        let mut edge_groups = Vec::new();
        pulled.for_each_chunk(gpu, &table.edges, &EDGE_VERTICES, 16, |chunk| {
            let edges = storage(gpu, "bias edges", bytemuck::cast_slice(chunk.items))?;
            bytes += edges.size();
            let group = chunk.bind_group(device, "bias edges", &self.layout, &[(2, &edges)]);
            edge_groups.push((group, chunk.items.len() as u32));
            Ok(())
        })?;
        bytes += pulled.bytes();
        Ok(Box::new(BiasDraw {
            pipelines: self.pipelines.clone(),
            vertices,
            indices,
            lines,
            edge_groups,
            triangles: mesh.triangles.len(),
            edges: table.edges.len() as u32,
            bytes,
        }))
    }
}

struct BiasDraw {
    pipelines: Arc<LazyPipelines<Pass>>,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    /// Two vertex indices per edge, for the classic one-pixel lines.
    lines: wgpu::Buffer,
    /// Per chunk of edges: the bind group of the pulled passes and its edge count.
    edge_groups: Vec<(wgpu::BindGroup, u32)>,
    triangles: usize,
    edges: u32,
    bytes: u64,
}

impl BiasDraw {
    /// Draws the pulled pass `pass` over every chunk of edges, `per_edge` vertices each.
    fn draw_pulled(&self, pass: &mut wgpu::RenderPass, pipeline: Pass, per_edge: u32) {
        pass.set_pipeline(&self.pipelines.get(pipeline));
        for (group, count) in &self.edge_groups {
            pass.set_bind_group(1, group, &[]);
            pass.draw(0..per_edge * count, 0..1);
        }
    }
}

impl Drawable for BiasDraw {
    fn encode(&self, frame: &FrameTargets, encoder: &mut wgpu::CommandEncoder) {
        let style = frame.style;
        let contours = style.hidden.contours_only();
        let wide = style.thickness > 1.0;
        let mut pass = frame.begin_pass(encoder, "bias");
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        pass.set_pipeline(&self.pipelines.get(Pass::Fill));
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..3 * self.triangles as u32, 0, 0..1);
        for hidden in [false, true] {
            if hidden && !style.hidden.dashed() {
                continue;
            }
            if wide {
                self.draw_pulled(&mut pass, Pass::Quad { contours, hidden }, 6);
            } else if contours || hidden {
                self.draw_pulled(&mut pass, Pass::PulledLine { contours, hidden }, 2);
            } else {
                pass.set_pipeline(&self.pipelines.get(Pass::Line));
                pass.set_index_buffer(self.lines.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..2 * self.edges, 0, 0..1);
            }
        }
    }

    fn triangles(&self) -> usize {
        self.triangles
    }

    fn bytes(&self) -> u64 {
        self.bytes
    }

    fn supports(&self, _: HiddenLines) -> bool {
        true
    }

    fn draws_alone(&self) -> bool {
        WireMode::Bias.draws_alone()
    }
}
