//! The tiled hierarchy: crack-free borders between neighbours at any two levels,
//! errors that grow towards the root, and the saved file read back by memory mapping.

mod common;

use common::{faulted_grid, layer, one_tile_top, shared_data};
use std::collections::HashMap;
use std::ops::Range;
use strata_grid::faults::fault_traces;
use strata_grid::synth::{SynthParams, generate};
use strata_grid::{
    CornerPointGrid, Face, ReadOptions, SurfaceMesh, Surfaces, layer_surfaces, side_surfaces,
};
use strata_lod::measure::deviation;

use strata_lod::{
    BuildOptions, CellCover, LayerRecord, LayerTree, LodFile, Node, NodeRecord, ViewPoint,
    build_file, build_layer,
};

/// The full-resolution surface that layer surface `layer` of a file built from `grid`
/// stores, with `property` as its scalar.
fn stored_surface(
    grid: &CornerPointGrid,
    layer: &LayerRecord,
    property: Option<&str>,
) -> SurfaceMesh {
    let face = if layer.face == 0 {
        Face::Top
    } else {
        Face::Bottom
    };
    layer_surfaces(
        grid,
        face,
        &Surfaces::layer(layer.k as usize, [0.0; 3]).property(property),
    )
    .unwrap()
}

/// How many of the nodes `chosen` draw each cell of layer surface `l`, row by row.
fn times_drawn(file: &LodFile, chosen: &[u32], l: usize) -> Vec<u8> {
    let [ni, nj] = file.dims();
    let mut cells = vec![0u8; ni as usize * nj as usize];
    for n in chosen.iter().map(|&i| &file.nodes()[i as usize]) {
        if n.layer as usize == l {
            for j in n.cells[1]..n.cells[3] {
                for i in n.cells[0]..n.cells[2] {
                    cells[(j * ni + i) as usize] += 1;
                }
            }
        }
    }
    cells
}

fn options(tile_cells: u32) -> BuildOptions {
    BuildOptions {
        tile_cells,
        ..BuildOptions::default()
    }
}

/// A faulted `nx` x `ny` grid, its second layer's top surface, and that surface's
/// tree in tiles of `tile_cells`.
fn layer_tree(nx: usize, ny: usize, tile_cells: u32) -> (CornerPointGrid, SurfaceMesh, LayerTree) {
    let grid = faulted_grid(nx, ny);
    let mesh = layer(&grid, 1);
    let tree = build_layer(&mesh, [nx as u32, ny as u32], &options(tile_cells)).unwrap();
    (grid, mesh, tree)
}

/// The hierarchy of `grid` in tiles of `tile_cells`, saved in a temporary folder
/// (kept while the folder is) and opened.
fn saved(grid: &CornerPointGrid, tile_cells: u32) -> (tempfile::TempDir, LodFile) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.lod");
    build_file(grid, None, &path, &options(tile_cells)).unwrap();
    let file = LodFile::open(&path).unwrap();
    (dir, file)
}

