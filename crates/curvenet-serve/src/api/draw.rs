//! Drawing on the page: the design's curves edited, each edit rebuilding the network
//! ([`curvenet::app::Drawing`]) and serving it as a new workspace; undo and redo walk through
//! the workspaces these edits replaced.
//!
//! - `GET /api/curves`: the design's curves as drawn, each one's number of move coefficients,
//!   the edge length, the largest move, and how many drawing edits undo and redo can walk;
//! - `POST /api/curves` `{"geodesic": {"point": [x,y,z], "direction": [dx,dy,dz]}}` or
//!   `{"through": [[x,y,z], ...]}`: adds a curve;
//! - `DELETE /api/curves/{id}`: deletes one;
//! - `POST /api/curves/{id}/move` `{"params": [a0, a1, ...]}`: moves one;
//! - `POST /api/curves/preview`: the curve an addition or a move would draw, nothing built
//!   (`{"geodesic": …}`, `{"through": …}`, `{"move": {"curve", "params"}}`, or
//!   `{"drag": {"curve", "from", "to"}}`, which also answers the move's coefficients);
//! - `POST /api/curves/undo`, `POST /api/curves/redo`.
//!
//! An edit answers the new state as `/api/set` does, plus `curve` (the id added or moved),
//! its `joints` (each one's point and the curves through it) and `curve_count`.

use super::{ApiError, ApiResult, AppState, StateAnswer, off_runtime, parse};
use crate::words::say;
use crate::workspace::{Redraw, Workspace};
use axum::body::Bytes;
use axum::extract::rejection::BytesRejection;
use axum::extract::{Path, State};
use axum::http::StatusCode;
use curvenet::app::{DrawEdit, DrawError, Drawing, NewCurve};
use curvenet::geom::Vec3;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use std::time::Instant;

/// The most drawing edits undo walks back through.
pub const HISTORY: usize = 64;

/// The workspaces drawing edits replaced (undo) and those undone (redo).
#[derive(Debug, Default)]
pub(crate) struct History {
    past: Vec<Arc<Workspace>>,
    future: Vec<Arc<Workspace>>,
}

impl From<DrawError> for ApiError {
    fn from(e: DrawError) -> Self {
        let status = if e.is_input() {
            StatusCode::UNPROCESSABLE_ENTITY
        } else {
            StatusCode::INTERNAL_SERVER_ERROR
        };
        ApiError::new(status, say(&e.message()))
    }
}

/// `{"point", "direction"}` of a geodesic.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GeodesicBody {
    point: [f64; 3],
    direction: [f64; 3],
}

/// The body of `POST /api/curves`: one of its fields.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AddBody {
    geodesic: Option<GeodesicBody>,
    through: Option<Vec<[f64; 3]>>,
}

/// `{"curve", "params"}` of a move.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MoveOf {
    curve: usize,
    params: Vec<f64>,
}

/// `{"curve", "from", "to"}` of a drag.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DragBody {
    curve: usize,
    from: [f64; 3],
    to: [f64; 3],
}

/// The body of `POST /api/curves/preview`: one of its fields.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PreviewBody {
    geodesic: Option<GeodesicBody>,
    through: Option<Vec<[f64; 3]>>,
    #[serde(rename = "move")]
    moved: Option<MoveOf>,
    drag: Option<DragBody>,
}

/// The body of `POST /api/curves/{id}/move`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MoveBody {
    params: Vec<f64>,
}

fn v3(p: [f64; 3]) -> Vec3 {
    Vec3::new(p[0], p[1], p[2])
}

/// The curve of `geodesic` or `through`, exactly one given.
fn new_curve(
    geodesic: Option<GeodesicBody>,
    through: Option<Vec<[f64; 3]>>,
    fields: &str,
) -> Result<NewCurve, ApiError> {
    match (geodesic, through) {
        (Some(g), None) => Ok(NewCurve::Geodesic {
            point: v3(g.point),
            direction: v3(g.direction),
        }),
        (None, Some(t)) => Ok(NewCurve::Through(t.into_iter().map(v3).collect())),
        _ => Err(ApiError::new(
            StatusCode::BAD_REQUEST,
            format!("give exactly one of {fields}"),
        )),
    }
}

/// One joint of a curve.
#[derive(Serialize)]
struct JointAnswer {
    point: [f64; 3],
    curves: Vec<usize>,
}

