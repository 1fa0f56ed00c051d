//! Surfaces decimated one by one, closed again where their outlines meet.
//!
//! A scene's layer surfaces and side walls are separate meshes: the top of the first
//! layer ends where the walls' top edge runs, along the same nodes. Each keeps its own
//! subset of those nodes, so after decimation the top's outline and the walls' edge
//! are two polylines through different nodes, and between them a sliver of the
//! background shows. [`stitch`] makes every node of such a shared outline that one
//! surface kept a node of the others too, by splitting their outline edge at it, and
//! puts all of them back where the input had them (a fit or lift may have moved one
//! side only). Where the input's place would turn a half of the split triangle over,
//! a node beyond the edge (a corner the decimation cut off) goes back there as a
//! triangle of its own on the edge; one inside (a wall thinning to nothing under an
//! outline the decimation straightened) goes on the edge it splits instead, and its
//! copies in the other surfaces follow it there. No half is turned over in texture
//! space either, where the grid lines are drawn from: a node whose own texture point
//! would do that takes the one on the edge.

use std::collections::HashMap;

use strata_grid::SurfaceMesh;

use crate::decimate::{cross3, dot3, sub3p};
use crate::reference::{NONE, VertexTriangles, boundary_edges, cross2, triangle_adjacency};
use crate::{Decimated, MaybeIndex};

/// What [`stitch`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stitched {
    /// Outline nodes put back into a surface that had dropped them, one triangle each.
    pub inserted: usize,
    /// Of those, the nodes beyond the outline edge between their neighbours, where the
    /// decimation cut their corner off and splitting the edge's triangle would turn a
    /// half of it over (in space or in texture space): each went back at the input's
    /// place as a triangle of its own on that edge.
    pub corners: usize,
    /// Of those, the nodes put on the outline edge they split rather than where the
    /// input has them, which would have turned a triangle over; their copies in the
    /// other surfaces moved there too.
    pub on_edge: usize,
    /// Of those, the nodes whose own texture point would turn a half of the split
    /// triangle over in texture space, which took the point on the edge's instead:
    /// the grid lines bend a little near them.
    pub texture_on_edge: usize,
    /// Shared outline nodes that could not be put back (the surface's outline there
    /// no longer runs along the input's, or the split would fold a triangle even on
    /// the edge), or whose copy could not follow one put on an edge all the way
    /// without folding (it goes as far as it can).
    pub skipped: usize,
}

/// A position, bit for bit.
type Key = [u32; 3];

/// An output's outline edges, each with its triangle, kept up to date as edges split.
type EdgeTriangles = HashMap<(u32, u32), u32>;

/// A mesh's outline edges, each with its triangle ([`outline_edges`]).
type OutlineEdges = Vec<((u32, u32), u32)>;

/// Outline vertices shared by more than one surface: by position, each surface's
/// vertex there.
type SharedNodes = Vec<(Key, Vec<(usize, u32)>)>;

/// The outline of a mesh: per vertex on it, the next and previous vertex along it
/// (in the triangles' winding) and a triangle with the edge to the next; [`NONE`]
/// off the outline, and where more than one outline passes through a vertex.
struct Outline {
    next: Vec<u32>,
    prev: Vec<u32>,
    triangle: Vec<u32>,
    /// On an outline edge, where several pass too.
    on: Vec<bool>,
}

/// The outline edges of `mesh` ([`boundary_edges`]).
fn outline_edges(mesh: &SurfaceMesh) -> OutlineEdges {
    let vt = VertexTriangles::new(mesh.vertex_count(), &mesh.triangles);
    boundary_edges(&mesh.triangles, &triangle_adjacency(&mesh.triangles, &vt))
}

impl Outline {
    fn of(mesh: &SurfaceMesh) -> Outline {
        Outline::from_edges(mesh.vertex_count(), &outline_edges(mesh))
    }

    /// The outline of a mesh of `n` vertices whose [`outline_edges`] are `edges`.
    fn from_edges(n: usize, edges: &[((u32, u32), u32)]) -> Outline {
        let mut out = Outline {
            next: vec![NONE; n],
            prev: vec![NONE; n],
            triangle: vec![NONE; n],
            on: vec![false; n],
        };
        // Outline edges starting and ending at each vertex: more than one of either
        // where several outlines pass.
        let (mut starting, mut ending) = (vec![0u8; n], vec![0u8; n]);
        for &((p, q), t) in edges {
            let (p, q) = (p as usize, q as usize);
            starting[p] = starting[p].saturating_add(1);
            ending[q] = ending[q].saturating_add(1);
            out.on[p] = true;
            out.on[q] = true;
            out.next[p] = q as u32;
            out.prev[q] = p as u32;
            out.triangle[p] = t;
        }
        for v in 0..n {
            if starting[v] > 1 || ending[v] > 1 {
                out.next[v] = NONE;
                out.prev[v] = NONE;
            }
        }
        out
    }

