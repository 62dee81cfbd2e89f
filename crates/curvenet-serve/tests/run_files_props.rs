//! A property of `POST /api/run`: whatever folder tree it is pointed at — symbolic links in
//! and out of the `--runs` folder at every level (intermediate folders, the run folder, its
//! `states` folder, each file), to files and to folders, relative and absolute, chained — the
//! server looks at and opens nothing outside `--runs` (the root's observer records every path),
//! answers as the tree inside says (a link leading out is refused, 403, a surface's left out),
//! and answers the same once everything outside is gone.
#![cfg(unix)]

mod common;

use common::{request, ring, ring_run, scratch, serve_runs_in};
use curvenet::run_folder::{Access, RunsRoot};
use proptest::prelude::*;
use serde_json::Value;
use std::net::SocketAddr;
use std::os::unix::fs::symlink;
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

/// A folder of the tree.
#[derive(Clone, Copy, Debug)]
enum Dir {
    /// A folder.
    Real,
    /// A link to a folder inside the runs folder.
    In { absolute: bool },
    /// A link to a folder outside (holding what a real one would).
    Out { absolute: bool },
}

/// A file of the run folder.
#[derive(Clone, Copy, Debug)]
enum File {
    Real,
    Missing,
    /// A link to a copy inside.
    In {
        absolute: bool,
    },
    /// A link to a copy outside.
    Out {
        absolute: bool,
    },
    /// A link to nothing outside.
    OutMissing {
        absolute: bool,
    },
    /// A link to a link inside to a copy outside.
    InThenOut,
    /// A link to a folder inside.
    ToFolder,
}

/// A generated tree: the folders on the way to the run folder, the run folder, its files
/// (`result.json`, `network.json`, `mesh.obj`), its `states` folder and a states file.
#[derive(Clone, Debug)]
struct Tree {
    levels: Vec<Dir>,
    run: Dir,
    files: [File; 3],
    states: Dir,
    state: File,
    absolute_request: bool,
}

const FILES: [&str; 3] = ["result.json", "network.json", "mesh.obj"];

fn dir() -> impl Strategy<Value = Dir> {
    prop_oneof![
        4 => Just(Dir::Real),
        2 => any::<bool>().prop_map(|absolute| Dir::In { absolute }),
        1 => any::<bool>().prop_map(|absolute| Dir::Out { absolute }),
    ]
}

fn file() -> impl Strategy<Value = File> {
    prop_oneof![
        8 => Just(File::Real),
        1 => Just(File::Missing),
        4 => any::<bool>().prop_map(|absolute| File::In { absolute }),
        1 => any::<bool>().prop_map(|absolute| File::Out { absolute }),
        1 => any::<bool>().prop_map(|absolute| File::OutMissing { absolute }),
        1 => Just(File::InThenOut),
        1 => Just(File::ToFolder),
    ]
}

fn tree() -> impl Strategy<Value = Tree> {
    (
        prop::collection::vec(dir(), 0..3),
        dir(),
        [file(), file(), file()],
        dir(),
        file(),
        any::<bool>(),
    )
        .prop_map(
            |(levels, run, files, states, state, absolute_request)| Tree {
                levels,
                run,
                files,
                states,
                state,
                absolute_request,
            },
        )
}

/// The server's answer as the tree inside says: the status, and for a load what its
/// warnings say of the surface.
fn expected(t: &Tree) -> (u16, Option<&'static str>) {
    if t.levels
        .iter()
        .chain([&t.run])
        .any(|d| matches!(d, Dir::Out { .. }))
    {
        return (403, None);
    }
    for f in &t.files[..2] {
        match f {
            File::Real | File::In { .. } => {}
            File::Missing | File::ToFolder => return (422, None),
            File::Out { .. } | File::OutMissing { .. } | File::InThenOut => return (403, None),
        }
    }
    let mesh = match t.files[2] {
        File::Real | File::In { .. } | File::Missing => None,
        File::ToFolder => Some("mesh.obj: not a regular file"),
        _ => Some("mesh.obj: outside the folder runs are loaded from"),
    };
    (200, mesh)
}

