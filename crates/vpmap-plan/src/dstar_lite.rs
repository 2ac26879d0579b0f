//! D* Lite: incremental re-planning on the 8-connected grid, for a robot that learns the
//! map as it moves (Koenig and Likhachev 2002, the optimized version of their Figure 4).
//!
//! Semantics: exactly the grid model of [`crate::astar`](mod@crate::astar). The robot moves
//! between the centres of 8-neighbouring passable cells; a straight step costs 1 and needs
//! both its cells passable, a diagonal step costs `sqrt 2` and needs both its cells **and
//! both orthogonal neighbours** passable (no corner cutting). Passable is
//! [`cell_passable`]: [`Occupancy::Free`], and
//! [`Occupancy::Unknown`] with [`DStarLiteOptions::unknown_passable`]. Step costs are
//! symmetric, so every cell's predecessors are its successors (its 8 neighbours). A cell
//! changing passability changes the costs of the 8 steps into and out of it, and of the 4
//! diagonal steps between its orthogonal neighbours that cut past it.
//!
//! The search runs backwards from the goal: `g(s)` and `rhs(s)` are costs from `s` to the
//! goal, the heuristic is the octile distance from the robot's cell (consistent), and the
//! priority queue holds the locally inconsistent cells (`g != rhs`) keyed by
//! `[min(g, rhs) + h(start, s) + k_m; min(g, rhs)]`, compared lexicographically. When the
//! robot moves and cells change, `k_m` grows by the heuristic distance moved since the last
//! change, so queued keys stay lower bounds and need no re-sorting. [`DStarLite::path`]
//! follows `argmin c(s, s') + g(s')` from the robot's cell: a shortest path on the current
//! map, of the same cost as a fresh A* on it.
//!
//! The queue is a binary heap with lazy deletion: a cell's entry is valid while it carries
//! the cell's current stamp, so "update" and "remove" are a push and a stamp change.
//! Costs and keys are `f64` sums of `1` and `sqrt 2`; the length of a returned plan is
//! recomputed from its straight and diagonal step counts, so it is exact like A*'s.
//!
//! Why not a crate: no Rust crate on docs.rs implements D* Lite on this grid model (no
//! corner cutting, unknown cells as an option) with the project's [`Budget`] and error
//! style; the generic graph implementations (e.g. gonum's in Go) would need the grid as an
//! explicit graph with per-edge updates. The algorithm is short enough to write to the
//! paper and test against repeated A* (`tests/it/dstar_lite.rs`).
//!
//! # Example
//! ```
//! use vpmap_plan::{CellXy, Occupancy, OccupancyGrid};
//! use vpmap_plan::dstar_lite::{DStarLite, DStarLiteOptions};
//! let grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
//! let mut planner = DStarLite::new(&grid, (0, 1), (4, 1), &DStarLiteOptions::default()).unwrap();
//! assert_eq!(planner.path().unwrap().unwrap().length_cells, 4.0);
//! // The robot learns that (2, 1) is blocked: the path bends around it.
//! planner.update_cells(&[(CellXy::new(2, 1), Occupancy::Occupied)]).unwrap();
//! let plan = planner.path().unwrap().unwrap();
//! assert!((plan.length_cells - 2.0 - 2.0 * std::f64::consts::SQRT_2).abs() < 1e-12);
//! // It moves one step and plans on from there, reusing the search.
//! planner.move_start((1, 0)).unwrap();
//! assert!((planner.path().unwrap().unwrap().length_cells - 2.0 - std::f64::consts::SQRT_2).abs() < 1e-12);
//! ```
//!
//! # References
//! S. Koenig, M. Likhachev, "D* Lite", AAAI 2002 (Figure 4, the optimized version); also
//! "Fast Replanning for Navigation in Unknown Terrain", IEEE Transactions on Robotics
//! 21(3), 2005.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::f64::consts::SQRT_2;

