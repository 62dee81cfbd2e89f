//! The energy's constants in the physical mode: each rod's stiffnesses from its material and
//! section, and supports that stay rigid whatever the scale.
//!
//! `k_s = E A` and `k_b = E I` per rod ([`Physical::scene_rod`]), in N and N·ℓ². The paper's
//! anchor weight `µ = 500` is a constant in scene units: next to a steel rod in millimetres
//! (`E A / h ≈ 3·10⁶ N/mm` for a 10 mm bar and 20 mm edges) it is a soft spring, and the
//! "support" would move. In the physical mode the anchors are scaled to the structure
//! instead ([`rigid_anchor_weight`]): a thousand times the stiffness of a typical edge of the
//! stiffest rod. That is about the paper's own ratio (its
//! `2µ = 1000` against `k_s / h ≈ 0.6`), so the Hessian's conditioning, and with it the
//! zero-mode threshold `C ε ‖H‖₁`, stays as in the paper's examples, while the supports move
//! by a thousandth of what the rod beside them stretches: measured, `λ` and `μ` within 10⁻⁵
//! of rigid supports (supports eliminated) on straight rods, arches and a small grid
//! (`tests/physical.rs`).

use super::Network;
use super::RodStiffness;
use crate::material::{Physical, RestShape};

/// `2µ` over the stiffness of a typical edge in the physical mode ([`rigid_anchor_weight`]).
pub const ANCHOR_STIFFNESS_RATIO: f64 = 1e3;

/// Rod `c`'s stiffnesses from `physical`, with rest shape `rest[c]` (straight where `rest` is
/// shorter).
pub fn physical_rods(physical: &Physical, n_rods: usize, rest: &[RestShape]) -> Vec<RodStiffness> {
    (0..n_rods)
        .map(|c| {
            let r = physical.scene_rod(c);
            RodStiffness {
                ks: r.ks,
                kb: r.kb,
                gj: r.gj,
                arm: r.outer_radius,
                rest: rest.get(c).copied().unwrap_or_default(),
            }
        })
        .collect()
}

/// The anchor weight `µ` that keeps the supports rigid next to `rods` on `network`:
/// `2µ = ANCHOR_STIFFNESS_RATIO · max(max k_s / h, max k_b / h³)` with `h` the median rest
/// edge: a thousand times the stiffest edge's axial stiffness, or, on edges shorter than the
/// rod is thick, its bending stiffness (an anchored vertex is pushed across the rod by the
/// bending terms beside it, `k_b / h³`; the paper's clamp also holds its rotation by two
/// anchors one edge apart, whose rotational stiffness must outgrow the bending terms' `k_b / h`
/// as `h` shrinks).
pub fn rigid_anchor_weight(network: &Network, rods: &[RodStiffness]) -> f64 {
    let ks = rods.iter().map(|r| r.ks).fold(0.0, f64::max);
    let kb = rods.iter().map(|r| r.kb).fold(0.0, f64::max);
    let h = network.edge_length_stats().median;
    let h = if h > 0.0 { h } else { 1.0 };
    0.5 * ANCHOR_STIFFNESS_RATIO * (ks / h).max(kb / (h * h * h))
}

/// The twist unknowns' mass per unit rest length of every rod, `ρ J / r²` (a twist unknown
/// is the outer fibre's displacement `r θ`, so its kinetic energy `½ ρ J ē θ̇²` is that of a
/// mass `ρ J ē / r²`: `ρ A ē / 2` for a solid bar).
pub fn twist_masses_per_length(physical: &Physical, n_rods: usize) -> Vec<f64> {
    (0..n_rods)
        .map(|c| {
            let r = physical.scene_rod(c);
            r.polar_mass_per_length / (r.outer_radius * r.outer_radius)
        })
        .collect()
}

/// Mass per unit length `ρ A` of every rod.
pub fn masses_per_length(physical: &Physical, n_rods: usize) -> Vec<f64> {
    (0..n_rods)
        .map(|c| physical.scene_rod(c).mass_per_length)
        .collect()
}
