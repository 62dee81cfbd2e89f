//! Tests of the block Lanczos eigensolver: its errors and edge cases (`errors`), its accuracy
//! and determinism (`accuracy`), on the helpers here.

#![allow(clippy::needless_range_loop)]

use super::dense::sym_eig_ascending;
use super::*;
use crate::rng::SplitMix64;
use faer::linalg::matmul::matmul;
use faer::prelude::*;
use faer::{Accum, Mat, Par};

mod accuracy;
mod errors;
use faer::Side;
use faer::sparse::{SparseColMat, Triplet};

// ---------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------

thread_local! {
    /// `max |VᵀV − I|` of the full final basis (incl. the pending block) of the last run
    /// on this thread.
    static BASIS_ORTH: std::cell::Cell<f64> = const { std::cell::Cell::new(f64::NAN) };
}

/// Called by the solver (test builds only) when it finishes.
pub(super) fn record_basis_orthogonality(v: MatRef<'_, f64>) {
    BASIS_ORTH.with(|c| c.set(orthonormality_error(v)));
}

/// Orthogonality of the last run's final basis on this thread.
fn last_basis_orthogonality() -> f64 {
    BASIS_ORTH.with(|c| c.get())
}

/// `y = A·x` for a dense matrix.
fn dense_op(a: &Mat<f64>) -> impl FnMut(MatRef<'_, f64>, MatMut<'_, f64>) + '_ {
    move |x, y| matmul(y, Accum::Replace, a.as_ref(), x, 1.0, Par::Seq)
}

/// Random matrix with entries uniform in [-1, 1).
fn random_mat(nrows: usize, ncols: usize, seed: u64) -> Mat<f64> {
    let mut rng = SplitMix64::new(seed);
    Mat::from_fn(nrows, ncols, |_, _| rng.uniform(-1.0, 1.0))
}

/// Random orthogonal `n × n` matrix (eigenvectors of a random symmetric matrix).
fn random_orthogonal(n: usize, seed: u64) -> Mat<f64> {
    let b = random_mat(n, n, seed);
    let s = Mat::from_fn(n, n, |i, j| b[(i, j)] + b[(j, i)]);
    sym_eig_ascending(s.as_ref()).unwrap().1
}

/// `Q·diag(d)·Qᵀ`.
fn with_spectrum(q: &Mat<f64>, d: &[f64]) -> Mat<f64> {
    let n = d.len();
    let qd = Mat::from_fn(n, n, |i, j| q[(i, j)] * d[j]);
    let mut a = Mat::<f64>::zeros(n, n);
    matmul(
        a.as_mut(),
        Accum::Replace,
        qd.as_ref(),
        q.transpose(),
        1.0,
        Par::Seq,
    );
    // Exact symmetry.
    Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}

/// `max |XᵀX − I|`.
fn orthonormality_error(x: MatRef<'_, f64>) -> f64 {
    let k = x.ncols();
    let mut g = Mat::<f64>::zeros(k, k);
    matmul(g.as_mut(), Accum::Replace, x.transpose(), x, 1.0, Par::Seq);
    let mut err = 0.0_f64;
    for i in 0..k {
        for j in 0..k {
            let target = if i == j { 1.0 } else { 0.0 };
            err = err.max((g[(i, j)] - target).abs());
        }
    }
    err
}

/// True residual norms `‖A·x_i − μ_i·x_i‖` for a dense `A`.
fn dense_residuals(a: &Mat<f64>, res: &EigenPairs) -> Vec<f64> {
    let x = res.vectors.as_ref();
    let mut ax = Mat::<f64>::zeros(x.nrows(), x.ncols());
    matmul(ax.as_mut(), Accum::Replace, a.as_ref(), x, 1.0, Par::Seq);
    (0..x.ncols())
        .map(|j| {
            let mut s = 0.0_f64;
            for i in 0..x.nrows() {
                let d = ax[(i, j)] - res.values[j] * x[(i, j)];
                s += d * d;
            }
            s.sqrt()
        })
        .collect()
}

/// Norm of the part of the columns of `x` outside span(`basis`) (orthonormal basis).
fn outside_span(basis: MatRef<'_, f64>, x: MatRef<'_, f64>) -> f64 {
    let mut c = Mat::<f64>::zeros(basis.ncols(), x.ncols());
    matmul(
        c.as_mut(),
        Accum::Replace,
        basis.transpose(),
        x,
        1.0,
        Par::Seq,
    );
    let mut r = x.to_owned();
    matmul(r.as_mut(), Accum::Add, basis, c.as_ref(), -1.0, Par::Seq);
    r.norm_l2()
}

/// Spring chain as a sparse symmetric matrix (full pattern): `diag[i]` on the diagonal,
/// `-off[i]` coupling `i` and `i + 1`.
fn tridiagonal(diag: &[f64], off: &[f64]) -> SparseColMat<usize, f64> {
    let n = diag.len();
    let mut trip = Vec::with_capacity(3 * n);
    for i in 0..n {
        trip.push(Triplet::new(i, i, diag[i]));
    }
    for (i, &o) in off.iter().enumerate() {
        if o != 0.0 {
            trip.push(Triplet::new(i + 1, i, -o));
            trip.push(Triplet::new(i, i + 1, -o));
        }
    }
    SparseColMat::try_new_from_triplets(n, n, &trip).unwrap()
}

/// Dirichlet 1D Laplacian `s·tridiag(-1, 2, -1)` of size `n` appended to `diag`/`off`
/// (decoupled from what is already there).
fn push_laplacian(diag: &mut Vec<f64>, off: &mut Vec<f64>, n: usize, s: f64) {
    if !diag.is_empty() {
        off.push(0.0);
    }
    for i in 0..n {
        diag.push(2.0 * s);
        if i + 1 < n {
            off.push(s);
        }
    }
}

/// Eigenvalue `k` (1-based) of `s·tridiag(-1, 2, -1)` of size `n`, computed without
/// cancellation: `2 − 2cos(kπ/(n+1)) = 4 sin²(kπ/(2(n+1)))`.
fn laplacian_eigenvalue(n: usize, k: usize, s: f64) -> f64 {
    let x = (k as f64) * std::f64::consts::PI / (2.0 * (n as f64 + 1.0));
    4.0 * s * x.sin() * x.sin()
}

/// Shift-and-invert operator `A⁻¹` from faer's sparse Cholesky factor.
fn inverse_op(
    a: &SparseColMat<usize, f64>,
) -> impl FnMut(MatRef<'_, f64>, MatMut<'_, f64>) + use<> {
    let llt = a.sp_cholesky(Side::Lower).unwrap();
    move |x, mut y| {
        y.copy_from(x);
        llt.solve_in_place(y.rb_mut());
    }
}

fn params(nev: usize, block_size: usize) -> BlockLanczosParams {
    BlockLanczosParams {
        nev,
        block_size,
        ..Default::default()
    }
}

// ---------------------------------------------------------------------------------------
// Parameters and errors
// ---------------------------------------------------------------------------------------
