//! The physical mode against textbook beams and arcs.
//!
//! A steel rod (E 210 GPa, ρ 7850 kg/m³, r = 10 mm) in a scene drawn in millimetres, L = 2 m:
//!
//! - self-weight deflection `H u = M g` at mid-span: clamped–clamped `q L⁴ / 384 E I`, pinned–
//!   pinned `5 q L⁴ / 384 E I`, `q = ρ A g`;
//! - first natural frequency of `H v = μ M v`, `f = √μ / 2π`: clamped
//!   `4.730² / (2π L²) · √(E I / ρ A)`, pinned `π / (2 L²) · √(E I / ρ A)`;
//! - the bending stress of a rod bent into a circular arc of radius `R`: `E r / R`;
//! - `μ_min` converges as `h` halves (second order), where the identity metric's `λ` halves;
//! - the supports are rigid: `λ` and `μ` move by less than 0.1 % (measured: ~1e-6) when the
//!   anchored coordinates are eliminated instead.
//!
//! A clamp holds the end vertex and its tangent (the physical mode's clamp, `rod::terms::clamp`):
//! the span is `L` for both supports, and every `h` is within 1 % and converges at second
//! order (numbers printed with `--nocapture`; `tests/physical_clamp.rs` holds the clamped
//! bar's convergence study). The paper's clamp (two vertices per end) acts half an edge in:
//! the model of these tests is the physical mode's (`ModelRules::PHYSICAL`).

mod common;

use common::{build, dense_eigen, dense_hessian, polyline, rel_diff, straight_rod};
use curvenet::geom::Vec3;
use curvenet::material::{Physical, RestShape, Section, presets};
use curvenet::physics::{PhysicalParams, analyze_physical, assembly_stresses};
use curvenet::rod::Network;
use curvenet::rod::mass::{inverse_sqrt_coordinates, lumped_masses, scale_hessian};
use curvenet::rod::physical::{masses_per_length, physical_rods, rigid_anchor_weight};
use curvenet::rod::{ActiveSet, EnergyModel, ModelRules, Supports};
use curvenet::solve::eigen::{EigenOptions, EigenParams, Spectrum, smallest_eigenpairs};
use curvenet::solve::{
    Backend, Cholesky, Equilibrium, NewtonInfo, NewtonParams, SolverTuning, SymbolicFactor,
};
use std::sync::Arc;

/// Relaxes structure `all` of `m` from `u` (in place) with the default parameters.
fn relax(m: &EnergyModel, all: &ActiveSet, u: &mut [f64]) -> NewtonInfo {
    let symbolic = SymbolicFactor::new(m.pattern(), Backend::default());
    Equilibrium {
        model: m,
        active: all,
        symbolic: &symbolic,
        params: &NewtonParams::default(),
        tuning: &SolverTuning::default(),
    }
    .relax(u, None)
    .info
}

/// The default number of smallest eigenpairs of the Hessian values `h` of `m`.
fn spectrum(symbolic: &Arc<SymbolicFactor>, m: &EnergyModel, h: &[f64]) -> Spectrum {
    smallest_eigenpairs(
        symbolic,
        m.pattern(),
        h,
        &EigenParams::default(),
        EigenOptions::default(),
    )
    .expect("spectrum")
    .expect("a spectrum below zero's shift")
    .spectrum
}
use curvenet::units::LengthUnit;
use std::f64::consts::PI;

const LEN: f64 = 2000.0;
const RADIUS: f64 = 10.0;

fn steel_mm(radius: f64) -> Physical {
    Physical::uniform(
        LengthUnit::Millimetre,
        presets::preset("steel").unwrap(),
        Section::Solid { radius },
    )
}

/// The physical model of `net` (every rod `phys`'s, rest shapes `rest`) with rigid anchors.
fn model(net: &Network, phys: &Physical, rest: &[RestShape]) -> EnergyModel {
    let rods = physical_rods(phys, net.rods.len(), rest);
    EnergyModel::with_rules(
        net,
        &rods,
        rigid_anchor_weight(net, &rods),
        ModelRules::PHYSICAL,
    )
}

