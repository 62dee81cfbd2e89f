//! Thick-restart block Lanczos for the largest eigenpairs of a symmetric operator.
//!
//! The stability analysis needs the few smallest eigenpairs of large sparse symmetric
//! matrices `H`. The caller does shift-and-invert with a sparse Cholesky factor and hands
//! this module the operator `Op = (H − σI)⁻¹`; [`largest_eigenpairs`] finds the
//! algebraically largest eigenvalues `μ` of `Op` (so `λ = σ + 1/μ`). With `H − σI`
//! positive definite, as a Cholesky factor requires, these belong to the eigenvalues of
//! `H` closest to `σ`.
//!
//! # Method
//!
//! * **Block** Krylov expansion (width [`BlockLanczosParams::block_size`]), so that
//!   eigenvalues of multiplicity up to the block size are all found.
//! * **Full reorthogonalisation** of every new block against the whole basis. The block
//!   Lanczos recurrence (coefficients known from `T`, touching only the last blocks) is
//!   the first orthogonalisation; a block classical Gram–Schmidt pass over the whole
//!   basis follows, and is repeated when it removes a large part of a column
//!   (Daniel–Gragg–Kaufman–Stewart criterion, "twice is enough"); columns that cancel
//!   within their block get a further pass. The basis stays orthonormal to ~1e-14.
//!   A rank-deficient block (an invariant subspace was found) is completed with fresh,
//!   seeded random vectors orthogonal to the basis, so the block keeps its width.
//! * The projected matrix `T = Vᵀ·Op·V` is kept as a small dense symmetric matrix, filled
//!   with the explicitly computed projection coefficients, and diagonalised with faer's
//!   dense self-adjoint eigensolver after every block (less often only if
//!   `max_basis² ≫ n·block_size`). Because of the full
//!   reorthogonalisation, the Lanczos relation `Op·V = V·T + Q·C` holds to rounding, so the
//!   residual of the Ritz pair `(θ, V·y)` is `‖C·y‖` at no extra operator cost.
//! * **Thick restart** (Krylov–Schur style): when the basis is full, it is compressed to
//!   the leading Ritz vectors (the wanted ones plus about half of the rest); `T` becomes
//!   diagonal bordered by the coupling to the pending block, and the iteration goes on.
//!
//! Everything in this module runs with [`faer::Par::Seq`] and draws its random numbers
//! from a self-contained splitmix64 generator seeded by [`BlockLanczosParams::seed`], so
//! the result is bit-identical for identical inputs, whatever the thread count (provided
//! the operator itself is deterministic).

use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::{ComputeEigenvectors, self_adjoint_evd, self_adjoint_evd_scratch};
use faer::linalg::matmul::matmul;
use faer::prelude::*;
use faer::{Accum, ColRef, Mat, MatMut, MatRef, Par};

#[cfg(test)]
mod tests;

/// Parameters of [`largest_eigenpairs`].
#[derive(Clone, Debug, PartialEq)]
pub struct BlockLanczosParams {
    /// Number of wanted eigenpairs (the largest eigenvalues of the operator). Default 4.
    pub nev: usize,
    /// Width of the Krylov blocks, at least 1. Eigenvalues of multiplicity up to
    /// `block_size` are reliably found. Default 3.
    pub block_size: usize,
    /// Maximum number of Krylov basis columns before a thick restart; must exceed
    /// `nev + block_size` unless it is at least `n`. The pending (not yet applied) block is
    /// stored on top of these. Default 60.
    pub max_basis: usize,
    /// Convergence tolerance: every wanted pair must satisfy
    /// `‖Op·y − μ·y‖ ≤ tol·|μ_max|`, with `μ_max` the Ritz value of largest magnitude
    /// (the pairs after the first: see [`Self::trailing_tol`]).
    /// Must be positive and finite. Default `1e-10`.
    pub tol: f64,
    /// The tolerance of the wanted pairs after the first, when they need less accuracy than
    /// the first (never below `tol`); `None`: `tol` for every pair. Default `None`.
    pub trailing_tol: Option<f64>,
    /// Maximum number of thick restarts before giving up with
    /// [`LanczosError::NotConverged`]. Default 50.
    pub max_restarts: usize,
    /// Seed of the deterministic random start and injection vectors. Default 0.
    pub seed: u64,
}

impl Default for BlockLanczosParams {
    fn default() -> Self {
        BlockLanczosParams {
            nev: 4,
            block_size: 3,
            max_basis: 60,
            tol: 1e-10,
            trailing_tol: None,
            max_restarts: 50,
            seed: 0,
        }
    }
}

