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
//! layer faults  per layer surface with fault traces (`strata_grid::faults`, found at
//!               full resolution), after its sides: the segments' two ends (six f32
//!               each), padded to 8 bytes
//! layer outline per layer surface with outline edges (`strata_grid::outline`, found
//!               at full resolution), after its faults: 18 words an edge (ends, point
//!               inward, grid line, along i, neighbours' far ends, padding)
//! LayerRecord   64 bytes per layer surface: grid layer, face, root node, node count,
//!               offsets of its cells and sides, side vertex and face counts, offset
//!               and count of its fault segments, count and offset of its outline
//!               edges
//! NodeRecord    96 bytes per node (see the struct; its faces exposed in the stack
//!               among them)
//! ```
//!
//! Node data is written as each layer is built, so building holds one batch of layers
//! in memory, not the model's hierarchy; the tables go at the end and the header,
//! which points at them, is written last.

mod build;
mod cells;
mod format;
mod read;
mod select;
mod writer;

pub use build::{BuildReport, build_file};
pub use format::{Indices, LayerRecord, NodeRecord, Vertex};
pub use read::LodFile;
pub use select::ViewPoint;
pub use writer::partial_path;
