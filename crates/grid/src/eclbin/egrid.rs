//! EGRID: the corner-point geometry of the main grid.

use std::path::Path;

use super::record::{RecordView, Records};
use super::writer::RecordWriter;
use crate::{CornerPointGrid, Dims, Error, MapAxes, ReadOptions, Result, Units};

/// The first keywords of the main grid that the reader uses.
#[derive(Default)]
struct Found<'a> {
    gridhead: Option<RecordView<'a>>,
    coord: Option<RecordView<'a>>,
    zcorn: Option<RecordView<'a>>,
    actnum: Option<RecordView<'a>>,
    mapaxes: Option<RecordView<'a>>,
    gridunit: Option<RecordView<'a>>,
}

/// Parses an EGRID, or a GRID file (see the `gridfile` module), held in memory;
/// `path` names it in errors and warnings.
///
/// Only the main grid is read: the keywords up to its ENDGRID (LGR ... ENDLGR blocks
/// are skipped wherever they appear), and nothing after it, so NNC and LGR sections
/// cost nothing. An EGRID holds geometry only, so `options` changes nothing here; it
/// is taken so that every reader has the same shape, and [`super::read_egrid`] uses it
/// to decide whether to load the result files.
pub fn parse_egrid_bytes(
    path: &Path,
    bytes: &[u8],
    options: &ReadOptions,
) -> Result<CornerPointGrid> {
    if super::gridfile::is_grid_file(Records::new(path, bytes)) {
        return super::gridfile::grid_from_records(path, Records::new(path, bytes));
    }
    egrid_from_records(path, Records::new(path, bytes), options)
}

/// [`parse_egrid_bytes`] over the keywords `records` walks.
pub(crate) fn egrid_from_records(
    path: &Path,
    records: Records<'_>,
    _options: &ReadOptions,
) -> Result<CornerPointGrid> {
    let mut found = Found::default();
    let mut in_lgr = false;
    for view in records {
        let view = view?;
        match view.name() {
            "LGR" => in_lgr = true,
            "ENDLGR" => in_lgr = false,
            _ if in_lgr => {}
            "ENDGRID" => break,
            "GRIDHEAD" => keep_first(&mut found.gridhead, view),
            "COORD" => keep_first(&mut found.coord, view),
            "ZCORN" => keep_first(&mut found.zcorn, view),
            "ACTNUM" => keep_first(&mut found.actnum, view),
            "MAPAXES" => keep_first(&mut found.mapaxes, view),
            "GRIDUNIT" => keep_first(&mut found.gridunit, view),
            _ => {}
        }
    }
    build(path, &found)
}

fn keep_first<'a>(slot: &mut Option<RecordView<'a>>, view: RecordView<'a>) {
    if slot.is_none() {
        *slot = Some(view);
    }
}

fn missing(path: &Path, keyword: &str) -> Error {
    Error::model(
        path,
        keyword,
        format!("no {keyword} in the EGRID main grid"),
    )
}

fn build(path: &Path, found: &Found<'_>) -> Result<CornerPointGrid> {
    let head = found.gridhead.ok_or_else(|| missing(path, "GRIDHEAD"))?;
    let dims = grid_dims(&head)?;

    let coord_view = found.coord.ok_or_else(|| missing(path, "COORD"))?;
    let zcorn_view = found.zcorn.ok_or_else(|| missing(path, "ZCORN"))?;
    let wrong_len = |view: &RecordView<'_>, want: usize| {
        view.error(format!(
            "{} values, a {} x {} x {} grid needs {want}",
            view.len(),
            dims.nx,
            dims.ny,
            dims.nz
        ))
    };
    // Dims::new checked that both sizes fit a usize.
    let (coord_len, zcorn_len) = (dims.coord_len().unwrap_or(0), dims.zcorn_len().unwrap_or(0));
    if coord_view.len() != coord_len {
        return Err(wrong_len(&coord_view, coord_len));
    }
    if zcorn_view.len() != zcorn_len {
        return Err(wrong_len(&zcorn_view, zcorn_len));
    }
    let coord = coord_view.to_f64()?;
    if let Some(bad) = coord.iter().position(|v| !v.is_finite()) {
        return Err(coord_view.error(format!(
            "value {} (pillar {}) is not a finite number",
            bad + 1,
            bad / 6 + 1
        )));
    }
    let zcorn = zcorn_view.to_f32()?;
    let actnum = match found.actnum {
        Some(view) if view.len() != dims.cell_count() => {
            return Err(wrong_len(&view, dims.cell_count()));
        }
        Some(view) => Some(view.to_positive_flags()?),
        None => None,
    };
    // Lengths and COORD are checked above, so what from_arrays can still refuse is a
    // non-finite corner depth: report it against ZCORN.
    let mut grid = CornerPointGrid::from_arrays(dims, coord, zcorn, actnum)
        .map_err(|e| zcorn_view.error(e.to_string()))?;

    map_and_units(path, &mut grid, found.mapaxes, found.gridunit)?;
    Ok(grid)
}

