//! `curvenet serve`, the real binary: the URL on its first line of stdout, `λ` of its states
//! equal to `curvenet analyze --remove` of the same sets, and its usage errors (exit 2).
#![cfg(feature = "serve")]

mod common;

use common::BIN;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};

/// A 3 × 3 grid of gently arched curves crossing at nine points (reference text format).
fn grid() -> String {
    let mut s = String::new();
    for (c, (dir, at)) in [(0, -1.0), (0, 0.0), (0, 1.0), (1, -1.0), (1, 0.0), (1, 1.0)]
        .into_iter()
        .enumerate()
    {
        s.push_str(&format!("CURVE {c}\n"));
        for i in 0..=8 {
            let t = -2.0 + 0.5 * i as f64;
            let z = 0.3 * (1.0 - t * t / 4.0);
            let (x, y) = if dir == 0 { (t, at) } else { (at, t) };
            s.push_str(&format!("{x} {y} {z}\n"));
        }
    }
    s
}

/// Options fit for the grid: a thin rod and a short edge length.
const QUIET: &[&str] = &["--radius", "0.01", "--edge-length", "0.25"];

/// A folder holding the grid's file.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("curvenet-serve-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("grid.txt"), grid()).unwrap();
    dir
}

/// A running `curvenet serve`, killed when dropped.
struct Served {
    child: Child,
    url: String,
}

