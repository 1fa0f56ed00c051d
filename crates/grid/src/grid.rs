//! The corner-point grid: pillars (COORD), corner depths (ZCORN), activity (ACTNUM),
//! map axes, units, per-cell properties and simulation report steps.
//!
//! Conventions, decided here once:
//! * cells are indexed `(i, j, k)` from 0, `i` fastest, as in the files; the command line
//!   speaks 1-based `I,J,K` and converts at its edge;
//! * depths are positive downward in the model (as in ZCORN); the display frame used by
//!   meshes is map x, map y and *elevation* = -depth, see [`CornerPointGrid::to_display`];
//! * the 8 corners of a cell are numbered as in Eclipse: `c = di + 2 dj + 4 dk` with
//!   `di, dj` in {0, 1} the pillar offsets and `dk = 0` the top, `dk = 1` the bottom face.

use std::collections::BTreeMap;

use ndarray::{Array3, s};
use rayon::prelude::*;
use serde::Serialize;

use crate::{Error, Result};

/// Dimensions of a grid in cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Dims {
    /// Cells along `i` (columns of a row, the fastest index in files).
    pub nx: usize,
    /// Cells along `j` (rows of a layer).
    pub ny: usize,
    /// Cells along `k` (layers, counted downward from the top).
    pub nz: usize,
}

impl Dims {
    /// Checked dimensions: each axis at least 1, and the number of corner depths
    /// (8 per cell) representable without overflow.
    pub fn new(nx: usize, ny: usize, nz: usize) -> Result<Self> {
        let d = Dims { nx, ny, nz };
        if nx == 0 || ny == 0 || nz == 0 {
            return Err(Error::Invalid(format!(
                "dimensions {nx} x {ny} x {nz} have a zero axis"
            )));
        }
        d.zcorn_len()
            .ok_or_else(|| Error::Invalid(format!("dimensions {nx} x {ny} x {nz} overflow")))?;
        Ok(d)
    }

    /// Number of cells, `None` on overflow.
    pub fn cell_count_checked(&self) -> Option<usize> {
        self.nx.checked_mul(self.ny)?.checked_mul(self.nz)
    }

    /// Number of cells (valid dims never overflow).
    pub fn cell_count(&self) -> usize {
        self.nx * self.ny * self.nz
    }

    /// Number of ZCORN values, `None` on overflow.
    pub fn zcorn_len(&self) -> Option<usize> {
        self.cell_count_checked()?.checked_mul(8)
    }

    /// Number of COORD values, `None` on overflow.
    pub fn coord_len(&self) -> Option<usize> {
        (self.nx.checked_add(1)?)
            .checked_mul(self.ny.checked_add(1)?)?
            .checked_mul(6)
    }

    /// Linear cell index, `i` fastest.
    pub fn cell_index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.nx * (j + self.ny * k)
    }

    /// Inverse of [`Dims::cell_index`].
    pub fn cell_ijk(&self, index: usize) -> (usize, usize, usize) {
        (
            index % self.nx,
            (index / self.nx) % self.ny,
            index / (self.nx * self.ny),
        )
    }
}

/// Length unit of the grid coordinates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    /// `METRES`, the default when a file names no unit.
    #[default]
    Metres,
    /// `FEET` (also read from `FT` and `FIELD`).
    Feet,
    /// `CM` (also read from `CENTIMETRES`).
    Centimetres,
}

impl Units {
    /// Parses the Eclipse spellings (`METRES`, `FEET`, `CM`, and common variants).
    pub fn parse(word: &str) -> Option<Self> {
        match word.trim().to_ascii_uppercase().as_str() {
            "METRES" | "METERS" | "M" | "METRIC" => Some(Units::Metres),
            "FEET" | "FT" | "FIELD" => Some(Units::Feet),
            "CM" | "CENTIMETRES" | "CENTIMETERS" => Some(Units::Centimetres),
            _ => None,
        }
    }

    /// The Eclipse keyword spelling.
    pub fn eclipse_name(&self) -> &'static str {
        match self {
            Units::Metres => "METRES",
            Units::Feet => "FEET",
            Units::Centimetres => "CM",
        }
    }
}

/// MAPAXES: three points in map coordinates, a point on the local y axis, the local
/// origin and a point on the local x axis, in the order of the keyword.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MapAxes {
    /// A point on the local y axis (map x, map y).
    pub y_axis: [f64; 2],
    /// Where the local origin lies on the map.
    pub origin: [f64; 2],
    /// A point on the local x axis (map x, map y).
    pub x_axis: [f64; 2],
}

impl MapAxes {
    /// From the six numbers of the keyword, in file order.
    pub fn from_values(v: [f64; 6]) -> Self {
        MapAxes {
            y_axis: [v[0], v[1]],
            origin: [v[2], v[3]],
            x_axis: [v[4], v[5]],
        }
    }

    /// The six numbers of the keyword, in file order.
    pub fn values(&self) -> [f64; 6] {
        [
            self.y_axis[0],
            self.y_axis[1],
            self.origin[0],
            self.origin[1],
            self.x_axis[0],
            self.x_axis[1],
        ]
    }

    /// Unit vectors of the local x and y axes in map coordinates; `None` when the
    /// axes are degenerate (coincident points).
    fn unit_axes(&self) -> Option<([f64; 2], [f64; 2])> {
        let unit = |p: [f64; 2]| {
            let d = [p[0] - self.origin[0], p[1] - self.origin[1]];
            let n = d[0].hypot(d[1]);
            (n > 0.0 && n.is_finite()).then(|| [d[0] / n, d[1] / n])
        };
        Some((unit(self.x_axis)?, unit(self.y_axis)?))
    }

