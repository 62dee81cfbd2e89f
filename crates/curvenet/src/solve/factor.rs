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
    /// When this analysis covers only some coordinates of a larger pattern (see
    /// [`SymbolicFactor::restricted`]): how they sit in it.
    restriction: Option<Restriction>,
    /// The subtree-parallel numeric factorization of a supernodal analysis (see
    /// `solve::supernodal`); `None` for simplicial analyses, which faer factors.
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

static SUBTREE_PARALLEL: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(true);

/// Switches the subtree-parallel numeric factorization and substitution
/// ([`Cholesky::solve_in_place_subtrees`], `solve::supernodal`) on (the default) or off
/// (faer's sequential supernodal factorization and substitution), for the whole process: a
/// benchmark switch. Both give the same factor up to round-off, and the same substitution bit
/// for bit; each is deterministic.
pub fn set_subtree_parallel(on: bool) {
    SUBTREE_PARALLEL.store(on, std::sync::atomic::Ordering::Relaxed);
}

fn subtree_parallel() -> bool {
    SUBTREE_PARALLEL.load(std::sync::atomic::Ordering::Relaxed)
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
    /// Analyses `pattern`: AMD, and on networks of more than [`ND_MIN_DOFS`] unknowns also
    /// nested dissection, keeping the ordering with less fill (see [`super::ordering`]).
    pub fn new(pattern: &Pattern) -> Arc<Self> {
        Arc::new(Self::analyse(pattern))
    }

    /// An analysis of the coordinates `keep` selects (`keep.len() == pattern.n`) for matrices
    /// on `pattern` whose other coordinates are decoupled (no stored off-diagonal entry of the
    /// matrix touches them: loose vertices, which only carry a diagonal). Factorizations with
    /// it take values on the whole `pattern` and give a factor of the whole matrix — the
    /// principal submatrix on `keep` factored sparsely, the rest a diagonal — at the cost of
    /// the kept coordinates only. A matrix that does couple a left-out coordinate is factored
    /// with `full` (the whole pattern's analysis) instead: the result is always exact.
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
        // 14% more fill on the tower), with the whole network's choice of method.
        let mut analysis = Self::analyse_preferring(&sub, Some(full.ordering));

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

    fn analyse(pattern: &Pattern) -> Self {
        Self::analyse_preferring(pattern, None)
    }

    /// AMD and, on patterns of at least [`ND_MIN_DOFS`] unknowns, nested dissection, keeping
    /// the one with less fill; with `prefer` set to nested dissection (a part of a network
    /// whose own analysis chose it), nested dissection alone when it is available.
    fn analyse_preferring(pattern: &Pattern, prefer: Option<OrderingKind>) -> Self {
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
        Self::finish(pattern, best.0, best.1)
    }

    /// The analysis of `pattern` with the supernodes of `inner` (an analysis of it) renumbered
    /// in postorder, and the subtree-parallel factorization's plan.
    fn finish(
        pattern: &Pattern,
        mut inner: SymbolicCholesky<usize>,
        ordering: OrderingKind,
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
            SymbolicCholeskyRaw::Supernodal(sup) => Plan::new(
                sup,
                inner.perm().map(|p| p.arrays().1),
                &pattern.col_ptr,
                &pattern.row_idx,
            ),
            SymbolicCholeskyRaw::Simplicial(_) => None,
        };
        SymbolicFactor {
            inner,
            ordering,
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

    /// The share of a factorization's work that [`Cholesky::factorize_reusing`] redoes when
    /// the matrix changes only in rows and columns `coords` (1 without a plan).
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
    /// parallel (1: sequential; 0: faer's own factorization, for simplicial analyses).
    pub fn parallel_subtrees(&self) -> usize {
        self.plan.as_ref().map_or(0, Plan::parallel_tasks)
    }

    /// Independent subtrees Newton's triangular substitutions run in parallel
    /// ([`Cholesky::solve_in_place_subtrees`]; 1: sequential; 0: faer's substitution, for
    /// simplicial analyses).
    pub fn parallel_solve_subtrees(&self) -> usize {
        self.plan.as_ref().map_or(0, Plan::parallel_solve_tasks)
    }

    /// Number of stored values in the factor `L`.
    pub fn factor_nnz(&self) -> usize {
        self.inner.len_val()
    }
}

/// How a solve runs its triangular substitutions.
#[derive(Clone, Copy, Debug)]
enum Substitution {
    /// Fixed groups of this many columns in parallel, each by faer's sequential substitution.
    Groups(usize),
    /// All the columns in one substitution whose independent subtrees run in parallel.
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

/// A factorization to copy values from: [`Cholesky::factorize_reusing`]'s reference, and the
/// coordinates (of the whole pattern) whose rows and columns hold every entry in which the
/// new matrix differs from the reference's.
#[derive(Clone, Copy, Debug)]
pub struct Reuse<'a> {
    /// A factorization with the same analysis and shift.
    pub reference: &'a Cholesky,
    /// Coordinates of the entries that may differ (both row and column among them).
    pub changed: &'a [usize],
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
            Self::factorize_impl(symbolic, pattern, values, shift, subtree_parallel())
        })
    }

    /// [`Cholesky::factorize`] with faer's own sequential numeric factorization: the
    /// reference the subtree-parallel one (`solve::supernodal`) is tested against.
    pub fn factorize_reference(
        symbolic: &Arc<SymbolicFactor>,
        pattern: &Pattern,
        values: &[f64],
        shift: f64,
    ) -> Result<Cholesky, NotPositiveDefinite> {
        Self::factorize_impl(symbolic, pattern, values, shift, false)
    }

    /// [`Cholesky::factorize_reusing`] when `reuse` is given, else [`Cholesky::factorize`].
    pub fn factorize_maybe_reusing(
        symbolic: &Arc<SymbolicFactor>,
        pattern: &Pattern,
        values: &[f64],
        shift: f64,
        reuse: Option<Reuse<'_>>,
    ) -> Result<Cholesky, NotPositiveDefinite> {
        match reuse {
            Some(r) => {
                Self::factorize_reusing(symbolic, pattern, values, shift, r.reference, r.changed)
            }
            None => Self::factorize(symbolic, pattern, values, shift),
        }
    }

    /// [`Cholesky::factorize`] of a matrix that differs from the one `reference` factors
    /// only in entries whose row and column both lie in `changed` (coordinates of the whole
    /// pattern), with the same analysis and shift: the supernodes the difference cannot
    /// reach are copied from `reference`, the others factored. The factor is bit-identical
    /// to [`Cholesky::factorize`]'s (same values, same operations). Falls back to a whole
    /// factorization when the reference does not fit (another analysis or shift, no
    /// subtree-parallel plan).
    pub fn factorize_reusing(
        symbolic: &Arc<SymbolicFactor>,
        pattern: &Pattern,
        values: &[f64],
        shift: f64,
        reference: &Cholesky,
        changed: &[usize],
    ) -> Result<Cholesky, NotPositiveDefinite> {
        crate::profile::time(crate::profile::Phase::Factor, || {
            let fits = Arc::ptr_eq(symbolic, &reference.symbolic)
                && reference.shift.to_bits() == shift.to_bits()
                && subtree_parallel();
            let Some(changed) = fits.then(|| symbolic.changed_supernodes(changed)).flatten() else {
                return Self::factorize_impl(symbolic, pattern, values, shift, subtree_parallel());
            };
            Self::factorize_with(
                symbolic,
                pattern,
                values,
                shift,
                true,
                Some((reference, &changed)),
            )
        })
    }

    fn factorize_impl(
        symbolic: &Arc<SymbolicFactor>,
        pattern: &Pattern,
        values: &[f64],
        shift: f64,
        tree: bool,
    ) -> Result<Cholesky, NotPositiveDefinite> {
        Self::factorize_with(symbolic, pattern, values, shift, tree, None)
    }

    fn factorize_with(
        symbolic: &Arc<SymbolicFactor>,
        pattern: &Pattern,
        values: &[f64],
        shift: f64,
        tree: bool,
        reuse: Option<(&Cholesky, &[bool])>,
    ) -> Result<Cholesky, NotPositiveDefinite> {
        if let Some(r) = &symbolic.restriction {
            if r.coupling.iter().any(|&k| values[k] != 0.0) {
                return Self::factorize_impl(&r.full, pattern, values, shift, tree);
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
            let mut f = Self::factorize_sub(symbolic, &r.sub, &sub, tree, reuse)?;
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
        let mut f = Self::factorize_sub(symbolic, pattern, vals, tree, reuse)?;
        f.shift = shift;
        Ok(f)
    }

    /// Factors the matrix with upper-triangle `vals` on `pattern`, the pattern `symbolic`
    /// analysed (the whole pattern, or the kept coordinates of a restricted analysis).
    fn factorize_sub(
        symbolic: &Arc<SymbolicFactor>,
        pattern: &Pattern,
        vals: &[f64],
        tree: bool,
        reuse: Option<(&Cholesky, &[bool])>,
    ) -> Result<Cholesky, NotPositiveDefinite> {
        let sym = &symbolic.inner;
        let mut l_values = symbolic.take_values();
        if let Some(plan) = symbolic.plan.as_ref().filter(|_| tree) {
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

    /// Solves `(H + τI) X = B` in place for the columns of `rhs`, in fixed groups of
    /// [`SOLVE_GROUP`] columns run in parallel.
    pub fn solve_in_place(&self, rhs: MatMut<'_, f64>) {
        self.solve_in_place_grouped(rhs, SOLVE_GROUP);
    }

    /// [`Self::solve_in_place`] in fixed groups of `group` columns (at least 1) run in
    /// parallel, each group by one sequential substitution: one column per group when the
    /// caller leaves a core idle (arched shell: a two-column solve 1.27 ms, a one-column one
    /// 0.86 ms, and two groups side by side cost little more than one), a few when every core
    /// is busy with other solves (one pass over the factor serves the group). A column's
    /// values depend on the grouping, never on the thread count.
    pub fn solve_in_place_grouped(&self, rhs: MatMut<'_, f64>, group: usize) {
        crate::profile::time(crate::profile::Phase::Solve, || {
            self.solve_impl(rhs, Substitution::Groups(group.max(1)))
        })
    }

    /// Solves `(H + τI) X = B` in place for all the columns of `rhs` in one substitution
    /// whose independent subtrees run in parallel (`solve::supernodal`; sequential when the
    /// analysis has no parallel schedule or [`set_subtree_parallel`] is off): for callers
    /// that leave the cores idle, such as Newton's steps (arched shell: 0.60 ms on two
    /// threads for one column, 0.78 ms sequential). Bit-identical to
    /// [`Self::solve_in_place_grouped`] with one group of all the columns; where the cores are
    /// busy with other work, its deferred updates make it about 10% slower than that.
    pub fn solve_in_place_subtrees(&self, rhs: MatMut<'_, f64>) {
        crate::profile::time(crate::profile::Phase::Solve, || {
            let how = if subtree_parallel() {
                Substitution::Subtrees
            } else {
                Substitution::Groups(rhs.ncols().max(1))
            };
            self.solve_impl(rhs, how)
        })
    }

    fn solve_impl(&self, rhs: MatMut<'_, f64>, how: Substitution) {
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
    fn solve_kept(&self, rhs: MatMut<'_, f64>, how: Substitution) {
        let group = match how {
            Substitution::Subtrees => {
                self.solve_subtrees(rhs);
                return;
            }
            Substitution::Groups(group) => group,
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

    /// Solves for one right-hand side given as a slice, by
    /// [`Self::solve_in_place_subtrees`].
    pub fn solve_vec(&self, rhs: &mut [f64]) {
        let n = rhs.len();
        let m = faer::MatMut::from_column_major_slice_mut(rhs, n, 1);
        self.solve_in_place_subtrees(m);
    }
}
