//! Worst-case stability of a network or of any sub-structure (SPEC §5).
//!
//! An [`Analyzer`] owns the energy model and the symbolic factorization of one network and
//! answers, for any set of curves `S`:
//!
//! - [`Analyzer::relax`]: the equilibrium of `S` (Newton, warm-startable);
//! - [`Analyzer::spectrum`]: the smallest eigenpairs of `S`'s Hessian at given displacements —
//!   `λ_fix(S | A)` when the displacements are `A`'s equilibrium;
//! - [`Analyzer::analyze`]: `λ_eq(S)` — relax `S`, then its spectrum, the worst-case load and
//!   deformation, the curves where the mode lives, and the gravity deflection.

use crate::network::Network;
use crate::rod::{ActiveSet, EnergyModel, Material};
use crate::solve::eigen::{EigenError, EigenOptions, EigenParams, Spectrum, Start};
use crate::solve::{
    Cholesky, Equilibrium, NewtonInfo, NewtonParams, SolverTuning, SymbolicFactor,
    smallest_eigenpairs,
};
use faer::MatRef;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Parameters of every stability computation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StabilityParams {
    /// Material constants.
    pub material: Material,
    /// Equilibrium solver.
    pub newton: NewtonParams,
    /// Eigen solver.
    pub eigen: EigenParams,
    /// Gravity load for the deflection report.
    pub gravity: GravityParams,
    /// The solvers' speed knobs (the factorization backend, Newton's techniques).
    pub solver: SolverTuning,
    /// A structure holding at most this share of the network's vertices is factored on its
    /// own vertices only (see [`Analyzer::symbolic_for`]); 0 factors every structure on the
    /// whole pattern. Only the work changes, not the results (beyond round-off).
    pub restrict_share: f64,
}

impl Default for StabilityParams {
    fn default() -> Self {
        StabilityParams {
            material: Material::default(),
            newton: NewtonParams::default(),
            eigen: EigenParams::default(),
            gravity: GravityParams::default(),
            solver: SolverTuning::default(),
            restrict_share: 0.85,
        }
    }
}

impl StabilityParams {
    /// Checks every part.
    pub fn validate(&self) -> Result<(), String> {
        if !(0.0..=1.0).contains(&self.restrict_share) {
            return Err(format!(
                "restrict_share must lie in [0, 1], got {}",
                self.restrict_share
            ));
        }
        self.material.validate()?;
        self.newton.validate()?;
        self.solver.validate()?;
        self.eigen.validate()?;
        self.gravity.validate()
    }
}

/// Gravity load: a weight per unit rest length on every vertex, along `direction`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GravityParams {
    /// Weight per unit length.
    pub weight_per_length: f64,
    /// Direction of the load (normalised on use).
    pub direction: [f64; 3],
}

impl Default for GravityParams {
    fn default() -> Self {
        GravityParams {
            weight_per_length: 1.0,
            direction: [0.0, 0.0, -1.0],
        }
    }
}

impl GravityParams {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), String> {
        let d = self.direction;
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let weight_ok = self.weight_per_length.is_finite() && self.weight_per_length >= 0.0;
        if !(weight_ok && n > 0.0 && n.is_finite()) {
            return Err(
                "gravity needs a finite non-negative weight and a non-zero direction".into(),
            );
        }
        Ok(())
    }
}

/// Share of the worst-case mode carried by one curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CurveShare {
    /// Curve id.
    pub curve: usize,
    /// Fraction of `‖v‖²` on the curve's vertices (shared vertices split evenly).
    pub share: f64,
}

/// Deflection under the gravity load, `H u = f`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GravityDeflection {
    /// Largest vertex displacement.
    pub max_displacement: f64,
    /// The vertex where it occurs.
    pub vertex: usize,
    /// Compliance `fᵀu` (work of the load).
    pub compliance: f64,
    /// Total load applied.
    pub total_load: f64,
}

/// Why an analysis failed.
#[derive(Debug, thiserror::Error)]
pub enum StabilityError {
    /// Eigen solver failure.
    #[error(transparent)]
    Eigen(#[from] EigenError),
    /// The structure has no curves.
    #[error("the structure has no curves")]
    Empty,
    /// Invalid parameters.
    #[error("invalid parameters: {0}")]
    Params(String),
}

/// `λ_eq` of a structure, with everything a report needs.
#[derive(Clone, Debug)]
pub struct Analysis {
    /// The equilibrium solve.
    pub newton: NewtonInfo,
    /// Displacements from the rest state at equilibrium.
    pub displacement: Vec<f64>,
    /// Smallest eigenpairs at equilibrium.
    pub spectrum: Spectrum,
    /// Curves carrying the worst-case mode, largest share first.
    pub mode_curves: Vec<CurveShare>,
    /// Gravity deflection, `None` when the structure is not positive definite.
    pub gravity: Option<GravityDeflection>,
}

impl Analysis {
    /// `λ`: the smallest eigenvalue at equilibrium.
    pub fn lambda(&self) -> f64 {
        self.spectrum.lambda()
    }

