//! The camera: look-at and orbit, fitting to a bounding box, vertical exaggeration,
//! and a depth range fitted to the scene so that far cells keep depth precision.
//!
//! Positions are in the display frame of strata-grid (x east, y north, z up,
//! relative to a mesh origin). Vertical exaggeration scales z before viewing.
//! Projection uses reversed depth (near = 1, far = 0) with a 32-bit float buffer,
//! the arrangement with the most uniform precision.

use glam::{Mat4, Vec3};

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view, degrees.
    pub fov_y_deg: f32,
    /// Vertical exaggeration applied to z before viewing.
    pub z_scale: f32,
}

impl Camera {
    /// A camera at `eye` looking at `target`.
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Self {
        Camera {
            eye,
            target,
            up,
            fov_y_deg: 35.0,
            z_scale: 1.0,
        }
    }

    /// A camera orbiting `target` at `distance`: azimuth in degrees clockwise from
    /// north (0: looking north from the south), elevation in degrees above the horizon
    /// (90: map view, north up).
    pub fn orbit(target: Vec3, azimuth_deg: f32, elevation_deg: f32, distance: f32) -> Self {
        let (az, el) = (
            azimuth_deg.to_radians(),
            elevation_deg.clamp(-89.9, 89.9).to_radians(),
        );
        let dir = Vec3::new(-az.sin() * el.cos(), -az.cos() * el.cos(), el.sin());
        // Near the zenith, "up" on screen is the horizontal viewing direction.
        let up = Vec3::new(az.sin(), az.cos(), 0.0);
        let up = if el.cos() < 1e-3 { up } else { Vec3::Z };
        Camera::look_at(target + dir * distance, target, up)
    }

    /// An orbit camera around the centre of the box `[min, max]` (unscaled display
    /// frame) under vertical exaggeration `z_scale`, at the distance where all eight
    /// corners just fit an image of `aspect` (width / height); `distance_factor`
    /// scales that distance (above 1 leaves a margin, below 1 zooms in).
    pub fn fit(
        min: Vec3,
        max: Vec3,
        z_scale: f32,
        aspect: f32,
        view: (f32, f32),
        distance_factor: f32,
    ) -> Self {
        let corners = (0..8).map(|k| {
            Vec3::new(
                if k & 1 == 0 { min.x } else { max.x },
                if k & 2 == 0 { min.y } else { max.y },
                if k & 4 == 0 { min.z } else { max.z },
            )
        });
        Self::fit_points(corners, z_scale, aspect, view, distance_factor)
    }

