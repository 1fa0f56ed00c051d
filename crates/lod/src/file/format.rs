//! The file's records and sizes as stored: what the writer lays down and the reader
//! maps in place (the layout is in [`super`]'s documentation).

use bytemuck::{Pod, Zeroable};

/// 2: the header ends with the property's cell range. 3: each layer surface's cells
/// and their values, which colour a selection cell by cell. 4: each grid layer's side
/// faces. 5: side faces wound counter-clockwise seen from outside their cells, so a
/// view leaves out those that turn their back to the eye. 6: the header ends with the
/// box views frame. 7: each layer surface's fault traces. 8: each node's exposed faces,
/// which let a view leave out what a closed stack hides, and each layer surface's
/// outline edges.
pub(super) const VERSION: u32 = 8;

/// Header flag: vertices carry a scalar (NaN otherwise).
pub(super) const HAS_SCALARS: u32 = 1;

/// Header flag: the model has stray corners, and views frame only `Header::framed`.
pub(super) const STRAY_CORNERS: u32 = 2;

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(super) struct Header {
    pub(super) magic: [u8; 8],
    pub(super) version: u32,
    pub(super) flags: u32,
    pub(super) origin: [f64; 3],
    pub(super) dims: [u32; 2],
    pub(super) tile_cells: u32,
    pub(super) layer_count: u32,
    pub(super) node_count: u32,
    pub(super) _pad: u32,
    pub(super) layers_offset: u64,
    pub(super) nodes_offset: u64,
    /// Smallest and largest finite value of the property over the active cells (NaN
    /// without a property): vertex scalars are averages over cells (extrapolated at
    /// borders), so only this gives the colour map the range `strata render` gives it.
    pub(super) scalar_range: [f32; 2],
    /// With [`STRAY_CORNERS`], the box of the model's corners but the stray ones
    /// (`CornerPointGrid::stray_corners`), least then greatest corner, in the display
    /// frame: what `strata render` frames, which the nodes' boxes, holding the stray
    /// corners, cannot give.
    pub(super) framed: [[f32; 3]; 2],
}

/// One layer surface of the file.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct LayerRecord {
    /// Grid layer (0-based).
    pub k: u32,
    /// 0: the layer's top faces, 1: its bottom faces.
    pub face: u32,
    /// Index of the root node.
    pub root: u32,
    /// Nodes of this layer (consecutive from the root).
    pub node_count: u32,
    /// Byte offset of the layer's cells (see the module's layout); 0 without a
    /// property.
    pub cells_offset: u64,
    /// Byte offset of grid layer `k`'s side faces, on its top surface's record; 0
    /// where there are none.
    pub sides_offset: u64,
    /// Vertices of the side faces.
    pub side_vertices: u32,
    /// Side faces, two triangles each.
    pub side_faces: u32,
    /// Byte offset of the layer surface's fault traces; 0 where there are none.
    pub faults_offset: u64,
    /// Fault trace segments (two points of three f32 each).
    pub fault_segments: u32,
    /// Outline edges (`strata_grid::outline`, 18 words each).
    pub outline_edges: u32,
    /// Byte offset of the layer surface's outline edges; 0 where there are none.
    pub outline_offset: u64,
}

/// One node of the file.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct NodeRecord {
    /// Index of the layer surface in [`crate::LodFile::layers`].
    pub layer: u32,
    /// 0 for leaves.
    pub level: u32,
    /// Tile coordinates at the node's level.
    pub tile: [u32; 2],
    /// `i0, j0, i1, j1`, ends excluded.
    pub cells: [u32; 4],
    /// Horizontal and vertical geometric error (display length units).
    pub error: [f32; 2],
    /// Least corner of the node's box (display frame, relative to the file's origin).
    pub min: [f32; 3],
    /// Greatest corner of the node's box.
    pub max: [f32; 3],
    /// Children are `first_child..first_child + child_count`.
    pub first_child: u32,
    /// Children of the node (0 for leaves).
    pub child_count: u32,
    /// Vertices stored for the node.
    pub vertex_count: u32,
    /// Indices stored for the node, three a triangle.
    pub index_count: u32,
    /// Byte offset of the vertices; the indices follow them.
    pub data_offset: u64,
    /// 2 or 4 bytes.
    pub index_width: u32,
    /// Faces of the node's cells that the grid layers above and below do not cover
    /// (where the cell above or below has no face): the only ones a closed stack
    /// shows, when it is not the top or bottom of what is drawn.
    pub exposed: u32,
}

