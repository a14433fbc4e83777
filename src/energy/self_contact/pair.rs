//! One pair of edges: its closest points and gap, a cheap bound on its distance, and the
//! exact gradient and Hessian of its distance (see the module doc of
//! [`crate::energy::self_contact`]).

use super::{node_x, SelfContact};
use crate::band::{Assembly, LOW_RANK_ENTRIES};
use crate::rod::dof;
use crate::rod::segments::{closest, Closest};
use crate::rod::vec3::f;

/// One pair's state at a configuration.
#[derive(Clone, Copy, Debug)]
pub struct PairState {
    /// The two edges.
    pub edges: (usize, usize),
    /// Their closest points.
    pub closest: Closest,
    /// The gap `d - a` (m).
    pub gap: f64,
}

impl SelfContact {
    /// The four nodes of the pair `(i, j)` at `q`: `x_i, x_{i+1}, x_j, x_{j+1}`.
    pub(super) fn nodes(q: &[f64], i: usize, j: usize) -> [[f64; 3]; 4] {
        [
            node_x(q, i),
            node_x(q, i + 1),
            node_x(q, j),
            node_x(q, j + 1),
        ]
    }

    /// A pair's state at `q`.
    pub fn pair(&self, q: &[f64], i: usize, j: usize) -> PairState {
        self.pair_at((i, j), Self::nodes(q, i, j))
    }

    /// The state of the pair `edges` with its four nodes at `x`.
    pub(super) fn pair_at(&self, edges: (usize, usize), x: [[f64; 3]; 4]) -> PairState {
        let c = closest(x[0], x[1], x[2], x[3]);
        PairState {
            edges,
            closest: c,
            gap: c.dist - self.a,
        }
    }

    /// Whether the pair `(i, j)` is certainly beyond the activation gap at `q`
    /// ([`Self::distance_bound`] exceeds `a + g_hat`): cheaper than the closest points for the
    /// candidates that are far.
    pub(super) fn surely_apart(&self, q: &[f64], i: usize, j: usize) -> bool {
        self.distance_bound(q, i, j) > self.a + self.g_hat
    }

    /// A lower bound of the pair's distance at `q`: the distance of the edges' midpoints less
    /// their half-lengths.
    pub(super) fn distance_bound(&self, q: &[f64], i: usize, j: usize) -> f64 {
        let [a0, a1, b0, b1] = Self::nodes(q, i, j);
        let mid = f::norm(f::sub(f::add(a0, a1), f::add(b0, b1)));
        0.5 * (mid - f::norm(f::sub(a1, a0)) - f::norm(f::sub(b1, b0)))
    }

    /// The gradient of a pair's distance over its four nodes' coordinates, and their indices.
    pub(super) fn distance_gradient(
        p: &PairState,
    ) -> ([usize; LOW_RANK_ENTRIES], [f64; LOW_RANK_ENTRIES]) {
        let (i, j) = p.edges;
        let c = &p.closest;
        let n = f::scale(c.delta, 1.0 / c.dist);
        let w = [1.0 - c.s, c.s, -(1.0 - c.t), -c.t];
        let nodes = [i, i + 1, j, j + 1];
        let mut idx = [0; LOW_RANK_ENTRIES];
        let mut val = [0.0; LOW_RANK_ENTRIES];
        for (r, (&node, &wr)) in nodes.iter().zip(&w).enumerate() {
            for k in 0..3 {
                idx[3 * r + k] = dof::node(node) + k;
                val[3 * r + k] = wr * n[k];
            }
        }
        (idx, val)
    }

