//! `POST /api/plan`: a scene, a start and a goal in; the paths of several planners out, on
//! the occupancy grid `/api/build` makes with the same parameters.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use axum::body::{Body, Bytes};
use axum::extract::{RawQuery, State};
use axum::http::HeaderMap;
use axum::response::Response;
use serde::Serialize;
use vpmap_metrology::interrupt::Interrupt;
use vpmap_pipeline::{
    Coordinates, Endpoint, EndpointRules, OptionNames, PlanningMap, endpoint_cell, units_name,
};
use vpmap_plan::grid::{CellXy, OccupancyGrid};
use vpmap_plan::mbpp::{BugFate, BugTrack};
use vpmap_plan::plan::Plan;
use vpmap_plan::planner::{Planner, PlannerKind};
use vpmap_plan::{Budget, Stop};

use super::answer::{elapsed_ms, respond, to_json};
use super::scene::{MAX_GRID_CELLS, map_options, pipeline_error, scene_from_value};
use super::smooth::{SmoothAsk, radius_fits, run_smooth, smooth_ask, smooth_plan_options};
use crate::error::ApiError;
use crate::params::{self, MAX_JSON_BODY_BYTES, Query};
use crate::state::{AppState, run_blocking};

/// Most bug-track points returned in all (MBPP's tracks are cut beyond).
pub const MAX_TRACK_POINTS: usize = 100_000;
/// MBPP's bug-step budget on the page: about two seconds of work (MBPP takes about ten
/// million steps a second on the project's machine); beyond it the planner answers with an
/// error naming the budget instead of holding the server.
pub const PAGE_MAX_BUG_STEPS: usize = 20_000_000;
/// Most MBPP alternatives the page returns (the shortest).
pub const PAGE_MAX_ALTERNATIVES: usize = 20;
/// Node expansions of A*, A* PS, Theta* and the exact planner on the page: the grid-cell cap
/// (a search on the page's largest grid may expand every cell once).
pub const PAGE_MAX_EXPANSIONS: usize = 4_000_000;
/// Cells looked up by the line-of-sight checks of A* PS, Theta* and the exact planner on the
/// page: about a second of work in a release build.
pub const PAGE_MAX_SIGHT_CELLS: usize = 400_000_000;
/// Planners run when the request names none.
const DEFAULT_PLANNERS: [PlannerKind; 3] = [
    PlannerKind::Mbpp,
    PlannerKind::AstarPs,
    PlannerKind::Optimal,
];

/// The fields a plan request may have.
const PLAN_FIELDS: [&str; 14] = [
    "scene",
    "method",
    "resolution",
    "robot_radius",
    "hidden_free",
    "click_sigma",
    "unknown_passable",
    "start",
    "goal",
    "planners",
    "turning_radius",
    "start_heading_deg",
    "goal_heading_deg",
    "reverse",
];

/// The name of the smooth planner in `planners` (not a [`PlannerKind`]: it plans poses).
const SMOOTH: &str = "smooth";

/// One planner a request asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PlannerChoice {
    /// A grid planner.
    Grid(PlannerKind),
    /// The smooth planner (`turning_radius`, headings, `reverse`).
    Smooth,
}

/// A plan request, read field by field so that every message names its field.
pub(super) struct PlanRequest {
    pub(super) scene: serde_json::Value,
    pub(super) method: Option<String>,
    pub(super) resolution: Option<f64>,
    pub(super) robot_radius: Option<f64>,
    pub(super) hidden_free: Option<bool>,
    pub(super) click_sigma: Option<f64>,
    pub(super) unknown_passable: Option<bool>,
    pub(super) start: [f64; 2],
    pub(super) goal: [f64; 2],
    pub(super) planners: Option<Vec<String>>,
    pub(super) turning_radius: Option<f64>,
    pub(super) start_heading_deg: Option<f64>,
    pub(super) goal_heading_deg: Option<f64>,
    pub(super) reverse: Option<bool>,
}

fn field_error(key: &str, wanted: &str, got: &serde_json::Value) -> ApiError {
    let mut shown = got.to_string();
    if shown.len() > 60 {
        shown.truncate(57);
        shown.push_str("...");
    }
    ApiError::bad_request(format!("field `{key}` must be {wanted}, got {shown}"))
}

