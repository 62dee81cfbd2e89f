//! Exports of a run folder (`curvenet::report::export`): content, round trips and errors.
//!
//! - the network file: the demo network (24 random geodesics on the built-in dome, as
//!   `curvenet demo`) and the final structure of its greedy run, exported, loaded back with
//!   `load_network` (no resampling) and analysed with `Analyzer` (relax + spectrum), give the
//!   same `λ` to 1e-9 relative; the loaded full network is bit-identical to the original;
//! - OBJ, curvenet-curves JSON, the points CSV and the fabrication table of a ring held by two
//!   crossing lines: closed curves repeat their first index, JSON reads back with
//!   `io::read_curves` bit for bit with labels carrying id / rest length / closed / supports,
//!   the fabrication table has the joints' arc lengths and the rods met there;
//! - missing and corrupt folders and files give errors naming the file, never a panic.

mod common;

use common::TempDir;
use curvenet::geom::Vec3;
use curvenet::io::{self, Origin, Polyline, TriMesh};
use curvenet::network::{BuildParams, build_network};
use curvenet::report::export::{
    self, ExportFormat, NetworkFile, load_network, parse_curve_label, parse_network_file,
    read_network_file,
};
use curvenet::rod::{ActiveSet, Supports};
use curvenet::run_folder::{InputDescription, OutputWriter, RunFolder, RunSetup, positions_at};
use curvenet::simplify::{Budget, GreedyParams, greedy};
use curvenet::stability::{Analyzer, StabilityParams};
use curvenet::trace::{Generator, builtin_surface, generate, scale_to_extent};
use std::path::Path;
use std::sync::OnceLock;

/// The demo's curves and surface: 24 random geodesics (seed 1) on the built-in dome scaled to
/// 4000 units, h = 100.
fn demo_scene() -> (Vec<Polyline>, TriMesh, BuildParams) {
    let surface = builtin_surface("dome").expect("built-in dome");
    let (mesh, _) = scale_to_extent(&surface, 4000.0);
    let traced = generate(&mesh, &Generator::Random { count: 24, seed: 1 }).expect("traces");
    let build = BuildParams {
        edge_length: 100.0,
        supports: Supports::Clamped,
        ..BuildParams::default()
    };
    (traced.curves, mesh, build)
}

/// Runs the greedy into `dir` as `curvenet` does (without the pictures).
fn make_run(
    dir: &Path,
    curves: &[Polyline],
    build: BuildParams,
    fraction: f64,
    keep: Vec<usize>,
    mesh: Option<&TriMesh>,
) {
    let (net, info) = build_network(curves, &build).expect("builds");
    let n = net.rods.len();
    let total = net.total_length(&(0..n).collect::<Vec<_>>());
    let params = GreedyParams {
        keep,
        ..GreedyParams::new(Budget::Fraction(fraction))
    };
    let stability = StabilityParams::default();
    let setup = RunSetup {
        input: InputDescription {
            example: Some("test".into()),
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
    let analyzer = Analyzer::new(net, stability).expect("analyzer");
    let mut w = OutputWriter::create(
        dir,
        analyzer.network(),
        setup,
        Budget::Fraction(fraction).length(total),
    )
    .expect("output folder");
    if let Some(m) = mesh {
        w.write_mesh(m).expect("mesh");
    }
    let outcome = greedy(&analyzer, &params, None, None, &mut w).expect("greedy");
    w.finish(&outcome, &serde_json::json!({})).expect("finish");
}

/// The demo run, made once for all tests of this file.
fn demo_run() -> &'static Path {
    static RUN: OnceLock<TempDir> = OnceLock::new();
    RUN.get_or_init(|| {
        let dir = TempDir::create("demo");
        let (curves, mesh, build) = demo_scene();
        make_run(dir.path(), &curves, build, 0.3, Vec::new(), Some(&mesh));
        dir
    })
    .path()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(f64::MIN_POSITIVE)
}

fn polyline(points: Vec<Vec3>, closed: bool) -> Polyline {
    Polyline {
        points,
        closed,
        origin: Origin::new("<test>", 0),
        label: None,
    }
}

/// A ring of radius 100 (curve 0, closed, 40 points) held by two lines along x and y
/// (curves 1 and 2, from −150 to 150) that cross it at four ring vertices and each other at
/// the origin.
fn ring_scene() -> Vec<Polyline> {
    let ring: Vec<Vec3> = (0..40)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / 40.0;
            Vec3::new(100.0 * t.cos(), 100.0 * t.sin(), 0.0)
        })
        .collect();
    let line = |d: Vec3| {
        polyline(
            (0..=30).map(|i| d * (-150.0 + 10.0 * i as f64)).collect(),
            false,
        )
    };
    vec![
        polyline(ring, true),
        line(Vec3::new(1.0, 0.0, 0.0)),
        line(Vec3::new(0.0, 1.0, 0.0)),
    ]
}

