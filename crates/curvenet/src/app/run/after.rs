//! What runs after the greedy: the local search, the choice of the answer and the
//! alternatives, and the certificate, each recorded in the run folder's writer.

use crate::app::observer::{Observer, StageGuard};
use crate::app::search::Search;
use crate::app::{AppError, Stage};
use crate::cancel::Cancel;
use crate::constraints::Constraints;
use crate::constraints::answer::{Answer, NoAnswer, choose};
use crate::rod::ActiveSet;
use crate::run_folder::answer::{NetworkState, alternative_offers};
use crate::run_folder::schema::objective_name;
use crate::run_folder::{
    LocalSearchRecord, OutputWriter, evaluated_offer, greedy_offers, measure_greedy_deviations,
    read_f64_file,
};
use crate::simplify::certificate::{Certificate, CertifyParams, certificate, tighten_certificate};
use crate::simplify::exhaustive::SubsetScore;
use crate::simplify::local::local_search;
use crate::simplify::{GreedyOutcome, GreedyParams};
use crate::stability::fixed::FixedProblem;
use crate::stability::{Analyzer, Evaluation, Prepare, Preset, Warm};
use crate::words::{Message, Opt, message};
use std::path::Path;
use std::time::Instant;

/// What runs after the greedy, each optional.
pub(super) struct After {
    /// The local search from the greedy's final network.
    pub local_search: bool,
    /// Alternatives to record beside the answer (0: none).
    pub alternatives: usize,
    /// The fixed-geometry certificate of the answer.
    pub certificate: bool,
    /// Branch and bound nodes spent tightening the certificate (None: by network size).
    pub certificate_nodes: Option<usize>,
}

/// The seconds the steps after the greedy took (0 for a step that did not run).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AfterSeconds {
    /// The local search.
    pub local_search: f64,
    /// Choosing the answer and the alternatives.
    pub alternatives: f64,
    /// The certificate.
    pub certificate: f64,
}

impl After {
    /// The local search, the answer and the alternatives, and the certificate, recorded in
    /// `writer`; [`AppError::Cancelled`] when `cancel` stopped a step.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn run(
        &self,
        analyzer: &Analyzer,
        search: &Search,
        outcome: &GreedyOutcome,
        writer: &mut OutputWriter<'_>,
        out: &Path,
        observer: &dyn Observer,
        cancel: &Cancel,
    ) -> Result<AfterSeconds, AppError> {
        let (params, constraints) = (&search.greedy, &search.constraints);
        let stopped = |stage| AppError::Cancelled {
            stage,
            kept: outcome.iterations.len(),
            folder: out.to_path_buf(),
        };
        let (local, local_seconds) =
            optional_step(self.local_search, "local search", observer, cancel, || {
                let _stage = StageGuard::start(observer, Stage::LocalSearch);
                local_search_of(analyzer, search, outcome, cancel)
            });
        if cancel.is_cancelled() {
            return Err(stopped(Stage::LocalSearch));
        }
        let (local, visited) = local.map_or((None, Vec::new()), |(r, v)| (Some(r), v));
        let local_eval = local
            .as_ref()
            .and_then(|l| evaluate_curves(analyzer, &l.curves, "local search's network", observer));
        writer.set_local_search(local);
        let alternatives_start = Instant::now();
        let chosen = {
            let _stage = StageGuard::start(observer, Stage::Alternatives);
            let found = Found {
                local: local_eval,
                visited: &visited,
                alternatives: self.alternatives,
            };
            answer_of(analyzer, constraints, outcome, found, cancel, out, observer)
        };
        let alternatives_seconds = alternatives_start.elapsed().as_secs_f64();
        if cancel.is_cancelled() {
            return Err(stopped(Stage::Alternatives));
        }
        if chosen.answer.is_err() && !self.local_search {
            let p = constraints.params();
            let limits = [
                (Opt::MaxGap, p.max_gap.is_some()),
                (Opt::MaxDeviation, p.max_deviation.is_some()),
            ];
            if let Some(&(opt, _)) = limits.iter().find(|l| l.1) {
                observer.note(&message![
                    "no network of the greedy's path meets ",
                    opt,
                    "; ",
                    Opt::LocalSearch,
                    " searches beyond the path (from the best single curves and networks grown \
                     to meet the limits) and may find one"
                ]);
            }
        }
        if self.alternatives > chosen.alternatives.len() {
            observer.note(&Message::from(format!(
                "{} alternative(s) asked for, {} found: the searches met no other stable \
                 network within the budget and the constraints that is distinct from these and \
                 not one of them with curves added",
                self.alternatives,
                chosen.alternatives.len()
            )));
        }
        // The certificate is of the answer (the greedy's final network when there is none).
        let certified = match &chosen.answer {
            Ok(a) => Some(a.found.curves.clone()),
            Err(_) => outcome.iterations.last().map(|it| it.curves.clone()),
        };
        writer.set_answer(chosen.answer, chosen.state);
        writer.set_alternatives(chosen.alternatives);
        let (certificate, certificate_seconds) =
            optional_step(self.certificate, "certificate", observer, cancel, || {
                let _stage = StageGuard::start(observer, Stage::Certificate);
                certificate_of(
                    analyzer,
                    out,
                    params,
                    constraints,
                    outcome,
                    certified.as_deref().unwrap_or_default(),
                    self.certificate_nodes,
                    cancel,
                )
            });
        if cancel.is_cancelled() {
            return Err(stopped(Stage::Certificate));
        }
        writer.set_certificate(certificate);
        Ok(AfterSeconds {
            local_search: local_seconds,
            alternatives: alternatives_seconds,
            certificate: certificate_seconds,
        })
    }
}

