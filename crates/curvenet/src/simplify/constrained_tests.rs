//! Every search under design constraints against brute force on small networks: each returns
//! only sets that meet the constraints, the exhaustive search and the exact search find the
//! constrained optimum, and constraints that ask for nothing leave every search as it is
//! without constraints.

use super::certificate::{CertifyParams, certificate, tighten_certificate};
use super::exact::{ExactParams, exact};
use super::exhaustive::{ExhaustiveParams, exhaustive};
use super::local::{LocalParams, local_search_multi};
use super::random::{RandomParams, random_search};
use super::{Budget, GreedyParams, StopReason, greedy};
use crate::cancel::Cancel;
use crate::constraints::testing::{grid, network, pavilion, square_mesh};
use crate::constraints::{ConstraintParams, Constraints, SymmetryOption, parse_groups};
use crate::io::TriMesh;
use crate::network::Network;
use crate::simplify::greedy::NoHooks;
use crate::stability::fixed::FixedProblem;
use crate::stability::{Analyzer, StabilityParams};

/// A small network, its constraints and the budget fraction they were bound to.
struct Case {
    name: &'static str,
    analyzer: Analyzer,
    constraints: Constraints,
    fraction: f64,
    keep: Vec<usize>,
}

fn case(
    name: &'static str,
    net: Network,
    mesh: Option<&TriMesh>,
    params: ConstraintParams,
    fraction: f64,
    keep: &[usize],
) -> Case {
    let total: f64 = net.rest_lengths().iter().sum();
    let constraints =
        Constraints::new(&net, mesh, &params, fraction * total, keep).expect("feasible");
    assert!(
        constraints.is_active(),
        "{name}: constraints ask for something"
    );
    let analyzer = Analyzer::new(net, StabilityParams::default()).expect("analyzer");
    Case {
        name,
        analyzer,
        constraints,
        fraction,
        keep: keep.to_vec(),
    }
}

/// Pavilions (ring, three arches, three short arches) under a rotation, a mirror (a vertical
/// plane through an arch: orbits of one and two curves), groups, connectivity with a number of
/// curves; a grid of lines over a square under a largest gap.
fn cases() -> Vec<Case> {
    let pav = || network(&pavilion(3, true, 0.0));
    let mesh = square_mesh(500.0, 0.0, 8);
    vec![
        case(
            "rotate:3",
            pav(),
            None,
            ConstraintParams {
                symmetry: SymmetryOption::Rotate(3),
                ..Default::default()
            },
            0.55,
            &[],
        ),
        case(
            "mirror",
            pav(),
            None,
            ConstraintParams {
                symmetry: SymmetryOption::Mirror,
                ..Default::default()
            },
            0.5,
            &[],
        ),
        case(
            "groups",
            pav(),
            None,
            ConstraintParams {
                groups: parse_groups("a: 1 4\nb: 2 5\n", "g.txt").expect("parses"),
                ..Default::default()
            },
            0.4,
            &[],
        ),
        case(
            "connected, min-curves 2",
            pav(),
            None,
            ConstraintParams {
                connected: true,
                min_curves: Some(2),
                ..Default::default()
            },
            0.35,
            &[],
        ),
        case(
            "max-gap",
            network(&grid(500.0, 3)),
            Some(&mesh),
            ConstraintParams {
                max_gap: Some(420.0),
                ..Default::default()
            },
            0.7,
            &[],
        ),
    ]
}

/// Every non-empty subset of `n` curves that meets the constraints (budget and keep list
/// included).
fn feasible(c: &Constraints) -> Vec<Vec<usize>> {
    let n = c.curve_count();
    let mut out: Vec<Vec<usize>> = (1u32..(1 << n))
        .map(|m| (0..n).filter(|i| m & (1 << i) != 0).collect::<Vec<_>>())
        .filter(|s| c.check(s).is_ok())
        .collect();
    out.sort();
    out
}

