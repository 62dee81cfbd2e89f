//! The generalisation measurement (`curvenet compare --fresh N`): networks drawn afresh, each
//! with its own surface, size, budget and seed, and the searches that produce a run's answer
//! (the greedy, then the local search from its final network and from the best single curves,
//! [`crate::simplify::local`]) against the exact optimum of `λ_eq` (exhaustive search).
//!
//! Network `k` of `N`: a SplitMix64 stream seeded by the base seed and `k` draws the number of
//! curves (uniform in `min_curves..=max_curves`), the budget (uniform in
//! `[min_budget, max_budget]`, rounded to 0.01) and the tracing seed; the surfaces are taken in
//! rotation. The curves are random geodesics ([`Generator::Random`]) on the surface scaled to
//! extent 4000, built at `h = 100` with clamped supports (as [`super::compare`]'s). A network
//! whose tracing or build fails is drawn again (up to 20 times).
//!
//! The optimum is found by exhaustive search over the *connected* feasible subsets only. That
//! is exact: a set's `λ_eq` is the smallest `λ_eq` of its connected parts (the parts are
//! independent structures, [`Analyzer::parts_of`]), and each part of a feasible set is itself
//! a connected feasible set (shorter, and there is no keep list), so some connected feasible
//! set is at least as stable as any feasible set. Every part of every feasible set is one of
//! these connected sets, so enumerating all the feasible subsets would relax exactly the same
//! structures (they are cached by part); leaving out the disconnected sets leaves out only
//! their enumeration and bookkeeping, which is what made networks of 15–18 curves (up to
//! 100,000 feasible subsets) out of reach before.
//!
//! Exhaustive search is still exponential: it runs on networks of at most
//! `exhaustive_max_curves` curves whose connected feasible subsets number at most
//! `max_subsets`; the others are reported as skipped (with the greedy's and the local search's
//! figures, no ratio), and so is a network on which no curve fits the budget (no subset is
//! feasible; the greedy's figure only). The report gives, over
//! the networks decided, the mean of (greedy + local search) / optimum and how many reach the
//! optimum (within the relative tolerance 1e-6: the searches and exhaustive search share one
//! evaluation, so an optimum found is the same number).

use super::{RandomDraw, Surface, check_build, connected_only, mean, scaled};
use crate::cancel::Cancel;
use crate::constraints::Constraints;
use crate::io::TriMesh;
use crate::network::Network;
use crate::rod::ActiveSet;
use crate::simplify::exhaustive::{ExhaustiveParams, exhaustive};
use crate::simplify::greedy::{GreedyParams, NoHooks, greedy};
use crate::simplify::local::{LocalParams, local_search};
use crate::simplify::{Budget, SimplifyError, StopReason};
use crate::stability::{Analyzer, Objective, StabilityParams};
use crate::words::Message;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Relative tolerance under which a search's `λ_eq` is the optimum.
pub const REACHED: f64 = 1e-6;

/// Feasible subsets counted at most (the count only describes the network; the search runs
/// over the connected ones).
pub const COUNT_CAP: usize = 1_000_000;

/// Parameters of the measurement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FreshParams {
    /// The networks drawn.
    #[serde(flatten)]
    pub draw: RandomDraw,
    /// Exhaustive search only on networks of at most this many curves.
    pub exhaustive_max_curves: usize,
    /// … and at most this many connected feasible subsets (the sets it evaluates).
    pub max_subsets: usize,
    /// What the searches maximise (the figures are its values: `μ_min` under the frequency
    /// objective).
    #[serde(default, skip_serializing_if = "Objective::is_lambda")]
    pub objective: Objective,
}

impl Default for FreshParams {
    fn default() -> Self {
        FreshParams {
            draw: RandomDraw {
                networks: 100,
                seed: 1,
                min_curves: 8,
                max_curves: 18,
                min_budget: 0.1,
                max_budget: 0.5,
                edge_length: 100.0,
            },
            exhaustive_max_curves: 18,
            max_subsets: 20_000,
            objective: Objective::Lambda,
        }
    }
}

