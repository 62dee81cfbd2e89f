//! Ctrl-C on the real binary (issue 7): `curvenet simplify` interrupted by SIGINT part-way
//! exits with code 130 keeping the iterations it finished, and `--resume` then writes a
//! `result.json` byte-identical to the one of an uninterrupted run.

#![cfg(unix)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The binary under test.
const BIN: &str = env!("CARGO_BIN_EXE_curvenet");

/// A fresh temporary folder, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("curvenet-int-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temporary folder");
        TempDir(dir)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The arguments of one `simplify` run of `curves` into `out`.
fn simplify_args(curves: &Path, out: &Path) -> Vec<String> {
    [
        "simplify",
        "--mesh",
        "dome",
        "--curves",
        curves.to_str().unwrap(),
        "--edge-length",
        "100",
        "--budget",
        "0.3",
        "--out",
        out.to_str().unwrap(),
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

/// Completed iterations in a run folder (the states the greedy saved).
fn saved_iterations(out: &Path) -> usize {
    std::fs::read_dir(out.join("iterations"))
        .map(|d| d.filter_map(Result::ok).count())
        .unwrap_or(0)
}

#[test]
fn sigint_keeps_finished_iterations_and_resume_matches_an_uninterrupted_run() {
    let tmp = TempDir::new("sigint");
    let curves = tmp.0.join("curves.json");
    let status = Command::new(BIN)
        .args([
            "trace",
            "--mesh",
            "dome",
            "--geodesics",
            "24",
            "--seed",
            "1",
        ])
        .arg("--out")
        .arg(&curves)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .expect("trace runs");
    assert!(status.success(), "trace failed");

    // The reference: an uninterrupted run.
    let full = tmp.0.join("full");
    let out = Command::new(BIN)
        .args(simplify_args(&curves, &full))
        .output()
        .expect("simplify runs");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let reference = std::fs::read(full.join("result.json")).expect("result.json");
    let total = saved_iterations(&full);
    assert!(
        total >= 5,
        "the run is long enough to interrupt ({total} iterations)"
    );

    // Interrupt a second run once it has saved two iterations (and before it is done).
    let cut = tmp.0.join("cut");
    let mut child = Command::new(BIN)
        .args(simplify_args(&curves, &cut))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("simplify starts");
    let start = Instant::now();
    while saved_iterations(&cut) < 2 {
        assert!(start.elapsed() < Duration::from_secs(120), "no progress");
        assert!(
            child.try_wait().expect("wait").is_none(),
            "finished before it could be cut"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(kill.success());
    let at = saved_iterations(&cut);
    let out = child.wait_with_output().expect("simplify ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!(
        "SIGINT sent with {at} iteration(s) saved after {:.2} s; exit {:?}",
        start.elapsed().as_secs_f64(),
        out.status.code()
    );
    if out.status.code() == Some(0) {
        // The signal came after the last iteration: nothing to resume, same result.
        assert_eq!(std::fs::read(cut.join("result.json")).unwrap(), reference);
        return;
    }
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(
        stderr.contains("--resume"),
        "tells how to continue: {stderr}"
    );
    let kept = saved_iterations(&cut);
    assert!(
        (2..=total).contains(&kept),
        "kept {kept} of {total} iterations"
    );

    // Resume: the same result.json, byte for byte.
    let mut args = simplify_args(&curves, &cut);
    args.push("--resume".into());
    let out = Command::new(BIN).args(args).output().expect("resume runs");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let resumed = std::fs::read(cut.join("result.json")).expect("result.json");
    assert!(
        resumed == reference,
        "resumed result.json differs from the uninterrupted one"
    );
    assert_eq!(saved_iterations(&cut), total);
}
