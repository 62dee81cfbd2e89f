//! The slide over HTTP: one slide at a time of the current structure's curves on the
//! surface ([`curvenet::app::Drawing::slider`]), on a thread of its own as the local search
//! runs (both on [`crate::job::Runs`]): its progress (evaluations, the best objective so far), its
//! cancellation (the best network so far kept) and its slid curves, which a designer adopts
//! as one drawing edit.

use crate::greedy::RunStatus;
use crate::job::{RunState, Runs};
use curvenet::cancel::Cancel;
use curvenet::io::Polyline;
use curvenet::simplify::SimplifyError;
use curvenet::slide::search::Step;
use curvenet::slide::{SlideOutcome, Slider};
use serde::Serialize;
use std::sync::Arc;

/// What a finished (or cancelled) slide found.
#[derive(Clone, Debug, Serialize)]
pub struct SlideResult {
    /// The objective (`λ_eq`, or `μ_min`) of the structure before the slide (rebuilt from its
    /// drawn curves on their own).
    pub lambda_before: f64,
    /// The objective of the slid structure.
    pub lambda_after: f64,
    /// Total rest length before.
    pub length_before: f64,
    /// Total rest length after.
    pub length_after: f64,
    /// The largest distance a curve moved.
    pub largest_move: f64,
    /// The largest move allowed.
    pub max_move: f64,
    /// Networks evaluated.
    pub evaluations: usize,
    /// Whether the slide was cancelled (the best network reached by then is kept).
    pub cancelled: bool,
    /// Whether it moved anything.
    pub moved: bool,
    /// Whether it stopped at the most evaluations asked for (checked before each one, within
    /// a sweep of the search too; the best network so far is kept).
    pub limited: bool,
}

/// The progress of the current (or last) slide: what `GET /api/slide` answers.
#[derive(Clone, Debug, Serialize)]
pub struct SlideProgress {
    /// Where the slide is (`idle`, `running`, `done`, `cancelled`, `error`).
    pub status: RunStatus,
    /// The budget as a fraction of the network's total rest length.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub budget: Option<f64>,
    /// The budget as a length.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub budget_length: Option<f64>,
    /// The structure that slides (the current one when it started).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub from: Option<Vec<usize>>,
    /// Networks evaluated when the search last improved (all of them once it ended).
    pub evaluations: usize,
    /// The best objective reached so far.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub best: Option<f64>,
    /// What it found, once it ended.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub result: Option<SlideResult>,
    /// Why the slide failed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Time since the slide started (its duration once it is over), milliseconds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub elapsed_ms: Option<f64>,
}

/// Why a slide request was refused.
#[derive(Debug, thiserror::Error)]
pub enum SlideRunError {
    /// A slide is computing (one at a time).
    #[error("a slide is already computing; cancel it (POST /api/slide/cancel) or wait")]
    Busy,
    /// Nothing is computing (cancel).
    #[error("no slide is computing")]
    NotRunning,
    /// No slide has curves to adopt.
    #[error(
        "no slide result to adopt: start one with POST /api/slide and wait for it to end (a \
         drawing edit since then forgets it)"
    )]
    NothingToAdopt,
}

/// What a slide records beside its job: its progress and, once it ended, what it found and
/// its slid curves (one per curve of the structure it slid).
#[derive(Debug, Default)]
struct Slid {
    evaluations: usize,
    best: Option<f64>,
    result: Option<SlideResult>,
    curves: Option<Vec<Polyline>>,
}

/// The server's slide: at most one at a time, its progress and its slid curves.
#[derive(Debug, Default)]
pub struct SlideRunner {
    runs: Arc<Runs<Slid>>,
}

impl SlideRunner {
    /// Starts `slider`, the slide of the structure `from` under the budget `(fraction,
    /// length)`; answers its first progress.
    ///
    /// # Errors
    ///
    /// [`SlideRunError::Busy`] while a slide computes.
    pub fn start(
        &self,
        slider: Slider,
        from: Vec<usize>,
        budget: (f64, f64),
    ) -> Result<SlideProgress, SlideRunError> {
        let work = move |cancel: &Cancel, runs: &Runs<Slid>| {
            let step = |st: &Step| {
                let mut s = runs.lock();
                let d = &mut s.data;
                d.evaluations = d.evaluations.max(st.evaluation);
                if st.value.is_finite() {
                    d.best = Some(d.best.map_or(st.value, |b| b.max(st.value)));
                }
            };
            slider
                .run(cancel, &step)
                .map_err(|e| SimplifyError::Params(e.message()))
        };
        let finish = |s: &mut RunState<Slid>, o: SlideOutcome| {
            let (before, after) = (&o.before, &o.after);
            if o.search.cancelled {
                s.job.status = RunStatus::Cancelled;
            }
            s.data = Slid {
                evaluations: o.search.evaluations,
                best: Some(after.lambda),
                result: Some(SlideResult {
                    lambda_before: before.lambda,
                    lambda_after: after.lambda,
                    length_before: before.length,
                    length_after: after.length,
                    largest_move: after.moves.iter().copied().fold(0.0, f64::max),
                    max_move: o.max_move,
                    evaluations: o.search.evaluations,
                    cancelled: o.search.cancelled,
                    moved: o.coefficients.iter().flatten().any(|&a| a != 0.0),
                    limited: o.search.limited,
                }),
                curves: Some(after.curves.clone()),
            };
        };
        if !self.runs.start(budget, from, "slide", work, finish) {
            return Err(SlideRunError::Busy);
        }
        Ok(self.progress())
    }

    /// The progress of the current (or last) slide.
    pub fn progress(&self) -> SlideProgress {
        progress_of(&self.runs.lock())
    }

    /// Asks the computing slide to stop (it does within a second, keeping the best network
    /// it reached).
    ///
    /// # Errors
    ///
    /// [`SlideRunError::NotRunning`] when no slide computes.
    pub fn cancel(&self) -> Result<SlideProgress, SlideRunError> {
        if !self.runs.cancel() {
            return Err(SlideRunError::NotRunning);
        }
        Ok(self.progress())
    }

    /// Asks the slide to stop if one computes (the design it runs on is being replaced).
    pub fn stop(&self) {
        self.runs.stop();
    }

    /// The structure that slid and its slid curves, once a slide has ended with them.
    ///
    /// # Errors
    ///
    /// [`SlideRunError::NothingToAdopt`] while no slide has them (none ran, one is running,
    /// or it failed).
    pub fn slid(&self) -> Result<(Vec<usize>, Vec<Polyline>), SlideRunError> {
        let s = self.runs.lock();
        match (&s.job.status, &s.from, &s.data.curves) {
            (RunStatus::Done | RunStatus::Cancelled, Some(f), Some(c)) => {
                Ok((f.clone(), c.clone()))
            }
            _ => Err(SlideRunError::NothingToAdopt),
        }
    }
}

fn progress_of(s: &RunState<Slid>) -> SlideProgress {
    SlideProgress {
        status: s.job.status,
        budget: s.job.budget(),
        budget_length: s.job.budget_length(),
        from: s.from.clone(),
        evaluations: s.data.evaluations,
        best: s.data.best,
        result: s.data.result.clone(),
        error: s.job.error.clone(),
        elapsed_ms: s.job.elapsed_ms(),
    }
}
