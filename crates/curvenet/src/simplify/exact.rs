//! Exact branch and bound over curves for the fixed-geometry objective `λ_fix` (SPEC §5):
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
//! its children are the faces of [`super::relaxation`]; with a keep list the root is the keep
//! list.
//!
//! # Bounds
//!
//! Every bound is a certified upper bound on `λ_fix` of all the subsets of a node, from
//! [`FixedProblem::best_bound`]: the Rayleigh certificates of the node's own structure `I`
//! (its low modes, valid for every subset), of its parent's, the span bounds `σ_c` of its
//! curves, the clamped certificates of `I` (its low modes with the vertices free curves touch
//! held fixed: Cauchy interlacing; one more eigen solve, which on the compare networks cuts
//! the nodes opened by 5–10× on most surfaces, [`ExactParams::clamped`]), and optionally
//! ([`ExactParams::relax_min_free`]) the relaxation of SPEC §7 ([`FixedProblem::relax_node`])
//! on nodes with many free curves (off by default: on the compare networks it opens far fewer
//! nodes but spends up to 24 eigen solves on each, and was no faster). A child's bound is computed
//! from its parent's certificates *before* its own structure is evaluated, so most children are
//! cut without an eigen solve. A node is cut when its bound is at most the incumbent plus a
//! relative [`ExactParams::tolerance`]; the answer is then optimal within that tolerance.
//!
//! # Order and determinism
//!
//! Nodes are opened best bound first, in waves of [`ExactParams::wave`] nodes processed in
//! parallel; each wave depends only on the state at its start and is merged in a fixed order,
//! so the search (and its answer) does not depend on the thread count. Only the time limit,
//! when it is hit, makes the run timing-dependent; the outcome says so.
//!
//! # Reach
//!
//! On `curvenet compare`'s random geodesic networks (budget 0.3, 2 cores) it proves every
//! network of 16 curves within a minute (1–18 s), 4 of 5 at 18, 3 of 5 at 20 (see
//! `docs/compare.md`); its bounds cut little on half_sphere, whose optimum holds several
//! stiff curves.

use super::relaxation::{Certificate, FixedProblem, Node, Rayleigh, RelaxParams, round_relaxed};
use super::{Scorer, SimplifyError};
use crate::rod::ActiveSet;
use crate::stability::StabilityError;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::sync::Arc;
use std::time::{Duration, Instant};

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
    /// `incumbent + tolerance·|incumbent|` (the SPEC's tie tolerance by default).
    pub tolerance: f64,
    /// Relax nodes (SPEC §7) with at least this many free curves when the cheap bounds do not
    /// cut them (None: never relax; the cheap bounds alone).
    pub relax_min_free: Option<usize>,
    /// The relaxation's parameters.
    pub relax: RelaxParams,
    /// Nodes opened per parallel wave (fixed, so the search does not depend on threads).
    pub wave: usize,
    /// Also bound each opened node with its clamped certificates (one more eigen solve: the
    /// low modes of `I` with the vertices free curves touch held fixed, see
    /// [`FixedProblem::clamped_certificates`]) when its cheap bound does not cut it.
    pub clamped: bool,
}

