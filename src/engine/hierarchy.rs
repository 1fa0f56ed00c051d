//! A hierarchy written by `strata lod build`, memory mapped: each frame chooses the
//! nodes its camera needs at the scene's pixel error and draws them over the model's
//! cells (with the global wireframe or none), or as their own triangles.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use strata_grid::SurfaceMesh;
use strata_grid::outline::OutlineEdge;
use strata_lod::{CellCover, LodFile, ViewPoint};
use strata_render::glam::Vec3;
use strata_render::image::RgbaImage;
use strata_render::wire::Drawable;
use strata_render::{
    Camera, CellDraw, IsolineOptions, Isolines, Output, RangeAdjust, Renderer, TiledCells, View,
    WireMode,
};

use super::pick::{Pick, Ray, global_column};
use super::whole::technique;
use super::{FrameReport, Note, look};
use crate::error::Context;
use crate::scene::{Lod, Scene};
use crate::surfaces::{
    box_outside_view, colour_range, corner_field, faces_in_view, first_face_centre, framed_box,
};
use crate::{Error, Result};

/// An open hierarchy and what every frame of a scene of it shares.
pub struct Hierarchy {
    file: LodFile,
    path: PathBuf,
    /// Per layer surface of the file, whether the scene draws it.
    drawn: Vec<bool>,
    /// The roots of the drawn surfaces.
    roots: Vec<u32>,
    /// The box the roots cover, within the model's corners but its stray ones.
    bounds: (Vec3, Vec3),
    /// The drawn layers' side faces, stored at full resolution.
    sides: Option<SurfaceMesh>,
    /// The stored property's range over the drawn layers' cells.
    scalar_range: Option<(f32, f32)>,
    wire: WireMode,
    /// The nodes the last frame drew, which picking looks through.
    last_chosen: Mutex<Vec<u32>>,
    /// The drawn layers' fault traces, stored at full resolution, read on the first
    /// frame, and their levels of detail as uploaded.
    traces: Option<TraceLevels>,
    /// The outer half of the outline's lines of the stack's top and bottom surfaces
    /// (stored at full resolution), uploaded on the first frame; none with side
    /// walls, which go down from the outline, or without a wireframe.
    outline: Option<Option<Box<dyn Drawable>>>,
}

/// The fault traces of the top and bottom surfaces drawn, at levels of detail, in
/// tiles: a far view sees a cell edge as a fraction of a pixel, and drawing every
/// trace (hundreds of thousands on a large model) would cost more than the surfaces. Each frame draws the tiles in
/// the picture, each at the coarsest level its nearest point allows: level `l` joins
/// the tile's traces into chains simplified within `TRACE_TOLERANCES[l]` cells.
struct TraceLevels {
    tiles: Vec<TraceTile>,
    /// The vertical exaggeration the levels are simplified for.
    z_scale: f32,
    /// A cell's size, display units.
    cell: f32,
    /// The last frame's choice and its upload.
    drawn: Option<(TraceChoice, Option<Box<dyn Drawable>>)>,
}

/// The tiles a frame draws traces of, each with its level.
type TraceChoice = Vec<(usize, usize)>;

/// The traces whose midpoints fall in one tile of the model's map box.
struct TraceTile {
    /// Box of the tile's traces (unscaled display frame).
    bounds: (Vec3, Vec3),
    /// Per level, once simplified.
    levels: Vec<Option<Vec<strata_grid::faults::Segment>>>,
}

/// Tiles on a side of the model's map box.
const TRACE_TILES: usize = 16;

/// The tolerances of the trace levels, in cells (0: the traces as stored).
const TRACE_TOLERANCES: [f32; 6] = [0.0, 1.0, 4.0, 16.0, 64.0, 256.0];

/// What a frame of a hierarchy draws: its camera, the nodes chosen, the side faces
/// in view, and the choice in words.
pub struct Plan {
    camera: Camera,
    chosen: Vec<u32>,
    sides: Option<SurfaceMesh>,
    /// Seconds the choice took.
    pub seconds: f64,
    /// The choice, per level, in words.
    pub notes: Vec<Note>,
}

