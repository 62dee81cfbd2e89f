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
        let _ = writeln!(
            s,
            "wall time: {:.2} s; output in {}",
            outcome.wall_seconds,
            outcome.folder.display()
        );
    }
    s
}
