//! The texture-based techniques of Celes & Abraham: `global`, `quad`, `tex` (vertex
//! buffers with the coordinates of each scheme) and `texgs` (per-triangle coordinates
//! made in the vertex shader while pulling vertices from storage buffers, which
//! stands in for the paper's geometry shader). `none` shares the vertex path with the
//! wire turned off, so every ratio to it compares like with like.

use bytemuck::{Pod, Zeroable};
use strata_grid::SurfaceMesh;
use wgpu::util::DeviceExt;

use super::labels::{Labelling, label_vertices};
use super::lines::{PulledMesh, check_mesh, storage, storage_layout};
use super::{
    Drawable, FrameTargets, PipelineContext, PipelineRequest, Technique, WireMode,
    texture_pipelines, texture_shader, texture_variant,
};
use crate::{Error, Gpu, Result};

/// The value written for an undefined scalar (see `UNDEFINED_SCALAR` in common.wgsl).
pub(super) const UNDEFINED_SCALAR: f32 = -3.0e38;

pub(super) fn scalar_at(mesh: &SurfaceMesh, v: usize) -> f32 {
    match mesh.scalars.get(v) {
        Some(s) if s.is_finite() => *s,
        Some(_) => UNDEFINED_SCALAR,
        None => 0.0,
    }
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(super) struct UvVertex {
    position: [f32; 3],
    uv: [f32; 2],
    scalar: f32,
}

/// `global`: the vertex's global coordinates, for major lines.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Tex3Vertex {
    position: [f32; 3],
    s: [f32; 3],
    scalar: f32,
    global: [f32; 2],
}

/// A `quad` vertex: the per-quad coordinates `uv` and, for major lines, the global ones.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct QuadVertex {
    position: [f32; 3],
    uv: [f32; 2],
    scalar: f32,
    global: [f32; 2],
}

pub(super) const UV_ATTRIBUTES: [wgpu::VertexAttribute; 3] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x2, 2 => Float32];
const TEX3_ATTRIBUTES: [wgpu::VertexAttribute; 4] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32, 3 => Float32x2];
const QUAD_ATTRIBUTES: [wgpu::VertexAttribute; 4] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x2, 2 => Float32, 3 => Float32x2];

/// `none`, `global`, `quad` and `tex`: indexed vertex buffers.
pub struct VertexTechnique {
    mode: WireMode,
    /// One per coverage form and use of extra lines (`texture_pipelines`).
    pipelines: [wgpu::RenderPipeline; 4],
}

impl VertexTechnique {
    pub fn new(mode: WireMode, ctx: &PipelineContext) -> Self {
        let module = texture_shader(&ctx.gpu.device);
        let uv_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<UvVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &UV_ATTRIBUTES,
        };
        let tex3_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Tex3Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &TEX3_ATTRIBUTES,
        };
        let quad_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<QuadVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &QUAD_ATTRIBUTES,
        };
        let (entries, layout) = match mode {
            WireMode::None => (("vs_uv", "fs_shaded"), uv_layout),
            WireMode::Tex => (("vs_tex3", "fs_tex3"), tex3_layout),
            WireMode::Quad => (("vs_quad", "fs_quad"), quad_layout),
            _ => (("vs_uv", "fs_uv"), uv_layout),
        };
        let buffers = [Some(layout)];
        let request = PipelineRequest {
            buffers: &buffers,
            ..PipelineRequest::new(mode.name(), &module, entries)
        };
        let pipelines = texture_pipelines(ctx, &request);
        VertexTechnique { mode, pipelines }
    }
}

impl Technique for VertexTechnique {
    fn mode(&self) -> WireMode {
        self.mode
    }

    fn prepare(&self, gpu: &Gpu, mesh: &SurfaceMesh) -> Result<Box<dyn Drawable>> {
        // Uploaded from where they are made: copies of a part's vertices and indices
        // cost as much as making them.
        let draw = |vertices: &[u8], triangles: &[[u32; 3]]| -> Result<Box<dyn Drawable>> {
            Ok(Box::new(IndexedDraw::new(
                gpu,
                self.pipelines.clone(),
                vertices,
                triangles,
                self.mode.name(),
            )?))
        };
        match self.mode {
            WireMode::Quad => {
                let (v, t) = quad_vertices(mesh)?;
                draw(bytemuck::cast_slice(&v), &t)
            }
            WireMode::Tex => {
                let l = label_vertices(mesh.vertex_count(), &mesh.triangles);
                let v: Vec<Tex3Vertex> = l
                    .source_vertex
                    .iter()
                    .zip(&l.labels)
                    .map(|(&src, &label)| Tex3Vertex {
                        position: mesh.positions[src as usize],
                        s: Labelling::coordinates(label),
                        scalar: scalar_at(mesh, src as usize),
                        global: mesh.texcoords[src as usize],
                    })
                    .collect();
                draw(bytemuck::cast_slice(&v), &l.triangles)
            }
            mode => {
                let draw = IndexedDraw::of_mesh(
                    gpu,
                    self.pipelines.clone(),
                    mesh,
                    &mesh.triangles,
                    mode.name(),
                )?;
                Ok(Box::new(draw))
            }
        }
    }
}

