//! Basic Theta* (Nash et al. 2007): A* on the 8-connected grid whose nodes may take any
//! earlier node in line of sight as parent, giving any-angle paths.
//!
//! Semantics: the search expands cells like [`crate::astar`](mod@crate::astar) (8
//! neighbours; a diagonal step needs both orthogonal neighbours traversable, which is
//! exactly when [`crate::los`] calls the single step clear). When it reaches neighbour `s'`
//! of cell `s`, it first tries "path 2": if the segment from `parent(s)` to `s'` is clear
//! under the rule of [`crate::los`], `s'` is offered `g(parent(s)) + |parent(s) s'|` with
//! parent `parent(s)`; otherwise "path 1", `g(s) + |s s'|` with parent `s`. The start is its
//! own parent (its neighbours take path 1 without a query, since a single step is clear
//! exactly when it is a legal move). Costs are Euclidean distances between cell centres,
//! the heuristic is the Euclidean distance to the goal, and the open list is a binary heap
//! ordered by `f = g + h`, ties towards larger `g`, then larger cell index. A cell is
//! expanded at most once.
//!
//! Every segment of the result is clear, but the path is not always a shortest one: a
//! parent is only ever a parent of an expanded neighbour, so paths stay close to the
//! grid's topology (compare [`crate::optimal`]).
//!
//! # References
//! A. Nash, K. Daniel, S. Koenig, A. Felner, "Theta*: Any-Angle Path Planning on Grids",
//! AAAI 2007.

use std::collections::BinaryHeap;

use crate::budget::Budget;
use crate::error::Result;
use crate::grid::{CellXy, MOVES, OccupancyGrid};
use crate::los::{LosCounter, Passable, PassableGrid};
use crate::plan::{Plan, PlanStats, cells_of, check_endpoint, path_length, xy};

/// Options of [`theta_star`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ThetaStarOptions {
    /// Whether [`Occupancy::Unknown`](crate::Occupancy::Unknown) cells may be entered (default: no).
    pub unknown_passable: bool,
    /// Most work before the search stops with an error (default: [`Budget::default`]).
    pub budget: Budget,
}

/// An open-list entry of a best-first search over `f64` costs. The heap pops the largest
/// `key`: the smallest `f`, then the largest `g` (both non-negative, so their IEEE bit
/// patterns order like the values), then the largest node number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct Entry {
    key: u128,
    /// The node.
    pub(crate) node: u32,
}

impl Entry {
    /// An entry for `node` with priority `f` and cost so far `g`.
    pub(crate) fn new(f: f64, g: f64, node: u32) -> Self {
        let key = (u128::from(!f.to_bits()) << 64) | u128::from(g.to_bits());
        Self { key, node }
    }
}

/// Euclidean distance between two cell centres, cells.
#[inline]
pub(crate) fn distance(a: (usize, usize), b: (usize, usize)) -> f64 {
    (a.0.abs_diff(b.0) as f64).hypot(a.1.abs_diff(b.1) as f64)
}

/// Follow `parent` links from `goal_index` back to a node that is its own parent.
pub(crate) fn trace_back(parent: &[u32], width: usize, goal_index: usize) -> Vec<(usize, usize)> {
    let mut waypoints = Vec::new();
    let mut index = goal_index;
    // A parent chain is at most as long as the number of cells.
    for _ in 0..=parent.len() {
        waypoints.push((index % width, index / width));
        match parent.get(index) {
            Some(&p) if p as usize != index => index = p as usize,
            _ => break,
        }
    }
    waypoints.reverse();
    waypoints
}

