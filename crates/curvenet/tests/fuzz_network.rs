//! Fuzzing network construction: `network::build_network` on random polylines must return a
//! network or a clean error, never panic, and every network it returns must be sound.
//!
//! The curves are made from recipes that aim at the hard cases: random points on an integer
//! grid (exact crossings at polyline vertices, collinear and overlapping pieces), random real
//! points, straight lines, near-duplicate points, copies of other curves (coincident, reversed,
//! shifted by a hair), closed polygons, spokes through one common point (many curves at one
//! joint), at scales from 1e-35 to 1e35 and with edge lengths from far below to far above the
//! curves' segments (and invalid ones: 0, negative, NaN, infinite).
//!
//! For every network returned: positions are finite, every rest length is positive and finite,
//! vertex indices are in range, every joint has at least two curve passes (and every vertex with
//! two passes is a joint), anchors sit on their rod, and the energy, gradient and Hessian at rest
//! are finite. The input checks of `network::checks` get random meshes (with missing vertices,
//! non-finite coordinates and degenerate faces) and must not panic either.
//!
//! Cases per property: `CURVENET_FUZZ_CASES` (or `PROPTEST_CASES`), default small so that CI
//! stays fast; for a long local run, e.g. `CURVENET_FUZZ_CASES=200000 cargo test --release
//! --test fuzz_network`. Failing seeds are kept in `tests/fuzz_regressions/`; inputs that once
//! broke the build are replayed by `regressions_still_build` from
//! `tests/fuzz_regressions/network/*.json`.

mod common;

use common::fuzz_config;
use curvenet::geom::Vec3;
use curvenet::io::{Origin, Polyline, TriMesh};
use curvenet::network::checks::{self, FAR_FROM_MESH};
use curvenet::network::{BuildParams, Network, build_network};
use curvenet::rod::{ActiveSet, EnergyModel, Material, Supports};
use proptest::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One curve's recipe.
#[derive(Clone, Debug)]
enum Shape {
    /// These points.
    Points(Vec<[f64; 3]>),
    /// `n` evenly spaced points from `a` to `b`.
    Line { a: [f64; 3], b: [f64; 3], n: usize },
    /// The points of an earlier curve (modulo the count), maybe reversed, shifted along x.
    Copy {
        of: usize,
        reverse: bool,
        shift: f64,
    },
    /// Every point followed by copies a relative `eps` away.
    NearDuplicates {
        base: Vec<[f64; 3]>,
        eps: f64,
        copies: usize,
    },
    /// A regular polygon of `n` corners around `centre` in a tilted plane.
    Polygon {
        centre: [f64; 3],
        radius: f64,
        n: usize,
        tilt: f64,
    },
    /// A line through the origin at angle `angle`, `n` points: spokes share one point.
    Spoke { angle: f64, n: usize },
}

/// A whole scene: curve recipes, closure flags, the scale and offset applied to every
/// coordinate, and the build parameters.
#[derive(Clone, Debug)]
struct Scene {
    shapes: Vec<(Shape, bool)>,
    scale: f64,
    offset: [f64; 3],
    h: EdgeLength,
    supports: Supports,
    tolerance: f64,
    merge: Option<f64>,
}

/// The target edge length: relative to the median input segment, or an absolute value (for the
/// invalid and extreme ones).
#[derive(Clone, Copy, Debug)]
enum EdgeLength {
    Relative(f64),
    Absolute(f64),
}

fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => (-3i32..=3).prop_map(f64::from),
        4 => -3.0..3.0f64,
        1 => Just(0.0),
        1 => (-3i32..=3).prop_map(|i| f64::from(i) + 1e-13),
        // Near the crossing tolerance (1e-3 of a unit segment): chains of near-joints.
        2 => ((-3i32..=3), prop::sample::select(&[-2e-3, -1e-3, -5e-4, 5e-4, 9.99e-4, 1e-3, 1.5e-3][..]))
            .prop_map(|(i, d)| f64::from(i) + d),
    ]
}

fn point() -> impl Strategy<Value = [f64; 3]> {
    prop_oneof![
        3 => (coordinate(), coordinate()).prop_map(|(x, y)| [x, y, 0.0]),
        2 => [coordinate(), coordinate(), coordinate()],
    ]
}

