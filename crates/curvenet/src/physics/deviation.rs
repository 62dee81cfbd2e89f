//! How far a structure stands from its design in the physical mode: the largest deviation
//! that `--max-deviation` bounds there.
//!
//! A vertex's deviation is its distance from its designed (drawn) place once the rods are
//! bent into shape and carry their own weight: the displacement of the physical equilibrium
//! (the structure's own model: `E A`, `E I`, rest shapes, rigid supports, clamps that hold the
//! end, pre-bent rods with their twist) plus the self-weight deflection linearised there
//! (`H u = M g`), in the scene's units. A pre-bent structure, in equilibrium where it was
//! drawn, deviates by its sag alone; with gravity off, by its equilibrium alone. A structure
//! whose Hessian at that equilibrium is not positive definite has no linear deflection and an
//! infinite deviation (it meets no limit).
//!
//! [`super::analyze_physical`] reports the same number (`max_deviation`), and
//! [`DeviationModel`] measures it for the searches without the rest of the analysis (no eigen
//! solve): one model and symbolic analysis per network, one relaxation and one factorization
//! per structure.

use super::PhysicalParams;
use super::loads::{held_vertices, self_weight};
use crate::rod::physical::{physical_rods, rigid_anchor_weight};
use crate::rod::{ActiveSet, EnergyModel, ModelRules, Network};
use crate::solve::{Backend, Cholesky, Equilibrium, SolverTuning, SymbolicFactor};
use std::sync::Arc;

/// A structure holding at most this share of the vertices is factored on its own vertices
/// (the symbolic analysis restricted to them).
const RESTRICT_SHARE: f64 = 0.85;

/// The largest deviation of a vertex from its designed place: the equilibrium's displacements
/// `u` plus the self-weight deflection `sag` (three per vertex), over the vertices `held`
/// marks; `(vertex, distance)`.
pub fn largest_deviation(u: &[f64], sag: &[f64], held: &[bool]) -> (usize, f64) {
    (0..held.len())
        .filter(|&v| held[v])
        .map(|v| {
            let d = (0..3)
                .map(|k| (u[3 * v + k] + sag[3 * v + k]).powi(2))
                .sum::<f64>()
                .sqrt();
            (v, d)
        })
        .fold((0, 0.0), |best, x| if x.1 > best.1 { x } else { best })
}

/// The physical model of one network, built once, measuring the largest deviation of any of
/// its structures (see the module's documentation).
#[derive(Debug)]
pub struct DeviationModel {
    model: EnergyModel,
    symbolic: Arc<SymbolicFactor>,
    params: PhysicalParams,
}

impl DeviationModel {
    /// The model of `network` with the physical parameters `params` (as
    /// [`super::analyze_physical`] builds it).
    pub fn new(network: &Network, params: &PhysicalParams) -> Self {
        let rods = physical_rods(&params.physical, network.rods.len(), &params.rest);
        let anchor = rigid_anchor_weight(network, &rods);
        let model = EnergyModel::with_rules(network, &rods, anchor, ModelRules::PHYSICAL);
        let symbolic = SymbolicFactor::new(model.pattern(), Backend::default());
        DeviationModel {
            model,
            symbolic,
            params: params.clone(),
        }
    }

    /// The largest deviation of a vertex of structure `active` of `network` (the network the
    /// model was built on) from its designed place, scene units; infinite when the structure
    /// has no linear self-weight deflection (its Hessian at equilibrium is not positive
    /// definite).
    pub fn measure(&self, network: &Network, active: &ActiveSet) -> f64 {
        if active.is_empty() {
            return 0.0;
        }
        let keep = self.model.coordinate_mask(active);
        let held = keep.iter().filter(|&&k| k).count();
        let symbolic = if held as f64 > RESTRICT_SHARE * keep.len() as f64 {
            Arc::clone(&self.symbolic)
        } else {
            SymbolicFactor::restricted(&self.symbolic, self.model.pattern(), &keep)
        };
        let mut u = vec![0.0; self.model.dofs()];
        let relaxed = Equilibrium {
            model: &self.model,
            active,
            symbolic: &symbolic,
            params: &self.params.newton,
            tuning: &SolverTuning::default(),
        }
        .relax(&mut u, None);
        let Ok(factor) =
            Cholesky::factorize(&symbolic, self.model.pattern(), &relaxed.hess, 0.0, None)
        else {
            return f64::INFINITY;
        };
        let mut w = self_weight(network, &self.params.physical, active);
        let vertices = w.len();
        w.resize(self.model.dofs(), 0.0);
        factor.solve_vec(&mut w);
        let held = held_vertices(network, active);
        let d = largest_deviation(&u[..vertices], &w[..vertices], &held).1;
        if d.is_finite() { d } else { f64::INFINITY }
    }
}

#[cfg(test)]
mod tests {
    use super::largest_deviation;

    #[test]
    fn the_equilibrium_and_the_sag_add_up() {
        let u = [0.0, 0.0, -1.0, 3.0, 0.0, 0.0];
        let sag = [0.0, 0.0, -2.0, 0.0, 4.0, 0.0];
        assert_eq!(largest_deviation(&u, &sag, &[true, true]), (1, 5.0));
        assert_eq!(largest_deviation(&u, &sag, &[true, false]), (0, 3.0));
    }
}
