//! Result files whose active set is not the grid's ACTNUM. Intersect writes an EGRID
//! whose ACTNUM counts cells that have no pore volume, and INIT and restart arrays
//! without them: INTEHEAD's active count is smaller. As xtgeo does
//! (`get_actnum_from_porv`), the cells with values are those with PORV > 0, PORV being
//! written for every cell; the grid keeps its ACTNUM, and the mapping is named in its
//! warnings (so `strata info` says it).

use std::path::Path;

use ndarray::Array3;

use super::record::RecordView;
use crate::{CornerPointGrid, Result};

/// The cells an INIT's arrays hold values for when INTEHEAD counts `nactive` and the
/// grid's ACTNUM another number and PORV > 0 in exactly `nactive` cells; `None`
/// otherwise (when the counts disagree still, the INIT is refused as written for
/// another grid).
pub fn result_cells(
    grid: &CornerPointGrid,
    nactive: i32,
    porv: Option<&RecordView<'_>>,
) -> Result<Option<Array3<bool>>> {
    let active = grid.active_count();
    if usize::try_from(nactive) == Ok(active) {
        return Ok(None);
    }
    let Some(porv) = porv else {
        return Ok(None);
    };
    let values = porv.to_f32()?;
    let cells: Vec<bool> = values.iter().map(|&v| v > 0.0).collect();
    if usize::try_from(nactive) != Ok(cells.iter().filter(|&&c| c).count()) {
        return Ok(None);
    }
    Array3::from_shape_vec(grid.actnum.raw_dim(), cells)
        .map(Some)
        .map_err(|e| porv.error(e.to_string()))
}

/// The warning that says results were mapped through PORV, and which active cells
/// have none.
pub fn mapped_warning(grid: &CornerPointGrid, path: &Path, cells: &Array3<bool>) -> String {
    let d = grid.dims();
    let without: Vec<String> = grid
        .actnum
        .iter()
        .zip(cells)
        .enumerate()
        .filter(|(_, (a, c))| **a && !**c)
        .take(5)
        .map(|(n, _)| {
            let (i, j, k) = d.cell_ijk(n);
            format!("({}, {}, {})", i + 1, j + 1, k + 1)
        })
        .collect();
    format!(
        "{}: results hold {} cells, ACTNUM has {} active: mapped through PORV > 0 as xtgeo \
         does (Intersect output); active cells without values: {}",
        path.display(),
        cells.iter().filter(|&&c| c).count(),
        grid.active_count(),
        without.join(" ")
    )
}
