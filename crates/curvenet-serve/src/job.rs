//! [`Job`]: what the server's greedy, local search and slide share about a run on a thread of
//! its own — its status, its budget, its time, its cancel token and why it failed — and
//! [`Runs`], the one-at-a-time runner of the local search and the slide around it (start on a
//! thread, record how it ended, cancel, stop).

use crate::greedy::RunStatus;
use curvenet::cancel::Cancel;
use curvenet::simplify::SimplifyError;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// One run's status, budget, time, cancel token and error.
#[derive(Debug)]
pub(crate) struct Job {
    /// Where the run is.
    pub(crate) status: RunStatus,
    /// Its budget: `(fraction of the total length, length)`.
    pub(crate) request: Option<(f64, f64)>,
    /// Why it failed.
    pub(crate) error: Option<String>,
    started: Option<Instant>,
    elapsed: Option<Duration>,
    cancel: Cancel,
}

impl Default for Job {
    fn default() -> Self {
        Job {
            status: RunStatus::Idle,
            request: None,
            error: None,
            started: None,
            elapsed: None,
            cancel: Cancel::never(),
        }
    }
}

impl Job {
    /// A run computing from now under the budget `(fraction, length)`.
    pub(crate) fn running(budget: (f64, f64)) -> Self {
        Job {
            status: RunStatus::Running,
            request: Some(budget),
            error: None,
            started: Some(Instant::now()),
            elapsed: None,
            cancel: Cancel::new(),
        }
    }

    /// The token the run polls.
    pub(crate) fn token(&self) -> Cancel {
        self.cancel.clone()
    }

    /// Asks the run to stop.
    pub(crate) fn cancel(&self) {
        self.cancel.cancel();
    }

    /// Whether a run computes.
    pub(crate) fn is_running(&self) -> bool {
        self.status == RunStatus::Running
    }

    /// The budget as a fraction of the total length.
    pub(crate) fn budget(&self) -> Option<f64> {
        self.request.map(|r| r.0)
    }

    /// The budget as a length.
    pub(crate) fn budget_length(&self) -> Option<f64> {
        self.request.map(|r| r.1)
    }

    /// Time since the run started (its duration once it is over), milliseconds.
    pub(crate) fn elapsed_ms(&self) -> Option<f64> {
        self.elapsed
            .or_else(|| self.started.map(|t| t.elapsed()))
            .map(|d| d.as_secs_f64() * 1e3)
    }

    /// Records how the run (the `what`, in messages) ended: done, cancelled, failed with its
    /// error, or stopped by a panic; the value of a run that returned one.
    pub(crate) fn end<T>(
        &mut self,
        outcome: std::thread::Result<Result<T, SimplifyError>>,
        what: &str,
    ) -> Option<T> {
        self.elapsed = self.started.map(|t| t.elapsed());
        match outcome {
            Ok(Ok(value)) => {
                self.status = RunStatus::Done;
                return Some(value);
            }
            Ok(Err(SimplifyError::Cancelled)) => self.status = RunStatus::Cancelled,
            Ok(Err(e)) => {
                self.status = RunStatus::Error;
                let why = match e {
                    SimplifyError::Params(m) => crate::words::say(&m),
                    e => e.to_string(),
                };
                self.error = Some(format!("the {what} failed: {why}"));
            }
            Err(_) => {
                self.status = RunStatus::Error;
                self.error = Some(format!(
                    "the {what} stopped unexpectedly (an internal error)"
                ));
            }
        }
        None
    }
}

/// What a run records beside its [`Job`]: the structure it started from and its own data `S`
/// (progress, result).
#[derive(Debug, Default)]
pub(crate) struct RunState<S> {
    /// Its status, budget, time, cancel token and error.
    pub(crate) job: Job,
    /// The structure it started from.
    pub(crate) from: Option<Vec<usize>>,
    /// Its own data.
    pub(crate) data: S,
}

/// The runs of one kind (the local search, the slide): at most one at a time on a thread of
/// its own, its state behind one lock — what starting, cancelling and stopping one share.
#[derive(Debug, Default)]
pub(crate) struct Runs<S> {
    state: Mutex<RunState<S>>,
}

impl<S: Default + Send + 'static> Runs<S> {
    /// Starts `work` (the run `what`, in messages) on a thread of its own from the structure
    /// `from` under the budget `(fraction, length)`; `work` polls the cancel token it is given
    /// and may record progress through the runs it is given; `finish` records the value of a
    /// run that returned one (its status already done). `false` when a run computes.
    pub(crate) fn start<T: Send + 'static>(
        self: &Arc<Self>,
        budget: (f64, f64),
        from: Vec<usize>,
        what: &'static str,
        work: impl FnOnce(&Cancel, &Self) -> Result<T, SimplifyError> + Send + 'static,
        finish: impl FnOnce(&mut RunState<S>, T) + Send + 'static,
    ) -> bool {
        let mut s = self.lock();
        if s.job.is_running() {
            return false;
        }
        *s = RunState {
            job: Job::running(budget),
            from: Some(from),
            data: S::default(),
        };
        let cancel = s.job.token();
        drop(s);
        let runs = Arc::clone(self);
        std::thread::spawn(move || {
            let outcome =
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| work(&cancel, &runs)));
            let mut s = runs.lock();
            if let Some(value) = s.job.end(outcome, what) {
                finish(&mut s, value);
            }
        });
        true
    }

    /// Asks the computing run to stop (it keeps the best it reached); `false` when none
    /// computes.
    pub(crate) fn cancel(&self) -> bool {
        let s = self.lock();
        s.job.is_running() && {
            s.job.cancel();
            true
        }
    }

    /// Asks the run to stop if one computes (the design it runs on is being replaced).
    pub(crate) fn stop(&self) {
        self.lock().job.cancel();
    }

    /// The state (a panic elsewhere leaves the last whole state).
    pub(crate) fn lock(&self) -> MutexGuard<'_, RunState<S>> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }
}
