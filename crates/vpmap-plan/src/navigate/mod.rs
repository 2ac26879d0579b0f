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

mod sensor;
mod ties;

use std::str::FromStr;
use std::time::Instant;

pub use sensor::{Belief, MAX_SENSOR_RANGE_CELLS, Sensed};

use crate::budget::Budget;
use crate::dstar_lite::{DStarLite, DStarLiteOptions};
use crate::error::{PlanError, Result};
use crate::grid::{CellXy, Occupancy, OccupancyGrid};
use crate::los::{Traversable, line_of_sight, visit_swept_cells};
use crate::plan::{Plan, check_endpoint, path_length};
use crate::planner::{BuiltIn, Planner, PlannerKind};

/// The planners a robot can re-plan with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OnlinePlanner {
    /// A* from scratch at every re-plan ([`crate::astar`](mod@crate::astar)).
    Astar,
    /// A* PS from scratch at every re-plan ([`crate::smoothing`]).
    AstarPs,
    /// D* Lite, incremental ([`crate::dstar_lite`](mod@crate::dstar_lite)).
    DStarLite,
    /// MBPP re-run from the robot's cell, keeping its alternatives (see the
    /// [module docs](self)).
    Mbpp,
    /// A* from scratch at every re-plan under the common tie rule (a plain A*, not the
    /// tuned one): drives the same track as [`OnlinePlanner::DStarLiteTies`].
    AstarTies,
    /// D* Lite under the common tie rule
    /// ([`DStarLiteOptions::common_ties`]): drives the same track as
    /// [`OnlinePlanner::AstarTies`].
    DStarLiteTies,
}

impl OnlinePlanner {
    /// Every online planner.
    pub const ALL: [Self; 6] = [
        Self::Astar,
        Self::AstarPs,
        Self::DStarLite,
        Self::Mbpp,
        Self::AstarTies,
        Self::DStarLiteTies,
    ];

    /// The planner's name (also what [`FromStr`] reads).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Astar => "astar",
            Self::AstarPs => "astar-ps",
            Self::DStarLite => "dstar-lite",
            Self::Mbpp => "mbpp",
            Self::AstarTies => "astar-ties",
            Self::DStarLiteTies => "dstar-lite-ties",
        }
    }
}

impl FromStr for OnlinePlanner {
    type Err = PlanError;

    fn from_str(s: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| PlanError::UnknownPlanner {
                name: s.to_owned(),
                choices: Self::ALL.map(Self::name).join(", "),
            })
    }
}

/// Options of [`navigate`].
#[derive(Clone, Debug, PartialEq)]
pub struct NavigateOptions {
    /// The planner (default D* Lite).
    pub planner: OnlinePlanner,
    /// Sensor range, cells (centre to centre); at least 1, at most
    /// [`MAX_SENSOR_RANGE_CELLS`] (default 10).
    pub sensor_range_cells: f64,
    /// Whether believed-unknown cells are passable to the planners (default `true`, the
    /// free-space assumption).
    pub unknown_passable: bool,
    /// Most moves (cells) before the run stops with [`Outcome::MoveLimit`] (default 10
    /// million).
    pub max_moves: usize,
    /// Most re-plans before the run stops with [`Outcome::ReplanLimit`] (default 1 million).
    pub max_replans: usize,
    /// The budget of each planner run (default [`Budget::default`]).
    pub budget: Budget,
}

impl Default for NavigateOptions {
    fn default() -> Self {
        Self {
            planner: OnlinePlanner::DStarLite,
            sensor_range_cells: 10.0,
            unknown_passable: true,
            max_moves: 10_000_000,
            max_replans: 1_000_000,
            budget: Budget::default(),
        }
    }
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// The robot reached the goal.
    Reached,
    /// No path to the goal even when every cell the sensor has not seen is believed free:
    /// the goal is unreachable as far as the robot can know. (When the belief has no path,
    /// its obstacles the sensor has never seen are doubted first, so a map's false obstacles
    /// never make the robot give up on a goal it could reach.)
    GoalUnreachable,
    /// [`NavigateOptions::max_moves`] reached.
    MoveLimit,
    /// [`NavigateOptions::max_replans`] reached.
    ReplanLimit,
}

