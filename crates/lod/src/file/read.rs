//! Opening a hierarchy file: mapping it, checking its tables and trees so that no
//! later read goes out of bounds, and reading its records and meshes in place.

use std::fs::File;
use std::path::{Path, PathBuf};

use memmap2::Mmap;
use strata_grid::faults::Segment;
use strata_grid::outline::OutlineEdge;
use strata_grid::{CellFace, Content, HIERARCHY_MAGIC, SurfaceMesh};

use super::format::{
    HAS_SCALARS, HEADER_BYTES, Header, Indices, LAYER_BYTES, LayerRecord, NODE_BYTES, NodeRecord,
    OUTLINE_EDGE_WORDS, STRAY_CORNERS, VERSION, Vertex, layer_cells_bytes, layer_sides_bytes,
    read_outline_edge,
};
use crate::{Error, Result};

/// Bytes of a fault trace segment as stored: two points of three f32.
const SEGMENT_BYTES: u64 = std::mem::size_of::<Segment>() as u64;

/// A hierarchy file, memory mapped.
pub struct LodFile {
    pub(super) path: PathBuf,
    pub(super) map: Mmap,
    pub(super) header: Header,
}

impl LodFile {
    /// Maps `path` and checks its tables (not the node data: indices are checked when
    /// a node's mesh is read).
    pub fn open(path: &Path) -> Result<Self> {
        let file = File::open(path).map_err(|e| Error::io(path, e))?;
        // SAFETY: the map is read-only; if another process truncates the file while it
        // is mapped, reads fault (as with any mapped file); its contents are checked
        // before use below and when node data is read.
        let map = unsafe { Mmap::map(&file) }.map_err(|e| Error::io(path, e))?;
        let bad = |at: u64, message: &str| Error::Format {
            path: path.to_path_buf(),
            at,
            message: message.to_string(),
        };
        let len = map.len() as u64;
        let head = map
            .get(..HEADER_BYTES)
            .ok_or_else(|| bad(0, "shorter than a hierarchy's header"))?;
        let header: Header = bytemuck::pod_read_unaligned(head);
        if header.magic != HIERARCHY_MAGIC {
            return Err(bad(
                0,
                &format!(
                    "wrong magic bytes: this is {}, not a hierarchy; `strata lod build MODEL -o \
                     FILE` makes one of a model",
                    Content::of(&map).describe()
                ),
            ));
        }
        if header.version != VERSION {
            return Err(bad(
                8,
                &format!(
                    "version {} (this reader knows {VERSION}): build it again with `strata lod build`",
                    header.version
                ),
            ));
        }
        let table_end = |offset: u64, count: u32, size: usize| {
            offset
                .checked_add(u64::from(count) * size as u64)
                .filter(|&end| end <= len && offset.is_multiple_of(8))
        };
        if table_end(header.layers_offset, header.layer_count, LAYER_BYTES).is_none() {
            return Err(bad(64, "layer table outside the file"));
        }
        if table_end(header.nodes_offset, header.node_count, NODE_BYTES).is_none() {
            return Err(bad(72, "node table outside the file"));
        }
        let out = LodFile {
            path: path.to_path_buf(),
            map,
            header,
        };
        let node_count = header.node_count;
        for (i, n) in out.nodes().iter().enumerate() {
            let at = header.nodes_offset + (NODE_BYTES * i) as u64;
            let data = u64::from(n.vertex_count) * 24
                + u64::from(n.index_count) * u64::from(n.index_width);
            let fits = n.data_offset.is_multiple_of(8)
                && matches!(n.index_width, 2 | 4)
                && n.index_count.is_multiple_of(3)
                && n.data_offset
                    .checked_add(data)
                    .is_some_and(|end| end <= len)
                && n.layer < header.layer_count
                && n.cells[0] <= n.cells[2]
                && n.cells[1] <= n.cells[3]
                && n.cells[2] <= header.dims[0]
                && n.cells[3] <= header.dims[1]
                && u64::from(n.first_child) + u64::from(n.child_count) <= u64::from(node_count)
                && (n.child_count == 0 || n.first_child as usize > i);
            if !fits {
                return Err(bad(at, &format!("node {i} is inconsistent")));
            }
        }
        let cells_bytes = layer_cells_bytes(u64::from(header.dims[0]) * u64::from(header.dims[1]));
        for (l, layer) in out.layers().iter().enumerate() {
            let at = header.layers_offset + (LAYER_BYTES * l) as u64;
            if layer.node_count == 0
                || u64::from(layer.root) + u64::from(layer.node_count) > u64::from(node_count)
            {
                return Err(bad(at, "layer's nodes outside the node table"));
            }
            let cells_fit = if out.has_scalars() {
                layer.cells_offset >= HEADER_BYTES as u64
                    && layer.cells_offset.is_multiple_of(8)
                    && layer
                        .cells_offset
                        .checked_add(cells_bytes)
                        .is_some_and(|end| end <= len)
            } else {
                layer.cells_offset == 0
            };
            if !cells_fit {
                return Err(bad(at, &format!("layer {l}: cells outside the file")));
            }
            // A section of `bytes` at `offset`: none (offset 0) when it has no items,
            // else 8-byte aligned, after the header and within the file.
            let fits = |items: u32, offset: u64, bytes: u64| {
                if items == 0 {
                    offset == 0
                } else {
                    offset >= HEADER_BYTES as u64
                        && offset.is_multiple_of(8)
                        && offset.checked_add(bytes).is_some_and(|end| end <= len)
                }
            };
            let sides_fit = fits(
                layer.side_faces,
                layer.sides_offset,
                layer_sides_bytes(layer.side_vertices, layer.side_faces),
            ) && (layer.side_faces > 0 || layer.side_vertices == 0);
            if !sides_fit {
                return Err(bad(at, &format!("layer {l}: sides outside the file")));
            }
            let faults_fit = fits(
                layer.fault_segments,
                layer.faults_offset,
                SEGMENT_BYTES * u64::from(layer.fault_segments),
            );
            if !faults_fit {
                return Err(bad(
                    at,
                    &format!("layer {l}: fault traces outside the file"),
                ));
            }
            let outline_fit = fits(
                layer.outline_edges,
                layer.outline_offset,
                4 * OUTLINE_EDGE_WORDS as u64 * u64::from(layer.outline_edges),
            );
            if !outline_fit {
                return Err(bad(
                    at,
                    &format!("layer {l}: outline edges outside the file"),
                ));
            }
        }
        out.check_tree()?;
        Ok(out)
    }

