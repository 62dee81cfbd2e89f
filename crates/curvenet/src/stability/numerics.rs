//! The facade's calls into the eigen solver, in one place: each way the stability
//! computations ask for a spectrum (about zero, above a shift, restricted to some
//! coordinates), over [`crate::solve::smallest_eigenpairs`].

use crate::solve::eigen::{EigenError, EigenOptions, EigenParams, Shift, Spectrum, Start};
use crate::solve::{Cholesky, Reuse, SymbolicFactor, smallest_eigenpairs};
use crate::sparse::Pattern;
use faer::MatRef;
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
        start: start.into(),
        ..Default::default()
    };
    let found = smallest_eigenpairs(symbolic, pattern, values, params, options)?
        .expect("a shift below zero always factors");
    let factor = found.factor.expect("the whole matrix was factored");
    Ok((found.spectrum, factor))
}

/// The smallest eigenpairs about `sigma > 0`, with the factorization of `H − σI`, or `None`
/// when that factorization fails, which proves an eigenvalue lies below `sigma`. A
/// [`Start::Lazy`] start is made only once the factorization succeeded.
pub(super) fn above<'a>(
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
        start: start.into(),
        keep: Some(keep),
        ..Default::default()
    };
    let found = smallest_eigenpairs(symbolic, pattern, values, params, options)?;
    Ok(found.expect("a shift below zero always factors").spectrum)
}
