//! Writing a hierarchy file: node data as each layer is built, the tables and header
//! last, under a temporary name until whole.

use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use bytemuck::Zeroable;
use strata_grid::faults::Segment;
use strata_grid::outline::OutlineEdge;
use strata_grid::{Face, HIERARCHY_MAGIC, SurfaceMesh};

use super::format::{
    HAS_SCALARS, Header, LayerRecord, NodeRecord, OUTLINE_EDGE_WORDS, STRAY_CORNERS, VERSION,
    Vertex, stored_outline_edge,
};
use crate::hierarchy::Node;
use crate::{Error, Result};

/// The cells of one layer surface over the grid's (i, j) domain: which have a face,
/// and the property's value on each.
pub(super) struct LayerCells {
    faces: Vec<u32>,
    values: Vec<f32>,
}

impl LayerCells {
    pub(super) fn of(mesh: &SurfaceMesh, dims: [u32; 2]) -> Self {
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
pub(super) struct StoredNode {
    pub(super) record: NodeRecord,
    data: Vec<u8>,
}

impl StoredNode {
    pub(super) fn of(node: Node) -> Self {
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
                exposed: 0,
            },
            data,
        }
    }
}

/// A layer surface's tree of [`StoredNode`]s, root first, breadth first, each with
/// the indices of its children.
pub(super) type StoredTree = Vec<(StoredNode, Vec<u32>)>;

/// Writes a hierarchy file. It is written beside `path` under another name and
/// takes `path`'s name only once whole ([`Writer::finish`]): a build that fails leaves
/// a hierarchy already at `path` as it was, and one that succeeds replaces it without
/// truncating it under a `lod view` that has it mapped.
/// The hidden file a hierarchy bound for `path` is written into until it is whole
/// (`.NAME.partial` beside it). A build that dies with its process leaves it behind;
/// whoever abandons a build removes it.
pub fn partial_path(path: &Path) -> PathBuf {
    let mut name = std::ffi::OsString::from(".");
    name.push(path.file_name().unwrap_or_else(|| "hierarchy".as_ref()));
    name.push(".partial");
    path.with_file_name(name)
}

pub(super) struct Writer {
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
    pub(super) fn create(path: &Path) -> Result<Self> {
        let partial = partial_path(path);
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

    pub(super) fn layer(
        &mut self,
        k: u32,
        face: Face,
        tree: &StoredTree,
        cells: Option<&LayerCells>,
        sides: Option<&SurfaceMesh>,
        (faults, outline): (&[Segment], &[OutlineEdge]),
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
        let faults_offset = match faults {
            [] => 0,
            _ => {
                let offset = self.pos;
                self.write(bytemuck::cast_slice(faults))?;
                self.pad()?;
                offset
            }
        };
        let outline_offset = match outline {
            [] => 0,
            _ => {
                let offset = self.pos;
                let words: Vec<[u32; OUTLINE_EDGE_WORDS]> =
                    outline.iter().map(stored_outline_edge).collect();
                self.write(bytemuck::cast_slice(&words))?;
                self.pad()?;
                offset
            }
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
            faults_offset,
            fault_segments: faults.len() as u32,
            outline_edges: outline.len() as u32,
            outline_offset,
        });
        Ok(())
    }

    pub(super) fn finish(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::LodFile;
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
}
