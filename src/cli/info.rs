//! `strata info`: what a model holds, or the corners and values of one cell.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use clap::Args;
use serde::Serialize;
use strata::grid::ndarray::Array3;
use strata::grid::{BoundingBox, Content, CornerPointGrid, Dims, MapAxes, Units};
use strata::lod::LodFile;

use super::ReadArgs;

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

#[derive(Serialize)]
struct CellInfo {
    file: String,
    /// 1-based I, J, K.
    cell: [usize; 3],
    active: bool,
    /// The order of `corners`.
    corner_order: &'static str,
    /// Map coordinates (x, y, depth) of the 8 corners.
    corners: [[f64; 3]; 8],
    /// Static properties, then the arrays of the last report step; null where undefined.
    values: Vec<(String, Option<f32>)>,
}

/// What `strata info` says of a hierarchy file.
#[derive(Serialize)]
struct HierarchyInfo {
    file: String,
    bytes: u64,
    /// Cells of the (i, j) domain.
    dims: [u32; 2],
    grid_layers: usize,
    layer_surfaces: usize,
    tile_cells: u32,
    /// Display frame (map x, map y, elevation) that positions are relative to.
    origin: [f64; 3],
    /// Display-frame bounds of the layer surfaces (origin added).
    min: [f64; 3],
    max: [f64; 3],
    /// Level 0 (the leaves, full resolution) first.
    levels: Vec<LevelInfo>,
    /// The stored property's range over the active cells, when one is stored.
    property_range: Option<[f32; 2]>,
    /// Side faces (outer shell and fault walls), at full resolution.
    side_faces: u64,
    /// When the model has stray corners, the bounds (display frame, origin added) of
    /// the rest of it, which views frame.
    framed: Option<[[f64; 3]; 2]>,
}

#[derive(Serialize)]
struct LevelInfo {
    level: u32,
    nodes: usize,
    triangles: u64,
    /// Largest horizontal and vertical geometric error of its nodes (display units).
    max_error: [f32; 2],
}

fn hierarchy_info(path: &Path, json: bool) -> Result<()> {
    let file = LodFile::open(path)?;
    // By level, as stored: a damaged file's level numbers may be anything.
    let mut levels = std::collections::BTreeMap::<u32, LevelInfo>::new();
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for n in file.nodes() {
        let l = levels.entry(n.level).or_insert(LevelInfo {
            level: n.level,
            nodes: 0,
            triangles: 0,
            max_error: [0.0; 2],
        });
        l.nodes += 1;
        l.triangles += u64::from(n.index_count / 3);
        l.max_error = [
            l.max_error[0].max(n.error[0]),
            l.max_error[1].max(n.error[1]),
        ];
        for a in 0..3 {
            lo[a] = lo[a].min(n.min[a]);
            hi[a] = hi[a].max(n.max[a]);
        }
    }
    let origin = file.origin();
    let info = HierarchyInfo {
        file: path.display().to_string(),
        bytes: std::fs::metadata(path)?.len(),
        dims: file.dims(),
        grid_layers: file
            .layers()
            .iter()
            .map(|l| l.k as usize + 1)
            .max()
            .unwrap_or(0),
        layer_surfaces: file.layers().len(),
        tile_cells: file.tile_cells(),
        origin,
        min: std::array::from_fn(|a| origin[a] + f64::from(lo[a])),
        max: std::array::from_fn(|a| origin[a] + f64::from(hi[a])),
        levels: levels.into_values().collect(),
        property_range: file.scalar_range().map(|(a, b)| [a, b]),
        side_faces: file.layers().iter().map(|l| u64::from(l.side_faces)).sum(),
        framed: file
            .framed()
            .map(|b| b.map(|c| std::array::from_fn(|a| origin[a] + f64::from(c[a])))),
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&info)?);
        return Ok(());
    }
    println!("{} (level-of-detail hierarchy)", info.file);
    println!("  size           {}", super::lod::size_text(info.bytes));
    println!(
        "  cells          {} x {} (i, j), {} grid layers, {} layer surfaces",
        info.dims[0], info.dims[1], info.grid_layers, info.layer_surfaces
    );
    if info.levels.is_empty() {
        println!("  no nodes");
    } else {
        println!("  x              {:.2} .. {:.2}", info.min[0], info.max[0]);
        println!("  y              {:.2} .. {:.2}", info.min[1], info.max[1]);
        println!("  elevation      {:.2} .. {:.2}", info.min[2], info.max[2]);
    }
    if let Some([lo, hi]) = info.framed {
        println!(
            "  framed         x {:.2} .. {:.2}, y {:.2} .. {:.2}, elevation {:.2} .. {:.2}: \
             the model has stray corners, which views leave out",
            lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]
        );
    }
    println!(
        "  leaf tiles     {} x {} cells",
        info.tile_cells, info.tile_cells
    );
    for l in &info.levels {
        println!(
            "  level {:<8} {} nodes, {} triangles, error up to {:.3} across, {:.3} up",
            l.level, l.nodes, l.triangles, l.max_error[0], l.max_error[1]
        );
    }
    match info.property_range {
        Some([a, b]) => println!("  property       {a} .. {b} over the active cells"),
        None => println!("  property       none"),
    }
    println!(
        "  side faces     {} (full resolution, two triangles each)",
        info.side_faces
    );
    Ok(())
}

const CORNER_ORDER: &str = "Eclipse order: top face (I,J) (I+1,J) (I,J+1) (I+1,J+1), then the bottom face in the same order";

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
        return hierarchy_info(path, args.json);
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
    let Dims { nx, ny, nz } = grid.dims();
    let [ci, cj, ck] = cell;
    if ci > nx || cj > ny || ck > nz {
        bail!("cell {ci},{cj},{ck} is outside the grid of {nx} x {ny} x {nz} cells");
    }
    let (i, j, k) = (ci - 1, cj - 1, ck - 1);
    let value = |a: &Array3<f32>| {
        let v = a[[k, j, i]];
        (!v.is_nan()).then_some(v)
    };
    let mut values: Vec<(String, Option<f32>)> = grid
        .properties
        .iter()
        .map(|(n, a)| (n.clone(), value(a)))
        .collect();
    if let Some(step) = grid.report_steps.last() {
        values.extend(
            step.arrays
                .iter()
                .map(|(n, a)| (format!("{n}@{}", step.number), value(a))),
        );
    }
    let info = CellInfo {
        file,
        cell,
        active: grid.is_active(i, j, k),
        corner_order: CORNER_ORDER,
        corners: grid.cell_corners(i, j, k),
        values,
    };
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