use crate::budget::Budget;
use crate::error::{PlanError, Result};
use crate::grid::{CellXy, Occupancy, OccupancyGrid};
use crate::los::{cell_passable, fill_padded};
use crate::plan::{Plan, PlanStats, check_endpoint, xy};

/// Options of [`DStarLite`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DStarLiteOptions {
    /// Whether [`Occupancy::Unknown`] cells may be entered (default: no).
    pub unknown_passable: bool,
    /// Most expansions one [`DStarLite::path`] call may make (its re-planning), and the
    /// [`Stop`](crate::budget::Stop) it looks at (default: [`Budget::default`]).
    pub budget: Budget,
}

/// Per-cell search state.
#[derive(Clone, Copy, Debug)]
struct Node {
    /// Cost-to-goal estimate, cells.
    g: f64,
    /// One-step lookahead `min c(s, s') + g(s')` (0 at the goal), cells.
    rhs: f64,
    /// Stamp of the cell's valid queue entry (entries with another stamp are stale).
    stamp: u32,
    /// Whether the cell is in the queue.
    queued: bool,
}

impl Default for Node {
    fn default() -> Self {
        Self {
            g: f64::INFINITY,
            rhs: f64::INFINITY,
            stamp: 0,
            queued: false,
        }
    }
}

/// A queue key `[k1; k2]` as ordered bits (both non-negative, so their IEEE bit patterns
/// order like the values), then the cell and its stamp.
type Entry = Reverse<(u64, u64, u32, u32)>;

/// Index deltas of the 8 moves in padded cells are built from these: E, S, W, N, SE, SW,
/// NW, NE.
const MOVE_DX: [isize; 8] = [1, 0, -1, 0, 1, -1, -1, 1];
/// See [`MOVE_DX`].
const MOVE_DY: [isize; 8] = [0, 1, 0, -1, 1, 1, -1, -1];

/// How far [`DStarLite::compute_shortest_path`] goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Until {
    /// The paper's condition: the top key below the start's, or the start overconsistent.
    Paper,
    /// Also every key whose first part ties with the start's (to a relative 1e-9).
    Ties,
    /// Until the queue is empty: every cell consistent.
    Empty,
}

/// What following the search from the start gave.
enum Extracted {
    /// A path, or `None` when there is none.
    Path(Option<Plan>),
    /// A queued (possibly stale) cell was met at this padded index.
    Inconsistent(usize),
}

/// A D* Lite search from a moving start to a fixed goal (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct DStarLite {
    /// Padded passability, border blocked: cell `(x, y)` at `(y + 1) pw + x + 1`.
    passable: Vec<bool>,
    nodes: Vec<Node>,
    queue: BinaryHeap<Entry>,
    /// Padded width.
    pw: usize,
    width: usize,
    height: usize,
    start: usize,
    last: usize,
    goal: usize,
    km: f64,
    opts: DStarLiteOptions,
    /// Index deltas of the 8 moves, padded cells.
    deltas: [isize; 8],
    /// Whether something changed since the last [`DStarLite::path`].
    dirty: bool,
    /// Queue pushes so far.
    pushes: usize,
}