/// `E I` and `ρ A` of the steel rod, N mm² and t/mm.
fn beam(phys: &Physical) -> (f64, f64) {
    let r = phys.scene_rod(0);
    (r.kb, r.mass_per_length)
}

/// The edge counts of the textbook runs.
const EDGE_COUNTS: [usize; 4] = [50, 100, 200, 400];

/// Checks a textbook run's relative errors (one per edge count, `h` halving): within 1 % at
/// every `h`, shrinking about fourfold per halving (second order).
fn check_textbook(what: &str, errors: &[f64], report: &[String]) {
    assert!(
        errors.iter().all(|&e| e < 0.01),
        "{what}: within 1 %: {report:#?}"
    );
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(order > 1.8, "{what}: second order: {report:#?}");
    }
}

/// The largest vertical deflection of a horizontal rod under its own weight (`H u = M g` at
/// the stress-free rest state).
fn self_weight_deflection(n: usize, supports: Supports) -> f64 {
    let phys = steel_mm(RADIUS);
    let net = straight_rod(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0), LEN, n, supports);
    let m = model(&net, &phys, &[]);
    let all = ActiveSet::all(1);
    let zero = vec![0.0; m.dofs()];
    let h = m.assemble(&zero, &all, true).hess;
    let masses = lumped_masses(&net, &masses_per_length(&phys, 1), &all);
    let g = phys.gravity_scene();
    let mut u: Vec<f64> = masses
        .iter()
        .flat_map(|&mv| [mv * g[0], mv * g[1], mv * g[2]])
        .collect();
    let symbolic = SymbolicFactor::new(m.pattern(), Backend::default());
    let factor =
        Cholesky::factorize(&symbolic, m.pattern(), &h, 0.0, None).expect("positive definite");
    factor.solve_vec(&mut u);
    (0..net.vertex_count())
        .map(|v| -u[3 * v + 2])
        .fold(0.0, f64::max)
}

#[test]
fn self_weight_deflection_of_textbook_beams() {
    let phys = steel_mm(RADIUS);
    let (ei, rho_a) = beam(&phys);
    let q = rho_a * -phys.gravity_scene()[2];
    let mut report = Vec::new();
    for supports in [Supports::Pinned, Supports::Clamped] {
        let want = match supports {
            Supports::Pinned => 5.0 * q * LEN.powi(4) / (384.0 * ei),
            Supports::Clamped => q * LEN.powi(4) / (384.0 * ei),
        };
        let mut errors = Vec::new();
        for n in EDGE_COUNTS {
            let got = self_weight_deflection(n, supports);
            let err = rel_diff(got, want);
            report.push(format!(
                "{supports:?} n = {n}: {got:.5} mm, textbook {want:.5} mm ({err:.2e})"
            ));
            errors.push(err);
        }
        check_textbook("self-weight", &errors, &report);
    }
    println!("{}", report.join("\n"));
}

/// The smallest eigenvalues of `H v = μ M v` (or of `H` alone) for the rod at rest.
fn rod_spectrum(n: usize, supports: Supports, mass_metric: bool) -> Vec<f64> {
    let phys = steel_mm(RADIUS);
    let net = straight_rod(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0), LEN, n, supports);
    let m = model(&net, &phys, &[]);
    let all = ActiveSet::all(1);
    let zero = vec![0.0; m.dofs()];
    let mut h = m.assemble(&zero, &all, true).hess;
    if mass_metric {
        let masses = lumped_masses(&net, &masses_per_length(&phys, 1), &all);
        scale_hessian(m.pattern(), &mut h, &inverse_sqrt_coordinates(&masses));
    }
    let symbolic = SymbolicFactor::new(m.pattern(), Backend::default());
    let s = spectrum(&symbolic, &m, &h);
    assert_eq!((s.zero_modes, s.negative_modes), (0, 0));
    s.values
}

