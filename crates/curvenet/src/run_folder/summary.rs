//! `summary.txt` and the warnings a run's record calls for.

use super::ResultFile;
use crate::fmt;
use crate::physics::PhysicalSummary;
use crate::simplify::greedy::IterationRecord;
use crate::stability::Objective;

/// One line per iteration whose relaxation stopped short of equilibrium (iteration cap,
/// stall, failed line search): its `λ_eq` (or `μ_min`, under `objective`) belongs to an
/// unrelaxed state. Empty when every relaxation converged (to the tolerance or the round-off
/// floor).
pub fn unrelaxed(iterations: &[IterationRecord], objective: Objective) -> Vec<String> {
    let value = objective.value_symbol();
    iterations
        .iter()
        .enumerate()
        .filter(|(_, r)| !r.newton.converged)
        .map(|(k, r)| {
            format!(
                "iteration {k} ({} curves): the relaxation stopped short of equilibrium \
                 ({} after {} Newton steps, relative gradient {:.1e}); its {value} is that \
                 of an unrelaxed state",
                r.curves.len(),
                r.newton.stop,
                r.newton.iterations,
                r.newton.grad_rel
            )
        })
        .collect()
}

/// What makes a network unstable, in words (`unstable: 1 zero mode, a mechanism …`), from its
/// `λ_eq` and the zero and negative modes among its computed eigenvalues; `None` when it is
/// stable (`λ_eq > 0`, no zero or negative mode). Every place that shows a recorded network's
/// numbers adds it, so a mechanism is never shown as if it could stand.
pub fn instability(lambda: f64, zero_modes: usize, negative_modes: usize) -> Option<String> {
    let plural = |n: usize, what: &str| format!("{n} {what} mode{}", if n == 1 { "" } else { "s" });
    match (zero_modes, negative_modes) {
        (0, 0) if lambda > 0.0 => None,
        (0, 0) => Some(format!(
            "unstable: λ_eq {lambda:.3e} is not positive, the network cannot stand"
        )),
        (z, 0) => Some(format!(
            "unstable: {}, a mechanism (a part of it moves freely)",
            plural(z, "zero")
        )),
        (0, n) => Some(format!(
            "unstable: {}, an unstable equilibrium",
            plural(n, "negative")
        )),
        (z, n) => Some(format!(
            "unstable: {} and {}, an unstable equilibrium and a mechanism",
            plural(n, "negative"),
            plural(z, "zero")
        )),
    }
}

/// [`instability`] of a recorded iteration.
pub fn record_instability(r: &IterationRecord) -> Option<String> {
    instability(r.lambda, r.zero_modes, r.negative_modes)
}

/// The warnings of a run whose recorded networks include unstable ones (zero or negative
/// modes): one line for the final network when it is unstable, one naming the other unstable
/// iterations. Empty when every recorded network is stable. The value shown is `objective`'s.
pub fn unstable(iterations: &[IterationRecord], objective: Objective) -> Vec<String> {
    let value = objective.value_symbol();
    let mut lines = Vec::new();
    let Some(last) = iterations.len().checked_sub(1) else {
        return lines;
    };
    if let Some(why) = record_instability(&iterations[last]) {
        lines.push(format!(
            "the final network (iteration {last}, {} curves, {value} {:.6e}) is {why}; it \
             cannot stand as built and is never the answer",
            iterations[last].curves.len(),
            iterations[last].lambda
        ));
    }
    let earlier: Vec<String> = iterations[..last]
        .iter()
        .enumerate()
        .filter_map(|(k, r)| {
            record_instability(r).map(|why| {
                let why = why.trim_start_matches("unstable: ");
                format!("{k} ({} curves, {why})", r.curves.len())
            })
        })
        .collect();
    const SHOWN: usize = 8;
    if !earlier.is_empty() {
        let more = earlier.len().saturating_sub(SHOWN);
        let mut list = earlier[..earlier.len().min(SHOWN)].join("; ");
        if more > 0 {
            list.push_str(&format!("; and {more} more"));
        }
        lines.push(format!(
            "{} earlier iteration(s) recorded unstable networks: {list}",
            earlier.len()
        ));
    }
    lines
}

/// ` (unstable: …)` after a recorded network's numbers when it is unstable, else nothing.
fn unstable_suffix(r: &IterationRecord) -> String {
    record_instability(r).map_or_else(String::new, |w| format!(" ({w})"))
}

