//! From a model to what is drawn: the layer and side surfaces a view asks for, with
//! the property that colours them, whole or in parts.

use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;
use strata_grid::{
    Columns, CornerPointGrid, Dims, Face, SurfaceMesh, Surfaces, drawn_cell, layer_surfaces,
    open_sides, side_face_corners, side_surfaces, visit_row_faces,
};
use strata_render::glam::Vec3;
use strata_render::{Camera, Framing};

use crate::progress::{Progress, Stage};
use crate::{Error, Result};

/// Which surfaces of a model to draw.
#[derive(Clone, Debug, Default)]
pub struct SceneOptions {
    /// Layers (0-based, end exclusive); all when `None`.
    pub layers: Option<Range<usize>>,
    /// Also the side faces: the outer shell and fault walls.
    pub sides: bool,
    /// Property that colours the cells; `None` for a solid colour.
    pub property: Option<String>,
    /// Paint each cell flat with its value (per-face vertices) rather than smoothly
    /// with values averaged onto nodes.
    pub flat_cells: bool,
    /// A range filter's columns (0-based): the cells outside are left out, and with
    /// `sides` the walls they leave are drawn ([`Surfaces::cut`]); all when `None`.
    pub cut: Option<Columns>,
    /// Inactive cells drawn too, without a value ([`Surfaces::inactive`]).
    pub inactive: bool,
}

/// The surfaces of `grid` for a view, in one mesh relative to the grid's display
/// origin, and the range of the property's defined values.
pub fn build(
    grid: &CornerPointGrid,
    options: &SceneOptions,
) -> Result<(SurfaceMesh, Option<(f32, f32)>)> {
    let origin = grid.display_origin();
    let mut mesh = SurfaceMesh::with_origin(origin);
    let all = Columns::all(grid.dims());
    for part in parts(grid, options, usize::MAX)? {
        mesh.append(&build_part(grid, options, &part, origin, &all)?);
    }
    if mesh.is_empty() {
        return Err(nothing_to_draw(grid, options));
    }
    Ok((mesh, colour_range_of(grid, options)?))
}

/// The surfaces of [`build`]'s mesh one by one: the top of each drawn layer, the
/// bottom of the last, and the sides of each run of layers; appended in this order
/// they are that mesh. For a decimation that splits one budget among them.
pub fn build_surfaces(grid: &CornerPointGrid, options: &SceneOptions) -> Result<Vec<SurfaceMesh>> {
    Ok(build_stacked_surfaces(grid, options)?.0)
}

/// [`build_surfaces`], and how many of them, from the first, are the stack of layer
/// surfaces (tops, then the bottom), top to bottom; the rest are side faces.
pub fn build_stacked_surfaces(
    grid: &CornerPointGrid,
    options: &SceneOptions,
) -> Result<(Vec<SurfaceMesh>, usize)> {
    let origin = grid.display_origin();
    let all = Columns::all(grid.dims());
    let mut surfaces = Vec::new();
    let mut stacked = 0;
    for part in parts(grid, options, usize::MAX)? {
        let sides = matches!(part, Part::Sides(_));
        let layers = match &part {
            Part::Tops(run) => run.clone().map(|k| Part::Tops(k..k + 1)).collect(),
            _ => vec![part],
        };
        for layer in &layers {
            let mesh = build_part(grid, options, layer, origin, &all)?;
            if !mesh.is_empty() {
                surfaces.push(mesh);
                stacked += usize::from(!sides);
            }
        }
    }
    if surfaces.is_empty() {
        return Err(nothing_to_draw(grid, options));
    }
    Ok((surfaces, stacked))
}

/// The error of a scene whose layers have no face to draw.
pub fn nothing_to_draw(grid: &CornerPointGrid, options: &SceneOptions) -> Error {
    let layers = options.layers.clone().unwrap_or(0..grid.dims().nz);
    Error::Scene(format!(
        "no active cell in layers {}..{}: nothing to draw",
        layers.start + 1,
        layers.end
    ))
}

/// The box (display frame) of a model's corners but its stray ones
/// ([`CornerPointGrid::stray_corners`]) as views frame it: widened by a hundredth of
/// its size on each axis, so that rounding keeps the corners on its faces.
pub fn framed_box([lo, hi]: [[f32; 3]; 2]) -> (Vec3, Vec3) {
    let (lo, hi) = (Vec3::from(lo), Vec3::from(hi));
    let margin = 0.01 * (hi - lo) + Vec3::splat(1e-3);
    (lo - margin, hi + margin)
}

