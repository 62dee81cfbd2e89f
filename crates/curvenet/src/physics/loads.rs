//! Loads and metrics of the physical mode: self-weight, the distributed load's length metric,
//! the mass metric, and what the eigenpairs and deflections mean physically.
//!
//! - **Self-weight** `f = M g`: each vertex's lumped mass (`rod::mass`) times gravity.
//! - **Natural frequencies**: `H v = μ M v`, `f = √μ / 2π` (Hz in the scene's N-ℓ-s system).
//! - **Worst-case distributed load**: among distributed loads `p(s)` (force per length along
//!   the curves) of RMS intensity `q` (`∫|p|² ds = q² L`, `L` the structure's length), the one
//!   that deflects the structure most (in the RMS sense) is the lowest mode of
//!   `H v = μ_L Λ v`, `Λ` the lumped length of each vertex (the mass metric with `ρ A = 1`):
//!   it deflects it by `q / μ_L` RMS. Unlike the paper's unit-norm worst-case load, whose
//!   nodal forces shrink as the edges do, this load is a force per length, so the answer
//!   converges as `h → 0`. The report gives the largest vertex deflection of that shape,
//!   `q · max|v̂| / μ_L` with `v̂` normalised to RMS 1 over the structure's length.

use crate::material::Physical;
use crate::rod::ActiveSet;
use crate::rod::Network;
use crate::rod::mass::lumped_masses;
use crate::rod::physical::masses_per_length;

/// The self-weight load `M g` of the structure `active` (zero on loose vertices).
pub fn self_weight(network: &Network, physical: &Physical, active: &ActiveSet) -> Vec<f64> {
    let masses = lumped_masses(
        network,
        &masses_per_length(physical, network.rods.len()),
        active,
    );
    let held = held_vertices(network, active);
    let g = physical.gravity_scene();
    masses
        .iter()
        .zip(&held)
        .flat_map(|(&m, &on)| {
            let m = if on { m } else { 0.0 };
            [m * g[0], m * g[1], m * g[2]]
        })
        .collect()
}

/// Each vertex's lumped length in the structure `active`: half of every adjacent rest edge of
/// its curves (the whole network's at loose vertices), the metric of the distributed load.
pub fn lumped_lengths(network: &Network, active: &ActiveSet) -> Vec<f64> {
    lumped_masses(network, &vec![1.0; network.rods.len()], active)
}

/// For every vertex, whether a curve of `active` holds it.
pub fn held_vertices(network: &Network, active: &ActiveSet) -> Vec<bool> {
    let mut held = vec![false; network.vertex_count()];
    for (c, rod) in network.rods.iter().enumerate() {
        if active.contains(c) {
            for &v in &rod.vertices {
                held[v as usize] = true;
            }
        }
    }
    held
}

/// `√μ / 2π` of each eigenvalue `μ` of the mass metric (Hz) that `positive` marks; `None`
/// for a zero or negative one (a mechanism or an unstable equilibrium has no frequency:
/// [`super::inertia::classify`] tells which).
pub fn frequencies_hz(mu: &[f64], positive: &[bool]) -> Vec<Option<f64>> {
    mu.iter()
        .zip(positive)
        .map(|(&m, &p)| p.then(|| m.sqrt() / std::f64::consts::TAU))
        .collect()
}

/// The largest vertex displacement of `u` over the vertices `held` marks: (vertex, length).
pub fn max_displacement(u: &[f64], held: &[bool]) -> (usize, f64) {
    (0..u.len() / 3)
        .filter(|&v| held[v])
        .map(|v| (v, (0..3).map(|k| u[3 * v + k].powi(2)).sum::<f64>().sqrt()))
        .fold((0, 0.0), |best, x| if x.1 > best.1 { x } else { best })
}

/// The worst-case distributed load's largest deflection (scene units) from the lowest pair
/// `(μ_L, v)` of `H v = μ_L Λ v` (`v` in physical coordinates, any scale), the vertices'
/// lumped lengths `lengths` and the RMS intensity `q` (N/ℓ): `q · max|v̂| / μ_L` with `v̂`
/// scaled to `v̂ᵀ Λ v̂ = Σ Λ` (RMS 1). Returns the vertex and the deflection.
pub fn worst_load_deflection(
    mu_l: f64,
    v: &[f64],
    lengths: &[f64],
    held: &[bool],
    q: f64,
) -> (usize, f64) {
    let (mut weighted, mut total) = (0.0, 0.0);
    for (i, &l) in lengths.iter().enumerate() {
        if held[i] {
            weighted += l * (0..3).map(|k| v[3 * i + k].powi(2)).sum::<f64>();
            total += l;
        }
    }
    let scale = if weighted > 0.0 {
        (total / weighted).sqrt()
    } else {
        0.0
    };
    let (vertex, peak) = max_displacement(v, held);
    (vertex, q * peak * scale / mu_l)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frequencies_and_peaks() {
        let f = frequencies_hz(
            &[-1.0, 0.0, 4.0 * std::f64::consts::PI.powi(2)],
            &[false, false, true],
        );
        assert_eq!(f[0], None);
        assert_eq!(f[1], None);
        assert!((f[2].unwrap() - 1.0).abs() < 1e-12);
        let u = [0.0, 0.0, 1.0, 3.0, 4.0, 0.0, 10.0, 0.0, 0.0];
        assert_eq!(max_displacement(&u, &[true, true, false]), (1, 5.0));
        // One vertex of length 2 carrying all: RMS 1 means |v̂| = 1 there.
        let (v, d) = worst_load_deflection(4.0, &u[..3], &[2.0], &[true], 8.0);
        assert_eq!((v, d), (0, 2.0));
    }
}
