//! A robot that drives a believed map, senses the true one and re-plans: the online use of
//! the planners (repeated A*, repeated A* PS, D* Lite and online MBPP; and repeated A* and
//! D* Lite under the common tie rule of [`crate::dstar_lite`](mod@crate::dstar_lite), which
//! drive identical tracks).
//!
//! # The model
//! - Two grids of one size and resolution: the **belief** (what the robot thinks, e.g. a map
//!   built from a photo, or all [`Occupancy::Unknown`] for unknown terrain) and the
//!   **truth**. Both are already inflated by the robot radius, as for `vpmap plan`, so the
//!   robot is a cell-sized square under the rule of [`crate::los`]. On the truth only
//!   [`Occupancy::Free`] cells can be entered.
//! - Believed-unknown cells are passable to the planners when
//!   [`NavigateOptions::unknown_passable`] is set (the free-space assumption, the default),
//!   blocked otherwise. The goal cell is known to be free (the robot is told where to go).
//! - The robot senses from every cell it stands on ([`Belief`] says exactly what is seen),
//!   then moves one cell along its plan: a grid plan step by step, an any-angle segment
//!   through its Bresenham cells (one per column of its major axis), sensing at each. A
//!   "bumper" stops it before it would sweep a truly blocked cell it has not seen (possible
//!   only behind a corner); that cell is then known blocked.
//! - It re-plans from its cell when (rule of every planner) a cell on the belief became
//!   blocked and its remaining path (the current segment and those after it) is no longer
//!   clear on the belief, or a cell became passable (a shorter path may have opened; with
//!   the free-space assumption and a truth without unknown cells this never happens, since
//!   cells only get blocked, and the current path then stays optimal on the belief). D*
//!   Lite is told every change and every move as they happen (its bookkeeping time counts
//!   as planning time) and computes only when re-planning.
//! - When the robot re-plans mid-segment, its driven polyline gets a waypoint at its cell;
//!   if the straight line from the segment's start to that cell is not clear on the truth,
//!   an intermediate Bresenham cell that makes both parts clear is added.
//!
//! # Online MBPP
//! MBPP is run again from the robot's cell on the updated belief (the thesis's planning and
//! re-planning, section 7.3). The alternatives of the previous runs are kept as candidates:
//! for each, the robot joins it at its last waypoint in line of sight (on the belief) and
//! follows it on; when that whole path is clear on the belief and no longer than the new
//! run's path, it is used instead. Where this differs from the thesis's sketch is in
//! `docs/navigation.md`.
//!
//! # Bounds
//! At most [`NavigateOptions::max_moves`] moves and [`NavigateOptions::max_replans`]
//! re-plans, each planner run within [`NavigateOptions::budget`]; a goal that cannot be
//! reached on the belief ends the run with [`Outcome::GoalUnreachable`].
//!
//! # Example
//! ```
//! use vpmap_plan::{Occupancy, OccupancyGrid};
//! use vpmap_plan::navigate::{navigate, NavigateOptions, OnlinePlanner, Outcome};
//! let mut truth = OccupancyGrid::new(12, 9, 1.0, [0.0; 2], Occupancy::Free).unwrap();
//! for y in 0..8 {
//!     truth.set(6, y, Occupancy::Occupied).unwrap(); // a wall the robot does not know
//! }
//! let belief = OccupancyGrid::new(12, 9, 1.0, [0.0; 2], Occupancy::Unknown).unwrap();
//! let opts = NavigateOptions { planner: OnlinePlanner::DStarLite, sensor_range_cells: 3.0, ..NavigateOptions::default() };
//! let run = navigate(&belief, &truth, (0, 0).into(), (11, 0).into(), &opts).unwrap();
//! assert_eq!(run.outcome, Outcome::Reached);
//! assert!(run.events.len() > 1); // it met the wall and re-planned
//! assert!(run.length_cells > 11.0);
//! ```
//!
//! # Files
//! - `options.rs`: the online planners and the options;
//! - `sensor.rs`: the belief and what the robot senses;
//! - `replan.rs`: the planner side of a drive (re-planning with each online planner, D* Lite's
//!   bookkeeping);
//! - `ties.rs`: A* under the common tie rule;
//! - `shadow.rs`: the A* timed beside a drive, replayed on the logged beliefs;
//! - `outcome.rs`: what a drive returns;
//! - `smooth.rs`: the drive with the smooth planner ([`navigate_smooth`]), along curves
//!   from the robot's pose and heading;
//! - this file: [`navigate`] and the drive itself (moving, the bumper, when to re-plan).

mod options;
mod outcome;
mod replan;
mod sensor;
mod shadow;
pub mod smooth;
mod ties;

