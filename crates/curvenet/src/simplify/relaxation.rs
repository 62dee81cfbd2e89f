//! Certified upper bounds on the best `λ_fix` of any feasible subset: the continuous
//! relaxation of the MI-SDP of SPEC §7, solved without an SDP solver.
//!
//! # The objective
//!
//! Everything here is about `λ_fix(S) = λ_fix(S | A)` with `A` the *full* network: its
//! equilibrium `u` is computed once, the local Hessians of every term once, and `H_S` is the
//! sum of the Hessians `H_c` of the curves `c ∈ S` (all their terms: stretching, bending,
//! anchors) over `V(S)`, the vertices of `S`'s curves (SPEC §5). The problem is
//!
//! ```text
//! λ* = max { λ_min(H_S) : S ⊇ keep, S ≠ ∅, Σ_{c∈S} L_c ≤ V }.
//! ```
//!
//! # The relaxation
//!
//! SPEC §7 writes the structure of `S` with per-curve factors `α_c ∈ {0,1}` and regularizers
//! `ρ` on the loose pieces. Here every term of curve `c` is scaled by `α_c` (the SPEC keeps the
//! terms not touching a joint, `H0_c`, unscaled; with binary `α` they live on `c`'s loose
//! pieces only, so both write the same structure, and scaling them too makes the relaxation
//! tighter and frees `ρ` from having to beat their negative eigenvalues), and the regularizer
//! is per vertex, `β_v ≤ 1 − α_c` for every curve `c` through `v` (for a joint of two curves this
//! is the SPEC's `β_ij`; with three or more it forbids regularizing a vertex a kept curve
//! holds):
//!
//! ```text
//! M_ρ(α, β) = Σ_c α_c H_c + ρ diag(β),   α ∈ K, 0 ≤ β_v ≤ 1 − max_{c∋v} α_c,
//! K = { α ∈ [0,1]^n : α_keep = 1, Σ α_c L_c ≤ V, Σ α_c ≥ 1 }.
//! ```
//!
//! For `α = 1_S` and `β = 1` on the vertices no curve of `S` holds, `M_ρ` is `H_S` plus `ρI` on
//! the loose vertices, so `λ_min = min(λ_fix(S), ρ)`: the relaxed maximum `B(ρ)` satisfies
//! `B(ρ) ≥ min(λ*, ρ)` for **every** `ρ`, and whenever a certified `B(ρ) < ρ`, then `λ* ≤ B(ρ)`
//! ("ρ was large enough": the loose pieces' eigenvalue `ρ` exceeds every feasible structure's).
//! The best `ρ` is the fixed point `B(ρ) = ρ`. Since `λ_min(M_ρ) < ρ` ⟺
//! `λ_min(H(α) − ρP(α)) < 0` with `P(α) = diag_v(max_{c∋v} α_c)`, the fixed point is the
//! quasi-concave generalized-eigenvalue problem
//!
//! ```text
//! μ* = max_{α ∈ K} μ(α),   μ(α) = λ_min(H(α), P(α)) = min_x xᵀH(α)x / xᵀP(α)x,
//! ```
//!
//! and `μ(1_S) = λ_fix(S)` exactly. This is what [`FixedProblem::relax_node`] maximizes.
//!
//! # Why every bound is rigorous
//!
//! The bounds do not trust the eigen solver or the optimizer: they come from *test vectors*.
//! For any vectors `x_k` with weights `z_k ≥ 0` and any feasible `S` (restricting `x_k` to
//! `V(S)`), since `H_c` only touches `V(c) ⊆ V(S)`,
//!
//! ```text
//! λ_fix(S) ≤ Σ_k z_k x_kᵀ H_S x_k / Σ_k z_k |x_k|_{V(S)}|² = N(S) / D(S),
//! N(S) = Σ_{c∈S} a_c,  a_c = Σ_k z_k x_kᵀH_c x_k,   D(S) = Σ_v w_v [v ∈ V(S)],  w_v = Σ_k z_k |x_{k,v}|².
//! ```
//!
//! `[v ∈ V(S)] = max_{c∋v} 1_S(c)`, whose convex extension is `max_{c∋v} α_c`, so
//! `max_S N/D ≤ max_{α∈K} N(α)/D(α)`, a ratio of a linear and a convex piecewise-linear function.
//! Its maximum is computed by Dinkelbach's method: `ρ* ≤ ρ` iff `F(ρ) = max_K N − ρD ≤ 0`, and
//! `F(ρ)` is a linear program that is solved exactly: a Lagrange multiplier `μ` on the budget
//! leaves `max_{α∈[0,1]^F} Σ (a_c − ρ d_c − μ L_c) α_c − ρ Σ_G h_G max_{c∈G} α_c`, the Lovász
//! extension of a supermodular set function, maximized at a vertex by a minimum cut (a
//! max-weight closure: a curve pays once for each group of shared vertices it covers); the
//! Lagrangian dual is convex piecewise linear in `μ` and minimized exactly by intersecting the
//! lines of its closures. Every value of the dual is an upper bound of `F(ρ)` (weak duality),
//! and `ρ* ≤ ρ + max(F(ρ), 0)/D_min` for any `ρ` (`F` is convex with slopes `≤ −D_min`), so the
//! bound never depends on the iteration having converged. Floating-point rounding in `xᵀH_cx`
//! is of the order `ε‖H‖₁` — the floor below which `λ` itself cannot be resolved (the zero-mode
//! threshold of SPEC §5 is `5ε‖H‖₁`); every bound adds `128·ε·‖H‖₁`.
//!
//! With `x` the eigenvector at the relaxed optimum (a mixture over its eigenspace when the
//! eigenvalue is repeated), the bound equals the relaxation's optimum: the optimizer produces the
//! certificate, the certificate does not depend on the optimizer.
//!
//! # Faces
//!
//! The ratio `N/D` is invariant under scaling `α`, so over `K` alone the budget only constrains
//! the `α`-weighted *average* length of the curves — a weak bound. But every non-empty `S` has a
//! curve at `α_c = 1`: with the keep list empty, the bound is the maximum over `c` of the
//! relaxation with `α_c = 1` and `α = 0` on the curves before `c` (the partition of the subsets
//! by their first curve); there the budget binds. These "faces" are also the root of
//! the exact branch and bound ([`super::exact`]).
//!
//! # The optimizer
//!
//! [`FixedProblem::relax_node`] is a Frank–Wolfe method for the quasi-concave `μ`: at `α_t`, the
//! eigenvector `x_t` gives the upper model `N_x(α)/D_x(α) ≥ μ(α)` (tight at `α_t`); its
//! maximizer over the node's polytope (the linear step, solved exactly as above) is the
//! Frank–Wolfe vertex `s_t`; a backtracking search on `μ(α_t + γ(s_t − α_t))` (quasi-concave,
//! so unimodal along the segment) takes the step. Every eigen solve yields a certificate; the
//! best is kept; the run stops on a relative gap, a cap on eigen solves, or a stalled step.

use super::{Budget, SimplifyError};
use crate::rod::ActiveSet;
use crate::rod::model::{LocalHessians, Terms};
use crate::solve::NewtonSummary;
use crate::solve::SymbolicFactor;
use crate::solve::eigen::{EigenError, EigenOptions, EigenParams, Spectrum, Start};
use crate::sparse::Pattern;
use crate::stability::{Analyzer, StabilityError};
use faer::{Mat, MatRef};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Relative width of an eigenvalue cluster treated as one repeated eigenvalue.
const CLUSTER: f64 = 1e-6;
/// Modes per eigen solve whose Rayleigh certificates are kept.
const CERT_MODES: usize = 3;

/// Vertices lying on exactly the same curves.
#[derive(Clone, Debug)]
struct VertexGroup {
    curves: Vec<usize>,
    vertices: Vec<u32>,
}

/// A test-vector certificate: `a_c = Σ_k z_k x_kᵀH_cx_k` per curve and `w` summed per vertex
/// group (see the module documentation). Valid for every subset, whatever `x` was.
#[derive(Clone, Debug)]
pub struct Rayleigh {
    a: Vec<f64>,
    g: Vec<f64>,
}

impl Rayleigh {
    /// Total weight `Σ_v w_v` (the denominator when every vertex is covered).
    fn mass(&self) -> f64 {
        self.g.iter().sum()
    }

    /// The same certificate scaled to unit mass (None when it has none).
    fn normalized(&self) -> Option<Rayleigh> {
        let m = self.mass();
        if !(m > 0.0 && m.is_finite()) {
            return None;
        }
        Some(Rayleigh {
            a: self.a.iter().map(|x| x / m).collect(),
            g: self.g.iter().map(|x| x / m).collect(),
        })
    }

    /// `(1 − z)·self + z·other`: the certificate of the union of the two weighted vector sets.
    fn mix(&self, other: &Rayleigh, z: f64) -> Rayleigh {
        Rayleigh {
            a: self
                .a
                .iter()
                .zip(&other.a)
                .map(|(x, y)| (1.0 - z) * x + z * y)
                .collect(),
            g: self
                .g
                .iter()
                .zip(&other.g)
                .map(|(x, y)| (1.0 - z) * x + z * y)
                .collect(),
        }
    }
}

