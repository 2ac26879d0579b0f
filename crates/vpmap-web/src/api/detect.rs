//! `POST /api/detect`: a photo in; its line segments, vanishing points, camera and a scene
//! out (as `vpmap detect`).

use std::time::Instant;

use axum::body::{Body, Bytes};
use axum::extract::{RawQuery, State};
use axum::http::{HeaderMap, StatusCode};
use axum::response::Response;
use serde::Serialize;
use serde_json::value::RawValue;
use vpmap_vision::photo::{Photo, PhotoLimits, decode_photo};
use vpmap_vision::{DetectOptions, Detection, VisionError, detect as detect_photo};

use super::answer::{elapsed_ms, respond, to_json};
use crate::error::ApiError;
use crate::params::{self, MAX_IMAGE_BODY_BYTES, Query, parse_number, parse_point};
use crate::state::{AppState, run_blocking};
use vpmap_vision::scene::{DetectedScene, detected_scene};

/// Largest photo side, pixels.
pub const MAX_PHOTO_SIDE_PX: u32 = 8000;
/// Most memory the decoder may allocate, bytes (an 8000 x 8000 RGBA photo takes 256 MB).
pub const MAX_DECODE_BYTES: u64 = 320 << 20;
/// Accepted `focal_px`, as multiples of the photo's longer side.
const FOCAL_RANGE_SIDES: std::ops::RangeInclusive<f64> = 0.1..=100.0;
/// Accepted `two_point_tolerance`, degrees.
const TOLERANCE_RANGE_DEG: std::ops::RangeInclusive<f64> = 0.0..=30.0;
/// Accepted `max_side`, pixels.
const MAX_SIDE_RANGE: std::ops::RangeInclusive<f64> = 64.0..=8192.0;
/// The query parameters `/api/detect` reads.
const DETECT_QUERY: [&str; 4] = [
    "focal_px",
    "principal_point",
    "two_point_tolerance",
    "max_side",
];

/// The detection options of a query, checked where the photo is not needed.
pub(super) struct DetectQuery {
    focal_px: Option<f64>,
    principal_point: Option<[f64; 2]>,
    two_point_tolerance_deg: f64,
    max_side_px: u32,
}

impl DetectQuery {
    pub(super) fn parse(raw: Option<&str>) -> Result<Self, ApiError> {
        let q = Query::parse(raw, &DETECT_QUERY)?;
        let d = DetectOptions::default();
        let focal_px = q
            .get("focal_px")
            .map(|v| parse_number("focal_px", v))
            .transpose()?;
        if let Some(f) = focal_px
            && f <= 0.0
        {
            return Err(ApiError::bad_request(format!(
                "focal_px is {f}; it must be a positive number of pixels"
            )));
        }
        let principal_point = q
            .get("principal_point")
            .map(|v| parse_point("principal_point", v))
            .transpose()?;
        let tolerance = q.number("two_point_tolerance", d.two_point_tolerance_deg)?;
        if !TOLERANCE_RANGE_DEG.contains(&tolerance) {
            return Err(ApiError::bad_request(format!(
                "two_point_tolerance is {tolerance}; it must be from {} to {} degrees",
                TOLERANCE_RANGE_DEG.start(),
                TOLERANCE_RANGE_DEG.end()
            )));
        }
        let max_side = q.number("max_side", f64::from(d.max_side_px))?;
        if !(MAX_SIDE_RANGE.contains(&max_side) && max_side.fract() == 0.0) {
            return Err(ApiError::bad_request(format!(
                "max_side is {max_side}; it must be a whole number of pixels from {} to {}",
                MAX_SIDE_RANGE.start(),
                MAX_SIDE_RANGE.end()
            )));
        }
        Ok(Self {
            focal_px,
            principal_point,
            two_point_tolerance_deg: tolerance,
            max_side_px: max_side as u32,
        })
    }

