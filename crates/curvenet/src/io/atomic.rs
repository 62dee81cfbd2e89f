//! Atomic writes ([`write_atomic`]) and the temporary files they have in flight.
//!
//! Every output goes to a temporary file next to its target (`.NAME.tmp.PID.N`), synced and
//! then renamed over the target. While a write is in flight its temporary file is listed here,
//! so that a process ending at once (a signal outside the stages that poll for cancellation)
//! removes it first ([`exit_removing_temp_files`]): the target keeps its old content or has the
//! new one whole, and no temporary file is left behind.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError, RwLock, RwLockReadGuard};

/// The temporary files of the atomic writes in flight.
static IN_FLIGHT: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The list of temporary files in flight, locked.
fn in_flight() -> MutexGuard<'static, Vec<PathBuf>> {
    IN_FLIGHT.lock().unwrap_or_else(PoisonError::into_inner)
}

/// A temporary file, listed in [`IN_FLIGHT`] while this is alive.
#[derive(Debug)]
struct InFlight(PathBuf);

impl InFlight {
    fn list(path: PathBuf) -> Self {
        in_flight().push(path.clone());
        InFlight(path)
    }
}

impl Drop for InFlight {
    fn drop(&mut self) {
        let mut list = in_flight();
        if let Some(i) = list.iter().position(|p| *p == self.0) {
            list.swap_remove(i);
        }
    }
}

/// Held by the steps that must not be cut in two ([`hold_exit`]).
static EXIT_HOLDS: RwLock<()> = RwLock::new(());

/// While alive, [`exit_removing_temp_files`] waits: the process ends after the step it covers,
/// not inside it.
#[must_use = "the exit waits only while the hold is alive"]
#[derive(Debug)]
pub struct ExitHold {
    _read: RwLockReadGuard<'static, ()>,
}

/// Holds [`exit_removing_temp_files`] off until the returned guard drops: for a step of
/// several file operations that leaves a folder whole only once it is complete (such as
/// swapping one run's files for another's). Holds may overlap; one started after the exit has
/// begun waits for ever (the process ends first).
pub fn hold_exit() -> ExitHold {
    ExitHold {
        _read: EXIT_HOLDS.read().unwrap_or_else(PoisonError::into_inner),
    }
}

/// Ends the process with `code` once the steps under [`hold_exit`] have ended and the
/// temporary files of the atomic writes in flight are removed. A write that starts or ends
/// meanwhile waits for the end, so none is left behind (its target keeps what it had).
pub fn exit_removing_temp_files(code: i32) -> ! {
    // Kept locked until the process ends, like the list below.
    let _holds = EXIT_HOLDS.write().unwrap_or_else(PoisonError::into_inner);
    let list = in_flight();
    for p in list.iter() {
        // Best effort: a file already renamed into place is gone under this name.
        let _ = fs::remove_file(p);
    }
    // The list stays locked until the process ends (exit runs no destructor).
    std::process::exit(code)
}

/// Distinguishes the temporary files of one process.
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `bytes` to `path` atomically: the data go to a temporary file in the same directory
/// (named after the target, the process id and a counter), are flushed to disk, and the
/// temporary file is then renamed over `path`. Readers see either the old or the new content,
/// never a mix; on failure the temporary file is removed and `path` is left as it was.
///
/// When `path` already exists its permissions are carried over to the new file. A symbolic link
/// at `path` is replaced by a regular file.
///
/// # Errors
///
/// Any I/O error of creating, writing, syncing or renaming the temporary file, and
/// [`std::io::ErrorKind::InvalidInput`] when `path` has no file name (such as `/` or `..`).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    stage_atomic(path, bytes)?.commit()
}

/// A file written and synced under its temporary name next to its target, not yet in place:
/// [`Staged::commit`] renames it over the target. Dropped uncommitted, its temporary file is
/// removed and the target keeps what it had. It lets a slow write overlap other work while
/// the file still takes its place after them (e.g. a page that marks a stage complete).
#[derive(Debug)]
pub struct Staged {
    temp: InFlight,
    path: PathBuf,
    dir: PathBuf,
    committed: bool,
}

