
// ---- bias.wgsl: the classic two-pass wireframe. The fill is pushed back by the
// pipeline's depth bias; the lines are then depth tested against it: line primitives
// one pixel wide, or screen-space quads for thicker lines (the quad of Bærentzen et
// al.'s equation 4, expanded here in the vertex shader by pulling the edge's ends).

// Per real edge: its two vertices and the vertex opposite it on either side (lines.rs).
@group(1) @binding(2) var<storage, read> edges: array<vec4<u32>>;

struct FillOut {
    @builtin(position) position: vec4<f32>,
    @location(0) wp: vec3<f32>,
    @location(1) scalar: f32,
}

@vertex
fn vs_fill(@location(0) p: vec3<f32>, @location(1) scalar: f32) -> FillOut {
    let wp = world(p);
    return FillOut(clip(wp), wp, scalar);
}

@fragment
fn fs_fill(in: FillOut) -> @location(0) vec4<f32> {
    let base = base_color(in.scalar);
    return compose(base, shade(base.rgb, dpdx(in.wp), dpdy(in.wp)), 0.0);
}

struct LineOut {
    @builtin(position) position: vec4<f32>,
    @location(0) scalar: f32,
    // Unit direction of the line in the window (for dashes).
    @location(1) @interpolate(flat) dir: vec2<f32>,
    @location(2) wp: vec3<f32>,
}

// One-pixel lines straight from the fill's vertex buffer, indexed by the edge list:
// the classic path, for visible lines of every edge.
@vertex
fn vs_line(@location(0) p: vec3<f32>, @location(1) scalar: f32) -> LineOut {
    let wp = world(p);
    return LineOut(clip(wp), scalar, vec2<f32>(1.0, 0.0), wp);
}

// The edge's two ends, or nothing when contour styles drop it.
struct EdgeEnds {
    a: vec4<f32>,
    b: vec4<f32>,
    wa: vec3<f32>,
    wb: vec3<f32>,
    drawn: bool,
}

fn edge_ends(e: u32) -> EdgeEnds {
    let rec = edges[e];
    let wa = pulled_world(rec.x);
    let wb = pulled_world(rec.y);
    let a = clip(wa);
    let b = clip(wb);
    var drawn = true;
    if CONTOURS {
        let o0 = clip(pulled_world(rec.z));
        var o1 = o0;
        if rec.w != NO_VERTEX {
            o1 = clip(pulled_world(rec.w));
        }
        drawn = is_contour(a, b, o0, o1, rec.w == NO_VERTEX);
    }
    return EdgeEnds(a, b, wa, wb, drawn);
}

// Clips segment a b to the visible side of the near plane (reversed depth: z <= w) so
// that both ends have a window position; `drawn` false when none of it is in front.
fn clip_near(ends: EdgeEnds) -> EdgeEnds {
    var out = ends;
    let fa = ends.a.z - ends.a.w;
    let fb = ends.b.z - ends.b.w;
    if fa > 0.0 && fb > 0.0 {
        out.drawn = false;
    } else if fa > 0.0 {
        out.a = mix(ends.a, ends.b, fa / (fa - fb));
    } else if fb > 0.0 {
        out.b = mix(ends.b, ends.a, fb / (fb - fa));
    }
    return out;
}

fn window_dir(a: vec4<f32>, b: vec4<f32>) -> vec2<f32> {
    let d = window(b) - window(a);
    let len = length(d);
    return select(vec2<f32>(1.0, 0.0), d / len, len > 1.0e-6);
}

// One-pixel lines pulled from the edge list (contour styles, and the dashed hidden pass).
@vertex
fn vs_line_pulled(@builtin(vertex_index) vi: u32) -> LineOut {
    let ends = clip_near(edge_ends(vi / 2u));
    if !ends.drawn {
        return LineOut(CULLED, 0.0, vec2<f32>(1.0, 0.0), vec3<f32>(0.0));
    }
    let at_b = vi % 2u == 1u;
    let v = edges[vi / 2u][vi % 2u];
    return LineOut(select(ends.a, ends.b, at_b), scalars[v], window_dir(ends.a, ends.b), select(ends.wa, ends.wb, at_b));
}

@fragment
fn fs_line(in: LineOut) -> @location(0) vec4<f32> {
    // A rasterized line covers one pixel per step: lines thinner than a pixel fade.
    var cov = min(frame.line.x, 1.0) * line_half(in.wp).y;
    if HIDDEN {
        cov *= dash(in.position.xy, in.dir);
    }
    return line_color(in.scalar, cov);
}

struct QuadOut {
    @builtin(position) position: vec4<f32>,
    @location(0) scalar: f32,
    // The segment's ends in the window, constant over the quad.
    @location(1) @interpolate(flat) ends: vec4<f32>,
    // Half thickness in pixels and intensity factor.
    @location(2) @interpolate(flat) half: vec2<f32>,
}

// Wide lines: six vertices (two triangles) per edge, the quad around the segment
// widened by the half thickness plus a pixel for the filtered border.
@vertex
fn vs_quad(@builtin(vertex_index) vi: u32) -> QuadOut {
    let e = vi / 6u;
    let ends = clip_near(edge_ends(e));
    var out: QuadOut;
    if !ends.drawn {
        out.position = CULLED;
        return out;
    }
    out.half = line_half(0.5 * (ends.wa + ends.wb));
    // Quad corners 0 1 2 3 = (a, -), (b, -), (b, +), (a, +); triangles 0 1 2 and 0 2 3.
    var corner_of = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u);
    let q = corner_of[vi % 6u];
    let at_b = q == 1u || q == 2u;
    out.position = quad_corner(ends.a, ends.b, q, out.half.x + 1.0);
    let v = edges[e][select(0u, 1u, at_b)];
    out.scalar = scalars[v];
    out.ends = vec4<f32>(window(ends.a), window(ends.b));
    return out;
}

@fragment
fn fs_quad(in: QuadOut) -> @location(0) vec4<f32> {
    let d = segment_distance(in.position.xy, in.ends.xy, in.ends.zw);
    var cov = box_coverage(d, in.half.x) * in.half.y;
    if HIDDEN {
        cov *= dash(in.position.xy, normalize(in.ends.zw - in.ends.xy + vec2<f32>(1.0e-6, 0.0)));
    }
    return line_color(in.scalar, cov);
}
