//! Drawing over HTTP: curves added (a geodesic from a point and a direction, a curve through
//! points), moved and deleted, each edit rebuilding the network; undo and redo; the design
//! saved (`GET /api/export?format=json` and `format=surface`) and analysed again by the
//! application layer as `curvenet analyze --curves saved.json --mesh surface.obj` reads it:
//! the same `λ_eq` to 1e-6 relative. Every bad request gets a 4xx with a message.

mod common;

use common::design::{
    analyzed_saved, close, close_to, lambda, physical_design, save, saved_inputs, serve,
    serve_inputs,
};
use common::{assert_refused, ok, scratch};
use curvenet::app::ModelOptions;
use serde_json::{Value, json};

/// A point in the middle of curve `c` of the design and the unit tangent there.
fn middle(curves: &Value, c: usize) -> ([f64; 3], [f64; 3]) {
    let pts = curves["curves"][c]["points"].as_array().unwrap();
    let p = |i: usize| -> [f64; 3] {
        let a = pts[i].as_array().unwrap();
        [0, 1, 2].map(|k| a[k].as_f64().unwrap())
    };
    let m = pts.len() / 2;
    let (a, b) = (p(m), p(m + 1));
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    (a, d.map(|x| x / n))
}

#[test]
fn drawn_curves_rebuild_the_network_as_analyze_reads_the_saved_design() {
    let addr = serve(6, 3);
    let dir = scratch("draw");
    let before = ok(addr, "GET", "/api/state", "");
    let curves = ok(addr, "GET", "/api/curves", "");
    assert_eq!(curves["editable"], true);
    assert_eq!(curves["curves"].as_array().unwrap().len(), 6);

    // A geodesic from the middle of curve 0, across it.
    let (p, t) = middle(&curves, 0);
    let across = [-t[1], t[0], 0.0];
    let preview = ok(
        addr,
        "POST",
        "/api/curves/preview",
        &json!({"geodesic": {"point": p, "direction": across}}).to_string(),
    );
    assert!(preview["points"].as_array().unwrap().len() >= 2);
    let added = ok(
        addr,
        "POST",
        "/api/curves",
        &json!({"geodesic": {"point": p, "direction": across}}).to_string(),
    );
    assert_eq!(added["curve"], 6);
    assert_eq!(added["curve_count"], 7);
    assert!(
        !added["joints"].as_array().unwrap().is_empty(),
        "a curve drawn from a curve meets it: {added}"
    );
    assert_ne!(lambda(&added), lambda(&before), "λ follows the new curve");
    close(
        lambda(&added),
        analyzed_saved(addr, &dir),
        "the added geodesic",
    );

    // A curve through three points of curves 1, 2 and 3.
    let curves = ok(addr, "GET", "/api/curves", "");
    let points: Vec<[f64; 3]> = (1..4).map(|c| middle(&curves, c).0).collect();
    let through = ok(
        addr,
        "POST",
        "/api/curves",
        &json!({ "through": points }).to_string(),
    );
    assert_eq!(through["curve"], 7);
    close(
        lambda(&through),
        analyzed_saved(addr, &dir),
        "the curve through points",
    );

    // Moved by its family of moves (a drag's coefficients), then deleted: λ comes back.
    let drag = ok(
        addr,
        "POST",
        "/api/curves/preview",
        &json!({"drag": {"curve": 7, "from": points[1], "to": [points[1][0] + 60.0, points[1][1], points[1][2]]}})
            .to_string(),
    );
    let params = drag["params"].clone();
    assert!(
        params
            .as_array()
            .unwrap()
            .iter()
            .any(|a| a.as_f64() != Some(0.0)),
        "{drag}"
    );
    let moved = ok(
        addr,
        "POST",
        "/api/curves/7/move",
        &json!({ "params": params }).to_string(),
    );
    assert_eq!(moved["curve"], 7);
    close(
        lambda(&moved),
        analyzed_saved(addr, &dir),
        "the moved curve",
    );
    let deleted = ok(addr, "DELETE", "/api/curves/7", "");
    assert_eq!(deleted["curve_count"], 7);
    close(
        lambda(&deleted),
        lambda(&added),
        "deleting the curve through points",
    );
    let deleted = ok(addr, "DELETE", "/api/curves/6", "");
    close(lambda(&deleted), lambda(&before), "deleting the geodesic");

    // Undo walks back through the edits, redo forward again.
    let u = ok(addr, "POST", "/api/curves/undo", "");
    assert_eq!(u["curve_count"], 7);
    close(
        lambda(&u),
        lambda(&added),
        "undoing the geodesic's deletion",
    );
    let u = ok(addr, "POST", "/api/curves/undo", "");
    close(lambda(&u), lambda(&moved), "undoing the deletion");
    let r = ok(addr, "POST", "/api/curves/redo", "");
    close(lambda(&r), lambda(&added), "redoing the deletion");
    let u = ok(addr, "POST", "/api/curves/undo", "");
    let u2 = ok(addr, "POST", "/api/curves/undo", "");
    close(lambda(&u), lambda(&moved), "undo after redo");
    close(lambda(&u2), lambda(&through), "undoing the move");
}

