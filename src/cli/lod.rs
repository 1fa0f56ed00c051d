//! `strata lod`: build a level-of-detail hierarchy file of a model, and view one; and
//! the decimation behind `strata render --lod`.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, Subcommand};
use rayon::prelude::*;
use strata::grid::SurfaceMesh;
use strata::lod::measure::deviation;
use strata::lod::{
    BuildOptions, CellCover, LodFile, Maker, Options, Progress, ProgressFn, Stitched, ViewPoint,
    build_file, decimate_chosen, share_surfaces,
};
use strata::render::glam::Vec3;
use strata::render::wire::Drawable;
use strata::render::{
    Camera, CellDraw, IsolineOptions, RangeAdjust, Renderer, Stacking, Style, TiledCells, View,
    WireMode, stack_pushes,
};
use strata::scene::{
    colour_range, corner_field, faces_in_view, first_face_centre, framed_box, framing_of,
};

use super::ReadArgs;
use super::style::{
    FrameArgs, IsoSpacing, LayerArgs, StyleArgs, decimated_wire, parse_iso_spacing, parse_zscale,
};

#[derive(Subcommand)]
pub enum LodCommand {
    /// Build the hierarchy of every layer surface of a model (on all cores) and save it.
    Build(BuildArgs),
    /// Open a saved hierarchy (memory mapped), choose the nodes a view needs for a
    /// given pixel error, print what was chosen, and draw it to a PNG with the lines
    /// and colours of `strata render`. With --wire global the original grid is drawn
    /// on whatever level is chosen, each cell in its own colour as the model's faces
    /// are (as with none, without the grid); with the others colours are interpolated
    /// between nodes. A layer is its top surface (and the model's bottom with the last
    /// layer), as the hierarchy stores them; its side faces are stored at full
    /// resolution and painted cell by cell as `strata render --sides` paints them.
    View(ViewArgs),
}

#[derive(Args)]
pub struct BuildArgs {
    /// Model file (.grdecl, .DATA, .EGRID).
    model: PathBuf,
    /// Output hierarchy file.
    #[arg(short, long)]
    output: PathBuf,
    /// Cells along each side of a leaf tile.
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=4096))]
    tile: u32,
    /// Vertical exaggeration the hierarchy will be viewed with (weighs vertical error).
    #[arg(long, default_value_t = 5.0, value_parser = parse_zscale)]
    zscale: f32,
    #[command(flatten)]
    read: ReadArgs,
    /// Property stored as the vertices' scalar (default: PORO when the model has it).
    #[arg(long)]
    property: Option<String>,
    /// Store no scalar.
    #[arg(long, conflicts_with = "property")]
    no_property: bool,
}

