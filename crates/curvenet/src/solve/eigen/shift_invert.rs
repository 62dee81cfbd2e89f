//! Shift-and-invert: the factorization of `H − σI` (about zero, moving the shift down until
//! it factors, or about a given `σ`), block Lanczos on its inverse, and the pairs of `H` it
//! gives.

use super::{EigenError, EigenParams, Spectrum};
use crate::solve::factor::{Cholesky, Reuse, Schedule, SymbolicFactor};
use crate::solve::lanczos::{BlockLanczosParams, EigenPairs, LanczosError, largest_eigenpairs};
use crate::sparse::Pattern;
use faer::{Mat, MatRef};
use std::sync::Arc;

/// The factorization of `H − σI` for [`Shift::BelowZero`].
pub(super) fn factor_below_zero(
    symbolic: &Arc<SymbolicFactor>,
    pattern: &Pattern,
    values: &[f64],
    params: &EigenParams,
) -> Result<(Cholesky, Shifted), EigenError> {
    let norm1 = pattern.sym_norm1(values);
    if !norm1.is_finite() {
        return Err(EigenError::NoShift(f64::NAN));
    }
    let eps = f64::EPSILON;
    let zero_threshold = params.zero_factor * eps * norm1;
    let mut shift = -(params.shift_factor * eps * norm1).max(f64::MIN_POSITIVE);
    let mut factorizations = 0;
    loop {
        factorizations += 1;
        match Cholesky::factorize(symbolic, pattern, values, -shift, None) {
            Ok(f) => {
                let shifted = Shifted {
                    shift,
                    factorizations,
                    norm1,
                    zero_threshold,
                };
                return Ok((f, shifted));
            }
            Err(_) => {
                if -shift > 2.0 * norm1 + 1.0 {
                    return Err(EigenError::NoShift(shift));
                }
                shift *= 10.0;
            }
        }
    }
}

/// The factorization of `H − σI` for [`Shift::Above`]; `None` when it fails (`λ < σ`).
pub(super) fn factor_at(
    symbolic: &Arc<SymbolicFactor>,
    pattern: &Pattern,
    values: &[f64],
    params: &EigenParams,
    sigma: f64,
    reuse: Option<Reuse<'_>>,
) -> Result<Option<(Cholesky, Shifted)>, EigenError> {
    let Ok(factor) = Cholesky::factorize(symbolic, pattern, values, -sigma, reuse) else {
        // A matrix with NaN or infinity fails too: that is an error, not an answer.
        if values.iter().any(|v| !v.is_finite()) {
            return Err(EigenError::NoShift(f64::NAN));
        }
        return Ok(None);
    };
    let norm1 = pattern.sym_norm1(values);
    if !norm1.is_finite() {
        return Err(EigenError::NoShift(f64::NAN));
    }
    let shifted = Shifted {
        shift: sigma,
        factorizations: 1,
        norm1,
        zero_threshold: params.zero_factor * f64::EPSILON * norm1,
    };
    Ok(Some((factor, shifted)))
}

/// What the factorization step of a shift-and-invert solve found.
pub(super) struct Shifted {
    shift: f64,
    factorizations: usize,
    norm1: f64,
    zero_threshold: f64,
}

