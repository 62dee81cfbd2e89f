//! The text a finished run shows its user: the record's summary, the answer's physical
//! figures, the times of the steps that ran and where the output is.

use super::RunOutcome;
use crate::physics::PhysicalSummary;
use crate::run_folder::summary;
use std::fmt::Write;

/// The finished run's summary (several lines, each ending in a newline).
pub fn run_summary(outcome: &RunOutcome) -> String {
    let result = &outcome.result;
    let mut s = summary(result);
    // The answer's figures; without an answer, the greedy's last network's, said as such.
    let shown = match &result.answer {
        Some(a) => a.physical.as_ref().map(|p| (p, "the answer")),
        None => result
            .iterations
            .last()
            .and_then(|r| r.physical.as_ref())
            .map(|p| (p, "the greedy's last network, not an answer")),
    };
    if let Some((p, what)) = shown {
        let _ = writeln!(s, "{}", physical_line(p, what));
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

/// A network's physical figures in one line.
fn physical_line(p: &PhysicalSummary, what: &str) -> String {
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
    line
}
