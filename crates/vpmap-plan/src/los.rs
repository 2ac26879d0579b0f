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
//! # Which cells can be entered
//! [`cell_passable`] is the one answer: [`Occupancy::Free`] always, [`Occupancy::Unknown`] when the
//! planner's `unknown_passable` option is set, [`Occupancy::Occupied`] never, and a cell
//! outside the grid never. [`Traversable`] (a grid plus that choice, looked up with bounds
//! checks) and [`PassableGrid`] (the same answers precomputed) both follow it, and so do
//! the planners' endpoint checks and A*'s own neighbour flags.
//!
//! # Two implementations of the walk
//! - [`visit_swept_cells`] is the **reference**: it enumerates the cells with one division
//!   per column, on coordinates, and asks a [`Passable`] about each. It is short enough to
//!   check by reading, and it is what [`line_of_sight`] uses on a plain grid or a
//!   [`Traversable`].
//! - [`PassableGrid`] is the **fast** walk every planner uses: the grid's passability is
//!   copied once into a byte array with a blocked one-cell border (so neighbour lookups
//!   need no bounds tests), and the same columns are walked on array indices, both
//!   quotients of the formula above kept as (quotient, remainder) pairs advanced by adding
//!   `|dv|`, so the walk needs no division. It looks up the same cells in the same order
//!   as the reference and stops at the same one (a property test in
//!   `tests/it/line_of_sight.rs` checks both on random grids), so answers and
//!   [`LosCounter`] counts are equal. Build it once per grid and planner option; a build
//!   costs one pass over the grid, `(width + 2) (height + 2)` bytes.
//!
//! # Free boxes
//! A segment's swept cells, column `k` of the frame above holding rows `first(k) ..=
//! last(k)`, both monotone in `k`, so the cells of columns `k0 ..= k1` lie in the box of
//! those columns and rows `first(k0) ..= last(k1)`. [`PassableGrid::index_boxes`] adds a
//! summed-area table of the blocked cells (four look-ups tell whether a box holds any);
//! [`PassableGrid::sight`] then proves free boxes clear without walking them, halves
//! blocked ones, and walks runs of a few columns cell by cell. The answer is the walk's
//! (every swept cell is either in a box proved free or looked up); the count is of table
//! entries and cells looked up, so it falls from `O(length)` to `O(log length)` for a
//! segment in open space. MBPP builds the index when it pays
//! ([`PassableGrid::index_boxes_when_worth_it`]: once its walks have looked up as many cells
//! as the grid has): its bugs check sight from a corner to every cell they walk, along
//! corridors hundreds of cells long.
//!
//! Any [`Passable`] answers segment queries through [`Passable::sight_counted`], which
//! [`PassableGrid`] overrides with the fast walk, so [`line_of_sight`] and
//! [`smooth_path`](crate::smoothing::smooth_path) get it whenever they are given one.
//!
//! # Complexity
//! `O(cells swept)`: `du + 1` columns of at most `|dv| / du + 3` cells, integer arithmetic
//! only, stopping at the first blocked cell.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::grid::{CellXy, Occupancy, OccupancyGrid};

/// Segments shorter than this many columns along their major axis are walked cell by cell
/// even when [`PassableGrid`] has its box index (a box test costs four look-ups).
const BOX_MIN_COLUMNS: i64 = 8;

/// Runs of at most this many columns of a blocked box are walked cell by cell rather than
/// halved again.
const BOX_LEAF_COLUMNS: i64 = 4;

/// Whether a robot may stand on a cell holding `cell`: [`Occupancy::Free`] cells always,
/// [`Occupancy::Unknown`] cells when `unknown_passable`, [`Occupancy::Occupied`] cells never. The
/// one definition every planner, endpoint check and [`PassableGrid`] uses.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, los::cell_passable};
/// assert!(cell_passable(Occupancy::Free, false));
/// assert!(!cell_passable(Occupancy::Unknown, false) && cell_passable(Occupancy::Unknown, true));
/// assert!(!cell_passable(Occupancy::Occupied, true));
/// ```
#[inline]
#[must_use]
pub fn cell_passable(cell: Occupancy, unknown_passable: bool) -> bool {
    match cell {
        Occupancy::Free => true,
        Occupancy::Unknown => unknown_passable,
        Occupancy::Occupied => false,
    }
}

