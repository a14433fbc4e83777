//! Energy terms of the rod. Each term gives its value and, on request, its gradient and
//! Hessian (optionally projected to positive semi-definite per stencil), added into the
//! band [`Assembly`] of [`crate::band`]; the implicit, static and explicit steppers all use
//! the one list [`rod_terms`]:
//!
//! * [`stretch`]: `EA/(2 l0) (|e| - l0)^2` per edge (near-inextensibility, MODEL 1.3), with a
//!   closed-form Hessian;
//! * [`bend_twist::BendTwist`]: bending `B/(2 l_i) |kappa_i - kappa0_i|^2` and twist
//!   `C/(2 l_i) (m_i - m0_i)^2` of every interior node together, one closed form in plain
//!   `f64` for the value, gradient and Hessian of a node's stencil;
//! * [`gravity`]: `-sum_i m_i g . x_i`.
//!
//! Beside the terms, [`self_contact`]: the barrier that keeps two parts of the body apart,
//! a function of pairs of edges anywhere on the body (not a band term: its Hessian is a
//! low-rank part of the assembly), added by the step's potential itself.
//!
//! Bending and twist of node `i` are functions of its stencil's 8 intrinsic coordinates
//! `(e^{i-1}, e^i, theta^{i-1}, theta^i)` and of the frozen reference frames of its two edges.
//! The pieces of that path, one file each:
//!
//! * [`stencil`]: the two energies written once, generically over the scalar (their value,
//!   and the gradient alone for explicit integration: closed form when the frames are
//!   current, dual numbers otherwise);
//! * [`bend_twist`]: the fused closed-form value, gradient and Hessian ([`bend_twist::BendTwist`]);
//! * [`reftwist`]: the reference twist's value and derivatives (solid-angle form);
//! * [`jet`]: second-order jets, for the reference twist's `atan2`;
//! * [`local`]: intrinsic coordinates, the chain rule into the band (linear), and the
//!   per-stencil projection to positive semi-definite.
//!
//! **Rod damping.** With a Kelvin-Voigt damping time `tau` ([`Model::damping_time`]) every
//! elastic strain `e` with stiffness `k` (bending, twist, stretch) also carries the viscous
//! dissipation potential `tau k/2 |de/dt|^2`. An implicit step measures the strain rate as
//! `(e(q) - e_o) / h'`, with the integrator's origin `e_o` and effective step `h'` (implicit
//! Euler: `e_o = e(q_n)`, `h' = h`; BDF2: `e_o = -(a1 e(q_n) + a2 e(q_{n-1})) / a0`,
//! `h' = h / a0`, as for friction's slip), so the step's potential gains
//! `h' tau k/2 |(e - e_o)/h'|^2`. With `r = tau / h'` the term and the elastic one combine into
//! one of the same form, `(1 + r) k/2 |e - e*|^2` plus a constant, about the blended rest strain
//! `e* = (e0 + r e_o) / (1 + r)`: the terms evaluate their usual energy with the stiffness
//! factor [`Ctx::elastic_scale`] `= 1 + r`, the blended natural curvature and twist in
//! [`Ctx::kappa0`] and [`Ctx::m0`], and the blended rest lengths [`Ctx::rest_len`]. The
//! derivatives are those of the elastic terms, checked against finite differences for any
//! rest strains and stiffness.
//!
//! The independent derivatives the fused stencil is tested against (hyper-dual numbers,
//! staged jets, per-term closed forms, bending and twist as separate terms) live in
//! `reference/`, compiled for tests and benches only (cargo feature `reference`).

pub mod bend_twist;
pub mod gravity;
pub mod jet;
pub mod local;
pub mod psd;
#[cfg(any(test, feature = "reference"))]
pub mod reference;
pub mod reftwist;
pub mod self_contact;
pub mod stencil;
pub mod stretch;

/// The gradient and band Hessian energy terms add into (defined in [`crate::band`]).
pub use crate::band::Assembly;
use crate::model::Model;
use crate::rod::dof;
use crate::rod::frames::StencilFrame;

