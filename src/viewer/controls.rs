//! Mouse and keys: how a gesture turns into a new camera of the scene, and the keys
//! the help overlay lists.

use strata_render::View;
use strata_render::glam::Vec3;

use crate::scene::CameraSpec;

/// Degrees the camera turns per pixel dragged.
pub const DEGREES_PER_PIXEL: f32 = 0.3;

/// The keys and what they do, as the help overlay and the README list them.
pub const KEYS: [(&str, &str); 12] = [
    ("drag (left)", "orbit"),
    ("drag (right or middle)", "pan"),
    ("wheel", "zoom to the cursor"),
    ("double-click", "centre on the point"),
    ("click", "pick the cell: I,J,K, corners, values"),
    ("F", "fit the model"),
    ("T", "view from the top"),
    ("S / W / N / E", "view from the south / west / north / east"),
    ("+ / -", "zoom in / out"),
    ("Space", "play the report steps"),
    ("F12", "screenshot (PNG beside the model)"),
    ("H or F1", "this help"),
];

/// The camera turned by a drag of `(dx, dy)` pixels.
pub fn orbit(camera: &mut CameraSpec, dx: f32, dy: f32) {
    camera.azimuth = (camera.azimuth - dx * DEGREES_PER_PIXEL).rem_euclid(360.0);
    camera.elevation = (camera.elevation + dy * DEGREES_PER_PIXEL).clamp(-89.0, 90.0);
}

/// The point the last frame looked at, in map coordinates (x, y, depth).
pub fn looked_at(view: &View, origin: [f64; 3]) -> [f64; 3] {
    to_map(view.camera.target, view.camera.z_scale, origin)
}

/// A point of the frame the camera sees (display frame, z exaggerated) in map
/// coordinates.
fn to_map(p: Vec3, z_scale: f32, origin: [f64; 3]) -> [f64; 3] {
    [
        f64::from(p.x) + origin[0],
        f64::from(p.y) + origin[1],
        -(f64::from(p.z / z_scale) + origin[2]),
    ]
}

/// The camera moved sideways by a drag of `(dx, dy)` pixels, so that the point under
/// the cursor at the target's depth follows it.
pub fn pan(camera: &mut CameraSpec, view: &View, origin: [f64; 3], dx: f32, dy: f32) {
    let c = &view.camera;
    let forward = c.target - c.eye;
    let distance = forward.length();
    let forward = forward.normalize_or(Vec3::NEG_Z);
    let right = forward.cross(c.up).normalize_or(Vec3::X);
    let up = right.cross(forward);
    let per_pixel =
        2.0 * distance * (0.5 * c.fov_y_deg.to_radians()).tan() / view.height.max(1) as f32;
    let moved = c.target - right * (dx * per_pixel) + up * (dy * per_pixel);
    camera.target = Some(to_map(moved, c.z_scale, origin));
}

/// The camera `steps` wheel notches closer (negative: farther), keeping `towards`
/// (the point under the cursor, map coordinates) where it is on screen.
pub fn zoom(
    camera: &mut CameraSpec,
    view: &View,
    origin: [f64; 3],
    steps: f32,
    towards: Option<[f64; 3]>,
) {
    let factor = 0.85f32.powf(steps);
    camera.distance = (camera.distance * factor).clamp(1e-4, 50.0);
    if let Some(point) = towards {
        let target = looked_at(view, origin);
        let f = f64::from(factor);
        camera.target = Some(std::array::from_fn(|a| {
            point[a] + (target[a] - point[a]) * f
        }));
    }
}

/// The view from `azimuth` degrees at `elevation`, the whole model framed.
pub fn view_from(camera: &mut CameraSpec, azimuth: f32, elevation: f32) {
    camera.azimuth = azimuth;
    camera.elevation = elevation;
    fit(camera);
}

/// The whole model framed again, looking at its middle.
pub fn fit(camera: &mut CameraSpec) {
    camera.distance = 1.0;
    camera.target = None;
    camera.centre = None;
}

#[cfg(test)]
mod tests {
    use super::*;
    use strata_render::Camera;

    fn top_view() -> View {
        View {
            camera: Camera::orbit(Vec3::new(10.0, 20.0, -30.0), 0.0, 90.0, 100.0),
            width: 200,
            height: 100,
            bounds: (Vec3::splat(-50.0), Vec3::splat(50.0)),
        }
    }

    #[test]
    fn orbit_turns_and_keeps_the_elevation_above_the_floor() {
        let mut camera = CameraSpec::default();
        orbit(&mut camera, -100.0, 1000.0);
        assert!((camera.azimuth - 60.0).abs() < 1e-4, "{}", camera.azimuth);
        assert_eq!(camera.elevation, 90.0);
    }

    #[test]
    fn panning_from_above_moves_the_target_by_the_pixels_dragged() {
        let view = top_view();
        let mut camera = CameraSpec::default();
        pan(&mut camera, &view, [1000.0, 2000.0, 0.0], 10.0, 0.0);
        let target = camera.target.expect("a target");
        // From above, north up: dragging right moves the model right, the look-at west.
        let per_pixel = 2.0 * 100.0 * (17.5f64).to_radians().tan() / 100.0;
        assert!(
            (target[0] - (1010.0 - 10.0 * per_pixel)).abs() < 1e-2,
            "{target:?}"
        );
        assert!((target[1] - 2020.0).abs() < 1e-2, "{target:?}");
        assert!((target[2] - 30.0).abs() < 1e-2, "{target:?}");
    }

    #[test]
    fn zooming_to_a_point_keeps_it_and_shortens_the_distance() {
        let view = top_view();
        let mut camera = CameraSpec::default();
        let point = [20.0, 20.0, 30.0];
        zoom(&mut camera, &view, [0.0; 3], 2.0, Some(point));
        assert!(camera.distance < 1.0);
        let target = camera.target.expect("a target");
        // The target moved towards the point by the zoom factor.
        let f = 0.85f64.powi(2);
        assert!(
            (target[0] - (20.0 + (10.0 - 20.0) * f)).abs() < 1e-3,
            "{target:?}"
        );
        fit(&mut camera);
        assert_eq!((camera.distance, camera.target), (1.0, None));
    }
}
