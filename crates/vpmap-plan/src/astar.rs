//! A* on the 8-connected grid with octile costs: the grid-path baseline.
//!
//! Semantics: the robot moves between the centres of 8-neighbouring traversable cells. A
//! straight step costs 1 and needs its target cell traversable; a diagonal step costs
//! `sqrt 2` and needs its target **and both orthogonal neighbours** traversable (no corner
//! cutting, no squeezing between two blocked cells that share a corner). These are exactly
//! the single steps that [`crate::los`] calls clear, and the movement model of the Moving
//! AI benchmarks, whose `.scen` optimal lengths this search reproduces. Cells outside the
//! grid and [`Occupancy::Occupied`](crate::Occupancy::Occupied) cells are never entered;
//! [`Occupancy::Unknown`](crate::Occupancy::Unknown) cells only with
//! [`AstarOptions::unknown_passable`].
//!
//! The search uses the octile distance heuristic (consistent, so each cell is expanded at
//! most once and the first goal expansion is optimal), an open list ordered by `f = g + h`
//! with ties broken towards larger `g` (deeper nodes) and then larger cell index (grouped
//! by exact `f`, so that pushes keeping `f` are O(1)), and flat arrays indexed by cell of
//! a copy of the grid with a blocked border (no bounds tests on neighbours). Path costs
//! and heuristic values are kept as exact counts of straight and diagonal steps, so the
//! reported length is `straight + diagonal * sqrt 2` to the last bit and equal priorities
//! compare equal (the tie-break then really prefers deeper nodes, which saves most
//! expansions on open ground).

use std::f64::consts::SQRT_2;

use crate::budget::Budget;
use crate::error::Result;
use crate::grid::{CellXy, OccupancyGrid};
use crate::los::fill_padded;
use crate::plan::{Plan, PlanStats, cells_of, check_endpoint, xy};

/// Options of [`astar`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AstarOptions {
    /// Whether [`Occupancy::Unknown`](crate::Occupancy::Unknown) cells may be entered (default: no).
    pub unknown_passable: bool,
    /// Most work before the search stops with an error (default: [`Budget::default`]).
    pub budget: Budget,
}

/// Flag of a traversable cell.
const PASSABLE: u8 = 1;
/// Flag of a cell expanded by the current search.
const CLOSED: u8 = 2;

/// No parent: the start cell.
const NO_PARENT: u32 = u32::MAX;

/// Per-cell search state, valid when `mark` belongs to the current search.
#[derive(Clone, Copy, Debug, Default)]
struct NodeState {
    /// Straight and diagonal steps of the best path found to this cell.
    steps: [u32; 2],
    /// Padded index of the previous cell on that path, or [`NO_PARENT`].
    parent: u32,
    /// `2 * generation` when open, `2 * generation + 1` when closed, anything else when
    /// untouched by the current search.
    mark: u32,
}

/// An open-list entry. The heap pops the largest entry: the smallest `f` (stored with
/// its bits inverted), then the largest `g` (both non-negative, so their IEEE bit
/// patterns order like the values), then the largest cell index (padded indices order
/// like grid indices).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Entry {
    f_inv: u64,
    g: u64,
    node: u32,
}

impl Entry {
    #[inline]
    fn new(f: f64, g: f64, node: u32) -> Self {
        Self {
            f_inv: !f.to_bits(),
            g: g.to_bits(),
            node,
        }
    }
}

/// The open list: pops [`Entry`]s largest first (smallest `f`, then largest `g`, then
/// largest node), exactly like one binary heap would. Entries are grouped by their exact
/// `f` (an open list holds few distinct values); the group of the smallest `f` (the
/// current level) is kept as `(g, node)` pairs in a vector sorted ascending. With a
/// consistent heuristic `f` never decreases along the search, and a node pushed into the
/// current level comes from expanding the level's largest entry with a larger `g`, so it
/// sorts at (or a few siblings from) the end: most pushes and pops are O(1).
#[derive(Clone, Debug, Default)]
struct OpenList {
    /// `f` bits of the current level, when there is one: every entry of `level` has this
    /// `f`, and every group in `groups` a larger one.
    current: Option<u64>,
    /// `(g bits, node)` of the current level, sorted ascending.
    level: Vec<(u64, u32)>,
    /// Later levels: `(f bits, unsorted (g bits, node) pairs)`, `f` strictly decreasing.
    groups: Vec<(u64, Vec<(u64, u32)>)>,
    /// Emptied group vectors kept for reuse.
    pool: Vec<Vec<(u64, u32)>>,
}

