//! `render --lod`: a scene's surfaces decimated to one budget, split by how much of
//! each is seen, with the input's cells to colour, line and trim the result by.

use std::time::Instant;

use rayon::prelude::*;
use strata_grid::SurfaceMesh;
use strata_lod::measure::OutlineBound;
use strata_lod::measure::deviation;
use strata_lod::{CellCover, Chosen, Maker, Options, Stitched, decimate_chosen, share_surfaces};
use strata_render::{CellDraw, Renderer, Stacking, TiledCells, stack_pushes};

use super::Note;
use crate::error::Context;
use crate::surfaces::framed_box;
use crate::{Error, Result};

/// How a scene is decimated ([`crate::scene::Lod::Decimated`]).
#[derive(Clone, Copy, Debug)]
pub struct Decimation {
    /// Share of the triangles kept, in (0, 100].
    pub percent: f64,
    /// Outlines grow only outward.
    pub cover: bool,
    /// Surfaces meet again where their outlines do.
    pub stitch: bool,
}

/// What the renderer needs to draw a decimated scene against the input's cells
/// ([`CellDraw`]): per vertex its piece of those cells, the cells, and their values
/// where a property colours the scene.
pub struct SceneCells {
    pub pieces: Vec<u32>,
    pub cover: CellCover,
    /// Per piece of `cover`, the renderer's push of its surface ([`Stacking`]); none
    /// for side faces.
    pub push: Vec<Option<f32>>,
    pub values: Option<Vec<f32>>,
    /// The input's isoline field at its cells' corners, when isolines are drawn.
    pub corners: Option<Vec<f32>>,
}

impl SceneCells {
    /// What the renderer draws: with `wire`, the input's grid lines too.
    pub fn draw(&self, wire: bool) -> CellDraw<'_> {
        CellDraw {
            pieces: &self.pieces,
            cover: &self.cover,
            values: self.values.as_deref().map(TiledCells::boxes),
            corners: self.corners.as_deref().map(TiledCells::boxes),
            // Where a decimated surface leaves its piece's cells (an outline corner cut
            // outward, a hole or fault trace crossed), its global coordinates name cells
            // the input does not have there: not drawn (it raises `bench lod`'s
            // line-pixel F1; docs/performance.md).
            mask: true,
            wire,
            // Layers thinner than the decimation's error: where a surface rose
            // through the one above it, its lines showed through that one's cells
            // (Reek at 10 %; docs/performance.md).
            stacking: Some(Stacking { push: &self.push }),
        }
    }
}

