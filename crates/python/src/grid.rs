//! `_Grid`: a model held in Rust, its arrays lent to numpy without a copy.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};

use numpy::ndarray::{Array3, Array5, ArrayBase, Dimension, OwnedRepr};
use numpy::{Element, IntoPyArray, PyArray, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn};
use pyo3::prelude::*;
use rayon::prelude::*;
use strata::cell::CellInfo;
use strata::engine::Model;
use strata::grid::synth::{SynthParams, generate};
use strata::grid::{CornerPointGrid, Dims, MapAxes};
use strata::scene::ModelSource;

use crate::errors::run;

/// Each grid's number, so that an engine knows whether the grid it holds is the one
/// asked for (two grids may come from one file and differ since).
static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// A report step for Python: number, date (year, month, day) and array names.
type StepInfo = (i32, Option<(i32, u32, u32)>, Vec<String>);

/// A corner-point model in memory. Its arrays are the Rust ones, lent read-only.
#[pyclass(frozen, name = "_Grid", module = "strata._strata")]
pub struct Grid {
    pub(crate) grid: CornerPointGrid,
    pub(crate) source: ModelSource,
    pub(crate) id: u64,
    warnings: Vec<String>,
}

impl Grid {
    fn new(grid: CornerPointGrid, source: ModelSource, warnings: Vec<String>) -> Self {
        Grid {
            grid,
            source,
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            warnings,
        }
    }

    /// The grid as the engine's model, named as it was read (or made).
    pub(crate) fn model(&self) -> (Model, Vec<strata::Note>) {
        Model::from_grid(self.source.clone(), self.grid.clone())
    }
}

/// `array`, owned by `grid`, as a read-only numpy array that keeps `grid` alive.
fn lend<'py, T: Element, D: Dimension>(
    array: &ArrayBase<OwnedRepr<T>, D>,
    grid: &Bound<'py, Grid>,
) -> Bound<'py, PyArray<T, D>> {
    // SAFETY: the container is the frozen grid that owns `array`: nothing mutates or
    // drops the array while the numpy array (whose base it becomes) lives.
    let lent = unsafe { PyArray::borrow_from_array(array, grid.clone().into_any()) };
    if let Ok(writable) = lent.try_readwrite() {
        writable.make_nonwriteable();
    }
    lent
}

/// Values of a numpy array in C order.
fn values<T: Element + Copy>(array: &PyReadonlyArrayDyn<'_, T>) -> Vec<T> {
    match array.as_slice() {
        Ok(slice) => slice.to_vec(),
        Err(_) => array.as_array().iter().copied().collect(),
    }
}

#[pymethods]
impl Grid {
    /// Reads a model as `strata info` does: GRDECL, DATA or EGRID (with its INIT and
    /// restart files), adding the property decks `props`.
    #[staticmethod]
    #[pyo3(signature = (path, props = Vec::new(), grid_only = false))]
    fn open(py: Python<'_>, path: PathBuf, props: Vec<PathBuf>, grid_only: bool) -> PyResult<Self> {
        let source = ModelSource {
            path,
            props,
            grid_only,
        };
        let (model, notes) = run(py, || Model::open(&source))?;
        let warnings = notes.into_iter().map(|n| note_text(&n).1).collect();
        Ok(Grid::new(model.grid, model.source, warnings))
    }

