//! The global wireframe of a decimated surface drawn against the cells of the surface
//! it was simplified from: the cell cover's pieces, their masks and values packed into
//! a texture looked up by global coordinates, and the stacking that keeps separately
//! decimated layers in their original order.

use std::ops::Range;

use strata_grid::SurfaceMesh;
use strata_lod::{CellCover, CoverPiece};
use wgpu::util::DeviceExt;

use super::texture::{IndexedDraw, UNDEFINED_SCALAR, UV_ATTRIBUTES, UvVertex};
use super::{
    Drawable, FrameTargets, PipelineContext, PipelineRequest, texture_pipelines, texture_shader,
    texture_variant,
};
use crate::{Error, Gpu, Result};

/// The global wireframe over a decimated surface, drawn against the cells of the
/// surface it was simplified from (`fs_uv_cells`, and with the mask `fs_uv_cover`; the
/// `_bare` entries without the wireframe): each vertex carries its piece of
/// [`CellCover`], and a texture holds the pieces' cells and, when given, their values.
pub struct CellTechnique {
    mask: bool,
    pipelines: [wgpu::RenderPipeline; 4],
    layout: wgpu::BindGroupLayout,
}

/// Per vertex of a cell draw: its piece, and how far its surface is pushed back in
/// the depth test seen from above and from below ([`Stacking`]).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct PieceVertex {
    piece: u32,
    push: [f32; 2],
}

const PIECE_ATTRIBUTES: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![3 => Uint32, 5 => Float32x2];

/// Words per piece at the front of the cover texture (see texture.wgsl).
const COVER_HEADER: usize = 9;

/// The header word of a piece without values (`NO_VALUES` in texture.wgsl).
const NO_VALUES: u32 = u32::MAX;

/// A decimated surface drawn against the cells of the surface it was simplified from
/// ([`crate::Renderer::prepare_cells`]).
#[derive(Clone, Copy, Debug)]
pub struct CellDraw<'a> {
    /// Per vertex of the drawn mesh, its piece of `cover` (strata-lod's
    /// `Decimated::pieces`).
    pub pieces: &'a [u32],
    /// The cells of the surface the drawn one was simplified from.
    pub cover: &'a CellCover,
    /// One value per cell (`cover.values(original)` for every box): each fragment
    /// takes its cell's colour, as the original's cell faces do; elsewhere, and
    /// without them (or in a tile they leave out), the vertex scalars'.
    pub values: Option<TiledCells<'a>>,
    /// Four values per cell (`cover.corner_values(original)` for every box), of the
    /// field the frame's isolines follow: each fragment evaluates the original's field
    /// from its texture coordinates, so the isolines are the original's as the grid
    /// lines are, and none are drawn outside its cells. Without them (or in a tile they
    /// leave out), isolines follow the vertex scalars.
    pub corners: Option<TiledCells<'a>>,
    /// Discard the fragments over cells their piece does not cover: what decimation
    /// moved beyond the input's cells (outline corners cut outward; with strata-lod's
    /// `Options::cover` outlines only grow outward, and so stay exactly the input's).
    pub mask: bool,
    /// Draw the original's grid lines (the global wireframe); without, the cells'
    /// colours and the isolines only.
    pub wire: bool,
    /// The order of the model's layer surfaces drawn together, where each was
    /// decimated on its own.
    pub stacking: Option<Stacking<'a>>,
}

/// Layer surfaces decimated one by one no longer keep their order where the layers are
/// thinner than the errors: a surface pokes through the one above it, and its grid
/// lines show through that one's cells. The original's order is restored in the depth
/// test: each fragment is tested as if its surface lay `push` lower, seen from above
/// (seen from below, higher by the largest push less its own), moved along its view
/// ray so that it stays on the same pixel. Surfaces further apart than that still hide
/// each other as the nearer one does.
#[derive(Clone, Copy, Debug)]
pub struct Stacking<'a> {
    /// Per piece of [`CellDraw::cover`], the push of its surface in display units
    /// (vertical, exaggerated as drawn): 0 at the top, growing downward
    /// ([`stack_pushes`]); `None` for a piece outside the stack (side faces), never
    /// pushed.
    pub push: &'a [Option<f32>],
}

