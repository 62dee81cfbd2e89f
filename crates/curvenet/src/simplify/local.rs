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
//! - **single moves** ([`Strategy::FirstImprovement`]): take a move that raises `λ_eq` by more
//!   than the tie tolerance (relative 1e-7), until no move does: the list is evaluated in
//!   fixed-size chunks in parallel and the first improving move of the first chunk that has
//!   one is taken.
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
//! that touches nothing else yields the short curve alone at once. Descending first and
//! chaining from the local optimum does at least as well as the descent alone (by
//! construction). The measurements of each variant against the exhaustive optimum are in
//! `docs/benchmarks.md` (*Local search*).
//!
//! **Under design constraints** (the `constraints` of [`local_search`]) the moves add, drop and swap
//! whole units (a group or a symmetry orbit; [`Constraints::neighbours`]), each recorded by
//! its unit's smallest curve, and only to sets that meet every constraint but
//! `--max-deviation`; a part step is taken only when the part alone meets them too. A set
//! whose equilibrium (relaxed from the drawn
//! state, by parts: [`Analyzer::parts_of`]) moves a vertex farther than `--max-deviation`
//! allows ranks below every set within it: the search may start there, never moves to one,
//! and a chain never passes through one. A chain locks every curve of a unit it moved.
//! Without constraints the moves are exactly those above.
//!
//! Every strategy is deterministic: moves are listed in a fixed order, sets are evaluated in
//! parallel but chosen by their position in the list, and every evaluation is independent of
//! the thread count. Every subset is evaluated with the shared [`Analyzer::lambda_eq_parts`]
//! (relaxed from the drawn state, connected parts cached in the analyzer, so sets that share
//! parts cost only their new parts), the evaluation of the greedy's final set and of the
//! exhaustive and random searches; the search also remembers every subset it evaluated, so
//! sets met again (chains revisit their neighbours) cost nothing.
//!
//! **Starts.** [`local_search`] searches from the start it is given (the greedy's final
//! network, when it is feasible) and then from the [`SINGLE_STARTS`] best *single-curve* sets
//! that fit the budget, ranked by their `λ_eq` (ties to the lower curve id): each curve alone,
//! with the keep list when there is one; under design constraints each unit (a group or a
//! symmetry orbit) alone, with the units holding the keep list, when the set meets every
//! constraint. A start equal to one already searched is not searched again. The best outcome
//! wins, ties to the earliest start, so the search never ends below the one from the given
//! start alone. Why: the greedy, removing one curve at a time from the full network, ends
//! among long curves, and at a tight budget the optimum often keeps a few short, stiff curves
//! that no chain from there reaches; the stiffest single curves start the search among them.
//! The searches share their evaluations (a set met by two costs one). A given start that is
//! not feasible (the greedy ended over the budget) is skipped: the single-curve starts need no
//! feasible greedy. [`local_search_multi`] searches from the starts it is given, only.
//! Measured against the exhaustive optimum in `docs/compare.md` (*Generalisation*) and
//! `docs/benchmarks.md` (*Local search*).
//!
//! **Visited sets** ([`LocalOutcome::visited`]): every feasible set the search evaluated (and
//! every part it stepped to) with `λ_eq > 0`, within `--max-deviation`, by decreasing `λ_eq`
//! (ties by curve ids), from the values it computed anyway (no evaluation of its own); a
//! multi-start search merges its starts'. A run's alternatives are chosen from them.
//!
//! Cancelled ([`Cancel`]), the search stops within one evaluation per thread and returns the
//! best set it had reached ([`LocalOutcome::cancelled`]).

use super::exhaustive::SubsetScore;
use super::{Budget, SimplifyError};
use crate::cancel::Cancel;
use crate::constraints::{Constraints, UnitMove};
use crate::stability::Analyzer;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// Moves evaluated together (in parallel) under first improvement; fixed, so the search does
/// not depend on the thread count.
const CHUNK: usize = 8;

