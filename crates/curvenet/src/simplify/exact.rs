//! Exact branch and bound over curves for the fixed-geometry objective `λ_fix`
//! (`docs/model.md`, *Searches beyond the greedy*):
//!
//! ```text
//! λ* = max { λ_fix(S | full network) : S ⊇ keep, S ≠ ∅, Σ_{c∈S} L_c ≤ V }.
//! ```
//!
//! # The tree
//!
//! Curves are put in a fixed order (ascending span bound `σ_c`, see
//! [`FixedProblem::span_bounds`]: the curves that limit every subset holding them come first,
//! so their subtrees, the largest, are the first to be cut). A node is a pair `(I, F)`: its
//! subsets are `I ∪ T` with `T ⊆ F` within the budget, `F` the curves after `I`'s last in that
//! order that still fit. Its children are `(I + F[j], F[j+1..])`: every feasible subset is the
//! `I` of exactly one node (the enumeration tree of exhaustive search), and is evaluated when
//! that node is opened. With an empty keep list the root is the empty set (not a subset) and
//! its children are the faces of [`super::certificate`]; with a keep list the root is the keep
//! list.
//!
//! # Bounds
//!
//! Every bound is a certified upper bound on `λ_fix` of all the subsets of a node, from
//! [`FixedProblem::best_bound`]: the Rayleigh certificates of the node's own structure `I`
//! (its low modes, valid for every subset), of its parent's, the span bounds `σ_c` of its
//! curves, the clamped certificates of `I` (its low modes with the vertices free curves touch
//! held fixed: Cauchy interlacing; one more eigen solve, [`ExactParams::clamped`]). A child's
//! bound is computed from its parent's certificates *before* its own structure is evaluated,
//! so most children are cut without an eigen solve (the measurements, and those of relaxing
//! nodes as well, are in `docs/compare.md`, *How far the exact solver goes* and *Certificates on
//! the paper's examples*). A node is cut when its bound is at most the incumbent plus a
//! relative [`ExactParams::tolerance`]; the answer is then optimal within that tolerance.
//!
//! # Order and determinism
//!
//! Nodes are opened best bound first, in waves of [`ExactParams::wave`] nodes processed in
//! parallel; each wave depends only on the state at its start and is merged in a fixed order,
//! so the search (and its answer) does not depend on the thread count. Only the time limit,
//! when it is hit, makes the run timing-dependent; the outcome says so.
//!
//! # Design constraints
//!
//! Under design constraints (the `constraints` of [`exact`]) the tree is the same (every subset is
//! still the `I` of one node, and a bound on all of a node's subsets bounds its feasible ones),
//! but only the sets that meet every constraint but `--max-deviation` become incumbents: the
//! answer is the constrained optimum of `λ_fix`, proved like the unconstrained one.
//!
//! How far it reaches within a minute on random networks is in `docs/compare.md`.

use super::SimplifyError;
use crate::cancel::Cancel;
use crate::constraints::Constraints;
use crate::stability::fixed::{FixedProblem, Node, Rayleigh};
use crate::stability::{Analyzer, StabilityError};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The longest time limit accepted, seconds (about 31 years: no limit in practice; a
/// [`Duration`] cannot hold much longer ones).
pub const MAX_TIME_LIMIT: f64 = 1e9;

/// Parameters of the exact solver.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExactParams {
    /// Stop after this wall time (seconds) with the best subset found and its gap (None: no
    /// limit). Hitting it makes the outcome timing-dependent.
    pub time_limit: Option<f64>,
    /// Stop after opening this many nodes (deterministic).
    pub max_nodes: usize,
    /// Relative optimality tolerance: a node is cut when its bound is at most
    /// `incumbent + tolerance·|incumbent|` (the greedy's tie tolerance by default).
    pub tolerance: f64,
    /// Nodes opened per parallel wave (fixed, so the search does not depend on threads).
    pub wave: usize,
}

impl Default for ExactParams {
    fn default() -> Self {
        ExactParams {
            time_limit: Some(60.0),
            max_nodes: 1_000_000,
            tolerance: 1e-7,
            wave: 8,
        }
    }
}

