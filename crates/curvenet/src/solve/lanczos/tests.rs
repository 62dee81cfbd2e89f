//! Tests of the block Lanczos eigensolver.

#![allow(clippy::needless_range_loop)]

use super::*;
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
    let mut rng = SplitMix64(seed);
    Mat::from_fn(nrows, ncols, |_, _| rng.uniform())
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

#[test]
fn invalid_params_are_errors() {
    let ok = BlockLanczosParams::default();
    assert!(ok.validate(100).is_ok());
    let bad = [
        (
            BlockLanczosParams {
                nev: 0,
                ..ok.clone()
            },
            100,
        ),
        (
            BlockLanczosParams {
                nev: 101,
                ..ok.clone()
            },
            100,
        ),
        (
            BlockLanczosParams {
                block_size: 0,
                ..ok.clone()
            },
            100,
        ),
        (
            BlockLanczosParams {
                max_basis: 7,
                ..ok.clone()
            },
            100,
        ),
        (
            BlockLanczosParams {
                max_basis: 0,
                ..ok.clone()
            },
            100,
        ),
        (
            BlockLanczosParams {
                nev: usize::MAX,
                block_size: usize::MAX,
                ..ok.clone()
            },
            usize::MAX,
        ),
        (
            BlockLanczosParams {
                tol: 0.0,
                ..ok.clone()
            },
            100,
        ),
        (
            BlockLanczosParams {
                tol: -1e-3,
                ..ok.clone()
            },
            100,
        ),
        (
            BlockLanczosParams {
                tol: f64::NAN,
                ..ok.clone()
            },
            100,
        ),
        (
            BlockLanczosParams {
                tol: f64::INFINITY,
                ..ok.clone()
            },
            100,
        ),
        (
            BlockLanczosParams {
                trailing_tol: Some(f64::NAN),
                ..ok.clone()
            },
            100,
        ),
        (
            BlockLanczosParams {
                trailing_tol: Some(0.0),
                ..ok.clone()
            },
            100,
        ),
        (ok.clone(), 0),
    ];
    for (p, n) in bad {
        assert!(
            matches!(p.validate(n), Err(LanczosError::InvalidParams(_))),
            "{p:?}, n = {n}"
        );
        let r = largest_eigenpairs(n, |_, _| {}, None, &p);
        assert!(matches!(r, Err(LanczosError::InvalidParams(_))), "{p:?}");
    }
    // Valid parameters but an impossible allocation: an error, not an abort.
    for n in [usize::MAX / 2, 1 << 40] {
        let r = largest_eigenpairs(n, |_, _| {}, None, &ok);
        assert!(matches!(r, Err(LanczosError::InvalidParams(_))), "n = {n}");
    }
    // max_basis ≥ n relaxes the max_basis > nev + block_size rule (no restart needed).
    let small = BlockLanczosParams {
        nev: 4,
        block_size: 3,
        max_basis: 5,
        ..ok.clone()
    };
    assert!(small.validate(5).is_ok());
    assert!(small.validate(6).is_err());
    // Warm start with the wrong number of rows.
    let w = Mat::<f64>::zeros(9, 2);
    let r = largest_eigenpairs(10, |_, _| {}, Some(w.as_ref()), &params(1, 1));
    assert!(matches!(r, Err(LanczosError::InvalidParams(_))));
}

