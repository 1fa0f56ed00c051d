// Texture-based wireframe (Celes & Abraham): lines are drawn while rasterizing the
// polygons, by mapping the wireframe texture with coordinates that reach an odd value
// on the edges to draw.
//  - vs_uv + fs_uv: two families from a 2D coordinate, lines at odd values with
//    mirrored-repeat addressing: `global` (node (i, j) at (2i + 1, 2j + 1));
//  - vs_quad + fs_quad: the same from per-quad -1 / +1 (`quad`);
//  - vs_tex3 + fs_tex3: three families, one per triangle edge, the edge where a
//    coordinate reaches 1: `tex` (per-vertex labels);
// The techniques with coordinates of their own also carry the global ones, from which
// major lines are drawn (local_cells in common.wgsl).
//  - vs_texgs + fs_tex3: the same coordinates made per triangle from the corner
//    index while pulling vertices from storage (`texgs`: wgpu has no geometry shader).

// `iso`: the isoline coordinate of `scalar` (line_coordinate).
struct UvOut {
    @builtin(position) position: vec4<f32>,
    @location(0) wp: vec3<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) scalar: f32,
    @location(3) iso: f32,
}

// `uv`: the global coordinates, for major lines (local_cells).
struct Tex3Out {
    @builtin(position) position: vec4<f32>,
    @location(0) wp: vec3<f32>,
    @location(1) s: vec3<f32>,
    @location(2) scalar: f32,
    @location(3) iso: f32,
    @location(4) uv: vec2<f32>,
}

// Gradient length of one coordinate, in coordinate units per pixel.
fn grad_len(dx: f32, dy: f32) -> f32 {
    return length(vec2<f32>(dx, dy));
}

@vertex
fn vs_uv(@location(0) p: vec3<f32>, @location(1) uv: vec2<f32>, @location(2) scalar: f32) -> UvOut {
    let wp = world(p);
    return UvOut(clip(wp), wp, uv, scalar, line_coordinate(scalar));
}

@fragment
fn fs_shaded(in: UvOut) -> @location(0) vec4<f32> {
    let base = base_color(in.scalar);
    let extra = extra_lines(in.wp, in.iso, depth_fraction(in.wp));
    return compose_lines(base, shade(base.rgb, dpdx(in.wp), dpdy(in.wp)), 0.0, extra);
}

@fragment
fn fs_uv(in: UvOut) -> @location(0) vec4<f32> {
    return uv_colour(in, in.scalar, in.iso, true);
}

// `quad`: per-quad coordinates `uv` (-1 / +1 on opposite sides) and the global ones,
// for major lines (local_cells).
struct QuadOut {
    @builtin(position) position: vec4<f32>,
    @location(0) wp: vec3<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) scalar: f32,
    @location(3) iso: f32,
    @location(4) global: vec2<f32>,
}

@vertex
fn vs_quad(@location(0) p: vec3<f32>, @location(1) uv: vec2<f32>, @location(2) scalar: f32, @location(3) global: vec2<f32>) -> QuadOut {
    let wp = world(p);
    return QuadOut(clip(wp), wp, uv, scalar, line_coordinate(scalar), global);
}

@fragment
fn fs_quad(in: QuadOut) -> @location(0) vec4<f32> {
    let du = dpdx(in.uv);
    let dv = dpdy(in.uv);
    let a = depth_fraction(in.wp);
    let local = union2(coverage(in.uv.x, grad_len(du.x, dv.x), a), coverage(in.uv.y, grad_len(du.y, dv.y), a));
    let base = base_color(in.scalar);
    let extra = extra_lines(in.wp, in.iso, a);
    return compose_cells(base, shade(base.rgb, dpdx(in.wp), dpdy(in.wp)), local_cells(local, in.global, a), extra);
}

