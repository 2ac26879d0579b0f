//! The local web page of vpmap and its JSON API (`vpmap serve`): annotate a photo, see its
//! floor map, 3D model and a planned path live.
//!
//! [`Server`] serves the page (the files of `assets/`, embedded at compile time) and four
//! JSON endpoints, documented with their parameters, limits and response shapes in
//! `docs/web-api.md`:
//!
//! | endpoint | what | built on |
//! |---|---|---|
//! | `GET /api/example` | the bundled office scene and a photo of it | [`example`]: the scene's truth rendered through its camera |
//! | `POST /api/build` | scene JSON in; map, floor-plan SVG, glTF model, occupancy grid, camera out | `vpmap_metrology::map::build_map`, `vpmap_render`, `vpmap_raster::rasterize_map` (as `vpmap build`) |
//! | `POST /api/detect` | photo in; segments, vanishing points, camera and a scene out | `vpmap_vision::detect`, then `vpmap_vision::scene::detected_scene` (as `vpmap detect`) |
//! | `POST /api/plan` | scene, start and goal in; paths of several planners out | `vpmap_plan::PlannerKind` (MBPP with its bug tracks) |
//!
//! # Security
//! The server binds to the loopback address unless told otherwise, reads nothing from the
//! file system (the page is compiled in), limits every body's size and every image's
//! dimensions before decoding, refuses cross-origin requests (an `Origin` header that is not
//! the server's own) and, on loopback, requests whose `Host` is not a loopback name (DNS
//! rebinding). All heavy work runs on blocking threads, and a panic there becomes a 500
//! answer, not a dead server.
//!
//! # Bounded work
//! [`ServerLimits`]: a header read timeout (slow or idle connections are closed), a body
//! deadline (408), a declared `Content-Length` over the route's limit refused with 413 before
//! the body is read, a few slots per heavy endpoint (503 with `Retry-After` after a short
//! wait), time limits and budgets for the planners, and time limits for a room's fit and the
//! search for box proposals; all of these also stop when the client goes away. [`serve_until_ctrl_c`] makes the allocator give freed memory back
//! ([`return_freed_memory_promptly`]).
//!
//! # Modules
//! Bottom-up, each using only those before it: `response` (JSON answers), `error`
//! ([`ApiError`], [`WebError`]), `limits` ([`ServerLimits`], the slots), `memory`, `params`
//! (query strings and bodies), `state` (what every request shares, blocking work), [`example`],
//! `assets` (the page), `api` (inside: `answer`, `scene`, `plan`, `navigate`, `build`,
//! `detect`, `fuzzing`, then its `mod.rs`); this file binds, guards and routes.
//!
//! # Example
//! ```no_run
//! # async fn run() -> Result<(), vpmap_web::WebError> {
//! let server = vpmap_web::Server::bind("127.0.0.1:0".parse().unwrap(), vpmap_web::ServeOptions::default()).await?;
//! println!("serving http://{}/", server.local_addr());
//! server.serve(std::future::pending()).await
//! # }
//! ```
#![deny(missing_docs)]

mod api;
mod assets;
mod error;
pub mod example;
mod limits;
mod memory;
mod params;
mod photos;
mod response;
mod state;

#[doc(hidden)]
pub use api::fuzzing;

use std::future::Future;
use std::net::{IpAddr, SocketAddr};
use std::sync::Arc;

use axum::Router;
use axum::extract::{Request, State};
use axum::http::{HeaderValue, StatusCode, header};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};

pub use error::{ApiError, WebError};
pub use limits::ServerLimits;
pub use memory::{MMAP_THRESHOLD_BYTES, return_freed_memory_promptly};
pub use params::{MAX_IMAGE_BODY_BYTES, MAX_JSON_BODY_BYTES};
use state::AppState;
pub use state::Logger;

/// How to serve.
#[derive(Clone, Default)]
pub struct ServeOptions {
    /// Receives a line for every internal error (a bug); nothing is written without it.
    pub log: Option<Logger>,
}

/// A bound server, ready to [`serve`](Server::serve).
pub struct Server {
    listener: tokio::net::TcpListener,
    addr: SocketAddr,
    log: Option<Logger>,
    limits: ServerLimits,
}

/// Whether `ip` is a loopback address (127.0.0.0/8, ::1, or ::ffff:127.x.y.z).
#[must_use]
pub fn is_loopback(ip: IpAddr) -> bool {
    match ip {
        IpAddr::V4(v4) => v4.is_loopback(),
        IpAddr::V6(v6) => {
            v6.is_loopback() || v6.to_ipv4_mapped().is_some_and(|v4| v4.is_loopback())
        }
    }
}

