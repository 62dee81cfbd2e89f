//! Bending and twist of a pre-bent rod through a material frame (the physical mode): the
//! discrete elastic rods of Bergou et al. 2008 ("Discrete Elastic Rods") and 2010 ("Discrete
//! Viscous Threads"), for one interior vertex and its two edges ([`frame`]).
//!
//! **Why a frame.** A rod straight at rest with a round section has no preferred direction
//! about its axis: its bending energy sees the centreline alone and its twist decouples, so
//! the paper drops the twist. A pre-bent rod's rest curvature has a direction, so bending
//! must be measured in a frame that turns with the cross-section, and a curved rod's bending
//! out of its plane couples with torsion. Without a frame the energy either misses the
//! direction (a zero mode per free vertex) or fixes it in the world, so that a rigid rotation
//! of the whole rod costs energy (what `rod::prebent` does, used where no twist unknowns are
//! carried). Here each edge `j` carries its twist angle `θ_j`, an unknown beside the
//! positions, and every rigid motion of the rod is a motion of zero energy.
//!
//! **The frame.** Each edge's *reference frame* is its rest director `d̄_j` (a unit vector
//! across the rest tangent `t̄_j`, parallel-transported along the rest rod) carried to the
//! current tangent `t_j` by the minimal rotation `P(t̄_j → t_j)` — for a static energy near
//! the drawn state this is the "time-parallel" transport of Bergou et al. 2010 taken in one
//! step from the rest state, exact as long as no edge turns by 180°. The *material frame*
//! `(m₁, m₂)` is the reference frame turned by `θ_j` about `t_j`.
//!
//! **The energy** at an interior vertex between edges `a` and `b` (rest lengths `ē_a`, `ē_b`),
//! with the curvature binormal `κb = 2 (e_a × e_b) / (ē_a ē_b + e_a · e_b)` of the paper:
//! - bending: the material curvatures `κ_j = (κb · m₂_j, −κb · m₁_j)` of both edges against
//!   their rest values, `E_b = k_b / (ē_a + ē_b) · ½ Σ_j |κ_j − κ̄_j|²` (`k_b = E I`; with zero
//!   rest curvature this is the paper's `k_b |κb|² / (ē_a + ē_b)`, whatever the twist);
//! - twist: `m = θ_b − θ_a + m_ref`, with the reference twist `m_ref` the signed angle about
//!   `t_b` from `P(t_a → t_b)` of edge `a`'s reference director to edge `b`'s, against its rest
//!   value: `E_t = G J (m − m̄)² / (ē_a + ē_b)` (`(G J / 2) ∫ τ² ds` on the dual length).
//!
//! A rigid rotation `R` of the rod, with each `θ_j` the angle from `P(t̄_j → R t̄_j) d̄_j` to
//! `R d̄_j`, gives every edge the material frame `R` times its rest one, so every term keeps
//! its rest value: zero energy. Rotating the drawn and the current state together changes
//! nothing either (a rest director turned about its tangent turns the rest and the current
//! material curvatures alike).
//!
//! **Units.** The unknown is not `θ` but `s = r θ` (`r` the section's outer radius, the
//! *arm*): the distance the outer fibre moves as the section twists, a length like the
//! positions, so the Hessian's entries, the gradient's norm and the zero band of the inertia
//! test stay commensurate (`G J / (r² h) ~ E A / h`), and its rotational inertia
//! `ρ J ē / r²` is a mass like the vertices' (`ρ A ē / 2` for a solid bar).
//!
//! **Why written here.** No Rust crate implements discrete elastic rods; the derivatives come
//! from the forward-mode jets (`rod::jet`) over the two edges and the two twists (8
//! variables), mapped to the 11 local unknowns `(x₀, x₁, x₂, s_a, s_b)`, and are checked
//! against finite differences like every other term.

use super::jet::{self, Jet, JetVec};
use super::terms::Local;
use crate::geom::Vec3;

/// The stiffnesses of a pre-bent rod's frame term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameStiffness {
    /// Bending stiffness `k_b = E I`.
    pub kb: f64,
    /// Torsional stiffness `G J`.
    pub gj: f64,
    /// The twist unknown's arm `r`: the unknown is `s = r θ`.
    pub arm: f64,
}

