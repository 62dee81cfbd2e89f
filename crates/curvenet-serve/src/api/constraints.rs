//! The design constraints' routes: `GET /api/constraints` (those in force, what checking
//! them found, the current structure's margins) and `POST /api/constraints` (put new ones in
//! force; `{}` clears them).

use super::{ApiError, ApiResult, off_runtime, parse};
use crate::constraints::ConstraintsBody;
use crate::workspace::Workspace;
use axum::body::Bytes;
use axum::extract::State;
use axum::extract::rejection::BytesRejection;
use axum::http::StatusCode;
use curvenet::constraints::ConstraintParams;
use serde::Serialize;
use std::sync::Arc;

/// What `GET /api/constraints` and `POST /api/constraints` answer.
#[derive(Serialize)]
pub(super) struct ConstraintsAnswer {
    /// The settings in force (the defaults when none is).
    constraints: ConstraintParams,
    /// What checking them found: the symmetry detected, groups widened, the surface's
    /// sampling.
    notes: Vec<String>,
    /// The current structure's margins (`null` when no constraint is in force).
    current: Option<serde_json::Value>,
}

fn answer(ws: &Workspace) -> ConstraintsAnswer {
    let c = ws.design.current();
    let net = ws.design.analyzer().network();
    let s = ws.constraints();
    ConstraintsAnswer {
        constraints: s.params().clone(),
        notes: s.notes(),
        current: s.margins(net, &c),
    }
}

pub(super) async fn get(State(ws): State<Arc<Workspace>>) -> ApiResult<ConstraintsAnswer> {
    let a = off_runtime(move || Ok(answer(&ws))).await?;
    Ok(axum::Json(a))
}

pub(super) async fn set(
    State(ws): State<Arc<Workspace>>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<ConstraintsAnswer> {
    let b: ConstraintsBody = parse(body)?;
    let unprocessable = |m: String| ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, m);
    let params = b.params().map_err(unprocessable)?;
    let a = off_runtime(move || {
        let net = ws.design.analyzer().network();
        ws.constraints()
            .set(net, ws.mesh.as_deref(), params)
            .map_err(unprocessable)?;
        Ok(answer(&ws))
    })
    .await?;
    Ok(axum::Json(a))
}
