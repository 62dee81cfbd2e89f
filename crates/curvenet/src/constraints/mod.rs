//! Design constraints every search honours: what a designer asks of the network beyond the
//! budget and the keep list.
//!
//! | option | constraint on a kept set `S` | module |
//! |---|---|---|
//! | `groups` (a groups file), `"group"` in JSON curves | each group is kept whole or removed whole | [`groups`] |
//! | `symmetry` (`rotate:N\|mirror\|auto`) | each orbit of the detected symmetry is kept whole or removed whole | [`symmetry`] |
//! | `connected` | `S` is one connected structure (curves joined through shared joints) | here |
//! | `min_curves` `K` | `S` holds at least `K` curves | here |
//! | `max_gap` `D` | every point of the surface lies within `D` of a rod of `S` (at rest) | [`coverage`] |
//! | `max_deviation` `D` | no vertex of `S` moves more than `D` from its designed position at `S`'s equilibrium | here |
//!
//! (Each option by its neutral key, [`Opt`]; a front end spells it its own way.)
//!
//! Groups and orbits together make the *units* of a search: the sets of curves it keeps or
//! removes together (groups sharing a curve, or a group and an orbit sharing one, are one
//! unit; a curve in no group is a unit of its own). A unit holding a curve of the keep list is
//! kept whole. Every search moves whole units, so its sets never split a group or an orbit.
//!
//! [`Constraints`] binds validated settings ([`ConstraintParams`]) to a network, its budget and
//! its keep list: it tests any set ([`Constraints::check`]), gives every constraint's margin
//! ([`Constraints::margins`]), and at construction analyses the combination up front, refusing
//! what nothing can satisfy ([`ConstraintError::Infeasible`]: the keep list with its groups
//! over the budget, more curves asked than the budget holds, keep-list curves no connected
//! network joins, a gap even every curve leaves, a point of the surface no unit within the
//! budget reaches). The searches use its helpers ([`Constraints::removal_candidates`] for the
//! greedy, [`Constraints::neighbours`] for the local search, [`Constraints::feasible_subsets`]
//! for the exhaustive search, [`Constraints::draw_subsets`] for the random search).
//!
//! [`answer`] chooses the network to build among those the searches evaluated: the best
//! stable one that meets every constraint, and the alternatives beside it.
//!
//! The largest deviation is the one constraint that needs an equilibrium, so it is never checked
//! up front: the largest displacement of a vertex of the structure ([`max_displacement`]) is
//! measured on each iteration the greedy records, on every set the local and exhaustive
//! searches evaluate, and on the answer, and a network over the limit is never the answer.

pub mod answer;
pub mod bits;
pub mod coverage;
mod feasibility;
pub mod groups;
mod search;
pub mod symmetry;
#[cfg(test)]
pub(crate) mod testing;

pub use bits::CurveSet;
pub use coverage::{Coverage, Gap};
pub use groups::{Group, parse_groups, read_groups};
pub(crate) use search::SubsetDraw;
pub use search::UnitMove;
pub use symmetry::{Symmetry, SymmetryFound, SymmetryOption};

use crate::io::TriMesh;
use crate::network::Network;
use crate::network::subnet::curve_components;
use crate::words::{Message, Opt, Piece, given, message};
use serde::{Deserialize, Serialize};

/// The constraint settings, as given on the command line and recorded in `result.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ConstraintParams {
    /// Groups of curves kept or removed together (the groups file, then the curve files').
    pub groups: Vec<Group>,
    /// The symmetry whose orbits become groups.
    pub symmetry: SymmetryOption,
    /// The symmetry test's tolerance, relative to the scene's size.
    pub symmetry_tolerance: f64,
    /// The kept curves form one connected structure.
    pub connected: bool,
    /// At least this many curves.
    pub min_curves: Option<usize>,
    /// Largest distance from a point of the surface to the nearest kept curve (scene units).
    pub max_gap: Option<f64>,
    /// Largest displacement of a vertex at the kept network's equilibrium (scene units).
    pub max_deviation: Option<f64>,
}

impl Default for ConstraintParams {
    fn default() -> Self {
        ConstraintParams {
            groups: Vec::new(),
            symmetry: SymmetryOption::None,
            symmetry_tolerance: symmetry::DEFAULT_TOLERANCE,
            connected: false,
            min_curves: None,
            max_gap: None,
            max_deviation: None,
        }
    }
}

