//! A network of pre-bent rods with joints converges at second order as the edges are halved:
//! three arcs across a half cylinder of radius 1 m and five lines along it (the vault of the
//! OpenSees cross-check), clamped steel bars of radius 10 mm, pre-bent. No closed form exists
//! for the network, so the study reads the order from successive differences of the lowest
//! frequencies and of the self-weight deflection (`order = log₂ |x_h − x_{h/2}| / |x_{h/2} −
//! x_{h/4}|`) and extrapolates (Richardson, second order) to estimate each level's error.
//!
//! The test checks two halvings (order near 2 on the first frequency); the study, h halved
//! four times from 50 mm, prints the table of docs/units.md:
//! `cargo test --release -p curvenet --test physical_grid_convergence -- --ignored --nocapture`.

mod common;

use common::{build, polyline};
use curvenet::geom::Vec3;
use curvenet::material::{Physical, RestShape, Section, presets};
use curvenet::physics::{PhysicalParams, analyze_physical};
use curvenet::rod::{ActiveSet, Supports};
use curvenet::units::LengthUnit;
use std::f64::consts::PI;

/// The vault's curves, metres: three arcs at y = 0.25, 0.5, 0.75 and five lines along y at
/// angles 8π/40 … 32π/40, each drawn with 401 points (finer than any edge of the study).
fn vault() -> Vec<curvenet::io::Polyline> {
    let n = 400;
    let mut curves = Vec::new();
    for i in 1..=3 {
        let y = 0.25 * f64::from(i);
        let pts = (0..=n)
            .map(|k| {
                let t = PI * f64::from(k) / f64::from(n);
                Vec3::new(t.cos(), y, t.sin())
            })
            .collect();
        curves.push(polyline(pts, false));
    }
    for j in [8, 14, 20, 26, 32] {
        let t = PI * f64::from(j) / 40.0;
        let pts = (0..=n)
            .map(|k| Vec3::new(t.cos(), f64::from(k) / f64::from(n), t.sin()))
            .collect();
        curves.push(polyline(pts, false));
    }
    curves
}

/// The lowest three frequencies (Hz) and the self-weight deflection (m) at edge length `h`.
fn figures(h: f64) -> (Vec<f64>, f64, usize) {
    let curves = vault();
    let net = build(&curves, h, Supports::Clamped);
    let mut params = PhysicalParams::new(Physical::uniform(
        LengthUnit::Metre,
        presets::preset("steel").unwrap(),
        Section::Solid { radius: 0.01 },
    ));
    params.rest = vec![RestShape::PreBent; net.rods.len()];
    params.frequencies = 3;
    let r = analyze_physical(&net, &params, &ActiveSet::all(net.rods.len())).expect("analysis");
    assert!(r.stable, "the vault stands at h = {h}");
    let f = r
        .frequencies_hz
        .iter()
        .map(|f| f.expect("stable"))
        .collect();
    let d = r.self_weight_max_deflection.expect("stable");
    (f, d, net.vertex_count())
}

/// One figure of a level, by level index.
type Series<'a> = Box<dyn Fn(usize) -> f64 + 'a>;

/// `log₂` of the ratio of successive differences.
fn order(a: f64, b: f64, c: f64) -> f64 {
    ((a - b).abs() / (b - c).abs()).log2()
}

#[test]
fn a_pre_bent_network_converges_at_second_order() {
    let levels: Vec<_> = [0.05, 0.025, 0.0125].into_iter().map(figures).collect();
    let f1: Vec<f64> = levels.iter().map(|l| l.0[0]).collect();
    let p = order(f1[0], f1[1], f1[2]);
    println!("f₁ {f1:?}, order {p:.2}");
    assert!((1.7..2.6).contains(&p), "order {p}");
}

#[test]
#[ignore = "a study: prints the table of docs/units.md"]
fn study_the_pre_bent_vault_as_h_halves() {
    let hs: Vec<f64> = (0..5).map(|k| 0.05 / f64::from(1 << k)).collect();
    let levels: Vec<_> = hs.iter().map(|&h| figures(h)).collect();
    // Richardson's estimate of the limit from the two finest levels (second order).
    let limit = |x: &dyn Fn(usize) -> f64| {
        let (a, b) = (x(levels.len() - 2), x(levels.len() - 1));
        b + (b - a) / 3.0
    };
    let series: [(&str, Series<'_>); 4] = [
        ("f₁ (Hz)", Box::new(|k| levels[k].0[0])),
        ("f₂ (Hz)", Box::new(|k| levels[k].0[1])),
        ("f₃ (Hz)", Box::new(|k| levels[k].0[2])),
        ("δ (mm)", Box::new(|k| 1000.0 * levels[k].1)),
    ];
    println!(
        "| h (mm) | vertices | f₁ (Hz) | order | f₂ (Hz) | order | f₃ (Hz) | order | δ (mm) | order |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for k in 0..levels.len() {
        let mut row = format!("| {:.4} | {} ", 1000.0 * hs[k], levels[k].2);
        for (_, x) in &series {
            let o = if k >= 2 {
                format!("{:.2}", order(x(k - 2), x(k - 1), x(k)))
            } else {
                String::new()
            };
            row += &format!("| {:.6} | {o} ", x(k));
        }
        println!("{row}|");
    }
    for (name, x) in &series {
        let l = limit(x.as_ref());
        let errors: Vec<String> = (0..levels.len())
            .map(|k| format!("{:+.2e}", x(k) / l - 1.0))
            .collect();
        println!(
            "{name}: extrapolated {l:.6}; relative errors {}",
            errors.join(", ")
        );
    }
}
