//! Orthonormalisation of new Krylov blocks against the basis: block classical Gram–Schmidt
//! passes (repeated by the Daniel–Gragg–Kaufman–Stewart criterion), and seeded random
//! vectors where a block is rank deficient.

use crate::rng::SplitMix64;
use faer::linalg::matmul::matmul;
use faer::prelude::*;
use faer::{Accum, ColRef, Mat, MatMut, MatRef, Par};

/// Columns whose norm falls below this fraction of the operator output's norm are
/// treated as linearly dependent (replaced by random vectors).
pub(super) const EXPAND_DROP_TOL: f64 = 1e-14;
/// Same for warm-start columns: nearly dependent warm vectors are better replaced by
/// random ones than normalised rounding noise.
pub(super) const START_DROP_TOL: f64 = 1e-10;
/// A further full orthogonalisation pass over the block is made while a pass keeps less
/// than this fraction of some column's norm (Daniel–Gragg–Kaufman–Stewart criterion).
pub(super) const DGKS_RATIO: f64 = std::f64::consts::FRAC_1_SQRT_2;
/// Random vectors are orthogonalised again while a pass keeps less than this fraction.
const REORTH_RATIO: f64 = 0.5;
/// Orthogonalising a column against the other new columns of its block (already
/// orthogonal to the basis) amplifies its residual components along the basis by the
/// norm ratio; beyond this ratio a further full pass is made (components stay below
/// `≈ 100·√m·ε`).
const BLOCK_CANCEL_RATIO: f64 = 1e-2;

/// `x ← x − B·(Bᵀx)`, `coef ← Bᵀx` (one classical Gram–Schmidt pass, `x` is `n × 1`).
fn project_out(basis: MatRef<'_, f64>, x: MatMut<'_, f64>, mut coef: MatMut<'_, f64>) {
    if basis.ncols() == 0 {
        return;
    }
    matmul(
        coef.rb_mut(),
        Accum::Replace,
        basis.transpose(),
        x.rb(),
        1.0,
        Par::Seq,
    );
    matmul(x, Accum::Add, basis, coef.rb(), -1.0, Par::Seq);
}

/// Euclidean norm: plain sum of squares when that is safe, faer's scaled (robust, but
/// much slower on entries below 1, whose scaled squares are subnormal) otherwise.
pub(super) fn norm2(x: ColRef<'_, f64>) -> f64 {
    let s = x.squared_norm_l2();
    if s.is_nan() || (s.is_finite() && s >= 1e-250) {
        s.sqrt()
    } else {
        x.norm_l2()
    }
}

/// Column norms of `w`.
pub(super) fn col_norms(w: MatRef<'_, f64>) -> Vec<f64> {
    (0..w.ncols()).map(|j| norm2(w.col(j))).collect()
}

/// A new block's columns to orthonormalise against the basis columns before `start`.
pub(super) struct NewBlock<'a> {
    /// The basis columns the block is orthogonal to (`v[:, 0..start]`); the new columns go
    /// after them.
    pub start: usize,
    /// Columns wanted (at most this many are made).
    pub q_target: usize,
    /// Each column's norm before any orthogonalisation.
    pub a0: &'a [f64],
    /// Each column's norm after the last pass against `v[:, 0..start]`.
    pub a1: &'a [f64],
    /// Columns left with norm `≤ drop_tol·a0[j]` count as dependent.
    pub drop_tol: f64,
}

/// Orthonormalises the columns of `w` (already orthogonal to `v[:, 0..start]` to working
/// precision) against the basis and each other, writing the new orthonormal columns into
/// `v[:, start..start + q]` with `q ≤ q_target`. Missing columns (rank deficiency, or fewer
/// columns than `q_target`) are filled with random vectors orthogonal to everything before
/// them. Returns `R` (`q × w.ncols()`) with `w_in = V·h_extra + Q·R`: the coefficients of
/// the extra passes against `v[:, 0..start]` are added into `h`.
pub(super) fn orthonormalize_block(
    v: &mut Mat<f64>,
    w: MatMut<'_, f64>,
    block: &NewBlock<'_>,
    h: Option<MatMut<'_, f64>>,
    rng: &mut SplitMix64,
) -> Mat<f64> {
    let n = v.nrows();
    if v.ncols() < block.start + block.q_target {
        // Within the reserved capacity: no reallocation.
        v.resize_with(n, block.start + block.q_target, |_, _| 0.0);
    }
    let (r, q) = orthonormalize_columns(v, w, block, h);
    let q = fill_random(v, block.start, q, block.q_target, rng);
    if q < block.q_target {
        r.subrows(0, q).to_owned()
    } else {
        r
    }
}