fn shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        4 => prop::collection::vec(point(), 0..10).prop_map(Shape::Points),
        2 => (point(), point(), 0usize..8).prop_map(|(a, b, n)| Shape::Line { a, b, n }),
        2 => (0usize..8, any::<bool>(), prop_oneof![Just(0.0), Just(1e-12), Just(1e-5), -1.0..1.0f64])
            .prop_map(|(of, reverse, shift)| Shape::Copy { of, reverse, shift }),
        1 => (
            prop::collection::vec(point(), 1..6),
            prop_oneof![Just(0.0), Just(1e-16), Just(1e-12), Just(1e-9), Just(1e-6)],
            1usize..3
        )
            .prop_map(|(base, eps, copies)| Shape::NearDuplicates { base, eps, copies }),
        1 => (point(), 0.1..3.0f64, 2usize..9, -1.0..1.0f64)
            .prop_map(|(centre, radius, n, tilt)| Shape::Polygon { centre, radius, n, tilt }),
        2 => (0.0..std::f64::consts::PI, 2usize..6).prop_map(|(angle, n)| Shape::Spoke { angle, n }),
    ]
}

fn edge_length() -> impl Strategy<Value = EdgeLength> {
    prop_oneof![
        12 => (-2.5..1.5f64).prop_map(|e| EdgeLength::Relative(10f64.powf(e))),
        1 => prop_oneof![
            Just(0.0),
            Just(-1.0),
            Just(f64::NAN),
            Just(f64::INFINITY),
            Just(f64::NEG_INFINITY),
            Just(1e-300),
            Just(f64::MIN_POSITIVE),
            Just(1e300),
            Just(f64::MAX),
        ]
        .prop_map(EdgeLength::Absolute),
        1 => Just(EdgeLength::Relative(1e-9)),
    ]
}

fn scene() -> impl Strategy<Value = Scene> {
    (
        prop::collection::vec((shape(), any::<bool>()), 1..7),
        prop_oneof![
            8 => Just(1.0),
            2 => (-3i32..=3).prop_map(|e| 10f64.powi(e)),
            1 => (-35i32..=35).prop_map(|e| 10f64.powi(e)),
            1 => prop_oneof![Just(1e-160), Just(1e160), Just(1e300)],
        ],
        prop_oneof![
            6 => Just([0.0; 3]),
            1 => [-1e6..1e6f64, -1e6..1e6f64, -1e6..1e6f64],
            1 => Just([1e15, -1e15, 0.0]),
        ],
        edge_length(),
        prop_oneof![Just(Supports::Clamped), Just(Supports::Pinned)],
        prop_oneof![8 => Just(1e-3), 1 => 1e-6..0.49f64, 1 => Just(0.4999)],
        prop_oneof![4 => Just(None), 1 => (0.01..0.99f64).prop_map(Some)],
    )
        .prop_map(
            |(shapes, scale, offset, h, supports, tolerance, merge)| Scene {
                shapes,
                scale,
                offset,
                h,
                supports,
                tolerance,
                merge,
            },
        )
}

