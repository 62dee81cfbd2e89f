//! The physical mode's clamp: the end vertex held in place (an anchor) and its tangent held
//! by a bending term at the end vertex against a *ghost edge*, the first edge mirrored
//! through the plane normal to the drawn end tangent ([`clamp`]).
//!
//! **Why.** The paper's clamp anchors the first two vertices: it holds the end of the first
//! edge and the next vertex, so the rod's slope vanishes at the middle of the first edge and
//! the free span is `L − h` — first-order convergence, on the stiff side (a 1 m steel bar
//! clamped at both ends with 50 edges: `f₁` +4.1 %, self-weight deflection −8 %). A clamp
//! of the continuum holds the end's position and tangent. With the end vertex `x₀` anchored,
//! mirror the first edge `e = x₁ − x₀` through the plane normal to the drawn end tangent
//! `T`: the ghost vertex `x₋₁ = x₀ + e − 2 (e·T) T` makes the discretisation symmetric about
//! the end (the even reflection `w₋₁ = w₁` of the central difference `w'(0) = 0`), and the
//! bending term at `x₀` between the ghost edge `g = x₀ − x₋₁ = 2 (e·T) T − e` and `e` takes
//! half the weight of an interior one (half its dual length lies on the rod): the trapezoid
//! rule, so the stationarity conditions are the interior stencil with `w₋₁ = w₁`, second
//! order. It depends on `e` alone (translation invariant), and on `T`, which the support
//! holds in the world.
//!
//! `T` is the tangent at the end of the circle through the first three drawn vertices (the
//! chord turned back by the tangent–chord angle, [`end_tangent`]): exact on a circular arc,
//! so a rod bent into an arc has the arc's curvature at its clamped ends too, and its
//! stresses there are the arc's. For a pre-bent rod the term measures the curvature from
//! its drawn value (zero energy and gradient where drawn); the vertex tangent of the ghost
//! stencil is `T` itself for every `e` (the stencil is symmetric about the plane), so no
//! rotation of the rest curvature is needed.
//!
//! The derivatives come from the forward-mode jets (`rod::jet`) over `e`.

use super::jet::{self, Jet, JetVec};
use super::terms::Local;
use crate::geom::Vec3;

/// A clamped end's drawn shape: the end tangent `T` (unit, pointing into the rod) and the
/// ghost stencil's rest curvature binormal (zero for a rod straight at rest).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClampRest {
    /// The drawn end tangent `T`, pointing into the rod.
    pub tangent: Vec3,
    /// The curvature binormal the ghost stencil has at rest (zero: straight at rest).
    pub kappa: Vec3,
}

/// The unit tangent at `x0` of the circle through `x0, x1, x2` (the chord `x1 − x0` turned
/// away from the bend by the angle at `x2`, the tangent–chord angle), pointing towards `x1`;
/// the chord's direction when the three are collinear or `x2` is absent.
pub fn end_tangent(x0: Vec3, x1: Vec3, x2: Option<Vec3>) -> Vec3 {
    let u = (x1 - x0).normalized();
    let Some(x2) = x2 else { return u };
    let n = (x1 - x0).cross(x2 - x1);
    if n.norm() <= 1e-14 * (x1 - x0).norm() * (x2 - x1).norm() {
        return u;
    }
    let n = n.normalized();
    let (a, b) = (x0 - x2, x1 - x2);
    let beta = a.cross(b).norm().atan2(a.dot(b));
    u * beta.cos() - n.cross(u) * beta.sin()
}

fn constant_vec<const N: usize>(v: Vec3) -> JetVec<N> {
    [Jet::constant(v.x), Jet::constant(v.y), Jet::constant(v.z)]
}

/// The ghost stencil's curvature binormal `2 (g × e) / (ē² + g·e)`, `g = 2 (e·T) T − e`.
#[inline(always)]
fn ghost_kappa<const N: usize>(e: &JetVec<N>, tangent: Vec3, rest: f64) -> JetVec<N> {
    let t = constant_vec::<N>(tangent);
    let et = jet::dot(e, &t);
    let g = jet::sub(&jet::scale(&t, et * 2.0), e);
    let denom = jet::dot(&g, e) + Jet::constant(rest * rest);
    jet::scale(&jet::cross(&g, e), denom.recip() * 2.0)
}

