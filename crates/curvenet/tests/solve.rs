//! Solver plumbing: the numeric factorization reuses buffers of dropped factors
//! (`solve::factor`), which must never change its values; eigenpairs of a structure with loose
//! vertices computed on the principal submatrix (`solve::EigenOptions::keep`) agree with those
//! of the whole matrix; the subtree-parallel backend against faer's, bit for bit where it
//! promises so; Newton's speed techniques against none; Newton's convergence scale.

mod common;

use common::{build, data_dir, norm, polyline, random_arches, random_curves};
use curvenet::geom::Vec3;
use curvenet::rod::model::Terms;
use curvenet::rod::{ActiveSet, Supports};
use curvenet::solve::{
    Backend, Cholesky, EigenOptions, Equilibrium, NewtonStop, Reuse, Schedule, Spectrum,
    SymbolicFactor, smallest_eigenpairs,
};
use curvenet::stability::{Analyzer, StabilityParams};

/// The solution of `F x = b` for a fixed right-hand side `b`.
fn solve_fixed(f: &Cholesky, n: usize) -> Vec<f64> {
    let mut rhs: Vec<f64> = (0..n).map(|i| ((i * 7919) % 101) as f64 - 50.0).collect();
    f.solve_vec(&mut rhs);
    rhs
}

fn solve_bits(f: &Cholesky, n: usize) -> Vec<u64> {
    solve_fixed(f, n).iter().map(|v| v.to_bits()).collect()
}

/// The analyzer of random curves (`seed`, four open ones) at edge length `h`, and the whole
/// network's Hessian in the drawn state.
fn drawn_hessian(seed: u64, h: f64) -> (Analyzer, Vec<f64>) {
    let net = build(&random_curves(seed, 4), h, Supports::Clamped);
    let a = Analyzer::new(net, StabilityParams::default()).expect("analyzer");
    let u = vec![0.0; a.model().dofs()];
    let hess = a.model().assemble(&u, &a.all(), true).hess;
    (a, hess)
}

#[test]
fn reused_buffers_give_bit_identical_factors() {
    let (a, h) = drawn_hessian(3, 20.0);
    let model = a.model();
    let n = model.dofs();
    let sym = a.symbolic();
    let pattern = model.pattern();
    // The drawn state's Hessian need not be definite: shift it by its 1-norm (Gershgorin).
    let s = pattern.sym_norm1(&h);

    let first = Cholesky::factorize(sym, pattern, &h, s, None).expect("positive definite");
    let reference = solve_bits(&first, n);
    drop(first);
    // A failed factorization (far below the smallest eigenvalue) hands its buffer back too.
    assert!(Cholesky::factorize(sym, pattern, &h, -10.0 * s, None).is_err());
    // Several factors alive at once, some on reused buffers, some on fresh ones.
    let alive: Vec<Cholesky> = (0..6)
        .map(|_| Cholesky::factorize(sym, pattern, &h, s, None).expect("positive definite"))
        .collect();
    for f in &alive {
        assert_eq!(solve_bits(f, n), reference);
    }
    drop(alive);
    // A differently shifted matrix in between must not leak into the next factor.
    let shifted = Cholesky::factorize(sym, pattern, &h, 2.0 * s, None).expect("positive definite");
    assert_ne!(solve_bits(&shifted, n), reference);
    drop(shifted);
    let again = Cholesky::factorize(sym, pattern, &h, s, None).expect("positive definite");
    assert_eq!(solve_bits(&again, n), reference);
}

