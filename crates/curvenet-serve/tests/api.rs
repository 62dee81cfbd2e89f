//! The HTTP API on a real socket: `λ` of every state equal to what `curvenet analyze --remove`
//! computes for the same set (`pipeline::analyze`), every bad request a 4xx with a JSON
//! message and the state untouched, concurrent clients each answered for their own set.

mod common;

use common::{
    analyze_lambda, assert_close, assert_refused, curves_of, dome, ok, post_set, random_set,
    request, serve,
};
use curvenet::rng::SplitMix64;
use curvenet::rod::Supports;
use serde_json::Value;

#[test]
fn the_tower_answers_with_the_lambda_of_analyze() {
    let ex = curvenet::paper::load_embedded("tower", Supports::default()).unwrap();
    let addr = serve(&ex.curves, &ex.build);
    let n = ex.curves.len();
    let all: Vec<usize> = (0..n).collect();

    let state = ok(addr, "GET", "/api/state", "");
    assert_eq!(curves_of(&state), all);
    assert_close(&state, analyze_lambda(&ex.curves, &ex.build, &all));
    for key in ["zero_modes", "negative_modes", "length", "status"] {
        assert!(!state[key].is_null(), "{key} in {state}");
    }

    let mut rng = SplitMix64::new(29);
    let kept = random_set(&mut rng, n, n - 3);
    let set = post_set(addr, &kept);
    assert_eq!(curves_of(&set), kept);
    assert!(set["elapsed_ms"].as_f64().unwrap() > 0.0);
    assert_close(&set, analyze_lambda(&ex.curves, &ex.build, &kept));

    // Toggling one removed curve back: analyze's λ of that set too.
    let back = (0..n).find(|c| !kept.contains(c)).unwrap();
    let toggled = ok(
        addr,
        "POST",
        "/api/toggle",
        &format!("{{\"curve\":{back}}}"),
    );
    let mut expected: Vec<usize> = kept.clone();
    expected.push(back);
    expected.sort_unstable();
    assert_eq!(curves_of(&toggled), expected);
    assert_close(&toggled, analyze_lambda(&ex.curves, &ex.build, &expected));
    assert_eq!(
        ok(addr, "GET", "/api/state", "")["lambda"],
        toggled["lambda"]
    );
}

#[test]
fn random_sets_of_a_small_network_answer_with_the_lambda_of_analyze() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    let n = curves.len();
    let mut rng = SplitMix64::new(7);
    for removed in [1, 2, 3] {
        let kept = random_set(&mut rng, n, n - removed);
        let set = post_set(addr, &kept);
        assert_eq!(curves_of(&set), kept);
        assert_close(&set, analyze_lambda(&curves, &build, &kept));
    }
    // The mode and the geometry, one entry per coordinate.
    let network = ok(addr, "GET", "/api/network", "");
    let coords = network["positions"].as_array().unwrap().len();
    assert_eq!(network["curves"].as_array().unwrap().len(), n);
    let mode = ok(addr, "GET", "/api/mode", "");
    assert_eq!(mode["mode"].as_array().unwrap().len(), coords);
    assert_eq!(mode["displacement"].as_array().unwrap().len(), coords);
    let norm: f64 = mode["mode"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap().powi(2))
        .sum();
    assert!((norm - 1.0).abs() < 1e-9, "‖mode‖² = {norm}");
}

#[test]
fn bad_requests_get_a_4xx_with_a_message_and_leave_the_state_alone() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    let before = ok(addr, "GET", "/api/state", "");
    let huge = format!("{{\"curves\":[{}0]}}", "0,".repeat(600_000));
    let cases: &[(&str, &str, &str, u16, &str)] = &[
        ("POST", "/api/set", "{\"curves\":[1,", 400, "malformed JSON"),
        ("POST", "/api/set", "", 400, "malformed JSON"),
        (
            "POST",
            "/api/set",
            "{\"curves\":\"all\"}",
            400,
            "malformed JSON",
        ),
        (
            "POST",
            "/api/set",
            "{\"curves\":[-1]}",
            400,
            "malformed JSON",
        ),
        (
            "POST",
            "/api/set",
            "{\"curves\":[1.5]}",
            400,
            "malformed JSON",
        ),
        (
            "POST",
            "/api/set",
            "{\"curves\":[0],\"x\":1}",
            400,
            "unknown field",
        ),
        (
            "POST",
            "/api/set",
            "{\"curves\":[0,999]}",
            422,
            "unknown curve 999",
        ),
        ("POST", "/api/set", "{\"curves\":[]}", 422, "no curves"),
        (
            "POST",
            "/api/toggle",
            "{\"curve\":8}",
            422,
            "unknown curve 8",
        ),
        (
            "POST",
            "/api/toggle",
            "{\"curve\":1e400}",
            400,
            "malformed JSON",
        ),
        ("POST", "/api/toggle", "[1]", 400, "malformed JSON"),
        // A key given twice: serde_json would keep the last silently.
        (
            "POST",
            "/api/toggle",
            "{\"curve\":1,\"curve\":2}",
            400,
            "duplicate key \"curve\" (first at line 1)",
        ),
        (
            "POST",
            "/api/set",
            "{\"curves\":[0,1],\n \"curves\":[2]}",
            400,
            "duplicate key \"curves\" (first at line 1): give each key once (line 2, column 2)",
        ),
        (
            "POST",
            "/api/constraints",
            "{\"max_gap\":100,\"connected\":true,\"max_gap\":900}",
            400,
            "duplicate key \"max_gap\"",
        ),
        ("POST", "/api/set", &huge, 413, "length limit"),
        ("GET", "/api/nothing", "", 404, "no such endpoint"),
        ("GET", "/../../etc/passwd", "", 404, "no such endpoint"),
        (
            "GET",
            "/api/%2e%2e/%2e%2e/etc/passwd",
            "",
            404,
            "no such endpoint",
        ),
        ("GET", "/api/set", "", 405, "use POST"),
        ("POST", "/api/state", "{}", 405, "use GET"),
    ];
    for &(method, path, body, status, says) in cases {
        assert_refused(addr, method, path, body, status, says);
    }
    // A whole network removed except what toggling the last curve would leave empty.
    ok(addr, "POST", "/api/set", "{\"curves\":[3]}");
    let (got, text) = request(addr, "POST", "/api/toggle", b"{\"curve\":3}");
    assert_eq!(got, 422, "{text}");
    assert_eq!(curves_of(&ok(addr, "GET", "/api/state", "")), vec![3]);
    // Back to the start: the same numbers as before.
    let all: Vec<usize> = (0..curves.len()).collect();
    let again = post_set(addr, &all);
    assert_eq!(again["lambda"], before["lambda"]);
}

