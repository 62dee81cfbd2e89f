//! The bench's worker processes: each example runs in a fresh process of the same executable
//! ([`run_worker`]), which prints its row as one JSON line.
//!
//! A worker lives no longer than the bench that started it: its standard input is a pipe the
//! bench holds open and never writes, and the worker ends (exit 130, as a cancelled command)
//! when that pipe closes ([`exit_with_parent`]) — the bench ended, by a signal or otherwise.
//! A terminal's Ctrl-C reaches both processes anyway; a `kill` of the bench alone would
//! otherwise leave its worker computing, then failing to print to a closed pipe.

use super::bench::BenchRow;
use std::io::Read;
use std::process::{Command, Stdio};

/// Why a worker gave no row.
#[derive(Debug, thiserror::Error)]
pub enum WorkerError {
    /// The worker could not be started or waited for.
    #[error("{example}: the bench's run could not start: {source}")]
    Start {
        /// The example.
        example: String,
        /// The system's reason.
        source: std::io::Error,
    },
    /// The worker failed, or printed no row.
    #[error("{example}: the bench's run {what}: {stdout}")]
    Failed {
        /// The example.
        example: String,
        /// What went wrong.
        what: String,
        /// What it printed.
        stdout: String,
    },
}

/// Runs example `name` once in a fresh process of this executable, with the arguments `args`
/// (the front end's, selecting that example), and reads its row.
///
/// # Errors
///
/// The worker could not start, failed, or printed no row.
pub fn run_worker(args: &[String], name: &str) -> Result<BenchRow, WorkerError> {
    let start = |source| WorkerError::Start {
        example: name.to_string(),
        source,
    };
    let exe = std::env::current_exe().map_err(start)?;
    let mut child = Command::new(exe)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .map_err(start)?;
    // Held open while the worker runs: `wait_with_output` would close it first.
    let lifeline = child.stdin.take();
    let out = child.wait_with_output().map_err(start)?;
    drop(lifeline);
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let failed = |what: String| WorkerError::Failed {
        example: name.to_string(),
        what,
        stdout: stdout.clone(),
    };
    if !out.status.success() {
        return Err(failed(format!("failed ({})", out.status)));
    }
    let line = (stdout.lines().rev())
        .find(|l| l.starts_with('{'))
        .ok_or_else(|| failed("printed no row".into()))?;
    serde_json::from_str(line)
        .map_err(|e| failed(format!("printed a row that does not read ({e})")))
}

/// In a worker: ends the process (exit 130) as soon as its standard input, the bench's
/// lifeline, closes.
pub fn exit_with_parent() {
    std::thread::spawn(|| {
        let mut buf = [0u8; 64];
        loop {
            match std::io::stdin().read(&mut buf) {
                Ok(0) | Err(_) => crate::io::exit_removing_temp_files(130),
                Ok(_) => {}
            }
        }
    });
}