#[test]
fn eigenpairs_on_the_principal_submatrix_match_the_whole_matrix() {
    let net = build(&random_curves(5, 4), 20.0, Supports::Clamped);
    let a = Analyzer::new(net, StabilityParams::default()).expect("analyzer");
    let model = a.model();
    let n = model.dofs();
    let mut u = vec![0.0; n];
    a.relax(&a.all(), &mut u);
    let curves = a.network().rods.len();
    let params = a.params().eigen.clone();
    // The ring and one arch: the other arches' own vertices are loose.
    let active = ActiveSet::from_curves(curves, &[0, 1]);
    let h = model.assemble(&u, &active, true).hess;
    let vertex_mask = model.vertex_mask(&active);
    let keep: Vec<bool> = vertex_mask.iter().flat_map(|&v| [v; 3]).collect();
    let kept = keep.iter().filter(|&&k| k).count();
    assert!(
        kept < n * 3 / 4,
        "the test needs the restricted path ({kept} of {n} kept)"
    );
    let spectrum = |keep: Option<&[bool]>| -> Spectrum {
        let options = EigenOptions {
            keep,
            ..Default::default()
        };
        smallest_eigenpairs(a.symbolic(), model.pattern(), &h, &params, options)
            .expect("solved")
            .expect("about zero")
            .spectrum
    };
    let whole = spectrum(None);
    let part = spectrum(Some(&keep));
    assert_eq!(part.vectors.nrows(), n);
    for (k, (w, p)) in whole.values.iter().zip(&part.values).enumerate() {
        let rel = (w - p).abs() / w.abs();
        assert!(rel < 1e-9, "λ{k}: whole {w:e}, principal {p:e}");
    }
    // Vectors vanish on loose coordinates and are eigenvectors of the whole matrix.
    let mut hv = vec![0.0; n];
    for j in 0..part.values.len() {
        let v: Vec<f64> = (0..n).map(|i| part.vectors[(i, j)]).collect();
        assert!(keep.iter().zip(&v).all(|(&k, &x)| k || x == 0.0));
        model.pattern().sym_matvec(&h, &v, &mut hv);
        let r: f64 = hv
            .iter()
            .zip(&v)
            .map(|(a, b)| (a - part.values[j] * b).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(r <= 1e-8 * part.norm1, "residual {r:e} of pair {j}");
    }
}

#[test]
fn restricted_analysis_factors_the_whole_matrix() {
    let net = build(&random_curves(7, 4), 20.0, Supports::Clamped);
    let a = Analyzer::new(net, StabilityParams::default()).expect("analyzer");
    let model = a.model();
    let n = model.dofs();
    let u = vec![0.0; n];
    let curves = a.network().rods.len();
    let active = ActiveSet::from_curves(curves, &[0, 2]);
    let restricted = a.symbolic_for(&active);
    assert!(
        restricted.kept_dofs() < n,
        "the structure leaves loose vertices ({} of {n} kept)",
        restricted.kept_dofs()
    );
    let h = model.assemble(&u, &active, true).hess;
    let s = model.pattern().sym_norm1(&h);
    let b: Vec<f64> = (0..n).map(|i| ((i * 31) % 17) as f64 - 8.0).collect();
    let residual = |f: &Cholesky, values: &[f64], shift: f64| {
        let mut x = b.clone();
        f.solve_vec(&mut x);
        let mut hx = vec![0.0; n];
        model.pattern().sym_matvec(values, &x, &mut hx);
        let r: f64 = hx
            .iter()
            .zip(&x)
            .zip(&b)
            .map(|((hx, x), b)| (hx + shift * x - b).powi(2))
            .sum::<f64>()
            .sqrt();
        r / b.iter().map(|v| v * v).sum::<f64>().sqrt()
    };
    // The structure's matrix (loose vertices decoupled): the restricted factor solves the
    // whole system as accurately as the full one.
    let fr = Cholesky::factorize(&restricted, model.pattern(), &h, s, None).expect("definite");
    let ff = Cholesky::factorize(a.symbolic(), model.pattern(), &h, s, None).expect("definite");
    let (rr, rf) = (residual(&fr, &h, s), residual(&ff, &h, s));
    assert!(
        rr < 1e-12 && rf < 1e-12,
        "residuals {rr:e} (restricted), {rf:e} (full)"
    );
    // A matrix coupling the left-out vertices (the whole network's) is factored exactly too:
    // the analysis falls back to the full pattern.
    let h_all = model.assemble(&u, &a.all(), true).hess;
    let s_all = model.pattern().sym_norm1(&h_all);
    let fc =
        Cholesky::factorize(&restricted, model.pattern(), &h_all, s_all, None).expect("definite");
    let rc = residual(&fc, &h_all, s_all);
    assert!(rc < 1e-12, "residual {rc:e} of a coupled matrix");
    // A non-positive diagonal on a left-out coordinate is reported, not hidden.
    assert!(Cholesky::factorize(&restricted, model.pattern(), &h, -10.0 * s, None).is_err());
}

#[test]
fn subtree_parallel_factor_matches_faer() {
    // Big enough for nested dissection, supernodes and a parallel schedule.
    let (a, h) = drawn_hessian(11, 0.5);
    let model = a.model();
    let n = model.dofs();
    assert!(n > 3000, "{n} unknowns");
    let sym = a.symbolic();
    assert!(
        sym.parallel_subtrees() >= 4,
        "{} subtrees",
        sym.parallel_subtrees()
    );
    let pattern = model.pattern();
    let s = pattern.sym_norm1(&h);
    let fast = Cholesky::factorize(sym, pattern, &h, s, None).expect("positive definite");
    // faer's own factorization, on an analysis of its own (the same ordering).
    let faer = SymbolicFactor::new(pattern, Backend::Faer);
    assert_eq!(faer.parallel_subtrees(), 0);
    assert_eq!(faer.factor_nnz(), sym.factor_nnz());
    let reference = Cholesky::factorize(&faer, pattern, &h, s, None).expect("positive definite");
    let (x, y) = (solve_fixed(&fast, n), solve_fixed(&reference, n));
    let err = x
        .iter()
        .zip(&y)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let scale = y.iter().map(|v| v.abs()).fold(0.0, f64::max);
    assert!(
        err <= 1e-12 * scale,
        "solutions differ by {err:e} (scale {scale:e})"
    );
    // Bit-identical in pools of one and two threads.
    let in_pool = |t: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .expect("pool")
            .install(|| {
                solve_bits(
                    &Cholesky::factorize(sym, pattern, &h, s, None).expect("pd"),
                    n,
                )
            })
    };
    assert_eq!(in_pool(1), in_pool(2));
    assert_eq!(in_pool(2), solve_bits(&fast, n));
    // Indefinite: both fail.
    assert!(Cholesky::factorize(sym, pattern, &h, -10.0 * s, None).is_err());
    assert!(Cholesky::factorize(&faer, pattern, &h, -10.0 * s, None).is_err());
}