impl Hierarchy {
    /// Opens the hierarchy `path` for `scene`: its drawn layers, their sides and the
    /// range their cells' values span.
    pub fn open(path: &Path, scene: &Scene) -> Result<Self> {
        let wire = technique(scene)?;
        if scene.colour.property.is_some() {
            return Err(Error::scene(format!(
                "{}: a hierarchy is coloured by the property it stores",
                path.display()
            )));
        }
        if scene.i.is_some() || scene.j.is_some() || scene.inactive {
            return Err(Error::scene(format!(
                "{}: I and J range filters and inactive cells are drawn from a model, not \
                 yet from a hierarchy",
                path.display()
            )));
        }
        let file = LodFile::open(path)?;
        let nz = file.layers().iter().map(|l| l.k as usize + 1).max();
        let Some(nz) = nz else {
            return Err(Error::scene(format!(
                "{}: no layer surface",
                path.display()
            )));
        };
        let layers = scene.layer_range(nz)?;
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
        // A model's stray corners are left out of the frame and, past the far plane,
        // out of the picture, as a model's scene leaves them.
        let bounds = match file.framed().map(framed_box) {
            Some((flo, fhi)) => (Vec3::from(lo).max(flo), Vec3::from(hi).min(fhi)),
            None => (Vec3::from(lo), Vec3::from(hi)),
        };
        let sides = if scene.sides {
            drawn_sides(&file, &drawn)?
        } else {
            None
        };
        // Colours span the property's range over the drawn layers' cells, as a
        // model's scene does, whatever the view selects.
        let scalar_range = match &layers {
            None => file
                .scalar_range()
                .and_then(|(lo, hi)| colour_range([lo, hi])),
            Some(_) => colour_range(drawn_values(&file, &drawn)),
        };
        Ok(Hierarchy {
            file,
            path: path.to_path_buf(),
            drawn,
            roots,
            bounds,
            sides,
            scalar_range,
            wire,
            last_chosen: Mutex::new(Vec::new()),
            traces: None,
            outline: None,
        })
    }

    /// The cell `ray` meets first among the nodes (and side faces) the last frame
    /// drew, and where: the node's layer record gives the layer, its global
    /// coordinates the column.
    pub fn pick(&self, ray: &Ray) -> Result<Option<Pick>> {
        let chosen = self
            .last_chosen
            .lock()
            .map_err(|_| Error::scene("an earlier frame failed while choosing its nodes"))?
            .clone();
        let origin = self.file.origin();
        let mut best: Option<(f32, Pick)> = None;
        for node in chosen {
            let mesh = self.file.mesh(node as usize)?;
            let Some(hit) = ray.nearest(&mesh) else {
                continue;
            };
            if best.as_ref().is_some_and(|(d, _)| *d <= hit.distance) {
                continue;
            }
            let layer = self.file.nodes()[node as usize].layer as usize;
            let k = self.file.layers()[layer].k as usize;
            let [i, j] = global_column(&mesh, &hit);
            let point = ray.map_point(hit.distance, origin);
            best = Some((
                hit.distance,
                Pick {
                    cell: [i, j, k],
                    point,
                },
            ));
        }
        if let Some(sides) = &self.sides
            && let Some(hit) = ray.nearest(sides)
            && best.as_ref().is_none_or(|(d, _)| hit.distance < *d)
            && let Some(face) = sides
                .cell_faces
                .iter()
                .find(|f| f.triangles.contains(&(hit.triangle as u32)))
        {
            let point = ray.map_point(hit.distance, origin);
            best = Some((
                hit.distance,
                Pick {
                    cell: face.cell.map(|c| c as usize),
                    point,
                },
            ));
        }
        Ok(best.map(|(_, pick)| pick))
    }

    /// Cells along I, J and K of the model the hierarchy was built from.
    pub fn dims(&self) -> [usize; 3] {
        let [ni, nj] = self.file.dims().map(|n| n as usize);
        let nz = self.file.layers().iter().map(|l| l.k as usize + 1).max();
        [ni, nj, nz.unwrap_or(0)]
    }

    /// The stored property's range over the drawn layers' cells.
    pub fn scalar_range(&self) -> Option<(f32, f32)> {
        self.scalar_range
    }

