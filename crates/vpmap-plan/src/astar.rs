//! A* on the 8-connected grid with octile costs: the grid-path baseline.
//!
//! Semantics: the robot moves between the centres of 8-neighbouring traversable cells. A
//! straight step costs 1 and needs its target cell traversable; a diagonal step costs
//! `sqrt 2` and needs its target **and both orthogonal neighbours** traversable (no corner
//! cutting, no squeezing between two blocked cells that share a corner). These are exactly
//! the single steps that [`crate::los`] calls clear, and the movement model of the Moving
//! AI benchmarks, whose `.scen` optimal lengths this search reproduces. Cells outside the
//! grid and [`Cell::Occupied`] cells are never entered;
//! [`Cell::Unknown`] cells only with
//! [`AstarOptions::unknown_passable`].
//!
//! The search uses the octile distance heuristic (consistent, so each cell is expanded at
//! most once and the first goal expansion is optimal), a binary heap ordered by `f = g + h`
//! with ties broken towards larger `g` (deeper nodes) and then larger cell index, and flat
//! arrays indexed by cell. Path costs and heuristic values are kept as exact counts of
//! straight and diagonal steps, so the reported length is `straight + diagonal * sqrt 2`
//! to the last bit and equal priorities compare equal (the tie-break then really prefers
//! deeper nodes, which saves most expansions on open ground).

use std::collections::BinaryHeap;
use std::f64::consts::SQRT_2;

use crate::error::Result;
use crate::grid::{Cell, OccupancyGrid};
use crate::plan::{Plan, PlanStats, check_endpoint};

/// Options of [`astar`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AstarOptions {
    /// Whether [`Cell::Unknown`] cells may be entered (default: no).
    pub unknown_passable: bool,
}

/// The 8 moves `(dx, dy)`, straight ones first.
const MOVES: [(i64, i64); 8] = [
    (1, 0),
    (0, 1),
    (-1, 0),
    (0, -1),
    (1, 1),
    (-1, 1),
    (-1, -1),
    (1, -1),
];

/// No parent: the start cell.
const NO_PARENT: u32 = u32::MAX;

/// Per-cell search state, valid when `mark` belongs to the current search.
#[derive(Clone, Copy, Debug, Default)]
struct NodeState {
    /// Straight and diagonal steps of the best path found to this cell.
    steps: [u32; 2],
    /// Index of the previous cell on that path, or [`NO_PARENT`].
    parent: u32,
    /// `2 * generation` when open, `2 * generation + 1` when closed, anything else when
    /// untouched by the current search.
    mark: u32,
}

/// An open-list entry. The heap pops the largest `key`: the smallest `f`, then the largest
/// `g` (both non-negative, so their IEEE bit patterns order like the values), then the
/// largest cell index.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Entry {
    key: u128,
    node: u32,
}