/// Single-curve (single-unit) starts [`local_search`] searches from besides the start it is
/// given: the best this many by `λ_eq`.
pub const SINGLE_STARTS: usize = 3;

/// How the local search uses its moves (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Strategy {
    /// Kernighan–Lin chains of best moves, improving or not; the best set of each chain.
    #[default]
    VariableDepth,
    /// Single improving moves: the first improving move of the list.
    FirstImprovement,
}

impl Strategy {
    /// The name used in reports (`variable_depth`, `first_improvement`).
    pub fn name(self) -> &'static str {
        match self {
            Strategy::VariableDepth => "variable_depth",
            Strategy::FirstImprovement => "first_improvement",
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
    /// Relative improvement a move (or a chain) must bring (the greedy's tie tolerance); also
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
    /// The start of the search that reached `best` (`steps` lead from it).
    pub start: SubsetScore,
    /// Every start searched from, in order, with its `λ_eq`: the start given first when it was
    /// feasible ([`Self::given_searched`]), then the single-curve starts.
    #[serde(default)]
    pub starts: Vec<SubsetScore>,
    /// Whether the start given was searched from (it was feasible): then it is `starts[0]`.
    #[serde(default)]
    pub given_searched: bool,
    /// The subset reached (no move, or no chain, improves it; or the move cap was hit).
    pub best: SubsetScore,
    /// Moves taken from `start`, in order.
    pub steps: Vec<Step>,
    /// Rounds run, the last one (which found no improvement) included: scans of the single
    /// moves, each followed under [`Strategy::VariableDepth`] by a chain when it finds no
    /// improving move.
    #[serde(default)]
    pub rounds: usize,
    /// Chains built ([`Strategy::VariableDepth`]), the last one included.
    #[serde(default)]
    pub chains: usize,
    /// Distinct subsets evaluated, over every start (the starts included, and the
    /// single-curve sets ranked to choose them).
    pub evaluations: usize,
    /// Connected structures relaxed for the first time while the search ran (the expensive
    /// part: the other evaluations were put together from the analyzer's cache). Counted on the
    /// analyzer's cache, so an analyzer that already evaluated other sets counts fewer.
    #[serde(default)]
    pub structures: usize,
    /// True when the search was cancelled: `best` is the best set reached by then.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub cancelled: bool,
    /// With `--max-deviation`: the largest displacement of a vertex of `best` at its
    /// equilibrium (over the limit only when no set within it was reached).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub deviation: Option<f64>,
    /// Every feasible set the search evaluated with `λ_eq > 0` (and within `--max-deviation`),
    /// each once, by decreasing `λ_eq` (ties by ascending curve ids): the values it computed
    /// anyway, where a run's alternatives come from. Not recorded in reports.
    #[serde(skip)]
    pub visited: Vec<SubsetScore>,
}

impl LocalOutcome {
    /// Whether `best` meets `--max-deviation` (always without it).
    pub fn within_deviation(&self, constraints: Option<&Constraints>) -> bool {
        match (constraints, self.deviation) {
            (Some(c), Some(d)) => c.deviation_ok(d),
            _ => true,
        }
    }

    /// The start given, scored, when it was searched from (it was feasible).
    pub fn given(&self) -> Option<&SubsetScore> {
        self.starts.first().filter(|_| self.given_searched)
    }
}

/// What the search knows of an evaluated subset.
#[derive(Clone, Debug)]
struct Entry {
    /// `λ_eq` (NaN when the evaluation failed).
    lambda: f64,
    /// What the search ranks it by: `λ_eq`, or −∞ when its equilibrium moves a vertex farther
    /// than `--max-deviation` allows (a set the search may leave but never reach).
    value: f64,
    /// When the subset falls apart into separate structures: the best sub-structure made of
    /// its parts that holds the keep list (its name for [`Move::Part`], its curves, its
    /// `λ_eq`), if better than the subset.
    part: Option<(usize, Vec<usize>, f64)>,
}

/// What the searches of one run know of the subsets they evaluated (shared by its starts).
type Memo = HashMap<Vec<usize>, Entry>;

/// `λ_eq` of subsets, each evaluated once per run.
struct Evaluator<'s> {
    analyzer: &'s Analyzer,
    /// Design constraints a part must meet to be stepped to.
    constraints: Option<&'s Constraints>,
    keep: Vec<usize>,
    tolerance: f64,
    memo: &'s mut Memo,
    cancel: &'s Cancel,
}