    /// Transforms local grid (x, y) to map coordinates, as `resdata` and `xtgeo` do:
    /// `origin + x * ux + y * uy` with `ux`, `uy` the unit axes.
    pub fn to_map(&self, x: f64, y: f64) -> [f64; 2] {
        match self.unit_axes() {
            Some((ux, uy)) => [
                self.origin[0] + x * ux[0] + y * uy[0],
                self.origin[1] + x * ux[1] + y * uy[1],
            ],
            None => [x, y],
        }
    }
}

/// One report step of a simulation restart (UNRST or Xnnnn).
#[derive(Clone, Debug, Default)]
pub struct ReportStep {
    /// Report number (SEQNUM).
    pub number: i32,
    /// Simulation date (year, month, day) from INTEHEAD, when present.
    pub date: Option<(i32, u32, u32)>,
    /// Solution arrays (PRESSURE, SWAT, SGAS, ...) over all cells; inactive cells are NaN.
    pub arrays: BTreeMap<String, Array3<f32>>,
}

/// Spreads `values` over the cells `mask` holds, NaN elsewhere; `None` unless there is
/// exactly one value per such cell.
pub(crate) fn expand_over(mask: &Array3<bool>, values: &[f32]) -> Option<Array3<f32>> {
    let mut it = values.iter();
    let full: Vec<f32> = mask
        .iter()
        .map(|&a| {
            if a {
                it.next().copied()
            } else {
                Some(f32::NAN)
            }
        })
        .collect::<Option<_>>()?;
    if it.next().is_some() {
        return None;
    }
    Array3::from_shape_vec(mask.raw_dim(), full).ok()
}

/// A corner-point grid with its properties.
///
/// Arrays use `ndarray` in file order (`i` fastest, so the last axis is `i`):
/// * `coord`: `[ny + 1, nx + 1, 6]`, per pillar top xyz then bottom xyz, local coordinates;
/// * `zcorn`: `[2 nz, 2 ny, 2 nx]` corner depths;
/// * `actnum`: `[nz, ny, nx]`;
/// * properties and report arrays: `[nz, ny, nx]`, NaN where a value is not defined.
#[derive(Clone, Debug)]
pub struct CornerPointGrid {
    dims: Dims,
    /// Pillars, `[ny + 1, nx + 1, 6]`: top xyz then bottom xyz in local coordinates
    /// (before [`MapAxes`]), depth positive downward.
    pub coord: Array3<f64>,
    /// Corner depths, `[2 nz, 2 ny, 2 nx]`, positive downward: a corner's position is
    /// where its pillar reaches this depth. Neighbours that disagree here are faulted.
    pub zcorn: Array3<f32>,
    /// Whether each cell takes part in the model, `[nz, ny, nx]`; inactive cells
    /// leave holes in surfaces, and INIT/restart arrays skip them.
    pub actnum: Array3<bool>,
    /// How local coordinates map onto the map; `None` when they already are map
    /// coordinates.
    pub mapaxes: Option<MapAxes>,
    /// Length unit of COORD and ZCORN.
    pub units: Units,
    /// Per-cell static properties (PORO, PERMX, NTG, ...), keyword upper case.
    pub properties: BTreeMap<String, Array3<f32>>,
    /// Code names of discrete properties, by property name: code -> name (a ROFF
    /// facies' `1 -> "Channel"`), for a categorical legend. A property listed here is
    /// discrete even when its map is empty; one not listed is continuous.
    pub codes: BTreeMap<String, BTreeMap<i32, String>>,
    /// One zone name per layer, top first, where the file divides layers into zones
    /// (ROFF subgrids, named `subgrid_0`, ... as xtgeo names them); empty otherwise.
    pub zones: Vec<String>,
    /// The cells INIT and restart arrays hold values for, where that is not ACTNUM:
    /// Intersect leaves out active cells without pore volume, and its results are
    /// mapped through PORV > 0 as xtgeo maps them. `None`: the active cells.
    pub result_cells: Option<Array3<bool>>,
    /// Report steps of a simulation, in file order.
    pub report_steps: Vec<ReportStep>,
    /// What a reader skipped and the user should know (a missing INCLUDE read with
    /// `grid_only`, an ignored keyword section, ...), one line each, naming the file.
    pub warnings: Vec<String>,
}

