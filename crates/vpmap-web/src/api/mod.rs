//! The JSON endpoints. Each handler checks what it can cheaply, then does the work on a
//! blocking thread (`crate::state::run_blocking`), serialising the answer there too.

mod answer;
mod build;
mod detect;
#[doc(hidden)]
pub mod fuzzing;
mod navigate;
mod plan;
mod scene;
mod smooth;
mod snap;

use axum::body::Bytes;
use axum::extract::State;
use axum::http::StatusCode;
use axum::response::Response;
use base64::Engine as _;
use base64::engine::general_purpose::STANDARD as BASE64;
use serde::Serialize;
use serde_json::value::RawValue;

pub use build::build;
pub use detect::detect;
pub use navigate::navigate_handler as navigate;
pub use plan::plan;
pub use snap::{photo, propose, snap};

use crate::error::ApiError;
use crate::example::{OFFICE_SCENE, OFFICE_TRUTH, office_photo_png};
use crate::state::{AppState, run_blocking};
use answer::{raw, respond, to_json};

#[derive(Serialize)]
struct PhotoInfo {
    width: u32,
    height: u32,
    media_type: &'static str,
}

#[derive(Serialize)]
struct ExampleResponse {
    name: &'static str,
    description: &'static str,
    scene: Box<RawValue>,
    photo_png_base64: String,
    photo: PhotoInfo,
    truth: Box<RawValue>,
}

/// `/api/example`'s answer, rendered once per server (the first call takes about a second).
pub(crate) fn example_body(state: &AppState) -> Result<Bytes, String> {
    state
        .0
        .example
        .get_or_init(|| {
            let (png, width, height) = office_photo_png()?;
            let answer = ExampleResponse {
                name: "office",
                description: "examples/office.json: a synthetic office photographed from 1.6 m at 25 deg pitch and 3 deg roll (focal 1100 px), with five annotated objects and the floor outline; the photo is rendered from the example's truth",
                scene: raw(OFFICE_SCENE).map_err(|e| e.message)?,
                photo_png_base64: BASE64.encode(png),
                photo: PhotoInfo {
                    width,
                    height,
                    media_type: "image/png",
                },
                truth: raw(OFFICE_TRUTH).map_err(|e| e.message)?,
            };
            to_json(&answer).map_err(|e| e.message)
        })
        .clone()
}

/// `GET /api/example`.
pub async fn example(State(state): State<AppState>) -> Response {
    let worker = state.clone();
    respond(
        run_blocking(&state, "/api/example", move || {
            example_body(&worker).map_err(|e| {
                ApiError::new(
                    StatusCode::INTERNAL_SERVER_ERROR,
                    format!("internal error: {e}"),
                )
            })
        })
        .await,
    )
}