impl Server {
    /// Listen on `addr` (port 0 picks a free port: see [`Server::local_addr`]).
    ///
    /// # Errors
    /// [`WebError::Bind`] when the address cannot be bound.
    pub async fn bind(addr: SocketAddr, options: ServeOptions) -> Result<Self, WebError> {
        let listener = tokio::net::TcpListener::bind(addr)
            .await
            .map_err(|source| WebError::Bind { addr, source })?;
        let addr = listener
            .local_addr()
            .map_err(|source| WebError::Bind { addr, source })?;
        Ok(Self {
            listener,
            addr,
            log: options.log,
            limits: ServerLimits::default(),
        })
    }

    /// Serve with these timeouts and caps instead of [`ServerLimits::default`].
    #[must_use]
    pub fn with_limits(mut self, limits: ServerLimits) -> Self {
        self.limits = limits;
        self
    }

    /// The address actually bound.
    #[must_use]
    pub fn local_addr(&self) -> SocketAddr {
        self.addr
    }

    /// Serve until `shutdown` completes, then finish the requests in flight and return.
    /// The example photo is rendered in the background right away, so the page's first
    /// `/api/example` is quick.
    ///
    /// Each connection is served by hyper's HTTP/1.1 server with a header read timeout
    /// ([`ServerLimits::header_read_timeout`]); accepting goes on through errors such as
    /// running out of file descriptors (it pauses a second and logs a line).
    ///
    /// # Errors
    /// None at present: the signature keeps [`WebError::Serve`] for a failure to serve.
    pub async fn serve(
        self,
        shutdown: impl Future<Output = ()> + Send + 'static,
    ) -> Result<(), WebError> {
        let Self {
            listener,
            addr,
            log,
            limits,
        } = self;
        let header_timeout = limits.header_read_timeout;
        let connection_slots = Arc::new(tokio::sync::Semaphore::new(limits.max_connections));
        let state = AppState::new(log, is_loopback(addr.ip()), limits);
        let warm = state.clone();
        tokio::task::spawn_blocking(move || {
            let _ = api::example_body(&warm);
        });
        let app = router(state.clone());
        // Every connection task holds a sender; `recv` ends when the last one has gone.
        let (open_tx, mut open_rx) = tokio::sync::mpsc::channel::<()>(1);
        let (stop_tx, stop_rx) = tokio::sync::watch::channel(false);
        let mut shutdown = std::pin::pin!(shutdown);
        loop {
            // A connection slot first: at the cap, new clients wait in the backlog.
            let slot = tokio::select! {
                slot = Arc::clone(&connection_slots).acquire_owned() => match slot {
                    Ok(slot) => slot,
                    Err(_closed) => break,
                },
                () = &mut shutdown => break,
            };
            let stream = tokio::select! {
                accepted = listener.accept() => match accepted {
                    Ok((stream, _peer)) => stream,
                    Err(e) if is_connection_error(&e) => continue,
                    Err(e) => {
                        // Out of file descriptors or memory: wait for some to free.
                        state.log(&format!("cannot accept a connection: {e}"));
                        tokio::time::sleep(std::time::Duration::from_secs(1)).await;
                        continue;
                    }
                },
                () = &mut shutdown => break,
            };
            let _ = stream.set_nodelay(true);
            tokio::spawn(serve_connection(
                stream,
                app.clone(),
                header_timeout,
                stop_rx.clone(),
                (open_tx.clone(), slot),
            ));
        }
        drop(listener);
        drop(open_tx);
        let _ = stop_tx.send(true);
        let _ = open_rx.recv().await;
        Ok(())
    }
}

/// An accept error that concerns one connection only (the client gave up).
fn is_connection_error(e: &std::io::Error) -> bool {
    matches!(
        e.kind(),
        std::io::ErrorKind::ConnectionRefused
            | std::io::ErrorKind::ConnectionAborted
            | std::io::ErrorKind::ConnectionReset
    )
}

