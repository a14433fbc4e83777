//! Closed-form derivatives of the bending and of the twist stencil, each on its own (a
//! reference: real runs use the fused stencil of [`crate::energy::bend_twist`]), exact with the
//! reference frames transported in time from the step's frozen frames.
//!
//! The twist is the solid-angle form of [`crate::energy::reftwist`] with the chain rule
//! through `t = e / |e|`; the bending is a sum of products of functions of one edge (see
//! [`bend_local`]). The tests compare both with the staged jets on random, strongly bent
//! stencils.

use super::jets::EdgeJets;
use super::terms::StencilDerivatives;
use crate::energy::jet::Jet;
use crate::energy::local::Local;
use crate::energy::reftwist::{ref_twist_tangent_derivatives, ref_twist_value};
use crate::energy::stencil::{self, BendStencil, TwistStencil};
use crate::rod::vec3::f;
use nalgebra::{SMatrix, SVector};

/// Closed-form bending and twist derivatives (gradients alone, for explicit integration,
/// those of the real path: [`stencil::bend_gradient`], [`stencil::twist_gradient`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Closed;

/// Chain rule through `t = e / |e|` for each of the two edges: gradient and Hessian in the
/// edge vectors from those in the tangents.
pub fn tangents_to_edges(
    t: [[f64; 3]; 2],
    len: [f64; 2],
    g: &[f64; 6],
    h: &[[f64; 6]; 6],
) -> ([f64; 6], [[f64; 6]; 6]) {
    // J_j = (I - t t^T) / |e_j| (symmetric).
    let jac = |j: usize| -> [[f64; 3]; 3] {
        std::array::from_fn(|a| {
            std::array::from_fn(|b| ((if a == b { 1.0 } else { 0.0 }) - t[j][a] * t[j][b]) / len[j])
        })
    };
    let js = [jac(0), jac(1)];
    let mut ge = [0.0; 6];
    for j in 0..2 {
        for a in 0..3 {
            ge[3 * j + a] = (0..3).map(|b| js[j][a][b] * g[3 * j + b]).sum();
        }
    }
    let mut he = [[0.0; 6]; 6];
    for bj in 0..2 {
        for bk in 0..2 {
            // J_j^T H_jk J_k.
            let mut m = [[0.0; 3]; 3];
            for a in 0..3 {
                for c in 0..3 {
                    m[a][c] = (0..3)
                        .map(|b| h[3 * bj + a][3 * bk + b] * js[bk][b][c])
                        .sum();
                }
            }
            for a in 0..3 {
                for c in 0..3 {
                    he[3 * bj + a][3 * bk + c] = (0..3).map(|b| js[bj][b][a] * m[b][c]).sum();
                }
            }
        }
    }
    // Second derivative of t contracted with the tangent gradient:
    // -(p t^T + t p^T + (g.t) P) / |e|^2, p = P g.
    for j in 0..2 {
        let gj = [g[3 * j], g[3 * j + 1], g[3 * j + 2]];
        let tj = t[j];
        let gt = f::dot(gj, tj);
        let p = f::sub(gj, f::scale(tj, gt));
        let w = 1.0 / (len[j] * len[j]);
        for a in 0..3 {
            for b in 0..3 {
                let pab = (if a == b { 1.0 } else { 0.0 }) - tj[a] * tj[b];
                he[3 * j + a][3 * j + b] -= w * (p[a] * tj[b] + tj[a] * p[b] + gt * pab);
            }
        }
    }
    (ge, he)
}

/// Value, gradient and Hessian of the twist stencil in closed form.
pub fn twist_local(st: &TwistStencil, edges: [&EdgeJets; 2], y: &[f64; 8]) -> Local {
    let fr = st.frame;
    let val = |v: &[Jet<3>; 3]| [v[0].v, v[1].v, v[2].v];
    let t = [val(&edges[0].t), val(&edges[1].t)];
    let a = [val(&edges[0].a1), val(&edges[1].a1)];
    let len = [edges[0].len.v, edges[1].len.v];
    let r = ref_twist_value(t, a, fr.ref_twist_prev);
    let (gt, ht) = ref_twist_tangent_derivatives(t[0], t[1], fr.t_old[0], fr.t_old[1]);
    let (ge, he) = tangents_to_edges(t, len, &gt, &ht);
    let d = y[7] - y[6] + r - st.m0;
    let c2 = 2.0 * st.coef;
    // m = theta1 - theta0 + r: gradient (ge, -1, 1), Hessian he in the edge block.
    let gm = [ge[0], ge[1], ge[2], ge[3], ge[4], ge[5], -1.0, 1.0];
    let grad = SVector::<f64, 8>::from_fn(|i, _| c2 * d * gm[i]);
    let hess = SMatrix::<f64, 8, 8>::from_fn(|i, j| {
        let curv = if i < 6 && j < 6 { d * he[i][j] } else { 0.0 };
        c2 * (gm[i] * gm[j] + curv)
    });
    (st.coef * d * d, grad, hess)
}

