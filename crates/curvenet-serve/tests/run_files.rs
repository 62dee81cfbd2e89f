//! `POST /api/run` reads nothing outside the `--runs` folder: files of a run folder linked to
//! files outside are refused unread (a surface's is left out), a path outside gets one answer
//! whether or not anything is there, and no message quotes a file's content. The confined
//! reader of the library keeps the side files (states, modes) inside too.

mod common;

use common::{request, ring, ring_run, scratch, serve_runs};
use curvenet::run_folder::{Access, RunFolder, RunsRoot, Which};
use serde_json::Value;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};

/// A finished run of the ring, written once.
fn template() -> &'static Path {
    static RUN: OnceLock<PathBuf> = OnceLock::new();
    RUN.get_or_init(|| {
        let dir = scratch("run-files-template");
        ring_run(&dir);
        dir
    })
}

/// Copies the folder `from` into `to` (created), sub-folders too.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), &target).unwrap();
        }
    }
}

/// A `runs` folder (canonical) and a folder beside it, outside.
fn runs_and_outside(name: &str) -> (PathBuf, PathBuf) {
    let base = scratch(name).canonicalize().unwrap();
    let (runs, outside) = (base.join("runs"), base.join("outside"));
    std::fs::create_dir_all(&runs).unwrap();
    std::fs::create_dir_all(&outside).unwrap();
    (runs, outside)
}

/// `POST /api/run` of `path`: the status and the answer.
fn load(addr: SocketAddr, path: &str) -> (u16, Value, String) {
    let body = serde_json::json!({ "path": path }).to_string();
    let (status, text) = request(addr, "POST", "/api/run", body.as_bytes());
    let v = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path}: {e}: {text}"));
    (status, v, text)
}

/// What is quoted of the outside files if they are read.
const SECRETS: [&str; 3] = ["SECRET", "root:", "/bin/"];

fn assert_quotes_nothing(text: &str, what: &str) {
    for s in SECRETS {
        assert!(!text.contains(s), "{what}: the answer quotes {s:?}: {text}");
    }
}