/// The best mixture `(1 − z)·base + z·r` for a bound `f` (quasi-convex in `z`: its sublevel
/// sets are convex), by golden-section search over `t = logit(z)` plus both ends.
fn best_mixture(base: &Rayleigh, r: &Rayleigh, f: &dyn Fn(&Rayleigh) -> f64) -> (Rayleigh, f64) {
    let (Some(b), Some(r)) = (base.normalized(), r.normalized()) else {
        let fb = f(base);
        let fr = f(r);
        return if fr < fb {
            (r.clone(), fr)
        } else {
            (base.clone(), fb)
        };
    };
    let fb = f(&b);
    let fr = f(&r);
    let mut best = if fr < fb {
        (r.clone(), fr)
    } else {
        (b.clone(), fb)
    };
    let at = |t: f64| -> (Rayleigh, f64) {
        let z = 1.0 / (1.0 + (-t).exp());
        let m = b.mix(&r, z);
        let v = f(&m);
        (m, v)
    };
    let phi = 0.5 * (5f64.sqrt() - 1.0);
    let (mut lo, mut hi) = (-24.0f64, 24.0f64);
    let mut x1 = hi - phi * (hi - lo);
    let mut x2 = lo + phi * (hi - lo);
    let mut f1 = at(x1);
    let mut f2 = at(x2);
    for _ in 0..28 {
        if f1.1 <= f2.1 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - phi * (hi - lo);
            f1 = at(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + phi * (hi - lo);
            f2 = at(x2);
        }
    }
    for cand in [f1, f2] {
        if cand.1 < best.1 {
            best = cand;
        }
    }
    best
}

/// A connected structure's `λ_fix` and the certificates from its low modes.
#[derive(Clone, Debug)]
pub struct Component {
    /// Curves, ascending.
    pub curves: Vec<usize>,
    /// `λ_fix` of the component.
    pub lambda: f64,
    /// Rayleigh certificates from its lowest modes.
    pub certificates: Vec<Arc<Rayleigh>>,
}

/// Whether a curve is in, out of, or free in the subsets of a node.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Status {
    /// In every subset of the node.
    In,
    /// In no subset of the node.
    Out,
    /// Either.
    Free,
}

/// A set of subsets: those holding the `In` curves, none of the `Out` curves, within budget.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Node {
    /// Status of every curve.
    pub status: Vec<Status>,
}

impl Node {
    /// The node whose subsets hold `included`, may hold any of `free` that fit the budget left,
    /// and nothing else.
    pub fn new(problem: &FixedProblem<'_>, included: &[usize], free: &[usize]) -> Node {
        let n = problem.curve_count();
        let mut status = vec![Status::Out; n];
        for &c in included {
            status[c] = Status::In;
        }
        let left = problem.budget - problem.length_of(included);
        for &c in free {
            if status[c] == Status::Out && problem.lengths[c] <= left {
                status[c] = Status::Free;
            }
        }
        Node { status }
    }

    /// Curves with a given status, ascending.
    pub fn curves(&self, s: Status) -> Vec<usize> {
        (0..self.status.len())
            .filter(|&c| self.status[c] == s)
            .collect()
    }
}

/// The result of bounding one node with one certificate.
#[derive(Clone, Debug)]
pub struct RatioBound {
    /// Certified: `λ_fix(S) ≤ upper` for every subset `S` of the node.
    pub upper: f64,
    /// The largest ratio `N(α)/D(α)` found (at `alpha`).
    pub value: f64,
    /// A maximizer of the ratio over the node's relaxed polytope (per curve).
    pub alpha: Vec<f64>,
}

/// Parameters of [`FixedProblem::relax_node`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RelaxParams {
    /// Cap on eigen solves.
    pub max_evals: usize,
    /// Stop when `(upper − value) ≤ tolerance·|upper|`.
    pub tolerance: f64,
    /// Stop after this many consecutive rounds without an accepted step (each round tries up
    /// to three step lengths).
    pub max_stalled: usize,
}

impl Default for RelaxParams {
    fn default() -> Self {
        RelaxParams {
            max_evals: 24,
            tolerance: 1e-3,
            max_stalled: 8,
        }
    }
}

/// The relaxation of one node.
#[derive(Clone, Debug)]
pub struct NodeRelaxation {
    /// Certified upper bound on `λ_fix` of the node's subsets.
    pub upper: f64,
    /// Best relaxed value `μ(α)` reached (a lower bound on the relaxation's optimum).
    pub value: f64,
    /// The relaxed point reaching it (per curve).
    pub alpha: Vec<f64>,
    /// Eigen solves spent.
    pub evals: usize,
    /// Frank–Wolfe steps taken.
    pub steps: usize,
    /// The certificates produced (valid for every node).
    pub certificates: Vec<Arc<Rayleigh>>,
}

/// Parameters of [`FixedProblem::certify`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CertifyParams {
    /// Relaxation of each face.
    pub relax: RelaxParams,
    /// Round every face's relaxed solution to subsets and evaluate them (better lower bounds).
    pub rounding: bool,
}

impl Default for CertifyParams {
    /// Up to 150 eigen solves per relaxed face, stopping at a 1% relative gap between the
    /// relaxed value and its bound (on the tower, 24 solves leave the bound at 3e-5 against a
    /// relaxed value of 6e-9; 120 bring it to 8.4e-9 against 7.7e-9).
    fn default() -> Self {
        CertifyParams {
            relax: RelaxParams {
                max_evals: 150,
                tolerance: 1e-2,
                max_stalled: 8,
            },
            rounding: true,
        }
    }
}

/// The bound of one face (the subsets whose first curve is `curve`), or of the root when a
/// keep list is given (`curve` = None).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FaceBound {
    /// The face's first curve.
    pub curve: Option<usize>,
    /// Certified upper bound on `λ_fix` of the face's subsets.
    pub upper: f64,
    /// Best relaxed value reached (NaN when the face was not relaxed).
    pub relaxed: f64,
    /// Eigen solves of its relaxation (0 when cheaper bounds sufficed).
    pub evals: usize,
}

/// A certified bracket of the best `λ_fix` over the feasible subsets.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoundReport {
    /// Certified: every feasible subset has `λ_fix ≤ upper`.
    pub upper: f64,
    /// The best `λ_fix` of a feasible subset met on the way (the incumbents, the faces' first
    /// curves and the roundings of the relaxed solutions).
    pub lower: f64,
    /// That subset.
    pub lower_curves: Vec<usize>,
    /// Every face.
    pub faces: Vec<FaceBound>,
    /// Eigen solves of the relaxations.
    pub relax_evals: usize,
    /// Eigen solves of `λ_fix` evaluations.
    pub evaluations: usize,
}

/// One eigen solve of the relaxation at `α`.
struct RelaxedEval {
    mu: f64,
    /// Eigenvectors of the scaled matrix (the next warm start).
    y: Mat<f64>,
    /// Certificates: the lowest modes alone, and the cluster mixture when repeated.
    certificates: Vec<Arc<Rayleigh>>,
}

/// The `λ_fix` problem of one network at the full network's equilibrium: evaluations with a
/// cache of connected components, certificates, relaxations and bounds.
pub struct FixedProblem<'a> {
    analyzer: &'a Analyzer,
    displacement: Vec<f64>,
    newton: Option<NewtonSummary>,
    locals: LocalHessians,
    lengths: Vec<f64>,
    budget: f64,
    keep: Vec<usize>,
    groups: Vec<VertexGroup>,
    eval_eigen: EigenParams,
    relax_eigen: EigenParams,
    margin: f64,
    /// Per curve: a certified upper bound on `λ_fix` of every subset holding it (the
    /// Rayleigh quotient of its lowest mode on the vertices no other curve holds).
    sigma: Vec<f64>,
    cache: Mutex<HashMap<Vec<usize>, Arc<Component>>>,
    eigen_solves: AtomicUsize,
    relax_solves: AtomicUsize,
}

impl std::fmt::Debug for FixedProblem<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FixedProblem")
            .field("curves", &self.lengths.len())
            .field("budget", &self.budget)
            .field("keep", &self.keep)
            .finish_non_exhaustive()
    }
}

impl<'a> FixedProblem<'a> {
    /// Relaxes the full network from the drawn state and sets up the problem.
    pub fn new(
        analyzer: &'a Analyzer,
        budget: Budget,
        keep: &[usize],
    ) -> Result<Self, SimplifyError> {
        let n = analyzer.network().rods.len();
        let mut u = vec![0.0; analyzer.model().dofs()];
        let info = analyzer.relax(&ActiveSet::all(n), &mut u);
        let mut p = Self::with_displacement(analyzer, u, budget, keep)?;
        p.newton = Some(info.summary());
        Ok(p)
    }

