//! Simplification: pick the subset of curves that fits the budget and is most stable.
//!
//! - [`greedy()`]: the paper's Algorithm 1 (SPEC §6), every iteration recorded;
//! - [`exhaustive`]: all feasible subsets, the exact optimum of `λ_eq` (or `λ_fix`) for small
//!   networks;
//! - [`relaxation`]: certified upper bounds on the best `λ_fix` (SPEC §7 relaxed);
//! - [`exact`]: branch and bound for the optimum of `λ_fix`, with a proof;
//! - [`local`]: local search (add, drop, swap) from a feasible subset, e.g. the greedy's;
//! - [`random`]: uniformly random feasible subsets, a given number of evaluations;
//! - [`result`]: the `result.json` schema (SPEC §10), written and read back.
//!
//! All searches share [`Scorer`], which evaluates `λ_eq(S)` and `λ_fix(S | A)` the same way
//! for everyone, so their answers are comparable.

pub mod candidates;
pub mod compare;
pub mod exact;
pub mod exhaustive;
pub mod greedy;
pub mod local;
pub mod random;
pub mod relaxation;
pub mod result;

pub use greedy::{GreedyHooks, GreedyOutcome, GreedyParams, StopReason, greedy};

use crate::rod::ActiveSet;
use crate::rod::model::LocalHessians;
use crate::solve::Cholesky;
use crate::solve::NewtonSummary;
use crate::solve::eigen::{
    Eigen, EigenOptions, EigenParams, Shift, Spectrum, Start, smallest_eigenpairs,
};
use crate::stability::{Analyzer, StabilityError};
use faer::{Mat, MatRef};
use serde::{Deserialize, Serialize};

/// The material budget `V`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Budget {
    /// A fraction of the total rest length of all curves, in `(0, 1]`.
    Fraction(f64),
    /// An absolute rest length.
    Length(f64),
}

impl Budget {
    /// The budget as a length, for a network of total rest length `total`.
    pub fn length(self, total: f64) -> f64 {
        match self {
            Budget::Fraction(f) => f * total,
            Budget::Length(l) => l,
        }
    }

    /// Checks the value.
    pub fn validate(self) -> Result<(), String> {
        match self {
            Budget::Fraction(f) if !(f > 0.0 && f <= 1.0) => {
                Err(format!("budget fraction must lie in (0, 1], got {f}"))
            }
            Budget::Length(l) if !(l > 0.0 && l.is_finite()) => {
                Err(format!("budget length must be a positive number, got {l}"))
            }
            _ => Ok(()),
        }
    }
}

/// Why a search could not run.
#[derive(Debug, thiserror::Error)]
pub enum SimplifyError {
    /// Bad parameters.
    #[error("{0}")]
    Params(String),
    /// A stability computation failed.
    #[error(transparent)]
    Stability(#[from] StabilityError),
    /// The run was cancelled; everything recorded so far is kept.
    #[error("cancelled")]
    Cancelled,
    /// A hook (e.g. writing progress) failed.
    #[error("{0}")]
    Hook(String),
}

/// `λ_eq` of a structure: its equilibrium and spectrum.
#[derive(Clone, Debug)]
pub struct Evaluation {
    /// Curves of the structure, ascending.
    pub curves: Vec<usize>,
    /// Total rest length.
    pub length: f64,
    /// The equilibrium solve.
    pub newton: NewtonSummary,
    /// Displacements at equilibrium.
    pub displacement: Vec<f64>,
    /// Spectrum at equilibrium.
    pub spectrum: Spectrum,
    /// Factorizations and solves it took.
    pub work: Work,
    /// The factorization of `H − σI` at equilibrium that the spectrum used (a preconditioner
    /// for the structures one curve smaller).
    pub factor: Option<std::sync::Arc<Cholesky>>,
    /// The symbolic analysis its factorizations used ([`Analyzer::symbolic_for`] the
    /// structure), good for every structure inside it.
    pub symbolic: std::sync::Arc<crate::solve::SymbolicFactor>,
}

/// What a previous step of a search hands [`Scorer::evaluate_warm`]; every field only changes
/// the work (and round-off).
#[derive(Debug, Default)]
pub struct Warm<'a> {
    /// A factorization of a nearby Hessian of the same structure: Newton's first steps reuse
    /// it.
    pub factor: Option<Cholesky>,
    /// Approximate low modes (columns): the eigen solver starts from them.
    pub modes: Option<MatRef<'a, f64>>,
    /// The symbolic analysis of a structure containing this one (the previous step's):
    /// Newton factors with it while the structure's own analysis, which the spectrum uses, is
    /// computed on another thread.
    pub superset: Option<&'a std::sync::Arc<crate::solve::SymbolicFactor>>,
    /// An estimate of `λ_eq` (the removed candidate's score): the spectrum is computed about
    /// a shift just below it when that shift proves to lie below every eigenvalue.
    pub lambda: Option<f64>,
}

