//! Measured image tests of isolines (Celes & Abraham 2011 section 6): on a plane
//! carrying f = x² + y² (steep) and f = 0.001 (x² + y²) (nearly flat), the drawn
//! isolines are measured across, all around each circle, against the analytic contour
//! (see support/mod.rs for the measuring convention: black surface, white lines, the
//! red channel is coverage).

mod support;

use strata_grid::SurfaceMesh;
use strata_lod::{CellCover, Options, decimate};
use strata_render::glam::{Vec2, Vec3};
use strata_render::wire::Drawable;
use strata_render::{
    Camera, Coverage, IsolineOptions, Isolines, RangeAdjust, Renderer, Style, View, WireMode,
};
use strata_render::{CellDraw, TiledCells};
use support::{Frame, Projector, Summary, measuring_style, renderer};

/// Image size; the plane [-1, 1]² fills it head-on, so the screen is an exact
/// similarity of the plane and a contour circle is a circle on screen.
const SIZE: u32 = 512;
const SIGMA: f32 = 2.0;
/// How far a scan reaches either side of the contour, pixels.
const REACH: f32 = 0.5 * SIGMA + 3.0;

/// The plane [-1, 1]² in `n` x `n` cells carrying `scale (x² + y²)`.
fn paraboloid(n: usize, scale: f32) -> SurfaceMesh {
    let h = 2.0 / n as f32;
    let mut mesh =
        SurfaceMesh::structured(n, n, |i, j| [i as f32 * h - 1.0, j as f32 * h - 1.0, 0.0]);
    mesh.scalars = mesh
        .positions
        .iter()
        .map(|p| scale * (p[0] * p[0] + p[1] * p[1]))
        .collect();
    mesh
}

/// Head-on view of the plane, filling the image.
fn head_on() -> View {
    let fov: f32 = 35.0;
    let distance = 1.0 / (0.5 * fov.to_radians()).tan();
    let mut camera = Camera::look_at(Vec3::new(0.0, 0.0, distance), Vec3::ZERO, Vec3::Y);
    camera.fov_y_deg = fov;
    View {
        camera,
        width: SIZE,
        height: SIZE,
        bounds: (Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)),
    }
}

fn style(isolines: Isolines, coverage: Coverage) -> Style {
    Style {
        isolines: Some(Isolines {
            color: [1.0, 1.0, 1.0, 1.0],
            major_every: 0,
            ..isolines
        }),
        ..measuring_style(SIGMA, coverage)
    }
}

/// One measurement across a contour circle.
#[derive(Clone, Copy, Debug)]
struct Scan {
    /// Signed distance of the measured centre from the analytic contour, pixels.
    offset: f32,
    /// Full width at half coverage, perpendicular to the contour, pixels.
    width: f32,
    peak: f32,
}

