//! The greedy over HTTP: one run at a time of the library's greedy
//! ([`curvenet::simplify::greedy()`]) on the design's network, on a thread of its own so that
//! edits and reads stay answered while it runs; its progress, its cancellation and its
//! recorded iterations, which a designer steps through by making one of them the current
//! structure.
//!
//! The run starts from the whole network, as `curvenet simplify` does, whatever structure is
//! current: its iterations are those of `simplify` with the same budget, keep list and design
//! constraints (the session's, bound to the run's budget and keep list by the caller).

use crate::constraints::SessionConstraints;
use crate::design::Design;
use crate::job::Job;
use curvenet::app::Search;
use curvenet::cancel::Cancel;
use curvenet::io::TriMesh;
use curvenet::physics::PhysicalSummary;
use curvenet::run_folder::instability;
use curvenet::simplify::greedy::{GreedyHooks, IterationRecord};
use curvenet::simplify::{Budget, greedy};
use curvenet::stability::Evaluation;
use serde::Serialize;
use std::sync::{Arc, Mutex, MutexGuard};

/// Where the greedy is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RunStatus {
    /// No run yet.
    Idle,
    /// A run is computing.
    Running,
    /// The run finished (the budget met, or a stop reason says why not).
    Done,
    /// The run was cancelled; the iterations recorded before are kept.
    Cancelled,
    /// The run failed; the iterations recorded before are kept.
    Error,
}

/// One recorded iteration of the greedy, as listed by `GET /api/greedy/iterations`.
#[derive(Clone, Debug, Serialize)]
pub struct Step {
    /// Its index: removals made before it.
    pub iteration: usize,
    /// Kept curves, ascending.
    pub curves: Vec<usize>,
    /// `λ_eq` of the structure, relaxed from the previous iteration's equilibrium.
    pub lambda: f64,
    /// Total rest length.
    pub length: f64,
    /// Zero eigenvalues among the smallest computed (a mechanism).
    pub zero_modes: usize,
    /// Negative eigenvalues among them (an unstable equilibrium).
    pub negative_modes: usize,
    /// The curve removed next (`None` on the last iteration).
    pub removed: Option<usize>,
    /// Whether its relaxation reached equilibrium (when not, `λ` is measured where it
    /// stopped).
    pub converged: bool,
    /// In the physical mode, the structure's physical numbers.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub physical: Option<PhysicalSummary>,
}

impl Step {
    fn of(k: usize, r: &IterationRecord) -> Self {
        Step {
            iteration: k,
            curves: r.curves.clone(),
            lambda: r.lambda,
            length: r.length,
            zero_modes: r.zero_modes,
            negative_modes: r.negative_modes,
            removed: r.removed,
            converged: r.newton.converged,
            physical: r.physical.clone(),
        }
    }
}

/// The progress of the current (or last) run: what `GET /api/greedy` answers.
#[derive(Clone, Debug, Serialize)]
pub struct Progress {
    /// Where the run is.
    pub status: RunStatus,
    /// The budget as a fraction of the network's total rest length.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub budget: Option<f64>,
    /// The budget as a length.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub budget_length: Option<f64>,
    /// Iterations recorded so far.
    pub iterations: usize,
    /// The last recorded iteration: its index, `λ_eq` and length.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub last: Option<Last>,
    /// Why a finished run stopped, in words.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stop: Option<String>,
    /// Why a run failed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Time since the run started (its duration once it is over), milliseconds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub elapsed_ms: Option<f64>,
}

/// The last recorded iteration, in [`Progress`].
#[derive(Clone, Debug, Serialize)]
pub struct Last {
    /// Its index.
    pub iteration: usize,
    /// Its `λ_eq`.
    pub lambda: f64,
    /// Its total rest length.
    pub length: f64,
    /// Curves kept.
    pub curves: usize,
    /// What makes it unstable, in words (`None`: stable).
    pub unstable: Option<String>,
    /// Whether its relaxation reached equilibrium.
    pub converged: bool,
}

