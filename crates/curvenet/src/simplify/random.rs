//! Random search: `λ_eq` of uniformly random feasible subsets, the paper's baseline
//! (`docs/model.md`, *Searches beyond the greedy*).
//!
//! Subsets are drawn by rejection: every curve outside the keep list is included with
//! probability ½ and the draw is kept when it is feasible and new, which makes every
//! feasible subset equally likely. When feasible subsets are too rare for rejection (under
//! one in a million draws), the remaining draws fall back to random maximal subsets (curves in
//! random order, added while the budget allows), and the outcome says so. The draws are made
//! first, from a seeded generator, and then evaluated in parallel, a few per thread at a
//! time: the result depends only on the seed, unless a wall-clock limit or a cancellation
//! ([`Cancel`]: the outcome says so) cuts the evaluation short.
//!
//! Under design constraints (the `constraints` of [`random_search`]) the draws are whole units and
//! only sets meeting every constraint but `--max-deviation` are kept
//! ([`Constraints::draw_subsets`]; without constraints, the same draws from the same seed).

use super::exhaustive::{SubsetScore, best_of};
use super::{Budget, SimplifyError};
use crate::cancel::Cancel;
use crate::constraints::Constraints;
use crate::constraints::SubsetDraw;
use crate::stability::Analyzer;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::time::{Duration, Instant};

/// Parameters of the random search.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RandomParams {
    /// The material budget.
    pub budget: Budget,
    /// Curves every subset must hold.
    pub keep: Vec<usize>,
    /// Number of distinct subsets to evaluate.
    pub evaluations: usize,
    /// Seed.
    pub seed: u64,
    /// Optional wall-clock limit on top (makes the result timing-dependent).
    pub time_limit: Option<Duration>,
}

/// What the random search found.
#[derive(Clone, Debug)]
pub struct RandomOutcome {
    /// The best subset.
    pub best: SubsetScore,
    /// Every evaluated subset, in draw order.
    pub evaluated: Vec<SubsetScore>,
    /// True when rejection became too slow and maximal random subsets were used.
    pub used_fallback: bool,
    /// True when every feasible subset was drawn before reaching the evaluation count.
    pub exhausted: bool,
    /// True when the search was cancelled before every draw was evaluated.
    pub cancelled: bool,
}

/// Draws up to `count` distinct feasible subsets.
pub fn draw_subsets(
    lengths: &[f64],
    budget: f64,
    keep: &[usize],
    count: usize,
    seed: u64,
) -> (Vec<Vec<usize>>, bool, bool) {
    let n = lengths.len();
    let mut kept = vec![false; n];
    for &k in keep {
        kept[k] = true;
    }
    let free: Vec<usize> = (0..n).filter(|&i| !kept[i]).collect();
    SubsetDraw {
        free: &free,
        unit_length: lengths,
        forced: keep,
        base: keep.iter().map(|&k| lengths[k]).sum(),
        budget,
    }
    .draw(count, seed, |i, s| s.push(i), |_| true)
}

/// Runs the random search, over the sets that meet the design `constraints` when given (bound
/// to `analyzer`'s network and `params`' budget and keep list).
pub fn random_search(
    analyzer: &Analyzer,
    params: &RandomParams,
    constraints: Option<&Constraints>,
    cancel: &Cancel,
) -> Result<RandomOutcome, SimplifyError> {
    search(analyzer, params, constraints, cancel)
}

/// The random search, under `constraints` when given.
fn search(
    analyzer: &Analyzer,
    params: &RandomParams,
    constraints: Option<&Constraints>,
    cancel: &Cancel,
) -> Result<RandomOutcome, SimplifyError> {
    params.budget.validate().map_err(SimplifyError::Params)?;
    if params.evaluations == 0 {
        return Err(SimplifyError::Params(
            "random search needs at least one evaluation".into(),
        ));
    }
    let lengths = analyzer.lengths();
    let budget = params.budget.length(lengths.iter().sum());
    let (subsets, used_fallback, exhausted) = match constraints {
        Some(c) => {
            super::exhaustive::check_binding(c, lengths.len(), budget, &params.keep)?;
            c.draw_subsets(params.evaluations, params.seed)
        }
        None => draw_subsets(
            &lengths,
            budget,
            &params.keep,
            params.evaluations,
            params.seed,
        ),
    };
    if subsets.is_empty() {
        return Err(SimplifyError::Params(
            format!("no feasible subset at budget {budget:.6}").into(),
        ));
    }
    let start = Instant::now();
    let mut evaluated = Vec::with_capacity(subsets.len());
    let batch = 4 * rayon::current_num_threads().max(1);
    let mut cancelled = false;
    for chunk in subsets.chunks(batch) {
        if params.time_limit.is_some_and(|t| start.elapsed() >= t) {
            break;
        }
        if cancel.is_cancelled() {
            cancelled = true;
            break;
        }
        evaluated.extend(
            chunk
                .par_iter()
                .map(|curves| SubsetScore {
                    curves: curves.clone(),
                    length: analyzer.total_length(curves),
                    lambda: analyzer
                        .lambda_eq(&analyzer.set(curves))
                        .unwrap_or(f64::NAN),
                })
                .collect::<Vec<_>>(),
        );
    }
    let Some(best) = best_of(&evaluated) else {
        if cancelled {
            return Err(SimplifyError::Cancelled);
        }
        return Err(SimplifyError::Params("every evaluation failed".into()));
    };
    Ok(RandomOutcome {
        best,
        evaluated,
        used_fallback,
        exhausted,
        cancelled,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn draws_are_feasible_distinct_and_roughly_uniform() {
        let lengths = [1.0, 1.0, 1.0, 1.0];
        // Budget 2: feasible = 4 singles + 6 pairs = 10 subsets.
        let (s, fb, ex) = draw_subsets(&lengths, 2.0, &[], 100, 3);
        assert!(!fb && ex);
        assert_eq!(s.len(), 10);
        let set: HashSet<_> = s.iter().cloned().collect();
        assert_eq!(set.len(), 10);
        // Uniformity: over many seeds, each single appears first about equally often.
        let mut first_size = [0usize; 3];
        for seed in 0..2000 {
            let (s, _, _) = draw_subsets(&lengths, 2.0, &[], 1, seed);
            first_size[s[0].len()] += 1;
        }
        // 4 of 10 subsets are singles, 6 are pairs.
        let singles = first_size[1] as f64 / 2000.0;
        assert!((singles - 0.4).abs() < 0.05, "{first_size:?}");
        let (k, _, _) = draw_subsets(&lengths, 2.0, &[2], 100, 1);
        assert!(k.iter().all(|s| s.contains(&2)));
        assert_eq!(k.len(), 4);
    }
}
