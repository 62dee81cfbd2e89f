//! Warm edits: each edit relaxed from a nearby equilibrium gives the `λ` of
//! `curvenet analyze --remove` of its set, and a set analysed before comes from the cache.

mod common;

use common::{analyze_lambda, assert_close, curves_of, dome, ok, random_set, serve};
use curvenet::network::build_network;
use curvenet::rng::SplitMix64;
use curvenet::rod::Supports;
use curvenet::stability::{Analyzer, StabilityParams};
use curvenet_serve::Design;

/// Removing two curves of the tower and restoring them, one toggle at a time: each state's
/// `λ` is `analyze --remove`'s of its set, the edits relax from the current equilibrium, and
/// the last restore, back to a set analysed before, comes from the cache.
#[test]
fn warm_toggles_of_the_tower_give_the_lambda_of_analyze_and_restores_come_from_the_cache() {
    let ex = curvenet::paper::load_embedded("tower", Supports::default()).unwrap();
    let addr = serve(&ex.curves, &ex.build);
    let n = ex.curves.len();
    let mut rng = SplitMix64::new(3);
    let a = rng.below(n as u64) as usize;
    let b = (a + 1 + rng.below(n as u64 - 1) as usize) % n;
    let all: Vec<usize> = (0..n).collect();
    let without = |gone: &[usize]| -> Vec<usize> {
        all.iter().copied().filter(|c| !gone.contains(c)).collect()
    };
    let steps = [
        (a, without(&[a])),
        (b, without(&[a, b])),
        (a, without(&[b])),
        (b, all.clone()),
    ];
    let mut froms = Vec::new();
    for (curve, expected) in &steps {
        let t = ok(
            addr,
            "POST",
            "/api/toggle",
            &format!("{{\"curve\":{curve}}}"),
        );
        assert_eq!(&curves_of(&t), expected);
        assert_close(&t, analyze_lambda(&ex.curves, &ex.build, expected));
        froms.push(t["from"].as_str().unwrap().to_string());
    }
    assert_eq!(froms[3], "cache", "{froms:?}");
    assert!(froms[..3].iter().all(|f| f != "cache"), "{froms:?}");
    assert!(froms[..3].iter().any(|f| f == "warm"), "{froms:?}");
    // Removing `a` again: the set of the first step, from the cache.
    let again = ok(addr, "POST", "/api/toggle", &format!("{{\"curve\":{a}}}"));
    assert_eq!(again["from"], "cache");
}

/// Random edits of the dome (sets, toggles), each warm-started from the last: `λ` and the
/// status of the cold analysis of every set.
#[test]
fn random_warm_edits_of_the_dome_match_cold_analyses() {
    let (curves, build) = dome();
    let (network, _) = build_network(&curves, &build).unwrap();
    let analyzer = Analyzer::new(network, StabilityParams::default()).unwrap();
    let n = curves.len();
    let all: Vec<usize> = (0..n).collect();
    let design = Design::new(analyzer, &all).unwrap();
    let mut rng = SplitMix64::new(5);
    for step in 0..10 {
        let e = if step % 3 == 2 {
            let removed = 1 + rng.below(3) as usize;
            let kept = random_set(&mut rng, n, n - removed);
            design.set(&kept).unwrap()
        } else {
            design.toggle(rng.below(n as u64) as usize).unwrap()
        };
        let set = design.analyzer().set(&e.summary.curves);
        let cold = design.analyzer().analyze(&set, None).unwrap();
        let (w, c) = (e.summary.lambda, cold.lambda());
        assert!(
            (w - c).abs() <= 1e-6 * c.abs(),
            "step {step} {:?} ({:?}): warm {w:e}, cold {c:e}",
            e.summary.curves,
            e.source
        );
        assert_eq!(
            e.summary.zero_modes, cold.spectrum.zero_modes,
            "step {step}"
        );
        assert_eq!(e.summary.negative_modes, cold.spectrum.negative_modes);
    }
    let (held, bytes) = design.cached();
    assert!(held >= 2 && bytes > 0, "{held} states, {bytes} bytes");
}
