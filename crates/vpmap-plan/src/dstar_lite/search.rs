//! The D* Lite search itself (Figure 4 of the paper, see the [module docs](super)) over queue
//! keys of one type: `g` and `rhs` per padded cell, step costs from the padded passability,
//! `UpdateVertex`, `ComputeShortestPath` and the path followed from the start; cell changes
//! and robot moves; and the conversion to wider keys.

use crate::budget::Budget;
use crate::error::{PlanError, Result};
use crate::grid::{CellXy, DIAGONAL_SIDES, MOVES, Occupancy, OccupancyGrid};
use crate::los::{cell_passable, fill_padded};
use crate::plan::{Plan, PlanStats, check_endpoint};

use super::cost::{StepCost, pack, tie_weight, unpack};
use super::keys::QueueKey;
use super::queue::Queue;

/// Options of [`DStarLite`](super::DStarLite).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DStarLiteOptions {
    /// Whether [`Occupancy::Unknown`] cells may be entered (default: no).
    pub unknown_passable: bool,
    /// Most expansions one [`DStarLite::path`](super::DStarLite::path) call may make (its
    /// re-planning), and the [`Stop`](crate::budget::Stop) it looks at (default:
    /// [`Budget::default`]).
    pub budget: Budget,
    /// The common tie rule (default: off): among equally short paths, the one of the
    /// smallest sum of [`tie_weight`](super::tie_weight)s of the cells it enters (see the
    /// [module docs](super)). Off, ties fall as the search meets them (smaller cost-to-goal
    /// first).
    pub common_ties: bool,
}

/// The reverse of each move.
const OPPOSITE: [usize; 8] = [2, 3, 0, 1, 6, 7, 4, 5];

/// How far [`Search::compute_shortest_path`] goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Until {
    /// The paper's condition: the top key below the start's, or the start overconsistent.
    Paper,
    /// Also every key whose first part's length ties with the start's.
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

/// What [`Search::path`] gave.
pub(super) enum Planned {
    /// The path, or `None` when there is none.
    Done(Option<Plan>),
    /// A key did not fit: the search must widen and go on.
    Widen,
}

/// The D* Lite search itself, over queue keys of type `K`.
#[derive(Clone, Debug)]
pub(super) struct Search<K> {
    /// Padded passability, border blocked: cell `(x, y)` at `(y + 1) pw + x + 1`.
    passable: Vec<bool>,
    /// Tie weight of each padded cell (empty without the common tie rule).
    weights: Vec<u32>,
    /// Per padded cell: the [`pack`]ed cost-to-goal estimate `g` and one-step lookahead
    /// `rhs = min c(s, s') + g(s')` (zero at the goal).
    costs: Vec<[u128; 2]>,
    /// The queue of the locally inconsistent cells.
    queue: Queue<K>,
    /// Padded width.
    pw: usize,
    width: usize,
    height: usize,
    pub(super) start: usize,
    last: usize,
    pub(super) goal: usize,
    km: StepCost,
    opts: DStarLiteOptions,
    /// Index deltas of the 8 moves, padded cells.
    deltas: [isize; 8],
    /// Whether something changed since the last [`DStarLite::path`](super::DStarLite::path).
    dirty: bool,
    /// Queue insertions and re-keyings so far.
    pushes: usize,
    /// Whether a key did not fit `K` (the search must widen before it goes on).
    pub(super) overflow: std::cell::Cell<bool>,
}

impl<K: QueueKey> Search<K> {
    /// [`DStarLite::new`](super::DStarLite::new).
    pub(super) fn new(
        grid: &OccupancyGrid,
        start: CellXy,
        goal: CellXy,
        opts: &DStarLiteOptions,
    ) -> Result<Self> {
        check_endpoint(grid, "start", start, opts.unknown_passable)?;
        check_endpoint(grid, "goal", goal, opts.unknown_passable)?;
        let (width, height) = (grid.width(), grid.height());
        let pw = width + 2;
        let mut passable = Vec::new();
        fill_padded(grid, opts.unknown_passable, &mut passable, false, true);
        let weights = if opts.common_ties {
            (0..passable.len())
                .map(|i| tie_weight((i % pw).wrapping_sub(1), (i / pw).wrapping_sub(1)))
                .collect()
        } else {
            Vec::new()
        };
        let pwi = pw as isize;
        let deltas = std::array::from_fn(|k| MOVES[k].1 * pwi + MOVES[k].0);
        let pad = |c: CellXy| (c.y + 1) * pw + c.x + 1;
        let mut this = Self {
            costs: vec![[0; 2]; passable.len()],
            queue: Queue::new(passable.len()),
            passable,
            weights,
            pw,
            width,
            height,
            start: pad(start),
            last: pad(start),
            goal: pad(goal),
            km: StepCost::ZERO,
            opts: opts.clone(),
            deltas,
            dirty: true,
            pushes: 0,
            overflow: std::cell::Cell::new(false),
        };
        let goal = this.goal;
        this.set_rhs(goal, StepCost::ZERO);
        this.update_vertex(goal);
        Ok(this)
    }

