//! Levels of detail for models too big to draw whole: a quadtree over the (i, j)
//! cells of each layer surface.
//!
//! Leaves are tiles of `tile_cells` x `tile_cells` cells at full resolution. A parent
//! merges its (up to four) children, welds them along the borders they share, and is
//! simplified with its own outer border *locked*: every node keeps the vertices of its
//! outer border exactly as in the original surface. Two neighbouring nodes, whatever
//! their levels, therefore meet along the same original border vertices and edges,
//! and no crack can open between them. (The price: borders stay at full resolution, so
//! coarse levels keep a line of small triangles along tile borders; the grid lines
//! drawn on them do not change.) A parent keeps a quarter of its children's triangles,
//! or more where its locked border would take over a quarter of those: the border
//! doubles at each level while the quarter stays, and a quarter in all left the
//! inside of a node less and less, until errors leapt (on a faulted 128 x 128 layer in
//! tiles of 8, far over a cell from level 2; `docs/performance.md`, "Hierarchy build
//! and view"). With the default tiles of 64 cells that begins at level 4, in
//! layers over 1024 cells across.
//! Over a flat stretch of layer with affine texture coordinates and scalar (the
//! layers of a block-centred deck such as SPE10), where simplifying changes nothing,
//! a parent goes on below the quarter and keeps little but its locked borders: the
//! root of a flat layer is two triangles.
//!
//! Above the quadtree's root, whose tile is the whole layer, coarsening goes on: a
//! chain of nodes over the whole layer (nothing to lock, no neighbour), each
//! simplified from the root to half the triangles of the one below, down to
//! [`COARSEST_TRIANGLES`]. The root keeps a tile's worth of triangles, which a layer
//! needs only where it fills a view: seen whole, or far, or with a budget of a few
//! pixels, a layer is drawn from one of the chain's nodes. (Halves rather than the
//! quadtree's quarters, and each from the root rather than from the node below,
//! because on a generated 1000 x 1000 layer seen whole from two directions a chain of
//! quarters each from the one below drew more triangles than this one
//! (`docs/performance.md`): a step of a quarter overshoots what a view needs by more,
//! and errors summed up a chain exceed those measured once.)
//!
//! Every vertex of every level lies on the original surface with the original
//! surface's texture coordinates there (each node is simplified on the original layer
//! as reference surface), so any selection draws the original wireframe.
//!
//! Each node carries its geometric error: how far its surface is from its children's
//! at the same texture coordinates (measured at the children's vertices), plus the
//! children's own error, horizontal and vertical separately so that the vertical
//! exaggeration can be applied when a view is known. Parents are never more accurate
//! than their children, so choosing, per frame, the coarsest nodes whose projected
//! error is under a pixel budget is a cut through each tree ([`crate::LodFile::select`]).

use std::sync::Arc;

use rayon::prelude::*;
use strata_grid::SurfaceMesh;

use crate::baseline::{optimize_order, permute_by};
use crate::measure::{Strays, UvIndex, components};
use crate::reference::NONE;
use crate::{Decimated, Error, MaybeIndex, Options, Reference, Result, decimate_on};

/// Error of a parent, in units in the last place of its largest coordinate
/// (horizontal and vertical apart), under which its simplification changed nothing
/// but the rounding of single-precision positions. At 1e-6 of its extent instead, a
/// generated 2000 x 2000 layer let nearly flat nodes through whose further collapses
/// all failed and cost time (`docs/performance.md`, "Hierarchy build and view").
const UNCHANGED_ULPS: f32 = 8.0;

/// The coarsest node of a layer has at most this many triangles, or is as small as
/// simplifying its outline and pieces within the rules leaves it.
const COARSEST_TRIANGLES: usize = 64;

