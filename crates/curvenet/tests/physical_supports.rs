//! Supports per curve end in the physical mode: Euler's columns (pinned–pinned with a sliding
//! end, clamped–free, clamped–clamped with a sliding end) buckle at `π² E I / (K L)²`, a
//! cantilever deflects as `P L³ / (3 E I)`, and a supports file names ends by point and by
//! curve.

mod common;

use common::{polyline, rel_diff};
use curvenet::geom::Vec3;
use curvenet::material::{EndSupport, Physical, RestShape, Section, presets};
use curvenet::network::{BuildParams, Network, build_network};
use curvenet::physics::cases::Loads;
use curvenet::physics::{PhysicalParams, PhysicalReport, analyze_physical};
use curvenet::rod::{ActiveSet, Supports};
use curvenet::units::LengthUnit;
use std::f64::consts::PI;

const L: f64 = 1000.0;

/// A straight steel bar `L` mm long along x, radius 10 mm, 50 edges, its ends held as given.
fn bar(start: EndSupport, end: EndSupport) -> Network {
    let pts = (0..=50)
        .map(|i| Vec3::new(L * i as f64 / 50.0, 0.0, 0.0))
        .collect();
    let params = BuildParams {
        edge_length: L / 50.0,
        supports: Supports::Clamped,
        ends: vec![[Some(start), Some(end)]],
        ..BuildParams::default()
    };
    build_network(&[polyline(pts, false)], &params)
        .expect("the bar builds")
        .0
}

fn analyze(net: &Network, loads: &str) -> PhysicalReport {
    let mut params = PhysicalParams::new(Physical::uniform(
        LengthUnit::Millimetre,
        presets::preset("steel").unwrap(),
        Section::Solid { radius: 10.0 },
    ));
    params.rest = vec![RestShape::Straight; net.rods.len()];
    params.loads = Some(Loads::parse(loads, "loads.json").expect("loads"));
    analyze_physical(net, &params, &ActiveSet::all(net.rods.len())).expect("analysis")
}

/// `E I` of the bar, N·mm².
fn ei() -> f64 {
    210e3 * PI * 1e4 / 4.0
}

/// Sliding along the bar's axis: y and z fixed.
fn sliding(rotation_held: bool) -> EndSupport {
    EndSupport {
        fixed: [false, true, true],
        rotation_held,
        ..EndSupport::FREE
    }
}

#[test]
fn euler_columns_buckle_at_the_critical_load() {
    // 1 kN pressing on the far end along the bar.
    let loads =
        r#"{"cases": [{"name": "P", "points": [{"at": [1000, 0, 0], "force": [-1000, 0, 0]}]}]}"#;
    for (name, start, end, k) in [
        (
            "pinned–pinned, sliding end",
            EndSupport::PINNED,
            sliding(false),
            1.0,
        ),
        ("clamped–free", EndSupport::CLAMPED, EndSupport::FREE, 2.0),
        (
            "clamped–clamped, sliding end",
            EndSupport::CLAMPED,
            sliding(true),
            0.5,
        ),
    ] {
        let r = analyze(&bar(start, end), loads);
        let case = &r.load_cases[0];
        let want = PI * PI * ei() / (k * L).powi(2) / 1000.0;
        let got = case.buckling_factor.expect("the column buckles");
        println!(
            "{name}: α_cr {got:.4} (Euler {want:.4}, {:+.3}%), {:?}, linearised {:?}",
            100.0 * (got / want - 1.0),
            case.buckling,
            case.linear_buckling_factor
        );
        assert!(rel_diff(got, want) < 0.01, "{name}: {got} vs {want}");
        assert!(r.stable, "{name}: the unloaded column stands");
    }
}

