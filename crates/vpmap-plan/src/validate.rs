//! An independent check that a path obeys the collision rule of [`crate::los`].
//!
//! [`validate_path`] tests the same rule as [`crate::los::line_of_sight`] by a different
//! method, so that the two can be checked against each other: for each segment it takes
//! every blocked cell (and every cell outside the grid) in the bounding box of the
//! segment's end cells grown by one cell, and decides with the separating axis theorem
//! whether the segment's swept region overlaps that cell's interior.
//!
//! In doubled coordinates (cell `(x, y)` is `[2x, 2x + 2] x [2y, 2y + 2]`, centres odd) the
//! swept region is the Minkowski sum of the segment `p0 p1` and the square `[-1, 1]^2`: a
//! hexagon (a rectangle for an axis-aligned segment) whose edges are parallel to the axes
//! or to the segment. Two convex polygons have overlapping interiors exactly when their
//! projections onto every edge normal of either one overlap in an interval of positive
//! length, so three axes decide: `(1, 0)`, `(0, 1)` and the segment's normal
//! `(-dy, dx)`. The projections are exact integer dot products and the overlap tests are
//! strict inequalities, so touching an edge or a corner is not an overlap.

use thiserror::Error;

use crate::grid::{CellXy, Occupancy, OccupancyGrid};

/// Why a path breaks the collision rule.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum PathViolation {
    /// The path has no waypoint.
    #[error("the path has no waypoints")]
    Empty,
    /// A waypoint lies outside the grid.
    #[error("waypoint {index} {cell:?} is outside the {width} x {height} grid")]
    WaypointOutsideGrid {
        /// Index of the waypoint.
        index: usize,
        /// The waypoint `(x, y)`.
        cell: CellXy,
        /// Grid width, cells.
        width: usize,
        /// Grid height, cells.
        height: usize,
    },
    /// A waypoint is a cell the robot may not occupy.
    #[error("waypoint {index} {cell:?} is a blocked ({state:?}) cell")]
    WaypointBlocked {
        /// Index of the waypoint.
        index: usize,
        /// The waypoint `(x, y)`.
        cell: CellXy,
        /// What the cell holds.
        state: Occupancy,
    },
    /// The robot's square, swept along a segment, overlaps a blocked cell's interior.
    #[error("segment {segment} from {from:?} to {to:?} overlaps blocked cell {cell:?}")]
    SegmentBlocked {
        /// Index of the segment (segment `i` joins waypoints `i` and `i + 1`).
        segment: usize,
        /// Its first waypoint.
        from: CellXy,
        /// Its last waypoint.
        to: CellXy,
        /// A blocked cell it overlaps (possibly outside the grid).
        cell: (i64, i64),
    },
}

/// Whether `(x, y)` is a cell the robot may occupy: inside the grid and free (or unknown
/// when `unknown_passable`).
pub(crate) fn passable(grid: &OccupancyGrid, x: i64, y: i64, unknown_passable: bool) -> bool {
    let (Ok(x), Ok(y)) = (usize::try_from(x), usize::try_from(y)) else {
        return false;
    };
    match grid.get(x, y) {
        Some(Occupancy::Free) => true,
        Some(Occupancy::Unknown) => unknown_passable,
        _ => false,
    }
}

/// Whether the unit square swept from the centre of cell `a` to the centre of cell `b`
/// overlaps the interior of cell `c` (separating axis theorem in doubled coordinates).
#[must_use]
pub fn swept_square_overlaps_cell(a: (i64, i64), b: (i64, i64), c: (i64, i64)) -> bool {
    let p0 = (2 * a.0 + 1, 2 * a.1 + 1);
    let p1 = (2 * b.0 + 1, 2 * b.1 + 1);
    let corner = (2 * c.0, 2 * c.1);
    let normal = (p0.1 - p1.1, p1.0 - p0.0);
    for axis in [(1, 0), (0, 1), normal] {
        if axis == (0, 0) {
            continue;
        }
        let dot = |p: (i64, i64)| axis.0 * p.0 + axis.1 * p.1;
        // The swept region: the segment's projection grown by the square's half-extent.
        let reach = axis.0.abs() + axis.1.abs();
        let (s0, s1) = (dot(p0), dot(p1));
        let swept = (s0.min(s1) - reach, s0.max(s1) + reach);
        // The cell: its four corners.
        let corners = [
            dot(corner),
            dot((corner.0 + 2, corner.1)),
            dot((corner.0, corner.1 + 2)),
            dot((corner.0 + 2, corner.1 + 2)),
        ];
        let lo = corners.iter().copied().fold(i64::MAX, i64::min);
        let hi = corners.iter().copied().fold(i64::MIN, i64::max);
        if !(swept.0 < hi && lo < swept.1) {
            return false;
        }
    }
    true
}

