//! The per-node stencil of bending and twist: its two energies written once, generically over
//! the scalar, and their gradient.
//!
//! Node `i`'s stencil has the 8 intrinsic coordinates `y = (e^{i-1}, e^i, theta^{i-1},
//! theta^i)` ([`super::local::intrinsic`]); both the bending and the twist energy of the node
//! are functions of `y` and of the frozen reference frames of its two edges. [`BendStencil`]
//! and [`TwistStencil`] are those energies ([`StencilEnergy::eval`] with `f64` is the value
//! every run uses; with dual numbers it differentiates itself).
//!
//! The gradient alone (explicit integration, [`super::bend_twist::BendTwist`]'s
//! [`super::Term::gradient`]): [`bend_gradient`] and [`twist_gradient`], the closed form of
//! Bergou et al. 2010 when the frames are current ([`frames_current`]), first-order dual
//! numbers otherwise. The Hessians of real runs come from the fused closed form of
//! [`super::bend_twist`]; the per-term references (staged jets, per-term closed forms, hyper-dual
//! numbers) live in `energy/reference/` and are compiled for tests and benches only.

use super::local::{add_gradient, intrinsic};
use crate::rod::frames::{self, StencilFrame};
use crate::rod::{vec3::f, V3};
use nalgebra::SVector;
use num_dual::{DualNum, DualSVec64};

/// A scalar function of the 8 stencil coordinates, generic over the number type.
pub trait StencilEnergy {
    /// Evaluate.
    fn eval<T: DualNum<Primitive = f64>>(&self, y: &[T; 8]) -> T;
}

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

/// Bending: value and gradient at `y`, in closed form when the stencil's frames are current,
/// by first-order dual numbers otherwise.
pub fn bend_gradient(st: &BendStencil, y: &[f64; 8]) -> (f64, [f64; 8]) {
    match Current::of(st.frame, y) {
        Some(c) => c.bend(st),
        None => dual_gradient(st, y),
    }
}

/// Twist: value and gradient at `y`, in closed form when the stencil's frames are current,
/// by first-order dual numbers otherwise.
pub fn twist_gradient(st: &TwistStencil, y: &[f64; 8]) -> (f64, [f64; 8]) {
    match Current::of(st.frame, y) {
        Some(c) => c.twist(st),
        None => dual_gradient(st, y),
    }
}

/// Whether the stencil's frozen frames sit at the current tangents of `y` (to 1e-12), as
/// right after [`crate::state::State::update_frames`]: then the closed-form gradient is exact.
pub fn frames_current(frame: &StencilFrame, y: &[f64; 8]) -> bool {
    let tangent = |e: [f64; 3]| f::scale(e, 1.0 / f::norm(e));
    let t0 = tangent([y[0], y[1], y[2]]);
    let t1 = tangent([y[3], y[4], y[5]]);
    let current = |a: [f64; 3], b: [f64; 3]| (0..3).all(|k| (a[k] - b[k]).abs() <= 1e-12);
    current(t0, frame.t_old[0]) && current(t1, frame.t_old[1])
}

/// Value and gradient of a stencil energy in its 8 intrinsic coordinates by first-order dual
/// numbers.
fn dual_gradient<E: StencilEnergy>(e: &E, y: &[f64; 8]) -> (f64, [f64; 8]) {
    let (v, g) = num_dual::gradient(
        |v: SVector<DualSVec64<8>, 8>| {
            let arr: [DualSVec64<8>; 8] = std::array::from_fn(|k| v[k]);
            e.eval(&arr)
        },
        &SVector::from(*y),
    );
    (v, std::array::from_fn(|k| g[k]))
}

/// The quantities of the closed-form gradient (Bergou et al. 2010, in this crate's sign
/// conventions `kappa_a = kb . (d_a^{i-1} + d_a^i)/2`):
///
/// ```text
/// dkappa_a/de^{i-1} = (-kappa_a tt + t^i x dd_a) / |e^{i-1}|,
/// dkappa_a/de^i     = (-kappa_a tt - t^{i-1} x dd_a) / |e^i|,
/// dkappa_1/dtheta^j = kb . d2^j / 2,   dkappa_2/dtheta^j = -kb . d1^j / 2,
/// dm/de^{i-1} = kb / (2 |e^{i-1}|),   dm/de^i = kb / (2 |e^i|),   dm/dtheta^{i-1,i} = -1, 1,
/// ```
///
/// `chi = t^{i-1}.t^i`, `tt = (t^{i-1} + t^i)/(1 + chi)`, `dd_a = (d_a^{i-1} + d_a^i)/(1 + chi)`.
/// These are the derivatives with the reference frames transported from the current tangents,
/// so they are exact only when the stencil's frozen frame is current ([`frames_current`]).
struct Current {
    kappa: [f64; 2],
    twist: f64,
    n: [f64; 2],
    t: [[f64; 3]; 2],
    kb: [f64; 3],
    tt: [f64; 3],
    dd: [[f64; 3]; 2],
    d1: [[f64; 3]; 2],
    d2: [[f64; 3]; 2],
}

