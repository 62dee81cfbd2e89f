//! `result.json`: the record of a run ([`ResultFile`]) and its parts.

use crate::constraints::answer::{Answer, NoAnswer};
use crate::network::{BuildInfo, BuildParams};
use crate::simplify::GreedyParams;
use crate::simplify::certificate::Certificate;
use crate::simplify::exhaustive::SubsetScore;
use crate::simplify::greedy::{IterationRecord, StopReason};
use crate::simplify::local::{LocalOutcome, LocalParams, Step, Strategy};
use crate::stability::StabilityParams;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// `result.json`'s name of what the searches maximised.
pub fn objective_name(objective: crate::stability::Objective) -> &'static str {
    match objective {
        crate::stability::Objective::Lambda => "lambda_eq",
        crate::stability::Objective::Frequency => "frequency",
    }
}

/// The format version of `result.json`.
pub const VERSION: u32 = 1;

/// Where the curves came from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InputDescription {
    /// Paper example name, if any.
    pub example: Option<String>,
    /// Mesh file, if any.
    pub mesh: Option<String>,
    /// Curve files in loading order.
    pub curve_files: Vec<String>,
    /// Scale applied.
    pub scale: f64,
}

/// The set-up of a run: everything needed to rebuild and rerun it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunSetup {
    /// Inputs.
    pub input: InputDescription,
    /// Network construction.
    pub build: BuildParams,
    /// Material and solvers.
    pub stability: StabilityParams,
    /// Greedy parameters (budget, keep list).
    pub greedy: GreedyParams,
    /// Network counts.
    pub network: BuildInfo,
    /// Total rest length of all curves.
    pub total_length: f64,
    /// The design constraints every search honoured (absent when none was asked for): a run
    /// resumed with others is refused.
    #[serde(
        default,
        skip_serializing_if = "crate::constraints::ConstraintParams::is_default"
    )]
    pub constraints: crate::constraints::ConstraintParams,
    /// The physical mode's options as given (absent in the paper's mode, and in runs recorded
    /// before they were): a run resumed with others is refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub physical: Option<crate::physics::PhysicalOptions>,
    /// The physical model those options resolved to (units, every curve's material and
    /// section, rest shapes, gravity): what an export to a structural code carries (absent
    /// in the paper's mode).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub physical_model: Option<PhysicalModel>,
}

/// The physical model of a run as resolved ([`RunSetup::physical_model`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhysicalModel {
    /// Units, materials, sections, gravity and the worst-case load.
    pub physical: crate::material::Physical,
    /// The curves pre-bent at rest, ascending (the others are straight at rest).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pre_bent: Vec<usize>,
    /// The load cases and combinations the run was given (its loads file, checked): the
    /// structural exports carry them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub loads: Option<crate::physics::cases::Loads>,
}

impl PhysicalModel {
    /// The record of `params`.
    pub fn of(params: &crate::physics::PhysicalParams) -> Self {
        let pre_bent = params.rest.iter().enumerate();
        PhysicalModel {
            physical: params.physical.clone(),
            pre_bent: pre_bent
                .filter(|(_, r)| **r == crate::material::RestShape::PreBent)
                .map(|(c, _)| c)
                .collect(),
            loads: params.loads.clone(),
        }
    }

    /// Every one of `n` curves' rest shape.
    pub fn rest(&self, n: usize) -> Vec<crate::material::RestShape> {
        let mut rest = vec![crate::material::RestShape::Straight; n];
        for &c in self.pre_bent.iter().filter(|&&c| c < n) {
            rest[c] = crate::material::RestShape::PreBent;
        }
        rest
    }
}

/// The final network of a run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FinalRecord {
    /// Curves kept.
    pub curves: Vec<usize>,
    /// Their total rest length.
    pub length: f64,
    /// `λ_eq` of the final network.
    pub lambda: f64,
}

