//! Smooth paths in a map's own coordinates: turning radius and headings in, segments and
//! poses out ([`smooth_options`], [`smooth_json`]), and the report of a drive with the smooth
//! planner ([`navigate_smooth_json`] and its picture [`navigate_smooth_svg`],
//! `vpmap navigate --planner smooth` and `vpmap.navigate(..., planner="smooth")`).
//!
//! A Moving AI map's coordinates are cells `(column, row)`, `y` down the rows, so a heading
//! `atan2(dy, dx)` there is the planner's heading. A ROS map's or a `map.json`'s
//! coordinates are metres with `y` up: positions go through the grid's origin and
//! resolution, headings and curvatures change sign. A `turn` of `left` always means the
//! heading (in the map's coordinates) increases.

use vpmap_plan::grid::{CellXy, OccupancyGrid};
use vpmap_plan::navigate::{Outcome, SmoothNavigation, TruthOptimum};
use vpmap_plan::smooth::{
    Gear, NoDrivablePath, NoPathKind, Pose, Segment, SmoothOptions, SmoothOutcome, SmoothPlan,
    SmoothStats,
};
use vpmap_render::{GridCoordinates, smooth_svg};

use crate::error::PipelineError;
use crate::planning::PlanningMap;
use crate::text::num;

/// A pose from the planner's cell-centre coordinates to the map's: `[x, y, heading_deg]`.
#[must_use]
pub fn pose_in_map(map: &PlanningMap, p: Pose) -> [f64; 3] {
    if map.in_cells {
        return [p.x, p.y, p.heading_rad.to_degrees()];
    }
    let g = &map.grid;
    let r = g.resolution_m();
    let o = g.origin_m();
    [
        o[0] + (p.x + 0.5) * r,
        o[1] + (g.height() as f64 - p.y - 0.5) * r,
        -p.heading_rad.to_degrees(),
    ]
}

/// A heading given in the map's coordinates, degrees, as the planner's, radians.
#[must_use]
pub fn heading_in_grid(map: &PlanningMap, heading_deg: f64) -> f64 {
    if map.in_cells {
        heading_deg.to_radians()
    } else {
        -heading_deg.to_radians()
    }
}

/// The planner's options for a turning radius in the map's units (metres, or cells for a
/// Moving AI map) and headings in degrees in the map's coordinates (`None`: free).
///
/// # Errors
/// When the radius is not finite and positive, or larger than the map, or a heading is
/// not finite: the message names the flag (`radius_name`) and the value.
pub fn smooth_options(
    map: &PlanningMap,
    radius: f64,
    radius_name: &str,
    headings_deg: [Option<f64>; 2],
    reverse: bool,
) -> Result<SmoothOptions, PipelineError> {
    let unit = map.unit();
    if !(radius.is_finite() && radius > 0.0) {
        return Err(PipelineError::Endpoint(format!(
            "{radius_name} must be a positive number of {unit}, got {}",
            num(radius)
        )));
    }
    let cells = radius / map.scale();
    let side = map.grid.width().max(map.grid.height()) as f64;
    if cells > side {
        return Err(PipelineError::Endpoint(format!(
            "{radius_name} {} {unit} is larger than the map ({} {unit} across at most): no turn of that radius fits",
            num(radius),
            num(side * map.scale())
        )));
    }
    for h in headings_deg.into_iter().flatten() {
        if !h.is_finite() {
            return Err(PipelineError::Endpoint(format!(
                "a heading must be a finite number of degrees, got {}",
                num(h)
            )));
        }
    }
    Ok(SmoothOptions {
        turning_radius_cells: cells,
        start_heading_rad: headings_deg[0].map(|h| heading_in_grid(map, h)),
        goal_heading_rad: headings_deg[1].map(|h| heading_in_grid(map, h)),
        reverse,
        ..SmoothOptions::default()
    })
}