fn distance_to_segment(p: [f64; 3], s: [[f32; 3]; 2]) -> f64 {
    let (a, b) = (s[0].map(f64::from), s[1].map(f64::from));
    let e: [f64; 3] = std::array::from_fn(|k| b[k] - a[k]);
    let len2: f64 = e.iter().map(|x| x * x).sum();
    let t = if len2 > 0.0 {
        ((0..3).map(|k| (p[k] - a[k]) * e[k]).sum::<f64>() / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (0..3)
        .map(|k| (a[k] + t * e[k] - p[k]).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Checks the border edges of node `a` on the stretch `lo..=hi` (texture units) of
/// the grid line `line` where the original surface continues across the line (an
/// interior edge of the original: not a fault trace, hole or outline, where the two
/// sides legitimately part): five points along each must lie on the border of `b`.
/// Returns the number of edges checked.
fn covered(
    a: &Node,
    b: &Node,
    original: &HashMap<(u32, u32), usize>,
    (axis, line, lo, hi): (usize, f32, f32, f32),
) -> usize {
    let other = 1 - axis;
    let on_stretch = |m: &SurfaceMesh, v: u32| {
        let t = m.texcoords[v as usize];
        t[axis] == line && t[other] >= lo && t[other] <= hi
    };
    let theirs: Vec<[[f32; 3]; 2]> = common::edge_uses(&b.mesh)
        .into_iter()
        .filter(|&((p, q), u)| u == 1 && on_stretch(&b.mesh, p) && on_stretch(&b.mesh, q))
        .map(|((p, q), _)| [b.mesh.positions[p as usize], b.mesh.positions[q as usize]])
        .collect();
    let mut checked = 0;
    for ((p, q), u) in common::edge_uses(&a.mesh) {
        if u != 1 || !on_stretch(&a.mesh, p) || !on_stretch(&a.mesh, q) {
            continue;
        }
        let (Some(op), Some(oq)) = (a.original[p as usize].get(), a.original[q as usize].get())
        else {
            panic!("a border vertex is not an original vertex");
        };
        if original.get(&(op.min(oq), op.max(oq))) != Some(&2) {
            continue;
        }
        let (pp, pq) = (a.mesh.positions[p as usize], a.mesh.positions[q as usize]);
        for s in 0..5 {
            let t = f64::from(s) / 4.0;
            let x: [f64; 3] =
                std::array::from_fn(|k| f64::from(pp[k]) + t * f64::from(pq[k] - pp[k]));
            let d = theirs
                .iter()
                .map(|&seg| distance_to_segment(x, seg))
                .fold(f64::INFINITY, f64::min);
            assert!(
                d < 1e-3,
                "level {} tile {:?}: border point {x:?} is {d} from the border of its level {} neighbour {:?}",
                a.level,
                a.tile,
                b.level,
                b.tile
            );
        }
        checked += 1;
    }
    checked
}

/// For every pair of nodes whose cell rectangles share a stretch of border (any two
/// levels), each one's border edges there lie on the other's; returns the number of
/// pairs with edges checked.
fn assert_crack_free(tree: &LayerTree, layer: &SurfaceMesh) -> usize {
    let original = common::edge_uses(layer);
    let mut pairs = 0;
    let nodes = &tree.nodes;
    let overlap = |lo0: u32, hi0: u32, lo1: u32, hi1: u32| lo0.max(lo1) < hi0.min(hi1);
    for (i, a) in nodes.iter().enumerate() {
        for b in nodes.iter().skip(i + 1) {
            let (ca, cb) = (a.cells, b.cells);
            // a's east side on b's west side or the other way round, overlapping in j;
            // likewise north and south.
            let shared = if (ca[2] == cb[0] || cb[2] == ca[0])
                && overlap(ca[1], ca[3], cb[1], cb[3])
            {
                let line = if ca[2] == cb[0] { ca[2] } else { ca[0] };
                Some((0, line, ca[1].max(cb[1]), ca[3].min(cb[3])))
            } else if (ca[3] == cb[1] || cb[3] == ca[1]) && overlap(ca[0], ca[2], cb[0], cb[2]) {
                let line = if ca[3] == cb[1] { ca[3] } else { ca[1] };
                Some((1, line, ca[0].max(cb[0]), ca[2].min(cb[2])))
            } else {
                None
            };
            let Some((axis, line, lo, hi)) = shared else {
                continue;
            };
            let odd = |c: u32| (2 * c + 1) as f32;
            let stretch = (axis, odd(line), odd(lo), odd(hi));
            let n = covered(a, b, &original, stretch) + covered(b, a, &original, stretch);
            pairs += usize::from(n > 0);
        }
    }
    pairs
}

#[test]
fn neighbours_at_every_pair_of_levels_share_their_borders() {
    let grid = faulted_grid(50, 40);
    let mesh = layer(&grid, 1);
    let tree = build_layer(&mesh, [50, 40], &options(6)).unwrap();
    // 9 x 7 leaves: levels 0..=4.
    assert_eq!(tree.nodes[0].level, 4);
    let levels: std::collections::BTreeSet<u32> = tree.nodes.iter().map(|n| n.level).collect();
    assert_eq!(levels.len(), 5);
    let pairs = assert_crack_free(&tree, &mesh);
    assert!(pairs > 100, "only {pairs} neighbouring pairs checked");

    for n in &tree.nodes {
        n.mesh.validate().unwrap();
        // Children are consecutive and one level down; errors never shrink upwards.
        for &c in &n.children {
            let c = &tree.nodes[c as usize];
            assert_eq!(c.level + 1, n.level);
            assert!(c.error[0] <= n.error[0] && c.error[1] <= n.error[1]);
            assert!((0..4).all(|k| if k < 2 {
                c.cells[k] >= n.cells[k]
            } else {
                c.cells[k] <= n.cells[k]
            }));
        }
        // Vertices keep their original texture coordinates where they are original.
        for (v, o) in n.original.iter().enumerate() {
            if let Some(o) = o.get() {
                assert_eq!(n.mesh.texcoords[v], mesh.texcoords[o as usize]);
            }
        }
    }
    // Leaves are the original surface, level by level the triangles shrink.
    let count = |level: u32| -> usize {
        tree.nodes
            .iter()
            .filter(|n| n.level == level)
            .map(|n| n.mesh.triangle_count())
            .sum()
    };
    assert_eq!(count(0), mesh.triangle_count());
    assert!(count(1) < count(0) / 2 && count(4) < count(1));
    assert!(tree.nodes[0].error[1] > 0.0);
}

#[test]
fn a_view_frustum_leaves_out_only_what_it_does_not_show_and_a_cell_has_one_leaf() {
    let grid = faulted_grid(40, 30);
    let (_dir, file) = saved(&grid, 8);
    let nodes = file.nodes();
    let (lo, hi) = (nodes[0].min, nodes[0].max);
    let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    // The quarter x <= mid x, y <= mid y of the model, seen from close over its corner.
    let always = [0.0, 0.0, 0.0, 1.0];
    let quarter = [
        [-1.0, 0.0, 0.0, mid[0]],
        [0.0, -1.0, 0.0, mid[1]],
        always,
        always,
        always,
    ];
    let whole = ViewPoint {
        eye: [lo[0], lo[1], hi[2] * 5.0 + 3000.0],
        z_scale: 5.0,
        fov_y_deg: 35.0,
        height_px: 800,
        frustum: None,
    };
    let seen = ViewPoint {
        frustum: Some(quarter),
        ..whole
    };
    let all = file.select(&whole, 4.0);
    let chosen = file.select(&seen, 4.0);
    let triangles =
        |s: &[u32]| -> u32 { s.iter().map(|&i| nodes[i as usize].index_count / 3).sum() };
    assert!(
        triangles(&chosen) < triangles(&all) * 3 / 4,
        "{} of {} triangles",
        triangles(&chosen),
        triangles(&all)
    );
    let reaches = |n: &NodeRecord| n.min[0] <= mid[0] && n.min[1] <= mid[1];
    // Every cell of every leaf in the quarter is drawn once, by a node that reaches it.
    for &i in &chosen {
        assert!(reaches(&nodes[i as usize]), "node {i} is outside the view");
    }
    for (l, layer) in file.layers().iter().enumerate() {
        let cells = times_drawn(&file, &chosen, l);
        assert!(
            cells.iter().all(|&c| c <= 1),
            "layer {l}: a cell drawn twice"
        );
        let leaves = (layer.root..layer.root + layer.node_count)
            .map(|i| &nodes[i as usize])
            .filter(|n| n.child_count == 0 && reaches(n));
        for n in leaves {
            for j in n.cells[1]..n.cells[3] {
                for i in n.cells[0]..n.cells[2] {
                    assert_eq!(
                        cells[(j * 40 + i) as usize],
                        1,
                        "layer {l}: cell ({i}, {j})"
                    );
                }
            }
        }
    }
    // The leaf that holds a cell, found down the tree, and the cell's centre there:
    // the same as on the layer's surface at full resolution.
    for (l, layer) in file.layers().iter().enumerate() {
        let leaf = file.leaf_of(l, [13, 21]).expect("a leaf holds the cell");
        let n = &nodes[leaf as usize];
        assert!(n.child_count == 0 && n.layer as usize == l);
        assert!((n.cells[0]..n.cells[2]).contains(&13) && (n.cells[1]..n.cells[3]).contains(&21));
        let at = |mesh: SurfaceMesh| {
            let c = mesh.cell_centre([13, 21]).expect("the cell has a face");
            std::array::from_fn::<f64, 3, _>(|a| mesh.origin[a] + f64::from(c[a]))
        };
        let (stored, whole) = (
            at(file.mesh(leaf as usize).unwrap()),
            at(stored_surface(&grid, layer, None)),
        );
        assert!(
            (0..3).all(|a| (stored[a] - whole[a]).abs() < 1e-2),
            "layer {l}: {stored:?} against {whole:?}"
        );
        assert_eq!(file.leaf_of(l, [40, 0]), None);
    }
}

#[test]
fn file_round_trip_and_selection() {
    let grid = faulted_grid(40, 30);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.lod");
    let report = build_file(&grid, Some("PORO"), &path, &options(8)).unwrap();
    assert_eq!(report.layers, 4, "3 tops and the last bottom");
    let file = LodFile::open(&path).unwrap();
    assert_eq!(file.layers().len(), 4);
    assert_eq!(file.nodes().len(), report.nodes);
    assert_eq!(file.dims(), [40, 30]);
    assert!(file.has_scalars());
    // The colour range is the property's over the active cells, wider than the
    // vertices' averages of it.
    let poro = grid.property("PORO").unwrap();
    let active = || {
        poro.iter()
            .zip(grid.actnum.iter())
            .filter(|&(_, &a)| a)
            .map(|(&v, _)| v)
    };
    let cells = (
        active().fold(f32::INFINITY, f32::min),
        active().fold(f32::NEG_INFINITY, f32::max),
    );
    assert_eq!(file.scalar_range(), Some(cells));
    let vertex_range = (0..file.nodes().len())
        .flat_map(|n| file.vertices(n).iter().map(|v| v.scalar))
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), s| {
            (lo.min(s), hi.max(s))
        });
    // The vertices' values (averaged over the cells around a node, extrapolated at
    // borders) span another range: the file keeps the cells' own.
    assert!(
        vertex_range != cells,
        "vertices {vertex_range:?}, cells {cells:?}"
    );
    let plain = dir.path().join("plain.lod");
    build_file(&grid, None, &plain, &options(8)).unwrap();
    assert_eq!(LodFile::open(&plain).unwrap().scalar_range(), None);

    // Same nodes, in the same order, as building in memory.
    let mesh = layer_surfaces(
        &grid,
        Face::Top,
        &Surfaces::layer(0, grid.display_origin()).property(Some("PORO")),
    )
    .unwrap();
    let tree = build_layer(&mesh, [40, 30], &options(8)).unwrap();
    let layer = file.layers()[0];
    let root = layer.root as usize;
    assert_eq!(layer.node_count as usize, tree.nodes.len());
    assert!(tree.nodes.len() > 5, "{} nodes", tree.nodes.len());
    for (n, node) in tree.nodes.iter().enumerate() {
        let record = &file.nodes()[root + n];
        assert_eq!(file.mesh(root + n).unwrap(), node.mesh, "node {n}");
        assert_eq!(
            (record.level, record.tile, record.cells, record.error),
            (node.level, node.tile, node.cells, node.error),
            "node {n}"
        );
        let children = record.first_child..record.first_child + record.child_count;
        let want: Vec<u32> = node.children.iter().map(|&c| c + root as u32).collect();
        assert_eq!(children.collect::<Vec<u32>>(), want, "node {n}");
    }

    // From far away the roots do; from close up over a corner, leaves there and
    // coarser nodes further off; every selection covers each layer's cells once.
    let (lo, hi) = (file.nodes()[root].min, file.nodes()[root].max);
    let far = ViewPoint {
        eye: [0.0, 0.0, 1e7],
        z_scale: 5.0,
        fov_y_deg: 35.0,
        height_px: 800,
        frustum: None,
    };
    let roots: Vec<u32> = file.layers().iter().map(|l| l.root).collect();
    assert_eq!(file.select(&far, 1.0), roots);
    let near = ViewPoint {
        eye: [lo[0], lo[1], hi[2] * 5.0 + 3000.0],
        ..far
    };
    // (A budget of a few pixels, so that the small model shows several levels.)
    let chosen = file.select(&near, 4.0);
    let levels: Vec<u32> = chosen
        .iter()
        .map(|&i| file.nodes()[i as usize].level)
        .collect();
    assert!(
        levels.contains(&0) && levels.iter().any(|&l| l > 0),
        "{levels:?}"
    );
    for (l, layer) in file.layers().iter().enumerate() {
        let surface = stored_surface(&grid, layer, None);
        let cells = times_drawn(&file, &chosen, l);
        // At most once everywhere; exactly once where the layer has a face (tiles
        // without any have no node).
        assert!(
            cells.iter().all(|&c| c <= 1),
            "layer {l}: a cell drawn twice"
        );
        for f in &surface.cell_faces {
            let c = (f.cell[1] * 40 + f.cell[0]) as usize;
            assert_eq!(
                cells[c], 1,
                "layer {l} (grid layer {}): cell {:?} not drawn",
                layer.k, f.cell
            );
        }
    }
    let drawn = file.selection_mesh(&chosen).unwrap();
    drawn.validate().unwrap();
    assert!(drawn.triangle_count() < report.input_triangles);

    check_layer_cells(&file, &grid);
    let tiled = check_selection_values(&file, &chosen, drawn.vertex_count());
    check_selection_corners(&file, &grid, &chosen, &tiled);
    // Neither without a property.
    let plain = LodFile::open(&plain).unwrap();
    assert!(plain.selection_cover(&chosen).unwrap().is_none());
    assert!(plain.selection_values(&chosen, None).unwrap().is_none());
    assert!(plain.selection_corners(&chosen, None).unwrap().is_none());
}

/// Each layer's cells in `file` (of `grid`, 40 cells across): a bit where its surface
/// has the cell's face, and the face's value.
fn check_layer_cells(file: &LodFile, grid: &CornerPointGrid) {
    for (l, layer) in file.layers().iter().enumerate() {
        let surface = stored_surface(grid, layer, Some("PORO"));
        let (faces, values) = file.layer_cells(l).expect("cells with a property");
        let has = |c: usize| faces[c / 32] >> (c % 32) & 1 != 0;
        assert_eq!(
            (0..40 * 30).filter(|&c| has(c)).count(),
            surface.cell_faces.len(),
            "layer {l}"
        );
        for f in &surface.cell_faces {
            let c = (f.cell[1] * 40 + f.cell[0]) as usize;
            assert!(
                has(c) && values[c].to_bits() == f.value.to_bits(),
                "layer {l}, cell {:?}",
                f.cell
            );
        }
    }
}

/// A selection's cover and values as [`check_selection_values`] read them, with the
/// range of each tile's values.
struct TiledValues {
    cover: CellCover,
    values: Vec<f32>,
    tiles: Vec<Range<usize>>,
}

/// The tiles a view wants of `tiles` in the tests: every third.
fn wanted(tiles: &[Range<usize>]) -> Vec<bool> {
    (0..tiles.len()).map(|k| k % 3 == 1).collect()
}

/// The `wanted` tiles' part of `all`, `per_cell` values a cell, as bits.
fn marked_part(tiles: &[Range<usize>], wanted: &[bool], all: &[f32], per_cell: usize) -> Vec<u32> {
    tiles
        .iter()
        .zip(wanted)
        .filter(|(_, w)| **w)
        .flat_map(|(range, _)| &all[per_cell * range.start..per_cell * range.end])
        .map(|v| v.to_bits())
        .collect()
}

/// `v` bit for bit, so that NaNs compare equal.
fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The selection `chosen`'s pieces are its nodes, their boxes the nodes' cells, and
/// its values come tile by tile (the leaves' squares), each tile's cells row by row;
/// only the marked tiles' values when a view wants only those.
fn check_selection_values(file: &LodFile, chosen: &[u32], drawn_vertices: usize) -> TiledValues {
    let side = file.tile_cells();
    let cover = file.selection_cover(chosen).unwrap().expect("a property");
    let values = file
        .selection_values(chosen, None)
        .unwrap()
        .expect("a property");
    assert_eq!(cover.pieces.len(), chosen.len());
    assert_eq!(cover.vertex_piece.len(), drawn_vertices);
    let mut first = 0;
    // Per tile of each box, in order, its values' range.
    let mut tiles = Vec::new();
    for (piece, &i) in cover.pieces.iter().zip(chosen) {
        let n = &file.nodes()[i as usize];
        let (faces, layer_values) = file.layer_cells(n.layer as usize).unwrap();
        assert_eq!(piece.origin, [n.cells[0] as i32, n.cells[1] as i32]);
        assert_eq!(
            piece.size,
            [n.cells[2] - n.cells[0], n.cells[3] - n.cells[1]]
        );
        let mut tile_starts = vec![first];
        for t in 0..piece.tile_count(side) {
            tile_starts.push(tile_starts[t] + piece.tile_cells(side, t));
        }
        for y in 0..piece.size[1] as usize {
            for x in 0..piece.size[0] as usize {
                let c = (n.cells[1] as usize + y) * 40 + n.cells[0] as usize + x;
                let cell = [piece.origin[0] + x as i32, piece.origin[1] + y as i32];
                assert_eq!(piece.covers(cell), faces[c / 32] >> (c % 32) & 1 != 0);
                let (tile, slot) = piece.tile_slot(side, cell).expect("in the box");
                let v = values[tile_starts[tile] + slot];
                assert_eq!(v.to_bits(), layer_values[c].to_bits());
            }
        }
        tiles.extend(tile_starts.windows(2).map(|w| w[0]..w[1]));
        first += piece.box_cells();
    }
    assert_eq!(first, values.len());
    assert!(
        cover.pieces.iter().any(|p| p.tile_count(side) > 1),
        "a box of several tiles"
    );
    let wanted = wanted(&tiles);
    let some = file
        .selection_values(chosen, Some(&wanted))
        .unwrap()
        .expect("a property");
    let want = marked_part(&tiles, &wanted, &values, 1);
    assert!(!want.is_empty() && bits(&some) == want);
    assert!(file.selection_values(chosen, Some(&wanted[1..])).is_err());
    TiledValues {
        cover,
        values,
        tiles,
    }
}

/// The corners of the cells of the boxes of `chosen`: the full-resolution surface's
/// vertex scalars at each cell face's corners (0, 0), (1, 0), (1, 1), (0, 1), whatever
/// level the node is on; NaN where the layer has no face. Each box comes in its
/// leaves' tiles, tile after tile; only the marked tiles' corners when a view wants
/// only those.
fn check_selection_corners(
    file: &LodFile,
    grid: &CornerPointGrid,
    chosen: &[u32],
    TiledValues {
        cover,
        values,
        tiles,
    }: &TiledValues,
) {
    let side = file.tile_cells();
    let corners = file
        .selection_corners(chosen, None)
        .unwrap()
        .expect("a property");
    assert_eq!(corners.len(), 4 * values.len());
    // Four per cell, in the order of `values`.
    let mut want = vec![f32::NAN; corners.len()];
    let mut first_tile = 0;
    for (piece, &i) in cover.pieces.iter().zip(chosen) {
        let n = &file.nodes()[i as usize];
        let layer = &file.layers()[n.layer as usize];
        let surface = stored_surface(grid, layer, Some("PORO"));
        for f in &surface.cell_faces {
            let [a, b] = f.triangles.map(|t| surface.triangles[t as usize]);
            let Some((tile, slot)) = piece.tile_slot(side, [f.cell[0] as i32, f.cell[1] as i32])
            else {
                continue;
            };
            let cell = tiles[first_tile + tile].start + slot;
            for (c, v) in [a[0], a[1], a[2], b[2]].into_iter().enumerate() {
                want[4 * cell + c] = surface.scalars[v as usize];
            }
        }
        first_tile += piece.tile_count(side);
    }
    for (k, (g, w)) in corners.iter().zip(&want).enumerate() {
        assert_eq!(g.to_bits(), w.to_bits(), "corner {k}");
    }
    assert!(want.iter().any(|w| !w.is_nan()));
    assert!(chosen.iter().any(|&i| file.nodes()[i as usize].level > 0));
    let wanted = wanted(tiles);
    let some = file
        .selection_corners(chosen, Some(&wanted))
        .unwrap()
        .expect("a property");
    let want = marked_part(tiles, &wanted, &corners, 4);
    assert!(!want.is_empty() && bits(&some) == want);
    assert!(file.selection_corners(chosen, Some(&wanted[1..])).is_err());
}

/// Layers are built in parallel batches, each written while the next is built: the
/// file must still be the same byte for byte whatever the number of threads.
#[test]
fn file_does_not_depend_on_the_thread_count() {
    let grid = faulted_grid(30, 20);
    let dir = tempfile::tempdir().unwrap();
    let build_on = |threads: usize| {
        let path = dir.path().join(format!("model-{threads}.lod"));
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let report = pool
            .install(|| build_file(&grid, Some("PORO"), &path, &options(4)))
            .unwrap();
        (report.nodes, std::fs::read(&path).unwrap())
    };
    let (nodes, one) = build_on(1);
    assert!(nodes > 4, "{nodes} nodes");
    for threads in [2, 3] {
        let (n, many) = build_on(threads);
        assert_eq!(n, nodes);
        assert!(many == one, "{threads} threads wrote another file");
    }
}

/// With a memory budget, layers are built as many at a time as it holds: the same file
/// as without one; below what one layer needs, a clear refusal and no file.
#[test]
fn a_memory_budget_limits_the_layers_built_at_once() {
    let grid = faulted_grid(30, 20);
    let dir = tempfile::tempdir().unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap();
    let build = |name: &str, memory: Option<u64>| {
        let path = dir.path().join(name);
        let options = BuildOptions {
            memory,
            ..options(4)
        };
        let built = pool.install(|| build_file(&grid, Some("PORO"), &path, &options));
        (built.map(|r| r.nodes), path)
    };
    let (free, free_path) = build("free.lod", None);
    // 600 cells a layer at most: room for one layer at a time, not two.
    let (tight, tight_path) = build("tight.lod", Some(200_000));
    assert_eq!(free.unwrap(), tight.unwrap());
    assert!(std::fs::read(&free_path).unwrap() == std::fs::read(&tight_path).unwrap());
    let (refused, refused_path) = build("refused.lod", Some(1_000));
    let message = refused.expect_err("refused").to_string();
    assert!(
        message.contains("active cells needs about") && message.contains("GB of memory"),
        "{message}"
    );
    assert!(!refused_path.exists());
}

/// A small faulted model's hierarchy saved in a fresh folder (kept while the first
/// value lives): the file's path and its bytes, for tests that damage it.
fn small_saved_file() -> (tempfile::TempDir, std::path::PathBuf, Vec<u8>) {
    let grid = faulted_grid(12, 10);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("small.lod");
    build_file(&grid, Some("PORO"), &path, &options(4)).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    (dir, path, bytes)
}

#[test]
fn damaged_files_are_errors() {
    let (_dir, path, bytes) = small_saved_file();
    for cut in [0, 7, 40, bytes.len() / 2, bytes.len() - 1] {
        std::fs::write(&path, &bytes[..cut]).unwrap();
        assert!(LodFile::open(&path).is_err(), "cut at {cut}");
    }
    let mut bad = bytes.clone();
    bad[0] = b'X';
    std::fs::write(&path, &bad).unwrap();
    let err = LodFile::open(&path).err().unwrap();
    assert!(err.to_string().contains("magic"), "{err}");
    // A file of the format before per-layer cells is named as such.
    let mut old = bytes.clone();
    old[8..12].copy_from_slice(&2u32.to_le_bytes());
    std::fs::write(&path, &old).unwrap();
    let err = LodFile::open(&path).err().unwrap().to_string();
    assert!(
        err.contains("version 2") && err.contains("lod build"),
        "{err}"
    );
}

/// A tree that is not each layer's quadtree (a child on its parent's level, outside
/// its parent's cells or in another layer, a leaf above level 0) is refused when the
/// file opens, naming the node: selection would otherwise draw cells twice or never.
#[test]
fn a_damaged_tree_is_refused_when_the_file_opens() {
    let (_dir, path, bytes) = small_saved_file();
    let file = LodFile::open(&path).unwrap();
    let nodes = file.nodes().to_vec();
    assert!(file.layers().len() > 1);
    // Where node `i`'s record is in the file (its bytes are unique: they hold the
    // offset of its data).
    let record = |i: usize| {
        let want = bytemuck::bytes_of(&nodes[i]);
        let at = bytes.windows(want.len()).position(|w| w == want).unwrap();
        assert!(bytes[at + 1..].windows(want.len()).all(|w| w != want));
        at
    };
    // A level-1 node away from the domain's corner, and its first child.
    let parent = (0..nodes.len())
        .find(|&i| nodes[i].level == 1 && nodes[i].cells[0] > 0 && nodes[i].layer == 0)
        .unwrap();
    let child = nodes[parent].first_child as usize;
    let root = file.layers()[0].root as usize;
    assert_eq!(nodes[root].child_count, 4);
    let leaf_elsewhere = file.layers()[1].root as usize + 1;
    let damage = |i: usize, edit: &dyn Fn(&mut NodeRecord)| {
        let mut node = nodes[i];
        edit(&mut node);
        let mut damaged = bytes.clone();
        let at = record(i);
        damaged[at..at + std::mem::size_of_val(&node)].copy_from_slice(bytemuck::bytes_of(&node));
        std::fs::write(&path, &damaged).unwrap();
        LodFile::open(&path).err().map(|e| e.to_string())
    };
    let level = nodes[parent].level;
    type Edit<'a> = &'a dyn Fn(&mut NodeRecord);
    let cases: [(&str, Edit, usize); 5] = [
        ("is on level 1, its parent", &|n| n.level = level, child),
        ("outside its parent", &|n| n.cells[0] = 0, child),
        ("names layer 1", &|n| n.layer = 1, child),
        ("level 0 with 4 children", &|n| n.level = 0, root),
        (
            "is not one of layer 0's nodes",
            &|n| n.first_child = leaf_elsewhere as u32,
            parent,
        ),
    ];
    for (want, edit, node) in cases {
        let err = damage(node, edit).unwrap_or_else(|| panic!("{want}: the file opened"));
        assert!(
            err.contains(want) && err.contains("not a valid strata LOD file"),
            "{err}"
        );
    }
    // The file as built opens.
    std::fs::write(&path, &bytes).unwrap();
    assert!(LodFile::open(&path).is_ok());
}

#[test]
fn over_a_flat_layer_coarse_nodes_keep_little_but_their_borders() {
    // A tilted plane, cells of 10 x 8, with a scalar affine in the cell indices: no
    // collapse inside a node changes anything drawn.
    let (ni, nj) = (48, 40);
    let mut mesh = SurfaceMesh::structured(ni, nj, |i, j| {
        let (x, y) = (i as f32 * 10.0, j as f32 * 8.0);
        [x, y, 100.0 + 0.05 * x - 0.1 * y]
    });
    mesh.scalars = mesh.texcoords.iter().map(|t| 0.5 * t[0] + t[1]).collect();
    let tree = build_layer(&mesh, [ni as u32, nj as u32], &options(6)).unwrap();
    assert!(assert_crack_free(&tree, &mesh) > 100);
    let mut parents = 0;
    for n in tree.nodes.iter().filter(|n| !n.children.is_empty()) {
        n.mesh.validate().unwrap();
        assert!(
            n.error[0] < 1e-3 && n.error[1] < 1e-3,
            "error {:?}",
            n.error
        );
        // The texture plane is covered once: no piece went missing.
        let area: f64 = n
            .mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| n.mesh.texcoords[v as usize].map(f64::from));
                0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
            })
            .sum();
        let [i0, j0, i1, j1] = n.cells;
        assert_eq!(area, f64::from(4 * (i1 - i0) * (j1 - j0)));
        // A node's outer border, where it has neighbours, stays whole: at most one
        // triangle per border edge (each of them spans a stretch of it), and the few
        // that join the corners.
        let locked = [i0 > 0, j0 > 0, i1 < ni as u32, j1 < nj as u32];
        let border_edges = (i1 - i0) * (u32::from(locked[1]) + u32::from(locked[3]))
            + (j1 - j0) * (u32::from(locked[0]) + u32::from(locked[2]));
        let kept = n.mesh.triangle_count();
        assert!(
            kept <= border_edges as usize + 6,
            "level {} node {:?}: {kept} triangles for {border_edges} locked border edges",
            n.level,
            n.cells
        );
        parents += 1;
    }
    assert!(parents >= 10, "{parents} parents");
    // The root has no neighbour: its plane is two triangles, or a few more.
    assert!(tree.nodes[0].mesh.triangle_count() <= 4);
}

