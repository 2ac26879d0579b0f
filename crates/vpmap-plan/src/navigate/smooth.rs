//! The drive with the smooth planner ([`navigate_smooth`]): the robot follows lines and
//! arcs of radius at least `R` and re-plans from its current pose **and heading**, so what
//! it drives is one tangent-continuous, curvature-bounded curve.
//!
//! # The model
//! As [`navigate`](super::navigate) (believed and true grids, both inflated; the sensor;
//! the free-space assumption; the goal known free; doubting the map's unseen obstacles when
//! the belief has no path), except for how the robot moves:
//! - A plan is a [`SmoothCurve`] from the robot's pose to the goal's cell centre
//!   ([`SmoothPlanner::plan_from_pose`], on the belief as it is at that moment). The first
//!   plan starts at the start cell's centre with the asked heading (free when none was
//!   asked); every later one at the robot's pose with its heading fixed.
//! - The robot drives each segment in steps of at most [`POSE_SPACING_CELLS`] along it (a
//!   **move**), sensing from the cell holding its position after each. Before a step the
//!   "bumper" tests the step's piece of curve exactly against the truth (the collision rule
//!   of [`crate::smooth::check`]): a truly blocked cell it would enter, not seen yet, becomes
//!   known blocked and the robot re-plans where it stands.
//! - The turning margin ([`SmoothNavigateOptions::turning_margin`]): with the free-space
//!   assumption a plan skirts the end of the part of a wall seen so far, and when the wall
//!   goes on the robot, which cannot turn on the spot, may be too close to turn away. So
//!   unknown cells not seen yet within `ceil(R)` cells of a seen obstacle or the map's
//!   border are believed blocked for planning (the plain belief is used when that leaves
//!   no path). Forward only: a robot that may back up does not need it.
//! - It re-plans when a sensed change blocks the rest of its curve on the belief (exactly,
//!   the same rule) or opens a cell. A re-plan mid-segment cuts the segment where the robot
//!   stands; the driven curve is the cut pieces end to end.
//! - When no drivable path leaves the robot's pose (a wall seen too late to turn before
//!   it, with reverse not allowed), the run ends with [`Outcome::NoDrivablePath`] and the
//!   planner's reason.
//!
//! # Bounds
//! At most [`SmoothNavigateOptions::max_moves`] moves (steps of a quarter cell) and
//! [`SmoothNavigateOptions::max_replans`] re-plans, each within the smooth planner's budget
//! ([`SmoothOptions::budget`], whose stop is also looked at every 64 moves). Each re-plan
//! builds the planner's tables for the belief: a few passes over the grid.

use std::time::Instant;

use crate::error::Result;
use crate::grid::{CellXy, Occupancy, OccupancyGrid};
use crate::smooth::check::segment_collision;
use crate::smooth::clearance::Field;
use crate::smooth::{
    POSE_SPACING_CELLS, Pose, Segment, SmoothCurve, SmoothOptions, SmoothOutcome, SmoothPlanner,
};

use super::outcome::{Outcome, ReplanEvent, ReplanReason};
use super::sensor::Belief;

/// Options of [`navigate_smooth`].
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothNavigateOptions {
    /// The smooth planner's options: turning radius, start and goal headings (the start's
    /// for the first plan only), reverse, budget. Its `unknown_passable` is ignored
    /// (see [`Self::unknown_passable`]).
    pub smooth: SmoothOptions,
    /// Sensor range, cells, as [`NavigateOptions::sensor_range_cells`](super::NavigateOptions::sensor_range_cells)
    /// (default 10).
    pub sensor_range_cells: f64,
    /// Whether believed-unknown cells are passable to the planner (default `true`).
    pub unknown_passable: bool,
    /// Most moves (steps of at most [`POSE_SPACING_CELLS`]) before the run stops with
    /// [`Outcome::MoveLimit`] (default 40 million).
    pub max_moves: usize,
    /// Most re-plans before the run stops with [`Outcome::ReplanLimit`] (default 100 000).
    pub max_replans: usize,
    /// Forward only, with the unknown passable: plan first with unknown cells not seen yet
    /// within `R` of a seen obstacle or the map's border believed blocked (the obstacle may
    /// go on, and the robot needs room to turn when it does), on the plain belief when that
    /// finds no path (default `true`). Not used when reverse is allowed: a robot that may
    /// back up gets away from a wall by backing, and the margin only lengthens its drive.
    pub turning_margin: bool,
}

