//! Curvature-bounded smooth paths a robot can drive ([`plan_smooth`]): lines and circular
//! arcs of radius at least `R`, tangent-continuous, clear of the blocked cells under the
//! collision rule of [`crate::los`] at every point (the unit square centred on the robot's
//! position overlaps no blocked cell's interior).
//!
//! # Method
//! 1. The exact shortest any-angle path ([`crate::anya`]): a lower bound on the length of
//!    any path, and the corridor to follow.
//! 2. [`fillet`]: Dubins paths through its corners (each corner a layer of candidate poses
//!    at the vertex, around the bisector heading), with feasibility repair by a lazy
//!    shortest path over those layers that may skip corners; collision tests exact by
//!    [`clearance::Field`].
//! 3. When that finds nothing: [`hybrid`], a Hybrid-A* with analytic Dubins expansion
//!    (Dolgov et al. 2008), complete up to its resolution.
//! 4. [`polish`] on the path of either (not on the Hybrid-A* run as the reference,
//!    [`SmoothMethod::HybridAstar`], nor with unknown cells passable): shortcuts by clear Dubins words, then each pose's
//!    heading tuned to the shortest, which removes wobble (curvature sign changes that
//!    steer nowhere); never longer, kept only when it passes the validator.
//!
//! With reverse allowed ([`SmoothOptions::reverse`]) both methods may back up (cusps): the
//! fillet's edges and the Hybrid-A*'s analytic expansion also try the Reeds-Shepp words
//! ([`reeds_shepp`], through [`connect`]), the Hybrid-A*'s primitives also run in reverse
//! and its heuristic is the Reeds-Shepp distance.
//! 5. Every returned path is checked by the independent validator [`check`]; a path that
//!    fails it is never returned.
//!
//! Modules, bottom-up: [`curve`] (poses, segments), [`dubins`], [`reeds_shepp`],
//! [`connect`] (the words both methods try), [`check`] (the validator), [`clearance`]
//! (the planner's collision test), [`fillet`], [`hybrid`], [`polish`].
//!
//! Coordinates are cell-centre coordinates (cell `(x, y)`'s centre at `(x, y)`, `y` down
//! the rows), headings `atan2(dy, dx)` in them; see [`curve`].
//!
//! # Example
//! ```
//! use vpmap_plan::{Occupancy, OccupancyGrid};
//! use vpmap_plan::smooth::{plan_smooth, SmoothOptions, SmoothOutcome};
//! let mut grid = OccupancyGrid::new(40, 30, 1.0, [0.0; 2], Occupancy::Free).unwrap();
//! for y in 0..20 {
//!     grid.set(20, y, Occupancy::Occupied).unwrap();
//! }
//! let opts = SmoothOptions { turning_radius_cells: 4.0, ..SmoothOptions::default() };
//! let SmoothOutcome::Path(plan) = plan_smooth(&grid, (5, 5), (35, 5), &opts).unwrap() else {
//!     panic!("no path");
//! };
//! assert!(plan.length_cells >= plan.any_angle_length_cells);
//! assert!(plan.max_curvature <= 1.0 / 4.0 + 1e-12);
//! ```

pub mod check;
pub mod clearance;
pub mod connect;
pub mod curve;
pub mod dubins;
pub mod fillet;
pub mod hybrid;
pub mod polish;
pub mod reeds_shepp;

pub use check::{SmoothRules, SmoothViolation, validate_smooth};
pub use curve::{Gear, Pose, Segment, SmoothCurve};
pub use dubins::{DubinsPath, dubins_distance, dubins_shortest, dubins_words};
pub use hybrid::{HybridOptions, HybridStats};
pub use reeds_shepp::{ReedsSheppPath, rs_distance, rs_paths, rs_shortest};

use std::f64::consts::PI;

use crate::anya::ExactPlanner;
use crate::budget::Budget;
use crate::error::{PlanError, Result};
use crate::grid::{CellXy, OccupancyGrid};
use crate::plan::{PlanStats, check_endpoint};
use clearance::Field;
use fillet::FilletStats;
use hybrid::HybridQuery;

