//! One grid cell: where it is ([`CellXy`]), what it holds ([`Occupancy`]) and what it costs
//! in memory ([`BYTES_PER_CELL`]). The lowest module of the crate: the error type names cells
//! too. Re-exported by [`crate::grid`].

use std::fmt;

/// About how many bytes of memory one grid cell costs from reading or rasterising the grid
/// to a planned path: its [`Occupancy`], the obstacle inflation's distance transform and the
/// largest planner's search arrays (the slope of `vpmap plan`'s peak resident memory against
/// cells, `scripts/limits-table.sh`: A* and A* PS 18 bytes a cell, also when A* expands every
/// cell of a 4000 x 4000 map; Theta* 15, the exact planner 8-10, MBPP 2-10, and 4 more when its line-of-sight box index
/// is built: at most 14).
pub const BYTES_PER_CELL: usize = 18;

/// Where a grid cell is: column `x` (left to right) and row `y` (from the top), both in
/// cells. Converts from and to the tuple `(x, y)` and compares equal to it, so
/// `plan.waypoints == [(0, 2), (5, 2)]` reads as before.
///
/// # Example
/// ```
/// use vpmap_plan::CellXy;
/// let c = CellXy::from((3, 1));
/// assert_eq!((c.x, c.y), (3, 1));
/// assert_eq!(c, (3, 1));
/// assert_eq!(<(usize, usize)>::from(c), (3, 1));
/// assert!(CellXy::new(0, 5) < CellXy::new(1, 0)); // ordered by x, then y
/// assert_eq!(format!("{c:?}"), "(3, 1)");
/// ```
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CellXy {
    /// Column, cells, left to right.
    pub x: usize,
    /// Row, cells, counted from the top.
    pub y: usize,
}

impl CellXy {
    /// The cell in column `x`, row `y`.
    #[inline]
    #[must_use]
    pub const fn new(x: usize, y: usize) -> Self {
        Self { x, y }
    }
}

/// Formats as the tuple `(x, y)`, as cells were printed before this type existed: error
/// messages and dumped paths stay the same.
impl fmt::Debug for CellXy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&(self.x, self.y), f)
    }
}

impl From<(usize, usize)> for CellXy {
    #[inline]
    fn from((x, y): (usize, usize)) -> Self {
        Self { x, y }
    }
}

impl From<CellXy> for (usize, usize) {
    #[inline]
    fn from(c: CellXy) -> Self {
        (c.x, c.y)
    }
}

impl PartialEq<(usize, usize)> for CellXy {
    #[inline]
    fn eq(&self, other: &(usize, usize)) -> bool {
        (self.x, self.y) == *other
    }
}

/// The occupancy of one grid cell: what may be there, not where it is.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
pub enum Occupancy {
    /// Seen floor, traversable.
    Free,
    /// An obstacle (or within the robot radius of one after inflation).
    Occupied,
    /// Not seen: outside the floor the photo shows.
    Unknown,
}