/// Measures the circle of radius `r_px` about `centre` (pixels) at `count` angles: along
/// the pixel row (or column, where the circle runs closer to horizontal) through each
/// point, the two half-coverage crossings, interpolated between pixel centres, give
/// the width (times the normal's component along the scan) and the centre. Scans that
/// would come near the radii in `others` are skipped; each scan reaches `reach` px
/// either side of the contour.
fn measure_circle(
    frame: &Frame,
    centre: Vec2,
    r_px: f32,
    count: usize,
    others: &[f32],
    reach: f32,
) -> Vec<Scan> {
    let mut scans = Vec::new();
    for a in 0..count {
        let theta = (a as f32 + 0.5) / count as f32 * std::f32::consts::TAU;
        let n = Vec2::new(theta.cos(), theta.sin());
        let rows = n.x.abs() >= n.y.abs();
        let p = centre + n * r_px;
        // The scan line through p and where the analytic circle crosses it.
        let (fixed, along_c, across_c) = if rows {
            (p.y.floor() + 0.5, centre.x, centre.y)
        } else {
            (p.x.floor() + 0.5, centre.y, centre.x)
        };
        let q = fixed - across_c;
        if q.abs() >= r_px {
            continue;
        }
        let half_chord = (r_px * r_px - q * q).sqrt();
        let sign = if rows { n.x.signum() } else { n.y.signum() };
        let cross = along_c + sign * half_chord;
        // The normal at the crossing, and the stretch of the scan across the line.
        let normal = if rows {
            Vec2::new(cross - centre.x, fixed - centre.y)
        } else {
            Vec2::new(fixed - centre.x, cross - centre.y)
        }
        .normalize();
        let stretch = if rows { normal.x.abs() } else { normal.y.abs() };
        let reach_px = reach / stretch;
        if others
            .iter()
            .any(|&o| (o - r_px).abs() < reach + 0.5 * SIGMA + 1.5)
        {
            continue;
        }
        let first = (cross - reach_px - 0.5).floor() as i64;
        let last = (cross + reach_px - 0.5).ceil() as i64;
        let mut pos = Vec::new();
        let mut cov = Vec::new();
        let mut on_surface = true;
        for k in first..=last {
            let (x, y) = if rows {
                (k, fixed.floor() as i64)
            } else {
                (fixed.floor() as i64, k)
            };
            match frame.at(x, y) {
                Some((c, true)) => {
                    pos.push(k as f32 + 0.5);
                    cov.push(c);
                }
                _ => on_surface = false,
            }
        }
        if !on_surface {
            continue;
        }
        let (peak, edges) = support::half_coverage_edges(&pos, &cov);
        let (width, offset) = match edges {
            Some((lo, hi)) => (
                (hi - lo) * stretch,
                (0.5 * (lo + hi) - cross) * stretch * sign,
            ),
            // A gap (or a line wider than the scan): width 0, offset NaN, which every
            // check rejects.
            None => (0.0, f32::NAN),
        };
        scans.push(Scan {
            offset,
            width,
            peak,
        });
    }
    scans
}

/// Screen centre and pixels per world unit of the head-on view.
fn screen_frame(view: &View) -> (Vec2, f32) {
    let proj = Projector::new(view);
    let c = proj.to_px(Vec3::ZERO);
    let scale = (proj.to_px(Vec3::X) - c).length();
    let check = (proj.to_px(Vec3::Y) - c).length();
    assert!(
        (scale - check).abs() < 1e-3 * scale,
        "the view is not a similarity"
    );
    (c, scale)
}

struct Measured {
    offsets: Summary,
    abs_offsets: Summary,
    widths: Summary,
    peaks: Summary,
}

impl Measured {
    fn of(scans: &[Scan]) -> Self {
        Measured {
            offsets: Summary::of(scans.iter().map(|s| s.offset)),
            abs_offsets: Summary::of(scans.iter().map(|s| s.offset.abs())),
            widths: Summary::of(scans.iter().map(|s| s.width)),
            peaks: Summary::of(scans.iter().map(|s| s.peak)),
        }
    }
}

/// Draws `mesh` with the isoline technique and `adjust`, and measures the contour
/// circles of the given radii (plane units).
fn draw_and_measure(
    r: &mut Renderer,
    mesh: &SurfaceMesh,
    isolines: Isolines,
    circles: &[f32],
    adjust: RangeAdjust,
    coverage: Coverage,
    reach: f32,
) -> Vec<Scan> {
    let view = head_on();
    let drawable = r
        .prepare_isolines(
            mesh,
            None,
            IsolineOptions {
                adjust,
                wire: false,
            },
        )
        .expect("prepare isolines");
    let image = r
        .render(&[drawable.as_ref()], &view, &style(isolines, coverage))
        .expect("render");
    let frame = Frame::new(&image);
    let (centre, px) = screen_frame(&view);
    let radii: Vec<f32> = circles.iter().map(|c| c * px).collect();
    let mut scans = Vec::new();
    for (i, &rad) in radii.iter().enumerate() {
        let others: Vec<f32> = radii
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .map(|(_, &o)| o)
            .collect();
        scans.extend(measure_circle(&frame, centre, rad, 720, &others, reach));
    }
    scans
}