pub use options::{NavigateOptions, OnlinePlanner};
pub use outcome::{Navigation, Outcome, ReplanEvent, ReplanReason, TruthOptimum};
pub use sensor::{Belief, MAX_SENSOR_RANGE_CELLS, Sensed};
pub use shadow::ShadowAstar;
pub use smooth::{SmoothNavigateOptions, SmoothNavigation, navigate_smooth};

use crate::budget::Budget;
use crate::error::{PlanError, Result};
use crate::grid::{CellXy, Occupancy, OccupancyGrid};
use crate::los::{Traversable, line_of_sight, visit_swept_cells};
use crate::plan::{check_endpoint, path_length};
use crate::planner::{Planner, PlannerKind};

use replan::{Online, Replanned, Run};
use shadow::BeliefLog;

/// The optimum on the true map (see [`TruthOptimum`]).
///
/// # Errors
/// As the planners: endpoints outside the grid or blocked, budget.
pub fn truth_optimum(
    truth: &OccupancyGrid,
    start: CellXy,
    goal: CellXy,
    budget: &Budget,
) -> Result<TruthOptimum> {
    let mut astar = PlannerKind::Astar
        .planner(false)
        .with_budget(budget.clone());
    let mut optimal = PlannerKind::Optimal
        .planner(false)
        .with_budget(budget.clone());
    Ok(TruthOptimum {
        octile_cells: astar.plan(truth, start, goal)?.best.map(|p| p.length_cells),
        any_angle_cells: optimal
            .plan(truth, start, goal)?
            .best
            .map(|p| p.length_cells),
    })
}

/// Check that `believed` and `truth` can be driven together from `start` to `goal`.
fn check_inputs(
    believed: &OccupancyGrid,
    truth: &OccupancyGrid,
    start: CellXy,
    goal: CellXy,
    sensor_range_cells: f64,
) -> Result<()> {
    if (believed.width(), believed.height()) != (truth.width(), truth.height()) {
        return Err(PlanError::MapMismatch {
            what: "size (cells)",
            believed: format!("{} x {}", believed.width(), believed.height()),
            truth: format!("{} x {}", truth.width(), truth.height()),
        });
    }
    let (rb, rt) = (believed.resolution_m(), truth.resolution_m());
    if (rb - rt).abs() > 1e-9 * rb.max(rt) {
        return Err(PlanError::MapMismatch {
            what: "resolution (m per cell)",
            believed: rb.to_string(),
            truth: rt.to_string(),
        });
    }
    let r = sensor_range_cells;
    if !(r.is_finite() && (1.0..=MAX_SENSOR_RANGE_CELLS).contains(&r)) {
        return Err(PlanError::InvalidParameter {
            field: "sensor range (cells)",
            value: r,
            requirement: "must be finite, at least 1 cell and at most 256 cells",
        });
    }
    check_endpoint(truth, "start", start, false)?;
    check_endpoint(truth, "goal", goal, false)?;
    Ok(())
}

/// The cells a robot driving from `a` to `b` stands on: one per column of the major axis
/// (the Bresenham cells), `a` excluded, `b` last.
fn segment_cells(a: CellXy, b: CellXy) -> Vec<CellXy> {
    let (dx, dy) = (b.x as i64 - a.x as i64, b.y as i64 - a.y as i64);
    let n = dx.abs().max(dy.abs());
    (1..=n)
        .map(|k| {
            let t = k as f64 / n as f64;
            let x = a.x as f64 + (dx as f64 * t).round();
            let y = a.y as f64 + (dy as f64 * t).round();
            CellXy::new(x as usize, y as usize)
        })
        .collect()
}

/// The Bresenham cells of segment `seg` of `path`, empty past its end.
fn segment_at(path: Option<&[CellXy]>, seg: usize) -> Vec<CellXy> {
    match path.map(|p| (p.get(seg), p.get(seg + 1))) {
        Some((Some(&a), Some(&b))) => segment_cells(a, b),
        _ => Vec::new(),
    }
}

/// Drive from `start` to `goal` on `believed`, sensing `truth` (see the
/// [module docs](self)).
///
/// # Errors
/// [`PlanError::MapMismatch`] when the maps differ in size or resolution,
/// [`PlanError::InvalidParameter`] for a sensor range that is not finite or outside
/// `1..=`[`MAX_SENSOR_RANGE_CELLS`], [`PlanError::EndpointOutsideGrid`] and
/// [`PlanError::EndpointBlocked`] for a start or goal outside the grid or not free on the
/// truth, and the planners' budget errors.
///
/// # Complexity
/// Per move: `O(R^3)` for sensing with range `R` (cells not yet seen only), `O(remaining
/// path)` line-of-sight work when a cell got blocked, plus the planner's work at re-plans.
pub fn navigate(
    believed: &OccupancyGrid,
    truth: &OccupancyGrid,
    start: CellXy,
    goal: CellXy,
    opts: &NavigateOptions,
) -> Result<Navigation> {
    drive(believed, truth, start, goal, opts, false)
}

