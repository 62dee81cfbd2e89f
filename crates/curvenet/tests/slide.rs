//! Sliding curves on the surface (`curvenet::slide`, `app::slide`) on a small curved network:
//! the search against a fine scan of a one-parameter family; the slid run's exported curves
//! analysed cold give the recorded objective; every exported point on the surface and within
//! the largest move of its drawn curve; a symmetric run stays symmetric and a group shares its
//! coefficients; the budget holds; the same result on one thread and
//! two; clear errors for a missing surface, a curve off it, a bad largest move and pinned
//! curves out of range.

mod common;

use common::TempDir;
use curvenet::app::{CurveSource, GivenCurves, InputSpec, MeshSource, ModelOptions, RunSpec};
use curvenet::app::{Setup, Silent, SlideSpec};
use curvenet::cancel::Cancel;
use curvenet::geom::Vec3;
use curvenet::io::{Origin, Polyline, TriMesh, parse_json_curves};
use curvenet::network::checks::surface::MeshDistance;
use curvenet::network::{BuildParams, build_network};
use curvenet::run_folder::{RunFolder, Which, network_polylines};
use curvenet::simplify::Budget;
use curvenet::slide::{MaxMove, SlideError, SlideParams, SlideProblem, Slider, is_gain};
use curvenet::stability::{Analyzer, StabilityParams};

const SIZE: f64 = 10.0;

fn height(x: f64, y: f64) -> f64 {
    2.0 * (std::f64::consts::PI * x / SIZE).sin() * (std::f64::consts::PI * y / SIZE).sin()
}

