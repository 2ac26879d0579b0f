//! The exact shortest any-angle path, fast: an Anya-style interval search (Harabor,
//! Grastien, Öz and Aksakalli 2016; the same search as Polyanya, Cui, Harabor and
//! Grastien 2017, on a mesh of rectangles) over the free space of the collision rule of
//! [`crate::los`], with the free space built once per grid ([`ExactPlanner::new`]).
//!
//! # The free space, exactly
//! In cell-centre coordinates the robot's centre may go anywhere outside the open squares
//! of side 2 centred on blocked cells (outside the grid counts as blocked; see
//! [`crate::optimal`]). Cut that closed set along the horizontal lines `Y = y` through
//! the cell centres:
//! - **on a row line** `Y = y` a point `(X, y)` is free exactly when every cell centre
//!   within Chebyshev distance below 1 of it is free: for `x < X < x + 1` the cells
//!   `(x, y)` and `(x + 1, y)`, for `X = x` the cell `(x, y)`. So the row line's free set
//!   is the union of the closed intervals `[a, b]` spanned by the maximal runs of free
//!   cells `a..=b` of row `y` (a run of one cell is a point);
//! - **in the open strip** `y < Y < y + 1` the cross-section is the same at every height:
//!   `X` is free exactly when the columns `floor(X)` and `ceil(X)` are both *double free*
//!   (the cells of rows `y` and `y + 1` free). So the strip's free set is a union of
//!   disjoint closed rectangles `[a, b] x [y, y + 1]`, one per maximal run `a..=b` of
//!   double-free columns, at least 2 apart; a run of one column is a zero-width vertical
//!   corridor. Each rectangle's top and bottom edges lie in runs of the two row lines.
//!
//! So the free space is a mesh of convex pieces (rectangles, possibly of zero width, and
//! row-line intervals, possibly of zero length) that meet only along the row lines, with
//! every vertex at a cell centre, and zero-width corridors are pieces like any other (no
//! relaxation is needed). A segment that leaves a row line into a strip stays in one
//! rectangle until the next row line (the cross-section is a union of disjoint closed
//! intervals and the segment's `X` varies continuously).
//!
//! # Search
//! A node is a root `r` (a cell centre, the start or a turning point, with the exact
//! length `g(r)` of the path that reaches it) and an interval `I` of a row line every
//! point of which `r` sees. A **cone** node (`r` off the row) is expanded into the strip
//! beyond the row: per rectangle `[a, b]` of that strip meeting `I`, the rays from `r`
//! through `I` projected onto the next row line and clipped to `[a, b]` give the
//! *observable* successor (same root); what of `[a, b]` lies left or right of that
//! projection is seen from the interval's end on that side when that end is a cell centre
//! (an integer), which becomes the root of a *non-observable* successor. A cone node also
//! turns at an integer end of its interval onto its row line (a **flat** node: root on
//! the row, the rest of the row's run beyond). A flat node turns at every rectangle side
//! beyond its root in the strips above and below (the whole top or bottom edge of that
//! rectangle, seen from that side's end). Nodes are ordered by `f = g(r) + h`, with `h`
//! the Euclidean length of the shortest path from `r` through `I` to the goal (the goal
//! mirrored through the row line when it lies on the root's side), which is admissible.
//! A node whose interval holds the goal gives a final entry with `f = g(r) + |r goal|`;
//! the first final entry taken off the open list is the answer. Polyanya's root-level
//! pruning keeps, per cell centre, the least `g` with which it has become a root, and
//! drops successors rooted there with a larger one. A cone node whose only successor is
//! its observable one (no turning point, not the goal's row) is expanded at once, row
//! after row, without the open list (Polyanya's intermediate pruning): a cone crosses an
//! open area in one step of the open list instead of one per row. A node entering a dead
//! end (a chain of rectangles with one way out, found in the build) that does not hold
//! the goal is dropped.
//!
//! Turning points are cell centres, so the path is a polyline through cell centres like
//! every other planner's, and its length is summed like theirs ([`crate::path_length`]).
//! Interval ends are `f64`; an end within `1e-9` of an integer is that integer (a
//! non-integer end is the crossing of a row line by the line through two cell centres at
//! most `height` rows apart, so it is at least `1 / height` from any integer).
//!
//! # Why it is exact
//! A shortest path is taut and bends only at cell centres ([`crate::optimal`]). Between
//! two bends it is a segment, which crosses the row lines in turn and lies in one
//! rectangle between two consecutive crossings, or runs along one row line. By induction
//! over the bends, every point `q` of a row line on a shortest path to the goal with last
//! bend `t` lies in the interval of some node rooted at `t` with `g(t)` optimal: from
//! `t`'s own node the observable successors follow the segment strip by strip, as long
//! as it stays in the projected cone; where the next bend `t'` lies at the end of that
//! cone on a row line, `t'` is an integer end of the projected interval (or a rectangle
//! side inside it), and the non-observable or flat successors rooted at `t'` contain the
//! next segment's first crossing. Bends are corner cells ([`crate::optimal`]'s proof),
//! so successors are rooted at corner cells only; generating more successors than the
//! taut ones (the planner does, where deciding tautness costs more than the node) only
//! adds feasible paths. Root-level pruning drops a node only when its root is reached by a
//! path at least as short, and any continuation from the dropped arrival is then at least
//! as long as the same continuation from the better one (Cui et al. 2017, section 5).
//! Dead-end pruning drops only paths that leave a region through the row line they
//! entered it by, which a segment along that line shortens.
//! The tests check the answer against the visibility graph of [`crate::optimal`] to
//! `1e-9` on thousands of random grids (mazes, rooms, spirals, diagonal walls with gaps,
//! cells touching at corners) and on Moving AI maps.
//!
//! # References
//! - D. Harabor, A. Grastien, D. Öz, V. Aksakalli, "Optimal Any-Angle Pathfinding In
//!   Practice", Journal of Artificial Intelligence Research 56, 2016 (Anya).
//! - M. Cui, D. Harabor, A. Grastien, "Compromise-free Pathfinding on a Navigation Mesh",
//!   IJCAI 2017 (Polyanya, root-level pruning).
//!
//! # Files
//! - `space.rs`: the free space cut into row-line runs and strip rectangles, with its corner
//!   cells, built once per grid;
//! - `dead_ends.rs`: dead-end pruning, its table built with the free space;
//! - `search.rs`: one query's interval search (nodes, roots, expansions, root-level and
//!   intermediate pruning);
//! - this file: [`ExactPlanner`], which holds the free space and runs the queries.

