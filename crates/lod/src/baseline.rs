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
//! on the original surface (see [`crate::decimate()`]).
//!
//! `clusterlod` builds meshoptimizer's other answer to massive meshes, a Nanite-style
//! DAG of clusters whose group borders are locked while each level is simplified;
//! measured here as the cut through that DAG a renderer would draw at the largest
//! error that keeps within the budget, against ours and its plain simplifiers.

use meshopt::{SimplifyOptions, VertexDataAdapter};
use strata_grid::SurfaceMesh;

use crate::decimate::Frame;
use crate::{Decimated, Error, MaybeIndex, Options, Reference, Result, ViewPoint};

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
    /// `clodBuild` (meshoptimizer's cluster LOD, its default configuration for
    /// rasterization, clusters of up to [`CLUSTER_TRIANGLES`] triangles, attributes
    /// weighed as `Attributes` weighs them), cut at the smallest error whose clusters
    /// fit the budget ([`ClusterLod::cut_within`]).
    ClusterLod,
}

/// Triangles of a cluster of [`Simplifier::ClusterLod`]: the size meshoptimizer's
/// examples draw meshlets with.
pub const CLUSTER_TRIANGLES: usize = 128;

impl Simplifier {
    /// Every simplifier, in the order the benchmark reports them.
    pub const ALL: [Simplifier; 5] = [
        Simplifier::Simplify,
        Simplifier::Attributes,
        Simplifier::Update,
        Simplifier::Sloppy,
        Simplifier::ClusterLod,
    ];

    /// The name the benchmark and the CLI report it under.
    pub fn name(self) -> &'static str {
        match self {
            Simplifier::Simplify => "meshopt_simplify",
            Simplifier::Attributes => "meshopt_attributes",
            Simplifier::Update => "meshopt_update",
            Simplifier::Sloppy => "meshopt_sloppy",
            Simplifier::ClusterLod => "meshopt_clusterlod",
        }
    }
}

/// `mesh` as meshoptimizer takes it: positions with `z_scale` applied, flat indices,
/// and per vertex the texture coordinates and scalar, weighed as [`Options`] weighs
/// them in ours, in the units of meshoptimizer's positions (scaled to unit extent).
struct Inputs {
    positions: Vec<[f32; 3]>,
    indices: Vec<u32>,
    attributes: Vec<f32>,
    /// Diagonal of the bounding box of `positions`.
    extent: f64,
    uv_scale: f32,
    s_scale: f32,
    s_mean: f32,
}

/// Weights of the three attributes: the scaling of [`Inputs`] already weighs them.
const WEIGHTS: [f32; 3] = [1.0; 3];

/// Bytes of a vertex's attributes in [`Inputs::attributes`].
const ATTRIBUTE_STRIDE: usize = 12;

impl Inputs {
    fn of(mesh: &SurfaceMesh, z_scale: f32) -> Result<Inputs> {
        mesh.validate().map_err(Error::Mesh)?;
        let options = Options {
            z_scale,
            ..Options::default()
        };
        let frame = Frame::new(mesh, &options);
        let positions: Vec<[f32; 3]> = mesh
            .positions
            .iter()
            .map(|p| [p[0], p[1], p[2] * z_scale])
            .collect();
        let extent = extent(&positions);
        let (uv_scale, s_scale, s_mean) = (
            (frame.uv_scale / extent) as f32,
            (frame.s_scale / extent) as f32,
            frame.s_mean as f32,
        );
        let attributes: Vec<f32> = (0..mesh.vertex_count())
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
        Ok(Inputs {
            positions,
            indices: mesh.triangles.iter().flatten().copied().collect(),
            attributes,
            extent,
            uv_scale,
            s_scale,
            s_mean,
        })
    }
}

