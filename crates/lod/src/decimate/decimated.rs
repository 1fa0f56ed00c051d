//! What a decimation hands back: the simplified mesh, how its vertices relate to the
//! input's, and where the time went.

use strata_grid::SurfaceMesh;

use crate::{CellCover, MaybeIndex};

/// A simplified mesh and how it relates to its input.
#[derive(Clone, Debug)]
pub struct Decimated {
    /// The simplified mesh (no cell faces: its triangles are no longer cell halves).
    pub mesh: SurfaceMesh,
    /// Per vertex: the input vertex it is, unchanged, or none for a vertex a collapse
    /// placed on the reference surface or that moved off it ([`crate::Options::lift`],
    /// [`crate::fit::fit`]).
    pub source: Vec<MaybeIndex>,
    /// Per vertex: a triangle of the reference surface the vertex lies on.
    pub home: Vec<u32>,
    /// The largest error of an accepted collapse: the square root of the quadric's
    /// area-weighted mean squared distance (position with z scaled, texture
    /// coordinates and scalar in length units), in display length units.
    pub error: f32,
    /// Collapses made (0 from meshoptimizer's simplifiers).
    pub collapses: usize,
    /// Input vertices on outlines, holes and fault traces (on an edge without a
    /// single neighbour), and locked ones: at least the outline corners, so where
    /// every piece has an outline (a reservoir layer's always has), a target of this
    /// many triangles or more can keep them all ([`crate::measure::outline_bound`]
    /// counts exactly, at the cost of another pass over the mesh). 0 from
    /// meshoptimizer's simplifiers.
    pub outline_vertices: usize,
    /// With [`crate::Options::cover`], the input's cells, which the decimation kept covered:
    /// the renderer's mask (with [`Decimated::pieces`]).
    pub cover: Option<CellCover>,
    /// Where the time went, for profiling.
    pub timings: Timings,
}

impl Decimated {
    /// Per vertex, its piece of `cover`, the [`CellCover`] of `input`, the surface
    /// this was simplified from: its own piece, or for a new vertex that of the input
    /// triangle it lies on (`u32::MAX` where neither is known, which the renderer
    /// refuses).
    pub fn pieces(&self, input: &SurfaceMesh, cover: &CellCover) -> Vec<u32> {
        self.source
            .iter()
            .zip(&self.home)
            .map(|(&source, &home)| {
                let v = source.get().unwrap_or_else(|| {
                    input
                        .triangles
                        .get(home as usize)
                        .map_or(u32::MAX, |t| t[0])
                });
                cover
                    .vertex_piece
                    .get(v as usize)
                    .copied()
                    .unwrap_or(u32::MAX)
            })
            .collect()
    }
}

/// Seconds spent in each stage of a decimation, and the number of passes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timings {
    /// Preparing the reference surface (triangle adjacency).
    pub reference: f64,
    /// Quadrics, boundary and vertex lists.
    pub setup: f64,
    /// Evaluating every edge, each pass (and renumbering the live vertices first,
    /// once enough are gone).
    pub evaluate: f64,
    /// Choosing and making the collapses (sorting included), each pass.
    pub collapse: f64,
    /// The final fit ([`crate::Options::lift`]), and locating the input's vertices on the
    /// result where [`crate::decimate_chosen`] fits it to them.
    pub lift: f64,
    /// Passes over the edges.
    pub passes: usize,
}