/// Framing for a picture of `aspect` (width / height) seen from `view` (azimuth,
/// elevation) under vertical exaggeration `z_scale`. With `framed`, the box of a
/// model's corners but its stray ones, only points in [`framed_box`] are framed: the
/// faces that reach a stray corner run out of the picture and the rest of the model
/// fills it.
pub fn framing_of(
    framed: Option<[[f32; 3]; 2]>,
    z_scale: f32,
    aspect: f32,
    view: (f32, f32),
) -> Framing {
    let framing = Framing::new(z_scale, aspect, view);
    match framed.map(framed_box) {
        Some((lo, hi)) => framing.within(lo, hi),
        None => framing,
    }
}

/// One piece of a scene drawn a part at a time ([`parts`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Part {
    /// The top faces of a run of layers.
    Tops(Range<usize>),
    /// The faces of the cells in rows `rows` of one layer's top or bottom: a layer
    /// with more active cells than a part, cut into bands.
    Band {
        /// The layer (0-based).
        layer: usize,
        /// Its top or bottom faces.
        face: Face,
        /// The rows of cells (0-based, end exclusive).
        rows: Range<usize>,
    },
    /// The bottom faces of the deepest layer, which close the stack.
    Bottom(usize),
    /// The side faces of a run of layers.
    Sides(Range<usize>),
}

impl Part {
    /// The active cells whose top or bottom faces the part holds (its side faces are
    /// few beside them).
    pub fn cells(&self, grid: &CornerPointGrid) -> usize {
        match self {
            Part::Tops(run) => active_cells(grid, run.clone()),
            Part::Band { layer, rows, .. } => grid.active_count_in(*layer, rows.clone()),
            Part::Bottom(k) => active_cells(grid, *k..*k + 1),
            Part::Sides(_) => 0,
        }
    }
}

/// The layers `options` draws, checked against the model's.
fn drawn_layers(grid: &CornerPointGrid, options: &SceneOptions) -> Result<Range<usize>> {
    let nz = grid.dims().nz;
    let layers = options.layers.clone().unwrap_or(0..nz);
    if layers.is_empty() || layers.end > nz {
        return Err(Error::Scene(format!(
            "layers {}..{} are not within the model's 1..{nz}",
            layers.start + 1,
            layers.end
        )));
    }
    Ok(layers)
}

/// The parts of a scene, in the order its whole mesh stacks them (the tops layer by
/// layer, the bottom, the sides layer by layer), so that drawing them one after
/// another gives the picture of the whole mesh. The layers are cut into runs of at
/// most `max_cells` active cells, and a layer with more into bands of rows, so that a
/// scene too large for memory is drawn in the memory of its largest part.
pub fn parts(
    grid: &CornerPointGrid,
    options: &SceneOptions,
    max_cells: usize,
) -> Result<Vec<Part>> {
    let layers = drawn_layers(grid, options)?;
    let per_layer = layers.clone().map(|k| active_cells(grid, k..k + 1));
    let runs = runs_of(layers.start, per_layer, max_cells);
    let whole_or_bands = |layer: usize, face: Face, cells: usize, whole: Part| {
        if cells <= max_cells {
            return vec![whole];
        }
        bands(grid, layer, max_cells)
            .map(|rows| Part::Band { layer, face, rows })
            .collect()
    };
    let mut parts: Vec<Part> = runs
        .iter()
        .flat_map(|(run, cells)| {
            whole_or_bands(run.start, Face::Top, *cells, Part::Tops(run.clone()))
        })
        .collect();
    let last = layers.end - 1;
    let last_cells = active_cells(grid, last..last + 1);
    parts.extend(whole_or_bands(
        last,
        Face::Bottom,
        last_cells,
        Part::Bottom(last),
    ));
    if options.sides {
        parts.extend(runs.into_iter().map(|(run, _)| Part::Sides(run)));
    }
    Ok(parts)
}

/// Whether `parts` cut the tops into more than one piece: then a scene is drawn a
/// part at a time, not as one mesh.
pub fn drawn_in_parts(parts: &[Part]) -> bool {
    let tops = parts.iter().filter(|p| match p {
        Part::Tops(_) => true,
        Part::Band { face, .. } => *face == Face::Top,
        Part::Bottom(_) | Part::Sides(_) => false,
    });
    tops.count() > 1
}