/// A looser tolerance for the pairs after the first: the first pair still meets `tol`, the
/// others their own, in fewer operator applications; the values stay accurate to about the
/// square of the residual.
#[test]
fn the_pairs_after_the_first_can_have_a_looser_tolerance() {
    let n = 300;
    let (mut diag, mut off) = (Vec::new(), Vec::new());
    push_laplacian(&mut diag, &mut off, n, 1.0);
    let a = tridiagonal(&diag, &off);
    let exact: Vec<f64> = (1..=3)
        .map(|k| 1.0 / laplacian_eigenvalue(n, k, 1.0))
        .collect();
    let all = BlockLanczosParams {
        nev: 3,
        block_size: 2,
        max_basis: 40,
        tol: 1e-10,
        ..Default::default()
    };
    let lead = BlockLanczosParams {
        trailing_tol: Some(1e-4),
        ..all.clone()
    };
    assert_eq!((lead.tolerance(0), lead.tolerance(2)), (1e-10, 1e-4));
    // Never tighter than `tol`.
    let odd = BlockLanczosParams {
        trailing_tol: Some(1e-12),
        ..all.clone()
    };
    assert_eq!(odd.tolerance(1), 1e-10);
    let full = largest_eigenpairs(n, inverse_op(&a), None, &all).unwrap();
    let part = largest_eigenpairs(n, inverse_op(&a), None, &lead).unwrap();
    assert!(
        part.info.applications < full.info.applications,
        "{} against {}",
        part.info.applications,
        full.info.applications
    );
    let scale = part.values[0].abs();
    assert!(part.info.residuals[0] <= 1e-10 * scale);
    for j in 1..3 {
        assert!(part.info.residuals[j] <= 1e-4 * scale);
    }
    assert!((part.values[0] - exact[0]).abs() <= 1e-12 * exact[0]);
    for j in 0..3 {
        assert!(
            (part.values[j] - exact[j]).abs() <= 1e-6 * exact[j],
            "pair {j}: {} against {}",
            part.values[j],
            exact[j]
        );
    }
}

#[test]
fn non_finite_operator_is_an_error() {
    let p = params(2, 2);
    let r = largest_eigenpairs(50, |_, mut y| y.fill(f64::NAN), None, &p);
    assert!(matches!(r, Err(LanczosError::NonFinite(_))), "{r:?}");
    // Infinity only later, in one entry.
    let mut calls = 0;
    let r = largest_eigenpairs(
        50,
        |x, mut y| {
            for j in 0..x.ncols() {
                for i in 0..50 {
                    y[(i, j)] = (i + 1) as f64 * x[(i, j)];
                }
            }
            calls += 1;
            if calls == 3 {
                y[(7, 0)] = f64::INFINITY;
            }
        },
        None,
        &p,
    );
    assert!(matches!(r, Err(LanczosError::NonFinite(_))), "{r:?}");
    assert_eq!(calls, 3);
    // NaN in the warm start.
    let mut w = Mat::<f64>::zeros(50, 1);
    w[(3, 0)] = f64::NAN;
    let r = largest_eigenpairs(50, |x, mut y| y.copy_from(x), Some(w.as_ref()), &p);
    assert!(matches!(r, Err(LanczosError::NonFinite(_))), "{r:?}");
}

#[test]
fn not_converged_returns_partial_result() {
    // Linear spectrum, tiny basis, no restart allowed: cannot converge.
    let n = 400;
    let d: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
    let p = BlockLanczosParams {
        nev: 3,
        block_size: 1,
        max_basis: 8,
        max_restarts: 2,
        ..Default::default()
    };
    let r = largest_eigenpairs(
        n,
        |x, mut y| {
            for j in 0..x.ncols() {
                for i in 0..n {
                    y[(i, j)] = d[i] * x[(i, j)];
                }
            }
        },
        None,
        &p,
    );
    match r {
        Err(LanczosError::NotConverged(partial)) => {
            assert_eq!(partial.values.len(), 3);
            assert_eq!(partial.vectors.ncols(), 3);
            assert_eq!(partial.info.restarts, 2);
            assert!(partial.info.converged < 3);
            assert!(partial.values[0] > 350.0 && partial.values[0] <= 400.0 + 1e-9);
            let msg = LanczosError::NotConverged(partial).to_string();
            assert!(msg.contains("did not converge"), "{msg}");
        }
        other => panic!("expected NotConverged, got {other:?}"),
    }
}

