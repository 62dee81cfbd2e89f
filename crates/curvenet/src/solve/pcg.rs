//! Conjugate gradients on a matrix of the model's pattern, preconditioned by the Cholesky
//! factor of a nearby matrix: Newton's steps near an equilibrium solve each Hessian with one
//! earlier factorization ([`super::newton`], Krylov steps).
//!
//! With the preconditioner `F⁻¹`, `F` a factorization of `H + E`, CG converges in about as
//! many iterations as `F⁻¹ H` has eigenvalues away from one: few while `E` is small next to
//! the soft eigenvalues of `H`, or of low rank. Starting from zero, every iterate `d` is a
//! descent direction of the quadratic model (`gᵀd > 0` for `H` positive definite on the
//! Krylov space); a direction of non-positive curvature ends the solve.

use super::factor::{Cholesky, Schedule};
use crate::sparse::Pattern;

/// What a preconditioned solve found.
#[derive(Debug)]
pub struct Pcg {
    /// The solution (the residual at most the target), or `None`: the target was not
    /// reached within the solves allowed, or the matrix showed a direction of non-positive
    /// curvature.
    pub x: Option<Vec<f64>>,
    /// Solves with the factor it took (one per iteration).
    pub solves: usize,
}

/// Solves `H x = b` (`H` given by its upper-triangle `values` on `pattern`) from `x = 0` by
/// conjugate gradients preconditioned with `factor`, until `‖b − H x‖ ≤ target`, with at most
/// `max_solves` solves.
pub fn solve(
    pattern: &Pattern,
    values: &[f64],
    factor: &Cholesky,
    b: &[f64],
    target: f64,
    max_solves: usize,
) -> Pcg {
    let n = b.len();
    let mut x = vec![0.0; n];
    let mut r = b.to_vec();
    let mut z = r.clone();
    let mut hp = vec![0.0; n];
    let mut solves = 0;
    if norm(&r) <= target {
        return Pcg { x: Some(x), solves };
    }
    precondition(factor, &mut z);
    solves += 1;
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    loop {
        pattern.sym_matvec(values, &p, &mut hp);
        let curvature = dot(&p, &hp);
        if !(curvature > 0.0 && rz > 0.0 && curvature.is_finite()) {
            return Pcg { x: None, solves };
        }
        let alpha = rz / curvature;
        for i in 0..n {
            x[i] += alpha * p[i];
            r[i] -= alpha * hp[i];
        }
        if norm(&r) <= target {
            return Pcg { x: Some(x), solves };
        }
        if solves >= max_solves {
            return Pcg { x: None, solves };
        }
        z.copy_from_slice(&r);
        precondition(factor, &mut z);
        solves += 1;
        let rz_next = dot(&r, &z);
        let beta = rz_next / rz;
        rz = rz_next;
        for i in 0..n {
            p[i] = z[i] + beta * p[i];
        }
    }
}

/// `z ← F⁻¹ z` by one sequential substitution: the solves of a CG run form a chain that
/// leaves the other cores idle, and a substitution split across cores waits on them whenever
/// the machine is busy with other work (bit-identical either way).
fn precondition(factor: &Cholesky, z: &mut [f64]) {
    let n = z.len();
    let column = faer::MatMut::from_column_major_slice_mut(z, n, 1);
    factor.solve_in_place(column, Schedule::Groups(1));
}

fn norm(v: &[f64]) -> f64 {
    dot(v, v).sqrt()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve::factor::SymbolicFactor;

    /// The tridiagonal matrix `tridiag(−1, d, −1)` of size `n` (upper triangle).
    fn tridiagonal(n: usize, d: f64) -> (Pattern, Vec<f64>) {
        let mut col_ptr = vec![0];
        let (mut row_idx, mut diag, mut values) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..n {
            if j > 0 {
                row_idx.push(j - 1);
                values.push(-1.0);
            }
            diag.push(row_idx.len());
            row_idx.push(j);
            values.push(d);
            col_ptr.push(row_idx.len());
        }
        let pattern = Pattern {
            n,
            col_ptr,
            row_idx,
            diag,
        };
        (pattern, values)
    }

    #[test]
    fn a_nearby_factor_solves_in_few_iterations_and_an_exact_one_in_one() {
        let n = 60;
        let (pattern, h) = tridiagonal(n, 2.1);
        let symbolic = SymbolicFactor::new(&pattern, Default::default());
        let b: Vec<f64> = (0..n).map(|i| ((i * 7) % 11) as f64 - 5.0).collect();
        let residual = |x: &[f64]| {
            let mut hx = vec![0.0; n];
            pattern.sym_matvec(&h, x, &mut hx);
            norm(&hx.iter().zip(&b).map(|(a, c)| a - c).collect::<Vec<_>>())
        };
        let exact = Cholesky::factorize(&symbolic, &pattern, &h, 0.0, None).unwrap();
        let s = solve(&pattern, &h, &exact, &b, 1e-10 * norm(&b), 5);
        assert_eq!(s.solves, 1);
        assert!(residual(&s.x.unwrap()) <= 1e-10 * norm(&b));
        // A factor of a matrix changed in one entry: CG with it needs two or three solves.
        let mut near = h.clone();
        near[pattern.diag[30]] += 0.5;
        let f = Cholesky::factorize(&symbolic, &pattern, &near, 0.0, None).unwrap();
        let s = solve(&pattern, &h, &f, &b, 1e-10 * norm(&b), 10);
        assert!(s.solves <= 3, "{}", s.solves);
        assert!(residual(&s.x.unwrap()) <= 1e-10 * norm(&b));
        // Too few solves allowed: no answer.
        let far = Cholesky::factorize(&symbolic, &pattern, &h, 3.0, None).unwrap();
        let s = solve(&pattern, &h, &far, &b, 1e-12 * norm(&b), 2);
        assert!(s.x.is_none() && s.solves == 2);
    }

    #[test]
    fn an_indefinite_matrix_ends_the_solve() {
        let n = 30;
        let (pattern, h) = tridiagonal(n, 1.0);
        let symbolic = SymbolicFactor::new(&pattern, Default::default());
        // `tridiag(−1, 1, −1)` has eigenvalues down to about −1; its shift by 2 factors and
        // shares its eigenvectors, so along the lowest one the first direction already has
        // negative curvature.
        let f = Cholesky::factorize(&symbolic, &pattern, &h, 2.0, None).unwrap();
        let theta = std::f64::consts::PI / (n as f64 + 1.0);
        let b: Vec<f64> = (1..=n).map(|i| (i as f64 * theta).sin()).collect();
        let s = solve(&pattern, &h, &f, &b, 1e-12, 100);
        assert!(s.x.is_none() && s.solves == 1, "{s:?}");
    }
}