#[test]
fn first_natural_frequencies_of_textbook_beams() {
    let phys = steel_mm(RADIUS);
    let (ei, rho_a) = beam(&phys);
    let mut report = Vec::new();
    for supports in [Supports::Pinned, Supports::Clamped] {
        let want = match supports {
            Supports::Pinned => PI / (2.0 * LEN * LEN) * (ei / rho_a).sqrt(),
            Supports::Clamped => {
                4.730_040_7f64.powi(2) / (2.0 * PI * LEN * LEN) * (ei / rho_a).sqrt()
            }
        };
        let mut errors = Vec::new();
        for n in EDGE_COUNTS {
            let mu = rod_spectrum(n, supports, true);
            // The two transverse directions: a pair.
            assert!(rel_diff(mu[0], mu[1]) < 1e-6, "{mu:?}");
            let f = mu[0].sqrt() / (2.0 * PI);
            let err = rel_diff(f, want);
            report.push(format!(
                "{supports:?} n = {n}: f₁ = {f:.5} Hz, textbook {want:.5} Hz ({err:.2e})"
            ));
            errors.push(err);
        }
        check_textbook("frequency", &errors, &report);
    }
    println!("{}", report.join("\n"));
}

#[test]
fn mu_converges_as_h_halves_where_lambda_does_not() {
    let mut report = Vec::new();
    let (mut mus, mut lambdas) = (Vec::new(), Vec::new());
    for n in [25usize, 50, 100, 200, 400] {
        mus.push(rod_spectrum(n, Supports::Pinned, true)[0]);
        lambdas.push(rod_spectrum(n, Supports::Pinned, false)[0]);
        report.push(format!(
            "n = {n}: μ₁ = {:.8e} s⁻², λ₁ = {:.6e}",
            mus.last().unwrap(),
            lambdas.last().unwrap()
        ));
    }
    println!("{}", report.join("\n"));
    // μ's changes shrink ~4× per halving (second order); λ halves with h.
    let changes: Vec<f64> = mus.windows(2).map(|w| rel_diff(w[1], w[0])).collect();
    for w in changes.windows(2) {
        let shrink = w[0] / w[1];
        assert!((3.0..5.0).contains(&shrink), "{changes:?}\n{report:?}");
    }
    assert!(*changes.last().unwrap() < 1e-3, "{changes:?}");
    for w in lambdas.windows(2) {
        assert!((w[1] / w[0] - 0.5).abs() < 0.02, "{lambdas:?}");
    }
}

/// The smallest eigenvalue of `H` (or of `M^{-1/2} H M^{-1/2}`) with the anchored coordinates
/// eliminated (rigid supports), from the dense matrix at displacements `u`.
fn rigid_smallest(m: &EnergyModel, net: &Network, u: &[f64], masses: Option<&[f64]>) -> (f64, f64) {
    let all = ActiveSet::all(net.rods.len());
    let mut h = m.assemble(u, &all, true).hess;
    if let Some(masses) = masses {
        scale_hessian(m.pattern(), &mut h, &inverse_sqrt_coordinates(masses));
    }
    let dense = {
        let mut d = faer::Mat::<f64>::zeros(m.dofs(), m.dofs());
        let p = m.pattern();
        for j in 0..p.n {
            for k in p.col_ptr[j]..p.col_ptr[j + 1] {
                d[(p.row_idx[k], j)] = h[k];
                d[(j, p.row_idx[k])] = h[k];
            }
        }
        d
    };
    let anchored = m.anchored_vertices();
    let free: Vec<usize> = (0..m.dofs()).filter(|&i| !anchored[i / 3]).collect();
    let sub = faer::Mat::<f64>::from_fn(free.len(), free.len(), |i, j| dense[(free[i], free[j])]);
    let (with, _) = dense_eigen(dense.as_ref());
    let (rigid, _) = dense_eigen(sub.as_ref());
    (with[0], rigid[0])
}

