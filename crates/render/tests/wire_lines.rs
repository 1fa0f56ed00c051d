//! Measured image tests of the texture-based wireframe on planar structured grids:
//! line width, orientation, position, anti-aliasing and saturation, for both the
//! texture and the analytic coverage. Every number is measured in the rendered image
//! against the grid lines projected on the CPU (see support/mod.rs for the measuring
//! convention); run with `--nocapture` to see the tables. CI runs this file with
//! `WGPU_BACKEND=gl` (llvmpipe) and `WGPU_BACKEND=vulkan` (lavapipe).

mod support;

use strata_render::glam::{Vec2, Vec3};
use strata_render::{Coverage, Renderer, View, WireMode};
use support::*;

const SIGMAS: [f32; 4] = [1.0, 2.0, 3.0, 5.0];
const COVERAGES: [Coverage; 2] = [Coverage::Texture, Coverage::Analytic];
/// Image side of the measured frames.
const SIZE: u32 = 384;
/// Tolerance of widths and centres (pixels).
const TOL: f32 = 0.5;

/// A named view of a planar grid.
struct Case {
    name: String,
    grid: PlaneGrid,
    view: View,
}

impl Case {
    fn new(grid: PlaneGrid, tilt_deg: f32, distance: f32) -> Self {
        Case {
            name: format!("tilt {tilt_deg:2}° dist {distance:3}"),
            view: grid_view(&grid, grid_camera(&grid, tilt_deg, distance), SIZE),
            grid,
        }
    }
}

/// Head-on and 60° tilt at three distances: cells of about 55, 30 and 18 px head-on
/// (so that even sigma 5 has cells wider than 3 sigma), shrinking towards the far
/// edge when tilted.
fn distance_cases(angle_deg: f32) -> Vec<Case> {
    let grid = PlaneGrid::square(16, 10.0, angle_deg);
    let mut cases = Vec::new();
    for tilt in [0.0, 60.0] {
        for distance in [110.0, 200.0, 340.0] {
            let mut case = Case::new(grid, tilt, distance);
            if angle_deg != 0.0 {
                case.name = format!("{} rot {angle_deg}°", case.name);
            }
            cases.push(case);
        }
    }
    cases
}

/// Scans of every measurable line of `case` at each sigma and coverage.
struct Sweep {
    backend: String,
    runs: Vec<(String, Coverage, f32, Vec<Scan>)>,
}

fn sweep(r: &mut Renderer, cases: &[Case]) -> Sweep {
    let mut runs = Vec::new();
    for case in cases {
        let drawable = r
            .prepare(&case.grid.mesh(), WireMode::Global)
            .unwrap_or_else(|e| panic!("prepare: {e}"));
        let proj = Projector::new(&case.view);
        for coverage in COVERAGES {
            for sigma in SIGMAS {
                let frame = render_frame(r, &[drawable.as_ref()], &case.view, sigma, coverage);
                let scans = measure_grid(&frame, &proj, &case.grid, sigma, 6);
                runs.push((case.name.clone(), coverage, sigma, scans));
            }
        }
    }
    Sweep {
        backend: backend(r),
        runs,
    }
}

impl Sweep {
    /// Prints one line per run with `what` of its scans summarised.
    fn print(&self, title: &str, what: impl Fn(&Scan) -> f32) {
        eprintln!("{title} ({})", self.backend);
        for (name, coverage, sigma, scans) in &self.runs {
            eprintln!(
                "  {name:28} {:8} sigma {sigma}: {}",
                format!("{coverage:?}"),
                Summary::of(scans.iter().map(&what))
            );
        }
    }

    /// Checks `ok` on every scan and that every run measured at least `min_scans`
    /// places; panics with every failure listed.
    fn check(&self, what: &str, min_scans: usize, ok: impl Fn(f32, &Scan) -> bool) {
        let mut failures = Vec::new();
        for (name, coverage, sigma, scans) in &self.runs {
            if scans.len() < min_scans {
                failures.push(format!(
                    "{name} {coverage:?} sigma {sigma}: only {} measurable places",
                    scans.len()
                ));
            }
            let bad: Vec<&Scan> = scans.iter().filter(|s| !ok(*sigma, s)).collect();
            if let Some(first) = bad.first() {
                failures.push(format!(
                    "{name} {coverage:?} sigma {sigma}: {what} fails at {} of {} places, e.g. {first:?}",
                    bad.len(),
                    scans.len()
                ));
            }
        }
        assert!(
            failures.is_empty(),
            "{} ({}):\n{}",
            what,
            self.backend,
            failures.join("\n")
        );
    }
}

fn width_ok(sigma: f32, s: &Scan) -> bool {
    (s.width - sigma).abs() <= TOL && (s.integral - sigma).abs() <= TOL
}

