//! What the HTTP tests share: a server on a free port, raw HTTP/1.1 requests, the networks
//! and the `λ` of `curvenet analyze --remove` to compare with, small run folders.
#![allow(dead_code)]

pub mod design;

use curvenet::geom::Vec3;
use curvenet::io::{Origin, Polyline, TriMesh};
use curvenet::network::{BuildParams, build_network};
use curvenet::pipeline;
use curvenet::rng::SplitMix64;
use curvenet::rod::Supports;
use curvenet::run_folder::{InputDescription, OutputWriter, RunSetup, RunsRoot};
use curvenet::simplify::{Budget, GreedyParams, greedy};
use curvenet::stability::{Analyzer, StabilityParams};
use curvenet_serve::{AppState, Design, ServeConfig, Server, Workspace};
use serde_json::Value;
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::{Path, PathBuf};

/// A server for `curves` built with `build`, all curves kept, listening on a free port.
pub fn serve(curves: &[Polyline], build: &BuildParams) -> SocketAddr {
    let (network, _) = build_network(curves, build).unwrap();
    let analyzer = Analyzer::new(network, StabilityParams::default()).unwrap();
    let all: Vec<usize> = (0..curves.len()).collect();
    let design = Design::new(analyzer, &all).unwrap();
    let server = Server::bind("127.0.0.1:0".parse().unwrap()).unwrap();
    let addr = server.local_addr().unwrap();
    std::thread::spawn(move || server.run(design));
    addr
}

/// One HTTP/1.1 request; the status, the head and the body. The body is written on a thread of its own
/// while the answer is read (a server refusing a huge body answers before reading it all).
pub fn request_full(
    addr: SocketAddr,
    method: &str,
    path: &str,
    body: &[u8],
) -> (u16, String, String) {
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
    (status, head.to_string(), body.to_string())
}

/// One HTTP/1.1 request; the status and the body.
pub fn request(addr: SocketAddr, method: &str, path: &str, body: &[u8]) -> (u16, String) {
    let (status, _, body) = request_full(addr, method, path, body);
    (status, body)
}

/// A request whose answer must be 200 with a JSON body.
pub fn ok(addr: SocketAddr, method: &str, path: &str, body: &str) -> Value {
    let (status, text) = request(addr, method, path, body.as_bytes());
    assert_eq!(status, 200, "{method} {path} {body}: {text}");
    serde_json::from_str(&text).unwrap()
}

/// Asserts that `method path` with `body` is refused with `status` and an error message
/// containing `says`.
pub fn assert_refused(
    addr: SocketAddr,
    method: &str,
    path: &str,
    body: &str,
    status: u16,
    says: &str,
) {
    let (got, text) = request(addr, method, path, body.as_bytes());
    let shown = &body[..body.len().min(40)];
    assert_eq!(got, status, "{method} {path} {shown}: {text}");
    let v: Value = serde_json::from_str(&text)
        .unwrap_or_else(|e| panic!("{method} {path} {shown}: not JSON ({e}): {text}"));
    let message = v["error"].as_str().unwrap_or_default();
    assert!(message.contains(says), "{method} {path} {shown}: {message}");
}

/// `POST /api/set` of `curves`: the state it answers.
pub fn post_set(addr: SocketAddr, curves: &[usize]) -> Value {
    ok(
        addr,
        "POST",
        "/api/set",
        &format!("{{\"curves\":{curves:?}}}"),
    )
}

pub fn curves_of(v: &Value) -> Vec<usize> {
    v["curves"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_u64().unwrap() as usize)
        .collect()
}

/// `λ` that `curvenet analyze --remove` gives the set `kept`.
pub fn analyze_lambda(curves: &[Polyline], build: &BuildParams, kept: &[usize]) -> f64 {
    let removed: Vec<usize> = (0..curves.len()).filter(|c| !kept.contains(c)).collect();
    let out = pipeline::analyze(
        curves,
        build,
        &StabilityParams::default(),
        None,
        &removed,
        Vec::new(),
    )
    .unwrap();
    out.report.lambda
}

pub fn assert_close(served: &Value, expected: f64) {
    let lambda = served["lambda"].as_f64().unwrap();
    let rel = (lambda - expected).abs() / expected.abs().max(f64::MIN_POSITIVE);
    assert!(rel <= 1e-6, "served λ {lambda:e}, analyze {expected:e}");
}

/// The small dome: 8 arcs, about 300 vertices.
pub fn dome() -> (Vec<Polyline>, BuildParams) {
    let s = curvenet::builtin::dome_arcs(2000.0, 700.0, 2, 4);
    let build = BuildParams {
        edge_length: 100.0,
        supports: Supports::Clamped,
        ..BuildParams::default()
    };
    (s.curves, build)
}