#[cfg(unix)]
#[test]
fn files_linked_outside_the_runs_folder_are_refused_unread_whatever_is_there() {
    use std::os::unix::fs::symlink;
    let (runs, outside) = runs_and_outside("linked-files");
    let secret_json = outside.join("secret.json");
    std::fs::write(&secret_json, "\"SECRET-1 a password\"\n").unwrap();
    let secret_obj = outside.join("secret.obj");
    std::fs::write(&secret_obj, "v SECRET-2 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let nothing = outside.join("nothing-here");
    let (curves, build) = ring();
    let addr = serve_runs(&curves, &build, &runs);
    for (file, secret) in [
        ("result.json", &secret_json),
        ("network.json", &secret_json),
        ("mesh.obj", &secret_obj),
    ] {
        // The same link to an outside file, to /etc/passwd, to nothing at all.
        let targets = [
            secret.as_path(),
            Path::new("/etc/passwd"),
            nothing.as_path(),
        ];
        let mut answers = Vec::new();
        for (i, target) in targets.iter().enumerate() {
            let name = format!("{}-{i}", file.replace('.', "-"));
            let dir = runs.join(&name);
            copy_dir(template(), &dir);
            std::fs::remove_file(dir.join(file)).unwrap();
            symlink(target, dir.join(file)).unwrap();
            let (status, v, text) = load(addr, &name);
            let what = format!("{file} -> {}", target.display());
            assert_quotes_nothing(&text, &what);
            let said = if file == "mesh.obj" {
                assert_eq!(status, 200, "{what}: {text}");
                v["warnings"].to_string()
            } else {
                assert_eq!(status, 403, "{what}: {text}");
                v["error"].to_string()
            };
            assert!(
                said.contains(&format!("{name}/{file}")) && said.contains("outside"),
                "{what}: {said}"
            );
            answers.push((status, said.replace(&name, "DIR")));
        }
        assert!(
            answers.iter().all(|a| *a == answers[0]),
            "{file}: the answers depend on what is outside: {answers:?}"
        );
    }
}

#[cfg(unix)]
#[test]
fn outside_paths_get_the_same_answer_whether_or_not_they_exist() {
    use std::os::unix::fs::symlink;
    let (runs, outside) = runs_and_outside("outside-paths");
    copy_dir(template(), &outside.join("run"));
    std::fs::create_dir_all(outside.join(".ssh")).unwrap();
    symlink(outside.join(".ssh"), runs.join("to-ssh")).unwrap();
    symlink(outside.join(".ssh_zzz"), runs.join("to-ssh_zzz")).unwrap();
    symlink(outside.join("run"), runs.join("to-run")).unwrap();
    symlink("../outside/run_zzz", runs.join("to-run_zzz")).unwrap();
    std::fs::create_dir_all(runs.join("inside")).unwrap();
    let (curves, build) = ring();
    let addr = serve_runs(&curves, &build, &runs);
    let out = outside.display().to_string();
    // Each pair: a path to something outside, the same path to nothing.
    let pairs = [
        (format!("{out}/.ssh"), format!("{out}/.ssh_zzz")),
        (format!("{out}/run"), format!("{out}/run_zzz")),
        ("../outside/run".into(), "../outside/run_zzz".into()),
        (
            "inside/../../outside/.ssh".into(),
            "inside/../../outside/.ssh_zzz".into(),
        ),
        ("to-ssh".into(), "to-ssh_zzz".into()),
        ("to-run".into(), "to-run_zzz".into()),
        ("to-run/states".into(), "to-run_zzz/states".into()),
        ("to-ssh/../to-run".into(), "to-ssh_zzz/../to-run".into()),
    ];
    for (there, missing) in pairs {
        let (status, v, text) = load(addr, &there);
        assert_eq!(status, 403, "{there}: {text}");
        let message = v["error"].as_str().unwrap();
        assert!(message.contains("outside the folder"), "{there}: {message}");
        let (status_missing, w, text_missing) = load(addr, &missing);
        assert_eq!(
            (status_missing, w["error"].as_str().unwrap()),
            (status, message.replace(&there, &missing).as_str()),
            "{missing} answers differently from {there}: {text_missing}"
        );
    }
    // Inside, nothing there and no run folder there may differ.
    let (status, _, _) = load(addr, "nowhere");
    assert_eq!(status, 422);
    let (status, _, text) = load(addr, "inside");
    assert_eq!(status, 422, "{text}");
}

#[test]
fn malformed_files_are_named_and_never_quoted() {
    let (runs, _) = runs_and_outside("malformed");
    let result = std::fs::read_to_string(template().join("result.json")).unwrap();
    assert!(
        result.contains("\"version\": 1"),
        "the record's version line"
    );
    let cases = [
        (
            "result.json",
            result.replacen("\"version\": 1", "\"version\": \"SECRET-3\"", 1),
            "not a curvenet run record (line",
        ),
        (
            "network.json",
            "{\"positions\": \"SECRET-4\"}".to_string(),
            "not a curvenet network (line",
        ),
        (
            "network.json",
            "SECRET-5".to_string(),
            "not valid JSON (line 1",
        ),
        (
            "result.json",
            "{\"version\": \"SECRET-6".to_string(),
            "it ends early",
        ),
    ];
    let (curves, build) = ring();
    let addr = serve_runs(&curves, &build, &runs);
    for (i, (file, text, says)) in cases.iter().enumerate() {
        let name = format!("bad-{i}");
        let dir = runs.join(&name);
        copy_dir(template(), &dir);
        std::fs::write(dir.join(file), text).unwrap();
        let (status, v, answer) = load(addr, &name);
        assert_eq!(status, 422, "{file}: {answer}");
        assert_quotes_nothing(&answer, file);
        let message = v["error"].as_str().unwrap();
        assert!(
            message.starts_with(&format!("{name}/{file}: ")) && message.contains(says),
            "{file}: {message}"
        );
    }
    // A surface that does not parse is left out, its line named.
    let dir = runs.join("bad-mesh");
    copy_dir(template(), &dir);
    std::fs::write(dir.join("mesh.obj"), "v 0 0 0\nv SECRET-7 0 0\nf 1 2 3\n").unwrap();
    let (status, v, answer) = load(addr, "bad-mesh");
    assert_eq!(status, 200, "{answer}");
    assert_quotes_nothing(&answer, "mesh.obj");
    assert_eq!(
        v["warnings"],
        serde_json::json!([
            "bad-mesh/mesh.obj: not a surface mesh (line 2); the surface is left out"
        ])
    );
}

/// The paths a root's reader looks at and opens, as its observer records them.
type Seen = Arc<Mutex<Vec<(PathBuf, Access)>>>;

/// `root` observed: what its reader looks at and opens is recorded.
fn observed(root: &Path) -> (RunsRoot, Seen) {
    let seen: Seen = Arc::default();
    let record = Arc::clone(&seen);
    let root = RunsRoot::new(root)
        .unwrap()
        .observed(move |p, a| record.lock().unwrap().push((p.to_path_buf(), a)));
    (root, seen)
}

/// Asserts that everything in `seen` is inside `root` (opened files in fact, after every
/// link; entries looked at in a folder inside), and empties it.
fn assert_all_inside(seen: &Seen, root: &Path, what: &str) {
    for (p, access) in seen.lock().unwrap().drain(..) {
        assert!(p.starts_with(root), "{what}: {access:?} {}", p.display());
        let real = match access {
            Access::Open => p.canonicalize(),
            Access::Look => p.parent().unwrap().canonicalize(),
        };
        let real = real.unwrap_or_else(|e| panic!("{what}: {}: {e}", p.display()));
        assert!(real.starts_with(root), "{what}: {access:?} {}", p.display());
    }
}

#[cfg(unix)]
#[test]
fn side_files_of_a_confined_run_folder_are_read_inside_only() {
    use std::os::unix::fs::symlink;
    let (runs, outside) = runs_and_outside("side-files");
    let dir = runs.join("run");
    copy_dir(template(), &dir);
    copy_dir(template(), &outside.join("run"));
    let (root, seen) = observed(&runs);
    let run = RunFolder::read(root.folder(Path::new("run")).unwrap()).unwrap();
    assert!(run.files.is_confined());
    let last = run.last_index();
    let mode_file = run.result.iterations[last].mode_file.clone();
    // Inside: read, each file opened where it lies.
    let u = run.displacement(last).unwrap();
    assert_eq!(u.len(), run.network.dofs());
    run.mode(last).unwrap();
    run.displacement_of(Which::Iteration(0)).unwrap();
    assert!(
        seen.lock()
            .unwrap()
            .iter()
            .any(|(p, a)| *a == Access::Open && p.ends_with(format!("states/{last:04}.bin"))),
        "the states file is read through the reader"
    );
    assert_all_inside(&seen, &runs, "inside");
    // A states file, a mode file and the states folder linked outside: refused, unread.
    let state = dir.join(format!("states/{last:04}.bin"));
    std::fs::remove_file(&state).unwrap();
    symlink(outside.join(format!("run/states/{last:04}.bin")), &state).unwrap();
    let e = run.displacement(last).unwrap_err().to_string();
    assert!(
        e.contains("outside") && e.contains(&format!("run/states/{last:04}.bin")),
        "{e}"
    );
    assert_all_inside(&seen, &runs, "a states file linked outside");
    std::fs::remove_file(dir.join(&mode_file)).unwrap();
    symlink("/etc/passwd", dir.join(&mode_file)).unwrap();
    let e = run.mode(last).unwrap_err().to_string();
    assert!(e.contains("outside"), "{e}");
    assert_all_inside(&seen, &runs, "a mode file linked outside");
    std::fs::remove_dir_all(dir.join("states")).unwrap();
    symlink("../../outside/run/states", dir.join("states")).unwrap();
    let e = run.displacement(0).unwrap_err().to_string();
    assert!(e.contains("outside"), "{e}");
    assert_all_inside(&seen, &runs, "the states folder linked outside");
    // A record naming a mode file outside the folder runs are loaded from.
    let mut rogue = run.clone();
    rogue.result.iterations[last].mode_file = "../../outside/run/states/0000.bin".into();
    let e = rogue.mode(last).unwrap_err().to_string();
    assert!(e.contains("outside"), "{e}");
    rogue.result.iterations[last].mode_file =
        outside.join("run/states/0000.bin").display().to_string();
    let e = rogue.mode(last).unwrap_err().to_string();
    assert!(e.contains("outside"), "{e}");
    assert_all_inside(&seen, &runs, "a rogue record");
}