fn ring_run() -> &'static Path {
    static RUN: OnceLock<TempDir> = OnceLock::new();
    RUN.get_or_init(|| {
        let dir = TempDir::create("ring");
        let build = BuildParams {
            edge_length: 10.0,
            supports: Supports::Clamped,
            ..BuildParams::default()
        };
        make_run(dir.path(), &ring_scene(), build, 0.8, vec![0], None);
        dir
    })
    .path()
}

#[test]
fn network_file_round_trip_gives_the_same_lambda() {
    let (curves, _, build) = demo_scene();
    let (net, _) = build_network(&curves, &build).expect("builds");
    let params = StabilityParams::default();
    let n = net.rods.len();
    let dir = TempDir::create("roundtrip");

    // The whole network: bit-identical after the round trip, and the same λ.
    let all: Vec<usize> = (0..n).collect();
    let file = NetworkFile::from_structure(&net, &all, params.material, None);
    let path = dir.path().join("network.json");
    std::fs::write(&path, file.to_json()).expect("writes");
    let loaded = load_network(&path).expect("loads");
    assert_eq!(loaded.positions, net.positions);
    assert_eq!(loaded.rods, net.rods);
    assert_eq!(loaded.joints, net.joints);
    assert_eq!(loaded.supports, net.supports);
    let original = Analyzer::new(net.clone(), params.clone()).expect("analyzer");
    let a = original.analyze(&original.all(), None).expect("analysis");
    let copy = Analyzer::new(loaded, params.clone()).expect("analyzer");
    let b = copy.analyze(&copy.all(), None).expect("analysis");
    eprintln!(
        "full network: λ {:e} vs {:e} (relative difference {:e})",
        a.lambda(),
        b.lambda(),
        rel(a.lambda(), b.lambda())
    );
    assert!(
        rel(a.lambda(), b.lambda()) <= 1e-9,
        "full network: λ {} vs {}",
        a.lambda(),
        b.lambda()
    );

    // The final structure of the demo's greedy run, exported from the run folder: the loaded
    // network (all its rods) has the λ of that structure in the original network.
    let run = RunFolder::open(demo_run()).expect("run folder");
    let k = run.last_index();
    let rec = run.record(k).expect("record").clone();
    assert!(rec.curves.len() < n, "the greedy removed curves");
    let text = export::network_json(&run, k).expect("exports");
    let path = dir.path().join("final.json");
    std::fs::write(&path, &text).expect("writes");
    let file = read_network_file(&path).expect("reads");
    assert_eq!(file.iteration, Some(k));
    assert_eq!(file.material, params.material);
    assert_eq!(
        file.rods.iter().map(|r| r.id).collect::<Vec<_>>(),
        rec.curves
    );
    let loaded = load_network(&path).expect("loads");
    assert_eq!(loaded.rods.len(), rec.curves.len());
    let kept_vertices = positions_at(&loaded, None).len();
    assert!(kept_vertices < net.positions.len());
    let active = ActiveSet::from_curves(n, &rec.curves);
    let a = original.analyze(&active, None).expect("analysis");
    let copy = Analyzer::new(loaded, params).expect("analyzer");
    let b = copy.analyze(&copy.all(), None).expect("analysis");
    eprintln!(
        "final structure: λ {:e} vs {:e} (relative difference {:e})",
        a.lambda(),
        b.lambda(),
        rel(a.lambda(), b.lambda())
    );
    assert!(
        rel(a.lambda(), b.lambda()) <= 1e-9,
        "final structure: λ {} (in the original network) vs {} (loaded)",
        a.lambda(),
        b.lambda()
    );
    // …and the run's own record (relaxed from the previous equilibrium) agrees closely.
    assert!(
        rel(rec.lambda, b.lambda()) <= 1e-6,
        "recorded λ {} vs {}",
        rec.lambda,
        b.lambda()
    );
    // The exported equilibrium is the run's, restricted to the kept vertices.
    let eq = file.equilibrium_vector().expect("equilibrium");
    let u = run.displacement(k).expect("state");
    let mut used = vec![false; net.positions.len()];
    for &c in &rec.curves {
        for &v in &net.rods[c].vertices {
            used[v as usize] = true;
        }
    }
    let expected: Vec<f64> = (0..net.positions.len())
        .filter(|&v| used[v])
        .flat_map(|v| u[3 * v..3 * v + 3].to_vec())
        .collect();
    assert_eq!(eq, expected);
}