#[derive(Args)]
pub struct ViewArgs {
    /// Hierarchy file written by `strata lod build`.
    file: PathBuf,
    /// Largest projected error of a chosen node, in pixels (0: full resolution; inf:
    /// the coarsest level).
    #[arg(long, default_value_t = 1.0, value_parser = parse_pixels)]
    pixels: f32,
    #[command(flatten)]
    drawn: LayerArgs,
    #[command(flatten)]
    style: StyleArgs,
    /// Isolines of the stored property: [SPACING[:MAJOR_EVERY]] (about ten lines over
    /// its range when no spacing is given; every fifth line major). On whatever level is
    /// chosen they are the model's, evaluated from the full-resolution tiles under the
    /// chosen nodes, which this reads only for the tiles the view shows (as the cells'
    /// values), found by a first pass (--wire global or none).
    #[arg(long, value_name = "SPACING[:MAJOR_EVERY]", num_args = 0..=1, default_missing_value = "", value_parser = parse_iso_spacing)]
    iso: Option<IsoSpacing>,
    #[command(flatten)]
    frame: FrameArgs,
    /// Output PNG; only the selection is printed when omitted.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

pub fn run(command: &LodCommand) -> Result<()> {
    match command {
        LodCommand::Build(args) => build(args),
        LodCommand::View(args) => view(args),
    }
}

fn build(args: &BuildArgs) -> Result<()> {
    let start = Instant::now();
    let inputs: Vec<&Path> = std::iter::once(args.model.as_path())
        .chain(args.read.props.iter().map(PathBuf::as_path))
        .collect();
    super::refuse_overwriting(&args.output, &inputs)?;
    let (path, grid) = super::open_model(Some(&args.model), &args.read)
        .with_context(|| format!("reading {}", args.model.display()))?;
    super::warn_about(&grid, &path);
    let read = start.elapsed().as_secs_f64();
    let property = if args.no_property {
        None
    } else {
        match &args.property {
            Some(p) => Some(p.clone()),
            None => grid.property("PORO").map(|_| "PORO".to_string()),
        }
    };
    let d = grid.dims();
    eprintln!(
        "{}: {} x {} x {} cells read in {read:.1} s; building {} layer surfaces on {}",
        args.model.display(),
        d.nx,
        d.ny,
        d.nz,
        d.nz + 1,
        match rayon::current_num_threads() {
            1 => "1 thread".to_string(),
            n => format!("{n} threads"),
        }
    );
    let bar = indicatif::ProgressBar::hidden();
    let options = BuildOptions {
        tile_cells: args.tile,
        decimation: Options {
            z_scale: args.zscale,
            ..Options::default()
        },
        progress: Some(progress_bar(bar.clone())),
        memory: super::available_memory().map(|bytes| bytes as u64),
        ..BuildOptions::default()
    };
    let report = build_file(&grid, property.as_deref(), &args.output, &options);
    bar.finish_and_clear();
    let report = report?;
    drop(grid);
    eprintln!(
        "{}: {} layer surfaces, {} nodes in {} levels, {} triangles in, {} stored, {} side \
         triangles, {}; built in {:.1} s, {:.1} s in all; peak memory {}",
        args.output.display(),
        report.layers,
        report.nodes,
        report.levels + 1,
        report.input_triangles,
        report.stored_triangles,
        report.side_triangles,
        size_text(report.bytes),
        report.seconds,
        start.elapsed().as_secs_f64(),
        strata::bench::lod::peak_memory_kb()
            .map_or("unknown".to_string(), |kb| size_text(kb * 1000)),
    );
    Ok(())
}

/// Draws a hierarchy build's progress on `bar`, on standard error (when it is a
/// terminal) once the build's length is known.
fn progress_bar(bar: indicatif::ProgressBar) -> ProgressFn {
    Arc::new(move |progress| match progress {
        Progress::Started { work, surfaces } => {
            bar.set_length(work);
            bar.set_message(format!("0/{surfaces} layer surfaces"));
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "{elapsed_precise} [{bar:40}] {percent:>3} %, {msg} (eta {eta})",
                )
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            // The clock moves while no tile ends: the side faces come first, and a root
            // takes a while.
            bar.enable_steady_tick(Duration::from_secs(1));
        }
        Progress::Worked(units) => bar.inc(units),
        Progress::Written {
            written,
            surfaces,
            input_triangles,
            stored_triangles,
        } => bar.set_message(format!(
            "{written}/{surfaces} layer surfaces, {:.1} M triangles in, {:.1} M stored",
            input_triangles as f64 / 1e6,
            stored_triangles as f64 / 1e6
        )),
    })
}

/// `bytes` in GB from a gigabyte up, else in MB.
pub fn size_text(bytes: u64) -> String {
    if bytes >= 1_000_000_000 {
        format!("{:.2} GB", bytes as f64 / 1e9)
    } else {
        format!("{:.1} MB", bytes as f64 / 1e6)
    }
}

