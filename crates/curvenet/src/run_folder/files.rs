//! [`RunFiles`]: every read of a run folder's files goes through one, confined to a folder of
//! run folders ([`RunsRoot`]) or not ([`RunFiles::unconfined`]).
//!
//! A confined reader resolves each path it is asked for itself, one component at a time from
//! the root, and before it opens anything: `..` steps up only as far as the root, and a
//! symbolic link is read (the link itself, inside the root) and its target followed the same
//! way. A path that leads out of the root — by its own `..`s, as an absolute path elsewhere,
//! or through a link whose target lies outside — is refused the moment it does, before
//! anything outside is looked at: nothing outside the root is opened, listed or even tested
//! for existence, so the answer about a path outside never depends on what exists there.
//! Every file read this way is resolved afresh (not only the run folder), only a regular file
//! is read, and on Unix the file opened must be the one resolved (its device and inode), so a
//! link swapped in between is refused too.
//!
//! A confined reader's messages name a file by its path inside the root and never quote its
//! content: a file that does not parse is named with the line and column where it fails and
//! what it was expected to be. An unconfined reader (the command line's, reading the user's
//! own folders) names files by the path as given and adds the parser's own description.

use serde::de::DeserializeOwned;
use std::ffi::OsString;
use std::fmt;
use std::fs::{self, Metadata};
use std::io::Read;
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

/// The most symbolic links one path may pass through (as Linux's `MAXSYMLINKS`).
const MAX_LINKS: usize = 40;

/// What a confined reader does with a path, as its observer ([`RunsRoot::observed`]) is told.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// The path's own entry is examined (its type, or the target a link names), without
    /// following it.
    Look,
    /// The file is opened for reading.
    Open,
}

/// What an observer of a [`RunsRoot`] is called with: each path before it is looked at or
/// opened.
pub type Observer = Arc<dyn Fn(&Path, Access) + Send + Sync>;

/// A folder of run folders: the only place a confined [`RunFiles`] reads from.
#[derive(Clone)]
pub struct RunsRoot {
    root: PathBuf,
    observer: Option<Observer>,
}

impl fmt::Debug for RunsRoot {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RunsRoot")
            .field("root", &self.root)
            .field("observed", &self.observer.is_some())
            .finish()
    }
}

/// Why a file of a run folder could not be read. Each names the file as its reader shows it
/// ([`RunFiles::name`]), and none quotes the file's content when the reader is confined.
#[derive(Debug, thiserror::Error)]
pub enum RunFileError {
    /// The path leads outside the folder runs are loaded from (nothing there was looked at).
    #[error("{file}: outside the folder runs are loaded from")]
    Outside {
        /// The path, as asked for.
        file: String,
    },
    /// Nothing is there.
    #[error("{file}: no such file or folder")]
    Missing {
        /// The path.
        file: String,
    },
    /// A folder was expected.
    #[error("{file}: not a folder (expected the output folder of a run, holding result.json)")]
    NotAFolder {
        /// The path.
        file: String,
    },
    /// A regular file was expected.
    #[error("{file}: not a regular file")]
    NotAFile {
        /// The path.
        file: String,
    },
    /// The path passes through too many symbolic links (a loop of links, most likely).
    #[error("{file}: too many symbolic links")]
    TooManyLinks {
        /// The path.
        file: String,
    },
    /// The file opened was not the one resolved: it was replaced in between.
    #[error("{file}: changed while being opened")]
    Changed {
        /// The path.
        file: String,
    },
    /// The system refused to read it.
    #[error("{file}: cannot be read: {source}")]
    Unreadable {
        /// The path.
        file: String,
        /// The system's error.
        #[source]
        source: std::io::Error,
    },
    /// It was read but is not what a run folder holds there.
    #[error("{file}: {problem}{}", detail.as_ref().map(|d| format!(": {d}")).unwrap_or_default())]
    Malformed {
        /// The path.
        file: String,
        /// What is wrong, in words that quote nothing of the file.
        problem: String,
        /// The parser's own description (unconfined readers only: it may quote the file).
        detail: Option<String>,
    },
}

impl RunFileError {
    /// The file the error is about, as its reader names it.
    pub fn file(&self) -> &str {
        match self {
            RunFileError::Outside { file }
            | RunFileError::Missing { file }
            | RunFileError::NotAFolder { file }
            | RunFileError::NotAFile { file }
            | RunFileError::TooManyLinks { file }
            | RunFileError::Changed { file }
            | RunFileError::Unreadable { file, .. }
            | RunFileError::Malformed { file, .. } => file,
        }
    }
}

