// ---- faults.wgsl: fault traces over the surfaces (faults.rs) ----

struct FaultOut {
    @builtin(position) position: vec4<f32>,
    // The segment's ends in window pixels.
    @location(0) @interpolate(flat) ends: vec4<f32>,
}

// Six vertices per segment (an instance): the two triangles of the quad around it.
@vertex
fn vs_fault(@builtin(vertex_index) vi: u32, @location(0) a: vec3<f32>, @location(1) b: vec3<f32>) -> FaultOut {
    let ca = pulled_clip(a);
    let cb = pulled_clip(b);
    // A segment reaching behind the eye is left out: its window positions mean nothing.
    if ca.w <= 1.0e-6 || cb.w <= 1.0e-6 {
        return FaultOut(CULLED, vec4<f32>(0.0));
    }
    // Corners 0 1 2 and 0 2 3 of quad_corner's order.
    let q = select(vi, select(vi - 2u, 0u, vi == 3u), vi >= 3u);
    let position = quad_corner(ca, cb, q, 0.5 * frame.faults.x + 1.0);
    return FaultOut(position, vec4<f32>(window(ca), window(cb)));
}

// A trace's depth is nearer by this fraction of itself per unit of coverage: where two
// traces fall on the same pixel (a segment's end over the next one's, both sides of a
// fault seen from above), the more covering passes the depth test and the other fails,
// so the pixel takes about the larger coverage instead of blending both.
const COVERAGE_DEPTH: f32 = 1.0e-4;

struct FaultFragment {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fs_fault(in: FaultOut) -> FaultFragment {
    let d = segment_distance(in.position.xy, in.ends.xy, in.ends.zw);
    let cov = box_coverage(d, 0.5 * frame.faults.x);
    if cov <= 0.0 {
        discard;
    }
    let color = vec4<f32>(frame.fault_color.rgb, cov * frame.fault_color.a);
    return FaultFragment(color, in.position.z * (1.0 + COVERAGE_DEPTH * cov));
}
