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
use curvenet::experiments::bench::{
    BenchParams, References, Rounds, format_row, header, run_example,
};
use curvenet::experiments::worker::run_worker;
use curvenet::paper;
use indicatif::{ProgressBar, ProgressStyle};

pub fn run(a: BenchArgs) -> anyhow::Result<()> {
    let data = curvenet::app::inputs::data_source(a.data.as_deref()).map_err(crate::front::fail)?;
    let threads = a.threads.unwrap_or_else(rayon::current_num_threads);
    if a.worker {
        let [name] = a.examples.as_slice() else {
            return Err(usage("--worker runs exactly one example"));
        };
        curvenet::experiments::worker::exit_with_parent();
        let ex = paper::load_from(name, &data, Default::default())?;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()?;
        let params = BenchParams {
            off: a.off.clone(),
            modes: a.modes,
        };
        let row = run_example(&params, &pool, &ex).map_err(anyhow::Error::msg)?;
        println!("{}", serde_json::to_string(&row)?);
        return Ok(());
    }
    let references = match &a.reference {
        Some(path) => References::read(path)?,
        None => References::default(),
    };
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
    println!("{}", header());
    let repeat = a.repeat as usize;
    let forwarded = worker_args(std::env::args().collect())?;
    let mut rounds = Rounds::new(a.examples.len(), repeat, references);
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
            let args = [&forwarded[..], &["--examples".into(), name.clone()]].concat();
            let row = run_worker(&args, name)?;
            bar.inc(1);
            if repeat > 1 {
                bar.suspend(|| {
                    eprintln!("round {}/{repeat}: {name} {:.2} s", round + 1, row.wall_s)
                });
            }
            if let Some(row) = rounds.record(i, name, round, row)? {
                bar.suspend(|| {
                    println!("{}", format_row(&row));
                    if a.json {
                        println!("{}", serde_json::to_string(&row).unwrap_or_default());
                    }
                });
            }
        }
    }
    bar.finish_and_clear();
    Ok(())
}

/// The arguments of a worker run: this bench's own switches (everything after `bench` but
/// the examples, the repeats, the references and `--json`), for one example given after them.
fn worker_args(argv: Vec<String>) -> anyhow::Result<Vec<String>> {
    let valued = ["--examples", "--repeat", "--reference"];
    curvenet::experiments::bench::worker_args(&argv, "bench", &valued, &["--json"], "--worker")
        .ok_or_else(|| anyhow::anyhow!("`bench` not found in the command line"))
}