/// A finished run of the ring, written once.
fn template() -> &'static Path {
    static RUN: OnceLock<PathBuf> = OnceLock::new();
    RUN.get_or_init(|| {
        let dir = scratch("props-template");
        ring_run(&dir);
        dir
    })
}

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

/// `to` relative to the folder `from` (both absolute).
fn relative(from: &Path, to: &Path) -> PathBuf {
    let (f, t): (Vec<Component<'_>>, Vec<Component<'_>>) =
        (from.components().collect(), to.components().collect());
    let common = f.iter().zip(&t).take_while(|(a, b)| a == b).count();
    let mut p = PathBuf::new();
    for _ in common..f.len() {
        p.push("..");
    }
    for c in &t[common..] {
        p.push(c);
    }
    p
}

/// Where one case's tree is built.
struct Case {
    /// Inside: the case's folder under the runs folder, and its stash of link targets.
    stash: PathBuf,
    /// Outside: the case's folder.
    outside: PathBuf,
    /// Names made so far (each link target unique).
    made: usize,
}

impl Case {
    fn unique(&mut self, what: &str) -> String {
        self.made += 1;
        format!("{what}-{}", self.made)
    }

    /// A link at `at` to `target`, written absolute or relative to the link's folder.
    fn link(at: &Path, target: &Path, absolute: bool) {
        let written = if absolute {
            target.to_path_buf()
        } else {
            relative(at.parent().unwrap(), target)
        };
        symlink(written, at).unwrap();
    }

    /// The folder `d` at `at`: the physical folder its content goes into, and whether it lies
    /// outside.
    fn folder(&mut self, d: Dir, at: &Path) -> (PathBuf, bool) {
        match d {
            Dir::Real => {
                std::fs::create_dir(at).unwrap();
                (at.to_path_buf(), false)
            }
            Dir::In { absolute } => {
                let name = self.unique("dir");
                let target = self.stash.join(name);
                std::fs::create_dir(&target).unwrap();
                Self::link(at, &target, absolute);
                (target, false)
            }
            Dir::Out { absolute } => {
                let name = self.unique("dir");
                let target = self.outside.join(name);
                std::fs::create_dir(&target).unwrap();
                Self::link(at, &target, absolute);
                (target, true)
            }
        }
    }

    /// The file `f` at `at`, a copy of `source`.
    fn file(&mut self, f: File, at: &Path, source: &Path) {
        let copy = |to: &Path| {
            std::fs::copy(source, to).unwrap();
        };
        match f {
            File::Real => copy(at),
            File::Missing => {}
            File::In { absolute } => {
                let name = self.unique("file");
                let target = self.stash.join(name);
                copy(&target);
                Self::link(at, &target, absolute);
            }
            File::Out { absolute } => {
                let name = self.unique("file");
                let target = self.outside.join(name);
                copy(&target);
                Self::link(at, &target, absolute);
            }
            File::OutMissing { absolute } => {
                let name = self.unique("none");
                let target = self.outside.join(name);
                Self::link(at, &target, absolute);
            }
            File::InThenOut => {
                let name = self.unique("file");
                let target = self.outside.join(name);
                copy(&target);
                let name = self.unique("hop");
                let hop = self.stash.join(name);
                Self::link(&hop, &target, true);
                Self::link(at, &hop, false);
            }
            File::ToFolder => Self::link(at, &self.stash, false),
        }
    }

    /// Builds `t` under `inside` (a folder inside the runs folder): the run folder's path
    /// from there.
    fn build(&mut self, t: &Tree, inside: &Path) -> PathBuf {
        let mut physical = inside.to_path_buf();
        let mut logical = PathBuf::new();
        let mut out = false;
        for (i, d) in t.levels.iter().enumerate() {
            let name = format!("level-{i}");
            let at = physical.join(&name);
            let d = if out { Dir::Real } else { *d };
            let (next, o) = self.folder(d, &at);
            (physical, out) = (next, out || o);
            logical.push(name);
        }
        let at = physical.join("run");
        logical.push("run");
        let (run, o) = self.folder(if out { Dir::Real } else { t.run }, &at);
        if out || o {
            // Outside: what a real run folder holds, so that following a link out would load.
            copy_dir(template(), &run);
            return logical;
        }
        for (name, f) in FILES.iter().zip(t.files) {
            self.file(f, &run.join(name), &template().join(name));
        }
        let (states, o) = self.folder(t.states, &run.join("states"));
        let source = template().join("states");
        if o {
            copy_dir(&source, &states);
        } else {
            let first = std::fs::read_dir(&source).unwrap().next().unwrap().unwrap();
            self.file(t.state, &states.join(first.file_name()), &first.path());
        }
        logical
    }
}