impl Drop for Served {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn serve(dir: &PathBuf, extra: &[&str]) -> Served {
    let mut child = Command::new(BIN)
        .args(["serve", "--curves", "grid.txt", "--port", "0"])
        .args(QUIET)
        .args(extra)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    Served {
        child,
        url: line.trim().to_string(),
    }
}

/// One request to the server at `url`; the status and the JSON body.
fn request(url: &str, method: &str, path: &str, body: &str) -> (u16, serde_json::Value) {
    let host = url.strip_prefix("http://").expect("an http URL");
    let mut s = TcpStream::connect(host).unwrap();
    write!(
        s,
        "{method} {path} HTTP/1.1\r\nHost: {host}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    let mut text = String::new();
    s.read_to_string(&mut text).unwrap();
    let (head, body) = text.split_once("\r\n\r\n").unwrap();
    let status = head.split(' ').nth(1).unwrap().parse().unwrap();
    (status, serde_json::from_str(body).unwrap())
}

/// `λ` of `curvenet analyze --json --remove removed`.
fn analyze(dir: &PathBuf, removed: &str) -> f64 {
    let mut args = vec!["analyze", "--json", "--curves", "grid.txt"];
    args.extend_from_slice(QUIET);
    if !removed.is_empty() {
        args.extend(["--remove", removed]);
    }
    let out = Command::new(BIN)
        .args(&args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    v["lambda"].as_f64().unwrap()
}

fn assert_close(served: &serde_json::Value, expected: f64) {
    let lambda = served["lambda"].as_f64().unwrap();
    assert!(
        (lambda - expected).abs() <= 1e-6 * expected.abs(),
        "served λ {lambda:e}, analyze {expected:e}"
    );
}

#[test]
fn serve_answers_with_the_lambda_of_analyze_remove() {
    let dir = folder("lambda");
    let s = serve(&dir, &["--remove", "4"]);
    assert!(s.url.starts_with("http://127.0.0.1:"), "{}", s.url);
    let (status, state) = request(&s.url, "GET", "/api/state", "");
    assert_eq!(status, 200);
    assert_eq!(state["curves"], serde_json::json!([0, 1, 2, 3, 5]));
    assert_close(&state, analyze(&dir, "4"));

    let (status, set) = request(&s.url, "POST", "/api/set", r#"{"curves":[0,2,3,4]}"#);
    assert_eq!(status, 200);
    assert_close(&set, analyze(&dir, "1,5"));
    let (status, toggled) = request(&s.url, "POST", "/api/toggle", r#"{"curve":5}"#);
    assert_eq!(status, 200);
    assert_eq!(toggled["curves"], serde_json::json!([0, 2, 3, 4, 5]));
    assert_close(&toggled, analyze(&dir, "1"));
    drop(s);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn serve_usage_errors_exit_2_naming_the_option() {
    let dir = folder("usage");
    let cases: &[(&[&str], &str)] = &[
        (&["--remove", "9"], "--remove names curve 9"),
        (
            &["--remove", "0,1,2,3,4,5"],
            "--remove would remove every curve",
        ),
        (
            &["--host", "no such host.invalid"],
            "--host no such host.invalid",
        ),
        (&["--example", "tower"], "cannot be used with"),
        (
            &["--host", "0.0.0.0", "--remove", "9"],
            "reachable from other machines",
        ),
        (
            &["--example", "nowhere", "--curves", "x"],
            "cannot be used with",
        ),
    ];
    for (extra, says) in cases {
        let out = Command::new(BIN)
            .args(["serve", "--curves", "grid.txt", "--port", "0"])
            .args(QUIET)
            .args(*extra)
            .current_dir(&dir)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains(says), "{extra:?}: {stderr}");
        assert!(out.stdout.is_empty(), "{extra:?}");
    }
    // Negative numbers reach their option's check instead of being taken for a flag.
    let negatives: &[(&[&str], &str)] = &[
        (&["--port", "-1"], "--port"),
        (&["--port", "65536"], "--port"),
        (&["--bench", "--bench-removals", "-1"], "--bench-removals"),
    ];
    for (args, says) in negatives {
        let out = Command::new(BIN)
            .args(["serve", "--curves", "grid.txt"])
            .args(*args)
            .current_dir(&dir)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
        assert!(
            !stderr.contains("unexpected argument"),
            "{args:?}: {stderr}"
        );
    }
    // A port in use: the message names it and suggests --port 0.
    let s = serve(&dir, &[]);
    let port = s.url.rsplit(':').next().unwrap().to_string();
    let out = Command::new(BIN)
        .args(["serve", "--curves", "grid.txt", "--port", &port])
        .args(QUIET)
        .current_dir(&dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("--port 0"), "{stderr}");
    drop(s);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The line on stderr saying what is served names the structure's status in words.
#[test]
fn serve_says_the_status_in_words() {
    let dir = folder("status");
    let mut child = Command::new(BIN)
        .args(["serve", "--curves", "grid.txt", "--port", "0"])
        .args(QUIET)
        .current_dir(&dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    while stderr.read_line(&mut line).unwrap() > 0 && !line.contains("serving") {
        line.clear();
    }
    let _ = child.kill();
    let _ = child.wait();
    assert!(line.contains("(stable)"), "{line}");
    assert!(!line.contains("Stable"), "{line}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A `simplify` run of the grid into `dir/run`.
fn simplified(dir: &PathBuf) -> PathBuf {
    let out = Command::new(BIN)
        .args([
            "simplify", "--curves", "grid.txt", "--budget", "0.6", "--out", "run",
        ])
        .args(QUIET)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    dir.join("run")
}

/// `curvenet serve --run DIR` with `extra` options, its stdout's first line read.
fn serve_run(dir: &PathBuf, run: &str, extra: &[&str]) -> Served {
    let mut child = Command::new(BIN)
        .args(["serve", "--run", run, "--port", "0"])
        .args(extra)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    Served {
        child,
        url: line.trim().to_string(),
    }
}

#[test]
fn serve_run_starts_on_the_runs_answer_with_its_iterations_to_step_through() {
    let dir = folder("run");
    let run = simplified(&dir);
    let result: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("result.json")).unwrap()).unwrap();
    let s = serve_run(&dir, "run", &[]);
    let (status, state) = request(&s.url, "GET", "/api/state", "");
    assert_eq!(status, 200);
    let answer = &result["answer"]["curves"];
    assert_eq!(&state["curves"], answer);
    let removed: Vec<String> = (0..6)
        .filter(|c| !answer.as_array().unwrap().contains(&serde_json::json!(c)))
        .map(|c| c.to_string())
        .collect();
    assert_close(&state, analyze(&dir, &removed.join(",")));
    // The run's iterations, to step through.
    let (status, progress) = request(&s.url, "GET", "/api/greedy", "");
    assert_eq!(status, 200);
    assert_eq!(progress["status"], "done");
    assert_eq!(progress["stop"], "budget met");
    let (_, listed) = request(&s.url, "GET", "/api/greedy/iterations", "");
    let recorded = result["iterations"].as_array().unwrap();
    let listed = listed["iterations"].as_array().unwrap();
    assert_eq!(listed.len(), recorded.len());
    for (a, b) in listed.iter().zip(recorded) {
        assert_eq!(a["curves"], b["curves"]);
    }
    let (status, step) = request(&s.url, "POST", "/api/greedy/step", r#"{"iteration":0}"#);
    assert_eq!(status, 200);
    assert_eq!(step["curves"], serde_json::json!([0, 1, 2, 3, 4, 5]));
    assert_close(&step, analyze(&dir, ""));
    // No request reaches the folder's files.
    for path in [
        "/result.json",
        "/run/result.json",
        "/api/../result.json",
        "/%2e%2e/grid.txt",
    ] {
        let (status, body) = request(&s.url, "GET", path, "");
        assert_eq!(status, 404, "{path}: {body}");
    }
    drop(s);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn serve_run_usage_errors_exit_2_naming_the_folder_or_the_option() {
    let dir = folder("run-usage");
    let run = simplified(&dir);
    std::fs::create_dir_all(dir.join("broken")).unwrap();
    std::fs::write(dir.join("broken/result.json"), "{\"version\": ").unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["--run", "nowhere"], "nowhere: not a folder"),
        (&["--run", "broken"], "broken/result.json"),
        (&["--run", "run", "--radius", "1"], "cannot be used with"),
        (
            &["--run", "run", "--curves", "grid.txt"],
            "cannot be used with",
        ),
        (&["--run", "run", "--remove", "7"], "--remove names curve 7"),
    ];
    for (args, says) in cases {
        let out = Command::new(BIN)
            .args(["serve", "--port", "0"])
            .args(*args)
            .current_dir(&dir)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
        assert!(out.stdout.is_empty(), "{args:?}");
    }
    assert!(run.join("result.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