    /// The problem at given displacements (the full network's equilibrium).
    pub fn with_displacement(
        analyzer: &'a Analyzer,
        displacement: Vec<f64>,
        budget: Budget,
        keep: &[usize],
    ) -> Result<Self, SimplifyError> {
        budget.validate().map_err(SimplifyError::Params)?;
        let model = analyzer.model();
        let n = analyzer.network().rods.len();
        if n == 0 {
            return Err(SimplifyError::Params("the network has no curves".into()));
        }
        if displacement.len() != model.dofs() {
            return Err(SimplifyError::Params(
                "displacements do not match the network".into(),
            ));
        }
        if let Some(&k) = keep.iter().find(|&&k| k >= n) {
            return Err(SimplifyError::Params(format!(
                "keep list names curve {k}, but there are {n} curves"
            )));
        }
        let mut keep = keep.to_vec();
        keep.sort_unstable();
        keep.dedup();
        let lengths = analyzer.network().rest_lengths();
        let budget = budget.length(lengths.iter().sum());
        let locals = model.local_hessians(&displacement, Terms::All);
        let mut index: BTreeMap<Vec<usize>, usize> = BTreeMap::new();
        let mut groups: Vec<VertexGroup> = Vec::new();
        for (v, cs) in model.vertex_curves().iter().enumerate() {
            if cs.is_empty() {
                continue;
            }
            let mut key: Vec<usize> = cs.iter().map(|&c| c as usize).collect();
            key.sort_unstable();
            key.dedup();
            let gi = *index.entry(key.clone()).or_insert_with(|| {
                groups.push(VertexGroup {
                    curves: key,
                    vertices: Vec::new(),
                });
                groups.len() - 1
            });
            groups[gi].vertices.push(v as u32);
        }
        let full = model.assemble(&displacement, &ActiveSet::all(n), true).hess;
        let norm1 = model.pattern().sym_norm1(&full);
        let base = &analyzer.params().eigen;
        let eval_eigen = base.fixed_spectrum();
        let relax_eigen = base.relaxation_step();
        let mut p = FixedProblem {
            analyzer,
            displacement,
            newton: None,
            locals,
            lengths,
            budget,
            keep,
            groups,
            eval_eigen,
            relax_eigen,
            margin: 128.0 * f64::EPSILON * norm1,
            sigma: Vec::new(),
            cache: Mutex::default(),
            eigen_solves: AtomicUsize::new(0),
            relax_solves: AtomicUsize::new(0),
        };
        let sigma: Vec<Result<f64, StabilityError>> =
            (0..n).into_par_iter().map(|c| p.span_bound(c)).collect();
        p.sigma = sigma.into_iter().collect::<Result<_, _>>()?;
        Ok(p)
    }

    /// `σ_c`: the Rayleigh quotient of the lowest mode of `H_c` on the vertices only curve `c`
    /// holds (its spans between joints, joints clamped), plus the margin. Only `c`'s terms
    /// reach those vertices, so by Cauchy interlacing every subset holding `c` has
    /// `λ_fix ≤ σ_c`; `+∞` when every vertex of `c` is shared.
    fn span_bound(&self, c: usize) -> Result<f64, StabilityError> {
        let n = self.curve_count();
        let model = self.analyzer.model();
        let mut own = vec![false; model.vertex_count()];
        let mut shared = vec![false; model.vertex_count()];
        for g in &self.groups {
            if g.curves.contains(&c) {
                for &v in &g.vertices {
                    if g.curves.len() == 1 {
                        own[v as usize] = true;
                    } else {
                        shared[v as usize] = true;
                    }
                }
            }
        }
        if !own.iter().any(|&o| o) {
            return Ok(f64::INFINITY);
        }
        let mut weights = vec![0.0; n];
        weights[c] = 1.0;
        let certs = self.clamped_modes(&weights, &shared, &own)?;
        let Some(r) = certs.first() else {
            return Ok(f64::INFINITY);
        };
        let den: f64 = r.g.iter().sum();
        Ok(if den > 0.0 {
            r.a[c] / den + self.margin
        } else {
            f64::INFINITY
        })
    }

    /// `σ_c` of every curve (see the module documentation).
    pub fn span_bounds(&self) -> &[f64] {
        &self.sigma
    }

    /// The smallest `σ_c` over the `In` curves of `node`.
    fn sigma_in(&self, node: &Node) -> f64 {
        (0..self.curve_count())
            .filter(|&c| node.status[c] == Status::In)
            .map(|c| self.sigma[c])
            .fold(f64::INFINITY, f64::min)
    }

    /// `node` without the free curves whose `σ_c ≤ threshold`: every subset holding one of
    /// them has `λ_fix ≤ threshold`.
    pub fn filtered(&self, node: &Node, threshold: f64) -> Node {
        let mut out = node.clone();
        for (c, s) in out.status.iter_mut().enumerate() {
            if *s == Status::Free && self.sigma[c] <= threshold {
                *s = Status::Out;
            }
        }
        out
    }

    /// The bound of certificate `r` on `node`, combined with the span bounds: the smallest
    /// `max(ρ, U_ρ)` over thresholds `ρ`, with `U_ρ` the ratio bound once the free curves with
    /// `σ ≤ ρ` are left out (a subset holding one of them has `λ_fix ≤ ρ`), and `σ` of the
    /// `In` curves.
    pub fn node_bound(&self, r: &Rayleigh, node: &Node) -> f64 {
        let sig_in = self.sigma_in(node);
        let u0 = self.ratio_bound(r, node).upper;
        let mut best = u0.min(sig_in);
        let mut th: Vec<f64> = (0..self.curve_count())
            .filter(|&c| node.status[c] == Status::Free && self.sigma[c] < best)
            .map(|c| self.sigma[c])
            .collect();
        th.sort_by(f64::total_cmp);
        th.dedup();
        if th.is_empty() {
            return best;
        }
        // g(k) = U at threshold th[k] is non-increasing, th increasing: find the first k with
        // g(k) ≤ th[k] by bisection.
        let g = |k: usize| self.ratio_bound(r, &self.filtered(node, th[k])).upper;
        let (mut lo, mut hi) = (0usize, th.len());
        let mut g_lo_prev = u0;
        while lo < hi {
            let mid = (lo + hi) / 2;
            let gm = g(mid);
            if gm <= th[mid] {
                best = best.min(th[mid]);
                hi = mid;
            } else {
                best = best.min(gm);
                g_lo_prev = gm;
                lo = mid + 1;
            }
        }
        best.min(g_lo_prev)
    }