    /// Checks that each layer's nodes form its quadtree: the layer's own nodes, each
    /// child one level below its parent and within its cells, leaves (and only
    /// leaves) on level 0. Selection and the readers of a selection's cells rely on
    /// it; a damaged file would otherwise draw a cell twice or not at all.
    fn check_tree(&self) -> Result<()> {
        let nodes = self.nodes();
        let bad = |i: usize, message: String| self.damaged(self.node_record_at(i as u32), message);
        for (l, layer) in self.layers().iter().enumerate() {
            let own = layer.root as usize..(layer.root + layer.node_count) as usize;
            for i in own.clone() {
                let n = &nodes[i];
                if n.layer as usize != l {
                    return Err(bad(
                        i,
                        format!("node {i} of layer {l} names layer {}", n.layer),
                    ));
                }
                if (n.child_count == 0) != (n.level == 0) {
                    return Err(bad(
                        i,
                        format!(
                            "node {i}: level {} with {} children",
                            n.level, n.child_count
                        ),
                    ));
                }
                let children = n.first_child as usize..(n.first_child + n.child_count) as usize;
                for (c, child) in children.clone().zip(&nodes[children]) {
                    let message = if !own.contains(&c) {
                        format!("node {c}, a child of node {i}, is not one of layer {l}'s nodes")
                    } else if child.level != n.level - 1 {
                        format!(
                            "node {c} is on level {}, its parent node {i} on level {}",
                            child.level, n.level
                        )
                    } else if !(0..2).all(|a| {
                        n.cells[a] <= child.cells[a] && child.cells[a + 2] <= n.cells[a + 2]
                    }) {
                        format!("node {c}'s cells are outside its parent node {i}'s")
                    } else {
                        continue;
                    };
                    return Err(bad(c, message));
                }
            }
        }
        Ok(())
    }

    /// The file this was opened from, for messages.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Display-frame origin that positions are relative to.
    pub fn origin(&self) -> [f64; 3] {
        self.header.origin
    }

    /// Cells of the grid along i and j.
    pub fn dims(&self) -> [u32; 2] {
        self.header.dims
    }