/// `positions` as meshoptimizer reads them.
fn adapter_of(positions: &[[f32; 3]]) -> Result<VertexDataAdapter<'_>> {
    VertexDataAdapter::new(bytemuck::cast_slice(positions), 12, 0)
        .map_err(|e| Error::Mesh(e.to_string()))
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
    let Inputs {
        mut positions,
        indices,
        mut attributes,
        extent,
        uv_scale,
        s_scale,
        s_mean,
    } = Inputs::of(mesh, z_scale)?;
    let target = 3 * target_triangles;
    let mut error = 0f32;
    let adapter = adapter_of(&positions)?;
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
            &WEIGHTS,
            ATTRIBUTE_STRIDE,
            &none,
            target,
            f32::MAX,
            SimplifyOptions::None,
            Some(&mut error),
        ),
        Simplifier::Sloppy => {
            meshopt::simplify_sloppy(&indices, &adapter, target, f32::MAX, Some(&mut error))
        }
        Simplifier::ClusterLod => {
            let dag = ClusterLod::of(&indices, &adapter, &attributes);
            let (cut, at) = dag.cut_within(target_triangles);
            // clusterlod's errors are in the units of the positions, not relative
            // to the extent as the simplifiers' are.
            error = at / extent as f32;
            cut
        }
        Simplifier::Update => {
            let mut updated = indices.clone();
            let n = meshopt::simplify_with_update(
                &mut updated,
                &mut positions,
                &mut attributes,
                &WEIGHTS,
                ATTRIBUTE_STRIDE,
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
    let mut remap = vec![MaybeIndex::NONE; mesh.vertex_count()];
    let (mut source, mut home) = (Vec::new(), Vec::new());
    for &v in &result {
        let v = v as usize;
        if remap[v].is_some() {
            continue;
        }
        remap[v] = MaybeIndex::some(out.positions.len() as u32);
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
            source.push(if moved {
                MaybeIndex::NONE
            } else {
                MaybeIndex::some(v as u32)
            });
        } else {
            push_vertex(&mut out, mesh, v);
            source.push(MaybeIndex::some(v as u32));
        }
        // meshoptimizer's indices are the input's, each used by an input triangle.
        home.push(reference_triangle[v].get().expect("a vertex of a triangle"));
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

/// Appends vertex `v` of `mesh` to `out`, attributes and all.
fn push_vertex(out: &mut SurfaceMesh, mesh: &SurfaceMesh, v: usize) {
    out.positions.push(mesh.positions[v]);
    out.texcoords.push(mesh.texcoords[v]);
    if !mesh.scalars.is_empty() {
        out.scalars.push(mesh.scalars[v]);
    }
}

/// The triangles `indices` (flat, into `mesh`'s vertices) as a mesh of their own,
/// holding the vertices they use with their attributes.
pub fn submesh(mesh: &SurfaceMesh, indices: &[u32]) -> SurfaceMesh {
    let mut out = SurfaceMesh::with_origin(mesh.origin);
    let mut remap = vec![MaybeIndex::NONE; mesh.vertex_count()];
    for &v in indices {
        if remap[v as usize].is_none() {
            remap[v as usize] = MaybeIndex::some(out.positions.len() as u32);
            push_vertex(&mut out, mesh, v as usize);
        }
    }
    out.triangles = remap_triangles(indices, &remap);
    out
}

/// A sphere that holds some geometry, and the error of that geometry; in the frame of
/// the positions meshoptimizer was given (vertical exaggeration applied).
#[derive(Clone, Copy, Debug)]
struct Bounds {
    centre: [f32; 3],
    radius: f32,
    error: f32,
}

impl From<meshopt::ClodBounds> for Bounds {
    fn from(b: meshopt::ClodBounds) -> Bounds {
        Bounds {
            centre: b.center,
            radius: b.radius,
            error: b.error,
        }
    }
}

/// meshoptimizer's cluster LOD DAG of one mesh ([`Simplifier::ClusterLod`]): every
/// group's simplified bounds and error, and every cluster's group, the group it was
/// simplified from and its indices (into the mesh's vertices).
pub struct ClusterLod {
    /// Bounds and error of each group's simplified clusters (error `f32::MAX` where
    /// the group is not simplified further).
    groups: Vec<Bounds>,
    clusters: Vec<Cluster>,
}

struct Cluster {
    group: usize,
    /// The group whose simplification made this cluster; `None` for original ones.
    refined: Option<usize>,
    /// A sphere around the cluster, for culling.
    bounds: Bounds,
    indices: Vec<u32>,
}

impl ClusterLod {
    /// The DAG of `mesh` with `z_scale` applied to its heights, attributes weighed as
    /// [`Simplifier::Attributes`] weighs them.
    pub fn build(mesh: &SurfaceMesh, z_scale: f32) -> Result<ClusterLod> {
        let inputs = Inputs::of(mesh, z_scale)?;
        let adapter = adapter_of(&inputs.positions)?;
        Ok(ClusterLod::of(
            &inputs.indices,
            &adapter,
            &inputs.attributes,
        ))
    }

    fn of(indices: &[u32], positions: &VertexDataAdapter<'_>, attributes: &[f32]) -> ClusterLod {
        let mesh = meshopt::ClodMesh {
            vertex_attributes: attributes,
            vertex_attributes_stride: ATTRIBUTE_STRIDE,
            attribute_weights: &WEIGHTS,
            ..meshopt::ClodMesh::new(indices, positions)
        };
        let mut dag = ClusterLod {
            groups: Vec::new(),
            clusters: Vec::new(),
        };
        let config = meshopt::clod_default_config(CLUSTER_TRIANGLES);
        meshopt::clod_build(config, &mesh, |group, clusters| {
            let id = dag.groups.len();
            dag.groups.push(group.simplified.into());
            dag.clusters.extend(clusters.iter().map(|c| Cluster {
                group: id,
                refined: usize::try_from(c.refined).ok(),
                bounds: c.bounds.into(),
                indices: c.indices.to_vec(),
            }));
            id as i32
        });
        dag
    }

    /// Triangles over every cluster of every level.
    pub fn stored_triangles(&self) -> usize {
        self.clusters.iter().map(|c| c.indices.len() / 3).sum()
    }

    /// The indices of the clusters a renderer draws when `too_coarse` says which
    /// groups' simplified clusters it cannot use: those whose group is too coarse and
    /// whose maker (if any) is not, and for which `shown` holds.
    fn cut(
        &self,
        too_coarse: impl Fn(&Bounds) -> bool,
        shown: impl Fn(&Bounds) -> bool,
    ) -> Vec<u32> {
        let coarse: Vec<bool> = self.groups.iter().map(&too_coarse).collect();
        self.clusters
            .iter()
            .filter(|c| coarse[c.group] && c.refined.is_none_or(|g| !coarse[g]) && shown(&c.bounds))
            .flat_map(|c| c.indices.iter().copied())
            .collect()
    }

    /// The indices of the finest cut at one error threshold with at most `target`
    /// triangles (the coarsest cut when none has so few), and that threshold.
    pub fn cut_within(&self, target: usize) -> (Vec<u32>, f32) {
        let mut errors: Vec<f32> = std::iter::once(0.0)
            .chain(
                self.groups
                    .iter()
                    .map(|g| g.error)
                    .filter(|e| *e < f32::MAX),
            )
            .collect();
        errors.sort_by(f32::total_cmp);
        errors.dedup();
        let at = |t: f32| self.cut(|g| g.error > t, |_| true);
        // Triangles drawn only fall as the threshold rises.
        let first_within = errors.partition_point(|&t| at(t).len() / 3 > target);
        let t = errors[first_within.min(errors.len() - 1)];
        (at(t), t)
    }

    /// The indices of the clusters drawn from `view`, with no group's projected error
    /// above `max_pixels`; clusters wholly outside one of the planes of its frustum
    /// are left out. The view's frame is the DAG's: vertical exaggeration applied, by
    /// the `z_scale` it was built with.
    pub fn cut_in_view(&self, view: &ViewPoint, max_pixels: f64) -> Vec<u32> {
        let eye = view.eye;
        let distance = |b: &Bounds| {
            let d2: f32 = (0..3).map(|a| (b.centre[a] - eye[a]).powi(2)).sum();
            f64::from(d2.sqrt() - b.radius)
        };
        let too_coarse = |b: &Bounds| {
            b.error == f32::MAX || {
                let d = distance(b);
                d <= 0.0 || view.pixels(f64::from(b.error), d) > max_pixels
            }
        };
        let shown = |b: &Bounds| {
            view.frustum.is_none_or(|planes| {
                planes.iter().all(|p| {
                    let along: f32 = (0..3).map(|a| p[a] * b.centre[a]).sum::<f32>() + p[3];
                    let norm = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                    along >= -b.radius * norm
                })
            })
        };
        self.cut(too_coarse, shown)
    }
}

/// Triangles of the flat index list `indices`, each index through `remap`, which
/// gives each of them a new index.
fn remap_triangles(indices: &[u32], remap: &[MaybeIndex]) -> Vec<[u32; 3]> {
    let new = |v: u32| {
        remap[v as usize]
            .get()
            .expect("the remap gives every vertex of a triangle an index")
    };
    indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]].map(new))
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
/// (none for a vertex no triangle uses, which is dropped); apply it to any
/// per-vertex data kept beside the mesh. Cell faces are dropped (the triangles they
/// name move).
pub fn optimize_order(mesh: &mut SurfaceMesh) -> Vec<MaybeIndex> {
    let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    let indices = meshopt::optimize_vertex_cache(&indices, mesh.vertex_count());
    let mut remap = vec![MaybeIndex::NONE; mesh.vertex_count()];
    let mut next = 0u32;
    for &v in &indices {
        if remap[v as usize].is_none() {
            remap[v as usize] = MaybeIndex::some(next);
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

/// Moves `data[old]` to `data[remap[old]]`, dropping entries mapped to none.
pub fn permute_by<T: Copy + Default>(data: &mut Vec<T>, remap: &[MaybeIndex], len: usize) {
    let mut out = vec![T::default(); len];
    for (old, new) in remap.iter().enumerate() {
        if let Some(new) = new.get() {
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
                for (v, src) in out.source.iter().enumerate() {
                    let src = src.get().expect("an input vertex");
                    assert_eq!(out.mesh.texcoords[v], mesh.texcoords[src as usize]);
                }
            }
        }
    }

    /// Area of `mesh` seen from above: a crack or an overlap between clusters of a
    /// cut changes it.
    fn plan_area(mesh: &SurfaceMesh) -> f64 {
        mesh.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
                let (u, w) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
                f64::from(u[0] * w[1] - u[1] * w[0]) / 2.0
            })
            .sum()
    }

    /// 120 x 80 cells of 10 m over gentle hills: 19 200 triangles.
    fn rolling() -> SurfaceMesh {
        SurfaceMesh::structured(120, 80, |i, j| {
            [
                i as f32 * 10.0,
                j as f32 * 10.0,
                ((i as f32) * 0.1).sin() * 20.0 + ((j as f32) * 0.15).cos() * 10.0,
            ]
        })
    }

    #[test]
    fn a_cluster_lod_cut_covers_the_surface_within_its_budget() {
        let mesh = rolling();
        let whole = plan_area(&mesh);
        let mut last = usize::MAX;
        for target in [19_000, 5_000, 2_000, 800] {
            let cut = simplify(&mesh, Simplifier::ClusterLod, target, 1.0).unwrap();
            cut.mesh.validate().unwrap();
            let n = cut.mesh.triangle_count();
            assert!(n <= target && n <= last, "{n} triangles for {target}");
            assert!(
                n > target / 4,
                "{n} triangles for {target}: not the finest cut"
            );
            let area = plan_area(&cut.mesh);
            assert!(
                (area - whole).abs() < 1e-3 * whole,
                "{target}: the cut covers {area} of {whole}"
            );
            for (v, src) in cut.source.iter().enumerate() {
                let src = src.get().expect("an input vertex");
                assert_eq!(cut.mesh.texcoords[v], mesh.texcoords[src as usize]);
            }
            last = n;
        }
        // A budget of every triangle draws the original clusters.
        let all = simplify(&mesh, Simplifier::ClusterLod, mesh.triangle_count(), 1.0).unwrap();
        assert_eq!(all.mesh.triangle_count(), mesh.triangle_count());
        assert_eq!(all.error, 0.0);
    }

    #[test]
    fn a_cluster_lod_view_cut_is_finer_near_the_eye_and_covers_the_surface() {
        let mesh = rolling();
        let dag = ClusterLod::build(&mesh, 1.0).unwrap();
        let whole = plan_area(&mesh);
        // Heights unexaggerated; a picture 1000 px high whose focal length is 1000 px.
        let from = |eye: [f32; 3], frustum: Option<[[f32; 4]; 5]>| ViewPoint {
            eye,
            z_scale: 1.0,
            fov_y_deg: 2.0 * 0.5f32.atan().to_degrees(),
            height_px: 1000,
            frustum,
        };
        let triangles_near = |cut: &SurfaceMesh, near: bool| {
            cut.triangles
                .iter()
                .filter(|t| {
                    let x = t.iter().map(|&v| cut.positions[v as usize][0]).sum::<f32>() / 3.0;
                    (x < 300.0) == near
                })
                .count()
        };
        let close = submesh(
            &mesh,
            &dag.cut_in_view(&from([0.0, 400.0, 60.0], None), 1.0),
        );
        let far = submesh(
            &mesh,
            &dag.cut_in_view(&from([600.0, 400.0, 1e7], None), 1.0),
        );
        for cut in [&close, &far] {
            cut.validate().unwrap();
            assert!((plan_area(cut) - whole).abs() < 1e-3 * whole);
        }
        // From far above the coarsest cut is enough; from the side at x = 0 the cells
        // near the eye are kept finer than those beyond.
        assert_eq!(far.triangle_count(), dag.cut_within(0).0.len() / 3);
        assert!(close.triangle_count() > 4 * far.triangle_count());
        // Density per unit of plan area: the near part is a quarter of the surface.
        let (near, beyond) = (triangles_near(&close, true), triangles_near(&close, false));
        assert!(
            near > beyond / 3 * 2,
            "{near} triangles near the eye, {beyond} beyond"
        );
        // A frustum that looks away from half the surface leaves its clusters out.
        let left_half = [[-1.0, 0.0, 0.0, 600.0]; 5];
        let culled = dag.cut_in_view(&from([0.0, 400.0, 60.0], Some(left_half)), 1.0);
        let all = dag.cut_in_view(&from([0.0, 400.0, 60.0], None), 1.0);
        assert!(culled.len() < all.len());
        // ... and keeps every triangle that reaches into the half it looks at.
        let inside = |indices: &[u32]| -> Vec<[u32; 3]> {
            let mut t: Vec<[u32; 3]> = indices
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .filter(|t| t.iter().any(|&v| mesh.positions[v as usize][0] <= 600.0))
                .collect();
            t.sort_unstable();
            t
        };
        assert_eq!(inside(&culled), inside(&all));
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
        assert!(remap.iter().all(|r| r.is_some()));
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
