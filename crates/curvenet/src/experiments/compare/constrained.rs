//! What each design constraint costs (`curvenet compare --constraints N`): on given networks
//! (the paper's examples) and on `N` random geodesic networks, the run's answer (the greedy,
//! then the local search from its final network and from the best single units, the answer
//! chosen among them as a run chooses it: stable, feasible, largest `λ_eq`) with no constraint
//! and with each constraint alone, its time, and whether the unconstrained answer — and on the
//! random networks the unconstrained optimum (exhaustive search) — breaks the constraint.
//!
//! The settings, each alone, with values set by one rule per network (not tuned to it):
//! - `symmetry auto`: the largest symmetry the network has that leaves a choice within the
//!   budget (not applicable when it has none: random geodesics never do);
//! - `groups`: curves `2k` and `2k + 1` kept or removed together (random pairs on the random
//!   networks, whose curves are numbered in the order they were drawn);
//! - `connected`;
//! - `max-gap`: [`ConstrainedParams::gap_fraction`] of the surface's extent (the largest side
//!   of its bounding box), or 1.25 times the gap every curve kept leaves when that is larger
//!   (a limit nothing meets would say nothing);
//! - `max-deviation`: [`ConstrainedParams::deviation_fraction`] of the surface's extent;
//! - `min-curves`: [`ConstrainedParams::min_kept`].
//!
//! Each setting runs with an analyzer of its own, so its time is its own (no help from the
//! structures another setting relaxed). The greedy's final network is offered with its
//! record's `λ_eq` and modes (its deviation, under `--max-deviation`, relaxed from the drawn
//! state as the local search measures it); the local search's best network is evaluated in
//! full. On the random networks exhaustive search gives the constrained optimum (over the
//! connected feasible subsets when the setting asks nothing else, as
//! [`super::fresh`] does).

use super::fresh::{COUNT_CAP, reaches};
use super::{RandomDraw, Surface, check_build, connected_only, mean, scaled};
use crate::cancel::Cancel;
use crate::constraints::answer::choose;
use crate::constraints::{ConstraintParams, Constraints, Group, SymmetryOption};
use crate::geom::Aabb;
use crate::io::TriMesh;
use crate::network::Network;
use crate::network::build::BuildError;
use crate::paper::{DataSource, ExampleError};
use crate::rod::ActiveSet;
use crate::run_folder::{evaluated_offer, greedy_offers};
use crate::simplify::exhaustive::{ExhaustiveParams, exhaustive};
use crate::simplify::greedy::{GreedyParams, NoHooks, greedy};
use crate::simplify::local::{LocalParams, local_search};
use crate::simplify::{Budget, SimplifyError};
use crate::stability::{Analyzer, Prepare, Preset, StabilityParams, Warm};
use crate::words::Message;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Parameters of the measurement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConstrainedParams {
    /// The random networks drawn.
    #[serde(flatten)]
    pub draw: RandomDraw,
    /// Exhaustive search on a random network only up to this many subsets.
    pub max_subsets: usize,
    /// `--max-gap` as a fraction of the surface's extent.
    pub gap_fraction: f64,
    /// `--max-deviation` as a fraction of the surface's extent.
    pub deviation_fraction: f64,
    /// `--min-curves`.
    pub min_kept: usize,
}

impl Default for ConstrainedParams {
    fn default() -> Self {
        ConstrainedParams {
            draw: RandomDraw {
                networks: 20,
                seed: 1,
                min_curves: 8,
                max_curves: 12,
                min_budget: 0.2,
                max_budget: 0.4,
                edge_length: 100.0,
            },
            max_subsets: 20_000,
            gap_fraction: 0.3,
            deviation_fraction: 0.001,
            min_kept: 3,
        }
    }
}

impl ConstrainedParams {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), Message> {
        self.draw.validate(20)?;
        for (name, f) in [
            ("gap", self.gap_fraction),
            ("deviation", self.deviation_fraction),
        ] {
            if !(f.is_finite() && f > 0.0) {
                return Err(format!("the {name} fraction must be positive, got {f}").into());
            }
        }
        if self.min_kept == 0 {
            return Err("the minimum number of curves must be at least 1".into());
        }
        check_build(self.draw.edge_length, self.max_subsets)
    }
}

/// A network to measure on: its surface, budget and keep list.
pub struct Case {
    /// Name for reports.
    pub name: String,
    /// The network.
    pub network: Network,
    /// Its surface (at the network's scale).
    pub mesh: TriMesh,
    /// The budget.
    pub budget: Budget,
    /// Curves every network keeps.
    pub keep: Vec<usize>,
    /// Whether to find the optima by exhaustive search (small networks only).
    pub exhaustive: bool,
}

