//! The HTTP API: routes, handlers and the JSON errors every bad request gets. The greedy's
//! routes are in [`greedy`], the local search's in [`local`], the slide's in [`slide`], the design constraints' in
//! [`constraints`], loading a run folder in [`run`], the export's in [`export`], drawing
//! (the design's curves added, deleted, moved; undo and redo of these) in [`draw`].
//!
//! Every handler works on the workspace current when its request arrives ([`AppState`]):
//! loading a run folder replaces it whole, and a request already answering finishes on the
//! workspace it started with.

mod constraints;
mod draw;
mod export;
mod greedy;
mod local;
mod run;
mod slide;

use crate::design::{DesignError, Edited, Evaluated, Summary};
use crate::workspace::Workspace;
use axum::Router;
use axum::body::Bytes;
use axum::extract::rejection::BytesRejection;
use axum::extract::{DefaultBodyLimit, FromRef, State};
use axum::http::{Method, StatusCode, Uri, header};
use axum::response::{Html, IntoResponse, Response};
use axum::routing::{get, post};
use curvenet::physics::PhysicalParams;
use curvenet::run_folder::RunsRoot;
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, RwLock};

/// The largest request body accepted (a list of every curve id of a large network fits).
pub const BODY_LIMIT: usize = 1 << 20;

/// The endpoints and their methods, as the 404 and 405 answers list them (a `{id}` segment
/// matches any one segment). Every route of [`router`] is here (a test asks each for the
/// methods it lacks).
pub const ENDPOINTS: &[(&str, &str)] = &[
    ("/", "GET"),
    ("/api/state", "GET"),
    ("/api/set", "POST"),
    ("/api/toggle", "POST"),
    ("/api/mode", "GET"),
    ("/api/network", "GET"),
    ("/api/greedy", "GET, POST"),
    ("/api/greedy/cancel", "POST"),
    ("/api/greedy/iterations", "GET"),
    ("/api/greedy/step", "POST"),
    ("/api/local", "GET, POST"),
    ("/api/local/cancel", "POST"),
    ("/api/local/adopt", "POST"),
    ("/api/slide", "GET, POST"),
    ("/api/slide/cancel", "POST"),
    ("/api/slide/adopt", "POST"),
    ("/api/constraints", "GET, POST"),
    ("/api/run", "POST"),
    ("/api/export", "GET"),
    ("/api/curves", "GET, POST"),
    ("/api/curves/{id}", "DELETE"),
    ("/api/curves/{id}/move", "POST"),
    ("/api/curves/preview", "POST"),
    ("/api/curves/undo", "POST"),
    ("/api/curves/redo", "POST"),
];

/// What a server is configured with beyond its first workspace.
#[derive(Clone, Debug, Default)]
pub struct ServeConfig {
    /// The folder whose run folders `POST /api/run` may load (`None`: loading is refused).
    /// Every file of a run folder is read through it, each path resolved inside it (`..` and
    /// symbolic links included), so nothing outside it is ever read.
    pub runs_root: Option<RunsRoot>,
    /// The physical mode's parameters applied to a run folder loaded (`None`: the paper's
    /// mode).
    pub physical: Option<PhysicalParams>,
}

/// What the handlers share: the current workspace (replaced whole when a run folder is
/// loaded) and the configuration.
#[derive(Clone, Debug)]
pub struct AppState {
    shared: Arc<Shared>,
}

#[derive(Debug)]
struct Shared {
    current: RwLock<Arc<Workspace>>,
    config: ServeConfig,
    /// A run folder is being loaded (one at a time).
    loading: AtomicBool,
    /// The workspaces drawing edits replaced, for undo and redo.
    history: std::sync::Mutex<draw::History>,
    /// Held by a drawing edit, an undo or a redo (one at a time, each on the workspace the
    /// last one left).
    drawing: tokio::sync::Mutex<()>,
}

impl AppState {
    /// The state serving `workspace` with `config`.
    pub fn new(workspace: Workspace, config: ServeConfig) -> Self {
        AppState {
            shared: Arc::new(Shared {
                current: RwLock::new(Arc::new(workspace)),
                config,
                loading: AtomicBool::new(false),
                history: Default::default(),
                drawing: tokio::sync::Mutex::new(()),
            }),
        }
    }

    /// The workspace served now.
    pub fn workspace(&self) -> Arc<Workspace> {
        let w = self
            .shared
            .current
            .read()
            .unwrap_or_else(|e| e.into_inner());
        Arc::clone(&w)
    }