/// The search was cancelled (its evaluations stopped part way).
struct Stopped;

impl Evaluator<'_> {
    /// Every set's entry: the new ones evaluated in parallel.
    fn eval_all(&mut self, sets: &[Vec<usize>]) -> Result<Vec<Entry>, Stopped> {
        let mut fresh: Vec<&Vec<usize>> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for s in sets {
            if !self.memo.contains_key(s) && seen.insert(s) {
                fresh.push(s);
            }
        }
        let (analyzer, cancel) = (self.analyzer, self.cancel);
        let (keep, tol, constraints) = (&self.keep, self.tolerance, self.constraints);
        let entries: Vec<Option<Entry>> = fresh
            .par_iter()
            .map(|s| {
                if cancel.is_cancelled() {
                    return None;
                }
                Some(match analyzer.parts_of(&analyzer.set(s)) {
                    Ok(parts) => {
                        let lambda = parts.iter().map(|p| p.lambda).fold(f64::INFINITY, f64::min);
                        let deviation = parts.iter().map(|p| p.deviation).fold(0.0, f64::max);
                        let within = constraints.is_none_or(|c| c.deviation_ok(deviation));
                        let value = if within { lambda } else { f64::NEG_INFINITY };
                        let values: Vec<(Vec<usize>, f64)> =
                            parts.iter().map(|p| (p.curves.clone(), p.lambda)).collect();
                        let part = best_part(&values, keep)
                            .filter(|p| improves(p.2, value, tol))
                            .filter(|p| constraints.is_none_or(|c| c.check(&p.1).is_ok()))
                            .filter(|p| {
                                let dev = parts
                                    .iter()
                                    .filter(|q| q.curves.iter().all(|x| p.1.contains(x)))
                                    .map(|q| q.deviation)
                                    .fold(0.0, f64::max);
                                constraints.is_none_or(|c| c.deviation_ok(dev))
                            });
                        Entry {
                            lambda,
                            value,
                            part,
                        }
                    }
                    Err(_) => Entry {
                        lambda: f64::NAN,
                        value: f64::NAN,
                        part: None,
                    },
                })
            })
            .collect();
        let mut stopped = false;
        for (s, e) in fresh.into_iter().zip(entries) {
            match e {
                Some(e) => {
                    self.memo.insert(s.clone(), e);
                }
                None => stopped = true,
            }
        }
        if stopped {
            return Err(Stopped);
        }
        Ok(sets.iter().map(|s| self.memo[s].clone()).collect())
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
    /// The set's `λ_eq`.
    lambda: f64,
    /// The set's rank ([`Entry::value`]).
    value: f64,
    part: Option<(usize, Vec<usize>, f64)>,
}

impl Candidate {
    fn new(step: Move, set: Vec<usize>, entry: Entry, parts: bool) -> Self {
        Candidate {
            step,
            set,
            lambda: entry.lambda,
            value: entry.value,
            part: entry.part.filter(|_| parts),
        }
    }

