//! Files written atomically, in order, on a background thread.
//!
//! A greedy run saves every iteration as it goes (states, modes, curves, `result.json`, the
//! carried test vectors): each file through [`super::write_atomic`]'s steps, a temporary file
//! synced to disk and renamed; on the computing thread the greedy would wait for the disk.
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
//! **Priority.** Saving costs CPU time (the kernel's copies and syncs, formatting the text
//! files: about 0.46 s over the shell's run), which a writer at the computation's priority
//! takes from the greedy. The writer therefore runs at the lowest priority
//! ([`crate::priority`]), in the computation's gaps. But the computation must never wait for a
//! low-priority thread: while other programs keep every core busy it gets almost no CPU time
//! (with the writer in Linux's idle class and nothing else, `curvenet example tower` took
//! 37.9 s against `bench`'s 5.5 s while a build kept both cores busy, its greedy waiting on
//! the full queue). So whenever the computation would wait for the writer (a full queue, a
//! flush, the end), a *relief* thread at the computation's priority takes the writing over for
//! good: it writes again the file the writer has in hand (removing the writer's temporary
//! file: the writer puts nothing in place once relieved) and then the rest, in order. The
//! writer names its temporary file and puts a file in place only under the lock the relief
//! takes over with, and its bytes are a pure function of what was submitted, so the two never
//! both put a file in place and the folder keeps a prefix of the run's files either way.

use super::atomic::{begin_atomic, sync_dir, write_atomic};
use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;

/// Files the queue holds before [`BackgroundWriter::submit`] waits (a greedy iteration
/// submits five or six).
const QUEUE: usize = 16;

/// Bytes made off the computing thread (such as a file's text), or why they could not be: a
/// pure function of what it captured (the relief may make them again).
type MakeBytes = Box<dyn Fn() -> Result<Vec<u8>, String> + Send + Sync>;

/// A file's bytes: given, or to be made by the thread that writes it.
enum Bytes {
    Given(Vec<u8>),
    Made(MakeBytes),
}

/// A submitted file (shared: the relief writes again the one the writer had in hand).
struct File {
    path: PathBuf,
    bytes: Bytes,
}

impl File {
    /// Its bytes, or why they could not be made (a panic of the function making them
    /// included: it fails this file instead of leaving a thread dead and a flush waiting).
    fn bytes(&self) -> Result<std::borrow::Cow<'_, [u8]>, String> {
        match &self.bytes {
            Bytes::Given(b) => Ok(std::borrow::Cow::Borrowed(b)),
            Bytes::Made(make) => std::panic::catch_unwind(std::panic::AssertUnwindSafe(make))
                .unwrap_or_else(|_| Err("its content could not be made (an internal error)".into()))
                .map(std::borrow::Cow::Owned),
        }
    }

    /// The failure of writing it.
    fn failure(&self, reason: String) -> WriteError {
        WriteError::Failed {
            path: self.path.clone(),
            reason,
        }
    }
}

/// The file the low-priority writer is writing, and the temporary file it fills.
struct InHand {
    file: Arc<File>,
    temp: PathBuf,
}

/// What the submitting side and the two threads share (under [`Shared::lock`]).
#[derive(Default)]
struct State {
    /// Submitted files not yet taken, in order.
    queue: VecDeque<Arc<File>>,
    /// The low-priority writer's file, between naming its temporary file and putting it in
    /// place.
    in_hand: Option<InHand>,
    /// Whether the relief has taken the writing over.
    relieved: bool,
    /// The relief thread, once started.
    relief: Option<JoinHandle<()>>,
    /// No more files will be submitted.
    closed: bool,
    /// The first failure: later files are skipped.
    failed: Option<WriteError>,
    /// Files submitted, and files done with (written, failed or skipped), in order.
    submitted: u64,
    finished: u64,
}

impl State {
    /// Done with one more file: written, or failed with `failure`.
    fn finish(&mut self, failure: Option<WriteError>) {
        if self.failed.is_none() {
            self.failed = failure;
        }
        self.finished += 1;
    }
}

/// The shared state and its condition variable (signalled on every change).
#[derive(Default)]
struct Shared {
    state: Mutex<State>,
    changed: Condvar,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    fn wait<'a>(&self, state: MutexGuard<'a, State>) -> MutexGuard<'a, State> {
        self.changed
            .wait(state)
            .unwrap_or_else(PoisonError::into_inner)
    }
}

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
}

/// Writes files atomically and in order on a thread of its own (see the module docs).
pub struct BackgroundWriter {
    shared: Arc<Shared>,
}

impl std::fmt::Debug for BackgroundWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = self.shared.lock();
        f.debug_struct("BackgroundWriter")
            .field("submitted", &s.submitted)
            .field("finished", &s.finished)
            .field("relieved", &s.relieved)
            .finish()
    }
}

impl BackgroundWriter {
    /// Starts the (low-priority) writer thread.
    pub fn new() -> std::io::Result<Self> {
        let shared = Arc::new(Shared::default());
        let theirs = Arc::clone(&shared);
        // Detached: nothing waits for it (module docs); it ends once relieved or closed.
        std::thread::Builder::new()
            .name("curvenet-writer".into())
            .spawn(move || write_in_the_gaps(&theirs))?;
        Ok(BackgroundWriter { shared })
    }

    /// Queues `bytes` to be written to `path`, after everything submitted before. Waits while
    /// the queue is full. An error if an earlier write failed (nothing more is written).
    pub fn submit(&self, path: PathBuf, bytes: Vec<u8>) -> Result<(), WriteError> {
        self.send(File {
            path,
            bytes: Bytes::Given(bytes),
        })
    }