#[test]
fn dense_helper() {
    let a = Mat::from_fn(3, 3, |i, j| if i == j { [3.0, 1.0, 2.0][i] } else { 0.0 });
    let (vals, vecs) = smallest_eigenpairs_dense(a.as_ref(), 2);
    assert_eq!(vals, vec![1.0, 2.0]);
    assert_eq!(vecs.ncols(), 2);
    assert_eq!(vecs[(1, 0)], 1.0);
    assert_eq!(vecs[(2, 1)], 1.0);
    // k clamped, bad input gives empty output and no panic.
    assert_eq!(smallest_eigenpairs_dense(a.as_ref(), 10).0.len(), 3);
    let rect = Mat::<f64>::zeros(3, 2);
    assert!(smallest_eigenpairs_dense(rect.as_ref(), 1).0.is_empty());
    assert!(try_smallest_eigenpairs_dense(rect.as_ref(), 1).is_err());
    let mut nan = Mat::<f64>::identity(3, 3);
    nan[(2, 0)] = f64::NAN;
    assert!(matches!(
        try_smallest_eigenpairs_dense(nan.as_ref(), 1),
        Err(LanczosError::NonFinite(_))
    ));
}

// ---------------------------------------------------------------------------------------
// Accuracy
// ---------------------------------------------------------------------------------------

#[test]
fn diagonal_operator_known_spectrum() {
    let n = 500;
    // Spectrum 1..=500 scattered over the positions by a fixed permutation.
    let pos = |v: usize| (v * 163 + 17) % n; // value v+1 sits at row pos(v); 163 ⟂ 500
    let mut d = vec![0.0; n];
    for v in 0..n {
        d[pos(v)] = (v + 1) as f64;
    }
    let res = largest_eigenpairs(
        n,
        |x, mut y| {
            for j in 0..x.ncols() {
                for i in 0..n {
                    y[(i, j)] = d[i] * x[(i, j)];
                }
            }
        },
        None,
        &params(4, 3),
    )
    .unwrap();
    eprintln!("diagonal n=500: info = {:?}", res.info);
    for k in 0..4 {
        let exact = (n - k) as f64;
        let rel = (res.values[k] - exact).abs() / exact;
        assert!(rel <= 1e-12, "value {k}: {} vs {exact}", res.values[k]);
        let row = pos(n - 1 - k);
        let col = res.vectors.col(k);
        // Sign convention: the large entry is positive.
        assert!((col[row] - 1.0).abs() < 1e-9, "vector {k}: {}", col[row]);
        let mut off = 0.0_f64;
        for i in 0..n {
            if i != row {
                off = off.max(col[i].abs());
            }
        }
        assert!(off < 1e-6, "vector {k}: off-entry {off}");
    }
    assert!(orthonormality_error(res.vectors.as_ref()) < 1e-12);
    assert!(
        last_basis_orthogonality() < 1e-13,
        "{}",
        last_basis_orthogonality()
    );
    assert_eq!(res.info.converged, 4);
    // Regression guard on the restart strategy (300 when written; 825 keeping only nev).
    assert!(res.info.applications <= 360, "{:?}", res.info);
}