/// The first half of [`write_atomic`]: `bytes` written and synced to a temporary file next to
/// `path`, which [`Staged::commit`] puts in place.
///
/// # Errors
///
/// As [`write_atomic`], but for the rename.
pub fn stage_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<Staged> {
    begin_atomic(path)?.write(bytes)
}

/// A temporary file created next to its target, still empty: [`Begun::write`] fills and syncs
/// it. Dropped, its temporary file is removed. It lets a writer name its temporary file before
/// the slow part of a write (`io::background`, whose relief removes a temporary file the
/// writer it relieves was filling).
#[derive(Debug)]
pub(crate) struct Begun {
    staged: Staged,
    file: fs::File,
}

/// The temporary file of an atomic write to `path`, created and listed as in flight.
///
/// # Errors
///
/// As [`write_atomic`]'s creating the temporary file.
pub(crate) fn begin_atomic(path: &Path) -> std::io::Result<Begun> {
    let name = path.file_name().ok_or_else(|| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("{} does not name a file", path.display()),
        )
    })?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    // A long target name is cut so that the temporary name stays within file-name limits.
    let stem: String = name.to_string_lossy().chars().take(100).collect();
    let (temp, file) = create_temp(&dir, &stem)?;
    Ok(Begun {
        staged: Staged {
            temp,
            path: path.to_path_buf(),
            dir,
            committed: false,
        },
        file,
    })
}

impl Begun {
    /// The temporary file's path.
    pub fn temp_path(&self) -> &Path {
        &self.staged.temp.0
    }

    /// Writes `bytes` to the temporary file (with the target's permissions when it exists) and
    /// syncs it.
    ///
    /// # Errors
    ///
    /// Writing, setting the permissions or syncing fails (the temporary file is then removed).
    pub fn write(mut self, bytes: &[u8]) -> std::io::Result<Staged> {
        self.file.write_all(bytes)?;
        if let Ok(meta) = fs::metadata(&self.staged.path) {
            self.file.set_permissions(meta.permissions())?;
        }
        self.file.sync_all()?;
        Ok(self.staged)
    }
}

impl Staged {
    /// Renames the temporary file over the target and syncs its folder's entry.
    ///
    /// # Errors
    ///
    /// The rename fails (the temporary file is then removed).
    pub fn commit(self) -> std::io::Result<()> {
        let dir = self.rename()?;
        sync_dir(&dir);
        Ok(())
    }

    /// [`Self::commit`] without syncing the folder's entry: the folder to pass to
    /// [`sync_dir`] afterwards (a rename is quick; the sync waits for the disk).
    ///
    /// # Errors
    ///
    /// The rename fails (the temporary file is then removed).
    pub(crate) fn rename(mut self) -> std::io::Result<PathBuf> {
        fs::rename(&self.temp.0, &self.path)?;
        self.committed = true;
        Ok(std::mem::take(&mut self.dir))
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if !self.committed {
            // Best effort: the error that stopped the write is the one worth reporting.
            let _ = fs::remove_file(&self.temp.0);
        }
    }
}