/// The drawn state of one frame term: the two edges' rest tangents and reference directors,
/// their rest material curvatures, and the rest reference twist.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameRest {
    /// Rest unit tangents of edges `a` and `b`.
    pub tangent: [Vec3; 2],
    /// Rest reference directors of edges `a` and `b` (unit, across their tangents).
    pub director: [Vec3; 2],
    /// Rest material curvatures `κ̄_a`, `κ̄_b`.
    pub kappa: [[f64; 2]; 2],
    /// Rest reference twist `m̄`.
    pub twist: f64,
}

pub(super) fn constant_vec<const N: usize>(v: Vec3) -> JetVec<N> {
    [Jet::constant(v.x), Jet::constant(v.y), Jet::constant(v.z)]
}

pub(super) fn unit<const N: usize>(v: &JetVec<N>) -> JetVec<N> {
    jet::scale(v, jet::dot(v, v).sqrt().recip())
}

/// `P(a → b) v = v + k × v + k × (k × v) / (1 + a·b)`, `k = a × b`: the minimal rotation taking
/// the unit `a` to the unit `b`, applied to `v` (exactly `v` when `a = b`).
#[inline(always)]
pub(super) fn transport<const N: usize>(a: &JetVec<N>, b: &JetVec<N>, v: &JetVec<N>) -> JetVec<N> {
    let k = jet::cross(a, b);
    let c = jet::dot(a, b) + Jet::constant(1.0);
    let kv = jet::cross(&k, v);
    let kkv = jet::scale(&jet::cross(&k, &kv), c.recip());
    jet::add(&jet::add(v, &kv), &kkv)
}

/// [`transport`] of plain vectors: the rest director of the next edge from the previous one.
pub fn transport_director(from: Vec3, to: Vec3, director: Vec3) -> Vec3 {
    let v = transport::<0>(
        &constant_vec(from),
        &constant_vec(to),
        &constant_vec(director),
    );
    Vec3::new(v[0].v, v[1].v, v[2].v)
}

/// The unit tangent of the rest edge `e` (the same arithmetic as the term's at rest).
pub fn rest_tangent(e: Vec3) -> Vec3 {
    let t = unit(&constant_vec::<0>(e));
    Vec3::new(t[0].v, t[1].v, t[2].v)
}

/// A unit vector across the unit `t`: `t × e_k` for the axis `e_k` least aligned with `t`,
/// normalised (the first edge's rest director; any choice gives the same energy).
pub fn first_director(t: Vec3) -> Vec3 {
    let a = [t.x.abs(), t.y.abs(), t.z.abs()];
    let k = (0..3).min_by(|&i, &j| a[i].total_cmp(&a[j])).unwrap_or(0);
    let mut e = Vec3::ZERO;
    e[k] = 1.0;
    t.cross(e).normalized()
}

/// The rest directors of consecutive edges with rest unit tangents `tangents`: the first
/// edge's [`first_director`], each next one its parallel transport (the rod's rest Bishop
/// frame, so the rest reference twist vanishes between consecutive edges).
pub fn rest_directors(tangents: &[Vec3]) -> Vec<Vec3> {
    let mut out: Vec<Vec3> = Vec::with_capacity(tangents.len());
    for (j, &t) in tangents.iter().enumerate() {
        out.push(match j {
            0 => first_director(t),
            _ => transport_director(tangents[j - 1], t, out[j - 1]),
        });
    }
    out
}

/// The material curvatures and the twist of the stencil: `([κ_a, κ_b], m)`.
struct Strains<const N: usize> {
    kappa: [[Jet<N>; 2]; 2],
    twist: Jet<N>,
}

