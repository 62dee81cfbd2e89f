//! The bending term of a pre-bent rod without twist unknowns: bending measured from the drawn
//! shape, with its exact gradient and Hessian ([`bend_rest`], whose doc explains the form
//! chosen). Re-exported by [`super::terms`] beside the paper's straight-rest term.
//!
//! It holds each cross-section's spin about the rod's axis in the world, so a rigid rotation
//! of the rod costs energy: the physical analysis uses the material frame and twist
//! unknowns of `rod::frame` instead ([`crate::rod::ModelRules::PHYSICAL`]), and so do the
//! searches' frequency objective; this term remains for models without twist unknowns
//! ([`crate::rod::ModelRules::PHYSICAL_WITHOUT_TWIST`], which the tests compare against).

use super::jet::{self, Jet, JetVec};
use super::terms::Local;
use crate::geom::Vec3;

/// The drawn shape of a pre-bent bending term: its curvature binormal `κ̄b` and its unit vertex
/// tangent `t̄` (the normalised sum of the unit edges), from its rest edges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestBend {
    /// Rest curvature binormal `κ̄b = 2 (ū × w̄) / (ē₀ ē₁ + ū·w̄)`.
    pub kappa: Vec3,
    /// Rest vertex tangent `t̄`.
    pub tangent: Vec3,
}

/// The curvature binormal `2 (u × w) / (ē₀ē₁ + u·w)` and the unit vertex tangent
/// `(û + ŵ)/|û + ŵ|` of the edges `u`, `w`, as jets (the same arithmetic for every `N`, so the
/// rest values [`rest_bend`] computes are bit for bit the values at the rest state).
#[inline(always)]
fn kappa_and_tangent<const N: usize>(
    u: &JetVec<N>,
    w: &JetVec<N>,
    r0: f64,
    r1: f64,
) -> (JetVec<N>, JetVec<N>) {
    let g = jet::dot(u, w) + Jet::constant(r0 * r1);
    let kappa = jet::scale(&jet::cross(u, w), g.recip() * 2.0);
    let uhat = jet::scale(u, jet::dot(u, u).sqrt().recip());
    let what = jet::scale(w, jet::dot(w, w).sqrt().recip());
    let n = jet::add(&uhat, &what);
    let t = jet::scale(&n, jet::dot(&n, &n).sqrt().recip());
    (kappa, t)
}

fn constant_vec<const N: usize>(v: Vec3) -> JetVec<N> {
    [Jet::constant(v.x), Jet::constant(v.y), Jet::constant(v.z)]
}

/// The rest curvature and tangent of a bending term whose rest edges are `u = X1 − X0`,
/// `w = X2 − X1` with rest lengths `r0`, `r1`.
pub fn rest_bend(u: Vec3, w: Vec3, r0: f64, r1: f64) -> RestBend {
    let (k, t) = kappa_and_tangent::<0>(&constant_vec(u), &constant_vec(w), r0, r1);
    RestBend {
        kappa: Vec3::new(k[0].v, k[1].v, k[2].v),
        tangent: Vec3::new(t[0].v, t[1].v, t[2].v),
    }
}

/// `κb − R(t̄ → t) κ̄b` with `R(a → b) v = v + k × v + k × (k × v) / (1 + a·b)`, `k = a × b`,
/// the minimal rotation taking `a` to `b` (Rodrigues; exactly `v` when `a = b`, so the
/// residual is exactly zero in the drawn state).
#[inline(always)]
fn rest_residual<const N: usize>(
    u: &JetVec<N>,
    w: &JetVec<N>,
    r0: f64,
    r1: f64,
    rest: &RestBend,
) -> JetVec<N> {
    let (kappa, t) = kappa_and_tangent(u, w, r0, r1);
    let tbar = constant_vec::<N>(rest.tangent);
    let kbar = constant_vec::<N>(rest.kappa);
    let k = jet::cross(&tbar, &t);
    let c = jet::dot(&tbar, &t);
    let kxv = jet::cross(&k, &kbar);
    let kkxv = jet::scale(&jet::cross(&k, &kxv), (c + Jet::constant(1.0)).recip());
    let target = jet::add(&jet::add(&kbar, &kxv), &kkxv);
    jet::sub(&kappa, &target)
}

