//! The slide over HTTP: the current structure's curves slid on the surface (streamed
//! progress, cancel), the slid curves adopted as one drawing edit whose `λ` is the slide's and
//! the one `curvenet analyze` finds for the saved design; undo takes it back; every bad
//! request gets a 4xx with a message.

mod common;

use common::design::{
    analyzed_saved, close, lambda, physical_design, saved_inputs, serve, serve_inputs,
};
use common::{assert_refused, ok, scratch};
use curvenet::app::ModelOptions;
use serde_json::{Value, json};
use std::net::SocketAddr;
use std::time::Duration;

/// The slide's progress once it is no longer running.
fn wait(addr: SocketAddr) -> Value {
    loop {
        let p = ok(addr, "GET", "/api/slide", "");
        if p["status"] != "running" {
            return p;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn a_slide_adopted_is_one_edit_with_the_slides_lambda() {
    let addr = serve(8, 3);
    let dir = scratch("slide");
    let before = ok(addr, "GET", "/api/state", "");
    assert_refused(addr, "POST", "/api/slide/adopt", "", 409, "no slide result");

    let started = ok(addr, "POST", "/api/slide", r#"{"max_evaluations": 120}"#);
    assert!(started["status"] == "running" || started["status"] == "done");
    let done = wait(addr);
    assert_eq!(done["status"], "done", "{done}");
    let result = &done["result"];
    let after = result["lambda_after"].as_f64().unwrap();
    assert!(result["evaluations"].as_u64().unwrap() > 0, "{done}");
    // The limit holds within a sweep of the search: it stops there, keeping the best so far,
    // and says so.
    assert!(result["evaluations"].as_u64().unwrap() <= 120, "{done}");
    assert_eq!(result["limited"], true, "{done}");
    assert_eq!(
        before["status"], "stable",
        "a stable structure slides: {before}"
    );
    assert!(after >= result["lambda_before"].as_f64().unwrap(), "{done}");
    assert_eq!(done["best"].as_f64(), Some(after));
    assert_eq!(result["moved"], true, "the slide moves curves: {done}");
    assert!(after > lambda(&before), "the slide stiffens: {done}");

    let adopted = ok(addr, "POST", "/api/slide/adopt", "");
    close(
        lambda(&adopted),
        after,
        "the adopted slide against the slide",
    );
    close(
        lambda(&adopted),
        analyzed_saved(addr, &dir),
        "the adopted slide against analyze of the saved design",
    );
    // The adopted slide belongs to the workspace it replaced: nothing left to adopt.
    assert_refused(addr, "POST", "/api/slide/adopt", "", 409, "no slide result");

    let undone = ok(addr, "POST", "/api/curves/undo", "");
    close(
        lambda(&undone),
        lambda(&before),
        "undo of the adopted slide",
    );
}

#[test]
fn a_slide_cancelled_keeps_its_best_and_bad_requests_get_a_4xx() {
    let addr = serve(4, 3);
    for (body, status, says) in [
        (r#"{"max_move": "far"}"#, 400, "max_move"),
        (r#"{"max_move": -1}"#, 422, "must be positive"),
        (r#"{"max_move": 1e9}"#, 422, "at most"),
        (r#"{"budget": 2}"#, 422, "budget"),
        (r#"{"max_evaluations": 0}"#, 400, "max_evaluations"),
        (r#"{"speed": 1}"#, 400, "speed"),
        ("not json", 400, ""),
    ] {
        assert_refused(addr, "POST", "/api/slide", body, status, says);
    }
    assert_refused(addr, "POST", "/api/slide/cancel", "", 409, "no slide");

    let started = ok(addr, "POST", "/api/slide", r#"{"max_evaluations": 100000}"#);
    assert_eq!(started["status"], "running");
    assert_refused(addr, "POST", "/api/slide", "", 409, "already computing");
    let cancelled = ok(addr, "POST", "/api/slide/cancel", "");
    assert_eq!(cancelled["status"], "running", "asked to stop: {cancelled}");
    let ended = wait(addr);
    assert_eq!(ended["status"], "cancelled", "{ended}");
    assert_eq!(ended["result"]["cancelled"], true);
    // The best network reached by then is adopted like a finished slide's.
    let adopted = ok(addr, "POST", "/api/slide/adopt", "");
    close(
        lambda(&adopted),
        ended["result"]["lambda_after"].as_f64().unwrap(),
        "the cancelled slide adopted",
    );

    // A network served without its surface cannot slide.
    let (curves, build) = common::dome();
    let bare = common::serve(&curves, &build);
    assert_refused(bare, "POST", "/api/slide", "", 409, "surface");
}

/// In the physical mode the page slides with the page's model (each curve its own material
/// and rest shape): the adopted slide's `λ` is the slide's, its physical analysis follows.
#[test]
fn a_slide_in_the_physical_mode_uses_the_pages_model() {
    let dir = scratch("slide-physical");
    let (design, m) = physical_design(serve(8, 3), &dir, |curves| {
        curves[0]["material"] = json!("aluminium");
        curves[1]["rest"] = json!("pre-bent");
        curves[2]["section"] = json!({"outer_diameter": "60mm", "wall": "4mm"});
    });
    let addr = serve_inputs(saved_inputs(design, m), ModelOptions::default());
    let before = ok(addr, "GET", "/api/state", "");
    assert!(
        before["physical"].is_object(),
        "the physical mode: {before}"
    );

    ok(addr, "POST", "/api/slide", r#"{"max_evaluations": 120}"#);
    let done = wait(addr);
    assert_eq!(done["status"], "done", "{done}");
    let result = &done["result"];
    let after = result["lambda_after"].as_f64().unwrap();
    assert!(after >= result["lambda_before"].as_f64().unwrap(), "{done}");
    assert_eq!(result["moved"], true, "the slide moves curves: {done}");
    let adopted = ok(addr, "POST", "/api/slide/adopt", "");
    close(
        lambda(&adopted),
        after,
        "the adopted slide against the slide",
    );
    let state = ok(addr, "GET", "/api/state", "");
    assert!(
        state["physical"]["mass_kg"].as_f64().unwrap() > 0.0,
        "{state}"
    );
}