impl RunsRoot {
    /// The folder `root` (its canonical path: every link in it resolved) as the one run folders
    /// are read from.
    ///
    /// # Errors
    ///
    /// [`RunFileError::Missing`] or [`RunFileError::Unreadable`] when `root` cannot be
    /// resolved, [`RunFileError::NotAFolder`] when it is not a folder.
    pub fn new(root: &Path) -> Result<Self, RunFileError> {
        let file = root.display().to_string();
        let root = root.canonicalize().map_err(|e| io_error(file.clone(), e))?;
        if !root.is_dir() {
            return Err(RunFileError::NotAFolder { file });
        }
        Ok(RunsRoot {
            root,
            observer: None,
        })
    }

    /// With `observer` told of every path before it is looked at or opened (tests check with
    /// it that nothing outside the root ever is).
    pub fn observed(mut self, observer: impl Fn(&Path, Access) + Send + Sync + 'static) -> Self {
        self.observer = Some(Arc::new(observer));
        self
    }

    /// The root's canonical path.
    pub fn path(&self) -> &Path {
        &self.root
    }

    /// The run folder `path` names (relative to the root, or absolute inside it), resolved
    /// inside the root, as a reader of its files.
    ///
    /// # Errors
    ///
    /// [`RunFileError::Outside`] when `path` leads outside the root (whether or not anything is
    /// there); when inside: [`RunFileError::Missing`], [`RunFileError::NotAFolder`],
    /// [`RunFileError::TooManyLinks`], [`RunFileError::Unreadable`].
    pub fn folder(&self, path: &Path) -> Result<RunFiles, RunFileError> {
        let file = || path.display().to_string();
        let (at, last) = self.resolve(&[], path, &file)?;
        if last.is_some_and(|m| !m.is_dir()) {
            return Err(RunFileError::NotAFolder { file: file() });
        }
        Ok(RunFiles {
            dir: self.join(&at),
            confined: Some(Confined {
                root: self.clone(),
                at,
            }),
        })
    }

    fn observe(&self, path: &Path, access: Access) {
        if let Some(o) = &self.observer {
            o(path, access);
        }
    }

    /// The root joined with the components `at`.
    fn join(&self, at: &[OsString]) -> PathBuf {
        let mut p = self.root.clone();
        p.extend(at);
        p
    }

    /// The steps of `path` from the folder `at` names, or from the root (`true`) for an
    /// absolute path; `None` when an absolute path is not inside the root (compared as
    /// written: nothing outside is looked at to find out).
    fn steps(&self, path: &Path) -> Option<(bool, Vec<Step>)> {
        let (from_root, rest) = if path.has_root() {
            (true, path.strip_prefix(&self.root).ok()?)
        } else {
            (false, path)
        };
        let steps = rest
            .components()
            .filter_map(|c| match c {
                Component::Normal(name) => Some(Some(Step::Name(name.to_os_string()))),
                Component::ParentDir => Some(Some(Step::Up)),
                Component::CurDir => None,
                // A prefix or a root after the stripped one: no path inside the root.
                Component::Prefix(_) | Component::RootDir => Some(None),
            })
            .collect::<Option<Vec<_>>>()?;
        Some((from_root, steps))
    }

    /// Resolves `path` from the folder `from` (components under the root, each a folder, no
    /// link): the components of what it names and, unless it ends on a folder already known
    /// (the root, or a step up), the entry's own metadata (never a link's).
    fn resolve(
        &self,
        from: &[OsString],
        path: &Path,
        file: &dyn Fn() -> String,
    ) -> Result<(Vec<OsString>, Option<Metadata>), RunFileError> {
        let outside = || RunFileError::Outside { file: file() };
        let mut at = from.to_vec();
        let (from_root, steps) = self.steps(path).ok_or_else(outside)?;
        if from_root {
            at.clear();
        }
        let mut pending: Vec<Step> = steps.into_iter().rev().collect();
        let mut last = None;
        let mut links = 0;
        while let Some(step) = pending.pop() {
            match step {
                Step::Up => {
                    at.pop().ok_or_else(outside)?;
                    last = None;
                }
                Step::Name(name) => {
                    let mut here = self.join(&at);
                    here.push(&name);
                    self.observe(&here, Access::Look);
                    let meta = fs::symlink_metadata(&here).map_err(|e| io_error(file(), e))?;
                    if meta.file_type().is_symlink() {
                        links += 1;
                        if links > MAX_LINKS {
                            return Err(RunFileError::TooManyLinks { file: file() });
                        }
                        let target = fs::read_link(&here).map_err(|e| io_error(file(), e))?;
                        let (from_root, steps) = self.steps(&target).ok_or_else(outside)?;
                        if from_root {
                            at.clear();
                        }
                        pending.extend(steps.into_iter().rev());
                        continue;
                    }
                    if !pending.is_empty() && !meta.is_dir() {
                        return Err(RunFileError::NotAFolder { file: file() });
                    }
                    at.push(name);
                    last = Some(meta);
                }
            }
        }
        Ok((at, last))
    }
}

