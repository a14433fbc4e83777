//! The bending and twist stencils' value, gradient and Hessian by staged second-order jets
//! ([`crate::energy::jet`]): each edge's frame as a function of its own 3 edge coordinates
//! ([`EdgeJets`]), the curvature binormal's projections and the reference twist over the 6
//! positional coordinates, and the strains over all 8. Exact up to round-off, and tested
//! against the hyper-dual numbers of [`super::autodiff`]; the per-term closed forms
//! ([`super::closed`]) and the fused stencil of real runs ([`crate::energy::bend_twist`]) are
//! tested against these.

use crate::energy::jet::{cross, dot, embed, lift, scale, to_na, transport, Jet, JV};
use crate::energy::stencil::{BendStencil, TwistStencil};
use crate::rod::frames::StencilFrame;
use nalgebra::{SMatrix, SVector};

/// One edge's reference frame as a function of its edge vector `e` (3 variables): length
/// `|e|`, tangent `t`, reference director `a1` transported in time from the frozen frame,
/// and `a2 = t x a1`.
#[derive(Clone, Copy, Debug)]
pub struct EdgeJets {
    /// `|e|`.
    pub len: Jet<3>,
    /// `t = e / |e|`.
    pub t: JV<3>,
    /// Transported reference director `a1`.
    pub a1: JV<3>,
    /// `a2 = t x a1`.
    pub a2: JV<3>,
}

impl EdgeJets {
    /// The frame jets of edge vector `e` with frozen tangent `t_old` and director `a1_old`.
    pub fn new(e: [f64; 3], t_old: [f64; 3], a1_old: [f64; 3]) -> Self {
        let ev: JV<3> = [Jet::var(e[0], 0), Jet::var(e[1], 1), Jet::var(e[2], 2)];
        let len = dot(&ev, &ev).sqrt();
        let t = scale(&ev, &len.recip());
        let a1 = transport(&lift(t_old), &t, &lift(a1_old));
        let a2 = cross(&t, &a1);
        EdgeJets { len, t, a1, a2 }
    }

    /// The jets of both edges of a stencil at `y`.
    pub fn of_stencil(frame: &StencilFrame, y: &[f64; 8]) -> [EdgeJets; 2] {
        [
            EdgeJets::new([y[0], y[1], y[2]], frame.t_old[0], frame.a1_old[0]),
            EdgeJets::new([y[3], y[4], y[5]], frame.t_old[1], frame.a1_old[1]),
        ]
    }
}

impl BendStencil<'_> {
    /// Value, gradient and Hessian in the 8 intrinsic coordinates, by staged jets: each
    /// edge's frame over its own 3 coordinates, the four projections of the curvature
    /// binormal on the reference frames over the 6 positional coordinates, and
    /// `kappa = 1/2 sum_j (cos theta^j (kb.a1^j) + sin theta^j (kb.a2^j), ...)` over all 8.
    /// Equal to [`super::autodiff::derivatives`] of
    /// [`crate::energy::stencil::StencilEnergy::eval`] up to round-off.
    pub fn derivatives(&self, y: [f64; 8]) -> (f64, SVector<f64, 8>, SMatrix<f64, 8, 8>) {
        let [e0, e1] = EdgeJets::of_stencil(self.frame, &y);
        self.derivatives_with([&e0, &e1], &y)
    }

    /// [`Self::derivatives`] with the two edges' frame jets given (shared with the twist
    /// stencil and the neighbouring node).
    pub fn derivatives_with(
        &self,
        edges: [&EdgeJets; 2],
        y: &[f64; 8],
    ) -> (f64, SVector<f64, 8>, SMatrix<f64, 8, 8>) {
        let (n0, a0, b0) = (edges[0].len, edges[0].a1, edges[0].a2);
        let (n1, a1, b1) = (edges[1].len, edges[1].a1, edges[1].a2);
        let e0: JV<6> = [Jet::var(y[0], 0), Jet::var(y[1], 1), Jet::var(y[2], 2)];
        let e1: JV<6> = [Jet::var(y[3], 3), Jet::var(y[4], 4), Jet::var(y[5], 5)];
        let n0: Jet<6> = Jet::embed(&n0, 0);
        let n1: Jet<6> = Jet::embed(&n1, 3);
        let (a0, b0): (JV<6>, JV<6>) = (embed(&a0, 0), embed(&b0, 0));
        let (a1, b1): (JV<6>, JV<6>) = (embed(&a1, 3), embed(&b1, 3));
        let denom = n0 * n1 + dot(&e0, &e1);
        let kb = scale(&cross(&e0, &e1), &(denom.recip() * 2.0));
        let p0: Jet<8> = Jet::embed(&dot(&kb, &a0), 0);
        let q0: Jet<8> = Jet::embed(&dot(&kb, &b0), 0);
        let p1: Jet<8> = Jet::embed(&dot(&kb, &a1), 0);
        let q1: Jet<8> = Jet::embed(&dot(&kb, &b1), 0);
        let (s0, c0) = Jet::<8>::var(y[6], 6).sin_cos();
        let (s1, c1) = Jet::<8>::var(y[7], 7).sin_cos();
        let k1 = (c0 * p0 + s0 * q0 + c1 * p1 + s1 * q1) * 0.5;
        let k2 = (c0 * q0 - s0 * p0 + c1 * q1 - s1 * p1) * 0.5;
        let d1 = k1 - self.kappa0[0];
        let d2 = k2 - self.kappa0[1];
        to_na(&((d1 * d1 + d2 * d2) * self.coef))
    }
}

