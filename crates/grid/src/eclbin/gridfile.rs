//! The GRID format, older than EGRID, as resdata reads it: DIMENS, then per cell a
//! COORDS record (i, j, k from 1, the global index, and from its fifth item on the
//! activity, 1 active; without it the cell is active) and a CORNERS record (its 8
//! corners, x y z each, in Eclipse order). Strata's model is pillars and depths, so
//! each pillar runs through the top corner of the column's first layer and the bottom
//! corner of its last (from the cell towards the grid's inside), and ZCORN takes every
//! cell's own corner depths.

use std::path::Path;

use super::egrid::map_and_units;
use super::record::{RecordView, Records};
use crate::{CornerPointGrid, Dims, Error, Result};

/// Whether the keywords are a GRID file's: COORDS before any GRIDHEAD (a summary
/// specification has DIMENS too, but no COORDS).
pub fn is_grid_file(records: Records<'_>) -> bool {
    for view in records.take(64) {
        match view.as_ref().map(RecordView::name) {
            Ok("COORDS") => return true,
            Ok("GRIDHEAD") | Err(_) => return false,
            _ => {}
        }
    }
    false
}

/// One cell as the file gives it.
struct Cell {
    index: usize,
    active: bool,
    corners: [f32; 24],
}

/// The main grid of a GRID file (LGR cells after an `LGR` keyword are left out).
pub fn grid_from_records(path: &Path, records: Records<'_>) -> Result<CornerPointGrid> {
    let (mut dims, mut mapaxes, mut gridunit) = (None, None, None);
    let mut cells: Vec<Cell> = Vec::new();
    let mut coords: Option<RecordView<'_>> = None;
    let mut records_end = 0;
    for view in records {
        let view = view?;
        records_end = usize::try_from(view.offset()).unwrap_or(usize::MAX);
        match view.name() {
            "DIMENS" => dims = Some(dimens(&view)?),
            "MAPAXES" => mapaxes = Some(view),
            "GRIDUNIT" => gridunit = Some(view),
            "LGR" => break,
            "COORDS" => coords = Some(view),
            "CORNERS" => {
                let d = dims.ok_or_else(|| view.error("CORNERS before DIMENS"))?;
                let c = coords
                    .take()
                    .ok_or_else(|| view.error("CORNERS without COORDS before it"))?;
                cells.push(cell(d, &c, &view)?);
            }
            _ => {}
        }
    }
    let d = dims.ok_or_else(|| Error::model(path, "DIMENS", "no DIMENS in the GRID file"))?;
    // A file may list only its active cells; still, each listed cell takes about 150
    // bytes, so a grid past four cells per byte of the file is not what it says.
    let bytes = records_end.max(1);
    if d.cell_count() / 4 > bytes {
        return Err(Error::model(
            path,
            "DIMENS",
            format!(
                "{} cells cannot be described by a file of {bytes} bytes",
                d.cell_count()
            ),
        ));
    }
    let mut by_index: Vec<Option<&Cell>> = vec![None; d.cell_count()];
    for c in &cells {
        by_index[c.index] = Some(c);
    }
    let coord = pillars(path, d, &by_index)?;
    let (zcorn, actnum) = depths(d, &by_index);
    let mut grid = CornerPointGrid::from_arrays(d, coord, zcorn, Some(actnum))
        .map_err(|e| Error::model(path, "CORNERS", e.to_string()))?;
    map_and_units(path, &mut grid, mapaxes, gridunit)?;
    Ok(grid)
}

fn corner(c: &Cell, n: usize) -> [f64; 3] {
    [c.corners[3 * n], c.corners[3 * n + 1], c.corners[3 * n + 2]].map(f64::from)
}

