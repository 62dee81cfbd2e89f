//! Local search after the greedy (`simplify::local`) on small random networks: whatever the
//! strategy, never worse than its start, every set feasible (keep list, budget, one curve at
//! least), every single move and every chain's last move an improvement, never above the
//! exhaustive optimum, improves a deliberately poor start, and does not depend on the thread
//! count (pools of one and two threads, bit for bit); the default search (descent, then
//! variable-depth chains, with part steps) reaches the exhaustive optimum from the greedy's set
//! on networks where single moves do not; the multi-start variant is at least the run from the
//! greedy's set.
//!
//! The ignored test `explore` measures the searches on `curvenet compare`'s random geodesic
//! networks (needs the reference data).

mod common;

use common::{build, random_arches};
use curvenet::cancel::Cancel;
use curvenet::network::Network;
use curvenet::rod::Supports;
use curvenet::simplify::exhaustive::{ExhaustiveParams, exhaustive};
use curvenet::simplify::greedy::NoHooks;
use curvenet::simplify::local::{
    LocalOutcome, LocalParams, Move, Strategy, local_search, local_search_multi,
};
use curvenet::simplify::{Budget, GreedyParams, greedy};
use curvenet::stability::{Analyzer, StabilityParams};

fn arches(seed: u64, n: usize, h: f64) -> Network {
    build(&random_arches(seed, n), h, Supports::Clamped)
}

/// An analyzer of `an`'s network with an empty cache of evaluated sets.
fn fresh(an: &Analyzer) -> Analyzer {
    Analyzer::new(an.network().clone(), an.params().clone()).expect("analyzer")
}

/// A search with an analyzer (and cache) of its own.
fn run(an: &Analyzer, params: &LocalParams, start: &[usize]) -> LocalOutcome {
    local_search(&fresh(an), params, start, &Cancel::never()).expect("local search")
}

/// The same search in a pool of `threads` threads.
fn run_in(threads: usize, an: &Analyzer, params: &LocalParams, start: &[usize]) -> LocalOutcome {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool")
        .install(|| run(an, params, start))
}

/// Replays the steps from the start: every set feasible, the moves legal, the values those of
/// the scorer, single moves improving, each round ending higher than the round before.
fn check_path(an: &Analyzer, params: &LocalParams, o: &LocalOutcome, cap: f64, keep: &[usize]) {
    let lengths = an.network().rest_lengths();
    let n = lengths.len();
    let sc = fresh(an);
    let mut set = o.start.curves.clone();
    let (mut round_start, mut prev) = (o.start.lambda, o.start.lambda);
    let mut round = usize::MAX;
    for (k, s) in o.steps.iter().enumerate() {
        if s.round != round {
            assert!(
                prev >= round_start,
                "round {round} ends lower than it started"
            );
            round_start = prev;
            round = s.round;
        }
        match s.step {
            Move::Add(c) => {
                assert!(!set.contains(&c));
                set.push(c);
            }
            Move::Drop(c) => {
                assert!(set.contains(&c) && !keep.contains(&c));
                set.retain(|&x| x != c);
            }
            Move::Swap { out, into } => {
                assert!(set.contains(&out) && !keep.contains(&out) && !set.contains(&into));
                set.retain(|&x| x != out);
                set.push(into);
            }
            Move::Part(c) => {
                assert!(params.parts, "a part step with parts off");
                let parts = sc.components(&curvenet::rod::ActiveSet::from_curves(n, &set));
                assert!(parts.len() > 1);
                let kept: Vec<usize> = parts
                    .into_iter()
                    .filter(|p| p.contains(&c) || p.iter().any(|x| keep.contains(x)))
                    .flatten()
                    .collect();
                set = kept;
            }
        }
        set.sort_unstable();
        assert!(!set.is_empty());
        assert!(
            set.iter().map(|&c| lengths[c]).sum::<f64>() <= cap,
            "over budget"
        );
        assert!(keep.iter().all(|c| set.contains(c)), "keep list lost");
        let v = sc
            .lambda_eq(&curvenet::rod::ActiveSet::from_curves(n, &set))
            .expect("λ_eq");
        assert_eq!(
            v.to_bits(),
            s.lambda.to_bits(),
            "step {k}: recorded λ_eq differs"
        );
        if params.strategy != Strategy::VariableDepth
            && !matches!(s.step, Move::Part(_))
            && !matches!(o.steps.get(k + 1), Some(next) if matches!(next.step, Move::Part(_)))
        {
            assert!(s.lambda > prev, "a single move that does not improve");
        }
        prev = s.lambda;
    }
    assert!(prev >= round_start);
    assert_eq!(set, o.best.curves);
    assert_eq!(prev.to_bits(), o.best.lambda.to_bits());
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
        let sc = fresh(&an);
        let ex = exhaustive(
            &sc,
            &ExhaustiveParams {
                keep: keep.clone(),
                ..ExhaustiveParams::new(budget)
            },
            &Cancel::never(),
        )
        .expect("exhaustive");
        let worst = ex
            .all
            .iter()
            .filter(|s| s.lambda.is_finite())
            .min_by(|a, b| a.lambda.total_cmp(&b.lambda))
            .expect("some")
            .clone();
        for (strategy, parts) in [
            (Strategy::FirstImprovement, false),
            (Strategy::FirstImprovement, true),
            (Strategy::VariableDepth, true),
            (Strategy::VariableDepth, false),
        ] {
            let params = LocalParams {
                keep: keep.clone(),
                strategy,
                parts,
                ..LocalParams::new(budget)
            };
            for from in [&start, &worst.curves] {
                let o = run_in(2, &an, &params, from);
                let b = &o.best;
                assert!(b.lambda >= o.start.lambda, "worse than its start");
                check_path(&an, &params, &o, cap, &keep);
                // Never above the optimum (same evaluation, cached or recomputed).
                assert!(b.lambda <= ex.best.lambda * (1.0 + 5e-8) + 1e-300);
                if from == &worst.curves && worst.lambda < ex.best.lambda * 0.5 {
                    assert!(!o.steps.is_empty(), "no move from the worst subset");
                }
                assert!(o.evaluations > 0 && o.structures > 0);
                assert_eq!(o.chains > 0, strategy == Strategy::VariableDepth);
                // Thread count does not matter, bit for bit.
                let one = run_in(1, &an, &params, from);
                assert_eq!(format!("{one:?}"), format!("{o:?}"));
            }
        }
        // Multi-start: at least the run from the greedy's set, never above the optimum,
        // and infeasible starts are skipped.
        let params = LocalParams {
            keep: keep.clone(),
            ..LocalParams::single_moves(budget)
        };
        let mut starts = vec![start.clone(), (0..n).collect()];
        starts.extend((0..n).map(|c| vec![c]));
        let m = local_search_multi(&sc, &params, &starts, &Cancel::never()).expect("multi");
        let from_greedy = run(&an, &params, &start);
        assert!(m.best.lambda >= from_greedy.best.lambda);
        assert!(m.best.lambda <= ex.best.lambda * (1.0 + 5e-8) + 1e-300);
        assert!(keep.iter().all(|k| m.best.curves.contains(k)));
    }
}