impl TwistStencil<'_> {
    /// Value, gradient and Hessian in the 8 intrinsic coordinates, by staged jets: each
    /// edge's frame over its own 3 coordinates, the reference twist over the 6 positional
    /// coordinates, and `m = theta^1 - theta^0 + r` over all 8. Equal to
    /// [`super::autodiff::derivatives`] of
    /// [`crate::energy::stencil::StencilEnergy::eval`] up to round-off.
    pub fn derivatives(&self, y: [f64; 8]) -> (f64, SVector<f64, 8>, SMatrix<f64, 8, 8>) {
        let [e0, e1] = EdgeJets::of_stencil(self.frame, &y);
        self.derivatives_with([&e0, &e1], &y)
    }

    /// [`Self::derivatives`] with the two edges' frame jets given (shared with the bending
    /// stencil and the neighbouring node).
    pub fn derivatives_with(
        &self,
        edges: [&EdgeJets; 2],
        y: &[f64; 8],
    ) -> (f64, SVector<f64, 8>, SMatrix<f64, 8, 8>) {
        let f = self.frame;
        let (t0, a0) = (edges[0].t, edges[0].a1);
        let (t1, a1) = (edges[1].t, edges[1].a1);
        let (t0, a0): (JV<6>, JV<6>) = (embed(&t0, 0), embed(&a0, 0));
        let (t1, a1): (JV<6>, JV<6>) = (embed(&t1, 3), embed(&a1, 3));
        let u = transport(&t0, &t1, &a0);
        let mut r = dot(&cross(&u, &a1), &t1).atan2(&dot(&u, &a1));
        let two_pi = std::f64::consts::TAU;
        let k = ((f.ref_twist_prev - r.v) / two_pi).round();
        if k != 0.0 {
            r = r + k * two_pi;
        }
        let m = Jet::<8>::var(y[7], 7) - Jet::<8>::var(y[6], 6) + Jet::embed(&r, 0);
        let d = m - self.m0;
        to_na(&(d * d * self.coef))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::psd::{project_psd, project_psd_nalgebra};
    use crate::energy::reference::autodiff;
    use crate::energy::reference::testing::{rel_diff, stencil};

    #[test]
    fn staged_bend_jets_match_num_dual() {
        for seed in 1..=200 {
            let (frame, y, mut r) = stencil(seed);
            let st = BendStencil {
                frame: &frame,
                kappa0: [0.5 * r.sym(), 0.5 * r.sym()],
                coef: 1.0 + r.sym(),
            };
            let (v, g, h) = st.derivatives(y);
            let (v_ref, g_ref, h_ref) = autodiff::derivatives(&st, y);
            assert!(
                (v - v_ref).abs() <= 1e-12 * v_ref.abs(),
                "value {v} vs {v_ref} (seed {seed})"
            );
            let eg = rel_diff(g.as_slice(), g_ref.as_slice());
            let eh = rel_diff(h.as_slice(), h_ref.as_slice());
            assert!(
                eg < 1e-9 && eh < 1e-9,
                "gradient {eg:e}, Hessian {eh:e} (seed {seed})"
            );
            let (mut p, mut p_ref) = (h, h_ref);
            project_psd(&mut p);
            project_psd_nalgebra(&mut p_ref);
            let ep = rel_diff(p.as_slice(), p_ref.as_slice());
            assert!(ep < 1e-9, "projected Hessian {ep:e} (seed {seed})");
        }
    }

    #[test]
    fn staged_twist_jets_match_num_dual() {
        for seed in 1..=200 {
            let (frame, y, mut r) = stencil(seed);
            let st = TwistStencil {
                frame: &frame,
                m0: 0.5 * r.sym(),
                coef: 1.0 + r.sym(),
            };
            let (v, g, h) = st.derivatives(y);
            let (v_ref, g_ref, h_ref) = autodiff::derivatives(&st, y);
            assert!(
                (v - v_ref).abs() <= 1e-12 * v_ref.abs(),
                "value {v} vs {v_ref} (seed {seed})"
            );
            let eg = rel_diff(g.as_slice(), g_ref.as_slice());
            let eh = rel_diff(h.as_slice(), h_ref.as_slice());
            assert!(
                eg < 1e-9 && eh < 1e-9,
                "gradient {eg:e}, Hessian {eh:e} (seed {seed})"
            );
            let (mut p, mut p_ref) = (h, h_ref);
            project_psd(&mut p);
            project_psd_nalgebra(&mut p_ref);
            let ep = rel_diff(p.as_slice(), p_ref.as_slice());
            assert!(ep < 1e-9, "projected Hessian {ep:e} (seed {seed})");
        }
    }
}
