//! Exactness of the energy and its derivatives (docs/model.md, *Energy*).
//!
//! On small random 3D networks (a closed wobbly ring crossed by 2–4 wobbly open arches, built
//! with `build_network`), at random displacements of realistic size:
//!
//! - the library's energy equals the formulas of docs/model.md (*Energy*) written out independently
//!   in the test;
//! - the assembled gradient matches a 4-point central finite difference of `energy`;
//! - the assembled sparse Hessian, expanded to dense, matches central finite differences of the
//!   assembled gradient, entry by entry (relative to its column's scale), for the whole network
//!   and for an `ActiveSet` without one curve, where loose vertices must carry exactly
//!   `loose_diagonal()` on their diagonal and nothing else;
//! - at `u = 0` (the drawn state) the energy is pure bending, positive, and the gradient is the
//!   drawn state's (it matches finite differences there too, and is not zero).
//!
//! Rods of different stiffnesses, some pre-bent (bending measured from the drawn shape), are
//! checked the same way, and a network of pre-bent rods is in equilibrium where it was drawn;
//! so are the physical mode's rules (clamps that hold the end, pre-bent rods with twist
//! unknowns and a material frame), clamped and pinned, with the twists displaced too.
//!
//! Two materials are used: the default one (stretching dominates the Hessian) and a thick one
//! (`r` comparable to the edge length) where bending and stretching entries have similar size,
//! so that an error in either term is visible.

mod common;

use common::{Rng, build, dense_hessian, norm, positions_of, random_curves, rel_diff, spec_energy};
use curvenet::material::RestShape;
use curvenet::network::Network;
use curvenet::rod::{ActiveSet, EnergyModel, Material, ModelRules, RodStiffness, Supports};

// Finite-difference steps and tolerances (scene units; edges are ~60 long, the shortest a few
// units). Both stencils are 4-point (error O(step⁴)); the steps sit where truncation and
// round-off balance (measured: worst errors 2.4e-11 for the gradient, 4.3e-10 for the
// Hessian; a step 3× smaller or larger gives 2–10× more). Tolerances leave a margin of ~25×.
// Errors are relative to the largest entry of the gradient / of the Hessian's column.
const GRAD_STEP: f64 = 1e-3;
const GRAD_TOL: f64 = 1e-9;
const HESS_STEP: f64 = 3e-3;
const HESS_TOL: f64 = 1e-8;

/// Materials under test: the reference's and a thick rod with a soft anchor.
fn materials() -> [Material; 2] {
    [
        Material::default(),
        Material {
            radius: 40.0,
            young: 0.5,
            anchor_weight: 3.0,
        },
    ]
}

/// A realistic displacement: a smooth random field of amplitude ~`amp` plus small noise, and a
/// thousand times less on anchored vertices (anchors hold their vertices: at an equilibrium they
/// move by force / 2µ).
fn random_displacement(net: &Network, rng: &mut Rng, amp: f64) -> Vec<f64> {
    let mut anchored = vec![false; net.vertex_count()];
    for r in &net.rods {
        for &v in &r.anchors {
            anchored[v as usize] = true;
        }
    }
    let k: Vec<[f64; 3]> = (0..3)
        .map(|_| {
            [
                rng.range(-1.0, 1.0) / 400.0,
                rng.range(-1.0, 1.0) / 400.0,
                rng.range(-1.0, 1.0) / 400.0,
            ]
        })
        .collect();
    let phase: Vec<f64> = (0..3)
        .map(|_| rng.range(0.0, std::f64::consts::TAU))
        .collect();
    let mut u = Vec::with_capacity(net.dofs());
    for (v, p) in net.positions.iter().enumerate() {
        let a = if anchored[v] { 1e-3 * amp } else { amp };
        for c in 0..3 {
            let arg = k[c][0] * p.x + k[c][1] * p.y + k[c][2] * p.z + phase[c];
            u.push(a * arg.sin() + 0.05 * a * rng.normal());
        }
    }
    u
}

