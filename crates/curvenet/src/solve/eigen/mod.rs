//! The smallest eigenpairs of a Hessian by shift-and-invert block Lanczos (`docs/model.md`,
//! *Stability*).
//!
//! `H − σI` is factored with the shared symbolic analysis at a shift `σ` just below zero
//! (`σ = −c·ε·‖H‖₁`); block Lanczos ([`super::lanczos`]) finds the largest eigenvalues `μ` of
//! `(H − σI)⁻¹` and `λ = σ + 1/μ`. The block finds repeated eigenvalues (symmetric scenes have
//! exact pairs). If `H − σI` is not positive definite, `H` has eigenvalues below `σ` (negative
//! modes): `σ` moves down geometrically until the factorization succeeds, and the eigenpairs
//! nearest above it are the most negative ones.
//!
//! Eigenvalues within `±C·ε·‖H‖₁` count as zero modes (mechanisms), below as negative modes
//! (an unstable equilibrium). Every returned pair comes with its residual `‖Hv − λv‖`.
//!
//! [`smallest_eigenpairs`] is the one entry: the matrix, the accuracy ([`EigenParams`]; the
//! searches' named presets are `stability::Preset`) and how to run ([`EigenOptions`]: the shift,
//! the start, a factor to reuse, the coordinates to keep). A generalized problem `H v = μ M v` with
//! a diagonal (lumped) mass `M` would enter there as one more option, solved as the standard
//! problem of `M^{-1/2} H M^{-1/2}` (shift-and-invert on `H − σM`).

mod shift_invert;

use super::factor::{Cholesky, Reuse, SymbolicFactor};
use crate::sparse::Pattern;
use crate::words::Message;
use faer::{Mat, MatRef};
use serde::{Deserialize, Serialize};
use shift_invert::{factor_at, factor_below_zero, finish};
use std::sync::Arc;

/// The most eigenpairs an analysis reports: the smallest eigenvalues of a structure and, in the
/// physical mode, its natural frequencies. One limit for every front end (the application
/// layer's `MAX_EIGEN_COUNT`) and for the physical analysis.
pub const MAX_EIGEN_COUNT: usize = 100;

/// Eigen-solver parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct EigenParams {
    /// Number of smallest eigenpairs to compute.
    pub count: usize,
    /// Lanczos block size: the largest multiplicity found for sure.
    pub block_size: usize,
    /// Largest Krylov basis before a restart.
    pub max_basis: usize,
    /// Relative residual tolerance of the inverted operator.
    pub tol: f64,
    /// The residual tolerance of the pairs after the first, when only the first needs `tol`
    /// (never below it); `None`: `tol` for every pair. A Ritz value's error is about the
    /// square of its residual over the gap to the next eigenvalue, so the later pairs'
    /// values stay accurate to about `trailing_tol²` while their vectors, which serve as a
    /// subspace (the candidates' bounds, the next solve's start), cost fewer solves.
    pub trailing_tol: Option<f64>,
    /// Restart cap.
    pub max_restarts: usize,
    /// `C` in the zero-mode threshold `C·ε·‖H‖₁`: below every real soft mode of the paper's
    /// examples (`docs/model.md`, *Stability*) and above exact mechanisms, which come out far
    /// below `ε‖H‖₁` (tested).
    pub zero_factor: f64,
    /// The first shift is `−shift_factor·ε·‖H‖₁`.
    pub shift_factor: f64,
    /// Seed of the random start block.
    pub seed: u64,
    /// Columns of a block solved per pass over the factor ([`crate::solve::Schedule::Groups`]); the
    /// groups run in parallel.
    pub solve_group: usize,
}

impl Default for EigenParams {
    fn default() -> Self {
        EigenParams {
            count: 4,
            block_size: 3,
            max_basis: 60,
            tol: 1e-10,
            trailing_tol: None,
            max_restarts: 60,
            zero_factor: 5.0,
            shift_factor: 10.0,
            seed: 0x5eed,
            solve_group: super::factor::SOLVE_GROUP,
        }
    }
}