/// One step of a path.
enum Step {
    Up,
    Name(OsString),
}

/// A confined reader's root and folder.
#[derive(Clone, Debug)]
struct Confined {
    root: RunsRoot,
    /// The folder's components under the root (each a folder, no link).
    at: Vec<OsString>,
}

/// The reader of one run folder's files: confined to a [`RunsRoot`] (from
/// [`RunsRoot::folder`]) or not ([`RunFiles::unconfined`]).
#[derive(Clone, Debug)]
pub struct RunFiles {
    dir: PathBuf,
    confined: Option<Confined>,
}

impl RunFiles {
    /// The reader of the folder `dir` as it is: paths followed wherever they lead, messages
    /// naming files by `dir` joined with their names and describing parse errors in full.
    pub fn unconfined(dir: &Path) -> Self {
        RunFiles {
            dir: dir.to_path_buf(),
            confined: None,
        }
    }

    /// The folder (for a confined reader, its canonical path).
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Whether reads are confined to a [`RunsRoot`].
    pub fn is_confined(&self) -> bool {
        self.confined.is_some()
    }

    /// How messages name the folder: its path inside the root (`.` for the root itself), or
    /// the path given.
    pub fn shown(&self) -> String {
        match &self.confined {
            Some(c) if c.at.is_empty() => ".".into(),
            Some(c) => c.at.iter().collect::<PathBuf>().display().to_string(),
            None => self.dir.display().to_string(),
        }
    }

    /// How messages name the file `rel` of the folder: its path inside the root, or the
    /// folder's path joined with it.
    pub fn name(&self, rel: &str) -> String {
        match &self.confined {
            Some(c) => {
                c.at.iter()
                    .collect::<PathBuf>()
                    .join(rel)
                    .display()
                    .to_string()
            }
            None => self.dir.join(rel).display().to_string(),
        }
    }

    /// The reader of the folder `name` inside this one (a run's `slide/`), confined as this
    /// one is.
    ///
    /// # Errors
    ///
    /// As [`RunsRoot::folder`] (confined); never for an unconfined reader.
    pub fn sub(&self, name: &str) -> Result<RunFiles, RunFileError> {
        match &self.confined {
            None => Ok(RunFiles::unconfined(&self.dir.join(name))),
            Some(c) => {
                let at: PathBuf = c.at.iter().collect::<PathBuf>().join(name);
                c.root.folder(&at)
            }
        }
    }

    /// Whether the folder itself is there (a confined reader's always is: it was resolved).
    pub fn folder_exists(&self) -> bool {
        self.confined.is_some() || self.dir.is_dir()
    }

    /// The bytes of the file `rel` (a path relative to the folder).
    ///
    /// # Errors
    ///
    /// Confined: [`RunFileError::Outside`] when `rel` leads outside the root;
    /// [`RunFileError::Missing`], [`RunFileError::NotAFolder`] (a step of it is a file),
    /// [`RunFileError::NotAFile`], [`RunFileError::TooManyLinks`], [`RunFileError::Changed`],
    /// [`RunFileError::Unreadable`]. Unconfined: [`RunFileError::Missing`] or
    /// [`RunFileError::Unreadable`].
    pub fn read(&self, rel: &str) -> Result<Vec<u8>, RunFileError> {
        let file = || self.name(rel);
        let Some(c) = &self.confined else {
            return fs::read(self.dir.join(rel)).map_err(|e| io_error(file(), e));
        };
        let (at, last) = c.root.resolve(&c.at, Path::new(rel), &file)?;
        let Some(meta) = last.filter(Metadata::is_file) else {
            return Err(RunFileError::NotAFile { file: file() });
        };
        let path = c.root.join(&at);
        c.root.observe(&path, Access::Open);
        let mut f = fs::File::open(&path).map_err(|e| io_error(file(), e))?;
        let opened = f.metadata().map_err(|e| io_error(file(), e))?;
        if !same_file(&meta, &opened) {
            return Err(RunFileError::Changed { file: file() });
        }
        let mut bytes = Vec::new();
        f.read_to_end(&mut bytes).map_err(|e| io_error(file(), e))?;
        Ok(bytes)
    }

    /// The file `rel` as text (UTF-8).
    ///
    /// # Errors
    ///
    /// Those of [`Self::read`]; [`RunFileError::Malformed`] when it is not UTF-8 text.
    pub fn read_text(&self, rel: &str) -> Result<String, RunFileError> {
        String::from_utf8(self.read(rel)?)
            .map_err(|_| self.malformed(rel, "not text (UTF-8)".into(), None))
    }

