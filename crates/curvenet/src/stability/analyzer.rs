//! [`Analyzer`]: one network's energy model, symbolic analysis and caches.

use super::presets::Preset;
use super::{StabilityError, StabilityParams, Tuning};
use crate::network::Network;
use crate::physics::{PhysicalParams, PhysicalSummary, PhysicsError, analyze_physical};
use crate::rod::{ActiveSet, EnergyModel};
use crate::solve::eigen::Spectrum;
use crate::solve::{Cholesky, Equilibrium, NewtonInfo, SymbolicFactor};
use faer::MatRef;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// Stability computations on one network; cheap to share across threads (see the module
/// documentation for what it offers).
#[derive(Debug)]
pub struct Analyzer {
    network: Network,
    model: EnergyModel,
    symbolic: Arc<SymbolicFactor>,
    params: StabilityParams,
    /// `λ_eq` of connected sets already evaluated, with their equilibrium's largest
    /// displacement ([`Self::lambda_eq`], [`Self::parts_of`]).
    pub(super) parts: Mutex<HashMap<Vec<usize>, (f64, f64)>>,
    /// The physical mode's parameters ([`Self::with_physical`]); `None` in the paper's mode.
    physical: Option<PhysicalParams>,
}

impl Analyzer {
    /// Builds the energy model and the symbolic factorization of `network`.
    pub fn new(network: Network, params: StabilityParams) -> Result<Self, String> {
        params.validate()?;
        let model = EnergyModel::new(&network, &params.material);
        let symbolic = SymbolicFactor::new(model.pattern(), params.tuning.solver.backend);
        Ok(Analyzer {
            network,
            model,
            symbolic,
            params,
            parts: Mutex::default(),
            physical: None,
        })
    }

    /// The analyzer in the physical mode: the searches also record each structure's physical
    /// numbers ([`Self::physical_summary`]). The objective (`λ_eq`, of the paper's model) is
    /// unchanged.
    ///
    /// # Errors
    ///
    /// Invalid physical parameters.
    pub fn with_physical(mut self, physical: PhysicalParams) -> Result<Self, String> {
        physical.validate()?;
        self.physical = Some(physical);
        Ok(self)
    }

    /// The physical mode's parameters (`None` in the paper's mode).
    pub fn physical(&self) -> Option<&PhysicalParams> {
        self.physical.as_ref()
    }

    /// The physical numbers of the structure `active` in the physical mode (`None` in the
    /// paper's mode): its own model's equilibrium, frequencies, deflections and stresses.
    ///
    /// # Errors
    ///
    /// The physical analysis failed (its eigen solver).
    pub fn physical_summary(
        &self,
        active: &ActiveSet,
    ) -> Result<Option<PhysicalSummary>, StabilityError> {
        let Some(p) = &self.physical else {
            return Ok(None);
        };
        match analyze_physical(&self.network, p, active) {
            Ok(r) => Ok(Some(r.summary())),
            Err(PhysicsError::Eigen(e)) => Err(StabilityError::Eigen(e)),
            Err(e) => Err(StabilityError::Params(e.to_string())),
        }
    }

    /// The network.
    pub fn network(&self) -> &Network {
        &self.network
    }

    /// The energy model.
    pub fn model(&self) -> &EnergyModel {
        &self.model
    }

    /// The shared symbolic factorization of the whole pattern.
    pub fn symbolic(&self) -> &Arc<SymbolicFactor> {
        &self.symbolic
    }

    /// The parameters.
    pub fn params(&self) -> &StabilityParams {
        &self.params
    }

    /// The speed-only knobs.
    pub fn tuning(&self) -> &Tuning {
        &self.params.tuning
    }

    /// Number of curves.
    pub fn curve_count(&self) -> usize {
        self.network.rods.len()
    }

    /// Rest length of every curve.
    pub fn lengths(&self) -> Vec<f64> {
        self.network.rest_lengths()
    }

    /// Total rest length of `curves`.
    pub fn total_length(&self, curves: &[usize]) -> f64 {
        self.network.total_length(curves)
    }

    /// All curves.
    pub fn all(&self) -> ActiveSet {
        ActiveSet::all(self.curve_count())
    }

