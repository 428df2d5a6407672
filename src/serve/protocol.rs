//! The HTTP side: the page, the WebSocket, and the rules every request passes (host, token,
//! origin, sizes, connections). A malformed message closes its own connection, never the
//! server.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use axum::Router;
use axum::extract::ws::{CloseFrame, Message, WebSocket, WebSocketUpgrade};
use axum::extract::{DefaultBodyLimit, Request, State};
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use serde::Deserialize;
use tokio::sync::broadcast::error::RecvError;

use super::engine::{Engine, MAX_PAGE_OVERRIDES, Request as EngineRequest, saveable};
use super::messages::ToPage;
use super::{Access, MAX_CONNECTIONS, MAX_MESSAGE_BYTES, ServeOptions, page};
use crate::scene::file::Override;

/// Largest HTTP request body read (the server reads none: pages talk over the WebSocket).
const MAX_BODY_BYTES: usize = 16 << 10;

/// How long a page may take to accept a message before it is dropped.
const SEND_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(30);

/// WebSocket close codes (RFC 6455, 7.4.1).
const CLOSE_UNSUPPORTED: u16 = 1003;
const CLOSE_POLICY: u16 = 1008;
const CLOSE_TRY_AGAIN: u16 = 1013;

pub struct AppState {
    engines: Engines,
    access: Access,
    connections: AtomicUsize,
}

/// Whose engine a page talks to.
pub enum Engines {
    /// One engine: every page sees and changes the same preview.
    Shared(Engine),
    /// A public server: each visitor's page has an engine of its own, started when it connects
    /// and closed when it goes, at most `most` at once.
    PerVisitor {
        options: Box<ServeOptions>,
        text: String,
        most: usize,
        /// Visitors' engines running: a place is freed when its engine's thread has ended,
        /// not when the page goes.
        visitors: Arc<AtomicUsize>,
    },
}

/// A visitor's place on a public server, held by their engine's thread.
struct Place(Arc<AtomicUsize>);

impl Place {
    /// A place, if fewer than `most` are taken.
    fn take(visitors: &Arc<AtomicUsize>, most: usize) -> Option<Place> {
        let taken = visitors.fetch_add(1, Ordering::Relaxed);
        let place = Place(visitors.clone());
        (taken < most).then_some(place)
    }
}

impl Drop for Place {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::Relaxed);
    }
}

impl AppState {
    pub fn new(engines: Engines, access: Access) -> AppState {
        AppState {
            engines,
            access,
            connections: AtomicUsize::new(0),
        }
    }

    fn public(&self) -> bool {
        matches!(self.engines, Engines::PerVisitor { .. })
    }
}

/// What a page may send (JSON text messages). Unknown types and fields are malformed (serde
/// refuses unknown fields of struct variants only: the messages without fields are empty
/// structs).
#[derive(Debug, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ClientMessage {
    /// `--set KEY=VALUE` overrides, each replacing the page's earlier one of the same key.
    Set {
        set: Vec<String>,
    },
    /// Drops the page's overrides of these keys (all of them when empty).
    Unset {
        keys: Vec<String>,
    },
    /// New scene text.
    Text {
        text: String,
    },
    /// Writes the scene text to the scene file.
    WriteScene {},
    /// Shows this frame of the scene's `[animation]` (`null`: the scene as written).
    Frame {
        frame: Option<u32>,
    },
    /// Display exposure in stops (does not restart the accumulation).
    Exposure {
        stops: f64,
    },
    Inspect {
        x: u32,
        y: u32,
    },
    /// Adds the ray trajectory from this pixel to the scene text.
    Trajectory {
        x: u32,
        y: u32,
    },
    /// Renders to this file beside the scene file.
    Save {
        file: String,
    },
    /// Stops the render being saved.
    CancelSave {},
}

pub fn router(state: Arc<AppState>) -> Router {
    Router::new()
        .route("/", get(index))
        .route("/ws", get(socket))
        .fallback(|| async { (StatusCode::NOT_FOUND, "not found") })
        .layer(middleware::from_fn_with_state(state.clone(), guard))
        .layer(DefaultBodyLimit::max(MAX_BODY_BYTES))
        .with_state(state)
}

/// Whether the Host header names this machine (for a server on loopback: a page of another
/// site that rebinds its name to 127.0.0.1 is refused).
fn local_host(host: &str) -> bool {
    let name = match host.rsplit_once(':') {
        Some((name, port)) if port.chars().all(|c| c.is_ascii_digit()) => name,
        _ => host,
    };
    let name = name.trim_start_matches('[').trim_end_matches(']');
    name.eq_ignore_ascii_case("localhost")
        || name
            .parse::<std::net::IpAddr>()
            .is_ok_and(|ip| ip.is_loopback())
}