impl BlockLanczosParams {
    /// The tolerance of wanted pair `j` (0: the first).
    pub fn tolerance(&self, j: usize) -> f64 {
        match self.trailing_tol {
            Some(t) if j > 0 => t.max(self.tol),
            _ => self.tol,
        }
    }

    /// Checks the parameters for an operator of dimension `n`.
    ///
    /// Requires `n ≥ 1`, `1 ≤ nev ≤ n`, `block_size ≥ 1`, a positive finite `tol`, and
    /// `max_basis > nev + block_size` unless `max_basis ≥ n` (the whole space fits in the
    /// basis, so no restart is ever needed).
    pub fn validate(&self, n: usize) -> Result<(), LanczosError> {
        let fail = |msg: String| Err(LanczosError::InvalidParams(msg));
        if n == 0 {
            return fail("operator dimension n must be at least 1".into());
        }
        if self.nev == 0 {
            return fail("nev must be at least 1".into());
        }
        if self.nev > n {
            return fail(format!(
                "nev = {} exceeds the operator dimension n = {n}",
                self.nev
            ));
        }
        if self.block_size == 0 {
            return fail("block_size must be at least 1".into());
        }
        if self.max_basis <= self.nev.saturating_add(self.block_size) && self.max_basis < n {
            return fail(format!(
                "max_basis = {} must exceed nev + block_size = {} + {} (or be at least n = {n})",
                self.max_basis, self.nev, self.block_size
            ));
        }
        if !(self.tol.is_finite() && self.tol > 0.0) {
            return fail(format!("tol = {} must be positive and finite", self.tol));
        }
        if let Some(t) = self.trailing_tol.filter(|t| !(t.is_finite() && *t > 0.0)) {
            return fail(format!("trailing_tol = {t} must be positive and finite"));
        }
        Ok(())
    }
}

/// Statistics of a [`largest_eigenpairs`] run.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockLanczosInfo {
    /// Number of thick restarts performed.
    pub restarts: usize,
    /// Number of operator applications, counted per column.
    pub applications: usize,
    /// Number of wanted pairs that met the tolerance.
    pub converged: usize,
    /// Residual norms `‖Op·y − μ·y‖` of the returned pairs (from the Lanczos relation,
    /// which full reorthogonalisation keeps accurate to rounding).
    pub residuals: Vec<f64>,
}

/// Eigenpairs returned by [`largest_eigenpairs`].
#[derive(Clone, Debug)]
pub struct EigenPairs {
    /// Eigenvalues `μ` of the operator, in descending order.
    pub values: Vec<f64>,
    /// The matching eigenvectors, `n × nev`, orthonormal columns; each column's entry of
    /// largest magnitude (the first one on ties) is positive.
    pub vectors: Mat<f64>,
    /// Run statistics.
    pub info: BlockLanczosInfo,
}

/// Errors of [`largest_eigenpairs`].
#[derive(Debug, thiserror::Error)]
pub enum LanczosError {
    /// The parameters, dimension or warm start are unusable; nothing was computed.
    #[error("invalid Lanczos parameters: {0}")]
    InvalidParams(String),
    /// The operator (or the warm start) produced NaN or infinite values.
    #[error("non-finite values: {0}")]
    NonFinite(String),
    /// The Krylov basis could not be extended with new directions before `nev` Ritz
    /// pairs existed (not expected in practice: needs random vectors to fail repeatedly).
    #[error("block Lanczos breakdown: {0}")]
    Breakdown(String),
    /// faer's dense symmetric eigensolver failed on the projected matrix.
    #[error("dense eigensolver failed: {0}")]
    DenseEigen(String),
    /// The tolerance was not met within `max_restarts`; the best approximations found
    /// (with their residuals in `info`) are attached.
    #[error(
        "block Lanczos did not converge: {}/{} pairs after {} restarts and {} applications",
        .0.info.converged, .0.values.len(), .0.info.restarts, .0.info.applications
    )]
    NotConverged(Box<EigenPairs>),
}