fn report(label: &str, r: &Renderer, scans: &[Scan]) -> Measured {
    let m = Measured::of(scans);
    eprintln!(
        "{} {label}: offset {} |offset| {} width {} peak {}",
        support::backend(r),
        m.offsets,
        m.abs_offsets,
        m.widths,
        m.peaks
    );
    m
}

/// Lines through `values` only: the spacing is larger than the field's range.
fn single(value: f32, spacing: f32) -> Isolines {
    Isolines {
        offset: value,
        ..Isolines::new(spacing)
    }
}

fn assert_on_contour_and_sigma_wide(label: &str, m: &Measured) {
    assert!(m.widths.n >= 200, "{label}: only {} scans", m.widths.n);
    assert!(
        m.abs_offsets.max < 1.0,
        "{label}: a centre {} px from the contour",
        m.abs_offsets.max
    );
    assert!(
        m.widths.min >= SIGMA - 0.5 && m.widths.max <= SIGMA + 0.5,
        "{label}: widths {} outside sigma {SIGMA} +- 0.5",
        m.widths
    );
    // No gap anywhere along the lines, across triangle edges included: every scan
    // (one every 0.2 to 0.6 px of arc) finds the line, nearly opaque (a 2 px line
    // fully covers some pixel when axis-aligned, 88 % of one at 45 degrees).
    assert!(m.peaks.min > 0.8, "{label}: a gap, peaks {}", m.peaks);
}

#[test]
fn steep_field_isolines_lie_on_their_contours_sigma_wide() {
    let mut r = renderer();
    let mesh = paraboloid(32, 1.0);
    // Circles r² = 0.1, 0.2, ... 0.8: 13 to 15 px apart at 256 px per unit.
    let values: Vec<f32> = (1..=8).map(|k| 0.1 * k as f32).collect();
    let iso = Isolines::new(0.1);
    for coverage in [Coverage::Texture, Coverage::Analytic] {
        for adjust in [RangeAdjust::Off, RangeAdjust::On] {
            let circles: Vec<f32> = values.iter().map(|v| v.sqrt()).collect();
            let scans = draw_and_measure(&mut r, &mesh, iso, &circles, adjust, coverage, REACH);
            let label = format!("steep {coverage:?} adjust {adjust:?}");
            let m = report(&label, &r, &scans);
            assert_on_contour_and_sigma_wide(&label, &m);
        }
    }
    // Every fragment path of the texture family draws the same isolines from its
    // interpolated scalar.
    for mode in [
        WireMode::None,
        WireMode::Global,
        WireMode::Tex,
        WireMode::TexGs,
    ] {
        let drawable = r.prepare(&mesh, mode).expect("prepare");
        let scans = measure_unwired(&mut r, drawable.as_ref(), iso, &values);
        let label = format!("steep fragment path of {}", mode.name());
        let m = report(&label, &r, &scans);
        assert_on_contour_and_sigma_wide(&label, &m);
    }
}

/// Draws `drawable` head-on with `iso` and its wire made invisible, so that only
/// isolines are measured, and measures the contour circles of x² + y² = `values`.
fn measure_unwired(
    r: &mut Renderer,
    drawable: &dyn Drawable,
    iso: Isolines,
    values: &[f32],
) -> Vec<Scan> {
    let view = head_on();
    let (centre, px) = screen_frame(&view);
    let radii: Vec<f32> = values.iter().map(|v| v.sqrt() * px).collect();
    let image = r
        .render(
            &[drawable],
            &view,
            &Style {
                wire_color: [1.0, 1.0, 1.0, 0.0],
                ..style(iso, Coverage::Texture)
            },
        )
        .expect("render");
    let frame = Frame::new(&image);
    radii
        .iter()
        .flat_map(|&rad| {
            let others: Vec<f32> = radii.iter().copied().filter(|&o| o != rad).collect();
            measure_circle(&frame, centre, rad, 720, &others, REACH)
        })
        .collect()
}

