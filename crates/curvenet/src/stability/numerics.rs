//! The facade's calls into the eigen solver, in one place: each way the stability
//! computations ask for a spectrum (about zero, above a shift, restricted to some
//! coordinates), over [`crate::solve::smallest_eigenpairs`].

use crate::solve::eigen::{EigenError, EigenOptions, EigenParams, Shift, Spectrum, Start};
use crate::solve::{Cholesky, Reuse, SymbolicFactor, smallest_eigenpairs};
use crate::sparse::Pattern;
use faer::{Mat, MatRef};
use std::sync::Arc;

/// The smallest eigenpairs of `values` (about a shift below zero), started from `start`.
pub(super) fn spectrum(
    pattern: &Pattern,
    values: &[f64],
    symbolic: &Arc<SymbolicFactor>,
    start: Option<MatRef<'_, f64>>,
    params: &EigenParams,
) -> Result<Spectrum, EigenError> {
    factored(pattern, values, symbolic, start, params).map(|(s, _)| s)
}

/// [`spectrum`] with the factorization of `H − σI` it used.
pub(super) fn factored(
    pattern: &Pattern,
    values: &[f64],
    symbolic: &Arc<SymbolicFactor>,
    start: Option<MatRef<'_, f64>>,
    params: &EigenParams,
) -> Result<(Spectrum, Cholesky), EigenError> {
    let options = EigenOptions {
        start: start.map_or(Start::Random, Start::Vectors),
        ..Default::default()
    };
    let found = smallest_eigenpairs(symbolic, pattern, values, params, options)?
        .expect("a shift below zero always factors");
    let factor = found.factor.expect("the whole matrix was factored");
    Ok((found.spectrum, factor))
}

/// The smallest eigenpairs about `sigma > 0`, with the factorization of `H − σI`, or `None`
/// when that factorization fails, which proves an eigenvalue lies below `sigma`.
pub(super) fn above(
    pattern: &Pattern,
    values: &[f64],
    symbolic: &Arc<SymbolicFactor>,
    start: Option<MatRef<'_, f64>>,
    params: &EigenParams,
    sigma: f64,
    reuse: Option<Reuse<'_>>,
) -> Result<Option<(Spectrum, Cholesky)>, EigenError> {
    let start = start.map_or(Start::Random, Start::Vectors);
    above_from(pattern, values, symbolic, start, params, sigma, reuse)
}

/// [`above`] with the start vectors made only once the factorization succeeded.
pub(super) fn above_with<'a>(
    pattern: &Pattern,
    values: &[f64],
    symbolic: &Arc<SymbolicFactor>,
    start: impl FnOnce() -> Option<Mat<f64>> + 'a,
    params: &EigenParams,
    sigma: f64,
    reuse: Option<Reuse<'a>>,
) -> Result<Option<(Spectrum, Cholesky)>, EigenError> {
    let start = Start::Lazy(Box::new(start));
    above_from(pattern, values, symbolic, start, params, sigma, reuse)
}

fn above_from<'a>(
    pattern: &Pattern,
    values: &[f64],
    symbolic: &Arc<SymbolicFactor>,
    start: Start<'a>,
    params: &EigenParams,
    sigma: f64,
    reuse: Option<Reuse<'a>>,
) -> Result<Option<(Spectrum, Cholesky)>, EigenError> {
    let options = EigenOptions {
        shift: Shift::Above(sigma),
        start,
        reuse,
        keep: None,
    };
    let found = smallest_eigenpairs(symbolic, pattern, values, params, options)?;
    Ok(found.map(|f| (f.spectrum, f.factor.expect("the whole matrix was factored"))))
}

/// The smallest eigenpairs of the principal submatrix on `keep` (the other coordinates
/// decoupled: [`EigenOptions::keep`]).
pub(super) fn restricted(
    pattern: &Pattern,
    values: &[f64],
    symbolic: &Arc<SymbolicFactor>,
    keep: &[bool],
    start: Option<MatRef<'_, f64>>,
    params: &EigenParams,
) -> Result<Spectrum, EigenError> {
    let options = EigenOptions {
        start: start.map_or(Start::Random, Start::Vectors),
        keep: Some(keep),
        ..Default::default()
    };
    let found = smallest_eigenpairs(symbolic, pattern, values, params, options)?;
    Ok(found.expect("a shift below zero always factors").spectrum)
}