/// Compares without stopping at the first difference.
fn same(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0, |d, (x, y)| d | (x ^ y)) == 0
}

/// The rules before any route: a loopback server answers only requests for a local host
/// name; a server reachable from elsewhere only those with the token.
async fn guard(State(state): State<Arc<AppState>>, request: Request, next: Next) -> Response {
    let host = request
        .headers()
        .get(header::HOST)
        .and_then(|h| h.to_str().ok())
        .unwrap_or("");
    if state.access.loopback && !local_host(host) {
        return (StatusCode::FORBIDDEN, "forbidden: not a local host name").into_response();
    }
    if let Some(token) = &state.access.token {
        let given = request
            .uri()
            .query()
            .unwrap_or("")
            .split('&')
            .find_map(|p| p.strip_prefix("token="))
            .unwrap_or("");
        if !same(given.as_bytes(), token.as_bytes()) {
            return (
                StatusCode::FORBIDDEN,
                "forbidden: the access token printed by timbre serve is needed (?token=...)",
            )
                .into_response();
        }
    }
    next.run(request).await
}

async fn index(State(state): State<Arc<AppState>>) -> Response {
    let mut response = page::PAGE.into_response();
    let headers = response.headers_mut();
    for (name, value) in [
        (header::CONTENT_TYPE, "text/html; charset=utf-8"),
        (header::CACHE_CONTROL, "no-store"),
        // The token is in the address: never send it elsewhere.
        (header::REFERRER_POLICY, "no-referrer"),
        (
            header::CONTENT_SECURITY_POLICY,
            // A public server's page may be embedded in any site's page (an <iframe>).
            if state.public() {
                "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; \
                 img-src 'self' blob: data:; connect-src 'self'; frame-ancestors *"
            } else {
                "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; \
                 img-src 'self' blob: data:; connect-src 'self'; frame-ancestors 'none'"
            },
        ),
        (header::X_CONTENT_TYPE_OPTIONS, "nosniff"),
    ] {
        headers.insert(name, HeaderValue::from_static(value));
    }
    response
}

/// Closes a visitor's engine when their connection ends, however it ends.
struct Closing(Option<Engine>);

impl Drop for Closing {
    fn drop(&mut self) {
        if let Some(engine) = &self.0 {
            engine.close();
        }
    }
}

/// Counts a connection for as long as it lives.
struct Counted(Arc<AppState>);

impl Drop for Counted {
    fn drop(&mut self) {
        self.0.connections.fetch_sub(1, Ordering::Relaxed);
    }
}

async fn socket(
    State(state): State<Arc<AppState>>,
    headers: HeaderMap,
    upgrade: WebSocketUpgrade,
) -> Response {
    // Browsers send the page's origin: only this server's own page may connect.
    if let Some(origin) = headers.get(header::ORIGIN) {
        let host = headers.get(header::HOST).and_then(|h| h.to_str().ok());
        let own = host.is_some_and(|h| {
            origin.to_str().is_ok_and(|o| {
                o.strip_prefix("http://")
                    .or_else(|| o.strip_prefix("https://"))
                    == Some(h)
            })
        });
        if !own {
            return (StatusCode::FORBIDDEN, "forbidden: another site's page").into_response();
        }
    }
    // Pages connected at once: a public server's visitors and the pages being told it is busy.
    let most = match &state.engines {
        Engines::Shared(_) => MAX_CONNECTIONS,
        Engines::PerVisitor { most, .. } => most + MAX_CONNECTIONS,
    };
    if state.connections.fetch_add(1, Ordering::Relaxed) >= most {
        state.connections.fetch_sub(1, Ordering::Relaxed);
        return (
            StatusCode::SERVICE_UNAVAILABLE,
            format!("at most {most} pages at once"),
        )
            .into_response();
    }
    let counted = Counted(state.clone());
    if let Engines::PerVisitor { most, visitors, .. } = &state.engines {
        let most = *most;
        let Some(place) = Place::take(visitors, most) else {
            // The page is told so, and says so.
            return upgrade.on_upgrade(move |mut socket| async move {
                let message = format!(
                    "busy: this server shows the scene to {most} visitors at once; try again in a while"
                );
                let _ = deliver(&mut socket, json(&ToPage::Busy { message }.text())).await;
                close(&mut socket, CLOSE_TRY_AGAIN, "busy").await;
                drop(counted);
            });
        };
        return upgrade
            .max_message_size(MAX_MESSAGE_BYTES)
            .max_frame_size(MAX_MESSAGE_BYTES)
            .on_upgrade(move |socket| connection(counted, Some(place), socket));
    }
    upgrade
        .max_message_size(MAX_MESSAGE_BYTES)
        .max_frame_size(MAX_MESSAGE_BYTES)
        .on_upgrade(move |socket| connection(counted, None, socket))
}