#[test]
fn line_width_head_on_and_tilted_at_three_distances() {
    let mut r = renderer();
    let sweep = sweep(&mut r, &distance_cases(0.0));
    sweep.print("full width at half coverage (px)", |s| s.width);
    sweep.print("integral of coverage across the line (px)", |s| s.integral);
    sweep.check("width within sigma ± 0.5 px", 20, width_ok);
}

#[test]
fn line_width_at_0_30_and_45_degrees_on_screen() {
    // Head-on, the grid rotated in its plane: one family at the angle, the other at
    // the angle + 90°. The level of each family must come from the full gradient of
    // its own coordinate; the per-axis derivative would thicken 45° lines by up to
    // sqrt(2) (to 7.1 px at sigma 5).
    let mut r = renderer();
    let mut cases = Vec::new();
    for angle in [0.0, 30.0, 45.0] {
        for distance in [110.0, 200.0] {
            let grid = PlaneGrid::square(16, 10.0, angle);
            let mut case = Case::new(grid, 0.0, distance);
            case.name = format!("rot {angle:2}° dist {distance}");
            cases.push(case);
        }
    }
    let sweep = sweep(&mut r, &cases);
    sweep.print("full width at half coverage (px) by orientation", |s| {
        s.width
    });
    sweep.print("angle of the measured lines on screen (deg)", |s| {
        s.angle_deg
    });
    sweep.check("width within sigma ± 0.5 px", 20, width_ok);
}

#[test]
fn line_centres_lie_on_the_projected_grid_lines() {
    let mut r = renderer();
    let mut cases = distance_cases(0.0);
    cases.extend(distance_cases(30.0));
    let sweep = sweep(&mut r, &cases);
    sweep.print("centre minus projected line (px, perpendicular)", |s| {
        s.offset
    });
    sweep.check("centre within 0.5 px of the projected line", 20, |_, s| {
        s.offset.abs() <= TOL
    });
}

