//! Sparse Cholesky factorization of `H + τI` over the model's fixed pattern, on faer.
//!
//! The symbolic analysis (fill-reducing ordering, elimination tree, supernodes) depends only
//! on the pattern, so it is done once per network ([`SymbolicFactor::new`]) and shared by every
//! Newton step, every eigen solve and every greedy candidate; each of those only redoes the
//! numeric factorization ([`Cholesky::factorize`]).
//!
//! Orderings are renumbered in a postorder of the elimination tree, and every analysis is
//! supernodal. The numeric factorization runs independent subtrees of the elimination tree in
//! parallel (`solve::supernodal`); each supernode is computed the same way whatever the
//! schedule, so every result is bit-identical whatever the thread count.

use super::ordering::{self, OrderingKind};
use super::supernodal::{self, Plan};
use crate::sparse::Pattern;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::SparseColMatRef;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::{Conj, Mat, MatMut, Par, Side};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Networks with at least this many unknowns also try a nested-dissection ordering.
pub const ND_MIN_DOFS: usize = 3000;

/// Right-hand sides solved together in one substitution by default ([`Schedule::Groups`]).
pub const SOLVE_GROUP: usize = 4;

/// Factor-value buffers kept for reuse per symbolic analysis (bounded: a dropped factor
/// beyond this many is freed).
const POOL_BUFFERS: usize = 4;

/// The numeric factorization and triangular substitutions a symbolic analysis runs: a
/// parameter of the analysis, so every factor of it takes the same path.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Backend {
    /// Independent subtrees of the elimination tree in parallel (`solve::supernodal`), on
    /// faer's dense kernels and storage layout: the same factor whatever the thread count,
    /// and substitutions ([`Schedule::Subtrees`]) bit-identical to faer's sequential ones.
    #[default]
    Subtrees,
    /// faer's own sequential supernodal factorization and substitution: the reference the
    /// other is tested against.
    Faer,
}

/// The symbolic Cholesky analysis of a pattern.
#[derive(Debug)]
pub struct SymbolicFactor {
    inner: SymbolicCholesky<usize>,
    ordering: OrderingKind,
    backend: Backend,
    /// Buffers of dropped factors and factorization scratch, reused by the next numeric
    /// factorizations: a fresh buffer of `L`'s size costs page faults and zeroing on every
    /// factorization. Which buffer a factorization gets never affects its values (faer zeroes
    /// `L` and overwrites the scratch).
    pool: std::sync::Mutex<Pool>,
    /// When this analysis covers only some coordinates of a larger pattern (see
    /// [`SymbolicFactor::restricted`]): how they sit in it.
    restriction: Option<Restriction>,
    /// The subtree-parallel numeric factorization of a supernodal analysis (see
    /// `solve::supernodal`); `None` with [`Backend::Faer`] and for simplicial analyses,
    /// which faer factors.
    plan: Option<Plan>,
}

/// The coordinates a restricted analysis covers, inside the full pattern.
#[derive(Debug)]
struct Restriction {
    /// The full pattern's analysis, used when a matrix couples a left-out coordinate.
    full: Arc<SymbolicFactor>,
    /// Size of the full pattern.
    n_full: usize,
    /// Kept coordinates of the full pattern, ascending.
    dofs: Vec<usize>,
    /// For each stored entry of the sub-pattern, its slot in the full pattern.
    slots: Vec<usize>,
    /// The pattern of the kept coordinates.
    sub: Pattern,
    /// Left-out coordinates and the full-pattern slot of their diagonal entry.
    rest: Vec<(usize, usize)>,
    /// Full-pattern slots of off-diagonal entries touching a left-out coordinate.
    coupling: Vec<usize>,
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

/// faer's symbolic analysis of `pattern` in the order `fwd` (original index of each new one).
fn custom_symbolic(pattern: &Pattern, fwd: Vec<usize>) -> Option<SymbolicCholesky<usize>> {
    let mut inv = vec![0; fwd.len()];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    factorize_symbolic_cholesky(
        pattern.symbolic(),
        Side::Upper,
        SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(&fwd, &inv, pattern.n)),
        symbolic_params(),
    )
    .ok()
}

