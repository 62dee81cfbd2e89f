//! Local search after the greedy: improve a feasible subset by moves on `λ_eq`.
//!
//! Moves, in this order:
//! - **add** a curve that fits the budget left (optional, [`LocalParams::add_back`]);
//! - **drop** a curve (optional, [`LocalParams::drop`]): `λ_eq` is not monotone in the set,
//!   and at a tight budget the optimum often keeps fewer, shorter curves than the greedy;
//! - **swap** a kept curve (not in the keep list) for a removed one, when the budget holds.
//!
//! Within each kind, moves are listed by ascending curve ids (for a swap: the curve leaving,
//! then the curve entering). Every set met is feasible: it holds the keep list and at least
//! one curve, and fits the budget.
//!
//! **Parts** ([`LocalParams::parts`], on by default). Curves that share no vertex are
//! separate structures and `λ_eq` of a set is the smallest of its parts' (the scorer computes
//! each part's value anyway). So every set evaluated also gives, for free, the `λ_eq` of each of
//! its parts alone — each a feasible set too (fewer curves, less length; with a keep list, the
//! parts holding it). When a move's set falls apart and its best part alone beats it, the move
//! is followed by [`Move::Part`]: keep that part, drop the others. The search ranks a move by
//! where it ends (after the part step, if any).
//!
//! How moves are used ([`Strategy`]):
//! - **single moves** ([`Strategy::FirstImprovement`], [`Strategy::BestImprovement`]): take a
//!   move that raises `λ_eq` by more than the SPEC's tie tolerance (relative 1e-7), until no
//!   move does. With first improvement, the list is evaluated in fixed-size chunks in parallel
//!   and the first improving move of the first chunk that has one is taken; with best
//!   improvement, the best move of the whole list (ties to the first).
//! - **variable depth** ([`Strategy::VariableDepth`], the default): descend by first
//!   improvement to a local optimum `S`; from it, build a *chain* of moves in Kernighan and
//!   Lin's manner, each the best move available at that point (largest `λ_eq`, values within
//!   the tie tolerance of the best going to the first in the move order) *even when it lowers
//!   `λ_eq`*, never moving a curve the chain already moved (a curve added, dropped or swapped
//!   is locked; a part step locks nothing), up to [`LocalParams::depth`] moves (default: the
//!   number of curves; the locks and the budget end a chain earlier). The best set met along
//!   the chain (the shortest prefix within the tie tolerance of the chain's best) replaces
//!   `S` when it beats `S` by more than the tie tolerance, and the descent starts again from
//!   it; the search stops at the first chain that does not improve.
//!
//! Why. At a tight budget the optimum of `λ_eq` often keeps one to four short, stiff curves
//! (`λ ∝ 1/L⁴`), while the greedy, removing curves one at a time from the full network, ends
//! with two to four long ones. Single moves stall there: swapping one long curve for a short
//! one leaves the other long curve(s) in the set, as part of the structure or as a separate
//! part, and `λ_eq` is still theirs; the move does not look better, and dropping them first
//! does not either. The part step sees through that: swapping a long curve for a short one
//! that touches nothing else yields the short curve alone at once. Measured on
//! `curvenet compare`'s random geodesic networks (10 networks each of 10, 12 and 14 curves,
//! budget 0.3; docs/compare.md), from the greedy's set alone, mean (min) share of the
//! exhaustive optimum and distinct subsets evaluated per network:
//!
//! | search | N = 10 | N = 12 | N = 14 |
//! |---|---|---|---|
//! | single moves (first improvement), no parts | 39% (8%), 34 | 46% (0.4%), 38 | 37% (1%), 58 |
//! | chains only (no descent first), no parts (†) | 51% (8%), 53 | 37% (0.4%), 75 | 38% (1%), 137 |
//! | single moves with parts | 97% (72%), 30 | 98% (84%), 47 | 99.6% (96%), 53 |
//! | chains only, with parts (†) | 100% (100%), 37 | 98% (84%), 72 | 96% (56%), 99 |
//! | **descent, then chains, with parts** (default) | 100% (100%), 36 | 98% (84%), 57 | 100% (100%), 76 |
//!
//! (exhaustive search evaluates 115, 357 and 1,276 subsets; † measured during development, the
//! others with the ignored test `explore` of `tests/local.rs`). Chains alone follow the best
//! move, which can lead elsewhere than the first-improvement descent (one N = 14 network: 56%
//! against 100%); descending first and chaining from the local optimum does at least as well
//! as the descent on every network (by construction), and its chains escaped the descent's
//! local optimum on two of the 30 networks (half spheres, whose curves all cross, so no part
//! step helps). One network (N = 12, half sphere, optimum three curves disjoint from the
//! greedy's three) stays at 84%: no chain of single moves from its local optimum leads there.
//! On networks that fall apart less the gain is smaller: on 40 arch networks of the tests
//! (9–10 chords of a dome, budget 0.3) the default reaches 84% of the optimum on average,
//! single moves without parts 68%, the greedy 52%.
//!
//! Every strategy is deterministic: moves are listed in a fixed order, sets are evaluated in
//! parallel but chosen by their position in the list, and every evaluation is independent of
//! the thread count. Every subset is evaluated with the shared [`Scorer::lambda_eq_parts`]
//! (relaxed from the drawn state, connected parts cached in the scorer, so sets that share
//! parts cost only their new parts), the evaluation of the greedy's final set and of the
//! exhaustive and random searches; the search also remembers every subset it evaluated, so
//! sets met again (chains revisit their neighbours) cost nothing.