/// A bump over the square `[0, 10]²`, `cells` triangles' pairs a side.
fn bump(cells: usize) -> TriMesh {
    let mut vertices = Vec::new();
    for j in 0..=cells {
        for i in 0..=cells {
            let (x, y) = (
                SIZE * i as f64 / cells as f64,
                SIZE * j as f64 / cells as f64,
            );
            vertices.push(Vec3::new(x, y, height(x, y)));
        }
    }
    let at = |i: usize, j: usize| (j * (cells + 1) + i) as u32;
    let mut faces = Vec::new();
    for j in 0..cells {
        for i in 0..cells {
            faces.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            faces.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    TriMesh { vertices, faces }
}

/// A straight line of the plane lifted onto the bump, from `a` to `b`.
fn lifted(a: (f64, f64), b: (f64, f64), line: usize) -> Polyline {
    let n = 60;
    Polyline {
        points: (0..=n)
            .map(|k| {
                let t = k as f64 / n as f64;
                let (x, y) = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
                Vec3::new(x, y, height(x, y))
            })
            .collect(),
        closed: false,
        origin: Origin::new("<test>", line),
        label: None,
    }
}

/// Two lines along x, two along y; the last (at x = 3, leaving a long span to its right)
/// is the one that moves.
fn four_curves() -> Vec<Polyline> {
    vec![
        lifted((0.0, 3.0), (SIZE, 3.0), 1),
        lifted((0.0, 7.0), (SIZE, 7.0), 2),
        lifted((1.0, 0.0), (1.0, SIZE), 3),
        lifted((3.0, 0.0), (3.0, SIZE), 4),
    ]
}

fn build_params() -> BuildParams {
    BuildParams {
        edge_length: 0.5,
        ..BuildParams::default()
    }
}

fn problem(curves: Vec<Polyline>, budget: f64) -> SlideProblem {
    SlideProblem {
        ids: (0..curves.len()).collect(),
        drawn: Vec::new(),
        curves,
        build: build_params(),
        stability: StabilityParams::default(),
        budget,
        fixed: Vec::new(),
        ties: Vec::new(),
        physical: None,
        constraints: Default::default(),
    }
}

/// The curves on the bump, at edge length 0.5; `supports`, a supports file.
fn on_bump(curves: Vec<Polyline>, supports: Option<std::path::PathBuf>) -> InputSpec {
    InputSpec {
        mesh: Some(MeshSource::Given {
            mesh: bump(40),
            name: "bump".into(),
        }),
        edge_length: Some(0.5),
        supports_file: supports,
        ..InputSpec::new(CurveSource::Given(GivenCurves {
            curves,
            ..GivenCurves::default()
        }))
    }
}

/// `four_curves` and one more along x at y = 5.
fn five_curves() -> Vec<Polyline> {
    let mut curves = four_curves();
    curves.push(lifted((0.0, 5.0), (SIZE, 5.0), 5));
    curves
}

/// The run `run` (its folder `run.out`; no pictures) of `input` in the model `model`,
/// recorded; returns its folder.
fn recorded_run(input: &InputSpec, model: &ModelOptions, run: RunSpec) -> std::path::PathBuf {
    let mut setup = Setup::new(input, model).expect("set-up");
    let run = RunSpec {
        pictures: false,
        ..run
    };
    curvenet::app::execute(&mut setup, &run, &Silent, &Cancel::never()).expect("runs");
    run.out
}

/// A run of `input` to `budget` (a fraction) in `dir/run`, in the paper's model.
fn run_to(dir: &TempDir, input: &InputSpec, budget: f64) -> std::path::PathBuf {
    let run = RunSpec {
        budget: Some(Budget::Fraction(budget)),
        ..RunSpec::new(dir.path().join("run"))
    };
    recorded_run(input, &ModelOptions::default(), run)
}

/// Curve 3 alone moves, along one function (a translation across itself, its ends sliding
/// along the boundary).
fn one_parameter(max_move: f64, min_step: f64) -> Slider {
    let params = SlideParams {
        max_move: MaxMove::Length(max_move),
        pinned: vec![0, 1, 2],
        functions: 1,
        min_step,
        probe: 8,
        ..SlideParams::default()
    };
    Slider::new(problem(four_curves(), 1e9), Some(&bump(40)), params).expect("slider")
}

#[test]
fn search_finds_the_best_of_a_fine_scan() {
    let slider = one_parameter(4.0, 1.0 / 128.0);
    assert_eq!(slider.dimension(), 1);
    let scan: Vec<(f64, f64)> = (-80..=80)
        .filter_map(|k| {
            let a = 4.0 * k as f64 / 80.0;
            slider.evaluate(&[a]).map(|e| (a, e.lambda))
        })
        .collect();
    assert!(scan.len() > 100, "most of the family is allowed");
    let (best_a, best) =
        scan.iter().copied().fold(
            (0.0, f64::NEG_INFINITY),
            |b, s| if s.1 > b.1 { s } else { b },
        );
    let out = slider.run(&Cancel::never(), &|_| {}).expect("slides");
    let found = out.after.lambda;
    assert!(
        found >= best * (1.0 - 1e-3),
        "search {found:e} at {:?}, scan best {best:e} at {best_a}",
        out.coefficients[3]
    );
    assert!(
        found > out.before.lambda,
        "the drawn position is not the best"
    );
    // The moved curve stays within the largest move and on the surface.
    assert!(out.after.moves[3] <= 4.0 + 1e-12);
    // Pinned curves stay (their joints' vertices lie where the crossings are, a hair off).
    assert!(
        out.after.moves[..3].iter().all(|&m| m < 1e-3),
        "{:?}",
        out.after.moves
    );
}

#[test]
fn the_budget_holds_and_the_result_is_the_same_on_any_thread_count() {
    let curves = four_curves();
    let (net, _) = build_network(&curves, &build_params()).expect("builds");
    let all: Vec<usize> = (0..4).collect();
    let budget = net.total_length(&all);
    let slide = || {
        let params = SlideParams {
            max_move: MaxMove::Fraction(0.05),
            max_evaluations: 40,
            ..SlideParams::default()
        };
        let slider =
            Slider::new(problem(curves.clone(), budget), Some(&bump(40)), params).expect("slider");
        slider.run(&Cancel::never(), &|_| {}).expect("slides")
    };
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .expect("pool")
    };
    let one = pool(1).install(slide);
    let two = pool(2).install(slide);
    assert_eq!(one.coefficients, two.coefficients);
    assert_eq!(one.after.lambda.to_bits(), two.after.lambda.to_bits());
    assert!(one.after.length <= budget * (1.0 + 1e-12));
    assert!(one.after.lambda >= one.before.lambda);
    let diagonal = (2.0 * SIZE * SIZE + 16.0f64).sqrt();
    assert!(
        one.after
            .moves
            .iter()
            .all(|&m| m <= 0.05 * diagonal * (1.0 + 1e-9))
    );
}

#[test]
fn bad_inputs_are_refused_clearly() {
    let mesh = bump(20);
    let err = |p: SlideProblem, mesh: Option<&TriMesh>, params: SlideParams| {
        Slider::new(p, mesh, params).expect_err("refused")
    };
    let e = err(problem(four_curves(), 1e9), None, SlideParams::default());
    assert!(matches!(e, SlideError::NoSurface(_)), "{e}");
    assert!(e.to_string().contains("mesh"), "{e}");
    let mut off = four_curves();
    for p in &mut off[2].points {
        p.z += 3.0;
    }
    let e = err(problem(off, 1e9), Some(&mesh), SlideParams::default());
    match &e {
        SlideError::OffSurface {
            curve, distance, ..
        } => {
            assert_eq!(*curve, 2);
            assert!(*distance > 2.5, "{distance}");
        }
        e => panic!("{e}"),
    }
    assert!(
        e.to_string().contains("curve 2 is not on the surface"),
        "{e}"
    );
    for max_move in [
        MaxMove::Length(-1.0),
        MaxMove::Fraction(0.9),
        MaxMove::Length(0.0),
    ] {
        let params = SlideParams {
            max_move,
            ..SlideParams::default()
        };
        let e = err(problem(four_curves(), 1e9), Some(&mesh), params);
        assert!(matches!(e, SlideError::Params(_)), "{e}");
        assert!(e.to_string().contains("max_move"), "{e}");
    }
    let params = SlideParams {
        pinned: vec![7],
        ..SlideParams::default()
    };
    let e = err(problem(four_curves(), 1e9), Some(&mesh), params);
    assert!(e.to_string().contains("pin names curve 7"), "{e}");
    assert_eq!("5%".parse::<MaxMove>().ok(), Some(MaxMove::Fraction(0.05)));
    assert_eq!("2.5".parse::<MaxMove>().ok(), Some(MaxMove::Length(2.5)));
    assert!("far".parse::<MaxMove>().is_err());
}

#[test]
fn a_slid_run_is_recorded_and_its_exported_curves_give_its_objective_cold() {
    let dir = TempDir::new("slide-run");
    let mesh = bump(40);
    let from = run_to(&dir, &on_bump(five_curves(), None), 0.85);
    let out = dir.path().join("slid");
    let slide = SlideSpec {
        max_move: MaxMove::Fraction(0.05),
        pictures: false,
        ..SlideSpec::new(&from, &out)
    };
    let done = curvenet::app::slide(&slide, &Silent, &Cancel::never()).expect("slides");
    let record = &done.record;
    assert!(record.lambda_after >= record.lambda_before);
    let slid = RunFolder::open(&out).expect("a run folder");
    let answer = slid.result.answer.clone().expect("an answer");
    assert_eq!(answer.found.source, "slide");
    assert_eq!(slid.result.slide.as_ref(), Some(record));
    assert!(answer.found.length <= record.budget * (1.0 + 1e-9));
    assert!(out.join("before.obj").is_file() && out.join("answer.obj").is_file());
    // The exported curves, read back and analysed cold.
    let text = curvenet::report::export::curves_json(&slid, Which::Answer, true).expect("json");
    let read = parse_json_curves(&text, "answer.json").expect("reads back");
    let params = slid.result.setup.build.clone();
    let (net, _) = build_network(&read.curves, &params).expect("builds");
    let an = Analyzer::new(net, StabilityParams::default()).expect("analyzer");
    let lambda = an.analyze(&an.all(), None).expect("analyses").lambda();
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    assert!(
        rel(lambda, record.lambda_after) < 1e-6,
        "{lambda} vs {record:?}"
    );
    assert!(
        rel(lambda, answer.found.lambda) < 1e-6,
        "{lambda} vs {answer:?}"
    );
    // Every exported point on the surface and within the largest move of its drawn curve.
    let source = RunFolder::open(&from).expect("the run slid");
    let distance = MeshDistance::new(&mesh);
    let diagonal = (2.0 * SIZE * SIZE + 16.0f64).sqrt();
    for (c, curve) in read.curves.iter().enumerate() {
        let id = record.curves[c].from;
        let drawn = &network_polylines(&source.network, &[id], None)[0];
        for &p in &curve.points {
            let d = distance.distance(p).expect("on the mesh").0;
            assert!(d <= 1e-3 * diagonal, "curve {c}: {d} from the surface");
        }
        let moved = curvenet::slide::moves::largest_distance(&curve.points, drawn);
        assert!(
            moved <= record.max_move * (1.0 + 1e-9),
            "curve {c}: {moved}"
        );
    }
    // The viewer holds the curves before they slid, to show beside the slid ones.
    let page = curvenet::report::viewer::viewer_html(&slid, &Default::default()).expect("page");
    assert!(
        page.contains("\"before\":[{"),
        "the viewer's data has the curves before"
    );
    // The same slide again gives the same record, byte for byte.
    let again = dir.path().join("again");
    let slide2 = SlideSpec {
        out: again.clone(),
        ..slide.clone()
    };
    curvenet::app::slide(&slide2, &Silent, &Cancel::never()).expect("slides again");
    let a = std::fs::read_to_string(out.join("result.json")).expect("result");
    let b = std::fs::read_to_string(again.join("result.json")).expect("result");
    let strip = |s: &str| {
        s.replace(out.to_str().unwrap(), "")
            .replace(again.to_str().unwrap(), "")
    };
    assert_eq!(strip(&a), strip(&b));
}

#[test]
fn each_slid_curve_keeps_its_own_end_supports() {
    // Curve 4 is pinned at both ends by a supports file, the others clamped: the slid run,
    // a network of the answer's curves only, holds each curve's ends as the run did.
    let dir = TempDir::new("slide-ends");
    std::fs::create_dir_all(dir.path()).expect("a folder");
    let file = dir.path().join("ends.json");
    std::fs::write(
        &file,
        r#"{"format": "curvenet-supports", "version": 1, "supports": [
            {"curve": 4, "end": "start", "support": "pinned"},
            {"curve": 4, "end": "end", "support": "pinned"}]}"#,
    )
    .expect("writes");
    let from = run_to(&dir, &on_bump(five_curves(), Some(file)), 0.85);
    let out = dir.path().join("slid");
    let slide = SlideSpec {
        max_move: MaxMove::Fraction(0.05),
        pictures: false,
        ..SlideSpec::new(&from, &out)
    };
    let done = curvenet::app::slide(&slide, &Silent, &Cancel::never()).expect("slides");
    let source = RunFolder::open(&from).expect("the run");
    let slid = RunFolder::open(&out).expect("the slid run");
    let (all, own) = (
        &source.result.setup.build.ends,
        &slid.result.setup.build.ends,
    );
    assert_eq!(all.len(), 5, "the run holds curve 4's ends: {all:?}");
    assert!(all[4].iter().all(|e| e.is_some()));
    assert_eq!(own.len(), done.record.curves.len());
    for (i, c) in done.record.curves.iter().enumerate() {
        assert_eq!(
            own[i], all[c.from],
            "slid curve {i} (curve {} of the run)",
            c.from
        );
    }
    for (i, rod) in slid.network.rods.iter().enumerate() {
        let from = done.record.curves[i].from;
        let held = source.network.rods[from].end_support(true);
        assert_eq!(rod.end_support(true), held, "slid curve {i}'s start");
    }
}

