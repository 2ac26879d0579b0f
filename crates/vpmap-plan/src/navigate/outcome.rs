//! What a drive gives: how it ended ([`Outcome`]), its planning events ([`ReplanEvent`]) and
//! the whole run ([`Navigation`]); and the optimum on the true map to compare it with
//! ([`TruthOptimum`]).

use crate::grid::CellXy;

use super::sensor::Belief;
use super::shadow::ShadowAstar;

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
    /// [`NavigateOptions::max_moves`](super::NavigateOptions::max_moves) reached.
    MoveLimit,
    /// [`NavigateOptions::max_replans`](super::NavigateOptions::max_replans) reached.
    ReplanLimit,
    /// The smooth planner ([`navigate_smooth`](super::navigate_smooth)) found no drivable
    /// path from the robot's pose, even with the map's unseen obstacles doubted (e.g. a wall
    /// seen too late to turn before it); the path's reason is in
    /// [`SmoothNavigation::reason`](super::SmoothNavigation::reason).
    NoDrivablePath,
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
            Self::NoDrivablePath => "no drivable path from the robot's pose",
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

/// The result of [`navigate`](super::navigate).
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
    ///
    /// [`navigate_with_astar_timed`]: super::navigate_with_astar_timed
    /// [`OnlinePlanner::Astar`]: super::OnlinePlanner::Astar
    pub shadow_astar: Option<ShadowAstar>,
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
