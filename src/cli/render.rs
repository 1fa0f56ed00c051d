//! `strata render`: a model's layers (and sides) shaded by a property with the cell
//! wireframe, to a PNG.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use strata::render::glam::Vec3;
use strata::render::{
    Camera, Coverage, IsolineOptions, RangeAdjust, Renderer, Style, View, WireMode,
};
use strata::scene::{SceneOptions, build, column_top};

use super::ReadArgs;
use super::style::{FrameArgs, IsoSpacing, LayerArgs, StyleArgs, decimated_wire, parse_iso};

#[derive(Args)]
pub struct RenderArgs {
    /// Model file (.grdecl, .DATA, .EGRID); the sample in data/ when omitted.
    model: Option<PathBuf>,
    #[command(flatten)]
    read: ReadArgs,
    #[command(flatten)]
    drawn: LayerArgs,
    #[command(flatten)]
    style: StyleArgs,
    /// Property colouring the cells (default: PORO when the model has it).
    #[arg(long)]
    property: Option<String>,
    /// Solid colour instead of a property.
    #[arg(long, conflicts_with = "property")]
    no_property: bool,
    /// Interpolate the property between nodes instead of painting cells flat.
    #[arg(long)]
    smooth: bool,
    #[command(flatten)]
    frame: FrameArgs,
    /// Output PNG.
    #[arg(short, long, default_value = "strata.png")]
    output: PathBuf,
    /// Isolines of a property: PROPERTY[:SPACING[:MAJOR_EVERY]] (spacing: about ten
    /// lines over the range when omitted; every fifth line major by default). Drawn
    /// with the global wireframe or none.
    #[arg(long, value_parser = parse_iso)]
    iso: Option<(String, IsoSpacing)>,
    /// Range adjust of the isolines: on, off, or the papers' formulas paper2010 and
    /// paper2011 (the latter moves lines: kept to show it).
    #[arg(long, default_value = "on", value_parser = parse_adjust)]
    iso_adjust: RangeAdjust,
    /// Decimate the drawn surfaces to PERCENT of their triangles (strata-lod) and draw
    /// the wireframe on the result: global draws the original grid lines, tex/texgs
    /// the decimated triangles (quad, which needs cell faces, is refused). With global
    /// or none, each cell keeps its own colour (looked up by the global coordinates);
    /// with the others, colours are interpolated between nodes (decimated triangles are
    /// no longer cells). Says when PERCENT is below the triangles that keep every corner
    /// of the outlines, holes and fault traces; there
    /// meshoptimizer's simplify decimates instead, its result fitted to the original
    /// grid lines (as strata's is just above that). With --iso the isolines are the
    /// original's: each fragment evaluates the original surface's field from its global
    /// coordinates, as it takes its cell's colour (--wire global or none).
    #[arg(long, value_name = "PERCENT", value_parser = super::lod::parse_percent)]
    lod: Option<f64>,
    /// With --lod: let the outlines, holes and fault traces grow only outward in the
    /// decimation, and draw each decimated surface over the original's cells only (a
    /// cell mask by the global coordinates), so those lines stay exactly the
    /// original's at any budget; the result is fitted to the original grid lines.
    /// Global wireframe only.
    #[arg(long, requires = "lod")]
    cover: bool,
}

fn parse_adjust(s: &str) -> Result<RangeAdjust, String> {
    RangeAdjust::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = RangeAdjust::ALL.iter().map(|(n, _)| *n).collect();
        format!("unknown range adjust {s:?}; one of {}", names.join(", "))
    })
}

