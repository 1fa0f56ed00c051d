//! The hierarchy on disk, and read back by memory mapping.
//!
//! Layout (little endian, every table and mesh 8-byte aligned, so that a mapped file
//! is used in place with no parsing or copying):
//!
//! ```text
//! Header       112 bytes  magic "STRATLOD", version, flags, origin, grid dims,
//!                         tile size, counts, offsets of the two tables, the
//!                         property's range over the active cells, the box views
//!                         frame when the model has stray corners
//! node data     per node: vertices (position, texture coordinates, scalar: 24 bytes
//!               each), then indices (u16 when the node has under 65536 vertices,
//!               else u32), padded to 8 bytes
//! layer cells   with a property, per layer surface after its nodes: a bit per cell of
//!               the (i, j) domain, row by row, set where the surface has the cell's
//!               face, then each cell's value (f32), padded to 8 bytes
//! layer sides   per grid layer with side faces (outer shell and fault walls), after
//!               its top surface's cells, at full resolution: vertices (as node
//!               data), then per face its two triangles (u32 indices, wound
//!               counter-clockwise seen from outside the face's cell), then per face
//!               its cell's (i, j) (u32 pairs), then per face the property's value
//!               (f32, NaN without one), padded to 8 bytes
//! LayerRecord   40 bytes per layer surface: grid layer, face, root node, node count,
//!               offsets of its cells and sides, side vertex and face counts
//! NodeRecord    96 bytes per node (see the struct)
//! ```
//!
//! Node data is written as each layer is built, so building holds one batch of layers
//! in memory, not the model's hierarchy; the tables go at the end and the header,
//! which points at them, is written last.

use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use bytemuck::{Pod, Zeroable};
use memmap2::Mmap;
use rayon::prelude::*;
use strata_grid::{
    CellFace, Content, CornerPointGrid, Face, HIERARCHY_MAGIC, SurfaceMesh, layer_surface,
    side_surfaces,
};

use crate::cover::cell_corners;
use crate::hierarchy::{Node, build_layer_with, layer_work};
use crate::{BuildOptions, CellCover, CoverPiece, Error, Progress, Result};

/// 2: the header ends with the property's cell range. 3: each layer surface's cells
/// and their values, which colour a selection cell by cell. 4: each grid layer's side
/// faces. 5: side faces wound counter-clockwise seen from outside their cells, so a
/// view leaves out those that turn their back to the eye. 6: the header ends with the
/// box views frame.
const VERSION: u32 = 6;
/// Header flag: vertices carry a scalar (NaN otherwise).
const HAS_SCALARS: u32 = 1;
/// Header flag: the model has stray corners, and views frame only `Header::framed`.
const STRAY_CORNERS: u32 = 2;

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Header {
    magic: [u8; 8],
    version: u32,
    flags: u32,
    origin: [f64; 3],
    dims: [u32; 2],
    tile_cells: u32,
    layer_count: u32,
    node_count: u32,
    _pad: u32,
    layers_offset: u64,
    nodes_offset: u64,
    /// Smallest and largest finite value of the property over the active cells (NaN
    /// without a property): vertex scalars are averages over cells, so only this
    /// gives the colour map the range `strata render` gives it.
    scalar_range: [f32; 2],
    /// With [`STRAY_CORNERS`], the box of the model's corners but the stray ones
    /// (`CornerPointGrid::stray_corners`), least then greatest corner, in the display
    /// frame: what `strata render` frames, which the nodes' boxes, holding the stray
    /// corners, cannot give.
    framed: [[f32; 3]; 2],
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
    pub side_vertices: u32,
    /// Side faces, two triangles each.
    pub side_faces: u32,
}

/// Sizes of the records as stored.
const HEADER_BYTES: usize = std::mem::size_of::<Header>();
const LAYER_BYTES: usize = std::mem::size_of::<LayerRecord>();
const NODE_BYTES: usize = std::mem::size_of::<NodeRecord>();

/// The cells of one layer surface over the grid's (i, j) domain: which have a face,
/// and the property's value on each.
struct LayerCells {
    faces: Vec<u32>,
    values: Vec<f32>,
}

impl LayerCells {
    fn of(mesh: &SurfaceMesh, dims: [u32; 2]) -> Self {
        let cells = dims[0] as usize * dims[1] as usize;
        let mut faces = vec![0; cells.div_ceil(32)];
        let mut values = vec![f32::NAN; cells];
        for face in &mesh.cell_faces {
            let c = face.cell[1] as usize * dims[0] as usize + face.cell[0] as usize;
            faces[c / 32] |= 1 << (c % 32);
            values[c] = face.value;
        }
        LayerCells { faces, values }
    }
}

/// Bytes of a layer's cells in the file for `cells` cells of the (i, j) domain.
fn layer_cells_bytes(cells: u64) -> u64 {
    4 * cells.div_ceil(32) + 4 * cells
}

/// Bytes of a layer's sides in the file: vertices, six indices, a cell and a value per
/// face.
fn layer_sides_bytes(vertices: u32, faces: u32) -> u64 {
    24 * u64::from(vertices) + (24 + 8 + 4) * u64::from(faces)
}

