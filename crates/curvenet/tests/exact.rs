//! The exact solver for `λ_fix` (branch and bound over curves, `simplify::exact`) against
//! exhaustive search over `λ_fix` on small random networks, and the relaxation's certified
//! bound against the same optimum.
//!
//! Networks: random crossing arches over a paraboloid (8, 10 and 12 arches, ~150–400 vertices),
//! clamped, budget fractions 0.3 and 0.4, with and without a keep list.
//!
//! - the exact solver proves an optimum, and its `λ_fix` equals the exhaustive maximum of
//!   `λ_fix` (the same cached evaluation, so within the solver's relative tolerance 1e-7 and
//!   never above it); its bound is at least that maximum;
//! - the relaxation's certificate (`certificate::certify`) bounds the maximum from above;
//! - the search does not depend on the thread count (same answer, same node count).
//!
//! The ignored test `exact_scaling` measures the solver on `curvenet compare`'s random geodesic
//! networks (needs the reference data): `N=… cargo test --release --test exact -- --ignored
//! --nocapture`.

mod common;

use common::{build, random_arches};
use curvenet::cancel::Cancel;
use curvenet::network::Network;
use curvenet::rod::Supports;
use curvenet::simplify::Budget;
use curvenet::simplify::certificate::{CertifyParams, certificate, certify, tighten_certificate};
use curvenet::simplify::exact::{ExactOutcome, ExactParams};
use curvenet::simplify::exhaustive::{ExhaustiveOutcome, exhaustive_fixed as exhaustive_fixed_c};
use curvenet::stability::fixed::{FixedProblem, RelaxParams};
use curvenet::stability::{Analyzer, StabilityParams};

fn exact(
    p: &FixedProblem<'_>,
    params: &ExactParams,
    incumbents: &[Vec<usize>],
) -> Result<ExactOutcome, curvenet::simplify::SimplifyError> {
    curvenet::simplify::exact::exact(p, params, None, incumbents, &Cancel::never())
}

fn exhaustive_fixed(
    p: &FixedProblem<'_>,
    max: usize,
) -> Result<ExhaustiveOutcome, curvenet::simplify::SimplifyError> {
    exhaustive_fixed_c(p, max, &Cancel::never())
}

struct Case {
    network: Network,
    fraction: f64,
    keep: Vec<usize>,
}

fn arches(seed: u64, n: usize, h: f64) -> Network {
    let net = build(&random_arches(seed, n), h, Supports::Clamped);
    assert_eq!(net.rods.len(), n);
    net
}

fn cases() -> Vec<Case> {
    vec![
        Case {
            network: arches(21, 8, 70.0),
            fraction: 0.4,
            keep: vec![],
        },
        Case {
            network: arches(22, 10, 80.0),
            fraction: 0.3,
            keep: vec![],
        },
        Case {
            network: arches(23, 10, 80.0),
            fraction: 0.4,
            keep: vec![],
        },
        Case {
            network: arches(24, 12, 90.0),
            fraction: 0.3,
            keep: vec![],
        },
        Case {
            network: arches(25, 12, 90.0),
            fraction: 0.35,
            keep: vec![],
        },
        Case {
            network: arches(26, 11, 90.0),
            fraction: 0.4,
            keep: vec![3],
        },
    ]
}

