//! Which cells can reach which: connected components of the passable cells by
//! breadth-first search, the reference for "is there a path at all".
//!
//! Semantics: cells are passable by [`cell_passable`]; the planners move 8-connected
//! without corner cutting (see [`crate::los`]). A legal diagonal step needs both
//! orthogonal neighbours passable, so it can be replaced by two straight steps, and
//! straight steps are legal 8-connected steps: the components under the planners' moves
//! are exactly the 4-connected components, which is what this module computes (4
//! neighbours per cell, no line-of-sight walk), independently of every planner.

use std::collections::VecDeque;

use crate::grid::{CellXy, OccupancyGrid};
use crate::los::cell_passable;

/// The connected components of a grid's passable cells (see the [module docs](self)).
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, reach::Components};
/// // ..#.
/// // .#..
/// let mut grid = OccupancyGrid::new(4, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// grid.set(2, 0, Occupancy::Occupied).unwrap();
/// grid.set(1, 1, Occupancy::Occupied).unwrap();
/// let components = Components::label(&grid, false);
/// assert_eq!(components.count(), 2); // no squeezing between (2, 0) and (1, 1)
/// assert!(components.connected((0, 0), (1, 0)));
/// assert!(!components.connected((1, 0), (2, 1)));
/// assert_eq!(components.of((1, 1)), None);
/// assert_eq!(components.size(components.of((3, 0)).unwrap()), 3);
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Components {
    width: usize,
    height: usize,
    /// Per cell, row-major: 0 for a blocked cell, else its component number from 1.
    labels: Vec<u32>,
    /// Cells per component (index `label - 1`).
    sizes: Vec<usize>,
}

impl Components {
    /// Label the cells of `grid` passable by [`cell_passable`] (unknown cells when
    /// `unknown_passable`), in row-major order of each component's first cell.
    ///
    /// # Complexity
    /// `O(width x height)` time, 4 bytes per cell.
    #[must_use]
    pub fn label(grid: &OccupancyGrid, unknown_passable: bool) -> Self {
        let (w, h) = (grid.width(), grid.height());
        let passable: Vec<bool> = grid
            .cells()
            .iter()
            .map(|&c| cell_passable(c, unknown_passable))
            .collect();
        let mut labels = vec![0u32; w * h];
        let mut sizes = Vec::new();
        let mut queue = VecDeque::new();
        for seed in 0..w * h {
            if !passable.get(seed).copied().unwrap_or(false)
                || labels.get(seed).is_none_or(|&l| l != 0)
            {
                continue;
            }
            // Fewer cells than MAX_CELLS < u32::MAX, so labels fit.
            let label = sizes.len() as u32 + 1;
            if let Some(l) = labels.get_mut(seed) {
                *l = label;
            }
            queue.push_back(seed);
            let mut size = 0;
            while let Some(i) = queue.pop_front() {
                size += 1;
                let (x, y) = (i % w, i / w);
                let neighbours = [
                    (x > 0).then(|| i - 1),
                    (x + 1 < w).then(|| i + 1),
                    (y > 0).then(|| i - w),
                    (y + 1 < h).then(|| i + w),
                ];
                for j in neighbours.into_iter().flatten() {
                    if passable.get(j).copied().unwrap_or(false)
                        && let Some(l) = labels.get_mut(j)
                        && *l == 0
                    {
                        *l = label;
                        queue.push_back(j);
                    }
                }
            }
            sizes.push(size);
        }
        Self {
            width: w,
            height: h,
            labels,
            sizes,
        }
    }

    /// The component number (from 1) of cell `(x, y)`, `None` when it is blocked or
    /// outside the grid.
    #[must_use]
    pub fn of(&self, cell: impl Into<CellXy>) -> Option<u32> {
        let CellXy { x, y } = cell.into();
        if x >= self.width || y >= self.height {
            return None;
        }
        match self.labels.get(y * self.width + x) {
            Some(&l) if l > 0 => Some(l),
            _ => None,
        }
    }

    /// Whether a planner can get from cell `a` to cell `b`: both passable and in one
    /// component.
    #[must_use]
    pub fn connected(&self, a: impl Into<CellXy>, b: impl Into<CellXy>) -> bool {
        matches!((self.of(a), self.of(b)), (Some(p), Some(q)) if p == q)
    }

    /// The label of every cell, row-major: 0 for a blocked cell, else its component number
    /// from 1 (see [`Components::of`]).
    #[must_use]
    pub fn labels(&self) -> &[u32] {
        &self.labels
    }

    /// Number of components.
    #[must_use]
    pub fn count(&self) -> usize {
        self.sizes.len()
    }

    /// Number of passable cells (the sum of every component's size).
    #[must_use]
    pub fn passable_cells(&self) -> usize {
        self.sizes.iter().sum()
    }

    /// The cell at row-major index `i` of [`Components::labels`].
    #[must_use]
    pub fn cell_at(&self, i: usize) -> CellXy {
        CellXy::new(i % self.width.max(1), i / self.width.max(1))
    }

    /// Cells in component `label` (0 for a number that is not a component).
    #[must_use]
    pub fn size(&self, label: u32) -> usize {
        (label as usize)
            .checked_sub(1)
            .and_then(|i| self.sizes.get(i))
            .copied()
            .unwrap_or(0)
    }
}

/// Whether `goal` can be reached from `start` by the planners' moves (see the
/// [module docs](self)); `false` when either is blocked or outside the grid. Labels the
/// whole grid: use [`Components`] for many queries.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, reach::reachable};
/// let mut grid = OccupancyGrid::new(3, 1, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// grid.set(1, 0, Occupancy::Unknown).unwrap();
/// assert!(!reachable(&grid, (0, 0), (2, 0), false));
/// assert!(reachable(&grid, (0, 0), (2, 0), true));
/// ```
#[must_use]
pub fn reachable(
    grid: &OccupancyGrid,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    unknown_passable: bool,
) -> bool {
    Components::label(grid, unknown_passable).connected(start, goal)
}
