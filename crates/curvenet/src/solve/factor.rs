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

/// Factor-value buffers kept for reuse per symbolic analysis (bounded: a dropped factor
/// beyond this many is freed).
const POOL_BUFFERS: usize = 4;

/// The symbolic Cholesky analysis of a pattern.
#[derive(Debug)]
pub struct SymbolicFactor {
    inner: SymbolicCholesky<usize>,
    ordering: OrderingKind,
    /// Buffers of dropped factors and factorization scratch, reused by the next numeric
    /// factorizations: a fresh buffer of `L`'s size costs page faults and zeroing on every
    /// factorization (≈ 8% of a factorization on the tower). Which buffer a factorization
    /// gets never affects its values (faer zeroes `L` and overwrites the scratch).
    pool: std::sync::Mutex<Pool>,
}

#[derive(Default)]
struct Pool {
    values: Vec<Vec<f64>>,
    scratch: Vec<MemBuffer>,
}

impl std::fmt::Debug for Pool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Pool")
            .field("values", &self.values.len())
            .field("scratch", &self.scratch.len())
            .finish()
    }
}

impl SymbolicFactor {
    fn take_values(&self) -> Vec<f64> {
        let len = self.inner.len_val();
        let reused = self.pool.lock().ok().and_then(|mut p| p.values.pop());
        reused
            .filter(|v| v.len() == len)
            .unwrap_or_else(|| vec![0.0; len])
    }

    fn give_values(&self, v: Vec<f64>) {
        if let Ok(mut p) = self.pool.lock()
            && p.values.len() < POOL_BUFFERS
        {
            p.values.push(v);
        }
    }

    fn take_scratch(&self) -> MemBuffer {
        let reused = self.pool.lock().ok().and_then(|mut p| p.scratch.pop());
        reused.unwrap_or_else(|| {
            MemBuffer::new(
                self.inner
                    .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            )
        })
    }

    fn give_scratch(&self, m: MemBuffer) {
        if let Ok(mut p) = self.pool.lock()
            && p.scratch.len() < POOL_BUFFERS
        {
            p.scratch.push(m);
        }
    }
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
            pool: Default::default(),
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
                        pool: Default::default(),
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

impl Drop for Cholesky {
    fn drop(&mut self) {
        self.symbolic.give_values(std::mem::take(&mut self.values));
    }
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
        let mut l_values = symbolic.take_values();
        let par = Par::Seq;
        let mut mem = symbolic.take_scratch();
        let result = sym.factorize_numeric_llt::<f64>(
            &mut l_values,
            a,
            Side::Upper,
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        );
        let result = result.map(|_| ());
        symbolic.give_scratch(mem);
        match result {
            Ok(()) => Ok(Cholesky {
                symbolic: symbolic.clone(),
                values: l_values,
                shift,
            }),
            Err(faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index }) => {
                symbolic.give_values(l_values);
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