#[test]
fn exact_matches_exhaustive_search_over_lambda_fix() {
    for (k, case) in cases().iter().enumerate() {
        let an = Analyzer::new(case.network.clone(), StabilityParams::default()).expect("an");
        let p = FixedProblem::new(&an, Budget::Fraction(case.fraction), &case.keep).expect("p");
        let params = ExactParams {
            time_limit: None,
            ..ExactParams::default()
        };
        let ex_outcome = exact(&p, &params, &[]).expect("exact");
        let ex = exhaustive_fixed(&p, 1_000_000).expect("exhaustive");
        let best = ex.best.lambda;
        println!(
            "case {k}: {} curves, {} vertices, {} feasible subsets; exhaustive {best:e} {:?}; \
             exact {:e} {:?} {:?}",
            p.curve_count(),
            case.network.vertex_count(),
            ex.all.len(),
            ex.best.curves,
            ex_outcome.lambda_fix,
            ex_outcome.curves,
            ex_outcome.info
        );
        assert!(ex_outcome.proven(), "case {k}: {:?}", ex_outcome.status);
        assert!(p.feasible(&ex_outcome.curves), "case {k}");
        for c in &case.keep {
            assert!(ex_outcome.curves.contains(c));
        }
        // The answer's value is one of the exhaustive values (same evaluation).
        let listed = ex
            .all
            .iter()
            .find(|s| s.curves == ex_outcome.curves)
            .expect("the answer is a feasible subset");
        assert_eq!(listed.lambda, ex_outcome.lambda_fix, "case {k}");
        assert!(ex_outcome.lambda_fix <= best, "case {k}");
        assert!(
            ex_outcome.lambda_fix >= best - params.tolerance * best.abs(),
            "case {k}: exact {:e} below the optimum {best:e}",
            ex_outcome.lambda_fix
        );
        assert!(ex_outcome.upper >= best, "case {k}");
        // Not a disguised exhaustive search: some subsets were never opened.
        assert!(ex_outcome.info.nodes <= ex.all.len() + 1, "case {k}");
        // The relaxation's certified bound (8 solves per face: the bound holds however far
        // the relaxation got).
        let light = CertifyParams {
            relax: RelaxParams {
                max_evals: 8,
                ..RelaxParams::default()
            },
        };
        let cert = certify(
            &p,
            &light,
            std::slice::from_ref(&ex_outcome.curves),
            &Cancel::never(),
        )
        .expect("certify");
        assert!(
            cert.upper >= best,
            "case {k}: certified bound {:e} below the optimum {best:e}",
            cert.upper
        );
        assert!(cert.lower <= best && cert.lower >= ex_outcome.lambda_fix);
        // λ_eq of the answer is a number.
        assert!(ex_outcome.lambda_eq(&an).expect("lambda_eq").is_finite());
    }
}

#[test]
fn exact_does_not_depend_on_the_thread_count() {
    let case = &cases()[3];
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| {
            let an = Analyzer::new(case.network.clone(), StabilityParams::default()).expect("an");
            let p = FixedProblem::new(&an, Budget::Fraction(case.fraction), &case.keep).expect("p");
            let params = ExactParams {
                time_limit: None,
                ..ExactParams::default()
            };
            let o = exact(&p, &params, &[]).expect("exact");
            (o.curves, o.lambda_fix, o.upper, o.info.nodes, o.info.cut)
        })
    };
    assert_eq!(run(1), run(3));
}

#[test]
fn limits_return_the_best_found_with_a_gap() {
    let case = &cases()[4];
    let an = Analyzer::new(case.network.clone(), StabilityParams::default()).expect("an");
    let p = FixedProblem::new(&an, Budget::Fraction(case.fraction), &case.keep).expect("p");
    let full = exact(
        &p,
        &ExactParams {
            time_limit: None,
            ..ExactParams::default()
        },
        &[],
    )
    .expect("exact");
    let o = exact(
        &p,
        &ExactParams {
            time_limit: None,
            max_nodes: 2,
            wave: 1,
            ..ExactParams::default()
        },
        &[],
    )
    .expect("limited");
    assert!(!o.proven());
    assert!(o.info.nodes <= 2);
    assert!(p.feasible(&o.curves));
    assert!(
        o.upper >= full.lambda_fix,
        "{} < {}",
        o.upper,
        full.lambda_fix
    );
    assert!(o.lambda_fix <= full.lambda_fix);
    assert!(o.gap >= 0.0);
}

/// Measures the solver on `curvenet compare`'s networks (N from the environment, default 14;
/// I instances, default 3). Prints times; asserts nothing about them.
/// A time limit no `Duration` can hold (or none a number can be) is refused, not a panic:
/// by the exact solver itself and by `compare`'s parameters.
#[test]
fn absurd_time_limits_are_refused() {
    use curvenet::experiments::compare::CompareParams;
    let an = Analyzer::new(arches(21, 8, 70.0), StabilityParams::default()).expect("an");
    let p = FixedProblem::new(&an, Budget::Fraction(0.4), &[]).expect("p");
    for bad in [1e30, -1.0, f64::NAN, f64::INFINITY] {
        let params = ExactParams {
            time_limit: Some(bad),
            ..ExactParams::default()
        };
        let e = exact(&p, &params, &[]).expect_err("refused").to_string();
        assert!(e.contains("time limit"), "{bad}: {e}");
        let compare = CompareParams {
            exact_time_limit: bad,
            ..CompareParams::default()
        };
        let e = compare.validate().expect_err("refused").to_string();
        assert!(e.contains("time limit"), "{bad}: {e}");
    }
}

