//! [`Analyzer`]: one network's energy model, symbolic analysis and caches.

use super::presets::Preset;
use super::{Objective, StabilityError, StabilityParams, Tuning};
use crate::network::Network;
use crate::physics::inertia::classify;
use crate::physics::{
    DeviationModel, PhysicalParams, PhysicalSummary, PhysicsError, analyze_physical,
};
use crate::rod::mass::{
    inverse_sqrt_coordinates, inverse_sqrt_with_twists, lumped_masses, scale_hessian, twist_masses,
};
use crate::rod::physical::{
    masses_per_length, physical_rods, rigid_anchor_weight, twist_masses_per_length,
};
use crate::rod::{ActiveSet, EnergyModel, ModelRules, RodStiffness};
use crate::solve::eigen::Spectrum;
use crate::solve::{Cholesky, Equilibrium, NewtonInfo, SymbolicFactor};
use faer::MatRef;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// Stability computations on one network; cheap to share across threads (see the module
/// documentation for what it offers).
#[derive(Debug)]
pub struct Analyzer {
    network: Network,
    model: EnergyModel,
    /// The whole pattern's symbolic analysis, made when first needed ([`Self::symbolic`]): an
    /// analyzer whose factorizations all use analyses made elsewhere (the viewer's gravity
    /// thread's) never makes it.
    symbolic: OnceLock<Arc<SymbolicFactor>>,
    params: StabilityParams,
    /// `λ_eq` of connected sets already evaluated, with their equilibrium's largest
    /// displacement ([`Self::lambda_eq`], [`Self::parts_of`]).
    pub(super) parts: Mutex<HashMap<Vec<usize>, (f64, f64)>>,
    /// The physical mode's parameters ([`Self::with_physical`]); `None` in the paper's mode.
    physical: Option<PhysicalParams>,
    /// The physical mode's load cases as given ([`Self::load_cases`]; `None`: none given).
    loaded: Option<PhysicalParams>,
    /// The physical mode's largest-deviation model, built when first asked for
    /// ([`Self::part_deviation`]).
    pub(super) deviation_model: OnceLock<DeviationModel>,
    /// The physical mode's largest deviation of connected sets already measured.
    pub(super) physical_deviations: Mutex<HashMap<Vec<usize>, f64>>,
    /// The frequency objective's model: the mass metric, and in the physical mode the rods'
    /// own stiffnesses (`None`: the paper's `λ_eq`).
    metric: Option<Metric>,
}

/// What the frequency objective ([`Objective::Frequency`]) adds to an analyzer: the mass
/// per unit length of every rod, and the energy's constants when they are not the paper
/// material's (the physical mode), so that the analyzer of a sub-network has the same model.
#[derive(Clone, Debug)]
struct Metric {
    mass_per_length: Vec<f64>,
    /// The twist unknowns' mass per unit length of every rod, `ρ J / r²` (the physical mode's
    /// pre-bent rods carry their twist; empty: no twists).
    twist_mass_per_length: Vec<f64>,
    /// Per-rod stiffnesses and the anchor weight (the physical mode).
    rods: Option<(Vec<RodStiffness>, f64)>,
}

impl Analyzer {
    /// Builds the energy model of `network` (its symbolic analysis is made when first
    /// needed: [`Self::symbolic`]).
    ///
    /// With [`Objective::Frequency`] the spectra are those of the mass metric with unit
    /// density (`ρ A = π r²` per unit length: the paper's model has no material), until
    /// [`Self::with_physical`] gives the rods' own.
    ///
    /// # Errors
    ///
    /// [`StabilityError::Params`] for invalid parameters.
    pub fn new(network: Network, params: StabilityParams) -> Result<Self, StabilityError> {
        params.validate().map_err(StabilityError::Params)?;
        let metric = (params.objective == Objective::Frequency).then(|| Metric {
            mass_per_length: vec![
                std::f64::consts::PI * params.material.radius.powi(2);
                network.rods.len()
            ],
            twist_mass_per_length: Vec::new(),
            rods: None,
        });
        Ok(Self::build(network, params, metric))
    }

    fn build(network: Network, params: StabilityParams, metric: Option<Metric>) -> Self {
        let model = match metric.as_ref().and_then(|m| m.rods.as_ref()) {
            Some((rods, anchor)) => {
                EnergyModel::with_rules(&network, rods, *anchor, ModelRules::PHYSICAL)
            }
            None => EnergyModel::new(&network, &params.material),
        };
        Analyzer {
            network,
            model,
            symbolic: OnceLock::new(),
            params,
            parts: Mutex::default(),
            physical: None,
            loaded: None,
            deviation_model: OnceLock::new(),
            physical_deviations: Mutex::default(),
            metric,
        }
    }