#[test]
fn a_cancelled_slide_keeps_the_best_so_far_and_constraints_hold() {
    let mesh = bump(40);
    let cancel = Cancel::new();
    cancel.cancel();
    let slider = Slider::new(
        problem(four_curves(), 1e9),
        Some(&mesh),
        SlideParams::default(),
    )
    .expect("s");
    let out = slider.run(&cancel, &|_| {}).expect("slides");
    assert!(out.search.cancelled);
    assert_eq!(out.after.lambda.to_bits(), out.before.lambda.to_bits());
    // Under the connected constraint every network taken is one structure.
    let p = SlideProblem {
        constraints: curvenet::constraints::ConstraintParams {
            connected: true,
            min_curves: Some(4),
            ..Default::default()
        },
        ..problem(four_curves(), 1e9)
    };
    let params = SlideParams {
        max_move: MaxMove::Fraction(0.2),
        max_evaluations: 40,
        ..SlideParams::default()
    };
    let out = Slider::new(p, Some(&mesh), params)
        .expect("slider")
        .run(&Cancel::never(), &|_| {})
        .expect("slides");
    assert!(out.after.feasible);
    let net = &out.after.network;
    let all: Vec<usize> = (0..4).collect();
    let parts = curvenet::network::subnet::curve_components(
        4,
        &all,
        net.joints
            .iter()
            .map(|j| j.curves.iter().map(|&c| c as usize).collect::<Vec<_>>()),
    );
    assert_eq!(parts.len(), 1, "{parts:?}");
}