#[test]
fn a_flat_patch_on_a_line_value_is_clear_and_its_edge_is_the_line() {
    let mut r = renderer();
    // A plateau at 0.25 inside the circle r = 0.5 of the paraboloid x² + y²: its
    // triangles are flat at exactly the value of the one line drawn.
    let mut mesh = paraboloid(32, 1.0);
    for f in &mut mesh.scalars {
        *f = f.max(0.25);
    }
    let view = head_on();
    let (centre, px) = screen_frame(&view);
    for (adjust, coverage) in [
        (RangeAdjust::On, Coverage::Texture),
        (RangeAdjust::Off, Coverage::Analytic),
    ] {
        let drawable = r
            .prepare_isolines(
                &mesh,
                None,
                IsolineOptions {
                    adjust,
                    wire: false,
                },
            )
            .expect("prepare isolines");
        let image = r
            .render(
                &[drawable.as_ref()],
                &view,
                &style(single(0.25, 1.0), coverage),
            )
            .expect("render");
        let frame = Frame::new(&image);
        // Line pixels by distance from the centre, in plane units.
        let (mut inside, mut edge) = (0, 0);
        for y in 0..SIZE as i64 {
            for x in 0..SIZE as i64 {
                let Some((c, true)) = frame.at(x, y) else {
                    continue;
                };
                let d = (Vec2::new(x as f32 + 0.5, y as f32 + 0.5) - centre).length() / px;
                if c > 0.5 && d < 0.35 {
                    inside += 1;
                }
                if c > 0.5 && (0.4..0.55).contains(&d) {
                    edge += 1;
                }
            }
        }
        eprintln!(
            "{} plateau {adjust:?} {coverage:?}: {inside} line pixels inside, {edge} at its edge",
            support::backend(&r)
        );
        assert_eq!(inside, 0, "{adjust:?}: the plateau is drawn as a line");
        // The edge is about 2 pi 0.5 256 = 804 px around, the line sigma wide.
        assert!(
            edge > 800,
            "{adjust:?}: the plateau's edge has {edge} line pixels"
        );
    }
}

/// The line pixels of `mesh` seen at a grazing angle in perspective (depth, and so the
/// perspective-correct interpolation, changes across every triangle), with isolines
/// `iso` drawn by the isoline technique with each range adjust and by the global
/// wireframe's fragment path.
fn grazing_line_pixels(
    r: &mut Renderer,
    mesh: &SurfaceMesh,
    iso: Isolines,
) -> Vec<(String, usize)> {
    let mut camera = Camera::look_at(Vec3::new(0.0, -2.6, 0.35), Vec3::ZERO, Vec3::Z);
    camera.fov_y_deg = 35.0;
    let view = View {
        camera,
        width: SIZE,
        height: SIZE,
        bounds: (Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)),
    };
    let mut drawables = Vec::new();
    for adjust in [RangeAdjust::On, RangeAdjust::Off] {
        let options = IsolineOptions {
            adjust,
            wire: false,
        };
        let drawable = r
            .prepare_isolines(mesh, None, options)
            .expect("prepare isolines");
        drawables.push((format!("isoline technique, adjust {adjust:?}"), drawable));
    }
    let global = r.prepare(mesh, WireMode::Global).expect("prepare global");
    drawables.push(("global wireframe's fragment path".to_string(), global));
    let unwired = Style {
        wire_color: [1.0, 1.0, 1.0, 0.0],
        ..style(iso, Coverage::Analytic)
    };
    drawables
        .into_iter()
        .map(|(label, drawable)| {
            let image = r
                .render(&[drawable.as_ref()], &view, &unwired)
                .expect("render");
            let frame = Frame::new(&image);
            let surface = frame.surface.iter().filter(|&&s| s).count();
            assert!(surface > 20_000, "{label}: the plane covers {surface} px");
            let lines = frame
                .coverage
                .iter()
                .zip(&frame.surface)
                .filter(|&(&c, &s)| s && c > 0.1)
                .count();
            (label, lines)
        })
        .collect()
}

