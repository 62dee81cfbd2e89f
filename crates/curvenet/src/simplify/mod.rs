//! Simplification: pick the subset of curves that fits the budget and is most stable
//! (`docs/model.md`, *Greedy simplification* and *Searches beyond the greedy*).
//!
//! - [`greedy()`]: the paper's Algorithm 1, every iteration recorded;
//! - [`local`]: local search (add, drop, swap, part steps, chains) from a feasible subset,
//!   e.g. the greedy's;
//! - [`exhaustive`]: all feasible subsets, the exact optimum of `λ_eq` (or `λ_fix`) for small
//!   networks;
//! - [`random`]: uniformly random feasible subsets, a given number of evaluations;
//! - [`exact`]: branch and bound for the optimum of `λ_fix`, with a proof;
//! - [`certificate`]: certified upper bounds on the best `λ_fix` from the continuous
//!   relaxation;
//!
//! The run folder a greedy run writes is [`crate::run_folder`]; the experiments that compare
//! the searches are [`crate::experiments`].
//!
//! These modules are the searches' policy: which set to evaluate next, what to prune, who
//! wins. Every number comes from the stability facade ([`crate::stability`]), which evaluates
//! `λ_eq(S)` and `λ_fix(S | A)` the same way for every search, so their answers compare.
//! Every long search polls a [`crate::cancel::Cancel`] token and stops within a second.

pub mod certificate;
#[cfg(test)]
mod constrained_tests;
pub mod exact;
pub mod exhaustive;
pub mod greedy;
pub mod local;
pub mod random;

pub use crate::stability::Budget;
pub use greedy::{GreedyHooks, GreedyOutcome, GreedyParams, StopReason, greedy};

use crate::stability::StabilityError;
use crate::words::Message;

/// Why a search could not run.
#[derive(Debug, thiserror::Error)]
pub enum SimplifyError {
    /// Bad parameters (the message names the option when a user set it).
    #[error("{0}")]
    Params(Message),
    /// A stability computation failed.
    #[error(transparent)]
    Stability(StabilityError),
    /// The run was cancelled; everything recorded so far is kept.
    #[error("cancelled")]
    Cancelled,
    /// A hook (e.g. writing progress) failed.
    #[error("{0}")]
    Hook(String),
}

impl SimplifyError {
    /// The error as a message naming the options a user set, for a front end to spell
    /// (`Display` shows it neutrally).
    pub fn message(&self) -> Message {
        match self {
            SimplifyError::Params(m) => m.clone(),
            SimplifyError::Stability(StabilityError::Params(m)) => m.clone(),
            e => Message::from(e.to_string()),
        }
    }
}

impl From<StabilityError> for SimplifyError {
    fn from(e: StabilityError) -> Self {
        match e {
            StabilityError::Cancelled => SimplifyError::Cancelled,
            e => SimplifyError::Stability(e),
        }
    }
}

impl From<crate::cancel::Cancelled> for SimplifyError {
    fn from(_: crate::cancel::Cancelled) -> Self {
        SimplifyError::Cancelled
    }
}

/// Picks the best of `(curve, score)` pairs: the largest score, treating scores within a
/// relative `tie` of the best as equal and taking the lowest curve id among them.
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
}
