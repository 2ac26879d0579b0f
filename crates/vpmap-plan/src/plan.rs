//! What every planner returns: [`Plan`], its [`PlanStats`], and shared input checks.

use crate::error::{PlanError, Result};
use crate::grid::{CellXy, OccupancyGrid};
use crate::los::{Passable, Traversable};

/// A path found by a planner.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// Cells `(x, y)` whose centres the path joins with straight segments, from the start
    /// cell to the goal cell (a single cell when they coincide). Every segment is clear
    /// under the rule of [`crate::los`].
    pub waypoints: Vec<CellXy>,
    /// Euclidean length of the polyline, cells (multiply by the grid's resolution for
    /// metres).
    pub length_cells: f64,
    /// How much work the search did.
    pub stats: PlanStats,
}

/// Search effort of a planner, for comparisons between planners.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct PlanStats {
    /// Nodes taken off the open list and expanded.
    pub expanded: usize,
    /// Nodes pushed onto the open list (including re-pushes after a cost decrease).
    pub generated: usize,
    /// Line-of-sight queries made.
    pub los_checks: usize,
    /// Cells looked up by those queries.
    pub los_cells: usize,
}

/// Euclidean length, in cells, of the polyline through the centres of `waypoints`.
///
/// # Example
/// ```
/// use vpmap_plan::{CellXy, plan::path_length};
/// let path = [(0, 0), (3, 4), (3, 6)].map(CellXy::from);
/// assert_eq!(path_length(&path), 7.0);
/// let one = [CellXy::new(2, 2)];
/// assert!(path_length(&one) == 0.0 && path_length(&one).is_sign_positive());
/// ```
#[must_use]
pub fn path_length(waypoints: &[CellXy]) -> f64 {
    waypoints
        .windows(2)
        .map(|w| match w {
            [a, b] => (a.x.abs_diff(b.x) as f64).hypot(a.y.abs_diff(b.y) as f64),
            _ => 0.0,
        })
        .sum::<f64>()
        // An empty sum of floats is -0.0; report +0.0 for a one-cell path.
        + 0.0
}

/// A planner's endpoint as the `(x, y)` tuple its inner loops work with.
#[inline]
pub(crate) fn xy(cell: impl Into<CellXy>) -> (usize, usize) {
    cell.into().into()
}

/// Waypoints from the inner loops' tuples.
pub(crate) fn cells_of(waypoints: Vec<(usize, usize)>) -> Vec<CellXy> {
    waypoints.into_iter().map(CellXy::from).collect()
}

/// Check that a planner's `start` or `goal` (named by `endpoint`) is a traversable cell.
pub(crate) fn check_endpoint(
    grid: &OccupancyGrid,
    endpoint: &'static str,
    cell: impl Into<CellXy>,
    unknown_passable: bool,
) -> Result<()> {
    let CellXy { x, y } = cell.into();
    let Some(state) = grid.get(x, y) else {
        return Err(PlanError::EndpointOutsideGrid {
            endpoint,
            x,
            y,
            width: grid.width(),
            height: grid.height(),
        });
    };
    if Traversable::new(grid, unknown_passable).passable(x as i64, y as i64) {
        Ok(())
    } else {
        Err(PlanError::EndpointBlocked {
            endpoint,
            x,
            y,
            cell: state,
        })
    }
}