#[test]
fn random_dense_spd_matches_dense_solver() {
    let n = 300;
    let b = random_mat(n, n, 42);
    let mut a = Mat::<f64>::zeros(n, n);
    matmul(
        a.as_mut(),
        Accum::Replace,
        b.transpose(),
        b.as_ref(),
        1.0 / n as f64,
        Par::Seq,
    );
    let a = Mat::from_fn(n, n, |i, j| {
        0.5 * (a[(i, j)] + a[(j, i)]) + if i == j { 1e-3 } else { 0.0 }
    });
    let k = 5;
    let res = largest_eigenpairs(n, dense_op(&a), None, &params(k, 3)).unwrap();
    eprintln!("random SPD n=300: info = {:?}", res.info);
    // Reference: smallest of −A.
    let neg = Mat::from_fn(n, n, |i, j| -a[(i, j)]);
    let (ref_vals, ref_vecs) = smallest_eigenpairs_dense(neg.as_ref(), k);
    let mut worst = 0.0_f64;
    for i in 0..k {
        let rel = (res.values[i] + ref_vals[i]).abs() / ref_vals[0].abs();
        worst = worst.max(rel);
        assert!(
            rel < 1e-12,
            "value {i}: {} vs {}",
            res.values[i],
            -ref_vals[i]
        );
    }
    // Same sign convention → the vectors themselves agree.
    let mut vec_err = 0.0_f64;
    for i in 0..k {
        let mut d = 0.0_f64;
        for r in 0..n {
            d = d.max((res.vectors[(r, i)] - ref_vecs[(r, i)]).abs());
        }
        vec_err = vec_err.max(d);
    }
    eprintln!("random SPD: worst value rel err {worst:.2e}, worst vector entry err {vec_err:.2e}");
    assert!(vec_err < 1e-7);
    assert!(outside_span(ref_vecs.as_ref(), res.vectors.as_ref()) < 1e-7);
    let true_res = dense_residuals(&a, &res);
    for (t, e) in true_res.iter().zip(&res.info.residuals) {
        assert!(*t <= 1e-10 * res.values[0], "true residual {t}");
        assert!(
            (t - e).abs() <= 1e-12 * res.values[0],
            "estimate {e} vs true {t}"
        );
    }
}

fn repeated_case(top: &[f64], nev: usize, block_size: usize, seed: u64) -> EigenPairs {
    let n = 200;
    let mut d: Vec<f64> = top.to_vec();
    let mut rng = SplitMix64(seed);
    while d.len() < n {
        // Uniform in [0, 0.8·min(top)): clearly below the top cluster.
        d.push(0.4 * top[nev - 1] * (1.0 + rng.uniform()));
    }
    let q = random_orthogonal(n, seed + 1);
    let a = with_spectrum(&q, &d);
    let res = largest_eigenpairs(n, dense_op(&a), None, &params(nev, block_size)).unwrap();
    eprintln!("repeated {top:?} b={block_size}: info = {:?}", res.info);
    for i in 0..nev {
        assert!(
            (res.values[i] - top[i]).abs() <= 1e-12 * top[0],
            "value {i}: {} vs {}",
            res.values[i],
            top[i]
        );
    }
    assert!(orthonormality_error(res.vectors.as_ref()) < 1e-12);
    assert!(
        last_basis_orthogonality() < 1e-13,
        "{}",
        last_basis_orthogonality()
    );
    for r in dense_residuals(&a, &res) {
        assert!(r <= 1e-10 * top[0], "residual {r}");
    }
    // The computed vectors span the exact eigenspaces (columns of q carrying `top`).
    let err = outside_span(q.as_ref().subcols(0, nev), res.vectors.as_ref());
    assert!(err < 1e-8, "eigenspace error {err}");
    res
}

#[test]
fn repeated_eigenvalue_multiplicity_two() {
    repeated_case(&[10.0, 10.0, 9.0, 8.5], 4, 3, 7);
    // Block size 2 also catches a double eigenvalue.
    repeated_case(&[10.0, 10.0, 9.0], 3, 2, 8);
}

#[test]
fn repeated_eigenvalue_multiplicity_three() {
    repeated_case(&[5.0, 5.0, 5.0, 4.5], 4, 3, 11);
}

// ---------------------------------------------------------------------------------------
// Shift-and-invert
// ---------------------------------------------------------------------------------------

#[test]
fn shift_invert_laplacian() {
    let n = 2000;
    let (mut diag, mut off) = (Vec::new(), Vec::new());
    push_laplacian(&mut diag, &mut off, n, 1.0);
    let a = tridiagonal(&diag, &off);
    let res = largest_eigenpairs(n, inverse_op(&a), None, &params(4, 3)).unwrap();
    let mut worst = 0.0_f64;
    for k in 0..4 {
        let exact = laplacian_eigenvalue(n, k + 1, 1.0);
        let rel = (1.0 / res.values[k] - exact).abs() / exact;
        worst = worst.max(rel);
        assert!(
            rel <= 1e-9,
            "λ_{k}: {} vs {exact} (rel {rel:.2e})",
            1.0 / res.values[k]
        );
    }
    eprintln!(
        "shift-invert Laplacian n=2000: worst rel err {worst:.2e}, info = {:?}",
        res.info
    );
    assert!(res.info.applications <= 36, "{:?}", res.info);
}

