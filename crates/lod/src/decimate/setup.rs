//! Preparing a decimation: checking its input, classifying vertices (boundary,
//! locked, seam twins) and summing each vertex's quadric.

use strata_grid::SurfaceMesh;

use super::collapse::COMPACT_BELOW;
use super::collapser::{ALIVE, BOUNDARY, Collapser, LOCKED, SEAM};
use super::frame::Frame;
use super::passes::{LOCAL_ROUNDS, LOCAL_VERTICES, Scratch};
use super::vector::{cross3, dot3, sub3};
use super::{Options, Timings};
use crate::cover::CellCover;
use crate::quadric::{Local, Point, Quadric};
use crate::reference::{NONE, Reference, VertexTriangles, cross2};
use crate::{Error, Result};

/// Cost, relative to the squared mean edge, of the collapses past the target
/// ([`Options::free_past_target`]). Not the tie's 1e-12: on a flat surface with an
/// affine scalar the vertices' single-precision quadrics ([`Local`]) put the cost of
/// collapses that change nothing near 1e-8 of it (a 20 x 20 test grid stopped at 20
/// triangles under the tie, at 3 under this).
const FREE_COST: f64 = 1e-6;

/// Per vertex, the other boundary vertex at its position (bit for bit), or [`NONE`];
/// where more than two are at one place, they are all locked. Two boundaries that
/// run together along a seam are two sides of one line: a layer pinched out between
/// two side walls (the wall's faces above and below it end on the same nodes, but
/// with the texture coordinates of their own layers), or walls of constant i and j
/// meeting at a corner pillar. A vertex of one side may go only where its twin goes,
/// onto the twin of where it goes. Empty when the surface has no seam.
pub(super) fn seam_twins(positions: &[[f32; 3]], flags: &mut [u8]) -> Vec<u32> {
    let on_boundary = flags
        .iter()
        .enumerate()
        .filter(|&(_, f)| f & ALIVE != 0 && f & (BOUNDARY | LOCKED) != 0)
        .map(|(v, _)| v as u32);
    let (pairs, crowded) = coincident(positions, on_boundary);
    let mut twin = Vec::new();
    for [a, b] in pairs {
        if (flags[a as usize] | flags[b as usize]) & LOCKED != 0 {
            flags[a as usize] |= LOCKED;
            flags[b as usize] |= LOCKED;
            continue;
        }
        if twin.is_empty() {
            twin = vec![NONE; flags.len()];
        }
        twin[a as usize] = b;
        twin[b as usize] = a;
        flags[a as usize] |= SEAM;
        flags[b as usize] |= SEAM;
    }
    for v in crowded {
        flags[v as usize] |= LOCKED;
    }
    twin
}

/// Of `vertices`, those at the same position (bit for bit) as exactly one other, in
/// pairs, and those at a position shared by more.
pub(crate) fn coincident(
    positions: &[[f32; 3]],
    vertices: impl Iterator<Item = u32>,
) -> (Vec<[u32; 2]>, Vec<u32>) {
    let mut at: Vec<([u32; 3], u32)> = vertices
        .map(|v| (positions[v as usize].map(f32::to_bits), v))
        .collect();
    at.sort_unstable();
    let (mut pairs, mut crowded) = (Vec::new(), Vec::new());
    for group in at.chunk_by(|x, y| x.0 == y.0) {
        match group {
            [_] => {}
            &[(_, a), (_, b)] => pairs.push([a, b]),
            _ => crowded.extend(group.iter().map(|&(_, v)| v)),
        }
    }
    (pairs, crowded)
}