impl Entry {
    fn new(f: f64, g: f64, node: u32) -> Self {
        let key = (u128::from(!f.to_bits()) << 64) | u128::from(g.to_bits());
        Self { key, node }
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
fn octile_steps(a: (usize, usize), b: (usize, usize)) -> [u32; 2] {
    let dx = a.0.abs_diff(b.0);
    let dy = a.1.abs_diff(b.1);
    let (long, short) = if dx >= dy { (dx, dy) } else { (dy, dx) };
    [(long - short) as u32, short as u32]
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
/// # Example
/// ```
/// use vpmap_plan::{Cell, OccupancyGrid, astar::{AstarOptions, AstarSearch}};
/// let grid = OccupancyGrid::new(8, 8, 1.0, [0.0; 2], Cell::Free).unwrap();
/// let mut search = AstarSearch::new();
/// for goal in [(7, 7), (7, 0), (3, 5)] {
///     let plan = search.search(&grid, (0, 0), goal, &AstarOptions::default()).unwrap().unwrap();
///     assert_eq!(plan.waypoints.last(), Some(&goal));
/// }
/// ```
#[derive(Clone, Debug, Default)]
pub struct AstarSearch {
    nodes: Vec<NodeState>,
    generation: u32,
    open: BinaryHeap<Entry>,
}

impl AstarSearch {
    /// A search with no memory allocated yet.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Size the arrays for `cells` cells and start a new generation; returns the
    /// `(open, closed)` marks of this search.
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

    /// Find a shortest 8-connected path from `start` to `goal` (see [`astar`]).
    ///
    /// # Errors
    /// As [`astar`].
    pub fn search(
        &mut self,
        grid: &OccupancyGrid,
        start: (usize, usize),
        goal: (usize, usize),
        opts: &AstarOptions,
    ) -> Result<Option<Plan>> {
        check_endpoint(grid, "start", start, opts.unknown_passable)?;
        check_endpoint(grid, "goal", goal, opts.unknown_passable)?;
        let unknown_passable = opts.unknown_passable;
        let cells = grid.cells();
        let width = grid.width();
        let (width_i, height_i) = (width as i64, grid.height() as i64);
        let (open_mark, closed_mark) = self.begin(width * grid.height());
        let mut stats = PlanStats::default();
        // Cell counts are below MAX_CELLS < u32::MAX, so indices fit in u32.
        let start_index = start.1 * width + start.0;
        let goal_index = goal.1 * width + goal.0;
        if let Some(node) = self.nodes.get_mut(start_index) {
            *node = NodeState {
                steps: [0, 0],
                parent: NO_PARENT,
                mark: open_mark,
            };
        }
        self.open.push(Entry::new(
            octile_length(octile_steps(start, goal)),
            0.0,
            start_index as u32,
        ));
        stats.generated += 1;
        while let Some(Entry { node, .. }) = self.open.pop() {
            let index = node as usize;
            let Some(state) = self.nodes.get_mut(index) else {
                continue;
            };
            if state.mark == closed_mark {
                continue; // a stale entry: the cell was expanded with a smaller cost
            }
            state.mark = closed_mark;
            let steps = state.steps;
            stats.expanded += 1;
            if index == goal_index {
                return Ok(Some(self.plan(width, goal_index, steps, stats)));
            }
            let (x, y) = ((index % width) as i64, (index / width) as i64);
            // Passability of the 3 x 3 block around (x, y), row-major, looked up once.
            let mut passable = [false; 9];
            for (k, slot) in passable.iter_mut().enumerate() {
                let (u, v) = (x + k as i64 % 3 - 1, y + k as i64 / 3 - 1);
                *slot = k != 4
                    && (0..width_i).contains(&u)
                    && (0..height_i).contains(&v)
                    && cells.get((v * width_i + u) as usize).is_some_and(|&c| {
                        c == Cell::Free || (unknown_passable && c == Cell::Unknown)
                    });
            }
            for (dx, dy) in MOVES {
                let at = |dx: i64, dy: i64| {
                    passable
                        .get(((dy + 1) * 3 + dx + 1) as usize)
                        .copied()
                        .unwrap_or(false)
                };
                let diagonal = dx != 0 && dy != 0;
                if !at(dx, dy) || (diagonal && !(at(dx, 0) && at(0, dy))) {
                    continue;
                }
                let (nx, ny) = (x + dx, y + dy);
                let next_index = ny as usize * width + nx as usize;
                let Some(next) = self.nodes.get_mut(next_index) else {
                    continue;
                };
                if next.mark == closed_mark {
                    continue;
                }
                let next_steps = if diagonal {
                    [steps[0], steps[1] + 1]
                } else {
                    [steps[0] + 1, steps[1]]
                };
                let g = octile_length(next_steps);
                if next.mark == open_mark && octile_length(next.steps) <= g {
                    continue;
                }
                *next = NodeState {
                    steps: next_steps,
                    parent: node,
                    mark: open_mark,
                };
                let h = octile_steps((nx as usize, ny as usize), goal);
                self.open
                    .push(Entry::new(priority(next_steps, h), g, next_index as u32));
                stats.generated += 1;
            }
        }
        Ok(None)
    }

    /// The plan ending at `goal_index`, following parents back to the start.
    fn plan(&self, width: usize, goal_index: usize, steps: [u32; 2], stats: PlanStats) -> Plan {
        let mut waypoints = Vec::with_capacity((steps[0] + steps[1]) as usize + 1);
        let mut index = goal_index;
        // A parent chain is at most as long as the number of cells.
        for _ in 0..=self.nodes.len() {
            waypoints.push((index % width, index / width));
            match self.nodes.get(index) {
                Some(state) if state.parent != NO_PARENT => index = state.parent as usize,
                _ => break,
            }
        }
        waypoints.reverse();
        Plan {
            waypoints,
            length: octile_length(steps),
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
/// `O(n log n)` time for `n` reachable cells, 16 bytes per grid cell.
///
/// # References
/// P. E. Hart, N. J. Nilsson, B. Raphael, "A Formal Basis for the Heuristic Determination
/// of Minimum Cost Paths", IEEE Transactions on Systems Science and Cybernetics 4(2), 1968.
///
/// # Example
/// ```
/// use vpmap_plan::{Cell, OccupancyGrid, astar::{astar, AstarOptions}};
/// // .#.
/// // ...
/// let mut grid = OccupancyGrid::new(3, 2, 1.0, [0.0; 2], Cell::Free).unwrap();
/// grid.set(1, 0, Cell::Occupied).unwrap();
/// let plan = astar(&grid, (0, 0), (2, 0), &AstarOptions::default()).unwrap().unwrap();
/// // No corner cutting around (1, 0): down, across, up.
/// assert_eq!(plan.waypoints, [(0, 0), (0, 1), (1, 1), (2, 1), (2, 0)]);
/// assert_eq!(plan.length, 4.0);
/// grid.set(1, 1, Cell::Occupied).unwrap();
/// assert_eq!(astar(&grid, (0, 0), (2, 0), &AstarOptions::default()).unwrap(), None);
/// assert!(astar(&grid, (0, 0), (1, 1), &AstarOptions::default()).is_err());
/// ```
pub fn astar(
    grid: &OccupancyGrid,
    start: (usize, usize),
    goal: (usize, usize),
    opts: &AstarOptions,
) -> Result<Option<Plan>> {
    AstarSearch::new().search(grid, start, goal, opts)
}
