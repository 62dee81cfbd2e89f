//! The output folder of a greedy run, written by `run_folder::OutputWriter`.
//!
//! On small networks (random crossing arches, 9 arches at budget 0.3: 7 removals; the dome,
//! 2×4 arcs: 6 removals), in temporary folders that are removed afterwards:
//!
//! - determinism: the same run inside rayon pools of 1 and 2 threads writes byte-identical
//!   `result.json`, `modes/*.bin`, `states/*.bin`, `iterations/*.obj`, `final.obj`,
//!   `summary.txt` and `network.json` (only `timings.json` may differ);
//! - resume: a run stopped after any k recorded iterations (cancelled between iterations,
//!   cancelled once iteration k handed on its test vectors, or its record failing to be
//!   written) leaves an incomplete `result.json` with k iterations; then
//!   `OutputWriter::resume` + `greedy(.., Some(point), ..)` + `finish` gives a `result.json`
//!   byte-identical to an uninterrupted run's (`complete`, `stop`, `final` included), and the
//!   same side files;
//! - contents: `network.json` (the network), `result.json` (parses as `ResultFile`, version 1,
//!   objective "lambda_eq", complete, every `mode_file` present with 3·V f64, `removed` and
//!   `score` null on the last iteration only, `final` = the last iteration, no timing fields),
//!   `timings.json`, `final.obj`, `summary.txt` and one `iterations/KKKK.obj` per iteration.

mod common;

use common::{TempDir, random_arches};
use curvenet::network::{BuildInfo, BuildParams, Network, build_network};
use curvenet::rod::Supports;
use curvenet::run_folder::{InputDescription, OutputWriter, ResultFile, RunSetup};
use curvenet::simplify::greedy::{GreedyHooks, GreedyOutcome, IterationRecord};
use curvenet::simplify::{Budget, GreedyParams, SimplifyError, greedy};
use curvenet::stability::Evaluation;
use curvenet::stability::{Analyzer, StabilityParams};
use std::collections::BTreeMap;
use std::path::Path;

/// A network with its build, the analyzer and the run's set-up.
struct Scene {
    analyzer: Analyzer,
    setup: RunSetup,
    params: GreedyParams,
}

fn scene(curves: &[curvenet::io::Polyline], h: f64, fraction: f64) -> Scene {
    scene_with(curves, h, fraction, StabilityParams::default())
}

fn scene_with(
    curves: &[curvenet::io::Polyline],
    h: f64,
    fraction: f64,
    stability: StabilityParams,
) -> Scene {
    let build = BuildParams {
        edge_length: h,
        supports: Supports::Clamped,
        ..Default::default()
    };
    let (net, info): (Network, BuildInfo) = build_network(curves, &build).expect("builds");
    let n = net.rods.len();
    let total = net.total_length(&(0..n).collect::<Vec<_>>());
    let params = GreedyParams::new(Budget::Fraction(fraction));
    let setup = RunSetup {
        input: InputDescription {
            example: None,
            mesh: None,
            curve_files: vec!["<test>".into()],
            scale: 1.0,
        },
        build,
        stability: stability.clone(),
        greedy: params.clone(),
        network: info,
        total_length: total,
        constraints: Default::default(),
        physical: None,
        physical_model: None,
    };
    Scene {
        analyzer: Analyzer::new(net, stability).expect("analyzer"),
        setup,
        params,
    }
}

fn arches_scene() -> Scene {
    // Carried test vectors in every iteration (by default only after iterations that needed
    // inertia tests, which this small network rarely does): the resume must restore them.
    let mut stability = StabilityParams::default();
    stability.tuning.carry_after = 0;
    scene_with(&random_arches(3, 9), 70.0, 0.3, stability)
}

fn dome_scene() -> Scene {
    let s = curvenet::builtin::dome_arcs(2000.0, 700.0, 2, 4);
    scene(&s.curves, 100.0, 0.3)
}

fn timings_json(g: &GreedyOutcome) -> serde_json::Value {
    serde_json::to_value(&g.timings).expect("timings serialize")
}