/// Factors storing more values than this solve a candidate's Lanczos block one column per
/// core instead of in one pass. Far beyond the caches, a pass for two columns costs nearly
/// two one-column passes, while two one-column solves side by side cost little more than
/// one (the bunny's factor, 10 M values: 20.8 ms in one pass, 12.1 ms side by side, 14.7 ms
/// for one column); smaller factors stay in cache and one pass is cheaper (roof, 0.3 M
/// values: 0.88 against 1.07 ms; tower, hill, tent 1–6% slower side by side, kagome, 2.6 M,
/// even). A function of the structure's size only, so the grouping, and with it every
/// result, never depends on the threads.
pub const LARGE_FACTOR_VALUES: usize = 4_000_000;

/// The spectrum's shift, as a fraction of [`Warm::lambda`].
const SPECTRUM_SHIFT: f64 = 0.9;

pub use crate::solve::eigen::{SPECTRUM_TOL, SPECTRUM_TRAILING_TOL};

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

impl Evaluation {
    /// `λ_eq`.
    pub fn lambda(&self) -> f64 {
        self.spectrum.lambda()
    }
}

/// Evaluates structures of one network the same way for every search.
#[derive(Debug)]
pub struct Scorer<'a> {
    analyzer: &'a Analyzer,
    /// Eigen parameters for `λ_eq` spectra (enough modes for the candidates' bounds).
    eval_eigen: EigenParams,
    /// Eigen parameters for candidate scores (only `λ` is needed).
    candidate_eigen: EigenParams,
    /// `λ_eq` of connected structures already evaluated.
    cache: std::sync::Mutex<std::collections::HashMap<Vec<usize>, f64>>,
}

impl<'a> Scorer<'a> {
    /// A scorer over `analyzer`'s network.
    pub fn new(analyzer: &'a Analyzer) -> Self {
        let candidate_eigen = analyzer.params().eigen.candidate_score();
        Scorer {
            analyzer,
            eval_eigen: analyzer.params().eigen.clone(),
            candidate_eigen,
            cache: Default::default(),
        }
    }

    /// Computes `k` modes in every `λ_eq` spectrum ([`EigenParams::greedy_spectrum`]): the
    /// greedy's records need `λ_eq`, its search a subspace.
    pub fn with_modes(mut self, k: usize) -> Self {
        self.eval_eigen = self.eval_eigen.greedy_spectrum(k);
        self
    }