/// Creates a fresh temporary file next to the target, listed as in flight, retrying on name
/// clashes (for example with a file left by a crashed process that had the same id).
fn create_temp(dir: &Path, name: &str) -> std::io::Result<(InFlight, fs::File)> {
    let pid = std::process::id();
    let mut last_err = None;
    for _ in 0..64 {
        let n = TEMP_COUNTER.fetch_add(1, Ordering::Relaxed);
        // Listed before it exists, so that no moment of its life goes unlisted.
        let temp = InFlight::list(dir.join(format!(".{name}.tmp.{pid}.{n}")));
        match fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temp.0)
        {
            Ok(f) => return Ok((temp, f)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last_err = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last_err.unwrap_or_else(|| {
        std::io::Error::new(
            std::io::ErrorKind::AlreadyExists,
            "could not find a free temporary file name",
        )
    }))
}

/// Flushes the directory entry of a rename to disk where the platform allows it (best effort:
/// some file systems and platforms cannot open or sync directories).
pub(crate) fn sync_dir(dir: &Path) {
    #[cfg(unix)]
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn listed(p: &Path) -> bool {
        in_flight().iter().any(|q| q == p)
    }

    #[test]
    fn a_temporary_file_is_listed_while_its_write_is_in_flight() {
        let dir = std::env::temp_dir().join(format!("curvenet-in-flight-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let (temp, file) = create_temp(&dir, "target.txt").unwrap();
        let tmp = temp.0.clone();
        assert!(tmp.is_file() && listed(&tmp));
        drop(file);
        fs::remove_file(&tmp).unwrap();
        drop(temp);
        assert!(!listed(&tmp));
        // A finished write leaves nothing listed under its target's name.
        write_atomic(&dir.join("target.txt"), b"x").unwrap();
        let prefix = dir.join(".target.txt.tmp.");
        assert!(
            !in_flight()
                .iter()
                .any(|p| p.to_string_lossy().starts_with(&*prefix.to_string_lossy()))
        );
        let _ = fs::remove_dir_all(&dir);
    }

    /// Run twice: by the test harness, and as a child process of that run (this test binary
    /// again, with the marker's path in the environment), which holds the exit, asks for it
    /// from another thread, and writes the marker before it lets go.
    #[test]
    fn the_exit_waits_for_the_steps_that_hold_it() {
        const CHILD: &str = "CURVENET_TEST_EXIT_HOLD_MARKER";
        const NAME: &str = "io::atomic::tests::the_exit_waits_for_the_steps_that_hold_it";
        if let Some(marker) = std::env::var_os(CHILD) {
            let hold = hold_exit();
            std::thread::spawn(|| {
                exit_removing_temp_files(3);
            });
            std::thread::sleep(std::time::Duration::from_millis(300));
            fs::write(marker, "written under the hold").unwrap();
            drop(hold);
            loop {
                std::thread::park();
            }
        }
        let dir = std::env::temp_dir().join(format!("curvenet-exit-hold-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let marker = dir.join("marker");
        let status = std::process::Command::new(std::env::current_exe().unwrap())
            .args(["--exact", NAME, "--test-threads=1"])
            .env(CHILD, &marker)
            .stdout(std::process::Stdio::null())
            .status()
            .unwrap();
        assert_eq!(status.code(), Some(3));
        assert_eq!(
            fs::read_to_string(&marker).unwrap(),
            "written under the hold"
        );
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_staged_file_takes_its_place_only_when_committed() {
        let dir = std::env::temp_dir().join(format!("curvenet-staged-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let target = dir.join("page.html");
        fs::write(&target, "old").unwrap();
        let temps = || {
            fs::read_dir(&dir)
                .unwrap()
                .filter(|e| {
                    e.as_ref()
                        .unwrap()
                        .file_name()
                        .to_string_lossy()
                        .contains(".tmp.")
                })
                .count()
        };
        // Dropped uncommitted: the target keeps what it had, and no temporary file is left.
        let staged = stage_atomic(&target, b"new").unwrap();
        assert_eq!(temps(), 1);
        assert_eq!(fs::read_to_string(&target).unwrap(), "old");
        drop(staged);
        assert_eq!(temps(), 0);
        assert_eq!(fs::read_to_string(&target).unwrap(), "old");
        // Committed: the new content is in place.
        stage_atomic(&target, b"new").unwrap().commit().unwrap();
        assert_eq!(temps(), 0);
        assert_eq!(fs::read_to_string(&target).unwrap(), "new");
        assert!(in_flight().iter().all(|p| !p.starts_with(&dir)));
        let _ = fs::remove_dir_all(&dir);
    }
}

/// Why a file cannot be written where asked ([`check_writable`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum Unwritable {
    /// The path is a folder.
    #[error("{}: is a folder; give a file name", .0.display())]
    Folder(PathBuf),
    /// The folder it would be written in does not exist.
    #[error("{}: the folder {} does not exist", path.display(), folder.display())]
    NoFolder {
        /// The file asked for.
        path: PathBuf,
        /// Its folder.
        folder: PathBuf,
    },
}

/// Checks, before any work, that a file can be written at `path`: not a folder, in a folder
/// that exists.
pub fn check_writable(path: &Path) -> Result<(), Unwritable> {
    if path.is_dir() {
        return Err(Unwritable::Folder(path.to_path_buf()));
    }
    let folder = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !folder.is_dir() {
        return Err(Unwritable::NoFolder {
            path: path.to_path_buf(),
            folder: folder.to_path_buf(),
        });
    }
    Ok(())
}