/// The jets of the edges `u = x1 − x0` (variables 0–2) and `w = x2 − x1` (variables 3–5).
fn edge_jets<const N: usize>(x0: Vec3, x1: Vec3, x2: Vec3) -> (JetVec<N>, JetVec<N>) {
    let (u, w) = (x1 - x0, x2 - x1);
    let var = |v: Vec3, first: usize| -> JetVec<N> {
        if N == 0 {
            constant_vec(v)
        } else {
            [
                Jet::variable(v.x, first),
                Jet::variable(v.y, first + 1),
                Jet::variable(v.z, first + 2),
            ]
        }
    };
    (var(u, 0), var(w, 3))
}

/// The pre-bent bending energy `k_b |κb − R(t̄ → t) κ̄b|² / (ē₀ + ē₁)` at the vertex `x1`
/// between edges `u = x1 − x0` and `w = x2 − x1` (rest lengths `r0`, `r1`, drawn shape
/// `rest`); see [`bend_rest`].
pub fn bend_rest_energy(
    x0: Vec3,
    x1: Vec3,
    x2: Vec3,
    r0: f64,
    r1: f64,
    kb: f64,
    rest: &RestBend,
) -> f64 {
    let (u, w) = edge_jets::<0>(x0, x1, x2);
    let r = rest_residual(&u, &w, r0, r1, rest);
    kb / (r0 + r1) * jet::dot(&r, &r).v
}

/// [`bend_rest`]'s energy and gradient (the same values, bit for bit).
pub fn bend_rest_energy_grad(
    x0: Vec3,
    x1: Vec3,
    x2: Vec3,
    r0: f64,
    r1: f64,
    kb: f64,
    rest: &RestBend,
) -> (f64, [f64; 9]) {
    let l = bend_rest(x0, x1, x2, r0, r1, kb, rest);
    (l.energy, l.grad)
}

/// The bending term of a *pre-bent* rod, with its exact gradient and Hessian over
/// `(x0, x1, x2)`: `E = k_b |κb − R(t̄ → t) κ̄b|² / (ē₀ + ē₁)`.
///
/// `κb` is the paper's curvature binormal, `κ̄b` its value in the drawn state, `t` the
/// vertex's unit tangent (the normalised sum of its unit edges), `t̄` its drawn value, and
/// `R(t̄ → t)` the minimal rotation taking `t̄` to `t`: the drawn curvature is carried along
/// as the rod's tangent turns. With `κ̄b = 0` this is the paper's term
/// ([`super::terms::bend`]); in the drawn state the energy and its gradient are exactly zero
/// (a pre-bent rod is in equilibrium where it was drawn), and the Hessian there is
/// `2 k_b JᵀJ / (ē₀ + ē₁)` with `J` the derivative of the residual: bending in the plane of
/// the drawn curvature and across it both cost `E I κ²` per length, as in a curved beam.
///
/// **Why this form.** A rod without twist has no material frame: its energy sees only the
/// centreline. Any energy of three consecutive points that is invariant under every rotation
/// of the current state is a function of the two edge lengths and the turning angle alone,
/// and so cannot see the *plane* of the bend. For a rod with rest curvature that is fatal:
/// bending it out of its drawn plane keeps every length and turning angle to first order, so
/// a planar pre-bent arc would have a zero mode for every free vertex (a real curved bar
/// resists that motion by bending about its other axis and by torsion, both of which need a
/// frame). A frame built from nearby points fails the same way (it turns with the very bend
/// it should measure), and a frame parallel-transported along the whole rod (the twist-free
/// Bishop frame) couples every vertex of a rod to every other, a dense Hessian. The minimal
/// rotation of the tangent is the local frame that is left: it is invariant under rotations
/// of the whole problem (drawn state and current state together) and under every rotation of
/// the current state about an axis across the tangent, and it holds the rod's spin about its
/// own tangent where it was drawn (as if the supports and joints held the cross-sections'
/// orientation about the rod's axis, i.e. the rod is torsionally stiff). A rigid rotation of
/// the current state by an angle `θ` about the tangent itself costs
/// `2 k_b |κ̄b|² (1 − cos θ) / (ē₀ + ē₁)`. It is singular only where the tangent reverses
/// (`t = −t̄`) or the rod folds back on itself (as the paper's term is).
///
/// The derivatives come from second-order forward-mode jets over `(u, w)` (`rod::jet`),
/// mapped to the vertices by `u = x1 − x0`, `w = x2 − x1`.
pub fn bend_rest(
    x0: Vec3,
    x1: Vec3,
    x2: Vec3,
    r0: f64,
    r1: f64,
    kb: f64,
    rest: &RestBend,
) -> Local<9> {
    let (u, w) = edge_jets::<6>(x0, x1, x2);
    let r = rest_residual(&u, &w, r0, r1, rest);
    let e = jet::dot(&r, &r) * (kb / (r0 + r1));
    let mut out = Local::<9>::zero();
    out.energy = e.v;
    // Map to vertices: x0 → −u, x1 → +u −w, x2 → +w.
    const J: [[f64; 2]; 3] = [[-1.0, 0.0], [1.0, -1.0], [0.0, 1.0]];
    for p in 0..3 {
        for a in 0..3 {
            out.grad[3 * p + a] = J[p][0] * e.g[a] + J[p][1] * e.g[3 + a];
        }
    }
    for p in 0..3 {
        for q in 0..3 {
            for a in 0..3 {
                for b in 0..3 {
                    let mut s = 0.0;
                    for (ss, js) in J[p].iter().enumerate() {
                        for (tt, jt) in J[q].iter().enumerate() {
                            s += js * jt * e.h[3 * ss + a][3 * tt + b];
                        }
                    }
                    out.hess[3 * p + a][3 * q + b] = s;
                }
            }
        }
    }
    // The sums above run in different orders for (i, j) and (j, i).
    crate::rod::terms::symmetrize(&mut out.hess);
    out
}

