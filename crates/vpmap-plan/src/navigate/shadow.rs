//! The tuned repeated A* timed beside a drive
//! ([`navigate_with_astar_timed`](super::navigate_with_astar_timed)): its totals
//! ([`ShadowAstar`]), and the log of the drive's beliefs it is replayed on after the drive.

use std::time::Instant;

use crate::error::Result;
use crate::grid::{CellXy, Occupancy, OccupancyGrid};
use crate::planner::{Planner, PlannerKind};

use super::options::NavigateOptions;
use super::sensor::Belief;

/// The tuned repeated A* run on the belief of each planning event of a drive
/// ([`navigate_with_astar_timed`]), its plans not used: forward (robot to goal, as
/// [`OnlinePlanner::Astar`] plans) and backward (goal to robot, the direction D* Lite
/// searches in). Totals over the events. The beliefs are replayed after the drive from its
/// log of changes, each direction in a pass of its own, so that no search shares the caches
/// with the planner driven or with the other direction.
///
/// [`navigate_with_astar_timed`]: super::navigate_with_astar_timed
/// [`OnlinePlanner::Astar`]: super::OnlinePlanner::Astar
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

/// The belief as it was when planning started, and every change and planning event after
/// it in order: enough to rebuild the belief of every event after the drive.
pub(super) struct BeliefLog {
    pub(super) initial: OccupancyGrid,
    pub(super) steps: Vec<Logged>,
}

/// One entry of a [`BeliefLog`].
pub(super) enum Logged {
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
    pub(super) fn replay(
        &self,
        goal: CellXy,
        opts: &NavigateOptions,
        last: &Belief,
    ) -> Result<ShadowAstar> {
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
