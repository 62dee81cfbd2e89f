//! Exhaustive search: `λ_eq` of every feasible subset, the exact optimum for small networks
//! (`docs/model.md`, *Searches beyond the greedy*).
//!
//! A subset is feasible when it holds the keep list, at least one curve, and its total rest
//! length is within the budget. Subsets are enumerated depth-first over curve ids (a branch
//! stops as soon as its length exceeds the budget) and evaluated in parallel with
//! [`Analyzer::lambda_eq`], the same evaluation the other searches use; [`exhaustive_fixed`]
//! does the same on `λ_fix` at the full network's equilibrium (the exact solver's objective).
//! Under design constraints (the `constraints` of [`exhaustive`]) the subsets are the feasible sets of
//! [`Constraints::feasible_subsets`] (whole units, every constraint but `--max-deviation`),
//! and with `--max-deviation` those whose equilibrium moves a vertex farther than it allows
//! ([`Analyzer::parts_of`]) are dropped, so the best is the constrained optimum.
//! A cancelled search ([`Cancel`]) stops within one evaluation per thread and is an error:
//! part of the subsets is no optimum.

use super::{Budget, SimplifyError};
use crate::cancel::Cancel;
use crate::constraints::Constraints;
use crate::stability::Analyzer;
use crate::stability::fixed::FixedProblem;
use crate::words::{Message, Opt, message};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Parameters of the exhaustive search.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExhaustiveParams {
    /// The material budget.
    pub budget: Budget,
    /// Curves every subset must hold.
    pub keep: Vec<usize>,
    /// Refuse when there are more feasible subsets than this.
    pub max_subsets: usize,
}

impl ExhaustiveParams {
    /// Exhaustive search with `budget`, no keep list, at most 200,000 subsets.
    pub fn new(budget: Budget) -> Self {
        ExhaustiveParams {
            budget,
            keep: Vec::new(),
            max_subsets: 200_000,
        }
    }
}

/// One evaluated subset.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SubsetScore {
    /// Curves, ascending.
    pub curves: Vec<usize>,
    /// Total rest length.
    pub length: f64,
    /// `λ_eq` (NaN when the evaluation failed).
    pub lambda: f64,
}

/// Everything the exhaustive search found.
#[derive(Clone, Debug)]
pub struct ExhaustiveOutcome {
    /// The best subset (largest `λ_eq`; ties within 1e-7 to the first enumerated).
    pub best: SubsetScore,
    /// Every feasible subset with its `λ_eq`, in enumeration order.
    pub all: Vec<SubsetScore>,
}

/// All feasible subsets of curves with `lengths` (ascending ids in each), depth-first; `Err`
/// when there are more than `cap`.
pub fn feasible_subsets(
    lengths: &[f64],
    budget: f64,
    keep: &[usize],
    cap: usize,
) -> Result<Vec<Vec<usize>>, Message> {
    let n = lengths.len();
    let mut forced = vec![false; n];
    for &k in keep {
        forced[k] = true;
    }
    let base: f64 = keep.iter().map(|&k| lengths[k]).sum();
    let mut out = Vec::new();
    if base > budget {
        return Ok(out);
    }
    let mut current: Vec<usize> = Vec::new();
    #[allow(clippy::too_many_arguments)]
    fn rec(
        i: usize,
        len: f64,
        lengths: &[f64],
        forced: &[bool],
        budget: f64,
        cap: usize,
        current: &mut Vec<usize>,
        out: &mut Vec<Vec<usize>>,
    ) -> Result<(), ()> {
        if i == lengths.len() {
            if !current.is_empty() {
                if out.len() >= cap {
                    return Err(());
                }
                out.push(current.clone());
            }
            return Ok(());
        }
        if forced[i] {
            current.push(i);
            rec(i + 1, len, lengths, forced, budget, cap, current, out)?;
            current.pop();
            return Ok(());
        }
        if len + lengths[i] <= budget {
            current.push(i);
            rec(
                i + 1,
                len + lengths[i],
                lengths,
                forced,
                budget,
                cap,
                current,
                out,
            )?;
            current.pop();
        }
        rec(i + 1, len, lengths, forced, budget, cap, current, out)
    }
    rec(
        0,
        base,
        lengths,
        &forced,
        budget,
        cap,
        &mut current,
        &mut out,
    )
    .map_err(|()| {
        format!(
            "exhaustive search refused: {n} curves have more than {cap} feasible subsets at budget \
             {budget:.6}; use the greedy or random search, or raise the limit"
        )
    })?;
    Ok(out)
}

/// Runs the exhaustive search on `λ_eq` (each subset relaxed to its own equilibrium), over the
/// sets that meet the design `constraints` when given (bound to `analyzer`'s network and
/// `params`' budget and keep list): then the best is the constrained optimum.
pub fn exhaustive(
    analyzer: &Analyzer,
    params: &ExhaustiveParams,
    constraints: Option<&Constraints>,
    cancel: &Cancel,
) -> Result<ExhaustiveOutcome, SimplifyError> {
    let limited = constraints.filter(|c| c.params().max_deviation.is_some());
    let score = |curves: &[usize]| match analyzer.parts_of(&analyzer.set(curves)) {
        Ok(parts) => {
            if limited.is_some_and(|c| !c.deviation_ok(analyzer.parts_deviation(&parts))) {
                OVER_DEVIATION
            } else {
                parts.iter().map(|p| p.lambda).fold(f64::INFINITY, f64::min)
            }
        }
        Err(_) => f64::NAN,
    };
    score_all(analyzer, params, constraints, &score, cancel)
}

/// The score of a subset whose equilibrium moves a vertex farther than `--max-deviation`
/// allows: dropped from the outcome.
const OVER_DEVIATION: f64 = f64::NEG_INFINITY;