#[test]
fn lines_are_anti_aliased_on_both_sides_without_gaps() {
    // Lines in general position (the grid rotated 30° in its plane, head-on and
    // tilted), so that their edges fall anywhere within a pixel. Along a pixel row
    // (column) the coverage ramp of a box-filtered edge from 0.05 to 0.95 is
    // 0.9 / cos θ px long, θ the line's angle from the pixel column (row), so a pixel
    // centre lands on it in a fraction min(1, 0.9 / cos θ) >= 0.9 of the scans. So:
    // over each frame at least 80% of the scans show a partly covered pixel on each
    // side of the line, and so do at least half the scans of every line with 4 scans
    // or more (an aliased line shows none). Lines aligned with the pixel grid are left
    // out: an edge exactly on a pixel boundary is legitimately all or nothing.
    //
    // No gaps: the most covered pixel of every scan across a line. A box-filtered
    // line of sigma >= 2 px covers a pixel within 0.5 px of its centre fully; the
    // texture reconstructs the filtered profile from samples half a pixel apart,
    // which rounds its corners by at most 1/8, hence 0.85. A 1 px line 0.5 px from
    // the nearest pixel centre leaves it half covered, hence 0.5 (rows at 30° from
    // the line reach 0.57).
    let mut r = renderer();
    let sweep = sweep(&mut r, &distance_cases(30.0));
    sweep.print("peak coverage across the line", |s| s.peak);
    let mut failures = Vec::new();
    eprintln!(
        "scans with partial coverage on both sides: all lines, worst line ({})",
        sweep.backend
    );
    let both = |s: &Scan| s.partial_before && s.partial_after;
    for (name, coverage, sigma, scans) in &sweep.runs {
        let pooled = scans.iter().filter(|s| both(s)).count() as f32 / scans.len().max(1) as f32;
        let mut lines: Vec<(Family, usize)> = scans.iter().map(|s| (s.family, s.index)).collect();
        lines.sort_by_key(|&(f, i)| (f == Family::J, i));
        lines.dedup();
        let mut worst: Option<(f32, (Family, usize), usize)> = None;
        for line in &lines {
            let of_line: Vec<&Scan> = scans
                .iter()
                .filter(|s| (s.family, s.index) == *line)
                .collect();
            let f = of_line.iter().filter(|s| both(s)).count() as f32 / of_line.len() as f32;
            if of_line.len() >= 4 && worst.is_none_or(|w| f < w.0) {
                worst = Some((f, *line, of_line.len()));
            }
        }
        let worst = worst.expect("a line with 4 scans or more");
        eprintln!(
            "  {name:28} {:8} sigma {sigma}: {:5.1}% of {} scans, worst line {:?} {:.0}% of {}",
            format!("{coverage:?}"),
            100.0 * pooled,
            scans.len(),
            worst.1,
            100.0 * worst.0,
            worst.2
        );
        if pooled < 0.8 || worst.0 < 0.5 || lines.len() < 5 {
            failures.push(format!(
                "{name} {coverage:?} sigma {sigma}: {:.1}% of {} scans over {} lines, worst line {:?} {:.0}% of {}",
                100.0 * pooled,
                scans.len(),
                lines.len(),
                worst.1,
                100.0 * worst.0,
                worst.2
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "anti-aliasing ({}):\n{}",
        sweep.backend,
        failures.join("\n")
    );
    sweep.check("no gap (peak coverage)", 20, |sigma, s| {
        s.peak >= if sigma < 2.0 { 0.5 } else { 0.85 }
    });
}

/// Mean coverage of the surface pixels of `grid` farther than `margin` px from its
/// outline (where the border lines, drawn by one polygon only, would count).
fn interior_mean(frame: &Frame, proj: &Projector, grid: &PlaneGrid, margin: f32) -> (usize, f64) {
    let corners = [
        grid.point(0.0, 0.0),
        grid.point(grid.ni as f32, 0.0),
        grid.point(grid.ni as f32, grid.nj as f32),
        grid.point(0.0, grid.nj as f32),
    ]
    .map(|p| proj.to_px(p));
    let (mut n, mut sum) = (0usize, 0f64);
    for y in 0..frame.height {
        for x in 0..frame.width {
            let (c, on) = frame.at(x as i64, y as i64).unwrap_or((0.0, false));
            let q = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let near_border = (0..4).any(|e| {
                let (a, b) = (corners[e], corners[(e + 1) % 4]);
                let t = ((q - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                (a + (b - a) * t - q).length() < margin
            });
            if on && !near_border {
                n += 1;
                sum += f64::from(c);
            }
        }
    }
    (n, if n == 0 { 0.0 } else { sum / n as f64 })
}

#[test]
fn dense_grids_do_not_saturate() {
    // Each line family is capped to a third of its cell (Celes & Abraham 3.1: a third
    // of the level), so where cells are smaller than 3 sigma px one family covers at
    // most 1/3 of the surface. Checked on strips with one dense family (400 x 1 and
    // 1 x 400 cells; the other family only draws the outline, which is left out).
    // A 400 x 400 grid has two families; their union is then bounded by
    // 1 - (1 - 1/3)^2 = 5/9, and is checked against that.
    let mut r = renderer();
    let be = backend(&r);
    const SLACK: f64 = 0.02;
    let mut failures = Vec::new();
    let strip_i = PlaneGrid {
        ni: 400,
        nj: 1,
        origin: Vec3::new(-200.0, -200.0, 0.0),
        du: Vec3::new(1.0, 0.0, 0.0),
        dv: Vec3::new(0.0, 400.0, 0.0),
    };
    let strip_j = PlaneGrid {
        ni: 1,
        nj: 400,
        du: Vec3::new(400.0, 0.0, 0.0),
        dv: Vec3::new(0.0, 1.0, 0.0),
        ..strip_i
    };
    let square = PlaneGrid::square(400, 1.0, 0.0);
    // Far: cells of about 0.8 px; grazing: 80° from the normal, cells of a few px at
    // the near edge down to a fraction of a pixel at the horizon.
    let views = [("far", 0.0, 900.0), ("grazing", 80.0, 330.0)];
    eprintln!("mean line coverage of the surface ({be})");
    for (label, grid, bound) in [
        ("400x1 strip", strip_i, 1.0 / 3.0),
        ("1x400 strip", strip_j, 1.0 / 3.0),
        ("400x400 grid", square, 5.0 / 9.0),
    ] {
        let drawable = r
            .prepare(&grid.mesh(), WireMode::Global)
            .unwrap_or_else(|e| panic!("prepare: {e}"));
        for (view_name, tilt, distance) in views {
            let view = grid_view(&grid, grid_camera(&grid, tilt, distance), 256);
            let proj = Projector::new(&view);
            for coverage in COVERAGES {
                for sigma in [1.0, 3.0, 5.0] {
                    let frame = render_frame(&mut r, &[drawable.as_ref()], &view, sigma, coverage);
                    let (n, mean) = interior_mean(&frame, &proj, &grid, 0.5 * sigma + 2.0);
                    eprintln!(
                        "  {label:12} {view_name:7} {:8} sigma {sigma}: {mean:.4} over {n} px (bound {bound:.4})",
                        format!("{coverage:?}")
                    );
                    if n < 10_000 || mean > bound + SLACK {
                        failures.push(format!(
                            "{label} {view_name} {coverage:?} sigma {sigma}: mean {mean:.4} over {n} px, bound {bound:.4} + {SLACK}"
                        ));
                    }
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "saturation ({be}):\n{}",
        failures.join("\n")
    );
}

/// Largest amplitude (in coverage) of the frequencies of `row` between `from` and `to`
/// cycles per pixel, the row detrended and Hann-windowed.
fn low_band_amplitude(row: &[f32], from: f64, to: f64) -> f64 {
    let n = row.len();
    let mean = row.iter().map(|&c| f64::from(c)).sum::<f64>() / n as f64;
    let window: Vec<f64> = (0..n)
        .map(|x| {
            let w = 0.5 - 0.5 * (std::f64::consts::TAU * x as f64 / (n - 1) as f64).cos();
            (f64::from(row[x]) - mean) * w
        })
        .collect();
    // The Hann window's mean is 1/2: amplitudes are scaled back by 2 / (n / 2).
    let scale = 4.0 / n as f64;
    (1..=n / 2)
        .map(|k| k as f64 / n as f64)
        .filter(|f| (from..=to).contains(f))
        .map(|f| {
            let (re, im) = window
                .iter()
                .enumerate()
                .fold((0.0, 0.0), |(re, im), (x, v)| {
                    let phase = std::f64::consts::TAU * f * x as f64;
                    (re + v * phase.cos(), im - v * phase.sin())
                });
            (re * re + im * im).sqrt() * scale
        })
        .fold(0.0, f64::max)
}

#[test]
fn dense_lines_do_not_alias_into_moire() {
    // Lines 2 to 6 px apart hold harmonics above the pixels' Nyquist frequency, which a
    // one-pixel box lets through as moire where the lines cross the pixel rows slanted:
    // beats much longer than a cell along each row. Rows of a tilted strip of one dense
    // line family (each row at one depth, so one period) are searched for frequencies
    // below 0.6 / P (P the lines' period along the row in px): the lines have none
    // there. Lines about vertical on screen, and crossing the rows at about 30°.
    let mut r = renderer();
    let be = backend(&r);
    let mut failures = Vec::new();
    for angle in [0.0, 30.0] {
        let square = PlaneGrid::square(400, 1.0, angle);
        let strip = PlaneGrid {
            nj: 1,
            dv: square.dv * 400.0,
            ..square
        };
        let drawable = r
            .prepare(&strip.mesh(), WireMode::Global)
            .unwrap_or_else(|e| panic!("prepare: {e}"));
        let view = grid_view(&strip, grid_camera(&strip, 70.0, 230.0), 512);
        let proj = Projector::new(&view);
        // Where line `a` crosses pixel row `y` (its ends projected: it stays straight).
        let crossing = |a: f32, y: f32| {
            let (p, q) = (
                proj.to_px(strip.point(a, 0.0)),
                proj.to_px(strip.point(a, 1.0)),
            );
            p.x + (q.x - p.x) * (y - p.y) / (q.y - p.y)
        };
        // The lines' period along row `y`, where the strip's middle lines cross it.
        let (top, bottom) = (
            proj.to_px(strip.point(200.0, 0.0)).y,
            proj.to_px(strip.point(200.0, 1.0)).y,
        );
        let period_at = |y: f32| {
            (top.min(bottom)..=top.max(bottom))
                .contains(&y)
                .then(|| (crossing(201.0, y) - crossing(199.0, y)).abs() / 2.0)
        };
        for coverage in COVERAGES {
            let frame = render_frame(&mut r, &[drawable.as_ref()], &view, 1.5, coverage);
            let mut amplitudes = Vec::new();
            for y in 0..frame.height {
                let period = period_at(y as f32 + 0.5).filter(|p| (2.0..=6.0).contains(p));
                let Some(period) = period else {
                    continue;
                };
                let row: Vec<f32> = (0..frame.width)
                    .filter_map(|x| frame.at(x as i64, y as i64).filter(|p| p.1).map(|p| p.0))
                    .collect();
                // The strip's outline lines and their anti-aliased edges are left out.
                let inner = &row[row.len().min(6)..row.len().saturating_sub(6)];
                if inner.len() < 128 {
                    continue;
                }
                let from = 3.0 / inner.len() as f64;
                amplitudes.push(low_band_amplitude(inner, from, 0.6 / f64::from(period)));
            }
            assert!(amplitudes.len() >= 40, "{} rows measured", amplitudes.len());
            amplitudes.sort_by(f64::total_cmp);
            let median = amplitudes[amplitudes.len() / 2];
            let max = amplitudes[amplitudes.len() - 1];
            eprintln!(
                "moire ({be}) lines at {angle}°, {coverage:?}: {} rows, low-band amplitude median {median:.4}, max {max:.4}",
                amplitudes.len()
            );
            if median > 0.008 || max > 0.05 {
                failures.push(format!(
                    "lines at {angle}°, {coverage:?}: median {median:.4}, max {max:.4}"
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "moire ({be}):\n{}",
        failures.join("\n")
    );
}