fn view(args: &ViewArgs) -> Result<()> {
    let start = Instant::now();
    if let Some(output) = &args.output {
        super::refuse_overwriting(output, &[&args.file])?;
    }
    let wire = decimated_wire(args.style.wire, "lod view")?;
    let file = LodFile::open(&args.file)?;
    let nz = file.layers().iter().map(|l| l.k as usize + 1).max();
    let Some(nz) = nz else {
        bail!("{}: no layer surface", args.file.display());
    };
    let layers = args.drawn.range(nz)?;
    let drawn: Vec<bool> = file
        .layers()
        .iter()
        .map(|l| layers.as_ref().is_none_or(|r| r.contains(&(l.k as usize))))
        .collect();
    // Frame the drawn surfaces' roots, which cover them.
    let roots: Vec<u32> = file
        .layers()
        .iter()
        .zip(&drawn)
        .filter(|(_, d)| **d)
        .map(|(l, _)| l.root)
        .collect();
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for &r in &roots {
        let n = &file.nodes()[r as usize];
        for a in 0..3 {
            lo[a] = lo[a].min(n.min[a]);
            hi[a] = hi[a].max(n.max[a]);
        }
    }
    // A model's stray corners are left out of the frame and, past the far plane, out
    // of the picture, as `strata render` leaves them.
    let framed = file.framed();
    let bounds = match framed.map(framed_box) {
        Some((flo, fhi)) => (Vec3::from(lo).max(flo), Vec3::from(hi).min(fhi)),
        None => (Vec3::from(lo), Vec3::from(hi)),
    };
    let frame = &args.frame;
    let sides = if args.drawn.sides {
        drawn_sides(&file, &drawn)?
    } else {
        None
    };
    let aspect = frame.size.0 as f32 / frame.size.1 as f32;
    // Nodes out of the picture are left out; framing looks at the whole model.
    let choose = |camera: &Camera, pixels: f32, culled: bool| -> Vec<u32> {
        let point = ViewPoint {
            eye: camera.eye.to_array(),
            z_scale: frame.zscale,
            fov_y_deg: camera.fov_y_deg,
            height_px: frame.size.1,
            frustum: culled.then(|| camera.frustum(aspect)),
        };
        file.select(&point, pixels)
            .into_iter()
            .filter(|&i| drawn[file.nodes()[i as usize].layer as usize])
            .collect()
    };
    // Framed on the roots' vertices, not their boxes (a grid rotated in map
    // coordinates fills a fraction of its box); then, as the roots are coarse, on the
    // vertices of the nodes within FRAMING_PIXELS of the full resolution that `render`
    // frames, so that the frame does not move with --pixels.
    let camera = fit_camera(frame_points(&file, &roots, sides.as_ref()), framed, frame);
    let framing = choose(&camera, FRAMING_PIXELS, false);
    let camera = fit_camera(frame_points(&file, &framing, sides.as_ref()), framed, frame);
    let camera = match frame.centre {
        Some(cell) => camera.centred_on(column_top(&file, &drawn, cell)?),
        None => camera,
    };
    let mut chosen = choose(&camera, args.pixels, true);
    let sides = sides
        .map(|sides| faces_in_view(&sides, &camera, aspect, true))
        .filter(|shown| !shown.is_empty());
    let mut per_level = std::collections::BTreeMap::<u32, (usize, usize)>::new();
    for &i in &chosen {
        let n = &file.nodes()[i as usize];
        let e = per_level.entry(n.level).or_default();
        e.0 += 1;
        e.1 += n.index_count as usize / 3;
    }
    let all: usize = file
        .nodes()
        .iter()
        .filter(|n| n.level == 0 && drawn[n.layer as usize])
        .map(|n| n.index_count as usize / 3)
        .sum();
    let drawn_triangles: usize = per_level.values().map(|v| v.1).sum();
    eprintln!(
        "{}: {} nodes; {} of {} layer surfaces drawn; at most {} px from this view: {} nodes, \
         {drawn_triangles} of {all} full-resolution triangles ({:.1} %), chosen in {:.3} s",
        args.file.display(),
        file.nodes().len(),
        roots.len(),
        file.layers().len(),
        args.pixels,
        chosen.len(),
        100.0 * drawn_triangles as f64 / all.max(1) as f64,
        start.elapsed().as_secs_f64()
    );
    for (level, (nodes, tris)) in &per_level {
        eprintln!("  level {level}: {nodes} nodes, {tris} triangles");
    }
    let Some(output) = &args.output else {
        return Ok(());
    };
    // Colours span the property's range over the drawn layers' cells, as in
    // `strata render`, whatever the view selects.
    let scalar_range = match &layers {
        None => file
            .scalar_range()
            .and_then(|(lo, hi)| colour_range([lo, hi])),
        Some(_) => colour_range(drawn_values(&file, &drawn)),
    };
    // The global coordinates find the model's cells, their colours and isolines, with
    // or without the model's grid lines over them.
    let by_cells = matches!(wire, WireMode::Global | WireMode::None);
    let isolines = match (args.iso, scalar_range) {
        (Some(_), _) if !by_cells => bail!(
            "--iso draws the model's isolines by the global coordinates: --wire global or \
             none, not {}",
            wire.name()
        ),
        (Some(iso), Some(range)) => Some(iso.isolines(range)),
        (Some(_), None) => bail!("{}: --iso: no property stored", args.file.display()),
        (None, _) => None,
    };
    let mut mesh = file.selection_mesh(&chosen)?;
    let mut renderer = Renderer::headless()?;
    let mut cover = if by_cells {
        file.selection_cover(&chosen)?
    } else {
        None
    };
    let view = View {
        camera,
        width: frame.size.0,
        height: frame.size.1,
        bounds,
    };
    let style = Style {
        isolines,
        ..args.style.style(
            renderer.gpu.info.device_type,
            scalar_range,
            [mesh.origin[0], mesh.origin[1]],
        )?
    };
    // The cells' values, and the isolines' field from the leaves under them, are read
    // for the part of each node the view shows, tile by tile: from above, one layer of
    // the stack; obliquely, the top and the others' edges.
    let tile = file.tile_cells();
    let mut shown = match &cover {
        Some(cover) => Some(
            renderer
                .visible_tiles(&mesh, (cover, tile), &view, &style)
                .context("finding the tiles the view shows")?,
        ),
        None => None,
    };
    let chosen_count = chosen.len();
    let tiles_shown = shown
        .as_ref()
        .map(|shown| (shown.iter().filter(|&&v| v).count(), shown.len()));
    if let (Some(all), Some(flags)) = (&cover, &shown)
        && let Some((kept, kept_flags)) = unhidden_nodes(&chosen, all, flags, tile)
    {
        mesh = file.selection_mesh(&kept)?;
        cover = file.selection_cover(&kept)?;
        shown = Some(kept_flags);
        chosen = kept;
    }
    let values = match &cover {
        Some(_) => file.selection_values(&chosen, shown.as_deref())?,
        None => None,
    };
    let corners = match (isolines, &cover) {
        (Some(_), Some(_)) => file.selection_corners(&chosen, shown.as_deref())?,
        _ => None,
    };
    let tiled = |values| TiledCells {
        values,
        tile,
        of: shown.as_deref(),
    };
    // Nothing chosen covers a pixel: the picture is the background (and the sides),
    // which `save_picture` notes.
    let drawable = match &cover {
        _ if chosen.is_empty() => None,
        Some(cover) => Some(
            renderer
                .prepare_cells(
                    &mesh,
                    &CellDraw {
                        pieces: &cover.vertex_piece,
                        cover,
                        values: values.as_deref().map(tiled),
                        corners: corners.as_deref().map(tiled),
                        mask: false,
                        wire: wire == WireMode::Global,
                        stacking: None,
                    },
                )
                .context("preparing the selection over the model's cells")?,
        ),
        None => Some(renderer.prepare(&mesh, wire)?),
    };
    let side_drawable = match &sides {
        Some(sides) => Some(
            prepare_sides(&mut renderer, sides, wire, isolines.is_some())
                .context("preparing the side faces")?,
        ),
        None => None,
    };
    let drawables: Vec<&dyn Drawable> = drawable
        .as_deref()
        .into_iter()
        .chain(side_drawable.as_deref())
        .collect();
    let image = renderer.render(&drawables, &view, &style)?;
    super::save_picture(&image, style.background, output)?;
    eprintln!(
        "{}: drawn with the {} wireframe{}, {}{}{}",
        output.display(),
        wire.name(),
        match &sides {
            Some(sides) => format!(", {} side triangles", sides.triangle_count()),
            None => String::new(),
        },
        match scalar_range {
            None => "no scalar".to_string(),
            Some((a, b)) => format!(
                "coloured {} over the property's cell range {a:.4}..{b:.4}{}",
                if shown.is_some() {
                    "cell by cell"
                } else {
                    "by values interpolated between nodes"
                },
                match tiles_shown {
                    Some((seen, all)) => {
                        format!(" (the cells of the {seen} of {all} tiles the view shows)")
                    }
                    None => String::new(),
                }
            ),
        },
        match isolines {
            Some(iso) => format!(
                ", isolines every {} (the model's, from the full-resolution leaves under \
                 those tiles)",
                iso.spacing
            ),
            None => String::new(),
        },
        match chosen.len() {
            drawn if drawn == chosen_count => String::new(),
            0 => format!("; none of the {chosen_count} nodes in view covers a pixel"),
            drawn => format!(
                "; {drawn} of the {chosen_count} nodes in view drawn, the others hidden behind them"
            ),
        }
    );
    Ok(())
}

