//! INIT (static properties) and restart files (UNRST, Xnnnn): arrays over active cells
//! mapped onto the grid.

use std::path::Path;

use ndarray::Array3;

use super::record::{RecordKind, RecordView, Records};
use super::writer::RecordWriter;
use crate::{CornerPointGrid, Error, ReportStep, Result, Units};

/// INTEHEAD items (0-based) this module reads and writes.
const IH_UNITS: usize = 2;
const IH_NX: usize = 8;
const IH_NY: usize = 9;
const IH_NZ: usize = 10;
const IH_NACTIVE: usize = 11;
const IH_PHASES: usize = 14;
const IH_DAY: usize = 64;
const IH_MONTH: usize = 65;
const IH_YEAR: usize = 66;
const IH_PROGRAM: usize = 94;
/// Header lengths Eclipse 100 writes; resdata expects at least these.
const INTEHEAD_LEN: usize = 411;
const LOGIHEAD_LEN: usize = 121;
const DOUBHEAD_LEN: usize = 229;

/// Arrays sized by wells, groups, connections, segments, aquifers, tables or regions,
/// not by cells. A model whose active count happens to equal one of those sizes must
/// not take them for cell data.
const NOT_CELL_ARRAYS: &[&str] = &[
    "INTEHEAD", "LOGIHEAD", "DOUBHEAD", "SEQNUM", "TABDIMS", "TAB", "DLYTIM", "REGDIMS", "REGRPT",
    "IGRP", "SGRP", "XGRP", "IWEL", "SWEL", "XWEL", "ICON", "SCON", "XCON", "ISEG", "RSEG", "ILBS",
    "ILBR", "IAAQ", "SAAQ", "XAAQ", "ICAQ", "SCAQ", "ACAQ", "NNC1", "NNC2", "TRANNNC", "CON",
];

/// What INTEHEAD says about the grid and date of a file.
struct Head {
    dims: [i32; 3],
    nactive: i32,
    units: i32,
    date: Option<(i32, u32, u32)>,
}

fn read_head(view: &RecordView<'_>) -> Result<Head> {
    let v = view.to_i32()?;
    if v.len() <= IH_NACTIVE {
        return Err(view.error(format!(
            "{} values, at least {} are needed for the dimensions",
            v.len(),
            IH_NACTIVE + 1
        )));
    }
    let date = match (v.get(IH_YEAR), v.get(IH_MONTH), v.get(IH_DAY)) {
        (Some(&y), Some(&m), Some(&d)) if (1..=12).contains(&m) && (1..=31).contains(&d) => {
            Some((y, m as u32, d as u32))
        }
        _ => None,
    };
    Ok(Head {
        dims: [v[IH_NX], v[IH_NY], v[IH_NZ]],
        nactive: v[IH_NACTIVE],
        units: v[IH_UNITS],
        date,
    })
}

/// Refuses a file written for another grid: its arrays would map onto the wrong cells.
fn check_head(grid: &CornerPointGrid, path: &Path, head: &Head, nactive: usize) -> Result<()> {
    let d = grid.dims();
    let same_dims = [d.nx, d.ny, d.nz]
        .iter()
        .zip(head.dims)
        .all(|(&g, h)| usize::try_from(h) == Ok(g));
    if same_dims_but_z(d, head.dims) {
        return Err(Error::model(
            path,
            "INTEHEAD",
            format!(
                "a dual-porosity file ({} layers for the grid's {}: matrix then fracture), not read",
                head.dims[2], d.nz
            ),
        ));
    }
    if !same_dims || usize::try_from(head.nactive) != Ok(nactive) {
        let [x, y, z] = head.dims;
        return Err(Error::model(
            path,
            "INTEHEAD",
            format!(
                "written for a {x} x {y} x {z} grid with {} active cells, the grid is {} x {} x {} with {nactive}",
                head.nactive, d.nx, d.ny, d.nz
            ),
        ));
    }
    Ok(())
}

