//! A sequential sparse Cholesky factor of a symmetric positive definite matrix (faer's LLᵀ
//! with AMD ordering). Sequential so that the field, hence the traced curves, is bit-identical
//! from run to run whatever the thread count.

use crate::trace::TraceError;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Par, Side};

/// A sparse Cholesky factor of a symmetric positive definite matrix, computed sequentially.
pub(super) struct SpdSolver {
    sym: faer::sparse::linalg::cholesky::SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    dim: usize,
}

impl SpdSolver {
    /// Factors the matrix given by its upper-triangle `triplets` (duplicates summed).
    pub(super) fn new(
        dim: usize,
        triplets: &[Triplet<usize, usize, f64>],
    ) -> Result<Self, TraceError> {
        let solver = |e: &dyn std::fmt::Debug| TraceError::Solver(format!("{e:?}"));
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(dim, dim, triplets)
            .map_err(|e| solver(&e))?;
        let sym = factorize_symbolic_cholesky(
            a.symbolic(),
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| solver(&e))?;
        let par = Par::Seq;
        let mut l_values = vec![0.0f64; sym.len_val()];
        let mut mem =
            MemBuffer::new(sym.factorize_numeric_llt_scratch::<f64>(par, Default::default()));
        sym.factorize_numeric_llt::<f64>(
            &mut l_values,
            a.as_ref(),
            Side::Upper,
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .map_err(|e| solver(&e))?;
        Ok(SpdSolver { sym, l_values, dim })
    }

    /// Solves `A x = rhs`.
    pub(super) fn solve(&self, mut rhs: Vec<f64>) -> Result<Vec<f64>, TraceError> {
        let par = Par::Seq;
        let mut mem = MemBuffer::new(self.sym.solve_in_place_scratch::<f64>(1, par));
        let x = faer::MatMut::from_column_major_slice_mut(&mut rhs, self.dim, 1);
        LltRef::new(&self.sym, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            x,
            par,
            MemStack::new(&mut mem),
        );
        if rhs.iter().any(|v| !v.is_finite()) {
            return Err(TraceError::Solver("non-finite solution".into()));
        }
        Ok(rhs)
    }
}