fn sorted(mut v: Vec<Vec<usize>>) -> Vec<Vec<usize>> {
    v.sort();
    v
}

#[test]
fn exhaustive_search_finds_the_constrained_optimum() {
    for k in cases() {
        let brute = feasible(&k.constraints);
        assert!(!brute.is_empty(), "{}", k.name);
        let mut params = ExhaustiveParams::new(Budget::Fraction(k.fraction));
        params.keep = k.keep.clone();
        let o =
            exhaustive(&k.analyzer, &params, Some(&k.constraints), &Cancel::new()).expect("runs");
        let sets: Vec<Vec<usize>> = o.all.iter().map(|s| s.curves.clone()).collect();
        assert_eq!(sorted(sets), brute, "{}: exactly the feasible sets", k.name);
        // The optimum over the feasible sets, evaluated one by one.
        let best = brute
            .iter()
            .map(|s| k.analyzer.lambda_eq(&k.analyzer.set(s)).expect("evaluates"))
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(
            (o.best.lambda - best).abs() <= 1e-7 * best.abs(),
            "{}: {} vs {best}",
            k.name,
            o.best.lambda
        );
        assert!(k.constraints.check(&o.best.curves).is_ok());
    }
}

#[test]
fn the_greedy_removes_whole_units_and_keeps_the_constraints() {
    for k in cases() {
        let mut params = GreedyParams::new(Budget::Fraction(k.fraction));
        params.keep = k.keep.clone();
        let g = greedy(
            &k.analyzer,
            &params,
            Some(&k.constraints),
            None,
            &mut NoHooks,
        )
        .expect("runs");
        let c = &k.constraints;
        assert!(g.iterations.len() >= 2, "{}: nothing removed", k.name);
        for (i, w) in g.iterations.windows(2).enumerate() {
            let removed: Vec<usize> = w[0]
                .curves
                .iter()
                .copied()
                .filter(|x| !w[1].curves.contains(x))
                .collect();
            let unit = &c.units()[c.unit_of(removed[0])];
            assert_eq!(
                &removed, unit,
                "{}: iteration {i} removes a whole unit",
                k.name
            );
            assert_eq!(w[0].removed, Some(unit[0]));
            if unit.len() > 1 {
                assert_eq!(&w[0].removed_group, unit);
            }
            // The removal was the best-scored of the removable units.
            let units = c.removal_candidates(&w[0].curves);
            let named: Vec<usize> = units.iter().map(|&u| c.units()[u][0]).collect();
            let scored: Vec<usize> = w[0].candidates.iter().map(|s| s.curve).collect();
            assert_eq!(scored, named, "{}: iteration {i}'s candidates", k.name);
        }
        let last = g.iterations.last().expect("an iteration");
        match g.stop {
            StopReason::BudgetMet => {
                assert!(c.check(&last.curves).is_ok(), "{}: the final set", k.name)
            }
            StopReason::Blocked => {
                assert!(c.removal_candidates(&last.curves).is_empty(), "{}", k.name)
            }
            s => panic!("{}: unexpected stop {s:?}", k.name),
        }
    }
}

#[test]
fn random_and_local_searches_return_only_feasible_sets() {
    for k in cases() {
        let c = &k.constraints;
        let best = feasible(c)
            .iter()
            .map(|s| k.analyzer.lambda_eq(&k.analyzer.set(s)).expect("evaluates"))
            .fold(f64::NEG_INFINITY, f64::max);
        let params = RandomParams {
            budget: Budget::Fraction(k.fraction),
            keep: k.keep.clone(),
            evaluations: 12,
            seed: 7,
            time_limit: None,
        };
        let r = random_search(&k.analyzer, &params, Some(c), &Cancel::new()).expect("runs");
        assert!(
            r.evaluated.iter().all(|s| c.check(&s.curves).is_ok()),
            "{}",
            k.name
        );
        assert!(r.best.lambda <= best * (1.0 + 1e-7));
        // The local search from every feasible unit alone and from the random search's best.
        let mut starts: Vec<Vec<usize>> = c.units().to_vec();
        starts.push(r.best.curves.clone());
        let mut lp = LocalParams::new(Budget::Fraction(k.fraction));
        lp.keep = k.keep.clone();
        let o =
            local_search_multi(&k.analyzer, &lp, Some(c), &starts, &Cancel::new()).expect("runs");
        assert!(
            c.check(&o.best.curves).is_ok(),
            "{}: {:?}",
            k.name,
            o.best.curves
        );
        assert!(o.best.lambda >= r.best.lambda * (1.0 - 1e-7) || r.best.lambda <= 0.0);
        assert!(o.best.lambda <= best * (1.0 + 1e-7), "{}", k.name);
    }
}

