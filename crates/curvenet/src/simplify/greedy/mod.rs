//! Greedy simplification, the paper's Algorithm 1 (`docs/model.md`, *Greedy simplification*).
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
//! **Under design constraints** (the `constraints` of [`greedy`]) the candidates are the removable
//! units of `A` ([`Constraints::removal_candidates`]: a group or a symmetry orbit is removed
//! as a whole, and no removal may leave a set that breaks a constraint other than the budget);
//! a unit `U` is scored by `λ_fix(A \ U | A)`. When every unit is one curve the candidates are
//! searched as above; when some unit holds several curves every unit is scored exactly
//! ([`Candidates::score_set`]; the single-curve bounds do not apply to sets). The run stops,
//! budget unmet, when the constraints allow no further removal ([`StopReason::Blocked`]).
//! `--max-deviation` needs each network's equilibrium and does not steer the removals: the
//! run's answer measures it on each recorded iteration's equilibrium and honours it. Without constraints the run is the one above, bit for bit.
//!
//! Each relaxation starts from the previous equilibrium, warm-started by what the previous
//! iteration hands on ([`Candidates::hand_on`]). The candidates are scored at `A`'s
//! equilibrium by the best-first search of [`search`], which asks the stability facade for
//! bounds, tests and scores. Every candidate's computation is deterministic and independent
//! of the others, so the choice does not depend on the thread count.

mod search;

pub use search::CandidateScore;

use super::{Budget, SimplifyError, pick_best};
use crate::constraints::Constraints;
use crate::physics::PhysicalSummary;
use crate::stability::NewtonSummary;
use crate::stability::candidates::{Candidates, Carried, Outcome};
use crate::stability::{ActiveSet, Analyzer, Evaluation, Objective, Prepare, Preset, Warm, Work};
use crate::words::Message;
use faer::Mat;
use rayon::prelude::*;
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
    /// Relative tolerance under which two scores tie (1e-7: the ties between symmetric
    /// curves, whose scores differ by round-off).
    pub tie_tolerance: f64,
    /// Stop after this many removals even if the budget is not met (None: no limit).
    #[serde(default)]
    pub max_removals: Option<usize>,
}

impl GreedyParams {
    /// A greedy with `budget`, no keep list and the tie tolerance 1e-7.
    pub fn new(budget: Budget) -> Self {
        GreedyParams {
            budget,
            keep: Vec::new(),
            tie_tolerance: 1e-7,
            max_removals: None,
        }
    }

    /// Checks the parameters against a network of `curves` curves.
    pub fn validate(&self, curves: usize) -> Result<(), Message> {
        self.budget.validate()?;
        if let Some(&c) = self.keep.iter().find(|&&c| c >= curves) {
            return Err(format!(
                "keep list names curve {c}, but the network has {curves} curves (ids 0..{})",
                curves.saturating_sub(1)
            )
            .into());
        }
        if !(self.tie_tolerance >= 0.0 && self.tie_tolerance < 1e-2) {
            return Err(format!(
                "tie tolerance must lie in [0, 1e-2), got {}",
                self.tie_tolerance
            )
            .into());
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
    /// The curve removed next (`None` on the last iteration); for a group removed as a
    /// whole, its smallest curve.
    pub removed: Option<usize>,
    /// Every curve removed next when a group of several curves is removed as a whole
    /// (ascending; empty for a single curve).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub removed_group: Vec<usize>,
    /// Its score `λ_fix` (`None` on the last iteration).
    pub score: Option<f64>,
    /// Every candidate's score, by curve id.
    pub candidates: Vec<CandidateScore>,
    /// Side file holding the worst-case mode (relative to the output folder).
    pub mode_file: String,
    /// The structure's physical numbers in the physical mode (absent in the paper's mode).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub physical: Option<PhysicalSummary>,
    /// Under the frequency objective (`lambda`, `eigenvalues` and `score` are then those of
    /// the mass metric, `μ`): the first natural frequency `√μ_min / 2π` (Hz in the physical
    /// mode; in the paper's mode per the scene's unit of time, unit density); absent when
    /// the structure is not stable, and under the objective `λ_eq`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_frequency: Option<f64>,
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
    /// `L(A) > V` and the design constraints allow no further removal.
    Blocked,
}

impl std::fmt::Display for StopReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            StopReason::BudgetMet => "budget met",
            StopReason::BudgetUnmet => "budget not met: only kept curves or one curve remain",
            StopReason::NoScorableCandidate => "no candidate could be scored",
            StopReason::RemovalLimit => "removal limit reached",
            StopReason::Blocked => {
                "budget not met: the design constraints allow no further removal"
            }
        })
    }
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
/// ([`Warm::lambda`]): the winner's score, or the current `λ_eq` when that is more than 5%
/// lower. Relaxing can lower `λ` far below the fixed-geometry score, while `λ_eq` falls only
/// a few percent per removal; where the two agree the score is the nearer estimate (a shift
/// above `λ_eq` costs a wasted factorization and a spectrum about zero).
fn spectrum_hint(score: f64, lambda: f64) -> f64 {
    if lambda > 0.0 && lambda < 0.95 * score {
        lambda
    } else {
        score
    }
}