/// Serve one connection until the client closes it, it times out, or the server stops (then
/// the request in flight is answered first).
async fn serve_connection(
    stream: tokio::net::TcpStream,
    app: Router,
    header_timeout: std::time::Duration,
    mut stop: tokio::sync::watch::Receiver<bool>,
    _open: (
        tokio::sync::mpsc::Sender<()>,
        tokio::sync::OwnedSemaphorePermit,
    ),
) {
    let service = hyper_util::service::TowerToHyperService::new(app);
    let mut builder = hyper::server::conn::http1::Builder::new();
    builder
        .timer(hyper_util::rt::TokioTimer::new())
        .header_read_timeout(header_timeout);
    let connection = builder.serve_connection(hyper_util::rt::TokioIo::new(stream), service);
    let mut connection = std::pin::pin!(connection);
    tokio::select! {
        _ = connection.as_mut() => return,
        _ = stop.wait_for(|stopping| *stopping) => connection.as_mut().graceful_shutdown(),
    }
    let _ = connection.await;
}

/// Resolve `host`, bind it on `port`, call `on_ready` with the address bound, and serve until
/// Ctrl-C (SIGINT). Builds its own multi-threaded runtime and makes the allocator return
/// freed memory promptly ([`return_freed_memory_promptly`]): it owns the process. Blocks
/// until the server stops (requests in flight are answered first; work still running two
/// seconds later is dropped).
///
/// # Errors
/// [`WebError`] when the host does not resolve, the address cannot be bound or serving fails.
pub fn serve_until_ctrl_c(
    host: &str,
    port: u16,
    options: ServeOptions,
    on_ready: impl FnOnce(SocketAddr),
) -> Result<(), WebError> {
    // False only where the C library has no such setting.
    let _taken = return_freed_memory_promptly();
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .max_blocking_threads(16)
        .build()
        .map_err(WebError::Runtime)?;
    let result = runtime.block_on(async move {
        let addr = resolve(host, port).await?;
        let server = Server::bind(addr, options).await?;
        on_ready(server.local_addr());
        server
            .serve(async {
                // If the signal cannot be watched, serve until the process is killed.
                if tokio::signal::ctrl_c().await.is_err() {
                    std::future::pending::<()>().await;
                }
            })
            .await
    });
    // A photo still being analysed is not waited for long.
    runtime.shutdown_timeout(std::time::Duration::from_secs(2));
    result
}

/// The first address `host` resolves to (an IP literal needs no resolver; `[::1]` may be
/// bracketed).
async fn resolve(host: &str, port: u16) -> Result<SocketAddr, WebError> {
    let bare = host
        .strip_prefix('[')
        .and_then(|h| h.strip_suffix(']'))
        .unwrap_or(host);
    if let Ok(ip) = bare.parse::<IpAddr>() {
        return Ok(SocketAddr::new(ip, port));
    }
    let mut addrs = tokio::net::lookup_host((bare, port))
        .await
        .map_err(|e| WebError::Resolve {
            host: host.to_owned(),
            reason: e.to_string(),
        })?;
    addrs.next().ok_or_else(|| WebError::Resolve {
        host: host.to_owned(),
        reason: "no address".to_owned(),
    })
}

/// Every route, the limits and the guard.
fn router(state: AppState) -> Router {
    Router::new()
        .route("/", get(assets::index))
        .route("/assets/{*path}", get(assets::asset))
        .route("/api/example", get(api::example))
        .route("/api/build", post(api::build))
        .route("/api/plan", post(api::plan))
        .route("/api/navigate", post(api::navigate))
        .route("/api/detect", post(api::detect))
        .route("/api/photo", post(api::photo))
        .route("/api/snap", post(api::snap))
        .route("/api/propose", post(api::propose))
        .fallback(not_found)
        .method_not_allowed_fallback(method_not_allowed)
        .layer(middleware::from_fn_with_state(state.clone(), guard))
        .with_state(state)
}

async fn not_found(request: Request) -> ApiError {
    ApiError::new(
        StatusCode::NOT_FOUND,
        format!("no such path {}", request.uri().path()),
    )
}

async fn method_not_allowed(request: Request) -> ApiError {
    let path = request.uri().path();
    let allowed = if path.starts_with("/api/") && path != "/api/example" {
        "POST"
    } else {
        "GET"
    };
    ApiError::new(
        StatusCode::METHOD_NOT_ALLOWED,
        format!(
            "{} is not allowed on {path}; use {allowed}",
            request.method()
        ),
    )
}