    /// The rank where it ends (`λ_eq`, or −∞ over `--max-deviation`).
    fn value(&self) -> f64 {
        self.part.as_ref().map_or(self.value, |p| p.2)
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

/// Runs the local search from `start` and from the [`SINGLE_STARTS`] best single-curve starts
/// (module documentation, *Starts*): the best outcome, ties to the earliest start. `start` is
/// skipped when it is not feasible (over the budget, without the keep list, or not meeting the
/// constraints); that is an error only when no single-curve start is feasible either. Under
/// the design `constraints` when given (bound to `analyzer`'s network and `params`' budget and
/// keep list): then the moves are of whole units, to sets that meet the constraints.
pub fn local_search(
    analyzer: &Analyzer,
    params: &LocalParams,
    constraints: Option<&Constraints>,
    start: &[usize],
    cancel: &Cancel,
) -> Result<LocalOutcome, SimplifyError> {
    let (lengths, budget) = check(analyzer, params)?;
    if let Some(c) = constraints {
        super::exhaustive::check_binding(c, lengths.len(), budget, &params.keep)?;
    }
    let n = lengths.len();
    if let Some(&c) = start.iter().chain(&params.keep).find(|&&c| c >= n) {
        return Err(SimplifyError::Params(format!(
            "curve {c} does not exist ({n} curves)"
        )));
    }
    let mut runs = MultiStart::new(analyzer, params, active(constraints), cancel);
    let given = runs.feasible(start);
    if given {
        runs.search(start)?;
    }
    if !runs.stopped {
        match runs.single_starts() {
            Ok(singles) => {
                for s in singles {
                    if !runs.search(&s)? {
                        break;
                    }
                }
            }
            Err(Stopped) => runs.stopped = true,
        }
    }
    runs.finish(given)
}

/// Constraints that ask for something (`None`: the search without them).
fn active(constraints: Option<&Constraints>) -> Option<&Constraints> {
    constraints.filter(|c| c.is_active())
}

/// Searches from several starts, sharing their evaluations; keeps the best outcome (ties to
/// the earliest start).
struct MultiStart<'s> {
    analyzer: &'s Analyzer,
    params: &'s LocalParams,
    constraints: Option<&'s Constraints>,
    cancel: &'s Cancel,
    lengths: Vec<f64>,
    budget: f64,
    memo: Memo,
    /// Structures in the analyzer's cache before the first search.
    cached_before: usize,
    /// The starts searched, in order.
    starts: Vec<SubsetScore>,
    best: Option<LocalOutcome>,
    /// A search was cancelled: no more starts.
    stopped: bool,
}

impl<'s> MultiStart<'s> {
    fn new(
        analyzer: &'s Analyzer,
        params: &'s LocalParams,
        constraints: Option<&'s Constraints>,
        cancel: &'s Cancel,
    ) -> Self {
        let lengths = analyzer.lengths();
        let budget = params.budget.length(lengths.iter().sum());
        MultiStart {
            analyzer,
            params,
            constraints,
            cancel,
            lengths,
            budget,
            memo: Memo::new(),
            cached_before: analyzer.cached_structures(),
            starts: Vec::new(),
            best: None,
            stopped: false,
        }
    }

    /// The total length of `s`, summed in ascending order of the ids (as everywhere).
    fn length(&self, s: &[usize]) -> f64 {
        let mut sorted = s.to_vec();
        sorted.sort_unstable();
        sorted.iter().map(|&c| self.lengths[c]).sum()
    }

    /// Whether `s` is a start the search may take: curves that exist, at least one, within
    /// the budget, holding the keep list, meeting the constraints.
    fn feasible(&self, s: &[usize]) -> bool {
        !s.is_empty()
            && s.iter().all(|&c| c < self.lengths.len())
            && self.length(s) <= self.budget
            && self.params.keep.iter().all(|k| s.contains(k))
            && self.constraints.is_none_or(|c| c.check(s).is_ok())
    }

