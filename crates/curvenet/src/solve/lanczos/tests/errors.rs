//! Bad parameters and operators are errors; runs that do not converge hand back what they
//! found; the dense helper.

use super::*;

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
    let (vals, vecs) = smallest_eigenpairs_dense(a.as_ref(), 2).expect("diagonal");
    assert_eq!(vals, vec![1.0, 2.0]);
    assert_eq!(vecs.ncols(), 2);
    assert_eq!(vecs[(1, 0)], 1.0);
    assert_eq!(vecs[(2, 1)], 1.0);
    // k clamped; bad input is an error, never a panic.
    let all = smallest_eigenpairs_dense(a.as_ref(), 10).expect("diagonal");
    assert_eq!(all.0.len(), 3);
    let rect = Mat::<f64>::zeros(3, 2);
    assert!(matches!(
        smallest_eigenpairs_dense(rect.as_ref(), 1),
        Err(LanczosError::InvalidParams(_))
    ));
    let mut nan = Mat::<f64>::identity(3, 3);
    nan[(2, 0)] = f64::NAN;
    assert!(matches!(
        smallest_eigenpairs_dense(nan.as_ref(), 1),
        Err(LanczosError::NonFinite(_))
    ));
}

// ---------------------------------------------------------------------------------------
// Accuracy
// ---------------------------------------------------------------------------------------