/// Layer `k`'s rows cut into bands of at most `max_cells` active cells (a row with
/// more is a band of its own).
fn bands(grid: &CornerPointGrid, k: usize, max_cells: usize) -> impl Iterator<Item = Range<usize>> {
    let per_row = (0..grid.dims().ny).map(|j| grid.active_count_in(k, j..j + 1));
    runs_of(0, per_row, max_cells)
        .into_iter()
        .map(|(rows, _)| rows)
}

/// Consecutive items from index `first`, of `counts` active cells each, in runs of at
/// most `max_cells` cells (an item with more is a run of its own), with each run's
/// cells.
fn runs_of(
    first: usize,
    counts: impl IntoIterator<Item = usize>,
    max_cells: usize,
) -> Vec<(Range<usize>, usize)> {
    let mut runs: Vec<(Range<usize>, usize)> = Vec::new();
    for (n, count) in counts.into_iter().enumerate() {
        let at = first + n;
        match runs.last_mut() {
            Some((run, cells)) if *cells + count <= max_cells => {
                run.end = at + 1;
                *cells += count;
            }
            _ => runs.push((at..at + 1, count)),
        }
    }
    runs
}

/// The active cells of `layers`.
pub fn active_cells(grid: &CornerPointGrid, layers: Range<usize>) -> usize {
    layers
        .map(|k| grid.active_count_in(k, 0..grid.dims().ny))
        .sum()
}

/// The surfaces of `part` of the scene `options` asks for, relative to `origin` (the
/// grid's display origin, which takes a pass over all its cells to find), coloured
/// and painted as the whole scene's: its faces in `columns` (none when that is
/// empty).
pub fn build_part(
    grid: &CornerPointGrid,
    options: &SceneOptions,
    part: &Part,
    origin: [f64; 3],
    columns: &Columns,
) -> Result<SurfaceMesh> {
    let property = options.property.as_deref();
    let columns = match part {
        Part::Band { rows, .. } => columns.in_rows(rows.clone()),
        _ => columns.clone(),
    };
    if columns.is_empty() {
        return Ok(SurfaceMesh::with_origin(origin));
    }
    let mesh = match part {
        Part::Tops(run) => layer_surfaces(
            grid,
            Face::Top,
            &Surfaces::new(run.clone(), origin)
                .property(property)
                .columns(columns.clone())
                .cut(options.cut.clone())
                .inactive(options.inactive),
        )?,
        Part::Band { layer, face, .. } => layer_surfaces(
            grid,
            *face,
            &Surfaces::layer(*layer, origin)
                .property(property)
                .columns(columns.clone())
                .cut(options.cut.clone())
                .inactive(options.inactive),
        )?,
        Part::Bottom(k) => layer_surfaces(
            grid,
            Face::Bottom,
            &Surfaces::layer(*k, origin)
                .property(property)
                .columns(columns.clone())
                .cut(options.cut.clone())
                .inactive(options.inactive),
        )?,
        Part::Sides(run) => {
            let scene = drawn_layers(grid, options)?;
            side_surfaces(
                grid,
                &Surfaces::new(run.clone(), origin)
                    .property(property)
                    .columns(columns.clone())
                    .among(scene)
                    .cut(options.cut.clone())
                    .inactive(options.inactive),
            )?
        }
    };
    Ok(if options.flat_cells && property.is_some() {
        mesh.with_cell_values()
    } else {
        mesh
    })
}

/// Rows of cells of one piece of [`build_part_on_all_cores`].
const ROWS_PER_PIECE: usize = 64;

/// [`build_part`] for drawing, on all cores: a part's top and bottom surfaces are
/// built in pieces of `ROWS_PER_PIECE` rows of one layer, in parallel, and put
/// together in order. The faces, their order and every corner's position, texture
/// coordinates and value are those of [`build_part`]; only the nodes on the seams
/// between pieces get a vertex in each piece, which changes no pixel. A part holds a
/// few layers, so building it a layer a thread left most cores of a many-core machine
/// idle, and the building took most of a frame (docs/performance.md).
pub fn build_part_on_all_cores(
    grid: &CornerPointGrid,
    options: &SceneOptions,
    part: &Part,
    origin: [f64; 3],
    columns: &Columns,
) -> Result<SurfaceMesh> {
    build_part_in_pieces(grid, options, part, origin, columns, ROWS_PER_PIECE)
}