#[test]
fn a_symmetric_run_slides_its_orbits_together_and_stays_symmetric() {
    use curvenet::constraints::{ConstraintParams, SymmetryOption, symmetry};
    let dir = TempDir::new("slide-symmetric");
    // A square of four curves on the bump, one orbit of its quarter turns.
    let curves = vec![
        lifted((2.0, 0.0), (2.0, SIZE), 1),
        lifted((0.0, 2.0), (SIZE, 2.0), 2),
        lifted((8.0, 0.0), (8.0, SIZE), 3),
        lifted((0.0, 8.0), (SIZE, 8.0), 4),
        lifted((0.0, 5.0), (SIZE, 5.0), 5),
        lifted((5.0, 0.0), (5.0, SIZE), 6),
    ];
    let run = RunSpec {
        budget: Some(Budget::Fraction(0.7)),
        constraints: ConstraintParams {
            symmetry: SymmetryOption::Rotate(4),
            ..ConstraintParams::default()
        },
        ..RunSpec::new(dir.path().join("run"))
    };
    let from = recorded_run(&on_bump(curves, None), &ModelOptions::default(), run);
    let out = dir.path().join("slid");
    let slide = SlideSpec {
        max_move: MaxMove::Fraction(0.05),
        ..SlideSpec::new(&from, &out)
    };
    let done = curvenet::app::slide(&slide, &Silent, &Cancel::never()).expect("slides");
    let record = &done.record;
    // The before/after picture is written with the slid run's pictures.
    let png = std::fs::read(out.join("slide.png")).expect("slide.png");
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 10_000,
        "{}",
        png.len()
    );
    // Every curve of the orbit moves, with its leader's coefficients.
    let orbit: Vec<_> = record.curves.iter().filter(|c| c.from < 4).collect();
    assert_eq!(orbit.len(), 4, "{record:?}");
    assert!(orbit.iter().all(|c| c.free));
    assert!(
        orbit
            .iter()
            .all(|c| c.coefficients == orbit[0].coefficients)
    );
    assert!(record.lambda_after > record.lambda_before, "{record:?}");
    // The slid network, built cold from its exported curves: the same λ_eq, and the symmetry.
    let slid = RunFolder::open(&out).expect("a run folder");
    let text = curvenet::report::export::curves_json(&slid, Which::Answer, true).expect("json");
    let read = parse_json_curves(&text, "answer.json").expect("reads back");
    let (net, _) = build_network(&read.curves, &slid.result.setup.build).expect("builds");
    let found = symmetry::find(&net, SymmetryOption::Rotate(4), symmetry::DEFAULT_TOLERANCE)
        .expect("the slid network keeps its quarter turns");
    assert!(found[0].orbits.iter().any(|o| o.len() == 4), "{found:?}");
    let an = Analyzer::new(net, StabilityParams::default()).expect("analyzer");
    let lambda = an.analyze(&an.all(), None).expect("analyses").lambda();
    let rel = (lambda - record.lambda_after).abs() / record.lambda_after.abs();
    assert!(rel < 1e-6, "{lambda} vs {}", record.lambda_after);
}

