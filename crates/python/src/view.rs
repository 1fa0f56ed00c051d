//! `view`: the interactive window from Python, where a display exists.

use std::path::PathBuf;

use pyo3::prelude::*;
use strata::viewer::{self, Options};

use crate::engine::parse_scene;
use crate::errors::run;

/// Opens the window (`strata view`) on the scene `json` and blocks until it is closed
/// or its `script` ends; returns the frames drawn and the median and slowest frame in
/// milliseconds. The GIL is released meanwhile.
#[pyfunction]
#[pyo3(signature = (json, script = None, size = (1280, 800)))]
pub fn view(
    py: Python<'_>,
    json: &str,
    script: Option<PathBuf>,
    size: (u32, u32),
) -> PyResult<(usize, f64, f64)> {
    let json = json.to_string();
    run(py, move || {
        let scene = parse_scene(&json)?;
        let summary = viewer::run(Options {
            scene,
            script,
            stats_file: None,
            size: [size.0, size.1],
        })?;
        Ok((summary.frames, summary.median_ms, summary.worst_ms))
    })
}