/// Largest spacing of [`SmoothPlan::poses`] along the path, cells.
pub const POSE_SPACING_CELLS: f64 = 0.25;

/// Which methods [`plan_smooth`] may use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SmoothMethod {
    /// Corner fillets on the exact any-angle path, Hybrid-A* when they fail (default).
    #[default]
    Auto,
    /// Hybrid-A* only (the benchmark's reference).
    HybridAstar,
}

/// Options of [`plan_smooth`].
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothOptions {
    /// Smallest turning radius `R`, cells (default 1).
    pub turning_radius_cells: f64,
    /// The start heading, radians (`None`: free).
    pub start_heading_rad: Option<f64>,
    /// The goal heading, radians (`None`: free).
    pub goal_heading_rad: Option<f64>,
    /// Allow driving in reverse (cusps); default forward only.
    pub reverse: bool,
    /// Whether unknown cells may be entered (default: no).
    pub unknown_passable: bool,
    /// Which methods to use.
    pub method: SmoothMethod,
    /// The Hybrid-A*'s settings.
    pub hybrid: HybridOptions,
    /// Work budget: the any-angle search's and the Hybrid-A*'s expansions and states.
    pub budget: Budget,
}

impl Default for SmoothOptions {
    fn default() -> Self {
        Self {
            turning_radius_cells: 1.0,
            start_heading_rad: None,
            goal_heading_rad: None,
            reverse: false,
            unknown_passable: false,
            method: SmoothMethod::Auto,
            hybrid: HybridOptions::default(),
            budget: Budget::default(),
        }
    }
}

/// Work counters of [`plan_smooth`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SmoothStats {
    /// The exact any-angle search's counters.
    pub any_angle: PlanStats,
    /// The fillet search's counters.
    pub fillet: FilletStats,
    /// The Hybrid-A*'s counters (zero when it did not run).
    pub hybrid: HybridStats,
}

/// A drivable path.
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothPlan {
    /// Its lines and arcs.
    pub curve: SmoothCurve,
    /// Poses along it at most [`POSE_SPACING_CELLS`] apart, the first and last exactly the
    /// start and goal (with the path's heading there when a heading was free).
    pub poses: Vec<Pose>,
    /// Length, cells.
    pub length_cells: f64,
    /// Largest curvature, 1/cells.
    pub max_curvature: f64,
    /// Smallest clearance over every point of the curve, cells: how close the robot's square
    /// comes to a blocked cell (Chebyshev distance between the square and the cell's, 0:
    /// touching; [`clearance::Field::curve_min_clearance`], exact).
    pub min_clearance_cells: f64,
    /// Changes between forward and reverse.
    pub cusps: usize,
    /// Sign changes of the curvature along the path.
    pub curvature_sign_changes: usize,
    /// `"fillet"` or `"hybrid-astar"`: which method found it.
    pub method: &'static str,
    /// Length of the exact any-angle path, cells (a lower bound of `length_cells`).
    pub any_angle_length_cells: f64,
    /// Work counters.
    pub stats: SmoothStats,
}

/// The kinds of "no drivable path".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum NoPathKind {
    /// No path of any shape: start and goal are in different components.
    NotConnected,
    /// The start pose cannot move: every turn and the straight line are blocked at once.
    StartHasNoRoom,
    /// The goal pose cannot be entered with its heading.
    GoalHasNoRoom,
    /// Both poses can move, but neither method found a path: the passages between them are
    /// too narrow for the corner fillets and for the Hybrid-A* at its resolution (not a proof
    /// that none exists).
    TooNarrow,
    /// A path was found but failed the independent check (a bug; it is not returned).
    FailedCheck,
}

