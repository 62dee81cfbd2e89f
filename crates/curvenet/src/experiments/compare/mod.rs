//! The paper's quantitative experiment (Fig. 10): greedy against exhaustive and random search
//! on random networks.
//!
//! For every size `N` and instance `i`, `N` random geodesics are traced on one of the given
//! surfaces (scaled to a largest extent of 4000, the reference's command-line scenes), built
//! at `h = 100` with clamped supports, and simplified to the budget by
//! - the greedy (its final set re-evaluated with [`crate::stability::Analyzer::lambda_eq`],
//!   like every other set),
//! - exhaustive search (every feasible subset: the optimum and the greedy's percentile),
//! - random search with as many evaluations as the greedy spent (every candidate of every
//!   iteration, as the paper's greedy evaluates them, plus one per iteration),
//! - the greedy followed by the local search of [`crate::simplify::local`]: its default
//!   (first-improvement descent with part steps, then variable-depth chains, from the greedy's
//!   final set and from the best single curves) and, for comparison, single improving moves
//!   (first improvement, no part steps) from the greedy's final set alone, each with an
//!   analyzer of its own so its time and the structures it relaxed are its own (no help from
//!   the other searches' cache),
//! - the multi-start local search: single moves from the greedy's set and from every curve
//!   alone, the best outcome,
//! - the rounded relaxation: the best `λ_fix` among the roundings of the relaxed faces'
//!   solutions (and the faces' first curves) of [`crate::simplify::certificate::certify`], re-evaluated on
//!   `λ_eq`; the same run gives the certified upper bound on `λ_fix`,
//! - the exact optimum of `λ_fix` ([`crate::simplify::exact`]), checked against exhaustive
//!   search over `λ_fix`, and the `λ_eq` of its answer.
//!
//! Every `λ_eq` ratio is against the exhaustive optimum of `λ_eq`; the `λ_fix` figures are at
//! the full network's equilibrium. Everything is seeded; the report depends only on the
//! parameters. The figures measured with it are in `docs/compare.md`.
//!
//! - [`instance`]: one network's figures ([`InstanceResult`]);
//! - [`summary`]: the figures per size ([`SizeSummary`]) and the report ([`CompareReport`]);
//! - [`fresh`]: the generalisation measurement on networks drawn afresh (sizes, budgets,
//!   surfaces and seeds varied), the searches that give a run's answer against the optimum
//!   ([`fresh()`], [`FreshReport`]);
//! - [`constrained`]: what each design constraint costs, on given networks and random ones
//!   ([`constrained()`], [`ConstrainedReport`]).
//!
//! Both draw their random networks alike ([`RandomDraw`]: how many, the base seed, the ranges of
//! curves and budgets, the edge length).

pub mod constrained;
pub mod fresh;
pub mod instance;
pub mod summary;

pub use constrained::{
    Case, CaseError, ConstrainedParams, ConstrainedReport, ConstrainedRow, constrained,
};
pub use fresh::{FreshParams, FreshReport, FreshRow, fresh};
pub use instance::{InstanceResult, instance_network};
pub use summary::{CompareReport, SizeSummary};

use crate::constraints::{ConstraintParams, Constraints};
use crate::io::TriMesh;
use crate::network::Network;
use crate::paper::DataSource;
use crate::rng::SplitMix64;
use crate::simplify::{Budget, SimplifyError};
use crate::trace::{SurfaceError, read_surface, scale_to_extent};
use crate::words::Message;
use instance::traced_network;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;

/// Parameters of the experiment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CompareParams {
    /// Numbers of curves `N`.
    pub sizes: Vec<usize>,
    /// Instances per size.
    pub instances: usize,
    /// Budget fraction.
    pub budget: f64,
    /// Base seed.
    pub seed: u32,
    /// Edge length `h` (scene units, surfaces at extent 4000).
    pub edge_length: f64,
    /// Largest number of feasible subsets exhaustive search may evaluate.
    pub max_subsets: usize,
    /// Time limit of the exact solver per instance, seconds.
    #[serde(default = "default_exact_time")]
    pub exact_time_limit: f64,
}

fn default_exact_time() -> f64 {
    60.0
}