impl EigenParams {
    /// These parameters asking for `count` pairs, the Krylov basis widened to hold them (at
    /// least `count + 4·block_size`).
    pub fn with_count(mut self, count: usize) -> Self {
        self.count = count;
        self.max_basis = self.max_basis.max(count + 4 * self.block_size);
        self
    }

    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), Message> {
        if self.count == 0 || self.block_size == 0 || self.solve_group == 0 {
            return Err("eigen count, block size and solve group must be at least 1".into());
        }
        if self.max_basis < self.count + 2 * self.block_size {
            return Err(format!(
                "eigen basis {} too small for {} pairs with block size {}",
                self.max_basis, self.count, self.block_size
            )
            .into());
        }
        if !(self.tol > 0.0 && self.tol < 1e-2) {
            return Err(format!("eigen tolerance must lie in (0, 1e-2), got {}", self.tol).into());
        }
        if let Some(t) = self.trailing_tol.filter(|t| !(*t > 0.0 && *t < 1e-2)) {
            return Err(format!("eigen trailing tolerance must lie in (0, 1e-2), got {t}").into());
        }
        if !(self.zero_factor > 0.0 && self.shift_factor > 0.0) {
            return Err("zero and shift factors must be positive".into());
        }
        Ok(())
    }
}

/// The smallest eigenpairs of a Hessian.
#[derive(Clone, Debug)]
pub struct Spectrum {
    /// Eigenvalues, ascending.
    pub values: Vec<f64>,
    /// Unit eigenvectors (columns), in the order of `values`.
    pub vectors: Mat<f64>,
    /// `‖Hv − λv‖ / ‖H‖₁` of each pair.
    pub residuals: Vec<f64>,
    /// `‖H‖₁`.
    pub norm1: f64,
    /// Zero-mode threshold `C·ε·‖H‖₁`.
    pub zero_threshold: f64,
    /// Computed eigenvalues with `|λ| ≤ threshold` (mechanisms).
    pub zero_modes: usize,
    /// Computed eigenvalues below `−threshold` (a lower bound when every computed value is
    /// negative).
    pub negative_modes: usize,
    /// The shift `σ` that was used.
    pub shift: f64,
    /// Numeric factorizations performed.
    pub factorizations: usize,
    /// Operator applications (one per column solve).
    pub solves: usize,
    /// Lanczos restarts.
    pub restarts: usize,
    /// Requested pairs the solver could not converge within its restarts (normally 0). When
    /// positive, `values` holds only the leading pairs that did converge (at least one:
    /// otherwise the solve is an error), and callers report it.
    pub unconverged: usize,
}

impl Spectrum {
    /// The smallest eigenvalue `λ`.
    pub fn lambda(&self) -> f64 {
        self.values[0]
    }
}

/// Why no eigenpairs could be computed.
#[derive(Debug, thiserror::Error)]
pub enum EigenError {
    /// Bad parameters.
    #[error("invalid eigen parameters: {0}")]
    InvalidParams(Message),
    /// No shift made `H − σI` positive definite (non-finite matrix entries?).
    #[error("could not factor H − σI for any shift down to {0:e}")]
    NoShift(f64),
    /// Lanczos did not converge.
    #[error("eigen solver did not converge: {0}")]
    NotConverged(String),
}

/// Where the shift `σ` of a shift-and-invert solve lies.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Shift {
    /// Just below zero (`σ = −shift_factor·ε·‖H‖₁`), moved down tenfold until `H − σI` is
    /// positive definite: the pairs nearest above it are the smallest eigenvalues, the most
    /// negative ones first.
    #[default]
    BelowZero,
    /// At `σ`: when `H − σI` is not positive definite its Cholesky factorization fails, which
    /// proves `λ < σ` (Sylvester's law of inertia) for one factorization and no solve (the
    /// answer is `None`). Otherwise shift-and-invert about `σ`, which converges faster than
    /// about zero when `σ` lies just below `λ`.
    Above(f64),
}

/// The start block of the Lanczos iteration.
#[derive(Default)]
pub enum Start<'a> {
    /// Seeded random vectors.
    #[default]
    Random,
    /// Columns of approximate eigenvectors (e.g. of a nearby matrix), at the matrix's full
    /// size; the result does not depend on them beyond the solver's tolerance.
    Vectors(MatRef<'a, f64>),
    /// Vectors made only once the factorization succeeded (a failed one, with
    /// [`Shift::Above`], then costs nothing else).
    Lazy(Box<dyn FnOnce() -> Option<Mat<f64>> + 'a>),
}

impl<'a> From<Option<MatRef<'a, f64>>> for Start<'a> {
    /// The vectors given, else random ones.
    fn from(start: Option<MatRef<'a, f64>>) -> Self {
        start.map_or(Start::Random, Start::Vectors)
    }
}

impl Start<'_> {
    fn vectors(self) -> Option<Mat<f64>> {
        match self {
            Start::Random => None,
            Start::Vectors(v) => Some(v.to_owned()),
            Start::Lazy(make) => make(),
        }
    }
}