/// Under the frequency objective, the first natural frequency `√μ_min / 2π` of a stable
/// structure evaluated as `eval`.
fn first_frequency(analyzer: &Analyzer, eval: &Evaluation) -> Option<f64> {
    let s = &eval.spectrum;
    let stable = s.zero_modes == 0 && s.negative_modes == 0 && s.lambda() > 0.0;
    (analyzer.objective() == Objective::Frequency && stable)
        .then(|| s.lambda().sqrt() / (2.0 * std::f64::consts::PI))
}

/// Whether the next iteration should use the test vectors carried over from this one: when
/// this one settled at least `after` candidates by an inertia test or by a carried vector's
/// bound ([`crate::stability::Tuning::carry_after`]). A function of the recorded values, so a
/// resumed run decides the same.
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
pub trait GreedyHooks: Send + Sync {
    /// Called once per iteration with its record, its evaluation (mode, equilibrium), and
    /// the number of iterations done; an error stops the run.
    fn iteration(&mut self, record: &IterationRecord, eval: &Evaluation) -> Result<(), String>;
    /// Called before [`Self::iteration`] of an iteration whose candidates were searched, with
    /// the test vectors it hands the next iteration (possibly none): a resumed run needs them
    /// to continue exactly as an uninterrupted one ([`ResumePoint::carried`]). A run stopped
    /// between the two calls has not recorded the iteration.
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

/// Runs the greedy on `analyzer`'s network, under the design `constraints` when given (bound
/// to that network and `params`' budget and keep list): then only whole units are removed and
/// every network recorded after the first meets every constraint but the budget and
/// `--max-deviation` (see the module documentation); constraints that ask for nothing, or
/// `None`, give the paper's run exactly. Returns once `hooks` have flushed
/// ([`GreedyHooks::flush`]), also when the run stopped early.
///
/// It runs on a worker of the current thread pool (the calling thread waits): its parallel
/// parts then split among the workers without each being handed over from a thread outside
/// the pool.
///
/// # Errors
///
/// [`SimplifyError::Params`] for bad parameters or constraints bound to another network,
/// budget or keep list; the run's own failures and cancellation.
pub fn greedy(
    analyzer: &Analyzer,
    params: &GreedyParams,
    constraints: Option<&Constraints>,
    resume: Option<ResumePoint>,
    hooks: &mut dyn GreedyHooks,
) -> Result<GreedyOutcome, SimplifyError> {
    rayon::scope(|_| greedy_in_pool(analyzer, params, constraints, resume, hooks))
}

/// [`greedy`], on a worker of the pool.
fn greedy_in_pool(
    analyzer: &Analyzer,
    params: &GreedyParams,
    constraints: Option<&Constraints>,
    resume: Option<ResumePoint>,
    hooks: &mut dyn GreedyHooks,
) -> Result<GreedyOutcome, SimplifyError> {
    if let Some(c) = constraints {
        let n = analyzer.curve_count();
        let total = analyzer.total_length(&(0..n).collect::<Vec<_>>());
        let budget = params.budget.length(total);
        if let Err(e) = super::exhaustive::check_binding(c, n, budget, &params.keep) {
            return finish(Err(e), hooks);
        }
    }
    let active = constraints.filter(|c| c.is_active());
    finish(run(analyzer, params, active, resume, hooks), hooks)
}

/// Flushes `hooks` after a run ([`greedy`]).
fn finish(
    outcome: Result<GreedyOutcome, SimplifyError>,
    hooks: &mut dyn GreedyHooks,
) -> Result<GreedyOutcome, SimplifyError> {
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
    constraints: Option<&Constraints>,
    resume: Option<ResumePoint>,
    hooks: &mut dyn GreedyHooks,
) -> Result<GreedyOutcome, SimplifyError> {
    let start = Instant::now();
    let n = analyzer.curve_count();
    params.validate(n).map_err(SimplifyError::Params)?;
    let total = analyzer.total_length(&(0..n).collect::<Vec<_>>());
    let mut keep = vec![false; n];
    for &c in &params.keep {
        keep[c] = true;
    }
    let mut state = State {
        analyzer,
        params,
        constraints,
        budget: params.budget.length(total),
        keep,
        timings: GreedyTimings::default(),
        iterations: Vec::new(),
        active: analyzer.all(),
        warm: Warm::default(),
        carried: Vec::new(),
        use_carried: false,
    };
    if let Some(r) = resume {
        state.resume(r)?;
    }
    let stop = loop {
        if hooks.cancelled() {
            return Err(SimplifyError::Cancelled);
        }
        if let Some(stop) = state.iteration(hooks)? {
            break stop;
        }
    };
    state.timings.total_seconds = start.elapsed().as_secs_f64();
    Ok(GreedyOutcome {
        iterations: state.iterations,
        stop,
        budget: state.budget,
        timings: state.timings,
    })
}

/// The greedy's state between iterations.
struct State<'a> {
    analyzer: &'a Analyzer,
    params: &'a GreedyParams,
    /// Design constraints that ask for something (`None`: the paper's run).
    constraints: Option<&'a Constraints>,
    /// The budget as a length.
    budget: f64,
    /// Curves never removed.
    keep: Vec<bool>,
    timings: GreedyTimings,
    iterations: Vec<IterationRecord>,
    /// The structure of the next iteration.
    active: ActiveSet,
    /// What the previous iteration hands the next one's evaluation: its equilibrium
    /// (Newton's start), its low modes (the eigen solver's start), its symbolic analysis and
    /// the factorization of the winning candidate's Hessian, which is the next structure's
    /// Hessian at that start (Newton's first matrix).
    warm: Warm,
    /// The test vectors handed on by the previous iteration's candidates.
    carried: Carried,
    use_carried: bool,
}

