//! The smooth planner on `/api/plan`: `"smooth"` among the `planners`, with a
//! `turning_radius` (map units) and optional `start_heading_deg` / `goal_heading_deg`
//! (degrees, `atan2(dy, dx)` in the map's coordinates, `y` up) and `reverse` (driving
//! backwards allowed, cusps reported). Its result row carries the
//! answer of `vpmap plan --planner smooth --json` ([`vpmap_pipeline::smooth::smooth_json`]).

use std::time::Instant;

use vpmap_pipeline::{PlanningMap, smooth_json, smooth_options};
use vpmap_plan::Budget;
use vpmap_plan::grid::{CellXy, OccupancyGrid};
use vpmap_plan::smooth::{Pose, SmoothOptions, SmoothOutcome, SmoothPlanner};

use crate::error::ApiError;

/// What a plan request asks of the smooth planner, checked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SmoothAsk {
    /// The smallest turning radius, map units.
    pub turning_radius: f64,
    /// The start and goal headings, degrees in the map's coordinates (`None`: free).
    pub headings_deg: [Option<f64>; 2],
    /// Whether the robot may drive in reverse (cusps allowed).
    pub reverse: bool,
}

fn shown(v: f64) -> String {
    vpmap_pipeline::num(v)
}

/// Check the smooth fields of a plan request: `turning_radius` is needed (and, like the
/// headings and `reverse`, only allowed) when `"smooth"` is among the planners; headings must
/// be finite. The radius is checked
/// against the map later ([`smooth_plan_options`]).
///
/// # Errors
/// A 400 naming the field and its value.
pub(crate) fn smooth_ask(
    wanted: bool,
    turning_radius: Option<f64>,
    headings_deg: [Option<f64>; 2],
    reverse: Option<bool>,
) -> Result<Option<SmoothAsk>, ApiError> {
    if !wanted {
        let given = [
            ("turning_radius", turning_radius.is_some()),
            ("start_heading_deg", headings_deg[0].is_some()),
            ("goal_heading_deg", headings_deg[1].is_some()),
            ("reverse", reverse.is_some()),
        ];
        if let Some((name, _)) = given.iter().find(|(_, v)| *v) {
            return Err(ApiError::bad_request(format!(
                "field `{name}` is only used by the smooth planner; add \"smooth\" to `planners`"
            )));
        }
        return Ok(None);
    }
    let Some(radius) = turning_radius else {
        return Err(ApiError::bad_request(
            "the smooth planner needs field `turning_radius`: the smallest turning radius in map units (metres on a metric map)",
        ));
    };
    if !(radius.is_finite() && radius > 0.0) {
        return Err(ApiError::bad_request(format!(
            "field `turning_radius` must be a positive number of map units, got {}",
            shown(radius)
        )));
    }
    for (name, h) in [
        ("start_heading_deg", headings_deg[0]),
        ("goal_heading_deg", headings_deg[1]),
    ] {
        if let Some(h) = h
            && !h.is_finite()
        {
            return Err(ApiError::bad_request(format!(
                "field `{name}` must be a finite number of degrees, got {}",
                shown(h)
            )));
        }
    }
    Ok(Some(SmoothAsk {
        turning_radius: radius,
        headings_deg,
        reverse: reverse.unwrap_or(false),
    }))
}

/// Check that the turning radius of `ask` fits on `grid` (a metric or camera-height map
/// whose units are `units`, the answer's `m` or `camera_heights`): at most the grid's larger
/// side.
///
/// # Errors
/// A 400 naming the radius and the map's size in the map's units.
pub(crate) fn radius_fits(
    ask: &SmoothAsk,
    grid: &OccupancyGrid,
    units: &str,
) -> Result<(), ApiError> {
    let units = if units == "m" { "m" } else { "camera heights" };
    let side = grid.width().max(grid.height()) as f64 * grid.resolution_m();
    if ask.turning_radius > side {
        return Err(ApiError::bad_request(format!(
            "field `turning_radius` is {} {units}, larger than the map ({} {units} across at most): no turn of that radius fits",
            shown(ask.turning_radius),
            shown(side)
        )));
    }
    Ok(())
}

