//! Energy terms of the rod. Each term gives its value and, on request, its gradient and
//! Hessian (optionally projected to positive semi-definite per stencil), accumulated into an
//! [`Assembly`] with a fixed banded pattern.
//!
//! * [`stretch`]: `EA/(2 l0) (|e| - l0)^2` per edge (near-inextensibility, MODEL 1.3);
//! * [`bend`]: `B/(2 l_i) |kappa_i - kappa0_i|^2` per interior node;
//! * [`twist`]: `C/(2 l_i) (m_i - m0_i)^2` per interior node;
//! * [`gravity`]: `-sum_i m_i g . x_i`.
//!
//! Bending and twist are written once, generically over the scalar (the energy alone, and the
//! reference for every derivative). Their exact gradient and Hessian in the 8 intrinsic
//! coordinates `(e^{i-1}, e^i, theta^{i-1}, theta^i)` of the stencil come, in the implicit
//! integrator, from [`node`]: one closed form for a node's bending and twist together in
//! plain `f64` ([`node::BendTwist`], the term of [`rod_terms`]). It is tested against the
//! staged second-order jets ([`autodiff::jet`], [`stencil::Jets`]) and the per-term closed
//! forms ([`closed`]), which are tested against `num-dual` hyper-dual numbers and finite
//! differences; the chain rule to the 11 node coordinates is linear. Stretching has a
//! closed-form Hessian.

pub mod autodiff;
pub mod bend;
pub mod closed;
pub mod gravity;
pub mod node;
pub mod stencil;
pub mod stretch;
pub mod twist;

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
}