// The surface coloured by `colour_scalar`, with `wire` under the two line families of
// `in.uv`; isolines follow the line coordinate `iso`.
fn uv_colour(in: UvOut, colour_scalar: f32, iso: f32, wire: bool) -> vec4<f32> {
    let dpx = dpdx(in.wp);
    let dpy = dpdy(in.wp);
    let du = dpdx(in.uv);
    let dv = dpdy(in.uv);
    let a = depth_fraction(in.wp);
    var cov = vec2<f32>(0.0);
    if wire {
        cov = global_cells(in.uv, du, dv, a);
    }
    let base = base_color(colour_scalar);
    let extra = extra_lines(in.wp, iso, a);
    return compose_cells(base, shade(base.rgb, dpx, dpy), cov, extra);
}

// Cells of the surfaces a decimated one was simplified from (strata-lod's CellCover),
// for a batch of consecutive pieces: the batch's first piece, then nine words per
// piece (first cell x and y as i32, cells across and down, index of its first bit word,
// indices of its tile tables of cell values and of corner values or NO_VALUES, and the
// side in cells of the square tiles of each, cut from its box's first cell), then the
// bits, then the value tiles and values, then the corner tiles and corner values. A
// tile table holds, per tile of the box, row by row, the index of the tile's first
// value or NO_VALUES; a tile's values are, per cell row by row, one f32 (cell values)
// or four (the field at the cell's corners (0, 0), (1, 0), (1, 1), (0, 1)). All in a
// texture read as a flat array.
@group(1) @binding(4) var cover_words: texture_2d<u32>;

const NO_VALUES: u32 = 0xffffffffu;

struct CoverOut {
    @builtin(position) position: vec4<f32>,
    @location(0) wp: vec3<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) scalar: f32,
    @location(3) iso: f32,
    @location(4) @interpolate(flat) piece: u32,
}

fn cover_word(i: u32) -> u32 {
    let w = textureDimensions(cover_words).x;
    return textureLoad(cover_words, vec2<u32>(i % w, i / w), 0).x;
}

// Where `piece`'s nine header words start.
fn piece_header(piece: u32) -> u32 {
    return 1u + 9u * (piece - cover_word(0u));
}

// Where the values of `cell` (its place in the box of the piece whose header is at `h`)
// start, `per_cell` to a cell, in the field whose tile table is header word `field`
// (5: cell values, 6: corner values, their tile sides two words on); NO_VALUES
// where the piece or the cell's tile has none.
fn cell_values(h: u32, field: u32, cell: u32, per_cell: u32) -> u32 {
    let table = cover_word(h + field);
    if table == NO_VALUES {
        return NO_VALUES;
    }
    let size = vec2<u32>(cover_word(h + 2u), cover_word(h + 3u));
    let side = cover_word(h + field + 2u);
    let at = vec2<u32>(cell % size.x, cell / size.x);
    let tile = at / side;
    let first = cover_word(table + tile.y * ((size.x - 1u) / side + 1u) + tile.x);
    if first == NO_VALUES {
        return NO_VALUES;
    }
    let lo = tile * side;
    let across = min(side, size.x - lo.x);
    return first + per_cell * ((at.y - lo.y) * across + at.x - lo.x);
}

// The place in `piece`'s box of the cell of global coordinates `uv` (node (i, j) at
// (2i + 1, 2j + 1)), or -1 where the piece does not cover that cell.
fn covered_cell(piece: u32, uv: vec2<f32>) -> i32 {
    let h = piece_header(piece);
    let cell = vec2<i32>(floor((uv - vec2<f32>(1.0)) * 0.5));
    let rel = cell - vec2<i32>(bitcast<i32>(cover_word(h)), bitcast<i32>(cover_word(h + 1u)));
    let size = vec2<i32>(i32(cover_word(h + 2u)), i32(cover_word(h + 3u)));
    if any(rel < vec2<i32>(0)) || any(rel >= size) {
        return -1;
    }
    let bit = u32(rel.y) * u32(size.x) + u32(rel.x);
    if ((cover_word(cover_word(h + 4u) + bit / 32u) >> (bit % 32u)) & 1u) == 0u {
        return -1;
    }
    return i32(bit);
}

// The scalar that colours a fragment: its cell's value where the piece covers the cell
// and has values there, as the original's cell faces are painted; else the
// interpolated one.
fn cell_scalar(piece: u32, cell: i32, interpolated: f32) -> f32 {
    if cell < 0 {
        return interpolated;
    }
    let v = cell_values(piece_header(piece), 5u, u32(cell), 1u);
    if v == NO_VALUES {
        return interpolated;
    }
    return bitcast<f32>(cover_word(v));
}