    /// A grid from Eclipse arrays in file order (i fastest): COORD (6 per pillar, map
    /// coordinates), ZCORN, ACTNUM, and per-cell properties over all cells.
    #[staticmethod]
    #[pyo3(signature = (dims, coord, zcorn, actnum, properties, name))]
    fn from_arrays(
        py: Python<'_>,
        dims: (usize, usize, usize),
        coord: PyReadonlyArrayDyn<'_, f64>,
        zcorn: PyReadonlyArrayDyn<'_, f32>,
        actnum: PyReadonlyArrayDyn<'_, bool>,
        properties: HashMap<String, PyReadonlyArrayDyn<'_, f32>>,
        name: String,
    ) -> PyResult<Self> {
        let (coord, zcorn, actnum) = (values(&coord), values(&zcorn), values(&actnum));
        let properties: Vec<(String, Vec<f32>)> = properties
            .into_iter()
            .map(|(n, a)| (n, values(&a)))
            .collect();
        let grid = run(py, move || {
            let dims = Dims::new(dims.0, dims.1, dims.2)?;
            let mut grid = CornerPointGrid::from_arrays(dims, coord, zcorn, Some(actnum))?;
            for (name, values) in properties {
                let got = values.len();
                let array =
                    Array3::from_shape_vec((dims.nz, dims.ny, dims.nx), values).map_err(|_| {
                        strata::Error::scene(format!(
                            "property {name}: {got} values, {} x {} x {} cells need {}",
                            dims.nx,
                            dims.ny,
                            dims.nz,
                            dims.cell_count()
                        ))
                    })?;
                grid.set_property(&name.to_uppercase(), array)?;
            }
            Ok(grid)
        })?;
        Ok(Grid::new(grid, ModelSource::new(name), Vec::new()))
    }

    /// A generated faulted model, as `strata synth` writes it (the same seed gives the
    /// same model).
    #[staticmethod]
    fn synth(
        py: Python<'_>,
        nx: usize,
        ny: usize,
        nz: usize,
        faults: usize,
        seed: u64,
    ) -> PyResult<Self> {
        let params = SynthParams {
            nx,
            ny,
            nz,
            faults,
            seed,
        };
        let grid = run(py, || Ok(generate(&params)?))?;
        let name = format!("synth {nx} x {ny} x {nz}, {faults} faults, seed {seed}");
        Ok(Grid::new(grid, ModelSource::new(name), Vec::new()))
    }

    /// (nx, ny, nz).
    #[getter]
    fn dims(&self) -> (usize, usize, usize) {
        let Dims { nx, ny, nz } = self.grid.dims();
        (nx, ny, nz)
    }

    /// The file read (or the name given), its property decks and whether only the grid
    /// was read.
    #[getter]
    fn source(&self) -> (PathBuf, Vec<PathBuf>, bool) {
        let s = &self.source;
        (s.path.clone(), s.props.clone(), s.grid_only)
    }

    /// What reading skipped or found suspicious, one line each, naming the file.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// Cells the simulation uses.
    #[getter]
    fn active_count(&self) -> usize {
        self.grid.active_count()
    }