/// `render --lod`: decimates the scene's `surfaces` (as
/// [`crate::surfaces::build_stacked_surfaces`] gives them, the first `stacked` the layers'
/// from the top) to `percent` of their triangles in all, split among them by the part
/// of each seen from around the model ([`Renderer::visible_fractions`],
/// `strata_lod::share_surfaces`), each surface on its own (on all cores), and appends
/// the results in order. With `cover` the outlines only grow outward; with
/// `against_cells` (or `cover`), the input's cells come back, to colour and line the
/// result by and to trim it to, with the stacked surfaces' order ([`SceneCells`]).
/// With `stitch`, the surfaces meet again where their outlines do
/// (`strata_lod::stitch`). `framed`, the box of the model's corners but its stray
/// ones in the surfaces' frame, is what the views that split the budget frame and
/// measure, as the picture frames it ([`framing_of`]).
pub fn decimate_scene(
    renderer: &mut Renderer,
    (surfaces, stacked, framed): (&[SurfaceMesh], usize, Option<[[f32; 3]; 2]>),
    decimation: &Decimation,
    z_scale: f32,
    against_cells: bool,
    notes: &mut Vec<Note>,
) -> Result<(SurfaceMesh, Option<SceneCells>)> {
    let &Decimation {
        percent,
        cover,
        stitch,
    } = decimation;
    let start = Instant::now();
    let total: usize = surfaces.iter().map(SurfaceMesh::triangle_count).sum();
    let visible = if surfaces.len() > 1 {
        renderer
            .visible_fractions(
                &surfaces.iter().collect::<Vec<_>>(),
                z_scale,
                framed.map(framed_box),
            )
            .context("measuring how much of each surface is seen")?
    } else {
        vec![1.0; surfaces.len()]
    };
    let shares = share_surfaces(percent / 100.0, surfaces, &visible);
    let measured = start.elapsed().as_secs_f64();
    let mut chosen = surfaces
        .par_iter()
        .zip(&shares)
        .map(|(mesh, &target)| {
            let fraction = target as f64 / mesh.triangle_count().max(1) as f64;
            let options = Options {
                z_scale,
                target_triangles: target,
                ..if cover {
                    Options::covering(mesh, fraction)
                } else {
                    Options::fraction(mesh, fraction)
                }
            };
            let chosen = decimate_chosen(mesh, &options)?;
            let below = chosen
                .outline
                .filter(|outline| target < outline.min_triangles);
            Ok((chosen, below))
        })
        .collect::<strata_lod::Result<Vec<_>>>()
        .context("decimating the scene")?;
    let stitched = if stitch {
        strata_lod::stitch(
            &surfaces.iter().collect::<Vec<_>>(),
            &mut chosen
                .iter_mut()
                .map(|(c, _)| &mut c.decimated)
                .collect::<Vec<_>>(),
        )
    } else {
        Stitched::default()
    };
    let origin = surfaces.first().map_or([0.0; 3], |s| s.origin);
    let mut out = SurfaceMesh::with_origin(origin);
    for (c, _) in &chosen {
        out.append(&c.decimated.mesh);
    }
    let by_meshopt = chosen
        .iter()
        .filter(|(c, _)| c.maker == Maker::Meshopt)
        .count();
    notes.push(Note::Info(format!(
        "decimated {} surfaces {} -> {} triangles ({:.1} %), error up to {:.3}, in {:.2} s \
         ({:.2} s of it measuring how much of each is seen); {}{}",
        surfaces.len(),
        total,
        out.triangle_count(),
        100.0 * out.triangle_count() as f64 / total.max(1) as f64,
        chosen
            .iter()
            .map(|(c, _)| c.decimated.error)
            .fold(0.0f32, f32::max),
        start.elapsed().as_secs_f64(),
        measured,
        shares_seen(&shares, surfaces, &visible),
        if by_meshopt > 0 {
            format!("; {by_meshopt} of them by meshopt_simplify")
        } else {
            String::new()
        },
    )));
    notes.extend(stitch_note(&stitched));
    notes.extend(outline_notes(&chosen));
    if out.is_empty() {
        return Err(Error::scene("decimation left no triangle"));
    }
    if !(against_cells || cover) {
        return Ok((out, None));
    }
    let cells = scene_cells(surfaces, stacked, chosen, z_scale, against_cells, notes)?;
    Ok((out, cells))
}

/// What stitching did, in words; `None` where it did nothing.
fn stitch_note(stitched: &Stitched) -> Option<Note> {
    if stitched.inserted + stitched.skipped == 0 {
        return None;
    }
    {
        // Each count that is not zero, with what it counts.
        let part = |count: usize, what: &str| {
            if count > 0 {
                format!(", {count} {what}")
            } else {
                String::new()
            }
        };
        Some(Note::Info(format!(
            "stitched the outlines the surfaces share: {} nodes one of them kept put back \
             into the others (a triangle each){}{}{}{}",
            stitched.inserted,
            part(
                stitched.corners,
                "of them as a triangle of their own where a corner was cut off"
            ),
            part(
                stitched.on_edge,
                "of them on the edge they split, where their own place would fold a triangle \
                 (their copies moved there too)"
            ),
            part(
                stitched.texture_on_edge,
                "with the edge's texture point, where their own would turn a triangle over in \
                 texture space"
            ),
            part(
                stitched.skipped,
                "left out or short of their place (where a triangle would fold, or the outline \
                 left the input's)"
            ),
        )))
    }
}