/// The answer to a drawing edit, an undo or a redo.
#[derive(Serialize)]
pub(crate) struct DrawAnswer {
    #[serde(flatten)]
    state: StateAnswer,
    /// The curve added or moved.
    #[serde(skip_serializing_if = "Option::is_none")]
    curve: Option<usize>,
    /// Its joints.
    #[serde(skip_serializing_if = "Option::is_none")]
    joints: Option<Vec<JointAnswer>>,
    /// The design's curves now.
    curve_count: usize,
    /// Server-side time: the rebuild and the analysis.
    elapsed_ms: f64,
}

impl DrawAnswer {
    fn of(ws: &Workspace, curve: Option<usize>, start: Instant) -> Self {
        let net = ws.design.analyzer().network();
        let joints = curve.map(|c| {
            curvenet::app::draw::joints_of(net, c)
                .into_iter()
                .map(|(p, curves)| JointAnswer {
                    point: [p.x, p.y, p.z],
                    curves,
                })
                .collect()
        });
        DrawAnswer {
            state: StateAnswer::of(ws, &ws.design.current()),
            curve,
            joints,
            curve_count: ws.design.analyzer().curve_count(),
            elapsed_ms: start.elapsed().as_secs_f64() * 1e3,
        }
    }
}

/// The drawing of `ws`, or why its curves cannot be edited.
fn drawing_of(ws: &Workspace) -> Result<Arc<Drawing>, ApiError> {
    ws.drawing.clone().ok_or_else(|| Redraw::NotEditable.into())
}

impl From<Redraw> for ApiError {
    fn from(e: Redraw) -> Self {
        match e {
            Redraw::NotEditable => ApiError::new(StatusCode::CONFLICT, e.to_string()),
            Redraw::Draw(e) => e.into(),
            Redraw::Design(e) => e.into(),
        }
    }
}

/// Applies `edit` to the current workspace's drawing: the new network built and analysed
/// (off the async runtime) and served, the old workspace kept for undo.
pub(super) async fn draw(app: AppState, edit: DrawEdit) -> ApiResult<DrawAnswer> {
    let _one = app.shared.drawing.lock().await;
    let old = app.workspace();
    let start = Instant::now();
    let (ws, answer) = off_runtime(move || {
        let (ws, curve) = old.draw(&edit)?;
        let answer = DrawAnswer::of(&ws, curve, start);
        Ok((ws, answer))
    })
    .await?;
    app.push_drawn(ws);
    Ok(axum::Json(answer))
}

/// `GET /api/curves`.
pub(super) async fn list(State(app): State<AppState>) -> ApiResult<serde_json::Value> {
    let ws = app.workspace();
    let (undo, redo) = {
        let h = app.history();
        (h.past.len(), h.future.len())
    };
    let v = off_runtime(move || {
        let Some(d) = &ws.drawing else {
            return Ok(
                serde_json::json!({ "editable": false, "curves": [], "undo": 0, "redo": 0 }),
            );
        };
        let curves: Vec<serde_json::Value> = d
            .curves()
            .iter()
            .enumerate()
            .map(|(c, p)| {
                serde_json::json!({
                    "points": p.points.iter().map(|q| [q.x, q.y, q.z]).collect::<Vec<_>>(),
                    "closed": p.closed,
                    "move_dimension": d.move_dimension(c).unwrap_or(0),
                })
            })
            .collect();
        Ok(serde_json::json!({
            "editable": true,
            "curves": curves,
            "edge_length": d.edge_length(),
            "max_move": d.max_move(),
            "undo": undo,
            "redo": redo,
        }))
    })
    .await?;
    Ok(axum::Json(v))
}