/// Columns whose norm falls below this fraction of the operator output's norm are
/// treated as linearly dependent (replaced by random vectors).
const EXPAND_DROP_TOL: f64 = 1e-14;
/// Same for warm-start columns: nearly dependent warm vectors are better replaced by
/// random ones than normalised rounding noise.
const START_DROP_TOL: f64 = 1e-10;
/// A further full orthogonalisation pass over the block is made while a pass keeps less
/// than this fraction of some column's norm (Daniel–Gragg–Kaufman–Stewart criterion).
const DGKS_RATIO: f64 = std::f64::consts::FRAC_1_SQRT_2;
/// Random vectors are orthogonalised again while a pass keeps less than this fraction.
const REORTH_RATIO: f64 = 0.5;
/// Orthogonalising a column against the other new columns of its block (already
/// orthogonal to the basis) amplifies its residual components along the basis by the
/// norm ratio; beyond this ratio a further full pass is made (components stay below
/// `≈ 100·√m·ε`).
const BLOCK_CANCEL_RATIO: f64 = 1e-2;
/// Rows per chunk when rotating the basis at a restart (bounds the scratch memory).
const ROTATE_CHUNK: usize = 1024;

/// Finds the `params.nev` algebraically largest eigenpairs of the symmetric operator
/// `Op` of dimension `n`.
///
/// `apply(x, y)` must set `y = Op·x` for a block of columns (`x` and `y` are `n × b`,
/// column-major; `y` is zero on entry). `Op` must be symmetric; for shift-and-invert
/// `Op = (H − σI)⁻¹`, and the eigenvalues of `H` are `σ + 1/μ`.
///
/// `warm_start` (optional, `n × m`, any `m`) gives start vectors, for instance the
/// previous solution of a slightly perturbed problem; they need not be orthonormal. The
/// blocks have width `max(block_size, min(m, nev))` (capped at `n`, and at
/// `max_basis − nev − 1` if `max_basis < n`); the first that many warm columns are used and orthonormalised, and dependent or
/// missing columns are filled with seeded random vectors. An `n × 0` warm start is the
/// same as none.
///
/// Small problems (`n ≤ max_basis`) are handled by the same iteration, which then ends
/// with the Krylov basis spanning the whole space at worst (an exact dense solve).
///
/// Memory: `n × (min(max_basis + width, n) + width)` doubles for the basis and the
/// operator output, plus `O(max_basis²)`. Work per block of `b` columns, besides the `b`
/// operator applications: `≈ 8·n·m·b` flops of reorthogonalisation (`m` = current basis
/// size) and a dense `m × m` eigensolve; `≈ 2·n·m·k` per thick restart.
///
/// # Errors
///
/// [`LanczosError::InvalidParams`] for bad parameters or a warm start with the wrong
/// number of rows; [`LanczosError::NonFinite`] if the operator (or warm start) yields NaN
/// or infinity; [`LanczosError::NotConverged`] (with the best approximations) if the
/// tolerance is not met within `max_restarts`; [`LanczosError::DenseEigen`] if faer's
/// dense eigensolver fails on the small projected matrix; [`LanczosError::Breakdown`] in
/// the (practically unreachable) case that no new Krylov direction can be found.
pub fn largest_eigenpairs(
    n: usize,
    apply: impl FnMut(MatRef<'_, f64>, MatMut<'_, f64>),
    warm_start: Option<MatRef<'_, f64>>,
    params: &BlockLanczosParams,
) -> Result<EigenPairs, LanczosError> {
    params.validate(n)?;
    if let Some(w) = warm_start.filter(|w| w.nrows() != n) {
        return Err(LanczosError::InvalidParams(format!(
            "warm start has {} rows, expected n = {n}",
            w.nrows()
        )));
    }
    let warm_cols = warm_start.map_or(0, |w| w.ncols());
    // Width of the first (and every following) block: room for up to `nev` warm vectors.
    // If restarts can happen (`max_basis < n`), validation gives
    // `max_basis − nev − 1 ≥ block_size`, and this cap leaves room to keep `nev + 1` Ritz
    // vectors at a restart.
    let mut width = params.block_size.max(warm_cols.min(params.nev)).min(n);
    if params.max_basis < n {
        width = width.min(params.max_basis - params.nev - 1);
    }
    let mut solver = Solver::new(n, apply, width, params)?;
    solver.start(warm_start)?;
    solver.run()
}

/// The `k` smallest eigenpairs of the dense symmetric matrix `a` (only its lower triangle
/// is read), eigenvalues ascending, vectors `n × k` with the sign convention of
/// [`EigenPairs::vectors`]. `k` is clamped to `n`.
///
/// Meant for tests and small problems. It never panics on bad input: a non-square or
/// non-finite matrix, or a failure of the dense eigensolver, yields empty output; use
/// [`try_smallest_eigenpairs_dense`] to get the reason instead.
pub fn smallest_eigenpairs_dense(a: MatRef<'_, f64>, k: usize) -> (Vec<f64>, Mat<f64>) {
    try_smallest_eigenpairs_dense(a, k).unwrap_or_else(|_| (Vec::new(), Mat::zeros(0, 0)))
}