/// Why there is no drivable path.
#[derive(Clone, Debug, PartialEq)]
pub struct NoDrivablePath {
    /// Which case it is.
    pub kind: NoPathKind,
    /// `Some("start")` or `Some("goal")` when that pose has no room to move.
    pub pose: Option<&'static str>,
    /// The room a turn needs, cells: a clear width of `2 R + 1`.
    pub room_cells: f64,
    /// One sentence for people.
    pub reason: String,
    /// Work counters.
    pub stats: SmoothStats,
}

/// What [`plan_smooth`] found.
#[derive(Clone, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)]
pub enum SmoothOutcome {
    /// A drivable path.
    Path(SmoothPlan),
    /// None, and why.
    NoPath(NoDrivablePath),
}

fn invalid(field: &'static str, value: f64, requirement: &'static str) -> PlanError {
    PlanError::InvalidParameter {
        field,
        value,
        requirement,
    }
}

/// Check the options against `grid`: a finite positive radius no larger than the grid,
/// finite headings.
fn check_options(grid: &OccupancyGrid, opts: &SmoothOptions) -> Result<()> {
    let r = opts.turning_radius_cells;
    if !(r.is_finite() && r > 0.0) {
        return Err(invalid(
            "SmoothOptions.turning_radius_cells",
            r,
            "must be finite and positive",
        ));
    }
    if r > grid.width().max(grid.height()) as f64 {
        return Err(invalid(
            "SmoothOptions.turning_radius_cells",
            r,
            "must be at most the grid's larger side (a larger turning circle cannot fit)",
        ));
    }
    for (field, h) in [
        ("SmoothOptions.start_heading_rad", opts.start_heading_rad),
        ("SmoothOptions.goal_heading_rad", opts.goal_heading_rad),
    ] {
        if let Some(h) = h
            && !h.is_finite()
        {
            return Err(invalid(field, h, "must be finite"));
        }
    }
    Ok(())
}

/// A drivable path from the centre of cell `start` to the centre of cell `goal` (see the
/// [module docs](self)): `SmoothOutcome::Path` with its segments, poses and measures, or
/// `SmoothOutcome::NoPath` with the reason.
///
/// # Errors
/// [`PlanError::InvalidParameter`] for a radius that is not finite and positive or is
/// larger than the grid, or a non-finite heading;
/// [`PlanError::EndpointOutsideGrid`], [`PlanError::EndpointBlocked`] for a bad start or
/// goal; [`PlanError::BudgetExhausted`] and [`PlanError::Stopped`] when the budget says so.
pub fn plan_smooth(
    grid: &OccupancyGrid,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    opts: &SmoothOptions,
) -> Result<SmoothOutcome> {
    check_options(grid, opts)?;
    SmoothPlanner::new(grid, opts.unknown_passable).plan(start, goal, opts)
}

/// [`plan_smooth`] with what it builds from the grid kept between queries: the exact
/// planner's free space ([`ExactPlanner`]) and the distance field of [`Field`] (one pass
/// over the grid each). Build it once per grid and `unknown_passable`.
#[derive(Clone, Debug)]
pub struct SmoothPlanner {
    grid: OccupancyGrid,
    unknown_passable: bool,
    exact: ExactPlanner,
    field: Field,
}

impl SmoothPlanner {
    /// Build the planner's tables for `grid`.
    ///
    /// # Complexity
    /// A few passes over the grid; about 15 bytes a cell.
    #[must_use]
    pub fn new(grid: &OccupancyGrid, unknown_passable: bool) -> Self {
        Self {
            grid: grid.clone(),
            unknown_passable,
            exact: ExactPlanner::new(grid, unknown_passable),
            field: Field::new(grid, unknown_passable),
        }
    }

    /// As [`plan_smooth`] on the planner's grid; `opts.unknown_passable` is the planner's.
    ///
    /// # Errors
    /// As [`plan_smooth`].
    pub fn plan(
        &mut self,
        start: impl Into<CellXy>,
        goal: impl Into<CellXy>,
        opts: &SmoothOptions,
    ) -> Result<SmoothOutcome> {
        let start = start.into();
        let start_pose = Pose::new(
            start.x as f64,
            start.y as f64,
            opts.start_heading_rad.unwrap_or(0.0),
        );
        self.plan_poses(start, start_pose, goal.into(), opts)
    }