/// Solves in groups (`Schedule::Groups`): with groups of one column, each
/// column is bit-identical to its own one-column solve; groups of four agree to round-off; the
/// values never depend on the thread count.
#[test]
fn grouped_solves_depend_on_the_grouping_only() {
    let (a, h) = drawn_hessian(3, 20.0);
    let model = a.model();
    let n = model.dofs();
    let pattern = model.pattern();
    let s = pattern.sym_norm1(&h);
    let f = Cholesky::factorize(a.symbolic(), pattern, &h, s, None).expect("positive definite");
    let rhs = faer::Mat::<f64>::from_fn(n, 6, |i, j| ((i * 7919 + j * 131) % 101) as f64 - 50.0);
    let solved = |group: usize, threads: usize| {
        let mut x = rhs.clone();
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| f.solve_in_place(x.as_mut(), Schedule::Groups(group)));
        x
    };
    let bits = |m: &faer::Mat<f64>| -> Vec<u64> {
        (0..m.ncols())
            .flat_map(|j| (0..m.nrows()).map(move |i| (i, j)))
            .map(|(i, j)| m[(i, j)].to_bits())
            .collect()
    };
    let single = solved(1, 2);
    for j in 0..rhs.ncols() {
        let mut col: Vec<f64> = (0..n).map(|i| rhs[(i, j)]).collect();
        f.solve_vec(&mut col);
        for (i, v) in col.iter().enumerate() {
            assert_eq!(v.to_bits(), single[(i, j)].to_bits(), "column {j}, row {i}");
        }
    }
    let grouped = solved(4, 2);
    let scale = (0..n).map(|i| single[(i, 0)].abs()).fold(0.0, f64::max);
    for j in 0..rhs.ncols() {
        for i in 0..n {
            let d = (grouped[(i, j)] - single[(i, j)]).abs();
            assert!(d <= 1e-10 * scale, "column {j}, row {i}: {d:e}");
        }
    }
    for group in [1, 4] {
        assert_eq!(
            bits(&solved(group, 1)),
            bits(&solved(group, 2)),
            "groups of {group}"
        );
    }
}