/// The local search run after the greedy (`--local-search`), from the greedy's final network
/// and from the best single curves ([`crate::simplify::local`], *Starts*).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LocalSearchRecord {
    /// The objective: `lambda_eq` (or `frequency`: the values are then `μ_min`), every subset
    /// relaxed from the drawn state (the
    /// evaluation of exhaustive search and `curvenet compare`; the greedy's own `λ_eq` is
    /// relaxed along its path, so it can differ slightly).
    pub objective: String,
    /// How moves were chosen.
    pub strategy: Strategy,
    /// Whether moves were followed by part steps.
    pub parts: bool,
    /// The greedy's final curves.
    pub start_curves: Vec<usize>,
    /// Their `λ_eq`, relaxed from the drawn state (`null` when they are over the budget: the
    /// search did not start from them).
    pub start_lambda: Option<f64>,
    /// Every start searched from, in order, with its `λ_eq`: the greedy's final curves (when
    /// within the budget), then the best single curves.
    #[serde(default)]
    pub starts: Vec<SubsetScore>,
    /// The start the best search came from: `moves` lead from it to `curves`.
    #[serde(default)]
    pub from_curves: Vec<usize>,
    /// The curves the search ended with.
    pub curves: Vec<usize>,
    /// Their total rest length (within the budget; the keep list is held).
    pub length: f64,
    /// Their `λ_eq`, relaxed from the drawn state.
    pub lambda: f64,
    /// `lambda / start_lambda` (`null` unless both are positive).
    pub ratio: Option<f64>,
    /// The moves taken from `from_curves`, in order, with the `λ_eq` after each.
    pub moves: Vec<Step>,
    /// Rounds run by the best search (scans of single moves, each followed by a chain when it
    /// found nothing).
    pub rounds: usize,
    /// Variable-depth chains built by the best search.
    pub chains: usize,
    /// Distinct subsets evaluated, over every start.
    pub evaluations: usize,
    /// Connected structures relaxed (the expensive evaluations).
    pub structures: usize,
}

impl LocalSearchRecord {
    /// The record of `outcome`, run with `params` after a greedy that ended at `greedy`;
    /// `None` when the answer's `λ_eq` is not finite (a failed evaluation: nothing worth
    /// recording).
    pub fn new(params: &LocalParams, outcome: &LocalOutcome, greedy: &[usize]) -> Option<Self> {
        let b = &outcome.best;
        if !b.lambda.is_finite() {
            return None;
        }
        let mut start_curves = greedy.to_vec();
        start_curves.sort_unstable();
        start_curves.dedup();
        let start_lambda = outcome
            .given()
            .filter(|g| g.curves == start_curves)
            .map(|g| g.lambda)
            .filter(|l| l.is_finite());
        Some(LocalSearchRecord {
            objective: "lambda_eq".into(),
            strategy: params.strategy,
            parts: params.parts,
            start_curves,
            start_lambda,
            starts: outcome.starts.clone(),
            from_curves: outcome.start.curves.clone(),
            curves: b.curves.clone(),
            length: b.length,
            lambda: b.lambda,
            ratio: start_lambda
                .filter(|&s| s > 0.0 && b.lambda > 0.0)
                .map(|s| b.lambda / s),
            moves: outcome.steps.clone(),
            rounds: outcome.rounds,
            chains: outcome.chains,
            evaluations: outcome.evaluations,
            structures: outcome.structures,
        })
    }