/// Fallible form of [`smallest_eigenpairs_dense`].
///
/// # Errors
///
/// [`LanczosError::InvalidParams`] if `a` is not square, [`LanczosError::NonFinite`] if
/// its lower triangle holds NaN or infinity, [`LanczosError::DenseEigen`] if faer's
/// eigensolver fails.
pub fn try_smallest_eigenpairs_dense(
    a: MatRef<'_, f64>,
    k: usize,
) -> Result<(Vec<f64>, Mat<f64>), LanczosError> {
    let n = a.nrows();
    if a.ncols() != n {
        return Err(LanczosError::InvalidParams(format!(
            "matrix is {} × {}, not square",
            n,
            a.ncols()
        )));
    }
    for j in 0..n {
        for i in j..n {
            if !a[(i, j)].is_finite() {
                return Err(LanczosError::NonFinite(format!(
                    "matrix entry ({i}, {j}) is {}",
                    a[(i, j)]
                )));
            }
        }
    }
    let k = k.min(n);
    let (values, vectors) = sym_eig_ascending(a)?;
    let mut x = vectors.subcols(0, k).to_owned();
    normalize_signs(x.as_mut());
    Ok((values[..k].to_vec(), x))
}

/// Dense symmetric eigendecomposition (lower triangle read), eigenvalues ascending.
fn sym_eig_ascending(a: MatRef<'_, f64>) -> Result<(Vec<f64>, Mat<f64>), LanczosError> {
    let k = a.nrows();
    let mut s = Diag::<f64>::zeros(k);
    let mut u = Mat::<f64>::zeros(k, k);
    let mut mem = MemBuffer::new(self_adjoint_evd_scratch::<f64>(
        k,
        ComputeEigenvectors::Yes,
        Par::Seq,
        Default::default(),
    ));
    self_adjoint_evd(
        a,
        s.as_mut(),
        Some(u.as_mut()),
        Par::Seq,
        MemStack::new(&mut mem),
        Default::default(),
    )
    .map_err(|e| LanczosError::DenseEigen(format!("{e:?} on a {k} × {k} matrix")))?;
    let values = (0..k).map(|i| s.column_vector()[i]).collect();
    Ok((values, u))
}

/// Flips each column so that its entry of largest magnitude (the first on ties) is
/// positive.
fn normalize_signs(mut x: MatMut<'_, f64>) {
    for j in 0..x.ncols() {
        let mut col = x.rb_mut().col_mut(j);
        let mut best = 0.0_f64;
        let mut best_val = 0.0_f64;
        for i in 0..col.nrows() {
            let v = col[i];
            if v.abs() > best {
                best = v.abs();
                best_val = v;
            }
        }
        if best_val < 0.0 {
            for i in 0..col.nrows() {
                col[i] = -col[i];
            }
        }
    }
}

/// splitmix64, mapped to uniform numbers in `[-1, 1)`.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn uniform(&mut self) -> f64 {
        // 53 random bits → [0, 1) → [-1, 1).
        ((self.next_u64() >> 11) as f64) * (2.0 / (1u64 << 53) as f64) - 1.0
    }
}

/// `x ← x − B·(Bᵀx)`, `coef ← Bᵀx` (one classical Gram–Schmidt pass, `x` is `n × 1`).
fn project_out(basis: MatRef<'_, f64>, x: MatMut<'_, f64>, mut coef: MatMut<'_, f64>) {
    if basis.ncols() == 0 {
        return;
    }
    matmul(
        coef.rb_mut(),
        Accum::Replace,
        basis.transpose(),
        x.rb(),
        1.0,
        Par::Seq,
    );
    matmul(x, Accum::Add, basis, coef.rb(), -1.0, Par::Seq);
}

/// Euclidean norm: plain sum of squares when that is safe, faer's scaled (robust, but
/// much slower on entries below 1, whose scaled squares are subnormal) otherwise.
fn norm2(x: ColRef<'_, f64>) -> f64 {
    let s = x.squared_norm_l2();
    if s.is_nan() || (s.is_finite() && s >= 1e-250) {
        s.sqrt()
    } else {
        x.norm_l2()
    }
}

/// Column norms of `w`.
fn col_norms(w: MatRef<'_, f64>) -> Vec<f64> {
    (0..w.ncols()).map(|j| norm2(w.col(j))).collect()
}