    /// The JSON file `rel` as a `T`, which `what` names in a message (`a curvenet run
    /// record`).
    ///
    /// # Errors
    ///
    /// Those of [`Self::read`]; [`RunFileError::Malformed`] naming the line and column where
    /// the file is not JSON or not `what`.
    pub fn read_json<T: DeserializeOwned>(&self, rel: &str, what: &str) -> Result<T, RunFileError> {
        let bytes = self.read(rel)?;
        let value = serde_json::from_slice(&bytes).map_err(|e| {
            use serde_json::error::Category;
            let (line, column) = (e.line(), e.column());
            let problem = match e.classify() {
                Category::Eof => format!("not {what}: it ends early (line {line})"),
                Category::Syntax | Category::Io => {
                    format!("not valid JSON (line {line}, column {column})")
                }
                Category::Data => format!("not {what} (line {line}, column {column})"),
            };
            self.malformed(rel, problem, Some(e.to_string()))
        })?;
        // A key given twice (serde_json keeps the last): refused; the key itself is named only
        // by an unconfined reader (it is the file's content).
        if let Some(d) = std::str::from_utf8(&bytes)
            .ok()
            .and_then(crate::io::duplicate_key)
        {
            let problem = format!(
                "a key is given twice in one object (line {}, column {})",
                d.line, d.column
            );
            return Err(self.malformed(rel, problem, Some(d.describe())));
        }
        Ok(value)
    }

    /// The file `rel` of little-endian f64.
    ///
    /// # Errors
    ///
    /// Those of [`Self::read`]; [`RunFileError::Malformed`] when its length is not a whole
    /// number of f64.
    pub fn read_f64(&self, rel: &str) -> Result<Vec<f64>, RunFileError> {
        let bytes = self.read(rel)?;
        super::f64_values(&bytes).ok_or_else(|| {
            let problem = format!(
                "truncated file ({} bytes is not a whole number of f64)",
                bytes.len()
            );
            self.malformed(rel, problem, None)
        })
    }

    /// A [`RunFileError::Malformed`] about `rel`: `problem`, with `detail` (the parser's
    /// description) only when the reader is not confined.
    pub fn malformed(&self, rel: &str, problem: String, detail: Option<String>) -> RunFileError {
        RunFileError::Malformed {
            file: self.name(rel),
            problem,
            detail: detail.filter(|_| !self.is_confined()),
        }
    }
}

/// The error of a failed system call on `file`.
fn io_error(file: String, e: std::io::Error) -> RunFileError {
    match e.kind() {
        std::io::ErrorKind::NotFound | std::io::ErrorKind::NotADirectory => {
            RunFileError::Missing { file }
        }
        _ => RunFileError::Unreadable { file, source: e },
    }
}

/// Whether the file opened (`opened`) is the one resolved (`resolved`).
#[cfg(unix)]
fn same_file(resolved: &Metadata, opened: &Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    resolved.dev() == opened.dev() && resolved.ino() == opened.ino()
}

/// Whether the file opened (`opened`) is the one resolved (`resolved`): a regular file of the
/// same length (no inode to compare).
#[cfg(not(unix))]
fn same_file(resolved: &Metadata, opened: &Metadata) -> bool {
    opened.is_file() && resolved.len() == opened.len()
}

#[cfg(test)]
mod tests {
    use super::{RunFileError, RunFiles, RunsRoot};

    /// A run folder's JSON with a key given twice is refused; only an unconfined reader names
    /// the key (it is the file's content).
    #[test]
    fn a_key_given_twice_is_refused_and_named_only_unconfined() {
        let root = std::env::temp_dir().join(format!("curvenet-keys-{}", std::process::id()));
        let dir = root.join("run");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("x.json"), "{\"a\": 1,\n \"a\": 2}").unwrap();
        let read = |files: &RunFiles| match files.read_json::<serde_json::Value>("x.json", "x") {
            Err(RunFileError::Malformed {
                problem, detail, ..
            }) => (problem, detail),
            other => panic!("{other:?}"),
        };
        let (problem, detail) = read(&RunFiles::unconfined(&dir));
        assert!(problem.contains("a key is given twice in one object (line 2, column 2)"));
        assert!(detail.unwrap().contains("duplicate key \"a\""));
        let confined = RunsRoot::new(&root)
            .unwrap()
            .folder(std::path::Path::new("run"))
            .unwrap();
        let (problem, detail) = read(&confined);
        assert!(problem.contains("line 2"), "{problem}");
        assert_eq!(detail, None);
        let _ = std::fs::remove_dir_all(&root);
    }
}
