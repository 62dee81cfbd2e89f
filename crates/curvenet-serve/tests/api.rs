//! The HTTP API on a real socket: `λ` of every state equal to what `curvenet analyze --remove`
//! computes for the same set (`pipeline::analyze`), every bad request a 4xx with a JSON
//! message and the state untouched, concurrent clients each answered for their own set.

use curvenet::io::Polyline;
use curvenet::network::{BuildParams, build_network};
use curvenet::pipeline;
use curvenet::rng::SplitMix64;
use curvenet::rod::Supports;
use curvenet::stability::{Analyzer, StabilityParams};
use curvenet_serve::{Design, Server};
use serde_json::Value;
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};

/// A server for `curves` built with `build`, all curves kept, listening on a free port.
fn serve(curves: &[Polyline], build: &BuildParams) -> SocketAddr {
    let (network, _) = build_network(curves, build).unwrap();
    let analyzer = Analyzer::new(network, StabilityParams::default()).unwrap();
    let all: Vec<usize> = (0..curves.len()).collect();
    let design = Design::new(analyzer, &all).unwrap();
    let server = Server::bind("127.0.0.1:0".parse().unwrap()).unwrap();
    let addr = server.local_addr().unwrap();
    std::thread::spawn(move || server.run(design));
    addr
}

/// One HTTP/1.1 request; the status and the body. The body is written on a thread of its own
/// while the answer is read (a server refusing a huge body answers before reading it all).
fn request(addr: SocketAddr, method: &str, path: &str, body: &[u8]) -> (u16, String) {
    let mut stream = TcpStream::connect(addr).unwrap();
    let head = format!(
        "{method} {path} HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\n\
         Content-Length: {}\r\nConnection: close\r\n\r\n",
        body.len()
    );
    stream.write_all(head.as_bytes()).unwrap();
    let mut writer = stream.try_clone().unwrap();
    let body = body.to_vec();
    let sent = std::thread::spawn(move || {
        // The server may close before reading everything it refuses.
        let _ = writer.write_all(&body);
    });
    let mut answer = Vec::new();
    let _ = stream.read_to_end(&mut answer);
    sent.join().unwrap();
    let text = String::from_utf8(answer).unwrap();
    let (head, body) = text.split_once("\r\n\r\n").expect("an HTTP answer");
    let status = head.split(' ').nth(1).unwrap().parse().unwrap();
    (status, body.to_string())
}

/// A request whose answer must be 200 with a JSON body.
fn ok(addr: SocketAddr, method: &str, path: &str, body: &str) -> Value {
    let (status, text) = request(addr, method, path, body.as_bytes());
    assert_eq!(status, 200, "{method} {path} {body}: {text}");
    serde_json::from_str(&text).unwrap()
}

fn curves_of(v: &Value) -> Vec<usize> {
    v["curves"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_u64().unwrap() as usize)
        .collect()
}

/// `λ` that `curvenet analyze --remove` gives the set `kept`.
fn analyze_lambda(curves: &[Polyline], build: &BuildParams, kept: &[usize]) -> f64 {
    let removed: Vec<usize> = (0..curves.len()).filter(|c| !kept.contains(c)).collect();
    let out = pipeline::analyze(
        curves,
        build,
        &StabilityParams::default(),
        &removed,
        Vec::new(),
    )
    .unwrap();
    out.report.lambda
}

fn assert_close(served: &Value, expected: f64) {
    let lambda = served["lambda"].as_f64().unwrap();
    let rel = (lambda - expected).abs() / expected.abs().max(f64::MIN_POSITIVE);
    assert!(rel <= 1e-6, "served λ {lambda:e}, analyze {expected:e}");
}

/// The small dome: 8 arcs, about 300 vertices.
fn dome() -> (Vec<Polyline>, BuildParams) {
    let s = curvenet::builtin::dome_arcs(2000.0, 700.0, 2, 4);
    let build = BuildParams {
        edge_length: 100.0,
        supports: Supports::Clamped,
        ..BuildParams::default()
    };
    (s.curves, build)
}