    /// Cells along each side of a leaf tile.
    pub fn tile_cells(&self) -> u32 {
        self.header.tile_cells
    }

    /// Whether vertices carry the property's value (and layers their cells).
    pub fn has_scalars(&self) -> bool {
        self.header.flags & HAS_SCALARS != 0
    }

    /// Smallest and largest value of the stored property over the model's active
    /// cells; `None` without a property, or when the file holds no finite range.
    pub fn scalar_range(&self) -> Option<(f32, f32)> {
        let [lo, hi] = self.header.scalar_range;
        (self.has_scalars() && lo.is_finite() && hi.is_finite() && lo <= hi).then_some((lo, hi))
    }

    /// The box views frame, when the model has stray corners: that of its corners
    /// but the stray ones (display frame, least then greatest corner), as `strata
    /// render` frames the model. `None` for a sound model, whose every point is
    /// framed, or when the stored box is not a box.
    pub fn framed(&self) -> Option<[[f32; 3]; 2]> {
        let [lo, hi] = self.header.framed;
        (self.header.flags & STRAY_CORNERS != 0
            && (0..3).all(|a| lo[a].is_finite() && hi[a].is_finite() && lo[a] <= hi[a]))
        .then_some([lo, hi])
    }

    /// The layer surfaces, in place in the mapped file.
    pub fn layers(&self) -> &[LayerRecord] {
        let o = self.header.layers_offset as usize;
        bytemuck::cast_slice(&self.map[o..o + LAYER_BYTES * self.header.layer_count as usize])
    }

    /// The nodes of all layer surfaces, in place in the mapped file.
    pub fn nodes(&self) -> &[NodeRecord] {
        let o = self.header.nodes_offset as usize;
        bytemuck::cast_slice(&self.map[o..o + NODE_BYTES * self.header.node_count as usize])
    }

    /// The cells of layer surface `l` over the (i, j) domain, row by row (in place in
    /// the mapped file): a bit per cell, set where the surface has the cell's face, and
    /// the property's value on each; `None` without a property.
    pub fn layer_cells(&self, l: usize) -> Option<(&[u32], &[f32])> {
        if !self.has_scalars() {
            return None;
        }
        let o = self.layers()[l].cells_offset as usize;
        let cells = self.header.dims[0] as usize * self.header.dims[1] as usize;
        let values = o + 4 * cells.div_ceil(32);
        Some((
            bytemuck::cast_slice(&self.map[o..values]),
            bytemuck::cast_slice(&self.map[values..values + 4 * cells]),
        ))
    }

    /// The fault traces of layer surface `l` (`strata_grid::faults`), found at full
    /// resolution when it was built, in the display frame of the file's origin.
    /// (In place in the mapped file: its offset was checked 8-byte aligned on opening.)
    pub fn layer_faults(&self, l: usize) -> &[Segment] {
        let layer = &self.layers()[l];
        let o = layer.faults_offset as usize;
        bytemuck::cast_slice(
            &self.map[o..o + SEGMENT_BYTES as usize * layer.fault_segments as usize],
        )
    }

    /// The outline edges of layer surface `l` (`strata_grid::outline`), found at full
    /// resolution when it was built, in the display frame of the file's origin.
    pub fn layer_outline(&self, l: usize) -> Vec<OutlineEdge> {
        let layer = &self.layers()[l];
        let o = layer.outline_offset as usize;
        let bytes = &self.map[o..o + 4 * OUTLINE_EDGE_WORDS * layer.outline_edges as usize];
        let words: &[u32] = bytemuck::cast_slice(bytes);
        words
            .chunks_exact(OUTLINE_EDGE_WORDS)
            .map(read_outline_edge)
            .collect()
    }

