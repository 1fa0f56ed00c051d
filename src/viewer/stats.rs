//! Frame statistics (`strata view --stats [FILE.json]`): per frame, what was drawn and
//! how long it took; at the end, the median and the worst.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;

use crate::{Error, FrameReport, Result};

/// One frame of the window.
#[derive(Clone, Debug, Serialize)]
pub struct FrameStat {
    /// Frames since the window opened.
    pub frame: usize,
    /// Milliseconds from the viewer's start to the frame's presentation (the first
    /// frame's is how long a model takes to show).
    pub at_ms: f64,
    /// Milliseconds from the start of the frame to its presentation: the panel, the
    /// engine's work and egui's painting.
    pub ms: f64,
    /// Milliseconds the engine took: building what the scene's change needs, then
    /// drawing.
    pub engine_ms: f64,
    /// Of which building (reading, extracting, choosing a hierarchy's nodes).
    pub build_ms: f64,
    /// Of the engine's time, choosing a hierarchy's nodes for the view.
    pub select_ms: f64,
    /// Triangles drawn.
    pub triangles: usize,
    /// Hierarchy nodes drawn (none for a model's own surfaces).
    pub nodes: Option<usize>,
    /// GPU memory allocated, in MiB, where the backend reports it (Vulkan, DirectX 12).
    pub gpu_mib: Option<f64>,
    /// What was drawn, in words (triangles, parts, nodes).
    pub drawn: String,
}

impl FrameStat {
    /// The figures in one line, as the panel shows them.
    pub fn line(&self) -> String {
        let mut line = format!(
            "frame {:.1} ms (engine {:.1}, building {:.1}), {} triangles",
            self.ms, self.engine_ms, self.build_ms, self.triangles
        );
        if let Some(nodes) = self.nodes {
            line += &format!(", {nodes} nodes chosen in {:.1} ms", self.select_ms);
        }
        if let Some(mib) = self.gpu_mib {
            line += &format!(", GPU memory {mib:.0} MiB");
        }
        line
    }

    /// The statistics of frame `frame`, presented `at_ms` after the start, which took
    /// `ms` in all and drew `report`.
    pub fn new(frame: usize, at_ms: f64, ms: f64, report: &FrameReport) -> Self {
        FrameStat {
            frame,
            at_ms,
            ms,
            engine_ms: 1e3 * (report.build_seconds + report.draw_seconds),
            build_ms: 1e3 * report.build_seconds,
            select_ms: 1e3 * report.select_seconds,
            triangles: report.triangles,
            nodes: report.nodes,
            gpu_mib: report.gpu_bytes.map(|b| b as f64 / f64::from(1 << 20)),
            drawn: report.drawn.clone(),
        }
    }
}

/// The frames of a run and where they go.
pub struct Stats {
    frames: Vec<FrameStat>,
    file: Option<PathBuf>,
    /// When the viewer started.
    start: Instant,
}

/// Frame times over a run.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Frames drawn.
    pub frames: usize,
    /// Median frame, milliseconds.
    pub median_ms: f64,
    /// Slowest frame, milliseconds.
    pub worst_ms: f64,
    /// Slowest frame but the first (which reads and builds the model), milliseconds.
    pub worst_after_first_ms: f64,
    /// Milliseconds from the viewer's start to the first picture presented.
    pub first_picture_ms: f64,
}

impl Stats {
    /// Statistics kept in memory, and written per frame to `file` when given.
    pub fn new(file: Option<PathBuf>) -> Self {
        Stats {
            frames: Vec::new(),
            file,
            start: Instant::now(),
        }
    }

    /// Adds a frame, just presented, which took `ms` in all and drew `report`.
    pub fn record(&mut self, ms: f64, report: &FrameReport) {
        let n = self.frames.len();
        let at_ms = 1e3 * self.start.elapsed().as_secs_f64();
        self.frames.push(FrameStat::new(n, at_ms, ms, report));
    }

    /// The last frame recorded.
    pub fn last(&self) -> Option<&FrameStat> {
        self.frames.last()
    }

    /// Median and worst frame times.
    pub fn summary(&self) -> Summary {
        let mut ms: Vec<f64> = self.frames.iter().map(|f| f.ms).collect();
        let worst_after_first = ms.iter().skip(1).copied().fold(0.0, f64::max);
        ms.sort_by(f64::total_cmp);
        Summary {
            frames: ms.len(),
            median_ms: ms.get(ms.len() / 2).copied().unwrap_or(0.0),
            worst_ms: ms.last().copied().unwrap_or(0.0),
            worst_after_first_ms: worst_after_first,
            first_picture_ms: self.frames.first().map_or(0.0, |f| f.at_ms),
        }
    }

    /// Writes the frames to the file given, if any.
    pub fn write(&self) -> Result<()> {
        let Some(path) = &self.file else {
            return Ok(());
        };
        write_json(
            path,
            &serde_json::json!({
                "summary": self.summary(),
                "frames": self.frames,
            }),
        )
    }
}

/// Writes `value` as pretty JSON to `path`.
pub fn write_json(path: &Path, value: &impl Serialize) -> Result<()> {
    let text = serde_json::to_string_pretty(value).map_err(|e| Error::scene(e.to_string()))?;
    std::fs::write(path, text).map_err(|e| Error::File {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}
