//! `POST /api/navigate`: a robot drives the map built from the scene (its belief) across the
//! bundled example's true office, senses the truth within its sensor range, and re-plans
//! (`vpmap_plan::navigate`, docs/navigation.md). What a map's error costs, on the page.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use axum::body::{Body, Bytes};
use axum::extract::{RawQuery, State};
use axum::http::HeaderMap;
use axum::response::Response;
use serde::Serialize;
use vpmap_metrology::interrupt::Interrupt;
use vpmap_metrology::synth::Truth;
use vpmap_plan::navigate::{
    MAX_SENSOR_RANGE_CELLS, NavigateOptions, OnlinePlanner, navigate, truth_optimum,
};
use vpmap_plan::{Budget, OccupancyGrid, Stop};
use vpmap_raster::truth_grid;

use super::answer::{elapsed_ms, respond, to_json};
use super::plan::{
    CancelOnDrop, CheckedPlan, PAGE_MAX_EXPANSIONS, PAGE_MAX_SIGHT_CELLS, checked_plan_request,
    json_body, world,
};
use super::scene::MAX_GRID_CELLS;
use crate::error::ApiError;
use crate::example::OFFICE_TRUTH;
use crate::params;
use crate::state::{AppState, run_blocking};

/// The sensor range when the request gives none, metres.
pub const DEFAULT_SENSOR_RANGE_M: f64 = 2.0;
/// Most cells a robot may move on the page (a path on the page's largest grid is far
/// shorter; the run stops with "move limit reached" beyond).
pub const PAGE_MAX_MOVES: usize = 1_000_000;
/// Most re-plans on the page.
pub const PAGE_MAX_REPLANS: usize = 100_000;
/// The fields this endpoint reads besides a plan request's (which it takes but `planners`).
const NAVIGATE_FIELDS: [&str; 3] = ["truth", "planner", "sensor_range"];
/// The truths the server knows.
const TRUTHS: [&str; 1] = ["example"];

/// One planning event, in map units.
#[derive(Serialize)]
struct EventOut {
    /// Where the robot was.
    at: [f64; 2],
    /// `initial`, `blocked` or `opened`.
    reason: &'static str,
    /// Planner time, milliseconds.
    time_ms: f64,
    /// Nodes expanded (MBPP: bug steps).
    expanded: usize,
    /// The new plan's length on the belief, map units (`null`: none).
    planned_length: Option<f64>,
    /// Online MBPP used a kept alternative.
    used_alternative: bool,
    /// Unseen map obstacles believed free from here on (no path otherwise).
    doubted_cells: usize,
}

/// A true object, for drawing.
#[derive(Serialize)]
struct TruthObjectOut<'a> {
    name: &'a str,
    footprint: &'a [[f64; 2]],
}

/// The answer.
#[derive(Serialize)]
struct NavigateResponse<'a> {
    planner: &'static str,
    /// `reached`, `goal unreachable after sensing`, ...
    outcome: &'static str,
    reached: bool,
    /// The driven polyline, map units.
    waypoints: Vec<[f64; 2]>,
    /// Its length, map units.
    length: f64,
    /// Every planning event, the initial one first.
    events: Vec<EventOut>,
    /// Planning events after the first.
    replans: usize,
    /// Total planning time, milliseconds.
    planning_time_ms: f64,
    /// Cells moved.
    moves: usize,
    /// Cells the sensor saw.
    seen_cells: usize,
    /// Shortest 8-connected path on the truth, map units.
    optimum_octile: Option<f64>,
    /// Shortest any-angle path on the truth, map units.
    optimum_any_angle: Option<f64>,
    /// The true office: its floor and objects (map units).
    truth_floor: &'a [[f64; 2]],
    truth_objects: Vec<TruthObjectOut<'a>>,
    units: &'static str,
    sensor_range: f64,
    warnings: Vec<String>,
    time_ms: f64,
}

/// The request's own fields, taken out of its JSON object; the rest is a plan request.
pub(crate) struct DriveFields {
    planner: OnlinePlanner,
    sensor_range: Option<f64>,
}

