//! `vpmap.navigate`: a robot drives a believed map, senses the true one and re-plans, as
//! `vpmap navigate` runs it; the answer is `navigate.json` as a dict. With
//! `planner="smooth"` the robot drives curvature-bounded curves (`vpmap navigate --planner
//! smooth`), and the dict's `poses` are an (N, 3) array.

use numpy::PyArray2;
use numpy::ndarray::Array2;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use vpmap_pipeline::{
    DriveMap, DriveReport, Endpoint, EndpointRules, OptionNames, PlanningMap, SmoothDriveReport,
    drive_maps, endpoint_cell, navigate_json, navigate_smooth_json, navigate_smooth_svg,
    smooth_options,
};
use vpmap_plan::budget::{Budget, Stop};
use vpmap_plan::grid::{CellXy, OccupancyGrid};
use vpmap_plan::navigate::{
    NavigateOptions, OnlinePlanner, SmoothNavigateOptions, navigate as drive, navigate_smooth,
    truth_optimum,
};

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
/// ``vpmap.plan``. ``planner``: ``"astar"``, ``"astar-ps"``, ``"dstar-lite"``, ``"mbpp"``,
/// ``"astar-ties"``, ``"dstar-lite-ties"`` or ``"smooth"``; ``sensor_range`` in the map's
/// units (default 10 cells); ``unknown_blocked`` believes unknown cells blocked. Returns
/// ``navigate.json`` as a dict (outcome, moves, length, waypoints, re-plans, the true
/// optimum); with ``svg=True`` the dict also holds ``"svg"``, the picture ``vpmap navigate``
/// writes as ``navigate.svg`` (SVG text: the true map, what the robot believed, its path and
/// re-plans).
///
/// ``planner="smooth"`` drives curvature-bounded curves re-planned from the robot's pose
/// and heading, as ``vpmap navigate --planner smooth``: ``turning_radius`` (the map's units,
/// required), ``start_heading`` and ``goal_heading`` (degrees, ``atan2(dy, dx)`` in the map's
/// coordinates; free when left out) and ``reverse`` (cusps allowed). Its dict is that
/// command's ``navigate.json`` (``segments``, ``cusps``, ``max_curvature``,
/// ``min_clearance``, ``replans``, ``events``, ``reason``, ...) except ``"poses"``: every pose
/// the robot stood at as an (N, 3) float64 array of ``(x, y, heading_deg)``, the start first.
/// Raises ``VpmapError`` as ``vpmap navigate``.
#[pyfunction]
#[pyo3(signature = (believed, truth, start, goal, *, planner="dstar-lite", sensor_range=None, unknown_blocked=false, robot_radius=None, resolution=0.05, max_moves=10_000_000, max_replans=1_000_000, max_expansions=None, timeout=None, svg=false, turning_radius=None, start_heading=None, goal_heading=None, reverse=false))]
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
    turning_radius: Option<f64>,
    start_heading: Option<f64>,
    goal_heading: Option<f64>,
    reverse: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let smooth = planner == "smooth";
    let planner: Option<OnlinePlanner> = if smooth {
        if turning_radius.is_none() {
            return Err(error(
                "planner \"smooth\" needs turning_radius (the map's units: metres, or cells)",
            ));
        }
        None
    } else {
        if turning_radius.is_some() || start_heading.is_some() || goal_heading.is_some() || reverse
        {
            return Err(error(format!(
                "turning_radius, start_heading, goal_heading and reverse are for planner=\"smooth\", not \"{planner}\""
            )));
        }
        Some(planner.parse().map_err(|e| error(format!("{e}, smooth")))?)
    };
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
    let budget = Budget {
        max_expansions: max_expansions.unwrap_or(vpmap_plan::budget::DEFAULT_MAX_EXPANSIONS),
        stop,
        ..Budget::default()
    };
    let limits = Limits {
        unknown_blocked,
        max_moves,
        max_replans,
        budget,
        range_cells,
        svg,
    };
    let Some(planner) = planner else {
        let smooth = SmoothArgs {
            turning_radius: turning_radius.unwrap_or(f64::NAN),
            headings_deg: [start_heading, goal_heading],
            reverse,
        };
        return drive_smooth(py, &believed, &truth, [from, to], &smooth, limits);
    };
    let [start, goal] = ends_on_truth(&believed, &truth, [from, to])?;
    let opts = NavigateOptions {
        planner,
        sensor_range_cells: range_cells,
        unknown_passable: !unknown_blocked,
        max_moves,
        max_replans,
        budget: limits.budget,
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

/// What a drive is bounded by and how it is reported, from the keywords.
struct Limits {
    unknown_blocked: bool,
    max_moves: usize,
    max_replans: usize,
    budget: Budget,
    range_cells: f64,
    svg: bool,
}

/// The smooth planner's keywords.
struct SmoothArgs {
    /// The map's units.
    turning_radius: f64,
    /// Degrees in the map's coordinates; `None`: free.
    headings_deg: [Option<f64>; 2],
    reverse: bool,
}

/// The start and the goal (the map's coordinates) as cells of the true map, checked as
/// `vpmap navigate` checks `--from` and `--to`.
fn ends_on_truth(
    believed: &PlanningMap,
    truth: &OccupancyGrid,
    ends: [[f64; 2]; 2],
) -> PyResult<[CellXy; 2]> {
    let coordinates = believed.coordinates();
    let rules = EndpointRules {
        unknown_passable: false,
        robot_radius: believed.robot_radius,
        names: OptionNames::WebApi,
    };
    let on_truth = |name: &str, point| {
        endpoint_cell(truth, coordinates, &Endpoint { name, point }, &rules)
            .map_err(|e| error(format!("{name} on the true map: {e}")))
    };
    Ok([on_truth("start", ends[0])?, on_truth("goal", ends[1])?])
}

/// `vpmap.navigate(..., planner="smooth")`: the checks, the drive and the report of
/// `vpmap navigate --planner smooth`, the poses as an (N, 3) array.
fn drive_smooth<'py>(
    py: Python<'py>,
    believed: &PlanningMap,
    truth: &OccupancyGrid,
    ends: [[f64; 2]; 2],
    args: &SmoothArgs,
    limits: Limits,
) -> PyResult<Bound<'py, PyAny>> {
    let mut smooth = smooth_options(
        believed,
        args.turning_radius,
        "turning_radius",
        args.headings_deg,
        args.reverse,
    )
    .map_err(error)?;
    smooth.budget = limits.budget;
    let [start, goal] = ends_on_truth(believed, truth, ends)?;
    let opts = SmoothNavigateOptions {
        smooth,
        sensor_range_cells: limits.range_cells,
        unknown_passable: !limits.unknown_blocked,
        max_moves: limits.max_moves,
        max_replans: limits.max_replans,
        ..SmoothNavigateOptions::default()
    };
    let (json, poses) = py
        .detach(|| {
            let run = navigate_smooth(&believed.grid, truth, start, goal, &opts)?;
            let optimum = truth_optimum(truth, start, goal, &opts.smooth.budget)?;
            let report = SmoothDriveReport {
                run: &run,
                optimum: &optimum,
                opts: &opts.smooth,
                unknown_passable: opts.unknown_passable,
                sensor_range_cells: limits.range_cells,
            };
            let mut json = navigate_smooth_json(believed, &report);
            if limits.svg
                && let Some(fields) = json.as_object_mut()
            {
                let picture = navigate_smooth_svg(
                    believed,
                    truth,
                    &report,
                    [start, goal],
                    args.turning_radius,
                );
                fields.insert("svg".to_owned(), serde_json::Value::String(picture));
            }
            let poses: Vec<f64> = run
                .poses
                .iter()
                .flat_map(|&q| vpmap_pipeline::smooth::pose_in_map(believed, q))
                .collect();
            Ok::<_, vpmap_plan::PlanError>((json, poses))
        })
        .map_err(|e| crate::plan::plan_error(&e))?;
    let dict = json_to_py(py, &json)?.cast_into::<PyDict>()?;
    let rows = poses.len() / 3;
    let poses = Array2::from_shape_vec((rows, 3), poses).map_err(error)?;
    dict.set_item("poses", PyArray2::from_owned_array(py, poses))?;
    Ok(dict.into_any())
}