/// An uninterrupted run into `dir`.
fn full_run(s: &Scene, dir: &Path) -> GreedyOutcome {
    let budget = s.params.budget.length(s.setup.total_length);
    let mut w = OutputWriter::create(dir, s.analyzer.network(), s.setup.clone(), budget)
        .expect("output folder");
    let g = greedy(&s.analyzer, &s.params, None, None, &mut w).expect("greedy runs");
    w.finish(&g, &timings_json(&g)).expect("finish");
    g
}

/// Every file under `dir` (relative path → bytes), `timings.json` left out.
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(root: &Path, d: &Path, out: &mut BTreeMap<String, Vec<u8>>) {
        for e in std::fs::read_dir(d).expect("readable folder") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                let rel = p.strip_prefix(root).expect("under root");
                let rel = rel.to_string_lossy().replace('\\', "/");
                if rel != "timings.json" {
                    out.insert(rel, std::fs::read(&p).expect("readable file"));
                }
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// Asserts that two output folders hold the same files with the same bytes.
fn assert_same_folders(a: &Path, b: &Path, what: &str) {
    let (fa, fb) = (files(a), files(b));
    assert_eq!(
        fa.keys().collect::<Vec<_>>(),
        fb.keys().collect::<Vec<_>>(),
        "{what}: different files"
    );
    for (name, bytes) in &fa {
        if bytes != &fb[name] {
            let first = bytes
                .iter()
                .zip(&fb[name])
                .position(|(x, y)| x != y)
                .unwrap_or(bytes.len().min(fb[name].len()));
            let around = |v: &[u8]| {
                String::from_utf8_lossy(&v[first.saturating_sub(80)..(first + 80).min(v.len())])
                    .into_owned()
            };
            panic!(
                "{what}: {name} differs at byte {first}:\n---\n{}\n---\n{}",
                around(bytes),
                around(&fb[name])
            );
        }
    }
}

/// Asserts that two values serialize to the same JSON, showing the first difference.
fn assert_same_json<T: serde::Serialize + ?Sized>(a: &T, b: &T, what: &str) {
    let a = serde_json::to_string(a).expect("serializes");
    let b = serde_json::to_string(b).expect("serializes");
    if a != b {
        let first = a
            .bytes()
            .zip(b.bytes())
            .position(|(x, y)| x != y)
            .unwrap_or(a.len().min(b.len()));
        let lo = first.saturating_sub(60);
        let around = |s: &str| {
            String::from_utf8_lossy(&s.as_bytes()[lo..(first + 60).min(s.len())]).into_owned()
        };
        panic!(
            "{what}: differ at byte {first}:\n  {}\n  {}",
            around(&a),
            around(&b)
        );
    }
}

#[test]
fn result_is_byte_identical_across_thread_counts() {
    for (name, s) in [("arches", arches_scene()), ("dome", dome_scene())] {
        let mut dirs = Vec::new();
        let mut outcomes = Vec::new();
        for threads in [1, 2] {
            let dir = TempDir::new(&format!("{name}-threads{threads}"));
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("thread pool");
            let g = pool.install(|| full_run(&s, dir.path()));
            outcomes.push(g);
            dirs.push(dir);
        }
        let ra = std::fs::read(dirs[0].path().join("result.json")).expect("result.json");
        let rb = std::fs::read(dirs[1].path().join("result.json")).expect("result.json");
        assert!(
            ra == rb,
            "{name}: result.json differs between 1 and 2 threads"
        );
        assert_same_folders(dirs[0].path(), dirs[1].path(), name);
        let removed: Vec<_> = outcomes[0].iterations.iter().map(|i| i.removed).collect();
        println!(
            "{name}: {} iterations, removals {removed:?}, identical with 1 and 2 threads",
            outcomes[0].iterations.len()
        );
    }
}

/// How a test run into a folder stops early, once `after` iterations are recorded.
#[derive(Clone, Copy, Debug)]
enum Stop {
    /// Cancelled between iterations.
    Between,
    /// Cancelled once the next iteration has handed on its test vectors, before it is
    /// recorded (a signal during its candidate search).
    AfterCarried,
    /// The next iteration's record cannot be written (a full disk), after its test vectors
    /// were.
    FailedWrite,
}

/// Hooks that write the folder and stop the run after `after` iterations, as `how` says.
struct StopAfter<'a> {
    writer: OutputWriter<'a>,
    after: usize,
    how: Stop,
    seen: usize,
    carried_next: bool,
}