impl FreshParams {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), Message> {
        if self.draw.networks == 0 {
            return Err(
                "the measurement on networks drawn afresh needs at least one network".into(),
            );
        }
        self.draw.validate(40)?;
        check_build(self.draw.edge_length, self.max_subsets)
    }
}

/// One network's figures.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FreshRow {
    /// Its place in the draw.
    pub index: usize,
    /// Surface traced on.
    pub surface: String,
    /// Seed of the geodesics.
    pub seed: u32,
    /// Curves.
    pub n: usize,
    /// Budget fraction.
    pub budget: f64,
    /// Vertices of the network.
    pub vertices: usize,
    /// `λ_eq` of the greedy's final network (relaxed from the drawn state).
    pub greedy: f64,
    /// Whether the greedy met the budget (the local search starts from its network only then;
    /// it starts from the best single curves either way).
    pub greedy_within: bool,
    /// `λ_eq` of greedy + local search (the greedy's when no curve fits the budget).
    pub local: f64,
    /// Its curves.
    pub local_curves: Vec<usize>,
    /// The exact optimum of `λ_eq` (`None`: exhaustive search skipped).
    pub optimum: Option<f64>,
    /// Its curves.
    pub optimum_curves: Vec<usize>,
    /// Feasible subsets (counted even when skipped; up to [`COUNT_CAP`], one more meaning
    /// more).
    pub feasible: usize,
    /// Connected feasible subsets, the sets exhaustive search evaluates (up to the subset
    /// limit, one more meaning more).
    #[serde(default)]
    pub connected: usize,
    /// Why exhaustive search was skipped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub skipped: Option<String>,
    /// Wall time of the greedy and the local search (seconds).
    pub search_seconds: f64,
    /// Wall time of exhaustive search (seconds).
    pub exhaustive_seconds: f64,
}

/// Whether a search's `λ_eq` reached the optimum `opt` (within [`REACHED`]).
pub(super) fn reaches(v: f64, opt: f64) -> bool {
    v >= opt - REACHED * opt.abs()
}

/// A search's `λ_eq` over the optimum's, 0 when it found nothing stable.
fn ratio(v: f64, opt: f64) -> f64 {
    if v.is_finite() && opt > 0.0 {
        (v / opt).max(0.0)
    } else {
        0.0
    }
}

/// The measurement's report.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FreshReport {
    /// Parameters.
    pub params: FreshParams,
    /// Surfaces used.
    pub surfaces: Vec<String>,
    /// Every network.
    pub rows: Vec<FreshRow>,
}

impl FreshReport {
    /// Networks whose optimum exhaustive search decided.
    pub fn decided(&self) -> Vec<&FreshRow> {
        self.rows.iter().filter(|r| r.optimum.is_some()).collect()
    }

    /// Over the decided networks, the mean of a search's `λ_eq` (`value` of a row) over the
    /// optimum, and how many reached the optimum.
    fn against_optimum(&self, value: fn(&FreshRow) -> f64) -> (f64, usize) {
        let decided = self.decided();
        let pairs = decided.iter().filter_map(|r| Some((value(r), r.optimum?)));
        let reached = pairs.clone().filter(|&(v, o)| reaches(v, o)).count();
        (mean(pairs.map(|(v, o)| ratio(v, o))), reached)
    }

