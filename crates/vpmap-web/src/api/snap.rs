//! Clicks that snap to the photo: `POST /api/photo` keeps a photo on the server
//! (`crate::photos`), `POST /api/snap` moves one click to the image corner it means
//! (`vpmap_vision::snap::snap_click`), `POST /api/propose` lists box candidates from the
//! photo's segments (`vpmap_vision::proposals::propose_boxes`). The JSON shapes are in
//! `docs/web-api.md`.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use axum::body::{Body, Bytes};
use axum::extract::{RawQuery, State};
use axum::http::{HeaderMap, StatusCode};
use axum::response::Response;
use serde::{Deserialize, Serialize};
use vpmap_metrology::interrupt::Interrupt;
use vpmap_metrology::scene::{
    BoxCorners, DivisionModel, ImageSize, LensDistortion, MAX_DIVISION_K, MAX_DIVISION_STRETCH,
};
use vpmap_vision::proposals::{ProposalOptions, propose_boxes};
use vpmap_vision::snap::scene::vanishing_points_at;
use vpmap_vision::snap::{Snap, SnapOptions, SnapOutcome, snap_click};
use vpmap_vision::{DetectOptions, VisionError, detect_segments};

use super::answer::{elapsed_ms, respond, to_json};
use super::detect::{check_media_type, decode};
use super::plan::{CancelOnDrop, json_body};
use crate::error::ApiError;
use crate::params::{self, MAX_IMAGE_BODY_BYTES, Query};
use crate::photos::StoredPhoto;
use crate::state::{AppState, run_blocking};

/// Largest search radius a request may ask for, pixels.
const MAX_RADIUS_PX: f64 = 32.0;
/// The click noise the search radius is made for when a request gives none, pixels.
const DEFAULT_CLICK_SIGMA_PX: f64 = 2.0;
/// Half the length of an edge drawn for the page, pixels (the part of it that was fitted).
const EDGE_DRAW_PX: f64 = 16.0;
/// The longer side of the image box proposals find their segments on, pixels: a larger photo
/// is analysed downscaled (its segments mapped back to full size, its corners snapped at full
/// size), so that finding them takes a bounded time and memory (an 8000 x 8000 photo at full
/// size took 1.75 GB).
pub const PROPOSAL_SIDE_PX: u32 = 2000;

#[derive(Serialize)]
struct PhotoAnswer {
    id: String,
    width: u32,
    height: u32,
    time_ms: f64,
}

/// `POST /api/photo` with the photo's bytes: kept for `/api/snap` and `/api/propose`.
pub async fn photo(
    State(state): State<AppState>,
    RawQuery(query): RawQuery,
    headers: HeaderMap,
    body: Body,
) -> Response {
    let result = async {
        let body = params::read_body(
            &headers,
            body,
            MAX_IMAGE_BODY_BYTES,
            state.0.limits.body_read_timeout,
        )
        .await?;
        Query::parse(query.as_deref(), &[])?;
        check_media_type(&headers)?;
        let slot = state.0.detect_slots.take("/api/photo").await?;
        let worker = state.clone();
        run_blocking(&state, "/api/photo", move || {
            let _slot = slot;
            let started = Instant::now();
            let photo = decode(&body)?;
            let (width, height) = (photo.image.width(), photo.image.height());
            let stored = StoredPhoto::new(&photo.image);
            drop(photo);
            let id = worker.0.photos.insert(stored);
            to_json(&PhotoAnswer {
                id,
                width,
                height,
                time_ms: elapsed_ms(started),
            })
        })
        .await
    }
    .await;
    respond(result)
}

/// A `/api/snap` request.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SnapRequest {
    photo: String,
    click: [f64; 2],
    #[serde(default)]
    vanishing_points: Vec<Option<Vec<f64>>>,
    click_sigma: Option<f64>,
    radius: Option<f64>,
    /// The photo's lens, as the scene's `lens_distortion` (`k`; `k_sd` is checked as the
    /// scene's and not used): the vanishing points are then the pinhole camera's and the
    /// click the photo's.
    lens_distortion: Option<LensDistortion>,
    /// The lens's centre (the scene's `principal_point`); the image centre without it.
    principal_point: Option<[f64; 2]>,
}