/// The surfaces whose share was below what keeps their outlines, and those fitted
/// to the grid lines, in words.
fn outline_notes(chosen: &[(Chosen, Option<OutlineBound>)]) -> Vec<Note> {
    let mut notes = Vec::new();
    let below: Vec<_> = chosen.iter().filter_map(|(_, b)| *b).collect();
    if !below.is_empty() {
        notes.push(Note::Note(format!(
            "on {} surfaces the share is below the triangles that keep every corner of \
             their outlines, holes and fault traces ({} corners, at least {} triangles): \
             there decimation cuts corners: what it cuts outward is not drawn, what it cuts \
             inward is lost (--cover grows them outward only)",
            below.len(),
            below.iter().map(|b| b.corners).sum::<usize>(),
            below.iter().map(|b| b.min_triangles).sum::<usize>(),
        )));
    }
    let fitted: Vec<(f64, f64)> = chosen.iter().filter_map(|(c, _)| c.fitted).collect();
    if !fitted.is_empty() {
        notes.push(Note::Info(format!(
            "fitted {} surfaces to the grid lines, texture coordinates fixed: the largest \
             RMS distance of their lines {:.3} -> {:.3} (lines a surface lost counted between \
             its RMS and largest distance)",
            fitted.len(),
            fitted.iter().map(|f| f.0).fold(0.0, f64::max),
            fitted.iter().map(|f| f.1).fold(0.0, f64::max),
        )));
    }
    notes
}

/// The input's cells of the decimated `chosen` surfaces of `surfaces` (the first
/// `stacked` the layers'), appended as their meshes are ([`SceneCells`]): their own
/// cover where the decimation made one, else (with `against_cells`) one made here;
/// `None` where a surface has none.
fn scene_cells(
    surfaces: &[SurfaceMesh],
    stacked: usize,
    chosen: Vec<(Chosen, Option<OutlineBound>)>,
    z_scale: f32,
    against_cells: bool,
    notes: &mut Vec<Note>,
) -> Result<Option<SceneCells>> {
    let coloured = against_cells && !surfaces.iter().all(|s| s.scalars.is_empty());
    // Each surface's cells, as its cover came back or made here, appended as the
    // meshes are, each result's vertices named by their piece among them, and the
    // cells' values surface by surface, in the order of the appended cover.
    let mut cells = CellCover::default();
    let mut pieces = Vec::new();
    let mut values = coloured.then(Vec::new);
    // How far each stacked surface strays vertically from the original, which is how
    // far it may rise through its neighbour: their pushes apart in the depth test.
    let vertical: Vec<f32> = surfaces
        .par_iter()
        .zip(&chosen)
        .take(stacked)
        .map(|(mesh, (c, _))| {
            let d = &c.decimated;
            deviation(mesh, &d.mesh, &d.home, 2, f64::from(z_scale)).vertical as f32
        })
        .collect();
    let surface_push = stack_pushes(&vertical);
    let mut push = Vec::new();
    for (i, (mesh, (mut c, _))) in surfaces.iter().zip(chosen).enumerate() {
        let own = match c.decimated.cover.take() {
            Some(own) => own,
            None if against_cells => match CellCover::of(mesh) {
                Ok(own) => own,
                Err(e) => {
                    notes.push(Note::Note(format!(
                        "drawn without the original's cells (colours interpolated \
                         between nodes, nothing trimmed to the cells): {e}"
                    )));
                    return Ok(None);
                }
            },
            None => return Ok(None),
        };
        let first = cells.pieces.len() as u32;
        pieces.extend(
            c.decimated
                .pieces(mesh, &own)
                .into_iter()
                .map(|p| p.saturating_add(first)),
        );
        if let Some(values) = &mut values {
            values.extend(own.values(mesh).context("the scene's cell values")?);
        }
        push.resize(push.len() + own.pieces.len(), surface_push.get(i).copied());
        cells.append(&own);
    }
    Ok(Some(SceneCells {
        pieces,
        push,
        values,
        corners: None,
        cover: cells,
    }))
}

/// How the budget went: the share of each surface's triangles kept, the least and
/// the most, and the visible fraction of those surfaces.
fn shares_seen(shares: &[usize], surfaces: &[SurfaceMesh], visible: &[f64]) -> String {
    let kept = |i: usize| shares[i] as f64 / surfaces[i].triangle_count().max(1) as f64;
    let order = |a: &usize, b: &usize| kept(*a).total_cmp(&kept(*b));
    let (Some(least), Some(most)) = (
        (0..shares.len()).min_by(order),
        (0..shares.len()).max_by(order),
    ) else {
        return String::new();
    };
    format!(
        "shares {:.1} % (surface {}, {:.0} % of it seen) to {:.1} % (surface {}, {:.0} % seen)",
        100.0 * kept(least),
        least + 1,
        100.0 * visible[least],
        100.0 * kept(most),
        most + 1,
        100.0 * visible[most],
    )
}
