//! The exact shortest any-angle path under the collision rule of [`crate::los`]:
//! [`optimal_any_angle`] (the fast interval search of [`crate::anya`]) and its reference
//! [`visibility_graph_any_angle`], A* on the visibility graph of the start, the goal and the
//! grid's convex corner cells, which the rest of these docs describe.
//!
//! # Why it is exact
//! Under the rule of [`crate::los`] the robot's centre may go anywhere outside the open
//! squares of side 2 centred on the blocked cells' centres (cells outside the grid count
//! as blocked), and a segment between two cell centres is clear exactly when it enters
//! none of them. In centre coordinates these squares have integer corners, which are cell
//! centres. A shortest path in this closed polygonal free space is taut: a polyline that
//! bends only at convex vertices of the obstacles, wrapping them (otherwise a bend could
//! be cut short). Where can a taut path bend at a point `c`? Near `c` each blocked
//! neighbour of `c` covers an open quadrant (a diagonal neighbour) or an open half-plane
//! (an orthogonal neighbour). A bend turning by less than 180 degrees must have an
//! obstacle inside its angle while both of its legs stay out of the open obstacle
//! regions, so the inside of the angle holds exactly one blocked quadrant `(dx, dy)`, due
//! to the diagonal neighbour `c + (dx, dy)`, and neither orthogonal neighbour
//! `c + (dx, 0)`, `c + (0, dy)` may be blocked (each would cover a half-plane that one leg
//! must cross). So the bends of a shortest path are among the **corner cells**: free cells
//! `c` with a direction `(dx, dy)` whose diagonal neighbour is blocked while both
//! orthogonal neighbours are free. A blocked diagonal neighbour outside the grid never
//! qualifies (one of the two orthogonal neighbours is then outside too): the border is
//! straight. Two blocked cells touching at a corner give each of the free cells between
//! them a corner on either side; the path may pass between them through that cell centre.
//!
//! Hence the shortest path from start to goal is a shortest path in the graph whose nodes
//! are the start, the goal and the corner cells, with an edge of Euclidean length between
//! every two nodes in line of sight, and A* with the (consistent) Euclidean heuristic
//! finds it. The turning points are cell centres, so the result is also the shortest
//! polyline through cell centres. Extra nodes would never break this; the criterion adds
//! a few that no shortest path needs (a corner cell whose other side is blocked too).
//!
//! # Search
//! Edges are generated lazily: when a node is expanded, every node not yet expanded whose
//! cost could improve is tried, and the line-of-sight query is made only then. Costs are
//! `f64` sums of Euclidean segment lengths, the open list a binary heap ordered by
//! `f = g + h`, ties towards larger `g`.
//!
//! # Complexity
//! `O(V^2)` line-of-sight queries in the worst case for `V` corner cells (each expansion
//! tries every node), each `O(cells swept)`, plus `O(width x height)` to find the corners:
//! a reference for tests and small maps, not a fast planner.
//!
//! # References
//! - T. Lozano-Pérez, M. A. Wesley, "An Algorithm for Planning Collision-Free Paths Among
//!   Polyhedral Obstacles", Communications of the ACM 22(10), 1979 (visibility graphs).
//! - T. Uras, S. Koenig, "An Empirical Comparison of Any-Angle Path-Planning Algorithms",
//!   SoCS 2015 (the grid corner criterion of visibility graphs and subgoal graphs).

use std::collections::BinaryHeap;

pub use crate::corners::corner_cells;

use crate::anya::ExactPlanner;
use crate::budget::Budget;
use crate::corners::corners_of;
use crate::error::Result;
use crate::grid::{CellXy, OccupancyGrid};
use crate::los::{LosCounter, Passable, PassableGrid};
use crate::plan::{Plan, PlanStats, check_endpoint, path_length, xy};
use crate::theta_star::{Entry, distance, trace_back};

/// Options of [`optimal_any_angle`] and [`visibility_graph_any_angle`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OptimalAnyAngleOptions {
    /// Whether [`Occupancy::Unknown`](crate::Occupancy::Unknown) cells may be entered (default: no).
    pub unknown_passable: bool,
    /// Most work before the search stops with an error (default: [`Budget::default`]).
    pub budget: Budget,
}

