//! The greedy's routes: `POST /api/greedy` (start), `GET /api/greedy` (progress),
//! `POST /api/greedy/cancel`, `GET /api/greedy/iterations`, `POST /api/greedy/step`.

use super::{ApiError, ApiResult, EditAnswer, blocking, off_runtime, parse};
use crate::design::Design;
use crate::greedy::{GreedyError, Progress, Request, RunStatus, Runner, Step};
use axum::body::Bytes;
use axum::extract::State;
use axum::extract::rejection::BytesRejection;
use axum::http::StatusCode;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

impl From<GreedyError> for ApiError {
    fn from(e: GreedyError) -> Self {
        let status = match e {
            GreedyError::Busy | GreedyError::NotRunning | GreedyError::NoRun => {
                StatusCode::CONFLICT
            }
            GreedyError::Params(_) | GreedyError::NoIteration { .. } => {
                StatusCode::UNPROCESSABLE_ENTITY
            }
        };
        ApiError::new(status, e.to_string())
    }
}

/// The body of `POST /api/greedy`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StartBody {
    /// The budget: a fraction of the network's total rest length, in (0, 1].
    budget: f64,
    #[serde(default)]
    keep: Vec<usize>,
    #[serde(default)]
    max_removals: Option<usize>,
}

/// The body of `POST /api/greedy/step`.
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
    State(design): State<Arc<Design>>,
    State(runner): State<Arc<Runner>>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<Progress> {
    let b: StartBody = parse(body)?;
    let request = Request {
        budget: b.budget,
        keep: b.keep,
        max_removals: b.max_removals,
    };
    let p = off_runtime(move || Ok(runner.start(design, request)?)).await?;
    Ok(axum::Json(p))
}

pub(super) async fn progress(State(runner): State<Arc<Runner>>) -> ApiResult<Progress> {
    Ok(axum::Json(runner.progress()))
}

pub(super) async fn cancel(State(runner): State<Arc<Runner>>) -> ApiResult<Progress> {
    Ok(axum::Json(runner.cancel()?))
}

pub(super) async fn iterations(State(runner): State<Arc<Runner>>) -> ApiResult<IterationsAnswer> {
    let (status, iterations) = runner.iterations();
    Ok(axum::Json(IterationsAnswer { status, iterations }))
}

pub(super) async fn step(
    State(design): State<Arc<Design>>,
    State(runner): State<Arc<Runner>>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<StepAnswer> {
    let StepBody { iteration } = parse(body)?;
    let curves = runner.curves_of(iteration)?;
    let e = blocking(design, move |d| d.set(&curves)).await?;
    Ok(axum::Json(StepAnswer {
        iteration,
        edit: e.into(),
    }))
}
