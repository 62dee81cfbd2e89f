//! The session's design constraints: groups, symmetry, connected, min-curves, max-gap,
//! max-deviation ([`curvenet::constraints`], as `simplify` takes them), set over HTTP for the
//! served network; the greedy and the local search started afterwards honour them, and every
//! state answer gives the current structure's margin for each.
//!
//! Setting them checks them against the whole network (groups naming unknown curves, a
//! symmetry the network lacks, `max_gap` without a surface or beyond what every curve
//! covers, …: refused with the reason); a search binds them to its own budget and keep list
//! when it starts, which may find them infeasible there (refused with the reason). The
//! margins are those of the budget of the search started last (none before the first).

use crate::design::Evaluated;
use crate::words::{Fields, say};
use curvenet::app::{Search, Silent};
use curvenet::constraints::{
    ConstraintError, ConstraintParams, Constraints, Group, SymmetryOption, max_displacement,
    parse_groups,
};
use curvenet::io::TriMesh;
use curvenet::network::Network;
use curvenet::simplify::Budget;
use serde::Deserialize;
use serde_json::{Value, json};

/// Groups as a request gives them: lists of curve ids, or the text of a groups file (one
/// group per line, `NAME: 0 1 4-7`).
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum GroupsBody {
    /// `[[0, 1], [2, 3]]`.
    Lists(Vec<Vec<usize>>),
    /// `"wings: 0 1\nfeet: 4-7"`.
    Text(String),
}

impl Default for GroupsBody {
    fn default() -> Self {
        GroupsBody::Lists(Vec::new())
    }
}

/// The body of `POST /api/constraints`: every field optional; an empty object clears them.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstraintsBody {
    /// Curves kept or removed together.
    #[serde(default)]
    pub groups: GroupsBody,
    /// `rotate:N`, `mirror`, `auto` or `none`.
    #[serde(default)]
    pub symmetry: Option<String>,
    /// The kept curves form one connected structure.
    #[serde(default)]
    pub connected: bool,
    /// At least this many curves.
    #[serde(default)]
    pub min_curves: Option<usize>,
    /// Largest distance from a point of the surface to a kept curve (scene units).
    #[serde(default)]
    pub max_gap: Option<f64>,
    /// Largest displacement of a vertex from its designed place at equilibrium (scene units;
    /// in the physical mode the physical model's, under self-weight).
    #[serde(default)]
    pub max_deviation: Option<f64>,
}

impl ConstraintsBody {
    /// The settings of the body.
    ///
    /// # Errors
    ///
    /// A message for a bad symmetry, a groups text that does not parse, or values out of
    /// range.
    pub fn params(self) -> Result<ConstraintParams, String> {
        let groups = match self.groups {
            GroupsBody::Lists(lists) => lists
                .into_iter()
                .enumerate()
                .map(|(i, mut curves)| {
                    curves.sort_unstable();
                    curves.dedup();
                    Group {
                        name: format!("group {}", i + 1),
                        curves,
                        origin: format!("groups[{i}]"),
                    }
                })
                .collect(),
            GroupsBody::Text(text) => parse_groups(&text, "groups").map_err(|e| e.to_string())?,
        };
        let symmetry = match &self.symmetry {
            Some(s) => s.parse::<SymmetryOption>()?,
            None => SymmetryOption::None,
        };
        let p = ConstraintParams {
            groups,
            symmetry,
            connected: self.connected,
            min_curves: self.min_curves,
            max_gap: self.max_gap,
            max_deviation: self.max_deviation,
            ..ConstraintParams::default()
        };
        p.validate().map_err(|m| say(&m))?;
        Ok(p)
    }
}

/// The constraints in force for one served network.
#[derive(Debug, Default)]
pub struct SessionConstraints {
    params: ConstraintParams,
    /// Bound to the whole network (its total length, no keep list): the margins' source.
    bound: Option<Constraints>,
    /// The budget of the search started last (a length).
    budget: Option<f64>,
    /// The scene's length unit in the physical mode, where the largest deviation is the
    /// physical model's (its notes say so).
    pub physical_unit: Option<String>,
}

