//! `strata render`: a model's layers (and sides) shaded by a property with the cell
//! wireframe, to a PNG.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use strata::grid::{StrayCorners, SurfaceMesh};
use strata::render::glam::Vec3;
use strata::render::{
    Coverage, HiddenLines, IsolineOptions, RangeAdjust, Renderer, Style, View, WireMode,
};
use strata::scene::{self, Part, SceneOptions, build, column_top};

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
    /// Decimate the drawn surfaces (strata-lod) to PERCENT of their triangles in all,
    /// split among them by how much of each the views around the model show (the tops
    /// between the first and the last hide under the others and keep fewer), and draw
    /// the wireframe on the result: global draws the original grid lines, tex/texgs
    /// the decimated triangles (quad, which needs cell faces, is refused). With global
    /// or none, each cell keeps its own colour (looked up by the global coordinates),
    /// and what the decimation moved beyond the original's cells (an outline corner
    /// cut outward) is not drawn, and the layers keep their order where they are
    /// thinner than the decimation's error (a surface that rose through the one above
    /// it stays hidden under it); with the others, colours are interpolated between
    /// nodes (decimated triangles are no longer cells). Says when a surface's share is
    /// below the triangles that keep every corner of its outlines, holes and fault
    /// traces; there meshoptimizer's simplify decimates instead, its result fitted to
    /// the original grid lines (as strata's is up to 2.5 times above that). With --iso the isolines are the original's:
    /// each fragment evaluates the original surface's field from its global
    /// coordinates, as it takes its cell's colour (--wire global or none).
    #[arg(long, value_name = "PERCENT", value_parser = super::lod::parse_percent)]
    lod: Option<f64>,
    /// With --lod: let the outlines, holes and fault traces grow only outward in the
    /// decimation, never inward, so that drawn over the original's cells only (as
    /// every decimated surface is) those lines stay exactly the original's at any
    /// budget; the result is fitted to the original grid lines. Global wireframe only.
    #[arg(long, requires = "lod")]
    cover: bool,
    /// With --lod: close the slivers between surfaces that share an outline (the top
    /// and bottom against the side walls with --sides, a layer against the walls of a
    /// hole or fault): each surface is decimated on its own, keeping different nodes
    /// of the shared outline; each node one of them kept is put back into the others,
    /// a triangle each (where its own place would fold one: there all the same, as a
    /// triangle of its own, beyond an edge that cut its corner off, else on the edge
    /// it splits). At 10 %, the sample with --sides went from 1 372 to 1 731
    /// triangles, Reek from 9 469 to 14 904.
    #[arg(long, requires = "lod")]
    stitch: bool,
    /// Hold at most this many active cells' surfaces at a time. A scene with more is
    /// drawn in parts (runs of layers, a larger layer in bands of rows; tops, then the
    /// bottom, then sides), each dropped once drawn, so that a model of any size draws
    /// in about the memory of one part; the picture is the same. Parts leave out what
    /// needs the whole scene at once: --lod, --cover, --wire bias and idbuffer, and
    /// hidden-line styles other than tehs.
    #[arg(long, value_name = "CELLS", default_value_t = 2_000_000,
          value_parser = clap::value_parser!(u64).range(1..))]
    part_cells: u64,
}

fn parse_adjust(s: &str) -> Result<RangeAdjust, String> {
    RangeAdjust::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = RangeAdjust::ALL.iter().map(|(n, _)| *n).collect();
        format!("unknown range adjust {s:?}; one of {}", names.join(", "))
    })
}