/// Every cell face gets its own four vertices with coordinates -1 / +1 on opposite
/// sides; the diagonal the two triangles share runs from (-1, -1) to (1, 1) and so
/// never reaches a line.
fn quad_vertices(mesh: &SurfaceMesh) -> Result<(Vec<QuadVertex>, Vec<[u32; 3]>)> {
    if mesh.cell_faces.is_empty() {
        return Err(Error::Invalid(
            "the quad wireframe needs a mesh made of cell faces".into(),
        ));
    }
    let mut vertices = Vec::with_capacity(4 * mesh.cell_faces.len());
    let mut triangles = Vec::with_capacity(2 * mesh.cell_faces.len());
    for face in &mesh.cell_faces {
        let [a, b] = face.triangles.map(|t| mesh.triangles[t as usize]);
        // The diagonal is the edge the two triangles share; `a` walks d0 -> x -> d1.
        let Some(e) = (0..3).find(|&e| {
            let (u, v) = (a[e], a[(e + 1) % 3]);
            b.contains(&u) && b.contains(&v)
        }) else {
            return Err(Error::Invalid(format!(
                "cell face {:?}: its triangles share no edge",
                face.cell
            )));
        };
        let (d1, d0) = (a[e], a[(e + 1) % 3]);
        let x = a[(e + 2) % 3];
        let Some(&y) = b.iter().find(|v| **v != d0 && **v != d1) else {
            return Err(Error::Invalid(format!(
                "cell face {:?} is degenerate",
                face.cell
            )));
        };
        let base = vertices.len() as u32;
        for (v, uv) in [
            (d0, [-1.0, -1.0]),
            (x, [1.0, -1.0]),
            (d1, [1.0, 1.0]),
            (y, [-1.0, 1.0]),
        ] {
            vertices.push(QuadVertex {
                position: mesh.positions[v as usize],
                uv,
                scalar: scalar_at(mesh, v as usize),
                global: mesh.texcoords[v as usize],
            });
        }
        triangles.push([base, base + 1, base + 2]);
        triangles.push([base, base + 2, base + 3]);
    }
    Ok((vertices, triangles))
}

/// An indexed triangle list in a vertex and an index buffer.
pub(super) struct IndexedDraw {
    pub pipelines: [wgpu::RenderPipeline; 4],
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    index_count: u32,
    pub bytes: u64,
}

impl IndexedDraw {
    fn new(
        gpu: &Gpu,
        pipelines: [wgpu::RenderPipeline; 4],
        vertices: &[u8],
        triangles: &[[u32; 3]],
        label: &str,
    ) -> Result<Self> {
        let fill = |mut bytes: wgpu::WriteOnly<[u8]>| bytes.copy_from_slice(vertices);
        Self::filled(gpu, pipelines, (vertices.len(), fill), triangles, label)
    }

    /// The vertices of `mesh` with their global coordinates, written straight into
    /// the vertex buffer. A part of a large model holds millions: made in a vector and
    /// copied, they were measured much slower to upload on lavapipe
    /// (`docs/performance.md`, "Wireframe techniques").
    pub fn of_mesh(
        gpu: &Gpu,
        pipelines: [wgpu::RenderPipeline; 4],
        mesh: &SurfaceMesh,
        triangles: &[[u32; 3]],
        label: &str,
    ) -> Result<Self> {
        const SIZE: usize = std::mem::size_of::<UvVertex>();
        let fill = |bytes: wgpu::WriteOnly<[u8]>| {
            let (vertices, _) = bytes.into_chunks::<SIZE>();
            vertices.write_iter((0..mesh.vertex_count()).map(|i| {
                bytemuck::cast::<UvVertex, [u8; SIZE]>(UvVertex {
                    position: mesh.positions[i],
                    uv: mesh.texcoords[i],
                    scalar: scalar_at(mesh, i),
                })
            }));
        };
        let bytes = SIZE * mesh.vertex_count();
        Self::filled(gpu, pipelines, (bytes, fill), triangles, label)
    }

