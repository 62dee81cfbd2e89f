//! Nodes of subsets (curves in, out, free) and their certified bounds.

use super::ratio_lp::RatioLp;
use super::{FixedProblem, Rayleigh, StabilityError, coordinates, zero_rows};
use crate::stability::numerics::restricted as smallest_eigenpairs_restricted;
use std::sync::Arc;
use std::sync::atomic::Ordering;

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

impl FixedProblem<'_> {
    /// The smallest `σ_c` over the `In` curves of `node`.
    pub(super) fn sigma_in(&self, node: &Node) -> f64 {
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

    /// The smallest bound over certificates.
    pub fn best_bound(&self, certs: &[Arc<Rayleigh>], node: &Node) -> f64 {
        certs
            .iter()
            .map(|c| self.node_bound(c, node))
            .fold(self.sigma_in(node), f64::min)
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
    pub(super) fn clamped_modes(
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
        let sp = smallest_eigenpairs_restricted(
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
}