/// Whether INTEHEAD has the grid's nx and ny and twice its nz: dual porosity.
fn same_dims_but_z(d: crate::Dims, dims: [i32; 3]) -> bool {
    usize::try_from(dims[0]) == Ok(d.nx)
        && usize::try_from(dims[1]) == Ok(d.ny)
        && usize::try_from(dims[2]) == Ok(2 * d.nz)
}

fn unit_system(units: Units) -> i32 {
    match units {
        Units::Metres => 1,
        Units::Feet => 2,
        Units::Centimetres => 3,
    }
}

/// A numeric array of one value per active cell that is not one of the
/// [`NOT_CELL_ARRAYS`].
fn is_cell_array(view: &RecordView<'_>, nactive: usize, kinds: &[RecordKind]) -> bool {
    nactive > 0
        && view.len() == nactive
        && kinds.contains(&view.kind())
        && !NOT_CELL_ARRAYS.contains(&view.name())
}

/// Spreads a result array over `cells` onto all cells (NaN elsewhere).
fn expand(cells: &Array3<bool>, view: &RecordView<'_>) -> Result<Array3<f32>> {
    let values = view.to_f32()?;
    crate::grid::expand_over(cells, &values)
        .ok_or_else(|| view.error("does not hold one value per active cell"))
}

/// Tracks LGR ... ENDLGR blocks, whose arrays belong to local grids, not the main one.
#[derive(Default)]
struct LgrSkip {
    inside: bool,
}

impl LgrSkip {
    /// True when `name` is an LGR delimiter or lies inside an LGR block.
    fn skips(&mut self, name: &str) -> bool {
        match name {
            "LGR" => self.inside = true,
            "ENDLGR" => self.inside = false,
            _ => return self.inside,
        }
        true
    }
}

/// Reads the static properties of an INIT held in memory into `grid`: PORV over all
/// cells, every other INTE/REAL/DOUB array of one value per active cell mapped onto
/// the cells. Nothing in `grid` changes unless the whole file reads.
pub fn parse_init_bytes(grid: &mut CornerPointGrid, path: &Path, bytes: &[u8]) -> Result<()> {
    init_from_records(grid, path, Records::new(path, bytes))
}

/// [`parse_init_bytes`] over the keywords `records` walks.
pub(crate) fn init_from_records(
    grid: &mut CornerPointGrid,
    path: &Path,
    records: Records<'_>,
) -> Result<()> {
    let ncells = grid.cell_count();
    let numeric = [RecordKind::Inte, RecordKind::Real, RecordKind::Doub];
    let mut head = None;
    let mut porv = None;
    let mut arrays = Vec::new();
    let mut lgr = LgrSkip::default();
    for view in records {
        let view = view?;
        if lgr.skips(view.name()) {
            continue;
        }
        match view.name() {
            "INTEHEAD" if head.is_none() => head = Some(read_head(&view)?),
            "PORV" if view.len() == ncells && numeric.contains(&view.kind()) => {
                porv = Some(view);
            }
            name if numeric.contains(&view.kind()) && !NOT_CELL_ARRAYS.contains(&name) => {
                arrays.push(view);
            }
            _ => {}
        }
    }
    let Some(head) = head else {
        return Err(Error::model(
            path,
            "INTEHEAD",
            "no INTEHEAD, so nothing says which grid the arrays belong to",
        ));
    };
    // On a first INIT whose active count differs from ACTNUM, map through PORV.
    let mapped = match grid.result_cells {
        None => super::active::result_cells(grid, head.nactive, porv.as_ref())?,
        Some(_) => None,
    };
    let cells = mapped
        .as_ref()
        .or(grid.result_cells.as_ref())
        .unwrap_or(&grid.actnum);
    let nres = cells.iter().filter(|&&c| c).count();
    check_head(grid, path, &head, nres)?;
    let mut props = Vec::new();
    if let Some(view) = porv {
        let d = grid.dims();
        let values = Array3::from_shape_vec((d.nz, d.ny, d.nx), view.to_f32()?)
            .map_err(|e| view.error(e.to_string()))?;
        props.push(("PORV".to_string(), values));
    }
    for view in arrays
        .iter()
        .filter(|v| nres > 0 && v.len() == nres && v.name() != "PORV")
    {
        props.push((view.name().to_string(), expand(cells, view)?));
    }
    if head.units != unit_system(grid.units) {
        grid.warnings.push(format!(
            "{}: INTEHEAD unit system {} differs from the grid's {}; coordinates keep the grid's",
            path.display(),
            head.units,
            grid.units.eclipse_name()
        ));
    }
    for (name, values) in props {
        grid.set_property(&name, values)?;
    }
    if let Some(cells) = mapped {
        grid.warnings
            .push(super::active::mapped_warning(grid, path, &cells));
        grid.result_cells = Some(cells);
    }
    Ok(())
}

