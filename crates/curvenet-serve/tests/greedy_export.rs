//! The greedy and the export over HTTP: a served run records the iterations of the library's
//! greedy, a step makes one of them current with `analyze`'s `λ`, a cancel stops a long run
//! while other requests are answered, the exports hold the current structure, and every bad
//! request gets a 4xx with a message.

mod common;

use common::{
    analyze_lambda, assert_close, assert_refused, curves_of, dome, ok, post_set, request,
    request_full, serve,
};
use curvenet::network::build_network;
use curvenet::rod::Supports;
use curvenet::simplify::greedy::NoHooks;
use curvenet::simplify::{Budget, GreedyParams, greedy};
use curvenet::stability::{Analyzer, StabilityParams};
use serde_json::Value;
use std::net::SocketAddr;
use std::time::{Duration, Instant};

/// Polls `GET /api/greedy` until the run is no longer running (at most two minutes).
fn wait_for_the_run(addr: SocketAddr) -> Value {
    let start = Instant::now();
    loop {
        let p = ok(addr, "GET", "/api/greedy", "");
        if p["status"] != "running" {
            return p;
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the greedy is still running: {p}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn a_served_greedy_records_the_librarys_iterations_and_steps_through_them() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    assert_eq!(ok(addr, "GET", "/api/greedy", "")["status"], "idle");
    // The current structure does not change where the run starts: the whole network.
    ok(addr, "POST", "/api/toggle", "{\"curve\":2}");
    let started = ok(addr, "POST", "/api/greedy", "{\"budget\":0.5}");
    assert_eq!(started["status"], "running");
    assert_eq!(started["budget"], 0.5);
    let done = wait_for_the_run(addr);
    assert_eq!(done["status"], "done", "{done}");
    assert_eq!(done["stop"], "budget met");

    let (network, _) = build_network(&curves, &build).unwrap();
    let analyzer = Analyzer::new(network, StabilityParams::default()).unwrap();
    let params = GreedyParams::new(Budget::Fraction(0.5));
    let expected = greedy(&analyzer, &params, None, None, &mut NoHooks).unwrap();
    let listed = ok(addr, "GET", "/api/greedy/iterations", "");
    assert_eq!(listed["status"], "done");
    let its = listed["iterations"].as_array().unwrap();
    assert_eq!(its.len(), expected.iterations.len());
    assert_eq!(done["iterations"], its.len());
    for (k, (got, want)) in its.iter().zip(&expected.iterations).enumerate() {
        assert_eq!(got["iteration"], k);
        assert_eq!(curves_of(got), want.curves, "iteration {k}");
        let lambda = got["lambda"].as_f64().unwrap();
        assert!(
            (lambda - want.lambda).abs() <= 1e-9 * want.lambda.abs(),
            "iteration {k}: served λ {lambda:e}, library {:e}",
            want.lambda
        );
        assert_eq!(got["removed"].as_u64().map(|c| c as usize), want.removed);
    }

    // Stepping to an iteration makes its structure current, with analyze's λ of that set.
    let last = its.len() - 1;
    let step = ok(
        addr,
        "POST",
        "/api/greedy/step",
        &format!("{{\"iteration\":{last}}}"),
    );
    assert_eq!(step["iteration"], last);
    let kept = curves_of(&its[last]);
    assert_eq!(curves_of(&step), kept);
    assert_close(&step, analyze_lambda(&curves, &build, &kept));
    assert_eq!(curves_of(&ok(addr, "GET", "/api/state", "")), kept);
    // The same structure through /api/set.
    let set = post_set(addr, &kept);
    assert_eq!(set["lambda"], step["lambda"]);
}

#[test]
fn a_long_greedy_can_be_cancelled_and_does_not_block_the_other_requests() {
    let ex = curvenet::paper::load_embedded("tower", Supports::default()).unwrap();
    let addr = serve(&ex.curves, &ex.build);
    let started = ok(addr, "POST", "/api/greedy", "{\"budget\":0.1}");
    assert_eq!(started["status"], "running");
    // One run at a time.
    let (status, text) = request(addr, "POST", "/api/greedy", b"{\"budget\":0.5}");
    assert_eq!(status, 409, "{text}");
    assert!(text.contains("already computing"), "{text}");
    // Edits and reads are answered while it runs.
    let toggled = ok(addr, "POST", "/api/toggle", "{\"curve\":0}");
    assert!(!curves_of(&toggled).contains(&0));
    ok(addr, "GET", "/api/state", "");
    let cancelling = ok(addr, "POST", "/api/greedy/cancel", "");
    assert_eq!(cancelling["status"], "running");
    let end = wait_for_the_run(addr);
    assert_eq!(end["status"], "cancelled", "{end}");
    let kept = end["iterations"].as_u64().unwrap();
    let listed = ok(addr, "GET", "/api/greedy/iterations", "");
    assert_eq!(listed["iterations"].as_array().unwrap().len() as u64, kept);
    // Cancelled runs keep their iterations; another run may start.
    let (status, text) = request(addr, "POST", "/api/greedy/cancel", b"");
    assert_eq!(status, 409, "{text}");
    ok(addr, "POST", "/api/greedy", "{\"budget\":0.9}");
    assert_eq!(wait_for_the_run(addr)["status"], "done");
}

#[test]
fn the_exports_hold_the_current_structure() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    ok(addr, "POST", "/api/set", "{\"curves\":[0,1,3,4,6]}");
    let (status, head, obj) = request_full(addr, "GET", "/api/export?format=obj", b"");
    assert_eq!(status, 200, "{obj}");
    let head = head.to_ascii_lowercase();
    assert!(
        head.contains("content-disposition: attachment; filename=\"curvenet_5_of_8.obj\""),
        "{head}"
    );
    assert!(obj.starts_with("# curvenet export: the served structure (5 of 8 curves)"));
    assert!(obj.contains("equilibrium state"), "{}", &obj[..100]);
    let objects: Vec<&str> = obj.lines().filter(|l| l.starts_with("o ")).collect();
    assert_eq!(
        objects,
        [
            "o curve 0",
            "o curve 1",
            "o curve 3",
            "o curve 4",
            "o curve 6"
        ]
    );

    let (status, head, csv) = request_full(addr, "GET", "/api/export?format=csv", b"");
    assert_eq!(status, 200, "{csv}");
    assert!(head.to_ascii_lowercase().contains("text/csv"), "{head}");
    let rows: Vec<&str> = csv.lines().filter(|l| !l.starts_with('#')).collect();
    assert!(
        rows[0].starts_with("curve,rest_length,cut_length"),
        "{}",
        rows[0]
    );
    let ids: Vec<&str> = rows[1..]
        .iter()
        .map(|r| r.split(',').next().unwrap())
        .collect();
    assert_eq!(ids, ["0", "1", "3", "4", "6"]);

    let (status, _, json) = request_full(addr, "GET", "/api/export?format=json", b"");
    assert_eq!(status, 200, "{json}");
    let v: Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["format"], "curvenet-curves");
    let labels: Vec<&str> = v["curves"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["label"].as_str().unwrap())
        .collect();
    assert_eq!(labels.len(), 5);
    assert!(labels[2].starts_with("id=3; rest_length="), "{}", labels[2]);
}