/// The planner's name in errors.
const PLANNER: &str = "the exact any-angle planner";

/// The exact shortest any-angle path from `start` to `goal` under the rule of
/// [`crate::los`] by the visibility graph (see the [module docs](self)): a polyline through
/// cell centres, turning only at corner cells. `Ok(None)` when the goal cannot be reached.
/// The slow reference of [`optimal_any_angle`] in the tests.
///
/// # Errors
/// [`PlanError::EndpointOutsideGrid`](crate::PlanError::EndpointOutsideGrid) when `start`
/// or `goal` is outside the grid,
/// [`PlanError::EndpointBlocked`](crate::PlanError::EndpointBlocked) when it is not
/// traversable.
///
/// # Complexity
/// `O(V^2)` line-of-sight queries for `V` corner cells, each `O(cells swept)`, plus
/// `O(width x height)`.
///
/// # References
/// T. Lozano-Pérez, M. A. Wesley, "An Algorithm for Planning Collision-Free Paths Among
/// Polyhedral Obstacles", Communications of the ACM 22(10), 1979.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, optimal::{visibility_graph_any_angle, OptimalAnyAngleOptions}};
/// // .....
/// // ..#..
/// // .....
/// let mut grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// grid.set(2, 1, Occupancy::Occupied).unwrap();
/// let opts = OptimalAnyAngleOptions::default();
/// let plan = visibility_graph_any_angle(&grid, (0, 1), (4, 1), &opts).unwrap().unwrap();
/// // Around the corner cell (1, 0) or (1, 2) and its mirror image.
/// assert_eq!(plan.waypoints.len(), 4);
/// assert!((plan.length_cells - (2.0 + 2.0 * 2f64.sqrt())).abs() < 1e-12);
/// ```
pub fn visibility_graph_any_angle(
    grid: &OccupancyGrid,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    opts: &OptimalAnyAngleOptions,
) -> Result<Option<Plan>> {
    let (start, goal) = (xy(start), xy(goal));
    check_endpoint(grid, "start", start, opts.unknown_passable)?;
    check_endpoint(grid, "goal", goal, opts.unknown_passable)?;
    opts.budget.stop.check(PLANNER)?;
    let passable = PassableGrid::new(grid, opts.unknown_passable);
    let mut nodes = corners_of(&passable);
    for endpoint in [start, goal] {
        if !nodes.contains(&endpoint) {
            nodes.push(endpoint);
        }
    }
    let Some(start_node) = nodes.iter().position(|&c| c == start) else {
        return Ok(None);
    };
    let mut g = vec![f64::INFINITY; nodes.len()];
    // Node numbers are below the cell count < u32::MAX.
    let mut parent: Vec<u32> = (0..nodes.len() as u32).collect();
    let mut closed = vec![false; nodes.len()];
    let mut open = BinaryHeap::new();
    let mut stats = PlanStats::default();
    let mut counter = LosCounter::default();
    if let Some(gs) = g.get_mut(start_node) {
        *gs = 0.0;
    }
    open.push(Entry::new(distance(start, goal), 0.0, start_node as u32));
    stats.generated += 1;
    while let Some(Entry { node, .. }) = open.pop() {
        let u = node as usize;
        match closed.get_mut(u) {
            Some(c) if !*c => *c = true,
            _ => continue, // stale entry
        }
        stats.expanded += 1;
        opts.budget
            .check(PLANNER, stats.expanded, counter.cells, stats.expanded)?;
        let (Some(&from), Some(&g_from)) = (nodes.get(u), g.get(u)) else {
            continue;
        };
        if from == goal {
            // Parent links between node numbers (as `(0, node)` with width 1), mapped to cells.
            let chain = trace_back(&parent, 1, u);
            let waypoints: Vec<CellXy> = chain
                .iter()
                .filter_map(|&(_, n)| nodes.get(n).copied().map(CellXy::from))
                .collect();
            let length_cells = path_length(&waypoints);
            stats.los_checks = counter.checks;
            stats.los_cells = counter.cells;
            return Ok(Some(Plan {
                waypoints,
                length_cells,
                stats,
            }));
        }
        for (v, &to) in nodes.iter().enumerate() {
            let (Some(&done), Some(&g_to)) = (closed.get(v), g.get(v)) else {
                continue;
            };
            if done {
                continue;
            }
            let candidate = g_from + distance(from, to);
            if candidate >= g_to {
                continue;
            }
            // Each expansion may try every node: the budget is looked at per query too.
            opts.budget
                .check(PLANNER, stats.expanded, counter.cells, counter.checks + 1)?;
            if passable.sight_counted(from, to, &mut counter) {
                if let (Some(gv), Some(pv)) = (g.get_mut(v), parent.get_mut(v)) {
                    *gv = candidate;
                    *pv = u as u32;
                }
                open.push(Entry::new(
                    candidate + distance(to, goal),
                    candidate,
                    v as u32,
                ));
                stats.generated += 1;
            }
        }
    }
    Ok(None)
}