/// Sends `message`; false if the page is gone or does not take it in time.
async fn deliver(socket: &mut WebSocket, message: Message) -> bool {
    matches!(
        tokio::time::timeout(SEND_TIMEOUT, socket.send(message)).await,
        Ok(Ok(()))
    )
}

fn json(text: &str) -> Message {
    Message::Text(text.into())
}

async fn close(socket: &mut WebSocket, code: u16, reason: &str) {
    // Close reasons are at most 123 bytes.
    let mut reason = reason.to_string();
    while reason.len() > 120 {
        reason.pop();
    }
    let _ = socket
        .send(Message::Close(Some(CloseFrame {
            code,
            reason: reason.into(),
        })))
        .await;
}

/// One page: the latest state and frame, then every message both ways until it goes. A
/// public server's visitor (with their `place`) gets an engine of their own.
async fn connection(counted: Counted, place: Option<Place>, mut socket: WebSocket) {
    let state = counted.0.clone();
    let engine = match (&state.engines, place) {
        (Engines::PerVisitor { options, text, .. }, Some(place)) => {
            match Engine::start(options, text.clone(), place) {
                Ok(engine) => engine,
                Err(e) => return close(&mut socket, CLOSE_TRY_AGAIN, &e.to_string()).await,
            }
        }
        (Engines::Shared(engine), _) => engine.clone(),
        (Engines::PerVisitor { .. }, None) => unreachable!("a visitor connects with a place"),
    };
    // A visitor's engine ends with their page.
    let _closing = Closing(state.public().then(|| engine.clone()));
    let mut subscription = engine.subscribe();
    // The newest frame now, then whenever there is a newer one and the page has taken the last
    // (with the first of each scene, if it was passed over).
    let now = subscription.frames.borrow_and_update().clone();
    let mut shown = now.generation;
    for m in subscription
        .now
        .iter()
        .map(|t| json(t))
        .chain(now.newest.map(Message::Binary))
    {
        if !deliver(&mut socket, m).await {
            return;
        }
    }
    loop {
        tokio::select! {
            incoming = socket.recv() => match incoming {
                Some(Ok(Message::Text(text))) => {
                    match serde_json::from_str::<ClientMessage>(text.as_str()) {
                        Ok(message) => {
                            if let Some(reply) = handle(&engine, message)
                                && !deliver(&mut socket, json(&reply)).await
                            {
                                return;
                            }
                        }
                        Err(e) => {
                            return close(&mut socket, CLOSE_POLICY, &format!("malformed message: {e}")).await;
                        }
                    }
                }
                Some(Ok(Message::Binary(_))) => {
                    return close(&mut socket, CLOSE_UNSUPPORTED, "binary messages are not accepted").await;
                }
                Some(Ok(Message::Ping(_) | Message::Pong(_))) => {}
                // Closed, or broken (a message over the size limit, a protocol error).
                Some(Ok(Message::Close(_))) | Some(Err(_)) | None => return,
            },
            out = subscription.json.recv() => match out {
                Ok(text) => {
                    if !deliver(&mut socket, json(&text)).await {
                        return;
                    }
                }
                // Too far behind: it gets the latest state (and error) again.
                Err(RecvError::Lagged(_)) => {
                    let fresh = engine.subscribe();
                    subscription.json = fresh.json;
                    for text in fresh.now {
                        if !deliver(&mut socket, json(&text)).await {
                            return;
                        }
                    }
                }
                Err(RecvError::Closed) => return,
            },
            changed = subscription.frames.changed() => {
                if changed.is_err() {
                    return;
                }
                let frames = subscription.frames.borrow_and_update().clone();
                let first = frames
                    .first
                    .filter(|first| frames.generation != shown && frames.newest.as_ref() != Some(first));
                shown = frames.generation;
                for frame in first.into_iter().chain(frames.newest) {
                    if !deliver(&mut socket, Message::Binary(frame)).await {
                        return;
                    }
                }
            }
        }
    }
}

