//! Edge-collapse decimation that keeps the global texture coordinates (and so the
//! original grid lines) where they were on the surface.
//!
//! * Error: generalized quadrics over position, texture coordinates and scalar
//!   ([`crate::quadric`]), plus boundary planes along outlines, holes and fault traces.
//! * Placement: the new vertex of a collapse is a texture coordinate — the quadric's
//!   minimum over the texture plane of the collapse (the plane through the edge's
//!   triangle, parameterised by texture coordinates) on that triangle's side of the
//!   edge, else the best point of the edge,
//!   else an endpoint, whichever costs least — and its position and scalar are those
//!   of the *reference* (original) surface there ([`Reference`]). Every vertex stays
//!   on the original surface with exactly its interpolated attributes, until a last
//!   step ([`Options::lift`]) moves interior vertices along the surface normal, by at
//!   most their error, to fit the simplified surface to the input's vertices, so that
//!   it passes through the original where it curves instead of lying on one side.
//! * Topology: boundary vertices only slide along their boundary (half-edge collapses
//!   onto a neighbour on it), an interior edge between two boundary vertices never
//!   collapses (that would pinch a hole shut or stitch the two sides of a fault), two
//!   boundaries that run together (a seam: one vertex on either side at each place,
//!   as where a layer pinches out between two side walls) slide together or not at
//!   all, so that no crack opens between them, the link condition keeps the surface
//!   manifold, and every triangle a collapse changes must keep the orientation of its
//!   normal and of its texture-space image, so nothing folds over and the texture
//!   parameterisation stays one-to-one. With [`Options::cover`] a boundary slides
//!   only where the surface gains area, over cells it does not cover, for a renderer
//!   that masks fragments by cell.
//! * Order and speed: collapses run in passes, as in meshoptimizer. A pass evaluates
//!   every edge and collapses them, up to what the target still needs and under an
//!   error bound of 3 times the cost of the last collapse the target would need
//!   (meshoptimizer's is 1.5; [`PASS_ERROR_BOUND`] says why; never below the last
//!   pass's, and twice it after a pass that stalled);
//!   the two ends of a collapse are left alone for the rest of the pass. Cheapest
//!   first, but in surface order where that is the same thing: a few rounds take the
//!   edges that are the cheapest at both their ends in the order of the triangles,
//!   block by block of neighbouring edges, then what is left goes by cost (on a
//!   2M-triangle layer, whose vertex data no cache holds, the rounds and then the
//!   blocks each made the collapse stage much faster; `docs/performance.md`). Every
//!   check reads the triangles as they are at that moment, so the collapses of one
//!   pass compose soundly. A greedy binary heap orders the collapses slightly better
//!   but was measured many times slower here: every pop walks a heap of several
//!   megabytes that no cache holds, while a pass streams through flat arrays
//!   (vertex-to-triangle lists in compressed rows, rebuilt between passes; the live
//!   vertices renumbered densely once most are gone, and the data of the next
//!   triangles and collapses prefetched), and collapses allocate nothing.

mod checks;
mod collapse;
mod collapser;
mod decimated;
mod evaluate;
mod frame;
mod lift;
mod options;
mod passes;
mod setup;
mod vector;

use std::time::Instant;

use strata_grid::SurfaceMesh;

pub use decimated::{Decimated, Timings};
pub(crate) use frame::Frame;
pub use options::{Options, Placement};
pub(crate) use setup::coincident;
pub(crate) use vector::{cross3, dot3, sub3p};

use crate::Result;
use crate::measure::Located;
use crate::reference::{Reference, VertexTriangles};
use collapser::Collapser;

/// Simplifies `mesh` on itself as the reference surface, with no locked vertex.
pub fn decimate(mesh: &SurfaceMesh, options: &Options) -> Result<Decimated> {
    let start = Instant::now();
    let (reference, vt) = Reference::with_vertex_triangles(mesh)?;
    let (decimated, _) = decimate_prepared(
        &reference,
        vt,
        options,
        start.elapsed().as_secs_f64(),
        false,
    )?;
    Ok(decimated)
}

/// [`decimate`] of the mesh `reference` was prepared from (with its vertex triangles
/// `vt`), which took `prepared` seconds; with `locate_input`, also the input's
/// vertices located on the result ([`Collapser::located`]), the samples of a
/// [`crate::fit::fit`] of it to the original grid nodes.
pub(crate) fn decimate_prepared(
    reference: &Reference,
    vt: VertexTriangles,
    options: &Options,
    prepared: f64,
    locate_input: bool,
) -> Result<(Decimated, Option<Located>)> {
    let start = Instant::now();
    let home = reference.vertex_triangle.clone();
    let topology = Some((reference.adjacency.as_slice(), vt));
    let collapser = Collapser::new(reference.mesh(), &home, reference, &[], options, topology)?;
    let setup = start.elapsed().as_secs_f64();
    let (mut out, located) = collapser.run(locate_input)?;
    out.timings.reference = prepared;
    out.timings.setup = setup;
    Ok((out, located))
}

/// Simplifies `mesh`, whose vertex `v` lies on triangle `home[v]` of `reference`,
/// keeping every vertex with `locked[v]` (`locked` may be empty: none). New vertices
/// are placed on `reference`; this is how the levels of a hierarchy all stay on the
/// original surface although each is simplified from the one below.
pub fn decimate_on(
    mesh: &SurfaceMesh,
    home: &[u32],
    reference: &Reference,
    locked: &[bool],
    options: &Options,
) -> Result<Decimated> {
    let start = Instant::now();
    let collapser = Collapser::new(mesh, home, reference, locked, options, None)?;
    let setup = start.elapsed().as_secs_f64();
    let (mut out, _) = collapser.run(false)?;
    out.timings.setup = setup;
    Ok(out)
}