/// The pixel budget of the nodes that frame a view (see `view`).
const FRAMING_PIXELS: f32 = 0.5;

/// Of the nodes `chosen`, whose pieces of `cover` have the tiles (of `tile` cells)
/// that `shown` marks, those that show at least one, with their tiles' flags; `None`
/// when none is hidden. A node that shows no tile is behind the others at every pixel
/// centre, and nothing else of it is drawn (its lines are on its surface), so the
/// frame is the same without it.
fn unhidden_nodes(
    chosen: &[u32],
    cover: &CellCover,
    shown: &[bool],
    tile: u32,
) -> Option<(Vec<u32>, Vec<bool>)> {
    let (mut kept, mut kept_shown, mut at) = (Vec::new(), Vec::new(), 0);
    for (&node, piece) in chosen.iter().zip(&cover.pieces) {
        let tiles = shown.get(at..at + piece.tile_count(tile))?;
        at += tiles.len();
        if tiles.contains(&true) {
            kept.push(node);
            kept_shown.extend_from_slice(tiles);
        }
    }
    (at == shown.len() && kept.len() < chosen.len()).then_some((kept, kept_shown))
}

/// Where `--centre` looks: the centre of cell `(i, j)`'s face on the first drawn
/// layer surface that has it, read from that surface's full-resolution leaf.
fn column_top(file: &LodFile, drawn: &[bool], cell: [u32; 2]) -> Result<Vec3> {
    let candidates = (0..drawn.len())
        .filter(|&l| drawn[l])
        .filter_map(|l| file.leaf_of(l, cell))
        .map(|leaf| Ok(file.mesh(leaf as usize)?.cell_centre(cell)));
    let [ni, nj] = file.dims().map(|n| n as usize);
    Ok(Vec3::from(first_face_centre(cell, [ni, nj], candidates)?))
}

