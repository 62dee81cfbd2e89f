//! The greedy on a paper's example, timed phase by phase (`curvenet bench`): one run's
//! [`BenchRow`] (counts, phase times, wall and CPU time, peak memory, every removal and
//! `λ_eq`), the median of repeated runs, and the table's text.
//!
//! Ratios to the paper's reference implementation come only from times the user measured
//! and gives ([`References`], read from a JSON file `{"tower": 103.8, …}`): a ratio is a
//! measurement side by side, never a figure from another machine.

use crate::network::build_network;
use crate::paper::LoadedExample;
use crate::profile;
use crate::simplify::greedy::NoHooks;
use crate::simplify::{Budget, GreedyParams, SimplifyError, greedy};
use crate::stability::{Analyzer, StabilityParams, Technique};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

/// One example's run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BenchRow {
    /// The example.
    pub example: String,
    /// Its curves.
    pub curves: usize,
    /// The curves of the greedy's last network.
    pub kept: usize,
    /// Degrees of freedom.
    pub dofs: usize,
    /// Greedy iterations.
    pub iterations: usize,
    /// Candidates scored.
    pub evaluated: usize,
    /// Candidates pruned without a score.
    pub pruned: usize,
    /// Cholesky factorizations.
    pub factorizations: usize,
    /// Triangular solves.
    pub solves: usize,
    /// Seconds relaxing (summed over threads).
    pub relax_s: f64,
    /// Seconds assembling.
    pub assemble_s: f64,
    /// Seconds factoring.
    pub factor_s: f64,
    /// Seconds solving.
    pub solve_s: f64,
    /// Seconds in eigen solves.
    pub eigen_s: f64,
    /// Seconds computing bounds.
    pub bound_s: f64,
    /// Wall time of the run the row reports (the median run with repeats).
    pub wall_s: f64,
    /// Wall time of every run, in the order they ran.
    pub wall_runs: Vec<f64>,
    /// CPU time of the process during the run (every thread, rayon's waiting included).
    pub cpu_s: Option<f64>,
    /// Peak resident memory, MiB.
    pub peak_mib: Option<f64>,
    /// The reference implementation's time measured by the user (`--reference`), seconds.
    pub reference_s: Option<f64>,
    /// The first three removals.
    pub removed_first: Vec<usize>,
    /// `λ_eq` of the last network.
    pub final_lambda: f64,
    /// The curve removed in every iteration (`None` in the last).
    pub removed: Vec<Option<usize>>,
    /// `λ_eq` of every iteration (JSON round-trips them bit for bit).
    pub lambdas: Vec<f64>,
}

impl BenchRow {
    /// Every removal and the bits of every `λ_eq`: what repeated runs must agree on.
    pub fn answer(&self) -> (&[Option<usize>], Vec<u64>) {
        (
            &self.removed,
            self.lambdas.iter().map(|l| l.to_bits()).collect(),
        )
    }
}

/// How a bench run is made: techniques switched off, the modes per iteration.
#[derive(Clone, Debug, Default)]
pub struct BenchParams {
    /// Techniques switched off (every configuration must make the same removals).
    pub off: Vec<Technique>,
    /// Low modes per iteration (`None`: the greedy's).
    pub modes: Option<usize>,
}

