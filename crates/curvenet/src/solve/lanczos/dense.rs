//! Dense symmetric eigenproblems: the projected matrix of the Lanczos iteration, and (in
//! tests) the oracle for small matrices.

use super::LanczosError;
use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::{ComputeEigenvectors, self_adjoint_evd, self_adjoint_evd_scratch};
use faer::prelude::*;
use faer::{Mat, MatMut, MatRef, Par};

/// The `k` smallest eigenpairs of the dense symmetric matrix `a` (only its lower triangle
/// is read), eigenvalues ascending, vectors `n × k` with the sign convention of
/// [`super::EigenPairs::vectors`]. `k` is clamped to `n`. The tests' reference solution.
///
/// # Errors
///
/// [`LanczosError::InvalidParams`] if `a` is not square, [`LanczosError::NonFinite`] if
/// its lower triangle holds NaN or infinity, [`LanczosError::DenseEigen`] if faer's
/// eigensolver fails.
#[cfg(test)]
pub(super) fn smallest_eigenpairs_dense(
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
pub(super) fn sym_eig_ascending(a: MatRef<'_, f64>) -> Result<(Vec<f64>, Mat<f64>), LanczosError> {
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
pub(super) fn normalize_signs(mut x: MatMut<'_, f64>) {
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