#[test]
fn the_exact_search_finds_the_constrained_optimum_of_the_fixed_objective() {
    for k in cases() {
        let c = &k.constraints;
        let problem =
            FixedProblem::new(&k.analyzer, Budget::Fraction(k.fraction), &k.keep).expect("problem");
        let brute = feasible(c)
            .iter()
            .map(|s| problem.lambda_fix(s).expect("evaluates"))
            .fold(f64::NEG_INFINITY, f64::max);
        let params = ExactParams {
            time_limit: None,
            ..ExactParams::default()
        };
        let o = exact(&problem, &params, Some(c), &[], &Cancel::new()).expect("runs");
        assert!(c.check(&o.curves).is_ok(), "{}: {:?}", k.name, o.curves);
        assert!(
            (o.lambda_fix - brute).abs() <= 1e-6 * brute.abs(),
            "{}: {} vs {brute}",
            k.name,
            o.lambda_fix
        );
    }
}

/// The certificate tightened under the constraints: its bound covers the constrained optimum
/// of `λ_fix`, its best subset meets the constraints, and with enough nodes it is that optimum.
#[test]
fn the_certificate_honours_the_constraints() {
    for k in cases() {
        let c = &k.constraints;
        let problem =
            FixedProblem::new(&k.analyzer, Budget::Fraction(k.fraction), &k.keep).expect("problem");
        let sets = feasible(c);
        let brute = sets
            .iter()
            .map(|s| problem.lambda_fix(s).expect("evaluates"))
            .fold(f64::NEG_INFINITY, f64::max);
        let never = Cancel::new();
        let mut cert =
            certificate(&problem, &sets[0], &CertifyParams::default(), &never).expect("runs");
        tighten_certificate(&problem, &mut cert, Some(c), 100_000, &never).expect("tightens");
        assert!(cert.constrained, "{}", k.name);
        assert!(
            cert.describe().contains("the design constraints"),
            "{}",
            k.name
        );
        assert!(c.check(&cert.best_found_curves).is_ok(), "{}", k.name);
        assert!(cert.upper_bound >= brute * (1.0 - 1e-9), "{}", k.name);
        assert!(cert.proven_optimum, "{}", k.name);
        assert!(
            (cert.best_found - brute).abs() <= 1e-6 * brute.abs(),
            "{}: {} vs {brute}",
            k.name,
            cert.best_found
        );
    }
}

