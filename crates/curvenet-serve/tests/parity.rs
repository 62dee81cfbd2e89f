//! The server's answers agree with the application layer's — what `curvenet analyze`,
//! `curvenet simplify` and Python's `analyze`/`simplify` give — for the same inputs and
//! options. Each server is started as `curvenet serve` starts it (`curvenet_serve::start`:
//! the inputs read, scaled, the default edge length chosen and the network built by
//! `curvenet::app`), on a paper's example (the tower), random geodesic networks (traced on a
//! built-in surface, or read from curve and mesh files), in the paper's mode, the physical
//! mode and under the frequency objective, with design constraints:
//!
//! - a structure the server analyses from the drawn state (its start: every curve, or what a
//!   removal leaves) against `app::analyze` of the same set: `λ_eq` (`μ_min` under the
//!   frequency objective), the two lowest eigenvalues, the zero and negative modes, the
//!   length, the curves carrying the mode, the gravity deflection and, in the physical mode,
//!   the whole physical report, **bit for bit**;
//! - remove/restore edits: a removal is relaxed warm from the previous equilibrium, so its
//!   `λ` is compared with `app::analyze`'s within **1e-6 relative** (an equilibrium converged
//!   from another start: the edit path's accuracy, docs/serve.md); a restore to a set
//!   analysed before comes from the cache, bit for bit as the first time;
//! - the served greedy under the same budget, keep list and constraints against
//!   `app::execute`'s `result.json`: every iteration's curves, removal, `λ`, length, mode
//!   counts and physical figures **bit for bit**;
//! - the served local search from the greedy's final network against the run's
//!   `local_search` record: the network found, its `λ` and length **bit for bit**, the start
//!   it came from, its moves and evaluations.
//!
//! Bit for bit holds because every number comes from the same library calls in the same
//! order; the searches' parallel parts give the same bits on any number of threads.

mod common;

use common::design::serve_inputs_without;
use common::{curves_of, ok, scratch};
use curvenet::app::{
    self, AnalyzeOutcome, CurveSource, InputSpec, MeshSource, ModelOptions, RunSpec, Setup, Silent,
};
use curvenet::cancel::Cancel;
use curvenet::constraints::{ConstraintParams, Group};
use curvenet::physics::PhysicalOptions;
use curvenet::run_folder::ResultFile;
use curvenet::simplify::Budget;
use curvenet::stability::Objective;
use curvenet::words::Neutral;
use serde_json::{Value, json};
use std::net::SocketAddr;
use std::path::Path;
use std::time::{Duration, Instant};

/// One set of inputs and options, served and run alike.
struct Case {
    name: &'static str,
    input: InputSpec,
    model: ModelOptions,
    /// Curve sets removed at the start of a server of their own (each compared bit for bit).
    removals: Vec<Vec<usize>>,
    /// Curves removed and restored one edit at a time.
    toggles: Vec<usize>,
    /// The searches' budget (a fraction) and keep list.
    budget: f64,
    keep: Vec<usize>,
    /// The design constraints: the API's body and the run's settings.
    constraints: Option<(Value, ConstraintParams)>,
    /// Run the local search after the greedy.
    local: bool,
}

/// A server of `case`'s inputs and model, with `remove` removed at the start.
fn serve(case: &Case, remove: &[usize]) -> SocketAddr {
    serve_inputs_without(case.input.clone(), case.model.clone(), remove.to_vec())
}

/// `app::analyze` of `case`'s inputs without `remove`: `curvenet analyze --remove`'s numbers.
fn analyzed(case: &Case, remove: &[usize]) -> AnalyzeOutcome {
    let mut setup = Setup::new(&case.input, &case.model).expect("set up");
    app::analyze(&mut setup, remove, &Neutral).expect("analysed")
}

/// The bits of a JSON number.
fn bits(v: &Value) -> u64 {
    v.as_f64()
        .unwrap_or_else(|| panic!("a number: {v}"))
        .to_bits()
}