/// faer's symbolic parameters: always supernodal (faer's default picks a simplicial factor
/// for matrices with little fill, which our subtree-parallel supernodal factorization beats).
fn symbolic_params() -> CholeskySymbolicParams<'static> {
    CholeskySymbolicParams {
        supernodal_flop_ratio_threshold:
            faer::sparse::linalg::SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
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
    /// Analyses `pattern` for factorizations by `backend`: AMD, and on networks of more than
    /// [`ND_MIN_DOFS`] unknowns also nested dissection, keeping the ordering with less fill
    /// (see [`super::ordering`]).
    pub fn new(pattern: &Pattern, backend: Backend) -> Arc<Self> {
        Arc::new(Self::analyse(pattern, None, backend))
    }

    /// An analysis of the coordinates `keep` selects (`keep.len() == pattern.n`) for matrices
    /// on `pattern` whose other coordinates are decoupled (no stored off-diagonal entry of the
    /// matrix touches them: loose vertices, which only carry a diagonal). Factorizations with
    /// it take values on the whole `pattern` and give a factor of the whole matrix — the
    /// principal submatrix on `keep` factored sparsely, the rest a diagonal — at the cost of
    /// the kept coordinates only. A matrix that does couple a left-out coordinate is factored
    /// with `full` (the whole pattern's analysis) instead: the result is always exact. The
    /// analysis has `full`'s backend.
    pub fn restricted(full: &Arc<SymbolicFactor>, pattern: &Pattern, keep: &[bool]) -> Arc<Self> {
        let (sub, slots, dofs) = pattern.principal(keep);
        let mut rest = Vec::new();
        let mut coupling = Vec::new();
        for j in 0..pattern.n {
            for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                let i = pattern.row_idx[k];
                if i == j {
                    if !keep[j] {
                        rest.push((j, k));
                    }
                } else if !keep[i] || !keep[j] {
                    coupling.push(k);
                }
            }
        }
        // A fresh ordering of the part (the whole network's ordering restricted to it leaves
        // more fill), with the whole network's choice of method.
        let mut analysis = Self::analyse(&sub, Some(full.ordering), full.backend);

        analysis.restriction = Some(Restriction {
            full: full.clone(),
            n_full: pattern.n,
            dofs,
            slots,
            sub,
            rest,
            coupling,
        });
        Arc::new(analysis)
    }

    /// Coordinates the factorizations work on (all of the pattern's unless restricted).
    pub fn kept_dofs(&self) -> usize {
        self.inner.nrows()
    }

    /// The factorizations' backend.
    pub fn backend(&self) -> Backend {
        self.backend
    }

    /// AMD and, on patterns of at least [`ND_MIN_DOFS`] unknowns, nested dissection, keeping
    /// the one with less fill; with `prefer` set to nested dissection (a part of a network
    /// whose own analysis chose it), nested dissection alone when it is available.
    fn analyse(pattern: &Pattern, prefer: Option<OrderingKind>, backend: Backend) -> Self {
        let nd = (pattern.n >= ND_MIN_DOFS)
            .then(|| ordering::nested_dissection(pattern))
            .flatten()
            .and_then(|perm| {
                custom_symbolic(
                    pattern,
                    ordering::postorder(pattern, &ordering::expand(&perm).0),
                )
            });
        let best = match nd {
            Some(nd) if prefer == Some(OrderingKind::NestedDissection) => {
                (nd, OrderingKind::NestedDissection)
            }
            nd => {
                let amd = factorize_symbolic_cholesky(
                    pattern.symbolic(),
                    Side::Upper,
                    SymmetricOrdering::Amd,
                    symbolic_params(),
                )
                .expect("symbolic analysis of a valid pattern");
                match nd {
                    Some(nd) if nd.len_val() < amd.len_val() => {
                        (nd, OrderingKind::NestedDissection)
                    }
                    _ => (amd, OrderingKind::Amd),
                }
            }
        };
        Self::finish(pattern, best.0, best.1, backend)
    }

    /// The analysis of `pattern` with the supernodes of `inner` (an analysis of it) renumbered
    /// in postorder, and the subtree-parallel factorization's plan.
    fn finish(
        pattern: &Pattern,
        mut inner: SymbolicCholesky<usize>,
        ordering: OrderingKind,
        backend: Backend,
    ) -> Self {
        // The renumbered analysis can merge supernodes differently, hence the loop.
        for _ in 0..4 {
            let reordered = match inner.raw() {
                SymbolicCholeskyRaw::Supernodal(sup) => {
                    supernodal::postordered(sup, inner.perm().map(|p| p.arrays().0))
                }
                SymbolicCholeskyRaw::Simplicial(_) => None,
            };
            match reordered.and_then(|fwd| custom_symbolic(pattern, fwd)) {
                Some(post) => inner = post,
                None => break,
            }
        }
        let plan = match inner.raw() {
            SymbolicCholeskyRaw::Supernodal(sup) if backend == Backend::Subtrees => Plan::new(
                sup,
                inner.perm().map(|p| p.arrays().1),
                &pattern.col_ptr,
                &pattern.row_idx,
            ),
            _ => None,
        };
        SymbolicFactor {
            inner,
            ordering,
            backend,
            pool: Default::default(),
            restriction: None,
            plan,
        }
    }

    /// The supernodes (of the subtree-parallel plan) whose factor values can change when
    /// the matrix changes only in entries whose row and column both lie in `coords`
    /// (coordinates of the whole pattern); `None` without a plan.
    fn changed_supernodes(&self, coords: &[usize]) -> Option<Vec<bool>> {
        let plan = self.plan.as_ref()?;
        let inv = self.inner.perm().map(|p| p.arrays().1);
        let cols: Vec<usize> = coords
            .iter()
            .filter_map(|&d| match &self.restriction {
                Some(r) => r.dofs.binary_search(&d).ok(),
                None => Some(d),
            })
            .map(|i| inv.map_or(i, |p| p[i]))
            .collect();
        Some(plan.changed_supernodes(&cols))
    }

    /// The share of a factorization's work that a factorization reusing another
    /// ([`Reuse`]) redoes when the matrix changes only in rows and columns `coords` (1 with
    /// [`Backend::Faer`], which reuses nothing).
    pub fn changed_work_share(&self, coords: &[usize]) -> f64 {
        match (self.plan.as_ref(), self.changed_supernodes(coords)) {
            (Some(plan), Some(changed)) => plan.work_share(&changed),
            _ => 1.0,
        }
    }

    /// The ordering chosen.
    pub fn ordering(&self) -> OrderingKind {
        self.ordering
    }

    /// Independent subtrees of the elimination tree the numeric factorization can run in
    /// parallel (1: sequential; 0: faer's own factorization).
    pub fn parallel_subtrees(&self) -> usize {
        self.plan.as_ref().map_or(0, Plan::parallel_tasks)
    }

    /// Independent subtrees a [`Schedule::Subtrees`] substitution runs in parallel (1:
    /// sequential; 0: faer's substitution).
    pub fn parallel_solve_subtrees(&self) -> usize {
        self.plan.as_ref().map_or(0, Plan::parallel_solve_tasks)
    }

    /// Number of stored values in the factor `L`.
    pub fn factor_nnz(&self) -> usize {
        self.inner.len_val()
    }
}

