//! Stretching energy `E_s = sum_j EA/(2 l0_j) (|e^j| - l0_j)^2`, the physical stretching
//! stiffness of a homogeneous circular rod (`EA = 16 B / a^2` by default), which keeps the
//! rod nearly inextensible (MODEL 1.3). Closed-form gradient `EA/l0 (|e| - l0) t` and Hessian
//! `EA/l0 [t t^T + (1 - l0/|e|)(I - t t^T)]`; the projection clamps `1 - l0/|e|` at zero,
//! which is exactly the positive part of the spectrum.

use super::{Assembly, Ctx, Term};
use crate::rod::dof;

/// The stretching term.
pub struct Stretch;

impl Term for Stretch {
    fn name(&self) -> &'static str {
        "stretch"
    }
    fn eval(&self, ctx: &Ctx, q: &[f64], mut out: Option<&mut Assembly>, project: bool) -> f64 {
        let m = ctx.model;
        let mut e = 0.0;
        for j in 0..m.nodes - 1 {
            let a = dof::node(j);
            let b = dof::node(j + 1);
            let ev = [q[b] - q[a], q[b + 1] - q[a + 1], q[b + 2] - q[a + 2]];
            let len = (ev[0] * ev[0] + ev[1] * ev[1] + ev[2] * ev[2]).sqrt();
            let l0 = ctx.rest_len[j];
            let k = ctx.elastic_scale * m.stretch / m.rest_len[j];
            e += 0.5 * k * (len - l0).powi(2);
            let Some(asm) = out.as_deref_mut() else {
                continue;
            };
            let t = [ev[0] / len, ev[1] / len, ev[2] / len];
            let mut c = 1.0 - l0 / len;
            if project {
                c = c.max(0.0);
            }
            let g = k * (len - l0);
            let mut h = [[0.0; 3]; 3];
            let mut neg = [[0.0; 3]; 3];
            for r in 0..3 {
                asm.grad[a + r] -= g * t[r];
                asm.grad[b + r] += g * t[r];
                for s in 0..3 {
                    let id = if r == s { 1.0 } else { 0.0 };
                    h[r][s] = k * (t[r] * t[s] + c * (id - t[r] * t[s]));
                    neg[r][s] = -h[r][s];
                }
            }
            asm.add_block3(a, a, &h);
            asm.add_block3(b, b, &h);
            asm.add_block3(a, b, &neg);
        }
        e
    }
}
