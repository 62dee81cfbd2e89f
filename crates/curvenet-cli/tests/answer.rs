//! The answer of a run (the network to build), through the real `curvenet` binary: a run whose
//! final network is a mechanism hands over nothing to build and names the smallest stable
//! network instead; a run with a stable final network exports it as the answer.

mod common;

use common::BIN;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A fresh output folder, removed afterwards.
struct Out(PathBuf);

impl Out {
    fn new(tag: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("curvenet-answer-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        Out(dir)
    }
}

impl Drop for Out {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs `curvenet example NAME --out DIR`: stdout, stderr, result.json.
fn example(name: &str, out: &Path) -> (String, String, serde_json::Value) {
    let o = Command::new(BIN)
        .args(["example", name, "--out"])
        .arg(out)
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{stdout}\n{stderr}");
    let text = std::fs::read_to_string(out.join("result.json")).expect("result.json");
    (stdout, stderr, serde_json::from_str(&text).expect("JSON"))
}

#[test]
fn a_mechanism_is_never_the_answer() {
    // arcshell's greedy ends on a mechanism (one zero mode: the closed ellipse swings freely);
    // every earlier iteration is stable but over the budget.
    let out = Out::new("arcshell");
    let (stdout, stderr, r) = example("arcshell", &out.0);
    let its = r["iterations"].as_array().unwrap();
    let last = its.last().unwrap();
    assert_eq!(last["zero_modes"], 1, "the greedy's path is as before");
    assert!(r["answer"].is_null(), "{}", r["answer"]);
    let no = &r["no_answer"];
    let reason = no["reason"].as_str().unwrap();
    assert!(reason.contains("mechanism"), "{reason}");
    assert!(
        reason.contains(&format!("iteration {}", its.len() - 1)),
        "{reason}"
    );
    // The smallest stable network: the iteration before the last, over the budget.
    let k = its.len() - 2;
    let s = &no["smallest_stable"];
    assert_eq!(s["iteration"], k);
    assert_eq!(s["curves"], its[k]["curves"]);
    let over = s["over_budget_percent"].as_f64().unwrap();
    let budget = r["budget"].as_f64().unwrap();
    let length = its[k]["length"].as_f64().unwrap();
    assert!((over - 100.0 * (length - budget) / budget).abs() < 1e-9 && over > 0.0);
    // The summary says so, and nothing is handed over to build.
    for text in [
        stdout.as_str(),
        &std::fs::read_to_string(out.0.join("summary.txt")).unwrap(),
    ] {
        assert!(text.contains("no answer: "), "{text}");
        assert!(
            text.contains(&format!(
                "smallest stable network of the run: iteration {k},"
            )),
            "{text}"
        );
    }
    assert!(!out.0.join("answer.obj").exists());
    assert!(!out.0.join("fabrication.csv").exists());
    assert!(
        stderr.contains("no fabrication table: nothing to build"),
        "{stderr}"
    );
    // The run's record of the greedy is still complete.
    assert!(out.0.join("final.obj").is_file());
    assert!(out.0.join("viewer.html").is_file());
}

#[test]
fn a_stable_final_network_is_the_answer() {
    let out = Out::new("roof");
    let (stdout, _, r) = example("roof", &out.0);
    let its = r["iterations"].as_array().unwrap();
    let k = its.len() - 1;
    let a = &r["answer"];
    assert_eq!(a["source"], "greedy");
    assert_eq!(a["iteration"], k);
    assert_eq!(a["curves"], its[k]["curves"]);
    assert_eq!(a["lambda"], its[k]["lambda"]);
    assert_eq!(a["zero_modes"], 0);
    assert_eq!(a["margins"]["budget"]["met"], true);
    assert!(r.get("no_answer").is_none());
    assert!(stdout.contains(&format!(
        "answer (the network to build): the greedy's iteration {k},"
    )));
    // Its files: the answer at equilibrium, and its fabrication table.
    let answer = std::fs::read_to_string(out.0.join("answer.obj")).unwrap();
    assert_eq!(
        answer,
        std::fs::read_to_string(out.0.join("final.obj")).unwrap()
    );
    let fab = std::fs::read_to_string(out.0.join("fabrication.csv")).unwrap();
    assert!(
        fab.starts_with(&format!(
            "# curvenet fabrication table: the answer (iteration {k})"
        )),
        "{fab}"
    );
    let rows = fab.lines().filter(|l| !l.starts_with('#')).count();
    assert_eq!(rows, 1 + its[k]["curves"].as_array().unwrap().len());
}