impl OpenList {
    fn clear(&mut self) {
        self.current = None;
        self.level.clear();
        for (_, mut group) in self.groups.drain(..) {
            group.clear();
            self.pool.push(group);
        }
    }

    /// Add `item` to the group of `f` bits `key`, creating it if needed.
    #[inline]
    fn group_push(&mut self, key: u64, item: (u64, u32)) {
        // Descending keys: most pushes land in one of the last few groups.
        let n = self.groups.len();
        let tail = n.saturating_sub(4);
        let found = match self.groups.get(tail..).and_then(|t| t.first()) {
            Some(&(f, _)) if key <= f => self
                .groups
                .get(tail..)
                .map_or(Err(n), |t| t.binary_search_by(|&(f, _)| key.cmp(&f)))
                .map(|at| at + tail)
                .map_err(|at| at + tail),
            _ => self.groups.binary_search_by(|&(f, _)| key.cmp(&f)),
        };
        match found {
            Ok(at) => {
                if let Some((_, group)) = self.groups.get_mut(at) {
                    group.push(item);
                }
            }
            Err(at) => {
                let mut group = self.pool.pop().unwrap_or_default();
                group.push(item);
                self.groups.insert(at, (key, group));
            }
        }
    }

    #[inline]
    fn push(&mut self, entry: Entry) {
        let key = !entry.f_inv;
        let item = (entry.g, entry.node);
        match self.current {
            Some(f) if f == key => {
                let mut at = self.level.len();
                while at > 0 && self.level.get(at - 1).is_some_and(|&e| e > item) {
                    at -= 1;
                }
                self.level.insert(at, item);
            }
            Some(f) if key < f => {
                // A smaller f than the current level (not expected with a consistent
                // heuristic, but kept exact): the level becomes the smallest group again.
                let level = std::mem::take(&mut self.level);
                self.level = self.pool.pop().unwrap_or_default();
                self.groups.push((f, level));
                self.current = None;
                self.group_push(key, item);
            }
            _ => self.group_push(key, item),
        }
    }

    /// The node of the largest entry, removed.
    #[inline]
    fn pop(&mut self) -> Option<u32> {
        if let Some((_, node)) = self.level.pop() {
            return Some(node);
        }
        let (key, mut group) = self.groups.pop()?;
        group.sort_unstable();
        let old = std::mem::replace(&mut self.level, group);
        self.pool.push(old);
        self.current = Some(key);
        self.level.pop().map(|(_, node)| node)
    }
}

/// Length of a path of `steps[0]` straight and `steps[1]` diagonal steps, cells.
#[inline]
fn octile_length(steps: [u32; 2]) -> f64 {
    f64::from(steps[0]) + f64::from(steps[1]) * SQRT_2
}

/// Octile distance between two cells, as straight and diagonal step counts: a shortest
/// path on an empty grid.
#[inline]
fn octile_steps(a: (u32, u32), b: (u32, u32)) -> [u32; 2] {
    let dx = a.0.abs_diff(b.0);
    let dy = a.1.abs_diff(b.1);
    let (long, short) = if dx >= dy { (dx, dy) } else { (dy, dx) };
    [long - short, short]
}

/// `f = g + h` from step counts, so that equal sums give bit-identical values and ties
/// are real ties (adding two rounded lengths would not).
#[inline]
fn priority(g: [u32; 2], h: [u32; 2]) -> f64 {
    octile_length([g[0] + h[0], g[1] + h[1]])
}

/// A reusable A* search: keeps its per-cell arrays and open list between calls, so that
/// many queries on grids of one size allocate once (no clearing either: each search
/// stamps the cells it touches with its own generation number).
///
/// Internally the grid is copied into a passability map with a one-cell blocked border
/// (rebuilt by every search, so grid edits between searches are always seen), which lets
/// the neighbour checks go without bounds tests.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, astar::{AstarOptions, AstarSearch}};
/// let grid = OccupancyGrid::new(8, 8, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// let mut search = AstarSearch::new();
/// for goal in [(7, 7), (7, 0), (3, 5)] {
///     let plan = search.search(&grid, (0, 0), goal, &AstarOptions::default()).unwrap().unwrap();
///     assert_eq!(*plan.waypoints.last().unwrap(), goal);
/// }
/// ```
#[derive(Clone, Debug, Default)]
pub struct AstarSearch {
    nodes: Vec<NodeState>,
    generation: u32,
    open: OpenList,
    /// Flags of the padded grid (`width + 2` by `height + 2`, border blocked):
    /// [`PASSABLE`] and, during a search, [`CLOSED`].
    passable: Vec<u8>,
}