    /// The analyzer in the physical mode: the searches also record each structure's physical
    /// numbers ([`Self::physical_summary`]). With the objective `λ_eq` the searches' model
    /// stays the paper's; with [`Objective::Frequency`] it becomes the structure's own (per-rod
    /// `E A`, `E I`, rest shapes, rigid anchors, the rods' `ρ A`), so the objective is the
    /// physical analysis' `μ_min`: its first natural frequency is `√μ_min / 2π` Hz.
    ///
    /// # Errors
    ///
    /// [`StabilityError::Params`] for invalid physical parameters.
    pub fn with_physical(mut self, mut physical: PhysicalParams) -> Result<Self, StabilityError> {
        physical.validate().map_err(StabilityError::Params)?;
        // The searches record each structure's own figures, not its load cases' (each case
        // follows its load in steps): those of the networks offered to build are asked for
        // apart ([`Self::load_cases`]).
        self.loaded = physical.loads.is_some().then(|| physical.clone());
        physical.loads = None;
        if self.metric.is_some() {
            let n = self.network.rods.len();
            let rods = physical_rods(&physical.physical, n, &physical.rest);
            let anchor = rigid_anchor_weight(&self.network, &rods);
            let metric = Metric {
                mass_per_length: masses_per_length(&physical.physical, n),
                twist_mass_per_length: twist_masses_per_length(&physical.physical, n),
                rods: Some((rods, anchor)),
            };
            self = Self::build(self.network, self.params, Some(metric));
        }
        self.physical = Some(physical);
        Ok(self)
    }

    /// Whether the spectra are the mass metric's (the frequency objective).
    pub(super) fn mass_metric(&self) -> bool {
        self.metric.is_some()
    }

    /// What the searches maximise.
    pub fn objective(&self) -> Objective {
        self.params.objective
    }

    /// The analyzer of `network`, the sub-network of `curves` (in that order) of this one,
    /// with the same model: the paper's material, or the same rods, anchor weight and masses
    /// under the frequency objective.
    pub(super) fn for_sub_network(
        &self,
        network: Network,
        curves: &[usize],
        params: StabilityParams,
    ) -> Result<Self, crate::words::Message> {
        params.validate()?;
        let metric = self.metric.as_ref().map(|m| Metric {
            mass_per_length: curves.iter().map(|&c| m.mass_per_length[c]).collect(),
            twist_mass_per_length: curves
                .iter()
                .filter_map(|&c| m.twist_mass_per_length.get(c).copied())
                .collect(),
            rods: m
                .rods
                .as_ref()
                .map(|(r, a)| (curves.iter().map(|&c| r[c]).collect(), *a)),
        });
        Ok(Self::build(network, params, metric))
    }

    /// The objective's metric for structure `active`: `1/√m` per coordinate, `m` the lumped
    /// masses ([`crate::rod::mass`]), and a pre-bent rod's twists their rotational inertia,
    /// as the physical analysis has them; `None` for `λ_eq` (the identity metric).
    pub(super) fn metric_scale(&self, active: &ActiveSet) -> Option<Vec<f64>> {
        let m = self.metric.as_ref()?;
        let masses = lumped_masses(&self.network, &m.mass_per_length, active);
        let twists = self.model.twist_dofs();
        if twists.is_empty() {
            return Some(inverse_sqrt_coordinates(&masses));
        }
        let inertia = twist_masses(&self.network, twists, &m.twist_mass_per_length);
        Some(inverse_sqrt_with_twists(&masses, &inertia))
    }

    /// Hessian values `h` of structure `active` in the objective's metric, in place
    /// (`M^{-1/2} H M^{-1/2}` under the frequency objective, unchanged for `λ_eq`); the scale
    /// used, if any.
    pub(super) fn to_metric(&self, active: &ActiveSet, h: &mut [f64]) -> Option<Vec<f64>> {
        let s = self.metric_scale(active)?;
        scale_hessian(self.model.pattern(), h, &s);
        Some(s)
    }