#[test]
fn every_bad_drawing_request_gets_a_4xx_with_a_message() {
    let addr = serve(5, 7);
    let curves = ok(addr, "GET", "/api/curves", "");
    let (p, t) = middle(&curves, 0);
    let far = [p[0], p[1], p[2] + 1e5];
    let add = |body: Value, status: u16, says: &str| {
        assert_refused(addr, "POST", "/api/curves", &body.to_string(), status, says);
    };
    add(
        json!({"geodesic": {"point": far, "direction": t}}),
        422,
        "from the surface",
    );
    add(json!({"through": [p, far]}), 422, "point 1 lies");
    add(json!({"through": [p]}), 422, "at least two distinct points");
    add(json!({"through": []}), 422, "at least two distinct points");
    add(
        json!({"through": [p, p]}),
        422,
        "at least two distinct points",
    );
    add(
        json!({"geodesic": {"point": p, "direction": [0.0, 0.0, 0.0]}}),
        422,
        "direction",
    );
    // From a curve's start on the boundary, heading out of the surface.
    let pts = curves["curves"][0]["points"].as_array().unwrap();
    let q = |i: usize| -> [f64; 3] { [0, 1, 2].map(|k| pts[i][k].as_f64().unwrap()) };
    let (a, b) = (q(0), q(1));
    let out = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    add(
        json!({"geodesic": {"point": a, "direction": out}}),
        422,
        "leaves the surface at once",
    );
    add(
        json!({"geodesic": {"point": p, "direction": t}, "through": [p, far]}),
        400,
        "exactly one",
    );
    add(json!({}), 400, "exactly one");
    add(json!({"circle": 1}), 400, "unknown field");
    let many: Vec<[f64; 3]> = (0..1001).map(|_| p).collect();
    add(json!({ "through": many }), 422, "at most 1000 points");
    let huge = format!("{{\"through\": [{}]}}", vec!["[1,2,3]"; 200_000].join(","));
    assert_refused(addr, "POST", "/api/curves", &huge, 413, "");
    assert_refused(
        addr,
        "DELETE",
        "/api/curves/99",
        "",
        422,
        "unknown curve 99",
    );
    assert_refused(addr, "DELETE", "/api/curves/x", "", 400, "not a curve id");
    assert_refused(
        addr,
        "POST",
        "/api/curves/0/move",
        &json!({"params": [1.0]}).to_string(),
        422,
        "coefficients",
    );
    let dim = curves["curves"][0]["move_dimension"].as_u64().unwrap() as usize;
    let beyond = vec![1e6; dim];
    assert_refused(
        addr,
        "POST",
        "/api/curves/0/move",
        &json!({ "params": beyond }).to_string(),
        422,
        "beyond its limits",
    );
    assert_refused(addr, "POST", "/api/curves/undo", "", 409, "nothing to undo");
    assert_refused(addr, "POST", "/api/curves/redo", "", 409, "nothing to redo");
    // Nothing refused changed the design.
    let after = ok(addr, "GET", "/api/curves", "");
    assert_eq!(after["curves"], curves["curves"]);
}