/// A `/api/propose` request.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ProposeRequest {
    photo: String,
    vanishing_points: Vec<Option<Vec<f64>>>,
    max_proposals: Option<usize>,
    /// The photo's lens, as in [`SnapRequest`].
    lens_distortion: Option<LensDistortion>,
    /// The lens's centre, as in [`SnapRequest`].
    principal_point: Option<[f64; 2]>,
}

#[derive(Serialize)]
struct SnapAnswer {
    click: [f64; 2],
    point: [f64; 2],
    snapped: bool,
    moved_px: f64,
    covariance_px2: Option<[[f64; 2]; 2]>,
    edges: Vec<[f64; 4]>,
    edge_directions: Vec<String>,
    note: Option<String>,
    time_ms: f64,
}

#[derive(Serialize)]
struct CornersOut<'a> {
    base: &'a BoxCorners,
    top: &'a BoxCorners,
}

#[derive(Serialize)]
struct ProposalOut<'a> {
    corners: CornersOut<'a>,
    score: f64,
}

#[derive(Serialize)]
struct ProposeAnswer<'a> {
    proposals: Vec<ProposalOut<'a>>,
    segments: usize,
    time_ms: f64,
}

fn parse<T: serde::de::DeserializeOwned>(body: &[u8], what: &str) -> Result<T, ApiError> {
    let text = params::json_text(body, what)?;
    serde_json::from_str(&text)
        .map_err(|e| ApiError::bad_request(format!("the body is not {what}: {e}")))
}

/// The vanishing points of a request as homogeneous pixels: `[x, y]` is a point, `[x, y, w]`
/// homogeneous; `null` entries (unknown) are left out, so only trailing ones may be null.
fn vanishing_points(given: &[Option<Vec<f64>>]) -> Result<Vec<[f64; 3]>, ApiError> {
    let mut out = Vec::new();
    let mut gap = None;
    for (i, v) in given.iter().enumerate() {
        let Some(v) = v else {
            gap.get_or_insert(i);
            continue;
        };
        if let Some(g) = gap {
            return Err(ApiError::bad_request(format!(
                "vanishing_points[{g}] is null but vanishing_points[{i}] is given; only the last ones may be unknown"
            )));
        }
        let p = match v.as_slice() {
            [x, y] => [*x, *y, 1.0],
            [x, y, w] => [*x, *y, *w],
            _ => {
                return Err(ApiError::bad_request(format!(
                    "vanishing_points[{i}] is {v:?}; give [x, y] pixels or [x, y, w] homogeneous"
                )));
            }
        };
        if !(p.iter().all(|c| c.is_finite()) && p.iter().any(|c| *c != 0.0)) {
            return Err(ApiError::bad_request(format!(
                "vanishing_points[{i}] is {v:?}; it must be finite and not all zero"
            )));
        }
        out.push(p);
    }
    if out.len() > 3 {
        return Err(ApiError::bad_request(format!(
            "vanishing_points has {} entries; give at most three (two horizontal, then the vertical)",
            out.len()
        )));
    }
    Ok(out)
}

fn snap_options(req: &SnapRequest) -> Result<SnapOptions, ApiError> {
    let sigma = req.click_sigma.unwrap_or(DEFAULT_CLICK_SIGMA_PX);
    if !(sigma > 0.0 && sigma <= super::scene::MAX_CLICK_SIGMA_PX) {
        return Err(ApiError::bad_request(format!(
            "click_sigma is {sigma}; give the clicks' noise in pixels, more than 0 and at most {}",
            super::scene::MAX_CLICK_SIGMA_PX
        )));
    }
    let mut opts = SnapOptions::for_click_sigma(sigma);
    if let Some(r) = req.radius {
        if !(1.0..=MAX_RADIUS_PX).contains(&r) {
            return Err(ApiError::bad_request(format!(
                "radius is {r}; give the search radius in pixels, from 1 to {MAX_RADIUS_PX}"
            )));
        }
        opts.search_radius_px = r;
    }
    Ok(opts)
}