impl SessionConstraints {
    /// The settings in force.
    pub fn params(&self) -> &ConstraintParams {
        &self.params
    }

    /// What checking them found (the symmetry detected, groups widened, …), one line each.
    pub fn notes(&self) -> Vec<String> {
        self.bound
            .as_ref()
            .map_or_else(Vec::new, |c| c.notes().iter().map(say).collect())
    }

    /// Puts `params` in force for `net` (with its surface `mesh`); nothing changes on an
    /// error.
    ///
    /// # Errors
    ///
    /// Why they cannot be used on this network (a message for the user).
    pub fn set(
        &mut self,
        net: &Network,
        mesh: Option<&TriMesh>,
        params: ConstraintParams,
    ) -> Result<(), String> {
        let bound = if params.is_default() {
            None
        } else {
            let all: Vec<usize> = (0..net.rods.len()).collect();
            let mut c = bind(net, mesh, &params, net.total_length(&all), &[])?;
            if let Some(u) = &self.physical_unit {
                c.deviation_measured_physically(u);
            }
            Some(c)
        };
        self.params = params;
        self.bound = bound;
        Ok(())
    }

    /// The search of `budget` and `keep` on `net` (with its surface `mesh`) under the
    /// constraints in force, bound by the application layer as a run binds its own
    /// ([`Search::new`]); the budget is remembered for the margins.
    ///
    /// # Errors
    ///
    /// A budget out of range, an unknown curve to keep, a keep list holding every curve, or
    /// constraints no network within that budget and keep list can meet (why, in the API's
    /// words).
    pub fn for_search(
        &mut self,
        net: &Network,
        mesh: Option<&TriMesh>,
        budget: Budget,
        keep: Vec<usize>,
    ) -> Result<Search, String> {
        let unit = self.physical_unit.as_deref();
        let params = self.params.clone();
        let search = Search::new(net, mesh, budget, keep, params, false, unit, &Silent)
            .map_err(|e| e.render(&Fields))?;
        self.budget = Some(search.budget_length);
        Ok(search)
    }

    /// The margins of the structure `s` (`None` when no constraint is in force):
    /// `{"met": bool, "margins": {...}}`, each margin `{value, limit, margin, met}`, the
    /// budget's against the search started last. The largest deviation is its equilibrium's
    /// largest displacement, or in the physical mode the physical analysis' (its equilibrium
    /// and self-weight deflection; infinite when unstable), as the searches measure it.
    pub fn margins(&self, net: &Network, s: &Evaluated) -> Option<Value> {
        let c = self.bound.as_ref()?;
        let curves = &s.summary.curves;
        let deviation = self
            .params
            .max_deviation
            .map(|_| match &s.summary.physical {
                Some(p) => p.max_deviation.map_or(f64::INFINITY, |d| d.max),
                None => max_displacement(net, curves, &s.displacement),
            });
        let m = c.margins(curves, deviation);
        let mut v = serde_json::to_value(&m).ok()?;
        match self.budget {
            Some(b) => {
                let length = m.budget.value;
                v["budget"] = json!({
                    "value": length, "limit": b, "margin": b - length, "met": length <= b,
                });
            }
            None => {
                if let Some(o) = v.as_object_mut() {
                    o.remove("budget");
                }
            }
        }
        let met = v
            .as_object()
            .is_some_and(|o| o.values().all(|m| m["met"] == json!(true)));
        Some(json!({ "met": met, "margins": v }))
    }
}

/// `params` bound to `net`, the budget and the keep list, its errors in the API's words.
fn bind(
    net: &Network,
    mesh: Option<&TriMesh>,
    params: &ConstraintParams,
    budget: f64,
    keep: &[usize],
) -> Result<Constraints, String> {
    Constraints::new(net, mesh, params, budget, keep).map_err(|e| match e {
        ConstraintError::Usage(m) => say(&m),
        ConstraintError::Infeasible(m) => {
            format!("the constraints cannot be met: {}", say(&m))
        }
    })
}