mod dead_ends;
mod search;
mod space;

use crate::budget::Budget;
use crate::error::Result;
use crate::grid::{CellXy, OccupancyGrid};
use crate::plan::{Plan, PlanStats, check_endpoint, path_length, xy};

use search::{PLANNER, Scratch, Search, trace};
use space::FreeSpace;

/// The exact any-angle planner with its free space built once for a grid (see the
/// [module docs](self)): build with [`ExactPlanner::new`], then ask any number of
/// [`ExactPlanner::plan`] queries.
///
/// # Example
/// ```
/// use vpmap_plan::{Budget, Occupancy, OccupancyGrid, anya::ExactPlanner};
/// // .....
/// // ..#..
/// // .....
/// let mut grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// grid.set(2, 1, Occupancy::Occupied).unwrap();
/// let mut planner = ExactPlanner::new(&grid, false);
/// let plan = planner.plan((0, 1), (4, 1), &Budget::default()).unwrap().unwrap();
/// assert_eq!(plan.waypoints.len(), 4);
/// assert!((plan.length_cells - (2.0 + 2.0 * 2f64.sqrt())).abs() < 1e-12);
/// ```
#[derive(Clone, Debug)]
pub struct ExactPlanner {
    grid: OccupancyGrid,
    unknown_passable: bool,
    /// The free space of `grid`: runs, rectangles, corner cells and dead ends.
    space: FreeSpace,
    /// Scratch of the searches: per cell, the index of its root with the least `g` in the
    /// current search, valid only when that root is at this cell (so nothing is reset
    /// between queries, and the zeroed table costs no pass over the grid to build).
    root_of: Vec<u32>,
    /// The searches' buffers, kept between queries.
    scratch: Scratch,
}