impl Stacking<'_> {
    /// Per vertex of a drawn mesh with `pieces`, the push seen from above and from
    /// below.
    fn pushes(&self, pieces: &[u32]) -> Result<Vec<[f32; 2]>> {
        let stacked = || self.push.iter().flatten().copied();
        if let Some(bad) = stacked().find(|p| !(p.is_finite() && *p >= 0.0)) {
            return Err(Error::Invalid(format!(
                "a stacking push of {bad} (not finite and at least 0)"
            )));
        }
        let deepest = stacked().fold(0.0, f32::max);
        pieces
            .iter()
            .map(|&p| {
                let push = *self.push.get(p as usize).ok_or_else(|| {
                    Error::Invalid(format!(
                        "piece {p} has no push in the stacking ({} pushes)",
                        self.push.len()
                    ))
                })?;
                Ok(push.map_or([0.0; 2], |push| [push, deepest - push]))
            })
            .collect()
    }
}

/// Per layer surface of a stack, top to bottom, its push ([`Stacking`]) from the
/// vertical error of each (how far it may lie from the original, e.g. strata-lod's
/// `Deviation::vertical`): each surface lies below the one above it by the errors of
/// both, so that neither can rise through the other.
pub fn stack_pushes(vertical_errors: &[f32]) -> Vec<f32> {
    let mut push = 0.0;
    let mut above = 0.0;
    vertical_errors
        .iter()
        .enumerate()
        .map(|(k, &e)| {
            let e = if e.is_finite() { e.max(0.0) } else { 0.0 };
            if k > 0 {
                push += above + e;
            }
            above = e;
            push
        })
        .collect()
}

/// Values on the cells of the pieces of a cell cover, for the tiles of each piece's box
/// that `of` marks (all without it). Each box is cut into squares of `tile` cells from
/// its origin (strata-lod's `CoverPiece::tiles`); the values come tile after tile, each
/// tile's cells row by row, piece after piece, a fixed number per cell (see
/// [`CellDraw`]). A view that shows a few tiles of a large piece needs only theirs.
#[derive(Clone, Copy, Debug)]
pub struct TiledCells<'a> {
    /// The values, laid out as the type's description says.
    pub values: &'a [f32],
    /// Side of the tiles in cells; `u32::MAX` for one tile per box.
    pub tile: u32,
    /// Per tile of each box (row by row, piece after piece), whether `values` hold it.
    pub of: Option<&'a [bool]>,
}

impl<'a> TiledCells<'a> {
    /// Values for every cell of every piece, box after box (as `CellCover::values`
    /// and `CellCover::corner_values` give them).
    pub fn boxes(values: &'a [f32]) -> Self {
        TiledCells {
            values,
            tile: u32::MAX,
            of: None,
        }
    }

    /// Per piece, its tiles among those `of` marks and how many values its marked ones
    /// hold at `per_cell` a cell.
    fn layout(&self, pieces: &[CoverPiece], per_cell: usize) -> Vec<(Range<usize>, usize)> {
        let mut next = 0;
        pieces
            .iter()
            .map(|p| {
                let tiles = next..next + p.tile_count(self.tile);
                next = tiles.end;
                let values = tiles
                    .clone()
                    .filter(|&t| self.of.is_none_or(|of| of.get(t) == Some(&true)))
                    .map(|t| per_cell * p.tile_cells(self.tile, t - tiles.start))
                    .sum();
                (tiles, values)
            })
            .collect()
    }

    /// The part of these for a batch: its `values` and `tiles`.
    fn part(&self, values: &Range<usize>, tiles: &Range<usize>) -> Self {
        TiledCells {
            values: &self.values[values.clone()],
            of: self.of.map(|of| &of[tiles.clone()]),
            tile: self.tile,
        }
    }
}

/// Values per cell of [`CellDraw::values`] and [`CellDraw::corners`].
const PER_CELL: [usize; 2] = [1, 4];