/// One node of the file.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct NodeRecord {
    /// Index of the layer surface in [`LodFile::layers`].
    pub layer: u32,
    /// 0 for leaves.
    pub level: u32,
    pub tile: [u32; 2],
    /// `i0, j0, i1, j1`, ends excluded.
    pub cells: [u32; 4],
    /// Horizontal and vertical geometric error (display length units).
    pub error: [f32; 2],
    pub min: [f32; 3],
    pub max: [f32; 3],
    /// Children are `first_child..first_child + child_count`.
    pub first_child: u32,
    pub child_count: u32,
    pub vertex_count: u32,
    pub index_count: u32,
    /// Byte offset of the vertices; the indices follow them.
    pub data_offset: u64,
    /// 2 or 4 bytes.
    pub index_width: u32,
    _pad: u32,
}

/// A selected node's box cut into tiles of the file's tile size, and where the values
/// of each tile asked for start among the node's (see [`LodFile::selection_values`]).
struct TileLayout {
    piece: CoverPiece,
    starts: Vec<Option<usize>>,
    /// Values of the node's tiles asked for.
    values: usize,
}

/// Sets the `len` bits of `dst` from bit `to` that are set in `src` from bit `from`
/// (bit `b` of a slice is bit `b % 32` of word `b / 32`), a word of `dst` at a time: a
/// row of a layer's faces into a box's bits.
fn copy_bits((src, from): (&[u32], usize), (dst, to): (&mut [u32], usize), len: usize) {
    let (mut from, mut to, mut left) = (from, to, len);
    while left > 0 {
        let n = (32 - to % 32).min(left);
        let (w, s) = (from / 32, from % 32);
        let mut chunk = src[w] >> s;
        if s + n > 32 {
            chunk |= src[w + 1] << (32 - s);
        }
        if n < 32 {
            chunk &= (1 << n) - 1;
        }
        dst[to / 32] |= chunk << (to % 32);
        (from, to, left) = (from + n, to + n, left - n);
    }
}

/// A vertex as stored.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub texcoord: [f32; 2],
    pub scalar: f32,
}

