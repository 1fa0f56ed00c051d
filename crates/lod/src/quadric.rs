//! Generalized quadric error metrics in the joint space of position and attributes
//! (Garland & Heckbert, "Simplifying surfaces with color and texture using quadric
//! error metrics", 1998).
//!
//! A vertex is a point of R⁶: the three position coordinates (z scaled by the view's
//! vertical exaggeration) and the two global texture coordinates and the scalar, each
//! scaled into length units. A triangle spans a plane of R⁶; its quadric gives the
//! squared distance of any point to that plane. Summed over the triangles around a
//! vertex, the quadric measures how far a replacement point moves the surface *and*
//! how far it moves the grid lines across it: on a flat layer whose cells are not
//! parallelograms, the texture coordinates are not affine in position, and only the
//! attribute part sees that a large triangle would bend the drawn grid lines.
//!
//! Values are `f64`: quadric coefficients are sums of squares of coordinates and lose
//! everything in `f32` long before the errors we rank are small.

/// Dimension of the joint space: position (3), texture coordinates (2), scalar (1).
pub(crate) const DIM: usize = 6;
/// Stored coefficients of the symmetric `DIM x DIM` matrix (upper triangle).
const SYM: usize = DIM * (DIM + 1) / 2;

/// A point of the joint space.
pub(crate) type Point = [f64; DIM];

/// Index of `(i, j)`, `i <= j`, in the packed upper triangle.
const fn packed(i: usize, j: usize) -> usize {
    i * DIM - i * (i + 1) / 2 + j
}

/// `x ↦ xᵀ A x + 2 bᵀ x + c`, with `w` the total weight (area) summed in, so that
/// `value / w` is a mean squared distance in length units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Quadric {
    a: [f64; SYM],
    b: [f64; DIM],
    c: f64,
    pub w: f64,
}

/// A vertex's quadric as kept between collapses: written around the vertex's own
/// joint point, in single precision. Around the point its coefficients are of the
/// size of the errors themselves (a triangle's or boundary plane's quadric is zero,
/// with zero gradient, at a corner of it), so `f32` holds them; written around the
/// frame's origin they are sums of squared coordinates, which need `f64`. Half the
/// bytes per vertex: the quadrics are most of the memory a decimation touches, and
/// on a generated 2000 x 2000 layer page faults took much of its time
/// (`docs/performance.md`, "Decimation internals").
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Local {
    a: [f32; SYM],
    b: [f32; DIM],
    c: f32,
    w: f32,
}

impl Local {
    /// Adds `q`, a [`Quadric::through`] this quadric's point.
    pub fn add_through(&mut self, q: &Local) {
        self.a.iter_mut().zip(&q.a).for_each(|(x, y)| *x += y);
        self.w += q.w;
    }

    /// The quadric in double precision, around the point it is kept around.
    #[inline]
    pub fn widened(&self) -> Quadric {
        Quadric {
            a: self.a.map(f64::from),
            b: self.b.map(f64::from),
            c: f64::from(self.c),
            w: f64::from(self.w),
        }
    }

    /// This quadric plus `other`, both written around this one's point, which is
    /// `offset` from `other`'s, in double precision: `other`'s part becomes
    /// `d ↦ dᵀ A d + 2 (A e + b)ᵀ d + eᵀ A e + 2 bᵀ e + c` with `e = offset`. The sum
    /// of a collapse's two ends in one go, without a copy of either: it is formed
    /// for every edge of every pass.
    #[inline]
    pub fn plus_moved(&self, other: &Local, offset: &Point) -> Quadric {
        let moved = other.widened();
        let ae = moved.apply(offset);
        Quadric {
            a: std::array::from_fn(|k| f64::from(self.a[k]) + moved.a[k]),
            b: std::array::from_fn(|k| f64::from(self.b[k]) + moved.b[k] + ae[k]),
            c: f64::from(self.c) + moved.c + dot(offset, &ae) + 2.0 * dot(&moved.b, offset),
            w: f64::from(self.w) + moved.w,
        }
    }
}

#[inline]
pub(crate) fn dot(x: &Point, y: &Point) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

impl Quadric {
    /// This quadric around a point where its value and gradient are zero (a corner
    /// of its triangle, a point of its plane): only its second-order part and weight,
    /// narrowed once for the corners it is added to ([`Local::add_through`]).
    pub fn through(&self) -> Local {
        Local {
            a: self.a.map(|x| x as f32),
            w: self.w as f32,
            ..Local::default()
        }
    }

