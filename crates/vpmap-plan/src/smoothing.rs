//! A* with post-smoothing (A* PS): an 8-connected A* path, then shortcuts between its
//! waypoints wherever the collision rule of [`crate::los`] allows.
//!
//! # The smoothing variant
//! Greedy **farthest-visible** smoothing: the first waypoint is the first anchor; from an
//! anchor, the A* path's waypoints are tried from the **last one backwards**, and the first
//! one in line of sight of the anchor (that is, the farthest visible one along the path)
//! becomes the next kept waypoint and the next anchor. The waypoint right after the anchor
//! is taken without a check when no later one is visible (consecutive waypoints of the
//! input are assumed clear, as they are for an A* path). Waypoints have distinct indices,
//! so there are no ties to break.
//!
//! Why this variant rather than the incremental one of Botea et al. (2004), used for A* PS
//! by Nash et al. (2007), which walks forward and stops at the **first** waypoint out of
//! sight: visibility along a path is not monotone (a waypoint can be hidden behind a
//! corner while a later one is visible again), and the farthest-visible rule skips such
//! detours, so its paths are never longer than the polyline it shortcuts and usually a
//! little shorter than the incremental variant's (the two differ by about 0.5 % on
//! benchmark maps). It costs more line-of-sight checks; see [`smooth_path`].
//!
//! # References
//! - A. Botea, M. Müller, J. Schaeffer, "Near Optimal Hierarchical Path-Finding", Journal
//!   of Game Development 1(1), 2004.
//! - A. Nash, K. Daniel, S. Koenig, A. Felner, "Theta*: Any-Angle Path Planning on Grids",
//!   AAAI 2007.

use crate::astar::{AstarOptions, AstarSearch};
use crate::budget::Budget;
use crate::error::Result;
use crate::grid::{CellXy, OccupancyGrid};
use crate::los::{LosCounter, Passable, PassableGrid};
use crate::plan::{Plan, PlanStats, path_length};

/// Options of [`astar_ps`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AstarPsOptions {
    /// Whether [`Occupancy::Unknown`](crate::Occupancy::Unknown) cells may be entered (default: no).
    pub unknown_passable: bool,
    /// Most work before the search stops with an error (default: [`Budget::default`]).
    pub budget: Budget,
}

/// Shorten a path whose consecutive waypoints are clear under the rule of [`crate::los`]
/// by greedy farthest-visible smoothing (see the [module docs](self)): keep the first
/// waypoint, then repeatedly jump to the farthest later waypoint in line of sight of the
/// last kept one. Line-of-sight queries are counted in `counter`; they take
/// [`Passable::sight_counted`], so a [`PassableGrid`] gives the fast walk of
/// [`crate::los`] (a plain grid or [`Traversable`](crate::los::Traversable) the reference
/// one, with the same answers).
///
/// The result starts and ends with the input's end waypoints, every segment of it is clear
/// (checked, or a segment of the input), and it is never longer than the input (triangle
/// inequality). An empty input gives an empty output.
///
/// # Complexity
/// `O(k n)` line-of-sight queries for `n` input and `k` output waypoints (each anchor scans
/// back from the last waypoint), each `O(cells swept)`.
///
/// # Example
/// ```
/// use vpmap_plan::{CellXy, Occupancy, OccupancyGrid, los::LosCounter, smoothing::smooth_path};
/// let mut grid = OccupancyGrid::new(3, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// grid.set(1, 1, Occupancy::Occupied).unwrap();
/// let path = [(0, 0), (1, 0), (2, 0), (2, 1), (2, 2)].map(CellXy::from);
/// let mut counter = LosCounter::default();
/// assert_eq!(smooth_path(&grid, &path, &mut counter), [(0, 0), (2, 0), (2, 2)]);
/// assert!(counter.checks > 0);
/// ```
pub fn smooth_path(grid: &impl Passable, path: &[CellXy], counter: &mut LosCounter) -> Vec<CellXy> {
    let mut anchor = 0;
    let mut kept = Vec::new();
    while let Some(&from) = path.get(anchor) {
        kept.push(from);
        if anchor + 1 >= path.len() {
            break;
        }
        let farthest = (anchor + 2..path.len())
            .rev()
            .find(|&j| {
                path.get(j)
                    .is_some_and(|&to| grid.sight_counted(from.into(), to.into(), counter))
            })
            .unwrap_or(anchor + 1);
        anchor = farthest;
    }
    kept
}

