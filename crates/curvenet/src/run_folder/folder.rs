//! The run folder itself: one run at a time ([`FolderLock`], an OS-level lock on
//! [`LOCK_FILE`], taken by [`claim`]), a fresh run starting clean ([`fresh_start`]), and the
//! temporary files a killed run left ([`remove_stale_temp_files`], which a resumed run's
//! [`claim`] calls).
//!
//! A folder is a *curvenet run* when it holds `result.json` or `network.json` and nothing but
//! the files and folders a run writes ([`RUN_FILES`], [`RUN_FOLDERS`]). A fresh run into one
//! removes the earlier run's files first, so no stale iteration, mode, state, answer or picture
//! is left beside the new run's. A non-empty folder that is not a run is refused unless the
//! caller forces it (then the run's own files are replaced and the others kept).

use crate::words::{Message, Opt, given, message};
use std::fs::{File, OpenOptions, TryLockError};
use std::path::{Path, PathBuf};

/// The file a run holds locked in its folder while it writes there. It stays in the folder
/// (removing it would let two runs lock two different files).
pub const LOCK_FILE: &str = ".curvenet.lock";

/// The files a run (its pictures, viewer page and fabrication table included) writes at the
/// top of its folder.
pub const RUN_FILES: &[&str] = &[
    "result.json",
    "timings.json",
    "network.json",
    "final.obj",
    "answer.obj",
    "mesh.obj",
    "summary.txt",
    "viewer.html",
    "final.png",
    "mode.png",
    "lambda.png",
    "fabrication.csv",
    "before.obj",
    "slide.png",
];

/// The folders a run writes (with `export/`, what `curvenet export` writes by default).
pub const RUN_FOLDERS: &[&str] = &[
    crate::run_layout::MODES,
    crate::run_layout::STATES,
    crate::run_layout::ITERATIONS,
    "export",
    "slide",
    crate::run_layout::ROUNDS,
];

/// Why a folder cannot take a run.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{}", self.message())]
pub enum FolderError {
    /// Another process holds the folder's lock (a run is writing there).
    Held(PathBuf),
    /// The folder is not empty and not a curvenet run: what it holds (the first entries).
    NotARun {
        /// The folder.
        dir: PathBuf,
        /// Entries that are no run's, sorted (at most a few).
        foreign: Vec<String>,
    },
    /// A file system error, with the path.
    Io(String),
}

impl FolderError {
    /// What went wrong and the options that help, for a front end to spell (the folder is
    /// named as the run's folder option).
    pub fn message(&self) -> Message {
        match self {
            FolderError::Held(dir) => message![
                given(Opt::Out, dir.display()),
                ": another curvenet run is writing in this folder; wait for it to end or give \
                 another ",
                Opt::Out
            ],
            FolderError::NotARun { dir, foreign } => message![
                given(Opt::Out, dir.display()),
                format!(
                    ": the folder is not empty and is not a curvenet run's (it holds {}); give an \
                     empty or new folder, or ",
                    foreign.join(", ")
                ),
                Opt::Force,
                " to run there anyway (the run's own files are replaced, the others kept)"
            ],
            FolderError::Io(m) => Message::from(m.as_str()),
        }
    }
}

/// The folder's lock, held while alive (the operating system releases it when the process
/// ends, however it ends).
#[derive(Debug)]
pub struct FolderLock {
    _file: Option<File>,
    /// Set when the file system cannot lock files: the run goes on unprotected.
    pub warning: Option<String>,
}

impl FolderLock {
    /// Locks `dir` (which must exist) for this process.
    ///
    /// # Errors
    ///
    /// [`FolderError::Held`] when another process holds it; [`FolderError::Io`] when the lock
    /// file cannot be opened.
    pub fn acquire(dir: &Path) -> Result<FolderLock, FolderError> {
        Self::take(dir, false)
    }

    /// Locks `dir` (which must exist) for a command that reads a finished run and writes
    /// beside it (`curvenet view`, `export`): any number of them at once, never beside a run
    /// (which holds the lock alone).
    ///
    /// # Errors
    ///
    /// As [`Self::acquire`].
    pub fn acquire_shared(dir: &Path) -> Result<FolderLock, FolderError> {
        Self::take(dir, true)
    }

    /// [`Self::acquire_shared`] for a command that reads a finished run and writes beside it,
    /// held while it writes: `None` for a folder that cannot be locked (read-only, say: no
    /// run writes there either).
    ///
    /// # Errors
    ///
    /// A run is writing in the folder ([`FolderError::Held`]).
    pub fn hold_shared(dir: &Path) -> Result<Option<FolderLock>, FolderError> {
        match Self::acquire_shared(dir) {
            Ok(lock) => Ok(Some(lock)),
            Err(e @ FolderError::Held(_)) => Err(e),
            Err(_) => Ok(None),
        }
    }

