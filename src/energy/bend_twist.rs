//! Bending and twist of one node together, value, gradient and Hessian in closed form with
//! plain `f64` arithmetic: the implicit integrator's default stencil ([`BendTwist`]).
//!
//! Both energies depend on the edge vectors only through the tangents `t^j = e^j / |e^j|`, so
//! the derivatives are taken in the 8 variables `x = (t^{i-1}, t^i, theta^{i-1}, theta^i)`,
//! added, and mapped once to the intrinsic coordinates `(e^{i-1}, e^i, theta^{i-1}, theta^i)`
//! by the chain rule through `t = e / |e|` (any smooth extension of the formulas off the unit
//! sphere gives the same derivatives in `e`).
//!
//! **The edge frame** ([`EdgeFrame`], computed once per edge and shared by the two nodes of
//! the edge): the reference director is the time-parallel transport of the frozen director
//! `ao` from the frozen tangent `to`,
//!
//! ```text
//! a1(t) = c ao + v x ao + (s / r) v,   c = to.t, v = to x t, s = m.t, m = ao x to, r = 1 + c,
//! ```
//!
//! and `a2 = t x a1`. Its Jacobian in `t` is
//! `(to.ao) I - to ao^T + ao to^T + (v m^T + s [to]x - (s/r) v to^T) / r`, and the Hessian of
//! `w . a1` for a fixed vector `w` comes from the one non-linear term `p q / r` with
//! `p = m.t`, `q = n.t`, `n = w x to`:
//! `(m n^T + n m^T)/r - (q m + p n) to^T / r^2 - to (q m + p n)^T / r^2 + 2 p q to to^T / r^3`.
//! For `w . a2 = a1 . (w x t)` it is that Hessian at `u = w x t` plus `Ja1^T [w]x - [w]x Ja1`.
//! No Hessian of a frame is stored: every second derivative the stencil needs is one of these
//! contractions.
//!
//! **Bending.** With the material directors `d1 = cos a1 + sin a2`, `d2 = cos a2 - sin a1`
//! and `chi = 1 + t0.t1`, the integrated curvatures are `kappa_a = psi_a / chi`,
//! `psi_1 = t0.d2^1 - t1.d2^0`, `psi_2 = t1.d1^0 - t0.d1^1`. The Hessian of the energy
//! `c sum_a (kappa_a - kappa0_a)^2` needs the second derivatives of the `kappa_a` only in the
//! combination `sum_a delta_a Hess kappa_a`, which is that of one function
//! `Psi = sum_a delta_a psi_a = t0 . U1 + t1 . U0`, `U` a rotation in `theta` of the edge's
//! `(a1, a2)`: two contracted frame Hessians per edge instead of twelve products of jets.
//!
//! **Twist** uses the solid-angle form of the reference twist of [`super::reftwist`].
//!
//! Tested against the staged jets of the references (`reference/jets.rs`, themselves checked
//! against hyper-dual numbers) on random, strongly bent stencils with frozen frames away from
//! the current tangents, and through the rod's whole energy against finite differences
//! (`tests/derivatives.rs`).

use super::local::{add_gradient, add_local, intrinsic, Local};
use super::reftwist::{ref_twist_tangent_derivatives, ref_twist_tangent_gradient, ref_twist_value};
use super::stencil::{self, BendStencil, TwistStencil};
use super::{Assembly, Ctx, Term};
use crate::rod::frames::{self, StencilFrame};
use crate::rod::V3;
use crate::rod::{dof, vec3::f};
use nalgebra::{SMatrix, SVector};
use std::sync::{Mutex, TryLockError};

type M3 = [[f64; 3]; 3];

/// `[w]x`, the matrix of `u -> w x u`.
#[inline(always)]
fn skew(w: [f64; 3]) -> M3 {
    [[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]]
}

/// `A^T w`.
#[inline(always)]
fn mul_t(a: &M3, w: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|j| a[0][j] * w[0] + a[1][j] * w[1] + a[2][j] * w[2])
}

/// `A B`.
#[inline(always)]
fn mul(a: &M3, b: &M3) -> M3 {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j])
    })
}