#[test]
fn a_cantilever_deflects_as_the_beam_formula_says() {
    let loads =
        r#"{"cases": [{"name": "P", "points": [{"at": [1000, 0, 0], "force": [0, 0, -1]}]}]}"#;
    let r = analyze(&bar(EndSupport::CLAMPED, EndSupport::FREE), loads);
    let case = &r.load_cases[0];
    let got = case.max_deflection.unwrap();
    let want = L.powi(3) / (3.0 * ei());
    println!("cantilever: tip {got:.6} mm (P L³/3EI {want:.6} mm)");
    assert!(rel_diff(got, want) < 0.01, "{got} vs {want}");
    // A cantilever's span is twice its reach.
    let limit = case.deflection_limit.unwrap_or(f64::NAN);
    assert!(
        limit.is_nan() || rel_diff(limit, 2.0 * L / 250.0) < 1e-9,
        "{limit}"
    );
}

#[test]
fn a_free_end_is_a_mechanism_where_nothing_else_holds() {
    // Pinned at one end, free at the other: the bar swings about the pin.
    let r = analyze(
        &bar(EndSupport::PINNED, EndSupport::FREE),
        r#"{"cases": [{"name": "G", "self_weight": true}]}"#,
    );
    assert!(!r.stable, "a bar pinned at one end only is a mechanism");
}

/// A shallow von Mises truss: two straight steel bars (r = 10 mm) from pinned supports at
/// x = ±500 mm up to an apex 5 mm high where they meet, the apex held out of the truss's
/// plane only, 1 N pressing down on it.
fn von_mises_truss() -> Network {
    let bar = |from: f64| {
        (0..=50)
            .map(|i| {
                let t = f64::from(i) / 50.0;
                Vec3::new(from * (1.0 - t), 0.0, 5.0 * t)
            })
            .collect()
    };
    let apex = EndSupport {
        fixed: [false, true, false],
        ..EndSupport::FREE
    };
    let params = BuildParams {
        edge_length: 10.0,
        supports: Supports::Pinned,
        ends: vec![[None, Some(apex)], [None, Some(apex)]],
        ..BuildParams::default()
    };
    let curves = [polyline(bar(-500.0), false), polyline(bar(500.0), false)];
    build_network(&curves, &params).expect("the truss builds").0
}

/// The snap-through load of the two-bar truss with axial stiffness `ea`, half-span `a` and
/// rise `h`: the largest `P(w) = 2 E A (h − w) (1/L(w) − 1/L₀)`, `L(w) = √(a² + (h − w)²)`,
/// over the apex's descent `w` (the bars' exact kinematics; their bending carries nothing
/// while they stay straight), by golden-section search.
fn snap_load(ea: f64, a: f64, h: f64) -> f64 {
    let l0 = (a * a + h * h).sqrt();
    let p = |w: f64| 2.0 * ea * (h - w) * (1.0 / (a * a + (h - w).powi(2)).sqrt() - 1.0 / l0);
    let (mut lo, mut hi) = (0.0, h);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..200 {
        let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if p(x1) < p(x2) {
            lo = x1;
        } else {
            hi = x2;
        }
    }
    p(0.5 * (lo + hi))
}

#[test]
fn a_shallow_truss_snaps_through_at_its_limit_point() {
    let net = von_mises_truss();
    assert_eq!(net.joints.len(), 1, "the bars meet at the apex");
    let r = analyze(
        &net,
        r#"{"cases": [{"name": "P", "points": [{"at": [0, 0, 5], "force": [0, 0, -1]}]}]}"#,
    );
    let case = &r.load_cases[0];
    let want = snap_load(210e3 * PI * 100.0, 500.0, 5.0);
    let got = case.buckling_factor.expect("the truss snaps");
    println!(
        "von Mises truss: α_cr {got:.4} N (closed form {want:.4} N, {:+.3}%), {:?}, \
         linearised {:?}",
        100.0 * (got / want - 1.0),
        case.buckling,
        case.linear_buckling_factor
    );
    assert_eq!(case.buckling.as_deref(), Some("limit point"));
    assert!(rel_diff(got, want) < 0.01, "{got} vs {want}");
}