impl<'a> Collapser<'a> {
    /// `topology`: the triangle adjacency and vertex-to-triangle lists of `mesh` when
    /// the caller has them (a mesh decimated on itself), else they are built here.
    pub(super) fn new(
        mesh: &'a SurfaceMesh,
        home: &[u32],
        reference: &'a Reference<'a>,
        locked: &[bool],
        options: &'a Options,
        topology: Option<(&[[u32; 3]], VertexTriangles)>,
    ) -> Result<Self> {
        options.check()?;
        check_input(mesh, home, reference, locked)?;
        let n = mesh.vertex_count();
        let owned;
        let (adjacency, vt) = match topology {
            Some(t) => t,
            None => {
                let vt = VertexTriangles::new(n, &mesh.triangles);
                owned = crate::reference::triangle_adjacency(&mesh.triangles, &vt);
                (owned.as_slice(), vt)
            }
        };
        let frame = Frame::new(mesh, options);
        let cover = if options.cover {
            Some(CellCover::of(mesh)?)
        } else {
            None
        };

        let x: Vec<Point> = (0..n).map(|v| Frame::of_mesh(mesh, v, &frame)).collect();
        let mut flags = vertex_flags(mesh, locked, adjacency, &vt);
        let twin = seam_twins(&mesh.positions, &mut flags);

        let (q, uv_sign) = quadrics(mesh, &x, adjacency, options);
        let mean_edge2 = mean_edge2(mesh, &x, &frame);

        let live_vertices = flags.iter().filter(|&&f| f & ALIVE != 0).count();
        let outline_vertices = flags
            .iter()
            .filter(|&&f| f & (BOUNDARY | LOCKED) != 0)
            .count();
        Ok(Collapser {
            input: mesh,
            reference,
            options,
            frame,
            has_scalars: !mesh.scalars.is_empty(),
            cover,
            x,
            q,
            position: mesh.positions.clone(),
            texcoord: mesh.texcoords.clone(),
            scalar: if mesh.scalars.is_empty() {
                vec![f32::NAN; n]
            } else {
                mesh.scalars.clone()
            },
            home: home.to_vec(),
            flags,
            twin,
            busy: vec![false; n],
            cheapest: vec![u32::MAX; n],
            original: (0..n as u32).collect(),
            current: (0..n as u32).collect(),
            merged_into: vec![NONE; n],
            compact_below: COMPACT_BELOW,
            rounds: if n > LOCAL_VERTICES { LOCAL_ROUNDS } else { 0 },
            scratch: Scratch::default(),
            tris: mesh.triangles.clone(),
            uv_sign,
            live: mesh.triangle_count(),
            live_vertices,
            outline_vertices,
            start: vt.start,
            refs: vt.triangles,
            candidates: Vec::new(),
            tie: 1e-12 * mean_edge2,
            free_cost: FREE_COST * mean_edge2,
            max_cost: 0.0,
            collapses: 0,
            mark: vec![0; n],
            stamp: 0,
            timings: Timings::default(),
        })
    }
}

/// Fails where `home` or `locked` do not fit `mesh` or `home` leaves `reference`.
fn check_input(
    mesh: &SurfaceMesh,
    home: &[u32],
    reference: &Reference,
    locked: &[bool],
) -> Result<()> {
    mesh.validate().map_err(Error::Mesh)?;
    let n = mesh.vertex_count();
    if home.len() != n {
        return Err(Error::Mesh(format!(
            "{} home triangles for {n} vertices",
            home.len()
        )));
    }
    if !locked.is_empty() && locked.len() != n {
        return Err(Error::Mesh(format!(
            "{} locks for {n} vertices",
            locked.len()
        )));
    }
    let ref_triangles = reference.mesh().triangle_count() as u32;
    if let Some(h) = home.iter().find(|&&h| h >= ref_triangles && h != NONE) {
        return Err(Error::Mesh(format!(
            "home triangle {h} is not in the reference surface ({ref_triangles} triangles)"
        )));
    }
    Ok(())
}

/// Per vertex of `mesh`, [`ALIVE`] where a triangle uses it, [`LOCKED`] where `locked`
/// says so, and [`BOUNDARY`] on boundary edges (no neighbour in `adjacency`); vertices
/// on a non-manifold edge or where more than one boundary passes (a pinch point) are
/// locked, as no local rule could simplify them soundly.
fn vertex_flags(
    mesh: &SurfaceMesh,
    locked: &[bool],
    adjacency: &[[u32; 3]],
    vt: &VertexTriangles,
) -> Vec<u8> {
    let n = mesh.vertex_count();
    let mut flags = vec![0u8; n];
    for t in &mesh.triangles {
        for &v in t {
            flags[v as usize] = ALIVE;
        }
    }
    for (f, &l) in flags.iter_mut().zip(locked) {
        if l {
            *f |= LOCKED;
        }
    }
    let mut boundary_edges = vec![0u8; n];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            if adjacency[t][k] != NONE {
                continue;
            }
            let (p, q) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
            let others = vt
                .of(p)
                .iter()
                .filter(|&&s| s as usize != t && mesh.triangles[s as usize].contains(&q))
                .count();
            for v in [p, q] {
                if others > 0 {
                    flags[v as usize] |= LOCKED;
                } else {
                    flags[v as usize] |= BOUNDARY;
                    boundary_edges[v as usize] = boundary_edges[v as usize].saturating_add(1);
                }
            }
        }
    }
    for (f, &e) in flags.iter_mut().zip(&boundary_edges) {
        if e > 2 {
            *f |= LOCKED;
        }
    }
    flags
}