    /// Searches from the feasible `start` unless it was searched already; false once the run
    /// is cancelled.
    fn search(&mut self, start: &[usize]) -> Result<bool, SimplifyError> {
        let mut set = start.to_vec();
        set.sort_unstable();
        set.dedup();
        if self.starts.iter().any(|s| s.curves == set) {
            return Ok(true);
        }
        let (analyzer, params, constraints) = (self.analyzer, self.params, self.constraints);
        let o = match search_from(
            analyzer,
            params,
            constraints,
            &set,
            self.cancel,
            &mut self.memo,
        ) {
            Err(SimplifyError::Cancelled) => {
                self.stopped = true;
                return Ok(false);
            }
            o => o?,
        };
        self.starts.push(o.start.clone());
        self.stopped = o.cancelled;
        let better = self.best.as_ref().is_none_or(|b| {
            let (ow, bw) = (
                o.within_deviation(constraints),
                b.within_deviation(constraints),
            );
            (ow && !bw)
                || (ow == bw
                    && (o.best.lambda > b.best.lambda
                        || (b.best.lambda.is_nan() && !o.best.lambda.is_nan())))
        });
        if better {
            self.best = Some(o);
        }
        Ok(!self.stopped)
    }

    /// The [`SINGLE_STARTS`] best single-curve starts (module documentation, *Starts*), best
    /// first: each curve (under constraints, each unit) with the keep list, when that is a
    /// feasible start, ranked by the search's value (`λ_eq`; sets over `--max-deviation` and
    /// failed evaluations are not taken), ties to the lower curve.
    fn single_starts(&mut self) -> Result<Vec<Vec<usize>>, Stopped> {
        let keep = &self.params.keep;
        let sets: Vec<Vec<usize>> = match self.constraints {
            Some(c) => {
                let forced = c.forced_curves();
                c.units()
                    .iter()
                    .enumerate()
                    .filter(|&(u, _)| !c.is_forced(u))
                    .map(|(_, unit)| {
                        let mut s = forced.clone();
                        s.extend_from_slice(unit);
                        s.sort_unstable();
                        s
                    })
                    .collect()
            }
            None => (0..self.lengths.len())
                .filter(|c| !keep.contains(c))
                .map(|c| {
                    let mut s = keep.clone();
                    s.push(c);
                    s.sort_unstable();
                    s.dedup();
                    s
                })
                .collect(),
        };
        let sets: Vec<Vec<usize>> = sets.into_iter().filter(|s| self.feasible(s)).collect();
        let entries = Evaluator {
            analyzer: self.analyzer,
            constraints: self.constraints,
            keep: keep.clone(),
            tolerance: self.params.tolerance,
            memo: &mut self.memo,
            cancel: self.cancel,
        }
        .eval_all(&sets)?;
        let mut ranked: Vec<usize> = (0..sets.len())
            .filter(|&i| entries[i].value.is_finite())
            .collect();
        // Stable: equal values keep the order of the curves.
        ranked.sort_by(|&a, &b| entries[b].value.total_cmp(&entries[a].value));
        Ok(ranked
            .into_iter()
            .take(SINGLE_STARTS)
            .map(|i| sets[i].clone())
            .collect())
    }