/// What the searches after the greedy found, offered beside the greedy's path.
struct Found<'v> {
    /// The local search's network, evaluated in full, when it ran.
    local: Option<Evaluation>,
    /// The feasible sets the local search evaluated, best first.
    visited: &'v [SubsetScore],
    /// Alternatives asked for.
    alternatives: usize,
}

/// The answer and the alternatives, each with its equilibrium and mode when it is not one of
/// the greedy's iterations.
struct Chosen {
    answer: Result<Answer, NoAnswer>,
    state: Option<NetworkState>,
    alternatives: Vec<(Answer, Option<NetworkState>)>,
}

/// The run's answer among the greedy's iterations, the local search's network (when it
/// ran, evaluated in full) and, with alternatives asked for, the best distinct networks the
/// local search evaluated (each evaluated in full); and the alternatives. With a largest
/// deviation, each greedy iteration's deviation is measured on its state in the run folder
/// `out`.
fn answer_of(
    analyzer: &Analyzer,
    constraints: &Constraints,
    outcome: &GreedyOutcome,
    found: Found<'_>,
    cancel: &Cancel,
    out: &Path,
    observer: &dyn Observer,
) -> Chosen {
    let mut offers = greedy_offers(&outcome.iterations);
    if constraints.params().max_deviation.is_some()
        && let Err(e) = measure_greedy_deviations(&mut offers, out, analyzer)
    {
        observer.warning(&Message::from(format!(
            "the greedy's deviations could not all be measured ({e}); iterations left \
             unmeasured are not offered as the answer"
        )));
    }
    let mut states: Vec<(Vec<usize>, NetworkState)> = Vec::new();
    if let Some(e) = &found.local {
        offers.push(evaluated_offer("local_search", e, analyzer, constraints));
        states.push((e.curves.clone(), NetworkState::of(e)));
    }
    let more = alternative_offers(
        analyzer,
        constraints,
        &offers,
        found.visited,
        "local_search",
        found.alternatives,
        cancel,
    );
    for (o, s) in more {
        states.push((o.curves.clone(), s));
        offers.push(o);
    }
    let mut choice = choose(constraints, &offers, found.alternatives);
    // In the physical mode every network offered to build carries its physical figures: a
    // greedy iteration's as recorded, any other's analysed now.
    if analyzer.physical().is_some() {
        let answers = choice
            .answer
            .iter_mut()
            .chain(choice.alternatives.iter_mut());
        for a in answers {
            let n = analyzer.network().rods.len();
            let active = ActiveSet::from_curves(n, &a.found.curves);
            a.physical = match a.found.iteration {
                // A greedy iteration's figures as recorded, with its load cases.
                Some(k) => outcome
                    .iterations
                    .get(k)
                    .and_then(|r| r.physical.clone())
                    .map(|mut p| {
                        match analyzer.load_cases(&active) {
                            Ok(cases) => p.load_cases = cases,
                            Err(e) => observer.warning(&Message::from(format!(
                                "the load cases of the network of {} curves could not be \
                                 computed: {e}",
                                a.found.curves.len()
                            ))),
                        }
                        p
                    }),
                None => analyzer
                    .offered_physical_summary(&active)
                    .map_err(|e| {
                        observer.warning(&Message::from(format!(
                            "the physical figures of the network of {} curves could not \
                                 be computed: {e}",
                            a.found.curves.len()
                        )))
                    })
                    .ok()
                    .flatten(),
            };
        }
    }
    let state_of = |a: &Answer| {
        a.found
            .iteration
            .is_none()
            .then(|| {
                states
                    .iter()
                    .find(|s| s.0 == a.found.curves)
                    .map(|s| s.1.clone())
            })
            .flatten()
    };
    Chosen {
        state: choice.answer.as_ref().ok().and_then(state_of),
        alternatives: choice
            .alternatives
            .iter()
            .map(|a| (a.clone(), state_of(a)))
            .collect(),
        answer: choice.answer,
    }
}

