//! Local search after the greedy (`simplify::local`) on small random networks: never worse
//! than its start, feasible, respects the keep list, every move strictly improves `λ_eq`,
//! bounded by the exhaustive optimum, improves a deliberately poor start, and does not depend
//! on the thread count; the multi-start variant is at least the run from the greedy's set.

mod common;

use common::{build, random_arches};
use curvenet::network::Network;
use curvenet::rod::Supports;
use curvenet::simplify::exhaustive::{ExhaustiveParams, exhaustive};
use curvenet::simplify::greedy::NoHooks;
use curvenet::simplify::local::{LocalParams, local_search, local_search_multi};
use curvenet::simplify::{Budget, GreedyParams, Scorer, greedy};
use curvenet::stability::{Analyzer, StabilityParams};

fn arches(seed: u64, n: usize, h: f64) -> Network {
    build(&random_arches(seed, n), h, Supports::Clamped)
}

fn run(
    an: &Analyzer,
    params: &LocalParams,
    start: &[usize],
) -> curvenet::simplify::local::LocalOutcome {
    let sc = Scorer::new(an);
    local_search(&sc, params, start).expect("local search")
}

#[test]
fn local_search_improves_feasibly_and_deterministically() {
    for (seed, n, h, fraction, keep) in [
        (31u64, 9usize, 70.0, 0.3, vec![]),
        (32, 10, 80.0, 0.35, vec![]),
        (33, 9, 70.0, 0.4, vec![2usize]),
    ] {
        let net = arches(seed, n, h);
        let an = Analyzer::new(net, StabilityParams::default()).expect("an");
        let budget = Budget::Fraction(fraction);
        let lengths = an.network().rest_lengths();
        let cap = budget.length(lengths.iter().sum());
        let g = greedy(
            &an,
            &GreedyParams {
                keep: keep.clone(),
                ..GreedyParams::new(budget)
            },
            None,
            &mut NoHooks,
        )
        .expect("greedy");
        let start = g.iterations.last().expect("one").curves.clone();
        let sc = Scorer::new(&an);
        let ex = exhaustive(
            &sc,
            &ExhaustiveParams {
                keep: keep.clone(),
                ..ExhaustiveParams::new(budget)
            },
        )
        .expect("exhaustive");
        let worst = ex
            .all
            .iter()
            .filter(|s| s.lambda.is_finite())
            .min_by(|a, b| a.lambda.total_cmp(&b.lambda))
            .expect("some")
            .clone();
        for best_improvement in [false, true] {
            let params = LocalParams {
                keep: keep.clone(),
                best_improvement,
                ..LocalParams::new(budget)
            };
            for from in [&start, &worst.curves] {
                let o = run(&an, &params, from);
                let b = &o.best;
                assert!(b.lambda >= o.start.lambda, "worse than its start");
                assert!(!b.curves.is_empty());
                assert!(b.curves.iter().map(|&c| lengths[c]).sum::<f64>() <= cap);
                assert!(keep.iter().all(|k| b.curves.contains(k)));
                let mut prev = o.start.lambda;
                for s in &o.steps {
                    assert!(s.lambda > prev, "a move that does not improve");
                    prev = s.lambda;
                }
                assert_eq!(prev, b.lambda);
                // Never above the optimum (same evaluation, cached or recomputed).
                assert!(b.lambda <= ex.best.lambda * (1.0 + 5e-8) + 1e-300);
                if from == &worst.curves && worst.lambda < ex.best.lambda * 0.5 {
                    assert!(!o.steps.is_empty(), "no move from the worst subset");
                }
                // Thread count does not matter.
                let one = rayon::ThreadPoolBuilder::new()
                    .num_threads(1)
                    .build()
                    .expect("pool")
                    .install(|| run(&an, &params, from));
                assert_eq!(one, o);
            }
            // Multi-start: at least the run from the greedy's set, never above the optimum,
            // and infeasible starts are skipped.
            let mut starts = vec![start.clone(), (0..n).collect()];
            starts.extend((0..n).map(|c| vec![c]));
            let sc = Scorer::new(&an);
            let m = local_search_multi(&sc, &params, &starts).expect("multi");
            let from_greedy = run(&an, &params, &start);
            assert!(m.best.lambda >= from_greedy.best.lambda);
            assert!(m.best.lambda <= ex.best.lambda * (1.0 + 5e-8) + 1e-300);
            assert!(keep.iter().all(|k| m.best.curves.contains(k)));
        }
    }
}
