//! Supports along or normal to the surface's boundary: an end sliding along the boundary is
//! the end held along the world's axes where the two coincide; the same problem turned by a
//! rigid motion (network, surface and load) has the same frequencies and buckling factor; an
//! end off the boundary, or without a surface, is an error naming the line and how far.

mod common;

use common::{polyline, rel_diff};
use curvenet::app::end_frames::end_frame;
use curvenet::app::{CurveSource, GivenCurves, InputSpec, MeshSource, ModelOptions, Setup};
use curvenet::geom::Vec3;
use curvenet::io::{Origin, TriMesh};
use curvenet::material::{CurveSpec, EndSupport, Physical, RestShape, Section, presets};
use curvenet::network::{BuildParams, Network, build_network};
use curvenet::physics::cases::Loads;
use curvenet::physics::{PhysicalParams, PhysicalReport, analyze_physical};
use curvenet::rod::{ActiveSet, Supports};
use curvenet::units::LengthUnit;
use std::f64::consts::PI;

const L: f64 = 1000.0;

/// A rigid motion: a turn by `angle` about `axis` (unit), then a shift.
#[derive(Clone, Copy)]
struct Motion {
    axis: Vec3,
    angle: f64,
    shift: Vec3,
}

impl Motion {
    const NONE: Motion = Motion {
        axis: Vec3 {
            x: 0.0,
            y: 0.0,
            z: 1.0,
        },
        angle: 0.0,
        shift: Vec3 {
            x: 0.0,
            y: 0.0,
            z: 0.0,
        },
    };

    fn turn(&self, v: Vec3) -> Vec3 {
        let (a, c, s) = (self.axis, self.angle.cos(), self.angle.sin());
        v * c + a.cross(v) * s + a * a.dot(v) * (1.0 - c)
    }

    fn apply(&self, v: Vec3) -> Vec3 {
        self.turn(v) + self.shift
    }
}

/// A flat rectangle `[0, L] × [−L/2, L/2]` in z = 0, moved by `m`.
fn plate(m: Motion) -> TriMesh {
    let h = L / 2.0;
    TriMesh {
        vertices: [(0.0, -h), (L, -h), (L, h), (0.0, h)]
            .into_iter()
            .map(|(x, y)| m.apply(Vec3::new(x, y, 0.0)))
            .collect(),
        faces: vec![[0, 1, 2], [0, 2, 3]],
    }
}

/// Sliding along the bar's axis, which crosses the plate's edge x = L: held along that edge
/// and normal to the plate.
fn along_the_edge() -> EndSupport {
    EndSupport {
        surface: [true, false, true],
        ..EndSupport::FREE
    }
}

/// A straight steel bar from the plate's middle to its edge x = L, 50 edges, moved by `m`;
/// pinned at the start, its end held by `end` (with the plate's directions there).
fn bar(end: EndSupport, m: Motion) -> Network {
    let pts: Vec<Vec3> = (0..=50)
        .map(|i| m.apply(Vec3::new(L * i as f64 / 50.0, 0.0, 0.0)))
        .collect();
    let frame = end
        .uses_surface()
        .then(|| end_frame(Some(&plate(m)), pts[50], &end, "the bar's end").expect("on the edge"));
    let params = BuildParams {
        edge_length: L / 50.0,
        supports: Supports::Clamped,
        ends: vec![[Some(EndSupport::PINNED), Some(end)]],
        end_frames: if frame.is_some() {
            vec![[None, frame]]
        } else {
            Vec::new()
        },
        ..BuildParams::default()
    };
    build_network(&[polyline(pts, false)], &params)
        .expect("the bar builds")
        .0
}

/// The bar's analysis with 1 kN pressing on its end along it (turned by `m`).
fn analyze(net: &Network, m: Motion) -> PhysicalReport {
    let (at, f) = (
        m.apply(Vec3::new(L, 0.0, 0.0)),
        m.turn(Vec3::new(-1000.0, 0.0, 0.0)),
    );
    let loads = format!(
        r#"{{"cases": [{{"name": "P", "points": [{{"at": [{}, {}, {}], "force": [{}, {}, {}]}}]}}]}}"#,
        at.x, at.y, at.z, f.x, f.y, f.z
    );
    let mut params = PhysicalParams::new(Physical::uniform(
        LengthUnit::Millimetre,
        presets::preset("steel").unwrap(),
        Section::Solid { radius: 10.0 },
    ));
    params.rest = vec![RestShape::Straight; net.rods.len()];
    params.loads = Some(Loads::parse(&loads, "loads.json").expect("loads"));
    analyze_physical(net, &params, &ActiveSet::all(net.rods.len())).expect("analysis")
}

fn frequencies(r: &PhysicalReport) -> Vec<f64> {
    r.frequencies_hz
        .iter()
        .map(|f| f.expect("stable"))
        .collect()
}