/// A function of a few of the 8 coordinates (`idx`): value, gradient and Hessian over them.
struct Block<const N: usize> {
    idx: [usize; N],
    v: f64,
    g: [f64; N],
    h: [[f64; N]; N],
}

/// `out += s A B` for functions `A`, `B` of disjoint sets of coordinates.
#[inline(always)]
fn add_product<const NA: usize, const NB: usize>(
    out: &mut Jet<8>,
    s: f64,
    a: &Block<NA>,
    b: &Block<NB>,
) {
    out.v += s * a.v * b.v;
    let (sa, sb) = (s * b.v, s * a.v);
    for i in 0..NA {
        out.g[a.idx[i]] += sa * a.g[i];
        for j in 0..NA {
            out.h[a.idx[i]][a.idx[j]] += sa * a.h[i][j];
        }
        for j in 0..NB {
            let x = s * a.g[i] * b.g[j];
            out.h[a.idx[i]][b.idx[j]] += x;
            out.h[b.idx[j]][a.idx[i]] += x;
        }
    }
    for i in 0..NB {
        out.g[b.idx[i]] += sb * b.g[i];
        for j in 0..NB {
            out.h[b.idx[i]][b.idx[j]] += sb * b.h[i][j];
        }
    }
}

/// Component `k` of edge `j`'s tangent as a function of its edge vector.
fn tangent(e: &EdgeJets, j: usize, k: usize) -> Block<3> {
    let t = &e.t[k];
    Block {
        idx: [3 * j, 3 * j + 1, 3 * j + 2],
        v: t.v,
        g: t.g,
        h: t.h,
    }
}

/// Component `k` of edge `j`'s material directors `(d1, d2)` as functions of its edge vector
/// and twist angle `theta` (`d1 = cos a1 + sin a2`, `d2 = cos a2 - sin a1`).
fn directors(e: &EdgeJets, j: usize, k: usize, theta: f64) -> [Block<4>; 2] {
    let (s, c) = theta.sin_cos();
    let (a, b) = (&e.a1[k], &e.a2[k]);
    let idx = [3 * j, 3 * j + 1, 3 * j + 2, 6 + j];
    let d1v = c * a.v + s * b.v;
    let d2v = c * b.v - s * a.v;
    let mut d1 = Block {
        idx,
        v: d1v,
        g: [0.0; 4],
        h: [[0.0; 4]; 4],
    };
    let mut d2 = Block {
        idx,
        v: d2v,
        g: [0.0; 4],
        h: [[0.0; 4]; 4],
    };
    for p in 0..3 {
        let g1 = c * a.g[p] + s * b.g[p];
        let g2 = c * b.g[p] - s * a.g[p];
        d1.g[p] = g1;
        d2.g[p] = g2;
        for r in 0..3 {
            d1.h[p][r] = c * a.h[p][r] + s * b.h[p][r];
            d2.h[p][r] = c * b.h[p][r] - s * a.h[p][r];
        }
        // d/dtheta d1 = d2, d/dtheta d2 = -d1.
        d1.h[p][3] = g2;
        d1.h[3][p] = g2;
        d2.h[p][3] = -g1;
        d2.h[3][p] = -g1;
    }
    d1.g[3] = d2v;
    d2.g[3] = -d1v;
    d1.h[3][3] = -d1v;
    d2.h[3][3] = -d2v;
    [d1, d2]
}