/// Counts and time of a run.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ExactInfo {
    /// Nodes opened (each evaluates its structure `I`).
    pub nodes: usize,
    /// Nodes cut by their bound before being opened.
    pub cut: usize,
    /// Node bounds computed (certificate bounds, cheap).
    pub bounds: usize,
    /// Eigen solves of `λ_fix` evaluations (connected structures not met before).
    pub eigen_solves: usize,
    /// Eigen solves of clamped certificates.
    pub relax_solves: usize,
    /// Wall time in seconds (not part of any deterministic output).
    pub seconds: f64,
}

/// Why the search stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ExactStatus {
    /// Every node was opened or cut: the answer is optimal (within the tolerance).
    Proven,
    /// The node limit was hit: the answer is the best found, `upper` bounds the optimum.
    NodeLimit,
    /// The time limit was hit: the answer is the best found, `upper` bounds the optimum.
    TimeLimit,
    /// The search was cancelled: the answer is the best found, `upper` bounds the optimum.
    Cancelled,
}

/// The exact solver's answer.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExactOutcome {
    /// The best feasible subset found, ascending.
    pub curves: Vec<usize>,
    /// Its total rest length.
    pub length: f64,
    /// Its `λ_fix` at the full network's equilibrium (the objective).
    pub lambda_fix: f64,
    /// Certified upper bound on `λ_fix` of every feasible subset (`lambda_fix` itself, plus the
    /// tolerance, when proven).
    pub upper: f64,
    /// Relative gap `(upper − lambda_fix)/|upper|` (0 when proven within the tolerance).
    pub gap: f64,
    /// Whether the answer is proven optimal.
    pub status: ExactStatus,
    /// Counts and time.
    pub info: ExactInfo,
}

impl ExactOutcome {
    /// True when the answer is proven optimal (within the tolerance).
    pub fn proven(&self) -> bool {
        self.status == ExactStatus::Proven
    }

    /// `λ_eq` of the answer (its own equilibrium), evaluated the way every search ranks a set
    /// ([`Analyzer::lambda_eq`]).
    pub fn lambda_eq(&self, analyzer: &Analyzer) -> Result<f64, StabilityError> {
        analyzer.lambda_eq(&analyzer.set(&self.curves))
    }
}

/// An open node.
struct Open {
    /// Structure `I`, ascending (empty only at the virtual root).
    included: Vec<usize>,
    /// Free curves, in the search order.
    free: Vec<usize>,
    /// Certified bound on the node's subsets.
    bound: f64,
    /// Certificates of the parent (used to bound the node's children too).
    inherited: Vec<Arc<Rayleigh>>,
    /// Creation number (ties of the bound: older first).
    seq: u64,
}

