//! Greedy simplification, the paper's Algorithm 1 (SPEC §6).
//!
//! ```text
//! A := all curves
//! loop:
//!     relax A; record A (curves, L(A), λ_eq(A), worst-case mode)
//!     if L(A) ≤ V: stop
//!     if every curve of A is kept or A has one curve: stop, budget unmet
//!     for every c in A not kept: score(c) := λ_fix(A \ {c} | A)      (in parallel)
//!     remove the c with the largest score (ties within 1e-7 → lowest id)
//! ```
//!
//! Each relaxation starts from the previous equilibrium. Candidate scores use the local
//! Hessians of `A`'s equilibrium, computed once per iteration, and are warm-started from
//! `A`'s low modes. Every candidate's computation is deterministic and independent of the
//! others, so the choice does not depend on the thread count.

use super::candidates::{CandidateContext, CandidateScore, CandidateTerms, Carried, PruneParams};
use super::{Budget, Evaluation, Scorer, SimplifyError, Warm, Work, pick_best};
use crate::rod::ActiveSet;
use crate::solve::NewtonSummary;
use crate::stability::Analyzer;
use faer::Mat;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Parameters of the greedy.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GreedyParams {
    /// The material budget.
    pub budget: Budget,
    /// Curves that are never removed.
    pub keep: Vec<usize>,
    /// Relative tolerance under which two scores tie (SPEC: 1e-7).
    pub tie_tolerance: f64,
    /// Candidate pruning by Rayleigh–Ritz bounds.
    #[serde(default)]
    pub prune: PruneParams,
    /// Low modes computed per iteration (the bounds' subspace; on the tower, 2 prune as well
    /// as 4 or 6 for a third of the solves).
    #[serde(default = "default_modes")]
    pub modes: usize,
    /// Start each iteration from the previous one's modes and the winner's factorization.
    #[serde(default = "default_true")]
    pub warm_start: bool,
    /// Stop after this many removals even if the budget is not met (None: no limit).
    #[serde(default)]
    pub max_removals: Option<usize>,
}

fn default_true() -> bool {
    true
}

fn default_modes() -> usize {
    2
}

impl GreedyParams {
    /// A greedy with `budget`, no keep list and the SPEC's tie tolerance.
    pub fn new(budget: Budget) -> Self {
        GreedyParams {
            budget,
            keep: Vec::new(),
            tie_tolerance: 1e-7,
            prune: PruneParams::default(),
            modes: default_modes(),
            warm_start: true,
            max_removals: None,
        }
    }

    /// Checks the parameters against a network of `curves` curves.
    pub fn validate(&self, curves: usize) -> Result<(), String> {
        self.budget.validate()?;
        if let Some(&c) = self.keep.iter().find(|&&c| c >= curves) {
            return Err(format!(
                "keep list names curve {c}, but the network has {curves} curves (ids 0..{})",
                curves.saturating_sub(1)
            ));
        }
        self.prune.validate()?;
        if !(self.tie_tolerance >= 0.0 && self.tie_tolerance < 1e-2) {
            return Err(format!(
                "tie tolerance must lie in [0, 1e-2), got {}",
                self.tie_tolerance
            ));
        }
        Ok(())
    }
}

/// One iteration of the greedy: the relaxed network after `k` removals.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct IterationRecord {
    /// Curves of the network, ascending.
    pub curves: Vec<usize>,
    /// Total rest length.
    pub length: f64,
    /// `λ_eq`.
    pub lambda: f64,
    /// Smallest eigenvalues at equilibrium.
    pub eigenvalues: Vec<f64>,
    /// Zero modes among them.
    pub zero_modes: usize,
    /// Negative modes among them.
    pub negative_modes: usize,
    /// The equilibrium solve.
    pub newton: NewtonSummary,
    /// The curve removed next (`None` on the last iteration).
    pub removed: Option<usize>,
    /// Its score `λ_fix` (`None` on the last iteration).
    pub score: Option<f64>,
    /// Every candidate's score, by curve id.
    pub candidates: Vec<CandidateScore>,
    /// Side file holding the worst-case mode (relative to the output folder).
    pub mode_file: String,
}

/// Why the greedy stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// `L(A) ≤ V`.
    BudgetMet,
    /// Only kept curves (or a single curve) remain and `L(A) > V`.
    BudgetUnmet,
    /// No candidate could be scored.
    NoScorableCandidate,
    /// The removal limit was reached.
    RemovalLimit,
}

