//! Measured image tests of map grid lines on a spade terrain (Celes & Abraham 2011,
//! Fig. 13a): lines at constant map x and map y, generated from object-space
//! coordinates, must lie at their map positions on the curved TIN and keep their
//! thickness in pixels at every zoom (see support/mod.rs for the measuring
//! convention: black surface, white lines, red channel = coverage).

mod support;

use strata_grid::SurfaceMesh;
use strata_grid::terrain::{TerrainSynth, triangulate};
use strata_render::glam::{Vec2, Vec3};
use strata_render::{Camera, Coverage, GridLines, Style, View, WireMode};
use support::{Frame, Projector, Summary, measuring_style, renderer};

const SIZE: u32 = 512;
const SPACING: f64 = 500.0;

/// The elevation of the TIN at display-frame (x, y), by barycentric interpolation in
/// the triangle that contains it.
fn surface_z(mesh: &SurfaceMesh, x: f32, y: f32) -> Option<f32> {
    mesh.triangles.iter().find_map(|t| {
        let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
        let det = (b[1] - c[1]) * (a[0] - c[0]) + (c[0] - b[0]) * (a[1] - c[1]);
        if det.abs() < 1e-9 {
            return None;
        }
        let l0 = ((b[1] - c[1]) * (x - c[0]) + (c[0] - b[0]) * (y - c[1])) / det;
        let l1 = ((c[1] - a[1]) * (x - c[0]) + (a[0] - c[0]) * (y - c[1])) / det;
        let l2 = 1.0 - l0 - l1;
        (l0 >= -1e-6 && l1 >= -1e-6 && l2 >= -1e-6).then(|| l0 * a[2] + l1 * b[2] + l2 * c[2])
    })
}

/// Full width at half coverage and centre offset across the screen line through `p`
/// with unit direction `t`, scanned along the pixel row (or column) through `p`;
/// `None` off the surface or the image.
fn scan(frame: &Frame, p: Vec2, t: Vec2, sigma: f32) -> Option<(f32, f32, f32)> {
    let n = t.perp();
    let rows = n.x.abs() >= n.y.abs();
    let stretch = if rows { n.x.abs() } else { n.y.abs() };
    let reach = (0.5 * sigma + 3.0) / stretch;
    let (fixed, centre) = if rows {
        let y = p.y.floor() + 0.5;
        (y, p.x + (y - p.y) * t.x / t.y)
    } else {
        let x = p.x.floor() + 0.5;
        (x, p.y + (x - p.x) * t.y / t.x)
    };
    let first = (centre - reach - 0.5).floor() as i64;
    let last = (centre + reach - 0.5).ceil() as i64;
    let mut pos = Vec::new();
    let mut cov = Vec::new();
    for k in first..=last {
        let (c, on) = if rows {
            frame.at(k, fixed.floor() as i64)?
        } else {
            frame.at(fixed.floor() as i64, k)?
        };
        if !on {
            return None;
        }
        pos.push(k as f32 + 0.5);
        cov.push(c);
    }
    let (peak, edges) = support::half_coverage_edges(&pos, &cov);
    match edges {
        Some((lo, hi)) => Some((
            (hi - lo) * stretch,
            (0.5 * (lo + hi) - centre) * stretch,
            peak,
        )),
        // A gap: width 0, which every check rejects.
        None => Some((0.0, f32::NAN, peak)),
    }
}