impl CornerPointGrid {
    /// Builds a grid from flat arrays in file order, checking their lengths and that
    /// every pillar coordinate and corner depth is finite.
    pub fn from_arrays(
        dims: Dims,
        coord: Vec<f64>,
        zcorn: Vec<f32>,
        actnum: Option<Vec<bool>>,
    ) -> Result<Self> {
        let Dims { nx, ny, nz } = dims;
        let expect = |name: &str, got: usize, want: Option<usize>| -> Result<usize> {
            let want = want.ok_or_else(|| Error::Invalid(format!("{name}: size overflows")))?;
            if got != want {
                return Err(Error::Invalid(format!(
                    "{name} has {got} values, {nx} x {ny} x {nz} needs {want}"
                )));
            }
            Ok(want)
        };
        expect("COORD", coord.len(), dims.coord_len())?;
        expect("ZCORN", zcorn.len(), dims.zcorn_len())?;
        if let Some(bad) = coord.iter().position(|v| !v.is_finite()) {
            return Err(Error::Invalid(format!(
                "COORD value {} (pillar {}) is not a finite number",
                bad + 1,
                bad / 6 + 1
            )));
        }
        // Chunked: a per-element parallel search was measured many times slower when
        // the cores are busy (docs/performance.md, "Reading and writing models").
        const CHUNK: usize = 1 << 16;
        if let Some(chunk) = zcorn
            .par_chunks(CHUNK)
            .position_first(|c| !c.iter().all(|v| v.is_finite()))
        {
            let bad = chunk * CHUNK
                + zcorn[chunk * CHUNK..]
                    .iter()
                    .position(|v| !v.is_finite())
                    .unwrap_or(0);
            return Err(Error::Invalid(format!(
                "ZCORN value {} is not a finite number",
                bad + 1
            )));
        }
        let actnum = match actnum {
            Some(a) => {
                expect("ACTNUM", a.len(), dims.cell_count_checked())?;
                a
            }
            None => vec![true; dims.cell_count()],
        };
        let shape_err = |e: ndarray::ShapeError| Error::Invalid(e.to_string());
        Ok(CornerPointGrid {
            dims,
            coord: Array3::from_shape_vec((ny + 1, nx + 1, 6), coord).map_err(shape_err)?,
            zcorn: Array3::from_shape_vec((2 * nz, 2 * ny, 2 * nx), zcorn).map_err(shape_err)?,
            actnum: Array3::from_shape_vec((nz, ny, nx), actnum).map_err(shape_err)?,
            mapaxes: None,
            units: Units::default(),
            properties: BTreeMap::new(),
            codes: BTreeMap::new(),
            zones: Vec::new(),
            result_cells: None,
            report_steps: Vec::new(),
            warnings: Vec::new(),
        })
    }

    /// The dimensions the arrays were checked against when the grid was built.
    pub fn dims(&self) -> Dims {
        self.dims
    }

    /// Number of cells, active or not: the length of a GRDECL property.
    pub fn cell_count(&self) -> usize {
        self.dims.cell_count()
    }

    /// Whether cell `(i, j, k)` (0-based) is active; panics outside the grid.
    pub fn is_active(&self, i: usize, j: usize, k: usize) -> bool {
        self.actnum[[k, j, i]]
    }

    /// Number of active cells: the length of an INIT or restart array.
    pub fn active_count(&self) -> usize {
        self.actnum
            .as_slice()
            .map(|a| a.par_iter().filter(|&&b| b).count())
            .unwrap_or_else(|| self.actnum.iter().filter(|&&b| b).count())
    }

    /// The active cells in rows `rows` (j) of layer `k`.
    pub fn active_count_in(&self, k: usize, rows: std::ops::Range<usize>) -> usize {
        self.actnum
            .slice(s![k, rows, ..])
            .iter()
            .filter(|&&a| a)
            .count()
    }

    /// For every cell (linear index, `i` fastest) its index among the active cells,
    /// or `None` when inactive. This is how INIT and restart arrays map onto cells.
    pub fn active_index(&self) -> Vec<Option<u32>> {
        let mut next = 0u32;
        self.actnum
            .iter()
            .map(|&a| {
                a.then(|| {
                    next += 1;
                    next - 1
                })
            })
            .collect()
    }

    /// Spreads an array over active cells onto all cells, NaN for inactive ones.
    /// Returns `None` when `values` does not hold exactly one value per active cell.
    pub fn expand_active(&self, values: &[f32]) -> Option<Array3<f32>> {
        expand_over(&self.actnum, values)
    }

    /// The number of cells result arrays hold values for ([`Self::result_cells`]).
    pub fn result_count(&self) -> usize {
        match &self.result_cells {
            Some(cells) => cells.iter().filter(|&&c| c).count(),
            None => self.active_count(),
        }
    }

    /// Pillar `(pi, pj)` (0..=nx, 0..=ny) as top and bottom points, local coordinates.
    /// Read by index rather than as a slice view: every corner of every surface comes
    /// through here, and making a view cost more than the arithmetic.
    pub fn pillar(&self, pi: usize, pj: usize) -> [f64; 6] {
        std::array::from_fn(|n| self.coord[[pj, pi, n]])
    }

    /// Depth of corner `c` (Eclipse numbering, see module docs) of cell `(i, j, k)`.
    pub fn corner_depth(&self, i: usize, j: usize, k: usize, c: usize) -> f32 {
        let (di, dj, dk) = (c & 1, (c >> 1) & 1, (c >> 2) & 1);
        self.zcorn[[2 * k + dk, 2 * j + dj, 2 * i + di]]
    }

    /// Local (x, y, depth) of the point at `depth` on pillar `(pi, pj)`.
    pub fn point_on_pillar(&self, pi: usize, pj: usize, depth: f64) -> [f64; 3] {
        let p = self.pillar(pi, pj);
        let dz = p[5] - p[2];
        let t = if dz.abs() > f64::EPSILON * p[2].abs().max(1.0) {
            (depth - p[2]) / dz
        } else {
            0.0
        };
        [p[0] + t * (p[3] - p[0]), p[1] + t * (p[4] - p[1]), depth]
    }

    /// Local (x, y, depth) of corner `c` of cell `(i, j, k)`, before MAPAXES.
    pub fn corner_local(&self, i: usize, j: usize, k: usize, c: usize) -> [f64; 3] {
        let depth = f64::from(self.corner_depth(i, j, k, c));
        self.point_on_pillar(i + (c & 1), j + ((c >> 1) & 1), depth)
    }

    /// Map (x, y, depth) of a local point: MAPAXES applied when present.
    pub fn to_map(&self, local: [f64; 3]) -> [f64; 3] {
        match &self.mapaxes {
            Some(m) => {
                let [x, y] = m.to_map(local[0], local[1]);
                [x, y, local[2]]
            }
            None => local,
        }
    }