/// 4-point central difference of the energy along coordinate `i`.
fn fd_gradient(model: &EnergyModel, u: &[f64], active: &ActiveSet, step: f64) -> Vec<f64> {
    let mut x = u.to_vec();
    (0..u.len())
        .map(|i| {
            let mut e = |d: f64| {
                x[i] = u[i] + d;
                let v = model.energy(&x, active);
                x[i] = u[i];
                v
            };
            let (p1, m1, p2, m2) = (e(step), e(-step), e(2.0 * step), e(-2.0 * step));
            (8.0 * (p1 - m1) - (p2 - m2)) / (12.0 * step)
        })
        .collect()
}

/// Checks the assembled gradient against finite differences; returns the worst error relative
/// to `‖g‖∞`.
fn check_gradient(model: &EnergyModel, u: &[f64], active: &ActiveSet, step: f64) -> f64 {
    let g = model.assemble(u, active, false).grad;
    let fd = fd_gradient(model, u, active, step);
    let scale = g.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(scale > 0.0, "the gradient is not identically zero here");
    g.iter()
        .zip(&fd)
        .map(|(a, b)| (a - b).abs() / scale)
        .fold(0.0, f64::max)
}

/// Checks the dense expansion of the assembled Hessian against 4-point central differences of
/// the assembled gradient. Non-loose entries: error ≤ `tol ·` the column's largest entry. Loose
/// coordinates: exactly `loose_diagonal` on the diagonal and 0 elsewhere in their row/column.
/// Returns the worst relative error seen on non-loose entries.
fn check_hessian(
    model: &EnergyModel,
    u: &[f64],
    active: &ActiveSet,
    step: f64,
    tol: f64,
) -> (f64, usize) {
    let n = model.dofs();
    let h = dense_hessian(model, u, active);
    let mask = model.coordinate_mask(active);
    let loose = |i: usize| !mask[i];
    let mut x = u.to_vec();
    let mut worst = 0.0f64;
    let mut loose_count = 0;
    for j in 0..n {
        if loose(j) {
            loose_count += 1;
            for i in 0..n {
                let want = if i == j { model.loose_diagonal() } else { 0.0 };
                assert_eq!(h[(i, j)], want, "loose coordinate {j}: entry ({i}, {j})");
            }
            continue;
        }
        let mut grad_at = |d: f64| {
            x[j] = u[j] + d;
            let g = model.assemble(&x, active, false).grad;
            x[j] = u[j];
            g
        };
        let (gp, gm) = (grad_at(step), grad_at(-step));
        let (gp2, gm2) = (grad_at(2.0 * step), grad_at(-2.0 * step));
        let scale = (0..n)
            .filter(|&i| !loose(i))
            .fold(0.0f64, |m, i| m.max(h[(i, j)].abs()));
        assert!(scale > 0.0, "column {j} of a non-loose coordinate is empty");
        for i in 0..n {
            if loose(i) {
                continue;
            }
            let fd = (8.0 * (gp[i] - gm[i]) - (gp2[i] - gm2[i])) / (12.0 * step);
            let err = (fd - h[(i, j)]).abs() / scale;
            assert!(
                err <= tol,
                "Hessian entry ({i}, {j}): assembled {:e}, finite difference {fd:e}, column \
                 scale {scale:e}, relative error {err:e} > {tol:e}",
                h[(i, j)]
            );
            worst = worst.max(err);
        }
    }
    (worst, loose_count)
}