/// The vertices of `nodes` and of `sides`.
fn frame_points<'a>(
    file: &'a LodFile,
    nodes: &'a [u32],
    sides: Option<&'a SurfaceMesh>,
) -> impl Iterator<Item = Vec3> + 'a {
    nodes
        .iter()
        .flat_map(|&i| file.vertices(i as usize))
        .map(|v| v.position)
        .chain(sides.into_iter().flat_map(|s| s.positions.iter().copied()))
        .map(Vec3::from)
}

/// A camera framing `points` (those in the box `framed`, when given) as `strata
/// render` frames a model.
fn fit_camera(
    points: impl Iterator<Item = Vec3>,
    framed: Option<[[f32; 3]; 2]>,
    frame: &FrameArgs,
) -> Camera {
    let (az, el, dist) = frame.view;
    let aspect = frame.size.0 as f32 / frame.size.1 as f32;
    let mut framing = framing_of(framed, frame.zscale, aspect, (az, el));
    framing.add(points);
    framing.camera(dist)
}

/// The side faces of the grid layers whose surfaces are marked `drawn`, in one mesh;
/// `None` where they have none.
fn drawn_sides(file: &LodFile, drawn: &[bool]) -> Result<Option<SurfaceMesh>> {
    let mut all = SurfaceMesh::with_origin(file.origin());
    for (l, _) in drawn.iter().enumerate().filter(|(_, d)| **d) {
        if let Some(sides) = file.layer_sides(l)? {
            all.append(&sides);
        }
    }
    Ok((!all.is_empty()).then_some(all))
}

/// The side faces drawn as `strata render --sides` draws them: painted cell by cell
/// where they carry a property, with isolines of it (`iso`) that follow the property
/// averaged onto their nodes.
fn prepare_sides(
    renderer: &mut Renderer,
    sides: &SurfaceMesh,
    wire: WireMode,
    iso: bool,
) -> Result<Box<dyn Drawable>> {
    let painted = !sides.scalars.is_empty();
    let by_cell;
    let mesh = if painted {
        by_cell = sides.with_cell_values();
        &by_cell
    } else {
        sides
    };
    if iso {
        let field = corner_field(sides, painted);
        let options = IsolineOptions {
            adjust: RangeAdjust::On,
            wire: wire == WireMode::Global,
        };
        return Ok(renderer.prepare_isolines(mesh, Some(&field), options)?);
    }
    Ok(renderer.prepare(mesh, wire)?)
}