// The paper's consistency tests (`g != rhs`, `rhs(s) = c(s, u) + g_old`) are exact: both
// sides are the same sums of the same stored values, so exact comparison is what they mean.
#[allow(clippy::float_cmp)]
impl DStarLite {
    /// Set up the search on `grid` from `start` to `goal` (no search runs until
    /// [`DStarLite::path`]).
    ///
    /// # Errors
    /// [`PlanError::EndpointOutsideGrid`] or [`PlanError::EndpointBlocked`] for a `start` or
    /// `goal` outside the grid or not passable.
    ///
    /// # Complexity
    /// `O(cells)`: 25 bytes per padded cell, plus the queue.
    pub fn new(
        grid: &OccupancyGrid,
        start: impl Into<CellXy>,
        goal: impl Into<CellXy>,
        opts: &DStarLiteOptions,
    ) -> Result<Self> {
        let (start, goal) = (start.into(), goal.into());
        check_endpoint(grid, "start", start, opts.unknown_passable)?;
        check_endpoint(grid, "goal", goal, opts.unknown_passable)?;
        let (width, height) = (grid.width(), grid.height());
        let pw = width + 2;
        let mut passable = Vec::new();
        fill_padded(grid, opts.unknown_passable, &mut passable, false, true);
        let pwi = pw as isize;
        let deltas = std::array::from_fn(|k| MOVE_DY[k] * pwi + MOVE_DX[k]);
        let pad = |c: CellXy| (c.y + 1) * pw + c.x + 1;
        let mut this = Self {
            nodes: vec![Node::default(); passable.len()],
            passable,
            queue: BinaryHeap::new(),
            pw,
            width,
            height,
            start: pad(start),
            last: pad(start),
            goal: pad(goal),
            km: 0.0,
            opts: opts.clone(),
            deltas,
            dirty: true,
            pushes: 0,
        };
        let goal = this.goal;
        if let Some(node) = this.nodes.get_mut(goal) {
            node.rhs = 0.0;
        }
        this.push(goal);
        Ok(this)
    }

    /// The robot's cell.
    #[must_use]
    pub fn start(&self) -> CellXy {
        self.cell(self.start)
    }

    /// The goal cell.
    #[must_use]
    pub fn goal(&self) -> CellXy {
        self.cell(self.goal)
    }

    /// The robot moved to `start` (the paper's `s_start = argmin ...`; any cell is accepted,
    /// the heuristic stays consistent). The key modifier `k_m` grows at the next
    /// [`DStarLite::update_cells`] that changes something.
    ///
    /// # Errors
    /// [`PlanError::EndpointOutsideGrid`] outside the grid.
    pub fn move_start(&mut self, start: impl Into<CellXy>) -> Result<()> {
        let c = start.into();
        if c.x >= self.width || c.y >= self.height {
            return Err(PlanError::EndpointOutsideGrid {
                endpoint: "start",
                x: c.x,
                y: c.y,
                width: self.width,
                height: self.height,
            });
        }
        let index = self.pad(c);
        if index != self.start {
            self.start = index;
            self.dirty = true;
        }
        Ok(())
    }

