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
    /// Where the eye is, in the scaled display frame.
    pub eye: Vec3,
    /// The point looked at, centred in the frame.
    pub target: Vec3,
    /// Which way is up on screen.
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
        points: impl IntoIterator<Item = Vec3>,
        z_scale: f32,
        aspect: f32,
        view: (f32, f32),
        distance_factor: f32,
    ) -> Self {
        let mut framing = Framing::new(z_scale, aspect, view);
        framing.add(points);
        framing.camera(distance_factor)
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

    /// World to eye space, for the frame uniforms.
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

/// Whether `p` is in the box `[min, max]` (every point is when there is none): the
/// corners a view frames ([`Framing::within`]) and measures
/// ([`crate::Renderer::visible_fractions`]), leaving a model's stray ones out.
pub(crate) fn in_box(framed: Option<(Vec3, Vec3)>, p: Vec3) -> bool {
    framed.is_none_or(|(lo, hi)| p.cmpge(lo).all() && p.cmple(hi).all())
}

/// What [`Camera::fit_points`] needs to know of a set of points, gathered a part at a
/// time: a scene drawn in parts, too large to hold at once, is framed exactly as the
/// same points in one mesh.
///
/// The viewing directions depend on the view's angles alone, so each side of the
/// picture is a linear function of a point, shifted by the centre found at the end:
/// the largest value over the points of each of the four, and the box for the centre,
/// are all that is kept.
#[derive(Clone, Debug)]
pub struct Framing {
    z_scale: f32,
    view: (f32, f32),
    forward: Vec3,
    /// Per side of the picture (right, left, up, down): the direction across the
    /// view over the tangent of the half angle, less the forward direction. A point
    /// fits from distance d where its value of each is at most d.
    sides: [Vec3; 4],
    /// The largest value of each side over the scaled points.
    reach: [f32; 4],
    /// Box of the points as given, and of them scaled.
    bounds: (Vec3, Vec3),
    scaled: (Vec3, Vec3),
    /// Only points in this box (unscaled) are framed ([`Framing::within`]).
    within: Option<(Vec3, Vec3)>,
}

impl Framing {
    /// Nothing framed yet, for a picture of `aspect` (width / height) seen from
    /// `(azimuth, elevation)` in degrees, under vertical exaggeration `z_scale`.
    pub fn new(z_scale: f32, aspect: f32, (azimuth_deg, elevation_deg): (f32, f32)) -> Self {
        let c = Camera::orbit(Vec3::ZERO, azimuth_deg, elevation_deg, 1.0);
        let forward = (c.target - c.eye).normalize();
        let right = forward.cross(c.up).normalize();
        let up = right.cross(forward);
        let tan_y = (0.5 * c.fov_y_deg.to_radians()).tan();
        let tan_x = tan_y * aspect.max(1e-3);
        let empty = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        Framing {
            z_scale,
            view: (azimuth_deg, elevation_deg),
            forward,
            sides: [
                right / tan_x - forward,
                -right / tan_x - forward,
                up / tan_y - forward,
                -up / tan_y - forward,
            ],
            reach: [f32::NEG_INFINITY; 4],
            bounds: empty,
            scaled: empty,
            within: None,
        }
    }

    /// Frames only the points in the box `[min, max]` (unscaled display frame), and
    /// leaves the others out of the camera's fit and of [`Framing::bounds`]: a model's
    /// stray corners then run out of the picture (and past the far plane) instead of
    /// shrinking the rest of it to a speck.
    pub fn within(self, min: Vec3, max: Vec3) -> Self {
        Framing {
            within: Some((min, max)),
            ..self
        }
    }

    /// Adds `points` (unscaled display frame).
    pub fn add(&mut self, points: impl IntoIterator<Item = Vec3>) {
        let scale = Vec3::new(1.0, 1.0, self.z_scale);
        for p in points {
            if !in_box(self.within, p) {
                continue;
            }
            let q = p * scale;
            self.bounds = (self.bounds.0.min(p), self.bounds.1.max(p));
            self.scaled = (self.scaled.0.min(q), self.scaled.1.max(q));
            for (reach, side) in self.reach.iter_mut().zip(&self.sides) {
                *reach = reach.max(q.dot(*side));
            }
        }
    }

    /// Adds the points `other` framed for the same view, as if added here: framings
    /// gathered in parallel, one per piece of a scene, merge into the whole's.
    pub fn merge(&mut self, other: &Framing) {
        let (lo, hi) = other.bounds;
        self.bounds = (self.bounds.0.min(lo), self.bounds.1.max(hi));
        let (lo, hi) = other.scaled;
        self.scaled = (self.scaled.0.min(lo), self.scaled.1.max(hi));
        for (reach, theirs) in self.reach.iter_mut().zip(other.reach) {
            *reach = reach.max(theirs);
        }
    }

    /// The box of the points added (unscaled), `None` before any.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.bounds
            .0
            .cmple(self.bounds.1)
            .all()
            .then_some(self.bounds)
    }

    /// The orbit camera around the centre of the points' box at the distance where all
    /// of them just fit, times `distance_factor` (above 1 leaves a margin, below 1
    /// zooms in).
    pub fn camera(&self, distance_factor: f32) -> Camera {
        let (lo, hi) = self.scaled;
        let centre = if lo.cmple(hi).all() {
            0.5 * (lo + hi)
        } else {
            Vec3::ZERO
        };
        let distance = self
            .reach
            .iter()
            .zip(&self.sides)
            .map(|(reach, side)| reach - centre.dot(*side))
            .fold(1e-6f32, f32::max);
        let mut c = Camera::orbit(centre, self.view.0, self.view.1, 1.0);
        c.z_scale = self.z_scale;
        c.eye = centre - self.forward * distance * distance_factor.max(1e-3) * 1.04;
        c
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
    fn framing_within_a_box_leaves_the_points_outside_it_out() {
        let model = [Vec3::new(0.0, 0.0, -80.0), Vec3::new(2000.0, 1000.0, 0.0)];
        let stray = Vec3::new(500.0, 500.0, -1e10);
        let framed = |framing: Framing| {
            let mut framing = framing;
            framing.add(model.into_iter().chain([stray]));
            (framing.camera(1.0), framing.bounds())
        };
        let plain = Framing::new(5.0, 1.5, (30.0, 35.0));
        let mut alone = plain.clone();
        alone.add(model);
        let (camera, bounds) = framed(plain.clone().within(model[0] - 1.0, model[1] + 1.0));
        assert_eq!(bounds, Some((model[0], model[1])));
        let want = alone.camera(1.0);
        assert!((camera.eye - want.eye).length() < 1e-3 && camera.target == want.target);
        // Without the box, the stray point takes the view.
        let (camera, bounds) = framed(plain);
        assert_eq!(bounds.map(|b| b.0.z), Some(stray.z));
        assert!((camera.eye - want.eye).length() > 1e6);
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
    fn a_framing_gathered_in_parts_is_the_framing_of_all_the_points() {
        // A tilted, offset cloud of points far from the origin.
        let points: Vec<Vec3> = (0..500)
            .map(|n| {
                let t = n as f32 * 0.37;
                Vec3::new(
                    4.0e4 + 900.0 * t.sin() + 3.0 * n as f32,
                    -2.0e4 + 400.0 * (1.3 * t).cos(),
                    -1500.0 + 60.0 * (0.7 * t).sin(),
                )
            })
            .collect();
        let (aspect, view) = (1.5, (30.0, 35.0));
        let whole = Camera::fit_points(points.iter().copied(), 5.0, aspect, view, 1.0);
        let mut framing = Framing::new(5.0, aspect, view);
        for part in points.chunks(77).rev() {
            framing.add(part.iter().copied());
        }
        assert_eq!(framing.camera(1.0), whole);
        // Framings of pieces, merged (an empty one too), are the framing of them all.
        let mut merged = Framing::new(5.0, aspect, view);
        for part in points.chunks(130) {
            let mut piece = Framing::new(5.0, aspect, view);
            piece.add(part.iter().copied());
            merged.merge(&piece);
        }
        merged.merge(&Framing::new(5.0, aspect, view));
        assert_eq!(merged.camera(1.0), whole);
        assert_eq!(merged.bounds(), framing.bounds());
        let (lo, hi) = framing.bounds().expect("points were added");
        assert!(
            points
                .iter()
                .all(|p| p.cmpge(lo).all() && p.cmple(hi).all())
        );
        assert!(Framing::new(5.0, aspect, view).bounds().is_none());
        // Every point in the picture, and the tightest on its border.
        let (near, far) = whole.depth_range(lo, hi);
        let vp = whole.view_proj(aspect, near, far);
        let reach = points
            .iter()
            .map(|&p| {
                let ndc = vp.project_point3(p);
                ndc.x.abs().max(ndc.y.abs())
            })
            .fold(0f32, f32::max);
        assert!(reach <= 1.0 && reach > 0.9, "the farthest point at {reach}");
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