/// How a solve runs its triangular substitutions. A column's values depend on the schedule
/// (on which columns share its substitution), never on the thread count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Schedule {
    /// Fixed groups of this many columns (at least 1) run in parallel, each by one sequential
    /// substitution: one column per group when the caller leaves a core idle (two groups side
    /// by side cost little more than one), a few when every core is busy with other solves
    /// (one pass over the factor serves the group).
    Groups(usize),
    /// All the columns in one substitution whose independent subtrees run in parallel
    /// (`solve::supernodal`; sequential without a parallel schedule or with
    /// [`Backend::Faer`]): for callers that leave the cores idle, such as Newton's steps.
    /// Bit-identical to one group of all the columns; where the cores are busy with other
    /// work, its deferred updates make it slower than that.
    Subtrees,
}

/// A numeric Cholesky factor `L Lᵀ = P (H + τI) Pᵀ`.
#[derive(Debug)]
pub struct Cholesky {
    symbolic: Arc<SymbolicFactor>,
    values: Vec<f64>,
    /// With a restricted analysis: the diagonal (shift included) of each left-out coordinate.
    rest: Vec<f64>,
    /// The diagonal shift `τ` that was added.
    pub shift: f64,
}

impl Drop for Cholesky {
    fn drop(&mut self) {
        self.symbolic.give_values(std::mem::take(&mut self.values));
    }
}

