//! The certificate: how far a subset (e.g. the greedy's answer) can be from the best, on the
//! fixed-geometry objective `λ_fix(· | full network)` (`docs/model.md`, *Relaxation and
//! certificate*).
//!
//! Every feasible subset has a first curve (with the keep list empty), so the subsets are
//! partitioned into *faces*, one per first curve (or a single root holding the keep list).
//! Each face is bounded by its own structure's certificates and clamping (cheap: two eigen
//! solves), then, while its cheap bound could still be the maximum, by the relaxation of the
//! face ([`FixedProblem::relax_node`]); the certified bound is the largest face bound. The
//! relaxed solutions are rounded to subsets, which only improve the best subset found. A
//! branch and bound ([`super::exact`]) can then tighten the bound ([`tighten_certificate`]).
//!
//! Cancelled ([`Cancel`]) once every face has its cheap bound, the certificate is still
//! valid (looser: the faces not relaxed keep their cheap bounds) and says so
//! ([`Certificate::cancelled`]); cancelled before, it is an error.

use super::SimplifyError;
use super::exact::{Best, ExactParams, ExactStatus, exact};
use crate::cancel::Cancel;
use crate::constraints::Constraints;
use crate::stability::StabilityError;
use crate::stability::fixed::{FixedProblem, Node, Rayleigh, RelaxParams, Status};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Parameters of [`certify`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CertifyParams {
    /// Relaxation of each face (whose solution is rounded to subsets, evaluated for better
    /// lower bounds).
    pub relax: RelaxParams,
}

impl Default for CertifyParams {
    /// Up to 150 eigen solves per relaxed face, stopping at a 1% relative gap between the
    /// relaxed value and its bound.
    fn default() -> Self {
        CertifyParams {
            relax: RelaxParams {
                max_evals: 150,
                tolerance: 1e-2,
                max_stalled: 8,
            },
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
    /// True when the run was cancelled after every face had its cheap bound: `upper` is
    /// certified but looser than a finished run's.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub cancelled: bool,
}

/// How far a subset (e.g. the greedy's answer) can be from the best, on the fixed-geometry
/// objective `λ_fix(· | full network)` (not `λ_eq`): written into `result.json`.
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
    /// True when the run was cancelled part way: the bound is certified, looser than a
    /// finished run's.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub cancelled: bool,
    /// True when the branch and bound honoured the run's design constraints: its bound and
    /// its best subset are then over the networks that meet them (the relaxation's bound,
    /// over every network within the budget, bounds those too).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub constrained: bool,
}

impl Certificate {
    /// What the certificate guarantees, in plain words, for summaries: the bound no network
    /// within the budget can exceed (on `λ_fix`, the stability at the full network's
    /// equilibrium shape) and the share of it the certified network reaches.
    pub fn describe(&self) -> String {
        let note = if self.proven_optimum {
            " (the bound is the proven optimum: branch and bound finished)"
        } else if self.cancelled {
            " (cancelled part way: a looser bound)"
        } else {
            ""
        };
        let reach = match self.ratio {
            Some(r) => format!(
                "the certified network {:?} has λ_fix {:.6e}, {:.1}% of that bound (within \
                 {:.1}% of it)",
                self.curves,
                self.lambda_fix,
                100.0 * r,
                100.0 * (1.0 - r)
            ),
            None => format!(
                "the certified network {:?} has λ_fix {:.6e}: no guarantee",
                self.curves, self.lambda_fix
            ),
        };
        let within = if self.constrained {
            "the budget and the design constraints"
        } else {
            "the budget"
        };
        format!(
            "certificate: no network within {within} can exceed λ_fix = {:.6e} (stability \
             at the full network's equilibrium shape, not relaxed){note}; {reach}; the best \
             λ_fix met while bounding is {:.6e} {:?}",
            self.upper_bound, self.best_found, self.best_found_curves,
        )
    }
}

/// The [`Certificate`] of `curves` (a feasible subset): its `λ_fix`, and the certified upper
/// bound of [`certify`] with `curves` as incumbent.
pub fn certificate(
    problem: &FixedProblem<'_>,
    curves: &[usize],
    params: &CertifyParams,
    cancel: &Cancel,
) -> Result<Certificate, SimplifyError> {
    let mut curves = curves.to_vec();
    curves.sort_unstable();
    curves.dedup();
    let lambda_fix = problem.lambda_fix(&curves)?;
    let report = certify(problem, params, std::slice::from_ref(&curves), cancel)?;
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
        cancelled: report.cancelled,
        constrained: false,
    })
}