    /// The stored property's values on the drawn layers' cells.
    pub fn values(&self) -> impl Iterator<Item = f32> + '_ {
        drawn_values(&self.file, &self.drawn)
    }

    /// The camera of `scene` and the nodes it needs at the scene's pixel error.
    pub fn plan(&self, scene: &Scene) -> Result<Plan> {
        let start = Instant::now();
        let file = &self.file;
        let pixels = match scene.lod {
            Lod::Hierarchy { pixels, .. } => pixels,
            _ => return Err(Error::scene("not a hierarchy's scene")),
        };
        let aspect = look::aspect(scene);
        let framed = file.framed();
        // Nodes out of the picture are left out; framing looks at the whole model.
        let inner = self.inner_surfaces();
        let choose = |camera: &Camera, pixels: f32, culled: bool| -> Vec<u32> {
            let point = ViewPoint {
                eye: camera.eye.to_array(),
                z_scale: scene.camera.z_scale,
                fov_y_deg: camera.fov_y_deg,
                height_px: scene.size[1],
                frustum: culled.then(|| camera.frustum(aspect)),
            };
            let inner: &[bool] = if culled { &inner } else { &[] };
            file.select_exposed(&point, pixels, inner)
                .into_iter()
                .filter(|&i| self.drawn[file.nodes()[i as usize].layer as usize])
                .collect()
        };
        // Framed on the roots' vertices, not their boxes (a grid rotated in map
        // coordinates fills a fraction of its box); then, as the roots are coarse, on
        // the vertices of the nodes within FRAMING_PIXELS of the full resolution that
        // a model's scene frames, so that the frame does not move with the error.
        let sides = self.sides.as_ref();
        let fit = |nodes: &[u32]| {
            let mut framing = look::framing(scene, framed);
            framing.add(frame_points(file, nodes, sides));
            framing.camera(scene.camera.distance)
        };
        let camera = fit(&self.roots);
        let framing = choose(&camera, FRAMING_PIXELS, false);
        let camera = fit(&framing);
        let camera = match scene.camera.centre {
            Some([i, j]) => camera.centred_on(column_top(file, &self.drawn, [i - 1, j - 1])?),
            None => camera,
        };
        let camera = look::aimed(scene, camera, file.origin());
        let chosen = choose(&camera, pixels, true);
        let sides = self
            .sides
            .as_ref()
            .map(|sides| faces_in_view(sides, &camera, aspect, true))
            .filter(|shown| !shown.is_empty());
        let seconds = start.elapsed().as_secs_f64();
        let notes = self.describe(&chosen, pixels, seconds, inner.contains(&true));
        Ok(Plan {
            camera,
            chosen,
            sides,
            seconds,
            notes,
        })
    }

    /// Uploads the outline's outer half, once: that of the stack's top and bottom
    /// surfaces, when the wireframe is drawn and no side walls go down from it.
    fn prepare_outline(&mut self, renderer: &mut Renderer) -> Result<()> {
        if self.outline.is_none() {
            let wired = self.wire.draws_edges();
            let edges: Vec<OutlineEdge> = match self.outer_surfaces() {
                outer if wired && self.sides.is_none() => outer
                    .into_iter()
                    .flat_map(|l| self.file.layer_outline(l))
                    .collect(),
                _ => Vec::new(),
            };
            self.outline = Some(
                renderer
                    .prepare_outline_edges(&edges)
                    .context("preparing the outline")?,
            );
        }
        Ok(())
    }

    /// The layer surfaces of the file the scene draws, top to bottom.
    fn drawn_surfaces(&self) -> Vec<usize> {
        (0..self.drawn.len()).filter(|&l| self.drawn[l]).collect()
    }

    /// The outer surfaces of the stack drawn, its top and its bottom: those between
    /// show only at its rims and fault walls, and drawing their lines too would
    /// multiply the cost by the layers.
    fn outer_surfaces(&self) -> Vec<usize> {
        let drawn = self.drawn_surfaces();
        let mut outer: Vec<usize> = drawn
            .first()
            .into_iter()
            .chain(drawn.last())
            .copied()
            .collect();
        outer.dedup();
        outer
    }

    /// Per layer surface of the file, whether it lies inside the stack drawn: drawn,
    /// neither its top nor its bottom, and closed by side faces. Only the faces of
    /// those that the layers above and below leave open can be seen.
    fn inner_surfaces(&self) -> Vec<bool> {
        let drawn = self.drawn_surfaces();
        let mut inner = vec![false; self.drawn.len()];
        if self.sides.is_some() && drawn.len() > 2 {
            for &l in &drawn[1..drawn.len() - 1] {
                inner[l] = true;
            }
        }
        inner
    }

    /// The nodes `chosen` at `pixels` of error, in words: how many of the drawn
    /// layers' full-resolution triangles, and per level; whether the inner surfaces'
    /// hidden nodes were left out (`inner_left_out`).
    fn describe(
        &self,
        chosen: &[u32],
        pixels: f32,
        seconds: f64,
        inner_left_out: bool,
    ) -> Vec<Note> {
        let file = &self.file;
        let mut per_level = BTreeMap::<u32, (usize, usize)>::new();
        for &i in chosen {
            let n = &file.nodes()[i as usize];
            let e = per_level.entry(n.level).or_default();
            e.0 += 1;
            e.1 += n.index_count as usize / 3;
        }
        let all: usize = file
            .nodes()
            .iter()
            .filter(|n| n.level == 0 && self.drawn[n.layer as usize])
            .map(|n| n.index_count as usize / 3)
            .sum();
        let drawn_triangles: usize = per_level.values().map(|v| v.1).sum();
        let mut notes = vec![Note::Info(format!(
            "{}: {} nodes; {} of {} layer surfaces drawn{}; at most {} px from this view: {} \
             nodes, {drawn_triangles} of {all} full-resolution triangles ({:.1} %), chosen in \
             {:.3} s",
            self.path.display(),
            file.nodes().len(),
            self.roots.len(),
            file.layers().len(),
            if inner_left_out {
                " (their inner faces hidden by the sides left out)"
            } else {
                ""
            },
            pixels,
            chosen.len(),
            100.0 * drawn_triangles as f64 / all.max(1) as f64,
            seconds
        ))];
        notes.extend(per_level.iter().map(|(level, (nodes, tris))| {
            Note::Info(format!("  level {level}: {nodes} nodes, {tris} triangles"))
        }));
        notes
    }
}

