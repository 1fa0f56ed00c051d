// Contour polylines as line primitives (contour.rs), appended to common.wgsl.

@vertex
fn vs_contour(@location(0) p: vec3<f32>) -> @builtin(position) vec4<f32> {
    var c = clip(world(p));
    // The lines lie on the surface: pull them a little towards the eye (reversed
    // depth: larger is nearer) so that the surface's own depth does not hide them.
    c.z = min(c.z + 1.0e-4 * c.w, c.w);
    return c;
}

// Line primitives are opaque, in the isolines' colour (whose alpha only scales the
// texture isolines' coverage), so the baseline can be drawn over a surface whose own
// isolines are hidden.
@fragment
fn fs_contour() -> @location(0) vec4<f32> {
    return vec4<f32>(frame.iso_color.rgb, 1.0);
}