impl CellTechnique {
    /// The pipelines of `fs_uv_cover` with `mask`, else of `fs_uv_cells`; their
    /// `_bare` forms without `wire`.
    pub fn new(ctx: &PipelineContext, mask: bool, wire: bool) -> Self {
        let device = &ctx.gpu.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("cell cover"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 4,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Uint,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let module = texture_shader(device);
        let buffers = [
            Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<UvVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &UV_ATTRIBUTES,
            }),
            Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<PieceVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &PIECE_ATTRIBUTES,
            }),
        ];
        let fragment = match (mask, wire) {
            (true, true) => "fs_uv_cover",
            (true, false) => "fs_uv_cover_bare",
            (false, true) => "fs_uv_cells",
            (false, false) => "fs_uv_cells_bare",
        };
        let request = PipelineRequest {
            buffers: &buffers,
            extra_layouts: &[&layout],
            ..PipelineRequest::new(cells_label(mask), &module, ("vs_uv_cover", fragment))
        };
        let pipelines = texture_pipelines(ctx, &request);
        CellTechnique {
            mask,
            pipelines,
            layout,
        }
    }

    /// Uploads `mesh`, drawn against the cells of `cells` (whose mask and wire are
    /// this technique's). A cover larger than one texture of the adapter holds is cut into
    /// batches of pieces, each with its texture and draw.
    pub fn prepare(
        &self,
        gpu: &Gpu,
        mesh: &SurfaceMesh,
        cells: &CellDraw,
    ) -> Result<Box<dyn Drawable>> {
        let limit = gpu.limits.max_texture_dimension_2d as usize;
        self.prepare_batched(gpu, mesh, cells, limit.min(4096) * limit)
    }

    /// [`CellTechnique::prepare`] with cover textures of at most `texture_words`.
    fn prepare_batched(
        &self,
        gpu: &Gpu,
        mesh: &SurfaceMesh,
        cells: &CellDraw,
        texture_words: usize,
    ) -> Result<Box<dyn Drawable>> {
        let CellDraw {
            pieces,
            cover,
            values,
            corners,
            ..
        } = *cells;
        if pieces.len() != mesh.vertex_count() {
            return Err(Error::Invalid(format!(
                "{} pieces for {} vertices",
                pieces.len(),
                mesh.vertex_count()
            )));
        }
        if let Some(p) = mesh
            .triangles
            .iter()
            .flatten()
            .map(|&v| pieces[v as usize])
            .find(|&p| p as usize >= cover.pieces.len())
        {
            return Err(Error::Invalid(format!(
                "piece {p} is not in the cover ({} pieces)",
                cover.pieces.len()
            )));
        }
        let width = (gpu.limits.max_texture_dimension_2d as usize)
            .min(4096)
            .min(texture_words);
        let plan = CoverPlan::new(mesh, cells, texture_words)?;
        let device = &gpu.device;
        let mut batches = Vec::new();
        let mut texels_bytes = 0;
        for ((batch, parts), triangles) in plan
            .batches
            .iter()
            .zip(&plan.batch_fields)
            .zip(&plan.triangle_ranges)
        {
            if triangles.is_empty() {
                continue;
            }
            let mut fields = [values, corners];
            for (field, (values, tiles)) in fields.iter_mut().zip(parts) {
                *field = field.map(|f| f.part(values, tiles));
            }
            let mut texels = cover_words(&cover.pieces[batch.clone()], batch.start, fields)?;
            let rows = texels.len().div_ceil(width).max(1);
            texels.resize(width * rows, 0);
            texels_bytes += 4 * texels.len() as u64;
            let size = wgpu::Extent3d {
                width: width as u32,
                height: rows as u32,
                depth_or_array_layers: 1,
            };
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some("cell cover"),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::R32Uint,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
            gpu.queue.write_texture(
                texture.as_image_copy(),
                bytemuck::cast_slice(&texels),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * width as u32),
                    rows_per_image: Some(rows as u32),
                },
                size,
            );
            let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("cell cover"),
                layout: &self.layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&view),
                }],
            });
            batches.push((bind_group, triangles.start * 3..triangles.end * 3));
        }
        let label = cells_label(self.mask);
        let draw = IndexedDraw::of_mesh(gpu, self.pipelines.clone(), mesh, &plan.triangles, label)?;
        let pushes = match cells.stacking {
            Some(stacking) => stacking.pushes(pieces)?,
            None => vec![[0.0; 2]; pieces.len()],
        };
        let piece_vertices: Vec<PieceVertex> = pieces
            .iter()
            .zip(pushes)
            .map(|(&piece, push)| PieceVertex { piece, push })
            .collect();
        let piece_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("cover pieces"),
            contents: bytemuck::cast_slice(&piece_vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let bytes = draw.bytes + piece_buffer.size() + texels_bytes;
        Ok(Box::new(CellsDraw {
            draw,
            pieces: piece_buffer,
            batches,
            bytes,
            label,
        }))
    }
}