/// COORD: each pillar through the top corner of the highest listed cell and the
/// bottom corner of the lowest in the first column beside it that lists any.
fn pillars(path: &Path, d: Dims, cells: &[Option<&Cell>]) -> Result<Vec<f64>> {
    let mut coord = Vec::with_capacity(6 * (d.nx + 1) * (d.ny + 1));
    for pj in 0..=d.ny {
        for pi in 0..=d.nx {
            let found = (0..4).find_map(|q| {
                let (ci, cj) = (
                    (pi + (q & 1)).wrapping_sub(1),
                    (pj + (q >> 1)).wrapping_sub(1),
                );
                if ci >= d.nx || cj >= d.ny {
                    return None;
                }
                let column = |k: usize| cells[d.cell_index(ci, cj, k)];
                let top = (0..d.nz).find_map(column)?;
                let bottom = (0..d.nz).rev().find_map(column)?;
                let n = (pi - ci) + 2 * (pj - cj);
                Some((corner(top, n), corner(bottom, n + 4)))
            });
            let (t, mut b) = found.ok_or_else(|| {
                Error::model(
                    path,
                    "CORNERS",
                    format!("no cell beside pillar ({pi}, {pj}) (from 0) has corners"),
                )
            })?;
            if (b[2] - t[2]).abs() < f64::EPSILON * t[2].abs().max(1.0) {
                b = [t[0], t[1], t[2] + 1.0]; // a column without thickness: a vertical pillar
            }
            coord.extend(t.into_iter().chain(b));
        }
    }
    Ok(coord)
}

/// ZCORN and ACTNUM. A cell the file does not list is inactive, flat at the bottom of
/// the nearest listed cell above it (or the top of the one below; depth 0 in a column
/// that lists none, where resdata puts all its corners).
fn depths(d: Dims, cells: &[Option<&Cell>]) -> (Vec<f32>, Vec<bool>) {
    let mut zcorn = vec![0.0f32; 8 * d.cell_count()];
    let mut actnum = vec![false; d.cell_count()];
    for (index, act) in actnum.iter_mut().enumerate() {
        let (i, j, k) = d.cell_ijk(index);
        let column = |k: usize| cells[d.cell_index(i, j, k)];
        let z: [f32; 8] = match column(k) {
            Some(c) => {
                *act = c.active;
                std::array::from_fn(|n| c.corners[3 * n + 2])
            }
            None => match (
                (0..k).rev().find_map(column),
                (k + 1..d.nz).find_map(column),
            ) {
                (Some(above), _) => std::array::from_fn(|n| above.corners[3 * (4 + n % 4) + 2]),
                (None, Some(below)) => std::array::from_fn(|n| below.corners[3 * (n % 4) + 2]),
                (None, None) => [0.0; 8],
            },
        };
        for (n, z) in z.into_iter().enumerate() {
            let (di, dj, dk) = (n & 1, (n >> 1) & 1, n >> 2);
            zcorn[((2 * k + dk) * 2 * d.ny + 2 * j + dj) * 2 * d.nx + 2 * i + di] = z;
        }
    }
    (zcorn, actnum)
}

fn dimens(view: &RecordView<'_>) -> Result<Dims> {
    let v = view.to_i32()?;
    let axis = |n: Option<&i32>| n.and_then(|&n| usize::try_from(n).ok()).filter(|&n| n > 0);
    match (axis(v.first()), axis(v.get(1)), axis(v.get(2))) {
        (Some(x), Some(y), Some(z)) => Dims::new(x, y, z).map_err(|e| view.error(e.to_string())),
        _ => Err(view.error(format!("{v:?} are not three positive dimensions"))),
    }
}

fn cell(d: Dims, coords: &RecordView<'_>, corners: &RecordView<'_>) -> Result<Cell> {
    let c = coords.to_i32()?;
    let axis = |n: usize, size: usize| {
        c.get(n)
            .and_then(|&v| usize::try_from(v).ok())
            .filter(|&v| (1..=size).contains(&v))
            .map(|v| v - 1)
    };
    let (Some(i), Some(j), Some(k)) = (axis(0, d.nx), axis(1, d.ny), axis(2, d.nz)) else {
        return Err(coords.error(format!(
            "{:?} is not a cell (i, j, k) of the grid",
            &c[..c.len().min(3)]
        )));
    };
    let values = corners.to_f32()?;
    let corners: [f32; 24] = values.as_slice().try_into().map_err(|_| {
        corners.error(format!(
            "{} values, a cell has 24 (8 corners, x y z)",
            values.len()
        ))
    })?;
    Ok(Cell {
        index: d.cell_index(i, j, k),
        active: c.get(4).is_none_or(|&a| a == 1),
        corners,
    })
}
