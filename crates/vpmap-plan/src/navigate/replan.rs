//! The planner side of a drive: the state of the planner it re-plans with ([`Online`]), a
//! re-plan with each of them (online MBPP joining its kept alternatives), doubting the map's
//! unseen obstacles, and telling D* Lite about moves and sensed changes.

use std::time::Instant;

use crate::dstar_lite::{DStarLite, DStarLiteOptions};
use crate::error::{PlanError, Result};
use crate::grid::{CellXy, Occupancy};
use crate::los::{Traversable, line_of_sight};
use crate::plan::{Plan, path_length};
use crate::planner::{BuiltIn, Planner};

use super::options::{NavigateOptions, OnlinePlanner};
use super::sensor::Belief;
use super::shadow::{BeliefLog, Logged};
use super::ties::TieAstar;

/// The planner state of a run.
pub(super) enum Online {
    /// A*, A* PS or MBPP through the planner interface.
    BuiltIn(Box<BuiltIn>),
    /// D* Lite, created at the first plan.
    DStarLite(Option<Box<DStarLite>>),
    /// A* under the common tie rule.
    AstarTies(Box<TieAstar>),
}

/// What a re-plan produced.
pub(super) struct Replanned {
    pub(super) plan: Option<Plan>,
    pub(super) time_s: f64,
    pub(super) used_alternative: bool,
}

/// A drive's planner state: the goal, the belief, the planner and its bookkeeping.
pub(super) struct Run<'a> {
    pub(super) goal: CellXy,
    pub(super) opts: &'a NavigateOptions,
    pub(super) belief: Belief,
    pub(super) online: Online,
    /// Online MBPP's kept alternatives.
    pub(super) candidates: Vec<Vec<CellXy>>,
    /// D* Lite's bookkeeping time, seconds.
    pub(super) update_s: f64,
    /// With the A* timed beside
    /// ([`navigate_with_astar_timed`](super::navigate_with_astar_timed)): the belief's
    /// history, to replay after the drive.
    pub(super) log: Option<BeliefLog>,
}

impl Run<'_> {
    /// Plan from `robot` on the current belief (a planning event).
    pub(super) fn replan(&mut self, robot: CellXy) -> Result<Replanned> {
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
    pub(super) fn doubt_unseen(&mut self, robot: CellXy) -> Result<usize> {
        let changes = self.belief.doubt_unseen(self.opts.unknown_passable)?;
        if !changes.is_empty() {
            self.observe(robot, &changes)?;
        }
        Ok(changes.len())
    }

    /// Tell D* Lite about a move and the changes sensed there (and log the changes when
    /// the belief is logged for the A* timed beside).
    pub(super) fn observe(&mut self, robot: CellXy, changes: &[(CellXy, Occupancy)]) -> Result<()> {
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