/// Networks where the greedy and single moves from its set stop short of the optimum and the
/// default search, from the greedy's set alone, reaches it (exhaustive search's answer).
#[test]
fn default_search_reaches_the_optimum() {
    for (seed, n, h) in [
        (40u64, 9usize, 70.0),
        (42, 10, 80.0),
        (54, 9, 70.0),
        (56, 10, 80.0),
    ] {
        let an = Analyzer::new(arches(seed, n, h), StabilityParams::default()).expect("an");
        let budget = Budget::Fraction(0.3);
        let g = greedy(&an, &GreedyParams::new(budget), None, &mut NoHooks).expect("greedy");
        let start = g.iterations.last().expect("one").curves.clone();
        let ex = exhaustive(
            &fresh(&an),
            &ExhaustiveParams::new(budget),
            &Cancel::never(),
        )
        .expect("ex");
        let opt = ex.best.lambda;
        let tie = |v: f64| v >= opt - 1e-7 * opt.abs();
        let single = run(&an, &LocalParams::single_moves(budget), &start);
        let o = run(&an, &LocalParams::new(budget), &start);
        println!(
            "seed {seed}: greedy {:.3}, single moves {:.3}, default {:.3} ({} subsets of {})",
            single.start.lambda / opt,
            single.best.lambda / opt,
            o.best.lambda / opt,
            o.evaluations,
            ex.all.len()
        );
        assert!(!tie(single.best.lambda), "single moves already optimal");
        assert!(
            tie(o.best.lambda),
            "seed {seed}: {:?} against {:?}",
            o.best,
            ex.best
        );
        assert!(o.evaluations < ex.all.len());
    }
}

/// Exploration on `curvenet compare`'s networks (needs the reference data): `N=10 I=10
/// cargo test --release -p curvenet --test local -- --ignored --nocapture explore`.
#[test]
#[ignore]
fn explore() {
    use curvenet::experiments::compare::{CompareParams, instance_network};
    let Some(data) = common::data_dir() else {
        return;
    };
    let surf = common::compare_surfaces(&data);
    let n = common::env_usize("N", 10);
    let budget = Budget::Fraction(0.3);
    for i in 0..common::env_usize("I", 10) {
        let (name, _, net) = instance_network(&surf, n, i, &CompareParams::default()).expect("net");
        let an = Analyzer::new(net, StabilityParams::default()).expect("an");
        let lengths = an.network().rest_lengths();
        let g = greedy(&an, &GreedyParams::new(budget), None, &mut NoHooks).expect("greedy");
        let start = g.iterations.last().expect("one").curves.clone();
        let sc = fresh(&an);
        let ex = exhaustive(&sc, &ExhaustiveParams::new(budget), &Cancel::never()).expect("ex");
        let mut singles: Vec<(usize, f64)> = (0..n)
            .filter_map(|c| {
                ex.all
                    .iter()
                    .find(|s| s.curves == [c])
                    .map(|s| (c, s.lambda / ex.best.lambda))
            })
            .collect();
        singles.sort_by(|a, b| b.1.total_cmp(&a.1));
        println!(
            "{name} i={i} lengths {:?} budget {:.0}\n  greedy {start:?} opt {:?} {:e}\n  singles {:?}",
            lengths.iter().map(|l| l.round()).collect::<Vec<_>>(),
            0.3 * lengths.iter().sum::<f64>(),
            ex.best.curves,
            ex.best.lambda,
            singles
                .iter()
                .map(|(c, r)| format!("{c}:{r:.3}"))
                .collect::<Vec<_>>()
        );
        use curvenet::simplify::local::Strategy;
        for (name, strategy, parts) in [
            ("single", Strategy::FirstImprovement, false),
            ("single+parts", Strategy::FirstImprovement, true),
            ("vd+parts", Strategy::VariableDepth, true),
        ] {
            let p = LocalParams {
                strategy,
                parts,
                ..LocalParams::new(budget)
            };
            let t = std::time::Instant::now();
            let o = local_search(&fresh(&an), &p, &start, &Cancel::never()).expect("ls");
            println!(
                "  {name:13} {:?} {:.3} evals {} structures {} {:.2}s",
                o.best.curves,
                o.best.lambda / ex.best.lambda,
                o.evaluations,
                o.structures,
                t.elapsed().as_secs_f64()
            );
        }
    }
}
