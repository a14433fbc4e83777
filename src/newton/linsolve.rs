//! Sparse Cholesky of the step Hessian with faer: the symbolic analysis (natural ordering:
//! the banded pattern needs no reordering) is computed once per pattern; every Newton
//! iteration refactorises numerically into preallocated storage, without allocating.

use crate::energy::Assembly;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// Reusable LL^T factorisation of matrices sharing one [`Assembly`] pattern.
pub struct LinSolver {
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    mem: MemBuffer,
    factored: bool,
}

/// The matrix was not positive definite.
#[derive(Debug, Clone, Copy)]
pub struct NotPositiveDefinite;

impl LinSolver {
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
        LinSolver {
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