impl ConstraintParams {
    /// True when no constraint is asked for (the searches then run exactly as without).
    pub fn is_empty(&self) -> bool {
        self.groups.iter().all(|g| g.curves.len() < 2)
            && self.symmetry == SymmetryOption::None
            && !self.connected
            && self.min_curves.is_none()
            && self.max_gap.is_none()
            && self.max_deviation.is_none()
    }

    /// True when every setting is the default (nothing asked for, not even a group of one).
    pub fn is_default(&self) -> bool {
        *self == ConstraintParams::default()
    }

    /// Checks the values (not their feasibility: [`Constraints::new`] does that).
    ///
    /// # Errors
    ///
    /// A message naming the option whose value is out of range.
    pub fn validate(&self) -> Result<(), Message> {
        if self.min_curves == Some(0) {
            return Err(message![Opt::MinCurves, " must be at least 1"]);
        }
        for (opt, v) in [
            (Opt::MaxGap, self.max_gap),
            (Opt::MaxDeviation, self.max_deviation),
        ] {
            if let Some(v) = v
                && !(v.is_finite() && v > 0.0)
            {
                return Err(message![
                    opt,
                    format!(" must be a positive distance in scene units, got {v}")
                ]);
            }
        }
        if !(self.symmetry_tolerance > 0.0 && self.symmetry_tolerance <= 0.1) {
            return Err(format!(
                "the symmetry tolerance must lie in (0, 0.1] (relative to the scene's size), got {}",
                self.symmetry_tolerance
            )
            .into());
        }
        check_groups(&self.groups)
    }
}

/// Refuses an empty group and a curve in two groups (a groups file refuses them at their
/// line; groups given otherwise, or a groups file beside the curve files' own groups, are
/// checked here), naming the groups and where they were defined.
fn check_groups(groups: &[Group]) -> Result<(), Message> {
    let mut owner: std::collections::HashMap<usize, &Group> = Default::default();
    for g in groups {
        if g.curves.is_empty() {
            return Err(format!(
                "group {} ({}) names no curve: a group holds at least one",
                g.name, g.origin
            )
            .into());
        }
        for &c in &g.curves {
            if let Some(other) = owner.insert(c, g)
                && !std::ptr::eq(other, g)
            {
                return Err(format!(
                    "curve {c} is in two groups, {} ({}) and {} ({}): a curve belongs to one \
                     group",
                    other.name, other.origin, g.name, g.origin
                )
                .into());
            }
        }
    }
    Ok(())
}

/// Why constraints cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum ConstraintError {
    /// A bad value or a missing input (a group naming no curve of the network, the largest
    /// gap without a surface, a symmetry the network does not have).
    #[error("{0}")]
    Usage(Message),
    /// No set of curves satisfies the combination with the budget and the keep list.
    #[error("no network can meet the constraints: {0}")]
    Infeasible(Message),
}

impl ConstraintError {
    /// The error as a message (what `Display` says, for a front end to spell).
    pub fn message(&self) -> Message {
        match self {
            ConstraintError::Usage(m) => m.clone(),
            ConstraintError::Infeasible(m) => m
                .clone()
                .prefixed(["no network can meet the constraints: ".into()]),
        }
    }
}

/// How a set breaks the constraints (the first broken one, in the order tested).
#[derive(Clone, Debug, PartialEq)]
pub enum Violation {
    /// No curve.
    Empty,
    /// Its length exceeds the budget.
    OverBudget {
        /// Its length.
        length: f64,
    },
    /// It lacks curve `0` of the keep list.
    MissesKeep(usize),
    /// It splits unit `0` (a group or an orbit).
    SplitsUnit(usize),
    /// Fewer curves than asked.
    TooFewCurves(usize),
    /// Several separate structures.
    Disconnected(usize),
    /// Parts of the surface farther than the limit from every kept curve (unmet needs).
    Gap(usize),
}

