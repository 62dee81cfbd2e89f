//! The local search, the design constraints and the gravity deflection over HTTP: a served
//! local search finds the library's best network from the current structure and is adopted
//! with `analyze`'s `λ`; constraints set for the session are honoured by the greedy and the
//! local search and their margins given with every state; the mode carries the gravity
//! deflection; every bad request gets a 4xx with a message and leaves the state alone.

mod common;

use common::{
    analyze_lambda, assert_close, assert_refused, curves_of, dome, ok, post_set, request, serve,
};
use curvenet::cancel::Cancel;
use curvenet::network::build_network;
use curvenet::simplify::Budget;
use curvenet::simplify::local::{LocalParams, local_search};
use curvenet::stability::{Analyzer, StabilityParams};
use serde_json::Value;
use std::net::SocketAddr;
use std::time::{Duration, Instant};

/// Polls `GET path` until its status is no longer `running` (at most two minutes).
fn wait(addr: SocketAddr, path: &str) -> Value {
    let start = Instant::now();
    loop {
        let p = ok(addr, "GET", path, "");
        if p["status"] != "running" {
            return p;
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "still running: {p}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn a_served_local_search_finds_the_librarys_network_and_is_adopted() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    assert_eq!(ok(addr, "GET", "/api/local", "")["status"], "idle");
    // From the current structure: curves 2 and 5 removed.
    let n = curves.len();
    let from: Vec<usize> = (0..n).filter(|c| ![2, 5].contains(c)).collect();
    post_set(addr, &from);
    let started = ok(addr, "POST", "/api/local", "{\"budget\":0.6}");
    assert_eq!(started["status"], "running");
    assert_eq!(started["budget"], 0.6);
    let done = wait(addr, "/api/local");
    assert_eq!(done["status"], "done", "{done}");
    assert_eq!(done["from"], serde_json::json!(from));

    let (network, _) = build_network(&curves, &build).unwrap();
    let analyzer = Analyzer::new(network, StabilityParams::default()).unwrap();
    let params = LocalParams::new(Budget::Fraction(0.6));
    let expected = local_search(&analyzer, &params, None, &from, &Cancel::never()).unwrap();
    let best = &done["result"]["best"];
    assert_eq!(curves_of(best), expected.best.curves);
    let lambda = best["lambda"].as_f64().unwrap();
    assert!((lambda - expected.best.lambda).abs() <= 1e-9 * expected.best.lambda.abs());

    // Adopting it makes it current, with analyze's λ of that set.
    let adopted = ok(addr, "POST", "/api/local/adopt", "");
    assert_eq!(curves_of(&adopted), expected.best.curves);
    assert_close(
        &adopted,
        analyze_lambda(&curves, &build, &expected.best.curves),
    );
    assert_eq!(
        curves_of(&ok(addr, "GET", "/api/state", "")),
        expected.best.curves
    );
}

#[test]
fn constraints_set_for_the_session_are_honoured_and_their_margins_given() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    let none = ok(addr, "GET", "/api/constraints", "");
    assert!(none["current"].is_null(), "{none}");
    assert!(ok(addr, "GET", "/api/state", "")["constraints"].is_null());

    // Curves 0 and 1 kept or removed together, at least 4 curves, one structure.
    let set = ok(
        addr,
        "POST",
        "/api/constraints",
        r#"{"groups":[[0,1]],"min_curves":4,"connected":true}"#,
    );
    assert_eq!(set["constraints"]["min_curves"], 4);
    assert_eq!(
        set["constraints"]["groups"][0]["curves"],
        serde_json::json!([0, 1])
    );
    let m = &set["current"];
    assert_eq!(m["met"], true, "{m}");
    assert_eq!(m["margins"]["min_curves"]["value"], curves.len() as f64);
    assert!(m["margins"].get("budget").is_none(), "no search yet: {m}");
    // A state that splits the group and has too few curves says so.
    let edited = post_set(addr, &[0, 2, 3]);
    let c = &edited["constraints"];
    assert_eq!(c["met"], false, "{c}");
    assert_eq!(c["margins"]["groups"]["met"], false);
    assert_eq!(c["margins"]["min_curves"]["met"], false);
    assert_eq!(ok(addr, "GET", "/api/state", "")["constraints"], *c);

    // The greedy honours them: every iteration keeps 0 and 1 together and 4 curves or more.
    ok(addr, "POST", "/api/greedy", "{\"budget\":0.5}");
    let done = wait(addr, "/api/greedy");
    assert!(
        ["done"].contains(&done["status"].as_str().unwrap()),
        "{done}"
    );
    let listed = ok(addr, "GET", "/api/greedy/iterations", "");
    let its = listed["iterations"].as_array().unwrap();
    for it in its {
        let kept = curves_of(it);
        assert_eq!(kept.contains(&0), kept.contains(&1), "{kept:?}");
        assert!(kept.len() >= 4, "{kept:?}");
    }
    // So does the local search, from the greedy's last network (no single curve meets the
    // constraints); its best network meets every margin, the budget's now too.
    let last = its.len() - 1;
    ok(
        addr,
        "POST",
        "/api/greedy/step",
        &format!("{{\"iteration\":{last}}}"),
    );
    ok(addr, "POST", "/api/local", "{\"budget\":0.5}");
    let done = wait(addr, "/api/local");
    assert_eq!(done["status"], "done", "{done}");
    let adopted = ok(addr, "POST", "/api/local/adopt", "");
    let kept = curves_of(&adopted);
    assert_eq!(kept.contains(&0), kept.contains(&1), "{kept:?}");
    assert!(kept.len() >= 4, "{kept:?}");
    assert_eq!(adopted["constraints"]["met"], true, "{adopted}");
    assert!(adopted["constraints"]["margins"]["budget"]["met"] == true);

    // Groups as the text of a groups file; an empty object clears them.
    let text = ok(
        addr,
        "POST",
        "/api/constraints",
        r#"{"groups":"pair: 2 3\n"}"#,
    );
    assert_eq!(text["constraints"]["groups"][0]["name"], "pair");
    let cleared = ok(addr, "POST", "/api/constraints", "{}");
    assert!(cleared["current"].is_null(), "{cleared}");
    assert!(ok(addr, "GET", "/api/state", "")["constraints"].is_null());
}

/// Curves to keep longer than the budget leave nothing to search: the answer says so at once,
/// by how much, and what helps (a larger budget or fewer curves), not to start elsewhere.
#[test]
fn a_keep_list_over_the_budget_is_refused_with_advice_that_helps() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    let body = "{\"budget\":0.1,\"keep\":[0,1,2,3,4,5]}";
    let (status, text) = request(addr, "POST", "/api/local", body.as_bytes());
    assert_eq!(status, 422, "{text}");
    let error = serde_json::from_str::<Value>(&text).unwrap()["error"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(
        error.contains("the curves to keep (0, 1, 2, 3, 4, 5) are ")
            && error.contains("over the budget")
            && error.contains("(budget 0.1)"),
        "{error}"
    );
    assert!(
        error.contains("raise budget to at least 0.")
            && error.contains("or keep fewer curves (keep)"),
        "{error}"
    );
    assert!(!error.contains("start it again"), "{error}");
    // The advice holds: at the budget it names, the search runs.
    let least: f64 = error
        .split("to at least ")
        .nth(1)
        .and_then(|t| t.split_whitespace().next())
        .and_then(|t| t.parse().ok())
        .unwrap();
    let body = format!("{{\"budget\":{least},\"keep\":[0,1,2,3,4,5]}}");
    ok(addr, "POST", "/api/local", &body);
    let done = wait(addr, "/api/local");
    assert_eq!(done["status"], "done", "{done}");
}

#[test]
fn bad_local_search_and_constraint_requests_get_a_4xx_and_leave_the_state_alone() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    post_set(addr, &[0, 1, 2, 3, 4, 5]);
    let before = ok(addr, "GET", "/api/state", "");
    let huge = format!("{{\"groups\":\"{}\"}}", "a: 0 1\\n".repeat(200_000));
    let huge_path = format!("{{\"path\":\"{}\"}}", "x/".repeat(600_000));
    let cases: &[(&str, &str, &str, u16, &str)] = &[
        ("POST", "/api/constraints", &huge, 413, "length limit"),
        ("POST", "/api/run", &huge_path, 413, "length limit"),
        ("POST", "/api/local/cancel", "", 409, "no local search"),
        (
            "POST",
            "/api/local/adopt",
            "",
            409,
            "no local search result",
        ),
        ("POST", "/api/local", "{\"budget\":2}", 422, "budget"),
        ("POST", "/api/local", "{\"budget\":0}", 422, "budget"),
        (
            "POST",
            "/api/local",
            "{\"budget\":0.5,\"keep\":[99]}",
            422,
            "99",
        ),
        (
            "POST",
            "/api/local",
            "{\"budget\":\"half\"}",
            400,
            "malformed",
        ),
        (
            "POST",
            "/api/local",
            "{\"budget\":0.5,\"max_removals\":2}",
            400,
            "max_removals",
        ),
        ("POST", "/api/local", "[0.5]", 400, "malformed"),
        ("GET", "/api/local/adopt", "", 405, "use POST"),
        (
            "POST",
            "/api/constraints",
            "{\"spin\":1}",
            400,
            "unknown field",
        ),
        (
            "POST",
            "/api/constraints",
            "{\"connected\":",
            400,
            "malformed",
        ),
        (
            "POST",
            "/api/constraints",
            "{\"symmetry\":\"spin\"}",
            422,
            "unknown symmetry",
        ),
        (
            "POST",
            "/api/constraints",
            "{\"symmetry\":\"rotate:1\"}",
            422,
            "at least 2",
        ),
        (
            "POST",
            "/api/constraints",
            "{\"min_curves\":0}",
            422,
            "min_curves must be at least 1",
        ),
        (
            "POST",
            "/api/constraints",
            "{\"groups\":[[0,99]]}",
            422,
            "99",
        ),
        (
            "POST",
            "/api/constraints",
            "{\"groups\":\"a: 0 x\"}",
            422,
            "groups:1",
        ),
        (
            "POST",
            "/api/constraints",
            "{\"max_gap\":100}",
            422,
            "serve with --mesh",
        ),
        (
            "POST",
            "/api/constraints",
            "{\"max_deviation\":-1}",
            422,
            "max_deviation must be a positive",
        ),
        (
            "POST",
            "/api/constraints",
            "{\"min_curves\":100}",
            422,
            "cannot be met",
        ),
        ("PUT", "/api/constraints", "{}", 405, "use GET, POST"),
    ];
    for &(method, path, body, status, says) in cases {
        assert_refused(addr, method, path, body, status, says);
    }
    // Constraints a search's budget cannot meet: refused when the search starts.
    ok(addr, "POST", "/api/constraints", "{\"min_curves\":7}");
    for path in ["/api/greedy", "/api/local"] {
        assert_refused(addr, "POST", path, "{\"budget\":0.2}", 422, "cannot be met");
    }
    assert_eq!(ok(addr, "GET", "/api/greedy", "")["status"], "idle");
    assert_eq!(ok(addr, "GET", "/api/local", "")["status"], "idle");
    // A refused setting leaves the earlier one in force.
    let (status, _) = request(addr, "POST", "/api/constraints", b"{\"min_curves\":0}");
    assert_eq!(status, 422);
    let kept = ok(addr, "GET", "/api/constraints", "");
    assert_eq!(kept["constraints"]["min_curves"], 7);
    let after = ok(addr, "GET", "/api/state", "");
    assert_eq!(after["curves"], before["curves"]);
    assert_eq!(after["lambda"], before["lambda"]);
}