/// One segment as JSON in the map's coordinates and units.
fn segment_json(map: &PlanningMap, s: &Segment) -> serde_json::Value {
    let scale = map.scale();
    let flip = if map.in_cells { 1.0 } else { -1.0 };
    let direction = match s.gear {
        Gear::Forward => "forward",
        Gear::Reverse => "reverse",
    };
    let mut v = serde_json::json!({
        "type": if s.curvature == 0.0 { "line" } else { "arc" },
        "start": pose_in_map(map, s.start),
        "end": pose_in_map(map, s.end()),
        "length": s.length * scale,
        "direction": direction,
    });
    if let (Some(c), Some(r), Some(obj)) = (s.centre(), s.radius(), v.as_object_mut()) {
        let centre = pose_in_map(map, Pose::new(c[0], c[1], 0.0));
        let heading_rate = flip * s.curvature * s.gear.sign();
        obj.insert("centre".into(), serde_json::json!([centre[0], centre[1]]));
        obj.insert("radius".into(), (r * scale).into());
        obj.insert(
            "turn".into(),
            if heading_rate > 0.0 { "left" } else { "right" }.into(),
        );
    }
    v
}

/// The answer of `vpmap plan --planner smooth --json`: `found`, `segments`, `poses`
/// (`[x, y, heading_deg]`), `length`, `max_curvature` (1/unit), `min_clearance`, `cusps`,
/// `curvature_sign_changes`, `method`, `any_angle_length`, `tightest_turn` (the index of
/// the segment) and `stats` (with `time_s`, the `seconds` the planner took); without a
/// path, `reason` ([`no_path_reason`] for the asked poses `start_goal`), `pose` and `room`
/// instead.
#[must_use]
pub fn smooth_json(
    map: &PlanningMap,
    outcome: &SmoothOutcome,
    start_goal: [Pose; 2],
    seconds: f64,
) -> serde_json::Value {
    let scale = map.scale();
    match outcome {
        SmoothOutcome::Path(p) => {
            let s = &p.stats;
            serde_json::json!({
                "found": true,
                "planner": "smooth",
                "units": map.unit(),
                "method": p.method,
                "length": p.length_cells * scale,
                "any_angle_length": p.any_angle_length_cells * scale,
                "max_curvature": p.max_curvature / scale,
                "min_clearance": p.min_clearance_cells * scale,
                "cusps": p.cusps,
                "curvature_sign_changes": p.curvature_sign_changes,
                "tightest_turn": p.curve.tightest_turn(),
                "segments": p.curve.segments.iter().map(|s| segment_json(map, s)).collect::<Vec<_>>(),
                "poses": p.poses.iter().map(|&q| pose_in_map(map, q)).collect::<Vec<_>>(),
                "stats": {
                    "any_angle_expanded": s.any_angle.expanded,
                    "fillet_rounds": s.fillet.rounds,
                    "fillet_words_tested": s.fillet.words_tested,
                    "hybrid_expanded": s.hybrid.expanded,
                    "hybrid_generated": s.hybrid.generated,
                    "hybrid_heuristic_cells": s.hybrid.heuristic_cells,
                    "time_s": seconds,
                },
            })
        }
        SmoothOutcome::NoPath(n) => serde_json::json!({
            "found": false,
            "planner": "smooth",
            "units": map.unit(),
            "reason": no_path_reason(map, n, start_goal),
            "pose": n.pose,
            "room": n.room_cells * scale,
            "stats": {
                "any_angle_expanded": n.stats.any_angle.expanded,
                "hybrid_expanded": n.stats.hybrid.expanded,
                "time_s": seconds,
            },
        }),
    }
}

