//! `GET /api/export?format=obj|csv|json`: the current structure as a file to save.

use super::{ApiError, off_runtime};
use crate::export::{Format, export as export_file};
use crate::workspace::Workspace;
use axum::extract::rejection::QueryRejection;
use axum::extract::{Query, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Deserialize;
use std::sync::Arc;

/// The query of `GET /api/export`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ExportQuery {
    format: String,
}

pub(super) async fn export(
    State(ws): State<Arc<Workspace>>,
    query: Result<Query<ExportQuery>, QueryRejection>,
) -> Result<Response, ApiError> {
    let Query(q) = query.map_err(|e| {
        ApiError::new(
            StatusCode::BAD_REQUEST,
            format!(
                "{}; use /api/export?format=obj (or csv, json, surface)",
                e.body_text()
            ),
        )
    })?;
    let format = Format::parse(&q.format).map_err(|e| ApiError::new(StatusCode::BAD_REQUEST, e))?;
    let (name, text) = off_runtime(move || {
        export_file(&ws, format).ok_or_else(|| {
            ApiError::new(
                StatusCode::NOT_FOUND,
                "this server has no surface to save (serve with --mesh)",
            )
        })
    })
    .await?;
    Ok((
        [
            (header::CONTENT_TYPE, format.content_type().to_string()),
            (
                header::CONTENT_DISPOSITION,
                format!("attachment; filename=\"{name}\""),
            ),
        ],
        text,
    )
        .into_response())
}
