//! The reference twist of a node stencil, its value and its exact derivatives in the two
//! tangents, with the reference frames transported in time from the step's frozen frames.
//!
//! The reference twist of node `i` is the angle, about `t^i`, from the space-parallel
//! transport of `a1^{i-1}` to `a1^i`, where each `a1^j` is itself the time-parallel transport
//! of the frozen director from the frozen tangent `tb^j` to `t^j`. Parallel transport around a
//! closed loop on the unit sphere rotates by the enclosed solid angle, so composing the
//! transports gives
//!
//! ```text
//! r(t0, t1) = rb - Omega(tb0, t0, t1) + Omega(tb0, tb1, t1),
//! Omega(a, b, c) = 2 atan2(a . (b x c), 1 + a.b + b.c + c.a)
//! ```
//!
//! (the signed solid angle of the geodesic triangle `a b c`; `rb` the reference twist at the
//! frozen frames). Both terms are `atan2` of a polynomial of degree two in the tangents, so the
//! gradient and Hessian in `(t0, t1)` are short closed forms. The value is computed directly
//! (as [`crate::rod::frames::strains`] does, with its `2 pi` branch), the derivatives from the
//! identity. The fused bending-and-twist stencil ([`super::bend_twist`]) takes the twist from here;
//! the tests compare the Hessian with finite differences of the gradient, and the stencil
//! with the staged jets on random, strongly bent stencils.

use super::jet::Jet;
use crate::rod::vec3::f;

/// The reference twist's gradient and Hessian in the tangents `(t0, t1)` (6 variables), with
/// the frozen tangents `tb0`, `tb1`.
#[inline(always)]
pub fn ref_twist_tangent_derivatives(
    t0: [f64; 3],
    t1: [f64; 3],
    tb0: [f64; 3],
    tb1: [f64; 3],
) -> ([f64; 6], [[f64; 6]; 6]) {
    // -Omega(tb0, t0, t1): n = tb0 . (t0 x t1), d = 1 + tb0.t0 + t0.t1 + t1.tb0, as jets
    // over (t0, t1) (the atan2's chain rule is the jets').
    let dn0 = f::cross(t1, tb0);
    let dn1 = f::cross(tb0, t0);
    let mut n1 = Jet::<6>::cst(f::dot(tb0, f::cross(t0, t1)));
    let mut d1 = Jet::<6>::cst(1.0 + f::dot(tb0, t0) + f::dot(t0, t1) + f::dot(t1, tb0));
    // d2 n / dt0 dt1 = -[tb0]x (so that dn/dt0 = t1 x tb0 = -tb0 x t1), and its transpose;
    // d2 d / dt0 dt1 = I.
    let skew = [
        [0.0, -tb0[2], tb0[1]],
        [tb0[2], 0.0, -tb0[0]],
        [-tb0[1], tb0[0], 0.0],
    ];
    for i in 0..3 {
        n1.g[i] = dn0[i];
        n1.g[3 + i] = dn1[i];
        d1.g[i] = tb0[i] + t1[i];
        d1.g[3 + i] = tb0[i] + t0[i];
        for j in 0..3 {
            n1.h[i][3 + j] = -skew[i][j];
            n1.h[3 + j][i] = -skew[i][j];
        }
        d1.h[i][3 + i] = 1.0;
        d1.h[3 + i][i] = 1.0;
    }
    let w1 = n1.atan2_derivatives(&d1);
    // +Omega(tb0, tb1, t1): n = (tb0 x tb1) . t1, d = 1 + tb0.tb1 + tb1.t1 + t1.tb0, over t1.
    let c = f::cross(tb0, tb1);
    let mut n2 = Jet::<3>::cst(f::dot(c, t1));
    let mut d2 = Jet::<3>::cst(1.0 + f::dot(tb0, tb1) + f::dot(tb1, t1) + f::dot(t1, tb0));
    n2.g = c;
    d2.g = f::add(tb1, tb0);
    let w2 = n2.atan2_derivatives(&d2);
    let mut g = w1.g.map(|x| -2.0 * x);
    let mut h = w1.h.map(|row| row.map(|x| -2.0 * x));
    for i in 0..3 {
        g[3 + i] += 2.0 * w2.g[i];
        for j in 0..3 {
            h[3 + i][3 + j] += 2.0 * w2.h[i][j];
        }
    }
    (g, h)
}