impl Case {
    /// The paper's example `name` (read from `data`) with its own budget and keep list, its
    /// optima not searched for.
    pub fn example(name: &str, data: &DataSource) -> Result<Case, CaseError> {
        let ex = crate::paper::load_from(name, data, Default::default())?;
        let (network, _) = crate::network::build_network(&ex.curves, &ex.build)?;
        Ok(Case {
            name: name.to_string(),
            network,
            mesh: ex.mesh,
            budget: Budget::Fraction(ex.setup.budget_fraction),
            keep: ex.setup.keep.clone(),
            exhaustive: false,
        })
    }
}

/// Why a paper's example could not be made a [`Case`].
#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    /// The example could not be loaded.
    #[error(transparent)]
    Example(#[from] ExampleError),
    /// Its network could not be built.
    #[error(transparent)]
    Build(#[from] BuildError),
}

/// The settings measured, in the report's order.
pub const SETTINGS: [&str; 7] = [
    "none",
    "symmetry auto",
    "groups",
    "connected",
    "max-gap",
    "max-deviation",
    "min-curves",
];

/// One network under one setting.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ConstrainedRow {
    /// The network.
    pub case: String,
    /// Whether it is a random network (else one of the given cases).
    pub random: bool,
    /// Its curves.
    pub n: usize,
    /// Budget fraction (or length, as given).
    pub budget: String,
    /// The setting ([`SETTINGS`]).
    pub setting: String,
    /// The constraint's value (the distance, the count; the symmetry found).
    pub value: String,
    /// Why the setting does not apply or nothing can meet it (no run then).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub skipped: Option<String>,
    /// `λ_eq` of the answer (`None`: no answer).
    pub lambda: Option<f64>,
    /// Its curves.
    pub curves: Vec<usize>,
    /// Which search found it.
    pub source: String,
    /// Why there is no answer.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub no_answer: Option<String>,
    /// Wall time of the greedy, the local search and the answer's evaluation (seconds).
    pub seconds: f64,
    /// Whether the unconstrained answer breaks this setting's constraint.
    pub unconstrained_answer_breaks: Option<bool>,
    /// The optimum `λ_eq` under the setting (exhaustive search), on the random networks.
    pub optimum: Option<f64>,
    /// Whether the unconstrained optimum breaks this setting's constraint.
    pub unconstrained_optimum_breaks: Option<bool>,
}

/// The measurement's report.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConstrainedReport {
    /// Parameters.
    pub params: ConstrainedParams,
    /// Surfaces of the random networks.
    pub surfaces: Vec<String>,
    /// Every network under every setting, network by network.
    pub rows: Vec<ConstrainedRow>,
}

/// Runs the measurement on the `cases` and on `params.draw.networks` random networks traced on
/// `surfaces` (names and meshes, any scale); `progress(done, total)` after each network.
pub fn constrained(
    params: &ConstrainedParams,
    cases: Vec<Case>,
    surfaces: &[Surface],
    progress: &dyn Fn(usize, usize),
) -> Result<ConstrainedReport, SimplifyError> {
    params.validate().map_err(SimplifyError::Params)?;
    let networks = params.draw.networks;
    if networks > 0 && surfaces.is_empty() {
        return Err(SimplifyError::Params(
            "random networks need surfaces".into(),
        ));
    }
    let scaled = scaled(surfaces.iter().map(|s| (&s.name, &s.mesh)));
    let total = cases.len() + networks;
    let mut rows = Vec::new();
    let mut done = 0;
    for case in cases {
        rows.extend(measure(params, &case, false)?);
        done += 1;
        progress(done, total);
    }
    for k in 0..networks {
        let case = draw(params, &scaled, k)?;
        rows.extend(measure(params, &case, true)?);
        done += 1;
        progress(done, total);
    }
    Ok(ConstrainedReport {
        params: params.clone(),
        surfaces: scaled.into_iter().map(|s| s.0).collect(),
        rows,
    })
}

/// Random network `k` of the draw ([`super::draw`]).
fn draw(
    params: &ConstrainedParams,
    scaled: &[(String, TriMesh)],
    k: usize,
) -> Result<Case, SimplifyError> {
    let mix = 0xD1B5_4A32_D192_ED03;
    params
        .draw
        .network(scaled, k, mix, |surface, _, budget, seed, network| Case {
            name: format!("{surface} #{k} (seed {seed})"),
            network,
            mesh: scaled[k % scaled.len()].1.clone(),
            budget: Budget::Fraction(budget),
            keep: Vec::new(),
            exhaustive: true,
        })
}