/// Why a greedy request was refused.
#[derive(Debug, thiserror::Error)]
pub enum GreedyError {
    /// A run is computing (only one at a time).
    #[error("a greedy run is already computing; cancel it (POST /api/greedy/cancel) or wait")]
    Busy,
    /// Nothing is computing (cancel).
    #[error("no greedy run is computing")]
    NotRunning,
    /// The parameters are out of range.
    #[error("{0}")]
    Params(String),
    /// No run has recorded an iteration yet.
    #[error("no greedy iteration recorded yet: start a run with POST /api/greedy")]
    NoRun,
    /// A local search is computing (only one at a time).
    #[error("a local search is already computing; cancel it (POST /api/local/cancel) or wait")]
    LocalBusy,
    /// No local search is computing (cancel).
    #[error("no local search is computing")]
    LocalNotRunning,
    /// No local search has a result to adopt.
    #[error("no local search result yet: start one with POST /api/local and wait for it to end")]
    NoLocalResult,
    /// No recorded iteration of that index.
    #[error("no iteration {asked}: the greedy recorded iterations 0..{last}")]
    NoIteration {
        /// The index asked for.
        asked: usize,
        /// The last recorded index.
        last: usize,
    },
}

/// The greedy's parameters as a request gives them.
#[derive(Clone, Debug)]
pub struct Request {
    /// The budget as a fraction of the total rest length, in `(0, 1]`.
    pub budget: f64,
    /// Curves never removed.
    pub keep: Vec<usize>,
    /// Stop after this many removals.
    pub max_removals: Option<usize>,
}

impl Request {
    /// The search of the request on `design`'s network under the session's `constraints`
    /// (with the surface `mesh`), bound as a run binds its own.
    ///
    /// # Errors
    ///
    /// [`GreedyError::Params`] for a budget out of `(0, 1]`, an unknown curve to keep, a keep
    /// list holding every curve, or constraints no network within the budget can meet.
    pub fn search(
        &self,
        design: &Design,
        constraints: &mut SessionConstraints,
        mesh: Option<&TriMesh>,
    ) -> Result<Search, GreedyError> {
        let net = design.analyzer().network();
        let mut search = constraints
            .for_search(net, mesh, Budget::Fraction(self.budget), self.keep.clone())
            .map_err(GreedyError::Params)?;
        search.greedy.max_removals = self.max_removals;
        Ok(search)
    }
}

/// The state shared by the run's thread and the handlers.
#[derive(Debug, Default)]
struct Shared {
    job: Job,
    iterations: Vec<Step>,
    stop: Option<String>,
}

/// The server's greedy: at most one run at a time, its progress and its iterations.
#[derive(Debug, Default)]
pub struct Runner {
    shared: Mutex<Shared>,
}

impl Runner {
    /// A runner holding the iterations of an earlier run (a run folder's), as if it had just
    /// finished with `stop` under the budget `(fraction, length)`.
    pub fn finished(records: &[IterationRecord], budget: (f64, f64), stop: Option<String>) -> Self {
        let r = Runner::default();
        {
            let mut s = r.lock();
            s.job.status = RunStatus::Done;
            s.job.request = Some(budget);
            s.iterations = records
                .iter()
                .enumerate()
                .map(|(k, r)| Step::of(k, r))
                .collect();
            s.stop = stop;
        }
        r
    }

    /// Starts a run on `design`'s network with `request`'s `search` ([`Request::search`]);
    /// answers its first progress.
    ///
    /// # Errors
    ///
    /// [`GreedyError::Busy`] while a run computes.
    pub fn start(
        self: &Arc<Self>,
        design: Arc<Design>,
        request: &Request,
        search: Search,
    ) -> Result<Progress, GreedyError> {
        let mut s = self.lock();
        if s.job.is_running() {
            return Err(GreedyError::Busy);
        }
        *s = Shared {
            job: Job::running((request.budget, search.budget_length)),
            iterations: Vec::new(),
            stop: None,
        };
        let cancel = s.job.token();
        let progress = progress_of(&s);
        drop(s);
        let runner = Arc::clone(self);
        std::thread::spawn(move || runner.run(&design, &search, cancel));
        Ok(progress)
    }

