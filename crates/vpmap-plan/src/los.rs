//! Line of sight between cell centres: the one collision rule of every planner.
//!
//! # The rule
//! A path is a polyline through cell centres, followed by a robot the size and shape of one
//! cell that keeps its orientation (an axis-aligned unit square). The segment between the
//! centres of cells `a` and `b` is **clear** when the unit square swept along it overlaps
//! the *interior* of no blocked cell, cells outside the grid counting as blocked. Touching a
//! blocked cell's edge or corner is allowed. (Its boundary is the thesis's two
//! corner-to-corner lines: the lines through the robot square's two corners that lead, on
//! either side of the segment.)
//!
//! Equivalently: the segment passes through no open square of side 2 (cells) centred on a
//! blocked cell's centre, i.e. no point of it is at Chebyshev distance below 1 from a
//! blocked centre. Consequences:
//! - a straight single step needs only its two cells free: the square slides along the
//!   neighbouring cells' edges;
//! - a diagonal single step needs both orthogonal neighbours free (no corner cutting, no
//!   squeezing between two blocked cells that share a corner), exactly the movement rule of
//!   the Moving AI benchmarks (see [`crate::astar`](mod@crate::astar));
//! - a segment from a cell to itself is clear when that cell is free.
//!
//! # Exact computation
//! In doubled coordinates cell `(x, y)` is the square `[2x, 2x + 2] x [2y, 2y + 2]`, its
//! centre `(2x + 1, 2y + 1)` is odd and cell boundaries are even, so every test is an
//! integer one. Let the segment run `du >= 0` cells along its major axis `u` and
//! `|dv| <= du` along the minor axis `v`. The segment's parameter interval over which the
//! swept square overlaps the open strip of column `u0 + k` is
//! `((k - 1) / du, (k + 1) / du)`, clipped to `[0, 1]`; the open interval it covers along
//! `v` then meets exactly the rows `v0 + j` (towards `v1`) with
//!
//! ```text
//! floor(max(k - 1, 0) |dv| / du)  <=  j  <=  ceil(min(k + 1, du) |dv| / du)
//! ```
//!
//! which [`visit_swept_cells`] enumerates column by column: every cell the swept square's
//! interior overlaps, each once, and no other. The independent check of the same rule in
//! [`crate::validate`] uses the separating axis theorem instead.
//!
//! # Complexity
//! `O(cells swept)`: `du + 1` columns of at most `|dv| / du + 3` cells, integer arithmetic
//! only, stopping at the first blocked cell.

use crate::grid::{Cell, OccupancyGrid};

/// Which cells a robot may occupy. Coordinates are signed so that cells outside the grid
/// can be asked about; they must answer `false`.
pub trait Passable {
    /// Whether cell `(x, y)` is inside the grid and traversable.
    fn passable(&self, x: i64, y: i64) -> bool;
}

impl<T: Passable + ?Sized> Passable for &T {
    #[inline]
    fn passable(&self, x: i64, y: i64) -> bool {
        (**self).passable(x, y)
    }
}

/// Only [`Cell::Free`] cells are passable.
impl Passable for OccupancyGrid {
    #[inline]
    fn passable(&self, x: i64, y: i64) -> bool {
        match (usize::try_from(x), usize::try_from(y)) {
            (Ok(x), Ok(y)) => self.is_free(x, y),
            _ => false,
        }
    }
}

/// An occupancy grid with a choice about its unknown cells: [`Cell::Free`] cells are
/// passable, [`Cell::Occupied`] cells and cells outside the grid are not, and
/// [`Cell::Unknown`] cells are passable when `unknown_passable` is set.
///
/// # Example
/// ```
/// use vpmap_plan::{Cell, OccupancyGrid, los::{Passable, Traversable}};
/// let grid = OccupancyGrid::new(2, 1, 1.0, [0.0; 2], Cell::Unknown).unwrap();
/// assert!(!Traversable::new(&grid, false).passable(0, 0));
/// assert!(Traversable::new(&grid, true).passable(0, 0));
/// assert!(!Traversable::new(&grid, true).passable(-1, 0));
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Traversable<'a> {
    /// The grid.
    pub grid: &'a OccupancyGrid,
    /// Whether [`Cell::Unknown`] cells may be entered.
    pub unknown_passable: bool,
}