impl Default for SmoothNavigateOptions {
    fn default() -> Self {
        Self {
            smooth: SmoothOptions::default(),
            sensor_range_cells: 10.0,
            unknown_passable: true,
            max_moves: 40_000_000,
            max_replans: 100_000,
            turning_margin: true,
        }
    }
}

/// The result of [`navigate_smooth`].
#[derive(Clone, Debug)]
pub struct SmoothNavigation {
    /// How the run ended.
    pub outcome: Outcome,
    /// Why the last plan found no drivable path (with [`Outcome::NoDrivablePath`]).
    pub reason: Option<String>,
    /// The curve the robot drove, from the start pose to where it stopped.
    pub driven: SmoothCurve,
    /// Every pose the robot stood at, in order, the start first (consecutive ones at most
    /// [`POSE_SPACING_CELLS`] apart along the curve).
    pub poses: Vec<Pose>,
    /// Length of the driven curve, cells.
    pub length_cells: f64,
    /// Largest curvature driven, 1/cells.
    pub max_curvature: f64,
    /// Changes between forward and reverse.
    pub cusps: usize,
    /// Sign changes of the curvature along the driven curve.
    pub curvature_sign_changes: usize,
    /// Smallest clearance on the true map over every point of the driven curve, cells (see
    /// [`Field::curve_min_clearance`]).
    pub min_clearance_cells: f64,
    /// Every planning event, the initial one first (`cell`: the cell holding the robot's
    /// position; `expanded`: the any-angle search's and the Hybrid-A*'s expansions).
    pub events: Vec<ReplanEvent>,
    /// Total planning time (building the planner's tables and planning), seconds.
    pub planning_time_s: f64,
    /// Total expansions of every event.
    pub expanded: usize,
    /// Moves made.
    pub moves: usize,
    /// The belief at the end, and the cells seen.
    pub belief: Belief,
}

/// The cell holding a position (cell `(x, y)` spans `x - 0.5 ..= x + 0.5`), if on the grid.
fn cell_of(grid: &OccupancyGrid, p: Pose) -> Option<CellXy> {
    let (x, y) = (p.x.round(), p.y.round());
    (x >= 0.0 && y >= 0.0 && x < grid.width() as f64 && y < grid.height() as f64)
        .then(|| CellXy::new(x as usize, y as usize))
}

/// The part of `seg` from `from` on, `length` long (clamped to what is left).
fn piece(seg: &Segment, from: f64, length: f64) -> Segment {
    Segment {
        start: seg.pose_at(from),
        length: length.min(seg.length - from).max(0.0),
        ..*seg
    }
}

/// A plan from the robot's pose on the current belief.
struct Planned {
    curve: Option<SmoothCurve>,
    reason: Option<String>,
    expanded: usize,
    length_cells: Option<f64>,
}

