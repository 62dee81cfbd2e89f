//! Rigid-motion invariance and symmetry of the energy (docs/model.md, *Energy*), with every anchor cleared.
//!
//! - the energy of a deformed state is unchanged by a rotation + translation of the positions
//!   (converted back to displacements from the rest state), the gradient rotates with it and
//!   the Hessian is conjugated by the rotation;
//! - at any state, translations are exact null vectors of the Hessian, and an infinitesimal
//!   rotation `Ωx` satisfies `H·Ωx = Ω·∇E` (rotations are null vectors exactly at equilibria);
//! - at a stress-free state (a tetrahedral frame of straight rods, and a curved random network
//!   relaxed without anchors) the dense Hessian has exactly 6 zero eigenvalues and their
//!   eigenvectors span the rigid motions;
//! - no net force and no net torque without anchors (and with anchors, the net force is the
//!   anchors' pull);
//! - the Hessian is symmetric: the stored pattern is a proper upper triangle, and the Jacobian
//!   of the assembled gradient (by finite differences, not symmetric by construction) equals
//!   its transpose and the assembled matrix.

mod common;

use common::{
    Rng, build, dense_hessian, norm, orthonormalize, positions_of, random_curves, rigid_motions,
    tetrahedron_curves, without_anchors,
};
use curvenet::geom::Vec3;
use curvenet::network::Network;
use curvenet::rod::{ActiveSet, EnergyModel, Material, Supports};
use curvenet::solve::lanczos::smallest_eigenpairs_dense;
use curvenet::stability::{Analyzer, StabilityParams};

/// Rotation matrix of angle `angle` about the unit `axis` (Rodrigues).
fn rotation(axis: Vec3, angle: f64) -> [[f64; 3]; 3] {
    let k = axis.normalized();
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    [
        [
            c + k.x * k.x * t,
            k.x * k.y * t - k.z * s,
            k.x * k.z * t + k.y * s,
        ],
        [
            k.y * k.x * t + k.z * s,
            c + k.y * k.y * t,
            k.y * k.z * t - k.x * s,
        ],
        [
            k.z * k.x * t - k.y * s,
            k.z * k.y * t + k.x * s,
            c + k.z * k.z * t,
        ],
    ]
}

fn apply(r: &[[f64; 3]; 3], p: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2])
}

/// Rotates every 3-vector of a flat vector.
fn rotate_all(r: &[[f64; 3]; 3], v: &[f64]) -> Vec<f64> {
    v.chunks(3)
        .flat_map(|c| apply(r, [c[0], c[1], c[2]]))
        .collect()
}

fn random_u(n: usize, rng: &mut Rng, amp: f64) -> Vec<f64> {
    (0..n).map(|_| amp * rng.normal()).collect()
}

fn free_network(seed: u64) -> Network {
    without_anchors(build(
        &random_curves(seed, 2 + seed as usize % 3),
        60.0,
        Supports::Clamped,
    ))
}

#[test]
fn energy_gradient_and_hessian_follow_rigid_motions() {
    let mut worst = [0.0f64; 3];
    for seed in 0..4u64 {
        let net = free_network(seed);
        let model = EnergyModel::new(&net, &Material::default());
        let all = ActiveSet::all(net.rods.len());
        let mut rng = Rng::new(1000 + seed);
        let rest = net.rest_coordinates();
        let u = random_u(net.dofs(), &mut rng, 4.0);
        let a = model.assemble(&u, &all, true);
        assert!(a.energy > 0.0);
        for _ in 0..3 {
            let axis = rng.normal3();
            let r = rotation(axis, rng.range(-3.1, 3.1));
            let t = [
                rng.range(-500.0, 500.0),
                rng.range(-500.0, 500.0),
                rng.range(-500.0, 500.0),
            ];
            // x' = R (X + u) + t, u' = x' − X.
            let x = positions_of(&net, &u);
            let moved: Vec<f64> = rotate_all(&r, &x)
                .chunks(3)
                .flat_map(|c| [c[0] + t[0], c[1] + t[1], c[2] + t[2]])
                .collect();
            let u2: Vec<f64> = moved.iter().zip(&rest).map(|(a, b)| a - b).collect();
            let b = model.assemble(&u2, &all, true);
            let e_err = (b.energy - a.energy).abs() / a.energy;
            assert!(
                e_err < 1e-12,
                "seed {seed}: energy {:e} became {:e} under a rigid motion",
                a.energy,
                b.energy
            );
            // ∇E(x') = R ∇E(x).
            let rg = rotate_all(&r, &a.grad);
            let gscale = a.grad.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let g_err = rg
                .iter()
                .zip(&b.grad)
                .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()))
                / gscale;
            assert!(
                g_err < 1e-10,
                "seed {seed}: gradient not equivariant ({g_err:e})"
            );
            // H(x') R v = R H(x) v for a random v.
            let v = random_u(net.dofs(), &mut rng, 1.0);
            let p = model.pattern();
            let mut hv = vec![0.0; net.dofs()];
            p.sym_matvec(&a.hess, &v, &mut hv);
            let rhv = rotate_all(&r, &hv);
            let mut h2rv = vec![0.0; net.dofs()];
            p.sym_matvec(&b.hess, &rotate_all(&r, &v), &mut h2rv);
            let h_err = rhv
                .iter()
                .zip(&h2rv)
                .map(|(p, q)| (p - q).powi(2))
                .sum::<f64>()
                .sqrt()
                / norm(&hv);
            assert!(
                h_err < 1e-10,
                "seed {seed}: Hessian not equivariant ({h_err:e})"
            );
            worst = [
                worst[0].max(e_err),
                worst[1].max(g_err),
                worst[2].max(h_err),
            ];
        }
    }
    println!(
        "rigid motions: worst energy {:e}, gradient {:e}, Hessian {:e}",
        worst[0], worst[1], worst[2]
    );
}