/// A factorization to copy values from ([`Cholesky::factorize`]), and the coordinates (of the
/// whole pattern) whose rows and columns hold every entry in which the new matrix differs
/// from the reference's.
#[derive(Clone, Copy, Debug)]
pub struct Reuse<'a> {
    /// A factorization with the same analysis and shift.
    pub reference: &'a Cholesky,
    /// Coordinates of the entries that may differ (both row and column among them).
    pub changed: &'a [usize],
}

impl Cholesky {
    /// Factors `H + τI` (`τ = shift`), `H` given by its upper-triangle `values` in `pattern`,
    /// with `symbolic` (an analysis of `pattern`, or a restriction of one).
    ///
    /// With `reuse`, a factorization of a matrix that differs from this one only in entries
    /// whose row and column both lie in [`Reuse::changed`]: the supernodes the difference
    /// cannot reach are copied from it, the others factored. The factor is bit-identical
    /// either way (same values, same operations); a reference that does not fit (another
    /// analysis or shift, or [`Backend::Faer`]) is ignored.
    pub fn factorize(
        symbolic: &Arc<SymbolicFactor>,
        pattern: &Pattern,
        values: &[f64],
        shift: f64,
        reuse: Option<Reuse<'_>>,
    ) -> Result<Cholesky, NotPositiveDefinite> {
        crate::profile::time(crate::profile::Phase::Factor, || {
            let changed = reuse
                .filter(|r| {
                    Arc::ptr_eq(symbolic, &r.reference.symbolic)
                        && r.reference.shift.to_bits() == shift.to_bits()
                })
                .and_then(|r| Some((r.reference, symbolic.changed_supernodes(r.changed)?)));
            let copy = changed.as_ref().map(|(r, c)| (*r, &c[..]));
            Self::factorize_shifted(symbolic, pattern, values, shift, copy)
        })
    }

    /// Adds the shift and factors, on the kept coordinates of a restricted analysis (the
    /// others' diagonal apart), or with the whole pattern's analysis when the matrix couples a
    /// left-out coordinate.
    fn factorize_shifted(
        symbolic: &Arc<SymbolicFactor>,
        pattern: &Pattern,
        values: &[f64],
        shift: f64,
        reuse: Option<(&Cholesky, &[bool])>,
    ) -> Result<Cholesky, NotPositiveDefinite> {
        if let Some(r) = &symbolic.restriction {
            if r.coupling.iter().any(|&k| values[k] != 0.0) {
                return Self::factorize_shifted(&r.full, pattern, values, shift, None);
            }
            let mut rest = Vec::with_capacity(r.rest.len());
            for &(j, k) in &r.rest {
                let d = values[k] + shift;
                if !(d > 0.0 && d.is_finite()) {
                    return Err(NotPositiveDefinite { column: j });
                }
                rest.push(d);
            }
            let mut sub: Vec<f64> = r.slots.iter().map(|&k| values[k]).collect();
            for &d in &r.sub.diag {
                sub[d] += shift;
            }
            let mut f = Self::factorize_kept(symbolic, &r.sub, &sub, reuse)?;
            f.rest = rest;
            f.shift = shift;
            return Ok(f);
        }
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
        let mut f = Self::factorize_kept(symbolic, pattern, vals, reuse)?;
        f.shift = shift;
        Ok(f)
    }

