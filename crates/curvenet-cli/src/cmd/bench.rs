//! `curvenet bench`: the greedy on the paper's examples, timed phase by phase.
//!
//! Each example runs in this process with a fresh profile and peak-memory mark; the table
//! gives counts (curves, degrees of freedom, iterations, candidate solves done and skipped,
//! factorizations) and times (relax, assemble, factor, eigen; summed over threads) next to the
//! wall time, the process's CPU time over the same span (`cpu s`, every thread; divided by
//! the thread count it is the least wall time the same work could take) and the reference
//! implementation's time on this kind of machine.
//!
//! Every run has a process of its own (the bench starts itself with the hidden `--worker`
//! switch and reads its JSON row): each starts from a fresh heap and thread pool, and its
//! peak resident memory is its own, not the high-water mark of the examples run before it.
//!
//! `--repeat N` runs every example `N` times, round by round, and reports the run with the
//! median wall time, the range of all of them beside it (this sandbox's timings drift by
//! 5–25% between runs minutes apart), and fails if two runs of an example disagree in any
//! removal or any bit of `λ_eq`. On a terminal a progress bar counts the runs (with an
//! estimate of the time left); piped, the output is the table alone.
//!
//! `--off NAME,…` switches techniques off ([`Technique`]) to measure what each contributes;
//! every configuration must make the same removals.

use crate::args::BenchArgs;
use crate::exit::usage;
use curvenet::network::build_network;
use curvenet::simplify::greedy::NoHooks;
use curvenet::simplify::{Budget, GreedyParams, greedy};
use curvenet::stability::{Analyzer, StabilityParams};
use curvenet::{paper, profile};
use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};
use std::process::{Command, Stdio};
use std::time::Instant;

/// The reference implementation's greedy on a 2-core machine like this one, seconds.
fn reference_seconds(name: &str) -> Option<f64> {
    match name {
        "tower" => Some(109.0),
        "arcshell" => Some(136.0),
        "shell" => Some(153.0),
        _ => None,
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
struct Row {
    example: String,
    curves: usize,
    kept: usize,
    dofs: usize,
    iterations: usize,
    evaluated: usize,
    pruned: usize,
    factorizations: usize,
    solves: usize,
    relax_s: f64,
    assemble_s: f64,
    factor_s: f64,
    solve_s: f64,
    eigen_s: f64,
    bound_s: f64,
    /// Wall time of the run the row reports (the median run with `--repeat`).
    wall_s: f64,
    /// Wall time of every run, in the order they ran.
    wall_runs: Vec<f64>,
    /// CPU time of the process during the run (every thread, rayon's waiting included).
    cpu_s: Option<f64>,
    peak_mib: Option<f64>,
    reference_s: Option<f64>,
    removed_first: Vec<usize>,
    final_lambda: f64,
    /// The curve removed in every iteration (`None` in the last).
    removed: Vec<Option<usize>>,
    /// `λ_eq` of every iteration (JSON round-trips them bit for bit).
    lambdas: Vec<f64>,
}

impl Row {
    /// Every removal and the bits of every `λ_eq`: what repeated runs must agree on.
    fn answer(&self) -> (&[Option<usize>], Vec<u64>) {
        (
            &self.removed,
            self.lambdas.iter().map(|l| l.to_bits()).collect(),
        )
    }
}

pub fn run(a: BenchArgs) -> anyhow::Result<()> {
    let data = super::data_source(a.data.as_deref())?;
    let threads = a.threads.unwrap_or_else(rayon::current_num_threads);
    if a.worker {
        let [name] = a.examples.as_slice() else {
            return Err(usage("--worker runs exactly one example"));
        };
        let ex = paper::load_from(name, &data, Default::default())?;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()?;
        let row = run_once(&a, &pool, name, &ex)?;
        println!("{}", serde_json::to_string(&row)?);
        return Ok(());
    }
    // Fail early, in this process, on an unknown example or missing data.
    for name in &a.examples {
        paper::load_from(name, &data, Default::default())?;
    }
    let off: Vec<String> = a.off.iter().map(|t| t.name().to_string()).collect();
    println!(
        "curvenet bench: {threads} thread(s); techniques off: {}",
        if off.is_empty() {
            "none".to_string()
        } else {
            off.join(", ")
        }
    );
    println!(
        "{:<9} {:>6} {:>6} {:>5} {:>5} {:>6} {:>6} {:>6} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>11} {:>8} {:>8} {:>8}",
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
        "ref/ours"
    );
    let repeat = a.repeat as usize;
    let forwarded = worker_args(std::env::args().collect())?;
    let mut runs: Vec<Vec<Row>> = vec![Vec::with_capacity(repeat); a.examples.len()];
    // On a terminal only (indicatif draws nothing when stderr is not one).
    let bar = ProgressBar::new((repeat * a.examples.len()) as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {pos}/{len} runs, ETA {eta} {msg}",
        )
        .expect("valid template"),
    );
    bar.enable_steady_tick(std::time::Duration::from_millis(250));
    for round in 0..repeat {
        for (i, name) in a.examples.iter().enumerate() {
            bar.set_message(format!("({name}, round {}/{repeat})", round + 1));
            let row = run_worker(&forwarded, name)?;
            bar.inc(1);
            if repeat > 1 {
                bar.suspend(|| {
                    eprintln!("round {}/{repeat}: {name} {:.2} s", round + 1, row.wall_s)
                });
            }
            if let Some(first) = runs[i].first()
                && first.answer() != row.answer()
            {
                anyhow::bail!(
                    "{name}: run {} made different removals or λ_eq than run 1 \
                     (the greedy must be deterministic)",
                    round + 1
                );
            }
            runs[i].push(row);
            if round + 1 == repeat {
                let row = median_row(std::mem::take(&mut runs[i]));
                bar.suspend(|| print_row(&row, a.json))?;
            }
        }
    }
    bar.finish_and_clear();
    Ok(())
}

/// The arguments of a worker run: this bench's own switches (everything after `bench` but
/// the examples, the repeats and `--json`), for one example given after them.
fn worker_args(argv: Vec<String>) -> anyhow::Result<Vec<String>> {
    let at = argv
        .iter()
        .position(|s| s == "bench")
        .ok_or_else(|| anyhow::anyhow!("`bench` not found in the command line"))?;
    let mut out = vec!["bench".to_string()];
    let mut rest = argv[at + 1..].iter();
    while let Some(arg) = rest.next() {
        match arg.as_str() {
            "--examples" | "--repeat" => {
                rest.next();
            }
            "--json" => {}
            s if s.starts_with("--examples=") || s.starts_with("--repeat=") => {}
            _ => out.push(arg.clone()),
        }
    }
    out.push("--worker".into());
    Ok(out)
}

/// Runs example `name` once in a fresh process of this executable and reads its row.
fn run_worker(forwarded: &[String], name: &str) -> anyhow::Result<Row> {
    let exe = std::env::current_exe()?;
    let out = Command::new(exe)
        .args(forwarded)
        .args(["--examples", name])
        .stdin(Stdio::null())
        .stderr(Stdio::inherit())
        .output()?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        anyhow::bail!("{name}: the bench's run failed ({}): {stdout}", out.status);
    }
    let line = stdout
        .lines()
        .rev()
        .find(|l| l.starts_with('{'))
        .ok_or_else(|| anyhow::anyhow!("{name}: the bench's run printed no row: {stdout}"))?;
    Ok(serde_json::from_str(line)?)
}