    /// As [`Self::plan`], but from a robot's pose anywhere on the grid (not only at a cell
    /// centre), its heading fixed (`opts.start_heading_rad` is ignored): a robot re-planning
    /// mid-drive ([`crate::navigate::navigate_smooth`]). The any-angle path (the lower bound
    /// and the corridor) starts from the cell holding `start`'s position.
    ///
    /// # Errors
    /// As [`plan_smooth`]; [`PlanError::InvalidParameter`] for a pose that is not finite,
    /// [`PlanError::EndpointOutsideGrid`] for one off the grid.
    pub fn plan_from_pose(
        &mut self,
        start: Pose,
        goal: impl Into<CellXy>,
        opts: &SmoothOptions,
    ) -> Result<SmoothOutcome> {
        for (field, v) in [
            ("start pose x (cells)", start.x),
            ("start pose y (cells)", start.y),
            ("start pose heading (rad)", start.heading_rad),
        ] {
            if !v.is_finite() {
                return Err(invalid(field, v, "must be finite"));
            }
        }
        let (w, h) = (self.grid.width(), self.grid.height());
        let (cx, cy) = (start.x.round(), start.y.round());
        if cx < 0.0 || cy < 0.0 || cx >= w as f64 || cy >= h as f64 {
            return Err(PlanError::EndpointOutsideGrid {
                endpoint: "start",
                x: cx.max(0.0) as usize,
                y: cy.max(0.0) as usize,
                width: w,
                height: h,
            });
        }
        let cell = CellXy::new(cx as usize, cy as usize);
        let opts = SmoothOptions {
            start_heading_rad: Some(start.heading_rad),
            ..opts.clone()
        };
        self.plan_poses(cell, start, goal.into(), &opts)
    }