    /// The analyzer.
    pub fn analyzer(&self) -> &'a Analyzer {
        self.analyzer
    }

    /// The equilibrium all `λ_fix` are taken at.
    pub fn displacement(&self) -> &[f64] {
        &self.displacement
    }

    /// How the full network was relaxed (None when the displacements were given).
    pub fn newton(&self) -> Option<&NewtonSummary> {
        self.newton.as_ref()
    }

    /// Number of curves.
    pub fn curve_count(&self) -> usize {
        self.lengths.len()
    }

    /// Rest length of every curve.
    pub fn lengths(&self) -> &[f64] {
        &self.lengths
    }

    /// The budget as a length.
    pub fn budget(&self) -> f64 {
        self.budget
    }

    /// The keep list, ascending.
    pub fn keep(&self) -> &[usize] {
        &self.keep
    }

    /// The absolute round-off margin added to every bound (`128·ε·‖H‖₁`).
    pub fn margin(&self) -> f64 {
        self.margin
    }

    /// Total rest length of `curves`.
    pub fn length_of(&self, curves: &[usize]) -> f64 {
        curves.iter().map(|&c| self.lengths[c]).sum()
    }

    /// True when `curves` is a feasible subset (non-empty, holds the keep list, within budget).
    pub fn feasible(&self, curves: &[usize]) -> bool {
        !curves.is_empty()
            && self.keep.iter().all(|k| curves.contains(k))
            && self.length_of(curves) <= self.budget
    }

    /// Eigen solves of `λ_fix` evaluations so far.
    pub fn eigen_solves(&self) -> usize {
        self.eigen_solves.load(Ordering::Relaxed)
    }

    /// Eigen solves of relaxations so far.
    pub fn relax_solves(&self) -> usize {
        self.relax_solves.load(Ordering::Relaxed)
    }

    /// The connected parts of `curves` (joined through shared vertices), each ascending, in
    /// order of their smallest curve.
    pub fn components(&self, curves: &[usize]) -> Vec<Vec<usize>> {
        let links = self.groups.iter().map(|g| g.curves.iter().copied());
        crate::network::subnet::curve_components(self.curve_count(), curves, links)
    }

    /// `λ_fix` of `curves` (any set, feasible or not): the smallest over its components.
    pub fn lambda_fix(&self, curves: &[usize]) -> Result<f64, StabilityError> {
        Ok(self
            .evaluate(curves)?
            .iter()
            .map(|c| c.lambda)
            .fold(f64::INFINITY, f64::min))
    }

    /// The components of `curves` with their `λ_fix` and certificates, weakest first (ties by
    /// smallest curve). Each component is computed once and cached.
    pub fn evaluate(&self, curves: &[usize]) -> Result<Vec<Arc<Component>>, StabilityError> {
        if curves.is_empty() {
            return Err(StabilityError::Empty);
        }
        let mut out = Vec::new();
        for part in self.components(curves) {
            let cached = self.cache.lock().expect("cache lock").get(&part).cloned();
            let comp = match cached {
                Some(c) => c,
                None => {
                    let c = Arc::new(self.compute_component(&part)?);
                    self.cache
                        .lock()
                        .expect("cache lock")
                        .insert(part, c.clone());
                    c
                }
            };
            out.push(comp);
        }
        out.sort_by(|a, b| a.lambda.total_cmp(&b.lambda).then(a.curves.cmp(&b.curves)));
        Ok(out)
    }

    /// The spectrum of `H_S` at the full equilibrium (every component together).
    pub fn spectrum(&self, curves: &[usize]) -> Result<Spectrum, StabilityError> {
        if curves.is_empty() {
            return Err(StabilityError::Empty);
        }
        let model = self.analyzer.model();
        let active = ActiveSet::from_curves(self.curve_count(), curves);
        let mut h = Vec::new();
        model.hessian_from_locals(&self.locals, &active, &mut h);
        self.eigen_solves.fetch_add(1, Ordering::Relaxed);
        Ok(restricted_spectrum(
            model.pattern(),
            &h,
            self.analyzer.symbolic(),
            &coordinates(&model.vertex_mask(&active)),
            None,
            &self.eval_eigen,
        )?)
    }

    fn compute_component(&self, part: &[usize]) -> Result<Component, StabilityError> {
        let model = self.analyzer.model();
        let n = self.curve_count();
        let active = ActiveSet::from_curves(n, part);
        let mut h = Vec::new();
        model.hessian_from_locals(&self.locals, &active, &mut h);
        self.eigen_solves.fetch_add(1, Ordering::Relaxed);
        let mask = model.vertex_mask(&active);
        let sp = restricted_spectrum(
            model.pattern(),
            &h,
            self.analyzer.symbolic(),
            &coordinates(&mask),
            None,
            &self.eval_eigen,
        )?;
        let mut x = sp.vectors.clone();
        zero_rows(&mut x, &mask);
        let certificates = self.certificates_of(x.as_ref(), &sp.values);
        Ok(Component {
            curves: part.to_vec(),
            lambda: sp.lambda(),
            certificates,
        })
    }

    /// Certificates from modes `x` (columns, eigenvalues `values` ascending): each of the
    /// lowest [`CERT_MODES`] alone, and the equal-weight mixture of the lowest cluster when the
    /// smallest eigenvalue is repeated.
    fn certificates_of(&self, x: MatRef<'_, f64>, values: &[f64]) -> Vec<Arc<Rayleigh>> {
        let k = x.ncols().min(values.len());
        if k == 0 {
            return Vec::new();
        }
        let model = self.analyzer.model();
        let n = self.curve_count();
        // Curves touching the support.
        let mut nonzero = vec![false; model.vertex_count()];
        for (v, nz) in nonzero.iter_mut().enumerate() {
            *nz = (0..k).any(|j| (0..3).any(|a| x[(3 * v + a, j)] != 0.0));
        }
        let touched: Vec<usize> = (0..n)
            .filter(|&c| model.curve_vertices(c).iter().any(|&v| nonzero[v as usize]))
            .collect();
        // Per-mode quadratic forms x_jᵀ H_c x_j.
        let forms: Vec<(usize, Vec<f64>)> = touched
            .par_iter()
            .map(|&c| {
                let hx = model.curve_hessian_product(&self.locals, c, x);
                let verts = model.curve_vertices(c);
                let mut f = vec![0.0; k];
                for (s, &v) in verts.iter().enumerate() {
                    for a in 0..3 {
                        let row = 3 * v as usize + a;
                        for (j, fj) in f.iter_mut().enumerate() {
                            *fj += x[(row, j)] * hx[(3 * s + a, j)];
                        }
                    }
                }
                (c, f)
            })
            .collect();
        let mut gw = vec![vec![0.0; k]; self.groups.len()];
        for (gi, g) in self.groups.iter().enumerate() {
            for &v in &g.vertices {
                if !nonzero[v as usize] {
                    continue;
                }
                for (j, w) in gw[gi].iter_mut().enumerate() {
                    for a in 0..3 {
                        let e = x[(3 * v as usize + a, j)];
                        *w += e * e;
                    }
                }
            }
        }
        let make = |z: &[f64]| -> Arc<Rayleigh> {
            let mut a = vec![0.0; n];
            for (c, f) in &forms {
                a[*c] = f.iter().zip(z).map(|(x, y)| x * y).sum();
            }
            let g = gw
                .iter()
                .map(|w| w.iter().zip(z).map(|(x, y)| x * y).sum())
                .collect();
            Arc::new(Rayleigh { a, g })
        };
        let mut out = Vec::new();
        for j in 0..k.min(CERT_MODES) {
            let mut z = vec![0.0; k];
            z[j] = 1.0;
            out.push(make(&z));
        }
        let lo = values[0];
        let tol = CLUSTER * lo.abs().max(self.margin);
        let m = values[..k].iter().take_while(|&&v| v - lo <= tol).count();
        if m > 1 {
            let mut z = vec![0.0; k];
            for zj in z.iter_mut().take(m) {
                *zj = 1.0 / m as f64;
            }
            out.push(make(&z));
        }
        out
    }

    /// Bounds `λ_fix` over the subsets of `node` with certificate `r` (exact Dinkelbach over
    /// the node's relaxed polytope; see the module documentation).
    pub fn ratio_bound(&self, r: &Rayleigh, node: &Node) -> RatioBound {
        let lp = RatioLp::build(self, r, node);
        let (upper, value, free_alpha) = lp.solve();
        let mut alpha: Vec<f64> = node
            .status
            .iter()
            .map(|s| if *s == Status::In { 1.0 } else { 0.0 })
            .collect();
        for (i, &c) in lp.free.iter().enumerate() {
            alpha[c] = free_alpha[i];
        }
        RatioBound {
            upper: upper + self.margin,
            value,
            alpha,
        }
    }

    /// True when certificate `r` proves that no subset of `node` has `λ_fix` above
    /// `threshold` (cheap tests first).
    pub fn prunes(&self, r: &Rayleigh, node: &Node, threshold: f64) -> bool {
        if self.sigma_in(node) <= threshold {
            return true;
        }
        let lp = RatioLp::build(self, r, &self.filtered(node, threshold));
        lp.at_most(threshold - self.margin)
    }

    /// The smallest bound over certificates.
    pub fn best_bound(&self, certs: &[Arc<Rayleigh>], node: &Node) -> f64 {
        certs
            .iter()
            .map(|c| self.node_bound(c, node))
            .fold(self.sigma_in(node), f64::min)
    }

    /// One eigen solve of the relaxation at `alpha` (per curve).
    fn eval_relaxed(
        &self,
        alpha: &[f64],
        warm: Option<MatRef<'_, f64>>,
    ) -> Result<RelaxedEval, StabilityError> {
        let model = self.analyzer.model();
        let pattern = model.pattern();
        let nv = model.vertex_count();
        let mut p = vec![0.0f64; nv];
        for g in &self.groups {
            let m = g.curves.iter().map(|&c| alpha[c]).fold(0.0, f64::max);
            for &v in &g.vertices {
                p[v as usize] = m;
            }
        }
        let s: Vec<f64> = p
            .iter()
            .map(|&pv| if pv > 0.0 { 1.0 / pv.sqrt() } else { 1.0 })
            .collect();
        let mut h = Vec::new();
        model.hessian_weighted(&self.locals, alpha, &mut h);
        for j in 0..pattern.n {
            let sj = s[j / 3];
            for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                h[k] *= s[pattern.row_idx[k] / 3] * sj;
            }
        }
        self.relax_solves.fetch_add(1, Ordering::Relaxed);
        let held: Vec<bool> = p.iter().map(|&pv| pv > 0.0).collect();
        let sp = restricted_spectrum(
            pattern,
            &h,
            self.analyzer.symbolic(),
            &coordinates(&held),
            warm,
            &self.relax_eigen,
        )?;
        let mut x = sp.vectors.clone();
        for v in 0..nv {
            for a in 0..3 {
                for j in 0..x.ncols() {
                    x[(3 * v + a, j)] = if p[v] > 0.0 {
                        x[(3 * v + a, j)] * s[v]
                    } else {
                        0.0
                    };
                }
            }
        }
        let certificates = self.certificates_of(x.as_ref(), &sp.values);
        Ok(RelaxedEval {
            mu: sp.lambda(),
            y: sp.vectors,
            certificates,
        })
    }

    /// Maximizes the relaxation `μ(α)` over the relaxed polytope of `node`, starting at `start`
    /// (default: the node's `In` curves), with the certificates of `pool` counted too.
    ///
    /// A cutting-plane (Frank–Wolfe-like) method: the best certificate so far — a mixture of
    /// the certificates of every eigen solve, improved by `best_mixture` as they come — is an
    /// upper model of `μ`; its maximizer over the polytope (the exact linear step) is the next
    /// vertex `s`; `μ` is evaluated at `α + γ(s − α)` for `γ = 1, ½, ¼` (quasi-concave, so
    /// unimodal along the segment) and the step is taken at the first improvement. Every eigen
    /// solve adds certificates, which cut the model where it was too optimistic. Free curves
    /// with `σ_c` at or below the best value reached are left out as it goes (any relaxed
    /// point using one has `μ ≤ σ_c`); bounds are `max(value, U)` on the node without them.
    pub fn relax_node(
        &self,
        node: &Node,
        params: &RelaxParams,
        start: Option<&[f64]>,
        pool: &[Arc<Rayleigh>],
    ) -> Result<NodeRelaxation, StabilityError> {
        let n = self.curve_count();
        let project = |work: &Node, a: &[f64]| -> Vec<f64> {
            (0..n)
                .map(|c| match work.status[c] {
                    Status::In => 1.0,
                    Status::Out => 0.0,
                    Status::Free => {
                        let x = a[c].clamp(0.0, 1.0);
                        if x < 1e-12 { 0.0 } else { x }
                    }
                })
                .collect()
        };
        let mut alpha = project(node, start.unwrap_or(&vec![0.0; n]));
        if !alpha.iter().any(|&a| a > 0.0) {
            return Err(StabilityError::Empty);
        }
        let mut upper = self.best_bound(pool, node);
        let mut certificates: Vec<Arc<Rayleigh>> = Vec::new();
        let first = self.eval_relaxed(&alpha, None)?;
        let mut evals = 1;
        let mut steps = 0;
        let mut stalled = 0usize;
        let mut value = first.mu;
        let mut warm = first.y.clone();
        // The model certificate at the current point (the mixture when repeated).
        let mut latest = first.certificates.last().cloned();
        // The best (mixed) certificate and its bound at the current threshold.
        let mut best: Option<Rayleigh> = None;
        let bound_at = |r: &Rayleigh, thr: f64| -> f64 {
            self.ratio_bound(r, &self.filtered(node, thr))
                .upper
                .max(thr)
        };
        let absorb = |certs: &[Arc<Rayleigh>],
                      thr: f64,
                      best: &mut Option<Rayleigh>,
                      certificates: &mut Vec<Arc<Rayleigh>>| {
            for c in certs {
                certificates.push(c.clone());
                let f = |r: &Rayleigh| bound_at(r, thr);
                *best = Some(match best.take() {
                    None => c.normalized().unwrap_or_else(|| (**c).clone()),
                    Some(b) => best_mixture(&b, c, &f).0,
                });
            }
        };
        let seed: Vec<Arc<Rayleigh>> = pool
            .iter()
            .cloned()
            .chain(first.certificates.iter().cloned())
            .collect();
        absorb(&seed, value, &mut best, &mut certificates);
        certificates.drain(..pool.len().min(certificates.len()));
        while let Some(b) = &best {
            let work = self.filtered(node, value);
            let rb = self.ratio_bound(b, &work);
            upper = upper.min(rb.upper.max(value));
            if evals >= params.max_evals || upper - value <= params.tolerance * upper.abs() {
                break;
            }
            // The best model's maximizer; when it does not move (a flat model, e.g. a
            // clamped certificate), the latest eigenvector's model (a Frank–Wolfe step).
            let mut dir: Vec<f64> = {
                let target = project(&work, &rb.alpha);
                (0..n).map(|c| target[c] - alpha[c]).collect()
            };
            if dir.iter().all(|d| d.abs() < 1e-9) {
                if let Some(l) = &latest {
                    let t = project(&work, &self.ratio_bound(l, &work).alpha);
                    dir = (0..n).map(|c| t[c] - alpha[c]).collect();
                }
            }
            if dir.iter().all(|d| d.abs() < 1e-9) {
                break;
            }
            let mut accepted = false;
            let mut gamma = 1.0;
            for _ in 0..3 {
                if evals >= params.max_evals {
                    break;
                }
                let trial = project(
                    &work,
                    &(0..n)
                        .map(|c| alpha[c] + gamma * dir[c])
                        .collect::<Vec<_>>(),
                );
                let ev = self.eval_relaxed(&trial, Some(warm.as_ref()))?;
                evals += 1;
                let improved = ev.mu > value + 1e-10 * value.abs();
                if improved {
                    alpha = trial;
                    value = ev.mu;
                    warm = ev.y.clone();
                    latest = ev.certificates.last().cloned();
                    steps += 1;
                }
                absorb(&ev.certificates, value, &mut best, &mut certificates);
                if improved {
                    accepted = true;
                    break;
                }
                gamma *= 0.5;
            }
            if accepted {
                stalled = 0;
            } else {
                stalled += 1;
            }
            if !accepted && (evals >= params.max_evals || stalled >= params.max_stalled) {
                break;
            }
        }
        if let Some(b) = &best {
            upper = upper.min(bound_at(b, value));
            certificates.push(Arc::new(b.clone()));
        }
        Ok(NodeRelaxation {
            upper,
            value,
            alpha,
            evals,
            steps,
            certificates,
        })
    }

    /// The node of the subsets whose smallest curve is `c` (keep list empty), or of all
    /// feasible subsets (keep list given, `c` = None).
    pub fn face(&self, c: Option<usize>) -> Node {
        let n = self.curve_count();
        match c {
            None => {
                let free: Vec<usize> = (0..n).filter(|c| !self.keep.contains(c)).collect();
                Node::new(self, &self.keep, &free)
            }
            Some(c) => {
                let mut inc = self.keep.clone();
                if !inc.contains(&c) {
                    inc.push(c);
                }
                let free: Vec<usize> = (c + 1..n).collect();
                Node::new(self, &inc, &free)
            }
        }
    }

    /// The certificate from clamping: the low modes of `H_In` on the `In` curves' vertices that
    /// no free curve touches. No free curve's terms reach them, so their Rayleigh quotient is
    /// the same in every subset of the node (Cauchy interlacing).
    pub fn clamped_certificates(&self, node: &Node) -> Result<Vec<Arc<Rayleigh>>, StabilityError> {
        let model = self.analyzer.model();
        let n = self.curve_count();
        let weights: Vec<f64> = (0..n)
            .map(|c| {
                if node.status[c] == Status::In {
                    1.0
                } else {
                    0.0
                }
            })
            .collect();
        let mut clamp = vec![false; model.vertex_count()];
        let mut kept = vec![false; model.vertex_count()];
        for g in &self.groups {
            let inn = g.curves.iter().any(|&c| node.status[c] == Status::In);
            let free = g.curves.iter().any(|&c| node.status[c] == Status::Free);
            for &v in &g.vertices {
                clamp[v as usize] = inn && free;
                kept[v as usize] = inn && !free;
            }
        }
        if !clamp.iter().any(|&c| c) || !kept.iter().any(|&k| k) {
            return Ok(Vec::new());
        }
        self.clamped_modes(&weights, &clamp, &kept)
    }

    /// Certificates from the low modes of `Σ weights_c H_c` with the vertices of `clamp`
    /// held fixed, restricted to the vertices of `kept`.
    fn clamped_modes(
        &self,
        weights: &[f64],
        clamp: &[bool],
        kept: &[bool],
    ) -> Result<Vec<Arc<Rayleigh>>, StabilityError> {
        let model = self.analyzer.model();
        let pattern = model.pattern();
        let mut h = Vec::new();
        model.hessian_weighted(&self.locals, weights, &mut h);
        let loose = model.loose_diagonal();
        for j in 0..pattern.n {
            for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                let i = pattern.row_idx[k];
                if clamp[i / 3] || clamp[j / 3] {
                    h[k] = if i == j { loose } else { 0.0 };
                }
            }
        }
        self.relax_solves.fetch_add(1, Ordering::Relaxed);
        // Coordinates of clamped vertices and of vertices no weighted curve holds are decoupled.
        let held: Vec<bool> = model
            .vertex_curves()
            .iter()
            .enumerate()
            .map(|(v, cs)| !clamp[v] && cs.iter().any(|&c| weights[c as usize] != 0.0))
            .collect();
        let sp = restricted_spectrum(
            pattern,
            &h,
            self.analyzer.symbolic(),
            &coordinates(&held),
            None,
            &self.relax_eigen,
        )?;
        let mut x = sp.vectors.clone();
        zero_rows(&mut x, kept);
        Ok(self.certificates_of(x.as_ref(), &sp.values))
    }

    /// Certified bracket of the best `λ_fix` over all feasible subsets: the faces are bounded
    /// (their first curve's certificates, clamping, then the relaxation when those do not
    /// reach the best known value), in parallel, deterministically. Faces are relaxed highest
    /// cheap bound first and only while their cheap bound exceeds every relaxed face's bound:
    /// the others could not change the maximum (their rounded subsets are then not tried).
    /// `incumbents` are feasible subsets known beforehand (e.g. the greedy's answer).
    pub fn certify(
        &self,
        params: &CertifyParams,
        incumbents: &[Vec<usize>],
    ) -> Result<BoundReport, SimplifyError> {
        let n = self.curve_count();
        if self.length_of(&self.keep) > self.budget {
            return Err(SimplifyError::Params(format!(
                "no feasible subset: the keep list alone exceeds the budget {:.6}",
                self.budget
            )));
        }
        let solves0 = (self.eigen_solves(), self.relax_solves());
        let mut lower = (f64::NEG_INFINITY, Vec::new());
        let consider = |lower: &mut (f64, Vec<usize>), s: &[usize], l: f64| {
            let mut s = s.to_vec();
            s.sort_unstable();
            if l > lower.0 || (l == lower.0 && s < lower.1) {
                *lower = (l, s);
            }
        };
        for s in incumbents {
            if self.feasible(s) {
                let l = self.lambda_fix(s)?;
                consider(&mut lower, s, l);
            }
        }
        let roots: Vec<(Option<usize>, Node)> = if self.keep.is_empty() {
            (0..n)
                .filter(|&c| self.lengths[c] <= self.budget)
                .map(|c| (Some(c), self.face(Some(c))))
                .collect()
        } else {
            vec![(None, self.face(None))]
        };
        if roots.is_empty() {
            return Err(SimplifyError::Params(format!(
                "no feasible subset: every curve is longer than the budget {:.6}",
                self.budget
            )));
        }
        // Phase 1: each root's own structure and its cheap certificates.
        let phase1: Vec<Result<RootBound, StabilityError>> = roots
            .par_iter()
            .map(|(_, node)| {
                let inc = node.curves(Status::In);
                let comps = self.evaluate(&inc)?;
                let lam = comps.iter().map(|c| c.lambda).fold(f64::INFINITY, f64::min);
                let mut certs: Vec<Arc<Rayleigh>> = comps
                    .iter()
                    .flat_map(|c| c.certificates.iter().cloned())
                    .collect();
                certs.extend(self.clamped_certificates(node)?);
                let up = self.best_bound(&certs, node);
                Ok((lam, certs, up))
            })
            .collect();
        let mut phase1_ok = Vec::with_capacity(roots.len());
        for (r, (_, node)) in phase1.into_iter().zip(&roots) {
            let (lam, certs, up) = r?;
            consider(&mut lower, &node.curves(Status::In), lam);
            phase1_ok.push((certs, up));
        }
        let floor = lower.0;
        let tol = params.relax.tolerance;
        // Phase 2: relax the faces the cheap bounds leave above the best known value, highest
        // cheap bound first, in fixed batches. The bound is the maximum over the faces, and
        // relaxing a face can only lower its own: once a relaxed face's bound is at least every
        // remaining face's cheap bound, relaxing those cannot change the maximum, so they are
        // left with their cheap bounds (the same certified bound for less work). Which faces
        // are relaxed depends only on the values, never on threads.
        let relax_face = |i: usize| -> Result<FaceOutcome, StabilityError> {
            let ((curve, node), (certs, up)) = (&roots[i], &phase1_ok[i]);
            let mut fb = FaceBound {
                curve: *curve,
                upper: *up,
                relaxed: f64::NAN,
                evals: 0,
            };
            let r = self.relax_node(node, &params.relax, None, certs)?;
            fb.upper = fb.upper.min(r.upper);
            fb.relaxed = r.value;
            fb.evals = r.evals;
            let rounded = if params.rounding {
                round_relaxed(
                    &r.alpha,
                    &self.lengths,
                    self.budget,
                    &node.curves(Status::In),
                )
            } else {
                Vec::new()
            };
            Ok((fb, rounded))
        };
        let mut outcomes: Vec<Option<FaceOutcome>> = vec![None; roots.len()];
        let mut order: Vec<usize> = (0..roots.len())
            .filter(|&i| {
                let up = phase1_ok[i].1;
                up > floor + tol * floor.abs() && !roots[i].1.curves(Status::Free).is_empty()
            })
            .collect();
        order.sort_by(|&a, &b| phase1_ok[b].1.total_cmp(&phase1_ok[a].1).then(a.cmp(&b)));
        let mut relaxed_max = f64::NEG_INFINITY;
        for batch in order.chunks(FACE_BATCH) {
            let todo: Vec<usize> = batch
                .iter()
                .copied()
                .filter(|&i| phase1_ok[i].1 > relaxed_max)
                .collect();
            if todo.is_empty() {
                break;
            }
            let done: Vec<Result<FaceOutcome, StabilityError>> =
                todo.par_iter().map(|&i| relax_face(i)).collect();
            for (&i, r) in todo.iter().zip(done) {
                let outcome = r?;
                relaxed_max = relaxed_max.max(outcome.0.upper);
                outcomes[i] = Some(outcome);
            }
        }
        let phase2: Vec<Result<FaceOutcome, StabilityError>> = outcomes
            .into_iter()
            .enumerate()
            .map(|(i, o)| {
                Ok(o.unwrap_or_else(|| {
                    (
                        FaceBound {
                            curve: roots[i].0,
                            upper: phase1_ok[i].1,
                            relaxed: f64::NAN,
                            evals: 0,
                        },
                        Vec::new(),
                    )
                }))
            })
            .collect();
        let mut faces = Vec::with_capacity(roots.len());
        let mut candidates: Vec<Vec<usize>> = Vec::new();
        for r in phase2 {
            let (fb, rounded) = r?;
            faces.push(fb);
            candidates.extend(rounded);
        }
        candidates.sort();
        candidates.dedup();
        let values: Vec<Result<f64, StabilityError>> =
            candidates.par_iter().map(|s| self.lambda_fix(s)).collect();
        for (s, v) in candidates.iter().zip(values) {
            consider(&mut lower, s, v?);
        }
        let upper = faces
            .iter()
            .map(|f| f.upper)
            .fold(f64::NEG_INFINITY, f64::max);
        Ok(BoundReport {
            upper: upper.max(lower.0),
            lower: lower.0,
            lower_curves: lower.1,
            faces,
            relax_evals: self.relax_solves() - solves0.1,
            evaluations: self.eigen_solves() - solves0.0,
        })
    }
}

