//! What [`mbpp`](super::mbpp) takes: its options and limits, and the test of the limits a run
//! looks at between its steps (its result, a [`Planned`](crate::Planned), and the records in
//! it live in `planned.rs`).

use crate::budget::Stop;
use crate::los::LosCounter;
use crate::planned::MbppStats;

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
    /// Most grid cells looked up by line-of-sight checks (the walk's, the selection's and
    /// the alternatives') before MBPP stops with
    /// [`PlanError::BudgetExhausted`](crate::PlanError::BudgetExhausted) (default
    /// [`DEFAULT_MAX_SIGHT_CELLS`](crate::budget::DEFAULT_MAX_SIGHT_CELLS)): on long
    /// zig-zag corridors these checks, not the bug steps, take the time.
    pub max_sight_cells: usize,
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
            max_sight_cells: crate::budget::DEFAULT_MAX_SIGHT_CELLS,
            stop: Stop::new(),
        }
    }
}

/// Whether the run must stop: a budget is spent or the [`Stop`](crate::budget::Stop) says
/// so (recorded in `stats`). Looked at between the walk, the selection's rounds and the
/// alternatives' checks.
pub(super) fn halted(opts: &MbppOptions, stats: &mut MbppStats, counter: &LosCounter) -> bool {
    if counter.cells > opts.max_sight_cells {
        stats.sight_budget_exhausted = true;
    }
    if stats.stopped.is_none() {
        stats.stopped = opts.stop.reason();
    }
    stats.budget_exhausted || stats.sight_budget_exhausted || stats.stopped.is_some()
}