    /// The 8 corners of cell `(i, j, k)` in map coordinates (x, y, depth), in Eclipse
    /// order (see module docs).
    pub fn cell_corners(&self, i: usize, j: usize, k: usize) -> [[f64; 3]; 8] {
        std::array::from_fn(|c| self.to_map(self.corner_local(i, j, k, c)))
    }

    /// The display frame used by every mesh: map x and y, elevation = -depth, all
    /// relative to `origin` (itself map x, map y, elevation) to keep `f32` precise.
    pub fn to_display(origin: [f64; 3], map: [f64; 3]) -> [f32; 3] {
        [
            (map[0] - origin[0]) as f32,
            (map[1] - origin[1]) as f32,
            (-map[2] - origin[2]) as f32,
        ]
    }

    /// A display origin for this grid: the centre of its [`Self::view_box`] in display
    /// coordinates (map x, map y, elevation). Not the bounding box's: a stray depth
    /// of 1e11 m would move it 5e10 m off the model, where `f32` steps are kilometres.
    pub fn display_origin(&self) -> [f64; 3] {
        self.view_box().display_centre()
    }

    /// Bounding box of the corners of the active cells (all cells when none is
    /// active), in map coordinates (x, y, depth).
    ///
    /// A corner lies on its pillar, along which x and y move monotonically with
    /// depth, so the box is that of each pillar's shallowest and deepest corner: a
    /// pass over the depths, and two points a pillar. Each rounded step of
    /// [`Self::point_on_pillar`] is monotonic, so without MAPAXES the box is exactly
    /// the corners'; a rotation adds x and y, whose sum may differ by a rounding.
    pub fn bounding_box(&self) -> BoundingBox {
        let any_active = self.actnum.iter().any(|&a| a);
        (0..=self.dims.ny)
            .into_par_iter()
            .map(|pj| {
                let mut b = BoundingBox::empty();
                for (pi, (lo, hi)) in self
                    .pillar_row_depths(pj, any_active)
                    .into_iter()
                    .enumerate()
                {
                    for z in [lo, hi].into_iter().filter(|z| z.is_finite()) {
                        b.include(self.to_map(self.point_on_pillar(pi, pj, f64::from(z))));
                    }
                }
                b
            })
            .reduce(BoundingBox::empty, |a, b| a.union(&b))
    }