/// Checks that `constraints` were bound to a network of `n` curves, the budget `budget` (a
/// length) and the keep list `keep`.
pub(super) fn check_binding(
    constraints: &Constraints,
    n: usize,
    budget: f64,
    keep: &[usize],
) -> Result<(), SimplifyError> {
    let sorted = |k: &[usize]| {
        let mut k = k.to_vec();
        k.sort_unstable();
        k.dedup();
        k
    };
    let same_budget = (constraints.budget() - budget).abs() <= 1e-12 * budget.abs().max(1.0);
    if constraints.curve_count() != n || sorted(keep) != sorted(constraints.keep()) || !same_budget
    {
        return Err(SimplifyError::Params(
            "the constraints were bound to another network, budget or keep list".into(),
        ));
    }
    Ok(())
}

/// Exhaustive search on the fixed-geometry objective `λ_fix(S | full network)` (the
/// objective of [`super::exact`] and of the relaxation's bounds), with the problem's budget
/// and keep list: every feasible subset is scored by [`FixedProblem::lambda_fix`], the same
/// evaluation the exact solver uses. The outcome's `lambda` fields hold `λ_fix`.
pub fn exhaustive_fixed(
    problem: &FixedProblem<'_>,
    max_subsets: usize,
    cancel: &Cancel,
) -> Result<ExhaustiveOutcome, SimplifyError> {
    let params = ExhaustiveParams {
        budget: Budget::Length(problem.budget()),
        keep: problem.keep().to_vec(),
        max_subsets,
    };
    let score = |curves: &[usize]| problem.lambda_fix(curves).unwrap_or(f64::NAN);
    score_all(problem.analyzer(), &params, None, &score, cancel)
}

/// Enumerates the feasible subsets (under `constraints` when given) and scores each with
/// `score` (in parallel).
fn score_all(
    analyzer: &Analyzer,
    params: &ExhaustiveParams,
    constraints: Option<&Constraints>,
    score: &(dyn Fn(&[usize]) -> f64 + Sync),
    cancel: &Cancel,
) -> Result<ExhaustiveOutcome, SimplifyError> {
    let n = analyzer.curve_count();
    params.budget.validate().map_err(SimplifyError::Params)?;
    if let Some(&k) = params.keep.iter().find(|&&k| k >= n) {
        return Err(SimplifyError::Params(
            format!("keep list names curve {k}, but there are {n} curves").into(),
        ));
    }
    let lengths = analyzer.lengths();
    let budget = params.budget.length(lengths.iter().sum());
    let subsets = match constraints {
        Some(c) => {
            check_binding(c, n, budget, &params.keep)?;
            c.feasible_subsets(params.max_subsets)
        }
        None => feasible_subsets(&lengths, budget, &params.keep, params.max_subsets),
    }
    .map_err(SimplifyError::Params)?;
    if subsets.is_empty() {
        return Err(SimplifyError::Params(
            match constraints {
                Some(_) => format!("no subset meets the constraints within the budget {budget:.6}"),
                None => {
                    format!(
                        "no feasible subset: the keep list alone exceeds the budget {budget:.6}"
                    )
                }
            }
            .into(),
        ));
    }
    let all: Vec<SubsetScore> = subsets
        .into_par_iter()
        .map(|curves| SubsetScore {
            length: analyzer.total_length(&curves),
            lambda: if cancel.is_cancelled() {
                f64::NAN
            } else {
                score(&curves)
            },
            curves,
        })
        .collect();
    cancel.check().map_err(|_| SimplifyError::Cancelled)?;
    let mut all = all;
    all.retain(|s| s.lambda != OVER_DEVIATION);
    let Some(best) = best_of(&all) else {
        return Err(SimplifyError::Params(if all.is_empty() {
            message![
                "no subset within the budget keeps its equilibrium within ",
                Opt::MaxDeviation
            ]
        } else {
            "no subset could be evaluated".into()
        }));
    };
    Ok(ExhaustiveOutcome { best, all })
}

/// The best subset of a list: largest `λ`, ties within 1e-7 relative to the first listed.
pub fn best_of(all: &[SubsetScore]) -> Option<SubsetScore> {
    let top = all
        .iter()
        .map(|s| s.lambda)
        .filter(|l| l.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    if !top.is_finite() {
        return None;
    }
    all.iter()
        .find(|s| s.lambda >= top - 1e-7 * top.abs())
        .cloned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enumerates_exactly_the_feasible_subsets() {
        let lengths = [1.0, 2.0, 3.0, 4.0];
        let subsets = feasible_subsets(&lengths, 5.0, &[], 1000).expect("small");
        // Brute force over all masks.
        let mut brute = Vec::new();
        for mask in 1u32..16 {
            let s: Vec<usize> = (0..4).filter(|i| mask & (1 << i) != 0).collect();
            if s.iter().map(|&i| lengths[i]).sum::<f64>() <= 5.0 {
                brute.push(s);
            }
        }
        let mut a = subsets.clone();
        a.sort();
        brute.sort();
        assert_eq!(a, brute);
        // With a keep list every subset holds it.
        let k = feasible_subsets(&lengths, 5.0, &[1], 1000).expect("small");
        assert!(k.iter().all(|s| s.contains(&1)));
        // {1} = 2, {0,1} = 3, {1,2} = 5; {0,1,2} = 6 and {1,3} = 6 exceed the budget.
        assert_eq!(k, vec![vec![0, 1], vec![1, 2], vec![1]]);
        assert!(feasible_subsets(&lengths, 100.0, &[], 3).is_err());
        assert!(
            feasible_subsets(&lengths, 1.0, &[3], 10)
                .expect("ok")
                .is_empty()
        );
    }
}