/// Fill `out` with `grid`'s passability (see [`cell_passable`]) padded by a one-cell
/// blocked border, row-major, `(width + 2) x (height + 2)` values: cell `(x, y)` is at
/// index `(y + 1) (width + 2) + x + 1`. Reuses `out`'s allocation.
pub(crate) fn fill_padded<T: Copy>(
    grid: &OccupancyGrid,
    unknown_passable: bool,
    out: &mut Vec<T>,
    blocked: T,
    passable: T,
) {
    let (width, height) = (grid.width(), grid.height());
    let padded_width = width + 2;
    out.clear();
    out.resize(padded_width * (height + 2), blocked);
    if width == 0 {
        return;
    }
    let rows = out
        .chunks_exact_mut(padded_width)
        .skip(1)
        .zip(grid.cells().chunks_exact(width));
    for (padded_row, row) in rows {
        if let Some(inner) = padded_row.get_mut(1..=width) {
            for (slot, &c) in inner.iter_mut().zip(row) {
                *slot = if cell_passable(c, unknown_passable) {
                    passable
                } else {
                    blocked
                };
            }
        }
    }
}

/// Which cells a robot may occupy. Coordinates are signed so that cells outside the grid
/// can be asked about; they must answer `false`.
pub trait Passable {
    /// Whether cell `(x, y)` is inside the grid and traversable.
    fn passable(&self, x: i64, y: i64) -> bool;

    /// Whether the segment between the centres of cells `a` and `b` is clear (see the
    /// [module docs](self)), counting the query and the cells looked up in `counter`. The
    /// default walks [`visit_swept_cells`]; [`PassableGrid`] overrides it with the fast
    /// walk, which gives the same answer and counts.
    fn sight_counted(
        &self,
        a: (usize, usize),
        b: (usize, usize),
        counter: &mut LosCounter,
    ) -> bool {
        counter.checks += 1;
        visit_swept_cells(a, b, |x, y| {
            counter.cells += 1;
            self.passable(x, y)
        })
    }
}

impl<T: Passable + ?Sized> Passable for &T {
    #[inline]
    fn passable(&self, x: i64, y: i64) -> bool {
        (**self).passable(x, y)
    }

    #[inline]
    fn sight_counted(
        &self,
        a: (usize, usize),
        b: (usize, usize),
        counter: &mut LosCounter,
    ) -> bool {
        (**self).sight_counted(a, b, counter)
    }
}

/// Only [`Occupancy::Free`] cells are passable.
impl Passable for OccupancyGrid {
    #[inline]
    fn passable(&self, x: i64, y: i64) -> bool {
        Traversable::new(self, false).passable(x, y)
    }
}

/// An occupancy grid with a choice about its unknown cells: [`Occupancy::Free`] cells are
/// passable, [`Occupancy::Occupied`] cells and cells outside the grid are not, and
/// [`Occupancy::Unknown`] cells are passable when `unknown_passable` is set.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, los::{Passable, Traversable}};
/// let grid = OccupancyGrid::new(2, 1, 1.0, [0.0; 2], Occupancy::Unknown).unwrap();
/// assert!(!Traversable::new(&grid, false).passable(0, 0));
/// assert!(Traversable::new(&grid, true).passable(0, 0));
/// assert!(!Traversable::new(&grid, true).passable(-1, 0));
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Traversable<'a> {
    /// The grid.
    pub grid: &'a OccupancyGrid,
    /// Whether [`Occupancy::Unknown`] cells may be entered.
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
        self.grid
            .get(x, y)
            .is_some_and(|c| cell_passable(c, self.unknown_passable))
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
    a: impl Into<CellXy>,
    b: impl Into<CellXy>,
    visit: impl FnMut(i64, i64) -> bool,
) -> bool {
    let (a, b) = (a.into(), b.into());
    visit_swept_cells_signed((a.x as i64, a.y as i64), (b.x as i64, b.y as i64), visit)
}