fn drive_fields(body: &[u8]) -> Result<(DriveFields, Vec<u8>), ApiError> {
    let text = params::json_text(body, "a navigate request")?;
    let mut value: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| ApiError::bad_request(format!("the body is not valid JSON: {e}")))?;
    let Some(fields) = value.as_object_mut() else {
        return Err(ApiError::bad_request(
            "the body is not a navigate request: it must be a JSON object with scene, start, goal and truth",
        ));
    };
    if fields.contains_key("planners") {
        return Err(ApiError::bad_request(format!(
            "field `planners` is for /api/plan; a robot drives with one `planner`: one of {}",
            OnlinePlanner::ALL.map(OnlinePlanner::name).join(", ")
        )));
    }
    let truth = fields.remove("truth");
    match truth.as_ref().and_then(serde_json::Value::as_str) {
        Some(t) if TRUTHS.contains(&t) => {}
        _ => {
            return Err(ApiError::bad_request(format!(
                "field `truth` must be one of {:?} (the true map to drive on), got {}",
                TRUTHS,
                truth.map_or_else(|| "nothing".to_owned(), |v| v.to_string())
            )));
        }
    }
    let planner = match fields.remove("planner") {
        None | Some(serde_json::Value::Null) => OnlinePlanner::DStarLite,
        Some(serde_json::Value::String(name)) => name.parse().map_err(|_| {
            ApiError::bad_request(format!(
                "field `planner` is {name:?}, which is not an online planner: one of {}",
                OnlinePlanner::ALL.map(OnlinePlanner::name).join(", ")
            ))
        })?,
        Some(v) => {
            return Err(ApiError::bad_request(format!(
                "field `planner` must be a planner's name, got {v}"
            )));
        }
    };
    let sensor_range = match fields.remove("sensor_range") {
        None | Some(serde_json::Value::Null) => None,
        Some(v) => Some(v.as_f64().ok_or_else(|| {
            ApiError::bad_request(format!(
                "field `sensor_range` must be a number of map units, got {v}"
            ))
        })?),
    };
    // The free-space assumption unless the request says otherwise.
    fields
        .entry("unknown_passable")
        .or_insert(serde_json::Value::Bool(true));
    let rest = serde_json::to_vec(&value).map_err(|e| {
        ApiError::bad_request(format!("the body cannot be read as a plan request: {e}"))
    })?;
    Ok((
        DriveFields {
            planner,
            sensor_range,
        },
        rest,
    ))
}

/// A navigate request that passed every check: what the run needs.
pub(crate) struct CheckedNavigate {
    /// The request's own fields (the planner; the sensor range as given).
    drive: DriveFields,
    /// The sensor range, checked, map units.
    sensor_range: f64,
    /// The plan request's part (the believed grid, start, goal, ...).
    plan: CheckedPlan,
    /// The bundled truth.
    truth: Truth,
    /// The truth rasterised on the believed grid's cells.
    true_grid: OccupancyGrid,
}