/// The name of a cell technique's pipelines and passes.
fn cells_label(mask: bool) -> &'static str {
    if mask {
        "global covered"
    } else {
        "global cells"
    }
}

/// How a cell draw is cut into batches of consecutive pieces whose words each fit one
/// cover texture of `capacity` words, and its triangles ordered batch by batch (each in
/// the batch of its first vertex's piece, which the flat-interpolated piece takes).
struct CoverPlan {
    batches: Vec<Range<usize>>,
    /// Per batch, for the cell values and the corner values: its pieces' values among
    /// all the pieces' and their tiles among all.
    batch_fields: Vec<[(Range<usize>, Range<usize>); 2]>,
    triangles: Vec<[u32; 3]>,
    /// Per batch, its triangles in `triangles`.
    triangle_ranges: Vec<Range<u32>>,
}

impl CoverPlan {
    fn new(mesh: &SurfaceMesh, cells: &CellDraw, capacity: usize) -> Result<Self> {
        let CellDraw {
            pieces,
            cover,
            values,
            corners,
            ..
        } = *cells;
        // Per field and piece, its tiles and the values of the marked ones.
        let fields = [values, corners];
        let mut layouts = [Vec::new(), Vec::new()];
        for (((field, per_cell), layout), name) in fields
            .iter()
            .zip(PER_CELL)
            .zip(&mut layouts)
            .zip(["cell values", "corner values"])
        {
            let Some(field) = field else {
                *layout = vec![(0..0, 0); cover.pieces.len()];
                continue;
            };
            *layout = field.layout(&cover.pieces, per_cell);
            let tile_count = layout.last().map_or(0, |(tiles, _)| tiles.end);
            if let Some(of) = field.of
                && of.len() != tile_count
            {
                return Err(Error::Invalid(format!(
                    "{name} marked for {} tiles of a cover of {tile_count}",
                    of.len()
                )));
            }
            let count: usize = layout.iter().map(|(_, values)| values).sum();
            if field.values.len() != count {
                return Err(Error::Invalid(format!(
                    "{} {name} for {count} ({per_cell} per cell of the tiles that have them)",
                    field.values.len()
                )));
            }
        }
        let mut batches: Vec<Range<usize>> = Vec::new();
        let mut batch_fields: Vec<[(Range<usize>, Range<usize>); 2]> = Vec::new();
        let mut batch_of_piece = Vec::with_capacity(cover.pieces.len());
        let mut words = 1;
        let mut value_ends = [0; 2];
        for (i, p) in cover.pieces.iter().enumerate() {
            let parts = [0, 1].map(|k| &layouts[k][i]);
            let w = COVER_HEADER
                + p.bits.len()
                + parts
                    .iter()
                    .map(|(tiles, values)| field_words(tiles, *values))
                    .sum::<usize>();
            if 1 + w > capacity {
                return Err(Error::Invalid(format!(
                    "piece {i} of the cell cover takes {w} words, more than this adapter's \
                     texture holds ({capacity})"
                )));
            }
            let ranges = [0, 1].map(|k| {
                let (tiles, values) = parts[k];
                let values = value_ends[k]..value_ends[k] + values;
                value_ends[k] = values.end;
                (values, tiles.clone())
            });
            match (batches.last_mut(), batch_fields.last_mut()) {
                (Some(b), Some(f)) if words + w <= capacity => {
                    b.end = i + 1;
                    for (f, (values, tiles)) in f.iter_mut().zip(ranges) {
                        f.0.end = values.end;
                        f.1.end = tiles.end;
                    }
                    words += w;
                }
                _ => {
                    batches.push(i..i + 1);
                    batch_fields.push(ranges);
                    words = 1 + w;
                }
            }
            batch_of_piece.push(batches.len() as u32 - 1);
        }
        let batch_of = |tri: &[u32; 3]| batch_of_piece[pieces[tri[0] as usize] as usize] as usize;
        let mut starts = vec![0u32; batches.len() + 1];
        for tri in &mesh.triangles {
            starts[batch_of(tri) + 1] += 1;
        }
        for b in 0..batches.len() {
            starts[b + 1] += starts[b];
        }
        let mut next = starts.clone();
        let mut triangles = vec![[0; 3]; mesh.triangles.len()];
        for tri in &mesh.triangles {
            let slot = &mut next[batch_of(tri)];
            triangles[*slot as usize] = *tri;
            *slot += 1;
        }
        Ok(CoverPlan {
            triangle_ranges: starts.windows(2).map(|w| w[0]..w[1]).collect(),
            batches,
            batch_fields,
            triangles,
        })
    }
}

