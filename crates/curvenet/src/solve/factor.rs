//! Sparse Cholesky factorization of `H + τI` over the model's fixed pattern, on faer.
//!
//! The symbolic analysis (fill-reducing ordering, elimination tree, supernodes) depends only
//! on the pattern, so it is done once per network ([`SymbolicFactor::new`]) and shared by every
//! Newton step, every eigen solve and every greedy candidate; each of those only redoes the
//! numeric factorization ([`Cholesky::factorize`]).
//!
//! Everything runs with `Par::Seq`: parallelism lives one level up (candidates in parallel),
//! which keeps every result bit-identical whatever the thread count.

use super::ordering::{self, OrderingKind};
use crate::rod::model::Pattern;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::SparseColMatRef;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::{Conj, MatMut, Par, Side};
use std::sync::Arc;

/// Networks with at least this many unknowns also try a nested-dissection ordering.
pub const ND_MIN_DOFS: usize = 3000;

/// Right-hand sides solved together in one call (see [`Cholesky::solve_in_place`]).
pub const SOLVE_GROUP: usize = 4;

/// The symbolic Cholesky analysis of a pattern.
#[derive(Debug)]
pub struct SymbolicFactor {
    inner: SymbolicCholesky<usize>,
    ordering: OrderingKind,
}

/// The numeric factorization failed: the matrix is not numerically positive definite.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error("matrix is not positive definite (non-positive pivot at column {column})")]
pub struct NotPositiveDefinite {
    /// Column (in the permuted order) where the pivot failed.
    pub column: usize,
}

impl SymbolicFactor {
    /// Analyses `pattern`: AMD, and on networks of more than [`ND_MIN_DOFS`] unknowns also
    /// nested dissection, keeping the ordering with less fill (see [`super::ordering`]).
    pub fn new(pattern: &Pattern) -> Arc<Self> {
        let amd = factorize_symbolic_cholesky(
            pattern.symbolic(),
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .expect("symbolic analysis of a valid pattern");
        let mut best = SymbolicFactor {
            inner: amd,
            ordering: OrderingKind::Amd,
        };
        if pattern.n >= ND_MIN_DOFS {
            if let Some(perm) = ordering::nested_dissection(pattern) {
                let (fwd, inv) = ordering::expand(&perm);
                let nd = factorize_symbolic_cholesky(
                    pattern.symbolic(),
                    Side::Upper,
                    SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(
                        &fwd, &inv, pattern.n,
                    )),
                    CholeskySymbolicParams::default(),
                )
                .expect("symbolic analysis of a valid pattern");
                if nd.len_val() < best.inner.len_val() {
                    best = SymbolicFactor {
                        inner: nd,
                        ordering: OrderingKind::NestedDissection,
                    };
                }
            }
        }
        Arc::new(best)
    }

    /// The ordering chosen.
    pub fn ordering(&self) -> OrderingKind {
        self.ordering
    }

    /// Number of stored values in the factor `L`.
    pub fn factor_nnz(&self) -> usize {
        self.inner.len_val()
    }
}

/// A numeric Cholesky factor `L Lᵀ = P (H + τI) Pᵀ`.
#[derive(Debug)]
pub struct Cholesky {
    symbolic: Arc<SymbolicFactor>,
    values: Vec<f64>,
    /// The diagonal shift `τ` that was added.
    pub shift: f64,
}

impl Cholesky {
    /// Factors `H + τI`, `H` given by its upper-triangle `values` in `pattern`.
    pub fn factorize(
        symbolic: &Arc<SymbolicFactor>,
        pattern: &Pattern,
        values: &[f64],
        shift: f64,
    ) -> Result<Cholesky, NotPositiveDefinite> {
        crate::profile::time(crate::profile::Phase::Factor, || {
            Self::factorize_impl(symbolic, pattern, values, shift)
        })
    }

    fn factorize_impl(
        symbolic: &Arc<SymbolicFactor>,
        pattern: &Pattern,
        values: &[f64],
        shift: f64,
    ) -> Result<Cholesky, NotPositiveDefinite> {
        let shifted;
        let vals = if shift != 0.0 {
            let mut v = values.to_vec();
            for &d in &pattern.diag {
                v[d] += shift;
            }
            shifted = v;
            &shifted[..]
        } else {
            values
        };
        let a = SparseColMatRef::new(pattern.symbolic(), vals);
        let sym = &symbolic.inner;
        let mut l_values = vec![0.0; sym.len_val()];
        let par = Par::Seq;
        let mut mem =
            MemBuffer::new(sym.factorize_numeric_llt_scratch::<f64>(par, Default::default()));
        let result = sym.factorize_numeric_llt::<f64>(
            &mut l_values,
            a,
            Side::Upper,
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        );
        match result {
            Ok(_) => Ok(Cholesky {
                symbolic: symbolic.clone(),
                values: l_values,
                shift,
            }),
            Err(faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index }) => {
                Err(NotPositiveDefinite { column: index })
            }
        }
    }

    /// Solves `(H + τI) X = B` in place for the columns of `rhs`, in fixed groups of
    /// [`SOLVE_GROUP`] columns run in parallel.
    pub fn solve_in_place(&self, rhs: MatMut<'_, f64>) {
        crate::profile::time(crate::profile::Phase::Solve, || self.solve_impl(rhs))
    }

    fn solve_impl(&self, rhs: MatMut<'_, f64>) {
        // Columns are solved in fixed groups of `SOLVE_GROUP`, in parallel when threads are
        // free. faer's result for a column depends on which columns share its call, so the
        // grouping is fixed (never by thread count) to keep results bit-identical.
        let k = rhs.ncols();
        if k <= SOLVE_GROUP {
            self.solve_group(rhs);
            return;
        }
        let mut groups = Vec::with_capacity(k.div_ceil(SOLVE_GROUP));
        let mut rest = rhs;
        while rest.ncols() > SOLVE_GROUP {
            let (a, b) = rest.split_at_col_mut(SOLVE_GROUP);
            groups.push(a);
            rest = b;
        }
        groups.push(rest);
        use rayon::prelude::*;
        groups.into_par_iter().for_each(|g| self.solve_group(g));
    }

    fn solve_group(&self, rhs: MatMut<'_, f64>) {
        let sym = &self.symbolic.inner;
        let mut mem = MemBuffer::new(sym.solve_in_place_scratch::<f64>(rhs.ncols(), Par::Seq));
        LltRef::new(sym, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut mem),
        );
    }

    /// Solves for one right-hand side given as a slice.
    pub fn solve_vec(&self, rhs: &mut [f64]) {
        let n = rhs.len();
        let m = faer::MatMut::from_column_major_slice_mut(rhs, n, 1);
        self.solve_in_place(m);
    }
}