/// Everything besides `q` that an energy evaluation depends on.
pub struct Ctx<'a> {
    /// The model.
    pub model: &'a Model,
    /// Frozen frame of every interior node's stencil (index `i - 1` for node `i`).
    pub frames: &'a [StencilFrame],
    /// Integrated natural curvature at every node (index = node; ends unused).
    pub kappa0: &'a [[f64; 2]],
    /// Integrated natural twist at every node (index = node; ends unused).
    pub m0: &'a [f64],
    /// Gravity vector (m/s^2), possibly scaled in static load stepping.
    pub gravity: [f64; 3],
    /// Rest length of every edge that the stretching term pulls toward: the model's
    /// [`Model::rest_len`], or with rod damping the blend described in [`crate::energy`]'s
    /// "Rod damping".
    pub rest_len: &'a [f64],
    /// Factor on every elastic stiffness: 1, or `1 + tau/h'` with rod damping.
    pub elastic_scale: f64,
}

/// One energy term.
pub trait Term: Send + Sync {
    /// Name for statistics and messages.
    fn name(&self) -> &'static str;
    /// Energy at `q`. With `out`, also adds the gradient and Hessian there; `project` makes
    /// every stencil's Hessian positive semi-definite.
    fn eval(&self, ctx: &Ctx, q: &[f64], out: Option<&mut Assembly>, project: bool) -> f64;
    /// Energy at `q`, its gradient added to `grad` (no Hessian: explicit integration). The
    /// default assembles into `scratch` and copies the gradient.
    fn gradient(&self, ctx: &Ctx, q: &[f64], grad: &mut [f64], scratch: &mut Assembly) -> f64 {
        scratch.clear();
        let e = self.eval(ctx, q, Some(scratch), false);
        for (g, s) in grad.iter_mut().zip(&scratch.grad) {
            *g += s;
        }
        e
    }
    /// Whether Newton may keep this term's Hessian from an earlier iterate close by and take
    /// only its value and gradient ([`Term::value_gradient`]) at the next ones
    /// ([`crate::newton::HessianCache`]): terms whose Hessian is most of an assembly's cost.
    fn reusable_hessian(&self) -> bool {
        false
    }
    /// Energy at an iterate of an implicit step (frozen frames not at the current tangents),
    /// its gradient added to `grad`, without the Hessian. The default assembles everything
    /// and drops the Hessian; terms with [`Term::reusable_hessian`] override it.
    fn value_gradient(&self, ctx: &Ctx, q: &[f64], grad: &mut [f64]) -> f64 {
        let mut scratch = Assembly::new(grad.len());
        self.gradient(ctx, q, grad, &mut scratch)
    }
}

/// All elastic and gravitational terms of the rod.
pub fn rod_terms() -> Vec<Box<dyn Term>> {
    vec![
        Box::new(stretch::Stretch),
        Box::new(bend_twist::BendTwist::default()),
        Box::new(gravity::Gravity),
    ]
}

/// Edge `j`'s vector at `q` with its frozen tangent and reference director (from the first
/// stencil holding it).
fn edge_at(ctx: &Ctx, q: &[f64], j: usize) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let (fr, k) = if j == 0 {
        (&ctx.frames[0], 0)
    } else {
        (&ctx.frames[j - 1], 1)
    };
    let (a, b) = (dof::node(j), dof::node(j + 1));
    let e = [q[b] - q[a], q[b + 1] - q[a + 1], q[b + 2] - q[a + 2]];
    (e, fr.t_old[k], fr.a1_old[k])
}

/// Total of all terms at `q`; with `out`, also gradient and Hessian.
pub fn total(
    terms: &[Box<dyn Term>],
    ctx: &Ctx,
    q: &[f64],
    mut out: Option<&mut Assembly>,
    project: bool,
) -> f64 {
    let mut e = 0.0;
    for t in terms {
        e += t.eval(ctx, q, out.as_deref_mut(), project);
    }
    e
}