/// Per vertex of `mesh` (joint points `x`), its quadric: each triangle's, weighted by
/// its area, on its corners, and a boundary plane on both ends of each boundary edge;
/// and per triangle, the sign of its texture-space area.
fn quadrics(
    mesh: &SurfaceMesh,
    x: &[Point],
    adjacency: &[[u32; 3]],
    options: &Options,
) -> (Vec<Local>, Vec<i8>) {
    let mut q = vec![Local::default(); mesh.vertex_count()];
    let mut uv_sign = Vec::with_capacity(mesh.triangle_count());
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let [p0, p1, p2] = tri.map(|v| x[v as usize]);
        let normal = cross3(sub3(&p1, &p0), sub3(&p2, &p0));
        let area = 0.5 * dot3(normal, normal).sqrt();
        let quad = Quadric::triangle(&p0, &p1, &p2, area).through();
        for &v in tri {
            q[v as usize].add_through(&quad);
        }
        let uv = tri.map(|v| mesh.texcoords[v as usize].map(f64::from));
        let s = cross2(uv[0], uv[1], uv[2]);
        uv_sign.push(if s > 0.0 {
            1
        } else if s < 0.0 {
            -1
        } else {
            0
        });
        if options.boundary_weight > 0.0 && area > 0.0 {
            for k in 0..3 {
                if adjacency[t][k] != NONE {
                    continue;
                }
                let (i, j) = (tri[(k + 1) % 3] as usize, tri[(k + 2) % 3] as usize);
                let e = sub3(&x[j], &x[i]);
                let m = cross3(e, normal);
                let len = dot3(m, m).sqrt();
                if len > 0.0 {
                    let m = m.map(|c| c / len);
                    let d = dot3(m, [x[i][0], x[i][1], x[i][2]]);
                    let weight = f64::from(options.boundary_weight) * dot3(e, e);
                    let quad = Quadric::plane(m, d, weight).through();
                    q[i].add_through(&quad);
                    q[j].add_through(&quad);
                }
            }
        }
    }
    (q, uv_sign)
}

/// Mean squared length of a sample of `mesh`'s edges (joint points `x`) that reach no
/// stray corner: the scale of ties and of free collapses.
fn mean_edge2(mesh: &SurfaceMesh, x: &[Point], frame: &Frame) -> f64 {
    let (mut sum, mut k) = (0.0, 0usize);
    for tri in mesh.triangles.iter().step_by(7) {
        if frame.reaches_stray(mesh, tri[0] as usize, tri[1] as usize) {
            continue;
        }
        let e = sub3(&x[tri[1] as usize], &x[tri[0] as usize]);
        sum += dot3(e, e);
        k += 1;
    }
    if k > 0 { sum / k as f64 } else { 1.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boundary_vertices_at_one_place_pair_as_twins_or_are_locked() {
        let b = ALIVE | BOUNDARY;
        // Two at x = 0 (a seam); three at x = 1 (locked); one alone at x = 2, beside
        // an interior vertex at its place (not a boundary: no seam); a pair at x = 3
        // of which one is locked (both locked).
        let at = |x: f32| [x, 0.0, 0.0];
        let positions = [
            at(0.0),
            at(0.0),
            at(1.0),
            at(1.0),
            at(1.0),
            at(2.0),
            at(2.0),
            at(3.0),
            at(3.0),
        ];
        let mut flags = [b, b, b, b, b, b, ALIVE, b, b | LOCKED];
        let twin = seam_twins(&positions, &mut flags);
        assert_eq!(twin[..2], [1, 0]);
        assert!(flags[..2].iter().all(|f| f & SEAM != 0 && f & LOCKED == 0));
        assert!(twin[2..].iter().all(|&t| t == NONE));
        assert!(flags[2..5].iter().all(|f| f & LOCKED != 0 && f & SEAM == 0));
        assert_eq!(flags[5..7], [b, ALIVE]);
        assert!(flags[7..].iter().all(|f| f & LOCKED != 0 && f & SEAM == 0));
        // No seam: no twins kept at all.
        let mut apart = [b, b];
        assert!(seam_twins(&[at(0.0), at(1.0)], &mut apart).is_empty());
        assert_eq!(apart, [b, b]);
    }
}