#[test]
fn library_energy_is_the_spec_energy() {
    for seed in 0..4u64 {
        let curves = random_curves(seed, 2 + seed as usize % 3);
        let net = build(&curves, 60.0, Supports::Clamped);
        let mut rng = Rng::new(100 + seed);
        for mat in materials() {
            let model = EnergyModel::new(&net, &mat);
            let all = ActiveSet::all(net.rods.len());
            for amp in [0.0, 3.0, 30.0] {
                let u = random_displacement(&net, &mut rng, amp);
                let x = positions_of(&net, &u);
                let mine = spec_energy(&net, &mat, &x, None);
                let lib = model.energy(&u, &all);
                assert!(
                    rel_diff(mine, lib) < 1e-11,
                    "seed {seed}, amplitude {amp}: library energy {lib:e}, formula {mine:e}"
                );
                // `energy` and `assemble` evaluate the bending term in two algebraically equal
                // forms (c·F/G² and c·F·(1/G)²): the last bit may differ.
                assert!(rel_diff(lib, model.assemble(&u, &all, false).energy) < 1e-14);
                // Without curve 1 (an open arch).
                let part = ActiveSet::all(net.rods.len()).without(1);
                let keep: Vec<usize> = part.curves();
                let mine = spec_energy(&net, &mat, &x, Some(&keep));
                let lib = model.energy(&u, &part);
                assert!(
                    rel_diff(mine, lib) < 1e-11,
                    "seed {seed}, without curve 1: library {lib:e}, formula {mine:e}"
                );
            }
        }
    }
}

#[test]
fn drawn_state_energy_is_pure_bending_and_positive() {
    for seed in 0..4u64 {
        let curves = random_curves(seed, 2 + seed as usize % 3);
        let net = build(&curves, 60.0, Supports::Clamped);
        let mat = Material::default();
        let model = EnergyModel::new(&net, &mat);
        let all = ActiveSet::all(net.rods.len());
        let zero = vec![0.0; net.dofs()];
        let a = model.assemble(&zero, &all, false);
        // Rest lengths are the drawn lengths and anchors sit where drawn: only bending is left.
        let x = net.rest_coordinates();
        let mine = spec_energy(&net, &mat, &x, None);
        assert!(
            a.energy > 0.0,
            "drawn curves are bent, energy {:e}",
            a.energy
        );
        assert!(rel_diff(a.energy, mine) < 1e-12);
        // ... because the rest lengths are the drawn lengths (no stretching at u = 0).
        for rod in &net.rods {
            for j in 0..rod.edge_count() {
                let (p, q) = rod.edge(j);
                let len = net.positions[p as usize].dist(net.positions[q as usize]);
                assert!(rel_diff(len, rod.rest_lengths[j]) < 1e-14);
            }
        }
        // The drawn state is not an equilibrium, and its gradient is the true one.
        assert!(norm(&a.grad) > 1e-6 * a.energy / 60.0);
        let err = check_gradient(&model, &zero, &all, GRAD_STEP);
        assert!(
            err < GRAD_TOL,
            "seed {seed}: gradient at u = 0 off by {err:e}"
        );
        // Anchored vertices feel no anchor force at u = 0; interior gradient is from bending.
        let g = &a.grad;
        let net_force: [f64; 3] =
            std::array::from_fn(|c| (0..net.vertex_count()).map(|v| g[3 * v + c]).sum());
        let gsum: f64 = g.iter().map(|x| x.abs()).sum();
        for f in net_force {
            assert!(
                f.abs() < 1e-12 * gsum,
                "internal forces sum to zero at u = 0"
            );
        }
    }
}

#[test]
fn gradient_matches_finite_differences() {
    let mut worst = 0.0f64;
    for seed in 0..4u64 {
        let curves = random_curves(seed, 2 + seed as usize % 3);
        let net = build(&curves, 60.0, Supports::Clamped);
        let mut rng = Rng::new(7 + seed);
        for mat in materials() {
            let model = EnergyModel::new(&net, &mat);
            let all = ActiveSet::all(net.rods.len());
            let without = all.without(1 + seed as usize % (net.rods.len() - 1));
            for amp in [3.0, 15.0] {
                let u = random_displacement(&net, &mut rng, amp);
                for active in [&all, &without] {
                    let err = check_gradient(&model, &u, active, GRAD_STEP);
                    worst = worst.max(err);
                    assert!(
                        err < GRAD_TOL,
                        "seed {seed}, amplitude {amp}, {} curves: gradient off by {err:e} \
                         (relative to its largest entry)",
                        active.len()
                    );
                }
            }
        }
    }
    println!("gradient: worst relative error {worst:e}");
}

