//! What a frame takes from a scene besides geometry: the render style (lines,
//! colours, isolines, grid lines) and the view (framing, camera, size).

use strata_grid::CornerPointGrid;
use strata_render::glam::Vec3;
use strata_render::wgpu::DeviceType;
use strata_render::{
    Attenuation, Camera, Coverage, FaultLines, Framing, GridLines, Isolines, MajorLines, Style,
    View, parse_color,
};

use crate::scene::{Attenuate, CoverageChoice, IsolineSpec, Scene};
use crate::surfaces::framing_of;
use crate::{Error, Result};

/// The form of line coverage to draw with on an adapter of `device`: `auto` is the
/// analytic form on CPU rasterizers, which pay for every filtered fetch, and the
/// texture on GPUs, whose texture units fetch nearly for free and which keeps the
/// attenuation table and arbitrary line profiles (docs/performance.md).
pub fn coverage(choice: CoverageChoice, device: DeviceType) -> Coverage {
    match choice {
        CoverageChoice::Auto if device == DeviceType::Cpu => Coverage::Analytic,
        CoverageChoice::Auto | CoverageChoice::Texture => Coverage::Texture,
        CoverageChoice::Analytic => Coverage::Analytic,
    }
}

/// The style `scene` asks for on an adapter of `device`, colouring `scalar_range`
/// (the scene's own range wins; a solid colour when neither), for meshes whose
/// display frame starts at map `display_origin`, with `isolines`.
pub fn style(
    scene: &Scene,
    device: DeviceType,
    scalar_range: Option<(f32, f32)>,
    display_origin: [f64; 2],
    isolines: Option<Isolines>,
) -> Result<Style> {
    let wire = &scene.wire;
    let colour = &scene.colour;
    Ok(Style {
        thickness: wire.thickness,
        wire_color: parse_color(&wire.color).ok_or_else(|| {
            Error::scene(format!("--wire-color {:?} is not a colour", wire.color))
        })?,
        attenuation: match wire.attenuate {
            Attenuate::None => Attenuation::None,
            Attenuate::Intensity => Attenuation::Intensity,
            Attenuate::Thickness => Attenuation::Thickness,
        },
        coverage: coverage(wire.coverage, device),
        isolation: wire.isolation,
        hidden: wire.hidden,
        colormap: colour.colormap,
        scale: colour.scale,
        scalar_range: match (colour.range, scalar_range) {
            (Some([lo, hi]), Some(_)) => Some((lo, hi)),
            (_, range) => range,
        },
        background: if wire.isolation {
            [0.0, 0.0, 0.0, 1.0]
        } else {
            [1.0; 4]
        },
        grid_lines: scene.grid_lines.map(|g| GridLines {
            origin: g.origin,
            ..GridLines::new(g.spacing, display_origin)
        }),
        isolines,
        major: match wire.major {
            0 => None,
            every => Some(MajorLines {
                every,
                fade: wire.fade,
                color: parse_color(&wire.major_color).ok_or_else(|| {
                    Error::scene(format!(
                        "--major-color {:?} is not a colour",
                        wire.major_color
                    ))
                })?,
            }),
        },
        faults: if wire.fault_thickness > 0.0 {
            Some(FaultLines {
                thickness: wire.fault_thickness,
                color: parse_color(&wire.fault_color).ok_or_else(|| {
                    Error::scene(format!(
                        "--fault-color {:?} is not a colour",
                        wire.fault_color
                    ))
                })?,
            })
        } else {
            None
        },
        ..Style::default()
    })
}

/// The isolines `spec` asks for of a field whose values span `range`: its spacing,
/// or about ten round lines over the range.
pub fn isolines(spec: &IsolineSpec, range: (f32, f32)) -> Isolines {
    Isolines {
        major_every: spec.major_every,
        ..Isolines::new(
            spec.spacing
                .unwrap_or_else(|| nice_spacing(range.1 - range.0, 10.0)),
        )
    }
}