    /// The shallowest and deepest corner depth on each pillar of row `pj` over the
    /// active cells (over all cells when `any_active` is false); infinite where no
    /// such cell touches the pillar.
    fn pillar_row_depths(&self, pj: usize, any_active: bool) -> Vec<(f32, f32)> {
        let Dims { nx, ny, nz } = self.dims;
        let mut depths = vec![(f32::INFINITY, f32::NEG_INFINITY); nx + 1];
        // The cells on either side of the row of pillars.
        let rows = pj.saturating_sub(1)..(pj + 1).min(ny);
        for k in 0..nz {
            for j in rows.clone() {
                let dj = pj - j;
                for i in (0..nx).filter(|&i| !any_active || self.actnum[[k, j, i]]) {
                    for (di, dk) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                        let z = self.zcorn[[2 * k + dk, 2 * j + dj, 2 * i + di]];
                        let (lo, hi) = &mut depths[i + di];
                        (*lo, *hi) = (lo.min(z), hi.max(z));
                    }
                }
            }
        }
        depths
    }

    /// Corners of the active cells that lie far outside where the rest of the model
    /// does, `None` when there are none: a stray depth or pillar coordinate stretches
    /// the extent every view frames until the model is a speck in it.
    ///
    /// Looked for among the points [`Self::bounding_box`] is made of, each pillar's
    /// shallowest and deepest corner: a point is stray when, along x, y or depth, it
    /// lies more than [`STRAY_SPREADS`] interquartile ranges of those points beyond
    /// their quartiles. An axis whose points are mostly one value (an interquartile
    /// range of 0) is not judged. The quartiles come from at most
    /// [`STRAY_QUARTILE_SAMPLES`] points evenly spread over the pillars, and only the
    /// pillars' two depths are held (8 bytes a pillar, against ZCORN's 32 a cell).
    pub fn stray_corners(&self) -> Option<StrayCorners> {
        self.stray_corners_sampling(STRAY_QUARTILE_SAMPLES).1
    }

    /// The box views frame: that of the corners of the active cells but the stray
    /// ones ([`Self::stray_corners`]), so that a few corrupt values leave the rest of
    /// the model in view; [`Self::bounding_box`] when there are none.
    pub fn view_box(&self) -> BoundingBox {
        self.view_box_and_stray_corners().0
    }

    /// [`Self::view_box`] and [`Self::stray_corners`] from one pass, for a caller that
    /// needs both.
    pub fn view_box_and_stray_corners(&self) -> (BoundingBox, Option<StrayCorners>) {
        self.stray_corners_sampling(STRAY_QUARTILE_SAMPLES)
    }

    /// [`Self::view_box`] and [`Self::stray_corners`], the quartiles from at most
    /// `samples` points.
    fn stray_corners_sampling(&self, samples: usize) -> (BoundingBox, Option<StrayCorners>) {
        let any_active = self.actnum.iter().any(|&a| a);
        let nx = self.dims.nx;
        let rows: Vec<Vec<(f32, f32)>> = (0..=self.dims.ny)
            .into_par_iter()
            .map(|pj| self.pillar_row_depths(pj, any_active))
            .collect();
        let end =
            |pi: usize, pj: usize, z: f32| self.to_map(self.point_on_pillar(pi, pj, f64::from(z)));
        let pillars = rows.len() * (nx + 1);
        let stride = pillars.div_ceil((samples / 2).max(1));
        let sampled: Vec<[f64; 3]> = (0..pillars)
            .step_by(stride)
            .flat_map(|n| {
                let (pi, pj) = (n % (nx + 1), n / (nx + 1));
                let (lo, hi) = rows[pj][pi];
                [lo, hi]
                    .into_iter()
                    .filter(|z| z.is_finite())
                    .map(move |z| end(pi, pj, z))
            })
            .collect();
        let limits: [Option<[f64; 3]>; 3] = std::array::from_fn(|axis| {
            let mut values: Vec<f64> = sampled.iter().map(|p| p[axis]).collect();
            let q1 = quantile(&mut values, 0.25)?;
            let q3 = quantile(&mut values, 0.75)?;
            let spread = q3 - q1;
            (spread > 0.0).then_some([
                q1 - STRAY_SPREADS * spread,
                q3 + STRAY_SPREADS * spread,
                spread,
            ])
        });
        // How many interquartile ranges past its limits a point lies, over the axes.
        let excess = |p: &[f64; 3]| {
            (0..3)
                .filter_map(|axis| {
                    let [lo, hi, spread] = limits[axis]?;
                    Some(((lo - p[axis]).max(p[axis] - hi) / spread).max(0.0))
                })
                .fold(0.0, f64::max)
        };
        let found = rows
            .par_iter()
            .enumerate()
            .map(|(pj, row)| {
                let mut found = Strays::default();
                for (pi, &(lo, hi)) in row.iter().enumerate() {
                    let mut stray = false;
                    for z in [lo, hi].into_iter().filter(|z| z.is_finite()) {
                        let map = end(pi, pj, z);
                        let e = excess(&map);
                        if e > 0.0 {
                            stray = true;
                            if found.worst.is_none_or(|(w, ..)| e > w) {
                                found.worst = Some((e, [pi, pj], z, map));
                            }
                        } else {
                            found.rest.include(map);
                        }
                    }
                    found.pillars += usize::from(stray);
                }
                found
            })
            .reduce(Strays::default, Strays::merge);
        let stray = found.worst.and_then(|(_, pillar, depth, map)| {
            let [i, j, k, corner] = self.cell_at_pillar_depth(pillar, depth, any_active)?;
            Some(StrayCorners {
                pillars: found.pillars,
                worst: StrayCorner {
                    pillar,
                    cell: [i, j, k],
                    corner,
                    map,
                },
                rest: found.rest,
            })
        });
        (found.rest, stray)
    }

    /// An active cell (any cell when `any_active` is false) with a corner at `depth`
    /// on `pillar`, as `[i, j, k, corner]`.
    fn cell_at_pillar_depth(
        &self,
        [pi, pj]: [usize; 2],
        depth: f32,
        any_active: bool,
    ) -> Option<[usize; 4]> {
        let Dims { nx, ny, nz } = self.dims;
        (0..nz).find_map(|k| {
            (pj.saturating_sub(1)..(pj + 1).min(ny)).find_map(|j| {
                (pi.saturating_sub(1)..(pi + 1).min(nx))
                    .filter(|&i| !any_active || self.actnum[[k, j, i]])
                    .find_map(|i| {
                        let (di, dj) = (pi - i, pj - j);
                        [0, 4]
                            .into_iter()
                            .map(|top_or_bottom| di + 2 * dj + top_or_bottom)
                            .find(|&c| self.corner_depth(i, j, k, c) == depth)
                            .map(|c| [i, j, k, c])
                    })
            })
        })
    }

    /// Fault detection along the i direction: does the face between `(i, j, k)` and
    /// `(i + 1, j, k)` have a shared corner whose depths differ between the two cells?
    pub fn i_face_faulted(&self, i: usize, j: usize, k: usize) -> bool {
        (0..2).any(|dk| {
            (0..2).any(|dj| {
                let a = self.zcorn[[2 * k + dk, 2 * j + dj, 2 * i + 1]];
                let b = self.zcorn[[2 * k + dk, 2 * j + dj, 2 * i + 2]];
                a != b
            })
        })
    }

    /// Fault detection along the j direction, between `(i, j, k)` and `(i, j + 1, k)`.
    pub fn j_face_faulted(&self, i: usize, j: usize, k: usize) -> bool {
        (0..2).any(|dk| {
            (0..2).any(|di| {
                let a = self.zcorn[[2 * k + dk, 2 * j + 1, 2 * i + di]];
                let b = self.zcorn[[2 * k + dk, 2 * j + 2, 2 * i + di]];
                a != b
            })
        })
    }

    /// Fraction of the interior vertical faces between two active cells that are split
    /// by a fault (some shared corner depth differs).
    pub fn fault_split_fraction(&self) -> f64 {
        let Dims { nx, ny, nz } = self.dims;
        let (faulted, total) = (0..nz)
            .into_par_iter()
            .map(|k| {
                let (mut f, mut t) = (0u64, 0u64);
                for j in 0..ny {
                    for i in 0..nx {
                        if !self.actnum[[k, j, i]] {
                            continue;
                        }
                        if i + 1 < nx && self.actnum[[k, j, i + 1]] {
                            t += 1;
                            f += u64::from(self.i_face_faulted(i, j, k));
                        }
                        if j + 1 < ny && self.actnum[[k, j + 1, i]] {
                            t += 1;
                            f += u64::from(self.j_face_faulted(i, j, k));
                        }
                    }
                }
                (f, t)
            })
            .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
        if total == 0 {
            0.0
        } else {
            faulted as f64 / total as f64
        }
    }

    /// Adds (or replaces) a per-cell property over all cells, checking its shape.
    pub fn set_property(&mut self, name: &str, values: Array3<f32>) -> Result<()> {
        let Dims { nx, ny, nz } = self.dims;
        if values.dim() != (nz, ny, nx) {
            return Err(Error::Invalid(format!(
                "property {name} has shape {:?}, the grid is {nx} x {ny} x {nz}",
                values.dim()
            )));
        }
        self.properties.insert(name.to_ascii_uppercase(), values);
        Ok(())
    }

    /// A property by name (case-insensitive) among the static properties, then the
    /// arrays of the last report step.
    pub fn property(&self, name: &str) -> Option<&Array3<f32>> {
        let key = name.to_ascii_uppercase();
        self.properties.get(&key).or_else(|| {
            self.report_steps
                .iter()
                .rev()
                .find_map(|s| s.arrays.get(&key))
        })
    }

    /// The values of property `name` over the active cells of `layers` (0-based, end
    /// exclusive): what a colour map spans, since inactive cells often hold zeros.
    pub fn active_values(
        &self,
        name: &str,
        layers: std::ops::Range<usize>,
    ) -> Option<impl Iterator<Item = f32> + '_> {
        let values = self.property(name)?;
        let layers = layers.start.min(self.dims.nz)..layers.end.min(self.dims.nz);
        Some(
            values
                .slice(s![layers.clone(), .., ..])
                .into_iter()
                .zip(self.actnum.slice(s![layers, .., ..]))
                .filter(|&(_, &active)| active)
                .map(|(&v, _)| v),
        )
    }
}

