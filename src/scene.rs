//! From a model to what is drawn: the layer and side surfaces a view asks for, with
//! the property that colours them.

use std::ops::Range;

use anyhow::{Result, bail};
use strata_grid::{
    Columns, CornerPointGrid, Dims, Face, SurfaceMesh, layer_surface, layer_surface_in,
    layer_surfaces, side_surfaces_among,
};
use strata_render::Camera;
use strata_render::glam::Vec3;

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
}

/// The surfaces of `grid` for a view, in one mesh relative to the grid's display
/// origin, and the range of the property's defined values.
pub fn build(
    grid: &CornerPointGrid,
    options: &SceneOptions,
) -> Result<(SurfaceMesh, Option<(f32, f32)>)> {
    let origin = grid.display_origin();
    let mut mesh = SurfaceMesh::with_origin(origin);
    for part in parts(grid, options, usize::MAX)? {
        mesh.append(&build_part(grid, options, &part, origin)?);
    }
    if mesh.is_empty() {
        return Err(nothing_to_draw(grid, options));
    }
    Ok((mesh, colour_range_of(grid, options)?))
}

/// The error of a scene whose layers have no face to draw.
pub fn nothing_to_draw(grid: &CornerPointGrid, options: &SceneOptions) -> anyhow::Error {
    let layers = options.layers.clone().unwrap_or(0..grid.dims().nz);
    anyhow::anyhow!(
        "no active cell in layers {}..{}: nothing to draw",
        layers.start + 1,
        layers.end
    )
}

/// One piece of a scene drawn a part at a time ([`parts`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Part {
    /// The top faces of a run of layers.
    Tops(Range<usize>),
    /// The faces of the cells in rows `rows` of one layer's top or bottom: a layer
    /// with more active cells than a part, cut into bands.
    Band {
        layer: usize,
        face: Face,
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
        bail!(
            "layers {}..{} are not within the model's 1..{nz}",
            layers.start + 1,
            layers.end
        );
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
/// and painted as the whole scene's.
pub fn build_part(
    grid: &CornerPointGrid,
    options: &SceneOptions,
    part: &Part,
    origin: [f64; 3],
) -> Result<SurfaceMesh> {
    let property = options.property.as_deref();
    let mesh = match part {
        Part::Tops(run) => layer_surfaces(grid, run.clone(), Face::Top, property, origin)?,
        Part::Band { layer, face, rows } => {
            let band = Columns::all(grid.dims()).in_rows(rows.clone());
            layer_surface_in(grid, *layer, *face, property, origin, &band)?
        }
        Part::Bottom(k) => layer_surface(grid, *k, Face::Bottom, property, origin)?,
        Part::Sides(run) => {
            let scene = drawn_layers(grid, options)?;
            side_surfaces_among(grid, run.clone(), scene, property, origin)?
        }
    };
    Ok(if options.flat_cells && property.is_some() {
        mesh.with_cell_values()
    } else {
        mesh
    })
}

/// The range of the defined values of the property colouring the scene, over all its
/// cells (`None` without a property or defined value).
pub fn colour_range_of(
    grid: &CornerPointGrid,
    options: &SceneOptions,
) -> Result<Option<(f32, f32)>> {
    let layers = drawn_layers(grid, options)?;
    Ok(options
        .property
        .as_deref()
        .and_then(|name| colour_range(grid.active_values(name, layers)?)))
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
pub fn box_in_view((lo, hi): ([f32; 3], [f32; 3]), camera: &Camera, aspect: f32) -> bool {
    let scale = Vec3::new(1.0, 1.0, camera.z_scale);
    let corners = (0..8).map(|c| {
        Vec3::new(
            if c & 1 == 0 { lo[0] } else { hi[0] },
            if c & 2 == 0 { lo[1] } else { hi[1] },
            if c & 4 == 0 { lo[2] } else { hi[2] },
        ) * scale
    });
    camera.frustum(aspect).iter().all(|plane| {
        let normal = Vec3::new(plane[0], plane[1], plane[2]);
        corners.clone().all(|p| normal.dot(p) + plane[3] >= 0.0)
    })
}

/// Where `--centre` looks: the centre of cell `(i, j)`'s top face on the first of
/// `layers` (all when `None`) whose surface has it, relative to `origin`.
pub fn column_top(
    grid: &CornerPointGrid,
    layers: Option<Range<usize>>,
    cell: [u32; 2],
    origin: [f64; 3],
) -> Result<[f32; 3]> {
    let Dims { nx, ny, nz } = grid.dims();
    let candidates = layers
        .unwrap_or(0..nz)
        .filter(|&k| grid.is_active(cell[0] as usize, cell[1] as usize, k))
        .map(|k| Ok(layer_surface(grid, k, Face::Top, None, origin)?.cell_centre(cell)));
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
        bail!("{named}: the model has {ni} x {nj} columns of cells");
    }
    for centre in candidates {
        if let Some(centre) = centre? {
            return Ok(centre);
        }
    }
    bail!("{named}: no drawn layer has a face of that cell (inactive or pinched out)")
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