/// Parse and check a `/api/navigate` body, in the endpoint's order: its own fields, the plan
/// request (with at most `max_grid_cells` grid cells), the sensor range, the units and the
/// true grid.
///
/// # Errors
/// The 400 answer `/api/navigate` gives before driving.
pub(crate) fn checked_navigate_request(
    body: &[u8],
    max_grid_cells: f64,
    interrupt: &Interrupt,
) -> Result<CheckedNavigate, ApiError> {
    let (drive, plan_body) = drive_fields(body)?;
    let plan = checked_plan_request(&plan_body, max_grid_cells, interrupt).map_err(|mut e| {
        e.message = e
            .message
            .replace("a plan request", "a navigate request")
            .replace(
                "in the plan request; known: ",
                &format!(
                    "in the navigate request; known: {}, ",
                    NAVIGATE_FIELDS.join(", ")
                ),
            );
        e
    })?;
    let (resolution, units) = (plan.grid.resolution_m(), plan.units);
    let sensor_range = drive.sensor_range.unwrap_or(DEFAULT_SENSOR_RANGE_M);
    let max_range = MAX_SENSOR_RANGE_CELLS * resolution;
    if !(sensor_range.is_finite() && sensor_range >= resolution && sensor_range <= max_range) {
        return Err(ApiError::bad_request(format!(
            "sensor_range is {}; it must be at least one cell ({resolution} {units}) and at most {MAX_SENSOR_RANGE_CELLS} cells ({} {units})",
            vpmap_pipeline::num(sensor_range),
            vpmap_pipeline::num(max_range)
        )));
    }
    let truth: Truth = serde_json::from_str(OFFICE_TRUTH).map_err(|e| {
        ApiError::new(
            axum::http::StatusCode::INTERNAL_SERVER_ERROR,
            format!("internal error: the bundled truth does not parse: {e}"),
        )
    })?;
    if units != "m" {
        return Err(ApiError::bad_request(
            "the true office is in metres: give the scene a scale (a camera height, a known distance or an object size) before driving on it",
        ));
    }
    let true_grid = truth_grid(&truth, &plan.grid, plan.robot_radius)
        .map_err(|e| ApiError::bad_request(format!("the true office: {e}")))?;
    Ok(CheckedNavigate {
        drive,
        sensor_range,
        plan,
        truth,
        true_grid,
    })
}

/// Check the request, drive, and write the answer.
fn navigate_answer(body: &[u8], stop: Stop, interrupt: &Interrupt) -> Result<Bytes, ApiError> {
    let started = Instant::now();
    let CheckedNavigate {
        drive,
        sensor_range,
        plan:
            CheckedPlan {
                unknown_passable,
                warnings,
                units,
                grid,
                start,
                goal,
                ..
            },
        truth,
        true_grid,
    } = checked_navigate_request(body, MAX_GRID_CELLS, interrupt)?;
    let resolution = grid.resolution_m();
    let budget = Budget {
        max_expansions: PAGE_MAX_EXPANSIONS,
        max_sight_cells: PAGE_MAX_SIGHT_CELLS,
        stop,
    };
    let opts = NavigateOptions {
        planner: drive.planner,
        sensor_range_cells: sensor_range / resolution,
        unknown_passable,
        max_moves: PAGE_MAX_MOVES,
        max_replans: PAGE_MAX_REPLANS,
        budget: budget.clone(),
    };
    let on_truth =
        |e: vpmap_plan::PlanError| ApiError::bad_request(format!("on the true office: {e}"));
    let run = navigate(&grid, &true_grid, start, goal, &opts).map_err(on_truth)?;
    let optimum = truth_optimum(&true_grid, start, goal, &budget).map_err(on_truth)?;
    let events = run
        .events
        .iter()
        .map(|e| EventOut {
            at: world(&grid, &[e.cell])[0],
            reason: e.reason.as_str(),
            time_ms: e.time_s * 1e3,
            expanded: e.expanded,
            planned_length: e.planned_length_cells.map(|l| l * resolution),
            used_alternative: e.used_alternative,
            doubted_cells: e.doubted_cells,
        })
        .collect::<Vec<_>>();
    to_json(&NavigateResponse {
        planner: drive.planner.name(),
        outcome: run.outcome.as_str(),
        reached: run.outcome == vpmap_plan::navigate::Outcome::Reached,
        waypoints: world(&grid, &run.waypoints),
        length: run.length_cells * resolution,
        replans: events.len().saturating_sub(1),
        events,
        planning_time_ms: run.planning_time_s * 1e3,
        moves: run.moves,
        seen_cells: run.belief.seen.iter().filter(|&&s| s).count(),
        optimum_octile: optimum.octile_cells.map(|l| l * resolution),
        optimum_any_angle: optimum.any_angle_cells.map(|l| l * resolution),
        truth_floor: &truth.floor,
        truth_objects: truth
            .objects
            .iter()
            .map(|o| TruthObjectOut {
                name: &o.name,
                footprint: &o.footprint,
            })
            .collect(),
        units,
        sensor_range,
        warnings,
        time_ms: elapsed_ms(started),
    })
}

