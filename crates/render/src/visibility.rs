//! Which tiles of a cell cover's pieces a frame shows: a pass that writes, at each pixel
//! centre, the piece of the nearest surface (the mesh hiding itself, two-sided), its
//! cell and how many cells the pixel's neighbours reach, read back. A hierarchy view
//! reads the model's isoline field only for the tiles it shows; a decimation of
//! several surfaces splits its budget by the part of each that such frames show,
//! sampled on the CPU ([`pixels_on_cpu`]) where the adapter is a CPU rasterizer.

use glam::{Mat4, Vec3};
use strata_grid::SurfaceMesh;
use strata_lod::CellCover;
use wgpu::util::DeviceExt;

use crate::camera::in_box;
use crate::gpu::Gpu;
use crate::renderer::{View, frame_texture, readback_buffer};
use crate::wire::{DEPTH_FORMAT, PipelineContext, PipelineRequest, pipeline};
use crate::{Error, Result};

/// Per pixel: piece + 1 (0 where no surface is), the cell's x and y (i32 bits) and the
/// cells a neighbouring pixel's footprint reaches from it.
const TILE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

/// Bytes per pixel of [`TILE_FORMAT`].
const TILE_TEXEL: usize = 16;

/// The farthest a pixel's neighbours are taken to reach, in texture space: at grazing
/// angles the derivatives grow without bound, and the tiles marked stop at the box.
const MAX_REACH: f32 = 1.0e6;