/// A request's lens on a photo of `width` x `height` pixels: `None` without one; 400 for a
/// `k` or centre that is not finite, a `k` beyond +-1, or one that folds the photo (the
/// scene file's rules, `docs/scene-format.md`).
fn lens_model(
    lens: Option<LensDistortion>,
    principal_point: Option<[f64; 2]>,
    width: u32,
    height: u32,
) -> Result<Option<DivisionModel>, ApiError> {
    let Some(lens) = lens else {
        return Ok(None);
    };
    if !(lens.k.is_finite() && lens.k.abs() <= MAX_DIVISION_K) {
        return Err(ApiError::bad_request(format!(
            "lens_distortion.k is {}; the division model's k lies within -{MAX_DIVISION_K} to {MAX_DIVISION_K} (phone lenses about -0.15 to 0)",
            lens.k
        )));
    }
    if let Some(sd) = lens.k_sd
        && !(sd.is_finite() && (0.0..=MAX_DIVISION_K).contains(&sd))
    {
        return Err(ApiError::bad_request(format!(
            "lens_distortion.k_sd is {sd}; a standard deviation lies within 0 to {MAX_DIVISION_K}"
        )));
    }
    if let Some(c) = principal_point
        && !c.iter().all(|v| v.is_finite() && v.abs() <= 1e7)
    {
        return Err(ApiError::bad_request(format!(
            "principal_point is {c:?}; give the lens's centre in pixels"
        )));
    }
    let image = ImageSize { width, height };
    let model = DivisionModel::new(lens.k, image, principal_point);
    let stretch = model.stretch(image);
    if stretch >= MAX_DIVISION_STRETCH {
        return Err(ApiError::bad_request(format!(
            "lens_distortion.k = {} folds this {width} x {height} photo (|k| r^2 = {stretch:.3} at a corner; at most {MAX_DIVISION_STRETCH})",
            lens.k
        )));
    }
    Ok(Some(model))
}

/// The kept photo of `id`, or 404 naming it.
fn stored(state: &AppState, id: &str) -> Result<std::sync::Arc<StoredPhoto>, ApiError> {
    state.0.photos.get(id).ok_or_else(|| {
        ApiError::new(
            StatusCode::NOT_FOUND,
            format!(
                "photo {id:?} is not kept on the server (unknown, or evicted by newer photos); send it again to /api/photo"
            ),
        )
    })
}

fn vision_error(e: &VisionError) -> ApiError {
    ApiError::bad_request(e.to_string())
}

fn snap_answer(snap: &Snap, started: Instant) -> SnapAnswer {
    let edges = snap
        .edges
        .iter()
        .map(|e| {
            let (p, d) = (e.point_px, e.direction_px);
            [
                p[0] - EDGE_DRAW_PX * d[0],
                p[1] - EDGE_DRAW_PX * d[1],
                p[0] + EDGE_DRAW_PX * d[0],
                p[1] + EDGE_DRAW_PX * d[1],
            ]
        })
        .collect();
    SnapAnswer {
        click: snap.click_px,
        point: snap.point_px,
        snapped: snap.snapped(),
        moved_px: snap.moved_px(),
        covariance_px2: snap.covariance_px2,
        edges,
        edge_directions: snap.edges.iter().map(|e| e.direction.to_string()).collect(),
        note: match snap.outcome {
            SnapOutcome::Snapped => None,
            SnapOutcome::Kept(why) => Some(why.to_string()),
        },
        time_ms: elapsed_ms(started),
    }
}

/// Snap one click of a `/api/snap` body on the kept photos.
pub(crate) fn snap_request(state: &AppState, body: &[u8]) -> Result<Bytes, ApiError> {
    let started = Instant::now();
    let req: SnapRequest = parse(body, "a snap request {photo, click, vanishing_points}")?;
    let vps = vanishing_points(&req.vanishing_points)?;
    let opts = snap_options(&req)?;
    let photo = stored(state, &req.photo)?;
    let lens = lens_model(
        req.lens_distortion,
        req.principal_point,
        photo.snap.width(),
        photo.snap.height(),
    )?;
    let vps = vanishing_points_at(&vps, lens.as_ref(), req.click);
    let snap = snap_click(&photo.snap, &vps, req.click, &opts).map_err(|e| vision_error(&e))?;
    to_json(&snap_answer(&snap, started))
}

