//! The text a finished run shows its user: the record's summary (with the answer's physical
//! figures), the times of the steps that ran and where the output is.

use super::RunOutcome;
use crate::run_folder::summary;
use std::fmt::Write;

/// The finished run's summary (several lines, each ending in a newline).
pub fn run_summary(outcome: &RunOutcome) -> String {
    let result = &outcome.result;
    let mut s = summary(result);
    if !outcome.already_complete {
        if result.local_search.is_some() {
            let _ = writeln!(
                s,
                "local search time: {:.2} s",
                outcome.seconds.local_search
            );
        }
        if result.certificate.is_some() {
            let _ = writeln!(s, "certificate time: {:.2} s", outcome.seconds.certificate);
        }
        if let Some(r) = &outcome.slide {
            s.push_str(&slide_summary(r, &outcome.folder.join("slide")));
        }
        let _ = writeln!(
            s,
            "wall time: {:.2} s; output in {}",
            outcome.wall_seconds,
            outcome.folder.display()
        );
    }
    s
}

/// A slid run's summary: the objective before and after, the moves, the joints changed and
/// where the slid run is (several lines, each ending in a newline). A value that is not
/// positive is named unstable; when the run recorded another value for the start (its curves
/// within the full network), both are shown.
pub fn slide_summary(r: &crate::run_folder::SlideRecord, folder: &std::path::Path) -> String {
    let value = |v: f64| match crate::run_folder::instability(v, 0, 0) {
        None => format!("{v:.6e}"),
        Some(_) => format!("{v:.6e} (unstable)"),
    };
    let gain = if r.lambda_before > 0.0 {
        format!(" ({:.3}×)", r.lambda_after / r.lambda_before)
    } else {
        String::new()
    };
    let moved = (r.curves.iter())
        .filter(|c| c.coefficients.iter().any(|&a| a != 0.0))
        .count();
    let name = match r.objective.as_str() {
        "frequency" => "μ_min",
        _ => "λ_eq",
    };
    let mut notes = String::new();
    let scale = r.lambda_before.abs().max(r.lambda_recorded.abs());
    if (r.lambda_before - r.lambda_recorded).abs() > 1e-6 * scale {
        notes += &format!(
            "before and after are of the curves rebuilt as a network of their own (what an \
             analysis of the exported curves gives); the run recorded {name} {} for the start's \
             curves within its whole network, whose rods also have vertices where the removed \
             curves crossed them\n",
            value(r.lambda_recorded)
        );
    }
    for k in &r.rounds {
        notes += &format!(
            "round {}: {} → local search {} ({} curves, measured within the network of every \
             curve) → slid {}; in {}\n",
            k.round,
            value(k.start),
            value(k.local_search),
            k.curves.len(),
            value(k.slid),
            folder.join(&k.folder).join("slid").display()
        );
    }
    if let Some(k) = r.answer_round.filter(|&k| k > 0) {
        notes += &format!(
            "the answer is round {k}'s slid network (the slide above is its own; the first \
             slide is kept in {})\n",
            folder
                .join(crate::run_layout::round_folder(0))
                .join("slid")
                .display()
        );
    }
    format!(
        "slid: {name} {} → {}{gain}; {moved} of {} curves moved, the largest move {} (at most \
         {}); joints added {}, removed {}; length {} (budget {}); {} networks evaluated{}\nslid \
         run in {}\n{notes}",
        value(r.lambda_before),
        value(r.lambda_after),
        r.curves.len(),
        crate::fmt::length(r.largest_move),
        crate::fmt::length(r.max_move),
        r.joints_added,
        r.joints_removed,
        crate::fmt::length(r.length_after),
        crate::fmt::length(r.budget),
        r.evaluations,
        if r.stopped { " (stopped early)" } else { "" },
        folder.display()
    )
}

#[cfg(test)]
mod tests {
    use super::slide_summary;
    use crate::run_folder::SlideRecord;

    fn record(before: f64, after: f64, recorded: f64) -> SlideRecord {
        serde_json::from_value(serde_json::json!({
            "from": "run", "objective": "lambda_eq", "lambda_before": before,
            "lambda_after": after, "lambda_recorded": recorded, "max_move": 1.0,
            "largest_move": 0.5, "joints_added": 0, "joints_removed": 0, "length_before": 10.0,
            "length_after": 10.0, "budget": 12.0, "fixed_ends": false, "curves": [],
            "evaluations": 3, "sweeps": 1, "steps": [], "stopped": false
        }))
        .expect("a slide record")
    }

    #[test]
    fn a_slide_names_unstable_values_and_the_runs_own_value_of_its_start() {
        let dir = std::path::Path::new("out/slide");
        let same = slide_summary(&record(2e-8, 3e-8, 2e-8), dir);
        assert!(
            same.starts_with("slid: λ_eq 2.000000e-8 → 3.000000e-8 (1.500×);"),
            "{same}"
        );
        assert!(
            !same.contains("unstable") && !same.contains("recorded"),
            "{same}"
        );
        let text = slide_summary(&record(-1e-9, 3e-8, 8e-9), dir);
        assert!(
            text.starts_with("slid: λ_eq -1.000000e-9 (unstable) → 3.000000e-8;"),
            "{text}"
        );
        assert!(
            text.contains("the run recorded λ_eq 8.000000e-9 for"),
            "{text}"
        );
    }
}