/// The belief with [`Occupancy::Unknown`] cells not seen yet within `margin` cells
/// (Chebyshev) of a seen blocked cell or of the map's border believed blocked: the obstacle may go on where it has
/// not been seen, and a robot that cannot turn on the spot needs room to turn when it does.
/// `None` when that changes nothing.
///
/// # Complexity
/// `O(cells)`: a dilation by running counts, along the rows then the columns.
fn with_margin(belief: &Belief, margin: usize) -> Option<OccupancyGrid> {
    let grid = &belief.grid;
    let (w, h) = (grid.width(), grid.height());
    if margin == 0 || w == 0 {
        return None;
    }
    let seen_blocked: Vec<bool> = grid
        .cells()
        .iter()
        .zip(&belief.seen)
        .map(|(&c, &seen)| seen && c == Occupancy::Occupied)
        .collect();
    // Along rows: any seen blocked cell within `margin` columns.
    let dilate = |line: &[bool]| -> Vec<bool> {
        let mut prefix = Vec::with_capacity(line.len() + 1);
        prefix.push(0usize);
        for &b in line {
            prefix.push(prefix.last().copied().unwrap_or(0) + usize::from(b));
        }
        (0..line.len())
            .map(|i| {
                let lo = i.saturating_sub(margin);
                let hi = (i + margin + 1).min(line.len());
                prefix.get(hi).copied().unwrap_or(0) > prefix.get(lo).copied().unwrap_or(0)
            })
            .collect()
    };
    let rows: Vec<bool> = seen_blocked.chunks(w).flat_map(dilate).collect();
    let mut near = vec![false; w * h];
    for x in 0..w {
        let column: Vec<bool> = (0..h)
            .map(|y| rows.get(y * w + x).copied().unwrap_or(false))
            .collect();
        for (y, b) in dilate(&column).into_iter().enumerate() {
            if let Some(n) = near.get_mut(y * w + x) {
                *n = b;
            }
        }
    }
    // The map's border is a known obstacle too.
    for (i, n) in near.iter_mut().enumerate() {
        let (x, y) = (i % w, i / w);
        if x < margin || y < margin || x + margin >= w || y + margin >= h {
            *n = true;
        }
    }
    let mut out = grid.clone();
    let mut changed = false;
    for ((cell, &seen), &n) in out.cells_mut().iter_mut().zip(&belief.seen).zip(&near) {
        if n && !seen && *cell == Occupancy::Unknown {
            *cell = Occupancy::Occupied;
            changed = true;
        }
    }
    changed.then_some(out)
}

/// Plan from `pose`: on the belief with the turning margin ([`with_margin`], when the
/// unknown is passable), and on the belief itself when that finds no path.
fn plan_with_margin(
    belief: &Belief,
    pose: Pose,
    first: bool,
    goal: CellXy,
    opts: &SmoothNavigateOptions,
) -> Result<Planned> {
    let margin = opts.smooth.turning_radius_cells.max(0.0).ceil() as usize;
    if opts.unknown_passable
        && opts.turning_margin
        && !opts.smooth.reverse
        && let Some(cautious) = with_margin(belief, margin)
        && let Some(start) = cell_of(&cautious, pose)
        && cautious.get(start.x, start.y) != Some(Occupancy::Occupied)
    {
        let planned = plan_once(&cautious, pose, first, goal, opts)?;
        if planned.curve.is_some() {
            return Ok(planned);
        }
        let plain = plan_once(&belief.grid, pose, first, goal, opts)?;
        return Ok(Planned {
            expanded: planned.expanded + plain.expanded,
            ..plain
        });
    }
    plan_once(&belief.grid, pose, first, goal, opts)
}

fn plan_once(
    belief: &OccupancyGrid,
    pose: Pose,
    first: bool,
    goal: CellXy,
    opts: &SmoothNavigateOptions,
) -> Result<Planned> {
    let mut planner = SmoothPlanner::new(belief, opts.unknown_passable);
    let outcome = if first && opts.smooth.start_heading_rad.is_none() {
        planner.plan(cell_of(belief, pose).unwrap_or(goal), goal, &opts.smooth)?
    } else {
        planner.plan_from_pose(pose, goal, &opts.smooth)?
    };
    Ok(match outcome {
        SmoothOutcome::Path(p) => Planned {
            expanded: p.stats.any_angle.expanded + p.stats.hybrid.expanded,
            length_cells: Some(p.length_cells),
            curve: Some(p.curve),
            reason: None,
        },
        SmoothOutcome::NoPath(n) => Planned {
            expanded: n.stats.any_angle.expanded + n.stats.hybrid.expanded,
            length_cells: None,
            curve: None,
            reason: Some(n.reason),
        },
    })
}

