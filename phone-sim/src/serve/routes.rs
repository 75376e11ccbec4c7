//! The HTTP routes of `conquest serve`.
//!
//! | route | does |
//! |---|---|
//! | `GET /` , `/app.js`, `/style.css` | the page (built into the binary) |
//! | `GET /ws` | WebSocket: a snapshot, then frames; commands in |
//! | `GET /api/state` | the snapshot as JSON |
//! | `POST /api/control` | one command (JSON); 400 with the reason if refused |
//! | `GET /api/export?format=field\|sep` | the explored map as a file |
//! | `POST /api/import?name=F` | a field file (body) to offer for new runs |

use super::AppState;
use super::api::{Command, Push};
use super::files::MAX_IMPORT_BYTES;
use super::session::Request;
use axum::Json;
use axum::body::Bytes;
use axum::extract::ws::{Message as WsMessage, WebSocket, WebSocketUpgrade};
use axum::extract::{DefaultBodyLimit, Query, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use serde::Deserialize;
use tokio::sync::{broadcast, oneshot};

const INDEX_HTML: &str = include_str!("../../web/index.html");
const APP_JS: &str = include_str!("../../web/app.js");
const STYLE_CSS: &str = include_str!("../../web/style.css");

/// The router over the session behind `state`.
pub fn router(state: AppState) -> axum::Router {
    axum::Router::new()
        .route(
            "/",
            get(|| async { page("text/html; charset=utf-8", INDEX_HTML) }),
        )
        .route(
            "/app.js",
            get(|| async { page("text/javascript; charset=utf-8", APP_JS) }),
        )
        .route(
            "/style.css",
            get(|| async { page("text/css; charset=utf-8", STYLE_CSS) }),
        )
        .route("/ws", get(ws))
        .route("/api/state", get(state_json))
        .route("/api/control", post(control))
        .route("/api/export", get(export))
        .route("/api/import", post(import))
        .layer(DefaultBodyLimit::max(MAX_IMPORT_BYTES))
        .with_state(state)
}

fn page(kind: &'static str, body: &'static str) -> Response {
    ([(header::CONTENT_TYPE, kind)], body).into_response()
}

fn error(status: StatusCode, message: impl Into<String>) -> Response {
    (status, Json(serde_json::json!({ "error": message.into() }))).into_response()
}

/// Sends a request to the session and waits for its answer.
async fn ask<T>(
    state: &AppState,
    make: impl FnOnce(oneshot::Sender<T>) -> Request,
) -> Result<T, Response> {
    let (tx, rx) = oneshot::channel();
    state
        .requests
        .send(make(tx))
        .map_err(|_| error(StatusCode::SERVICE_UNAVAILABLE, "the session has ended"))?;
    rx.await
        .map_err(|_| error(StatusCode::SERVICE_UNAVAILABLE, "the session has ended"))
}

async fn state_json(State(state): State<AppState>) -> Response {
    match ask(&state, Request::Snapshot).await {
        Ok(s) => Json(s).into_response(),
        Err(r) => r,
    }
}

async fn control(State(state): State<AppState>, body: Bytes) -> Response {
    let command: Command = match serde_json::from_slice(&body) {
        Ok(c) => c,
        Err(e) => return error(StatusCode::BAD_REQUEST, format!("bad command: {e}")),
    };
    match ask(&state, |tx| Request::Command(command, tx)).await {
        Ok(Ok(())) => Json(serde_json::json!({ "ok": true })).into_response(),
        Ok(Err(e)) => error(StatusCode::BAD_REQUEST, e),
        Err(r) => r,
    }
}

#[derive(Deserialize)]
struct ExportQuery {
    #[serde(default = "default_format")]
    format: String,
}

fn default_format() -> String {
    "field".into()
}

async fn export(State(state): State<AppState>, Query(q): Query<ExportQuery>) -> Response {
    match ask(&state, |tx| Request::Export(q.format, tx)).await {
        Ok(Ok((file, text))) => (
            [
                (
                    header::CONTENT_TYPE,
                    "text/plain; charset=utf-8".to_string(),
                ),
                (
                    header::CONTENT_DISPOSITION,
                    format!("attachment; filename=\"{file}\""),
                ),
            ],
            text,
        )
            .into_response(),
        Ok(Err(e)) => error(StatusCode::BAD_REQUEST, e),
        Err(r) => r,
    }
}

#[derive(Deserialize)]
struct ImportQuery {
    name: String,
}

async fn import(
    State(state): State<AppState>,
    Query(q): Query<ImportQuery>,
    body: Bytes,
) -> Response {
    match ask(&state, |tx| Request::Import(q.name, body.to_vec(), tx)).await {
        Ok(Ok(choice)) => Json(choice).into_response(),
        Ok(Err(e)) => error(StatusCode::BAD_REQUEST, e),
        Err(r) => r,
    }
}

async fn ws(State(state): State<AppState>, upgrade: WebSocketUpgrade) -> Response {
    upgrade.on_upgrade(move |socket| session_socket(state, socket))
}

/// One page's WebSocket: a snapshot, then every push; commands in. A page
/// that falls behind gets a fresh snapshot instead of the frames it missed.
async fn session_socket(state: AppState, mut socket: WebSocket) {
    // Subscribe before the snapshot so that nothing falls in between.
    let mut pushes = state.push.subscribe();
    if send_snapshot(&state, &mut socket).await.is_err() {
        return;
    }
    loop {
        tokio::select! {
            incoming = socket.recv() => {
                let Some(Ok(msg)) = incoming else { return };
                let text = match msg {
                    WsMessage::Text(t) => t.to_string(),
                    WsMessage::Close(_) => return,
                    _ => continue,
                };
                let reply = match serde_json::from_str::<Command>(&text) {
                    Ok(c) => match ask(&state, |tx| Request::Command(c, tx)).await {
                        Ok(Ok(())) => None,
                        Ok(Err(e)) => Some(e),
                        Err(_) => return,
                    },
                    Err(e) => Some(format!("bad command: {e}")),
                };
                if let Some(message) = reply {
                    let Ok(text) = serde_json::to_string(&Push::Error { message }) else {
                        continue;
                    };
                    if socket.send(WsMessage::Text(text.into())).await.is_err() {
                        return;
                    }
                }
            }
            push = pushes.recv() => match push {
                Ok(text) => {
                    if socket.send(WsMessage::Text(text.to_string().into())).await.is_err() {
                        return;
                    }
                }
                Err(broadcast::error::RecvError::Lagged(_)) => {
                    if send_snapshot(&state, &mut socket).await.is_err() {
                        return;
                    }
                }
                Err(broadcast::error::RecvError::Closed) => return,
            },
        }
    }
}

async fn send_snapshot(state: &AppState, socket: &mut WebSocket) -> Result<(), ()> {
    let snap = ask(state, Request::Snapshot).await.map_err(|_| ())?;
    let text = serde_json::to_string(&Push::Snapshot(snap)).map_err(|_| ())?;
    socket
        .send(WsMessage::Text(text.into()))
        .await
        .map_err(|_| ())
}
