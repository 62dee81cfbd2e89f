//! The HTTP API: routes, handlers and the JSON errors every bad request gets. The greedy's
//! routes are in [`greedy`], the export's in [`export`].

mod export;
mod greedy;

use crate::design::{Design, DesignError, Edited, Summary};
use crate::greedy::Runner;
use axum::Router;
use axum::body::Bytes;
use axum::extract::rejection::BytesRejection;
use axum::extract::{DefaultBodyLimit, FromRef, State};
use axum::http::{Method, StatusCode, Uri, header};
use axum::response::{Html, IntoResponse, Response};
use axum::routing::{get, post};
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::sync::Arc;

/// The largest request body accepted (a list of every curve id of a large network fits).
pub const BODY_LIMIT: usize = 1 << 20;

/// The endpoints and their methods, as the 404 and 405 answers list them.
const ENDPOINTS: &[(&str, &str)] = &[
    ("/api/state", "GET"),
    ("/api/set", "POST"),
    ("/api/toggle", "POST"),
    ("/api/mode", "GET"),
    ("/api/network", "GET"),
    ("/api/greedy", "GET, POST"),
    ("/api/greedy/cancel", "POST"),
    ("/api/greedy/iterations", "GET"),
    ("/api/greedy/step", "POST"),
    ("/api/export", "GET"),
];

/// What the handlers share: the design and its greedy.
#[derive(Clone, Debug)]
pub struct AppState {
    /// The network being designed and its current structure.
    pub design: Arc<Design>,
    /// The greedy runs on it.
    pub greedy: Arc<Runner>,
}

impl AppState {
    /// The state of `design`, no greedy run yet.
    pub fn new(design: Design) -> Self {
        AppState {
            design: Arc::new(design),
            greedy: Arc::new(Runner::default()),
        }
    }
}

impl FromRef<AppState> for Arc<Design> {
    fn from_ref(s: &AppState) -> Self {
        s.design.clone()
    }
}

impl FromRef<AppState> for Arc<Runner> {
    fn from_ref(s: &AppState) -> Self {
        s.greedy.clone()
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
        .route("/api/export", get(export::export))
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
            DesignError::Analysis(_) => StatusCode::INTERNAL_SERVER_ERROR,
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

/// A summary with the server-side time of its computation.
#[derive(Serialize)]
pub(crate) struct EditAnswer {
    #[serde(flatten)]
    summary: Summary,
    elapsed_ms: f64,
    /// Where the answer came from: the cache, a warm start or the drawn state.
    from: crate::design::Source,
}

impl From<Edited> for EditAnswer {
    fn from(e: Edited) -> Self {
        EditAnswer {
            summary: e.summary,
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
    if !value.is_object() {
        return Err(ApiError::new(
            StatusCode::BAD_REQUEST,
            "malformed JSON body: expected an object such as {\"curves\": [0, 1]}",
        ));
    }
    serde_json::from_value(value).map_err(malformed)
}

/// Runs `f` on the design off the async runtime (the analyses take up to seconds).
async fn blocking<T: Send + 'static>(
    design: Arc<Design>,
    f: impl FnOnce(&Design) -> Result<T, DesignError> + Send + 'static,
) -> Result<T, ApiError> {
    off_runtime(move || f(&design).map_err(ApiError::from)).await
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

async fn index() -> Html<&'static str> {
    Html(INDEX)
}

async fn state(State(design): State<Arc<Design>>) -> ApiResult<Summary> {
    let s = blocking(design, |d| Ok(d.current().summary.clone())).await?;
    Ok(axum::Json(s))
}

async fn set(
    State(design): State<Arc<Design>>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<EditAnswer> {
    let SetBody { curves } = parse(body)?;
    let e = blocking(design, move |d| d.set(&curves)).await?;
    Ok(axum::Json(e.into()))
}

async fn toggle(
    State(design): State<Arc<Design>>,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<EditAnswer> {
    let ToggleBody { curve } = parse(body)?;
    let e = blocking(design, move |d| d.toggle(curve)).await?;
    Ok(axum::Json(e.into()))
}

async fn mode(State(design): State<Arc<Design>>) -> ApiResult<ModeAnswer> {
    let m = blocking(design, |d| {
        let c = d.current();
        Ok(ModeAnswer {
            curves: c.summary.curves.clone(),
            lambda: c.summary.lambda,
            status: c.summary.status,
            mode: c.mode.clone(),
            displacement: c.displacement.clone(),
        })
    })
    .await?;
    Ok(axum::Json(m))
}

async fn network(State(design): State<Arc<Design>>) -> ApiResult<NetworkAnswer> {
    let n = blocking(design, |d| {
        let net = d.analyzer().network();
        Ok(NetworkAnswer {
            positions: net.rest_coordinates(),
            curves: net.rods.iter().map(|r| r.vertices.clone()).collect(),
            closed: net.rods.iter().map(|r| r.closed).collect(),
            lengths: net.rest_lengths(),
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

async fn method_not_allowed(method: Method, uri: Uri) -> Response {
    let allowed = ENDPOINTS
        .iter()
        .find(|(path, _)| *path == uri.path())
        .map_or("GET", |e| e.1);
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

/// The page at `/` until the viewer is served: what the API offers.
const INDEX: &str = "<!doctype html><meta charset=utf-8><title>curvenet serve</title>\
<h1>curvenet serve</h1><p>The JSON API of this network: \
<a href=/api/state>GET /api/state</a>, POST /api/set <code>{\"curves\":[…]}</code>, \
POST /api/toggle <code>{\"curve\":id}</code>, <a href=/api/mode>GET /api/mode</a>, \
<a href=/api/network>GET /api/network</a>, POST /api/greedy <code>{\"budget\":0.5}</code>, \
<a href=/api/greedy>GET /api/greedy</a>, <a href=/api/greedy/iterations>GET \
/api/greedy/iterations</a>, POST /api/greedy/step <code>{\"iteration\":k}</code>, \
POST /api/greedy/cancel, <a href=\"/api/export?format=obj\">GET /api/export?format=obj</a> \
(csv, json).</p>";