    /// One line for summaries; the value shown is the objective's (`λ_eq`, or `μ_min`), the
    /// length in `unit` (the physical mode's scene unit) when given.
    pub fn describe(&self, unit: Option<&str>) -> String {
        let value = if self.objective == objective_name(crate::stability::Objective::Frequency) {
            crate::stability::Objective::Frequency.value_symbol()
        } else {
            crate::stability::Objective::Lambda.value_symbol()
        };
        let gain = self
            .ratio
            .map_or_else(String::new, |r| format!(", {r:.3}× the greedy's"));
        let greedy = match self.start_lambda {
            Some(l) => format!("greedy's set {l:.6e} relaxed from the drawn state{gain}"),
            None => "the greedy's set is over the budget".to_string(),
        };
        let from = if self.from_curves == self.start_curves {
            "the greedy's final network".to_string()
        } else {
            format!("curves {:?}", self.from_curves)
        };
        format!(
            "local search from the greedy's final network and the best single curves ({} \
             starts): best from {from}, {} move(s); curves {:?}, length {}, {value} \
             {:.6e} ({greedy}); {} subsets evaluated, {} structures relaxed",
            self.starts.len(),
            self.moves.len(),
            self.curves,
            crate::fmt::length_in(self.length, unit),
            self.lambda,
            self.evaluations,
            self.structures
        )
    }
}

/// `result.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResultFile {
    /// Format version ([`VERSION`]).
    pub version: u32,
    /// The set-up.
    pub setup: RunSetup,
    /// The objective reported per iteration ([`objective_name`]): `lambda_eq` (the paper's),
    /// or `frequency`, with which each iteration's `lambda` holds `μ_min` of the mass-metric
    /// problem and `first_frequency` its frequency `√μ_min / 2π`.
    pub objective: String,
    /// The budget `V` as a length.
    pub budget: f64,
    /// False while the run is in progress (or was interrupted).
    pub complete: bool,
    /// Why the run stopped (absent while in progress).
    pub stop: Option<StopReason>,
    /// Every recorded iteration.
    pub iterations: Vec<IterationRecord>,
    /// The last recorded network.
    #[serde(rename = "final")]
    pub final_network: Option<FinalRecord>,
    /// How far the final network can be from the best feasible subset on the fixed-geometry
    /// objective `λ_fix` (absent when skipped or not computable).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub certificate: Option<Certificate>,
    /// The local search from the final network (absent unless asked for, or when it could
    /// not run).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub local_search: Option<LocalSearchRecord>,
    /// The network to build: the best stable network meeting the budget and every constraint
    /// among those the run's searches evaluated; `null` when there is none (see
    /// [`Self::no_answer`]) or while the run is in progress.
    #[serde(default)]
    pub answer: Option<Answer>,
    /// Why there is no answer, and the run's smallest stable network (present only when the
    /// run completed without an answer).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub no_answer: Option<NoAnswer>,
    /// With `--alternatives K`: up to K further stable networks meeting the budget and every
    /// constraint, distinct from the answer and from each other, by decreasing `λ_eq` (each
    /// like [`Self::answer`]; absent when none were asked for or found).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub alternatives: Vec<Answer>,
    /// A slid run's record: the network it started from and how its curves moved (absent
    /// unless the answer is a slid network, whose `source` is then `slide`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slide: Option<SlideRecord>,
}