/// All elastic and gravitational terms of the rod.
pub fn rod_terms() -> Vec<Box<dyn Term>> {
    vec![
        Box::new(stretch::Stretch),
        Box::new(node::BendTwist),
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

/// Gradient and upper-triangular banded Hessian in compressed-column form, with a pattern
/// fixed at construction (half-bandwidth [`dof::HALF_BANDWIDTH`]) so that the symbolic
/// factorisation is computed once.
#[derive(Clone, Debug)]
pub struct Assembly {
    /// Gradient.
    pub grad: Vec<f64>,
    /// Column pointers of the upper triangle.
    pub col_ptr: Vec<usize>,
    /// Row indices of the upper triangle.
    pub row_idx: Vec<usize>,
    /// Values of the upper triangle.
    pub values: Vec<f64>,
    w: usize,
    /// Frame jets of every edge for the current assembly ([`stencil`]), shared by the bending
    /// and twist terms, and what they were computed for.
    edges: Vec<stencil::EdgeJets>,
    edges_key: Option<(u64, usize, Vec<f64>)>,
    generation: u64,
    /// Scratch for the edge frames of [`node::BendTwist`].
    node_edges: Vec<node::EdgeFrame>,
}

impl Assembly {
    /// An empty assembly for `n` coordinates.
    pub fn new(n: usize) -> Self {
        let w = dof::HALF_BANDWIDTH;
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for j in 0..n {
            for i in j.saturating_sub(w)..=j {
                row_idx.push(i);
            }
            col_ptr.push(row_idx.len());
        }
        let values = vec![0.0; row_idx.len()];
        Assembly {
            grad: vec![0.0; n],
            col_ptr,
            row_idx,
            values,
            w,
            edges: Vec::new(),
            edges_key: None,
            generation: 0,
            node_edges: Vec::new(),
        }
    }
    /// Half-bandwidth of the pattern.
    pub fn half_bandwidth(&self) -> usize {
        self.w
    }
    /// Dimension.
    pub fn n(&self) -> usize {
        self.grad.len()
    }
    /// Zero gradient and Hessian (a new assembly: cached edge frames are recomputed).
    pub fn clear(&mut self) {
        self.grad.fill(0.0);
        self.values.fill(0.0);
        self.generation += 1;
    }

    /// The frame jets of every edge at `q` with the frozen frames of `ctx`: computed once per
    /// assembly (between two [`Assembly::clear`]s, for the same `q` and frames) and shared by
    /// the stencil terms. Give them back with [`Assembly::put_edges`].
    pub fn take_edges(&mut self, ctx: &Ctx, q: &[f64]) -> Vec<stencil::EdgeJets> {
        let frames_id = ctx.frames.as_ptr() as usize;
        let fresh = matches!(&self.edges_key,
            Some((g, f, kq)) if *g == self.generation && *f == frames_id && kq.as_slice() == q);
        let mut edges = std::mem::take(&mut self.edges);
        if !fresh {
            let ne = ctx.model.nodes - 1;
            edges.clear();
            for j in 0..ne {
                let (e, t_old, a1_old) = edge_at(ctx, q, j);
                edges.push(stencil::EdgeJets::new(e, t_old, a1_old));
            }
            match &mut self.edges_key {
                Some((g, f, kq)) => {
                    *g = self.generation;
                    *f = frames_id;
                    kq.clear();
                    kq.extend_from_slice(q);
                }
                None => self.edges_key = Some((self.generation, frames_id, q.to_vec())),
            }
        }
        edges
    }

    /// Return the edge frames taken by [`Assembly::take_edges`].
    pub fn put_edges(&mut self, edges: Vec<stencil::EdgeJets>) {
        self.edges = edges;
    }
    #[inline]
    fn pos(&self, i: usize, j: usize) -> usize {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        debug_assert!(j - i <= self.w, "entry ({i},{j}) outside the band");
        self.col_ptr[j] + i - j.saturating_sub(self.w)
    }
    /// Add `v` to the symmetric entry `(i, j)` (once; the transpose is implied).
    #[inline]
    pub fn add_h(&mut self, i: usize, j: usize, v: f64) {
        let p = self.pos(i, j);
        self.values[p] += v;
    }
    /// Symmetric entry `(i, j)`.
    pub fn h(&self, i: usize, j: usize) -> f64 {
        if i.abs_diff(j) > self.w {
            0.0
        } else {
            self.values[self.pos(i, j)]
        }
    }
    /// Add interior node `i`'s stencil gradient and Hessian, given in its intrinsic
    /// coordinates `(e^{i-1}, e^i, theta^{i-1}, theta^i)`, at the node coordinates: the chain
    /// rule of [`autodiff::to_nodes`] written straight into the band. The stencil's 11
    /// coordinates are the band's `dof::node(i - 1) ..= dof::node(i + 1) + 2` in the order
    /// `x_{i-1}, theta^{i-1}, x_i, theta^i, x_{i+1}`, so column `b` of the node Hessian adds its
    /// upper part to one contiguous slice of column `first + b`.
    pub fn add_node_stencil(
        &mut self,
        i: usize,
        g: &nalgebra::SVector<f64, 8>,
        h: &nalgebra::SMatrix<f64, 8, 8>,
    ) {
        /// `y J` in band order for a row `y` over the intrinsic coordinates.
        #[inline(always)]
        fn band_row(y: [f64; 8]) -> [f64; 11] {
            [
                -y[0],
                -y[1],
                -y[2],
                y[6],
                y[0] - y[3],
                y[1] - y[4],
                y[2] - y[5],
                y[7],
                y[3],
                y[4],
                y[5],
            ]
        }
        let first = dof::node(i - 1);
        debug_assert_eq!(dof::node(i + 1) + 2 - first, self.w);
        let gx = band_row(std::array::from_fn(|k| g[k]));
        for (d, x) in self.grad[first..=first + self.w].iter_mut().zip(gx) {
            *d += x;
        }
        // M = H J (8 x 11, H symmetric so its columns are its rows), then column b of
        // J^T M is band_row of column b of M.
        let m: [[f64; 11]; 8] =
            std::array::from_fn(|k| band_row(std::array::from_fn(|l| h[(l, k)])));
        for b in 0..11 {
            let col = band_row(std::array::from_fn(|k| m[k][b]));
            let j = first + b;
            let start = self.col_ptr[j] + first - j.saturating_sub(self.w);
            for (v, x) in self.values[start..=start + b].iter_mut().zip(&col) {
                *v += x;
            }
        }
    }
    /// Hold coordinate `k` fixed: zero its gradient, row and column, and put 1 on the diagonal.
    pub fn fix(&mut self, k: usize) {
        self.grad[k] = 0.0;
        let n = self.n();
        // Column k's upper part is contiguous (rows k - w ..= k); the rest of row k lies one
        // entry in each later column.
        let diag = self.col_ptr[k + 1] - 1;
        self.values[self.col_ptr[k]..diag].fill(0.0);
        self.values[diag] = 1.0;
        for j in k + 1..=(k + self.w).min(n - 1) {
            self.values[self.col_ptr[j] + k - j.saturating_sub(self.w)] = 0.0;
        }
    }

    /// Row `k` of the symmetric matrix over columns `k - w ..= k + w` into `out` (zero outside
    /// the matrix).
    pub fn row(&self, k: usize, out: &mut [f64]) {
        let w = self.w;
        debug_assert_eq!(out.len(), 2 * w + 1);
        let n = self.n();
        // Columns k - w ..= k: column k's upper part, right-aligned at out[w].
        let col = &self.values[self.col_ptr[k]..self.col_ptr[k + 1]];
        out[..w + 1 - col.len()].fill(0.0);
        out[w + 1 - col.len()..=w].copy_from_slice(col);
        for r in w + 1..=2 * w {
            let j = k + r - w;
            out[r] = if j < n {
                self.values[self.col_ptr[j] + k - j.saturating_sub(w)]
            } else {
                0.0
            };
        }
    }
    /// `y = H x` for the symmetric matrix.
    pub fn mul(&self, x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for j in 0..self.n() {
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[p];
                let v = self.values[p];
                y[i] += v * x[j];
                if i != j {
                    y[j] += v * x[i];
                }
            }
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `row` and `fix` address the band as `h` and `add_h` do.
    #[test]
    fn row_and_fix_match_entrywise_access() {
        let n = dof::count(6);
        let mut asm = Assembly::new(n);
        let w = asm.half_bandwidth();
        for j in 0..n {
            for i in j.saturating_sub(w)..=j {
                asm.add_h(i, j, ((i * 31 + j * 7) as f64).sin());
            }
        }
        let mut row = vec![0.0; 2 * w + 1];
        for k in 0..n {
            asm.row(k, &mut row);
            for (r, &x) in row.iter().enumerate() {
                let j = (k + r).wrapping_sub(w);
                let want = if j < n { asm.h(k, j) } else { 0.0 };
                assert_eq!(x, want, "row {k}, column {j}");
            }
        }
        for k in [0, 5, 12, n - 1] {
            let mut fixed = asm.clone();
            fixed.fix(k);
            for i in 0..n {
                for j in 0..n {
                    let want = if i == k || j == k {
                        if i == j {
                            1.0
                        } else {
                            0.0
                        }
                    } else {
                        asm.h(i, j)
                    };
                    assert_eq!(fixed.h(i, j), want, "fix {k}: ({i}, {j})");
                }
            }
        }
    }

    /// A node stencil in intrinsic coordinates added straight into the band equals its chain
    /// rule to the 11 node coordinates ([`autodiff::to_nodes`]) added entry by entry.
    #[test]
    fn node_stencil_scatter_equals_chain_rule_then_entrywise() {
        let n = dof::count(7);
        let (mut fast, mut slow) = (Assembly::new(n), Assembly::new(n));
        for i in 1..6 {
            let g = nalgebra::SVector::<f64, 8>::from_fn(|k, _| ((k + 3 * i) as f64).cos());
            let b = nalgebra::SMatrix::<f64, 8, 8>::from_fn(|a, c| ((a * 8 + c + i) as f64).sin());
            let h = b + b.transpose();
            fast.add_node_stencil(i, &g, &h);
            let (gx, hx) = autodiff::to_nodes(&g, &h);
            let idx = dof::stencil(i);
            for a in 0..11 {
                slow.grad[idx[a]] += gx[a];
                for c in 0..11 {
                    if idx[a] <= idx[c] {
                        slow.add_h(idx[a], idx[c], hx[a * 11 + c]);
                    }
                }
            }
        }
        for k in 0..n {
            assert!((fast.grad[k] - slow.grad[k]).abs() < 1e-14, "gradient {k}");
        }
        for (p, (x, y)) in fast.values.iter().zip(&slow.values).enumerate() {
            assert!((x - y).abs() < 1e-13, "Hessian entry {p}: {x} vs {y}");
        }
    }
}