/// The largest side of the mesh's bounding box.
fn extent(mesh: &TriMesh) -> f64 {
    let e = Aabb::of_points(&mesh.vertices).extent();
    e.x.max(e.y).max(e.z)
}

/// The constraint settings of `setting` on `case` (with the value shown), or why it is
/// skipped.
fn settings_of(
    params: &ConstrainedParams,
    case: &Case,
    setting: &str,
) -> (ConstraintParams, String) {
    let n = case.network.rods.len();
    let mut p = ConstraintParams::default();
    let value = match setting {
        "symmetry auto" => {
            p.symmetry = SymmetryOption::Auto;
            String::new()
        }
        "groups" => {
            p.groups = (0..n / 2)
                .map(|k| Group {
                    name: format!("pair {k}"),
                    curves: vec![2 * k, 2 * k + 1],
                    origin: "the pairs of the comparison".into(),
                })
                .collect();
            format!("{} pairs", n / 2)
        }
        "connected" => {
            p.connected = true;
            String::new()
        }
        "max-gap" => {
            let all: Vec<usize> = (0..n).collect();
            let floor = crate::constraints::Coverage::new(&case.network, &case.mesh, 1.0)
                .map(|c| 1.25 * c.gap(&all).value)
                .unwrap_or(0.0);
            let d = (params.gap_fraction * extent(&case.mesh)).max(floor);
            p.max_gap = Some(d);
            format!("{d:.4e}")
        }
        "max-deviation" => {
            let d = params.deviation_fraction * extent(&case.mesh);
            p.max_deviation = Some(d);
            format!("{d:.4e}")
        }
        "min-curves" => {
            p.min_curves = Some(params.min_kept);
            params.min_kept.to_string()
        }
        _ => String::new(),
    };
    (p, value)
}

/// Every setting on `case`.
fn measure(
    params: &ConstrainedParams,
    case: &Case,
    random: bool,
) -> Result<Vec<ConstrainedRow>, SimplifyError> {
    let n = case.network.rods.len();
    let cap = case.budget.length(case.network.rest_lengths().iter().sum());
    let budget = match case.budget {
        Budget::Fraction(f) => format!("{f:.2}"),
        Budget::Length(l) => format!("{l:.4e}"),
    };
    let mut rows: Vec<ConstrainedRow> = Vec::new();
    // The unconstrained answer's and optimum's curves and deviations.
    let mut free: Option<(Vec<usize>, f64)> = None;
    let mut free_optimum: Option<(Vec<usize>, f64)> = None;
    for setting in SETTINGS {
        let (cp, value) = settings_of(params, case, setting);
        let base = ConstrainedRow {
            case: case.name.clone(),
            random,
            n,
            budget: budget.clone(),
            setting: setting.into(),
            value,
            ..ConstrainedRow::default()
        };
        let (mut row, mut bound) = run_setting(case, &cp, cap, base)?;
        let Some(c) = bound.as_ref() else {
            rows.push(row);
            continue;
        };
        if setting == "none" {
            if row.lambda.is_some() {
                let analyzer = analyzer_of(case)?;
                let dev = analyzer
                    .deviation(&analyzer.set(&row.curves))
                    .unwrap_or(f64::NAN);
                free = Some((row.curves.clone(), dev));
            }
        } else {
            let breaks = |(curves, dev): &(Vec<usize>, f64)| {
                c.check(curves).is_err() || !c.deviation_ok(*dev)
            };
            row.unconstrained_answer_breaks = free.as_ref().map(breaks);
            row.unconstrained_optimum_breaks = free_optimum.as_ref().map(breaks);
        }
        if random && case.exhaustive {
            let analyzer = analyzer_of(case)?;
            let constraints = if setting == "none" {
                connected_only(&case.network, cap, &case.keep)?
            } else {
                bound.take().expect("bound")
            };
            let ex = exhaustive(
                &analyzer,
                &ExhaustiveParams {
                    budget: case.budget,
                    keep: case.keep.clone(),
                    max_subsets: params.max_subsets.min(COUNT_CAP),
                },
                Some(&constraints),
                &Cancel::never(),
            );
            if let Ok(ex) = ex {
                row.optimum = Some(ex.best.lambda);
                if setting == "none" {
                    let dev = analyzer
                        .deviation(&analyzer.set(&ex.best.curves))
                        .unwrap_or(f64::NAN);
                    free_optimum = Some((ex.best.curves.clone(), dev));
                }
            }
        }
        rows.push(row);
    }
    Ok(rows)
}

