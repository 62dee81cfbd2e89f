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
//! feasible greedy. Under `--min-curves` or `--max-gap` a single unit rarely meets the
//! constraints and the greedy, which may not remove a unit whose removal breaks them, often
//! stops over the budget; so the search also starts from sets *grown* to meet them
//! ([`Constraints::grow`]: from each unit as a seed, shortest first, the unit that removes
//! the most shortfall per unit of length joins until none is left), the [`SINGLE_STARTS`]
//! best of the first [`GROWN_EVALUATED`] distinct ones. When no start fits but the keep list
//! alone does (a budget that holds the kept curves and no more), the search starts from it.
//! Kept curves longer than the budget are refused up front ([`keep_fits`]), saying by how
//! much and what budget holds them.
//! [`local_search_multi`] searches from the starts it is given, only.
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

mod evaluator;
mod search;
mod starts;

use super::exhaustive::SubsetScore;
use super::{Budget, SimplifyError};
use crate::cancel::Cancel;
use crate::constraints::Constraints;
use crate::stability::Analyzer;
use serde::{Deserialize, Serialize};
use starts::MultiStart;

/// Single-curve (single-unit) starts [`local_search`] searches from besides the start it is
/// given: the best this many by `λ_eq`.
pub const SINGLE_STARTS: usize = 3;

/// Grown starts evaluated before the best [`SINGLE_STARTS`] of them are searched from
/// (module documentation, *Starts*).
pub const GROWN_EVALUATED: usize = 12;

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
        return Err(SimplifyError::Params(
            format!("curve {c} does not exist ({n} curves)").into(),
        ));
    }
    let mut runs = MultiStart::new(analyzer, params, active(constraints), cancel);
    let given = runs.feasible(start);
    if given {
        runs.search(start)?;
    }
    runs.search_each(MultiStart::single_starts)?;
    runs.search_each(MultiStart::grown_starts)?;
    runs.search_each(MultiStart::keep_start)?;
    runs.finish(given)
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

/// Constraints that ask for something (`None`: the search without them).
fn active(constraints: Option<&Constraints>) -> Option<&Constraints> {
    constraints.filter(|c| c.is_active())
}

/// The curves' lengths and the budget as a length, once the parameters are checked.
fn check(analyzer: &Analyzer, params: &LocalParams) -> Result<(Vec<f64>, f64), SimplifyError> {
    params.budget.validate().map_err(SimplifyError::Params)?;
    if !(params.tolerance >= 0.0 && params.tolerance.is_finite()) {
        return Err(SimplifyError::Params(
            format!(
                "local search tolerance must be a finite non-negative number, got {}",
                params.tolerance
            )
            .into(),
        ));
    }
    let lengths = analyzer.lengths();
    let budget = params.budget.length(lengths.iter().sum());
    keep_fits(&lengths, params.budget, &params.keep)?;
    Ok((lengths, budget))
}

/// Checks that the curves to keep fit the `budget` on a network of curves of `lengths`: kept
/// curves longer than the budget leave no network to search from, whatever the start, and the
/// message says by how much and what helps (a budget at least their length, or fewer curves
/// to keep). Curve ids past the network are left to the caller's check.
///
/// # Errors
///
/// [`SimplifyError::Params`] when the kept curves alone exceed the budget.
pub fn keep_fits(lengths: &[f64], budget: Budget, keep: &[usize]) -> Result<(), SimplifyError> {
    use crate::fmt::{length, percent};
    use crate::words::{Opt, given, message};
    let total: f64 = lengths.iter().sum();
    let limit = budget.length(total);
    let mut kept: Vec<usize> = keep
        .iter()
        .copied()
        .filter(|&c| c < lengths.len())
        .collect();
    kept.sort_unstable();
    kept.dedup();
    let need: f64 = kept.iter().map(|&c| lengths[c]).sum();
    if need <= limit {
        return Ok(());
    }
    let ids: Vec<String> = kept.iter().map(usize::to_string).collect();
    let (opt, shown, least) = match budget {
        Budget::Fraction(f) => (
            Opt::Budget,
            f.to_string(),
            // Rounded up, so the budget advised holds them.
            ((need / total * 1000.0).ceil() / 1000.0)
                .min(1.0)
                .to_string(),
        ),
        Budget::Length(l) => (Opt::BudgetLength, length(l), length(need)),
    };
    Err(SimplifyError::Params(message![
        format!(
            "the curves to keep ({}) are {} long alone, {} ({}%) over the budget {} (",
            ids.join(", "),
            length(need),
            length(need - limit),
            percent(100.0 * (need - limit) / limit),
            length(limit),
        ),
        given(opt, shown),
        "): no network within the budget holds them; raise ",
        opt,
        format!(" to at least {least} or keep fewer curves ("),
        Opt::Keep,
        ")"
    ]))
}