#[test]
fn a_field_flat_at_a_line_value_shows_no_rounding_speckle_at_a_grazing_angle() {
    let mut r = renderer();
    // Lines every 0.01 from 0.08, as strata picks them for SPE9's porosity.
    let porosity = Isolines {
        offset: 0.08,
        ..Isolines::new(0.01)
    };
    // Every value SPE9's layers carry, each a whole plane at one porosity: several
    // lie on a line's value up to f32 rounding. Before the rounding was allowed
    // for, these planes sprayed line pixels wherever the interpolated value rounded
    // to within a pixel's gradient of the line (thousands of pixels on SPE9's render;
    // docs/performance.md). And a structure map's depth, 2000 m on a 10 m line:
    // interpolating the depth itself would round it 200 times coarser than its line
    // coordinate.
    let flat = (8..=17)
        .map(|k| (0.01 * k as f32, porosity))
        .chain([(2000.0, Isolines::new(10.0))]);
    for (value, iso) in flat {
        let mut mesh = paraboloid(16, 0.0);
        mesh.scalars.fill(value);
        for (label, lines) in grazing_line_pixels(&mut r, &mesh, iso) {
            eprintln!(
                "{} plane at {value}, {label}: {lines} line pixels",
                support::backend(&r)
            );
            assert_eq!(lines, 0, "{label}: a plane flat at {value} shows lines");
        }
    }
    // The same view draws a line that is there: the plane sloping through 0.13 along
    // y, the line across the whole plane.
    let mut mesh = paraboloid(16, 0.0);
    for (f, p) in mesh.scalars.iter_mut().zip(&mesh.positions) {
        *f = 0.13 + 0.004 * p[1];
    }
    for (label, lines) in grazing_line_pixels(&mut r, &mesh, porosity) {
        eprintln!(
            "{} sloping plane, {label}: {lines} line pixels",
            support::backend(&r)
        );
        assert!(lines > 500, "{label}: the line through 0.13 has {lines} px");
    }
}

#[test]
fn a_decimated_surface_draws_the_original_isolines_from_its_cells_corners() {
    let mut r = renderer();
    let mesh = paraboloid(32, 1.0);
    // The plane keeps its texture coordinates exactly (they are affine in x and y), so
    // what moves an isoline is only how its field is carried.
    let out = decimate(&mesh, &Options::fraction(&mesh, 0.1)).expect("decimate");
    let cover = CellCover::of(&mesh).expect("cell faces");
    let pieces = out.pieces(&mesh, &cover);
    let corners = cover.corner_values(&mesh).expect("corner values");
    let values: Vec<f32> = (1..=8).map(|k| 0.1 * k as f32).collect();
    let iso = Isolines::new(0.1);
    let original = r.prepare(&mesh, WireMode::Global).expect("original");
    let scans = measure_unwired(&mut r, original.as_ref(), iso, &values);
    let original = report("original", &r, &scans);
    let mut measured = Vec::new();
    for (label, corners) in [
        ("corner values", Some(&corners[..])),
        ("vertex scalars", None),
    ] {
        let drawable = r
            .prepare_cells(
                &out.mesh,
                &CellDraw {
                    pieces: &pieces,
                    cover: &cover,
                    values: None,
                    corners: corners.map(TiledCells::boxes),
                    mask: false,
                    wire: true,
                    stacking: None,
                },
            )
            .expect("prepare cells");
        let scans = measure_unwired(&mut r, drawable.as_ref(), iso, &values);
        let label = format!(
            "{} -> {} triangles, isolines from the {label}",
            mesh.triangle_count(),
            out.mesh.triangle_count()
        );
        measured.push((label.clone(), report(&label, &r, &scans)));
    }
    // From the original's field at the cells' corners: on the contours, sigma wide,
    // and where the original draws them.
    let (label, exact) = &measured[0];
    assert_on_contour_and_sigma_wide(label, exact);
    for (what, a, b) in [
        ("mean offset", exact.offsets.mean, original.offsets.mean),
        (
            "largest |offset|",
            exact.abs_offsets.max,
            original.abs_offsets.max,
        ),
        ("mean width", exact.widths.mean, original.widths.mean),
    ] {
        assert!(
            (a - b).abs() < 0.05,
            "{label}: {what} {a} px, the original's {b} px"
        );
    }
    // From the decimated vertices' scalars: the field is linear over far larger
    // triangles, and its isolines cut across the circles' arcs.
    let off = measured[1].1.abs_offsets.max;
    assert!(
        off >= 2.0,
        "{}: isolines within {off} px of their contours",
        measured[1].0
    );
}

