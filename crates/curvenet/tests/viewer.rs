//! The viewer page and the pictures of a run (`curvenet::report::{viewer, render, plot}`).
//!
//! On a small greedy run on the built-in dome (random geodesics, with the surface):
//!
//! - the page is one self-contained file: the data as JSON in a `<script>` element, the script
//!   inline, no URL, no placeholder left; the embedded data decodes to the run's iterations,
//!   curves, `λ`, equilibrium displacements and modes (within the 16-bit quantization), the rest
//!   positions (within f32), the surface;
//! - the gravity deflection embedded per iteration is `H⁻¹ f` at the recorded equilibrium: its
//!   largest displacement equals `Analyzer::gravity`'s at the same state;
//! - `final.png`, `mode.png` and `lambda.png` have the documented sizes, are not blank (and
//!   `final.png` shows the kept curves' colour), and are byte-identical when written twice;
//! - `write_run_outputs` writes the pictures, the page and the fabrication table.

mod common;

use common::TempDir;
use curvenet::network::{BuildParams, build_network};
use curvenet::report::plot::PLOT_SIZE;
use curvenet::report::render::{KEPT, PICTURE_SIZE};
use curvenet::report::viewer::{
    self, ViewerOptions, decode_f32, decode_i16, gravity_deflection, viewer_html,
};
use curvenet::rod::{ActiveSet, Supports};
use curvenet::run_folder::RunFolder;
use curvenet::run_folder::{InputDescription, OutputWriter, RunSetup};
use curvenet::simplify::{Budget, GreedyParams, greedy};
use curvenet::stability::{Analyzer, StabilityParams};
use curvenet::trace::{Generator, builtin_surface, generate, scale_to_extent};
use std::path::Path;
use std::sync::OnceLock;

/// A greedy run on 12 random geodesics over the built-in dome, made once.
fn run_dir() -> &'static Path {
    static RUN: OnceLock<TempDir> = OnceLock::new();
    RUN.get_or_init(|| {
        let dir = TempDir::new("run");
        let surface = builtin_surface("dome").expect("dome");
        let (mesh, _) = scale_to_extent(&surface, 4000.0);
        let curves = generate(&mesh, &Generator::Random { count: 12, seed: 3 })
            .expect("traces")
            .curves;
        let build = BuildParams {
            edge_length: 100.0,
            supports: Supports::Clamped,
            ..BuildParams::default()
        };
        let (net, info) = build_network(&curves, &build).expect("builds");
        let n = net.rods.len();
        let total = net.total_length(&(0..n).collect::<Vec<_>>());
        let params = GreedyParams::new(Budget::Fraction(0.4));
        let stability = StabilityParams::default();
        let setup = RunSetup {
            input: InputDescription {
                example: Some("viewer-test".into()),
                mesh: Some("builtin:dome".into()),
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
        let analyzer = Analyzer::new(net, stability).expect("analyzer");
        let mut w = OutputWriter::create(dir.path(), analyzer.network(), setup, 0.4 * total)
            .expect("output folder");
        w.write_mesh(&mesh).expect("mesh");
        let outcome = greedy(&analyzer, &params, None, None, &mut w).expect("greedy");
        w.finish(&outcome, &serde_json::json!({})).expect("finish");
        dir
    })
    .path()
}

/// The JSON embedded in a viewer page.
fn embedded_data(html: &str) -> serde_json::Value {
    let open = "<script id=\"curvenet-data\" type=\"application/json\">";
    let start = html.find(open).expect("data element") + open.len();
    let end = start + html[start..].find("</script>").expect("closed");
    serde_json::from_str(&html[start..end]).expect("valid JSON")
}

#[test]
fn the_page_is_self_contained_and_holds_the_run() {
    let run = RunFolder::open(run_dir()).expect("opens");
    let html = viewer_html(&run, &ViewerOptions::default()).expect("page");
    assert!(html.starts_with("<!DOCTYPE html>"));
    for bad in ["http://", "https://", "//cdn", "src=", "{{", "@import"] {
        assert!(!html.contains(bad), "the page contains {bad:?}");
    }
    assert!(html.contains("getContext('webgl'"));
    assert!(html.contains("<title>curvenet: viewer-test</title>"));
    let size = html.len();
    assert!(size < 2_000_000, "page of {size} bytes");

    let data = embedded_data(&html);
    assert_eq!(data["format"], "curvenet-viewer");
    let net = &run.network;
    let rest = decode_f32(&data["positions"]).expect("positions");
    assert_eq!(rest.len(), net.dofs());
    for (v, p) in net.positions.iter().enumerate() {
        for k in 0..3 {
            assert!((rest[3 * v + k] - p[k]).abs() <= 1e-6 * p[k].abs().max(1.0));
        }
    }
    let rods = data["rods"].as_array().expect("rods");
    assert_eq!(rods.len(), net.rods.len());
    for (c, r) in rods.iter().enumerate() {
        let v: Vec<u32> = serde_json::from_value(r["v"].clone()).unwrap();
        assert_eq!(v, net.rods[c].vertices);
        let len = r["length"].as_f64().unwrap();
        assert!((len - net.rods[c].rest_length()).abs() <= 1e-5 * len);
    }
    let mesh = run.mesh.as_ref().expect("the run has its surface");
    let mv = decode_f32(&data["mesh"]["vertices"]).expect("mesh vertices");
    assert_eq!(mv.len(), 3 * mesh.vertices.len());

    let its = data["iterations"].as_array().expect("iterations");
    assert_eq!(its.len(), run.iteration_count());
    assert!(its.len() >= 3);
    for (k, it) in its.iter().enumerate() {
        let rec = run.record(k).unwrap();
        let curves: Vec<usize> = serde_json::from_value(it["curves"].clone()).unwrap();
        assert_eq!(curves, rec.curves);
        assert_eq!(it["lambda"].as_f64(), Some(rec.lambda));
        assert_eq!(it["removed"].as_u64().map(|c| c as usize), rec.removed);
        // A relaxation short of equilibrium is flagged for the page to name.
        assert_eq!(it["unrelaxed"].as_bool(), Some(!rec.newton.converged));
        let verts = viewer::active_vertices(&run, &rec.curves);
        for (field, full) in [
            ("u", run.displacement(k).unwrap()),
            ("mode", run.mode(k).unwrap()),
        ] {
            let q = decode_i16(&it[field]).expect(field);
            assert_eq!(q.len(), 3 * verts.len(), "{field} of iteration {k}");
            let max = it[field]["max"].as_f64().unwrap();
            assert!(max > 0.0);
            for (i, &v) in verts.iter().enumerate() {
                for a in 0..3 {
                    let err = (q[3 * i + a] - full[3 * v + a]).abs();
                    assert!(err <= max / 32767.0, "{field}[{v}] off by {err}");
                }
            }
        }
    }
    // The removed curves' iterations.
    let removed_at = data["removed_at"].as_array().unwrap();
    for (k, rec) in run.result.iterations.iter().enumerate() {
        if let Some(c) = rec.removed {
            assert_eq!(removed_at[c].as_u64(), Some(k as u64));
        }
    }
}

#[test]
fn gravity_is_the_hessian_solve_at_the_recorded_equilibrium() {
    let run = RunFolder::open(run_dir()).expect("opens");
    let data = viewer::viewer_data(&run, &ViewerOptions::default()).expect("data");
    let analyzer =
        Analyzer::new(run.network.clone(), run.result.setup.stability.clone()).expect("analyzer");
    let n = run.network.rods.len();
    for k in [0, run.last_index()] {
        let rec = run.record(k).unwrap();
        let u = run.displacement(k).unwrap();
        let active = ActiveSet::from_curves(n, &rec.curves);
        let h = analyzer.model().assemble(&u, &active, true).hess;
        let summary = analyzer.gravity(&active, &h).expect("positive definite");
        let g = gravity_deflection(&analyzer, &rec.curves, &u).expect("solves");
        let (vmax, dmax) = (0..run.network.positions.len())
            .map(|v| {
                (
                    v,
                    (g[3 * v].powi(2) + g[3 * v + 1].powi(2) + g[3 * v + 2].powi(2)).sqrt(),
                )
            })
            .fold((0, 0.0), |b, x| if x.1 > b.1 { x } else { b });
        assert_eq!(vmax, summary.vertex);
        assert!((dmax - summary.max_displacement).abs() <= 1e-12 * dmax);
        let embedded = &data["iterations"][k]["gravity"];
        assert_eq!(embedded["vertex"].as_u64(), Some(vmax as u64));
        assert!((embedded["max_displacement"].as_f64().unwrap() - dmax).abs() <= 1e-12 * dmax);
        // The load points down (−z): the structure sags.
        let sag: f64 = (0..g.len() / 3).map(|v| g[3 * v + 2]).sum();
        assert!(sag < 0.0);
    }
    let none = viewer::viewer_data(&run, &ViewerOptions { gravity: false }).expect("data");
    assert!(none["iterations"][0]["gravity"].is_null());
}

fn decode_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let file = std::fs::File::open(path).expect("png exists");
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let mut reader = decoder.read_info().expect("png header");
    let mut buf = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut buf).expect("png data");
    assert_eq!(info.color_type, png::ColorType::Rgb);
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