impl<'a> Traversable<'a> {
    /// `grid` with unknown cells passable or not.
    #[must_use]
    pub fn new(grid: &'a OccupancyGrid, unknown_passable: bool) -> Self {
        Self {
            grid,
            unknown_passable,
        }
    }
}

impl Passable for Traversable<'_> {
    #[inline]
    fn passable(&self, x: i64, y: i64) -> bool {
        let (Ok(x), Ok(y)) = (usize::try_from(x), usize::try_from(y)) else {
            return false;
        };
        match self.grid.get(x, y) {
            Some(Cell::Free) => true,
            Some(Cell::Unknown) => self.unknown_passable,
            Some(Cell::Occupied) | None => false,
        }
    }
}

/// Line-of-sight work counters, for planners' statistics.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LosCounter {
    /// Number of line-of-sight queries.
    pub checks: usize,
    /// Number of cells looked up by those queries.
    pub cells: usize,
}

/// Call `visit(x, y)` for every cell whose interior the unit square swept from the centre
/// of cell `a` to the centre of cell `b` overlaps (see the [module docs](self)), column by
/// column along the major axis from one end, stopping as soon as `visit` returns `false`.
/// Returns whether every call returned `true`. Both end cells are visited.
///
/// # Example
/// ```
/// use vpmap_plan::los::visit_swept_cells;
/// let mut cells = Vec::new();
/// visit_swept_cells((0, 0), (2, 1), |x, y| { cells.push((x, y)); true });
/// cells.sort();
/// assert_eq!(cells, [(0, 0), (0, 1), (1, 0), (1, 1), (2, 0), (2, 1)]);
/// let mut cells = Vec::new();
/// visit_swept_cells((0, 0), (2, 2), |x, y| { cells.push((x, y)); true });
/// assert_eq!(cells.len(), 7); // (2, 0) and (0, 2) are only touched at a corner
/// ```
pub fn visit_swept_cells(
    a: (usize, usize),
    b: (usize, usize),
    mut visit: impl FnMut(i64, i64) -> bool,
) -> bool {
    let (ax, ay, bx, by) = (a.0 as i64, a.1 as i64, b.0 as i64, b.1 as i64);
    if (bx - ax).abs() >= (by - ay).abs() {
        sweep_columns((ax, ay), (bx, by), visit)
    } else {
        sweep_columns((ay, ax), (by, bx), |v, u| visit(u, v))
    }
}

/// The walk of [`visit_swept_cells`] in a frame whose first axis is the major one
/// (`|p1.0 - p0.0| >= |p1.1 - p0.1|`); `visit` receives frame coordinates.
fn sweep_columns(p0: (i64, i64), p1: (i64, i64), mut visit: impl FnMut(i64, i64) -> bool) -> bool {
    // The rule is symmetric under reversing the segment: walk towards increasing u.
    let ((u0, v0), (u1, v1)) = if p1.0 < p0.0 { (p1, p0) } else { (p0, p1) };
    let du = u1 - u0;
    let dv = (v1 - v0).abs();
    let step = if v1 < v0 { -1 } else { 1 };
    if du == 0 {
        // |dv| <= du: a single cell.
        return visit(u0, v0);
    }
    for k in 0..=du {
        let first = (k - 1).max(0) * dv / du;
        let last = ((k + 1).min(du) * dv + du - 1) / du;
        for j in first..=last {
            if !visit(u0 + k, v0 + step * j) {
                return false;
            }
        }
    }
    true
}