    /// [`Self::plan`] from `start_pose` (in or at the centre of cell `start`), its heading
    /// fixed when `opts.start_heading_rad` is given.
    fn plan_poses(
        &mut self,
        start: CellXy,
        start_pose: Pose,
        goal: CellXy,
        opts: &SmoothOptions,
    ) -> Result<SmoothOutcome> {
        let Self {
            grid,
            unknown_passable,
            exact,
            field,
        } = self;
        let (grid, field) = (&*grid, &*field);
        check_options(grid, opts)?;
        let opts = &SmoothOptions {
            unknown_passable: *unknown_passable,
            ..opts.clone()
        };
        check_endpoint(grid, "start", start, opts.unknown_passable)?;
        check_endpoint(grid, "goal", goal, opts.unknown_passable)?;
        let r = opts.turning_radius_cells;
        let mut stats = SmoothStats::default();
        let goal_pose = Pose::new(
            goal.x as f64,
            goal.y as f64,
            opts.goal_heading_rad.unwrap_or(0.0),
        );
        let room = 2.0 * r + 1.0;
        let Some(taut) = exact.plan(start, goal, &opts.budget)? else {
            return Ok(SmoothOutcome::NoPath(NoDrivablePath {
                kind: NoPathKind::NotConnected,
                pose: None,
                room_cells: room,
                reason: "start and goal are not connected".to_owned(),
                stats,
            }));
        };
        stats.any_angle = taut.stats;
        let rules = SmoothRules {
            radius_cells: r,
            start: start_pose,
            start_heading: opts.start_heading_rad.is_some(),
            goal: goal_pose,
            goal_heading: opts.goal_heading_rad.is_some(),
            reverse: opts.reverse,
            unknown_passable: opts.unknown_passable,
        };
        let same_pose = start_pose.distance(&goal_pose) < 1e-12
            && match (opts.start_heading_rad, opts.goal_heading_rad) {
                (Some(a), Some(b)) => {
                    (a - b)
                        .rem_euclid(2.0 * PI)
                        .min((b - a).rem_euclid(2.0 * PI))
                        < 1e-12
                }
                _ => true,
            };
        let mut rejected: Option<SmoothViolation> = None;
        if same_pose {
            let empty = SmoothCurve::default();
            return Ok(SmoothOutcome::Path(finish(
                field,
                empty,
                &rules,
                "fillet",
                taut.length_cells,
                stats,
            )));
        }
        if opts.method == SmoothMethod::Auto {
            let ends = (
                start_pose,
                !rules.start_heading,
                goal_pose,
                !rules.goal_heading,
            );
            if let Some(curve) = fillet::fillet(
                field,
                &taut.waypoints,
                ends,
                r,
                opts.reverse,
                &mut stats.fillet,
            ) {
                let curve = polished(field, grid, curve, &rules);
                match validate_smooth(grid, &curve, &rules) {
                    Ok(()) => {
                        return Ok(SmoothOutcome::Path(finish(
                            field,
                            curve,
                            &rules,
                            "fillet",
                            taut.length_cells,
                            stats,
                        )));
                    }
                    Err(v) => rejected = Some(v),
                }
            }
        }
        let query = HybridQuery {
            start: start_pose,
            start_free: !rules.start_heading,
            goal: goal_pose,
            goal_free: !rules.goal_heading,
            radius: r,
            reverse: opts.reverse,
        };
        if let Some(curve) =
            hybrid::hybrid_astar(field, &query, &opts.hybrid, &opts.budget, &mut stats.hybrid)?
        {
            // The reference (`HybridAstar`) is left as searched; the fallback is polished.
            let curve = if opts.method == SmoothMethod::Auto {
                polished(field, grid, curve, &rules)
            } else {
                curve
            };
            match validate_smooth(grid, &curve, &rules) {
                Ok(()) => {
                    return Ok(SmoothOutcome::Path(finish(
                        field,
                        curve,
                        &rules,
                        "hybrid-astar",
                        taut.length_cells,
                        stats,
                    )));
                }
                Err(v) => rejected = Some(v),
            }
        }
        Ok(SmoothOutcome::NoPath(no_room(
            field,
            &rules,
            taut.length_cells,
            rejected,
            stats,
        )))
    }
}

/// The measures and poses of a validated curve.
/// `curve` after [`polish::polish`] when the result passes the validator, else `curve`.
/// Not with unknown cells passable (navigation on a map being discovered): there the
/// polish's shortcuts cut through unknown space, and in `vpmap navigate`'s test drive
/// that left the robot facing a wall it then found, with no room to turn.
fn polished(
    field: &Field,
    grid: &OccupancyGrid,
    curve: SmoothCurve,
    rules: &SmoothRules,
) -> SmoothCurve {
    if rules.unknown_passable {
        return curve;
    }
    let free = (!rules.start_heading, !rules.goal_heading);
    match polish::polish(field, &curve, free, rules.radius_cells, rules.reverse) {
        Some(p) if validate_smooth(grid, &p, rules).is_ok() => p,
        _ => curve,
    }
}