/// A round spacing (1, 2 or 5 times a power of ten) giving about `lines` lines over
/// `range`; worked out in f64 so that it is the f32 nearest the round number (0.05,
/// not 0.049999997).
pub fn nice_spacing(range: f32, lines: f32) -> f32 {
    let raw = (f64::from(range) / f64::from(lines)).max(f64::from(f32::MIN_POSITIVE));
    let power = raw.log10().floor() as i32;
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * 10f64.powi(power))
        .find(|s| *s >= raw)
        .unwrap_or(10f64.powi(power + 1)) as f32
}

/// The width / height of `scene`'s picture.
pub fn aspect(scene: &Scene) -> f32 {
    scene.size[0] as f32 / scene.size[1] as f32
}

/// The framing of `scene`'s camera before any point is added: the model's corners
/// but its stray ones (`framed`, display frame) bound what it frames.
pub fn framing(scene: &Scene, framed: Option<[[f32; 3]; 2]>) -> Framing {
    let c = &scene.camera;
    framing_of(framed, c.z_scale, aspect(scene), (c.azimuth, c.elevation))
}

/// `camera` moved sideways to look at the scene's camera target, when it has one
/// (`origin`: the display origin of the positions drawn).
pub fn aimed(scene: &Scene, camera: Camera, origin: [f64; 3]) -> Camera {
    match scene.camera.target {
        Some(target) => camera.centred_on(Vec3::from(CornerPointGrid::to_display(origin, target))),
        None => camera,
    }
}

/// The view of `scene` through `camera` (at the scene's distance already), over
/// the framed `bounds`.
pub fn view(scene: &Scene, camera: Camera, bounds: (Vec3, Vec3)) -> View {
    View {
        camera,
        width: scene.size[0],
        height: scene.size[1],
        bounds,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_coverage_is_analytic_on_cpu_rasterizers_only() {
        use DeviceType::{Cpu, DiscreteGpu, IntegratedGpu};
        assert_eq!(coverage(CoverageChoice::Auto, Cpu), Coverage::Analytic);
        assert_eq!(
            coverage(CoverageChoice::Auto, DiscreteGpu),
            Coverage::Texture
        );
        assert_eq!(
            coverage(CoverageChoice::Auto, IntegratedGpu),
            Coverage::Texture
        );
        assert_eq!(coverage(CoverageChoice::Texture, Cpu), Coverage::Texture);
        assert_eq!(
            coverage(CoverageChoice::Analytic, DiscreteGpu),
            Coverage::Analytic
        );
    }

    #[test]
    fn major_lines_and_fault_traces_are_drawn_unless_the_scene_sets_zero() {
        let mut scene = Scene::of_model("m.grdecl");
        let drawn = |scene: &Scene| {
            style(scene, DeviceType::Cpu, None, [0.0; 2], None)
                .expect("a style")
                .major
        };
        let major = drawn(&scene).expect("major lines by default");
        assert_eq!((major.every, major.fade), (10, 4.0));
        assert_eq!(Some(major.color), parse_color("#0d1f66"));
        scene.wire.major = 0;
        assert_eq!(drawn(&scene), None);
        let faults = |scene: &Scene| {
            style(scene, DeviceType::Cpu, None, [0.0; 2], None)
                .expect("a style")
                .faults
        };
        assert_eq!(faults(&scene).map(|f| f.thickness), Some(2.5));
        scene.wire.fault_thickness = 0.0;
        assert_eq!(faults(&scene), None);
    }

    #[test]
    fn isolines_take_a_spacing_or_about_ten_round_lines() {
        // Range 0.0615..0.2968: the first round spacing not below a tenth of it.
        let spec = IsolineSpec::of(Some("PORO"));
        assert_eq!(isolines(&spec, (0.0615, 0.2968)).spacing, 0.05);
        let spec = IsolineSpec {
            spacing: Some(0.01),
            major_every: 4,
            ..spec
        };
        let lines = isolines(&spec, (0.0, 1.0));
        assert_eq!((lines.spacing, lines.major_every), (0.01, 4));
    }
}