use super::exhaustive::SubsetScore;
use super::{Budget, Scorer, SimplifyError};
use crate::rod::ActiveSet;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// Moves evaluated together (in parallel) under first improvement; fixed, so the search does
/// not depend on the thread count.
const CHUNK: usize = 8;

/// How the local search uses its moves (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Strategy {
    /// Kernighan–Lin chains of best moves, improving or not; the best set of each chain.
    #[default]
    VariableDepth,
    /// Single improving moves: the first improving move of the list.
    FirstImprovement,
    /// Single improving moves: the best move of the list.
    BestImprovement,
}

impl Strategy {
    /// The name used in reports (`variable_depth`, `first_improvement`, `best_improvement`).
    pub fn name(self) -> &'static str {
        match self {
            Strategy::VariableDepth => "variable_depth",
            Strategy::FirstImprovement => "first_improvement",
            Strategy::BestImprovement => "best_improvement",
        }
    }
}

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
    /// How moves are chosen.
    pub strategy: Strategy,
    /// Follow every move, when its set falls apart into separate structures, by keeping the
    /// best of them alone if that is better ([`Move::Part`]; free: the parts' `λ_eq` are
    /// computed anyway).
    #[serde(default)]
    pub parts: bool,
    /// Longest chain under [`Strategy::VariableDepth`] (`None`: the number of curves).
    pub depth: Option<usize>,
    /// Cap on moves taken (kept moves; a chain's moves after its best set do not count).
    pub max_moves: usize,
    /// Relative improvement a move (or a chain) must bring (the SPEC's tie tolerance); also
    /// the tolerance within which a chain's candidate moves are tied.
    pub tolerance: f64,
}

impl LocalParams {
    /// Variable-depth search with add-back and drop moves, up to 100 moves.
    pub fn new(budget: Budget) -> Self {
        LocalParams {
            budget,
            keep: Vec::new(),
            add_back: true,
            drop: true,
            strategy: Strategy::VariableDepth,
            parts: true,
            depth: None,
            max_moves: 100,
            tolerance: 1e-7,
        }
    }

