//! Ctrl-C (SIGINT), SIGTERM and SIGHUP: one handler for every subcommand, installed first.
//!
//! A signal stops the command with exit code 130 and keeps what it has recorded. During a
//! stage that polls the process's token ([`token`]: the greedy, the local search, the
//! certificate) it cancels the token: the stage stops at its next poll (within a second) and
//! the command says what is kept and how to continue. Anywhere else, and on a second signal,
//! the process exits at once, first removing the temporary files of the atomic writes in
//! flight, so nothing half-written is left.
//!
//! On Unix no signal handler runs: [`install`] blocks the three signals before any other
//! thread exists (threads inherit the mask; child processes start with an empty one) and one
//! thread takes them with `sigwait`. So no library that installs handlers for a while can
//! catch one: METIS points SIGTERM at a `longjmp` into its error path during every ordering,
//! which crashed a run stopped then. Elsewhere ctrlc's handler does the same job.

use curvenet::cancel::Cancel;
use std::sync::LazyLock;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The token every polling stage of this process shares.
static CANCEL: LazyLock<Cancel> = LazyLock::new(Cancel::new);

/// How many polling stages run now (a [`Stage`] guard counts itself here).
static POLLING: AtomicUsize = AtomicUsize::new(0);

/// The exit code of a cancelled command (128 + SIGINT, what shells report for Ctrl-C).
pub const CANCELLED: i32 = 130;

/// Starts receiving the signals: call once, first in `main`, before any thread starts.
#[cfg(unix)]
pub fn install() {
    use nix::sys::signal::{SigSet, Signal::*};
    let set: SigSet = [SIGINT, SIGTERM, SIGHUP].into_iter().collect();
    // Fails only for an invalid set (never, here): signals then keep their default action.
    if set.thread_block().is_err() {
        return;
    }
    let waiter = move || {
        while set.wait().is_ok() {
            on_signal();
        }
    };
    let spawned = std::thread::Builder::new()
        .name("signals".into())
        .spawn(waiter);
    if spawned.is_err() {
        // No thread to take them: the signals get their default action back.
        let _ = set.thread_unblock();
    }
}

/// Starts receiving the signals. Call once, first thing in `main`.
#[cfg(not(unix))]
pub fn install() {
    let _ = ctrlc::set_handler(on_signal); // fails only if one is installed (never, here)
}

fn on_signal() {
    if POLLING.load(Ordering::SeqCst) > 0 && !CANCEL.is_cancelled() {
        CANCEL.cancel();
        eprintln!("\nstopping (a second Ctrl-C stops at once)…");
    } else {
        eprintln!("\ncancelled");
        curvenet::io::exit_removing_temp_files(CANCELLED);
    }
}

/// The process's cancellation token, for the stages a [`Stage`] guard covers.
pub fn token() -> Cancel {
    CANCEL.clone()
}

/// While alive, signals cancel the token instead of ending the process: hold one around every
/// stage that polls [`token`].
#[must_use = "the guard covers the stage only while it is alive"]
pub struct Stage(());

impl Stage {
    /// Starts a polling stage.
    pub fn start() -> Self {
        POLLING.fetch_add(1, Ordering::SeqCst);
        Stage(())
    }
}

impl Drop for Stage {
    fn drop(&mut self) {
        POLLING.fetch_sub(1, Ordering::SeqCst);
    }
}