impl Outcome {
    /// A short description (`"reached"`, `"goal unreachable after sensing"`, ...).
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Reached => "reached",
            Self::GoalUnreachable => "goal unreachable after sensing",
            Self::MoveLimit => "move limit reached",
            Self::ReplanLimit => "re-plan limit reached",
        }
    }
}

/// Why the robot planned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReplanReason {
    /// The first plan, from the start.
    Initial,
    /// A newly blocked cell lies on the remaining path.
    Blocked,
    /// A cell became passable: a shorter path may have opened.
    Opened,
}

impl ReplanReason {
    /// `"initial"`, `"blocked"` or `"opened"`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Initial => "initial",
            Self::Blocked => "blocked",
            Self::Opened => "opened",
        }
    }
}

/// One planning event.
#[derive(Clone, Debug, PartialEq)]
pub struct ReplanEvent {
    /// Moves made before it.
    pub moves: usize,
    /// The robot's cell.
    pub cell: CellXy,
    /// Why.
    pub reason: ReplanReason,
    /// Planner time, seconds (wall clock).
    pub time_s: f64,
    /// Nodes the planner expanded (MBPP: bug steps).
    pub expanded: usize,
    /// Length of the new plan on the belief, cells; `None` when there is none.
    pub planned_length_cells: Option<f64>,
    /// Online MBPP: whether a kept alternative was used instead of the new run's path.
    pub used_alternative: bool,
    /// Cells the map believed blocked that the sensor had never seen, believed free from
    /// this event on because no path existed otherwise (0 in most events; see
    /// [`Outcome::GoalUnreachable`]).
    pub doubted_cells: usize,
}

/// The result of [`navigate`].
#[derive(Clone, Debug)]
pub struct Navigation {
    /// How the run ended.
    pub outcome: Outcome,
    /// Every cell the robot stood on, in order, start first.
    pub cells: Vec<CellXy>,
    /// The driven polyline (segment ends and re-planning cells), clear on the truth.
    pub waypoints: Vec<CellXy>,
    /// Length of [`Navigation::waypoints`], cells.
    pub length_cells: f64,
    /// Every planning event, the initial one first.
    pub events: Vec<ReplanEvent>,
    /// Total planning time: every event's, plus D* Lite's bookkeeping of changes and
    /// moves, seconds.
    pub planning_time_s: f64,
    /// Total expansions of every event.
    pub expanded: usize,
    /// Moves made.
    pub moves: usize,
    /// The belief at the end, and the cells seen.
    pub belief: Belief,
    /// [`navigate_with_astar_timed`] only: the repeated A* (the tuned one,
    /// [`OnlinePlanner::Astar`]'s planner) run at every planning event of this drive on
    /// the same belief, forward from the robot's cell and backward from the goal; not part
    /// of [`Navigation::planning_time_s`].
    pub shadow_astar: Option<ShadowAstar>,
}

/// The tuned repeated A* run on the belief of each planning event of a drive
/// ([`navigate_with_astar_timed`]), its plans not used: forward (robot to goal, as
/// [`OnlinePlanner::Astar`] plans) and backward (goal to robot, the direction D* Lite
/// searches in). Totals over the events. The beliefs are replayed after the drive from its
/// log of changes, each direction in a pass of its own, so that no search shares the caches
/// with the planner driven or with the other direction.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShadowAstar {
    /// Forward searches' time, seconds.
    pub forward_time_s: f64,
    /// Forward searches' expansions.
    pub forward_expanded: usize,
    /// Backward searches' time, seconds.
    pub backward_time_s: f64,
    /// Backward searches' expansions.
    pub backward_expanded: usize,
}

/// The shortest paths on the true map, for comparison: octile (A*) and any-angle (the
/// exact planner), cells; `None` when the goal is unreachable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TruthOptimum {
    /// Shortest 8-connected path, cells.
    pub octile_cells: Option<f64>,
    /// Shortest any-angle path, cells.
    pub any_angle_cells: Option<f64>,
}

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
    opts: &NavigateOptions,
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
    let r = opts.sensor_range_cells;
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