#[test]
fn concurrent_clients_each_get_the_state_of_their_own_set() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    let n = curves.len();
    let mut rng = SplitMix64::new(11);
    let sets: Vec<Vec<usize>> = (0..6)
        .map(|i| random_set(&mut rng, n, n - 1 - i % 3))
        .collect();
    let answers: Vec<Value> = std::thread::scope(|s| {
        let handles: Vec<_> = sets
            .iter()
            .map(|set| s.spawn(move || post_set(addr, set)))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for (set, answer) in sets.iter().zip(&answers) {
        assert_eq!(&curves_of(answer), set);
        assert_close(answer, analyze_lambda(&curves, &build, set));
    }
    // The final state is whole: one of the sets, with that set's λ.
    let last = ok(addr, "GET", "/api/state", "");
    let i = sets.iter().position(|s| *s == curves_of(&last)).unwrap();
    assert_eq!(last["lambda"], answers[i]["lambda"]);
}

#[test]
fn the_page_is_the_viewer_in_app_mode_and_loads_nothing_from_outside() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    ok(addr, "POST", "/api/toggle", "{\"curve\":5}");
    let (status, head, page) = common::request_full(addr, "GET", "/", b"");
    assert_eq!(status, 200, "{page}");
    assert!(head.to_ascii_lowercase().contains("text/html"), "{head}");
    assert!(page.contains("<title>curvenet serve: network</title>"));
    assert!(page.contains("\"app\":true"));
    assert!(
        page.contains("api/toggle"),
        "the app's script is in the page"
    );
    assert!(!page.contains("http://") && !page.contains("https://"));
    // The live structure embedded is the current one.
    let data = page
        .split("<script id=\"curvenet-data\" type=\"application/json\">")
        .nth(1)
        .and_then(|rest| rest.split("</script>").next())
        .expect("the page's data");
    let data: Value = serde_json::from_str(&data.replace("<\\/", "</")).unwrap();
    let live = &data["iterations"][0];
    let state = ok(addr, "GET", "/api/state", "");
    assert_eq!(live["curves"], state["curves"]);
    assert_eq!(live["lambda"], state["lambda"]);
    assert_eq!(data["rods"].as_array().unwrap().len(), curves.len());
    let coords = data["iterations"][0]["mode"]["full"]
        .as_array()
        .unwrap()
        .len();
    assert_eq!(
        coords,
        ok(addr, "GET", "/api/mode", "")["mode"]
            .as_array()
            .unwrap()
            .len()
    );
}

/// Every route answers a method it lacks with 405, naming the methods it allows (in the
/// message and the `Allow` header), and does not answer 405 to those (a malformed body then
/// gets a 4xx of its own).
#[test]
fn every_route_names_the_methods_it_allows() {
    let (curves, build) = dome();
    let addr = serve(&curves, &build);
    for &(route, allowed) in curvenet_serve::api::ENDPOINTS {
        let path = route.replace("{id}", "0");
        let methods: Vec<&str> = allowed.split(", ").collect();
        for method in ["GET", "POST", "PUT", "DELETE", "PATCH"] {
            let (status, head, body) = common::request_full(addr, method, &path, b"[");
            if methods.contains(&method) {
                assert_ne!(status, 405, "{method} {path}: {body}");
                continue;
            }
            assert_eq!(status, 405, "{method} {path}: {body}");
            assert!(
                body.contains(&format!("use {allowed}\"")),
                "{method} {path}: {body}"
            );
            let allow = head.lines().find_map(|l| {
                l.to_ascii_lowercase()
                    .strip_prefix("allow: ")
                    .map(str::to_owned)
            });
            assert_eq!(
                allow.as_deref(),
                Some(allowed.to_ascii_lowercase().as_str()),
                "{method} {path}: {head}"
            );
        }
    }
}