#[test]
fn the_mode_carries_the_gravity_deflection_and_so_does_the_page() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    post_set(addr, &[0, 1, 2, 3, 4, 6, 7]);
    let mode = ok(addr, "GET", "/api/mode", "");
    let g = &mode["gravity"];
    let coords = mode["displacement"].as_array().unwrap().len();
    let disp: Vec<f64> = g["displacement"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(disp.len(), coords);
    // The library's gravity deflection at the served equilibrium.
    let (network, _) = build_network(&curves, &build).unwrap();
    let analyzer = Analyzer::new(network, StabilityParams::default()).unwrap();
    let u: Vec<f64> = mode["displacement"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let kept = curves_of(&mode);
    let expected =
        curvenet::report::viewer::gravity_deflection(&analyzer, &kept, &u).expect("stable");
    let largest = expected
        .chunks(3)
        .map(|c| (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt())
        .fold(0.0f64, f64::max);
    assert!(largest > 0.0);
    let served = g["max_displacement"].as_f64().unwrap();
    assert!(
        (served - largest).abs() <= 1e-9 * largest,
        "{served} {largest}"
    );
    let (_, page) = request(addr, "GET", "/", b"");
    assert!(
        page.contains("\"gravity\":{\"full\":["),
        "the live structure has it"
    );
}

#[test]
fn concurrent_clients_setting_constraints_and_searching_see_whole_states() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    let answers: Vec<(u16, String)> = std::thread::scope(|s| {
        let handles: Vec<_> = (1..=6)
            .map(|k| {
                s.spawn(move || match k % 3 {
                    0 => request(addr, "POST", "/api/local", b"{\"budget\":0.7}"),
                    1 => {
                        let body = format!("{{\"min_curves\":{k}}}");
                        request(addr, "POST", "/api/constraints", body.as_bytes())
                    }
                    _ => request(
                        addr,
                        "POST",
                        "/api/toggle",
                        format!("{{\"curve\":{k}}}").as_bytes(),
                    ),
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let mut searches = 0;
    for (status, body) in &answers {
        match status {
            200 => searches += usize::from(body.contains("\"from\"")),
            409 => assert!(body.contains("already computing"), "{body}"),
            _ => panic!("{status}: {body}"),
        }
    }
    assert!(searches >= 1);
    wait(addr, "/api/local");
    // The constraints in force are one of those set, and the state's margins are theirs.
    let c = ok(addr, "GET", "/api/constraints", "");
    let k = c["constraints"]["min_curves"].as_u64().unwrap();
    assert!([1, 4].contains(&k), "{c}");
    let state = ok(addr, "GET", "/api/state", "");
    let m = &state["constraints"]["margins"]["min_curves"];
    assert_eq!(m["limit"], k as f64);
    assert_eq!(m["value"], curves_of(&state).len() as f64);
    assert_eq!(c["current"], state["constraints"]);
}

#[test]
fn a_long_local_search_can_be_cancelled_and_does_not_block_the_other_requests() {
    let ex = curvenet::paper::load_embedded("tower", curvenet::rod::Supports::default()).unwrap();
    let addr = serve(&ex.curves, &ex.build);
    let started = ok(addr, "POST", "/api/local", "{\"budget\":0.3}");
    assert_eq!(started["status"], "running");
    assert_refused(
        addr,
        "POST",
        "/api/local",
        "{\"budget\":0.3}",
        409,
        "already computing",
    );
    // Reads are answered while it runs.
    let t = Instant::now();
    ok(addr, "GET", "/api/state", "");
    assert!(t.elapsed() < Duration::from_secs(5));
    let cancelled = ok(addr, "POST", "/api/local/cancel", "");
    assert_eq!(cancelled["status"], "running");
    let end = wait(addr, "/api/local");
    assert_eq!(end["status"], "cancelled", "{end}");
    assert!(end["elapsed_ms"].as_f64().unwrap() < 60_000.0, "{end}");
    // A run folder cannot be loaded from a server started without a folder to load from.
    assert_refused(
        addr,
        "POST",
        "/api/run",
        "{\"path\":\".\"}",
        403,
        "loads no run folder",
    );
}