/// A design in the physical mode, its curves with their own materials, sections, rest shapes
/// and end supports, drawn on, saved and opened by a second server (`curvenet serve --curves
/// saved.json --mesh surface.obj`, no other option): the same `λ_eq` and physical numbers.
#[test]
fn a_saved_design_reloads_to_the_same_analysis() {
    let dir = scratch("reload");
    // The dome's curves, given units and per-curve specs.
    let (design, m) = physical_design(serve(6, 3), &dir, |curves| {
        curves[0]["material"] = json!("aluminium");
        curves[1]["rest"] = json!("pre-bent");
        curves[2]["supports"] = json!({"start": "pinned"});
        curves[3]["section"] = json!({"outer_diameter": "60mm", "wall": "4mm"});
        curves[4]["material"] = json!({"preset": "timber", "young": "9GPa", "poisson": 0.3});
    });

    let first = serve_inputs(saved_inputs(design, m), ModelOptions::default());
    let state = ok(first, "GET", "/api/state", "");
    assert!(state["physical"].is_object(), "the physical mode: {state}");
    let drawn = ok(first, "GET", "/api/curves", "");
    let (p, t) = middle(&drawn, 0);
    let added = ok(
        first,
        "POST",
        "/api/curves",
        &json!({"geodesic": {"point": p, "direction": [-t[1], t[0], 0.0]}}).to_string(),
    );
    assert_eq!(added["curve_count"], 7);
    let before = ok(first, "GET", "/api/state", "");

    let saved = dir.join("again");
    std::fs::create_dir_all(&saved).unwrap();
    let (c, m) = save(first, &saved);
    let text = std::fs::read_to_string(&c).unwrap();
    for says in [
        "\"units\": \"mm\"",
        "\"edge_length\": 200",
        "\"aluminium\"",
        "\"pre-bent\"",
        "\"pinned\"",
        "\"wall\":\"0.004m\"",
        "\"young\":\"9000000000Pa\"",
    ] {
        assert!(text.contains(says), "the saved design says {says}: {text}");
    }
    let second = serve_inputs(saved_inputs(c, m), ModelOptions::default());
    let after = ok(second, "GET", "/api/state", "");
    assert_eq!(after["curves"], before["curves"]);
    close_to(lambda(&after), lambda(&before), 1e-9, "λ_eq reloaded");
    for key in [
        "mass_kg",
        "mu_min",
        "first_frequency_hz",
        "self_weight_max_deflection",
    ] {
        let (a, b) = (&after["physical"][key], &before["physical"][key]);
        close_to(
            a.as_f64().unwrap_or_else(|| panic!("{key}: {a}")),
            b.as_f64().unwrap(),
            1e-9,
            key,
        );
    }
}

/// A design served with pinned supports (`--supports pinned`) saves each open end pinned: the
/// saved design reloads to the same `λ_eq` without the option.
#[test]
fn a_design_with_pinned_supports_reloads_to_the_same_lambda() {
    use curvenet::app::{CurveSource, InputSpec};
    let dir = scratch("reload-pinned");
    let input = InputSpec {
        edge_length: Some(common::design::H),
        supports: Some(curvenet::rod::Supports::Pinned),
        ..InputSpec::new(CurveSource::Geodesics {
            surface: "dome".into(),
            count: 6,
            seed: 3,
        })
    };
    let first = serve_inputs(input, ModelOptions::default());
    let before = ok(first, "GET", "/api/state", "");
    let (c, m) = save(first, &dir);
    assert!(
        std::fs::read_to_string(&c)
            .unwrap()
            .contains("\"supports\": \"pinned\"")
    );
    let second = serve_inputs(saved_inputs(c, m), ModelOptions::default());
    let after = ok(second, "GET", "/api/state", "");
    close_to(lambda(&after), lambda(&before), 1e-9, "λ_eq reloaded");
}