impl Default for CompareParams {
    fn default() -> Self {
        CompareParams {
            sizes: vec![10, 12, 14, 16],
            instances: 10,
            budget: 0.3,
            seed: 1,
            edge_length: 100.0,
            max_subsets: 200_000,
            exact_time_limit: default_exact_time(),
        }
    }
}

/// A named surface to trace on.
#[derive(Clone, Debug)]
pub struct Surface {
    /// Name for reports.
    pub name: String,
    /// The mesh (any scale; it is scaled to extent 4000).
    pub mesh: TriMesh,
}

/// The surfaces `names` name, to trace on: the paper's simple surfaces
/// ([`crate::paper::SIMPLE_SURFACES`], read from `data`), OBJ files or built-in surfaces
/// ([`crate::trace::read_surface`]); and what reading them found.
pub fn surfaces(
    names: &[String],
    data: &DataSource,
) -> Result<(Vec<Surface>, Vec<String>), SurfaceError> {
    let mut warnings = Vec::new();
    let mut surfaces = Vec::new();
    for name in names {
        let mesh = if crate::paper::SIMPLE_SURFACES.contains(&name.as_str()) {
            let file = data.read_mesh(&format!("{name}.obj"))?;
            warnings.extend(file.warnings.iter().map(|w| w.to_string()));
            file.mesh
        } else {
            let (mesh, _, read) = read_surface(Path::new(name))?;
            warnings.extend(read);
            mesh
        };
        surfaces.push(Surface {
            name: name.clone(),
            mesh,
        });
    }
    Ok((surfaces, warnings))
}

impl CompareParams {
    /// Checks the parameters: sizes within 2..=30 (exhaustive search is exponential), at least
    /// one instance, a budget fraction in `(0, 1]`, a positive edge length and subset limit, a
    /// time limit between 0 and [`crate::simplify::exact::MAX_TIME_LIMIT`] seconds.
    pub fn validate(&self) -> Result<(), Message> {
        if self.sizes.is_empty() || self.sizes.iter().any(|n| !(2..=30).contains(n)) {
            return Err(format!(
                "sizes must be given and lie between 2 and 30 (exhaustive search is \
                 exponential), got {:?}",
                self.sizes
            )
            .into());
        }
        if self.instances == 0 {
            return Err("instances must be at least 1".into());
        }
        Budget::Fraction(self.budget).validate()?;
        check_build(self.edge_length, self.max_subsets)?;
        let max = crate::simplify::exact::MAX_TIME_LIMIT;
        if !(0.0..=max).contains(&self.exact_time_limit) {
            return Err(format!(
                "the exact solver's time limit must lie between 0 and {max:e} seconds, got {}",
                self.exact_time_limit
            )
            .into());
        }
        Ok(())
    }
}

/// Checks what both measurements share: a positive edge length and subset limit.
fn check_build(edge_length: f64, max_subsets: usize) -> Result<(), Message> {
    if !(edge_length.is_finite() && edge_length > 0.0) {
        return Err(format!("edge length must be a positive number, got {edge_length}").into());
    }
    if max_subsets == 0 {
        return Err("the subset limit must be at least 1".into());
    }
    Ok(())
}

/// What a random draw of networks varies (`compare --fresh`, `compare --constraints`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RandomDraw {
    /// Networks to draw.
    pub networks: usize,
    /// Base seed.
    pub seed: u32,
    /// Fewest curves of a network.
    pub min_curves: usize,
    /// Most curves of a network.
    pub max_curves: usize,
    /// Smallest budget fraction.
    pub min_budget: f64,
    /// Largest budget fraction.
    pub max_budget: f64,
    /// Edge length `h` (scene units, surfaces at extent 4000).
    pub edge_length: f64,
}

impl RandomDraw {
    /// Checks the ranges: `2 ≤ min_curves ≤ max_curves ≤ most`, `0 < min_budget ≤ max_budget
    /// ≤ 1`.
    fn validate(&self, most: usize) -> Result<(), String> {
        let (c0, c1, b0, b1) = (
            self.min_curves,
            self.max_curves,
            self.min_budget,
            self.max_budget,
        );
        if !(2 <= c0 && c0 <= c1 && c1 <= most) {
            return Err(format!(
                "the numbers of curves must satisfy 2 ≤ {c0} ≤ {c1} ≤ {most}"
            ));
        }
        if !(0.0 < b0 && b0 <= b1 && b1 <= 1.0) {
            return Err(format!("the budgets must satisfy 0 < {b0} ≤ {b1} ≤ 1"));
        }
        Ok(())
    }

