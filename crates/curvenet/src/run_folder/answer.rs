//! The networks a run offers as its answer (see [`crate::constraints::answer::choose`]).

use super::read_f64_file;
use crate::constraints::answer::Offer;
use crate::constraints::max_displacement;
use crate::network::Network;
use crate::simplify::greedy::IterationRecord;
use crate::stability::Evaluation;
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

/// Measures the largest displacement at equilibrium (`--max-deviation`) of each of the
/// greedy's `offers` ([`greedy_offers`]) on its iteration's state in the run folder `dir`.
///
/// # Errors
///
/// A state file that cannot be read or does not match `network` (the offers measured so far
/// keep their deviation; the others stay unmeasured, which disqualifies them).
pub fn measure_greedy_deviations(
    offers: &mut [Offer],
    dir: &Path,
    network: &Network,
) -> Result<(), String> {
    let dofs = 3 * network.positions.len();
    for o in offers.iter_mut() {
        let Some(k) = o.iteration else { continue };
        let u = read_f64_file(&dir.join(format!("states/{k:04}.bin")))?;
        if u.len() < dofs {
            return Err(format!("states/{k:04}.bin does not match the network"));
        }
        o.deviation = Some(max_displacement(network, &o.curves, &u));
    }
    Ok(())
}

/// A network another search found, evaluated in full (`λ_eq`, its modes, its equilibrium's
/// largest displacement), offered as the run's answer.
pub fn evaluated_offer(source: &str, eval: &Evaluation, network: &Network) -> Offer {
    Offer {
        source: source.into(),
        iteration: None,
        curves: eval.curves.clone(),
        length: eval.length,
        lambda: eval.lambda(),
        zero_modes: eval.spectrum.zero_modes,
        negative_modes: eval.spectrum.negative_modes,
        deviation: Some(max_displacement(network, &eval.curves, &eval.displacement)),
    }
}
