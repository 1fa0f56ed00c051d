//! The decimation strata draws with: ours, except where the budget is below, or not
//! far above, what keeping the surface's outlines costs
//! ([`outline_bound`](crate::measure::outline_bound)).
//!
//! Ours is made to keep outlines, holes and fault traces where they are. Below that
//! bound every simplifier must cut outline corners, and there meshoptimizer's
//! `simplify` (position error only, every kept vertex an input vertex), [`fit`] to the
//! original grid lines (every vertex moved, texture coordinates fixed, to where the
//! surface draws the lines nearest to where the original does), spends the few
//! triangles better. Running both there and keeping the one that drew the grid lines
//! nearer (the RMS of [`GridLines::deviation`] as [`score`]d), meshoptimizer's won on
//! nearly every layer surface of the bench's models below its bound, the comparison
//! cost several times what ours alone does, and without it the bench's frames (worse
//! of its two views, line-pixel F1) came out all but the same; so meshoptimizer's is
//! taken there without one. The figures are in `docs/performance.md` ("Decimation
//! internals").
//!
//! Just above the bound (under `MESHOPT_NEAR_BOUND` times it), ours keeps the
//! outlines but has few triangles left for the surface inside them, and
//! meshoptimizer's, fitted, is taken there too. Further above (under `FIT_NEAR_BOUND`
//! times the bound) ours is fitted. With [`Options::cover`] the renderer's
//! cell mask keeps the outlines, at any budget, and ours is fitted at every one.
//!
//! Near the bound ours is fitted to the original grid nodes, its input vertices, which
//! the decimation itself locates on its result (each among the triangles of the
//! vertex it was merged into); elsewhere the fit's samples are two per cell edge,
//! which [`GridLines::locate`] finds by a search of the whole result. On Reek's layers
//! the nodes' fit cost a fraction of the search's, and the bench's frames came out as
//! well (line-pixel F1 within a thousandth, `strata bench lod --quick`); the edges'
//! midpoints as well cost more for nothing. With [`Options::cover`] the search's
//! samples stay: there they drew the lines nearer on the smallest model, simpleb8
//! (figures: `docs/performance.md`, "Decimation internals").

use std::time::Instant;

use strata_grid::SurfaceMesh;

use crate::baseline::{Simplifier, simplify};
use crate::decimate::decimate_prepared;
use crate::fit::fit;
use crate::measure::{Deviation, GridLines, Located, OutlineBound, components, outline_bound_of};
use crate::reference::{NONE, Reference};
use crate::{Decimated, Options, Result};

/// Points sampled along each original cell edge to fit meshoptimizer's result: a grid
/// node and the edge's midpoint. More samples left emerald's line-pixel F1 where it
/// was, and one alone lowered simpleb8's (`docs/performance.md`, "Decimation
/// internals").
const SAMPLES_PER_EDGE: usize = 2;

/// Under this many times the outline bound, meshoptimizer's `simplify` fitted to the
/// grid lines is taken, as below the bound: there ours spends nearly all its triangles
/// on the outline's corners, while meshoptimizer's may cut one and give the surface
/// inside what it saves. On the grid lines (two samples a cell edge, RMS distance as
/// [`score`]d; meshoptimizer's is fitted to those samples, ours to the grid nodes),
/// meshoptimizer's drew them nearer than ours on every layer surface of the bench's
/// models that `strata bench lod` decimates at 10 and 20 % to under 1.5 times their
/// bound, and on most of those between 1.5 and 2.5 times it. In the bench's frames
/// (worse of two views, line-pixel F1, 50 to 2 %), taking it under 1.5 times the bound
/// rather than 1 raised Reek's, emerald's and simpleb8's, and 2 or 2.5 raised none
/// further (emerald's fell at 10 %). Figures: `docs/performance.md`, "Decimation
/// internals".
const MESHOPT_NEAR_BOUND: f64 = 1.5;

/// Above the outline bound but under this many times it, ours is fitted too: its
/// outline corners take most of the budget there, and the fit is what the surface
/// inside them gets. In the bench's frames (worse of two views, line-pixel F1) the fit
/// raised ours most near the bound, on emerald and Reek; further from it the gain was a
/// thousandth or less, while the fit still costs a measurable share of what ours does.
/// Figures: `docs/performance.md`, "Decimation internals".
const FIT_NEAR_BOUND: f64 = 2.5;