    /// Like [`Camera::fit`], but frames the given points (e.g. a mesh's vertices)
    /// rather than their bounding box, which is much tighter for rotated grids.
    pub fn fit_points(
        points: impl IntoIterator<Item = Vec3> + Clone,
        z_scale: f32,
        aspect: f32,
        (azimuth_deg, elevation_deg): (f32, f32),
        distance_factor: f32,
    ) -> Self {
        let scale = Vec3::new(1.0, 1.0, z_scale);
        let (lo, hi) = points
            .clone()
            .into_iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p * scale), hi.max(p * scale))
            });
        let centre = if lo.cmple(hi).all() {
            0.5 * (lo + hi)
        } else {
            Vec3::ZERO
        };
        let mut c = Camera::orbit(centre, azimuth_deg, elevation_deg, 1.0);
        c.z_scale = z_scale;
        let forward = (c.target - c.eye).normalize();
        let right = forward.cross(c.up).normalize();
        let up = right.cross(forward);
        let tan_y = (0.5 * c.fov_y_deg.to_radians()).tan();
        let tan_x = tan_y * aspect.max(1e-3);
        // A corner at offset p from the centre is inside the frustum from distance d
        // along -forward when |p.right| <= tan_x (d + p.forward), likewise for up.
        let distance = points
            .into_iter()
            .map(|p| {
                let p = p * scale - centre;
                let depth = p.dot(forward);
                (p.dot(right).abs() / tan_x - depth).max(p.dot(up).abs() / tan_y - depth)
            })
            .fold(1e-6f32, f32::max);
        c.eye = centre - forward * distance * distance_factor.max(1e-3) * 1.04;
        c
    }

    /// The same view moved sideways so that `point` (unscaled display frame) is at the
    /// picture's centre: direction and distance stay, so `--view`'s distance factor
    /// still zooms, now towards `point` instead of the middle of the model.
    pub fn centred_on(self, point: Vec3) -> Camera {
        let offset = point * Vec3::new(1.0, 1.0, self.z_scale) - self.target;
        Camera {
            eye: self.eye + offset,
            target: self.target + offset,
            ..self
        }
    }

    /// The planes that bound what a picture of `aspect` (width / height) shows, in the
    /// display frame *after* vertical exaggeration, as `(a, b, c, d)` with
    /// `a x + b y + c z + d >= 0` on the inner side: the four sides of the picture and
    /// the plane through the eye across the view. Something wholly outside one of
    /// them is not in the picture.
    pub fn frustum(&self, aspect: f32) -> [[f32; 4]; 5] {
        // Rows of the clip transform (Gribb & Hartmann): a point is inside where
        // -w <= x <= w, -w <= y <= w and w >= 0; near and far do not matter here.
        let clip = self.projection(aspect, 1.0, 2.0) * self.view();
        let row = |r: usize| clip.row(r);
        let w = row(3);
        [w + row(0), w - row(0), w + row(1), w - row(1), w].map(|p| p.to_array())
    }

    /// The world transform applied before viewing: vertical exaggeration.
    pub fn model(&self) -> Mat4 {
        Mat4::from_scale(Vec3::new(1.0, 1.0, self.z_scale))
    }

    pub fn view(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.eye, self.target, self.up)
    }

    /// Reversed-depth perspective projection between `near` and `far` (distances along
    /// the view direction).
    pub fn projection(&self, aspect: f32, near: f32, far: f32) -> Mat4 {
        // Swapping near and far of the WebGPU (0..1 depth) projection reverses depth.
        glam::camera::rh::proj::directx::perspective(self.fov_y_deg.to_radians(), aspect, far, near)
    }

    /// Near and far distances that enclose the box `[min, max]` (unscaled display
    /// frame) with a small margin; the near plane never goes closer than 1/10000 of
    /// the far one, so depth precision stays usable when the eye is inside the box.
    pub fn depth_range(&self, min: Vec3, max: Vec3) -> (f32, f32) {
        let to_view = self.view() * self.model();
        let (mut near, mut far) = (f32::INFINITY, 0f32);
        for c in 0..8 {
            let p = Vec3::new(
                if c & 1 == 0 { min.x } else { max.x },
                if c & 2 == 0 { min.y } else { max.y },
                if c & 4 == 0 { min.z } else { max.z },
            );
            let d = -to_view.transform_point3(p).z;
            near = near.min(d);
            far = far.max(d);
        }
        let far = (far * 1.02).max(1e-3);
        ((near * 0.98).max(far * 1e-4), far)
    }

    /// Clip transform of the scene: projection x view x model.
    pub fn view_proj(&self, aspect: f32, near: f32, far: f32) -> Mat4 {
        self.projection(aspect, near, far) * self.view() * self.model()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_azimuth_and_elevation() {
        let c = Camera::orbit(Vec3::ZERO, 0.0, 0.0, 10.0);
        assert!((c.eye - Vec3::new(0.0, -10.0, 0.0)).length() < 1e-4);
        let c = Camera::orbit(Vec3::ZERO, 90.0, 0.0, 10.0);
        assert!((c.eye - Vec3::new(-10.0, 0.0, 0.0)).length() < 1e-4);
        let top = Camera::orbit(Vec3::ZERO, 0.0, 90.0, 10.0);
        assert!(top.eye.z > 9.99);
        // Map view: north is up on screen.
        let ndc = top
            .view_proj(1.0, 1.0, 20.0)
            .project_point3(Vec3::new(0.0, 1.0, 0.0));
        assert!(ndc.y > 0.0 && ndc.x.abs() < 1e-4);
    }

    #[test]
    fn a_centred_camera_keeps_its_view_and_shows_the_point_in_the_middle() {
        let (lo, hi) = (Vec3::new(0.0, 0.0, -80.0), Vec3::new(2000.0, 1000.0, 0.0));
        let whole = Camera::fit(lo, hi, 5.0, 1.5, (30.0, 35.0), 0.1);
        let point = Vec3::new(1700.0, 150.0, -20.0);
        let c = whole.centred_on(point);
        let ndc = c.view_proj(1.5, 1.0, 1e5).project_point3(point);
        assert!(ndc.x.abs() < 1e-4 && ndc.y.abs() < 1e-4, "{ndc}");
        assert!(((c.eye - c.target) - (whole.eye - whole.target)).length() < 1e-3);
        // The planes hold the point and the centre of the view, not what is behind the
        // eye or off to one side.
        let inside = |p: Vec3| {
            let p = p * Vec3::new(1.0, 1.0, 5.0);
            c.frustum(1.5)
                .iter()
                .all(|[a, b, e, d]| a * p.x + b * p.y + e * p.z + d >= 0.0)
        };
        assert!(inside(point));
        let behind = 2.0 * c.eye - c.target;
        assert!(!inside(Vec3::new(behind.x, behind.y, behind.z / 5.0)));
        assert!(
            !inside(lo) || !inside(hi),
            "a close-up shows the whole model"
        );
        let right = (c.target - c.eye).cross(c.up).normalize();
        let distance = (c.target - c.eye).length();
        let aside = |k: f32| {
            let p = c.target + right * k * distance;
            Vec3::new(p.x, p.y, p.z / 5.0)
        };
        // 35 degrees of height at 1.5 wide: half the width is tan(17.5) * 1.5 = 0.47.
        assert!(inside(aside(0.45)) && !inside(aside(0.5)));
    }

    #[test]
    fn fit_keeps_the_box_in_view_and_depth_range_encloses_it() {
        let (lo, hi) = (
            Vec3::new(-500.0, -300.0, -50.0),
            Vec3::new(500.0, 300.0, 50.0),
        );
        let c = Camera::fit(lo, hi, 5.0, 1.5, (30.0, 35.0), 1.0);
        let (near, far) = c.depth_range(lo, hi);
        assert!(near > 0.0 && far > near);
        let vp = c.view_proj(1.5, near, far);
        let mut tight = 0f32;
        for corner in 0..8 {
            let p = Vec3::new(
                if corner & 1 == 0 { lo.x } else { hi.x },
                if corner & 2 == 0 { lo.y } else { hi.y },
                if corner & 4 == 0 { lo.z } else { hi.z },
            );
            let ndc = vp.project_point3(p);
            assert!(ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0, "{p} -> {ndc}");
            tight = tight.max(ndc.x.abs()).max(ndc.y.abs());
            assert!((0.0..=1.0).contains(&ndc.z), "depth {}", ndc.z);
        }
        // Fitted, not merely inside: some corner reaches near the image border.
        assert!(tight > 0.9, "loosest corner at {tight}");
    }
}