#[test]
fn hessian_matches_finite_differences_full_network() {
    let mut worst = 0.0f64;
    for seed in 0..3u64 {
        let curves = random_curves(seed, 2 + seed as usize);
        let net = build(&curves, 60.0, Supports::Clamped);
        let mut rng = Rng::new(31 + seed);
        for mat in materials() {
            let model = EnergyModel::new(&net, &mat);
            let all = ActiveSet::all(net.rods.len());
            let u = random_displacement(&net, &mut rng, 10.0);
            let (err, loose) = check_hessian(&model, &u, &all, HESS_STEP, HESS_TOL);
            assert_eq!(loose, 0, "every vertex is on a curve");
            worst = worst.max(err);
        }
    }
    println!("Hessian, full network: worst relative error {worst:e}");
}

#[test]
fn hessian_matches_finite_differences_without_a_curve() {
    let mut worst = 0.0f64;
    for seed in 0..3u64 {
        let curves = random_curves(seed, 2 + seed as usize);
        let net = build(&curves, 60.0, Supports::Clamped);
        let mut rng = Rng::new(57 + seed);
        // Remove the ring (curve 0: its free vertices become loose) or an arch.
        for removed in [0, 1 + seed as usize] {
            let active = ActiveSet::all(net.rods.len()).without(removed);
            let mat = materials()[(seed as usize + removed) % 2];
            let model = EnergyModel::new(&net, &mat);
            let u = random_displacement(&net, &mut rng, 10.0);
            let (err, loose) = check_hessian(&model, &u, &active, HESS_STEP, HESS_TOL);
            // The removed curve's vertices that are no joint are loose; joints are not.
            let vc = net.vertex_curves();
            let expected = vc
                .iter()
                .filter(|cs| cs.iter().all(|&c| c as usize == removed))
                .count();
            assert!(expected > 0);
            assert_eq!(loose, 3 * expected, "loose coordinates of curve {removed}");
            // Loose coordinates have no gradient either.
            let g = model.assemble(&u, &active, false).grad;
            let mask = model.vertex_mask(&active);
            for (v, on) in mask.iter().enumerate() {
                if !on {
                    assert_eq!(&g[3 * v..3 * v + 3], &[0.0; 3]);
                }
            }
            worst = worst.max(err);
        }
    }
    println!("Hessian, one curve removed: worst relative error {worst:e}");
}

#[test]
fn random_networks_are_connected_as_designed() {
    // Guards the inputs of the tests above: each arch meets the ring twice, every later arch
    // meets arch 0 once, and nothing else crosses.
    for seed in 0..4u64 {
        let n_open = 2 + seed as usize % 3;
        let net = build(&random_curves(seed, n_open), 60.0, Supports::Clamped);
        assert_eq!(net.rods.len(), n_open + 1);
        let mut pairs: Vec<Vec<u32>> = net.joints.iter().map(|j| j.curves.clone()).collect();
        pairs.sort();
        let mut want: Vec<Vec<u32>> = Vec::new();
        for k in 1..=n_open as u32 {
            want.push(vec![0, k]);
            want.push(vec![0, k]);
            if k > 1 {
                want.push(vec![1, k]);
            }
        }
        want.sort();
        assert_eq!(pairs, want, "seed {seed}: joints");
        assert!(net.rods[0].closed && net.rods[0].anchors.is_empty());
        assert!(net.rods[1..].iter().all(|r| r.anchors.len() == 4));
    }
}

#[test]
fn derivatives_on_a_self_crossing_rod() {
    // A rod that passes one vertex twice: terms of one rod share a vertex at two places.
    for h in [30.0, 60.0] {
        let net = build(&[common::curl_curve(30.0)], h, Supports::Clamped);
        assert_eq!(net.joints.len(), 1);
        assert_eq!(net.joints[0].curves, vec![0]);
        let j = net.joints[0].vertex;
        assert_eq!(net.rods[0].vertices.iter().filter(|&&v| v == j).count(), 2);
        let mut rng = Rng::new(h as u64);
        for mat in materials() {
            let model = EnergyModel::new(&net, &mat);
            let all = ActiveSet::all(1);
            let u = random_displacement(&net, &mut rng, 3.0);
            let x = positions_of(&net, &u);
            assert!(rel_diff(model.energy(&u, &all), spec_energy(&net, &mat, &x, None)) < 1e-11);
            let err = check_gradient(&model, &u, &all, GRAD_STEP);
            assert!(err < GRAD_TOL, "h = {h}: gradient off by {err:e}");
            check_hessian(&model, &u, &all, HESS_STEP, HESS_TOL);
        }
    }
}