/// `POST /api/navigate` with a navigate request as the body: a plan request (without
/// `planners`) plus `truth` (`"example"`), `planner` (an online planner, default
/// `dstar-lite`) and `sensor_range` (map units, default 2).
pub async fn navigate_handler(
    State(state): State<AppState>,
    RawQuery(query): RawQuery,
    headers: HeaderMap,
    body: Body,
) -> Response {
    // Dropped with this future when the client goes away: the run then stops.
    let cancelled = CancelOnDrop(Arc::new(AtomicBool::new(false)));
    let result = async {
        let body = json_body(&state, query.as_deref(), &headers, body).await?;
        let slot = state.0.plan_slots.take("/api/navigate").await?;
        let timeout = state.0.limits.plan_timeout;
        let stop = Stop::new()
            .with_flag(Arc::clone(&cancelled.0))
            .with_timeout(timeout);
        let interrupt = Interrupt::default()
            .with_flag(Arc::clone(&cancelled.0))
            .with_timeout(timeout);
        run_blocking(&state, "/api/navigate", move || {
            let _slot = slot;
            navigate_answer(&body, stop, &interrupt)
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

    fn body(extra: &str) -> Vec<u8> {
        format!(
            r#"{{"scene": {OFFICE_SCENE}, "resolution": 0.1, "start": [1.1, 1.7], "goal": [0.2, 5.0]{extra}}}"#
        )
        .into_bytes()
    }

    #[test]
    fn the_robot_reaches_the_goal_on_the_true_office_no_shorter_than_its_optimum() {
        for planner in OnlinePlanner::ALL {
            let answer = navigate_answer(
                &body(&format!(
                    r#", "truth": "example", "planner": "{}""#,
                    planner.name()
                )),
                Stop::new(),
                &Interrupt::default(),
            )
            .unwrap();
            let v: serde_json::Value = serde_json::from_slice(&answer).unwrap();
            assert_eq!(v["outcome"], "reached", "{planner:?}: {v}");
            let length = v["length"].as_f64().unwrap();
            let optimum = v["optimum_any_angle"].as_f64().unwrap();
            assert!(
                length >= optimum - 1e-9,
                "{planner:?}: {length} < {optimum}"
            );
            assert!(v["events"][0]["reason"] == "initial");
            // The track starts on the start's cell (within half a cell of the point asked).
            let first = &v["waypoints"][0];
            let (x, y) = (first[0].as_f64().unwrap(), first[1].as_f64().unwrap());
            assert!(
                (x - 1.1).abs() <= 0.05 + 1e-9 && (y - 1.7).abs() <= 0.05 + 1e-9,
                "{first}"
            );
        }
    }

    #[test]
    fn bad_requests_name_the_field() {
        let e = |extra: &str| {
            navigate_answer(&body(extra), Stop::new(), &Interrupt::default())
                .err()
                .unwrap()
                .message
        };
        assert!(e("").contains("field `truth` must be one of [\"example\"]"));
        assert!(e(r#", "truth": "kitchen""#).contains("got \"kitchen\""));
        assert!(
            e(r#", "truth": "example", "planner": "dijkstra""#)
                .contains("\"dijkstra\", which is not an online planner")
        );
        assert!(e(r#", "truth": "example", "planners": ["astar"]"#).contains("for /api/plan"));
        let m = e(r#", "truth": "example", "sensor_range": 0"#);
        assert!(
            m.starts_with("sensor_range is 0; it must be at least one cell (0.1 m)"),
            "{m}"
        );
        assert!(
            e(r#", "truth": "example", "sensor_range": 1e300"#).contains("sensor_range is 1e300")
        );
        assert!(
            e(r#", "truth": "example", "x": 1"#)
                .contains("unknown field \"x\" in the navigate request")
        );
    }
}