    /// Single moves, first improvement, with add-back and drop moves and without
    /// [`Self::parts`], up to 100 moves.
    pub fn single_moves(budget: Budget) -> Self {
        LocalParams {
            strategy: Strategy::FirstImprovement,
            parts: false,
            ..LocalParams::new(budget)
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
    /// Keep only the connected part (curves joined through shared vertices) whose smallest
    /// curve is this one, together with the parts holding the keep list: drop the other
    /// parts. With a keep list, the curve is the smallest of the parts kept.
    Part(usize),
}

impl Move {
    /// The curves it moves (a chain locks them; [`Move::Part`] locks nothing).
    fn curves(self) -> [Option<usize>; 2] {
        match self {
            Move::Add(c) | Move::Drop(c) => [Some(c), None],
            Move::Swap { out, into } => [Some(out), Some(into)],
            Move::Part(_) => [None, None],
        }
    }

    /// `set` (ascending) after the move, ascending.
    fn apply(self, set: &[usize]) -> Vec<usize> {
        let mut s = set.to_vec();
        match self {
            Move::Add(c) => s.push(c),
            Move::Drop(c) => s.retain(|&x| x != c),
            Move::Swap { out, into } => {
                s.retain(|&x| x != out);
                s.push(into);
            }
            Move::Part(_) => unreachable!("a part is taken from the evaluation"),
        }
        s.sort_unstable();
        s
    }
}

/// A move taken and the `λ_eq` it reached.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Step {
    /// The move.
    pub step: Move,
    /// `λ_eq` after it.
    pub lambda: f64,
    /// The round it belongs to, from 0. A single move is a round of its own; the moves of a
    /// chain ([`Strategy::VariableDepth`]) share theirs (they may lower `λ_eq`; the last one of
    /// the round improves on the round before); a [`Move::Part`] shares its move's round.
    #[serde(default)]
    pub round: usize,
}

/// What the local search did.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LocalOutcome {
    /// The starting subset.
    pub start: SubsetScore,
    /// The subset reached (no move, or no chain, improves it; or the move cap was hit).
    pub best: SubsetScore,
    /// Moves taken, in order.
    pub steps: Vec<Step>,
    /// Rounds run, the last one (which found no improvement) included: scans of the single
    /// moves, each followed under [`Strategy::VariableDepth`] by a chain when it finds no
    /// improving move.
    #[serde(default)]
    pub rounds: usize,
    /// Chains built ([`Strategy::VariableDepth`]), the last one included.
    #[serde(default)]
    pub chains: usize,
    /// Distinct subsets evaluated (the start included).
    pub evaluations: usize,
    /// Connected structures relaxed for the first time while the search ran (the expensive
    /// part: the other evaluations were put together from the scorer's cache). Counted on the
    /// scorer's cache, so a scorer that already evaluated other sets counts fewer.
    #[serde(default)]
    pub structures: usize,
}

/// What the search knows of an evaluated subset.
#[derive(Clone, Debug)]
struct Entry {
    /// `λ_eq` (NaN when the evaluation failed).
    lambda: f64,
    /// When the subset falls apart into separate structures: the best sub-structure made of
    /// its parts that holds the keep list (its name for [`Move::Part`], its curves, its
    /// `λ_eq`), if better than the subset.
    part: Option<(usize, Vec<usize>, f64)>,
}

/// `λ_eq` of subsets, each evaluated once per search.
struct Evaluator<'s, 'a> {
    scorer: &'s Scorer<'a>,
    n: usize,
    keep: Vec<usize>,
    tolerance: f64,
    memo: HashMap<Vec<usize>, Entry>,
}

impl Evaluator<'_, '_> {
    /// Every set's entry: the new ones evaluated in parallel.
    fn eval_all(&mut self, sets: &[Vec<usize>]) -> Vec<Entry> {
        let mut fresh: Vec<&Vec<usize>> = Vec::new();
        {
            let mut seen = std::collections::HashSet::new();
            for s in sets {
                if !self.memo.contains_key(s) && seen.insert(s) {
                    fresh.push(s);
                }
            }
        }
        let (scorer, n) = (self.scorer, self.n);
        let (keep, tol) = (&self.keep, self.tolerance);
        let entries: Vec<Entry> = fresh
            .par_iter()
            .map(
                |s| match scorer.lambda_eq_parts(&ActiveSet::from_curves(n, s)) {
                    Ok(parts) => {
                        let lambda = parts.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
                        let part = best_part(&parts, keep).filter(|p| improves(p.2, lambda, tol));
                        Entry { lambda, part }
                    }
                    Err(_) => Entry {
                        lambda: f64::NAN,
                        part: None,
                    },
                },
            )
            .collect();
        for (s, e) in fresh.into_iter().zip(entries) {
            self.memo.insert(s.clone(), e);
        }
        sets.iter().map(|s| self.memo[s].clone()).collect()
    }
}