/// A* PS: a shortest 8-connected grid path (see [`crate::astar`](mod@crate::astar)),
/// smoothed by [`smooth_path`] under the rule of [`crate::los`]. `Ok(None)` when the goal
/// cannot be reached. The statistics are A*'s expansions and generations plus the
/// smoothing's line-of-sight queries.
///
/// # Errors
/// [`PlanError::EndpointOutsideGrid`](crate::PlanError::EndpointOutsideGrid) when `start`
/// or `goal` is outside the grid,
/// [`PlanError::EndpointBlocked`](crate::PlanError::EndpointBlocked) when it is not
/// traversable.
///
/// # Complexity
/// A*'s `O(n log n)` for `n` reachable cells, plus [`smooth_path`]'s.
///
/// # References
/// A. Botea, M. Müller, J. Schaeffer, "Near Optimal Hierarchical Path-Finding", Journal of
/// Game Development 1(1), 2004.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, smoothing::{astar_ps, AstarPsOptions}};
/// let grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// let plan = astar_ps(&grid, (0, 0), (4, 2), &AstarPsOptions::default()).unwrap().unwrap();
/// assert_eq!(plan.waypoints, [(0, 0), (4, 2)]);
/// assert!((plan.length_cells - 20f64.sqrt()).abs() < 1e-12);
/// ```
pub fn astar_ps(
    grid: &OccupancyGrid,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    opts: &AstarPsOptions,
) -> Result<Option<Plan>> {
    let astar_opts = AstarOptions {
        unknown_passable: opts.unknown_passable,
        budget: opts.budget.clone(),
    };
    let Some(grid_plan) = AstarSearch::new().search(grid, start, goal, &astar_opts)? else {
        return Ok(None);
    };
    let mut counter = LosCounter::default();
    let passable = PassableGrid::new(grid, opts.unknown_passable);
    let waypoints = smooth_path(&passable, &grid_plan.waypoints, &mut counter);
    // Smoothing makes at most one query per pair of waypoints of the A* path.
    opts.budget
        .check("A* PS", grid_plan.stats.expanded, counter.cells, 0)?;
    let length_cells = path_length(&waypoints);
    Ok(Some(Plan {
        waypoints,
        length_cells,
        stats: PlanStats {
            los_checks: counter.checks,
            los_cells: counter.cells,
            ..grid_plan.stats
        },
    }))
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::grid::Occupancy;

    #[test]
    fn farthest_visible_waypoint_skips_a_hidden_one() {
        // A path that dips behind a wall and comes back: from (0, 0), waypoint (1, 2) is
        // hidden by the wall at (1, 1) (the incremental variant would keep (0, 2)), but
        // (3, 0) is visible again.
        let mut grid = OccupancyGrid::new(4, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        grid.set(1, 1, Occupancy::Occupied).unwrap();
        let path = [(0, 0), (0, 1), (0, 2), (1, 2), (2, 2), (3, 1), (3, 0)].map(CellXy::from);
        let mut counter = LosCounter::default();
        assert_eq!(smooth_path(&grid, &path, &mut counter), [(0, 0), (3, 0)]);
    }

    #[test]
    fn short_paths_are_kept() {
        let grid = OccupancyGrid::new(2, 1, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        let mut counter = LosCounter::default();
        assert!(smooth_path(&grid, &[], &mut counter).is_empty());
        assert_eq!(
            smooth_path(&grid, &[CellXy::new(1, 0)], &mut counter),
            [(1, 0)]
        );
        assert_eq!(
            smooth_path(&grid, &[CellXy::new(0, 0), CellXy::new(1, 0)], &mut counter),
            [(0, 0), (1, 0)]
        );
        assert_eq!(counter.checks, 0);
    }

    #[test]
    fn unreachable_goal_and_bad_endpoints() {
        let mut grid = OccupancyGrid::new(3, 1, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        grid.set(1, 0, Occupancy::Unknown).unwrap();
        let opts = AstarPsOptions::default();
        assert_eq!(astar_ps(&grid, (0, 0), (2, 0), &opts).unwrap(), None);
        let through = AstarPsOptions {
            unknown_passable: true,
            ..AstarPsOptions::default()
        };
        let plan = astar_ps(&grid, (0, 0), (2, 0), &through).unwrap().unwrap();
        assert_eq!(plan.waypoints, [(0, 0), (2, 0)]);
        assert!(astar_ps(&grid, (0, 0), (3, 0), &opts).is_err());
        assert!(astar_ps(&grid, (1, 0), (2, 0), &opts).is_err());
    }
}