/// Value, gradient and Hessian of the bending stencil in closed form: with `chi = 1 + t0.t1`,
/// the integrated curvatures are `kappa_1 = (t0 . d2^1 - t1 . d2^0) / chi` and
/// `kappa_2 = (t1 . d1^0 - t0 . d1^1) / chi` (the components of `kb = 2 t0 x t1 / chi` on the
/// mean material frame), each a sum of products of functions of one edge; the edges' tangents
/// and transported directors come with their derivatives in [`EdgeJets`].
pub fn bend_local(st: &BendStencil, edges: [&EdgeJets; 2], y: &[f64; 8]) -> Local {
    let mut psi = [Jet::<8>::cst(0.0), Jet::<8>::cst(0.0)];
    let mut chi = Jet::<8>::cst(1.0);
    let d0: [[Block<4>; 2]; 3] = std::array::from_fn(|k| directors(edges[0], 0, k, y[6]));
    let d1: [[Block<4>; 2]; 3] = std::array::from_fn(|k| directors(edges[1], 1, k, y[7]));
    for k in 0..3 {
        let t0 = tangent(edges[0], 0, k);
        let t1 = tangent(edges[1], 1, k);
        add_product(&mut psi[0], 1.0, &t0, &d1[k][1]);
        add_product(&mut psi[0], -1.0, &t1, &d0[k][1]);
        add_product(&mut psi[1], 1.0, &t1, &d0[k][0]);
        add_product(&mut psi[1], -1.0, &t0, &d1[k][0]);
        add_product(&mut chi, 1.0, &t0, &t1);
    }
    // kappa = psi / chi: grad = (grad psi - kappa grad chi) / chi,
    // Hess = (Hess psi - kappa Hess chi - grad kappa grad chi^T - grad chi grad kappa^T) / chi.
    let w = 1.0 / chi.v;
    let mut energy = 0.0;
    let mut grad = SVector::<f64, 8>::zeros();
    let mut hess = SMatrix::<f64, 8, 8>::zeros();
    let c2 = 2.0 * st.coef;
    for a in 0..2 {
        let kappa = psi[a].v * w;
        let gk: [f64; 8] = std::array::from_fn(|i| (psi[a].g[i] - kappa * chi.g[i]) * w);
        let delta = kappa - st.kappa0[a];
        energy += st.coef * delta * delta;
        for i in 0..8 {
            grad[i] += c2 * delta * gk[i];
            for j in 0..8 {
                let hk =
                    (psi[a].h[i][j] - kappa * chi.h[i][j] - gk[i] * chi.g[j] - chi.g[i] * gk[j])
                        * w;
                hess[(i, j)] += c2 * (gk[i] * gk[j] + delta * hk);
            }
        }
    }
    (energy, grad, hess)
}

impl StencilDerivatives for Closed {
    fn bend(&self, st: &BendStencil, edges: [&EdgeJets; 2], y: &[f64; 8]) -> Local {
        bend_local(st, edges, y)
    }
    fn twist(&self, st: &TwistStencil, edges: [&EdgeJets; 2], y: &[f64; 8]) -> Local {
        twist_local(st, edges, y)
    }
    fn bend_gradient(&self, st: &BendStencil, y: &[f64; 8]) -> (f64, [f64; 8]) {
        stencil::bend_gradient(st, y)
    }
    fn twist_gradient(&self, st: &TwistStencil, y: &[f64; 8]) -> (f64, [f64; 8]) {
        stencil::twist_gradient(st, y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::reference::testing::{assert_matches, stencil};

    /// The closed form equals the staged jets (themselves checked against hyper-dual numbers
    /// and finite differences) on random, strongly bent stencils with frozen frames away from
    /// the current tangents.
    #[test]
    fn closed_twist_matches_the_jets() {
        for seed in 1..=300 {
            let (frame, y, mut r) = stencil(seed);
            let st = TwistStencil {
                frame: &frame,
                m0: 0.5 * r.sym(),
                coef: 1.0 + r.sym(),
            };
            let edges = EdgeJets::of_stencil(&frame, &y);
            assert_matches(
                twist_local(&st, [&edges[0], &edges[1]], &y),
                st.derivatives(y),
                seed,
            );
        }
    }

    /// The closed-form bending stencil equals the staged jets on random, strongly bent
    /// stencils with frozen frames away from the current tangents.
    #[test]
    fn closed_bend_matches_the_jets() {
        for seed in 1..=300 {
            let (frame, y, mut r) = stencil(seed);
            let st = BendStencil {
                frame: &frame,
                kappa0: [0.5 * r.sym(), 0.5 * r.sym()],
                coef: 1.0 + r.sym(),
            };
            let edges = EdgeJets::of_stencil(&frame, &y);
            assert_matches(
                bend_local(&st, [&edges[0], &edges[1]], &y),
                st.derivatives(y),
                seed,
            );
        }
    }
}
