
// ---- idbuffer.wgsl: Bærentzen et al.'s ID-buffer method (2008, section 3).
// Pass 1 writes each polygon's ID and depth; pass 2 draws every edge as a
// screen-aligned quad whose fragments keep the prefiltered intensity I(d) of their
// distance to the segment where the ID under them is one of the edge's polygons or
// their depth passes the test (silhouettes), max-blended into a line buffer; pass 3
// shades the polygons with depth test "equal" and mixes in the line buffer; a final
// window-filling pass blends the lines that stick out over the background.

@group(1) @binding(2) var<storage, read> triangles: array<TriangleRecord>;
// Per real edge, two records: its vertices and the vertices opposite it (lines.rs),
// then its polygons' IDs plus one (0: none).
@group(1) @binding(3) var<storage, read> edges: array<vec4<u32>>;

// The ID buffer: polygon ID plus one (0: none) and the polygon's depth, as bits (a
// copy of the depth buffer: the GL backend cannot load from depth textures).
@group(2) @binding(0) var id_buffer: texture_2d<u32>;
// r: visible line intensity, g: hidden (dashed) line intensity.
@group(2) @binding(2) var line_buffer: texture_2d<f32>;

struct PolyOut {
    // Passes 1 and 3 must rasterize identical depths for the "equal" test.
    @builtin(position) @invariant position: vec4<f32>,
    @location(0) wp: vec3<f32>,
    @location(1) scalar: f32,
    @location(2) @interpolate(flat) id: u32,
}

@vertex
fn vs_poly(@builtin(vertex_index) vi: u32) -> PolyOut {
    let rec = triangles[vi / 3u];
    let v = rec.corners[vi % 3u];
    let wp = pulled_world(v);
    return PolyOut(clip(wp), wp, scalars[v], rec.across.w + 1u);
}

@fragment
fn fs_id(in: PolyOut) -> @location(0) vec2<u32> {
    return vec2<u32>(in.id, bitcast<u32>(in.position.z));
}

struct EdgeOut {
    @builtin(position) position: vec4<f32>,
    // The segment's ends in the window, constant over the quad.
    @location(0) @interpolate(flat) ends: vec4<f32>,
    // Half thickness in pixels and intensity factor.
    @location(1) @interpolate(flat) half: vec2<f32>,
    @location(2) @interpolate(flat) ids: vec2<u32>,
}

// The quad of equation 4 (`quad_corner`): the segment lengthened and widened by the
// half thickness plus the reach of the intensity's tail, six vertices (two triangles)
// per edge.
@vertex
fn vs_edge(@builtin(vertex_index) vi: u32) -> EdgeOut {
    let e = vi / 6u;
    let rec = edges[2u * e];
    let wa = pulled_world(rec.x);
    let wb = pulled_world(rec.y);
    var a = clip(wa);
    var b = clip(wb);
    var out: EdgeOut;
    out.position = CULLED;
    if CONTOURS {
        let o0 = clip(pulled_world(rec.z));
        var o1 = o0;
        if rec.w != NO_VERTEX {
            o1 = clip(pulled_world(rec.w));
        }
        if !is_contour(a, b, o0, o1, rec.w == NO_VERTEX) {
            return out;
        }
    }
    // Keep the visible part of the segment (reversed depth: in front when z <= w).
    let fa = a.z - a.w;
    let fb = b.z - b.w;
    if fa > 0.0 && fb > 0.0 {
        return out;
    } else if fa > 0.0 {
        a = mix(a, b, fa / (fa - fb));
    } else if fb > 0.0 {
        b = mix(b, a, fb / (fb - fa));
    }
    out.half = line_half(0.5 * (wa + wb));
    // exp2(-2 x^2) is below 1/255 beyond 1.8 pixels past the core (Bærentzen's d_max).
    let reach = out.half.x - HALF_POINT + 1.8;
    var corner_of = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u);
    out.position = quad_corner(a, b, corner_of[vi % 6u], reach);
    out.ends = vec4<f32>(window(a), window(b));
    out.ids = edges[2u * e + 1u].xy;
    return out;
}

@fragment
fn fs_edge(in: EdgeOut) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(in.position.xy);
    let under = textureLoad(id_buffer, pixel, 0).rg;
    let id = under.x;
    let depth = bitcast<f32>(under.y);
    let intensity = falloff(segment_distance(in.position.xy, in.ends.xy, in.ends.zw), in.half.x) * in.half.y;
    // Reversed depth: a line fragment nearer than (or level with) the surface passes.
    let visible = id == in.ids.x || id == in.ids.y || in.position.z >= depth;
    if visible {
        return vec4<f32>(intensity, 0.0, 0.0, 0.0);
    }
    if HIDDEN {
        let dir = normalize(in.ends.zw - in.ends.xy + vec2<f32>(1.0e-6, 0.0));
        return vec4<f32>(0.0, intensity * dash(in.position.xy, dir), 0.0, 0.0);
    }
    return vec4<f32>(0.0);
}

@fragment
fn fs_shade(in: PolyOut) -> @location(0) vec4<f32> {
    let lines = textureLoad(line_buffer, vec2<i32>(in.position.xy), 0);
    let base = base_color(in.scalar);
    let lit = shade(base.rgb, dpdx(in.wp), dpdy(in.wp));
    let under = mix(lit, frame.wire_color.rgb, lines.g * frame.wire_color.a);
    return compose(base, under, lines.r);
}

// The window-filling pass: drawn at the far end of the depth range and kept only where
// no polygon was drawn (depth still cleared), where it blends the lines' outer halves
// over the background.
@vertex
fn vs_window(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    let x = f32(vi & 1u) * 4.0 - 1.0;
    let y = f32(vi >> 1u) * 4.0 - 1.0;
    return vec4<f32>(x, y, 0.0, 1.0);
}

@fragment
fn fs_window(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let lines = textureLoad(line_buffer, vec2<i32>(position.xy), 0);
    return vec4<f32>(frame.wire_color.rgb, lines.r * frame.wire_color.a);
}
