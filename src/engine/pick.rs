//! Picking: the cell under a pixel of the last frame.
//!
//! # How it works
//! A ray from the eye through the pixel's centre, in the frame the camera sees
//! (vertical exaggeration applied), is tested against every triangle the frame drew,
//! on all cores; the nearest hit names the cell. A full-resolution mesh knows each
//! triangle's cell ([`SurfaceMesh::cell_faces`]); a decimated one does not, but its
//! global texture coordinates survived decimation and name the column (node `(i, j)`
//! has `(2i + 1, 2j + 1)`), and the depth of the hit names the layer.
//!
//! # Why not a GPU pick pass
//! An ID buffer would need a pipeline per wireframe technique and a readback per
//! click; the ray costs a few milliseconds for a million triangles and is the same
//! on every adapter.

use rayon::prelude::*;
use strata_grid::{CornerPointGrid, SurfaceMesh};
use strata_render::View;
use strata_render::glam::Vec3;

/// The cell under a pixel, and where the ray met it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pick {
    /// The cell, 0-based `[i, j, k]`.
    pub cell: [usize; 3],
    /// The point hit, in map coordinates (x, y, depth).
    pub point: [f64; 3],
}

/// A ray in the frame the camera sees: display frame, z exaggerated.
pub(crate) struct Ray {
    origin: Vec3,
    dir: Vec3,
    z_scale: f32,
}

impl Ray {
    /// The ray from `view`'s eye through the centre of pixel `(x, y)` (from the top
    /// left of the frame).
    pub fn through(view: &View, x: f32, y: f32) -> Ray {
        let camera = &view.camera;
        let forward = (camera.target - camera.eye).normalize_or(Vec3::NEG_Z);
        let right = forward.cross(camera.up).normalize_or(Vec3::X);
        let up = right.cross(forward);
        let tan_y = (0.5 * camera.fov_y_deg.to_radians()).tan();
        let aspect = view.width as f32 / view.height.max(1) as f32;
        let ndc_x = 2.0 * (x + 0.5) / view.width.max(1) as f32 - 1.0;
        let ndc_y = 1.0 - 2.0 * (y + 0.5) / view.height.max(1) as f32;
        let dir = forward + right * (ndc_x * tan_y * aspect) + up * (ndc_y * tan_y);
        Ray {
            origin: camera.eye,
            dir: dir.normalize(),
            z_scale: camera.z_scale,
        }
    }

    /// The nearest triangle of `mesh` the ray meets: its index, the distance along
    /// the ray, and the barycentric weights of its second and third vertices.
    pub fn nearest(&self, mesh: &SurfaceMesh) -> Option<Hit> {
        let scale = Vec3::new(1.0, 1.0, self.z_scale);
        let at = |v: u32| Vec3::from(mesh.positions[v as usize]) * scale;
        mesh.triangles
            .par_iter()
            .enumerate()
            .filter_map(|(t, tri)| {
                let (distance, b) = self.meets(at(tri[0]), at(tri[1]), at(tri[2]))?;
                Some(Hit {
                    triangle: t,
                    distance,
                    weights: b,
                })
            })
            .min_by(|a, b| a.distance.total_cmp(&b.distance))
    }

    /// Möller-Trumbore: the distance to the triangle `(a, b, c)` and the weights of
    /// `b` and `c` at the hit, either side facing.
    fn meets(&self, a: Vec3, b: Vec3, c: Vec3) -> Option<(f32, [f32; 2])> {
        let (e1, e2) = (b - a, c - a);
        let p = self.dir.cross(e2);
        let det = e1.dot(p);
        if det.abs() < f32::MIN_POSITIVE {
            return None;
        }
        let inv = 1.0 / det;
        let s = self.origin - a;
        let u = s.dot(p) * inv;
        let q = s.cross(e1);
        let v = self.dir.dot(q) * inv;
        let t = e2.dot(q) * inv;
        let eps = -1e-5;
        (u >= eps && v >= eps && u + v <= 1.0 - eps && t > 0.0).then_some((t, [u, v]))
    }

    /// The point at `distance`, unexaggerated, in map coordinates (x, y, depth) for
    /// positions relative to display origin `origin`.
    pub fn map_point(&self, distance: f32, origin: [f64; 3]) -> [f64; 3] {
        let p = self.origin + self.dir * distance;
        [
            f64::from(p.x) + origin[0],
            f64::from(p.y) + origin[1],
            -(f64::from(p.z / self.z_scale) + origin[2]),
        ]
    }
}

/// Where the map point `point` (x, y, depth) falls in `view`'s frame, whose positions
/// are relative to `origin`: in pixels from the frame's top left corner, continuous
/// (pixel `(x, y)` spans `x..x + 1`); `None` behind the eye.
pub(crate) fn pixel_of(view: &View, origin: [f64; 3], point: [f64; 3]) -> Option<[f32; 2]> {
    let display = Vec3::new(
        (point[0] - origin[0]) as f32,
        (point[1] - origin[1]) as f32,
        (-point[2] - origin[2]) as f32,
    );
    let projection = view.projection();
    let clip = projection.clip(display.to_array());
    (clip.w > f32::EPSILON).then(|| projection.window(clip).to_array())
}

/// Where a ray met a mesh.
pub(crate) struct Hit {
    /// The triangle met.
    pub triangle: usize,
    /// How far along the ray.
    pub distance: f32,
    /// The barycentric weights of the triangle's second and third vertices.
    pub weights: [f32; 2],
}