#[test]
fn supports_are_rigid_at_any_scale() {
    // A straight rod (stress free) and two crossing arches bent into shape (relaxed first),
    // in millimetres and in metres: the anchors scale with the rods.
    let mut report = Vec::new();
    for units in [LengthUnit::Millimetre, LengthUnit::Metre] {
        let s = 1e-3 / units.metres();
        let phys = Physical::uniform(
            units,
            presets::preset("steel").unwrap(),
            Section::Solid { radius: RADIUS * s },
        );
        for supports in [Supports::Pinned, Supports::Clamped] {
            let rod = straight_rod(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0), LEN * s, 40, supports);
            let arch = |a: Vec3, b: Vec3| {
                let pts = (0..=16)
                    .map(|i| {
                        let t = i as f64 / 16.0;
                        (a.lerp(b, t) + Vec3::new(0.0, 0.0, 400.0 * (PI * t).sin())) * s
                    })
                    .collect();
                polyline(pts, false)
            };
            let arches = build(
                &[
                    arch(Vec3::new(-800.0, 0.0, 0.0), Vec3::new(800.0, 0.0, 0.0)),
                    arch(Vec3::new(0.0, -800.0, 0.0), Vec3::new(0.0, 800.0, 0.0)),
                ],
                50.0 * s,
                supports,
            );
            for (name, net) in [("rod", rod), ("arches", arches)] {
                let m = model(&net, &phys, &[]);
                let all = ActiveSet::all(net.rods.len());
                let mut u = vec![0.0; m.dofs()];
                let info = relax(&m, &all, &mut u);
                assert!(info.converged, "{name}: {info:?}");
                let masses = lumped_masses(&net, &masses_per_length(&phys, net.rods.len()), &all);
                let (l, l_rigid) = rigid_smallest(&m, &net, &u, None);
                let (mu, mu_rigid) = rigid_smallest(&m, &net, &u, Some(&masses));
                let (dl, dmu) = (rel_diff(l, l_rigid), rel_diff(mu, mu_rigid));
                report.push(format!(
                    "{units} {supports:?} {name}: λ {l:.6e} (rigid {l_rigid:.6e}, {dl:.1e}), \
                     μ {mu:.6e} (rigid {mu_rigid:.6e}, {dmu:.1e})"
                ));
                assert!(dl < 1e-3 && dmu < 1e-3, "{report:?}");
            }
        }
    }
    // The paper's anchor weight (µ = 500, a constant in scene units) next to the same steel
    // rod in millimetres is a soft spring: the supports give and λ is far off.
    let phys = steel_mm(RADIUS);
    let net = straight_rod(
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, 0.0),
        LEN,
        40,
        Supports::Clamped,
    );
    let rods = physical_rods(&phys, 1, &[]);
    let soft = EnergyModel::with_rods(&net, &rods, 500.0);
    let (l, l_rigid) = rigid_smallest(&soft, &net, &vec![0.0; soft.dofs()], None);
    report.push(format!(
        "mm Clamped rod, µ = 500: λ {l:.6e} (rigid {l_rigid:.6e}, {:.1e})",
        rel_diff(l, l_rigid)
    ));
    assert!(rel_diff(l, l_rigid) > 0.1, "{report:?}");
    println!("{}", report.join("\n"));
}

#[test]
fn bending_stress_of_a_rod_bent_into_an_arc() {
    // A quarter circle of radius R, straight at rest, clamped at both ends: it stays an arc
    // (pure bending), σ = E r / R = 210 000 · 10 / 1000 = 2100 MPa. Pre-bent, it is
    // stress-free.
    let big_r = 1000.0;
    let phys = steel_mm(RADIUS);
    let want = 210_000.0 * RADIUS / big_r;
    let mut report = Vec::new();
    for n in [32usize, 64, 128] {
        let pts: Vec<Vec3> = (0..=n)
            .map(|i| {
                let t = 0.5 * PI * i as f64 / n as f64;
                Vec3::new(big_r * t.cos(), big_r * t.sin(), 0.0)
            })
            .collect();
        let net = build(
            &[polyline(pts, false)],
            0.5 * PI * big_r / n as f64,
            Supports::Clamped,
        );
        for rest in [RestShape::Straight, RestShape::PreBent] {
            let m = model(&net, &phys, &[rest]);
            let all = ActiveSet::all(1);
            let mut u = vec![0.0; m.dofs()];
            let info = relax(&m, &all, &mut u);
            assert!(info.converged);
            let s = assembly_stresses(&net, &phys, &[rest], &all, &u, Some(&m));
            let c = s.curves[0];
            report.push(format!(
                "n = {n} {}: σ_b = {:.3} MPa (E r / R = {want} MPa), axial {:.3e} MPa",
                rest.name(),
                c.bending_mpa,
                c.axial_mpa
            ));
            match rest {
                RestShape::Straight => {
                    assert!(rel_diff(c.bending_mpa, want) < 0.01, "{report:?}");
                    // Above steel's 355 MPa: it would break.
                    assert_eq!(s.overstressed().len(), 1);
                    assert!(c.utilisation() > 5.0);
                }
                RestShape::PreBent => {
                    assert!(c.bending_mpa < 1e-6 * want, "{report:?}");
                    assert!(s.overstressed().is_empty());
                }
            }
        }
    }
    println!("{}", report.join("\n"));
}

