//! Local search after the greedy: improve a feasible subset by single moves on `λ_eq`.
//!
//! Moves, in this order:
//! - **add** a curve that fits the budget left (optional, [`LocalParams::add_back`]);
//! - **drop** a curve (optional, [`LocalParams::drop`]): `λ_eq` is not monotone in the set,
//!   and at a tight budget the optimum often keeps fewer, shorter curves than the greedy;
//! - **swap** a kept curve (not in the keep list) for a removed one, when the budget holds.
//!
//! Within each kind, moves are listed by ascending curve ids (for a swap: the curve leaving,
//! then the curve entering). A move is taken when it raises `λ_eq` by more than the SPEC's tie
//! tolerance (relative 1e-7), so the search ends. With first improvement, the list is
//! evaluated in fixed-size chunks in parallel and the first improving move of the first chunk
//! that has one is taken; with best improvement, the best move of the whole list (ties to the
//! first). Either way the path does not depend on the thread count. Every subset is evaluated
//! with the shared [`Scorer::lambda_eq`] (relaxed from the drawn state, components cached), the
//! same evaluation as the greedy's final set and the exhaustive and random searches.

use super::exhaustive::SubsetScore;
use super::{Budget, Scorer, SimplifyError};
use crate::rod::ActiveSet;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Moves evaluated together (in parallel) under first improvement; fixed, so the search does
/// not depend on the thread count.
const CHUNK: usize = 8;

/// Parameters of the local search.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LocalParams {
    /// The material budget.
    pub budget: Budget,
    /// Curves every subset must hold.
    pub keep: Vec<usize>,
    /// Try adding a curve within the leftover budget.
    pub add_back: bool,
    /// Try dropping a curve.
    pub drop: bool,
    /// Take the best move of each round instead of the first improving one.
    pub best_improvement: bool,
    /// Cap on moves taken.
    pub max_moves: usize,
    /// Relative improvement a move must bring (the SPEC's tie tolerance).
    pub tolerance: f64,
}

impl LocalParams {
    /// First improvement with add-back and drop moves, up to 100 moves.
    pub fn new(budget: Budget) -> Self {
        LocalParams {
            budget,
            keep: Vec::new(),
            add_back: true,
            drop: true,
            best_improvement: false,
            max_moves: 100,
            tolerance: 1e-7,
        }
    }
}

/// One move.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Move {
    /// Add a curve.
    Add(usize),
    /// Drop a curve.
    Drop(usize),
    /// Swap `out` for `into`.
    Swap {
        /// The curve leaving.
        out: usize,
        /// The curve entering.
        into: usize,
    },
}

/// A move taken and the `λ_eq` it reached.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Step {
    /// The move.
    pub step: Move,
    /// `λ_eq` after it.
    pub lambda: f64,
}

/// What the local search did.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LocalOutcome {
    /// The starting subset.
    pub start: SubsetScore,
    /// The subset reached (no move improves it, or the move cap was hit).
    pub best: SubsetScore,
    /// Moves taken, in order.
    pub steps: Vec<Step>,
    /// Subsets evaluated (including cached ones).
    pub evaluations: usize,
}