/// How [`smallest_eigenpairs`] runs: everything but the matrix and the accuracy.
#[derive(Default)]
pub struct EigenOptions<'a> {
    /// Where the shift lies.
    pub shift: Shift,
    /// The start block.
    pub start: Start<'a>,
    /// A factorization the one of `H − σI` copies what it can from ([`Cholesky::factorize`];
    /// the factor, hence the result, is the same either way).
    pub reuse: Option<Reuse<'a>>,
    /// The coordinates to solve on, when the others are decoupled from them (no stored
    /// off-diagonal entry links them: loose vertices, which carry only a diagonal): the
    /// smallest eigenpairs of the principal submatrix on them, the decoupled coordinates'
    /// eigenvalues left out. When it selects at most [`RESTRICT_MAX_SHARE`] of them, the
    /// factorizations see only those (an analysis of their own, without `reuse`, and no
    /// factor handed out); otherwise the whole matrix is solved, whose decoupled diagonals
    /// must then lie above the pairs sought. Vectors come back at full size, zero outside.
    pub keep: Option<&'a [bool]>,
}

/// The eigenpairs found, and the factorization of `H − σI` they used (a good Newton matrix
/// for the same structure near this state; `None` when a submatrix of its own was solved).
#[derive(Debug)]
pub struct Eigen {
    /// The pairs.
    pub spectrum: Spectrum,
    /// The factorization of `H − σI`.
    pub factor: Option<Cholesky>,
}

/// Above this share of kept coordinates, [`EigenOptions::keep`] solves the whole matrix (a
/// symbolic analysis of the submatrix would cost more than it saves).
pub const RESTRICT_MAX_SHARE: f64 = 0.75;

/// The `params.count` smallest eigenpairs of the symmetric matrix whose upper triangle is
/// `values` in `pattern`, by shift-and-invert block Lanczos with `symbolic`'s factorizations.
///
/// `Ok(None)` only with [`Shift::Above`]: the proof that `λ < σ`. A matrix with NaN or
/// infinite entries is an error, not such a proof.
pub fn smallest_eigenpairs(
    symbolic: &Arc<SymbolicFactor>,
    pattern: &Pattern,
    values: &[f64],
    params: &EigenParams,
    options: EigenOptions<'_>,
) -> Result<Option<Eigen>, EigenError> {
    let _timer = crate::profile::Timer::new(crate::profile::Phase::Eigen);
    params.validate().map_err(EigenError::InvalidParams)?;
    if let Shift::Above(sigma) = options.shift
        && !sigma.is_finite()
    {
        return Err(EigenError::InvalidParams(
            format!("the shift must be finite, got {sigma:e}").into(),
        ));
    }
    let Some(keep) = options.keep.filter(|keep| {
        let kept = keep.iter().filter(|&&k| k).count();
        kept > 0 && kept as f64 <= RESTRICT_MAX_SHARE * pattern.n as f64
    }) else {
        return solve_whole(symbolic, pattern, values, params, options);
    };
    let (sub, slots, dofs) = pattern.principal(keep);
    let sub_values: Vec<f64> = slots.iter().map(|&k| values[k]).collect();
    let sub_symbolic = SymbolicFactor::new(&sub, symbolic.backend());
    let (start, map) = (options.start, dofs.clone());
    let sub_start = Start::Lazy(Box::new(move || {
        let w = start.vectors()?;
        Some(Mat::from_fn(map.len(), w.ncols(), |i, j| w[(map[i], j)]))
    }));
    let sub_options = EigenOptions {
        shift: options.shift,
        start: sub_start,
        reuse: None,
        keep: None,
    };
    let Some(found) = solve_whole(&sub_symbolic, &sub, &sub_values, params, sub_options)? else {
        return Ok(None);
    };
    let mut spectrum = found.spectrum;
    let mut full = Mat::<f64>::zeros(pattern.n, spectrum.vectors.ncols());
    for (i, &d) in dofs.iter().enumerate() {
        for j in 0..full.ncols() {
            full[(d, j)] = spectrum.vectors[(i, j)];
        }
    }
    spectrum.vectors = full;
    Ok(Some(Eigen {
        spectrum,
        factor: None,
    }))
}

