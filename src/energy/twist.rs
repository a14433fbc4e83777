//! Twist energy `E_t = sum_i C/(2 l_i) (m_i - m0_i)^2` over interior nodes, with the
//! integrated twist `m_i = theta^i - theta^{i-1} + ref twist` of [`crate::rod::frames::strains`] and natural (rest)
//! twist `m0_i` (integrated, rad) that may change with time (muscles).

use super::autodiff;
pub use super::stencil::TwistStencil;
use super::stencil::{self, EdgeJets, Jets, StencilDerivatives};
use super::{Assembly, Ctx, Term};
use nalgebra::{SMatrix, SVector};

/// The twist term, with its stencil derivatives from `D` ([`Jets`] by default).
pub struct Twist<D: StencilDerivatives = Jets>(pub D);

impl TwistStencil<'_> {
    /// Value, gradient and Hessian in the 8 intrinsic coordinates, by staged jets: each
    /// edge's frame over its own 3 coordinates, the reference twist over the 6 positional
    /// coordinates, and `m = theta^1 - theta^0 + r` over all 8. Equal to
    /// [`autodiff::derivatives`] of [`autodiff::StencilEnergy::eval`] up to round-off.
    pub fn derivatives(&self, y: [f64; 8]) -> (f64, SVector<f64, 8>, SMatrix<f64, 8, 8>) {
        let [e0, e1] = EdgeJets::of_stencil(self.frame, &y);
        self.derivatives_with([&e0, &e1], &y)
    }

    /// [`Self::derivatives`] with the two edges' frame jets given (shared with the bending
    /// stencil and the neighbouring node, [`super::stencil`]).
    pub fn derivatives_with(
        &self,
        edges: [&EdgeJets; 2],
        y: &[f64; 8],
    ) -> (f64, SVector<f64, 8>, SMatrix<f64, 8, 8>) {
        use autodiff::jet::{cross, dot, embed, to_na, transport, Jet, JV};
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

impl<D: StencilDerivatives> Term for Twist<D> {
    fn name(&self) -> &'static str {
        "twist"
    }
    fn eval(&self, ctx: &Ctx, q: &[f64], out: Option<&mut Assembly>, project: bool) -> f64 {
        let m = ctx.model;
        let make = |i: usize| TwistStencil {
            frame: &ctx.frames[i - 1],
            m0: ctx.m0[i],
            coef: m.twist / (2.0 * m.voronoi[i]),
        };
        stencil::assemble_nodes(ctx, q, out, project, make, |st, e, y| {
            self.0.twist(st, e, y)
        })
    }
    fn gradient(&self, ctx: &Ctx, q: &[f64], grad: &mut [f64], _scratch: &mut Assembly) -> f64 {
        let m = ctx.model;
        let make = |i: usize| TwistStencil {
            frame: &ctx.frames[i - 1],
            m0: ctx.m0[i],
            coef: m.twist / (2.0 * m.voronoi[i]),
        };
        stencil::gradient_nodes(ctx, q, grad, make, |st, y| self.0.twist_gradient(st, y))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::autodiff::testing::{rel_diff, stencil};

    #[test]
    fn staged_jets_match_num_dual() {
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
            autodiff::project_psd(&mut p);
            autodiff::project_psd_nalgebra(&mut p_ref);
            let ep = rel_diff(p.as_slice(), p_ref.as_slice());
            assert!(ep < 1e-9, "projected Hessian {ep:e} (seed {seed})");
        }
    }
}
