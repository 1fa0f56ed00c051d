//! What the techniques that draw edges (`bias`, `dist`, `idbuffer`) and the quality
//! reference share: the table of a mesh's real edges with the triangles on either
//! side, storage buffers split into chunks that fit a binding, and a pipeline builder
//! with the depth and blend settings those techniques vary.
//!
//! A quad mesh's diagonals are never edges here (DESIGN.md section 3: comparisons are
//! only fair when every technique draws cell edges only), and an edge's two opposite
//! vertices are kept so that shaders can tell contour edges (Rossignac & van
//! Emmerik's CEHS/CEHD) per frame: the edge is on the outline when it has one
//! triangle, on the silhouette when its two triangles face opposite ways.

use std::collections::HashMap;
use std::hash::Hash;
use std::sync::{Arc, Mutex, PoisonError};

use strata_grid::SurfaceMesh;
use wgpu::util::DeviceExt;

use super::texture::scalar_at;
use super::{DEPTH_FORMAT, PipelineContext, frame_target};
use crate::{Error, Gpu, Result};

/// "No vertex": the far side of an outline edge.
pub(crate) const NONE: u32 = u32::MAX;

/// The real edges of a mesh, each once.
pub(crate) struct EdgeTable {
    /// Per edge: its two vertices, then the vertex opposite it in each of its two
    /// triangles ([`NONE`] for the second on the outline, and where more than two
    /// triangles share the edge, so that such edges count as contours).
    pub edges: Vec<[u32; 4]>,
    /// Per edge: the triangles on either side ([`NONE`] as above).
    pub triangles: Vec<[u32; 2]>,
    /// Per triangle and edge `e` (corner `e` to `e + 1`): the vertex opposite that
    /// edge in the neighbouring triangle, [`NONE`] on the outline.
    pub across: Vec<[u32; 3]>,
}

impl EdgeTable {
    /// Builds the table by sorting the triangles' edges by their vertex pair. Vertices
    /// at the same position count as one: meshes that paint cells flat give every
    /// cell face its own vertices (`SurfaceMesh::with_cell_values`), and the cells'
    /// common edges must still be found (else every edge would be an outline).
    pub fn new(mesh: &SurfaceMesh) -> Self {
        let masks = mesh.edge_mask();
        let mut first_at: HashMap<[u32; 3], u32> = HashMap::with_capacity(mesh.vertex_count());
        let weld: Vec<u32> = mesh
            .positions
            .iter()
            .enumerate()
            .map(|(v, p)| *first_at.entry(p.map(f32::to_bits)).or_insert(v as u32))
            .collect();
        let mut sides: Vec<(u64, u32)> = Vec::with_capacity(3 * mesh.triangles.len());
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for e in 0..3 {
                let (a, b) = (weld[tri[e] as usize], weld[tri[(e + 1) % 3] as usize]);
                let key = (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
                sides.push((key, 3 * t as u32 + e as u32));
            }
        }
        sides.sort_unstable();
        let mut table = EdgeTable {
            edges: Vec::with_capacity(sides.len() / 2 + 1),
            triangles: Vec::with_capacity(sides.len() / 2 + 1),
            across: vec![[NONE; 3]; mesh.triangles.len()],
        };
        let opposite = |te: u32| {
            let (t, e) = (te / 3, te % 3);
            mesh.triangles[t as usize][(e as usize + 2) % 3]
        };
        for group in sides.chunk_by(|a, b| a.0 == b.0) {
            let first = group[0].1;
            let (t0, e0) = ((first / 3) as usize, (first % 3) as usize);
            if let [(_, a), (_, b)] = group {
                table.across[(*a / 3) as usize][(*a % 3) as usize] = opposite(*b);
                table.across[(*b / 3) as usize][(*b % 3) as usize] = opposite(*a);
            }
            let real = group
                .iter()
                .any(|&(_, te)| masks[(te / 3) as usize] & (1 << (te % 3)) != 0);
            if !real {
                continue;
            }
            let tri = mesh.triangles[t0];
            let (o1, t1) = match group {
                [_, (_, b)] => (opposite(*b), *b / 3),
                _ => (NONE, NONE),
            };
            table
                .edges
                .push([tri[e0], tri[(e0 + 1) % 3], opposite(first), o1]);
            table.triangles.push([t0 as u32, t1]);
        }
        table
    }
}

