//! Small vector arithmetic on joint points and positions, shared by decimation, the
//! fit and the stitch.

use crate::quadric::Point;

/// `a - b` in position only.
#[inline]
pub(super) fn sub3(a: &Point, b: &Point) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The position part of a joint point.
#[inline]
pub(super) fn spatial(x: &Point) -> [f64; 3] {
    [x[0], x[1], x[2]]
}

/// `a - b`.
#[inline]
pub(crate) fn sub3p(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The cross product `u x v`.
#[inline]
pub(crate) fn cross3(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

/// The dot product `u . v`.
#[inline]
pub(crate) fn dot3(u: [f64; 3], v: [f64; 3]) -> f64 {
    u[0] * v[0] + u[1] * v[1] + u[2] * v[2]
}
