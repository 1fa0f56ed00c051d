//! What a decimation is asked for: its target, error bound, weights and placement,
//! and the checks that refuse options it could not honour.

use strata_grid::SurfaceMesh;

use crate::{Error, Result};

/// What to simplify to, and how errors are weighed.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Stop at this many triangles (or above it, when no valid collapse is left or the
    /// error bound is reached).
    pub target_triangles: usize,
    /// Stop before a collapse whose error (see [`crate::Decimated::error`]) exceeds this, in
    /// display length units; infinite to stop by count only.
    pub max_error: f32,
    /// Vertical exaggeration the surface is viewed with: a vertical error counts this
    /// many times a horizontal one, as it does on screen.
    pub z_scale: f32,
    /// Weight of texture-coordinate error: at 1, shifting the texture by some distance
    /// along the surface costs what moving the surface by that distance costs.
    pub texcoord_weight: f32,
    /// Weight of scalar error: at 1, changing the scalar by its whole range costs
    /// what moving the surface by one mean edge length costs.
    pub scalar_weight: f32,
    /// Weight of the boundary planes relative to the triangles' quadrics.
    pub boundary_weight: f32,
    /// Where new vertices go.
    pub placement: Placement,
    /// After the last pass, move every interior vertex along the original surface's
    /// normal, by at most its error, so that the simplified surface fits the input's
    /// vertices (least squares, each compared with the simplified surface's point of
    /// its texture coordinates): a coarse surface then passes through the original
    /// instead of lying on one side of it where it curves, and the grid lines it
    /// carries are drawn where the original draws them. With [`Placement::Surface`]
    /// the vertex keeps the texture coordinates and scalar of its point of the
    /// original, so each grid line through it is raised along the normal and no
    /// further; with [`Placement::Optimal`] it takes those of the original's point
    /// nearest it, as its placement did. (meshoptimizer's `simplify_with_update`
    /// moves its vertices too, but optimises texture coordinates as well, which moves
    /// grid lines off where the original draws them.) The reported error may grow
    /// (never past `max_error`): the fit leaves the quadrics' minima for the surface.
    /// Measured on Reek's layers at 10 % (`strata bench lod --quick`, one view), with
    /// [`Placement::Surface`]: moving each vertex to its own quadric's minimum on the
    /// normal raised the line-pixel F1 and drew the lines nearer, and this fit did
    /// both further, at a higher but still small share of a decimation's time
    /// (`docs/performance.md`, "Decimation internals").
    pub lift: bool,
    /// Let outlines, holes and fault traces move only outward, over cells that the
    /// piece of surface they bound does not cover ([`crate::CellCover`]): a boundary vertex
    /// goes onto its neighbour on the boundary only where the boundary turns away from
    /// the surface there (or runs straight), and the triangle the surface gains covers
    /// no cell of its own piece. Drawn with the renderer's cell mask, which discards
    /// the fragments of cells the piece does not cover, the outlines stay exactly where
    /// the original draws them, whatever the budget; without the mask the surface is
    /// drawn over the cells it gained. Needs a mesh made of cell faces.
    pub cover: bool,
    /// Past the target, go on with every collapse whose cost is under a millionth of
    /// the squared mean edge: on flat regions where position, texture coordinates and
    /// scalar are all affine, those that change nothing drawn. A quadric measures its
    /// cost at the vertices only, so elsewhere such collapses can still bend the
    /// surface between them: the hierarchy keeps their result only where it measured
    /// no change, which lets a coarse node over a flat layer keep little more than
    /// its outline.
    pub free_past_target: bool,
}

/// Where a collapse puts its new vertex. Either way, its texture coordinates and
/// scalar are those of the original surface at the point of the original nearest to
/// it (distances with z scaled by `z_scale`), so the grid lines through it are where
/// the original draws them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Placement {
    /// At the quadric's minimum over the texture plane of the collapse, on the
    /// original surface: every vertex keeps exactly the original's position, texture
    /// coordinates and scalar there (until [`Options::lift`]).
    #[default]
    Surface,
    /// At the quadric's minimum over the texture plane and the normal off it: the
    /// vertex may leave the original surface, by at most the error of its collapse,
    /// which lets a coarse surface pass through the original rather than lie on one
    /// side of it where it curves; its texture coordinates are those of the nearest
    /// point of the original.
    Optimal,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            target_triangles: 0,
            max_error: f32::INFINITY,
            z_scale: 1.0,
            texcoord_weight: 1.0,
            scalar_weight: 1.0,
            boundary_weight: 4.0,
            placement: Placement::default(),
            lift: true,
            cover: false,
            free_past_target: false,
        }
    }
}

impl Options {
    /// Keep `fraction` of the triangles of `mesh`.
    pub fn fraction(mesh: &SurfaceMesh, fraction: f64) -> Self {
        Options {
            target_triangles: (mesh.triangle_count() as f64 * fraction).round() as usize,
            ..Options::default()
        }
    }

    /// Keep `fraction` of the triangles of `mesh` with [`Options::cover`], weighted as
    /// measured best for it. No boundary planes: the renderer's mask draws the
    /// outlines wherever the decimated ones lie. Half the texture weight: it raised
    /// emerald's line-pixel F1 at 10 % (`strata bench lod --quick`, both views) and
    /// left Reek's as it was, and every boundary weight tried lowered emerald's
    /// (`docs/performance.md`, "Decimation internals").
    pub fn covering(mesh: &SurfaceMesh, fraction: f64) -> Self {
        Options {
            cover: true,
            boundary_weight: 0.0,
            texcoord_weight: 0.5,
            ..Options::fraction(mesh, fraction)
        }
    }

    pub(super) fn check(&self) -> Result<()> {
        let finite_pos = |name: &str, x: f32| {
            if x.is_finite() && x >= 0.0 {
                Ok(())
            } else {
                Err(Error::Option(format!(
                    "{name} must be finite and >= 0, got {x}"
                )))
            }
        };
        finite_pos("texcoord_weight", self.texcoord_weight)?;
        finite_pos("scalar_weight", self.scalar_weight)?;
        finite_pos("boundary_weight", self.boundary_weight)?;
        if !(self.z_scale.is_finite() && self.z_scale > 0.0) {
            return Err(Error::Option(format!(
                "z_scale must be finite and > 0, got {}",
                self.z_scale
            )));
        }
        if self.max_error.is_nan() || self.max_error < 0.0 {
            return Err(Error::Option(format!(
                "max_error must be >= 0, got {}",
                self.max_error
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decimate;

    #[test]
    fn options_are_checked() {
        let mesh = SurfaceMesh::structured(2, 2, |i, j| [i as f32, j as f32, 0.0]);
        let bad = Options {
            z_scale: 0.0,
            ..Options::default()
        };
        assert!(matches!(decimate(&mesh, &bad), Err(Error::Option(_))));
        let mut broken = mesh.clone();
        broken.triangles.push([0, 1, 99]);
        assert!(matches!(
            decimate(&broken, &Options::default()),
            Err(Error::Mesh(_))
        ));
    }
}