    /// Check the intrinsics against the photo's size.
    pub(super) fn check_against(&self, width: u32, height: u32) -> Result<(), ApiError> {
        let side = f64::from(width.max(height));
        if let Some(f) = self.focal_px
            && !FOCAL_RANGE_SIDES.contains(&(f / side))
        {
            return Err(ApiError::bad_request(format!(
                "focal_px {f} is outside {} to {} px ({} to {} times the photo's longer side, {side} px)",
                FOCAL_RANGE_SIDES.start() * side,
                FOCAL_RANGE_SIDES.end() * side,
                FOCAL_RANGE_SIDES.start(),
                FOCAL_RANGE_SIDES.end()
            )));
        }
        if let Some([x, y]) = self.principal_point
            && !((0.0..=f64::from(width)).contains(&x) && (0.0..=f64::from(height)).contains(&y))
        {
            return Err(ApiError::bad_request(format!(
                "principal_point ({x}, {y}) lies outside the {width} x {height} photo"
            )));
        }
        Ok(())
    }
}

/// Check the declared media type: any image type, a generic binary type, or none (the
/// bytes decide which format it is, and only JPEG and PNG are read).
pub(super) fn check_media_type(headers: &HeaderMap) -> Result<(), ApiError> {
    match params::media_type(headers).as_deref() {
        None | Some("application/octet-stream") => Ok(()),
        Some(t) if t.starts_with("image/") => Ok(()),
        Some(other) => Err(ApiError::bad_request(format!(
            "Content-Type {other:?} is not accepted here; send the photo's bytes as image/jpeg or image/png"
        ))),
    }
}

/// Decode a JPEG or PNG, checking its size in the header first and limiting the decoder's
/// memory.
pub(super) fn decode(bytes: &[u8]) -> Result<Photo, ApiError> {
    let limits = PhotoLimits {
        max_side_px: MAX_PHOTO_SIDE_PX,
        max_pixels: u64::from(MAX_PHOTO_SIDE_PX) * u64::from(MAX_PHOTO_SIDE_PX),
        max_decode_bytes: MAX_DECODE_BYTES,
    };
    decode_photo(bytes, &limits).map_err(|e| match e {
        VisionError::EmptyPhoto => {
            ApiError::bad_request("the body is empty; send the photo's bytes (JPEG or PNG)")
        }
        e => ApiError::bad_request(e.to_string()),
    })
}

#[derive(Serialize)]
struct VanishingPointOut {
    point: Option<[f64; 2]>,
    segments: Vec<usize>,
    vertical: bool,
    direction_camera: [f64; 3],
    /// The direction's own vanishing point: its segments alone, not held orthogonal
    /// (`vpmap_vision::VanishingPoint::own_point`); `null` when they do not fix one.
    own_point: Option<OwnPointOut>,
}

#[derive(Serialize)]
struct OwnPointOut {
    point: Option<[f64; 2]>,
    direction_camera: [f64; 3],
    from_frame_deg: f64,
    edges: usize,
}

#[derive(Serialize)]
struct ImageSizeOut {
    width: u32,
    height: u32,
}

#[derive(Serialize)]
struct DetectResponse {
    scene: Box<RawValue>,
    segments: Vec<[f64; 4]>,
    vanishing_points: Vec<VanishingPointOut>,
    perspective: &'static str,
    focal_px: f64,
    principal_point: [f64; 2],
    image: ImageSizeOut,
    focal_estimated: bool,
    principal_point_estimated: bool,
    vertical_tilt_deg: f64,
    adjusted_deg: f64,
    reoriented: bool,
    warnings: Vec<String>,
    time_ms: f64,
}

/// Warnings about a detection: thinly supported vanishing points, the calibration's notes.
fn warnings(det: &Detection, scene: &DetectedScene) -> Vec<String> {
    let mut out: Vec<String> = scene
        .thinly_supported(det)
        .into_iter()
        .map(|(name, n)| format!("{name} rests on only {n} segments; check it"))
        .collect();
    out.extend(scene.off_centre_warning(det));
    out.extend(scene.calibration.warnings.iter().cloned());
    out
}

