//! `_Engine`: the library's scene renderer behind Python, scenes read from JSON with
//! the field that is wrong named, and PNG encoding for Jupyter.

use std::sync::Mutex;

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3, PyReadonlyArray3};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use strata::scene::{Lod, ModelSource};
use strata::{Scene, SceneRenderer};

use crate::errors::run;
use crate::grid::{Grid, note_text};

/// Reads a scene from JSON, naming the field serde refused (`wire.thickness: invalid
/// type ...`), then checks its values as [`Scene::check`] does. A scene without a model
/// is checked as if it had one: Python gives the model to `render`.
pub fn parse_scene(json: &str) -> strata::Result<Scene> {
    let de = &mut serde_json::Deserializer::from_str(json);
    let scene: Scene = serde_path_to_error::deserialize(de).map_err(|e| {
        let inner = e.inner().to_string();
        // The JSON is made by the package, not typed: its line and column say nothing.
        let inner = inner
            .split(" at line ")
            .next()
            .unwrap_or(&inner)
            .to_string();
        match e.path().to_string().as_str() {
            "." => strata::Error::scene(format!("scene: {inner}")),
            path => strata::Error::scene(format!("scene field {path}: {inner}")),
        }
    })?;
    let mut checked = scene.clone();
    if checked.model.is_none() && !matches!(checked.lod, Lod::Hierarchy { .. }) {
        checked.model = Some(ModelSource::new("<model>"));
    }
    checked.check()?;
    Ok(scene)
}

/// Checks a scene given as JSON and returns it with every field, defaults filled in.
#[pyfunction]
pub fn check_scene(py: Python<'_>, json: &str) -> PyResult<String> {
    run(py, || parse_scene(json).map(|s| s.to_json()))
}

/// An RGBA picture, `(height, width, 4)` uint8, as PNG bytes.
#[pyfunction]
pub fn png<'py>(
    py: Python<'py>,
    picture: PyReadonlyArray3<'_, u8>,
) -> PyResult<Bound<'py, PyBytes>> {
    let array = picture.as_array();
    let (h, w, channels) = array.dim();
    let pixels: Vec<u8> = array.iter().copied().collect();
    let bytes = run(py, move || {
        if channels != 4 {
            return Err(strata::Error::scene(format!(
                "a picture is (height, width, 4) RGBA, this one has {channels} channels"
            )));
        }
        let size =
            |n: usize| u32::try_from(n).map_err(|_| strata::Error::scene("picture too large"));
        let image = strata::render::image::RgbaImage::from_raw(size(w)?, size(h)?, pixels)
            .ok_or_else(|| strata::Error::scene("picture: size and pixels disagree"))?;
        let mut out = std::io::Cursor::new(Vec::new());
        image
            .write_to(&mut out, strata::render::image::ImageFormat::Png)
            .map_err(|e| strata::Error::scene(format!("PNG: {e}")))?;
        Ok(out.into_inner())
    })?;
    Ok(PyBytes::new(py, &bytes))
}

/// The engine and the grid it holds, if it was given one.
struct Held {
    engine: SceneRenderer,
    grid: Option<u64>,
}

/// A scene renderer kept between calls: a new camera on the same model draws from
/// what is held. One per process serves `strata.render` (and each Dask worker).
#[pyclass(name = "_Engine", module = "strata._strata")]
pub struct Engine {
    held: Mutex<Option<Held>>,
}

/// What one frame gives Python: the picture and the engine's notes (kind, text).
type Rendered<'py> = (Bound<'py, PyArray3<u8>>, Vec<(&'static str, String)>);

#[pymethods]
impl Engine {
    #[new]
    fn new() -> Self {
        Engine {
            held: Mutex::new(None),
        }
    }

    /// Draws the scene `json`; of `grid` when given (the scene's model is then the
    /// grid's), else of the model or hierarchy the scene names.
    #[pyo3(signature = (json, grid = None))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        json: &str,
        grid: Option<&Bound<'py, Grid>>,
    ) -> PyResult<Rendered<'py>> {
        let grid = grid.map(Bound::get);
        let (image, notes) = run(py, || {
            let mut scene = parse_scene(json)?;
            if let Some(grid) = grid {
                scene.model = Some(grid.source.clone());
            }
            // A panic while drawing (caught by `run`) leaves the lock poisoned and the
            // engine in an unknown state: the next picture starts a fresh one.
            let mut held = self.held.lock().unwrap_or_else(|poisoned| {
                let mut held = poisoned.into_inner();
                *held = None;
                held
            });
            let given = grid.map(|g| g.id);
            // From a grid back to files: a fresh engine, since the grid's source may
            // name the very file asked for now, and the held grid may differ from it.
            let h = match held.as_mut() {
                Some(h) if h.grid.is_none() || given.is_some() => {
                    h.engine.set_scene(scene)?;
                    h
                }
                _ => held.insert(Held {
                    engine: SceneRenderer::new(scene)?,
                    grid: None,
                }),
            };
            if let Some(grid) = grid.filter(|g| h.grid != Some(g.id)) {
                let (model, read) = grid.model();
                h.engine.set_model(model, read);
                h.grid = Some(grid.id);
            }
            let mut notes = Vec::new();
            let frame = h.engine.render()?;
            notes.extend(frame.report.notes.iter().map(note_text));
            let (w, hgt) = frame.image.dimensions();
            let pixels = frame.image.into_raw();
            let image = Array3::from_shape_vec((hgt as usize, w as usize, 4), pixels)
                .map_err(|e| strata::Error::scene(format!("picture: {e}")))?;
            Ok((image, notes))
        })?;
        Ok((image.into_pyarray(py), notes))
    }

    /// How often the engine read a model, built its content and drew a frame.
    fn counters(&self) -> (usize, usize, usize) {
        let held = self.held.lock().ok();
        let c = held
            .as_ref()
            .and_then(|h| h.as_ref())
            .map(|h| h.engine.counters())
            .unwrap_or_default();
        (c.models_read, c.contents_built, c.frames)
    }
}