/// The server of the property, its runs folder, what its reader looked at and opened, and
/// the folder outside.
struct Fixture {
    addr: SocketAddr,
    runs: PathBuf,
    outside: PathBuf,
    seen: Arc<Mutex<Vec<(PathBuf, Access)>>>,
    cases: AtomicUsize,
}

fn fixture() -> &'static Fixture {
    static F: OnceLock<Fixture> = OnceLock::new();
    F.get_or_init(|| {
        let base = scratch("props").canonicalize().unwrap();
        let (runs, outside) = (base.join("runs"), base.join("outside"));
        std::fs::create_dir_all(&runs).unwrap();
        std::fs::create_dir_all(&outside).unwrap();
        let seen: Arc<Mutex<Vec<(PathBuf, Access)>>> = Arc::default();
        let record = Arc::clone(&seen);
        let root = RunsRoot::new(&runs)
            .unwrap()
            .observed(move |p, a| record.lock().unwrap().push((p.to_path_buf(), a)));
        let (curves, build) = ring();
        let addr = serve_runs_in(&curves, &build, root);
        Fixture {
            addr,
            runs,
            outside,
            seen,
            cases: AtomicUsize::new(0),
        }
    })
}

/// `POST /api/run` of `path`: the status and the answer.
fn load(addr: SocketAddr, path: &str) -> (u16, Value) {
    let body = serde_json::json!({ "path": path }).to_string();
    let (status, text) = request(addr, "POST", "/api/run", body.as_bytes());
    (status, serde_json::from_str(&text).unwrap())
}

/// Everything the reader looked at since last asked lies inside `runs`: each entry looked at
/// in a folder inside, each file opened inside after every link.
fn all_inside(f: &Fixture) -> Result<(), TestCaseError> {
    for (p, access) in f.seen.lock().unwrap().drain(..) {
        prop_assert!(p.starts_with(&f.runs), "{:?} {}", access, p.display());
        let real = match access {
            Access::Open => p.canonicalize(),
            Access::Look => p.parent().unwrap().canonicalize(),
        };
        let real = real.map_err(|e| TestCaseError::fail(format!("{}: {e}", p.display())))?;
        prop_assert!(real.starts_with(&f.runs), "{:?} {}", access, p.display());
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn a_run_folder_is_read_inside_the_runs_folder_only(t in tree()) {
        let f = fixture();
        let k = f.cases.fetch_add(1, Ordering::Relaxed);
        let inside = f.runs.join(format!("case-{k}"));
        let outside = f.outside.join(format!("case-{k}"));
        std::fs::create_dir_all(&inside).unwrap();
        std::fs::create_dir_all(inside.join("stash")).unwrap();
        std::fs::create_dir_all(&outside).unwrap();
        let mut case = Case { stash: inside.join("stash"), outside: outside.clone(), made: 0 };
        let run = Path::new(&format!("case-{k}")).join(case.build(&t, &inside));
        let path = if t.absolute_request { f.runs.join(&run) } else { run };
        let path = path.display().to_string();
        f.seen.lock().unwrap().clear();

        let (status, answer) = load(f.addr, &path);
        all_inside(f)?;
        let (want, mesh) = expected(&t);
        prop_assert_eq!(status, want, "{}", answer);
        if status == 200 {
            let warnings = answer["warnings"].as_array().unwrap();
            match mesh {
                None => prop_assert!(warnings.is_empty(), "{}", answer),
                Some(says) => prop_assert!(
                    warnings.len() == 1 && warnings[0].as_str().unwrap().contains(says),
                    "{}", answer
                ),
            }
        }

        // Nothing outside any more: the same answer, word for word.
        std::fs::remove_dir_all(&outside).unwrap();
        let again = load(f.addr, &path);
        all_inside(f)?;
        prop_assert_eq!(&again, &(status, answer));
    }
}