/// The planner state of a run.
enum Online {
    /// A*, A* PS or MBPP through the planner interface.
    BuiltIn(Box<BuiltIn>),
    /// D* Lite, created at the first plan.
    DStarLite(Option<Box<DStarLite>>),
    /// A* under the common tie rule.
    AstarTies(Box<ties::TieAstar>),
}

/// What a re-plan produced.
struct Replanned {
    plan: Option<Plan>,
    time_s: f64,
    used_alternative: bool,
}

struct Run<'a> {
    goal: CellXy,
    opts: &'a NavigateOptions,
    belief: Belief,
    online: Online,
    /// Online MBPP's kept alternatives.
    candidates: Vec<Vec<CellXy>>,
    /// D* Lite's bookkeeping time, seconds.
    update_s: f64,
    /// With the A* timed beside ([`navigate_with_astar_timed`]): the belief's history, to
    /// replay after the drive.
    log: Option<BeliefLog>,
}

/// The belief as it was when planning started, and every change and planning event after
/// it in order: enough to rebuild the belief of every event after the drive.
struct BeliefLog {
    initial: OccupancyGrid,
    steps: Vec<Logged>,
}

enum Logged {
    /// Cells that took these states.
    Changes(Vec<(CellXy, Occupancy)>),
    /// A planning event with the robot at this cell.
    Event(CellXy),
}

impl BeliefLog {
    /// Replay the drive's beliefs with the tuned A* alone, forward (robot to goal) and then
    /// backward (goal to robot), each in its own pass so that neither the planner driven nor
    /// the other direction shares the caches with it; check that the replay ends on the
    /// drive's final belief.
    fn replay(&self, goal: CellXy, opts: &NavigateOptions, last: &Belief) -> Result<ShadowAstar> {
        let mut total = ShadowAstar::default();
        for backward in [false, true] {
            let mut astar = PlannerKind::Astar
                .planner(opts.unknown_passable)
                .with_budget(opts.budget.clone());
            let mut grid = self.initial.clone();
            let (mut time_s, mut expanded) = (0.0, 0);
            for step in &self.steps {
                match step {
                    Logged::Changes(changes) => {
                        for &(c, o) in changes {
                            grid.set(c.x, c.y, o)?;
                        }
                    }
                    &Logged::Event(robot) => {
                        let (from, to) = if backward {
                            (goal, robot)
                        } else {
                            (robot, goal)
                        };
                        let t0 = Instant::now();
                        let planned = astar.plan(&grid, from, to)?;
                        time_s += t0.elapsed().as_secs_f64();
                        expanded += planned.best.as_ref().map_or(0, |b| b.stats.expanded);
                    }
                }
            }
            debug_assert!(
                grid.cells() == last.grid.cells(),
                "the belief log missed a change"
            );
            if backward {
                (total.backward_time_s, total.backward_expanded) = (time_s, expanded);
            } else {
                (total.forward_time_s, total.forward_expanded) = (time_s, expanded);
            }
        }
        Ok(total)
    }
}