#[test]
fn obj_json_and_csv_exports_of_a_ring_and_two_lines() {
    let run = RunFolder::open(ring_run()).expect("run folder");
    assert!(run.iteration_count() >= 2);
    let net = &run.network;
    assert!(net.rods[0].closed);
    assert_eq!(
        net.joints.len(),
        5,
        "four ring crossings and the lines' crossing"
    );
    let k = 0;
    let u = run.displacement(k).expect("state");
    let eq = positions_at(net, Some(&u));

    // OBJ: one `o` and one `l` per curve, the ring's `l` repeating its first index; the
    // points read back at equilibrium, bit for bit.
    let obj = export::curves_obj(&run, k, false).expect("obj");
    let l_records: Vec<&str> = obj.lines().filter(|l| l.starts_with("l ")).collect();
    assert_eq!(l_records.len(), 3);
    let ring_idx: Vec<&str> = l_records[0].split_whitespace().skip(1).collect();
    assert_eq!(ring_idx.len(), net.rods[0].vertices.len() + 1);
    assert_eq!(ring_idx.first(), ring_idx.last());
    assert!(obj.contains("o curve 0\n") && obj.contains("o curve 2\n"));
    let back = io::parse_obj_polylines(&obj, "x.obj")
        .expect("reads")
        .curves;
    assert_eq!(back.len(), 3);
    assert!(back[0].closed && !back[1].closed);
    for (c, p) in back.iter().enumerate() {
        let expected: Vec<Vec3> = net.rods[c]
            .vertices
            .iter()
            .map(|&v| eq[v as usize])
            .collect();
        assert_eq!(p.points, expected, "curve {c}");
    }
    let rest_obj = export::curves_obj(&run, k, true).expect("obj");
    let back = io::parse_obj_polylines(&rest_obj, "x.obj")
        .expect("reads")
        .curves;
    assert_eq!(
        back[1].points,
        net.rods[1]
            .vertices
            .iter()
            .map(|&v| net.positions[v as usize])
            .collect::<Vec<_>>()
    );

    // JSON, read back by io::read_curves: rest and equilibrium points, labels with the data.
    let dir = TempDir::create("json");
    let paths = export::write_exports(&run, k, ExportFormat::Json, dir.path()).expect("writes");
    assert_eq!(paths.len(), 2);
    let rest = io::read_curves(&paths[0]).expect("rest json reads").curves;
    let equi = io::read_curves(&paths[1])
        .expect("equilibrium json reads")
        .curves;
    assert_eq!(rest.len(), 3);
    for (c, (r, e)) in rest.iter().zip(&equi).enumerate() {
        let rod = &net.rods[c];
        let (id, len, closed, supports) =
            parse_curve_label(r.label.as_deref().expect("label")).expect("parses");
        assert_eq!(id, c);
        assert_eq!(len, rod.rest_length());
        assert_eq!(closed, rod.closed);
        assert_eq!(r.closed, rod.closed);
        assert_eq!(supports, if c == 0 { "none" } else { "clamped" });
        assert_eq!(r.label, e.label);
        let at =
            |pos: &[Vec3]| -> Vec<Vec3> { rod.vertices.iter().map(|&v| pos[v as usize]).collect() };
        assert_eq!(r.points, at(&net.positions));
        assert_eq!(e.points, at(&eq));
    }

    // Points CSV: one row per curve vertex, rest and equilibrium columns.
    let csv = export::points_csv(&run, k).expect("csv");
    let rows: Vec<&str> = csv.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(
        rows[0],
        "curve,point,vertex,closed,s,x_rest,y_rest,z_rest,x_eq,y_eq,z_eq"
    );
    let n_points: usize = net.rods.iter().map(|r| r.vertices.len()).sum();
    assert_eq!(rows.len(), 1 + n_points);
    let r1: Vec<&str> = rows[1].split(',').collect();
    let v0 = net.rods[0].vertices[0] as usize;
    assert_eq!(r1[0..4], ["0", "0", &v0.to_string(), "true"]);
    assert_eq!(r1[5].parse::<f64>().unwrap(), net.positions[v0].x);
    assert_eq!(r1[8].parse::<f64>().unwrap(), eq[v0].x);

    // Fabrication table: one row per rod; the x line meets the ring at s = 50 and 250 and the
    // y line at s = 150; the ring is closed with no supports.
    let fab = export::fabrication_csv(&run, k).expect("fabrication");
    assert!(fab.contains("# cut_length = rest_length"));
    let rows: Vec<Vec<String>> = fab
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    assert_eq!(
        rows[0].join(","),
        "curve,rest_length,cut_length,closed,vertices,joint_count,joints,start_support,end_support"
    );
    assert_eq!(rows.len(), 4);
    let ring = &rows[1];
    assert_eq!(ring[0], "0");
    assert_eq!(ring[3], "true");
    assert_eq!(ring[5], "4");
    assert_eq!((ring[7].as_str(), ring[8].as_str()), ("none", "none"));
    assert_eq!(ring[1], ring[2]);
    assert_eq!(ring[1].parse::<f64>().unwrap(), net.rods[0].rest_length());
    let line = &rows[2];
    assert_eq!(line[0], "1");
    assert_eq!((line[7].as_str(), line[8].as_str()), ("clamped", "clamped"));
    let joints: Vec<(f64, String)> = line[6]
        .split(';')
        .map(|j| {
            let (s, ids) = j.split_once(':').expect("s:ids");
            (s.parse().expect("number"), ids.to_string())
        })
        .collect();
    assert_eq!(joints.len(), 3);
    for ((s, ids), (es, eids)) in joints.iter().zip([(50.0, "0"), (150.0, "2"), (250.0, "0")]) {
        assert!((s - es).abs() < 1e-9, "joint at {s}, expected {es}");
        assert_eq!(ids, eids);
    }
    // At a later iteration the removed curve no longer appears among the rods met.
    let last = run.last_index();
    let kept = &run.record(last).unwrap().curves;
    let fab = export::fabrication_csv(&run, last).expect("fabrication");
    let data_rows = fab.lines().filter(|l| !l.starts_with('#')).count() - 1;
    assert_eq!(data_rows, kept.len());
    for c in (0..3).filter(|c| !kept.contains(c)) {
        assert!(!fab.contains(&format!(":{c}\n")) && !fab.contains(&format!(":{c};")));
    }

    // All formats at once: seven files.
    let dir = TempDir::create("all");
    let paths = export::write_exports(&run, last, ExportFormat::All, dir.path()).expect("writes");
    assert_eq!(paths.len(), 7);
    assert!(paths.iter().all(|p| p.is_file()));
    let loaded = load_network(&dir.path().join(format!("network_{last:04}.json"))).expect("loads");
    assert_eq!(loaded.rods.len(), kept.len());
}