/// The best sub-structure of a set made of its connected `parts` that holds `keep` (`None`
/// for a connected set): without a keep list the best part alone (ties to the first), with
/// one the parts holding it (any other part can only lower `λ_eq`).
fn best_part(parts: &[(Vec<usize>, f64)], keep: &[usize]) -> Option<(usize, Vec<usize>, f64)> {
    if parts.len() < 2 {
        return None;
    }
    if keep.is_empty() {
        let values: Vec<f64> = parts.iter().map(|p| p.1).collect();
        let i = best_position(&values, 0.0)?;
        return Some((parts[i].0[0], parts[i].0.clone(), parts[i].1));
    }
    let core: Vec<&(Vec<usize>, f64)> = parts
        .iter()
        .filter(|p| p.0.iter().any(|c| keep.contains(c)))
        .collect();
    if core.is_empty() || core.len() == parts.len() {
        return None;
    }
    let mut set: Vec<usize> = core.iter().flat_map(|p| p.0.iter().copied()).collect();
    set.sort_unstable();
    let lambda = core.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    Some((set[0], set, lambda))
}

/// A move evaluated: the set it leads to, possibly followed by keeping its best part.
struct Candidate {
    step: Move,
    set: Vec<usize>,
    lambda: f64,
    part: Option<(usize, Vec<usize>, f64)>,
}

impl Candidate {
    fn new(step: Move, set: Vec<usize>, entry: Entry, parts: bool) -> Self {
        Candidate {
            step,
            set,
            lambda: entry.lambda,
            part: entry.part.filter(|_| parts),
        }
    }

    /// `λ_eq` where it ends.
    fn value(&self) -> f64 {
        self.part.as_ref().map_or(self.lambda, |p| p.2)
    }

    /// The set where it ends.
    fn end(&self) -> &[usize] {
        self.part.as_ref().map_or(&self.set, |p| &p.1)
    }

    /// Its steps (one or two).
    fn steps(&self, round: usize) -> Vec<Step> {
        let mut v = vec![Step {
            step: self.step,
            lambda: self.lambda,
            round,
        }];
        if let Some(p) = &self.part {
            v.push(Step {
                step: Move::Part(p.0),
                lambda: p.2,
                round,
            });
        }
        v
    }
}

/// Whether `v` beats `reference` by more than the relative `tol` (a finite value beats a
/// failed evaluation).
fn improves(v: f64, reference: f64, tol: f64) -> bool {
    if reference.is_finite() {
        v > reference + tol * reference.abs()
    } else {
        v.is_finite()
    }
}