impl Run<'_> {
    fn replan(&mut self, robot: CellXy) -> Result<Replanned> {
        if let Some(log) = &mut self.log {
            log.steps.push(Logged::Event(robot));
        }
        let t0 = Instant::now();
        match &mut self.online {
            Online::DStarLite(state) => {
                if state.is_none() {
                    let opts = DStarLiteOptions {
                        unknown_passable: self.opts.unknown_passable,
                        budget: self.opts.budget.clone(),
                        common_ties: self.opts.planner == OnlinePlanner::DStarLiteTies,
                    };
                    *state = Some(Box::new(DStarLite::new(
                        &self.belief.grid,
                        robot,
                        self.goal,
                        &opts,
                    )?));
                }
                let Some(planner) = state else {
                    return Err(PlanError::InconsistentSearch {
                        planner: "D* Lite",
                        x: robot.x,
                        y: robot.y,
                    });
                };
                planner.move_start(robot)?;
                let plan = planner.path()?;
                Ok(Replanned {
                    plan,
                    time_s: t0.elapsed().as_secs_f64(),
                    used_alternative: false,
                })
            }
            Online::AstarTies(search) => {
                let plan = search.search(
                    &self.belief.grid,
                    robot,
                    self.goal,
                    self.opts.unknown_passable,
                    &self.opts.budget,
                )?;
                Ok(Replanned {
                    plan,
                    time_s: t0.elapsed().as_secs_f64(),
                    used_alternative: false,
                })
            }
            Online::BuiltIn(planner) => {
                let planned = planner.plan(&self.belief.grid, robot, self.goal)?;
                let mut plan = planned.best;
                let mut used_alternative = false;
                if self.opts.planner == OnlinePlanner::Mbpp {
                    let view = Traversable::new(&self.belief.grid, self.opts.unknown_passable);
                    let mut best: Option<Vec<CellXy>> = None;
                    for candidate in &self.candidates {
                        let Some(joined) = join_candidate(&view, robot, candidate) else {
                            continue;
                        };
                        let length = path_length(&joined);
                        let bound = best.as_ref().map_or_else(
                            || plan.as_ref().map_or(f64::INFINITY, |p| p.length_cells),
                            |b| path_length(b),
                        );
                        if length <= bound + 1e-9 {
                            best = Some(joined);
                        }
                    }
                    self.candidates
                        .extend(planned.alternatives.into_iter().map(|p| p.waypoints));
                    let keep = crate::mbpp::DEFAULT_MAX_ALTERNATIVES;
                    if self.candidates.len() > keep {
                        let drop = self.candidates.len() - keep;
                        self.candidates.drain(..drop);
                    }
                    if let Some(waypoints) = best {
                        let stats = plan.as_ref().map(|p| p.stats).unwrap_or_default();
                        plan = Some(Plan {
                            length_cells: path_length(&waypoints),
                            waypoints,
                            stats,
                        });
                        used_alternative = true;
                    }
                }
                Ok(Replanned {
                    plan,
                    time_s: t0.elapsed().as_secs_f64(),
                    used_alternative,
                })
            }
        }
    }

    /// Believe free every cell the belief holds impassable that the sensor has never seen
    /// (the map's unverified obstacles), telling D* Lite; returns how many.
    fn doubt_unseen(&mut self, robot: CellXy) -> Result<usize> {
        let unknown_passable = self.opts.unknown_passable;
        let width = self.belief.grid.width();
        let mut changes = Vec::new();
        for (i, (&cell, &seen)) in self
            .belief
            .grid
            .cells()
            .iter()
            .zip(&self.belief.seen)
            .enumerate()
        {
            if !seen && !crate::los::cell_passable(cell, unknown_passable) && width > 0 {
                changes.push((CellXy::new(i % width, i / width), Occupancy::Free));
            }
        }
        for &(c, o) in &changes {
            self.belief.grid.set(c.x, c.y, o)?;
        }
        if !changes.is_empty() {
            self.observe(robot, &changes)?;
        }
        Ok(changes.len())
    }

    /// Tell D* Lite about a move and the changes sensed there (and log the changes when
    /// the belief is logged for the A* timed beside).
    fn observe(&mut self, robot: CellXy, changes: &[(CellXy, Occupancy)]) -> Result<()> {
        if let Some(log) = &mut self.log
            && !changes.is_empty()
        {
            log.steps.push(Logged::Changes(changes.to_vec()));
        }
        if let Online::DStarLite(Some(planner)) = &mut self.online {
            let t0 = Instant::now();
            planner.move_start(robot)?;
            planner.update_cells(changes)?;
            self.update_s += t0.elapsed().as_secs_f64();
        }
        Ok(())
    }
}

/// A kept MBPP alternative joined from `robot`: the robot goes straight to the last
/// waypoint it sees (on the belief) and follows the alternative on; `None` unless every
/// segment is clear.
fn join_candidate(
    view: &Traversable<'_>,
    robot: CellXy,
    candidate: &[CellXy],
) -> Option<Vec<CellXy>> {
    let at = candidate
        .iter()
        .rposition(|&w| line_of_sight(view, robot, w))?;
    let mut joined = vec![robot];
    joined.extend(candidate.get(at..)?.iter().copied().filter(|&w| w != robot));
    joined
        .windows(2)
        .all(|s| match s {
            [a, b] => line_of_sight(view, *a, *b),
            _ => true,
        })
        .then_some(joined)
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
    check_inputs(believed, truth, start, goal, opts)?;
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
