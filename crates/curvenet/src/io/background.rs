//! Files written atomically, in order, on a background thread.
//!
//! A greedy run saves every iteration as it goes (states, modes, curves, `result.json`, the
//! carried test vectors): each file through [`write_atomic`], a temporary file synced to disk
//! and renamed; on the computing thread the greedy would wait for the disk.
//! [`BackgroundWriter`] hands them to a thread of its own, which writes them one after the
//! other in the order submitted, so the folder on disk always holds a prefix of what was
//! submitted: `result.json` never names an iteration whose files are not there yet.
//!
//! The queue is bounded ([`QUEUE`] files): a computation that outruns the disk waits
//! instead of piling up memory. The first failed write stops all later ones (they could
//! refer to the missing file) and is reported by the next [`BackgroundWriter::submit`] or
//! [`BackgroundWriter::flush`]. Dropping the writer writes everything still queued first,
//! so a run stopped by an error or a cancellation loses nothing it submitted.
//!
//! The thread runs in the idle scheduling class ([`crate::priority`]): it writes in the
//! computation's gaps, and when it falls behind, the bounded queue makes the computation wait
//! for it.

use super::write_atomic;
use std::path::PathBuf;
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

/// Files the queue holds before [`BackgroundWriter::submit`] waits (a greedy iteration
/// submits five or six).
const QUEUE: usize = 16;

/// Bytes to be made on the writer thread (such as a file's text, formatted there rather than
/// on the computing thread), or why they could not be.
type MakeBytes = Box<dyn FnOnce() -> Result<Vec<u8>, String> + Send>;

/// What the writer thread is asked to do.
enum Job {
    /// Write these bytes to this path (atomically).
    Write(PathBuf, Vec<u8>),
    /// Make the bytes, then write them to this path (atomically).
    Make(PathBuf, MakeBytes),
    /// Signal back once every earlier job is done.
    Flush(SyncSender<()>),
}

/// The first failure of the writer thread, shared with the submitting side.
type Failure = Arc<Mutex<Option<WriteError>>>;

/// Why the background writer stopped writing.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum WriteError {
    /// A file could not be written: its path and the system's reason.
    #[error("{}: {reason}", path.display())]
    Failed {
        /// The file.
        path: PathBuf,
        /// What the system said.
        reason: String,
    },
    /// The writer thread stopped unexpectedly.
    #[error("the output writer thread stopped unexpectedly")]
    Stopped,
}

/// Writes files atomically and in order on a thread of its own (see the module docs).
#[derive(Debug)]
pub struct BackgroundWriter {
    jobs: Option<SyncSender<Job>>,
    thread: Option<JoinHandle<()>>,
    failed: Failure,
}

impl BackgroundWriter {
    /// Starts the writer thread.
    pub fn new() -> std::io::Result<Self> {
        let (jobs, queue) = sync_channel(QUEUE);
        let failed: Failure = Arc::default();
        let shared = failed.clone();
        let thread = std::thread::Builder::new()
            .name("curvenet-writer".into())
            .spawn(move || {
                // Files wait; the computation that submits them does not.
                crate::priority::idle_priority();
                run(queue, shared)
            })?;
        Ok(BackgroundWriter {
            jobs: Some(jobs),
            thread: Some(thread),
            failed,
        })
    }

    /// Queues `bytes` to be written to `path`, after everything submitted before. Waits while
    /// the queue is full. An error if an earlier write failed (nothing more is written).
    pub fn submit(&self, path: PathBuf, bytes: Vec<u8>) -> Result<(), WriteError> {
        self.check()?;
        self.send(Job::Write(path, bytes))
    }

    /// [`Self::submit`] of the bytes `make` returns, called on the writer thread (after the
    /// writes submitted before): the work of making them stays off the submitting thread. An
    /// error from `make` stops the writer as a failed write does.
    pub fn submit_with(
        &self,
        path: PathBuf,
        make: impl FnOnce() -> Result<Vec<u8>, String> + Send + 'static,
    ) -> Result<(), WriteError> {
        self.check()?;
        self.send(Job::Make(path, Box::new(make)))
    }

    /// Waits until everything submitted so far is on disk; an error if any write failed.
    pub fn flush(&self) -> Result<(), WriteError> {
        let (done, wait) = sync_channel(1);
        self.send(Job::Flush(done))?;
        wait.recv().map_err(|_| WriteError::Stopped)?;
        self.check()
    }

    fn send(&self, job: Job) -> Result<(), WriteError> {
        self.jobs
            .as_ref()
            .ok_or(WriteError::Stopped)?
            .send(job)
            .map_err(|_| WriteError::Stopped)
    }

    fn check(&self) -> Result<(), WriteError> {
        match self.failed.lock() {
            Ok(f) => f.clone().map_or(Ok(()), Err),
            Err(_) => Err(WriteError::Stopped),
        }
    }
}

impl Drop for BackgroundWriter {
    /// Writes everything still queued, then stops the thread.
    fn drop(&mut self) {
        drop(self.jobs.take());
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The writer thread: jobs in order until the submitting side hangs up; after a failure, the
/// later writes are skipped (flushes still answer).
fn run(queue: Receiver<Job>, failed: Failure) {
    let mut ok = true;
    for job in queue {
        let (path, bytes) = match job {
            Job::Flush(done) => {
                let _ = done.send(());
                continue;
            }
            _ if !ok => continue,
            Job::Write(path, bytes) => (path, Ok(bytes)),
            Job::Make(path, make) => {
                let bytes = make();
                (path, bytes)
            }
        };
        let written = bytes.and_then(|b| write_atomic(&path, &b).map_err(|e| e.to_string()));
        if let Err(reason) = written {
            ok = false;
            if let Ok(mut f) = failed.lock() {
                *f = Some(WriteError::Failed { reason, path });
            }
        }
    }
}