impl GreedyHooks for StopAfter<'_> {
    fn iteration(&mut self, record: &IterationRecord, eval: &Evaluation) -> Result<(), String> {
        if matches!(self.how, Stop::FailedWrite) && self.seen >= self.after {
            return Err("result.json: No space left on device".into());
        }
        self.writer.iteration(record, eval)?;
        self.seen += 1;
        Ok(())
    }

    fn carried(
        &mut self,
        carried: &curvenet::stability::candidates::Carried,
    ) -> Result<(), String> {
        self.carried_next = self.seen >= self.after;
        self.writer.carried(carried)
    }

    fn cancelled(&self) -> bool {
        let stop = match self.how {
            Stop::Between => self.seen >= self.after,
            Stop::AfterCarried => self.carried_next,
            Stop::FailedWrite => false,
        };
        stop || self.writer.cancelled()
    }

    fn flush(&mut self) -> Result<(), String> {
        self.writer.flush().map_err(|e| e.to_string())
    }
}

/// A run into `dir` stopped as `how` says after `after` iterations; checks that it reports
/// the stop. The folder is flushed and the writer dropped when it returns.
fn stopped_run(s: &Scene, dir: &Path, after: usize, how: Stop) {
    let budget = s.params.budget.length(s.setup.total_length);
    let writer = OutputWriter::create(dir, s.analyzer.network(), s.setup.clone(), budget)
        .expect("output folder");
    let mut hooks = StopAfter {
        writer,
        after,
        how,
        seen: 0,
        carried_next: false,
    };
    let r = greedy(&s.analyzer, &s.params, None, None, &mut hooks);
    let expected = match how {
        Stop::FailedWrite => matches!(r, Err(SimplifyError::Hook(_))),
        _ => matches!(r, Err(SimplifyError::Cancelled)),
    };
    assert!(
        expected,
        "after = {after}, {how:?}: expected a stopped run, got {:?}",
        r.map(|g| g.stop)
    );
}

/// A run into `dir` cancelled between iterations after `after` of them.
fn cancelled_run(s: &Scene, dir: &Path, after: usize) {
    stopped_run(s, dir, after, Stop::Between);
}

#[test]
fn resumed_run_writes_the_same_result_as_an_uninterrupted_one() {
    let s = arches_scene();
    let full = TempDir::new("full");
    let g_full = full_run(&s, full.path());
    let n = g_full.iterations.len();
    assert!(
        n >= 6,
        "the network needs at least 5 removals, got {}",
        n - 1
    );
    // The run hands test vectors between iterations and uses them (their bounds are
    // recorded): a resumed run must read them back to continue identically.
    let extended = g_full
        .iterations
        .iter()
        .flat_map(|i| &i.candidates)
        .filter(|c| c.extended_bound.is_some())
        .count();
    assert!(extended > 0, "the run used no carried vector");
    // From every recorded iteration that removed a curve, however the run stopped there.
    for k in 1..n {
        for how in [Stop::Between, Stop::AfterCarried, Stop::FailedWrite] {
            if matches!(how, Stop::AfterCarried) && k == n - 1 {
                // The last iteration searches no candidate: it hands nothing on.
                continue;
            }
            let what = format!("k = {k}, {how:?}");
            let dir = TempDir::new(&format!("resume{k}"));
            stopped_run(&s, dir.path(), k, how);
            // The interrupted folder: k iterations, incomplete.
            let partial = ResultFile::read(dir.path()).expect("partial result.json");
            assert!(!partial.complete && partial.stop.is_none() && partial.final_network.is_none());
            assert_eq!(partial.iterations.len(), k, "{what}");
            // Read back exactly as recorded (f64 values included).
            assert_same_json(
                &partial.iterations[..],
                &g_full.iterations[..k],
                &format!("{what}: iterations read back from result.json"),
            );

            let (mut writer, point) =
                OutputWriter::resume(dir.path(), s.analyzer.network(), &s.setup, None)
                    .unwrap_or_else(|e| panic!("{what}: resume failed: {e}"));
            assert!(
                writer.warnings().is_empty(),
                "{what}: {:?}",
                writer.warnings()
            );
            let point = point.expect("an interrupted run has a point to resume from");
            assert_eq!(point.iterations.len(), k);
            let g = greedy(&s.analyzer, &s.params, None, Some(point), &mut writer)
                .expect("resumed greedy");
            writer.finish(&g, &timings_json(&g)).expect("finish");
            assert_eq!(g.stop, g_full.stop);
            assert_eq!(g.iterations.len(), n);

            // result.json (complete, stop and final included) and every side file, byte for
            // byte.
            assert_same_folders(full.path(), dir.path(), &format!("resume after {what}"));
        }
        println!("resume after {k} iteration(s), however stopped: identical output");
    }
}