    /// Serves `workspace` from now on (another network: the drawing's undo history is
    /// forgotten); the one it replaces is handed back (its searches asked to stop).
    pub fn replace(&self, workspace: Workspace) -> Arc<Workspace> {
        self.forget_drawn();
        let mut w = self
            .shared
            .current
            .write()
            .unwrap_or_else(|e| e.into_inner());
        let old = std::mem::replace(&mut *w, Arc::new(workspace));
        old.stop();
        old
    }

    /// The configuration.
    pub fn config(&self) -> &ServeConfig {
        &self.shared.config
    }
}

impl FromRef<AppState> for Arc<Workspace> {
    fn from_ref(s: &AppState) -> Self {
        s.workspace()
    }
}

/// The router of the API over `app`.
pub fn router(app: AppState) -> Router {
    Router::new()
        .route("/", get(index))
        .route("/api/state", get(state))
        .route("/api/set", post(set))
        .route("/api/toggle", post(toggle))
        .route("/api/mode", get(mode))
        .route("/api/network", get(network))
        .route("/api/greedy", get(greedy::progress).post(greedy::start))
        .route("/api/greedy/cancel", post(greedy::cancel))
        .route("/api/greedy/iterations", get(greedy::iterations))
        .route("/api/greedy/step", post(greedy::step))
        .route("/api/local", get(local::progress).post(local::start))
        .route("/api/local/cancel", post(local::cancel))
        .route("/api/local/adopt", post(local::adopt))
        .route("/api/slide", get(slide::progress).post(slide::start))
        .route("/api/slide/cancel", post(slide::cancel))
        .route("/api/slide/adopt", post(slide::adopt))
        .route(
            "/api/constraints",
            get(constraints::get).post(constraints::set),
        )
        .route("/api/run", post(run::load))
        .route("/api/export", get(export::export))
        .route("/api/curves", get(draw::list).post(draw::add))
        .route("/api/curves/preview", post(draw::preview))
        .route("/api/curves/undo", post(draw::undo))
        .route("/api/curves/redo", post(draw::redo))
        .route("/api/curves/{id}", axum::routing::delete(draw::delete))
        .route("/api/curves/{id}/move", post(draw::move_curve))
        .fallback(not_found)
        .method_not_allowed_fallback(method_not_allowed)
        .layer(DefaultBodyLimit::max(BODY_LIMIT))
        .with_state(app)
}

/// An error answered as `{"error": message}` with its status.
#[derive(Debug)]
pub struct ApiError {
    status: StatusCode,
    message: String,
}

impl ApiError {
    pub(crate) fn new(status: StatusCode, message: impl Into<String>) -> Self {
        ApiError {
            status,
            message: message.into(),
        }
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let body = serde_json::json!({ "error": self.message });
        (self.status, axum::Json(body)).into_response()
    }
}

impl From<DesignError> for ApiError {
    fn from(e: DesignError) -> Self {
        let status = match e {
            DesignError::UnknownCurve { .. } | DesignError::Empty => {
                StatusCode::UNPROCESSABLE_ENTITY
            }
            DesignError::Analysis(_) | DesignError::Physical(_) => {
                StatusCode::INTERNAL_SERVER_ERROR
            }
        };
        ApiError::new(status, e.to_string())
    }
}

/// A handler's answer: JSON or an [`ApiError`].
pub(crate) type ApiResult<T> = Result<axum::Json<T>, ApiError>;

/// The body of `POST /api/set`.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SetBody {
    curves: Vec<usize>,
}

/// The body of `POST /api/toggle`.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ToggleBody {
    curve: usize,
}

/// A state: the summary and, with design constraints in force, the structure's margins.
#[derive(Serialize)]
pub(crate) struct StateAnswer {
    #[serde(flatten)]
    summary: Summary,
    /// `{"met", "margins"}` of the session's constraints (absent when none is in force).
    #[serde(skip_serializing_if = "Option::is_none")]
    constraints: Option<serde_json::Value>,
}

impl StateAnswer {
    /// The state of `structure` in `ws`.
    pub(crate) fn of(ws: &Workspace, structure: &Evaluated) -> Self {
        let net = ws.design.analyzer().network();
        let s = &structure.summary;
        StateAnswer {
            summary: s.clone(),
            constraints: ws.constraints().margins(net, structure),
        }
    }
}

/// A state with the server-side time of its computation.
#[derive(Serialize)]
pub(crate) struct EditAnswer {
    #[serde(flatten)]
    state: StateAnswer,
    elapsed_ms: f64,
    /// Where the answer came from: the cache, a warm start or the drawn state.
    from: crate::design::Source,
}