impl<'a> State<'a> {
    /// Continues after the last recorded iteration of `r`, exactly as an uninterrupted run.
    fn resume(&mut self, r: ResumePoint) -> Result<(), SimplifyError> {
        let last = r
            .iterations
            .last()
            .ok_or_else(|| SimplifyError::Params("nothing to resume".into()))?;
        let removed = last
            .removed
            .ok_or_else(|| SimplifyError::Params("the recorded run already finished".into()))?;
        let prev = self.analyzer.set(&last.curves);
        // A winner scored about a positive shift (the inertia test) passed no factorization on.
        // Nor did an iteration whose units were scored as sets (one holds several curves).
        let about_zero = last
            .candidates
            .iter()
            .find(|c| c.curve == removed)
            .is_none_or(|c| c.shift.is_none())
            && last.candidates.iter().all(|c| c.group.is_empty());
        let hint = last.score.map(|s| spectrum_hint(s, last.lambda));
        let tuning = self.analyzer.tuning();
        if tuning.prune && tuning.carry {
            self.use_carried = carried_pays(&last.candidates, tuning.carry_after);
            self.carried = r.carried;
        }
        self.warm =
            self.analyzer
                .resume_warm(&prev, r.displacement, r.modes, removed, about_zero, hint);
        self.active = prev.without(removed);
        for &c in &last.removed_group {
            self.active.remove(c);
        }
        self.iterations = r.iterations;
        Ok(())
    }

