//! `strata render`: a model's layers (and sides) shaded by a property with the cell
//! wireframe, to a PNG.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, ValueEnum};
use strata::render::glam::Vec3;
use strata::render::wgpu::DeviceType;
use strata::render::{
    Attenuation, Camera, Colormap, Coverage, GridLines, IsolineOptions, Isolines, RangeAdjust,
    Renderer, Style, View, WireMode, parse_color,
};
use strata::scene::{SceneOptions, build};

#[derive(Clone, Copy, ValueEnum)]
enum AttenuateArg {
    None,
    Intensity,
    Thickness,
}

#[derive(Clone, Copy, ValueEnum)]
enum CoverageArg {
    /// Analytic on CPU rasterizers, the texture on GPUs.
    Auto,
    Texture,
    Analytic,
}

impl CoverageArg {
    /// The form to draw with on an adapter of `device`. `strata bench wire` measured
    /// the analytic form at 0.9-1.2 x the shaded frame on llvmpipe and lavapipe and
    /// the texture tap at 1.25-1.7 x: a CPU rasterizer pays for every filtered fetch,
    /// a GPU's texture units fetch nearly for free, and the texture keeps the
    /// attenuation table and arbitrary line profiles.
    fn resolve(self, device: DeviceType) -> Coverage {
        match self {
            CoverageArg::Auto if device == DeviceType::Cpu => Coverage::Analytic,
            CoverageArg::Auto | CoverageArg::Texture => Coverage::Texture,
            CoverageArg::Analytic => Coverage::Analytic,
        }
    }
}

#[derive(Args)]
pub struct RenderArgs {
    /// Model file (.grdecl, .DATA, .EGRID); the sample in data/ when omitted.
    model: Option<PathBuf>,
    /// GRDECL decks of per-cell properties to add (e.g. PORO beside an EGRID).
    #[arg(long = "props", value_name = "FILE")]
    props: Vec<PathBuf>,
    /// One layer, 1-based.
    #[arg(long, conflicts_with = "layers")]
    layer: Option<usize>,
    /// A range of layers, 1-based and inclusive: A..B.
    #[arg(long, value_parser = parse_layers)]
    layers: Option<(usize, usize)>,
    /// Also draw the side faces: the outer shell and fault walls.
    #[arg(long)]
    sides: bool,
    /// Wireframe technique: none, global, quad, tex, texgs, bias, dist, idbuffer.
    #[arg(long, default_value = "global", value_parser = parse_wire)]
    wire: WireMode,
    /// Hidden-line style (Rossignac & van Emmerik): tehs hides hidden edges, tehd dashes
    /// them, cehs and cehd draw contour edges only (outlines and silhouettes). bias,
    /// dist and idbuffer draw all four; the texture techniques tehs only.
    #[arg(long, default_value = "tehs", value_parser = parse_hidden)]
    hidden: strata::render::HiddenLines,
    /// Line thickness in pixels.
    #[arg(long, default_value_t = 1.5)]
    thickness: f32,
    /// Line colour: #rrggbb[aa] or a name (black, white, red, ...).
    #[arg(long, default_value = "#141414")]
    wire_color: String,
    /// Fade or thin lines with distance.
    #[arg(long, value_enum, default_value = "none")]
    attenuate: AttenuateArg,
    /// Line coverage from the mip-mapped texture or evaluated analytically (auto:
    /// analytic on CPU rasterizers, where it is the faster, the texture on GPUs).
    #[arg(long, value_enum, default_value = "auto")]
    coverage: CoverageArg,
    /// Lines alone, in the cells' colours, without the shaded surface.
    #[arg(long)]
    isolation: bool,
    /// Property colouring the cells (default: PORO when the model has it).
    #[arg(long)]
    property: Option<String>,
    /// Solid colour instead of a property.
    #[arg(long, conflicts_with = "property")]
    no_property: bool,
    /// Interpolate the property between nodes instead of painting cells flat.
    #[arg(long)]
    smooth: bool,
    /// Colour map: viridis, turbo, cividis, magma, inferno, plasma, spectral.
    #[arg(long, default_value = "viridis")]
    colormap: String,
    /// Vertical exaggeration.
    #[arg(long, default_value_t = 5.0)]
    zscale: f32,
    /// View: azimuth (degrees clockwise from north), elevation (degrees), and optionally
    /// distance as a multiple of the fitting distance.
    #[arg(long, default_value = "30,35", value_parser = parse_view)]
    view: (f32, f32, f32),
    /// Image size WxH.
    #[arg(long, default_value = "1200x900", value_parser = parse_size)]
    size: (u32, u32),
    /// Output PNG.
    #[arg(short, long, default_value = "strata.png")]
    output: PathBuf,
    /// Isolines of a property: PROPERTY[:SPACING[:MAJOR_EVERY]] (spacing: about ten
    /// lines over the range when omitted; every fifth line major by default). Drawn
    /// with the global wireframe or none.
    #[arg(long, value_parser = parse_iso)]
    iso: Option<(String, Option<f32>, u32)>,
    /// Range adjust of the isolines: on, off, or the papers' formulas paper2010 and
    /// paper2011 (the latter moves lines: kept to show it).
    #[arg(long, default_value = "on", value_parser = parse_adjust)]
    iso_adjust: RangeAdjust,
    /// Map grid lines: SPACING[,X0[,Y0]] in map units, through map (X0, Y0).
    #[arg(long, value_parser = parse_grid_lines)]
    grid_lines: Option<(f64, f64, f64)>,
    /// Decimate the drawn surfaces to PERCENT of their triangles (strata-lod) and draw
    /// the wireframe on the result: global draws the original grid lines, tex/texgs
    /// the decimated triangles. With global, each cell keeps its own colour (looked up
    /// by the global coordinates); with the others, colours are interpolated between
    /// nodes (decimated triangles are no longer cells). Says when PERCENT is below the
    /// triangles that keep every corner of the outlines, holes and fault traces; there
    /// meshoptimizer's simplify decimates instead, its result fitted to the original
    /// grid lines (as strata's is just above that).
    #[arg(long, value_name = "PERCENT", value_parser = super::lod::parse_percent, conflicts_with = "iso")]
    lod: Option<f64>,
    /// With --lod: let the outlines, holes and fault traces grow only outward in the
    /// decimation, and draw each decimated surface over the original's cells only (a
    /// cell mask by the global coordinates), so those lines stay exactly the
    /// original's at any budget; the result is fitted to the original grid lines.
    /// Global wireframe only.
    #[arg(long, requires = "lod")]
    cover: bool,
}

