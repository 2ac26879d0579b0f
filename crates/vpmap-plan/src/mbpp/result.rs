//! What [`mbpp`](super::mbpp) takes and records: options, the bugs' records and the work
//! counters (its result is a [`Planned`](crate::Planned)).

use super::Xy;
use super::to_u;
use crate::budget::{Stop, StopReason};
use crate::grid::CellXy;

/// Options of [`mbpp`](super::mbpp).
#[derive(Clone, Debug, PartialEq)]
pub struct MbppOptions {
    /// Whether [`Occupancy::Unknown`](crate::Occupancy::Unknown) cells may be entered (default: no).
    pub unknown_passable: bool,
    /// Record every bug's track (the cells it walked) in [`Planned::bugs`](crate::Planned::bugs) (default: no; it
    /// costs memory proportional to the bugs' steps).
    pub record_tracks: bool,
    /// How deeply re-planning may nest (default 4).
    pub max_replan_depth: usize,
    /// When a wall-following bug leaves the wall (default: the thesis's m-line rule).
    pub leave: LeaveRule,
    /// Most bug steps (all bugs, all re-planning runs together) before MBPP stops with
    /// [`PlanError::BudgetExhausted`](crate::PlanError::BudgetExhausted) (default
    /// [`DEFAULT_MAX_BUG_STEPS`]): a zig-zag floor can make bugs multiply without end.
    pub max_bug_steps: usize,
    /// Most alternative paths kept, the shortest first (default [`DEFAULT_MAX_ALTERNATIVES`]).
    pub max_alternatives: usize,
    /// A deadline or cancellation flag, looked at every few thousand bug steps; when it
    /// stops the walk MBPP returns [`PlanError::Stopped`](crate::PlanError::Stopped)
    /// (default: none).
    pub stop: Stop,
}

/// The default of [`MbppOptions::max_bug_steps`]: 200 million steps, about a minute of work
/// on the project's machine (the benchmark's largest maps take under 10 million).
pub const DEFAULT_MAX_BUG_STEPS: usize = 200_000_000;

/// The default of [`MbppOptions::max_alternatives`].
pub const DEFAULT_MAX_ALTERNATIVES: usize = 1000;

/// When a wall-following bug leaves the wall for greedy moves (condition C2(a)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LeaveRule {
    /// The thesis's rule: on meeting the start-goal m-line again, further along it than the
    /// hit (Bug2). Greedy moves follow the m-line.
    #[default]
    MLine,
    /// As soon as the bug is closer to the goal than at its hit (the leave rule of
    /// DistBug-like bug algorithms); greedy moves then follow a new straight line from the
    /// leave cell to the goal. Shorter tracks, more bugs; see `docs/mbpp.md` for the
    /// comparison.
    Closer,
}

impl Default for MbppOptions {
    fn default() -> Self {
        Self {
            unknown_passable: false,
            record_tracks: false,
            max_replan_depth: 4,
            leave: LeaveRule::MLine,
            max_bug_steps: DEFAULT_MAX_BUG_STEPS,
            max_alternatives: DEFAULT_MAX_ALTERNATIVES,
            stop: Stop::new(),
        }
    }
}

/// How a bug's travel ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BugFate {
    /// It reached the goal.
    ReachedGoal,
    /// It stood on an m-line cell another bug had walked greedily and waited there (C3);
    /// its `v_list` is completed from that bug's.
    Waiting,
    /// Its wall walk repeated a state without meeting the m-line beyond its hit (C1(b)).
    Looped,
    /// It could not move at all (C1(a)).
    Stuck,
}

/// One bug's life, for drawing and statistics.
#[derive(Clone, Debug, PartialEq)]
pub struct BugTrack {
    /// The bug that gave birth to it (`None` for the first bug).
    pub parent: Option<usize>,
    /// The cells it walked, from its birth cell (empty unless
    /// [`MbppOptions::record_tracks`] is set).
    pub cells: Vec<CellXy>,
    /// Where it hit obstacles (its `hit_list`).
    pub hits: Vec<CellXy>,
    /// Where it left walls for the m-line (its `leave_list`).
    pub leaves: Vec<CellXy>,
    /// Steps it took.
    pub steps: usize,
    /// How it ended.
    pub fate: BugFate,
}

impl BugTrack {
    /// A bug's record at birth on `cell` (its track holds `cell` when `record`).
    pub(super) fn born(parent: Option<usize>, cell: Xy, record: bool, fate: BugFate) -> Self {
        Self {
            parent,
            cells: if record { vec![to_u(cell)] } else { Vec::new() },
            hits: Vec::new(),
            leaves: Vec::new(),
            steps: 0,
            fate,
        }
    }
}

/// Work counters of [`mbpp`](super::mbpp) (including nested re-planning runs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct MbppStats {
    /// Bugs born, the first one included.
    pub bugs: usize,
    /// Steps taken by all bugs.
    pub bug_steps: usize,
    /// Obstacle hits.
    pub hits: usize,
    /// Bugs that waited (C3).
    pub waits: usize,
    /// Line-of-sight queries (during the walk, the final check and the smoothing).
    pub los_checks: usize,
    /// Cells looked up by those queries.
    pub los_cells: usize,
    /// Blocked segments re-planned.
    pub replans: usize,
    /// The walk stopped at [`MbppOptions::max_bug_steps`] (then [`mbpp`](super::mbpp)
    /// returns an error instead of a result).
    pub budget_exhausted: bool,
    /// The walk was stopped by [`MbppOptions::stop`] (then [`mbpp`](super::mbpp) returns
    /// an error instead of a result).
    pub stopped: Option<StopReason>,
}
