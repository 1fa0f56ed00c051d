//! One module per subcommand of the `strata` binary.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use strata::grid::CornerPointGrid;

pub mod info;
pub mod lod;
pub mod render;
pub mod style;
pub mod synth;
pub mod terrain;

/// Opens `model` (the sample in `data/` when `None`) and adds the per-cell arrays of
/// each property deck in `props` (e.g. the PORO GRDECL that goes with an EGRID).
pub fn open_model(model: Option<&Path>, props: &[PathBuf]) -> Result<(PathBuf, CornerPointGrid)> {
    let path = model.map_or_else(crate::sample_model, Path::to_path_buf);
    let mut grid = strata::grid::open(&path)?;
    add_properties(&mut grid, &path, props)?;
    Ok((path, grid))
}

/// Adds to `grid`, read from `path`, the per-cell arrays of each property deck in
/// `props`.
pub fn add_properties(grid: &mut CornerPointGrid, path: &Path, props: &[PathBuf]) -> Result<()> {
    for deck in props {
        strata::grid::grdecl::read_properties(grid, deck).with_context(|| {
            format!(
                "adding the properties of {} to {}",
                deck.display(),
                path.display()
            )
        })?;
    }
    Ok(())
}