    /// The run's body, on its own thread: the library's greedy, its outcome recorded.
    fn run(&self, design: &Design, search: &Search, cancel: Cancel) {
        let mut hooks = Hooks {
            runner: self,
            cancel,
        };
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            greedy(
                design.analyzer(),
                &search.greedy,
                Some(&search.constraints),
                None,
                &mut hooks,
            )
        }));
        let mut s = self.lock();
        if let Some(out) = s.job.end(outcome, "greedy") {
            s.stop = Some(out.stop.to_string());
        }
    }

    /// The progress of the current (or last) run.
    pub fn progress(&self) -> Progress {
        progress_of(&self.lock())
    }

    /// Asks the run to stop if one computes (the design it runs on is being replaced).
    pub fn stop(&self) {
        self.lock().job.cancel();
    }

    /// Asks the computing run to stop (it does within a second, keeping its iterations).
    ///
    /// # Errors
    ///
    /// [`GreedyError::NotRunning`] when no run computes.
    pub fn cancel(&self) -> Result<Progress, GreedyError> {
        let s = self.lock();
        if !s.job.is_running() {
            return Err(GreedyError::NotRunning);
        }
        s.job.cancel();
        Ok(progress_of(&s))
    }

    /// The recorded iterations (of a run still computing: those so far).
    pub fn iterations(&self) -> (RunStatus, Vec<Step>) {
        let s = self.lock();
        (s.job.status, s.iterations.clone())
    }

    /// The curves of recorded iteration `k`.
    ///
    /// # Errors
    ///
    /// [`GreedyError::NoRun`] before any iteration is recorded, [`GreedyError::NoIteration`]
    /// when `k` is past the last one.
    pub fn curves_of(&self, k: usize) -> Result<Vec<usize>, GreedyError> {
        let s = self.lock();
        match s.iterations.get(k) {
            Some(step) => Ok(step.curves.clone()),
            None if s.iterations.is_empty() => Err(GreedyError::NoRun),
            None => Err(GreedyError::NoIteration {
                asked: k,
                last: s.iterations.len() - 1,
            }),
        }
    }

    /// The shared state (a panic elsewhere leaves the last whole state).
    fn lock(&self) -> MutexGuard<'_, Shared> {
        self.shared.lock().unwrap_or_else(|e| e.into_inner())
    }
}

fn progress_of(s: &Shared) -> Progress {
    Progress {
        status: s.job.status,
        budget: s.job.budget(),
        budget_length: s.job.budget_length(),
        iterations: s.iterations.len(),
        last: s.iterations.last().map(|l| Last {
            iteration: l.iteration,
            lambda: l.lambda,
            length: l.length,
            curves: l.curves.len(),
            unstable: instability(l.lambda, l.zero_modes, l.negative_modes),
            converged: l.converged,
        }),
        stop: s.stop.clone(),
        error: s.job.error.clone(),
        elapsed_ms: s.job.elapsed_ms(),
    }
}

/// The run's hooks: each iteration recorded in the shared state as it comes, the cancel token
/// polled.
struct Hooks<'a> {
    runner: &'a Runner,
    cancel: Cancel,
}

impl GreedyHooks for Hooks<'_> {
    fn iteration(&mut self, record: &IterationRecord, _: &Evaluation) -> Result<(), String> {
        let mut s = self.runner.lock();
        let k = s.iterations.len();
        s.iterations.push(Step::of(k, record));
        Ok(())
    }

    fn cancelled(&self) -> bool {
        self.cancel.is_cancelled()
    }
}