#[test]
fn nearly_flat_field_keeps_sigma_with_the_adjust() {
    let mut r = renderer();
    // f = 0.001 r²: at r = 0.5 the isoline coordinate changes by 8e-5 units per
    // pixel, 3x less than one texel of the 4096-texel texture per pixel.
    let scale = 0.001;
    let mesh = paraboloid(32, scale);
    let value = scale * 0.25;
    let iso = single(value, 0.1);
    let mut widths = Vec::new();
    for adjust in [RangeAdjust::Off, RangeAdjust::On, RangeAdjust::Paper2010] {
        // Without the adjust the line is wide: scan far enough to find its edges.
        let reach = if adjust == RangeAdjust::Off {
            24.0
        } else {
            REACH
        };
        let scans = draw_and_measure(&mut r, &mesh, iso, &[0.5], adjust, Coverage::Texture, reach);
        let label = format!("flat Texture adjust {adjust:?}");
        let m = report(&label, &r, &scans);
        widths.push(m.widths.mean);
        // The papers' own factor is reported, not required: it leaves the triangles
        // beside the line unadjusted, so the line's anti-aliased edge is magnified
        // there wherever it reaches over a triangle edge.
        if adjust == RangeAdjust::On {
            assert_on_contour_and_sigma_wide(&label, &m);
        }
    }
    // Analytic coverage has no texture to magnify: sigma wide without the adjust.
    let scans = draw_and_measure(
        &mut r,
        &mesh,
        iso,
        &[0.5],
        RangeAdjust::Off,
        Coverage::Analytic,
        REACH,
    );
    let m = report("flat Analytic adjust Off", &r, &scans);
    assert_on_contour_and_sigma_wide("flat analytic, no adjust", &m);
    eprintln!(
        "{}: mean width without / with the adjust: {:.3} / {:.3} px",
        support::backend(&r),
        widths[0],
        widths[1]
    );
    // The problem the adjust solves: without it the texture is magnified and the
    // line is far wider than sigma.
    assert!(
        widths[0] > 2.0 * SIGMA,
        "without the adjust the flat-field line is only {} px wide",
        widths[0]
    );
}

#[test]
fn the_2010_pivot_keeps_isolines_at_their_value_and_the_2011_pivot_moves_them() {
    let mut r = renderer();
    let scale = 0.001;
    let mesh = paraboloid(32, scale);
    let value = scale * 0.25;
    let iso = single(value, 0.1);
    let mut off_contour = Vec::new();
    for adjust in [RangeAdjust::Paper2010, RangeAdjust::Paper2011] {
        let scans = draw_and_measure(
            &mut r,
            &mesh,
            iso,
            &[0.5],
            adjust,
            Coverage::Analytic,
            REACH,
        );
        let m = report(&format!("flat Analytic {adjust:?}"), &r, &scans);
        // Scans whose line is more than 1 px from the contour, or missing.
        let off = scans
            .iter()
            .filter(|s| !(s.offset.abs() <= 1.0 && s.width > 0.0))
            .count();
        eprintln!(
            "{} {adjust:?}: {off} of {} scans off the contour",
            support::backend(&r),
            scans.len()
        );
        assert!(scans.len() >= 200, "{adjust:?}: only {} scans", scans.len());
        off_contour.push((off, scans.len(), m));
    }
    // fM: every scan on the contour.
    assert_eq!(
        off_contour[0].0, 0,
        "2010 (fM): {:?}",
        off_contour[0].2.offsets
    );
    // fm: the line is drawn where u = fm + range, towards each triangle's lowest
    // corner, a different distance in each triangle: most of it is off the contour.
    let (off, n, _) = &off_contour[1];
    assert!(
        *off * 2 > *n,
        "2011 (fm): only {off} of {n} scans off the contour; the pivot should move the line"
    );
}
