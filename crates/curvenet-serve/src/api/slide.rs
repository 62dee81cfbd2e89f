//! The slide's routes: `POST /api/slide` (start a slide of the current structure),
//! `GET /api/slide` (progress and result), `POST /api/slide/cancel`, `POST /api/slide/adopt`
//! (the slid curves put in place of the drawn ones, as one drawing edit).
//!
//! `POST /api/slide` takes `{"budget", "max_move", "max_evaluations"}`, each optional:
//! `budget` a fraction of the network's total rest length in (0, 1] (default the current
//! structure's length), `max_move` how far a point may move (a length, or a string such as
//! `"5%"` of the surface's bounding-box diagonal; default the slide feature's), and
//! `max_evaluations` the most networks the search evaluates (default the slide feature's).

use super::draw::{DrawAnswer, draw};
use super::{ApiError, ApiResult, AppState, off_runtime, parse};
use crate::slide::{SlideProgress, SlideRunError};
use crate::words::say;
use crate::workspace::Workspace;
use axum::body::Bytes;
use axum::extract::State;
use axum::extract::rejection::BytesRejection;
use axum::http::StatusCode;
use curvenet::app::Drawing;
use curvenet::simplify::Budget;
use curvenet::slide::{MaxMove, SlideParams};
use serde::Deserialize;
use std::sync::Arc;

/// The most networks a slide may be asked to evaluate.
pub const MAX_EVALUATIONS: usize = 100_000;

impl From<SlideRunError> for ApiError {
    fn from(e: SlideRunError) -> Self {
        ApiError::new(StatusCode::CONFLICT, e.to_string())
    }
}

/// `max_move`: a length or a string (`"5%"`, `"0.2"`).
#[derive(Deserialize)]
#[serde(untagged)]
enum MaxMoveBody {
    Length(f64),
    Text(String),
}

/// The body of `POST /api/slide`.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct StartBody {
    budget: Option<f64>,
    max_move: Option<MaxMoveBody>,
    max_evaluations: Option<usize>,
}

fn bad(message: impl Into<String>) -> ApiError {
    ApiError::new(StatusCode::BAD_REQUEST, message)
}

/// The slide's parameters of `b`.
fn params_of(b: &StartBody) -> Result<SlideParams, ApiError> {
    // The page's limit holds within a sweep of the search too.
    let mut params = SlideParams {
        strict_limit: true,
        ..SlideParams::default()
    };
    match &b.max_move {
        None => {}
        Some(MaxMoveBody::Length(v)) => params.max_move = MaxMove::Length(*v),
        Some(MaxMoveBody::Text(t)) => {
            params.max_move = t
                .parse()
                .map_err(|m| bad(format!("max_move: {}", say(&m))))?;
        }
    }
    if let Some(n) = b.max_evaluations {
        if !(1..=MAX_EVALUATIONS).contains(&n) {
            return Err(bad(format!(
                "max_evaluations is {n}: give 1 to {MAX_EVALUATIONS}"
            )));
        }
        params.max_evaluations = n;
    }
    Ok(params)
}

pub(super) async fn start(
    State(ws): State<Arc<Workspace>>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<SlideProgress> {
    // An empty body starts a slide with every default.
    let b: StartBody = match &body {
        Ok(bytes) if bytes.iter().all(u8::is_ascii_whitespace) => StartBody::default(),
        _ => parse(body)?,
    };
    let params = params_of(&b)?;
    let p = off_runtime(move || {
        let drawing = ws.drawing.clone().ok_or_else(|| {
            ApiError::new(
                StatusCode::CONFLICT,
                crate::workspace::not_editable("sliding"),
            )
        })?;
        let current = ws.design.current();
        let kept = current.summary.curves.clone();
        let total: f64 = ws.design.analyzer().lengths().iter().sum();
        let length = match b.budget {
            None => current.summary.length,
            Some(f) if f > 0.0 && f <= 1.0 => f * total,
            Some(f) => {
                return Err(ApiError::new(
                    StatusCode::UNPROCESSABLE_ENTITY,
                    format!("budget is {f}: give a fraction of the total length in (0, 1]"),
                ));
            }
        };
        let search = {
            let net = ws.design.analyzer().network();
            let mut c = ws.constraints();
            c.for_search(net, ws.mesh.as_deref(), Budget::Length(length), Vec::new())
                .map_err(|m| ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, m))?
        };
        let slider = drawing.slider(&kept, length, &search.constraints, params)?;
        Ok(ws.slide.start(slider, kept, (length / total, length))?)
    })
    .await?;
    Ok(axum::Json(p))
}

pub(super) async fn progress(State(ws): State<Arc<Workspace>>) -> ApiResult<SlideProgress> {
    Ok(axum::Json(ws.slide.progress()))
}

pub(super) async fn cancel(State(ws): State<Arc<Workspace>>) -> ApiResult<SlideProgress> {
    Ok(axum::Json(ws.slide.cancel()?))
}

/// `POST /api/slide/adopt`: one drawing edit (undo takes it back).
pub(super) async fn adopt(State(app): State<AppState>) -> ApiResult<DrawAnswer> {
    let (kept, curves) = app.workspace().slide.slid()?;
    draw(app, Drawing::slid_edit(&kept, &curves)).await
}