/// Axis-aligned box; empty when `min > max`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BoundingBox {
    /// Least x, y and z of what was included.
    pub min: [f64; 3],
    /// Greatest x, y and z of what was included.
    pub max: [f64; 3],
}

impl BoundingBox {
    /// The box that includes nothing: the start of a fold with [`Self::include`] or
    /// [`Self::union`].
    pub fn empty() -> Self {
        BoundingBox {
            min: [f64::INFINITY; 3],
            max: [f64::NEG_INFINITY; 3],
        }
    }

    /// Whether nothing has been included.
    pub fn is_empty(&self) -> bool {
        (0..3).any(|a| self.min[a] > self.max[a])
    }

    /// Grows the box to contain `p`.
    pub fn include(&mut self, p: [f64; 3]) {
        for (a, v) in p.into_iter().enumerate() {
            self.min[a] = self.min[a].min(v);
            self.max[a] = self.max[a].max(v);
        }
    }

    /// The smallest box containing both (an empty box leaves the other unchanged).
    pub fn union(&self, other: &Self) -> Self {
        BoundingBox {
            min: std::array::from_fn(|a| self.min[a].min(other.min[a])),
            max: std::array::from_fn(|a| self.max[a].max(other.max[a])),
        }
    }

    /// The centre of the box in display coordinates (map x, map y, elevation), as
    /// [`CornerPointGrid::display_origin`] takes it.
    pub fn display_centre(&self) -> [f64; 3] {
        [
            0.5 * (self.min[0] + self.max[0]),
            0.5 * (self.min[1] + self.max[1]),
            -0.5 * (self.min[2] + self.max[2]),
        ]
    }

    /// The box in the display frame of `origin` ([`CornerPointGrid::to_display`]):
    /// its least and greatest corner, elevation taking the place of depth.
    pub fn to_display(&self, origin: [f64; 3]) -> [[f32; 3]; 2] {
        let [a, b] = [self.min, self.max].map(|c| CornerPointGrid::to_display(origin, c));
        [
            std::array::from_fn(|k| a[k].min(b[k])),
            std::array::from_fn(|k| a[k].max(b[k])),
        ]
    }

    /// Length of the diagonal; 0 for an empty box.
    pub fn extent(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        (0..3)
            .map(|a| (self.max[a] - self.min[a]).powi(2))
            .sum::<f64>()
            .sqrt()
    }
}

/// How far beyond its quartiles, in interquartile ranges, a corner of a model is
/// stray. The real models in the project's data reach at most 3.3 (Reek's depths);
/// past 10 the rest of the model fills at most a sixth of the view along that axis.
pub const STRAY_SPREADS: f64 = 10.0;

/// What [`CornerPointGrid::stray_corners`] finds.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StrayCorners {
    /// Pillars with a stray corner.
    pub pillars: usize,
    /// The corner farthest out.
    pub worst: StrayCorner,
    /// The box of the model without its stray corners, in map coordinates.
    pub rest: BoundingBox,
}

/// One stray corner.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StrayCorner {
    /// Its pillar, `(pi, pj)` from 0.
    pub pillar: [usize; 2],
    /// A cell with this corner, `(i, j, k)` from 0.
    pub cell: [usize; 3],
    /// The corner's number in that cell (Eclipse order).
    pub corner: usize,
    /// Map (x, y, depth).
    pub map: [f64; 3],
}

/// Points that [`CornerPointGrid::stray_corners`] samples to find the quartiles.
pub const STRAY_QUARTILE_SAMPLES: usize = 1 << 20;

/// What a part of the pillars holds of [`StrayCorners`]: pillars with a stray end,
/// the farthest end (excess, pillar, depth, map point), the box of the others.
struct Strays {
    pillars: usize,
    worst: Option<(f64, [usize; 2], f32, [f64; 3])>,
    rest: BoundingBox,
}

