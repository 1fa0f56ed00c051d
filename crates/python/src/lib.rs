//! The native module of the `strata` Python package (`strata._strata`).
//!
//! Thin on purpose: models are read by `strata::engine::Model`, pictures drawn by
//! `strata::SceneRenderer` from a `strata::Scene` parsed from JSON, so the package
//! says and draws what the command line does. The Python layer
//! (`python/strata/__init__.py`) gives it its API: masked arrays, `Scene`, xtgeo,
//! ensembles. Everything long runs with the GIL released ([`errors::run`]).

use pyo3::prelude::*;

mod engine;
mod errors;
mod grid;
mod lod;
mod view;

/// The native module.
#[pymodule]
fn _strata(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)?;
    m.add_class::<grid::Grid>()?;
    m.add_class::<engine::Engine>()?;
    m.add_function(wrap_pyfunction!(engine::check_scene, m)?)?;
    m.add_function(wrap_pyfunction!(engine::png, m)?)?;
    m.add_function(wrap_pyfunction!(lod::lod_build, m)?)?;
    m.add_function(wrap_pyfunction!(view::view, m)?)?;
    Ok(())
}
