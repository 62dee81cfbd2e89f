//! The lumped mass matrix of a structure and the symmetric scaling that turns the generalized
//! eigenproblem `H v = μ M v` into an ordinary one.
//!
//! Each vertex carries `ρ A` times half of each adjacent rest edge of every curve of the
//! structure through it, on each of its three coordinates: `M` is diagonal. With
//! `H̃ = M^{-1/2} H M^{-1/2}` (the same sparsity pattern, scaled values), `H v = μ M v` is
//! `H̃ ṽ = μ ṽ` with `ṽ = M^{1/2} v`, so every eigen solver, inertia test and factorization
//! works unchanged. In the scene's unit system `μ` is in s⁻² and `√μ / 2π` is a natural
//! frequency in hertz. Unlike the identity metric's `λ`, which scales with the edge length
//! (`λ₁ ≈ k_b (π/L)⁴ h` for a beam), `μ` converges as the edges shrink.
//!
//! In the physical mode a pre-bent rod's twist unknowns carry the rotational inertia of
//! their edges ([`twist_masses`]), one diagonal entry each after the vertices'.
//!
//! A vertex no curve of the structure holds is loose: it carries the mass of all the curves of
//! the network through it, so the loose diagonal of `H` keeps it far above the structure's
//! spectrum after the scaling too.

use super::ActiveSet;
use super::Network;
use super::model::TwistDof;
use crate::sparse::Pattern;

/// The lumped mass of every vertex of the structure `active` (the whole network's at loose
/// vertices), with rod `c` weighing `mass_per_length[c]` per unit rest length.
pub fn lumped_masses(network: &Network, mass_per_length: &[f64], active: &ActiveSet) -> Vec<f64> {
    assert_eq!(
        mass_per_length.len(),
        network.rods.len(),
        "one mass per length per rod"
    );
    let n = network.vertex_count();
    let mut held = vec![0.0; n];
    let mut all = vec![0.0; n];
    for (c, rod) in network.rods.iter().enumerate() {
        for j in 0..rod.edge_count() {
            let (a, b) = rod.edge(j);
            let half = 0.5 * mass_per_length[c] * rod.rest_lengths[j];
            for v in [a as usize, b as usize] {
                all[v] += half;
                if active.contains(c) {
                    held[v] += half;
                }
            }
        }
    }
    held.iter()
        .zip(&all)
        .map(|(&h, &a)| if h > 0.0 { h } else { a })
        .collect()
}

/// `1/√m` for every coordinate (three per vertex) of the vertex masses `masses`.
pub fn inverse_sqrt_coordinates(masses: &[f64]) -> Vec<f64> {
    masses.iter().flat_map(|&m| [1.0 / m.sqrt(); 3]).collect()
}

/// The mass of each twist unknown `twists` (a model's [`super::EnergyModel::twist_dofs`]):
/// its edge's rest length times its rod's `twist_mass_per_length` (`ρ J / r²`: the unknown is
/// the outer fibre's displacement `r θ`, `rod::physical::twist_masses_per_length`), whether
/// or not its rod is in the structure (a loose twist keeps its mass, as a loose vertex does).
pub fn twist_masses(
    network: &Network,
    twists: &[TwistDof],
    twist_mass_per_length: &[f64],
) -> Vec<f64> {
    twists
        .iter()
        .map(|t| {
            let c = t.curve as usize;
            twist_mass_per_length[c] * network.rods[c].rest_lengths[t.edge as usize]
        })
        .collect()
}

/// `1/√m` for every coordinate of a model with twist unknowns: three per vertex of the vertex
/// masses `masses`, then one per twist of `twists` ([`twist_masses`]).
pub fn inverse_sqrt_with_twists(masses: &[f64], twists: &[f64]) -> Vec<f64> {
    let mut s = inverse_sqrt_coordinates(masses);
    s.extend(twists.iter().map(|&m| 1.0 / m.sqrt()));
    s
}

/// `M^{-1/2} H M^{-1/2}` in place: the upper-triangle values `hess` of `pattern` scaled by
/// `s_i s_j` with `s = inverse_sqrt_coordinates(masses)`.
pub fn scale_hessian(pattern: &Pattern, hess: &mut [f64], s: &[f64]) {
    assert_eq!(s.len(), pattern.n, "one scale per coordinate");
    for j in 0..pattern.n {
        for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
            hess[k] *= s[pattern.row_idx[k]] * s[j];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Vec3;
    use crate::rod::Supports;
    use crate::rod::{Joint, Rod};

    /// Two straight rods crossing at vertex 2: rod 0 = 0-1-2-3 (edges 1, 1, 2), rod 1 = 4-2-5
    /// (edges 3, 3).
    fn cross() -> Network {
        let positions = (0..6).map(|i| Vec3::new(i as f64, 0.0, 0.0)).collect();
        Network {
            positions,
            rods: vec![
                Rod {
                    vertices: vec![0, 1, 2, 3],
                    closed: false,
                    rest_lengths: vec![1.0, 1.0, 2.0],
                    anchors: vec![0, 3],
                    ends: None,
                    frames: None,
                },
                Rod {
                    vertices: vec![4, 2, 5],
                    closed: false,
                    rest_lengths: vec![3.0, 3.0],
                    anchors: vec![4, 5],
                    ends: None,
                    frames: None,
                },
            ],
            joints: vec![Joint {
                vertex: 2,
                curves: vec![0, 1],
            }],
            supports: Supports::Pinned,
        }
    }

    #[test]
    fn masses_are_half_the_adjacent_edges() {
        let net = cross();
        let rho_a = [2.0, 10.0];
        let m = lumped_masses(&net, &rho_a, &ActiveSet::all(2));
        assert_eq!(m, vec![1.0, 2.0, 3.0 + 30.0, 2.0, 15.0, 15.0]);
        // Without rod 1 the joint carries rod 0's mass only; rod 1's own vertices are loose
        // and keep their mass.
        let m = lumped_masses(&net, &rho_a, &ActiveSet::from_curves(2, &[0]));
        assert_eq!(m, vec![1.0, 2.0, 3.0, 2.0, 15.0, 15.0]);
        let total: f64 = lumped_masses(&net, &rho_a, &ActiveSet::all(2)).iter().sum();
        assert_eq!(total, 2.0 * 4.0 + 10.0 * 6.0);
        let s = inverse_sqrt_coordinates(&[4.0, 1.0]);
        assert_eq!(s, vec![0.5, 0.5, 0.5, 1.0, 1.0, 1.0]);
    }
}
