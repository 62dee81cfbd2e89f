//! The paper's quantitative experiment (Fig. 10): greedy against exhaustive and random search
//! on random networks.
//!
//! For every size `N` and instance `i`, `N` random geodesics are traced on one of the given
//! surfaces (scaled to a largest extent of 4000, the reference's command-line scenes), built
//! at `h = 100` with clamped supports, and simplified to the budget by
//! - the greedy (its final set re-evaluated with [`crate::stability::Analyzer::lambda_eq`], like
//!   every other set),
//! - exhaustive search (every feasible subset: the optimum and the greedy's percentile),
//! - random search with as many evaluations as the greedy spent (every candidate of every
//!   iteration, as the paper's greedy evaluates them, plus one per iteration),
//! - the greedy followed by the local search of [`super::local`]: its default (first-improvement
//!   descent with part steps, then variable-depth chains) and, for comparison, the former
//!   single improving moves (first improvement, no part steps), each from the greedy's final
//!   set alone, each with a scorer of its own so its time and the structures it relaxed are
//!   its own (no help from the other searches' cache),
//! - the multi-start local search: single moves from the greedy's set and from every curve
//!   alone, the best outcome,
//! - the rounded relaxation: the best `λ_fix` among the roundings of the relaxed faces'
//!   solutions (and the faces' first curves) of [`certify`], re-evaluated on
//!   `λ_eq`; the same run gives the certified upper bound on `λ_fix`,
//! - the exact optimum of `λ_fix` ([`super::exact`]), checked against exhaustive search over
//!   `λ_fix`, and the `λ_eq` of its answer.
//!
//! Every `λ_eq` ratio is against the exhaustive optimum of `λ_eq`; the `λ_fix` figures are at
//! the full network's equilibrium.
//!
//! Everything is seeded; the report depends only on the parameters.

use super::certificate::{CertifyParams, certify};
use super::exact::{ExactParams, exact};
use super::exhaustive::{ExhaustiveParams, exhaustive, exhaustive_fixed};
use super::greedy::{GreedyParams, NoHooks, greedy};
use super::local::{LocalOutcome, LocalParams, local_search, local_search_multi};
use super::random::{RandomParams, random_search};
use super::{Budget, SimplifyError};
use crate::cancel::Cancel;
use crate::io::TriMesh;
use crate::network::{BuildParams, build_network};
use crate::rod::ActiveSet;
use crate::stability::fixed::FixedProblem;
use crate::stability::{Analyzer, StabilityParams};
use crate::trace::{Generator, generate, scale_to_extent};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Parameters of the experiment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CompareParams {
    /// Numbers of curves `N`.
    pub sizes: Vec<usize>,
    /// Instances per size.
    pub instances: usize,
    /// Budget fraction.
    pub budget: f64,
    /// Base seed.
    pub seed: u32,
    /// Edge length `h` (scene units, surfaces at extent 4000).
    pub edge_length: f64,
    /// Largest number of feasible subsets exhaustive search may evaluate.
    pub max_subsets: usize,
    /// Time limit of the exact solver per instance, seconds.
    #[serde(default = "default_exact_time")]
    pub exact_time_limit: f64,
}

fn default_exact_time() -> f64 {
    60.0
}

impl Default for CompareParams {
    fn default() -> Self {
        CompareParams {
            sizes: vec![10, 12, 14, 16],
            instances: 10,
            budget: 0.3,
            seed: 1,
            edge_length: 100.0,
            max_subsets: 200_000,
            exact_time_limit: default_exact_time(),
        }
    }
}

/// A named surface to trace on.
#[derive(Clone, Debug)]
pub struct Surface {
    /// Name for reports.
    pub name: String,
    /// The mesh (any scale; it is scaled to extent 4000).
    pub mesh: TriMesh,
}