/// `x A + y B`.
#[inline(always)]
fn lin(x: f64, a: &M3, y: f64, b: &M3) -> M3 {
    std::array::from_fn(|i| std::array::from_fn(|j| x * a[i][j] + y * b[i][j]))
}

/// One edge's length, tangent and transported reference directors with their first
/// derivatives in the tangent, and what the contracted second derivatives need.
#[derive(Clone, Copy, Debug, Default)]
pub struct EdgeFrame {
    /// `|e|`.
    pub len: f64,
    /// `t = e / |e|`.
    pub t: [f64; 3],
    /// Transported reference director.
    pub a1: [f64; 3],
    /// `a2 = t x a1`.
    pub a2: [f64; 3],
    /// `d a1 / d t`.
    ja1: M3,
    /// `d a2 / d t`.
    ja2: M3,
    /// The edge's twist angle `theta`, its cosine and sine.
    theta: f64,
    cos: f64,
    sin: f64,
    /// Material directors `d1 = cos a1 + sin a2`, `d2 = cos a2 - sin a1`.
    d1: [f64; 3],
    d2: [f64; 3],
    /// Frozen tangent.
    to: [f64; 3],
    /// `ao x to`.
    m: [f64; 3],
    /// `1 + to . t`.
    r: f64,
}

impl EdgeFrame {
    /// The frame of edge vector `e` with frozen tangent `t_old` and director `a1_old`, and its
    /// material directors at twist angle `theta` (computed once per edge, shared by the edge's
    /// two nodes).
    pub fn new(e: [f64; 3], t_old: [f64; 3], a1_old: [f64; 3], theta: f64) -> Self {
        let len = f::norm(e);
        let t = f::scale(e, 1.0 / len);
        let (to, ao) = (t_old, a1_old);
        let c = f::dot(to, t);
        let v = f::cross(to, t);
        let m = f::cross(ao, to);
        let s = f::dot(m, t);
        let r = 1.0 + c;
        let a1 = f::add(f::add(f::scale(ao, c), f::cross(v, ao)), f::scale(v, s / r));
        let a2 = f::cross(t, a1);
        let (toao, sr) = (f::dot(to, ao), s / r);
        let kt = skew(to);
        let ja1: M3 = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let id = if i == j { toao } else { 0.0 };
                id - to[i] * ao[j]
                    + ao[i] * to[j]
                    + (v[i] * m[j] - sr * v[i] * to[j]) / r
                    + sr * kt[i][j]
            })
        });
        // d(t x a1) = [t]x Ja1 - [a1]x.
        let ja2 = lin(1.0, &mul(&skew(t), &ja1), -1.0, &skew(a1));
        let (sin, cos) = theta.sin_cos();
        EdgeFrame {
            len,
            t,
            a1,
            a2,
            ja1,
            ja2,
            theta,
            cos,
            sin,
            d1: f::add(f::scale(a1, cos), f::scale(a2, sin)),
            d2: f::sub(f::scale(a2, cos), f::scale(a1, sin)),
            to,
            m,
            r,
        }
    }

    /// Hessian in `t` of `w . a1(t)` for a fixed `w`.
    #[inline(always)]
    fn hess_a1(&self, w: [f64; 3]) -> M3 {
        let (m, to, t, r) = (self.m, self.to, self.t, self.r);
        let n = f::cross(w, to);
        let (p, q) = (f::dot(m, t), f::dot(n, t));
        let ir = 1.0 / r;
        let b = f::scale(f::add(f::scale(m, q), f::scale(n, p)), ir * ir);
        let c = 2.0 * p * q * ir * ir * ir;
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                (m[i] * n[j] + n[i] * m[j]) * ir - b[i] * to[j] - to[i] * b[j] + c * to[i] * to[j]
            })
        })
    }

    /// Hessian in `t` of `w . a2(t) = a1(t) . (w x t)` for a fixed `w`.
    #[cfg(test)]
    fn hess_a2(&self, w: [f64; 3]) -> M3 {
        self.hess_comb(w, 0.0, 1.0)
    }

    /// Hessian in `t` of `w . (alpha a1(t) + beta a2(t))` for a fixed `w`. With
    /// `w . a2 = a1 . (w x t)` this is the Hessian of `a1` contracted with
    /// `alpha w + beta w x t` (linear in the contracting vector: one [`EdgeFrame::hess_a1`])
    /// plus `beta (X + X^T)`, `X = Ja1^T [w]x`.
    #[inline(always)]
    fn hess_comb(&self, w: [f64; 3], alpha: f64, beta: f64) -> M3 {
        let h = self.hess_a1(f::add(
            f::scale(w, alpha),
            f::scale(f::cross(w, self.t), beta),
        ));
        let x = mul(&transpose(&self.ja1), &skew(w));
        std::array::from_fn(|i| std::array::from_fn(|j| h[i][j] + beta * (x[i][j] + x[j][i])))
    }
}