    /// [`Self::submit`] of the bytes `make` returns, made by the thread that writes them: the
    /// work of making them stays off the submitting thread. `make` must be a pure function of
    /// what it captured (it may be called twice). An error from `make` stops the writer as a
    /// failed write does.
    pub fn submit_with(
        &self,
        path: PathBuf,
        make: impl Fn() -> Result<Vec<u8>, String> + Send + Sync + 'static,
    ) -> Result<(), WriteError> {
        self.send(File {
            path,
            bytes: Bytes::Made(Box::new(make)),
        })
    }

    /// Waits until everything submitted so far is on disk; an error if any write failed.
    pub fn flush(&self) -> Result<(), WriteError> {
        let mut state = self.shared.lock();
        let target = state.submitted;
        if state.finished < target {
            self.relieve(&mut state);
        }
        while state.finished < target {
            state = self.shared.wait(state);
        }
        state.failed.clone().map_or(Ok(()), Err)
    }

    fn send(&self, file: File) -> Result<(), WriteError> {
        let mut state = self.shared.lock();
        loop {
            if let Some(e) = &state.failed {
                return Err(e.clone());
            }
            if state.queue.len() < QUEUE {
                break;
            }
            self.relieve(&mut state);
            state = self.shared.wait(state);
        }
        state.queue.push_back(Arc::new(file));
        state.submitted += 1;
        self.shared.changed.notify_all();
        Ok(())
    }

    /// Starts the relief (module docs) unless it runs already; the caller is about to wait.
    /// A relief that cannot start leaves the writing to the writer.
    fn relieve(&self, state: &mut State) {
        if state.relieved {
            return;
        }
        let theirs = Arc::clone(&self.shared);
        // Started by the computing thread, it runs at its priority.
        let started = std::thread::Builder::new()
            .name("curvenet-writer-relief".into())
            .spawn(move || relieve_the_writer(&theirs));
        if let Ok(handle) = started {
            state.relieved = true;
            state.relief = Some(handle);
            self.shared.changed.notify_all();
        }
    }
}

impl Drop for BackgroundWriter {
    /// Writes everything still queued (by the relief), then lets the threads end.
    fn drop(&mut self) {
        let relief = {
            let mut state = self.shared.lock();
            state.closed = true;
            if state.finished < state.submitted {
                self.relieve(&mut state);
            }
            self.shared.changed.notify_all();
            state.relief.take()
        };
        match relief {
            Some(relief) => {
                let _ = relief.join();
            }
            None => {
                // No relief (it could not start): wait for the writer itself.
                let mut state = self.shared.lock();
                while state.finished < state.submitted {
                    state = self.shared.wait(state);
                }
            }
        }
    }
}

/// The low-priority writer: files in order until relieved or closed. It names each file's
/// temporary file and puts the file in place under the lock, so that a relief taking over in
/// between knows the temporary file to remove and the file to write again.
fn write_in_the_gaps(shared: &Shared) {
    crate::priority::background_priority();
    loop {
        let (file, begun) = {
            let mut state = shared.lock();
            let file = loop {
                if state.relieved {
                    return;
                }
                if let Some(f) = state.queue.pop_front() {
                    break f;
                }
                if state.closed {
                    return;
                }
                state = shared.wait(state);
            };
            if state.failed.is_some() {
                state.finish(None);
                shared.changed.notify_all();
                continue;
            }
            match begin_atomic(&file.path) {
                Ok(begun) => {
                    state.in_hand = Some(InHand {
                        file: Arc::clone(&file),
                        temp: begun.temp_path().to_path_buf(),
                    });
                    (file, begun)
                }
                Err(e) => {
                    state.finish(Some(file.failure(e.to_string())));
                    shared.changed.notify_all();
                    continue;
                }
            }
        };
        // The slow part, unlocked.
        let staged = file
            .bytes()
            .and_then(|b| begun.write(&b).map_err(|e| e.to_string()));
        let mut state = shared.lock();
        if state.in_hand.take().is_none() {
            // Relieved meanwhile: the relief writes this file again and removed the
            // temporary one.
            return;
        }
        let placed = staged.and_then(|s| s.rename().map_err(|e| e.to_string()));
        let failure = placed.as_ref().err().map(|e| file.failure(e.clone()));
        state.finish(failure);
        shared.changed.notify_all();
        drop(state);
        if let Ok(dir) = placed {
            sync_dir(&dir);
        }
    }
}

/// The relief: the file the writer had in hand, then the rest, in order, until closed.
fn relieve_the_writer(shared: &Shared) {
    let mut next = shared.lock().in_hand.take().map(|h| {
        // Never to be put in place: the writer checks its file is still in hand first.
        let _ = std::fs::remove_file(&h.temp);
        h.file
    });
    loop {
        let file = match next.take() {
            Some(f) => f,
            None => {
                let mut state = shared.lock();
                loop {
                    if let Some(f) = state.queue.pop_front() {
                        break f;
                    }
                    if state.closed {
                        return;
                    }
                    state = shared.wait(state);
                }
            }
        };
        let skip = shared.lock().failed.is_some();
        let failure = if skip {
            None
        } else {
            file.bytes()
                .and_then(|b| write_atomic(&file.path, &b).map_err(|e| e.to_string()))
                .err()
                .map(|e| file.failure(e))
        };
        let mut state = shared.lock();
        state.finish(failure);
        shared.changed.notify_all();
    }
}
