//! Long calls: the work runs on a thread of its own without the GIL while the calling
//! thread waits, hands progress to the Python callback (holding the GIL only for the call)
//! and polls for signals. A `KeyboardInterrupt` (or an exception raised by the callback)
//! sets the [`Cancel`] token the library polls; the work stops within a fraction of a
//! second, keeping what it recorded, and the call raises that exception.

use curvenet::cancel::Cancel;
use pyo3::prelude::*;
use std::sync::{Mutex, mpsc};
use std::time::Duration;

/// How often the waiting thread polls for signals.
const POLL: Duration = Duration::from_millis(50);

/// What the work sends back while it runs.
pub type Progress = mpsc::Sender<String>;

/// Runs `work` without the GIL. `work` gets a [`Cancel`] token to hand the library and a
/// sender for progress messages (JSON text, passed to `progress` as a parsed object by the
/// Python layer: here, as the string). Returns `work`'s result, or the Python exception
/// that interrupted it.
pub fn run<T, F>(py: Python<'_>, progress: Option<&Bound<'_, PyAny>>, work: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce(&Cancel, &Progress) -> T + Send,
{
    let cancel = Cancel::new();
    let (tx, rx) = mpsc::channel::<String>();
    // Behind a mutex only to be shareable with the GIL-free wait below (one reader).
    let rx = Mutex::new(rx);
    let mut interrupted: Option<PyErr> = None;
    let result = std::thread::scope(|s| {
        let worker = {
            let cancel = cancel.clone();
            s.spawn(move || {
                let tx = tx;
                work(&cancel, &tx)
            })
        };
        loop {
            let msg = py.detach(|| {
                rx.lock()
                    .map_err(|_| mpsc::RecvTimeoutError::Disconnected)
                    .and_then(|r| r.recv_timeout(POLL))
            });
            match msg {
                Ok(text) => {
                    if interrupted.is_none()
                        && let Some(cb) = progress
                        && let Err(e) = cb.call1((text,))
                    {
                        cancel.cancel();
                        interrupted = Some(e);
                    }
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                // The worker dropped its sender: it is done.
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            }
            if interrupted.is_none()
                && let Err(e) = py.check_signals()
            {
                cancel.cancel();
                interrupted = Some(e);
            }
        }
        py.detach(move || worker.join())
    });
    let result = match result {
        Ok(r) => r,
        Err(panic) => std::panic::resume_unwind(panic),
    };
    match interrupted {
        Some(e) => Err(e),
        None => Ok(result),
    }
}
