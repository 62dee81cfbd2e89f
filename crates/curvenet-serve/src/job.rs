//! [`Job`]: what the server's greedy and local search share about a run on a thread of its
//! own — its status, its budget, its time, its cancel token and why it failed.

use crate::greedy::RunStatus;
use curvenet::cancel::Cancel;
use curvenet::simplify::SimplifyError;
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