/// Every key of a JSON value, recursively.
fn keys(v: &serde_json::Value, out: &mut Vec<String>) {
    match v {
        serde_json::Value::Object(m) => {
            for (k, x) in m {
                out.push(k.clone());
                keys(x, out);
            }
        }
        serde_json::Value::Array(a) => a.iter().for_each(|x| keys(x, out)),
        _ => {}
    }
}

#[test]
fn output_folder_holds_the_contracted_files() {
    let s = dome_scene();
    let dir = TempDir::new("contents");
    let g = full_run(&s, dir.path());
    let d = dir.path();
    let n_it = g.iterations.len();
    assert!(n_it >= 3);

    // network.json is the network (written and read back exactly).
    let bytes = std::fs::read(d.join("network.json")).expect("network.json");
    assert!(bytes == serde_json::to_vec(s.analyzer.network()).expect("serializes"));
    let net: Network = serde_json::from_slice(&bytes).expect("network.json parses");
    assert_same_json(&net, s.analyzer.network(), "network.json read back");

    // result.json.
    let r = ResultFile::read(d).expect("result.json parses as ResultFile");
    assert_eq!(r.version, 1);
    assert_eq!(r.objective, "lambda_eq");
    assert!(r.complete);
    assert_eq!(r.stop, Some(g.stop));
    assert_same_json(&r.setup, &s.setup, "setup read back from result.json");
    assert_same_json(&r.budget, &g.budget, "budget read back from result.json");
    assert_same_json(&r.iterations, &g.iterations, "iterations read back");
    let last = r.iterations.last().expect("iterations");
    let fin = r.final_network.as_ref().expect("final record");
    assert_eq!(fin.curves, last.curves);
    assert_eq!((fin.length, fin.lambda), (last.length, last.lambda));
    assert!(fin.length <= r.budget);
    let dofs = s.analyzer.network().dofs();
    for (k, it) in r.iterations.iter().enumerate() {
        assert_eq!(it.mode_file, format!("modes/{k:04}.bin"));
        let mode = std::fs::read(d.join(&it.mode_file)).expect("mode file exists");
        assert_eq!(mode.len(), 8 * dofs, "{}: 3·V f64", it.mode_file);
        let obj = d.join(format!("iterations/{k:04}.obj"));
        let text = std::fs::read_to_string(&obj).expect("iteration OBJ exists");
        let lines = text.lines().filter(|l| l.starts_with("l ")).count();
        assert_eq!(
            lines,
            it.curves.len(),
            "{}: one polyline per curve",
            obj.display()
        );
        let is_last = k + 1 == n_it;
        assert_eq!(it.removed.is_none(), is_last, "iteration {k}: removed");
        assert_eq!(it.score.is_none(), is_last, "iteration {k}: score");
    }
    assert!(!d.join(format!("iterations/{n_it:04}.obj")).exists());
    assert_eq!(
        std::fs::read_dir(d.join("iterations"))
            .expect("folder")
            .count(),
        n_it
    );
    // In the JSON text: numbers, and null on the last iteration only.
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("result.json")).expect("file")).expect("json");
    let its = v["iterations"].as_array().expect("iterations array");
    for (k, it) in its.iter().enumerate() {
        let is_last = k + 1 == its.len();
        assert_eq!(it["removed"].is_null(), is_last, "iteration {k}");
        assert_eq!(it["score"].is_null(), is_last, "iteration {k}");
        assert!(is_last || (it["removed"].is_u64() && it["score"].is_f64()));
        assert!(it["lambda"].is_f64() && it["length"].is_f64());
    }
    // No timing fields.
    let mut all = Vec::new();
    keys(&v, &mut all);
    for k in &all {
        let k = k.to_lowercase();
        assert!(
            !["second", "time", "elapsed", "duration", "wall"]
                .iter()
                .any(|w| k.contains(w)),
            "result.json has a timing field '{k}'"
        );
    }
    // The other files.
    let timings: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("timings.json")).expect("timings.json"))
            .expect("timings.json parses");
    assert!(timings["total_seconds"].is_f64());
    let final_obj = std::fs::read_to_string(d.join("final.obj")).expect("final.obj");
    assert_eq!(
        final_obj.lines().filter(|l| l.starts_with("l ")).count(),
        last.curves.len()
    );
    assert_eq!(
        final_obj,
        std::fs::read_to_string(d.join(format!("iterations/{:04}.obj", n_it - 1))).expect("obj")
    );
    let summary = std::fs::read_to_string(d.join("summary.txt")).expect("summary.txt");
    assert!(summary.contains("λ_eq") && summary.contains("removed in order"));
    // The stop reason in words, not as code.
    assert!(summary.contains("; stop: budget met\n"), "{summary}");
    assert!(!summary.contains("Some("), "{summary}");
    println!(
        "output folder: {n_it} iterations, {} keys in result.json",
        all.len()
    );
}

