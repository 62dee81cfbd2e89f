//! The three local energy terms of a discrete elastic rod without twist (`docs/model.md`,
//! *Energy*), each with its exact gradient and Hessian, and the bending term of a pre-bent rod
//! ([`bend_rest`], bending measured from the drawn shape; its doc explains the form chosen),
//! and the physical mode's clamp ([`clamp`], a bending term against a mirrored ghost edge).
//!
//! Every term acts on a few vertices; the result is a [`Local`] value with the energy, the
//! gradient over the term's `D = 3·(vertex count)` coordinates (vertex-major: `x0.x, x0.y, x0.z,
//! x1.x, …`) and the full dense `D×D` Hessian. Nothing is projected to be positive definite: the
//! stability analysis needs the true Hessian.

use crate::geom::Vec3;

pub use super::clamp::{
    ClampRest, clamp, clamp_energy, clamp_energy_grad, clamp_rest, clamp_strain, end_tangent,
};
pub use super::prebent::{
    RestBend, bend_rest, bend_rest_energy, bend_rest_energy_grad, bend_strain, rest_bend,
};

/// Energy, gradient and Hessian of one term over its `D` coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Local<const D: usize> {
    /// Energy value.
    pub energy: f64,
    /// Gradient, vertex-major.
    pub grad: [f64; D],
    /// Hessian, row-major and symmetric.
    pub hess: [[f64; D]; D],
}

impl<const D: usize> Local<D> {
    pub(crate) fn zero() -> Self {
        Local {
            energy: 0.0,
            grad: [0.0; D],
            hess: [[0.0; D]; D],
        }
    }
}

/// A symmetric 3×3 block helper: `s·I + Σ c_k a_k b_kᵀ` assembled explicitly.
type M3 = [[f64; 3]; 3];

#[inline]
fn outer(a: Vec3, b: Vec3) -> M3 {
    [
        [a.x * b.x, a.x * b.y, a.x * b.z],
        [a.y * b.x, a.y * b.y, a.y * b.z],
        [a.z * b.x, a.z * b.y, a.z * b.z],
    ]
}

#[inline]
fn m3_axpy(acc: &mut M3, s: f64, m: &M3) {
    for i in 0..3 {
        for j in 0..3 {
            acc[i][j] += s * m[i][j];
        }
    }
}

#[inline]
fn m3_add_identity(acc: &mut M3, s: f64) {
    for (i, row) in acc.iter_mut().enumerate() {
        row[i] += s;
    }
}

/// Stretching energy of one edge `e = x1 − x0` with rest length `rest` and stretching stiffness
/// `ks`: `E = ½ k_s (|e|/ē − 1)² ē`.
#[inline]
pub fn stretch_energy(x0: Vec3, x1: Vec3, rest: f64, ks: f64) -> f64 {
    let l = (x1 - x0).norm();
    let strain = (l - rest) / rest;
    0.5 * ks * strain * strain * rest
}

/// [`stretch_energy`] with its gradient and Hessian over `(x0, x1)`.
pub fn stretch(x0: Vec3, x1: Vec3, rest: f64, ks: f64) -> Local<6> {
    let e = x1 - x0;
    let l = e.norm();
    let strain = (l - rest) / rest;
    let mut out = Local::<6>::zero();
    out.energy = 0.5 * ks * strain * strain * rest;
    if l == 0.0 {
        // Fully collapsed edge: the direction is undefined. The energy is ½k_s ē and the
        // gradient vanishes by symmetry; the Hessian's isotropic part is −k_s/l·(…) which
        // diverges. Report a zero gradient and the axial stiffness in every direction, a
        // finite stand-in that keeps Newton going (it never happens at an equilibrium).
        let k = ks / rest;
        for a in 0..3 {
            out.hess[a][a] = k;
            out.hess[a + 3][a + 3] = k;
            out.hess[a][a + 3] = -k;
            out.hess[a + 3][a] = -k;
        }
        return out;
    }
    let t = e / l;
    let g = t * (ks * strain);
    for a in 0..3 {
        out.grad[a] = -g[a];
        out.grad[a + 3] = g[a];
    }
    // d²E/de² = (k_s/ē) t tᵀ + k_s (strain/l) (I − t tᵀ)
    let iso = ks * strain / l;
    let mut k = outer(t, t);
    for row in k.iter_mut() {
        for v in row.iter_mut() {
            *v *= ks / rest - iso;
        }
    }
    m3_add_identity(&mut k, iso);
    for a in 0..3 {
        for b in 0..3 {
            out.hess[a][b] = k[a][b];
            out.hess[a + 3][b + 3] = k[a][b];
            out.hess[a][b + 3] = -k[a][b];
            out.hess[a + 3][b] = -k[a][b];
        }
    }
    out
}