fn build_part_in_pieces(
    grid: &CornerPointGrid,
    options: &SceneOptions,
    part: &Part,
    origin: [f64; 3],
    columns: &Columns,
    rows_per_piece: usize,
) -> Result<SurfaceMesh> {
    let (layers, face, rows) = match part {
        Part::Tops(run) => (run.clone(), Face::Top, columns.j.clone()),
        Part::Band { layer, face, rows } => {
            (*layer..*layer + 1, *face, columns.in_rows(rows.clone()).j)
        }
        Part::Bottom(k) => (*k..*k + 1, Face::Bottom, columns.j.clone()),
        Part::Sides(_) => return build_part(grid, options, part, origin, columns),
    };
    let pieces: Vec<Part> = layers
        .flat_map(|layer| {
            rows.clone()
                .step_by(rows_per_piece.max(1))
                .map(move |start| Part::Band {
                    layer,
                    face,
                    rows: start..(start + rows_per_piece).min(rows.end),
                })
        })
        .collect();
    let meshes = pieces
        .par_iter()
        .map(|piece| build_part(grid, options, piece, origin, columns))
        .collect::<Result<Vec<_>>>()?;
    let mut mesh = SurfaceMesh::with_origin(origin);
    for m in &meshes {
        mesh.append(m);
    }
    Ok(mesh)
}

/// Where a scene drawn in parts lies, found before any part is drawn: the framing of
/// all its vertices, its triangles, and the box of each tile of columns of its
/// faces, which says what of each layer a close-up needs.
#[derive(Clone, Debug)]
pub struct SceneExtent {
    /// The framing of every vertex of the scene, for its view.
    pub framing: Framing,
    /// Triangles of the whole scene.
    pub triangles: usize,
    /// All the grid's columns, and how many on a side of a tile.
    columns: Columns,
    tile: usize,
    tiles_across: usize,
    /// Per tile, row by row.
    boxes: Vec<TileBox>,
}

/// The box of a tile's faces (unscaled display frame), `None` where it has none.
type TileBox = Option<(Vec3, Vec3)>;

/// Tiles on a side of the columns, at most: few enough that their boxes are small
/// and quickly tested, enough that a close-up needs only some.
const TILES_ACROSS: usize = 64;