    /// The analyzer.
    pub fn analyzer(&self) -> &'a Analyzer {
        self.analyzer
    }

    /// `λ_eq(active)`: relaxes from `start` (or the drawn state) and computes the spectrum.
    pub fn evaluate(
        &self,
        active: &ActiveSet,
        start: Option<&[f64]>,
    ) -> Result<Evaluation, StabilityError> {
        self.evaluate_warm(active, start, Warm::default())
    }

    /// [`Self::evaluate`] with help from a previous step (see [`Warm`]): only the work
    /// changes, and round-off (the same `warm` gives the same result).
    pub fn evaluate_warm(
        &self,
        active: &ActiveSet,
        start: Option<&[f64]>,
        warm: Warm<'_>,
    ) -> Result<Evaluation, StabilityError> {
        self.evaluate_warm_beside(active, start, warm, |_| ())
            .map(|(e, ())| e)
    }

    /// [`Self::evaluate_warm`], running `beside` on the equilibrium while the spectrum is
    /// computed (its solves leave a core idle): the greedy prepares its candidates' terms
    /// there ([`candidates::CandidateTerms`]).
    pub fn evaluate_warm_beside<T: Send>(
        &self,
        active: &ActiveSet,
        start: Option<&[f64]>,
        warm: Warm<'_>,
        beside: impl FnOnce(&[f64]) -> T + Send,
    ) -> Result<(Evaluation, T), StabilityError> {
        let a = self.analyzer;
        if active.is_empty() {
            return Err(StabilityError::Empty);
        }
        let model = a.model();
        let mut u = start.map_or_else(|| vec![0.0; model.dofs()], <[f64]>::to_vec);
        let factor = warm.factor;
        // The relaxation hands out the Hessian at the equilibrium (its last assembly).
        let (symbolic, (newton, h)) = match warm.superset {
            Some(superset) => rayon::join(
                || a.symbolic_for(active),
                || a.relax_assembled(active, &mut u, factor, superset),
            ),
            None => {
                let symbolic = a.symbolic_for(active);
                let relaxed = a.relax_assembled(active, &mut u, factor, &symbolic);
                (symbolic, relaxed)
            }
        };
        let modes = warm.modes.map(|w| restrict(w, &model.vertex_mask(active)));
        let modes = modes.as_ref().map(|w| w.as_ref());
        // About a shift right below the expected λ when one is known: a successful Cholesky
        // of `H − σI` proves no eigenvalue lies below σ, and shift-and-invert separates the
        // clustered smallest eigenvalues far better there than about zero (roof: 51 solves
        // per spectrum about zero). Otherwise, or if λ turns out below σ, about zero.
        let solve = |shift: Shift| {
            let options = EigenOptions {
                shift,
                start: modes.map_or(Start::Random, Start::Vectors),
                ..Default::default()
            };
            smallest_eigenpairs(&symbolic, model.pattern(), &h, &self.eval_eigen, options)
        };
        let spectrum = || -> Result<_, StabilityError> {
            let shifted = match warm.lambda.map(|l| SPECTRUM_SHIFT * l) {
                Some(sigma) if sigma > 0.0 && sigma.is_finite() => solve(Shift::Above(sigma))?,
                _ => None,
            };
            Ok(match shifted {
                Some(found) => found,
                None => solve(Shift::BelowZero)?.expect("a shift below zero always factors"),
            })
        };
        let (spectrum, extra) = rayon::join(spectrum, || beside(&u));
        let Eigen { spectrum, factor } = spectrum?;
        let factor = factor.expect("the whole matrix was factored");
        let curves = active.curves();
        Ok((
            Evaluation {
                factor: Some(std::sync::Arc::new(factor)),
                length: a.network().total_length(&curves),
                curves,
                newton: newton.summary(),
                work: Work {
                    factorizations: spectrum.factorizations + newton.factorizations,
                    solves: spectrum.solves,
                },
                displacement: u,
                spectrum,
                symbolic,
            },
            extra,
        ))
    }

    /// `λ_eq(active)` relaxed from the drawn state, the way every search ranks a subset
    /// (path-independent, so greedy, exhaustive and random results compare).
    ///
    /// Curves that share no vertex are independent structures: the Hessian is block diagonal
    /// and each part relaxes on its own, so `λ_eq` is the smallest `λ_eq` of the connected
    /// parts. Each part's value is computed once and remembered (searches over subsets meet
    /// the same parts again and again).
    pub fn lambda_eq(&self, active: &ActiveSet) -> Result<f64, StabilityError> {
        Ok(self
            .lambda_eq_parts(active)?
            .iter()
            .map(|p| p.1)
            .fold(f64::INFINITY, f64::min))
    }

    /// The connected parts of `active` (as [`Self::components`]) with the `λ_eq` of each,
    /// relaxed on its own (cached); [`Self::lambda_eq`] is the smallest of them.
    pub fn lambda_eq_parts(
        &self,
        active: &ActiveSet,
    ) -> Result<Vec<(Vec<usize>, f64)>, StabilityError> {
        if active.is_empty() {
            return Err(StabilityError::Empty);
        }
        let mut parts = Vec::new();
        for part in self.components(active) {
            let cached = self.cache.lock().expect("cache lock").get(&part).copied();
            let value = match cached {
                Some(v) => v,
                None => {
                    let v = self.lambda_eq_connected(&part)?;
                    self.cache
                        .lock()
                        .expect("cache lock")
                        .insert(part.clone(), v);
                    v
                }
            };
            parts.push((part, value));
        }
        Ok(parts)
    }

    /// Connected structures whose `λ_eq` the scorer has computed and remembers (each one
    /// relaxation and one eigen solve; see [`Self::lambda_eq`]).
    pub fn cached_structures(&self) -> usize {
        self.cache.lock().expect("cache lock").len()
    }

    /// The connected parts of `active` (curves joined through shared vertices), each sorted,
    /// in order of their smallest curve.
    pub fn components(&self, active: &ActiveSet) -> Vec<Vec<usize>> {
        let links = self
            .analyzer
            .model()
            .vertex_curves()
            .iter()
            .map(|cs| cs.iter().map(|&c| c as usize));
        crate::network::subnet::curve_components(active.universe(), &active.curves(), links)
    }

    /// `λ_eq` of a connected structure, on its own network (the loose vertices deleted, so
    /// the factorizations only see the structure's own unknowns).
    fn lambda_eq_connected(&self, curves: &[usize]) -> Result<f64, StabilityError> {
        let (network, _) = self.analyzer.network().sub_network(curves);
        let n = network.rods.len();
        let mut params = self.analyzer.params().clone();
        params.eigen = self.candidate_eigen.clone();
        let sub = Analyzer::new(network, params).map_err(StabilityError::Params)?;
        let active = ActiveSet::all(n);
        let mut u = vec![0.0; sub.model().dofs()];
        sub.relax(&active, &mut u);
        Ok(sub.spectrum(&active, &u, None)?.lambda())
    }

    /// `λ_fix(active | A)` from the local Hessians at `A`'s equilibrium, warm-started from
    /// `warm` (approximate low modes), with the factorization it used.
    ///
    /// `symbolic` is the analysis to factor with: [`Analyzer::symbolic_for`] `active` or a
    /// structure containing it.
    pub fn lambda_fixed(
        &self,
        locals: &LocalHessians,
        active: &ActiveSet,
        warm: Option<MatRef<'_, f64>>,
        symbolic: &std::sync::Arc<crate::solve::SymbolicFactor>,
    ) -> Result<(Spectrum, Cholesky), StabilityError> {
        let h = self.fixed_hessian(locals, active)?;
        let model = self.analyzer.model();
        let warm = warm.map(|w| restrict(w, &model.vertex_mask(active)));
        let options = EigenOptions {
            start: warm
                .as_ref()
                .map_or(Start::Random, |w| Start::Vectors(w.as_ref())),
            ..Default::default()
        };
        let params = self.candidate_params(symbolic);
        let found = smallest_eigenpairs(symbolic, model.pattern(), &h, &params, options)?
            .expect("a shift below zero always factors");
        Ok((found.spectrum, found.factor.expect("the whole matrix")))
    }

    /// The candidates' eigen parameters for factors of `symbolic`: one column per solve group
    /// on large factors ([`LARGE_FACTOR_VALUES`]).
    fn candidate_params(
        &self,
        symbolic: &crate::solve::SymbolicFactor,
    ) -> std::borrow::Cow<'_, EigenParams> {
        if symbolic.factor_nnz() > LARGE_FACTOR_VALUES {
            std::borrow::Cow::Owned(self.candidate_eigen.column_by_column())
        } else {
            std::borrow::Cow::Borrowed(&self.candidate_eigen)
        }
    }

    /// [`Self::lambda_fixed`] shifted about `sigma`, given `h`, the Hessian of `active` at
    /// `A`'s equilibrium ([`EnergyModel::hessian_from_locals`] or, for `A` without one curve,
    /// [`EnergyModel::hessian_without`]): `Ok(None)` when one factorization proves
    /// `λ_fix(active | A) < sigma` (see [`Shift::Above`], and [`EigenOptions::reuse`]). The
    /// warm start is asked of `warm` only when that factorization succeeds.
    ///
    /// [`EnergyModel::hessian_from_locals`]: crate::rod::EnergyModel::hessian_from_locals
    /// [`EnergyModel::hessian_without`]: crate::rod::EnergyModel::hessian_without
    pub fn lambda_fixed_above(
        &self,
        h: &[f64],
        active: &ActiveSet,
        warm: impl FnOnce() -> Option<Mat<f64>>,
        sigma: f64,
        symbolic: &std::sync::Arc<crate::solve::SymbolicFactor>,
        reuse: Option<crate::solve::Reuse<'_>>,
    ) -> Result<Option<(Spectrum, Cholesky)>, StabilityError> {
        if active.is_empty() {
            return Err(StabilityError::Empty);
        }
        let model = self.analyzer.model();
        // The warm start (`warm` restricted to `active`'s vertices) only once the
        // factorization about `σ` succeeds.
        let warm = move || warm().map(|w| restrict(w.as_ref(), &model.vertex_mask(active)));
        let options = EigenOptions {
            shift: Shift::Above(sigma),
            start: Start::Lazy(Box::new(warm)),
            reuse,
            keep: None,
        };
        let params = self.candidate_params(symbolic);
        let found = smallest_eigenpairs(symbolic, model.pattern(), h, &params, options)?;
        Ok(found.map(|f| (f.spectrum, f.factor.expect("the whole matrix"))))
    }

    /// The Hessian of `active` from the local Hessians at `A`'s equilibrium.
    fn fixed_hessian(
        &self,
        locals: &LocalHessians,
        active: &ActiveSet,
    ) -> Result<Vec<f64>, StabilityError> {
        if active.is_empty() {
            return Err(StabilityError::Empty);
        }
        let mut h = Vec::new();
        self.analyzer
            .model()
            .hessian_from_locals(locals, active, &mut h);
        Ok(h)
    }
}