fn parse_iso(s: &str) -> Result<(String, Option<f32>, u32), String> {
    let mut parts = s.split(':');
    let name = parts
        .next()
        .filter(|n| !n.is_empty())
        .ok_or_else(|| format!("expected PROPERTY[:SPACING[:MAJOR_EVERY]], got {s:?}"))?;
    let spacing = parts
        .next()
        .map(|v| {
            v.trim()
                .parse::<f32>()
                .ok()
                .filter(|x| *x > 0.0 && x.is_finite())
                .ok_or_else(|| format!("{v:?} is not a positive spacing"))
        })
        .transpose()?;
    let major = parts
        .next()
        .map(|v| v.trim().parse::<u32>().map_err(|e| format!("{v:?}: {e}")))
        .transpose()?
        .unwrap_or(5);
    if parts.next().is_some() {
        return Err(format!(
            "expected PROPERTY[:SPACING[:MAJOR_EVERY]], got {s:?}"
        ));
    }
    Ok((name.to_string(), spacing, major))
}

fn parse_adjust(s: &str) -> Result<RangeAdjust, String> {
    RangeAdjust::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = RangeAdjust::ALL.iter().map(|(n, _)| *n).collect();
        format!("unknown range adjust {s:?}; one of {}", names.join(", "))
    })
}

/// SPACING[,X0[,Y0]]: Y0 defaults to X0, both to 0.
pub(crate) fn parse_grid_lines(s: &str) -> Result<(f64, f64, f64), String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>().map_err(|e| format!("{x:?}: {e}")))
        .collect::<Result<_, _>>()?;
    let (spacing, x0, y0) = match v.as_slice() {
        [d] => (*d, 0.0, 0.0),
        [d, x] => (*d, *x, *x),
        [d, x, y] => (*d, *x, *y),
        _ => return Err(format!("expected SPACING[,X0[,Y0]], got {s:?}")),
    };
    if !(spacing > 0.0 && spacing.is_finite() && x0.is_finite() && y0.is_finite()) {
        return Err(format!(
            "grid lines {s:?}: spacing must be positive, origin finite"
        ));
    }
    Ok((spacing, x0, y0))
}

/// A round spacing (1, 2 or 5 times a power of ten) giving about `lines` lines over
/// `range`.
fn nice_spacing(range: f32, lines: f32) -> f32 {
    let raw = (range / lines).max(f32::MIN_POSITIVE);
    let step = 10f32.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * step)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * step)
}

pub(crate) fn parse_wire(s: &str) -> Result<WireMode, String> {
    WireMode::from_name(s).ok_or_else(|| {
        format!(
            "unknown wire mode {s:?}; one of {}",
            strata::render::wire_mode_names().join(", ")
        )
    })
}

