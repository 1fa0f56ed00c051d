//! `lod_build`: a level-of-detail hierarchy of a model, its progress told to Python.

use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use pyo3::prelude::*;
use strata::engine::Model;
use strata::lod::{BuildOptions, Options, Progress, build_file};
use strata::scene::ModelSource;

use crate::errors::run;

/// How often the progress callback is called at most: each call takes the GIL from
/// the threads that build.
const TELL_EVERY: Duration = Duration::from_millis(200);

/// Builds the hierarchy of every layer of the model at `path` into `output`, as `strata
/// lod build` does; `progress(done, total)` is called as it goes (from the build's
/// threads, at most five times a second, and once at the end). Returns the build's
/// report as (layers, nodes, levels, input triangles, stored triangles, bytes, seconds).
#[pyfunction]
#[pyo3(signature = (path, output, props = Vec::new(), grid_only = false, property = None, no_property = false, tile = 64, zscale = 5.0, progress = None))]
#[allow(clippy::too_many_arguments)] // Python keyword arguments, named at every call
pub fn lod_build(
    py: Python<'_>,
    path: PathBuf,
    output: PathBuf,
    props: Vec<PathBuf>,
    grid_only: bool,
    property: Option<String>,
    no_property: bool,
    tile: u32,
    zscale: f32,
    progress: Option<Py<PyAny>>,
) -> PyResult<(usize, usize, u32, usize, usize, u64, f64)> {
    let source = ModelSource {
        path,
        props,
        grid_only,
    };
    let report = run(py, move || {
        let (model, _) = Model::open(&source)?;
        let grid = model.grid;
        let property = match (no_property, property) {
            (true, _) => None,
            (false, Some(p)) => Some(p),
            (false, None) => grid.property("PORO").map(|_| "PORO".to_string()),
        };
        let told = progress.map(teller);
        let options = BuildOptions {
            tile_cells: tile,
            decimation: Options {
                z_scale: zscale,
                ..Options::default()
            },
            progress: told.as_ref().map(|(f, _)| f.clone()),
            memory: strata::memory::available_memory().map(|bytes| bytes as u64),
            ..BuildOptions::default()
        };
        let report = build_file(&grid, property.as_deref(), &output, &options)?;
        if let Some((_, end)) = told {
            end();
        }
        Ok(report)
    })?;
    Ok((
        report.layers,
        report.nodes,
        report.levels,
        report.input_triangles,
        report.stored_triangles,
        report.bytes,
        report.seconds,
    ))
}

/// A build's progress callback that calls `callback(done, total)` now and then, and
/// the call that tells the end.
fn teller(callback: Py<PyAny>) -> (strata::lod::ProgressFn, impl FnOnce()) {
    let total = Arc::new(AtomicU64::new(0));
    let done = Arc::new(AtomicU64::new(0));
    let last = Arc::new(Mutex::new(Instant::now()));
    let callback = Arc::new(callback);
    let tell = {
        let callback = callback.clone();
        move |done: u64, total: u64| {
            Python::attach(|py| {
                if let Err(e) = callback.call1(py, (done, total)) {
                    // A failing progress bar must not stop the build: shown, not raised.
                    e.print(py);
                }
            });
        }
    };
    let on_progress: strata::lod::ProgressFn = {
        let (total, done, tell) = (total.clone(), done.clone(), tell.clone());
        Arc::new(move |p: Progress| {
            match p {
                Progress::Started { work, .. } => total.store(work, Ordering::Relaxed),
                Progress::Worked(units) => {
                    done.fetch_add(units, Ordering::Relaxed);
                }
                Progress::Written { .. } => {}
            }
            let due = last.lock().is_ok_and(|mut at| {
                let due = at.elapsed() >= TELL_EVERY;
                if due {
                    *at = Instant::now();
                }
                due
            });
            if due {
                tell(done.load(Ordering::Relaxed), total.load(Ordering::Relaxed));
            }
        })
    };
    let end = move || {
        let total = total.load(Ordering::Relaxed);
        tell(total, total);
    };
    (on_progress, end)
}
