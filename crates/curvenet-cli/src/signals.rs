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
//! SIGTERM and SIGHUP behave exactly like SIGINT (ctrlc's `termination` feature routes all
//! three to the handler).

use curvenet::cancel::Cancel;
use std::sync::LazyLock;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The token every polling stage of this process shares.
static CANCEL: LazyLock<Cancel> = LazyLock::new(Cancel::new);

/// How many polling stages run now (a [`Stage`] guard counts itself here).
static POLLING: AtomicUsize = AtomicUsize::new(0);

/// The exit code of a cancelled command (128 + SIGINT, what shells report for Ctrl-C).
pub const CANCELLED: i32 = 130;

/// Installs the handler. Call once, first thing in `main`.
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