/// `count` distinct random curves out of `n`, ascending.
fn random_set(rng: &mut SplitMix64, n: usize, count: usize) -> Vec<usize> {
    let mut ids: Vec<usize> = (0..n).collect();
    for i in 0..count {
        let j = i + (rng.next_u64() % (n - i) as u64) as usize;
        ids.swap(i, j);
    }
    let mut set = ids[..count].to_vec();
    set.sort_unstable();
    set
}

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
    let set = ok(
        addr,
        "POST",
        "/api/set",
        &format!("{{\"curves\":{kept:?}}}"),
    );
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
        let set = ok(
            addr,
            "POST",
            "/api/set",
            &format!("{{\"curves\":{kept:?}}}"),
        );
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
        let (got, text) = request(addr, method, path, body.as_bytes());
        let shown = &body[..body.len().min(40)];
        assert_eq!(got, status, "{method} {path} {shown}: {text}");
        let v: Value = serde_json::from_str(&text)
            .unwrap_or_else(|e| panic!("{method} {path} {shown}: not JSON ({e}): {text}"));
        let message = v["error"].as_str().unwrap_or_default();
        assert!(message.contains(says), "{method} {path} {shown}: {message}");
    }
    // A whole network removed except what toggling the last curve would leave empty.
    ok(addr, "POST", "/api/set", "{\"curves\":[3]}");
    let (got, text) = request(addr, "POST", "/api/toggle", b"{\"curve\":3}");
    assert_eq!(got, 422, "{text}");
    assert_eq!(curves_of(&ok(addr, "GET", "/api/state", "")), vec![3]);
    // Back to the start: the same numbers as before.
    let all: Vec<usize> = (0..curves.len()).collect();
    let again = ok(addr, "POST", "/api/set", &format!("{{\"curves\":{all:?}}}"));
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
            .map(|set| {
                s.spawn(move || ok(addr, "POST", "/api/set", &format!("{{\"curves\":{set:?}}}")))
            })
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

/// Removing two curves of the tower and restoring them, one toggle at a time: each state's
/// `λ` is `analyze --remove`'s of its set, the edits relax from the current equilibrium, and
/// the last restore, back to a set analysed before, comes from the cache.
#[test]
fn warm_toggles_of_the_tower_give_the_lambda_of_analyze_and_restores_come_from_the_cache() {
    let ex = curvenet::paper::load_embedded("tower", Supports::default()).unwrap();
    let addr = serve(&ex.curves, &ex.build);
    let n = ex.curves.len();
    let mut rng = SplitMix64::new(3);
    let a = rng.below(n as u64) as usize;
    let b = (a + 1 + rng.below(n as u64 - 1) as usize) % n;
    let all: Vec<usize> = (0..n).collect();
    let without = |gone: &[usize]| -> Vec<usize> {
        all.iter().copied().filter(|c| !gone.contains(c)).collect()
    };
    let steps = [
        (a, without(&[a])),
        (b, without(&[a, b])),
        (a, without(&[b])),
        (b, all.clone()),
    ];
    let mut froms = Vec::new();
    for (curve, expected) in &steps {
        let t = ok(
            addr,
            "POST",
            "/api/toggle",
            &format!("{{\"curve\":{curve}}}"),
        );
        assert_eq!(&curves_of(&t), expected);
        assert_close(&t, analyze_lambda(&ex.curves, &ex.build, expected));
        froms.push(t["from"].as_str().unwrap().to_string());
    }
    assert_eq!(froms[3], "cache", "{froms:?}");
    assert!(froms[..3].iter().all(|f| f != "cache"), "{froms:?}");
    assert!(froms[..3].iter().any(|f| f == "warm"), "{froms:?}");
    // Removing `a` again: the set of the first step, from the cache.
    let again = ok(addr, "POST", "/api/toggle", &format!("{{\"curve\":{a}}}"));
    assert_eq!(again["from"], "cache");
}

/// Random edits of the dome (sets, toggles), each warm-started from the last: `λ` and the
/// status of the cold analysis of every set.
#[test]
fn random_warm_edits_of_the_dome_match_cold_analyses() {
    let (curves, build) = dome();
    let (network, _) = build_network(&curves, &build).unwrap();
    let analyzer = Analyzer::new(network, StabilityParams::default()).unwrap();
    let n = curves.len();
    let all: Vec<usize> = (0..n).collect();
    let design = Design::new(analyzer, &all).unwrap();
    let mut rng = SplitMix64::new(5);
    for step in 0..10 {
        let e = if step % 3 == 2 {
            let removed = 1 + rng.below(3) as usize;
            let kept = random_set(&mut rng, n, n - removed);
            design.set(&kept).unwrap()
        } else {
            design.toggle(rng.below(n as u64) as usize).unwrap()
        };
        let set = design.analyzer().set(&e.summary.curves);
        let cold = design.analyzer().analyze(&set, None).unwrap();
        let (w, c) = (e.summary.lambda, cold.lambda());
        assert!(
            (w - c).abs() <= 1e-6 * c.abs(),
            "step {step} {:?} ({:?}): warm {w:e}, cold {c:e}",
            e.summary.curves,
            e.source
        );
        assert_eq!(
            e.summary.zero_modes, cold.spectrum.zero_modes,
            "step {step}"
        );
        assert_eq!(e.summary.negative_modes, cold.spectrum.negative_modes);
    }
    let (held, bytes) = design.cached();
    assert!(held >= 2 && bytes > 0, "{held} states, {bytes} bytes");
}
