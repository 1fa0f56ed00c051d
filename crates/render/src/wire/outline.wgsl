// ---- outline.wgsl: the outer half of the lines on a surface's outline (outline.rs) ----

struct OutlineOut {
    @builtin(position) position: vec4<f32>,
    // The edge's ends in window pixels.
    @location(0) @interpolate(flat) ends: vec4<f32>,
    // The first end of the edge before it and the second of the edge after it.
    @location(1) @interpolate(flat) joins: vec4<f32>,
    // xy: the point one cell inward; z: the grid line's index.
    @location(2) @interpolate(flat) inward: vec3<f32>,
    // Attenuation's depth fraction.
    @location(3) depth_fraction: f32,
}

// Six vertices per edge (an instance): the two triangles of the quad around it,
// reaching past its ends to cover the pixels around the corners it turns.
@vertex
fn vs_outline(
    @builtin(vertex_index) vi: u32,
    @location(0) a: vec3<f32>,
    @location(1) b: vec3<f32>,
    @location(2) inward: vec4<f32>,
    @location(3) before: vec3<f32>,
    @location(4) after: vec3<f32>,
) -> OutlineOut {
    let ca = pulled_clip(a);
    let cb = pulled_clip(b);
    let ci = clip(world(inward.xyz));
    let c0 = clip(world(before));
    let c1 = clip(world(after));
    // An edge reaching behind the eye is left out: its window positions mean nothing.
    if min(min(ca.w, cb.w), min(ci.w, min(c0.w, c1.w))) <= 1.0e-6 {
        return OutlineOut(CULLED, vec4<f32>(0.0), vec4<f32>(0.0), vec3<f32>(0.0), 0.0);
    }
    let q = select(vi, select(vi - 2u, 0u, vi == 3u), vi >= 3u);
    let position = quad_corner(ca, cb, q, 0.5 * frame.line.x + 1.5);
    let at_b = q == 1u || q == 2u;
    return OutlineOut(
        position,
        vec4<f32>(window(ca), window(cb)),
        vec4<f32>(window(c0), window(c1)),
        vec3<f32>(window(ci), inward.w),
        depth_fraction(world(select(a, b, at_b))),
    );
}

// The unit normal of the line splitting the pixels around a join between the edge
// running along unit `e` and its neighbour running along `other` (any length): the
// bisector of the turn, the plain perpendicular where nothing turns.
fn join_normal(e: vec2<f32>, other: vec2<f32>) -> vec2<f32> {
    let o = select(e, normalize(other), length(other) > 1.0e-4);
    let m = e + o;
    return select(e, normalize(m), length(m) > 1.0e-4);
}

// Coverage of a pixel `d` px from grid line `line`, whose cells are `cell_px` wide on
// screen across it, as (minor, major): cell_lines' levels, ranks, fading and coverage
// for a line known in advance, the offset into the line's own half period so that
// no line beyond it is seen.
fn outline_lines(line: f32, d: f32, cell_px: f32, a: f32) -> vec2<f32> {
    let grad = 2.0 / max(cell_px, 1.0e-6);
    let n = frame.major.x;
    if n < 1.5 {
        return vec2<f32>(coverage(2.0 * line + 1.0 + min(d * grad, 1.0), grad, a), 0.0);
    }
    var level = 0.0;
    if cell_px <= frame.major.y {
        level = select(1.0, 2.0, n * cell_px <= frame.major.y);
    }
    let step = level_scale(level, n);
    if !is_multiple(line, step) {
        return vec2<f32>(0.0);
    }
    let index = round(line / step);
    var rank = level;
    if level < 2.0 && is_multiple(index, n) {
        rank = select(level + 1.0, 2.0, level < 1.0 && is_multiple(index, n * n));
    }
    let scale = level_scale(rank, n);
    let c = coverage(2.0 * line / scale + 1.0 + min(d * grad / scale, 1.0), grad / scale, a);
    let w = c * select(line_fade(scale * cell_px), 1.0, rank > 1.5);
    return select(vec2<f32>(w, 0.0), vec2<f32>(0.0, w), rank > 0.5);
}

@fragment
fn fs_outline(in: OutlineOut) -> @location(0) vec4<f32> {
    let p = in.position.xy;
    let wa = in.ends.xy;
    let wb = in.ends.zw;
    let len = length(wb - wa);
    if len < 1.0e-4 {
        discard;
    }
    let e = (wb - wa) / len;
    // The normal into the surface, and the cell's width along it.
    var n = vec2<f32>(-e.y, e.x);
    let cell_px = dot(in.inward.xy - wa, n);
    if abs(cell_px) < 1.0e-4 {
        discard;
    }
    n = n * sign(cell_px);
    // The surface draws the pixels on its side, the inner half of the line.
    if dot(p - wa, n) > 0.0 {
        discard;
    }
    // Around each end, the pixels on this edge's side of the bisector with its
    // neighbour: a corner's pixels are covered once.
    if dot(p - wa, join_normal(e, wa - in.joins.xy)) < 0.0 {
        discard;
    }
    if dot(p - wb, join_normal(e, in.joins.zw - wb)) >= 0.0 {
        discard;
    }
    let d = segment_distance(p, wa, wb);
    let c = outline_lines(in.inward.z, d, abs(cell_px), in.depth_fraction);
    let major = c.y > 0.0;
    let color = select(frame.wire_color, frame.major_color, major);
    let alpha = max(c.x, c.y) * color.a;
    if alpha <= 0.0 {
        discard;
    }
    return vec4<f32>(color.rgb, alpha);
}