/// "no drivable path" in the map's units and coordinates: which pose, how much room a turn
/// needs. `start_goal` are the asked poses (planner coordinates, headings as asked).
#[must_use]
pub fn no_path_reason(map: &PlanningMap, n: &NoDrivablePath, start_goal: [Pose; 2]) -> String {
    let unit = map.unit();
    let room = num(round3(n.room_cells * map.scale()));
    let radius = num(round3((n.room_cells - 1.0) / 2.0 * map.scale()));
    let pose = |p: Pose| {
        let q = pose_in_map(map, p);
        format!(
            "({}, {}) heading {} degrees",
            num(round3(q[0])),
            num(round3(q[1])),
            num(round3(q[2]))
        )
    };
    match n.kind {
        NoPathKind::NotConnected => "start and goal are not connected".to_owned(),
        NoPathKind::StartHasNoRoom => format!(
            "the start pose {} has no room to move: every turn of radius {radius} {unit} and the straight line ahead are blocked at once; turning needs a clear space about {room} {unit} wide",
            pose(start_goal[0])
        ),
        NoPathKind::GoalHasNoRoom => format!(
            "the goal pose {} cannot be entered: every turn of radius {radius} {unit} and the straight line into it are blocked; turning needs a clear space about {room} {unit} wide",
            pose(start_goal[1])
        ),
        NoPathKind::TooNarrow => format!(
            "no path with turning radius {radius} {unit} was found: start and goal are connected, but neither the corner fillets nor the Hybrid-A* (complete only up to its cells and headings) fit a turn through the passages between them (a turn needs a clear space about {room} {unit} wide)"
        ),
        _ => n.reason.clone(),
    }
}

/// `v` rounded to three decimals, for messages.
fn round3(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// The one-line answer of `vpmap plan --planner smooth`: the path's length, segments, cusps,
/// tightest radius, clearance, method and time, or "no drivable path" and why.
#[must_use]
pub fn smooth_text(
    map: &PlanningMap,
    outcome: &SmoothOutcome,
    start_goal: [Pose; 2],
    seconds: f64,
) -> String {
    let (unit, scale, ms) = (map.unit(), map.scale(), seconds * 1e3);
    match outcome {
        SmoothOutcome::Path(p) => format!(
            "smooth: path found, length {:.3} {unit} ({} segments, {} cusps, tightest radius {:.3} {unit}, min clearance {:.3} {unit}, by {}, {ms:.3} ms)",
            p.length_cells * scale,
            p.curve.segments.len(),
            p.cusps,
            if p.max_curvature > 0.0 {
                scale / p.max_curvature
            } else {
                f64::INFINITY
            },
            p.min_clearance_cells * scale,
            p.method,
        ),
        SmoothOutcome::NoPath(n) => format!(
            "smooth: no drivable path: {} ({ms:.3} ms)",
            no_path_reason(map, n, start_goal)
        ),
    }
}

/// What `navigate.json` says about a drive with the smooth planner besides the drive.
#[derive(Debug, Clone, Copy)]
pub struct SmoothDriveReport<'a> {
    /// The drive.
    pub run: &'a SmoothNavigation,
    /// The optimum on the true map.
    pub optimum: &'a TruthOptimum,
    /// The options the robot planned with (turning radius, reverse), in cells.
    pub opts: &'a SmoothOptions,
    /// Whether unknown cells were passable to the planner.
    pub unknown_passable: bool,
    /// The sensor range, cells.
    pub sensor_range_cells: f64,
}