#[test]
fn shift_invert_ill_conditioned() {
    // Stiff chain (λ_max ≈ 1e6) plus a tiny-stiffness chain whose lowest eigenvalue is
    // λ_min ≈ 1e-3 (κ ≈ 1e9) or ≈ 1e-9 (κ ≈ 1e15); the four smallest eigenvalues all
    // belong to the soft chain.
    let (n1, s1) = (2000, 2.5e5);
    let n2 = 1000;
    for target in [1e-3, 1e-9] {
        let s2 = target / laplacian_eigenvalue(n2, 1, 1.0);
        let (mut diag, mut off) = (Vec::new(), Vec::new());
        push_laplacian(&mut diag, &mut off, n1, s1);
        push_laplacian(&mut diag, &mut off, n2, s2);
        let a = tridiagonal(&diag, &off);
        let lam_max = laplacian_eigenvalue(n1, n1, s1);
        let lam_min = laplacian_eigenvalue(n2, 1, s2);
        let res = largest_eigenpairs(n1 + n2, inverse_op(&a), None, &params(4, 3)).unwrap();
        let mut worst = 0.0_f64;
        for k in 0..4 {
            let exact = laplacian_eigenvalue(n2, k + 1, s2);
            let rel = (1.0 / res.values[k] - exact).abs() / exact;
            worst = worst.max(rel);
            assert!(
                rel <= 1e-9,
                "λ_{k}: {} vs {exact} (rel {rel:.2e})",
                1.0 / res.values[k]
            );
        }
        assert!(orthonormality_error(res.vectors.as_ref()) < 1e-12);
        assert!(
            last_basis_orthogonality() < 1e-13,
            "{}",
            last_basis_orthogonality()
        );
        eprintln!(
            "shift-invert κ = {:.1e} (λ_min = {lam_min:.3e}, λ_max = {lam_max:.3e}): worst rel err {worst:.2e}, applications {}",
            lam_max / lam_min,
            res.info.applications
        );
    }
}

#[test]
fn warm_start_saves_applications() {
    let n = 2000;
    let (mut diag, mut off) = (Vec::new(), Vec::new());
    push_laplacian(&mut diag, &mut off, n, 1.0);
    let p = params(4, 3);
    let cold = largest_eigenpairs(n, inverse_op(&tridiagonal(&diag, &off)), None, &p).unwrap();

    // Slightly perturbed matrix: diagonal changed by up to 1e-4·λ_min.
    let lam1 = laplacian_eigenvalue(n, 1, 1.0);
    let mut rng = SplitMix64(99);
    let diag2: Vec<f64> = diag
        .iter()
        .map(|d| d + 1e-4 * lam1 * rng.uniform())
        .collect();
    let a2 = tridiagonal(&diag2, &off);
    let cold2 = largest_eigenpairs(n, inverse_op(&a2), None, &p).unwrap();
    let warm = largest_eigenpairs(n, inverse_op(&a2), Some(cold.vectors.as_ref()), &p).unwrap();
    eprintln!(
        "warm start: cold {} applications ({} restarts), warm {} applications ({} restarts)",
        cold2.info.applications, cold2.info.restarts, warm.info.applications, warm.info.restarts
    );
    assert!(
        2 * warm.info.applications < cold2.info.applications,
        "warm {} vs cold {}",
        warm.info.applications,
        cold2.info.applications
    );
    for k in 0..4 {
        let rel = (warm.values[k] - cold2.values[k]).abs() / cold2.values[k];
        assert!(
            rel < 1e-12,
            "value {k}: warm {} vs cold {}",
            warm.values[k],
            cold2.values[k]
        );
    }
    assert!(outside_span(cold2.vectors.as_ref(), warm.vectors.as_ref()) < 1e-6);
}