impl AstarSearch {
    /// A search with no memory allocated yet.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Size the arrays for `cells` (padded) cells and start a new generation; returns
    /// the `(open, closed)` marks of this search.
    fn begin(&mut self, cells: usize) -> (u32, u32) {
        if self.nodes.len() != cells || self.generation >= u32::MAX / 2 - 1 {
            self.nodes.clear();
            self.nodes.resize(cells, NodeState::default());
            self.generation = 0;
        }
        self.generation += 1;
        self.open.clear();
        (2 * self.generation, 2 * self.generation + 1)
    }

    /// Fill [`Self::passable`] for `grid`, padded with a blocked border (the cells
    /// [`cell_passable`](crate::los::cell_passable) lets a robot enter).
    fn fill_passable(&mut self, grid: &OccupancyGrid, unknown_passable: bool) {
        fill_padded(grid, unknown_passable, &mut self.passable, 0, PASSABLE);
    }

    /// Find a shortest 8-connected path from `start` to `goal` (see [`astar`]).
    ///
    /// # Errors
    /// As [`astar`].
    pub fn search(
        &mut self,
        grid: &OccupancyGrid,
        start: impl Into<CellXy>,
        goal: impl Into<CellXy>,
        opts: &AstarOptions,
    ) -> Result<Option<Plan>> {
        let (start, goal) = (xy(start), xy(goal));
        check_endpoint(grid, "start", start, opts.unknown_passable)?;
        check_endpoint(grid, "goal", goal, opts.unknown_passable)?;
        opts.budget.stop.check("A*")?;
        // Padded coordinates: cell (x, y) is (x + 1, y + 1) in a grid one cell larger on
        // every side. Cell counts are below MAX_CELLS, so padded indices fit in u32.
        let pw = grid.width() + 2;
        let (open_mark, closed_mark) = self.begin(pw * (grid.height() + 2));
        self.fill_passable(grid, opts.unknown_passable);
        let mut stats = PlanStats::default();
        let pw32 = pw as u32;
        let start_p = ((start.0 + 1) as u32, (start.1 + 1) as u32);
        let goal_p = ((goal.0 + 1) as u32, (goal.1 + 1) as u32);
        let start_index = start_p.1 * pw32 + start_p.0;
        let goal_index = goal_p.1 * pw32 + goal_p.0;
        if let Some(node) = self.nodes.get_mut(start_index as usize) {
            *node = NodeState {
                steps: [0, 0],
                parent: NO_PARENT,
                mark: open_mark,
            };
        }
        self.open.push(Entry::new(
            octile_length(octile_steps(start_p, goal_p)),
            0.0,
            start_index,
        ));
        stats.generated += 1;
        let nodes = self.nodes.as_mut_slice();
        let passable = self.passable.as_mut_slice();
        let open = &mut self.open;
        // Index deltas of the 8 moves, in padded cells: E, S, W, N, SE, SW, NW, NE.
        let pwi = pw as isize;
        let deltas: [isize; 8] = [1, pwi, -1, -pwi, pwi + 1, pwi - 1, -pwi - 1, 1 - pwi];
        let move_dx: [i32; 8] = [1, 0, -1, 0, 1, -1, -1, 1];
        let move_dy: [i32; 8] = [0, 1, 0, -1, 1, 1, -1, -1];
        while let Some(node) = open.pop() {
            let index = node as usize;
            let Some(flags) = passable.get_mut(index) else {
                continue;
            };
            if *flags & CLOSED != 0 {
                continue; // a stale entry: the cell was expanded with a smaller cost
            }
            *flags |= CLOSED;
            let Some(state) = nodes.get_mut(index) else {
                continue;
            };
            state.mark = closed_mark;
            let steps = state.steps;
            stats.expanded += 1;
            opts.budget.check("A*", stats.expanded, 0, stats.expanded)?;
            if node == goal_index {
                return Ok(Some(self.plan(pw, goal_index as usize, steps, stats)));
            }
            let (x, y) = (node % pw32, node / pw32);
            // Expanded cells are traversable grid cells, so every neighbour index lies
            // inside the padded grid; the border cells are blocked.
            let flag = |k: usize| {
                passable
                    .get(index.wrapping_add_signed(deltas[k]))
                    .copied()
                    .unwrap_or(0)
            };
            let flags = [
                flag(0),
                flag(1),
                flag(2),
                flag(3),
                flag(4),
                flag(5),
                flag(6),
                flag(7),
            ];
            let pass = |k: usize| flags[k] & PASSABLE != 0;
            let straight = [pass(0), pass(1), pass(2), pass(3)];
            let allowed = [
                straight[0],
                straight[1],
                straight[2],
                straight[3],
                straight[0] && straight[1] && pass(4),
                straight[2] && straight[1] && pass(5),
                straight[2] && straight[3] && pass(6),
                straight[0] && straight[3] && pass(7),
            ];
            let straight_steps = [steps[0] + 1, steps[1]];
            let diagonal_steps = [steps[0], steps[1] + 1];
            let g_straight = octile_length(straight_steps);
            let g_diagonal = octile_length(diagonal_steps);
            for k in 0..8 {
                if !allowed[k] || flags[k] & CLOSED != 0 {
                    continue;
                }
                let next_index = index.wrapping_add_signed(deltas[k]);
                let Some(next) = nodes.get_mut(next_index) else {
                    continue;
                };
                if next.mark == closed_mark {
                    continue;
                }
                let (next_steps, g) = if k >= 4 {
                    (diagonal_steps, g_diagonal)
                } else {
                    (straight_steps, g_straight)
                };
                if next.mark == open_mark && octile_length(next.steps) <= g {
                    continue;
                }
                *next = NodeState {
                    steps: next_steps,
                    parent: node,
                    mark: open_mark,
                };
                let next_p = (
                    x.wrapping_add_signed(move_dx[k]),
                    y.wrapping_add_signed(move_dy[k]),
                );
                let h = octile_steps(next_p, goal_p);
                open.push(Entry::new(priority(next_steps, h), g, next_index as u32));
                stats.generated += 1;
            }
        }
        Ok(None)
    }