/// Why a benchmark run failed.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The example's network could not be built.
    #[error(transparent)]
    Build(#[from] crate::network::build::BuildError),
    /// The greedy failed.
    #[error(transparent)]
    Greedy(#[from] SimplifyError),
    /// The greedy ended without recording an iteration.
    #[error("the greedy recorded no iteration")]
    NoIteration,
}

/// Runs the greedy on `ex` once in `pool`, with a fresh profile and peak-memory mark.
///
/// # Errors
///
/// The network cannot be built, or the greedy fails.
pub fn run_example(
    params: &BenchParams,
    pool: &rayon::ThreadPool,
    ex: &LoadedExample,
) -> Result<BenchRow, BenchError> {
    let mut stability = StabilityParams::default();
    let mut greedy_params = GreedyParams::new(Budget::Fraction(ex.setup.budget_fraction));
    greedy_params.keep = ex.setup.keep.clone();
    for &t in &params.off {
        stability = stability.without(t);
    }
    if let Some(m) = params.modes {
        stability.tuning.modes = m;
    }
    profile::reset_peak_memory();
    profile::reset();
    let cpu_start = profile::cpu_seconds();
    let start = Instant::now();
    let (o, dofs) = pool.install(|| -> Result<_, BenchError> {
        let (network, _) = build_network(&ex.curves, &ex.build)?;
        let analyzer = Analyzer::new(network, stability).map_err(SimplifyError::from)?;
        let dofs = analyzer.model().dofs();
        let o = greedy(&analyzer, &greedy_params, None, None, &mut NoHooks)?;
        Ok((o, dofs))
    })?;
    let wall = start.elapsed().as_secs_f64();
    let cpu = profile::cpu_seconds()
        .zip(cpu_start)
        .map(|(end, start)| ((end - start) * 100.0).round() / 100.0);
    let p = profile::snapshot();
    let t = &o.timings;
    let last = o.iterations.last().ok_or(BenchError::NoIteration)?;
    Ok(BenchRow {
        example: ex.setup.name.to_string(),
        curves: ex.curves.len(),
        kept: last.curves.len(),
        dofs,
        iterations: o.iterations.len(),
        evaluated: t.candidate_evaluations,
        pruned: t.candidates_pruned,
        factorizations: t.relax_work.factorizations + t.candidate_work.factorizations,
        solves: t.relax_work.solves + t.candidate_work.solves,
        relax_s: p.relax.seconds,
        assemble_s: p.assemble.seconds,
        factor_s: p.factor.seconds,
        solve_s: p.solve.seconds,
        eigen_s: p.eigen.seconds,
        bound_s: p.bound.seconds,
        wall_s: wall,
        wall_runs: vec![wall],
        cpu_s: cpu,
        peak_mib: profile::peak_memory().map(|b| b as f64 / (1024.0 * 1024.0)),
        reference_s: None,
        removed_first: o
            .iterations
            .iter()
            .filter_map(|i| i.removed)
            .take(3)
            .collect(),
        final_lambda: last.lambda,
        removed: o.iterations.iter().map(|i| i.removed).collect(),
        lambdas: o.iterations.iter().map(|i| i.lambda).collect(),
    })
}

/// The row of the run with the median wall time (the slower of the two middle ones for an
/// even count), with every run's wall time. `None` for no run.
pub fn median_row(mut runs: Vec<BenchRow>) -> Option<BenchRow> {
    if runs.is_empty() {
        return None;
    }
    let walls: Vec<f64> = runs.iter().map(|r| r.wall_s).collect();
    runs.sort_by(|x, y| x.wall_s.total_cmp(&y.wall_s));
    let mut row = runs.swap_remove(runs.len() / 2);
    row.wall_runs = walls;
    Some(row)
}

/// The runs of a bench with repeats, in rounds (every example once per round, so the
/// machine's drift touches them alike): each run checked against the example's first (the
/// greedy must be deterministic), and after an example's last round its median run
/// ([`median_row`]) with the reference time the user gave.
#[derive(Clone, Debug)]
pub struct Rounds {
    runs: Vec<Vec<BenchRow>>,
    repeat: usize,
    references: References,
}

/// Two runs of an example disagreed.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{name}: run {run} made different removals or λ_eq than run 1 (the greedy must be \
     deterministic)"
)]
pub struct Disagreement {
    /// The example.
    pub name: String,
    /// The run that disagreed with the first (from 1).
    pub run: usize,
}

impl Rounds {
    /// `repeat` rounds of `examples` examples, `references` beside the median rows.
    pub fn new(examples: usize, repeat: usize, references: References) -> Self {
        Rounds {
            runs: vec![Vec::with_capacity(repeat); examples],
            repeat,
            references,
        }
    }