/// A served state analysed from the drawn state against `app::analyze` of its set, bit for
/// bit (and the served gravity deflection of the current structure, `mode`).
fn assert_state_is_analyzes(what: &str, state: &Value, mode: &Value, out: &AnalyzeOutcome) {
    let r = &out.report;
    assert_eq!(bits(&state["lambda"]), r.lambda.to_bits(), "{what}: λ");
    assert_eq!(
        state["curves"].as_array().unwrap().len(),
        r.curves,
        "{what}"
    );
    assert_eq!(bits(&state["length"]), r.length.to_bits(), "{what}: length");
    assert_eq!(state["zero_modes"], r.zero_modes, "{what}");
    assert_eq!(state["negative_modes"], r.negative_modes, "{what}");
    let served: Vec<u64> = state["eigenvalues"]
        .as_array()
        .unwrap()
        .iter()
        .map(bits)
        .collect();
    let analysed: Vec<u64> = r.eigenvalues.iter().take(2).map(|e| e.to_bits()).collect();
    assert_eq!(served, analysed, "{what}: eigenvalues");
    assert_eq!(
        state["mode_curves"],
        json!(r.mode_curves),
        "{what}: mode curves"
    );
    match &r.gravity {
        Some(g) => {
            assert_eq!(
                bits(&mode["gravity"]["max_displacement"]),
                g.max_displacement.to_bits()
            );
            assert_eq!(mode["gravity"]["vertex"], g.vertex, "{what}");
        }
        None => assert!(mode["gravity"].is_null(), "{what}"),
    }
    match &out.physical {
        Some(p) => assert_eq!(state["physical"], json!(p), "{what}: physical report"),
        None => assert!(state.get("physical").is_none(), "{what}"),
    }
}