/// Indices of a node, in their stored width.
#[derive(Clone, Copy, Debug)]
pub enum Indices<'a> {
    U16(&'a [u16]),
    U32(&'a [u32]),
}

impl Indices<'_> {
    pub fn len(&self) -> usize {
        match self {
            Indices::U16(i) => i.len(),
            Indices::U32(i) => i.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn get(&self, k: usize) -> u32 {
        match self {
            Indices::U16(i) => u32::from(i[k]),
            Indices::U32(i) => i[k],
        }
    }
}

/// What [`build_file`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BuildReport {
    pub layers: usize,
    pub nodes: usize,
    /// Triangles of the layer surfaces.
    pub input_triangles: usize,
    /// Triangles stored over all levels.
    pub stored_triangles: usize,
    /// Triangles of the side faces (stored at full resolution).
    pub side_triangles: usize,
    /// Highest level (the roots').
    pub levels: u32,
    pub bytes: u64,
    pub seconds: f64,
}

/// A mesh's vertices as stored.
fn stored_vertices(mesh: &SurfaceMesh) -> Vec<Vertex> {
    (0..mesh.vertex_count())
        .map(|v| Vertex {
            position: mesh.positions[v],
            texcoord: mesh.texcoords[v],
            scalar: mesh.scalars.get(v).copied().unwrap_or(f32::NAN),
        })
        .collect()
}

/// A node as the file stores it, made as soon as its parent is built: its record (but
/// for where it goes in the file) and its data, vertices then indices padded to 8
/// bytes. A large layer's tree is held in this form while the rest of it is built:
/// 24 bytes a vertex and 2 an index, where a built node holds about 52 a vertex.
struct StoredNode {
    record: NodeRecord,
    data: Vec<u8>,
}

impl StoredNode {
    fn of(node: Node) -> Self {
        let mesh = &node.mesh;
        let mut data: Vec<u8> = bytemuck::cast_slice(&stored_vertices(mesh)).to_vec();
        let index_width = if mesh.vertex_count() <= usize::from(u16::MAX) + 1 {
            let i: Vec<u16> = mesh.triangles.iter().flatten().map(|&v| v as u16).collect();
            data.extend_from_slice(bytemuck::cast_slice(&i));
            2
        } else {
            let i: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
            data.extend_from_slice(bytemuck::cast_slice(&i));
            4
        };
        data.resize(data.len().next_multiple_of(8), 0);
        StoredNode {
            record: NodeRecord {
                layer: 0,
                level: node.level,
                tile: node.tile,
                cells: node.cells,
                error: node.error,
                min: node.bounds.0,
                max: node.bounds.1,
                first_child: 0,
                child_count: 0,
                vertex_count: mesh.vertex_count() as u32,
                index_count: 3 * mesh.triangle_count() as u32,
                data_offset: 0,
                index_width,
                _pad: 0,
            },
            data,
        }
    }
}

/// A layer surface's tree of [`StoredNode`]s, root first, breadth first, each with
/// the indices of its children.
type StoredTree = Vec<(StoredNode, Vec<u32>)>;

/// Writes a hierarchy file. It is written beside `path` under another name and
/// takes `path`'s name only once whole ([`Writer::finish`]): a build that fails leaves
/// a hierarchy already at `path` as it was, and one that succeeds replaces it without
/// truncating it under a `lod view` that has it mapped.
struct Writer {
    path: PathBuf,
    partial: PathBuf,
    out: BufWriter<File>,
    pos: u64,
    nodes: Vec<NodeRecord>,
    layers: Vec<LayerRecord>,
    /// Whether the file took its name; if not, the partial file is removed on drop.
    named: bool,
}

impl Writer {
    fn create(path: &Path) -> Result<Self> {
        let mut name = std::ffi::OsString::from(".");
        name.push(path.file_name().unwrap_or_else(|| "hierarchy".as_ref()));
        name.push(".partial");
        let partial = path.with_file_name(name);
        let file = File::create(&partial).map_err(|e| Error::io(path, e))?;
        let mut w = Writer {
            path: path.to_path_buf(),
            partial,
            out: BufWriter::with_capacity(1 << 20, file),
            pos: 0,
            nodes: Vec::new(),
            layers: Vec::new(),
            named: false,
        };
        w.write(bytemuck::bytes_of(&Header::zeroed()))?;
        Ok(w)
    }

    fn write(&mut self, bytes: &[u8]) -> Result<()> {
        self.out
            .write_all(bytes)
            .map_err(|e| Error::io(&self.path, e))?;
        self.pos += bytes.len() as u64;
        Ok(())
    }

    fn pad(&mut self) -> Result<()> {
        let n = (8 - self.pos % 8) % 8;
        self.write(&[0u8; 8][..n as usize])
    }

    fn layer(
        &mut self,
        k: u32,
        face: Face,
        tree: &StoredTree,
        cells: Option<&LayerCells>,
        sides: Option<&SurfaceMesh>,
    ) -> Result<()> {
        if tree.is_empty() {
            return Ok(());
        }
        let layer = self.layers.len() as u32;
        let base = self.nodes.len() as u32;
        for (node, children) in tree {
            let data_offset = self.pos;
            self.write(&node.data)?;
            self.nodes.push(NodeRecord {
                layer,
                first_child: children.first().map_or(0, |&c| base + c),
                child_count: children.len() as u32,
                data_offset,
                ..node.record
            });
        }
        let cells_offset = match cells {
            Some(cells) => {
                let offset = self.pos;
                self.write(bytemuck::cast_slice(&cells.faces))?;
                self.write(bytemuck::cast_slice(&cells.values))?;
                self.pad()?;
                offset
            }
            None => 0,
        };
        let (sides_offset, side_vertices, side_faces) = match sides {
            Some(sides) if !sides.cell_faces.is_empty() => {
                let offset = self.pos;
                self.write(bytemuck::cast_slice(&stored_vertices(sides)))?;
                let indices: Vec<u32> = sides
                    .cell_faces
                    .iter()
                    .flat_map(|f| f.triangles)
                    .flat_map(|t| sides.triangles[t as usize])
                    .collect();
                self.write(bytemuck::cast_slice(&indices))?;
                let cells: Vec<[u32; 2]> = sides
                    .cell_faces
                    .iter()
                    .map(|f| [f.cell[0], f.cell[1]])
                    .collect();
                self.write(bytemuck::cast_slice(&cells))?;
                let values: Vec<f32> = sides.cell_faces.iter().map(|f| f.value).collect();
                self.write(bytemuck::cast_slice(&values))?;
                self.pad()?;
                (
                    offset,
                    sides.vertex_count() as u32,
                    sides.cell_faces.len() as u32,
                )
            }
            _ => (0, 0, 0),
        };
        self.layers.push(LayerRecord {
            k,
            face: match face {
                Face::Top => 0,
                Face::Bottom => 1,
            },
            root: base,
            node_count: tree.len() as u32,
            cells_offset,
            sides_offset,
            side_vertices,
            side_faces,
        });
        Ok(())
    }

    fn finish(
        mut self,
        origin: [f64; 3],
        dims: [u32; 2],
        tile_cells: u32,
        scalar_range: Option<[f32; 2]>,
        framed: Option<[[f32; 3]; 2]>,
    ) -> Result<u64> {
        let layers_offset = self.pos;
        let layers = std::mem::take(&mut self.layers);
        self.write(bytemuck::cast_slice(&layers))?;
        self.pad()?;
        let nodes_offset = self.pos;
        let nodes = std::mem::take(&mut self.nodes);
        self.write(bytemuck::cast_slice(&nodes))?;
        let header = Header {
            magic: HIERARCHY_MAGIC,
            version: VERSION,
            flags: if scalar_range.is_some() {
                HAS_SCALARS
            } else {
                0
            } | if framed.is_some() { STRAY_CORNERS } else { 0 },
            origin,
            dims,
            tile_cells,
            layer_count: layers.len() as u32,
            node_count: nodes.len() as u32,
            _pad: 0,
            layers_offset,
            nodes_offset,
            scalar_range: scalar_range.unwrap_or([f32::NAN; 2]),
            framed: framed.unwrap_or([[f32::NAN; 3]; 2]),
        };
        let path = self.path.clone();
        let io = |e| Error::io(&path, e);
        self.out.seek(SeekFrom::Start(0)).map_err(io)?;
        self.out
            .write_all(bytemuck::bytes_of(&header))
            .map_err(io)?;
        self.out.flush().map_err(io)?;
        std::fs::rename(&self.partial, &self.path).map_err(io)?;
        self.named = true;
        Ok(self.pos)
    }
}

impl Drop for Writer {
    fn drop(&mut self) {
        if !self.named {
            // Best effort: an error here would hide the one that stopped the build.
            let _ = std::fs::remove_file(&self.partial);
        }
    }
}

/// One layer surface built for the file.
struct BuiltSurface {
    input_triangles: usize,
    k: usize,
    face: Face,
    tree: StoredTree,
    cells: Option<LayerCells>,
}

/// Bytes one layer surface's hierarchy holds per active cell while it is built: the
/// surface, its reference index and its tree. Measured: 9.9 GB over the grid for two
/// surfaces of 33 M cells built at once (149 bytes a cell); rounded up.
const BUILD_BYTES_PER_CELL: f64 = 160.0;

/// How many layer surfaces to build at once: one per thread, fewer when `memory` (bytes)
/// cannot hold that many of the largest; an error when it cannot hold one.
fn batch_size(grid: &CornerPointGrid, memory: Option<u64>) -> Result<usize> {
    let threads = rayon::current_num_threads().max(1);
    let Some(memory) = memory else {
        return Ok(threads);
    };
    let d = grid.dims();
    let largest = (0..d.nz)
        .map(|k| grid.active_count_in(k, 0..d.ny))
        .max()
        .unwrap_or(0);
    let each = largest as f64 * BUILD_BYTES_PER_CELL;
    if each > memory as f64 {
        return Err(Error::Option(format!(
            "a layer of {largest} active cells needs about {:.1} GB to build its hierarchy, \
             and {:.1} GB of memory is available",
            each / 1e9,
            memory as f64 / 1e9
        )));
    }
    Ok(((memory as f64 / each.max(1.0)) as usize).clamp(1, threads))
}

/// Builds the hierarchy of every layer surface of `grid` (the top faces of each layer
/// and the bottom faces of the last, like `strata render`), with `property` as scalar,
/// and writes it to `path`. Layers are built on all cores, in batches whose results
/// are written in layer order, so the file does not depend on the thread count.
/// [`BuildOptions::progress`] is told the tiles built, weighed by their work
/// ([`layer_work`]).
pub fn build_file(
    grid: &CornerPointGrid,
    property: Option<&str>,
    path: &Path,
    options: &BuildOptions,
) -> Result<BuildReport> {
    options.check()?;
    let start = Instant::now();
    let d = grid.dims();
    let dims = [
        u32::try_from(d.nx).map_err(|_| Error::Option(format!("nx = {} is too large", d.nx)))?,
        u32::try_from(d.ny).map_err(|_| Error::Option(format!("ny = {} is too large", d.ny)))?,
    ];
    let (view_box, stray) = grid.view_box_and_stray_corners();
    let origin = view_box.display_centre();
    let surfaces: Vec<(usize, Face)> = (0..d.nz)
        .map(|k| (k, Face::Top))
        .chain((d.nz > 0).then_some((d.nz - 1, Face::Bottom)))
        .collect();
    let tell = |progress: Progress| {
        if let Some(f) = &options.progress {
            f(progress);
        }
    };
    tell(Progress::Started {
        work: surfaces.len() as u64 * layer_work(dims, options.tile_cells),
        surfaces: surfaces.len(),
    });
    let built = |units: u64| tell(Progress::Worked(units));
    // The side faces of all layers at once, so that a vertex between two layers
    // averages the property over both, as `strata render --sides` draws it.
    let sides = sides_by_layer(&side_surfaces(grid, 0..d.nz, property, origin)?, d.nz);
    let batch = batch_size(grid, options.memory)?;
    let mut writer = Writer::create(path)?;
    let mut report = BuildReport::default();
    let mut written = 0;
    for chunk in surfaces.chunks(batch) {
        let built: Vec<BuiltSurface> = chunk
            .par_iter()
            .map(|&(k, face)| {
                let mut mesh = layer_surface(grid, k, face, property, origin)?;
                let cells = property.map(|_| LayerCells::of(&mesh, dims));
                // The tree needs no cell faces: 24 bytes a cell less while it is built.
                mesh.cell_faces = Vec::new();
                let tree = build_layer_with(&mesh, dims, options, &built, &StoredNode::of)?;
                Ok(BuiltSurface {
                    input_triangles: mesh.triangle_count(),
                    k,
                    face,
                    tree,
                    cells,
                })
            })
            .collect::<Result<_>>()?;
        for s in built {
            let tree = &s.tree;
            // A grid layer's side faces go with its top surface.
            let sides = match s.face {
                Face::Top => sides.get(s.k),
                Face::Bottom => None,
            };
            report.input_triangles += s.input_triangles;
            report.stored_triangles += tree
                .iter()
                .map(|(n, _)| n.record.index_count as usize / 3)
                .sum::<usize>();
            report.levels = report
                .levels
                .max(tree.first().map_or(0, |(n, _)| n.record.level));
            report.nodes += tree.len();
            report.layers += usize::from(!tree.is_empty());
            report.side_triangles += sides.map_or(0, SurfaceMesh::triangle_count);
            writer.layer(s.k as u32, s.face, tree, s.cells.as_ref(), sides)?;
            written += 1;
            tell(Progress::Written {
                written,
                surfaces: surfaces.len(),
                input_triangles: report.input_triangles,
                stored_triangles: report.stored_triangles,
            });
        }
    }
    let scalar_range = property.map(|name| cell_range(grid, name));
    let framed = stray.map(|s| s.rest.to_display(origin));
    report.bytes = writer.finish(origin, dims, options.tile_cells, scalar_range, framed)?;
    report.seconds = start.elapsed().as_secs_f64();
    Ok(report)
}

/// `sides`, the side faces of grid layers in layer order, cut into one mesh per grid
/// layer of `nz`; each vertex keeps its scalar.
fn sides_by_layer(sides: &SurfaceMesh, nz: usize) -> Vec<SurfaceMesh> {
    let mut out: Vec<SurfaceMesh> = (0..nz)
        .map(|_| SurfaceMesh::with_origin(sides.origin))
        .collect();
    // Per input vertex: the layer it was last taken into, and its index there.
    let mut taken = vec![(u32::MAX, 0u32); sides.vertex_count()];
    for face in &sides.cell_faces {
        let k = face.cell[2];
        let Some(mesh) = out.get_mut(k as usize) else {
            continue;
        };
        let first = mesh.triangles.len() as u32;
        for t in face.triangles {
            let triangle = sides.triangles[t as usize].map(|v| {
                let (layer, index) = &mut taken[v as usize];
                if *layer != k {
                    *layer = k;
                    *index = mesh.positions.len() as u32;
                    mesh.positions.push(sides.positions[v as usize]);
                    mesh.texcoords.push(sides.texcoords[v as usize]);
                    if let Some(&s) = sides.scalars.get(v as usize) {
                        mesh.scalars.push(s);
                    }
                }
                *index
            });
            mesh.triangles.push(triangle);
        }
        mesh.cell_faces.push(CellFace {
            triangles: [first, first + 1],
            ..*face
        });
    }
    out
}

/// Smallest and largest finite value of property `name` over the active cells (NaN
/// when there is none).
fn cell_range(grid: &CornerPointGrid, name: &str) -> [f32; 2] {
    grid.active_values(name, 0..grid.dims().nz)
        .into_iter()
        .flatten()
        .filter(|v| v.is_finite())
        .fold([f32::NAN; 2], |[lo, hi], v| [lo.min(v), hi.max(v)])
}

/// Where a frame is seen from, for choosing levels of detail.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewPoint {
    /// Eye position in the display frame *after* vertical exaggeration (as a camera
    /// fitted with that exaggeration has it).
    pub eye: [f32; 3],
    pub z_scale: f32,
    /// Vertical field of view, degrees.
    pub fov_y_deg: f32,
    /// Image height, pixels.
    pub height_px: u32,
    /// The planes that bound the picture, in the same frame as `eye`, each `(a, b, c,
    /// d)` with `a x + b y + c z + d >= 0` inside (as `Camera::frustum` of
    /// strata-render gives them): nodes wholly outside one are not chosen. `None`
    /// chooses over the whole model.
    pub frustum: Option<[[f32; 4]; 5]>,
}