/// Bending energy at the vertex `x1` between edges `u = x1 − x0` and `w = x2 − x1` with rest
/// lengths `r0`, `r1` and bending stiffness `kb`:
/// `κb = 2 (u × w) / (ē₀ ē₁ + u·w)`, `E = k_b |κb|² / (ē₀ + ē₁)` (rest curvature 0).
#[inline]
pub fn bend_energy(x0: Vec3, x1: Vec3, x2: Vec3, r0: f64, r1: f64, kb: f64) -> f64 {
    let u = x1 - x0;
    let w = x2 - x1;
    let c = 4.0 * kb / (r0 + r1);
    let g = r0 * r1 + u.dot(w);
    c * u.cross(w).norm2() / (g * g)
}

/// The bending term's energy, gradient and the quantities its Hessian reuses.
struct BendFirst {
    u: Vec3,
    w: Vec3,
    c: f64,
    uw: f64,
    f: f64,
    ig: f64,
    ig2: f64,
    fu: Vec3,
    fw: Vec3,
    energy: f64,
    grad: [f64; 9],
}

/// The first half of [`bend`], shared with [`bend_energy_grad`] (so both give the same
/// gradient, bit for bit).
#[inline(always)]
fn bend_first(x0: Vec3, x1: Vec3, x2: Vec3, r0: f64, r1: f64, kb: f64) -> BendFirst {
    let u = x1 - x0;
    let w = x2 - x1;
    let c = 4.0 * kb / (r0 + r1);
    let uw = u.dot(w);
    let g = r0 * r1 + uw;
    let cr = u.cross(w);
    let f = cr.norm2();
    let ig = 1.0 / g;
    let ig2 = ig * ig;
    let energy = c * f * ig2;

    // First derivatives in (u, w).
    let fu = w.cross(cr) * 2.0;
    let fw = cr.cross(u) * 2.0;
    // ∂G/∂u = w, ∂G/∂w = u.
    // ∂E = c (∂F/G² − 2F ∂G/G³)
    let eu = (fu * ig2 - w * (2.0 * f * ig2 * ig)) * c;
    let ew = (fw * ig2 - u * (2.0 * f * ig2 * ig)) * c;
    // Map to vertices: x0 → −u, x1 → +u −w, x2 → +w.
    let mut grad = [0.0; 9];
    for a in 0..3 {
        grad[a] = -eu[a];
        grad[3 + a] = eu[a] - ew[a];
        grad[6 + a] = ew[a];
    }
    BendFirst {
        u,
        w,
        c,
        uw,
        f,
        ig,
        ig2,
        fu,
        fw,
        energy,
        grad,
    }
}

/// [`bend`]'s energy and gradient without its Hessian (the same values, bit for bit).
#[inline]
pub fn bend_energy_grad(
    x0: Vec3,
    x1: Vec3,
    x2: Vec3,
    r0: f64,
    r1: f64,
    kb: f64,
) -> (f64, [f64; 9]) {
    let b = bend_first(x0, x1, x2, r0, r1, kb);
    (b.energy, b.grad)
}

