//! `curvenet bench` on one paper example: the table's columns and its `--json` rows, whose
//! times must be consistent with each other (the CPU time against the wall time and the
//! thread count), and `--repeat`, whose row is the median run.

mod common;

use common::BIN;
use std::process::Command;

#[test]
fn the_bench_row_reports_wall_and_cpu_time_consistently() {
    let out = Command::new(BIN)
        .args([
            "bench",
            "--examples",
            "tower",
            "--threads",
            "2",
            "--json",
            "--repeat",
            "2",
        ])
        .output()
        .expect("run curvenet bench");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "bench failed: {stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let header = stdout
        .lines()
        .find(|l| l.starts_with("example"))
        .expect("a header line");
    for column in ["wall s", "wall range", "cpu s", "peak MiB", "facts"] {
        assert!(header.contains(column), "no `{column}` in {header:?}");
    }
    let row: serde_json::Value = stdout
        .lines()
        .find(|l| l.starts_with('{'))
        .map(|l| serde_json::from_str(l).expect("a JSON row"))
        .expect("a --json row");
    assert_eq!(row["example"], "tower");
    assert_eq!(row["curves"], 33);
    let wall = row["wall_s"].as_f64().expect("wall_s");
    let cpu = row["cpu_s"].as_f64().expect("cpu_s (Linux /proc)");
    assert!(wall > 0.0);
    // Two runs (they agreed bit for bit, or the bench would have failed); the row is the
    // slower of the two middle ones, so the slower run here.
    let runs: Vec<f64> = row["wall_runs"]
        .as_array()
        .expect("wall_runs")
        .iter()
        .map(|w| w.as_f64().expect("a wall time"))
        .collect();
    assert_eq!(runs.len(), 2, "one wall time per run: {runs:?}");
    assert_eq!(wall, runs[0].max(runs[1]), "the median run's wall time");
    assert!(
        stdout.lines().filter(|l| l.starts_with('{')).count() == 1,
        "one row per example, not per run"
    );
    // CPU time was counted (how much of the wall time it fills depends on what else the
    // machine runs, so only its physical ceiling is checked: at most two threads' worth plus
    // the counters' 10 ms resolution).
    assert!(cpu > 0.0, "cpu {cpu} s for a wall time of {wall} s");
    assert!(
        cpu <= 2.0 * wall + 0.05,
        "cpu {cpu} s exceeds two threads over {wall} s"
    );
    // The greedy's phases ran: its factorization counter and phase times are filled in.
    assert!(row["factorizations"].as_u64().is_some_and(|f| f > 0));
    assert!(row["factor_s"].as_f64().is_some_and(|t| t > 0.0));
}