#[test]
fn a_group_moves_with_one_set_of_coefficients() {
    use curvenet::slide::{Tie, TieMap};
    let p = SlideProblem {
        ties: vec![Tie {
            curve: 1,
            leader: 0,
            map: TieMap::Shared,
        }],
        ..problem(four_curves(), 1e9)
    };
    let params = SlideParams {
        pinned: vec![2, 3],
        max_evaluations: 30,
        ..SlideParams::default()
    };
    let slider = Slider::new(p, Some(&bump(40)), params).expect("slider");
    assert_eq!(slider.dimension(), 3, "the group's one family");
    assert!(slider.moving(1));
    let out = slider.run(&Cancel::never(), &|_| {}).expect("slides");
    assert_eq!(out.coefficients[0], out.coefficients[1]);
    assert!(out.coefficients[2].is_empty() && out.coefficients[3].is_empty());
}

#[test]
fn slide_rounds_alternate_a_local_search_and_a_slide_and_the_best_slide_is_the_answer() {
    let dir = TempDir::new("slide-rounds");
    let mut curves = five_curves();
    curves.push(lifted((6.0, 0.0), (6.0, SIZE), 6));
    let run = RunSpec {
        budget: Some(Budget::Fraction(0.7)),
        slide: Some(SlideSpec {
            rounds: 2,
            ..SlideSpec::new("", "")
        }),
        ..RunSpec::new(dir.path().join("run"))
    };
    let from = recorded_run(&on_bump(curves, None), &ModelOptions::default(), run);
    let slid = RunFolder::open(&from.join("slide")).expect("the slid run");
    let record = slid.result.slide.clone().expect("a slide record");
    let rounds = &record.rounds;
    assert_eq!(rounds.len(), 2, "{record:?}");
    // Each round starts from the last slide; the local search starts from the slid network
    // (measured among every curve: within a hair of its own objective), the slide after it
    // from the local search's network.
    assert_eq!(rounds[1].start.to_bits(), rounds[0].slid.to_bits());
    for r in rounds {
        assert!(r.local_search >= r.start * (1.0 - 1e-2), "{r:?}");
        assert!(r.slid >= r.local_search * (1.0 - 1e-2), "{r:?}");
    }
    // The answer is the best of every slide (the first slide's is round 0), a later one only
    // for a gain (more than 1e-6 relative: here round 2 slides back to round 1's network, a
    // hair above it), and says which.
    let values = [rounds[0].start, rounds[0].slid, rounds[1].slid];
    let best = (1..3).fold(0, |b, k| match is_gain(values[k], values[b]) {
        true => k,
        false => b,
    });
    assert!(best > 0, "here a round's slide is a gain: {values:?}");
    assert_eq!(record.answer_round, Some(best), "{values:?}");
    assert_eq!(record.lambda_after.to_bits(), values[best].to_bits());
    let answer = slid.result.answer.clone().expect("an answer");
    assert_eq!(answer.found.source, "slide");
    assert!(answer.found.length <= record.budget * (1.0 + 1e-9));
    // The others are kept: each round's slid run, and the first slide's when a round won.
    for k in 1..=2 {
        let r = RunFolder::open(&from.join("slide").join(format!("rounds/{k}/slid"))).expect("run");
        let own = r.result.slide.expect("its record");
        assert_eq!(own.lambda_after.to_bits(), values[k].to_bits());
    }
    if best > 0 {
        let first = RunFolder::open(&from.join("slide/rounds/0/slid")).expect("the first slide");
        let own = first.result.slide.clone().expect("its record");
        assert_eq!(own.lambda_after.to_bits(), values[0].to_bits());
        assert!(own.rounds.is_empty());
        // Each folder is a whole run: the answer's equilibrium is the winning round's, and
        // the first slide's went with it.
        let won = RunFolder::open(&from.join(format!("slide/rounds/{best}/slid"))).expect("run");
        let u = |r: &RunFolder| r.displacement_of(Which::Answer).expect("its equilibrium");
        assert_eq!(u(&slid), u(&won));
        assert_eq!(u(&first).len(), first.network.dofs());
        // The swap leaves no file under a temporary name.
        let names = std::fs::read_dir(from.join("slide/rounds/0/slid")).expect("lists");
        for n in names {
            let n = n.expect("an entry").file_name();
            assert!(!n.to_string_lossy().contains(".tmp."), "{n:?}");
        }
    }
    // The answer's exported curves analysed cold give its objective; every point within the
    // largest move of the curve as drawn in the run (the moves of the rounds do not add up).
    let text = curvenet::report::export::curves_json(&slid, Which::Answer, true).expect("json");
    let read = parse_json_curves(&text, "answer.json").expect("reads back");
    let (net, _) = build_network(&read.curves, &slid.result.setup.build).expect("builds");
    let an = Analyzer::new(net, StabilityParams::default()).expect("analyzer");
    let lambda = an.analyze(&an.all(), None).expect("analyses").lambda();
    assert!(
        (lambda - record.lambda_after).abs() < 1e-6 * record.lambda_after.abs(),
        "{lambda} vs {record:?}"
    );
    let source = RunFolder::open(&from).expect("the run");
    for (i, curve) in read.curves.iter().enumerate() {
        let id = match best {
            0 => record.curves[i].from,
            k => rounds[k - 1].curves[record.curves[i].from],
        };
        let drawn = &network_polylines(&source.network, &[id], None)[0];
        let moved = curvenet::slide::moves::largest_distance(&curve.points, drawn);
        assert!(
            moved <= record.max_move * (1.0 + 1e-3),
            "curve {id}: {moved}"
        );
    }
    // Sliding again into the same folder starts afresh: the earlier slide's rounds go with
    // its other files (and the next time, its pictures).
    let again = SlideSpec::new(&from, from.join("slide"));
    curvenet::app::slide(&again, &Silent, &Cancel::never()).expect("slides into it again");
    assert!(!from.join("slide/rounds").exists());
    assert!(from.join("slide/slide.png").is_file());
    curvenet::app::slide(&again, &Silent, &Cancel::never()).expect("and again");
    let slid = RunFolder::open(&from.join("slide")).expect("the slid run");
    assert!(slid.result.slide.expect("a record").rounds.is_empty());
}