#[test]
fn reek_hierarchy_is_crack_free() {
    let Some(data) = shared_data("reek_hierarchy_is_crack_free") else {
        return;
    };
    let options_read = ReadOptions {
        grid_only: true,
        ..ReadOptions::default()
    };
    let grid = strata_grid::open_with(&data.join("reek/REEK.EGRID"), &options_read).unwrap();
    let d = grid.dims();
    let mesh =
        layer_surfaces(&grid, Face::Top, &Surfaces::layer(0, grid.display_origin())).unwrap();
    let tree = build_layer(&mesh, [d.nx as u32, d.ny as u32], &options(8)).unwrap();
    assert!(assert_crack_free(&tree, &mesh) > 50);
}

/// Per face of `mesh` (two triangles each): its cell, value, and its triangles'
/// corners (position, texture coordinates and scalar, bit for bit).
fn side_faces(mesh: &SurfaceMesh) -> Vec<([u32; 3], u32, Vec<[u32; 6]>)> {
    mesh.cell_faces
        .iter()
        .map(|f| {
            let corners = f
                .triangles
                .iter()
                .flat_map(|&t| mesh.triangles[t as usize])
                .map(|v| {
                    let v = v as usize;
                    let [x, y, z] = mesh.positions[v];
                    let [u, w] = mesh.texcoords[v];
                    let s = mesh.scalars.get(v).copied().unwrap_or(f32::NAN);
                    [x, y, z, u, w, s].map(f32::to_bits)
                })
                .collect();
            (f.cell, f.value.to_bits(), corners)
        })
        .collect()
}