/// Whether a `Host` header names this machine's loopback interface (`localhost`,
/// `127.x.y.z`, `[::1]`, with or without a port).
fn is_loopback_host(host: &str) -> bool {
    let name = if let Some(rest) = host.strip_prefix('[') {
        rest.split(']').next().unwrap_or("")
    } else {
        host.rsplit_once(':').map_or(host, |(name, port)| {
            if port.bytes().all(|b| b.is_ascii_digit()) {
                name
            } else {
                host
            }
        })
    };
    let name = name.trim_end_matches('.');
    name.eq_ignore_ascii_case("localhost")
        || name
            .get(name.len().saturating_sub(".localhost".len())..)
            .is_some_and(|tail| tail.eq_ignore_ascii_case(".localhost"))
        || name.parse::<IpAddr>().is_ok_and(is_loopback)
}

/// Refuse cross-origin requests and, on loopback, foreign `Host` names; mark every answer
/// `nosniff`.
async fn guard(State(state): State<AppState>, request: Request, next: Next) -> Response {
    let headers = request.headers();
    let host = headers
        .get(header::HOST)
        .map(|h| String::from_utf8_lossy(h.as_bytes()).into_owned());
    if state.0.loopback_hosts_only
        && let Some(host) = &host
        && !is_loopback_host(host)
    {
        return ApiError::new(
            StatusCode::FORBIDDEN,
            format!(
                "Host {host:?} is not a loopback name; open the page at http://127.0.0.1:<port>/ or http://localhost:<port>/"
            ),
        )
        .into_response();
    }
    if let Some(origin) = headers.get(header::ORIGIN) {
        let origin = String::from_utf8_lossy(origin.as_bytes()).into_owned();
        let own = host.as_ref().is_some_and(|h| {
            origin
                .strip_prefix("http://")
                .is_some_and(|o| o.eq_ignore_ascii_case(h))
        });
        if !own {
            return ApiError::new(
                StatusCode::FORBIDDEN,
                format!(
                    "cross-origin request from {origin:?} refused; only the page served here may call the API"
                ),
            )
            .into_response();
        }
    }
    let mut response = next.run(request).await;
    response.headers_mut().insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    response
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::run_blocking;

    #[test]
    fn loopback_host_names() {
        for ok in [
            "localhost",
            "localhost:8080",
            "LOCALHOST.:1",
            "127.0.0.1:8080",
            "127.1.2.3",
            "[::1]:80",
            "[::1]",
            "app.localhost:3000",
        ] {
            assert!(is_loopback_host(ok), "{ok}");
        }
        for bad in [
            "evil.example:8080",
            "localhost.evil.example",
            "10.0.0.1:8080",
            "[::2]:80",
            "",
            "127.0.0.1.evil.example",
        ] {
            assert!(!is_loopback_host(bad), "{bad}");
        }
    }

    #[test]
    fn a_panic_in_a_handler_is_a_500_and_a_log_line() {
        let lines = Arc::new(std::sync::Mutex::new(Vec::<String>::new()));
        let sink = Arc::clone(&lines);
        let state = AppState::new(
            Some(Arc::new(move |l: &str| {
                if let Ok(mut v) = sink.lock() {
                    v.push(l.to_owned());
                }
            })),
            true,
            ServerLimits::default(),
        );
        let runtime = tokio::runtime::Builder::new_current_thread()
            .build()
            .unwrap_or_else(|e| panic!("{e}"));
        let result: Result<(), ApiError> =
            runtime.block_on(run_blocking(&state, "/api/test", || {
                let empty: Vec<u8> = Vec::new();
                let i = empty.len() + 3;
                assert!(i < empty.len(), "index {i} out of range");
                Ok(())
            }));
        let e = result
            .err()
            .unwrap_or_else(|| ApiError::bad_request("no error"));
        assert_eq!(e.status, StatusCode::INTERNAL_SERVER_ERROR);
        assert!(e.message.contains("index 3 out of range"), "{}", e.message);
        let logged = lines.lock().map(|v| v.clone()).unwrap_or_default();
        assert_eq!(logged.len(), 1);
        assert!(logged[0].contains("/api/test"));
    }

    #[test]
    fn loopback_addresses() {
        assert!(is_loopback(
            "127.0.0.1".parse().unwrap_or(IpAddr::from([0; 4]))
        ));
        assert!(is_loopback("::1".parse().unwrap_or(IpAddr::from([0; 4]))));
        assert!(is_loopback(
            "::ffff:127.0.0.1".parse().unwrap_or(IpAddr::from([0; 4]))
        ));
        assert!(!is_loopback(
            "0.0.0.0".parse().unwrap_or(IpAddr::from([0; 4]))
        ));
    }
}

/// The README's example, compiled and run as a doc test.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
