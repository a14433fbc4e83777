//! The band Hessian's factorisation. Every assembled Hessian is a band of half-width
//! [`crate::rod::dof::HALF_BANDWIDTH`] (node-centred stencils on the interleaved coordinates),
//! so Newton factorises it with a band Cholesky ([`LinSolver`]) in preallocated storage, without
//! allocating. faer's general sparse Cholesky ([`FaerLlt`], natural ordering, symbolic analysis
//! once) gives the same factor and is the reference it is tested against; on this pattern its
//! elimination-tree reach and the column copies around it cost three times the band
//! arithmetic (`cargo bench --bench linsolve`; `lab/bench/bench.sh` keeps a record).

use super::Assembly;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// faer's sparse (simplicial) LL^T of matrices sharing one [`Assembly`] pattern: the
/// reference the band solver is tested and benchmarked against.
pub struct FaerLlt {
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    mem: MemBuffer,
    factored: bool,
}

/// The matrix was not positive definite.
#[derive(Debug, Clone, Copy)]
pub struct NotPositiveDefinite;

impl FaerLlt {
    /// Symbolic analysis of the pattern of `asm`.
    pub fn new(asm: &Assembly) -> Self {
        let n = asm.n();
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &asm.col_ptr, None, &asm.row_idx);
        let symbolic = factorize_symbolic_cholesky(
            sym,
            Side::Upper,
            SymmetricOrdering::Identity,
            CholeskySymbolicParams::default(),
        )
        .expect("symbolic Cholesky of a banded pattern");
        let l_values = vec![0.0; symbolic.len_val()];
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        FaerLlt {
            symbolic,
            l_values,
            mem: MemBuffer::new(req),
            factored: false,
        }
    }

    /// Numeric factorisation of the matrix in `asm`.
    pub fn factor(&mut self, asm: &Assembly) -> Result<(), NotPositiveDefinite> {
        let n = asm.n();
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &asm.col_ptr, None, &asm.row_idx);
        let a = SparseColMatRef::new(sym, &asm.values);
        let stack = MemStack::new(&mut self.mem);
        self.factored = false;
        self.symbolic
            .factorize_numeric_llt::<f64>(
                &mut self.l_values,
                a,
                Side::Upper,
                Default::default(),
                Par::Seq,
                stack,
                Default::default(),
            )
            .map_err(|_| NotPositiveDefinite)?;
        self.factored = true;
        Ok(())
    }

    /// Solve `A x = b` in place with the last factorisation.
    pub fn solve(&mut self, b: &mut [f64]) {
        assert!(self.factored, "solve before a successful factor");
        let n = b.len();
        let llt = faer::sparse::linalg::cholesky::LltRef::<'_, usize, f64>::new(
            &self.symbolic,
            &self.l_values,
        );
        let stack = MemStack::new(&mut self.mem);
        let rhs = MatMut::from_column_major_slice_mut(b, n, 1);
        llt.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, stack);
    }
}

/// Half-bandwidth of the band solver (that of every assembled Hessian).
const W: usize = crate::rod::dof::HALF_BANDWIDTH;
/// Entries of a row of `L` in the band.
const W1: usize = W + 1;

/// Band Cholesky in its square-root-free form `A = L D L^T` (`L` unit lower triangular, `D`
/// diagonal and positive) of matrices with the [`Assembly`] pattern (half-bandwidth
/// `W` = [`crate::rod::dof::HALF_BANDWIDTH`]). `L` is stored by rows, each padded to `W + 1`
/// entries: `rows[i][W - (i - k)]` is `L[i][k]` for `i - W <= k < i` and `rows[i][W]` is
/// `D[i]`, with zeros where `k < 0`, and `W` spare rows after the last so that every column
/// takes the same fixed-size steps (which the compiler unrolls). Without the square root the
/// chain from one pivot to the next is one division, a multiply and a multiply-add: a
/// factorisation and solve take 0.86 (200 elements) and 0.73 (50) of the `L L^T` form's time
/// (`cargo bench --bench linsolve`, one machine, against a saved baseline).
#[derive(Clone, Debug)]
pub struct LinSolver {
    rows: Vec<[f64; W1]>,
    /// `1 / D[i]`.
    inv_diag: Vec<f64>,
    /// Rows of `L` that are zero off the diagonal (held coordinates, `Assembly::fix`, and the
    /// first): the solves skip their multiply-adds, which use row `j` only.
    decoupled: Vec<bool>,
    /// Right-hand side padded with `W` leading zeros.
    rhs: Vec<f64>,
    factored: bool,
    /// The low-rank part of the last factorised matrix (see [`Woodbury`]).
    woodbury: Woodbury,
}