#[test]
fn each_grid_layers_side_faces_are_stored_at_full_resolution() {
    let grid = faulted_grid(40, 30);
    let dir = tempfile::tempdir().unwrap();
    let nz = grid.dims().nz;
    for property in [Some("PORO"), None] {
        let path = dir.path().join("model.lod");
        let report = build_file(&grid, property, &path, &options(8)).unwrap();
        let file = LodFile::open(&path).unwrap();
        // The model's side faces as `strata render --sides` draws them: vertices
        // between layers average the property over both.
        let want = side_surfaces(
            &grid,
            &Surfaces::new(0..nz, grid.display_origin()).property(property),
        )
        .unwrap();
        let want = side_faces(&want);
        let mut got = Vec::new();
        for (l, layer) in file.layers().iter().enumerate() {
            let sides = file.layer_sides(l).unwrap();
            if layer.face == 1 {
                assert!(sides.is_none(), "a bottom surface has sides");
                continue;
            }
            let sides = sides.expect("every layer of the faulted grid has sides");
            sides.validate().unwrap();
            assert!(sides.cell_faces.iter().all(|f| f.cell[2] == layer.k));
            assert_eq!(sides.origin, file.origin());
            got.extend(side_faces(&sides));
        }
        assert_eq!(got.len(), want.len(), "{property:?}");
        assert!(got == want, "{property:?}: stored side faces differ");
        assert_eq!(2 * got.len(), report.side_triangles);
        // Faces inside the domain are fault walls (or the edges of holes).
        let walls = got
            .iter()
            .filter(|(cell, ..)| (1..39).contains(&cell[0]) && (1..29).contains(&cell[1]))
            .count();
        assert!(walls > 20, "{walls} side faces inside the domain");
        // Scalars vary up and down a wall only where layers share vertices (corners
        // (0, 0), (1, 0), (1, 1) then (0, 0), (1, 1), (0, 1): a face's top and bottom
        // corners are 0 and 5, 1 and 2).
        if property.is_some() {
            let vertical = got
                .iter()
                .filter(|(_, _, c)| c[0][5] != c[5][5] || c[1][5] != c[2][5])
                .count();
            assert!(
                vertical > got.len() / 2,
                "{vertical} of {} faces",
                got.len()
            );
        }
    }
}