    /// Whether `v` is on an outline edge (`false` for no vertex of the mesh).
    fn on(&self, v: u32) -> bool {
        self.on.get(v as usize).copied().unwrap_or(false)
    }
}

/// Closes the outlines that `outputs[i]`, the decimation of `inputs[i]` (each on
/// itself as reference, as [`crate::decimate_chosen`] makes them), shares with the
/// others: where two inputs have outline vertices at the same position, bit for bit,
/// and relative to the same origin. After it, each shared outline node is in all the
/// outputs whose inputs have it or in none, at its input position (or, where that
/// would fold a triangle, at one place between it and the edge a surface split for
/// it, or as near that place as each copy goes), so the outlines run through the same
/// nodes along straight edges. Each node put back costs a triangle. Nothing changes
/// unless there is an output for every input.
pub fn stitch(inputs: &[&SurfaceMesh], outputs: &mut [&mut Decimated]) -> Stitched {
    let mut stitched = Stitched::default();
    if inputs.is_empty() || inputs.len() != outputs.len() {
        return stitched;
    }
    let outlines: Vec<Outline> = inputs.iter().map(|m| Outline::of(m)).collect();
    let shared = shared_outline_vertices(inputs, &outlines);
    if shared.is_empty() {
        return stitched;
    }
    let (mut present, mut output_edges): (Vec<_>, Vec<_>) = outputs
        .iter()
        .enumerate()
        .map(|(s, output)| kept_outline_vertices(inputs[s], &outlines[s], output))
        .unzip();
    // Nodes one surface kept go back into the others.
    let mut missing: Vec<Vec<u32>> = vec![Vec::new(); inputs.len()];
    for (_, list) in &shared {
        if list.iter().any(|(s, v)| present[*s].contains_key(v)) {
            for &(s, v) in list {
                if !present[s].contains_key(&v) {
                    missing[s].push(v);
                }
            }
        }
    }
    // Nodes put on an edge, by their input position: where their copies go.
    let mut on_edge: HashMap<Key, [f32; 3]> = HashMap::new();
    for (s, vertices) in missing.iter_mut().enumerate() {
        if vertices.is_empty() {
            continue;
        }
        vertices.sort_unstable();
        vertices.dedup();
        let mut edges: EdgeTriangles = std::mem::take(&mut output_edges[s]).into_iter().collect();
        for &v in vertices.iter() {
            let own = inputs[s].positions[v as usize];
            let agreed = on_edge.get(&own.map(f32::to_bits)).copied();
            match put_back(
                inputs[s],
                &outlines[s],
                outputs[s],
                (&present[s], &mut edges),
                v,
                agreed,
            ) {
                Some(Put {
                    vertex: o,
                    position,
                    corner,
                    texture_on_edge,
                }) => {
                    present[s].insert(v, o);
                    stitched.inserted += 1;
                    stitched.corners += usize::from(corner);
                    stitched.texture_on_edge += usize::from(texture_on_edge);
                    if position != own {
                        on_edge.insert(own.map(f32::to_bits), position);
                        stitched.on_edge += 1;
                    }
                }
                None => stitched.skipped += 1,
            }
        }
    }
    // Every shared node where its input has it: the input vertex again.
    for (key, list) in &shared {
        if on_edge.contains_key(key) {
            continue;
        }
        for &(s, v) in list {
            if let Some(&o) = present[s].get(&v) {
                outputs[s].mesh.positions[o as usize] = inputs[s].positions[v as usize];
                outputs[s].source[o as usize] = MaybeIndex::some(v);
            }
        }
    }
    stitched.skipped += follow_to_edges(&shared, &on_edge, &present, outputs);
    stitched
}