/// Report steps of a restart file held in memory: a step begins at each SEQNUM; its
/// date comes from INTEHEAD; every REAL/DOUB array of one value per active cell is a
/// solution array. Arrays before any SEQNUM (a non-unified file may have none) form a
/// step numbered `fallback`, or by position when that is `None`.
fn restart_steps(
    grid: &CornerPointGrid,
    path: &Path,
    records: Records<'_>,
    fallback: Option<i32>,
) -> Result<Vec<ReportStep>> {
    let nactive = grid.result_count();
    let solution = [RecordKind::Real, RecordKind::Doub];
    let mut steps: Vec<ReportStep> = Vec::new();
    let mut current: Option<ReportStep> = None;
    let mut lgr = LgrSkip::default();
    let implicit = |steps: &[ReportStep]| ReportStep {
        number: fallback.unwrap_or(steps.len() as i32),
        ..ReportStep::default()
    };
    for view in records {
        let view = view?;
        if lgr.skips(view.name()) {
            continue;
        }
        match view.name() {
            "SEQNUM" => {
                let number = *view
                    .to_i32()?
                    .first()
                    .ok_or_else(|| view.error("holds no report number"))?;
                steps.extend(current.take());
                current = Some(ReportStep {
                    number,
                    ..ReportStep::default()
                });
            }
            "INTEHEAD" => {
                let h = read_head(&view)?;
                check_head(grid, path, &h, nactive)?;
                current.get_or_insert_with(|| implicit(&steps)).date = h.date;
            }
            name if is_cell_array(&view, nactive, &solution) => {
                let values = expand(grid.result_cells.as_ref().unwrap_or(&grid.actnum), &view)?;
                current
                    .get_or_insert_with(|| implicit(&steps))
                    .arrays
                    .insert(name.to_string(), values);
            }
            _ => {}
        }
    }
    steps.extend(current);
    Ok(steps)
}

/// The report number a non-unified restart's extension gives (`X0012` -> 12), or
/// `None` when the extension is not `Xnnnn`.
pub(crate) fn xnnnn_number(path: &Path) -> Option<i32> {
    let ext = path.extension()?.to_str()?;
    let digits = ext.strip_prefix(['X', 'x', 'F', 'f'])?;
    (digits.len() == 4 && digits.bytes().all(|b| b.is_ascii_digit()))
        .then(|| digits.parse().ok())
        .flatten()
}

/// Appends the report steps of a restart file held in memory to `grid`. `path` names
/// it in errors and, for a non-unified `Xnnnn` file without SEQNUM, gives the report
/// number. Nothing in `grid` changes unless the whole file reads.
pub fn parse_restart_bytes(grid: &mut CornerPointGrid, path: &Path, bytes: &[u8]) -> Result<()> {
    restart_from_records(grid, path, Records::new(path, bytes))
}

/// [`parse_restart_bytes`] over the keywords `records` walks.
pub(crate) fn restart_from_records(
    grid: &mut CornerPointGrid,
    path: &Path,
    records: Records<'_>,
) -> Result<()> {
    let steps = restart_steps(grid, path, records, xnnnn_number(path))?;
    grid.report_steps.extend(steps);
    Ok(())
}

