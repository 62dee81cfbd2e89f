//! A clamp's hold on a pre-bent rod's twist (the physical mode): the twist between the
//! clamp's material frame, fixed in the world, and the end edge's ([`clamp_twist`]).
//!
//! **Why a term, not a held unknown.** The twist unknowns live on the edges (a staggered
//! grid: `θ_j` at edge `j`'s midpoint), so holding the end edge's `θ` would hold the twist half
//! an edge into the rod, a first-order error — the same defect as the paper's clamp for
//! bending. The clamp holds the section at the end vertex itself: its frame is the end
//! edge's rest director carried to the drawn end tangent `T` (`rod::clamp`), and the twist
//! from it to the end edge's material frame, `m = θ + m_ref` (`m_ref` the signed angle about the
//! edge's tangent from the clamp's director carried to it to the edge's reference director),
//! costs `G J m² / ē` over the half edge between them (`(G J / 2) ∫ τ² ds` with `τ = m / (ē/2)`),
//! the odd reflection `θ₋₁ = −θ₀` of the central difference: second order, like the clamp's
//! bending term.
//!
//! At the rod's far end the edge is taken from the end inwards (its tangent and twist
//! reversed, the same material frame), so both ends use the same formula. The term is zero
//! with a zero gradient where drawn; the derivatives come from the forward-mode jets over the
//! edge and its twist unknown.

use super::frame::{FrameStiffness, constant_vec, transport, unit};
use super::jet::{self, Jet, JetVec};
use super::terms::Local;
use crate::geom::Vec3;

/// The drawn state of a clamp's twist term: the end edge's rest tangent and director (from
/// the end inwards), and the clamp's frame (the drawn end tangent and the director carried to
/// it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClampTwistRest {
    /// The end edge's rest unit tangent, pointing into the rod.
    pub tangent: Vec3,
    /// The end edge's rest reference director.
    pub director: Vec3,
    /// The drawn end tangent `T`, pointing into the rod.
    pub end_tangent: Vec3,
    /// The clamp's director: the edge's rest director carried to `T`.
    pub end_director: Vec3,
    /// The rest twist `m̄` (zero up to round-off: the two carryings do not cancel bit for
    /// bit), so that the term is exactly zero where drawn.
    pub twist: f64,
}

/// The drawn state of a clamp's twist term for the rest end edge `e` (from the end inwards)
/// with rest director `director` (the rod's frame terms') and drawn end tangent
/// `end_tangent`.
pub fn clamp_twist_rest(e: Vec3, director: Vec3, end_tangent: Vec3) -> ClampTwistRest {
    let tangent = super::frame::rest_tangent(e);
    let d = transport::<0>(
        &constant_vec(tangent),
        &constant_vec(end_tangent),
        &constant_vec(director),
    );
    let mut rest = ClampTwistRest {
        tangent,
        director,
        end_tangent,
        end_director: Vec3::new(d[0].v, d[1].v, d[2].v),
        twist: 0.0,
    };
    rest.twist = twist::<0>(&constant_vec(e), Jet::constant(0.0), &rest).v;
    rest
}

/// `m = θ + m_ref − m̄` for the edge `e` with twist `theta` (the same arithmetic for every
/// `N`).
#[inline(always)]
fn twist<const N: usize>(e: &JetVec<N>, theta: Jet<N>, rest: &ClampTwistRest) -> Jet<N> {
    let t = unit(e);
    let reference = transport(
        &constant_vec(rest.tangent),
        &t,
        &constant_vec(rest.director),
    );
    let carried = transport(
        &constant_vec(rest.end_tangent),
        &t,
        &constant_vec(rest.end_director),
    );
    let m_ref =
        jet::dot(&jet::cross(&carried, &reference), &t).atan2(&jet::dot(&carried, &reference));
    theta + m_ref - Jet::constant(rest.twist)
}

/// The energy jet over `(e, s)`: `G J (θ + m_ref − m̄)² / ē`, `θ = sign · s / r`.
#[inline(always)]
fn energy_jet<const N: usize>(
    e: Vec3,
    s: f64,
    sign: f64,
    len: f64,
    k: &FrameStiffness,
    rest: &ClampTwistRest,
) -> Jet<N> {
    let var = |v: f64, i: usize| {
        if N == 0 {
            Jet::constant(v)
        } else {
            Jet::variable(v, i)
        }
    };
    let ej = [var(e.x, 0), var(e.y, 1), var(e.z, 2)];
    let m = twist(&ej, var(s, 3) * (sign / k.arm), rest);
    m * m * (k.gj / len)
}

/// The clamp's twist energy at the end vertex `x0` with its neighbour `x1` and the end
/// edge's twist unknown `s` (`sign`: +1 when the edge runs from the end inwards, −1 at the far
/// end), rest length `len` (see [`clamp_twist`]).
pub fn clamp_twist_energy(
    x: [Vec3; 2],
    s: f64,
    sign: f64,
    len: f64,
    k: &FrameStiffness,
    rest: &ClampTwistRest,
) -> f64 {
    energy_jet::<0>(x[1] - x[0], s, sign, len, k, rest).v
}

