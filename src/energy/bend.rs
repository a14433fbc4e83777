//! Bending energy `E_b = sum_i B/(2 l_i) |kappa_i - kappa0_i|^2` over interior nodes, with the
//! integrated strains `kappa_i` of [`crate::rod::frames::strains`] and natural (rest)
//! curvature `kappa0_i` (integrated, dimensionless) that may change with time (muscles).

use super::autodiff::{self, StencilEnergy};
use super::{Assembly, Ctx, Term};
use crate::rod::{dof, frames, frames::StencilFrame, V3};
use num_dual::DualNum;

/// The bending term.
pub struct Bend;

/// One node's bending energy.
pub struct BendStencil<'a> {
    /// Frozen frames.
    pub frame: &'a StencilFrame,
    /// Natural integrated curvature.
    pub kappa0: [f64; 2],
    /// `B / (2 l_i)`.
    pub coef: f64,
}

impl StencilEnergy for BendStencil<'_> {
    fn eval<T: DualNum<Primitive = f64>>(&self, y: &[T; 8]) -> T {
        let e0 = V3([y[0].clone(), y[1].clone(), y[2].clone()]);
        let e1 = V3([y[3].clone(), y[4].clone(), y[5].clone()]);
        let s = frames::strains(&e0, &e1, &y[6], &y[7], self.frame);
        let [k1, k2] = s.kappa;
        let d1 = k1 - self.kappa0[0];
        let d2 = k2 - self.kappa0[1];
        (d1.clone() * d1 + d2.clone() * d2) * self.coef
    }
}

impl Term for Bend {
    fn name(&self) -> &'static str {
        "bend"
    }
    fn eval(&self, ctx: &Ctx, q: &[f64], mut out: Option<&mut Assembly>, project: bool) -> f64 {
        let m = ctx.model;
        let mut e = 0.0;
        for i in 1..m.nodes - 1 {
            let st = BendStencil { frame: &ctx.frames[i - 1], kappa0: ctx.kappa0[i], coef: m.bend / (2.0 * m.voronoi[i]) };
            let y = autodiff::intrinsic(q, i);
            match out.as_deref_mut() {
                None => e += st.eval(&y),
                Some(asm) => {
                    let (v, g, mut h) = autodiff::derivatives(&st, y);
                    if project {
                        autodiff::project_psd(&mut h);
                    }
                    let (gx, hx) = autodiff::to_nodes(&g, &h);
                    asm.add_local(&dof::stencil(i), &gx, &hx);
                    e += v;
                }
            }
        }
        e
    }
}