/// `POST /api/curves`.
pub(super) async fn add(
    State(app): State<AppState>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<DrawAnswer> {
    let AddBody { geodesic, through } = parse(body)?;
    let curve = new_curve(geodesic, through, "\"geodesic\" and \"through\"")?;
    draw(app, DrawEdit::Add(curve)).await
}

/// `DELETE /api/curves/{id}`.
pub(super) async fn delete(
    State(app): State<AppState>,
    Path(id): Path<String>,
) -> ApiResult<DrawAnswer> {
    draw(app, DrawEdit::Delete(curve_id(&id)?)).await
}

/// `POST /api/curves/{id}/move`.
pub(super) async fn move_curve(
    State(app): State<AppState>,
    Path(id): Path<String>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<DrawAnswer> {
    let curve = curve_id(&id)?;
    let MoveBody { params } = parse(body)?;
    draw(app, DrawEdit::Move { curve, params }).await
}

/// The curve id of a path.
fn curve_id(id: &str) -> Result<usize, ApiError> {
    id.parse().map_err(|_| {
        ApiError::new(
            StatusCode::BAD_REQUEST,
            format!("{id:?} is not a curve id (a number such as 3)"),
        )
    })
}

/// A previewed curve.
#[derive(Serialize)]
pub(super) struct PreviewAnswer {
    points: Vec<[f64; 3]>,
    /// A drag's move coefficients (what `POST /api/curves/{id}/move` takes).
    #[serde(skip_serializing_if = "Option::is_none")]
    params: Option<Vec<f64>>,
}

/// `POST /api/curves/preview`.
pub(super) async fn preview(
    State(app): State<AppState>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<PreviewAnswer> {
    let PreviewBody {
        geodesic,
        through,
        moved,
        drag,
    } = parse(body)?;
    let fields = "\"geodesic\", \"through\", \"move\" and \"drag\"";
    let ws = app.workspace();
    let drawing = drawing_of(&ws)?;
    let answer = off_runtime(move || {
        let (edit, params) = match (moved, drag) {
            (Some(m), None) if geodesic.is_none() && through.is_none() => (
                DrawEdit::Move {
                    curve: m.curve,
                    params: m.params,
                },
                None,
            ),
            (None, Some(d)) if geodesic.is_none() && through.is_none() => {
                let params = drawing.drag(d.curve, v3(d.from), v3(d.to))?;
                (
                    DrawEdit::Move {
                        curve: d.curve,
                        params: params.clone(),
                    },
                    Some(params),
                )
            }
            (None, None) => (DrawEdit::Add(new_curve(geodesic, through, fields)?), None),
            _ => {
                return Err(ApiError::new(
                    StatusCode::BAD_REQUEST,
                    format!("give exactly one of {fields}"),
                ));
            }
        };
        let curve = drawing.preview(&edit)?;
        Ok(PreviewAnswer {
            points: curve.points.iter().map(|q| [q.x, q.y, q.z]).collect(),
            params,
        })
    })
    .await?;
    Ok(axum::Json(answer))
}

/// `POST /api/curves/undo`.
pub(super) async fn undo(State(app): State<AppState>) -> ApiResult<DrawAnswer> {
    step(app, true).await
}

/// `POST /api/curves/redo`.
pub(super) async fn redo(State(app): State<AppState>) -> ApiResult<DrawAnswer> {
    step(app, false).await
}

async fn step(app: AppState, back: bool) -> ApiResult<DrawAnswer> {
    let _one = app.shared.drawing.lock().await;
    let start = Instant::now();
    let ws = app.step_drawn(back).ok_or_else(|| {
        let what = if back { "undo" } else { "redo" };
        ApiError::new(
            StatusCode::CONFLICT,
            format!(
                "nothing to {what}: no drawing edit to walk {}",
                if back { "back" } else { "forward" }
            ),
        )
    })?;
    let answer = off_runtime(move || Ok(DrawAnswer::of(&ws, None, start))).await?;
    Ok(axum::Json(answer))
}

impl AppState {
    /// Serves `next`, the workspace of a drawing edit, keeping the one it replaces for undo
    /// (and forgetting what was undone).
    fn push_drawn(&self, next: Workspace) {
        let mut h = self.history();
        let replaced = self.swap(Arc::new(next));
        h.past.push(replaced);
        if h.past.len() > HISTORY {
            h.past.remove(0);
        }
        h.future.clear();
    }

    /// Serves the workspace before (`back`) or after the current one in the drawing's
    /// history, `None` when there is none.
    fn step_drawn(&self, back: bool) -> Option<Arc<Workspace>> {
        let mut h = self.history();
        let next = if back { h.past.pop() } else { h.future.pop() }?;
        let replaced = self.swap(Arc::clone(&next));
        if back {
            h.future.push(replaced);
        } else {
            h.past.push(replaced);
        }
        Some(next)
    }

    fn history(&self) -> std::sync::MutexGuard<'_, History> {
        self.shared
            .history
            .lock()
            .unwrap_or_else(|e| e.into_inner())
    }

    /// Serves `ws`; the workspace it replaces is handed back, its searches asked to stop.
    fn swap(&self, ws: Arc<Workspace>) -> Arc<Workspace> {
        let mut w = self
            .shared
            .current
            .write()
            .unwrap_or_else(|e| e.into_inner());
        let old = std::mem::replace(&mut *w, ws);
        old.stop();
        old
    }

    /// Forgets the drawing's history (another network is served).
    pub(crate) fn forget_drawn(&self) {
        let mut h = self.history();
        h.past.clear();
        h.future.clear();
    }
}