impl std::fmt::Display for Violation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Violation::Empty => write!(f, "no curve"),
            Violation::OverBudget { length } => write!(f, "length {length:.6} over the budget"),
            Violation::MissesKeep(c) => write!(f, "curve {c} of the keep list missing"),
            Violation::SplitsUnit(u) => write!(f, "group {u} split"),
            Violation::TooFewCurves(k) => write!(f, "only {k} curves"),
            Violation::Disconnected(p) => write!(f, "{p} separate structures"),
            Violation::Gap(m) => write!(f, "{m} parts of the surface beyond the largest gap"),
        }
    }
}

/// One constraint's standing for a set: `margin ≥ 0` exactly when it is met.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Margin {
    /// The set's value (its length, its number of curves, its gap…).
    pub value: f64,
    /// The limit.
    pub limit: f64,
    /// How far inside the limit (`limit − value` for an upper limit, `value − limit` for a
    /// lower one).
    pub margin: f64,
    /// Whether the constraint is met.
    pub met: bool,
    /// Where the value is reached (the gap's point of the surface).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<[f64; 3]>,
    /// The value's resolution (the gap's sample spacing: the surface's true gap exceeds
    /// `value` by less).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resolution: Option<f64>,
}

impl Margin {
    fn upper(value: f64, limit: f64) -> Self {
        Margin {
            value,
            limit,
            margin: limit - value,
            met: value <= limit,
            at: None,
            resolution: None,
        }
    }

    fn lower(value: f64, limit: f64) -> Self {
        Margin {
            margin: value - limit,
            met: value >= limit,
            ..Margin::upper(value, limit)
        }
    }
}

/// Every constraint's margin for one set (the budget always; the others when asked for).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Margins {
    /// Length against the budget.
    pub budget: Margin,
    /// Curves of the keep list missing (limit 0; with a keep list).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub keep: Option<Margin>,
    /// Groups split (limit 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub groups: Option<Margin>,
    /// Orbits of the symmetry split (limit 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub symmetry: Option<Margin>,
    /// Separate structures (limit 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub connected: Option<Margin>,
    /// Number of curves (lower limit).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_curves: Option<Margin>,
    /// The surface's largest gap.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_gap: Option<Margin>,
    /// The largest displacement at equilibrium (absent when not evaluated).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_deviation: Option<Margin>,
}

impl Margins {
    /// Whether every constraint listed is met.
    pub fn all_met(&self) -> bool {
        [
            Some(&self.budget),
            self.keep.as_ref(),
            self.groups.as_ref(),
            self.symmetry.as_ref(),
            self.connected.as_ref(),
            self.min_curves.as_ref(),
            self.max_gap.as_ref(),
            self.max_deviation.as_ref(),
        ]
        .into_iter()
        .flatten()
        .all(|m| m.met)
    }
}

/// Constraints bound to one network, budget and keep list.
pub struct Constraints {
    params: ConstraintParams,
    n: usize,
    lengths: Vec<f64>,
    budget: f64,
    keep: Vec<usize>,
    /// The units: a partition of the curves, each ascending, in order of their smallest curve.
    units: Vec<Vec<usize>>,
    unit_of: Vec<usize>,
    unit_sets: Vec<CurveSet>,
    /// Units holding a curve of the keep list.
    forced: Vec<bool>,
    /// The curves of the forced units.
    forced_set: CurveSet,
    groups: Vec<CurveSet>,
    symmetry: Option<SymmetryFound>,
    orbits: Vec<CurveSet>,
    /// For each curve, the curves it shares a vertex with (under the connected constraint).
    adjacency: Option<Vec<CurveSet>>,
    coverage: Option<Coverage>,
    notes: Vec<Message>,
    /// Which of the notes says how the largest deviation is measured.
    deviation_note: Option<usize>,
    /// The scene's length unit when the largest deviation is the physical mode's.
    deviation_unit: Option<String>,
}

impl std::fmt::Debug for Constraints {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Constraints")
            .field("params", &self.params)
            .field("budget", &self.budget)
            .field("keep", &self.keep)
            .field("units", &self.units.len())
            .finish_non_exhaustive()
    }
}

impl Constraints {
    /// No constraint beyond the budget and the keep list: every curve its own unit.
    pub fn none(net: &Network, budget: f64, keep: &[usize]) -> Self {
        Self::bind(net, ConstraintParams::default(), None, None, budget, keep)
    }

