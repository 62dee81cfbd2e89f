//! What a run tells its user beside its record: the warnings of its set-up and of its end,
//! and the refusal of a resume that asks for steps a finished run lacks.

use crate::app::AppError;
use crate::fmt::length;
use crate::network::{BuildInfo, Network};
use crate::run_folder::ResultFile;
use crate::simplify::{GreedyOutcome, StopReason};
use crate::words::{Message, Opt, message};
use std::path::Path;

/// The warnings of a run's set-up that let it go on: a budget that removes nothing or that
/// the keep list alone exceeds, curves that cross nothing.
pub(super) fn start_warnings(
    network: &Network,
    info: &BuildInfo,
    keep: &[usize],
    budget: f64,
    total: f64,
) -> Vec<Message> {
    let mut warnings = Vec::new();
    if budget >= total {
        warnings.push(Message::from(format!(
            "the budget {} is not below the total length {}: nothing will be removed",
            length(budget),
            length(total)
        )));
    }
    let kept_length = network.total_length(keep);
    if kept_length > budget {
        warnings.push(Message::from(format!(
            "the keep list alone needs {}, more than the budget {}: the budget cannot be met",
            length(kept_length),
            length(budget)
        )));
    }
    if !info.isolated_curves.is_empty() {
        warnings.push(Message::from(format!(
            "curves that cross nothing: {}",
            list(&info.isolated_curves)
        )));
    }
    warnings
}

/// The warning of a run that ended without meeting its budget: what it ended at and why.
pub(super) fn budget_unmet(outcome: &GreedyOutcome, budget: f64) -> Option<Message> {
    let last = outcome.iterations.last()?;
    let why = match outcome.stop {
        StopReason::BudgetMet => return None,
        StopReason::BudgetUnmet if last.curves.len() == 1 => {
            "a single curve is left, and it alone is longer than the budget"
        }
        StopReason::BudgetUnmet => "only curves of the keep list are left",
        StopReason::NoScorableCandidate => "no curve could be scored for removal",
        StopReason::RemovalLimit => "the removal limit was reached",
        StopReason::Blocked => "the design constraints allow no further removal",
    };
    Some(Message::from(format!(
        "the budget {} was not met: the run ended at {} curve(s) of total length {} ({why}); \
         the final network is over the budget",
        length(budget),
        last.curves.len(),
        length(last.length)
    )))
}

/// Refuses to call a finished run's resume done when it asks for a step the run did not
/// take (the local search, alternatives, the certificate): the recorded run is left as it
/// is, and the message names the option.
pub(super) fn refuse_missing_steps(
    result: &ResultFile,
    spec: &super::RunSpec,
    out: &Path,
) -> Result<(), AppError> {
    let lacks = if spec.local_search && result.local_search.is_none() {
        message!["without ", Opt::LocalSearch]
    } else if spec.alternatives > result.alternatives.len() {
        message![
            format!(
                "with {} alternative(s), fewer than ",
                result.alternatives.len()
            ),
            crate::words::given(Opt::Alternatives, spec.alternatives),
            " asks"
        ]
    } else if spec.certify && result.certificate.is_none() {
        message!["without ", Opt::Certify]
    } else {
        return Ok(());
    };
    Err(AppError::Usage(
        lacks
            .prefixed([format!("{}: the run is complete, ", out.display()).into()])
            .then(
                message![
                    ": a resume only finishes an interrupted run; run again without ",
                    Opt::Resume,
                    " (a fresh run in the folder) for the steps it lacks"
                ]
                .pieces()
                .iter()
                .cloned(),
            ),
    ))
}

/// Curve ids as a user reads them: `3, 5, 8`.
pub(crate) fn list(ids: &[usize]) -> String {
    ids.iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}