    fn take(dir: &Path, shared: bool) -> Result<FolderLock, FolderError> {
        let path = dir.join(LOCK_FILE);
        let file = OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .map_err(|e| FolderError::Io(format!("{}: {e}", path.display())))?;
        let locked = if shared {
            file.try_lock_shared()
        } else {
            file.try_lock()
        };
        match locked {
            Ok(()) => Ok(FolderLock {
                _file: Some(file),
                warning: None,
            }),
            Err(TryLockError::WouldBlock) => Err(FolderError::Held(dir.to_path_buf())),
            Err(TryLockError::Error(e)) => Ok(FolderLock {
                _file: None,
                warning: Some(format!(
                    "{}: the folder cannot be locked ({e}): nothing stops another run from \
                     writing there at the same time",
                    dir.display()
                )),
            }),
        }
    }
}

/// Whether `name` is a temporary file of an atomic write ([`crate::io::write_atomic`]:
/// `.NAME.tmp.PID.N`).
fn is_temp(name: &str) -> bool {
    name.starts_with('.') && name.contains(".tmp.")
}

/// The names in `dir` (none when it does not exist).
fn entries(dir: &Path) -> Result<Vec<String>, FolderError> {
    let read = match std::fs::read_dir(dir) {
        Ok(r) => r,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(FolderError::Io(format!("{}: {e}", dir.display()))),
    };
    let mut names = Vec::new();
    for e in read {
        let e = e.map_err(|e| FolderError::Io(format!("{}: {e}", dir.display())))?;
        names.push(e.file_name().to_string_lossy().into_owned());
    }
    names.sort();
    Ok(names)
}

fn remove(path: &Path) -> Result<(), FolderError> {
    let r = if path.is_dir() {
        std::fs::remove_dir_all(path)
    } else {
        std::fs::remove_file(path)
    };
    match r {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(FolderError::Io(format!(
            "{}: cannot remove it: {e}",
            path.display()
        ))),
    }
}

/// Removes the temporary files of atomic writes a killed run left in `dir` and its
/// sub-folders; returns how many there were. Call it only while holding the folder's lock
/// (no other run is writing them).
///
/// # Errors
///
/// A file that cannot be listed or removed.
pub fn remove_stale_temp_files(dir: &Path) -> Result<usize, FolderError> {
    let mut n = 0;
    for sub in std::iter::once("").chain(RUN_FOLDERS.iter().copied()) {
        let d = dir.join(sub);
        for name in entries(&d)? {
            if is_temp(&name) {
                remove(&d.join(&name))?;
                n += 1;
            }
        }
    }
    Ok(n)
}

/// A run's hold on its folder: the lock, and how many temporary files a stopped run had left
/// there (removed).
#[derive(Debug)]
pub struct Claim {
    /// Held to the end of the run.
    pub lock: FolderLock,
    /// The temporary files removed (a resumed run's only).
    pub stale_temp_files: usize,
}

/// Locks `dir` (which must exist) for a run; when the run resumes the one recorded there,
/// also removes the temporary files a stopped run left (under the lock, so none is another
/// run's). The command line and the Python binding both start their runs here.
///
/// # Errors
///
/// As [`FolderLock::acquire`] and [`remove_stale_temp_files`].
pub fn claim(dir: &Path, resume: bool) -> Result<Claim, FolderError> {
    let lock = FolderLock::acquire(dir)?;
    let stale_temp_files = if resume {
        remove_stale_temp_files(dir)?
    } else {
        0
    };
    Ok(Claim {
        lock,
        stale_temp_files,
    })
}

/// What a fresh run removes from its folder first ([`fresh_start`]), to be done with
/// [`FreshStart::apply`] once the run is about to write.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FreshStart {
    dir: PathBuf,
    remove: Vec<String>,
}

/// `alternative-N.obj` or `alternative-N.csv`: an alternative's files (`--alternatives`).
fn is_alternative(name: &str) -> bool {
    name.strip_prefix("alternative-")
        .and_then(|r| r.strip_suffix(".obj").or_else(|| r.strip_suffix(".csv")))
        .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
}

