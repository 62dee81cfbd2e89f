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
//! from [`crate::rng::SplitMix64`] seeded by [`BlockLanczosParams::seed`], so
//! the result is bit-identical for identical inputs, whatever the thread count (provided
//! the operator itself is deterministic).

mod dense;
mod orthogonal;
mod params;
mod solver;
#[cfg(test)]
mod tests;

#[cfg(test)]
use dense::smallest_eigenpairs_dense;
pub use params::{BlockLanczosInfo, BlockLanczosParams, EigenPairs, LanczosError};

use faer::{MatMut, MatRef};
use solver::Solver;

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