/// [`visit_swept_cells`] between cells with signed coordinates (the rule is translation
/// invariant, so cells outside the grid are walked the same way).
fn visit_swept_cells_signed(
    (ax, ay): (i64, i64),
    (bx, by): (i64, i64),
    mut visit: impl FnMut(i64, i64) -> bool,
) -> bool {
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
/// use vpmap_plan::{Occupancy, OccupancyGrid, los::line_of_sight};
/// let mut grid = OccupancyGrid::new(3, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// grid.set(2, 0, Occupancy::Occupied).unwrap();
/// assert!(line_of_sight(&grid, (0, 0), (2, 2))); // touches (2, 0) at a corner only
/// grid.set(1, 0, Occupancy::Occupied).unwrap();
/// assert!(!line_of_sight(&grid, (0, 0), (2, 2))); // overlaps (1, 0)
/// assert!(line_of_sight(&grid, (0, 1), (2, 1))); // slides along (1, 0)'s edge
/// ```
#[must_use]
pub fn line_of_sight(grid: &impl Passable, a: impl Into<CellXy>, b: impl Into<CellXy>) -> bool {
    grid.sight_counted(a.into().into(), b.into().into(), &mut LosCounter::default())
}

/// [`line_of_sight`] that also counts the query and the cells it looked up in `counter`.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, los::{line_of_sight_counted, LosCounter}};
/// let grid = OccupancyGrid::new(4, 1, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// let mut counter = LosCounter::default();
/// assert!(line_of_sight_counted(&grid, (0, 0), (3, 0), &mut counter));
/// assert_eq!(counter, LosCounter { checks: 1, cells: 4 });
/// ```
pub fn line_of_sight_counted(
    grid: &impl Passable,
    a: impl Into<CellXy>,
    b: impl Into<CellXy>,
    counter: &mut LosCounter,
) -> bool {
    grid.sight_counted(a.into().into(), b.into().into(), counter)
}

/// An occupancy grid's passability (see [`cell_passable`]) precomputed once, with a
/// blocked one-cell border, for the planners' inner loops: which cells can be entered
/// ([`PassableGrid::passable`]), which single steps are legal ([`PassableGrid::step_clear`])
/// and whether a segment is clear ([`PassableGrid::sight`], the division-free walk of the
/// [module docs](self)).
///
/// It is a copy: edits to the grid after [`PassableGrid::new`] are not seen until
/// [`PassableGrid::rebuild`]. Coordinates are signed cells; every cell outside the grid is
/// blocked.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, los::{LosCounter, Passable, PassableGrid}};
/// let mut grid = OccupancyGrid::new(3, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// grid.set(2, 0, Occupancy::Unknown).unwrap();
/// let view = PassableGrid::new(&grid, false);
/// assert!(!view.passable(2, 0) && !view.passable(-1, 0) && view.passable(2, 2));
/// assert!(!view.step_clear((1, 0), (1, 1))); // would cut the corner of (2, 0)
/// let mut counter = LosCounter::default();
/// assert!(view.sight((0, 0), (2, 2), &mut counter)); // (2, 0)'s corner is only touched
/// assert!(!view.sight((0, 0), (2, 1), &mut counter)); // overlaps (2, 0)
/// assert!(PassableGrid::new(&grid, true).sight((0, 0), (2, 1), &mut counter));
/// assert_eq!(counter.checks, 3);
/// ```
#[derive(Clone, Debug, Default)]
pub struct PassableGrid {
    /// Passability, padded: cell `(x, y)` at `(y + 1) * padded_width + x + 1`.
    cells: Vec<bool>,
    padded_width: i64,
    width: i64,
    height: i64,
    unknown_passable: bool,
    /// The box index: whether and when it is built, and the table once built.
    boxes: BoxIndex,
}

/// When [`PassableGrid`] builds its box index.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum BoxMode {
    /// Never (the walk's counts are the reference's).
    #[default]
    Off,
    /// Built by [`PassableGrid::index_boxes`].
    Now,
    /// Built once the walks have looked up as many cells as the table has entries
    /// ([`PassableGrid::index_boxes_when_worth_it`]).
    WhenWorthIt,
}

/// [`PassableGrid`]'s box index.
#[derive(Debug, Default)]
struct BoxIndex {
    mode: BoxMode,
    /// Cells looked up by walks since the grid was built (for [`BoxMode::WhenWorthIt`]).
    walked: AtomicUsize,
    /// The summed-area table of blocked cells over the padded array: entry
    /// `r (padded_width + 1) + c` counts the blocked cells in padded rows `< r` and padded
    /// columns `< c`.
    blocked_sums: OnceLock<Vec<u32>>,
}

