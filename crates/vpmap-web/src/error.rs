//! The errors of this crate: [`WebError`] for starting and running the server, [`ApiError`]
//! for one request.

use std::net::SocketAddr;

use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};

/// What can stop the server.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum WebError {
    /// The host name did not resolve to any address.
    #[error("cannot resolve host {host:?}: {reason}")]
    Resolve {
        /// The host given.
        host: String,
        /// Why, from the resolver.
        reason: String,
    },
    /// The address could not be bound (in use, not this machine's, not permitted).
    #[error("cannot listen on {addr}")]
    Bind {
        /// The address.
        addr: SocketAddr,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The async runtime could not be started.
    #[error("cannot start the server's runtime: {0}")]
    Runtime(std::io::Error),
    /// Accepting or serving connections failed.
    #[error("the server stopped: {0}")]
    Serve(std::io::Error),
}

/// A request that cannot be answered: an HTTP status and a one-line message naming the
/// problem and the offending value. Answered as `{"error": message}`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ApiError {
    /// 400, 403, 404, 405, 408, 413, 503 or (for a bug) 500.
    pub status: StatusCode,
    /// One line.
    pub message: String,
    /// Sent as `Retry-After`, seconds (a busy server's 503).
    retry_after_s: Option<u64>,
    /// Answer with `Connection: close` (the body was not read to its end).
    close_connection: bool,
}

impl ApiError {
    /// A 400 Bad Request.
    pub fn bad_request(message: impl Into<String>) -> Self {
        Self::new(StatusCode::BAD_REQUEST, message)
    }

    /// An error with any status; the message is folded onto one line.
    pub fn new(status: StatusCode, message: impl Into<String>) -> Self {
        let message: String = message.into();
        Self {
            status,
            message: message.split_whitespace().collect::<Vec<_>>().join(" "),
            retry_after_s: None,
            close_connection: false,
        }
    }

    /// The same error, telling the client to try again after `seconds` (`Retry-After`).
    #[must_use]
    pub fn retry_after(mut self, seconds: u64) -> Self {
        self.retry_after_s = Some(seconds);
        self
    }

    /// The same error, closing the connection after the answer (`Connection: close`): for
    /// a request whose body is left unread.
    #[must_use]
    pub fn closing(mut self) -> Self {
        self.close_connection = true;
        self
    }
}

impl std::fmt::Display for ApiError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {}", self.status.as_u16(), self.message)
    }
}

impl std::error::Error for ApiError {}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let mut response = crate::response::json_response(
            self.status,
            &serde_json::json!({ "error": self.message }),
        );
        let headers = response.headers_mut();
        if let Some(seconds) = self.retry_after_s {
            headers.insert(header::RETRY_AFTER, HeaderValue::from(seconds));
        }
        if self.close_connection {
            headers.insert(header::CONNECTION, HeaderValue::from_static("close"));
        }
        response
    }
}
