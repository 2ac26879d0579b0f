//! The request checks of the JSON endpoints, callable without a server: for the fuzz target
//! `web_body` (`fuzz/`, see `docs/fuzzing.md`). Each function runs the same parsing and
//! validation as its endpoint, in the same order, and stops before the expensive work
//! (planning, pictures, the 3D model); `/api/snap` and `/api/propose` run in full on a small
//! kept photo (fuzz targets `snap_body`, `propose_body`). Not part of the supported API.

use std::sync::OnceLock;

use vpmap_metrology::interrupt::Interrupt;
use vpmap_metrology::scene::ImageSize;
use vpmap_metrology::synth::{SynthOptions, synthesize};
use vpmap_pipeline::MapOptions;
use vpmap_vision::synthetic::photo::{PhotoOptions, render_photo};

use super::detect::DetectQuery;
use super::navigate::checked_navigate_request;
use super::plan::checked_plan_request;
use super::scene::{MAX_GRID_CELLS, map_options_from_query, pipeline_error, scene_from_text};
use super::snap::{propose_request, snap_request};
use crate::error::ApiError;
use crate::limits::ServerLimits;
use crate::params;
use crate::photos::StoredPhoto;
use crate::state::AppState;

/// The grid limit: the page's ([`MAX_GRID_CELLS`]) or `max_grid_cells`, whichever is smaller.
fn capped(mut options: MapOptions, max_grid_cells: f64) -> MapOptions {
    options.max_grid_cells = Some(max_grid_cells.min(MAX_GRID_CELLS));
    options
}

/// `POST /api/build?{query}` with `body`: the query's options, the scene, then its map and
/// occupancy grid (at most `max_grid_cells` cells, and never more than the page allows).
///
/// # Errors
/// The 400 answer `/api/build` would give.
pub fn build_request(
    query: Option<&str>,
    body: &[u8],
    max_grid_cells: f64,
) -> Result<(), ApiError> {
    let options = capped(map_options_from_query(query)?, max_grid_cells);
    let text = params::json_text(body, "a scene (docs/scene-format.md)")?;
    let parsed = scene_from_text(&text)?;
    vpmap_pipeline::map_and_grid(&parsed.scene, &options).map_err(pipeline_error)?;
    Ok(())
}

/// `POST /api/plan` with `body`: the request's fields, options and planners, the scene, its
/// map and grid (at most `max_grid_cells` cells) and the start and goal cells; the planners
/// are not run.
///
/// # Errors
/// The 400 answer `/api/plan` would give before planning.
pub fn plan_request(body: &[u8], max_grid_cells: f64) -> Result<(), ApiError> {
    checked_plan_request(body, max_grid_cells, &Interrupt::default()).map(|_| ())
}

/// `POST /api/navigate` with `body`: the request's own fields (`truth`, `planner`,
/// `sensor_range`), then everything [`plan_request`] checks, the sensor range against the grid
/// and the true office rasterised on the grid; the robot does not drive.
///
/// # Errors
/// The 400 answer `/api/navigate` would give before driving.
pub fn navigate_request(body: &[u8], max_grid_cells: f64) -> Result<(), ApiError> {
    checked_navigate_request(body, max_grid_cells, &Interrupt::default()).map(|_| ())
}

/// The server state of [`snap_body`] and [`propose_body`]: one kept photo, id `p1`, a
/// 320 x 240 rendering of a synthetic scene of boxes (made on first use).
fn photo_state() -> Result<&'static AppState, ApiError> {
    static STATE: OnceLock<Result<AppState, String>> = OnceLock::new();
    STATE
        .get_or_init(|| {
            let (scene, truth) = synthesize(&SynthOptions {
                image: ImageSize {
                    width: 320,
                    height: 240,
                },
                focal_px: 220.0,
                ..SynthOptions::default()
            })
            .map_err(|e| e.to_string())?;
            let photo = render_photo(&scene, &truth, &PhotoOptions::default())
                .map_err(|e| e.to_string())?;
            let state = AppState::new(None, true, ServerLimits::default());
            state.0.photos.insert(StoredPhoto::new(&photo.image));
            Ok(state)
        })
        .as_ref()
        .map_err(|e| ApiError::bad_request(format!("no photo to fuzz on: {e}")))
}

/// `POST /api/snap` with `body`, on a kept photo `p1` of 320 x 240 pixels (see
/// `photo_state`): the request's fields, its vanishing points and options, then the snap.
///
/// # Errors
/// The 400 or 404 answer `/api/snap` would give.
pub fn snap_body(body: &[u8]) -> Result<(), ApiError> {
    snap_request(photo_state()?, body).map(|_| ())
}

/// `POST /api/propose` with `body`, on the same kept photo as [`snap_body`]: the request's
/// fields and vanishing points, the photo's segments (found once), then the box proposals
/// (bounded by `ProposalOptions`' caps; no time limit, so that a run is deterministic).
///
/// # Errors
/// The 400 or 404 answer `/api/propose` would give.
pub fn propose_body(body: &[u8]) -> Result<(), ApiError> {
    propose_request(photo_state()?, body, &Interrupt::default()).map(|_| ())
}

