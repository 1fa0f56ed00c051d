//! `strata info MODEL.lod`: what a hierarchy file holds, level by level.

use std::path::Path;

use anyhow::Result;
use serde::Serialize;
use strata::lod::LodFile;

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

/// Prints what the hierarchy file `path` holds: a table, or JSON with `json`.
pub fn info(path: &Path, json: bool) -> Result<()> {
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
    println!(
        "  size           {}",
        crate::cli::lod::size_text(info.bytes)
    );
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