#[test]
fn a_pre_bent_rod_rests_where_it_was_drawn() {
    // Two crossing wobbly 3D arches, pre-bent: the drawn state is an equilibrium (energy and
    // gradient exactly zero), Newton stays there, and the structure is stable (no zero
    // modes: bending out of the drawn plane is resisted). Straight at rest, the same arches
    // spring back.
    let wobbly = |dir: Vec3, side: Vec3| {
        let pts = (0..=24)
            .map(|i| {
                let t = i as f64 / 24.0;
                dir * (1500.0 * (t - 0.5))
                    + side * (120.0 * (3.0 * PI * t).sin())
                    + Vec3::new(0.0, 0.0, 600.0 * (PI * t).sin())
            })
            .collect();
        polyline(pts, false)
    };
    let net = build(
        &[
            wobbly(Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)),
            wobbly(Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 0.0, 0.0)),
        ],
        40.0,
        Supports::Clamped,
    );
    assert_eq!(net.joints.len(), 1, "the arches cross");
    let phys = steel_mm(RADIUS);
    let all = ActiveSet::all(net.rods.len());
    let mut moved = Vec::new();
    for rest in [RestShape::PreBent, RestShape::Straight] {
        let m = model(&net, &phys, &[rest, rest]);
        let zero = vec![0.0; m.dofs()];
        let a = m.assemble(&zero, &all, true);
        let gnorm = a.grad.iter().map(|g| g * g).sum::<f64>().sqrt();
        let mut u = zero.clone();
        let symbolic = SymbolicFactor::new(m.pattern(), Backend::default());
        let info = relax(&m, &all, &mut u);
        assert!(info.converged, "{info:?}");
        let max_u = u.iter().fold(0.0f64, |x, v| x.max(v.abs()));
        moved.push(max_u);
        let h = m.assemble(&u, &all, true).hess;
        let s = spectrum(&symbolic, &m, &h);
        println!(
            "{}: |∇E(drawn)| = {gnorm:.3e}, E = {:.3e}, moved {max_u:.3e} mm, λ = {:.4e}, \
             zero modes {}",
            rest.name(),
            a.energy,
            s.values[0],
            s.zero_modes
        );
        if rest == RestShape::PreBent {
            // Stretching terms are zero up to the round-off of the rest lengths.
            assert!(
                a.energy < 1e-20 * phys.scene_rod(0).ks * LEN,
                "{}",
                a.energy
            );
            assert!(gnorm < 1e-9 * phys.scene_rod(0).ks, "{gnorm}");
            assert!(max_u < 1e-9, "{max_u}");
        }
        assert_eq!((s.zero_modes, s.negative_modes), (0, 0));
    }
    assert!(
        moved[1] > 1.0,
        "straight at rest, the arch springs back: {moved:?}"
    );
}

