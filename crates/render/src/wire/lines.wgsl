
// ---- lines.wgsl: shared by the techniques that draw edges (bias, dist, idbuffer) ----

// Hidden-line style of the pipeline (Rossignac & van Emmerik): contour edges only
// (CEHS/CEHD), and whether this pass draws the hidden edges, dashed (TEHD/CEHD).
override CONTOURS: bool = false;
override HIDDEN: bool = false;

// Length in pixels of a dash and of the gap after it.
const DASH_PX: f32 = 5.0;
// Distance beyond the opaque core at which exp2(-2 x^2) is one half.
const HALF_POINT: f32 = 0.70710678;
// "No vertex" (the far side of an outline edge), as lines.rs writes it.
const NO_VERTEX: u32 = 0xffffffffu;

// Window coordinates (pixels, y down, pixel centres at .5) of a clip position with w > 0:
// those of @builtin(position) in fragment shaders.
fn window(c: vec4<f32>) -> vec2<f32> {
    let ndc = c.xy / c.w;
    return vec2<f32>((0.5 + 0.5 * ndc.x) * frame.viewport.x, (0.5 - 0.5 * ndc.y) * frame.viewport.y);
}

// Clip offset that moves a clip position by `px` pixels in the window.
fn clip_offset(px: vec2<f32>, w: f32) -> vec4<f32> {
    return vec4<f32>(2.0 * px.x * frame.viewport.z * w, -2.0 * px.y * frame.viewport.w * w, 0.0, 0.0);
}

// Corner q (0 1 2 3 = (a, -), (b, -), (b, +), (a, +)) of a screen-aligned quad along
// segment a b (clip positions in front of the near plane): from `across.x` to
// `across.y` pixels along the window direction `side`, and lengthened by `ends.x` and
// `ends.y` pixels past a and b. The corners' depths are extrapolated along the segment,
// where window depth is affine, so that the quad's depth along the segment is the
// edge's own; moving the ends in x and y alone would stretch the edge's depth over the
// longer quad and sink its near half into the surface.
fn segment_quad_corner(a: vec4<f32>, b: vec4<f32>, q: u32, side: vec2<f32>, across: vec2<f32>, ends: vec2<f32>) -> vec4<f32> {
    let pa = window(a);
    let pb = window(b);
    let len = length(pb - pa);
    let along = select(vec2<f32>(1.0, 0.0), (pb - pa) / len, len > 1.0e-6);
    let at_b = q == 1u || q == 2u;
    let past = select(-ends.x, ends.y, at_b);
    let c = select(a, b, at_b);
    let za = a.z / a.w;
    let zb = b.z / b.w;
    let z = select(za, zb, at_b) + past * (zb - za) / max(len, 1.0e-6);
    let offset = clip_offset(past * along + select(across.x, across.y, q >= 2u) * side, c.w);
    return vec4<f32>(c.xy + offset.xy, select(z, c.z / c.w, len <= 1.0e-6) * c.w, c.w);
}

// Corner q of the quad around segment a b, lengthened and widened by `reach` pixels
// (Bærentzen et al.'s equation 4).
fn quad_corner(a: vec4<f32>, b: vec4<f32>, q: u32, reach: f32) -> vec4<f32> {
    let d = window(b) - window(a);
    let along = select(vec2<f32>(1.0, 0.0), normalize(d), length(d) > 1.0e-6);
    let side = vec2<f32>(-along.y, along.x);
    return segment_quad_corner(a, b, q, side, vec2<f32>(-reach, reach), vec2<f32>(reach));
}

// Facing of the triangle a b c, from its clip positions: the sign is the winding on
// screen, valid even when a vertex is behind the eye (homogeneous orientation).
fn facing(a: vec4<f32>, b: vec4<f32>, c: vec4<f32>) -> f32 {
    return dot(a.xyw, cross(b.xyw, c.xyw));
}

// Whether edge a b is a contour edge: on the outline (no second triangle), or on the
// silhouette, where its two triangles (a b o0 and b a o1) face opposite ways, i.e. the
// opposite vertices lie on the same side of the edge.
fn is_contour(a: vec4<f32>, b: vec4<f32>, o0: vec4<f32>, o1: vec4<f32>, outline: bool) -> bool {
    return outline || facing(a, b, o0) * facing(a, b, o1) > 0.0;
}

