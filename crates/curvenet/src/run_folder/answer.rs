//! The networks a run offers as its answer (see [`crate::constraints::answer::choose`]).

use crate::constraints::answer::Offer;
use crate::simplify::greedy::IterationRecord;
use crate::stability::Evaluation;

/// The networks of the greedy's path, offered as the run's answer in the order they were
/// recorded (`source` "greedy", with their iteration).
pub fn greedy_offers(iterations: &[IterationRecord]) -> Vec<Offer> {
    iterations
        .iter()
        .enumerate()
        .map(|(k, it)| Offer {
            source: "greedy".into(),
            iteration: Some(k),
            curves: it.curves.clone(),
            length: it.length,
            lambda: it.lambda,
            zero_modes: it.zero_modes,
            negative_modes: it.negative_modes,
            deviation: None,
        })
        .collect()
}

/// A network another search found, evaluated in full (`λ_eq`, its modes), offered as the
/// run's answer.
pub fn evaluated_offer(source: &str, eval: &Evaluation) -> Offer {
    Offer {
        source: source.into(),
        iteration: None,
        curves: eval.curves.clone(),
        length: eval.length,
        lambda: eval.lambda(),
        zero_modes: eval.spectrum.zero_modes,
        negative_modes: eval.spectrum.negative_modes,
        deviation: None,
    }
}
