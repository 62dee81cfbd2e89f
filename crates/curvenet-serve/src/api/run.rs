//! `POST /api/run` `{"path": DIR}`: loads the run folder `DIR` on the server's machine and
//! serves it in place of the current network (its network, its greedy iterations to step
//! through, starting on its answer), as `serve --run DIR` would have.
//!
//! Only files inside the configured root ([`super::ServeConfig::runs_root`]) are read: `DIR`
//! is taken relative to it (an absolute path as it is), and it and every file of it are read
//! through the root's confined reader ([`curvenet::run_folder::RunsRoot`]), which resolves each
//! path inside the root (every `..` and symbolic link) and refuses one that leads outside
//! before looking at anything there. A path outside gets one answer (403) whether or not
//! anything is there; messages name files by their path inside the root and never quote their
//! content. Only a curvenet run folder is loaded (its `result.json` and `network.json` read and
//! checked); nothing is written.

use super::{ApiError, ApiResult, AppState, StateAnswer, off_runtime, parse};
use crate::workspace::{OpenRunError, open_run};
use axum::body::Bytes;
use axum::extract::State;
use axum::extract::rejection::BytesRejection;
use axum::http::StatusCode;
use curvenet::run_folder::{RunFileError, RunFiles, RunsRoot};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::atomic::Ordering;

/// The longest path accepted.
const MAX_PATH: usize = 4096;

/// The body of `POST /api/run`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RunBody {
    path: String,
}

/// What a load answers: what is served now.
#[derive(Serialize)]
pub(super) struct LoadAnswer {
    /// The run folder, as the page's title names it.
    name: String,
    /// Curves of its network.
    curve_count: usize,
    /// Greedy iterations recorded by the run.
    iterations: usize,
    /// Problems reading it that did not stop the loading.
    warnings: Vec<String>,
    /// The state served now: the run's answer (its last iteration when it has none).
    state: StateAnswer,
}

/// Clears the loading flag when dropped.
struct Loading<'a>(&'a std::sync::atomic::AtomicBool);

impl Drop for Loading<'_> {
    fn drop(&mut self) {
        self.0.store(false, Ordering::Release);
    }
}

pub(super) async fn load(
    State(app): State<AppState>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<LoadAnswer> {
    let RunBody { path } = parse(body)?;
    let root = app.config().runs_root.clone().ok_or_else(|| {
        ApiError::new(
            StatusCode::FORBIDDEN,
            "this server loads no run folder (it was started without a folder to load runs from)",
        )
    })?;
    let files = resolve(&root, &path)?;
    let flag = &app.shared.loading;
    if flag.swap(true, Ordering::AcqRel) {
        return Err(ApiError::new(
            StatusCode::CONFLICT,
            "a run folder is being loaded; wait for it to finish",
        ));
    }
    let _loading = Loading(flag);
    let physical = app.config().physical.clone();
    let (ws, warnings, iterations) = off_runtime(move || {
        let name = files.dir().display().to_string();
        let run = open_run(files, physical.as_ref()).map_err(|e| {
            let status = match &e {
                OpenRunError::Folder(f) if f.is_outside() => StatusCode::FORBIDDEN,
                _ => StatusCode::UNPROCESSABLE_ENTITY,
            };
            ApiError::new(status, e.to_string())
        })?;
        let warnings = run.warnings.clone();
        let iterations = run.greedy.iterations().1.len();
        let ws = run.workspace(&[], &name)?;
        Ok((ws, warnings, iterations))
    })
    .await?;
    let answer = LoadAnswer {
        name: ws.name.to_string(),
        curve_count: ws.design.analyzer().curve_count(),
        iterations,
        warnings,
        state: StateAnswer::of(&ws, &ws.design.current()),
    };
    app.replace(ws);
    Ok(axum::Json(answer))
}

/// The reader of the run folder `path` names under `root` (relative to it, or absolute),
/// confined to `root`.
fn resolve(root: &RunsRoot, path: &str) -> Result<RunFiles, ApiError> {
    let unprocessable = |m: String| ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, m);
    if path.trim().is_empty() || path.len() > MAX_PATH || path.contains('\0') {
        return Err(unprocessable(format!(
            "path: give the folder of a run (holding result.json), at most {MAX_PATH} bytes"
        )));
    }
    root.folder(Path::new(path)).map_err(|e| match e {
        RunFileError::Outside { .. } => ApiError::new(
            StatusCode::FORBIDDEN,
            format!(
                "{path}: outside the folder runs are loaded from ({}); start serve with \
                 --runs DIR to load from another",
                root.path().display()
            ),
        ),
        RunFileError::Missing { .. } => unprocessable(format!("{path}: no such folder")),
        e => unprocessable(e.to_string()),
    })
}