/// Block Lanczos on `(H − σI)⁻¹` given its factorization, and the pairs of `H` it gives.
pub(super) fn finish(
    pattern: &Pattern,
    values: &[f64],
    factor: Cholesky,
    shifted: Shifted,
    warm_start: Option<MatRef<'_, f64>>,
    params: &EigenParams,
) -> Result<(Spectrum, Cholesky), EigenError> {
    let Shifted {
        shift,
        factorizations,
        norm1,
        zero_threshold,
    } = shifted;
    let n = pattern.n;
    let lanczos = BlockLanczosParams {
        nev: params.count.min(n),
        block_size: params.block_size.min(n),
        max_basis: params.max_basis.min(n.max(1)),
        tol: params.tol,
        trailing_tol: params.trailing_tol,
        max_restarts: params.max_restarts,
        seed: params.seed,
    };
    let pairs = largest_eigenpairs(
        n,
        |x, mut y| {
            y.copy_from(x);
            factor.solve_in_place(y, Schedule::Groups(params.solve_group));
        },
        warm_start,
        &lanczos,
    );
    let (pairs, unconverged) = match pairs {
        Ok(p) => (p, 0),
        Err(LanczosError::NotConverged(partial)) => {
            let requested = partial.values.len();
            let message = LanczosError::NotConverged(partial.clone()).to_string();
            let p = converged_prefix(*partial, |j| lanczos.tolerance(j));
            if p.values.is_empty() {
                return Err(EigenError::NotConverged(message));
            }
            let kept = p.values.len();
            (p, requested - kept)
        }
        Err(e) => return Err(EigenError::NotConverged(e.to_string())),
    };

    // μ descending → λ = σ + 1/μ ascending.
    let k = pairs.values.len();
    let mut vals = Vec::with_capacity(k);
    let mut vectors = Mat::<f64>::zeros(n, k);
    let mut residuals = Vec::with_capacity(k);
    let mut hv = vec![0.0; n];
    for j in 0..k {
        let lambda = shift + 1.0 / pairs.values[j];
        let v: Vec<f64> = (0..n).map(|i| pairs.vectors[(i, j)]).collect();
        pattern.sym_matvec(values, &v, &mut hv);
        let r = hv
            .iter()
            .zip(&v)
            .map(|(a, b)| (a - lambda * b).powi(2))
            .sum::<f64>()
            .sqrt();
        vals.push(lambda);
        residuals.push(r / norm1.max(f64::MIN_POSITIVE));
        for i in 0..n {
            vectors[(i, j)] = v[i];
        }
    }
    let zero_modes = vals.iter().filter(|l| l.abs() <= zero_threshold).count();
    let negative_modes = vals.iter().filter(|&&l| l < -zero_threshold).count();
    Ok((
        Spectrum {
            values: vals,
            vectors,
            residuals,
            norm1,
            zero_threshold,
            zero_modes,
            negative_modes,
            shift,
            factorizations,
            solves: pairs.info.applications,
            restarts: pairs.info.restarts,
            unconverged,
        },
        factor,
    ))
}

/// The leading pairs of a run that did not converge whose residuals meet their tolerance
/// (`tol(j)` times the largest `|μ|` for pair `j`, the solver's own test); the rest are
/// dropped.
fn converged_prefix(mut pairs: EigenPairs, tol: impl Fn(usize) -> f64) -> EigenPairs {
    let scale = pairs
        .values
        .iter()
        .fold(f64::MIN_POSITIVE, |acc, v| acc.max(v.abs()));
    let k = pairs
        .info
        .residuals
        .iter()
        .enumerate()
        .take_while(|&(j, &r)| r <= tol(j) * scale)
        .count()
        .min(pairs.values.len());
    pairs.values.truncate(k);
    pairs.vectors = pairs.vectors.subcols(0, k).to_owned();
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve::lanczos::BlockLanczosInfo;

    #[test]
    fn unconverged_runs_keep_only_their_converged_leading_pairs() {
        let n = 5;
        let pairs = |residuals: Vec<f64>| EigenPairs {
            values: vec![4.0, 3.0, 2.0, 1.0],
            vectors: Mat::from_fn(n, 4, |i, j| if i == j { 1.0 } else { 0.0 }),
            info: BlockLanczosInfo {
                restarts: 50,
                applications: 400,
                converged: residuals.iter().filter(|&&r| r <= 4e-10).count(),
                residuals,
            },
        };
        // The third pair misses the tolerance (1e-10 × 4): the fourth, though converged,
        // is not kept, since a missing pair before it may hide a smaller λ.
        let p = converged_prefix(pairs(vec![1e-14, 3e-10, 1e-6, 1e-14]), |_| 1e-10);
        assert_eq!(p.values, vec![4.0, 3.0]);
        assert_eq!((p.vectors.nrows(), p.vectors.ncols()), (n, 2));
        assert_eq!(p.vectors[(1, 1)], 1.0);
        // A looser tolerance for the pairs after the first keeps the third too.
        let p = converged_prefix(pairs(vec![1e-14, 3e-10, 1e-6, 1e-3]), |j| {
            if j == 0 { 1e-10 } else { 1e-6 }
        });
        assert_eq!(p.values, vec![4.0, 3.0, 2.0]);
        let p = converged_prefix(pairs(vec![1e-9, 1e-14, 1e-14, 1e-14]), |j| {
            if j == 0 { 1e-10 } else { 1e-6 }
        });
        assert!(
            p.values.is_empty(),
            "the first pair keeps its own tolerance"
        );
        // Nothing converged: nothing kept (the caller reports an error).
        let p = converged_prefix(pairs(vec![1e-6, 1e-14, 1e-14, 1e-14]), |_| 1e-10);
        assert!(p.values.is_empty() && p.vectors.ncols() == 0);
    }
}
