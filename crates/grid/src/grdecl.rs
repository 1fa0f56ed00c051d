//! GRDECL text decks (and `.DATA` decks): reader and writer.

use std::path::Path;

use crate::{CornerPointGrid, Error, ReadOptions, Result};

/// Reads a GRDECL or DATA deck.
pub fn read(path: &Path, _options: &ReadOptions) -> Result<CornerPointGrid> {
    Err(Error::model(path, "", "GRDECL reader not yet written"))
}

/// Writes a grid as a GRDECL deck.
pub fn write(_grid: &CornerPointGrid, path: &Path) -> Result<()> {
    Err(Error::model(path, "", "GRDECL writer not yet written"))
}