/// How far a subset (e.g. the greedy's answer) can be from the best, on the fixed-geometry
/// objective `λ_fix(· | full network)` of SPEC §5 (not `λ_eq`): written into `result.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Certificate {
    /// The objective certified: always `"lambda_fix"` (λ at the full network's equilibrium,
    /// without relaxing the subset).
    pub objective: String,
    /// The certified subset, ascending.
    pub curves: Vec<usize>,
    /// Its `λ_fix` at the full network's equilibrium.
    pub lambda_fix: f64,
    /// Certified: no feasible subset has `λ_fix` above this (the relaxation's bound).
    pub upper_bound: f64,
    /// `lambda_fix / upper_bound`: the subset reaches at least this fraction of the best
    /// `λ_fix` of any feasible subset (meaningful when both are positive; null otherwise).
    pub ratio: Option<f64>,
    /// The best `λ_fix` of a feasible subset met while bounding (the subset itself, the faces'
    /// first curves, the roundings of the relaxed solutions).
    pub best_found: f64,
    /// That subset.
    pub best_found_curves: Vec<usize>,
    /// Nodes of the exact branch and bound run to tighten the bound (0 when none was run).
    #[serde(default)]
    pub branch_and_bound_nodes: usize,
    /// True when that branch and bound finished: `best_found` is then the optimum of
    /// `λ_fix` (within 1e-7 relative) and `upper_bound` is that optimum plus the tolerance.
    #[serde(default)]
    pub proven_optimum: bool,
}

