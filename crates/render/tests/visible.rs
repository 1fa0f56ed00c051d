//! `Renderer::visible_fractions`: how much of each of several surfaces the views around
//! them show, which splits a decimation budget among a model's layer surfaces. CI runs
//! this file on llvmpipe (GL) and lavapipe (Vulkan).

mod support;

use strata_grid::SurfaceMesh;
use strata_render::glam::Vec3;
use strata_render::{Renderer, Sampling};
use support::*;

/// A gently curved square of `n` x `n` cells of 10 m at depth offset `z`.
fn layer(n: usize, z: f32) -> SurfaceMesh {
    SurfaceMesh::structured(n, n, |i, j| {
        let (x, y) = (i as f32 * 10.0, j as f32 * 10.0);
        [x, y, z + 0.002 * (x - 100.0) * (y - 100.0) / 10.0]
    })
}

#[test]
fn a_surface_alone_is_seen_whole() {
    let mut r = renderer();
    let one = layer(20, 0.0);
    let seen = r
        .visible_fractions(&[&one], 5.0, None)
        .expect("visible fractions");
    assert_eq!(seen.len(), 1);
    // Pixel centres against the triangles' exact area: only the outline's pixels differ.
    assert!((seen[0] - 1.0).abs() < 0.03, "{}: {seen:?}", backend(&r));
}

#[test]
fn stacked_surfaces_hide_those_between_top_and_bottom() {
    let mut r = renderer();
    let stack: Vec<SurfaceMesh> = (0..4).map(|k| layer(20, -2.0 * k as f32)).collect();
    let seen = r
        .visible_fractions(&stack.iter().collect::<Vec<_>>(), 5.0, None)
        .expect("visible fractions");
    let name = backend(&r);
    // Top and bottom show whole from their own side (half the views) and hardly at all
    // from the other; those between show only a strip at the rim.
    for &outer in [seen[0], seen[3]].iter() {
        assert!((0.45..0.6).contains(&outer), "{name}: {seen:?}");
    }
    for &inner in &seen[1..3] {
        assert!(inner < 0.1, "{name}: {seen:?}");
    }
    // Moved aside, the second surface no longer lies under the first: it shows from
    // above as the top does.
    let mut aside = stack.clone();
    for p in &mut aside[1].positions {
        p[0] += 400.0;
    }
    let seen = r
        .visible_fractions(&aside.iter().collect::<Vec<_>>(), 5.0, None)
        .expect("visible fractions");
    assert!(seen[1] > 0.9, "{name}: {seen:?}");
    // A surface of no triangle covers no pixel.
    let empty = SurfaceMesh::default();
    let seen = r
        .visible_fractions(&[&stack[0], &empty], 5.0, None)
        .expect("visible fractions");
    assert_eq!(seen[1], 0.0, "{name}: {seen:?}");
}

/// The fractions of both samplings, each surface's within `tolerance`.
fn both_agree(r: &mut Renderer, surfaces: &[&SurfaceMesh], tolerance: f64) -> Vec<f64> {
    let name = backend(r);
    let cpu = r
        .visible_fractions_by(surfaces, 5.0, None, Sampling::Cpu)
        .expect("sampled on the CPU");
    let drawn = r
        .visible_fractions_by(surfaces, 5.0, None, Sampling::Adapter)
        .expect("drawn by the adapter");
    assert_eq!(cpu.len(), surfaces.len());
    for (a, b) in cpu.iter().zip(&drawn) {
        assert!(
            (a - b).abs() <= tolerance,
            "{name}: CPU {cpu:?}, adapter {drawn:?}"
        );
    }
    cpu
}

#[test]
fn sampling_on_the_cpu_sees_what_the_adapter_draws() {
    let mut r = renderer();
    // Stacked, one moved aside, and one tilted through the others: the nearest surface
    // changes across each frame.
    let mut stack: Vec<SurfaceMesh> = (0..4).map(|k| layer(20, -2.0 * k as f32)).collect();
    for p in &mut stack[1].positions {
        p[0] += 100.0;
    }
    for p in &mut stack[2].positions {
        p[2] += 0.05 * (p[0] - 100.0);
    }
    let seen = both_agree(&mut r, &stack.iter().collect::<Vec<_>>(), 0.005);
    assert!(seen.iter().all(|&s| s > 0.0), "{seen:?}");
    // At equal depth the surface drawn last shows, in both: a copy hides its original.
    let one = layer(20, 0.0);
    let seen = both_agree(&mut r, &[&one, &one.clone()], 0.005);
    assert!(seen[0] < 0.01 && (seen[1] - 1.0).abs() < 0.03, "{seen:?}");
}

#[test]
fn triangles_out_of_the_framed_box_are_neither_seen_nor_counted() {
    let mut r = renderer();
    let name = backend(&r);
    let stack: Vec<SurfaceMesh> = (0..4).map(|k| layer(20, -2.0 * k as f32)).collect();
    let mut stray = stack.clone();
    // A node inside the top surface at a depth as corrupt as a file's can be.
    stray[0].positions[10 * 21 + 10][2] = -1e11;
    let framed = Some((Vec3::new(-1.0, -1.0, -10.0), Vec3::new(201.0, 201.0, 5.0)));
    for sampling in [Sampling::Cpu, Sampling::Adapter] {
        let mut seen = |surfaces: &[SurfaceMesh], framed| {
            r.visible_fractions_by(&surfaces.iter().collect::<Vec<_>>(), 5.0, framed, sampling)
                .expect("visible fractions")
        };
        let sound = seen(&stack, None);
        // The sound surfaces are all in the box: framed by it, as without it.
        assert_eq!(seen(&stack, framed), sound, "{name} {sampling:?}");
        let left_out = seen(&stray, framed);
        for (s, k) in left_out.iter().zip(&sound) {
            assert!(
                (s - k).abs() < 0.02,
                "{name} {sampling:?}: {left_out:?} against {sound:?}"
            );
        }
        // Counted, the stray corner's faces shrink the rest of the model to a speck.
        let counted = seen(&stray, None);
        assert!(
            counted[0] < 0.5 * sound[0],
            "{name} {sampling:?}: {counted:?} against {sound:?}"
        );
    }
}
