//! strata's errors as Python exceptions, and the one way native code runs: with the GIL
//! released and any panic caught, so that neither a long read nor a bug stops Python.

use std::panic::{AssertUnwindSafe, catch_unwind};

use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::{PyErr, create_exception};
use strata::Error;

create_exception!(
    _strata,
    StrataError,
    PyException,
    "Every error strata raises; the message is the command line's (file, keyword, line or record)."
);
create_exception!(
    _strata,
    FileError,
    StrataError,
    "A file that cannot be read or written, or holds something it should not; the message names it."
);
create_exception!(
    _strata,
    OptionError,
    StrataError,
    "A scene field, argument or array that no picture or model can be made of."
);
create_exception!(
    _strata,
    GpuError,
    StrataError,
    "The GPU refused a device or failed a frame."
);
create_exception!(
    _strata,
    NoAdapterError,
    GpuError,
    "No GPU adapter strata can draw with (on a machine without a GPU: Mesa's llvmpipe or lavapipe)."
);

/// Which exception an error raises.
enum Kind {
    File,
    Option,
    Gpu,
    NoAdapter,
}

fn kind(e: &Error) -> Kind {
    match e {
        Error::Grid(g) => grid_kind(g),
        Error::Lod(l) => match l {
            strata::lod::Error::Io { .. } | strata::lod::Error::Format { .. } => Kind::File,
            strata::lod::Error::Grid(g) => grid_kind(g),
            strata::lod::Error::Mesh(_) | strata::lod::Error::Option(_) => Kind::Option,
        },
        Error::Render(r) => match r {
            strata::render::Error::NoAdapter(_) | strata::render::Error::Unsuitable(_) => {
                Kind::NoAdapter
            }
            strata::render::Error::Invalid(_) => Kind::Option,
            strata::render::Error::Output { .. } => Kind::File,
            strata::render::Error::Device { .. } | strata::render::Error::Gpu(_) => Kind::Gpu,
        },
        Error::Scene(_) => Kind::Option,
        Error::SceneFile { .. } | Error::File { .. } => Kind::File,
        Error::Window(_) => Kind::Gpu,
        Error::While { source, .. } => kind(source),
    }
}

fn grid_kind(e: &strata::grid::Error) -> Kind {
    match e {
        // A grid built from the caller's arrays: the arguments are wrong, not a file.
        strata::grid::Error::Invalid(_) => Kind::Option,
        _ => Kind::File,
    }
}

/// The error and its causes, each after a colon, leaving out a cause whose text the
/// message already holds: what the `strata` binary prints after `strata: `.
fn message(e: &Error) -> String {
    let mut out = e.to_string();
    let mut cause = std::error::Error::source(e);
    while let Some(c) = cause {
        let text = c.to_string();
        if !out.contains(&text) {
            out = format!("{out}: {text}");
        }
        cause = c.source();
    }
    out
}

/// The Python exception of `e`.
pub fn to_py(e: &Error) -> PyErr {
    let text = message(e);
    match kind(e) {
        Kind::File => FileError::new_err(text),
        Kind::Option => OptionError::new_err(text),
        Kind::Gpu => GpuError::new_err(text),
        Kind::NoAdapter => NoAdapterError::new_err(text),
    }
}

/// Runs `work` with the GIL released (reading, building and drawing take seconds that
/// other Python threads may use), turning its error into the matching exception and a
/// panic into a `StrataError` rather than letting it reach Python.
pub fn run<T: Send>(
    py: Python<'_>,
    work: impl FnOnce() -> strata::Result<T> + Send,
) -> PyResult<T> {
    py.detach(|| catch_unwind(AssertUnwindSafe(work)))
        .map_err(|panic| {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".into());
            StrataError::new_err(format!(
                "internal error (a bug in strata, please report it): {what}"
            ))
        })?
        .map_err(|e| to_py(&e))
}

/// Adds the exception classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("StrataError", py.get_type::<StrataError>())?;
    m.add("FileError", py.get_type::<FileError>())?;
    m.add("OptionError", py.get_type::<OptionError>())?;
    m.add("GpuError", py.get_type::<GpuError>())?;
    m.add("NoAdapterError", py.get_type::<NoAdapterError>())?;
    Ok(())
}
