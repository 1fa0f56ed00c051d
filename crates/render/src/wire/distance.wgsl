
// ---- distance.wgsl: the single-pass wireframe of Bærentzen et al. (2006, 2008) with
// the handling of vertices behind the eye of Gateau's SolidWireframe (NVIDIA, 2007).
// wgpu has no geometry shader: a compute prepass does its per-triangle work, one
// invocation per triangle, and writes each corner's clip position and distances; the
// draw (3 T vertices, `vertex_index / 3` the triangle) reads them back. Doing the same
// work in the vertex shader, each vertex pulling its whole triangle, was measured
// slower on llvmpipe / lavapipe (distance.rs; docs/performance.md).

@group(1) @binding(2) var<storage, read> triangles: array<TriangleRecord>;

// Distance given to an edge that is not drawn.
const FAR: f32 = 1.0e6;

struct DistOut {
    @builtin(position) position: vec4<f32>,
    @location(0) wp: vec3<f32>,
    @location(1) scalar: f32,
    // Standard case: component k is the window distance to the edge opposite corner k
    // (edge k + 1), which must be interpolated linearly in the window. Declared
    // `linear` (no perspective correction), llvmpipe and lavapipe interpolate it
    // wrongly in triangles clipped at the viewport's sides where w varies much (whole
    // triangles turned to line near the camera); so it is passed as Bærentzen et al.
    // do where linear interpolation is missing: times the corner's w, perspective
    // interpolated, and multiplied by the interpolated 1 / w (`position.w`) in the
    // fragment, which clipping preserves.
    @location(2) dist_w: vec3<f32>,
    // Gateau's case: 0 in the standard case; else bit 0 set, bits 1, 2, 3 for the
    // lines (a, dir a), (b, dir b) and a-b to measure in the fragment.
    @location(3) @interpolate(flat) lines: u32,
    @location(4) @interpolate(flat) line_a: vec4<f32>,
    @location(5) @interpolate(flat) line_b: vec4<f32>,
}

// Edge index of the corner pair {u, v}: edge e joins corners e and e + 1.
fn edge_of(u: u32, v: u32) -> u32 {
    return select(v, u, (u + 1u) % 3u == v);
}

// A clip position is on the visible side of the near plane (reversed depth: z <= w).
fn in_front(c: vec4<f32>) -> bool {
    return c.z <= c.w;
}

// Where segment a (in front) - b (behind) crosses the near plane.
fn near_crossing(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    let fa = a.z - a.w;
    let fb = b.z - b.w;
    return mix(a, b, fa / (fa - fb));
}

// The window line through in-front corner a along the visible part of edge a - b
// (b behind the near plane): (a, unit direction), or a zero direction when that part
// is shorter than a hundredth of a pixel and the edge bounds nothing visible.
fn visible_line(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    let pa = window(a);
    let d = window(near_crossing(a, b)) - pa;
    let len = length(d);
    if len < 0.01 {
        return vec4<f32>(pa, 0.0, 0.0);
    }
    return vec4<f32>(pa, d / len);
}

// The real edges of triangle t, less those that are not contours in contour styles.
fn drawn_edges(rec: TriangleRecord, corners: array<vec4<f32>, 3>) -> u32 {
    var c = corners;
    var mask = rec.corners.w & 7u;
    if CONTOURS {
        for (var e = 0u; e < 3u; e++) {
            let o = rec.across[e];
            var o1 = c[(e + 2u) % 3u];
            if o != NO_VERTEX {
                o1 = clip(pulled_world(o));
            }
            if !is_contour(c[e], c[(e + 1u) % 3u], c[(e + 2u) % 3u], o1, o == NO_VERTEX) {
                mask &= ~(1u << e);
            }
        }
    }
    return mask;
}

// Gateau's tricky case of a triangle with corners behind the near plane (`front`
// false): they have no window position, but the visible parts of the edges do, passed
// as window lines constant over the triangle. `lines`: bit 0 set, then bits 1, 2, 3
// for the lines (a, dir a), (b, dir b) and a-b that are real edges.
struct Tricky {
    lines: u32,
    a: vec4<f32>,
    b: vec4<f32>,
}