/// The physical model of the physical tests: steel tubes of radius 0.05 m on the bump in
/// metres, on their first frequency; `loads` a loads file.
fn steel(loads: Option<&std::path::Path>) -> ModelOptions {
    use curvenet::physics::PhysicalOptions;
    ModelOptions {
        radius: Some(0.05),
        objective: curvenet::stability::Objective::Frequency,
        physical: PhysicalOptions {
            units: Some("m".into()),
            material: Some("steel".into()),
            loads: loads.map(|l| l.display().to_string()),
            ..Default::default()
        },
        ..ModelOptions::default()
    }
}

#[test]
fn a_physical_run_slides_on_its_first_frequency_under_its_largest_deviation() {
    let dir = TempDir::new("slide-physical");
    let model = steel(None);
    let limit = 1.0;
    let run = RunSpec {
        budget: Some(Budget::Fraction(0.85)),
        constraints: curvenet::constraints::ConstraintParams {
            max_deviation: Some(limit),
            ..Default::default()
        },
        ..RunSpec::new(dir.path().join("run"))
    };
    let from = recorded_run(&on_bump(five_curves(), None), &model, run);
    let out = dir.path().join("slid");
    let slide = SlideSpec {
        pictures: false,
        ..SlideSpec::new(&from, &out)
    };
    let done = curvenet::app::slide(&slide, &Silent, &Cancel::never()).expect("slides");
    let record = &done.record;
    assert_eq!(record.objective, "frequency");
    assert!(record.lambda_after >= record.lambda_before, "{record:?}");
    // The slid answer's physical figures, recomputed for it.
    let slid = RunFolder::open(&out).expect("a run folder");
    let answer = slid.result.answer.clone().expect("an answer");
    assert!(answer.physical.is_some(), "{answer:?}");
    assert!(slid.result.setup.physical_model.is_some());
    // Its exported curves analysed cold in the physical model: the recorded μ_min, and the
    // largest deviation under self-weight, measured as the run measures it, within the limit.
    let text = curvenet::report::export::curves_json(&slid, Which::Answer, true).expect("json");
    let read = parse_json_curves(&text, "answer.json").expect("reads back");
    let (net, _) = build_network(&read.curves, &slid.result.setup.build).expect("builds");
    let resolved = model.resolve(None, &[]).expect("model");
    let mut physical = resolved.physical.expect("physical");
    physical.rest = vec![Default::default(); net.rods.len()];
    let an = Analyzer::new(net, slid.result.setup.stability.clone())
        .and_then(|a| a.with_physical(physical))
        .expect("analyzer");
    let analysis = an.analyze(&an.all(), None).expect("analyses");
    let mu = analysis.lambda();
    assert!(
        (mu - record.lambda_after).abs() < 1e-6 * mu.abs(),
        "{mu} vs {record:?}"
    );
    let all: Vec<usize> = (0..an.network().rods.len()).collect();
    let deviation = an
        .structure_deviation(&all, &analysis.displacement)
        .expect("a deviation");
    let recorded = record.deviation.expect("the slid network's deviation");
    assert!(recorded <= limit, "{recorded}");
    assert!(
        (deviation - recorded).abs() <= 1e-6 * recorded,
        "{deviation} vs {recorded}"
    );
}

