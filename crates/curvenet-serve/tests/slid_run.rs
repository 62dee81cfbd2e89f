//! A run folder made with `--slide` served (`curvenet serve RUNDIR`): its slid network is the
//! structure served, `GET /api/network` says how it slid and gives the curves before, and the
//! page carries them for its before/after toggle.

mod common;

use common::design::{H, close};
use common::{assert_refused, ok, request, scratch};
use curvenet::app::{
    CurveSource, InputSpec, ModelOptions, RunSpec, Setup, Silent, SlideSpec, execute, slide,
};
use curvenet::cancel::Cancel;
use curvenet::run_folder::RunsRoot;
use curvenet::simplify::Budget;
use curvenet::slide::MaxMove;
use curvenet_serve::start::{ServeSpec, Source, open};
use curvenet_serve::{AppState, Server};

#[test]
fn a_run_made_with_slide_is_served_as_its_slid_network() {
    let dir = scratch("slid-run");
    let input = InputSpec {
        edge_length: Some(H),
        ..InputSpec::new(CurveSource::Geodesics {
            surface: "dome".into(),
            count: 6,
            seed: 3,
        })
    };
    let mut setup = Setup::new(&input, &ModelOptions::default()).expect("set-up");
    let run = dir.join("run");
    let spec = RunSpec {
        budget: Some(Budget::Fraction(0.85)),
        pictures: false,
        ..RunSpec::new(&run)
    };
    execute(&mut setup, &spec, &Silent, &Cancel::never()).expect("runs");
    // As `--slide` records it: the slid run in the run's `slide/`.
    let slid = SlideSpec {
        max_move: MaxMove::Fraction(0.05),
        pictures: false,
        ..SlideSpec::new(&run, run.join("slide"))
    };
    let record = slide(&slid, &Silent, &Cancel::never())
        .expect("slides")
        .record;

    let served = ServeSpec {
        source: Source::Run(run.clone()),
        model: ModelOptions::default(),
        remove: Vec::new(),
    };
    let opened = open(&served, &Silent).expect("served");
    let server = Server::bind("127.0.0.1:0".parse().unwrap()).unwrap();
    let addr = server.local_addr().unwrap();
    let config = opened.config(RunsRoot::new(&dir).unwrap());
    std::thread::spawn(move || server.serve(AppState::new(opened.workspace, config)));

    let state = ok(addr, "GET", "/api/state", "");
    close(
        state["lambda"].as_f64().unwrap(),
        record.lambda_after,
        "the served structure is the slid network",
    );
    let network = ok(addr, "GET", "/api/network", "");
    let s = &network["slid"];
    assert_eq!(
        s["record"]["lambda_after"].as_f64(),
        Some(record.lambda_after)
    );
    assert_eq!(
        s["record"]["lambda_before"].as_f64(),
        Some(record.lambda_before)
    );
    let before = s["before"].as_array().expect("the curves before");
    assert_eq!(before.len(), network["curves"].as_array().unwrap().len());
    assert!(
        before
            .iter()
            .all(|c| c["points"].as_array().unwrap().len() >= 2)
    );
    // Its greedy panel: the slid network holds less than the budget it was chosen under.
    let greedy = ok(addr, "GET", "/api/greedy", "");
    let fraction = greedy["budget"].as_f64().expect("the budget's fraction");
    assert!(fraction > 0.0 && fraction <= 1.0, "{greedy}");
    // The page carries them (its "before" toggle).
    let (status, page) = request(addr, "GET", "/", b"");
    assert_eq!(status, 200);
    assert!(
        page.contains("\"before\":[{"),
        "the page's data has the curves before"
    );

    // A run folder holds no curves as drawn: drawing and sliding say how to serve them.
    let geodesic = r#"{"geodesic": {"point": [0, 0, 0], "direction": [1, 0, 0]}}"#;
    for (path, body) in [("/api/curves", geodesic), ("/api/slide", "{}")] {
        assert_refused(
            addr,
            "POST",
            path,
            body,
            409,
            "curvenet export RUNDIR --format json",
        );
    }

    // A run without a slide: no `slid`.
    let (status, _) = request(addr, "POST", "/api/run", br#"{"path": "run/slide"}"#);
    assert_eq!(status, 200);
    let plain = dir.join("plain");
    execute(
        &mut Setup::new(&input, &ModelOptions::default()).unwrap(),
        &RunSpec {
            budget: Some(Budget::Fraction(0.85)),
            pictures: false,
            ..RunSpec::new(&plain)
        },
        &Silent,
        &Cancel::never(),
    )
    .expect("runs");
    let (status, text) = request(addr, "POST", "/api/run", br#"{"path": "plain"}"#);
    assert_eq!(status, 200, "{text}");
    assert!(ok(addr, "GET", "/api/network", "")["slid"].is_null());
}