impl Default for ExactParams {
    fn default() -> Self {
        ExactParams {
            time_limit: Some(60.0),
            max_nodes: 1_000_000,
            tolerance: 1e-7,
            relax_min_free: None,
            relax: RelaxParams::default(),
            wave: 8,
            clamped: true,
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
    /// Eigen solves of relaxations and clamped certificates.
    pub relax_solves: usize,
    /// Nodes relaxed.
    pub relaxations: usize,
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

    /// `λ_eq` of the answer (its own equilibrium), evaluated with the shared scorer.
    pub fn lambda_eq(&self, scorer: &Scorer<'_>) -> Result<f64, StabilityError> {
        let n = scorer.analyzer().network().rods.len();
        scorer.lambda_eq(&ActiveSet::from_curves(n, &self.curves))
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
    /// Subsets rounded from a relaxation, with their `λ_fix`.
    rounded: Vec<(Vec<usize>, f64)>,
    /// Bounds computed.
    bounds: usize,
    relaxed: bool,
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

/// Finds the feasible subset with the largest `λ_fix` (see the module documentation).
/// `incumbents` are feasible subsets known beforehand (e.g. the greedy's answer); they only
/// speed the search up.
pub fn exact(
    problem: &FixedProblem<'_>,
    params: &ExactParams,
    incumbents: &[Vec<usize>],
) -> Result<ExactOutcome, SimplifyError> {
    let start = Instant::now();
    let n = problem.curve_count();
    let keep = problem.keep().to_vec();
    let budget = problem.budget();
    if problem.length_of(&keep) > budget {
        return Err(SimplifyError::Params(format!(
            "no feasible subset: the keep list alone exceeds the budget {budget:.6}"
        )));
    }
    if keep.is_empty() && problem.lengths().iter().all(|&l| l > budget) {
        return Err(SimplifyError::Params(format!(
            "no feasible subset: every curve is longer than the budget {budget:.6}"
        )));
    }
    if params.wave == 0 {
        return Err(SimplifyError::Params(
            "exact: wave must be at least 1".into(),
        ));
    }
    let solves0 = (problem.eigen_solves(), problem.relax_solves());
    let deadline = params.time_limit.map(Duration::from_secs_f64);

    // Search order: ascending σ_c, ties by id.
    let sigma = problem.span_bounds();
    let mut order: Vec<usize> = (0..n).filter(|c| !keep.contains(c)).collect();
    order.sort_by(|&a, &b| sigma[a].total_cmp(&sigma[b]).then(a.cmp(&b)));

    let mut best: (f64, Vec<usize>) = (f64::NEG_INFINITY, Vec::new());
    let consider = |best: &mut (f64, Vec<usize>), s: &[usize], l: f64| {
        let mut s = s.to_vec();
        s.sort_unstable();
        if l > best.0 || (l == best.0 && s < best.1) {
            *best = (l, s);
        }
    };
    for s in incumbents {
        if problem.feasible(s) {
            let l = problem.lambda_fix(s)?;
            consider(&mut best, s, l);
        }
    }

    let mut info = ExactInfo::default();
    let mut heap: BinaryHeap<Open> = BinaryHeap::new();
    let mut seq = 0u64;
    let root_free = fitting(problem, &keep, &order);
    heap.push(Open {
        included: keep.clone(),
        free: root_free,
        bound: f64::INFINITY,
        inherited: Vec::new(),
        seq,
    });
    seq += 1;
    let mut status = ExactStatus::Proven;
    loop {
        let level = cut_level(best.0, params.tolerance);
        // Drop what the incumbent cuts (the heap is ordered by bound: stop at the first cut).
        if heap.peek().is_none_or(|o| o.bound <= level) {
            // (NaN bounds are never cut: `total_cmp` puts them on top.)
            info.cut += heap.len();
            heap.clear();
            break;
        }
        if info.nodes >= params.max_nodes {
            status = ExactStatus::NodeLimit;
            break;
        }
        if deadline.is_some_and(|d| start.elapsed() >= d) {
            status = ExactStatus::TimeLimit;
            break;
        }
        let mut wave = Vec::with_capacity(params.wave);
        while wave.len() < params.wave && info.nodes + wave.len() < params.max_nodes {
            match heap.peek() {
                Some(o) if !(o.bound <= level) => wave.push(heap.pop().expect("peeked")),
                _ => break,
            }
        }
        let opened: Vec<Result<Opened, StabilityError>> = wave
            .par_iter()
            .map(|o| open_node(problem, params, o))
            .collect();
        for (o, r) in wave.into_iter().zip(opened) {
            let r = r?;
            info.nodes += 1;
            info.bounds += r.bounds;
            info.relaxations += usize::from(r.relaxed);
            if let Some(l) = r.lambda {
                consider(&mut best, &o.included, l);
            }
            for (s, l) in &r.rounded {
                consider(&mut best, s, *l);
            }
            let level = cut_level(best.0, params.tolerance);
            for mut child in r.children {
                if child.bound <= level {
                    info.cut += 1;
                    continue;
                }
                child.seq = seq;
                seq += 1;
                heap.push(child);
            }
        }
    }
    let level = cut_level(best.0, params.tolerance);
    let open_max = heap
        .iter()
        .map(|o| o.bound)
        .fold(f64::NEG_INFINITY, f64::max);
    let upper = if status == ExactStatus::Proven {
        level.max(best.0)
    } else {
        open_max.max(level)
    };
    info.eigen_solves = problem.eigen_solves() - solves0.0;
    info.relax_solves = problem.relax_solves() - solves0.1;
    info.seconds = start.elapsed().as_secs_f64();
    if best.1.is_empty() {
        return Err(SimplifyError::Params(
            "exact: no feasible subset was evaluated (node or time limit too small)".into(),
        ));
    }
    let gap = if status == ExactStatus::Proven {
        0.0
    } else {
        ((upper - best.0) / upper.abs()).max(0.0)
    };
    Ok(ExactOutcome {
        length: problem.length_of(&best.1),
        curves: best.1,
        lambda_fix: best.0,
        upper,
        gap,
        status,
        info,
    })
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

/// Opens a node: evaluates its structure, bounds it with its own certificates (and the
/// relaxation when asked), and bounds each child with the node's certificates.
fn open_node(
    problem: &FixedProblem<'_>,
    params: &ExactParams,
    o: &Open,
) -> Result<Opened, StabilityError> {
    let mut bounds = 0;
    let (lambda, mut certs) = if o.included.is_empty() {
        (None, Vec::new())
    } else {
        let comps = problem.evaluate(&o.included)?;
        let lam = comps.iter().map(|c| c.lambda).fold(f64::INFINITY, f64::min);
        let certs: Vec<Arc<Rayleigh>> = comps
            .iter()
            .flat_map(|c| c.certificates.iter().cloned())
            .collect();
        (Some(lam), certs)
    };
    let mut bound = o.bound;
    let mut rounded = Vec::new();
    let mut relaxed = false;
    if o.free.is_empty() {
        return Ok(Opened {
            lambda,
            children: Vec::new(),
            rounded,
            bounds,
            relaxed,
        });
    }
    if !o.included.is_empty() {
        let node = Node::new(problem, &o.included, &o.free);
        bound = min_bound(bound, problem.best_bound(&certs, &node));
        bounds += 1;
        if params.clamped && bound > lambda.unwrap_or(f64::NEG_INFINITY) {
            let clamped = problem.clamped_certificates(&node)?;
            if !clamped.is_empty() {
                bound = min_bound(bound, problem.best_bound(&clamped, &node));
                bounds += 1;
                certs.extend(clamped);
            }
        }
        if let Some(min_free) = params.relax_min_free {
            if o.free.len() >= min_free && bound > lambda.unwrap_or(f64::NEG_INFINITY) {
                let pool: Vec<Arc<Rayleigh>> = certs.iter().chain(&o.inherited).cloned().collect();
                let r = problem.relax_node(&node, &params.relax, None, &pool)?;
                relaxed = true;
                bound = min_bound(bound, r.upper);
                certs.extend(r.certificates.iter().cloned());
                for s in round_relaxed(&r.alpha, problem.lengths(), problem.budget(), &o.included) {
                    if problem.feasible(&s) && s != o.included {
                        let l = problem.lambda_fix(&s)?;
                        rounded.push((s, l));
                    }
                }
            }
        }
    }
    // Children (I + F[j], F[j+1..] that fits), bounded with this node's certificates and
    // the parent's.
    let pool: Vec<Arc<Rayleigh>> = certs.iter().chain(&o.inherited).cloned().collect();
    let children: Vec<Open> = (0..o.free.len())
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
    bounds += children.len();
    Ok(Opened {
        lambda,
        children,
        rounded,
        bounds,
        relaxed,
    })
}

/// Tightens a [`Certificate`] with at most `max_nodes` nodes of the exact branch and bound
/// (deterministic: no time limit), seeded with the certified subset and the best one found:
/// the bound becomes the smaller of the relaxation's and the search's (the largest bound of
/// the nodes left open, or the optimum when the search finished), and the best subset found
/// is updated.
pub fn tighten_certificate(
    problem: &FixedProblem<'_>,
    certificate: &mut Certificate,
    max_nodes: usize,
) -> Result<(), SimplifyError> {
    if max_nodes == 0 {
        return Ok(());
    }
    let params = ExactParams {
        time_limit: None,
        max_nodes,
        ..ExactParams::default()
    };
    let seeds = [
        certificate.curves.clone(),
        certificate.best_found_curves.clone(),
    ];
    let o = exact(problem, &params, &seeds)?;
    certificate.branch_and_bound_nodes = o.info.nodes;
    if o.lambda_fix > certificate.best_found {
        certificate.best_found = o.lambda_fix;
        certificate.best_found_curves = o.curves.clone();
    }
    if o.upper < certificate.upper_bound {
        certificate.upper_bound = o.upper.max(certificate.lambda_fix);
    }
    certificate.proven_optimum = o.proven();
    let (l, u) = (certificate.lambda_fix, certificate.upper_bound);
    certificate.ratio = (l > 0.0 && u > 0.0).then(|| l / u);
    Ok(())
}