/// How far [`crate::build_file`] is, told as it goes: a model of tens of millions of
/// cells takes minutes, and a front end shows a bar.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress {
    /// The build begins: `work` units in all over `surfaces` layer surfaces. A unit is
    /// a leaf tile's worth of work, so that a bar moves within a layer too, where one
    /// of layers would stand still for minutes on a model of a few large ones.
    Started {
        /// Units of work of the whole build.
        work: u64,
        /// Layer surfaces the build makes.
        surfaces: usize,
    },
    /// This many more units are done (told from the threads that did them).
    Worked(u64),
    /// A layer surface is in the file, with the totals so far.
    Written {
        /// Layer surfaces written so far.
        written: usize,
        /// Layer surfaces of the whole build.
        surfaces: usize,
        /// Triangles of the layer surfaces written.
        input_triangles: usize,
        /// Triangles stored for them over all levels.
        stored_triangles: usize,
    },
}

/// Where a build tells its [`Progress`]; called from the threads that build, so it is
/// shared and thread-safe.
pub type ProgressFn = Arc<dyn Fn(Progress) + Send + Sync>;

/// How a hierarchy is built.
#[derive(Clone)]
pub struct BuildOptions {
    /// Cells along each side of a leaf tile.
    pub tile_cells: u32,
    /// Share of its children's triangles a parent keeps (a quarter keeps nodes of
    /// about the same size at every level); more where its locked border, kept whole,
    /// would leave the inside less than three quarters of that.
    pub reduction: f64,
    /// How errors are weighed when simplifying (target and error bound are set per
    /// node).
    pub decimation: Options,
    /// Told how far [`crate::build_file`] is; nothing is told without it.
    pub progress: Option<ProgressFn>,
    /// Bytes the layer surfaces being built at once may hold ([`crate::build_file`]
    /// builds fewer at a time, or refuses, to stay under it); no limit when `None`.
    pub memory: Option<u64>,
}

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions {
            tile_cells: 64,
            reduction: 0.25,
            decimation: Options {
                // The default vertical exaggeration of `strata render`.
                z_scale: 5.0,
                ..Options::default()
            },
            progress: None,
            memory: None,
        }
    }
}

impl std::fmt::Debug for BuildOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BuildOptions")
            .field("tile_cells", &self.tile_cells)
            .field("reduction", &self.reduction)
            .field("decimation", &self.decimation)
            .field("progress", &self.progress.as_ref().map(|_| "callback"))
            .field("memory", &self.memory)
            .finish()
    }
}

impl BuildOptions {
    pub(crate) fn check(&self) -> Result<()> {
        if self.tile_cells == 0 || self.tile_cells > 4096 {
            return Err(Error::Option(format!(
                "tile_cells must be in 1..=4096, got {}",
                self.tile_cells
            )));
        }
        if !(self.reduction > 0.0 && self.reduction <= 1.0) {
            return Err(Error::Option(format!(
                "reduction must be in (0, 1], got {}",
                self.reduction
            )));
        }
        Ok(())
    }
}

/// A node of a layer's quadtree, or of the chain above its root.
#[derive(Clone, Debug)]
pub struct Node {
    /// 0 for leaves (full resolution), one more each level up, the chain above the
    /// quadtree's root included.
    pub level: u32,
    /// Tile coordinates at this level.
    pub tile: [u32; 2],
    /// Cells covered: `i0, j0, i1, j1`, ends excluded.
    pub cells: [u32; 4],
    /// Geometric error: largest horizontal and vertical distance between this
    /// node's surface and the original at the same texture coordinates (see the
    /// module documentation for how it is measured).
    pub error: [f32; 2],
    /// Bounds of the region (positions relative to the mesh origin).
    pub bounds: ([f32; 3], [f32; 3]),
    /// Vertex-cache ordered mesh, without cell faces.
    pub mesh: SurfaceMesh,
    /// Indices of the children in [`LayerTree::nodes`].
    pub children: Vec<u32>,
    /// Per vertex, the original vertex it is, or none for one placed by a collapse.
    pub original: Vec<MaybeIndex>,
    /// Per vertex, a triangle of the original layer it lies on.
    pub home: Vec<u32>,
}

/// The quadtree of one layer surface under its chain of coarser nodes: the coarsest
/// first, then breadth first, so the children of a node are consecutive.
#[derive(Clone, Debug, Default)]
pub struct LayerTree {
    /// The nodes, coarsest first (see [`LayerTree`]).
    pub nodes: Vec<Node>,
}