/// Whether the segment between the centres of cells `a` and `b` is clear (see the
/// [module docs](self) for the exact rule). Cells outside the grid are blocked, so an end
/// cell outside the grid or not passable gives `false`.
///
/// # Complexity
/// `O(cells swept)`, integer arithmetic, stopping at the first blocked cell.
///
/// # Example
/// ```
/// use vpmap_plan::{Cell, OccupancyGrid, los::line_of_sight};
/// let mut grid = OccupancyGrid::new(3, 3, 1.0, [0.0; 2], Cell::Free).unwrap();
/// grid.set(2, 0, Cell::Occupied).unwrap();
/// assert!(line_of_sight(&grid, (0, 0), (2, 2))); // touches (2, 0) at a corner only
/// grid.set(1, 0, Cell::Occupied).unwrap();
/// assert!(!line_of_sight(&grid, (0, 0), (2, 2))); // overlaps (1, 0)
/// assert!(line_of_sight(&grid, (0, 1), (2, 1))); // slides along (1, 0)'s edge
/// ```
#[must_use]
pub fn line_of_sight(grid: &impl Passable, a: (usize, usize), b: (usize, usize)) -> bool {
    visit_swept_cells(a, b, |x, y| grid.passable(x, y))
}

/// [`line_of_sight`] that also counts the query and the cells it looked up in `counter`.
///
/// # Example
/// ```
/// use vpmap_plan::{Cell, OccupancyGrid, los::{line_of_sight_counted, LosCounter}};
/// let grid = OccupancyGrid::new(4, 1, 1.0, [0.0; 2], Cell::Free).unwrap();
/// let mut counter = LosCounter::default();
/// assert!(line_of_sight_counted(&grid, (0, 0), (3, 0), &mut counter));
/// assert_eq!(counter, LosCounter { checks: 1, cells: 4 });
/// ```
pub fn line_of_sight_counted(
    grid: &impl Passable,
    a: (usize, usize),
    b: (usize, usize),
    counter: &mut LosCounter,
) -> bool {
    counter.checks += 1;
    visit_swept_cells(a, b, |x, y| {
        counter.cells += 1;
        grid.passable(x, y)
    })
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    fn swept(a: (usize, usize), b: (usize, usize)) -> Vec<(i64, i64)> {
        let mut cells = Vec::new();
        visit_swept_cells(a, b, |x, y| {
            cells.push((x, y));
            true
        });
        cells
    }

    #[test]
    fn swept_cells_are_symmetric_and_unique() {
        for (a, b) in [((3, 4), (9, 1)), ((5, 5), (2, 11)), ((0, 7), (7, 0))] {
            let mut forward = swept(a, b);
            let mut backward = swept(b, a);
            forward.sort_unstable();
            backward.sort_unstable();
            assert_eq!(forward, backward);
            let n = forward.len();
            forward.dedup();
            assert_eq!(forward.len(), n);
        }
    }

    #[test]
    fn single_steps_follow_the_octile_rule() {
        assert_eq!(swept((4, 4), (5, 4)), [(4, 4), (5, 4)]);
        let mut up = swept((4, 4), (4, 3));
        up.sort_unstable();
        assert_eq!(up, [(4, 3), (4, 4)]);
        let mut d = swept((4, 4), (3, 5));
        d.sort_unstable();
        assert_eq!(d, [(3, 4), (3, 5), (4, 4), (4, 5)]);
        assert_eq!(swept((2, 2), (2, 2)), [(2, 2)]);
    }

    #[test]
    fn counter_counts_cells_until_the_first_blocked_one() {
        let mut grid = OccupancyGrid::new(5, 1, 1.0, [0.0; 2], Cell::Free).unwrap();
        grid.set(2, 0, Cell::Occupied).unwrap();
        let mut counter = LosCounter::default();
        assert!(!line_of_sight_counted(&grid, (0, 0), (4, 0), &mut counter));
        assert_eq!(
            counter,
            LosCounter {
                checks: 1,
                cells: 3
            }
        );
    }
}
