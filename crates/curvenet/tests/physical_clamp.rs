//! The physical mode's clamp holds the end itself (its position and tangent): a steel bar
//! clamped at both ends converges to Euler–Bernoulli's clamped–clamped beam at second order,
//! through the whole physical analysis (`physics::analyze_physical`).
//!
//! A steel bar (E 210 GPa, ρ 7850 kg/m³, solid r = 10 mm) in millimetres, `L = 1 m`:
//! `f₁ = (4.730² / 2π) √(E I / (ρ A L⁴))`, self-weight `δ_mid = w L⁴ / (384 E I)`,
//! `w = ρ A g`. The paper's clamp (two anchored vertices per end) acts half an edge in:
//! `f₁` +4.1 % and `δ` −8 % at 50 edges, first order.
//!
//! The convergence study (`h` halved four times, the table in `docs/units.md`):
//! `cargo test --release -p curvenet --test physical_clamp -- --ignored --nocapture`.

mod common;

use common::{rel_diff, straight_rod};
use curvenet::geom::Vec3;
use curvenet::material::{Physical, Section, presets};
use curvenet::physics::{PhysicalParams, analyze_physical};
use curvenet::rod::mass::{inverse_sqrt_coordinates, lumped_masses, scale_hessian};
use curvenet::rod::physical::{masses_per_length, physical_rods, rigid_anchor_weight};
use curvenet::rod::{ActiveSet, EnergyModel, Supports};
use curvenet::solve::eigen::{EigenOptions, EigenParams, smallest_eigenpairs};
use curvenet::solve::{Backend, Cholesky, SymbolicFactor};
use curvenet::units::LengthUnit;
use std::f64::consts::PI;

const LEN: f64 = 1000.0;
const RADIUS: f64 = 10.0;

fn steel() -> Physical {
    Physical::uniform(
        LengthUnit::Millimetre,
        presets::preset("steel").unwrap(),
        Section::Solid { radius: RADIUS },
    )
}

/// The beam formulas' `f₁` (Hz) and self-weight `δ` (mm) of the bar with `supports` at both
/// ends.
fn textbook(supports: Supports) -> (f64, f64) {
    let phys = steel();
    let r = phys.scene_rod(0);
    let (ei, rho_a) = (r.kb, r.mass_per_length);
    let w = rho_a * -phys.gravity_scene()[2];
    match supports {
        Supports::Clamped => (
            4.730_040_7f64.powi(2) / (2.0 * PI) * (ei / (rho_a * LEN.powi(4))).sqrt(),
            w * LEN.powi(4) / (384.0 * ei),
        ),
        Supports::Pinned => (
            PI / (2.0 * LEN * LEN) * (ei / rho_a).sqrt(),
            5.0 * w * LEN.powi(4) / (384.0 * ei),
        ),
    }
}

/// `f₁` (Hz) and the self-weight deflection (mm) of the bar with `n` edges, from the physical
/// analysis.
fn bar(n: usize, supports: Supports) -> (f64, f64) {
    let net = straight_rod(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0), LEN, n, supports);
    let r = analyze_physical(&net, &PhysicalParams::new(steel()), &ActiveSet::all(1))
        .expect("analysis");
    assert!(r.stable && r.equilibrium.converged, "{r:?}");
    (
        r.first_frequency_hz.expect("stable"),
        r.self_weight_max_deflection.expect("stable"),
    )
}