/// The outline vertices of `inputs` (with their `outlines`) at a position, bit for
/// bit, where another surface of the same origin has one too, by position, each with
/// its surface and vertex; in the order of the positions' bits, so that the result
/// does not depend on a map's order.
fn shared_outline_vertices(inputs: &[&SurfaceMesh], outlines: &[Outline]) -> SharedNodes {
    let origin = inputs[0].origin;
    let mut at: HashMap<Key, Vec<(usize, u32)>> = HashMap::new();
    for (s, (mesh, outline)) in inputs.iter().zip(outlines).enumerate() {
        if mesh.origin != origin {
            continue;
        }
        for (v, p) in mesh.positions.iter().enumerate() {
            if outline.on(v as u32) {
                at.entry(p.map(f32::to_bits))
                    .or_default()
                    .push((s, v as u32));
            }
        }
    }
    at.retain(|_, list| list.iter().any(|&(s, _)| s != list[0].0));
    let mut shared: SharedNodes = at.into_iter().collect();
    shared.sort_unstable_by_key(|(key, _)| *key);
    shared
}

/// The output vertex of each outline vertex of `input` (with its `outline`) that
/// `output` kept, and the output's outline edges. A vertex is found by `source`, or,
/// for one a fit or lift moved (texture coordinates stay), as the corner of its home
/// triangle with its texture coordinates (coincident vertices on two sides of a seam
/// can share those; they do not share triangles), else as the input outline vertex of
/// its texture coordinates nearest to it.
fn kept_outline_vertices(
    input: &SurfaceMesh,
    outline: &Outline,
    output: &Decimated,
) -> (HashMap<u32, u32>, OutlineEdges) {
    let mut by_texcoord: HashMap<[u32; 2], Vec<u32>> = HashMap::new();
    for (v, uv) in input.texcoords.iter().enumerate() {
        if outline.on(v as u32) {
            by_texcoord
                .entry(uv.map(f32::to_bits))
                .or_default()
                .push(v as u32);
        }
    }
    let edges = outline_edges(&output.mesh);
    let own = Outline::from_edges(output.mesh.vertex_count(), &edges);
    let mut kept = HashMap::new();
    for (o, source) in output.source.iter().enumerate() {
        if !own.on(o as u32) {
            continue;
        }
        let v = source.get().or_else(|| {
            output.mesh.texcoords.get(o).and_then(|&uv| {
                let at_home = output
                    .home
                    .get(o)
                    .and_then(|&t| input.triangles.get(t as usize))
                    .and_then(|corners| {
                        corners.iter().copied().find(|&c| {
                            outline.on(c) && input.texcoords.get(c as usize) == Some(&uv)
                        })
                    });
                at_home.or_else(|| {
                    let here = output.mesh.positions[o];
                    let distance = |v: &&u32| {
                        let p = input.positions[**v as usize];
                        (0..3).map(|k| (p[k] - here[k]).powi(2)).sum::<f32>()
                    };
                    by_texcoord
                        .get(&uv.map(f32::to_bits))?
                        .iter()
                        .min_by(|a, b| distance(a).total_cmp(&distance(b)))
                        .copied()
                })
            })
        });
        if let Some(v) = v.filter(|&v| outline.on(v)) {
            kept.insert(v, o as u32);
        }
    }
    (kept, edges)
}