/// Tightens a [`Certificate`] with at most `max_nodes` nodes of the exact branch and bound
/// (deterministic: no time limit), seeded with the certified subset and the best one found:
/// the bound becomes the smaller of the relaxation's and the search's (the largest bound of
/// the nodes left open, or the optimum when the search finished), and the best subset found
/// is updated. Cancelled, it keeps what the search had proved.
///
/// Under design `constraints` (bound to the problem's budget and keep list) the branch and
/// bound honours them, as [`exact`] does: only networks that meet them become its incumbents,
/// so its bound and its best subset are over those networks (a valid bound either way: the
/// relaxation's bound covers every network within the budget, the constrained ones among
/// them). The best subset the relaxation met is then replaced by the search's when it breaks
/// a constraint.
pub fn tighten_certificate(
    problem: &FixedProblem<'_>,
    certificate: &mut Certificate,
    constraints: Option<&Constraints>,
    max_nodes: usize,
    cancel: &Cancel,
) -> Result<(), SimplifyError> {
    if max_nodes == 0 || certificate.cancelled {
        return Ok(());
    }
    let constraints = constraints.filter(|c| c.is_active());
    let params = ExactParams {
        time_limit: None,
        max_nodes,
        ..ExactParams::default()
    };
    let seeds = [
        certificate.curves.clone(),
        certificate.best_found_curves.clone(),
    ];
    let o = exact(problem, &params, constraints, &seeds, cancel)?;
    certificate.branch_and_bound_nodes = o.info.nodes;
    certificate.cancelled = o.status == ExactStatus::Cancelled;
    if let Some(c) = constraints {
        certificate.constrained = true;
        if c.check(&certificate.best_found_curves).is_err() && !o.curves.is_empty() {
            certificate.best_found = o.lambda_fix;
            certificate.best_found_curves = o.curves.clone();
        }
    }
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

/// Faces relaxed together (in parallel) before the next look at the bounds; fixed, so which
/// faces get relaxed never depends on the thread count.
const FACE_BATCH: usize = 2;

/// A face: its first curve (None for the root holding the keep list) and its node.
type Face = (Option<usize>, Node);

/// A face's cheap certificates and the bound they give.
type Cheap = (Vec<Arc<Rayleigh>>, f64);

/// A face's bound and the subsets rounded from its relaxed optimum.
type FaceOutcome = (FaceBound, Vec<Vec<usize>>);

/// Certified bracket of the best `λ_fix` over all feasible subsets: the faces are bounded
/// (their first curve's certificates, clamping, then the relaxation when those do not reach
/// the best known value), in parallel, deterministically. Faces are relaxed highest cheap
/// bound first and only while their cheap bound exceeds every relaxed face's bound: the
/// others could not change the maximum (their rounded subsets are then not tried).
/// `incumbents` are feasible subsets known beforehand (e.g. the greedy's answer).
pub fn certify(
    problem: &FixedProblem<'_>,
    params: &CertifyParams,
    incumbents: &[Vec<usize>],
    cancel: &Cancel,
) -> Result<BoundReport, SimplifyError> {
    let p = problem;
    if p.length_of(p.keep()) > p.budget() {
        return Err(SimplifyError::Params(
            format!(
                "no feasible subset: the keep list alone exceeds the budget {:.6}",
                p.budget()
            )
            .into(),
        ));
    }
    let solves0 = (p.eigen_solves(), p.relax_solves());
    let mut lower = Best::default();
    for s in incumbents {
        if p.feasible(s) {
            lower.consider(s, p.lambda_fix(s)?);
        }
    }
    let faces = faces(p)?;
    let cheap = cheap_bounds(p, &faces, &mut lower, cancel)?;
    let (outcomes, cancelled) = relax_faces(p, params, &faces, &cheap, lower.0, cancel)?;
    let mut bounds = Vec::with_capacity(faces.len());
    let mut candidates: Vec<Vec<usize>> = Vec::new();
    for (fb, rounded) in outcomes {
        bounds.push(fb);
        candidates.extend(rounded);
    }
    if !cancelled {
        candidates.sort();
        candidates.dedup();
        let values: Vec<Result<f64, StabilityError>> =
            candidates.par_iter().map(|s| p.lambda_fix(s)).collect();
        for (s, v) in candidates.iter().zip(values) {
            lower.consider(s, v?);
        }
    }
    let upper = bounds
        .iter()
        .map(|f| f.upper)
        .fold(f64::NEG_INFINITY, f64::max);
    Ok(BoundReport {
        upper: upper.max(lower.0),
        lower: lower.0,
        lower_curves: lower.1,
        faces: bounds,
        relax_evals: p.relax_solves() - solves0.1,
        evaluations: p.eigen_solves() - solves0.0,
        cancelled,
    })
}

/// The faces: one per curve that fits the budget (the subsets whose first curve it is) with
/// the keep list empty, else the one root holding the keep list.
fn faces(p: &FixedProblem<'_>) -> Result<Vec<Face>, SimplifyError> {
    let faces: Vec<Face> = if p.keep().is_empty() {
        (0..p.curve_count())
            .filter(|&c| p.lengths()[c] <= p.budget())
            .map(|c| (Some(c), p.face(Some(c))))
            .collect()
    } else {
        vec![(None, p.face(None))]
    };
    if faces.is_empty() {
        return Err(SimplifyError::Params(
            format!(
                "no feasible subset: every curve is longer than the budget {:.6}",
                p.budget()
            )
            .into(),
        ));
    }
    Ok(faces)
}

/// Each face's own structure (a feasible subset: `lower` considers it) and its cheap
/// certificates: the structure's low modes and the clamped ones.
fn cheap_bounds(
    p: &FixedProblem<'_>,
    faces: &[Face],
    lower: &mut Best,
    cancel: &Cancel,
) -> Result<Vec<Cheap>, SimplifyError> {
    let bounded: Vec<Result<(f64, Cheap), StabilityError>> = faces
        .par_iter()
        .map(|(_, node)| {
            cancel.check()?;
            let inc = node.curves(Status::In);
            let comps = p.evaluate(&inc)?;
            let lam = comps.iter().map(|c| c.lambda).fold(f64::INFINITY, f64::min);
            let mut certs: Vec<Arc<Rayleigh>> = comps
                .iter()
                .flat_map(|c| c.certificates.iter().cloned())
                .collect();
            certs.extend(p.clamped_certificates(node)?);
            let up = p.best_bound(&certs, node);
            Ok((lam, (certs, up)))
        })
        .collect();
    let mut cheap = Vec::with_capacity(faces.len());
    for (r, (_, node)) in bounded.into_iter().zip(faces) {
        let (lam, c) = r.map_err(cancelled_or)?;
        lower.consider(&node.curves(Status::In), lam);
        cheap.push(c);
    }
    Ok(cheap)
}

/// Relaxes the faces the cheap bounds leave above the best known value `floor`, highest cheap
/// bound first, in fixed batches. The bound is the maximum over the faces, and relaxing a face
/// can only lower its own: once a relaxed face's bound is at least every remaining face's
/// cheap bound, relaxing those cannot change the maximum, so they keep their cheap bounds
/// (the same certified bound for less work). Which faces are relaxed depends only on the
/// values, never on threads. Also says whether it was cancelled (the faces not relaxed by
/// then keep their cheap bounds).
fn relax_faces(
    p: &FixedProblem<'_>,
    params: &CertifyParams,
    faces: &[Face],
    cheap: &[Cheap],
    floor: f64,
    cancel: &Cancel,
) -> Result<(Vec<FaceOutcome>, bool), SimplifyError> {
    let relax_face = |i: usize| -> Result<FaceOutcome, StabilityError> {
        let ((curve, node), (certs, up)) = (&faces[i], &cheap[i]);
        let r = p.relax_node(node, &params.relax, None, certs, cancel)?;
        let fb = FaceBound {
            curve: *curve,
            upper: up.min(r.upper),
            relaxed: r.value,
            evals: r.evals,
        };
        let rounded = round_relaxed(&r.alpha, p.lengths(), p.budget(), &node.curves(Status::In));
        Ok((fb, rounded))
    };
    let tol = params.relax.tolerance;
    let mut outcomes: Vec<Option<FaceOutcome>> = vec![None; faces.len()];
    let mut order: Vec<usize> = (0..faces.len())
        .filter(|&i| {
            let up = cheap[i].1;
            up > floor + tol * floor.abs() && !faces[i].1.curves(Status::Free).is_empty()
        })
        .collect();
    order.sort_by(|&a, &b| cheap[b].1.total_cmp(&cheap[a].1).then(a.cmp(&b)));
    let mut relaxed_max = f64::NEG_INFINITY;
    let mut cancelled = false;
    for batch in order.chunks(FACE_BATCH) {
        let todo: Vec<usize> = batch
            .iter()
            .copied()
            .filter(|&i| cheap[i].1 > relaxed_max)
            .collect();
        if todo.is_empty() || cancelled {
            break;
        }
        let done: Vec<Result<FaceOutcome, StabilityError>> =
            todo.par_iter().map(|&i| relax_face(i)).collect();
        for (&i, r) in todo.iter().zip(done) {
            match r {
                Ok(outcome) => {
                    relaxed_max = relaxed_max.max(outcome.0.upper);
                    outcomes[i] = Some(outcome);
                }
                Err(StabilityError::Cancelled) => cancelled = true,
                Err(e) => return Err(e.into()),
            }
        }
    }
    let outcomes = outcomes
        .into_iter()
        .enumerate()
        .map(|(i, o)| {
            o.unwrap_or_else(|| {
                let bound = FaceBound {
                    curve: faces[i].0,
                    upper: cheap[i].1,
                    relaxed: f64::NAN,
                    evals: 0,
                };
                (bound, Vec::new())
            })
        })
        .collect();
    Ok((outcomes, cancelled))
}

/// A stability error, the cancellation as the search's own.
fn cancelled_or(e: StabilityError) -> SimplifyError {
    match e {
        StabilityError::Cancelled => SimplifyError::Cancelled,
        e => e.into(),
    }
}

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

#[cfg(test)]
mod tests {
    use super::round_relaxed;

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