/// Words of a piece's field, its `tiles` and the `values` of the marked ones: a table of
/// its tiles and the values, where it has any.
fn field_words(tiles: &Range<usize>, values: usize) -> usize {
    if values > 0 { tiles.len() + values } else { 0 }
}

/// The words of a batch of `pieces`, the first of which is piece `first_piece` of the
/// cover, and of their cell values and corner values (`fields`, see [`CellDraw`]) when
/// given, as `covered_cell`, `cell_scalar` and `cell_iso` in texture.wgsl read them.
fn cover_words(
    pieces: &[CoverPiece],
    first_piece: usize,
    fields: [Option<TiledCells>; 2],
) -> Result<Vec<u32>> {
    let layouts =
        [0, 1].map(|k| fields[k].map_or_else(Vec::new, |f| f.layout(pieces, PER_CELL[k])));
    let bit_words: usize = pieces.iter().map(|p| p.bits.len()).sum();
    let header = 1 + COVER_HEADER * pieces.len();
    let field_total = |k: usize| -> usize {
        layouts[k]
            .iter()
            .map(|(tiles, values)| field_words(tiles, *values))
            .sum()
    };
    let total = header + bit_words + field_total(0) + field_total(1);
    let word = |offset: usize| {
        u32::try_from(offset)
            .ok()
            .filter(|&w| w != NO_VALUES)
            .ok_or_else(|| Error::Invalid(format!("a cell cover of {total} words (over 2^32)")))
    };
    // Each field's tile tables, then its values.
    let table_words = |k: usize| -> usize {
        layouts[k]
            .iter()
            .filter(|(_, v)| *v > 0)
            .map(|(t, _)| t.len())
            .sum()
    };
    let first_table = [header + bit_words, header + bit_words + field_total(0)];
    let first_values = [0, 1].map(|k| first_table[k] + table_words(k));
    let mut words = Vec::with_capacity(total);
    words.push(word(first_piece)?);
    let mut bits = header;
    let mut table = first_table;
    for (i, p) in pieces.iter().enumerate() {
        let mut tables = [NO_VALUES; 2];
        for k in 0..2 {
            if let Some((tiles, values)) = layouts[k].get(i)
                && *values > 0
            {
                tables[k] = word(table[k])?;
                table[k] += tiles.len();
            }
        }
        words.extend([
            p.origin[0] as u32,
            p.origin[1] as u32,
            p.size[0],
            p.size[1],
            word(bits)?,
            tables[0],
            tables[1],
            fields[0].map_or(u32::MAX, |f| f.tile),
            fields[1].map_or(u32::MAX, |f| f.tile),
        ]);
        bits += p.bits.len();
    }
    for p in pieces {
        words.extend_from_slice(&p.bits);
    }
    let scalar_bits = |v: &f32| {
        if v.is_finite() {
            v.to_bits()
        } else {
            UNDEFINED_SCALAR.to_bits()
        }
    };
    for k in 0..2 {
        let Some(field) = fields[k] else {
            continue;
        };
        let mut first = first_values[k];
        for (p, (tiles, values)) in pieces.iter().zip(&layouts[k]) {
            if *values == 0 {
                continue;
            }
            for t in tiles.clone() {
                if field.of.is_none_or(|of| of[t]) {
                    words.push(word(first)?);
                    first += PER_CELL[k] * p.tile_cells(field.tile, t - tiles.start);
                } else {
                    words.push(NO_VALUES);
                }
            }
        }
        words.extend(field.values.iter().map(scalar_bits));
    }
    Ok(words)
}

