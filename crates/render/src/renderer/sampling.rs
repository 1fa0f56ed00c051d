//! View sampling: which tiles of a decimated surface a view shows, and how much of
//! each stacked surface shows from around the model, either drawn by the adapter or
//! tested on the CPU's cores.

use glam::Vec3;
use rayon::prelude::*;
use strata_grid::SurfaceMesh;
use strata_lod::CellCover;

use super::{Renderer, View, validated};
use crate::camera::in_box;
use crate::visibility::{self, SampleFrame};
use crate::{Framing, Result, Style};

/// Directions (azimuth, elevation in degrees) from which
/// [`Renderer::visible_fractions`] looks at a model: rings of six at 30 and 70
/// degrees above and below the horizon, the steep rings turned half a step, so that
/// what shows from above and from below counts alike.
pub const SHARE_VIEWS: [(f32, f32); 24] = {
    let mut views = [(0.0, 0.0); 24];
    let elevations = [30.0, 70.0, -30.0, -70.0];
    let mut k = 0;
    while k < 24 {
        let ring = k / 6;
        let turn = if ring % 2 == 1 { 30.0 } else { 0.0 };
        views[k] = ((k % 6) as f32 * 60.0 + turn, elevations[ring]);
        k += 1;
    }
    views
};

/// Side of the square frames of [`Renderer::visible_fractions`], in pixels.
pub const SHARE_SIZE: u32 = 256;

/// Where [`Renderer::visible_fractions_by`] samples its views.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampling {
    /// Drawn by the adapter and read back.
    Adapter,
    /// Pixel centres tested against each triangle on the CPU's cores, all views at
    /// once.
    Cpu,
}

impl Renderer {
    /// Per tile of `tile` cells of each piece's box of `cover` (strata-lod's
    /// `CoverPiece::tiles`, row by row, piece after piece), whether `view` shows `mesh`
    /// in it at some pixel centre, or takes a derivative there, the mesh hiding itself
    /// (two-sided, the nearest surface wins); the cover's `vertex_piece` gives each
    /// vertex's piece. What is drawn with the mesh can only hide more. `style` is the
    /// frame's, so that its textures stay as they are.
    pub fn visible_tiles(
        &mut self,
        mesh: &SurfaceMesh,
        (cover, tile): (&CellCover, u32),
        view: &View,
        style: &Style,
    ) -> Result<Vec<bool>> {
        self.set_frame(view, style)?;
        validated(&self.gpu, || {
            visibility::visible_tiles(&self.sample_frame(view), mesh, (cover, tile))
        })
    }

    /// Per surface of `surfaces` (drawn together, under vertical exaggeration
    /// `z_scale`), the fraction of its area that the others and itself leave seen:
    /// pixels showing it over pixels its triangles cover, summed over
    /// [`SHARE_VIEWS`] around the model (each framing all of it, [`SHARE_SIZE`]
    /// pixels square). Stacked layer surfaces show whole at the top and bottom of the
    /// stack from above and below, and little of those between. A surface that covers
    /// no pixel in any view gets 0. Sampled on the CPU's cores where the adapter is a
    /// CPU rasterizer ([`Sampling::Cpu`]), else drawn by the adapter.
    ///
    /// With `framed`, a box in the first surface's frame (unscaled) that holds all
    /// but a model's stray corners, as pictures frame it ([`Framing::within`]):
    /// the views frame what is in it, and triangles with a corner outside it are
    /// neither seen nor counted. A stray corner's faces run far out of every view:
    /// on a generated model of 40 x 30 x 3 cells with one corner at a depth of 1e11,
    /// no surface came out seen at all (`render --lod` split its budget evenly), and
    /// with the corner at 1e5 the top, partly hidden, came out seen whole
    /// (`docs/performance.md`, "Decimation internals").
    pub fn visible_fractions(
        &mut self,
        surfaces: &[&SurfaceMesh],
        z_scale: f32,
        framed: Option<(Vec3, Vec3)>,
    ) -> Result<Vec<f64>> {
        let sampling = if self.gpu.info.device_type == wgpu::DeviceType::Cpu {
            Sampling::Cpu
        } else {
            Sampling::Adapter
        };
        self.visible_fractions_by(surfaces, z_scale, framed, sampling)
    }

