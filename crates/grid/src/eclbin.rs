//! Eclipse binary files (EGRID, INIT, UNRST, Xnnnn): reader and writer.

use std::path::Path;

use crate::{CornerPointGrid, Error, ReadOptions, Result};

/// Reads an EGRID, and with `load_results` the INIT and restart files beside it.
pub fn read_egrid(path: &Path, _options: &ReadOptions) -> Result<CornerPointGrid> {
    Err(Error::model(path, "", "EGRID reader not yet written"))
}

/// Writes a grid as an EGRID.
pub fn write_egrid(_grid: &CornerPointGrid, path: &Path) -> Result<()> {
    Err(Error::model(path, "", "EGRID writer not yet written"))
}