/// The row of the run with the median wall time (the slower of the two middle ones for an
/// even count), with every run's wall time.
fn median_row(mut runs: Vec<Row>) -> Row {
    let walls: Vec<f64> = runs.iter().map(|r| r.wall_s).collect();
    runs.sort_by(|x, y| x.wall_s.total_cmp(&y.wall_s));
    let mut row = runs.swap_remove(runs.len() / 2);
    row.wall_runs = walls;
    row
}

fn run_once(
    a: &BenchArgs,
    pool: &rayon::ThreadPool,
    name: &str,
    ex: &paper::LoadedExample,
) -> anyhow::Result<Row> {
    let mut stability = StabilityParams::default();
    let mut params = GreedyParams::new(Budget::Fraction(ex.setup.budget_fraction));
    params.keep = ex.setup.keep.clone();
    for &t in &a.off {
        stability = stability.without(t);
    }
    if let Some(m) = a.modes {
        stability.tuning.modes = m;
    }
    profile::reset_peak_memory();
    profile::reset();
    let cpu_start = profile::cpu_seconds();
    let start = Instant::now();
    let outcome = pool.install(|| -> anyhow::Result<_> {
        let (network, _) = build_network(&ex.curves, &ex.build)?;
        let analyzer = Analyzer::new(network, stability).map_err(|e| usage(e.to_string()))?;
        let dofs = analyzer.model().dofs();
        Ok((greedy(&analyzer, &params, None, None, &mut NoHooks)?, dofs))
    })?;
    let wall = start.elapsed().as_secs_f64();
    let cpu = profile::cpu_seconds()
        .zip(cpu_start)
        .map(|(end, start)| ((end - start) * 100.0).round() / 100.0);
    let (o, dofs) = outcome;
    let p = profile::snapshot();
    let t = &o.timings;
    let last = o.iterations.last().expect("at least one iteration");
    let row = Row {
        example: name.to_string(),
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
        reference_s: reference_seconds(name),
        removed_first: o
            .iterations
            .iter()
            .filter_map(|i| i.removed)
            .take(3)
            .collect(),
        final_lambda: last.lambda,
        removed: o.iterations.iter().map(|i| i.removed).collect(),
        lambdas: o.iterations.iter().map(|i| i.lambda).collect(),
    };
    Ok(row)
}

fn print_row(row: &Row, json: bool) -> anyhow::Result<()> {
    let spread = match row.wall_runs.len() {
        0 | 1 => "-".to_string(),
        _ => {
            let lo = row.wall_runs.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = row.wall_runs.iter().copied().fold(0.0, f64::max);
            format!("{lo:.2}–{hi:.2}")
        }
    };
    println!(
        "{:<9} {:>6} {:>6} {:>5} {:>5} {:>6} {:>6} {:>6} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>11} {:>8} {:>8} {:>8}",
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
        row.reference_s
            .map_or("-".into(), |r| format!("{:.0}×", r / row.wall_s)),
    );
    if json {
        println!("{}", serde_json::to_string(row)?);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::worker_args;

    #[test]
    fn worker_runs_get_the_switches_but_not_the_examples_repeats_or_json() {
        let argv = [
            "curvenet",
            "bench",
            "--examples",
            "tower,roof",
            "--off",
            "prune,warm",
            "--repeat",
            "3",
            "--json",
            "--threads=2",
            "--repeat=4",
            "--examples=shell",
            "--data",
            "/d",
        ];
        let got = worker_args(argv.iter().map(|s| s.to_string()).collect()).expect("args");
        assert_eq!(
            got,
            [
                "bench",
                "--off",
                "prune,warm",
                "--threads=2",
                "--data",
                "/d",
                "--worker"
            ]
        );
    }
}
