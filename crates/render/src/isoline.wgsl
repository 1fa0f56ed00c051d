// Isolines with the range adjust (Celes & Abraham 2011 section 6, 2010 section V).
// Appended to common.wgsl (frame uniforms, coverage, extra_lines, compose_lines).
//
// cs_adjust, a compute prepass over triangles, stands in for the paper's geometry
// shader: per triangle it maps the three corner values of the field through the
// texture matrix (s = 2 (f - offset) / spacing + 1, lines at odd s) and writes the
// three adjusted coordinates to a per-corner buffer, which vs_iso reads as a vertex
// attribute of a de-indexed draw (corner = vertex_index).

struct IsoParams {
    // 0 off, 1 on (strata's), 2 the 2010 paper's formula, 3 the 2011 journal's.
    mode: u32,
    triangles: u32,
    // Threads per row of the 2D dispatch (large meshes exceed 65535 groups in x).
    row: u32,
    pad: u32,
}

// Corner records: x, y, z, u, v, colour scalar, isoline field.
const CORNER_FLOATS: u32 = 7u;
// After the adjust a coordinate unit spans at most 64 px (gradient >= 1/64 units per
// pixel): far from magnifying any wireframe texture (4096 texels per unit) and far
// from the saturation cap, which only bites when a unit spans fewer than
// thickness / (2 cap) px.
const TARGET_GRADIENT: f32 = 0.015625;

@group(1) @binding(0) var<storage, read> corners: array<f32>;
@group(1) @binding(1) var<storage, read_write> adjusted: array<f32>;
@group(1) @binding(2) var<uniform> params: IsoParams;

fn corner_position(i: u32) -> vec3<f32> {
    let b = i * CORNER_FLOATS;
    return vec3<f32>(corners[b], corners[b + 1u], corners[b + 2u]);
}

// The papers' `adjust` (Fig. 15 of 2011, Fig. 12 of 2010), written for lines at odd
// s: u = (s + 1) / 2 has its lines at the integers, as the papers' texture does. When
// the triangle's range [m, M] holds exactly one line (floor M - floor m == 1), that
// line is u = floor M, and the papers scale the range to 1 around a pivot:
// `around_max` true is the 2010 pivot fM, false the 2011 pivot fm.
fn adjust_paper(s: vec3<f32>, around_max: bool) -> vec3<f32> {
    let u = 0.5 * (s + 1.0);
    let hi = max(u.x, max(u.y, u.z));
    let lo = min(u.x, min(u.y, u.z));
    let f_hi = floor(hi);
    let f_lo = floor(lo);
    if f_hi - f_lo != 1.0 {
        return s;
    }
    let pivot = select(f_lo, f_hi, around_max);
    let v = (u - pivot) / (hi - lo) + pivot;
    return 2.0 * v - 1.0;
}

// Pixel position (x, y) and clip w of a display-frame point.
fn to_pixels(p: vec3<f32>) -> vec3<f32> {
    let c = clip(world(p));
    let ndc = c.xy / c.w;
    return vec3<f32>((0.5 * ndc.x + 0.5) * frame.viewport.x, (0.5 - 0.5 * ndc.y) * frame.viewport.y, c.w);
}