// Half the line thickness in pixels at world point wp, thinned by thickness
// attenuation, and the intensity factor of intensity attenuation (common.wgsl curves).
fn line_half(wp: vec3<f32>) -> vec2<f32> {
    let a = depth_fraction(wp);
    var half = 0.5 * frame.line.x;
    var intensity = 1.0;
    if frame.atten.z == 2.0 {
        half = max(0.25, half * thickness_factor(a));
    } else if frame.atten.z == 1.0 {
        intensity = intensity_factor(a);
    }
    return vec2<f32>(half, intensity);
}

// Bærentzen's intensity I(x) = exp2(-2 x^2), with x the distance beyond the line's
// opaque core as Gateau maps it, so that the intensity is one half at `half` pixels
// from the edge and a line is 2 half pixels wide at half intensity.
fn falloff(d: f32, half: f32) -> f32 {
    let x = max(d - half + HALF_POINT, 0.0);
    return exp2(-2.0 * x * x);
}

// Exact box-filtered coverage of a pixel at distance d from the centre of a line of
// half width `half` (the prefiltered quads of `bias`).
fn box_coverage(d: f32, half: f32) -> f32 {
    return clamp(min(d + 0.5, half) - max(d - 0.5, -half), 0.0, 1.0);
}

// Distance from p to the segment a b (round ends).
fn segment_distance(p: vec2<f32>, a: vec2<f32>, b: vec2<f32>) -> f32 {
    let ab = b - a;
    let t = clamp(dot(p - a, ab) / max(dot(ab, ab), 1.0e-12), 0.0, 1.0);
    return length(p - (a + t * ab));
}

// 1 on the dashes of a line running along unit direction `dir`, 0 in the gaps: dashes
// of DASH_PX pixels measured along the line in the window, so they keep their length
// at any zoom.
fn dash(p: vec2<f32>, dir: vec2<f32>) -> f32 {
    // One orientation per line: the two triangles along an edge may see it either way,
    // and opposite phases would fill each other's gaps.
    let d = select(dir, -dir, dir.x < 0.0 || (dir.x == 0.0 && dir.y < 0.0));
    return select(0.0, 1.0, fract(dot(p, d) / (2.0 * DASH_PX)) < 0.5);
}

// Colour of line coverage `cov` drawn over what is already in the frame: the wire
// colour, or in isolation the primitive's own colour.
fn line_color(scalar: f32, cov: f32) -> vec4<f32> {
    if frame.line.w > 0.5 {
        return vec4<f32>(base_color(scalar).rgb, cov);
    }
    return vec4<f32>(frame.wire_color.rgb, cov * frame.wire_color.a);
}

// Fraction of its distance from the eye by which a line drawn as geometry over a
// surface (fault traces, outline edges) is drawn nearer, so that it passes the depth
// test on the surface it lies on (and on the neighbouring surface its quad reaches
// across) without sinking into it at grazing angles; the vertex moves along its view
// ray, so it stays on the same pixel.
const EDGE_PULL: f32 = 0.002;

// Clip position of display-frame point p drawn EDGE_PULL nearer.
fn pulled_clip(p: vec3<f32>) -> vec4<f32> {
    let wp = world(p);
    return clip(wp - (wp - frame.eye.xyz) * EDGE_PULL);
}

// Where to put a vertex that must not draw: outside the clip volume.
const CULLED: vec4<f32> = vec4<f32>(2.0, 2.0, 2.0, 1.0);

// Pulled vertex data, at the same place in every technique of this family: positions
// (xyz packed) and per-vertex scalars.
@group(1) @binding(0) var<storage, read> positions: array<f32>;
@group(1) @binding(1) var<storage, read> scalars: array<f32>;

// What lines.rs writes per triangle: `corners` its vertices and, in w, the mask of its
// real edges (bit e: corner e to e + 1; a quad's diagonal is not real); `across` the
// vertex across each edge (NO_VERTEX on the outline) and, in w, its polygon's ID.
struct TriangleRecord {
    corners: vec4<u32>,
    across: vec4<u32>,
}

fn pulled_world(v: u32) -> vec3<f32> {
    return world(vec3<f32>(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u]));
}