impl Certificate {
    /// One line for summaries.
    pub fn describe(&self) -> String {
        let ratio = self
            .ratio
            .map_or_else(|| "n/a".to_string(), |r| format!("{:.1}%", 100.0 * r));
        format!(
            "certificate (fixed geometry, λ_fix at the full network's equilibrium): λ_fix {:.6e}, \
             certified upper bound on any feasible subset {:.6e}, guaranteed ratio {ratio}; best \
             λ_fix found while bounding {:.6e} {:?}{}",
            self.lambda_fix,
            self.upper_bound,
            self.best_found,
            self.best_found_curves,
            if self.proven_optimum {
                " (proven optimal by branch and bound)"
            } else {
                ""
            }
        )
    }
}

impl FixedProblem<'_> {
    /// The [`Certificate`] of `curves` (a feasible subset): its `λ_fix`, and the certified
    /// upper bound of [`Self::certify`] with `curves` as incumbent.
    pub fn certificate(
        &self,
        curves: &[usize],
        params: &CertifyParams,
    ) -> Result<Certificate, SimplifyError> {
        let mut curves = curves.to_vec();
        curves.sort_unstable();
        curves.dedup();
        let lambda_fix = self.lambda_fix(&curves)?;
        let report = self.certify(params, std::slice::from_ref(&curves))?;
        let upper = report.upper.max(lambda_fix);
        let ratio = (lambda_fix > 0.0 && upper > 0.0).then(|| lambda_fix / upper);
        Ok(Certificate {
            objective: "lambda_fix".into(),
            curves,
            lambda_fix,
            upper_bound: upper,
            ratio,
            best_found: report.lower,
            best_found_curves: report.lower_curves,
            branch_and_bound_nodes: 0,
            proven_optimum: false,
        })
    }
}

/// Faces relaxed together (in parallel) before the next look at the bounds; fixed, so which
/// faces get relaxed never depends on the thread count.
const FACE_BATCH: usize = 2;

/// A root's `λ_fix`, its cheap certificates and the bound they give.
type RootBound = (f64, Vec<Arc<Rayleigh>>, f64);

/// A face's bound and the subsets rounded from its relaxed optimum.
type FaceOutcome = (FaceBound, Vec<Vec<usize>>);

/// Rounds a relaxed solution: curves by decreasing `α` (ties by id), each added while the
/// budget allows, starting from `base`; every distinct prefix is a candidate subset.
pub fn round_relaxed(
    alpha: &[f64],
    lengths: &[f64],
    budget: f64,
    base: &[usize],
) -> Vec<Vec<usize>> {
    let mut order: Vec<usize> = (0..alpha.len()).filter(|&c| alpha[c] > 1e-9).collect();
    order.sort_by(|&a, &b| alpha[b].total_cmp(&alpha[a]).then(a.cmp(&b)));
    let mut s: Vec<usize> = base.to_vec();
    let mut len: f64 = s.iter().map(|&c| lengths[c]).sum();
    let mut out = Vec::new();
    if !s.is_empty() && len <= budget {
        let mut t = s.clone();
        t.sort_unstable();
        out.push(t);
    }
    for c in order {
        if s.contains(&c) || len + lengths[c] > budget {
            continue;
        }
        s.push(c);
        len += lengths[c];
        let mut t = s.clone();
        t.sort_unstable();
        out.push(t);
    }
    out
}

/// Per-coordinate flags (three per vertex) from per-vertex flags.
fn coordinates(vertices: &[bool]) -> Vec<bool> {
    vertices.iter().flat_map(|&v| [v; 3]).collect()
}

/// Zeroes the rows of vertices with `mask[v] == false`.
fn zero_rows(x: &mut Mat<f64>, mask: &[bool]) {
    for (v, &on) in mask.iter().enumerate() {
        if !on {
            for j in 0..x.ncols() {
                for a in 0..3 {
                    x[(3 * v + a, j)] = 0.0;
                }
            }
        }
    }
}

/// The ratio `N(α)/D(α)` of one certificate on one node, over the node's relaxed polytope:
/// `α_In = 1`, `α_Out = 0`, free `α ∈ [0,1]` with `Σ L α ≤ cap`.
struct RatioLp {
    n0: f64,
    d0: f64,
    /// Free curve ids, ascending.
    free: Vec<usize>,
    a: Vec<f64>,
    d: Vec<f64>,
    len: Vec<f64>,
    /// Groups of shared vertices covered only by free curves (≥ 2 of them): free indices,
    /// weight.
    multi: Vec<(Vec<u32>, f64)>,
    cap: f64,
    /// Scale for tolerances.
    scale: f64,
}

