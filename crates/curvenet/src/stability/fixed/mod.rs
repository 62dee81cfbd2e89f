//! The fixed-geometry problem: `λ_fix` of any set of curves at the full network's
//! equilibrium, and certified upper bounds on the best `λ_fix` of any feasible subset — the
//! continuous relaxation of the mixed-integer SDP (`docs/model.md`, *Relaxation and
//! certificate*), solved without an SDP solver. The searches over it (the certificate's
//! faces, the exact branch and bound) are in `simplify`.
//!
//! # The objective
//!
//! Everything here is about `λ_fix(S) = λ_fix(S | A)` with `A` the *full* network: its
//! equilibrium `u` is computed once, the local Hessians of every term once, and `H_S` is the
//! sum of the Hessians `H_c` of the curves `c ∈ S` (all their terms: stretching, bending,
//! anchors) over `V(S)`, the vertices of `S`'s curves. The problem is
//!
//! ```text
//! λ* = max { λ_min(H_S) : S ⊇ keep, S ≠ ∅, Σ_{c∈S} L_c ≤ V }.
//! ```
//!
//! # The relaxation
//!
//! The mixed-integer formulation writes the structure of `S` with per-curve factors
//! `α_c ∈ {0,1}` and regularizers `ρ` on the loose pieces. Here every term of curve `c` is
//! scaled by `α_c` (the formulation keeps the
//! terms not touching a joint, `H0_c`, unscaled; with binary `α` they live on `c`'s loose
//! pieces only, so both write the same structure, and scaling them too makes the relaxation
//! tighter and frees `ρ` from having to beat their negative eigenvalues), and the regularizer
//! is per vertex, `β_v ≤ 1 − α_c` for every curve `c` through `v` (for a joint of two curves this
//! is the formulation's `β_ij`; with three or more it forbids regularizing a vertex a kept curve
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
//! threshold is `5ε‖H‖₁`); every bound adds `128·ε·‖H‖₁`.
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
//! the exact branch and bound (`simplify::exact`).
//!
//! # The optimizer
//!
//! [`FixedProblem::relax_node`] is a Frank–Wolfe method for the quasi-concave `μ`: at `α_t`, the
//! eigenvector `x_t` gives the upper model `N_x(α)/D_x(α) ≥ μ(α)` (tight at `α_t`); its
//! maximizer over the node's polytope (the linear step, solved exactly as above) is the
//! Frank–Wolfe vertex `s_t`; a backtracking search on `μ(α_t + γ(s_t − α_t))` (quasi-concave,
//! so unimodal along the segment) takes the step. Every eigen solve yields a certificate; the
//! best is kept; the run stops on a relative gap, a cap on eigen solves, or a stalled step.

mod maxflow;
mod node;
mod ratio_lp;
mod rayleigh;
mod relax;

pub use node::{Node, RatioBound, Status};
pub use rayleigh::Rayleigh;
pub use relax::{NodeRelaxation, RelaxParams};

use super::presets::Preset;
use super::{Analyzer, Budget, StabilityError};
use crate::rod::ActiveSet;
use crate::rod::model::{LocalHessians, Terms};
use crate::solve::eigen::EigenParams;
use crate::stability::numerics::restricted as smallest_eigenpairs_restricted;
use faer::Mat;
use rayon::prelude::*;
use std::collections::{BTreeMap, HashMap};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Vertices lying on exactly the same curves.
#[derive(Clone, Debug)]
struct VertexGroup {
    curves: Vec<usize>,
    vertices: Vec<u32>,
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

/// The `λ_fix` problem of one network at the full network's equilibrium: evaluations with a
/// cache of connected components, certificates, relaxations and bounds.
pub struct FixedProblem<'a> {
    analyzer: &'a Analyzer,
    displacement: Vec<f64>,
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
    ) -> Result<Self, StabilityError> {
        let mut u = vec![0.0; analyzer.model().dofs()];
        analyzer.relax(&analyzer.all(), &mut u);
        Self::with_displacement(analyzer, u, budget, keep)
    }

    /// The problem at given displacements (the full network's equilibrium).
    pub fn with_displacement(
        analyzer: &'a Analyzer,
        displacement: Vec<f64>,
        budget: Budget,
        keep: &[usize],
    ) -> Result<Self, StabilityError> {
        budget.validate().map_err(StabilityError::Params)?;
        if analyzer.objective() != super::Objective::Lambda {
            return Err(StabilityError::Params(
                format!(
                    "the certificate and the exact search bound λ_fix, the paper's objective at \
                 the full network's equilibrium: their relaxation does not model the {} \
                 objective's mass metric, which changes with the set of curves (use the \
                 objective lambda for them)",
                    analyzer.objective().name()
                )
                .into(),
            ));
        }
        let model = analyzer.model();
        let n = analyzer.curve_count();
        if n == 0 {
            return Err(StabilityError::Params("the network has no curves".into()));
        }
        if displacement.len() != model.dofs() {
            return Err(StabilityError::Params(
                "displacements do not match the network".into(),
            ));
        }
        if let Some(&k) = keep.iter().find(|&&k| k >= n) {
            return Err(StabilityError::Params(
                format!("keep list names curve {k}, but there are {n} curves").into(),
            ));
        }
        let mut keep = keep.to_vec();
        keep.sort_unstable();
        keep.dedup();
        let lengths = analyzer.lengths();
        let budget = budget.length(lengths.iter().sum());
        let locals = model.local_hessians(&displacement, Terms::All);
        let groups = vertex_groups(analyzer);
        let full = model.assemble(&displacement, &analyzer.all(), true).hess;
        let norm1 = model.pattern().sym_norm1(&full);
        let base = &analyzer.params().eigen;
        let mut p = FixedProblem {
            analyzer,
            displacement,
            locals,
            lengths,
            budget,
            keep,
            groups,
            eval_eigen: Preset::Fixed.params(base),
            relax_eigen: Preset::Relaxation.params(base),
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
        let den = r.mass();
        Ok(if den > 0.0 {
            r.weight(c) / den + self.margin
        } else {
            f64::INFINITY
        })
    }

    /// `σ_c` of every curve (see [`Self::span_bound`]).
    pub fn span_bounds(&self) -> &[f64] {
        &self.sigma
    }

    /// The analyzer.
    pub fn analyzer(&self) -> &'a Analyzer {
        self.analyzer
    }

    /// The equilibrium all `λ_fix` are taken at.
    pub fn displacement(&self) -> &[f64] {
        &self.displacement
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

    /// Eigen solves of relaxations and clamped certificates so far.
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

    fn compute_component(&self, part: &[usize]) -> Result<Component, StabilityError> {
        let model = self.analyzer.model();
        let active = ActiveSet::from_curves(self.curve_count(), part);
        let mut h = Vec::new();
        model.hessian_from_locals(&self.locals, &active, &mut h);
        self.eigen_solves.fetch_add(1, Ordering::Relaxed);
        let mask = model.vertex_mask(&active);
        let sp = smallest_eigenpairs_restricted(
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
}

/// The network's vertices grouped by the set of curves through them.
fn vertex_groups(analyzer: &Analyzer) -> Vec<VertexGroup> {
    let mut index: BTreeMap<Vec<usize>, usize> = BTreeMap::new();
    let mut groups: Vec<VertexGroup> = Vec::new();
    for (v, cs) in analyzer.model().vertex_curves().iter().enumerate() {
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
    groups
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