    /// The same search with keys of type `K2`, this one left empty: every field moves
    /// over and each queued key is computed anew.
    pub(super) fn convert<K2: QueueKey>(&mut self) -> Search<K2> {
        let (cells, queue) = self.queue.convert();
        let mut to = Search {
            passable: std::mem::take(&mut self.passable),
            weights: std::mem::take(&mut self.weights),
            costs: std::mem::take(&mut self.costs),
            queue,
            pw: self.pw,
            width: self.width,
            height: self.height,
            start: self.start,
            last: self.last,
            goal: self.goal,
            km: self.km,
            opts: self.opts.clone(),
            deltas: self.deltas,
            dirty: self.dirty,
            pushes: self.pushes,
            overflow: std::cell::Cell::new(false),
        };
        to.queue_afresh(&cells);
        // Converting is not searching: the re-queued keys are not counted as pushes.
        to.pushes = self.pushes;
        to
    }

    /// [`DStarLite::move_start`](super::DStarLite::move_start).
    pub(super) fn move_start(&mut self, c: CellXy) -> Result<()> {
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

    /// [`DStarLite::update_cells`](super::DStarLite::update_cells).
    pub(super) fn update_cells(&mut self, changes: &[(CellXy, Occupancy)]) -> Result<usize> {
        // (padded cell, position in `changes` reversed, passable now): a cell listed twice takes its
        // last state, as writing the changes to a grid in order would.
        let mut latest = Vec::with_capacity(changes.len());
        for (order, &(c, state)) in changes.iter().enumerate() {
            if c.x >= self.width || c.y >= self.height {
                return Err(PlanError::CellOutOfBounds {
                    x: c.x,
                    y: c.y,
                    width: self.width,
                    height: self.height,
                });
            }
            let now = cell_passable(state, self.opts.unknown_passable);
            latest.push((self.pad(c), std::cmp::Reverse(order), now));
        }
        latest.sort_unstable();
        latest.dedup_by_key(|f| f.0);
        let flips: Vec<(usize, bool)> = latest
            .into_iter()
            .filter(|&(index, _, now)| self.passable.get(index).copied() != Some(now))
            .map(|(index, _, now)| (index, now))
            .collect();
        if flips.is_empty() {
            return Ok(0);
        }
        self.km = self.km.add(self.heuristic(self.last, self.start));
        self.last = self.start;
        if self.km.straight >= K::KM_LIMIT || self.km.diagonal >= K::KM_LIMIT {
            self.rekey();
        }
        // Every directed step whose cost may change, as (from, move): into and out of each
        // flipped cell, and the diagonal steps between its orthogonal neighbours.
        let mut edges: Vec<(usize, usize)> = Vec::with_capacity(flips.len() * 24);
        for &(c, _) in &flips {
            for (k, (&delta, &back)) in self.deltas.iter().zip(&OPPOSITE).enumerate() {
                edges.push((c, k));
                edges.push((c.wrapping_add_signed(delta), back));
            }
        }
        // The diagonal moves `4 + i` from `u` that pass the flipped cell: it is one of their
        // sides `u + delta[side]`.
        for &(c, _) in &flips {
            for (i, &(s0, s1)) in DIAGONAL_SIDES.iter().enumerate() {
                for side in [s0, s1] {
                    let u = c.wrapping_add_signed(-self.deltas[side]);
                    edges.push((u, 4 + i));
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let old: Vec<StepCost> = edges.iter().map(|&(u, k)| self.cost(u, k)).collect();
        for &(c, now) in &flips {
            if let Some(p) = self.passable.get_mut(c) {
                *p = now;
            }
        }
        for (&(u, k), &c_old) in edges.iter().zip(&old) {
            let c_new = self.cost(u, k);
            if c_new == c_old {
                continue;
            }
            let v = u.wrapping_add_signed(self.deltas[k]);
            if u != self.goal {
                let g_v = self.g(v);
                let rhs_u = self.rhs(u);
                if c_old > c_new {
                    self.set_rhs(u, rhs_u.min(c_new.add(g_v)));
                } else if rhs_u == c_old.add(g_v) {
                    let best = self.best_successor(u);
                    self.set_rhs(u, best);
                }
            }
            self.update_vertex(u);
        }
        self.dirty = true;
        Ok(flips.len())
    }

    /// [`DStarLite::path`](super::DStarLite::path), adding to `stats`.
    pub(super) fn path(&mut self, stats: &mut PlanStats) -> Result<Planned> {
        if self.dirty {
            self.compute_shortest_path(Until::Paper, stats)?;
            if self.overflow.get() {
                return Ok(Planned::Widen);
            }
        }
        self.dirty = false;
        // Following `argmin c + g` is safe through consistent cells; a cell left
        // inconsistent with a key equal to the start's (a tie, which the paper's loop does
        // not process) may hold a stale `g`. Then process the ties, and failing that every
        // queued cell, and follow again.
        for until in [Until::Ties, Until::Empty] {
            match self.extract(*stats) {
                Extracted::Path(plan) => return Ok(Planned::Done(plan)),
                Extracted::Inconsistent(_) => {
                    self.compute_shortest_path(until, stats)?;
                    if self.overflow.get() {
                        self.dirty = true;
                        return Ok(Planned::Widen);
                    }
                }
            }
        }
        match self.extract(*stats) {
            Extracted::Path(plan) => Ok(Planned::Done(plan)),
            Extracted::Inconsistent(at) => Err(self.inconsistent(at)),
        }
    }

    /// Follow `argmin c(s, s') + g(s')` from the start to the goal through consistent
    /// cells (exact ties to the first move in the order E, S, W, N, SE, SW, NW, NE).
    fn extract(&self, stats: PlanStats) -> Extracted {
        if !self.passable.get(self.start).copied().unwrap_or(false)
            || !self.rhs(self.start).is_finite()
        {
            return Extracted::Path(None);
        }
        let expected = self.rhs(self.start);
        let mut waypoints = Vec::with_capacity(
            (expected.straight as usize)
                .saturating_add(expected.diagonal as usize)
                .saturating_add(1)
                .min(self.costs.len()),
        );
        let mut xy = self.cell(self.start);
        waypoints.push(xy);
        let mut total = StepCost::ZERO;
        let mut at = self.start;
        while at != self.goal {
            if waypoints.len() > self.costs.len() {
                return Extracted::Inconsistent(at);
            }
            let mut best: Option<(StepCost, usize, StepCost, usize)> = None;
            for k in 0..8 {
                let n = at.wrapping_add_signed(self.deltas[k]);
                let g_n = self.g(n);
                if !g_n.is_finite() {
                    continue;
                }
                let c = self.cost(at, k);
                if !c.is_finite() {
                    continue;
                }
                let through = c.add(g_n);
                if best.is_none_or(|b| through < b.0) {
                    best = Some((through, n, c, k));
                }
            }
            let Some((_, next, step, k)) = best else {
                return Extracted::Inconsistent(at);
            };
            if self.queue.queued(next) {
                return Extracted::Inconsistent(next);
            }
            total = total.add(step);
            // The next cell's coordinates by the move (no division).
            let (dx, dy) = (
                MOVES.get(k).map_or(0, |m| m.0),
                MOVES.get(k).map_or(0, |m| m.1),
            );
            xy = CellXy::new(xy.x.wrapping_add_signed(dx), xy.y.wrapping_add_signed(dy));
            waypoints.push(xy);
            at = next;
        }
        Extracted::Path(Some(Plan {
            waypoints,
            length_cells: total.length(),
            stats,
        }))
    }

    /// The paper's `ComputeShortestPath` (Figure 4, lines 10-28).
    /// `until` [`Until::Paper`] is the paper's loop; the others process more (see
    /// [`DStarLite::path`](super::DStarLite::path)). Adds the expansions and pushes to `stats`.
    fn compute_shortest_path(&mut self, until: Until, stats: &mut PlanStats) -> Result<()> {
        let pushes_before = self.pushes;
        while let Some(&(top, u)) = self.queue.first() {
            if self.overflow.get() {
                break;
            }
            let u = u as usize;
            let start_key = self.key(self.start);
            let more = match until {
                Until::Paper => top < start_key,
                Until::Ties => top.k1_length_le(start_key),
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
                self.queue_set(u, new_key);
            } else if g_u > rhs_u {
                self.set_g(u, rhs_u);
                self.queue.remove(u);
                for (delta, back) in self.deltas.into_iter().zip(OPPOSITE) {
                    // Predecessor s = u + delta steps to u by the opposite move.
                    let s = u.wrapping_add_signed(delta);
                    let c = self.cost(s, back);
                    if !c.is_finite() {
                        continue;
                    }
                    let via = c.add(rhs_u);
                    if s != self.goal && via < self.rhs(s) {
                        self.set_rhs(s, via);
                    }
                    self.update_vertex(s);
                }
            } else {
                let g_old = g_u;
                self.set_g(u, StepCost::INF);
                for (delta, back) in self.deltas.into_iter().zip(OPPOSITE) {
                    let s = u.wrapping_add_signed(delta);
                    let c = self.cost(s, back);
                    if !c.is_finite() {
                        continue;
                    }
                    if s != self.goal && self.rhs(s) == c.add(g_old) {
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

    /// `UpdateVertex(u)` of Figure 4: queue `u` with its current key when inconsistent
    /// (or re-key it), take it out when consistent.
    fn update_vertex(&mut self, u: usize) {
        let Some(&[g, rhs]) = self.costs.get(u) else {
            return;
        };
        if g != rhs {
            let key = self.key(u);
            self.queue_set(u, key);
        } else if self.queue.queued(u) {
            self.queue.remove(u);
        }
    }

    /// Start `k_m` again from zero: every queued key is computed anew for the current
    /// start and the heap rebuilt (keeps the keys' step counts small; `O(queue)`, after
    /// tens of millions of cells driven).
    fn rekey(&mut self) {
        self.km = StepCost::ZERO;
        let cells = self.queue.take_cells();
        self.queue_afresh(&cells);
    }

    /// Queue `cells`, taken out of an emptied queue, again, each with its key computed
    /// afresh ([`Search::rekey`], [`Search::convert`]).
    fn queue_afresh(&mut self, cells: &[u32]) {
        self.queue.forget(cells);
        for &u in cells {
            let key = self.key(u as usize);
            self.queue_set(u as usize, key);
        }
    }

    /// Queue `u` with `key`, or change its key (counted as a push either way).
    fn queue_set(&mut self, u: usize, key: K) {
        self.pushes += 1;
        self.queue.set(u, key);
    }

    /// `CalculateKey(s)`.
    fn key(&self, s: usize) -> K {
        let m = self.g(s).min(self.rhs(s));
        K::new(m.add(self.heuristic(self.start, s)).add(self.km), m).unwrap_or_else(|| {
            self.overflow.set(true);
            K::MAX
        })
    }

    /// `min over successors s' of c(u, s') + g(s')`.
    fn best_successor(&self, u: usize) -> StepCost {
        let mut best = StepCost::INF;
        for k in 0..8 {
            let n = u.wrapping_add_signed(self.deltas[k]);
            best = best.min(self.cost(u, k).add(self.g(n)));
        }
        best
    }

    /// Cost of move `k` from `u`, infinite when illegal.
    #[inline]
    fn cost(&self, u: usize, k: usize) -> StepCost {
        let pass = |i: usize| self.passable.get(i).copied().unwrap_or(false);
        let Some(&delta) = self.deltas.get(k) else {
            return StepCost::INF;
        };
        let v = u.wrapping_add_signed(delta);
        if !pass(u) || !pass(v) {
            return StepCost::INF;
        }
        let weight = self.weights.get(v).copied().unwrap_or(0);
        match k.checked_sub(4).and_then(|i| DIAGONAL_SIDES.get(i)) {
            None => StepCost::step(false, weight),
            Some(&(a, b)) => {
                let side = |s: usize| pass(u.wrapping_add_signed(self.deltas[s]));
                if side(a) && side(b) {
                    StepCost::step(true, weight)
                } else {
                    StepCost::INF
                }
            }
        }
    }

    /// Octile distance between two padded cells.
    #[inline]
    fn heuristic(&self, a: usize, b: usize) -> StepCost {
        // Padded indices fit in u32 (grids hold at most 30 million cells): 32-bit division.
        let pw = self.pw as u32;
        let (a, b) = (a as u32, b as u32);
        let dx = (a % pw).abs_diff(b % pw);
        let dy = (a / pw).abs_diff(b / pw);
        StepCost::octile(dx as usize, dy as usize)
    }

    #[inline]
    fn g(&self, u: usize) -> StepCost {
        self.costs.get(u).map_or(StepCost::INF, |c| unpack(c[0]))
    }

    #[inline]
    fn rhs(&self, u: usize) -> StepCost {
        self.costs.get(u).map_or(StepCost::INF, |c| unpack(c[1]))
    }

    #[inline]
    fn set_g(&mut self, u: usize, g: StepCost) {
        if let Some(c) = self.costs.get_mut(u) {
            c[0] = pack(g);
        }
    }

    #[inline]
    fn set_rhs(&mut self, u: usize, rhs: StepCost) {
        if let Some(c) = self.costs.get_mut(u) {
            c[1] = pack(rhs);
        }
    }

    fn pad(&self, c: CellXy) -> usize {
        (c.y + 1) * self.pw + c.x + 1
    }

    pub(super) fn cell(&self, index: usize) -> CellXy {
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
