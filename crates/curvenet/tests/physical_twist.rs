//! A pre-bent rod carries its twist (the physical mode, `rod::frame`), through the whole
//! physical analysis (`physics::analyze_physical`, what `analyze` reports):
//!
//! - a pre-bent quarter circle pinned at both ends swings rigidly about its chord: a
//!   mechanism, reported as not stable (the twist-free term held each section's spin in the
//!   world and called it stable, 65.85 Hz);
//! - a pre-bent semicircle clamped at both ends has the continuum's first frequency, out of
//!   its plane (`tests/physical_arc.rs` solves the continuum; the twist-free term and the
//!   paper's clamp gave 24 % more).

mod common;

use common::{build, polyline, rel_diff};
use curvenet::geom::Vec3;
use curvenet::material::{Physical, RestShape, Section, presets};
use curvenet::network::Network;
use curvenet::physics::{PhysicalParams, PhysicalReport, analyze_physical};
use curvenet::rod::{ActiveSet, Supports};
use curvenet::units::LengthUnit;
use std::f64::consts::PI;

/// A circular arc of radius `r` and opening `alpha` in the xy-plane, drawn with 91 points as
/// in the file and resampled at 10 mm.
fn arc(r: f64, alpha: f64, supports: Supports) -> Network {
    let pts = (0..=90)
        .map(|i| {
            let t = alpha * i as f64 / 90.0;
            Vec3::new(r * t.cos(), r * t.sin(), 0.0)
        })
        .collect();
    build(&[polyline(pts, false)], 10.0, supports)
}

/// The physical analysis of `net`, a pre-bent solid steel rod of radius 10 mm in
/// millimetres (`analyze --units mm --material steel --radius 10`, the curve pre-bent).
fn analyze(net: &Network) -> PhysicalReport {
    let mut params = PhysicalParams::new(Physical::uniform(
        LengthUnit::Millimetre,
        presets::preset("steel").unwrap(),
        Section::Solid { radius: 10.0 },
    ));
    params.rest = vec![RestShape::PreBent];
    params.frequencies = 6;
    analyze_physical(net, &params, &ActiveSet::all(1)).expect("analysis")
}

#[test]
fn a_pinned_pre_bent_quarter_circle_is_a_mechanism() {
    let r = analyze(&arc(500.0, 0.5 * PI, Supports::Pinned));
    println!(
        "pinned quarter circle: stable {}, zero modes {}, negative {}, μ_min {:e}, \
         frequencies {:?}",
        r.stable, r.zero_modes, r.negative_modes, r.mu_min, r.frequencies_hz
    );
    assert!(r.equilibrium.converged);
    assert!(!r.stable, "{r:?}");
    assert_eq!(r.zero_modes + r.negative_modes, 1, "{r:?}");
    assert_eq!(r.first_frequency_hz, None);
    assert_eq!(r.self_weight_max_deflection, None);
    assert!(
        r.warnings
            .iter()
            .any(|w| w.to_string().contains("not stable"))
    );
    // Its other modes remain: the in-plane ones are the twist-free model's (226.32 and
    // 528.21 Hz before).
    let f: Vec<f64> = r.frequencies_hz.iter().flatten().copied().collect();
    assert!(f.iter().any(|&f| rel_diff(f, 226.32) < 2e-3), "{f:?}");
    assert!(f.iter().any(|&f| rel_diff(f, 528.21) < 2e-3), "{f:?}");
}

#[test]
fn a_clamped_pre_bent_semicircle_has_the_continuums_first_frequency() {
    // The continuum's first mode of a steel semicircle of radius 500 mm clamped at both
    // ends is out of its plane, 29.9496 Hz (`tests/physical_arc.rs`; in the plane 72.141).
    let r = analyze(&arc(500.0, PI, Supports::Clamped));
    let f = r.first_frequency_hz.expect("stable");
    println!(
        "clamped semicircle: f₁ {f:.4} Hz (continuum 29.9496), self-weight {:?} mm, \
         frequencies {:?}",
        r.self_weight_max_deflection, r.frequencies_hz
    );
    assert!(rel_diff(f, 29.9496) < 5e-3, "{f}");
}

/// A grid of `n` by `n` straight rods of length 1000 mm on the plane z = 0, crossing at
/// every 250 mm, drawn with 41 points each and resampled at 25 mm.
fn straight_grid() -> Network {
    let line = |i: usize, along_x: bool| {
        let y = 250.0 * (i + 1) as f64;
        let pts = (0..=40)
            .map(|t| {
                let x = 25.0 * t as f64;
                if along_x {
                    Vec3::new(x, y, 0.0)
                } else {
                    Vec3::new(y, x, 0.0)
                }
            })
            .collect();
        polyline(pts, false)
    };
    let curves: Vec<_> = (0..3)
        .flat_map(|i| [line(i, true), line(i, false)])
        .collect();
    build(&curves, 25.0, Supports::Pinned)
}

#[test]
fn pre_bent_rods_drawn_straight_are_straight_rods_not_spinning_mechanisms() {
    // A straight rod spins about its own axis without moving a point: were its twist an
    // unknown, every rod of a pinned grid would add a zero mode and the grid would be
    // called a mechanism. Drawn straight, a pre-bent rod is a straight one, number for number.
    let net = straight_grid();
    let report = |rest: RestShape| {
        let mut params = PhysicalParams::new(Physical::uniform(
            LengthUnit::Millimetre,
            presets::preset("steel").unwrap(),
            Section::Solid { radius: 10.0 },
        ));
        params.rest = vec![rest; 6];
        analyze_physical(&net, &params, &ActiveSet::all(6)).expect("analysis")
    };
    let (bent, straight) = (report(RestShape::PreBent), report(RestShape::Straight));
    println!(
        "pinned grid of straight rods: pre-bent {:?}, straight {:?} Hz",
        bent.frequencies_hz, straight.frequencies_hz
    );
    assert!(bent.stable, "{bent:?}");
    assert_eq!(bent.zero_modes, 0);
    assert_eq!(bent.frequencies_hz, straight.frequencies_hz);
    assert_eq!(
        bent.self_weight_max_deflection,
        straight.self_weight_max_deflection
    );
}