/// `count` distinct random curves out of `n`, ascending.
pub fn random_set(rng: &mut SplitMix64, n: usize, count: usize) -> Vec<usize> {
    let mut ids: Vec<usize> = (0..n).collect();
    for i in 0..count {
        let j = i + (rng.next_u64() % (n - i) as u64) as usize;
        ids.swap(i, j);
    }
    let mut set = ids[..count].to_vec();
    set.sort_unstable();
    set
}

/// A server for `curves` built with `build`, all curves kept, loading run folders from the
/// folder `runs` (as `serve --runs`), listening on a free port.
pub fn serve_runs(curves: &[Polyline], build: &BuildParams, runs: &Path) -> SocketAddr {
    serve_runs_in(curves, build, RunsRoot::new(runs).unwrap())
}

/// [`serve_runs`] with the root given (observed, say).
pub fn serve_runs_in(curves: &[Polyline], build: &BuildParams, runs: RunsRoot) -> SocketAddr {
    let (network, _) = build_network(curves, build).unwrap();
    let analyzer = Analyzer::new(network, StabilityParams::default()).unwrap();
    let all: Vec<usize> = (0..curves.len()).collect();
    let design = Design::new(analyzer, &all).unwrap();
    let server = Server::bind("127.0.0.1:0".parse().unwrap()).unwrap();
    let addr = server.local_addr().unwrap();
    let config = ServeConfig {
        runs_root: Some(runs),
        physical: None,
    };
    let app = AppState::new(Workspace::new(design, "network"), config);
    std::thread::spawn(move || server.serve(app));
    addr
}

/// An empty folder of its own for a test, `name`d, under the tests' temporary folder.
pub fn scratch(name: &str) -> PathBuf {
    let dir =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("serve-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A ring of radius 100 (curve 0, closed) held by two lines along x and y (curves 1 and 2)
/// that cross it and each other: three curves, about a hundred vertices.
pub fn ring() -> (Vec<Polyline>, BuildParams) {
    let polyline = |points: Vec<Vec3>, closed: bool| Polyline {
        points,
        closed,
        origin: Origin::new("<test>", 0),
        label: None,
    };
    let ring = (0..40)
        .map(|i| {
            let t = std::f64::consts::TAU * f64::from(i) / 40.0;
            Vec3::new(100.0 * t.cos(), 100.0 * t.sin(), 0.0)
        })
        .collect();
    let line = |d: Vec3| {
        let points = (0..=30)
            .map(|i| d * (-150.0 + 10.0 * f64::from(i)))
            .collect();
        polyline(points, false)
    };
    let curves = vec![
        polyline(ring, true),
        line(Vec3::new(1.0, 0.0, 0.0)),
        line(Vec3::new(0.0, 1.0, 0.0)),
    ];
    let build = BuildParams {
        edge_length: 10.0,
        supports: Supports::Clamped,
        ..BuildParams::default()
    };
    (curves, build)
}

/// Writes a finished greedy run of the [`ring`] (budget 80%, the ring kept) into `dir`, with
/// a surface (`mesh.obj`: two triangles): `result.json`, `network.json`, `mesh.obj`,
/// `states/0000.bin`, … as `curvenet simplify --out dir` writes them.
pub fn ring_run(dir: &Path) {
    let (curves, build) = ring();
    let (net, info) = build_network(&curves, &build).unwrap();
    let n = net.rods.len();
    let total = net.total_length(&(0..n).collect::<Vec<_>>());
    let params = GreedyParams {
        keep: vec![0],
        ..GreedyParams::new(Budget::Fraction(0.8))
    };
    let stability = StabilityParams::default();
    let setup = RunSetup {
        input: InputDescription {
            example: Some("ring".into()),
            mesh: None,
            curve_files: Vec::new(),
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
    let analyzer = Analyzer::new(net, stability).unwrap();
    let budget = Budget::Fraction(0.8).length(total);
    let mut w = OutputWriter::create(dir, analyzer.network(), setup, budget).unwrap();
    let mesh = TriMesh {
        vertices: vec![
            Vec3::new(-200.0, -200.0, -1.0),
            Vec3::new(200.0, -200.0, -1.0),
            Vec3::new(200.0, 200.0, -1.0),
            Vec3::new(-200.0, 200.0, -1.0),
        ],
        faces: vec![[0, 1, 2], [0, 2, 3]],
    };
    w.write_mesh(&mesh).unwrap();
    let outcome = greedy(&analyzer, &params, None, None, &mut w).unwrap();
    w.finish(&outcome, &serde_json::json!({})).unwrap();
}
