//! `POST /api/build`: a scene in; the map, its floor plan, 3D model, occupancy grid and the
//! camera out.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use axum::body::{Body, Bytes};
use axum::extract::{RawQuery, State};
use axum::http::HeaderMap;
use axum::response::Response;
use base64::Engine as _;
use base64::engine::general_purpose::STANDARD as BASE64;
use serde::Serialize;
use vpmap_metrology::interrupt::Interrupt;
use vpmap_metrology::map::{CameraReport, FloorMap};
use vpmap_metrology::scene::LensDistortion;
use vpmap_pipeline::{MapOptions, units_name};

use super::answer::{elapsed_ms, respond, to_json};
use super::plan::CancelOnDrop;
use super::scene::{map_options_from_query, pipeline_error, scene_from_text};
use crate::error::ApiError;
use crate::params::{self, MAX_JSON_BODY_BYTES};
use crate::state::{AppState, run_blocking};

#[derive(Serialize)]
struct Occupancy {
    yaml: String,
    pgm_base64: String,
    width: usize,
    height: usize,
    resolution: f64,
    origin: [f64; 2],
    free: usize,
    occupied: usize,
    unknown: usize,
}

#[derive(Serialize)]
struct CameraSummary {
    perspective: &'static str,
    pitch_deg: f64,
    roll_deg: f64,
    focal_px: f64,
    principal_point: [f64; 2],
    height: f64,
    horizon: Option<[[f64; 2]; 2]>,
    /// The lens the photo's clicks were undistorted by (`map.camera.lens_distortion`), so that
    /// the page can show it and draw the pinhole `horizon` where the photo shows it.
    #[serde(skip_serializing_if = "Option::is_none")]
    lens_distortion: Option<LensDistortion>,
}

#[derive(Serialize)]
struct BuildResponse<'a> {
    map: &'a FloorMap,
    units: &'static str,
    svg: String,
    glb_base64: String,
    occupancy: Occupancy,
    camera: CameraSummary,
    warnings: Vec<String>,
    time_ms: f64,
}

/// The horizon's two ends across the image, pixels: where the image points whose viewing
/// rays are horizontal meet the image's left and right edges (its top and bottom edges when
/// the horizon is steeper than 45 degrees). The ends may lie above or below the image.
/// `None` when no ray is horizontal (the camera looks straight down or up).
fn horizon(camera: &CameraReport) -> Option<[[f64; 2]; 2]> {
    // Pixel (u, v) looks along R K^-1 (u, v, 1); horizontal when the map-frame z is 0:
    // r20 (u - cx) + r21 (v - cy) + r22 f = 0.
    let [r20, r21, r22] = camera.rotation_map_from_camera[2];
    let [cx, cy] = camera.principal_point;
    let f = camera.focal_px;
    let (w, h) = (
        f64::from(camera.image.width),
        f64::from(camera.image.height),
    );
    let ends = if r21.abs() >= r20.abs() {
        let v = |u: f64| cy - (r20 * (u - cx) + r22 * f) / r21;
        [[0.0, v(0.0)], [w, v(w)]]
    } else {
        let u = |v: f64| cx - (r21 * (v - cy) + r22 * f) / r20;
        [[u(0.0), 0.0], [u(h), h]]
    };
    (r20.hypot(r21) > 1e-12 && ends.iter().flatten().all(|c| c.is_finite())).then_some(ends)
}

fn camera_summary(camera: &CameraReport) -> CameraSummary {
    CameraSummary {
        perspective: camera.perspective.name(),
        pitch_deg: camera.pitch_deg,
        roll_deg: camera.roll_deg,
        focal_px: camera.focal_px,
        principal_point: camera.principal_point,
        height: camera.height,
        horizon: horizon(camera),
        lens_distortion: camera.lens_distortion,
    }
}