impl Clone for BoxIndex {
    fn clone(&self) -> Self {
        Self {
            mode: self.mode,
            walked: AtomicUsize::new(self.walked.load(Ordering::Relaxed)),
            blocked_sums: self.blocked_sums.clone(),
        }
    }
}

impl PassableGrid {
    /// `grid`'s passability, unknown cells passable or not.
    ///
    /// # Complexity
    /// One pass over the grid; `(width + 2) (height + 2)` bytes.
    #[must_use]
    pub fn new(grid: &OccupancyGrid, unknown_passable: bool) -> Self {
        let mut view = Self::default();
        view.rebuild(grid, unknown_passable);
        view
    }

    /// Recompute for `grid` (which may differ in size), reusing the allocation; the box
    /// index is rebuilt too when it was built.
    pub fn rebuild(&mut self, grid: &OccupancyGrid, unknown_passable: bool) {
        fill_padded(grid, unknown_passable, &mut self.cells, false, true);
        self.padded_width = grid.width() as i64 + 2;
        self.width = grid.width() as i64;
        self.height = grid.height() as i64;
        self.unknown_passable = unknown_passable;
        self.boxes = BoxIndex {
            mode: self.boxes.mode,
            ..BoxIndex::default()
        };
        if self.boxes.mode == BoxMode::Now {
            self.index_boxes();
        }
    }

    /// Build the box index: a summed-area table of the blocked cells, so that
    /// [`PassableGrid::sight`] can prove a whole box of cells free with four look-ups
    /// instead of walking it cell by cell (see "Free boxes" in the [module docs](self)).
    /// Answers stay the same; the counts of looked-up cells fall.
    ///
    /// # Complexity
    /// One pass over the grid; `4 (width + 3) (height + 3)` bytes more.
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::{Occupancy, OccupancyGrid, los::{LosCounter, PassableGrid}};
    /// let mut grid = OccupancyGrid::new(100, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    /// grid.set(50, 2, Occupancy::Occupied).unwrap();
    /// let plain = PassableGrid::new(&grid, false);
    /// let mut boxed = plain.clone();
    /// boxed.index_boxes();
    /// let (mut walked, mut proved) = (LosCounter::default(), LosCounter::default());
    /// // Row 0 is free end to end: one box proves it.
    /// assert!(plain.sight((0, 0), (99, 0), &mut walked));
    /// assert!(boxed.sight((0, 0), (99, 0), &mut proved));
    /// assert_eq!((walked.cells, proved.cells), (100, 4));
    /// // A segment that meets (50, 2): the same answer both ways.
    /// assert!(!plain.sight((0, 0), (99, 2), &mut walked));
    /// assert!(!boxed.sight((0, 0), (99, 2), &mut proved));
    /// ```
    pub fn index_boxes(&mut self) {
        self.boxes.mode = BoxMode::Now;
        let sums = self.blocked_sums();
        self.boxes.blocked_sums = OnceLock::from(sums);
    }

    /// Build the box index of [`PassableGrid::index_boxes`] only when it pays: at the first
    /// query after the walks have looked up as many cells as the index has entries (so a
    /// few short queries on a large grid never pay for it, and long ones pay at most twice
    /// what walking alone would have cost before it). Answers stay the same; the counts of
    /// looked-up cells depend only on the queries asked before, so they are the same on
    /// every run.
    pub fn index_boxes_when_worth_it(&mut self) {
        if self.boxes.mode == BoxMode::Off {
            self.boxes.mode = BoxMode::WhenWorthIt;
        }
    }

    /// The summed-area table of the blocked cells (see [`BoxIndex::blocked_sums`]).
    fn blocked_sums(&self) -> Vec<u32> {
        let pw = self.padded_width.max(0) as usize;
        let rows = self.cells.len().checked_div(pw).unwrap_or(0);
        let stride = pw + 1;
        let mut sums = vec![0u32; stride * (rows + 1)];
        for r in 0..rows {
            let mut in_row = 0u32;
            for c in 0..pw {
                let blocked = !self.cells.get(r * pw + c).copied().unwrap_or(false);
                in_row += u32::from(blocked);
                let above = sums.get(r * stride + c + 1).copied().unwrap_or(0);
                if let Some(slot) = sums.get_mut((r + 1) * stride + c + 1) {
                    *slot = above + in_row;
                }
            }
        }
        sums
    }

