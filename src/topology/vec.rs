//! Small vector helpers on `[f64; 3]`.

use super::*;

#[inline(always)]
pub(super) fn sub(a: &V3, b: &V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
pub(super) fn add(a: &V3, b: &V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[inline(always)]
pub(super) fn scale(a: &V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

#[inline(always)]
pub(super) fn dot(a: &V3, b: &V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
pub(super) fn cross(a: &V3, b: &V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline(always)]
pub(super) fn norm(a: &V3) -> f64 {
    dot(a, a).sqrt()
}

/// Unit vector along `a`, or `None` if `a` is zero (or not finite).
#[inline(always)]
pub(super) fn unit(a: &V3) -> Option<V3> {
    let l = norm(a);
    if l > 0.0 && l.is_finite() {
        Some(scale(a, 1.0 / l))
    } else {
        None
    }
}

/// Unit vector along `a`, or the zero vector if `a` is zero.
#[inline(always)]
pub(super) fn unit_or_zero(a: &V3) -> V3 {
    unit(a).unwrap_or([0.0; 3])
}

/// Component of `u` perpendicular to the unit vector `t`.
#[inline(always)]
pub(super) fn reject(u: &V3, t: &V3) -> V3 {
    sub(u, &scale(t, dot(u, t)))
}

/// Some unit vector perpendicular to the unit vector `t` (deterministic).
pub(super) fn any_perpendicular(t: &V3) -> V3 {
    let (ax, ay, az) = (t[0].abs(), t[1].abs(), t[2].abs());
    let e = if ax <= ay && ax <= az {
        [1.0, 0.0, 0.0]
    } else if ay <= az {
        [0.0, 1.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    };
    unit(&cross(t, &e)).unwrap_or([1.0, 0.0, 0.0])
}