/// [`navigate`], and the tuned repeated A* ([`OnlinePlanner::Astar`]'s planner) is also run
/// on the belief of every planning event, forward from the robot's cell and backward from
/// the goal, and timed apart ([`Navigation::shadow_astar`]; its plans are not used; the
/// beliefs are replayed after the drive, see [`ShadowAstar`]). With
/// [`OnlinePlanner::DStarLiteTies`] this times D* Lite and repeated A* on one and the same
/// track: the drive [`OnlinePlanner::AstarTies`] makes too, re-planning at the same cells.
///
/// # Errors
/// As [`navigate`].
pub fn navigate_with_astar_timed(
    believed: &OccupancyGrid,
    truth: &OccupancyGrid,
    start: CellXy,
    goal: CellXy,
    opts: &NavigateOptions,
) -> Result<Navigation> {
    drive(believed, truth, start, goal, opts, true)
}

/// [`navigate`], with the A* timed beside when `shadow`.
#[allow(clippy::too_many_lines)]
fn drive(
    believed: &OccupancyGrid,
    truth: &OccupancyGrid,
    start: CellXy,
    goal: CellXy,
    opts: &NavigateOptions,
    shadow: bool,
) -> Result<Navigation> {
    check_inputs(believed, truth, start, goal, opts.sensor_range_cells)?;
    let mut belief_grid = believed.clone();
    belief_grid.set(goal.x, goal.y, Occupancy::Free)?;
    let online = match opts.planner {
        OnlinePlanner::DStarLite | OnlinePlanner::DStarLiteTies => Online::DStarLite(None),
        OnlinePlanner::AstarTies => Online::AstarTies(Box::default()),
        other => {
            let kind = match other {
                OnlinePlanner::Astar => PlannerKind::Astar,
                OnlinePlanner::AstarPs => PlannerKind::AstarPs,
                _ => PlannerKind::Mbpp,
            };
            Online::BuiltIn(Box::new(
                kind.planner(opts.unknown_passable)
                    .with_budget(opts.budget.clone()),
            ))
        }
    };
    let mut run = Run {
        goal,
        opts,
        belief: Belief::new(belief_grid, opts.sensor_range_cells),
        online,
        candidates: Vec::new(),
        update_s: 0.0,
        log: None,
    };
    let mut robot = start;
    run.belief.sense(truth, robot, opts.unknown_passable);
    if shadow {
        run.log = Some(BeliefLog {
            initial: run.belief.grid.clone(),
            steps: Vec::new(),
        });
    }
    let mut events = Vec::new();
    let mut cells = vec![start];
    let mut waypoints = vec![start];
    let mut moves = 0;
    let mut expanded = 0;
    let mut event_s = 0.0;
    let mut reason = Some(ReplanReason::Initial);
    let mut path: Option<Vec<CellXy>> = None;
    // The current segment: from `path[seg]` through `seg_cells`, `k` of them driven.
    let mut seg = 0;
    let mut seg_cells: Vec<CellXy> = Vec::new();
    let mut k = 0;
    let outcome = loop {
        if let Some(why) = reason.take() {
            if events.len() >= opts.max_replans {
                break Outcome::ReplanLimit;
            }
            // A mid-segment stop: a waypoint at the robot's cell.
            if k > 0
                && let Some(&a) = path.as_ref().and_then(|p| p.get(seg))
            {
                push_stop(
                    truth,
                    &mut waypoints,
                    a,
                    seg_cells.get(..k).unwrap_or_default(),
                );
            }
            let mut replanned = run.replan(robot)?;
            let mut doubted_cells = 0;
            if replanned.plan.is_none() {
                // No path on the belief: doubt the map's obstacles not seen yet, plan again.
                doubted_cells = run.doubt_unseen(robot)?;
                if doubted_cells > 0 {
                    let again = run.replan(robot)?;
                    replanned = Replanned {
                        time_s: replanned.time_s + again.time_s,
                        ..again
                    };
                }
            }
            event_s += replanned.time_s;
            let stats = replanned.plan.as_ref().map(|p| p.stats).unwrap_or_default();
            expanded += stats.expanded;
            events.push(ReplanEvent {
                moves,
                cell: robot,
                reason: why,
                time_s: replanned.time_s,
                expanded: stats.expanded,
                planned_length_cells: replanned.plan.as_ref().map(|p| p.length_cells),
                used_alternative: replanned.used_alternative,
                doubted_cells,
            });
            path = replanned.plan.map(|p| p.waypoints);
            seg = 0;
            k = 0;
            seg_cells = segment_at(path.as_deref(), seg);
        }
        if robot == goal {
            break Outcome::Reached;
        }
        let Some(p) = &path else {
            break Outcome::GoalUnreachable;
        };
        if moves >= opts.max_moves {
            break Outcome::MoveLimit;
        }
        // The run's own work (sensing, moving) is bounded by the budget's stop too, not only
        // the planner runs: looked at every 64 moves.
        if moves % 64 == 0 {
            opts.budget.stop.check("the navigation")?;
        }
        let (Some(&a), Some(&b), Some(&next)) = (p.get(seg), p.get(seg + 1), seg_cells.get(k))
        else {
            // The plan ends here but not at the goal (not expected): plan again.
            reason = Some(ReplanReason::Blocked);
            continue;
        };
        // The bumper: truly blocked cells the next stretch would sweep, not seen yet.
        let bumped = bump(truth, &mut run.belief, a, b, robot, next);
        if !bumped.is_empty() {
            run.observe(robot, &bumped)?;
            reason = Some(ReplanReason::Blocked);
            continue;
        }
        robot = next;
        moves += 1;
        k += 1;
        cells.push(robot);
        if k == seg_cells.len() {
            waypoints.push(b);
            seg += 1;
            k = 0;
            seg_cells = segment_at(Some(p), seg);
        }
        let sensed = run.belief.sense(truth, robot, opts.unknown_passable);
        run.observe(robot, &sensed.changes)?;
        if sensed.changes.is_empty() {
            continue;
        }
        let view = Traversable::new(&run.belief.grid, opts.unknown_passable);
        let blocked_ahead = p
            .get(seg..)
            .unwrap_or_default()
            .windows(2)
            .any(|s| !line_of_sight(&view, s[0], s[1]));
        if blocked_ahead {
            reason = Some(ReplanReason::Blocked);
        } else if sensed.opened {
            reason = Some(ReplanReason::Opened);
        }
    };
    let length_cells = path_length(&waypoints);
    let shadow_astar = run
        .log
        .as_ref()
        .map(|log| log.replay(goal, opts, &run.belief))
        .transpose()?;
    Ok(Navigation {
        outcome,
        cells,
        waypoints,
        length_cells,
        events,
        planning_time_s: event_s + run.update_s,
        expanded,
        moves,
        belief: run.belief,
        shadow_astar,
    })
}