/// The position of the best finite value, values within the relative `tol` of the best going
/// to the first.
fn best_position(vals: &[f64], tol: f64) -> Option<usize> {
    let best = vals
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    if !best.is_finite() {
        return None;
    }
    let floor = best - tol * best.abs();
    vals.iter().position(|&v| v.is_finite() && v >= floor)
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
    if !(params.tolerance >= 0.0 && params.tolerance.is_finite()) {
        return Err(SimplifyError::Params(format!(
            "local search tolerance must be a finite non-negative number, got {}",
            params.tolerance
        )));
    }
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
    let cached_before = scorer.cached_structures();
    let tol = params.tolerance;
    let mut ev = Evaluator {
        scorer,
        n,
        keep: params.keep.clone(),
        tolerance: tol,
        memo: HashMap::new(),
    };
    let first = ev.eval_all(std::slice::from_ref(&cur)).remove(0);
    let mut lambda = first.lambda;
    let start_score = SubsetScore {
        curves: cur.clone(),
        length: length(&cur),
        lambda,
    };
    let mut steps = Vec::new();
    if let Some(p) = first.part.filter(|_| params.parts) {
        // The start falls apart and one of its parts alone is better.
        steps.push(Step {
            step: Move::Part(p.0),
            lambda: p.2,
            round: 0,
        });
        cur = p.1;
        lambda = p.2;
    }
    let candidates = |ev: &mut Evaluator<'_, '_>, set: &[usize], moves: &[Move]| {
        let sets: Vec<Vec<usize>> = moves.iter().map(|m| m.apply(set)).collect();
        let entries = ev.eval_all(&sets);
        moves
            .iter()
            .zip(sets)
            .zip(entries)
            .map(|((m, s), e)| Candidate::new(*m, s, e, params.parts))
            .collect::<Vec<_>>()
    };
    let (mut rounds, mut chains) = (steps.len(), 0);
    while steps.len() < params.max_moves {
        let round = rounds;
        rounds += 1;
        // A scan of single moves (first improvement under variable depth too: the descent to
        // a local optimum before any chain).
        let first = params.strategy != Strategy::BestImprovement;
        let moves = neighbourhood(&cur, &lengths, budget, params, None);
        let chunk = if first { CHUNK } else { moves.len().max(1) };
        let mut taken: Option<Candidate> = None;
        for part in moves.chunks(chunk) {
            let mut cands = candidates(&mut ev, &cur, part);
            let values: Vec<f64> = cands.iter().map(Candidate::value).collect();
            let pick = if first {
                values.iter().position(|&v| improves(v, lambda, tol))
            } else {
                best_position(&values, 0.0).filter(|&i| improves(values[i], lambda, tol))
            };
            if let Some(i) = pick {
                taken = Some(cands.swap_remove(i));
                break;
            }
        }
        if let Some(c) = taken {
            steps.extend(c.steps(round));
            cur = c.end().to_vec();
            lambda = c.value();
            continue;
        }
        if params.strategy != Strategy::VariableDepth {
            break;
        }
        // A local optimum of single moves: a chain from it.
        chains += 1;
        let mut set = cur.clone();
        let mut locked = vec![false; n];
        let mut chain: Vec<Candidate> = Vec::new();
        for _ in 0..params.depth.unwrap_or(n).max(1) {
            let moves = neighbourhood(&set, &lengths, budget, params, Some(&locked));
            let mut cands = candidates(&mut ev, &set, &moves);
            let values: Vec<f64> = cands.iter().map(Candidate::value).collect();
            let Some(i) = best_position(&values, tol) else {
                break;
            };
            let c = cands.swap_remove(i);
            for x in c.step.curves().into_iter().flatten() {
                locked[x] = true;
            }
            set = c.end().to_vec();
            chain.push(c);
        }
        let top = chain
            .iter()
            .map(Candidate::value)
            .fold(f64::NEG_INFINITY, f64::max);
        if !improves(top, lambda, tol) {
            break;
        }
        // The shortest prefix within the tolerance of the chain's best.
        let floor = top - tol * top.abs();
        let end = chain
            .iter()
            .position(|c| c.value() >= floor && improves(c.value(), lambda, tol))
            .expect("the chain's best improves")
            + 1;
        for c in &chain[..end] {
            steps.extend(c.steps(round));
        }
        cur = chain[end - 1].end().to_vec();
        lambda = chain[end - 1].value();
    }
    Ok(LocalOutcome {
        start: start_score,
        best: SubsetScore {
            length: length(&cur),
            curves: cur,
            lambda,
        },
        steps,
        rounds,
        chains,
        evaluations: ev.memo.len(),
        structures: scorer.cached_structures().saturating_sub(cached_before),
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

/// The moves from `cur` that stay feasible and move no `locked` curve, in the documented
/// order.
fn neighbourhood(
    cur: &[usize],
    lengths: &[f64],
    budget: f64,
    params: &LocalParams,
    locked: Option<&[bool]>,
) -> Vec<Move> {
    let n = lengths.len();
    let free = |c: &usize| locked.is_none_or(|l| !l[*c]);
    // Feasibility on the new set's own length (summed in ascending order, as everywhere).
    let fits = |m: &Move| m.apply(cur).iter().map(|&c| lengths[c]).sum::<f64>() <= budget;
    let outside: Vec<usize> = (0..n).filter(|c| !cur.contains(c)).filter(free).collect();
    let removable: Vec<usize> = cur
        .iter()
        .copied()
        .filter(|c| !params.keep.contains(c))
        .filter(free)
        .collect();
    let mut moves = Vec::new();
    if params.add_back {
        moves.extend(outside.iter().map(|&c| Move::Add(c)));
    }
    if params.drop && cur.len() > 1 {
        moves.extend(removable.iter().map(|&c| Move::Drop(c)));
    }
    for &out in &removable {
        moves.extend(outside.iter().map(|&into| Move::Swap { out, into }));
    }
    moves.retain(fits);
    moves
}
