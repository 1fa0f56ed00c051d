//! Which tiles of a cell cover's pieces a frame shows: a pass that writes, at each pixel
//! centre, the piece of the nearest surface (the mesh hiding itself, two-sided), its
//! cell and how many cells the pixel's neighbours reach, read back. A hierarchy view
//! reads the model's isoline field only for the tiles it shows.

use strata_grid::SurfaceMesh;
use strata_lod::CellCover;
use wgpu::util::DeviceExt;

use crate::gpu::Gpu;
use crate::renderer::{frame_texture, readback_buffer};
use crate::wire::{DEPTH_FORMAT, PipelineContext, pipeline_into};
use crate::{Error, Result};

/// Per pixel: piece + 1 (0 where no surface is), the cell's x and y (i32 bits) and the
/// cells a neighbouring pixel's footprint reaches from it.
const TILE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

/// Bytes per pixel of [`TILE_FORMAT`].
const TILE_TEXEL: usize = 16;

/// The farthest a pixel's neighbours are taken to reach, in texture space: at grazing
/// angles the derivatives grow without bound, and the tiles marked stop at the box.
const MAX_REACH: f32 = 1.0e6;

const SHADER: &str = r"
struct TileOut {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) piece: u32,
}

@vertex
fn vs_tile(@location(0) p: vec3<f32>, @location(1) uv: vec2<f32>, @location(2) piece: u32) -> TileOut {
    return TileOut(clip(world(p)), uv, piece);
}

// The frame's fragments take derivatives across their 2 x 2 quads: the cells of a
// pixel's neighbours, one pixel away at most, are read with its own.
@fragment
fn fs_tile(in: TileOut) -> @location(0) vec4<u32> {
    let d = min(abs(dpdx(in.uv)) + abs(dpdy(in.uv)), vec2<f32>(MAX_REACH));
    let cell = vec2<i32>(floor((in.uv - vec2<f32>(1.0)) * 0.5));
    let lo = vec2<i32>(floor((in.uv - d - vec2<f32>(1.0)) * 0.5));
    let hi = vec2<i32>(floor((in.uv + d - vec2<f32>(1.0)) * 0.5));
    let reach = max(cell - lo, hi - cell);
    return vec4<u32>(in.piece + 1u, bitcast<u32>(cell.x), bitcast<u32>(cell.y), u32(max(reach.x, reach.y)));
}
";

/// Per tile of `tile` cells of each piece's box of `cover` (strata-lod's
/// `CoverPiece::tiles`, row by row, piece after piece), whether a `width` x `height`
/// frame with the frame uniforms of `frame_bind_group` (laid out by `frame_layout`)
/// shows `mesh` in it at some pixel centre or takes a derivative there; the cover's
/// `vertex_piece` gives each vertex's piece.
pub(crate) fn visible_tiles(
    gpu: &Gpu,
    frame_layout: &wgpu::BindGroupLayout,
    frame_bind_group: &wgpu::BindGroup,
    (mesh, cover, tile): (&SurfaceMesh, &CellCover, u32),
    (width, height): (u32, u32),
) -> Result<Vec<bool>> {
    let pieces = &cover.vertex_piece;
    let piece_count = cover.pieces.len();
    if pieces.len() != mesh.vertex_count() || mesh.texcoords.len() != mesh.vertex_count() {
        return Err(Error::Invalid(format!(
            "{} pieces and {} texture coordinates for {} vertices",
            pieces.len(),
            mesh.texcoords.len(),
            mesh.vertex_count()
        )));
    }
    if let Some(v) = mesh.triangles.iter().flatten().find(|&&v| {
        pieces
            .get(v as usize)
            .is_none_or(|&p| p as usize >= piece_count)
    }) {
        return Err(Error::Invalid(format!(
            "vertex {v} is in none of the cover's {piece_count} pieces"
        )));
    }
    // Where each piece's tiles start among all, and their end.
    let first_tile: Vec<usize> = std::iter::once(0)
        .chain(cover.pieces.iter().scan(0, |end, p| {
            *end += p.tile_count(tile);
            Some(*end)
        }))
        .collect();
    let mut visible = vec![false; first_tile[piece_count]];
    if mesh.is_empty() {
        return Ok(visible);
    }
    let device = &gpu.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("visible tiles"),
        source: wgpu::ShaderSource::Wgsl(
            format!(
                "{}const MAX_REACH: f32 = {MAX_REACH:?};\n{SHADER}",
                include_str!("wire/common.wgsl")
            )
            .into(),
        ),
    });
    let ctx = PipelineContext { gpu, frame_layout };
    let pipeline = pipeline_into(
        &ctx,
        "visible tiles",
        &module,
        ("vs_tile", "fs_tile"),
        &[
            Some(wgpu::VertexBufferLayout {
                array_stride: 12,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3],
            }),
            Some(wgpu::VertexBufferLayout {
                array_stride: 8,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![1 => Float32x2],
            }),
            Some(wgpu::VertexBufferLayout {
                array_stride: 4,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![2 => Uint32],
            }),
        ],
        (&[], &[]),
        Some(TILE_FORMAT.into()),
    );
    let buffer = |label, contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage,
        })
    };
    let vertex = |label, contents| buffer(label, contents, wgpu::BufferUsages::VERTEX);
    let positions = vertex("tile positions", bytemuck::cast_slice(&mesh.positions));
    let texcoords = vertex("tile texcoords", bytemuck::cast_slice(&mesh.texcoords));
    let piece_buffer = vertex("vertex pieces", bytemuck::cast_slice(pieces));
    let indices = buffer(
        "tile indices",
        bytemuck::cast_slice(&mesh.triangles),
        wgpu::BufferUsages::INDEX,
    );
    let target =
        |label, format, usage| frame_texture(device, label, (width, height), format, usage);
    let ids = target(
        "tiles",
        TILE_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let depth = target(
        "tile depth",
        DEPTH_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let (readback, padded_row) =
        readback_buffer(gpu, "tiles readback", (width, height), TILE_TEXEL as u32);
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let ids_view = ids.create_view(&Default::default());
        let depth_view = depth.create_view(&Default::default());
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("visible tiles"),
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
        pass.set_vertex_buffer(1, texcoords.slice(..));
        pass.set_vertex_buffer(2, piece_buffer.slice(..));
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
    // Neighbouring pixels mostly name the same tiles: each run is marked once.
    let mut last = [0u32; 4];
    for row in mapped.chunks_exact(padded_row as usize) {
        let row: &[[u32; 4]] = bytemuck::cast_slice(&row[..TILE_TEXEL * width as usize]);
        for &texel @ [id, x, y, reach] in row {
            if id == 0 || texel == last {
                continue;
            }
            last = texel;
            let p = id as usize - 1;
            let Some(piece) = cover.pieces.get(p) else {
                continue;
            };
            let side = i64::from(tile.max(1));
            let [across, down] = piece.tiles(tile).map(i64::from);
            let range = |c: u32, origin: i32, count: i64| {
                let rel = i64::from(c as i32) - i64::from(origin);
                let reach = i64::from(reach);
                (
                    (rel - reach).div_euclid(side).max(0),
                    (rel + reach).div_euclid(side).min(count - 1),
                )
            };
            let (x0, x1) = range(x, piece.origin[0], across);
            let (y0, y1) = range(y, piece.origin[1], down);
            for ty in y0..=y1 {
                for tx in x0..=x1 {
                    visible[first_tile[p] + (ty * across + tx) as usize] = true;
                }
            }
        }
    }
    Ok(visible)
}
