//! One interface over every planner: [`Planner`], its result [`Planned`], and
//! [`PlannerKind`], the built-in planners by name.
//!
//! # Example
//! ```
//! use vpmap_plan::{Occupancy, OccupancyGrid, planner::{Planner, PlannerKind}};
//! let mut grid = OccupancyGrid::new(8, 5, 1.0, [0.0; 2], Occupancy::Free).unwrap();
//! for y in 0..4 {
//!     grid.set(4, y, Occupancy::Occupied).unwrap();
//! }
//! let mut lengths = Vec::new();
//! for kind in PlannerKind::ALL {
//!     let mut planner = kind.planner(false);
//!     let planned = planner.plan(&grid, (0, 0).into(), (7, 0).into()).unwrap();
//!     lengths.push((planner.name(), planned.best.unwrap().length_cells));
//! }
//! let optimal = lengths.iter().find(|(name, _)| *name == "optimal").unwrap().1;
//! assert!(lengths.iter().all(|&(_, length)| length >= optimal - 1e-9));
//! ```

use std::fmt;
use std::str::FromStr;

pub use crate::planned::Planned;

use crate::anya::ExactPlanner;
use crate::astar::{AstarOptions, AstarSearch};
use crate::budget::{Budget, Stop};
use crate::error::{PlanError, Result};
use crate::grid::{CellXy, OccupancyGrid};
use crate::mbpp::{LeaveRule, MbppOptions, mbpp};
use crate::smoothing::{AstarPsOptions, astar_ps};
use crate::theta_star::{ThetaStarOptions, theta_star};

/// A path planner on occupancy grids: start and goal are cells `(x, y)`.
pub trait Planner {
    /// The planner's short name (`astar`, `astar-ps`, `theta-star`, `mbpp`, `optimal`).
    fn name(&self) -> &'static str;

    /// Plan from `start` to `goal`.
    ///
    /// # Errors
    /// When `start` or `goal` is outside the grid or not traversable.
    fn plan(&mut self, grid: &OccupancyGrid, start: CellXy, goal: CellXy) -> Result<Planned>;
}

/// The built-in planners.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PlannerKind {
    /// Multi-Bug Path Planning with the thesis's m-line leave rule ([`crate::mbpp`](mod@crate::mbpp)).
    Mbpp,
    /// MBPP leaving walls as soon as it is closer to the goal than at the hit
    /// ([`LeaveRule::Closer`]).
    MbppCloser,
    /// A* with line-of-sight post-smoothing ([`crate::smoothing`]).
    AstarPs,
    /// Basic Theta* ([`crate::theta_star`](mod@crate::theta_star)).
    ThetaStar,
    /// 8-connected octile A* ([`crate::astar`](mod@crate::astar)).
    Astar,
    /// The exact shortest any-angle path ([`crate::optimal`], by [`crate::anya`]).
    Optimal,
}

impl PlannerKind {
    /// Every built-in planner.
    pub const ALL: [Self; 6] = [
        Self::Mbpp,
        Self::MbppCloser,
        Self::AstarPs,
        Self::ThetaStar,
        Self::Astar,
        Self::Optimal,
    ];

    /// The planner's name (also what [`FromStr`] reads).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Mbpp => "mbpp",
            Self::MbppCloser => "mbpp-closer",
            Self::AstarPs => "astar-ps",
            Self::ThetaStar => "theta-star",
            Self::Astar => "astar",
            Self::Optimal => "optimal",
        }
    }

    /// A planner of this kind; `unknown_passable` lets paths cross unknown cells.
    #[must_use]
    pub fn planner(self, unknown_passable: bool) -> BuiltIn {
        BuiltIn {
            kind: self,
            unknown_passable,
            record_tracks: false,
            mbpp_budget: (
                crate::mbpp::DEFAULT_MAX_BUG_STEPS,
                crate::mbpp::DEFAULT_MAX_ALTERNATIVES,
            ),
            budget: Budget::default(),
            search: AstarSearch::new(),
            exact: None,
        }
    }
}