    /// The worst-case load (unit eigenvector of `λ`).
    pub fn mode(&self) -> Vec<f64> {
        self.spectrum.vectors.col(0).iter().copied().collect()
    }
}

/// Stability computations on one network; cheap to share across threads.
#[derive(Debug)]
pub struct Analyzer {
    network: Network,
    model: EnergyModel,
    symbolic: Arc<SymbolicFactor>,
    params: StabilityParams,
}

impl Analyzer {
    /// Builds the energy model and the symbolic factorization of `network`.
    pub fn new(network: Network, params: StabilityParams) -> Result<Self, String> {
        params.validate()?;
        let model = EnergyModel::new(&network, &params.material);
        let symbolic = SymbolicFactor::new(model.pattern(), params.solver.backend);
        Ok(Analyzer {
            network,
            model,
            symbolic,
            params,
        })
    }

    /// The network.
    pub fn network(&self) -> &Network {
        &self.network
    }

    /// The energy model.
    pub fn model(&self) -> &EnergyModel {
        &self.model
    }

    /// The shared symbolic factorization.
    pub fn symbolic(&self) -> &Arc<SymbolicFactor> {
        &self.symbolic
    }

    /// The symbolic analysis for the matrices of structure `active` (and of its
    /// sub-structures): the whole pattern's while `active` holds more than
    /// [`StabilityParams::restrict_share`] of the vertices, otherwise one restricted to `active`'s vertices
    /// (see [`SymbolicFactor::restricted`]) — the other vertices are loose, decoupled, so the
    /// factorizations only need to see `active`'s. A pure function of `active`: which analysis
    /// a computation uses never depends on what ran before it.
    pub fn symbolic_for(&self, active: &ActiveSet) -> Arc<SymbolicFactor> {
        let mask = self.model.vertex_mask(active);
        let held = mask.iter().filter(|&&m| m).count();
        if held as f64 > self.params.restrict_share * mask.len() as f64 {
            return self.symbolic.clone();
        }
        let keep: Vec<bool> = mask.iter().flat_map(|&m| [m; 3]).collect();
        SymbolicFactor::restricted(&self.symbolic, self.model.pattern(), &keep)
    }

    /// The parameters.
    pub fn params(&self) -> &StabilityParams {
        &self.params
    }

    /// All curves.
    pub fn all(&self) -> ActiveSet {
        ActiveSet::all(self.network.rods.len())
    }

    /// Relaxes `active` from displacements `u` (updated in place). The relative tolerance is
    /// measured against the structure's gradient in the drawn state, whatever `u` starts at.
    pub fn relax(&self, active: &ActiveSet, u: &mut [f64]) -> NewtonInfo {
        self.relax_with(active, u, None, &self.symbolic_for(active))
    }

    /// [`Self::relax`] whose first steps reuse `factor`, a factorization of a nearby Hessian
    /// of the same structure, with the symbolic analysis given (one of [`Self::symbolic_for`]
    /// `active` or a superset of it).
    pub fn relax_with(
        &self,
        active: &ActiveSet,
        u: &mut [f64],
        factor: Option<Cholesky>,
        symbolic: &Arc<SymbolicFactor>,
    ) -> NewtonInfo {
        self.relax_assembled(active, u, factor, symbolic).0
    }

    /// [`Self::relax_with`], also handing out the Hessian values at the equilibrium
    /// ([`crate::solve::Relaxed`]).
    pub fn relax_assembled(
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
            tuning: &self.params.solver,
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
        if active.is_empty() {
            return Err(StabilityError::Empty);
        }
        let h = self.model.assemble(u, active, true).hess;
        Ok(self.spectrum_of(active, &h, &self.symbolic_for(active), warm_start)?)
    }