    /// The side faces of layer surface `l`'s grid layer (outer shell and fault walls,
    /// as `strata_grid::side_surfaces` makes them) at full resolution, with their cells
    /// and values; `None` where it has none (bottom surfaces, layers without side
    /// faces). Fails when an index is out of range.
    pub fn layer_sides(&self, l: usize) -> Result<Option<SurfaceMesh>> {
        let layer = &self.layers()[l];
        if layer.side_faces == 0 {
            return Ok(None);
        }
        let faces = layer.side_faces as usize;
        let o = layer.sides_offset as usize;
        let indices_at = o + 24 * layer.side_vertices as usize;
        let cells_at = indices_at + 24 * faces;
        let values_at = cells_at + 8 * faces;
        let vertices: &[Vertex] = bytemuck::cast_slice(&self.map[o..indices_at]);
        let indices: &[u32] = bytemuck::cast_slice(&self.map[indices_at..cells_at]);
        let cells: &[[u32; 2]] = bytemuck::cast_slice(&self.map[cells_at..values_at]);
        let values: &[f32] = bytemuck::cast_slice(&self.map[values_at..values_at + 4 * faces]);
        if let Some(&v) = indices.iter().find(|&&v| v as usize >= vertices.len()) {
            return Err(self.damaged(
                layer.sides_offset,
                format!("layer {l}: side index {v} of {} vertices", vertices.len()),
            ));
        }
        let mut mesh = SurfaceMesh::with_origin(self.origin());
        mesh.positions = vertices.iter().map(|v| v.position).collect();
        mesh.texcoords = vertices.iter().map(|v| v.texcoord).collect();
        if self.has_scalars() {
            mesh.scalars = vertices.iter().map(|v| v.scalar).collect();
        }
        mesh.triangles = indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        mesh.cell_faces = (0..faces)
            .map(|f| CellFace {
                triangles: [2 * f as u32, 2 * f as u32 + 1],
                cell: [cells[f][0], cells[f][1], layer.k],
                value: values[f],
            })
            .collect();
        Ok(Some(mesh))
    }

    /// The stored vertices of node `i` (in place in the mapped file).
    pub fn vertices(&self, i: usize) -> &[Vertex] {
        let n = &self.nodes()[i];
        let o = n.data_offset as usize;
        bytemuck::cast_slice(&self.map[o..o + 24 * n.vertex_count as usize])
    }

    /// The stored indices of node `i` (in place in the mapped file).
    pub fn indices(&self, i: usize) -> Indices<'_> {
        let n = &self.nodes()[i];
        let o = n.data_offset as usize + 24 * n.vertex_count as usize;
        let bytes = &self.map[o..o + n.index_width as usize * n.index_count as usize];
        if n.index_width == 2 {
            Indices::U16(bytemuck::cast_slice(bytes))
        } else {
            Indices::U32(bytemuck::cast_slice(bytes))
        }
    }

    /// Node `i` as a mesh; fails when an index is out of range.
    pub fn mesh(&self, i: usize) -> Result<SurfaceMesh> {
        let mut mesh = SurfaceMesh::with_origin(self.origin());
        self.append_to(i, &mut mesh)?;
        Ok(mesh)
    }

    pub(super) fn append_to(&self, i: usize, mesh: &mut SurfaceMesh) -> Result<()> {
        let vertices = self.vertices(i);
        let indices = self.indices(i);
        let base = mesh.vertex_count() as u32;
        if let Some(k) = (0..indices.len()).find(|&k| indices.get(k) as usize >= vertices.len()) {
            return Err(self.damaged(
                self.nodes()[i].data_offset,
                format!(
                    "node {i}: index {} of {} vertices",
                    indices.get(k),
                    vertices.len()
                ),
            ));
        }
        let scalars = self.has_scalars();
        if scalars && mesh.scalars.len() < mesh.positions.len() {
            mesh.scalars.resize(mesh.positions.len(), f32::NAN);
        }
        for v in vertices {
            mesh.positions.push(v.position);
            mesh.texcoords.push(v.texcoord);
            if scalars {
                mesh.scalars.push(v.scalar);
            }
        }
        for k in (0..indices.len()).step_by(3) {
            mesh.triangles.push([
                base + indices.get(k),
                base + indices.get(k + 1),
                base + indices.get(k + 2),
            ]);
        }
        Ok(())
    }

    /// Node `i`, or an error naming it.
    pub(super) fn node(&self, i: u32) -> Result<&NodeRecord> {
        self.nodes()
            .get(i as usize)
            .ok_or_else(|| Error::Option(format!("no node {i}")))
    }

    /// The error for damage found at byte `at` of the file once it is open.
    pub(super) fn damaged(&self, at: u64, message: String) -> Error {
        Error::Format {
            path: self.path.clone(),
            at,
            message,
        }
    }

    /// Where node `i`'s record is in the file.
    pub(super) fn node_record_at(&self, i: u32) -> u64 {
        self.header.nodes_offset + NODE_BYTES as u64 * u64::from(i)
    }
}