    /// One iteration: relaxes and records the structure, then (unless a stop applies) scores
    /// its candidates and removes the winner. The stop reason once the run is over.
    fn iteration(
        &mut self,
        hooks: &mut dyn GreedyHooks,
    ) -> Result<Option<StopReason>, SimplifyError> {
        let (analyzer, tuning) = (self.analyzer, self.analyzer.tuning());
        let t = Instant::now();
        let warm = std::mem::take(&mut self.warm);
        let preset = Preset::Greedy {
            modes: tuning.modes,
        };
        // The candidates' terms (they need only the equilibrium) beside the spectrum.
        let mut eval = analyzer.evaluate(&self.active, warm, preset, Prepare::Candidates)?;
        self.timings.relax_seconds += t.elapsed().as_secs_f64();
        self.timings.relax_work.add(eval.work);
        let k = self.iterations.len();
        let mut record = IterationRecord {
            curves: eval.curves.clone(),
            length: eval.length,
            lambda: eval.lambda(),
            eigenvalues: eval.spectrum.values.clone(),
            zero_modes: eval.spectrum.zero_modes,
            negative_modes: eval.spectrum.negative_modes,
            newton: eval.newton.summary(),
            removed: None,
            removed_group: Vec::new(),
            score: None,
            candidates: Vec::new(),
            mode_file: crate::run_layout::mode_file(k),
            physical: analyzer.physical_summary(&self.active)?,
            first_frequency: first_frequency(analyzer, &eval),
        };
        // The removable units (each named by its smallest curve); `None`: every curve not kept.
        let units = self.constraints.map(|c| {
            c.removal_candidates(&eval.curves)
                .into_iter()
                .map(|u| c.units()[u].clone())
                .collect::<Vec<_>>()
        });
        let candidates: Vec<usize> = match &units {
            Some(units) => units.iter().map(|u| u[0]).collect(),
            None => eval
                .curves
                .iter()
                .copied()
                .filter(|&c| !self.keep[c])
                .collect(),
        };
        if let Some(stop) = self.stop(&eval, &candidates) {
            self.record(hooks, record, &eval)?;
            return Ok(Some(stop));
        }
        let groups = units.filter(|units| units.iter().any(|u| u.len() > 1));
        let (ctx, scores) = match &groups {
            Some(units) => self.score_units(&mut eval, units, &*hooks),
            None => self.search(&mut eval, &candidates, hooks),
        };
        // Before the record, so a resume from it finds them (possibly none).
        hooks.carried(&self.carried).map_err(SimplifyError::Hook)?;
        if hooks.cancelled() {
            return Err(SimplifyError::Cancelled);
        }
        let pairs: Vec<(usize, f64)> = scores
            .iter()
            .filter_map(|s| s.score.map(|v| (s.curve, v)))
            .collect();
        record.candidates = scores;
        let Some((chosen, score)) = pick_best(&pairs, self.params.tie_tolerance) else {
            self.record(hooks, record, &eval)?;
            return Ok(Some(StopReason::NoScorableCandidate));
        };
        record.removed = Some(chosen);
        record.score = Some(score);
        let removed = match &groups {
            Some(units) => units
                .iter()
                .find(|u| u[0] == chosen)
                .expect("the winner is a unit")
                .clone(),
            None => vec![chosen],
        };
        if removed.len() > 1 {
            record.removed_group = removed.clone();
        }
        self.record(hooks, record, &eval)?;
        let hint = spectrum_hint(score, eval.lambda());
        self.warm = match groups {
            Some(_) => ctx.hand_on_set(eval, hint),
            None => ctx.hand_on(chosen, eval, hint),
        };
        for c in removed {
            self.active.remove(c);
        }
        Ok(None)
    }