    /// Squared distance to the plane of the triangle `p q r`, times `weight` (its
    /// area). Degenerate triangles give the zero quadric. Inlined: decimation's set-up
    /// adds only its second-order part, and the rest is then never computed (a
    /// measurably faster set-up, `docs/performance.md`).
    #[inline]
    pub fn triangle(p: &Point, q: &Point, r: &Point, weight: f64) -> Quadric {
        let sub = |x: &Point, y: &Point| -> Point { std::array::from_fn(|k| x[k] - y[k]) };
        let mut e1 = sub(q, p);
        let l1 = dot(&e1, &e1).sqrt();
        if l1 <= 0.0 || !l1.is_finite() {
            return Quadric::default();
        }
        e1.iter_mut().for_each(|x| *x /= l1);
        let pr = sub(r, p);
        let along = dot(&e1, &pr);
        let mut e2: Point = std::array::from_fn(|k| pr[k] - along * e1[k]);
        let l2 = dot(&e2, &e2).sqrt();
        if l2 <= 1e-12 * l1 || !l2.is_finite() {
            return Quadric::default();
        }
        e2.iter_mut().for_each(|x| *x /= l2);
        let (pe1, pe2) = (dot(p, &e1), dot(p, &e2));
        let mut out = Quadric {
            w: weight,
            c: weight * (dot(p, p) - pe1 * pe1 - pe2 * pe2),
            ..Quadric::default()
        };
        for i in 0..DIM {
            out.b[i] = weight * (pe1 * e1[i] + pe2 * e2[i] - p[i]);
            for j in i..DIM {
                let identity = if i == j { 1.0 } else { 0.0 };
                out.a[packed(i, j)] = weight * (identity - e1[i] * e1[j] - e2[i] * e2[j]);
            }
        }
        out
    }

    /// Squared distance of the position part to the plane `n · x = d` (`n` a unit
    /// vector), times `weight`; carries no area into `w`. Used along boundary edges,
    /// for a plane through the edge perpendicular to its triangle, so that moving an
    /// outline, hole or fault trace costs what moving it off that line costs.
    pub fn plane(n: [f64; 3], d: f64, weight: f64) -> Quadric {
        let mut out = Quadric {
            c: weight * d * d,
            ..Quadric::default()
        };
        for i in 0..3 {
            out.b[i] = -weight * d * n[i];
            for j in i..3 {
                out.a[packed(i, j)] = weight * n[i] * n[j];
            }
        }
        out
    }

    /// Sums in place; decimation sums as it moves ([`Local::plus_moved`]).
    #[cfg(test)]
    pub fn add(&mut self, o: &Quadric) {
        self.a.iter_mut().zip(&o.a).for_each(|(x, y)| *x += y);
        self.b.iter_mut().zip(&o.b).for_each(|(x, y)| *x += y);
        self.c += o.c;
        self.w += o.w;
    }

    /// The same function written around `origin`: `d ↦ dᵀ A d + 2 b'ᵀ d + c'` with
    /// `d = x - origin`.
    pub fn around(&self, origin: &Point) -> Local {
        let ao = self.apply(origin);
        Local {
            a: self.a.map(|x| x as f32),
            b: std::array::from_fn(|k| (ao[k] + self.b[k]) as f32),
            c: (dot(origin, &ao) + 2.0 * dot(&self.b, origin) + self.c) as f32,
            w: self.w as f32,
        }
    }

    /// `A x`, written out: this product is most of the cost of decimation.
    #[inline]
    pub fn apply(&self, x: &Point) -> Point {
        let a = &self.a;
        [
            a[0] * x[0] + a[1] * x[1] + a[2] * x[2] + a[3] * x[3] + a[4] * x[4] + a[5] * x[5],
            a[1] * x[0] + a[6] * x[1] + a[7] * x[2] + a[8] * x[3] + a[9] * x[4] + a[10] * x[5],
            a[2] * x[0] + a[7] * x[1] + a[11] * x[2] + a[12] * x[3] + a[13] * x[4] + a[14] * x[5],
            a[3] * x[0] + a[8] * x[1] + a[12] * x[2] + a[15] * x[3] + a[16] * x[4] + a[17] * x[5],
            a[4] * x[0] + a[9] * x[1] + a[13] * x[2] + a[16] * x[3] + a[18] * x[4] + a[19] * x[5],
            a[5] * x[0] + a[10] * x[1] + a[14] * x[2] + a[17] * x[3] + a[19] * x[4] + a[20] * x[5],
        ]
    }