/// A short text summary of a result: in the physical mode every length carries the scene's
/// unit, and the answer's physical figures (or, without an answer, the greedy's last
/// network's, said as such) end it.
pub fn summary(r: &ResultFile) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let first = r.iterations.first();
    let last = r.iterations.last();
    let goal = r.setup.stability.objective;
    let frequency = goal == Objective::Frequency;
    let value = goal.value_symbol();
    let unit = r.length_unit();
    let len = |x: f64| fmt::length_in(x, unit);
    let objective = if frequency {
        "the first natural frequency, μ_min"
    } else {
        "λ_eq"
    };
    let freq = |it: &IterationRecord| match (frequency, it.first_frequency) {
        (false, _) => String::new(),
        (true, Some(f)) => format!(", f₁ {f:.6e}"),
        (true, None) => String::new(),
    };
    let _ = writeln!(
        s,
        "curvenet greedy simplification (objective {objective}, supports {})",
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
        "budget: {} of {} total rest length",
        len(r.budget),
        len(r.setup.total_length)
    );
    if let (Some(f), Some(l)) = (first, last) {
        for (what, it) in [("start", f), ("final", l)] {
            let _ = writeln!(
                s,
                "{what}: {} curves, length {}, {value} {:.6e}{}{}",
                it.curves.len(),
                len(it.length),
                it.lambda,
                freq(it),
                unstable_suffix(it)
            );
        }
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
    for line in unrelaxed(&r.iterations, goal)
        .into_iter()
        .chain(unstable(&r.iterations, goal))
    {
        let _ = writeln!(s, "warning: {line}");
    }
    if let Some(l) = &r.local_search {
        let _ = writeln!(s, "{}", l.describe(unit));
    }
    if let Some(c) = &r.certificate {
        let _ = writeln!(s, "{}", c.describe());
    }
    if let Some(a) = &r.answer {
        let _ = writeln!(
            s,
            "answer (the network to build): {}",
            a.describe(value, unit)
        );
    } else if let Some(n) = &r.no_answer {
        let _ = writeln!(s, "{}", n.describe(value, unit));
    }
    for (i, a) in r.alternatives.iter().enumerate() {
        let _ = writeln!(
            s,
            "alternative {} (alternative-{}.obj): {}; curves {:?}",
            i + 1,
            i + 1,
            a.describe(value, unit),
            a.found.curves
        );
    }
    // The answer's physical figures; without an answer, the greedy's last network's.
    let shown = match &r.answer {
        Some(a) => a.physical.as_ref().map(|p| (p, "the answer")),
        None => r
            .iterations
            .last()
            .and_then(|i| i.physical.as_ref())
            .map(|p| (p, "the greedy's last network, not an answer")),
    };
    if let Some((p, what)) = shown {
        let _ = writeln!(s, "{}", physical_line(p, what, unit));
    }
    s
}

/// A network's physical figures in one line, each with its unit (`unit`: the scene's length
/// unit, the deflections' and deviations', when the record does not name it).
fn physical_line(p: &PhysicalSummary, what: &str, unit: Option<&str>) -> String {
    use std::fmt::Write as _;
    let unit = p.units.as_deref().or(unit).unwrap_or("(scene units)");
    let opt = |v: Option<f64>, unit: &str| {
        v.map_or("none (unstable)".into(), |v| format!("{v:.4} {unit}"))
    };
    let mut line = format!(
        "physical ({what}): first frequency {}, self-weight deflection {}, worst-load \
         deflection {}",
        opt(p.first_frequency_hz, "Hz"),
        opt(p.self_weight_max_deflection, unit),
        opt(p.load_max_deflection, unit),
    );
    if let Some(d) = p.max_deviation {
        let _ = write!(
            line,
            ", deviation from the design under self-weight {d:.4} {unit}"
        );
    }
    let _ = write!(
        line,
        ", assembly bending stress {:.1} MPa, mass {:.2} kg",
        p.assembly_max_bending_stress_mpa, p.mass_kg
    );
    if let Some(u) = p.max_utilisation {
        let _ = write!(line, ", utilisation {u:.3}");
    }
    if !p.overstressed_curves.is_empty() {
        let ids: Vec<String> = p.overstressed_curves.iter().map(usize::to_string).collect();
        let _ = write!(
            line,
            ", curves that would break when bent: {}",
            ids.join(", ")
        );
    }
    for case in &p.load_cases {
        let _ = write!(line, "\n  {}", case.to_text(unit));
    }
    line
}

#[cfg(test)]
mod tests {
    use super::{instability, unrelaxed, unstable};
    use crate::simplify::greedy::IterationRecord;
    use crate::solve::NewtonStop;
    use crate::stability::NewtonSummary;
    use crate::stability::Objective;

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
            first_frequency: None,
        }
    }

    #[test]
    fn relaxations_short_of_equilibrium_are_reported() {
        let its = vec![
            record(5, true, NewtonStop::Converged),
            record(4, true, NewtonStop::RoundoffFloor),
            record(3, false, NewtonStop::MaxIterations),
        ];
        let lines = unrelaxed(&its, Objective::Lambda);
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
        assert!(unrelaxed(&its[..2], Objective::Lambda).is_empty());
    }

    #[test]
    fn unstable_networks_are_named() {
        assert_eq!(instability(1e-6, 0, 0), None);
        assert!(
            instability(-2e-15, 1, 0)
                .unwrap()
                .contains("1 zero mode, a mechanism")
        );
        assert!(
            instability(-1e-3, 0, 2)
                .unwrap()
                .contains("2 negative modes")
        );
        assert!(instability(0.0, 0, 0).unwrap().starts_with("unstable: "));
        let mut its: Vec<IterationRecord> = (0..4)
            .map(|k| record(10 - k, true, NewtonStop::Converged))
            .collect();
        assert!(unstable(&its, Objective::Lambda).is_empty());
        its[2].zero_modes = 1;
        its[3].lambda = -2e-15;
        its[3].zero_modes = 1;
        let lines = unstable(&its, Objective::Lambda);
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert!(
            lines[0].starts_with("the final network (iteration 3, 7 curves")
                && lines[0].contains("unstable: 1 zero mode"),
            "{}",
            lines[0]
        );
        assert!(
            lines[1].contains("1 earlier iteration(s)")
                && lines[1].contains("2 (8 curves, 1 zero mode"),
            "{}",
            lines[1]
        );
        // Under the frequency objective the value shown is μ_min.
        let freq = unstable(&its, Objective::Frequency);
        assert!(
            freq[0].contains("7 curves, μ_min -2.000000e-15)"),
            "{}",
            freq[0]
        );
        assert!(!freq[0].contains("λ_eq"), "{}", freq[0]);
        its[1].newton.converged = false;
        let freq = unrelaxed(&its, Objective::Frequency);
        assert!(freq[0].contains("its μ_min is that of"), "{}", freq[0]);
    }
}
