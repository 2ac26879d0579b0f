//! The corner cells of a grid: the only places a shortest any-angle path bends (the proof is
//! in [`crate::optimal`]'s module docs). Shared by the exact planner ([`crate::anya`]) and its
//! visibility-graph reference ([`crate::optimal`]); re-exported by [`crate::optimal`].

use crate::grid::{CellXy, OccupancyGrid};
use crate::los::{Passable, PassableGrid};

/// The four diagonal directions.
const DIAGONALS: [(i64, i64); 4] = [(1, 1), (-1, 1), (-1, -1), (1, -1)];

/// Every corner cell of the grid (see [`crate::optimal`]'s module docs), in row-major order: a
/// traversable cell with a diagonal direction `(dx, dy)` whose diagonal neighbour is
/// blocked (or outside the grid) while both orthogonal neighbours `(x + dx, y)` and
/// `(x, y + dy)` are traversable.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, optimal::corner_cells};
/// let mut grid = OccupancyGrid::new(3, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// assert!(corner_cells(&grid, false).is_empty());
/// grid.set(1, 1, Occupancy::Occupied).unwrap();
/// assert_eq!(corner_cells(&grid, false), [(0, 0), (2, 0), (0, 2), (2, 2)]);
/// ```
#[must_use]
pub fn corner_cells(grid: &OccupancyGrid, unknown_passable: bool) -> Vec<CellXy> {
    corners_of(&PassableGrid::new(grid, unknown_passable))
        .into_iter()
        .map(CellXy::from)
        .collect()
}

/// [`corner_cells`] of a grid's precomputed passability.
pub(crate) fn corners_of(passable: &PassableGrid) -> Vec<(usize, usize)> {
    let mut corners = Vec::new();
    for y in 0..passable.height() {
        for x in 0..passable.width() {
            if is_corner_cell(passable, x as i64, y as i64) {
                corners.push((x, y));
            }
        }
    }
    corners
}

/// Whether `(x, y)` is a corner cell (see [`corner_cells`]): passable, with a blocked
/// diagonal neighbour whose two cells next to both are passable.
pub(crate) fn is_corner_cell(passable: &PassableGrid, x: i64, y: i64) -> bool {
    passable.passable(x, y)
        && DIAGONALS.iter().any(|&(dx, dy)| {
            !passable.passable(x + dx, y + dy)
                && passable.passable(x + dx, y)
                && passable.passable(x, y + dy)
        })
}