/// The extent of the scene `options` asks for ([`SceneExtent`]), for the view
/// `framing` was made for (it holds no point yet), from the corners of its faces in
/// one parallel pass over rows of tiles, building no mesh: those corners are exactly
/// the vertices of its surfaces. `progress`, when given, hears of each row done.
pub fn scene_extent(
    grid: &CornerPointGrid,
    options: &SceneOptions,
    origin: [f64; 3],
    framing: Framing,
    progress: Option<&(dyn Fn(Progress) + Send + Sync + '_)>,
) -> Result<SceneExtent> {
    let layers = drawn_layers(grid, options)?;
    let Dims { nx, ny, .. } = grid.dims();
    let tile = nx.max(ny).div_ceil(TILES_ACROSS).max(1);
    let tiles_across = nx.div_ceil(tile);
    let tile_rows = ny.div_ceil(tile);
    let cut = options
        .cut
        .clone()
        .unwrap_or_else(|| Columns::all(grid.dims()));
    let rows_done = AtomicUsize::new(0);
    let layer_faces: Vec<(usize, Face)> = layers
        .clone()
        .map(|k| (k, Face::Top))
        .chain([(layers.end - 1, Face::Bottom)])
        .collect();
    // A row of tiles at a time, in parallel: each its own framing, boxes and count.
    let rows: Vec<(Framing, Vec<TileBox>, usize)> = (0..tile_rows)
        .into_par_iter()
        .map(|tile_row| {
            let mut framing = framing.clone();
            let mut boxes: Vec<TileBox> = vec![None; tiles_across];
            let mut triangles = 0;
            // Corners already framed (shared with the face before) box their tile alone.
            let mut add = |i: usize, corners: [[f32; 3]; 4], framed: usize| {
                let corners = corners.map(Vec3::from);
                framing.add(corners[..4 - framed].iter().copied());
                let (lo, hi) = boxes[i / tile].get_or_insert((corners[0], corners[0]));
                for c in corners {
                    (*lo, *hi) = (lo.min(c), hi.max(c));
                }
            };
            let rows = tile_row * tile..((tile_row + 1) * tile).min(ny);
            for j in rows.clone().filter(|j| cut.j.contains(j)) {
                for &(k, face) in &layer_faces {
                    visit_row_faces(
                        grid,
                        ([j, k], cut.i.clone(), options.inactive),
                        face,
                        origin,
                        |i, [sw, se, ne, nw], west_given| {
                            triangles += 2;
                            add(i, [se, ne, sw, nw], 2 * usize::from(west_given));
                        },
                    );
                }
            }
            if options.sides {
                for k in layers.clone() {
                    // Which cells have faces, a row at a time: the row's, and the rows
                    // beside it, which say which of its sides are open.
                    let row = |j: usize| -> Vec<bool> {
                        (0..nx)
                            .map(|i| {
                                cut.contains(i, j) && drawn_cell(grid, [i, j, k], options.inactive)
                            })
                            .collect()
                    };
                    let mut before = rows.start.checked_sub(1).map(row).unwrap_or_default();
                    let mut here = row(rows.start);
                    for j in rows.clone() {
                        let after = if j + 1 < ny { row(j + 1) } else { Vec::new() };
                        let with_faces = |i: usize, at: usize| match at.cmp(&j) {
                            std::cmp::Ordering::Less => before[i],
                            std::cmp::Ordering::Equal => here[i],
                            std::cmp::Ordering::Greater => after[i],
                        };
                        for i in (0..nx).filter(|&i| here[i]) {
                            let open = open_sides(grid, [i, j, k], with_faces);
                            for side in (0..4).filter(|&s| open[s]) {
                                // A degenerate face leaves its vertices in the mesh.
                                let (corners, kept) =
                                    side_face_corners(grid, [i, j, k], side, origin);
                                triangles += 2 * usize::from(kept);
                                add(i, corners, 0);
                            }
                        }
                        before = std::mem::replace(&mut here, after);
                    }
                }
            }
            if let Some(report) = progress {
                report(Progress {
                    stage: Stage::Framing,
                    done: rows_done.fetch_add(1, Ordering::Relaxed) + 1,
                    total: tile_rows,
                });
            }
            (framing, boxes, triangles)
        })
        .collect();
    let mut extent = SceneExtent {
        framing,
        triangles: 0,
        columns: Columns::all(grid.dims()),
        tile,
        tiles_across,
        boxes: Vec::with_capacity(rows.len() * tiles_across),
    };
    for (framing, boxes, triangles) in rows {
        extent.framing.merge(&framing);
        extent.boxes.extend(boxes);
        extent.triangles += triangles;
    }
    Ok(extent)
}

impl SceneExtent {
    /// The columns whose layer faces a picture of `aspect` (width / height) that
    /// `camera` takes may show: the rectangle around the tiles whose box is not wholly
    /// outside it (empty when there is none).
    pub fn columns_in_view(&self, camera: &Camera, aspect: f32) -> Columns {
        let seen = self.boxes.iter().enumerate().filter_map(|(n, b)| {
            let (lo, hi) = (*b)?;
            let outside = box_outside_view((lo.into(), hi.into()), camera, aspect);
            (!outside).then_some((n % self.tiles_across, n / self.tiles_across))
        });
        let (lo, hi) = seen.fold(([usize::MAX; 2], [0; 2]), |(lo, hi), (i, j)| {
            (
                [lo[0].min(i), lo[1].min(j)],
                [hi[0].max(i + 1), hi[1].max(j + 1)],
            )
        });
        let span = |a: usize, b: usize, n: usize| {
            a.saturating_mul(self.tile).min(n)..(b * self.tile).min(n)
        };
        Columns {
            i: span(lo[0], hi[0], self.columns.i.end),
            j: span(lo[1], hi[1], self.columns.j.end),
        }
    }
}

/// The range of the defined values of the property colouring the scene, over all its
/// cells (`None` without a property or defined value).
pub fn colour_range_of(
    grid: &CornerPointGrid,
    options: &SceneOptions,
) -> Result<Option<(f32, f32)>> {
    Ok(colour_values_of(grid, options)?.and_then(colour_range))
}

/// The values of the property colouring the scene over all its cells (its active
/// cells in the drawn layers); `None` without a property.
pub fn colour_values_of<'g>(
    grid: &'g CornerPointGrid,
    options: &SceneOptions,
) -> Result<Option<impl Iterator<Item = f32> + 'g>> {
    let layers = drawn_layers(grid, options)?;
    Ok(options
        .property
        .as_deref()
        .and_then(|name| grid.active_values(name, layers)))
}