    /// [`Renderer::visible_fractions`], sampled as `sampling` says.
    pub fn visible_fractions_by(
        &mut self,
        surfaces: &[&SurfaceMesh],
        z_scale: f32,
        framed: Option<(Vec3, Vec3)>,
        sampling: Sampling,
    ) -> Result<Vec<f64>> {
        let count = surfaces.len();
        // Each surface's positions moved to the first one's origin, as
        // `SurfaceMesh::append` moves them.
        let origin = surfaces.first().map_or([0.0; 3], |s| s.origin);
        let shifts: Vec<Vec3> = surfaces
            .iter()
            .map(|s| Vec3::from_array(std::array::from_fn(|a| (s.origin[a] - origin[a]) as f32)))
            .collect();
        let positions = || {
            surfaces
                .iter()
                .zip(&shifts)
                .flat_map(|(s, &shift)| s.positions.iter().map(move |&p| Vec3::from(p) + shift))
        };
        let framing = |direction| {
            let framing = Framing::new(z_scale, 1.0, direction);
            let mut framing = match framed {
                Some((lo, hi)) => framing.within(lo, hi),
                None => framing,
            };
            framing.add(positions());
            framing
        };
        let Some(bounds) = framing(SHARE_VIEWS[0]).bounds() else {
            return Ok(vec![0.0; count]);
        };
        let view_from = |direction| View {
            camera: framing(direction).camera(1.0),
            width: SHARE_SIZE,
            height: SHARE_SIZE,
            bounds,
        };
        let per_view: Vec<(Vec<u64>, Vec<f64>)> = match sampling {
            Sampling::Cpu => SHARE_VIEWS
                .par_iter()
                .map(|&direction| {
                    visibility::pixels_on_cpu(surfaces, &shifts, framed, &view_from(direction))
                })
                .collect(),
            Sampling::Adapter => {
                let mut all = SurfaceMesh::with_origin(origin);
                let mut groups = Vec::new();
                for (g, s) in surfaces.iter().enumerate() {
                    all.append(s);
                    groups.resize(all.vertex_count(), g as u32);
                }
                if !all.texcoords.is_empty() && all.texcoords.len() != all.vertex_count() {
                    all.texcoords.clear();
                }
                if framed.is_some() {
                    let positions = &all.positions;
                    all.triangles.retain(|t| {
                        t.iter()
                            .all(|&v| in_box(framed, positions[v as usize].into()))
                    });
                }
                let mut per_view = Vec::with_capacity(SHARE_VIEWS.len());
                for &direction in &SHARE_VIEWS {
                    let view = &view_from(direction);
                    self.set_frame(view, &Style::default())?;
                    let pixels = validated(&self.gpu, || {
                        visibility::visible_pixels(&self.sample_frame(view), (&all, &groups, count))
                    })?;
                    let area = visibility::projected_pixels((&all, &groups, count), view);
                    per_view.push((pixels, area));
                }
                per_view
            }
        };
        let (mut seen, mut covered) = (vec![0u64; count], vec![0.0f64; count]);
        for (pixels, area) in per_view {
            for g in 0..count {
                seen[g] += pixels[g];
                covered[g] += area[g];
            }
        }
        Ok(seen
            .iter()
            .zip(&covered)
            .map(|(&s, &c)| {
                if c > 0.0 {
                    (s as f64 / c).min(1.0)
                } else {
                    0.0
                }
            })
            .collect())
    }

    /// The frame last set up for `view` ([`Renderer::set_frame`]), as the visibility
    /// passes draw it.
    fn sample_frame(&self, view: &View) -> SampleFrame<'_> {
        SampleFrame {
            gpu: &self.gpu,
            layout: &self.frame_layout,
            bind_group: &self.bind_group,
            width: view.width,
            height: view.height,
        }
    }
}