/// Per triangle, what the pulling vertex shaders read (`TriangleRecord` in
/// lines.wgsl): its vertices and real-edge mask (bit e: edge from corner e to e + 1),
/// then the vertex across each edge and the triangle's polygon.
pub(crate) fn triangle_records(mesh: &SurfaceMesh, table: &EdgeTable) -> Vec<[u32; 8]> {
    let masks = mesh.edge_mask();
    let polygons = polygon_ids(mesh);
    mesh.triangles
        .iter()
        .zip(&masks)
        .zip(&table.across)
        .zip(&polygons)
        .map(|(((t, m), a), p)| [t[0], t[1], t[2], u32::from(*m), a[0], a[1], a[2], *p])
        .collect()
}

/// The polygon of each triangle: its cell face's index for triangles of cell faces,
/// else one past the faces plus the triangle's own index (plain triangle meshes).
pub(crate) fn polygon_ids(mesh: &SurfaceMesh) -> Vec<u32> {
    let faces = mesh.cell_faces.len() as u32;
    let mut ids: Vec<u32> = (0..mesh.triangles.len() as u32)
        .map(|t| faces + t)
        .collect();
    for (f, face) in mesh.cell_faces.iter().enumerate() {
        for t in face.triangles {
            if let Some(id) = ids.get_mut(t as usize) {
                *id = f as u32;
            }
        }
    }
    ids
}

/// Splits `count` items, each needing `bytes_per_item` in its largest per-item
/// storage buffer, into ranges whose buffers fit the adapter's binding limit.
pub(crate) fn chunks(
    gpu: &Gpu,
    count: usize,
    bytes_per_item: usize,
) -> Vec<std::ops::Range<usize>> {
    let limit = gpu.limits.max_storage_buffer_binding_size as usize;
    let per = (limit / bytes_per_item.max(1)).max(1);
    (0..count.div_ceil(per))
        .map(|c| c * per..((c + 1) * per).min(count))
        .collect()
}

/// A read-only storage buffer holding `data`, refused when it exceeds a binding.
pub(crate) fn storage(gpu: &Gpu, label: &str, data: &[u8]) -> Result<wgpu::Buffer> {
    let limit = gpu.limits.max_storage_buffer_binding_size;
    if data.len() as u64 > limit {
        return Err(Error::Invalid(format!(
            "{label}: a storage buffer of {} bytes exceeds this adapter's binding limit of {limit}",
            data.len()
        )));
    }
    // wgpu refuses empty bindings: an empty range gets one unused word.
    let contents: &[u8] = if data.is_empty() { &[0; 4] } else { data };
    Ok(gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        }))
}

/// The vertex data every technique that pulls its vertices reads (group 1, bindings 0
/// and 1 of lines.wgsl and of `vs_texgs`): positions, xyz packed, and per-vertex
/// scalars.
pub(crate) struct PulledVertices {
    pub positions: wgpu::Buffer,
    pub scalars: wgpu::Buffer,
}

/// Bytes of one vertex in the larger of [`PulledVertices`]' buffers (xyz).
const POSITION_BYTES: usize = std::mem::size_of::<[f32; 3]>();

impl PulledVertices {
    /// All the vertices of `mesh` ([`Self::gather`] of every one, without copying the
    /// positions first).
    fn whole(gpu: &Gpu, mesh: &SurfaceMesh, label: &str) -> Result<Self> {
        let scalars: Vec<f32> = (0..mesh.vertex_count())
            .map(|v| scalar_at(mesh, v))
            .collect();
        Ok(PulledVertices {
            positions: storage(gpu, label, bytemuck::cast_slice(&mesh.positions))?,
            scalars: storage(gpu, label, bytemuck::cast_slice(&scalars))?,
        })
    }

    /// The vertices `which` of `mesh`, in that order.
    fn gather(gpu: &Gpu, mesh: &SurfaceMesh, which: &[u32], label: &str) -> Result<Self> {
        let positions: Vec<[f32; 3]> = which.iter().map(|&v| mesh.positions[v as usize]).collect();
        let scalars: Vec<f32> = which.iter().map(|&v| scalar_at(mesh, v as usize)).collect();
        Ok(PulledVertices {
            positions: storage(gpu, label, bytemuck::cast_slice(&positions))?,
            scalars: storage(gpu, label, bytemuck::cast_slice(&scalars))?,
        })
    }

