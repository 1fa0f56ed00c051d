//! One cell of a model as `strata info --cell` gives it: its corners and values.
//! Kept in the library so that every front end (the command line, the Python
//! package's `Grid.cell`) says the same about a cell.

use serde::Serialize;
use strata_grid::ndarray::Array3;
use strata_grid::{CornerPointGrid, Dims};

use crate::{Error, Result};

/// The order of [`CellInfo::corners`], in words.
pub const CORNER_ORDER: &str = "Eclipse order: top face (I,J) (I+1,J) (I,J+1) (I+1,J+1), then the bottom face in the same order";

/// A cell's corners and values.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CellInfo {
    /// The model file it was read from, as given.
    pub file: String,
    /// 1-based I, J, K.
    pub cell: [usize; 3],
    /// Whether the simulation uses it (ACTNUM).
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
    /// Cell `cell` (1-based I, J, K) of `grid`, read from `file`; a cell outside the
    /// grid is refused with the grid's size.
    pub fn of(grid: &CornerPointGrid, file: impl Into<String>, cell: [usize; 3]) -> Result<Self> {
        let Dims { nx, ny, nz } = grid.dims();
        let [ci, cj, ck] = cell;
        if !(1..=nx).contains(&ci) || !(1..=ny).contains(&cj) || !(1..=nz).contains(&ck) {
            return Err(Error::scene(format!(
                "cell {ci},{cj},{ck} is outside the grid of {nx} x {ny} x {nz} cells \
                 (1-based I,J,K)"
            )));
        }
        let (i, j, k) = (ci - 1, cj - 1, ck - 1);
        let value = |a: &Array3<f32>| {
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
            file: file.into(),
            cell,
            active: grid.is_active(i, j, k),
            corner_order: CORNER_ORDER,
            corners: grid.cell_corners(i, j, k),
            values,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cell_gives_its_corners_and_values_and_one_outside_is_refused() {
        let grid = strata_grid::open(&crate::sample_model()).expect("the sample model");
        let Dims { nx, ny, nz } = grid.dims();
        let info = CellInfo::of(&grid, "sample", [2, 3, 1]).expect("a cell inside");
        assert_eq!(info.corners, grid.cell_corners(1, 2, 0));
        assert_eq!(info.active, grid.is_active(1, 2, 0));
        let poro = grid.property("PORO").expect("PORO")[[0, 2, 1]];
        assert!(info.values.contains(&("PORO".to_string(), Some(poro))));
        for outside in [[0, 1, 1], [nx + 1, 1, 1], [1, ny + 1, 1], [1, 1, nz + 1]] {
            let said = CellInfo::of(&grid, "sample", outside)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default();
            assert!(said.contains(&format!("{nx} x {ny} x {nz}")), "{said}");
        }
    }
}
