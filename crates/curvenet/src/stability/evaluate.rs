//! [`Analyzer::evaluate`]: `λ_eq` of a structure the way the searches need it — warm-started
//! from a previous step, the spectrum to a preset's accuracy, and what the next candidate
//! search needs prepared beside it.

use super::candidates::Terms;
use super::numerics;
use super::presets::Preset;
use super::{Analyzer, StabilityError};
use crate::rod::ActiveSet;
use crate::solve::eigen::Spectrum;
use crate::solve::{Cholesky, NewtonInfo, SymbolicFactor};
use faer::{Mat, MatRef};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// `λ_eq` of a structure: its equilibrium and spectrum.
#[derive(Debug)]
pub struct Evaluation {
    /// Curves of the structure, ascending.
    pub curves: Vec<usize>,
    /// Total rest length.
    pub length: f64,
    /// The equilibrium solve.
    pub newton: NewtonInfo,
    /// Displacements at equilibrium.
    pub displacement: Vec<f64>,
    /// Spectrum at equilibrium.
    pub spectrum: Spectrum,
    /// Factorizations and solves it took.
    pub work: Work,
    /// The factorization of `H − σI` at equilibrium that the spectrum used (the candidates'
    /// preconditioner).
    pub(super) factor: Arc<Cholesky>,
    /// The symbolic analysis its factorizations used ([`Analyzer::symbolic_for`] the
    /// structure), good for every structure inside it.
    pub(super) symbolic: Arc<SymbolicFactor>,
    /// The candidates' terms at the equilibrium, when asked for ([`Prepare::Candidates`]).
    pub(super) terms: Option<Terms>,
}

impl Evaluation {
    /// The symbolic analysis of its structure ([`Analyzer::symbolic_for`] it), which
    /// factorizations of the structure's matrices can reuse.
    pub fn symbolic(&self) -> &Arc<SymbolicFactor> {
        &self.symbolic
    }

    /// `λ_eq` (`μ_min` under the frequency objective: the objective's value).
    pub fn lambda(&self) -> f64 {
        self.spectrum.lambda()
    }
}

/// Where an evaluation starts and what a previous step hands it; everything but the start
/// only changes the work (and round-off: the same `Warm` gives the same result).
#[derive(Debug, Default)]
pub struct Warm {
    /// Displacements Newton starts from (`None`: the drawn state).
    pub(super) start: Option<Vec<f64>>,
    /// A factorization of a nearby Hessian of the same structure: Newton's first steps reuse
    /// it.
    pub(super) factor: Option<Cholesky>,
    /// Approximate low modes (columns): the eigen solver starts from them.
    pub(super) modes: Option<Mat<f64>>,
    /// The symbolic analysis of a structure containing this one: Newton factors with it
    /// while the structure's own analysis, which the spectrum uses, is computed beside.
    pub(super) superset: Option<Arc<SymbolicFactor>>,
    /// An estimate of `λ_eq`: the spectrum is computed about a shift just below it when that
    /// shift proves to lie below every eigenvalue.
    pub(super) lambda: Option<f64>,
}

impl Warm {
    /// Newton starts from displacements `u`.
    pub fn start(u: Vec<f64>) -> Self {
        Warm {
            start: Some(u),
            ..Warm::default()
        }
    }

    /// With an estimate of `λ_eq` (e.g. the removed candidate's score).
    pub fn lambda(mut self, estimate: f64) -> Self {
        self.lambda = Some(estimate);
        self
    }

    /// The same start without anything else ([`super::Tuning::warm_start`] off).
    fn start_only(self) -> Self {
        Warm {
            start: self.start,
            ..Warm::default()
        }
    }
}

/// What an evaluation prepares beside its spectrum (whose solves leave a core idle).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Prepare {
    /// Nothing.
    #[default]
    Nothing,
    /// The terms of the candidate search at the equilibrium ([`super::candidates`]).
    Candidates,
}