    /// The plan ending at padded index `goal_index`, following parents back to the start;
    /// `pw` is the padded width.
    fn plan(&self, pw: usize, goal_index: usize, steps: [u32; 2], stats: PlanStats) -> Plan {
        let mut waypoints = Vec::with_capacity((steps[0] + steps[1]) as usize + 1);
        let mut index = goal_index;
        // A parent chain is at most as long as the number of cells.
        for _ in 0..=self.nodes.len() {
            waypoints.push((index % pw - 1, index / pw - 1));
            match self.nodes.get(index) {
                Some(state) if state.parent != NO_PARENT => index = state.parent as usize,
                _ => break,
            }
        }
        waypoints.reverse();
        Plan {
            waypoints: cells_of(waypoints),
            length_cells: octile_length(steps),
            stats,
        }
    }
}

/// A shortest 8-connected grid path from `start` to `goal`, octile costs, no corner
/// cutting (see the [module docs](self)). The waypoints are every cell of the path, start
/// and goal included; `Ok(None)` when the goal cannot be reached. Allocates a fresh
/// [`AstarSearch`]; keep one to run many queries.
///
/// # Errors
/// [`PlanError::EndpointOutsideGrid`](crate::PlanError::EndpointOutsideGrid) when `start`
/// or `goal` is outside the grid,
/// [`PlanError::EndpointBlocked`](crate::PlanError::EndpointBlocked) when it is not
/// traversable.
///
/// # Complexity
/// `O(n log n)` time for `n` reachable cells plus `O(cells)` to copy the grid, 17 bytes
/// per grid cell.
///
/// # References
/// P. E. Hart, N. J. Nilsson, B. Raphael, "A Formal Basis for the Heuristic Determination
/// of Minimum Cost Paths", IEEE Transactions on Systems Science and Cybernetics 4(2), 1968.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, astar::{astar, AstarOptions}};
/// // .#.
/// // ...
/// let mut grid = OccupancyGrid::new(3, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// grid.set(1, 0, Occupancy::Occupied).unwrap();
/// let plan = astar(&grid, (0, 0), (2, 0), &AstarOptions::default()).unwrap().unwrap();
/// // No corner cutting around (1, 0): down, across, up.
/// assert_eq!(plan.waypoints, [(0, 0), (0, 1), (1, 1), (2, 1), (2, 0)]);
/// assert_eq!(plan.length_cells, 4.0);
/// grid.set(1, 1, Occupancy::Occupied).unwrap();
/// assert_eq!(astar(&grid, (0, 0), (2, 0), &AstarOptions::default()).unwrap(), None);
/// assert!(astar(&grid, (0, 0), (1, 1), &AstarOptions::default()).is_err());
/// ```
pub fn astar(
    grid: &OccupancyGrid,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    opts: &AstarOptions,
) -> Result<Option<Plan>> {
    AstarSearch::new().search(grid, start, goal, opts)
}