impl ExactPlanner {
    /// Build the free space of `grid` (unknown cells passable or not).
    ///
    /// # Complexity
    /// One pass over the grid; about 6 bytes a cell (a copy of the grid, a corner flag and a
    /// root slot per cell; the runs, rectangles and dead ends per row), 8 bytes a cell of peak
    /// memory with a search that reaches every cell (`scripts/limits-table.sh`).
    #[must_use]
    pub fn new(grid: &OccupancyGrid, unknown_passable: bool) -> Self {
        Self {
            grid: grid.clone(),
            unknown_passable,
            space: FreeSpace::new(grid, unknown_passable),
            root_of: vec![0; grid.width() * grid.height()],
            scratch: Scratch::default(),
        }
    }

    /// Whether this planner was built for `grid` with `unknown_passable` (for callers that
    /// cache it across queries).
    #[must_use]
    pub fn is_for(&self, grid: &OccupancyGrid, unknown_passable: bool) -> bool {
        // The same revision is the same cells (a clone neither changed since): no need to
        // compare them.
        self.unknown_passable == unknown_passable
            && (self.grid.revision() == grid.revision() || self.grid == *grid)
    }

    /// The exact shortest any-angle path from `start` to goal under the rule of
    /// [`crate::los`], as a polyline through cell centres; `Ok(None)` when the goal cannot
    /// be reached. `budget.max_expansions` counts search nodes expanded (taken off the
    /// open list, or a cone's intermediate rows); `budget.max_sight_cells` does not apply
    /// (no line-of-sight queries); the stop is looked at every few thousand expansions.
    ///
    /// # Errors
    /// [`PlanError::EndpointOutsideGrid`](crate::PlanError::EndpointOutsideGrid),
    /// [`PlanError::EndpointBlocked`](crate::PlanError::EndpointBlocked) for a bad start
    /// or goal, [`PlanError::BudgetExhausted`](crate::PlanError::BudgetExhausted) and
    /// [`PlanError::Stopped`](crate::PlanError::Stopped) when the budget says so.
    pub fn plan(
        &mut self,
        start: impl Into<CellXy>,
        goal: impl Into<CellXy>,
        budget: &Budget,
    ) -> Result<Option<Plan>> {
        let (start, goal) = (xy(start), xy(goal));
        check_endpoint(&self.grid, "start", start, self.unknown_passable)?;
        check_endpoint(&self.grid, "goal", goal, self.unknown_passable)?;
        budget.stop.check(PLANNER)?;
        let mut scratch = std::mem::take(&mut self.scratch);
        scratch.clear();
        let mut search = Search {
            space: &self.space,
            root_of: &mut self.root_of,
            goal: (goal.0 as i32, goal.1 as i32),
            s: scratch,
            stats: PlanStats::default(),
        };
        let found = search.run((start.0 as i32, start.1 as i32), budget);
        let (stats, scratch) = (search.stats, search.s);
        let chain = found.map(|found| found.map(|root| trace(&scratch.roots, root, goal)));
        self.scratch = scratch;
        let Some(chain) = chain? else {
            return Ok(None);
        };
        let length_cells = path_length(&chain);
        Ok(Some(Plan {
            waypoints: chain,
            length_cells,
            stats,
        }))
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::float_cmp)]
mod tests {
    use super::*;
    use crate::grid::Occupancy;

    #[test]
    fn one_cell_corridors_are_followed_along_their_centre_line() {
        // .#...
        // .#.#.
        // ...#.
        let mut grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        for (x, y) in [(1, 0), (1, 1), (3, 1), (3, 2)] {
            grid.set(x, y, Occupancy::Occupied).unwrap();
        }
        let mut planner = ExactPlanner::new(&grid, false);
        let plan = planner
            .plan((0, 0), (4, 2), &Budget::default())
            .unwrap()
            .unwrap();
        assert_eq!(
            plan.waypoints,
            [(0, 0), (0, 2), (2, 2), (2, 0), (4, 0), (4, 2)]
        );
        assert_eq!(plan.length_cells, 10.0);
        grid.set(2, 1, Occupancy::Occupied).unwrap();
        let mut planner = ExactPlanner::new(&grid, false);
        assert_eq!(
            planner.plan((0, 0), (4, 2), &Budget::default()).unwrap(),
            None
        );
    }
}