    /// The best outcome, with every start and the run's evaluations; `given`: whether the first
    /// start searched was the one given.
    fn finish(self, given: bool) -> Result<LocalOutcome, SimplifyError> {
        let cancelled = self.cancel.is_cancelled();
        match self.best {
            Some(mut b) => {
                b.given_searched = given;
                b.starts = self.starts;
                b.evaluations = self.memo.len();
                b.structures = self
                    .analyzer
                    .cached_structures()
                    .saturating_sub(self.cached_before);
                b.cancelled |= cancelled;
                b.visited = visited(&self.memo, &self.lengths);
                Ok(b)
            }
            None if cancelled || self.stopped => Err(SimplifyError::Cancelled),
            None => Err(SimplifyError::Params(
                "local search: no feasible start (neither the start given nor any single curve \
                 with the keep list fits the budget and the constraints)"
                    .into(),
            )),
        }
    }
}

/// The local search from `start` (feasible), under `constraints` when given, adding what it
/// evaluates to `memo`. The outcome's `starts`, `evaluations` and `structures` are left for
/// [`MultiStart::finish`].
fn search_from(
    analyzer: &Analyzer,
    params: &LocalParams,
    constraints: Option<&Constraints>,
    start: &[usize],
    cancel: &Cancel,
    memo: &mut Memo,
) -> Result<LocalOutcome, SimplifyError> {
    let (lengths, budget) = check(analyzer, params)?;
    let mut cur: Vec<usize> = start.to_vec();
    cur.sort_unstable();
    cur.dedup();
    let n = lengths.len();
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
    if let Some(Err(v)) = constraints.map(|c| c.check(&cur)) {
        return Err(SimplifyError::Params(format!(
            "local search needs a starting subset that meets the constraints: {v}"
        )));
    }
    let mut search = Search {
        ev: Evaluator {
            analyzer,
            constraints,
            keep: params.keep.clone(),
            tolerance: params.tolerance,
            memo,
            cancel,
        },
        params,
        constraints,
        lengths: &lengths,
        budget,
        lambda: f64::NAN,
        cur,
        steps: Vec::new(),
        rounds: 0,
        chains: 0,
    };
    let (start_score, cancelled) = match search.start() {
        Ok(start) => (start, search.run().is_err()),
        Err(Stopped) => return Err(SimplifyError::Cancelled),
    };
    // A start over `--max-deviation` that no move left: its own `λ_eq`.
    let lambda = if search.lambda == f64::NEG_INFINITY {
        search
            .ev
            .memo
            .get(&search.cur)
            .map_or(f64::NAN, |e| e.lambda)
    } else {
        search.lambda
    };
    let deviation = constraints
        .filter(|c| c.params().max_deviation.is_some())
        .and_then(|_| analyzer.deviation(&analyzer.set(&search.cur)).ok());
    Ok(LocalOutcome {
        // Filled in by the multi-start run from the evaluations all its starts share.
        visited: Vec::new(),
        start: start_score,
        starts: Vec::new(),
        given_searched: false,
        deviation,
        best: SubsetScore {
            length: length(&search.cur),
            curves: search.cur,
            lambda,
        },
        steps: search.steps,
        rounds: search.rounds,
        chains: search.chains,
        evaluations: 0,
        structures: 0,
        cancelled,
    })
}

/// The feasible sets of `memo` (and the parts it stepped to) with `λ_eq > 0` within
/// `--max-deviation`, by decreasing `λ_eq`, ties by ascending curve ids, each once.
fn visited(memo: &HashMap<Vec<usize>, Entry>, lengths: &[f64]) -> Vec<SubsetScore> {
    let score = |curves: &[usize], lambda: f64| SubsetScore {
        curves: curves.to_vec(),
        length: curves.iter().map(|&c| lengths[c]).sum(),
        lambda,
    };
    let mut out: Vec<SubsetScore> = Vec::new();
    for (set, e) in memo {
        if e.value.is_finite() && e.lambda > 0.0 {
            out.push(score(set, e.lambda));
        }
        if let Some((_, part, lambda)) = &e.part
            && *lambda > 0.0
        {
            out.push(score(part, *lambda));
        }
    }
    sort_visited(&mut out);
    out
}

/// Sorts sets by decreasing `λ_eq`, ties by ascending curve ids, and keeps each set once.
fn sort_visited(sets: &mut Vec<SubsetScore>) {
    sets.sort_by(|a, b| {
        b.lambda
            .total_cmp(&a.lambda)
            .then_with(|| a.curves.cmp(&b.curves))
    });
    let mut seen = std::collections::HashSet::new();
    sets.retain(|s| seen.insert(s.curves.clone()));
}

/// The curves' lengths and the budget as a length, once the parameters are checked.
fn check(analyzer: &Analyzer, params: &LocalParams) -> Result<(Vec<f64>, f64), SimplifyError> {
    params.budget.validate().map_err(SimplifyError::Params)?;
    if !(params.tolerance >= 0.0 && params.tolerance.is_finite()) {
        return Err(SimplifyError::Params(format!(
            "local search tolerance must be a finite non-negative number, got {}",
            params.tolerance
        )));
    }
    let lengths = analyzer.lengths();
    let budget = params.budget.length(lengths.iter().sum());
    Ok((lengths, budget))
}

/// The state of one local search.
struct Search<'s> {
    ev: Evaluator<'s>,
    params: &'s LocalParams,
    constraints: Option<&'s Constraints>,
    lengths: &'s [f64],
    budget: f64,
    /// The current set and its rank ([`Entry::value`]: its `λ_eq` once a set within
    /// `--max-deviation` is reached).
    cur: Vec<usize>,
    lambda: f64,
    steps: Vec<Step>,
    rounds: usize,
    chains: usize,
}

