//! What the searches need of the constraints: whole units to remove, add, drop and swap, and
//! the feasible sets enumerated or drawn.
//!
//! Without constraints every unit is one curve and unit `u` is curve `u`: the moves, the
//! enumeration order and the random draws are then those of the searches on curves (the same
//! order, the same draws from the same seed).

use super::{Constraints, CurveSet};
use crate::rng::SplitMix64;
use crate::words::Message;
use serde::{Deserialize, Serialize};
use std::collections::HashSet;

/// A move of the local search over units (unit ids: see [`Constraints::units`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum UnitMove {
    /// Add a unit.
    Add(usize),
    /// Drop a unit.
    Drop(usize),
    /// Swap unit `out` for unit `into`.
    Swap {
        /// The unit leaving.
        out: usize,
        /// The unit entering.
        into: usize,
    },
}

impl UnitMove {
    /// The units it moves.
    pub fn units(self) -> [Option<usize>; 2] {
        match self {
            UnitMove::Add(u) | UnitMove::Drop(u) => [Some(u), None],
            UnitMove::Swap { out, into } => [Some(out), Some(into)],
        }
    }
}

/// Relative slack of the enumeration's running length against the budget: the running sum
/// is not summed in the order of the exact test ([`Constraints::length`]), so the branch test
/// must not cut a set the exact test accepts.
const PRUNE_SLACK: f64 = 1e-12;

impl Constraints {
    /// The units: sets of curves kept or removed together, a partition of the curves, each
    /// ascending, in order of their smallest curve.
    pub fn units(&self) -> &[Vec<usize>] {
        &self.units
    }

    /// The unit holding curve `c`.
    pub fn unit_of(&self, c: usize) -> usize {
        self.unit_of[c]
    }

    /// Whether unit `u` holds a curve of the keep list (it is never removed).
    pub fn is_forced(&self, u: usize) -> bool {
        self.forced[u]
    }

    /// The curves of the units holding the keep list, ascending.
    pub fn forced_curves(&self) -> Vec<usize> {
        self.forced_set.to_vec()
    }

    /// The units of `curves` (a set of whole units) the greedy may remove: not forced, and
    /// leaving a set that meets every constraint but the budget (at least one curve, enough
    /// curves, connected, the surface covered). Ascending.
    pub fn removal_candidates(&self, curves: &[usize]) -> Vec<usize> {
        let set = CurveSet::from_curves(self.n, curves);
        let mut units: Vec<usize> = curves.iter().map(|&c| self.unit_of[c]).collect();
        units.sort_unstable();
        units.dedup();
        units
            .into_iter()
            .filter(|&u| !self.forced[u])
            .filter(|&u| {
                let mut rest = set.clone();
                rest.difference_with(&self.unit_sets[u]);
                !rest.is_empty() && self.check_shape(&rest).is_ok()
            })
            .collect()
    }

    /// How far `set` is from the constraints that adding curves can meet: the curves
    /// missing to `--min-curves`, the unmet parts of the surface under `--max-gap`, and the
    /// structures beyond one under `--connected`; 0 when all three hold.
    pub(crate) fn shortfall(&self, set: &CurveSet) -> usize {
        let few = self
            .params
            .min_curves
            .map_or(0, |k| k.saturating_sub(set.len()));
        let gap = self.coverage.as_ref().map_or(0, |cov| cov.unmet(set));
        let parts = if self.adjacency.is_some() {
            self.parts(set).saturating_sub(1)
        } else {
            0
        };
        few + gap + parts
    }

    /// Whether the searches need starts [`Self::grow`] builds: `--min-curves` or `--max-gap`
    /// is in force, which a single unit rarely meets.
    pub fn needs_grown_starts(&self) -> bool {
        self.params.min_curves.is_some() || self.coverage.is_some()
    }

    /// A set meeting every constraint but `--max-deviation`, grown from unit `seed` with the
    /// units holding the keep list: while the set falls short ([`Self::shortfall`]), the unit
    /// that fits the budget left and removes the most shortfall per unit of length joins it
    /// (ties to the lower unit). `None` when the seed is forced or over the budget, or when
    /// no unit that fits reduces the shortfall. Ascending.
    pub fn grow(&self, seed: usize) -> Option<Vec<usize>> {
        if self.forced[seed] {
            return None;
        }
        let mut set = self.forced_set.clone();
        set.union_with(&self.unit_sets[seed]);
        let unit_length = |u: usize| self.length(&self.units[u]);
        let mut length = self.length(&set.to_vec());
        if length > self.budget {
            return None;
        }
        loop {
            let short = self.shortfall(&set);
            if short == 0 {
                return self.check_set(&set, length).is_ok().then(|| set.to_vec());
            }
            let mut best: Option<(f64, usize)> = None;
            for u in 0..self.units.len() {
                if self.unit_sets[u].intersects(&set) || length + unit_length(u) > self.budget {
                    continue;
                }
                let mut next = set.clone();
                next.union_with(&self.unit_sets[u]);
                let gain = short.saturating_sub(self.shortfall(&next));
                if gain == 0 {
                    continue;
                }
                let rate = gain as f64 / unit_length(u).max(f64::MIN_POSITIVE);
                if best.is_none_or(|(r, _)| rate > r) {
                    best = Some((rate, u));
                }
            }
            let (_, u) = best?;
            set.union_with(&self.unit_sets[u]);
            length = self.length(&set.to_vec());
        }
    }