// ---------------------------------------------------------------------------------------
// Small problems, breakdown, determinism
// ---------------------------------------------------------------------------------------

#[test]
fn tiny_problems() {
    // n = 1.
    let one = Mat::from_fn(1, 1, |_, _| 3.0);
    let res = largest_eigenpairs(1, dense_op(&one), None, &params(1, 3)).unwrap();
    assert!((res.values[0] - 3.0).abs() < 1e-15, "{:?}", res.values);
    assert!((res.vectors[(0, 0)] - 1.0).abs() < 1e-15);
    assert_eq!(res.info.applications, 1);

    // n = 2, both eigenpairs.
    let two = Mat::from_fn(2, 2, |i, j| if i == j { 2.0 } else { 1.0 });
    let res = largest_eigenpairs(2, dense_op(&two), None, &params(2, 3)).unwrap();
    assert!((res.values[0] - 3.0).abs() < 1e-14 && (res.values[1] - 1.0).abs() < 1e-14);
    let s = std::f64::consts::FRAC_1_SQRT_2;
    assert!((res.vectors[(0, 0)] - s).abs() < 1e-14 && (res.vectors[(1, 0)] - s).abs() < 1e-14);
    assert!(orthonormality_error(res.vectors.as_ref()) < 1e-14);

    // n = 5 with max_basis clamped to n (as a caller may do), warm start wider than n.
    let b5 = random_mat(5, 5, 4);
    let a5 = Mat::from_fn(5, 5, |i, j| b5[(i, j)] + b5[(j, i)]);
    let p5 = BlockLanczosParams {
        nev: 4,
        block_size: 3,
        max_basis: 5,
        ..Default::default()
    };
    let warm = random_mat(5, 9, 6);
    let res = largest_eigenpairs(5, dense_op(&a5), Some(warm.as_ref()), &p5).unwrap();
    let neg = Mat::from_fn(5, 5, |i, j| -a5[(i, j)]);
    let (vals, _) = smallest_eigenpairs_dense(neg.as_ref(), 4);
    for k in 0..4 {
        assert!((res.values[k] + vals[k]).abs() < 1e-13, "value {k}");
    }
    assert!(orthonormality_error(res.vectors.as_ref()) < 1e-13);

    // n = 5, all five pairs (the Krylov space is the whole space), block wider than n.
    let b = random_mat(5, 5, 3);
    let a = Mat::from_fn(5, 5, |i, j| b[(i, j)] + b[(j, i)]);
    for bs in [1, 2, 3, 7] {
        let p = BlockLanczosParams {
            nev: 5,
            block_size: bs,
            max_basis: 13,
            ..Default::default()
        };
        let res = largest_eigenpairs(5, dense_op(&a), None, &p).unwrap();
        let neg = Mat::from_fn(5, 5, |i, j| -a[(i, j)]);
        let (vals, _) = smallest_eigenpairs_dense(neg.as_ref(), 5);
        for k in 0..5 {
            assert!(
                (res.values[k] + vals[k]).abs() < 1e-13,
                "bs {bs}, value {k}"
            );
        }
        assert!(orthonormality_error(res.vectors.as_ref()) < 1e-13);
        for r in dense_residuals(&a, &res) {
            assert!(r < 1e-13);
        }
    }
}