    /// The smallest eigenpairs of Hessian values `h` of `active` with `symbolic`.
    fn spectrum_of(
        &self,
        active: &ActiveSet,
        h: &[f64],
        symbolic: &Arc<SymbolicFactor>,
        warm_start: Option<MatRef<'_, f64>>,
    ) -> Result<Spectrum, EigenError> {
        debug_assert!(!active.is_empty());
        let options = EigenOptions {
            start: warm_start.map_or(Start::Random, Start::Vectors),
            ..Default::default()
        };
        let found = smallest_eigenpairs(
            symbolic,
            self.model.pattern(),
            h,
            &self.params.eigen,
            options,
        )?;
        Ok(found.expect("a shift below zero always factors").spectrum)
    }

    /// `λ_eq(active)`: relaxes from `start` (or the drawn state) and analyses the equilibrium.
    pub fn analyze(
        &self,
        active: &ActiveSet,
        start: Option<&[f64]>,
    ) -> Result<Analysis, StabilityError> {
        if active.is_empty() {
            return Err(StabilityError::Empty);
        }
        let mut u = start.map_or_else(|| vec![0.0; self.model.dofs()], <[f64]>::to_vec);
        let symbolic = self.symbolic_for(active);
        let newton = self.relax_with(active, &mut u, None, &symbolic);
        let h = self.model.assemble(&u, active, true).hess;
        let spectrum = self.spectrum_of(active, &h, &symbolic, None)?;
        let mode_curves = self.mode_curves(active, spectrum.vectors.col(0).iter().copied());
        let gravity = self.gravity(active, &h);
        Ok(Analysis {
            newton,
            displacement: u,
            spectrum,
            mode_curves,
            gravity,
        })
    }

    /// Share of `‖v‖²` per active curve, largest first (ties by id).
    pub fn mode_curves(&self, active: &ActiveSet, v: impl Iterator<Item = f64>) -> Vec<CurveShare> {
        let v: Vec<f64> = v.collect();
        let vc = self.network.vertex_curves();
        let mut share = vec![0.0; self.network.rods.len()];
        let mut total = 0.0;
        for (vert, curves) in vc.iter().enumerate() {
            let on: Vec<usize> = curves
                .iter()
                .map(|&c| c as usize)
                .filter(|&c| active.contains(c))
                .collect();
            if on.is_empty() {
                continue;
            }
            let e: f64 = (0..3).map(|a| v[3 * vert + a].powi(2)).sum();
            total += e;
            for &c in &on {
                share[c] += e / on.len() as f64;
            }
        }
        let mut out: Vec<CurveShare> = active
            .curves()
            .into_iter()
            .map(|c| CurveShare {
                curve: c,
                share: if total > 0.0 { share[c] / total } else { 0.0 },
            })
            .collect();
        out.sort_by(|a, b| b.share.total_cmp(&a.share).then(a.curve.cmp(&b.curve)));
        out
    }

    /// The gravity load on the curves of `active`: `weight_per_length` along the gravity
    /// direction, half of each edge's weight on each of its ends.
    pub fn gravity_load(&self, active: &ActiveSet) -> Vec<f64> {
        let g = &self.params.gravity;
        let dir = crate::geom::Vec3::from(g.direction).normalized();
        let mut f = vec![0.0; self.model.dofs()];
        for (c, rod) in self.network.rods.iter().enumerate() {
            if !active.contains(c) {
                continue;
            }
            for j in 0..rod.edge_count() {
                let (a, b) = rod.edge(j);
                let w = 0.5 * g.weight_per_length * rod.rest_lengths[j];
                for k in 0..3 {
                    f[3 * a as usize + k] += w * dir[k];
                    f[3 * b as usize + k] += w * dir[k];
                }
            }
        }
        f
    }

    /// Deflection under the gravity load with Hessian values `h` (None if not positive
    /// definite).
    pub fn gravity(&self, active: &ActiveSet, h: &[f64]) -> Option<GravityDeflection> {
        let n = self.model.dofs();
        let f = self.gravity_load(active);
        let factor =
            Cholesky::factorize(&self.symbolic, self.model.pattern(), h, 0.0, None).ok()?;
        let mut u = f.clone();
        factor.solve_vec(&mut u);
        let compliance: f64 = f.iter().zip(&u).map(|(a, b)| a * b).sum();
        let total_load = f.iter().map(|x| x * x).sum::<f64>().sqrt();
        let (vertex, max_displacement) = (0..n / 3)
            .map(|v| (v, (0..3).map(|k| u[3 * v + k].powi(2)).sum::<f64>().sqrt()))
            .fold((0, 0.0), |best, x| if x.1 > best.1 { x } else { best });
        Some(GravityDeflection {
            max_displacement,
            vertex,
            compliance,
            total_load,
        })
    }
}
