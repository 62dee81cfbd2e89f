//! Design constraints through the real `curvenet` binary: groups (a file and the JSON curves'
//! own), symmetry, connectivity, number of curves and the largest gap reach every search;
//! the largest deviation is measured on the answer, and a limit no network meets leaves no
//! answer, saying why; bad values and combinations nothing can satisfy exit 2 before any
//! work, naming why.

mod common;

use common::{BIN, TempDir};
use std::path::Path;
use std::process::Command;

/// `curvenet simplify --curves grid.txt --out out --budget 0.5 ARGS` in `dir`:
/// exit code, stdout + stderr.
fn simplify(dir: &Path, curves: &str, args: &[&str]) -> (i32, String) {
    let o = Command::new(BIN)
        .args([
            "simplify", "--curves", curves, "--out", "out", "--budget", "0.5",
        ])
        .args(args)
        .current_dir(dir)
        .output()
        .expect("runs");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    (o.status.code().unwrap_or(-1), text)
}

fn result(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("out/result.json")).expect("result.json");
    serde_json::from_str(&text).expect("JSON")
}

/// The curve lists of every iteration.
fn paths(r: &serde_json::Value) -> Vec<Vec<u64>> {
    r["iterations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|it| {
            it["curves"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c.as_u64().unwrap())
                .collect()
        })
        .collect()
}

#[test]
fn a_group_is_removed_whole() {
    let d = TempDir::with_grid("constraints-groups");
    std::fs::write(d.0.join("g.txt"), "pair: 0 1\n").unwrap();
    let (code, text) = simplify(&d.0, "grid.txt", &["--groups", "g.txt"]);
    assert_eq!(code, 0, "{text}");
    let r = result(&d.0);
    for p in paths(&r) {
        assert_eq!(p.contains(&0), p.contains(&1), "{p:?} splits the group");
    }
    let removed_group = r["iterations"]
        .as_array()
        .unwrap()
        .iter()
        .find(|it| it["removed_group"].is_array());
    if let Some(it) = removed_group {
        assert_eq!(it["removed_group"], serde_json::json!([0, 1]));
        assert_eq!(it["removed"], 0);
    }
    // The same groups from the JSON curve format's own "group" fields.
    let d = TempDir::with_grid("constraints-json");
    let curve = |pts: &str, group: Option<&str>| match group {
        Some(g) => format!("{{\"points\": {pts}, \"group\": \"{g}\"}}"),
        None => format!("{{\"points\": {pts}}}"),
    };
    let json = format!(
        "{{\"format\": \"curvenet-curves\", \"version\": 1, \"curves\": [{}, {}, {}, {}]}}",
        curve("[[-1,-0.5,0],[0,-0.5,0],[1,-0.5,0]]", Some("pair")),
        curve("[[-1,0.5,0],[0,0.5,0],[1,0.5,0]]", Some("pair")),
        curve("[[-0.5,-1,0],[-0.5,0,0],[-0.5,1,0]]", None),
        curve("[[0.5,-1,0],[0.5,0,0],[0.5,1,0]]", None),
    );
    std::fs::write(d.0.join("grid.json"), json).unwrap();
    let (code, text) = simplify(&d.0, "grid.json", &[]);
    assert_eq!(code, 0, "{text}");
    for p in paths(&result(&d.0)) {
        assert_eq!(
            p.contains(&0),
            p.contains(&1),
            "{p:?} splits the JSON group"
        );
    }
}

#[test]
fn a_run_keeps_the_constraints_and_its_answer_meets_them() {
    let d = TempDir::with_grid("constraints-connected");
    let (code, text) = simplify(
        &d.0,
        "grid.txt",
        &["--connected", "--min-curves", "2", "--local-search"],
    );
    assert_eq!(code, 0, "{text}");
    let r = result(&d.0);
    for p in paths(&r) {
        assert!(p.len() >= 2, "{p:?}: fewer than 2 curves");
        // Connected: a curve along x with one along y.
        let x = p.iter().any(|&c| c < 2);
        let y = p.iter().any(|&c| c >= 2);
        assert!(x && y, "{p:?} is not connected");
    }
    let answer = &r["answer"];
    assert!(answer.is_object(), "{}", r["answer"]);
    assert!(answer["curves"].as_array().unwrap().len() >= 2);
}

#[test]
fn the_constraints_are_recorded_and_a_resume_with_others_is_refused() {
    let d = TempDir::with_grid("constraints-resume");
    let (code, text) = simplify(&d.0, "grid.txt", &["--connected"]);
    assert_eq!(code, 0, "{text}");
    let r = result(&d.0);
    assert_eq!(
        r["setup"]["constraints"]["connected"], true,
        "{}",
        r["setup"]
    );
    let (code, text) = simplify(&d.0, "grid.txt", &["--min-curves", "2", "--resume"]);
    assert_eq!(code, 2, "{text}");
    // The refusal names the first difference.
    assert!(
        text.contains("cannot resume") && text.contains("--connected was true, now false"),
        "{text}"
    );
    // Without constraints nothing is recorded.
    let d = TempDir::with_grid("constraints-plain");
    let (code, text) = simplify(&d.0, "grid.txt", &[]);
    assert_eq!(code, 0, "{text}");
    assert!(result(&d.0)["setup"].get("constraints").is_none());
}