/// The low-rank part `U U^T` of a matrix `A + U U^T` ([`Assembly::low_rank`]), solved by the
/// Sherman-Morrison-Woodbury identity
/// `(A + U U^T)^-1 b = y - Z S^-1 U^T y`, `y = A^-1 b`, `Z = A^-1 U`, `S = I + U^T Z`:
/// one band solve per column at the factorisation, then per solve one band solve and a
/// dense `k x k` Cholesky solve (`k` the columns: a few per self-contact pair).
#[derive(Clone, Debug, Default)]
struct Woodbury {
    cols: Vec<super::LowRank>,
    /// `Z = A^-1 U`, one column per entry.
    z: Vec<Vec<f64>>,
    /// Cholesky factor of the capacitance matrix `S = I + U^T Z`.
    chol: Option<nalgebra::linalg::Cholesky<f64, nalgebra::Dyn>>,
}

impl LinSolver {
    /// Storage for matrices with the pattern of `asm`.
    pub fn new(asm: &Assembly) -> Self {
        assert_eq!(asm.half_bandwidth(), W, "the band solver's half-bandwidth");
        let n = asm.n();
        LinSolver {
            rows: vec![[0.0; W1]; n + W],
            inv_diag: vec![0.0; n],
            decoupled: vec![false; n],
            rhs: vec![0.0; n + W],
            factored: false,
            woodbury: Woodbury::default(),
        }
    }

    /// Factorise the matrix in `asm`; `Err` at the first pivot that is not positive (or not
    /// finite).
    ///
    /// Right-looking: once column `k` of `L` is known, the rank-one update of the trailing
    /// `W x W` triangle follows, each row a contiguous slice of fixed length. Its multiply-adds
    /// are independent of each other (a left-looking, dot-product order chains them through
    /// one accumulator).
    pub fn factor(&mut self, asm: &Assembly) -> Result<(), NotPositiveDefinite> {
        self.factor_band(asm)?;
        self.woodbury.cols.clear();
        self.woodbury.chol = None;
        let k = asm.low_rank.len();
        if k == 0 {
            return Ok(());
        }
        let n = asm.n();
        let mut wb = std::mem::take(&mut self.woodbury);
        wb.cols.extend_from_slice(&asm.low_rank);
        wb.z.resize_with(k, Vec::new);
        for (u, z) in wb.cols.iter().zip(wb.z.iter_mut()) {
            z.clear();
            z.resize(n, 0.0);
            for (&i, &v) in u.idx.iter().zip(&u.val) {
                z[i] += v;
            }
            self.solve_band(z);
        }
        let s = nalgebra::DMatrix::from_fn(k, k, |r, c| {
            wb.cols[r].dot(&wb.z[c]) + if r == c { 1.0 } else { 0.0 }
        });
        // Symmetrise the rounding of `U^T A^-1 U`.
        let s = 0.5 * (&s + s.transpose());
        wb.chol = nalgebra::linalg::Cholesky::new(s);
        let ok = wb.chol.is_some();
        self.woodbury = wb;
        if ok {
            Ok(())
        } else {
            self.factored = false;
            Err(NotPositiveDefinite)
        }
    }