/// Check that a polyline through cell centres obeys the collision rule of [`crate::los`]:
/// every waypoint is a passable cell of the grid, and the unit square swept along every
/// segment overlaps no blocked cell's interior (cells outside the grid count as blocked;
/// unknown cells are blocked unless `unknown_passable`).
///
/// Independent of [`crate::los::line_of_sight`] by construction (see the
/// [module docs](self)); meant for tests and for checking paths from elsewhere.
///
/// # Errors
/// The first [`PathViolation`] found: waypoints are checked in order, then segments in
/// order; for a blocked segment, the reported cell is the first overlapped blocked cell in
/// row-major order.
///
/// # Complexity
/// `O(area of each segment's bounding box)`.
///
/// # Example
/// ```
/// use vpmap_plan::{CellXy, Occupancy, OccupancyGrid, validate::{validate_path, PathViolation}};
/// let mut grid = OccupancyGrid::new(3, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// grid.set(1, 0, Occupancy::Occupied).unwrap();
/// let path = |cells: &[(usize, usize)]| cells.iter().map(|&c| CellXy::from(c)).collect::<Vec<_>>();
/// assert_eq!(validate_path(&grid, &path(&[(0, 0), (0, 2), (2, 2)]), false), Ok(()));
/// assert_eq!(
///     validate_path(&grid, &path(&[(0, 1), (2, 0)]), false),
///     Err(PathViolation::SegmentBlocked {
///         segment: 0,
///         from: CellXy::new(0, 1),
///         to: CellXy::new(2, 0),
///         cell: (1, 0),
///     }),
/// );
/// ```
pub fn validate_path(
    grid: &OccupancyGrid,
    waypoints: &[CellXy],
    unknown_passable: bool,
) -> Result<(), PathViolation> {
    if waypoints.is_empty() {
        return Err(PathViolation::Empty);
    }
    for (index, &cell) in waypoints.iter().enumerate() {
        match grid.get(cell.x, cell.y) {
            None => {
                return Err(PathViolation::WaypointOutsideGrid {
                    index,
                    cell,
                    width: grid.width(),
                    height: grid.height(),
                });
            }
            Some(state @ Occupancy::Occupied) => {
                return Err(PathViolation::WaypointBlocked { index, cell, state });
            }
            Some(state @ Occupancy::Unknown) if !unknown_passable => {
                return Err(PathViolation::WaypointBlocked { index, cell, state });
            }
            Some(_) => {}
        }
    }
    for (segment, pair) in waypoints.windows(2).enumerate() {
        let &[from, to] = pair else { continue };
        let a = (from.x as i64, from.y as i64);
        let b = (to.x as i64, to.y as i64);
        for y in a.1.min(b.1) - 1..=a.1.max(b.1) + 1 {
            for x in a.0.min(b.0) - 1..=a.0.max(b.0) + 1 {
                if !passable(grid, x, y, unknown_passable)
                    && swept_square_overlaps_cell(a, b, (x, y))
                {
                    return Err(PathViolation::SegmentBlocked {
                        segment,
                        from,
                        to,
                        cell: (x, y),
                    });
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn overlap_of_single_steps() {
        // Straight step: the side neighbours are touched along an edge only.
        assert!(!swept_square_overlaps_cell((0, 0), (1, 0), (0, 1)));
        assert!(!swept_square_overlaps_cell((0, 0), (1, 0), (1, -1)));
        assert!(swept_square_overlaps_cell((0, 0), (1, 0), (1, 0)));
        // Diagonal step: both orthogonal neighbours are overlapped.
        assert!(swept_square_overlaps_cell((0, 0), (1, 1), (1, 0)));
        assert!(swept_square_overlaps_cell((0, 0), (1, 1), (0, 1)));
        assert!(!swept_square_overlaps_cell((0, 0), (1, 1), (2, 0)));
        // A point "segment" overlaps its own cell only.
        assert!(swept_square_overlaps_cell((3, 3), (3, 3), (3, 3)));
        assert!(!swept_square_overlaps_cell((3, 3), (3, 3), (4, 4)));
    }

    fn cells(xy: &[(usize, usize)]) -> Vec<CellXy> {
        xy.iter().map(|&c| CellXy::from(c)).collect()
    }

    #[test]
    fn waypoint_violations_are_reported_in_order() {
        let mut grid = OccupancyGrid::new(3, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        grid.set(2, 1, Occupancy::Unknown).unwrap();
        assert_eq!(validate_path(&grid, &[], false), Err(PathViolation::Empty));
        assert_eq!(
            validate_path(&grid, &cells(&[(0, 0), (3, 0)]), false),
            Err(PathViolation::WaypointOutsideGrid {
                index: 1,
                cell: CellXy::new(3, 0),
                width: 3,
                height: 2
            })
        );
        assert_eq!(
            validate_path(&grid, &cells(&[(0, 0), (2, 1)]), false),
            Err(PathViolation::WaypointBlocked {
                index: 1,
                cell: CellXy::new(2, 1),
                state: Occupancy::Unknown
            })
        );
        assert_eq!(
            validate_path(&grid, &cells(&[(0, 0), (2, 1)]), true),
            Ok(())
        );
    }
}