impl Current {
    fn of(fr: &StencilFrame, y: &[f64; 8]) -> Option<Self> {
        let e0 = [y[0], y[1], y[2]];
        let e1 = [y[3], y[4], y[5]];
        let (n0, n1) = (f::norm(e0), f::norm(e1));
        let (t0, t1) = (f::scale(e0, 1.0 / n0), f::scale(e1, 1.0 / n1));
        if !frames_current(fr, y) {
            return None;
        }
        let st = frames::strains::<f64>(&V3(e0), &V3(e1), &y[6], &y[7], fr);
        let directors = |t: [f64; 3], t_old: [f64; 3], a_old: [f64; 3], theta: f64| {
            let a = f::transport(t_old, t, a_old);
            let b = f::cross(t, a);
            let (s, c) = theta.sin_cos();
            (
                f::add(f::scale(a, c), f::scale(b, s)),
                f::sub(f::scale(b, c), f::scale(a, s)),
            )
        };
        let (d1a, d2a) = directors(t0, fr.t_old[0], fr.a1_old[0], y[6]);
        let (d1b, d2b) = directors(t1, fr.t_old[1], fr.a1_old[1], y[7]);
        let w = 1.0 / (1.0 + f::dot(t0, t1));
        Some(Current {
            kappa: st.kappa,
            twist: st.twist,
            n: [n0, n1],
            t: [t0, t1],
            kb: f::scale(f::cross(t0, t1), 2.0 * w),
            tt: f::scale(f::add(t0, t1), w),
            dd: [f::scale(f::add(d1a, d1b), w), f::scale(f::add(d2a, d2b), w)],
            d1: [d1a, d1b],
            d2: [d2a, d2b],
        })
    }

    fn bend(&self, bend: &BendStencil) -> (f64, [f64; 8]) {
        let cb = 2.0 * bend.coef;
        let gk = [
            cb * (self.kappa[0] - bend.kappa0[0]),
            cb * (self.kappa[1] - bend.kappa0[1]),
        ];
        let energy = bend.coef
            * ((self.kappa[0] - bend.kappa0[0]).powi(2) + (self.kappa[1] - bend.kappa0[1]).powi(2));
        let [t0, t1] = self.t;
        let [n0, n1] = self.n;
        let mut g0 = [0.0; 3];
        let mut g1 = [0.0; 3];
        for a in 0..2 {
            let k = self.kappa[a];
            g0 = f::add(
                g0,
                f::scale(
                    f::add(f::scale(self.tt, -k), f::cross(t1, self.dd[a])),
                    gk[a] / n0,
                ),
            );
            g1 = f::add(
                g1,
                f::scale(
                    f::sub(f::scale(self.tt, -k), f::cross(t0, self.dd[a])),
                    gk[a] / n1,
                ),
            );
        }
        let kb = self.kb;
        let th = |j: usize| 0.5 * (gk[0] * f::dot(kb, self.d2[j]) - gk[1] * f::dot(kb, self.d1[j]));
        (
            energy,
            [g0[0], g0[1], g0[2], g1[0], g1[1], g1[2], th(0), th(1)],
        )
    }

    fn twist(&self, twist: &TwistStencil) -> (f64, [f64; 8]) {
        let gm = 2.0 * twist.coef * (self.twist - twist.m0);
        let energy = twist.coef * (self.twist - twist.m0).powi(2);
        let g0 = f::scale(self.kb, 0.5 * gm / self.n[0]);
        let g1 = f::scale(self.kb, 0.5 * gm / self.n[1]);
        (energy, [g0[0], g0[1], g0[2], g1[0], g1[1], g1[2], -gm, gm])
    }
}

/// Sum of one stencil energy over the interior nodes, its gradient added to `grad`.
pub(crate) fn gradient_nodes<S>(
    ctx: &crate::energy::Ctx,
    q: &[f64],
    grad: &mut [f64],
    make: impl Fn(usize) -> S,
    gradient: impl Fn(&S, &[f64; 8]) -> (f64, [f64; 8]),
) -> f64 {
    let mut e = 0.0;
    for i in 1..ctx.model.nodes - 1 {
        let (v, g) = gradient(&make(i), &intrinsic(q, i));
        e += v;
        add_gradient(grad, i, &g);
    }
    e
}
