//! The up-front analysis of a combination of constraints, budget and keep list: what no set
//! can satisfy is refused before any search runs, with the reason.
//!
//! Each test is a necessary condition (a set passing all of them may still not exist; the
//! searches then find no feasible network and the run says so):
//!
//! - the forced units (the groups holding keep-list curves) fit the budget;
//! - without a keep list, some unit fits the budget;
//! - at least `K` curves: at most the network's curves, and at most the number of curves the
//!   budget can hold (units taken by ascending length per curve, the last one in part: an
//!   upper bound);
//! - connected: the forced curves lie in one connected part of the whole network;
//! - a largest gap `D`: every curve kept leaves no gap above `D`, and every part of the surface
//!   (each need of [`super::Coverage`]) has a unit within `D` short enough for the budget the
//!   forced units leave.

use super::{Constraints, CurveSet};
use crate::fmt::length as num;
use crate::words::{Message, Opt, given, message};

/// Curve ids as `0, 3, 5` (at most a dozen, then a count).
fn list(curves: impl IntoIterator<Item = usize>) -> String {
    let all: Vec<usize> = curves.into_iter().collect();
    let mut s: Vec<String> = all.iter().take(12).map(|c| c.to_string()).collect();
    if all.len() > 12 {
        s.push(format!("… ({} curves)", all.len()));
    }
    s.join(", ")
}

impl Constraints {
    /// Runs the tests of the module documentation; records what it found in the notes.
    pub(crate) fn analyse(&mut self) -> Result<(), Message> {
        if let Some(f) = &self.symmetry {
            self.notes.push(message![
                given(Opt::Symmetry, f.option()),
                format!(": {}", f.describe())
            ]);
        }
        let keep_length = self.length(&self.keep);
        let forced: Vec<usize> = self.forced_set.to_vec();
        let forced_length = self.length(&forced);
        for (u, unit) in self.units.iter().enumerate() {
            let extra: Vec<usize> = unit
                .iter()
                .copied()
                .filter(|c| !self.keep.contains(c))
                .collect();
            if self.forced[u] && !extra.is_empty() {
                self.notes.push(Message::from(format!(
                    "curves {} are kept whole with curve(s) {} of the keep list (one group)",
                    list(extra),
                    list(unit.iter().copied().filter(|c| self.keep.contains(c)))
                )));
            }
        }
        if keep_length <= self.budget && forced_length > self.budget {
            return Err(format!(
                "the keep list needs {} and, with the groups holding its curves (curves {}), {}: \
                 more than the budget {}",
                num(keep_length),
                list(forced.iter().copied()),
                num(forced_length),
                num(self.budget)
            )
            .into());
        }
        if keep_length > self.budget {
            self.notes.push(Message::from(format!(
                "the keep list alone needs {}, more than the budget {}: no network meets the budget",
                num(keep_length),
                num(self.budget)
            )));
        }
        let free: Vec<usize> = (0..self.units.len()).filter(|&u| !self.forced[u]).collect();
        let unit_length = |u: usize| self.length(&self.units[u]);
        if forced.is_empty()
            && let Some(&u) = free
                .iter()
                .min_by(|&&a, &&b| unit_length(a).total_cmp(&unit_length(b)))
            && unit_length(u) > self.budget
        {
            return Err(format!(
                "every group is longer than the budget {}: the shortest (curves {}) needs {}",
                num(self.budget),
                list(self.units[u].iter().copied()),
                num(unit_length(u))
            )
            .into());
        }
        self.analyse_min_curves(&free, forced.len(), forced_length)?;
        self.analyse_connected(&forced)?;
        self.analyse_gap(&free, forced_length)?;
        if self.params.max_deviation.is_some() {
            self.deviation_note = Some(self.notes.len());
            self.notes.push(self.deviation_note_text(None));
        }
        Ok(())
    }

    /// The note saying how the largest deviation is measured: on the equilibrium of the
    /// searches' model (the paper's), or in the physical mode (`unit`: the scene's length
    /// unit) on the structure's own model under its own weight.
    fn deviation_note_text(&self, unit: Option<&str>) -> Message {
        let d = self.params.max_deviation.unwrap_or(0.0);
        match unit {
            None => message![
                given(Opt::MaxDeviation, num(d)),
                ": measured on the equilibrium of every network the greedy records and the \
                 local search evaluates (the largest displacement of a vertex from its designed \
                 place); a network over it is never the answer"
            ],
            Some(u) => message![
                given(Opt::MaxDeviation, format!("{} {u}", num(d))),
                ": measured in the physical model on every network the greedy records and the \
                 local search evaluates: the largest distance of a vertex from its designed \
                 place once the rods are bent into shape and carry their own weight (the \
                 structure's equilibrium plus its self-weight deflection); a network over it is \
                 never the answer"
            ],
        }
    }