/// Counts of the expensive operations, for benchmarks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Work {
    /// Sparse numeric factorizations.
    pub factorizations: usize,
    /// Solves with a factor (one per right-hand side).
    pub solves: usize,
}

impl Work {
    /// Adds `other` to `self`.
    pub fn add(&mut self, other: Work) {
        self.factorizations += other.factorizations;
        self.solves += other.solves;
    }
}

impl Analyzer {
    /// `λ_eq(active)`: relaxes from `warm`'s start (warm-started as it says, unless
    /// [`super::Tuning::warm_start`] is off) and computes the spectrum to the accuracy of
    /// `preset`, preparing `prepare` beside it. Under the frequency objective the spectrum is
    /// the mass metric's ([`super::Objective::Frequency`]): `lambda()` is `μ_min`.
    pub fn evaluate(
        &self,
        active: &ActiveSet,
        warm: Warm,
        preset: Preset,
        prepare: Prepare,
    ) -> Result<Evaluation, StabilityError> {
        if active.is_empty() {
            return Err(StabilityError::Empty);
        }
        let warm = if self.tuning().warm_start {
            warm
        } else {
            warm.start_only()
        };
        let model = self.model();
        let mut u = warm.start.unwrap_or_else(|| vec![0.0; model.dofs()]);
        // The relaxation hands out the Hessian at the equilibrium (its last assembly).
        let (symbolic, (newton, h)) = match &warm.superset {
            Some(superset) => rayon::join(
                || self.symbolic_for(active),
                || self.relax_from(active, &mut u, warm.factor, superset),
            ),
            None => {
                let symbolic = self.symbolic_for(active);
                let relaxed = self.relax_from(active, &mut u, warm.factor, &symbolic);
                (symbolic, relaxed)
            }
        };
        let modes = warm
            .modes
            .map(|w| restrict(w.as_ref(), &model.coordinate_mask(active)));
        let params = preset.params(&self.params().eigen);
        let spectrum = || {
            self.in_metric(active, &h, |h| {
                let modes = modes.as_ref().map(|w| w.as_ref());
                // About a shift right below the expected λ when one is known: a successful
                // Cholesky of `H − σI` proves no eigenvalue lies below σ, and shift-and-invert
                // separates the clustered smallest eigenvalues far better there than about zero.
                // Otherwise, or if λ turns out below σ, about zero.
                let shifted = match warm.lambda.map(|l| self.tuning().spectrum_shift * l) {
                    Some(sigma) if sigma > 0.0 && sigma.is_finite() => numerics::above(
                        model.pattern(),
                        h,
                        &symbolic,
                        modes.into(),
                        &params,
                        sigma,
                        None,
                    )?,
                    _ => None,
                };
                Ok(match shifted {
                    Some(pair) => pair,
                    None => numerics::factored(model.pattern(), h, &symbolic, modes, &params)?,
                })
            })
        };
        let terms = || (prepare == Prepare::Candidates).then(|| Terms::compute(self, active, &u));
        let (spectrum, terms) = rayon::join(spectrum, terms);
        let (spectrum, factor) = spectrum?;
        let curves = active.curves();
        Ok(Evaluation {
            factor: Arc::new(factor),
            length: self.total_length(&curves),
            curves,
            work: Work {
                factorizations: spectrum.factorizations + newton.factorizations,
                solves: spectrum.solves,
            },
            newton,
            displacement: u,
            spectrum,
            symbolic,
            terms,
        })
    }
}

/// Zeroes the rows of the coordinates a structure leaves loose (`keep[i] == false`: its
/// `EnergyModel::coordinate_mask`, vertices' and twists') in a copy of `v`.
pub(super) fn restrict(v: MatRef<'_, f64>, keep: &[bool]) -> Mat<f64> {
    let mut out = v.to_owned();
    for (i, &on) in keep.iter().enumerate() {
        if !on && i < out.nrows() {
            for j in 0..out.ncols() {
                out[(i, j)] = 0.0;
            }
        }
    }
    out
}