/// The rest state of a clamped end: drawn end vertex `x0`, its neighbour `x1`, the next one
/// `x2` (absent on a one-edge rod), the end edge's rest length, and whether the rod is
/// pre-bent (then the ghost stencil's drawn curvature is its rest curvature).
pub fn clamp_rest(x0: Vec3, x1: Vec3, x2: Option<Vec3>, rest: f64, pre_bent: bool) -> ClampRest {
    let tangent = end_tangent(x0, x1, x2);
    let kappa = if pre_bent {
        let k = ghost_kappa::<0>(&constant_vec(x1 - x0), tangent, rest);
        Vec3::new(k[0].v, k[1].v, k[2].v)
    } else {
        Vec3::ZERO
    };
    ClampRest { tangent, kappa }
}

/// `κb(g, e) − κ̄b`: the bending strain at the clamped end.
#[inline(always)]
fn residual<const N: usize>(e: &JetVec<N>, rest: f64, c: &ClampRest) -> JetVec<N> {
    jet::sub(&ghost_kappa(e, c.tangent, rest), &constant_vec(c.kappa))
}

fn edge_jet<const N: usize>(e: Vec3) -> JetVec<N> {
    if N == 0 {
        constant_vec(e)
    } else {
        [
            Jet::variable(e.x, 0),
            Jet::variable(e.y, 1),
            Jet::variable(e.z, 2),
        ]
    }
}

/// The clamp's bending energy `k_b |κb(g, e) − κ̄b|² / (4 ē)` at the end vertex `x0` with
/// neighbour `x1` (see [`clamp`]).
pub fn clamp_energy(x0: Vec3, x1: Vec3, rest: f64, kb: f64, c: &ClampRest) -> f64 {
    let r = residual(&edge_jet::<0>(x1 - x0), rest, c);
    kb / (4.0 * rest) * jet::dot(&r, &r).v
}

/// [`clamp`]'s energy and gradient (the same values, bit for bit).
pub fn clamp_energy_grad(x0: Vec3, x1: Vec3, rest: f64, kb: f64, c: &ClampRest) -> (f64, [f64; 6]) {
    let l = clamp(x0, x1, rest, kb, c);
    (l.energy, l.grad)
}

/// The clamp's bending term over `(x0, x1)`, with its exact gradient and Hessian:
/// `E = k_b |κb(g, e) − κ̄b|² / (4 ē)`, half the interior term `k_b |κb|² / (ē₀ + ē₁)` with
/// both edges `ē` long, between `e = x1 − x0` and the ghost edge `g = 2 (e·T) T − e`
/// (the module's docs say why). `|κb| = 2 tan ψ` for an edge turned by `ψ` from `T`.
pub fn clamp(x0: Vec3, x1: Vec3, rest: f64, kb: f64, c: &ClampRest) -> Local<6> {
    let r = residual(&edge_jet::<3>(x1 - x0), rest, c);
    let e = jet::dot(&r, &r) * (kb / (4.0 * rest));
    let mut out = Local::<6>::zero();
    out.energy = e.v;
    for a in 0..3 {
        out.grad[a] = -e.g[a];
        out.grad[3 + a] = e.g[a];
        for b in 0..3 {
            let h = e.h[a][b];
            out.hess[a][b] = h;
            out.hess[3 + a][3 + b] = h;
            out.hess[a][3 + b] = -h;
            out.hess[3 + a][b] = -h;
        }
    }
    out
}