fn finish(
    field: &Field,
    curve: SmoothCurve,
    rules: &SmoothRules,
    method: &'static str,
    any_angle: f64,
    stats: SmoothStats,
) -> SmoothPlan {
    let mut poses = curve.sample(POSE_SPACING_CELLS);
    let first_heading = curve
        .segments
        .first()
        .map_or(rules.start.heading_rad, |s| s.start.heading_rad);
    let last_heading = curve
        .segments
        .last()
        .map_or(rules.goal.heading_rad, |s| s.end().heading_rad);
    let first = Pose::new(
        rules.start.x,
        rules.start.y,
        if rules.start_heading {
            rules.start.heading_rad
        } else {
            first_heading
        },
    );
    let last = Pose::new(
        rules.goal.x,
        rules.goal.y,
        if rules.goal_heading {
            rules.goal.heading_rad
        } else {
            last_heading
        },
    );
    if poses.is_empty() {
        poses.push(first);
    } else {
        if let Some(p) = poses.first_mut() {
            *p = first;
        }
        if let Some(p) = poses.last_mut() {
            *p = last;
        }
    }
    SmoothPlan {
        length_cells: curve.length(),
        max_curvature: curve.max_curvature(),
        // Touching within round-off is touching.
        min_clearance_cells: {
            let c = field.curve_min_clearance(&curve, rules.start);
            if c.abs() < 1e-9 { 0.0 } else { c }
        },
        cusps: curve.cusps(),
        curvature_sign_changes: curve.curvature_sign_changes(),
        method,
        any_angle_length_cells: any_angle,
        stats,
        poses,
        curve,
    }
}

/// Whether a robot at `pose` can move at all: one primitive step (a quarter of the turning
/// circle or `sqrt 2` cells, whichever is shorter... at least one cell) left, straight or
/// right, forward (or in reverse when allowed).
fn can_move(field: &Field, pose: Pose, r: f64, reverse: bool) -> bool {
    let step = (r * PI / 2.0).min(2f64.sqrt()).max(1.0);
    let gears: &[Gear] = if reverse {
        &[Gear::Forward, Gear::Reverse]
    } else {
        &[Gear::Forward]
    };
    gears.iter().any(|&gear| {
        [1.0 / r, 0.0, -1.0 / r].iter().any(|&curvature| {
            field.segment_clear(&Segment {
                start: pose,
                curvature,
                length: step,
                gear,
            })
        })
    })
}

/// The reason for "no drivable path" after both methods failed.
fn no_room(
    field: &Field,
    rules: &SmoothRules,
    any_angle: f64,
    rejected: Option<SmoothViolation>,
    stats: SmoothStats,
) -> NoDrivablePath {
    let r = rules.radius_cells;
    let room = 2.0 * r + 1.0;
    let deg = |h: f64| h.to_degrees();
    if let Some(v) = rejected {
        return NoDrivablePath {
            kind: NoPathKind::FailedCheck,
            pose: None,
            room_cells: room,
            reason: format!("the path found failed the independent check ({v}); none is returned"),
            stats,
        };
    }
    if rules.start_heading && !can_move(field, rules.start, r, rules.reverse) {
        return NoDrivablePath {
            kind: NoPathKind::StartHasNoRoom,
            pose: Some("start"),
            room_cells: room,
            reason: format!(
                "the start pose ({}, {}) heading {:.1} degrees has no room to move: every turn of radius {r} cells and the straight line are blocked within a cell; it needs a clear turning space about {room:.1} cells wide",
                rules.start.x,
                rules.start.y,
                deg(rules.start.heading_rad)
            ),
            stats,
        };
    }
    let arriving = Pose::new(rules.goal.x, rules.goal.y, rules.goal.heading_rad + PI);
    if rules.goal_heading && !can_move(field, arriving, r, rules.reverse) {
        return NoDrivablePath {
            kind: NoPathKind::GoalHasNoRoom,
            pose: Some("goal"),
            room_cells: room,
            reason: format!(
                "the goal pose ({}, {}) heading {:.1} degrees cannot be reached: every turn of radius {r} cells and the straight line into it are blocked within a cell; it needs a clear turning space about {room:.1} cells wide",
                rules.goal.x,
                rules.goal.y,
                deg(rules.goal.heading_rad)
            ),
            stats,
        };
    }
    NoDrivablePath {
        kind: NoPathKind::TooNarrow,
        pose: None,
        room_cells: room,
        reason: format!(
            "no path with turning radius {r} cells was found between them: the any-angle path ({any_angle:.2} cells) passes where neither the corner fillets nor the Hybrid-A* (complete only up to its cells and headings) fit a turn of that radius (a turn needs a clear space about {room:.1} cells wide)"
        ),
        stats,
    }
}
