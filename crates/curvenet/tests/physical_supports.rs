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