/// The cell faces of `mesh` that `camera` may show in a picture of `aspect` (width /
/// height): those not wholly outside one of the picture's planes
/// ([`Camera::frustum`]), and with `facing_only` those that face the eye. That is for
/// side faces, which wind counter-clockwise seen from outside their cells: the cells
/// drawn are closed by their layers' top and bottom surfaces and their other side
/// faces, which hide a face that turns its back.
pub fn faces_in_view(
    mesh: &SurfaceMesh,
    camera: &Camera,
    aspect: f32,
    facing_only: bool,
) -> SurfaceMesh {
    let planes = camera.frustum(aspect);
    let scale = Vec3::new(1.0, 1.0, camera.z_scale);
    let at = |v: u32| Vec3::from(mesh.positions[v as usize]) * scale;
    let outside =
        |plane: &[f32; 4], p: Vec3| Vec3::new(plane[0], plane[1], plane[2]).dot(p) + plane[3] < 0.0;
    mesh.cell_faces_where(|face| {
        let triangles = face.triangles.map(|t| mesh.triangles[t as usize].map(at));
        let corners = || triangles.iter().flatten().copied();
        let faces_eye = || {
            triangles
                .iter()
                .any(|[a, b, c]| (*b - *a).cross(*c - *a).dot(camera.eye - *a) > 0.0)
        };
        (!facing_only || faces_eye())
            && !planes
                .iter()
                .any(|plane| corners().all(|p| outside(plane, p)))
    })
}

/// Whether the box `(lo, hi)` (unscaled display frame) lies wholly inside the picture
/// of `aspect` that `camera` takes ([`Camera::frustum`]): then no face in it need be
/// tested by [`faces_in_view`].
pub fn box_in_view(bounds: ([f32; 3], [f32; 3]), camera: &Camera, aspect: f32) -> bool {
    let corners = box_corners(bounds, camera.z_scale);
    camera.frustum(aspect).iter().all(|plane| {
        let normal = Vec3::new(plane[0], plane[1], plane[2]);
        corners.iter().all(|&p| normal.dot(p) + plane[3] >= 0.0)
    })
}

/// Whether the box `(lo, hi)` (unscaled display frame) lies wholly outside one of the
/// planes of the picture of `aspect` that `camera` takes: then nothing in it shows.
pub fn box_outside_view(bounds: ([f32; 3], [f32; 3]), camera: &Camera, aspect: f32) -> bool {
    let corners = box_corners(bounds, camera.z_scale);
    camera.frustum(aspect).iter().any(|plane| {
        let normal = Vec3::new(plane[0], plane[1], plane[2]);
        corners.iter().all(|&p| normal.dot(p) + plane[3] < 0.0)
    })
}

/// The eight corners of the box `(lo, hi)`, exaggerated by `z_scale`.
fn box_corners((lo, hi): ([f32; 3], [f32; 3]), z_scale: f32) -> [Vec3; 8] {
    std::array::from_fn(|c| {
        Vec3::new(
            if c & 1 == 0 { lo[0] } else { hi[0] },
            if c & 2 == 0 { lo[1] } else { hi[1] },
            if c & 4 == 0 { lo[2] } else { hi[2] },
        ) * Vec3::new(1.0, 1.0, z_scale)
    })
}

/// Where `--centre` looks: the centre of cell `(i, j)`'s top face on the first layer
/// `options` draws whose surface has it (within its cut), relative to `origin`.
pub fn column_top(
    grid: &CornerPointGrid,
    options: &SceneOptions,
    cell: [u32; 2],
    origin: [f64; 3],
) -> Result<[f32; 3]> {
    let Dims { nx, ny, nz } = grid.dims();
    let [i, j] = cell.map(|c| c as usize);
    // The one cell's face, as the whole surface has it: its corners are the surface's.
    let column = Columns {
        i: i..i + 1,
        j: j..j + 1,
    };
    let in_cut = options.cut.as_ref().is_none_or(|cut| cut.contains(i, j));
    let candidates = options
        .layers
        .clone()
        .unwrap_or(0..nz)
        .filter(|&k| in_cut && drawn_cell(grid, [i, j, k], options.inactive))
        .map(|k| {
            let face = layer_surfaces(
                grid,
                Face::Top,
                &Surfaces::layer(k, origin)
                    .columns(column.clone())
                    .inactive(options.inactive),
            )?;
            Ok(face.cell_centre(cell))
        });
    first_face_centre(cell, [nx, ny], candidates)
}

/// The first centre that `candidates` (cell `(i, j)`'s face centre on each drawn
/// surface in turn, `None` where it has none) finds, for `--centre` on a model of
/// `columns` columns of cells; the candidates are looked at only once the cell is
/// known to be in the model.
pub fn first_face_centre(
    [i, j]: [u32; 2],
    columns: [usize; 2],
    candidates: impl IntoIterator<Item = Result<Option<[f32; 3]>>>,
) -> Result<[f32; 3]> {
    let named = format!("--centre {},{}", i + 1, j + 1);
    let [ni, nj] = columns;
    if i as usize >= ni || j as usize >= nj {
        return Err(Error::Scene(format!(
            "{named}: the model has {ni} x {nj} columns of cells"
        )));
    }
    for centre in candidates {
        if let Some(centre) = centre? {
            return Ok(centre);
        }
    }
    Err(Error::Scene(format!(
        "{named}: no drawn layer has a face of that cell (inactive or pinched out)"
    )))
}

