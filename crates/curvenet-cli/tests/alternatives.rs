//! `--alternatives K` through the real `curvenet` binary: the alternatives are distinct,
//! feasible, stable, sorted by λ_eq and no better than the answer; asking for more than there
//! are gives fewer without error; each is exported (OBJ, fabrication table) and `export` reads
//! it back; the same on one thread and on several; bad values exit 2 naming the option.

mod common;

use common::{BIN, TempDir};
use std::path::Path;
use std::process::Command;

/// Runs the binary in `dir` with `args` (and `RAYON_NUM_THREADS` when given): exit code,
/// stdout, stderr.
fn run(dir: &Path, args: &[&str], threads: Option<usize>) -> (i32, String, String) {
    let mut cmd = Command::new(BIN);
    cmd.args(args).current_dir(dir);
    if let Some(t) = threads {
        cmd.env("RAYON_NUM_THREADS", t.to_string());
    }
    let o = cmd.output().expect("runs");
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// `simplify` of the grid into `dir/OUT` at half its length with `--alternatives K`.
fn simplify(dir: &Path, out: &str, k: &str, threads: Option<usize>) -> (i32, String, String) {
    run(
        dir,
        &[
            "simplify",
            "--curves",
            "grid.txt",
            "--budget",
            "0.5",
            "--out",
            out,
            "--alternatives",
            k,
        ],
        threads,
    )
}

fn result(dir: &Path, out: &str) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join(out).join("result.json")).expect("result.json");
    serde_json::from_str(&text).expect("JSON")
}

fn curves(v: &serde_json::Value) -> Vec<u64> {
    v["curves"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_u64().unwrap())
        .collect()
}

#[test]
fn alternatives_are_distinct_feasible_stable_and_sorted() {
    let d = TempDir::with_grid("alt-many");
    // More than there are: fewer, no error, a note saying so.
    let (code, stdout, stderr) = simplify(&d.0, "out", "100", None);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stderr.contains("100 alternative(s) asked for"), "{stderr}");
    let r = result(&d.0, "out");
    let answer = &r["answer"];
    let alts = r["alternatives"].as_array().expect("alternatives");
    assert!((3..100).contains(&alts.len()), "{}", alts.len());
    let budget = r["budget"].as_f64().unwrap();
    let lambda = |v: &serde_json::Value| v["lambda"].as_f64().unwrap();
    let mut seen = vec![curves(answer)];
    for (i, a) in alts.iter().enumerate() {
        assert_eq!(a["zero_modes"], 0, "{a}");
        assert_eq!(a["negative_modes"], 0, "{a}");
        assert!(lambda(a) > 0.0);
        assert!(lambda(a) <= lambda(answer) * (1.0 + 1e-7), "{a}");
        if i > 0 {
            assert!(lambda(a) <= lambda(&alts[i - 1]) * (1.0 + 1e-7), "sorted");
        }
        assert!(a["length"].as_f64().unwrap() <= budget);
        assert_eq!(a["margins"]["budget"]["met"], true);
        let c = curves(a);
        assert!(!seen.contains(&c), "distinct: {c:?} twice");
        // Every curve of the grid is 2 long: two sets are distinct designs.
        seen.push(c);
        // Its files: at equilibrium, and its fabrication table.
        let n = i + 1;
        let obj = std::fs::read_to_string(d.0.join(format!("out/alternative-{n}.obj"))).unwrap();
        assert_eq!(
            obj.matches("\nl ").count() + usize::from(obj.starts_with("l ")),
            seen.last().unwrap().len()
        );
        let csv = std::fs::read_to_string(d.0.join(format!("out/alternative-{n}.csv"))).unwrap();
        assert!(
            csv.starts_with(&format!("# curvenet fabrication table: alternative {n} ")),
            "{csv}"
        );
        assert!(stdout.contains(&format!("alternative {n} (alternative-{n}.obj): ")));
    }
    let summary = std::fs::read_to_string(d.0.join("out/summary.txt")).unwrap();
    assert!(
        summary.contains("alternative 1 (alternative-1.obj)"),
        "{summary}"
    );
    let viewer = std::fs::read_to_string(d.0.join("out/viewer.html")).unwrap();
    assert!(viewer.contains("\"label\":\"alternative 1\""));

    // Fewer asked for: the best of them, in the same order; the files of the others go.
    let (code, _, stderr) = simplify(&d.0, "out", "2", None);
    assert_eq!(code, 0, "{stderr}");
    let two = result(&d.0, "out");
    let two = two["alternatives"].as_array().unwrap();
    assert_eq!(two.len(), 2);
    assert_eq!(two[..], alts[..2]);
    assert!(!d.0.join("out/alternative-3.obj").exists());
    assert!(!d.0.join("out/alternative-3.csv").exists());
}

#[test]
fn alternatives_are_exported_and_the_same_on_any_number_of_threads() {
    let d = TempDir::with_grid("alt-export");
    let (code, _, stderr) = simplify(&d.0, "one", "3", Some(1));
    assert_eq!(code, 0, "{stderr}");
    let (code, _, stderr) = simplify(&d.0, "two", "3", Some(2));
    assert_eq!(code, 0, "{stderr}");
    let one = std::fs::read(d.0.join("one/result.json")).unwrap();
    assert_eq!(one, std::fs::read(d.0.join("two/result.json")).unwrap());
    let r = result(&d.0, "one");
    assert_eq!(r["alternatives"].as_array().unwrap().len(), 3);

    let (code, _, stderr) = run(
        &d.0,
        &["export", "one", "--alternative", "2", "--out", "x"],
        None,
    );
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.starts_with("alternative 2 ("), "{stderr}");
    let obj = std::fs::read_to_string(d.0.join("x/curves_alternative-2.obj")).unwrap();
    assert!(
        obj.starts_with("# curvenet export: alternative 2 ("),
        "{obj}"
    );
    for f in ["fabrication", "points"] {
        assert!(d.0.join(format!("x/{f}_alternative-2.csv")).is_file());
    }
    let net = std::fs::read_to_string(d.0.join("x/network_alternative-2.json")).unwrap();
    let net: serde_json::Value = serde_json::from_str(&net).unwrap();
    assert_eq!(net["lambda"], r["alternatives"][1]["lambda"]);
    let (code, _, stderr) = run(&d.0, &["export", "one", "--answer", "--out", "y"], None);
    assert_eq!(code, 0, "{stderr}");
    assert!(d.0.join("y/curves_answer.obj").is_file());

    // An alternative the run does not have: exit 2, saying which it has.
    let (code, _, stderr) = run(&d.0, &["export", "one", "--alternative", "4"], None);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("alternatives 1 to 3"), "{stderr}");
}

#[test]
fn bad_alternative_counts_exit_2_naming_the_option() {
    let d = TempDir::with_grid("alt-bad");
    for bad in ["-1", "abc", "1.5", "101", ""] {
        let (code, _, stderr) = simplify(&d.0, "out", bad, None);
        assert_eq!(code, 2, "--alternatives {bad:?}: {stderr}");
        assert!(stderr.contains("--alternatives"), "{stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    for bad in ["0", "x"] {
        let (code, _, stderr) = run(&d.0, &["export", "out", "--alternative", bad], None);
        assert_eq!(code, 2, "--alternative {bad}: {stderr}");
        assert!(stderr.contains("--alternative"), "{stderr}");
    }
}
