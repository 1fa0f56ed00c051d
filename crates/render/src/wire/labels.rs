//! The α/β/γ vertex labelling of Celes & Abraham (section 3.2) for drawing the edges
//! of arbitrary triangle meshes with per-vertex texture coordinates: every triangle
//! needs three distinct labels. A search over triangles across their edges labels
//! vertices; a vertex whose label conflicts is duplicated (reusing an earlier
//! duplicate with the right label when there is one), and the search stops spreading
//! from a triangle that needed a duplicate; an outer loop reaches every triangle.
//!
//! The paper searches depth first; we search breadth first. A depth-first walk runs
//! off in a long thin path whose sides later close onto each other with labels that
//! disagree, while a breadth-first front grows as a disc, labelling each triangle
//! from two already labelled neighbours. Measured (tests/wire_modes.rs): breadth first
//! copies far fewer vertices on an icosphere, about as many on Delaunay
//! triangulations, and none on structured meshes either way; on `strata bench wire`'s
//! sphere it makes `tex` cheaper (`docs/performance.md`, "Wireframe techniques").

use std::collections::{HashMap, VecDeque};

/// The result: for each output vertex the original it copies and its label (0, 1, 2),
/// and the triangles re-indexed onto the output vertices.
#[derive(Clone, Debug, PartialEq)]
pub struct Labelling {
    /// Per output vertex, the input vertex it copies.
    pub source_vertex: Vec<u32>,
    /// Per output vertex, its label (α, β, γ as 0, 1, 2).
    pub labels: Vec<u8>,
    /// The input's triangles re-indexed onto the output vertices.
    pub triangles: Vec<[u32; 3]>,
}

impl Labelling {
    /// Fraction of vertices added by duplication (the paper's "Extra" column).
    pub fn duplicated_fraction(&self, original_vertices: usize) -> f64 {
        if original_vertices == 0 {
            return 0.0;
        }
        (self.labels.len() - original_vertices) as f64 / original_vertices as f64
    }

    /// The per-vertex texture coordinates of a label: 0 at the vertex's own unit, 1 at
    /// the two others, so that unit `l` draws the edge opposite the vertex labelled `l`.
    /// A vertex no triangle uses is left unlabelled and gets 1 at all three.
    pub fn coordinates(label: u8) -> [f32; 3] {
        let mut s = [1.0; 3];
        if let Some(own) = s.get_mut(usize::from(label)) {
            *own = 0.0;
        }
        s
    }
}

const UNLABELLED: u8 = u8::MAX;

/// Labels the vertices of `triangles` (over `vertex_count` vertices).
pub fn label_vertices(vertex_count: usize, triangles: &[[u32; 3]]) -> Labelling {
    // Triangles around each undirected edge.
    let mut edges: HashMap<(u32, u32), Vec<u32>> = HashMap::with_capacity(triangles.len() * 3 / 2);
    for (t, tri) in triangles.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (tri[e], tri[(e + 1) % 3]);
            edges
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push(t as u32);
        }
    }
    let mut out = Labelling {
        source_vertex: (0..vertex_count as u32).collect(),
        labels: vec![UNLABELLED; vertex_count],
        triangles: triangles.to_vec(),
    };
    // Duplicates of each original vertex, by label.
    let mut copies: HashMap<u32, [u32; 3]> = HashMap::new();
    let mut visited = vec![false; triangles.len()];
    let mut queue = VecDeque::new();
    for first in 0..triangles.len() {
        if visited[first] {
            continue;
        }
        queue.push_back(first as u32);
        while let Some(t) = queue.pop_front() {
            let t = t as usize;
            if visited[t] {
                continue;
            }
            visited[t] = true;
            if label_triangle(&mut out, &mut copies, t) {
                continue;
            }
            let tri = triangles[t];
            for e in 0..3 {
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                for &n in &edges[&(a.min(b), a.max(b))] {
                    if !visited[n as usize] {
                        queue.push_back(n);
                    }
                }
            }
        }
    }
    out
}

/// Labels triangle `t`'s vertices; returns whether a vertex had to be duplicated.
fn label_triangle(out: &mut Labelling, copies: &mut HashMap<u32, [u32; 3]>, t: usize) -> bool {
    let tri = out.triangles[t];
    let mut used = [false; 3];
    let mut conflicting = [false; 3];
    for (c, &v) in tri.iter().enumerate() {
        let l = out.labels[v as usize];
        if l != UNLABELLED {
            if used[usize::from(l)] {
                conflicting[c] = true;
            } else {
                used[usize::from(l)] = true;
            }
        }
    }
    let mut duplicated = false;
    for c in 0..3 {
        let v = tri[c];
        if out.labels[v as usize] != UNLABELLED && !conflicting[c] {
            continue;
        }
        let Some(free) = (0..3u8).find(|&l| !used[usize::from(l)]) else {
            continue;
        };
        used[usize::from(free)] = true;
        if !conflicting[c] {
            out.labels[v as usize] = free;
            continue;
        }
        duplicated = true;
        let source = out.source_vertex[v as usize];
        let slots = copies.entry(source).or_insert([u32::MAX; 3]);
        let copy = if slots[usize::from(free)] != u32::MAX {
            slots[usize::from(free)]
        } else if out.labels[source as usize] == free {
            source
        } else {
            let id = out.labels.len() as u32;
            out.labels.push(free);
            out.source_vertex.push(source);
            slots[usize::from(free)] = id;
            id
        };
        out.triangles[t][c] = copy;
    }
    duplicated
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(l: &Labelling) {
        for t in &l.triangles {
            let labels = t.map(|v| l.labels[v as usize]);
            assert!(labels.iter().all(|&x| x < 3));
            assert!(
                labels[0] != labels[1] && labels[1] != labels[2] && labels[0] != labels[2],
                "{labels:?}"
            );
        }
    }

    /// A structured triangle mesh: an n x n grid of quads, each split along the same diagonal.
    fn structured(n: u32) -> (usize, Vec<[u32; 3]>) {
        let v = |i: u32, j: u32| j * (n + 1) + i;
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                tris.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
                tris.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
            }
        }
        (((n + 1) * (n + 1)) as usize, tris)
    }

    #[test]
    fn structured_meshes_need_no_duplicate() {
        let (nv, tris) = structured(40);
        let l = label_vertices(nv, &tris);
        check(&l);
        assert_eq!(l.duplicated_fraction(nv), 0.0);
    }

    #[test]
    fn a_fan_of_five_triangles_needs_duplicates() {
        // Five triangles around a centre vertex: the rim is an odd cycle, which two
        // labels cannot alternate around, so some rim vertex must be duplicated.
        let tris: Vec<[u32; 3]> = (0..5).map(|k| [0, 1 + k, 1 + (k + 1) % 5]).collect();
        let l = label_vertices(6, &tris);
        check(&l);
        assert!(l.duplicated_fraction(6) > 0.0);
        for (t, orig) in l.triangles.iter().zip(&tris) {
            assert_eq!(t.map(|v| l.source_vertex[v as usize]), *orig);
        }
    }

    #[test]
    fn coordinates_draw_the_opposite_edge() {
        assert_eq!(Labelling::coordinates(0), [0.0, 1.0, 1.0]);
        assert_eq!(Labelling::coordinates(2), [1.0, 1.0, 0.0]);
    }
}
