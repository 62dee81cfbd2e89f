//! `λ_eq` of the subsets a local search meets, each evaluated once per run (a memo shared by
//! its starts), with the best part a set falls apart into; the order the search ranks values by.

use crate::cancel::Cancel;
use crate::constraints::Constraints;
use crate::simplify::exhaustive::SubsetScore;
use crate::stability::Analyzer;
use rayon::prelude::*;
use std::collections::HashMap;

/// What the search knows of an evaluated subset.
#[derive(Clone, Debug)]
pub(super) struct Entry {
    /// `λ_eq` (NaN when the evaluation failed).
    pub(super) lambda: f64,
    /// What the search ranks it by: `λ_eq`, or −∞ when its equilibrium moves a vertex farther
    /// than `--max-deviation` allows (a set the search may leave but never reach).
    pub(super) value: f64,
    /// When the subset falls apart into separate structures: the best sub-structure made of
    /// its parts that holds the keep list (its name for [`super::Move::Part`], its curves, its
    /// `λ_eq`), if better than the subset.
    pub(super) part: Option<(usize, Vec<usize>, f64)>,
}

/// What the searches of one run know of the subsets they evaluated (shared by its starts).
pub(super) type Memo = HashMap<Vec<usize>, Entry>;

/// `λ_eq` of subsets, each evaluated once per run.
pub(super) struct Evaluator<'s> {
    pub(super) analyzer: &'s Analyzer,
    /// Design constraints a part must meet to be stepped to.
    pub(super) constraints: Option<&'s Constraints>,
    pub(super) keep: Vec<usize>,
    pub(super) tolerance: f64,
    pub(super) memo: &'s mut Memo,
    pub(super) cancel: &'s Cancel,
}

/// The search was cancelled (its evaluations stopped part way).
pub(super) struct Stopped;

impl Evaluator<'_> {
    /// Every set's entry: the new ones evaluated in parallel.
    pub(super) fn eval_all(&mut self, sets: &[Vec<usize>]) -> Result<Vec<Entry>, Stopped> {
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
                        // The largest deviation is measured only when it is bounded (in the
                        // physical mode it costs a relaxation of its own).
                        let limited = constraints.filter(|c| c.params().max_deviation.is_some());
                        let within = limited
                            .is_none_or(|c| c.deviation_ok(analyzer.parts_deviation(&parts)));
                        let value = if within { lambda } else { f64::NEG_INFINITY };
                        let values: Vec<(Vec<usize>, f64)> =
                            parts.iter().map(|p| (p.curves.clone(), p.lambda)).collect();
                        let part = best_part(&values, keep)
                            .filter(|p| improves(p.2, value, tol))
                            .filter(|p| constraints.is_none_or(|c| c.check(&p.1).is_ok()))
                            .filter(|p| {
                                limited.is_none_or(|c| {
                                    let within: Vec<_> = parts
                                        .iter()
                                        .filter(|q| q.curves.iter().all(|x| p.1.contains(x)))
                                        .cloned()
                                        .collect();
                                    c.deviation_ok(analyzer.parts_deviation(&within))
                                })
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

/// Whether `v` beats `reference` by more than the relative `tol` (a finite value beats a
/// failed evaluation).
pub(super) fn improves(v: f64, reference: f64, tol: f64) -> bool {
    if reference.is_finite() {
        v > reference + tol * reference.abs()
    } else {
        v.is_finite()
    }
}

/// The position of the best finite value, values within the relative `tol` of the best going
/// to the first.
pub(super) fn best_position(vals: &[f64], tol: f64) -> Option<usize> {
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

/// The feasible sets of `memo` (and the parts it stepped to) with `λ_eq > 0` within
/// `--max-deviation`, by decreasing `λ_eq`, ties by ascending curve ids, each once.
pub(super) fn visited(memo: &HashMap<Vec<usize>, Entry>, lengths: &[f64]) -> Vec<SubsetScore> {
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