    /// Why the run stops at structure `eval` with removable `candidates`, if it does.
    fn stop(&self, eval: &Evaluation, candidates: &[usize]) -> Option<StopReason> {
        let k = self.iterations.len();
        if eval.length <= self.budget {
            Some(StopReason::BudgetMet)
        } else if candidates.is_empty() && self.constraints.is_some() {
            Some(StopReason::Blocked)
        } else if candidates.is_empty() || eval.curves.len() <= 1 {
            Some(StopReason::BudgetUnmet)
        } else if self.params.max_removals.is_some_and(|m| k >= m) {
            Some(StopReason::RemovalLimit)
        } else {
            None
        }
    }

    /// Scores every candidate at the structure's equilibrium; keeps the carried test vectors
    /// for the next iteration.
    fn search(
        &mut self,
        eval: &mut Evaluation,
        candidates: &[usize],
        hooks: &dyn GreedyHooks,
    ) -> (Candidates<'a>, Vec<CandidateScore>) {
        let tuning = self.analyzer.tuning();
        let t = Instant::now();
        let carried = if self.use_carried {
            std::mem::take(&mut self.carried)
        } else {
            Vec::new()
        };
        let mut ctx = Candidates::new(self.analyzer, &self.active, eval, carried);
        self.timings.locals_seconds += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let tie = self.params.tie_tolerance;
        let scores = search::score_all(&mut ctx, candidates, tuning, tie, &|| hooks.cancelled());
        self.timings.candidates_seconds += t.elapsed().as_secs_f64();
        self.timings.candidate_evaluations += scores.iter().filter(|s| !s.pruned).count();
        self.timings.candidates_pruned += scores.iter().filter(|s| s.pruned).count();
        self.timings.candidate_work.add(ctx.work());
        if tuning.prune && tuning.carry {
            self.carried = ctx.take_carried();
            self.use_carried = carried_pays(&scores, tuning.carry_after);
        }
        (ctx, scores)
    }

    /// Scores every unit of `units` (some hold several curves) exactly, in parallel: the
    /// score of removing the unit as a whole, recorded under its smallest curve.
    fn score_units(
        &mut self,
        eval: &mut Evaluation,
        units: &[Vec<usize>],
        hooks: &dyn GreedyHooks,
    ) -> (Candidates<'a>, Vec<CandidateScore>) {
        let t = Instant::now();
        let ctx = Candidates::new(self.analyzer, &self.active, eval, Vec::new());
        self.timings.locals_seconds += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let scores: Vec<CandidateScore> = units
            .par_iter()
            .map(|u| {
                if hooks.cancelled() {
                    return CandidateScore::of_group(u, Outcome::Failed("cancelled".into()));
                }
                CandidateScore::of_group(u, ctx.score_set(u))
            })
            .collect();
        self.timings.candidates_seconds += t.elapsed().as_secs_f64();
        self.timings.candidate_evaluations += scores.len();
        self.timings.candidate_work.add(ctx.work());
        // No test vectors are carried over a set's removal.
        self.carried = Vec::new();
        self.use_carried = false;
        (ctx, scores)
    }

    /// Hands `record` to `hooks` and keeps it.
    fn record(
        &mut self,
        hooks: &mut dyn GreedyHooks,
        record: IterationRecord,
        eval: &Evaluation,
    ) -> Result<(), SimplifyError> {
        hooks
            .iteration(&record, eval)
            .map_err(SimplifyError::Hook)?;
        self.iterations.push(record);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::{StopReason, spectrum_hint};

    #[test]
    fn stop_reasons_read_as_words() {
        assert_eq!(StopReason::BudgetMet.to_string(), "budget met");
        assert_eq!(
            StopReason::RemovalLimit.to_string(),
            "removal limit reached"
        );
    }

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