#[test]
fn breakdown_and_degenerate_warm_start() {
    // Diagonal operator; the warm start is an exact eigenvector and a duplicate of it, so
    // the first expansion breaks down and random vectors must be injected.
    let n = 120;
    let d: Vec<f64> = (0..n)
        .map(|i| {
            if i < 3 {
                50.0 - i as f64
            } else {
                (i % 17) as f64
            }
        })
        .collect();
    let op = |x: MatRef<'_, f64>, mut y: MatMut<'_, f64>| {
        for j in 0..x.ncols() {
            for i in 0..n {
                y[(i, j)] = d[i] * x[(i, j)];
            }
        }
    };
    let mut w = Mat::<f64>::zeros(n, 3);
    w[(2, 0)] = 1.0;
    w[(2, 1)] = -2.0;
    let res = largest_eigenpairs(n, op, Some(w.as_ref()), &params(3, 3)).unwrap();
    for k in 0..3 {
        assert!(
            (res.values[k] - (50 - k) as f64).abs() < 1e-12,
            "{:?}",
            res.values
        );
        assert!((res.vectors[(k, k)] - 1.0).abs() < 1e-12);
    }
    assert!(orthonormality_error(res.vectors.as_ref()) < 1e-14);
    // Zero operator: everything is an eigenvector of 0.
    let res = largest_eigenpairs(30, |_, _| {}, None, &params(2, 2)).unwrap();
    assert_eq!(res.values, vec![0.0, 0.0]);
    assert!(orthonormality_error(res.vectors.as_ref()) < 1e-14);
}

#[test]
fn deterministic_bit_identical() {
    let n = 300;
    let q = random_orthogonal(n, 5);
    let d: Vec<f64> = (0..n).map(|i| 100.0 / (1.0 + i as f64)).collect();
    let a = with_spectrum(&q, &d);
    let p = BlockLanczosParams {
        nev: 4,
        block_size: 3,
        max_basis: 12, // force restarts
        seed: 1234,
        ..Default::default()
    };
    // Same solve inside rayon pools of 1 and 4 threads (faer's default global parallelism
    // follows the pool), without touching process-wide settings.
    let in_pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let r = largest_eigenpairs(n, dense_op(&a), None, &p).unwrap();
                (r, last_basis_orthogonality())
            })
    };
    let (r1, orth1) = in_pool(1);
    let (r2, _) = in_pool(4);
    assert!(r1.info.restarts > 0);
    assert!(orth1 < 1e-13, "{orth1}");
    assert_eq!(r1.info, r2.info);
    let bits = |r: &EigenPairs| {
        let mut v: Vec<u64> = r.values.iter().map(|x| x.to_bits()).collect();
        for j in 0..r.vectors.ncols() {
            for i in 0..n {
                v.push(r.vectors[(i, j)].to_bits());
            }
        }
        v
    };
    assert_eq!(bits(&r1), bits(&r2));
    // Another seed converges to the same pairs, not bit-identically.
    let r3 =
        largest_eigenpairs(n, dense_op(&a), None, &BlockLanczosParams { seed: 99, ..p }).unwrap();
    for k in 0..4 {
        assert!((r3.values[k] - r1.values[k]).abs() < 1e-12 * r1.values[0]);
    }
}

#[test]
fn single_vector_and_large_basis() {
    // block_size 1 (plain thick-restart Lanczos) and a basis much larger than needed on a
    // small problem (exercises the sparse convergence checks).
    let n = 150;
    let d: Vec<f64> = (0..n)
        .map(|i| 1.0 + ((i * 37) % n) as f64 / n as f64)
        .collect();
    let mut sorted = d.clone();
    sorted.sort_by(|a, b| b.total_cmp(a));
    let op = |x: MatRef<'_, f64>, mut y: MatMut<'_, f64>| {
        for j in 0..x.ncols() {
            for i in 0..n {
                y[(i, j)] = d[i] * x[(i, j)];
            }
        }
    };
    for (bs, mb) in [(1, 20), (2, 140), (3, 148)] {
        let p = BlockLanczosParams {
            nev: 3,
            block_size: bs,
            max_basis: mb,
            max_restarts: 500,
            ..Default::default()
        };
        let res = largest_eigenpairs(n, op, None, &p).unwrap();
        for k in 0..3 {
            assert!(
                (res.values[k] - sorted[k]).abs() < 1e-12,
                "bs {bs}: {:?}",
                res.values
            );
        }
        assert!(orthonormality_error(res.vectors.as_ref()) < 1e-12);
        assert!(
            last_basis_orthogonality() < 1e-13,
            "{}",
            last_basis_orthogonality()
        );
    }
}