    /// The error at the point the quadric is written around (`x = 0`): `c`
    /// normalized. Decimation writes each pair's quadric around one end, so that end
    /// costs no product.
    #[inline]
    pub fn error_at_origin(&self) -> f64 {
        self.normalize(self.c)
    }

    /// [`Quadric::value`] at the point the quadric is written around.
    #[inline]
    pub fn value_at_origin(&self) -> f64 {
        self.c.max(0.0)
    }

    /// What a value is divided by to make it an error: `w`, or 1 when nothing with
    /// an area was summed in. Choices of one quadric compare by value against a tie
    /// times this, and only the chosen one is divided (a division per candidate
    /// placement was a noticeable share of the evaluation of Reek's edges;
    /// `docs/performance.md`).
    #[inline]
    pub fn weight(&self) -> f64 {
        if self.w > 0.0 { self.w } else { 1.0 }
    }

    /// Turns a quadric value into an error (see [`Quadric::error`]).
    #[inline]
    pub fn normalize(&self, value: f64) -> f64 {
        value.max(0.0) / self.weight()
    }

    /// `xᵀ A x + 2 bᵀ x + c`, never negative.
    #[inline]
    pub fn value(&self, x: &Point) -> f64 {
        (dot(x, &self.apply(x)) + 2.0 * dot(&self.b, x) + self.c).max(0.0)
    }

    /// The mean squared distance at `x`: `value / w` (the value itself when nothing
    /// with an area was summed in).
    #[inline]
    pub fn error(&self, x: &Point) -> f64 {
        self.normalize(self.value(x))
    }

    /// This quadric on the plane `J d` through the point it is written around (`J`:
    /// two columns of R⁶), given `A J`. Decimation forms it around an end of the
    /// collapsing edge, where the quadric's gradient is `2 b` and its value `c`,
    /// without a product by `A`.
    #[inline]
    pub fn on_plane(&self, j: &[Point; 2], aj: &[Point; 2]) -> PlaneQuadric {
        PlaneQuadric {
            h: [dot(&j[0], &aj[0]), dot(&j[0], &aj[1]), dot(&j[1], &aj[1])],
            g: std::array::from_fn(|k| dot(&j[k], &self.b)),
            c: self.c,
        }
    }

    /// Minimum over the 3-space `C d` through the point the quadric is written around
    /// (`C`: three columns of R⁶), as `d` and the quadric's value there, given `A C`;
    /// `None` when not well conditioned.
    pub fn minimize_in_space(&self, c: &[Point; 3], ac: &[Point; 3]) -> Option<([f64; 3], f64)> {
        let mut h = [[0f64; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                h[i][j] = dot(&c[i], &ac[j]);
            }
        }
        let g: [f64; 3] = std::array::from_fn(|k| dot(&c[k], &self.b));
        // Cramer's rule on the symmetric 3 x 3 system H d = -g.
        let det3 = |m: &[[f64; 3]; 3]| {
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
        };
        let det = det3(&h);
        let trace = h[0][0] + h[1][1] + h[2][2];
        if !(trace > 0.0 && det > 1e-9 * trace * trace * trace) {
            return None;
        }
        let inv = 1.0 / det;
        let d: [f64; 3] = std::array::from_fn(|k| {
            let mut m = h;
            for (row, gi) in m.iter_mut().zip(&g) {
                row[k] = -gi;
            }
            det3(&m) * inv
        });
        let mut value = self.c;
        for i in 0..3 {
            value += 2.0 * d[i] * g[i];
            for j in 0..3 {
                value += d[i] * d[j] * h[i][j];
            }
        }
        Some((d, value))
    }
}

/// A [`Quadric`] on a plane through the point it is written around, in the plane's
/// own coordinates: `d ↦ dᵀ H d + 2 gᵀ d + c` ([`Quadric::on_plane`]). Where an
/// edge's texture plane is known, the edge lies in it, so the costs of both its ends,
/// of the plane's minimum and of the segment's come from these six numbers, with no
/// further product in the joint space.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PlaneQuadric {
    h: [f64; 3],
    g: [f64; 2],
    c: f64,
}

