//! `vpmap.navigate`: a robot drives a believed map, senses the true one and re-plans, as
//! `vpmap navigate` runs it; the answer is `navigate.json` as a dict.

use pyo3::prelude::*;
use vpmap_pipeline::{
    DriveMap, DriveReport, Endpoint, EndpointRules, OptionNames, drive_maps, endpoint_cell,
    navigate_json,
};
use vpmap_plan::budget::{Budget, Stop};
use vpmap_plan::grid::CellXy;
use vpmap_plan::navigate::{NavigateOptions, OnlinePlanner, navigate as drive, truth_optimum};

use crate::convert::{as_path, error, json_to_py, point, shown};
use crate::grid::Grid;
use crate::map::pipeline_error;

/// A map given as a `Grid` or a file (read as `vpmap navigate` reads it).
fn given(what: &str, obj: &Bound<'_, PyAny>) -> PyResult<DriveMap> {
    if let Ok(g) = obj.cast::<Grid>() {
        return Ok(DriveMap::Given(g.get().map.clone()));
    }
    as_path(obj).map(DriveMap::File).ok_or_else(|| {
        error(format!(
            "{what} {} is neither a Grid nor a file path",
            shown(obj)
        ))
    })
}

/// Drive a robot across a believed map while it senses the true one, as ``vpmap navigate``
/// does (docs/navigation.md).
///
/// ``believed`` is a ``Grid`` or a map file (``map.json``, ``.yaml``, ``.map``), or ``None``
/// to start knowing nothing (``--unknown``); ``truth`` a ``Grid``, a map file of the same
/// size, or a synthetic scene's truth (``*.truth.json``). ``start``/``goal`` as in
/// ``vpmap.plan``. ``planner``: ``"astar"``, ``"astar-ps"``, ``"dstar-lite"`` or ``"mbpp"``;
/// ``sensor_range`` in the map's units (default 10 cells); ``unknown_blocked`` believes
/// unknown cells blocked. Returns ``navigate.json`` as a dict (outcome, moves, length,
/// waypoints, re-plans, the true optimum); with ``svg=True`` the dict also holds ``"svg"``,
/// the picture ``vpmap navigate`` writes as ``navigate.svg`` (SVG text: the true map, what
/// the robot believed, its path and re-plans). Raises ``VpmapError`` as ``vpmap navigate``.
#[pyfunction]
#[pyo3(signature = (believed, truth, start, goal, *, planner="dstar-lite", sensor_range=None, unknown_blocked=false, robot_radius=None, resolution=0.05, max_moves=10_000_000, max_replans=1_000_000, max_expansions=None, timeout=None, svg=false))]
#[allow(clippy::too_many_arguments)]
pub fn navigate<'py>(
    py: Python<'py>,
    believed: Option<&Bound<'py, PyAny>>,
    truth: &Bound<'py, PyAny>,
    start: &Bound<'py, PyAny>,
    goal: &Bound<'py, PyAny>,
    planner: &str,
    sensor_range: Option<f64>,
    unknown_blocked: bool,
    robot_radius: Option<f64>,
    resolution: f64,
    max_moves: usize,
    max_replans: usize,
    max_expansions: Option<usize>,
    timeout: Option<f64>,
    svg: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let planner: OnlinePlanner = planner.parse().map_err(|e| error(&e))?;
    let from = point("start", start)?;
    let to = point("goal", goal)?;
    let believed = believed.map(|b| given("believed", b)).transpose()?;
    let truth = given("truth", truth)?;
    let stop = match timeout {
        None => Stop::new(),
        Some(t) if t.is_finite() && t > 0.0 && t <= 86_400.0 => {
            Stop::new().with_timeout(std::time::Duration::from_secs_f64(t))
        }
        Some(t) => {
            return Err(error(format!(
                "timeout {} is not a time limit; give a number of seconds above 0 and at most 86400",
                vpmap_pipeline::num(t)
            )));
        }
    };
    let (believed, truth) = py
        .detach(|| drive_maps(believed, truth, robot_radius, resolution))
        .map_err(pipeline_error)?;
    let scale = believed.scale();
    let unit = believed.unit();
    let range_cells =
        vpmap_pipeline::drive::sensor_range_cells(sensor_range, scale, unit, "sensor_range")
            .map_err(error)?;
    let coordinates = believed.coordinates();
    let rules = EndpointRules {
        unknown_passable: false,
        robot_radius: believed.robot_radius,
        names: OptionNames::WebApi,
    };
    let on_truth = |name: &str, point| {
        endpoint_cell(&truth, coordinates, &Endpoint { name, point }, &rules)
            .map_err(|e| error(format!("{name} on the true map: {e}")))
    };
    let start = on_truth("start", from)?;
    let goal = on_truth("goal", to)?;
    let opts = NavigateOptions {
        planner,
        sensor_range_cells: range_cells,
        unknown_passable: !unknown_blocked,
        max_moves,
        max_replans,
        budget: Budget {
            max_expansions: max_expansions.unwrap_or(vpmap_plan::budget::DEFAULT_MAX_EXPANSIONS),
            stop,
            ..Budget::default()
        },
    };
    let json = py
        .detach(|| {
            let run = drive(&believed.grid, &truth, start, goal, &opts)?;
            let optimum = truth_optimum(&truth, start, goal, &opts.budget)?;
            let coords = |c: CellXy| -> [f64; 2] {
                if believed.in_cells {
                    [c.x as f64, c.y as f64]
                } else {
                    truth.world_from_cell(c.x, c.y)
                }
            };
            let report = DriveReport {
                run: &run,
                optimum: &optimum,
                planner,
                unknown_passable: !unknown_blocked,
                sensor_range_cells: range_cells,
                scale,
                unit,
            };
            let mut json = navigate_json(&report, &coords);
            if svg && let Some(fields) = json.as_object_mut() {
                let picture = vpmap_render::navigation_svg(
                    &truth,
                    &believed.grid,
                    &run,
                    start,
                    goal,
                    planner,
                );
                fields.insert("svg".to_owned(), serde_json::Value::String(picture));
            }
            Ok::<_, vpmap_plan::PlanError>(json)
        })
        .map_err(|e| crate::plan::plan_error(&e))?;
    json_to_py(py, &json)
}