#[test]
fn translations_are_null_and_rotations_satisfy_h_omega_x_equals_omega_g() {
    for seed in 0..4u64 {
        let net = free_network(seed);
        let model = EnergyModel::new(&net, &Material::default());
        let all = ActiveSet::all(net.rods.len());
        let mut rng = Rng::new(2000 + seed);
        let u = random_u(net.dofs(), &mut rng, 4.0);
        let a = model.assemble(&u, &all, true);
        let x = positions_of(&net, &u);
        let p = model.pattern();
        let hnorm = p.sym_norm1(&a.hess);
        let motions = rigid_motions(&x);
        let mut hr = vec![0.0; net.dofs()];
        for (k, r) in motions.iter().enumerate() {
            p.sym_matvec(&a.hess, r, &mut hr);
            // Translations: H t = 0. Rotation about e_k: H (e_k × x) = e_k × ∇E.
            let want: Vec<f64> = if k < 3 {
                vec![0.0; net.dofs()]
            } else {
                let mut e = Vec3::ZERO;
                e[k - 3] = 1.0;
                a.grad
                    .chunks(3)
                    .flat_map(|g| e.cross(Vec3::new(g[0], g[1], g[2])).to_array())
                    .collect()
            };
            let err = norm(&hr.iter().zip(&want).map(|(p, q)| p - q).collect::<Vec<_>>());
            let scale = hnorm * norm(r);
            assert!(
                err < 1e-13 * scale,
                "seed {seed}, rigid motion {k}: ‖H r − want‖ = {err:e}, ‖H‖‖r‖ = {scale:e}"
            );
            if k >= 3 {
                // Away from equilibrium the rotation is not a null vector: the identity is
                // not trivially satisfied.
                assert!(norm(&want) > 1e-6 * scale);
            }
        }
    }
}