    /// Factorise the band of `asm` (its low-rank part left out).
    fn factor_band(&mut self, asm: &Assembly) -> Result<(), NotPositiveDefinite> {
        let n = asm.n();
        self.factored = false;
        // Row j of the upper triangle's column j: rows max(0, j - W)..=j, right-aligned.
        for j in 0..n.min(W) {
            let col = &asm.values[asm.col_ptr[j]..asm.col_ptr[j + 1]];
            let row = &mut self.rows[j];
            row[..W1 - col.len()].fill(0.0);
            row[W1 - col.len()..].copy_from_slice(col);
        }
        if n > W {
            // Full rows are contiguous in the assembly.
            let full = &asm.values[asm.col_ptr[W]..asm.col_ptr[n]];
            for (row, col) in self.rows[W..n].iter_mut().zip(full.chunks_exact(W1)) {
                *row = col.try_into().unwrap();
            }
        }
        for row in &mut self.rows[n..] {
            *row = [0.0; W1];
        }
        for k in 0..n {
            let d = self.rows[k][W];
            if !(d > 0.0 && d.is_finite()) {
                return Err(NotPositiveDefinite);
            }
            let inv = 1.0 / d;
            self.decoupled[k] = self.rows[k][..W].iter().all(|&x| x == 0.0);
            self.inv_diag[k] = inv;
            // Column k below the diagonal: `a = L[k+1+t][k] D[k]` (as reduced so far) at
            // rows[k+1+t][W-1-t], replaced by `L[k+1+t][k] = a / D[k]`.
            let below: &mut [[f64; W1]; W] = (&mut self.rows[k + 1..k + 1 + W]).try_into().unwrap();
            let mut col = [0.0; W];
            let mut unscaled = [0.0; W];
            let mut coupled = false;
            for t in 0..W {
                unscaled[t] = below[t][W - 1 - t];
                col[t] = unscaled[t] * inv;
                below[t][W - 1 - t] = col[t];
                coupled |= col[t] != 0.0;
            }
            // A held coordinate's column is zero below the diagonal (`Assembly::fix`): nothing
            // to update (a third of the columns on the S-start, whose touching heights and
            // sticking positions are held).
            if !coupled {
                continue;
            }
            // A[i][j] -= L[i][k] D[k] L[j][k], k < j <= i <= k + W: row i = k+1+t, columns
            // j = k+1+u (u <= t) at W - (t - u).
            for t in 0..W {
                let lik = col[t];
                for u in 0..=t {
                    below[t][W - t + u] -= lik * unscaled[u];
                }
            }
        }
        self.factored = true;
        Ok(())
    }

    /// Solve `A x = b` in place with the last factorisation (band and low-rank part).
    pub fn solve(&mut self, b: &mut [f64]) {
        self.solve_band(b);
        let wb = &self.woodbury;
        if let Some(chol) = &wb.chol {
            let t =
                nalgebra::DVector::from_iterator(wb.cols.len(), wb.cols.iter().map(|u| u.dot(b)));
            let c = chol.solve(&t);
            for (z, ci) in wb.z.iter().zip(c.iter()) {
                for (x, zi) in b.iter_mut().zip(z) {
                    *x -= ci * zi;
                }
            }
        }
    }