impl PlanRequest {
    pub(super) fn from_text(text: &str) -> Result<Self, ApiError> {
        let value: serde_json::Value = serde_json::from_str(text)
            .map_err(|e| ApiError::bad_request(format!("the body is not valid JSON: {e}")))?;
        let Some(fields) = value.as_object() else {
            return Err(ApiError::bad_request(
                "the body is not a plan request: it must be a JSON object with scene, start and goal",
            ));
        };
        if let Some(unknown) = fields.keys().find(|k| !PLAN_FIELDS.contains(&k.as_str())) {
            return Err(ApiError::bad_request(format!(
                "unknown field {unknown:?} in the plan request; known: {}",
                PLAN_FIELDS.join(", ")
            )));
        }
        let present = |key: &str| fields.get(key).filter(|v| !v.is_null());
        let number = |key: &str| {
            present(key)
                .map(|v| v.as_f64().ok_or_else(|| field_error(key, "a number", v)))
                .transpose()
        };
        let flag = |key: &str| {
            present(key)
                .map(|v| {
                    v.as_bool()
                        .ok_or_else(|| field_error(key, "true or false", v))
                })
                .transpose()
        };
        let point = |key: &str| -> Result<[f64; 2], ApiError> {
            let wanted = "a point [x, y] in map units (two numbers)";
            let v = present(key).ok_or_else(|| {
                ApiError::bad_request(format!("field `{key}` is missing; give {wanted}"))
            })?;
            match v.as_array().map(Vec::as_slice) {
                Some([x, y]) => match (x.as_f64(), y.as_f64()) {
                    (Some(x), Some(y)) => Ok([x, y]),
                    _ => Err(field_error(key, wanted, v)),
                },
                _ => Err(field_error(key, wanted, v)),
            }
        };
        let scene = present("scene").cloned().ok_or_else(|| {
            ApiError::bad_request("field `scene` is missing; give the scene JSON object")
        })?;
        let method = present("method")
            .map(|v| {
                v.as_str().map(str::to_owned).ok_or_else(|| {
                    field_error("method", "\"fit\", \"sideview\" or \"projective\"", v)
                })
            })
            .transpose()?;
        let planners = present("planners")
            .map(|v| {
                let wanted = "a list of planner names";
                v.as_array()
                    .ok_or_else(|| field_error("planners", wanted, v))?
                    .iter()
                    .map(|n| {
                        n.as_str()
                            .map(str::to_owned)
                            .ok_or_else(|| field_error("planners", wanted, v))
                    })
                    .collect::<Result<Vec<_>, _>>()
            })
            .transpose()?;
        Ok(Self {
            scene,
            method,
            resolution: number("resolution")?,
            robot_radius: number("robot_radius")?,
            hidden_free: flag("hidden_free")?,
            click_sigma: number("click_sigma")?,
            unknown_passable: flag("unknown_passable")?,
            start: point("start")?,
            goal: point("goal")?,
            planners,
            turning_radius: number("turning_radius")?,
            start_heading_deg: number("start_heading_deg")?,
            goal_heading_deg: number("goal_heading_deg")?,
            reverse: flag("reverse")?,
        })
    }
}

#[derive(Serialize)]
struct PathOut {
    length_m: f64,
    waypoints: Vec<[f64; 2]>,
}

#[derive(Serialize)]
struct BugOut {
    parent: Option<usize>,
    cells: Vec<[f64; 2]>,
    hits: Vec<[f64; 2]>,
    leaves: Vec<[f64; 2]>,
    steps: usize,
    fate: &'static str,
}

#[derive(Serialize, Default)]
struct StatsOut {
    expanded: usize,
    generated: usize,
    los_checks: usize,
    los_cells: usize,
}

#[derive(Serialize)]
struct ResultOut {
    /// The smooth planner's answer as `vpmap plan --planner smooth --json` gives it.
    #[serde(skip_serializing_if = "Option::is_none")]
    smooth: Option<serde_json::Value>,
    planner: &'static str,
    found: bool,
    skipped: bool,
    note: Option<String>,
    length_m: Option<f64>,
    waypoints: Vec<[f64; 2]>,
    alternatives: Vec<PathOut>,
    bugs: Vec<BugOut>,
    stats: StatsOut,
    time_ms: f64,
}

#[derive(Serialize)]
struct GridOut {
    width: usize,
    height: usize,
    resolution: f64,
    origin: [f64; 2],
}

