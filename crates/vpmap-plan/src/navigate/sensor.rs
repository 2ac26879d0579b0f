//! The robot's sensor and its belief about the map.

use crate::grid::{CellXy, Occupancy, OccupancyGrid};
use crate::los::{cell_passable, visit_swept_cells};

/// What one sensing changed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sensed {
    /// Cells whose believed state changed, with their new state.
    pub changes: Vec<(CellXy, Occupancy)>,
    /// Whether a cell the planners could not enter became passable.
    pub opened: bool,
}

/// Largest sensor range accepted, cells: sensing costs `O(R^3)` cell look-ups per move
/// (`pi R^2` cells in range, each checked along a sight line of up to `R` cells).
pub const MAX_SENSOR_RANGE_CELLS: f64 = 256.0;

/// What the robot believes about the map, and which cells it has seen.
///
/// A cell is **seen** from the robot's cell `r` when the distance between their centres is
/// at most the sensor range and the unit square swept from `r`'s centre to the cell's
/// centre (the project's line-of-sight rule, [`crate::los`]) overlaps no cell that is
/// blocked on the **true** map, the seen cell itself excepted (so obstacles are seen, and
/// hide what lies behind them). A seen cell's belief becomes its true state:
/// [`Occupancy::Free`] stays free, [`Occupancy::Occupied`] and [`Occupancy::Unknown`]
/// (nothing to stand on) become occupied.
#[derive(Clone, Debug)]
pub struct Belief {
    /// The believed map.
    pub grid: OccupancyGrid,
    /// Per cell, row-major: seen at least once.
    pub seen: Vec<bool>,
    /// Cell offsets within the range, nearest first.
    offsets: Vec<(i64, i64)>,
}

impl Belief {
    /// A belief starting from `grid`, with a sensor of `range_cells` (nothing seen yet).
    #[must_use]
    pub fn new(grid: OccupancyGrid, range_cells: f64) -> Self {
        let r = range_cells.max(0.0).floor() as i64;
        let mut offsets = Vec::new();
        for dy in -r..=r {
            for dx in -r..=r {
                if ((dx * dx + dy * dy) as f64).sqrt() <= range_cells {
                    offsets.push((dx, dy));
                }
            }
        }
        offsets.sort_by_key(|&(dx, dy)| dx * dx + dy * dy);
        let seen = vec![false; grid.cells().len()];
        Self {
            grid,
            seen,
            offsets,
        }
    }

    /// Sense from `robot` on the true map `truth` (same size as the belief): every cell
    /// seen (see [`Belief`]) gets its true state. Returns the changes; "passable" is
    /// [`cell_passable`] with `unknown_passable`.
    pub fn sense(
        &mut self,
        truth: &OccupancyGrid,
        robot: CellXy,
        unknown_passable: bool,
    ) -> Sensed {
        let mut changes = Vec::new();
        let mut opened = false;
        let (w, h) = (self.grid.width() as i64, self.grid.height() as i64);
        let (rx, ry) = (robot.x as i64, robot.y as i64);
        let blocked = |x: i64, y: i64| {
            usize::try_from(x)
                .ok()
                .zip(usize::try_from(y).ok())
                .and_then(|(x, y)| truth.get(x, y))
                .is_none_or(|c| c != Occupancy::Free)
        };
        for &(dx, dy) in &self.offsets {
            let (x, y) = (rx + dx, ry + dy);
            if x < 0 || y < 0 || x >= w || y >= h {
                continue;
            }
            let (ux, uy) = (x as usize, y as usize);
            let Some(index) = self.grid.index(ux, uy) else {
                continue;
            };
            if self.seen.get(index).copied().unwrap_or(true) {
                continue;
            }
            let visible = visit_swept_cells(robot, (ux, uy), |cx, cy| {
                (cx == x && cy == y) || !blocked(cx, cy)
            });
            if !visible {
                continue;
            }
            if let Some(s) = self.seen.get_mut(index) {
                *s = true;
            }
            let now = if blocked(x, y) {
                Occupancy::Occupied
            } else {
                Occupancy::Free
            };
            if let Some(cell) = self.grid.cells_mut().get_mut(index)
                && *cell != now
            {
                opened |= !cell_passable(*cell, unknown_passable) && now == Occupancy::Free;
                *cell = now;
                changes.push((CellXy::new(ux, uy), now));
            }
        }
        Sensed { changes, opened }
    }

    /// Believe free every cell the belief holds impassable (under `unknown_passable`) that
    /// the sensor has never seen (the map's unverified obstacles); returns the changes.
    ///
    /// # Errors
    /// Not expected (the cells are the grid's own).
    pub(super) fn doubt_unseen(
        &mut self,
        unknown_passable: bool,
    ) -> crate::error::Result<Vec<(CellXy, Occupancy)>> {
        let width = self.grid.width();
        let mut changes = Vec::new();
        for (i, (&cell, &seen)) in self.grid.cells().iter().zip(&self.seen).enumerate() {
            if !seen && !cell_passable(cell, unknown_passable) && width > 0 {
                changes.push((CellXy::new(i % width, i / width), Occupancy::Free));
            }
        }
        for &(c, o) in &changes {
            self.grid.set(c.x, c.y, o)?;
        }
        Ok(changes)
    }
}