/// Passes a page's message to the engine; the answer for this page alone, if any (a value the
/// engine cannot take).
fn handle(engine: &Engine, message: ClientMessage) -> Option<String> {
    let result = match message {
        ClientMessage::Set { set } if set.len() > MAX_PAGE_OVERRIDES => Err(format!(
            "at most {MAX_PAGE_OVERRIDES} --set values at once, got {}",
            set.len()
        )),
        ClientMessage::Set { set } => set
            .iter()
            .map(|s| s.parse().map_err(|e| format!("--set {e}")))
            .collect::<Result<Vec<Override>, String>>()
            .and_then(|overrides| engine.set(overrides)),
        ClientMessage::Unset { keys } => {
            engine.unset(&keys);
            Ok(())
        }
        ClientMessage::Text { text } => {
            engine.text(text);
            Ok(())
        }
        ClientMessage::WriteScene {} => engine.request(EngineRequest::WriteScene),
        ClientMessage::Frame { frame } => {
            engine.frame(frame);
            Ok(())
        }
        ClientMessage::Exposure { stops } => exposure(stops).map(|stops| engine.exposure(stops)),
        ClientMessage::Inspect { x, y } => engine.request(EngineRequest::Inspect { x, y }),
        ClientMessage::Trajectory { x, y } => engine.request(EngineRequest::Trajectory { x, y }),
        ClientMessage::Save { file } => {
            saveable(&file).and_then(|()| engine.request(EngineRequest::Save { file }))
        }
        ClientMessage::CancelSave {} => {
            engine.cancel_save();
            Ok(())
        }
    };
    result.err().map(|e| ToPage::notice(Err(e)).text())
}

/// An exposure the page may set: from -30 to 30 stops (a number out of range is echoed in
/// short: `1e308`, not 309 digits).
fn exposure(stops: f64) -> Result<f64, String> {
    if stops.is_finite() && stops.abs() <= 30.0 {
        Ok(stops)
    } else {
        Err(format!("exposure {stops:?}: from -30 to 30 stops"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn host_names_of_this_machine_are_local_and_others_not() {
        for host in [
            "localhost",
            "localhost:8080",
            "127.0.0.1:1",
            "127.1.2.3",
            "[::1]:80",
            "LOCALHOST",
        ] {
            assert!(local_host(host), "{host}");
        }
        for host in [
            "",
            "evil.example:8080",
            "localhost.evil.example",
            "192.168.1.2:80",
            "[::2]:80",
        ] {
            assert!(!local_host(host), "{host}");
        }
    }

    #[test]
    fn tokens_are_compared_whole() {
        assert!(same(b"abc", b"abc"));
        assert!(!same(b"abc", b"abd"));
        assert!(!same(b"abc", b"ab"));
        assert!(!same(b"", b"a"));
    }

    #[test]
    fn an_exposure_out_of_range_is_echoed_in_short() {
        assert_eq!(exposure(-30.0), Ok(-30.0));
        assert_eq!(
            exposure(1e308),
            Err("exposure 1e308: from -30 to 30 stops".into())
        );
        assert_eq!(
            exposure(-30.5),
            Err("exposure -30.5: from -30 to 30 stops".into())
        );
    }

    #[test]
    fn messages_without_fields_take_no_fields() {
        for (text, message) in [
            (r#"{"type":"write_scene"}"#, ClientMessage::WriteScene {}),
            (r#"{"type":"cancel_save"}"#, ClientMessage::CancelSave {}),
        ] {
            assert_eq!(
                serde_json::from_str::<ClientMessage>(text).unwrap(),
                message
            );
            let extra = text.replace('}', r#","evil":1}"#);
            assert!(
                serde_json::from_str::<ClientMessage>(&extra).is_err(),
                "{extra}"
            );
        }
    }

    #[test]
    fn messages_of_unknown_types_or_fields_are_malformed() {
        let ok: ClientMessage = serde_json::from_str(r#"{"type":"inspect","x":1,"y":2}"#).unwrap();
        assert_eq!(ok, ClientMessage::Inspect { x: 1, y: 2 });
        for bad in [
            r#"{"type":"inspect","x":-1,"y":2}"#,
            r#"{"type":"inspect","x":1,"y":2,"z":3}"#,
            r#"{"type":"format_disk"}"#,
            r#"{"x":1}"#,
            "not json",
        ] {
            assert!(serde_json::from_str::<ClientMessage>(bad).is_err(), "{bad}");
        }
    }
}