/// The property's values on the cells of the layer surfaces marked `drawn` (none
/// without a property).
fn drawn_values<'f>(file: &'f LodFile, drawn: &'f [bool]) -> impl Iterator<Item = f32> + 'f {
    drawn
        .iter()
        .enumerate()
        .filter(|(_, d)| **d)
        .filter_map(|(l, _)| file.layer_cells(l))
        .flat_map(|(faces, values)| {
            values
                .iter()
                .enumerate()
                .filter(|(c, _)| faces[c / 32] >> (c % 32) & 1 != 0)
                .map(|(_, v)| *v)
        })
}

/// What the renderer needs to draw a decimated scene against the input's cells
/// ([`CellDraw`]): per vertex its piece of those cells, the cells, and their values
/// where a property colours the scene.
pub struct SceneCells {
    pub pieces: Vec<u32>,
    pub cover: CellCover,
    /// Per piece of `cover`, the renderer's push of its surface ([`Stacking`]); none
    /// for side faces.
    pub push: Vec<Option<f32>>,
    pub values: Option<Vec<f32>>,
    /// The input's isoline field at its cells' corners, when isolines are drawn.
    pub corners: Option<Vec<f32>>,
}

impl SceneCells {
    /// What the renderer draws: with `wire`, the input's grid lines too.
    pub fn draw(&self, wire: bool) -> CellDraw<'_> {
        CellDraw {
            pieces: &self.pieces,
            cover: &self.cover,
            values: self.values.as_deref().map(TiledCells::boxes),
            corners: self.corners.as_deref().map(TiledCells::boxes),
            // Where a decimated surface leaves its piece's cells (an outline corner cut
            // outward, a hole or fault trace crossed), its global coordinates name cells
            // the input does not have there: not drawn. `bench lod`'s line-pixel F1 at
            // 10 %, worse of two views: emerald 0.920 without, 0.958 with; Reek 0.995.
            mask: true,
            wire,
            // Layers thinner than the decimation's error: where a surface rose
            // through the one above it, its lines showed through that one's cells
            // (Reek at 10 %, `bench lod`'s line-pixel F1 0.9952 without, 0.9980 with).
            stacking: Some(Stacking { push: &self.push }),
        }
    }
}