/// The box proposals of a `/api/propose` body on the kept photos, stopping when `interrupt`
/// fires.
pub(crate) fn propose_request(
    state: &AppState,
    body: &[u8],
    interrupt: &Interrupt,
) -> Result<Bytes, ApiError> {
    let started = Instant::now();
    let req: ProposeRequest = parse(body, "a propose request {photo, vanishing_points}")?;
    let vps = vanishing_points(&req.vanishing_points)?;
    if vps.len() < 2 {
        return Err(ApiError::bad_request(format!(
            "vanishing_points gives {} known vanishing points; box proposals need the two horizontal ones",
            vps.len()
        )));
    }
    let max = req.max_proposals.unwrap_or(20);
    if !(1..=100).contains(&max) {
        return Err(ApiError::bad_request(format!(
            "max_proposals is {max}; give 1 to 100"
        )));
    }
    let photo = stored(state, &req.photo)?;
    let segments = photo
        .segments
        .get_or_init(|| {
            let side = photo.image.width().max(photo.image.height());
            let opts = DetectOptions {
                max_side_px: side.clamp(640, PROPOSAL_SIDE_PX),
                ..DetectOptions::default()
            };
            detect_segments(&photo.image, &opts).map_err(|e| e.to_string())
        })
        .as_ref()
        .map_err(|e| ApiError::bad_request(format!("no line segments found: {e}")))?;
    let lens = lens_model(
        req.lens_distortion,
        req.principal_point,
        photo.snap.width(),
        photo.snap.height(),
    )?;
    let opts = ProposalOptions {
        max_proposals: max,
        interrupt: interrupt.clone(),
        lens,
        ..ProposalOptions::default()
    };
    let found = propose_boxes(&photo.snap, segments, &vps, &opts).map_err(|e| vision_error(&e))?;
    let answer = ProposeAnswer {
        proposals: found
            .iter()
            .map(|p| ProposalOut {
                corners: CornersOut {
                    base: &p.base,
                    top: &p.top,
                },
                score: p.score,
            })
            .collect(),
        segments: segments.len(),
        time_ms: elapsed_ms(started),
    };
    to_json(&answer)
}

/// `POST /api/snap` with `{photo, click, vanishing_points, click_sigma?, radius?}`.
pub async fn snap(
    State(state): State<AppState>,
    RawQuery(query): RawQuery,
    headers: HeaderMap,
    body: Body,
) -> Response {
    let result = async {
        let body = json_body(&state, query.as_deref(), &headers, body).await?;
        let worker = state.clone();
        run_blocking(&state, "/api/snap", move || snap_request(&worker, &body)).await
    }
    .await;
    respond(result)
}