/// Zeroes the rows of loose vertices (`mask[v] == false`) in a copy of `v`.
fn restrict(v: MatRef<'_, f64>, mask: &[bool]) -> Mat<f64> {
    let mut out = v.to_owned();
    for (vert, &on) in mask.iter().enumerate() {
        if !on {
            for j in 0..out.ncols() {
                for a in 0..3 {
                    out[(3 * vert + a, j)] = 0.0;
                }
            }
        }
    }
    out
}

/// Picks the best of `(curve, score)` pairs: the largest score, treating scores within a
/// relative `tie` of the best as equal and taking the lowest curve id among them (SPEC §6).
pub fn pick_best(scores: &[(usize, f64)], tie: f64) -> Option<(usize, f64)> {
    let best = scores
        .iter()
        .map(|s| s.1)
        .filter(|s| s.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    if !best.is_finite() {
        return None;
    }
    let floor = best - tie * best.abs();
    scores
        .iter()
        .filter(|s| s.1 >= floor)
        .min_by_key(|s| s.0)
        .copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ties_go_to_the_lowest_id() {
        let s = [(4, 1.0), (2, 1.0 - 1e-9), (7, 0.5), (1, 0.99)];
        assert_eq!(pick_best(&s, 1e-7), Some((2, 1.0 - 1e-9)));
        assert_eq!(pick_best(&s, 0.02), Some((1, 0.99)));
        assert_eq!(pick_best(&[], 1e-7), None);
        assert_eq!(pick_best(&[(3, f64::NAN)], 1e-7), None);
        // Negative scores (unstable structures) rank below positive ones.
        assert_eq!(pick_best(&[(0, -1e-9), (5, 1e-12)], 1e-7), Some((5, 1e-12)));
    }

    #[test]
    fn budgets() {
        assert_eq!(Budget::Fraction(0.25).length(200.0), 50.0);
        assert_eq!(Budget::Length(30.0).length(200.0), 30.0);
        assert!(Budget::Fraction(0.0).validate().is_err());
        assert!(Budget::Fraction(1.5).validate().is_err());
        assert!(Budget::Length(-1.0).validate().is_err());
        assert!(Budget::Length(f64::NAN).validate().is_err());
    }
}