/// Cells along each side of a tile at `level` of a quadtree whose leaves are
/// `tile_cells` wide.
fn tile_span(tile_cells: u32, level: u32) -> u32 {
    tile_cells.saturating_mul(1 << level.min(31))
}

/// Tiles across and along a grid of `dims` cells at `level` of such a quadtree.
fn tiles_at(dims: [u32; 2], tile_cells: u32, level: u32) -> [u32; 2] {
    let span = tile_span(tile_cells, level);
    [dims[0].div_ceil(span).max(1), dims[1].div_ceil(span).max(1)]
}

/// The level of the root of such a quadtree.
fn root_level(dims: [u32; 2], tile_cells: u32) -> u32 {
    let mut level = 0;
    while tiles_at(dims, tile_cells, level) != [1, 1] {
        level += 1;
    }
    level
}

/// Work of a parent node for a progress count, in leaves: a parent simplifies its
/// children's triangles (about four leaves' worth at every level), a leaf only orders
/// its own. The weight is a parent's time over a leaf's as measured on a generated
/// layer (`docs/performance.md`, "Hierarchy build and view").
const PARENT_WORK: u64 = 20;

/// Units of work of building the quadtree of a layer of a grid of `dims` cells (as
/// [`build_layer_with`] counts them): a unit a leaf tile, [`PARENT_WORK`] a parent
/// tile, empty tiles included.
pub(crate) fn layer_work(dims: [u32; 2], tile_cells: u32) -> u64 {
    let tiles = |level: u32| {
        let [x, y] = tiles_at(dims, tile_cells, level);
        u64::from(x) * u64::from(y)
    };
    let parents: u64 = (1..=root_level(dims, tile_cells)).map(tiles).sum();
    // The chain above the root counts as one parent: each of its nodes simplifies
    // the root alone, a quarter of what a parent simplifies.
    tiles(0) + PARENT_WORK * (parents + 1)
}

/// Builds the quadtree of `layer`, a layer surface of a grid of `dims` = `[nx, ny]`
/// cells (texture coordinates `(2i + 1, 2j + 1)` at node `(i, j)`), on all cores.
pub fn build_layer(
    layer: &SurfaceMesh,
    dims: [u32; 2],
    options: &BuildOptions,
) -> Result<LayerTree> {
    let nodes = build_layer_with(layer, dims, options, &|_| {}, &|node| node)?;
    Ok(LayerTree {
        nodes: nodes
            .into_iter()
            .map(|(node, children)| Node { children, ..node })
            .collect(),
    })
}

/// A node made into what the caller keeps (by `keep` of [`build_layer_with`]) once
/// its parent is built, with its descendants.
struct Kept<K> {
    node: K,
    children: Vec<Kept<K>>,
}

/// A node whose parent is not built yet, which needs it whole.
struct Pending<K> {
    node: Node,
    children: Vec<Kept<K>>,
}

/// What a layer's nodes' errors are measured by: the component of each of its
/// triangles (a vertex is looked for in its own), and what reaches a stray corner
/// (left out: where a coarser node draws a texture coordinate next to a corner at a
/// depth of 1e11 is no measure of the rest of it, and such a node's error of 1e11
/// kept it from ever being chosen).
struct LayerParts {
    labels: Vec<u32>,
    strays: Strays,
}

/// What building a layer's quadtree reads.
struct LayerBuild<'a> {
    layer: &'a SurfaceMesh,
    reference: Reference<'a>,
    parts: LayerParts,
    dims: [u32; 2],
    options: &'a BuildOptions,
    /// Triangles of the layer by leaf tile (row by row): those of leaf `id` are
    /// `by_tile[start[id]..start[id + 1]]`.
    by_tile: Vec<u32>,
    start: Vec<u32>,
    built: &'a (dyn Fn(u64) + Sync),
}

