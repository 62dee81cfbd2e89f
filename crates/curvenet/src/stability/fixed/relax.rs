//! The relaxation of one node: maximizing `μ(α)` over the node's relaxed polytope by a
//! Frank–Wolfe method on the certificates' upper model (see the module documentation of
//! [`super`]).

use super::rayleigh::best_mixture;
use super::{FixedProblem, Node, Rayleigh, StabilityError, Status, coordinates};
use crate::cancel::Cancel;
use crate::stability::numerics::restricted as smallest_eigenpairs_restricted;
use faer::{Mat, MatRef};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use std::sync::atomic::Ordering;

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

/// One eigen solve of the relaxation at `α`.
struct RelaxedEval {
    mu: f64,
    /// Eigenvectors of the scaled matrix (the next warm start).
    y: Mat<f64>,
    /// Certificates: the lowest modes alone, and the cluster mixture when repeated.
    certificates: Vec<Arc<Rayleigh>>,
}

impl FixedProblem<'_> {
    /// One eigen solve of the relaxation at `alpha` (per curve): the smallest eigenpairs of
    /// `P^{-1/2} H(α) P^{-1/2}`, and the certificates of its modes scaled back.
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
        let sp = smallest_eigenpairs_restricted(
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
    /// (default: the node's `In` curves), with the certificates of `pool` counted too; stops
    /// with [`StabilityError::Cancelled`] between eigen solves once `cancel` is set.
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
        cancel: &Cancel,
    ) -> Result<NodeRelaxation, StabilityError> {
        let n = self.curve_count();
        let alpha = project(node, start.unwrap_or(&vec![0.0; n]));
        if !alpha.iter().any(|&a| a > 0.0) {
            return Err(StabilityError::Empty);
        }
        cancel.check()?;
        let upper = self.best_bound(pool, node);
        let first = self.eval_relaxed(&alpha, None)?;
        let mut fw = FrankWolfe {
            problem: self,
            node,
            params,
            alpha,
            value: first.mu,
            upper,
            warm: first.y.clone(),
            latest: first.certificates.last().cloned(),
            best: None,
            certificates: Vec::new(),
            evals: 1,
            steps: 0,
        };
        let seed: Vec<Arc<Rayleigh>> = pool
            .iter()
            .cloned()
            .chain(first.certificates.iter().cloned())
            .collect();
        fw.absorb(&seed);
        fw.certificates
            .drain(..pool.len().min(fw.certificates.len()));
        let mut stalled = 0usize;
        while let Some(dir) = fw.direction() {
            cancel.check()?;
            let accepted = fw.line_search(&dir, cancel)?;
            stalled = if accepted { 0 } else { stalled + 1 };
            if !accepted && (fw.evals >= params.max_evals || stalled >= params.max_stalled) {
                break;
            }
        }
        Ok(fw.finish())
    }
}

/// `a` projected on `work`'s polytope box: `In` curves at 1, `Out` at 0, free ones clamped to
/// `[0, 1]` (tiny values to 0).
fn project(work: &Node, a: &[f64]) -> Vec<f64> {
    (0..work.status.len())
        .map(|c| match work.status[c] {
            Status::In => 1.0,
            Status::Out => 0.0,
            Status::Free => {
                let x = a[c].clamp(0.0, 1.0);
                if x < 1e-12 { 0.0 } else { x }
            }
        })
        .collect()
}

/// The state of [`FixedProblem::relax_node`].
struct FrankWolfe<'p, 'a> {
    problem: &'p FixedProblem<'a>,
    node: &'p Node,
    params: &'p RelaxParams,
    /// The current point and its value `μ(α)`.
    alpha: Vec<f64>,
    value: f64,
    /// The best certified bound so far.
    upper: f64,
    /// The current point's eigenvectors (the next solve's start).
    warm: Mat<f64>,
    /// The model certificate at the current point (the mixture when repeated).
    latest: Option<Arc<Rayleigh>>,
    /// The best (mixed) certificate, normalized.
    best: Option<Rayleigh>,
    /// Every certificate produced.
    certificates: Vec<Arc<Rayleigh>>,
    evals: usize,
    steps: usize,
}