impl PartialEq for Open {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Open {}
impl PartialOrd for Open {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Open {
    fn cmp(&self, other: &Self) -> Ordering {
        // Max-heap: larger bound first, then smaller seq.
        self.bound
            .total_cmp(&other.bound)
            .then(other.seq.cmp(&self.seq))
    }
}

/// What opening a node produced.
struct Opened {
    /// `λ_fix(I)` (None at the virtual root).
    lambda: Option<f64>,
    /// Children with their bounds, in order.
    children: Vec<Open>,
    /// Bounds computed.
    bounds: usize,
}

/// The smaller of two bounds, a NaN bound counting as no bound.
fn min_bound(a: f64, b: f64) -> f64 {
    match (a.is_nan(), b.is_nan()) {
        (true, true) => f64::INFINITY,
        (true, false) => b,
        (false, true) => a,
        (false, false) => a.min(b),
    }
}

/// The incumbent plus the tolerance band: a bound at or below this is cut.
fn cut_level(incumbent: f64, tolerance: f64) -> f64 {
    if !incumbent.is_finite() {
        return incumbent;
    }
    incumbent + tolerance * incumbent.abs()
}

/// Finds the feasible subset with the largest `λ_fix` (see the module documentation), among
/// the sets that meet the design `constraints` when given (bound to the problem's network,
/// budget and keep list). `incumbents` are feasible subsets known beforehand (e.g. the
/// greedy's answer); they only speed the search up (those that do not meet the constraints
/// are ignored). Once `cancel` is set the search stops between eigen solves with the best
/// subset found and the bound of the nodes left open ([`ExactStatus::Cancelled`]).
pub fn exact(
    problem: &FixedProblem<'_>,
    params: &ExactParams,
    constraints: Option<&Constraints>,
    incumbents: &[Vec<usize>],
    cancel: &Cancel,
) -> Result<ExactOutcome, SimplifyError> {
    if let Some(c) = constraints {
        let (n, budget) = (problem.curve_count(), problem.budget());
        super::exhaustive::check_binding(c, n, budget, problem.keep())?;
    }
    run(
        problem,
        params,
        constraints.filter(|c| c.is_active()),
        incumbents,
        cancel,
    )
}

/// The search of [`exact`], under `constraints` when given.
fn run(
    problem: &FixedProblem<'_>,
    params: &ExactParams,
    constraints: Option<&Constraints>,
    incumbents: &[Vec<usize>],
    cancel: &Cancel,
) -> Result<ExactOutcome, SimplifyError> {
    let start = Instant::now();
    check(problem, params)?;
    let solves0 = (problem.eigen_solves(), problem.relax_solves());
    let mut search = Search {
        problem,
        params,
        constraints,
        heap: BinaryHeap::new(),
        best: Best::default(),
        info: ExactInfo::default(),
        seq: 0,
    };
    for s in incumbents {
        if problem.feasible(s) && search.admits(s) {
            let l = problem.lambda_fix(s)?;
            search.best.consider(s, l);
        }
    }
    // Search order: ascending σ_c, ties by id.
    let keep = problem.keep().to_vec();
    let sigma = problem.span_bounds();
    let mut order: Vec<usize> = (0..problem.curve_count())
        .filter(|c| !keep.contains(c))
        .collect();
    order.sort_by(|&a, &b| sigma[a].total_cmp(&sigma[b]).then(a.cmp(&b)));
    let root = Open {
        free: fitting(problem, &keep, &order),
        included: keep,
        bound: f64::INFINITY,
        inherited: Vec::new(),
        seq: 0,
    };
    search.push(root);
    let deadline = params
        .time_limit
        .and_then(|t| Duration::try_from_secs_f64(t).ok());
    let status = search.run(|| deadline.is_some_and(|d| start.elapsed() >= d), cancel)?;
    search.info.eigen_solves = problem.eigen_solves() - solves0.0;
    search.info.relax_solves = problem.relax_solves() - solves0.1;
    search.info.seconds = start.elapsed().as_secs_f64();
    search.finish(status)
}

/// The problem's and the parameters' own errors: no feasible subset, no wave.
fn check(problem: &FixedProblem<'_>, params: &ExactParams) -> Result<(), SimplifyError> {
    let budget = problem.budget();
    if problem.length_of(problem.keep()) > budget {
        return Err(SimplifyError::Params(
            format!("no feasible subset: the keep list alone exceeds the budget {budget:.6}")
                .into(),
        ));
    }
    if problem.keep().is_empty() && problem.lengths().iter().all(|&l| l > budget) {
        return Err(SimplifyError::Params(
            format!("no feasible subset: every curve is longer than the budget {budget:.6}").into(),
        ));
    }
    if let Some(t) = params.time_limit
        && !(0.0..=MAX_TIME_LIMIT).contains(&t)
    {
        return Err(SimplifyError::Params(
            format!(
                "exact: the time limit must lie between 0 and {MAX_TIME_LIMIT:e} seconds, got {t}"
            )
            .into(),
        ));
    }
    if params.wave == 0 {
        return Err(SimplifyError::Params(
            "exact: wave must be at least 1".into(),
        ));
    }
    Ok(())
}

/// The best feasible subset met: its `λ_fix` and curves.
#[derive(Debug)]
pub(super) struct Best(pub(super) f64, pub(super) Vec<usize>);

impl Default for Best {
    fn default() -> Self {
        Best(f64::NEG_INFINITY, Vec::new())
    }
}

impl Best {
    /// Takes `s` when it beats the best (ties to the smaller list).
    pub(super) fn consider(&mut self, s: &[usize], l: f64) {
        let mut s = s.to_vec();
        s.sort_unstable();
        if l > self.0 || (l == self.0 && s < self.1) {
            *self = Best(l, s);
        }
    }
}

/// The state of [`exact`]'s best-first search.
struct Search<'p, 'a> {
    problem: &'p FixedProblem<'a>,
    params: &'p ExactParams,
    /// Design constraints an incumbent must meet.
    constraints: Option<&'p Constraints>,
    heap: BinaryHeap<Open>,
    /// The incumbent.
    best: Best,
    info: ExactInfo,
    /// The next node's creation number.
    seq: u64,
}

impl Search<'_, '_> {
    fn level(&self) -> f64 {
        cut_level(self.best.0, self.params.tolerance)
    }

