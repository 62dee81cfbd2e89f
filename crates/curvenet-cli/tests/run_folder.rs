//! The run folder on the real binary: unstable recorded networks named wherever their numbers
//! appear, the folder's lock, a fresh run into an old folder, and `--resume` comparing inputs by
//! content.

mod common;

use common::{BIN, GRID, TempDir, dome_curves, dome_run};
use std::path::Path;
use std::process::{Command, Output};

/// A single free closed loop: nothing holds it, so it has zero modes (a mechanism).
const LOOP: &str = "CURVE loop\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 0\n";

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
    let tmp = TempDir::new("runf");
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
    let tmp = TempDir::new("runf");
    let o = run_in(&tmp.0, &["example", "arcshell", "--out", "out"]);
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
    let tmp = TempDir::new("runf");
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

/// `simplify` of the grid in `dir` into `out` with `budget`, then `extra`.
fn simplify_grid(dir: &Path, out: &str, budget: &str, extra: &[&str]) -> Output {
    let mut args = vec![
        "simplify",
        "--curves",
        "grid.txt",
        "--edge-length",
        "0.25",
        "--radius",
        "0.01",
        "--budget",
        budget,
        "--out",
        out,
    ];
    args.extend_from_slice(extra);
    run_in(dir, &args)
}

/// The names in a folder, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(Result::ok)
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn a_fresh_run_into_an_old_run_s_folder_starts_clean() {
    let tmp = TempDir::new("runf");
    tmp.write("grid.txt", GRID);
    let o = simplify_grid(&tmp.0, "out", "0.5", &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let long = names(&tmp.0.join("out/iterations"));
    // Stale files of an earlier run: more iterations than the new run makes, a temporary file.
    std::fs::write(tmp.0.join("out/iterations/0099.obj"), "stale").unwrap();
    std::fs::write(tmp.0.join("out/.result.json.tmp.1.0"), "stale").unwrap();
    let o = simplify_grid(&tmp.0, "out", "0.9", &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains("a fresh run"), "{}", stderr(&o));
    let short = names(&tmp.0.join("out/iterations"));
    assert!(short.len() < long.len(), "{short:?} vs {long:?}");
    for d in ["iterations", "modes"] {
        let n = names(&tmp.0.join("out").join(d)).len();
        assert_eq!(n, short.len(), "{d}: only the new run's iterations");
    }
    assert!(
        !names(&tmp.0.join("out"))
            .iter()
            .any(|n| n.contains(".tmp."))
    );
    let result: serde_json::Value =
        serde_json::from_str(&read(tmp.0.join("out/result.json"))).unwrap();
    assert_eq!(result["iterations"].as_array().unwrap().len(), short.len());
}

#[test]
fn a_non_empty_folder_that_is_no_run_s_is_refused_unless_forced() {
    let tmp = TempDir::new("runf");
    tmp.write("grid.txt", GRID);
    std::fs::create_dir_all(tmp.0.join("mine")).unwrap();
    tmp.write("mine/notes.txt", "my notes");
    let o = simplify_grid(&tmp.0, "mine", "0.9", &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--out mine: the folder is not empty and is not a curvenet run's")
            && stderr(&o).contains("notes.txt")
            && stderr(&o).contains("--force"),
        "{}",
        stderr(&o)
    );
    assert!(!tmp.0.join("mine/result.json").exists(), "no work done");
    let o = simplify_grid(&tmp.0, "mine", "0.9", &["--force"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(read(tmp.0.join("mine/notes.txt")), "my notes");
    assert!(tmp.0.join("mine/result.json").is_file());
}

#[test]
fn a_folder_another_run_holds_is_refused() {
    use std::process::Stdio;
    let tmp = TempDir::new("runf");
    // A run long enough to overlap: 24 geodesics on the built-in dome.
    dome_curves(&tmp.0, "dome.json");
    let owned = dome_run("dome.json", "out");
    let args: Vec<&str> = owned.iter().map(String::as_str).collect();
    let mut first = Command::new(BIN)
        .args(&args)
        .current_dir(&tmp.0)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("curvenet starts");
    let started = std::time::Instant::now();
    while !tmp.0.join("out/result.json").is_file() {
        assert!(started.elapsed().as_secs() < 60, "the first run writes");
        assert!(first.try_wait().unwrap().is_none(), "the first run ended");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let second = run_in(&tmp.0, &args);
    let still_running = first.try_wait().unwrap().is_none();
    first.kill().expect("SIGKILL");
    let _ = first.wait();
    assert!(
        still_running,
        "the first run ended before the second started"
    );
    assert_eq!(second.status.code(), Some(2), "{}", stderr(&second));
    assert!(
        stderr(&second).contains("--out out: another curvenet run is writing in this folder"),
        "{}",
        stderr(&second)
    );
    // The lock goes with the process, however it ended: the killed run resumes.
    let resumed = run_in(&tmp.0, &[&args[..], &["--resume"]].concat());
    assert_eq!(resumed.status.code(), Some(0), "{}", stderr(&resumed));
}

#[test]
fn resume_compares_inputs_by_content_and_names_the_first_difference() {
    let tmp = TempDir::new("runf");
    tmp.write("grid.txt", GRID);
    let o = simplify_grid(&tmp.0, "out", "0.5", &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let result = read(tmp.0.join("out/result.json"));
    // The same content by another path: accepted, the record unchanged.
    tmp.write("copy.txt", GRID);
    let o = run_in(
        &tmp.0,
        &[
            "simplify",
            "--curves",
            "./copy.txt",
            "--edge-length",
            "0.25",
            "--radius",
            "0.01",
            "--budget",
            "0.5",
            "--out",
            "out",
            "--resume",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains("already complete"), "{}", stderr(&o));
    assert_eq!(read(tmp.0.join("out/result.json")), result);
    // Another budget: refused, naming it.
    let o = simplify_grid(&tmp.0, "out", "0.4", &["--resume"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--budget was 0.5, now 0.4"),
        "{}",
        stderr(&o)
    );
    // Other content under the same name: refused, naming the first curve that differs.
    tmp.write("grid.txt", GRID.replace("\n0.5 1 0\n", "\n0.5 1.2 0\n"));
    let o = simplify_grid(&tmp.0, "out", "0.5", &["--resume"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains(
            "the curves files' content differs from the run's: curve 3 is not the one recorded"
        ),
        "{}",
        stderr(&o)
    );
    assert_eq!(read(tmp.0.join("out/result.json")), result);
    // Another objective, in a user's words.
    tmp.write("grid.txt", GRID);
    let o = simplify_grid(
        &tmp.0,
        "out",
        "0.5",
        &["--resume", "--objective", "frequency"],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--objective was lambda, now frequency"),
        "{}",
        stderr(&o)
    );
}

/// The square under the grid, as `--mesh`.
const SQUARE: &str = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n";

#[test]
fn resume_compares_the_physical_mode_and_the_mesh() {
    let tmp = TempDir::new("runf");
    tmp.write("grid.txt", GRID);
    tmp.write("square.obj", SQUARE);
    let mm = ["--units", "mm", "--mesh", "square.obj"];
    let o = simplify_grid(&tmp.0, "out", "0.5", &mm);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let result = read(tmp.0.join("out/result.json"));
    let refused = |extra: &[&str], says: &str| {
        let o = simplify_grid(&tmp.0, "out", "0.5", &[extra, &["--resume"]].concat());
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(says), "{extra:?}: {}", stderr(&o));
        assert!(
            !stderr(&o).contains("--radius was"),
            "{extra:?}: {}",
            stderr(&o)
        );
        assert_eq!(read(tmp.0.join("out/result.json")), result);
    };
    refused(
        &["--units", "m", "--mesh", "square.obj"],
        "--units was mm, now m",
    );
    // Without --units the same --radius 0.01 is the paper's: the mode is what differs.
    refused(&["--mesh", "square.obj"], "--units was mm, now not given");
    refused(
        &[
            "--units",
            "mm",
            "--mesh",
            "square.obj",
            "--density",
            "1000kg/m3",
        ],
        "--density was not given, now 1000kg/m3",
    );
    // The mesh by content: a moved vertex.
    tmp.write("moved.obj", SQUARE.replace("v 1 1 0", "v 1 1 0.5"));
    refused(
        &["--units", "mm", "--mesh", "moved.obj"],
        "--mesh's content differs from the run's: its vertex 2 moved",
    );
    // The same set-up resumes (the run is complete).
    let o = simplify_grid(&tmp.0, "out", "0.5", &[&mm[..], &["--resume"]].concat());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains("already complete"), "{}", stderr(&o));
}

#[test]
fn view_and_export_refuse_a_folder_a_run_is_writing_in() {
    let tmp = TempDir::new("runf");
    tmp.write("grid.txt", GRID);
    let o = simplify_grid(&tmp.0, "out", "0.5", &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // This process holds the lock as a run does.
    let lock = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(tmp.0.join("out/.curvenet.lock"))
        .unwrap();
    lock.lock().unwrap();
    for args in [
        &["view", "out", "--no-pictures"][..],
        &["export", "out", "--out", "exported"][..],
    ] {
        let o = run_in(&tmp.0, args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("out: a curvenet run is writing in this folder"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
    assert!(!tmp.0.join("exported").exists());
    lock.unlock().unwrap();
    for args in [
        &["view", "out", "--no-pictures"][..],
        &["export", "out", "--out", "exported"][..],
    ] {
        let o = run_in(&tmp.0, args);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", stderr(&o));
    }
}

/// A damaged run folder is bad input: `view` and `export` exit 2 naming the state file that is
/// missing or truncated.
#[test]
fn view_and_export_of_a_damaged_run_folder_exit_2_naming_the_file() {
    let tmp = TempDir::with_grid("damaged");
    let o = simplify_grid(&tmp.0, "out", "0.6", &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let states = tmp.0.join("out/states");
    let last = names(&states)
        .into_iter()
        .filter(|n| n.ends_with(".bin") && !n.contains("modes") && !n.contains("carried"))
        .max()
        .expect("a state file");
    let file = format!("states/{last}");
    let bytes = std::fs::read(states.join(&last)).unwrap();
    for damage in ["truncated", "missing"] {
        if damage == "truncated" {
            std::fs::write(states.join(&last), &bytes[..bytes.len() - 3]).unwrap();
        } else {
            std::fs::remove_file(states.join(&last)).unwrap();
        }
        for args in [
            &["view", "out", "--output", "v.html"][..],
            &["export", "out", "--out", "e"][..],
        ] {
            let o = run_in(&tmp.0, args);
            let err = stderr(&o);
            assert_eq!(o.status.code(), Some(2), "{damage} {args:?}: {err}");
            assert!(err.contains(&file), "{damage} {args:?}: {err}");
        }
    }
}

/// The viewer page a run writes (its gravity deflections solved while the greedy ran) is the
/// page `view` makes from the folder alone, byte for byte.
#[test]
fn the_runs_viewer_page_is_the_one_view_makes_from_the_folder() {
    let tmp = TempDir::new("viewer-ahead");
    dome_curves(&tmp.0, "dome.json");
    let args = dome_run("dome.json", "out");
    let o = run_in(&tmp.0, &args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let o = run_in(
        &tmp.0,
        &["view", "out", "--output", "again.html", "--no-pictures"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let page = std::fs::read_to_string(tmp.0.join("out/viewer.html")).unwrap();
    assert!(page.contains("\"max_displacement\""), "gravity embedded");
    assert!(page == std::fs::read_to_string(tmp.0.join("again.html")).unwrap());
}
