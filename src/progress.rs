//! Progress of the engine's long steps, reported through a callback so that each front
//! end shows it its own way (a terminal bar, a window's, a notebook's).

/// A long step of drawing a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// The pass over a large scene's corners that frames it before any part is drawn
    /// (counted in rows of tiles).
    Framing,
    /// Drawing a large scene a part at a time (counted in parts).
    Parts,
}

impl Stage {
    /// What the stage does, for a progress bar's label.
    pub fn label(self) -> &'static str {
        match self {
            Stage::Framing => "framing: rows of tiles",
            Stage::Parts => "drawing: parts",
        }
    }
}

/// How far a stage has come: `done` of `total` units; `done == total` ends it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// The step under way.
    pub stage: Stage,
    /// Units finished.
    pub done: usize,
    /// Units in all.
    pub total: usize,
}

/// The callback a front end hands the engine; called from worker threads.
pub type ProgressFn = dyn Fn(Progress) + Send + Sync;