#[test]
fn a_physical_run_with_its_own_materials_pre_bent_curves_and_point_loads_slides() {
    let dir = TempDir::new("slide-physical-own");
    std::fs::create_dir_all(dir.path()).expect("a folder");
    // Curve 1 of aluminium, curve 3 pre-bent at rest; a point load at curve 3's middle.
    let curves = five_curves();
    let spec = |c: usize| match c {
        1 => r#", "material": "aluminium""#,
        3 => r#", "rest": "pre-bent""#,
        _ => "",
    };
    let json = |curves: &[Polyline], spec: &dyn Fn(usize) -> &'static str| {
        let items: Vec<String> = (curves.iter().enumerate())
            .map(|(c, p)| {
                let pts: Vec<String> = (p.points.iter())
                    .map(|q| format!("[{:e}, {:e}, {:e}]", q.x, q.y, q.z))
                    .collect();
                format!(r#"{{"points": [{}]{}}}"#, pts.join(", "), spec(c))
            })
            .collect();
        format!(
            r#"{{"format": "curvenet-curves", "version": 1, "curves": [{}]}}"#,
            items.join(",\n")
        )
    };
    let file = dir.path().join("curves.json");
    std::fs::write(&file, json(&curves, &spec)).expect("writes");
    let at = [3.0, 5.0, height(3.0, 5.0)];
    let loads = dir.path().join("loads.json");
    std::fs::write(
        &loads,
        format!(
            r#"{{"cases": [{{"name": "G", "self_weight": true}},
                {{"name": "P", "points": [{{"at": [{}, {}, {}], "force": [0, 0, -1000]}}]}}]}}"#,
            at[0], at[1], at[2]
        ),
    )
    .expect("writes");
    let input = InputSpec {
        mesh: Some(MeshSource::Given {
            mesh: bump(40),
            name: "bump".into(),
        }),
        edge_length: Some(0.5),
        ..InputSpec::new(CurveSource::Files(vec![file]))
    };
    let model = steel(Some(&loads));
    // Every curve kept; the pre-bent curve alone moves.
    let run = RunSpec {
        budget: Some(Budget::Length(100.0)),
        ..RunSpec::new(dir.path().join("run"))
    };
    let from = recorded_run(&input, &model, run);
    let out = dir.path().join("slid");
    let slide = SlideSpec {
        pictures: false,
        max_move: MaxMove::Fraction(0.05),
        pin: vec![0, 1, 2, 4],
        ..SlideSpec::new(&from, &out)
    };
    let done = curvenet::app::slide(&slide, &Silent, &Cancel::never()).expect("slides");
    let record = &done.record;
    let slid = RunFolder::open(&out).expect("a run folder");
    let position = |id: usize| {
        record
            .curves
            .iter()
            .position(|c| c.from == id)
            .expect("kept")
    };
    let (aluminium, bent) = (position(1), position(3));
    assert!(record.lambda_after > record.lambda_before, "{record:?}");
    assert!(record.curves[bent].largest_move > 0.01, "{record:?}");
    // Each curve keeps its own material and rest shape, by its place in the slid network.
    let own = slid.result.setup.physical_model.clone().expect("physical");
    assert_eq!(own.pre_bent, vec![bent]);
    assert_eq!(
        own.physical
            .curves
            .iter()
            .map(|o| o.curve)
            .collect::<Vec<_>>(),
        vec![aluminium]
    );
    // The point load went with curve 3: on the slid curve, where it was along it.
    let slid_curves = network_polylines(&slid.network, &[bent], None);
    let moved = own.loads.as_ref().expect("loads").cases[1].points[0].at;
    let off = curvenet::slide::moves::largest_distance(&[moved.into()], &slid_curves[0]);
    assert!(off < 1e-9 * SIZE, "{moved:?} is {off} off the slid curve");
    // `curvenet analyze` of the exported curves with the same per-curve material and rest
    // shapes and the moved loads: the recorded objective, to 1e-6.
    let text = curvenet::report::export::curves_json(&slid, Which::Answer, true).expect("json");
    let read = parse_json_curves(&text, "answer.json").expect("reads back");
    let exported = dir.path().join("answer.json");
    let own_spec = |c: usize| match c {
        c if c == aluminium => spec(1),
        c if c == bent => spec(3),
        _ => "",
    };
    std::fs::write(&exported, json(&read.curves, &own_spec)).expect("writes");
    let cold = InputSpec {
        curves: CurveSource::Files(vec![exported]),
        ..input.clone()
    };
    let mut setup = Setup::new(&cold, &model).expect("set-up");
    let analysed =
        curvenet::app::analyze(&mut setup, &[], &curvenet::words::Recorded).expect("analyses");
    let mu = analysed.analysis.lambda();
    assert!(
        (mu - record.lambda_after).abs() < 1e-6 * mu.abs(),
        "{mu} vs {record:?}"
    );
}
