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

/// `curvenet serve --curves grid.txt` (with the quiet options and `extra`) in `dir`.
fn serve(dir: &PathBuf, extra: &[&str]) -> Served {
    let mut args = vec!["--curves", "grid.txt"];
    args.extend_from_slice(QUIET);
    args.extend_from_slice(extra);
    serve_with(dir, &args, None)
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
        (&["--runs", "nowhere"], "--runs nowhere: no such folder"),
        (&["--material", "steel"], "--units"),
        (&["--units", "furlong"], "--units"),
        (
            &["--density", "7850kg/m3"],
            "--density belongs to the physical mode",
        ),
        (&["--objective", "beauty"], "--objective"),
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
    let mut args = vec!["--run", run];
    args.extend_from_slice(extra);
    serve_with(dir, &args, None)
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

/// `curvenet serve ARGS --port 0` in `dir` with `path` as its PATH when given, stderr to
/// `dir/stderr.txt`; its stdout's first line read.
fn serve_with(dir: &PathBuf, args: &[&str], path: Option<&str>) -> Served {
    let mut cmd = Command::new(BIN);
    cmd.arg("serve")
        .args(args)
        .args(["--port", "0"])
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(std::fs::File::create(dir.join("stderr.txt")).unwrap());
    if let Some(p) = path {
        cmd.env("PATH", p);
    }
    let mut child = cmd.spawn().unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    Served {
        child,
        url: line.trim().to_string(),
    }
}

/// `curvenet analyze --json ARGS` in `dir`: its JSON.
fn analyze_json(dir: &PathBuf, args: &[&str]) -> serde_json::Value {
    let out = Command::new(BIN)
        .args(["analyze", "--json"])
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn serve_answers_with_the_lambda_of_analyze_on_a_random_geodesic_network() {
    let dir = folder("geodesics");
    let out = Command::new(BIN)
        .args([
            "trace",
            "--mesh",
            "dome",
            "--geodesics",
            "12",
            "--seed",
            "5",
        ])
        .args(["--out", "geo.json"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let input = ["--curves", "geo.json", "--mesh", "dome"];
    let s = serve_with(&dir, &input, None);
    // Random removal sets (SplitMix64-like steps, fixed seed), each against a cold analyze.
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut next = || {
        x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = x;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    for removed in [1, 2, 3, 4] {
        let mut ids: Vec<usize> = (0..12).collect();
        for i in 0..removed {
            let j = i + (next() % (12 - i) as u64) as usize;
            ids.swap(i, j);
        }
        let mut gone = ids[..removed].to_vec();
        gone.sort_unstable();
        let kept: Vec<usize> = (0..12).filter(|c| !gone.contains(c)).collect();
        let (status, state) = request(
            &s.url,
            "POST",
            "/api/set",
            &format!("{{\"curves\":{kept:?}}}"),
        );
        assert_eq!(status, 200, "{state}");
        let list: Vec<String> = gone.iter().map(usize::to_string).collect();
        let mut args = input.to_vec();
        let list = list.join(",");
        args.extend(["--remove", &list]);
        let cold = analyze_json(&dir, &args);
        assert_close(&state, cold["lambda"].as_f64().unwrap());
        assert_eq!(state["zero_modes"], cold["zero_modes"], "{gone:?}");
        assert_eq!(state["negative_modes"], cold["negative_modes"], "{gone:?}");
    }
    drop(s);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn serve_in_the_physical_mode_gives_the_physical_numbers_of_analyze() {
    let dir = folder("physical");
    let physical = ["--units", "m", "--material", "steel"];
    let mut args = vec!["--curves", "grid.txt"];
    args.extend_from_slice(QUIET);
    args.extend_from_slice(&physical);
    let s = serve_with(&dir, &args, None);
    let (status, state) = request(&s.url, "POST", "/api/toggle", r#"{"curve":2}"#);
    assert_eq!(status, 200, "{state}");
    let mut cold_args = args.clone();
    cold_args.extend(["--remove", "2"]);
    let cold = analyze_json(&dir, &cold_args);
    assert_close(&state, cold["lambda"].as_f64().unwrap());
    let (p, q) = (&state["physical"], &cold["physical"]);
    for key in [
        "first_frequency_hz",
        "self_weight_max_deflection",
        "assembly_max_bending_stress_mpa",
        "assembly_max_axial_stress_mpa",
        "mass_kg",
    ] {
        let (a, b) = (p[key].as_f64().unwrap(), q[key].as_f64().unwrap());
        assert!(
            (a - b).abs() <= 1e-9 * b.abs(),
            "{key}: served {a}, analyze {b}"
        );
    }
    assert_eq!(
        p["load_max_deflection"]["vertex"],
        q["load_max_deflection"]["vertex"]
    );
    assert_eq!(p["max_utilisation"]["curve"], q["max_utilisation"]["curve"]);
    assert_eq!(p["units"], "m");
    // The state and the page carry them too; without the physical mode nothing is added.
    let (_, now) = request(&s.url, "GET", "/api/state", "");
    assert_eq!(now["physical"], state["physical"]);
    // The start line labels the paper's λ_eq and gives physical figures with their units.
    let started = std::fs::read_to_string(dir.join("stderr.txt")).unwrap();
    let line = started
        .lines()
        .find(|l| l.starts_with("serving"))
        .unwrap_or_else(|| panic!("{started}"));
    assert!(line.contains("λ_eq (the paper's model) = "), "{line}");
    assert!(
        line.contains("self-weight deflection ") && line.contains(" m;"),
        "{line}"
    );
    // The largest deviation is the physical model's: the physical analysis' own.
    let (status, c) = request(
        &s.url,
        "POST",
        "/api/constraints",
        r#"{"max_deviation":10}"#,
    );
    assert_eq!(status, 200, "{c}");
    let margin = c["current"]["margins"]["max_deviation"]["value"]
        .as_f64()
        .unwrap();
    let physical = now["physical"]["max_deviation"]["max"].as_f64().unwrap();
    assert_eq!(margin, physical, "{c}");
    assert!(
        c["notes"]
            .to_string()
            .contains("measured in the physical model"),
        "{c}"
    );
    drop(s);
    let mut plain = vec!["--curves", "grid.txt"];
    plain.extend_from_slice(QUIET);
    let s = serve_with(&dir, &plain, None);
    let (_, state) = request(&s.url, "GET", "/api/state", "");
    assert!(state.get("physical").is_none(), "{state}");
    drop(s);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_run_folder_is_loaded_from_the_page_and_bad_paths_are_refused() {
    let dir = folder("load");
    let run = simplified(&dir);
    std::fs::create_dir_all(dir.join("broken")).unwrap();
    std::fs::write(dir.join("broken/result.json"), "{\"version\": ").unwrap();
    std::fs::create_dir_all(dir.join("empty")).unwrap();
    let outside = folder("load-outside");
    let outside_run = simplified(&outside);
    #[cfg(unix)]
    std::os::unix::fs::symlink(&outside_run, dir.join("link")).unwrap();
    let result: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("result.json")).unwrap()).unwrap();
    // Served from its inputs, with curve 3 removed.
    let mut args = vec!["--curves", "grid.txt", "--remove", "3"];
    args.extend_from_slice(QUIET);
    let s = serve_with(&dir, &args, None);
    let (_, before) = request(&s.url, "GET", "/api/state", "");
    let cases: &[(&str, u16, &str)] = &[
        (r#"{"path":"nowhere"}"#, 422, "nowhere: no such folder"),
        (r#"{"path":"broken"}"#, 422, "result.json"),
        (r#"{"path":"empty"}"#, 422, "result.json"),
        (r#"{"path":"grid.txt"}"#, 422, "not a folder"),
        (r#"{"path":""}"#, 422, "give the folder of a run"),
        (r#"{"path":"/"}"#, 403, "outside the folder"),
        (r#"{"path":"../"}"#, 403, "outside the folder"),
        (r#"{"path":"run/../.."}"#, 403, "outside the folder"),
        (r#"{"path":"link"}"#, 403, "outside the folder"),
        (r#"{"path":5}"#, 400, "malformed JSON"),
        (r#"{"dir":"run"}"#, 400, "unknown field"),
        (r#"{"path":"run""#, 400, "malformed JSON"),
    ];
    for (body, status, says) in cases {
        let (got, answer) = request(&s.url, "POST", "/api/run", body);
        assert_eq!(got, *status, "{body}: {answer}");
        let message = answer["error"].as_str().unwrap_or_default();
        assert!(message.contains(says), "{body}: {message}");
    }
    let (_, after) = request(&s.url, "GET", "/api/state", "");
    assert_eq!(after, before, "a refused load changes nothing");

    // The run: its answer current, its iterations to step through, the page renamed.
    let (status, loaded) = request(&s.url, "POST", "/api/run", r#"{"path":"run"}"#);
    assert_eq!(status, 200, "{loaded}");
    assert_eq!(loaded["state"]["curves"], result["answer"]["curves"]);
    let (_, state) = request(&s.url, "GET", "/api/state", "");
    assert_eq!(state["curves"], result["answer"]["curves"]);
    let (_, listed) = request(&s.url, "GET", "/api/greedy/iterations", "");
    let recorded = result["iterations"].as_array().unwrap();
    assert_eq!(
        listed["iterations"].as_array().unwrap().len(),
        recorded.len()
    );
    assert_eq!(loaded["iterations"], recorded.len());
    let (status, step) = request(&s.url, "POST", "/api/greedy/step", r#"{"iteration":0}"#);
    assert_eq!(status, 200);
    assert_eq!(step["curves"], serde_json::json!([0, 1, 2, 3, 4, 5]));
    assert_close(&step, analyze(&dir, ""));
    drop(s);
    // --runs names the folder runs are loaded from.
    let runs = outside.display().to_string();
    let mut args = vec!["--curves", "grid.txt", "--runs", &runs];
    args.extend_from_slice(QUIET);
    let s = serve_with(&dir, &args, None);
    let body = format!("{{\"path\":\"{}\"}}", outside_run.display());
    let (status, loaded) = request(&s.url, "POST", "/api/run", &body);
    assert_eq!(status, 200, "{loaded}");
    let (status, refused) = request(&s.url, "POST", "/api/run", r#"{"path":"../"}"#);
    assert_eq!(status, 403, "{refused}");
    drop(s);
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&outside);
}

#[test]
fn serve_open_starts_the_browser_and_a_missing_one_is_a_warning() {
    let dir = folder("open");
    // A stand-in browser that records what it was asked to open.
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let opener = bin.join("xdg-open");
    std::fs::write(
        &opener,
        format!(
            "#!/bin/sh\n[ -n \"$1\" ] && echo \"$1\" > {}\nexit 0\n",
            dir.join("opened.txt").display()
        ),
    )
    .unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&opener, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    let mut args = vec!["--curves", "grid.txt", "--open"];
    args.extend_from_slice(QUIET);
    let path = format!("{}:/bin:/usr/bin", bin.display());
    let s = serve_with(&dir, &args, Some(&path));
    let start = std::time::Instant::now();
    while !dir.join("opened.txt").exists() && start.elapsed().as_secs() < 20 {
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    std::thread::sleep(std::time::Duration::from_millis(100));
    let opened = std::fs::read_to_string(dir.join("opened.txt")).unwrap_or_default();
    assert_eq!(opened.trim(), s.url);
    drop(s);
    // No browser at all: a warning, and the server serves.
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let s = serve_with(&dir, &args, Some(&empty.display().to_string()));
    let (status, _) = request(&s.url, "GET", "/api/state", "");
    assert_eq!(status, 200);
    let stderr = std::fs::read_to_string(dir.join("stderr.txt")).unwrap();
    assert!(
        stderr.contains("warning: could not open a browser"),
        "{stderr}"
    );
    assert!(stderr.contains(&s.url), "{stderr}");
    drop(s);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_host_that_is_not_loopback_is_warned_about_with_the_address_bound() {
    let dir = folder("host");
    let mut args = vec!["--curves", "grid.txt", "--host", "0.0.0.0"];
    args.extend_from_slice(QUIET);
    let s = serve_with(&dir, &args, None);
    let port = s.url.rsplit(':').next().unwrap().to_string();
    assert_ne!(port, "0");
    let stderr = std::fs::read_to_string(dir.join("stderr.txt")).unwrap();
    assert!(
        stderr.contains(&format!("listens on 0.0.0.0:{port},")),
        "{stderr}"
    );
    drop(s);
    let _ = std::fs::remove_dir_all(&dir);
}
