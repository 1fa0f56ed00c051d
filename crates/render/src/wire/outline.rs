//! The outer half of the lines on a surface's outline (`strata_grid::outline`): the
//! model's outline, holes and inactive cells; and on its silhouette, where a folded
//! surface turns away from the eye (`silhouette.rs`, drawn as outline edges of the
//! frame).
//!
//! # How it works
//! The texture techniques draw a cell line where the surface is: on an outline edge,
//! only the half of the line that falls on the surface shows, and a one-pixel outline
//! nearly vanishes. This pass draws the other half as a screen-space quad per piece
//! of the outline the frame draws (`outline_chains`: runs of edges along one grid line
//! merged where they are straight on screen, chosen on the CPU), after the surface,
//! depth tested without writing depth. The fragment keeps the pixels on the far side
//! of the edge from the surface, evaluates the line as the texture techniques evaluate
//! theirs (`cell_lines`: thickness, coverage form, major lines and their fading,
//! attenuation), from its distance to the edge and the cell's width on screen, and
//! around each end keeps only the pixels on its side of the bisector with the next
//! edge, so a corner is covered once.
//!
//! # Why not the obvious way
//! Widening the mesh by a skirt of triangles would need each technique to extrapolate
//! its own coordinates into the skirt; a second pass over the whole mesh (as `bias`
//! or `dist` draw edges) costs what the texture techniques save. The outline is a
//! fraction of the edges, and this pass draws only those.

use std::cell::RefCell;

use glam::Vec3;
use strata_grid::outline::OutlineEdge;
use wgpu::util::DeviceExt;

use super::lines::{PassSpec, shader};
use super::outline_chains::{Chosen, OutlineChains};
use super::silhouette::Silhouettes;
use super::{Drawable, FrameTargets, PipelineContext};
use crate::Gpu;

/// An outline edge as the shader reads it: its ends, the point one cell inward with
/// the grid line's index, and its neighbours' far ends, each with 1 where the outline
/// goes on straight there (no corner to split: the shader need not project it).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct EdgeRecord {
    ends: [[f32; 3]; 2],
    inward: [f32; 3],
    line: f32,
    before: [f32; 3],
    straight_before: f32,
    after: [f32; 3],
    straight_after: f32,
}

/// Whether `p`, `q` and `r` lie on one straight line, in that order: a straight
/// line projects to a straight line.
fn straight(p: [f32; 3], q: [f32; 3], r: [f32; 3]) -> bool {
    let (u, v) = (Vec3::from(q) - Vec3::from(p), Vec3::from(r) - Vec3::from(q));
    u.dot(v) > 0.0 && u.cross(v).length() <= 1.0e-5 * u.length() * v.length()
}

impl EdgeRecord {
    /// The record of chosen piece `piece` of `chains`, joined to the pieces chosen
    /// before and after it in its chain where they are its neighbours (`before`,
    /// `after`), else to the outline's edges there.
    fn of(
        chains: &OutlineChains,
        piece: Chosen,
        before: Option<Chosen>,
        after: Option<Chosen>,
    ) -> Self {
        let edges = &chains.edges;
        let (first, last) = (&edges[piece.start as usize], &edges[piece.end as usize - 1]);
        let middle = &edges[((piece.start + piece.end) / 2) as usize];
        let (a, b) = (first.ends[0], last.ends[1]);
        let before = match before {
            Some(p) if p.end == piece.start && chains.follows(piece.start) => {
                edges[p.start as usize].ends[0]
            }
            _ => first.before,
        };
        let after = match after {
            Some(p) if p.start == piece.end && chains.follows(p.start) => {
                edges[p.end as usize - 1].ends[1]
            }
            _ => last.after,
        };
        EdgeRecord::new(&OutlineEdge {
            ends: [a, b],
            before,
            after,
            ..*middle
        })
    }

    /// The record of edge `e`, with the neighbours it names.
    fn new(e: &OutlineEdge) -> Self {
        let [a, b] = e.ends;
        EdgeRecord {
            ends: e.ends,
            inward: e.inward,
            line: e.line as f32,
            before: e.before,
            straight_before: f32::from(u8::from(straight(e.before, a, b))),
            after: e.after,
            straight_after: f32::from(u8::from(straight(a, b, e.after))),
        }
    }
}

const EDGE_ATTRIBUTES: [wgpu::VertexAttribute; 5] = wgpu::vertex_attr_array![
    0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Float32x4, 4 => Float32x4
];

/// The quad of an edge: corners 0 1 2 and 0 2 3 of four (`outline.wgsl`).
const QUAD_INDICES: [u16; 6] = [0, 1, 2, 0, 2, 3];

