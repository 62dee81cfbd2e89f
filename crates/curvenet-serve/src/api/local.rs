//! The local search's routes: `POST /api/local` (start from the current structure),
//! `GET /api/local` (progress and result), `POST /api/local/cancel`, `POST /api/local/adopt`
//! (its best network made current).

use super::greedy::{StartBody, search_for};
use super::{ApiError, ApiResult, EditAnswer, blocking, off_runtime, parse};
use crate::greedy::Request;
use crate::local::LocalProgress;
use crate::workspace::Workspace;
use axum::body::Bytes;
use axum::extract::State;
use axum::extract::rejection::BytesRejection;
use axum::http::StatusCode;
use std::sync::Arc;

pub(super) async fn start(
    State(ws): State<Arc<Workspace>>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<LocalProgress> {
    let b: StartBody = parse(body)?;
    let request = Request::from(b);
    if request.max_removals.is_some() {
        return Err(ApiError::new(
            StatusCode::BAD_REQUEST,
            "malformed JSON body: max_removals belongs to the greedy (POST /api/greedy); the \
             local search takes budget and keep",
        ));
    }
    let p = off_runtime(move || {
        let search = search_for(&ws, &request)?;
        Ok(ws.local.start(Arc::clone(&ws.design), &request, search)?)
    })
    .await?;
    Ok(axum::Json(p))
}

pub(super) async fn progress(State(ws): State<Arc<Workspace>>) -> ApiResult<LocalProgress> {
    Ok(axum::Json(ws.local.progress()))
}

pub(super) async fn cancel(State(ws): State<Arc<Workspace>>) -> ApiResult<LocalProgress> {
    Ok(axum::Json(ws.local.cancel()?))
}

pub(super) async fn adopt(State(ws): State<Arc<Workspace>>) -> ApiResult<EditAnswer> {
    let curves = ws.local.best()?;
    let e = blocking(ws, move |w| Ok(EditAnswer::of(w, &w.design.set(&curves)?))).await?;
    Ok(axum::Json(e))
}
