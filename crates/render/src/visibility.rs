//! Which pieces of a mesh a frame shows: a pass that writes, at each pixel centre, the
//! piece of the nearest surface (the mesh hiding itself, two-sided), read back. A
//! hierarchy view reads the model's isoline field only for the pieces it shows.

use strata_grid::SurfaceMesh;
use wgpu::util::DeviceExt;

use crate::gpu::Gpu;
use crate::renderer::{frame_texture, readback_buffer};
use crate::wire::{DEPTH_FORMAT, PipelineContext, pipeline_into};
use crate::{Error, Result};

/// Piece + 1 per pixel; 0 where no surface is.
const PIECE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

const SHADER: &str = r"
struct PieceOut {
    @builtin(position) position: vec4<f32>,
    @location(0) @interpolate(flat) piece: u32,
}

@vertex
fn vs_piece(@location(0) p: vec3<f32>, @location(1) piece: u32) -> PieceOut {
    return PieceOut(clip(world(p)), piece);
}

@fragment
fn fs_piece(in: PieceOut) -> @location(0) u32 {
    return in.piece + 1u;
}
";

/// Per piece below `piece_count`, whether a `width` x `height` frame with the frame
/// uniforms of `frame_bind_group` (laid out by `frame_layout`) shows `mesh` from it at
/// some pixel centre; `pieces` gives each vertex's piece.
pub(crate) fn visible_pieces(
    gpu: &Gpu,
    frame_layout: &wgpu::BindGroupLayout,
    frame_bind_group: &wgpu::BindGroup,
    (mesh, pieces, piece_count): (&SurfaceMesh, &[u32], usize),
    (width, height): (u32, u32),
) -> Result<Vec<bool>> {
    if pieces.len() != mesh.vertex_count() {
        return Err(Error::Invalid(format!(
            "{} pieces for {} vertices",
            pieces.len(),
            mesh.vertex_count()
        )));
    }
    if let Some(p) = pieces.iter().find(|&&p| p as usize >= piece_count) {
        return Err(Error::Invalid(format!("piece {p} of {piece_count}")));
    }
    let mut visible = vec![false; piece_count];
    if mesh.is_empty() {
        return Ok(visible);
    }
    let device = &gpu.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("visible pieces"),
        source: wgpu::ShaderSource::Wgsl(
            format!("{}{SHADER}", include_str!("wire/common.wgsl")).into(),
        ),
    });
    let ctx = PipelineContext { gpu, frame_layout };
    let pipeline = pipeline_into(
        &ctx,
        "visible pieces",
        &module,
        ("vs_piece", "fs_piece"),
        &[
            Some(wgpu::VertexBufferLayout {
                array_stride: 12,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3],
            }),
            Some(wgpu::VertexBufferLayout {
                array_stride: 4,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![1 => Uint32],
            }),
        ],
        (&[], &[]),
        Some(PIECE_FORMAT.into()),
    );
    let buffer = |label, contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage,
        })
    };
    let positions = buffer(
        "piece positions",
        bytemuck::cast_slice(&mesh.positions),
        wgpu::BufferUsages::VERTEX,
    );
    let piece_buffer = buffer(
        "vertex pieces",
        bytemuck::cast_slice(pieces),
        wgpu::BufferUsages::VERTEX,
    );
    let indices = buffer(
        "piece indices",
        bytemuck::cast_slice(&mesh.triangles),
        wgpu::BufferUsages::INDEX,
    );
    let target =
        |label, format, usage| frame_texture(device, label, (width, height), format, usage);
    let ids = target(
        "pieces",
        PIECE_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let depth = target(
        "piece depth",
        DEPTH_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let (readback, padded_row) = readback_buffer(gpu, "pieces readback", width, height);
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let ids_view = ids.create_view(&Default::default());
        let depth_view = depth.create_view(&Default::default());
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("visible pieces"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &ids_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, frame_bind_group, &[]);
        pass.set_vertex_buffer(0, positions.slice(..));
        pass.set_vertex_buffer(1, piece_buffer.slice(..));
        pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..3 * mesh.triangle_count() as u32, 0, 0..1);
    }
    encoder.copy_texture_to_buffer(
        ids.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_row),
                rows_per_image: Some(height),
            },
        },
        ids.size(),
    );
    gpu.queue.submit([encoder.finish()]);
    gpu.map_read(&readback)?;
    let mapped = readback
        .slice(..)
        .get_mapped_range()
        .map_err(|e| Error::Gpu(e.to_string()))?;
    for row in mapped.chunks_exact(padded_row as usize) {
        let row: &[u32] = bytemuck::cast_slice(&row[..4 * width as usize]);
        for &id in row.iter().filter(|&&id| id > 0) {
            if let Some(v) = visible.get_mut(id as usize - 1) {
                *v = true;
            }
        }
    }
    Ok(visible)
}
