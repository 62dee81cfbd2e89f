//! Ctrl-C (SIGINT), SIGTERM and SIGHUP: one handler for every subcommand, installed before any
//! work.
//!
//! The rule: a signal stops the command with exit code 130 and keeps what it has recorded.
//!
//! - During a stage that polls the process's cancellation token ([`token`]: the greedy, the
//!   local search, the certificate), a signal cancels the token; the stage stops at its next
//!   poll (within a second), keeps what it recorded, and the command exits 130 saying what is
//!   kept and how to continue.
//! - Anywhere else (reading inputs, building the network, the pictures, the comparison's
//!   searches, a benchmark, the exports), and on a second signal, the process exits 130 at
//!   once. Every output is written to a temporary file and renamed, and the temporary files of
//!   the writes in flight are removed before the exit, so nothing half-written is left, under
//!   its final name or any other.
//!
//! How signals arrive (Unix): [`install`] blocks the three signals in the main thread before
//! any other thread exists, so every thread inherits the block, and one thread takes them with
//! `sigwait`. No signal handler runs at all, so a library that installs its own handlers for a
//! while cannot catch one: METIS's nested dissection points SIGTERM at a `longjmp` into its own
//! error path during every ordering (a SIGTERM then crashed the process with SIGSEGV, and
//! concurrent orderings could leave that handler in place). Child processes start with an
//! empty signal mask (the standard library resets it). Elsewhere, ctrlc's handler does the
//! same job.

use curvenet::cancel::Cancel;
use std::sync::LazyLock;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The token every polling stage of this process shares.
static CANCEL: LazyLock<Cancel> = LazyLock::new(Cancel::new);

/// How many polling stages run now (a [`Stage`] guard counts itself here).
static POLLING: AtomicUsize = AtomicUsize::new(0);

/// The exit code of a cancelled command (128 + SIGINT, what shells report for Ctrl-C).
pub const CANCELLED: i32 = 130;

/// Starts receiving the signals. Call once, first thing in `main`, before any thread is
/// started: threads inherit the signal mask of the thread that starts them.
#[cfg(unix)]
pub fn install() {
    use nix::sys::signal::{SigSet, Signal};
    let mut set = SigSet::empty();
    for s in [Signal::SIGINT, Signal::SIGTERM, Signal::SIGHUP] {
        set.add(s);
    }
    // Fails only for an invalid signal set (never, here): signals then keep their default
    // action, which also ends the process.
    if set.thread_block().is_err() {
        return;
    }
    let waiter = std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            while set.wait().is_ok() {
                on_signal();
            }
        });
    if waiter.is_err() {
        // No thread to take them: give the signals their default action back.
        let _ = set.thread_unblock();
    }
}

/// Starts receiving the signals. Call once, first thing in `main`.
#[cfg(not(unix))]
pub fn install() {
    // Fails only when a handler is already installed (never, here): signals then keep their
    // default action, which also ends the process.
    let _ = ctrlc::set_handler(on_signal);
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