/// A fresh analyzer of `case`'s network.
fn analyzer_of(case: &Case) -> Result<Analyzer, SimplifyError> {
    Analyzer::new(case.network.clone(), StabilityParams::default()).map_err(SimplifyError::from)
}

/// One setting's run: the constraints bound, the greedy, the local search, the answer chosen;
/// its row, and the constraints bound (`None` when it did not run) to test the unconstrained
/// networks against.
fn run_setting(
    case: &Case,
    cp: &ConstraintParams,
    cap: f64,
    mut row: ConstrainedRow,
) -> Result<(ConstrainedRow, Option<Constraints>), SimplifyError> {
    let constraints = match Constraints::new(&case.network, Some(&case.mesh), cp, cap, &case.keep) {
        Ok(c) => c,
        Err(e) => {
            row.skipped = Some(e.to_string());
            return Ok((row, None));
        }
    };
    if cp.symmetry == SymmetryOption::Auto {
        match constraints.symmetry() {
            Some(s) => row.value = s.option().to_string(),
            None => {
                row.skipped = Some("no symmetry".into());
                return Ok((row, None));
            }
        }
    }
    let analyzer = analyzer_of(case)?;
    let start = Instant::now();
    let gp = GreedyParams {
        keep: case.keep.clone(),
        ..GreedyParams::new(case.budget)
    };
    let g = match greedy(&analyzer, &gp, Some(&constraints), None, &mut NoHooks) {
        Ok(g) => g,
        Err(e) => {
            row.skipped = Some(format!("the greedy failed: {e}"));
            return Ok((row, None));
        }
    };
    let mut offers = greedy_offers(&g.iterations);
    if cp.max_deviation.is_some()
        && let Some(last) = offers.last_mut()
    {
        last.deviation = analyzer.deviation(&analyzer.set(&last.curves)).ok();
    }
    let last = g.iterations.last().expect("one iteration at least");
    let lp = LocalParams {
        keep: case.keep.clone(),
        ..LocalParams::new(case.budget)
    };
    if let Ok(o) = local_search(
        &analyzer,
        &lp,
        Some(&constraints),
        &last.curves,
        &Cancel::never(),
    ) && o.best.lambda.is_finite()
    {
        let active = ActiveSet::from_curves(case.network.rods.len(), &o.best.curves);
        if let Ok(e) =
            analyzer.evaluate(&active, Warm::default(), Preset::Analysis, Prepare::Nothing)
        {
            offers.push(evaluated_offer("local_search", &e, &analyzer, &constraints));
        }
    }
    let choice = choose(&constraints, &offers, 0);
    row.seconds = start.elapsed().as_secs_f64();
    match choice.answer {
        Ok(a) => {
            row.lambda = Some(a.found.lambda);
            row.curves = a.found.curves;
            row.source = a.found.source;
        }
        Err(e) => row.no_answer = Some(e.reason.render(&crate::words::Recorded)),
    }
    Ok((row, Some(constraints)))
}

impl ConstrainedReport {
    /// The summary over the random networks and the per-network table, as Markdown.
    pub fn markdown(&self) -> String {
        let mut s = String::new();
        let cases: Vec<&ConstrainedRow> = self.rows.iter().filter(|r| !r.random).collect();
        if !cases.is_empty() {
            s.push_str(
                "| network | constraint | value | answer λ_eq | × unconstrained | curves | seconds | unconstrained answer breaks it |\n\
                 |---|---|---|---|---|---|---|---|\n",
            );
            for r in &cases {
                s.push_str(&self.case_line(r));
            }
            s.push('\n');
        }
        let random: Vec<&ConstrainedRow> = self.rows.iter().filter(|r| r.random).collect();
        if random.is_empty() {
            return s;
        }
        let d = &self.params.draw;
        let what = d.describe(&self.surfaces);
        s.push_str(&format!(
            "{} random geodesic networks ({what}):\n\n",
            d.networks
        ));
        s.push_str(
            "| constraint | networks run | no answer | answer λ_eq / unconstrained answer's (mean) | answer / constrained optimum (mean) | constrained optimum reached | seconds (mean) | unconstrained answer breaks it | unconstrained optimum breaks it |\n\
             |---|---|---|---|---|---|---|---|---|\n",
        );
        for setting in SETTINGS {
            s.push_str(&self.setting_line(setting, &random));
        }
        s
    }