#[test]
fn pre_bent_rods_in_the_dense_hessian_match_the_sparse_one() {
    // The assembled Hessian with pre-bent terms, expanded to dense, is symmetric and matches
    // the local terms (a smoke test of the model's dispatch; the terms' own derivatives are
    // checked by finite differences in `rod::terms` and `energy_derivatives.rs`).
    let net = build(
        &[polyline(
            (0..=10)
                .map(|i| Vec3::new(100.0 * i as f64, 0.0, 30.0 * (i as f64 * 0.6).sin()))
                .collect(),
            false,
        )],
        50.0,
        Supports::Pinned,
    );
    let phys = steel_mm(RADIUS);
    let m = model(&net, &phys, &[RestShape::PreBent]);
    let all = ActiveSet::all(1);
    let u: Vec<f64> = (0..m.dofs())
        .map(|i| 0.3 * ((i as f64) * 0.7).sin())
        .collect();
    let d = dense_hessian(&m, &u, &all);
    for i in 0..d.nrows() {
        for j in 0..i {
            assert_eq!(d[(i, j)], d[(j, i)]);
        }
    }
    assert!(m.energy(&u, &all) > 0.0);
}

#[test]
fn physical_analysis_of_a_pinned_steel_beam_matches_the_textbook() {
    // The whole physical analysis (its own model, rigid anchors, equilibrium, mass metric,
    // self-weight) on a straight pinned rod: Euler–Bernoulli's first frequency and mid-span
    // deflection, the rod's mass, no stress.
    let phys = steel_mm(RADIUS);
    let (ei, rho_a) = beam(&phys);
    let net = straight_rod(
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, 0.0),
        LEN,
        200,
        Supports::Pinned,
    );
    let params = PhysicalParams::new(phys.clone());
    let r = analyze_physical(&net, &params, &ActiveSet::all(1)).expect("analysis");
    let f_want = PI / (2.0 * LEN * LEN) * (ei / rho_a).sqrt();
    let f = r.first_frequency_hz.expect("stable");
    let q = rho_a * -phys.gravity_scene()[2];
    let w_want = 5.0 * q * LEN.powi(4) / (384.0 * ei);
    let w = r.self_weight_max_deflection.expect("stable");
    let mass_want = 7850.0 * PI * 0.01f64.powi(2) * 2.0;
    println!(
        "f₁ = {f:.5} Hz (textbook {f_want:.5} Hz, {:.2e}); self-weight {w:.5} mm (textbook \
         {w_want:.5} mm, {:.2e}); mass {:.4} kg ({mass_want:.4}); frequencies {:?}",
        rel_diff(f, f_want),
        rel_diff(w, w_want),
        r.mass_kg,
        r.frequencies_hz
    );
    assert!(r.stable && r.equilibrium.converged, "{r:?}");
    assert!(rel_diff(f, f_want) < 1e-3, "{f} vs {f_want}");
    assert!(rel_diff(w, w_want) < 1e-2, "{w} vs {w_want}");
    assert!(rel_diff(r.mass_kg, mass_want) < 1e-12);
    // The second frequency is the other transverse direction's; the third is 4× the first.
    let fs: Vec<f64> = r.frequencies_hz.iter().map(|f| f.unwrap()).collect();
    assert!(rel_diff(fs[1], fs[0]) < 1e-6, "{fs:?}");
    assert!(rel_diff(fs[2], 4.0 * fs[0]) < 1e-2, "{fs:?}");
    assert!(r.assembly_max_bending_stress_mpa < 1e-6);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    // The worst-case distributed load of RMS 1 kN/m is the first mode's shape, sin(πs/L):
    // peak √2 · q L⁴ / (π⁴ E I).
    let d = r.load_max_deflection.expect("stable");
    let q_load = phys.load_scene();
    let d_want = 2f64.sqrt() * q_load * LEN.powi(4) / (PI.powi(4) * ei);
    assert!(rel_diff(d.max, d_want) < 1e-2, "{} vs {d_want}", d.max);
}

