//! How much work a planner may do: [`Budget`] (counted work: expansions and line-of-sight
//! cells) and [`Stop`] (a deadline or a cancellation flag, checked as the search runs).
//!
//! Every planner takes a budget in its options and returns a distinct error when it is
//! reached: [`PlanError::BudgetExhausted`] for counted
//! work (the same input always stops at the same point) and
//! [`PlanError::Stopped`] for a deadline or a cancellation (wall
//! time; a server sets the flag when its client has gone). The defaults are generous but
//! finite; `docs/limits.md` lists them with their options.
//!
//! # Example
//! ```
//! use std::sync::{Arc, atomic::{AtomicBool, Ordering}};
//! use vpmap_plan::{Occupancy, OccupancyGrid, PlanError};
//! use vpmap_plan::budget::{Budget, Stop, StopReason};
//! use vpmap_plan::theta_star::{theta_star, ThetaStarOptions};
//! let grid = OccupancyGrid::new(200, 200, 1.0, [0.0; 2], Occupancy::Free).unwrap();
//! let cancelled = Arc::new(AtomicBool::new(false));
//! let opts = ThetaStarOptions {
//!     budget: Budget { stop: Stop::new().with_flag(cancelled.clone()), ..Budget::default() },
//!     ..ThetaStarOptions::default()
//! };
//! assert!(theta_star(&grid, (0, 0), (199, 150), &opts).unwrap().is_some());
//! cancelled.store(true, Ordering::Relaxed); // the client went away
//! let err = theta_star(&grid, (0, 0), (199, 150), &opts).unwrap_err();
//! assert!(matches!(err, PlanError::Stopped { reason: StopReason::Cancelled, .. }));
//! ```

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

pub use crate::stop_reason::StopReason;

use crate::error::{PlanError, Result};

/// The default of [`Budget::max_expansions`]: 200 million node expansions (at least every
/// cell of the largest grid once; a few tens of seconds of A*).
pub const DEFAULT_MAX_EXPANSIONS: usize = 200_000_000;

/// The default of [`Budget::max_sight_cells`] (and of MBPP's): 2 billion cells looked up by
/// line-of-sight queries, about 10 s on the project's machine. The benchmark's hardest query
/// (the exact planner on `maze512-2-5`) looks up 1.44 billion.
pub const DEFAULT_MAX_SIGHT_CELLS: usize = 2_000_000_000;

/// How often, in units of counted work, a search looks at its [`Stop`] (reading the clock
/// costs about as much as a few expansions).
pub(crate) const STOP_CHECK_INTERVAL: usize = 4096;

/// A planner's work budget (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct Budget {
    /// Most nodes a search expands (A*, A* PS's A*, Theta*, the exact planner) before it
    /// stops with [`PlanError::BudgetExhausted`] (default [`DEFAULT_MAX_EXPANSIONS`]).
    pub max_expansions: usize,
    /// Most grid cells its line-of-sight queries look up (Theta*, A* PS's smoothing, the
    /// exact planner, MBPP through [`BuiltIn`](crate::planner::BuiltIn)) before it stops with [`PlanError::BudgetExhausted`] (default
    /// [`DEFAULT_MAX_SIGHT_CELLS`]).
    pub max_sight_cells: usize,
    /// A deadline or cancellation flag (default: none).
    pub stop: Stop,
}

impl Default for Budget {
    fn default() -> Self {
        Self {
            max_expansions: DEFAULT_MAX_EXPANSIONS,
            max_sight_cells: DEFAULT_MAX_SIGHT_CELLS,
            stop: Stop::new(),
        }
    }
}

impl Budget {
    /// `Err` when `expanded` nodes or `sight_cells` looked-up cells are over the budget, or
    /// when the [`Stop`] says so; `planner` names the planner in the error. The stop is only
    /// looked at when `tick` (a counter of the caller's work) is a multiple of
    /// [`STOP_CHECK_INTERVAL`].
    pub(crate) fn check(
        &self,
        planner: &'static str,
        expanded: usize,
        sight_cells: usize,
        tick: usize,
    ) -> Result<()> {
        if expanded > self.max_expansions {
            return Err(PlanError::BudgetExhausted {
                planner,
                what: "node expansions",
                limit: self.max_expansions,
                option: "max_expansions",
            });
        }
        if sight_cells > self.max_sight_cells {
            return Err(PlanError::BudgetExhausted {
                planner,
                what: "cells looked up by line-of-sight checks",
                limit: self.max_sight_cells,
                option: "max_sight_cells",
            });
        }
        if tick.is_multiple_of(STOP_CHECK_INTERVAL) {
            self.stop.check(planner)?;
        }
        Ok(())
    }
}

/// A deadline and a cancellation flag a running planner looks at every few thousand
/// expansions (see the [module docs](self)). The default never stops.
#[derive(Clone, Debug, Default)]
pub struct Stop {
    /// When to stop, with the time allowed (for the message), seconds.
    deadline: Option<(Instant, f64)>,
    /// Stop once this is `true`.
    flag: Option<Arc<AtomicBool>>,
}

impl PartialEq for Stop {
    /// Equal when the deadlines are equal and the flags are the same flag.
    fn eq(&self, other: &Self) -> bool {
        let same_flag = match (&self.flag, &other.flag) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        };
        same_flag && self.deadline.map(|d| d.0) == other.deadline.map(|d| d.0)
    }
}

impl Stop {
    /// A stop that never stops.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            deadline: None,
            flag: None,
        }
    }

    /// Stop `timeout` from now.
    #[must_use]
    pub fn with_timeout(mut self, timeout: Duration) -> Self {
        let now = Instant::now();
        let deadline = now.checked_add(timeout);
        self.deadline = deadline.map(|d| (d, timeout.as_secs_f64()));
        self
    }

    /// Stop at `deadline`.
    #[must_use]
    pub fn with_deadline(mut self, deadline: Instant) -> Self {
        let allowed_s = deadline
            .saturating_duration_since(Instant::now())
            .as_secs_f64();
        self.deadline = Some((deadline, allowed_s));
        self
    }

    /// Stop once `flag` is `true` (set it from another thread, e.g. when a client has gone).
    #[must_use]
    pub fn with_flag(mut self, flag: Arc<AtomicBool>) -> Self {
        self.flag = Some(flag);
        self
    }

    /// Why to stop now, if at all.
    #[must_use]
    pub fn reason(&self) -> Option<StopReason> {
        if self
            .flag
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed))
        {
            return Some(StopReason::Cancelled);
        }
        match self.deadline {
            Some((deadline, _)) if Instant::now() >= deadline => Some(StopReason::Deadline),
            _ => None,
        }
    }

    /// The time the deadline allows, seconds (0 without a deadline).
    #[must_use]
    pub fn allowed_s(&self) -> f64 {
        self.deadline.map_or(0.0, |d| d.1)
    }

    /// `Err(PlanError::Stopped)` naming `planner` when [`Self::reason`] says to stop.
    ///
    /// # Errors
    /// [`PlanError::Stopped`] when the deadline has passed or the flag is set.
    pub fn check(&self, planner: &'static str) -> Result<()> {
        match self.reason() {
            None => Ok(()),
            Some(reason) => Err(PlanError::Stopped {
                planner,
                reason,
                allowed_s: self.allowed_s(),
            }),
        }
    }
}