/// The range of the finite `values` that a colour map spans, one unit wide when they
/// are all equal; `None` when there is none.
pub fn colour_range(values: impl IntoIterator<Item = f32>) -> Option<(f32, f32)> {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    (lo <= hi).then_some((lo, if hi > lo { hi } else { lo + 1.0 }))
}

/// The isoline field of `smooth` (a property averaged onto its nodes) per triangle
/// corner of the same surfaces as drawn: `cell_painted` ones
/// (`SurfaceMesh::with_cell_values`) list their triangles face by face, the others in
/// `smooth`'s order.
pub fn corner_field(smooth: &SurfaceMesh, cell_painted: bool) -> Vec<f32> {
    let corners = |t: u32| smooth.triangles[t as usize].map(|v| smooth.scalars[v as usize]);
    if cell_painted {
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
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use strata_grid::synth::{SynthParams, generate};

    fn faulted() -> CornerPointGrid {
        generate(&SynthParams {
            nx: 70,
            ny: 45,
            nz: 4,
            faults: 4,
            seed: 3,
        })
        .expect("a generated grid")
    }

    /// Per triangle corner, in order: position, texture coordinates and value.
    fn corners(mesh: &SurfaceMesh) -> Vec<([f32; 3], [f32; 2], Option<u32>)> {
        mesh.triangles
            .iter()
            .flatten()
            .map(|&v| {
                let v = v as usize;
                let value = mesh.scalars.get(v).map(|s| s.to_bits());
                (mesh.positions[v], mesh.texcoords[v], value)
            })
            .collect()
    }

    #[test]
    fn a_part_built_in_pieces_has_the_faces_and_corners_of_the_part_built_whole() {
        let grid = faulted();
        let origin = grid.display_origin();
        let all = Columns::all(grid.dims());
        let close = Columns {
            i: 10..50,
            j: 5..40,
        };
        for (property, flat_cells) in [(None, false), (Some("PORO"), false), (Some("PORO"), true)] {
            let options = SceneOptions {
                sides: true,
                property: property.map(str::to_string),
                flat_cells,
                ..SceneOptions::default()
            };
            // Parts of a few layers, and bands of a layer too large for a part.
            let parts: Vec<Part> = [10_000, 900]
                .iter()
                .flat_map(|&cells| parts(&grid, &options, cells).expect("the parts"))
                .collect();
            assert!(
                parts
                    .iter()
                    .any(|p| matches!(p, Part::Tops(run) if run.len() > 1))
            );
            assert!(parts.iter().any(|p| matches!(p, Part::Band { .. })));
            for part in &parts {
                for columns in [&all, &close] {
                    let whole = build_part(&grid, &options, part, origin, columns).expect("a part");
                    let pieces = build_part_in_pieces(&grid, &options, part, origin, columns, 7)
                        .expect("a part in pieces");
                    assert_eq!(faces(&pieces), faces(&whole), "{part:?}");
                    assert_eq!(corners(&pieces), corners(&whole), "{part:?}");
                    assert_eq!(
                        pieces
                            .cell_faces
                            .iter()
                            .map(|f| f.value.to_bits())
                            .collect::<Vec<_>>(),
                        whole
                            .cell_faces
                            .iter()
                            .map(|f| f.value.to_bits())
                            .collect::<Vec<_>>()
                    );
                }
            }
        }
    }

    /// The cells and corners of `mesh`'s faces, in order.
    fn faces(mesh: &SurfaceMesh) -> Vec<([u32; 3], Vec<[f32; 3]>)> {
        mesh.cell_faces
            .iter()
            .map(|f| {
                let corners = f.triangles.iter().flat_map(|&t| mesh.triangles[t as usize]);
                (
                    f.cell,
                    corners.map(|v| mesh.positions[v as usize]).collect(),
                )
            })
            .collect()
    }

    #[test]
    fn the_extent_of_a_scene_frames_and_counts_its_whole_mesh() {
        // With and without side faces, all layers or some: the corners frame the
        // scene exactly as its mesh's vertices do, degenerate faces' included.
        let grid = faulted();
        let origin = grid.display_origin();
        let framing = Framing::new(3.0, 1.5, (30.0, 35.0));
        for (sides, layers) in [(true, None), (false, None), (true, Some(1..3))] {
            let options = SceneOptions {
                layers,
                sides,
                property: Some("PORO".into()),
                flat_cells: true,
                cut: None,
                inactive: false,
            };
            let (whole, _) = build(&grid, &options).expect("the scene");
            assert!(whole.triangle_count() > 10_000);
            let mut of_mesh = framing.clone();
            of_mesh.add(whole.positions.iter().map(|&p| Vec3::from(p)));
            let rows = std::sync::Mutex::new(Vec::new());
            let count = |p: Progress| rows.lock().expect("not poisoned").push(p);
            let extent = scene_extent(&grid, &options, origin, framing.clone(), Some(&count));
            let extent = extent.expect("the extent");
            // Every row of tiles was counted, once.
            let mut rows = rows.into_inner().expect("not poisoned");
            rows.sort_by_key(|p| p.done);
            assert!(rows.len() > 1);
            assert!(rows.iter().enumerate().all(|(n, p)| {
                p.stage == Stage::Framing && p.done == n + 1 && p.total == rows.len()
            }));
            assert_eq!(extent.triangles, whole.triangle_count());
            assert_eq!(extent.framing.camera(1.0), of_mesh.camera(1.0));
            assert_eq!(extent.framing.bounds(), of_mesh.bounds());
            // Seen whole, every column is needed.
            let camera = extent.framing.camera(1.0);
            assert_eq!(
                extent.columns_in_view(&camera, 1.5),
                Columns::all(grid.dims())
            );
        }
    }

    #[test]
    fn the_centre_of_a_cell_is_found_on_its_face_alone_as_on_the_whole_layer() {
        let grid = faulted();
        let origin = grid.display_origin();
        let d = grid.dims();
        let mut found = 0;
        for (i, j) in (0..d.nx)
            .step_by(3)
            .flat_map(|i| (0..d.ny).step_by(4).map(move |j| (i, j)))
        {
            let cell = [i as u32, j as u32];
            let on_layers = (0..d.nz).map(|k| {
                let layer =
                    strata_grid::layer_surfaces(&grid, Face::Top, &Surfaces::layer(k, origin))?;
                Ok(layer.cell_centre(cell))
            });
            let whole = first_face_centre(cell, [d.nx, d.ny], on_layers);
            let alone = column_top(&grid, &SceneOptions::default(), cell, origin);
            match (whole, alone) {
                (Ok(a), Ok(b)) => {
                    assert_eq!(a, b, "{cell:?}");
                    found += 1;
                }
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
                (a, b) => panic!("{cell:?}: {a:?} against {b:?}"),
            }
        }
        assert!(found > 200, "{found} centres");
        let beyond = column_top(&grid, &SceneOptions::default(), [70, 3], origin)
            .expect_err("off the model");
        assert!(beyond.to_string().contains("70 x 45 columns"), "{beyond}");
    }

    #[test]
    fn a_close_up_builds_only_the_columns_it_shows() {
        // A close-up of the middle of the model: a part built in the columns in view
        // shows the same faces, in the same order, as the part built whole, and those
        // columns are a small share of all.
        let grid = faulted();
        let options = SceneOptions {
            sides: true,
            ..SceneOptions::default()
        };
        let origin = grid.display_origin();
        let parts = parts(&grid, &options, 900).expect("the parts");
        let framing = Framing::new(1.0, 1.5, (30.0, 60.0));
        let extent = scene_extent(&grid, &options, origin, framing, None).expect("the extent");
        let centre = column_top(&grid, &SceneOptions::default(), [30, 20], origin).expect("a face");
        let camera = extent.framing.camera(0.1).centred_on(Vec3::from(centre));
        let columns = extent.columns_in_view(&camera, 1.5);
        assert!(
            columns.i.len() * columns.j.len() < 70 * 45 / 4,
            "{columns:?}"
        );
        assert!(columns.i.contains(&30) && columns.j.contains(&20));
        let all = Columns::all(grid.dims());
        let mut shown = 0;
        for part in &parts {
            let seen = |columns: &Columns| {
                let mesh = build_part(&grid, &options, part, origin, columns).expect("a part");
                faces(&faces_in_view(&mesh, &camera, 1.5, false))
            };
            let whole = seen(&all);
            shown += whole.len();
            assert!(seen(&columns) == whole, "{part:?}");
        }
        assert!(shown > 500, "{shown} faces in view");
    }
}
