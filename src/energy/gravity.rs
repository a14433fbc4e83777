//! Gravitational potential `E_g = -sum_i m_i g . x_i` (lumped node masses).

use super::{Assembly, Ctx, Term};
use crate::rod::dof;

/// The gravity term.
pub struct Gravity;

impl Term for Gravity {
    fn name(&self) -> &'static str {
        "gravity"
    }
    fn eval(&self, ctx: &Ctx, q: &[f64], mut out: Option<&mut Assembly>, _project: bool) -> f64 {
        let m = ctx.model;
        let g = ctx.gravity;
        let mut e = 0.0;
        for i in 0..m.nodes {
            let k = dof::node(i);
            for c in 0..3 {
                let f = m.mass[k + c] * g[c];
                e -= f * q[k + c];
                if let Some(asm) = out.as_deref_mut() {
                    asm.grad[k + c] -= f;
                }
            }
        }
        e
    }
}