impl Search<'_> {
    /// Evaluates the start (and takes its best part when it falls apart into a better one).
    fn start(&mut self) -> Result<SubsetScore, Stopped> {
        let first = self.ev.eval_all(std::slice::from_ref(&self.cur))?.remove(0);
        self.lambda = first.value;
        let start = SubsetScore {
            curves: self.cur.clone(),
            length: self.cur.iter().map(|&c| self.lengths[c]).sum(),
            lambda: first.lambda,
        };
        if let Some(p) = first.part.filter(|_| self.params.parts) {
            // The start falls apart and one of its parts alone is better.
            self.steps.push(Step {
                step: Move::Part(p.0),
                lambda: p.2,
                round: 0,
            });
            self.cur = p.1;
            self.lambda = p.2;
        }
        self.rounds = self.steps.len();
        Ok(start)
    }

    /// Rounds of single moves (and chains under variable depth) until none improves or the
    /// move cap is hit.
    fn run(&mut self) -> Result<(), Stopped> {
        while self.steps.len() < self.params.max_moves {
            let round = self.rounds;
            self.rounds += 1;
            if let Some(c) = self.scan()? {
                self.take(std::slice::from_ref(&c), round);
                continue;
            }
            if self.params.strategy != Strategy::VariableDepth {
                break;
            }
            // A local optimum of single moves: a chain from it.
            self.chains += 1;
            if !self.chain(round)? {
                break;
            }
        }
        Ok(())
    }

    /// The moves (with the sets they lead to), evaluated.
    fn candidates(&mut self, moves: &[(Move, Vec<usize>)]) -> Result<Vec<Candidate>, Stopped> {
        let sets: Vec<Vec<usize>> = moves.iter().map(|m| m.1.clone()).collect();
        let entries = self.ev.eval_all(&sets)?;
        let parts = self.params.parts;
        Ok(moves
            .iter()
            .zip(sets)
            .zip(entries)
            .map(|((m, s), e)| Candidate::new(m.0, s, e, parts))
            .collect())
    }

    /// The moves from `set` that stay feasible and move no `locked` curve, in the
    /// documented order, with the sets they lead to.
    fn moves(&self, set: &[usize], locked: Option<&[bool]>) -> Vec<(Move, Vec<usize>)> {
        match self.constraints {
            Some(c) => unit_moves(c, set, self.params, locked),
            None => neighbourhood(set, self.lengths, self.budget, self.params, locked)
                .into_iter()
                .map(|m| (m, m.apply(set)))
                .collect(),
        }
    }

    /// A scan of single moves by first improvement (under variable depth too: the descent to
    /// a local optimum before any chain): the improving move taken, if any.
    fn scan(&mut self) -> Result<Option<Candidate>, Stopped> {
        let tol = self.params.tolerance;
        let moves = self.moves(&self.cur, None);
        for part in moves.chunks(CHUNK) {
            let cands = self.candidates(part)?;
            let pick = cands
                .iter()
                .position(|c| improves(c.value(), self.lambda, tol));
            if let Some(i) = pick {
                let mut cands = cands;
                return Ok(Some(cands.swap_remove(i)));
            }
        }
        Ok(None)
    }

    /// A Kernighan–Lin chain from the current set; takes its best prefix when it improves
    /// (true), else leaves the set (false).
    fn chain(&mut self, round: usize) -> Result<bool, Stopped> {
        let (params, tol) = (self.params, self.params.tolerance);
        let n = self.lengths.len();
        let mut set = self.cur.clone();
        let mut locked = vec![false; n];
        let mut chain: Vec<Candidate> = Vec::new();
        for _ in 0..params.depth.unwrap_or(n).max(1) {
            let moves = self.moves(&set, Some(&locked));
            let mut cands = self.candidates(&moves)?;
            let values: Vec<f64> = cands.iter().map(Candidate::value).collect();
            let Some(i) = best_position(&values, tol) else {
                break;
            };
            let c = cands.swap_remove(i);
            for x in c.step.curves().into_iter().flatten() {
                match self.constraints {
                    Some(cs) => {
                        for &y in &cs.units()[cs.unit_of(x)] {
                            locked[y] = true;
                        }
                    }
                    None => locked[x] = true,
                }
            }
            set = c.end().to_vec();
            chain.push(c);
        }
        let top = chain
            .iter()
            .map(Candidate::value)
            .fold(f64::NEG_INFINITY, f64::max);
        if !improves(top, self.lambda, tol) {
            return Ok(false);
        }
        // The shortest prefix within the tolerance of the chain's best.
        let floor = top - tol * top.abs();
        let end = chain
            .iter()
            .position(|c| c.value() >= floor && improves(c.value(), self.lambda, tol))
            .expect("the chain's best improves")
            + 1;
        self.take(&chain[..end], round);
        Ok(true)
    }

    /// Takes `moves` (in order) as round `round`'s.
    fn take(&mut self, moves: &[Candidate], round: usize) {
        for c in moves {
            self.steps.extend(c.steps(round));
        }
        let last = moves.last().expect("a move");
        self.cur = last.end().to_vec();
        self.lambda = last.value();
    }
}