    /// Binds `params` to `net` (with its surface `mesh`, needed by the largest gap), the budget
    /// (a length) and the keep list, and analyses the combination.
    ///
    /// # Errors
    ///
    /// [`ConstraintError::Usage`] for bad values, groups naming curves the network lacks,
    /// the largest gap without a surface, or a symmetry the network does not have;
    /// [`ConstraintError::Infeasible`] when no set can meet the constraints (the message says
    /// why).
    pub fn new(
        net: &Network,
        mesh: Option<&TriMesh>,
        params: &ConstraintParams,
        budget: f64,
        keep: &[usize],
    ) -> Result<Self, ConstraintError> {
        params.validate().map_err(ConstraintError::Usage)?;
        let n = net.rods.len();
        groups::check_groups(&params.groups, n).map_err(ConstraintError::Usage)?;
        if let Some(&c) = keep.iter().find(|&&c| c >= n) {
            return Err(ConstraintError::Usage(
                format!("keep list names curve {c}, but the network has {n} curves").into(),
            ));
        }
        let coverage = match (params.max_gap, mesh) {
            (None, _) => None,
            (Some(_), None) => {
                return Err(ConstraintError::Usage(message![
                    Opt::MaxGap,
                    " measures the gap over the surface: give the mesh (",
                    Opt::Mesh,
                    ")"
                ]));
            }
            (Some(d), Some(m)) => Some(Coverage::new(net, m, d).map_err(ConstraintError::Usage)?),
        };
        let found = symmetry::find(net, params.symmetry, params.symmetry_tolerance)
            .map_err(|e| ConstraintError::Usage(e.0.into()))?;
        let auto = || given(Opt::Symmetry, "auto");
        let mut notes = Vec::new();
        if params.symmetry == SymmetryOption::Auto && found.is_empty() {
            notes.push(message![
                auto(),
                ": the network has no symmetry; none is used"
            ]);
        }
        // Auto: the largest symmetry the rest allows; otherwise the one asked for.
        let mut coverage = coverage;
        let mut refused = Vec::new();
        for f in &found {
            let mut c = Self::bind(
                net,
                params.clone(),
                Some(f.clone()),
                coverage.take(),
                budget,
                keep,
            );
            let analysed = c.analyse().and_then(|()| {
                // Auto also refuses a symmetry that leaves nothing to choose beyond the keep
                // list (its orbits all too long for the budget left).
                if params.symmetry == SymmetryOption::Auto && !c.leaves_a_choice() {
                    Err(Message::from(
                        "no orbit beyond the keep list fits the budget",
                    ))
                } else {
                    Ok(())
                }
            });
            match analysed {
                Ok(()) => {
                    if !refused.is_empty() {
                        notes.push(
                            message![auto(), ": larger symmetries refused: "]
                                .then(Message::join(refused, "; ")),
                        );
                    }
                    c.notes.splice(0..0, notes);
                    return Ok(c);
                }
                Err(e) if params.symmetry != SymmetryOption::Auto => {
                    return Err(ConstraintError::Infeasible(
                        e.prefixed([format!("with {}: ", f.option()).into()]),
                    ));
                }
                Err(e) => {
                    refused.push(
                        message![format!("{} (", f.option())]
                            .then(e)
                            .then([Piece::from(")")]),
                    );
                    coverage = c.coverage.take();
                }
            }
        }
        if !refused.is_empty() {
            notes.push(
                message![
                    auto(),
                    ": no symmetry of the network leaves a feasible network ("
                ]
                .then(Message::join(refused, "; "))
                .then([Piece::from("); none is used")]),
            );
        }
        let mut c = Self::bind(net, params.clone(), None, coverage, budget, keep);
        c.analyse().map_err(ConstraintError::Infeasible)?;
        c.notes.splice(0..0, notes);
        Ok(c)
    }

    /// Whether a unit outside the forced ones fits in the budget the forced ones leave.
    fn leaves_a_choice(&self) -> bool {
        let room = self.budget - self.length(&self.forced_set.to_vec());
        (0..self.units.len()).any(|u| !self.forced[u] && self.length(&self.units[u]) <= room)
    }