    /// The exact Hessian of a pair's distance over its four nodes' twelve coordinates (order
    /// `x_i, x_{i+1}, x_j, x_{j+1}`). With `delta = A(s, t) x` and `F = |delta|`, the closest
    /// points' parameters that lie inside `(0, 1)` (the free ones, `z`) move with `x`, so the
    /// Hessian is the Schur complement `F_xx - F_xz F_zz^-1 F_zx` of the Hessian of `F` over
    /// `(x, z)`; a parameter at an end of its edge stays there. Where the two edges are
    /// parallel (`F_zz` singular) `s` is held as well.
    pub fn distance_hessian(&self, q: &[f64], p: &PairState) -> [[f64; 12]; 12] {
        let (i, j) = p.edges;
        let c = &p.closest;
        let d = c.dist;
        let n = f::scale(c.delta, 1.0 / d);
        let e1 = f::sub(node_x(q, i + 1), node_x(q, i));
        let e2 = f::sub(node_x(q, j + 1), node_x(q, j));
        // P v / d with P = I - n n^T.
        let proj = |v: [f64; 3]| f::scale(f::sub(v, f::scale(n, f::dot(n, v))), 1.0 / d);
        let w = [1.0 - c.s, c.s, -(1.0 - c.t), -c.t];
        let mut h = [[0.0; 12]; 12];
        for a in 0..4 {
            for b in 0..4 {
                for r in 0..3 {
                    for k in 0..3 {
                        let pij = if r == k { 1.0 } else { 0.0 } - n[r] * n[k];
                        h[3 * a + r][3 * b + k] = w[a] * w[b] * pij / d;
                    }
                }
            }
        }
        // Mixed rows F_xz: for s, (dA/ds)^T n + A^T P e1 / d; for t, (dA/dt)^T n - A^T P e2 / d.
        let pe1 = proj(e1);
        let pe2 = proj(e2);
        let mut fxz = [[0.0; 12]; 2];
        for a in 0..4 {
            for r in 0..3 {
                fxz[0][3 * a + r] = w[a] * pe1[r];
                fxz[1][3 * a + r] = -w[a] * pe2[r];
            }
        }
        for r in 0..3 {
            fxz[0][r] -= n[r];
            fxz[0][3 + r] += n[r];
            fxz[1][6 + r] += n[r];
            fxz[1][9 + r] -= n[r];
        }
        let fss = f::dot(e1, pe1);
        let ftt = f::dot(e2, pe2);
        let fst = -f::dot(e1, pe2);
        let inside = |x: f64| x > 0.0 && x < 1.0;
        let (mut free_s, free_t) = (inside(c.s), inside(c.t));
        if free_s && free_t && fss * ftt - fst * fst <= 1e-10 * fss * ftt {
            free_s = false;
        }
        let mut sub = |g: &[f64; 12], k: &[f64; 12], coef: f64| {
            for r in 0..12 {
                for col in 0..12 {
                    h[r][col] -= coef * g[r] * k[col];
                }
            }
        };
        match (free_s, free_t) {
            (true, true) => {
                let det = fss * ftt - fst * fst;
                let (iss, itt, ist) = (ftt / det, fss / det, -fst / det);
                sub(&fxz[0], &fxz[0], iss);
                sub(&fxz[1], &fxz[1], itt);
                sub(&fxz[0], &fxz[1], ist);
                sub(&fxz[1], &fxz[0], ist);
            }
            (true, false) => sub(&fxz[0], &fxz[0], 1.0 / fss),
            (false, true) => sub(&fxz[1], &fxz[1], 1.0 / ftt),
            (false, false) => {}
        }
        h
    }

    /// The pair's barrier Hessian `b'' grad d grad d^T + b' grad^2 d`, projected to positive
    /// semi-definite, as low-rank columns `sqrt(lambda) v` of its positive eigenpairs.
    pub(super) fn add_pair_hessian(
        &self,
        q: &[f64],
        p: &PairState,
        db: f64,
        ddb: f64,
        asm: &mut Assembly,
    ) {
        let (idx, g) = Self::distance_gradient(p);
        let hd = self.distance_hessian(q, p);
        let k = nalgebra::SMatrix::<f64, 12, 12>::from_fn(|r, c| ddb * g[r] * g[c] + db * hd[r][c]);
        let k = 0.5 * (k + k.transpose());
        let eig = k.symmetric_eigen();
        let top = eig.eigenvalues.max();
        for (l, lam) in eig.eigenvalues.iter().enumerate() {
            if *lam > 1e-12 * top {
                let v = eig.eigenvectors.column(l);
                let root = lam.sqrt();
                asm.add_low_rank(idx, std::array::from_fn(|r| root * v[r]));
            }
        }
    }
}