/// The column `[i, j]` (0-based) a hit on a layer surface landed in, by the global
/// coordinates interpolated at the hit (cell `i` spans `2i + 1 ..= 2i + 3`).
pub(crate) fn global_column(mesh: &SurfaceMesh, hit: &Hit) -> [usize; 2] {
    let tri = mesh.triangles[hit.triangle];
    let [wb, wc] = hit.weights;
    std::array::from_fn(|axis| {
        let c = |v: u32| mesh.texcoords[v as usize][axis];
        let coord = (1.0 - wb - wc) * c(tri[0]) + wb * c(tri[1]) + wc * c(tri[2]);
        ((coord - 1.0) / 2.0).floor().max(0.0) as usize
    })
}

/// The cell of `mesh` that `hit` landed on: by the cell faces where the mesh has
/// them, else by the global coordinates (the column) and `grid` (the layer among
/// `layers`, 0-based inclusive, whose top or bottom is nearest the point's depth).
pub(crate) fn hit_cell(
    mesh: &SurfaceMesh,
    hit: &Hit,
    depth: f64,
    grid: &CornerPointGrid,
    layers: [usize; 2],
) -> Option<[usize; 3]> {
    let t = hit.triangle as u32;
    if let Some(face) = mesh.cell_faces.iter().find(|f| f.triangles.contains(&t)) {
        return Some(face.cell.map(|c| c as usize));
    }
    let dims = grid.dims();
    let [i, j] = global_column(mesh, hit);
    let (i, j) = (
        i.min(dims.nx.saturating_sub(1)),
        j.min(dims.ny.saturating_sub(1)),
    );
    let k = (layers[0]..=layers[1].min(dims.nz - 1)).min_by(|&a, &b| {
        let off = |k: usize| {
            let corners = grid.cell_corners(i, j, k);
            let top = corners[..4].iter().map(|c| c[2]).sum::<f64>() / 4.0;
            let bottom = corners[4..].iter().map(|c| c[2]).sum::<f64>() / 4.0;
            (top - depth).abs().min((bottom - depth).abs())
        };
        off(a).total_cmp(&off(b))
    })?;
    Some([i, j, k])
}

#[cfg(test)]
mod tests {
    use super::*;
    use strata_render::Camera;

    #[test]
    fn the_ray_through_the_middle_pixel_meets_the_point_looked_at() {
        let mesh = SurfaceMesh::structured(4, 4, |i, j| [i as f32, j as f32, 0.0]);
        let camera = Camera::orbit(Vec3::new(1.5, 2.5, 0.0), 0.0, 90.0, 10.0);
        let view = View {
            camera,
            width: 101,
            height: 101,
            bounds: (Vec3::ZERO, Vec3::splat(4.0)),
        };
        let ray = Ray::through(&view, 50.0, 50.0);
        let hit = ray.nearest(&mesh).expect("a hit");
        let point = ray.map_point(hit.distance, [0.0; 3]);
        assert!(
            (point[0] - 1.5).abs() < 1e-3 && (point[1] - 2.5).abs() < 1e-3,
            "{point:?}"
        );
        let face = mesh
            .cell_faces
            .iter()
            .find(|f| f.triangles.contains(&(hit.triangle as u32)));
        assert_eq!(face.map(|f| f.cell), Some([1, 2, 0]));
        // A pixel off the mesh meets nothing.
        assert!(Ray::through(&view, 0.0, 0.0).nearest(&mesh).is_none());
    }

    #[test]
    fn a_point_picked_projects_back_onto_the_centre_of_its_pixel() {
        let mesh = SurfaceMesh::structured(8, 6, |i, j| {
            [10.0 * i as f32, 10.0 * j as f32, -((i + j) as f32)]
        });
        let mut camera = Camera::orbit(Vec3::new(40.0, 30.0, -7.0), 35.0, 40.0, 150.0);
        camera.z_scale = 3.0;
        let view = View {
            camera,
            width: 320,
            height: 200,
            bounds: (Vec3::new(0.0, 0.0, -14.0), Vec3::new(80.0, 60.0, 0.0)),
        };
        let origin = [1000.0, 2000.0, 500.0];
        for (x, y) in [(160.0, 100.0), (120.0, 120.0), (200.0, 120.0)] {
            let ray = Ray::through(&view, x, y);
            let hit = ray
                .nearest(&mesh)
                .unwrap_or_else(|| panic!("pixel ({x}, {y}) shows no mesh"));
            let point = ray.map_point(hit.distance, origin);
            let at = pixel_of(&view, origin, point).expect("in front of the eye");
            assert!(
                (at[0] - x - 0.5).abs() < 1e-2 && (at[1] - y - 0.5).abs() < 1e-2,
                "pixel ({x}, {y}) came back at {at:?}"
            );
        }
        // Behind the eye: nowhere in the frame.
        let behind = ray_behind(&view, origin);
        assert_eq!(pixel_of(&view, origin, behind), None);
    }

    /// A map point behind `view`'s eye.
    fn ray_behind(view: &View, origin: [f64; 3]) -> [f64; 3] {
        let camera = &view.camera;
        let back = camera.eye + (camera.eye - camera.target);
        Ray {
            origin: back,
            dir: Vec3::X,
            z_scale: camera.z_scale,
        }
        .map_point(0.0, origin)
    }
}
