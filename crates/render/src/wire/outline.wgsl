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

// Where the edge's neighbour at one end lies on screen, for the bisector there: its far
// end `p` projected where the outline turns, a point straight on along the edge where
// it does not (`straight` 1: nothing to project, the split is the perpendicular).
fn join_point(p: vec4<f32>, end: vec2<f32>, e: vec2<f32>) -> vec2<f32> {
    if p.w > 0.5 {
        return end + e;
    }
    let c = clip(world(p.xyz));
    return select(end + e, window(c), c.w > 1.0e-6);
}

// Four vertices per edge (an instance, drawn as two triangles): the quad beside it, on
// the side away from the surface, reaching past its ends where the outline turns (the
// corner's pixels up to the bisector) and a pixel elsewhere.
@vertex
fn vs_outline(
    @builtin(vertex_index) q: u32,
    @location(0) a: vec3<f32>,
    @location(1) b: vec3<f32>,
    @location(2) inward: vec4<f32>,
    @location(3) before: vec4<f32>,
    @location(4) after: vec4<f32>,
) -> OutlineOut {
    let ca = pulled_clip(a);
    let cb = pulled_clip(b);
    let ci = clip(world(inward.xyz));
    // An edge reaching behind the eye is left out: its window positions mean nothing.
    if min(min(ca.w, cb.w), ci.w) <= 1.0e-6 {
        return OutlineOut(CULLED, vec4<f32>(0.0), vec4<f32>(0.0), vec3<f32>(0.0), 0.0);
    }
    let wa = window(ca);
    let wb = window(cb);
    let wi = window(ci);
    let len = length(wb - wa);
    let e = select(vec2<f32>(1.0, 0.0), (wb - wa) / len, len > 1.0e-6);
    let n = vec2<f32>(-e.y, e.x);
    let outward = select(n, -n, dot(wi - wa, n) > 0.0);
    // An edge whose line is not drawn at this level (cells small on screen, the line
    // not a major one) draws nothing.
    if outline_level(inward.w, abs(dot(wi - wa, n))).y <= 0.0 {
        return OutlineOut(CULLED, vec4<f32>(0.0), vec4<f32>(0.0), vec3<f32>(0.0), 0.0);
    }
    // Coverage ends a pixel past the line's half width (a two-pixel box at most).
    let reach = 0.5 * frame.line.x + 1.0;
    let ends = vec2<f32>(select(reach, 1.0, before.w > 0.5), select(reach, 1.0, after.w > 0.5));
    // From half a pixel inside the edge (pixels centred on it are the surface's) to
    // `reach` out.
    let position = segment_quad_corner(ca, cb, q, outward, vec2<f32>(-0.5, reach), ends);
    let at_b = q == 1u || q == 2u;
    return OutlineOut(
        position,
        vec4<f32>(wa, wb),
        vec4<f32>(join_point(before, wa, -e), join_point(after, wb, e)),
        vec3<f32>(wi, inward.w),
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

// How grid line `line`, whose cells are `cell_px` wide on screen across it, is drawn:
// x the scale of its level's coordinate, y its opacity (0: not drawn, not a line of
// the level drawn or faded out), z 1 for a major line. cell_lines' levels, ranks and
// fading for a line known in advance; constant along an outline edge, so that the
// vertex shader leaves out edges whose line is not drawn.
fn outline_level(line: f32, cell_px: f32) -> vec3<f32> {
    let n = frame.major.x;
    if n < 1.5 {
        return vec3<f32>(1.0, 1.0, 0.0);
    }
    var level = 0.0;
    if cell_px <= frame.major.y {
        level = select(1.0, 2.0, n * cell_px <= frame.major.y);
    }
    let step = level_scale(level, n);
    if !is_multiple(line, step) {
        return vec3<f32>(step, 0.0, 0.0);
    }
    let index = round(line / step);
    var rank = level;
    if level < 2.0 && is_multiple(index, n) {
        rank = select(level + 1.0, 2.0, level < 1.0 && is_multiple(index, n * n));
    }
    let scale = level_scale(rank, n);
    let opacity = select(line_fade(scale * cell_px), 1.0, rank > 1.5);
    return vec3<f32>(scale, opacity, select(0.0, 1.0, rank > 0.5));
}

// Coverage of a pixel `d` px from grid line `line` drawn as `level` says (see
// outline_level), as (minor, major): the offset is kept within the line's own half
// period, so that no line beyond it is seen.
fn outline_lines(line: f32, d: f32, cell_px: f32, a: f32, level: vec3<f32>) -> vec2<f32> {
    let grad = 2.0 / max(cell_px, 1.0e-6);
    let scale = level.x;
    let c = coverage(2.0 * line / scale + 1.0 + min(d * grad / scale, 1.0), grad / scale, a);
    let w = c * level.y;
    return select(vec2<f32>(w, 0.0), vec2<f32>(0.0, w), level.z > 0.5);
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
    let level = outline_level(in.inward.z, abs(cell_px));
    let c = outline_lines(in.inward.z, d, abs(cell_px), in.depth_fraction, level);
    let major = c.y > 0.0;
    let color = select(frame.wire_color, frame.major_color, major);
    var alpha = max(c.x, c.y) * color.a;
    // Where the cells are so small on screen that the cap thins every line to `cap`
    // coordinate units (coverage_analytic), the lines' mean covers the surface evenly;
    // beyond it the edge's own line, that thin, is all there is to draw (not a band of
    // that mean as wide as the quad).
    let g = 2.0 / max(abs(cell_px), 1.0e-6) / level.x;
    if 0.5 * frame.line.x * g > frame.line.y {
        alpha = min(alpha, box_coverage(d, frame.line.y / g) * color.a);
    }
    if alpha <= 0.0 {
        discard;
    }
    return vec4<f32>(color.rgb, alpha);
}
