//! The D* Lite handle a robot drives with ([`DStarLite`]: `move_start`, `update_cells`,
//! `path`), over a search with narrow or tie keys that widens once and for good when its keys
//! outgrow them; and [`dstar_lite`], a one-shot search.

use crate::error::Result;
use crate::grid::{CellXy, Occupancy, OccupancyGrid};
use crate::plan::{Plan, PlanStats, xy};

use super::keys::{NarrowKey, TieKey, WideKey};
use super::search::{DStarLiteOptions, Planned, Search};

/// A D* Lite search from a moving start to a fixed goal (see the [module docs](super)).
///
/// Its queue holds 16-byte keys (24 under the common tie rule) and widens to 48-byte ones,
/// once and for good, when a key's step counts outgrow them (cells over about a million
/// steps from the goal; see the [module docs](super)).
#[derive(Clone, Debug)]
pub struct DStarLite {
    search: Searches,
}

/// The search with either kind of key.
#[derive(Clone, Debug)]
enum Searches {
    Narrow(Search<NarrowKey>),
    Ties(Search<TieKey>),
    Wide(Search<WideKey>),
}

/// The same code on either kind of search.
macro_rules! each {
    ($searches:expr, $s:ident => $e:expr) => {
        match $searches {
            Searches::Narrow($s) => $e,
            Searches::Ties($s) => $e,
            Searches::Wide($s) => $e,
        }
    };
}

impl DStarLite {
    /// Set up the search on `grid` from `start` to `goal` (no search runs until
    /// [`DStarLite::path`]).
    ///
    /// # Errors
    /// [`PlanError::EndpointOutsideGrid`](crate::PlanError::EndpointOutsideGrid) or
    /// [`PlanError::EndpointBlocked`](crate::PlanError::EndpointBlocked) for a `start` or
    /// `goal` outside the grid or not passable.
    ///
    /// # Complexity
    /// `O(cells)`: 37 bytes per padded cell (41 with the common tie rule), zeroed memory
    /// except the passability, plus the queue.
    pub fn new(
        grid: &OccupancyGrid,
        start: impl Into<CellXy>,
        goal: impl Into<CellXy>,
        opts: &DStarLiteOptions,
    ) -> Result<Self> {
        let (start, goal) = (start.into(), goal.into());
        let search = if opts.common_ties {
            Searches::Ties(Search::new(grid, start, goal, opts)?)
        } else {
            Searches::Narrow(Search::new(grid, start, goal, opts)?)
        };
        let mut this = Self { search };
        this.widen_if_needed();
        Ok(this)
    }

    /// The robot's cell.
    #[must_use]
    pub fn start(&self) -> CellXy {
        each!(&self.search, s => s.cell(s.start))
    }

    /// The goal cell.
    #[must_use]
    pub fn goal(&self) -> CellXy {
        each!(&self.search, s => s.cell(s.goal))
    }

    /// The robot moved to `start` (the paper's `s_start = argmin ...`; any cell is accepted,
    /// the heuristic stays consistent). The key modifier `k_m` grows at the next
    /// [`DStarLite::update_cells`] that changes something.
    ///
    /// # Errors
    /// [`PlanError::EndpointOutsideGrid`](crate::PlanError::EndpointOutsideGrid) outside the
    /// grid.
    pub fn move_start(&mut self, start: impl Into<CellXy>) -> Result<()> {
        let start = start.into();
        each!(&mut self.search, s => s.move_start(start))
    }

    /// Cells whose state changed (to the state given). Updates the affected step costs
    /// and the `rhs` values and queue entries of their ends (Figure 4, lines 38-47), adding
    /// `h(s_last, s_start)` to `k_m` first when any passability changed; returns how many
    /// cells changed passability. A cell listed more than once takes its last state. The new
    /// plan comes from the next [`DStarLite::path`].
    ///
    /// # Errors
    /// [`PlanError::CellOutOfBounds`](crate::PlanError::CellOutOfBounds) for a cell outside
    /// the grid (nothing is changed).
    pub fn update_cells(&mut self, changes: &[(CellXy, Occupancy)]) -> Result<usize> {
        let changed = each!(&mut self.search, s => s.update_cells(changes))?;
        self.widen_if_needed();
        Ok(changed)
    }

    /// A shortest path from the robot's cell to the goal on the current map, every cell
    /// of it (like [`astar`](crate::astar::astar)), or `Ok(None)` when there is none.
    /// Runs the paper's `ComputeShortestPath` first when anything changed; the plan's
    /// statistics count that run's expansions and queue pushes (zero when nothing
    /// changed).
    ///
    /// # Errors
    /// [`PlanError::BudgetExhausted`](crate::PlanError::BudgetExhausted) or
    /// [`PlanError::Stopped`](crate::PlanError::Stopped) from the budget (the search state
    /// stays valid: a later call continues it);
    /// [`PlanError::InconsistentSearch`](crate::PlanError::InconsistentSearch) if the path
    /// cannot be followed (a bug).
    pub fn path(&mut self) -> Result<Option<Plan>> {
        let mut stats = PlanStats::default();
        loop {
            match each!(&mut self.search, s => s.path(&mut stats))? {
                Planned::Done(plan) => return Ok(plan),
                Planned::Widen => self.widen_if_needed(),
            }
        }
    }