#[inline(always)]
fn transpose(a: &M3) -> M3 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[j][i]))
}

/// One node's bending and twist parameters.
pub struct NodeStencil<'a> {
    /// Frozen frames.
    pub frame: &'a StencilFrame,
    /// Natural integrated curvature.
    pub kappa0: [f64; 2],
    /// `B / (2 l_i)`.
    pub bend: f64,
    /// Natural integrated twist.
    pub m0: f64,
    /// `C / (2 l_i)`.
    pub twist: f64,
}

impl<'a> NodeStencil<'a> {
    /// Interior node `i`'s stencil of the rod in `ctx`.
    pub fn of(ctx: &Ctx<'a>, i: usize) -> Self {
        let m = ctx.model;
        NodeStencil {
            frame: &ctx.frames[i - 1],
            kappa0: ctx.kappa0[i],
            bend: ctx.elastic_scale * m.bend / (2.0 * m.voronoi[i]),
            m0: ctx.m0[i],
            twist: ctx.elastic_scale * m.twist / (2.0 * m.voronoi[i]),
        }
    }
}

/// The first-order part of node `st`'s bending: everything the gradient needs, and what the
/// Hessian of [`node_local`] reuses.
struct Bend {
    /// The frames' Jacobians contracted with the other edge's tangent: `Ja^T t`.
    ja0: [f64; 3],
    jb0: [f64; 3],
    ja1: [f64; 3],
    jb1: [f64; 3],
    g_kappa: [[f64; 8]; 2],
    g_chi: [f64; 8],
    /// `1 / chi`.
    w: f64,
    delta: [f64; 2],
    /// `sum_a delta_a kappa_a`.
    big_k: f64,
    /// `sum_a delta_a grad kappa_a`.
    gk: [f64; 8],
}

#[inline(always)]
fn mix(x: f64, a: [f64; 3], y: f64, b: [f64; 3]) -> [f64; 3] {
    f::add(f::scale(a, x), f::scale(b, y))
}

#[inline(always)]
fn bend_first(st: &NodeStencil, edges: [&EdgeFrame; 2]) -> Bend {
    let [e0, e1] = edges;
    let (t0, t1) = (e0.t, e1.t);
    let (s0, c0) = (e0.sin, e0.cos);
    let (s1, c1) = (e1.sin, e1.cos);
    let (d10, d20) = (e0.d1, e0.d2);
    let (d11, d21) = (e1.d1, e1.d2);
    let (ja0, jb0) = (mul_t(&e0.ja1, t1), mul_t(&e0.ja2, t1));
    let (ja1, jb1) = (mul_t(&e1.ja1, t0), mul_t(&e1.ja2, t0));

    // Bending: psi_a, chi and their gradients in x = (t0, t1, theta0, theta1).
    let chi = 1.0 + f::dot(t0, t1);
    let psi = [
        f::dot(t0, d21) - f::dot(t1, d20),
        f::dot(t1, d10) - f::dot(t0, d11),
    ];
    let cat = |a: [f64; 3], b: [f64; 3], c: f64, d: f64| -> [f64; 8] {
        [a[0], a[1], a[2], b[0], b[1], b[2], c, d]
    };
    // Jd1^T t = c Ja1^T t + s Ja2^T t, Jd2^T t = c Ja2^T t - s Ja1^T t.
    let g_psi = [
        cat(
            f::sub(d21, mix(c0, jb0, -s0, ja0)),
            f::sub(mix(c1, jb1, -s1, ja1), d20),
            f::dot(t1, d10),
            -f::dot(t0, d11),
        ),
        cat(
            f::sub(mix(c0, ja0, s0, jb0), d11),
            f::sub(d10, mix(c1, ja1, s1, jb1)),
            f::dot(t1, d20),
            -f::dot(t0, d21),
        ),
    ];
    let g_chi = cat(t1, t0, 0.0, 0.0);
    let w = 1.0 / chi;
    let kappa = [psi[0] * w, psi[1] * w];
    let g_kappa: [[f64; 8]; 2] =
        std::array::from_fn(|a| std::array::from_fn(|k| (g_psi[a][k] - kappa[a] * g_chi[k]) * w));
    let delta = [kappa[0] - st.kappa0[0], kappa[1] - st.kappa0[1]];
    Bend {
        ja0,
        jb0,
        ja1,
        jb1,
        g_kappa,
        g_chi,
        w,
        delta,
        big_k: delta[0] * kappa[0] + delta[1] * kappa[1],
        gk: std::array::from_fn(|k| delta[0] * g_kappa[0][k] + delta[1] * g_kappa[1][k]),
    }
}

