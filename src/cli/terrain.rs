//! `strata terrain`: a TIN from scattered picks (a file of x, y, z lines, or
//! generated), triangulated with constrained Delaunay, drawn shaded by elevation with
//! map grid lines of constant thickness and optional depth contours, to a PNG.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use strata::grid::terrain::{self, TerrainInput, TerrainSynth};
use strata::render::glam::Vec3;
use strata::render::{
    Camera, Colormap, GridLines, IsolineOptions, Isolines, RangeAdjust, Renderer, Style, View,
    WireMode,
};

use super::parse::{parse_grid_lines, parse_size, parse_view, parse_zscale};

#[derive(Args)]
pub struct TerrainArgs {
    /// Picks: one `x, y, z` per line (a header line is allowed). Omit with --generate.
    points: Option<PathBuf>,
    /// Generate N picks on a synthetic faulted dome instead of reading a file (with
    /// its own outline and fault trace).
    #[arg(long, value_name = "N", conflicts_with = "points")]
    generate: Option<usize>,
    /// Seed of the generated picks.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Also write the generated picks to this file (x,y,z).
    #[arg(long, value_name = "CSV")]
    write_points: Option<PathBuf>,
    /// The file's z is depth (positive down), not elevation.
    #[arg(long)]
    depth: bool,
    /// Outline (x, y per line): triangles outside are dropped.
    #[arg(long, value_name = "CSV")]
    boundary: Option<PathBuf>,
    /// Fault trace (x, y per line), kept as triangle edges; may be repeated.
    #[arg(long, value_name = "CSV")]
    fault: Vec<PathBuf>,
    /// Map grid lines: SPACING[,X0[,Y0]] in map units, through map (X0, Y0).
    #[arg(long, default_value = "500", value_parser = parse_grid_lines)]
    grid_lines: (f64, f64, f64),
    /// Elevation contours every SPACING metres, every MAJOR-th one darker:
    /// SPACING[:MAJOR].
    #[arg(long, value_parser = parse_contours)]
    contours: Option<(f32, u32)>,
    /// Also draw the triangle edges (texgs: per-triangle coordinates).
    #[arg(long)]
    edges: bool,
    /// Line thickness in pixels.
    #[arg(long, default_value_t = 1.5)]
    thickness: f32,
    /// Vertical exaggeration.
    #[arg(long, default_value_t = 3.0, value_parser = parse_zscale)]
    zscale: f32,
    /// View: azimuth, elevation (degrees)[, distance factor].
    #[arg(long, default_value = "20,50", value_parser = parse_view)]
    view: (f32, f32, f32),
    /// Image size WxH.
    #[arg(long, default_value = "1200x900", value_parser = parse_size)]
    size: (u32, u32),
    /// Colour map of elevation.
    #[arg(long, default_value = "viridis")]
    colormap: String,
    /// Output PNG.
    #[arg(short, long, default_value = "terrain.png")]
    output: PathBuf,
}

fn parse_contours(s: &str) -> Result<(f32, u32), String> {
    let (spacing, major) = match s.split_once(':') {
        Some((a, b)) => (a, Some(b)),
        None => (s, None),
    };
    let spacing = spacing
        .trim()
        .parse::<f32>()
        .ok()
        .filter(|v| *v > 0.0 && v.is_finite())
        .ok_or_else(|| format!("{spacing:?} is not a positive spacing"))?;
    let major = match major {
        Some(m) => m.trim().parse::<u32>().map_err(|e| format!("{m:?}: {e}"))?,
        None => 5,
    };
    Ok((spacing, major))
}

/// Bytes a pick costs from the triangulation to the frame, at the peak. Measured on
/// generated picks; the figures are in docs/performance.md ("Drawing in parts, and
/// memory").
const TIN_BYTES_PER_PICK: f64 = 400.0;