/// Sets the grid's map axes and length unit from MAPAXES and GRIDUNIT, when present.
pub(super) fn map_and_units(
    path: &Path,
    grid: &mut CornerPointGrid,
    mapaxes: Option<RecordView<'_>>,
    gridunit: Option<RecordView<'_>>,
) -> Result<()> {
    if let Some(view) = mapaxes {
        let v = view.to_f64()?;
        let values: [f64; 6] = v
            .as_slice()
            .try_into()
            .map_err(|_| view.error(format!("{} values, MAPAXES needs 6", v.len())))?;
        if values.iter().any(|x| !x.is_finite()) {
            return Err(view.error("a value is not a finite number"));
        }
        grid.mapaxes = Some(MapAxes::from_values(values));
    }
    if let Some(view) = gridunit {
        let unit = view.to_strings()?.into_iter().next().unwrap_or_default();
        match Units::parse(&unit) {
            Some(u) => grid.units = u,
            None => grid.warnings.push(format!(
                "{}: GRIDUNIT {unit:?} is not a known length unit, metres assumed",
                path.display()
            )),
        }
    }
    Ok(())
}

/// Grid dimensions from GRIDHEAD (item 1 the grid type, 1 = corner point; items 2-4
/// nx, ny, nz).
fn grid_dims(head: &RecordView<'_>) -> Result<Dims> {
    let items = head.to_i32()?;
    let [kind, nx, ny, nz, ..] = items[..] else {
        return Err(head.error(format!(
            "{} values, at least 4 are needed (type, nx, ny, nz)",
            items.len()
        )));
    };
    if kind != 1 {
        return Err(head.error(format!(
            "grid type {kind} is not a corner-point grid (1); unstructured grids are not read"
        )));
    }
    let axis = |n: i32| usize::try_from(n).ok().filter(|&n| n > 0);
    match (axis(nx), axis(ny), axis(nz)) {
        (Some(x), Some(y), Some(z)) => Dims::new(x, y, z).map_err(|e| head.error(e.to_string())),
        _ => Err(head.error(format!(
            "dimensions {nx} x {ny} x {nz} are not all positive"
        ))),
    }
}

/// Length of the GRIDHEAD and FILEHEAD arrays Eclipse writes.
const HEAD_LEN: usize = 100;
/// GRIDHEAD item holding the number of reservoirs (always 1 here).
const GRIDHEAD_NUMRES: usize = 24;

/// Writes `grid` as a standard EGRID: FILEHEAD, MAPUNITS and MAPAXES (when the grid has
/// map axes), GRIDUNIT, GRIDHEAD, COORD (REAL), ZCORN, ACTNUM, ENDGRID.
pub fn write_egrid(grid: &CornerPointGrid, path: &Path) -> Result<()> {
    let mut w = RecordWriter::create(path)?;
    let dims = grid.dims();
    let mut filehead = [0i32; HEAD_LEN];
    // Format version 3, release year, and original grid format 1 (corner point), as
    // resdata writes them.
    filehead[0] = 3;
    filehead[1] = 2007;
    filehead[6] = 1;
    w.inte("FILEHEAD", &filehead)?;
    let units = grid.units.eclipse_name();
    if let Some(m) = &grid.mapaxes {
        w.strings("MAPUNITS", super::RecordKind::Char, &[units])?;
        w.real_from_f64("MAPAXES", &m.values())?;
    }
    w.strings("GRIDUNIT", super::RecordKind::Char, &[units, ""])?;
    let too_big = |n: usize| {
        i32::try_from(n).map_err(|_| {
            Error::model(
                path,
                "GRIDHEAD",
                format!("dimension {n} does not fit an INTE"),
            )
        })
    };
    let mut gridhead = [0i32; HEAD_LEN];
    gridhead[0] = 1;
    gridhead[1] = too_big(dims.nx)?;
    gridhead[2] = too_big(dims.ny)?;
    gridhead[3] = too_big(dims.nz)?;
    gridhead[GRIDHEAD_NUMRES] = 1;
    w.inte("GRIDHEAD", &gridhead)?;
    w.real_from_f64(
        "COORD",
        grid.coord.as_standard_layout().as_slice().unwrap_or(&[]),
    )?;
    w.real(
        "ZCORN",
        grid.zcorn.as_standard_layout().as_slice().unwrap_or(&[]),
    )?;
    w.flags(
        "ACTNUM",
        grid.actnum.as_standard_layout().as_slice().unwrap_or(&[]),
    )?;
    w.inte("ENDGRID", &[])?;
    w.finish()?;
    Ok(())
}