/// A factorization copying the supernodes a curve's removal cannot reach from a factorization
/// of the whole structure (`Cholesky::factorize` with a `Reuse`) is bit-identical to a whole
/// factorization, on the whole pattern's analysis and on a restricted one, in pools of one and
/// two threads; a reference of another shift is ignored.
#[test]
fn reusing_a_reference_factor_is_bit_identical() {
    let (a, _) = drawn_hessian(11, 0.5);
    let model = a.model();
    let n = model.dofs();
    let curves = a.network().rods.len();
    let u = vec![0.0; n];
    let locals = model.local_hessians(&u, Terms::All);
    // The whole structure, and one without curve 0 (its analysis restricted to its vertices).
    for active in [a.all(), a.all().without(0)] {
        let sym = a.symbolic_for(&active);
        let mut h = Vec::new();
        model.hessian_from_locals(&locals, &active, &mut h);
        let s = model.pattern().sym_norm1(&h);
        let reference = Cholesky::factorize(&sym, model.pattern(), &h, s, None).expect("pd");
        let mut shares = Vec::new();
        for c in active.curves() {
            let mut hc = Vec::new();
            model.hessian_from_locals(&locals, &active.without(c), &mut hc);
            let changed: Vec<usize> = model
                .curve_vertices(c)
                .iter()
                .flat_map(|&v| (0..3).map(move |k| 3 * v as usize + k))
                .collect();
            shares.push(sym.changed_work_share(&changed));
            let whole = solve_bits(
                &Cholesky::factorize(&sym, model.pattern(), &hc, s, None).expect("pd"),
                n,
            );
            for t in [1, 2] {
                let reused = rayon::ThreadPoolBuilder::new()
                    .num_threads(t)
                    .build()
                    .expect("pool")
                    .install(|| {
                        let reuse = Reuse {
                            reference: &reference,
                            changed: &changed,
                        };
                        Cholesky::factorize(&sym, model.pattern(), &hc, s, Some(reuse)).expect("pd")
                    });
                assert_eq!(solve_bits(&reused, n), whole, "curve {c}, {t} thread(s)");
            }
            // A reference of another shift is not used: still the same factor.
            let shifted =
                Cholesky::factorize(&sym, model.pattern(), &h, 2.0 * s, None).expect("pd");
            let reuse = Reuse {
                reference: &shifted,
                changed: &changed,
            };
            let other =
                Cholesky::factorize(&sym, model.pattern(), &hc, s, Some(reuse)).expect("pd");
            assert_eq!(solve_bits(&other, n), whole, "curve {c}, other shift");
        }
        // Some work is saved for every curve, none for no change.
        assert!(shares.iter().all(|&w| w < 1.0), "{shares:?} of {curves}");
        // One changed diagonal entry: its supernode and every ancestor change, nothing else.
        for d in [0, n / 3, n / 2, n - 1] {
            let mut h2 = h.clone();
            h2[model.pattern().diag[d]] += 0.5 * s;
            let whole = solve_bits(
                &Cholesky::factorize(&sym, model.pattern(), &h2, s, None).expect("pd"),
                n,
            );
            let reuse = Reuse {
                reference: &reference,
                changed: &[d],
            };
            let reused =
                Cholesky::factorize(&sym, model.pattern(), &h2, s, Some(reuse)).expect("pd");
            assert_eq!(solve_bits(&reused, n), whole, "coordinate {d}");
            assert!(sym.changed_work_share(&[d]) < 1.0);
        }
        assert_eq!(sym.changed_work_share(&[]), 0.0);
    }
}