// The isoline coordinate at global coordinates `uv` in `cell` of `piece`: the
// original's field, linear on each half of the cell face split along its (0, 0)-(1, 1)
// diagonal as the original's triangles are, undefined outside its cells; the
// interpolated coordinate where the piece, or the cell's tile of its box, has no corner
// values. The corners go through iso_coordinate before the interpolation, as vertices
// do (line_coordinate).
fn cell_iso(piece: u32, cell: i32, uv: vec2<f32>, interpolated: f32) -> f32 {
    let h = piece_header(piece);
    if cover_word(h + 6u) == NO_VALUES {
        return interpolated;
    }
    if cell < 0 {
        return ISO_UNDEFINED;
    }
    let c = cell_values(h, 6u, u32(cell), 4u);
    if c == NO_VALUES {
        return interpolated;
    }
    let f = vec4<f32>(
        bitcast<f32>(cover_word(c)),
        bitcast<f32>(cover_word(c + 1u)),
        bitcast<f32>(cover_word(c + 2u)),
        bitcast<f32>(cover_word(c + 3u)),
    );
    if any(f <= vec4<f32>(UNDEFINED_SCALAR)) {
        return ISO_UNDEFINED;
    }
    // s at the corners (0, 0), (1, 0), (1, 1), (0, 1).
    let s = vec4<f32>(iso_coordinate(f.x), iso_coordinate(f.y), iso_coordinate(f.z), iso_coordinate(f.w));
    let t = clamp(fract((uv - vec2<f32>(1.0)) * 0.5), vec2<f32>(0.0), vec2<f32>(1.0));
    if t.x >= t.y {
        return s.x + t.x * (s.y - s.x) + t.y * (s.z - s.y);
    }
    return s.x + t.y * (s.w - s.x) + t.x * (s.z - s.w);
}

// Least |z| of a view ray's direction that a push is divided by: along a ray that
// grazes the layers, a vertex moves at most twenty times its push.
const PUSH_MIN_DZ: f32 = 0.05;

// `push`: how far lower (seen from above, x) or higher (seen from below, y) the
// vertex's surface is depth tested (strata-render's `Stacking`). The vertex moves
// along its view ray, which keeps it on the same pixel, by what takes it that far
// vertically; the fragment keeps its true position for shading.
@vertex
fn vs_uv_cover(@location(0) p: vec3<f32>, @location(1) uv: vec2<f32>, @location(2) scalar: f32, @location(3) piece: u32, @location(5) push: vec2<f32>) -> CoverOut {
    let wp = world(p);
    let ray = normalize(wp - frame.eye.xyz);
    let vertical = select(push.x, push.y, ray.z > 0.0);
    let tested = select(wp, wp + ray * (vertical / max(abs(ray.z), PUSH_MIN_DZ)), vertical > 0.0);
    // Pushed past the far plane, at it (reversed depth: 0), rather than clipped away.
    var position = clip(tested);
    position.z = max(position.z, 0.0);
    return CoverOut(position, wp, uv, scalar, line_coordinate(scalar), piece);
}

// A fragment of a decimated surface in `cell` of the original's (-1: none): its
// cell's colour, the original's isolines and, with `wire`, the global wireframe.
fn cell_colour(in: CoverOut, cell: i32, wire: bool) -> vec4<f32> {
    let surface = UvOut(in.position, in.wp, in.uv, in.scalar, in.iso);
    return uv_colour(surface, cell_scalar(in.piece, cell, in.scalar), cell_iso(in.piece, cell, in.uv, in.iso), wire);
}

// cell_colour drawn only over the cells of the original surface: a decimated surface
// whose outlines grew outward (strata-lod's `Options::cover`) loses what it gained, and
// its outlines, holes and fault traces are the original's. The colour is found before
// the discard, which would leave the derivatives it takes outside uniform control flow.
fn covered_colour(in: CoverOut, wire: bool) -> vec4<f32> {
    let cell = covered_cell(in.piece, in.uv);
    let colour = cell_colour(in, cell, wire);
    if cell < 0 {
        discard;
    }
    return colour;
}

