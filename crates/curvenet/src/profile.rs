//! Process-wide counters of where the time goes, for `curvenet bench`.
//!
//! Each phase accumulates CPU-side wall time (summed over threads, so with two busy threads a
//! phase can exceed the elapsed time) and a call count. The counters only observe: nothing
//! reads them to make a decision, so results never depend on them.

use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// A measured phase.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Energy, gradient and Hessian assembly (including local Hessians).
    Assemble,
    /// Numeric sparse factorizations.
    Factor,
    /// Triangular solves with a factor (per call, any number of right-hand sides).
    Solve,
    /// Whole eigen solves (factorization and solves included).
    Eigen,
    /// Whole Newton relaxations (assembly, factorizations and solves included).
    Relax,
    /// Rayleigh–Ritz bounds of candidates.
    Bound,
}

const PHASES: usize = 6;

static NANOS: [AtomicU64; PHASES] = [const { AtomicU64::new(0) }; PHASES];
static CALLS: [AtomicU64; PHASES] = [const { AtomicU64::new(0) }; PHASES];

fn index(p: Phase) -> usize {
    match p {
        Phase::Assemble => 0,
        Phase::Factor => 1,
        Phase::Solve => 2,
        Phase::Eigen => 3,
        Phase::Relax => 4,
        Phase::Bound => 5,
    }
}

/// Runs `f`, adding its duration to `phase`.
#[inline]
pub fn time<T>(phase: Phase, f: impl FnOnce() -> T) -> T {
    let t = Instant::now();
    let r = f();
    let i = index(phase);
    NANOS[i].fetch_add(t.elapsed().as_nanos() as u64, Ordering::Relaxed);
    CALLS[i].fetch_add(1, Ordering::Relaxed);
    r
}

/// Seconds and calls of one phase.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PhaseTotal {
    /// Accumulated seconds (summed over threads).
    pub seconds: f64,
    /// Number of timed calls.
    pub calls: u64,
}

/// A snapshot of every phase.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    /// Assembly.
    pub assemble: PhaseTotal,
    /// Factorizations.
    pub factor: PhaseTotal,
    /// Solves.
    pub solve: PhaseTotal,
    /// Eigen solves.
    pub eigen: PhaseTotal,
    /// Relaxations.
    pub relax: PhaseTotal,
    /// Candidate bounds.
    pub bound: PhaseTotal,
}

fn total(i: usize) -> PhaseTotal {
    PhaseTotal {
        seconds: NANOS[i].load(Ordering::Relaxed) as f64 * 1e-9,
        calls: CALLS[i].load(Ordering::Relaxed),
    }
}

/// The counters now.
pub fn snapshot() -> Snapshot {
    Snapshot {
        assemble: total(0),
        factor: total(1),
        solve: total(2),
        eigen: total(3),
        relax: total(4),
        bound: total(5),
    }
}

/// Sets every counter to zero.
pub fn reset() {
    for i in 0..PHASES {
        NANOS[i].store(0, Ordering::Relaxed);
        CALLS[i].store(0, Ordering::Relaxed);
    }
}

/// Peak resident memory of the process in bytes (Linux `VmHWM`), if known.
pub fn peak_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// CPU time of the whole process so far (user and system, every thread), in seconds, if
/// known (Linux `/proc/self/stat`, 10 ms resolution). Against the wall time it shows how
/// much of the machine a run used: on two cores, a run whose CPU time is `c` cannot take
/// less than `c / 2` seconds without doing less work.
pub fn cpu_seconds() -> Option<f64> {
    cpu_seconds_from(&std::fs::read_to_string("/proc/self/stat").ok()?)
}

/// Clock ticks per second of `/proc`'s times (`USER_HZ`, 100 on every Linux ABI).
const USER_HZ: f64 = 100.0;

/// [`cpu_seconds`] from the text of `/proc/<pid>/stat`: `utime` and `stime`, the 14th and 15th
/// fields, counted after the command name (which may hold spaces and parentheses).
fn cpu_seconds_from(stat: &str) -> Option<f64> {
    let rest = &stat[stat.rfind(')')? + 1..];
    let mut fields = rest.split_whitespace();
    // `rest` starts at the 3rd field (state): utime is the 14th, stime the 15th.
    let utime: u64 = fields.nth(11)?.parse().ok()?;
    let stime: u64 = fields.next()?.parse().ok()?;
    Some((utime + stime) as f64 / USER_HZ)
}

/// Resets the peak-memory mark to the current use (Linux `clear_refs`); false if unsupported.
pub fn reset_peak_memory() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// Adds the time until it is dropped to a phase (for timing a whole function body).
#[derive(Debug)]
pub struct Timer {
    phase: Phase,
    start: Instant,
}

impl Timer {
    /// Starts timing `phase`.
    #[inline]
    pub fn new(phase: Phase) -> Self {
        Timer {
            phase,
            start: Instant::now(),
        }
    }
}

impl Drop for Timer {
    fn drop(&mut self) {
        let i = index(self.phase);
        NANOS[i].fetch_add(self.start.elapsed().as_nanos() as u64, Ordering::Relaxed);
        CALLS[i].fetch_add(1, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cpu_time_is_read_after_the_command_name() {
        // A command name with spaces and a parenthesis; utime 250 and stime 30 ticks.
        let stat = "4242 (a (b) c) R 1 2 3 4 5 6 7 8 9 10 250 30 0 0 20 0 3 0 100 0 0";
        assert_eq!(cpu_seconds_from(stat), Some(2.8));
        assert_eq!(cpu_seconds_from("4242 (x) R 1 2"), None);
        assert_eq!(cpu_seconds_from("no parenthesis"), None);
    }

    #[test]
    fn cpu_time_grows_while_the_process_computes() {
        let Some(start) = cpu_seconds() else {
            // Not Linux: nothing to measure.
            assert!(!std::path::Path::new("/proc/self/stat").exists());
            return;
        };
        let wall = Instant::now();
        let mut x = 1.0f64;
        while cpu_seconds().is_some_and(|c| c < start + 0.05) {
            for _ in 0..100_000 {
                x = (x * 1.000_000_1).sqrt() + 1e-9;
            }
            assert!(
                wall.elapsed().as_secs() < 20,
                "CPU time stayed at {start} s for 20 s of computing"
            );
        }
        assert!(x.is_finite());
    }
}
