//! The greedy's routes: `POST /api/greedy` (start), `GET /api/greedy` (progress),
//! `POST /api/greedy/cancel`, `GET /api/greedy/iterations`, `POST /api/greedy/step`.

use super::{ApiError, ApiResult, EditAnswer, blocking, off_runtime, parse};
use crate::greedy::{GreedyError, Progress, Request, RunStatus, Step};
use crate::workspace::Workspace;
use axum::body::Bytes;
use axum::extract::State;
use axum::extract::rejection::BytesRejection;
use axum::http::StatusCode;
use curvenet::app::Search;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

impl From<GreedyError> for ApiError {
    fn from(e: GreedyError) -> Self {
        let status = match e {
            GreedyError::Busy
            | GreedyError::NotRunning
            | GreedyError::NoRun
            | GreedyError::LocalBusy
            | GreedyError::LocalNotRunning
            | GreedyError::NoLocalResult => StatusCode::CONFLICT,
            GreedyError::Params(_) | GreedyError::NoIteration { .. } => {
                StatusCode::UNPROCESSABLE_ENTITY
            }
        };
        ApiError::new(status, e.to_string())
    }
}

/// The body of `POST /api/greedy` (and, without `max_removals`, of `POST /api/local`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct StartBody {
    /// The budget: a fraction of the network's total rest length, in (0, 1].
    budget: f64,
    #[serde(default)]
    keep: Vec<usize>,
    #[serde(default)]
    max_removals: Option<usize>,
}

impl From<StartBody> for Request {
    fn from(b: StartBody) -> Self {
        Request {
            budget: b.budget,
            keep: b.keep,
            max_removals: b.max_removals,
        }
    }
}

/// The search of `request` on the workspace's network under the session's constraints.
pub(super) fn search_for(ws: &Workspace, request: &Request) -> Result<Search, ApiError> {
    Ok(request.search(&ws.design, &mut ws.constraints(), ws.mesh.as_deref())?)
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StepBody {
    iteration: usize,
}

/// `GET /api/greedy/iterations`.
#[derive(Serialize)]
pub(super) struct IterationsAnswer {
    status: RunStatus,
    iterations: Vec<Step>,
}

/// `POST /api/greedy/step`: the edit's answer and the iteration it made current.
#[derive(Serialize)]
pub(super) struct StepAnswer {
    iteration: usize,
    #[serde(flatten)]
    edit: EditAnswer,
}

pub(super) async fn start(
    State(ws): State<Arc<Workspace>>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<Progress> {
    let b: StartBody = parse(body)?;
    let request = Request::from(b);
    let p = off_runtime(move || {
        let search = search_for(&ws, &request)?;
        Ok(ws.greedy.start(Arc::clone(&ws.design), &request, search)?)
    })
    .await?;
    Ok(axum::Json(p))
}

pub(super) async fn progress(State(ws): State<Arc<Workspace>>) -> ApiResult<Progress> {
    Ok(axum::Json(ws.greedy.progress()))
}

pub(super) async fn cancel(State(ws): State<Arc<Workspace>>) -> ApiResult<Progress> {
    Ok(axum::Json(ws.greedy.cancel()?))
}

pub(super) async fn iterations(State(ws): State<Arc<Workspace>>) -> ApiResult<IterationsAnswer> {
    let (status, iterations) = ws.greedy.iterations();
    Ok(axum::Json(IterationsAnswer { status, iterations }))
}

pub(super) async fn step(
    State(ws): State<Arc<Workspace>>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<StepAnswer> {
    let StepBody { iteration } = parse(body)?;
    let curves = ws.greedy.curves_of(iteration)?;
    let e = blocking(ws, move |w| Ok(EditAnswer::of(w, &w.design.set(&curves)?))).await?;
    Ok(axum::Json(StepAnswer { iteration, edit: e }))
}
