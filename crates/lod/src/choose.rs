//! The decimation strata draws with: ours, except where the budget is below what
//! keeping the surface's outlines costs ([`outline_bound`]).
//!
//! Ours is made to keep outlines, holes and fault traces where they are. Below that
//! bound every simplifier must cut outline corners, and there meshoptimizer's
//! `simplify` (position error only, every kept vertex an input vertex) often spends
//! the few triangles better. Both then run, each is [`fit`] to the original grid
//! lines (every vertex moved, texture coordinates fixed, to where the surface draws
//! the lines nearest to where the original does), and the one that then draws them
//! nearer (the RMS of [`GridLines::deviation`], the measure `strata bench lod`
//! reports, as [`score`]d) is kept. Measured with the bench's frames (worse of its
//! two views, line-pixel F1; ours alone -> chosen without the fit -> chosen and
//! fitted, meshopt_simplify's best beside): simpleb8 at 10 % 0.181 -> 0.295 -> 0.430
//! (0.295), Reek at 5 % 0.895 -> 0.922 -> 0.944 (0.922) and at 2 % 0.832 -> 0.847 ->
//! 0.864 (0.847), emerald at 10 % 0.851 -> 0.869 -> 0.904 (0.836), at 5 % 0.729 ->
//! 0.718 -> 0.816 (0.713) and at 2 % 0.646 -> 0.591 -> 0.667 (0.623). Reek at 10 % is
//! above its bound and unchanged.

use strata_grid::SurfaceMesh;

use crate::baseline::{Simplifier, simplify};
use crate::fit::fit;
use crate::measure::{Deviation, GridLines, outline_bound};
use crate::{Decimated, Options, Result, decimate};

/// Points sampled along each original cell edge to compare the two decimations: a
/// grid node and the edge's midpoint. On emerald at 10 % (the bench's first view),
/// 1, 2 and 4 samples chose decimations of F1 0.872, 0.871 and 0.871 and ran at 0.53,
/// 0.45 and 0.35 M input triangles per CPU second, ours alone at 1.15 (2 samples run
/// at 0.51 since both measures share one [`GridLines`], on the calling thread).
const SAMPLES_PER_EDGE: usize = 2;

/// Who made a [`Chosen`] decimation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Maker {
    Strata,
    /// meshoptimizer's `simplify` ([`Simplifier::Simplify`]).
    Meshopt,
}

/// A decimation and who made it.
#[derive(Clone, Debug)]
pub struct Chosen {
    /// With [`Maker::Meshopt`], its `error` is meshoptimizer's, in display length
    /// units.
    pub decimated: Decimated,
    pub maker: Maker,
    /// The [`score`]s (RMS distance of the original grid lines, display length units,
    /// z scaled) of ours and of meshoptimizer's, each fitted, when both ran.
    pub compared: Option<(f64, f64)>,
}

/// [`decimate`], or meshoptimizer's `simplify` where it draws the grid lines nearer
/// to the original, either [`fit`] to them: only tried when the target is below the
/// surface's [`outline_bound`], and not with [`Options::cover`] (outlines kept by the
/// cell mask) or a finite [`Options::max_error`] (meshoptimizer's error is another
/// measure, and the fit moves vertices past the collapses' errors).
pub fn decimate_chosen(mesh: &SurfaceMesh, options: &Options) -> Result<Chosen> {
    let ours = decimate(mesh, options)?;
    let comparable = !options.cover && options.max_error.is_infinite();
    // The outline vertices bound the corners from above, for free: most targets are
    // above them, and the exact bound is not needed.
    if !comparable
        || options.target_triangles >= ours.outline_vertices
        || options.target_triangles >= outline_bound(mesh).min_triangles
    {
        return Ok(Chosen {
            decimated: ours,
            maker: Maker::Strata,
            compared: None,
        });
    }
    let theirs = simplify(
        mesh,
        Simplifier::Simplify,
        options.target_triangles,
        options.z_scale,
    )?;
    let lines = GridLines::of(mesh, SAMPLES_PER_EDGE);
    let z_scale = f64::from(options.z_scale);
    // Each fitted to the grid lines (its outlines are cut either way), then scored on
    // the samples located for its fit.
    let fitted = |mut d: Decimated| {
        let located = lines.locate(&d.mesh, &d.home);
        let reach = located.deviation(&d.mesh, z_scale).max;
        fit(&located, &mut d, z_scale, reach);
        let scored = score(&located.deviation(&d.mesh, z_scale));
        (d, scored)
    };
    let ((ours, ours_score), (theirs, theirs_score)) = (fitted(ours), fitted(theirs));
    let compared = (ours_score, theirs_score);
    let (decimated, maker) = if compared.1 < compared.0 {
        (theirs, Maker::Meshopt)
    } else {
        (ours, Maker::Strata)
    };
    Ok(Chosen {
        decimated,
        maker,
        compared: Some(compared),
    })
}