/// A closure (set of free curves) of the Lagrangian at one `(ρ, μ)`.
struct Closure {
    set: Vec<bool>,
    /// `N − ρD` at the set (independent of `μ`).
    base: f64,
    /// Its length.
    len: f64,
    /// Upper bound of the Lagrangian at this `μ` (from the flow).
    upper: f64,
}

impl RatioLp {
    fn build(p: &FixedProblem<'_>, r: &Rayleigh, node: &Node) -> RatioLp {
        let n = p.curve_count();
        let mut fidx = vec![u32::MAX; n];
        let mut free = Vec::new();
        let mut n0 = 0.0;
        let mut in_len = 0.0;
        for c in 0..n {
            match node.status[c] {
                Status::In => {
                    n0 += r.a[c];
                    in_len += p.lengths[c];
                }
                Status::Free => {
                    fidx[c] = free.len() as u32;
                    free.push(c);
                }
                Status::Out => {}
            }
        }
        let a: Vec<f64> = free.iter().map(|&c| r.a[c]).collect();
        let len: Vec<f64> = free.iter().map(|&c| p.lengths[c]).collect();
        let mut d = vec![0.0; free.len()];
        let mut d0 = 0.0;
        let mut multi: BTreeMap<Vec<u32>, f64> = BTreeMap::new();
        for (gi, g) in p.groups.iter().enumerate() {
            let w = r.g[gi];
            if w == 0.0 {
                continue;
            }
            if g.curves.iter().any(|&c| node.status[c] == Status::In) {
                d0 += w;
                continue;
            }
            let fl: Vec<u32> = g
                .curves
                .iter()
                .filter(|&&c| node.status[c] == Status::Free)
                .map(|&c| fidx[c])
                .collect();
            match fl.len() {
                0 => {}
                1 => d[fl[0] as usize] += w,
                _ => *multi.entry(fl).or_insert(0.0) += w,
            }
        }
        let multi: Vec<(Vec<u32>, f64)> = multi.into_iter().collect();
        let scale = n0.abs()
            + d0
            + a.iter().map(|x| x.abs()).sum::<f64>()
            + d.iter().sum::<f64>()
            + multi.iter().map(|m| m.1).sum::<f64>();
        RatioLp {
            n0,
            d0,
            free,
            a,
            d,
            len,
            multi,
            cap: p.budget - in_len,
            scale,
        }
    }

    /// `(N(α), D(α))` at free weights `alpha`.
    fn value(&self, alpha: &[f64]) -> (f64, f64) {
        let mut num = self.n0;
        let mut den = self.d0;
        for i in 0..self.free.len() {
            num += self.a[i] * alpha[i];
            den += self.d[i] * alpha[i];
        }
        for (g, w) in &self.multi {
            den += w * g.iter().map(|&i| alpha[i as usize]).fold(0.0, f64::max);
        }
        (num, den)
    }

    /// Free curves that can be in a subset at all.
    fn usable(&self) -> bool {
        !self.free.is_empty() && self.cap > 0.0
    }

    /// The max-weight closure at `(ρ ≥ 0, μ ≥ 0)`.
    fn closure(&self, rho: f64, mu: f64) -> Closure {
        let f = self.free.len();
        let m = self.multi.len();
        let profit: Vec<f64> = (0..f)
            .map(|i| self.a[i] - rho * self.d[i] - mu * self.len[i])
            .collect();
        let mut g = Dinic::new(2 + f + m);
        let (s, t) = (0, 1);
        let mut pos_sum = 0.0;
        let mut cap_scale = 0.0;
        for (i, &p) in profit.iter().enumerate() {
            if p > 0.0 {
                g.add(s, 2 + i, p);
                pos_sum += p;
            } else if p < 0.0 {
                g.add(2 + i, t, -p);
            }
            cap_scale += p.abs();
        }
        for (j, (members, w)) in self.multi.iter().enumerate() {
            let c = rho * w;
            cap_scale += c;
            if c > 0.0 {
                g.add(2 + f + j, t, c);
            }
            for &i in members {
                g.add(2 + i as usize, 2 + f + j, f64::INFINITY);
            }
        }
        let eps = 1e-14 * cap_scale.max(f64::MIN_POSITIVE);
        let flow = g.max_flow(s, t, eps);
        let reach = g.reachable(s, eps);
        let set: Vec<bool> = (0..f).map(|i| reach[2 + i]).collect();
        let mut base = self.n0 - rho * self.d0;
        let mut len = 0.0;
        for i in 0..f {
            if set[i] {
                base += self.a[i] - rho * self.d[i];
                len += self.len[i];
            }
        }
        for (members, w) in &self.multi {
            if members.iter().any(|&i| set[i as usize]) {
                base -= rho * w;
            }
        }
        let line = base + mu * (self.cap - len);
        let upper = (self.n0 - rho * self.d0 + mu * self.cap + (pos_sum - flow)).max(line);
        Closure {
            set,
            base,
            len,
            upper,
        }
    }

    /// A fractional knapsack: max `Σ p_i α_i`, `Σ L_i α_i ≤ cap`, `α ∈ [0,1]`; value and `α`.
    fn knapsack(&self, p: &[f64]) -> (f64, Vec<f64>) {
        let f = self.free.len();
        let mut alpha = vec![0.0; f];
        let mut order: Vec<usize> = (0..f).filter(|&i| p[i] > 0.0).collect();
        order.sort_by(|&x, &y| {
            (p[y] / self.len[y].max(f64::MIN_POSITIVE))
                .total_cmp(&(p[x] / self.len[x].max(f64::MIN_POSITIVE)))
                .then(x.cmp(&y))
        });
        let mut left = self.cap.max(0.0);
        let mut value = 0.0;
        for i in order {
            let take = if self.len[i] <= 0.0 {
                1.0
            } else {
                (left / self.len[i]).min(1.0)
            };
            if take <= 0.0 {
                break;
            }
            alpha[i] = take;
            value += take * p[i];
            left -= take * self.len[i];
        }
        (value, alpha)
    }

    /// An upper bound of `F(ρ) = max_α N − ρD` and a (near) maximizer.
    fn f_upper(&self, rho: f64) -> (f64, Vec<f64>) {
        let f = self.free.len();
        if !self.usable() {
            return (self.n0 - rho * self.d0, vec![0.0; f]);
        }
        if rho < 0.0 {
            // −ρD is convex here; bound D by its largest value and maximize N alone.
            let d_all =
                self.d0 + self.d.iter().sum::<f64>() + self.multi.iter().map(|m| m.1).sum::<f64>();
            let (kv, alpha) = self.knapsack(&self.a);
            return (self.n0 - rho * d_all + kv, alpha);
        }
        let ind = |c: &Closure| -> Vec<f64> {
            c.set.iter().map(|&b| if b { 1.0 } else { 0.0 }).collect()
        };
        let c0 = self.closure(rho, 0.0);
        if c0.len <= self.cap {
            return (c0.upper, ind(&c0));
        }
        let mu_hi = (0..f)
            .filter(|&i| self.len[i] > 0.0)
            .map(|i| (self.a[i] - rho * self.d[i]) / self.len[i])
            .fold(0.0, f64::max)
            * (1.0 + 1e-9)
            + f64::MIN_POSITIVE;
        let chi = self.closure(rho, mu_hi);
        let mut best = c0.upper.min(chi.upper);
        let (mut lo, mut hi) = (c0, chi);
        if hi.len > self.cap {
            // Zero-length curves keep the closure over the cap; settle for the bound.
            return (best, ind(&hi));
        }
        let tol = 1e-12 * self.scale.max(f64::MIN_POSITIVE);
        for _ in 0..64 {
            let mu = ((lo.base - hi.base) / (lo.len - hi.len)).max(0.0);
            let cm = self.closure(rho, mu);
            best = best.min(cm.upper);
            let lo_line = lo.base + mu * (self.cap - lo.len);
            let cm_line = cm.base + mu * (self.cap - cm.len);
            if cm_line <= lo_line + tol {
                break;
            }
            if cm.len > self.cap {
                lo = cm;
            } else {
                hi = cm;
            }
        }
        let theta = ((self.cap - hi.len) / (lo.len - hi.len)).clamp(0.0, 1.0);
        let alpha: Vec<f64> = (0..f)
            .map(|i| {
                theta * f64::from(u8::from(lo.set[i]))
                    + (1.0 - theta) * f64::from(u8::from(hi.set[i]))
            })
            .collect();
        (best, alpha)
    }

    /// Dinkelbach: (certified upper bound of the ratio without margin, best ratio found, its
    /// free weights).
    fn solve(&self) -> (f64, f64, Vec<f64>) {
        let f = self.free.len();
        if !(self.d0 > 0.0) {
            return (f64::INFINITY, f64::NAN, vec![0.0; f]);
        }
        let mut rho = self.n0 / self.d0;
        let mut best_alpha = vec![0.0; f];
        let mut upper = f64::INFINITY;
        let tol = 1e-13 * (self.scale / self.d0);
        for _ in 0..40 {
            let (fu, alpha) = self.f_upper(rho);
            upper = upper.min(rho + fu.max(0.0) / self.d0);
            let (num, den) = self.value(&alpha);
            let r = if den > 0.0 {
                num / den
            } else {
                f64::NEG_INFINITY
            };
            if r > rho + tol {
                rho = r;
                best_alpha = alpha;
            } else {
                break;
            }
            if upper - rho <= tol {
                break;
            }
        }
        (upper.max(rho), rho, best_alpha)
    }

