//! [`Observer`]: what a run tells its front end while it goes (warnings, notes, each greedy
//! iteration, the stages that poll the cancellation token), for it to print, forward to a
//! Python callback or stream to a page.

use super::error::Stage;
use crate::simplify::greedy::IterationRecord;
use crate::words::Message;

/// Receives what a run reports as it goes. Every method has a default that ignores it.
pub trait Observer: Sync {
    /// A finding the run goes on with (an input's oddity, a budget that removes nothing).
    fn warning(&self, warning: &Message) {
        let _ = warning;
    }
    /// Information: what was left out, what was removed from a folder, what a resume does.
    fn note(&self, note: &Message) {
        let _ = note;
    }
    /// One greedy iteration recorded; `total` is the network's total length and `budget`
    /// the run's budget (both scene units).
    fn iteration(&self, record: &IterationRecord, total: f64, budget: f64) {
        let _ = (record, total, budget);
    }
    /// One step sliding took: the networks evaluated so far and the objective reached.
    fn slide_step(&self, step: &crate::slide::Step) {
        let _ = step;
    }
    /// A stage that polls the cancellation token starts (`true`) or ends (`false`). The
    /// command line cancels the token on Ctrl-C only inside such a stage, and exits at once
    /// outside.
    fn stage(&self, stage: Stage, started: bool) {
        let _ = (stage, started);
    }
}

/// An observer that ignores everything.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Observer for Silent {}

/// A guard that reports a stage's start and, when dropped, its end.
pub(crate) struct StageGuard<'a> {
    observer: &'a dyn Observer,
    stage: Stage,
}

impl<'a> StageGuard<'a> {
    /// Reports `stage`'s start to `observer`.
    pub(crate) fn start(observer: &'a dyn Observer, stage: Stage) -> Self {
        observer.stage(stage, true);
        StageGuard { observer, stage }
    }
}

impl Drop for StageGuard<'_> {
    fn drop(&mut self) {
        self.observer.stage(self.stage, false);
    }
}
