//! One cell as `strata info --cell` shows it and a window's picking reports it: its
//! corners and every loaded property's value.

use serde::Serialize;
use strata_grid::{CornerPointGrid, Dims};

use crate::{Error, Result};

/// The order of [`CellInfo::corners`], in words.
pub const CORNER_ORDER: &str = "Eclipse order: top face (I,J) (I+1,J) (I,J+1) (I+1,J+1), then the bottom face in the same order";

/// A cell's place, corners and values.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CellInfo {
    /// The model file it was read from.
    pub file: String,
    /// 1-based I, J, K.
    pub cell: [usize; 3],
    /// Whether the model's ACTNUM keeps it.
    pub active: bool,
    /// The order of `corners` ([`CORNER_ORDER`]).
    pub corner_order: &'static str,
    /// Map coordinates (x, y, depth) of the 8 corners.
    pub corners: [[f64; 3]; 8],
    /// Static properties, then the arrays of the last report step (named
    /// `NAME@STEP`); `None` where undefined.
    pub values: Vec<(String, Option<f32>)>,
}

impl CellInfo {
    /// Cell `cell` (1-based I, J, K) of `grid`, read from `file`.
    pub fn of(grid: &CornerPointGrid, file: String, cell: [usize; 3]) -> Result<Self> {
        let Dims { nx, ny, nz } = grid.dims();
        let [ci, cj, ck] = cell;
        if !(1..=nx).contains(&ci) || !(1..=ny).contains(&cj) || !(1..=nz).contains(&ck) {
            return Err(Error::scene(format!(
                "cell {ci},{cj},{ck} is outside the grid of {nx} x {ny} x {nz} cells (1-based)"
            )));
        }
        let (i, j, k) = (ci - 1, cj - 1, ck - 1);
        let value = |a: &strata_grid::ndarray::Array3<f32>| {
            let v = a[[k, j, i]];
            (!v.is_nan()).then_some(v)
        };
        let mut values: Vec<(String, Option<f32>)> = grid
            .properties
            .iter()
            .map(|(n, a)| (n.clone(), value(a)))
            .collect();
        if let Some(step) = grid.report_steps.last() {
            values.extend(
                step.arrays
                    .iter()
                    .map(|(n, a)| (format!("{n}@{}", step.number), value(a))),
            );
        }
        Ok(CellInfo {
            file,
            cell,
            active: grid.is_active(i, j, k),
            corner_order: CORNER_ORDER,
            corners: grid.cell_corners(i, j, k),
            values,
        })
    }
}