/// Local search from the starts given, and from those only (e.g. the greedy's answer, then
/// every curve alone): the best outcome, ties to the earliest start; under the design
/// `constraints` when given (as [`local_search`]). The searches share their evaluations.
/// Starts that are not feasible (or do not meet the constraints) are skipped; a cancelled
/// search ends the run with the best outcome so far.
pub fn local_search_multi(
    analyzer: &Analyzer,
    params: &LocalParams,
    constraints: Option<&Constraints>,
    starts: &[Vec<usize>],
    cancel: &Cancel,
) -> Result<LocalOutcome, SimplifyError> {
    let (lengths, budget) = check(analyzer, params)?;
    if let Some(c) = constraints {
        super::exhaustive::check_binding(c, lengths.len(), budget, &params.keep)?;
    }
    let mut runs = MultiStart::new(analyzer, params, active(constraints), cancel);
    let given = starts.first().is_some_and(|s| runs.feasible(s));
    for s in starts {
        if runs.feasible(s) && !runs.search(s)? {
            break;
        }
    }
    runs.finish(given)
}

/// The unit moves from `cur` under `constraints` ([`Constraints::neighbours`]), each named by
/// its units' smallest curves; a unit is locked when its curves are.
fn unit_moves(
    constraints: &Constraints,
    cur: &[usize],
    params: &LocalParams,
    locked: Option<&[bool]>,
) -> Vec<(Move, Vec<usize>)> {
    let units = constraints.units();
    let unit_locked: Option<Vec<bool>> = locked.map(|l| units.iter().map(|u| l[u[0]]).collect());
    constraints
        .neighbours(cur, params.add_back, params.drop, unit_locked.as_deref())
        .into_iter()
        .map(|(m, set)| {
            let first = |u: usize| units[u][0];
            let m = match m {
                UnitMove::Add(u) => Move::Add(first(u)),
                UnitMove::Drop(u) => Move::Drop(first(u)),
                UnitMove::Swap { out, into } => Move::Swap {
                    out: first(out),
                    into: first(into),
                },
            };
            (m, set)
        })
        .collect()
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