impl Hierarchy {
    /// Draws a frame of `scene`: the nodes its camera needs, over the model's cells
    /// where the technique finds them by the global coordinates.
    pub fn draw(
        &mut self,
        renderer: &mut Renderer,
        scene: &Scene,
        output: Output,
    ) -> Result<(Option<RgbaImage>, FrameReport)> {
        let z_scale = scene.camera.z_scale;
        if self.traces.as_ref().is_none_or(|t| t.z_scale != z_scale) {
            let segments = self
                .outer_surfaces()
                .into_iter()
                .flat_map(|l| self.file.layer_faults(l).iter().copied());
            let [ni, nj] = self.file.dims().map(|n| n.max(1) as f32);
            let (lo, hi) = self.bounds;
            self.traces = Some(TraceLevels {
                tiles: trace_tiles(segments, self.bounds),
                z_scale,
                cell: ((hi.x - lo.x) / ni).min((hi.y - lo.y) / nj).max(0.0),
                drawn: None,
            });
        }
        self.prepare_outline(renderer)?;
        let Plan {
            camera,
            mut chosen,
            sides,
            seconds,
            notes,
        } = self.plan(scene)?;
        let file = &self.file;
        let wire = self.wire;
        // The global coordinates find the model's cells, their colours and isolines,
        // with or without the model's grid lines over them.
        let by_cells = matches!(wire, WireMode::Global | WireMode::None);
        let isolines = self.isolines(scene, by_cells)?;
        let mut mesh = file.selection_mesh(&chosen)?;
        let mut cover = if by_cells {
            file.selection_cover(&chosen)?
        } else {
            None
        };
        let view = look::view(scene, camera, self.bounds);
        let style = look::style(
            scene,
            renderer.gpu.info.device_type,
            self.scalar_range,
            [mesh.origin[0], mesh.origin[1]],
            isolines,
        )?;
        // The cells' values, and the isolines' field from the leaves under them, are
        // read for the part of each node the view shows, tile by tile: from above, one
        // layer of the stack; obliquely, the top and the others' edges.
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
        // Nothing chosen covers a pixel: the picture is the background (and the sides).
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
                prepare_sides(renderer, sides, wire, isolines.is_some())
                    .context("preparing the side faces")?,
            ),
            None => None,
        };
        if let Ok(mut last) = self.last_chosen.lock() {
            last.clone_from(&chosen);
        }
        // Fault traces last, over the surfaces they lie on, at the level the nearest
        // part of the model needs; none where no node covers a pixel (their width is in
        // pixels: they would draw a model too small to see).
        let traces = match &mut self.traces {
            Some(levels) if !chosen.is_empty() => levels.drawable(renderer, &view, scene)?,
            _ => None,
        };
        let outline = match &self.outline {
            Some(Some(outline)) if !chosen.is_empty() => Some(outline.as_ref()),
            _ => None,
        };
        let drawables: Vec<&dyn Drawable> = drawable
            .as_deref()
            .into_iter()
            .chain(side_drawable.as_deref())
            .chain(outline)
            .chain(traces)
            .collect();
        let image = renderer.render_to(&drawables, &view, &style, output)?;
        let side_triangles = sides.as_ref().map_or(0, SurfaceMesh::triangle_count);
        let drawn = self.drawn_words(
            sides.as_ref(),
            (shown.is_some(), tiles_shown),
            isolines.as_ref(),
            (chosen.len(), chosen_count),
        );
        let triangles = mesh.triangle_count() + side_triangles;
        let report = FrameReport {
            triangles,
            drawn,
            colouring: self
                .scalar_range
                .map(|r| ("stored property".to_string(), r)),
            coverage: style.coverage,
            notes,
            view: Some((view, mesh.origin)),
            select_seconds: seconds,
            nodes: Some(chosen.len()),
            ..FrameReport::default()
        };
        Ok((image, report))
    }

    /// What a frame drew, in words: the technique, the side triangles, how it was
    /// coloured (`by_cell`, with the tiles shown of all), the isolines, and how many
    /// of the nodes chosen were `drawn`.
    fn drawn_words(
        &self,
        sides: Option<&SurfaceMesh>,
        (by_cell, tiles_shown): (bool, Option<(usize, usize)>),
        isolines: Option<&Isolines>,
        (drawn, chosen_count): (usize, usize),
    ) -> String {
        format!(
            "drawn with the {} wireframe{}, {}{}{}",
            self.wire.name(),
            match sides {
                Some(sides) => format!(", {} side triangles", sides.triangle_count()),
                None => String::new(),
            },
            match self.scalar_range {
                None => "no scalar".to_string(),
                Some((a, b)) => format!(
                    "coloured {} over the property's cell range {a:.4}..{b:.4}{}",
                    if by_cell {
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
            match drawn {
                n if n == chosen_count => String::new(),
                0 => format!("; none of the {chosen_count} nodes in view covers a pixel"),
                n => format!(
                    "; {n} of the {chosen_count} nodes in view drawn, the others hidden \
                     behind them"
                ),
            }
        )
    }

    /// The isolines `scene` asks for of the stored property, drawn by the global
    /// coordinates (`by_cells`).
    fn isolines(&self, scene: &Scene, by_cells: bool) -> Result<Option<Isolines>> {
        match (&scene.isolines, self.scalar_range) {
            (Some(_), _) if !by_cells => Err(Error::scene(format!(
                "--iso draws the model's isolines by the global coordinates: --wire global or \
                 none, not {}",
                self.wire.name()
            ))),
            (Some(spec), _) if spec.property.is_some() => Err(Error::scene(format!(
                "{}: a hierarchy's isolines are of the property it stores",
                self.path.display()
            ))),
            (Some(spec), Some(range)) => Ok(Some(look::isolines(spec, range))),
            (Some(_), None) => Err(Error::scene(format!(
                "{}: --iso: no property stored",
                self.path.display()
            ))),
            (None, _) => Ok(None),
        }
    }
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

/// The side faces drawn as a model's scene draws them: painted cell by cell
/// where they carry a property, with isolines of it (`iso`) that follow the property
/// averaged onto their nodes; no outline, the walls going down from the layers'.
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
        return Ok(renderer.prepare_isolines_band(mesh, Some(&field), options, None)?);
    }
    Ok(renderer.prepare_band(mesh, wire, None)?)
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

impl TraceLevels {
    /// The traces of the tiles in `view`'s picture, each at the coarsest level within
    /// `scene`'s pixel error at its nearest point (as stored at a pixel error of 0),
    /// uploaded when the choice changes.
    fn drawable(
        &mut self,
        renderer: &mut Renderer,
        view: &View,
        scene: &Scene,
    ) -> Result<Option<&dyn Drawable>> {
        let pixels = match scene.lod {
            Lod::Hierarchy { pixels, .. } => pixels,
            _ => 0.0,
        };
        let camera = &view.camera;
        let aspect = view.width as f32 / view.height.max(1) as f32;
        let scale = Vec3::new(1.0, 1.0, camera.z_scale);
        let focal = view.height.max(1) as f32 / (2.0 * (0.5 * camera.fov_y_deg.to_radians()).tan());
        let mut choice = Vec::new();
        for (t, tile) in self.tiles.iter().enumerate() {
            let unscaled = (tile.bounds.0.to_array(), tile.bounds.1.to_array());
            if box_outside_view(unscaled, camera, aspect) {
                continue;
            }
            let (a, b) = (tile.bounds.0 * scale, tile.bounds.1 * scale);
            let (lo, hi) = (a.min(b), a.max(b));
            let allowed = pixels * camera.eye.clamp(lo, hi).distance(camera.eye) / focal;
            let level = (0..TRACE_TOLERANCES.len())
                .rev()
                .find(|&l| TRACE_TOLERANCES[l] * self.cell <= allowed)
                .unwrap_or(0);
            choice.push((t, level));
        }
        if self
            .drawn
            .as_ref()
            .is_none_or(|(drawn, _)| *drawn != choice)
        {
            let mut segments = Vec::new();
            for &(t, level) in &choice {
                let tile = &mut self.tiles[t];
                if tile.levels[level].is_none() {
                    let raw = tile.levels[0].as_deref().unwrap_or_default();
                    let tolerance = TRACE_TOLERANCES[level] * self.cell;
                    let simplified =
                        strata_grid::faults::simplified_traces(raw, tolerance, self.z_scale);
                    tile.levels[level] = Some(simplified);
                }
                segments.extend_from_slice(tile.levels[level].as_deref().unwrap_or_default());
            }
            let prepared =
                (renderer.prepare_fault_traces(&segments)).context("preparing the fault traces")?;
            self.drawn = Some((choice, prepared));
        }
        Ok(self.drawn.as_ref().and_then(|(_, d)| d.as_deref()))
    }
}

/// `segments` in [`TRACE_TILES`] x [`TRACE_TILES`] tiles of the map box of `bounds`
/// (by their midpoints), each with its box; empty tiles left out.
fn trace_tiles(
    segments: impl Iterator<Item = strata_grid::faults::Segment>,
    (lo, hi): (Vec3, Vec3),
) -> Vec<TraceTile> {
    let n = TRACE_TILES;
    let mut tiles: Vec<Vec<strata_grid::faults::Segment>> = vec![Vec::new(); n * n];
    let size = (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE));
    for s in segments {
        let mid = (Vec3::from(s[0]) + Vec3::from(s[1])) * 0.5;
        let at = |v: f32, lo: f32, size: f32| ((((v - lo) / size) * n as f32) as usize).min(n - 1);
        tiles[at(mid.y, lo.y, size.y) * n + at(mid.x, lo.x, size.x)].push(s);
    }
    tiles
        .into_iter()
        .filter(|t| !t.is_empty())
        .map(|segments| {
            let points = segments.iter().flatten().map(|&p| Vec3::from(p));
            let bounds = points.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), p| {
                (a.min(p), b.max(p))
            });
            let mut levels = vec![None; TRACE_TOLERANCES.len()];
            levels[0] = Some(segments);
            TraceTile { bounds, levels }
        })
        .collect()
}
