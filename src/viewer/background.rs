//! A hierarchy built behind the window.
//!
//! A model with more active cells than a scene draws whole (`part_cells`) would take
//! seconds a frame. The window opens it at once on a preview, its top layer decimated
//! to a few ten thousand triangles, while a thread on all cores but one reads the model
//! again and builds its hierarchy into `MODEL.lod` beside it (or in the temporary
//! folder where that folder is not writable); the window then draws the hierarchy. A
//! hierarchy found beside the model, newer than it, is used at once.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::thread::JoinHandle;

use strata_lod::{BuildOptions, Progress, build_file, partial_path};

use crate::engine::Model;
use crate::scene::{Lod, ModelSource, Scene};
use crate::{Error, Result};

/// Triangles the preview is decimated to.
const PREVIEW_TRIANGLES: f64 = 40_000.0;

/// A hierarchy being built.
pub struct Build {
    /// Where it goes.
    pub path: PathBuf,
    done: Arc<AtomicU64>,
    total: Arc<AtomicU64>,
    thread: Option<JoinHandle<Result<()>>>,
}

/// Where the hierarchy of `model` is kept: `MODEL.lod` beside it.
pub fn beside(model: &Path) -> PathBuf {
    model.with_extension("lod")
}

/// The hierarchy kept beside `model`, when there is one newer than the model.
pub fn kept(model: &Path) -> Option<PathBuf> {
    let lod = beside(model);
    let modified = |p: &Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    (modified(&lod)? >= modified(model)?).then_some(lod)
}

/// `scene` drawing `model`'s top layer (or the first layer it asks for) decimated to
/// about [`PREVIEW_TRIANGLES`], without sides.
pub fn preview(scene: &Scene, model: &Model) -> Scene {
    let d = model.grid.dims();
    let top = scene.layers.map_or(1, |[first, _]| first);
    let triangles = 2.0 * (d.nx * d.ny) as f64;
    Scene {
        layers: Some([top, top]),
        sides: false,
        lod: Lod::Decimated {
            percent: (100.0 * PREVIEW_TRIANGLES / triangles).clamp(0.01, 100.0),
            cover: false,
            stitch: false,
        },
        ..scene.clone()
    }
}

/// `scene` drawing the hierarchy at `path` with what a hierarchy draws of `scene`'s
/// choices (its layers, sides, style and camera), its model kept for picking.
pub fn on_hierarchy(scene: &Scene, path: &Path) -> Scene {
    let mut hierarchy = Scene::of_hierarchy(path);
    // The model stays open for the picked cells' values.
    hierarchy.model.clone_from(&scene.model);
    hierarchy.layers = scene.layers;
    hierarchy.sides = scene.sides;
    hierarchy.wire = scene.wire.clone();
    hierarchy.isolines = scene.isolines.clone().map(|mut iso| {
        iso.property = None;
        iso
    });
    hierarchy.grid_lines = scene.grid_lines;
    hierarchy.camera = scene.camera;
    hierarchy.size = scene.size;
    hierarchy
}

impl Build {
    /// Starts building the hierarchy of `source`, coloured by `property`, into `path`.
    pub fn start(source: ModelSource, property: Option<String>, path: PathBuf) -> Build {
        let done = Arc::new(AtomicU64::new(0));
        let total = Arc::new(AtomicU64::new(0));
        let (d, t, out) = (done.clone(), total.clone(), path.clone());
        let thread = std::thread::spawn(move || {
            let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(cores.saturating_sub(1).max(1))
                .build()
                .map_err(|e| Error::scene(format!("no threads to build the hierarchy: {e}")))?;
            let (model, _) = Model::open(&source)?;
            let options = BuildOptions {
                progress: Some(Arc::new(move |p| match p {
                    Progress::Started { work, .. } => t.store(work, Ordering::Relaxed),
                    Progress::Worked(units) => {
                        d.fetch_add(units, Ordering::Relaxed);
                    }
                    Progress::Written { .. } => {}
                })),
                memory: crate::memory::available_memory().map(|b| b as u64),
                ..BuildOptions::default()
            };
            // Built aside and renamed: a half-written file is never taken for a hierarchy.
            let part = Build::part(&out);
            pool.install(|| build_file(&model.grid, property.as_deref(), &part, &options))?;
            std::fs::rename(&part, &out).map_err(|e| Error::File {
                path: out.clone(),
                message: e.to_string(),
            })
        });
        Build {
            path,
            done,
            total,
            thread: Some(thread),
        }
    }

    /// Where the build writes before renaming: `MODEL.lod.part`, itself written
    /// through strata-lod's hidden partial file.
    fn part(path: &Path) -> PathBuf {
        path.with_extension("lod.part")
    }

    /// How far the build is, 0 to 1.
    pub fn fraction(&self) -> f32 {
        let total = self.total.load(Ordering::Relaxed).max(1);
        (self.done.load(Ordering::Relaxed) as f64 / total as f64).min(1.0) as f32
    }

    /// The hierarchy's path once the build is over (or why it failed); `None` while it
    /// goes on, unless `wait`.
    pub fn finished(&mut self, wait: bool) -> Option<Result<PathBuf>> {
        if !wait && !self.thread.as_ref()?.is_finished() {
            return None;
        }
        let joined = self.thread.take()?.join();
        Some(match joined {
            Ok(Ok(())) => Ok(self.path.clone()),
            Ok(Err(e)) => Err(e),
            Err(_) => Err(Error::scene("the hierarchy's build stopped with a panic")),
        })
    }
}

/// Where to build `model`'s hierarchy: beside it where its folder takes a file, else
/// in the temporary folder.
pub fn destination(model: &Path) -> PathBuf {
    let beside = beside(model);
    let probe = beside.with_extension("lod.probe");
    if std::fs::write(&probe, b"").is_ok() {
        let _ = std::fs::remove_file(&probe);
        return beside;
    }
    let name = beside
        .file_name()
        .map_or_else(|| "model.lod".into(), |n| n.to_os_string());
    std::env::temp_dir().join(name)
}

impl Drop for Build {
    /// A build left unfinished (the window closed) dies with the process, before its
    /// writer can clean up: its partial file is removed here, so nothing half-written
    /// stays beside the model.
    fn drop(&mut self) {
        if self.thread.as_ref().is_some_and(|t| !t.is_finished()) {
            let _ = std::fs::remove_file(partial_path(&Build::part(&self.path)));
        }
    }
}