impl EditAnswer {
    /// The answer to the edit `e` in `ws`.
    pub(crate) fn of(ws: &Workspace, e: &Edited) -> Self {
        EditAnswer {
            state: StateAnswer::of(ws, &e.structure),
            elapsed_ms: e.elapsed.as_secs_f64() * 1e3,
            from: e.source,
        }
    }
}

/// `GET /api/mode`: the current structure's worst-case mode and equilibrium, for drawing.
#[derive(Serialize)]
struct ModeAnswer {
    curves: Vec<usize>,
    lambda: f64,
    status: crate::design::Status,
    /// The unit eigenvector of `λ`, 3 numbers per vertex.
    mode: Vec<f64>,
    /// Displacements from the rest state at equilibrium, 3 numbers per vertex.
    displacement: Vec<f64>,
    /// The deflection under the gravity load at the equilibrium (`null` when the structure
    /// is not positive definite).
    gravity: Option<Gravity>,
}

/// A gravity deflection for drawing.
#[derive(Serialize)]
pub(crate) struct Gravity {
    /// Displacements under the load, 3 numbers per vertex.
    pub(crate) displacement: Vec<f64>,
    /// The largest vertex displacement.
    pub(crate) max_displacement: f64,
    /// Where it occurs.
    pub(crate) vertex: usize,
}

impl Gravity {
    /// The gravity deflection of `structure` (computed on first use).
    pub(crate) fn of(ws: &Workspace, structure: &Evaluated) -> Option<Self> {
        let (u, summary) = structure.gravity(ws.design.analyzer())?;
        Some(Gravity {
            displacement: u.to_vec(),
            max_displacement: summary.max_displacement,
            vertex: summary.vertex,
        })
    }
}

/// `GET /api/network`: the network's geometry, for drawing.
#[derive(Serialize)]
struct NetworkAnswer {
    /// Rest positions, 3 numbers per vertex.
    positions: Vec<f64>,
    /// Each curve's vertices in order (a closed curve's last edge returns to its first).
    curves: Vec<Vec<u32>>,
    /// Which curves are closed.
    closed: Vec<bool>,
    /// Each curve's rest length.
    lengths: Vec<f64>,
    /// When the network is a slid run's: how it slid and the curves before.
    #[serde(skip_serializing_if = "Option::is_none")]
    slid: Option<SlidAnswer>,
}

/// A slid run's slide, as `GET /api/network` answers it.
#[derive(Serialize)]
struct SlidAnswer {
    /// The slide's record (`result.json`'s `slide`: `lambda_before`, `lambda_after`,
    /// `largest_move`, `max_move`, `joints_added`, ...).
    record: curvenet::run_folder::schema::SlideRecord,
    /// The curves before they slid: each its points (`[x, y, z]`) and whether it is closed.
    before: Vec<BeforeCurve>,
}

/// One curve before it slid.
#[derive(Serialize)]
struct BeforeCurve {
    points: Vec<[f64; 3]>,
    closed: bool,
}

/// The JSON of `body`, or a 400 naming what is wrong with it (a 413 when it is too large).
pub(crate) fn parse<T: DeserializeOwned>(
    body: Result<Bytes, BytesRejection>,
) -> Result<T, ApiError> {
    let body = body.map_err(|r| ApiError::new(r.status(), r.body_text()))?;
    let malformed = |e: serde_json::Error| {
        ApiError::new(StatusCode::BAD_REQUEST, format!("malformed JSON body: {e}"))
    };
    // An object, not the array serde would also read a struct from.
    let value: serde_json::Value = serde_json::from_slice(&body).map_err(malformed)?;
    // serde_json keeps the last of a key given twice: refused, naming it.
    if let Some(d) = std::str::from_utf8(&body)
        .ok()
        .and_then(curvenet::io::duplicate_key)
    {
        return Err(ApiError::new(
            StatusCode::BAD_REQUEST,
            format!(
                "malformed JSON body: {} (line {}, column {})",
                d.describe(),
                d.line,
                d.column
            ),
        ));
    }
    if !value.is_object() {
        return Err(ApiError::new(
            StatusCode::BAD_REQUEST,
            "malformed JSON body: expected an object such as {\"curves\": [0, 1]}",
        ));
    }
    serde_json::from_value(value).map_err(malformed)
}

/// Runs `f` on the workspace off the async runtime (the analyses take up to seconds).
async fn blocking<T: Send + 'static>(
    ws: Arc<Workspace>,
    f: impl FnOnce(&Workspace) -> Result<T, DesignError> + Send + 'static,
) -> Result<T, ApiError> {
    off_runtime(move || f(&ws).map_err(ApiError::from)).await
}

