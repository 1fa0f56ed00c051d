//! One module per subcommand of the `strata` binary.

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;
use strata::Note;
use strata::engine::Model;
use strata::scene::ModelSource;

pub mod bench;
pub mod info;
pub mod lod;
pub mod parse;
pub mod render;
pub mod style;
pub mod synth;
pub mod terrain;
#[cfg(feature = "viewer")]
pub mod view;

/// How the commands that read a model read it.
#[derive(Args)]
pub struct ReadArgs {
    /// Per-cell properties to add: GRDECL decks (e.g. PORO beside an EGRID) or ROFF
    /// parameter files (e.g. b_poro.roff beside b_grid.roff).
    #[arg(long = "props", value_name = "FILE")]
    pub props: Vec<PathBuf>,
    /// Read the grid only: no properties or results, and a deck goes on past INCLUDE
    /// files that are missing (e.g. a .DATA deck shipped without its property files),
    /// each named in a warning; the decks given with --props are still added.
    #[arg(long)]
    pub grid_only: bool,
}

impl ReadArgs {
    /// Whether any option asks for more than the model's own file.
    pub fn given(&self) -> bool {
        self.grid_only || !self.props.is_empty()
    }
}

/// Saves a frame's picture to `path`, and says so when it is the background alone:
/// no part of the model covered a pixel, and the user would otherwise find a blank
/// picture.
pub fn save_picture(frame: &strata::Frame, path: &Path) -> Result<()> {
    strata::render::save_png(&frame.image, path)?;
    if frame.report.blank {
        eprintln!(
            "note: {}: the background alone, no part of the model covers a pixel; the view \
             frames the model's extent, which `strata info` on the model gives: a few stray \
             depths or coordinates can stretch it until the rest is a speck",
            path.display()
        );
    }
    Ok(())
}

/// A terminal progress bar per long step of the engine (hidden where standard error
/// is not a terminal).
pub fn progress_bars() -> Box<strata::progress::ProgressFn> {
    use strata::progress::{Progress, Stage};
    let style = indicatif::ProgressStyle::with_template(
        "{elapsed_precise} [{bar:40}] {msg} {pos}/{len} (eta {eta})",
    )
    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
    let bar: std::sync::Mutex<Option<(Stage, indicatif::ProgressBar)>> = Default::default();
    Box::new(move |p: Progress| {
        let Ok(mut held) = bar.lock() else {
            return;
        };
        if held.as_ref().is_none_or(|(stage, _)| *stage != p.stage) {
            let new = indicatif::ProgressBar::new(p.total as u64)
                .with_style(style.clone())
                .with_message(p.stage.label());
            *held = Some((p.stage, new));
        }
        if let Some((_, bar)) = held.as_ref() {
            bar.set_position(p.done as u64);
            if p.done >= p.total {
                bar.finish_and_clear();
            }
        }
    })
}

/// Opens `model` (the sample in `data/` when `None`) as `read` says, with the
/// per-cell arrays of each of its property decks added (e.g. the PORO GRDECL that
/// goes with an EGRID), and what reading it found to warn about.
pub fn open_model(model: Option<&Path>, read: &ReadArgs) -> Result<(Model, Vec<Note>)> {
    let source = ModelSource {
        path: model.map_or_else(strata::sample_model, Path::to_path_buf),
        props: read.props.clone(),
        grid_only: read.grid_only,
    };
    Ok(Model::open(&source)?)
}

/// Refuses to write `output` over one of the files a command reads (`inputs`: the
/// model and its property decks, a hierarchy, terrain picks): `lod build MODEL -o
/// MODEL` replaced the model with its hierarchy. The same file by another name (a
/// link, `./`) is found too.
pub fn refuse_overwriting(output: &Path, inputs: &[&Path]) -> Result<()> {
    if let Some(input) = inputs.iter().find(|input| same_file(output, input)) {
        anyhow::bail!(
            "{}: is {}, which this command reads; choose another output",
            output.display(),
            input.display()
        );
    }
    Ok(())
}

/// Whether `a` and `b` both exist and are one file: the same device and inode.
#[cfg(unix)]
fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    let id = |p: &Path| std::fs::metadata(p).map(|m| (m.dev(), m.ino()));
    matches!((id(a), id(b)), (Ok(a), Ok(b)) if a == b)
}

/// Whether `a` and `b` both exist and are one file (where there are no inode numbers
/// to compare: by their canonical paths).
#[cfg(not(unix))]
fn same_file(a: &Path, b: &Path) -> bool {
    matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b)
}

pub use strata::memory::{available_memory, check_memory};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_output_that_is_an_input_by_any_name_is_refused() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let model = dir.path().join("model.egrid");
        std::fs::write(&model, b"model").expect("written");
        let other = dir.path().join("other.lod");
        std::fs::write(&other, b"other").expect("written");
        let fresh = dir.path().join("fresh.lod");
        let dotted = dir.path().join(".").join("model.egrid");
        let refused = |output: &Path| refuse_overwriting(output, &[&other, &model]).is_err();
        assert!(refused(&model));
        assert!(refused(&dotted));
        #[cfg(unix)]
        {
            let linked = dir.path().join("linked.egrid");
            std::os::unix::fs::symlink(&model, &linked).expect("a symbolic link");
            let hard = dir.path().join("hard.egrid");
            std::fs::hard_link(&model, &hard).expect("a hard link");
            assert!(refused(&linked));
            assert!(refused(&hard));
        }
        assert!(!refused(&fresh), "a file that is not there yet");
        assert!(
            refuse_overwriting(&other, &[&model]).is_ok(),
            "another existing file may be replaced"
        );
        let said = refuse_overwriting(&model, &[&model])
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(said.contains("choose another output"), "{said}");
    }
}
