//! The run folder on the real binary: unstable recorded networks named wherever their numbers
//! appear, the folder's lock, a fresh run into an old folder, and `--resume` comparing inputs by
//! content.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The binary under test.
const BIN: &str = env!("CARGO_BIN_EXE_curvenet");

/// A flat 2 × 2 grid of straight curves crossing at four points (reference text format).
const GRID: &str = "CURVE 0\n-1 -0.5 0\n0 -0.5 0\n1 -0.5 0\n\
                    CURVE 1\n-1 0.5 0\n0 0.5 0\n1 0.5 0\n\
                    CURVE 2\n-0.5 -1 0\n-0.5 0 0\n-0.5 1 0\n\
                    CURVE 3\n0.5 -1 0\n0.5 0 0\n0.5 1 0\n";

/// A single free closed loop: nothing holds it, so it has zero modes (a mechanism).
const LOOP: &str = "CURVE loop\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 0\n";

/// A fresh temporary folder, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new() -> Self {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("curvenet-runf-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temporary folder");
        TempDir(dir)
    }

    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, text).expect("input written");
        p
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs the binary in `dir` with `args`.
fn run_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("curvenet runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn read(p: impl AsRef<Path>) -> String {
    let p = p.as_ref();
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn a_free_loop_simplified_is_named_unstable_wherever_its_numbers_appear() {
    let tmp = TempDir::new();
    tmp.write("loop.txt", LOOP);
    let o = run_in(
        &tmp.0,
        &[
            "simplify",
            "--curves",
            "loop.txt",
            "--edge-length",
            "0.1",
            "--radius",
            "0.01",
            "--budget",
            "0.5",
            "--out",
            "out",
        ],
    );
    let (err, out) = (stderr(&o), stdout(&o));
    assert_eq!(o.status.code(), Some(0), "{err}");
    // stderr: a warning naming the final network unstable.
    assert!(
        err.contains("warning: the final network (iteration 0, 1 curves")
            && err.contains("unstable: ")
            && err.contains("zero mode"),
        "{err}"
    );
    // stdout and summary.txt: the numbers come with the word.
    let summary = read(tmp.0.join("out/summary.txt"));
    for text in [&out, &summary] {
        let final_line = text
            .lines()
            .find(|l| l.starts_with("final: "))
            .unwrap_or_else(|| panic!("no final line: {text}"));
        assert!(final_line.contains("(unstable: "), "{final_line}");
        assert!(text.contains("warning: the final network"), "{text}");
    }
    // The run's OBJ files, the viewer's data and every export's header.
    assert!(read(tmp.0.join("out/final.obj")).starts_with("# WARNING: this network is unstable"));
    assert!(read(tmp.0.join("out/iterations/0000.obj")).starts_with("# WARNING"));
    let viewer = read(tmp.0.join("out/viewer.html"));
    assert!(viewer.contains("\"unstable\":\"unstable: "), "viewer data");
    assert!(
        !tmp.0.join("out/fabrication.csv").exists(),
        "nothing to build"
    );
    let o = run_in(
        &tmp.0,
        &["export", "out", "--format", "all", "--out", "exported"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("iteration 0 is unstable: "),
        "{}",
        stderr(&o)
    );
    for f in [
        "curves_0000.obj",
        "curves_0000_rest.obj",
        "fabrication_0000.csv",
        "points_0000.csv",
        "network_0000.json",
    ] {
        let text = read(tmp.0.join("exported").join(f));
        let head: String = text.lines().take(5).collect::<Vec<_>>().join("\n");
        assert!(
            head.contains("WARNING: this network is unstable: "),
            "{f}: {head}"
        );
    }
}

#[test]
fn arcshell_s_final_mechanism_is_named_unstable() {
    // The greedy's final 8-curve network has λ_eq ≈ -2e-15 and one zero mode.
    let tmp = TempDir::new();
    let o = run_in(
        &tmp.0,
        &["example", "arcshell", "--no-certificate", "--out", "out"],
    );
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(
        err.contains("warning: the final network (iteration 59, 8 curves")
            && err.contains("unstable: 1 zero mode, a mechanism"),
        "{err}"
    );
    let summary = read(tmp.0.join("out/summary.txt"));
    assert!(
        summary.contains("final: 8 curves") && summary.contains("(unstable: 1 zero mode"),
        "{summary}"
    );
    assert!(read(tmp.0.join("out/final.obj")).starts_with("# WARNING"));
}

#[test]
fn a_stable_grid_says_nothing_of_instability() {
    let tmp = TempDir::new();
    tmp.write("grid.txt", GRID);
    let o = run_in(
        &tmp.0,
        &[
            "simplify",
            "--curves",
            "grid.txt",
            "--edge-length",
            "0.25",
            "--radius",
            "0.01",
            "--budget",
            "0.9",
            "--out",
            "out",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!stderr(&o).contains("unstable"), "{}", stderr(&o));
    assert!(!read(tmp.0.join("out/summary.txt")).contains("unstable"));
    assert!(!read(tmp.0.join("out/final.obj")).contains("WARNING"));
}
