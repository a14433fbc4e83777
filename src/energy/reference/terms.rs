//! Bending and twist as two separate energy terms, each with its stencil derivatives from a
//! [`StencilDerivatives`] (the staged jets [`Jets`] or the closed forms of
//! [`super::closed::Closed`]): the references the fused term of real runs
//! ([`crate::energy::bend_twist::BendTwist`]) is tested and benchmarked against.
//!
//! * bending `E_b = sum_i B/(2 l_i) |kappa_i - kappa0_i|^2` over interior nodes;
//! * twist `E_t = sum_i C/(2 l_i) (m_i - m0_i)^2` over interior nodes,
//!
//! with the integrated strains `kappa_i`, `m_i` of [`crate::rod::frames::strains`] and the
//! natural (rest) strains `kappa0_i`, `m0_i` that may change with time (muscles).

use super::jets::EdgeJets;
use crate::band::Assembly;
use crate::energy::local::{add_local, intrinsic, Local};
use crate::energy::stencil::{self, BendStencil, StencilEnergy, TwistStencil};
use crate::energy::{Ctx, Term};

/// The bending term, with its stencil derivatives from `D` ([`Jets`] by default).
pub struct Bend<D: StencilDerivatives = Jets>(pub D);

/// The twist term, with its stencil derivatives from `D` ([`Jets`] by default).
pub struct Twist<D: StencilDerivatives = Jets>(pub D);

/// Derivatives of one node's bending and twist energies.
pub trait StencilDerivatives: Send + Sync {
    /// Bending: value, gradient and Hessian at `y`, with the two edges' frame jets.
    fn bend(&self, st: &BendStencil, edges: [&EdgeJets; 2], y: &[f64; 8]) -> Local;
    /// Twist: value, gradient and Hessian at `y`, with the two edges' frame jets.
    fn twist(&self, st: &TwistStencil, edges: [&EdgeJets; 2], y: &[f64; 8]) -> Local;
    /// Bending: value and gradient at `y`.
    fn bend_gradient(&self, st: &BendStencil, y: &[f64; 8]) -> (f64, [f64; 8]);
    /// Twist: value and gradient at `y`.
    fn twist_gradient(&self, st: &TwistStencil, y: &[f64; 8]) -> (f64, [f64; 8]);
}

/// Staged jets (Hessians, [`super::jets`]); the real path's gradients
/// ([`stencil::bend_gradient`], [`stencil::twist_gradient`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Jets;

impl StencilDerivatives for Jets {
    fn bend(&self, st: &BendStencil, edges: [&EdgeJets; 2], y: &[f64; 8]) -> Local {
        st.derivatives_with(edges, y)
    }
    fn twist(&self, st: &TwistStencil, edges: [&EdgeJets; 2], y: &[f64; 8]) -> Local {
        st.derivatives_with(edges, y)
    }
    fn bend_gradient(&self, st: &BendStencil, y: &[f64; 8]) -> (f64, [f64; 8]) {
        stencil::bend_gradient(st, y)
    }
    fn twist_gradient(&self, st: &TwistStencil, y: &[f64; 8]) -> (f64, [f64; 8]) {
        stencil::twist_gradient(st, y)
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
            coef: ctx.elastic_scale * m.bend / (2.0 * m.voronoi[i]),
        };
        assemble_nodes(ctx, q, out, project, make, |st, e, y| self.0.bend(st, e, y))
    }
    fn gradient(&self, ctx: &Ctx, q: &[f64], grad: &mut [f64], _scratch: &mut Assembly) -> f64 {
        let m = ctx.model;
        let make = |i: usize| BendStencil {
            frame: &ctx.frames[i - 1],
            kappa0: ctx.kappa0[i],
            coef: ctx.elastic_scale * m.bend / (2.0 * m.voronoi[i]),
        };
        stencil::gradient_nodes(ctx, q, grad, make, |st, y| self.0.bend_gradient(st, y))
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
            coef: ctx.elastic_scale * m.twist / (2.0 * m.voronoi[i]),
        };
        assemble_nodes(ctx, q, out, project, make, |st, e, y| {
            self.0.twist(st, e, y)
        })
    }
    fn gradient(&self, ctx: &Ctx, q: &[f64], grad: &mut [f64], _scratch: &mut Assembly) -> f64 {
        let m = ctx.model;
        let make = |i: usize| TwistStencil {
            frame: &ctx.frames[i - 1],
            m0: ctx.m0[i],
            coef: ctx.elastic_scale * m.twist / (2.0 * m.voronoi[i]),
        };
        stencil::gradient_nodes(ctx, q, grad, make, |st, y| self.0.twist_gradient(st, y))
    }
}

/// Sum of one stencil energy over the interior nodes, with its derivatives added to `out`
/// when given (the edge frames computed once per call): the body of the bending and twist
/// terms. `make(i)` is node `i`'s stencil, `local` its value, gradient and Hessian.
fn assemble_nodes<S: StencilEnergy>(
    ctx: &Ctx,
    q: &[f64],
    out: Option<&mut Assembly>,
    project: bool,
    make: impl Fn(usize) -> S,
    local: impl Fn(&S, [&EdgeJets; 2], &[f64; 8]) -> Local,
) -> f64 {
    let nodes = ctx.model.nodes;
    let mut e = 0.0;
    let Some(asm) = out else {
        for i in 1..nodes - 1 {
            e += make(i).eval(&intrinsic(q, i));
        }
        return e;
    };
    let edges: Vec<EdgeJets> = (0..nodes - 1)
        .map(|j| {
            let (e, t_old, a1_old) = crate::energy::edge_at(ctx, q, j);
            EdgeJets::new(e, t_old, a1_old)
        })
        .collect();
    for i in 1..nodes - 1 {
        let y = intrinsic(q, i);
        e += add_local(
            asm,
            i,
            local(&make(i), [&edges[i - 1], &edges[i]], &y),
            project,
        );
    }
    e
}
