//! Twist energy `E_t = sum_i C/(2 l_i) (m_i - m0_i)^2` over interior nodes, with the
//! integrated twist `m_i = theta^i - theta^{i-1} + ref twist` of [`crate::rod::frames::strains`] and natural (rest)
//! twist `m0_i` (integrated, rad) that may change with time (muscles).

use super::autodiff::{self, StencilEnergy};
use super::{Assembly, Ctx, Term};
use crate::rod::{dof, frames, frames::StencilFrame, V3};
use num_dual::DualNum;

/// The twist term.
pub struct Twist;

/// One node's twist energy.
pub struct TwistStencil<'a> {
    /// Frozen frames.
    pub frame: &'a StencilFrame,
    /// Natural integrated twist.
    pub m0: f64,
    /// `C / (2 l_i)`.
    pub coef: f64,
}

impl StencilEnergy for TwistStencil<'_> {
    fn eval<T: DualNum<Primitive = f64>>(&self, y: &[T; 8]) -> T {
        let e0 = V3([y[0].clone(), y[1].clone(), y[2].clone()]);
        let e1 = V3([y[3].clone(), y[4].clone(), y[5].clone()]);
        let s = frames::strains(&e0, &e1, &y[6], &y[7], self.frame);
        let d = s.twist - self.m0;
        d.clone() * d * self.coef
    }
}

impl Term for Twist {
    fn name(&self) -> &'static str {
        "twist"
    }
    fn eval(&self, ctx: &Ctx, q: &[f64], mut out: Option<&mut Assembly>, project: bool) -> f64 {
        let m = ctx.model;
        let mut e = 0.0;
        for i in 1..m.nodes - 1 {
            let st = TwistStencil { frame: &ctx.frames[i - 1], m0: ctx.m0[i], coef: m.twist / (2.0 * m.voronoi[i]) };
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