/// [`bend_energy`] with its gradient and Hessian over `(x0, x1, x2)`.
///
/// Written as `E = c F / G²` with `F = |u × w|²`, `G = ē₀ē₁ + u·w`, `c = 4k_b/(ē₀+ē₁)`;
/// the derivatives are taken in `(u, w)` and mapped to the vertices by `u = x1 − x0`,
/// `w = x2 − x1`. `∂F/∂u = 2 w × (u × w)` and `∂F/∂w = 2 (u × w) × u` avoid the cancellation
/// of the expanded form near straight configurations.
pub fn bend(x0: Vec3, x1: Vec3, x2: Vec3, r0: f64, r1: f64, kb: f64) -> Local<9> {
    let BendFirst {
        u,
        w,
        c,
        uw,
        f,
        ig,
        ig2,
        fu,
        fw,
        energy,
        grad,
    } = bend_first(x0, x1, x2, r0, r1, kb);
    let mut out = Local::<9>::zero();
    out.energy = energy;
    out.grad = grad;

    // Second derivatives in (u, w):
    // ∂²E = c [ ∂²F/G² − 2/G³ (∂F ⊗ ∂G + ∂G ⊗ ∂F) + 6F/G⁴ ∂G ⊗ ∂G − 2F/G³ ∂²G ]
    // ∂²F/∂u² = 2|w|² I − 2 w wᵀ,   ∂²F/∂w² = 2|u|² I − 2 u uᵀ,
    // ∂²F/∂u∂w = 4 u wᵀ − 2 w uᵀ − 2 (u·w) I,   ∂²G/∂u∂w = I.
    let ig3 = ig2 * ig;
    let ig4 = ig2 * ig2;
    let mut huu: M3 = [[0.0; 3]; 3];
    m3_add_identity(&mut huu, 2.0 * w.norm2() * ig2);
    m3_axpy(&mut huu, -2.0 * ig2, &outer(w, w));
    m3_axpy(&mut huu, -2.0 * ig3, &outer(fu, w));
    m3_axpy(&mut huu, -2.0 * ig3, &outer(w, fu));
    m3_axpy(&mut huu, 6.0 * f * ig4, &outer(w, w));

    let mut hww: M3 = [[0.0; 3]; 3];
    m3_add_identity(&mut hww, 2.0 * u.norm2() * ig2);
    m3_axpy(&mut hww, -2.0 * ig2, &outer(u, u));
    m3_axpy(&mut hww, -2.0 * ig3, &outer(fw, u));
    m3_axpy(&mut hww, -2.0 * ig3, &outer(u, fw));
    m3_axpy(&mut hww, 6.0 * f * ig4, &outer(u, u));

    // huw[i][j] = ∂²E/∂u_i∂w_j
    let mut huw: M3 = [[0.0; 3]; 3];
    m3_axpy(&mut huw, 4.0 * ig2, &outer(u, w));
    m3_axpy(&mut huw, -2.0 * ig2, &outer(w, u));
    m3_add_identity(&mut huw, -2.0 * uw * ig2 - 2.0 * f * ig3);
    m3_axpy(&mut huw, -2.0 * ig3, &outer(fu, u));
    m3_axpy(&mut huw, -2.0 * ig3, &outer(w, fw));
    m3_axpy(&mut huw, 6.0 * f * ig4, &outer(w, u));

    // Map to vertices: x0 → −u, x1 → +u −w, x2 → +w.
    // Hessian blocks: H_pq = Σ J_p^s J_q^t H_st with J_0 = (−1, 0), J_1 = (1, −1), J_2 = (0, 1)
    // over s, t ∈ {u, w}.
    const J: [[f64; 2]; 3] = [[-1.0, 0.0], [1.0, -1.0], [0.0, 1.0]];
    for p in 0..3 {
        for q in 0..3 {
            let (a_uu, a_uw, a_wu, a_ww) = (
                J[p][0] * J[q][0],
                J[p][0] * J[q][1],
                J[p][1] * J[q][0],
                J[p][1] * J[q][1],
            );
            for i in 0..3 {
                for j in 0..3 {
                    out.hess[3 * p + i][3 * q + j] = c
                        * (a_uu * huu[i][j]
                            + a_uw * huw[i][j]
                            + a_wu * huw[j][i]
                            + a_ww * hww[i][j]);
                }
            }
        }
    }
    // Floating-point sums above run in different orders for (i, j) and (j, i).
    symmetrize(&mut out.hess);
    out
}

/// Makes `h` exactly symmetric: each pair of entries becomes their mean.
pub(crate) fn symmetrize<const D: usize>(h: &mut [[f64; D]; D]) {
    for i in 0..D {
        for j in 0..i {
            let m = 0.5 * (h[i][j] + h[j][i]);
            h[i][j] = m;
            h[j][i] = m;
        }
    }
}

/// Anchor spring energy `E = µ (x − x̄)ᵀ W (x − x̄)` pulling a supported vertex to its target
/// along the directions it fixes: `W = Σ d dᵀ` over their unit vectors (diagonal, 1 for a fixed
/// world axis and 0 for a free one, when only world axes are fixed; a support along the
/// surface's directions adds their outer products).
#[inline]
pub fn anchor_energy(x: Vec3, target: Vec3, mu: f64, w: &[[f64; 3]; 3]) -> f64 {
    let d = x - target;
    mu * (0..3)
        .map(|a| (0..3).map(|b| w[a][b] * d[b]).sum::<f64>() * d[a])
        .sum::<f64>()
}

/// [`anchor_energy`] with its gradient `2µ W (x − x̄)` and Hessian `2µ W`.
pub fn anchor(x: Vec3, target: Vec3, mu: f64, w: &[[f64; 3]; 3]) -> Local<3> {
    let d = x - target;
    let mut out = Local::<3>::zero();
    out.energy = anchor_energy(x, target, mu, w);
    for a in 0..3 {
        out.grad[a] = (0..3).map(|b| 2.0 * mu * w[a][b] * d[b]).sum::<f64>();
        for b in 0..3 {
            out.hess[a][b] = 2.0 * mu * w[a][b];
        }
    }
    out
}

/// Projects a symmetric matrix onto the positive semidefinite cone in place: eigenvalues
/// below zero are set to zero. Newton uses projected Hessians for its direction far from
/// equilibrium, where the exact Hessian is indefinite; the stability analysis always uses the
/// exact one.
///
/// A 6×6 matrix whose coordinates are all coupled (a bent rod's reduced bending block: the
/// projections' bulk) is decomposed by nalgebra's symmetric eigen-solver, twice as fast as
/// Jacobi sweeps at this size. Any other, and a 6×6 one that falls apart into groups of
/// coordinates with exactly zero coupling (a straight or planar rod), goes through cyclic
/// Jacobi sweeps: their rotations leave exact zeros where they are, so such a rod's Newton
/// steps stay exactly straight or planar, where Householder reflections would leave round-off
/// that a compressed rod's negative modes then amplify.
pub fn project_psd<const D: usize>(h: &mut [[f64; D]; D]) {
    project_psd_changed(h);
}