    fn bytes(&self) -> u64 {
        self.positions.size() + self.scalars.size()
    }
}

/// Fields of a [`triangle_records`] record that name vertices: its corners and the
/// vertices across its edges.
pub(crate) const TRIANGLE_RECORD_VERTICES: [usize; 6] = [0, 1, 2, 4, 5, 6];

/// Fields of an [`EdgeTable`] edge that name vertices: all four.
pub(crate) const EDGE_VERTICES: [usize; 4] = [0, 1, 2, 3];

/// A mesh whose vertices a technique pulls from storage, cut with the technique's
/// triangles or edges into chunks that each fit one binding.
///
/// While the vertices fit one binding, every chunk shares them and the items keep the
/// mesh's vertex numbers. Beyond (about 11 M vertices at 128 MiB; meshes that paint
/// cells flat have four per cell face), each chunk gets its own copy of the vertices
/// its items name, renumbered in the order the items first name them. The meshes here
/// run in (i, j) order, so a chunk's items name a compact band of vertices and the
/// copies add little beyond the chunks' shared borders.
pub(crate) struct PulledMesh<'m> {
    mesh: &'m SurfaceMesh,
    label: &'m str,
    /// The whole mesh's vertices, when they fit one binding.
    shared: Option<PulledVertices>,
    /// Bytes of vertex data uploaded so far.
    bytes: u64,
    /// Per mesh vertex, its number in the chunk being cut ([`NONE`] outside it).
    local: Vec<u32>,
}

/// Items of one chunk (triangle or edge records) and the vertices they pull.
pub(crate) struct PulledChunk<'c, const N: usize> {
    /// Which of the items given to [`PulledMesh::for_each_chunk`] this chunk holds.
    pub range: std::ops::Range<usize>,
    /// Those items, their vertex fields numbering `vertices`.
    pub items: &'c [[u32; N]],
    pub vertices: &'c PulledVertices,
}

impl<const N: usize> PulledChunk<'_, N> {
    /// A bind group of the chunk's vertices (bindings 0 and 1) and the technique's
    /// own buffers at theirs.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        own: &[(u32, &wgpu::Buffer)],
    ) -> wgpu::BindGroup {
        let mut entries = vec![(0, &self.vertices.positions), (1, &self.vertices.scalars)];
        entries.extend_from_slice(own);
        bind_buffers(device, label, layout, &entries)
    }
}

impl<'m> PulledMesh<'m> {
    pub fn new(gpu: &Gpu, mesh: &'m SurfaceMesh, label: &'m str) -> Result<Self> {
        let limit = gpu.limits.max_storage_buffer_binding_size as usize;
        let shared = if mesh.vertex_count() * POSITION_BYTES <= limit {
            Some(PulledVertices::whole(gpu, mesh, label)?)
        } else {
            None
        };
        Ok(PulledMesh {
            mesh,
            label,
            bytes: shared.as_ref().map_or(0, |v| v.bytes()),
            shared,
            local: Vec::new(),
        })
    }

