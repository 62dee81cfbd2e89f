//! The text a finished run shows its user: the record's summary, the answer's physical
//! figures, the times of the steps that ran and where the output is.

use super::RunOutcome;
use crate::run_folder::summary;
use crate::simplify::greedy::IterationRecord;
use std::fmt::Write;

/// The finished run's summary (several lines, each ending in a newline).
pub fn run_summary(outcome: &RunOutcome) -> String {
    let result = &outcome.result;
    let mut s = summary(result);
    // The answer's figures when it is one of the greedy's networks, else the last one's,
    // labelled as such.
    let answer = result
        .answer
        .as_ref()
        .and_then(|a| a.found.iteration)
        .and_then(|k| result.iterations.get(k).map(|r| (r, "the answer")));
    let shown = answer.or_else(|| {
        result
            .iterations
            .last()
            .map(|r| (r, "the greedy's last network"))
    });
    if let Some(line) = shown.and_then(|(r, what)| physical_line(r, what)) {
        let _ = writeln!(s, "{line}");
    }
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
        let _ = writeln!(
            s,
            "wall time: {:.2} s; output in {}",
            outcome.wall_seconds,
            outcome.folder.display()
        );
    }
    s
}

/// A network's physical figures in one line (the physical mode only).
fn physical_line(record: &IterationRecord, what: &str) -> Option<String> {
    let p = record.physical.as_ref()?;
    let unit = p.units.as_deref().unwrap_or("(scene units)");
    let opt = |v: Option<f64>, unit: &str| {
        v.map_or("none (unstable)".into(), |v| format!("{v:.4} {unit}"))
    };
    let mut line = format!(
        "physical ({what}): first frequency {}, self-weight deflection {}, worst-load \
         deflection {}, assembly bending stress {:.1} MPa, mass {:.2} kg",
        opt(p.first_frequency_hz, "Hz"),
        opt(p.self_weight_max_deflection, unit),
        opt(p.load_max_deflection, unit),
        p.assembly_max_bending_stress_mpa,
        p.mass_kg
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
    Some(line)
}