    /// Whether every cell of the box with corners `(x0, y0)` and `(x1, y1)` (inclusive,
    /// in the grid or its border, `x0 <= x1`, `y0 <= y1`) is passable, from the box index.
    #[inline]
    fn box_free(&self, sums: &[u32], (x0, y0): (i64, i64), (x1, y1): (i64, i64)) -> bool {
        let stride = self.padded_width + 1;
        let at = |r: i64, c: i64| {
            usize::try_from(r * stride + c)
                .ok()
                .and_then(|i| sums.get(i))
                .copied()
                .unwrap_or(0)
        };
        // Padded rows y0 + 1 ..= y1 + 1 and columns x0 + 1 ..= x1 + 1.
        let (r0, c0, r1, c1) = (y0 + 1, x0 + 1, y1 + 2, x1 + 2);
        at(r1, c1)
            .wrapping_sub(at(r0, c1))
            .wrapping_sub(at(r1, c0))
            .wrapping_add(at(r0, c0))
            == 0
    }

    /// Grid width, cells.
    #[must_use]
    pub fn width(&self) -> usize {
        self.width as usize
    }

    /// Grid height, cells.
    #[must_use]
    pub fn height(&self) -> usize {
        self.height as usize
    }

    /// Whether [`Occupancy::Unknown`] cells count as passable.
    #[must_use]
    pub fn unknown_passable(&self) -> bool {
        self.unknown_passable
    }

    /// Index of `(x, y)` in the padded array, when it lies in the grid or its border.
    #[inline]
    fn padded_index(&self, (x, y): (i64, i64)) -> Option<usize> {
        if x < -1 || y < -1 || x > self.width || y > self.height {
            return None;
        }
        usize::try_from((y + 1) * self.padded_width + x + 1).ok()
    }

    /// Whether the 8-connected single step from cell `from` by `(dx, dy)` (each in
    /// `-1..=1`) is legal: its target is passable and, for a diagonal step, so are both
    /// orthogonal neighbours. From a passable `from` these are exactly the single steps
    /// [`line_of_sight`] calls clear; `from` itself is not checked.
    #[inline]
    #[must_use]
    pub fn step_clear(&self, from: (i64, i64), (dx, dy): (i64, i64)) -> bool {
        let (x, y) = from;
        self.passable(x + dx, y + dy)
            && (dx == 0 || dy == 0 || (self.passable(x + dx, y) && self.passable(x, y + dy)))
    }

    /// Whether the segment between the centres of cells `a` and `b` is clear, counting the
    /// query and the cells looked up in `counter` exactly as [`line_of_sight_counted`] on a
    /// [`Traversable`] of the same grid would (same cells, same order, same answer). With
    /// the box index ([`PassableGrid::index_boxes`]) the answer is the same and the count
    /// is of the table entries and cells looked up by the box test instead.
    ///
    /// # Complexity
    /// `O(cells swept)`, additions only, stopping at the first blocked cell; with the box
    /// index, `O(log cells swept)` in open space.
    // Not inlined: inlined into MBPP's step and A* PS's smoothing loop it measured 2-20 %
    // more instructions there (callgrind), none fewer in Theta*.
    #[inline(never)]
    pub fn sight(&self, a: (i64, i64), b: (i64, i64), counter: &mut LosCounter) -> bool {
        counter.checks += 1;
        if self.padded_index(a).is_none() || self.padded_index(b).is_none() {
            return visit_swept_cells_signed(a, b, |x, y| {
                counter.cells += 1;
                self.passable(x, y)
            });
        }
        if let Some(sums) = self.boxes.blocked_sums.get() {
            return self.boxed_walk(sums, a, b, counter);
        }
        let before = counter.cells;
        let clear = self.walk_cells(a, b, counter);
        if self.boxes.mode == BoxMode::WhenWorthIt {
            let walked = counter.cells.saturating_sub(before);
            let total = self.boxes.walked.fetch_add(walked, Ordering::Relaxed) + walked;
            if total >= self.cells.len() {
                self.boxes.blocked_sums.get_or_init(|| self.blocked_sums());
            }
        }
        clear
    }

