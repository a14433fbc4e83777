//! The Newton system's storage and its factorisation: a gradient and a symmetric band
//! Hessian, and the band Cholesky that solves with it.
//!
//! Every Hessian the simulator assembles couples only coordinates within one node-centred
//! stencil of the interleaved layout (`x_{i-1}, theta^{i-1}, x_i, theta^i, x_{i+1}`: 11
//! consecutive coordinates), so it is a band of half-width [`dof::HALF_BANDWIDTH`]. An
//! [`Assembly`] keeps the upper triangle of that band in compressed-column form with a
//! pattern fixed at construction: energy terms and contact models add into it
//! ([`Assembly::add_h`], [`Assembly::grad`]), Newton holds coordinates ([`Assembly::fix`]) and
//! factorises it ([`cholesky::LinSolver`]), the conic program reads it as a sparse matrix.
//! Nothing here knows what the coordinates mean beyond the bandwidth.
//!
//! A term that couples coordinates far apart (the self-contact of two parts of the body,
//! [`crate::energy::self_contact`]) adds its Hessian as a low-rank part `U U^T` beside the
//! band: columns [`LowRank`] of at most 12 entries ([`Assembly::add_low_rank`]). The band
//! factorisation solves with the whole matrix by the Sherman-Morrison-Woodbury identity
//! ([`cholesky::LinSolver`]), [`Assembly::mul`] multiplies by it, and [`Assembly::fix`] holds a
//! coordinate in it too. Without such terms the low-rank part is empty and costs nothing.

pub mod cholesky;

use crate::rod::dof;

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
    /// Columns of the low-rank part `U U^T` of the Hessian (outside the band's pattern).
    pub low_rank: Vec<LowRank>,
    w: usize,
}

/// Entries per [`LowRank`] column: the coordinates of two edges' four nodes.
pub const LOW_RANK_ENTRIES: usize = 12;

/// One column `u` of the low-rank part `U U^T` of a Hessian: `val[r]` at coordinate `idx[r]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LowRank {
    /// Coordinates.
    pub idx: [usize; LOW_RANK_ENTRIES],
    /// Entries.
    pub val: [f64; LOW_RANK_ENTRIES],
}

impl LowRank {
    /// `u . x`.
    #[inline]
    pub fn dot(&self, x: &[f64]) -> f64 {
        self.idx.iter().zip(&self.val).map(|(&k, v)| v * x[k]).sum()
    }
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
            low_rank: Vec::new(),
            w,
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
    /// Zero gradient and Hessian.
    pub fn clear(&mut self) {
        self.grad.fill(0.0);
        self.values.fill(0.0);
        self.low_rank.clear();
    }

    /// Add the column `u` (entries `val` at coordinates `idx`) to the low-rank part `U U^T`.
    pub fn add_low_rank(&mut self, idx: [usize; LOW_RANK_ENTRIES], val: [f64; LOW_RANK_ENTRIES]) {
        self.low_rank.push(LowRank { idx, val });
    }

    /// The low-rank part's share of the moves `target` of the coordinates `held` (about to be
    /// held by [`Assembly::fix`]) in the gradient of the others: `g_i += (U U^T d)_i` for every
    /// coordinate `i` not held, `d` the targets of the held ones. The band's share is the
    /// caller's, from the rows it captured.
    pub fn low_rank_held_moves(&mut self, held: &[bool], target: &[f64]) {
        for u in &self.low_rank {
            let s: f64 = u
                .idx
                .iter()
                .zip(&u.val)
                .filter(|(&k, _)| held[k])
                .map(|(&k, v)| v * target[k])
                .sum();
            if s == 0.0 {
                continue;
            }
            for (&k, v) in u.idx.iter().zip(&u.val) {
                if !held[k] {
                    self.grad[k] += v * s;
                }
            }
        }
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
    /// Add the 3 x 3 block `h` at rows `i0..i0 + 3` and columns `j0..j0 + 3`: all of it when
    /// `i0 + 3 <= j0` (an off-diagonal block, upper triangle), its upper triangle when
    /// `i0 == j0` (a diagonal block). One column lookup per column instead of one per entry.
    #[inline]
    pub fn add_block3(&mut self, i0: usize, j0: usize, h: &[[f64; 3]; 3]) {
        let diagonal = i0 == j0;
        debug_assert!(
            diagonal || i0 + 3 <= j0,
            "block ({i0},{j0}) overlaps the diagonal"
        );
        debug_assert!(j0 + 2 - i0 <= self.w, "block ({i0},{j0}) outside the band");
        for s in 0..3 {
            let j = j0 + s;
            let base = self.col_ptr[j] + i0 - j.saturating_sub(self.w);
            let rows = if diagonal { s + 1 } else { 3 };
            for (r, v) in self.values[base..base + rows].iter_mut().enumerate() {
                *v += h[r][s];
            }
        }
    }
    /// Symmetric entry `(i, j)` of the band (the low-rank part not included).
    pub fn h(&self, i: usize, j: usize) -> f64 {
        if i.abs_diff(j) > self.w {
            0.0
        } else {
            self.values[self.pos(i, j)]
        }
    }
    /// Hold coordinate `k` fixed: zero its gradient, row and column, and put 1 on the diagonal.
    pub fn fix(&mut self, k: usize) {
        self.grad[k] = 0.0;
        for u in &mut self.low_rank {
            for (&i, v) in u.idx.iter().zip(u.val.iter_mut()) {
                if i == k {
                    *v = 0.0;
                }
            }
        }
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
    /// `y = H x` for the symmetric matrix (band and low-rank part).
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
        for u in &self.low_rank {
            let s = u.dot(x);
            for (&k, v) in u.idx.iter().zip(&u.val) {
                y[k] += v * s;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `add_block3` adds what `add_h` entry by entry adds, diagonal blocks by their upper
    /// triangle, at the first columns (where the band is cut off) and inside.
    #[test]
    fn block_adds_match_entrywise_adds() {
        let n = dof::count(6);
        let h: [[f64; 3]; 3] =
            std::array::from_fn(|r| std::array::from_fn(|s| (1 + 3 * r + s) as f64));
        for (i0, j0) in [(0, 0), (0, 4), (4, 4), (8, 12), (n - 3, n - 3)] {
            let mut block = Assembly::new(n);
            let mut entries = Assembly::new(n);
            block.add_block3(i0, j0, &h);
            for r in 0..3 {
                for s in 0..3 {
                    if i0 != j0 || r <= s {
                        entries.add_h(i0 + r, j0 + s, h[r][s]);
                    }
                }
            }
            assert_eq!(block.values, entries.values, "block ({i0}, {j0})");
        }
    }

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
}