    /// The summary and the per-network table, as Markdown.
    pub fn markdown(&self) -> String {
        let p = &self.params;
        // The figures are the objective's: λ_eq, or μ_min under the frequency objective.
        let value = p.objective.value_symbol();
        let decided = self.decided();
        let (greedy_mean, greedy_reached) = self.against_optimum(|r| r.greedy);
        let (local_mean, local_reached) = self.against_optimum(|r| r.local);
        let mut s = format!(
            "{} networks drawn afresh ({}); \
             exhaustive search over the connected feasible subsets on {} of them (at most {} \
             curves and {} connected feasible subsets; {} skipped{}).\n\n\
             | search | mean % of the optimum {value} | optimum reached |\n|---|---|---|\n\
             | greedy | {:.1}% | {}/{} ({:.1}%) |\n\
             | greedy + local search | {:.1}% | {}/{} ({:.1}%) |\n",
            self.rows.len(),
            p.draw.describe(&self.surfaces),
            decided.len(),
            p.exhaustive_max_curves,
            p.max_subsets,
            self.rows.len() - decided.len(),
            self.skip_reasons(),
            100.0 * greedy_mean,
            greedy_reached,
            decided.len(),
            percent(greedy_reached, decided.len()),
            100.0 * local_mean,
            local_reached,
            decided.len(),
            percent(local_reached, decided.len()),
        );
        s.push_str(&format!(
            "\n| # | surface | curves | budget | feasible subsets | connected | greedy | greedy + local search | optimum {value} |\n\
             |---|---|---|---|---|---|---|---|---|\n",
        ));
        for r in &self.rows {
            let (g, l, o) = match r.optimum {
                Some(o) => (
                    format!("{:.1}%", 100.0 * ratio(r.greedy, o)),
                    format!("{:.1}%", 100.0 * ratio(r.local, o)),
                    format!("{o:.4e}"),
                ),
                None => (
                    format!("{:.4e}", r.greedy),
                    format!("{:.4e}", r.local),
                    format!("skipped ({})", r.skipped.as_deref().unwrap_or("")),
                ),
            };
            s.push_str(&format!(
                "| {} | {} | {} | {:.2} | {} | {} | {g} | {l} | {o} |\n",
                r.index,
                r.surface,
                r.n,
                r.budget,
                count(r.feasible, COUNT_CAP),
                count(r.connected, p.max_subsets)
            ));
        }
        s
    }
}

impl FreshReport {
    /// Why networks were skipped, counted by reason in order of first appearance
    /// (`": 3 over 14 curves, 1 no curve fits the budget"`; empty when none was).
    fn skip_reasons(&self) -> String {
        let mut counts: Vec<(String, usize)> = Vec::new();
        for r in self.rows.iter().filter(|r| r.optimum.is_none()) {
            let why = match r.skipped.as_deref() {
                Some(w) if w.ends_with(" curves") => {
                    format!("over {} curves", self.params.exhaustive_max_curves)
                }
                Some(w) => w.to_string(),
                None => "not decided".to_string(),
            };
            match counts.iter_mut().find(|c| c.0 == why) {
                Some(c) => c.1 += 1,
                None => counts.push((why, 1)),
            }
        }
        if counts.is_empty() {
            return String::new();
        }
        let parts: Vec<String> = counts.iter().map(|(w, k)| format!("{k} {w}")).collect();
        format!(": {}", parts.join(", "))
    }
}

/// A count that stopped at `cap` (`cap + 1`: more than `cap`).
fn count(k: usize, cap: usize) -> String {
    if k > cap {
        format!("> {cap}")
    } else {
        k.to_string()
    }
}

fn percent(part: usize, whole: usize) -> f64 {
    if whole == 0 {
        f64::NAN
    } else {
        100.0 * part as f64 / whole as f64
    }
}

