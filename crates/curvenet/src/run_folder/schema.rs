//! `result.json`: the record of a run ([`ResultFile`]) and its parts.

use crate::constraints::answer::{Answer, NoAnswer};
use crate::network::{BuildInfo, BuildParams};
use crate::simplify::GreedyParams;
use crate::simplify::certificate::Certificate;
use crate::simplify::greedy::{IterationRecord, StopReason};
use crate::simplify::local::{LocalOutcome, LocalParams, Step, Strategy};
use crate::stability::StabilityParams;
use serde::{Deserialize, Serialize};
use std::path::Path;

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

/// The local search run after the greedy (`--local-search`), from the greedy's final network.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LocalSearchRecord {
    /// The objective: always `lambda_eq`, every subset relaxed from the drawn state (the
    /// evaluation of exhaustive search and `curvenet compare`; the greedy's own `λ_eq` is
    /// relaxed along its path, so it can differ slightly).
    pub objective: String,
    /// How moves were chosen.
    pub strategy: Strategy,
    /// Whether moves were followed by part steps.
    pub parts: bool,
    /// The greedy's final curves (the start).
    pub start_curves: Vec<usize>,
    /// Their `λ_eq`, relaxed from the drawn state.
    pub start_lambda: f64,
    /// The curves the search ended with (the start when nothing improved it).
    pub curves: Vec<usize>,
    /// Their total rest length (within the budget; the keep list is held).
    pub length: f64,
    /// Their `λ_eq`, relaxed from the drawn state.
    pub lambda: f64,
    /// `lambda / start_lambda` (`null` unless both are positive).
    pub ratio: Option<f64>,
    /// The moves taken, in order, with the `λ_eq` after each.
    pub moves: Vec<Step>,
    /// Rounds run (scans of single moves, each followed by a chain when it found nothing).
    pub rounds: usize,
    /// Variable-depth chains built.
    pub chains: usize,
    /// Distinct subsets evaluated.
    pub evaluations: usize,
    /// Connected structures relaxed (the expensive evaluations).
    pub structures: usize,
}

impl LocalSearchRecord {
    /// The record of `outcome`, run with `params`; `None` when a `λ_eq` is not finite (a
    /// failed evaluation: nothing worth recording).
    pub fn new(params: &LocalParams, outcome: &LocalOutcome) -> Option<Self> {
        let (s, b) = (&outcome.start, &outcome.best);
        if !(s.lambda.is_finite() && b.lambda.is_finite()) {
            return None;
        }
        Some(LocalSearchRecord {
            objective: "lambda_eq".into(),
            strategy: params.strategy,
            parts: params.parts,
            start_curves: s.curves.clone(),
            start_lambda: s.lambda,
            curves: b.curves.clone(),
            length: b.length,
            lambda: b.lambda,
            ratio: (s.lambda > 0.0 && b.lambda > 0.0).then(|| b.lambda / s.lambda),
            moves: outcome.steps.clone(),
            rounds: outcome.rounds,
            chains: outcome.chains,
            evaluations: outcome.evaluations,
            structures: outcome.structures,
        })
    }

    /// One line for summaries.
    pub fn describe(&self) -> String {
        let gain = self
            .ratio
            .map_or_else(String::new, |r| format!(", {r:.3}× the greedy's"));
        format!(
            "local search from the greedy's final network: {} move(s); curves {:?}, length {:.6}, \
             λ_eq {:.6e} (greedy's set {:.6e} relaxed from the drawn state{gain}); {} subsets \
             evaluated, {} structures relaxed",
            self.moves.len(),
            self.curves,
            self.length,
            self.lambda,
            self.start_lambda,
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
    /// The objective reported per iteration.
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
}

impl ResultFile {
    /// Reads `DIR/result.json`.
    pub fn read(dir: &Path) -> Result<ResultFile, String> {
        let path = dir.join("result.json");
        let text =
            std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let r: ResultFile = serde_json::from_str(&text)
            .map_err(|e| format!("{}:{}: {e}", path.display(), e.line()))?;
        if r.version != VERSION {
            return Err(format!(
                "{}: unsupported version {} (expected {VERSION})",
                path.display(),
                r.version
            ));
        }
        Ok(r)
    }
}