    /// Records `row`, the run of round `round` (from 0) of example `i`, named `name`: after
    /// the example's last round, its median row.
    ///
    /// # Errors
    ///
    /// The run made other removals or another `λ_eq` than the example's first.
    pub fn record(
        &mut self,
        i: usize,
        name: &str,
        round: usize,
        row: BenchRow,
    ) -> Result<Option<BenchRow>, Disagreement> {
        if let Some(first) = self.runs[i].first()
            && first.answer() != row.answer()
        {
            return Err(Disagreement {
                name: name.to_string(),
                run: round + 1,
            });
        }
        self.runs[i].push(row);
        if round + 1 < self.repeat {
            return Ok(None);
        }
        Ok(
            median_row(std::mem::take(&mut self.runs[i])).map(|mut row| {
                row.reference_s = self.references.0.get(name).copied();
                row
            }),
        )
    }
}

/// The reference implementation's times measured by the user, seconds by example name.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct References(pub BTreeMap<String, f64>);

impl References {
    /// Reads a JSON object of positive seconds by example name (`{"tower": 103.8}`).
    ///
    /// # Errors
    ///
    /// The file cannot be read, is not such an object, or holds a time that is not a
    /// positive number.
    pub fn read(path: &Path) -> Result<References, crate::io::InputError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| crate::io::InputError::Io {
            file: file.clone(),
            source,
        })?;
        let refs: References = serde_json::from_str(&text).map_err(|e| {
            crate::io::InputError::parse(
                &file,
                e.line(),
                "expected a JSON object of the reference's seconds by example, e.g. \
                 {\"tower\": 103.8}",
            )
        })?;
        if let Some(d) = crate::io::duplicate_key(&text) {
            return Err(crate::io::InputError::parse(&file, d.line, d.describe()));
        }
        if let Some((name, s)) = refs.0.iter().find(|(_, s)| !(s.is_finite() && **s > 0.0)) {
            return Err(crate::io::InputError::parse(
                &file,
                0,
                format!("{name}: {s} is not a positive number of seconds"),
            ));
        }
        Ok(refs)
    }
}

/// The table's header line.
pub fn header() -> String {
    format!(
        "{:<9} {:>6} {:>6} {:>5} {:>5} {:>6} {:>6} {:>6} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>11} {:>8} {:>8} {:>8} {:>8}",
        "example",
        "curves",
        "dofs",
        "iters",
        "evals",
        "pruned",
        "facts",
        "solves",
        "relax s",
        "asm s",
        "factor s",
        "solve s",
        "eigen s",
        "bound s",
        "wall s",
        "wall range",
        "cpu s",
        "peak MiB",
        "ref s",
        "ref/ours"
    )
}

/// A row of the table.
pub fn format_row(row: &BenchRow) -> String {
    let spread = match row.wall_runs.len() {
        0 | 1 => "-".to_string(),
        _ => {
            let lo = row.wall_runs.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = row.wall_runs.iter().copied().fold(0.0, f64::max);
            format!("{lo:.2}–{hi:.2}")
        }
    };
    format!(
        "{:<9} {:>6} {:>6} {:>5} {:>5} {:>6} {:>6} {:>6} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>11} {:>8} {:>8} {:>8} {:>8}",
        row.example,
        format!("{}→{}", row.curves, row.kept),
        row.dofs,
        row.iterations,
        row.evaluated,
        row.pruned,
        row.factorizations,
        row.solves,
        row.relax_s,
        row.assemble_s,
        row.factor_s,
        row.solve_s,
        row.eigen_s,
        row.bound_s,
        row.wall_s,
        spread,
        row.cpu_s.map_or("?".into(), |c| format!("{c:.2}")),
        row.peak_mib.map_or("?".into(), |m| format!("{m:.0}")),
        row.reference_s.map_or("-".into(), |r| format!("{r:.1}")),
        row.reference_s
            .map_or("-".into(), |r| format!("{:.0}×", r / row.wall_s)),
    )
}