/// [`build_layer`], for a caller that keeps each node as `keep` makes it, and is told
/// by `built` the units of [`layer_work`] as each tile is built (from the threads
/// that build them), so that a progress bar moves within a layer too: a single layer
/// of tens of millions of cells takes minutes. The nodes come root first, breadth
/// first, each with the indices of its children (consecutive).
///
/// The tree is built depth first, a subtree per task: a node is handed to `keep` as
/// soon as its parent is built, so that only the nodes still waiting for their
/// parent are held whole (the file keeps the others as it stores them, in about half
/// the memory), not every level of the layer at once.
pub(crate) fn build_layer_with<K: Send>(
    layer: &SurfaceMesh,
    dims: [u32; 2],
    options: &BuildOptions,
    built: &(dyn Fn(u64) + Sync),
    keep: &(dyn Fn(Node) -> K + Sync),
) -> Result<Vec<(K, Vec<u32>)>> {
    options.check()?;
    let t = options.tile_cells;
    if layer.is_empty() {
        built(layer_work(dims, t));
        return Ok(Vec::new());
    }
    let (by_tile, start) = triangles_by_tile(layer, dims, t)?;
    let build = LayerBuild {
        layer,
        reference: Reference::new(layer)?,
        parts: LayerParts {
            labels: components(layer),
            strays: Strays::of(layer),
        },
        dims,
        options,
        by_tile,
        start,
        built,
    };
    let root = build.subtree(root_level(dims, t), [0, 0], keep)?;
    let root = root.map(|root| build.coarser(root, keep)).transpose()?;
    built(PARENT_WORK);
    Ok(root.map_or_else(Vec::new, |root| {
        breadth_first(Kept {
            node: keep(root.node),
            children: root.children,
        })
    }))
}

