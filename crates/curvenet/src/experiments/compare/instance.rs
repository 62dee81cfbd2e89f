//! One instance of the experiment: a random network and every search's figures on it.

use super::CompareParams;
use crate::cancel::Cancel;
use crate::io::TriMesh;
use crate::network::{BuildParams, Network, build_network};
use crate::rod::ActiveSet;
use crate::simplify::certificate::{CertifyParams, certify};
use crate::simplify::exact::{ExactParams, exact};
use crate::simplify::exhaustive::{ExhaustiveParams, exhaustive, exhaustive_fixed};
use crate::simplify::greedy::{GreedyParams, NoHooks, greedy};
use crate::simplify::local::{LocalOutcome, LocalParams, local_search, local_search_multi};
use crate::simplify::random::{RandomParams, random_search};
use crate::simplify::{Budget, SimplifyError};
use crate::stability::fixed::FixedProblem;
use crate::stability::{Analyzer, StabilityParams};
use crate::trace::{Generator, generate};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// One instance's figures (a figure a report does not hold reads as 0).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct InstanceResult {
    /// Curves requested.
    pub n: usize,
    /// Surface traced on.
    pub surface: String,
    /// Seed of the geodesics.
    pub seed: u32,
    /// Vertices of the network.
    pub vertices: usize,
    /// Greedy's final curves.
    pub greedy_curves: Vec<usize>,
    /// `λ_eq` of the greedy's final set.
    pub greedy: f64,
    /// Evaluations the greedy spent.
    pub greedy_evaluations: usize,
    /// The optimum `λ_eq` over all feasible subsets.
    pub optimum: f64,
    /// The optimal curves.
    pub optimum_curves: Vec<usize>,
    /// Number of feasible subsets.
    pub feasible: usize,
    /// Percentage of feasible subsets with `λ_eq ≤` the greedy's.
    pub percentile: f64,
    /// Best `λ_eq` found by random search.
    pub random: f64,
    /// Wall time of the greedy (seconds).
    pub greedy_seconds: f64,
    /// `λ_eq` after the local search (its default: descent, part steps, chains) from the
    /// greedy's final set.
    pub local: f64,
    /// Its curves.
    pub local_curves: Vec<usize>,
    /// Moves it kept.
    pub local_moves: usize,
    /// Chains it built (the last one, which found nothing, included).
    pub local_chains: usize,
    /// Distinct subsets it evaluated.
    pub local_evaluations: usize,
    /// Connected structures it relaxed (its own analyzer: nothing cached beforehand).
    pub local_structures: usize,
    /// Its wall time (seconds).
    pub local_seconds: f64,
    /// `λ_eq` after single improving moves (first improvement, no part steps) from the
    /// greedy's final set.
    pub single: f64,
    /// Its curves.
    pub single_curves: Vec<usize>,
    /// Moves it took.
    pub single_moves: usize,
    /// Distinct subsets it evaluated.
    pub single_evaluations: usize,
    /// Its wall time (seconds, its own analyzer).
    pub single_seconds: f64,
    /// Wall time of exhaustive search over `λ_eq` (seconds).
    pub exhaustive_seconds: f64,
    /// Connected structures exhaustive search relaxed.
    pub exhaustive_structures: usize,
    /// `λ_eq` of the multi-start local search (from the greedy's set and every curve alone).
    pub multi: f64,
    /// Its curves.
    pub multi_curves: Vec<usize>,
    /// `λ_eq` of the rounded relaxation's subset.
    pub rounded: f64,
    /// Its curves (the best `λ_fix` among the roundings and the faces' first curves).
    pub rounded_curves: Vec<usize>,
    /// `λ_fix` of the greedy's final set (full network's equilibrium).
    pub greedy_fix: f64,
    /// Certified upper bound on `λ_fix` of any feasible subset (relaxation).
    pub bound_fix: f64,
    /// The exact solver's `λ_fix` (optimal when `exact_proven`).
    pub exact_fix: f64,
    /// Its curves.
    pub exact_curves: Vec<usize>,
    /// Whether it proved optimality within its time limit.
    pub exact_proven: bool,
    /// Nodes it opened.
    pub exact_nodes: usize,
    /// Its wall time (seconds).
    pub exact_seconds: f64,
    /// `λ_eq` of its answer.
    pub exact_eq: f64,
    /// Exhaustive search's optimum of `λ_fix`.
    pub exhaustive_fix: f64,
}