/// Value and gradient (no Hessian) of node `st`'s bending plus twist in its intrinsic
/// coordinates: the first-order part of [`node_local`], for iterates whose Hessian is kept
/// from an earlier one ([`BendTwist::value_gradient`]).
#[inline(always)]
pub fn node_local_gradient(st: &NodeStencil, edges: [&EdgeFrame; 2]) -> (f64, [f64; 8]) {
    let [e0, e1] = edges;
    let (t0, t1) = (e0.t, e1.t);
    let b = bend_first(st, edges);
    let r = ref_twist_value([t0, t1], [e0.a1, e1.a1], st.frame.ref_twist_prev);
    let gr = ref_twist_tangent_gradient(t0, t1, st.frame.t_old[0], st.frame.t_old[1]);
    let dm = e1.theta - e0.theta + r - st.m0;
    let gm = [gr[0], gr[1], gr[2], gr[3], gr[4], gr[5], -1.0, 1.0];
    let (cb, ct) = (2.0 * st.bend, 2.0 * st.twist);
    let energy = st.bend * (b.delta[0] * b.delta[0] + b.delta[1] * b.delta[1]) + st.twist * dm * dm;
    let gx: [f64; 8] = std::array::from_fn(|k| cb * b.gk[k] + ct * dm * gm[k]);
    (energy, tangent_gradient_to_edges(edges, &gx).0)
}