/// The triangles of `layer` by the leaf tile (of `tile_cells` cells) under their
/// texture-space centroid, as [`LayerBuild::by_tile`] and [`LayerBuild::start`].
fn triangles_by_tile(
    layer: &SurfaceMesh,
    dims: [u32; 2],
    tile_cells: u32,
) -> Result<(Vec<u32>, Vec<u32>)> {
    let t = tile_cells;
    let leaf_tiles = tiles_at(dims, t, 0);
    // The leaf tile of each triangle, as u32 (NONE when outside the grid): this list
    // has an entry per triangle of the layer, which an `Option<usize>` would make
    // 16 bytes.
    let tile_of = |tri: &[u32; 3]| -> u32 {
        let (mut u, mut v) = (0f64, 0f64);
        for &c in tri {
            let tc = layer.texcoords[c as usize];
            u += f64::from(tc[0]) / 3.0;
            v += f64::from(tc[1]) / 3.0;
        }
        let (i, j) = (((u - 1.0) / 2.0).floor(), ((v - 1.0) / 2.0).floor());
        let (tx, ty) = ((i / f64::from(t)).floor(), (j / f64::from(t)).floor());
        if tx >= 0.0 && ty >= 0.0 && tx < f64::from(leaf_tiles[0]) && ty < f64::from(leaf_tiles[1])
        {
            ty as u32 * leaf_tiles[0] + tx as u32
        } else {
            NONE
        }
    };
    let tile_count = (leaf_tiles[0] * leaf_tiles[1]) as usize;
    let mut start = vec![0u32; tile_count + 1];
    let assigned: Vec<u32> = layer.triangles.par_iter().map(tile_of).collect();
    if assigned.contains(&NONE) {
        return Err(Error::Mesh(format!(
            "a triangle's texture coordinates are outside the {} x {} cells of the grid",
            dims[0], dims[1]
        )));
    }
    for &a in &assigned {
        start[a as usize + 1] += 1;
    }
    for i in 0..tile_count {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut by_tile = vec![0u32; layer.triangle_count()];
    for (tri, &a) in assigned.iter().enumerate() {
        by_tile[fill[a as usize] as usize] = tri as u32;
        fill[a as usize] += 1;
    }
    Ok((by_tile, start))
}

impl LayerBuild<'_> {
    /// Cells covered by `tile` at `level`: `i0, j0, i1, j1`, ends excluded.
    fn span_cells(&self, level: u32, tile: [u32; 2]) -> [u32; 4] {
        let span = tile_span(self.options.tile_cells, level);
        [
            tile[0] * span,
            tile[1] * span,
            ((tile[0] + 1) * span).min(self.dims[0]),
            ((tile[1] + 1) * span).min(self.dims[1]),
        ]
    }

    /// The subtree of `tile` at `level` (`None` where it has no triangle), its
    /// children's subtrees built in parallel.
    fn subtree<K: Send>(
        &self,
        level: u32,
        tile: [u32; 2],
        keep: &(dyn Fn(Node) -> K + Sync),
    ) -> Result<Option<Pending<K>>> {
        let t = self.options.tile_cells;
        if level == 0 {
            let id = (tile[1] * tiles_at(self.dims, t, 0)[0] + tile[0]) as usize;
            let tris = &self.by_tile[self.start[id] as usize..self.start[id + 1] as usize];
            let node = (!tris.is_empty()).then(|| Pending {
                node: leaf(self.layer, tris, tile, self.span_cells(0, tile)),
                children: Vec::new(),
            });
            (self.built)(1);
            return Ok(node);
        }
        let below = tiles_at(self.dims, t, level - 1);
        let children: Vec<Option<Pending<K>>> = (0..4)
            .map(|k| [2 * tile[0] + (k & 1), 2 * tile[1] + (k >> 1)])
            .filter(|c| c[0] < below[0] && c[1] < below[1])
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|c| self.subtree(level - 1, c, keep))
            .collect::<Result<_>>()?;
        let children: Vec<Pending<K>> = children.into_iter().flatten().collect();
        let node = if children.is_empty() {
            None
        } else {
            let nodes: Vec<&Node> = children.iter().map(|c| &c.node).collect();
            let slot = Slot {
                level,
                tile,
                cells: self.span_cells(level, tile),
            };
            let node = self.parent(&nodes, slot, self.options.reduction)?;
            let children = children
                .into_iter()
                .map(|c| Kept {
                    node: keep(c.node),
                    children: c.children,
                })
                .collect();
            Some(Pending { node, children })
        };
        (self.built)(PARENT_WORK);
        Ok(node)
    }

    /// Above the quadtree's root (`top`), nodes over the whole layer, each with half
    /// the triangles of the one below it while that leaves it at most three quarters
    /// of them, until one has at most [`COARSEST_TRIANGLES`]: far or small on screen,
    /// a layer is then drawn with as few triangles as its pixels allow, where the root
    /// keeps the triangles of a tile however small the layer looks. Each is simplified
    /// from the root, not from the node below: its error is measured once against
    /// the root, not summed up the chain.
    fn coarser<K: Send>(
        &self,
        mut top: Pending<K>,
        keep: &(dyn Fn(Node) -> K + Sync),
    ) -> Result<Pending<K>> {
        if top.node.mesh.triangle_count() <= COARSEST_TRIANGLES {
            return Ok(top);
        }
        let root = top.node.clone();
        let mut reduction = 1.0;
        while top.node.mesh.triangle_count() > COARSEST_TRIANGLES {
            reduction *= 0.5;
            let below = &top.node;
            let slot = Slot {
                level: below.level + 1,
                tile: below.tile,
                cells: below.cells,
            };
            let mut node = self.parent(&[&root], slot, reduction)?;
            if 4 * node.mesh.triangle_count() > 3 * below.mesh.triangle_count() {
                break;
            }
            // Measured against the root: never less than the error of the node below.
            node.error = [0, 1].map(|a| node.error[a].max(below.error[a]));
            top = Pending {
                node,
                children: vec![Kept {
                    node: keep(top.node),
                    children: top.children,
                }],
            };
        }
        Ok(top)
    }
}

