//! faer's sparse Cholesky factorization with the symbolic analysis (ordering, elimination tree,
//! supernodes) done once per pattern and only the numeric factorization repeated each Gauss-Newton
//! iteration, into buffers allocated once.
//!
//! The factor only ever preconditions conjugate gradients on the exact Gauss-Newton system (see
//! `coarse`), so it is computed in single precision: that halves the memory the factorization and
//! every triangular solve stream through and doubles the SIMD width, which is what their time is
//! made of (issue 5, bar 4), while the step itself is still solved in `f64` to the conjugate-gradient
//! tolerance. The matrix is first scaled to unit diagonal (Jacobi), so `f32`'s range and precision
//! see the matrix's conditioning rather than the spread of its weights (`α_reg` up to 10⁴ × `α_fit`).
//! Should a pivot still vanish in `f32`, the same scaled matrix is factored in `f64`; only when that
//! fails too is the non-positive pivot reported (the caller then adds damping). The single-precision
//! work runs with subnormals flushed to zero (see `flush`).

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltError;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use super::flush::flushing_subnormals;
use super::pattern::Pattern;
use super::{FactorizationError, RegisterError};

/// Which factor the last successful factorization produced.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Precision {
    Single,
    Double,
}

/// A reusable factorization of matrices with one fixed pattern.
pub struct Cholesky {
    /// Shared with [`Cholesky::sibling`]s.
    symbolic: Arc<SymbolicCholesky<u32>>,
    /// `1/√h_ii`: the factor is of `S H S`.
    scaling: Vec<f64>,
    scaled: Vec<f32>,
    single: Vec<f32>,
    /// The `f64` fallback, allocated on first use.
    double: Vec<f64>,
    rhs: Vec<f32>,
    factor_scratch: MemBuffer,
    solve_scratch: MemBuffer,
    par: Par,
    factored: Option<Precision>,
}

fn out_of_memory(what: &'static str) -> RegisterError {
    FactorizationError::OutOfMemory { what }.into()
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
        .map_err(|e| FactorizationError::Symbolic {
            unknowns: n,
            reason: format!("{e:?}"),
        })?;
        Self::with_symbolic(Arc::new(symbolic), n, pattern.row_idx.len(), par)
    }

    /// A second factorization of the same pattern, with buffers of its own: the coarse stage
    /// factors the next stage's matrix into one while it still solves with the other.
    pub fn sibling(&self) -> Result<Self, RegisterError> {
        Self::with_symbolic(
            Arc::clone(&self.symbolic),
            self.scaling.len(),
            self.scaled.len(),
            self.par,
        )
    }

    fn with_symbolic(
        symbolic: Arc<SymbolicCholesky<u32>>,
        n: usize,
        nonzeros: usize,
        par: Par,
    ) -> Result<Self, RegisterError> {
        let factor_scratch = MemBuffer::try_new(StackReq::or(
            symbolic.factorize_numeric_llt_scratch::<f32>(par, Default::default()),
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        ))
        .map_err(|_| out_of_memory("factorization workspace"))?;
        let solve_scratch = MemBuffer::try_new(StackReq::or(
            symbolic.solve_in_place_scratch::<f32>(1, par),
            symbolic.solve_in_place_scratch::<f64>(1, par),
        ))
        .map_err(|_| out_of_memory("solve workspace"))?;
        let single = vec![0.0; symbolic.len_val()];
        Ok(Self {
            symbolic,
            scaling: vec![1.0; n],
            scaled: vec![0.0; nonzeros],
            single,
            double: Vec::new(),
            rhs: vec![0.0; n],
            factor_scratch,
            solve_scratch,
            par,
            factored: None,
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
        self.factored = None;
        for (c, s) in self.scaling.iter_mut().enumerate() {
            let d = values[pattern.col_ptr[c + 1] as usize - 1];
            if !(d > 0.0 && d.is_finite()) {
                return Err(LltError::NonPositivePivot { index: c });
            }
            *s = 1.0 / d.sqrt();
        }
        let scaling = &self.scaling;
        let scaled =
            |k: usize, c: usize| values[k] * scaling[pattern.row_idx[k] as usize] * scaling[c];
        for c in 0..n {
            for k in pattern.col_ptr[c] as usize..pattern.col_ptr[c + 1] as usize {
                self.scaled[k] = scaled(k, c) as f32;
            }
        }
        let structure =
            SymbolicSparseColMatRef::new_checked(n, n, &pattern.col_ptr, None, &pattern.row_idx);
        let single = flushing_subnormals(|| {
            self.symbolic.factorize_numeric_llt(
                &mut self.single,
                SparseColMatRef::new(structure, &self.scaled),
                Side::Upper,
                Default::default(),
                self.par,
                MemStack::new(&mut self.factor_scratch),
                Default::default(),
            )
        });
        if single.is_ok() {
            self.factored = Some(Precision::Single);
            return Ok(());
        }
        let wide: Vec<f64> = (0..n)
            .flat_map(|c| {
                (pattern.col_ptr[c] as usize..pattern.col_ptr[c + 1] as usize).map(move |k| (k, c))
            })
            .map(|(k, c)| scaled(k, c))
            .collect();
        self.double.resize(self.symbolic.len_val(), 0.0);
        self.symbolic.factorize_numeric_llt(
            &mut self.double,
            SparseColMatRef::new(structure, &wide),
            Side::Upper,
            Default::default(),
            self.par,
            MemStack::new(&mut self.factor_scratch),
            Default::default(),
        )?;
        self.factored = Some(Precision::Double);
        Ok(())
    }

    /// Solves `H x = rhs` in place with the last successful factorization.
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<(), RegisterError> {
        let n = rhs.len();
        let precision = match self.factored {
            Some(precision) if n == self.symbolic.nrows() => precision,
            _ => {
                return Err(FactorizationError::NotFactored { dimension: n }.into());
            }
        };
        let stack = MemStack::new(&mut self.solve_scratch);
        match precision {
            Precision::Single => {
                for ((r, s), x) in self.rhs.iter_mut().zip(&self.scaling).zip(rhs.iter()) {
                    *r = (x * s) as f32;
                }
                flushing_subnormals(|| {
                    LltRef::new(&self.symbolic, &self.single).solve_in_place_with_conj(
                        Conj::No,
                        MatMut::from_column_major_slice_mut(&mut self.rhs, n, 1),
                        self.par,
                        stack,
                    )
                });
                for ((x, s), r) in rhs.iter_mut().zip(&self.scaling).zip(&self.rhs) {
                    *x = f64::from(*r) * s;
                }
            }
            Precision::Double => {
                rhs.iter_mut().zip(&self.scaling).for_each(|(x, s)| *x *= s);
                LltRef::new(&self.symbolic, &self.double).solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(rhs, n, 1),
                    self.par,
                    stack,
                );
                rhs.iter_mut().zip(&self.scaling).for_each(|(x, s)| *x *= s);
            }
        }
        Ok(())
    }
}
