//! Textbook beam results on a straight rod (docs/model.md, *Energy* and *Stability*).
//!
//! (a) Axial stiffness: on a uniform stretch field `u_i = δ·x_i/L` the Hessian's quadratic
//!     form is `(k_s/L)·δ²`; on a parabolic transverse field `w = 4δ·x(L−x)/L²` it is the
//!     discrete bending value `64·k_b·δ²·(L−h)/L⁴` (→ `64 k_b δ²/L³`, the continuum
//!     `∫k_b w''²`), and with clamped anchors the anchors' `2µ|u_a|²` is added.
//! (b) Euler–Bernoulli modes of a pinned–pinned rod: there is no mass matrix, so
//!     `λ₁ ≈ k_b (π/L)⁴ h`: `λ₁/h` converges as `h → 0` (relative error decreasing
//!     at second order, finest within 1 %), `λ₁` is a repeated pair (the two transverse directions), the next pair
//!     is the second mode `≈ 16 λ₁` (`n⁴`), and the sparse solver agrees with dense eigenvalues.
//! (c) Clamping raises `λ₁` over pinning, by about the clamped/pinned ratio `(4.730/π)⁴`.

mod common;

use common::{dense_hessian, rel_diff, straight_rod, without_anchors};
use curvenet::geom::Vec3;
use curvenet::network::Network;
use curvenet::rod::{ActiveSet, EnergyModel, Material, Supports};
use curvenet::solve::lanczos::smallest_eigenpairs_dense;
use curvenet::stability::{Analyzer, StabilityParams};
use std::f64::consts::PI;

/// `uᵀ H u` at the rest state.
fn quadratic_form(model: &EnergyModel, net: &Network, u: &[f64]) -> f64 {
    let zero = vec![0.0; net.dofs()];
    let all = ActiveSet::all(net.rods.len());
    let h = model.assemble(&zero, &all, true).hess;
    let mut hu = vec![0.0; u.len()];
    model.pattern().sym_matvec(&h, u, &mut hu);
    u.iter().zip(&hu).map(|(a, b)| a * b).sum()
}

/// Arc-length coordinate of every vertex along the rod from `start`.
fn abscissa(net: &Network, start: Vec3, dir: Vec3) -> Vec<f64> {
    net.positions
        .iter()
        .map(|p| (*p - start).dot(dir))
        .collect()
}

#[test]
fn axial_and_bending_stiffness_of_a_straight_rod() {
    let mat = Material::default();
    let (ks, kb) = (mat.ks(), mat.kb());
    let (len, n, delta) = (1000.0, 25usize, 0.7);
    let h = len / n as f64;
    let start = Vec3::new(-120.0, 40.0, 7.0);
    let tilted = Vec3::new(0.3, -0.5, 0.8).normalized();
    for dir in [Vec3::new(1.0, 0.0, 0.0), tilted] {
        // A direction perpendicular to the rod for the transverse field.
        let perp = dir.cross(Vec3::new(0.0, 0.0, 1.0) + dir * 0.1).normalized();
        let clamped = straight_rod(start, dir, len, n, Supports::Clamped);
        let free = without_anchors(clamped.clone());
        let s = abscissa(&free, start, dir);
        let stretch: Vec<f64> = s
            .iter()
            .flat_map(|&x| (dir * (delta * x / len)).to_array())
            .collect();
        let bend: Vec<f64> = s
            .iter()
            .flat_map(|&x| (perp * (4.0 * delta * x * (len - x) / (len * len))).to_array())
            .collect();

        let model = EnergyModel::new(&free, &mat);
        let q = quadratic_form(&model, &free, &stretch);
        let want = ks / len * delta * delta;
        assert!(
            rel_diff(q, want) < 1e-10,
            "axial stiffness: uᵀHu = {q:e}, k_s δ²/L = {want:e}"
        );
        let q = quadratic_form(&model, &free, &bend);
        let want = 64.0 * kb * delta * delta * (len - h) / len.powi(4);
        // The stretching blocks (k_s/h ≈ 0.3, a million times the bending form here) cancel
        // on a transverse field only up to round-off when the rod is not axis-aligned: allow
        // 10 ε (k_s/h) |u|² on top.
        let u2: f64 = bend.iter().map(|x| x * x).sum();
        let tol = 1e-12 + 10.0 * f64::EPSILON * (ks / h) * u2 / want;
        assert!(
            rel_diff(q, want) < tol,
            "bending stiffness along {dir:?}: uᵀHu = {q:e}, 64 k_b δ² (L−h)/L⁴ = {want:e}, \
             tolerance {tol:e}"
        );

        // With the clamped anchors: + 2µ Σ |u_a|² over the four anchored vertices.
        let model = EnergyModel::new(&clamped, &mat);
        assert_eq!(clamped.rods[0].anchors.len(), 4);
        let anchors: f64 = clamped.rods[0]
            .anchors
            .iter()
            .map(|&a| {
                (0..3)
                    .map(|c| stretch[3 * a as usize + c].powi(2))
                    .sum::<f64>()
            })
            .sum();
        let q = quadratic_form(&model, &clamped, &stretch);
        let want = ks / len * delta * delta + 2.0 * mat.anchor_weight * anchors;
        assert!(rel_diff(q, want) < 1e-10, "with anchors: {q:e} vs {want:e}");
    }
}

