//! The numeric factorization reuses buffers of dropped factors (`solve::factor`): which buffer
//! a factorization gets must never change its values.

mod common;

use common::{build, random_curves};
use curvenet::rod::Supports;
use curvenet::solve::Cholesky;
use curvenet::stability::{Analyzer, StabilityParams};

fn solve_bits(f: &Cholesky, n: usize) -> Vec<u64> {
    let mut rhs: Vec<f64> = (0..n).map(|i| ((i * 7919) % 101) as f64 - 50.0).collect();
    f.solve_vec(&mut rhs);
    rhs.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn reused_buffers_give_bit_identical_factors() {
    let net = build(&random_curves(3, 4), 20.0, Supports::Clamped);
    let a = Analyzer::new(net, StabilityParams::default()).expect("analyzer");
    let model = a.model();
    let n = model.dofs();
    let u = vec![0.0; n];
    let h = model.assemble(&u, &a.all(), true).hess;
    let sym = a.symbolic();
    let pattern = model.pattern();
    // The drawn state's Hessian need not be definite: shift it by its 1-norm (Gershgorin).
    let s = pattern.sym_norm1(&h);

    let first = Cholesky::factorize(sym, pattern, &h, s).expect("positive definite");
    let reference = solve_bits(&first, n);
    drop(first);
    // A failed factorization (far below the smallest eigenvalue) hands its buffer back too.
    assert!(Cholesky::factorize(sym, pattern, &h, -10.0 * s).is_err());
    // Several factors alive at once, some on reused buffers, some on fresh ones.
    let alive: Vec<Cholesky> = (0..6)
        .map(|_| Cholesky::factorize(sym, pattern, &h, s).expect("positive definite"))
        .collect();
    for f in &alive {
        assert_eq!(solve_bits(f, n), reference);
    }
    drop(alive);
    // A differently shifted matrix in between must not leak into the next factor.
    let shifted = Cholesky::factorize(sym, pattern, &h, 2.0 * s).expect("positive definite");
    assert_ne!(solve_bits(&shifted, n), reference);
    drop(shifted);
    let again = Cholesky::factorize(sym, pattern, &h, s).expect("positive definite");
    assert_eq!(solve_bits(&again, n), reference);
}