/// Runs `f` on a blocking thread, off the async runtime.
pub(crate) async fn off_runtime<T: Send + 'static>(
    f: impl FnOnce() -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    tokio::task::spawn_blocking(f).await.map_err(|e| {
        ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("the computation stopped: {e}"),
        )
    })?
}

/// `GET /`: the app page over the current structure.
async fn index(State(ws): State<Arc<Workspace>>) -> Result<Html<String>, ApiError> {
    let page = off_runtime(move || {
        crate::app::page(&ws).map_err(|e| ApiError::new(StatusCode::INTERNAL_SERVER_ERROR, e))
    })
    .await?;
    Ok(Html(page))
}

async fn state(State(ws): State<Arc<Workspace>>) -> ApiResult<StateAnswer> {
    let s = blocking(ws, |w| Ok(StateAnswer::of(w, &w.design.current()))).await?;
    Ok(axum::Json(s))
}

async fn set(
    State(ws): State<Arc<Workspace>>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<EditAnswer> {
    let SetBody { curves } = parse(body)?;
    let e = blocking(ws, move |w| Ok(EditAnswer::of(w, &w.design.set(&curves)?))).await?;
    Ok(axum::Json(e))
}

async fn toggle(
    State(ws): State<Arc<Workspace>>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<EditAnswer> {
    let ToggleBody { curve } = parse(body)?;
    let e = blocking(ws, move |w| Ok(EditAnswer::of(w, &w.design.toggle(curve)?))).await?;
    Ok(axum::Json(e))
}

async fn mode(State(ws): State<Arc<Workspace>>) -> ApiResult<ModeAnswer> {
    let m = blocking(ws, |w| {
        let c = w.design.current();
        Ok(ModeAnswer {
            curves: c.summary.curves.clone(),
            lambda: c.summary.lambda,
            status: c.summary.status,
            mode: c.mode.clone(),
            displacement: c.displacement.clone(),
            gravity: Gravity::of(w, &c),
        })
    })
    .await?;
    Ok(axum::Json(m))
}

async fn network(State(ws): State<Arc<Workspace>>) -> ApiResult<NetworkAnswer> {
    let n = blocking(ws, |w| {
        let net = w.design.analyzer().network();
        Ok(NetworkAnswer {
            positions: net.rest_coordinates(),
            curves: net.rods.iter().map(|r| r.vertices.clone()).collect(),
            closed: net.rods.iter().map(|r| r.closed).collect(),
            lengths: net.rest_lengths(),
            slid: w.slid.as_ref().map(|s| SlidAnswer {
                record: s.record.clone(),
                before: (s.before.iter())
                    .map(|c| BeforeCurve {
                        points: c.points.iter().map(|p| p.to_array()).collect(),
                        closed: c.closed,
                    })
                    .collect(),
            }),
        })
    })
    .await?;
    Ok(axum::Json(n))
}

async fn not_found(method: Method, uri: Uri) -> ApiError {
    let list: Vec<String> = ENDPOINTS
        .iter()
        .map(|(path, methods)| format!("{methods} {path}"))
        .collect();
    ApiError::new(
        StatusCode::NOT_FOUND,
        format!(
            "no such endpoint: {method} {}; the API is {}",
            uri.path(),
            list.join(", ")
        ),
    )
}

/// The methods the route of `path` allows: a route without a `{id}` segment first (as the
/// router matches them), `None` for a path no route has.
pub fn allowed_methods(path: &str) -> Option<&'static str> {
    let matches = |route: &str| {
        let (a, b): (Vec<&str>, Vec<&str>) =
            (route.split('/').collect(), path.split('/').collect());
        a.len() == b.len()
            && a.iter()
                .zip(&b)
                .all(|(r, p)| r == p || (*r == "{id}" && !p.is_empty()))
    };
    let exact = ENDPOINTS.iter().find(|(route, _)| *route == path);
    exact
        .or_else(|| ENDPOINTS.iter().find(|(route, _)| matches(route)))
        .map(|e| e.1)
}

async fn method_not_allowed(method: Method, uri: Uri) -> Response {
    let allowed = allowed_methods(uri.path()).unwrap_or("GET");
    let mut r = ApiError::new(
        StatusCode::METHOD_NOT_ALLOWED,
        format!("{method} {}: use {allowed}", uri.path()),
    )
    .into_response();
    if let Ok(v) = header::HeaderValue::from_str(allowed) {
        r.headers_mut().insert(header::ALLOW, v);
    }
    r
}
