//! The model a scene reads: opened once, its property decks added, its warnings and
//! stray corners named, and the report step a scene asks for laid over its
//! properties.

use std::path::Path;

use strata_grid::{CornerPointGrid, ReadOptions, StrayCorners};

use super::Note;
use crate::error::Context;
use crate::scene::ModelSource;
use crate::{Error, Result};

/// A model as read, with what reading it found.
pub struct Model {
    /// What it was read from.
    pub source: ModelSource,
    /// The grid and its properties.
    pub grid: CornerPointGrid,
    /// Its corners far outside the rest, which pictures leave out of their framing.
    pub stray: Option<StrayCorners>,
    /// The report step laid over the static properties, and the names it added.
    step: Option<(i32, Vec<String>)>,
}

impl Model {
    /// Reads `source` and adds the per-cell arrays of each of its property decks;
    /// what reading skipped and the stray corners come back as warnings.
    pub fn open(source: &ModelSource) -> Result<(Self, Vec<Note>)> {
        let options = ReadOptions {
            grid_only: source.grid_only,
            ..ReadOptions::default()
        };
        let mut grid = strata_grid::open_with(&source.path, &options)?;
        for deck in &source.props {
            strata_grid::read_properties(&mut grid, deck).with_context(|| {
                format!(
                    "adding the properties of {} to {}",
                    deck.display(),
                    source.path.display()
                )
            })?;
        }
        Ok(Self::from_grid(source.clone(), grid))
    }

    /// A model of a grid already in memory (read and changed by the caller, or made
    /// from another library's arrays, as the Python package's `Grid` is), named by
    /// `source`; its warnings and stray corners come back as [`Model::open`] gives them.
    pub fn from_grid(source: ModelSource, grid: CornerPointGrid) -> (Self, Vec<Note>) {
        let stray = grid.stray_corners();
        let notes = grid
            .warnings
            .iter()
            .cloned()
            .chain(stray.as_ref().map(|s| stray_warning(s, &source.path)))
            .map(Note::Warning)
            .collect();
        let model = Model {
            source,
            grid,
            stray,
            step: None,
        };
        (model, notes)
    }

    /// Makes the arrays of report step `number` (SEQNUM) the values of their
    /// properties, or the last step's again with `None`. A static property of the
    /// same name keeps its own values.
    pub fn use_step(&mut self, number: Option<i32>) -> Result<()> {
        if self.step.as_ref().map(|s| s.0) == number {
            return Ok(());
        }
        if let Some((_, added)) = self.step.take() {
            for name in added {
                self.grid.properties.remove(&name);
            }
        }
        let Some(number) = number else {
            return Ok(());
        };
        let steps = &self.grid.report_steps;
        let Some(step) = steps.iter().find(|s| s.number == number) else {
            let numbers: Vec<String> = steps.iter().map(|s| s.number.to_string()).collect();
            return Err(Error::scene(format!(
                "{}: no report step {number}{}",
                self.source.path.display(),
                match numbers.is_empty() {
                    true => " (the model has no results)".to_string(),
                    false => format!("; its steps are {}", numbers.join(", ")),
                }
            )));
        };
        let arrays: Vec<(String, _)> = step
            .arrays
            .iter()
            .filter(|(name, _)| !self.grid.properties.contains_key(*name))
            .map(|(name, values)| (name.clone(), values.clone()))
            .collect();
        let mut added = Vec::with_capacity(arrays.len());
        for (name, values) in arrays {
            self.grid.set_property(&name, values)?;
            added.push(name);
        }
        self.step = Some((number, added));
        Ok(())
    }

    /// The property that colours a scene: `named`, or PORO when the model has it.
    pub fn colouring_property(&self, named: Option<&str>, solid: bool) -> Option<String> {
        match (solid, named) {
            (true, _) => None,
            (false, Some(name)) => Some(name.to_string()),
            (false, None) => self.grid.property("PORO").map(|_| "PORO".to_string()),
        }
    }
}

/// Names the corner of the model read from `path` farthest outside the rest of it,
/// of those `stray` found ([`CornerPointGrid::stray_corners`]): one stray depth is
/// enough to pull a face across every picture, and this says which cell to mend.
pub fn stray_warning(stray: &StrayCorners, path: &Path) -> String {
    let w = &stray.worst;
    let [x, y, depth] = w.map;
    let (lo, hi) = (stray.rest.min, stray.rest.max);
    format!(
        "{}: cell {},{},{} has a corner (number {}, on pillar {},{}) at x {x:.2}, y {y:.2}, \
         depth {depth:.2}, far outside the rest of the model (x {:.2} .. {:.2}, y {:.2} .. \
         {:.2}, depth {:.2} .. {:.2}): pictures frame the rest, and the faces that reach \
         it run out of them; {} pillar(s) have corners that far out (over {} interquartile \
         ranges past the quartiles)",
        path.display(),
        w.cell[0] + 1,
        w.cell[1] + 1,
        w.cell[2] + 1,
        w.corner,
        w.pillar[0] + 1,
        w.pillar[1] + 1,
        lo[0],
        hi[0],
        lo[1],
        hi[1],
        lo[2],
        hi[2],
        stray.pillars,
        strata_grid::STRAY_SPREADS,
    )
}