    /// The `none` row of `r`'s network.
    fn baseline(&self, r: &ConstrainedRow) -> Option<&ConstrainedRow> {
        self.rows
            .iter()
            .find(|b| b.case == r.case && b.setting == "none")
    }

    fn case_line(&self, r: &ConstrainedRow) -> String {
        let value = if r.value.is_empty() { "—" } else { &r.value };
        if let Some(why) = &r.skipped {
            return format!(
                "| {} | {} | {value} | n/a ({}) | | | | |\n",
                r.case,
                r.setting,
                why.replace('|', "/")
            );
        }
        let (lambda, times) = match r.lambda {
            Some(l) => (
                format!("{l:.4e}"),
                self.baseline(r)
                    .and_then(|b| b.lambda)
                    .map_or("—".into(), |b| format!("{:.2}", l / b)),
            ),
            None => (
                format!(
                    "no answer ({})",
                    r.no_answer.as_deref().unwrap_or("").replace('|', "/")
                ),
                "—".into(),
            ),
        };
        let breaks = match r.unconstrained_answer_breaks {
            Some(true) => "yes",
            Some(false) => "no",
            None => "—",
        };
        format!(
            "| {} | {} | {value} | {lambda} | {times} | {} | {:.1} | {breaks} |\n",
            r.case,
            r.setting,
            r.curves.len(),
            r.seconds
        )
    }

    fn setting_line(&self, setting: &str, random: &[&ConstrainedRow]) -> String {
        let rows: Vec<&&ConstrainedRow> = random
            .iter()
            .filter(|r| r.setting == setting && r.skipped.is_none())
            .collect();
        if rows.is_empty() {
            return format!("| {setting} | 0 | | | | | | | |\n");
        }
        let no_answer = rows.iter().filter(|r| r.lambda.is_none()).count();
        let vs_free = mean(rows.iter().filter_map(|r| {
            let b = self.baseline(r)?.lambda?;
            Some(r.lambda.unwrap_or(0.0) / b)
        }));
        let decided: Vec<_> = rows.iter().filter(|r| r.optimum.is_some()).collect();
        let vs_opt = mean(
            decided
                .iter()
                .map(|r| r.lambda.unwrap_or(0.0) / r.optimum.unwrap_or(f64::NAN)),
        );
        let reached = decided
            .iter()
            .filter(|r| {
                let o = r.optimum.unwrap_or(f64::NAN);
                r.lambda.is_some_and(|l| reaches(l, o))
            })
            .count();
        let count = |f: &dyn Fn(&ConstrainedRow) -> Option<bool>| {
            let known: Vec<bool> = rows.iter().filter_map(|r| f(r)).collect();
            if setting == "none" {
                "—".to_string()
            } else {
                format!("{}/{}", known.iter().filter(|&&b| b).count(), known.len())
            }
        };
        format!(
            "| {setting} | {} | {no_answer} | {:.1}% | {:.1}% | {reached}/{} | {:.2} | {} | {} |\n",
            rows.len(),
            100.0 * vs_free,
            100.0 * vs_opt,
            decided.len(),
            mean(rows.iter().map(|r| r.seconds)),
            count(&|r| r.unconstrained_answer_breaks),
            count(&|r| r.unconstrained_optimum_breaks),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two small random networks: every setting runs or says why not, every answer meets its
    /// setting's constraints, and no answer beats the constrained optimum.
    #[test]
    fn two_small_networks() {
        let params = ConstrainedParams {
            draw: RandomDraw {
                networks: 2,
                min_curves: 7,
                max_curves: 8,
                min_budget: 0.3,
                max_budget: 0.35,
                ..ConstrainedParams::default().draw
            },
            ..ConstrainedParams::default()
        };
        let dome = Surface {
            name: "dome".into(),
            mesh: crate::trace::builtin_surface("dome").expect("dome"),
        };
        let r = constrained(&params, Vec::new(), &[dome], &|_, _| {}).expect("runs");
        assert_eq!(r.rows.len(), 2 * SETTINGS.len());
        for row in &r.rows {
            if row.setting == "symmetry auto" {
                assert_eq!(row.skipped.as_deref(), Some("no symmetry"), "{row:?}");
                continue;
            }
            if let (Some(l), Some(o)) = (row.lambda, row.optimum) {
                assert!(l <= o * (1.0 + 1e-6), "{row:?}");
            }
            if row.setting != "none" && row.skipped.is_none() {
                assert!(row.unconstrained_answer_breaks.is_some(), "{row:?}");
            }
        }
        let md = r.markdown();
        assert!(md.contains("| connected |"), "{md}");
    }
}