    /// The constraints without any analysis.
    fn bind(
        net: &Network,
        params: ConstraintParams,
        symmetry: Option<SymmetryFound>,
        coverage: Option<Coverage>,
        budget: f64,
        keep: &[usize],
    ) -> Self {
        let n = net.rods.len();
        let groups: Vec<CurveSet> = params
            .groups
            .iter()
            .map(|g| CurveSet::from_curves(n, &g.curves))
            .collect();
        let orbits: Vec<CurveSet> = symmetry
            .iter()
            .flat_map(|f| &f.orbits)
            .map(|o| CurveSet::from_curves(n, o))
            .collect();
        let all: Vec<usize> = (0..n).collect();
        let units = curve_components(n, &all, groups.iter().chain(&orbits).map(CurveSet::iter));
        let mut unit_of = vec![0; n];
        for (u, unit) in units.iter().enumerate() {
            for &c in unit {
                unit_of[c] = u;
            }
        }
        let unit_sets: Vec<CurveSet> = units.iter().map(|u| CurveSet::from_curves(n, u)).collect();
        let mut forced = vec![false; units.len()];
        let mut forced_set = CurveSet::new(n);
        for &k in keep {
            forced[unit_of[k]] = true;
            forced_set.union_with(&unit_sets[unit_of[k]]);
        }
        let adjacency = params.connected.then(|| {
            let mut adj = vec![CurveSet::new(n); n];
            for cs in net.vertex_curves() {
                for &a in &cs {
                    for &b in &cs {
                        if a != b {
                            adj[a as usize].insert(b as usize);
                        }
                    }
                }
            }
            adj
        });
        let mut keep: Vec<usize> = keep.to_vec();
        keep.sort_unstable();
        keep.dedup();
        Constraints {
            params,
            n,
            lengths: net.rest_lengths(),
            budget,
            keep,
            units,
            unit_of,
            unit_sets,
            forced,
            forced_set,
            groups,
            symmetry,
            orbits,
            adjacency,
            coverage,
            notes: Vec::new(),
            deviation_note: None,
            deviation_unit: None,
        }
    }

    /// The settings.
    pub fn params(&self) -> &ConstraintParams {
        &self.params
    }

    /// True when a constraint beyond the budget and the keep list is in force.
    pub fn is_active(&self) -> bool {
        !self.params.is_empty()
    }

    /// Number of curves of the network.
    pub fn curve_count(&self) -> usize {
        self.n
    }

    /// The budget (a length).
    pub fn budget(&self) -> f64 {
        self.budget
    }

    /// The keep list, ascending.
    pub fn keep(&self) -> &[usize] {
        &self.keep
    }

    /// The symmetry in force, if any.
    pub fn symmetry(&self) -> Option<&SymmetryFound> {
        self.symmetry.as_ref()
    }

    /// What the analysis found and decided (the symmetry, groups widened by the keep list,
    /// the surface's sampling), one line each, for the user.
    pub fn notes(&self) -> &[Message] {
        &self.notes
    }

    /// The total rest length of `curves`, summed in ascending order of the ids (the length
    /// every search and every report uses).
    pub fn length(&self, curves: &[usize]) -> f64 {
        let mut sorted = curves.to_vec();
        sorted.sort_unstable();
        sorted.iter().map(|&c| self.lengths[c]).sum()
    }

    /// Tests `curves` against the budget, the keep list and every constraint except
    /// `--max-deviation` (which needs the equilibrium).
    pub fn check(&self, curves: &[usize]) -> Result<(), Violation> {
        let set = CurveSet::from_curves(self.n, curves);
        self.check_set(&set, self.length(curves))
    }

    /// [`Self::check`] on a set whose length is known.
    pub(crate) fn check_set(&self, set: &CurveSet, length: f64) -> Result<(), Violation> {
        if set.is_empty() {
            return Err(Violation::Empty);
        }
        if length > self.budget {
            return Err(Violation::OverBudget { length });
        }
        if let Some(&k) = self.keep.iter().find(|&&k| !set.contains(k)) {
            return Err(Violation::MissesKeep(k));
        }
        self.check_shape(set)
    }