impl ViewPoint {
    /// Pixels that a length `error` at distance `distance` covers.
    pub(crate) fn pixels(&self, error: f64, distance: f64) -> f64 {
        if distance <= 0.0 {
            return f64::INFINITY;
        }
        let focal = f64::from(self.height_px)
            / (2.0 * (f64::from(self.fov_y_deg).to_radians() / 2.0).tan());
        error * focal / distance
    }

    /// Whether the box `[min, max]` (unscaled) lies wholly outside one of the planes
    /// of `frustum`: then its corner furthest along the plane's normal is outside.
    fn misses(&self, min: [f32; 3], max: [f32; 3]) -> bool {
        let Some(planes) = &self.frustum else {
            return false;
        };
        let scale = [1.0, 1.0, f64::from(self.z_scale)];
        planes.iter().any(|plane| {
            let furthest: f64 = (0..3)
                .map(|a| {
                    let corner = if plane[a] >= 0.0 { max[a] } else { min[a] };
                    f64::from(plane[a]) * f64::from(corner) * scale[a]
                })
                .sum();
            furthest + f64::from(plane[3]) < 0.0
        })
    }
}

/// A hierarchy file, memory mapped.
pub struct LodFile {
    path: PathBuf,
    map: Mmap,
    header: Header,
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
            let sides_fit = if layer.side_faces == 0 {
                layer.sides_offset == 0 && layer.side_vertices == 0
            } else {
                layer.sides_offset >= HEADER_BYTES as u64
                    && layer.sides_offset.is_multiple_of(8)
                    && layer
                        .sides_offset
                        .checked_add(layer_sides_bytes(layer.side_vertices, layer.side_faces))
                        .is_some_and(|end| end <= len)
            };
            if !sides_fit {
                return Err(bad(at, &format!("layer {l}: sides outside the file")));
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

    pub fn tile_cells(&self) -> u32 {
        self.header.tile_cells
    }

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

    pub fn layers(&self) -> &[LayerRecord] {
        let o = self.header.layers_offset as usize;
        bytemuck::cast_slice(&self.map[o..o + LAYER_BYTES * self.header.layer_count as usize])
    }

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

    fn append_to(&self, i: usize, mesh: &mut SurfaceMesh) -> Result<()> {
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

    /// The coarsest nodes whose error, projected from `view`, is at most `max_pixels`
    /// (leaves where nothing coarser is good enough): a cut through each layer's tree,
    /// so every cell is drawn exactly once, except under nodes wholly outside the
    /// view's frustum, which are left out.
    pub fn select(&self, view: &ViewPoint, max_pixels: f32) -> Vec<u32> {
        let nodes = self.nodes();
        let zs = f64::from(view.z_scale);
        let eye = view.eye.map(f64::from);
        let mut out = Vec::new();
        let mut stack: Vec<u32> = self.layers().iter().map(|l| l.root).collect();
        stack.reverse();
        while let Some(i) = stack.pop() {
            let n = &nodes[i as usize];
            // Widened by the node's error, the box holds the surface it stands for.
            let (across, up) = (n.error[0], n.error[1]);
            let widen = |p: [f32; 3], sign: f32| {
                [p[0] + sign * across, p[1] + sign * across, p[2] + sign * up]
            };
            if view.misses(widen(n.min, -1.0), widen(n.max, 1.0)) {
                continue;
            }
            let error =
                (f64::from(n.error[0]).powi(2) + (zs * f64::from(n.error[1])).powi(2)).sqrt();
            // Distance from the eye to the node's box, in the exaggerated frame.
            let d2: f64 = (0..3)
                .map(|a| {
                    let s = if a == 2 { zs } else { 1.0 };
                    let (lo, hi) = (f64::from(n.min[a]) * s, f64::from(n.max[a]) * s);
                    let e = eye[a];
                    if e < lo {
                        (lo - e).powi(2)
                    } else if e > hi {
                        (e - hi).powi(2)
                    } else {
                        0.0
                    }
                })
                .sum();
            if n.child_count == 0 || view.pixels(error, d2.sqrt()) <= f64::from(max_pixels) {
                out.push(i);
            } else {
                stack.extend((n.first_child..n.first_child + n.child_count).rev());
            }
        }
        out
    }

    /// The leaf of layer surface `l` whose cells hold cell `(i, j)`, found down its
    /// tree; `None` where no tile of the layer holds it.
    pub fn leaf_of(&self, l: usize, [i, j]: [u32; 2]) -> Option<u32> {
        let nodes = self.nodes();
        let holds = |n: &NodeRecord| {
            (n.cells[0]..n.cells[2]).contains(&i) && (n.cells[1]..n.cells[3]).contains(&j)
        };
        // `open` checked that children are one level below their parents: this ends.
        let mut at = self.layers().get(l)?.root;
        loop {
            let n = nodes.get(at as usize).filter(|n| holds(n))?;
            if n.child_count == 0 {
                return Some(at);
            }
            at = (n.first_child..n.first_child + n.child_count)
                .find(|&c| nodes.get(c as usize).is_some_and(holds))?;
        }
    }

    /// The nodes `selection` in one mesh (relative to [`LodFile::origin`]).
    pub fn selection_mesh(&self, selection: &[u32]) -> Result<SurfaceMesh> {
        let mut mesh = SurfaceMesh::with_origin(self.origin());
        for &i in selection {
            if i as usize >= self.nodes().len() {
                return Err(Error::Option(format!("no node {i}")));
            }
            self.append_to(i as usize, &mut mesh)?;
        }
        Ok(mesh)
    }

    /// The cells under the nodes `selection`, for drawing
    /// [`LodFile::selection_mesh`] coloured cell by cell as the model's faces are: a
    /// piece per node (its vertices in `vertex_piece`), whose box is the node's cells
    /// and whose bits its layer's faces there. `None` without a property.
    pub fn selection_cover(&self, selection: &[u32]) -> Result<Option<CellCover>> {
        if !self.has_scalars() {
            return Ok(None);
        }
        let ni = self.header.dims[0] as usize;
        let mut cover = CellCover::default();
        for &i in selection {
            let (n, mut piece) = self.node_box(i)?;
            let Some((faces, _)) = self.layer_cells(n.layer as usize) else {
                return Ok(None);
            };
            let [i0, j0, i1, j1] = n.cells.map(|c| c as usize);
            let mut bits = vec![0u32; piece.box_cells().div_ceil(32)];
            for (y, j) in (j0..j1).enumerate() {
                copy_bits((faces, j * ni + i0), (&mut bits, y * (i1 - i0)), i1 - i0);
            }
            let index = cover.pieces.len() as u32;
            cover
                .vertex_piece
                .extend(std::iter::repeat_n(index, n.vertex_count as usize));
            piece.bits = bits;
            cover.pieces.push(piece);
        }
        Ok(Some(cover))
    }

    /// The property's value on every cell of the boxes of
    /// [`LodFile::selection_cover`], each box cut into tiles of
    /// [`LodFile::tile_cells`] (its leaves' squares, see [`CoverPiece::tiles`]), tile
    /// after tile and node after node, each tile's cells row by row; NaN where the
    /// layer has no face. Only for the tiles that `wanted` marks, one flag per tile of
    /// each box in that order (all without it): a view needs the values of the part
    /// of the model it shows. `None` without a property.
    pub fn selection_values(
        &self,
        selection: &[u32],
        wanted: Option<&[bool]>,
    ) -> Result<Option<Vec<f32>>> {
        if !self.has_scalars() {
            return Ok(None);
        }
        let side = self.tile_cells();
        let ni = self.header.dims[0] as usize;
        let layouts = self.tile_layouts(selection, wanted, 1)?;
        let mut values = Vec::with_capacity(layouts.iter().map(|l| l.values).sum());
        for (&i, layout) in selection.iter().zip(&layouts) {
            let n = self.node(i)?;
            let Some((_, layer_values)) = self.layer_cells(n.layer as usize) else {
                return Ok(None);
            };
            let piece = &layout.piece;
            for t in (0..layout.starts.len()).filter(|&t| layout.starts[t].is_some()) {
                let [x0, y0, x1, y1] = piece.tile_box(side, t).map(|c| c as usize);
                let [i0, j0] = [n.cells[0] as usize, n.cells[1] as usize];
                for j in j0 + y0..j0 + y1 {
                    let row = j * ni + i0;
                    values.extend_from_slice(&layer_values[row + x0..row + x1]);
                }
            }
        }
        Ok(Some(values))
    }

    /// The stored scalar at the four corners of every cell of the boxes of
    /// [`LodFile::selection_cover`] (each cell's as [`CellCover::corner_values`]
    /// orders them), read from the full-resolution leaves under each selected node,
    /// tile after tile as [`LodFile::selection_values`] gives values: with them the
    /// renderer draws the isolines of the model's surfaces on whatever level is
    /// chosen. Only for the tiles that `wanted` marks: the leaves under the others
    /// are not read. `None` without a property.
    pub fn selection_corners(
        &self,
        selection: &[u32],
        wanted: Option<&[bool]>,
    ) -> Result<Option<Vec<f32>>> {
        if !self.has_scalars() {
            return Ok(None);
        }
        let layouts = self.tile_layouts(selection, wanted, 4)?;
        let mut corners = vec![f32::NAN; layouts.iter().map(|l| l.values).sum()];
        let mut boxes = Vec::with_capacity(layouts.len());
        let mut rest = &mut corners[..];
        for layout in &layouts {
            let (this, next) = rest.split_at_mut(layout.values);
            boxes.push(this);
            rest = next;
        }
        selection
            .par_iter()
            .zip(&layouts)
            .zip(boxes)
            .filter(|(_, out)| !out.is_empty())
            .try_for_each(|((&i, layout), out)| self.node_corners(i, layout, out))?;
        Ok(Some(corners))
    }

    /// Per node of `selection`, its box cut into tiles and where the values of the
    /// tiles that `wanted` marks (one flag per tile of each box, node after node; all
    /// without it) start among the node's, `per_cell` to a cell.
    fn tile_layouts(
        &self,
        selection: &[u32],
        wanted: Option<&[bool]>,
        per_cell: usize,
    ) -> Result<Vec<TileLayout>> {
        let side = self.tile_cells();
        let pieces = selection
            .iter()
            .map(|&i| Ok(self.node_box(i)?.1))
            .collect::<Result<Vec<CoverPiece>>>()?;
        let tiles: usize = pieces.iter().map(|p| p.tile_count(side)).sum();
        if let Some(wanted) = wanted
            && wanted.len() != tiles
        {
            return Err(Error::Option(format!(
                "{} tiles marked of a selection of {tiles}",
                wanted.len()
            )));
        }
        let mut first_tile = 0;
        Ok(pieces
            .into_iter()
            .map(|piece| {
                let mut values = 0;
                let starts = (0..piece.tile_count(side))
                    .map(|t| {
                        wanted.is_none_or(|w| w[first_tile + t]).then(|| {
                            let start = values;
                            values += per_cell * piece.tile_cells(side, t);
                            start
                        })
                    })
                    .collect();
                first_tile += piece.tile_count(side);
                TileLayout {
                    piece,
                    starts,
                    values,
                }
            })
            .collect())
    }

    /// Node `i`, or an error naming it.
    fn node(&self, i: u32) -> Result<&NodeRecord> {
        self.nodes()
            .get(i as usize)
            .ok_or_else(|| Error::Option(format!("no node {i}")))
    }

    /// The error for damage found at byte `at` of the file once it is open.
    fn damaged(&self, at: u64, message: String) -> Error {
        Error::Format {
            path: self.path.clone(),
            at,
            message,
        }
    }

    /// Where node `i`'s record is in the file.
    fn node_record_at(&self, i: u32) -> u64 {
        self.header.nodes_offset + NODE_BYTES as u64 * u64::from(i)
    }

    /// Node `i` and the box of its cells as a piece of a selection's cover (no bits
    /// yet).
    fn node_box(&self, i: u32) -> Result<(&NodeRecord, CoverPiece)> {
        let n = self.node(i)?;
        let [i0, j0, i1, j1] = n.cells;
        let [Ok(oi), Ok(oj)] = [i0, j0].map(i32::try_from) else {
            return Err(self.damaged(
                self.node_record_at(i),
                format!("node {i}: cells from ({i0}, {j0}) are beyond a cell cover's reach"),
            ));
        };
        let piece = CoverPiece {
            origin: [oi, oj],
            size: [i1.saturating_sub(i0), j1.saturating_sub(j0)],
            bits: Vec::new(),
        };
        Ok((n, piece))
    }

    /// [`LodFile::selection_corners`] of node `i`, whose box is `piece`, into `out`,
    /// four per cell of each tile of the box that `starts` gives a place in `out`; the
    /// leaves under the other tiles are not read.
    fn node_corners(&self, i: u32, layout: &TileLayout, out: &mut [f32]) -> Result<()> {
        let TileLayout { piece, starts, .. } = layout;
        let side = self.tile_cells().max(1);
        let across = piece.tiles(side)[0];
        // Does the box of node `m` hold a tile that `starts` places?
        let wanted = |m: &NodeRecord| {
            let [i0, j0, i1, j1] = m.cells;
            let rel = |c: u32, o: i32| (i64::from(c) - i64::from(o)).max(0) as u64;
            let lo = [rel(i0, piece.origin[0]), rel(j0, piece.origin[1])];
            let hi = [rel(i1, piece.origin[0]), rel(j1, piece.origin[1])];
            let side = u64::from(side);
            (lo[1] / side..hi[1].div_ceil(side)).any(|ty| {
                (lo[0] / side..hi[0].div_ceil(side).min(u64::from(across))).any(|tx| {
                    starts
                        .get((ty * u64::from(across) + tx) as usize)
                        .is_some_and(Option::is_some)
                })
            })
        };
        let mut stack = vec![i];
        while let Some(k) = stack.pop() {
            let m = self.node(k)?;
            if !wanted(m) {
                continue;
            }
            if m.level > 0 {
                stack.extend(m.first_child..m.first_child + m.child_count);
                continue;
            }
            let vertices = self.vertices(k as usize);
            let indices = self.indices(k as usize);
            for t in 0..indices.len() / 3 {
                let tri = [0, 1, 2].map(|c| vertices.get(indices.get(3 * t + c) as usize));
                let [Some(a), Some(b), Some(c)] = tri else {
                    return Err(self.damaged(
                        m.data_offset,
                        format!("node {k}: triangle {t} names a vertex the node does not have"),
                    ));
                };
                let tri = [a, b, c];
                let slot = cell_corners(tri.map(|v| v.texcoord))
                    .and_then(|(cell, at)| Some((piece.tile_slot(side, cell)?, at)));
                let Some(((tile, slot), at)) = slot else {
                    return Err(self.damaged(
                        m.data_offset,
                        format!("node {k}: triangle {t} is not a half of a cell of node {i}"),
                    ));
                };
                if let Some(start) = starts[tile] {
                    for (v, c) in tri.iter().zip(at) {
                        out[start + 4 * slot + c] = v.scalar;
                    }
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};
    use strata_grid::synth::{SynthParams, generate};

    #[test]
    fn the_build_counts_every_tile_of_every_layer_surface_once() {
        // 10 x 7 cells in tiles of 4: 3 x 2 leaves, 2 x 1 parents, then the root and
        // the levels above it.
        assert_eq!(layer_work([10, 7], 4), 6 + 20 * (2 + 1 + 1));
        let mut grid = generate(&SynthParams {
            nx: 30,
            ny: 20,
            nz: 3,
            faults: 2,
            seed: 3,
        })
        .expect("a generated grid");
        // An empty layer still counts all its tiles, so the bar ends full.
        grid.actnum
            .slice_mut(strata_grid::ndarray::s![1, .., ..])
            .fill(false);
        let dir = tempfile::tempdir().expect("a temporary folder");
        let log = Arc::new(Mutex::new(Vec::new()));
        let tell = Arc::clone(&log);
        let options = BuildOptions {
            tile_cells: 4,
            progress: Some(Arc::new(move |p| {
                tell.lock().expect("not poisoned").push(p)
            })),
            ..BuildOptions::default()
        };
        let path = dir.path().join("counted.lod");
        let report = build_file(&grid, None, &path, &options).expect("the hierarchy is built");
        assert_eq!(report.layers, 3, "the empty layer has no surface");
        let whole = 4 * layer_work([30, 20], 4);
        let told = std::mem::take(&mut *log.lock().expect("not poisoned"));
        assert_eq!(
            told.first(),
            Some(&Progress::Started {
                work: whole,
                surfaces: 4
            })
        );
        let worked: u64 = told
            .iter()
            .map(|p| match p {
                Progress::Worked(units) => *units,
                _ => 0,
            })
            .sum();
        assert_eq!(worked, whole);
        assert!(matches!(
            told.last(),
            Some(Progress::Written {
                written: 4,
                surfaces: 4,
                ..
            })
        ));

        // Tiles of no cells are refused before anything is told.
        let none = BuildOptions {
            tile_cells: 0,
            ..options
        };
        let err = build_file(&grid, None, &path, &none).err();
        assert!(
            err.as_ref()
                .is_some_and(|e| e.to_string().contains("tile_cells must be in 1..=4096")),
            "{err:?}"
        );
        assert!(log.lock().expect("not poisoned").is_empty());
    }

    #[test]
    fn a_hierarchy_takes_its_name_only_once_written_whole() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let path = dir.path().join("model.lod");
        std::fs::write(&path, b"an earlier hierarchy").expect("written");
        let listing = || {
            let mut names: Vec<String> = std::fs::read_dir(dir.path())
                .expect("the folder lists")
                .map(|e| {
                    e.expect("an entry")
                        .file_name()
                        .to_string_lossy()
                        .into_owned()
                })
                .collect();
            names.sort();
            names
        };
        // A build that stops half way (the writer dropped unfinished).
        let mut writer = Writer::create(&path).expect("the writer starts");
        writer.write(&[1; 64]).expect("written");
        assert_eq!(listing(), [".model.lod.partial", "model.lod"]);
        drop(writer);
        assert_eq!(listing(), ["model.lod"]);
        assert_eq!(
            std::fs::read(&path).expect("reads"),
            b"an earlier hierarchy"
        );
        // One that ends replaces it.
        let writer = Writer::create(&path).expect("the writer starts");
        let bytes = writer
            .finish([0.0; 3], [1, 1], 1, None, None)
            .expect("the file is finished");
        assert_eq!(listing(), ["model.lod"]);
        assert_eq!(std::fs::metadata(&path).expect("there").len(), bytes);
        assert!(LodFile::open(&path).is_ok());
    }

    #[test]
    fn bits_are_copied_at_any_offsets_as_one_by_one() {
        // A pattern with runs and isolated bits, no period of 32.
        let src: Vec<u32> = (0..6u32)
            .map(|k| k.wrapping_mul(0x9E37_79B9) ^ 0x0F0F_3C3C)
            .collect();
        let bit = |v: &[u32], b: usize| v[b / 32] >> (b % 32) & 1;
        for from in [0, 1, 31, 32, 33, 70] {
            for to in [0, 5, 31, 32, 63] {
                for len in [0, 1, 7, 31, 32, 33, 64, 100] {
                    let mut dst = vec![0u32; 6];
                    copy_bits((&src, from), (&mut dst, to), len);
                    let mut want = vec![0u32; 6];
                    for b in 0..len {
                        want[(to + b) / 32] |= bit(&src, from + b) << ((to + b) % 32);
                    }
                    assert_eq!(dst, want, "from {from}, to {to}, {len} bits");
                }
            }
        }
    }
}