/// The frame a visibility pass draws, as the renderer set it up for a view: grouped so
/// that the passes take one frame rather than its five parts.
pub(crate) struct SampleFrame<'a> {
    pub gpu: &'a Gpu,
    pub layout: &'a wgpu::BindGroupLayout,
    /// The frame uniforms (group 0).
    pub bind_group: &'a wgpu::BindGroup,
    pub width: u32,
    pub height: u32,
}

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
/// `CoverPiece::tiles`, row by row, piece after piece), whether `frame` shows `mesh`
/// in it at some pixel centre or takes a derivative there; the cover's `vertex_piece`
/// gives each vertex's piece.
pub(crate) fn visible_tiles(
    frame: &SampleFrame,
    mesh: &SurfaceMesh,
    (cover, tile): (&CellCover, u32),
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
    let texels = id_frame(frame, mesh, pieces)?;
    // Neighbouring pixels mostly name the same tiles: each run is marked once.
    let mut last = [0u32; 4];
    for row in texels.chunks_exact(frame.width as usize) {
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

/// One frame of `mesh`, the nearest surface at each pixel centre (the mesh hiding
/// itself, two-sided), read back row by row as [`TILE_FORMAT`] texels: `ids[v] + 1`
/// of the triangle's first vertex `v` (0 where no surface is), the cell and the reach
/// of `fs_tile`.
fn id_frame(frame: &SampleFrame, mesh: &SurfaceMesh, ids: &[u32]) -> Result<Vec<[u32; 4]>> {
    let SampleFrame {
        gpu,
        layout: frame_layout,
        bind_group: frame_bind_group,
        width,
        height,
    } = *frame;
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
    let buffers = [
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
    ];
    let pipeline = pipeline(
        &ctx,
        &PipelineRequest {
            buffers: &buffers,
            target: Some(TILE_FORMAT.into()),
            ..PipelineRequest::new("visible tiles", &module, ("vs_tile", "fs_tile"))
        },
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
    // A mesh without texture coordinates is drawn with zeros: its cells mean nothing.
    let zeros;
    let uv: &[[f32; 2]] = if mesh.texcoords.len() == mesh.vertex_count() {
        &mesh.texcoords
    } else {
        zeros = vec![[0.0f32; 2]; mesh.vertex_count()];
        &zeros
    };
    let texcoords = vertex("tile texcoords", bytemuck::cast_slice(uv));
    let piece_buffer = vertex("vertex pieces", bytemuck::cast_slice(ids));
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
    let mut texels = Vec::with_capacity(width as usize * height as usize);
    for row in mapped.chunks_exact(padded_row as usize) {
        texels.extend_from_slice(bytemuck::cast_slice::<u8, [u32; 4]>(
            &row[..TILE_TEXEL * width as usize],
        ));
    }
    Ok(texels)
}

/// Per group of `groups` (one per vertex of `mesh`, under `count`), the pixels whose
/// centre shows it nearest in `frame` (the mesh hiding itself, two-sided).
pub(crate) fn visible_pixels(
    frame: &SampleFrame,
    (mesh, groups, count): (&SurfaceMesh, &[u32], usize),
) -> Result<Vec<u64>> {
    let mut pixels = vec![0u64; count];
    if mesh.is_empty() {
        return Ok(pixels);
    }
    let texels = id_frame(frame, mesh, groups)?;
    for &[id, ..] in &texels {
        if let Some(n) = (id as usize).checked_sub(1).and_then(|g| pixels.get_mut(g)) {
            *n += 1;
        }
    }
    Ok(pixels)
}

/// Where `clip` puts `p` on a `width` x `height` picture: pixels from the top left,
/// y down, and depth; `None` behind the eye.
fn on_screen(clip: &Mat4, p: Vec3, (width, height): (f32, f32)) -> Option<[f32; 3]> {
    let c = *clip * p.extend(1.0);
    (c.w > 0.0).then(|| {
        [
            (c.x / c.w + 1.0) * 0.5 * width,
            (1.0 - c.y / c.w) * 0.5 * height,
            c.z / c.w,
        ]
    })
}

/// Per group of `groups` (one per vertex of `mesh`, under `count`), the area in pixels
/// its triangles cover in `view`, each counted whole whatever hides it: where
/// [`visible_pixels`] counts what is seen, this counts what could be.
pub(crate) fn projected_pixels(
    (mesh, groups, count): (&SurfaceMesh, &[u32], usize),
    view: &View,
) -> Vec<f64> {
    let camera = &view.camera;
    let (width, height) = (view.width as f32, view.height as f32);
    // Depth does not change where a point lands on the picture: any near and far do.
    let clip =
        camera.projection(width / height.max(1.0), 1.0, 2.0) * camera.view() * camera.model();
    let screen: Vec<Option<[f32; 3]>> = mesh
        .positions
        .iter()
        .map(|&p| on_screen(&clip, Vec3::from(p), (width, height)))
        .collect();
    let mut area = vec![0.0; count];
    for tri in &mesh.triangles {
        let corner = |k: usize| screen.get(tri[k] as usize).copied().flatten();
        let (Some(a), Some(b), Some(c)) = (corner(0), corner(1), corner(2)) else {
            continue;
        };
        let Some(total) = groups
            .get(tri[0] as usize)
            .and_then(|&g| area.get_mut(g as usize))
        else {
            continue;
        };
        let cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        *total += 0.5 * f64::from(cross.abs());
    }
    area
}

/// [`visible_pixels`] and [`projected_pixels`] of one view at once, per surface of
/// `surfaces` drawn in their order, each moved by its `shifts` entry, of the
/// triangles with every corner in the box `framed` (all without one); sampled on the
/// CPU: each triangle's pixel centres, the nearest surface winning (reversed depth,
/// the last drawn at equal depth, as the frame's `GreaterEqual` test), with the
/// frame's transform and depth range. On a CPU rasterizer this is the faster way: at
/// [`crate::SHARE_SIZE`] most triangles are far under a pixel, and a bounding box with
/// no pixel centre in it ends one here after a few comparisons, where the rasterizer
/// sets each up in full. One surface's vertices are projected at a time, so a view
/// holds a layer's worth of them, never a whole model's.
pub(crate) fn pixels_on_cpu(
    surfaces: &[&SurfaceMesh],
    shifts: &[Vec3],
    framed: Option<(Vec3, Vec3)>,
    view: &View,
) -> (Vec<u64>, Vec<f64>) {
    let count = surfaces.len();
    let (mut seen, mut area) = (vec![0u64; count], vec![0.0; count]);
    let camera = &view.camera;
    let (width, height) = (view.width as usize, view.height as usize);
    let (near, far) = camera.depth_range(view.bounds.0, view.bounds.1);
    let clip = camera.view_proj(view.width as f32 / view.height.max(1) as f32, near, far);
    let (w, h) = (width as f32, height as f32);
    let mut depth = vec![f32::NEG_INFINITY; width * height];
    let mut owner = vec![u32::MAX; width * height];
    // Each vertex's place [`on_screen`], none outside `framed`.
    let mut screen: Vec<Option<[f32; 3]>> = Vec::new();
    for (group, (mesh, &shift)) in surfaces.iter().zip(shifts).enumerate() {
        screen.clear();
        screen.extend(mesh.positions.iter().map(|&p| {
            let p = Vec3::from(p) + shift;
            in_box(framed, p)
                .then(|| on_screen(&clip, p, (w, h)))
                .flatten()
        }));
        for tri in &mesh.triangles {
            let corner = |k: usize| screen.get(tri[k] as usize).copied().flatten();
            let (Some(a), Some(b), Some(c)) = (corner(0), corner(1), corner(2)) else {
                continue;
            };
            let edge = |p: [f32; 3], q: [f32; 3], x: f32, y: f32| {
                (q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0])
            };
            let twice = edge(a, b, c[0], c[1]);
            area[group] += 0.5 * f64::from(twice.abs());
            if twice == 0.0 || !twice.is_finite() {
                continue;
            }
            // Pixel centres (x + 0.5, y + 0.5) inside the box.
            let lo = |v: f32| (v - 0.5).ceil().max(0.0);
            let hi = |v: f32, size: f32| (v - 0.5).floor().min(size - 1.0);
            let (x0, x1) = (
                lo(a[0].min(b[0]).min(c[0])),
                hi(a[0].max(b[0]).max(c[0]), w),
            );
            let (y0, y1) = (
                lo(a[1].min(b[1]).min(c[1])),
                hi(a[1].max(b[1]).max(c[1]), h),
            );
            if x0 > x1 || y0 > y1 {
                continue;
            }
            let inv = 1.0 / twice;
            for y in y0 as usize..=y1 as usize {
                let py = y as f32 + 0.5;
                for x in x0 as usize..=x1 as usize {
                    let px = x as f32 + 0.5;
                    // Barycentric weights, all of one sign inside whichever way it turns.
                    let (wa, wb, wc) = (
                        edge(b, c, px, py) * inv,
                        edge(c, a, px, py) * inv,
                        edge(a, b, px, py) * inv,
                    );
                    if wa < 0.0 || wb < 0.0 || wc < 0.0 {
                        continue;
                    }
                    let z = wa * a[2] + wb * b[2] + wc * c[2];
                    let at = y * width + x;
                    if z >= depth[at] {
                        depth[at] = z;
                        owner[at] = group as u32;
                    }
                }
            }
        }
    }
    for &g in &owner {
        if let Some(n) = seen.get_mut(g as usize) {
            *n += 1;
        }
    }
    (seen, area)
}