/// The paper example `name`'s network (clamped supports), if the reference data is there.
fn paper_network(name: &str) -> Option<curvenet::network::Network> {
    let ex = curvenet::paper::load(name, &data_dir()?, Supports::Clamped).expect("loads");
    Some(
        curvenet::network::build_network(&ex.curves, &ex.build)
            .expect("builds")
            .0,
    )
}

/// Two relaxations of one structure end at the same equilibrium: energies within
/// `energy_rel`, displacements within 1e-6 of their scale.
fn assert_same_equilibrium(
    (a, ua): (&curvenet::solve::NewtonInfo, &[f64]),
    (b, ub): (&curvenet::solve::NewtonInfo, &[f64]),
    energy_rel: f64,
) {
    assert!(
        (a.energy - b.energy).abs() <= energy_rel * b.energy.abs(),
        "energies {} and {}",
        a.energy,
        b.energy
    );
    let scale = ub.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = ua
        .iter()
        .zip(ub)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(
        diff <= 1e-6 * scale,
        "displacements {diff:e} apart (scale {scale:e})"
    );
}

/// Steps escaping a saddle are doubled while the energy falls (`SolverTuning::
/// escape_doublings`): the kagome's first relaxation from its drawn state passes one, and
/// with the doublings it reaches the same equilibrium (energy and displacements) in fewer
/// factorizations.
#[test]
fn saddle_escapes_reach_the_same_equilibrium_sooner() {
    let Some(net) = paper_network("kagome") else {
        return;
    };
    let relax = |doublings: usize| {
        let mut params = StabilityParams::default();
        params.tuning.solver.escape_doublings = doublings;
        // Every step factored afresh: the doublings' saving alone.
        params.tuning.solver.chord_below = 0.0;
        let a = Analyzer::new(net.clone(), params).expect("analyzer");
        let mut u = vec![0.0; a.model().dofs()];
        let info = a.relax(&a.all(), &mut u);
        assert!(info.converged, "{info:?}");
        (info, u)
    };
    let (plain, u0) = relax(0);
    let (escaping, u1) = relax(StabilityParams::default().tuning.solver.escape_doublings);
    assert_eq!(plain.escape_doublings, 0);
    assert!(plain.projected_steps > 0, "a saddle on the way: {plain:?}");
    assert!(escaping.escape_doublings > 0, "{escaping:?}");
    assert!(
        escaping.factorizations < plain.factorizations,
        "{} against {}",
        escaping.factorizations,
        plain.factorizations
    );
    assert_same_equilibrium((&escaping, &u1), (&plain, &u0), 1e-10);
}

/// A relaxation from near an equilibrium (`Equilibrium::relax_near`, a warm edit's) stops at
/// the first saddle it meets instead of walking over it: from the kagome's drawn state, which
/// lies before one, it reports the stop and takes no step of the saddle escape, where
/// `relax` passes the saddle and converges.
#[test]
fn a_relaxation_near_an_equilibrium_stops_at_a_saddle() {
    let Some(net) = paper_network("kagome") else {
        return;
    };
    let a = Analyzer::new(net, StabilityParams::default()).expect("analyzer");
    let all = a.all();
    let eq = Equilibrium {
        model: a.model(),
        active: &all,
        symbolic: a.symbolic(),
        params: &a.params().newton,
        tuning: &a.params().tuning.solver,
    };
    let mut u = vec![0.0; a.model().dofs()];
    let near = eq.relax_near(&mut u).info;
    assert_eq!(near.stop, NewtonStop::Saddle, "{near:?}");
    assert!(!near.converged);
    assert_eq!(near.projected_steps, 0);
    let mut u = vec![0.0; a.model().dofs()];
    let cold = eq.relax(&mut u, None).info;
    assert!(cold.converged && cold.projected_steps > 0, "{cold:?}");
}