/// [`bar`] with the paper's clamp (two anchored vertices per end) in the same physical
/// model: what the physical mode gave before its clamp held the end.
fn bar_with_the_papers_clamp(n: usize) -> (f64, f64) {
    let phys = steel();
    let net = straight_rod(
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, 0.0),
        LEN,
        n,
        Supports::Clamped,
    );
    let rods = physical_rods(&phys, 1, &[]);
    let m = EnergyModel::with_rods(&net, &rods, rigid_anchor_weight(&net, &rods));
    let all = ActiveSet::all(1);
    let h = m.assemble(&vec![0.0; m.dofs()], &all, true).hess;
    let masses = lumped_masses(&net, &masses_per_length(&phys, 1), &all);
    let symbolic = SymbolicFactor::new(m.pattern(), Backend::default());
    let mut scaled = h.clone();
    scale_hessian(m.pattern(), &mut scaled, &inverse_sqrt_coordinates(&masses));
    let mu = smallest_eigenpairs(
        &symbolic,
        m.pattern(),
        &scaled,
        &EigenParams::default(),
        EigenOptions::default(),
    )
    .expect("spectrum")
    .expect("pairs")
    .spectrum
    .lambda();
    let g = phys.gravity_scene();
    let mut u: Vec<f64> = masses.iter().flat_map(|&mv| g.map(|g| mv * g)).collect();
    Cholesky::factorize(&symbolic, m.pattern(), &h, 0.0, None)
        .expect("positive definite")
        .solve_vec(&mut u);
    let d = u.chunks(3).map(|c| -c[2]).fold(0.0, f64::max);
    (mu.sqrt() / (2.0 * PI), d)
}

/// The observed order of convergence from the errors at `h` and `h / 2`.
fn order(coarse: f64, fine: f64) -> f64 {
    (coarse / fine).log2()
}

#[test]
fn a_clamped_bar_matches_the_beam_within_half_a_percent_at_50_edges() {
    let (f_want, d_want) = textbook(Supports::Clamped);
    let (f, d) = bar(50, Supports::Clamped);
    let (ef, ed) = (rel_diff(f, f_want), rel_diff(d, d_want));
    println!("50 edges: f₁ {f:.4} Hz ({f_want:.4}, {ef:.2e}), δ {d:.5} mm ({d_want:.5}, {ed:.2e})");
    assert!(ef < 5e-3, "f₁ {f} against {f_want}");
    assert!(ed < 5e-3, "δ {d} against {d_want}");
    // Second order: the errors at 10 and 20 edges shrink about fourfold.
    let (f10, d10) = bar(10, Supports::Clamped);
    let (f20, d20) = bar(20, Supports::Clamped);
    let of = order(rel_diff(f10, f_want), rel_diff(f20, f_want));
    let od = order(rel_diff(d10, d_want), rel_diff(d20, d_want));
    println!("observed orders 10 → 20 edges: f₁ {of:.2}, δ {od:.2}");
    assert!(of >= 1.8 && od >= 1.8, "orders {of}, {od}");
}

/// The convergence study of `docs/units.md`: clamped and pinned bars, `h` halved four times.
#[test]
#[ignore = "a study: prints the table of docs/units.md"]
fn convergence_study_of_clamped_and_pinned_bars() {
    for supports in [Supports::Clamped, Supports::Pinned] {
        let (f_want, d_want) = textbook(supports);
        println!(
            "{supports:?}: f₁ {f_want:.5} Hz, δ {d_want:.6} mm\n\
             | edges | h (mm) | f₁ (Hz) | error | order | δ (mm) | error | order |\n\
             |---|---|---|---|---|---|---|---|"
        );
        let mut last: Option<(f64, f64)> = None;
        for n in [50usize, 100, 200, 400, 800] {
            if supports == Supports::Clamped {
                let (f, d) = bar_with_the_papers_clamp(n);
                println!(
                    "(the paper's clamp, {n} edges: f₁ {f:.4} Hz {:+.2e}, δ {d:.6} mm {:+.2e})",
                    f / f_want - 1.0,
                    d / d_want - 1.0
                );
            }
            let (f, d) = bar(n, supports);
            let (ef, ed) = (rel_diff(f, f_want), rel_diff(d, d_want));
            let (of, od) = last.map_or((String::new(), String::new()), |(a, b)| {
                (
                    format!("{:.2}", order(a, ef)),
                    format!("{:.2}", order(b, ed)),
                )
            });
            println!(
                "| {n} | {} | {f:.4} | {:+.2e} | {of} | {d:.6} | {:+.2e} | {od} |",
                LEN / n as f64,
                f / f_want - 1.0,
                d / d_want - 1.0
            );
            last = Some((ef, ed));
        }
    }
}