fn tricky_lines(corners: array<vec4<f32>, 3>, front: vec3<bool>, mask: u32) -> Tricky {
    var c = corners;
    var out = Tricky(1u, vec4<f32>(0.0), vec4<f32>(0.0));
    let n = u32(front.x) + u32(front.y) + u32(front.z);
    if n == 1u {
        // Corner i in front: edges i-j and i-l, both from a = b = corner i.
        let i = select(select(2u, 1u, front.y), 0u, front.x);
        let j = (i + 1u) % 3u;
        let l = (i + 2u) % 3u;
        out.a = visible_line(c[i], c[j]);
        out.b = visible_line(c[i], c[l]);
        if ((mask >> edge_of(i, j)) & 1u) != 0u && any(out.a.zw != vec2<f32>(0.0)) {
            out.lines |= 2u;
        }
        if ((mask >> edge_of(i, l)) & 1u) != 0u && any(out.b.zw != vec2<f32>(0.0)) {
            out.lines |= 4u;
        }
    } else if n == 2u {
        // Corners i, j in front, l behind: edges i-l and j-l, and i-j whole.
        let l = select(select(2u, 1u, !front.y), 0u, !front.x);
        let i = (l + 1u) % 3u;
        let j = (l + 2u) % 3u;
        out.a = visible_line(c[i], c[l]);
        out.b = visible_line(c[j], c[l]);
        if ((mask >> edge_of(i, l)) & 1u) != 0u && any(out.a.zw != vec2<f32>(0.0)) {
            out.lines |= 2u;
        }
        if ((mask >> edge_of(j, l)) & 1u) != 0u && any(out.b.zw != vec2<f32>(0.0)) {
            out.lines |= 4u;
        }
        if ((mask >> edge_of(i, j)) & 1u) != 0u {
            out.lines |= 8u;
        }
    }
    return out;
}

// The standard case: what corner k passes, its height over its opposite edge (edge
// k + 1) in component k and 0 in the others, FAR in every component whose edge is not
// drawn.
fn corner_distances(corners: array<vec4<f32>, 3>, mask: u32, k: u32) -> vec3<f32> {
    var c = corners;
    let pk = window(c[k]);
    let a = window(c[(k + 1u) % 3u]) - pk;
    let b = window(c[(k + 2u) % 3u]) - pk;
    let h = abs(a.x * b.y - a.y * b.x) / max(length(b - a), 1.0e-12);
    var dist = vec3<f32>(0.0);
    for (var j = 0u; j < 3u; j++) {
        if ((mask >> ((j + 1u) % 3u)) & 1u) == 0u {
            dist[j] = FAR;
        }
    }
    if ((mask >> ((k + 1u) % 3u)) & 1u) != 0u {
        dist[k] = h;
    }
    return dist;
}

// The triangle's corners in clip space.
fn triangle_clip(rec: TriangleRecord) -> array<vec4<f32>, 3> {
    return array<vec4<f32>, 3>(
        clip(pulled_world(rec.corners.x)),
        clip(pulled_world(rec.corners.y)),
        clip(pulled_world(rec.corners.z)),
    );
}

fn in_front3(corners: array<vec4<f32>, 3>) -> vec3<bool> {
    return vec3<bool>(in_front(corners[0]), in_front(corners[1]), in_front(corners[2]));
}

// The compute prepass: one invocation per triangle writes its three corners (clip
// position; distances times w and, in w, the tricky case's line bits) and, for tricky
// triangles, their two lines after the 6 n corner records.
@group(1) @binding(3) var<storage, read_write> corners_out: array<vec4<f32>>;
@group(1) @binding(4) var<storage, read> corners_in: array<vec4<f32>>;

@compute @workgroup_size(64)
fn cs_dist(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = arrayLength(&triangles);
    let t = id.x;
    if t >= n {
        return;
    }
    let rec = triangles[t];
    var c = triangle_clip(rec);
    let mask = drawn_edges(rec, c);
    let front = in_front3(c);
    if all(front) {
        for (var k = 0u; k < 3u; k++) {
            corners_out[6u * t + 2u * k] = c[k];
            corners_out[6u * t + 2u * k + 1u] = vec4<f32>(corner_distances(c, mask, k) * c[k].w, 0.0);
        }
        return;
    }
    let tricky = tricky_lines(c, front, mask);
    for (var k = 0u; k < 3u; k++) {
        corners_out[6u * t + 2u * k] = c[k];
        corners_out[6u * t + 2u * k + 1u] = vec4<f32>(0.0, 0.0, 0.0, f32(tricky.lines));
    }
    corners_out[6u * n + 2u * t] = tricky.a;
    corners_out[6u * n + 2u * t + 1u] = tricky.b;
}

