//! The paper's quantitative experiment (Fig. 10): greedy against exhaustive and random search
//! on random networks.
//!
//! For every size `N` and instance `i`, `N` random geodesics are traced on one of the given
//! surfaces (scaled to a largest extent of 4000, the reference's command-line scenes), built
//! at `h = 100` with clamped supports, and simplified to the budget by
//! - the greedy (its final set re-evaluated with [`Scorer::lambda_eq`], like every other set),
//! - exhaustive search (every feasible subset: the optimum and the greedy's percentile),
//! - random search with as many evaluations as the greedy spent (every candidate of every
//!   iteration, as the paper's greedy evaluates them, plus one per iteration).
//!
//! Everything is seeded; the report depends only on the parameters.

use super::exhaustive::{ExhaustiveParams, exhaustive};
use super::greedy::{GreedyParams, NoHooks, greedy};
use super::random::{RandomParams, random_search};
use super::{Budget, Scorer, SimplifyError};
use crate::io::TriMesh;
use crate::network::{BuildParams, build_network};
use crate::rod::ActiveSet;
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
    /// The summary as a Markdown table.
    pub fn markdown(&self) -> String {
        let mut s = String::from(
            "| N | instances | greedy/optimum mean | min | greedy percentile mean | min | greedy/random mean | feasible subsets | seconds |\n|---|---|---|---|---|---|---|---|---|\n",
        );
        for r in &self.summary {
            s.push_str(&format!(
                "| {} | {} | {:.1}% | {:.1}% | {:.1} | {:.1} | {:.2} | {:.0} | {:.1} |\n",
                r.n,
                r.instances,
                100.0 * r.ratio_mean,
                100.0 * r.ratio_min,
                r.percentile_mean,
                r.percentile_min,
                r.random_ratio_mean,
                r.feasible_mean,
                r.seconds
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
            let scorer = Scorer::new(&analyzer);
            let budget = Budget::Fraction(params.budget);
            let g = greedy(&analyzer, &GreedyParams::new(budget), None, &mut NoHooks)?;
            let last = g.iterations.last().expect("one iteration at least");
            let greedy_lambda = scorer.lambda_eq(&ActiveSet::from_curves(n, &last.curves))?;
            let greedy_evaluations = g
                .iterations
                .iter()
                .map(|it| it.candidates.len())
                .sum::<usize>()
                + g.iterations.len();
            let ex = exhaustive(
                &scorer,
                &ExhaustiveParams {
                    budget,
                    keep: Vec::new(),
                    max_subsets: params.max_subsets,
                },
            )?;
            let below = ex
                .all
                .iter()
                .filter(|s| s.lambda <= greedy_lambda * (1.0 + 1e-9))
                .count();
            let rnd = random_search(
                &scorer,
                &RandomParams {
                    budget,
                    keep: Vec::new(),
                    evaluations: greedy_evaluations,
                    seed: u64::from(seed),
                    time_limit: None,
                },
            )?;
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
