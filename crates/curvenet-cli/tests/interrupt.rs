//! Signals on the real binary. SIGINT, SIGTERM and SIGHUP alike stop every long stage (the greedy, the
//! local search, the certificate, the comparison's searches) within about a second with exit
//! code 130, keeping what was recorded; `--resume` then writes a `result.json` byte-identical
//! to the one of an uninterrupted run, also after SIGKILL (again and again).

#![cfg(unix)]

mod common;

use common::{BIN, TempDir, dome_curves, dome_run};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The longest a stage may take to stop after a signal. The stages poll their token every
/// fraction of a second; the margin is for a loaded machine.
const STOP_WITHIN: Duration = Duration::from_secs(3);

/// The arguments of one `simplify` run of `curves` into `out`, then `extra`.
fn simplify_args(curves: &Path, out: &Path, extra: &[&str]) -> Vec<String> {
    let mut args = dome_run(curves.to_str().unwrap(), out.to_str().unwrap());
    args.extend(extra.iter().map(|s| s.to_string()));
    args
}

/// Runs the binary to its end, asserting exit 0.
fn run_ok(args: &[String]) -> Output {
    let out = Command::new(BIN)
        .args(args)
        .output()
        .expect("curvenet runs");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Completed iterations in a run folder (the states the greedy saved).
fn saved_iterations(out: &Path) -> usize {
    std::fs::read_dir(out.join("iterations"))
        .map(|d| d.filter_map(Result::ok).count())
        .unwrap_or(0)
}

/// Starts the binary with stderr captured.
fn start(args: &[String]) -> Child {
    Command::new(BIN)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("curvenet starts")
}

/// Waits until `ready` holds, failing if the child ends first.
fn wait_until(child: &mut Child, ready: impl Fn() -> bool) {
    let start = Instant::now();
    while !ready() {
        assert!(start.elapsed() < Duration::from_secs(120), "no progress");
        assert!(
            child.try_wait().expect("wait").is_none(),
            "finished before it could be interrupted"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Sends `signal` ("INT", "TERM", "HUP") to the child and waits for it: its output and how long it
/// took to stop.
fn interrupt(child: Child, signal: &str) -> (Output, Duration) {
    let kill = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(kill.success());
    let sent = Instant::now();
    let out = child.wait_with_output().expect("curvenet ends");
    (out, sent.elapsed())
}

/// Asserts a run stopped by a signal exited 130 within [`STOP_WITHIN`], saying how to go on.
fn assert_cancelled(out: &Output, took: Duration, stage: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!(
        "{stage}: stopped {:.3} s after the signal, exit {:?}",
        took.as_secs_f64(),
        out.status.code()
    );
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(took < STOP_WITHIN, "{stage} took {took:?} to stop");
    assert!(
        stderr.contains("--resume"),
        "tells how to continue: {stderr}"
    );
}

/// A greedy run interrupted by `signal` once it has saved six iterations (past the first
/// iterations that hand test vectors on to the next) keeps them, and `--resume` gives the
/// uninterrupted run's result.json.
fn greedy_interrupted_by(signal: &str) {
    let tmp = TempDir::new(&format!("int-greedy-{signal}"));
    let curves = dome_curves(&tmp.0, "curves.json");
    let full = tmp.0.join("full");
    run_ok(&simplify_args(&curves, &full, &[]));
    let reference = std::fs::read(full.join("result.json")).expect("result.json");
    let total = saved_iterations(&full);
    assert!(
        total >= 5,
        "the run is long enough to interrupt ({total} iterations)"
    );

    let cut = tmp.0.join("cut");
    let mut child = start(&simplify_args(&curves, &cut, &[]));
    wait_until(&mut child, || saved_iterations(&cut) >= 6);
    let (out, took) = interrupt(child, signal);
    if out.status.code() == Some(0) {
        // The signal came after the last iteration: nothing to resume, same result.
        assert_eq!(std::fs::read(cut.join("result.json")).unwrap(), reference);
        return;
    }
    assert_cancelled(&out, took, "the greedy");
    let kept = saved_iterations(&cut);
    assert!(
        (6..=total).contains(&kept),
        "kept {kept} of {total} iterations"
    );

    run_ok(&simplify_args(&curves, &cut, &["--resume"]));
    let resumed = std::fs::read(cut.join("result.json")).expect("result.json");
    assert!(
        resumed == reference,
        "resumed result.json differs from the uninterrupted one"
    );
    assert_eq!(saved_iterations(&cut), total);
}

#[test]
fn sigint_during_the_greedy_keeps_its_iterations_and_resume_matches_an_uninterrupted_run() {
    greedy_interrupted_by("INT");
}

#[test]
fn sigterm_during_the_greedy_keeps_its_iterations_and_resume_matches_an_uninterrupted_run() {
    greedy_interrupted_by("TERM");
}

#[test]
fn sigkill_again_and_again_during_the_greedy_then_resume_matches_an_uninterrupted_run() {
    let tmp = TempDir::new("int-greedy-KILL");
    let curves = dome_curves(&tmp.0, "curves.json");
    let full = tmp.0.join("full");
    run_ok(&simplify_args(&curves, &full, &[]));
    let reference = std::fs::read(full.join("result.json")).expect("result.json");

    // Killed (no handler runs) a few iterations further each time, then resumed, until the
    // run finishes: each kill lands wherever the run happens to be, writing or computing.
    let cut = tmp.0.join("cut");
    let mut kills = 0;
    let mut extra: &[&str] = &[];
    loop {
        let before = saved_iterations(&cut);
        let mut child = start(&simplify_args(&curves, &cut, extra));
        extra = &["--resume"];
        let started = Instant::now();
        let ended = loop {
            if child.try_wait().expect("wait").is_some() {
                break true;
            }
            if saved_iterations(&cut) >= before + 3 {
                break false;
            }
            assert!(started.elapsed() < Duration::from_secs(120), "no progress");
            std::thread::sleep(Duration::from_millis(5));
        };
        if !ended {
            child.kill().expect("SIGKILL");
            kills += 1;
        }
        let out = child.wait_with_output().expect("curvenet ends");
        let stderr = String::from_utf8_lossy(&out.stderr);
        // The build's own finding (two joints nearly coincide on this sketch) is printed by
        // every run; a resume adds none of its own.
        assert!(
            !stderr
                .lines()
                .any(|l| l.contains("warning") && !l.contains("the shortest rest edge")),
            "a resume after a kill goes on without warnings: {stderr}"
        );
        if ended {
            assert_eq!(out.status.code(), Some(0), "{stderr}");
            break;
        }
    }
    println!("killed {kills} times, resumed each time");
    assert!(kills >= 2, "the run was killed {kills} times");
    let resumed = std::fs::read(cut.join("result.json")).expect("result.json");
    assert!(
        resumed == reference,
        "resumed result.json differs from the uninterrupted one"
    );
}

/// A run interrupted by `signal` in the stage after the greedy (the greedy's last iteration
/// saved, the run not finished) stops at once, and `--resume` finishes it with the
/// uninterrupted run's result.json.
fn stage_after_the_greedy_interrupted_by(signal: &str, stage: &str, extra: &[&str]) {
    let tmp = TempDir::new(&format!("int-after-{signal}"));
    let curves = dome_curves(&tmp.0, "curves.json");
    let full = tmp.0.join("full");
    run_ok(&simplify_args(&curves, &full, extra));
    let reference = std::fs::read(full.join("result.json")).expect("result.json");
    let total = saved_iterations(&full);

    let cut = tmp.0.join("cut");
    let mut child = start(&simplify_args(&curves, &cut, extra));
    wait_until(&mut child, || saved_iterations(&cut) >= total);
    // Into the stage (it takes seconds on this network).
    std::thread::sleep(Duration::from_millis(300));
    let (out, took) = interrupt(child, signal);
    assert_cancelled(&out, took, stage);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains(stage), "names the stage: {stderr}");
    assert!(
        !std::fs::read_to_string(cut.join("result.json"))
            .expect("result.json kept")
            .is_empty()
    );

    run_ok(&simplify_args(
        &curves,
        &cut,
        &[extra, &["--resume"]].concat(),
    ));
    let resumed = std::fs::read(cut.join("result.json")).expect("result.json");
    assert!(
        resumed == reference,
        "resumed result.json differs from the uninterrupted one"
    );
}

#[test]
fn sigterm_during_the_local_search_stops_it_at_once_and_resume_finishes_the_run() {
    // With alternatives: the resumed run finds the same ones.
    stage_after_the_greedy_interrupted_by(
        "TERM",
        "the local search",
        &["--local-search", "--alternatives", "3"],
    );
}

#[test]
fn sigint_during_the_certificate_stops_it_at_once_and_resume_finishes_the_run() {
    stage_after_the_greedy_interrupted_by("INT", "the certificate", &["--certify"]);
}

#[test]
fn sigint_during_the_local_search_stops_it_at_once_and_resume_finishes_the_run() {
    stage_after_the_greedy_interrupted_by("INT", "the local search", &["--local-search"]);
}

#[test]
fn sigterm_during_the_certificate_stops_it_at_once_and_resume_finishes_the_run() {
    stage_after_the_greedy_interrupted_by("TERM", "the certificate", &["--certify"]);
}

#[test]
fn sighup_during_the_greedy_keeps_its_iterations_and_resume_matches_an_uninterrupted_run() {
    greedy_interrupted_by("HUP");
}

/// The processes whose parent is `pid` (Linux: `/proc/PID/task/PID/children`).
fn children_of(pid: u32) -> Vec<u32> {
    let path = format!("/proc/{pid}/task/{pid}/children");
    let text = std::fs::read_to_string(path).unwrap_or_default();
    text.split_whitespace()
        .filter_map(|s| s.parse().ok())
        .collect()
}

#[test]
fn sigterm_to_a_bench_ends_its_worker_too() {
    if !Path::new("/proc/self/task").is_dir() {
        return; // no /proc to find the worker by
    }
    let mut child = start(&["bench", "--examples", "tower"].map(String::from));
    let parent = child.id();
    let start = Instant::now();
    let worker = loop {
        if let Some(&w) = children_of(parent).first() {
            break w;
        }
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no worker started"
        );
        assert!(child.try_wait().expect("wait").is_none(), "the bench ended");
        std::thread::sleep(Duration::from_millis(5));
    };
    std::thread::sleep(Duration::from_millis(300));
    let (out, _) = interrupt(child, "TERM");
    assert_eq!(out.status.code(), Some(130));
    // The worker ends with the bench (it is nobody's child now: watch its /proc entry).
    let sent = Instant::now();
    let alive = || {
        std::fs::read_to_string(format!("/proc/{worker}/stat")).is_ok_and(|s| {
            !s.rsplit(')')
                .next()
                .unwrap_or("")
                .trim_start()
                .starts_with('Z')
        })
    };
    while alive() {
        assert!(sent.elapsed() < STOP_WITHIN, "the worker still runs");
        std::thread::sleep(Duration::from_millis(10));
    }
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn sigterm_during_a_comparison_stops_it_at_once_and_writes_no_report() {
    let tmp = TempDir::new("int-compare");
    let json = tmp.0.join("compare.json");
    let mut child = start(
        &[
            "compare",
            "--sizes",
            "16",
            "--instances",
            "3",
            "--json",
            json.to_str().unwrap(),
        ]
        .map(String::from),
    );
    std::thread::sleep(Duration::from_secs(1));
    assert!(child.try_wait().expect("wait").is_none(), "still searching");
    let (out, took) = interrupt(child, "TERM");
    println!(
        "compare: stopped {:.3} s after the signal",
        took.as_secs_f64()
    );
    assert_eq!(
        out.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(took < STOP_WITHIN, "took {took:?} to stop");
    assert!(!json.exists(), "no report of a cancelled comparison");
}

#[test]
fn resume_draws_the_pictures_a_signal_stopped() {
    // A signal while the pictures are drawn ends the process at once: the run is complete
    // (result.json finished) but its pictures and viewer page are missing.
    let tmp = TempDir::new("int-pictures");
    let curves = dome_curves(&tmp.0, "curves.json");
    let out = tmp.0.join("out");
    run_ok(&simplify_args(&curves, &out, &[]));
    let result = std::fs::read(out.join("result.json")).expect("result.json");
    for f in ["viewer.html", "final.png", "mode.png"] {
        std::fs::remove_file(out.join(f)).expect("written by the run");
    }
    let resumed = run_ok(&simplify_args(&curves, &out, &["--resume"]));
    assert!(String::from_utf8_lossy(&resumed.stderr).contains("already complete"));
    for f in ["viewer.html", "final.png", "mode.png"] {
        assert!(out.join(f).is_file(), "{f} drawn again");
    }
    assert_eq!(std::fs::read(out.join("result.json")).unwrap(), result);
}

/// The temporary files (`.NAME.tmp.PID.N`) in `out` and its sub-folders.
fn temp_files(out: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut dirs = vec![out.to_path_buf()];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                dirs.push(p);
            } else if e.file_name().to_string_lossy().contains(".tmp.") {
                found.push(p);
            }
        }
    }
    found
}

/// Whether one of the files written after the run's result (pictures, viewer page,
/// fabrication table) is being written in `out`: its temporary file is there.
fn writing_pictures(out: &Path) -> bool {
    const AFTER_THE_RESULT: [&str; 5] = [
        ".final.png.tmp.",
        ".mode.png.tmp.",
        ".lambda.png.tmp.",
        ".viewer.html.tmp.",
        ".fabrication.csv.tmp.",
    ];
    std::fs::read_dir(out)
        .into_iter()
        .flatten()
        .flatten()
        .any(|e| {
            let name = e.file_name();
            let name = name.to_string_lossy();
            AFTER_THE_RESULT.iter().any(|t| name.starts_with(t))
        })
}

#[test]
fn sigterm_while_the_pictures_are_written_leaves_no_temporary_file_and_resume_cleans_up() {
    let tmp = TempDir::new("int-pictures-TERM");
    let curves = dome_curves(&tmp.0, "curves.json");
    let out = tmp.0.join("out");
    let args = simplify_args(&curves, &out, &[]);
    // The signal is sent the moment a picture's temporary file appears (its write in flight).
    // Whether the write could have finished before the process ends depends on the moment,
    // so the run is interrupted several times; a run that ends first (the write too quick to
    // be seen, or the signal arriving as the process exits) does not count.
    let mut interrupted = 0;
    for _ in 0..30 {
        if interrupted == 6 {
            break;
        }
        let _ = std::fs::remove_dir_all(&out);
        let mut child = start(&args);
        let started = Instant::now();
        let seen = loop {
            if writing_pictures(&out) {
                break true;
            }
            if child.try_wait().expect("wait").is_some() {
                break false;
            }
            assert!(started.elapsed() < Duration::from_secs(120), "no progress");
            std::thread::yield_now();
        };
        if !seen {
            continue;
        }
        let (o, took) = interrupt(child, "TERM");
        println!(
            "pictures: stopped {:.3} s after the signal, exit {:?}",
            took.as_secs_f64(),
            o.status.code()
        );
        if o.status.code() == Some(0) {
            // The signal came as the run was ending: it ended whole, which does not count.
            assert!(out.join("viewer.html").is_file() && out.join("final.png").is_file());
            assert_eq!(temp_files(&out), Vec::<PathBuf>::new(), "a whole run");
            continue;
        }
        interrupted += 1;
        assert_eq!(
            o.status.code(),
            Some(130),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(took < STOP_WITHIN, "the pictures took {took:?} to stop");
        assert_eq!(
            temp_files(&out),
            Vec::<PathBuf>::new(),
            "no temporary file left"
        );
    }
    assert_eq!(interrupted, 6, "picture writes seen in flight");
    let result = std::fs::read(out.join("result.json")).expect("result.json kept");

    // What a killed run (no handler runs) leaves behind: a resumed run removes it.
    let pid = 4_000_000;
    let planted = [
        out.join(format!(".result.json.tmp.{pid}.0")),
        out.join(format!("iterations/.0003.obj.tmp.{pid}.1")),
        out.join(format!("states/.0002.bin.tmp.{pid}.2")),
    ];
    for p in &planted {
        std::fs::write(p, b"half").expect("planted");
    }
    let resumed = run_ok(&simplify_args(&curves, &out, &["--resume"]));
    let stderr = String::from_utf8_lossy(&resumed.stderr);
    assert!(stderr.contains("already complete"), "{stderr}");
    assert!(stderr.contains("removed 3 temporary file(s)"), "{stderr}");
    assert_eq!(
        temp_files(&out),
        Vec::<PathBuf>::new(),
        "stale temporary files removed"
    );
    for f in ["viewer.html", "final.png", "mode.png"] {
        assert!(out.join(f).is_file(), "{f} drawn");
    }
    assert!(
        std::fs::read(out.join("result.json")).unwrap() == result,
        "resume leaves the finished result.json as it was"
    );
}