/// Builds instance `i` of size `n`: traces on surfaces in rotation until a network builds
/// with `n` curves (a surface whose traces fail is skipped to the next seed). `surfaces` are
/// already scaled to extent 4000. Returns the surface's name, the seed and the network.
pub fn instance_network(
    surfaces: &[(String, TriMesh)],
    n: usize,
    i: usize,
    params: &CompareParams,
) -> Result<(String, u32, Network), SimplifyError> {
    for attempt in 0..20u32 {
        let (name, mesh) = &surfaces[(i + attempt as usize) % surfaces.len()];
        let seed = params
            .seed
            .wrapping_add((1000 * n + 10 * i) as u32)
            .wrapping_add(7919 * attempt);
        if let Some(net) = traced_network(mesh, n, seed, params.edge_length) {
            return Ok((name.clone(), seed, net));
        }
    }
    Err(SimplifyError::Params(
        format!("could not build a network of {n} curves after 20 tries").into(),
    ))
}

/// `n` random geodesics traced on `mesh` with `seed` and built at `edge_length` with clamped
/// supports; `None` when the tracing fails, gives fewer curves or the build fails.
pub(super) fn traced_network(
    mesh: &TriMesh,
    n: usize,
    seed: u32,
    edge_length: f64,
) -> Option<Network> {
    let traced = generate(mesh, &Generator::Random { count: n, seed }).ok()?;
    if traced.curves.len() != n {
        return None;
    }
    let build = BuildParams {
        edge_length,
        ..BuildParams::default()
    };
    build_network(&traced.curves, &build)
        .ok()
        .map(|(net, _)| net)
}

/// The figures of instance `i` of size `n` on the `scaled` surfaces.
pub(super) fn run(
    scaled: &[(String, TriMesh)],
    n: usize,
    i: usize,
    params: &CompareParams,
) -> Result<InstanceResult, SimplifyError> {
    let (surface, seed, network) = instance_network(scaled, n, i, params)?;
    let mut row = InstanceResult {
        n,
        surface,
        seed,
        vertices: network.vertex_count(),
        ..InstanceResult::default()
    };
    let analyzer = Analyzer::new(network, StabilityParams::default())?;
    let budget = Budget::Fraction(params.budget);
    greedy_figures(&mut row, &analyzer, budget)?;
    local_figures(&mut row, &analyzer, budget)?;
    exhaustive_figures(&mut row, &analyzer, budget, params.max_subsets)?;
    fixed_figures(&mut row, &analyzer, budget, params)?;
    Ok(row)
}

/// The greedy: its final set, that set's `λ_eq` relaxed from the drawn state, its
/// evaluations (every candidate of every iteration plus one per iteration) and time.
fn greedy_figures(
    row: &mut InstanceResult,
    analyzer: &Analyzer,
    budget: Budget,
) -> Result<(), SimplifyError> {
    let t = Instant::now();
    let g = greedy(
        analyzer,
        &GreedyParams::new(budget),
        None,
        None,
        &mut NoHooks,
    )?;
    row.greedy_seconds = t.elapsed().as_secs_f64();
    let last = g.iterations.last().expect("one iteration at least");
    row.greedy_curves = last.curves.clone();
    row.greedy = analyzer.lambda_eq(&ActiveSet::from_curves(row.n, &last.curves))?;
    row.greedy_evaluations = g
        .iterations
        .iter()
        .map(|it| it.candidates.len())
        .sum::<usize>()
        + g.iterations.len();
    Ok(())
}