/// Runs the measurement on `surfaces` (names and meshes, any scale); `progress(done, total)`
/// after each network.
pub fn fresh(
    params: &FreshParams,
    surfaces: &[Surface],
    progress: &dyn Fn(usize, usize),
) -> Result<FreshReport, SimplifyError> {
    params.validate().map_err(SimplifyError::Params)?;
    if surfaces.is_empty() {
        return Err(SimplifyError::Params(
            "the measurement on networks drawn afresh needs surfaces".into(),
        ));
    }
    let scaled = scaled(surfaces.iter().map(|s| (&s.name, &s.mesh)));
    let networks = params.draw.networks;
    let mut rows = Vec::with_capacity(networks);
    for k in 0..networks {
        rows.push(row(params, &scaled, k)?);
        progress(k + 1, networks);
    }
    Ok(FreshReport {
        params: params.clone(),
        surfaces: scaled.into_iter().map(|s| s.0).collect(),
        rows,
    })
}

/// Network `k`: its draw (surface, curves, budget, seed) and the network built.
fn draw(
    params: &FreshParams,
    scaled: &[(String, TriMesh)],
    k: usize,
) -> Result<(FreshRow, Network), SimplifyError> {
    let mix = 0x9E37_79B9_7F4A_7C15;
    params
        .draw
        .network(scaled, k, mix, |surface, n, budget, seed, net| {
            let row = FreshRow {
                index: k,
                surface: surface.into(),
                seed,
                n,
                budget,
                vertices: net.vertex_count(),
                ..FreshRow::default()
            };
            (row, net)
        })
}