/// The bending strain vector of a term at `x0, x1, x2`: the curvature binormal `κb` of a rod
/// straight at rest, `κb − R(t̄ → t) κ̄b` of a pre-bent one (the residual [`bend_rest`]
/// squares). Its length times `2 / (ē₀ + ē₁)` is the curvature the material feels.
pub fn bend_strain(
    x0: Vec3,
    x1: Vec3,
    x2: Vec3,
    r0: f64,
    r1: f64,
    rest: Option<&RestBend>,
) -> Vec3 {
    let (u, w) = edge_jets::<0>(x0, x1, x2);
    let r = match rest {
        Some(rest) => rest_residual(&u, &w, r0, r1, rest),
        None => kappa_and_tangent(&u, &w, r0, r1).0,
    };
    Vec3::new(r[0].v, r[1].v, r[2].v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;
    use crate::rod::terms::bend;

    fn split<const D: usize>(x: &[f64; D], k: usize) -> Vec3 {
        Vec3::new(x[3 * k], x[3 * k + 1], x[3 * k + 2])
    }

    /// A random bent stencil with rest lengths near its edges' and its drawn shape.
    fn random_rest_stencil(rng: &mut SplitMix64) -> ([Vec3; 3], f64, f64, RestBend) {
        let a = rng.vec3();
        let d = rng.vec3() + Vec3::new(1.5, 0.0, 0.0);
        let b = a + d;
        let c = b + d + rng.vec3() * 0.8;
        let (r0, r1) = (a.dist(b) * (1.0 + 0.1 * rng.signed()), b.dist(c));
        let rest = rest_bend(b - a, c - b, r0, r1);
        ([a, b, c], r0, r1, rest)
    }

    /// 4-point central differences of `energy` (gradient) and of `eval`'s gradient (Hessian)
    /// at `x`, against `eval`'s, with errors relative to the largest Hessian entry: near the
    /// drawn shape the gradient is small while the Hessian is not, and the gradient's
    /// truncation error scales with the latter.
    fn check_fd4<const D: usize>(
        x: [f64; D],
        eval: impl Fn(&[f64; D]) -> Local<D>,
        energy: impl Fn(&[f64; D]) -> f64,
    ) {
        let l = eval(&x);
        assert_eq!(l.energy.to_bits(), energy(&x).to_bits());
        let h = 1e-3;
        let hnorm = l.hess.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let at = |k: usize, s: f64| {
            let mut y = x;
            y[k] += s;
            y
        };
        let d4 = |f: &dyn Fn(&[f64; D]) -> f64, k: usize| {
            (8.0 * (f(&at(k, h)) - f(&at(k, -h))) - (f(&at(k, 2.0 * h)) - f(&at(k, -2.0 * h))))
                / (12.0 * h)
        };
        for k in 0..D {
            let fd = d4(&energy, k);
            assert!(
                (fd - l.grad[k]).abs() <= 1e-8 * hnorm,
                "grad[{k}]: analytic {} fd {fd}",
                l.grad[k]
            );
            for j in 0..D {
                let fd = d4(&|y: &[f64; D]| eval(y).grad[j], k);
                assert!(
                    (fd - l.hess[j][k]).abs() <= 1e-7 * hnorm,
                    "hess[{j}][{k}]: analytic {} fd {fd}",
                    l.hess[j][k]
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

    #[test]
    fn pre_bent_derivatives_match_finite_differences() {
        let mut rng = SplitMix64::new(19);
        for i in 0..60 {
            let ([a, b, c], r0, r1, rest) = random_rest_stencil(&mut rng);
            // Away from the drawn shape (strongly or slightly), where the residual is not zero.
            let amount = if i % 2 == 0 { 0.5 } else { 1e-3 };
            let (a, b, c) = (
                a + rng.vec3() * amount,
                b + rng.vec3() * amount,
                c + rng.vec3() * amount,
            );
            let kb = 2.5;
            let x = [a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z];
            check_fd4(
                x,
                |x| bend_rest(split(x, 0), split(x, 1), split(x, 2), r0, r1, kb, &rest),
                |x| bend_rest_energy(split(x, 0), split(x, 1), split(x, 2), r0, r1, kb, &rest),
            );
        }
    }

    #[test]
    fn pre_bent_term_rests_in_its_drawn_shape() {
        let mut rng = SplitMix64::new(23);
        for _ in 0..50 {
            let ([a, b, c], r0, r1, rest) = random_rest_stencil(&mut rng);
            let l = bend_rest(a, b, c, r0, r1, 3.0, &rest);
            assert_eq!(l.energy, 0.0);
            assert!(l.grad.iter().all(|g| *g == 0.0), "{:?}", l.grad);
            // The Hessian there is 2 k_b JᵀJ/(ē₀+ē₁): positive semidefinite, zero on the
            // translations and on rotations about axes across the tangent, but not on the spin
            // about the tangent (held where drawn).
            let h = l.hess;
            let quad = |v: &[f64; 9]| -> f64 {
                (0..9)
                    .map(|i| (0..9).map(|j| v[i] * h[i][j] * v[j]).sum::<f64>())
                    .sum()
            };
            let scale = h.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
            for _ in 0..10 {
                let v: [f64; 9] = std::array::from_fn(|_| rng.signed());
                assert!(quad(&v) >= -1e-12 * scale);
            }
            let t = rest.tangent;
            let across = t.cross(rng.vec3()).normalized();
            let spin = |axis: Vec3| -> [f64; 9] {
                let mut v = [0.0; 9];
                for (k, p) in [a, b, c].into_iter().enumerate() {
                    let d = axis.cross(p - b);
                    v[3 * k..3 * k + 3].copy_from_slice(&d.to_array());
                }
                v
            };
            assert!(quad(&spin(across)).abs() <= 1e-10 * scale, "across");
            if rest.kappa.norm() > 1e-3 {
                assert!(quad(&spin(t)) > 1e-6 * scale * rest.kappa.norm2());
            }
        }
    }

    #[test]
    fn pre_bent_term_is_the_papers_when_drawn_straight() {
        // Rest curvature zero: the same energy and derivatives as the straight-rest term.
        let mut rng = SplitMix64::new(29);
        for _ in 0..30 {
            let a = rng.vec3();
            let d = Vec3::new(1.0, 0.3, -0.2);
            let (b, c) = (a + d, a + d * 2.5);
            let rest = rest_bend(b - a, c - b, d.norm(), 1.5 * d.norm());
            assert!(rest.kappa.norm() < 1e-15, "{:?}", rest.kappa);
            let (a, b, c) = (
                a + rng.vec3() * 0.3,
                b + rng.vec3() * 0.3,
                c + rng.vec3() * 0.3,
            );
            let (r0, r1) = (d.norm(), 1.5 * d.norm());
            let p = bend(a, b, c, r0, r1, 1.7);
            let q = bend_rest(a, b, c, r0, r1, 1.7, &rest);
            assert!((p.energy - q.energy).abs() <= 1e-12 * p.energy);
            let hs = p.hess.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
            for i in 0..9 {
                assert!((p.grad[i] - q.grad[i]).abs() <= 1e-12 * hs.max(1.0));
                for j in 0..9 {
                    assert!((p.hess[i][j] - q.hess[i][j]).abs() <= 1e-11 * hs);
                }
            }
        }
    }

    #[test]
    fn pre_bent_term_under_rotations() {
        let mut rng = SplitMix64::new(31);
        let ([a, b, c], r0, r1, rest) = random_rest_stencil(&mut rng);
        let rot = |axis: Vec3, angle: f64, v: Vec3| -> Vec3 {
            let k = axis.normalized();
            let (s, co) = angle.sin_cos();
            v * co + k.cross(v) * s + k * (k.dot(v) * (1.0 - co))
        };
        // Rotating the drawn and the current state together changes nothing.
        let (a2, b2, c2) = (
            a + rng.vec3() * 0.2,
            b + rng.vec3() * 0.2,
            c + rng.vec3() * 0.2,
        );
        let e = bend_rest_energy(a2, b2, c2, r0, r1, 2.0, &rest);
        let axis = Vec3::new(0.3, -0.8, 0.5);
        let q = |v: Vec3| rot(axis, 0.9, v) + Vec3::new(4.0, -1.0, 2.0);
        let rest_q = rest_bend(q(b) - q(a), q(c) - q(b), r0, r1);
        let e_q = bend_rest_energy(q(a2), q(b2), q(c2), r0, r1, 2.0, &rest_q);
        assert!((e - e_q).abs() <= 1e-12 * e, "{e} vs {e_q}");
        // Turning the drawn shape about an axis across its tangent costs nothing.
        let across = rest.tangent.cross(Vec3::new(0.2, 0.9, -0.4));
        let turned = |v: Vec3| rot(across, 0.7, v - b) + b;
        let e = bend_rest_energy(turned(a), turned(b), turned(c), r0, r1, 2.0, &rest);
        assert!(e <= 1e-24, "{e}");
        // Spinning it about its tangent by θ costs 2 k_b |κ̄b|² (1 − cos θ) / (ē₀ + ē₁).
        let theta = 0.4;
        let spun = |v: Vec3| rot(rest.tangent, theta, v - b) + b;
        let e = bend_rest_energy(spun(a), spun(b), spun(c), r0, r1, 2.0, &rest);
        let want = 2.0 * 2.0 * rest.kappa.norm2() * (1.0 - theta.cos()) / (r0 + r1);
        assert!((e / want - 1.0).abs() < 1e-10, "{e} vs {want}");
        // The gradient alone is the full term's, bit for bit.
        let full = bend_rest(a2, b2, c2, r0, r1, 2.0, &rest);
        let (energy, grad) = bend_rest_energy_grad(a2, b2, c2, r0, r1, 2.0, &rest);
        assert_eq!(energy.to_bits(), full.energy.to_bits());
        assert_eq!(grad.map(f64::to_bits), full.grad.map(f64::to_bits));
        assert_eq!(
            bend_rest_energy(a2, b2, c2, r0, r1, 2.0, &rest).to_bits(),
            full.energy.to_bits()
        );
    }
}