impl Default for Strays {
    fn default() -> Self {
        Strays {
            pillars: 0,
            worst: None,
            rest: BoundingBox::empty(),
        }
    }
}

impl Strays {
    /// Both parts; of two equally far ends, `self`'s (the earlier pillars').
    fn merge(self, other: Strays) -> Strays {
        let worst = match (self.worst, other.worst) {
            (Some(a), Some(b)) if b.0 > a.0 => Some(b),
            (None, b) => b,
            (a, _) => a,
        };
        Strays {
            pillars: self.pillars + other.pillars,
            worst,
            rest: self.rest.union(&other.rest),
        }
    }
}

/// The `fraction` quantile of `values` (reordered), the nearest rank below; `None`
/// when empty.
fn quantile(values: &mut [f64], fraction: f64) -> Option<f64> {
    let last = values.len().checked_sub(1)?;
    let rank = (last as f64 * fraction) as usize;
    Some(*values.select_nth_unstable_by(rank, f64::total_cmp).1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 x 1 x 1 grid of unit cubes with vertical pillars, the right cell thrown
    /// down by `throw` on its shared face.
    fn two_cells(throw: f32) -> CornerPointGrid {
        let dims = Dims::new(2, 1, 1).unwrap();
        let mut coord = Vec::new();
        for j in 0..2 {
            for i in 0..3 {
                coord.extend([i as f64, j as f64, 0.0, i as f64, j as f64, 10.0]);
            }
        }
        let mut zcorn = Vec::new();
        for dk in 0..2 {
            for _ in 0..2 {
                for x in 0..4 {
                    let right = if x >= 2 { throw } else { 0.0 };
                    zcorn.push(1000.0 + dk as f32 + right);
                }
            }
        }
        CornerPointGrid::from_arrays(dims, coord, zcorn, None).unwrap()
    }

    /// A 30 x 20 x 4 faulted synthetic grid with every seventh cell inactive.
    fn faulted_with_holes() -> CornerPointGrid {
        let mut g = crate::synth::generate(&crate::synth::SynthParams {
            nx: 30,
            ny: 20,
            nz: 4,
            faults: 3,
            seed: 5,
        })
        .unwrap();
        for (n, a) in g.actnum.iter_mut().enumerate() {
            *a &= n % 7 != 3;
        }
        g
    }

    #[test]
    fn the_bounding_box_is_that_of_every_active_cells_corners() {
        // Leaning pillars, faults, inactive cells and a rotated map frame: the box
        // from each pillar's shallowest and deepest corner is, bit for bit, the box
        // of all the active cells' corners; with no active cell, of all cells'.
        let mut g = faulted_with_holes();
        let Dims { nx, ny, nz } = g.dims();
        let of_corners = |g: &CornerPointGrid, active_only: bool| {
            let mut b = BoundingBox::empty();
            for (k, j, i) in
                (0..nz).flat_map(|k| (0..ny).flat_map(move |j| (0..nx).map(move |i| (k, j, i))))
            {
                if !active_only || g.is_active(i, j, k) {
                    g.cell_corners(i, j, k)
                        .into_iter()
                        .for_each(|c| b.include(c));
                }
            }
            b
        };
        let b = g.bounding_box();
        assert!(!b.is_empty());
        assert_eq!(b, of_corners(&g, true));
        // Rotated, x and y each still move one way along a pillar, their map sum
        // within rounding.
        let (x0, y0) = (4.0e5, 6.7e6);
        g.mapaxes = Some(MapAxes::from_values([
            x0 - 0.5,
            y0 + 0.866,
            x0,
            y0,
            x0 + 0.866,
            y0 + 0.5,
        ]));
        let (b, all) = (g.bounding_box(), of_corners(&g, true));
        for a in 0..3 {
            assert!((b.min[a] - all.min[a]).abs() <= 1e-9 * all.min[a].abs().max(1.0));
            assert!((b.max[a] - all.max[a]).abs() <= 1e-9 * all.max[a].abs().max(1.0));
        }
        assert!(b.min[0] < x0 && b.max[1] > y0, "{b:?}");
        g.mapaxes = None;
        g.actnum.fill(false);
        assert_eq!(g.bounding_box(), of_corners(&g, false));
    }

    #[test]
    fn a_stray_depth_or_pillar_is_found_and_named_and_the_rest_is_boxed_without_it() {
        let mut g = faulted_with_holes();
        assert_eq!(g.stray_corners(), None, "a sound model has none");
        let whole = g.bounding_box();
        assert_eq!(g.view_box(), whole, "a sound model's view frames all of it");

        // One deep corner of an active cell: corner 5 (di 1, dj 0, bottom) of cell
        // (12, 7, 2), on pillar (13, 7).
        let (i, j, k) = (12, 7, 2);
        assert!(g.is_active(i, j, k));
        g.zcorn[[2 * k + 1, 2 * j, 2 * i + 1]] = 1e11;
        let found = g.stray_corners().expect("the stray depth is found");
        // Quartiles from a tenth of the pillars' ends: the same finding.
        assert_eq!(g.stray_corners_sampling(130).1, Some(found.clone()));
        assert_eq!(found.pillars, 1);
        assert_eq!(found.worst.pillar, [13, 7]);
        assert_eq!(found.worst.cell, [i, j, k]);
        assert_eq!(found.worst.corner, 5);
        assert_eq!(found.worst.map[2], f64::from(1e11f32));
        assert_eq!(g.bounding_box().max[2], f64::from(1e11f32));
        for a in 0..3 {
            assert!(found.rest.min[a] >= whole.min[a] && found.rest.max[a] <= whole.max[a]);
        }
        assert!(found.rest.max[2] - found.rest.min[2] > 0.5 * (whole.max[2] - whole.min[2]));
        // Views frame the rest, about the sound model's middle.
        assert_eq!(g.view_box(), found.rest);
        let middle = |b: &BoundingBox| -0.5 * (b.min[2] + b.max[2]);
        assert_eq!(g.display_origin()[2], middle(&found.rest));
        assert!((middle(&found.rest) - middle(&whole)).abs() < 0.5 * (whole.max[2] - whole.min[2]));

        // A corner of an inactive cell (ZCORN holds each cell's own) is not part of
        // the model drawn.
        g.actnum[[k, j, i]] = false;
        assert_eq!(g.stray_corners(), None, "only an inactive cell has it");
        g.actnum[[k, j, i]] = true;
        g.zcorn[[2 * k + 1, 2 * j, 2 * i + 1]] = g.zcorn[[2 * k + 1, 2 * j, 2 * i]];

        // A pillar thrown far east, with a rotated map frame: x and y both stray.
        g.mapaxes = Some(MapAxes::from_values([0.0, 1.0, 0.0, 0.0, 1.0, 0.0]));
        assert_eq!(g.stray_corners(), None);
        g.coord[[4, 9, 0]] += 1e7;
        g.coord[[4, 9, 3]] += 1e7;
        let found = g.stray_corners().expect("the stray pillar is found");
        assert_eq!((found.pillars, found.worst.pillar), (1, [9, 4]));
        assert!(found.worst.map[0] > 1e6, "{:?}", found.worst);
    }

    #[test]
    fn corners_interpolate_pillars_and_follow_eclipse_order() {
        let g = two_cells(0.0);
        let c = g.cell_corners(1, 0, 0);
        assert_eq!(c[0], [1.0, 0.0, 1000.0]);
        assert_eq!(c[1], [2.0, 0.0, 1000.0]);
        assert_eq!(c[2], [1.0, 1.0, 1000.0]);
        assert_eq!(c[7], [2.0, 1.0, 1001.0]);
    }

    #[test]
    fn inclined_pillar_is_interpolated_at_corner_depth() {
        let mut g = two_cells(0.0);
        // Pillar (0,0) leans +x by 10 over its 10 m of depth span.
        g.coord[[0, 0, 3]] = 10.0;
        g.coord[[0, 0, 5]] = 10.0;
        let p = g.point_on_pillar(0, 0, 5.0);
        assert!((p[0] - 5.0).abs() < 1e-12);
    }

    #[test]
    fn faults_are_detected_from_shared_corner_depths() {
        assert!(!two_cells(0.0).i_face_faulted(0, 0, 0));
        assert_eq!(two_cells(0.0).fault_split_fraction(), 0.0);
        let g = two_cells(3.0);
        assert!(g.i_face_faulted(0, 0, 0));
        assert_eq!(g.fault_split_fraction(), 1.0);
    }

    #[test]
    fn mapaxes_rotate_and_translate() {
        let mut g = two_cells(0.0);
        // Local x points north, local y points west, origin at (100, 200).
        g.mapaxes = Some(MapAxes::from_values([
            90.0, 200.0, 100.0, 200.0, 100.0, 201.0,
        ]));
        let c = g.cell_corners(1, 0, 0);
        assert!((c[1][0] - 100.0).abs() < 1e-9 && (c[1][1] - 202.0).abs() < 1e-9);
        assert!((c[3][0] - 99.0).abs() < 1e-9);
    }

    #[test]
    fn active_arrays_expand_onto_cells() {
        let mut g = two_cells(0.0);
        g.actnum[[0, 0, 0]] = false;
        assert_eq!(g.active_index(), vec![None, Some(0)]);
        let full = g.expand_active(&[7.0]).unwrap();
        assert!(full[[0, 0, 0]].is_nan() && full[[0, 0, 1]] == 7.0);
        assert!(g.expand_active(&[1.0, 2.0]).is_none());
    }

    #[test]
    fn active_values_skip_inactive_cells_and_other_layers() {
        let mut g = two_cells(0.0);
        g.set_property(
            "poro",
            Array3::from_shape_vec((1, 1, 2), vec![0.0, 0.25]).unwrap(),
        )
        .unwrap();
        g.actnum[[0, 0, 0]] = false;
        let values = |layers| {
            g.active_values("PORO", layers)
                .map(Iterator::collect::<Vec<_>>)
        };
        assert_eq!(values(0..1), Some(vec![0.25]));
        assert_eq!(values(1..4), Some(vec![]));
        assert!(g.active_values("NTG", 0..1).is_none());
    }

    #[test]
    fn bad_arrays_are_refused() {
        let dims = Dims::new(1, 1, 1).unwrap();
        let err = CornerPointGrid::from_arrays(dims, vec![0.0; 24], vec![0.0; 7], None);
        assert!(err.unwrap_err().to_string().contains("ZCORN has 7 values"));
        let mut coord = vec![0.0; 24];
        coord[4] = f64::NAN;
        let err = CornerPointGrid::from_arrays(dims, coord, vec![0.0; 8], None);
        assert!(err.unwrap_err().to_string().contains("pillar 1"));
        let mut zcorn = vec![0.0; 8];
        zcorn[5] = f32::INFINITY;
        let err = CornerPointGrid::from_arrays(dims, vec![0.0; 24], zcorn, None);
        assert!(err.unwrap_err().to_string().contains("ZCORN value 6"));
        assert!(Dims::new(usize::MAX / 2, 4, 1).is_err());
    }
}