#[test]
fn impossible_constraints_exit_2_before_any_work_naming_why() {
    let d = TempDir::with_grid("constraints-bad");
    std::fs::write(d.0.join("g.txt"), "pair: 0 9\n").unwrap();
    std::fs::write(d.0.join("bad.txt"), "pair: 0 x\n").unwrap();
    for (args, want) in [
        (&["--min-curves", "3"][..], "--min-curves 3"),
        (&["--max-gap", "0.3"][..], "--max-gap"),
        (&["--symmetry", "rotate:3"][..], "rotation of order 3"),
        (&["--symmetry", "spin"][..], "unknown symmetry"),
        (&["--groups", "g.txt"][..], "g.txt:1"),
        (&["--groups", "bad.txt"][..], "bad.txt:1"),
        (&["--groups", "nosuch.txt"][..], "nosuch.txt"),
        (&["--min-curves", "0"][..], "--min-curves"),
        (&["--max-deviation", "-1"][..], "--max-deviation"),
    ] {
        let (code, text) = simplify(&d.0, "grid.txt", args);
        assert_eq!(code, 2, "{args:?}: {text}");
        assert!(text.contains(want), "{args:?}: {text}");
        assert!(
            !d.0.join("out/result.json").exists(),
            "{args:?}: no work done"
        );
    }
}

#[test]
fn the_tower_keeps_its_symmetry() {
    let dir = TempDir::with_grid("constraints-tower");
    let o = Command::new(BIN)
        .args(["example", "tower", "--symmetry", "rotate:8"])
        .arg("--out")
        .arg(dir.0.join("out"))
        .output()
        .expect("runs");
    let text = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{text}");
    assert!(text.contains("rotation of order 8"), "{text}");
    let r = result(&dir.0);
    // The orbits of the rotation by 45°: the ring alone, and eight of four curves. Each step
    // removes one whole orbit, recorded as a group when it has several curves.
    let its = r["iterations"].as_array().unwrap();
    let p = paths(&r);
    assert!(p.len() >= 3, "{p:?}");
    for (k, w) in p.windows(2).enumerate() {
        let gone: Vec<u64> = w[0].iter().copied().filter(|c| !w[1].contains(c)).collect();
        assert!(
            gone == [0] || gone.len() == 4,
            "iteration {k} removes {gone:?}"
        );
        if gone.len() == 4 {
            assert_eq!(its[k]["removed_group"], serde_json::json!(gone));
        }
    }
}

/// Three bent arches (reference text format), clamped at their ends: 0 and 1 in planes
/// `y = ∓0.5`, 2 across them (crossing both at height 1). Bent rods with straight rest shapes,
/// so every network sags from its designed shape at equilibrium.
fn arches() -> String {
    let mut s = String::new();
    for (i, y) in [-0.5f64, 0.5].into_iter().enumerate() {
        s.push_str(&format!("CURVE {i}\n"));
        for k in 0..=8 {
            let x = -1.0 + 0.25 * k as f64;
            s.push_str(&format!("{x} {y} {}\n", (1.0 - x * x).max(0.0).sqrt()));
        }
    }
    s.push_str("CURVE 2\n");
    let r = 1.25f64.sqrt();
    let ys = [-r, -1.0, -0.75, -0.5, -0.25, 0.0, 0.25, 0.5, 0.75, 1.0, r];
    for y in ys {
        s.push_str(&format!("0 {y} {}\n", (1.25 - y * y).max(0.0).sqrt()));
    }
    s
}

#[test]
fn max_deviation_is_measured_and_an_impossible_one_leaves_no_answer() {
    let d = TempDir::with_grid("constraints-deviation");
    std::fs::write(d.0.join("arches.txt"), arches()).unwrap();
    // A generous limit: the answer's margin is its measured deviation, within the limit.
    let (code, text) = simplify(
        &d.0,
        "arches.txt",
        &["--max-deviation", "1000", "--local-search"],
    );
    assert_eq!(code, 0, "{text}");
    let r = result(&d.0);
    let m = &r["answer"]["margins"]["max_deviation"];
    let value = m["value"]
        .as_f64()
        .unwrap_or_else(|| panic!("{}", r["answer"]));
    assert!(value > 1e-6 && value <= 1000.0, "{m}");
    assert_eq!(m["met"], true);
    // A limit below every network's deviation: no answer, and the reason says why.
    let deviation = format!("{:e}", value * 1e-6);
    let d = TempDir::with_grid("constraints-deviation-none");
    std::fs::write(d.0.join("arches.txt"), arches()).unwrap();
    let (code, text) = simplify(
        &d.0,
        "arches.txt",
        &["--max-deviation", &deviation, "--local-search"],
    );
    assert_eq!(code, 0, "{text}");
    let r = result(&d.0);
    assert!(r["answer"].is_null(), "{}", r["answer"]);
    let reason = r["no_answer"]["reason"].as_str().unwrap();
    assert!(reason.contains("--max-deviation"), "{reason}");
    assert!(text.contains("no answer"), "{text}");
}