/// Value, gradient and Hessian of node `st`'s bending plus twist in its intrinsic
/// coordinates, with its two edges' frames (their twist angles `theta` included).
#[inline(always)]
pub fn node_local(st: &NodeStencil, edges: [&EdgeFrame; 2]) -> Local {
    let [e0, e1] = edges;
    let (t0, t1) = (e0.t, e1.t);
    let (s0, c0) = (e0.sin, e0.cos);
    let (s1, c1) = (e1.sin, e1.cos);
    let Bend {
        ja0,
        jb0,
        ja1,
        jb1,
        g_kappa,
        g_chi,
        w,
        delta,
        big_k,
        gk,
    } = bend_first(st, edges);

    // Psi = sum_a delta_a psi_a = t0 . U1 + t1 . U0, U = alpha a1 + beta a2 of each edge.
    let (dl1, dl2) = (delta[0], delta[1]);
    let (al0, be0) = (dl2 * c0 + dl1 * s0, dl2 * s0 - dl1 * c0);
    let (al0p, be0p) = (dl1 * c0 - dl2 * s0, dl2 * c0 + dl1 * s0);
    let (al1, be1) = (-dl1 * s1 - dl2 * c1, dl1 * c1 - dl2 * s1);
    let (al1p, be1p) = (-dl1 * c1 + dl2 * s1, -dl1 * s1 - dl2 * c1);
    let comb = |e: &EdgeFrame, a: f64, b: f64| f::add(f::scale(e.a1, a), f::scale(e.a2, b));
    let (u0, u0p) = (comb(e0, al0, be0), comb(e0, al0p, be0p));
    let (u1, u1p) = (comb(e1, al1, be1), comb(e1, al1p, be1p));
    let ju0 = lin(al0, &e0.ja1, be0, &e0.ja2);
    let ju1 = lin(al1, &e1.ja1, be1, &e1.ja2);
    let h00 = e0.hess_comb(t1, al0, be0);
    let h11 = e1.hess_comb(t0, al1, be1);
    let t0_th0 = mix(al0p, ja0, be0p, jb0);
    let t1_th1 = mix(al1p, ja1, be1p, jb1);
    // hpsi = Hess Psi - K Hess chi (K = sum_a delta_a kappa_a; Hess chi is the identity in
    // the (t0, t1) blocks).
    let mut hpsi = [[0.0; 8]; 8];
    for i in 0..3 {
        for j in 0..3 {
            hpsi[i][j] = h00[i][j];
            hpsi[3 + i][3 + j] = h11[i][j];
            // d2 Psi/dt0_i dt1_j = JU1[i][j] + JU0[j][i], minus K on the diagonal.
            let x = ju1[i][j] + ju0[j][i] - if i == j { big_k } else { 0.0 };
            hpsi[i][3 + j] = x;
            hpsi[3 + j][i] = x;
        }
        hpsi[i][6] = t0_th0[i];
        hpsi[6][i] = t0_th0[i];
        hpsi[3 + i][6] = u0p[i];
        hpsi[6][3 + i] = u0p[i];
        hpsi[i][7] = u1p[i];
        hpsi[7][i] = u1p[i];
        hpsi[3 + i][7] = t1_th1[i];
        hpsi[7][3 + i] = t1_th1[i];
    }
    hpsi[6][6] = -f::dot(t1, u0);
    hpsi[7][7] = -f::dot(t0, u1);

    // Twist: m = theta1 - theta0 + r(t0, t1).
    let r = ref_twist_value([t0, t1], [e0.a1, e1.a1], st.frame.ref_twist_prev);
    let (gr, hr) = ref_twist_tangent_derivatives(t0, t1, st.frame.t_old[0], st.frame.t_old[1]);
    let dm = e1.theta - e0.theta + r - st.m0;
    let gm = [gr[0], gr[1], gr[2], gr[3], gr[4], gr[5], -1.0, 1.0];

    // Sum in x.
    let (cb, ct) = (2.0 * st.bend, 2.0 * st.twist);
    let energy = st.bend * (delta[0] * delta[0] + delta[1] * delta[1]) + st.twist * dm * dm;
    let gx: [f64; 8] = std::array::from_fn(|k| cb * gk[k] + ct * dm * gm[k]);
    let mut hx = [[0.0; 8]; 8];
    for i in 0..8 {
        for j in i..8 {
            let bend = g_kappa[0][i] * g_kappa[0][j]
                + g_kappa[1][i] * g_kappa[1][j]
                + (hpsi[i][j] - gk[i] * g_chi[j] - g_chi[i] * gk[j]) * w;
            let curv = if i < 6 && j < 6 { dm * hr[i][j] } else { 0.0 };
            let v = cb * bend + ct * (gm[i] * gm[j] + curv);
            hx[i][j] = v;
            hx[j][i] = v;
        }
    }
    let (g, h) = tangents_to_edges_8(edges, &gx, &hx);
    (energy, g, h)
}

/// The gradient part of [`tangents_to_edges_8`]: the gradient in `(e0, e1, theta0, theta1)`
/// from that in `(t0, t1, theta0, theta1)`, with each edge's `g . t` and `p = P g` (the edge
/// gradient is `p / |e|`).
#[inline(always)]
fn tangent_gradient_to_edges(
    edges: [&EdgeFrame; 2],
    gx: &[f64; 8],
) -> ([f64; 8], [f64; 2], [[f64; 3]; 2]) {
    let t = [edges[0].t, edges[1].t];
    let il = [1.0 / edges[0].len, 1.0 / edges[1].len];
    let gt: [f64; 2] =
        std::array::from_fn(|j| f::dot([gx[3 * j], gx[3 * j + 1], gx[3 * j + 2]], t[j]));
    let p: [[f64; 3]; 2] =
        std::array::from_fn(|j| std::array::from_fn(|a| gx[3 * j + a] - t[j][a] * gt[j]));
    let mut ge = [0.0; 8];
    for j in 0..2 {
        for a in 0..3 {
            ge[3 * j + a] = p[j][a] * il[j];
        }
    }
    ge[6] = gx[6];
    ge[7] = gx[7];
    (ge, gt, p)
}