#[test]
fn bad_folders_and_files_give_clear_errors() {
    let dir = TempDir::create("bad");
    let missing = dir.path().join("nope");
    let e = RunFolder::open(&missing).unwrap_err().to_string();
    assert!(e.contains("nope") && e.contains("not a folder"), "{e}");
    let e = RunFolder::open(dir.path()).unwrap_err().to_string();
    assert!(e.contains("result.json"), "{e}");

    // A copy of the ring run, then damaged piece by piece.
    let copy = dir.path().join("run");
    copy_dir(ring_run(), &copy);
    let ok = RunFolder::open(&copy).expect("the copy opens");
    let net_text = std::fs::read_to_string(copy.join("network.json")).unwrap();

    std::fs::write(copy.join("result.json"), "{\"version\": 1, ").unwrap();
    let e = RunFolder::open(&copy).unwrap_err().to_string();
    assert!(e.contains("result.json"), "{e}");
    std::fs::copy(ring_run().join("result.json"), copy.join("result.json")).unwrap();

    let mut bad: curvenet::network::Network = serde_json::from_str(&net_text).unwrap();
    bad.rods[1].vertices[3] = 1_000_000;
    std::fs::write(
        copy.join("network.json"),
        serde_json::to_string(&bad).unwrap(),
    )
    .unwrap();
    let e = RunFolder::open(&copy).unwrap_err().to_string();
    assert!(e.contains("network.json") && e.contains("1000000"), "{e}");
    let mut bad: curvenet::network::Network = serde_json::from_str(&net_text).unwrap();
    bad.rods[2].rest_lengths.pop();
    std::fs::write(
        copy.join("network.json"),
        serde_json::to_string(&bad).unwrap(),
    )
    .unwrap();
    let e = RunFolder::open(&copy).unwrap_err().to_string();
    assert!(e.contains("rest lengths"), "{e}");
    std::fs::write(copy.join("network.json"), &net_text).unwrap();

    // Truncated and missing side files.
    std::fs::write(copy.join("states/0000.bin"), [0u8; 13]).unwrap();
    let run = RunFolder::open(&copy).expect("opens");
    let e = run.displacement(0).unwrap_err().to_string();
    assert!(e.contains("0000.bin") && e.contains("truncated"), "{e}");
    std::fs::write(copy.join("states/0000.bin"), [0u8; 16]).unwrap();
    let e = run.displacement(0).unwrap_err().to_string();
    assert!(e.contains("expected 3·V"), "{e}");
    std::fs::remove_file(copy.join("states/0000.bin")).unwrap();
    let e = export::curves_obj(&run, 0, false).unwrap_err().to_string();
    assert!(e.contains("0000.bin"), "{e}");
    let e = export::export_files(&ok, 99, ExportFormat::All)
        .unwrap_err()
        .to_string();
    assert!(e.contains("no iteration 99"), "{e}");

    // A corrupt mesh is a warning, not an error.
    std::fs::write(copy.join("mesh.obj"), "v 0 0 0\nf 1 2 3\n").unwrap();
    let run = RunFolder::open(&copy).expect("opens");
    assert!(run.mesh.is_none());
    assert!(run.warnings.iter().any(|w| w.contains("mesh.obj")));

    // Network files.
    let good = NetworkFile::from_structure(&ok.network, &[0, 1, 2], Default::default(), None);
    let text = good.to_json();
    assert!(parse_network_file(&text).is_ok());
    for (from, to, phrase) in [
        ("\"curvenet-network\"", "\"curvenet-curves\"", "format"),
        ("\"version\": 1", "\"version\": 7", "version"),
        (
            "\"rest_lengths\":[",
            "\"rest_lengths\":[-1.0,",
            "rest length",
        ),
        ("\"radius\":2.0", "\"radius\":-2.0", "radius"),
    ] {
        assert!(text.contains(from), "{from}");
        let e = parse_network_file(&text.replacen(from, to, 1))
            .unwrap_err()
            .to_string();
        assert!(e.contains(phrase), "{phrase}: {e}");
    }
    let e = parse_network_file("{\"format\": ").unwrap_err().to_string();
    assert!(e.contains("line"), "{e}");
    let e = load_network(&dir.path().join("missing.json"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.json"), "{e}");
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let p = entry.path();
        if p.is_dir() {
            copy_dir(&p, &to.join(entry.file_name()));
        } else {
            std::fs::copy(&p, to.join(entry.file_name())).unwrap();
        }
    }
}