/// Time spent per phase (not part of the result: timings live in `timings.json`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GreedyTimings {
    /// Relaxations and `λ_eq` spectra.
    pub relax_seconds: f64,
    /// Per-iteration preparation of the candidates (local Hessians, `H·V`).
    pub locals_seconds: f64,
    /// Candidate scoring (wall time).
    pub candidates_seconds: f64,
    /// Candidate evaluations performed.
    pub candidate_evaluations: usize,
    /// Candidates skipped because their bound showed they could not win.
    pub candidates_pruned: usize,
    /// Factorizations and solves of relaxations and `λ_eq` spectra.
    pub relax_work: Work,
    /// Factorizations and solves of candidate scores.
    pub candidate_work: Work,
    /// Total wall time.
    pub total_seconds: f64,
}

/// Everything the greedy produced.
#[derive(Clone, Debug)]
pub struct GreedyOutcome {
    /// Every iteration, first (all curves) to last.
    pub iterations: Vec<IterationRecord>,
    /// Why it stopped.
    pub stop: StopReason,
    /// The budget as a length.
    pub budget: f64,
    /// Timings.
    pub timings: GreedyTimings,
}

/// The estimate of the next structure's `λ_eq` its spectrum is shifted below
/// ([`crate::simplify::Warm::lambda`]): the winner's score, or the current `λ_eq` when that is
/// more than 5% lower. Relaxing can lower `λ` far below the fixed-geometry score (the tower:
/// `λ_eq` at 0.63–0.99 of the score, so a shift at 0.9 × the score failed for 24 of its 26
/// spectra, each failure a wasted factorization and a spectrum about zero), while `λ_eq` falls
/// only a few percent per removal; where the two agree (roof, shells) the score is the
/// nearer estimate.
fn spectrum_hint(score: f64, lambda: f64) -> f64 {
    if lambda > 0.0 && lambda < 0.95 * score {
        lambda
    } else {
        score
    }
}

/// Whether the next iteration should use the test vectors carried over from this one: when
/// this one settled at least `after` candidates by an inertia test or by a carried vector's
/// bound ([`PruneParams::carry_after`]). A function of the recorded values, so a resumed run
/// decides the same.
fn carried_pays(scores: &[CandidateScore], after: usize) -> bool {
    let settled = scores
        .iter()
        .filter(|s| {
            s.pruned
                && (s.below.is_some() || (s.refined_bound.is_none() && s.extended_bound.is_some()))
        })
        .count();
    settled >= after
}

/// Callbacks of a greedy run: saving progress, cancelling.
pub trait GreedyHooks: Sync {
    /// Called once per iteration with its record, its evaluation (mode, equilibrium), and
    /// the number of iterations done; an error stops the run.
    fn iteration(&mut self, record: &IterationRecord, eval: &Evaluation) -> Result<(), String>;
    /// Called right before [`Self::iteration`] of an iteration whose candidates were searched,
    /// with the test vectors it hands the next iteration: a resumed run needs them to continue
    /// exactly as an uninterrupted one ([`ResumePoint::carried`]).
    fn carried(&mut self, carried: &Carried) -> Result<(), String> {
        let _ = carried;
        Ok(())
    }
    /// Polled between candidates and iterations (from several threads); `true` stops the run
    /// cleanly, keeping every recorded iteration.
    fn cancelled(&self) -> bool {
        false
    }
    /// Called once before the greedy returns, whatever its outcome: hooks that save in the
    /// background finish their writes (an error here fails a run that otherwise succeeded).
    fn flush(&mut self) -> Result<(), String> {
        Ok(())
    }
}

/// Hooks that do nothing.
#[derive(Debug, Default)]
pub struct NoHooks;

impl GreedyHooks for NoHooks {
    fn iteration(&mut self, _: &IterationRecord, _: &Evaluation) -> Result<(), String> {
        Ok(())
    }
}

/// A completed iteration to resume from: the last recorded network's equilibrium and low
/// modes, from which the next iteration starts exactly as an uninterrupted run would.
#[derive(Clone, Debug)]
pub struct ResumePoint {
    /// Iterations already recorded.
    pub iterations: Vec<IterationRecord>,
    /// Equilibrium displacements of the last recorded iteration.
    pub displacement: Vec<f64>,
    /// Low modes of the last recorded iteration (columns).
    pub modes: Mat<f64>,
    /// The test vectors the last recorded iteration handed on ([`GreedyHooks::carried`];
    /// empty if unknown: the run continues with the same removals, its bounds start afresh).
    pub carried: Carried,
}