#[test]
fn pictures_have_their_size_show_something_and_are_reproducible() {
    let dir = run_dir();
    let out = viewer::write_run_outputs(dir).expect("writes");
    let names: Vec<String> = out
        .files
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "final.png",
            "mode.png",
            "lambda.png",
            "fabrication.csv",
            "viewer.html"
        ]
    );
    let first: Vec<Vec<u8>> = ["final.png", "mode.png", "lambda.png"]
        .iter()
        .map(|n| std::fs::read(dir.join(n)).unwrap())
        .collect();
    for (name, (w, h)) in [
        ("final.png", PICTURE_SIZE),
        ("mode.png", PICTURE_SIZE),
        ("lambda.png", PLOT_SIZE),
    ] {
        let (pw, ph, px) = decode_png(&dir.join(name));
        assert_eq!((pw as usize, ph as usize), (w, h), "{name}");
        let drawn = px.chunks(3).filter(|p| p.iter().any(|&c| c < 235)).count();
        let total = w * h;
        assert!(
            drawn > total / 50,
            "{name}: only {drawn} of {total} pixels drawn"
        );
        if name == "final.png" {
            let kept = KEPT.map(|c| (c * 255.0).round() as i32);
            let blue = px
                .chunks(3)
                .filter(|p| (0..3).all(|k| (p[k] as i32 - kept[k]).abs() <= 3))
                .count();
            assert!(blue > 500, "final.png: {blue} pixels of the kept colour");
        }
    }
    // Written again: the same bytes.
    let run = RunFolder::open(dir).expect("opens");
    viewer::write_pictures(&run).expect("writes");
    for (n, bytes) in ["final.png", "mode.png", "lambda.png"].iter().zip(&first) {
        assert_eq!(&std::fs::read(dir.join(n)).unwrap(), bytes, "{n} differs");
    }
    let fab = std::fs::read_to_string(dir.join("fabrication.csv")).unwrap();
    assert_eq!(
        fab.lines().filter(|l| !l.starts_with('#')).count(),
        1 + run.record(run.last_index()).unwrap().curves.len()
    );
}