/// How a slid run's curves moved (`slide` in `result.json`, [`crate::slide`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlideRecord {
    /// The run folder the network came from.
    pub from: String,
    /// The objective (`lambda_eq` or `frequency`, as [`ResultFile::objective`]).
    pub objective: String,
    /// The objective of the network it started from, rebuilt from its curves and analysed
    /// cold.
    pub lambda_before: f64,
    /// The objective of the slid network (analysed cold, as an analysis of its exported
    /// curves gives it).
    pub lambda_after: f64,
    /// The answer's objective as the run it came from recorded it (its final network's when
    /// it had no answer).
    pub lambda_recorded: f64,
    /// The largest move allowed (scene units).
    pub max_move: f64,
    /// The largest distance of a point of a slid curve from the curve as drawn.
    pub largest_move: f64,
    /// Joints (by the curves they join) the slid network has and the start lacked.
    pub joints_added: usize,
    /// Joints the start had and the slid network lacks.
    pub joints_removed: usize,
    /// Total rest length before.
    pub length_before: f64,
    /// Total rest length after.
    pub length_after: f64,
    /// The budget (a length).
    pub budget: f64,
    /// Every end stayed where it was.
    pub fixed_ends: bool,
    /// Every curve, in this run's order: its id in the run it came from, whether it could
    /// move, its largest move and its move's coefficients.
    pub curves: Vec<SlideCurve>,
    /// Networks evaluated.
    pub evaluations: usize,
    /// Sweeps of the search.
    pub sweeps: usize,
    /// The steps the search took, in order.
    pub steps: Vec<crate::slide::Step>,
    /// The search was stopped before it finished (the best network so far is the answer).
    pub stopped: bool,
    /// The rounds of topology and geometry after this slide (a run's slide rounds): each a
    /// local search on the slid curves, then a slide of its network.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rounds: Vec<SlideRound>,
    /// With rounds: the slide whose network is the answer, the best of every slide by the
    /// objective (the earliest of equals): 0 the first slide, `K` round `K`'s. When it is a
    /// round's, this record is that round's slide's own (its `from` the round's local search,
    /// `rounds/K/local`), the first slide kept in `rounds/0/slid`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub answer_round: Option<usize>,
    /// The slid network's largest deviation from its designed place (scene units), measured
    /// as the run's largest-deviation constraint measures it (in the physical mode under
    /// self-weight); present when that constraint is in force.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub deviation: Option<f64>,
}

/// One round after a slide ([`SlideRecord::rounds`]): a local search over the network's
/// curves with the slid ones in place of their drawn shapes, from the slid network, then its
/// network slid again.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlideRound {
    /// The round, from 1.
    pub round: usize,
    /// The objective of the network the round started from (the last slide's).
    pub start: f64,
    /// The objective of the local search's network.
    pub local_search: f64,
    /// The objective once that network slid.
    pub slid: f64,
    /// The local search's curves (ids of the network the first slide started from).
    pub curves: Vec<usize>,
    /// The run folder of the local search's network (`local`) and of its slide (`slid`),
    /// relative to the slid run's folder.
    pub folder: String,
}

/// One curve of a slid run ([`SlideRecord::curves`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlideCurve {
    /// Its id in the run the network came from.
    pub from: usize,
    /// Whether it could move (not kept, pinned, or in a group or symmetry orbit).
    pub free: bool,
    /// Its largest distance from the curve as drawn.
    pub largest_move: f64,
    /// Its move's coefficients (one per offset function; empty when it could not move).
    pub coefficients: Vec<f64>,
}

impl ResultFile {
    /// The scene's length unit in the physical mode (`mm`, `cm`, `m`; `None` in the paper's
    /// mode, whose lengths are bare scene units): the recorded networks' physical figures',
    /// else the options'.
    pub fn length_unit(&self) -> Option<&str> {
        self.iterations
            .iter()
            .find_map(|i| i.physical.as_ref().and_then(|p| p.units.as_deref()))
            .or_else(|| self.setup.physical.as_ref()?.units.as_deref())
    }

    /// Reads `DIR/result.json`.
    ///
    /// # Errors
    ///
    /// As [`Self::read_from`].
    pub fn read(dir: &Path) -> Result<ResultFile, super::RunFolderError> {
        Self::read_from(&super::RunFiles::unconfined(dir))
    }

    /// Reads `result.json` through `files` (confined or not: see [`super::files`]).
    ///
    /// # Errors
    ///
    /// The file cannot be read, is not a run record, or is of another format version.
    pub fn read_from(files: &super::RunFiles) -> Result<ResultFile, super::RunFolderError> {
        let r: ResultFile = files.read_json("result.json", "a curvenet run record")?;
        if r.version != VERSION {
            return Err(super::RunFolderError::Invalid {
                file: files.name("result.json"),
                problem: format!("unsupported version {} (expected {VERSION})", r.version),
            });
        }
        Ok(r)
    }
}