    /// The swept cells of the segment from `a` to `b` (both in the grid or its border)
    /// checked by boxes (see "Free boxes" in the [module docs](self)): columns
    /// `k0 ..= k1` of the walk's frame, whose rows are monotone in `k`, lie in one box; a
    /// box the index proves free clears its columns (four look-ups counted), a blocked box
    /// is halved, and runs of at most [`BOX_LEAF_COLUMNS`] columns are walked cell by cell.
    fn boxed_walk(
        &self,
        sums: &[u32],
        a: (i64, i64),
        b: (i64, i64),
        counter: &mut LosCounter,
    ) -> bool {
        let x_major = (b.0 - a.0).abs() >= (b.1 - a.1).abs();
        let (p0, p1) = if x_major {
            (a, b)
        } else {
            ((a.1, a.0), (b.1, b.0))
        };
        let ((u0, v0), (u1, v1)) = if p1.0 < p0.0 { (p1, p0) } else { (p0, p1) };
        let du = u1 - u0;
        let dv = (v1 - v0).abs();
        let v_sign = if v1 < v0 { -1 } else { 1 };
        if du < BOX_MIN_COLUMNS {
            return self.walk_cells(a, b, counter);
        }
        let to_xy = |u: i64, v: i64| if x_major { (u, v) } else { (v, u) };
        // Whether the box of frame columns `ua ..= ub` and rows `va`, `vb` (either order)
        // is free, counting its four look-ups.
        let free = |(ua, ub): (i64, i64), (va, vb): (i64, i64), counter: &mut LosCounter| {
            counter.cells += 4;
            let (xa, ya) = to_xy(ua, va.min(vb));
            let (xb, yb) = to_xy(ub, va.max(vb));
            self.box_free(sums, (xa.min(xb), ya.min(yb)), (xa.max(xb), ya.max(yb)))
        };
        // The whole segment's box first (rows 0 ..= dv): most segments in open space end here.
        if free((u0, u1), (v0, v1), counter) {
            return true;
        }
        // Rows (offsets towards v1) of column k: first(k) ..= last(k), as in `sweep_columns`.
        let first = |k: i64| (k - 1).max(0) * dv / du;
        let last = |k: i64| ((k + 1).min(du) * dv + du - 1) / du;
        // Halving `du + 1 < 2^63` columns nests under 64 deep: one pending half a level.
        let mid = du / 2;
        let mut stack = [(0, mid); 64];
        if let Some(slot) = stack.get_mut(1) {
            *slot = (mid + 1, du);
        }
        let mut depth = 2;
        while depth > 0 {
            depth -= 1;
            let Some(&(k0, k1)) = stack.get(depth) else {
                break;
            };
            let rows = (v0 + v_sign * first(k0), v0 + v_sign * last(k1));
            if free((u0 + k0, u0 + k1), rows, counter) {
                continue;
            }
            if k1 - k0 < BOX_LEAF_COLUMNS {
                for k in k0..=k1 {
                    for j in first(k)..=last(k) {
                        let (x, y) = to_xy(u0 + k, v0 + v_sign * j);
                        counter.cells += 1;
                        if !self.passable(x, y) {
                            return false;
                        }
                    }
                }
                continue;
            }
            let mid = k0 + (k1 - k0) / 2;
            // Depth first, the columns nearer `u0` first.
            for half in [(mid + 1, k1), (k0, mid)] {
                let Some(slot) = stack.get_mut(depth) else {
                    // Not reached (see above); walk the whole segment rather than skip a part.
                    return self.walk_cells(a, b, counter);
                };
                *slot = half;
                depth += 1;
            }
        }
        true
    }

    /// [`PassableGrid::sight`] that also reports every cell it looks up to `seen`, in
    /// order (for testing the walk against [`visit_swept_cells`]).
    pub fn sight_traced(
        &self,
        a: (i64, i64),
        b: (i64, i64),
        counter: &mut LosCounter,
        mut seen: impl FnMut(i64, i64),
    ) -> bool {
        counter.checks += 1;
        if self.padded_index(a).is_none() || self.padded_index(b).is_none() {
            return visit_swept_cells_signed(a, b, |x, y| {
                counter.cells += 1;
                seen(x, y);
                self.passable(x, y)
            });
        }
        let pw = self.padded_width;
        self.walk(a, b, counter, |index| {
            let i = index as i64;
            seen(i % pw - 1, i / pw - 1);
            self.cells.get(index).copied().unwrap_or(false)
        })
    }