/// Chain rule through `t^j = e^j / |e^j|` for the two edges, the twist angles passing
/// through: gradient and Hessian in `(e0, e1, theta0, theta1)` from those in
/// `(t0, t1, theta0, theta1)`. With `J_j = P_j / |e_j|`, `P_j = I - t_j t_j^T`, block by block:
/// `P_j H P_k = H - u t_k^T - t_j v^T + (t_j . u) t_j t_k^T` with `u = H t_k`, `v = H^T t_j`,
/// plus, on each edge's diagonal block, the tangent's second derivative contracted with the
/// gradient, `-(p t^T + t p^T + (g.t) P) / |e|^2`, `p = P g`.
#[inline(always)]
fn tangents_to_edges_8(
    edges: [&EdgeFrame; 2],
    gx: &[f64; 8],
    hx: &[[f64; 8]; 8],
) -> (SVector<f64, 8>, SMatrix<f64, 8, 8>) {
    let t = [edges[0].t, edges[1].t];
    let il = [1.0 / edges[0].len, 1.0 / edges[1].len];
    // `J_j x` for a 3-vector `x` of edge j.
    let proj = |j: usize, x: [f64; 3]| -> [f64; 3] {
        let d = f::dot(t[j], x);
        std::array::from_fn(|a| (x[a] - t[j][a] * d) * il[j])
    };
    let (ge, gt, p) = tangent_gradient_to_edges(edges, gx);
    let ge = SVector::<f64, 8>::from(ge);
    let mut he = SMatrix::<f64, 8, 8>::zeros();
    // Position blocks (j, k), k >= j.
    for (j, k) in [(0, 0), (0, 1), (1, 1)] {
        let h: M3 = std::array::from_fn(|a| std::array::from_fn(|b| hx[3 * j + a][3 * k + b]));
        let (tj, tk) = (t[j], t[k]);
        let u: [f64; 3] = std::array::from_fn(|a| f::dot(h[a], tk));
        let v = mul_t(&h, tj);
        let s = f::dot(tj, u);
        let w = il[j] * il[k];
        for a in 0..3 {
            // Diagonal blocks: the upper triangle, mirrored (exactly symmetric).
            for b in if j == k { a } else { 0 }..3 {
                let x = (h[a][b] - u[a] * tk[b] - tj[a] * v[b] + s * tj[a] * tk[b]) * w;
                he[(3 * j + a, 3 * k + b)] = x;
                he[(3 * k + b, 3 * j + a)] = x;
            }
        }
    }
    // Position-angle columns and the angle block.
    for c in 6..8 {
        for j in 0..2 {
            let col = proj(j, [hx[3 * j][c], hx[3 * j + 1][c], hx[3 * j + 2][c]]);
            for a in 0..3 {
                he[(3 * j + a, c)] = col[a];
                he[(c, 3 * j + a)] = col[a];
            }
        }
        for d in 6..8 {
            he[(c, d)] = hx[c][d];
        }
    }
    for j in 0..2 {
        let (tj, p, gt) = (t[j], p[j], gt[j]);
        let w = il[j] * il[j];
        for a in 0..3 {
            for b in a..3 {
                let pab = (if a == b { 1.0 } else { 0.0 }) - tj[a] * tj[b];
                let x = he[(3 * j + a, 3 * j + b)] - w * (p[a] * tj[b] + tj[a] * p[b] + gt * pab);
                he[(3 * j + a, 3 * j + b)] = x;
                he[(3 * j + b, 3 * j + a)] = x;
            }
        }
    }
    (ge, he)
}

/// Bending and twist as one term, each node's stencil by [`node_local`] and scattered once;
/// its energy alone and its gradient alone (explicit integration) as the separate terms.
/// Holds the edge frames of the last assembly as scratch, so that an assembly allocates
/// nothing (a term evaluated from two threads at once computes the second into a fresh
/// vector).
///
/// The assembly runs on the calling thread. Computing the edge frames and the stencils on
/// rayon's threads (tried from 50 elements on) cost more than it saved on 2 cores: every
/// assembly handed work to the pool and waited for it (futex wake-ups were a third of the
/// samples), and the S-start took 1.4 to 2 times as long at 50 to 200 elements and the same
/// at 400 (guide, "What an iteration costs").
#[derive(Default)]
pub struct BendTwist {
    scratch: Mutex<Vec<EdgeFrame>>,
}