    /// The largest deviation is the physical mode's (the searches' analyzer measures it on
    /// the structure's own model, [`crate::stability::Analyzer::part_deviation`]), in `unit`
    /// (the scene's length unit): the note says so.
    pub fn deviation_measured_physically(&mut self, unit: &str) {
        self.deviation_unit = Some(unit.to_string());
        if let Some(i) = self.deviation_note {
            self.notes[i] = self.deviation_note_text(Some(unit));
        }
    }

    /// The scene's length unit when the largest deviation is the physical mode's
    /// ([`Self::deviation_measured_physically`]), else `None`.
    pub fn deviation_unit(&self) -> Option<&str> {
        self.deviation_unit.as_deref()
    }

    fn analyse_min_curves(
        &self,
        free: &[usize],
        forced_count: usize,
        forced_length: f64,
    ) -> Result<(), Message> {
        let Some(k) = self.params.min_curves else {
            return Ok(());
        };
        if k > self.n {
            return Err(message![
                given(Opt::MinCurves, k),
                format!(": the network has only {} curves", self.n)
            ]);
        }
        // Fractional knapsack on the number of curves: an upper bound.
        let mut order: Vec<(f64, usize, usize)> = free
            .iter()
            .map(|&u| {
                let len = self.length(&self.units[u]);
                (len / self.units[u].len() as f64, self.units[u].len(), u)
            })
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
        let mut room = self.budget - forced_length;
        let mut most = forced_count as f64;
        for (per, count, _) in order {
            let len = per * count as f64;
            if len <= room {
                room -= len;
                most += count as f64;
            } else {
                most += (room / per).max(0.0);
                break;
            }
        }
        let most = (most + 1e-9).floor() as usize;
        if most < k {
            return Err(message![
                given(Opt::MinCurves, k),
                format!(
                    ": at most {most} curves fit in the budget {} (the shortest first, groups \
                     whole)",
                    num(self.budget)
                )
            ]);
        }
        Ok(())
    }

    fn analyse_connected(&self, forced: &[usize]) -> Result<(), Message> {
        let (Some(adj), Some(&first)) = (&self.adjacency, forced.first()) else {
            return Ok(());
        };
        // The part of the whole network holding the first forced curve.
        let all = CurveSet::from_curves(self.n, &(0..self.n).collect::<Vec<_>>());
        let reach = self.component(adj, first, &all);
        if let Some(&c) = forced.iter().find(|&&c| !reach.contains(c)) {
            return Err(message![
                Opt::Connected,
                format!(
                    ": curves {first} and {c} (kept with the keep list) lie in separate parts of \
                     the network, which no kept curves can join"
                )
            ]);
        }
        Ok(())
    }

    fn analyse_gap(&mut self, free: &[usize], forced_length: f64) -> Result<(), Message> {
        let Some(cov) = &self.coverage else {
            return Ok(());
        };
        let d = cov.limit();
        let full = cov.full_gap();
        let limit = || given(Opt::MaxGap, num(d));
        let note = message![
            limit(),
            format!(
                ": the surface sampled at {} points (spacing {}: the true gap exceeds the \
                 measured one by less), {} distinct needs; every curve kept leaves a gap of {}",
                cov.sample_count(),
                num(cov.spacing()),
                cov.need_count(),
                num(full.value)
            )
        ];
        if full.value > d {
            return Err(message![
                limit(),
                format!(
                    ": even with every curve kept, the point ({}, {}, {}) of the surface lies {} \
                     from the nearest curve (the smallest gap possible)",
                    num(full.at.x),
                    num(full.at.y),
                    num(full.at.z),
                    num(full.value)
                )
            ]);
        }
        let room = self.budget - forced_length;
        for (need, at) in cov.needs() {
            if need.intersects(&self.forced_set) {
                continue;
            }
            let shortest = free
                .iter()
                .filter(|&&u| self.unit_sets[u].intersects(need))
                .map(|&u| (self.length(&self.units[u]), u))
                .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            if let Some((len, u)) = shortest
                && len > room
            {
                return Err(message![
                    limit(),
                    format!(
                        ": the point ({}, {}, {}) of the surface is within {} only of curves {}, \
                         and the shortest group holding one (curves {}) needs {}, more than the \
                         budget leaves ({})",
                        num(at.x),
                        num(at.y),
                        num(at.z),
                        num(d),
                        list(need.iter()),
                        list(self.units[u].iter().copied()),
                        num(len),
                        num(room)
                    )
                ]);
            }
        }
        self.notes.push(note);
        Ok(())
    }
}