/// Runs the greedy on `analyzer`'s network. Returns once `hooks` have flushed
/// ([`GreedyHooks::flush`]), also when the run stopped early.
pub fn greedy(
    analyzer: &Analyzer,
    params: &GreedyParams,
    resume: Option<ResumePoint>,
    hooks: &mut dyn GreedyHooks,
) -> Result<GreedyOutcome, SimplifyError> {
    let outcome = run(analyzer, params, resume, hooks);
    let flushed = hooks.flush().map_err(SimplifyError::Hook);
    // The run's own error first: a failed write that stopped it is reported as such.
    let outcome = outcome?;
    flushed?;
    Ok(outcome)
}

/// The greedy's loop ([`greedy`] without the final flush).
fn run(
    analyzer: &Analyzer,
    params: &GreedyParams,
    resume: Option<ResumePoint>,
    hooks: &mut dyn GreedyHooks,
) -> Result<GreedyOutcome, SimplifyError> {
    let start = Instant::now();
    let n = analyzer.network().rods.len();
    params.validate(n).map_err(SimplifyError::Params)?;
    let total = analyzer.network().total_length(&(0..n).collect::<Vec<_>>());
    let budget = params.budget.length(total);
    let scorer = Scorer::new(analyzer).with_modes(params.modes);
    let mut keep = vec![false; n];
    for &c in &params.keep {
        keep[c] = true;
    }
    let mut timings = GreedyTimings::default();
    let mut superset = None;
    // The last winner's score, an estimate of the next `λ_eq` (see `Warm::lambda`).
    let mut lambda_hint = None;
    let mut carried: Carried = Vec::new();
    let mut use_carried = false;

    // What each iteration hands the next: its equilibrium (Newton's start), its low modes (the
    // eigen solver's start) and the factorization of the winning candidate's Hessian, which is
    // the next structure's Hessian at that start (Newton's first matrix).
    // The previous structure's symbolic analysis serves the next relaxation (see
    // `Scorer::evaluate_warm`); a pure function of that structure, recomputed on resume.
    let (mut iterations, mut active, mut warm, mut warm_modes, mut next_factor) = match resume {
        None => (Vec::new(), ActiveSet::all(n), None, None, None),
        Some(r) => {
            let last = r
                .iterations
                .last()
                .ok_or_else(|| SimplifyError::Params("nothing to resume".into()))?;
            let removed = last
                .removed
                .ok_or_else(|| SimplifyError::Params("the recorded run already finished".into()))?;
            let prev = ActiveSet::from_curves(n, &last.curves);
            // Recompute the winner's factorization: it depends only on the recorded state. A
            // winner scored about a positive shift (the inertia test) passed none on.
            let scored_about_zero = last
                .candidates
                .iter()
                .find(|c| c.curve == removed)
                .is_none_or(|c| c.shift.is_none());
            let factor = if scored_about_zero {
                let ctx =
                    CandidateContext::new(&scorer, &prev, &r.displacement, r.modes.as_ref(), None);
                ctx.score(removed).ok().map(|(_, f)| f)
            } else {
                None
            };
            superset = Some(analyzer.symbolic_for(&prev));
            lambda_hint = last.score.map(|s| spectrum_hint(s, last.lambda));
            if params.prune.enabled && params.prune.carry {
                use_carried = carried_pays(&last.candidates, params.prune.carry_after);
                carried = r.carried;
            }
            (
                r.iterations,
                prev.without(removed),
                Some(r.displacement),
                Some(r.modes),
                factor,
            )
        }
    };

    loop {
        if hooks.cancelled() {
            return Err(SimplifyError::Cancelled);
        }
        let t = Instant::now();
        let relax_symbolic = superset.take();
        let hints = if params.warm_start {
            Warm {
                factor: next_factor.take(),
                modes: warm_modes.as_ref().map(|m: &Mat<f64>| m.as_ref()),
                superset: relax_symbolic.as_ref(),
                lambda: lambda_hint.take(),
            }
        } else {
            Warm::default()
        };
        // The candidates' terms (they need only the equilibrium) beside the spectrum.
        let (eval, terms) = scorer.evaluate_warm_beside(&active, warm.as_deref(), hints, |u| {
            CandidateTerms::compute(&scorer, &active, u)
        })?;
        timings.relax_seconds += t.elapsed().as_secs_f64();
        timings.relax_work.add(eval.work);
        let k = iterations.len();
        let mut record = IterationRecord {
            curves: eval.curves.clone(),
            length: eval.length,
            lambda: eval.lambda(),
            eigenvalues: eval.spectrum.values.clone(),
            zero_modes: eval.spectrum.zero_modes,
            negative_modes: eval.spectrum.negative_modes,
            newton: eval.newton.clone(),
            removed: None,
            score: None,
            candidates: Vec::new(),
            mode_file: format!("modes/{k:04}.bin"),
        };
        let candidates: Vec<usize> = eval.curves.iter().copied().filter(|&c| !keep[c]).collect();
        let stop = if eval.length <= budget {
            Some(StopReason::BudgetMet)
        } else if candidates.is_empty() || eval.curves.len() <= 1 {
            Some(StopReason::BudgetUnmet)
        } else if params.max_removals.is_some_and(|m| k >= m) {
            Some(StopReason::RemovalLimit)
        } else {
            None
        };
        if let Some(stop) = stop {
            hooks
                .iteration(&record, &eval)
                .map_err(SimplifyError::Hook)?;
            iterations.push(record);
            timings.total_seconds = start.elapsed().as_secs_f64();
            return Ok(GreedyOutcome {
                iterations,
                stop,
                budget,
                timings,
            });
        }

        // Score every candidate at A's equilibrium.
        let t = Instant::now();
        let mut ctx = CandidateContext::of_evaluation_with(&scorer, &active, &eval, terms);
        if use_carried {
            ctx = ctx.with_carried(std::mem::take(&mut carried));
        }
        timings.locals_seconds += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let shared: &dyn GreedyHooks = &*hooks;
        let (scores, mut factors) =
            ctx.score_all(&candidates, &params.prune, params.tie_tolerance, &|| {
                shared.cancelled()
            });
        timings.candidates_seconds += t.elapsed().as_secs_f64();
        timings.candidate_evaluations += scores.iter().filter(|s| !s.pruned).count();
        timings.candidates_pruned += scores.iter().filter(|s| s.pruned).count();
        timings.candidate_work.add(ctx.work());
        if params.prune.enabled && params.prune.carry {
            carried = ctx.take_carried();
            use_carried = carried_pays(&scores, params.prune.carry_after);
            hooks.carried(&carried).map_err(SimplifyError::Hook)?;
        }
        if hooks.cancelled() {
            return Err(SimplifyError::Cancelled);
        }
        let pairs: Vec<(usize, f64)> = scores
            .iter()
            .filter_map(|s| s.score.map(|v| (s.curve, v)))
            .collect();
        record.candidates = scores;
        let Some((chosen, score)) = pick_best(&pairs, params.tie_tolerance) else {
            hooks
                .iteration(&record, &eval)
                .map_err(SimplifyError::Hook)?;
            iterations.push(record);
            timings.total_seconds = start.elapsed().as_secs_f64();
            return Ok(GreedyOutcome {
                iterations,
                stop: StopReason::NoScorableCandidate,
                budget,
                timings,
            });
        };
        record.removed = Some(chosen);
        record.score = Some(score);
        hooks
            .iteration(&record, &eval)
            .map_err(SimplifyError::Hook)?;
        iterations.push(record);
        active.remove(chosen);
        next_factor = factors
            .iter()
            .position(|f| f.0 == chosen)
            .map(|i| factors.swap_remove(i).1);
        let lambda_now = eval.lambda();
        warm_modes = Some(eval.spectrum.vectors);
        warm = Some(eval.displacement);
        superset = Some(eval.symbolic);
        lambda_hint = Some(spectrum_hint(score, lambda_now));
    }
}

#[cfg(test)]
mod tests {
    use super::spectrum_hint;

    #[test]
    fn the_spectrum_hint_is_the_lower_estimate_only_when_clearly_lower() {
        // The tower: λ_eq far below the score.
        assert_eq!(spectrum_hint(2.71e-9, 2.14e-9), 2.14e-9);
        // The roof: the score, within a few percent of λ_eq.
        assert_eq!(spectrum_hint(5.0e-6, 4.9e-6), 5.0e-6);
        assert_eq!(spectrum_hint(5.0e-6, 5.2e-6), 5.0e-6);
        // A mechanism or an unstable structure: no estimate from λ_eq.
        assert_eq!(spectrum_hint(1e-9, -1e-14), 1e-9);
        assert_eq!(spectrum_hint(1e-9, 0.0), 1e-9);
    }
}