/// The reference twist's gradient alone in the tangents `(t0, t1)`: that of
/// [`ref_twist_tangent_derivatives`], from `d atan2(n, d) = (d dn - n dd) / (n^2 + d^2)`.
#[inline(always)]
pub fn ref_twist_tangent_gradient(
    t0: [f64; 3],
    t1: [f64; 3],
    tb0: [f64; 3],
    tb1: [f64; 3],
) -> [f64; 6] {
    // -Omega(tb0, t0, t1) over (t0, t1).
    let (dn0, dn1) = (f::cross(t1, tb0), f::cross(tb0, t0));
    let n1 = f::dot(tb0, f::cross(t0, t1));
    let d1 = 1.0 + f::dot(tb0, t0) + f::dot(t0, t1) + f::dot(t1, tb0);
    let (dd0, dd1) = (f::add(tb0, t1), f::add(tb0, t0));
    let s1 = -2.0 / (n1 * n1 + d1 * d1);
    // +Omega(tb0, tb1, t1) over t1.
    let c = f::cross(tb0, tb1);
    let n2 = f::dot(c, t1);
    let d2 = 1.0 + f::dot(tb0, tb1) + f::dot(tb1, t1) + f::dot(t1, tb0);
    let dd2 = f::add(tb1, tb0);
    let s2 = 2.0 / (n2 * n2 + d2 * d2);
    std::array::from_fn(|k| {
        if k < 3 {
            s1 * (d1 * dn0[k] - n1 * dd0[k])
        } else {
            let i = k - 3;
            s1 * (d1 * dn1[i] - n1 * dd1[i]) + s2 * (d2 * c[i] - n2 * dd2[i])
        }
    })
}

/// The reference twist's value, as [`crate::rod::frames::strains`] computes it: the angle
/// about `t^i` from the space-parallel transport of `a1^{i-1}` to `a1^i`, on the `2 pi` branch
/// nearest the previous step's `prev`.
pub fn ref_twist_value(t: [[f64; 3]; 2], a1: [[f64; 3]; 2], prev: f64) -> f64 {
    let u = f::transport(t[0], t[1], a1[0]);
    let r = f::dot(f::cross(u, a1[1]), t[1]).atan2(f::dot(u, a1[1]));
    let two_pi = std::f64::consts::TAU;
    let k = ((prev - r) / two_pi).round();
    if k != 0.0 {
        r + k * two_pi
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The solid-angle identity's Hessian against central differences of its gradient.
    #[test]
    fn ref_twist_tangent_hessian_matches_finite_differences() {
        let unit = |v: [f64; 3]| f::scale(v, 1.0 / f::norm(v));
        let t0 = unit([0.3, -0.8, 0.5]);
        let t1 = unit([-0.2, -0.9, 0.6]);
        let tb0 = unit([0.1, -1.0, 0.2]);
        let tb1 = unit([0.0, -0.7, 0.8]);
        let (_, h) = ref_twist_tangent_derivatives(t0, t1, tb0, tb1);
        let eps = 1e-6;
        for k in 0..6 {
            let shift = |s: f64| {
                let mut x = [t0[0], t0[1], t0[2], t1[0], t1[1], t1[2]];
                x[k] += s;
                ref_twist_tangent_derivatives([x[0], x[1], x[2]], [x[3], x[4], x[5]], tb0, tb1).0
            };
            let (gp, gm) = (shift(eps), shift(-eps));
            for i in 0..6 {
                let fd = (gp[i] - gm[i]) / (2.0 * eps);
                assert!(
                    (fd - h[i][k]).abs() <= 1e-6 * (1.0 + h[i][k].abs()),
                    "H[{i}][{k}] {} vs {fd}",
                    h[i][k]
                );
            }
        }
    }
}