// strata's adjust. The pivot is the 2010 paper's (fM: the line the range encloses;
// for a range that encloses none, the nearest line, so that the anti-aliased edge of
// a line passing just outside the triangle is drawn with the same scale as its
// centre). Scaling around the line keeps s' = L exactly where s = L. The factor is
// chosen from the triangle's gradient on screen rather than fixed to "range -> 1":
//  - it is only as large as needed to stop magnification (a unit spans at most
//    1 / TARGET_GRADIENT px), so the small mip levels' saturation cap never thins a
//    line in small triangles, as the papers' fixed factor does;
//  - it never puts a corner more than one unit (half the line period) from L, so no
//    other line can appear inside the triangle (the papers' factor puts a corner up
//    to 2 units away, next to the neighbouring line, whose anti-aliased edge then
//    shows as a spot);
//  - it is never below 1: the adjust never magnifies.
fn adjust_to_view(s: vec3<f32>, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>) -> vec3<f32> {
    let hi = max(s.x, max(s.y, s.z));
    let lo = min(s.x, min(s.y, s.z));
    let line = 2.0 * floor(0.25 * (hi + lo)) + 1.0;
    let d = abs(s - line);
    let dmax = max(d.x, max(d.y, d.z));
    if dmax <= 0.0 {
        return s;
    }
    let a = to_pixels(p0);
    let b = to_pixels(p1);
    let c = to_pixels(p2);
    // A corner behind the eye: no meaningful gradient on screen; leave it.
    if min(a.z, min(b.z, c.z)) <= 0.0 {
        return s;
    }
    let e1 = b.xy - a.xy;
    let e2 = c.xy - a.xy;
    let det = e1.x * e2.y - e1.y * e2.x;
    if abs(det) < 1.0e-6 {
        return s;
    }
    let ds1 = s.y - s.x;
    let ds2 = s.z - s.x;
    let grad = vec2<f32>(ds1 * e2.y - ds2 * e1.y, ds2 * e1.x - ds1 * e2.x) / det;
    let k = max(1.0, min(TARGET_GRADIENT / max(length(grad), 1.0e-30), 1.0 / dmax));
    return line + (s - line) * k;
}

@compute @workgroup_size(64)
fn cs_adjust(@builtin(global_invocation_id) id: vec3<u32>) {
    let t = id.y * params.row + id.x;
    if t >= params.triangles {
        return;
    }
    var s = vec3<f32>(0.0);
    var defined = true;
    for (var c = 0u; c < 3u; c++) {
        let f = corners[(3u * t + c) * CORNER_FLOATS + 6u];
        defined = defined && f > UNDEFINED_SCALAR;
        s[c] = iso_coordinate(f);
    }
    if !defined {
        s = vec3<f32>(ISO_UNDEFINED);
    } else if params.mode == 1u {
        s = adjust_to_view(s, corner_position(3u * t), corner_position(3u * t + 1u), corner_position(3u * t + 2u));
    } else if params.mode == 2u {
        s = adjust_paper(s, true);
    } else if params.mode == 3u {
        s = adjust_paper(s, false);
    }
    for (var c = 0u; c < 3u; c++) {
        adjusted[3u * t + c] = s[c];
    }
}

struct IsoOut {
    @builtin(position) position: vec4<f32>,
    @location(0) wp: vec3<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) scalar: f32,
    @location(3) s: f32,
}

@vertex
fn vs_iso(@location(0) p: vec3<f32>, @location(1) uv: vec2<f32>, @location(2) scalar: f32, @location(3) s: f32) -> IsoOut {
    let wp = world(p);
    return IsoOut(clip(wp), wp, uv, scalar, s);
}

// Surface, isolines and grid lines; `wire` adds the global-coordinate wireframe.
fn shade_iso(in: IsoOut, wire: bool) -> vec4<f32> {
    let dpx = dpdx(in.wp);
    let dpy = dpdy(in.wp);
    let du = dpdx(in.uv);
    let dv = dpdy(in.uv);
    let a = depth_fraction(in.wp);
    // The cell lines as (minor, major), major lines in their own colour as the
    // wireframe techniques draw them.
    var cov = vec2<f32>(0.0);
    if wire {
        cov = global_cells(in.uv, du, dv, a);
    }
    // The texture is sampled as the paper samples it: never finer than its level 0
    // (two texels per pixel, see wire_texture.rs), so where the coordinate changes
    // less than that per pixel the line is magnified and thickens, the problem the
    // range adjust solves. (coverage_texture alone would rescale the distance below
    // level 0 and hide it: the fragment paths rely on that instead of an adjust.)
    var floor_grad = 0.0;
    if frame.line.z < 0.5 {
        floor_grad = 2.0 / f32(textureDimensions(wire_tex, 0).x);
    }
    let extra = extra_lines_floored(in.wp, in.s, a, floor_grad);
    let base = base_color(in.scalar);
    return compose_cells(base, shade(base.rgb, dpx, dpy), cov, extra);
}

@fragment
fn fs_iso_wire(in: IsoOut) -> @location(0) vec4<f32> {
    return shade_iso(in, true);
}

@fragment
fn fs_iso(in: IsoOut) -> @location(0) vec4<f32> {
    return shade_iso(in, false);
}