/// The strains of edges `u`, `w` (rest lengths `r0`, `r1`) with twist angles `th`, against
/// rest tangents and directors `tangent`, `director` (the same arithmetic for every `N`, so
/// the rest values [`frame_rest`] computes are bit for bit the values at the rest state).
#[inline(always)]
fn strains<const N: usize>(
    u: &JetVec<N>,
    w: &JetVec<N>,
    th: [Jet<N>; 2],
    r0: f64,
    r1: f64,
    tangent: &[Vec3; 2],
    director: &[Vec3; 2],
) -> Strains<N> {
    let t = [unit(u), unit(w)];
    let reference: [JetVec<N>; 2] = std::array::from_fn(|j| {
        transport(&constant_vec(tangent[j]), &t[j], &constant_vec(director[j]))
    });
    let g = jet::dot(u, w) + Jet::constant(r0 * r1);
    let kb = jet::scale(&jet::cross(u, w), g.recip() * 2.0);
    let kappa = std::array::from_fn(|j| {
        let (s, c) = th[j].sin_cos();
        let side = jet::cross(&t[j], &reference[j]);
        let m1 = jet::add(&jet::scale(&reference[j], c), &jet::scale(&side, s));
        let m2 = jet::sub(&jet::scale(&side, c), &jet::scale(&reference[j], s));
        [jet::dot(&kb, &m2), -jet::dot(&kb, &m1)]
    });
    let carried = transport(&t[0], &t[1], &reference[0]);
    let m_ref = jet::dot(&jet::cross(&carried, &reference[1]), &t[1])
        .atan2(&jet::dot(&carried, &reference[1]));
    Strains {
        kappa,
        twist: th[1] - th[0] + m_ref,
    }
}

/// The drawn state of a frame term whose rest edges are `u`, `w` (rest lengths `r0`, `r1`)
/// with rest directors `director` (from [`rest_directors`]).
pub fn frame_rest(u: Vec3, w: Vec3, r0: f64, r1: f64, director: [Vec3; 2]) -> FrameRest {
    let tangent = [rest_tangent(u), rest_tangent(w)];
    let zero = Jet::constant(0.0);
    let s = strains::<0>(
        &constant_vec(u),
        &constant_vec(w),
        [zero, zero],
        r0,
        r1,
        &tangent,
        &director,
    );
    FrameRest {
        tangent,
        director,
        kappa: s.kappa.map(|k| k.map(|x| x.v)),
        twist: s.twist.v,
    }
}

/// The energy jet over `(u, w, s_a, s_b)` (8 variables, or constants with `N = 0`).
#[inline(always)]
fn energy_jet<const N: usize>(
    x: [Vec3; 3],
    s: [f64; 2],
    r0: f64,
    r1: f64,
    k: &FrameStiffness,
    rest: &FrameRest,
) -> Jet<N> {
    let var = |v: f64, i: usize| {
        if N == 0 {
            Jet::constant(v)
        } else {
            Jet::variable(v, i)
        }
    };
    let (u, w) = (x[1] - x[0], x[2] - x[1]);
    let u = [var(u.x, 0), var(u.y, 1), var(u.z, 2)];
    let w = [var(w.x, 3), var(w.y, 4), var(w.z, 5)];
    let th = [var(s[0], 6) * (1.0 / k.arm), var(s[1], 7) * (1.0 / k.arm)];
    let st = strains(&u, &w, th, r0, r1, &rest.tangent, &rest.director);
    let mut bend = Jet::constant(0.0);
    for j in 0..2 {
        for c in 0..2 {
            let d = st.kappa[j][c] - Jet::constant(rest.kappa[j][c]);
            bend = bend + d * d;
        }
    }
    let dm = st.twist - Jet::constant(rest.twist);
    bend * (0.5 * k.kb / (r0 + r1)) + dm * dm * (k.gj / (r0 + r1))
}

/// The frame term's energy at vertices `x = (x₀, x₁, x₂)` and twist unknowns
/// `s = (s_a, s_b)` (see [`frame`]).
pub fn frame_energy(
    x: [Vec3; 3],
    s: [f64; 2],
    r0: f64,
    r1: f64,
    k: &FrameStiffness,
    rest: &FrameRest,
) -> f64 {
    energy_jet::<0>(x, s, r0, r1, k, rest).v
}

