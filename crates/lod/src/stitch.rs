//! Surfaces decimated one by one, closed again where their outlines meet.
//!
//! A scene's layer surfaces and side walls are separate meshes: the top of the first
//! layer ends where the walls' top edge runs, along the same nodes. Each keeps its own
//! subset of those nodes, so after decimation the top's outline and the walls' edge
//! are two polylines through different nodes, and between them a sliver of the
//! background shows. [`stitch`] makes every node of such a shared outline that one
//! surface kept a node of the others too, by splitting their outline edge at it, and
//! puts all of them back where the input had them (a fit or lift may have moved one
//! side only).

use std::collections::HashMap;

use strata_grid::SurfaceMesh;

use crate::reference::{NONE, VertexTriangles, boundary_edges, triangle_adjacency};
use crate::{Decimated, NEW};

/// What [`stitch`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stitched {
    /// Outline nodes put back into a surface that had dropped them, one triangle each.
    pub inserted: usize,
    /// Shared outline nodes that could not be put back (the surface's outline there
    /// no longer runs along the input's, or the split would fold a triangle).
    pub skipped: usize,
}

/// A position, bit for bit.
type Key = [u32; 3];

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
fn outline_edges(mesh: &SurfaceMesh) -> Vec<((u32, u32), u32)> {
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
/// outputs whose inputs have it or in none, at its input position, so the outlines
/// run through the same nodes along straight edges. Each node put back costs a
/// triangle. Nothing changes unless there is an output for every input.
pub fn stitch(inputs: &[&SurfaceMesh], outputs: &mut [&mut Decimated]) -> Stitched {
    let mut stitched = Stitched::default();
    let Some(origin) = inputs.first().map(|m| m.origin) else {
        return stitched;
    };
    if inputs.len() != outputs.len() {
        return stitched;
    }
    let outlines: Vec<Outline> = inputs.iter().map(|m| Outline::of(m)).collect();
    // Outline vertices by position, those of more than one surface.
    let mut at: HashMap<Key, Vec<(usize, u32)>> = HashMap::new();
    for (s, (mesh, outline)) in inputs.iter().zip(&outlines).enumerate() {
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
    if at.is_empty() {
        return stitched;
    }
    // Per surface, the output vertex of each input outline vertex it kept: by
    // `source`, or, for one a fit or lift moved (texture coordinates stay), the corner
    // of its home triangle with its texture coordinates (coincident vertices on two
    // sides of a seam can share those; they do not share triangles), else the input
    // outline vertex of its texture coordinates nearest to it.
    let mut present: Vec<HashMap<u32, u32>> = Vec::with_capacity(inputs.len());
    let mut output_edges = Vec::with_capacity(inputs.len());
    for (s, output) in outputs.iter().enumerate() {
        let (input, outline) = (inputs[s], &outlines[s]);
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
        output_edges.push(edges);
        let mut kept = HashMap::new();
        for (o, &source) in output.source.iter().enumerate() {
            if !own.on(o as u32) {
                continue;
            }
            let v = if source != NEW {
                Some(source)
            } else {
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
            };
            if let Some(v) = v.filter(|&v| outline.on(v)) {
                kept.insert(v, o as u32);
            }
        }
        present.push(kept);
    }
    // Nodes one surface kept go back into the others.
    let mut missing: Vec<Vec<u32>> = vec![Vec::new(); inputs.len()];
    for list in at.values() {
        if list.iter().any(|(s, v)| present[*s].contains_key(v)) {
            for &(s, v) in list {
                if !present[s].contains_key(&v) {
                    missing[s].push(v);
                }
            }
        }
    }
    for (s, vertices) in missing.iter_mut().enumerate() {
        if vertices.is_empty() {
            continue;
        }
        vertices.sort_unstable();
        vertices.dedup();
        let mut edges: HashMap<(u32, u32), u32> =
            std::mem::take(&mut output_edges[s]).into_iter().collect();
        for &v in vertices.iter() {
            match put_back(
                inputs[s],
                &outlines[s],
                outputs[s],
                &present[s],
                &mut edges,
                v,
            ) {
                Some(o) => {
                    present[s].insert(v, o);
                    stitched.inserted += 1;
                }
                None => stitched.skipped += 1,
            }
        }
    }
    // Every shared node where its input has it: the input vertex again.
    for list in at.values() {
        for &(s, v) in list {
            if let Some(&o) = present[s].get(&v) {
                outputs[s].mesh.positions[o as usize] = inputs[s].positions[v as usize];
                outputs[s].source[o as usize] = v;
            }
        }
    }
    stitched
}

/// Puts input outline vertex `v` back into `output`: splits the output's outline
/// edge between the nearest vertices along the input's outline on either side that
/// the output has (`kept`: input vertex to output vertex), found in `edges` (the
/// output's outline edges and their triangles, kept up to date), and returns the new
/// vertex; `None` where the output has no such edge, or the split would turn a
/// triangle over.
fn put_back(
    input: &SurfaceMesh,
    outline: &Outline,
    output: &mut Decimated,
    kept: &HashMap<u32, u32>,
    edges: &mut HashMap<(u32, u32), u32>,
    v: u32,
) -> Option<u32> {
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
    let point = |p: [f32; 3]| p.map(f64::from);
    let normal = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
        let (u, w): ([f64; 3], [f64; 3]) = (
            std::array::from_fn(|i| b[i] - a[i]),
            std::array::from_fn(|i| c[i] - a[i]),
        );
        [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ]
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let [b, a, c] = [before, after, third].map(|w| point(mesh.positions[w as usize]));
    let p = point(input.positions[v as usize]);
    let whole = normal(b, a, c);
    if dot(normal(b, p, c), whole) <= 0.0 || dot(normal(p, a, c), whole) <= 0.0 {
        return None;
    }
    let new = mesh.vertex_count() as u32;
    mesh.positions.push(input.positions[v as usize]);
    if let Some(&uv) = input.texcoords.get(v as usize) {
        mesh.texcoords.push(uv);
    }
    if !mesh.scalars.is_empty() {
        mesh.scalars
            .push(input.scalars.get(v as usize).copied().unwrap_or(f32::NAN));
    }
    let mut first = tri;
    first[(k + 1) % 3] = new;
    let mut second = tri;
    second[k] = new;
    mesh.triangles[t] = first;
    edges.remove(&(before, after));
    edges.insert((before, new), t as u32);
    edges.insert((new, after), mesh.triangles.len() as u32);
    mesh.triangles.push(second);
    output.source.push(v);
    output.home.push(outline.triangle[v as usize]);
    Some(new)
}
