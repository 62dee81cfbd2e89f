//! Claiming a run's folder before any work: created when missing, locked for the run (a
//! resumed run's stale temporary files removed), and for a fresh run what it will remove of
//! an earlier run's files (done once the run starts writing).

use crate::app::AppError;
use crate::app::observer::Observer;
use crate::run_folder::folder::{
    FolderError, FolderLock, FreshStart, claim as lock_folder, fresh_start,
};
use crate::words::{Message, Opt, given, message};
use std::path::Path;

/// Makes sure `out` is (or can be made) a folder and locks it for this run, before any work:
/// a file there, a folder that cannot be created, one another run holds, or (for a fresh run)
/// a non-empty folder that is no curvenet run's without `force`, is a usage error naming it.
pub(super) fn claim(
    out: &Path,
    resume: bool,
    force: bool,
    observer: &dyn Observer,
) -> Result<(FolderLock, Option<FreshStart>), AppError> {
    if out.exists() && !out.is_dir() {
        return Err(AppError::usage(message![
            given(Opt::Out, out.display()),
            ": is a file, not a folder; give a folder for the run's outputs"
        ]));
    }
    std::fs::create_dir_all(out).map_err(|e| {
        AppError::usage(message![
            given(Opt::Out, out.display()),
            format!(": cannot create the folder: {e}")
        ])
    })?;
    let resuming = resume && out.join("result.json").is_file();
    let held = lock_folder(out, resuming).map_err(folder_error)?;
    let lock = held.lock;
    if let Some(w) = &lock.warning {
        observer.warning(&Message::from(w.as_str()));
    }
    if held.stale_temp_files > 0 {
        observer.note(&Message::from(format!(
            "{}: removed {} temporary file(s) a stopped run left",
            out.display(),
            held.stale_temp_files
        )));
    }
    if resuming {
        return Ok((lock, None));
    }
    let fresh = fresh_start(out, force).map_err(folder_error)?;
    Ok((lock, Some(fresh)))
}

/// A folder that cannot take the run, as a usage error naming the options that help.
fn folder_error(e: FolderError) -> AppError {
    AppError::Usage(e.message())
}