    /// Cells whose state changed (to the state given). Updates the affected step costs
    /// and the `rhs` values and queue entries of their ends (Figure 4, lines 38-47), adding
    /// `h(s_last, s_start)` to `k_m` first when any passability changed; returns how many
    /// cells changed passability. The new plan comes from the next [`DStarLite::path`].
    ///
    /// # Errors
    /// [`PlanError::CellOutOfBounds`] for a cell outside the grid (nothing is changed).
    pub fn update_cells(&mut self, changes: &[(CellXy, Occupancy)]) -> Result<usize> {
        let mut flips = Vec::new();
        for &(c, state) in changes {
            if c.x >= self.width || c.y >= self.height {
                return Err(PlanError::CellOutOfBounds {
                    x: c.x,
                    y: c.y,
                    width: self.width,
                    height: self.height,
                });
            }
            let index = self.pad(c);
            let now = cell_passable(state, self.opts.unknown_passable);
            if self.passable.get(index).copied() != Some(now) {
                flips.push((index, now));
            }
        }
        flips.sort_unstable();
        flips.dedup_by_key(|f| f.0);
        if flips.is_empty() {
            return Ok(0);
        }
        self.km += self.heuristic(self.last, self.start);
        self.last = self.start;
        // Every directed step whose cost may change: into and out of each flipped cell,
        // and the diagonal steps between its orthogonal neighbours.
        let mut edges: Vec<(usize, usize)> = Vec::with_capacity(flips.len() * 24);
        for &(c, _) in &flips {
            for k in 0..8 {
                let n = c.wrapping_add_signed(self.deltas[k]);
                edges.push((c, n));
                edges.push((n, c));
            }
            for k in 0..4 {
                let a = c.wrapping_add_signed(self.deltas[k]);
                let b = c.wrapping_add_signed(self.deltas[(k + 1) % 4]);
                edges.push((a, b));
                edges.push((b, a));
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let old: Vec<f64> = edges.iter().map(|&(u, v)| self.cost(u, v)).collect();
        for &(c, now) in &flips {
            if let Some(p) = self.passable.get_mut(c) {
                *p = now;
            }
        }
        for (&(u, v), &c_old) in edges.iter().zip(&old) {
            let c_new = self.cost(u, v);
            if c_new == c_old {
                continue;
            }
            if u != self.goal {
                let g_v = self.g(v);
                let rhs_u = self.rhs(u);
                if c_old > c_new {
                    self.set_rhs(u, rhs_u.min(c_new + g_v));
                } else if rhs_u == c_old + g_v {
                    let best = self.best_successor(u);
                    self.set_rhs(u, best);
                }
            }
            self.update_vertex(u);
        }
        self.dirty = true;
        Ok(flips.len())
    }

    /// A shortest path from the robot's cell to the goal on the current map, every cell
    /// of it (like [`astar`](crate::astar::astar)), or `Ok(None)` when there is none.
    /// Runs the paper's `ComputeShortestPath` first when anything changed; the plan's
    /// statistics count that run's expansions and queue pushes (zero when nothing
    /// changed).
    ///
    /// # Errors
    /// [`PlanError::BudgetExhausted`] or [`PlanError::Stopped`] from the budget (the
    /// search state stays valid: a later call continues it);
    /// [`PlanError::InconsistentSearch`] if the path cannot be followed (a bug).
    pub fn path(&mut self) -> Result<Option<Plan>> {
        let mut stats = PlanStats::default();
        if self.dirty {
            self.compute_shortest_path(Until::Paper, &mut stats)?;
        }
        self.dirty = false;
        // Following `argmin c + g` is safe through consistent cells; a cell left
        // inconsistent with a key equal to the start's (a tie, which the paper's loop does
        // not process) may hold a stale `g`. Then process the ties, and failing that every
        // queued cell, and follow again.
        for until in [Until::Ties, Until::Empty] {
            match self.extract(stats) {
                Extracted::Path(plan) => return Ok(plan),
                Extracted::Inconsistent(_) => self.compute_shortest_path(until, &mut stats)?,
            }
        }
        match self.extract(stats) {
            Extracted::Path(plan) => Ok(plan),
            Extracted::Inconsistent(at) => Err(self.inconsistent(at)),
        }
    }

    /// Follow `argmin c(s, s') + g(s')` from the start to the goal through consistent
    /// cells.
    fn extract(&self, stats: PlanStats) -> Extracted {
        if !self.passable.get(self.start).copied().unwrap_or(false)
            || !self.rhs(self.start).is_finite()
        {
            return Extracted::Path(None);
        }
        let mut waypoints = vec![self.cell(self.start)];
        let mut steps = [0u32; 2];
        let mut at = self.start;
        while at != self.goal {
            if waypoints.len() > self.nodes.len() {
                return Extracted::Inconsistent(at);
            }
            let mut best: Option<(f64, usize, usize)> = None;
            for k in 0..8 {
                let n = at.wrapping_add_signed(self.deltas[k]);
                let total = self.cost(at, n) + self.g(n);
                if total.is_finite() && best.is_none_or(|b| total < b.0) {
                    best = Some((total, n, k));
                }
            }
            let Some((_, next, k)) = best else {
                return Extracted::Inconsistent(at);
            };
            if self.nodes.get(next).is_some_and(|n| n.queued) {
                return Extracted::Inconsistent(next);
            }
            if let Some(s) = steps.get_mut(usize::from(k >= 4)) {
                *s += 1;
            }
            waypoints.push(self.cell(next));
            at = next;
        }
        Extracted::Path(Some(Plan {
            waypoints,
            length_cells: f64::from(steps[0]) + f64::from(steps[1]) * SQRT_2,
            stats,
        }))
    }

    /// The paper's `ComputeShortestPath` (Figure 4, lines 10-28).
    /// `until` [`Until::Paper`] is the paper's loop; the others process more (see
    /// [`DStarLite::path`]). Adds the expansions and pushes to `stats`.
    fn compute_shortest_path(&mut self, until: Until, stats: &mut PlanStats) -> Result<()> {
        let pushes_before = self.pushes;
        while let Some((top, u)) = self.top() {
            let start_key = self.key(self.start);
            let more = match until {
                Until::Paper => top < start_key,
                Until::Ties => top.0 <= start_key.0 + 1e-9 * start_key.0.max(1.0),
                Until::Empty => true,
            };
            if !(more || self.rhs(self.start) > self.g(self.start)) {
                break;
            }
            stats.expanded += 1;
            self.opts
                .budget
                .check("D* Lite", stats.expanded, 0, stats.expanded)?;
            let new_key = self.key(u);
            let (g_u, rhs_u) = (self.g(u), self.rhs(u));
            if top < new_key {
                self.push(u);
            } else if g_u > rhs_u {
                self.set_g(u, rhs_u);
                self.remove(u);
                for k in 0..8 {
                    let s = u.wrapping_add_signed(self.deltas[k]);
                    let c = self.cost(s, u);
                    if !c.is_finite() {
                        continue;
                    }
                    if s != self.goal && c + rhs_u < self.rhs(s) {
                        self.set_rhs(s, c + rhs_u);
                    }
                    self.update_vertex(s);
                }
            } else {
                let g_old = g_u;
                self.set_g(u, f64::INFINITY);
                for k in 0..8 {
                    let s = u.wrapping_add_signed(self.deltas[k]);
                    let c = self.cost(s, u);
                    if !c.is_finite() {
                        continue;
                    }
                    if s != self.goal && self.rhs(s) == c + g_old {
                        let best = self.best_successor(s);
                        self.set_rhs(s, best);
                    }
                    self.update_vertex(s);
                }
                self.update_vertex(u);
            }
        }
        stats.generated += self.pushes - pushes_before;
        Ok(())
    }

    /// `UpdateVertex(u)` of Figure 4: queue `u` with its current key when inconsistent,
    /// take it out when consistent.
    fn update_vertex(&mut self, u: usize) {
        let (g, rhs) = (self.g(u), self.rhs(u));
        if g != rhs {
            self.push(u);
        } else if self.nodes.get(u).is_some_and(|n| n.queued) {
            self.remove(u);
        }
    }

    /// Queue (or re-key) `u` with its current key.
    fn push(&mut self, u: usize) {
        let key = self.key(u);
        let Some(node) = self.nodes.get_mut(u) else {
            return;
        };
        node.stamp = node.stamp.wrapping_add(1);
        node.queued = true;
        self.queue.push(Reverse((
            key.0.to_bits(),
            key.1.to_bits(),
            u as u32,
            node.stamp,
        )));
        self.pushes += 1;
    }

    /// Take `u` out of the queue (its entries become stale).
    fn remove(&mut self, u: usize) {
        if let Some(node) = self.nodes.get_mut(u) {
            node.stamp = node.stamp.wrapping_add(1);
            node.queued = false;
        }
    }

    /// The smallest valid key and its cell, dropping stale entries.
    fn top(&mut self) -> Option<((f64, f64), usize)> {
        while let Some(&Reverse((k1, k2, u, stamp))) = self.queue.peek() {
            let u = u as usize;
            if self
                .nodes
                .get(u)
                .is_some_and(|n| n.queued && n.stamp == stamp)
            {
                return Some(((f64::from_bits(k1), f64::from_bits(k2)), u));
            }
            self.queue.pop();
        }
        None
    }

    /// `CalculateKey(s)`.
    fn key(&self, s: usize) -> (f64, f64) {
        let m = self.g(s).min(self.rhs(s));
        (m + self.heuristic(self.start, s) + self.km, m)
    }

    /// `min over successors s' of c(u, s') + g(s')`.
    fn best_successor(&self, u: usize) -> f64 {
        let mut best = f64::INFINITY;
        for k in 0..8 {
            let n = u.wrapping_add_signed(self.deltas[k]);
            best = best.min(self.cost(u, n) + self.g(n));
        }
        best
    }

    /// Cost of the single step from `u` to its neighbour `v`, infinite when illegal.
    fn cost(&self, u: usize, v: usize) -> f64 {
        let pass = |i: usize| self.passable.get(i).copied().unwrap_or(false);
        if !pass(u) || !pass(v) {
            return f64::INFINITY;
        }
        let (ux, uy) = (u % self.pw, u / self.pw);
        let (vx, vy) = (v % self.pw, v / self.pw);
        if ux.abs_diff(vx) > 1 || uy.abs_diff(vy) > 1 || u == v {
            return f64::INFINITY;
        }
        if ux == vx || uy == vy {
            1.0
        } else if pass(uy * self.pw + vx) && pass(vy * self.pw + ux) {
            SQRT_2
        } else {
            f64::INFINITY
        }
    }

    /// Octile distance between two padded cells.
    fn heuristic(&self, a: usize, b: usize) -> f64 {
        let dx = (a % self.pw).abs_diff(b % self.pw);
        let dy = (a / self.pw).abs_diff(b / self.pw);
        let (long, short) = if dx >= dy { (dx, dy) } else { (dy, dx) };
        (long - short) as f64 + short as f64 * SQRT_2
    }

    fn g(&self, u: usize) -> f64 {
        self.nodes.get(u).map_or(f64::INFINITY, |n| n.g)
    }

    fn rhs(&self, u: usize) -> f64 {
        self.nodes.get(u).map_or(f64::INFINITY, |n| n.rhs)
    }

    fn set_g(&mut self, u: usize, g: f64) {
        if let Some(n) = self.nodes.get_mut(u) {
            n.g = g;
        }
    }

    fn set_rhs(&mut self, u: usize, rhs: f64) {
        if let Some(n) = self.nodes.get_mut(u) {
            n.rhs = rhs;
        }
    }

    fn pad(&self, c: CellXy) -> usize {
        (c.y + 1) * self.pw + c.x + 1
    }

    fn cell(&self, index: usize) -> CellXy {
        CellXy::new(
            (index % self.pw).saturating_sub(1),
            (index / self.pw).saturating_sub(1),
        )
    }

    fn inconsistent(&self, at: usize) -> PlanError {
        let c = self.cell(at);
        PlanError::InconsistentSearch {
            planner: "D* Lite",
            x: c.x,
            y: c.y,
        }
    }
}

/// The shortest path of a one-shot D* Lite search (a fresh [`DStarLite`] and one
/// [`DStarLite::path`]): the same cost as [`astar`](crate::astar::astar), for tests and
/// the planner interface.
///
/// # Errors
/// As [`DStarLite::new`] and [`DStarLite::path`].
pub fn dstar_lite(
    grid: &OccupancyGrid,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    opts: &DStarLiteOptions,
) -> Result<Option<Plan>> {
    let (start, goal) = (xy(start), xy(goal));
    DStarLite::new(grid, start, goal, opts)?.path()
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    #[allow(clippy::float_cmp)]
    fn open_grid_straight_line() {
        let grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        let mut p = DStarLite::new(&grid, (0, 1), (4, 1), &DStarLiteOptions::default()).unwrap();
        let plan = p.path().unwrap();
        assert_eq!(plan.unwrap().length_cells, 4.0);
    }
}