/// The arguments a bench forwards to a worker run of one example: everything after
/// `command` in `argv`, without the options of `valued` (each with its value, given apart or
/// after `=`) and the switches of `dropped`, then `worker` (the switch that makes the run a
/// worker's). The front end names its own options.
pub fn worker_args(
    argv: &[String],
    command: &str,
    valued: &[&str],
    dropped: &[&str],
    worker: &str,
) -> Option<Vec<String>> {
    let at = argv.iter().position(|s| s == command)?;
    let mut out = vec![command.to_string()];
    let mut rest = argv[at + 1..].iter();
    while let Some(arg) = rest.next() {
        let with_value = |v: &&str| arg.strip_prefix(*v).is_some_and(|r| r.starts_with('='));
        if valued.contains(&arg.as_str()) {
            rest.next();
        } else if !dropped.contains(&arg.as_str()) && !valued.iter().any(with_value) {
            out.push(arg.clone());
        }
    }
    out.push(worker.to_string());
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_are_positive_seconds_by_example() {
        let dir = std::env::temp_dir().join(format!("curvenet-refs-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let good = dir.join("good.json");
        std::fs::write(&good, r#"{"tower": 103.8, "shell": 173.6}"#).unwrap();
        let r = References::read(&good).unwrap();
        assert_eq!(r.0.get("tower"), Some(&103.8));
        for (name, text) in [("neg.json", r#"{"tower": -1}"#), ("list.json", "[1, 2]")] {
            let p = dir.join(name);
            std::fs::write(&p, text).unwrap();
            let e = References::read(&p).unwrap_err().to_string();
            assert!(e.contains(name), "{e}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn rounds_check_every_run_against_the_first_and_give_the_median() {
        let row = |wall_s: f64, lambda: f64| BenchRow {
            example: "tower".into(),
            curves: 3,
            kept: 1,
            dofs: 9,
            iterations: 3,
            evaluated: 0,
            pruned: 0,
            factorizations: 0,
            solves: 0,
            relax_s: 0.0,
            assemble_s: 0.0,
            factor_s: 0.0,
            solve_s: 0.0,
            eigen_s: 0.0,
            bound_s: 0.0,
            wall_s,
            wall_runs: Vec::new(),
            cpu_s: None,
            peak_mib: None,
            reference_s: None,
            removed_first: vec![2, 0],
            final_lambda: lambda,
            removed: vec![Some(2), Some(0), None],
            lambdas: vec![1.0, 0.5, lambda],
        };
        let refs = References([("tower".to_string(), 10.0)].into_iter().collect());
        let mut rounds = Rounds::new(1, 3, refs);
        assert!(
            rounds
                .record(0, "tower", 0, row(3.0, 0.25))
                .unwrap()
                .is_none()
        );
        assert!(
            rounds
                .record(0, "tower", 1, row(1.0, 0.25))
                .unwrap()
                .is_none()
        );
        let median = rounds
            .record(0, "tower", 2, row(2.0, 0.25))
            .unwrap()
            .unwrap();
        assert_eq!((median.wall_s, median.reference_s), (2.0, Some(10.0)));
        assert_eq!(median.wall_runs, [3.0, 1.0, 2.0]);
        // A run whose λ_eq differs in one bit is refused, naming it.
        let mut rounds = Rounds::new(1, 2, References::default());
        rounds.record(0, "tower", 0, row(1.0, 0.25)).unwrap();
        let e = rounds
            .record(
                0,
                "tower",
                1,
                row(1.0, f64::from_bits(0.25f64.to_bits() + 1)),
            )
            .unwrap_err();
        assert_eq!(e.to_string().split(':').next(), Some("tower"));
        assert_eq!(e.run, 2);
    }

    #[test]
    fn worker_runs_get_the_switches_but_not_the_examples_repeats_or_json() {
        let argv: Vec<String> = [
            "curvenet",
            "bench",
            "--examples",
            "tower,roof",
            "--off",
            "prune,warm",
            "--repeat",
            "3",
            "--json",
            "--reference",
            "refs.json",
            "--threads=2",
            "--repeat=4",
            "--examples=shell",
            "--data",
            "/d",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let valued = ["--examples", "--repeat", "--reference"];
        let got = super::worker_args(&argv, "bench", &valued, &["--json"], "--worker");
        let want = [
            "bench",
            "--off",
            "prune,warm",
            "--threads=2",
            "--data",
            "/d",
            "--worker",
        ];
        assert_eq!(got.expect("bench is there"), want);
    }
}