/// Polls `GET path` until its status is no longer `running` (at most five minutes).
fn wait(addr: SocketAddr, path: &str) -> Value {
    let start = Instant::now();
    loop {
        let p = ok(addr, "GET", path, "");
        if p["status"] != "running" {
            return p;
        }
        assert!(
            start.elapsed() < Duration::from_secs(300),
            "still running: {p}"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Everything the case compares: the start, the removals, the edits, the greedy and the
/// local search.
fn check(case: &Case) {
    let name = case.name;
    // The start: every curve.
    let addr = serve(case, &[]);
    let all = analyzed(case, &[]);
    let state = ok(addr, "GET", "/api/state", "");
    let mode = ok(addr, "GET", "/api/mode", "");
    assert_state_is_analyzes(&format!("{name}: start"), &state, &mode, &all);
    let positions = ok(addr, "GET", "/api/network", "")["positions"]
        .as_array()
        .unwrap()
        .len();
    assert_eq!(
        positions,
        3 * all.report.vertices,
        "{name}: the same network"
    );
    // Removals at the start: sets analysed from the drawn state.
    for remove in &case.removals {
        let removed = serve(case, remove);
        let what = format!("{name}: without {remove:?}");
        let state = ok(removed, "GET", "/api/state", "");
        let mode = ok(removed, "GET", "/api/mode", "");
        assert_state_is_analyzes(&what, &state, &mode, &analyzed(case, remove));
    }
    // Remove and restore, one edit at a time.
    let mut gone: Vec<usize> = Vec::new();
    for &c in case.toggles.iter().chain(case.toggles.iter().rev()) {
        let t = ok(addr, "POST", "/api/toggle", &format!("{{\"curve\":{c}}}"));
        match gone.iter().position(|&g| g == c) {
            Some(i) => {
                gone.remove(i);
            }
            None => gone.push(c),
        }
        let expected = analyzed(case, &gone).report.lambda;
        let lambda = t["lambda"].as_f64().unwrap();
        if gone.is_empty() {
            // Back to the start, a set analysed before: the first answer's bits.
            assert_eq!(t["from"], "cache", "{name}: the restore of every curve");
            assert_eq!(bits(&t["lambda"]), all.report.lambda.to_bits(), "{name}");
        } else {
            let rel = (lambda - expected).abs() / expected.abs();
            assert!(
                rel <= 1e-6,
                "{name} without {gone:?} ({}): served {lambda:e}, analyze {expected:e}",
                t["from"]
            );
        }
    }
    // The searches, as a run makes them.
    let dir = scratch(&format!("parity-{name}"));
    let mut setup = Setup::new(&case.input, &case.model).expect("set up");
    let spec = RunSpec {
        budget: Some(Budget::Fraction(case.budget)),
        keep: Some(case.keep.clone()),
        constraints: case
            .constraints
            .as_ref()
            .map(|c| c.1.clone())
            .unwrap_or_default(),
        local_search: case.local,
        pictures: false,
        ..RunSpec::new(dir.join("run"))
    };
    let run: ResultFile = app::execute(&mut setup, &spec, &Silent, &Cancel::never())
        .expect("run")
        .result;
    if let Some((body, _)) = &case.constraints {
        ok(addr, "POST", "/api/constraints", &body.to_string());
    }
    let request = json!({ "budget": case.budget, "keep": case.keep }).to_string();
    ok(addr, "POST", "/api/greedy", &request);
    let done = wait(addr, "/api/greedy");
    assert_eq!(done["status"], "done", "{name}: {done}");
    // The last iteration as the progress names it: unstable or not, relaxed or not.
    let last = run.iterations.last().expect("iterations");
    assert_eq!(
        done["last"]["unstable"],
        json!(curvenet::run_folder::record_instability(last)),
        "{name}"
    );
    assert_eq!(done["last"]["converged"], last.newton.converged, "{name}");
    let listed = ok(addr, "GET", "/api/greedy/iterations", "");
    let steps = listed["iterations"].as_array().unwrap();
    assert_eq!(steps.len(), run.iterations.len(), "{name}: iterations");
    assert!(steps.len() > 2, "{name}: a greedy that removes curves");
    for (k, (s, r)) in steps.iter().zip(&run.iterations).enumerate() {
        let what = format!("{name}: iteration {k}");
        assert_eq!(curves_of(s), r.curves, "{what}");
        assert_eq!(s["removed"], json!(r.removed), "{what}");
        assert_eq!(bits(&s["lambda"]), r.lambda.to_bits(), "{what}: λ");
        assert_eq!(bits(&s["length"]), r.length.to_bits(), "{what}: length");
        assert_eq!(s["zero_modes"], r.zero_modes, "{what}");
        assert_eq!(s["negative_modes"], r.negative_modes, "{what}");
        assert_eq!(s["converged"], r.newton.converged, "{what}");
        match &r.physical {
            Some(p) => assert_eq!(s["physical"], json!(p), "{what}: physical figures"),
            None => assert!(s.get("physical").is_none(), "{what}"),
        }
    }
    if case.local {
        let record = run.local_search.as_ref().expect("the run's local search");
        let last = steps.len() - 1;
        ok(
            addr,
            "POST",
            "/api/greedy/step",
            &format!("{{\"iteration\":{last}}}"),
        );
        ok(addr, "POST", "/api/local", &request);
        let done = wait(addr, "/api/local");
        assert_eq!(done["status"], "done", "{name}: {done}");
        let found = &done["result"];
        let best = &found["best"];
        assert_eq!(
            curves_of(best),
            record.curves,
            "{name}: the local search's network"
        );
        assert_eq!(
            bits(&best["lambda"]),
            record.lambda.to_bits(),
            "{name}: its λ"
        );
        assert_eq!(
            bits(&best["length"]),
            record.length.to_bits(),
            "{name}: its length"
        );
        assert_eq!(
            curves_of(&found["start"]),
            record.from_curves,
            "{name}: its start"
        );
        assert_eq!(found["moves"], record.moves.len(), "{name}: its moves");
        assert_eq!(found["evaluations"], record.evaluations, "{name}");
        assert!(record.moves.len() > 1, "{name}: a search that moves");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `count` random geodesics on the built-in dome (largest extent 4000) at edge length `h`
/// (`None`: the application layer's default).
fn geodesics(count: usize, seed: u32, h: Option<f64>) -> InputSpec {
    InputSpec {
        edge_length: h,
        ..InputSpec::new(CurveSource::Geodesics {
            surface: "dome".into(),
            count,
            seed,
        })
    }
}

#[test]
fn the_tower_served_agrees_with_analyze_and_simplify() {
    let input = InputSpec::new(CurveSource::Example {
        name: "tower".into(),
        data: None,
    });
    let setup = Setup::new(&input, &ModelOptions::default()).unwrap();
    let example = setup.inputs.example.clone().expect("an example");
    check(&Case {
        name: "tower",
        input,
        model: ModelOptions::default(),
        removals: vec![vec![3], vec![1, 2, 30]],
        toggles: vec![5, 22],
        budget: example.budget,
        keep: example.keep,
        constraints: None,
        local: false,
    });
}

/// Geodesics traced on the dome, read back from curve and mesh files as a user's inputs, at
/// the default edge length; the searches under groups, connectivity, a minimum number of
/// curves and the surface's largest gap.
#[test]
fn a_random_network_from_files_served_under_constraints_agrees() {
    let traced = Setup::new(&geodesics(9, 5, Some(200.0)), &ModelOptions::default()).unwrap();
    let dir = scratch("parity-inputs");
    let curves = dir.join("curves.obj");
    let mesh = dir.join("dome.obj");
    std::fs::write(&curves, curvenet::io::curves_to_obj(&traced.inputs.curves)).unwrap();
    let surface = traced.inputs.mesh.as_ref().unwrap();
    std::fs::write(&mesh, curvenet::io::mesh_to_obj(surface)).unwrap();
    let input = InputSpec {
        mesh: Some(MeshSource::Path(mesh.clone())),
        scale: 0.5,
        ..InputSpec::new(CurveSource::Files(vec![curves.clone()]))
    };
    let body = json!({
        "groups": [[0, 1]], "connected": true, "min_curves": 3, "max_gap": 1000.0,
    });
    let params = ConstraintParams {
        groups: vec![Group {
            name: "group 1".into(),
            curves: vec![0, 1],
            origin: "groups[0]".into(),
        }],
        connected: true,
        min_curves: Some(3),
        max_gap: Some(1000.0),
        ..ConstraintParams::default()
    };
    check(&Case {
        name: "files",
        input,
        model: ModelOptions::default(),
        removals: vec![vec![4]],
        toggles: vec![2, 7],
        budget: 0.4,
        keep: vec![],
        constraints: Some((body, params)),
        local: true,
    });
    let _ = std::fs::remove_dir_all(Path::new(&dir));
}

/// The physical mode (a steel dome in millimetres) with load cases: every state's physical
/// figures with its load cases, and every iteration's.
#[test]
fn a_random_network_served_in_the_physical_mode_agrees() {
    let loads = std::env::temp_dir().join(format!(
        "curvenet-serve-parity-loads-{}.json",
        std::process::id()
    ));
    std::fs::write(
        &loads,
        r#"{"cases": [{"name": "G", "self_weight": true},
                      {"name": "S", "line": {"intensity": "1kN/m", "direction": [0, 0, -1]}}],
            "combinations": [{"name": "ULS", "factors": {"G": 1.35, "S": 1.5}}]}"#,
    )
    .expect("loads file");
    check(&Case {
        name: "physical",
        input: geodesics(9, 11, Some(250.0)),
        model: ModelOptions {
            physical: PhysicalOptions {
                units: Some("mm".into()),
                material: Some("steel".into()),
                loads: Some(loads.display().to_string()),
                ..PhysicalOptions::default()
            },
            ..ModelOptions::default()
        },
        removals: vec![vec![0, 3]],
        toggles: vec![6],
        budget: 0.5,
        keep: vec![],
        constraints: None,
        local: true,
    });
}

/// The frequency objective: `μ_min` served, the searches maximising it, under symmetry and a
/// largest deviation.
#[test]
fn a_random_network_served_under_the_frequency_objective_agrees() {
    let body = json!({ "symmetry": "auto", "max_deviation": 50.0 });
    let params = ConstraintParams {
        symmetry: "auto".parse().unwrap(),
        max_deviation: Some(50.0),
        ..ConstraintParams::default()
    };
    check(&Case {
        name: "frequency",
        input: geodesics(9, 13, Some(250.0)),
        model: ModelOptions {
            objective: Objective::Frequency,
            ..ModelOptions::default()
        },
        removals: vec![vec![2]],
        toggles: vec![1, 4],
        budget: 0.4,
        keep: vec![],
        constraints: Some((body, params)),
        local: true,
    });
}

/// The default edge length is the application layer's, whoever reads the inputs: the served
/// network is the one `analyze` builds.
#[test]
fn the_default_edge_length_is_the_application_layers() {
    let case = Case {
        name: "default-h",
        input: geodesics(6, 3, None),
        model: ModelOptions::default(),
        removals: vec![],
        toggles: vec![],
        budget: 0.5,
        keep: vec![],
        constraints: None,
        local: false,
    };
    let setup = Setup::new(&case.input, &case.model).unwrap();
    assert_eq!(
        Some(setup.inputs.build.edge_length),
        curvenet::pipeline::default_edge_length(&setup.inputs.curves)
    );
    let addr = serve(&case, &[]);
    let state = ok(addr, "GET", "/api/state", "");
    let mode = ok(addr, "GET", "/api/mode", "");
    assert_state_is_analyzes("default h", &state, &mode, &analyzed(&case, &[]));
}