#[test]
#[ignore]
fn exact_scaling() {
    use curvenet::experiments::compare::{CompareParams, instance_network};
    let Some(data) = common::data_dir() else {
        return;
    };
    let surf = common::compare_surfaces(&data);
    let n = common::env_usize("N", 14);
    let exhaustive = std::env::var("EX").is_ok();
    for i in 0..common::env_usize("I", 3) {
        let (name, seed, net) =
            instance_network(&surf, n, i, &CompareParams::default()).expect("net");
        let vertices = net.vertex_count();
        let an = Analyzer::new(net, StabilityParams::default()).expect("an");
        let t = std::time::Instant::now();
        let p = FixedProblem::new(&an, Budget::Fraction(0.3), &[]).expect("p");
        let setup = t.elapsed().as_secs_f64();
        let o = exact(&p, &ExactParams::default(), &[]).expect("exact");
        println!(
            "N={n} i={i} {name} seed {seed} {vertices} vertices: setup {setup:.2}s, {:?} \
             λ_fix {:e} {:?} upper {:e} {:?}",
            o.status, o.lambda_fix, o.curves, o.upper, o.info
        );
        if exhaustive {
            let t = std::time::Instant::now();
            let ex = exhaustive_fixed(&p, 10_000_000).expect("ex");
            println!(
                "   exhaustive {} subsets {:.2}s best {:e} {:?}",
                ex.all.len(),
                t.elapsed().as_secs_f64(),
                ex.best.lambda,
                ex.best.curves
            );
        }
    }
}

/// The certificate's bound on a paper example (EXAMPLE, default tower; EVALS relaxation
/// evaluations). Prints the faces; asserts only that the bound is above the greedy-free
/// lower value found.
#[test]
#[ignore]
fn certificate_on_a_paper_example() {
    let Some(data) = common::data_dir() else {
        return;
    };
    let name = std::env::var("EXAMPLE").unwrap_or_else(|_| "tower".into());
    let evals: usize = std::env::var("EVALS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(24);
    let ex = curvenet::paper::load(&name, &data, Supports::Clamped).expect("load");
    let (net, _) = curvenet::network::build_network(&ex.curves, &ex.build).expect("build");
    let an = Analyzer::new(net, StabilityParams::default()).expect("an");
    let t = std::time::Instant::now();
    let p = FixedProblem::new(
        &an,
        Budget::Fraction(ex.setup.budget_fraction),
        &ex.setup.keep,
    )
    .expect("p");
    println!("setup {:.2}s", t.elapsed().as_secs_f64());
    let t = std::time::Instant::now();
    let params = CertifyParams {
        relax: RelaxParams {
            max_evals: evals,
            ..RelaxParams::default()
        },
    };
    let r = certify(&p, &params, &[], &Cancel::never()).expect("certify");
    println!(
        "certify {:.2}s upper {:e} lower {:e} {:?} relax evals {} evaluations {}",
        t.elapsed().as_secs_f64(),
        r.upper,
        r.lower,
        r.lower_curves,
        r.relax_evals,
        r.evaluations
    );
    for f in &r.faces {
        println!("  {f:?}");
    }
    assert!(r.upper >= r.lower);
}

#[test]
fn a_certificate_tightened_by_branch_and_bound() {
    let case = &cases()[1];
    let an = Analyzer::new(case.network.clone(), StabilityParams::default()).expect("an");
    let p = FixedProblem::new(&an, Budget::Fraction(case.fraction), &case.keep).expect("p");
    let ex = exhaustive_fixed(&p, 1_000_000).expect("exhaustive");
    // Some feasible subset that is not the optimum: the worst one.
    let worst = ex
        .all
        .iter()
        .min_by(|a, b| a.lambda.total_cmp(&b.lambda))
        .expect("subsets")
        .curves
        .clone();
    let light = CertifyParams {
        relax: RelaxParams {
            max_evals: 8,
            ..RelaxParams::default()
        },
    };
    let never = Cancel::never();
    let mut c = certificate(&p, &worst, &light, &never).expect("certificate");
    assert_eq!(c.curves, worst);
    assert!(c.upper_bound >= ex.best.lambda && !c.proven_optimum);
    let loose = c.upper_bound;
    // A node budget too small to finish: a valid bound, not proven.
    let mut partial = c.clone();
    tighten_certificate(&p, &mut partial, None, 2, &never).expect("tighten");
    assert!(!partial.proven_optimum && partial.branch_and_bound_nodes <= 2);
    assert!(partial.upper_bound >= ex.best.lambda && partial.upper_bound <= loose);
    // Enough nodes: the optimum, proven.
    tighten_certificate(&p, &mut c, None, 100_000, &never).expect("tighten");
    assert!(c.proven_optimum);
    assert!(c.best_found >= ex.best.lambda * (1.0 - 1e-7) && c.best_found <= ex.best.lambda);
    assert!(c.upper_bound >= ex.best.lambda && c.upper_bound <= loose);
    if let Some(r) = c.ratio {
        assert_eq!(r, c.lambda_fix / c.upper_bound);
    }
}