/// Everything `/api/build` answers, serialised.
fn build_answer(
    body: &[u8],
    options: &MapOptions,
    interrupt: &Interrupt,
) -> Result<Bytes, ApiError> {
    let started = Instant::now();
    let text = params::json_text(body, "a scene (docs/scene-format.md)")?;
    let parsed = scene_from_text(&text)?;
    let built =
        vpmap_pipeline::build_until(&parsed.scene, options, interrupt).map_err(pipeline_error)?;
    let (map, grid) = (&built.map, &built.grid);
    let (free, occupied, unknown) = grid.counts();
    let mut warnings = parsed.warnings;
    warnings.extend(map.warnings.iter().cloned());
    let answer = BuildResponse {
        map,
        units: units_name(map.units),
        svg: built.svg,
        glb_base64: BASE64.encode(&built.model_glb),
        occupancy: Occupancy {
            yaml: built.occupancy_yaml,
            pgm_base64: BASE64.encode(&built.occupancy_pgm),
            width: grid.width(),
            height: grid.height(),
            resolution: grid.resolution_m(),
            origin: grid.origin_m(),
            free,
            occupied,
            unknown,
        },
        camera: camera_summary(&map.camera),
        warnings,
        time_ms: elapsed_ms(started),
    };
    to_json(&answer)
}

/// `POST /api/build?method=&resolution=&robot_radius=&hidden_free=&click_sigma=` with a scene as
/// the body.
pub async fn build(
    State(state): State<AppState>,
    RawQuery(query): RawQuery,
    headers: HeaderMap,
    body: Body,
) -> Response {
    // Dropped with this future when the client goes away: a room's fit then stops.
    let cancelled = CancelOnDrop(Arc::new(AtomicBool::new(false)));
    let result = async {
        let limits = &state.0.limits;
        let body = params::read_body(
            &headers,
            body,
            MAX_JSON_BODY_BYTES,
            limits.body_read_timeout,
        )
        .await?;
        let options = map_options_from_query(query.as_deref())?;
        params::expect_json(&headers)?;
        let slot = state.0.build_slots.take("/api/build").await?;
        let interrupt = Interrupt::default()
            .with_flag(Arc::clone(&cancelled.0))
            .with_timeout(limits.build_timeout);
        run_blocking(&state, "/api/build", move || {
            let _slot = slot;
            build_answer(&body, &options, &interrupt)
        })
        .await
    }
    .await;
    respond(result)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::example::OFFICE_SCENE;

    #[test]
    fn horizon_of_the_office_passes_through_both_horizontal_vanishing_points() {
        let parsed = scene_from_text(OFFICE_SCENE).unwrap_or_else(|e| panic!("{e}"));
        let map = vpmap_pipeline::map_and_grid(&parsed.scene, &MapOptions::default())
            .unwrap_or_else(|e| panic!("{e}"))
            .map;
        let [a, b] = horizon(&map.camera).unwrap_or_default();
        assert_eq!((a[0], b[0]), (0.0, 1600.0));
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        for vp in &map.camera.vanishing_points[..2] {
            // Distance of the vanishing point from the horizon line, pixels.
            let d = (dx * (vp[1] - a[1]) - dy * (vp[0] - a[0])).abs() / dx.hypot(dy);
            assert!(d < 1e-6 * vp[0].hypot(vp[1]).max(1.0), "{vp:?}: {d}");
        }
        // 3 degrees of roll: the horizon falls to the right.
        assert!(((b[1] - a[1]) / 1600.0 - 3f64.to_radians().tan()).abs() < 1e-9);
    }

    #[test]
    fn the_answer_s_camera_carries_the_photo_s_lens() {
        let answer = |scene: &str| -> serde_json::Value {
            let bytes = build_answer(
                scene.as_bytes(),
                &MapOptions::default(),
                &Interrupt::default(),
            )
            .unwrap_or_else(|e| panic!("{e:?}"));
            serde_json::from_slice(&bytes).unwrap_or_else(|e| panic!("{e}"))
        };
        let plain = answer(OFFICE_SCENE);
        assert!(
            plain["camera"].get("lens_distortion").is_none(),
            "{}",
            plain["camera"]
        );
        let mut scene: serde_json::Value =
            serde_json::from_str(OFFICE_SCENE).unwrap_or_else(|e| panic!("{e}"));
        scene["lens_distortion"] = serde_json::json!({"k": -0.02, "k_sd": 0.004});
        let lensed = answer(&scene.to_string());
        assert_eq!(lensed["camera"]["lens_distortion"]["k"], -0.02);
        assert_eq!(lensed["camera"]["lens_distortion"]["k_sd"], 0.004);
    }
}
