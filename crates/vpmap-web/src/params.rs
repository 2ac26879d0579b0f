//! Query strings and request bodies, checked with one-line messages.

use std::time::Duration;

use axum::body::{Body, Bytes};
use axum::http::{HeaderMap, StatusCode, header};
use http_body_util::BodyExt as _;

use crate::error::ApiError;

/// Largest JSON body (`/api/build`, `/api/plan`), bytes.
pub const MAX_JSON_BODY_BYTES: usize = 4 << 20;
/// Largest image body (`/api/detect`), bytes.
pub const MAX_IMAGE_BODY_BYTES: usize = 25_000_000;

/// The parameters of a query string, each allowed once and only from `known`.
pub struct Query {
    pairs: Vec<(String, String)>,
}

impl Query {
    /// Parse `raw` (`None` when the URL has no `?`).
    ///
    /// # Errors
    /// A parameter not in `known`, or given twice.
    pub fn parse(raw: Option<&str>, known: &[&str]) -> Result<Self, ApiError> {
        let pairs: Vec<(String, String)> = raw
            .map(|q| {
                form_urlencoded::parse(q.as_bytes())
                    .map(|(k, v)| (k.into_owned(), v.into_owned()))
                    .collect()
            })
            .unwrap_or_default();
        for (i, (key, _)) in pairs.iter().enumerate() {
            if !known.contains(&key.as_str()) {
                return Err(ApiError::bad_request(if known.is_empty() {
                    format!(
                        "unknown query parameter {key:?}; this endpoint takes no query parameters (its options are fields of the JSON body, or it has none)"
                    )
                } else {
                    format!(
                        "unknown query parameter {key:?}; known: {}",
                        known.join(", ")
                    )
                }));
            }
            if pairs[..i].iter().any(|(k, _)| k == key) {
                return Err(ApiError::bad_request(format!(
                    "query parameter {key:?} is given twice"
                )));
            }
        }
        Ok(Self { pairs })
    }

    /// The value of `key`, if given.
    pub fn get(&self, key: &str) -> Option<&str> {
        self.pairs
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// A finite number, or `default` when absent.
    ///
    /// # Errors
    /// The value is not a finite number.
    pub fn number(&self, key: &str, default: f64) -> Result<f64, ApiError> {
        self.get(key).map_or(Ok(default), |v| parse_number(key, v))
    }

    /// `true`/`false` (or `1`/`0`), or `default` when absent.
    ///
    /// # Errors
    /// Any other value.
    pub fn flag(&self, key: &str, default: bool) -> Result<bool, ApiError> {
        match self.get(key) {
            None => Ok(default),
            Some("true" | "1") => Ok(true),
            Some("false" | "0") => Ok(false),
            Some(v) => Err(ApiError::bad_request(format!(
                "query parameter {key} is {v:?}; use true or false"
            ))),
        }
    }
}

/// A finite number named `what`.
///
/// # Errors
/// `text` is not a finite number.
pub fn parse_number(what: &str, text: &str) -> Result<f64, ApiError> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v + 0.0),
        _ => Err(ApiError::bad_request(format!(
            "{what} is {text:?}, which is not a finite number"
        ))),
    }
}

/// `X,Y` as two finite numbers.
///
/// # Errors
/// Anything else.
pub fn parse_point(what: &str, text: &str) -> Result<[f64; 2], ApiError> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    match parts.as_slice() {
        [x, y] => match (x.parse::<f64>(), y.parse::<f64>()) {
            (Ok(x), Ok(y)) if x.is_finite() && y.is_finite() => Ok([x + 0.0, y + 0.0]),
            _ => Err(point_error(what, text)),
        },
        _ => Err(point_error(what, text)),
    }
}

fn point_error(what: &str, text: &str) -> ApiError {
    ApiError::bad_request(format!(
        "{what} is {text:?}, which is not a point X,Y (two numbers separated by a comma)"
    ))
}

/// `bytes` as a short readable size: `4194304 bytes (4.2 MB)`.
pub fn size_text(bytes: u64) -> String {
    if bytes >= 1_000_000_000 {
        format!("{bytes} bytes ({:.1} GB)", bytes as f64 / 1e9)
    } else {
        format!("{bytes} bytes ({:.1} MB)", bytes as f64 / 1e6)
    }
}