/// Drive from the centre of `start` to the centre of `goal` on `believed`, sensing
/// `truth`, with the smooth planner (see the [module docs](self)).
///
/// # Errors
/// As [`navigate`](super::navigate) for the maps, the sensor range and the endpoints; as
/// [`plan_smooth`](crate::smooth::plan_smooth) for the turning radius, the headings and
/// the budget.
///
/// # Complexity
/// Per move: sensing as [`navigate`](super::navigate) and an exact test of a quarter cell
/// of curve; after a sensed change, an exact test of the rest of the curve; per re-plan, a
/// few passes over the grid plus the smooth planner's work.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid};
/// use vpmap_plan::navigate::{navigate_smooth, Outcome, SmoothNavigateOptions};
/// use vpmap_plan::smooth::{validate_smooth, Pose, SmoothOptions, SmoothRules};
/// let mut truth = OccupancyGrid::new(40, 30, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// for y in 0..20 {
///     truth.set(20, y, Occupancy::Occupied).unwrap(); // a wall the robot does not know
/// }
/// let belief = OccupancyGrid::new(40, 30, 1.0, [0.0; 2], Occupancy::Unknown).unwrap();
/// // It may back up: forward only, a wall seen late can leave it no room to turn.
/// let smooth = SmoothOptions {
///     turning_radius_cells: 3.0,
///     start_heading_rad: Some(0.0),
///     reverse: true,
///     ..SmoothOptions::default()
/// };
/// let opts = SmoothNavigateOptions { smooth, ..SmoothNavigateOptions::default() };
/// let run = navigate_smooth(&belief, &truth, (5, 5).into(), (35, 5).into(), &opts).unwrap();
/// assert_eq!(run.outcome, Outcome::Reached);
/// let rules = SmoothRules {
///     radius_cells: 3.0,
///     start: Pose::new(5.0, 5.0, 0.0),
///     start_heading: true,
///     goal: Pose::new(35.0, 5.0, 0.0),
///     goal_heading: false,
///     reverse: true,
///     unknown_passable: false,
/// };
/// assert!(validate_smooth(&truth, &run.driven, &rules).is_ok()); // drivable on the truth
/// ```
#[allow(clippy::too_many_lines)]
pub fn navigate_smooth(
    believed: &OccupancyGrid,
    truth: &OccupancyGrid,
    start: CellXy,
    goal: CellXy,
    opts: &SmoothNavigateOptions,
) -> Result<SmoothNavigation> {
    super::check_inputs(believed, truth, start, goal, opts.sensor_range_cells)?;
    let mut belief_grid = believed.clone();
    belief_grid.set(goal.x, goal.y, Occupancy::Free)?;
    let mut belief = Belief::new(belief_grid, opts.sensor_range_cells);
    let unknown_passable = opts.unknown_passable;
    let mut robot = Pose::new(
        start.x as f64,
        start.y as f64,
        opts.smooth.start_heading_rad.unwrap_or(0.0),
    );
    belief.sense(truth, start, unknown_passable);
    let mut driven = SmoothCurve::default();
    let mut poses = vec![robot];
    let mut events = Vec::new();
    let (mut moves, mut expanded, mut planning_time_s) = (0, 0, 0.0);
    let mut reason = Some(ReplanReason::Initial);
    let mut last_reason: Option<String> = None;
    // The plan being driven, the segment `seg` of it, `s` cells into that segment.
    let mut plan: Option<Vec<Segment>> = None;
    let (mut seg, mut s) = (0, 0.0);
    let outcome = loop {
        if let Some(why) = reason.take() {
            if events.len() >= opts.max_replans {
                break Outcome::ReplanLimit;
            }
            // A stop mid-segment: the driven part of it.
            if let Some(cur) = plan.as_ref().and_then(|p| p.get(seg)) {
                driven.push(piece(cur, 0.0, s));
            }
            let first = events.is_empty();
            let t0 = Instant::now();
            let mut planned = plan_with_margin(&belief, robot, first, goal, opts)?;
            let mut doubted_cells = 0;
            if planned.curve.is_none() {
                doubted_cells = belief.doubt_unseen(unknown_passable)?.len();
                if doubted_cells > 0 {
                    let again = plan_with_margin(&belief, robot, first, goal, opts)?;
                    planned = Planned {
                        expanded: planned.expanded + again.expanded,
                        ..again
                    };
                }
            }
            let time_s = t0.elapsed().as_secs_f64();
            planning_time_s += time_s;
            expanded += planned.expanded;
            events.push(ReplanEvent {
                moves,
                cell: cell_of(&belief.grid, robot).unwrap_or(start),
                reason: why,
                time_s,
                expanded: planned.expanded,
                planned_length_cells: planned.length_cells,
                used_alternative: false,
                doubted_cells,
            });
            last_reason = planned.reason;
            plan = planned.curve.map(|c| c.segments);
            (seg, s) = (0, 0.0);
            // A free start heading is the first plan's.
            if first
                && opts.smooth.start_heading_rad.is_none()
                && let Some(first_seg) = plan.as_ref().and_then(|p| p.first())
            {
                robot = first_seg.start;
                if let Some(p) = poses.first_mut() {
                    *p = robot;
                }
            }
        }
        let Some(p) = &plan else {
            break Outcome::NoDrivablePath;
        };
        let Some(cur) = p.get(seg).copied() else {
            // Every segment driven: the plan ends at the goal's centre.
            break Outcome::Reached;
        };
        if moves >= opts.max_moves {
            driven.push(piece(&cur, 0.0, s));
            break Outcome::MoveLimit;
        }
        if moves % 64 == 0 {
            opts.smooth.budget.stop.check("the navigation")?;
        }
        let steps = (cur.length / POSE_SPACING_CELLS).ceil().max(1.0);
        let step = piece(&cur, s, cur.length / steps);
        // The bumper: a truly blocked cell the step would enter, not seen yet.
        if let Some(((x, y), _)) = segment_collision(truth, &step, false) {
            if let (Ok(ux), Ok(uy)) = (usize::try_from(x), usize::try_from(y))
                && let Some(i) = truth.index(ux, uy)
            {
                if let Some(seen) = belief.seen.get_mut(i) {
                    *seen = true;
                }
                belief.grid.set(ux, uy, Occupancy::Occupied)?;
            }
            reason = Some(ReplanReason::Blocked);
            continue;
        }
        robot = step.end();
        moves += 1;
        s += step.length;
        poses.push(robot);
        if s >= cur.length * (1.0 - 1e-12) {
            driven.push(cur);
            seg += 1;
            s = 0.0;
        }
        let Some(cell) = cell_of(truth, robot) else {
            continue;
        };
        let sensed = belief.sense(truth, cell, unknown_passable);
        if sensed.changes.is_empty() {
            continue;
        }
        let grid = &belief.grid;
        let rest_blocked = p.get(seg).is_some_and(|c| {
            segment_collision(grid, &piece(c, s, c.length), unknown_passable).is_some()
        }) || p
            .get(seg + 1..)
            .unwrap_or_default()
            .iter()
            .any(|c| segment_collision(grid, c, unknown_passable).is_some());
        if rest_blocked {
            reason = Some(ReplanReason::Blocked);
        } else if sensed.opened {
            reason = Some(ReplanReason::Opened);
        }
    };
    let field = Field::new(truth, false);
    let first = poses.first().copied().unwrap_or(robot);
    let min_clearance = field.curve_min_clearance(&driven, first);
    Ok(SmoothNavigation {
        outcome,
        reason: if outcome == Outcome::NoDrivablePath {
            last_reason
        } else {
            None
        },
        length_cells: driven.length(),
        max_curvature: driven.max_curvature(),
        cusps: driven.cusps(),
        curvature_sign_changes: driven.curvature_sign_changes(),
        min_clearance_cells: if min_clearance.abs() < 1e-9 {
            0.0
        } else {
            min_clearance
        },
        driven,
        poses,
        events,
        planning_time_s,
        expanded,
        moves,
        belief,
    })
}
