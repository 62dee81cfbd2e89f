//! Accuracy against dense solutions and known spectra, repeated eigenvalues, warm starts,
//! tiny problems, breakdowns and bit-identical determinism.

use super::*;

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
    let (ref_vals, ref_vecs) = smallest_eigenpairs_dense(neg.as_ref(), k).expect("dense solve");
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
    let mut rng = SplitMix64::new(seed);
    while d.len() < n {
        // Uniform in [0, 0.8·min(top)): clearly below the top cluster.
        d.push(0.4 * top[nev - 1] * (1.0 + rng.uniform(-1.0, 1.0)));
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
    let mut rng = SplitMix64::new(99);
    let diag2: Vec<f64> = diag
        .iter()
        .map(|d| d + 1e-4 * lam1 * rng.uniform(-1.0, 1.0))
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
    let (vals, _) = smallest_eigenpairs_dense(neg.as_ref(), 4).expect("dense solve");
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
        let (vals, _) = smallest_eigenpairs_dense(neg.as_ref(), 5).expect("dense solve");
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