/// Damage anywhere (a few random bytes of a saved file overwritten, a thousand times
/// over) is an error or data that reads back wrong, never a panic: the tables are
/// checked when the file opens and indices when a node's mesh is read.
#[test]
fn random_damage_never_panics() {
    let (_dir, path, bytes) = small_saved_file();
    // A fixed linear congruential sequence: the same damage on every run.
    let mut state = 12345u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 33) as usize
    };
    let view = ViewPoint {
        eye: [0.0, 0.0, 1e4],
        z_scale: 5.0,
        fov_y_deg: 35.0,
        height_px: 800,
        frustum: None,
    };
    let (mut opened, mut refused) = (0, 0);
    for round in 0..1000 {
        let mut damaged = bytes.clone();
        for _ in 0..1 + round % 4 {
            let at = next() % damaged.len();
            damaged[at] = next() as u8;
        }
        std::fs::write(&path, &damaged).unwrap();
        let read = std::panic::catch_unwind(|| {
            let file = LodFile::open(&path).ok()?;
            for max_pixels in [1.0, 4.0, 1e9] {
                let selection = file.select(&view, max_pixels);
                let _ = file.selection_mesh(&selection);
                let _ = file.selection_cover(&selection);
                let _ = file.selection_values(&selection, None);
                let _ = file.selection_corners(&selection, None);
            }
            for l in 0..file.layers().len() {
                let _ = file.layer_sides(l);
                for cell in [[0, 0], [5, 7], [u32::MAX, 3]] {
                    if let Some(leaf) = file.leaf_of(l, cell) {
                        let _ = file.mesh(leaf as usize).map(|m| m.cell_centre(cell));
                    }
                }
            }
            for i in 0..file.nodes().len() {
                let _ = file.mesh(i);
            }
            Some(())
        });
        match read {
            Ok(Some(())) => opened += 1,
            Ok(None) => refused += 1,
            Err(_) => panic!("round {round}: reading the damaged file panicked"),
        }
    }
    // Both paths ran: damage in the tables is refused, damage in vertex data is not.
    assert!(
        opened > 0 && refused > 0,
        "{opened} opened, {refused} refused"
    );
}

