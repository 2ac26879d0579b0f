//! The occupancy grid: a row-major raster of [`Occupancy`]s with a metric frame.
//!
//! Semantics, fixed for every module of this crate:
//! - Cells are indexed `(x, y)`: `x` is the column (left to right), `y` is the row counted
//!   from the **top** (as in an image). Cell `(x, y)` lives at `cells[y * width + x]`.
//! - The map frame is right-handed with `+y` up, so rows flip between cell `y` and world `y`:
//!   row 0 is the row of highest world `y`.
//! - `origin_m` is the map-frame position of the **lower-left corner** of the lower-left cell
//!   `(0, height - 1)` (the ROS `map_server` convention). Cell `(x, y)` covers the square
//!   `[ox + x r, ox + (x + 1) r] x [oy + (height - 1 - y) r, oy + (height - y) r]`,
//!   `r = resolution_m`.
//! - Lengths are metres when the floor map is metric; for an unscaled map they are in camera
//!   heights (the names keep `_m`).

use std::sync::atomic::{AtomicU64, Ordering};

pub use crate::cell::{BYTES_PER_CELL, CellXy, Occupancy};
use crate::error::{PlanError, Result};

/// Largest number of cells a grid may have: 30 million cells, about 540 MB of work memory
/// at [`BYTES_PER_CELL`] (a 5,477 x 5,477 grid; 274 m square at 5 cm). A grid is refused
/// with [`PlanError::GridTooLarge`] before anything of its size is allocated.
pub const MAX_CELLS: usize = 30_000_000;

/// The 8 grid moves `(dx, dy)` in the order E, S, W, N, SE, SW, NW, NE (row 0 at the top,
/// so S is `+y`): the straight ones first, each diagonal `4 + i` between the straight moves
/// [`DIAGONAL_SIDES`]`[i]`. The order is what the planners' documented tie-breaks refer to.
pub(crate) const MOVES: [(isize, isize); 8] = [
    (1, 0),
    (0, 1),
    (-1, 0),
    (0, -1),
    (1, 1),
    (-1, 1),
    (-1, -1),
    (1, -1),
];

/// The straight moves (indices into [`MOVES`]) that the diagonal move `4 + i` passes
/// between: both must be open for it (no corner cutting).
pub(crate) const DIAGONAL_SIDES: [(usize, usize); 4] = [(0, 1), (2, 1), (2, 3), (0, 3)];

/// A 2D occupancy grid with a metric frame (see the [module docs](self) for the conventions).
///
/// Two grids are equal when their sizes, cells and frames are (their revisions, which
/// only name a content, are not compared).
#[derive(Clone, Debug)]
pub struct OccupancyGrid {
    width: usize,
    height: usize,
    cells: Vec<Occupancy>,
    resolution_m: f64,
    origin_m: [f64; 2],
    /// A number no other grid content of this process has had: new for every grid made
    /// and at every change of its cells, kept by a clone (whose cells are the same). A
    /// planner that keeps a copy of the cells recognises the grid by it without comparing
    /// them ([`OccupancyGrid::revision`]).
    revision: u64,
}

impl PartialEq for OccupancyGrid {
    fn eq(&self, other: &Self) -> bool {
        self.width == other.width
            && self.height == other.height
            && self.cells == other.cells
            && self.resolution_m == other.resolution_m
            && self.origin_m == other.origin_m
    }
}