    /// Whether the queue holds [`WideKey`]s (for tests).
    #[cfg(test)]
    fn is_wide(&self) -> bool {
        matches!(self.search, Searches::Wide(_))
    }

    /// Move a narrow search whose keys overflowed to wide keys (its `g`, `rhs` and queue
    /// membership carry over as they are: D* Lite's invariants do not depend on the order
    /// of past expansions; every queued key is computed anew).
    fn widen_if_needed(&mut self) {
        let wide = match &mut self.search {
            Searches::Narrow(s) if s.overflow.get() => s.convert(),
            Searches::Ties(s) if s.overflow.get() => s.convert(),
            _ => return,
        };
        self.search = Searches::Wide(wide);
    }
}

/// The shortest path of a one-shot D* Lite search (a fresh [`DStarLite`] and one
/// [`DStarLite::path`]): the same cost as [`astar`](crate::astar::astar), for tests and
/// the planner interface.
///
/// # Errors
/// As [`DStarLite::new`] and [`DStarLite::path`].
pub fn dstar_lite(
    grid: &OccupancyGrid,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    opts: &DStarLiteOptions,
) -> Result<Option<Plan>> {
    let (start, goal) = (xy(start), xy(goal));
    DStarLite::new(grid, start, goal, opts)?.path()
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::dstar_lite::keys::NARROW_MAX_STEPS;

    #[test]
    #[allow(clippy::float_cmp)]
    fn open_grid_straight_line() {
        let grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        let mut p = DStarLite::new(&grid, (0, 1), (4, 1), &DStarLiteOptions::default()).unwrap();
        let plan = p.path().unwrap();
        assert_eq!(plan.unwrap().length_cells, 4.0);
    }

    /// Ordinary searches keep their narrow keys: through walls, dead ends and no path.
    #[test]
    fn ordinary_searches_stay_narrow() {
        let mut grid = OccupancyGrid::new(30, 20, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        for y in 0..19 {
            grid.set(15, y, Occupancy::Occupied).unwrap();
        }
        for common_ties in [false, true] {
            let opts = DStarLiteOptions {
                common_ties,
                ..DStarLiteOptions::default()
            };
            let mut p = DStarLite::new(&grid, (2, 2), (28, 2), &opts).unwrap();
            assert!(p.path().unwrap().is_some());
            p.move_start((3, 3)).unwrap();
            p.update_cells(&[(CellXy::new(15, 19), Occupancy::Occupied)])
                .unwrap();
            assert!(p.path().unwrap().is_none());
            p.update_cells(&[(CellXy::new(15, 10), Occupancy::Free)])
                .unwrap();
            assert!(p.path().unwrap().is_some());
            assert!(!p.is_wide(), "common ties {common_ties}");
        }
    }

    /// A search whose keys outgrow the narrow ones (over a million steps from the goal)
    /// widens and still finds the shortest path: at the start (the heuristic alone is too
    /// long) and in the middle of a drive (with a queue to carry over).
    #[test]
    #[allow(clippy::float_cmp)]
    fn a_search_too_long_for_narrow_keys_widens_and_stays_exact() {
        let width = NARROW_MAX_STEPS as usize + 100;
        let grid = OccupancyGrid::new(width, 1, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        for common_ties in [false, true] {
            let opts = DStarLiteOptions {
                common_ties,
                ..DStarLiteOptions::default()
            };
            widens_and_stays_exact(&grid, &opts);
        }
    }

    #[allow(clippy::float_cmp)]
    fn widens_and_stays_exact(grid: &OccupancyGrid, opts: &DStarLiteOptions) {
        let (grid, opts, width) = (grid, opts, grid.width());
        let mut far = DStarLite::new(grid, (0, 0), (width - 1, 0), opts).unwrap();
        assert!(far.is_wide());
        let plan = far.path().unwrap().unwrap();
        assert_eq!(plan.length_cells, (width - 1) as f64);

        let mut p = DStarLite::new(grid, (width - 50, 0), (width - 1, 0), opts).unwrap();
        assert!(!p.is_wide());
        assert_eq!(p.path().unwrap().unwrap().length_cells, 49.0);
        // The robot is carried far away; a cell beyond the goal's side changes.
        p.move_start((10, 0)).unwrap();
        p.update_cells(&[(CellXy::new(5, 0), Occupancy::Occupied)])
            .unwrap();
        let plan = p.path().unwrap().unwrap();
        assert!(p.is_wide());
        assert_eq!(plan.length_cells, (width - 11) as f64);
        assert_eq!(plan.waypoints.first(), Some(&CellXy::new(10, 0)));
        // And it re-plans on: a wall between the robot and the goal.
        p.update_cells(&[(CellXy::new(20, 0), Occupancy::Occupied)])
            .unwrap();
        assert!(p.path().unwrap().is_none());
    }
}