// The global wireframe over the original's cells only.
@fragment
fn fs_uv_cover(in: CoverOut) -> @location(0) vec4<f32> {
    return covered_colour(in, true);
}

// fs_uv_cover without the wireframe.
@fragment
fn fs_uv_cover_bare(in: CoverOut) -> @location(0) vec4<f32> {
    return covered_colour(in, false);
}

// The global wireframe over a decimated surface, coloured cell by cell where the
// original has the cell, with nothing discarded.
@fragment
fn fs_uv_cells(in: CoverOut) -> @location(0) vec4<f32> {
    return cell_colour(in, covered_cell(in.piece, in.uv), true);
}

// fs_uv_cells without the wireframe.
@fragment
fn fs_uv_cells_bare(in: CoverOut) -> @location(0) vec4<f32> {
    return cell_colour(in, covered_cell(in.piece, in.uv), false);
}

@vertex
fn vs_tex3(@location(0) p: vec3<f32>, @location(1) s: vec3<f32>, @location(2) scalar: f32, @location(3) uv: vec2<f32>) -> Tex3Out {
    let wp = world(p);
    return Tex3Out(clip(wp), wp, s, scalar, line_coordinate(scalar), uv);
}

@fragment
fn fs_tex3(in: Tex3Out) -> @location(0) vec4<f32> {
    let dpx = dpdx(in.wp);
    let dpy = dpdy(in.wp);
    let dsx = dpdx(in.s);
    let dsy = dpdy(in.s);
    let a = depth_fraction(in.wp);
    let c0 = coverage(in.s.x, grad_len(dsx.x, dsy.x), a);
    let c1 = coverage(in.s.y, grad_len(dsx.y, dsy.y), a);
    let c2 = coverage(in.s.z, grad_len(dsx.z, dsy.z), a);
    let base = base_color(in.scalar);
    let extra = extra_lines(in.wp, in.iso, a);
    let cov = local_cells(union2(union2(c0, c1), c2), in.uv, a);
    return compose_cells(base, shade(base.rgb, dpx, dpy), cov, extra);
}

// Vertex pulling for texgs: positions (xyz packed), scalars, the index buffer, and per
// triangle seven words: the mask of real edges (bit e: edge from corner e to corner
// e + 1; a quad's diagonal is not real and is never drawn), then its corners' global
// coordinates as f32 bits, for major lines (in one buffer: the downlevel limit is four
// storage buffers in a vertex shader).
@group(1) @binding(0) var<storage, read> pulled_positions: array<f32>;
@group(1) @binding(1) var<storage, read> pulled_scalars: array<f32>;
@group(1) @binding(2) var<storage, read> pulled_indices: array<u32>;
@group(1) @binding(3) var<storage, read> pulled_triangles: array<u32>;

@vertex
fn vs_texgs(@builtin(vertex_index) vi: u32) -> Tex3Out {
    let corner = vi % 3u;
    let v = pulled_indices[vi];
    let p = vec3<f32>(pulled_positions[3u * v], pulled_positions[3u * v + 1u], pulled_positions[3u * v + 2u]);
    let record = 7u * (vi / 3u);
    let mask = pulled_triangles[record];
    let uv = vec2<f32>(
        bitcast<f32>(pulled_triangles[record + 1u + 2u * corner]),
        bitcast<f32>(pulled_triangles[record + 2u + 2u * corner]),
    );
    // Family c draws the edge opposite corner c, i.e. edge (c + 1) % 3: it is 1 at the
    // two other corners and 0 at corner c, or 0 everywhere when that edge is not real.
    var s = vec3<f32>(1.0, 1.0, 1.0);
    s[corner] = 0.0;
    for (var c = 0u; c < 3u; c++) {
        if ((mask >> ((c + 1u) % 3u)) & 1u) == 0u {
            s[c] = 0.0;
        }
    }
    let wp = world(p);
    let scalar = pulled_scalars[v];
    return Tex3Out(clip(wp), wp, s, scalar, line_coordinate(scalar), uv);
}