    /// The constraints that do not involve the budget or the keep list.
    pub(crate) fn check_shape(&self, set: &CurveSet) -> Result<(), Violation> {
        if let Some(u) = self.split_unit(set) {
            return Err(Violation::SplitsUnit(u));
        }
        if let Some(k) = self.params.min_curves {
            let len = set.len();
            if len < k {
                return Err(Violation::TooFewCurves(len));
            }
        }
        if self.adjacency.is_some() {
            let parts = self.parts(set);
            if parts > 1 {
                return Err(Violation::Disconnected(parts));
            }
        }
        if let Some(cov) = &self.coverage {
            let unmet = cov.unmet(set);
            if unmet > 0 {
                return Err(Violation::Gap(unmet));
            }
        }
        Ok(())
    }

    /// The first unit `set` holds in part only.
    fn split_unit(&self, set: &CurveSet) -> Option<usize> {
        set.iter().find_map(|c| {
            let u = self.unit_of[c];
            (!self.unit_sets[u].is_subset(set)).then_some(u)
        })
    }

    /// The number of connected structures `set` makes (through shared vertices; with
    /// `--connected`, else each curve counts alone).
    fn parts(&self, set: &CurveSet) -> usize {
        let Some(adj) = &self.adjacency else {
            return set.len();
        };
        let mut left = set.clone();
        let mut parts = 0;
        for start in set.iter() {
            if left.contains(start) {
                parts += 1;
                left.difference_with(&self.component(adj, start, &left));
            }
        }
        parts
    }

    /// The curves of `within` that `start` reaches through shared vertices without leaving
    /// `within` (`adj`: each curve's neighbours).
    fn component(&self, adj: &[CurveSet], start: usize, within: &CurveSet) -> CurveSet {
        let mut reach = CurveSet::from_curves(self.n, &[start]);
        let mut stack = vec![start];
        while let Some(c) = stack.pop() {
            for d in adj[c].iter() {
                if within.contains(d) && !reach.contains(d) {
                    reach.insert(d);
                    stack.push(d);
                }
            }
        }
        reach
    }

    /// Every constraint's margin for `curves`; `deviation` is their largest displacement at
    /// equilibrium when it was evaluated ([`max_displacement`]).
    pub fn margins(&self, curves: &[usize], deviation: Option<f64>) -> Margins {
        let set = CurveSet::from_curves(self.n, curves);
        let split = |sets: &[CurveSet]| {
            sets.iter()
                .filter(|g| g.intersects(&set) && !g.is_subset(&set))
                .count() as f64
        };
        let max_gap = self.coverage.as_ref().map(|cov| {
            let g = cov.gap(curves);
            Margin {
                at: Some(g.at.to_array()),
                resolution: Some(cov.spacing()),
                ..Margin::upper(g.value, cov.limit())
            }
        });
        Margins {
            budget: Margin::upper(self.length(curves), self.budget),
            keep: (!self.keep.is_empty()).then(|| {
                let missing = self.keep.iter().filter(|&&k| !set.contains(k)).count();
                Margin::upper(missing as f64, 0.0)
            }),
            groups: (!self.groups.is_empty()).then(|| Margin::upper(split(&self.groups), 0.0)),
            symmetry: self
                .symmetry
                .as_ref()
                .map(|_| Margin::upper(split(&self.orbits), 0.0)),
            connected: self
                .adjacency
                .as_ref()
                .map(|_| Margin::upper(self.parts(&set) as f64, 1.0)),
            min_curves: self
                .params
                .min_curves
                .map(|k| Margin::lower(set.len() as f64, k as f64)),
            max_gap,
            max_deviation: self
                .params
                .max_deviation
                .zip(deviation)
                .map(|(d, v)| Margin::upper(v, d)),
        }
    }

    /// Whether a largest displacement `deviation` meets `--max-deviation` (always without it).
    pub fn deviation_ok(&self, deviation: f64) -> bool {
        self.params.max_deviation.is_none_or(|d| deviation <= d)
    }
}

/// The largest displacement of a vertex of `curves`' rods: `max_v |u_v|` over the structure's
/// vertices (the `--max-deviation` of a network at its equilibrium `u`, a displacement from the
/// rest state, 3 coordinates per vertex of `net`).
pub fn max_displacement(net: &Network, curves: &[usize], u: &[f64]) -> f64 {
    let mut worst = 0.0f64;
    for &c in curves {
        for &v in &net.rods[c].vertices {
            let i = 3 * v as usize;
            if let Some(d) = u.get(i..i + 3) {
                worst = worst.max((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests;