#[test]
fn wide_warm_start_uses_nev_columns() {
    let n = 300;
    let q = random_orthogonal(n, 21);
    let d: Vec<f64> = (0..n).map(|i| 10.0 / (1.0 + i as f64)).collect();
    let a = with_spectrum(&q, &d);
    let p = params(4, 2);
    let cold = largest_eigenpairs(n, dense_op(&a), None, &p).unwrap();
    // 10 warm columns: the exact top-4 eigenvectors first, then junk.
    let mut w = random_mat(n, 10, 3);
    w.as_mut()
        .subcols_mut(0, 4)
        .copy_from(q.as_ref().subcols(0, 4));
    let warm = largest_eigenpairs(n, dense_op(&a), Some(w.as_ref()), &p).unwrap();
    // Exact warm vectors: one block of 4 applications suffices.
    assert_eq!(warm.info.applications, 4, "{:?}", warm.info);
    for k in 0..4 {
        assert!((warm.values[k] - cold.values[k]).abs() < 1e-12 * d[0]);
    }
}

/// Timing on a 2D grid Laplacian (n ≈ 20,000, double eigenvalues), shift-and-invert.
/// Run with `cargo test --release -- --ignored --nocapture bench_grid`.
#[test]
#[ignore]
fn bench_grid() {
    use std::time::{Duration, Instant};
    let g = 141;
    let n = g * g;
    let build = |eps: f64| {
        let mut rng = SplitMix64(5);
        let mut trip = Vec::new();
        for i in 0..g {
            for j in 0..g {
                let k = i * g + j;
                trip.push(Triplet::new(k, k, 4.0 + eps * rng.uniform()));
                if i + 1 < g {
                    trip.push(Triplet::new(k + g, k, -1.0));
                    trip.push(Triplet::new(k, k + g, -1.0));
                }
                if j + 1 < g {
                    trip.push(Triplet::new(k + 1, k, -1.0));
                    trip.push(Triplet::new(k, k + 1, -1.0));
                }
            }
        }
        SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &trip).unwrap()
    };
    let lam =
        |a: usize, b: usize| laplacian_eigenvalue(g, a, 1.0) + laplacian_eigenvalue(g, b, 1.0);
    let exact = [lam(1, 1), lam(1, 2), lam(2, 1), lam(2, 2)];
    let p = params(4, 3);
    let run = |a: &SparseColMat<usize, f64>, warm: Option<MatRef<'_, f64>>| {
        let llt = a.sp_cholesky(Side::Lower).unwrap();
        let mut op_time = Duration::ZERO;
        let t0 = Instant::now();
        let res = largest_eigenpairs(
            n,
            |x, mut y| {
                let t = Instant::now();
                y.copy_from(x);
                llt.solve_in_place(y.rb_mut());
                op_time += t.elapsed();
            },
            warm,
            &p,
        )
        .unwrap();
        (res, t0.elapsed(), op_time)
    };
    let a0 = build(0.0);
    let (cold, t, top) = run(&a0, None);
    let errs: Vec<f64> = (0..4)
        .map(|k| (1.0 / cold.values[k] - exact[k]).abs() / exact[k])
        .collect();
    eprintln!(
        "grid n={n}: cold {} apps, {} restarts, total {:?}, operator {:?}, rel errs {errs:?}",
        cold.info.applications, cold.info.restarts, t, top
    );
    for eps in [1e-3, 1e-5, 1e-7] {
        let a1 = build(eps);
        let (c1, t1, o1) = run(&a1, None);
        let (w1, t2, o2) = run(&a1, Some(cold.vectors.as_ref()));
        eprintln!(
            "  perturbed diag ±{eps:.0e}: cold {} apps ({t1:?}, op {o1:?}), warm {} apps ({t2:?}, op {o2:?})",
            c1.info.applications, w1.info.applications
        );
    }
}