/// Ritz values (descending), vectors (columns of `y`, same order) and residual norms.
struct Ritz {
    theta: Vec<f64>,
    y: Mat<f64>,
    res: Vec<f64>,
}

/// State of one block Lanczos run.
///
/// Invariants between steps: `v[:, 0..m]` is the orthonormal basis whose operator images
/// are known, `v[:, m..m+p]` the pending block (orthonormal to it, not yet applied);
/// `t[0..m, 0..m] = Vᵀ·Op·V` and `t[m..m+p, 0..m] = C`, with `Op·V = V·T + P·C`.
struct Solver<'p, F> {
    n: usize,
    apply: F,
    params: &'p BlockLanczosParams,
    v: Mat<f64>,
    t: Mat<f64>,
    w: Mat<f64>,
    m: usize,
    p: usize,
    rng: SplitMix64,
    applications: usize,
    restarts: usize,
}

impl<'p, F: FnMut(MatRef<'_, f64>, MatMut<'_, f64>)> Solver<'p, F> {
    fn new(
        n: usize,
        apply: F,
        width: usize,
        params: &'p BlockLanczosParams,
    ) -> Result<Self, LanczosError> {
        // Active basis ≤ max_basis, pending block ≤ width on top; never more than n. The
        // basis storage is reserved up front (fallibly) but its columns are initialised
        // only as the basis grows into them.
        let cap = params.max_basis.saturating_add(width).min(n);
        let mut v = Mat::new();
        let mut t = Mat::new();
        let mut w = Mat::new();
        let reserved = v
            .try_reserve(n, cap)
            .and_then(|()| t.try_reserve(cap, cap))
            .and_then(|()| w.try_reserve(n, width));
        if reserved.is_err() {
            return Err(LanczosError::InvalidParams(format!(
                "cannot allocate a {n} × {cap} Krylov basis (reduce max_basis)"
            )));
        }
        v.resize_with(n, 0, |_, _| 0.0);
        t.resize_with(cap, cap, |_, _| 0.0);
        w.resize_with(n, width, |_, _| 0.0);
        Ok(Solver {
            n,
            apply,
            params,
            v,
            t,
            w,
            m: 0,
            p: 0,
            rng: SplitMix64(params.seed),
            applications: 0,
            restarts: 0,
        })
    }

    /// Builds the first (pending) block from the warm start and random columns.
    fn start(&mut self, warm_start: Option<MatRef<'_, f64>>) -> Result<(), LanczosError> {
        let width = self.w.ncols();
        let used = warm_start.map_or(0, |ws| ws.ncols().min(width));
        if let Some(ws) = warm_start {
            for j in 0..used {
                for i in 0..self.n {
                    let x = ws[(i, j)];
                    if !x.is_finite() {
                        return Err(LanczosError::NonFinite(format!(
                            "warm start entry ({i}, {j}) is {x}"
                        )));
                    }
                }
            }
            self.w.subcols_mut(0, used).copy_from(ws.subcols(0, used));
        }
        let w = self.w.as_mut().subcols_mut(0, used);
        let a0 = col_norms(w.rb());
        let r = orthonormalize_block(
            &mut self.v,
            0,
            w,
            &a0,
            &a0,
            None,
            width,
            &mut self.rng,
            START_DROP_TOL,
        );
        self.m = 0;
        self.p = r.nrows();
        Ok(())
    }

    /// Main loop: expand, check, restart.
    fn run(mut self) -> Result<EigenPairs, LanczosError> {
        let nev = self.params.nev;
        // Basis size from which the next convergence check is due (see below).
        let mut next_check = nev;
        loop {
            if self.p == 0 && self.m < nev {
                // Only reachable if random injection failed, which needs an exhausted space.
                return Err(LanczosError::Breakdown(format!(
                    "Krylov basis stuck at {} < nev = {nev} columns",
                    self.m
                )));
            }
            self.expand()?;
            let at_restart = self.m + self.p > self.params.max_basis;
            // A check costs O(m³) for the dense eigensolver against O(n·m·p) per block
            // for the reorthogonalisation: check every block unless m² ≫ n·p (only for
            // huge max_basis), and always before a restart or at the end of the space.
            if self.m < nev || (self.m < next_check && !at_restart && self.p > 0) {
                continue;
            }
            let ritz = self.ritz()?;
            let scale = ritz
                .theta
                .iter()
                .fold(f64::MIN_POSITIVE, |acc, t| acc.max(t.abs()));
            let converged = (0..nev)
                .filter(|&j| ritz.res[j] <= self.params.tolerance(j) * scale)
                .count();
            // p == 0: the basis spans an invariant subspace (the whole space for n ≤
            // max_basis), so T is exact.
            if converged == nev || self.p == 0 {
                return Ok(self.finish(&ritz, converged));
            }
            if at_restart {
                if self.restarts >= self.params.max_restarts {
                    return Err(LanczosError::NotConverged(Box::new(
                        self.finish(&ritz, converged),
                    )));
                }
                self.restart(&ritz);
            }
            next_check =
                self.m + self.m.saturating_mul(self.m) / self.n.saturating_mul(4 * self.p.max(1));
        }
    }