/// A revision no grid has had yet (see [`OccupancyGrid::revision`]).
fn new_revision() -> u64 {
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

/// Number of cells of a `width x height` grid, or the error that refuses it.
pub(crate) fn checked_cell_count(width: usize, height: usize) -> Result<usize> {
    if width == 0 || height == 0 {
        return Err(PlanError::EmptyGrid { width, height });
    }
    match width.checked_mul(height) {
        Some(n) if n <= MAX_CELLS => Ok(n),
        _ => Err(PlanError::GridTooLarge {
            width,
            height,
            max: MAX_CELLS,
        }),
    }
}

fn check_frame(resolution_m: f64, origin_m: [f64; 2]) -> Result<()> {
    if !(resolution_m.is_finite() && resolution_m > 0.0) {
        return Err(PlanError::InvalidParameter {
            field: "resolution_m",
            value: resolution_m,
            requirement: "must be finite and positive",
        });
    }
    for (field, value) in [("origin_m[0]", origin_m[0]), ("origin_m[1]", origin_m[1])] {
        if !value.is_finite() {
            return Err(PlanError::InvalidParameter {
                field,
                value,
                requirement: "must be finite",
            });
        }
    }
    Ok(())
}

/// Squared distance, in cells, from a cell centre to the square of a cell `d` cells away
/// along one axis: `max(|d| - 1/2, 0)^2`.
fn axis_gap_sq(d: usize) -> f64 {
    if d == 0 {
        0.0
    } else {
        let g = d as f64 - 0.5;
        g * g
    }
}

/// Lower envelope of the parabolas `q -> (q - b - shift)^2 + f[b]` over the finite `f[b]`,
/// evaluated at every integer `q` (Felzenszwalb and Huttenlocher's 1D distance transform).
/// `out[q]` is infinite when every `f[b]` is infinite.
fn parabola_envelope(
    f: &[f64],
    shift: f64,
    out: &mut [f64],
    vertices: &mut Vec<usize>,
    starts: &mut Vec<f64>,
) {
    vertices.clear();
    starts.clear();
    for (b, &fb) in f.iter().enumerate() {
        if !fb.is_finite() {
            continue;
        }
        let cb = b as f64 + shift;
        while let (Some(&last), Some(&start)) = (vertices.last(), starts.last()) {
            let fl = f.get(last).copied().unwrap_or(f64::INFINITY);
            let cl = last as f64 + shift;
            let s = ((fb + cb * cb) - (fl + cl * cl)) / (2.0 * (cb - cl));
            if s <= start {
                vertices.pop();
                starts.pop();
            } else {
                vertices.push(b);
                starts.push(s);
                break;
            }
        }
        if vertices.is_empty() {
            vertices.push(b);
            starts.push(f64::NEG_INFINITY);
        }
    }
    let mut k = 0;
    for (q, o) in out.iter_mut().enumerate() {
        let qf = q as f64;
        while starts.get(k + 1).is_some_and(|&s| s < qf) {
            k += 1;
        }
        *o = match vertices.get(k) {
            Some(&b) => {
                let d = qf - (b as f64 + shift);
                d * d + f.get(b).copied().unwrap_or(f64::INFINITY)
            }
            None => f64::INFINITY,
        };
    }
}

impl OccupancyGrid {
    /// A `width x height` grid with every cell set to `fill`.
    ///
    /// # Errors
    /// [`PlanError::InvalidParameter`] when `resolution_m` is not finite and positive or
    /// `origin_m` is not finite; [`PlanError::EmptyGrid`] for a zero side;
    /// [`PlanError::GridTooLarge`] above [`MAX_CELLS`] cells.
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::{Occupancy, OccupancyGrid};
    /// let grid = OccupancyGrid::new(4, 3, 0.05, [-0.1, 0.0], Occupancy::Free).unwrap();
    /// assert_eq!((grid.width(), grid.height()), (4, 3));
    /// assert_eq!(grid.counts(), (12, 0, 0));
    /// assert!(OccupancyGrid::new(100_000, 100_000, 0.05, [0.0; 2], Occupancy::Free).is_err());
    /// ```
    pub fn new(
        width: usize,
        height: usize,
        resolution_m: f64,
        origin_m: [f64; 2],
        fill: Occupancy,
    ) -> Result<Self> {
        check_frame(resolution_m, origin_m)?;
        let n = checked_cell_count(width, height)?;
        Ok(Self {
            width,
            height,
            cells: vec![fill; n],
            resolution_m,
            origin_m,
            revision: new_revision(),
        })
    }

    /// A grid from its cells in row-major order, row 0 at the top.
    ///
    /// # Errors
    /// As [`OccupancyGrid::new`], and [`PlanError::CellCount`] when `cells.len()` is not
    /// `width * height`.
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::{Occupancy, OccupancyGrid};
    /// use Occupancy::{Free as F, Occupied as O};
    /// let grid = OccupancyGrid::from_cells(2, 2, 1.0, [0.0; 2], vec![O, F, F, F]).unwrap();
    /// assert_eq!(grid.get(0, 0), Some(O));
    /// assert_eq!(grid.world_from_cell(0, 0), [0.5, 1.5]);
    /// ```
    pub fn from_cells(
        width: usize,
        height: usize,
        resolution_m: f64,
        origin_m: [f64; 2],
        cells: Vec<Occupancy>,
    ) -> Result<Self> {
        check_frame(resolution_m, origin_m)?;
        let n = checked_cell_count(width, height)?;
        if cells.len() != n {
            return Err(PlanError::CellCount {
                width,
                height,
                expected: n,
                found: cells.len(),
            });
        }
        Ok(Self {
            width,
            height,
            cells,
            resolution_m,
            origin_m,
            revision: new_revision(),
        })
    }

    /// Number of columns.
    #[must_use]
    pub fn width(&self) -> usize {
        self.width
    }

    /// Number of rows.
    #[must_use]
    pub fn height(&self) -> usize {
        self.height
    }

    /// Side length of a cell, metres.
    #[must_use]
    pub fn resolution_m(&self) -> f64 {
        self.resolution_m
    }

    /// Map-frame position of the lower-left corner of the lower-left cell, metres.
    #[must_use]
    pub fn origin_m(&self) -> [f64; 2] {
        self.origin_m
    }

    /// Every cell, row-major, row 0 at the top.
    #[must_use]
    pub fn cells(&self) -> &[Occupancy] {
        &self.cells
    }

    /// Every cell, mutable, row-major, row 0 at the top (the grid takes a new
    /// [revision](OccupancyGrid::revision)).
    #[must_use]
    pub fn cells_mut(&mut self) -> &mut [Occupancy] {
        self.revision = new_revision();
        &mut self.cells
    }

    /// A number that names this grid's content within the process: two grids with the
    /// same revision have the same size and cells (one is a clone of the other, neither
    /// changed since). Every grid made gets a new one, and so does a grid at every
    /// [`set`](OccupancyGrid::set) and [`cells_mut`](OccupancyGrid::cells_mut). Searches
    /// that keep a padded copy of the cells ([`AstarSearch`](crate::AstarSearch)) reuse it
    /// while the revision is the one they copied.
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::{Occupancy, OccupancyGrid};
    /// let mut grid = OccupancyGrid::new(2, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    /// let copy = grid.clone();
    /// assert_eq!(copy.revision(), grid.revision());
    /// grid.set(0, 0, Occupancy::Occupied).unwrap();
    /// assert_ne!(copy.revision(), grid.revision());
    /// let other = OccupancyGrid::new(2, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    /// assert_eq!(other, copy); // same content: equal,
    /// assert_ne!(other.revision(), copy.revision()); // but made apart
    /// ```
    #[must_use]
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// Index of cell `(x, y)` in [`OccupancyGrid::cells`], or `None` outside the grid.
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::{Occupancy, OccupancyGrid};
    /// let grid = OccupancyGrid::new(3, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    /// assert_eq!(grid.index(2, 1), Some(5));
    /// assert_eq!(grid.index(3, 0), None);
    /// ```
    #[inline]
    #[must_use]
    pub fn index(&self, x: usize, y: usize) -> Option<usize> {
        (x < self.width && y < self.height).then(|| y * self.width + x)
    }

    /// The cell at `(x, y)`, or `None` outside the grid.
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::{Occupancy, OccupancyGrid};
    /// let grid = OccupancyGrid::new(3, 2, 1.0, [0.0; 2], Occupancy::Unknown).unwrap();
    /// assert_eq!(grid.get(2, 1), Some(Occupancy::Unknown));
    /// assert_eq!(grid.get(0, 2), None);
    /// ```
    #[inline]
    #[must_use]
    pub fn get(&self, x: usize, y: usize) -> Option<Occupancy> {
        self.index(x, y).and_then(|i| self.cells.get(i).copied())
    }

    /// Whether `(x, y)` is inside the grid and [`Occupancy::Free`].
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::{Occupancy, OccupancyGrid};
    /// let grid = OccupancyGrid::new(2, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    /// assert!(grid.is_free(1, 1));
    /// assert!(!grid.is_free(2, 1));
    /// ```
    #[inline]
    #[must_use]
    pub fn is_free(&self, x: usize, y: usize) -> bool {
        self.get(x, y) == Some(Occupancy::Free)
    }

    /// Set the cell at `(x, y)`.
    ///
    /// # Errors
    /// [`PlanError::CellOutOfBounds`] outside the grid.
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::{Occupancy, OccupancyGrid};
    /// let mut grid = OccupancyGrid::new(2, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    /// grid.set(1, 0, Occupancy::Occupied).unwrap();
    /// assert_eq!(grid.counts(), (3, 1, 0));
    /// assert!(grid.set(2, 0, Occupancy::Occupied).is_err());
    /// ```
    pub fn set(&mut self, x: usize, y: usize, cell: Occupancy) -> Result<()> {
        let slot = self.index(x, y).and_then(|i| self.cells.get_mut(i)).ok_or(
            PlanError::CellOutOfBounds {
                x,
                y,
                width: self.width,
                height: self.height,
            },
        )?;
        *slot = cell;
        self.revision = new_revision();
        Ok(())
    }

    /// Map-frame position of the centre of cell `(x, y)`, metres (also defined for indices
    /// outside the grid).
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::{Occupancy, OccupancyGrid};
    /// let grid = OccupancyGrid::new(4, 3, 0.5, [-1.0, 2.0], Occupancy::Free).unwrap();
    /// // Row 0 is the top row: highest world y.
    /// assert_eq!(grid.world_from_cell(0, 0), [-0.75, 3.25]);
    /// assert_eq!(grid.world_from_cell(3, 2), [0.75, 2.25]);
    /// ```
    #[must_use]
    pub fn world_from_cell(&self, x: usize, y: usize) -> [f64; 2] {
        let r = self.resolution_m;
        [
            self.origin_m[0] + (x as f64 + 0.5) * r,
            self.origin_m[1] + (self.height as f64 - y as f64 - 0.5) * r,
        ]
    }

    /// The cell containing a map-frame point, or `None` outside the grid (or for a
    /// non-finite point). Cells are half-open: a point on a shared edge belongs to the
    /// cell on its right (larger `x`) and above it (larger world `y`).
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::{CellXy, Occupancy, OccupancyGrid};
    /// let grid = OccupancyGrid::new(4, 3, 0.5, [-1.0, 2.0], Occupancy::Free).unwrap();
    /// assert_eq!(grid.cell_from_world([-0.75, 3.25]), Some(CellXy::new(0, 0)));
    /// assert_eq!(grid.cell_from_world([-1.0, 2.0]), Some(CellXy { x: 0, y: 2 }));
    /// assert_eq!(grid.cell_from_world([1.0, 2.0]), None);
    /// ```
    #[must_use]
    pub fn cell_from_world(&self, point_m: [f64; 2]) -> Option<CellXy> {
        let u = (point_m[0] - self.origin_m[0]) / self.resolution_m;
        let v = (point_m[1] - self.origin_m[1]) / self.resolution_m;
        if !(u >= 0.0 && v >= 0.0 && u < self.width as f64 && v < self.height as f64) {
            return None;
        }
        let x = (u.floor() as usize).min(self.width - 1);
        let row_from_bottom = (v.floor() as usize).min(self.height - 1);
        Some(CellXy::new(x, self.height - 1 - row_from_bottom))
    }

    /// Number of `(free, occupied, unknown)` cells.
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::{Occupancy, OccupancyGrid};
    /// let grid = OccupancyGrid::new(2, 3, 1.0, [0.0; 2], Occupancy::Unknown).unwrap();
    /// assert_eq!(grid.counts(), (0, 0, 6));
    /// ```
    #[must_use]
    pub fn counts(&self) -> (usize, usize, usize) {
        let mut counts = (0, 0, 0);
        for c in &self.cells {
            match c {
                Occupancy::Free => counts.0 += 1,
                Occupancy::Occupied => counts.1 += 1,
                Occupancy::Unknown => counts.2 += 1,
            }
        }
        counts
    }

    /// Squared distance, in cells, from every cell centre to the nearest occupied cell's
    /// square; infinite when the grid has no occupied cell.
    ///
    /// For offsets `(dx, dy)` in cells the distance is `g(dx) + g(dy)` with
    /// `g(d) = max(|d| - 1/2, 0)^2`. Separable: a row pass gives the horizontal term, a
    /// column pass takes the lower envelope of the half-cell-shifted parabolas
    /// `(y - b -+ 1/2)^2 + f(b)` on either side, which is exact in `O(width x height)`.
    fn obstacle_distance_sq_cells(&self) -> Vec<f64> {
        let (w, h) = (self.width, self.height);
        // Row pass: squared horizontal gap to the nearest occupied cell of the same row.
        let mut column_cost = vec![f64::INFINITY; self.cells.len()];
        for (row, out) in self.cells.chunks(w).zip(column_cost.chunks_mut(w)) {
            let mut nearest: Option<usize> = None;
            for (x, (c, o)) in row.iter().zip(out.iter_mut()).enumerate() {
                if *c == Occupancy::Occupied {
                    nearest = Some(x);
                }
                if let Some(a) = nearest {
                    *o = axis_gap_sq(x - a);
                }
            }
            nearest = None;
            for (x, (c, o)) in row.iter().zip(out.iter_mut()).enumerate().rev() {
                if *c == Occupancy::Occupied {
                    nearest = Some(x);
                }
                if let Some(a) = nearest {
                    *o = o.min(axis_gap_sq(a - x));
                }
            }
        }
        // Column pass.
        let mut f = vec![0.0; h];
        let mut above = vec![0.0; h];
        let mut below = vec![0.0; h];
        let (mut vertices, mut starts) = (Vec::with_capacity(h), Vec::with_capacity(h));
        for x in 0..w {
            for (fy, cost) in f.iter_mut().zip(column_cost.iter().skip(x).step_by(w)) {
                *fy = *cost;
            }
            parabola_envelope(&f, 0.5, &mut above, &mut vertices, &mut starts);
            parabola_envelope(&f, -0.5, &mut below, &mut vertices, &mut starts);
            let column = column_cost.iter_mut().skip(x).step_by(w);
            for (((out, fy), a), b) in column.zip(&f).zip(&above).zip(&below) {
                *out = fy.min(*a).min(*b);
            }
        }
        column_cost
    }

    /// Distance, metres, from every cell centre to the nearest occupied cell's square
    /// (0 for occupied cells), row-major like [`OccupancyGrid::cells`]; infinite when the
    /// grid has no occupied cell. Exact Euclidean distance, not a chamfer approximation.
    ///
    /// # Complexity
    /// `O(width x height)` time, two `f64` buffers of the grid's size.
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::{Occupancy, OccupancyGrid};
    /// let mut grid = OccupancyGrid::new(4, 1, 0.1, [0.0; 2], Occupancy::Free).unwrap();
    /// grid.set(0, 0, Occupancy::Occupied).unwrap();
    /// let d = grid.obstacle_distance_m();
    /// assert!((d[3] - 0.25).abs() < 1e-12); // centre 0.35 m, obstacle square ends at 0.1 m
    /// ```
    #[must_use]
    pub fn obstacle_distance_m(&self) -> Vec<f64> {
        let r = self.resolution_m;
        self.obstacle_distance_sq_cells()
            .into_iter()
            .map(|d| d.sqrt() * r)
            .collect()
    }

    /// The grid with obstacles grown by `radius_m`: every cell whose centre lies within
    /// `radius_m` (inclusive) of an occupied cell's square becomes [`Occupancy::Occupied`],
    /// whether it was [`Occupancy::Free`] or [`Occupancy::Unknown`] (a robot centred there would
    /// overlap the obstacle either way). Other cells keep their state, so unknown cells
    /// farther from obstacles stay unknown. A radius of 0 returns an identical grid.
    ///
    /// # Errors
    /// [`PlanError::InvalidParameter`] when `radius_m` is negative or not finite.
    ///
    /// # Complexity
    /// `O(width x height)` whatever the radius: an exact Euclidean distance transform
    /// (Felzenszwalb and Huttenlocher) to the obstacles' squares, thresholded.
    ///
    /// # References
    /// P. F. Felzenszwalb, D. P. Huttenlocher, "Distance Transforms of Sampled Functions",
    /// Theory of Computing 8 (2012).
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::{Occupancy, OccupancyGrid};
    /// let mut grid = OccupancyGrid::new(5, 5, 0.1, [0.0; 2], Occupancy::Free).unwrap();
    /// grid.set(2, 2, Occupancy::Occupied).unwrap();
    /// // 0.06 m reaches the 4 side neighbours (0.05 m away), not the diagonals (0.0707 m)...
    /// assert_eq!(grid.inflate(0.06).unwrap().counts().1, 5);
    /// // ...which 0.075 m reaches.
    /// assert_eq!(grid.inflate(0.075).unwrap().counts().1, 9);
    /// ```
    pub fn inflate(&self, radius_m: f64) -> Result<OccupancyGrid> {
        if !(radius_m.is_finite() && radius_m >= 0.0) {
            return Err(PlanError::InvalidParameter {
                field: "radius_m",
                value: radius_m,
                requirement: "must be finite and non-negative",
            });
        }
        let mut out = self.clone();
        if radius_m == 0.0 || !self.cells.contains(&Occupancy::Occupied) {
            return Ok(out);
        }
        let limit_sq_cells = (radius_m / self.resolution_m).powi(2);
        let distance = self.obstacle_distance_sq_cells();
        for (c, d) in out.cells.iter_mut().zip(distance) {
            if d <= limit_sq_cells {
                *c = Occupancy::Occupied;
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::float_cmp)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn brute_distance_sq(grid: &OccupancyGrid, x: usize, y: usize) -> f64 {
        let mut best = f64::INFINITY;
        for b in 0..grid.height() {
            for a in 0..grid.width() {
                if grid.get(a, b) == Some(Occupancy::Occupied) {
                    best = best.min(axis_gap_sq(a.abs_diff(x)) + axis_gap_sq(b.abs_diff(y)));
                }
            }
        }
        best
    }

    #[test]
    fn world_and_cell_transforms_are_inverse() {
        let grid = OccupancyGrid::new(7, 5, 0.2, [-3.0, 1.5], Occupancy::Free).unwrap();
        for y in 0..5 {
            for x in 0..7 {
                assert_eq!(
                    grid.cell_from_world(grid.world_from_cell(x, y)),
                    Some(CellXy::new(x, y))
                );
            }
        }
        assert_relative_eq!(grid.world_from_cell(0, 4)[1], 1.6);
        assert_relative_eq!(grid.world_from_cell(0, 0)[1], 2.4);
        assert_eq!(grid.cell_from_world([f64::NAN, 2.0]), None);
        assert_eq!(grid.cell_from_world([-3.0001, 2.0]), None);
        assert_eq!(grid.cell_from_world([-2.0, 2.5]), None);
        assert_eq!(
            grid.cell_from_world([-2.0, 2.4999]),
            Some(CellXy::new(5, 0))
        );
    }

    #[test]
    fn invalid_frames_and_sizes_are_refused() {
        let e = OccupancyGrid::new(2, 2, 0.0, [0.0; 2], Occupancy::Free).unwrap_err();
        assert!(e.to_string().contains("resolution_m"), "{e}");
        let e = OccupancyGrid::new(2, 2, 1.0, [0.0, f64::NAN], Occupancy::Free).unwrap_err();
        assert!(e.to_string().contains("origin_m[1]"), "{e}");
        let e = OccupancyGrid::new(0, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap_err();
        assert!(matches!(e, PlanError::EmptyGrid { .. }));
        let e = OccupancyGrid::new(usize::MAX, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap_err();
        assert!(matches!(e, PlanError::GridTooLarge { .. }));
        let e = OccupancyGrid::new(20_001, 10_000, 1.0, [0.0; 2], Occupancy::Free).unwrap_err();
        assert!(e.to_string().contains("20001 x 10000"), "{e}");
        let e =
            OccupancyGrid::from_cells(2, 2, 1.0, [0.0; 2], vec![Occupancy::Free; 3]).unwrap_err();
        assert!(matches!(
            e,
            PlanError::CellCount {
                expected: 4,
                found: 3,
                ..
            }
        ));
    }

    #[test]
    fn distance_transform_matches_brute_force() {
        let mut grid = OccupancyGrid::new(13, 9, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        for (x, y) in [(0, 0), (5, 4), (6, 4), (12, 8), (3, 7)] {
            grid.set(x, y, Occupancy::Occupied).unwrap();
        }
        let d = grid.obstacle_distance_sq_cells();
        for y in 0..9 {
            for x in 0..13 {
                assert_eq!(d[y * 13 + x], brute_distance_sq(&grid, x, y), "({x}, {y})");
            }
        }
    }

    #[test]
    fn inflation_without_obstacles_or_radius_is_identity() {
        let mut grid = OccupancyGrid::new(4, 3, 0.1, [0.0; 2], Occupancy::Unknown).unwrap();
        assert_eq!(grid.inflate(1.0).unwrap(), grid);
        assert!(grid.obstacle_distance_m().iter().all(|d| d.is_infinite()));
        grid.set(1, 1, Occupancy::Occupied).unwrap();
        assert_eq!(grid.inflate(0.0).unwrap(), grid);
        assert_eq!(grid.inflate(0.049).unwrap(), grid);
        assert!(grid.inflate(-0.1).is_err());
        assert!(grid.inflate(f64::INFINITY).is_err());
    }

    #[test]
    fn inflation_turns_unknown_cells_into_obstacles() {
        let mut grid = OccupancyGrid::new(5, 1, 1.0, [0.0; 2], Occupancy::Unknown).unwrap();
        grid.set(0, 0, Occupancy::Occupied).unwrap();
        grid.set(4, 0, Occupancy::Free).unwrap();
        let inflated = grid.inflate(1.5).unwrap();
        let (f, o, u) = (Occupancy::Free, Occupancy::Occupied, Occupancy::Unknown);
        assert_eq!(inflated.cells(), &[o, o, o, u, f]);
    }
}