/// The bending and twist term of a pre-bent rod at the vertex `x₁` between edges
/// `x₁ − x₀` and `x₂ − x₁` with twist unknowns `s_a`, `s_b` (the module's docs), with its
/// exact gradient and Hessian over the 11 local unknowns `(x₀, x₁, x₂, s_a, s_b)`.
pub fn frame(
    x: [Vec3; 3],
    s: [f64; 2],
    r0: f64,
    r1: f64,
    k: &FrameStiffness,
    rest: &FrameRest,
) -> Local<11> {
    let e = energy_jet::<8>(x, s, r0, r1, k, rest);
    // Local unknown L as a combination of the jet's variables: x₀ → −u, x₁ → u − w, x₂ → w.
    let combo = |l: usize| -> [(usize, f64); 2] {
        match l {
            0..=2 => [(l, -1.0), (l, 0.0)],
            3..=5 => [(l - 3, 1.0), (l, -1.0)],
            6..=8 => [(l - 3, 1.0), (l - 3, 0.0)],
            _ => [(l - 3, 1.0), (l - 3, 0.0)],
        }
    };
    let mut out = Local::<11>::zero();
    out.energy = e.v;
    for l in 0..11 {
        out.grad[l] = combo(l).iter().map(|&(i, c)| c * e.g[i]).sum();
        for m in 0..11 {
            let mut h = 0.0;
            for &(i, ci) in &combo(l) {
                for &(j, cj) in &combo(m) {
                    h += ci * cj * e.h[i][j];
                }
            }
            out.hess[l][m] = h;
        }
    }
    super::terms::symmetrize(&mut out.hess);
    out
}

