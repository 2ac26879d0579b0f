//! Repeated A* under the common tie rule: the planner configuration that drives the same
//! track as D* Lite with [`DStarLiteOptions::common_ties`](crate::dstar_lite::DStarLiteOptions::common_ties).
//!
//! Costs are [`StepCost`]s: the octile length as exact step counts first, then the sum of
//! the [`tie_weight`]s of the cells the path enters (the robot's cell excluded, the goal
//! included: exactly what D* Lite's `g` of the robot's cell sums backwards). The heuristic
//! is the octile distance with weight 0, consistent for these lexicographic costs. The
//! optimum is then unique unless two equally short paths have equal weight sums, and A*
//! (forward, from the robot) and D* Lite (backward, from the goal) return the same path.
//! This is a plain A* (binary heap, lazy deletion): the project's tuned A*
//! ([`crate::astar`](mod@crate::astar)) stays the speed reference, with its own tie-break.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::budget::Budget;
use crate::dstar_lite::{StepCost, tie_weight};
use crate::error::Result;
use crate::grid::{CellXy, OccupancyGrid};
use crate::grid::{DIAGONAL_SIDES, MOVES};
use crate::los::fill_padded;
use crate::plan::{Plan, PlanStats, check_endpoint};

/// No parent.
const NO_PARENT: u32 = u32::MAX;

/// A reusable A* search under the common tie rule (see the [module docs](self)).
#[derive(Clone, Debug, Default)]
pub(crate) struct TieAstar {
    passable: Vec<bool>,
    g: Vec<StepCost>,
    parent: Vec<u32>,
    closed: Vec<bool>,
    heap: BinaryHeap<Reverse<(StepCost, u32)>>,
}

impl TieAstar {
    /// A shortest path from `start` to `goal` on `grid` under the common tie rule (every
    /// cell, like [`astar`](crate::astar::astar)); `Ok(None)` when there is none.
    pub(crate) fn search(
        &mut self,
        grid: &OccupancyGrid,
        start: CellXy,
        goal: CellXy,
        unknown_passable: bool,
        budget: &Budget,
    ) -> Result<Option<Plan>> {
        check_endpoint(grid, "start", start, unknown_passable)?;
        check_endpoint(grid, "goal", goal, unknown_passable)?;
        budget.stop.check("A* (common ties)")?;
        let pw = grid.width() + 2;
        fill_padded(grid, unknown_passable, &mut self.passable, false, true);
        let n = self.passable.len();
        self.g.clear();
        self.g.resize(n, StepCost::INF);
        self.parent.clear();
        self.parent.resize(n, NO_PARENT);
        self.closed.clear();
        self.closed.resize(n, false);
        self.heap.clear();
        let pad = |c: CellXy| (c.y + 1) * pw + c.x + 1;
        let (s, t) = (pad(start), pad(goal));
        let h = |i: usize| StepCost::octile((i % pw).abs_diff(t % pw), (i / pw).abs_diff(t / pw));
        let deltas: [isize; 8] = std::array::from_fn(|k| MOVES[k].1 * pw as isize + MOVES[k].0);
        let mut stats = PlanStats::default();
        if let Some(g) = self.g.get_mut(s) {
            *g = StepCost::ZERO;
        }
        self.heap.push(Reverse((h(s), s as u32)));
        stats.generated += 1;
        let pass = |p: &[bool], i: usize| p.get(i).copied().unwrap_or(false);
        while let Some(Reverse((_, u))) = self.heap.pop() {
            let u = u as usize;
            if self.closed.get(u).copied().unwrap_or(true) {
                continue;
            }
            if let Some(c) = self.closed.get_mut(u) {
                *c = true;
            }
            stats.expanded += 1;
            budget.check("A* (common ties)", stats.expanded, 0, stats.expanded)?;
            let g_u = self.g.get(u).copied().unwrap_or(StepCost::INF);
            if u == t {
                let mut waypoints = Vec::new();
                let mut at = u;
                for _ in 0..=n {
                    waypoints.push(CellXy::new(at % pw - 1, at / pw - 1));
                    match self.parent.get(at) {
                        Some(&p) if p != NO_PARENT => at = p as usize,
                        _ => break,
                    }
                }
                waypoints.reverse();
                return Ok(Some(Plan {
                    waypoints,
                    length_cells: g_u.length(),
                    stats,
                }));
            }
            for k in 0..8 {
                let v = u.wrapping_add_signed(deltas[k]);
                if !pass(&self.passable, v) || self.closed.get(v).copied().unwrap_or(true) {
                    continue;
                }
                let diagonal = k >= 4;
                if let Some(&(a, b)) = k.checked_sub(4).and_then(|i| DIAGONAL_SIDES.get(i))
                    && !(pass(&self.passable, u.wrapping_add_signed(deltas[a]))
                        && pass(&self.passable, u.wrapping_add_signed(deltas[b])))
                {
                    continue;
                }
                let w = tie_weight(v % pw - 1, v / pw - 1);
                let g_v = g_u.add(StepCost::step(diagonal, w));
                if self.g.get(v).is_some_and(|&old| g_v < old) {
                    if let Some(slot) = self.g.get_mut(v) {
                        *slot = g_v;
                    }
                    if let Some(slot) = self.parent.get_mut(v) {
                        *slot = u as u32;
                    }
                    self.heap.push(Reverse((g_v.add(h(v)), v as u32)));
                    stats.generated += 1;
                }
            }
        }
        Ok(None)
    }
}