// Drawing after the prepass: each vertex reads its corner's record.
@vertex
fn vs_dist_prepass(@builtin(vertex_index) vi: u32) -> DistOut {
    let t = vi / 3u;
    let n = arrayLength(&triangles);
    let v = triangles[t].corners[vi % 3u];
    let d = corners_in[2u * vi + 1u];
    var out: DistOut;
    out.position = corners_in[2u * vi];
    out.wp = pulled_world(v);
    out.scalar = scalars[v];
    out.dist_w = d.xyz;
    out.lines = u32(d.w);
    out.line_a = vec4<f32>(0.0);
    out.line_b = vec4<f32>(0.0);
    if out.lines != 0u {
        out.line_a = corners_in[6u * n + 2u * t];
        out.line_b = corners_in[6u * n + 2u * t + 1u];
    }
    return out;
}

// Distance from window point f to the line through p along unit direction dir.
fn line_distance(f: vec2<f32>, p: vec2<f32>, dir: vec2<f32>) -> f32 {
    let q = f - p;
    return abs(q.x * dir.y - q.y * dir.x);
}

// The fragment's distance to the nearest drawn edge, and in Gateau's case that edge's
// direction in the window (for dashes; zero in the standard case).
fn nearest_edge(in: DistOut) -> vec3<f32> {
    if in.lines == 0u {
        let dist = in.dist_w * in.position.w;
        return vec3<f32>(min(dist.x, min(dist.y, dist.z)), 0.0, 0.0);
    }
    let f = in.position.xy;
    var best = vec3<f32>(FAR, 1.0, 0.0);
    if (in.lines & 2u) != 0u {
        best = vec3<f32>(line_distance(f, in.line_a.xy, in.line_a.zw), in.line_a.zw);
    }
    if (in.lines & 4u) != 0u {
        let d = line_distance(f, in.line_b.xy, in.line_b.zw);
        if d < best.x {
            best = vec3<f32>(d, in.line_b.zw);
        }
    }
    if (in.lines & 8u) != 0u {
        let ab = in.line_b.xy - in.line_a.xy;
        let dir = ab / max(length(ab), 1.0e-12);
        let d = line_distance(f, in.line_a.xy, dir);
        if d < best.x {
            best = vec3<f32>(d, dir);
        }
    }
    return best;
}

// Direction in the window of the edge nearest the fragment in the standard case: the
// distance to an edge grows across it, so the edge runs perpendicular to the gradient
// of its distance. `gx`, `gy`: the derivatives of `dist`.
fn edge_direction(dist: vec3<f32>, gx: vec3<f32>, gy: vec3<f32>) -> vec2<f32> {
    var k = 0u;
    if dist.y < dist[k] {
        k = 1u;
    }
    if dist.z < dist[k] {
        k = 2u;
    }
    let g = vec2<f32>(gx[k], gy[k]);
    return vec2<f32>(-g.y, g.x) / max(length(g), 1.0e-12);
}

@fragment
fn fs_dist(in: DistOut) -> @location(0) vec4<f32> {
    let dpx = dpdx(in.wp);
    let dpy = dpdy(in.wp);
    let edge = nearest_edge(in);
    let hw = line_half(in.wp);
    let base = base_color(in.scalar);
    return compose(base, shade(base.rgb, dpx, dpy), falloff(edge.x, hw.x) * hw.y);
}

// The hidden pass of TEHD/CEHD: the polygons behind the visible surface, drawing only
// their edges, dashed, over the frame.
@fragment
fn fs_dist_hidden(in: DistOut) -> @location(0) vec4<f32> {
    // Derivatives first: they need uniform control flow.
    let dist = in.dist_w * in.position.w;
    let gx = dpdx(dist);
    let gy = dpdy(dist);
    let edge = nearest_edge(in);
    var dir = edge.yz;
    if in.lines == 0u {
        dir = edge_direction(dist, gx, gy);
    }
    let hw = line_half(in.wp);
    return line_color(in.scalar, falloff(edge.x, hw.x) * hw.y * dash(in.position.xy, dir));
}