/// The column-by-column part of [`orthonormalize_block`]: `R` and the number of columns
/// made.
fn orthonormalize_columns(
    v: &mut Mat<f64>,
    mut w: MatMut<'_, f64>,
    block: &NewBlock<'_>,
    mut h: Option<MatMut<'_, f64>>,
) -> (Mat<f64>, usize) {
    let n = v.nrows();
    let (start, q_target) = (block.start, block.q_target);
    let p = w.ncols();
    let mut r = Mat::<f64>::zeros(q_target, p);
    let mut coef = Mat::<f64>::zeros(start + q_target, 1);
    let mut q = 0;
    for j in 0..p {
        let mut wj = w.rb_mut().subcols_mut(j, 1);
        // Two passes against the new columns of this block.
        for _ in 0..2 {
            if q == 0 {
                break;
            }
            let mut c = coef.as_mut().subrows_mut(0, q);
            project_out(v.as_ref().subcols(start, q), wj.rb_mut(), c.rb_mut());
            for i in 0..q {
                r[(i, j)] += c[(i, 0)];
            }
        }
        let mut prev = block.a1[j];
        let mut cur = norm2(wj.rb().col(0));
        // Heavy cancellation: further full passes until the norm stabilises.
        let mut extra = 0;
        while cur < BLOCK_CANCEL_RATIO * prev && cur > 0.0 && extra < 3 {
            let mut c = coef.as_mut().subrows_mut(0, start + q);
            project_out(v.as_ref().subcols(0, start + q), wj.rb_mut(), c.rb_mut());
            if let Some(h) = h.as_mut() {
                for i in 0..start {
                    h[(i, j)] += c[(i, 0)];
                }
            }
            for i in 0..q {
                r[(i, j)] += c[(start + i, 0)];
            }
            prev = cur;
            cur = norm2(wj.rb().col(0));
            extra += 1;
        }
        if q < q_target && cur.is_normal() && cur > block.drop_tol * block.a0[j] {
            let mut dst = v.as_mut().col_mut(start + q);
            let src = wj.rb().col(0);
            for i in 0..n {
                dst[i] = src[i] / cur;
            }
            r[(q, j)] = cur;
            q += 1;
        }
    }
    (r, q)
}

/// Fills `v[:, start + q..start + q_target]` with random unit vectors orthogonal to the
/// basis before them (breakdown, start block); returns the columns made in all (fewer only
/// when the space is exhausted).
fn fill_random(
    v: &mut Mat<f64>,
    start: usize,
    mut q: usize,
    q_target: usize,
    rng: &mut SplitMix64,
) -> usize {
    let n = v.nrows();
    let mut coef = Mat::<f64>::zeros(start + q_target, 1);
    'fill: while q < q_target {
        for _attempt in 0..10 {
            let (left, right) = v.as_mut().split_at_col_mut(start + q);
            let basis = left.rb();
            let mut x = right.subcols_mut(0, 1);
            for i in 0..n {
                x[(i, 0)] = rng.uniform(-1.0, 1.0);
            }
            let a = norm2(x.rb().col(0));
            let mut prev = a;
            let mut cur = a;
            for pass in 0..4 {
                let c = coef.as_mut().subrows_mut(0, start + q);
                project_out(basis, x.rb_mut(), c);
                cur = norm2(x.rb().col(0));
                if pass >= 1 && cur >= REORTH_RATIO * prev {
                    break;
                }
                prev = cur;
            }
            if cur.is_normal() && cur > 1e-8 * a {
                for i in 0..n {
                    x[(i, 0)] /= cur;
                }
                q += 1;
                continue 'fill;
            }
        }
        // Could not find a new direction (only possible when the space is exhausted).
        break;
    }
    q
}