    /// Whether `s` may be an incumbent: it meets the design constraints, if any.
    fn admits(&self, s: &[usize]) -> bool {
        self.constraints.is_none_or(|c| c.check(s).is_ok())
    }

    fn push(&mut self, mut node: Open) {
        node.seq = self.seq;
        self.seq += 1;
        self.heap.push(node);
    }

    /// Opens waves of nodes until every node is opened or cut, or a limit is hit.
    fn run(
        &mut self,
        out_of_time: impl Fn() -> bool,
        cancel: &Cancel,
    ) -> Result<ExactStatus, SimplifyError> {
        loop {
            let level = self.level();
            // Drop what the incumbent cuts (the heap is ordered by bound: stop at the first
            // cut; NaN bounds are never cut: `total_cmp` puts them on top).
            if self.heap.peek().is_none_or(|o| o.bound <= level) {
                self.info.cut += self.heap.len();
                self.heap.clear();
                return Ok(ExactStatus::Proven);
            }
            if self.info.nodes >= self.params.max_nodes {
                return Ok(ExactStatus::NodeLimit);
            }
            if out_of_time() {
                return Ok(ExactStatus::TimeLimit);
            }
            if cancel.is_cancelled() || self.wave(level, cancel)? {
                return Ok(ExactStatus::Cancelled);
            }
        }
    }

    /// Opens one wave of the best nodes in parallel and merges them in order; true when it was
    /// cancelled (the nodes not opened go back on the heap).
    fn wave(&mut self, level: f64, cancel: &Cancel) -> Result<bool, SimplifyError> {
        let (max_nodes, size) = (self.params.max_nodes, self.params.wave);
        let mut wave = Vec::with_capacity(size);
        while wave.len() < size && self.info.nodes + wave.len() < max_nodes {
            match self.heap.peek() {
                Some(o) if !(o.bound <= level) => wave.push(self.heap.pop().expect("peeked")),
                _ => break,
            }
        }
        let problem = self.problem;
        let opened: Vec<Result<Opened, StabilityError>> = wave
            .par_iter()
            .map(|o| open_node(problem, o, cancel))
            .collect();
        let mut cancelled = false;
        for (o, r) in wave.into_iter().zip(opened) {
            match r {
                Ok(r) => self.merge(&o, r),
                Err(StabilityError::Cancelled) => {
                    cancelled = true;
                    self.heap.push(o);
                }
                Err(e) => return Err(e.into()),
            }
        }
        Ok(cancelled)
    }

    /// Records an opened node: its structure as an incumbent, its children that
    /// the incumbent does not cut on the heap.
    fn merge(&mut self, o: &Open, r: Opened) {
        self.info.nodes += 1;
        self.info.bounds += r.bounds;
        if let Some(l) = r.lambda
            && self.admits(&o.included)
        {
            self.best.consider(&o.included, l);
        }
        let level = self.level();
        for child in r.children {
            if child.bound <= level {
                self.info.cut += 1;
            } else {
                self.push(child);
            }
        }
    }