/// `render --lod`: decimates the scene's `surfaces` (as
/// [`strata::scene::build_stacked_surfaces`] gives them, the first `stacked` the layers'
/// from the top) to `percent` of their triangles in all, split among them by the part
/// of each seen from around the model ([`Renderer::visible_fractions`],
/// `strata_lod::share_surfaces`), each surface on its own (on all cores), and appends
/// the results in order. With `cover` the outlines only grow outward; with
/// `against_cells` (or `cover`), the input's cells come back, to colour and line the
/// result by and to trim it to, with the stacked surfaces' order ([`SceneCells`]).
/// With `stitch`, the surfaces meet again where their outlines do
/// (`strata_lod::stitch`). `framed`, the box of the model's corners but its stray
/// ones in the surfaces' frame, is what the views that split the budget frame and
/// measure, as the picture frames it ([`framing_of`]).
pub fn decimate_scene(
    renderer: &mut Renderer,
    surfaces: &[SurfaceMesh],
    stacked: usize,
    framed: Option<[[f32; 3]; 2]>,
    percent: f64,
    z_scale: f32,
    (cover, against_cells, stitch): (bool, bool, bool),
) -> Result<(SurfaceMesh, Option<SceneCells>)> {
    let start = Instant::now();
    let total: usize = surfaces.iter().map(SurfaceMesh::triangle_count).sum();
    let visible = if surfaces.len() > 1 {
        renderer
            .visible_fractions(
                &surfaces.iter().collect::<Vec<_>>(),
                z_scale,
                framed.map(framed_box),
            )
            .context("measuring how much of each surface is seen")?
    } else {
        vec![1.0; surfaces.len()]
    };
    let shares = share_surfaces(percent / 100.0, surfaces, &visible);
    let measured = start.elapsed().as_secs_f64();
    let mut chosen = surfaces
        .par_iter()
        .zip(&shares)
        .map(|(mesh, &target)| {
            let fraction = target as f64 / mesh.triangle_count().max(1) as f64;
            let options = Options {
                z_scale,
                target_triangles: target,
                ..if cover {
                    Options::covering(mesh, fraction)
                } else {
                    Options::fraction(mesh, fraction)
                }
            };
            let chosen = decimate_chosen(mesh, &options)?;
            let below = chosen
                .outline
                .filter(|outline| target < outline.min_triangles);
            Ok((chosen, below))
        })
        .collect::<strata::lod::Result<Vec<_>>>()
        .context("decimating the scene")?;
    let stitched = if stitch {
        strata::lod::stitch(
            &surfaces.iter().collect::<Vec<_>>(),
            &mut chosen
                .iter_mut()
                .map(|(c, _)| &mut c.decimated)
                .collect::<Vec<_>>(),
        )
    } else {
        Stitched::default()
    };
    let origin = surfaces.first().map_or([0.0; 3], |s| s.origin);
    let mut out = SurfaceMesh::with_origin(origin);
    for (c, _) in &chosen {
        out.append(&c.decimated.mesh);
    }
    let by_meshopt = chosen
        .iter()
        .filter(|(c, _)| c.maker == Maker::Meshopt)
        .count();
    eprintln!(
        "decimated {} surfaces {} -> {} triangles ({:.1} %), error up to {:.3}, in {:.2} s \
         ({:.2} s of it measuring how much of each is seen); {}{}",
        surfaces.len(),
        total,
        out.triangle_count(),
        100.0 * out.triangle_count() as f64 / total.max(1) as f64,
        chosen
            .iter()
            .map(|(c, _)| c.decimated.error)
            .fold(0.0f32, f32::max),
        start.elapsed().as_secs_f64(),
        measured,
        shares_seen(&shares, surfaces, &visible),
        if by_meshopt > 0 {
            format!("; {by_meshopt} of them by meshopt_simplify")
        } else {
            String::new()
        },
    );
    if stitched.inserted + stitched.skipped > 0 {
        // Each count that is not zero, with what it counts.
        let part = |count: usize, what: &str| {
            if count > 0 {
                format!(", {count} {what}")
            } else {
                String::new()
            }
        };
        eprintln!(
            "stitched the outlines the surfaces share: {} nodes one of them kept put back \
             into the others (a triangle each){}{}{}{}",
            stitched.inserted,
            part(
                stitched.corners,
                "of them as a triangle of their own where a corner was cut off"
            ),
            part(
                stitched.on_edge,
                "of them on the edge they split, where their own place would fold a triangle \
                 (their copies moved there too)"
            ),
            part(
                stitched.texture_on_edge,
                "with the edge's texture point, where their own would turn a triangle over in \
                 texture space"
            ),
            part(
                stitched.skipped,
                "left out or short of their place (where a triangle would fold, or the outline \
                 left the input's)"
            ),
        );
    }
    let below: Vec<_> = chosen.iter().filter_map(|(_, b)| *b).collect();
    if !below.is_empty() {
        eprintln!(
            "note: on {} surfaces the share is below the triangles that keep every corner of \
             their outlines, holes and fault traces ({} corners, at least {} triangles): \
             there decimation cuts corners: what it cuts outward is not drawn, what it cuts \
             inward is lost (--cover grows them outward only)",
            below.len(),
            below.iter().map(|b| b.corners).sum::<usize>(),
            below.iter().map(|b| b.min_triangles).sum::<usize>(),
        );
    }
    let fitted: Vec<(f64, f64)> = chosen.iter().filter_map(|(c, _)| c.fitted).collect();
    if !fitted.is_empty() {
        eprintln!(
            "fitted {} surfaces to the grid lines, texture coordinates fixed: the largest \
             RMS distance of their lines {:.3} -> {:.3} (lines a surface lost counted between \
             its RMS and largest distance)",
            fitted.len(),
            fitted.iter().map(|f| f.0).fold(0.0, f64::max),
            fitted.iter().map(|f| f.1).fold(0.0, f64::max),
        );
    }
    if out.is_empty() {
        return Err(anyhow!("decimation left no triangle"));
    }
    let coloured = against_cells && !surfaces.iter().all(|s| s.scalars.is_empty());
    // Each surface's cells, as its cover came back or made here, appended as the
    // meshes are, each result's vertices named by their piece among them, and the
    // cells' values surface by surface, in the order of the appended cover.
    let mut cells = CellCover::default();
    let mut pieces = Vec::with_capacity(out.vertex_count());
    let mut values = coloured.then(Vec::new);
    if !(against_cells || cover) {
        return Ok((out, None));
    }
    // How far each stacked surface strays vertically from the original, which is how
    // far it may rise through its neighbour: their pushes apart in the depth test.
    let vertical: Vec<f32> = surfaces
        .par_iter()
        .zip(&chosen)
        .take(stacked)
        .map(|(mesh, (c, _))| {
            let d = &c.decimated;
            deviation(mesh, &d.mesh, &d.home, 2, f64::from(z_scale)).vertical as f32
        })
        .collect();
    let surface_push = stack_pushes(&vertical);
    let mut push = Vec::new();
    for (i, (mesh, (mut c, _))) in surfaces.iter().zip(chosen).enumerate() {
        let own = match c.decimated.cover.take() {
            Some(own) => own,
            None if against_cells => match CellCover::of(mesh) {
                Ok(own) => own,
                Err(e) => {
                    eprintln!(
                        "note: drawn without the original's cells (colours interpolated \
                         between nodes, nothing trimmed to the cells): {e}"
                    );
                    return Ok((out, None));
                }
            },
            None => return Ok((out, None)),
        };
        let first = cells.pieces.len() as u32;
        pieces.extend(
            c.decimated
                .pieces(mesh, &own)
                .into_iter()
                .map(|p| p.saturating_add(first)),
        );
        if let Some(values) = &mut values {
            values.extend(own.values(mesh).context("the scene's cell values")?);
        }
        push.resize(push.len() + own.pieces.len(), surface_push.get(i).copied());
        cells.append(&own);
    }
    Ok((
        out,
        Some(SceneCells {
            pieces,
            push,
            values,
            corners: None,
            cover: cells,
        }),
    ))
}