/// The exact shortest any-angle path from `start` to `goal` under the rule of
/// [`crate::los`]: [`ExactPlanner`] (an Anya-style interval search, see [`crate::anya`])
/// built for this one query. To ask several queries on one grid, build the
/// [`ExactPlanner`] once and call [`ExactPlanner::plan`]. The answer's length equals
/// [`visibility_graph_any_angle`]'s (the tests check it to 1e-9).
/// `opts.budget.max_expansions` counts interval nodes; `max_sight_cells` does not apply.
///
/// # Errors
/// As [`ExactPlanner::plan`].
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, optimal::{optimal_any_angle, OptimalAnyAngleOptions}};
/// let mut grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// grid.set(2, 1, Occupancy::Occupied).unwrap();
/// let plan = optimal_any_angle(&grid, (0, 1), (4, 1), &OptimalAnyAngleOptions::default())
///     .unwrap()
///     .unwrap();
/// assert!((plan.length_cells - (2.0 + 2.0 * 2f64.sqrt())).abs() < 1e-12);
/// ```
pub fn optimal_any_angle(
    grid: &OccupancyGrid,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    opts: &OptimalAnyAngleOptions,
) -> Result<Option<Plan>> {
    ExactPlanner::new(grid, opts.unknown_passable).plan(start, goal, &opts.budget)
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::float_cmp)]
mod tests {
    use super::*;
    use crate::grid::Occupancy;

    #[test]
    fn corners_of_cells_touching_at_a_corner() {
        // .#.
        // #..
        // ...
        let mut grid = OccupancyGrid::new(3, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        grid.set(1, 0, Occupancy::Occupied).unwrap();
        grid.set(0, 1, Occupancy::Occupied).unwrap();
        let corners = corner_cells(&grid, false);
        // (1, 1) is diagonal to no blocked cell; (2, 1) and (1, 2) wrap the two corners.
        assert_eq!(corners, [(2, 1), (1, 2)]);
    }

    #[test]
    fn wall_with_a_gap() {
        // .....
        // ##.##
        // .....
        let mut grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        for x in [0, 1, 3, 4] {
            grid.set(x, 1, Occupancy::Occupied).unwrap();
        }
        let opts = OptimalAnyAngleOptions::default();
        let plan = optimal_any_angle(&grid, (0, 0), (4, 2), &opts)
            .unwrap()
            .unwrap();
        assert_eq!(plan.waypoints, [(0, 0), (2, 0), (2, 2), (4, 2)]);
        assert_eq!(plan.length_cells, 6.0);
        assert_eq!(
            optimal_any_angle(&grid, (0, 0), (0, 0), &opts)
                .unwrap()
                .unwrap()
                .length_cells,
            0.0
        );
        grid.set(2, 1, Occupancy::Occupied).unwrap();
        assert_eq!(
            optimal_any_angle(&grid, (0, 0), (4, 2), &opts).unwrap(),
            None
        );
    }
}
