//! Small dense helpers of the bounds: bases as lists of columns, Gram matrices, Ritz values.

use super::Bound;
use faer::{Mat, MatRef};

/// The columns of `ms`, in order: a basis made of several blocks, without copying them.
pub(super) fn columns<'m>(ms: &[&'m Mat<f64>]) -> Vec<&'m [f64]> {
    ms.iter()
        .flat_map(|m| (0..m.ncols()).map(move |j| col(m, j)))
        .collect()
}

/// Column `j` of `m` as a slice (faer stores columns contiguously).
fn col(m: &Mat<f64>, j: usize) -> &[f64] {
    m.col(j)
        .try_as_col_major()
        .expect("contiguous column")
        .as_slice()
}

/// `AᵀB` for the bases `a` and `b` (lists of columns).
pub(super) fn gram(a: &[&[f64]], b: &[&[f64]]) -> Mat<f64> {
    Mat::from_fn(a.len(), b.len(), |i, j| dot(a[i], b[j]))
}

/// `xᵀy`, summed in eight interleaved lanes (vectorized).
fn dot(x: &[f64], y: &[f64]) -> f64 {
    let mut acc = [0.0; 8];
    let (xc, yc) = (x.chunks_exact(8), y.chunks_exact(8));
    let tail: f64 = xc
        .remainder()
        .iter()
        .zip(yc.remainder())
        .map(|(a, b)| a * b)
        .sum();
    for (a, b) in xc.zip(yc) {
        for l in 0..8 {
            acc[l] += a[l] * b[l];
        }
    }
    acc.iter().sum::<f64>() + tail
}

/// `A·Q` for the basis `a` (a list of columns).
pub(super) fn combine(a: &[&[f64]], q: MatRef<'_, f64>) -> Mat<f64> {
    let n = a.first().map_or(0, |c| c.len());
    let mut out = Mat::<f64>::zeros(n, q.ncols());
    for j in 0..q.ncols() {
        let o = out
            .col_mut(j)
            .try_as_col_major_mut()
            .expect("contiguous column")
            .as_slice_mut();
        for (i, c) in a.iter().enumerate() {
            let w = q[(i, j)];
            for (o, x) in o.iter_mut().zip(c.iter()) {
                *o += w * x;
            }
        }
    }
    out
}

/// The lower of two bounds once their margins are counted (`a` on a tie).
pub(super) fn lower(a: Bound, b: Bound) -> Bound {
    if b.value + b.margin < a.value + a.margin {
        b
    } else {
        a
    }
}

/// Zeroes `rows` of `m`.
pub(super) fn zero_rows(m: &mut Mat<f64>, rows: &[usize]) {
    for &row in rows {
        for j in 0..m.ncols() {
            m[(row, j)] = 0.0;
        }
    }
}

/// The smallest Ritz values of the pencil `(K, G)` over the range of `G`, ascending, with
/// their coefficient vectors (columns, in the `k`-dimensional space of `K`); empty if `G`
/// vanishes.
pub(super) fn ritz(k: MatRef<'_, f64>, g: MatRef<'_, f64>) -> (Vec<f64>, Mat<f64>) {
    let n = g.nrows();
    let none = (Vec::new(), Mat::<f64>::zeros(n, 0));
    let sym = |m: MatRef<'_, f64>| Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (m[(i, j)] + m[(j, i)]));
    let Ok(eg) = sym(g).self_adjoint_eigen(faer::Side::Lower) else {
        return none;
    };
    let s = eg.S();
    let gmax = (0..n).map(|i| s[i]).fold(0.0, f64::max);
    let keep: Vec<usize> = (0..n)
        .filter(|&i| s[i] > 1e-8 * gmax.max(1e-300) && s[i] > 0.0)
        .collect();
    if keep.is_empty() {
        return none;
    }
    let u = eg.U();
    let b = Mat::<f64>::from_fn(n, keep.len(), |i, j| u[(i, keep[j])] / s[keep[j]].sqrt());
    let m = b.transpose() * sym(k).as_ref() * b.as_ref();
    let r = keep.len();
    let m = Mat::<f64>::from_fn(r, r, |i, j| 0.5 * (m[(i, j)] + m[(j, i)]));
    let Ok(em) = m.self_adjoint_eigen(faer::Side::Lower) else {
        return none;
    };
    let values = (0..r).map(|i| em.S()[i]).collect();
    (values, b * em.U())
}