/// [`project_psd`], telling whether the matrix changed (false: it was left as it was, also
/// when it holds a NaN or an infinity).
fn project_psd_changed<const D: usize>(h: &mut [[f64; D]; D]) -> bool {
    if D == 6 && coupled(h) {
        let (rows, _) = h.as_flattened_mut().as_chunks_mut::<6>();
        if let Ok(h6) = <&mut [[f64; 6]; 6]>::try_from(rows) {
            return project_psd_coupled6(h6);
        }
    }
    project_psd_jacobi(h)
}

/// Whether every coordinate of `h` is linked to every other by a chain of nonzero entries
/// (the matrix does not fall apart into independent diagonal blocks under any permutation).
fn coupled<const D: usize>(h: &[[f64; D]; D]) -> bool {
    debug_assert!(D < 64);
    let all = (1u64 << D) - 1;
    let (mut reached, mut frontier) = (1u64, 1u64);
    while frontier != 0 {
        let i = frontier.trailing_zeros() as usize;
        frontier &= frontier - 1;
        for (j, &x) in h[i].iter().enumerate() {
            if x != 0.0 && reached & (1 << j) == 0 {
                reached |= 1 << j;
                frontier |= 1 << j;
            }
        }
    }
    reached == all
}

/// The eigen-solver's iteration cap: far more than a symmetric 6×6 matrix needs; reaching it
/// leaves the matrix as it was.
const MAX_EIGEN_ITERATIONS: usize = 1000;

/// [`project_psd_changed`] of a 6×6 matrix by nalgebra's symmetric eigen-decomposition
/// (Householder tridiagonalization and implicit QR, on the stack).
fn project_psd_coupled6(h: &mut [[f64; 6]; 6]) -> bool {
    if !h.iter().flatten().all(|x| x.is_finite()) {
        return false;
    }
    let m = nalgebra::Matrix6::from_fn(|i, j| h[i][j]);
    let Some(eig) = nalgebra::SymmetricEigen::try_new(m, f64::EPSILON, MAX_EIGEN_ITERATIONS) else {
        return false;
    };
    let (l, v) = (&eig.eigenvalues, &eig.eigenvectors);
    if l.iter().all(|&x| x >= 0.0) {
        return false;
    }
    keep_positive_part(h, |k| l[k], |i, k| v[(i, k)]);
    true
}

/// Sets `h = V diag(max(λ, 0)) Vᵀ` from the eigenvalues `lambda(k)` and the eigenvectors'
/// components `v(i, k)` (the `i`-th of the `k`-th).
fn keep_positive_part<const D: usize>(
    h: &mut [[f64; D]; D],
    lambda: impl Fn(usize) -> f64,
    v: impl Fn(usize, usize) -> f64,
) {
    for i in 0..D {
        for j in 0..=i {
            let mut sum = 0.0;
            for k in 0..D {
                let l = lambda(k);
                if l > 0.0 {
                    sum += v(i, k) * l * v(j, k);
                }
            }
            h[i][j] = sum;
            h[j][i] = sum;
        }
    }
}