impl BendTwist {
    /// Every edge's frame at `q`, passed to `f` (in the scratch buffer, or a fresh one when
    /// another thread holds it).
    fn with_frames<R>(&self, ctx: &Ctx, q: &[f64], f: impl FnOnce(&[EdgeFrame]) -> R) -> R {
        let mut fresh = Vec::new();
        let mut guard = match self.scratch.try_lock() {
            Ok(g) => Some(g),
            Err(TryLockError::Poisoned(p)) => Some(p.into_inner()),
            Err(TryLockError::WouldBlock) => None,
        };
        let edges = guard.as_deref_mut().unwrap_or(&mut fresh);
        edges.clear();
        edges.extend((0..ctx.model.nodes - 1).map(|j| {
            let (e, t_old, a1_old) = super::edge_at(ctx, q, j);
            EdgeFrame::new(e, t_old, a1_old, q[dof::edge(j)])
        }));
        f(edges)
    }
}

impl Term for BendTwist {
    fn name(&self) -> &'static str {
        "bend+twist"
    }
    fn eval(&self, ctx: &Ctx, q: &[f64], out: Option<&mut Assembly>, project: bool) -> f64 {
        let nodes = ctx.model.nodes;
        let Some(asm) = out else {
            // The bending and the twist of a node from one evaluation of its strains (the
            // same numbers as `BendStencil::eval + TwistStencil::eval`, which compute them
            // once each).
            let mut e = 0.0;
            for i in 1..nodes - 1 {
                let st = NodeStencil::of(ctx, i);
                let y = intrinsic(q, i);
                let (e0, e1) = (V3([y[0], y[1], y[2]]), V3([y[3], y[4], y[5]]));
                let s = frames::strains(&e0, &e1, &y[6], &y[7], st.frame);
                let (d1, d2) = (s.kappa[0] - st.kappa0[0], s.kappa[1] - st.kappa0[1]);
                let d = s.twist - st.m0;
                e += (d1 * d1 + d2 * d2) * st.bend + d * d * st.twist;
            }
            return e;
        };
        self.with_frames(ctx, q, |edges| {
            let mut e = 0.0;
            for i in 1..nodes - 1 {
                let local = node_local(&NodeStencil::of(ctx, i), [&edges[i - 1], &edges[i]]);
                e += add_local(asm, i, local, project);
            }
            e
        })
    }
    fn reusable_hessian(&self) -> bool {
        true
    }
    fn value_gradient(&self, ctx: &Ctx, q: &[f64], grad: &mut [f64]) -> f64 {
        self.with_frames(ctx, q, |edges| {
            let mut e = 0.0;
            for i in 1..ctx.model.nodes - 1 {
                let (v, g) =
                    node_local_gradient(&NodeStencil::of(ctx, i), [&edges[i - 1], &edges[i]]);
                add_gradient(grad, i, &g);
                e += v;
            }
            e
        })
    }
    fn gradient(&self, ctx: &Ctx, q: &[f64], grad: &mut [f64], _scratch: &mut Assembly) -> f64 {
        stencil::gradient_nodes(
            ctx,
            q,
            grad,
            |i| split(&NodeStencil::of(ctx, i)),
            |(b, t), y| {
                let (vb, gb) = stencil::bend_gradient(b, y);
                let (vt, gt) = stencil::twist_gradient(t, y);
                (vb + vt, std::array::from_fn(|k| gb[k] + gt[k]))
            },
        )
    }
}

/// The bending and the twist stencil of a node.
fn split<'a>(st: &NodeStencil<'a>) -> (BendStencil<'a>, TwistStencil<'a>) {
    (
        BendStencil {
            frame: st.frame,
            kappa0: st.kappa0,
            coef: st.bend,
        },
        TwistStencil {
            frame: st.frame,
            m0: st.m0,
            coef: st.twist,
        },
    )
}

#[cfg(test)]
#[path = "bend_twist_tests.rs"]
mod tests;
