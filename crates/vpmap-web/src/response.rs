//! JSON answers: the body, its content type and `Cache-Control: no-store`.

use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;

/// A JSON answer (`Cache-Control: no-store`).
pub(crate) fn json_response(status: StatusCode, value: &impl Serialize) -> Response {
    match serde_json::to_vec(value) {
        Ok(body) => json_bytes_response(status, body.into()),
        Err(e) => (
            StatusCode::INTERNAL_SERVER_ERROR,
            [(header::CONTENT_TYPE, "application/json")],
            format!(
                "{{\"error\": \"internal error: cannot write the answer as JSON: {}\"}}",
                e.to_string().replace(['"', '\\'], "'")
            ),
        )
            .into_response(),
    }
}

/// A JSON answer from bytes already serialised.
pub(crate) fn json_bytes_response(status: StatusCode, body: axum::body::Bytes) -> Response {
    (
        status,
        [
            (header::CONTENT_TYPE, "application/json"),
            (header::CACHE_CONTROL, "no-store"),
        ],
        body,
    )
        .into_response()
}
