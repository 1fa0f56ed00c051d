//! One triangle budget for a model of several surfaces, split by how much of each is
//! seen (after Zhang & Turk, "Visibility-guided simplification", IEEE Visualization
//! 2002, who weigh the quadric error by a visibility measure).
//!
//! Layer surfaces stacked in a model hide one another: seen from outside, the top of
//! the first layer and the bottom of the last show whole, the tops between them
//! mostly only at their rims. A budget split evenly spends most of it on what is not
//! seen. Take a surface's error to fall as its triangles rise, e = c s / n for `s` input
//! triangles and `n` kept (halving per doubling, as measured on emerald's layers; see
//! `docs/performance.md`), and the error a picture shows of it to scale
//! with the part seen, the fraction `v`. The sum over surfaces of v e for a fixed sum
//! of n is least where n is proportional to s times the square root of v: a surface
//! seen at a quarter of its area keeps half the density of one seen whole, and
//! surfaces all seen whole split the budget evenly, as before.

use strata_grid::SurfaceMesh;

/// A surface to share a budget with: its triangles and the fraction of it seen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceShare {
    /// Triangles of the surface.
    pub triangles: usize,
    /// Of the surface's area (projected, summed over the views of the measure), the
    /// fraction no other surface hides: 0 to 1.
    pub visible: f64,
}

/// The least visible fraction a surface is weighed with. A surface that the views of
/// the measure barely show is still seen edge-on at its rim, where its outline and
/// relief draw lines, or from elsewhere, or in a picture of its layer alone. Measured
/// with `strata bench lod --quick` at 10 % (line-pixel F1, one view; the surfaces
/// between top and bottom are seen at less than this on Reek and emerald) for least
/// fractions of 0.01 to 0.1 and an even split: 0.03 drew emerald best and Reek and
/// emerald with the cell mask nearly best, and every least fraction beat the even
/// split on emerald (the table is in `docs/performance.md`, "Decimation internals").
///
/// At 0.01 Reek's inner surfaces get about their outline bound and nothing more;
/// from 0.05 on, meshoptimizer's `simplify_with_attributes` given the same split
/// draws emerald's lines better than ours.
pub const MIN_VISIBLE: f64 = 0.03;

/// Splits `budget` triangles among `surfaces`: each keeps a share proportional to its
/// triangles times the square root of its visible fraction (at least
/// [`MIN_VISIBLE`]), never more than it has; what a surface cannot take goes to the
/// others. The shares sum to `budget`, or to all the triangles where that is less.
pub fn share_budget(budget: usize, surfaces: &[SurfaceShare]) -> Vec<usize> {
    let total: usize = surfaces.iter().map(|s| s.triangles).sum();
    if budget >= total {
        return surfaces.iter().map(|s| s.triangles).collect();
    }
    let density: Vec<f64> = surfaces
        .iter()
        .map(|s| {
            let v = if s.visible.is_finite() {
                s.visible
            } else {
                0.0
            };
            v.clamp(MIN_VISIBLE, 1.0).sqrt()
        })
        .collect();
    // Water filling: surfaces whose share would exceed their triangles keep them all,
    // and the rest split what is left, until none overflows. Each round caps at least
    // one more surface, so there are at most as many rounds as surfaces.
    let mut capped = vec![false; surfaces.len()];
    let mut exact = vec![0.0; surfaces.len()];
    loop {
        let left = budget as f64
            - surfaces
                .iter()
                .zip(&capped)
                .filter(|(_, c)| **c)
                .map(|(s, _)| s.triangles as f64)
                .sum::<f64>();
        let weight: f64 = surfaces
            .iter()
            .zip(&density)
            .zip(&capped)
            .filter(|(_, c)| !**c)
            .map(|((s, d), _)| s.triangles as f64 * d)
            .sum();
        let mut overflow = false;
        for (i, s) in surfaces.iter().enumerate() {
            exact[i] = if capped[i] {
                s.triangles as f64
            } else if weight > 0.0 {
                left * s.triangles as f64 * density[i] / weight
            } else {
                0.0
            };
            if !capped[i] && exact[i] >= s.triangles as f64 {
                capped[i] = true;
                overflow = true;
            }
        }
        if !overflow {
            break;
        }
    }
    // Whole triangles: the floors, then one more to the largest remainders.
    let mut shares: Vec<usize> = exact.iter().map(|e| e.floor() as usize).collect();
    let given: usize = shares.iter().sum();
    let mut order: Vec<usize> = (0..surfaces.len()).collect();
    order.sort_by(|&a, &b| {
        let (ra, rb) = (exact[a] - exact[a].floor(), exact[b] - exact[b].floor());
        rb.total_cmp(&ra).then(a.cmp(&b))
    });
    let mut missing = budget.saturating_sub(given);
    for i in order {
        if missing == 0 {
            break;
        }
        if shares[i] < surfaces[i].triangles {
            shares[i] += 1;
            missing -= 1;
        }
    }
    shares
}

