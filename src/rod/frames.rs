//! Reference and material frames, and the discrete strains of one interior node.
//!
//! Each edge `j` carries a reference director `a1^j` that is parallel-transported in *time*
//! (Bergou et al. 2010): during a step the reference director of the new tangent `t^j` is
//! `P(t^j_old -> t^j) a1^j_old`, a smooth function of the node positions. The material frame
//! is the reference frame rotated by the twist angle `theta^j` about the tangent:
//! `d1 = cos(theta) a1 + sin(theta) a2`, `d2 = -sin(theta) a1 + cos(theta) a2`,
//! `a2 = t x a1`, `d3 = t`.
//!
//! At interior node `i` (between edges `i-1` and `i`) the curvature binormal is
//! `kb = 2 e^{i-1} x e^i / (|e^{i-1}||e^i| + e^{i-1}.e^i)`; the integrated bending strains are
//! its components in the averaged material frame, `kappa_1 = kb.(d1^{i-1}+d1^i)/2` (bending
//! about `d1`: out of the ground plane for a snake at rest) and `kappa_2 = kb.(d2^{i-1}+d2^i)/2`
//! (bending about `d2`: within the ground plane). The integrated twist is
//! `m_i = theta^i - theta^{i-1} + r_i` with the reference twist `r_i`, the signed angle about
//! `t^i` from `P(t^{i-1} -> t^i) a1^{i-1}` to `a1^i`, unwrapped next to its previous value.

use super::vec3::{f, transport, V3};
use num_dual::DualNum;

/// Parameters of one interior-node stencil that are frozen during a step: the two edges'
/// tangents and reference directors at the start of the step and the previous reference twist.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StencilFrame {
    /// Unit tangents of edges `i-1` and `i` at the start of the step.
    pub t_old: [[f64; 3]; 2],
    /// Reference directors `a1` of edges `i-1` and `i` at the start of the step.
    pub a1_old: [[f64; 3]; 2],
    /// Reference twist at the start of the step (rad), for unwrapping.
    pub ref_twist_prev: f64,
}

/// Integrated discrete strains at an interior node.
#[derive(Clone, Debug)]
pub struct Strains<T> {
    /// `[kappa_1, kappa_2]`: bending about `d1` and about `d2` (dimensionless, integrated).
    pub kappa: [T; 2],
    /// Integrated twist `m_i` (rad).
    pub twist: T,
}

/// Material directors `(d1, d2)` of an edge from its tangent, reference director and angle.
pub fn material<T: DualNum<Primitive = f64>>(t: &V3<T>, a1: &V3<T>, theta: &T) -> (V3<T>, V3<T>) {
    let a2 = t.cross(a1);
    let (s, c) = theta.sin_cos();
    let d1 = a1.scale(&c).add(&a2.scale(&s));
    let d2 = a2.scale(&c).sub(&a1.scale(&s));
    (d1, d2)
}

/// Reference director of an edge with current tangent `t`, transported from the frozen frame.
pub fn reference<T: DualNum<Primitive = f64>>(
    t_old: [f64; 3],
    a1_old: [f64; 3],
    t: &V3<T>,
) -> V3<T> {
    transport(&V3::lift(t_old), t, &V3::lift(a1_old))
}

/// Signed angle about `t` from `u` to `w` (both perpendicular to `t`).
pub fn signed_angle<T: DualNum<Primitive = f64>>(u: &V3<T>, w: &V3<T>, t: &V3<T>) -> T {
    let s = u.cross(w).dot(t);
    let c = u.dot(w);
    s.atan2(c)
}

/// Discrete strains of the stencil with edge vectors `e0 = e^{i-1}`, `e1 = e^i` and twist
/// angles `th0`, `th1`.
pub fn strains<T: DualNum<Primitive = f64>>(
    e0: &V3<T>,
    e1: &V3<T>,
    th0: &T,
    th1: &T,
    p: &StencilFrame,
) -> Strains<T> {
    let n0 = e0.norm();
    let n1 = e1.norm();
    let t0 = e0.scale(&n0.recip());
    let t1 = e1.scale(&n1.recip());
    let a0 = reference(p.t_old[0], p.a1_old[0], &t0);
    let a1 = reference(p.t_old[1], p.a1_old[1], &t1);
    let (d1a, d2a) = material(&t0, &a0, th0);
    let (d1b, d2b) = material(&t1, &a1, th1);
    let denom = n0 * n1 + e0.dot(e1);
    let kb = e0.cross(e1).scale(&(denom.recip() * 2.0));
    let k1 = kb.dot(&d1a.add(&d1b)) * 0.5;
    let k2 = kb.dot(&d2a.add(&d2b)) * 0.5;
    let u = transport(&t0, &t1, &a0);
    let mut r = signed_angle(&u, &a1, &t1);
    let two_pi = std::f64::consts::TAU;
    let k = ((p.ref_twist_prev - r.re()) / two_pi).round();
    if k != 0.0 {
        r += k * two_pi;
    }
    let twist = th1.clone() - th0.clone() + r;
    Strains {
        kappa: [k1, k2],
        twist,
    }
}

/// Plain-number reference twist of a stencil for the current positions (used to update the
/// frozen frame after a step).
pub fn ref_twist(e0: [f64; 3], e1: [f64; 3], p: &StencilFrame) -> f64 {
    let s = strains::<f64>(&V3(e0), &V3(e1), &0.0, &0.0, p);
    s.twist
}

/// A unit director perpendicular to the unit tangent `t`: horizontal (`e_z x t`) when the
/// tangent is not vertical, so that `d2 = t x d1` points up for a rod lying on the ground.
pub fn initial_director(t: [f64; 3]) -> [f64; 3] {
    let h = f::cross([0.0, 0.0, 1.0], t);
    if f::norm(h) > 1e-8 {
        f::unit(h)
    } else {
        f::unit(f::cross(t, [1.0, 0.0, 0.0]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_rod_has_no_strain_and_d2_up() {
        let t = [-1.0, 0.0, 0.0];
        let a = initial_director(t);
        let p = StencilFrame {
            t_old: [t, t],
            a1_old: [a, a],
            ref_twist_prev: 0.0,
        };
        let s = strains::<f64>(&V3([-0.1, 0.0, 0.0]), &V3([-0.1, 0.0, 0.0]), &0.3, &0.5, &p);
        assert!(s.kappa[0].abs() < 1e-15 && s.kappa[1].abs() < 1e-15);
        assert!((s.twist - 0.2).abs() < 1e-15);
        let (d1, d2) = material(&V3(t), &V3(a), &0.0);
        assert!((d2.0[2] - 1.0).abs() < 1e-15, "d2 must point up: {:?}", d2);
        assert!(d1.0[2].abs() < 1e-15);
    }

    #[test]
    fn in_plane_bend_is_kappa2() {
        // Bending within the ground plane (z = const) rotates about d2 (vertical).
        let t0 = [-1.0, 0.0, 0.0];
        let a = initial_director(t0);
        let ang: f64 = 0.2;
        let t1 = [-ang.cos(), ang.sin(), 0.0];
        let a1 = initial_director(t1);
        let p = StencilFrame {
            t_old: [t0, t1],
            a1_old: [a, a1],
            ref_twist_prev: 0.0,
        };
        let s = strains::<f64>(&V3(t0), &V3(t1), &0.0, &0.0, &p);
        assert!(s.kappa[0].abs() < 1e-14);
        assert!((s.kappa[1].abs() - 2.0 * (ang / 2.0).tan()).abs() < 1e-14);
    }
}
