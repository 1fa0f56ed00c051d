//! From a model to what is drawn: the layer and side surfaces a view asks for, with
//! the property that colours them.

use std::ops::Range;

use anyhow::{Result, bail};
use strata_grid::{
    CornerPointGrid, Dims, Face, SurfaceMesh, layer_surface, layer_surfaces, side_surfaces,
};

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
    let nz = grid.dims().nz;
    let layers = options.layers.clone().unwrap_or(0..nz);
    if layers.is_empty() || layers.end > nz {
        bail!(
            "layers {}..{} are not within the model's 1..{nz}",
            layers.start + 1,
            layers.end
        );
    }
    let origin = grid.display_origin();
    let property = options.property.as_deref();
    let mut mesh = layer_surfaces(grid, layers.clone(), Face::Top, property, origin)?;
    // The bottom of the deepest layer closes the stack.
    mesh.append(&layer_surface(
        grid,
        layers.end - 1,
        Face::Bottom,
        property,
        origin,
    )?);
    if options.sides {
        mesh.append(&side_surfaces(grid, layers.clone(), property, origin)?);
    }
    if mesh.is_empty() {
        bail!(
            "no active cell in layers {}..{}: nothing to draw",
            layers.start + 1,
            layers.end
        );
    }
    let range = property.and_then(|name| colour_range(grid.active_values(name, layers.clone())?));
    if options.flat_cells && property.is_some() {
        mesh = mesh.with_cell_values();
    }
    Ok((mesh, range))
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