    /// The outcome: the incumbent, and the bound of what is left open.
    fn finish(self, status: ExactStatus) -> Result<ExactOutcome, SimplifyError> {
        let level = self.level();
        let open_max = self
            .heap
            .iter()
            .map(|o| o.bound)
            .fold(f64::NEG_INFINITY, f64::max);
        let Best(lambda_fix, curves) = self.best;
        let upper = if status == ExactStatus::Proven {
            level.max(lambda_fix)
        } else {
            open_max.max(level)
        };
        if curves.is_empty() {
            if status == ExactStatus::Cancelled {
                return Err(SimplifyError::Cancelled);
            }
            return Err(SimplifyError::Params(
                "exact: no feasible subset was evaluated (node or time limit too small)".into(),
            ));
        }
        let gap = if status == ExactStatus::Proven {
            0.0
        } else {
            ((upper - lambda_fix) / upper.abs()).max(0.0)
        };
        Ok(ExactOutcome {
            length: self.problem.length_of(&curves),
            curves,
            lambda_fix,
            upper,
            gap,
            status,
            info: self.info,
        })
    }
}

/// The curves of `order` that fit the budget left by `included` (and are not in it).
fn fitting(problem: &FixedProblem<'_>, included: &[usize], order: &[usize]) -> Vec<usize> {
    let left = problem.budget() - problem.length_of(included);
    order
        .iter()
        .copied()
        .filter(|&c| !included.contains(&c) && problem.lengths()[c] <= left)
        .collect()
}

/// Opens a node: evaluates its structure, bounds it with its own certificates and clamped
/// ones, and bounds each child with the node's certificates and its parent's.
fn open_node(
    problem: &FixedProblem<'_>,
    o: &Open,
    cancel: &Cancel,
) -> Result<Opened, StabilityError> {
    cancel.check()?;
    let mut opened = Opened {
        lambda: None,
        children: Vec::new(),
        bounds: 0,
    };
    let mut certs: Vec<Arc<Rayleigh>> = Vec::new();
    if !o.included.is_empty() {
        let comps = problem.evaluate(&o.included)?;
        opened.lambda = Some(comps.iter().map(|c| c.lambda).fold(f64::INFINITY, f64::min));
        certs = comps
            .iter()
            .flat_map(|c| c.certificates.iter().cloned())
            .collect();
    }
    if o.free.is_empty() {
        return Ok(opened);
    }
    let mut bound = o.bound;
    if let Some(lambda) = opened.lambda {
        // The node's own certificates, then (one more eigen solve) the clamped ones: the low
        // modes of `I` with the vertices free curves touch held fixed.
        let node = Node::new(problem, &o.included, &o.free);
        bound = min_bound(bound, problem.best_bound(&certs, &node));
        opened.bounds += 1;
        if bound > lambda {
            cancel.check()?;
            let clamped = problem.clamped_certificates(&node)?;
            if !clamped.is_empty() {
                bound = min_bound(bound, problem.best_bound(&clamped, &node));
                opened.bounds += 1;
                certs.extend(clamped);
            }
        }
    }
    // Children (I + F[j], F[j+1..] that fits), bounded with this node's certificates and
    // the parent's.
    let pool: Vec<Arc<Rayleigh>> = certs.iter().chain(&o.inherited).cloned().collect();
    opened.children = (0..o.free.len())
        .into_par_iter()
        .map(|j| {
            let mut inc = o.included.clone();
            inc.push(o.free[j]);
            inc.sort_unstable();
            let free = fitting(problem, &inc, &o.free[j + 1..]);
            let node = Node::new(problem, &inc, &free);
            let b = min_bound(bound, problem.best_bound(&pool, &node));
            Open {
                included: inc,
                free,
                bound: b,
                inherited: certs.clone(),
                seq: 0,
            }
        })
        .collect();
    opened.bounds += opened.children.len();
    Ok(opened)
}