/// Moves the copies of the `shared` nodes that one surface put on an edge (`on_edge`,
/// by input position), the output vertices `present` names in `outputs`: all copies
/// at the first point from the input's place towards that edge where none of them
/// folds a triangle (the surface that split its edge there too), else each copy as
/// far towards the edge as it goes without folding one. Returns the copies that could
/// not reach the common point ([`Stitched::skipped`]).
fn follow_to_edges(
    shared: &SharedNodes,
    on_edge: &HashMap<Key, [f32; 3]>,
    present: &[HashMap<u32, u32>],
    outputs: &mut [&mut Decimated],
) -> usize {
    let mut skipped = 0;
    let mut stars: Vec<Option<VertexTriangles>> = (0..outputs.len()).map(|_| None).collect();
    for (key, list) in shared {
        let Some(&edge) = on_edge.get(key) else {
            continue;
        };
        let copies: Vec<(usize, u32, u32)> = list
            .iter()
            .filter_map(|&(s, v)| present[s].get(&v).map(|&o| (s, v, o)))
            .collect();
        for &(s, _, _) in &copies {
            let mesh = &outputs[s].mesh;
            stars[s]
                .get_or_insert_with(|| VertexTriangles::new(mesh.vertex_count(), &mesh.triangles));
        }
        let unfolded = |s: usize, o: u32, position: [f32; 3]| {
            stars[s]
                .as_ref()
                .is_some_and(|star| moves_unfolded(&outputs[s].mesh, star, o, position))
        };
        let own = point(key.map(f32::from_bits));
        let towards = |step: usize| -> [f32; 3] {
            let part = step as f64 / TOWARDS_THE_EDGE as f64;
            std::array::from_fn(|i| (own[i] + part * (f64::from(edge[i]) - own[i])) as f32)
        };
        let common = (1..=TOWARDS_THE_EDGE)
            .map(towards)
            .find(|&position| copies.iter().all(|&(s, _, o)| unfolded(s, o, position)));
        // Without one, each copy goes as far towards the edge as it can: the crack that
        // stays is no wider than it must be.
        let moves: Vec<Option<([f32; 3], bool)>> = copies
            .iter()
            .map(|&(s, _, o)| {
                common.map(|position| (position, true)).or_else(|| {
                    (0..=TOWARDS_THE_EDGE)
                        .rev()
                        .map(|step| (towards(step), step == TOWARDS_THE_EDGE))
                        .find(|&(position, _)| unfolded(s, o, position))
                })
            })
            .collect();
        for ((s, v, o), position) in copies.into_iter().zip(moves) {
            let Some((position, closed)) = position else {
                skipped += 1;
                continue;
            };
            skipped += usize::from(!closed);
            outputs[s].mesh.positions[o as usize] = position;
            outputs[s].source[o as usize] = MaybeIndex::some(v);
        }
    }
    skipped
}

/// The normal of triangle `a b c` (twice its area).
fn normal(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    cross3(sub3p(b, a), sub3p(c, a))
}

fn point(p: [f32; 3]) -> [f64; 3] {
    p.map(f64::from)
}

/// Would every triangle of `mesh` at vertex `o` (`star`) keep its side when `o` moves
/// to `position`?
fn moves_unfolded(mesh: &SurfaceMesh, star: &VertexTriangles, o: u32, position: [f32; 3]) -> bool {
    star.of(o).iter().all(|&t| {
        let corners = mesh.triangles[t as usize];
        let before = corners.map(|w| point(mesh.positions[w as usize]));
        let after = corners.map(|w| {
            if w == o {
                point(position)
            } else {
                point(mesh.positions[w as usize])
            }
        });
        dot3(
            normal(before[0], before[1], before[2]),
            normal(after[0], after[1], after[2]),
        ) > 0.0
    })
}

/// Where a node whose input position (or texture point) `p` would turn a half of the
/// split triangle over goes on the outline edge `b a` instead: `p`'s nearest point
/// there, kept off both ends so that neither half is empty.
fn on_the_edge<const N: usize>(b: [f64; N], a: [f64; N], p: [f64; N]) -> [f32; N] {
    let e: [f64; N] = std::array::from_fn(|i| a[i] - b[i]);
    let len2: f64 = e.iter().map(|x| x * x).sum();
    let t = if len2 > 0.0 {
        let along: f64 = (0..N).map(|i| (p[i] - b[i]) * e[i]).sum();
        (along / len2).clamp(EDGE_END_MARGIN, 1.0 - EDGE_END_MARGIN)
    } else {
        0.5
    };
    std::array::from_fn(|i| (b[i] + t * e[i]) as f32)
}

/// The points tried for a node one surface put on an edge and its copies, as parts of
/// the way from the input's place to that edge: the nearest where no copy folds.
const TOWARDS_THE_EDGE: usize = 16;

/// How near either end of the edge it splits a node put on the edge may go, as a part
/// of its length.
const EDGE_END_MARGIN: f64 = 0.05;

/// A node [`put_back`]: its vertex, where it went, and how.
struct Put {
    vertex: u32,
    position: [f32; 3],
    /// As a triangle of its own beyond the edge, not by splitting the edge's triangle.
    corner: bool,
    /// With the texture point on the edge, not its own.
    texture_on_edge: bool,
}