    /// Applies the operator to the pending block, orthogonalises the images against the
    /// whole basis and forms the next pending block.
    fn expand(&mut self) -> Result<(), LanczosError> {
        let (n, m, p) = (self.n, self.m, self.p);
        let mp = m + p;
        let mut w = self.w.as_mut().subcols_mut(0, p);
        w.fill(0.0);
        (self.apply)(self.v.as_ref().subcols(m, p), w.rb_mut());
        self.applications += p;
        let a0 = col_norms(w.rb());
        if let Some(j) = a0.iter().position(|x| !x.is_finite()) {
            return Err(LanczosError::NonFinite(format!(
                "operator output column {j} contains NaN or infinity"
            )));
        }

        // Local pass (the block Lanczos recurrence): by symmetry and the relation
        // `Op·V = V·T + P·C`, the projection of `Op·P` on the old basis is `Cᵀ` and needs
        // no pass over `V`; only the diagonal block `A = Pᵀ·Op·P` is computed. `C` is
        // zero left of column `c0` (it is `[0, R]` after a plain step, dense after a
        // thick restart).
        let mut h = Mat::<f64>::zeros(mp, p);
        matmul(
            h.as_mut().subrows_mut(m, p),
            Accum::Replace,
            self.v.as_ref().subcols(m, p).transpose(),
            w.rb(),
            1.0,
            Par::Seq,
        );
        let c0 = (0..m)
            .find(|&i| (0..p).any(|j| self.t[(m + j, i)] != 0.0))
            .unwrap_or(m);
        for i in c0..m {
            for j in 0..p {
                h[(i, j)] = self.t[(m + j, i)];
            }
        }
        matmul(
            w.rb_mut(),
            Accum::Add,
            self.v.as_ref().subcols(c0, mp - c0),
            h.as_ref().subrows(c0, mp - c0),
            -1.0,
            Par::Seq,
        );

        // Full reorthogonalisation against the whole basis (incl. P): a block classical
        // Gram–Schmidt pass, made a second time if it removed more than 1 − 1/√2 of some
        // column's norm (Daniel–Gragg–Kaufman–Stewart criterion). With the local pass as
        // the first orthogonalisation this is "twice is enough" at one sweep over `V`
        // in the usual case (two near an invariant subspace), instead of two to four.
        let basis = self.v.as_ref().subcols(0, mp);
        let mut before = col_norms(w.rb());
        let mut h2 = Mat::<f64>::zeros(mp, p);
        for _ in 0..2 {
            matmul(
                h2.as_mut(),
                Accum::Replace,
                basis.transpose(),
                w.rb(),
                1.0,
                Par::Seq,
            );
            matmul(w.rb_mut(), Accum::Add, basis, h2.as_ref(), -1.0, Par::Seq);
            h += &h2;
            let after = col_norms(w.rb());
            let again = after.iter().zip(&before).any(|(a, b)| *a < DGKS_RATIO * b);
            before = after;
            if !again {
                break;
            }
        }
        let a1 = before;

        let q_target = p.min(n - mp);
        let r = orthonormalize_block(
            &mut self.v,
            mp,
            w,
            &a0,
            &a1,
            Some(h.as_mut()),
            q_target,
            &mut self.rng,
            EXPAND_DROP_TOL,
        );
        let q = r.nrows();

        // T[:, m..mp] = H (and its transpose), diagonal block symmetrised.
        let t = &mut self.t;
        for j in 0..p {
            for i in 0..m {
                t[(i, m + j)] = h[(i, j)];
                t[(m + j, i)] = h[(i, j)];
            }
            for i in 0..p {
                t[(m + i, m + j)] = 0.5 * (h[(m + i, j)] + h[(m + j, i)]);
            }
        }
        // New coupling C = [0 … 0, R] between the new pending block and the basis.
        for i in 0..q {
            for j in 0..mp + q {
                t[(mp + i, j)] = 0.0;
                t[(j, mp + i)] = 0.0;
            }
            for j in 0..p {
                t[(mp + i, m + j)] = r[(i, j)];
                t[(m + j, mp + i)] = r[(i, j)];
            }
        }
        self.m = mp;
        self.p = q;
        Ok(())
    }