pub fn run(args: &RenderArgs) -> Result<()> {
    let start = Instant::now();
    let inputs: Vec<&Path> = args
        .model
        .iter()
        .chain(&args.read.props)
        .map(PathBuf::as_path)
        .collect();
    super::refuse_overwriting(&args.output, &inputs)?;
    let wire = match args.lod {
        Some(_) => decimated_wire(args.style.wire, "--lod")?,
        None => args.style.wire,
    };
    let (path, grid) = super::open_model(args.model.as_deref(), &args.read)?;
    let stray = super::warn_about(&grid, &path);
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
    let parts = scene::parts(&grid, &options, args.part_cells as usize)?;
    let largest = parts.iter().map(|p| p.cells(&grid)).max().unwrap_or(0);
    let per_cell = bytes_per_cell(args.style.wire, args.iso.is_some());
    super::check_memory(
        largest as f64 * per_cell,
        &format!("the {largest} active cells of the largest part"),
        "to draw (lower --part-cells)",
    )?;
    if args.iso.is_some() && !matches!(wire, WireMode::Global | WireMode::None) {
        bail!(
            "--iso draws with --wire global or none, not {}",
            wire.name()
        );
    }
    if scene::drawn_in_parts(&parts) {
        return draw_in_parts(args, (&grid, stray.as_ref()), &options, parts, start);
    }
    if args.cover && wire != WireMode::Global {
        bail!("--cover draws with --wire global, not {}", wire.name());
    }
    let global = wire == WireMode::Global;
    // The global coordinates find the original's cells, their colours and isolines,
    // with or without the original's grid lines over them.
    let by_cells = global || wire == WireMode::None;
    let mut renderer = Renderer::headless()?;
    let (mesh, range, mut cells) = match args.lod {
        Some(percent) => {
            let (surfaces, stacked) = scene::build_stacked_surfaces(&grid, &options)?;
            let origin = surfaces.first().map_or([0.0; 3], |s| s.origin);
            let (mesh, cells) = super::lod::decimate_scene(
                &mut renderer,
                &surfaces,
                stacked,
                stray.as_ref().map(|s| s.rest.to_display(origin)),
                percent,
                args.frame.zscale,
                (args.cover, by_cells, args.stitch),
            )?;
            (mesh, scene::colour_range_of(&grid, &options)?, cells)
        }
        None => {
            let (mesh, range) = build(&grid, &options)?;
            (mesh, range, None)
        }
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
            let (smooth_options, iso_range) = field_options(&grid, &options, name)?;
            let (smooth, _) = build(&grid, &smooth_options)?;
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
    let loaded = Instant::now();

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
    let (az, el, dist) = args.frame.view;
    let mut framing = scene::framing_of(
        stray.as_ref().map(|s| s.rest.to_display(mesh.origin)),
        args.frame.zscale,
        args.frame.size.0 as f32 / args.frame.size.1 as f32,
        (az, el),
    );
    framing.add(mesh.positions.iter().map(|&p| Vec3::from(p)));
    let bounds = framing.bounds().ok_or_else(|| anyhow!("empty scene"))?;
    let camera = framing.camera(dist);
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
    super::save_picture(&image, style.background, &args.output)?;
    let drawn = format!("{} triangles", mesh.triangle_count());
    report(
        args,
        &renderer,
        &style,
        (&options, range),
        &drawn,
        [start, loaded],
    );
    Ok(())
}

/// Bytes `render` holds per active cell of a part at its peak, painted per cell: the
/// surfaces, their GPU buffers and the rasterizer's copies.
fn bytes_per_cell(wire: WireMode, iso: bool) -> f64 {
    wire.bytes_per_cell(iso)
}

/// Prints what `render` drew, in how long and on what: `drawn` says how much; reading
/// and building ran from `start` to `loaded`, drawing from then on.
fn report(
    args: &RenderArgs,
    renderer: &Renderer,
    style: &Style,
    (options, range): (&SceneOptions, Option<(f32, f32)>),
    drawn: &str,
    [start, loaded]: [Instant; 2],
) {
    eprintln!(
        "{}: {drawn}, {} wireframe ({} coverage), {}; model read in {:.2} s, frame in {:.2} s on {}",
        args.output.display(),
        args.style.wire.name(),
        match style.coverage {
            Coverage::Texture => "texture",
            Coverage::Analytic => "analytic",
        },
        match (&options.property, range) {
            (Some(p), Some((lo, hi))) => format!("{p} {lo:.4}..{hi:.4}"),
            _ => "solid colour".to_string(),
        },
        (loaded - start).as_secs_f64(),
        loaded.elapsed().as_secs_f64(),
        renderer.gpu.describe()
    );
}

/// Draws a scene of more than one run of layers part by part
/// ([`Renderer::render_parts`]): a first pass over the parts' positions frames the
/// view as the whole mesh would be framed (without the `stray` corners), a second
/// builds, draws and drops each part.
fn draw_in_parts(
    args: &RenderArgs,
    (grid, stray): (&strata::grid::CornerPointGrid, Option<&StrayCorners>),
    options: &SceneOptions,
    parts: Vec<Part>,
    start: Instant,
) -> Result<()> {
    let count = parts.len();
    let cells = args.part_cells;
    // What needs the whole scene at once is refused before the passes over the parts.
    let whole = |what: String, instead: &str| {
        anyhow!(
            "{what} the whole scene at once, and these layers hold more than --part-cells \
             {cells} active cells ({count} parts): raise --part-cells, draw fewer layers, \
             or {instead}"
        )
    };
    if args.lod.is_some() {
        return Err(whole(
            "--lod decimates".into(),
            "build a hierarchy with `strata lod build` and draw it with `strata lod view`",
        ));
    }
    let wire = args.style.wire;
    if !wire.draws_alone() {
        let alone: Vec<&str> = WireMode::ALL
            .into_iter()
            .filter(|m| m.draws_alone() && *m != WireMode::None)
            .map(WireMode::name)
            .collect();
        let instead = format!("use --wire {}", alone.join(", "));
        return Err(whole(format!("--wire {} draws", wire.name()), &instead));
    }
    let range = scene::colour_range_of(grid, options)?;
    let iso = match &args.iso {
        Some((name, spacing)) => {
            let (smooth_options, iso_range) = field_options(grid, options, name)?;
            Some((smooth_options, spacing.isolines(iso_range)))
        }
        None => None,
    };
    let origin = grid.display_origin();
    let mut renderer = Renderer::headless()?;
    let style = Style {
        isolines: iso.as_ref().map(|(_, isolines)| *isolines),
        ..args
            .style
            .style(renderer.gpu.info.device_type, range, [origin[0], origin[1]])?
    };
    if style.hidden != HiddenLines::Suppressed {
        let what = format!("--hidden {} needs", style.hidden.name());
        return Err(whole(what, "use --hidden tehs"));
    }
    let (az, el, dist) = args.frame.view;
    let (width, height) = args.frame.size;
    let aspect = width as f32 / height as f32;
    // The framing pass a row of tiles at a time, then a part at a time: a bar on a
    // terminal says where they are.
    let bar_style = indicatif::ProgressStyle::with_template(
        "{elapsed_precise} [{bar:40}] {msg} {pos}/{len} (eta {eta})",
    )
    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
    let bar = |length: usize, message: &'static str| {
        indicatif::ProgressBar::new(length as u64)
            .with_style(bar_style.clone())
            .with_message(message)
    };
    let framed = stray.map(|s| s.rest.to_display(origin));
    let framing = scene::framing_of(framed, args.frame.zscale, aspect, (az, el));
    let framing_bar = bar(0, "framing: rows of tiles");
    let extent = scene::scene_extent(grid, options, origin, framing, Some(&framing_bar))?;
    framing_bar.finish_and_clear();
    let bar = bar(count, "drawing: parts");
    let framing = &extent.framing;
    let Some(bounds) = framing.bounds() else {
        return Err(scene::nothing_to_draw(grid, options));
    };
    let camera = framing.camera(dist);
    let camera = match args.frame.centre {
        Some(cell) => camera.centred_on(Vec3::from(column_top(
            grid,
            options.layers.clone(),
            cell,
            origin,
        )?)),
        None => camera,
    };
    let view = View {
        camera,
        width,
        height,
        bounds,
    };
    let loaded = Instant::now();
    // What a part shows: its faces not wholly off the picture, which would draw no
    // pixel. In a close-up most go, and most of the layers' faces are not even built:
    // only the columns in view are. A part wholly in the picture is drawn as built.
    // Side faces that turn their back stay (unlike `lod view`): at an outline they
    // may take a pixel, and the picture is the one mesh's.
    let columns = extent.columns_in_view(&view.camera, aspect);
    let in_view = |mesh: SurfaceMesh| match mesh.bounds() {
        Some(bounds) if scene::box_in_view(bounds, &view.camera, aspect) => mesh,
        _ => scene::faces_in_view(&mesh, &view.camera, aspect, false),
    };
    let (mut drawn, mut triangles) = (0, 0);
    let mut queue = parts.iter();
    let image = renderer.render_parts(&view, &style, |r| -> Result<_> {
        for part in queue.by_ref() {
            bar.inc(1);
            let mesh = in_view(scene::build_part_on_all_cores(
                grid, options, part, origin, &columns,
            )?);
            if mesh.triangle_count() == 0 {
                continue;
            }
            drawn += 1;
            triangles += mesh.triangle_count();
            let drawable = match &iso {
                Some((smooth_options, _)) => {
                    let smooth = scene::build_part_on_all_cores(
                        grid,
                        smooth_options,
                        part,
                        origin,
                        &columns,
                    )?;
                    let smooth = in_view(smooth);
                    let field = corner_field(options, &smooth, &mesh)?;
                    let iso_options = IsolineOptions {
                        adjust: args.iso_adjust,
                        wire: wire == WireMode::Global,
                    };
                    r.prepare_isolines(&mesh, Some(&field), iso_options)?
                }
                None => r
                    .prepare(&mesh, wire)
                    .with_context(|| format!("preparing the {} wireframe", wire.name()))?,
            };
            return Ok(Some(drawable));
        }
        Ok(None)
    })?;
    bar.finish_and_clear();
    super::save_picture(&image, style.background, &args.output)?;
    let what = format!(
        "{triangles} triangles (of {} in the scene) in {drawn} of {count} parts",
        extent.triangles
    );
    report(
        args,
        &renderer,
        &style,
        (options, range),
        &what,
        [start, loaded],
    );
    Ok(())
}

/// The scene `options` asks for with property `name` averaged onto its nodes, whose
/// values are then the isoline field, and the range of its defined values.
fn field_options(
    grid: &strata::grid::CornerPointGrid,
    options: &SceneOptions,
    name: &str,
) -> Result<(SceneOptions, (f32, f32))> {
    if grid.property(name).is_none() {
        bail!("--iso: the model has no property {name}");
    }
    let smooth_options = SceneOptions {
        property: Some(name.to_string()),
        flat_cells: false,
        ..options.clone()
    };
    let range = scene::colour_range_of(grid, &smooth_options)?
        .ok_or_else(|| anyhow!("--iso: {name} has no defined value here"))?;
    Ok((smooth_options, range))
}

/// The isoline field of `smooth` (the scene of [`field_options`]) per triangle corner of `mesh`,
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