#[test]
fn bad_greedy_and_export_requests_get_a_4xx_with_a_message() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    let cases: &[(&str, &str, &str, u16, &str)] = &[
        ("POST", "/api/greedy", "{\"budget\":", 400, "malformed JSON"),
        ("POST", "/api/greedy", "{}", 400, "missing field"),
        (
            "POST",
            "/api/greedy",
            "{\"budget\":\"half\"}",
            400,
            "malformed JSON",
        ),
        (
            "POST",
            "/api/greedy",
            "{\"budget\":0.5,\"x\":1}",
            400,
            "unknown field",
        ),
        (
            "POST",
            "/api/greedy",
            "{\"budget\":0}",
            422,
            "budget fraction",
        ),
        (
            "POST",
            "/api/greedy",
            "{\"budget\":1.5}",
            422,
            "budget fraction",
        ),
        (
            "POST",
            "/api/greedy",
            "{\"budget\":-0.2}",
            422,
            "budget fraction",
        ),
        (
            "POST",
            "/api/greedy",
            "{\"budget\":0.5,\"keep\":[99]}",
            422,
            "keep list names curve 99",
        ),
        ("POST", "/api/greedy/cancel", "", 409, "no greedy run"),
        (
            "POST",
            "/api/greedy/step",
            "{\"iteration\":0}",
            409,
            "no greedy iteration",
        ),
        (
            "POST",
            "/api/greedy/step",
            "{\"iteration\":-1}",
            400,
            "malformed JSON",
        ),
        ("GET", "/api/greedy/step", "", 405, "use POST"),
        ("GET", "/api/greedy/cancel", "", 405, "use POST"),
        ("DELETE", "/api/greedy", "", 405, "use GET, POST"),
        (
            "GET",
            "/api/export?format=stl",
            "",
            400,
            "unknown export format 'stl'",
        ),
        ("GET", "/api/export", "", 400, "format=obj"),
        (
            "GET",
            "/api/export?format=obj&x=1",
            "",
            400,
            "unknown field",
        ),
        (
            "GET",
            "/api/export/../../../etc/passwd",
            "",
            404,
            "no such endpoint",
        ),
        ("POST", "/api/export?format=obj", "", 405, "use GET"),
    ];
    for &(method, path, body, status, says) in cases {
        assert_refused(addr, method, path, body, status, says);
    }
    // A step past the last iteration, once a run has recorded some.
    ok(addr, "POST", "/api/greedy", "{\"budget\":0.9}");
    assert_eq!(wait_for_the_run(addr)["status"], "done");
    let (got, text) = request(addr, "POST", "/api/greedy/step", b"{\"iteration\":99}");
    assert_eq!(got, 422, "{text}");
    assert!(text.contains("no iteration 99"), "{text}");
}