impl fmt::Display for PlannerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for PlannerKind {
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

/// A built-in planner (see [`PlannerKind::planner`]). A* reuses its search arrays between
/// queries (the calling thread's on grids of up to 2 Mi cells, so that a planner made for
/// one query allocates none, its own on larger ones); the exact planner keeps its [`ExactPlanner`] (the grid's free space) while the
/// grid and `unknown_passable` stay the same (compared cell by cell at each query).
#[derive(Clone, Debug)]
pub struct BuiltIn {
    kind: PlannerKind,
    unknown_passable: bool,
    record_tracks: bool,
    mbpp_budget: (usize, usize),
    budget: Budget,
    search: AstarSearch,
    exact: Option<ExactPlanner>,
}

impl BuiltIn {
    /// MBPP's work budget: most bug steps and most alternatives kept (defaults
    /// [`crate::mbpp::DEFAULT_MAX_BUG_STEPS`], [`crate::mbpp::DEFAULT_MAX_ALTERNATIVES`]).
    #[must_use]
    pub fn with_mbpp_budget(mut self, max_bug_steps: usize, max_alternatives: usize) -> Self {
        self.mbpp_budget = (max_bug_steps, max_alternatives);
        self
    }

    /// The work budget of A*, A* PS, Theta* and the exact planner, and the [`Stop`] of
    /// every planner, MBPP included (default [`Budget::default`]).
    #[must_use]
    pub fn with_budget(mut self, budget: Budget) -> Self {
        self.budget = budget;
        self
    }

    /// Most node expansions of A*, A* PS, Theta* and the exact planner
    /// ([`Budget::max_expansions`]).
    #[must_use]
    pub fn with_max_expansions(mut self, max_expansions: usize) -> Self {
        self.budget.max_expansions = max_expansions;
        self
    }

    /// A deadline or cancellation flag for every planner ([`Budget::stop`]).
    #[must_use]
    pub fn with_stop(mut self, stop: Stop) -> Self {
        self.budget.stop = stop;
        self
    }

    /// Record MBPP's bug tracks (for drawing); off by default.
    #[must_use]
    pub fn with_tracks(mut self, record_tracks: bool) -> Self {
        self.record_tracks = record_tracks;
        self
    }

    /// Which planner this is.
    #[must_use]
    pub fn kind(&self) -> PlannerKind {
        self.kind
    }
}

impl Planner for BuiltIn {
    fn name(&self) -> &'static str {
        self.kind.name()
    }

    fn plan(&mut self, grid: &OccupancyGrid, start: CellXy, goal: CellXy) -> Result<Planned> {
        let unknown_passable = self.unknown_passable;
        let best = match self.kind {
            PlannerKind::Mbpp | PlannerKind::MbppCloser => {
                let leave = if self.kind == PlannerKind::Mbpp {
                    LeaveRule::MLine
                } else {
                    LeaveRule::Closer
                };
                let opts = MbppOptions {
                    unknown_passable,
                    record_tracks: self.record_tracks,
                    leave,
                    max_bug_steps: self.mbpp_budget.0,
                    max_alternatives: self.mbpp_budget.1,
                    max_sight_cells: self.budget.max_sight_cells,
                    stop: self.budget.stop.clone(),
                    ..MbppOptions::default()
                };
                return mbpp(grid, start, goal, &opts);
            }
            PlannerKind::AstarPs => {
                let opts = AstarPsOptions {
                    unknown_passable,
                    budget: self.budget.clone(),
                };
                astar_ps(grid, start, goal, &opts)?
            }
            PlannerKind::ThetaStar => {
                let opts = ThetaStarOptions {
                    unknown_passable,
                    budget: self.budget.clone(),
                };
                theta_star(grid, start, goal, &opts)?
            }
            PlannerKind::Astar => {
                let opts = AstarOptions {
                    unknown_passable,
                    budget: self.budget.clone(),
                };
                // A planner made for one query (as `vpmap.plan` makes it) borrows the
                // thread's A* arrays instead of allocating its own.
                self.search
                    .or_thread_search(grid, |search| search.search(grid, start, goal, &opts))?
            }
            PlannerKind::Optimal => {
                let exact = match &mut self.exact {
                    Some(exact) if exact.is_for(grid, unknown_passable) => exact,
                    slot => slot.insert(ExactPlanner::new(grid, unknown_passable)),
                };
                exact.plan(start, goal, &self.budget)?
            }
        };
        Ok(Planned {
            best,
            ..Planned::default()
        })
    }
}
