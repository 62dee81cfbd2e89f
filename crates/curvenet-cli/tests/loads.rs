//! Load cases on the command line (`analyze --loads FILE`): the cases' figures in the text and
//! in `--json`, and bad loads files refused with exit 2 naming the file, the line and what is
//! wrong.

mod common;

use common::{BIN, TempDir};
use std::process::{Command, Output};

/// The reference format's grid of `common::GRID`, in metres: steel bars of radius 10 mm.
const OPTIONS: &[&str] = &[
    "--units",
    "m",
    "--material",
    "steel",
    "--radius",
    "0.01",
    "--edge-length",
    "0.1",
];

fn analyze(dir: &TempDir, extra: &[&str]) -> Output {
    let mut args = vec!["analyze", "--curves", "grid.txt"];
    args.extend_from_slice(OPTIONS);
    args.extend_from_slice(extra);
    Command::new(BIN)
        .args(&args)
        .current_dir(&dir.0)
        .output()
        .expect("runs")
}

#[test]
fn load_cases_are_reported_with_their_verdicts() {
    let dir = TempDir::with_grid("loads");
    dir.write(
        "loads.json",
        r#"{"cases": [{"name": "G", "self_weight": true},
                      {"name": "P", "points": [{"at": [0.5, 0.5, 0], "force": [0, 0, -100]}]}],
            "combinations": [{"name": "ULS", "factors": {"G": 1.35, "P": 1.5}}]}"#,
    );
    let out = analyze(
        &dir,
        &["--loads", "loads.json", "--deflection-limit", "span/250"],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    for part in [
        "load case G: max deflection",
        "load case P: max deflection",
        "combination ULS (1.35·G + 1.50·P)",
    ] {
        assert!(text.contains(part), "{part}: {text}");
    }
    let out = analyze(&dir, &["--loads", "loads.json", "--json"]);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let cases = report["physical"]["load_cases"].as_array().expect("cases");
    assert_eq!(cases.len(), 3);
    for key in [
        "name",
        "max_deflection",
        "max_utilisation",
        "buckling_factor",
        "passes",
    ] {
        assert!(cases[2].get(key).is_some(), "{key}: {}", cases[2]);
    }
}

#[test]
fn a_pressure_case_reaches_the_report() {
    let dir = TempDir::with_grid("loads-pressure");
    dir.write(
        "loads.json",
        r#"{"cases": [{"name": "G", "self_weight": true},
                      {"name": "W", "pressure": {"intensity": "0.1kN/m", "axis": [0, 0, 1],
                                                 "toward": "outside"}}],
            "combinations": [{"name": "C", "factors": {"G": 1, "W": 1.5}}]}"#,
    );
    let out = analyze(&dir, &["--loads", "loads.json", "--json"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let cases = report["physical"]["load_cases"].as_array().expect("cases");
    let names: Vec<&str> = cases.iter().filter_map(|c| c["name"].as_str()).collect();
    assert_eq!(names, ["G", "W", "C"]);
    for c in &cases[1..] {
        assert_eq!(c["holds"], true, "{c}");
        assert!(c["max_deflection"].as_f64().is_some_and(|d| d > 0.0), "{c}");
    }
}

#[test]
fn bad_loads_are_refused_naming_file_line_and_what() {
    let dir = TempDir::with_grid("loads-bad");
    for (text, parts) in [
        (
            "{\"cases\": [{\"name\": \"G\", \"self_weight\": true}],\n \"combinations\": [{\"name\": \"C\", \"factors\": {\"S\": 1.5}}]}",
            &["bad.json:2", "names load case S", "its cases: G"][..],
        ),
        (
            "{\"cases\": [\n {\"name\": \"P\", \"points\": [{\"at\": [0, 0, 5], \"force\": [0, 0, -1]}]}]}",
            &[
                "load case P",
                "m from the structure",
                "must lie on the network",
            ][..],
        ),
        (
            "{\"cases\": [\n {\"name\": \"S\", \"line\": {\"intensity\": \"2\", \"direction\": [0, 0, -1]}}]}",
            &["bad.json:2", "needs a unit"][..],
        ),
        (
            "{\"cases\": [\n {\"nme\": \"S\"}]}",
            &["bad.json:2", "unknown field"][..],
        ),
    ] {
        dir.write("bad.json", text);
        let out = analyze(&dir, &["--loads", "bad.json"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{text}: {err}");
        for part in parts {
            assert!(err.contains(part), "{part}: {err}");
        }
        assert!(!err.contains("panicked"), "{err}");
    }
    let out = analyze(&dir, &["--loads", "missing.json"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--loads") && err.contains("missing.json"),
        "{err}"
    );
    let out = analyze(&dir, &["--deflection-limit", "span/-3"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--deflection-limit"));
}

#[test]
fn a_run_records_the_load_cases_of_the_networks_it_offers() {
    let dir = TempDir::with_grid("loads-run");
    dir.write(
        "loads.json",
        r#"{"cases": [{"name": "G", "self_weight": true},
                      {"name": "P", "points": [{"at": [0.5, 0.5, 0], "force": [0, 0, -100]}]}]}"#,
    );
    let mut args = vec!["simplify", "--curves", "grid.txt"];
    args.extend_from_slice(OPTIONS);
    args.extend_from_slice(&[
        "--loads",
        "loads.json",
        "--budget",
        "0.7",
        "--alternatives",
        "1",
        "--local-search",
        "--out",
        "run",
    ]);
    let out = Command::new(BIN)
        .args(&args)
        .current_dir(&dir.0)
        .output()
        .expect("runs");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let result: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.0.join("run/result.json")).unwrap()).unwrap();
    // The answer and every alternative carry each case's figures; the iterations do not.
    let mut offered = vec![&result["answer"]];
    offered.extend(result["alternatives"].as_array().into_iter().flatten());
    for a in offered {
        let cases = a["physical"]["load_cases"].as_array().expect("load cases");
        let names: Vec<&str> = cases.iter().map(|c| c["name"].as_str().unwrap()).collect();
        assert_eq!(names, ["G", "P"], "{a}");
        assert!(
            cases
                .iter()
                .all(|c| c["max_deflection"].as_f64().unwrap() > 0.0)
        );
    }
    assert!(
        result["iterations"][0]["physical"]
            .get("load_cases")
            .is_none()
    );
    assert_eq!(
        result["setup"]["physical_model"]["loads"]["cases"][1]["name"],
        "P"
    );
    let summary = std::fs::read_to_string(dir.0.join("run/summary.txt")).unwrap();
    assert!(summary.contains("load case P: max deflection"), "{summary}");
}