    /// An indexed draw of `triangles` over a vertex buffer of `bytes` that `fill`
    /// writes while it is mapped.
    fn filled(
        gpu: &Gpu,
        pipelines: [wgpu::RenderPipeline; 4],
        (bytes, fill): (usize, impl FnOnce(wgpu::WriteOnly<[u8]>)),
        triangles: &[[u32; 3]],
        label: &str,
    ) -> Result<Self> {
        if triangles.is_empty() {
            return Err(Error::Invalid(
                "nothing to draw: the mesh has no triangles".into(),
            ));
        }
        let device = &gpu.device;
        let vertex_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: wgpu::util::align_to(bytes as u64, wgpu::COPY_BUFFER_ALIGNMENT),
            usage: wgpu::BufferUsages::VERTEX,
            mapped_at_creation: true,
        });
        {
            let mut mapped = vertex_buffer
                .slice(..)
                .get_mapped_range_mut()
                .map_err(|e| Error::Gpu(format!("mapping {label}'s vertices: {e}")))?;
            fill(mapped.slice(..bytes));
        }
        vertex_buffer.unmap();
        let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(triangles),
            usage: wgpu::BufferUsages::INDEX,
        });
        Ok(IndexedDraw {
            pipelines,
            vertices: vertex_buffer,
            indices: index_buffer,
            index_count: 3 * triangles.len() as u32,
            bytes: (bytes + 12 * triangles.len()) as u64,
        })
    }
}

impl Drawable for IndexedDraw {
    fn encode(&self, frame: &FrameTargets, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = frame.begin_pass(encoder, "indexed mesh");
        self.draw_in_pass(frame, &mut pass);
    }

    fn single_pass(&self) -> bool {
        true
    }

    fn draw_in_pass(&self, frame: &FrameTargets, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipelines[texture_variant(frame)]);
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
    }

    fn triangles(&self) -> usize {
        self.index_count as usize / 3
    }

    fn bytes(&self) -> u64 {
        self.bytes
    }
}

/// `texgs`: non-indexed draw of 3 T vertices; the vertex shader reads the index and
/// vertex data from storage buffers and makes each corner's coordinates.
pub struct PulledTechnique {
    pipelines: [wgpu::RenderPipeline; 4],
    layout: wgpu::BindGroupLayout,
}

impl PulledTechnique {
    pub fn new(ctx: &PipelineContext) -> Self {
        let device = &ctx.gpu.device;
        let layout = storage_layout(
            device,
            "texgs storage",
            &[0, 1, 2, 3],
            wgpu::ShaderStages::VERTEX,
        );
        let module = texture_shader(device);
        let request = PipelineRequest {
            extra_layouts: &[&layout],
            ..PipelineRequest::new("texgs", &module, ("vs_texgs", "fs_tex3"))
        };
        let pipelines = texture_pipelines(ctx, &request);
        PulledTechnique { pipelines, layout }
    }
}

impl Technique for PulledTechnique {
    fn mode(&self) -> WireMode {
        WireMode::TexGs
    }

    fn prepare(&self, gpu: &Gpu, mesh: &SurfaceMesh) -> Result<Box<dyn Drawable>> {
        check_mesh(mesh)?;
        let device = &gpu.device;
        let masks: Vec<u32> = mesh.edge_mask().into_iter().map(u32::from).collect();
        let mut pulled = PulledMesh::new(gpu, mesh, "texgs vertices")?;
        let mut bytes = 0;
        let mut draws = Vec::new();
        // Per triangle: three indices, then the mask and its corners' global
        // coordinates (texture.wgsl, `pulled_triangles`).
        pulled.for_each_chunk(gpu, &mesh.triangles, &[0, 1, 2], 40, |chunk| {
            let indices = storage(gpu, "texgs triangles", bytemuck::cast_slice(chunk.items))?;
            let records: Vec<u32> = chunk
                .range
                .clone()
                .flat_map(|t| {
                    let uv = mesh.triangles[t].map(|v| mesh.texcoords[v as usize]);
                    std::iter::once(masks[t]).chain(uv.into_iter().flatten().map(f32::to_bits))
                })
                .collect();
            let records = storage(gpu, "texgs edge masks", bytemuck::cast_slice(&records))?;
            bytes += indices.size() + records.size();
            let own = [(2, &indices), (3, &records)];
            let group = chunk.bind_group(device, "texgs", &self.layout, &own);
            draws.push((group, 3 * chunk.items.len() as u32));
            Ok(())
        })?;
        bytes += pulled.bytes();
        let draw = PulledDraw {
            pipelines: self.pipelines.clone(),
            draws,
            triangles: mesh.triangles.len(),
            bytes,
        };
        Ok(Box::new(draw))
    }
}

struct PulledDraw {
    pipelines: [wgpu::RenderPipeline; 4],
    /// Per chunk of triangles: bind group and vertex count.
    draws: Vec<(wgpu::BindGroup, u32)>,
    triangles: usize,
    bytes: u64,
}

impl Drawable for PulledDraw {
    fn encode(&self, frame: &FrameTargets, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = frame.begin_pass(encoder, "texgs");
        self.draw_in_pass(frame, &mut pass);
    }

    fn single_pass(&self) -> bool {
        true
    }

    fn draw_in_pass(&self, frame: &FrameTargets, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipelines[texture_variant(frame)]);
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        for (group, vertices) in &self.draws {
            pass.set_bind_group(1, group, &[]);
            pass.draw(0..*vertices, 0..1);
        }
    }

    fn triangles(&self) -> usize {
        self.triangles
    }

    fn bytes(&self) -> u64 {
        self.bytes
    }
}