/// The bending strain of a frame term: `√(½ Σ_j |κ_j − κ̄_j|²)`, whose `2 / (ē_a + ē_b)` times
/// is the curvature the material feels (the material-frame counterpart of
/// `rod::terms::bend_strain`'s length), and the twist strain `m − m̄`.
pub fn frame_strain(
    x: [Vec3; 3],
    s: [f64; 2],
    r0: f64,
    r1: f64,
    k: &FrameStiffness,
    rest: &FrameRest,
) -> (f64, f64) {
    let (u, w) = (x[1] - x[0], x[2] - x[1]);
    let th = [s[0] / k.arm, s[1] / k.arm].map(Jet::<0>::constant);
    let st = strains(
        &constant_vec(u),
        &constant_vec(w),
        th,
        r0,
        r1,
        &rest.tangent,
        &rest.director,
    );
    let mut sq = 0.0;
    for j in 0..2 {
        for c in 0..2 {
            sq += (st.kappa[j][c].v - rest.kappa[j][c]).powi(2);
        }
    }
    ((0.5 * sq).sqrt(), st.twist.v - rest.twist)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    /// Rotation of `v` by `angle` about the unit `axis`.
    fn rot(axis: Vec3, angle: f64, v: Vec3) -> Vec3 {
        let (s, c) = angle.sin_cos();
        v * c + axis.cross(v) * s + axis * (axis.dot(v) * (1.0 - c))
    }

    /// A random bent stencil, its rest lengths, stiffnesses and drawn state.
    fn stencil(rng: &mut SplitMix64) -> ([Vec3; 3], f64, f64, FrameStiffness, FrameRest) {
        let a = rng.vec3();
        let d = rng.vec3() + Vec3::new(1.5, 0.0, 0.0);
        let b = a + d;
        let c = b + d + rng.vec3() * 0.8;
        let (r0, r1) = (a.dist(b), b.dist(c));
        let k = FrameStiffness {
            kb: 2.0,
            gj: 1.5,
            arm: 0.3,
        };
        let d = rest_directors(&[rest_tangent(b - a), rest_tangent(c - b)]);
        let rest = frame_rest(b - a, c - b, r0, r1, [d[0], d[1]]);
        ([a, b, c], r0, r1, k, rest)
    }

    #[test]
    fn frame_derivatives_match_finite_differences() {
        let mut rng = SplitMix64::new(43);
        for i in 0..30 {
            let (x, r0, r1, k, rest) = stencil(&mut rng);
            let amount = if i % 2 == 0 { 0.4 } else { 1e-3 };
            let x = x.map(|p| p + rng.vec3() * amount);
            let s = [rng.signed() * amount, rng.signed() * amount];
            let flat: [f64; 11] =
                std::array::from_fn(|l| if l < 9 { x[l / 3][l % 3] } else { s[l - 9] });
            let split = |y: &[f64; 11]| {
                (
                    [0, 1, 2].map(|p| Vec3::new(y[3 * p], y[3 * p + 1], y[3 * p + 2])),
                    [y[9], y[10]],
                )
            };
            let l = frame(x, s, r0, r1, &k, &rest);
            assert_eq!(
                l.energy.to_bits(),
                frame_energy(x, s, r0, r1, &k, &rest).to_bits()
            );
            let hnorm = l.hess.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
            let h = 1e-4;
            for m in 0..11 {
                let at = |d: f64| {
                    let mut y = flat;
                    y[m] += d;
                    split(&y)
                };
                let e = |d: f64| {
                    let (x, s) = at(d);
                    frame_energy(x, s, r0, r1, &k, &rest)
                };
                let fd = (8.0 * (e(h) - e(-h)) - (e(2.0 * h) - e(-2.0 * h))) / (12.0 * h);
                assert!(
                    (fd - l.grad[m]).abs() <= 1e-8 * hnorm,
                    "grad[{m}]: {} vs {fd}",
                    l.grad[m]
                );
                let g = |d: f64| {
                    let (x, s) = at(d);
                    frame(x, s, r0, r1, &k, &rest).grad
                };
                let (gp, gm, gp2, gm2) = (g(h), g(-h), g(2.0 * h), g(-2.0 * h));
                for j in 0..11 {
                    let fd = (8.0 * (gp[j] - gm[j]) - (gp2[j] - gm2[j])) / (12.0 * h);
                    assert!(
                        (fd - l.hess[j][m]).abs() <= 1e-7 * hnorm,
                        "hess[{j}][{m}]: {} vs {fd}",
                        l.hess[j][m]
                    );
                    assert_eq!(l.hess[j][m], l.hess[m][j]);
                }
            }
        }
    }

    #[test]
    fn rigid_motions_cost_nothing_when_the_twists_follow() {
        let mut rng = SplitMix64::new(47);
        for _ in 0..20 {
            let (x, r0, r1, k, rest) = stencil(&mut rng);
            // Where drawn: zero energy and gradient.
            let l = frame(x, [0.0, 0.0], r0, r1, &k, &rest);
            assert_eq!(l.energy, 0.0);
            assert!(l.grad.iter().all(|g| *g == 0.0), "{:?}", l.grad);
            // A rigid rotation with each edge's twist the angle from its carried reference
            // director to its rotated rest director.
            let axis = rng.vec3().normalized();
            let angle = 3.0 * rng.signed();
            let y = x.map(|p| rot(axis, angle, p) + Vec3::new(1.0, -2.0, 0.5));
            let s: [f64; 2] = std::array::from_fn(|j| {
                let t = rot(axis, angle, rest.tangent[j]);
                let reference = transport_director(rest.tangent[j], t, rest.director[j]);
                let want = rot(axis, angle, rest.director[j]);
                k.arm * reference.cross(want).dot(t).atan2(reference.dot(want))
            });
            let e = frame_energy(y, s, r0, r1, &k, &rest);
            assert!(e <= 1e-24, "{e}");
            // Without the twists following, a rotation about the rod's own axis costs
            // energy (the section's orientation is what the rest curvature's direction is
            // measured in).
            let spin = x.map(|p| rot(rest.tangent[0], 0.5, p - x[1]) + x[1]);
            assert!(frame_energy(spin, [0.0, 0.0], r0, r1, &k, &rest) > 1e-6);
        }
    }

    #[test]
    fn straight_at_rest_bending_is_the_papers_whatever_the_twist() {
        let mut rng = SplitMix64::new(53);
        for _ in 0..20 {
            let a = rng.vec3();
            let d = Vec3::new(1.0, 0.4, -0.2);
            let (b, c) = (a + d, a + d * 2.2);
            let (r0, r1) = (d.norm(), 1.2 * d.norm());
            let k = FrameStiffness {
                kb: 1.7,
                gj: 0.0,
                arm: 0.2,
            };
            let dir = rest_directors(&[rest_tangent(b - a), rest_tangent(c - b)]);
            let rest = frame_rest(b - a, c - b, r0, r1, [dir[0], dir[1]]);
            let x = [a, b, c].map(|p| p + rng.vec3() * 0.3);
            let s = [rng.signed(), rng.signed()];
            let e = frame_energy(x, s, r0, r1, &k, &rest);
            let p = crate::rod::terms::bend_energy(x[0], x[1], x[2], r0, r1, k.kb);
            assert!((e - p).abs() <= 1e-12 * p, "{e} vs {p}");
        }
    }
}