/// The polylines of a scene.
fn curves_of(scene: &Scene) -> Vec<Polyline> {
    let mut raw: Vec<Vec<[f64; 3]>> = Vec::new();
    for (shape, _) in &scene.shapes {
        let pts: Vec<[f64; 3]> = match shape {
            Shape::Points(p) => p.clone(),
            Shape::Line { a, b, n } => (0..*n)
                .map(|i| {
                    let t = if *n > 1 {
                        i as f64 / (*n - 1) as f64
                    } else {
                        0.0
                    };
                    [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]))
                })
                .collect(),
            Shape::Copy { of, reverse, shift } => {
                let mut p = if raw.is_empty() {
                    vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
                } else {
                    raw[of % raw.len()].clone()
                };
                if *reverse {
                    p.reverse();
                }
                for q in &mut p {
                    q[0] += shift;
                }
                p
            }
            Shape::NearDuplicates { base, eps, copies } => base
                .iter()
                .flat_map(|p| {
                    (0..=*copies).map(move |k| {
                        let d = eps * k as f64;
                        [p[0] + d * (1.0 + p[0].abs()), p[1] - d, p[2] + 0.5 * d]
                    })
                })
                .collect(),
            Shape::Polygon {
                centre,
                radius,
                n,
                tilt,
            } => (0..*n)
                .map(|i| {
                    let a = 2.0 * std::f64::consts::PI * i as f64 / *n as f64;
                    [
                        centre[0] + radius * a.cos(),
                        centre[1] + radius * a.sin(),
                        centre[2] + tilt * radius * a.sin(),
                    ]
                })
                .collect(),
            Shape::Spoke { angle, n } => (0..*n)
                .map(|i| {
                    let t = -1.0 + 2.0 * i as f64 / (*n - 1).max(1) as f64;
                    [t * angle.cos(), t * angle.sin(), 0.0]
                })
                .collect(),
        };
        raw.push(pts);
    }
    raw.into_iter()
        .zip(&scene.shapes)
        .enumerate()
        .map(|(i, (pts, (_, closed)))| Polyline {
            points: pts
                .iter()
                .map(|p| {
                    Vec3::new(
                        p[0] * scene.scale + scene.offset[0],
                        p[1] * scene.scale + scene.offset[1],
                        p[2] * scene.scale + scene.offset[2],
                    )
                })
                .collect(),
            closed: *closed,
            origin: Origin::new("fuzz", i + 1),
            label: None,
        })
        .collect()
}

/// Median input segment length over all curves (1 when there is none).
fn median_segment_length(curves: &[Polyline]) -> f64 {
    let mut lens: Vec<f64> = curves
        .iter()
        .flat_map(|c| {
            let n = c.points.len();
            let segs = if c.closed { n } else { n.saturating_sub(1) };
            (0..segs).map(move |k| c.points[k].dist(c.points[(k + 1) % n]))
        })
        .collect();
    if lens.is_empty() {
        return 1.0;
    }
    lens.sort_by(f64::total_cmp);
    lens[lens.len() / 2]
}

/// The build parameters of a scene.
fn params_of(scene: &Scene, curves: &[Polyline]) -> BuildParams {
    let h = match scene.h {
        EdgeLength::Absolute(h) => h,
        EdgeLength::Relative(r) => r * median_segment_length(curves),
    };
    BuildParams {
        edge_length: h,
        supports: scene.supports,
        ends: Vec::new(),
        end_frames: Vec::new(),
        tolerance: scene.tolerance,
        merge_joints_below: scene.merge,
    }
}

/// Builds and checks every invariant; `Err` describes the first violation.
fn check_build(curves: &[Polyline], params: &BuildParams) -> Result<(), String> {
    let (network, info) = match build_network(curves, params) {
        Ok(x) => x,
        Err(e) => {
            let text = e.to_string();
            return if text.is_empty() {
                Err("empty error message".into())
            } else {
                Ok(())
            };
        }
    };
    check_network(&network, curves)?;
    if info.vertices != network.vertex_count() || info.joints != network.joints.len() {
        return Err(format!("info counts disagree: {info:?}"));
    }
    if info.curves != curves.len() || info.isolated_curves.iter().any(|&c| c >= curves.len()) {
        return Err(format!("info curve ids out of range: {info:?}"));
    }
    if info.warnings.iter().any(|w| w.to_string().is_empty()) {
        return Err("empty warning".into());
    }
    // Determinism: a second build is identical.
    let (again, info2) = build_network(curves, params).map_err(|e| format!("rebuild: {e}"))?;
    if again != network || info2 != info {
        return Err("two builds of the same input differ".into());
    }
    Ok(())
}

