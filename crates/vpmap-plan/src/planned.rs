//! What a planner returns for one query ([`Planned`]): the path, the other feasible paths,
//! and MBPP's records of its bugs ([`BugTrack`], [`BugFate`]) and its counters
//! ([`MbppStats`]). Shared by [`crate::planner`], which re-exports [`Planned`], and
//! [`crate::mbpp`](mod@crate::mbpp), which returns it and re-exports the records.

use crate::budget::StopReason;
use crate::grid::CellXy;
use crate::plan::Plan;

/// What a planner returns for one query (also what [`mbpp`](crate::mbpp::mbpp) returns).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Planned {
    /// The path, or `None` when the goal cannot be reached from the start. MBPP's is the
    /// shortest feasible path after smoothing; its statistics count bug steps as `expanded`
    /// and bugs as `generated`.
    pub best: Option<Plan>,
    /// Other feasible paths the planner found (empty for all but MBPP). MBPP's: the
    /// `v_list`s of the bugs that reached the goal and of the waiting bugs completed from
    /// them whose segments are all clear, unsmoothed, shortest first, without duplicates or
    /// the path `best` was smoothed from.
    pub alternatives: Vec<Plan>,
    /// MBPP's bugs of the top-level run, in order of birth (tracks only when asked for;
    /// empty for the other planners).
    pub bugs: Vec<BugTrack>,
    /// MBPP's counters (zero for the other planners).
    pub mbpp_stats: MbppStats,
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
    /// [`MbppOptions::record_tracks`](crate::mbpp::MbppOptions::record_tracks) is set).
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

/// Work counters of [`mbpp`](crate::mbpp::mbpp) (including nested re-planning runs).
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
    /// The walk stopped at
    /// [`MbppOptions::max_bug_steps`](crate::mbpp::MbppOptions::max_bug_steps) (then
    /// [`mbpp`](crate::mbpp::mbpp) returns an error instead of a result).
    pub budget_exhausted: bool,
    /// The run stopped at
    /// [`MbppOptions::max_sight_cells`](crate::mbpp::MbppOptions::max_sight_cells) (then
    /// [`mbpp`](crate::mbpp::mbpp) returns an error instead of a result).
    pub sight_budget_exhausted: bool,
    /// The walk was stopped by [`MbppOptions::stop`](crate::mbpp::MbppOptions::stop) (then
    /// [`mbpp`](crate::mbpp::mbpp) returns an error instead of a result).
    pub stopped: Option<StopReason>,
}