/// Who made a [`Chosen`] decimation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Maker {
    /// Ours ([`crate::decimate()`]).
    Strata,
    /// meshoptimizer's `simplify` ([`Simplifier::Simplify`]), fitted.
    Meshopt,
}

/// A decimation and who made it.
#[derive(Clone, Debug)]
pub struct Chosen {
    /// With [`Maker::Meshopt`], its `error` is meshoptimizer's, in display length
    /// units.
    pub decimated: Decimated,
    /// Whose decimation it is.
    pub maker: Maker,
    /// Where the result was [`fit`]ted, its scores (`score`: RMS distance of the original
    /// grid lines, display length units, z scaled) before and after.
    pub fitted: Option<(f64, f64)>,
    /// The surface's [`outline_bound`](crate::measure::outline_bound), where the
    /// target was near enough to it to need it (under 2.5 times the outline edges,
    /// which bound it from above; never with [`Options::cover`] or an error target).
    pub outline: Option<OutlineBound>,
}

/// [`decimate`](crate::decimate()), or, where the target is below
/// `MESHOPT_NEAR_BOUND` times the surface's
/// [`outline_bound`](crate::measure::outline_bound), meshoptimizer's `simplify`
/// [`fit`] to the original grid lines; ours (fitted too) where meshoptimizer's result
/// draws none of them (it takes a target of no triangle literally). Ours fitted
/// above the bound but near it (`FIT_NEAR_BOUND`), and with [`Options::cover`] at
/// any target: the cell mask draws the outlines where their cells' texture
/// coordinates fall, so moving outline vertices does not cut them, and the fit drew
/// the lines nearer at every budget measured (bench frames, worse of two views,
/// line-pixel F1 on emerald and Reek; `docs/performance.md`). With a finite
/// [`Options::max_error`], ours alone (meshoptimizer's error is another measure, and
/// the fit moves vertices past it).
pub fn decimate_chosen(mesh: &SurfaceMesh, options: &Options) -> Result<Chosen> {
    let start = Instant::now();
    let (reference, vt) = Reference::with_vertex_triangles(mesh)?;
    let prepared = start.elapsed().as_secs_f64();
    let target = options.target_triangles;
    let fitting = options.max_error.is_infinite();
    // The outline edges bound the corners, and so the outline bound, from above, for
    // free: most targets are far above them, and the exact bound is not needed.
    let outline_edges = reference.adjacency.iter().flatten();
    let outline_edges = outline_edges.filter(|&&t| t == NONE).count();
    let labels =
        (fitting && !options.cover && (target as f64) < FIT_NEAR_BOUND * outline_edges as f64)
            .then(|| components(mesh));
    let bound = labels
        .as_ref()
        .map(|labels| outline_bound_of(mesh, &vt, &reference.adjacency, labels));
    let z_scale = f64::from(options.z_scale);
    let on_lines = |decimated: &mut Decimated, lines: &GridLines| {
        let located = lines.locate(&decimated.mesh, &decimated.home, z_scale);
        fitted(&located, decimated, z_scale)
    };
    if bound.is_some_and(|bound| (target as f64) < MESHOPT_NEAR_BOUND * bound.min_triangles as f64)
    {
        let labels = labels.unwrap_or_else(|| components(mesh));
        let lines = GridLines::of_parts(mesh, &vt, &reference.adjacency, labels, SAMPLES_PER_EDGE);
        let mut theirs = simplify(mesh, Simplifier::Simplify, target, options.z_scale)?;
        if let Some(scores) = on_lines(&mut theirs, &lines) {
            return Ok(Chosen {
                decimated: theirs,
                maker: Maker::Meshopt,
                fitted: Some(scores),
                outline: bound,
            });
        }
        let (mut ours, _) = decimate_prepared(&reference, vt, options, prepared, false)?;
        let scores = on_lines(&mut ours, &lines);
        return Ok(Chosen {
            decimated: ours,
            maker: Maker::Strata,
            fitted: scores,
            outline: bound,
        });
    }
    let near =
        bound.is_some_and(|bound| (target as f64) < FIT_NEAR_BOUND * bound.min_triangles as f64);
    // Sampled before the decimation takes the vertex triangles.
    let cover_lines = (fitting && options.cover).then(|| {
        let labels = components(mesh);
        GridLines::of_parts(mesh, &vt, &reference.adjacency, labels, SAMPLES_PER_EDGE)
    });
    let (mut ours, nodes) = decimate_prepared(&reference, vt, options, prepared, near)?;
    let scores = match &cover_lines {
        Some(lines) => on_lines(&mut ours, lines),
        None => nodes.and_then(|nodes| fitted(&nodes, &mut ours, z_scale)),
    };
    Ok(Chosen {
        decimated: ours,
        maker: Maker::Strata,
        fitted: scores,
        outline: bound,
    })
}