    /// The moves from `cur` (a feasible set) to feasible sets, with the set each leads to
    /// (ascending): adds (with `add`), drops (with `drop`), then swaps (the unit leaving, then
    /// the unit entering), each by ascending unit, none moving a `locked` unit.
    pub fn neighbours(
        &self,
        cur: &[usize],
        add: bool,
        drop: bool,
        locked: Option<&[bool]>,
    ) -> Vec<(UnitMove, Vec<usize>)> {
        let free = |u: &usize| locked.is_none_or(|l| !l[*u]);
        let inside = CurveSet::from_curves(self.n, cur);
        let mut in_units: Vec<usize> = cur.iter().map(|&c| self.unit_of[c]).collect();
        in_units.sort_unstable();
        in_units.dedup();
        let outside: Vec<usize> = (0..self.units.len())
            .filter(|&u| !self.unit_sets[u].intersects(&inside))
            .filter(free)
            .collect();
        let removable: Vec<usize> = in_units
            .iter()
            .copied()
            .filter(|&u| !self.forced[u])
            .filter(free)
            .collect();
        let mut moves = Vec::new();
        if add {
            moves.extend(outside.iter().map(|&u| UnitMove::Add(u)));
        }
        if drop {
            moves.extend(removable.iter().map(|&u| UnitMove::Drop(u)));
        }
        for &out in &removable {
            moves.extend(outside.iter().map(|&into| UnitMove::Swap { out, into }));
        }
        moves
            .into_iter()
            .filter_map(|m| {
                let mut set = inside.clone();
                if let UnitMove::Drop(u) | UnitMove::Swap { out: u, .. } = m {
                    set.difference_with(&self.unit_sets[u]);
                }
                if let UnitMove::Add(u) | UnitMove::Swap { into: u, .. } = m {
                    set.union_with(&self.unit_sets[u]);
                }
                let curves = set.to_vec();
                self.check_set(&set, self.length(&curves))
                    .is_ok()
                    .then_some((m, curves))
            })
            .collect()
    }

    /// Every feasible set (budget, keep list, every constraint but the largest deviation), each
    /// ascending, depth-first over the units (with a unit before without); `Err` when there are
    /// more than `cap`. Branches that cannot reach the budget, the number of curves or the
    /// surface's cover are cut.
    pub fn feasible_subsets(&self, cap: usize) -> Result<Vec<Vec<usize>>, Message> {
        let m = self.units.len();
        let lengths: Vec<f64> = (0..m).map(|u| self.length(&self.units[u])).collect();
        // What the units from `u` on can still add: curves and the union of their sets.
        let mut rest_count = vec![0usize; m + 1];
        let mut rest_set = vec![CurveSet::new(self.n); m + 1];
        for u in (0..m).rev() {
            rest_count[u] = rest_count[u + 1];
            rest_set[u] = rest_set[u + 1].clone();
            if !self.forced[u] {
                rest_count[u] += self.units[u].len();
                rest_set[u].union_with(&self.unit_sets[u]);
            }
        }
        let base = self.length(&self.forced_set.to_vec());
        let limit = self.budget + PRUNE_SLACK * self.budget.abs();
        let mut out = Vec::new();
        if base > limit {
            return Ok(out);
        }
        let mut state = Enumeration {
            c: self,
            lengths: &lengths,
            rest_count: &rest_count,
            rest_set: &rest_set,
            limit,
            cap,
            current: self.forced_set.clone(),
            out: &mut out,
        };
        state.rec(0, base).map_err(|()| {
            Message::from(format!(
                "exhaustive search refused: the network's {} curves ({m} groups) have more than \
                 {cap} feasible subsets at budget {:.6}; use the greedy or random search, or \
                 raise the limit",
                self.n, self.budget
            ))
        })?;
        Ok(out)
    }

    /// Up to `count` distinct feasible sets drawn uniformly from `seed`, the way the random
    /// search draws: each unit outside the forced ones kept with probability ½, the draw kept
    /// when feasible and new; when feasible draws are too rare (half a million misses before
    /// the first), random maximal sets (units in random order, added while the budget allows)
    /// instead. Returns the sets, whether the fallback was used, and whether fewer than
    /// `count` were found.
    pub fn draw_subsets(&self, count: usize, seed: u64) -> (Vec<Vec<usize>>, bool, bool) {
        let free: Vec<usize> = (0..self.units.len()).filter(|&u| !self.forced[u]).collect();
        let unit_length: Vec<f64> = (0..self.units.len())
            .map(|u| self.length(&self.units[u]))
            .collect();
        let forced = self.forced_set.to_vec();
        SubsetDraw {
            free: &free,
            unit_length: &unit_length,
            forced: &forced,
            base: self.length(&forced),
            budget: self.budget,
        }
        .draw(
            count,
            seed,
            |u, s| s.extend_from_slice(&self.units[u]),
            |s| self.check(s).is_ok(),
        )
    }
}