#[test]
fn short_self_loop_has_a_finite_energy() {
    // The curl (length 188) at h = 100: the piece from the joint back to itself would get
    // max(2, round(1.88)) = 2 edges, J → a → J, whose bending term at `a` has
    // ē₀ē₁ + e₀·e₁ = 0 (NaN energy); a loop gets at least 3 edges.
    let net = build(&[common::curl_curve(30.0)], 100.0, Supports::Clamped);
    let model = EnergyModel::new(&net, &Material::default());
    let u = vec![0.0; net.dofs()];
    let a = model.assemble(&u, &ActiveSet::all(1), true);
    assert!(a.energy.is_finite(), "energy {}", a.energy);
    assert!(a.grad.iter().chain(&a.hess).all(|x| x.is_finite()));
}

/// Rods of different stiffnesses, some pre-bent: every second curve pre-bent (the ring among
/// them), stiffnesses varying by curve so that a term wired to the wrong rod shows.
fn mixed_rods(net: &Network, mat: &Material) -> Vec<RodStiffness> {
    (0..net.rods.len())
        .map(|c| RodStiffness {
            ks: mat.ks() * (1.0 + 0.5 * c as f64),
            kb: mat.kb() * (2.0 - 0.3 * c as f64),
            gj: mat.kb() * (0.6 + 0.2 * c as f64),
            arm: mat.radius * (1.0 + 0.1 * c as f64),
            rest: if c % 2 == 0 {
                RestShape::PreBent
            } else {
                RestShape::Straight
            },
        })
        .collect()
}

#[test]
fn derivatives_with_pre_bent_rods_and_per_rod_stiffness() {
    let mut worst = (0.0f64, 0.0f64);
    for seed in 0..3u64 {
        let curves = random_curves(seed, 2 + seed as usize);
        let net = build(&curves, 60.0, Supports::Clamped);
        let mut rng = Rng::new(91 + seed);
        for mat in materials() {
            let model = EnergyModel::with_rods(&net, &mixed_rods(&net, &mat), mat.anchor_weight);
            let all = ActiveSet::all(net.rods.len());
            let without = all.without(1 + seed as usize % (net.rods.len() - 1));
            let u = random_displacement(&net, &mut rng, 10.0);
            for active in [&all, &without] {
                let g = check_gradient(&model, &u, active, GRAD_STEP);
                assert!(g < GRAD_TOL, "seed {seed}: gradient off by {g:e}");
                let (h, _) = check_hessian(&model, &u, active, HESS_STEP, HESS_TOL);
                worst = (worst.0.max(g), worst.1.max(h));
                // `energy` and `assemble` agree.
                let e = model.energy(&u, active);
                assert!(rel_diff(e, model.assemble(&u, active, true).energy) < 1e-14);
            }
        }
    }
    println!(
        "pre-bent and per-rod stiffness: gradient {:e}, Hessian {:e}",
        worst.0, worst.1
    );
}

#[test]
fn a_network_of_pre_bent_rods_rests_where_drawn() {
    for seed in 0..4u64 {
        let curves = random_curves(seed, 2 + seed as usize % 3);
        let net = build(&curves, 60.0, Supports::Clamped);
        let mat = Material::default();
        let rods: Vec<RodStiffness> = (0..net.rods.len())
            .map(|_| RodStiffness {
                rest: RestShape::PreBent,
                ..RodStiffness::from(&mat)
            })
            .collect();
        let model = EnergyModel::with_rods(&net, &rods, mat.anchor_weight);
        let all = ActiveSet::all(net.rods.len());
        let zero = vec![0.0; net.dofs()];
        let a = model.assemble(&zero, &all, false);
        // Bending is exactly zero; stretching only the round-off of the rest lengths.
        let straight = EnergyModel::new(&net, &mat).assemble(&zero, &all, false);
        assert!(a.energy <= 1e-24 * straight.energy, "{:e}", a.energy);
        assert!(
            norm(&a.grad) <= 1e-12 * norm(&straight.grad),
            "{:e}",
            norm(&a.grad)
        );
    }
}