/// [`smallest_eigenpairs`] on the whole matrix.
fn solve_whole(
    symbolic: &Arc<SymbolicFactor>,
    pattern: &Pattern,
    values: &[f64],
    params: &EigenParams,
    options: EigenOptions<'_>,
) -> Result<Option<Eigen>, EigenError> {
    let shifted = match options.shift {
        Shift::BelowZero => Some(factor_below_zero(symbolic, pattern, values, params)?),
        Shift::Above(sigma) => factor_at(symbolic, pattern, values, params, sigma, options.reuse)?,
    };
    let Some((factor, shifted)) = shifted else {
        return Ok(None);
    };
    let warm = options.start.vectors();
    let (spectrum, factor) = finish(
        pattern,
        values,
        factor,
        shifted,
        warm.as_ref().map(|w| w.as_ref()),
        params,
    )?;
    Ok(Some(Eigen {
        spectrum,
        factor: Some(factor),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tridiagonal matrix `tridiag(−1, 2, −1) − 2.5 I` of size `n` (upper triangle) and
    /// its eigenvalues `2 − 2 cos(kπ/(n+1)) − 2.5`, ascending.
    fn shifted_laplacian(n: usize) -> (Pattern, Vec<f64>, Vec<f64>) {
        let (pattern, values) = crate::sparse::tridiagonal(n, 2.0 - 2.5);
        let exact = (1..=n)
            .map(|k| 2.0 - 2.0 * (k as f64 * std::f64::consts::PI / (n as f64 + 1.0)).cos() - 2.5)
            .collect();
        (pattern, values, exact)
    }

    /// `smallest_eigenpairs` about `σ` on the shifted Laplacian.
    fn above(
        pattern: &Pattern,
        values: &[f64],
        symbolic: &Arc<SymbolicFactor>,
        params: &EigenParams,
        sigma: f64,
        start: Start<'_>,
    ) -> Result<Option<Eigen>, EigenError> {
        let options = EigenOptions {
            shift: Shift::Above(sigma),
            start,
            ..Default::default()
        };
        smallest_eigenpairs(symbolic, pattern, values, params, options)
    }

    #[test]
    fn a_negative_shift_proves_or_finds_negative_eigenvalues() {
        let (pattern, values, exact) = shifted_laplacian(40);
        let symbolic = SymbolicFactor::new(&pattern, Default::default());
        let params = EigenParams {
            count: 2,
            ..Default::default()
        };
        assert!(exact[0] < -0.4 && exact[1] < exact[0] + 0.1);
        // Below the shift: one failed factorization says so.
        let at = |sigma: f64| {
            above(&pattern, &values, &symbolic, &params, sigma, Start::Random).expect("valid")
        };
        assert!(at(exact[0] + 1e-3).is_none());
        // Just below λ₁ (negative): the pairs, to the solver's accuracy.
        let sp = at(exact[0] - 1e-3)
            .expect("H − σI is positive definite")
            .spectrum;
        assert!(
            (sp.lambda() - exact[0]).abs() < 1e-9,
            "{} {}",
            sp.lambda(),
            exact[0]
        );
        assert!((sp.values[1] - exact[1]).abs() < 1e-9);
        assert_eq!(sp.negative_modes, 2);
        assert!(
            above(
                &pattern,
                &values,
                &symbolic,
                &params,
                f64::NAN,
                Start::Random
            )
            .is_err()
        );
        // A matrix with NaN fails its factorization too: an error, not a proof.
        let mut bad = values.clone();
        bad[pattern.diag[7]] = f64::NAN;
        let r = above(&pattern, &bad, &symbolic, &params, -1.0, Start::Random);
        assert!(r.is_err(), "{r:?}");
    }

    /// A lazy start is made only when the factorization about `σ` succeeds.
    #[test]
    fn the_warm_start_is_made_only_for_a_successful_factorization() {
        let (pattern, values, exact) = shifted_laplacian(40);
        let symbolic = SymbolicFactor::new(&pattern, Default::default());
        let params = EigenParams {
            count: 2,
            ..Default::default()
        };
        let made = std::cell::Cell::new(0);
        let lazy = || {
            Start::Lazy(Box::new(|| {
                made.set(made.get() + 1);
                None
            }))
        };
        let below = above(
            &pattern,
            &values,
            &symbolic,
            &params,
            exact[0] + 1e-3,
            lazy(),
        );
        assert!(below.expect("valid").is_none());
        assert_eq!(made.get(), 0, "no warm start for a failed factorization");
        let found = above(
            &pattern,
            &values,
            &symbolic,
            &params,
            exact[0] - 1e-3,
            lazy(),
        );
        assert!(found.expect("valid").is_some());
        assert_eq!(made.get(), 1);
    }
}