#[test]
fn small_tiles_whose_locked_borders_take_much_of_a_node_still_err_under_a_cell() {
    // Tiles of 8 x 8 cells: a level-3 node's locked borders alone are half the
    // triangles a quarter of its children would leave it. They stay whole and the
    // inside keeps three quarters of that quarter: a quarter in all starved the inside
    // of the nodes above level 1 (errors of many cells; `docs/performance.md`).
    let (nx, ny) = (128, 128);
    let (_, mesh, tree) = layer_tree(nx, ny, 8);
    let (lo, hi) = mesh.bounds().unwrap();
    let cell = (hi[0] - lo[0]) / nx as f32;
    // 16 x 16 leaves: the quadtree's root is on level 4, the coarser levels over the
    // whole layer above it err more by design.
    assert!(tree.nodes[0].level > 4);
    for n in tree.nodes.iter().filter(|n| n.level <= 4) {
        // The root, a few hundred triangles for the whole layer, may err more.
        let bound = if n.level == 4 { 2.0 * cell } else { cell };
        assert!(
            n.error[0] < bound && n.error[1] < bound,
            "level {} node {:?}: error {:?} against cells of {cell}",
            n.level,
            n.cells,
            n.error
        );
    }
}

#[test]
fn above_the_quadtree_coarser_nodes_over_the_whole_layer_err_no_more_than_they_say() {
    let (nx, ny) = (96, 80);
    let (grid, mesh, tree) = layer_tree(nx, ny, 32);
    // 3 x 3 leaves of 32 cells: the quadtree's root is on level 2.
    let root = tree.nodes.iter().position(|n| n.level == 2).unwrap();
    assert!(root >= 2, "{root} levels above the quadtree's root");
    let top = &tree.nodes[0];
    assert!(
        top.mesh.triangle_count() <= 64,
        "the coarsest node keeps {} triangles",
        top.mesh.triangle_count()
    );
    for (i, n) in tree.nodes[..=root].iter().enumerate() {
        n.mesh.validate().unwrap();
        assert_eq!(n.cells, [0, 0, nx as u32, ny as u32]);
        if i < root {
            // A chain: one child each, three quarters of its triangles or fewer, more
            // error.
            assert_eq!(n.children, [i as u32 + 1]);
            let child = &tree.nodes[i + 1];
            assert_eq!(n.level, child.level + 1);
            assert!(4 * n.mesh.triangle_count() <= 3 * child.mesh.triangle_count());
            assert!(n.error[0] >= child.error[0] && n.error[1] >= child.error[1]);
        }
        for (v, o) in n.original.iter().enumerate() {
            if let Some(o) = o.get() {
                assert_eq!(n.mesh.texcoords[v], mesh.texcoords[o as usize]);
            }
        }
        // The error a node carries holds on the original grid lines, sampled apart
        // from the vertices it was measured at (the children's, or the root's).
        let z_scale = 5.0;
        let d = deviation(&mesh, &n.mesh, &n.home, 4, z_scale);
        let said = f64::from(n.error[0]).hypot(z_scale * f64::from(n.error[1]));
        assert!(
            d.missed == 0 && d.max <= said + 1e-3,
            "level {}, {} triangles: grid lines up to {} away (missed {}), error {said}",
            n.level,
            n.mesh.triangle_count(),
            d.max,
            d.missed
        );
    }

    // Seen from far, a layer is one of those nodes, every cell drawn once.
    let (_dir, file) = saved(&grid, 32);
    let nodes = file.nodes();
    let (lo, hi) = (nodes[0].min, nodes[0].max);
    let far = ViewPoint {
        eye: [
            0.5 * (lo[0] + hi[0]),
            0.5 * (lo[1] + hi[1]),
            hi[2] * 5.0 + 20.0 * (hi[0] - lo[0]),
        ],
        z_scale: 5.0,
        fov_y_deg: 35.0,
        height_px: 800,
        frustum: None,
    };
    let chosen = file.select(&far, 1.0);
    assert_eq!(chosen.len(), file.layers().len(), "{chosen:?}");
    for (l, layer) in file.layers().iter().enumerate() {
        let picked = &nodes[chosen[l] as usize];
        let quadtree_root = nodes[layer.root as usize..]
            .iter()
            .find(|n| n.level == 2)
            .unwrap();
        assert!(
            picked.level > 2 && picked.index_count < quadtree_root.index_count,
            "layer {l}: level {} with {} indices",
            picked.level,
            picked.index_count
        );
        assert!(times_drawn(&file, &chosen, l).iter().all(|&n| n == 1));
    }
}