/// The pipeline that draws outline edges, shared by a technique's drawables.
pub(crate) fn outline_pipeline(ctx: &PipelineContext) -> wgpu::RenderPipeline {
    let module = shader(
        &ctx.gpu.device,
        "outline edges",
        include_str!("outline.wgsl"),
    );
    let buffers = [Some(wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<EdgeRecord>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &EDGE_ATTRIBUTES,
    })];
    PassSpec {
        buffers: &buffers,
        // Drawn nearer than the surface (EDGE_PULL), over whatever lies behind the
        // outline; not written, so that what is drawn later behind it still shows.
        depth: Some((wgpu::CompareFunction::Greater, false)),
        ..PassSpec::new("outline edges", &module, "vs_outline", "fs_outline")
    }
    .build(&ctx.gpu.device, ctx.frame_layout)
}

/// Outline edges and silhouette candidates uploaded for drawing after their surface,
/// what each frame draws chosen on the CPU ([`OutlineChains`], [`Silhouettes`]).
pub(crate) struct OutlineLines {
    pipeline: wgpu::RenderPipeline,
    chains: OutlineChains,
    silhouettes: Option<Silhouettes>,
    /// The chosen pieces' and silhouette edges' records, rewritten every frame; grown
    /// when a frame needs more room.
    buffer: RefCell<wgpu::Buffer>,
    /// [`QUAD_INDICES`]: four vertices an edge, shaded once each.
    quad: wgpu::Buffer,
    /// The last frame's choice, kept to reuse its memory.
    chosen: RefCell<Choice>,
}

/// What a frame draws: pieces of the outline, silhouette edges, their records.
#[derive(Default)]
struct Choice {
    pieces: Vec<Chosen>,
    silhouette: Vec<OutlineEdge>,
    records: Vec<EdgeRecord>,
}

/// A vertex buffer of `records` edge records.
fn edge_buffer(gpu: &Gpu, records: usize) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("outline edges"),
        size: (records.max(1) * std::mem::size_of::<EdgeRecord>()) as u64,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl OutlineLines {
    /// `edges` and the silhouette edges of `silhouettes` uploaded, drawn by `pipeline`
    /// ([`outline_pipeline`]); `None` when there are neither.
    pub fn new(
        gpu: &Gpu,
        edges: &[OutlineEdge],
        silhouettes: Option<Silhouettes>,
        pipeline: &wgpu::RenderPipeline,
    ) -> Option<Self> {
        (!edges.is_empty() || silhouettes.is_some()).then(|| OutlineLines {
            pipeline: pipeline.clone(),
            chains: OutlineChains::new(edges),
            silhouettes,
            buffer: RefCell::new(edge_buffer(gpu, edges.len())),
            quad: gpu
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("outline quad"),
                    contents: bytemuck::cast_slice(&QUAD_INDICES),
                    usage: wgpu::BufferUsages::INDEX,
                }),
            chosen: RefCell::new(Choice::default()),
        })
    }

    /// Chooses what `frame` draws and writes its records; their count.
    fn choose(&self, frame: &FrameTargets) -> u32 {
        let mut chosen = self.chosen.borrow_mut();
        let Choice {
            pieces,
            silhouette,
            records,
        } = &mut *chosen;
        self.chains.choose(&frame.projection, frame.style, pieces);
        records.clear();
        records.extend((0..pieces.len()).map(|n| {
            EdgeRecord::of(
                &self.chains,
                pieces[n],
                n.checked_sub(1).map(|m| pieces[m]),
                pieces.get(n + 1).copied(),
            )
        }));
        if let Some(silhouettes) = &self.silhouettes {
            silhouettes.choose(&frame.projection, silhouette);
            records.extend(silhouette.iter().map(EdgeRecord::new));
        }
        if records.is_empty() {
            return 0;
        }
        let mut buffer = self.buffer.borrow_mut();
        let bytes: &[u8] = bytemuck::cast_slice(records);
        if buffer.size() < bytes.len() as u64 {
            *buffer = edge_buffer(frame.gpu, records.len().next_power_of_two());
        }
        frame.gpu.queue.write_buffer(&buffer, 0, bytes);
        records.len() as u32
    }
}

impl Drawable for OutlineLines {
    fn encode(&self, frame: &FrameTargets, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = frame.begin_pass(encoder, "outline edges");
        self.draw_in_pass(frame, &mut pass);
    }

    fn single_pass(&self) -> bool {
        true
    }

    /// Writes the frame's choice into the buffer before drawing it: a drawable draws
    /// once a submitted frame.
    fn draw_in_pass(&self, frame: &FrameTargets, pass: &mut wgpu::RenderPass<'_>) {
        let count = self.choose(frame);
        if count == 0 {
            return;
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        pass.set_vertex_buffer(0, self.buffer.borrow().slice(..));
        pass.set_index_buffer(self.quad.slice(..), wgpu::IndexFormat::Uint16);
        pass.draw_indexed(0..6, 0, 0..count);
    }

    fn triangles(&self) -> usize {
        0
    }

    fn bytes(&self) -> u64 {
        self.buffer.borrow().size() + self.quad.size()
    }
}