    /// Factors the matrix with upper-triangle `vals` on `pattern`, the pattern `symbolic`
    /// analysed (the whole pattern, or the kept coordinates of a restricted analysis).
    fn factorize_kept(
        symbolic: &Arc<SymbolicFactor>,
        pattern: &Pattern,
        vals: &[f64],
        reuse: Option<(&Cholesky, &[bool])>,
    ) -> Result<Cholesky, NotPositiveDefinite> {
        let sym = &symbolic.inner;
        let mut l_values = symbolic.take_values();
        if let Some(plan) = symbolic.plan.as_ref() {
            let result = match reuse {
                Some((reference, changed)) => {
                    plan.factorize_partial(vals, &mut l_values, &reference.values, changed)
                }
                None => plan.factorize(vals, &mut l_values),
            };
            return match result {
                Ok(()) => Ok(Cholesky {
                    symbolic: symbolic.clone(),
                    values: l_values,
                    rest: Vec::new(),
                    shift: 0.0,
                }),
                Err(column) => {
                    symbolic.give_values(l_values);
                    Err(NotPositiveDefinite { column })
                }
            };
        }
        let a = SparseColMatRef::new(pattern.symbolic(), vals);
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
                rest: Vec::new(),
                shift: 0.0,
            }),
            Err(faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index }) => {
                symbolic.give_values(l_values);
                Err(NotPositiveDefinite { column: index })
            }
        }
    }

    /// Solves `(H + τI) X = B` in place for the columns of `rhs`, on `schedule`.
    pub fn solve_in_place(&self, rhs: MatMut<'_, f64>, schedule: Schedule) {
        let schedule = match schedule {
            Schedule::Groups(g) => Schedule::Groups(g.max(1)),
            s => s,
        };
        crate::profile::time(crate::profile::Phase::Solve, || {
            self.solve_scheduled(rhs, schedule)
        })
    }

    /// Solves for one right-hand side given as a slice, on [`Schedule::Subtrees`].
    pub fn solve_vec(&self, rhs: &mut [f64]) {
        let n = rhs.len();
        let m = faer::MatMut::from_column_major_slice_mut(rhs, n, 1);
        self.solve_in_place(m, Schedule::Subtrees);
    }

    fn solve_scheduled(&self, rhs: MatMut<'_, f64>, how: Schedule) {
        let Some(r) = &self.symbolic.restriction else {
            self.solve_kept(rhs, how);
            return;
        };
        assert_eq!(rhs.nrows(), r.n_full, "right-hand side of the full size");
        let mut rhs = rhs;
        let mut sub = Mat::<f64>::from_fn(r.dofs.len(), rhs.ncols(), |i, j| rhs[(r.dofs[i], j)]);
        self.solve_kept(sub.as_mut(), how);
        for j in 0..rhs.ncols() {
            for (i, &d) in r.dofs.iter().enumerate() {
                rhs[(d, j)] = sub[(i, j)];
            }
            for (&(d, _), &diag) in r.rest.iter().zip(&self.rest) {
                rhs[(d, j)] /= diag;
            }
        }
    }

    /// Solves on the coordinates the factor covers.
    fn solve_kept(&self, rhs: MatMut<'_, f64>, how: Schedule) {
        let group = match how {
            Schedule::Subtrees => {
                self.solve_subtrees(rhs);
                return;
            }
            Schedule::Groups(group) => group,
        };
        // Columns are solved in fixed groups of `group`, in parallel when threads are
        // free. faer's result for a column depends on which columns share its call, so the
        // grouping is fixed (never by thread count) to keep results bit-identical.
        let k = rhs.ncols();
        if k <= group {
            self.solve_group(rhs);
            return;
        }
        let mut groups = Vec::with_capacity(k.div_ceil(group));
        let mut rest = rhs;
        while rest.ncols() > group {
            let (a, b) = rest.split_at_col_mut(group);
            groups.push(a);
            rest = b;
        }
        groups.push(rest);
        use rayon::prelude::*;
        groups.into_par_iter().for_each(|g| self.solve_group(g));
    }

    /// All the columns of `rhs` in one subtree-parallel substitution (faer's sequential one
    /// for analyses without a plan): bit-identical to [`Self::solve_group`].
    fn solve_subtrees(&self, mut rhs: MatMut<'_, f64>) {
        let sym = &self.symbolic.inner;
        if let Some(plan) = self.symbolic.plan.as_ref() {
            match sym.perm() {
                Some(perm) => {
                    let (fwd, inv) = perm.arrays();
                    let mut x = Mat::from_fn(rhs.nrows(), rhs.ncols(), |i, j| rhs[(fwd[i], j)]);
                    plan.solve_in_place(&self.values, x.as_mut());
                    for j in 0..rhs.ncols() {
                        for (i, &p) in inv.iter().enumerate() {
                            rhs[(i, j)] = x[(p, j)];
                        }
                    }
                }
                None => plan.solve_in_place(&self.values, rhs),
            }
        } else {
            self.solve_group(rhs);
        }
    }

    /// All the columns of `rhs` in one call of faer's sequential substitution.
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
}