/// `curves` relaxed and its spectrum computed (a warning and `None` when that fails).
fn evaluate_curves(
    analyzer: &Analyzer,
    curves: &[usize],
    what: &str,
    observer: &dyn Observer,
) -> Option<Evaluation> {
    let active = ActiveSet::from_curves(analyzer.network().rods.len(), curves);
    analyzer
        .evaluate(&active, Warm::default(), Preset::Analysis, Prepare::Nothing)
        .map_err(|e| {
            observer.warning(&Message::from(format!(
                "the {what} could not be evaluated: {e}"
            )))
        })
        .ok()
}

/// The local search (its default: descent with part steps, then variable-depth chains) from
/// the greedy's final network (when it is within the budget) and from the best single curves,
/// with the run's budget, keep list and constraints.
fn local_search_of(
    analyzer: &Analyzer,
    search: &Search,
    outcome: &GreedyOutcome,
    cancel: &Cancel,
) -> Result<(LocalSearchRecord, Vec<SubsetScore>), Message> {
    let last = outcome.iterations.last().ok_or("no iteration")?;
    let local = search.local();
    let o = local_search(
        analyzer,
        &local,
        Some(&search.constraints),
        &last.curves,
        cancel,
    )
    .map_err(|e| e.message())?;
    let mut record =
        LocalSearchRecord::new(&local, &o, &last.curves).ok_or("λ_eq could not be evaluated")?;
    record.objective = objective_name(analyzer.objective()).into();
    Ok((record, o.visited))
}

/// Runs an optional step after the greedy when `on`: its result, or `None` with a warning
/// when it fails (the greedy's results stand either way; a cancelled step is no failure), and
/// the seconds it took.
fn optional_step<T>(
    on: bool,
    what: &str,
    observer: &dyn Observer,
    cancel: &Cancel,
    run: impl FnOnce() -> Result<T, Message>,
) -> (Option<T>, f64) {
    let start = Instant::now();
    let result = if on {
        run()
            .map_err(|e| {
                if !cancel.is_cancelled() {
                    observer.warning(&e.prefixed([format!("no {what}: ").into()]));
                }
            })
            .ok()
    } else {
        None
    };
    (result, start.elapsed().as_secs_f64())
}

/// The fixed-geometry certificate of `curves` (the answer): `λ_fix` at the full network's
/// equilibrium (iteration 0's state) against the relaxation's certified bound on any network
/// within the budget.
#[allow(clippy::too_many_arguments)]
fn certificate_of(
    analyzer: &Analyzer,
    out: &Path,
    params: &GreedyParams,
    constraints: &Constraints,
    outcome: &GreedyOutcome,
    curves: &[usize],
    nodes: Option<usize>,
    cancel: &Cancel,
) -> Result<Certificate, Message> {
    let n = analyzer.network().rods.len();
    let full_state = outcome
        .iterations
        .first()
        .filter(|it| it.curves.len() == n)
        .and_then(|_| read_f64_file(&out.join(crate::run_layout::state_file(0))).ok());
    let problem = match full_state {
        Some(u) => FixedProblem::with_displacement(analyzer, u, params.budget, &params.keep),
        None => FixedProblem::new(analyzer, params.budget, &params.keep),
    }
    .map_err(|e| e.to_string())?;
    if curves.is_empty() || !problem.feasible(curves) {
        return Err("the final network does not meet the budget".into());
    }
    let mut c = certificate(&problem, curves, &CertifyParams::default(), cancel)
        .map_err(|e| e.message())?;
    // Branch and bound nodes: as given, or about 1e6 unknowns' worth of eigen solves.
    let nodes = nodes.unwrap_or_else(|| (1e6 / analyzer.model().dofs().max(1) as f64) as usize);
    tighten_certificate(
        &problem,
        &mut c,
        Some(constraints),
        nodes.min(super::MAX_CERTIFICATE_NODES),
        cancel,
    )
    .map_err(|e| e.message())?;
    Ok(c)
}