/// One instance's figures.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
    #[serde(default)]
    pub greedy_seconds: f64,
    /// `λ_eq` after the local search (its default: descent, part steps, chains) from the
    /// greedy's final set.
    pub local: f64,
    /// Its curves.
    pub local_curves: Vec<usize>,
    /// Moves it kept.
    pub local_moves: usize,
    /// Chains it built (the last one, which found nothing, included).
    #[serde(default)]
    pub local_chains: usize,
    /// Distinct subsets it evaluated.
    #[serde(default)]
    pub local_evaluations: usize,
    /// Connected structures it relaxed (its own scorer: nothing cached beforehand).
    #[serde(default)]
    pub local_structures: usize,
    /// Its wall time (seconds).
    #[serde(default)]
    pub local_seconds: f64,
    /// `λ_eq` after single improving moves (first improvement, no part steps) from the
    /// greedy's final set.
    #[serde(default)]
    pub single: f64,
    /// Its curves.
    #[serde(default)]
    pub single_curves: Vec<usize>,
    /// Moves it took.
    #[serde(default)]
    pub single_moves: usize,
    /// Distinct subsets it evaluated.
    #[serde(default)]
    pub single_evaluations: usize,
    /// Its wall time (seconds, its own scorer).
    #[serde(default)]
    pub single_seconds: f64,
    /// Wall time of exhaustive search over `λ_eq` (seconds).
    #[serde(default)]
    pub exhaustive_seconds: f64,
    /// Connected structures exhaustive search relaxed.
    #[serde(default)]
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

/// Figures of one size `N` over its instances.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SizeSummary {
    /// Number of curves.
    pub n: usize,
    /// Instances measured.
    pub instances: usize,
    /// Mean of greedy / optimum.
    pub ratio_mean: f64,
    /// Smallest greedy / optimum.
    pub ratio_min: f64,
    /// Mean percentile of the greedy among feasible subsets.
    pub percentile_mean: f64,
    /// Smallest percentile.
    pub percentile_min: f64,
    /// Mean of greedy / random search.
    pub random_ratio_mean: f64,
    /// Mean number of feasible subsets.
    pub feasible_mean: f64,
    /// Mean of (greedy + local search) / optimum (`λ_eq`).
    pub local_ratio_mean: f64,
    /// Smallest (greedy + local search) / optimum.
    pub local_ratio_min: f64,
    /// Instances where it reached the optimum (within the relative tie tolerance 1e-7).
    #[serde(default)]
    pub local_optimal: usize,
    /// Mean of (greedy + single improving moves) / optimum (`λ_eq`).
    #[serde(default)]
    pub single_ratio_mean: f64,
    /// Smallest (greedy + single improving moves) / optimum.
    #[serde(default)]
    pub single_ratio_min: f64,
    /// Mean wall time of the greedy (seconds per network).
    #[serde(default)]
    pub greedy_seconds_mean: f64,
    /// Mean number of the greedy's evaluations (candidates scored on `λ_fix`, plus one
    /// `λ_eq` per iteration).
    #[serde(default)]
    pub greedy_evaluations_mean: f64,
    /// Mean distinct subsets the local search evaluated.
    #[serde(default)]
    pub local_evaluations_mean: f64,
    /// Mean connected structures it relaxed.
    #[serde(default)]
    pub local_structures_mean: f64,
    /// Mean moves it kept.
    #[serde(default)]
    pub local_moves_mean: f64,
    /// Mean chains it built.
    #[serde(default)]
    pub local_chains_mean: f64,
    /// Mean wall time (seconds per network).
    #[serde(default)]
    pub local_seconds_mean: f64,
    /// Largest wall time (seconds).
    #[serde(default)]
    pub local_seconds_max: f64,
    /// Mean distinct subsets single improving moves evaluated.
    #[serde(default)]
    pub single_evaluations_mean: f64,
    /// Mean wall time of single improving moves (seconds per network).
    #[serde(default)]
    pub single_seconds_mean: f64,
    /// Mean connected structures exhaustive search relaxed.
    #[serde(default)]
    pub exhaustive_structures_mean: f64,
    /// Mean wall time of exhaustive search (seconds per network).
    #[serde(default)]
    pub exhaustive_seconds_mean: f64,
    /// Mean of multi-start local search / optimum (`λ_eq`).
    pub multi_ratio_mean: f64,
    /// Smallest multi-start local search / optimum.
    pub multi_ratio_min: f64,
    /// Mean of rounded relaxation / optimum (`λ_eq`).
    pub rounded_ratio_mean: f64,
    /// Mean of (the exact `λ_fix` optimum's `λ_eq`) / optimum (`λ_eq`).
    pub exact_eq_ratio_mean: f64,
    /// Mean of random search / optimum (`λ_eq`).
    pub random_opt_ratio_mean: f64,
    /// Mean of greedy `λ_fix` / optimum `λ_fix`.
    pub greedy_fix_ratio_mean: f64,
    /// Mean of greedy `λ_fix` / certified bound, over instances where both are positive.
    pub certified_ratio_mean: f64,
    /// Mean of optimum `λ_fix` / certified bound (how tight the bound is), same instances.
    pub bound_tightness_mean: f64,
    /// Instances where the exact solver proved an optimum equal to exhaustive search's.
    pub exact_matches: usize,
    /// Largest exact solver time (seconds).
    pub exact_seconds_max: f64,
    /// Wall time for this size.
    pub seconds: f64,
}

