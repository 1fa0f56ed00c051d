//! `strata render`: a model's layers (and sides) shaded by a property with the cell
//! wireframe, to a PNG.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, ValueEnum};
use strata::render::glam::Vec3;
use strata::render::{
    Attenuation, Camera, Colormap, Coverage, Renderer, Style, View, WireMode, parse_color,
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
    Texture,
    Analytic,
}

#[derive(Args)]
pub struct RenderArgs {
    /// Model file (.grdecl, .DATA, .EGRID); the sample in data/ when omitted.
    model: Option<PathBuf>,
    /// One layer, 1-based.
    #[arg(long, conflicts_with = "layers")]
    layer: Option<usize>,
    /// A range of layers, 1-based and inclusive: A..B.
    #[arg(long, value_parser = parse_layers)]
    layers: Option<(usize, usize)>,
    /// Also draw the side faces: the outer shell and fault walls.
    #[arg(long)]
    sides: bool,
    /// Wireframe technique: none, global, quad, tex, texgs.
    #[arg(long, default_value = "global", value_parser = parse_wire)]
    wire: WireMode,
    /// Line thickness in pixels.
    #[arg(long, default_value_t = 1.5)]
    thickness: f32,
    /// Line colour: #rrggbb[aa] or a name (black, white, red, ...).
    #[arg(long, default_value = "#141414")]
    wire_color: String,
    /// Fade or thin lines with distance.
    #[arg(long, value_enum, default_value = "none")]
    attenuate: AttenuateArg,
    /// Line coverage from the mip-mapped texture or evaluated analytically.
    #[arg(long, value_enum, default_value = "texture")]
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
}

fn parse_wire(s: &str) -> Result<WireMode, String> {
    WireMode::from_name(s).ok_or_else(|| {
        format!(
            "unknown wire mode {s:?}; one of {}",
            strata::render::wire_mode_names().join(", ")
        )
    })
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

fn parse_view(s: &str) -> Result<(f32, f32, f32), String> {
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

fn parse_size(s: &str) -> Result<(u32, u32), String> {
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
    let path = args.model.clone().unwrap_or_else(crate::sample_model);
    let start = Instant::now();
    let grid = strata::grid::open(&path)?;
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
        flat_cells: !args.smooth,
    };
    let (mesh, range) = build(&grid, &options)?;
    let loaded = start.elapsed();

    let mut renderer = Renderer::headless()?;
    let drawable = renderer
        .prepare(&mesh, args.wire)
        .with_context(|| format!("preparing the {} wireframe", args.wire.name()))?;
    let (lo, hi) = mesh.bounds().ok_or_else(|| anyhow!("empty scene"))?;
    let bounds = (Vec3::from(lo), Vec3::from(hi));
    let (az, el, dist) = args.view;
    let view = View {
        camera: Camera::fit(
            bounds.0,
            bounds.1,
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
        coverage: match args.coverage {
            CoverageArg::Texture => Coverage::Texture,
            CoverageArg::Analytic => Coverage::Analytic,
        },
        isolation: args.isolation,
        colormap: Colormap::from_name(&args.colormap)
            .ok_or_else(|| anyhow!("unknown colour map {:?}", args.colormap))?,
        scalar_range: range,
        background: if args.isolation {
            [0.0, 0.0, 0.0, 1.0]
        } else {
            [1.0; 4]
        },
        ..Style::default()
    };
    let image = renderer.render(&[drawable.as_ref()], &view, &style)?;
    strata::render::save_png(&image, &args.output)?;
    eprintln!(
        "{}: {} triangles, {} wireframe, {}; model read in {:.2} s, frame in {:.2} s on {}",
        args.output.display(),
        mesh.triangle_count(),
        args.wire.name(),
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
