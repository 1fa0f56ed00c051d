// Shared by every technique: the frame uniforms, shading, and the coverage of a pixel
// by the line at the nearest odd value of a coordinate, from a mip-mapped texture
// (Celes & Abraham) or evaluated analytically from the coordinate's gradient.

struct Frame {
    view_proj: mat4x4<f32>,
    // xyz: eye in the exaggerated display frame; w: vertical exaggeration.
    eye: vec4<f32>,
    // xyz: unit direction towards the light; w: ambient fraction.
    light: vec4<f32>,
    wire_color: vec4<f32>,
    solid_color: vec4<f32>,
    // width, height, 1 / width, 1 / height.
    viewport: vec4<f32>,
    // x: thickness in pixels; y: saturation cap (fraction of a coordinate unit);
    // z: 1 analytic coverage, 0 texture; w: 1 lines in isolation, 0 over the surface.
    line: vec4<f32>,
    // x: near distance; y: 1 / (far - near); z: 0 none, 1 intensity, 2 thickness;
    // w: number of attenuation layers in the wireframe texture.
    atten: vec4<f32>,
    // x: scalar at the colour map's start; y: 1 / range; z: 1 colour by scalar;
    // w: the scale (scale.rs), 0 linear, 1 log (x, y of ln values), 2 categorical
    // (x: the palette's length).
    scalar: vec4<f32>,
    // Isolines (isoline.rs): x: 2 / spacing; y: offset (a line's value); z: every
    // z-th line is major (0: none); w: 1 drawn, 0 not.
    iso: vec4<f32>,
    // Isoline colour; alpha scales major lines, half of it minor ones.
    iso_color: vec4<f32>,
    // Map grid lines (gridlines.rs): x, y: offsets added to the display frame's x and
    // y; z: 2 / spacing; w: 1 drawn, 0 not.
    grid: vec4<f32>,
    grid_color: vec4<f32>,
    // Major cell lines (cell_lines): x: every x-th cell line is major, and every x^2-th
    // too (0: none, every line is drawn alike); y: on-screen spacing in pixels at
    // which a level of lines is gone.
    major: vec4<f32>,
    major_color: vec4<f32>,
    // Fault traces (faults.rs): x: thickness in pixels, 0: not drawn.
    faults: vec4<f32>,
    fault_color: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var wire_tex: texture_2d_array<f32>;
@group(0) @binding(2) var wire_sampler: sampler;
@group(0) @binding(3) var colormap: texture_2d<f32>;
@group(0) @binding(4) var colormap_sampler: sampler;

// Scalars below this are "undefined" (the CPU writes -3.0e38 for NaN, since NaN
// comparisons are not reliable across shader compilers).
const UNDEFINED_SCALAR: f32 = -1.0e38;

fn world(p: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(p.xy, p.z * frame.eye.w);
}

fn clip(wp: vec3<f32>) -> vec4<f32> {
    return frame.view_proj * vec4<f32>(wp, 1.0);
}

// 0 at the near end of the scene, 1 at the far end.
fn depth_fraction(wp: vec3<f32>) -> f32 {
    return clamp((distance(wp, frame.eye.xyz) - frame.atten.x) * frame.atten.y, 0.0, 1.0);
}

// The attenuation curves; the wireframe texture's layers are built from the same ones.
fn intensity_factor(a: f32) -> f32 {
    return 1.0 - 0.85 * a;
}

fn thickness_factor(a: f32) -> f32 {
    return 1.0 - 0.65 * a;
}

// Length of the lines of period `period` (starting at 0, `width` long) in [0, t].
fn periodic_lines(t: f32, period: f32, width: f32) -> f32 {
    return floor(t / period) * width + min(t - period * floor(t / period), width);
}

// Mean coverage of a box `box_width` px wide centred `d` px from the nearest of the
// lines `period` px apart and `2 half` px wide: every line the box reaches counts.
fn box_lines(d: f32, half: f32, period: f32, box_width: f32) -> f32 {
    // The box's start, measured from the start of the nearest line's period.
    let lo = d + half - 0.5 * box_width + period;
    let covered = periodic_lines(lo + box_width, period, 2.0 * half) - periodic_lines(lo, period, 2.0 * half);
    return clamp(covered / box_width, 0.0, 1.0);
}

// Coverage of a pixel by the lines at the odd values of x. `grad` is |grad x| in
// coordinate units per pixel: the distance in pixels is the distance in units over
// it, and the half width is capped to `cap` units so that lines never cover more than
// that fraction of small cells (no saturation). The filter is a one-pixel box where
// cells (the lines' period P) are 8 px or more. Below, lines slanted across the pixel
// rows alias into moire through it, so it turns into a two-pixel box by P = 4 (a blend
// of the two: both, and so the blend, cancel the integer frequencies that alias onto
// the mean), and into a box of P itself below 2 px (the flat mean).
fn coverage_analytic(x: f32, grad: f32, a: f32) -> f32 {
    let g = max(grad, 1.0e-12);
    var half = 0.5 * frame.line.x;
    var intensity = 1.0;
    if frame.atten.z == 2.0 {
        half = max(0.25, half * thickness_factor(a));
    } else if frame.atten.z == 1.0 {
        intensity = intensity_factor(a);
    }
    half = min(half, frame.line.y / g);
    let period = 2.0 / g;
    let d = (x - (2.0 * floor(0.5 * x) + 1.0)) / g;
    let narrow = box_lines(d, half, period, min(period, 1.0));
    let wide = box_lines(d, half, period, min(period, 2.0));
    return mix(narrow, wide, clamp(2.0 - 0.25 * period, 0.0, 1.0)) * intensity;
}

// The same coverage from the mip-mapped wireframe texture (wire_texture.rs: each level
// holds the pixel-filtered half line at two texels per pixel). The level is chosen
// from the full gradient of this coordinate alone, not from the larger per-axis
// derivative the hardware would use, which would make diagonal lines up to sqrt(2)
// too thick; and one level is sampled, never two blended:
//  - where the line keeps its thickness (half * grad <= cap, cells at least
//    thickness / cap pixels wide), the finest level whose texels are at most half a
//    pixel, with the distance to the line rescaled so that they are exactly half a
//    pixel. Trilinear filtering would blend the line of level L (thickness texels)
//    with that of level L + 1 (twice as wide in pixels): the half-coverage edge then
//    wanders by up to a third of the thickness between levels and the line is thinned
//    near the cap where level L + 1 is already capped. Rescaling also keeps the
//    thickness under magnification (cells wider than the texture at 2 texels/pixel);
//  - where the cap applies, the finest level whose texels are at least half a pixel,
//    unscaled: every such level is capped, so its line edge is exactly at `cap`
//    units, filtered over 1 to 2 pixels; its mean over a cell stays at most the cap
//    (no saturation) however small the cells get.
fn coverage_texture(x: f32, grad: f32, a: f32) -> f32 {
    let layers = frame.atten.w;
    let layer = i32(round(a * (layers - 1.0)));
    let g = max(grad, 1.0e-12);
    // The layer's thickness, as wire_texture.rs builds it.
    var half = 0.5 * frame.line.x;
    if frame.atten.z == 2.0 {
        half = max(0.25, half * thickness_factor(f32(layer) / max(layers - 1.0, 1.0)));
    }
    let top = f32(textureNumLevels(wire_tex) - 1u);
    // log2 of the texels per pixel of level 0, less one: level `lod` has two texels
    // per pixel.
    let lod = log2(g * f32(textureDimensions(wire_tex, 0).x)) - 1.0;
    let odd = 2.0 * floor(0.5 * x) + 1.0;
    if half * g <= frame.line.y {
        let level = clamp(floor(lod), 0.0, top);
        let d = clamp((x - odd) * exp2(level - lod), -1.0, 1.0);
        return textureSampleLevel(wire_tex, wire_sampler, vec2<f32>(odd + d, 0.5), layer, level).a;
    }
    let level = clamp(ceil(lod), 0.0, top);
    return textureSampleLevel(wire_tex, wire_sampler, vec2<f32>(x, 0.5), layer, level).a;
}

// Which coverage a pipeline evaluates: 0 the texture, 1 analytic, 2 the one the frame
// uniform names. The texture techniques build a pipeline per form (wire/mod.rs,
// `texture_pipelines`) so that each shader holds one form: llvmpipe and lavapipe pay
// for code under a uniform branch even when it is not taken. On lavapipe a shader
// with both forms was measured much slower than one with one form, and even the
// shaded-only frame paid for the texture taps in its (disabled) isoline and grid-line
// branches (docs/performance.md, "Wireframe techniques").
override COVERAGE_FORM: u32 = 2u;

fn coverage(x: f32, grad: f32, a: f32) -> f32 {
    if COVERAGE_FORM == 1u || (COVERAGE_FORM == 2u && frame.line.z > 0.5) {
        return coverage_analytic(x, grad, a);
    }
    return coverage_texture(x, grad, a);
}

// Opacity of a level of lines `spacing` px apart: none at the fade spacing, full at
// three times it. Linear in the spacing, so that the level's mean coverage (about
// opacity x thickness / spacing) still grows as one zooms in all the way to full
// strength; a smoothstep would flatten near the top and let it fall.
fn line_fade(spacing: f32) -> f32 {
    let gone = frame.major.y;
    return clamp((spacing - gone) / (2.0 * gone), 0.0, 1.0);
}

// Whether the line index `index` is a multiple of `n` (floats hold these exactly).
fn is_multiple(index: f32, n: f32) -> bool {
    return abs(index - n * round(index / n)) < 0.5;
}

// N^level for the levels 0, 1 and 2 (exact, where pow need not be).
fn level_scale(level: f32, n: f32) -> f32 {
    return select(select(1.0, n, level > 0.5), n * n, level > 1.5);
}

// Coverage of a pixel by the cell lines of the global coordinate `x` (odd on every
// line, two units per cell, `grad` units per pixel), as (minor, major). With major
// lines every N cells, lines form three levels: every cell (0), every N (1) and every
// N^2 (2, never faded). The finest level whose lines are more than the fade spacing
// apart is drawn, each line with the opacity of the coarsest level it belongs to, so
// the nearest line alone is evaluated, once, whatever the level: a texture tap or an
// analytic evaluation per family as without major lines. A line of a coarser level
// than the finest drawn is evaluated in that level's own coordinate (x - 1) / N^l + 1,
// with the saturation cap of its own spacing: where the cell lines are gone, the major
// lines keep their full width. The level changes per pixel with the gradient, so the
// near and far parts of an oblique view each get theirs; at a change, the lines of
// the finer level are at zero opacity, so nothing pops.
fn cell_lines(x: f32, grad: f32, a: f32) -> vec2<f32> {
    let n = frame.major.x;
    if n < 1.5 {
        return vec2<f32>(coverage(x, grad, a), 0.0);
    }
    let cell_px = 2.0 / max(grad, 1.0e-12);
    var level = 0.0;
    if cell_px <= frame.major.y {
        level = select(1.0, 2.0, n * cell_px <= frame.major.y);
    }
    // The nearest line of that level, and the coarsest level it belongs to.
    let index = floor(0.5 * ((x - 1.0) / level_scale(level, n) + 1.0));
    var rank = level;
    if level < 2.0 && is_multiple(index, n) {
        rank = select(level + 1.0, 2.0, level < 1.0 && is_multiple(index, n * n));
    }
    let scale = level_scale(rank, n);
    let c = coverage((x - 1.0) / scale + 1.0, grad / scale, a);
    let w = c * select(line_fade(scale * cell_px), 1.0, rank > 1.5);
    return select(vec2<f32>(w, 0.0), vec2<f32>(0.0, w), rank > 0.5);
}

// The global wireframe's coverage as (minor, major) at global coordinates `uv`, whose
// screen derivatives are `du` and `dv`: both line families of cell_lines, united.
fn global_cells(uv: vec2<f32>, du: vec2<f32>, dv: vec2<f32>, a: f32) -> vec2<f32> {
    let cu = cell_lines(uv.x, length(vec2<f32>(du.x, dv.x)), a);
    let cv = cell_lines(uv.y, length(vec2<f32>(du.y, dv.y)), a);
    return vec2<f32>(union2(cu.x, cv.x), union2(cu.y, cv.y));
}

// The wire of the techniques with coordinates of their own (quad, tex, texgs), as
// (minor, major): `local` is their coverage of the cell edges. With major lines, those
// come from the global coordinates `uv` (cell_lines) and `local` draws the others,
// faded as the denser family of cell lines fades, and only where it covers more than
// the major line: on a major line it is that line, which must not count twice.
fn local_cells(local: f32, uv: vec2<f32>, a: f32) -> vec2<f32> {
    if frame.major.x < 1.5 {
        return vec2<f32>(local, 0.0);
    }
    let du = dpdx(uv);
    let dv = dpdy(uv);
    let gu = length(vec2<f32>(du.x, dv.x));
    let gv = length(vec2<f32>(du.y, dv.y));
    let major = union2(cell_lines(uv.x, gu, a).y, cell_lines(uv.y, gv, a).y);
    let minor = local * line_fade(2.0 / max(max(gu, gv), 1.0e-12));
    // Over the major line's colour, the share of the minor line's that brings the
    // total to `minor` (compose_cells).
    let over = select(0.0, (minor - major) / max(1.0 - major, 1.0e-6), minor > major);
    return vec2<f32>(over, major);
}

// Union of two line families' coverages.
fn union2(a: f32, b: f32) -> f32 {
    return 1.0 - (1.0 - a) * (1.0 - b);
}

fn base_color(scalar: f32) -> vec4<f32> {
    if frame.scalar.z > 0.5 {
        if scalar < UNDEFINED_SCALAR {
            return vec4<f32>(0.55, 0.55, 0.55, 1.0);
        }
        if frame.scalar.w > 1.5 {
            // Categorical: the code's texel, never a blend of two.
            let n = i32(frame.scalar.x);
            let code = i32(round(scalar));
            return textureLoad(colormap, vec2<i32>(((code % n) + n) % n, 0), 0);
        }
        var v = scalar;
        if frame.scalar.w > 0.5 {
            if scalar <= 0.0 {
                return vec4<f32>(0.55, 0.55, 0.55, 1.0);
            }
            v = log(scalar);
        }
        let u = clamp((v - frame.scalar.x) * frame.scalar.y, 0.0, 1.0);
        return textureSampleLevel(colormap, colormap_sampler, vec2<f32>(u, 0.5), 0.0);
    }
    return frame.solid_color;
}

// Two-sided diffuse lighting with the flat normal of the fragment's facet.
fn shade(base: vec3<f32>, dpx: vec3<f32>, dpy: vec3<f32>) -> vec3<f32> {
    let n = normalize(cross(dpx, dpy));
    let diffuse = abs(dot(n, frame.light.xyz));
    return base * (frame.light.w + (1.0 - frame.light.w) * diffuse);
}

// Final colour: lines over the shaded surface, or in isolation with the primitive's
// own colour over a transparent interior.
fn compose(base: vec4<f32>, lit: vec3<f32>, cov: f32) -> vec4<f32> {
    if frame.line.w > 0.5 {
        return vec4<f32>(base.rgb, cov);
    }
    return vec4<f32>(mix(lit, frame.wire_color.rgb, cov * frame.wire_color.a), 1.0);
}

// Lines decoupled from the mesh (Celes & Abraham 2011 section 6): isolines of a
// scalar and map grid lines, with the wireframe's coverage, so that they keep its
// thickness in pixels. The scalar goes through the texture matrix to the coordinate
// s = 2 (f - offset) / spacing + 1, odd on the isolines; the isoline technique
// (isoline.rs) passes its range-adjusted s instead.
fn iso_coordinate(scalar: f32) -> f32 {
    return (scalar - frame.iso.y) * frame.iso.x + 1.0;
}

// The isoline coordinate of a scalar that may be undefined.
const ISO_UNDEFINED: f32 = -3.0e38;

// iso_coordinate, or ISO_UNDEFINED for an undefined scalar. Computed per vertex and
// interpolated, as the papers' texture matrix does: the interpolation then rounds s,
// a few line periods, not the scalar itself (a depth of 2000 m on a 10 m spacing is
// 200 periods from zero, and rounds about that much coarser).
fn line_coordinate(f: f32) -> f32 {
    return select(ISO_UNDEFINED, iso_coordinate(f), f > UNDEFINED_SCALAR);
}

// Isolines of the line coordinate `s` (none where it is undefined) and grid lines at
// the display-frame position `wp`, as a premultiplied colour and its coverage. Major
// isolines (every frame.iso.z-th, counted from the offset) are drawn at full opacity,
// the others at half: one texture serves both.
fn extra_lines(wp: vec3<f32>, s: f32, a: f32) -> vec4<f32> {
    if !EXTRA_LINES {
        return vec4<f32>(0.0);
    }
    return extra_lines_floored(wp, s, a, 0.0);
}

// Whether a pipeline draws isolines and grid lines at all. The texture techniques
// build pipelines without them for frames that have none (wire/mod.rs,
// `texture_pipelines`), for the reason of COVERAGE_FORM: the CPU rasterizers paid for
// the disabled branches, texture taps included, in every frame (measured on
// lavapipe; docs/performance.md, "Wireframe techniques").
override EXTRA_LINES: bool = true;

// How far interpolation rounds a line coordinate, relative to its magnitude: the
// perspective-correct interpolation of three equal corners gives their value back
// only to about 16 units in the last place. This is twice the least tolerance that left
// planes flat at a line's value without line pixels, measured on llvmpipe and lavapipe at a
// grazing angle (tests/isolines.rs; docs/performance.md, "Isolines"). Where the coordinate
// changes less than this per pixel the field is flat: the next line would be tens of
// thousands of pixels away, and none could be placed to a pixel.
const ISO_NOISE: f32 = 4.0e-6;

// extra_lines with the isolines' gradient floored at `min_grad` units per pixel (the
// isoline technique's way of sampling as the paper does, see isoline.wgsl).
fn extra_lines_floored(wp: vec3<f32>, s: f32, a: f32, min_grad: f32) -> vec4<f32> {
    // Derivatives only under the uniform switches: frames without these lines pay
    // nothing for them.
    var iso = 0.0;
    if frame.iso.w > 0.5 {
        let grad = length(vec2<f32>(dpdx(s), dpdy(s)));
        let ds = max(grad, min_grad);
        // The nearest line is 2 floor(s / 2) + 1, the floor(s / 2)-th from the offset.
        let index = floor(0.5 * s);
        let every = frame.iso.z;
        let major = every < 1.5 || abs(index - every * round(index / every)) < 0.5;
        // A flat patch of the field (a triangle with three equal corners) lying on a
        // line's value is not a line: it is left clear, and the line is drawn where
        // the field leaves that value, by the sloping neighbours.
        if s > UNDEFINED_SCALAR && grad > ISO_NOISE * abs(s) {
            iso = coverage(s, ds, a) * frame.iso_color.a * select(0.5, 1.0, major);
        }
    }
    var grid = 0.0;
    if frame.grid.w > 0.5 {
        let k = frame.grid.z;
        let dx = length(vec2<f32>(dpdx(wp.x), dpdy(wp.x))) * k;
        let dy = length(vec2<f32>(dpdx(wp.y), dpdy(wp.y))) * k;
        let gx = coverage((wp.x + frame.grid.x) * k + 1.0, dx, a);
        let gy = coverage((wp.y + frame.grid.y) * k + 1.0, dy, a);
        grid = union2(gx, gy) * frame.grid_color.a;
    }
    // Grid lines over isolines.
    let rgb = frame.grid_color.rgb * grid + frame.iso_color.rgb * iso * (1.0 - grid);
    return vec4<f32>(rgb, union2(iso, grid));
}

// compose() with lines decoupled from the mesh laid over the wireframe: `extra` is
// extra_lines' premultiplied colour and coverage.
fn compose_lines(base: vec4<f32>, lit: vec3<f32>, cov: f32, extra: vec4<f32>) -> vec4<f32> {
    return compose_cells(base, lit, vec2<f32>(cov, 0.0), extra);
}

// compose_lines with the wire's coverage as (minor, major) (cell_lines): major lines in
// their own colour over the minor ones.
fn compose_cells(base: vec4<f32>, lit: vec3<f32>, cov: vec2<f32>, extra: vec4<f32>) -> vec4<f32> {
    if frame.line.w > 0.5 {
        return vec4<f32>(base.rgb, union2(union2(cov.x, cov.y), extra.a));
    }
    let minor = mix(lit, frame.wire_color.rgb, cov.x * frame.wire_color.a);
    let wired = mix(minor, frame.major_color.rgb, cov.y * frame.major_color.a);
    return vec4<f32>(wired * (1.0 - extra.a) + extra.rgb, 1.0);
}