fn parse_hidden(s: &str) -> Result<strata::render::HiddenLines, String> {
    strata::render::HiddenLines::from_name(s)
        .ok_or_else(|| format!("unknown hidden-line style {s:?}; one of tehs, tehd, cehs, cehd"))
}

fn parse_layers(s: &str) -> Result<(usize, usize), String> {
    let (a, b) = s
        .split_once("..")
        .ok_or_else(|| format!("expected A..B, got {s:?}"))?;
    let num = |v: &str| {
        v.trim()
            .parse::<usize>()
            .ok()
            .filter(|&n| n >= 1)
            .ok_or_else(|| format!("{v:?} is not a 1-based layer"))
    };
    let (a, b) = (num(a)?, num(b)?);
    if a > b {
        return Err(format!("layer range {a}..{b} is empty"));
    }
    Ok((a, b))
}

pub(crate) fn parse_view(s: &str) -> Result<(f32, f32, f32), String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>().map_err(|e| format!("{x:?}: {e}")))
        .collect::<Result<_, _>>()?;
    match v.as_slice() {
        [az, el] => Ok((*az, *el, 1.0)),
        [az, el, d] if *d > 0.0 => Ok((*az, *el, *d)),
        _ => Err(format!("expected AZ,EL[,DIST] with DIST > 0, got {s:?}")),
    }
}

pub(crate) fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WxH, got {s:?}"))?;
    let dim = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|&n| (1..=16384).contains(&n))
            .ok_or_else(|| format!("{v:?} is not a size in 1..16384"))
    };
    Ok((dim(w)?, dim(h)?))
}

pub fn run(args: &RenderArgs) -> Result<()> {
    let start = Instant::now();
    let (_, grid) = super::open_model(args.model.as_deref(), &args.props)?;
    let nz = grid.dims().nz;
    let layers = match (args.layer, args.layers) {
        (Some(k), _) if (1..=nz).contains(&k) => Some(k - 1..k),
        (Some(k), _) => bail!("layer {k} is not within the model's 1..{nz}"),
        (None, Some((a, b))) => Some(a - 1..b),
        (None, None) => None,
    };
    let property = if args.no_property {
        None
    } else {
        match &args.property {
            Some(p) => Some(p.clone()),
            None => grid.property("PORO").map(|_| "PORO".to_string()),
        }
    };
    let options = SceneOptions {
        layers,
        sides: args.sides,
        property,
        flat_cells: !args.smooth && args.lod.is_none(),
    };
    let (mesh, range) = build(&grid, &options)?;
    if args.cover && args.wire != WireMode::Global {
        bail!("--cover draws with --wire global, not {}", args.wire.name());
    }
    let global = args.wire == WireMode::Global;
    let (mesh, cells) = match args.lod {
        Some(percent) => {
            super::lod::decimate_scene(&mesh, percent, args.zscale, args.cover, global)?
        }
        None => (mesh, None),
    };
    if args.lod.is_some() && !mesh.scalars.is_empty() && !global {
        eprintln!(
            "note: with --wire {}, colours are interpolated between the decimated surface's \
             nodes; --wire global colours each cell as the original does",
            args.wire.name()
        );
    }
    // Isolines need the property interpolated between nodes, whatever colours the
    // cells: one value per triangle corner of `mesh`.
    let iso = match &args.iso {
        Some((name, spacing, major)) => {
            let (field, iso_range) = isoline_field(&grid, &options, &mesh, name)?;
            let spacing = spacing.unwrap_or_else(|| nice_spacing(iso_range.1 - iso_range.0, 10.0));
            Some((field, spacing, *major))
        }
        None => None,
    };
    let loaded = start.elapsed();

    let mut renderer = Renderer::headless()?;
    let drawable = match &iso {
        Some((field, ..)) => {
            if !matches!(args.wire, WireMode::Global | WireMode::None) {
                bail!(
                    "--iso draws with --wire global or none, not {}",
                    args.wire.name()
                );
            }
            renderer.prepare_isolines(
                &mesh,
                Some(field),
                IsolineOptions {
                    adjust: args.iso_adjust,
                    wire: args.wire == WireMode::Global,
                },
            )?
        }
        None => match &cells {
            Some(cells) => renderer
                .prepare_cells(&mesh, &cells.draw())
                .context("preparing the global wireframe over the original's cells")?,
            None => renderer
                .prepare(&mesh, args.wire)
                .with_context(|| format!("preparing the {} wireframe", args.wire.name()))?,
        },
    };
    let (lo, hi) = mesh.bounds().ok_or_else(|| anyhow!("empty scene"))?;
    let bounds = (Vec3::from(lo), Vec3::from(hi));
    let (az, el, dist) = args.view;
    let view = View {
        camera: Camera::fit_points(
            mesh.positions.iter().map(|&p| Vec3::from(p)),
            args.zscale,
            args.size.0 as f32 / args.size.1 as f32,
            (az, el),
            dist,
        ),
        width: args.size.0,
        height: args.size.1,
        bounds,
    };
    let style = Style {
        thickness: args.thickness,
        wire_color: parse_color(&args.wire_color)
            .ok_or_else(|| anyhow!("--wire-color {:?} is not a colour", args.wire_color))?,
        attenuation: match args.attenuate {
            AttenuateArg::None => Attenuation::None,
            AttenuateArg::Intensity => Attenuation::Intensity,
            AttenuateArg::Thickness => Attenuation::Thickness,
        },
        coverage: args.coverage.resolve(renderer.gpu.info.device_type),
        isolation: args.isolation,
        hidden: args.hidden,
        colormap: Colormap::from_name(&args.colormap)
            .ok_or_else(|| anyhow!("unknown colour map {:?}", args.colormap))?,
        scalar_range: range,
        background: if args.isolation {
            [0.0, 0.0, 0.0, 1.0]
        } else {
            [1.0; 4]
        },
        isolines: iso.as_ref().map(|(_, spacing, major)| Isolines {
            major_every: *major,
            ..Isolines::new(*spacing)
        }),
        grid_lines: args.grid_lines.map(|(spacing, x0, y0)| GridLines {
            origin: [x0, y0],
            ..GridLines::new(spacing, [mesh.origin[0], mesh.origin[1]])
        }),
        ..Style::default()
    };
    let image = renderer.render(&[drawable.as_ref()], &view, &style)?;
    strata::render::save_png(&image, &args.output)?;
    eprintln!(
        "{}: {} triangles, {} wireframe ({} coverage), {}; model read in {:.2} s, frame in {:.2} s on {}",
        args.output.display(),
        mesh.triangle_count(),
        args.wire.name(),
        match style.coverage {
            Coverage::Texture => "texture",
            Coverage::Analytic => "analytic",
        },
        match (&options.property, range) {
            (Some(p), Some((lo, hi))) => format!("{p} {lo:.4}..{hi:.4}"),
            _ => "solid colour".to_string(),
        },
        loaded.as_secs_f64(),
        (start.elapsed() - loaded).as_secs_f64(),
        renderer.gpu.describe()
    );
    Ok(())
}