/// Checks that `h` (dense, at a stress-free or equilibrium state with positions `x`) has
/// exactly six zero eigenvalues whose eigenvectors span the rigid motions of `x`.
fn check_six_rigid_zero_modes(h: faer::MatRef<'_, f64>, x: &[f64], what: &str) {
    let n = h.nrows();
    let hnorm = (0..n)
        .map(|j| (0..n).map(|i| h[(i, j)].abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let (vals, vecs) = smallest_eigenpairs_dense(h, 8).expect("dense solve");
    let zero = 100.0 * f64::EPSILON * hnorm;
    let zeros = vals.iter().filter(|l| l.abs() <= zero).count();
    println!(
        "{what}: ‖H‖₁ = {hnorm:e}, smallest eigenvalues {:?}",
        vals.iter().map(|v| format!("{v:.3e}")).collect::<Vec<_>>()
    );
    assert_eq!(
        zeros, 6,
        "{what}: zero eigenvalues (threshold {zero:e}): {vals:?}"
    );
    assert!(
        vals[6] > 1e4 * zero,
        "{what}: the 7th eigenvalue {:e} is well separated from zero",
        vals[6]
    );
    // Each null vector lies in the span of the rigid motions, and every rigid motion is in
    // the computed null space.
    let rigid = orthonormalize(&rigid_motions(x));
    for k in 0..6 {
        let v: Vec<f64> = (0..n).map(|i| vecs[(i, k)]).collect();
        let mut rest = v.clone();
        for q in &rigid {
            let d: f64 = v.iter().zip(q).map(|(a, b)| a * b).sum();
            rest.iter_mut().zip(q).for_each(|(a, b)| *a -= d * b);
        }
        let off = norm(&rest) / norm(&v);
        assert!(
            off < 1e-6,
            "{what}: null vector {k} is {off:e} away from rigid motions"
        );
    }
    for (k, q) in rigid.iter().enumerate() {
        let captured: f64 = (0..6)
            .map(|c| (0..n).map(|i| vecs[(i, c)] * q[i]).sum::<f64>().powi(2))
            .sum();
        assert!(
            (1.0 - captured).abs() < 1e-10,
            "{what}: rigid motion {k} only {captured} inside the null space"
        );
    }
}

#[test]
fn stress_free_frame_has_exactly_six_rigid_zero_modes() {
    let net = without_anchors(build(&tetrahedron_curves(), 40.0, Supports::Clamped));
    assert_eq!(net.joints.len(), 4, "the six rods meet at the four corners");
    assert!(net.joints.iter().all(|j| j.curves.len() == 3));
    let model = EnergyModel::new(&net, &Material::default());
    let all = ActiveSet::all(net.rods.len());
    let zero = vec![0.0; net.dofs()];
    let a = model.assemble(&zero, &all, false);
    // Straight rods at their rest lengths: stress-free.
    assert!(a.energy.abs() < 1e-20, "energy {:e}", a.energy);
    assert!(norm(&a.grad) < 1e-12, "gradient {:e}", norm(&a.grad));
    let h = dense_hessian(&model, &zero, &all);
    check_six_rigid_zero_modes(h.as_ref(), &net.rest_coordinates(), "tetrahedral frame");
}

#[test]
fn relaxed_free_network_has_exactly_six_rigid_zero_modes() {
    // A curved network (ring + arches, no anchors) relaxed to its own equilibrium.
    let net = free_network(1);
    let analyzer = Analyzer::new(net.clone(), StabilityParams::default()).expect("analyzer");
    let all = analyzer.all();
    let mut u = vec![0.0; net.dofs()];
    let info = analyzer.relax(&all, &mut u);
    println!("free network relax: {info:?}");
    assert!(
        info.converged,
        "Newton converges on a free network: {info:?}"
    );
    let model = analyzer.model();
    let h = dense_hessian(model, &u, &all);
    check_six_rigid_zero_modes(h.as_ref(), &positions_of(&net, &u), "relaxed free network");
}

#[test]
fn no_net_force_or_torque_without_anchors() {
    for seed in 0..4u64 {
        let net = free_network(seed);
        let model = EnergyModel::new(&net, &Material::default());
        let all = ActiveSet::all(net.rods.len());
        let mut rng = Rng::new(3000 + seed);
        for amp in [0.0, 1.0, 10.0] {
            let u = random_u(net.dofs(), &mut rng, amp);
            let g = model.assemble(&u, &all, false).grad;
            let x = positions_of(&net, &u);
            let gsum: f64 = g.iter().map(|v| v.abs()).sum();
            assert!(gsum > 0.0);
            let mut force = Vec3::ZERO;
            let mut torque = Vec3::ZERO;
            let mut torque_scale = 0.0;
            for v in 0..net.vertex_count() {
                let f = Vec3::new(g[3 * v], g[3 * v + 1], g[3 * v + 2]);
                let p = Vec3::new(x[3 * v], x[3 * v + 1], x[3 * v + 2]);
                force += f;
                torque += p.cross(f);
                torque_scale += p.norm() * f.norm();
            }
            assert!(
                force.norm() < 1e-13 * gsum,
                "seed {seed}, amplitude {amp}: net force {force:?} (Σ|g| = {gsum:e})"
            );
            assert!(
                torque.norm() < 1e-13 * torque_scale,
                "seed {seed}, amplitude {amp}: net torque {torque:?} (scale {torque_scale:e})"
            );
        }
    }
    // With anchors the net force is exactly the anchors' pull Σ 2µ u_a.
    let net = build(&random_curves(5, 3), 60.0, Supports::Clamped);
    let mat = Material::default();
    let model = EnergyModel::new(&net, &mat);
    let mut rng = Rng::new(77);
    let u = random_u(net.dofs(), &mut rng, 2.0);
    let g = model
        .assemble(&u, &ActiveSet::all(net.rods.len()), false)
        .grad;
    let mut force = [0.0; 3];
    let mut pull = [0.0; 3];
    for v in 0..net.vertex_count() {
        for c in 0..3 {
            force[c] += g[3 * v + c];
        }
    }
    for rod in &net.rods {
        for &a in &rod.anchors {
            for c in 0..3 {
                pull[c] += 2.0 * mat.anchor_weight * u[3 * a as usize + c];
            }
        }
    }
    for c in 0..3 {
        assert!(pull[c].abs() > 1.0);
        assert!((force[c] - pull[c]).abs() < 1e-10 * pull[c].abs());
    }
}

#[test]
fn hessian_is_symmetric() {
    let net = free_network(2);
    let model = EnergyModel::new(&net, &Material::default());
    let all = ActiveSet::all(net.rods.len());
    let p = model.pattern();
    // The stored pattern is an upper triangle with sorted rows and correct diagonal slots, so
    // the stored values define one symmetric matrix.
    assert_eq!(p.col_ptr.len(), p.n + 1);
    for j in 0..p.n {
        let rows = &p.row_idx[p.col_ptr[j]..p.col_ptr[j + 1]];
        assert!(rows.windows(2).all(|w| w[0] < w[1]), "column {j} sorted");
        assert!(
            rows.iter().all(|&i| i <= j),
            "column {j} is upper-triangular"
        );
        assert_eq!(p.row_idx[p.diag[j]], j);
        assert!(p.col_ptr[j] <= p.diag[j] && p.diag[j] < p.col_ptr[j + 1]);
    }
    let mut rng = Rng::new(4242);
    let u = random_u(net.dofs(), &mut rng, 3.0);
    let h = dense_hessian(&model, &u, &all);
    // sym_matvec agrees with the dense expansion.
    let v = random_u(net.dofs(), &mut rng, 1.0);
    let mut hv = vec![0.0; net.dofs()];
    p.sym_matvec(&model.assemble(&u, &all, true).hess, &v, &mut hv);
    for i in 0..net.dofs() {
        let d: f64 = (0..net.dofs()).map(|j| h[(i, j)] * v[j]).sum();
        assert!((d - hv[i]).abs() <= 1e-12 * norm(&hv));
    }
    // Several vectors in one pass: each result bit-identical to its own product.
    let w = random_u(net.dofs(), &mut rng, 1.0);
    let mut hw = vec![0.0; net.dofs()];
    let hess = model.assemble(&u, &all, true).hess;
    p.sym_matvec(&hess, &w, &mut hw);
    let x: Vec<[f64; 2]> = v.iter().zip(&w).map(|(a, b)| [*a, *b]).collect();
    let mut y = vec![[0.0; 2]; net.dofs()];
    p.sym_matvec_many(&hess, &x, &mut y);
    for i in 0..net.dofs() {
        assert_eq!(y[i][0].to_bits(), hv[i].to_bits(), "first vector, row {i}");
        assert_eq!(y[i][1].to_bits(), hw[i].to_bits(), "second vector, row {i}");
    }
    // The Jacobian of the gradient, by central differences column by column, is not symmetric
    // by construction: it is when the gradient is a true gradient field.
    let n = net.dofs();
    let step = 1e-4;
    let mut jac = faer::Mat::<f64>::zeros(n, n);
    let mut x = u.clone();
    for j in 0..n {
        x[j] = u[j] + step;
        let gp = model.assemble(&x, &all, false).grad;
        x[j] = u[j] - step;
        let gm = model.assemble(&x, &all, false).grad;
        x[j] = u[j];
        for i in 0..n {
            jac[(i, j)] = (gp[i] - gm[i]) / (2.0 * step);
        }
    }
    let mut worst = 0.0f64;
    for j in 0..n {
        let col: f64 = (0..n).fold(0.0, |m, i| m.max(h[(i, j)].abs()));
        for i in 0..n {
            let s = col.max((0..n).fold(0.0, |m, k| m.max(h[(k, i)].abs())));
            let asym = (jac[(i, j)] - jac[(j, i)]).abs() / s;
            let off = (jac[(i, j)] - h[(i, j)]).abs() / s;
            worst = worst.max(asym).max(off);
        }
    }
    assert!(
        worst < 1e-6,
        "finite-difference Jacobian asymmetric or off by {worst:e}"
    );
    println!("symmetry: worst {worst:e}");
}