    /// Cuts `items`, whose fields `vertex_fields` name vertices of the mesh (or
    /// [`NONE`]), into chunks whose buffers fit one binding: the technique's own
    /// per-item buffers, `item_bytes` per item at most, and the vertices they pull.
    /// Hands each chunk to `each` in order; only one chunk's copies live at a time.
    pub fn for_each_chunk<const N: usize>(
        &mut self,
        gpu: &Gpu,
        items: &[[u32; N]],
        vertex_fields: &[usize],
        item_bytes: usize,
        mut each: impl FnMut(PulledChunk<'_, N>) -> Result<()>,
    ) -> Result<()> {
        if let Some(shared) = &self.shared {
            for range in chunks(gpu, items.len(), item_bytes) {
                each(PulledChunk {
                    items: &items[range.clone()],
                    range,
                    vertices: shared,
                })?;
            }
            return Ok(());
        }
        // Every item may name vertices no other item of its chunk names.
        let per_item = item_bytes.max(vertex_fields.len() * POSITION_BYTES);
        self.local.resize(self.mesh.vertex_count(), NONE);
        for range in chunks(gpu, items.len(), per_item) {
            let mut named: Vec<u32> = Vec::new();
            let renumbered: Vec<[u32; N]> = items[range.clone()]
                .iter()
                .map(|item| {
                    let mut item = *item;
                    for &field in vertex_fields {
                        let v = item[field];
                        if v == NONE {
                            continue;
                        }
                        let slot = &mut self.local[v as usize];
                        if *slot == NONE {
                            *slot = named.len() as u32;
                            named.push(v);
                        }
                        item[field] = *slot;
                    }
                    item
                })
                .collect();
            for &v in &named {
                self.local[v as usize] = NONE;
            }
            let vertices = PulledVertices::gather(gpu, self.mesh, &named, self.label)?;
            self.bytes += vertices.bytes();
            each(PulledChunk {
                range,
                items: &renumbered,
                vertices: &vertices,
            })?;
        }
        Ok(())
    }

    /// Bytes of vertex data uploaded, shared or per chunk.
    pub fn bytes(&self) -> u64 {
        self.bytes
    }
}

/// Refuses a mesh with nothing to draw.
pub(crate) fn check_mesh(mesh: &SurfaceMesh) -> Result<()> {
    if mesh.triangles.is_empty() {
        return Err(Error::Invalid(
            "nothing to draw: the mesh has no triangles".into(),
        ));
    }
    mesh.validate().map_err(Error::Invalid)
}

/// A bind group layout of read-only storage buffers at `bindings`, seen by `visibility`.
pub(crate) fn storage_layout(
    device: &wgpu::Device,
    label: &str,
    bindings: &[u32],
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = bindings
        .iter()
        .map(|&binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: true },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        })
        .collect();
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &entries,
    })
}

/// A bind group of whole buffers at their bindings.
fn bind_buffers(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    buffers: &[(u32, &wgpu::Buffer)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = buffers
        .iter()
        .map(|(binding, b)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: b.as_entire_binding(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// The WGSL of one of these techniques: the shared frame code, the shared line code,
/// then the technique's own.
pub(crate) fn shader(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(
            [
                include_str!("common.wgsl"),
                include_str!("lines.wgsl"),
                source,
            ]
            .concat()
            .into(),
        ),
    })
}

/// Colour writes blended "over" (alpha blending), as every frame item draws.
pub(crate) const BLEND_OVER: Option<wgpu::BlendState> = Some(wgpu::BlendState::ALPHA_BLENDING);

/// How one pass of a technique rasterizes, tests depth and writes colour.
pub(crate) struct PassSpec<'a> {
    pub label: &'a str,
    pub module: &'a wgpu::ShaderModule,
    pub vs: &'a str,
    pub fs: &'a str,
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    pub extra_layouts: &'a [&'a wgpu::BindGroupLayout],
    pub topology: wgpu::PrimitiveTopology,
    /// Depth test against the frame's reversed depth (`None`: no depth attachment).
    pub depth: Option<(wgpu::CompareFunction, bool)>,
    pub bias: wgpu::DepthBiasState,
    /// Colour targets: the frame's by default ([`frame_target`]).
    pub targets: Vec<Option<wgpu::ColorTargetState>>,
    /// Values of the shader's `override` constants.
    pub constants: &'a [(&'a str, f64)],
}

impl<'a> PassSpec<'a> {
    /// A triangle-list pass into the frame's colour and depth, depth tested as every
    /// frame item is (reversed depth: nearer is greater), blended over.
    pub fn new(label: &'a str, module: &'a wgpu::ShaderModule, vs: &'a str, fs: &'a str) -> Self {
        PassSpec {
            label,
            module,
            vs,
            fs,
            buffers: &[],
            extra_layouts: &[],
            topology: wgpu::PrimitiveTopology::TriangleList,
            depth: Some((wgpu::CompareFunction::GreaterEqual, true)),
            bias: Default::default(),
            targets: vec![frame_target(BLEND_OVER)],
            constants: &[],
        }
    }