#[test]
fn sliding_along_the_boundary_is_sliding_along_the_axes_it_coincides_with() {
    let world = analyze(
        &bar(
            EndSupport {
                fixed: [false, true, true],
                ..EndSupport::FREE
            },
            Motion::NONE,
        ),
        Motion::NONE,
    );
    let surface = analyze(&bar(along_the_edge(), Motion::NONE), Motion::NONE);
    let (fw, fs) = (frequencies(&world), frequencies(&surface));
    println!("world axes {fw:?}\nboundary   {fs:?}");
    for (a, b) in fw.iter().zip(&fs) {
        assert!(rel_diff(*a, *b) < 1e-12, "{a} vs {b}");
    }
    let (aw, as_) = (
        world.load_cases[0].buckling_factor.unwrap(),
        surface.load_cases[0].buckling_factor.unwrap(),
    );
    let euler = PI * PI * 210e3 * PI * 1e4 / 4.0 / (L * L) / 1000.0;
    println!("α_cr world {aw:.6}, boundary {as_:.6}, Euler {euler:.6}");
    assert!(rel_diff(aw, as_) < 1e-9, "{aw} vs {as_}");
    assert!(rel_diff(as_, euler) < 0.01, "{as_} vs {euler}");
}

#[test]
fn a_rigid_motion_of_network_surface_and_load_changes_nothing() {
    let m = Motion {
        axis: Vec3::new(0.3, -0.8, 0.52).normalized(),
        angle: 0.87,
        shift: Vec3::new(120.0, -40.0, 75.0),
    };
    let here = analyze(&bar(along_the_edge(), Motion::NONE), Motion::NONE);
    let there = analyze(&bar(along_the_edge(), m), m);
    let (fh, ft) = (frequencies(&here), frequencies(&there));
    println!("as drawn {fh:?}\nmoved    {ft:?}");
    for (a, b) in fh.iter().zip(&ft) {
        assert!(rel_diff(*a, *b) < 1e-7, "{a} vs {b}");
    }
    let (ah, at) = (
        here.load_cases[0].buckling_factor.unwrap(),
        there.load_cases[0].buckling_factor.unwrap(),
    );
    println!("α_cr as drawn {ah:.8}, moved {at:.8}");
    assert!(rel_diff(ah, at) < 1e-5, "{ah} vs {at}");
    // Held along the world's z axis alone instead, the moved bar's end is free across it in
    // one direction: a mechanism (a check that the directions matter).
    let skew = analyze(
        &bar(
            EndSupport {
                fixed: [false, false, true],
                ..EndSupport::FREE
            },
            m,
        ),
        m,
    );
    assert!(
        !skew.stable,
        "held along z alone, the moved bar swings about its pin"
    );
}

/// The set-up of the bar drawn in `bar.json` at line 7, its end held by `end`, on `mesh`.
fn set_up(end: EndSupport, end_at: f64, mesh: Option<TriMesh>) -> Result<Setup, String> {
    let mut curve = polyline(
        (0..=10)
            .map(|i| Vec3::new(end_at * i as f64 / 10.0, 0.0, 0.0))
            .collect(),
        false,
    );
    curve.origin = Origin::new("bar.json", 7);
    let given = GivenCurves {
        curves: vec![curve],
        groups: vec![None],
        specs: vec![CurveSpec {
            supports: [Some(EndSupport::PINNED), Some(end)],
            ..CurveSpec::default()
        }],
        files: vec!["bar.json".into()],
        ..GivenCurves::default()
    };
    let mut spec = InputSpec::new(CurveSource::Given(given));
    spec.mesh = mesh.map(|mesh| MeshSource::Given {
        mesh,
        name: "plate".into(),
    });
    Setup::new(&spec, &ModelOptions::default()).map_err(|e| e.to_string())
}

#[test]
fn the_set_up_finds_the_boundary_directions() {
    let setup = set_up(along_the_edge(), L, Some(plate(Motion::NONE))).expect("set-up");
    let frames = setup.inputs.build.end_frames[0][1].expect("the end's frame");
    let [t, _, n] = frames.0;
    assert!(
        (t[1].abs() - 1.0).abs() < 1e-12,
        "along the edge x = L: {t:?}"
    );
    assert!(
        (n[2].abs() - 1.0).abs() < 1e-12,
        "normal to the plate: {n:?}"
    );
}

#[test]
fn bad_surface_supports_are_named_with_their_line() {
    let Err(e) = set_up(along_the_edge(), L, None) else {
        panic!("no surface")
    };
    println!("{e}");
    assert!(e.contains("bar.json") && e.contains('7'), "{e}");
    assert!(e.contains("there is no surface"), "{e}");
    let Err(e) = set_up(along_the_edge(), L - 100.0, Some(plate(Motion::NONE))) else {
        panic!("off the boundary")
    };
    println!("{e}");
    assert!(e.contains("bar.json"), "{e}");
    assert!(
        e.contains("not on the surface's boundary") && e.contains("100.0 away"),
        "{e}"
    );
    // Normal to the surface only: anywhere on it, but not off it.
    let normal = EndSupport {
        surface: [false, false, true],
        ..EndSupport::PINNED
    };
    assert!(set_up(normal, L - 100.0, Some(plate(Motion::NONE))).is_ok());
    let mut lifted = plate(Motion::NONE);
    lifted.vertices.iter_mut().for_each(|v| v.z += 50.0);
    let Err(e) = set_up(normal, L, Some(lifted)) else {
        panic!("off the surface")
    };
    println!("{e}");
    assert!(
        e.contains("not on the surface") && e.contains("50.00 away"),
        "{e}"
    );
}