/// [`random_displacement`] followed by a twist for each twist unknown of `model`: an angle of
/// up to ~0.3 rad times the unknown's arm (`s = r θ`), smooth along each rod.
fn random_unknowns(net: &Network, model: &EnergyModel, rng: &mut Rng, amp: f64) -> Vec<f64> {
    let mut u = random_displacement(net, rng, amp);
    let phase = rng.range(0.0, std::f64::consts::TAU);
    for t in model.twist_dofs() {
        let arg = 0.2 * t.edge as f64 + phase + t.curve as f64;
        u.push(0.3 * 40.0 * arg.sin() + 0.5 * rng.normal());
    }
    assert_eq!(u.len(), model.dofs());
    u
}

#[test]
fn derivatives_under_the_physical_rules_with_twist() {
    let mut worst = (0.0f64, 0.0f64);
    let mut twists = 0;
    for seed in 0..3u64 {
        let curves = random_curves(seed, 2 + seed as usize);
        for supports in [Supports::Clamped, Supports::Pinned] {
            let net = build(&curves, 60.0, supports);
            let mut rng = Rng::new(191 + seed);
            for mat in materials() {
                let rods = mixed_rods(&net, &mat);
                let model =
                    EnergyModel::with_rules(&net, &rods, mat.anchor_weight, ModelRules::PHYSICAL);
                twists += model.twist_count();
                assert!(model.twist_count() > 0);
                let all = ActiveSet::all(net.rods.len());
                // Without a pre-bent curve: its twists are loose.
                let without = all.without(2 * (seed as usize % 2));
                let u = random_unknowns(&net, &model, &mut rng, 10.0);
                for active in [&all, &without] {
                    let g = check_gradient(&model, &u, active, GRAD_STEP);
                    assert!(g < GRAD_TOL, "seed {seed}: gradient off by {g:e}");
                    let (h, _) = check_hessian(&model, &u, active, HESS_STEP, HESS_TOL);
                    worst = (worst.0.max(g), worst.1.max(h));
                    let e = model.energy(&u, active);
                    assert!(rel_diff(e, model.assemble(&u, active, true).energy) < 1e-14);
                }
            }
        }
    }
    println!(
        "physical rules with {twists} twists: gradient {:e}, Hessian {:e}",
        worst.0, worst.1
    );
}

#[test]
fn pre_bent_rods_with_twist_rest_where_drawn() {
    for seed in 0..4u64 {
        let curves = random_curves(seed, 2 + seed as usize % 3);
        for supports in [Supports::Clamped, Supports::Pinned] {
            let net = build(&curves, 60.0, supports);
            let mat = Material::default();
            let rods: Vec<RodStiffness> = (0..net.rods.len())
                .map(|_| RodStiffness {
                    rest: RestShape::PreBent,
                    ..RodStiffness::from(&mat)
                })
                .collect();
            let model =
                EnergyModel::with_rules(&net, &rods, mat.anchor_weight, ModelRules::PHYSICAL);
            let all = ActiveSet::all(net.rods.len());
            let zero = vec![0.0; model.dofs()];
            let a = model.assemble(&zero, &all, false);
            let straight =
                EnergyModel::new(&net, &mat).assemble(&vec![0.0; net.dofs()], &all, false);
            assert!(a.energy <= 1e-24 * straight.energy, "{:e}", a.energy);
            assert!(
                norm(&a.grad) <= 1e-12 * norm(&straight.grad),
                "{:e}",
                norm(&a.grad)
            );
        }
    }
}