    pub fn build(
        &self,
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
    ) -> wgpu::RenderPipeline {
        let mut layouts: Vec<Option<&wgpu::BindGroupLayout>> = vec![Some(frame_layout)];
        layouts.extend(self.extra_layouts.iter().map(|l| Some(*l)));
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(self.label),
            bind_group_layouts: &layouts,
            immediate_size: 0,
        });
        let options = wgpu::PipelineCompilationOptions {
            constants: self.constants,
            ..Default::default()
        };
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(self.label),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: self.module,
                entry_point: Some(self.vs),
                compilation_options: options.clone(),
                buffers: self.buffers,
            },
            primitive: wgpu::PrimitiveState {
                topology: self.topology,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: self.depth.map(|(compare, write)| wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(write),
                depth_compare: Some(compare),
                stencil: Default::default(),
                bias: self.bias,
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: self.module,
                entry_point: Some(self.fs),
                compilation_options: options,
                targets: &self.targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

/// A technique's pipelines, built on first use: a technique has many variants
/// (hidden-line styles, line widths) of which a frame uses one or two, and building a
/// pipeline compiles shaders, which takes a while on the CPU rasterizers.
pub(crate) struct LazyPipelines<K> {
    device: wgpu::Device,
    frame_layout: wgpu::BindGroupLayout,
    built: Mutex<HashMap<K, wgpu::RenderPipeline>>,
    #[allow(clippy::type_complexity)]
    make:
        Box<dyn Fn(K, &wgpu::Device, &wgpu::BindGroupLayout) -> wgpu::RenderPipeline + Send + Sync>,
}

impl<K: Copy + Eq + Hash> LazyPipelines<K> {
    pub fn new(
        ctx: &PipelineContext,
        make: impl Fn(K, &wgpu::Device, &wgpu::BindGroupLayout) -> wgpu::RenderPipeline
        + Send
        + Sync
        + 'static,
    ) -> Arc<Self> {
        Arc::new(LazyPipelines {
            device: ctx.gpu.device.clone(),
            frame_layout: ctx.frame_layout.clone(),
            built: Mutex::new(HashMap::new()),
            make: Box::new(make),
        })
    }

    /// The pipeline of variant `key`.
    pub fn get(&self, key: K) -> wgpu::RenderPipeline {
        self.built
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .entry(key)
            .or_insert_with(|| (self.make)(key, &self.device, &self.frame_layout))
            .clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quad_grid_has_cell_edges_only_with_their_neighbours() {
        // 3 x 2 cells: 4 * 2 + 3 * 3 = 17 cell edges, no diagonal.
        let mesh = SurfaceMesh::structured(3, 2, |i, j| [i as f32, j as f32, 0.0]);
        let table = EdgeTable::new(&mesh);
        assert_eq!(table.edges.len(), 17);
        for [a, b, _, _] in &table.edges {
            let (pa, pb) = (mesh.positions[*a as usize], mesh.positions[*b as usize]);
            let axis_aligned = pa[0] == pb[0] || pa[1] == pb[1];
            assert!(axis_aligned, "diagonal {pa:?} {pb:?} listed as an edge");
        }
        let outline = table.edges.iter().filter(|e| e[3] == NONE).count();
        assert_eq!(outline, 2 * 3 + 2 * 2);
        // Interior edges have their two opposite vertices on either side.
        for [a, b, o0, o1] in table.edges.iter().filter(|e| e[3] != NONE) {
            let p = |v: &u32| mesh.positions[*v as usize];
            let side = |o: &u32| {
                let (pa, pb, po) = (p(a), p(b), p(o));
                (pb[0] - pa[0]) * (po[1] - pa[1]) - (pb[1] - pa[1]) * (po[0] - pa[0])
            };
            assert!(side(o0) * side(o1) < 0.0);
        }
        // Every triangle knows its neighbour across the diagonal.
        assert!(table.across.iter().all(|a| a.iter().any(|&v| v != NONE)));
    }

    #[test]
    fn cells_with_their_own_vertices_share_edges_by_position() {
        let mesh = SurfaceMesh::structured(3, 2, |i, j| [i as f32, j as f32, 0.0]);
        let flat = mesh.with_cell_values();
        assert!(flat.vertex_count() > mesh.vertex_count());
        let table = EdgeTable::new(&flat);
        assert_eq!(table.edges.len(), 17);
        assert_eq!(table.edges.iter().filter(|e| e[3] == NONE).count(), 10);
    }

    #[test]
    fn polygons_are_cell_faces_or_triangles() {
        let mut mesh = SurfaceMesh::structured(2, 1, |i, j| [i as f32, j as f32, 0.0]);
        assert_eq!(polygon_ids(&mesh), vec![0, 0, 1, 1]);
        mesh.cell_faces.clear();
        assert_eq!(polygon_ids(&mesh), vec![0, 1, 2, 3]);
    }
}