/// The invariants of a built network.
fn check_network(network: &Network, curves: &[Polyline]) -> Result<(), String> {
    let n = network.vertex_count();
    if network.rods.len() != curves.len() {
        return Err(format!(
            "{} rods for {} curves",
            network.rods.len(),
            curves.len()
        ));
    }
    if let Some(p) = network.positions.iter().find(|p| !p.is_finite()) {
        return Err(format!("non-finite position {p:?}"));
    }
    let mut passes = vec![0usize; n];
    for (c, rod) in network.rods.iter().enumerate() {
        let m = rod.vertices.len();
        let edges = if rod.closed { m } else { m.saturating_sub(1) };
        if m < 2 || (rod.closed && m < 3) {
            return Err(format!("rod {c} has {m} vertices"));
        }
        if rod.rest_lengths.len() != edges {
            return Err(format!(
                "rod {c}: {} rest lengths for {edges} edges",
                rod.rest_lengths.len()
            ));
        }
        if let Some(l) = rod
            .rest_lengths
            .iter()
            .find(|l| !(l.is_finite() && **l > 0.0))
        {
            return Err(format!("rod {c} has rest length {l}"));
        }
        if let Some(v) = rod.vertices.iter().find(|&&v| v as usize >= n) {
            return Err(format!("rod {c} has vertex {v} of {n}"));
        }
        for &v in &rod.vertices {
            passes[v as usize] += 1;
        }
        if rod.closed && !rod.anchors.is_empty() {
            return Err(format!("closed rod {c} has anchors"));
        }
        if let Some(a) = rod.anchors.iter().find(|a| !rod.vertices.contains(a)) {
            return Err(format!("rod {c} anchors vertex {a}, not on it"));
        }
        for j in 0..edges {
            let (a, b) = rod.edge(j);
            if a == b {
                return Err(format!("rod {c} edge {j} joins vertex {a} to itself"));
            }
        }
    }
    let mut joint_vertex = vec![false; n];
    for (k, joint) in network.joints.iter().enumerate() {
        let v = joint.vertex as usize;
        if v >= n {
            return Err(format!("joint {k} at vertex {v} of {n}"));
        }
        joint_vertex[v] = true;
        if passes[v] < 2 {
            return Err(format!("joint {k} (vertex {v}) has {} pass(es)", passes[v]));
        }
        if joint.curves.is_empty() || joint.curves.windows(2).any(|w| w[0] >= w[1]) {
            return Err(format!("joint {k} curve list {:?}", joint.curves));
        }
        for &c in &joint.curves {
            if !network
                .rods
                .get(c as usize)
                .is_some_and(|r| r.vertices.contains(&joint.vertex))
            {
                return Err(format!("joint {k} lists curve {c}, which misses it"));
            }
        }
    }
    if let Some(v) = (0..n).find(|&v| passes[v] >= 2 && !joint_vertex[v]) {
        return Err(format!("vertex {v} has {} passes but no joint", passes[v]));
    }
    if let Some(v) = (0..n).find(|&v| passes[v] == 0) {
        return Err(format!("vertex {v} belongs to no rod"));
    }
    let model = EnergyModel::new(network, &Material::default());
    let u = vec![0.0; network.dofs()];
    let all = ActiveSet::all(network.rods.len());
    let e = model.energy(&u, &all);
    if !(e.is_finite() && e >= 0.0) {
        return Err(format!("energy at rest {e}"));
    }
    let a = model.assemble(&u, &all, true);
    if !a.energy.is_finite() {
        return Err(format!("assembled energy {}", a.energy));
    }
    if let Some(g) = a.grad.iter().find(|g| !g.is_finite()) {
        return Err(format!("gradient entry {g}"));
    }
    if let Some(h) = a.hess.iter().find(|h| !h.is_finite()) {
        return Err(format!("Hessian entry {h}"));
    }
    Ok(())
}

/// A random mesh: some vertices (maybe non-finite), faces that may point nowhere.
fn mesh() -> impl Strategy<Value = TriMesh> {
    (
        prop::collection::vec(
            prop_oneof![
                8 => point(),
                1 => Just([f64::NAN, 0.0, 0.0]),
                1 => Just([1e300, -1e300, 0.0]),
            ],
            0..12,
        ),
        prop::collection::vec(prop::array::uniform3(0u32..14), 0..20),
    )
        .prop_map(|(v, faces)| TriMesh {
            vertices: v.into_iter().map(Vec3::from).collect(),
            faces,
        })
}

proptest! {
    #![proptest_config(fuzz_config(1500))]

    /// `build_network` never panics and every network it returns is sound.
    #[test]
    fn build_network_is_total_and_sound(scene in scene()) {
        let curves = curves_of(&scene);
        let params = params_of(&scene, &curves);
        if let Err(e) = check_build(&curves, &params) {
            // Keep the input for the regression folder.
            let case = RegressionCase { found: String::new(), curves: curves.clone(), params: params.clone() };
            return Err(TestCaseError::fail(format!(
                "{e}\ninput: {}",
                serde_json::to_string(&case).unwrap_or_default()
            )));
        }
    }
}