    /// True when the ratio is certainly at most `threshold` over the polytope.
    fn at_most(&self, threshold: f64) -> bool {
        if !(self.d0 > 0.0) {
            return false;
        }
        let rho = threshold;
        // Quick test: drop the shared-vertex costs (they only lower N − ρD when ρ ≥ 0).
        let quick = if rho >= 0.0 {
            let p: Vec<f64> = (0..self.free.len())
                .map(|i| self.a[i] - rho * self.d[i])
                .collect();
            let base = self.n0 - rho * self.d0;
            if !self.usable() {
                base
            } else {
                base + self.knapsack(&p).0
            }
        } else {
            f64::INFINITY
        };
        if quick <= 0.0 {
            return true;
        }
        self.f_upper(rho).0 <= 0.0
    }
}

/// Dinic's maximum flow on a small graph with `f64` capacities.
struct Dinic {
    adj: Vec<Vec<usize>>,
    to: Vec<usize>,
    cap: Vec<f64>,
}

impl Dinic {
    fn new(n: usize) -> Self {
        Dinic {
            adj: vec![Vec::new(); n],
            to: Vec::new(),
            cap: Vec::new(),
        }
    }

    fn add(&mut self, u: usize, v: usize, c: f64) {
        self.adj[u].push(self.to.len());
        self.to.push(v);
        self.cap.push(c);
        self.adj[v].push(self.to.len());
        self.to.push(u);
        self.cap.push(0.0);
    }

    fn levels(&self, s: usize, eps: f64) -> Vec<usize> {
        let mut level = vec![usize::MAX; self.adj.len()];
        level[s] = 0;
        let mut queue = std::collections::VecDeque::from([s]);
        while let Some(u) = queue.pop_front() {
            for &e in &self.adj[u] {
                let v = self.to[e];
                if self.cap[e] > eps && level[v] == usize::MAX {
                    level[v] = level[u] + 1;
                    queue.push_back(v);
                }
            }
        }
        level
    }

    fn push(
        &mut self,
        u: usize,
        t: usize,
        f: f64,
        level: &[usize],
        it: &mut [usize],
        eps: f64,
    ) -> f64 {
        if u == t {
            return f;
        }
        while it[u] < self.adj[u].len() {
            let e = self.adj[u][it[u]];
            let v = self.to[e];
            if self.cap[e] > eps && level[v] == level[u].wrapping_add(1) {
                let d = self.push(v, t, f.min(self.cap[e]), level, it, eps);
                if d > 0.0 {
                    self.cap[e] -= d;
                    self.cap[e ^ 1] += d;
                    return d;
                }
            }
            it[u] += 1;
        }
        0.0
    }

    fn max_flow(&mut self, s: usize, t: usize, eps: f64) -> f64 {
        let mut flow = 0.0;
        loop {
            let level = self.levels(s, eps);
            if level[t] == usize::MAX {
                return flow;
            }
            let mut it = vec![0; self.adj.len()];
            loop {
                let f = self.push(s, t, f64::INFINITY, &level, &mut it, eps);
                if !(f > eps) {
                    if f > 0.0 {
                        flow += f;
                    }
                    break;
                }
                flow += f;
            }
        }
    }

    fn reachable(&self, s: usize, eps: f64) -> Vec<bool> {
        let level = self.levels(s, eps);
        level.iter().map(|&l| l != usize::MAX).collect()
    }
}

/// The smallest eigenpairs of the principal submatrix on `keep` (the other coordinates
/// decoupled: [`EigenOptions::keep`]).
fn restricted_spectrum(
    pattern: &Pattern,
    h: &[f64],
    symbolic: &Arc<SymbolicFactor>,
    keep: &[bool],
    warm: Option<MatRef<'_, f64>>,
    params: &EigenParams,
) -> Result<Spectrum, EigenError> {
    let options = EigenOptions {
        start: warm.map_or(Start::Random, Start::Vectors),
        keep: Some(keep),
        ..Default::default()
    };
    let found = crate::solve::smallest_eigenpairs(symbolic, pattern, h, params, options)?;
    Ok(found.expect("a shift below zero always factors").spectrum)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force of `max_T Σ_{i∈T} p_i − Σ_G c_G [G ∩ T ≠ ∅]`.
    fn brute_closure(p: &[f64], groups: &[(Vec<u32>, f64)]) -> f64 {
        let f = p.len();
        let mut best = f64::NEG_INFINITY;
        for mask in 0u32..(1 << f) {
            let mut v = 0.0;
            for i in 0..f {
                if mask & (1 << i) != 0 {
                    v += p[i];
                }
            }
            for (g, c) in groups {
                if g.iter().any(|&i| mask & (1 << i) != 0) {
                    v -= c;
                }
            }
            best = best.max(v);
        }
        best
    }

    fn lp(
        a: Vec<f64>,
        d: Vec<f64>,
        len: Vec<f64>,
        multi: Vec<(Vec<u32>, f64)>,
        cap: f64,
    ) -> RatioLp {
        let scale = 1.0;
        RatioLp {
            n0: 0.3,
            d0: 1.0,
            free: (0..a.len()).collect(),
            a,
            d,
            len,
            multi,
            cap,
            scale,
        }
    }

    #[test]
    fn closures_are_optimal() {
        let mut rng = crate::rng::SplitMix64::new(7);
        for _ in 0..200 {
            let f = 1 + rng.below(6) as usize;
            let a: Vec<f64> = (0..f).map(|_| rng.next_f64() * 2.0 - 0.5).collect();
            let d: Vec<f64> = (0..f).map(|_| rng.next_f64()).collect();
            let len: Vec<f64> = (0..f).map(|_| 0.2 + rng.next_f64()).collect();
            let mut multi = Vec::new();
            for _ in 0..rng.below(5) {
                let mut g: Vec<u32> = (0..f as u32).filter(|_| rng.next_u64() & 1 == 1).collect();
                if g.len() < 2 {
                    continue;
                }
                g.sort_unstable();
                multi.push((g, rng.next_f64()));
            }
            let l = lp(a.clone(), d.clone(), len.clone(), multi.clone(), 1.0);
            let rho = rng.next_f64();
            let mu = rng.next_f64();
            let c = l.closure(rho, mu);
            let p: Vec<f64> = (0..f).map(|i| a[i] - rho * d[i] - mu * len[i]).collect();
            let g: Vec<(Vec<u32>, f64)> = multi.iter().map(|(g, w)| (g.clone(), rho * w)).collect();
            let brute = brute_closure(&p, &g);
            let found = c.base - l.n0 + rho * l.d0 - mu * c.len;
            assert!((found - brute).abs() < 1e-12, "{found} vs {brute}");
            let upper = c.upper - (l.n0 - rho * l.d0 + mu * l.cap);
            assert!(upper >= brute - 1e-12 && upper <= brute + 1e-9);
        }
    }

    /// The ratio bound against a fine grid of the relaxed polytope (2–3 free curves) and the
    /// binary points.
    #[test]
    fn ratio_bound_dominates_the_polytope() {
        let mut rng = crate::rng::SplitMix64::new(11);
        for _ in 0..100 {
            let f = 2 + rng.below(2) as usize;
            let a: Vec<f64> = (0..f).map(|_| rng.next_f64() * 2.0 - 0.3).collect();
            let d: Vec<f64> = (0..f).map(|_| rng.next_f64()).collect();
            let len: Vec<f64> = (0..f).map(|_| 0.2 + rng.next_f64()).collect();
            let multi = vec![((0..f as u32).collect::<Vec<_>>(), rng.next_f64())];
            let cap = 0.3 + rng.next_f64();
            let l = lp(a, d, len, multi, cap);
            let (upper, value, alpha) = l.solve();
            let (num, den) = l.value(&alpha);
            assert!((num / den - value).abs() <= 1e-12 * value.abs().max(1.0));
            assert!(upper >= value);
            let steps = 40;
            let mut best = f64::NEG_INFINITY;
            let mut x = vec![0usize; f];
            loop {
                let al: Vec<f64> = x.iter().map(|&k| k as f64 / steps as f64).collect();
                let used: f64 = al.iter().zip(&l.len).map(|(a, b)| a * b).sum();
                if used <= cap {
                    let (nn, dd) = l.value(&al);
                    best = best.max(nn / dd);
                }
                let mut i = 0;
                while i < f {
                    x[i] += 1;
                    if x[i] <= steps {
                        break;
                    }
                    x[i] = 0;
                    i += 1;
                }
                if i == f {
                    break;
                }
            }
            assert!(upper >= best - 1e-12, "{upper} < grid {best}");
            // The exact optimum is within the grid's resolution of the best grid point.
            assert!(upper <= best + 0.2, "{upper} far above grid {best}");
        }
    }

    #[test]
    fn rounding_prefixes() {
        let alpha = [0.2, 1.0, 0.0, 0.7];
        let lengths = [1.0, 2.0, 1.0, 2.5];
        let r = round_relaxed(&alpha, &lengths, 3.5, &[]);
        assert_eq!(r, vec![vec![1], vec![0, 1]]);
        let r = round_relaxed(&alpha, &lengths, 10.0, &[2]);
        assert_eq!(
            r,
            vec![vec![2], vec![1, 2], vec![1, 2, 3], vec![0, 1, 2, 3]]
        );
    }
}