#[test]
fn a_file_that_cannot_be_written_stops_the_run_with_its_name() {
    // The files are written in the background (`io::BackgroundWriter`): a failure must still
    // reach the greedy, name the file, and keep `result.json` from recording the iteration.
    let s = dome_scene();
    let dir = TempDir::new("unwritable");
    let budget = s.params.budget.length(s.setup.total_length);
    let mut w = OutputWriter::create(dir.path(), s.analyzer.network(), s.setup.clone(), budget)
        .expect("output folder");
    // `iterations` becomes a file: no curve file can be made inside it.
    let iterations = dir.path().join("iterations");
    std::fs::remove_dir_all(&iterations).expect("remove iterations/");
    std::fs::write(&iterations, b"in the way").expect("a file in its place");
    let r = greedy(&s.analyzer, &s.params, None, None, &mut w);
    match r {
        Err(SimplifyError::Hook(msg)) => {
            assert!(msg.contains("iterations/0000.obj"), "{msg}");
        }
        other => panic!(
            "expected the failed write as an error, got {:?}",
            other.map(|g| g.stop)
        ),
    }
    drop(w);
    // The states written before the failure are there; nothing after it.
    assert!(dir.path().join("states/0000.bin").is_file());
    let recorded = ResultFile::read(dir.path()).expect("result.json");
    assert!(recorded.iterations.is_empty() && !recorded.complete);
}

#[test]
fn a_damaged_carried_vectors_file_is_a_warning_on_resume_and_the_removals_stay() {
    let s = arches_scene();
    let full = TempDir::new("carried-full");
    let g_full = full_run(&s, full.path());
    let removals = |g: &GreedyOutcome| g.iterations.iter().map(|i| i.removed).collect::<Vec<_>>();
    // Damaged (cut in half), and absent: each is a warning naming the file.
    for damage in [true, false] {
        let dir = TempDir::new(&format!("carried-{damage}"));
        cancelled_run(&s, dir.path(), 2);
        // Iteration 1 is the last recorded: its vectors are in slot 1.
        let carried = dir.path().join("states/carried.1.bin");
        let bytes = std::fs::read(&carried).expect("the run saved its carried vectors");
        if damage {
            std::fs::write(&carried, &bytes[..bytes.len() / 2]).unwrap();
        } else {
            std::fs::remove_file(&carried).unwrap();
        }
        let (mut writer, point) =
            OutputWriter::resume(dir.path(), s.analyzer.network(), &s.setup, None)
                .expect("a damaged side file does not stop a resume");
        let point = point.expect("a point to resume from");
        assert!(point.carried.is_empty());
        assert_eq!(writer.warnings().len(), 1, "{:?}", writer.warnings());
        let w = &writer.warnings()[0];
        let why = if damage { "damaged" } else { "missing" };
        assert!(w.contains("states/carried.1.bin") && w.contains(why), "{w}");
        let g =
            greedy(&s.analyzer, &s.params, None, Some(point), &mut writer).expect("resumed greedy");
        writer.finish(&g, &timings_json(&g)).expect("finish");
        assert_eq!(removals(&g), removals(&g_full), "damaged = {damage}");
    }
}