    /// Ritz pairs of the current basis, with residual norms `‖C·y‖`.
    fn ritz(&self) -> Result<Ritz, LanczosError> {
        let (m, p) = (self.m, self.p);
        let (asc, u) = sym_eig_ascending(self.t.as_ref().submatrix(0, 0, m, m))?;
        if asc.iter().any(|x| !x.is_finite()) {
            return Err(LanczosError::NonFinite(
                "projected matrix has non-finite eigenvalues".into(),
            ));
        }
        let theta: Vec<f64> = asc.iter().rev().copied().collect();
        let mut y = Mat::<f64>::zeros(m, m);
        for j in 0..m {
            y.col_mut(j).copy_from(u.col(m - 1 - j));
        }
        let mut cy = Mat::<f64>::zeros(p, m);
        matmul(
            cy.as_mut(),
            Accum::Replace,
            self.t.as_ref().submatrix(m, 0, p, m),
            y.as_ref(),
            1.0,
            Par::Seq,
        );
        let res = col_norms(cy.as_ref());
        Ok(Ritz { theta, y, res })
    }

    /// Thick restart: compresses the basis to the leading Ritz vectors.
    fn restart(&mut self, ritz: &Ritz) {
        let (n, m, p) = (self.n, self.m, self.p);
        let nev = self.params.nev;
        // Keep the wanted pairs plus about half of the free room; at least nev + 1 fits
        // because p ≤ max_basis − nev − 1.
        let free = self.params.max_basis - p - nev;
        let k = (nev + free.div_ceil(2)).min(m - 1);
        let yk = ritz.y.as_ref().subcols(0, k);

        // V[:, :k] = V[:, :m]·Y_k, by row chunks to bound the scratch memory.
        let mut tmp = Mat::<f64>::zeros(ROTATE_CHUNK.min(n), k);
        let mut r0 = 0;
        while r0 < n {
            let rows = ROTATE_CHUNK.min(n - r0);
            let mut tmp_rows = tmp.as_mut().subrows_mut(0, rows);
            matmul(
                tmp_rows.rb_mut(),
                Accum::Replace,
                self.v.as_ref().submatrix(r0, 0, rows, m),
                yk,
                1.0,
                Par::Seq,
            );
            self.v
                .as_mut()
                .submatrix_mut(r0, 0, rows, k)
                .copy_from(tmp_rows.rb());
            r0 += rows;
        }
        // Move the pending block from columns m.. to k.. (k < m: increasing order is safe).
        for j in 0..p {
            let (left, right) = self.v.as_mut().split_at_col_mut(m + j);
            left.col_mut(k + j).copy_from(right.col(0));
        }
        // New coupling C·Y_k, and T = diag(θ) bordered by it.
        let mut cy = Mat::<f64>::zeros(p, k);
        matmul(
            cy.as_mut(),
            Accum::Replace,
            self.t.as_ref().submatrix(m, 0, p, m),
            yk,
            1.0,
            Par::Seq,
        );
        let t = &mut self.t;
        t.as_mut().submatrix_mut(0, 0, k + p, k + p).fill(0.0);
        for i in 0..k {
            t[(i, i)] = ritz.theta[i];
        }
        for i in 0..p {
            for j in 0..k {
                t[(k + i, j)] = cy[(i, j)];
                t[(j, k + i)] = cy[(i, j)];
            }
        }
        self.m = k;
        self.restarts += 1;
    }

    /// Assembles the output from the current Ritz pairs.
    fn finish(&self, ritz: &Ritz, converged: usize) -> EigenPairs {
        #[cfg(test)]
        tests::record_basis_orthogonality(self.v.as_ref().subcols(0, self.m + self.p));
        let nev = self.params.nev;
        let mut x = Mat::<f64>::zeros(self.n, nev);
        matmul(
            x.as_mut(),
            Accum::Replace,
            self.v.as_ref().subcols(0, self.m),
            ritz.y.as_ref().subcols(0, nev),
            1.0,
            Par::Seq,
        );
        normalize_signs(x.as_mut());
        EigenPairs {
            values: ritz.theta[..nev].to_vec(),
            vectors: x,
            info: BlockLanczosInfo {
                restarts: self.restarts,
                applications: self.applications,
                converged,
                residuals: ritz.res[..nev].to_vec(),
            },
        }
    }
}