/// Two bars crossing on the plate (moved by `m`), each end held across the plate's edge and
/// normal to the plate, sliding along the edge.
fn cross(m: Motion) -> Network {
    let h = L / 2.0;
    let ends = [
        (Vec3::new(0.0, 0.0, 0.0), Vec3::new(L, 0.0, 0.0)),
        (Vec3::new(L / 2.0, -h, 0.0), Vec3::new(L / 2.0, h, 0.0)),
    ];
    let slide = EndSupport {
        surface: [false, true, true],
        ..EndSupport::FREE
    };
    let mesh = plate(m);
    let curves: Vec<_> = ends
        .iter()
        .map(|&(a, b)| {
            let pts = (0..=8)
                .map(|i| m.apply(a.lerp(b, i as f64 / 8.0)))
                .collect();
            polyline(pts, false)
        })
        .collect();
    let frames = curves
        .iter()
        .map(|c| {
            let at = [c.points[0], c.points[8]];
            at.map(|p| Some(end_frame(Some(&mesh), p, &slide, "an end").expect("on the edge")))
        })
        .collect();
    let params = BuildParams {
        edge_length: L / 8.0,
        supports: Supports::Pinned,
        ends: vec![[Some(slide); 2]; 2],
        end_frames: frames,
        ..BuildParams::default()
    };
    build_network(&curves, &params).expect("the cross builds").0
}

#[test]
fn the_energy_with_skew_supports_has_exact_derivatives() {
    use common::dense_hessian;
    use curvenet::rod::model::Terms;
    use curvenet::rod::{EnergyModel, ModelRules, RodStiffness};
    let m = Motion {
        axis: Vec3::new(-0.4, 0.7, 0.2).normalized(),
        angle: 0.6,
        shift: Vec3::new(3.0, 1.0, -2.0),
    };
    let net = cross(m);
    assert!(net.rods.iter().all(|r| r.frames.is_some()));
    let rods = vec![
        RodStiffness {
            ks: 1e3,
            kb: 1e5,
            gj: 7e4,
            arm: 10.0,
            rest: RestShape::Straight,
        };
        2
    ];
    let model = EnergyModel::with_rules(&net, &rods, 50.0, ModelRules::PHYSICAL);
    let all = ActiveSet::all(2);
    let u: Vec<f64> = (0..model.dofs())
        .map(|i| 2.0 * ((i as f64) * 0.7).sin())
        .collect();
    let a = model.assemble(&u, &all, true);
    let hess = dense_hessian(&model, &u, &all);
    let step = 1e-4;
    let mut worst = (0.0f64, 0.0f64);
    for k in 0..model.dofs() {
        let (mut up, mut um) = (u.clone(), u.clone());
        up[k] += step;
        um[k] -= step;
        let fd = (model.energy(&up, &all) - model.energy(&um, &all)) / (2.0 * step);
        worst.0 = worst.0.max((fd - a.grad[k]).abs());
        let (gp, gm) = (
            model.assemble(&up, &all, false).grad,
            model.assemble(&um, &all, false).grad,
        );
        for j in 0..model.dofs() {
            worst.1 = worst
                .1
                .max(((gp[j] - gm[j]) / (2.0 * step) - hess[(j, k)]).abs());
        }
    }
    let gscale = a.grad.iter().fold(0.0f64, |s, g| s.max(g.abs()));
    let hscale = (0..model.dofs()).fold(0.0f64, |s, i| s.max(hess[(i, i)].abs()));
    println!(
        "gradient error {:.2e} of {gscale:.2e}, Hessian {:.2e} of {hscale:.2e}",
        worst.0, worst.1
    );
    assert!(worst.0 <= 1e-6 * gscale, "gradient");
    assert!(worst.1 <= 1e-6 * hscale, "Hessian");
    // The Hessian from local Hessians, and without a curve, are the whole assembly's.
    let bits = |h: &[f64]| h.iter().map(|v| v.to_bits()).collect::<Vec<u64>>();
    let locals = model.local_hessians(&u, Terms::All);
    let mut h = Vec::new();
    model.hessian_from_locals(&locals, &all, &mut h);
    assert_eq!(bits(&h), bits(&a.hess));
    for c in 0..2 {
        let mut whole = Vec::new();
        model.hessian_from_locals(&locals, &all.without(c), &mut whole);
        let mut fast = Vec::new();
        model.hessian_without(&locals, &all, &h, c, &mut fast);
        assert_eq!(bits(&fast), bits(&whole), "without curve {c}");
    }
}
