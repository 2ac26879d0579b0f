//! What every request shares: the server's [`AppState`] (log, limits, slots, the example's
//! answer), where it logs ([`Logger`]), and running a handler's work on a blocking thread
//! ([`run_blocking`]).

use std::panic::AssertUnwindSafe;
use std::sync::{Arc, OnceLock};

use axum::http::StatusCode;

use crate::error::ApiError;
use crate::limits::{ServerLimits, Slots};
use crate::photos::PhotoStore;

/// Where the server writes what its operator should know (internal errors); one line each.
pub type Logger = Arc<dyn Fn(&str) + Send + Sync>;

/// Shared by every request.
pub(crate) struct Shared {
    pub(crate) log: Option<Logger>,
    /// Bound to loopback: accept only loopback names in `Host`.
    pub(crate) loopback_hosts_only: bool,
    /// Timeouts and caps.
    pub(crate) limits: ServerLimits,
    /// Scenes built at once.
    pub(crate) build_slots: Slots,
    /// Plans computed at once.
    pub(crate) plan_slots: Slots,
    /// Photos decoded and analysed at once (each may take hundreds of megabytes).
    pub(crate) detect_slots: Slots,
    /// The photos clicks snap on (`/api/photo`).
    pub(crate) photos: PhotoStore,
    /// `/api/example`'s answer, made on first use.
    pub(crate) example: OnceLock<Result<axum::body::Bytes, String>>,
}

/// The state handed to every handler.
#[derive(Clone)]
pub(crate) struct AppState(pub(crate) Arc<Shared>);

impl AppState {
    pub(crate) fn new(
        log: Option<Logger>,
        loopback_hosts_only: bool,
        limits: ServerLimits,
    ) -> Self {
        let wait = limits.slot_wait;
        Self(Arc::new(Shared {
            log,
            loopback_hosts_only,
            build_slots: Slots::new("/api/build", limits.build_slots, wait),
            plan_slots: Slots::new("/api/plan and /api/navigate", limits.plan_slots, wait),
            detect_slots: Slots::new(
                "/api/detect, /api/photo and /api/propose",
                limits.detect_slots,
                wait,
            ),
            limits,
            photos: PhotoStore::default(),
            example: OnceLock::new(),
        }))
    }

    pub(crate) fn log(&self, line: &str) {
        if let Some(log) = &self.0.log {
            log(line);
        }
    }
}

/// Run `work` on a blocking thread; a panic there becomes a 500 [`ApiError`] and a log line.
pub(crate) async fn run_blocking<T: Send + 'static>(
    state: &AppState,
    what: &'static str,
    work: impl FnOnce() -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    let outcome =
        tokio::task::spawn_blocking(move || std::panic::catch_unwind(AssertUnwindSafe(work))).await;
    let message = match outcome {
        Ok(Ok(result)) => return result,
        Ok(Err(payload)) => panic_text(payload.as_ref()),
        Err(join) => join.to_string(),
    };
    state.log(&format!("internal error in {what}: {message}"));
    Err(ApiError::new(
        StatusCode::INTERNAL_SERVER_ERROR,
        format!("internal error in {what}: {message} (a bug in vpmap; please report it)"),
    ))
}

fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "panic".to_owned()
    }
}