    /// The draw in words: `seed 1; 8–18 curves, budgets 0.10–0.50, surfaces a, b`.
    fn describe(&self, surfaces: &[String]) -> String {
        format!(
            "seed {}; {}–{} curves, budgets {:.2}–{:.2}, surfaces {}",
            self.seed,
            self.min_curves,
            self.max_curves,
            self.min_budget,
            self.max_budget,
            surfaces.join(", ")
        )
    }

    /// Network `k`, as `make(surface, curves, budget fraction, tracing seed, network)` gives
    /// it: a SplitMix64 stream seeded by the base seed times `mix`, plus `k`, draws the number
    /// of curves (uniform), the budget (uniform, rounded to 0.01) and the tracing seed; the
    /// `scaled` surfaces are taken in rotation. A network whose tracing or build fails is
    /// drawn again (up to 20 times).
    fn network<T>(
        &self,
        scaled: &[(String, TriMesh)],
        k: usize,
        mix: u64,
        make: impl FnOnce(&str, usize, f64, u32, Network) -> T,
    ) -> Result<T, SimplifyError> {
        let seed = u64::from(self.seed).wrapping_mul(mix);
        let mut rng = SplitMix64::new(seed.wrapping_add(k as u64));
        let (name, mesh) = &scaled[k % scaled.len()];
        let span = (self.max_curves - self.min_curves + 1) as u64;
        for _ in 0..20 {
            let n = self.min_curves + rng.below(span) as usize;
            let budget = (100.0 * rng.uniform(self.min_budget, self.max_budget)).round() / 100.0;
            let budget = budget.clamp(self.min_budget, self.max_budget);
            let seed = rng.next_u64() as u32;
            if let Some(network) = traced_network(mesh, n, seed, self.edge_length) {
                return Ok(make(name, n, budget, seed, network));
            }
        }
        Err(SimplifyError::Params(
            format!("network {k}: could not build a network on {name} after 20 tries").into(),
        ))
    }
}

/// The surfaces scaled to the experiments' extent, 4000.
fn scaled<'a>(surfaces: impl Iterator<Item = (&'a String, &'a TriMesh)>) -> Vec<(String, TriMesh)> {
    surfaces
        .map(|(name, m)| (name.clone(), scale_to_extent(m, 4000.0).0))
        .collect()
}

/// The constraints that keep only the connected subsets of `network` within `cap` (and
/// keeping `keep`): exhaustive search over them finds the optimum (see [`mod@fresh`]).
fn connected_only(
    network: &Network,
    cap: f64,
    keep: &[usize],
) -> Result<Constraints, SimplifyError> {
    let only = ConstraintParams {
        connected: true,
        ..ConstraintParams::default()
    };
    Constraints::new(network, None, &only, cap, keep)
        .map_err(|e| SimplifyError::Params(e.to_string().into()))
}

/// Mean of the values (NaN when there is none).
fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, count) = values.fold((0.0, 0usize), |(s, c), v| (s + v, c + 1));
    sum / count as f64
}

/// Runs the experiment; `progress(done, total)` is called after each instance.
pub fn compare(
    params: &CompareParams,
    surfaces: &[Surface],
    progress: &dyn Fn(usize, usize),
) -> Result<CompareReport, SimplifyError> {
    if surfaces.is_empty() {
        return Err(SimplifyError::Params("compare needs surfaces".into()));
    }
    params.validate().map_err(SimplifyError::Params)?;
    let scaled = scaled(surfaces.iter().map(|s| (&s.name, &s.mesh)));
    let total = params.sizes.len() * params.instances;
    let mut instances = Vec::new();
    let mut summary = Vec::new();
    for &n in &params.sizes {
        let start = Instant::now();
        let mut rows = Vec::new();
        for i in 0..params.instances {
            rows.push(instance::run(&scaled, n, i, params)?);
            progress(instances.len() + rows.len(), total);
        }
        summary.push(SizeSummary::of(n, &rows, start.elapsed().as_secs_f64()));
        instances.extend(rows);
    }
    Ok(CompareReport {
        params: params.clone(),
        surfaces: scaled.into_iter().map(|s| s.0).collect(),
        instances,
        summary,
    })
}
