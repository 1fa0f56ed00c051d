//! `strata view`: opens the interactive window on a model, a hierarchy or a scene.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use strata::Scene;
use strata::scene::ModelSource;
use strata::viewer::{self, Options};

use crate::cli::parse::parse_size;

#[derive(Args)]
pub struct ViewArgs {
    /// Model file (.grdecl, .DATA, .EGRID) or a hierarchy (.lod) written by `strata
    /// lod build`; the sample in data/ when omitted.
    model: Option<PathBuf>,
    /// Open this scene (JSON, as `render --save-scene` writes it) instead.
    #[arg(long, value_name = "FILE.json", conflicts_with = "model")]
    scene: Option<PathBuf>,
    /// GRDECL decks of per-cell properties to add.
    #[arg(long = "props", value_name = "FILE")]
    props: Vec<PathBuf>,
    /// Run the commands in FILE (one per line: orbit, set, frames, pick, wait,
    /// screenshot, save, load, quit) instead of waiting for the user, then close.
    #[arg(long, value_name = "FILE")]
    script: Option<PathBuf>,
    /// Print frame statistics when the window closes (median and worst frame), and
    /// write them per frame to FILE.json when given.
    #[arg(long, value_name = "FILE.json", num_args = 0..=1, default_missing_value = "-")]
    stats: Option<PathBuf>,
    /// Inner size of the window in pixels.
    #[arg(long, default_value = "1280x800", value_parser = parse_size)]
    size: (u32, u32),
}

pub fn run(args: &ViewArgs) -> Result<()> {
    let scene = match (&args.scene, &args.model) {
        (Some(file), _) => Scene::load(file)?,
        (None, Some(path)) if path.extension().is_some_and(|e| e == "lod") => {
            if !args.props.is_empty() {
                bail!(
                    "{}: a hierarchy is coloured by the property it stores; --props needs a model",
                    path.display()
                );
            }
            Scene::of_hierarchy(path)
        }
        (None, model) => {
            let path = model.clone().unwrap_or_else(strata::sample_model);
            Scene {
                model: Some(ModelSource {
                    props: args.props.clone(),
                    ..ModelSource::new(path)
                }),
                ..Scene::default()
            }
        }
    };
    let stats_file = args.stats.clone().filter(|p| p.as_os_str() != "-");
    let summary = viewer::run(Options {
        scene,
        script: args.script.clone(),
        stats_file,
        size: [args.size.0, args.size.1],
    })?;
    if args.stats.is_some() {
        println!("{}", serde_json::to_string(&summary)?);
    }
    Ok(())
}