    /// Length unit of the coordinates, as Eclipse names it.
    #[getter]
    fn units(&self) -> &'static str {
        self.grid.units.eclipse_name()
    }

    /// MAPAXES (six numbers) when the file had them.
    #[getter]
    fn mapaxes(&self) -> Option<[f64; 6]> {
        self.grid.mapaxes.as_ref().map(MapAxes::values)
    }

    /// COORD, `(ny + 1, nx + 1, 6)`, local coordinates (before MAPAXES), lent.
    fn coord<'py>(slf: &Bound<'py, Self>) -> Bound<'py, PyArray<f64, numpy::Ix3>> {
        lend(&slf.get().grid.coord, slf)
    }

    /// COORD with MAPAXES applied to its points, `(ny + 1, nx + 1, 6)`: a new array
    /// (the file's COORD when it has no MAPAXES, copied).
    fn map_coord<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray<f64, numpy::Ix3>> {
        let mut coord = self.grid.coord.clone();
        for mut pillar in coord.rows_mut() {
            for end in [0, 3] {
                let local = [pillar[end], pillar[end + 1], pillar[end + 2]];
                let [x, y, z] = self.grid.to_map(local);
                (pillar[end], pillar[end + 1], pillar[end + 2]) = (x, y, z);
            }
        }
        coord.into_pyarray(py)
    }

    /// ZCORN, `(2 nz, 2 ny, 2 nx)`, lent.
    fn zcorn<'py>(slf: &Bound<'py, Self>) -> Bound<'py, PyArray<f32, numpy::Ix3>> {
        lend(&slf.get().grid.zcorn, slf)
    }

    /// ACTNUM, `(nz, ny, nx)`, lent.
    fn actnum<'py>(slf: &Bound<'py, Self>) -> Bound<'py, PyArray<bool, numpy::Ix3>> {
        lend(&slf.get().grid.actnum, slf)
    }

    /// Names of the static properties.
    fn property_names(&self) -> Vec<String> {
        self.grid.properties.keys().cloned().collect()
    }

    /// A static property, `(nz, ny, nx)`, NaN where undefined, lent.
    fn property<'py>(
        slf: &Bound<'py, Self>,
        name: &str,
    ) -> Option<Bound<'py, PyArray<f32, numpy::Ix3>>> {
        slf.get().grid.property(name).map(|a| lend(a, slf))
    }

    /// The report steps: (number, (year, month, day) or None, array names).
    fn steps(&self) -> Vec<StepInfo> {
        self.grid
            .report_steps
            .iter()
            .map(|s| (s.number, s.date, s.arrays.keys().cloned().collect()))
            .collect()
    }

    /// Array `name` of the report step at `index` (in file order), lent.
    fn step_array<'py>(
        slf: &Bound<'py, Self>,
        index: usize,
        name: &str,
    ) -> Option<Bound<'py, PyArray<f32, numpy::Ix3>>> {
        let step = slf.get().grid.report_steps.get(index)?;
        step.arrays.get(name).map(|a| lend(a, slf))
    }

    /// Every cell's 8 corners in map coordinates (x, y, depth), `(nx, ny, nz, 8, 3)` in
    /// Eclipse corner order: computed (the file holds pillars and depths, not corners)
    /// into a buffer numpy then owns, without a copy.
    fn corners<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let grid = &self.grid;
        let corners = run(py, || corners(grid))?;
        Ok(corners.into_dyn().into_pyarray(py))
    }

    /// Cell (i, j, k), 1-based, as `strata info --cell --json` gives it.
    fn cell_json(&self, py: Python<'_>, i: usize, j: usize, k: usize) -> PyResult<String> {
        let file = self.source.path.display().to_string();
        let info = run(py, || CellInfo::of(&self.grid, file, [i, j, k]))?;
        serde_json::to_string(&info).map_err(|e| crate::errors::StrataError::new_err(e.to_string()))
    }

    /// Writes the grid and its static properties: EGRID for a `.egrid` name, else GRDECL.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        run(py, || Ok(strata::grid::save(&self.grid, &path)?))
    }
}

/// The corners of every cell, i slowest (numpy's and xtgeo's `(nx, ny, nz)` order).
fn corners(grid: &CornerPointGrid) -> strata::Result<Array5<f64>> {
    let Dims { nx, ny, nz } = grid.dims();
    let per_i = ny * nz * 24;
    let mut out = vec![0.0; nx * per_i];
    out.par_chunks_mut(per_i.max(1))
        .enumerate()
        .for_each(|(i, column)| {
            for (n, cell) in column.chunks_exact_mut(24).enumerate() {
                let (j, k) = (n / nz, n % nz);
                for (c, xyz) in grid.cell_corners(i, j, k).iter().enumerate() {
                    cell[3 * c..3 * c + 3].copy_from_slice(xyz);
                }
            }
        });
    Array5::from_shape_vec((nx, ny, nz, 8, 3), out)
        .map_err(|e| strata::Error::scene(format!("corners: {e}")))
}

/// A note's kind and text.
pub fn note_text(note: &strata::Note) -> (&'static str, String) {
    match note {
        strata::Note::Warning(t) => ("warning", t.clone()),
        strata::Note::Note(t) => ("note", t.clone()),
        strata::Note::Info(t) => ("info", t.clone()),
    }
}