/// A pinned-pinned (or clamped) rod along x of length `len` with `n` edges and stiff anchors.
fn rod_analyzer(len: f64, n: usize, supports: Supports) -> Analyzer {
    let net = straight_rod(
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        len,
        n,
        supports,
    );
    let params = StabilityParams {
        material: Material {
            anchor_weight: 1e7,
            ..Material::default()
        },
        ..StabilityParams::default()
    };
    Analyzer::new(net, params).expect("analyzer")
}

/// The smallest eigenvalues at the (straight, stress-free) rest state.
fn rest_spectrum(a: &Analyzer) -> Vec<f64> {
    let zero = vec![0.0; a.model().dofs()];
    // The rest state is an equilibrium.
    let g = a.model().assemble(&zero, &a.all(), false).grad;
    assert!(g.iter().all(|&x| x == 0.0));
    let s = a.spectrum(&a.all(), &zero, None).expect("spectrum");
    assert_eq!(s.zero_modes, 0);
    assert_eq!(s.negative_modes, 0);
    assert!(
        s.residuals.iter().all(|&r| r < common::RESIDUAL_BOUND),
        "{:?}",
        s.residuals
    );
    s.values
}

#[test]
fn pinned_rod_converges_to_euler_bernoulli() {
    // L = 100 keeps the axial modes (λ/h ≈ k_s (π/L)²) far above the first two bending
    // pairs: k_s/k_b (L/π)² ≈ 1000 ≫ 16.
    let len = 100.0;
    let kb = Material::default().kb();
    let exact = kb * (PI / len).powi(4);
    let mut last_err = f64::INFINITY;
    let mut report = Vec::new();
    for n in [20usize, 40, 80, 160] {
        let h = len / n as f64;
        let a = rod_analyzer(len, n, Supports::Pinned);
        let vals = rest_spectrum(&a);
        let l1 = vals[0] / h;
        let err = rel_diff(l1, exact);
        report.push(format!(
            "n = {n}: λ₁/h = {l1:.6e} (error {err:.2e}), λ₃/λ₁ = {:.4}",
            vals[2] / vals[0]
        ));
        // Second-order convergence: the error shrinks ~4× per halving of h.
        let shrink = last_err / err;
        assert!(
            last_err.is_infinite() || (3.0..5.0).contains(&shrink),
            "error does not decrease at second order: {report:?}"
        );
        last_err = err;
        // Two transverse directions: an exact pair, then the second mode's pair at ~n⁴ = 16.
        assert!(rel_diff(vals[0], vals[1]) < 1e-8, "λ₁, λ₂ = {vals:?}");
        assert!(rel_diff(vals[2], vals[3]) < 1e-8, "λ₃, λ₄ = {vals:?}");
        let ratio = vals[2] / vals[0];
        assert!(
            (ratio - 16.0).abs() < 0.02 * 16.0,
            "n = {n}: second mode at {ratio} λ₁, expected ≈ 16"
        );
    }
    println!("{}", report.join("\n"));
    assert!(last_err < 0.01, "finest λ₁/h within 1 %: {report:?}");
}

#[test]
fn sparse_eigenvalues_agree_with_dense_on_a_rod() {
    // A dense eigensolver is accurate to ~ε‖H‖₁ in absolute terms; with µ = 1e7 that is 1e-8,
    // already 1e-4 of λ₁ at n = 20 (shift-and-invert through a Cholesky factor does better on
    // such graded matrices). So compare on rods with a moderate anchor weight, µ = 1e3.
    for (n, supports) in [(20usize, Supports::Pinned), (40, Supports::Clamped)] {
        let mut a = rod_analyzer(100.0, n, supports);
        let net = a.network().clone();
        let mut params = a.params().clone();
        params.material.anchor_weight = 1e3;
        a = Analyzer::new(net, params).expect("analyzer");
        let vals = rest_spectrum(&a);
        let zero = vec![0.0; a.model().dofs()];
        let hd = dense_hessian(a.model(), &zero, &a.all());
        let (dense, _) = smallest_eigenpairs_dense(hd.as_ref(), 4).expect("dense solve");
        for k in 0..4 {
            let d = rel_diff(dense[k], vals[k]);
            println!(
                "n = {n}, {supports:?}: λ{k}: sparse {:e}, dense {:e}, rel {d:e}",
                vals[k], dense[k]
            );
            assert!(
                d < 1e-8,
                "n = {n}: eigenvalue {k}: sparse {:e}, dense {:e}",
                vals[k],
                dense[k]
            );
        }
    }
}

#[test]
fn clamping_stiffens_the_rod() {
    let len = 100.0;
    let n = 160;
    let h = len / n as f64;
    let pinned = rest_spectrum(&rod_analyzer(len, n, Supports::Pinned))[0];
    let clamped = rest_spectrum(&rod_analyzer(len, n, Supports::Clamped))[0];
    assert!(clamped > pinned, "clamped {clamped:e} ≤ pinned {pinned:e}");
    // Clamped–clamped / pinned–pinned first modes: (4.7300/π)⁴ = 5.14 for the same span.
    // The discrete clamp holds the first and last two vertices: zero slope on the first edge,
    // i.e. at its midpoint, so the clamped span is L − h.
    let theory = (4.730_040_7 / PI).powi(4) * (len / (len - h)).powi(4);
    let ratio = clamped / pinned;
    println!("clamped/pinned = {ratio:.5}, theory with span L − h: {theory:.5}");
    assert!(
        rel_diff(ratio, theory) < 0.005,
        "clamped/pinned = {ratio}, expected ≈ {theory}"
    );
}