/// Fits `decimated` to the samples `located` on it and returns its [`score`]s before
/// and after; nothing when it draws none of them.
fn fitted(located: &Located, decimated: &mut Decimated, z_scale: f64) -> Option<(f64, f64)> {
    let before = located.deviation(&decimated.mesh, z_scale);
    (before.samples > 0).then(|| {
        fit(located, decimated, z_scale, before.max);
        let after = located.deviation(&decimated.mesh, z_scale);
        (score(&before), score(&after))
    })
}

/// The RMS distance of the original grid lines, with every sample the result misses
/// (its piece lost, or shrunk far from it) counted at the geometric mean of the
/// result's RMS and largest distance, so that dropping a piece does not look nearer;
/// a result that measures no sample at all (an empty one) scores infinite.
pub fn score(d: &Deviation) -> f64 {
    if d.samples == 0 {
        return f64::INFINITY;
    }
    // A missed sample's square: (sqrt(rms * max))^2.
    let squares = d.rms * (d.rms * d.samples as f64 + d.max * d.missed as f64);
    (squares / (d.samples + d.missed) as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decimate;
    use crate::measure::{deviation, outline_bound};
    use strata_grid::CellFace;

    /// A flat grid of 12 x 8 cells with a notch of 4 x 3 cells cut out of one side:
    /// an outline of 8 corners, so 6 triangles at least keep them.
    fn notched() -> SurfaceMesh {
        let full = SurfaceMesh::structured(12, 8, |i, j| {
            [i as f32 * 10.0, j as f32 * 10.0, 0.02 * (i * j) as f32]
        });
        let mut mesh = SurfaceMesh::with_origin(full.origin);
        mesh.positions = full.positions.clone();
        mesh.texcoords = full.texcoords.clone();
        for face in &full.cell_faces {
            let [i, j, _] = face.cell;
            if (4..8).contains(&i) && j >= 5 {
                continue;
            }
            let first = mesh.triangles.len() as u32;
            for &t in &face.triangles {
                mesh.triangles.push(full.triangles[t as usize]);
            }
            mesh.cell_faces.push(CellFace {
                triangles: [first, first + 1],
                ..*face
            });
        }
        mesh
    }

    #[test]
    fn a_little_further_above_the_outline_bound_ours_is_fitted() {
        let mesh = notched();
        // The bound is 6 triangles: fitted from 1.5 up to 2.5 times that, exclusive.
        for target in [9, 12, 14, 15] {
            let options = Options {
                target_triangles: target,
                ..Options::default()
            };
            let chosen = decimate_chosen(&mesh, &options).unwrap();
            assert_eq!(chosen.maker, Maker::Strata, "target {target}");
            let ours = decimate(&mesh, &options).unwrap();
            assert_eq!(chosen.decimated.mesh.triangles, ours.mesh.triangles);
            assert_eq!(chosen.decimated.mesh.texcoords, ours.mesh.texcoords);
            if target == 15 {
                assert!(chosen.fitted.is_none());
                assert_eq!(chosen.decimated.mesh.positions, ours.mesh.positions);
                continue;
            }
            let (before, after) = chosen.fitted.expect("fitted near the bound");
            assert!(after < before, "target {target}: {before} -> {after}");
            assert_ne!(chosen.decimated.mesh.positions, ours.mesh.positions);
        }
    }

    #[test]
    fn far_above_the_outline_bound_or_with_an_error_target_ours_runs_alone() {
        let mesh = notched();
        let bound = outline_bound(&mesh).min_triangles;
        assert_eq!(bound, 6, "{bound}");
        // An error target, even below the bound: meshoptimizer's error is another
        // measure, and the fit moves vertices past it.
        let error_target = Options {
            target_triangles: 2,
            max_error: 50.0,
            ..Options::default()
        };
        let far_above = Options {
            target_triangles: 40,
            ..Options::default()
        };
        for options in [far_above, error_target] {
            let chosen = decimate_chosen(&mesh, &options).unwrap();
            assert_eq!(chosen.maker, Maker::Strata);
            assert!(chosen.fitted.is_none());
            let ours = decimate(&mesh, &options).unwrap();
            assert_eq!(chosen.decimated.mesh.triangles, ours.mesh.triangles);
            assert_eq!(chosen.decimated.mesh.positions, ours.mesh.positions);
            // The rectangle's 40 outline vertices, and 6 more around the notch.
            assert_eq!(ours.outline_vertices, 46);
        }
    }

    #[test]
    fn below_it_or_just_above_meshopts_result_is_fitted() {
        let mesh = notched();
        // Below the bound of 6 triangles, and under 1.5 times it.
        for target in [2, 3, 4, 6, 8] {
            let options = Options {
                target_triangles: target,
                ..Options::default()
            };
            let chosen = decimate_chosen(&mesh, &options).unwrap();
            assert_eq!(chosen.maker, Maker::Meshopt, "target {target}");
            let (before, after) = chosen.fitted.expect("fitted below the bound");
            assert!(after <= before, "target {target}: {before} -> {after}");
            let kept = &chosen.decimated;
            kept.mesh.validate().unwrap();
            let measured = deviation(&mesh, &kept.mesh, &kept.home, SAMPLES_PER_EDGE, 1.0);
            let measured = score(&measured);
            assert!(
                (measured - after).abs() <= 1e-9 * before,
                "target {target}: kept {measured}, fitted {after}"
            );
            // Only positions moved: meshoptimizer's triangles and texture coordinates.
            let theirs = simplify(&mesh, Simplifier::Simplify, target, 1.0).unwrap();
            assert_eq!(kept.mesh.triangles, theirs.mesh.triangles);
            assert_eq!(kept.mesh.texcoords, theirs.mesh.texcoords);
        }
    }

    #[test]
    fn missed_samples_count_between_the_rms_and_the_largest_distance() {
        let measured = Deviation {
            samples: 3,
            max: 4.0,
            rms: 1.0,
            outside: 1,
            vertical: 0.0,
            missed: 0,
        };
        assert_eq!(score(&measured), 1.0);
        // One sample more, missed: counted at sqrt(1 * 4) = 2.
        let one_missed = Deviation {
            missed: 1,
            ..measured
        };
        assert!((score(&one_missed) - (7.0f64 / 4.0).sqrt()).abs() < 1e-12);
        let nothing = Deviation {
            missed: 5,
            ..Deviation::default()
        };
        assert_eq!(score(&nothing), f64::INFINITY);
    }

    #[test]
    fn an_empty_meshopt_result_leaves_ours() {
        // meshoptimizer takes a target of no triangle literally.
        let mesh = notched();
        let chosen = decimate_chosen(&mesh, &Options::default()).unwrap();
        assert_eq!(chosen.maker, Maker::Strata);
        let ours = decimate(&mesh, &Options::default()).unwrap();
        assert_eq!(chosen.decimated.mesh.triangles, ours.mesh.triangles);
        // Fitted too: the fit weighs the samples the surface draws, the score also
        // those outside it, so the score may rise by a trifle.
        let (before, after) = chosen.fitted.expect("ours fitted below the bound");
        assert!(
            after.is_finite() && after <= 1.001 * before,
            "{before} -> {after}"
        );
        assert!(!chosen.decimated.mesh.is_empty());
    }

    #[test]
    fn a_covering_decimation_is_ours_fitted_and_keeps_its_cover() {
        let mesh = notched();
        for target in [2, 20] {
            let options = Options {
                target_triangles: target,
                ..Options::covering(&mesh, 0.01)
            };
            let chosen = decimate_chosen(&mesh, &options).unwrap();
            assert_eq!(chosen.maker, Maker::Strata);
            let (before, after) = chosen.fitted.expect("a covering decimation is fitted");
            assert!(after <= before, "target {target}: {before} -> {after}");
            let ours = decimate(&mesh, &options).unwrap();
            let kept = &chosen.decimated;
            kept.mesh.validate().unwrap();
            // Positions moved; triangles, texture coordinates and the cells stayed.
            assert_ne!(kept.mesh.positions, ours.mesh.positions, "target {target}");
            assert_eq!(kept.mesh.triangles, ours.mesh.triangles);
            assert_eq!(kept.mesh.texcoords, ours.mesh.texcoords);
            assert_eq!(kept.cover, ours.cover);
            let cover = kept.cover.as_ref().expect("the input's cells");
            assert!(kept.pieces(&mesh, cover).iter().all(|&p| p == 0));
        }
    }
}