/// The isoline field of property `name` per triangle corner of `mesh` (built with
/// `options`), from the same surfaces with the property averaged onto nodes, and the
/// range of its defined values. Cell-painted meshes list their triangles face by
/// face (`SurfaceMesh::with_cell_values`), smooth ones in extraction order.
fn isoline_field(
    grid: &strata::grid::CornerPointGrid,
    options: &SceneOptions,
    mesh: &strata::grid::SurfaceMesh,
    name: &str,
) -> Result<(Vec<f32>, (f32, f32))> {
    if grid.property(name).is_none() {
        bail!("--iso: the model has no property {name}");
    }
    let smooth_options = SceneOptions {
        property: Some(name.to_string()),
        flat_cells: false,
        ..options.clone()
    };
    let (smooth, range) = build(grid, &smooth_options)?;
    let range = range.ok_or_else(|| anyhow!("--iso: {name} has no defined value here"))?;
    let corners = |t: u32| smooth.triangles[t as usize].map(|v| smooth.scalars[v as usize]);
    let cell_painted = options.flat_cells && options.property.is_some();
    let field: Vec<f32> = if cell_painted {
        smooth
            .cell_faces
            .iter()
            .flat_map(|f| f.triangles)
            .flat_map(corners)
            .collect()
    } else {
        (0..smooth.triangle_count() as u32)
            .flat_map(corners)
            .collect()
    };
    if field.len() != 3 * mesh.triangle_count() {
        bail!(
            "--iso: {} isoline values for {} triangles",
            field.len(),
            mesh.triangle_count()
        );
    }
    Ok((field, range))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_coverage_is_analytic_on_cpu_rasterizers_only() {
        use DeviceType::{Cpu, DiscreteGpu, IntegratedGpu};
        assert_eq!(CoverageArg::Auto.resolve(Cpu), Coverage::Analytic);
        assert_eq!(CoverageArg::Auto.resolve(DiscreteGpu), Coverage::Texture);
        assert_eq!(CoverageArg::Auto.resolve(IntegratedGpu), Coverage::Texture);
        assert_eq!(CoverageArg::Texture.resolve(Cpu), Coverage::Texture);
        assert_eq!(
            CoverageArg::Analytic.resolve(DiscreteGpu),
            Coverage::Analytic
        );
    }
}