/// What [`decimate_chosen`] compares: the RMS distance of the original grid lines,
/// with every sample the result misses (its piece lost, or shrunk far from it)
/// counted at the geometric mean of the result's RMS and largest distance; a result
/// that measures no sample at all (an empty one) scores infinite. Measured with the
/// bench (worse view's F1, emerald / simpleb8 at 10 %): missed samples at the largest
/// distance kept ours where meshopt's drops a sliver and draws the rest nearer,
/// 0.867 / 0.269; refusing any result that misses a sample, 0.859 / 0.269; this,
/// 0.869 / 0.295, as left out altogether (which lets a result that drops whole
/// pieces win).
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
    use crate::measure::deviation;
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
    fn above_the_outline_bound_ours_runs_alone() {
        let mesh = notched();
        let bound = outline_bound(&mesh).min_triangles;
        assert_eq!(bound, 6, "{bound}");
        let options = Options {
            target_triangles: 40,
            ..Options::default()
        };
        let chosen = decimate_chosen(&mesh, &options).unwrap();
        assert_eq!(chosen.maker, Maker::Strata);
        assert!(chosen.compared.is_none());
        let ours = decimate(&mesh, &options).unwrap();
        assert_eq!(chosen.decimated.mesh.triangles, ours.mesh.triangles);
        // The rectangle's 40 outline vertices, and 6 more around the notch.
        assert_eq!(ours.outline_vertices, 46);
    }

    #[test]
    fn below_it_the_nearer_grid_lines_win() {
        let mesh = notched();
        for target in [2, 3, 4] {
            let options = Options {
                target_triangles: target,
                ..Options::default()
            };
            let chosen = decimate_chosen(&mesh, &options).unwrap();
            let (ours, theirs) = chosen.compared.expect("both ran below the bound");
            let kept = deviation(
                &mesh,
                &chosen.decimated.mesh,
                &chosen.decimated.home,
                SAMPLES_PER_EDGE,
                1.0,
            );
            let kept = score(&kept);
            assert!(
                (kept - ours.min(theirs)).abs() <= 1e-9 * ours.max(theirs),
                "target {target}: kept {kept} of {ours} and {theirs}"
            );
            let want = if theirs < ours {
                Maker::Meshopt
            } else {
                Maker::Strata
            };
            assert_eq!(chosen.maker, want, "target {target}");
            chosen.decimated.mesh.validate().unwrap();
        }
    }

    #[test]
    fn missed_samples_count_between_the_rms_and_the_largest_distance() {
        let measured = Deviation {
            samples: 3,
            max: 4.0,
            rms: 1.0,
            outside: 1,
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
    fn an_empty_result_never_wins() {
        // meshoptimizer takes a target of no triangle literally.
        let chosen = decimate_chosen(&notched(), &Options::default()).unwrap();
        assert!(chosen.compared.is_some());
        assert_eq!(chosen.maker, Maker::Strata);
        assert!(!chosen.decimated.mesh.is_empty());
    }

    #[test]
    fn cover_and_error_targets_never_compare() {
        let mesh = notched();
        for options in [
            Options {
                target_triangles: 2,
                ..Options::covering(&mesh, 0.01)
            },
            Options {
                target_triangles: 2,
                max_error: 50.0,
                ..Options::default()
            },
        ] {
            let chosen = decimate_chosen(&mesh, &options).unwrap();
            assert_eq!(chosen.maker, Maker::Strata);
            assert!(chosen.compared.is_none());
        }
    }
}