#[derive(Serialize)]
struct PlanResponse {
    results: Vec<ResultOut>,
    grid: GridOut,
    units: &'static str,
    start_cell: [usize; 2],
    goal_cell: [usize; 2],
    warnings: Vec<String>,
    time_ms: f64,
}

fn fate_name(fate: BugFate) -> &'static str {
    match fate {
        BugFate::ReachedGoal => "reached-goal",
        BugFate::Waiting => "waiting",
        BugFate::Looped => "looped",
        BugFate::Stuck => "stuck",
    }
}

fn planner_names() -> String {
    format!(
        "{}, {SMOOTH}",
        PlannerKind::ALL.map(PlannerKind::name).join(", ")
    )
}

/// The planners asked for, in order, each once.
pub(super) fn planners(names: Option<&[String]>) -> Result<Vec<PlannerChoice>, ApiError> {
    let Some(names) = names else {
        return Ok(DEFAULT_PLANNERS.map(PlannerChoice::Grid).to_vec());
    };
    if names.is_empty() {
        return Err(ApiError::bad_request(format!(
            "field `planners` is empty; name one or more of {}",
            planner_names()
        )));
    }
    let mut kinds = Vec::new();
    for name in names {
        if name == SMOOTH {
            if !kinds.contains(&PlannerChoice::Smooth) {
                kinds.push(PlannerChoice::Smooth);
            }
            continue;
        }
        let kind: PlannerKind = name.parse().map_err(|_| {
            ApiError::bad_request(format!(
                "field `planners` names {name:?}, which is not a planner; choose from {}",
                planner_names()
            ))
        })?;
        if !kinds.contains(&PlannerChoice::Grid(kind)) {
            kinds.push(PlannerChoice::Grid(kind));
        }
    }
    Ok(kinds)
}

/// A path in map units.
fn path_out(grid: &OccupancyGrid, plan: &Plan) -> PathOut {
    PathOut {
        length_m: plan.length_cells * grid.resolution_m(),
        waypoints: world(grid, &plan.waypoints),
    }
}

/// Cell centres in map units, rounded to 1e-6 (a micrometre: the JSON stays short).
pub(super) fn world(grid: &OccupancyGrid, cells: &[CellXy]) -> Vec<[f64; 2]> {
    cells
        .iter()
        .map(|&CellXy { x, y }| {
            grid.world_from_cell(x, y)
                .map(|v| (v * 1e6).round() / 1e6 + 0.0)
        })
        .collect()
}

/// When the planners of one request must stop.
pub(super) struct PlanStop {
    /// Set when the client has gone.
    pub(super) cancelled: Arc<AtomicBool>,
    /// The end of the time allowed to all planners of the request.
    pub(super) all_by: Instant,
    /// Time allowed to each planner.
    pub(super) each: std::time::Duration,
}

impl PlanStop {
    /// The [`Stop`] of a planner starting now: its own time limit, or what is left of the
    /// request's if that ends sooner.
    pub(super) fn for_planner(&self) -> Stop {
        let stop = Stop::new().with_flag(Arc::clone(&self.cancelled));
        match Instant::now().checked_add(self.each) {
            Some(own) if own < self.all_by => stop.with_timeout(self.each),
            _ => stop.with_deadline(self.all_by),
        }
    }
}

impl PlanStop {
    /// The [`Interrupt`] of the request's map (a room's fit): its flag and its deadline.
    pub(super) fn for_map(&self) -> Interrupt {
        Interrupt::default()
            .with_flag(Arc::clone(&self.cancelled))
            .with_deadline(self.all_by)
    }
}

/// Sets its flag when dropped: the handler's future is dropped when the client goes away.
pub(super) struct CancelOnDrop(pub(super) Arc<AtomicBool>);