/// The substitutions of Krylov steps split across the cores
/// (`SolverTuning::split_solves_above`, for large factors) give the relaxation of one
/// sequential substitution each, bit for bit: the arched shell relaxed near its equilibrium
/// after the greedy's first removal, in pools of one and two threads.
#[test]
fn split_krylov_substitutions_give_the_same_relaxation() {
    let Some(net) = paper_network("arcshell") else {
        return;
    };
    let a = Analyzer::new(net.clone(), StabilityParams::default()).expect("analyzer");
    assert!(
        a.symbolic().parallel_solve_subtrees() > 1,
        "a parallel schedule"
    );
    let mut start = vec![0.0; a.model().dofs()];
    assert!(a.relax(&a.all(), &mut start).converged);
    let after = a.all().without(30);
    let relax_near = |split_solves_above: usize| {
        let mut params = StabilityParams::default();
        params.tuning.solver.split_solves_above = split_solves_above;
        let eq = Equilibrium {
            model: a.model(),
            active: &after,
            symbolic: a.symbolic(),
            params: &params.newton,
            tuning: &params.tuning.solver,
        };
        let mut u = start.clone();
        let info = eq.relax_near(&mut u).info;
        assert!(info.converged && info.krylov_steps > 0, "{info:?}");
        (info, u.iter().map(|v| v.to_bits()).collect::<Vec<u64>>())
    };
    let sequential = relax_near(usize::MAX);
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        let split = pool.install(|| relax_near(0));
        assert_eq!(split, sequential, "{threads} threads");
    }
}

/// In Newton's quadratic phase the last factorization serves the step
/// (`SolverTuning::chord_below`): the arched shell's relaxations (from its drawn state, then
/// after the greedy's first removal from that equilibrium) end at the same equilibrium
/// (energies to round-off, displacements to the round-off floor's reach) with fewer
/// factorizations.
#[test]
fn chord_steps_in_the_quadratic_phase_reach_the_same_equilibrium() {
    let Some(net) = paper_network("arcshell") else {
        return;
    };
    let relax = |chord_below: f64| {
        let mut params = StabilityParams::default();
        params.tuning.solver.chord_below = chord_below;
        let a = Analyzer::new(net.clone(), params).expect("analyzer");
        let mut u = vec![0.0; a.model().dofs()];
        let first = a.relax(&a.all(), &mut u);
        let mut u_after = u.clone();
        let after = a.relax(&a.all().without(30), &mut u_after);
        for info in [&first, &after] {
            assert!(info.converged, "{info:?}");
        }
        [(first, u), (after, u_after)]
    };
    let plain = relax(0.0);
    let chord = relax(StabilityParams::default().tuning.solver.chord_below);
    let mut chord_steps = 0;
    for ((p, up), (c, uc)) in plain.iter().zip(&chord) {
        assert_eq!(p.chord_steps, 0, "{p:?}");
        chord_steps += c.chord_steps;
        assert!(c.factorizations < p.factorizations, "{c:?} against {p:?}");
        assert_same_equilibrium((c, uc), (p, up), 1e-12);
    }
    assert!(chord_steps > 0, "no step used the last factorization");
}