/// `POST /api/propose` with `{photo, vanishing_points, max_proposals?}`.
pub async fn propose(
    State(state): State<AppState>,
    RawQuery(query): RawQuery,
    headers: HeaderMap,
    body: Body,
) -> Response {
    // Dropped with this future when the client goes away: the search then stops.
    let cancelled = CancelOnDrop(Arc::new(AtomicBool::new(false)));
    let result = async {
        let body = json_body(&state, query.as_deref(), &headers, body).await?;
        let slot = state.0.detect_slots.take("/api/propose").await?;
        let interrupt = Interrupt::default()
            .with_flag(Arc::clone(&cancelled.0))
            .with_timeout(state.0.limits.propose_timeout);
        let worker = state.clone();
        run_blocking(&state, "/api/propose", move || {
            let _slot = slot;
            propose_request(&worker, &body, &interrupt)
        })
        .await
    }
    .await;
    respond(result)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::limits::ServerLimits;
    use vpmap_metrology::scene::ImageSize;
    use vpmap_metrology::synth::{SynthOptions, synthesize};
    use vpmap_vision::snap::scene::scene_vanishing_points;
    use vpmap_vision::synthetic::photo::{CornerKind, PhotoOptions, TrueCorner, render_photo};

    /// A server state holding one rendered photo (id `p1`), its vanishing points and the
    /// true corners of its clicks.
    fn rendered() -> (AppState, Vec<[f64; 3]>, Vec<TrueCorner>) {
        let (scene, truth) = synthesize(&SynthOptions {
            image: ImageSize {
                width: 800,
                height: 600,
            },
            focal_px: 550.0,
            ..SynthOptions::default()
        })
        .unwrap();
        let photo = render_photo(&scene, &truth, &PhotoOptions::default()).unwrap();
        let state = AppState::new(None, true, ServerLimits::default());
        assert_eq!(state.0.photos.insert(StoredPhoto::new(&photo.image)), "p1");
        (
            state,
            scene_vanishing_points(&scene).unwrap(),
            photo.corners,
        )
    }

    fn ask(state: &AppState, body: &str) -> Result<serde_json::Value, ApiError> {
        snap_request(state, body.as_bytes()).map(|b| serde_json::from_slice(&b).unwrap())
    }

    fn snap_body(click: [f64; 2], vps: &[[f64; 3]]) -> String {
        serde_json::json!({"photo": "p1", "click": click, "vanishing_points": vps}).to_string()
    }

    #[test]
    fn a_click_near_a_box_corner_snaps_onto_it_and_one_on_the_floor_stays() {
        let (state, vps, corners) = rendered();
        let boxes: Vec<&TrueCorner> = corners
            .iter()
            .filter(|c| c.visible && c.kind == CornerKind::BoxCorner)
            .collect();
        assert!(boxes.len() >= 4, "{} visible box corners", boxes.len());
        let mut near = 0;
        for c in &boxes {
            let t = c.point_px;
            let v = ask(&state, &snap_body([t[0] + 1.5, t[1] - 1.0], &vps)).unwrap();
            if v["snapped"] == true {
                let p = [
                    v["point"][0].as_f64().unwrap(),
                    v["point"][1].as_f64().unwrap(),
                ];
                let e = (p[0] - t[0]).hypot(p[1] - t[1]);
                near += usize::from(e < 1.0);
                assert!(v["covariance_px2"][0][0].as_f64().unwrap() > 0.0, "{v}");
                assert_eq!(v["edges"].as_array().unwrap().len(), 2, "{v}");
                assert!(v["note"].is_null());
            }
        }
        // Most box corners snap to within a pixel of the truth (some are low-contrast).
        assert!(
            2 * near >= boxes.len(),
            "{near} of {} within 1 px",
            boxes.len()
        );
        // The floor at the bottom middle of the photo: no edges, the click stays.
        let v = ask(&state, &snap_body([400.0, 595.0], &vps)).unwrap();
        assert_eq!(v["snapped"], false, "{v}");
        assert_eq!(v["point"], serde_json::json!([400.0, 595.0]));
        assert!(v["covariance_px2"].is_null());
        assert!(v["note"].as_str().is_some_and(|n| !n.is_empty()), "{v}");
    }

    #[test]
    fn a_lens_in_the_request_snaps_the_bowed_corners_of_a_wide_lens() {
        // A render through a wide lens (k = -0.15): the scene's vanishing points are the
        // pinhole camera's, so the photo's edges near its corners run off them by degrees.
        let k = -0.15;
        let (mut near_without, mut near_with) = (0, 0);
        for seed in 0..4 {
            let (scene, truth) = synthesize(&SynthOptions {
                seed,
                image: ImageSize {
                    width: 800,
                    height: 600,
                },
                focal_px: 480.0,
                pitch_deg: 20.0,
                ..SynthOptions::default()
            })
            .unwrap();
            let photo = render_photo(
                &scene,
                &truth,
                &PhotoOptions {
                    seed,
                    distortion_k: k,
                    ..PhotoOptions::default()
                },
            )
            .unwrap();
            let state = AppState::new(None, true, ServerLimits::default());
            assert_eq!(state.0.photos.insert(StoredPhoto::new(&photo.image)), "p1");
            let vps = scene_vanishing_points(&scene).unwrap();
            for c in photo
                .corners
                .iter()
                .filter(|c| c.visible && c.kind == CornerKind::BoxCorner)
            {
                let t = c.point_px;
                let click = [t[0] + 1.2, t[1] - 0.9];
                let near = |v: serde_json::Value| {
                    let p = [
                        v["point"][0].as_f64().unwrap(),
                        v["point"][1].as_f64().unwrap(),
                    ];
                    usize::from(v["snapped"] == true && (p[0] - t[0]).hypot(p[1] - t[1]) < 1.0)
                };
                near_without += near(ask(&state, &snap_body(click, &vps)).unwrap());
                let mut body: serde_json::Value =
                    serde_json::from_str(&snap_body(click, &vps)).unwrap();
                body["lens_distortion"] = serde_json::json!({"k": k, "k_sd": 0.01});
                body["principal_point"] = serde_json::json!([400.0, 300.0]);
                near_with += near(ask(&state, &body.to_string()).unwrap());
            }
        }
        assert!(
            near_with > near_without,
            "{near_with} within 1 px with the lens, {near_without} without"
        );
    }

    #[test]
    fn a_lens_that_is_not_one_is_refused_naming_it() {
        let (state, vps, _) = rendered();
        let with = |lens: serde_json::Value| {
            let mut body: serde_json::Value =
                serde_json::from_str(&snap_body([100.0, 100.0], &vps)).unwrap();
            body["lens_distortion"] = lens;
            ask(&state, &body.to_string()).unwrap_err()
        };
        let e = with(serde_json::json!({"k": 3.0}));
        assert!(
            e.message.contains("lens_distortion.k is 3") && e.message.contains("-1 to 1"),
            "{}",
            e.message
        );
        let e = with(serde_json::json!({"k": -0.95}));
        assert!(
            e.message.contains("folds this 800 x 600 photo"),
            "{}",
            e.message
        );
        let e = with(serde_json::json!({"k": -0.1, "k_sd": -0.5}));
        assert!(
            e.message.contains("lens_distortion.k_sd is -0.5"),
            "{}",
            e.message
        );
        let e = with(serde_json::json!({"k": -0.1, "bend": 2}));
        assert!(e.message.contains("bend"), "{}", e.message);
        let e = propose_request(
            &state,
            br#"{"photo": "p1", "vanishing_points": [[1, 2], [900, 2]], "lens_distortion": {"k": -3}}"#,
            &Interrupt::default(),
        )
        .unwrap_err();
        assert!(
            e.message.contains("lens_distortion.k is -3"),
            "{}",
            e.message
        );
    }

    #[test]
    fn bad_requests_name_the_value() {
        let (state, vps, _) = rendered();
        let e = ask(&state, &snap_body([-3.0, 200.0], &vps)).unwrap_err();
        assert_eq!(e.status, StatusCode::BAD_REQUEST);
        assert!(
            e.message.contains("(-3, 200)") && e.message.contains("800 x 600"),
            "{}",
            e.message
        );
        let e = ask(&state, r#"{"photo": "p7", "click": [10, 10]}"#).unwrap_err();
        assert_eq!(e.status, StatusCode::NOT_FOUND);
        assert!(e.message.contains("\"p7\""), "{}", e.message);
        let e = ask(&state, r#"{"photo": "p1", "click": [10]}"#).unwrap_err();
        assert!(
            e.message.starts_with("the body is not a snap request"),
            "{}",
            e.message
        );
        let e = ask(
            &state,
            r#"{"photo": "p1", "click": [10, 10], "vanishing_points": [null, [1, 2]]}"#,
        )
        .unwrap_err();
        assert!(
            e.message.contains("vanishing_points[0] is null"),
            "{}",
            e.message
        );
        let e = ask(
            &state,
            r#"{"photo": "p1", "click": [10, 10], "radius": 500}"#,
        )
        .unwrap_err();
        assert!(e.message.contains("radius is 500"), "{}", e.message);
        let e = propose_request(
            &state,
            br#"{"photo": "p1", "vanishing_points": [[1, 2]]}"#,
            &Interrupt::default(),
        )
        .unwrap_err();
        assert!(
            e.message.contains("gives 1 known vanishing points"),
            "{}",
            e.message
        );
        // A photo that cannot be decoded: nothing kept.
        assert!(decode(b"not a photo").is_err());
        assert!(state.0.photos.get("p2").is_none());
    }

    #[test]
    fn boxes_are_proposed_from_the_segments() {
        let (state, vps, corners) = rendered();
        let body = serde_json::json!({"photo": "p1", "vanishing_points": vps}).to_string();
        let v: serde_json::Value = serde_json::from_slice(
            &propose_request(&state, body.as_bytes(), &Interrupt::default()).unwrap(),
        )
        .unwrap();
        let proposals = v["proposals"].as_array().unwrap();
        assert!(!proposals.is_empty(), "{v}");
        // The best one's base near corner is a true box corner.
        let near = &proposals[0]["corners"]["base"]["near"];
        let p = [near[0].as_f64().unwrap(), near[1].as_f64().unwrap()];
        let best = corners
            .iter()
            .filter(|c| c.kind == CornerKind::BoxCorner)
            .map(|c| (c.point_px[0] - p[0]).hypot(c.point_px[1] - p[1]))
            .fold(f64::INFINITY, f64::min);
        assert!(best < 2.0, "{best} px from a box corner: {v}");
    }
}
