//! faer's sparse Cholesky factorization with the symbolic analysis (ordering, elimination tree,
//! supernodes) done once per pattern and only the numeric factorization repeated each Gauss-Newton
//! iteration, into buffers allocated once.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltError;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use super::RegisterError;
use super::pattern::Pattern;

/// A reusable factorization of matrices with one fixed pattern.
pub struct Cholesky {
    symbolic: SymbolicCholesky<u32>,
    factor: Vec<f64>,
    factor_scratch: MemBuffer,
    solve_scratch: MemBuffer,
    par: Par,
    factored: bool,
}

fn out_of_memory(what: &str) -> RegisterError {
    RegisterError::Factorization(format!("out of memory allocating {what}"))
}

impl Cholesky {
    /// Symbolic analysis of `pattern` with `par` for the numeric work.
    pub fn analyze(pattern: &Pattern, par: Par) -> Result<Self, RegisterError> {
        let n = pattern.dimension();
        let (fwd, inv) = pattern.ordering()?;
        let perm = faer::perm::PermRef::new_checked(&fwd, &inv, n);
        let structure =
            SymbolicSparseColMatRef::new_checked(n, n, &pattern.col_ptr, None, &pattern.row_idx);
        let symbolic = factorize_symbolic_cholesky(
            structure,
            Side::Upper,
            SymmetricOrdering::Custom(perm),
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| RegisterError::Factorization(format!("symbolic analysis: {e:?}")))?;
        let factor_scratch = MemBuffer::try_new(
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        )
        .map_err(|_| out_of_memory("factorization workspace"))?;
        let solve_scratch = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(1, par))
            .map_err(|_| out_of_memory("solve workspace"))?;
        let factor = vec![0.0; symbolic.len_val()];
        Ok(Self {
            symbolic,
            factor,
            factor_scratch,
            solve_scratch,
            par,
            factored: false,
        })
    }

    /// Nonzeros of the Cholesky factor.
    pub fn factor_nonzeros(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Numeric factorization of the matrix whose upper triangle is `values` (in `pattern`'s
    /// layout). A non-positive pivot is returned as such so the caller can add damping.
    pub fn factor(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), LltError> {
        let n = pattern.dimension();
        let matrix = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, &pattern.col_ptr, None, &pattern.row_idx),
            values,
        );
        self.factored = false;
        self.symbolic.factorize_numeric_llt(
            &mut self.factor,
            matrix,
            Side::Upper,
            Default::default(),
            self.par,
            MemStack::new(&mut self.factor_scratch),
            Default::default(),
        )?;
        self.factored = true;
        Ok(())
    }

    /// Solves `H x = rhs` in place with the last successful factorization.
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<(), RegisterError> {
        if !self.factored || rhs.len() != self.symbolic.nrows() {
            return Err(RegisterError::Factorization(
                "solve without a matching factorization".into(),
            ));
        }
        let n = rhs.len();
        LltRef::new(&self.symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            self.par,
            MemStack::new(&mut self.solve_scratch),
        );
        Ok(())
    }
}