/// A leaf: the triangles `tris` of `layer`, with their vertices.
fn leaf(layer: &SurfaceMesh, tris: &[u32], tile: [u32; 2], cells: [u32; 4]) -> Node {
    let mut verts: Vec<u32> = tris
        .iter()
        .flat_map(|&t| layer.triangles[t as usize])
        .collect();
    verts.sort_unstable();
    verts.dedup();
    let local = |v: u32| verts.binary_search(&v).map_or(NONE, |i| i as u32);
    let mut mesh = SurfaceMesh::with_origin(layer.origin);
    let mut home = vec![NONE; verts.len()];
    for &t in tris {
        let tri = layer.triangles[t as usize];
        for &v in &tri {
            let l = local(v) as usize;
            if home[l] == NONE {
                home[l] = t;
            }
        }
        mesh.triangles.push(tri.map(local));
    }
    for &v in &verts {
        mesh.positions.push(layer.positions[v as usize]);
        mesh.texcoords.push(layer.texcoords[v as usize]);
        if !layer.scalars.is_empty() {
            mesh.scalars.push(layer.scalars[v as usize]);
        }
    }
    let mut node = Node {
        level: 0,
        tile,
        cells,
        error: [0.0; 2],
        bounds: mesh.bounds().unwrap_or(([0.0; 3], [0.0; 3])),
        mesh,
        children: Vec::new(),
        original: verts.into_iter().map(MaybeIndex::some).collect(),
        home,
    };
    reorder(&mut node);
    node
}

/// Vertex-cache order for the node's mesh, carrying its per-vertex data along.
fn reorder(node: &mut Node) {
    let remap = optimize_order(&mut node.mesh);
    let n = node.mesh.vertex_count();
    permute_by(&mut node.original, &remap, n);
    permute_by(&mut node.home, &remap, n);
}

/// Where a node sits in its layer's tree.
#[derive(Clone, Copy, Debug)]
struct Slot {
    level: u32,
    tile: [u32; 2],
    /// Cells covered: `i0, j0, i1, j1`, ends excluded.
    cells: [u32; 4],
}

/// Children merged into one mesh, the vertices they share (the same original
/// vertex, along their common borders) welded into one.
struct Merged {
    mesh: SurfaceMesh,
    original: Vec<MaybeIndex>,
    home: Vec<u32>,
}

impl Merged {
    fn of(children: &[&Node], origin: [f64; 3]) -> Merged {
        let mut mesh = SurfaceMesh::with_origin(origin);
        let (mut original, mut home) = (Vec::new(), Vec::new());
        for child in children {
            mesh.append(&child.mesh);
            original.extend_from_slice(&child.original);
            home.extend_from_slice(&child.home);
        }
        let mut order: Vec<(u32, u32)> = original
            .iter()
            .enumerate()
            .filter_map(|(v, o)| Some((o.get()?, v as u32)))
            .collect();
        order.sort_unstable();
        let mut weld: Vec<u32> = (0..mesh.vertex_count() as u32).collect();
        for w in order.windows(2) {
            if w[0].0 == w[1].0 {
                weld[w[1].1 as usize] = weld[w[0].1 as usize];
            }
        }
        // Keep the first vertex of each welded group.
        let mut keep = vec![MaybeIndex::NONE; weld.len()];
        let mut next = 0u32;
        for v in 0..weld.len() {
            if weld[v] as usize == v {
                keep[v] = MaybeIndex::some(next);
                next += 1;
            }
        }
        let welded = |v: u32| {
            keep[weld[v as usize] as usize]
                .get()
                .expect("the first vertex of each welded group is kept")
        };
        for t in mesh.triangles.iter_mut() {
            *t = t.map(welded);
        }
        let n = next as usize;
        permute_by(&mut mesh.positions, &keep, n);
        permute_by(&mut mesh.texcoords, &keep, n);
        if !mesh.scalars.is_empty() {
            permute_by(&mut mesh.scalars, &keep, n);
        }
        permute_by(&mut original, &keep, n);
        permute_by(&mut home, &keep, n);
        Merged {
            mesh,
            original,
            home,
        }
    }
}

/// Per vertex of `mesh`, whether it is on the outer border of `cells` where a
/// neighbour tile exists in a grid of `dims` cells: kept as it is, so that neighbours
/// meet without cracks.
fn locked_border(mesh: &SurfaceMesh, cells: [u32; 4], dims: [u32; 2]) -> Vec<bool> {
    let line = |c: u32| (2 * c + 1) as f32;
    mesh.texcoords
        .iter()
        .map(|&[u, v]| {
            (cells[0] > 0 && u == line(cells[0]))
                || (cells[2] < dims[0] && u == line(cells[2]))
                || (cells[1] > 0 && v == line(cells[1]))
                || (cells[3] < dims[1] && v == line(cells[3]))
        })
        .collect()
}