/// [`project_psd_changed`] by cyclic Jacobi sweeps (hand-written: they keep exact zeros,
/// which no library's small symmetric eigen-solver promises).
fn project_psd_jacobi<const D: usize>(h: &mut [[f64; D]; D]) -> bool {
    let mut a = *h;
    let mut v = [[0.0f64; D]; D];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    let scale: f64 = a.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    if scale == 0.0 || !scale.is_finite() {
        return false;
    }
    for _sweep in 0..50 {
        let off: f64 = (0..D)
            .flat_map(|i| (0..D).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum();
        if off.sqrt() <= 1e-15 * scale {
            break;
        }
        for p in 0..D {
            for q in p + 1..D {
                if a[p][q].abs() <= 1e-300 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..D {
                    let (akp, akq) = (a[k][p], a[k][q]);
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for k in 0..D {
                    let (apk, aqk) = (a[p][k], a[q][k]);
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for row in v.iter_mut() {
                    let (vkp, vkq) = (row[p], row[q]);
                    row[p] = c * vkp - s * vkq;
                    row[q] = s * vkp + c * vkq;
                }
            }
        }
    }
    if (0..D).all(|i| a[i][i] >= 0.0) {
        return false;
    }
    keep_positive_part(h, |k| a[k][k], |i, k| v[i][k]);
    true
}

/// [`project_psd`] of a translation-invariant term's Hessian over `D = 3·m` coordinates
/// (`m` vertices): such a Hessian vanishes on the three translations, so it equals
/// `Qᵀ(QHQᵀ)Q` for the `M = D − 3` orthonormal rows `q` of `Q` spanning their complement,
/// and its projection is `Qᵀ proj(QHQᵀ) Q` — an `M×M` eigen-decomposition instead of a
/// `D×D` one (bending: 6×6 instead of 9×9, about four times less work; stretching: 3×3
/// instead of 6×6). The same projection in exact arithmetic; the translations stay exactly
/// in the null space, and a Hessian positive semidefinite on the complement is left as it
/// is.
fn project_psd_reduced<const D: usize, const M: usize>(h: &mut [[f64; D]; D], q: &[[f64; D]; M]) {
    // B = Q H Qᵀ.
    let mut hq = [[0.0; M]; D];
    for (i, row) in h.iter().enumerate() {
        for (b, qb) in q.iter().enumerate() {
            hq[i][b] = row.iter().zip(qb).map(|(x, y)| x * y).sum();
        }
    }
    let mut bm = [[0.0; M]; M];
    for a in 0..M {
        for b in 0..=a {
            let v: f64 = (0..D).map(|i| q[a][i] * hq[i][b]).sum();
            bm[a][b] = v;
            bm[b][a] = v;
        }
    }
    if !project_psd_changed(&mut bm) {
        return;
    }
    // H = Qᵀ B Q.
    let mut bq = [[0.0; D]; M];
    for a in 0..M {
        for i in 0..D {
            bq[a][i] = (0..M).map(|b| bm[a][b] * q[b][i]).sum();
        }
    }
    for i in 0..D {
        for j in 0..=i {
            let v: f64 = (0..M).map(|a| q[a][i] * bq[a][j]).sum();
            h[i][j] = v;
            h[j][i] = v;
        }
    }
}

/// Orthonormal rows spanning the complement of the translations of two vertices.
const STRETCH_Q: [[f64; 6]; 3] = {
    let r = std::f64::consts::FRAC_1_SQRT_2;
    [
        [-r, 0.0, 0.0, r, 0.0, 0.0],
        [0.0, -r, 0.0, 0.0, r, 0.0],
        [0.0, 0.0, -r, 0.0, 0.0, r],
    ]
};

/// Orthonormal rows spanning the complement of the translations of three vertices:
/// `(−1, 0, 1)/√2` and `(1, −2, 1)/√6` per axis.
const BEND_Q: [[f64; 9]; 6] = {
    let r = std::f64::consts::FRAC_1_SQRT_2;
    // 1/√6 and 2/√6.
    let s = 0.408_248_290_463_863;
    let t = 0.816_496_580_927_726_1;
    [
        [-r, 0.0, 0.0, 0.0, 0.0, 0.0, r, 0.0, 0.0],
        [0.0, -r, 0.0, 0.0, 0.0, 0.0, 0.0, r, 0.0],
        [0.0, 0.0, -r, 0.0, 0.0, 0.0, 0.0, 0.0, r],
        [s, 0.0, 0.0, -t, 0.0, 0.0, s, 0.0, 0.0],
        [0.0, s, 0.0, 0.0, -t, 0.0, 0.0, s, 0.0],
        [0.0, 0.0, s, 0.0, 0.0, -t, 0.0, 0.0, s],
    ]
};

/// [`project_psd`] of a stretching Hessian ([`stretch`]), through its 3×3 block off the
/// translations.
pub fn project_psd_stretch(h: &mut [[f64; 6]; 6]) {
    project_psd_reduced(h, &STRETCH_Q);
}

/// [`project_psd`] of a bending Hessian ([`bend`]), through its 6×6 block off the
/// translations.
pub fn project_psd_bend(h: &mut [[f64; 9]; 9]) {
    project_psd_reduced(h, &BEND_Q);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    /// Checks gradient and Hessian of `f` against central differences at `x` (D coordinates).
    fn check_fd<const D: usize>(
        x: [f64; D],
        eval: impl Fn(&[f64; D]) -> Local<D>,
        energy: impl Fn(&[f64; D]) -> f64,
    ) {
        let l = eval(&x);
        assert!((l.energy - energy(&x)).abs() <= 1e-12 * l.energy.abs().max(1e-300));
        let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1.0);
        let h = 1e-5 * scale;
        let gnorm = l.grad.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let hnorm = l.hess.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        for k in 0..D {
            let mut xp = x;
            let mut xm = x;
            xp[k] += h;
            xm[k] -= h;
            let fd_g = (energy(&xp) - energy(&xm)) / (2.0 * h);
            assert!(
                (fd_g - l.grad[k]).abs() <= 1e-6 * gnorm.max(1e-12) + 1e-9 * l.energy.abs(),
                "grad[{k}]: analytic {} fd {}",
                l.grad[k],
                fd_g
            );
            let gp = eval(&xp).grad;
            let gm = eval(&xm).grad;
            for j in 0..D {
                let fd_h = (gp[j] - gm[j]) / (2.0 * h);
                assert!(
                    (fd_h - l.hess[j][k]).abs() <= 1e-6 * hnorm.max(1e-12),
                    "hess[{j}][{k}]: analytic {} fd {}",
                    l.hess[j][k],
                    fd_h
                );
            }
        }
        for i in 0..D {
            for j in 0..D {
                assert_eq!(
                    l.hess[i][j], l.hess[j][i],
                    "Hessian not symmetric at ({i},{j})"
                );
            }
        }
    }

    fn split<const D: usize>(x: &[f64; D], k: usize) -> Vec3 {
        Vec3::new(x[3 * k], x[3 * k + 1], x[3 * k + 2])
    }

    #[test]
    fn stretch_derivatives_match_finite_differences() {
        let mut rng = SplitMix64::new(7);
        for _ in 0..50 {
            let a = rng.vec3();
            let b = a + rng.vec3();
            let rest = 0.5 + rng.signed().abs();
            let ks = 4.0 * std::f64::consts::PI;
            let x = [a.x, a.y, a.z, b.x, b.y, b.z];
            check_fd(
                x,
                |x| stretch(split(x, 0), split(x, 1), rest, ks),
                |x| stretch_energy(split(x, 0), split(x, 1), rest, ks),
            );
        }
    }

    #[test]
    fn bend_derivatives_match_finite_differences() {
        let mut rng = SplitMix64::new(11);
        for i in 0..100 {
            let a = rng.vec3();
            // Mix of strongly bent and nearly straight configurations.
            let d = rng.vec3() + Vec3::new(1.5, 0.0, 0.0);
            let bend_amount = if i % 2 == 0 { 1.0 } else { 1e-3 };
            let b = a + d;
            let c = b + d + rng.vec3() * bend_amount;
            let (r0, r1) = (0.7 + rng.signed().abs(), 0.7 + rng.signed().abs());
            let kb = 4.0 * std::f64::consts::PI;
            let x = [a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z];
            check_fd(
                x,
                |x| bend(split(x, 0), split(x, 1), split(x, 2), r0, r1, kb),
                |x| bend_energy(split(x, 0), split(x, 1), split(x, 2), r0, r1, kb),
            );
        }
    }

    /// `Σ d dᵀ` over `dirs` (each normalised).
    fn weights(dirs: &[Vec3]) -> [[f64; 3]; 3] {
        let mut w = [[0.0; 3]; 3];
        for d in dirs {
            let d = d.normalized();
            for a in 0..3 {
                for b in 0..3 {
                    w[a][b] += d[a] * d[b];
                }
            }
        }
        w
    }

    #[test]
    fn anchor_derivatives_match_finite_differences() {
        let mut rng = SplitMix64::new(3);
        let t = rng.vec3();
        let a = rng.vec3();
        let diag = |v: [f64; 3]| [[v[0], 0.0, 0.0], [0.0, v[1], 0.0], [0.0, 0.0, v[2]]];
        let skew = weights(&[rng.vec3(), rng.vec3()]);
        for w in [
            diag([1.0; 3]),
            diag([0.0, 1.0, 1.0]),
            diag([1.0, 0.0, 0.0]),
            skew,
        ] {
            check_fd(
                [a.x, a.y, a.z],
                |x| anchor(split(x, 0), t, 500.0, &w),
                |x| anchor_energy(split(x, 0), t, 500.0, &w),
            );
        }
    }

    #[test]
    fn a_skew_anchor_penalises_only_its_directions_and_turns_with_them() {
        let mut rng = SplitMix64::new(11);
        let (d1, d2) = (rng.vec3().normalized(), rng.vec3());
        let d2 = (d2 - d1 * d1.dot(d2)).normalized();
        let free = d1.cross(d2);
        let w = weights(&[d1, d2]);
        let t = rng.vec3();
        // Sliding along the free direction costs nothing; along a held one, µ s².
        assert!(anchor_energy(t + free * 3.0, t, 7.0, &w).abs() < 1e-12);
        assert!((anchor_energy(t + d2 * 3.0, t, 7.0, &w) - 63.0).abs() < 1e-10);
        // A rigid motion of the vertex, its target and the directions keeps the energy and
        // turns the gradient.
        let (axis, angle) = (rng.vec3().normalized(), 1.234_f64);
        let rot = |v: Vec3| {
            v * angle.cos() + axis.cross(v) * angle.sin() + axis * axis.dot(v) * (1.0 - angle.cos())
        };
        let shift = rng.vec3() * 10.0;
        let x = rng.vec3();
        let moved = weights(&[rot(d1), rot(d2)]);
        let l0 = anchor(x, t, 7.0, &w);
        let l1 = anchor(rot(x) + shift, rot(t) + shift, 7.0, &moved);
        assert!((l0.energy - l1.energy).abs() <= 1e-12 * l0.energy.abs());
        let g0 = rot(Vec3::new(l0.grad[0], l0.grad[1], l0.grad[2]));
        for a in 0..3 {
            assert!((g0[a] - l1.grad[a]).abs() <= 1e-12 * l0.energy.abs().max(1.0));
        }
    }

    #[test]
    fn bend_energy_is_curvature_squared_for_small_angles() {
        // A circle arc of radius R sampled with step s: turning angle φ = s/R per vertex;
        // (k_b/2)∫κ² ds over one dual length s gives k_b s / (2R²).
        let (r, s, kb) = (50.0, 0.5, 3.0);
        let phi = s / r;
        let p = |k: f64| Vec3::new(r * (k * phi).cos(), r * (k * phi).sin(), 0.0);
        let chord = p(0.0).dist(p(1.0));
        let e = bend_energy(p(0.0), p(1.0), p(2.0), chord, chord, kb);
        let expected = kb * chord / (2.0 * r * r);
        assert!((e / expected - 1.0).abs() < 1e-3, "{e} vs {expected}");
    }

    #[test]
    fn terms_are_invariant_under_rigid_motion() {
        let mut rng = SplitMix64::new(5);
        let (a, b, c) = (rng.vec3(), rng.vec3(), rng.vec3());
        let rot = |v: Vec3| {
            // rotation by 0.7 rad about z then 0.3 rad about x, plus a translation
            let (s1, c1) = 0.7f64.sin_cos();
            let (s2, c2) = 0.3f64.sin_cos();
            let v = Vec3::new(c1 * v.x - s1 * v.y, s1 * v.x + c1 * v.y, v.z);
            Vec3::new(v.x, c2 * v.y - s2 * v.z, s2 * v.y + c2 * v.z) + Vec3::new(3.0, -2.0, 1.0)
        };
        let e0 = bend_energy(a, b, c, 1.1, 0.9, 2.0);
        let e1 = bend_energy(rot(a), rot(b), rot(c), 1.1, 0.9, 2.0);
        assert!((e0 - e1).abs() < 1e-12 * e0);
        let s0 = stretch_energy(a, b, 0.8, 2.0);
        let s1 = stretch_energy(rot(a), rot(b), 0.8, 2.0);
        assert!((s0 - s1).abs() < 1e-12 * s0);
        // The gradient of a translation-invariant term sums to zero.
        let l = bend(a, b, c, 1.1, 0.9, 2.0);
        for k in 0..3 {
            let sum = l.grad[k] + l.grad[3 + k] + l.grad[6 + k];
            assert!(sum.abs() < 1e-12 * l.grad.iter().fold(0.0f64, |m, v| m.max(v.abs())));
        }
    }

    /// A symmetric matrix with entries uniform in [−1, 1].
    fn random_symmetric<const D: usize>(rng: &mut SplitMix64) -> [[f64; D]; D] {
        let mut m = [[0.0; D]; D];
        for i in 0..D {
            for j in 0..=i {
                let v = rng.signed();
                m[i][j] = v;
                m[j][i] = v;
            }
        }
        m
    }

    #[test]
    fn psd_projection_clamps_negative_eigenvalues_only() {
        let mut rng = SplitMix64::new(21);
        for _ in 0..50 {
            let mut m = random_symmetric::<9>(&mut rng);
            let orig = m;
            project_psd(&mut m);
            // PSD: xᵀMx ≥ 0 for random x, and the projection is the nearest PSD matrix, so
            // M_proj − M is PSD too (it adds back the negative part).
            for _ in 0..20 {
                let x: Vec<f64> = (0..9).map(|_| rng.signed()).collect();
                let q: f64 = (0..9)
                    .flat_map(|i| (0..9).map(move |j| (i, j)))
                    .map(|(i, j)| x[i] * m[i][j] * x[j])
                    .sum();
                let d: f64 = (0..9)
                    .flat_map(|i| (0..9).map(move |j| (i, j)))
                    .map(|(i, j)| x[i] * (m[i][j] - orig[i][j]) * x[j])
                    .sum();
                assert!(q >= -1e-12 && d >= -1e-12, "q {q} d {d}");
            }
        }
        // A PSD matrix is left as it is.
        let mut a = [[0.0; 3]; 3];
        a[0][0] = 2.0;
        a[1][1] = 1.0;
        a[0][1] = 0.5;
        a[1][0] = 0.5;
        let before = a;
        project_psd(&mut a);
        assert_eq!(a, before);
    }

    /// Frobenius distance between two matrices, relative to the first's norm.
    fn rel_dist<const D: usize>(a: &[[f64; D]; D], b: &[[f64; D]; D]) -> f64 {
        let d: f64 = a
            .iter()
            .flatten()
            .zip(b.iter().flatten())
            .map(|(x, y)| (x - y) * (x - y))
            .sum();
        let n: f64 = a.iter().flatten().map(|x| x * x).sum();
        (d / n.max(f64::MIN_POSITIVE)).sqrt()
    }

    /// `reduce(h)`, checked against the full projection of `h`.
    fn same_projection<const D: usize>(
        h: [[f64; D]; D],
        reduce: fn(&mut [[f64; D]; D]),
        what: &str,
    ) -> [[f64; D]; D] {
        let (mut full, mut reduced) = (h, h);
        project_psd(&mut full);
        reduce(&mut reduced);
        let d = rel_dist(&full, &reduced);
        assert!(d < 1e-10, "{what}: {d}");
        reduced
    }

    #[test]
    fn reduced_projections_match_the_full_one() {
        // Bent and compressed or stretched configurations: the terms' Hessians are
        // indefinite, and the projection off the translations is the same matrix as the
        // full 9×9 (6×6) one.
        let mut rng = SplitMix64::new(77);
        let (mut bent, mut compressed) = (0, 0);
        for _ in 0..200 {
            let (a, b, c) = (rng.vec3(), rng.vec3(), rng.vec3());
            let (r0, r1) = (0.5 + rng.signed().abs(), 0.5 + rng.signed().abs());
            let h = bend(a, b, c, r0, r1, 1.3).hess;
            let reduced = same_projection(h, project_psd_bend, "bend");
            bent += usize::from(reduced != h);
            // The projection keeps the translations in the null space.
            let scale = reduced.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
            for row in &reduced {
                for axis in 0..3 {
                    let t: f64 = (0..3).map(|v| row[3 * v + axis]).sum();
                    assert!(t.abs() <= 1e-12 * scale, "translation {t}");
                }
            }
            let rest = 0.2 + 2.0 * rng.signed().abs();
            let h = stretch(a, b, rest, 2.5).hess;
            let reduced = same_projection(h, project_psd_stretch, "stretch");
            compressed += usize::from(reduced != h);
        }
        // Both kinds of term were indefinite often enough to test something.
        assert!(
            bent > 20 && compressed > 20,
            "bent {bent}, compressed {compressed}"
        );
        // A stretched edge (positive semidefinite Hessian) is left as it is.
        let h = stretch(Vec3::ZERO, Vec3::new(1.5, 0.0, 0.0), 1.0, 1.0).hess;
        let mut p = h;
        project_psd_stretch(&mut p);
        assert_eq!(p, h);
    }

    #[test]
    fn both_eigen_solvers_give_the_same_projection() {
        // Random symmetric 6×6 matrices (coupled): nalgebra's path against the Jacobi sweeps.
        let mut rng = SplitMix64::new(8);
        let mut changed = 0;
        for _ in 0..200 {
            let m = random_symmetric::<6>(&mut rng);
            assert!(coupled(&m));
            let (mut fast, mut jacobi) = (m, m);
            let a = project_psd_coupled6(&mut fast);
            let b = project_psd_jacobi(&mut jacobi);
            assert_eq!(a, b);
            changed += usize::from(a);
            let d = rel_dist(&jacobi, &fast);
            assert!(d < 1e-12, "{d}");
        }
        assert!(changed > 100, "{changed}");
    }

    #[test]
    fn projections_keep_exact_zeros_of_straight_and_planar_rods() {
        // A bent rod in the xy-plane: its Hessian does not couple z to x or y, and its
        // projection must not either (the rod's Newton steps stay in its plane).
        let mut rng = SplitMix64::new(3);
        let flat = |v: Vec3| Vec3::new(v.x, v.y, 0.0);
        let mut changed = 0;
        for _ in 0..50 {
            let (a, b, c) = (flat(rng.vec3()), flat(rng.vec3()), flat(rng.vec3()));
            let exact = bend(a, b, c, 0.9, 1.1, 1.3).hess;
            let mut h = exact;
            project_psd_bend(&mut h);
            changed += usize::from(h != exact);
            for i in 0..9 {
                for j in 0..9 {
                    if (i % 3 == 2) != (j % 3 == 2) {
                        assert_eq!(h[i][j], 0.0, "({i}, {j})");
                    }
                }
            }
        }
        assert!(changed > 10, "{changed}");
        // A compressed straight edge along x (indefinite: it would buckle sideways): no
        // coupling between the three axes, before or after.
        let exact = stretch(Vec3::ZERO, Vec3::new(0.8, 0.0, 0.0), 1.0, 1.0).hess;
        let mut s = exact;
        project_psd_stretch(&mut s);
        assert_ne!(s, exact);
        for i in 0..6 {
            for j in 0..6 {
                if i % 3 != j % 3 {
                    assert_eq!(s[i][j], 0.0, "({i}, {j})");
                }
            }
        }
    }

    #[test]
    fn bend_gradient_alone_is_the_full_terms_bit_for_bit() {
        let mut rng = SplitMix64::new(5);
        for _ in 0..100 {
            let (a, b, c) = (rng.vec3(), rng.vec3(), rng.vec3());
            let (r0, r1) = (0.5 + rng.signed().abs(), 0.5 + rng.signed().abs());
            let full = bend(a, b, c, r0, r1, 1.7);
            let (energy, grad) = bend_energy_grad(a, b, c, r0, r1, 1.7);
            assert_eq!(energy.to_bits(), full.energy.to_bits());
            assert_eq!(grad.map(f64::to_bits), full.grad.map(f64::to_bits));
        }
    }

    #[test]
    fn straight_unstretched_rod_has_zero_energy_and_gradient() {
        let (a, b, c) = (
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.5, 0.0, 0.0),
        );
        let l = bend(a, b, c, 1.0, 1.5, 1.0);
        assert_eq!(l.energy, 0.0);
        assert!(l.grad.iter().all(|g| *g == 0.0));
        let s = stretch(a, b, 1.0, 1.0);
        assert_eq!(s.energy, 0.0);
        // Axial stiffness k_s/ē along the edge.
        assert!((s.hess[3][3] - 1.0).abs() < 1e-15);
        assert!(s.hess[4][4].abs() < 1e-15);
    }
}