/// The values of `values` at the active cells, in cell order.
fn active_values(grid: &CornerPointGrid, values: &Array3<f32>) -> Vec<f32> {
    values
        .iter()
        .zip(grid.actnum.iter())
        .filter_map(|(&v, &a)| a.then_some(v))
        .collect()
}

/// INTEHEAD for `grid` with `date`; unknown dates are written as zeros, which read
/// back as no date.
fn intehead(
    grid: &CornerPointGrid,
    path: &Path,
    date: Option<(i32, u32, u32)>,
) -> Result<Vec<i32>> {
    let d = grid.dims();
    let int = |n: usize| {
        i32::try_from(n)
            .map_err(|_| Error::model(path, "INTEHEAD", format!("{n} does not fit an INTE")))
    };
    let mut h = vec![0; INTEHEAD_LEN];
    h[IH_UNITS] = unit_system(grid.units);
    h[IH_NX] = int(d.nx)?;
    h[IH_NY] = int(d.ny)?;
    h[IH_NZ] = int(d.nz)?;
    h[IH_NACTIVE] = int(grid.active_count())?;
    // Oil, water and gas, and "Eclipse 100" as the writing program: the values
    // resdata needs to classify the file.
    h[IH_PHASES] = 7;
    h[IH_PROGRAM] = 100;
    if let Some((y, m, day)) = date {
        h[IH_YEAR] = y;
        h[IH_MONTH] = m as i32;
        h[IH_DAY] = day as i32;
    }
    Ok(h)
}

fn write_heads(
    w: &mut RecordWriter<impl std::io::Write>,
    grid: &CornerPointGrid,
    path: &Path,
    date: Option<(i32, u32, u32)>,
) -> Result<()> {
    w.inte("INTEHEAD", &intehead(grid, path, date)?)?;
    w.logi("LOGIHEAD", &[false; LOGIHEAD_LEN])?;
    w.doub("DOUBHEAD", &[0.0; DOUBHEAD_LEN])
}

/// Writes the static properties of `grid` as an INIT: INTEHEAD (dims, active count,
/// unit system, the first report date when there is one), LOGIHEAD, DOUBHEAD, PORV
/// over all cells when the grid has it (pore volumes are not invented here; NaN is
/// written as 0), then every other property over the active cells as REAL.
pub fn write_init(grid: &CornerPointGrid, path: &Path) -> Result<()> {
    let mut w = RecordWriter::create(path)?;
    let date = grid.report_steps.first().and_then(|s| s.date);
    write_heads(&mut w, grid, path, date)?;
    if let Some(porv) = grid.properties.get("PORV") {
        let all: Vec<f32> = porv
            .iter()
            .map(|&v| if v.is_nan() { 0.0 } else { v })
            .collect();
        w.real("PORV", &all)?;
    }
    for (name, values) in grid.properties.iter().filter(|(n, _)| *n != "PORV") {
        w.real(name, &active_values(grid, values))?;
    }
    w.finish()?;
    Ok(())
}

/// Writes the report steps of `grid` as a unified restart: per step SEQNUM, INTEHEAD
/// with its date, LOGIHEAD, DOUBHEAD, then its arrays over the active cells as REAL
/// between STARTSOL and ENDSOL.
pub fn write_unrst(grid: &CornerPointGrid, path: &Path) -> Result<()> {
    let mut w = RecordWriter::create(path)?;
    for step in &grid.report_steps {
        w.inte("SEQNUM", &[step.number])?;
        write_heads(&mut w, grid, path, step.date)?;
        w.mess("STARTSOL")?;
        for (name, values) in &step.arrays {
            w.real(name, &active_values(grid, values))?;
        }
        w.mess("ENDSOL")?;
    }
    w.finish()?;
    Ok(())
}