    /// The set of `curves` (ids below [`Self::curve_count`]).
    pub fn set(&self, curves: &[usize]) -> ActiveSet {
        ActiveSet::from_curves(self.curve_count(), curves)
    }

    /// The connected parts of `active` (curves joined through shared vertices), each sorted,
    /// in order of their smallest curve.
    pub fn components(&self, active: &ActiveSet) -> Vec<Vec<usize>> {
        let links = self
            .model
            .vertex_curves()
            .iter()
            .map(|cs| cs.iter().map(|&c| c as usize));
        crate::network::subnet::curve_components(active.universe(), &active.curves(), links)
    }

    /// The symbolic analysis for the matrices of structure `active` (and of its
    /// sub-structures): the whole pattern's while `active` holds more than
    /// [`Tuning::restrict_share`] of the vertices, otherwise one restricted to `active`'s
    /// vertices ([`SymbolicFactor::restricted`]) — the other vertices are loose, decoupled,
    /// so the factorizations only need to see `active`'s. A pure function of `active`: which
    /// analysis a computation uses never depends on what ran before it.
    pub fn symbolic_for(&self, active: &ActiveSet) -> Arc<SymbolicFactor> {
        let mask = self.model.vertex_mask(active);
        let held = mask.iter().filter(|&&m| m).count();
        if held as f64 > self.params.tuning.restrict_share * mask.len() as f64 {
            return self.symbolic.clone();
        }
        let keep: Vec<bool> = mask.iter().flat_map(|&m| [m; 3]).collect();
        SymbolicFactor::restricted(&self.symbolic, self.model.pattern(), &keep)
    }

    /// Relaxes `active` from displacements `u` (updated in place). The relative tolerance is
    /// measured against the structure's gradient in the drawn state, whatever `u` starts at.
    pub fn relax(&self, active: &ActiveSet, u: &mut [f64]) -> NewtonInfo {
        self.relax_from(active, u, None, &self.symbolic_for(active))
            .0
    }

    /// [`Self::relax`] whose first steps reuse `factor` (a factorization of a nearby Hessian
    /// of the same structure), factoring with `symbolic` (one of [`Self::symbolic_for`]
    /// `active` or a superset of it); also hands out the Hessian at the equilibrium.
    pub(super) fn relax_from(
        &self,
        active: &ActiveSet,
        u: &mut [f64],
        factor: Option<Cholesky>,
        symbolic: &Arc<SymbolicFactor>,
    ) -> (NewtonInfo, Vec<f64>) {
        let relaxed = Equilibrium {
            model: &self.model,
            active,
            symbolic,
            params: &self.params.newton,
            tuning: &self.params.tuning.solver,
        }
        .relax(u, factor);
        (relaxed.info, relaxed.hess)
    }

    /// Smallest eigenpairs of `active`'s Hessian at displacements `u` (no relaxation):
    /// `λ_fix(active | A)` when `u` is the equilibrium of `A`.
    pub fn spectrum(
        &self,
        active: &ActiveSet,
        u: &[f64],
        warm_start: Option<MatRef<'_, f64>>,
    ) -> Result<Spectrum, StabilityError> {
        self.spectrum_preset(active, u, warm_start, Preset::Analysis)
    }

    /// [`Self::spectrum`] to the accuracy of `preset`.
    pub(super) fn spectrum_preset(
        &self,
        active: &ActiveSet,
        u: &[f64],
        warm_start: Option<MatRef<'_, f64>>,
        preset: Preset,
    ) -> Result<Spectrum, StabilityError> {
        if active.is_empty() {
            return Err(StabilityError::Empty);
        }
        let h = self.model.assemble(u, active, true).hess;
        Ok(super::numerics::spectrum(
            self.model.pattern(),
            &h,
            &self.symbolic_for(active),
            warm_start,
            &preset.params(&self.params.eigen),
        )?)
    }

    /// The eigen parameters of `preset` for factors of `symbolic`.
    pub(super) fn eigen(&self, preset: Preset, symbolic: &SymbolicFactor) -> super::EigenParams {
        preset.params_for(
            &self.params.eigen,
            &self.params.tuning,
            symbolic.factor_nnz(),
        )
    }
}