/// Checks `dir` (locked by this process; absent or empty is fine) for a fresh run: a curvenet
/// run's folder is to have the earlier run's files removed; any other non-empty folder is
/// refused unless `force` (then the run's own files are removed and the others kept).
/// Nothing is removed yet.
///
/// # Errors
///
/// [`FolderError::NotARun`] for a foreign non-empty folder without `force`;
/// [`FolderError::Io`] when the folder cannot be listed.
pub fn fresh_start(dir: &Path, force: bool) -> Result<FreshStart, FolderError> {
    let names: Vec<String> = entries(dir)?
        .into_iter()
        .filter(|n| n != LOCK_FILE)
        .collect();
    let ours = |n: &String| {
        RUN_FILES.contains(&n.as_str())
            || RUN_FOLDERS.contains(&n.as_str())
            || is_temp(n)
            || is_alternative(n)
    };
    let foreign: Vec<String> = names.iter().filter(|n| !ours(n)).cloned().collect();
    let is_run = names
        .iter()
        .any(|n| n == "result.json" || n == "network.json");
    if !names.is_empty() && !force && (!is_run || !foreign.is_empty()) {
        const SHOWN: usize = 5;
        let listed = if foreign.is_empty() { &names } else { &foreign };
        let mut shown: Vec<String> = listed.iter().take(SHOWN).cloned().collect();
        if listed.len() > SHOWN {
            shown.push(format!("and {} more", listed.len() - SHOWN));
        }
        return Err(FolderError::NotARun {
            dir: dir.to_path_buf(),
            foreign: shown,
        });
    }
    Ok(FreshStart {
        dir: dir.to_path_buf(),
        remove: names.into_iter().filter(|n| ours(n)).collect(),
    })
}

impl FreshStart {
    /// Removes the earlier run's files; a note saying so when there were any.
    ///
    /// # Errors
    ///
    /// A file or folder that cannot be removed.
    pub fn apply(&self) -> Result<Option<String>, FolderError> {
        for n in &self.remove {
            remove(&self.dir.join(n))?;
        }
        Ok((!self.remove.is_empty()).then(|| {
            format!(
                "{}: a fresh run: the earlier run's files there were removed ({})",
                self.dir.display(),
                self.remove.join(", ")
            )
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("curvenet-folder-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn shared_locks_share_the_folder_and_keep_a_run_out() {
        let d = tmp("shared");
        let a = FolderLock::acquire_shared(&d).expect("first reader");
        let b = FolderLock::acquire_shared(&d).expect("second reader");
        assert!(matches!(FolderLock::acquire(&d), Err(FolderError::Held(_))));
        drop((a, b));
        let run = FolderLock::acquire(&d).expect("the run");
        assert!(matches!(
            FolderLock::acquire_shared(&d),
            Err(FolderError::Held(_))
        ));
        drop(run);
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_second_lock_on_a_folder_is_refused_until_the_first_is_dropped() {
        let d = tmp("lock");
        let first = FolderLock::acquire(&d).unwrap();
        assert!(first.warning.is_none());
        assert_eq!(
            FolderLock::acquire(&d).unwrap_err(),
            FolderError::Held(d.clone())
        );
        drop(first);
        assert!(FolderLock::acquire(&d).is_ok());
        // A claim is the same lock; a resuming one removes the temporary files left there.
        std::fs::write(d.join(".result.json.tmp.7.0"), "x").unwrap();
        let held = claim(&d, false).unwrap();
        assert_eq!(held.stale_temp_files, 0);
        assert!(d.join(".result.json.tmp.7.0").exists());
        assert_eq!(claim(&d, true).unwrap_err(), FolderError::Held(d.clone()));
        drop(held);
        assert_eq!(claim(&d, true).unwrap().stale_temp_files, 1);
        assert!(!d.join(".result.json.tmp.7.0").exists());
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn old_runs_start_clean_foreign_folders_need_force_temp_files_go() {
        let d = tmp("clean");
        assert_eq!(fresh_start(&d, false).unwrap().apply(), Ok(None));
        for f in ["result.json", "answer.obj", ".result.json.tmp.7.0"] {
            std::fs::write(d.join(f), "x").unwrap();
        }
        std::fs::create_dir_all(d.join("iterations")).unwrap();
        std::fs::write(d.join("iterations/0099.obj"), "x").unwrap();
        std::fs::write(d.join("iterations/.0003.obj.tmp.7.1"), "x").unwrap();
        assert_eq!(remove_stale_temp_files(&d), Ok(2));
        assert!(d.join("answer.obj").exists());
        assert!(fresh_start(&d, false).unwrap().apply().unwrap().is_some());
        assert_eq!(entries(&d).unwrap(), Vec::<String>::new());

        std::fs::write(d.join("notes.txt"), "mine").unwrap();
        std::fs::write(d.join("final.png"), "x").unwrap();
        match fresh_start(&d, false) {
            Err(FolderError::NotARun { foreign, .. }) => {
                assert_eq!(foreign, vec!["notes.txt".to_string()]);
            }
            other => panic!("{other:?}"),
        }
        assert!(fresh_start(&d, true).unwrap().apply().unwrap().is_some());
        assert_eq!(entries(&d).unwrap(), vec!["notes.txt".to_string()]);
        let _ = std::fs::remove_dir_all(&d);
    }
}
