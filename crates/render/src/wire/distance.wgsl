
// ---- distance.wgsl: the single-pass wireframe of Bærentzen et al. (2006, 2008) with
// the handling of vertices behind the eye of Gateau's SolidWireframe (NVIDIA, 2007).
// wgpu has no geometry shader: each vertex pulls its whole triangle from storage
// (`vertex_index / 3` is the triangle, `% 3` the corner) and does the geometry
// shader's per-triangle work for its own corner.

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

@vertex
fn vs_dist(@builtin(vertex_index) vi: u32) -> DistOut {
    let t = vi / 3u;
    let k = vi % 3u;
    let rec = triangles[t];
    var v = array<u32, 3>(rec.corners.x, rec.corners.y, rec.corners.z);
    var c: array<vec4<f32>, 3>;
    for (var i = 0u; i < 3u; i++) {
        c[i] = clip(pulled_world(v[i]));
    }
    let mask = drawn_edges(rec, c);
    var out: DistOut;
    out.dist_w = vec3<f32>(0.0);
    out.position = c[k];
    out.wp = pulled_world(v[k]);
    out.scalar = scalars[v[k]];
    var dist = vec3<f32>(0.0);
    out.lines = 0u;
    out.line_a = vec4<f32>(0.0);
    out.line_b = vec4<f32>(0.0);
    let front = vec3<bool>(in_front(c[0]), in_front(c[1]), in_front(c[2]));
    if all(front) {
        // The easy standard case: the height of corner k over its opposite edge.
        var p = array<vec2<f32>, 3>(window(c[0]), window(c[1]), window(c[2]));
        let a = p[(k + 1u) % 3u] - p[k];
        let b = p[(k + 2u) % 3u] - p[k];
        let h = abs(a.x * b.y - a.y * b.x) / max(length(b - a), 1.0e-12);
        for (var j = 0u; j < 3u; j++) {
            if ((mask >> ((j + 1u) % 3u)) & 1u) == 0u {
                dist[j] = FAR;
            }
        }
        if ((mask >> ((k + 1u) % 3u)) & 1u) != 0u {
            dist[k] = h;
        }
        out.dist_w = dist * c[k].w;
        return out;
    }
    // Gateau's tricky case: corners behind the near plane have no window position, but
    // the visible parts of the edges do; pass them as lines constant over the triangle.
    let n = u32(front.x) + u32(front.y) + u32(front.z);
    if n == 0u {
        return out;
    }
    var lines = 1u;
    if n == 1u {
        // Corner i in front: edges i-j and i-k, both from a = b = corner i.
        let i = select(select(2u, 1u, front.y), 0u, front.x);
        let j = (i + 1u) % 3u;
        let l = (i + 2u) % 3u;
        out.line_a = visible_line(c[i], c[j]);
        out.line_b = visible_line(c[i], c[l]);
        if ((mask >> edge_of(i, j)) & 1u) != 0u && any(out.line_a.zw != vec2<f32>(0.0)) {
            lines |= 2u;
        }
        if ((mask >> edge_of(i, l)) & 1u) != 0u && any(out.line_b.zw != vec2<f32>(0.0)) {
            lines |= 4u;
        }
    } else {
        // Corners i, j in front, l behind: edges i-l and j-l, and i-j whole.
        let l = select(select(2u, 1u, !front.y), 0u, !front.x);
        let i = (l + 1u) % 3u;
        let j = (l + 2u) % 3u;
        out.line_a = visible_line(c[i], c[l]);
        out.line_b = visible_line(c[j], c[l]);
        if ((mask >> edge_of(i, l)) & 1u) != 0u && any(out.line_a.zw != vec2<f32>(0.0)) {
            lines |= 2u;
        }
        if ((mask >> edge_of(j, l)) & 1u) != 0u && any(out.line_b.zw != vec2<f32>(0.0)) {
            lines |= 4u;
        }
        if ((mask >> edge_of(i, j)) & 1u) != 0u {
            lines |= 8u;
        }
    }
    out.lines = lines;
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
