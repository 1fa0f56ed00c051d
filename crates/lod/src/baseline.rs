//! meshoptimizer (the `meshopt` crate, meshoptimizer 1.x): its simplifiers as the
//! baseline ours is measured against on the same meshes and budgets, and its
//! vertex-cache ordering for GPU buffers.
//!
//! meshoptimizer simplifies by half-edge collapse: a vertex moves onto a neighbour,
//! so every kept vertex is an input vertex, exactly on the surface with its exact
//! texture coordinates; what it cannot do is put a vertex where no input vertex is.
//! `simplify_with_update` does (it moves kept vertices to its quadric optimum and
//! updates their attributes), but then nothing ties the new texture coordinates to
//! the original surface at the new position. Ours places new vertices and keeps them
//! on the original surface (see [`crate::decimate`]).

use meshopt::{SimplifyOptions, VertexDataAdapter};
use strata_grid::SurfaceMesh;

use crate::decimate::Frame;
use crate::reference::NONE;
use crate::{Decimated, Error, NEW, Options, Reference, Result};

/// The meshoptimizer simplifiers compared with ours.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Simplifier {
    /// `meshopt_simplify`: position error only.
    Simplify,
    /// `meshopt_simplifyWithAttributes`: position, texture coordinates and scalar,
    /// weighted as ours weighs them.
    Attributes,
    /// `meshopt_simplifyWithUpdate`: as `Attributes`, and kept vertices move to the
    /// quadric's optimum with updated attributes.
    Update,
    /// `meshopt_simplifySloppy`: vertex clustering, ignores topology.
    Sloppy,
}

impl Simplifier {
    pub const ALL: [Simplifier; 4] = [
        Simplifier::Simplify,
        Simplifier::Attributes,
        Simplifier::Update,
        Simplifier::Sloppy,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Simplifier::Simplify => "meshopt_simplify",
            Simplifier::Attributes => "meshopt_attributes",
            Simplifier::Update => "meshopt_update",
            Simplifier::Sloppy => "meshopt_sloppy",
        }
    }
}

/// Simplifies `mesh` to about `target_triangles` with `simplifier`; positions, texture
/// coordinates and scalar are weighed as [`Options`] with `z_scale` weighs them in
/// ours. `home` of each result vertex is a triangle of `mesh` around the input vertex
/// it comes from; `error` is meshoptimizer's result error in display length units.
pub fn simplify(
    mesh: &SurfaceMesh,
    simplifier: Simplifier,
    target_triangles: usize,
    z_scale: f32,
) -> Result<Decimated> {
    mesh.validate().map_err(Error::Mesh)?;
    let options = Options {
        z_scale,
        ..Options::default()
    };
    let frame = Frame::new(mesh, &options);
    let mut positions: Vec<[f32; 3]> = mesh
        .positions
        .iter()
        .map(|p| [p[0], p[1], p[2] * z_scale])
        .collect();
    let extent = extent(&positions);
    let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    let target = 3 * target_triangles;
    // Attributes in the units of meshoptimizer's positions (scaled to unit extent).
    let (uv_scale, s_scale, s_mean) = (
        (frame.uv_scale / extent) as f32,
        (frame.s_scale / extent) as f32,
        frame.s_mean as f32,
    );
    let mut attributes: Vec<f32> = (0..mesh.vertex_count())
        .flat_map(|v| {
            let [u, w] = mesh.texcoords[v];
            let s = mesh.scalars.get(v).copied().unwrap_or(f32::NAN);
            let s = if s.is_nan() {
                0.0
            } else {
                (s - s_mean) * s_scale
            };
            [u * uv_scale, w * uv_scale, s]
        })
        .collect();
    let weights = [1.0f32; 3];
    let mut error = 0f32;
    let bytes: &[u8] = bytemuck::cast_slice(&positions);
    let adapter = VertexDataAdapter::new(bytes, 12, 0).map_err(|e| Error::Mesh(e.to_string()))?;
    let none = vec![false; mesh.vertex_count()];
    let result = match simplifier {
        Simplifier::Simplify => meshopt::simplify(
            &indices,
            &adapter,
            target,
            f32::MAX,
            SimplifyOptions::None,
            Some(&mut error),
        ),
        Simplifier::Attributes => meshopt::simplify_with_attributes_and_locks(
            &indices,
            &adapter,
            &attributes,
            &weights,
            12,
            &none,
            target,
            f32::MAX,
            SimplifyOptions::None,
            Some(&mut error),
        ),
        Simplifier::Sloppy => {
            meshopt::simplify_sloppy(&indices, &adapter, target, f32::MAX, Some(&mut error))
        }
        Simplifier::Update => {
            let mut updated = indices.clone();
            let n = meshopt::simplify_with_update(
                &mut updated,
                &mut positions,
                &mut attributes,
                &weights,
                12,
                None,
                target,
                f32::MAX,
                SimplifyOptions::None,
                Some(&mut error),
            );
            updated.truncate(n);
            updated
        }
    };
    let reference_triangle = Reference::vertex_triangles(mesh);
    let mut out = SurfaceMesh::with_origin(mesh.origin);
    let mut remap = vec![NONE; mesh.vertex_count()];
    let (mut source, mut home) = (Vec::new(), Vec::new());
    for &v in &result {
        let v = v as usize;
        if remap[v] != NONE {
            continue;
        }
        remap[v] = out.positions.len() as u32;
        if simplifier == Simplifier::Update {
            let p = positions[v];
            let a = &attributes[3 * v..3 * v + 3];
            out.positions.push([p[0], p[1], p[2] / z_scale]);
            let unscale = |x: f32| if uv_scale > 0.0 { x / uv_scale } else { x };
            out.texcoords.push([unscale(a[0]), unscale(a[1])]);
            if !mesh.scalars.is_empty() {
                out.scalars.push(if s_scale > 0.0 {
                    a[2] / s_scale + s_mean
                } else {
                    mesh.scalars[v]
                });
            }
            let moved = out.positions.last() != Some(&mesh.positions[v]);
            source.push(if moved { NEW } else { v as u32 });
        } else {
            out.positions.push(mesh.positions[v]);
            out.texcoords.push(mesh.texcoords[v]);
            if !mesh.scalars.is_empty() {
                out.scalars.push(mesh.scalars[v]);
            }
            source.push(v as u32);
        }
        home.push(reference_triangle[v]);
    }
    out.triangles = remap_triangles(&result, &remap);
    Ok(Decimated {
        mesh: out,
        source,
        home,
        error: error * extent as f32,
        collapses: 0,
        outline_vertices: 0,
        cover: None,
        timings: Default::default(),
    })
}

