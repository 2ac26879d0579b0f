//! How every endpoint answers: the JSON body serialised on the worker thread ([`to_json`],
//! [`raw`] for JSON compiled in), the answer or the error as a response ([`respond`]), and
//! the time taken ([`elapsed_ms`]).

use axum::body::Bytes;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use serde_json::value::RawValue;

use crate::error::ApiError;
use crate::response::json_bytes_response;

/// Milliseconds since `start`.
pub(super) fn elapsed_ms(start: std::time::Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

/// A response, or the error as one.
pub(super) fn respond(result: Result<Bytes, ApiError>) -> Response {
    match result {
        Ok(body) => json_bytes_response(StatusCode::OK, body),
        Err(e) => e.into_response(),
    }
}

/// Serialise an answer (on the blocking thread that made it).
pub(super) fn to_json(value: &impl Serialize) -> Result<Bytes, ApiError> {
    serde_json::to_vec(value).map(Bytes::from).map_err(|e| {
        ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("internal error: cannot write the answer as JSON: {e}"),
        )
    })
}

/// JSON text compiled in, embedded as it is (key order kept).
pub(super) fn raw(text: &str) -> Result<Box<RawValue>, ApiError> {
    RawValue::from_string(text.trim().to_owned()).map_err(|e| {
        ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("internal error: a bundled JSON file does not parse: {e}"),
        )
    })
}