    /// Solve with the band alone.
    fn solve_band(&mut self, b: &mut [f64]) {
        assert!(self.factored, "solve before a successful factor");
        let n = b.len();
        let y = &mut self.rhs;
        y[..W].fill(0.0);
        y[W..].copy_from_slice(b);
        // L y = b, row by row: row j holds columns j - W..j, i.e. y[j..j + W] padded.
        // The previous row's unknown enters last, so each row waits on it for one
        // multiply-add only.
        for j in 0..n {
            if self.decoupled[j] {
                continue;
            }
            let row = &self.rows[j];
            let win: &[f64; W] = (&y[j..j + W]).try_into().unwrap();
            let mut acc = [0.0; 2];
            for t in 0..W - 1 {
                acc[t % 2] += row[t] * win[t];
            }
            let rest = y[j + W] - (acc[0] + acc[1]);
            y[j + W] = rest - row[W - 1] * win[W - 1];
        }
        // D z = y.
        for (z, inv) in y[W..].iter_mut().zip(&self.inv_diag) {
            *z *= inv;
        }
        // L^T x = z: once x_j is known, subtract column j of L^T (row j of L).
        for j in (0..n).rev() {
            let xj = y[j + W];
            if self.decoupled[j] {
                continue;
            }
            let row = &self.rows[j];
            let win: &mut [f64; W] = (&mut y[j..j + W]).try_into().unwrap();
            for t in 0..W {
                win[t] -= row[t] * xj;
            }
        }
        b.copy_from_slice(&y[W..]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symmetric band matrix of `n` coordinates with random entries and `diag` on the
    /// diagonal, and a random right-hand side in `grad`.
    fn band(n: usize, diag: f64, seed: u64) -> Assembly {
        let mut asm = Assembly::new(n);
        let mut x = seed;
        let mut next = || crate::fd::uniform(&mut x);
        for j in 0..n {
            for i in j.saturating_sub(W)..j {
                asm.add_h(i, j, next());
            }
            asm.add_h(j, j, diag * (1.0 + 0.5 * next()));
            asm.grad[j] = next();
        }
        asm
    }

    /// `asm`'s system solved with `ours` (factorised here) and with faer: both solutions.
    fn solve_both(ours: &mut LinSolver, asm: &Assembly) -> (Vec<f64>, Vec<f64>) {
        let mut faer = FaerLlt::new(asm);
        ours.factor(asm).unwrap();
        faer.factor(asm).unwrap();
        let (mut x, mut y) = (asm.grad.clone(), asm.grad.clone());
        ours.solve(&mut x);
        faer.solve(&mut y);
        (x, y)
    }

    /// The band factorisation solves like faer's sparse Cholesky and leaves a residual at
    /// rounding level, for sizes below, at and above the bandwidth.
    #[test]
    fn band_solve_matches_faer() {
        for (n, seed) in [
            (1, 3),
            (7, 5),
            (10, 7),
            (11, 9),
            (12, 11),
            (35, 13),
            (203, 17),
        ] {
            let asm = band(n, 2.0 * W as f64, 0x9E37_79B9_7F4A_7C15 ^ seed);
            let (x, y) = solve_both(&mut LinSolver::new(&asm), &asm);
            for k in 0..n {
                assert!(
                    (x[k] - y[k]).abs() < 1e-13,
                    "n {n}, x[{k}]: {} vs {}",
                    x[k],
                    y[k]
                );
                let ax: f64 = (0..n).map(|j| asm.h(k, j) * x[j]).sum();
                assert!((ax - asm.grad[k]).abs() < 1e-12, "n {n}, row {k}: residual");
            }
        }
    }

    /// Held coordinates (`Assembly::fix`: the skipped columns and rows) solve like faer too,
    /// the same solver refactorised with another held set included (the skips are per
    /// factorisation), and a held coordinate's solution is its right-hand side.
    #[test]
    fn held_coordinates_solve_like_faer() {
        let n = 203;
        let mut ours: Option<LinSolver> = None;
        for (held, seed) in [
            (vec![0, 1, 2, 50, 51, 202], 31),
            (vec![3, 7, 8, 9, 100], 37),
        ] {
            let mut asm = band(n, 2.0 * W as f64, seed);
            for &k in &held {
                asm.fix(k);
                asm.grad[k] = 0.5 + k as f64;
            }
            let (x, y) = solve_both(ours.get_or_insert_with(|| LinSolver::new(&asm)), &asm);
            for k in 0..n {
                assert!((x[k] - y[k]).abs() < 1e-13, "held {held:?}, x[{k}]");
            }
            for &k in &held {
                assert_eq!(x[k], asm.grad[k], "held coordinate {k}");
            }
        }
    }

    /// A band plus a low-rank part far outside it (columns coupling coordinates 0..3 with
    /// 180..192, and a held coordinate among them) solves to a residual at rounding level
    /// against the dense product, and the held coordinate keeps its right-hand side.
    #[test]
    fn low_rank_part_solves_by_woodbury() {
        let n = 203;
        let mut asm = band(n, 2.0 * W as f64, 41);
        let mut seed = 7u64;
        for c in 0..5 {
            let mut idx = [0usize; super::super::LOW_RANK_ENTRIES];
            let mut val = [0.0; super::super::LOW_RANK_ENTRIES];
            for r in 0..idx.len() {
                idx[r] = if r < 6 { 3 * c + r } else { 180 + r };
                val[r] = 3.0 * crate::fd::uniform(&mut seed);
            }
            asm.add_low_rank(idx, val);
        }
        asm.fix(185);
        asm.grad[185] = 2.5;
        let mut lin = LinSolver::new(&asm);
        lin.factor(&asm).unwrap();
        let mut x = asm.grad.clone();
        lin.solve(&mut x);
        let mut ax = vec![0.0; n];
        asm.mul(&x, &mut ax);
        for k in 0..n {
            assert!(
                (ax[k] - asm.grad[k]).abs() < 1e-11,
                "row {k}: {} vs {}",
                ax[k],
                asm.grad[k]
            );
        }
        assert!((x[185] - 2.5).abs() < 1e-13);
        // Without the low-rank part the solution differs (the test can fail).
        let mut band_only = asm.clone();
        band_only.low_rank.clear();
        let mut y = band_only.grad.clone();
        let mut lin2 = LinSolver::new(&band_only);
        lin2.factor(&band_only).unwrap();
        lin2.solve(&mut y);
        assert!(x.iter().zip(&y).any(|(a, b)| (a - b).abs() > 1e-3));
    }

    /// An indefinite band matrix is refused by both.
    #[test]
    fn indefinite_band_is_refused() {
        let mut asm = band(40, 2.0 * W as f64, 21);
        asm.add_h(25, 25, -100.0);
        assert!(LinSolver::new(&asm).factor(&asm).is_err());
        assert!(FaerLlt::new(&asm).factor(&asm).is_err());
        let mut nan = band(40, 2.0 * W as f64, 23);
        nan.add_h(3, 3, f64::NAN);
        assert!(LinSolver::new(&nan).factor(&nan).is_err());
    }
}