/// Network `k`'s figures.
fn row(
    params: &FreshParams,
    scaled: &[(String, TriMesh)],
    k: usize,
) -> Result<FreshRow, SimplifyError> {
    let (mut row, network) = draw(params, scaled, k)?;
    let stability = StabilityParams {
        objective: params.objective,
        ..StabilityParams::default()
    };
    let analyzer = Analyzer::new(network, stability)?;
    let budget = Budget::Fraction(row.budget);
    let never = Cancel::never();
    let t = Instant::now();
    let g = greedy(
        &analyzer,
        &GreedyParams::new(budget),
        None,
        None,
        &mut NoHooks,
    )?;
    let last = g.iterations.last().expect("one iteration at least");
    row.greedy = analyzer.lambda_eq(&ActiveSet::from_curves(row.n, &last.curves))?;
    row.greedy_within = g.stop == StopReason::BudgetMet;
    (row.local, row.local_curves) = (row.greedy, last.curves.clone());
    let lengths = analyzer.lengths();
    let cap = budget.length(lengths.iter().sum());
    // No subset is feasible: nothing for the local search or exhaustive search to find.
    if lengths.iter().all(|&l| l > cap) {
        row.search_seconds = t.elapsed().as_secs_f64();
        row.skipped = Some("no curve fits the budget".into());
        return Ok(row);
    }
    // From the greedy's network when it is within the budget, and from the best single curves.
    let o = local_search(
        &analyzer,
        &LocalParams::new(budget),
        None,
        &last.curves,
        &never,
    )?;
    if o.best.lambda.is_finite() {
        (row.local, row.local_curves) = (o.best.lambda, o.best.curves);
    }
    row.search_seconds = t.elapsed().as_secs_f64();
    row.feasible = Constraints::none(analyzer.network(), cap, &[])
        .feasible_subsets(COUNT_CAP)
        .map_or(COUNT_CAP + 1, |s| s.len());
    if row.n > params.exhaustive_max_curves {
        row.skipped = Some(format!("{} curves", row.n));
        return Ok(row);
    }
    // Only connected sets: exact for the optimum (see the module's doc).
    let connected = connected_only(analyzer.network(), cap, &[])?;
    row.connected = connected
        .feasible_subsets(params.max_subsets)
        .map_or(params.max_subsets + 1, |s| s.len());
    if row.connected > params.max_subsets {
        row.skipped = Some(format!(
            "over {} connected feasible subsets",
            params.max_subsets
        ));
        return Ok(row);
    }
    let t = Instant::now();
    let ex = exhaustive(
        &analyzer,
        &ExhaustiveParams {
            budget,
            keep: Vec::new(),
            max_subsets: params.max_subsets,
        },
        Some(&connected),
        &never,
    )?;
    row.exhaustive_seconds = t.elapsed().as_secs_f64();
    row.optimum = Some(ex.best.lambda);
    row.optimum_curves = ex.best.curves;
    Ok(row)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tables name the objective's value: `μ_min` under the frequency objective.
    #[test]
    fn the_tables_name_the_objective_s_value() {
        let report = |objective| FreshReport {
            params: FreshParams {
                objective,
                ..FreshParams::default()
            },
            surfaces: vec!["dome".into()],
            rows: Vec::new(),
        };
        let f = report(Objective::Frequency).markdown();
        assert!(f.contains("mean % of the optimum μ_min"), "{f}");
        assert!(f.contains("| optimum μ_min |"), "{f}");
        assert!(!f.contains("λ_eq"), "{f}");
        let l = report(Objective::Lambda).markdown();
        assert!(l.contains("| optimum λ_eq |"), "{l}");
    }

    /// The optimum over the connected feasible subsets is the optimum over every feasible
    /// subset (a set is as stable as its weakest part, and each part is feasible alone).
    #[test]
    fn connected_subsets_hold_the_optimum() {
        let params = FreshParams {
            draw: RandomDraw {
                min_curves: 8,
                max_curves: 9,
                min_budget: 0.3,
                max_budget: 0.4,
                ..FreshParams::default().draw
            },
            ..FreshParams::default()
        };
        let surfaces = [(
            "dome".to_string(),
            crate::trace::builtin_surface("dome").expect("dome"),
        )];
        let scaled = scaled(surfaces.iter().map(|(n, m)| (n, m)));
        let mut disconnected_seen = false;
        for k in 0..2 {
            let (row, network) = draw(&params, &scaled, k).expect("drawn");
            let analyzer = Analyzer::new(network, StabilityParams::default()).expect("analyzer");
            let budget = Budget::Fraction(row.budget);
            let ex = |c: Option<&Constraints>| {
                exhaustive(
                    &analyzer,
                    &ExhaustiveParams::new(budget),
                    c,
                    &Cancel::never(),
                )
                .expect("exhaustive")
            };
            let all = ex(None);
            let cap = budget.length(analyzer.lengths().iter().sum());
            let c = connected_only(analyzer.network(), cap, &[]).expect("bound");
            let connected = ex(Some(&c));
            disconnected_seen |= connected.all.len() < all.all.len();
            assert_eq!(
                connected.best.lambda.to_bits(),
                all.best.lambda.to_bits(),
                "network {k}: {:?} against {:?}",
                connected.best,
                all.best
            );
        }
        assert!(
            disconnected_seen,
            "the networks had no disconnected feasible subset"
        );
    }

    /// A network on which no curve fits the budget is skipped with that reason (no subset is
    /// feasible: nothing to search), counted among the skipped, not an error.
    #[test]
    fn networks_no_curve_of_which_fits_the_budget_are_skipped() {
        let mesh = crate::constraints::testing::square_mesh(500.0, 0.0, 8);
        let params = FreshParams {
            draw: RandomDraw {
                networks: 2,
                min_curves: 8,
                max_curves: 8,
                min_budget: 0.01,
                max_budget: 0.01,
                ..FreshParams::default().draw
            },
            ..FreshParams::default()
        };
        let square = Surface {
            name: "square".into(),
            mesh,
        };
        let r = fresh(&params, &[square], &|_, _| {}).expect("runs");
        for row in &r.rows {
            assert_eq!(row.skipped.as_deref(), Some("no curve fits the budget"));
            assert_eq!((row.feasible, row.optimum), (0, None));
            assert_eq!(row.local.to_bits(), row.greedy.to_bits());
            assert!(!row.greedy_within);
        }
        let md = r.markdown();
        assert!(md.contains("2 skipped: 2 no curve fits the budget"), "{md}");
        assert!(md.contains("skipped (no curve fits the budget)"), "{md}");
    }
}