    /// The spectrum of `h` (the unscaled Hessian values of `active`) computed in the
    /// objective's metric with `compute`: for `λ_eq` as it is; under the frequency objective
    /// on `M^{-1/2} H M^{-1/2}`, its zero and negative modes judged in the identity metric as
    /// `λ_eq`'s are (each mode's Rayleigh quotient in `H` against the band `C ε ‖H‖₁`:
    /// near-massless vertices cannot widen the band; the signs are `H`'s by Sylvester's law).
    pub(super) fn in_metric<T>(
        &self,
        active: &ActiveSet,
        h: &[f64],
        compute: impl FnOnce(&[f64]) -> Result<(Spectrum, T), StabilityError>,
    ) -> Result<(Spectrum, T), StabilityError> {
        let Some(s) = self.metric_scale(active) else {
            return compute(h);
        };
        let mut scaled = h.to_vec();
        scale_hessian(self.model.pattern(), &mut scaled, &s);
        let (mut spectrum, extra) = compute(&scaled)?;
        let keep = self.model.coordinate_mask(active);
        let signs = classify(
            &spectrum,
            self.model.pattern(),
            h,
            &s,
            &keep,
            self.params.eigen.zero_factor,
        );
        spectrum.zero_modes = signs.zero;
        spectrum.negative_modes = signs.negative;
        Ok((spectrum, extra))
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
        self.physical
            .as_ref()
            .map(|p| self.analyze_physical(p, active).map(|r| r.summary()))
            .transpose()
    }

    /// [`Self::physical_summary`] of a network offered to build, with its load cases when
    /// the physical mode was given some: one analysis gives both.
    ///
    /// # Errors
    ///
    /// The physical analysis failed.
    pub fn offered_physical_summary(
        &self,
        active: &ActiveSet,
    ) -> Result<Option<PhysicalSummary>, StabilityError> {
        self.physical_with_loads()
            .map(|p| self.analyze_physical(p, active).map(|r| r.summary()))
            .transpose()
    }

    /// The physical analysis of `active` with `params`, its errors the analyzer's.
    fn analyze_physical(
        &self,
        params: &PhysicalParams,
        active: &ActiveSet,
    ) -> Result<crate::physics::PhysicalReport, StabilityError> {
        analyze_physical(&self.network, params, active).map_err(|e| match e {
            PhysicsError::Eigen(e) => StabilityError::Eigen(e),
            e => StabilityError::Params(e.to_string().into()),
        })
    }

    /// The physical mode's parameters with the load cases given (the server's full analysis
    /// of its current structure); `None` in the paper's mode.
    pub fn physical_with_loads(&self) -> Option<&PhysicalParams> {
        self.loaded.as_ref().or(self.physical.as_ref())
    }

    /// The structure `active`'s load cases, when the physical mode was given some (empty
    /// otherwise): each followed as a nonlinear equilibrium, with its verdict and critical
    /// load factor ([`crate::physics::loaded`]).
    ///
    /// # Errors
    ///
    /// The physical analysis failed.
    pub fn load_cases(
        &self,
        active: &ActiveSet,
    ) -> Result<Vec<crate::physics::loaded::LoadCaseReport>, StabilityError> {
        match &self.loaded {
            Some(p) => Ok(self.analyze_physical(p, active)?.load_cases),
            None => Ok(Vec::new()),
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
        self.symbolic.get_or_init(|| {
            SymbolicFactor::new(self.model.pattern(), self.params.tuning.solver.backend)
        })
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
            return self.symbolic().clone();
        }
        let keep = self.model.coordinate_mask(active);
        SymbolicFactor::restricted(self.symbolic(), self.model.pattern(), &keep)
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
        let relaxed = self.equilibrium(active, symbolic).relax(u, factor);
        (relaxed.info, relaxed.hess)
    }

    /// [`Self::relax`] from displacements `u` near the equilibrium (a nearby structure's):
    /// one factorization preconditions every later step ([`Equilibrium::relax_near`]),
    /// factoring with `symbolic`; also hands out the Hessian at the equilibrium.
    pub(super) fn relax_near(
        &self,
        active: &ActiveSet,
        u: &mut [f64],
        symbolic: &Arc<SymbolicFactor>,
    ) -> (NewtonInfo, Vec<f64>) {
        let relaxed = self.equilibrium(active, symbolic).relax_near(u);
        (relaxed.info, relaxed.hess)
    }

    /// The equilibrium problem of `active`, factored with `symbolic`.
    fn equilibrium<'a>(
        &'a self,
        active: &'a ActiveSet,
        symbolic: &'a Arc<SymbolicFactor>,
    ) -> Equilibrium<'a> {
        Equilibrium {
            model: &self.model,
            active,
            symbolic,
            params: &self.params.newton,
            tuning: &self.params.tuning.solver,
        }
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
        let symbolic = self.symbolic_for(active);
        let params = preset.params(&self.params.eigen);
        let (spectrum, ()) = self.in_metric(active, &h, |h| {
            let s =
                super::numerics::spectrum(self.model.pattern(), h, &symbolic, warm_start, &params)?;
            Ok((s, ()))
        })?;
        Ok(spectrum)
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