/// How the budget went: the share of each surface's triangles kept, the least and
/// the most, and the visible fraction of those surfaces.
fn shares_seen(shares: &[usize], surfaces: &[SurfaceMesh], visible: &[f64]) -> String {
    let kept = |i: usize| shares[i] as f64 / surfaces[i].triangle_count().max(1) as f64;
    let order = |a: &usize, b: &usize| kept(*a).total_cmp(&kept(*b));
    let (Some(least), Some(most)) = (
        (0..shares.len()).min_by(order),
        (0..shares.len()).max_by(order),
    ) else {
        return String::new();
    };
    format!(
        "shares {:.1} % (surface {}, {:.0} % of it seen) to {:.1} % (surface {}, {:.0} % seen)",
        100.0 * kept(least),
        least + 1,
        100.0 * visible[least],
        100.0 * kept(most),
        most + 1,
        100.0 * visible[most],
    )
}

/// `--lod PERCENT`: a share of the triangles in (0, 100].
pub fn parse_percent(s: &str) -> Result<f64, String> {
    s.trim()
        .trim_end_matches('%')
        .parse::<f64>()
        .ok()
        .filter(|p| *p > 0.0 && *p <= 100.0)
        .ok_or_else(|| format!("{s:?} is not a percentage in (0, 100]"))
}

/// `--pixels PX`: a projected error of at least 0 pixels. NaN would choose nothing
/// coarser than the leaves (no error compares below it) without saying so.
fn parse_pixels(s: &str) -> Result<f32, String> {
    s.trim()
        .parse::<f32>()
        .ok()
        .filter(|p| *p >= 0.0)
        .ok_or_else(|| format!("{s:?} is not a number of pixels of at least 0"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixel_errors_and_percentages_are_checked() {
        assert_eq!(parse_pixels("0.5"), Ok(0.5));
        assert_eq!(parse_pixels("0"), Ok(0.0));
        assert_eq!(parse_pixels("inf"), Ok(f32::INFINITY));
        for bad in ["-1", "NaN", "nan", "", "1px"] {
            assert!(parse_pixels(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_percent("10%"), Ok(10.0));
        for bad in ["0", "100.5", "nan", "-3"] {
            assert!(parse_percent(bad).is_err(), "{bad}");
        }
    }
}