impl LayerBuild<'_> {
    /// A parent at `slot`: its children merged and welded, simplified with its outer
    /// border locked to `reduction` of their triangles (or more, see
    /// [`BuildOptions::reduction`]), and its error measured.
    fn parent(&self, children: &[&Node], slot: Slot, reduction: f64) -> Result<Node> {
        let merged = Merged::of(children, self.reference.mesh().origin);
        let merged_locked = locked_border(&merged.mesh, slot.cells, self.dims);
        // The locked border is kept whole, a triangle a vertex at least: beyond it the
        // inside keeps three quarters of the reduction's target or more.
        let border = merged_locked.iter().filter(|&&l| l).count();
        let reduced = ((merged.mesh.triangle_count() as f64) * reduction).ceil() as usize;
        let decimation = Options {
            target_triangles: reduced.max(border + reduced * 3 / 4),
            ..self.options.decimation.clone()
        };
        let simplified = decimate_on(
            &merged.mesh,
            &merged.home,
            &self.reference,
            &merged_locked,
            &decimation,
        )?;
        // Error: distance to the children's surface at the children's vertices, plus
        // the children's own error.
        let measured = self.deviation(&merged, &simplified);
        let (simplified, measured) =
            self.past_target(children, &merged, &decimation, simplified, measured, slot)?;
        let child_error = children.iter().fold([0f32; 2], |e, c| {
            [e[0].max(c.error[0]), e[1].max(c.error[1])]
        });
        let (mut lo, mut hi) = simplified.mesh.bounds().unwrap_or(([0.0; 3], [0.0; 3]));
        for c in children {
            for a in 0..3 {
                lo[a] = lo[a].min(c.bounds.0[a]);
                hi[a] = hi[a].max(c.bounds.1[a]);
            }
        }
        let mut node = Node {
            level: slot.level,
            tile: slot.tile,
            cells: slot.cells,
            error: [
                child_error[0] + measured[0] as f32,
                child_error[1] + measured[1] as f32,
            ],
            bounds: (lo, hi),
            original: simplified
                .source
                .iter()
                .map(|s| {
                    s.get()
                        .map_or(MaybeIndex::NONE, |s| merged.original[s as usize])
                })
                .collect(),
            home: simplified.home,
            mesh: simplified.mesh,
            children: Vec::new(),
        };
        reorder(&mut node);
        Ok(node)
    }

    /// Distance from `merged`, the children's surface, to `simplified` (see
    /// [`vertex_deviation`]).
    fn deviation(&self, merged: &Merged, simplified: &Decimated) -> [f64; 2] {
        vertex_deviation(
            (&merged.mesh, &merged.home),
            (&simplified.mesh, &simplified.home),
            self.reference.mesh(),
            &self.parts,
        )
    }

    /// `simplified`, the parent at `slot` simplified from `merged` to the target of
    /// `decimation` (`measured` its error), or, over a flat, affine stretch of layer,
    /// one simplified further where that changes nothing.
    ///
    /// There collapses that change nothing go on past the target, and stay if they
    /// changed nothing indeed (a quadric's cost is measured at the vertices only).
    /// Tried from the children where they are such stretches themselves (small by
    /// then, and the target may be below what their locked borders need), else from
    /// the target's result where it changed nothing. A leaf's error is nothing
    /// because it is the input, not because it is flat: taken for flat, the root of a
    /// layer of one tile (emerald's, 20 x 40 cells) was the only child of the second
    /// node above it, which kept it whole, and the chain stopped at half the root's
    /// triangles instead of at most COARSEST_TRIANGLES.
    fn past_target(
        &self,
        children: &[&Node],
        merged: &Merged,
        decimation: &Options,
        simplified: Decimated,
        measured: [f64; 2],
        slot: Slot,
    ) -> Result<(Decimated, [f64; 2])> {
        let unchanged = merged.mesh.bounds().map_or([0.0; 2], |(lo, hi)| {
            let largest = |a: usize| lo[a].abs().max(hi[a].abs());
            let ulp = |x: f32| f32::from_bits(x.to_bits() + 1) - x;
            [largest(0).max(largest(1)), largest(2)].map(|x| f64::from(UNCHANGED_ULPS * ulp(x)))
        });
        let exact = |error: &[f64]| error[0] <= unchanged[0] && error[1] <= unchanged[1];
        let flat_children = children
            .iter()
            .all(|c| c.level > 0 && exact(&c.error.map(f64::from)));
        let from_target = !flat_children && exact(&measured);
        if !from_target && !flat_children {
            return Ok((simplified, measured));
        }
        let (mesh, mesh_home) = if from_target {
            (&simplified.mesh, &simplified.home[..])
        } else {
            (&merged.mesh, &merged.home[..])
        };
        let free = Options {
            target_triangles: mesh.triangle_count(),
            free_past_target: true,
            ..decimation.clone()
        };
        let locked = locked_border(mesh, slot.cells, self.dims);
        let mut further = decimate_on(mesh, mesh_home, &self.reference, &locked, &free)?;
        if from_target {
            for s in further.source.iter_mut() {
                if let Some(from) = s.get() {
                    *s = simplified.source[from as usize];
                }
            }
        }
        // Kept where it changed nothing and is smaller, or where the target's result
        // changed something (from the children, the collapses that change nothing can
        // leave more than the target where the scalar is not affine).
        let further_measured = self.deviation(merged, &further);
        let smaller = further.mesh.triangle_count() < simplified.mesh.triangle_count();
        Ok(
            if exact(&further_measured) && (smaller || !exact(&measured)) {
                (further, further_measured)
            } else {
                (simplified, measured)
            },
        )
    }
}