proptest! {
    #![proptest_config(fuzz_config(400))]

    /// The input checks (mesh defects, curves far from the mesh, curves that run together)
    /// never panic, whatever the mesh and the curves.
    #[test]
    fn input_checks_are_total(scene in scene(), mesh in mesh()) {
        let curves = curves_of(&scene);
        let found = checks::curves_far_from_mesh(&curves, &mesh, FAR_FROM_MESH);
        prop_assert!(found.curves.iter().all(|f| f.curve < curves.len() && f.far_points <= f.points));
        let _ = checks::far_from_mesh_warning(&found, "m.obj");
        let _ = checks::mesh_warnings(&mesh, "m.obj");
        for o in checks::overlapping_curves(&curves, scene.tolerance) {
            prop_assert!(o.a < o.b && o.b < curves.len() && o.length >= 0.0);
        }
        let index = checks::MeshDistance::new(&mesh);
        for c in &curves {
            for &p in &c.points {
                if let Some((d, t)) = index.distance(p) {
                    prop_assert!(d >= 0.0 && t < index.triangle_count());
                }
            }
        }
    }
}

/// A scene small enough to analyse quickly: edge lengths near the input's segments.
fn small_scene() -> impl Strategy<Value = Scene> {
    (scene(), 0.3..3.0f64).prop_map(|(mut s, h)| {
        s.h = EdgeLength::Relative(h);
        s
    })
}

proptest! {
    #![proptest_config(fuzz_config(40))]

    /// The whole analysis (equilibrium, eigenvalues, report) of any network that builds, with a
    /// rod radius from far too thin to far too thick and any curves removed, never panics, and
    /// its λ is a number.
    #[test]
    fn analysis_never_panics(
        scene in small_scene(),
        radius_exponent in -5.0..0.5f64,
        remove in prop::collection::vec(0usize..8, 0..3),
    ) {
        let curves = curves_of(&scene);
        let params = params_of(&scene, &curves);
        let Ok((network, _)) = build_network(&curves, &params) else {
            return Ok(());
        };
        prop_assume!(network.vertex_count() <= 2000);
        let lengths = network.rest_lengths();
        let median = {
            let mut l = lengths.clone();
            l.sort_by(f64::total_cmp);
            l[l.len() / 2]
        };
        let mut stability = curvenet::stability::StabilityParams::default();
        stability.material.radius = median * 10f64.powf(radius_exponent);
        let mut removed: Vec<usize> = remove.into_iter().filter(|&c| c < curves.len()).collect();
        removed.sort_unstable();
        removed.dedup();
        prop_assume!(removed.len() < curves.len());
        match curvenet::pipeline::analyze(&curves, &params, &stability, None, &removed, Vec::new()) {
            Ok(out) => prop_assert!(!out.report.lambda.is_nan(), "λ is NaN: {:?}", out.report),
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }
}

/// An input kept in `tests/fuzz_regressions/network/`.
#[derive(Debug, Serialize, Deserialize)]
struct RegressionCase {
    /// How the input was found and what it broke (free text; not used).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    found: String,
    curves: Vec<Polyline>,
    params: BuildParams,
}

/// Every input that once broke construction still builds to a sound network or a clean error.
#[test]
fn regressions_still_build() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions/network");
    let mut count = 0;
    let mut entries: Vec<_> = std::fs::read_dir(&dir)
        .expect("the regression folder exists")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    entries.sort();
    for path in entries {
        let text = std::fs::read_to_string(&path).unwrap();
        let case: RegressionCase =
            serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        if let Err(e) = check_build(&case.curves, &case.params) {
            panic!("{}: {e}", path.display());
        }
        count += 1;
    }
    assert!(count > 0, "no regression inputs in {}", dir.display());
}

