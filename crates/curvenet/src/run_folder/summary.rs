//! `summary.txt` and the warnings a run's record calls for.

use super::ResultFile;
use crate::simplify::greedy::IterationRecord;

/// One line per iteration whose relaxation stopped short of equilibrium (iteration cap,
/// stall, failed line search): its `λ_eq` belongs to an unrelaxed state. Empty when every
/// relaxation converged (to the tolerance or the round-off floor).
pub fn unrelaxed(iterations: &[IterationRecord]) -> Vec<String> {
    iterations
        .iter()
        .enumerate()
        .filter(|(_, r)| !r.newton.converged)
        .map(|(k, r)| {
            format!(
                "iteration {k} ({} curves): the relaxation stopped short of equilibrium \
                 ({} after {} Newton steps, relative gradient {:.1e}); its λ_eq is that of \
                 an unrelaxed state",
                r.curves.len(),
                r.newton.stop,
                r.newton.iterations,
                r.newton.grad_rel
            )
        })
        .collect()
}

/// A short text summary of a result.
pub fn summary(r: &ResultFile) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let first = r.iterations.first();
    let last = r.iterations.last();
    let _ = writeln!(
        s,
        "curvenet greedy simplification (objective λ_eq, supports {})",
        r.setup.build.supports.name()
    );
    if let Some(ex) = &r.setup.input.example {
        let _ = writeln!(s, "example: {ex}");
    }
    let n = &r.setup.network;
    let _ = writeln!(
        s,
        "network: {} curves, {} vertices, {} joints",
        n.curves, n.vertices, n.joints
    );
    let _ = writeln!(
        s,
        "budget: {:.6} of {:.6} total rest length",
        r.budget, r.setup.total_length
    );
    if let (Some(f), Some(l)) = (first, last) {
        let _ = writeln!(
            s,
            "start: {} curves, length {:.6}, λ_eq {:.6e}",
            f.curves.len(),
            f.length,
            f.lambda
        );
        let _ = writeln!(
            s,
            "final: {} curves, length {:.6}, λ_eq {:.6e}",
            l.curves.len(),
            l.length,
            l.lambda
        );
        let _ = writeln!(s, "kept curves: {:?}", l.curves);
    }
    let removed: Vec<String> = r
        .iterations
        .iter()
        .filter_map(|i| i.removed.map(|c| c.to_string()))
        .collect();
    let _ = writeln!(s, "removed in order: {}", removed.join(", "));
    let stop = r.stop.map_or("not finished".to_string(), |s| s.to_string());
    let _ = writeln!(s, "iterations: {}; stop: {stop}", r.iterations.len());
    for line in unrelaxed(&r.iterations) {
        let _ = writeln!(s, "warning: {line}");
    }
    if let Some(l) = &r.local_search {
        let _ = writeln!(s, "{}", l.describe());
    }
    if let Some(c) = &r.certificate {
        let _ = writeln!(s, "{}", c.describe());
    }
    if let Some(a) = &r.answer {
        let _ = writeln!(s, "answer (the network to build): {}", a.describe());
    } else if let Some(n) = &r.no_answer {
        let _ = writeln!(s, "{}", n.describe());
    }
    for (i, a) in r.alternatives.iter().enumerate() {
        let _ = writeln!(
            s,
            "alternative {} (alternative-{}.obj): {}; curves {:?}",
            i + 1,
            i + 1,
            a.describe(),
            a.curves
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::unrelaxed;
    use crate::simplify::greedy::IterationRecord;
    use crate::solve::NewtonStop;
    use crate::solve::NewtonSummary;

    fn record(curves: usize, converged: bool, stop: NewtonStop) -> IterationRecord {
        IterationRecord {
            curves: (0..curves).collect(),
            length: 1.0,
            lambda: 1e-9,
            eigenvalues: vec![1e-9],
            zero_modes: 0,
            negative_modes: 0,
            newton: NewtonSummary {
                iterations: if converged { 5 } else { 200 },
                converged,
                grad_rel: if converged { 1e-12 } else { 2.6e-8 },
                stop,
                factorizations: 5,
                chord_steps: 0,
            },
            removed: None,
            removed_group: Vec::new(),
            score: None,
            candidates: Vec::new(),
            mode_file: String::new(),
            physical: None,
        }
    }

    #[test]
    fn relaxations_short_of_equilibrium_are_reported() {
        let its = vec![
            record(5, true, NewtonStop::Converged),
            record(4, true, NewtonStop::RoundoffFloor),
            record(3, false, NewtonStop::MaxIterations),
        ];
        let lines = unrelaxed(&its);
        assert_eq!(lines.len(), 1, "{lines:?}");
        assert!(
            lines[0].starts_with("iteration 2 (3 curves)"),
            "{}",
            lines[0]
        );
        assert!(
            lines[0].contains("iteration limit reached after 200 Newton steps"),
            "{}",
            lines[0]
        );
        assert!(unrelaxed(&its[..2]).is_empty());
    }
}
