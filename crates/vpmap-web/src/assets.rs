//! The page: every file of `assets/`, compiled in. Nothing is read from the file system at
//! run time, so no request can reach a file outside the folder.

use axum::extract::Path;
use axum::extract::rejection::PathRejection;
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use include_dir::{Dir, include_dir};

use crate::ApiError;

/// The `assets/` folder as it was at compile time.
static ASSETS: Dir<'static> = include_dir!("$CARGO_MANIFEST_DIR/assets");

/// The Content-Type of a file, by its extension.
fn content_type(path: &str) -> &'static str {
    let ext = path
        .rsplit_once('.')
        .map(|(_, e)| e.to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "html" | "htm" => "text/html; charset=utf-8",
        "js" | "mjs" => "text/javascript; charset=utf-8",
        "css" => "text/css; charset=utf-8",
        "json" | "map" => "application/json",
        "svg" => "image/svg+xml",
        "png" => "image/png",
        "jpg" | "jpeg" => "image/jpeg",
        "gif" => "image/gif",
        "webp" => "image/webp",
        "ico" => "image/x-icon",
        "wasm" => "application/wasm",
        "glb" => "model/gltf-binary",
        "txt" | "md" => "text/plain; charset=utf-8",
        "woff2" => "font/woff2",
        "woff" => "font/woff",
        _ => "application/octet-stream",
    }
}

/// The embedded file at `path` (relative to `assets/`), if there is one.
fn file(path: &str) -> Option<&'static [u8]> {
    // Only plain relative paths: no `..`, no absolute or Windows-style paths, no empty parts.
    let plain = !path.is_empty()
        && !path.contains('\\')
        && path
            .split('/')
            .all(|part| !part.is_empty() && part != "." && part != "..");
    plain
        .then(|| ASSETS.get_file(path))
        .flatten()
        .map(include_dir::File::contents)
}

fn serve(path: &str) -> Response {
    match file(path) {
        Some(bytes) => (
            [
                (header::CONTENT_TYPE, content_type(path)),
                (header::CACHE_CONTROL, "no-cache"),
            ],
            bytes,
        )
            .into_response(),
        None => ApiError::new(
            StatusCode::NOT_FOUND,
            format!("no such file /assets/{path}"),
        )
        .into_response(),
    }
}

/// `GET /`: `assets/index.html`.
pub async fn index() -> Response {
    serve("index.html")
}

/// `GET /assets/<path>`.
pub async fn asset(path: Result<Path<String>, PathRejection>) -> Response {
    match path {
        Ok(Path(path)) => serve(&path),
        Err(e) => {
            ApiError::bad_request(format!("bad asset path: {}", e.body_text())).into_response()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_embedded_plain_paths_are_found() {
        assert!(file("index.html").is_some());
        for bad in [
            "../Cargo.toml",
            "./index.html",
            "/index.html",
            "a//index.html",
            "..\\Cargo.toml",
            "",
        ] {
            assert!(file(bad).is_none(), "{bad}");
        }
        assert_eq!(content_type("app.MJS"), "text/javascript; charset=utf-8");
        assert_eq!(content_type("x.wasm"), "application/wasm");
        assert_eq!(content_type("noext"), "application/octet-stream");
    }
}
