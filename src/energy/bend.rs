//! Bending energy `E_b = sum_i B/(2 l_i) |kappa_i - kappa0_i|^2` over interior nodes, with the
//! integrated strains `kappa_i` of [`crate::rod::frames::strains`] and natural (rest)
//! curvature `kappa0_i` (integrated, dimensionless) that may change with time (muscles).

use super::autodiff;
pub use super::stencil::BendStencil;
use super::stencil::{self, EdgeJets, Jets, StencilDerivatives};
use super::{Assembly, Ctx, Term};
use nalgebra::{SMatrix, SVector};

/// The bending term, with its stencil derivatives from `D` ([`Jets`] by default).
pub struct Bend<D: StencilDerivatives = Jets>(pub D);

impl BendStencil<'_> {
    /// Value, gradient and Hessian in the 8 intrinsic coordinates, by staged jets: each
    /// edge's frame over its own 3 coordinates, the four projections of the curvature
    /// binormal on the reference frames over the 6 positional coordinates, and
    /// `kappa = 1/2 sum_j (cos theta^j (kb.a1^j) + sin theta^j (kb.a2^j), ...)` over all 8.
    /// Equal to [`autodiff::derivatives`] of [`autodiff::StencilEnergy::eval`] up to round-off.
    pub fn derivatives(&self, y: [f64; 8]) -> (f64, SVector<f64, 8>, SMatrix<f64, 8, 8>) {
        let [e0, e1] = EdgeJets::of_stencil(self.frame, &y);
        self.derivatives_with([&e0, &e1], &y)
    }

    /// [`Self::derivatives`] with the two edges' frame jets given (shared with the twist
    /// stencil and the neighbouring node, [`super::stencil`]).
    pub fn derivatives_with(
        &self,
        edges: [&EdgeJets; 2],
        y: &[f64; 8],
    ) -> (f64, SVector<f64, 8>, SMatrix<f64, 8, 8>) {
        use autodiff::jet::{cross, dot, embed, scale, to_na, Jet, JV};
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

impl<D: StencilDerivatives> Term for Bend<D> {
    fn name(&self) -> &'static str {
        "bend"
    }
    fn eval(&self, ctx: &Ctx, q: &[f64], out: Option<&mut Assembly>, project: bool) -> f64 {
        let m = ctx.model;
        let make = |i: usize| BendStencil {
            frame: &ctx.frames[i - 1],
            kappa0: ctx.kappa0[i],
            coef: m.bend / (2.0 * m.voronoi[i]),
        };
        stencil::assemble_nodes(ctx, q, out, project, make, |st, e, y| self.0.bend(st, e, y))
    }
    fn gradient(&self, ctx: &Ctx, q: &[f64], grad: &mut [f64], _scratch: &mut Assembly) -> f64 {
        let m = ctx.model;
        let make = |i: usize| BendStencil {
            frame: &ctx.frames[i - 1],
            kappa0: ctx.kappa0[i],
            coef: m.bend / (2.0 * m.voronoi[i]),
        };
        stencil::gradient_nodes(ctx, q, grad, make, |st, y| self.0.bend_gradient(st, y))
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
            autodiff::project_psd(&mut p);
            autodiff::project_psd_nalgebra(&mut p_ref);
            let ep = rel_diff(p.as_slice(), p_ref.as_slice());
            assert!(ep < 1e-9, "projected Hessian {ep:e} (seed {seed})");
        }
    }
}
