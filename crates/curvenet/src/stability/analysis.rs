//! [`Analyzer::analyze`]: `λ_eq` of one structure with everything a report shows (the mode's
//! curves, the gravity deflection).

use super::{Analyzer, StabilityError};
use crate::rod::ActiveSet;
use crate::solve::eigen::Spectrum;
use crate::solve::{Cholesky, NewtonInfo, SymbolicFactor};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

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

impl Analyzer {
    /// `λ_eq(active)`: relaxes from `start` (or the drawn state) and analyses the equilibrium.
    pub fn analyze(
        &self,
        active: &ActiveSet,
        start: Option<&[f64]>,
    ) -> Result<Analysis, StabilityError> {
        if active.is_empty() {
            return Err(StabilityError::Empty);
        }
        let model = self.model();
        let mut u = start.map_or_else(|| vec![0.0; model.dofs()], <[f64]>::to_vec);
        let symbolic = self.symbolic_for(active);
        let newton = self.relax_from(active, &mut u, None, &symbolic).0;
        let h = model.assemble(&u, active, true).hess;
        let (spectrum, ()) = self.in_metric(active, &h, |h| {
            let params = &self.params().eigen;
            let s = super::numerics::spectrum(model.pattern(), h, &symbolic, None, params)?;
            Ok((s, ()))
        })?;
        let mode_curves = self.mode_curves(active, spectrum.vectors.col(0).iter().copied());
        let gravity = self
            .gravity_solve(active, &h, &symbolic)
            .map(|(_, summary)| summary);
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
        let vc = self.network().vertex_curves();
        let mut share = vec![0.0; self.curve_count()];
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
        let g = &self.params().gravity;
        let dir = crate::geom::Vec3::from(g.direction).normalized();
        let mut f = vec![0.0; self.model().dofs()];
        for (c, rod) in self.network().rods.iter().enumerate() {
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
        self.gravity_solve(active, h, &self.symbolic_for(active))
            .map(|(_, summary)| summary)
    }

    /// The displacement field under the gravity load of the structure `active` at the
    /// displacements `u0` (its equilibrium), with its summary: `H(u0) u = f` (None if the
    /// Hessian is not positive definite or the solve is not finite).
    pub fn gravity_at(
        &self,
        active: &ActiveSet,
        u0: &[f64],
    ) -> Option<(Vec<f64>, GravityDeflection)> {
        self.gravity_at_with(active, u0, &self.symbolic_for(active))
    }

    /// [`Self::gravity_at`] factoring with `symbolic`, the analysis
    /// [`Self::symbolic_for`] gives `active` (e.g. [`super::Evaluation::symbolic`] of the
    /// structure, computed already): the same numbers, without analysing the structure again.
    pub fn gravity_at_with(
        &self,
        active: &ActiveSet,
        u0: &[f64],
        symbolic: &Arc<SymbolicFactor>,
    ) -> Option<(Vec<f64>, GravityDeflection)> {
        let h = self.model().assemble(u0, active, true).hess;
        self.gravity_solve(active, &h, symbolic)
    }

    /// `H u = f` under the gravity load, factored with `symbolic` (the structure's own
    /// analysis: a structure holding a small part of the network is factored on its own
    /// vertices).
    fn gravity_solve(
        &self,
        active: &ActiveSet,
        h: &[f64],
        symbolic: &Arc<SymbolicFactor>,
    ) -> Option<(Vec<f64>, GravityDeflection)> {
        let n = self.model().dofs();
        let f = self.gravity_load(active);
        let factor = Cholesky::factorize(symbolic, self.model().pattern(), h, 0.0, None).ok()?;
        let mut u = f.clone();
        factor.solve_vec(&mut u);
        if !u.iter().all(|x| x.is_finite()) {
            return None;
        }
        let compliance: f64 = f.iter().zip(&u).map(|(a, b)| a * b).sum();
        let total_load = f.iter().map(|x| x * x).sum::<f64>().sqrt();
        let (vertex, max_displacement) = (0..n / 3)
            .map(|v| (v, (0..3).map(|k| u[3 * v + k].powi(2)).sum::<f64>().sqrt()))
            .fold((0, 0.0), |best, x| if x.1 > best.1 { x } else { best });
        let summary = GravityDeflection {
            max_displacement,
            vertex,
            compliance,
            total_load,
        };
        Some((u, summary))
    }
}
