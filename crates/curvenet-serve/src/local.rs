//! The local search over HTTP: one run at a time of the library's local search
//! ([`curvenet::simplify::local::local_search`]) on the design's network, from the structure
//! current when it starts, on a thread of its own so that edits and reads stay answered while
//! it runs; its progress, its cancellation and its best network, which a designer adopts as
//! the current structure.
//!
//! The search is the one `curvenet simplify --local-search` runs after the greedy: moves
//! (add, drop, swap, part steps, variable-depth chains) within the budget, from the given
//! start (here the current structure, when it fits the budget and the constraints) and from
//! the three stiffest single curves (and, under a minimum number of curves or a largest gap,
//! the best networks grown to meet it), honouring the session's design constraints. It has no
//! intermediate progress: it reports its result when it ends (a cancelled search reports the
//! best network it had reached).

use crate::design::Design;
use crate::greedy::{GreedyError, Request, RunStatus};
use crate::job::{RunState, Runs};
use curvenet::app::Search;
use curvenet::cancel::Cancel;
use curvenet::constraints::Constraints;
use curvenet::simplify::SimplifyError;
use curvenet::simplify::exhaustive::SubsetScore;
use curvenet::simplify::local::{LocalOutcome, keep_fits, local_search};
use serde::Serialize;
use std::sync::Arc;

/// A network the search evaluated.
#[derive(Clone, Debug, Serialize)]
pub struct Found {
    /// Kept curves, ascending.
    pub curves: Vec<usize>,
    /// Total rest length.
    pub length: f64,
    /// The objective's value (`λ_eq`, or `μ_min` under the frequency objective), relaxed from
    /// the drawn state.
    pub lambda: f64,
}

impl From<&SubsetScore> for Found {
    fn from(s: &SubsetScore) -> Self {
        Found {
            curves: s.curves.clone(),
            length: s.length,
            lambda: s.lambda,
        }
    }
}

/// What a finished (or cancelled) search found.
#[derive(Clone, Debug, Serialize)]
pub struct LocalResult {
    /// The best network reached.
    pub best: Found,
    /// The start that reached it.
    pub start: Found,
    /// The current structure as it was scored, when the search started from it (it fitted
    /// the budget and the constraints).
    pub given: Option<Found>,
    /// Moves taken from that start to the best network.
    pub moves: usize,
    /// Distinct networks evaluated.
    pub evaluations: usize,
    /// Whether the search was cancelled (`best` is the best reached by then).
    pub cancelled: bool,
    /// Whether the best network meets `max_deviation` (always without it).
    pub within_deviation: bool,
}

impl LocalResult {
    fn of(o: &LocalOutcome, constraints: Option<&Constraints>) -> Self {
        LocalResult {
            best: (&o.best).into(),
            start: (&o.start).into(),
            given: o.given().map(Found::from),
            moves: o.steps.len(),
            evaluations: o.evaluations,
            cancelled: o.cancelled,
            within_deviation: o.within_deviation(constraints),
        }
    }
}

/// The progress of the current (or last) search: what `GET /api/local` answers.
#[derive(Clone, Debug, Serialize)]
pub struct LocalProgress {
    /// Where the search is (`idle`, `running`, `done`, `cancelled`, `error`).
    pub status: RunStatus,
    /// The budget as a fraction of the network's total rest length.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub budget: Option<f64>,
    /// The budget as a length.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub budget_length: Option<f64>,
    /// The structure the search started from (the current one when it started).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub from: Option<Vec<usize>>,
    /// What it found, once it ended.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub result: Option<LocalResult>,
    /// Why the search failed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Time since the search started (its duration once it is over), milliseconds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub elapsed_ms: Option<f64>,
}

/// The server's local search: at most one at a time, its progress and its result.
#[derive(Debug, Default)]
pub struct LocalRunner {
    runs: Arc<Runs<Option<LocalResult>>>,
}

impl LocalRunner {
    /// Starts a search on `design`'s network from its current structure with `request`'s
    /// `search` ([`Request::search`]: its budget, keep list and constraints; `max_removals`
    /// is the greedy's); answers its first progress.
    ///
    /// # Errors
    ///
    /// [`GreedyError::LocalBusy`] while a search computes.
    pub fn start(
        &self,
        design: Arc<Design>,
        request: &Request,
        search: Search,
    ) -> Result<LocalProgress, GreedyError> {
        let params = search.local();
        // Kept curves over the budget leave nothing to search: said at once, with what helps.
        keep_fits(&design.analyzer().lengths(), params.budget, &params.keep).map_err(|e| {
            GreedyError::Params(match e {
                SimplifyError::Params(m) => crate::words::say(&m),
                e => e.to_string(),
            })
        })?;
        let from = design.current().summary.curves.clone();
        let search = Arc::new(search);
        let work = {
            let (from, search) = (from.clone(), Arc::clone(&search));
            move |cancel: &Cancel, _: &Runs<Option<LocalResult>>| {
                // A search with no start that fits says how to give it one.
                let how = "; it starts from the current structure (when it fits) and from \
                           single curves: make a structure that fits current (a greedy \
                           iteration, for one) and start it again";
                local_search(
                    design.analyzer(),
                    &params,
                    Some(&search.constraints),
                    &from,
                    cancel,
                )
                .map_err(|e| match e {
                    SimplifyError::Params(m) => SimplifyError::Params(m.then([how.into()])),
                    e => e,
                })
            }
        };
        let budget = (request.budget, search.budget_length);
        let finish = move |s: &mut RunState<Option<LocalResult>>, o: LocalOutcome| {
            if o.cancelled {
                s.job.status = RunStatus::Cancelled;
            }
            s.data = Some(LocalResult::of(&o, Some(&search.constraints)));
        };
        if !self.runs.start(budget, from, "local search", work, finish) {
            return Err(GreedyError::LocalBusy);
        }
        Ok(self.progress())
    }

    /// The progress of the current (or last) search.
    pub fn progress(&self) -> LocalProgress {
        progress_of(&self.runs.lock())
    }

    /// Asks the computing search to stop (it does within one evaluation, keeping the best
    /// network it reached).
    ///
    /// # Errors
    ///
    /// [`GreedyError::LocalNotRunning`] when no search computes.
    pub fn cancel(&self) -> Result<LocalProgress, GreedyError> {
        if !self.runs.cancel() {
            return Err(GreedyError::LocalNotRunning);
        }
        Ok(self.progress())
    }

    /// Asks the search to stop if one computes (the design it runs on is being replaced).
    pub fn stop(&self) {
        self.runs.stop();
    }

    /// The curves of the best network found, once a search has ended with one.
    ///
    /// # Errors
    ///
    /// [`GreedyError::NoLocalResult`] while no search has a result (none ran, one is running, or
    /// it failed).
    pub fn best(&self) -> Result<Vec<usize>, GreedyError> {
        let s = self.runs.lock();
        match (&s.job.status, &s.data) {
            (RunStatus::Running, _) | (_, None) => Err(GreedyError::NoLocalResult),
            (_, Some(r)) => Ok(r.best.curves.clone()),
        }
    }
}

fn progress_of(s: &RunState<Option<LocalResult>>) -> LocalProgress {
    LocalProgress {
        status: s.job.status,
        budget: s.job.budget(),
        budget_length: s.job.budget_length(),
        from: s.from.clone(),
        result: s.data.clone(),
        error: s.job.error.clone(),
        elapsed_ms: s.job.elapsed_ms(),
    }
}