impl Drop for CancelOnDrop {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

/// Run one planner (MBPP with its bug tracks).
fn run_planner(
    kind: PlannerKind,
    grid: &OccupancyGrid,
    start: CellXy,
    goal: CellXy,
    unknown_passable: bool,
    track_budget: &mut usize,
    stop: Stop,
) -> Result<ResultOut, ApiError> {
    let started = Instant::now();
    let mut out = ResultOut {
        smooth: None,
        planner: kind.name(),
        found: false,
        skipped: false,
        note: None,
        length_m: None,
        waypoints: Vec::new(),
        alternatives: Vec::new(),
        bugs: Vec::new(),
        stats: StatsOut::default(),
        time_ms: 0.0,
    };
    let is_mbpp = matches!(kind, PlannerKind::Mbpp | PlannerKind::MbppCloser);
    let planned = kind
        .planner(unknown_passable)
        .with_tracks(is_mbpp)
        .with_mbpp_budget(PAGE_MAX_BUG_STEPS, PAGE_MAX_ALTERNATIVES)
        .with_budget(Budget {
            max_expansions: PAGE_MAX_EXPANSIONS,
            max_sight_cells: PAGE_MAX_SIGHT_CELLS,
            stop,
        })
        .plan(grid, start, goal)
        .map_err(|e| ApiError::bad_request(format!("{}: {e}", kind.name())))?;
    out.time_ms = elapsed_ms(started);
    if let Some(best) = &planned.best {
        let p = path_out(grid, best);
        out.found = true;
        out.length_m = Some(p.length_m);
        out.waypoints = p.waypoints;
        out.stats = StatsOut {
            expanded: best.stats.expanded,
            generated: best.stats.generated,
            los_checks: best.stats.los_checks,
            los_cells: best.stats.los_cells,
        };
    }
    out.alternatives = planned
        .alternatives
        .iter()
        .map(|p| path_out(grid, p))
        .collect();
    let mut cut = false;
    out.bugs = planned
        .bugs
        .iter()
        .map(|b: &BugTrack| {
            let keep = b.cells.len().min(*track_budget);
            cut |= keep < b.cells.len();
            *track_budget -= keep;
            BugOut {
                parent: b.parent,
                cells: world(grid, &b.cells[..keep]),
                hits: world(grid, &b.hits),
                leaves: world(grid, &b.leaves),
                steps: b.steps,
                fate: fate_name(b.fate),
            }
        })
        .collect();
    if cut {
        out.note = Some(format!(
            "bug tracks cut after {MAX_TRACK_POINTS} points in all"
        ));
    }
    Ok(out)
}

/// The smooth planner's result row, within the page's work budget and the planner's time.
fn smooth_result(
    map: &PlanningMap,
    units: &str,
    ask: &SmoothAsk,
    start: CellXy,
    goal: CellXy,
    unknown_passable: bool,
    stop: &PlanStop,
) -> Result<ResultOut, ApiError> {
    let budget = Budget {
        max_expansions: PAGE_MAX_EXPANSIONS,
        max_sight_cells: PAGE_MAX_SIGHT_CELLS,
        stop: stop.for_planner(),
    };
    let opts = smooth_plan_options(map, units, ask, unknown_passable, budget)?;
    let run = run_smooth(map, units, start, goal, &opts)?;
    Ok(ResultOut {
        smooth: Some(run.json),
        planner: "smooth",
        found: run.length.is_some(),
        skipped: false,
        note: run.note,
        length_m: run.length,
        waypoints: run.points,
        alternatives: Vec::new(),
        bugs: Vec::new(),
        stats: StatsOut {
            expanded: run.expanded,
            generated: run.generated,
            los_checks: 0,
            los_cells: 0,
        },
        time_ms: run.time_ms,
    })
}

/// A plan request checked up to the planning: its planners, the scene's map and grid, and the
/// start and goal cells (what `/api/plan` and the fuzz target `web_body` share).
pub(crate) struct CheckedPlan {
    /// The planners asked for, in order.
    pub kinds: Vec<PlannerChoice>,
    /// What the smooth planner is asked (when it is among `kinds`).
    pub smooth: Option<SmoothAsk>,
    /// Whether unknown cells may be crossed.
    pub unknown_passable: bool,
    /// The scene's warnings, then the map's.
    pub warnings: Vec<String>,
    /// The map's units name (`m` or `camera heights`).
    pub units: &'static str,
    /// The robot's radius the grid is inflated by, map units.
    pub robot_radius: f64,
    /// The occupancy grid.
    pub grid: OccupancyGrid,
    /// The start and goal cells.
    pub start: CellXy,
    /// See `start`.
    pub goal: CellXy,
}

/// Parse and check a `/api/plan` body, in the endpoint's order: the request's fields, the map
/// options (with at most `max_grid_cells` grid cells), the planners, the scene, its map and
/// grid (a room's fit stopping when `interrupt` fires), then the start and goal.
///
/// # Errors
/// The 400 answer `/api/plan` gives before planning.
pub(crate) fn checked_plan_request(
    body: &[u8],
    max_grid_cells: f64,
    interrupt: &Interrupt,
) -> Result<CheckedPlan, ApiError> {
    let text = params::json_text(body, "a plan request")?;
    let request = PlanRequest::from_text(&text)?;
    let mut options = map_options(
        request.method.as_deref(),
        request.resolution,
        request.robot_radius,
        request.hidden_free,
        request.click_sigma,
    )?;
    options.max_grid_cells = Some(max_grid_cells.min(MAX_GRID_CELLS));
    let kinds = planners(request.planners.as_deref())?;
    let smooth = smooth_ask(
        kinds.contains(&PlannerChoice::Smooth),
        request.turning_radius,
        [request.start_heading_deg, request.goal_heading_deg],
        request.reverse,
    )?;
    let unknown_passable = request.unknown_passable.unwrap_or(false);
    let parsed = scene_from_value(&request.scene)?;
    let vpmap_pipeline::MapAndGrid { map, grid } =
        vpmap_pipeline::map_and_grid_until(&parsed.scene, &options, interrupt)
            .map_err(pipeline_error)?;
    let units = units_name(map.units);
    let coordinates = Coordinates::Map {
        units: if units == "m" { "m" } else { "camera heights" },
    };
    let rules = EndpointRules {
        unknown_passable,
        robot_radius: options.robot_radius_m,
        names: OptionNames::WebApi,
    };
    let [start, goal] = [("start", request.start), ("goal", request.goal)].map(|(name, point)| {
        endpoint_cell(&grid, coordinates, &Endpoint { name, point }, &rules).map_err(pipeline_error)
    });
    let (start, goal) = (start?, goal?);
    let mut warnings = parsed.warnings;
    warnings.extend(map.warnings.iter().cloned());
    if let Some(ask) = &smooth {
        radius_fits(ask, &grid, units)?;
    }
    Ok(CheckedPlan {
        kinds,
        smooth,
        unknown_passable,
        warnings,
        units,
        robot_radius: options.robot_radius_m,
        grid,
        start,
        goal,
    })
}

fn plan_answer(body: &[u8], stop: &PlanStop) -> Result<Bytes, ApiError> {
    let started = Instant::now();
    let CheckedPlan {
        kinds,
        smooth,
        unknown_passable,
        warnings,
        units,
        robot_radius,
        grid,
        start,
        goal,
    } = checked_plan_request(body, MAX_GRID_CELLS, &stop.for_map())?;
    // The smooth planner reads the grid as a map in metres (or camera heights), y up.
    let map = PlanningMap {
        grid,
        in_cells: false,
        robot_radius,
    };
    let grid = &map.grid;
    let mut budget = MAX_TRACK_POINTS;
    let results = kinds
        .into_iter()
        .map(|choice| match (choice, &smooth) {
            (PlannerChoice::Grid(kind), _) => run_planner(
                kind,
                grid,
                start,
                goal,
                unknown_passable,
                &mut budget,
                stop.for_planner(),
            ),
            (PlannerChoice::Smooth, Some(ask)) => {
                smooth_result(&map, units, ask, start, goal, unknown_passable, stop)
            }
            (PlannerChoice::Smooth, None) => Err(ApiError::bad_request(
                "the smooth planner needs field `turning_radius`",
            )),
        })
        .collect::<Result<Vec<_>, _>>()?;
    to_json(&PlanResponse {
        results,
        grid: GridOut {
            width: grid.width(),
            height: grid.height(),
            resolution: grid.resolution_m(),
            origin: grid.origin_m(),
        },
        units,
        start_cell: [start.x, start.y],
        goal_cell: [goal.x, goal.y],
        warnings,
        time_ms: elapsed_ms(started),
    })
}

/// The JSON body of a request without query parameters (`/api/plan`, `/api/navigate`):
/// read within the server's body limits, the query refused when not empty, the content type
/// checked.
pub(super) async fn json_body(
    state: &AppState,
    query: Option<&str>,
    headers: &HeaderMap,
    body: Body,
) -> Result<Bytes, ApiError> {
    let body = params::read_body(
        headers,
        body,
        MAX_JSON_BODY_BYTES,
        state.0.limits.body_read_timeout,
    )
    .await?;
    Query::parse(query, &[])?;
    params::expect_json(headers)?;
    Ok(body)
}

/// `POST /api/plan` with a plan request as the body.
pub async fn plan(
    State(state): State<AppState>,
    RawQuery(query): RawQuery,
    headers: HeaderMap,
    body: Body,
) -> Response {
    // Dropped with this future when the client goes away: the planners then stop.
    let cancelled = CancelOnDrop(Arc::new(AtomicBool::new(false)));
    let result = async {
        let limits = &state.0.limits;
        let body = json_body(&state, query.as_deref(), &headers, body).await?;
        let slot = state.0.plan_slots.take("/api/plan").await?;
        let stop = PlanStop {
            cancelled: Arc::clone(&cancelled.0),
            all_by: Instant::now() + limits.plan_timeout,
            each: limits.planner_timeout,
        };
        run_blocking(&state, "/api/plan", move || {
            let _slot = slot;
            plan_answer(&body, &stop)
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
    fn optimal_runs_on_fine_grids_and_is_never_longer_than_a_star_ps() {
        // At 0.005 m the office has 3,152 corner cells: the old visibility graph was skipped
        // there (2.9 s in a release build); the exact interval search runs (docs/planning.md).
        // Generous time limits: this checks the answer, not the speed, in a debug build.
        let body = format!(
            r#"{{"scene": {}, "resolution": 0.005, "start": [1.1, 1.7], "goal": [0.2, 5.0], "planners": ["optimal", "astar-ps"]}}"#,
            crate::example::OFFICE_SCENE
        );
        let stop = PlanStop {
            cancelled: Arc::new(AtomicBool::new(false)),
            all_by: Instant::now() + std::time::Duration::from_secs(600),
            each: std::time::Duration::from_secs(300),
        };
        let answer = plan_answer(body.as_bytes(), &stop).unwrap();
        let v: serde_json::Value = serde_json::from_slice(&answer).unwrap();
        let length = |i: usize| {
            let r = &v["results"][i];
            assert_eq!(r["found"], true, "{r}");
            assert_eq!(r["skipped"], false);
            r["length_m"].as_f64().unwrap()
        };
        assert_eq!(v["results"][0]["planner"], "optimal");
        assert!(length(0) <= length(1) + 1e-9, "{v}");
    }

    #[test]
    fn planner_names_are_checked_and_deduplicated() {
        let names = |v: &[&str]| v.iter().map(|s| (*s).to_owned()).collect::<Vec<_>>();
        assert_eq!(
            planners(Some(&names(&["mbpp", "optimal", "mbpp"]))).ok(),
            Some(vec![
                PlannerChoice::Grid(PlannerKind::Mbpp),
                PlannerChoice::Grid(PlannerKind::Optimal)
            ])
        );
        assert_eq!(
            planners(Some(&names(&["smooth", "mbpp", "smooth"]))).ok(),
            Some(vec![
                PlannerChoice::Smooth,
                PlannerChoice::Grid(PlannerKind::Mbpp)
            ])
        );
        assert!(planners(Some(&names(&["dijkstra"]))).is_err());
        assert!(planners(Some(&[])).is_err());
        assert_eq!(
            planners(None).ok(),
            Some(DEFAULT_PLANNERS.map(PlannerChoice::Grid).to_vec())
        );
    }

    #[test]
    fn each_planner_gets_its_time_or_what_is_left_of_the_request() {
        let now = Instant::now();
        let secs = std::time::Duration::from_secs;
        let stop = |all: u64, each: u64| {
            PlanStop {
                cancelled: Arc::new(AtomicBool::new(false)),
                all_by: now + secs(all),
                each: secs(each),
            }
            .for_planner()
        };
        assert!((stop(6, 3).allowed_s() - 3.0).abs() < 1e-9);
        let left = stop(2, 3).allowed_s();
        assert!(left <= 2.0 && left > 1.5, "{left}");
        assert!(stop(0, 3).reason().is_some());
        let cancelled = PlanStop {
            cancelled: Arc::new(AtomicBool::new(false)),
            all_by: now + secs(60),
            each: secs(60),
        };
        let planner = cancelled.for_planner();
        assert!(planner.reason().is_none());
        drop(CancelOnDrop(Arc::clone(&cancelled.cancelled)));
        assert_eq!(planner.reason(), Some(vpmap_plan::StopReason::Cancelled));
    }
}