struct CellsDraw {
    draw: IndexedDraw,
    pieces: wgpu::Buffer,
    /// Per batch of pieces, its cover texture and its indices.
    batches: Vec<(wgpu::BindGroup, Range<u32>)>,
    bytes: u64,
    label: &'static str,
}

impl Drawable for CellsDraw {
    fn encode(&self, frame: &FrameTargets, encoder: &mut wgpu::CommandEncoder) {
        let d = &self.draw;
        let mut pass = frame.begin_pass(encoder, self.label);
        pass.set_pipeline(&d.pipelines[texture_variant(frame)]);
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        pass.set_vertex_buffer(0, d.vertices.slice(..));
        pass.set_vertex_buffer(1, self.pieces.slice(..));
        pass.set_index_buffer(d.indices.slice(..), wgpu::IndexFormat::Uint32);
        for (bind_group, indices) in &self.batches {
            pass.set_bind_group(1, bind_group, &[]);
            pass.draw_indexed(indices.clone(), 0, 0..1);
        }
    }

    fn triangles(&self) -> usize {
        self.draw.triangles()
    }

    fn bytes(&self) -> u64 {
        self.bytes
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use strata_grid::CellFace;

    use super::*;
    use crate::renderer::test_renderer;
    use crate::{Camera, Style, View};

    #[test]
    fn each_surface_is_pushed_below_the_one_above_by_both_errors() {
        assert_eq!(stack_pushes(&[1.0, 2.0, 0.5]), [0.0, 3.0, 5.5]);
        // An unknown error counts as none.
        assert_eq!(stack_pushes(&[f32::NAN, 1.0]), [0.0, 1.0]);
        let stacking = Stacking {
            push: &[Some(0.0), Some(3.0), Some(5.5), None],
        };
        let pushes = stacking.pushes(&[2, 0, 1, 3]).expect("pushes");
        assert_eq!(pushes, [[5.5, 0.0], [0.0, 5.5], [3.0, 2.5], [0.0, 0.0]]);
        let unknown = stacking.pushes(&[4]).expect_err("piece 4 has no push");
        assert!(unknown.to_string().contains("piece 4"), "{unknown}");
        let negative = Stacking {
            push: &[Some(-1.0)],
        }
        .pushes(&[0]);
        assert!(negative.is_err());
    }

    /// Nine separate blocks of 6 x 6 cells (cells (i, j) with i % 8 < 6 and j % 8 < 6
    /// of a flat 24 x 24 grid), valued in a pattern the zero vertex scalars do not
    /// follow.
    fn blocks() -> SurfaceMesh {
        let full = SurfaceMesh::structured(24, 24, |i, j| [i as f32, j as f32, 0.0]);
        let mut mesh = SurfaceMesh {
            scalars: vec![0.0; full.vertex_count()],
            ..full.clone()
        };
        mesh.triangles.clear();
        mesh.cell_faces.clear();
        for face in &full.cell_faces {
            let [i, j, _] = face.cell;
            if i % 8 >= 6 || j % 8 >= 6 {
                continue;
            }
            let t = mesh.triangles.len() as u32;
            mesh.triangles
                .extend(face.triangles.map(|old| full.triangles[old as usize]));
            mesh.cell_faces.push(CellFace {
                triangles: [t, t + 1],
                value: ((7 * i + 3 * j) % 5) as f32,
                ..*face
            });
        }
        mesh
    }

    /// The blocks, their cover, its cell values, and the corner values of a field other
    /// than the vertex scalars (so that isolines go through the batches too).
    fn covered_blocks() -> (SurfaceMesh, CellCover, Vec<f32>, Vec<f32>) {
        let mesh = blocks();
        let cover = CellCover::of(&mesh).expect("cell faces");
        assert_eq!(cover.pieces.len(), 9);
        let values = cover.values(&mesh).expect("values");
        let field = SurfaceMesh {
            scalars: mesh
                .positions
                .iter()
                .map(|p| 0.3 * p[0] + 0.2 * p[1])
                .collect(),
            ..mesh.clone()
        };
        let corners = cover.corner_values(&field).expect("corner values");
        (mesh, cover, values, corners)
    }

    /// Words of one block's piece: header, bits, and the values and the corners, each
    /// with a one-tile table.
    fn piece_words(cover: &CellCover) -> usize {
        COVER_HEADER + cover.pieces[0].bits.len() + 1 + 36 + 1 + 4 * 36
    }

    /// A cell draw of the blocks' `cover`, with its grid lines and no mask.
    fn cells_of<'a>(
        cover: &'a CellCover,
        values: Option<TiledCells<'a>>,
        corners: Option<TiledCells<'a>>,
    ) -> CellDraw<'a> {
        CellDraw {
            pieces: &cover.vertex_piece,
            cover,
            values,
            corners,
            mask: false,
            wire: true,
            stacking: None,
        }
    }

    /// Side of the tiles the blocks' values are cut into: four per 6 x 6 block, clipped.
    const SIDE: u32 = 4;

    /// The values of `field` (`per_cell` a cell, box after box) for the tiles of side
    /// [`SIDE`] that `marks` marks, tile after tile.
    fn tile_values(cover: &CellCover, marks: &[bool], field: &[f32], per_cell: usize) -> Vec<f32> {
        let tiles = (0..cover.pieces.len())
            .flat_map(|p| (0..cover.pieces[p].tile_count(SIDE)).map(move |t| (p, t)));
        tiles
            .zip(marks)
            .filter(|(_, m)| **m)
            .flat_map(|((p, t), _)| {
                let piece = &cover.pieces[p];
                let first: usize = cover.pieces[..p].iter().map(CoverPiece::box_cells).sum();
                let [x0, y0, x1, y1] = piece.tile_box(SIDE, t);
                (y0..y1)
                    .flat_map(move |y| {
                        (x0..x1).map(move |x| first + (y * piece.size[0] + x) as usize)
                    })
                    .flat_map(|c| field[per_cell * c..per_cell * (c + 1)].to_vec())
            })
            .collect()
    }

    /// Values in tiles of side [`SIDE`], those `of` marks (all without it).
    fn tiled<'a>(values: &'a [f32], of: Option<&'a [bool]>) -> TiledCells<'a> {
        TiledCells {
            values,
            tile: SIDE,
            of,
        }
    }

    /// Every other tile of the blocks' 36.
    fn every_other_tile() -> Vec<bool> {
        (0..36).map(|t| t % 2 == 0).collect()
    }

    #[test]
    fn a_cover_cut_into_batches_draws_as_one_texture() {
        let (mesh, cover, values, corners) = covered_blocks();
        let piece_words = piece_words(&cover);
        let mut r = test_renderer();
        let technique = CellTechnique::new(&r.context(), false, true);
        let draw = |values, corners| cells_of(&cover, values, corners);
        let (lo, hi) = mesh.bounds().expect("bounds");
        let view = View {
            camera: Camera::fit_points(
                mesh.positions.iter().map(|&p| Vec3::from(p)),
                1.0,
                1.0,
                (0.0, 89.0),
                1.0,
            ),
            width: 240,
            height: 240,
            bounds: (Vec3::from(lo), Vec3::from(hi)),
        };
        let plain = Style {
            scalar_range: Some((0.0, 4.0)),
            ..Style::default()
        };
        let with_isolines = Style {
            isolines: Some(crate::Isolines::new(1.0)),
            ..plain
        };
        let mut frame = |cells: CellDraw, words: usize, style: &Style| {
            let plan = CoverPlan::new(&mesh, &cells, words).expect("plan");
            let drawable = technique
                .prepare_batched(&r.gpu, &mesh, &cells, words)
                .expect("prepare");
            let image = r
                .render(&[drawable.as_ref()], &view, style)
                .expect("render");
            (plan.batches.len(), image)
        };
        let all = draw(
            Some(TiledCells::boxes(&values)),
            Some(TiledCells::boxes(&corners)),
        );
        let (one, whole) = frame(all, 1 << 20, &with_isolines);
        let (nine, batched) = frame(all, 1 + piece_words, &with_isolines);
        // The same values in tiles, all of them or every other one: the fragments in
        // the others follow the vertex scalars, and batches still cut the values where
        // the tiles have them.
        let marked = every_other_tile();
        let every = vec![true; 36];
        let every_value = tile_values(&cover, &every, &values, 1);
        let every_corner = tile_values(&cover, &every, &corners, 4);
        let some_values = tile_values(&cover, &marked, &values, 1);
        let some_corners = tile_values(&cover, &marked, &corners, 4);
        let (_, tiled_whole) = frame(
            draw(
                Some(tiled(&every_value, None)),
                Some(tiled(&every_corner, None)),
            ),
            1 << 20,
            &with_isolines,
        );
        let partial = draw(
            Some(tiled(&some_values, Some(&marked))),
            Some(tiled(&some_corners, Some(&marked))),
        );
        let (_, partial_whole) = frame(partial, 1 << 20, &with_isolines);
        let (_, partial_batched) = frame(partial, 1 + piece_words, &with_isolines);
        let (_, some_coloured) = frame(
            draw(
                Some(tiled(&some_values, Some(&marked))),
                Some(TiledCells::boxes(&corners)),
            ),
            1 << 20,
            &with_isolines,
        );
        let (_, no_isolines) = frame(all, 1 << 20, &plain);
        let (_, interpolated) = frame(draw(None, None), 1 << 20, &plain);
        assert_eq!((one, nine), (1, 9));
        let differing = |a: &image::RgbaImage, b: &image::RgbaImage| {
            a.pixels().zip(b.pixels()).filter(|(x, y)| x != y).count()
        };
        assert_eq!(differing(&whole, &batched), 0, "batches change the frame");
        assert_eq!(
            differing(&whole, &tiled_whole),
            0,
            "the values in tiles draw what they draw in boxes"
        );
        assert_eq!(
            differing(&partial_whole, &partial_batched),
            0,
            "batches change the frame with values for some tiles"
        );
        assert!(
            differing(&whole, &some_coloured) > 240 * 240 / 20,
            "tiles without cell values take the vertex scalars' colours"
        );
        assert!(
            differing(&some_coloured, &partial_whole) > 240 * 240 / 200,
            "tiles without corners draw the vertex scalars' isolines"
        );
        assert!(
            differing(&whole, &no_isolines) > 240 * 240 / 50,
            "the corner values draw isolines"
        );
        assert!(
            differing(&no_isolines, &interpolated) > 240 * 240 / 10,
            "the cells' values colour the frame"
        );
    }

    #[test]
    fn a_cover_plan_refuses_what_does_not_fit_the_cover_or_a_texture() {
        let (mesh, cover, values, corners) = covered_blocks();
        let all = cells_of(
            &cover,
            Some(TiledCells::boxes(&values)),
            Some(TiledCells::boxes(&corners)),
        );
        assert!(
            CoverPlan::new(&mesh, &all, piece_words(&cover)).is_err(),
            "a piece larger than a texture is refused"
        );
        let marked = every_other_tile();
        let some_corners = tile_values(&cover, &marked, &corners, 4);
        let every_value = tile_values(&cover, &[true; 36], &values, 1);
        let refused = |values, corners, why: &str| {
            let cells = cells_of(&cover, values, corners);
            assert!(CoverPlan::new(&mesh, &cells, 1 << 20).is_err(), "{why}");
        };
        refused(
            None,
            Some(TiledCells::boxes(&corners[4..])),
            "corner values of another cover",
        );
        refused(
            Some(TiledCells::boxes(&values[1..])),
            None,
            "cell values of another cover",
        );
        refused(
            None,
            Some(tiled(&some_corners, Some(&marked[1..]))),
            "marks for another number of tiles",
        );
        refused(
            Some(tiled(&every_value[1..], None)),
            None,
            "too few cell values for the tiles",
        );
    }
}