/// `navigate.json` of `vpmap navigate --planner smooth` (format in docs/navigation.md): the
/// fields of the other planners' report that apply (`outcome`, `reached`, `moves`,
/// `length`, the true optima and the excess over them, `replans`, `planning_time_s`,
/// `events`, `seen_cells`), and the driven curve: `segments`, `poses` (every pose the robot
/// stood at, `[x, y, heading_deg]`), `max_curvature`, `min_clearance`, `cusps`,
/// `curvature_sign_changes`; `reason` when no drivable path was left.
#[must_use]
pub fn navigate_smooth_json(
    map: &PlanningMap,
    report: &SmoothDriveReport<'_>,
) -> serde_json::Value {
    let SmoothDriveReport {
        run,
        optimum,
        opts,
        unknown_passable,
        sensor_range_cells,
    } = *report;
    let scale = map.scale();
    let unit = map.unit();
    let at = |c: CellXy| {
        let p = pose_in_map(map, Pose::new(c.x as f64, c.y as f64, 0.0));
        [p[0], p[1]]
    };
    let events: Vec<serde_json::Value> = run
        .events
        .iter()
        .map(|e| {
            serde_json::json!({
                "moves": e.moves,
                "cell": [e.cell.x, e.cell.y],
                "at": at(e.cell),
                "pose": run.poses.get(e.moves).map(|&p| pose_in_map(map, p)),
                "reason": e.reason.as_str(),
                "time_s": e.time_s,
                "expanded": e.expanded,
                "planned_length": e.planned_length_cells.map(|l| l * scale),
                "doubted_cells": e.doubted_cells,
            })
        })
        .collect();
    let excess = |opt: Option<f64>| opt.filter(|&o| o > 0.0).map(|o| run.length_cells / o - 1.0);
    serde_json::json!({
        "version": 1,
        "planner": "smooth",
        "units": unit,
        "turning_radius": opts.turning_radius_cells * scale,
        "reverse": opts.reverse,
        "sensor_range_cells": sensor_range_cells,
        "unknown_passable": unknown_passable,
        "outcome": run.outcome.as_str(),
        "reached": run.outcome == Outcome::Reached,
        "reason": run.reason,
        "moves": run.moves,
        "length": run.length_cells * scale,
        "length_cells": run.length_cells,
        "length_m": if unit == "m" { Some(run.length_cells * scale) } else { None },
        "optimum_octile": optimum.octile_cells.map(|l| l * scale),
        "optimum_any_angle": optimum.any_angle_cells.map(|l| l * scale),
        "excess_over_octile": excess(optimum.octile_cells),
        "excess_over_any_angle": excess(optimum.any_angle_cells),
        "replans": run.events.len().saturating_sub(1),
        "planning_time_s": run.planning_time_s,
        "expanded": run.expanded,
        "max_curvature": run.max_curvature / scale,
        "min_clearance": run.min_clearance_cells * scale,
        "cusps": run.cusps,
        "curvature_sign_changes": run.curvature_sign_changes,
        "segments": run.driven.segments.iter().map(|s| segment_json(map, s)).collect::<Vec<_>>(),
        "poses": run.poses.iter().map(|&q| pose_in_map(map, q)).collect::<Vec<_>>(),
        "events": events,
        "seen_cells": run.belief.seen.iter().filter(|&&s| s).count(),
    })
}

/// `navigate.svg` of a drive with the smooth planner: the true map and the driven curve, its
/// tightest turn marked, titled with the outcome and the turning radius (the map's units).
/// `start` and `goal` are the cells the drive was asked between; `turning_radius` is as
/// given (the map's units), for the title.
#[must_use]
pub fn navigate_smooth_svg(
    map: &PlanningMap,
    truth: &OccupancyGrid,
    report: &SmoothDriveReport<'_>,
    ends: [CellXy; 2],
    turning_radius: f64,
) -> String {
    let run = report.run;
    let driven = SmoothPlan {
        curve: run.driven.clone(),
        poses: run.poses.clone(),
        length_cells: run.length_cells,
        max_curvature: run.max_curvature,
        min_clearance_cells: run.min_clearance_cells,
        cusps: run.cusps,
        curvature_sign_changes: run.curvature_sign_changes,
        method: "navigate",
        any_angle_length_cells: report.optimum.any_angle_cells.unwrap_or(0.0),
        stats: SmoothStats::default(),
    };
    let coordinates = if map.in_cells {
        GridCoordinates::Cells
    } else {
        GridCoordinates::World
    };
    let title = format!(
        "Smooth navigation ({}; turning radius {} {})",
        run.outcome.as_str(),
        num(turning_radius),
        map.unit()
    );
    smooth_svg(truth, Some(&driven), ends[0], ends[1], coordinates, &title)
}