/// The bending strain at a clamped end, `κb(g, e) − κ̄b`: its length over `ē` is the
/// curvature the material feels there.
pub fn clamp_strain(x0: Vec3, x1: Vec3, rest: f64, c: &ClampRest) -> Vec3 {
    let r = residual(&edge_jet::<0>(x1 - x0), rest, c);
    Vec3::new(r[0].v, r[1].v, r[2].v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    #[test]
    fn end_tangent_is_the_circles() {
        let r = 3.0;
        let p = |t: f64| Vec3::new(r * t.cos(), r * t.sin(), 0.0);
        for (a, b) in [(0.1, 0.25), (0.3, 0.3), (0.05, 0.4)] {
            let t = end_tangent(p(0.0), p(a), Some(p(a + b)));
            assert!(t.dist(Vec3::new(0.0, 1.0, 0.0)) < 1e-14, "{t:?}");
        }
        let t = end_tangent(
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Some(Vec3::new(5.0, 0.0, 0.0)),
        );
        assert_eq!(t, Vec3::new(1.0, 0.0, 0.0));
    }

    #[test]
    fn clamp_derivatives_match_finite_differences() {
        let mut rng = SplitMix64::new(41);
        for i in 0..40 {
            let x0 = rng.vec3();
            let x1 = x0 + Vec3::new(1.3, 0.0, 0.0) + rng.vec3() * 0.4;
            let x2 = x1 + Vec3::new(1.1, 0.0, 0.0) + rng.vec3() * 0.4;
            let rest = x0.dist(x1) * (1.0 + 0.05 * rng.signed());
            let c = clamp_rest(x0, x1, Some(x2), rest, i % 2 == 0);
            let amount = if i % 4 < 2 { 0.3 } else { 1e-3 };
            let (y0, y1) = (x0 + rng.vec3() * amount, x1 + rng.vec3() * amount);
            let x = [y0.x, y0.y, y0.z, y1.x, y1.y, y1.z];
            let split = |x: &[f64; 6], k: usize| Vec3::new(x[3 * k], x[3 * k + 1], x[3 * k + 2]);
            let kb = 2.0;
            let l = clamp(y0, y1, rest, kb, &c);
            assert_eq!(
                l.energy.to_bits(),
                clamp_energy(y0, y1, rest, kb, &c).to_bits()
            );
            let hnorm = l.hess.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
            let h = 1e-4;
            for k in 0..6 {
                let at = |s: f64| {
                    let mut y = x;
                    y[k] += s;
                    y
                };
                let e = |y: [f64; 6]| clamp_energy(split(&y, 0), split(&y, 1), rest, kb, &c);
                let fd = (8.0 * (e(at(h)) - e(at(-h))) - (e(at(2.0 * h)) - e(at(-2.0 * h))))
                    / (12.0 * h);
                assert!((fd - l.grad[k]).abs() <= 1e-8 * hnorm, "grad[{k}]");
                let g = |y: [f64; 6]| clamp(split(&y, 0), split(&y, 1), rest, kb, &c).grad;
                let (gp, gm) = (g(at(h)), g(at(-h)));
                for j in 0..6 {
                    let fd = (gp[j] - gm[j]) / (2.0 * h);
                    assert!((fd - l.hess[j][k]).abs() <= 1e-6 * hnorm, "hess[{j}][{k}]");
                    assert_eq!(l.hess[j][k], l.hess[k][j]);
                }
            }
        }
    }

    #[test]
    fn an_edge_turned_from_the_clamp_costs_half_an_interior_bend() {
        // Straight rest, edge turned by ψ from T: |κb| = 2 tan ψ, E = k_b (2 tan ψ)² / (4 ē).
        let (rest, kb, psi) = (2.0, 3.0, 0.2f64);
        let c = clamp_rest(Vec3::ZERO, Vec3::new(rest, 0.0, 0.0), None, rest, false);
        let x1 = Vec3::new(psi.cos(), psi.sin(), 0.0) * rest;
        let e = clamp_energy(Vec3::ZERO, x1, rest, kb, &c);
        let want = kb * (2.0 * psi.tan()).powi(2) / (4.0 * rest);
        assert!((e / want - 1.0).abs() < 1e-13, "{e} vs {want}");
        // Pre-bent: zero energy and gradient where drawn, under a rigid motion of the whole
        // problem too.
        let (x0, x1, x2) = (
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(2.0, 2.5, 3.0),
            Vec3::new(2.8, 3.4, 3.2),
        );
        let c = clamp_rest(x0, x1, Some(x2), x0.dist(x1), true);
        let l = clamp(x0, x1, x0.dist(x1), kb, &c);
        assert_eq!(l.energy, 0.0);
        assert!(l.grad.iter().all(|g| *g == 0.0));
        assert!(c.kappa.norm() > 0.1);
    }
}