pub fn run(args: &TerrainArgs) -> Result<()> {
    let inputs: Vec<&Path> = args
        .points
        .iter()
        .chain(&args.boundary)
        .chain(&args.fault)
        .map(PathBuf::as_path)
        .collect();
    super::refuse_overwriting(&args.output, &inputs)?;
    let input = match (&args.points, args.generate) {
        (Some(path), None) => TerrainInput {
            points: terrain::read_points(path, args.depth)?,
            boundary: args
                .boundary
                .as_deref()
                .map(terrain::read_polyline)
                .transpose()?,
            faults: args
                .fault
                .iter()
                .map(|f| terrain::read_polyline(f))
                .collect::<Result<_, _>>()?,
        },
        (None, Some(n)) => {
            super::check_memory(
                n as f64 * TIN_BYTES_PER_PICK,
                &format!("{n} picks"),
                "to triangulate",
            )?;
            let input = TerrainSynth {
                points: n,
                seed: args.seed,
                ..TerrainSynth::default()
            }
            .generate();
            if let Some(out) = &args.write_points {
                terrain::write_points(out, &input.points)?;
                eprintln!("wrote {} picks to {}", input.points.len(), out.display());
            }
            input
        }
        _ => bail!("give a file of picks or --generate N"),
    };
    let picks = input.points.len();
    super::check_memory(
        picks as f64 * TIN_BYTES_PER_PICK,
        &format!("{picks} picks"),
        "to triangulate",
    )?;
    let tin = terrain::triangulate(&input).context("triangulating the picks")?;
    let mesh = &tin.mesh;
    if tin.duplicates > 0 || tin.conflicting_constraints > 0 {
        eprintln!(
            "note: {} duplicate picks dropped, {} crossing constraint segments dropped",
            tin.duplicates, tin.conflicting_constraints
        );
    }
    let (lo, hi) = mesh.bounds().ok_or_else(|| anyhow!("empty terrain"))?;
    let bounds = (Vec3::from(lo), Vec3::from(hi));
    let (az, el, dist) = args.view;
    let aspect = args.size.0 as f32 / args.size.1 as f32;
    let view = View {
        camera: Camera::fit(bounds.0, bounds.1, args.zscale, aspect, (az, el), dist),
        width: args.size.0,
        height: args.size.1,
        bounds,
    };
    let (spacing, x0, y0) = args.grid_lines;
    let style = Style {
        thickness: args.thickness,
        colormap: Colormap::from_name(&args.colormap)
            .ok_or_else(|| anyhow!("unknown colour map {:?}", args.colormap))?,
        scalar_range: Some((lo[2], hi[2].max(lo[2] + 1.0))),
        wire_color: [0.25, 0.25, 0.25, 0.6],
        isolines: args.contours.map(|(spacing, major)| Isolines {
            major_every: major,
            color: [0.05, 0.05, 0.05, 0.9],
            ..Isolines::new(spacing)
        }),
        grid_lines: Some(GridLines {
            origin: [x0, y0],
            color: [1.0, 1.0, 1.0, 0.9],
            ..GridLines::new(spacing, [mesh.origin[0], mesh.origin[1]])
        }),
        ..Style::default()
    };
    let mut renderer = Renderer::headless()?;
    let drawable = if args.edges {
        renderer.prepare(mesh, WireMode::TexGs)?
    } else {
        renderer.prepare_isolines(
            mesh,
            None,
            IsolineOptions {
                adjust: RangeAdjust::On,
                wire: false,
            },
        )?
    };
    let image = renderer.render(&[drawable.as_ref()], &view, &style)?;
    strata::render::save_png(&image, &args.output)?;
    eprintln!(
        "{}: {} picks, {} triangles, elevation {:.1}..{:.1} m, grid every {spacing} m, on {}",
        args.output.display(),
        input.points.len(),
        mesh.triangle_count(),
        lo[2],
        hi[2],
        renderer.gpu.describe()
    );
    Ok(())
}