    /// [`PassableGrid::walk`] over the passable cells, cell by cell.
    #[inline]
    fn walk_cells(&self, a: (i64, i64), b: (i64, i64), counter: &mut LosCounter) -> bool {
        self.walk(a, b, counter, |index| {
            self.cells.get(index).copied().unwrap_or(false)
        })
    }

    /// The column walk of [`visit_swept_cells`] on padded indices, for end cells `a` and
    /// `b` in the grid or its border (the callers send others to the reference walk):
    /// `probe(index)` says whether the cell at that padded index is passable. Counts
    /// looked-up cells in `counter.cells` (not the query).
    #[inline]
    fn walk(
        &self,
        a: (i64, i64),
        b: (i64, i64),
        counter: &mut LosCounter,
        mut probe: impl FnMut(usize) -> bool,
    ) -> bool {
        // The frame of `sweep_columns`: `u` is the major axis; `u_stride` and `v_stride`
        // are the index steps of one cell along `u` and `v`.
        let (p0, p1, u_stride, v_stride) = if (b.0 - a.0).abs() >= (b.1 - a.1).abs() {
            (a, b, 1, self.padded_width)
        } else {
            ((a.1, a.0), (b.1, b.0), self.padded_width, 1)
        };
        let ((u0, v0), (u1, v1)) = if p1.0 < p0.0 { (p1, p0) } else { (p0, p1) };
        let du = u1 - u0;
        let dv = (v1 - v0).abs();
        let v_step = if v1 < v0 { -v_stride } else { v_stride };
        // Index of the frame's first cell (u0, v0), back in grid coordinates.
        let (x0, y0) = if u_stride == 1 { (u0, v0) } else { (v0, u0) };
        let origin = (y0 + 1) * self.padded_width + x0 + 1;
        if du == 0 {
            counter.cells += 1;
            return probe(origin as usize);
        }
        // Column k covers rows floor(lo dv / du) ..= ceil(hi dv / du) with lo = max(k - 1, 0)
        // and hi = min(k + 1, du), as in `sweep_columns`. Both quotients are kept as
        // (quotient, remainder) and advanced by adding dv (at most one carry, dv <= du), so
        // the walk needs no division.
        let advance = |(q, r): (i64, i64)| {
            if r + dv >= du {
                (q + 1, r + dv - du)
            } else {
                (q, r + dv)
            }
        };
        let mut lo = (0, 0);
        let mut hi = advance((0, 0));
        // Both ends lie in the padded array, so every swept cell does (it lies in their
        // bounding box) and every index is non-negative; `probe` still guards the upper end.
        let mut column = origin;
        for k in 0..=du {
            let first = lo.0;
            let last = hi.0 + i64::from(hi.1 > 0);
            let mut index = column + first * v_step;
            for j in first..=last {
                if !probe(index as usize) {
                    counter.cells += (j - first + 1) as usize;
                    return false;
                }
                index += v_step;
            }
            counter.cells += (last - first + 1) as usize;
            if k >= 1 {
                lo = advance(lo);
            }
            if k + 1 < du {
                hi = advance(hi);
            }
            column += u_stride;
        }
        true
    }
}

impl Passable for PassableGrid {
    #[inline]
    fn passable(&self, x: i64, y: i64) -> bool {
        self.padded_index((x, y))
            .and_then(|i| self.cells.get(i))
            .copied()
            .unwrap_or(false)
    }

    #[inline]
    fn sight_counted(
        &self,
        a: (usize, usize),
        b: (usize, usize),
        counter: &mut LosCounter,
    ) -> bool {
        self.sight((a.0 as i64, a.1 as i64), (b.0 as i64, b.1 as i64), counter)
    }
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
        let mut grid = OccupancyGrid::new(5, 1, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        grid.set(2, 0, Occupancy::Occupied).unwrap();
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