impl FrankWolfe<'_, '_> {
    /// The bound of certificate `r` at threshold `thr` (the free curves with `σ ≤ thr` left
    /// out).
    fn bound_at(&self, r: &Rayleigh, thr: f64) -> f64 {
        let p = self.problem;
        p.ratio_bound(r, &p.filtered(self.node, thr)).upper.max(thr)
    }

    /// Records `certs` and mixes each into the best certificate at the current value.
    fn absorb(&mut self, certs: &[Arc<Rayleigh>]) {
        let thr = self.value;
        for c in certs {
            self.certificates.push(c.clone());
            let f = |r: &Rayleigh| self.bound_at(r, thr);
            let mixed = match &self.best {
                None => c.normalized().unwrap_or_else(|| (**c).clone()),
                Some(b) => best_mixture(b, c, &f).0,
            };
            self.best = Some(mixed);
        }
    }

    /// Tightens the bound with the best model and returns the next direction: toward the
    /// model's maximizer, or (a flat model, e.g. a clamped certificate) the latest
    /// eigenvector's; `None` once converged, out of eigen solves or without a direction.
    fn direction(&mut self) -> Option<Vec<f64>> {
        let p = self.problem;
        let b = self.best.as_ref()?;
        let work = p.filtered(self.node, self.value);
        let rb = p.ratio_bound(b, &work);
        self.upper = self.upper.min(rb.upper.max(self.value));
        let gap = self.upper - self.value;
        if self.evals >= self.params.max_evals || gap <= self.params.tolerance * self.upper.abs() {
            return None;
        }
        let toward = |target: Vec<f64>| -> Vec<f64> {
            (0..target.len())
                .map(|c| target[c] - self.alpha[c])
                .collect()
        };
        let flat = |d: &[f64]| d.iter().all(|x| x.abs() < 1e-9);
        let mut dir = toward(project(&work, &rb.alpha));
        if flat(&dir)
            && let Some(l) = &self.latest
        {
            dir = toward(project(&work, &p.ratio_bound(l, &work).alpha));
        }
        (!flat(&dir)).then_some(dir)
    }

    /// Tries the steps `γ = 1, ½, ¼` along `dir`; true when one improved `μ` (and was taken).
    fn line_search(&mut self, dir: &[f64], cancel: &Cancel) -> Result<bool, StabilityError> {
        let work = self.problem.filtered(self.node, self.value);
        let mut gamma = 1.0;
        for _ in 0..3 {
            if self.evals >= self.params.max_evals {
                break;
            }
            cancel.check()?;
            let step: Vec<f64> = (0..dir.len())
                .map(|c| self.alpha[c] + gamma * dir[c])
                .collect();
            let trial = project(&work, &step);
            let ev = self
                .problem
                .eval_relaxed(&trial, Some(self.warm.as_ref()))?;
            self.evals += 1;
            let improved = ev.mu > self.value + 1e-10 * self.value.abs();
            if improved {
                self.alpha = trial;
                self.value = ev.mu;
                self.warm = ev.y.clone();
                self.latest = ev.certificates.last().cloned();
                self.steps += 1;
            }
            self.absorb(&ev.certificates);
            if improved {
                return Ok(true);
            }
            gamma *= 0.5;
        }
        Ok(false)
    }

    /// The outcome: the best certificate's final bound joins the certificates.
    fn finish(mut self) -> NodeRelaxation {
        if let Some(b) = self.best.take() {
            self.upper = self.upper.min(self.bound_at(&b, self.value));
            self.certificates.push(Arc::new(b));
        }
        NodeRelaxation {
            upper: self.upper,
            value: self.value,
            alpha: self.alpha,
            evals: self.evals,
            steps: self.steps,
            certificates: self.certificates,
        }
    }
}
