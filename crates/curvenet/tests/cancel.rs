//! Cancelling the long searches (`Cancel`): the local search, the certificate, the exact
//! search, exhaustive and random search stop soon after the token is set — within the
//! evaluations already under way, counted in work (structures relaxed, eigen solves), not in
//! seconds — and return what they had: the local search its best set so far, the
//! certificate a bound that is still certified (faces not relaxed keep their cheap bounds),
//! the exact search its best subset with the bound of the nodes left open, random search the
//! draws it evaluated; exhaustive search, whose part of the subsets is no optimum, an error.
//!
//! Each search runs on one thread while another sets the token once the search's work
//! counter reaches a mark; the work done after that is bounded by what was under way.

mod common;

use common::{build, random_arches};
use curvenet::cancel::Cancel;
use curvenet::rod::Supports;
use curvenet::simplify::certificate::{CertifyParams, certify};
use curvenet::simplify::exact::{ExactParams, ExactStatus, exact};
use curvenet::simplify::exhaustive::{ExhaustiveParams, exhaustive};
use curvenet::simplify::local::{LocalParams, local_search, local_search_multi};
use curvenet::simplify::random::{RandomParams, random_search};
use curvenet::simplify::{Budget, SimplifyError};
use curvenet::stability::fixed::FixedProblem;
use curvenet::stability::{Analyzer, StabilityParams};
use std::time::Duration;

fn analyzer(seed: u64, arches: usize) -> Analyzer {
    let net = build(&random_arches(seed, arches), 70.0, Supports::Clamped);
    Analyzer::new(net, StabilityParams::default()).expect("analyzer")
}

/// Runs `search` on this thread while another sets `cancel` once `work()` reaches `mark`;
/// returns the search's result and the work counted when the token was set (None when the
/// search ended first).
fn cancel_at<T: Send>(
    cancel: &Cancel,
    work: &(dyn Fn() -> usize + Sync),
    mark: usize,
    search: impl FnOnce() -> T + Send,
) -> (T, Option<usize>) {
    let done = std::sync::atomic::AtomicBool::new(false);
    std::thread::scope(|s| {
        let watcher = s.spawn(|| {
            while !done.load(std::sync::atomic::Ordering::Relaxed) {
                if work() >= mark {
                    cancel.cancel();
                    return Some(work());
                }
                std::thread::sleep(Duration::from_micros(200));
            }
            None
        });
        let out = search();
        done.store(true, std::sync::atomic::Ordering::Relaxed);
        (out, watcher.join().expect("watcher"))
    })
}

/// Work under way when the token is set: each thread finishes the evaluation it started (a
/// set of a few connected parts, or one eigen solve).
fn in_flight() -> usize {
    4 * rayon::current_num_threads().max(1)
}

#[test]
fn a_cancelled_local_search_returns_its_best_set_so_far() {
    let an = analyzer(5, 12);
    let budget = Budget::Fraction(0.3);
    let params = LocalParams::new(budget);
    // A poor start: the single longest-lasting feasible curve set is improved move by move.
    let lengths = an.lengths();
    let cap = budget.length(lengths.iter().sum());
    let start: Vec<usize> = (0..an.curve_count())
        .filter(|&c| lengths[c] <= cap)
        .take(1)
        .collect();
    // The search from the start alone: the default searches from it first.
    let full = local_search_multi(
        &an,
        &params,
        None,
        std::slice::from_ref(&start),
        &Cancel::never(),
    )
    .expect("runs");
    assert!(!full.cancelled);
    assert!(full.structures > 40, "long enough ({})", full.structures);

    let an = analyzer(5, 12);
    let cancel = Cancel::new();
    let work = || an.cached_structures();
    let (o, at) = cancel_at(&cancel, &work, 20, || {
        local_search(&an, &params, None, &start, &cancel)
    });
    let o = o.expect("a cancelled search still answers");
    let Some(at) = at else {
        panic!("the search ended before it was cancelled");
    };
    assert!(o.cancelled, "says it was cancelled");
    assert_eq!(
        o.start.curves, start,
        "cancelled during the search from the start given"
    );
    let after = an.cached_structures();
    assert!(
        after <= at + in_flight(),
        "{} structures relaxed after the cancel",
        after - at
    );
    // What it had: a feasible set at least as good as the start, on the path of the full run.
    assert!(o.best.length <= cap && !o.best.curves.is_empty());
    assert!(o.best.lambda >= o.start.lambda);
    assert!(o.best.lambda <= full.best.lambda);
    let prefix = &full.steps[..o.steps.len()];
    assert_eq!(
        o.steps, prefix,
        "the moves taken are the full run's first ones"
    );
}