/// Add the waypoint(s) of a stop at the last of `driven` (Bresenham cells of a segment
/// starting at `a`): the cell itself when `a` sees it on the truth, else through the
/// latest driven cell that both sees.
fn push_stop(truth: &OccupancyGrid, waypoints: &mut Vec<CellXy>, a: CellXy, driven: &[CellXy]) {
    let Some(&at) = driven.last() else { return };
    let view = Traversable::new(truth, false);
    if !line_of_sight(&view, a, at) {
        let via = driven
            .iter()
            .rev()
            .skip(1)
            .find(|&&c| line_of_sight(&view, a, c) && line_of_sight(&view, c, at));
        match via {
            Some(&c) => waypoints.push(c),
            None => waypoints.extend(driven.iter().take(driven.len().saturating_sub(1))),
        }
    }
    waypoints.push(at);
}

/// Cells swept by segment `a -> b` between the robot's cell and `next` (columns of the
/// major axis between theirs) that are blocked on the truth and not seen: they become
/// known blocked and are returned as changes.
fn bump(
    truth: &OccupancyGrid,
    belief: &mut Belief,
    a: CellXy,
    b: CellXy,
    robot: CellXy,
    next: CellXy,
) -> Vec<(CellXy, Occupancy)> {
    let x_major = a.x.abs_diff(b.x) >= a.y.abs_diff(b.y);
    let major = |c: CellXy| if x_major { c.x } else { c.y };
    let (lo, hi) = (major(robot).min(major(next)), major(robot).max(major(next)));
    let mut hits = Vec::new();
    visit_swept_cells(a, b, |x, y| {
        if let (Ok(ux), Ok(uy)) = (usize::try_from(x), usize::try_from(y)) {
            let c = CellXy::new(ux, uy);
            let m = major(c);
            if m >= lo
                && m <= hi
                && truth.get(ux, uy) != Some(Occupancy::Free)
                && let Some(i) = truth.index(ux, uy)
                && !belief.seen.get(i).copied().unwrap_or(true)
            {
                hits.push((c, i));
            }
        }
        true
    });
    let mut changes = Vec::new();
    for (c, i) in hits {
        if let Some(s) = belief.seen.get_mut(i) {
            *s = true;
        }
        if let Some(cell) = belief.grid.cells_mut().get_mut(i)
            && *cell != Occupancy::Occupied
        {
            *cell = Occupancy::Occupied;
            changes.push((c, Occupancy::Occupied));
        }
    }
    changes
}