/// The clamp's twist term over `(x0, x1, s)` with its exact gradient and Hessian: the end
/// vertex `x0`, its neighbour `x1`, the end edge's twist unknown `s = r θ` (the module's docs).
pub fn clamp_twist(
    x: [Vec3; 2],
    s: f64,
    sign: f64,
    len: f64,
    k: &FrameStiffness,
    rest: &ClampTwistRest,
) -> Local<7> {
    let e = energy_jet::<4>(x[1] - x[0], s, sign, len, k, rest);
    // x0 → −e, x1 → +e, s → s.
    let combo = |l: usize| -> (usize, f64) {
        match l {
            0..=2 => (l, -1.0),
            3..=5 => (l - 3, 1.0),
            _ => (3, 1.0),
        }
    };
    let mut out = Local::<7>::zero();
    out.energy = e.v;
    for l in 0..7 {
        let (i, ci) = combo(l);
        out.grad[l] = ci * e.g[i];
        for m in 0..7 {
            let (j, cj) = combo(m);
            out.hess[l][m] = ci * cj * e.h[i][j];
        }
    }
    out
}

/// The twist strain at a clamp, `m − m̄` (its `2 / ē` times is the twist per length there).
pub fn clamp_twist_strain(
    x: [Vec3; 2],
    s: f64,
    sign: f64,
    k: &FrameStiffness,
    rest: &ClampTwistRest,
) -> f64 {
    let e = constant_vec::<0>(x[1] - x[0]);
    twist(&e, Jet::constant(s * sign / k.arm), rest).v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;
    use crate::rod::frame::{first_director, rest_tangent};

    #[test]
    fn clamp_twist_derivatives_match_finite_differences() {
        let mut rng = SplitMix64::new(59);
        let k = FrameStiffness {
            kb: 1.0,
            gj: 2.0,
            arm: 0.4,
        };
        for i in 0..30 {
            let x0 = rng.vec3();
            let x1 = x0 + Vec3::new(1.2, 0.3, -0.2) + rng.vec3() * 0.2;
            let t = rest_tangent(x1 - x0);
            let end = (t + rng.vec3() * 0.1).normalized();
            let rest = clamp_twist_rest(x1 - x0, first_director(t), end);
            let len = x0.dist(x1);
            // Where drawn: zero.
            let l = clamp_twist([x0, x1], 0.0, 1.0, len, &k, &rest);
            assert_eq!(l.energy, 0.0);
            assert!(l.grad.iter().all(|g| *g == 0.0));
            let amount = if i % 2 == 0 { 0.3 } else { 1e-3 };
            let y = [x0 + rng.vec3() * amount, x1 + rng.vec3() * amount];
            let s = amount * rng.signed();
            let sign = if i % 3 == 0 { -1.0 } else { 1.0 };
            let flat: [f64; 7] = std::array::from_fn(|l| if l < 6 { y[l / 3][l % 3] } else { s });
            let split = |f: &[f64; 7]| {
                (
                    [Vec3::new(f[0], f[1], f[2]), Vec3::new(f[3], f[4], f[5])],
                    f[6],
                )
            };
            let l = clamp_twist(y, s, sign, len, &k, &rest);
            let hnorm = l.hess.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
            let h = 1e-4;
            for m in 0..7 {
                let at = |d: f64| {
                    let mut f = flat;
                    f[m] += d;
                    split(&f)
                };
                let e = |d: f64| {
                    let (x, s) = at(d);
                    clamp_twist_energy(x, s, sign, len, &k, &rest)
                };
                let fd = (8.0 * (e(h) - e(-h)) - (e(2.0 * h) - e(-2.0 * h))) / (12.0 * h);
                assert!((fd - l.grad[m]).abs() <= 1e-8 * hnorm, "grad[{m}]");
                let g = |d: f64| {
                    let (x, s) = at(d);
                    clamp_twist(x, s, sign, len, &k, &rest).grad
                };
                let (gp, gm) = (g(h), g(-h));
                for j in 0..7 {
                    let fd = (gp[j] - gm[j]) / (2.0 * h);
                    assert!((fd - l.hess[j][m]).abs() <= 1e-6 * hnorm, "hess[{j}][{m}]");
                    assert_eq!(l.hess[j][m], l.hess[m][j]);
                }
            }
        }
    }

    #[test]
    fn a_twisted_end_edge_costs_its_half_edge() {
        // A straight edge along x twisted by θ: G J θ² / ē.
        let k = FrameStiffness {
            kb: 1.0,
            gj: 3.0,
            arm: 0.5,
        };
        let t = Vec3::new(1.0, 0.0, 0.0);
        let rest = clamp_twist_rest(t * 2.0, first_director(t), t);
        let theta = 0.2;
        let e = clamp_twist_energy(
            [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0)],
            theta * k.arm,
            1.0,
            2.0,
            &k,
            &rest,
        );
        assert!((e - 3.0 * theta * theta / 2.0).abs() < 1e-15, "{e}");
    }
}
