//! What the drawing and slide tests share: a server of the application layer's inputs (as
//! `curvenet serve` opens one), `λ` read from an answer, relative comparisons, and the design a
//! server saves read back as `curvenet analyze --curves saved.json --mesh surface.obj` does.

use super::request;
use curvenet::app::{self, CurveSource, InputSpec, MeshSource, ModelOptions, Setup, Silent};
use curvenet::run_folder::RunsRoot;
use curvenet::words::Neutral;
use curvenet_serve::start::{ServeSpec, Source, open};
use curvenet_serve::{AppState, Server};
use serde_json::Value;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};

/// The edge length the tests build with.
pub const H: f64 = 200.0;

/// A server of `input` in the model of `model`, as `curvenet serve` opens it, on a free port.
pub fn serve_inputs(input: InputSpec, model: ModelOptions) -> SocketAddr {
    serve_inputs_without(input, model, Vec::new())
}

/// [`serve_inputs`] with the curves `remove` removed at the start (`serve --remove`).
pub fn serve_inputs_without(
    input: InputSpec,
    model: ModelOptions,
    remove: Vec<usize>,
) -> SocketAddr {
    let spec = ServeSpec {
        source: Source::Inputs(Box::new(input)),
        model,
        remove,
    };
    let opened = open(&spec, &Silent).expect("served");
    let server = Server::bind("127.0.0.1:0".parse().unwrap()).unwrap();
    let addr = server.local_addr().unwrap();
    let config = opened.config(RunsRoot::new(&std::env::temp_dir()).unwrap());
    std::thread::spawn(move || server.serve(AppState::new(opened.workspace, config)));
    addr
}

/// A server of `count` random geodesics on the built-in dome (as `curvenet serve --demo`
/// starts one), at edge length [`H`].
pub fn serve(count: usize, seed: u32) -> SocketAddr {
    let input = InputSpec {
        edge_length: Some(H),
        ..InputSpec::new(CurveSource::Geodesics {
            surface: "dome".into(),
            count,
            seed,
        })
    };
    serve_inputs(input, ModelOptions::default())
}

/// The `λ` of a state.
pub fn lambda(v: &Value) -> f64 {
    v["lambda"].as_f64().expect("a λ")
}

/// Asserts `a` is `b` to `tol` relative.
pub fn close_to(a: f64, b: f64, tol: f64, what: &str) {
    let rel = (a - b).abs() / b.abs().max(f64::MIN_POSITIVE);
    assert!(rel <= tol, "{what}: {a:e} against {b:e} (relative {rel:e})");
}

/// Asserts `a` is `b` to 1e-6 relative.
pub fn close(a: f64, b: f64, what: &str) {
    close_to(a, b, 1e-6, what);
}

/// Saves the server's design into `dir` (`export?format=json` and `format=surface`): the
/// curve file and the mesh written.
pub fn save(addr: SocketAddr, dir: &Path) -> (PathBuf, PathBuf) {
    let (status, curves) = request(addr, "GET", "/api/export?format=json", b"");
    assert_eq!(status, 200, "{curves}");
    let (status, surface) = request(addr, "GET", "/api/export?format=surface", b"");
    assert_eq!(status, 200, "{surface}");
    let (c, m) = (dir.join("saved.json"), dir.join("surface.obj"));
    std::fs::write(&c, curves).unwrap();
    std::fs::write(&m, surface).unwrap();
    (c, m)
}

/// Saves the server's design into `dir` as a design in millimetres whose curves `specs` gives
/// their own specs (materials, sections, rest shapes, supports: each curve's JSON object):
/// the design file (`design.json`) and the mesh.
pub fn physical_design(
    addr: SocketAddr,
    dir: &Path,
    specs: impl FnOnce(&mut [Value]),
) -> (PathBuf, PathBuf) {
    let (c, m) = save(addr, dir);
    let mut file: Value = serde_json::from_str(&std::fs::read_to_string(&c).unwrap()).unwrap();
    file["units"] = Value::from("mm");
    specs(file["curves"].as_array_mut().expect("the saved curves"));
    let design = dir.join("design.json");
    std::fs::write(&design, file.to_string()).unwrap();
    (design, m)
}

/// The inputs of a saved design, as `--curves saved.json --mesh surface.obj` reads them
/// (no edge length: the file's).
pub fn saved_inputs(curves: PathBuf, mesh: PathBuf) -> InputSpec {
    InputSpec {
        mesh: Some(MeshSource::Path(mesh)),
        ..InputSpec::new(CurveSource::Files(vec![curves]))
    }
}

/// The `λ_eq` that `curvenet analyze --curves saved.json --mesh surface.obj` finds for the
/// design the server saves now.
pub fn analyzed_saved(addr: SocketAddr, dir: &Path) -> f64 {
    let (c, m) = save(addr, dir);
    let mut setup =
        Setup::new(&saved_inputs(c, m), &ModelOptions::default()).expect("the saved design reads");
    app::analyze(&mut setup, &[], &Neutral)
        .expect("analysed")
        .report
        .lambda
}