#[test]
fn a_cancelled_certificate_keeps_a_certified_bound() {
    let an = analyzer(3, 10);
    let p = FixedProblem::new(&an, Budget::Fraction(0.3), &[]).expect("problem");
    let params = CertifyParams::default();
    let full = certify(&p, &params, &[], &Cancel::never()).expect("certifies");
    assert!(!full.cancelled);
    assert!(full.relax_evals > 30, "long enough ({})", full.relax_evals);

    let p = FixedProblem::new(&an, Budget::Fraction(0.3), &[]).expect("problem");
    let cancel = Cancel::new();
    let start = p.relax_solves();
    let work = || p.relax_solves() - start;
    let (r, at) = cancel_at(&cancel, &work, full.relax_evals / 3, || {
        certify(&p, &params, &[], &cancel)
    });
    let r = r.expect("a cancelled certificate still bounds");
    let Some(at) = at else {
        panic!("the certificate ended before it was cancelled");
    };
    assert!(r.cancelled);
    assert!(
        r.relax_evals <= at + in_flight(),
        "{} eigen solves after the cancel",
        r.relax_evals - at
    );
    // Still certified, looser (the faces not relaxed keep their cheap bounds), never below
    // the best subset found.
    assert!(r.upper >= full.upper, "{:e} < {:e}", r.upper, full.upper);
    assert!(r.upper >= full.lower && r.lower <= full.lower);
}

#[test]
fn a_cancelled_exact_search_returns_its_best_subset_and_an_open_bound() {
    let an = analyzer(4, 12);
    let p = FixedProblem::new(&an, Budget::Fraction(0.3), &[]).expect("problem");
    let params = ExactParams {
        time_limit: None,
        wave: 1,
        ..ExactParams::default()
    };
    let full = exact(&p, &params, None, &[], &Cancel::never()).expect("exact");
    assert!(full.proven());
    assert!(full.info.nodes > 20, "long enough ({})", full.info.nodes);

    let p = FixedProblem::new(&an, Budget::Fraction(0.3), &[]).expect("problem");
    let cancel = Cancel::new();
    let work = || p.eigen_solves() + p.relax_solves();
    let mark = work() + 10;
    let (o, at) = cancel_at(&cancel, &work, mark, || {
        exact(&p, &params, None, &[], &cancel)
    });
    let o = o.expect("answers");
    let Some(at) = at else {
        panic!("the search ended before it was cancelled");
    };
    assert_eq!(o.status, ExactStatus::Cancelled);
    assert!(work() <= at + in_flight(), "{} solves after", work() - at);
    assert!(o.lambda_fix <= full.lambda_fix && p.feasible(&o.curves));
    assert!(
        o.upper >= full.lambda_fix,
        "the open nodes still bound the optimum"
    );
}

#[test]
fn cancelled_exhaustive_and_random_searches() {
    let an = analyzer(6, 10);
    let budget = Budget::Fraction(0.3);
    let cancel = Cancel::new();
    let work = || an.cached_structures();
    let (ex, at) = cancel_at(&cancel, &work, 10, || {
        exhaustive(&an, &ExhaustiveParams::new(budget), None, &cancel)
    });
    if let Some(at) = at {
        assert!(matches!(ex, Err(SimplifyError::Cancelled)), "{ex:?}");
        assert!(an.cached_structures() <= at + in_flight());
    }
    // Random search with its draws cut short: the ones it evaluated, flagged.
    let an = analyzer(6, 10);
    let cancel = Cancel::new();
    let work = || an.cached_structures();
    let params = RandomParams {
        budget,
        keep: Vec::new(),
        evaluations: 200,
        seed: 1,
        time_limit: None,
    };
    let (r, at) = cancel_at(&cancel, &work, 10, || {
        random_search(&an, &params, None, &cancel)
    });
    if at.is_some() {
        let r = r.expect("answers");
        assert!(r.cancelled && r.evaluated.len() < 200);
    }
    // Cancelled before it starts: no answer.
    let never_started = Cancel::new();
    never_started.cancel();
    let an = analyzer(6, 10);
    assert!(matches!(
        random_search(&an, &params, None, &never_started),
        Err(SimplifyError::Cancelled)
    ));
    assert!(matches!(
        local_search(&an, &LocalParams::new(budget), None, &[0], &never_started),
        Err(SimplifyError::Cancelled) | Err(SimplifyError::Params(_))
    ));
}