/// The local searches after the greedy, each with an analyzer (and cache) of its own (timed
/// alone): the default (from the greedy's set and the best single curves) and single
/// improving moves from the greedy's set alone.
fn local_figures(
    row: &mut InstanceResult,
    analyzer: &Analyzer,
    budget: Budget,
) -> Result<(), SimplifyError> {
    let timed = |p: &LocalParams, default: bool| -> Result<(LocalOutcome, f64), SimplifyError> {
        let own = Analyzer::new(analyzer.network().clone(), StabilityParams::default())?;
        let t = Instant::now();
        let start = &row.greedy_curves;
        let o = if default {
            local_search(&own, p, None, start, &Cancel::never())?
        } else {
            local_search_multi(&own, p, None, std::slice::from_ref(start), &Cancel::never())?
        };
        Ok((o, t.elapsed().as_secs_f64()))
    };
    let (local, local_seconds) = timed(&LocalParams::new(budget), true)?;
    let (single, single_seconds) = timed(&LocalParams::single_moves(budget), false)?;
    row.local = local.best.lambda;
    row.local_curves = local.best.curves.clone();
    row.local_moves = local.steps.len();
    row.local_chains = local.chains;
    row.local_evaluations = local.evaluations;
    row.local_structures = local.structures;
    row.local_seconds = local_seconds;
    row.single = single.best.lambda;
    row.single_curves = single.best.curves.clone();
    row.single_moves = single.steps.len();
    row.single_evaluations = single.evaluations;
    row.single_seconds = single_seconds;
    Ok(())
}

/// Exhaustive search (the optimum and the greedy's percentile), random search with the
/// greedy's evaluations, and the multi-start local search.
fn exhaustive_figures(
    row: &mut InstanceResult,
    analyzer: &Analyzer,
    budget: Budget,
    max_subsets: usize,
) -> Result<(), SimplifyError> {
    let never = Cancel::never();
    let cached = analyzer.cached_structures();
    let t = Instant::now();
    let ex = exhaustive(
        analyzer,
        &ExhaustiveParams {
            budget,
            keep: Vec::new(),
            max_subsets,
        },
        None,
        &never,
    )?;
    row.exhaustive_seconds = t.elapsed().as_secs_f64();
    row.exhaustive_structures = analyzer.cached_structures() - cached;
    let below = ex
        .all
        .iter()
        .filter(|s| s.lambda <= row.greedy * (1.0 + 1e-9))
        .count();
    row.optimum = ex.best.lambda;
    row.optimum_curves = ex.best.curves.clone();
    row.feasible = ex.all.len();
    row.percentile = 100.0 * below as f64 / ex.all.len() as f64;
    let rnd = random_search(
        analyzer,
        &RandomParams {
            budget,
            keep: Vec::new(),
            evaluations: row.greedy_evaluations,
            seed: u64::from(row.seed),
            time_limit: None,
        },
        None,
        &never,
    )?;
    row.random = rnd.best.lambda;
    let mut starts = vec![row.greedy_curves.clone()];
    starts.extend((0..row.n).map(|c| vec![c]));
    let single_moves = LocalParams::single_moves(budget);
    let multi = local_search_multi(analyzer, &single_moves, None, &starts, &never)?;
    row.multi = multi.best.lambda;
    row.multi_curves = multi.best.curves.clone();
    Ok(())
}

/// The fixed-geometry objective `λ_fix` at the full network's equilibrium: the greedy's, the
/// certified bound and the rounded relaxation, the exact optimum (and its `λ_eq`), exhaustive
/// search's optimum.
fn fixed_figures(
    row: &mut InstanceResult,
    analyzer: &Analyzer,
    budget: Budget,
    params: &CompareParams,
) -> Result<(), SimplifyError> {
    let never = Cancel::never();
    let problem = FixedProblem::new(analyzer, budget, &[])?;
    row.greedy_fix = problem.lambda_fix(&row.greedy_curves)?;
    let report = certify(&problem, &CertifyParams::default(), &[], &never)?;
    row.bound_fix = report.upper;
    row.rounded = analyzer.lambda_eq(&ActiveSet::from_curves(row.n, &report.lower_curves))?;
    row.rounded_curves = report.lower_curves.clone();
    let ex_fix = exact(
        &problem,
        &ExactParams {
            time_limit: Some(params.exact_time_limit),
            ..ExactParams::default()
        },
        None,
        &[row.greedy_curves.clone(), report.lower_curves.clone()],
        &never,
    )?;
    row.exact_eq = ex_fix.lambda_eq(analyzer)?;
    row.exact_fix = ex_fix.lambda_fix;
    row.exact_curves = ex_fix.curves.clone();
    row.exact_proven = ex_fix.proven();
    row.exact_nodes = ex_fix.info.nodes;
    row.exact_seconds = ex_fix.info.seconds;
    row.exhaustive_fix = exhaustive_fixed(&problem, params.max_subsets, &never)?
        .best
        .lambda;
    Ok(())
}