pub fn run(args: &RenderArgs) -> Result<()> {
    let start = Instant::now();
    let wire = match args.lod {
        Some(_) => decimated_wire(args.style.wire, "--lod")?,
        None => args.style.wire,
    };
    let (_, grid) = super::open_model(args.model.as_deref(), &args.read)?;
    super::warn_skipped(&grid);
    let layers = args.drawn.range(grid.dims().nz)?;
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
        sides: args.drawn.sides,
        property,
        flat_cells: !args.smooth && args.lod.is_none(),
    };
    let (mesh, range) = build(&grid, &options)?;
    if args.cover && wire != WireMode::Global {
        bail!("--cover draws with --wire global, not {}", wire.name());
    }
    if args.iso.is_some() && !matches!(wire, WireMode::Global | WireMode::None) {
        bail!(
            "--iso draws with --wire global or none, not {}",
            wire.name()
        );
    }
    let global = wire == WireMode::Global;
    // The global coordinates find the original's cells, their colours and isolines,
    // with or without the original's grid lines over them.
    let by_cells = global || wire == WireMode::None;
    let (mesh, mut cells) = match args.lod {
        Some(percent) => super::lod::decimate_scene(
            &mesh,
            percent,
            args.frame.zscale,
            args.cover,
            by_cells && (!mesh.scalars.is_empty() || args.iso.is_some()),
        )?,
        None => (mesh, None),
    };
    if args.lod.is_some() && !mesh.scalars.is_empty() && !by_cells {
        eprintln!(
            "note: with --wire {}, colours are interpolated between the decimated surface's \
             nodes; --wire global or none colours each cell as the original does",
            wire.name()
        );
    }
    // Isolines follow the property interpolated between nodes, whatever colours the
    // cells: one value per triangle corner of `mesh`, or on a decimated surface the
    // original's values at its cells' corners.
    let iso = match &args.iso {
        Some((name, spacing)) => {
            let (smooth, iso_range) = field_mesh(&grid, &options, name)?;
            let field = match (&mut cells, args.lod) {
                (Some(cells), Some(_)) => {
                    cells.corners = Some(
                        cells
                            .cover
                            .corner_values(&smooth)
                            .context("the original's isoline field at the cells' corners")?,
                    );
                    None
                }
                (None, Some(_)) => bail!("--lod with --iso needs the scene's cells"),
                (_, None) => Some(corner_field(&options, &smooth, &mesh)?),
            };
            Some((field, spacing.isolines(iso_range)))
        }
        None => None,
    };
    let loaded = start.elapsed();

    let mut renderer = Renderer::headless()?;
    let drawable = match (&cells, &iso) {
        (Some(cells), _) => renderer
            .prepare_cells(&mesh, &cells.draw(global))
            .context("preparing the global wireframe over the original's cells")?,
        (None, Some((Some(field), ..))) => renderer.prepare_isolines(
            &mesh,
            Some(field),
            IsolineOptions {
                adjust: args.iso_adjust,
                wire: wire == WireMode::Global,
            },
        )?,
        _ => renderer
            .prepare(&mesh, wire)
            .with_context(|| format!("preparing the {} wireframe", wire.name()))?,
    };
    let (lo, hi) = mesh.bounds().ok_or_else(|| anyhow!("empty scene"))?;
    let bounds = (Vec3::from(lo), Vec3::from(hi));
    let (az, el, dist) = args.frame.view;
    let camera = Camera::fit_points(
        mesh.positions.iter().map(|&p| Vec3::from(p)),
        args.frame.zscale,
        args.frame.size.0 as f32 / args.frame.size.1 as f32,
        (az, el),
        dist,
    );
    let camera = match args.frame.centre {
        Some(cell) => camera.centred_on(Vec3::from(column_top(
            &grid,
            options.layers.clone(),
            cell,
            mesh.origin,
        )?)),
        None => camera,
    };
    let view = View {
        camera,
        width: args.frame.size.0,
        height: args.frame.size.1,
        bounds,
    };
    let style = Style {
        isolines: iso.as_ref().map(|(_, isolines)| *isolines),
        ..args.style.style(
            renderer.gpu.info.device_type,
            range,
            [mesh.origin[0], mesh.origin[1]],
        )?
    };
    let image = renderer.render(&[drawable.as_ref()], &view, &style)?;
    strata::render::save_png(&image, &args.output)?;
    eprintln!(
        "{}: {} triangles, {} wireframe ({} coverage), {}; model read in {:.2} s, frame in {:.2} s on {}",
        args.output.display(),
        mesh.triangle_count(),
        wire.name(),
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

/// The surfaces of `options` with property `name` averaged onto their nodes, whose
/// vertex scalars are the isoline field, and the range of its defined values.
fn field_mesh(
    grid: &strata::grid::CornerPointGrid,
    options: &SceneOptions,
    name: &str,
) -> Result<(strata::grid::SurfaceMesh, (f32, f32))> {
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
    Ok((smooth, range))
}

/// The isoline field of `smooth` (see [`field_mesh`]) per triangle corner of `mesh`,
/// the same surfaces built with `options`.
fn corner_field(
    options: &SceneOptions,
    smooth: &strata::grid::SurfaceMesh,
    mesh: &strata::grid::SurfaceMesh,
) -> Result<Vec<f32>> {
    let cell_painted = options.flat_cells && options.property.is_some();
    let field = strata::scene::corner_field(smooth, cell_painted);
    if field.len() != 3 * mesh.triangle_count() {
        bail!(
            "--iso: {} isoline values for {} triangles",
            field.len(),
            mesh.triangle_count()
        );
    }
    Ok(field)
}