/// [`share_budget`] of `fraction` of all the triangles of `surfaces`, each seen at its
/// fraction in `visible` (a surface without one counts as unmeasured).
pub fn share_surfaces(fraction: f64, surfaces: &[SurfaceMesh], visible: &[f64]) -> Vec<usize> {
    let total: usize = surfaces.iter().map(SurfaceMesh::triangle_count).sum();
    let shares: Vec<SurfaceShare> = surfaces
        .iter()
        .enumerate()
        .map(|(i, s)| SurfaceShare {
            triangles: s.triangle_count(),
            visible: visible.get(i).copied().unwrap_or(f64::NAN),
        })
        .collect();
    share_budget((total as f64 * fraction).round() as usize, &shares)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn surfaces(list: &[(usize, f64)]) -> Vec<SurfaceShare> {
        list.iter()
            .map(|&(triangles, visible)| SurfaceShare { triangles, visible })
            .collect()
    }

    #[test]
    fn surfaces_seen_alike_split_the_budget_by_their_triangles() {
        let s = surfaces(&[(1000, 1.0), (3000, 1.0), (500, 1.0)]);
        assert_eq!(share_budget(450, &s), vec![100, 300, 50]);
        let hidden_alike = surfaces(&[(1000, 0.3), (3000, 0.3)]);
        assert_eq!(share_budget(400, &hidden_alike), vec![100, 300]);
    }

    #[test]
    fn a_surface_seen_at_a_quarter_keeps_half_the_density() {
        let s = surfaces(&[(1000, 1.0), (1000, 0.25), (1000, 1.0)]);
        let shares = share_budget(500, &s);
        assert_eq!(shares, vec![200, 100, 200]);
        // Hidden entirely, or unmeasured: the least weight, not nothing.
        let s = surfaces(&[(1000, 1.0), (1000, 0.0), (1000, f64::NAN)]);
        let shares = share_budget(1000, &s);
        assert_eq!(shares.iter().sum::<usize>(), 1000);
        assert!(shares[1].abs_diff(shares[2]) <= 1, "{shares:?}");
        let ratio = shares[0] as f64 / shares[1] as f64;
        assert!(
            (ratio - 1.0 / MIN_VISIBLE.sqrt()).abs() < 0.05,
            "{shares:?}"
        );
    }

    #[test]
    fn what_a_surface_cannot_take_goes_to_the_others_and_the_sum_is_the_budget() {
        let s = surfaces(&[(10, 1.0), (1000, 0.09), (1000, 0.36)]);
        // Unbounded, the first would take 1500 * 10 / 910 = 16.5 of its 10; the others
        // split the rest 1 : 2.
        assert_eq!(share_budget(1500, &s), vec![10, 497, 993]);
        for budget in [0, 1, 7, 333, 2009] {
            let shares = share_budget(budget, &s);
            assert_eq!(shares.iter().sum::<usize>(), budget, "{budget}: {shares:?}");
            assert!(shares.iter().zip(&s).all(|(n, s)| *n <= s.triangles));
        }
        assert_eq!(share_budget(5000, &s), vec![10, 1000, 1000]);
        assert!(share_budget(10, &[]).is_empty());
    }
}
