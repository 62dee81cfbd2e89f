//! The local search's starts: the start given, the best single-curve (single-unit) sets and,
//! under `--min-curves` or `--max-gap`, the best sets grown to meet them, searched in turn
//! over one shared memo; the best outcome kept.

use super::evaluator::{Evaluator, Memo, Stopped, visited};
use super::search::search_from;
use super::{GROWN_EVALUATED, LocalOutcome, LocalParams, SINGLE_STARTS};
use crate::cancel::Cancel;
use crate::constraints::Constraints;
use crate::simplify::SimplifyError;
use crate::simplify::exhaustive::SubsetScore;
use crate::stability::Analyzer;

/// Searches from several starts, sharing their evaluations; keeps the best outcome (ties to
/// the earliest start).
pub(super) struct MultiStart<'s> {
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
    pub(super) stopped: bool,
}

impl<'s> MultiStart<'s> {
    pub(super) fn new(
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
    pub(super) fn feasible(&self, s: &[usize]) -> bool {
        !s.is_empty()
            && s.iter().all(|&c| c < self.lengths.len())
            && self.length(s) <= self.budget
            && self.params.keep.iter().all(|k| s.contains(k))
            && self.constraints.is_none_or(|c| c.check(s).is_ok())
    }

    /// Searches from the feasible `start` unless it was searched already; false once the run
    /// is cancelled.
    pub(super) fn search(&mut self, start: &[usize]) -> Result<bool, SimplifyError> {
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

    /// Searches from each start `starts` gives, in turn, unless the run has stopped; a
    /// cancelled evaluation of the starts stops it.
    pub(super) fn search_each(
        &mut self,
        starts: impl FnOnce(&mut Self) -> Result<Vec<Vec<usize>>, Stopped>,
    ) -> Result<(), SimplifyError> {
        if self.stopped {
            return Ok(());
        }
        match starts(self) {
            Ok(sets) => {
                for s in sets {
                    if !self.search(&s)? {
                        break;
                    }
                }
            }
            Err(Stopped) => self.stopped = true,
        }
        Ok(())
    }

    /// The [`SINGLE_STARTS`] best single-curve starts (module documentation, *Starts*), best
    /// first: each curve (under constraints, each unit) with the keep list, when that is a
    /// feasible start, ranked by the search's value (`λ_eq`; sets over `--max-deviation` and
    /// failed evaluations are not taken), ties to the lower curve.
    pub(super) fn single_starts(&mut self) -> Result<Vec<Vec<usize>>, Stopped> {
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
        self.best_of(sets)
    }

    /// Under `--min-curves` or `--max-gap`, the [`SINGLE_STARTS`] best *grown* starts (module
    /// documentation, *Starts*), best first: from each unit as a seed, shortest seed first,
    /// a set grown to meet the constraints ([`Constraints::grow`]); the first
    /// [`GROWN_EVALUATED`] distinct feasible ones are evaluated and ranked by the search's
    /// value, ties to the earlier seed. None without those constraints.
    pub(super) fn grown_starts(&mut self) -> Result<Vec<Vec<usize>>, Stopped> {
        let Some(c) = self.constraints.filter(|c| c.needs_grown_starts()) else {
            return Ok(Vec::new());
        };
        let mut seeds: Vec<usize> = (0..c.units().len()).collect();
        // Stable: equal lengths keep the order of the units.
        seeds.sort_by(|&a, &b| c.length(&c.units()[a]).total_cmp(&c.length(&c.units()[b])));
        let mut sets: Vec<Vec<usize>> = Vec::new();
        for seed in seeds {
            if self.cancel.is_cancelled() {
                return Err(Stopped);
            }
            if let Some(set) = c.grow(seed)
                && self.feasible(&set)
                && !sets.contains(&set)
            {
                sets.push(set);
                if sets.len() == GROWN_EVALUATED {
                    break;
                }
            }
        }
        self.best_of(sets)
    }

    /// The keep list alone, when no other start was feasible and it is (a budget that holds
    /// the kept curves and nothing more): the search may still add to it.
    pub(super) fn keep_start(&mut self) -> Result<Vec<Vec<usize>>, Stopped> {
        let mut keep = self.params.keep.clone();
        keep.sort_unstable();
        keep.dedup();
        Ok(if self.starts.is_empty() && self.feasible(&keep) {
            vec![keep]
        } else {
            Vec::new()
        })
    }

    /// The [`SINGLE_STARTS`] sets of `sets` of the best finite values, best first, ties to
    /// the earlier set.
    fn best_of(&mut self, sets: Vec<Vec<usize>>) -> Result<Vec<Vec<usize>>, Stopped> {
        let entries = Evaluator {
            analyzer: self.analyzer,
            constraints: self.constraints,
            keep: self.params.keep.clone(),
            tolerance: self.params.tolerance,
            memo: &mut self.memo,
            cancel: self.cancel,
        }
        .eval_all(&sets)?;
        let mut ranked: Vec<usize> = (0..sets.len())
            .filter(|&i| entries[i].value.is_finite())
            .collect();
        // Stable: equal values keep the order of the sets.
        ranked.sort_by(|&a, &b| entries[b].value.total_cmp(&entries[a].value));
        Ok(ranked
            .into_iter()
            .take(SINGLE_STARTS)
            .map(|i| sets[i].clone())
            .collect())
    }

    /// The best outcome, with every start and the run's evaluations; `given`: whether the first
    /// start searched was the one given.
    pub(super) fn finish(self, given: bool) -> Result<LocalOutcome, SimplifyError> {
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