/// The whole experiment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CompareReport {
    /// Parameters.
    pub params: CompareParams,
    /// Surfaces used, in rotation order.
    pub surfaces: Vec<String>,
    /// Every instance.
    pub instances: Vec<InstanceResult>,
    /// Per-size figures.
    pub summary: Vec<SizeSummary>,
}

impl CompareReport {
    /// The summary as Markdown tables: `λ_eq` against the exhaustive optimum, what the
    /// greedy, the local searches and exhaustive search cost, then the fixed-geometry
    /// objective `λ_fix`.
    pub fn markdown(&self) -> String {
        let mut s = String::from(
            "λ_eq, as a percentage of the exhaustive optimum (mean over instances; min in brackets):\n\n\
             | N | instances | feasible subsets | greedy | greedy + local search | greedy + single moves | multi-start single moves | rounded relaxation | exact λ_fix optimum | random search | greedy percentile | greedy/random | seconds |\n\
             |---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
        );
        for r in &self.summary {
            s.push_str(&format!(
                "| {} | {} | {:.0} | {:.1}% ({:.1}%) | {:.1}% ({:.1}%) | {:.1}% ({:.1}%) | {:.1}% ({:.1}%) | {:.1}% | {:.1}% | {:.1}% | {:.1} ({:.1}) | {:.2} | {:.1} |\n",
                r.n,
                r.instances,
                r.feasible_mean,
                100.0 * r.ratio_mean,
                100.0 * r.ratio_min,
                100.0 * r.local_ratio_mean,
                100.0 * r.local_ratio_min,
                100.0 * r.single_ratio_mean,
                100.0 * r.single_ratio_min,
                100.0 * r.multi_ratio_mean,
                100.0 * r.multi_ratio_min,
                100.0 * r.rounded_ratio_mean,
                100.0 * r.exact_eq_ratio_mean,
                100.0 * r.random_opt_ratio_mean,
                r.percentile_mean,
                r.percentile_min,
                r.random_ratio_mean,
                r.seconds
            ));
        }
        s.push_str(
            "\nCost per network (mean; each local search from the greedy's set with a scorer of its own):\n\n\
             | N | greedy seconds | greedy evaluations | local search: optimum reached | moves (chains) | subsets evaluated | structures relaxed | seconds (max) | single moves: subsets | seconds | exhaustive: structures relaxed | seconds |\n\
             |---|---|---|---|---|---|---|---|---|---|---|---|\n",
        );
        for r in &self.summary {
            s.push_str(&format!(
                "| {} | {:.2} | {:.0} | {}/{} | {:.1} ({:.1}) | {:.0} | {:.0} | {:.2} ({:.2}) | {:.0} | {:.2} | {:.0} | {:.2} |\n",
                r.n,
                r.greedy_seconds_mean,
                r.greedy_evaluations_mean,
                r.local_optimal,
                r.instances,
                r.local_moves_mean,
                r.local_chains_mean,
                r.local_evaluations_mean,
                r.local_structures_mean,
                r.local_seconds_mean,
                r.local_seconds_max,
                r.single_evaluations_mean,
                r.single_seconds_mean,
                r.exhaustive_structures_mean,
                r.exhaustive_seconds_mean
            ));
        }
        s.push_str(
            "\nλ_fix (fixed geometry at the full network's equilibrium, SPEC §5):\n\n\
             | N | greedy / optimum | greedy / certified bound | optimum / certified bound | exact = exhaustive | exact seconds (max) |\n\
             |---|---|---|---|---|---|\n",
        );
        for r in &self.summary {
            s.push_str(&format!(
                "| {} | {:.1}% | {:.1}% | {:.1}% | {}/{} | {:.2} |\n",
                r.n,
                100.0 * r.greedy_fix_ratio_mean,
                100.0 * r.certified_ratio_mean,
                100.0 * r.bound_tightness_mean,
                r.exact_matches,
                r.instances,
                r.exact_seconds_max
            ));
        }
        s
    }
}