/// Words (4 bytes) of an outline edge as stored: its ends (6 f32), the point one cell
/// inward (3 f32), its grid line and whether it runs along i (2 u32), the neighbours'
/// far ends (6 f32) and a word of padding.
pub(super) const OUTLINE_EDGE_WORDS: usize = 18;

/// An outline edge as stored.
pub(super) fn stored_outline_edge(
    e: &strata_grid::outline::OutlineEdge,
) -> [u32; OUTLINE_EDGE_WORDS] {
    let mut out = [0u32; OUTLINE_EDGE_WORDS];
    let floats = e.ends.iter().chain([&e.inward]).flatten();
    for (o, v) in out.iter_mut().zip(floats) {
        *o = v.to_bits();
    }
    out[9] = e.line;
    out[10] = u32::from(e.along_i);
    for (o, v) in out[11..17].iter_mut().zip(e.before.iter().chain(&e.after)) {
        *o = v.to_bits();
    }
    out
}

/// An outline edge read back from its stored words.
pub(super) fn read_outline_edge(w: &[u32]) -> strata_grid::outline::OutlineEdge {
    let point = |at: usize| [0, 1, 2].map(|a| f32::from_bits(w[at + a]));
    strata_grid::outline::OutlineEdge {
        ends: [point(0), point(3)],
        inward: point(6),
        line: w[9],
        along_i: w[10] != 0,
        before: point(11),
        after: point(14),
    }
}

/// Sizes of the records as stored.
pub(super) const HEADER_BYTES: usize = std::mem::size_of::<Header>();

pub(super) const LAYER_BYTES: usize = std::mem::size_of::<LayerRecord>();

pub(super) const NODE_BYTES: usize = std::mem::size_of::<NodeRecord>();

/// Bytes of a layer's cells in the file for `cells` cells of the (i, j) domain.
pub(super) fn layer_cells_bytes(cells: u64) -> u64 {
    4 * cells.div_ceil(32) + 4 * cells
}

/// Bytes of a layer's sides in the file: vertices, six indices, a cell and a value per
/// face.
pub(super) fn layer_sides_bytes(vertices: u32, faces: u32) -> u64 {
    24 * u64::from(vertices) + (24 + 8 + 4) * u64::from(faces)
}

/// A vertex as stored.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    /// Display frame, relative to the file's origin.
    pub position: [f32; 3],
    /// Global texture coordinates: `(2i + 1, 2j + 1)` at grid node `(i, j)`.
    pub texcoord: [f32; 2],
    /// The property's value (NaN without one).
    pub scalar: f32,
}

/// Indices of a node, in their stored width.
#[derive(Clone, Copy, Debug)]
pub enum Indices<'a> {
    /// Nodes of at most 65536 vertices: half the bytes.
    U16(&'a [u16]),
    /// Larger nodes.
    U32(&'a [u32]),
}

impl Indices<'_> {
    /// Number of indices.
    pub fn len(&self) -> usize {
        match self {
            Indices::U16(i) => i.len(),
            Indices::U32(i) => i.len(),
        }
    }

    /// Whether the node has no index.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Index `k`, widened to `u32`.
    pub fn get(&self, k: usize) -> u32 {
        match self {
            Indices::U16(i) => u32::from(i[k]),
            Indices::U32(i) => i[k],
        }
    }
}
