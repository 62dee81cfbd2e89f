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
/// where the slid run is (several lines, each ending in a newline).
pub fn slide_summary(r: &crate::run_folder::SlideRecord, folder: &std::path::Path) -> String {
    let gain = if r.lambda_before > 0.0 {
        format!(" ({:.3}×)", r.lambda_after / r.lambda_before)
    } else {
        String::new()
    };
    let moved = (r.curves.iter())
        .filter(|c| c.coefficients.iter().any(|&a| a != 0.0))
        .count();
    let mut rounds = String::new();
    for k in &r.rounds {
        rounds += &format!(
            "round {}: {:.6e} → local search {:.6e} ({} curves) → slid {:.6e}; in {}\n",
            k.round,
            k.start,
            k.local_search,
            k.curves.len(),
            k.slid,
            folder.join(&k.folder).join("slid").display()
        );
    }
    if let Some(k) = r.answer_round.filter(|&k| k > 0) {
        rounds += &format!(
            "the answer is round {k}'s slid network (the slide above is its own; the first \
             slide is kept in {})\n",
            folder
                .join(crate::run_layout::ROUNDS)
                .join("0")
                .join("slid")
                .display()
        );
    }
    format!(
        "slid: {} {:.6e} → {:.6e}{gain}; {moved} of {} curves moved, the largest move {} (at \
         most {}); joints added {}, removed {}; length {} (budget {}); {} networks \
         evaluated{}\nslid run in {}\n{rounds}",
        if r.objective == "frequency" {
            "μ_min"
        } else {
            "λ_eq"
        },
        r.lambda_before,
        r.lambda_after,
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