/// Read a request body of at most `limit_bytes`, all of it within `timeout`.
///
/// A declared `Content-Length` above the limit is refused before a byte of the body is read;
/// a body without one (chunked) is refused as soon as it passes the limit. Every refusal
/// closes the connection, since the rest of the body is left unread.
///
/// # Errors
/// 413 when the body is (or declares itself) larger than the limit, 408 when it does not
/// arrive within `timeout`, 400 when the connection fails while it is read.
pub async fn read_body(
    headers: &HeaderMap,
    body: Body,
    limit_bytes: usize,
    timeout: Duration,
) -> Result<Bytes, ApiError> {
    let limit = limit_bytes as u64;
    let too_large = |what: String| {
        ApiError::new(
            StatusCode::PAYLOAD_TOO_LARGE,
            format!("{what}; the limit here is {}", size_text(limit)),
        )
        .closing()
    };
    let declared = match headers.get(header::CONTENT_LENGTH) {
        // hyper has already refused a malformed Content-Length.
        Some(v) => std::str::from_utf8(v.as_bytes())
            .ok()
            .and_then(|t| t.trim().parse::<u64>().ok()),
        None => None,
    };
    if let Some(n) = declared
        && n > limit
    {
        return Err(too_large(format!(
            "the request declares a body of {} (Content-Length)",
            size_text(n)
        )));
    }
    let deadline = tokio::time::Instant::now() + timeout;
    // Grown as the bytes arrive, not reserved for what is declared: a client declaring
    // 25 MB and sending nothing holds no memory.
    let mut buf = Vec::new();
    let mut body = body;
    loop {
        match tokio::time::timeout_at(deadline, body.frame()).await {
            Err(_elapsed) => {
                let of = declared.map_or_else(String::new, |n| format!(" of {n}"));
                return Err(ApiError::new(
                    StatusCode::REQUEST_TIMEOUT,
                    format!(
                        "the request body did not arrive within {} s ({} bytes{of} received); send it at once",
                        timeout.as_secs_f64(),
                        buf.len()
                    ),
                )
                .closing());
            }
            Ok(None) => return Ok(Bytes::from(buf)),
            Ok(Some(Err(e))) => {
                return Err(
                    ApiError::bad_request(format!("cannot read the request body: {e}")).closing(),
                );
            }
            Ok(Some(Ok(frame))) => {
                if let Ok(data) = frame.into_data() {
                    if buf.len() + data.len() > limit_bytes {
                        return Err(too_large(
                            "the request body is larger than allowed".to_owned(),
                        ));
                    }
                    buf.extend_from_slice(&data);
                }
            }
        }
    }
}

/// The media type of the request (`Content-Type` without parameters, lower case), if any.
pub fn media_type(headers: &HeaderMap) -> Option<String> {
    headers.get(header::CONTENT_TYPE).map(|v| {
        String::from_utf8_lossy(v.as_bytes())
            .split(';')
            .next()
            .unwrap_or("")
            .trim()
            .to_ascii_lowercase()
    })
}

/// Check that a JSON endpoint got JSON: `application/json` (or `text/plain`, what a browser
/// sends for a string body, or no Content-Type at all).
///
/// # Errors
/// Any other media type.
pub fn expect_json(headers: &HeaderMap) -> Result<(), ApiError> {
    match media_type(headers).as_deref() {
        None | Some("application/json" | "text/plain") => Ok(()),
        Some(other) => Err(ApiError::bad_request(format!(
            "Content-Type {other:?} is not accepted here; send the JSON with Content-Type application/json"
        ))),
    }
}

/// The body as JSON text: UTF-8 (a byte-order mark is skipped), not empty.
///
/// # Errors
/// An empty body, or one that is not UTF-8.
pub fn json_text(bytes: &[u8], what: &str) -> Result<String, ApiError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        ApiError::bad_request(format!(
            "the body is not UTF-8 text (invalid byte at offset {}); send {what} as JSON",
            e.valid_up_to()
        ))
    })?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(ApiError::bad_request(format!(
            "the body is empty; send {what} as JSON"
        )));
    }
    Ok(text.to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn query_rejects_unknown_and_repeated_parameters() {
        let known = ["method", "resolution"];
        assert!(Query::parse(Some("method=sideview&resolution=0.1"), &known).is_ok());
        let e = Query::parse(Some("resolutoin=0.1"), &known).err();
        assert!(e.is_some_and(|e| e.message.contains("\"resolutoin\"")));
        assert!(Query::parse(Some("method=a&method=b"), &known).is_err());
        // Where none is known, the message does not end in an empty list (issue 40).
        let e = Query::parse(Some("x=1"), &[]).err().map(|e| e.message);
        assert_eq!(
            e.as_deref(),
            Some(
                "unknown query parameter \"x\"; this endpoint takes no query parameters (its options are fields of the JSON body, or it has none)"
            )
        );
        let q = Query::parse(Some("resolution=nan"), &known);
        assert!(q.is_ok_and(|q| q.number("resolution", 0.05).is_err()));
    }

    #[test]
    fn points_are_two_finite_numbers() {
        assert_eq!(parse_point("p", " 1.5, -2").ok(), Some([1.5, -2.0]));
        for bad in ["1", "1,2,3", "a,b", "inf,1", ""] {
            assert!(parse_point("p", bad).is_err(), "{bad}");
        }
    }
}