fn detect_answer(bytes: &[u8], query: &DetectQuery) -> Result<Bytes, ApiError> {
    let started = Instant::now();
    let photo = decode(bytes)?;
    query.check_against(photo.image.width(), photo.image.height())?;
    // The EXIF focal length as a prior, as `vpmap detect` uses it; one present but unusable is
    // said among the warnings.
    let (focal_prior, exif_warning) = match query.focal_px {
        Some(_) => (None, None),
        None => match photo.exif_focal_prior() {
            Ok(prior) => (prior, None),
            Err(why) => (None, Some(format!("the photo: {why}"))),
        },
    };
    let opts = DetectOptions {
        focal_px: query.focal_px,
        focal_prior,
        principal_point_px: query.principal_point,
        max_side_px: query.max_side_px,
        two_point_tolerance_deg: query.two_point_tolerance_deg,
        ..DetectOptions::default()
    };
    let det = detect_photo(&photo.image, &opts)
        .map_err(|e| ApiError::bad_request(format!("no vanishing points found: {e}")))?;
    let scene = detected_scene(&det)
        .map_err(|e| ApiError::bad_request(format!("no usable vanishing points: {e}")))?;
    let scene_json = RawValue::from_string(scene.json.trim().to_owned()).map_err(|e| {
        ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("internal error: the detected scene is not JSON: {e}"),
        )
    })?;
    let answer = DetectResponse {
        scene: scene_json,
        segments: det
            .segments
            .iter()
            .map(|s| [s.start_px[0], s.start_px[1], s.end_px[0], s.end_px[1]])
            .collect(),
        vanishing_points: det
            .vanishing_points
            .iter()
            .map(|v| VanishingPointOut {
                point: v.point_px,
                segments: v.segments.clone(),
                vertical: v.vertical,
                direction_camera: v.direction_camera,
                own_point: v.own_point.map(|o| OwnPointOut {
                    point: o.point_px,
                    direction_camera: o.direction_camera,
                    from_frame_deg: o.from_frame_deg,
                    edges: o.edges,
                }),
            })
            .collect(),
        perspective: scene.perspective.name(),
        focal_px: det.intrinsics.focal_px,
        principal_point: det.intrinsics.principal_point_px,
        image: ImageSizeOut {
            width: det.image_size_px[0],
            height: det.image_size_px[1],
        },
        focal_estimated: det.focal_estimated,
        principal_point_estimated: det.principal_point_estimated,
        vertical_tilt_deg: det.vertical_tilt_deg,
        adjusted_deg: scene.adjusted_deg,
        reoriented: photo.reoriented,
        warnings: exif_warning
            .into_iter()
            .chain(warnings(&det, &scene))
            .collect(),
        time_ms: elapsed_ms(started),
    };
    to_json(&answer)
}

/// `POST /api/detect?focal_px=&principal_point=X,Y` with the photo's bytes as the body.
pub async fn detect(
    State(state): State<AppState>,
    RawQuery(query): RawQuery,
    headers: HeaderMap,
    body: Body,
) -> Response {
    let result = async {
        let limits = &state.0.limits;
        let body = params::read_body(
            &headers,
            body,
            MAX_IMAGE_BODY_BYTES,
            limits.body_read_timeout,
        )
        .await?;
        let query = DetectQuery::parse(query.as_deref())?;
        check_media_type(&headers)?;
        if body.is_empty() {
            return Err(ApiError::bad_request(
                "the body is empty; send the photo's bytes (JPEG or PNG)",
            ));
        }
        let slot = state.0.detect_slots.take("/api/detect").await?;
        run_blocking(&state, "/api/detect", move || {
            let _slot = slot;
            detect_answer(&body, &query)
        })
        .await
    }
    .await;
    respond(result)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detect_query_is_checked() {
        assert!(DetectQuery::parse(Some("focal_px=1100&principal_point=800,600")).is_ok());
        assert!(DetectQuery::parse(Some("focal_px=-3")).is_err());
        assert!(DetectQuery::parse(Some("principal_point=800")).is_err());
        assert!(DetectQuery::parse(Some("max_side=10")).is_err());
        assert!(DetectQuery::parse(Some("focal=3")).is_err());
        let q = DetectQuery::parse(Some("focal_px=10")).unwrap_or_else(|e| panic!("{e}"));
        assert!(q.check_against(1600, 1200).is_err());
    }

    #[test]
    fn not_an_image_is_refused_before_decoding() {
        assert!(decode(b"").is_err());
        let e = decode(b"hello, world").err().map(|e| e.message);
        assert!(e.is_some_and(|m| m.contains("not a JPEG or PNG")));
        let e = decode(b"GIF89a\x01\x00\x01\x00").err().map(|e| e.message);
        assert!(e.is_some_and(|m| m.contains("gif")),);
    }
}