/// Orthonormalises the columns of `w` against `v[:, 0..start]` and each other, writing
/// the new orthonormal columns into `v[:, start..start + q]` with `q ≤ q_target`.
///
/// `w` must already be orthogonal to `v[:, 0..start]` to working precision; `a0[j]` is the
/// norm of column `j` before any orthogonalisation and `a1[j]` its norm after the last
/// pass against `v[:, 0..start]`.
/// Columns left with norm `≤ drop_tol·a0[j]` count as dependent. Missing columns (rank
/// deficiency, or fewer columns than `q_target`) are filled with random vectors
/// orthogonal to everything before them. Returns `R` (`q × w.ncols()`) with
/// `w_in = V·h_extra + Q·R` — coefficients of the extra passes against
/// `v[:, 0..start]` are added into `h`.
#[allow(clippy::too_many_arguments)]
fn orthonormalize_block(
    v: &mut Mat<f64>,
    start: usize,
    mut w: MatMut<'_, f64>,
    a0: &[f64],
    a1: &[f64],
    mut h: Option<MatMut<'_, f64>>,
    q_target: usize,
    rng: &mut SplitMix64,
    drop_tol: f64,
) -> Mat<f64> {
    let n = v.nrows();
    let p = w.ncols();
    if v.ncols() < start + q_target {
        // Within the reserved capacity: no reallocation.
        v.resize_with(n, start + q_target, |_, _| 0.0);
    }
    let mut r = Mat::<f64>::zeros(q_target, p);
    let mut coef = Mat::<f64>::zeros(start + q_target, 1);
    let mut q = 0;
    for j in 0..p {
        let mut wj = w.rb_mut().subcols_mut(j, 1);
        // Two passes against the new columns of this block.
        for _ in 0..2 {
            if q == 0 {
                break;
            }
            let mut c = coef.as_mut().subrows_mut(0, q);
            project_out(v.as_ref().subcols(start, q), wj.rb_mut(), c.rb_mut());
            for i in 0..q {
                r[(i, j)] += c[(i, 0)];
            }
        }
        let mut prev = a1[j];
        let mut cur = norm2(wj.rb().col(0));
        // Heavy cancellation: further full passes until the norm stabilises.
        let mut extra = 0;
        while cur < BLOCK_CANCEL_RATIO * prev && cur > 0.0 && extra < 3 {
            let mut c = coef.as_mut().subrows_mut(0, start + q);
            project_out(v.as_ref().subcols(0, start + q), wj.rb_mut(), c.rb_mut());
            if let Some(h) = h.as_mut() {
                for i in 0..start {
                    h[(i, j)] += c[(i, 0)];
                }
            }
            for i in 0..q {
                r[(i, j)] += c[(start + i, 0)];
            }
            prev = cur;
            cur = norm2(wj.rb().col(0));
            extra += 1;
        }
        if q < q_target && cur.is_normal() && cur > drop_tol * a0[j] {
            let mut dst = v.as_mut().col_mut(start + q);
            let src = wj.rb().col(0);
            for i in 0..n {
                dst[i] = src[i] / cur;
            }
            r[(q, j)] = cur;
            q += 1;
        }
    }
    // Fill up with random vectors orthogonal to the basis (breakdown / start block).
    'fill: while q < q_target {
        for _attempt in 0..10 {
            let (left, right) = v.as_mut().split_at_col_mut(start + q);
            let basis = left.rb();
            let mut x = right.subcols_mut(0, 1);
            for i in 0..n {
                x[(i, 0)] = rng.uniform();
            }
            let a = norm2(x.rb().col(0));
            let mut prev = a;
            let mut cur = a;
            for pass in 0..4 {
                let c = coef.as_mut().subrows_mut(0, start + q);
                project_out(basis, x.rb_mut(), c);
                cur = norm2(x.rb().col(0));
                if pass >= 1 && cur >= REORTH_RATIO * prev {
                    break;
                }
                prev = cur;
            }
            if cur.is_normal() && cur > 1e-8 * a {
                for i in 0..n {
                    x[(i, 0)] /= cur;
                }
                q += 1;
                continue 'fill;
            }
        }
        // Could not find a new direction (only possible when the space is exhausted).
        break;
    }
    if q < q_target {
        r.subrows(0, q).to_owned()
    } else {
        r
    }
}