/// Triangles of the flat index list `indices`, each index through `remap`.
fn remap_triangles(indices: &[u32], remap: &[u32]) -> Vec<[u32; 3]> {
    indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]].map(|v| remap[v as usize]))
        .collect()
}

/// Length of the diagonal of the bounding box of `positions`.
fn extent(positions: &[[f32; 3]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in positions {
        for a in 0..3 {
            lo[a] = lo[a].min(f64::from(p[a]));
            hi[a] = hi[a].max(f64::from(p[a]));
        }
    }
    let d: f64 = (0..3).map(|a| (hi[a] - lo[a]).max(0.0).powi(2)).sum();
    d.sqrt().max(f64::MIN_POSITIVE)
}

/// Reorders `mesh` for the GPU: triangles for the post-transform vertex cache
/// (meshoptimizer's `optimizeVertexCache`), then vertices in order of first use so
/// that fetches run forward through memory. Returns the new index of each old vertex
/// ([`NONE`] for a vertex no triangle uses, which is dropped); apply it to any
/// per-vertex data kept beside the mesh. Cell faces are dropped (the triangles they
/// name move).
pub fn optimize_order(mesh: &mut SurfaceMesh) -> Vec<u32> {
    let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    let indices = meshopt::optimize_vertex_cache(&indices, mesh.vertex_count());
    let mut remap = vec![NONE; mesh.vertex_count()];
    let mut next = 0u32;
    for &v in &indices {
        if remap[v as usize] == NONE {
            remap[v as usize] = next;
            next += 1;
        }
    }
    let permute = |data: &mut Vec<_>| permute_by(data, &remap, next as usize);
    permute(&mut mesh.positions);
    permute_by(&mut mesh.texcoords, &remap, next as usize);
    if !mesh.scalars.is_empty() {
        permute_by(&mut mesh.scalars, &remap, next as usize);
    }
    mesh.triangles = remap_triangles(&indices, &remap);
    mesh.cell_faces.clear();
    remap
}

/// Moves `data[old]` to `data[remap[old]]`, dropping entries mapped to [`NONE`].
pub fn permute_by<T: Copy + Default>(data: &mut Vec<T>, remap: &[u32], len: usize) {
    let mut out = vec![T::default(); len];
    for (old, &new) in remap.iter().enumerate() {
        if new != NONE {
            out[new as usize] = data[old];
        }
    }
    *data = out;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bumpy() -> SurfaceMesh {
        SurfaceMesh::structured(30, 20, |i, j| {
            [
                i as f32 * 10.0,
                j as f32 * 10.0,
                ((i as f32) * 0.3).sin() * 4.0 + j as f32 * 0.2,
            ]
        })
    }

    #[test]
    fn every_simplifier_reaches_about_the_target_on_the_surface() {
        let mesh = bumpy();
        for s in Simplifier::ALL {
            let out = simplify(&mesh, s, 200, 5.0).unwrap();
            out.mesh.validate().unwrap();
            let n = out.mesh.triangle_count();
            assert!((100..=260).contains(&n), "{}: {n} triangles", s.name());
            if s != Simplifier::Update {
                // Kept vertices are input vertices, attributes and all.
                for (v, &src) in out.source.iter().enumerate() {
                    assert_eq!(out.mesh.texcoords[v], mesh.texcoords[src as usize]);
                }
            }
        }
    }

    #[test]
    fn gpu_order_keeps_the_triangles() {
        let mut mesh = bumpy();
        let before: Vec<[[f32; 2]; 3]> = mesh
            .triangles
            .iter()
            .map(|t| t.map(|v| mesh.texcoords[v as usize]))
            .collect();
        let remap = optimize_order(&mut mesh);
        assert!(remap.iter().all(|&r| r != NONE));
        mesh.validate().unwrap();
        let mut after: Vec<[[f32; 2]; 3]> = mesh
            .triangles
            .iter()
            .map(|t| t.map(|v| mesh.texcoords[v as usize]))
            .collect();
        // Same triangles (possibly with rotated corners), in another order.
        let canon = |t: &mut [[f32; 2]; 3]| {
            let k = (0..3)
                .min_by(|&a, &b| t[a].partial_cmp(&t[b]).unwrap())
                .unwrap();
            t.rotate_left(k);
        };
        let mut before = before;
        before.iter_mut().for_each(canon);
        after.iter_mut().for_each(canon);
        before.sort_by(|a, b| a.partial_cmp(b).unwrap());
        after.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(before, after);
        // Vertices come in order of first use.
        let first: Vec<u32> =
            mesh.triangles
                .iter()
                .flatten()
                .copied()
                .fold(Vec::new(), |mut seen, v| {
                    if !seen.contains(&v) {
                        seen.push(v);
                    }
                    seen
                });
        assert!(first.windows(2).all(|w| w[0] < w[1]));
    }
}
