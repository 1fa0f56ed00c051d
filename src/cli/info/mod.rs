//! `strata info`: what a model holds, or the corners and values of one cell.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use serde::Serialize;
use strata::cell::{CORNER_ORDER, CellInfo};
use strata::grid::{BoundingBox, Content, CornerPointGrid, Dims, MapAxes, Units};

use crate::cli::ReadArgs;

mod hierarchy;

#[derive(Args)]
pub struct InfoArgs {
    /// Model file (.grdecl, .DATA, .EGRID), or a hierarchy written by `strata lod
    /// build` (summarised: levels, nodes, triangles, errors); the sample in data/ when
    /// omitted.
    model: Option<PathBuf>,
    /// One cell, 1-based as reservoir tools number them: I,J,K.
    #[arg(long, value_name = "I,J,K", value_parser = parse_cell)]
    cell: Option<[usize; 3]>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    read: ReadArgs,
}

fn parse_cell(s: &str) -> Result<[usize; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [i, j, k] = parts.as_slice() else {
        return Err(format!("expected I,J,K, got {s:?}"));
    };
    let num = |v: &str| match v.parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("{v:?} is not a 1-based cell index")),
    };
    Ok([num(i)?, num(j)?, num(k)?])
}

#[derive(Serialize)]
struct ModelInfo {
    file: String,
    dims: Dims,
    cells: usize,
    active_cells: usize,
    /// Map coordinates (x, y, depth), over the active cells.
    bounding_box: BoundingBox,
    units: Units,
    mapaxes: Option<MapAxes>,
    properties: Vec<String>,
    report_steps: Vec<StepInfo>,
    fault_split_fraction: f64,
    warnings: Vec<String>,
}

#[derive(Serialize)]
struct StepInfo {
    number: i32,
    date: Option<String>,
    arrays: Vec<String>,
}

pub fn run(args: &InfoArgs) -> Result<()> {
    if let Some(path) = &args.model
        && Content::of_file(path)? == Content::Hierarchy
    {
        if args.cell.is_some() || args.read.given() {
            bail!(
                "{}: a level-of-detail hierarchy has no cells to show or properties to add; \
                 --cell, --props and --grid-only need a model",
                path.display()
            );
        }
        return hierarchy::info(path, args.json);
    }
    let (model, notes) = super::open_model(args.model.as_deref(), &args.read)?;
    let file = model.source.path.display().to_string();
    let warnings = notes
        .into_iter()
        .filter_map(|note| match note {
            strata::Note::Warning(text) => Some(text),
            _ => None,
        })
        .collect();
    match args.cell {
        Some(cell) => cell_info(&model.grid, file, cell, args.json),
        None => model_info(&model.grid, file, warnings, args.json),
    }
}

fn model_info(
    grid: &CornerPointGrid,
    file: String,
    warnings: Vec<String>,
    json: bool,
) -> Result<()> {
    let info = ModelInfo {
        file,
        dims: grid.dims(),
        cells: grid.cell_count(),
        active_cells: grid.active_count(),
        bounding_box: grid.bounding_box(),
        units: grid.units,
        mapaxes: grid.mapaxes,
        properties: grid.properties.keys().cloned().collect(),
        report_steps: grid
            .report_steps
            .iter()
            .map(|s| StepInfo {
                number: s.number,
                date: s.date.map(|(y, m, d)| format!("{y:04}-{m:02}-{d:02}")),
                arrays: s.arrays.keys().cloned().collect(),
            })
            .collect(),
        fault_split_fraction: grid.fault_split_fraction(),
        warnings,
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&info)?);
        return Ok(());
    }
    let Dims { nx, ny, nz } = info.dims;
    let b = &info.bounding_box;
    println!("{}", info.file);
    println!("  dimensions     {nx} x {ny} x {nz}");
    println!(
        "  cells          {} ({} active, {:.1} %)",
        info.cells,
        info.active_cells,
        100.0 * info.active_cells as f64 / info.cells as f64
    );
    println!("  units          {}", info.units.eclipse_name());
    if !b.is_empty() {
        println!("  x              {:.2} .. {:.2}", b.min[0], b.max[0]);
        println!("  y              {:.2} .. {:.2}", b.min[1], b.max[1]);
        println!("  depth          {:.2} .. {:.2}", b.min[2], b.max[2]);
    }
    if let Some(m) = &info.mapaxes {
        println!("  mapaxes        {:?}", m.values());
    }
    println!(
        "  fault split    {:.2} % of interior faces",
        100.0 * info.fault_split_fraction
    );
    println!(
        "  properties     {}",
        if info.properties.is_empty() {
            "none".into()
        } else {
            info.properties.join(", ")
        }
    );
    if !info.report_steps.is_empty() {
        println!("  report steps   {}", info.report_steps.len());
        for s in &info.report_steps {
            println!(
                "    {:>4}  {}  {}",
                s.number,
                s.date.as_deref().unwrap_or("----------"),
                s.arrays.join(" ")
            );
        }
    }
    for w in &info.warnings {
        println!("  warning: {w}");
    }
    Ok(())
}

fn cell_info(grid: &CornerPointGrid, file: String, cell: [usize; 3], json: bool) -> Result<()> {
    let [ci, cj, ck] = cell;
    let info = CellInfo::of(grid, file, cell)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&info)?);
        return Ok(());
    }
    println!(
        "{} cell {ci},{cj},{ck} ({})",
        info.file,
        if info.active { "active" } else { "inactive" }
    );
    println!("  corners ({})", CORNER_ORDER);
    for (n, c) in info.corners.iter().enumerate() {
        println!("    {n}  {:>14.3} {:>14.3} {:>10.3}", c[0], c[1], c[2]);
    }
    for (name, v) in &info.values {
        match v {
            Some(v) => println!("  {name:<12} {v}"),
            None => println!("  {name:<12} undefined"),
        }
    }
    Ok(())
}