#[test]
fn over_a_layer_of_one_tile_the_chain_goes_down_to_the_coarsest_node() {
    let (sound, stray) = (one_tile_top(false), one_tile_top(true));
    for (name, mesh) in [("sound", &sound), ("stray", &stray)] {
        // One leaf: the quadtree's root is the leaf itself, whose error is nothing
        // because it is the input, not because the layer is flat. Taken for flat,
        // the chain stopped at half the leaf's triangles.
        let tree = build_layer(mesh, [40, 30], &options(64)).unwrap();
        let leaf = tree.nodes.iter().position(|n| n.level == 0).unwrap();
        assert_eq!(
            tree.nodes[leaf].mesh.triangle_count(),
            mesh.triangle_count()
        );
        let top = &tree.nodes[0];
        assert!(
            top.mesh.triangle_count() <= 64 && leaf >= 4,
            "{name}: the coarsest of {} nodes keeps {} of {} triangles",
            leaf + 1,
            top.mesh.triangle_count(),
            mesh.triangle_count()
        );
        // The error each node says holds on the grid lines. With the stray corner it
        // leaves out what reaches it: measured there, it was 1e11 from the fourth node
        // on, and no view chose those nodes. The lines next to it are then measured
        // to the nearest of what the node draws, and lay a little further than the
        // vertices the error is measured at (`docs/performance.md`).
        for n in &tree.nodes {
            let z_scale = 5.0;
            let d = deviation(mesh, &n.mesh, &n.home, 4, z_scale);
            let said = f64::from(n.error[0]).hypot(z_scale * f64::from(n.error[1]));
            let holds = name == "stray" || d.max <= said + 1e-3;
            assert!(
                said < 1e3 && holds,
                "{name}, level {}: grid lines up to {} away, error {said}",
                n.level,
                d.max
            );
        }
    }
}