/// Constraints that ask for nothing leave every search as it is.
#[test]
fn empty_constraints_leave_every_search_as_it_is() {
    let net = network(&pavilion(3, false, 0.0));
    let total: f64 = net.rest_lengths().iter().sum();
    let none = Constraints::none(&net, 0.5 * total, &[]);
    let an = Analyzer::new(net, StabilityParams::default()).expect("analyzer");
    let budget = Budget::Fraction(0.5);
    let gp = GreedyParams::new(budget);
    let a = greedy(&an, &gp, None, None, &mut NoHooks).expect("runs");
    let b = greedy(&an, &gp, Some(&none), None, &mut NoHooks).expect("runs");
    assert_eq!(a.iterations, b.iterations);
    let ep = ExhaustiveParams::new(budget);
    let cancel = Cancel::new();
    let a = exhaustive(&an, &ep, None, &cancel).expect("runs");
    let b = exhaustive(&an, &ep, Some(&none), &cancel).expect("runs");
    assert_eq!(a.all, b.all);
    let rp = RandomParams {
        budget,
        keep: Vec::new(),
        evaluations: 5,
        seed: 3,
        time_limit: None,
    };
    let a = random_search(&an, &rp, None, &cancel).expect("runs");
    let b = random_search(&an, &rp, Some(&none), &cancel).expect("runs");
    assert_eq!(a.evaluated, b.evaluated);
    let lp = LocalParams::new(budget);
    let starts = vec![vec![0], vec![1], vec![2]];
    let a = local_search_multi(&an, &lp, None, &starts, &cancel).expect("runs");
    let b = local_search_multi(&an, &lp, Some(&none), &starts, &cancel).expect("runs");
    assert_eq!(a, b);
    let problem = FixedProblem::new(&an, budget, &[]).expect("problem");
    let ex = ExactParams::default();
    let a = exact(&problem, &ex, None, &[], &cancel).expect("runs");
    let b = exact(&problem, &ex, Some(&none), &[], &cancel).expect("runs");
    assert_eq!((a.curves, a.lambda_fix), (b.curves, b.lambda_fix));
    // Constraints bound to another budget are refused.
    let other = Constraints::none(an.network(), 0.4 * total, &[]);
    assert!(greedy(&an, &gp, Some(&other), None, &mut NoHooks).is_err());
}

