//! Conjugate gradients on a matrix of the model's pattern, preconditioned by the Cholesky
//! factor of a nearby matrix: Newton's steps near an equilibrium solve each Hessian with one
//! earlier factorization ([`super::newton`], Krylov steps).
//!
//! With the preconditioner `F⁻¹`, `F` a factorization of `H + E`, CG converges in about as
//! many iterations as `F⁻¹ H` has eigenvalues away from one: few while `E` is small next to
//! the soft eigenvalues of `H`, or of low rank. Starting from zero, every iterate `d` is a
//! descent direction of the quadratic model (`gᵀd > 0` for `H` positive definite on the
//! Krylov space). The iteration is faer's (`faer::matrix_free::conjugate_gradient`), over the
//! pattern's symmetric product and the factor's substitution; a direction of negative
//! curvature ends it (faer reports the operator as not positive definite).

use super::factor::{Cholesky, Schedule};
use crate::sparse::Pattern;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::matrix_free::conjugate_gradient::{
    CgParams, conjugate_gradient, conjugate_gradient_scratch,
};
use faer::matrix_free::{InitialGuessStatus, LinOp, Precond};
use faer::reborrow::ReborrowMut;
use faer::{Mat, MatMut, MatRef, Par};
use std::sync::atomic::{AtomicUsize, Ordering};

/// What a preconditioned solve found.
#[derive(Debug)]
pub struct Pcg {
    /// The solution (the residual below the target), or `None`: the target was not reached
    /// within the solves allowed, or the matrix showed a direction of negative curvature.
    pub x: Option<Vec<f64>>,
    /// Solves with the factor it took (one per iteration).
    pub solves: usize,
}

/// Solves `H x = b` (`H` given by its upper-triangle `values` on `pattern`) from `x = 0` by
/// conjugate gradients preconditioned with `factor`, until `‖b − H x‖ < target`, with at most
/// `max_solves` solves, each a substitution on `schedule`.
pub fn solve(
    pattern: &Pattern,
    values: &[f64],
    factor: &Cholesky,
    b: &[f64],
    target: f64,
    max_solves: usize,
    schedule: Schedule,
) -> Pcg {
    let n = b.len();
    let op = Symmetric { pattern, values };
    let precond = Substitution {
        factor,
        n,
        solves: AtomicUsize::new(0),
        max_solves,
        schedule,
    };
    let params = CgParams {
        // With `Zero` faer 0.24 leaves its residual unset; from a zero guess the residual
        // `b − H·0` is `b` either way.
        initial_guess: InitialGuessStatus::MaybeNonZero,
        abs_tolerance: target,
        rel_tolerance: 0.0,
        // The first solve comes before the first iteration, one more after each.
        max_iters: max_solves.max(1),
        ..Default::default()
    };
    let mut x = Mat::<f64>::zeros(n, 1);
    let rhs = MatRef::from_column_major_slice(b, n, 1);
    let mut mem = MemBuffer::new(conjugate_gradient_scratch(&precond, &op, 1, Par::Seq));
    let found = conjugate_gradient(
        x.as_mut(),
        &precond,
        &op,
        rhs,
        params,
        |_| {},
        Par::Seq,
        MemStack::new(&mut mem),
    );
    let solves = precond.solves.load(Ordering::Relaxed);
    let x = match found {
        Ok(_) => Some(x.col(0).iter().copied().collect()),
        Err(_) => None,
    };
    Pcg { x, solves }
}

/// `H` as faer's operator: the pattern's symmetric product.
#[derive(Debug)]
struct Symmetric<'a> {
    pattern: &'a Pattern,
    values: &'a [f64],
}

impl LinOp<f64> for Symmetric<'_> {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> StackReq {
        StackReq::EMPTY
    }

    fn nrows(&self) -> usize {
        self.pattern.n
    }

    fn ncols(&self) -> usize {
        self.pattern.n
    }

    fn apply(&self, mut out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _: Par, _: &mut MemStack) {
        for j in 0..rhs.ncols() {
            let x = rhs.col(j).try_as_col_major().map(|c| c.as_slice());
            let y = out.rb_mut().col_mut(j).try_as_col_major_mut();
            match (x, y) {
                (Some(x), Some(y)) => self.pattern.sym_matvec(self.values, x, y.as_slice_mut()),
                _ => {
                    let x: Vec<f64> = rhs.col(j).iter().copied().collect();
                    let mut y = vec![0.0; self.pattern.n];
                    self.pattern.sym_matvec(self.values, &x, &mut y);
                    for (i, v) in y.into_iter().enumerate() {
                        out[(i, j)] = v;
                    }
                }
            }
        }
    }

    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, s: &mut MemStack) {
        self.apply(out, rhs, par, s);
    }
}

/// `F⁻¹` as faer's preconditioner, counting its solves, at most `max_solves`: faer applies it
/// once more after its last iteration, whose result a solve that stops there never uses, so
/// that application is skipped. Each solve is one substitution on the caller's `schedule`
/// (the solves of a CG run form a chain that leaves the other cores idle; see
/// [`super::SolverTuning::split_solves_above`]).
#[derive(Debug)]
struct Substitution<'a> {
    factor: &'a Cholesky,
    n: usize,
    solves: AtomicUsize,
    max_solves: usize,
    schedule: Schedule,
}

impl LinOp<f64> for Substitution<'_> {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> StackReq {
        StackReq::EMPTY
    }

    fn nrows(&self) -> usize {
        self.n
    }

    fn ncols(&self) -> usize {
        self.n
    }

    fn apply(&self, mut out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _: Par, _: &mut MemStack) {
        out.copy_from(rhs);
        if self.solves.fetch_add(1, Ordering::Relaxed) < self.max_solves {
            self.factor.solve_in_place(out, self.schedule);
        } else {
            self.solves.fetch_sub(1, Ordering::Relaxed);
        }
    }

    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, s: &mut MemStack) {
        self.apply(out, rhs, par, s);
    }
}

impl Precond<f64> for Substitution<'_> {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve::factor::SymbolicFactor;
    use crate::sparse::tridiagonal;

    fn norm(v: &[f64]) -> f64 {
        v.iter().map(|x| x * x).sum::<f64>().sqrt()
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
        let cg = |f: &Cholesky, target: f64, max_solves: usize| {
            solve(&pattern, &h, f, &b, target, max_solves, Schedule::Groups(1))
        };
        let exact = Cholesky::factorize(&symbolic, &pattern, &h, 0.0, None).unwrap();
        let s = cg(&exact, 1e-10 * norm(&b), 5);
        assert_eq!(s.solves, 1);
        assert!(residual(&s.x.unwrap()) <= 1e-10 * norm(&b));
        // A factor of a matrix changed in one entry: CG with it needs two or three solves.
        let mut near = h.clone();
        near[pattern.diag[30]] += 0.5;
        let f = Cholesky::factorize(&symbolic, &pattern, &near, 0.0, None).unwrap();
        let s = cg(&f, 1e-10 * norm(&b), 10);
        assert!(s.solves <= 3, "{}", s.solves);
        assert!(residual(&s.x.unwrap()) <= 1e-10 * norm(&b));
        // Too few solves allowed: no answer.
        let far = Cholesky::factorize(&symbolic, &pattern, &h, 3.0, None).unwrap();
        let s = cg(&far, 1e-12 * norm(&b), 2);
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
        let s = solve(&pattern, &h, &f, &b, 1e-12, 100, Schedule::Groups(1));
        assert!(s.x.is_none() && s.solves == 1, "{s:?}");
    }
}