impl PlaneQuadric {
    /// The quadric's value at `d`, never negative.
    #[inline]
    pub fn value(&self, d: [f64; 2]) -> f64 {
        let h = &self.h;
        (self.c
            + 2.0 * (d[0] * self.g[0] + d[1] * self.g[1])
            + d[0] * d[0] * h[0]
            + 2.0 * d[0] * d[1] * h[1]
            + d[1] * d[1] * h[2])
            .max(0.0)
    }

    /// The minimum, as `d` and the value there; `None` when the quadric is not well
    /// conditioned on the plane (flat along some direction, so the minimum is not
    /// unique).
    #[inline]
    pub fn minimum(&self) -> Option<([f64; 2], f64)> {
        let (h, g) = (&self.h, &self.g);
        let det = h[0] * h[2] - h[1] * h[1];
        let trace = h[0] + h[2];
        if !(trace > 0.0 && det > 1e-9 * trace * trace) {
            return None;
        }
        let inv = 1.0 / det;
        let d = [
            -(h[2] * g[0] - h[1] * g[1]) * inv,
            -(h[0] * g[1] - h[1] * g[0]) * inv,
        ];
        Some((d, self.value(d)))
    }

    /// The minimum over the segment `t e`, `t` in `[0, 1]`, as `t` and the value there.
    #[inline]
    pub fn minimum_on_segment(&self, e: [f64; 2]) -> (f64, f64) {
        let h = e[0] * e[0] * self.h[0] + 2.0 * e[0] * e[1] * self.h[1] + e[1] * e[1] * self.h[2];
        let g = e[0] * self.g[0] + e[1] * self.g[1];
        let t = if h > 0.0 {
            (-g / h).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (t, (self.c + 2.0 * t * g + t * t * h).max(0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(x: f64, y: f64, z: f64, u: f64, v: f64, s: f64) -> Point {
        [x, y, z, u, v, s]
    }

    #[test]
    fn triangle_quadric_is_squared_distance_to_its_plane() {
        let (p, q, r) = (
            pt(0.0, 0.0, 0.0, 1.0, 1.0, 0.0),
            pt(2.0, 0.0, 0.0, 3.0, 1.0, 0.0),
            pt(0.0, 2.0, 0.0, 1.0, 3.0, 0.0),
        );
        let quad = Quadric::triangle(&p, &q, &r, 1.0);
        for x in [p, q, r, pt(0.5, 0.5, 0.0, 1.5, 1.5, 0.0)] {
            assert!(quad.value(&x) < 1e-12, "{x:?} is on the plane");
        }
        // Off the plane by 3 in z, and the texture coordinates off by 4 in u.
        assert!((quad.value(&pt(0.5, 0.5, 3.0, 1.5, 1.5, 0.0)) - 9.0).abs() < 1e-9);
        assert!((quad.value(&pt(0.5, 0.5, 0.0, 5.5, 1.5, 0.0)) - 8.0).abs() < 1e-9);
        assert!((quad.value(&pt(0.5, 0.5, 0.0, 1.5, 1.5, 2.0)) - 4.0).abs() < 1e-9);
    }

    #[test]
    fn a_quadric_kept_around_a_far_corner_measures_what_it_measured() {
        // A corner kilometres from the display origin, cells of 50 m: written around
        // the origin, single precision would lose these errors entirely.
        let o = pt(4_000.0, 7_000.0, -8_000.0, 801.0, 1203.0, 0.2);
        let p = pt(4_050.0, 7_000.0, -8_010.0, 803.0, 1203.0, 0.25);
        let r = pt(4_000.0, 7_050.0, -7_995.0, 801.0, 1205.0, 0.21);
        let (t1, t2) = (
            Quadric::triangle(&o, &p, &r, 1250.0),
            Quadric::triangle(
                &o,
                &r,
                &pt(455_950.0, 6_789_000.0, -1_590.0, 799.0, 1203.0, 0.2),
                1250.0,
            ),
        );
        let mut local = Local::default();
        local.add_through(&t1.through());
        local.add_through(&t2.through());
        let mut exact = t1;
        exact.add(&t2);
        // Written around the frame's origin, and around the neighbouring corner `r`
        // as a collapse of the edge `o r` sees it.
        let moved = |local: &Local, offset: &Point| Local::default().plus_moved(local, offset);
        let minus = |x: &Point| x.map(|c| -c);
        let kept = moved(&local, &minus(&o));
        let from_r = moved(&local, &std::array::from_fn(|k| r[k] - o[k]));
        // Points a cell or two away, off the planes by metres.
        for x in [
            pt(4_020.0, 7_010.0, -8_001.0, 801.8, 1203.4, 0.22),
            pt(3_990.0, 7_030.0, -7_990.0, 800.6, 1204.2, 0.2),
            pt(4_100.0, 6_950.0, -8_050.0, 805.0, 1201.0, 0.3),
        ] {
            let (want, got) = (exact.value(&x), kept.value(&x));
            assert!(want > 1.0, "{x:?} is off the planes");
            assert!((got - want).abs() < 1e-5 * want, "{got} against {want}");
            let near = from_r.value(&std::array::from_fn(|k| x[k] - r[k]));
            assert!((near - want).abs() < 1e-5 * want, "{near} against {want}");
        }
        // Moved to another point and back, through single precision both times:
        // where the value is near zero, the mean squared distance (value / weight)
        // is off by under 1e-5 m².
        let there = moved(&kept.around(&p), &minus(&p));
        for x in [o, p, r] {
            let (want, got) = (exact.value(&x), there.value(&x));
            assert!(
                (got - want).abs() < 1e-5 * want.max(exact.w),
                "{got} against {want}"
            );
        }
    }

    #[test]
    fn minimum_on_a_plane_and_a_segment() {
        // Written around z = 5, as decimation writes a pair's quadric around one end:
        // two planes z = 1 and z = -1 in position only, so the best z is 0.
        let mut quad = Quadric::plane([0.0, 0.0, 1.0], 1.0 - 5.0, 1.0);
        quad.add(&Quadric::plane([0.0, 0.0, 1.0], -1.0 - 5.0, 1.0));
        assert!((quad.error_at_origin() - 52.0).abs() < 1e-9);
        // The plane spanned by x and z: flat along x, so no unique minimum.
        let j = [
            pt(1.0, 0.0, 0.0, 0.0, 0.0, 0.0),
            pt(0.0, 0.0, 1.0, 0.0, 0.0, 0.0),
        ];
        let on_plane = |quad: &Quadric| quad.on_plane(&j, &[quad.apply(&j[0]), quad.apply(&j[1])]);
        // Down z to -5 on the plane: at z = 0 both planes are at distance 1.
        let (t, value) = on_plane(&quad).minimum_on_segment([0.0, -10.0]);
        assert!(
            (t - 0.5).abs() < 1e-12 && (value - 2.0).abs() < 1e-9,
            "{t} {value}"
        );
        assert!((on_plane(&quad).value([0.0, -10.0]) - 52.0).abs() < 1e-9);
        assert!(on_plane(&quad).minimum().is_none());
        // Add x = 2 and the minimum is unique: x = 2, z = 0.
        quad.add(&Quadric::plane([1.0, 0.0, 0.0], 2.0, 1.0));
        let (d, value) = on_plane(&quad).minimum().unwrap();
        assert!(
            (d[0] - 2.0).abs() < 1e-9 && (d[1] + 5.0).abs() < 1e-9,
            "{d:?}"
        );
        assert!(
            (value - 2.0).abs() < 1e-9
                && (value - quad.value(&pt(2.0, 0.0, -5.0, 0.0, 0.0, 0.0))).abs() < 1e-9
        );
        // In space, y the third direction: flat along y until y = 3 is added too.
        let in_space = |quad: &Quadric| {
            let c = [j[0], j[1], pt(0.0, 1.0, 0.0, 0.0, 0.0, 0.0)];
            quad.minimize_in_space(&c, &c.map(|x| quad.apply(&x)))
        };
        assert_eq!(in_space(&quad), None);
        quad.add(&Quadric::plane([0.0, 1.0, 0.0], 3.0, 1.0));
        let (d, value) = in_space(&quad).unwrap();
        assert!(
            (d[0] - 2.0).abs() < 1e-9 && (d[1] + 5.0).abs() < 1e-9 && (d[2] - 3.0).abs() < 1e-9,
            "{d:?}"
        );
        assert!((value - 2.0).abs() < 1e-9, "{value}");
    }
}