/// Random subsets of units drawn whole beside the forced curves (see
/// [`Constraints::draw_subsets`]; the random search on curves draws the same way, one curve a
/// unit).
pub(crate) struct SubsetDraw<'a> {
    /// The units that may be drawn, ascending.
    pub(crate) free: &'a [usize],
    /// Each unit's length (indexed by unit).
    pub(crate) unit_length: &'a [f64],
    /// The curves every set holds.
    pub(crate) forced: &'a [usize],
    /// Their length.
    pub(crate) base: f64,
    /// The largest total length of a set.
    pub(crate) budget: f64,
}

impl SubsetDraw<'_> {
    /// Up to `count` distinct sets drawn from `seed`: each free unit (its curves added to the
    /// set by `add`) kept with probability ½, the draw kept when it is within the budget, new
    /// and `accept`ed; when such draws are too rare (half a million misses before the first),
    /// random maximal sets (free units in random order, added while the budget allows)
    /// instead. Returns the sets (curves ascending), whether the fallback was used, and
    /// whether fewer than `count` were found.
    pub(crate) fn draw(
        &self,
        count: usize,
        seed: u64,
        add: impl Fn(usize, &mut Vec<usize>),
        accept: impl Fn(&[usize]) -> bool,
    ) -> (Vec<Vec<usize>>, bool, bool) {
        let mut rng = SplitMix64::new(seed);
        let mut seen: HashSet<Vec<usize>> = HashSet::new();
        let mut out = Vec::new();
        let mut fallback = false;
        let mut misses = 0u64;
        let max_misses = 1_000_000u64;
        while out.len() < count && misses < max_misses {
            let mut s: Vec<usize> = Vec::new();
            let mut len = self.base;
            if !fallback {
                for &u in self.free {
                    if rng.next_u64() & 1 == 1 {
                        add(u, &mut s);
                        len += self.unit_length[u];
                    }
                }
            } else {
                let mut order = self.free.to_vec();
                for i in (1..order.len()).rev() {
                    order.swap(i, rng.below(i as u64 + 1) as usize);
                }
                for u in order {
                    if len + self.unit_length[u] <= self.budget {
                        add(u, &mut s);
                        len += self.unit_length[u];
                    }
                }
            }
            s.extend_from_slice(self.forced);
            s.sort_unstable();
            s.dedup();
            let ok = !s.is_empty() && len <= self.budget && !seen.contains(&s) && accept(&s);
            if !ok {
                misses += 1;
                if !fallback && misses >= max_misses / 2 && out.is_empty() {
                    fallback = true;
                    misses = 0;
                }
                continue;
            }
            misses = 0;
            seen.insert(s.clone());
            out.push(s);
        }
        let exhausted = out.len() < count;
        (out, fallback, exhausted)
    }
}

/// The depth-first enumeration's state.
struct Enumeration<'a> {
    c: &'a Constraints,
    lengths: &'a [f64],
    rest_count: &'a [usize],
    rest_set: &'a [CurveSet],
    limit: f64,
    cap: usize,
    current: CurveSet,
    out: &'a mut Vec<Vec<usize>>,
}

impl Enumeration<'_> {
    /// Sets extending `current` (which holds the forced units from the start) with the units
    /// from `u` on; `len` is its running length.
    fn rec(&mut self, u: usize, len: f64) -> Result<(), ()> {
        let c = self.c;
        // Cuts: not enough curves left for `--min-curves`, or the surface out of reach.
        if let Some(k) = c.params.min_curves
            && self.current.len() + self.rest_count[u] < k
        {
            return Ok(());
        }
        if let Some(cov) = &c.coverage {
            let mut reach = self.current.clone();
            reach.union_with(&self.rest_set[u]);
            if !cov.covers(&reach) {
                return Ok(());
            }
        }
        if u == c.units.len() {
            if self.current.is_empty() {
                return Ok(());
            }
            let curves = self.current.to_vec();
            if c.check_set(&self.current, c.length(&curves)).is_ok() {
                if self.out.len() >= self.cap {
                    return Err(());
                }
                self.out.push(curves);
            }
            return Ok(());
        }
        if c.forced[u] {
            return self.rec(u + 1, len);
        }
        if len + self.lengths[u] <= self.limit {
            self.current.union_with(&c.unit_sets[u]);
            self.rec(u + 1, len + self.lengths[u])?;
            self.current.difference_with(&c.unit_sets[u]);
        }
        self.rec(u + 1, len)
    }
}
