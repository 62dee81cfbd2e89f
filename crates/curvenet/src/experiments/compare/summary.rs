//! The experiment's figures per size and its report.

use super::instance::InstanceResult;
use super::{CompareParams, mean};
use serde::{Deserialize, Serialize};

/// Figures of one size `N` over its instances (a figure a report does not hold reads as 0).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
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
    pub local_optimal: usize,
    /// Mean of (greedy + single improving moves) / optimum (`λ_eq`).
    pub single_ratio_mean: f64,
    /// Smallest (greedy + single improving moves) / optimum.
    pub single_ratio_min: f64,
    /// Mean wall time of the greedy (seconds per network).
    pub greedy_seconds_mean: f64,
    /// Mean number of the greedy's evaluations (candidates scored on `λ_fix`, plus one
    /// `λ_eq` per iteration).
    pub greedy_evaluations_mean: f64,
    /// Mean distinct subsets the local search evaluated.
    pub local_evaluations_mean: f64,
    /// Mean connected structures it relaxed.
    pub local_structures_mean: f64,
    /// Mean moves it kept.
    pub local_moves_mean: f64,
    /// Mean chains it built.
    pub local_chains_mean: f64,
    /// Mean wall time (seconds per network).
    pub local_seconds_mean: f64,
    /// Largest wall time (seconds).
    pub local_seconds_max: f64,
    /// Mean distinct subsets single improving moves evaluated.
    pub single_evaluations_mean: f64,
    /// Mean wall time of single improving moves (seconds per network).
    pub single_seconds_mean: f64,
    /// Mean connected structures exhaustive search relaxed.
    pub exhaustive_structures_mean: f64,
    /// Mean wall time of exhaustive search (seconds per network).
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
            "\nCost per network (mean; each local search from the greedy's set with an analyzer of its own):\n\n\
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
            "\nλ_fix (fixed geometry at the full network's equilibrium):\n\n\
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

impl SizeSummary {
    /// The figures of size `n` over its instances `rows`, measured in `seconds`.
    pub fn of(n: usize, rows: &[InstanceResult], seconds: f64) -> SizeSummary {
        type Figure<'a> = &'a dyn Fn(&InstanceResult) -> f64;
        let mean_of = |f: Figure<'_>| mean(rows.iter().map(f));
        let min_of = |f: Figure<'_>| rows.iter().map(f).fold(f64::INFINITY, f64::min);
        let max_of = |f: Figure<'_>| rows.iter().map(f).fold(0.0, f64::max);
        SizeSummary {
            n,
            instances: rows.len(),
            ratio_mean: mean_of(&|r| r.greedy / r.optimum),
            ratio_min: min_of(&|r| r.greedy / r.optimum),
            percentile_mean: mean_of(&|r| r.percentile),
            percentile_min: min_of(&|r| r.percentile),
            random_ratio_mean: mean_of(&|r| r.greedy / r.random),
            feasible_mean: mean_of(&|r| r.feasible as f64),
            local_ratio_mean: mean_of(&|r| r.local / r.optimum),
            local_ratio_min: min_of(&|r| r.local / r.optimum),
            local_optimal: rows
                .iter()
                .filter(|r| r.local >= r.optimum - 1e-7 * r.optimum.abs())
                .count(),
            single_ratio_mean: mean_of(&|r| r.single / r.optimum),
            single_ratio_min: min_of(&|r| r.single / r.optimum),
            greedy_seconds_mean: mean_of(&|r| r.greedy_seconds),
            greedy_evaluations_mean: mean_of(&|r| r.greedy_evaluations as f64),
            local_evaluations_mean: mean_of(&|r| r.local_evaluations as f64),
            local_structures_mean: mean_of(&|r| r.local_structures as f64),
            local_moves_mean: mean_of(&|r| r.local_moves as f64),
            local_chains_mean: mean_of(&|r| r.local_chains as f64),
            local_seconds_mean: mean_of(&|r| r.local_seconds),
            local_seconds_max: max_of(&|r| r.local_seconds),
            single_evaluations_mean: mean_of(&|r| r.single_evaluations as f64),
            single_seconds_mean: mean_of(&|r| r.single_seconds),
            exhaustive_structures_mean: mean_of(&|r| r.exhaustive_structures as f64),
            exhaustive_seconds_mean: mean_of(&|r| r.exhaustive_seconds),
            multi_ratio_mean: mean_of(&|r| r.multi / r.optimum),
            multi_ratio_min: min_of(&|r| r.multi / r.optimum),
            rounded_ratio_mean: mean_of(&|r| r.rounded / r.optimum),
            exact_eq_ratio_mean: mean_of(&|r| r.exact_eq / r.optimum),
            random_opt_ratio_mean: mean_of(&|r| r.random / r.optimum),
            greedy_fix_ratio_mean: mean_of(&|r| r.greedy_fix / r.exhaustive_fix),
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
            exact_seconds_max: max_of(&|r| r.exact_seconds),
            seconds,
        }
    }
}

/// Mean of `a / b` over the pairs where both are positive (NaN when there is none).
fn mean_positive(pairs: impl Iterator<Item = (f64, f64)>) -> f64 {
    mean(
        pairs
            .filter(|(a, b)| *a > 0.0 && *b > 0.0)
            .map(|(a, b)| a / b),
    )
}