/// Hand-made hard cases that must keep working.
#[test]
fn hand_made_hard_cases() {
    let line = |pts: &[[f64; 3]], closed: bool| Polyline {
        points: pts.iter().map(|&p| Vec3::from(p)).collect(),
        closed,
        origin: Origin::new("hand", 1),
        label: None,
    };
    let p = |h: f64| BuildParams {
        edge_length: h,
        ..BuildParams::default()
    };
    // Coincident curves: built, with a warning that they run together.
    let a = line(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]], false);
    let (net, info) = build_network(&[a.clone(), a.clone()], &p(0.1)).unwrap();
    check_network(&net, &[a.clone(), a.clone()]).unwrap();
    assert!(
        info.warnings
            .iter()
            .any(|w| w.to_string().contains("run together")),
        "{:?}",
        info.warnings
    );
    // A tiny h is refused before it exhausts memory.
    let e = build_network(std::slice::from_ref(&a), &p(1e-9)).unwrap_err();
    assert!(e.to_string().contains("vertices, more than"), "{e}");
    // Scenes out of the model's range are refused with the curve's place.
    let tiny = line(&[[0.0, 0.0, 0.0], [1e-40, 0.0, 0.0]], false);
    let e = build_network(&[tiny], &p(1e-41)).unwrap_err();
    assert!(e.to_string().starts_with("hand:1: curve 0:"), "{e}");
    assert!(e.to_string().contains("outside"), "{e}");
    let huge = line(&[[0.0, 0.0, 0.0], [1e200, 0.0, 0.0]], false);
    let e = build_network(&[huge], &p(1e199)).unwrap_err();
    assert!(e.to_string().contains("outside"), "{e}");
    // 32 spokes through one point: one joint with 32 curves.
    let spokes: Vec<Polyline> = (0..32)
        .map(|i| {
            let a = std::f64::consts::PI * i as f64 / 32.0;
            line(&[[-a.cos(), -a.sin(), 0.0], [a.cos(), a.sin(), 0.0]], false)
        })
        .collect();
    let (net, info) = build_network(&spokes, &p(0.25)).unwrap();
    check_network(&net, &spokes).unwrap();
    assert_eq!(info.max_curves_at_joint, 32);
    // A closed curve that crosses nothing floats free: a warning says so.
    let ring = line(&[[0.0, 0.0, 5.0], [1.0, 0.0, 5.0], [0.0, 1.0, 5.0]], true);
    let (_, info) = build_network(&[a, ring], &p(0.1)).unwrap();
    assert!(
        info.warnings
            .iter()
            .any(|w| w.to_string().contains("float free")),
        "{:?}",
        info.warnings
    );
}

/// Merged joints never fold a curve back on itself. Three lines: `a` along x, `b` and `c`
/// crossing it 0.8 apart and each other between them, so the three crossings lie within the
/// merge distance (0.6) of their neighbours in space and form one joint, while `a` passes
/// through it twice, 0.8 apart along it: pinned there twice, the piece between would be two
/// edges out and back (a fold, whose Hessian has huge negative eigenvalues). The passes are one.
#[test]
fn merged_joints_never_fold_a_curve() {
    let line = |a: Vec3, b: Vec3| Polyline {
        points: (0..=40).map(|i| a.lerp(b, i as f64 / 40.0)).collect(),
        closed: false,
        origin: Origin::new("<test>", 0),
        label: None,
    };
    let curves = vec![
        line(Vec3::new(-50.0, 0.0, 0.0), Vec3::new(50.0, 0.0, 0.0)),
        line(Vec3::new(-30.0, -30.0, 0.0), Vec3::new(30.0, 30.0, 0.0)),
        line(Vec3::new(30.8, -30.0, 0.0), Vec3::new(-29.2, 30.0, 0.0)),
    ];
    let params = BuildParams {
        edge_length: 10.0,
        merge_joints_below: Some(0.06),
        ..Default::default()
    };
    let (network, _) = build_network(&curves, &params).expect("builds");
    check_network(&network, &curves).expect("sound");
    assert_eq!(network.joints.len(), 1, "one merged joint");
    for (c, rod) in network.rods.iter().enumerate() {
        let v = &rod.vertices;
        assert!(
            v.windows(3).all(|w| w[0] != w[2]),
            "rod {c} folds back: {v:?}"
        );
        let j = network.joints[0].vertex;
        assert_eq!(v.iter().filter(|&&x| x == j).count(), 1, "rod {c}");
    }
}