/// The greedy in the physical mode chooses as in the paper's mode (its objective is the
/// paper's λ) and records every iteration's physical numbers: those of the physical analysis
/// of that iteration's structure.
#[test]
fn the_greedy_records_each_iterations_physical_numbers() {
    use curvenet::simplify::greedy::{NoHooks, greedy};
    use curvenet::simplify::{Budget, GreedyParams};
    use curvenet::stability::{Analyzer, StabilityParams};
    // A 3 × 3 grid of gently arched curves, 3 m square, drawn in millimetres.
    let mut curves = Vec::new();
    for i in 0..3 {
        let c = -1000.0 + 1000.0 * i as f64;
        let arch = |t: f64| 300.0 * (1.0 - (t / 1500.0).powi(2));
        let pts =
            |f: &dyn Fn(f64) -> Vec3| (0..=12).map(|k| f(-1500.0 + 250.0 * k as f64)).collect();
        curves.push(polyline(
            pts(&|t| Vec3::new(t, c, arch(t) + arch(c))),
            false,
        ));
        curves.push(polyline(
            pts(&|t| Vec3::new(c, t, arch(t) + arch(c))),
            false,
        ));
    }
    let net = build(&curves, 125.0, Supports::Clamped);
    let params = GreedyParams::new(Budget::Fraction(0.6));
    let paper = Analyzer::new(net.clone(), StabilityParams::default()).unwrap();
    let plain = greedy(&paper, &params, None, None, &mut NoHooks).expect("paper greedy");
    let physical = PhysicalParams::new(steel_mm(RADIUS));
    let analyzer = Analyzer::new(net.clone(), StabilityParams::default())
        .unwrap()
        .with_physical(physical.clone())
        .unwrap();
    let run = greedy(&analyzer, &params, None, None, &mut NoHooks).expect("physical greedy");
    assert!(plain.iterations.len() > 1);
    assert_eq!(run.iterations.len(), plain.iterations.len());
    for (a, b) in run.iterations.iter().zip(&plain.iterations) {
        assert_eq!(
            (&a.curves, a.removed, a.lambda),
            (&b.curves, b.removed, b.lambda)
        );
        assert!(b.physical.is_none());
        let p = a.physical.as_ref().expect("physical numbers per iteration");
        let mut active = ActiveSet::all(net.rods.len());
        for c in 0..net.rods.len() {
            if !a.curves.contains(&c) {
                active.remove(c);
            }
        }
        let report = analyze_physical(&net, &physical, &active).unwrap();
        assert_eq!(p, &report.summary());
        assert!(p.stable && p.first_frequency_hz.unwrap() > 0.0 && p.mass_kg > 0.0);
    }
    // Removing curves takes mass away.
    let mass = |k: usize| run.iterations[k].physical.as_ref().unwrap().mass_kg;
    assert!(mass(run.iterations.len() - 1) < mass(0));
    // The paper's mode writes no physical field.
    let json = serde_json::to_string(&plain.iterations[0]).unwrap();
    assert!(!json.contains("physical"));
}

/// Two joints a hair apart along a curve leave a vertex with almost no mass, so
/// `M^{-1/2} H M^{-1/2}` has huge entries there: a zero band scaled by that matrix's norm
/// called the paper's shell in steel a mechanism (4 zero modes with `μ_min = 7.6e3 s⁻²`).
/// Judged in the identity metric (`physics::inertia`), it is stable, as in the paper's mode.
#[test]
fn near_coincident_joints_do_not_make_a_stable_shell_look_like_a_mechanism() {
    use curvenet::network::build_network;
    let ex = curvenet::paper::load_embedded("shell", Supports::Clamped).expect("shell");
    let (net, _) = build_network(&ex.curves, &ex.build).expect("shell builds");
    let shortest = net.edge_length_stats().min;
    assert!(
        shortest < 1e-2 * ex.build.edge_length,
        "the shell keeps a tiny rest edge ({shortest})"
    );
    let params = PhysicalParams::new(steel_mm(RADIUS));
    let r = analyze_physical(&net, &params, &ActiveSet::all(net.rods.len())).expect("analysis");
    println!(
        "shell in steel: stable {}, zero {}, μ_min {:.4e}, f₁ {:?}",
        r.stable, r.zero_modes, r.mu_min, r.first_frequency_hz
    );
    assert!(
        r.stable && r.zero_modes == 0 && r.negative_modes == 0,
        "{:?}",
        r.warnings
    );
    let f = r
        .first_frequency_hz
        .expect("a stable structure has a first frequency");
    assert!((13.0..15.0).contains(&f), "f₁ = {f} Hz (measured 13.9)");
}