/// Largest horizontal and vertical distance, over the vertices of `from` (vertex `v`
/// on triangle `from_home[v]` of the layer, `original`), to the point of `to` with the
/// same texture coordinates in the same component (`parts`), both but where they are
/// at a stray corner.
fn vertex_deviation(
    (from, from_home): (&SurfaceMesh, &[u32]),
    (to, to_home): (&SurfaceMesh, &[u32]),
    original: &SurfaceMesh,
    parts: &LayerParts,
) -> [f64; 2] {
    let label_of = |home: u32| parts.labels.get(home as usize).copied().unwrap_or(NONE);
    let stray = |mesh: &SurfaceMesh, home: &[u32], v: u32| {
        parts
            .strays
            .holds(original, home[v as usize], mesh.positions[v as usize])
    };
    let to_labels = to
        .triangles
        .iter()
        .map(|t| {
            if t.iter().any(|&v| stray(to, to_home, v)) {
                NONE
            } else {
                label_of(to_home[t[0] as usize])
            }
        })
        .collect();
    let index = UvIndex::new(to, to_labels);
    let mut found = Vec::new();
    let mut worst = [0f64; 2];
    for (v, &home) in from_home.iter().enumerate() {
        if stray(from, from_home, v as u32) {
            continue;
        }
        let uv = from.texcoords[v].map(f64::from);
        let p = from.positions[v].map(f64::from);
        let label = label_of(home);
        index.find(uv, label, &mut found);
        if found.is_empty()
            && let Some(n) = index.nearest(uv, label, 2)
        {
            found.push(n);
        }
        let best = found
            .iter()
            .map(|f| {
                let q = index.position(f);
                let xy = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
                (xy, (q[2] - p[2]).abs())
            })
            .min_by(|a, b| (a.0 * a.0 + a.1 * a.1).total_cmp(&(b.0 * b.0 + b.1 * b.1)));
        if let Some((xy, z)) = best {
            worst = [worst[0].max(xy), worst[1].max(z)];
        }
    }
    worst
}

/// The nodes of the tree under `root`, root first, breadth first, each with the
/// indices of its children (consecutive).
fn breadth_first<K>(root: Kept<K>) -> Vec<(K, Vec<u32>)> {
    let mut out: Vec<(K, Vec<u32>)> = Vec::new();
    let mut queue = std::collections::VecDeque::from([root]);
    while let Some(Kept { node, children }) = queue.pop_front() {
        let first = (out.len() + queue.len() + 1) as u32;
        out.push((node, (first..first + children.len() as u32).collect()));
        queue.extend(children);
    }
    out
}
