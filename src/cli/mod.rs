//! One module per subcommand of the `strata` binary.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use strata::grid::{CornerPointGrid, ReadOptions, StrayCorners};

pub mod info;
pub mod lod;
pub mod render;
pub mod style;
pub mod synth;
pub mod terrain;

/// How the commands that read a model read it.
#[derive(Args)]
pub struct ReadArgs {
    /// GRDECL decks of per-cell properties to add (e.g. PORO beside an EGRID).
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

/// Saves `image` to `path`, and says so when it is `background` alone: no part of the
/// model covered a pixel, and the user would otherwise find a blank picture.
pub fn save_picture(
    image: &strata::render::image::RgbaImage,
    background: [f32; 4],
    path: &Path,
) -> Result<()> {
    strata::render::save_png(image, path)?;
    let clear = background.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
    if image.pixels().all(|p| p.0 == clear) {
        eprintln!(
            "note: {}: the background alone, no part of the model covers a pixel; the view \
             frames the model's extent, which `strata info` on the model gives: a few stray \
             depths or coordinates can stretch it until the rest is a speck",
            path.display()
        );
    }
    Ok(())
}

/// Opens `model` (the sample in `data/` when `None`) as `read` says, and adds the
/// per-cell arrays of each of its property decks (e.g. the PORO GRDECL that goes with
/// an EGRID).
pub fn open_model(model: Option<&Path>, read: &ReadArgs) -> Result<(PathBuf, CornerPointGrid)> {
    let path = model.map_or_else(crate::sample_model, Path::to_path_buf);
    let options = ReadOptions {
        grid_only: read.grid_only,
        ..ReadOptions::default()
    };
    let mut grid = strata::grid::open_with(&path, &options)?;
    add_properties(&mut grid, &path, &read.props)?;
    Ok((path, grid))
}

/// Prints what reading `grid` (from `path`) skipped (missing INCLUDE files, unreadable
/// results, local grids) and its stray corners ([`stray_warning`]) on standard error,
/// for the commands whose output is a picture or a file; the stray corners, which a
/// picture leaves out of its framing.
pub fn warn_about(grid: &CornerPointGrid, path: &Path) -> Option<StrayCorners> {
    let stray = grid.stray_corners();
    for warning in grid
        .warnings
        .iter()
        .cloned()
        .chain(stray.as_ref().map(|s| stray_warning(s, path)))
    {
        eprintln!("strata: warning: {warning}");
    }
    stray
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
        strata::grid::STRAY_SPREADS,
    )
}

/// Adds to `grid`, read from `path`, the per-cell arrays of each property deck in
/// `props`.
fn add_properties(grid: &mut CornerPointGrid, path: &Path, props: &[PathBuf]) -> Result<()> {
    for deck in props {
        strata::grid::grdecl::read_properties(grid, deck).with_context(|| {
            format!(
                "adding the properties of {} to {}",
                deck.display(),
                path.display()
            )
        })?;
    }
    Ok(())
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

/// Refuses work that needs about `needed` bytes when the system has less available
/// (Linux's MemAvailable; elsewhere nothing is known and nothing is refused): past the
/// memory there is, the allocator aborts or the system's OOM killer ends the run long
/// after it started. `what` and `doing` name the work in the message.
pub fn check_memory(needed: f64, what: &str, doing: &str) -> Result<()> {
    if let Some(available) = available_memory()
        && needed > available
    {
        anyhow::bail!(
            "{what} need about {:.1} GB {doing}, and {:.1} GB of memory is available",
            needed / 1e9,
            available / 1e9
        );
    }
    Ok(())
}

/// Memory the system can still give this process without swapping, in bytes
/// (Linux's MemAvailable; `None` where it is not known).
pub fn available_memory() -> Option<f64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kb = info
        .lines()
        .find_map(|l| l.strip_prefix("MemAvailable:"))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse::<f64>()
        .ok()?;
    Some(1024.0 * kb)
}

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