/// Puts input outline vertex `v` back into `output`: splits the output's outline
/// edge between the nearest vertices along the input's outline on either side that
/// the output has (`kept`: input vertex to output vertex), found in `edges` (the
/// output's outline edges and their triangles, kept up to date). The node goes to
/// `agreed` if given (where another surface put it on its edge), else to the input's
/// place; where the split would turn a half of the triangle over there (in space or
/// in texture space) and the node lies beyond the edge, it goes back there as a
/// triangle of its own on the edge; else, where the split turns a half over in space,
/// on the edge itself ([`on_the_edge`]), and where it turns one over in texture space
/// only, with the texture point on the edge. `None` where the output has no such
/// edge, or the split would turn a triangle over in space at `agreed` or on the edge.
fn put_back(
    input: &SurfaceMesh,
    outline: &Outline,
    output: &mut Decimated,
    (kept, edges): (&HashMap<u32, u32>, &mut EdgeTriangles),
    v: u32,
    agreed: Option<[f32; 3]>,
) -> Option<Put> {
    let along = |step: &[u32]| {
        let mut w = v;
        for _ in 0..input.vertex_count() {
            w = step[w as usize];
            if w == NONE || w == v {
                return None;
            }
            if let Some(&o) = kept.get(&w) {
                return Some(o);
            }
        }
        None
    };
    let (before, after) = (along(&outline.prev)?, along(&outline.next)?);
    let mesh = &mut output.mesh;
    let t = *edges.get(&(before, after))? as usize;
    let tri = *mesh.triangles.get(t)?;
    let k = (0..3).find(|&k| tri[k] == before && tri[(k + 1) % 3] == after)?;
    let third = tri[(k + 2) % 3];
    let [b, a, c] = [before, after, third].map(|w| point(mesh.positions[w as usize]));
    let whole = normal(b, a, c);
    let uv = *input.texcoords.get(v as usize)?;
    let [tb, ta, tc] = [before, after, third].map(|w| mesh.texcoords[w as usize].map(f64::from));
    let tn = uv.map(f64::from);
    let whole_uv = cross2(tb, ta, tc);
    // Both halves of the split keep the triangle's side, in space with the node at `p`
    // and in texture space (where the grid lines are drawn from).
    let split_uv = cross2(tb, tn, tc) * whole_uv > 0.0 && cross2(tn, ta, tc) * whole_uv > 0.0;
    let splits_in_space = |p: [f32; 3]| {
        let p = point(p);
        dot3(normal(b, p, c), whole) > 0.0 && dot3(normal(p, a, c), whole) > 0.0
    };
    let splits = |p: [f32; 3]| split_uv && splits_in_space(p);
    // Beyond the edge, where the decimation cut the corner at the node off, the corner
    // can go back as a triangle of its own on the edge.
    let ear_fits = |p: [f32; 3]| {
        dot3(normal(a, b, point(p)), whole) > 0.0 && cross2(ta, tb, tn) * whole_uv > 0.0
    };
    let own = agreed.unwrap_or(input.positions[v as usize]);
    let (position, corner) = if splits(own) {
        (own, false)
    } else if ear_fits(own) {
        (own, true)
    } else if splits_in_space(own) {
        (own, false)
    } else {
        let on_edge = on_the_edge(b, a, point(own));
        if agreed.is_some() || !splits_in_space(on_edge) {
            return None;
        }
        (on_edge, false)
    };
    // A split that would turn a half over in texture space takes the texture point on
    // the edge instead: the grid lines near the node bend (by up to 0.9 of a cell on
    // emerald's), none is drawn mirrored.
    let texture_on_edge = !corner && !split_uv;
    let uv = if texture_on_edge {
        on_the_edge(tb, ta, tn)
    } else {
        uv
    };
    let new = mesh.vertex_count() as u32;
    mesh.positions.push(position);
    mesh.texcoords.push(uv);
    if !mesh.scalars.is_empty() {
        mesh.scalars
            .push(input.scalars.get(v as usize).copied().unwrap_or(f32::NAN));
    }
    let added = mesh.triangles.len() as u32;
    edges.remove(&(before, after));
    if corner {
        mesh.triangles.push([after, before, new]);
        edges.insert((before, new), added);
        edges.insert((new, after), added);
    } else {
        let mut first = tri;
        first[(k + 1) % 3] = new;
        let mut second = tri;
        second[k] = new;
        mesh.triangles[t] = first;
        mesh.triangles.push(second);
        edges.insert((before, new), t as u32);
        edges.insert((new, after), added);
        // The triangle's edge from `after` to `third` went to the second half; it may
        // be an outline edge too.
        if let Some(owner) = edges.get_mut(&(after, third))
            && *owner == t as u32
        {
            *owner = added;
        }
    }
    output.source.push(MaybeIndex::some(v));
    output.home.push(outline.triangle[v as usize]);
    Some(Put {
        vertex: new,
        position,
        corner,
        texture_on_edge,
    })
}