#[test]
fn each_layer_surfaces_fault_traces_are_stored_as_found_at_full_resolution() {
    let grid = faulted_grid(40, 30);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.lod");
    build_file(&grid, None, &path, &options(8)).unwrap();
    let file = LodFile::open(&path).unwrap();
    let origin = grid.display_origin();
    let mut all = 0;
    for (l, layer) in file.layers().iter().enumerate() {
        let face = if layer.face == 0 {
            Face::Top
        } else {
            Face::Bottom
        };
        let k = layer.k as usize;
        let mesh = layer_surfaces(&grid, face, &Surfaces::layer(k, origin)).unwrap();
        let want = fault_traces(&mesh);
        assert_eq!(file.layer_faults(l), &want[..], "layer surface {l}");
        all += want.len();
    }
    // The faulted grid's faults split every layer surface: both sides' edges.
    assert!(all >= 2 * file.layers().len(), "{all} segments");
    // A generated grid without faults stores none.
    let unfaulted = generate(&SynthParams {
        nx: 40,
        ny: 30,
        nz: 3,
        faults: 0,
        seed: 7,
    })
    .unwrap();
    build_file(&unfaulted, None, &path, &options(8)).unwrap();
    let file = LodFile::open(&path).unwrap();
    assert!((0..file.layers().len()).all(|l| file.layer_faults(l).is_empty()));
}

/// Each node counts the faces of its cells that the layers above and below leave
/// open, and a choice among the inner surfaces of a closed stack keeps only nodes
/// with such faces, so nothing that shows is left out.
#[test]
fn nodes_count_the_faces_a_closed_stack_exposes() {
    // A pinched-out middle layer in the west, an inactive ellipse through all layers
    // and an inactive strip in the top layer.
    let grid = generate(&SynthParams {
        nx: 30,
        ny: 20,
        nz: 5,
        faults: 2,
        seed: 5,
    })
    .unwrap();
    let (_dir, file) = saved(&grid, 4);
    let has = |i: u32, j: u32, k: i64| {
        (0..5).contains(&k) && strata_grid::has_faces(&grid, i as usize, j as usize, k as usize)
    };
    let exposed = |n: &NodeRecord| {
        let layer = &file.layers()[n.layer as usize];
        let k = i64::from(layer.k);
        let mut count = 0;
        for j in n.cells[1]..n.cells[3] {
            for i in n.cells[0]..n.cells[2] {
                let open = layer.face == 1
                    || k == 0
                    || !has(i, j, k - 1)
                    || (k + 1 < 5 && !has(i, j, k + 1));
                count += u32::from(has(i, j, k) && open);
            }
        }
        count
    };
    for n in file.nodes() {
        assert_eq!(n.exposed, exposed(n), "{n:?}");
    }
    // Of the inner surfaces (the tops of layers 2 to 5), only those around the
    // pinch-out and under the strip expose faces: the pinched layer's faces in the
    // east are covered on both sides, the last layer's by its own bottom.
    let inner_exposed: Vec<u32> = file.layers()[1..5]
        .iter()
        .map(|l| file.nodes()[l.root as usize].exposed)
        .collect();
    assert!(
        inner_exposed[0] > 0 && inner_exposed[2] > 0,
        "{inner_exposed:?}"
    );
    assert_eq!([inner_exposed[1], inner_exposed[3]], [0, 0]);

    let view = ViewPoint {
        eye: [0.0, 0.0, 1e4],
        z_scale: 1.0,
        fov_y_deg: 30.0,
        height_px: 600,
        frustum: None,
    };
    let inner: Vec<bool> = (0..file.layers().len())
        .map(|l| l > 0 && l + 1 < file.layers().len())
        .collect();
    let all = file.select(&view, 0.0);
    let shown = file.select_exposed(&view, 0.0, &inner);
    assert!(shown.len() < all.len(), "{} of {}", shown.len(), all.len());
    for &i in &all {
        let n = &file.nodes()[i as usize];
        let kept = shown.contains(&i);
        assert_eq!(kept, !inner[n.layer as usize] || n.exposed > 0, "{n:?}");
    }
}
