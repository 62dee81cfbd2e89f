//! The networks a run offers as its answer and its alternatives (see
//! [`crate::constraints::answer::choose`]).

use super::read_f64_file;
use crate::cancel::Cancel;
use crate::constraints::answer::{Offer, choose, distinct, qualifies};
use crate::constraints::{Constraints, max_displacement};
use crate::rod::ActiveSet;
use crate::simplify::exhaustive::SubsetScore;
use crate::simplify::greedy::IterationRecord;
use crate::stability::{Analyzer, Evaluation, Prepare, Preset, Warm};
use rayon::prelude::*;
use std::path::Path;

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

/// Measures the largest deviation from the design of each of the greedy's `offers`
/// ([`greedy_offers`]): in the paper's mode the largest displacement of its iteration's state
/// in the run folder `dir`, in the physical mode the physical model's
/// ([`Analyzer::part_deviation`]).
///
/// # Errors
///
/// A state file that cannot be read or does not match the network, or a structure the
/// physical mode cannot evaluate (the offers measured so far keep their deviation; the others
/// stay unmeasured, which disqualifies them).
pub fn measure_greedy_deviations(
    offers: &mut [Offer],
    dir: &Path,
    analyzer: &Analyzer,
) -> Result<(), super::RunFolderError> {
    let network = analyzer.network();
    let dofs = 3 * network.positions.len();
    for o in offers.iter_mut() {
        let Some(k) = o.iteration else { continue };
        if analyzer.physical().is_some() {
            let d = analyzer
                .deviation(&analyzer.set(&o.curves))
                .map_err(|e| super::RunFolderError::Failed(e.to_string()))?;
            o.deviation = Some(d);
            continue;
        }
        let u = read_f64_file(&dir.join(crate::run_layout::state_file(k)))?;
        if u.len() < dofs {
            return Err(super::RunFolderError::Invalid {
                file: crate::run_layout::state_file(k),
                problem: "does not match the network".into(),
            });
        }
        o.deviation = Some(max_displacement(network, &o.curves, &u));
    }
    Ok(())
}

/// A network another search found, evaluated in full (`λ_eq`, its modes), offered as the
/// run's answer; with a largest deviation in `constraints`, its deviation from the design
/// ([`Analyzer::structure_deviation`]: the equilibrium's largest displacement, or the physical
/// mode's).
pub fn evaluated_offer(
    source: &str,
    eval: &Evaluation,
    analyzer: &Analyzer,
    constraints: &Constraints,
) -> Offer {
    let deviation = constraints.params().max_deviation.and_then(|_| {
        analyzer
            .structure_deviation(&eval.curves, &eval.displacement)
            .ok()
    });
    Offer {
        source: source.into(),
        iteration: None,
        curves: eval.curves.clone(),
        length: eval.length,
        lambda: eval.lambda(),
        zero_modes: eval.spectrum.zero_modes,
        negative_modes: eval.spectrum.negative_modes,
        deviation,
    }
}

/// The equilibrium and worst-case mode of a network that is not one of the greedy's
/// iterations (the answer or an alternative), for its files in the run folder.
#[derive(Clone, Debug, PartialEq)]
pub struct NetworkState {
    /// Equilibrium displacements (3·V).
    pub displacement: Vec<f64>,
    /// The worst-case mode (3·V).
    pub mode: Vec<f64>,
}

impl NetworkState {
    /// The equilibrium and lowest mode of `eval`.
    pub fn of(eval: &Evaluation) -> Self {
        NetworkState {
            displacement: eval.displacement.clone(),
            mode: eval.spectrum.vectors.col(0).iter().copied().collect(),
        }
    }
}

/// Networks evaluated in full per batch (in parallel) while looking for alternatives; fixed,
/// so the work does not depend on the thread count (the result never does).
const BATCH: usize = 4;

/// Networks evaluated in full at most for `count` alternatives: `4 count + 8`.
fn evaluation_cap(count: usize) -> usize {
    4 * count + 8
}

/// Offers for `count` alternatives beside `offers` (the greedy's path, the local search's
/// network, …): the sets of `visited` (a search's evaluated feasible sets, best first:
/// [`crate::simplify::local::LocalOutcome::visited`]), each evaluated in full (relaxed from the
/// drawn state, its spectrum with the analysis' accuracy, its modes counted) under `source`,
/// in order, skipping sets already offered and sets not distinct
/// ([`crate::constraints::answer::distinct`]) from a network chosen so far, until `count`
/// alternatives qualify, the sets run out, `4 count + 8` were evaluated, or `cancel` is set.
/// Each comes with its equilibrium and mode. Deterministic: the sets are taken in order and
/// each evaluation is independent of the others and of the thread count.
pub fn alternative_offers(
    analyzer: &Analyzer,
    constraints: &Constraints,
    offers: &[Offer],
    visited: &[SubsetScore],
    source: &str,
    count: usize,
    cancel: &Cancel,
) -> Vec<(Offer, NetworkState)> {
    let mut found: Vec<(Offer, NetworkState)> = Vec::new();
    if count == 0 {
        return found;
    }
    let n = analyzer.network().rods.len();
    let mut all: Vec<Offer> = offers.to_vec();
    let mut rest = visited
        .iter()
        .filter(|s| !offers.iter().any(|o| o.curves == s.curves));
    let mut evaluated = 0;
    loop {
        let chosen = choose(constraints, &all, count);
        if chosen.alternatives.len() >= count || cancel.is_cancelled() {
            break;
        }
        let picked: Vec<Vec<usize>> = chosen
            .answer
            .iter()
            .chain(&chosen.alternatives)
            .map(|a| a.found.curves.clone())
            .collect();
        let room = BATCH.min(evaluation_cap(count) - evaluated);
        let batch: Vec<&SubsetScore> = rest
            .by_ref()
            .filter(|s| picked.iter().all(|p| distinct(constraints, p, &s.curves)))
            .take(room)
            .collect();
        if batch.is_empty() {
            break;
        }
        evaluated += batch.len();
        let evals: Vec<Option<(Offer, NetworkState)>> = batch
            .par_iter()
            .map(|s| {
                let active = ActiveSet::from_curves(n, &s.curves);
                let eval = analyzer
                    .evaluate(&active, Warm::default(), Preset::Analysis, Prepare::Nothing)
                    .ok()?;
                Some((
                    evaluated_offer(source, &eval, analyzer, constraints),
                    NetworkState::of(&eval),
                ))
            })
            .collect();
        for (offer, state) in evals.into_iter().flatten() {
            if qualifies(constraints, &offer) {
                all.push(offer.clone());
                found.push((offer, state));
            }
        }
        if evaluated >= evaluation_cap(count) {
            break;
        }
    }
    found
}