/// The planner's options for `ask` on `map` (whose units are `units`), with the page's
/// work `budget`.
///
/// # Errors
/// A 400 when the radius is larger than the map, naming it in the map's units.
pub(crate) fn smooth_plan_options(
    map: &PlanningMap,
    units: &str,
    ask: &SmoothAsk,
    unknown_passable: bool,
    budget: Budget,
) -> Result<SmoothOptions, ApiError> {
    radius_fits(ask, &map.grid, units)?;
    let mut opts = smooth_options(
        map,
        ask.turning_radius,
        "field `turning_radius`",
        ask.headings_deg,
        ask.reverse,
    )
    .map_err(|e| ApiError::bad_request(e.to_string()))?;
    opts.unknown_passable = unknown_passable;
    opts.budget = budget;
    Ok(opts)
}

/// A smooth plan's result: the CLI's JSON, whether a path was found, its length, its poses'
/// positions, the reason when there is none, the work counters and the time taken.
pub(crate) struct SmoothRun {
    /// `smooth_json`'s answer.
    pub json: serde_json::Value,
    /// Its length, map units, when found.
    pub length: Option<f64>,
    /// The poses' positions, map units.
    pub points: Vec<[f64; 2]>,
    /// "no drivable path: ..." when none was found.
    pub note: Option<String>,
    /// Nodes expanded: the any-angle search's and the Hybrid-A*'s.
    pub expanded: usize,
    /// States generated by the Hybrid-A*.
    pub generated: usize,
    /// Milliseconds.
    pub time_ms: f64,
}

/// Plan a smooth path on `map` (whose units are `units`: the answer's `units` says so, where
/// the pipeline's JSON would say `m` for any map not in cells) from `start` to `goal` with
/// `opts`.
///
/// # Errors
/// A 400 naming the planner when it refuses the query or its budget runs out.
pub(crate) fn run_smooth(
    map: &PlanningMap,
    units: &str,
    start: CellXy,
    goal: CellXy,
    opts: &SmoothOptions,
) -> Result<SmoothRun, ApiError> {
    let began = Instant::now();
    let outcome = SmoothPlanner::new(&map.grid, opts.unknown_passable)
        .plan(start, goal, opts)
        .map_err(|e| ApiError::bad_request(format!("smooth: {e}")))?;
    let seconds = began.elapsed().as_secs_f64();
    let asked = [
        (start, opts.start_heading_rad),
        (goal, opts.goal_heading_rad),
    ]
    .map(|(c, h)| Pose::new(c.x as f64, c.y as f64, h.unwrap_or(0.0)));
    let mut json = smooth_json(map, &outcome, asked, seconds);
    if let Some(fields) = json.as_object_mut() {
        fields.insert("units".into(), units.into());
    }
    let run = match &outcome {
        SmoothOutcome::Path(p) => SmoothRun {
            length: Some(p.length_cells * map.scale()),
            points: p
                .poses
                .iter()
                .map(|&q| {
                    let m = vpmap_pipeline::smooth::pose_in_map(map, q);
                    [m[0], m[1]]
                })
                .collect(),
            note: None,
            expanded: p.stats.any_angle.expanded + p.stats.hybrid.expanded,
            generated: p.stats.hybrid.generated,
            json,
            time_ms: seconds * 1e3,
        },
        SmoothOutcome::NoPath(n) => SmoothRun {
            length: None,
            points: Vec::new(),
            note: Some(format!(
                "no drivable path: {}",
                json.get("reason")
                    .and_then(serde_json::Value::as_str)
                    .unwrap_or(&n.reason)
            )),
            expanded: n.stats.any_angle.expanded + n.stats.hybrid.expanded,
            generated: n.stats.hybrid.generated,
            json,
            time_ms: seconds * 1e3,
        },
    };
    Ok(run)
}