/// The local search's default starts under constraints (and a keep list): the greedy's set
/// when it is feasible, then the best single units (with the units holding the keep list)
/// that meet every constraint, ranked by `λ_eq` as brute force ranks them; every start and
/// the answer feasible; never below the search from the greedy's set alone; an infeasible
/// start given is skipped, not an error.
#[test]
fn the_local_searchs_single_unit_starts_meet_the_constraints() {
    use super::local::{GROWN_EVALUATED, SINGLE_STARTS, local_search};
    let mut all = cases();
    all.push(case(
        "groups, keep 0",
        network(&pavilion(3, true, 0.0)),
        None,
        ConstraintParams {
            groups: parse_groups("a: 1 4\nb: 2 5\n", "g.txt").expect("parses"),
            ..Default::default()
        },
        0.6,
        &[0],
    ));
    let never = Cancel::new();
    let mut with_singles = Vec::new();
    for k in all {
        let c = &k.constraints;
        let budget = Budget::Fraction(k.fraction);
        let mut gp = GreedyParams::new(budget);
        gp.keep = k.keep.clone();
        let g = greedy(&k.analyzer, &gp, Some(c), None, &mut NoHooks).expect("greedy");
        let start = g.iterations.last().expect("one").curves.clone();
        let mut lp = LocalParams::new(budget);
        lp.keep = k.keep.clone();
        // The single-unit starts, by brute force: each unit not holding the keep list, with
        // the units that do, when the set meets the constraints; the best by λ_eq.
        let forced = c.forced_curves();
        let mut singles: Vec<(Vec<usize>, f64)> = (0..c.units().len())
            .filter(|&u| !c.is_forced(u))
            .map(|u| {
                let mut s = forced.clone();
                s.extend_from_slice(&c.units()[u]);
                s.sort_unstable();
                s
            })
            .filter(|s| c.check(s).is_ok())
            .map(|s| {
                let l = k.analyzer.lambda_eq(&k.analyzer.set(&s)).expect("λ");
                (s, l)
            })
            .collect();
        singles.sort_by(|a, b| b.1.total_cmp(&a.1));
        // Under --min-curves or --max-gap, then the grown starts, by brute force: from each
        // unit as a seed (shortest first) the set grown to meet the constraints, the first
        // GROWN_EVALUATED distinct ones, the best SINGLE_STARTS by λ_eq.
        let mut grown_expected: Vec<Vec<usize>> = Vec::new();
        if c.needs_grown_starts() {
            let mut seeds: Vec<usize> = (0..c.units().len()).collect();
            seeds.sort_by(|&a, &b| c.length(&c.units()[a]).total_cmp(&c.length(&c.units()[b])));
            let mut grown: Vec<Vec<usize>> = Vec::new();
            for u in seeds {
                if let Some(s) = c.grow(u)
                    && c.check(&s).is_ok()
                    && !grown.contains(&s)
                    && grown.len() < GROWN_EVALUATED
                {
                    grown.push(s);
                }
            }
            let mut ranked: Vec<(Vec<usize>, f64)> = grown
                .into_iter()
                .map(|s| {
                    let l = k.analyzer.lambda_eq(&k.analyzer.set(&s)).expect("λ");
                    (s, l)
                })
                .collect();
            ranked.sort_by(|a, b| b.1.total_cmp(&a.1));
            grown_expected.extend(ranked.into_iter().take(SINGLE_STARTS).map(|(s, _)| s));
        }
        let any_single = !singles.is_empty();
        let any_start = any_single || !grown_expected.is_empty();
        let name = k.name;
        let o = match local_search(&k.analyzer, &lp, Some(c), &start, &never) {
            Ok(o) => o,
            Err(e) => {
                // Nothing to start from: the greedy ended over the budget, no unit fits.
                assert!(c.check(&start).is_err() && !any_start, "{name}: {e}");
                continue;
            }
        };
        assert!(c.check(&o.best.curves).is_ok(), "{name}: {:?}", o.best);
        assert!(
            o.starts.iter().all(|s| c.check(&s.curves).is_ok()),
            "{name}"
        );
        assert_eq!(o.given_searched, c.check(&start).is_ok(), "{name}");
        let mut expected: Vec<Vec<usize>> =
            o.given().map(|g| g.curves.clone()).into_iter().collect();
        for (s, _) in singles.into_iter().take(SINGLE_STARTS) {
            if !expected.contains(&s) {
                expected.push(s);
            }
        }
        for s in grown_expected.iter().cloned() {
            if !expected.contains(&s) {
                expected.push(s);
            }
        }
        let got: Vec<Vec<usize>> = o.starts.iter().map(|s| s.curves.clone()).collect();
        assert_eq!(got, expected, "{name}: the starts");
        if got.len() > usize::from(o.given_searched) {
            with_singles.push(name);
        }
        if o.given_searched {
            let alone = local_search_multi(
                &k.analyzer,
                &lp,
                Some(c),
                std::slice::from_ref(&start),
                &never,
            )
            .expect("runs");
            assert!(o.best.lambda >= alone.best.lambda, "{name}");
        }
        // Every curve at once is over the budget: skipped, the single units still searched
        // (an error when there is none).
        let everything: Vec<usize> = (0..c.curve_count()).collect();
        match local_search(&k.analyzer, &lp, Some(c), &everything, &never) {
            Ok(o) => assert!(
                any_start && !o.given_searched && c.check(&o.best.curves).is_ok(),
                "{name}"
            ),
            Err(e) => assert!(!any_start, "{name}: {e}"),
        }
    }
    println!("single-unit starts searched on: {with_singles:?}");
    assert!(with_singles.len() >= 3, "{with_singles:?}");
}

/// The mirror case is one: orbits of two curves (arches the plane swaps) beside curves the
/// plane maps onto themselves, so its searches move pairs and single curves.
#[test]
fn the_mirror_case_pairs_curves() {
    let k = cases()
        .into_iter()
        .find(|k| k.name == "mirror")
        .expect("the mirror case");
    let found = k.constraints.symmetry().expect("a mirror plane");
    assert_eq!(found.option(), SymmetryOption::Mirror);
    assert!(found.orbits.iter().any(|o| o.len() == 2), "{found:?}");
    assert!(found.orbits.iter().any(|o| o.len() == 1), "{found:?}");
}