/// Runs the local search from `start` (a feasible subset).
pub fn local_search(
    scorer: &Scorer<'_>,
    params: &LocalParams,
    start: &[usize],
) -> Result<LocalOutcome, SimplifyError> {
    let net = scorer.analyzer().network();
    let n = net.rods.len();
    params.budget.validate().map_err(SimplifyError::Params)?;
    let lengths = net.rest_lengths();
    let budget = params.budget.length(lengths.iter().sum());
    let mut cur: Vec<usize> = start.to_vec();
    cur.sort_unstable();
    cur.dedup();
    if let Some(&c) = cur.iter().chain(&params.keep).find(|&&c| c >= n) {
        return Err(SimplifyError::Params(format!(
            "curve {c} does not exist ({n} curves)"
        )));
    }
    let length = |s: &[usize]| -> f64 { s.iter().map(|&c| lengths[c]).sum() };
    if cur.is_empty() || length(&cur) > budget || !params.keep.iter().all(|k| cur.contains(k)) {
        return Err(SimplifyError::Params(
            "local search needs a feasible starting subset".into(),
        ));
    }
    let eval = |s: &[usize]| -> f64 {
        scorer
            .lambda_eq(&ActiveSet::from_curves(n, s))
            .unwrap_or(f64::NAN)
    };
    let mut lambda = eval(&cur);
    let start_score = SubsetScore {
        curves: cur.clone(),
        length: length(&cur),
        lambda,
    };
    let mut steps = Vec::new();
    let mut evaluations = 1;
    while steps.len() < params.max_moves {
        let moves = neighbourhood(&cur, &lengths, budget, params);
        let apply = |m: &Move| -> Vec<usize> {
            let mut s = cur.clone();
            match *m {
                Move::Add(c) => s.push(c),
                Move::Drop(c) => s.retain(|&x| x != c),
                Move::Swap { out, into } => {
                    s.retain(|&x| x != out);
                    s.push(into);
                }
            }
            s.sort_unstable();
            s
        };
        let floor = lambda + params.tolerance * lambda.abs();
        let better = |l: f64| l > floor || (!lambda.is_finite() && l.is_finite());
        let mut taken: Option<(Move, Vec<usize>, f64)> = None;
        if params.best_improvement {
            let vals: Vec<f64> = moves.par_iter().map(|m| eval(&apply(m))).collect();
            evaluations += vals.len();
            for (m, &v) in moves.iter().zip(&vals) {
                if better(v) && taken.as_ref().is_none_or(|t| v > t.2) {
                    taken = Some((*m, apply(m), v));
                }
            }
        } else {
            for chunk in moves.chunks(CHUNK) {
                let vals: Vec<f64> = chunk.par_iter().map(|m| eval(&apply(m))).collect();
                evaluations += vals.len();
                if let Some((m, &v)) = chunk.iter().zip(&vals).find(|(_, v)| better(**v)) {
                    taken = Some((*m, apply(m), v));
                    break;
                }
            }
        }
        let Some((m, s, v)) = taken else { break };
        cur = s;
        lambda = v;
        steps.push(Step { step: m, lambda: v });
    }
    Ok(LocalOutcome {
        start: start_score,
        best: SubsetScore {
            length: length(&cur),
            curves: cur,
            lambda,
        },
        steps,
        evaluations,
    })
}

/// Local search from several starts (e.g. the greedy's answer, then every curve alone, which
/// reaches the small sets of short curves a greedy started from the full network misses): the
/// best outcome, ties to the earliest start. Starts that are not feasible are skipped.
pub fn local_search_multi(
    scorer: &Scorer<'_>,
    params: &LocalParams,
    starts: &[Vec<usize>],
) -> Result<LocalOutcome, SimplifyError> {
    let net = scorer.analyzer().network();
    let lengths = net.rest_lengths();
    let budget = params.budget.length(lengths.iter().sum());
    let n = lengths.len();
    let mut best: Option<LocalOutcome> = None;
    for s in starts {
        let feasible = !s.is_empty()
            && s.iter().all(|&c| c < n)
            && s.iter().map(|&c| lengths[c]).sum::<f64>() <= budget
            && params.keep.iter().all(|k| s.contains(k));
        if !feasible {
            continue;
        }
        let o = local_search(scorer, params, s)?;
        let better = best.as_ref().is_none_or(|b| {
            o.best.lambda > b.best.lambda || (b.best.lambda.is_nan() && !o.best.lambda.is_nan())
        });
        if better {
            best = Some(o);
        }
    }
    best.ok_or_else(|| SimplifyError::Params("local search: no feasible start".into()))
}

/// The moves from `cur` that stay feasible, in the documented order.
fn neighbourhood(cur: &[usize], lengths: &[f64], budget: f64, params: &LocalParams) -> Vec<Move> {
    let n = lengths.len();
    let used: f64 = cur.iter().map(|&c| lengths[c]).sum();
    let outside: Vec<usize> = (0..n).filter(|c| !cur.contains(c)).collect();
    let removable: Vec<usize> = cur
        .iter()
        .copied()
        .filter(|c| !params.keep.contains(c))
        .collect();
    let mut moves = Vec::new();
    if params.add_back {
        moves.extend(
            outside
                .iter()
                .filter(|&&c| used + lengths[c] <= budget)
                .map(|&c| Move::Add(c)),
        );
    }
    if params.drop && cur.len() > 1 {
        moves.extend(removable.iter().map(|&c| Move::Drop(c)));
    }
    for &out in &removable {
        for &into in &outside {
            if used - lengths[out] + lengths[into] <= budget {
                moves.push(Move::Swap { out, into });
            }
        }
    }
    moves
}