#[test]
fn grid_lines_on_the_terrain_are_at_their_map_positions_sigma_wide_at_three_zooms() {
    let mut r = renderer();
    let be = support::backend(&r);
    let synth = TerrainSynth {
        points: 500,
        ..TerrainSynth::default()
    };
    let terrain = triangulate(&synth.generate()).expect("terrain");
    let mesh = terrain.mesh;
    let o = mesh.origin;
    // Grid lines through a point that is not a multiple of the spacing, so that the
    // origin is honoured, not assumed.
    let grid_origin = [456_125.0, 6_780_050.0];
    let (lo, hi) = mesh.bounds().expect("bounds");
    let bounds = (Vec3::from(lo), Vec3::from(hi));
    for coverage in [Coverage::Texture, Coverage::Analytic] {
        for sigma in [1.5f32, 3.0] {
            let style = Style {
                grid_lines: Some(GridLines {
                    origin: grid_origin,
                    color: [1.0, 1.0, 1.0, 1.0],
                    ..GridLines::new(SPACING, [o[0], o[1]])
                }),
                ..measuring_style(sigma, coverage)
            };
            for (zoom, distance) in [(1, 1.0f32), (2, 0.55), (4, 0.3)] {
                let view = View {
                    camera: Camera::fit(bounds.0, bounds.1, 2.0, 1.0, (20.0, 60.0), distance),
                    width: SIZE,
                    height: SIZE,
                    bounds,
                };
                let drawable = r.prepare(&mesh, WireMode::None).expect("prepare");
                let image = r
                    .render(&[drawable.as_ref()], &view, &style)
                    .expect("render");
                let frame = Frame::new(&image);
                let proj = Projector::new(&view);
                // A point on the terrain at map (mx, my), on screen.
                let on_screen = |mx: f64, my: f64| -> Option<Vec2> {
                    let (x, y) = ((mx - o[0]) as f32, (my - o[1]) as f32);
                    let z = surface_z(&mesh, x, y)?;
                    Some(proj.to_px(Vec3::new(x, y, z)))
                };
                let mut widths = Vec::new();
                let mut offsets = Vec::new();
                let mut peaks = Vec::new();
                let (map_lo, map_hi) = (
                    [f64::from(lo[0]) + o[0], f64::from(lo[1]) + o[1]],
                    [f64::from(hi[0]) + o[0], f64::from(hi[1]) + o[1]],
                );
                for axis in 0..2 {
                    let other = 1 - axis;
                    let first = ((map_lo[axis] - grid_origin[axis]) / SPACING).ceil() as i64;
                    let last = ((map_hi[axis] - grid_origin[axis]) / SPACING).floor() as i64;
                    for k in first..=last {
                        let line = grid_origin[axis] + k as f64 * SPACING;
                        let steps = 400;
                        for s in 0..steps {
                            let along = map_lo[other]
                                + (s as f64 + 0.5) / steps as f64 * (map_hi[other] - map_lo[other]);
                            // Keep clear of the crossing lines of the other family.
                            let rel = (along - grid_origin[other]) / SPACING;
                            let at = |a: f64, b: f64| {
                                if axis == 0 {
                                    on_screen(a, b)
                                } else {
                                    on_screen(b, a)
                                }
                            };
                            let (Some(p), Some(p0), Some(p1), Some(q)) = (
                                at(line, along),
                                at(line, along - 5.0),
                                at(line, along + 5.0),
                                at(line, rel.round() * SPACING + grid_origin[other]),
                            ) else {
                                continue;
                            };
                            if (q - p).length() < 0.5 * sigma + 6.0 {
                                continue;
                            }
                            // Lines must be measurable: neighbours at least 3 sigma away.
                            let (Some(n0), Some(n1)) =
                                (at(line - SPACING, along), at(line + SPACING, along))
                            else {
                                continue;
                            };
                            let t = (p1 - p0).normalize();
                            let gap = |n: Vec2| (n - p).perp_dot(t).abs();
                            if gap(n0).min(gap(n1)) < 3.0 * sigma + 6.0 {
                                continue;
                            }
                            if let Some((w, off, peak)) = scan(&frame, p, t, sigma) {
                                widths.push(w);
                                offsets.push(off.abs());
                                peaks.push(peak);
                            }
                        }
                    }
                }
                let (w, off) = (Summary::of(widths.clone()), Summary::of(offsets.clone()));
                eprintln!(
                    "{be} {coverage:?} sigma {sigma} zoom {zoom}: width {w} |offset| {off} peak {}",
                    Summary::of(peaks)
                );
                assert!(w.n >= 100, "zoom {zoom}: only {} scans", w.n);
                assert!(
                    off.max < 1.0 && offsets.iter().all(|o| o.is_finite()),
                    "zoom {zoom} sigma {sigma} {coverage:?}: a line centre {} px from its map position",
                    off.max
                );
                assert!(
                    w.min >= sigma - 0.5 && w.max <= sigma + 0.5,
                    "zoom {zoom} sigma {sigma} {coverage:?}: widths {w}"
                );
            }
        }
    }
}