/// `POST /api/detect?{query}` for a photo of `width` x `height` pixels: the query's options,
/// then the intrinsics against the photo's size.
///
/// # Errors
/// The 400 answer `/api/detect` would give before decoding the photo, or after reading its
/// size.
pub fn detect_query(query: Option<&str>, width: u32, height: u32) -> Result<(), ApiError> {
    DetectQuery::parse(query)?.check_against(width, height)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::example::OFFICE_SCENE;

    #[test]
    fn build_request_reads_the_query_the_scene_and_the_grid_limit() {
        let office = OFFICE_SCENE.as_bytes();
        assert!(build_request(Some("resolution=0.1"), office, 1e5).is_ok());
        // 0.05 m makes about 177 x 209 cells: over a limit of 20000, under the page's.
        let e = build_request(None, office, 2e4).err();
        assert!(e.is_some_and(|e| e.message.contains("the limit is 20000 cells")));
        let e = build_request(Some("method=side"), office, 1e5).err();
        assert!(e.is_some_and(|e| e.message.starts_with("method is \"side\"")));
        let e = build_request(None, b"[1, 2]", 1e5).err();
        assert!(e.is_some_and(|e| e.message.contains("must be a JSON object")));
    }

    #[test]
    fn plan_request_checks_fields_planners_and_endpoints() {
        let body = |start: &str, planners: &str| {
            format!(
                r#"{{"scene": {OFFICE_SCENE}, "resolution": 0.1, "hidden_free": true, "start": {start}, "goal": [2.0, 5.0], "planners": {planners}}}"#
            )
        };
        assert!(plan_request(body("[1.5, 3.5]", r#"["astar"]"#).as_bytes(), 1e5).is_ok());
        let e = plan_request(body("[1.5, 3.5]", r#"["dijkstra"]"#).as_bytes(), 1e5).err();
        assert!(e.is_some_and(|e| e.message.contains("\"dijkstra\", which is not a planner")));
        let e = plan_request(body("[100, 3.5]", "null").as_bytes(), 1e5).err();
        assert!(
            e.as_ref().is_some_and(|e| e.message.starts_with("start ")),
            "{e:?}"
        );
        let e = plan_request(
            br#"{"scene": {}, "start": [0, 0], "goal": [1, 1], "x": 1}"#,
            1e5,
        )
        .err();
        assert!(e.is_some_and(|e| e.message.contains("unknown field \"x\"")));
    }

    #[test]
    fn navigate_request_checks_its_fields_then_the_plan_request() {
        let body = |extra: &str| {
            format!(
                r#"{{"scene": {OFFICE_SCENE}, "resolution": 0.1, "start": [1.1, 1.7], "goal": [0.2, 5.0]{extra}}}"#
            )
        };
        assert!(navigate_request(body(r#", "truth": "example""#).as_bytes(), 1e5).is_ok());
        let e = navigate_request(body("").as_bytes(), 1e5).err();
        assert!(e.is_some_and(|e| e.message.contains("field `truth`")));
        let e = navigate_request(
            body(r#", "truth": "example", "sensor_range": -1"#).as_bytes(),
            1e5,
        )
        .err();
        assert!(e.is_some_and(|e| e.message.starts_with("sensor_range is -1")));
        // The grid limit of the fuzz target applies to the believed grid.
        let e = navigate_request(body(r#", "truth": "example""#).as_bytes(), 2e3).err();
        assert!(e.is_some_and(|e| e.message.contains("the limit is 2000 cells")),);
    }

    #[test]
    fn snap_and_propose_bodies_run_on_the_kept_photo() {
        let vps = "[[1600, 100], [-900, 120], [160, -4000]]";
        let snap = format!(r#"{{"photo": "p1", "click": [160, 200], "vanishing_points": {vps}}}"#);
        assert!(snap_body(snap.as_bytes()).is_ok());
        let e = snap_body(br#"{"photo": "p2", "click": [1, 1]}"#).err();
        assert!(e.is_some_and(|e| e.status == axum::http::StatusCode::NOT_FOUND));
        let propose =
            format!(r#"{{"photo": "p1", "vanishing_points": {vps}, "max_proposals": 3}}"#);
        assert!(propose_body(propose.as_bytes()).is_ok());
        let e =
            propose_body(br#"{"photo": "p1", "vanishing_points": [], "max_proposals": 0}"#).err();
        assert!(e.is_some_and(|e| e.message.contains("gives 0 known vanishing points")));
    }

    #[test]
    fn detect_query_checks_options_against_the_photo() {
        assert!(detect_query(Some("focal_px=900&principal_point=400,300"), 800, 600).is_ok());
        assert!(detect_query(Some("principal_point=900,300"), 800, 600).is_err());
        assert!(detect_query(Some("max_side=10"), 800, 600).is_err());
    }
}