/// The subtree-parallel substitution (`Schedule::Subtrees`, `solve::supernodal`) is
/// bit-identical to faer's sequential one (`Schedule::Groups` with one group), for
/// one, two and four columns, in pools of one and two threads, on a network big enough for a parallel schedule and on a small one (one
/// sequential task).
#[test]
fn subtree_parallel_solves_match_faer_bit_for_bit() {
    for (seed, h) in [(11, 0.5), (3, 20.0)] {
        let (a, hess) = drawn_hessian(seed, h);
        let model = a.model();
        let n = model.dofs();
        // The first network's substitutions run on a parallel schedule, the second's in one
        // sequential task.
        let tasks = a.symbolic().parallel_solve_subtrees();
        if seed == 11 {
            assert!(tasks >= 2, "{tasks} substitution subtrees");
        } else {
            assert_eq!(tasks, 1, "{n} unknowns");
        }
        let pattern = model.pattern();
        let s = pattern.sym_norm1(&hess);
        let f =
            Cholesky::factorize(a.symbolic(), pattern, &hess, s, None).expect("positive definite");
        let rhs =
            faer::Mat::<f64>::from_fn(n, 4, |i, j| ((i * 7919 + j * 131) % 101) as f64 - 50.0);
        let bits = |m: &faer::Mat<f64>| -> Vec<u64> {
            (0..m.ncols())
                .flat_map(|j| (0..m.nrows()).map(move |i| (i, j)))
                .map(|(i, j)| m[(i, j)].to_bits())
                .collect()
        };
        for k in [1, 2, 4] {
            let rhs = rhs.subcols(0, k).to_owned();
            let mut reference = rhs.clone();
            f.solve_in_place(reference.as_mut(), Schedule::Groups(k));
            for threads in [1, 2] {
                let mut x = rhs.clone();
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .expect("pool")
                    .install(|| f.solve_in_place(x.as_mut(), Schedule::Subtrees));
                assert_eq!(
                    bits(&x),
                    bits(&reference),
                    "seed {seed}, {k} columns, {threads} threads"
                );
            }
        }
        // `solve_vec` is the one-column case.
        let mut v: Vec<f64> = (0..n).map(|i| rhs[(i, 0)]).collect();
        f.solve_vec(&mut v);
        let mut reference = rhs.subcols(0, 1).to_owned();
        f.solve_in_place(reference.as_mut(), Schedule::Groups(1));
        let v_bits: Vec<u64> = v.iter().map(|x| x.to_bits()).collect();
        assert_eq!(v_bits, bits(&reference), "seed {seed}, solve_vec");
    }
}

/// Unloaded straight rods (a tilted grid of straight curves crossing at joints) are at rest in
/// their drawn state, where their gradient is pure round-off: Newton judges it against the
/// forces' natural scale and converges at once, instead of chasing a tolerance relative to
/// round-off (it stalled, and every such network reported "equilibrium not reached").
#[test]
fn unloaded_straight_rods_converge_at_once() {
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let (cz, sz) = (17f64.to_radians().cos(), 17f64.to_radians().sin());
    let at = |u: f64, v: f64| {
        let (x, y, z) = (u, v * c, v * s);
        Vec3::new(x * cz - y * sz, x * sz + y * cz, z)
    };
    let mut curves = Vec::new();
    for i in 0..5 {
        let t = 100.0 + 200.0 * i as f64;
        curves.push(polyline(vec![at(t, 0.0), at(t, 1000.0)], false));
        curves.push(polyline(vec![at(0.0, t), at(1000.0, t)], false));
    }
    for supports in [Supports::Clamped, Supports::Pinned] {
        let a = Analyzer::new(build(&curves, 50.0, supports), StabilityParams::default())
            .expect("analyzer");
        assert_eq!(a.network().joints.len(), 25);
        let mut u = vec![0.0; a.model().dofs()];
        let info = a.relax(&a.all(), &mut u);
        assert_eq!(info.stop, NewtonStop::Converged, "{supports:?}: {info:?}");
        assert!(info.converged && info.iterations == 0, "{info:?}");
        assert!(info.grad_rel < a.params().newton.rel_tol, "{info:?}");
        assert!(
            u.iter().all(|&x| x == 0.0),
            "the drawn state is the equilibrium"
        );
    }
}

/// Curved rods have a drawn gradient far above the forces' natural scale (random arches: about
/// 160 times), so their relaxations are judged against their drawn state, exactly as without
/// that scale.
#[test]
fn curved_rods_are_judged_against_their_drawn_gradient() {
    let a = Analyzer::new(
        build(&random_arches(7, 6), 40.0, Supports::Clamped),
        StabilityParams::default(),
    )
    .expect("analyzer");
    let (model, all) = (a.model(), a.all());
    let drawn = norm(&model.assemble(&vec![0.0; model.dofs()], &all, false).grad);
    let natural = model.natural_force_scale(&all);
    assert!(
        natural > 0.0 && natural < 0.1 * drawn,
        "{natural:e} against {drawn:e}"
    );
}