/// An any-angle path from `start` to `goal` by Basic Theta* (see the [module docs](self)).
/// The waypoints are the path's turning points, start and goal included; `Ok(None)` when
/// the goal cannot be reached. Each segment is clear under the rule of [`crate::los`].
///
/// # Errors
/// [`PlanError::EndpointOutsideGrid`](crate::PlanError::EndpointOutsideGrid) when `start`
/// or `goal` is outside the grid,
/// [`PlanError::EndpointBlocked`](crate::PlanError::EndpointBlocked) when it is not
/// traversable.
///
/// # Complexity
/// `O(n log n)` heap work for `n` reachable cells plus up to 8 line-of-sight queries per
/// expansion, each `O(cells swept)`; 24 bytes per grid cell.
///
/// # References
/// A. Nash, K. Daniel, S. Koenig, A. Felner, "Theta*: Any-Angle Path Planning on Grids",
/// AAAI 2007.
///
/// # Example
/// ```
/// use vpmap_plan::{CellXy, Occupancy, OccupancyGrid, theta_star::{theta_star, ThetaStarOptions}};
/// // ....
/// // .#..
/// // ....
/// let mut grid = OccupancyGrid::new(4, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// grid.set(1, 1, Occupancy::Occupied).unwrap();
/// let opts = ThetaStarOptions::default();
/// let plan = theta_star(&grid, (0, 2), (3, 0), &opts).unwrap().unwrap();
/// assert_eq!(plan.waypoints.first(), Some(&CellXy::new(0, 2)));
/// assert_eq!(plan.waypoints.last(), Some(&CellXy::new(3, 0)));
/// assert!(plan.length_cells < 3.0 + 2f64.sqrt()); // shorter than any grid path
/// ```
pub fn theta_star(
    grid: &OccupancyGrid,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    opts: &ThetaStarOptions,
) -> Result<Option<Plan>> {
    let (start, goal) = (xy(start), xy(goal));
    check_endpoint(grid, "start", start, opts.unknown_passable)?;
    check_endpoint(grid, "goal", goal, opts.unknown_passable)?;
    opts.budget.stop.check("Theta*")?;
    let passable = PassableGrid::new(grid, opts.unknown_passable);
    let width = grid.width();
    let cells = width * grid.height();
    let mut g = vec![f64::INFINITY; cells];
    // Cell counts are below MAX_CELLS < u32::MAX, so indices fit in u32.
    let mut parent = vec![u32::MAX; cells];
    let mut closed = vec![false; cells];
    let mut open = BinaryHeap::new();
    let mut stats = PlanStats::default();
    let mut counter = LosCounter::default();
    let start_index = start.1 * width + start.0;
    let goal_index = goal.1 * width + goal.0;
    if let (Some(gs), Some(ps)) = (g.get_mut(start_index), parent.get_mut(start_index)) {
        *gs = 0.0;
        *ps = start_index as u32;
    }
    open.push(Entry::new(distance(start, goal), 0.0, start_index as u32));
    stats.generated += 1;
    while let Some(Entry { node, .. }) = open.pop() {
        let index = node as usize;
        match closed.get_mut(index) {
            Some(c) if !*c => *c = true,
            _ => continue, // a stale entry: the cell was expanded with a smaller cost
        }
        stats.expanded += 1;
        opts.budget
            .check("Theta*", stats.expanded, counter.cells, stats.expanded)?;
        if index == goal_index {
            let waypoints = cells_of(trace_back(&parent, width, goal_index));
            let length_cells = path_length(&waypoints);
            stats.los_checks = counter.checks;
            stats.los_cells = counter.cells;
            return Ok(Some(Plan {
                waypoints,
                length_cells,
                stats,
            }));
        }
        let cell = (index % width, index / width);
        let g_cell = g.get(index).copied().unwrap_or(f64::INFINITY);
        let parent_index = parent.get(index).map_or(index, |&p| p as usize);
        let parent_cell = (parent_index % width, parent_index / width);
        let g_parent = g.get(parent_index).copied().unwrap_or(f64::INFINITY);
        let (x, y) = (cell.0 as i64, cell.1 as i64);
        for (dx, dy) in MOVES.map(|(dx, dy)| (dx as i64, dy as i64)) {
            if !passable.step_clear((x, y), (dx, dy)) {
                continue;
            }
            let next = ((x + dx) as usize, (y + dy) as usize);
            let next_index = next.1 * width + next.0;
            if closed.get(next_index).is_none_or(|&c| c) {
                continue;
            }
            let (candidate_g, candidate_parent) = if parent_index != index
                && passable.sight_counted(parent_cell, next, &mut counter)
            {
                (g_parent + distance(parent_cell, next), parent_index)
            } else {
                (g_cell + distance(cell, next), index)
            };
            if let (Some(gn), Some(pn)) = (g.get_mut(next_index), parent.get_mut(next_index))
                && candidate_g < *gn
            {
                *gn = candidate_g;
                *pn = candidate_parent as u32;
                open.push(Entry::new(
                    candidate_g + distance(next, goal),
                    candidate_g,
                    next_index as u32,
                ));
                stats.generated += 1;
            }
        }
    }
    Ok(None)
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::float_cmp)]
mod tests {
    use super::*;
    use crate::grid::Occupancy;

    #[test]
    fn open_grid_gives_a_straight_segment() {
        let grid = OccupancyGrid::new(9, 5, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        let plan = theta_star(&grid, (0, 0), (8, 3), &ThetaStarOptions::default())
            .unwrap()
            .unwrap();
        assert_eq!(plan.waypoints, [(0, 0), (8, 3)]);
        assert!((plan.length_cells - 73f64.sqrt()).abs() < 1e-12);
        assert!(plan.stats.los_checks > 0);
    }

    #[test]
    fn start_equal_to_goal_and_unreachable_goal() {
        let mut grid = OccupancyGrid::new(3, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        let opts = ThetaStarOptions::default();
        let plan = theta_star(&grid, (1, 1), (1, 1), &opts).unwrap().unwrap();
        assert_eq!(plan.waypoints, [(1, 1)]);
        assert_eq!(plan.length_cells, 0.0);
        for (x, y) in [(1, 0), (0, 1)] {
            grid.set(x, y, Occupancy::Occupied).unwrap();
        }
        // (0, 0) is cut off: the diagonal step to (1, 1) would cut both corners.
        assert_eq!(theta_star(&grid, (0, 0), (2, 2), &opts).unwrap(), None);
    }
}