/// Builds instance `i` of size `n`: traces on surfaces in rotation until a network builds
/// with `n` curves (a surface whose traces fail is skipped to the next seed). `surfaces` are
/// already scaled to extent 4000. Returns the surface's name, the seed and the network.
pub fn instance_network(
    surfaces: &[(String, TriMesh)],
    n: usize,
    i: usize,
    params: &CompareParams,
) -> Result<(String, u32, crate::network::Network), SimplifyError> {
    for attempt in 0..20u32 {
        let (name, mesh) = &surfaces[(i + attempt as usize) % surfaces.len()];
        let seed = params
            .seed
            .wrapping_add((1000 * n + 10 * i) as u32)
            .wrapping_add(7919 * attempt);
        let Ok(traced) = generate(mesh, &Generator::Random { count: n, seed }) else {
            continue;
        };
        if traced.curves.len() != n {
            continue;
        }
        let build = BuildParams {
            edge_length: params.edge_length,
            ..BuildParams::default()
        };
        if let Ok((net, _)) = build_network(&traced.curves, &build) {
            return Ok((name.clone(), seed, net));
        }
    }
    Err(SimplifyError::Params(format!(
        "could not build a network of {n} curves after 20 tries"
    )))
}

/// Runs the experiment; `progress(done, total)` is called after each instance.
pub fn compare(
    params: &CompareParams,
    surfaces: &[Surface],
    progress: &dyn Fn(usize, usize),
) -> Result<CompareReport, SimplifyError> {
    if surfaces.is_empty() || params.instances == 0 || params.sizes.is_empty() {
        return Err(SimplifyError::Params(
            "compare needs surfaces, sizes and instances".into(),
        ));
    }
    Budget::Fraction(params.budget)
        .validate()
        .map_err(SimplifyError::Params)?;
    let scaled: Vec<(String, TriMesh)> = surfaces
        .iter()
        .map(|s| (s.name.clone(), scale_to_extent(&s.mesh, 4000.0).0))
        .collect();
    let total = params.sizes.len() * params.instances;
    let mut done = 0;
    let mut instances = Vec::new();
    let mut summary = Vec::new();
    for &n in &params.sizes {
        let start = Instant::now();
        let mut rows = Vec::new();
        for i in 0..params.instances {
            let (surface, seed, network) = instance_network(&scaled, n, i, params)?;
            let vertices = network.vertex_count();
            let analyzer = Analyzer::new(network, StabilityParams::default())
                .map_err(SimplifyError::Params)?;
            let never = Cancel::never();
            let budget = Budget::Fraction(params.budget);
            let t = Instant::now();
            let g = greedy(&analyzer, &GreedyParams::new(budget), None, &mut NoHooks)?;
            let greedy_seconds = t.elapsed().as_secs_f64();
            let last = g.iterations.last().expect("one iteration at least");
            let greedy_lambda = analyzer.lambda_eq(&ActiveSet::from_curves(n, &last.curves))?;
            let greedy_evaluations = g
                .iterations
                .iter()
                .map(|it| it.candidates.len())
                .sum::<usize>()
                + g.iterations.len();
            // The local searches first, each with an analyzer (and cache) of its own (timed
            // alone).
            let timed = |p: &LocalParams| -> Result<(LocalOutcome, f64), SimplifyError> {
                let own = Analyzer::new(analyzer.network().clone(), StabilityParams::default())
                    .map_err(SimplifyError::Params)?;
                let t = Instant::now();
                let o = local_search(&own, p, &last.curves, &never)?;
                Ok((o, t.elapsed().as_secs_f64()))
            };
            let (local, local_seconds) = timed(&LocalParams::new(budget))?;
            let (single, single_seconds) = timed(&LocalParams::single_moves(budget))?;
            let cached = analyzer.cached_structures();
            let t = Instant::now();
            let ex = exhaustive(
                &analyzer,
                &ExhaustiveParams {
                    budget,
                    keep: Vec::new(),
                    max_subsets: params.max_subsets,
                },
                &never,
            )?;
            let exhaustive_seconds = t.elapsed().as_secs_f64();
            let exhaustive_structures = analyzer.cached_structures() - cached;
            let below = ex
                .all
                .iter()
                .filter(|s| s.lambda <= greedy_lambda * (1.0 + 1e-9))
                .count();
            let rnd = random_search(
                &analyzer,
                &RandomParams {
                    budget,
                    keep: Vec::new(),
                    evaluations: greedy_evaluations,
                    seed: u64::from(seed),
                    time_limit: None,
                },
                &never,
            )?;
            let mut starts = vec![last.curves.clone()];
            starts.extend((0..n).map(|c| vec![c]));
            let single_moves = LocalParams::single_moves(budget);
            let multi = local_search_multi(&analyzer, &single_moves, &starts, &never)?;
            let problem = FixedProblem::new(&analyzer, budget, &[])?;
            let greedy_fix = problem.lambda_fix(&last.curves)?;
            let report = certify(&problem, &CertifyParams::default(), &[], &never)?;
            let rounded = analyzer.lambda_eq(&ActiveSet::from_curves(n, &report.lower_curves))?;
            let ex_fix = exact(
                &problem,
                &ExactParams {
                    time_limit: Some(params.exact_time_limit),
                    ..ExactParams::default()
                },
                &[last.curves.clone(), report.lower_curves.clone()],
                &never,
            )?;
            let exact_eq = ex_fix.lambda_eq(&analyzer)?;
            let exh_fix = exhaustive_fixed(&problem, params.max_subsets, &never)?;
            rows.push(InstanceResult {
                n,
                surface,
                seed,
                vertices,
                greedy_curves: last.curves.clone(),
                greedy: greedy_lambda,
                greedy_evaluations,
                optimum: ex.best.lambda,
                optimum_curves: ex.best.curves.clone(),
                feasible: ex.all.len(),
                percentile: 100.0 * below as f64 / ex.all.len() as f64,
                random: rnd.best.lambda,
                greedy_seconds,
                local: local.best.lambda,
                local_curves: local.best.curves.clone(),
                local_moves: local.steps.len(),
                local_chains: local.chains,
                local_evaluations: local.evaluations,
                local_structures: local.structures,
                local_seconds,
                single: single.best.lambda,
                single_curves: single.best.curves.clone(),
                single_moves: single.steps.len(),
                single_evaluations: single.evaluations,
                single_seconds,
                exhaustive_seconds,
                exhaustive_structures,
                multi: multi.best.lambda,
                multi_curves: multi.best.curves.clone(),
                rounded,
                rounded_curves: report.lower_curves.clone(),
                greedy_fix,
                bound_fix: report.upper,
                exact_fix: ex_fix.lambda_fix,
                exact_curves: ex_fix.curves.clone(),
                exact_proven: ex_fix.proven(),
                exact_nodes: ex_fix.info.nodes,
                exact_seconds: ex_fix.info.seconds,
                exact_eq,
                exhaustive_fix: exh_fix.best.lambda,
            });
            done += 1;
            progress(done, total);
        }
        let k = rows.len() as f64;
        let ratios: Vec<f64> = rows.iter().map(|r| r.greedy / r.optimum).collect();
        summary.push(SizeSummary {
            n,
            instances: rows.len(),
            ratio_mean: ratios.iter().sum::<f64>() / k,
            ratio_min: ratios.iter().copied().fold(f64::INFINITY, f64::min),
            percentile_mean: rows.iter().map(|r| r.percentile).sum::<f64>() / k,
            percentile_min: rows
                .iter()
                .map(|r| r.percentile)
                .fold(f64::INFINITY, f64::min),
            random_ratio_mean: rows.iter().map(|r| r.greedy / r.random).sum::<f64>() / k,
            feasible_mean: rows.iter().map(|r| r.feasible as f64).sum::<f64>() / k,
            local_ratio_mean: rows.iter().map(|r| r.local / r.optimum).sum::<f64>() / k,
            local_ratio_min: rows
                .iter()
                .map(|r| r.local / r.optimum)
                .fold(f64::INFINITY, f64::min),
            local_optimal: rows
                .iter()
                .filter(|r| r.local >= r.optimum - 1e-7 * r.optimum.abs())
                .count(),
            single_ratio_mean: rows.iter().map(|r| r.single / r.optimum).sum::<f64>() / k,
            single_ratio_min: rows
                .iter()
                .map(|r| r.single / r.optimum)
                .fold(f64::INFINITY, f64::min),
            greedy_seconds_mean: mean(rows.iter().map(|r| r.greedy_seconds)),
            greedy_evaluations_mean: mean(rows.iter().map(|r| r.greedy_evaluations as f64)),
            local_evaluations_mean: mean(rows.iter().map(|r| r.local_evaluations as f64)),
            local_structures_mean: mean(rows.iter().map(|r| r.local_structures as f64)),
            local_moves_mean: mean(rows.iter().map(|r| r.local_moves as f64)),
            local_chains_mean: mean(rows.iter().map(|r| r.local_chains as f64)),
            local_seconds_mean: mean(rows.iter().map(|r| r.local_seconds)),
            local_seconds_max: rows.iter().map(|r| r.local_seconds).fold(0.0, f64::max),
            single_evaluations_mean: mean(rows.iter().map(|r| r.single_evaluations as f64)),
            single_seconds_mean: mean(rows.iter().map(|r| r.single_seconds)),
            exhaustive_structures_mean: mean(rows.iter().map(|r| r.exhaustive_structures as f64)),
            exhaustive_seconds_mean: mean(rows.iter().map(|r| r.exhaustive_seconds)),
            multi_ratio_mean: rows.iter().map(|r| r.multi / r.optimum).sum::<f64>() / k,
            multi_ratio_min: rows
                .iter()
                .map(|r| r.multi / r.optimum)
                .fold(f64::INFINITY, f64::min),
            rounded_ratio_mean: rows.iter().map(|r| r.rounded / r.optimum).sum::<f64>() / k,
            exact_eq_ratio_mean: rows.iter().map(|r| r.exact_eq / r.optimum).sum::<f64>() / k,
            random_opt_ratio_mean: rows.iter().map(|r| r.random / r.optimum).sum::<f64>() / k,
            greedy_fix_ratio_mean: rows
                .iter()
                .map(|r| r.greedy_fix / r.exhaustive_fix)
                .sum::<f64>()
                / k,
            certified_ratio_mean: mean_positive(rows.iter().map(|r| (r.greedy_fix, r.bound_fix))),
            bound_tightness_mean: mean_positive(
                rows.iter().map(|r| (r.exhaustive_fix, r.bound_fix)),
            ),
            exact_matches: rows
                .iter()
                .filter(|r| {
                    r.exact_proven
                        && (r.exhaustive_fix - r.exact_fix).abs() <= 1e-7 * r.exhaustive_fix.abs()
                })
                .count(),
            exact_seconds_max: rows.iter().map(|r| r.exact_seconds).fold(0.0, f64::max),
            seconds: start.elapsed().as_secs_f64(),
        });
        instances.extend(rows);
    }
    Ok(CompareReport {
        params: params.clone(),
        surfaces: scaled.into_iter().map(|s| s.0).collect(),
        instances,
        summary,
    })
}

/// Mean of the values (NaN when there is none).
fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, count) = values.fold((0.0, 0usize), |(s, c), v| (s + v, c + 1));
    sum / count as f64
}

/// Mean of `a / b` over the pairs where both are positive (NaN when there is none).
fn mean_positive(pairs: impl Iterator<Item = (f64, f64)>) -> f64 {
    let v: Vec<f64> = pairs
        .filter(|(a, b)| *a > 0.0 && *b > 0.0)
        .map(|(a, b)| a / b)
        .collect();
    v.iter().sum::<f64>() / v.len() as f64
}
