//! The free space of the collision rule cut along the row lines (see "The free space,
//! exactly" in the [module docs](super)), built once per grid: each row's runs of passable
//! cells, each strip's rectangles, the corner cells (the only places a shortest path bends)
//! and the dead-end table ([`super::dead_ends`]).

use crate::corners::is_corner_cell;
use crate::grid::OccupancyGrid;
use crate::los::{Passable, PassableGrid};

use super::dead_ends::{dead_ends, enters_dead_end};

/// The free space of one grid (see the [module docs](self)).
#[derive(Clone, Debug)]
pub(super) struct FreeSpace {
    /// Grid width, cells.
    pub(super) width: i32,
    /// Grid height, cells.
    pub(super) height: i32,
    /// Per row: its maximal runs `(first, last)` of passable cells, by column.
    runs: Vec<Vec<(i32, i32)>>,
    /// Per strip `y` (between rows `y` and `y + 1`): its rectangles `(a, b)`, by `a`.
    strips: Vec<Vec<(i32, i32)>>,
    /// Per strip and rectangle (as `strips`): `[up, down]`, the last row of the dead end
    /// entered through the rectangle upwards and downwards
    /// ([`NOT_DEAD`](super::dead_ends::NOT_DEAD) when it is none; see
    /// [`FreeSpace::dead_end`]).
    dead: Vec<Vec<[i32; 2]>>,
    /// Per cell: whether it is a corner cell ([`crate::optimal::corner_cells`]), the only
    /// places a shortest path bends.
    corner: Vec<bool>,
}

impl FreeSpace {
    /// Build the free space of `grid` (unknown cells passable or not).
    pub(super) fn new(grid: &OccupancyGrid, unknown_passable: bool) -> Self {
        let passable = PassableGrid::new(grid, unknown_passable);
        let (w, h) = (grid.width() as i32, grid.height() as i32);
        let free = |x: i32, y: i32| passable.passable(i64::from(x), i64::from(y));
        let runs: Vec<Vec<(i32, i32)>> = (0..h).map(|y| runs_of(w, |x| free(x, y))).collect();
        let strips: Vec<Vec<(i32, i32)>> = (0..h - 1)
            .map(|y| runs_of(w, |x| free(x, y) && free(x, y + 1)))
            .collect();
        let dead = dead_ends(&runs, &strips);
        // A corner cell (x, y) has a blocked diagonal neighbour (x + dx, y + dy) with
        // (x, y + dy) passable: x ends a run of row y + dy on the dx side. So only the ends
        // of the runs of the rows above and below are asked.
        let mut corner = vec![false; grid.width() * grid.height()];
        for y in 0..h {
            let beside = [y - 1, y + 1].map(|r| usize::try_from(r).ok().and_then(|r| runs.get(r)));
            for &(a, b) in beside.into_iter().flatten().flatten() {
                for x in [a, b] {
                    if is_corner_cell(&passable, i64::from(x), i64::from(y))
                        && let Some(slot) = corner.get_mut((y * w + x) as usize)
                    {
                        *slot = true;
                    }
                }
            }
        }
        Self {
            width: w,
            height: h,
            runs,
            strips,
            dead,
            corner,
        }
    }

    /// The run `(first, last)` of row `y` holding column `x`, if that cell is passable.
    pub(super) fn run_at(&self, x: i32, y: i32) -> Option<(i32, i32)> {
        let runs = self.runs.get(usize::try_from(y).ok()?)?;
        runs.get(runs.partition_point(|&(_, b)| b < x))
            .copied()
            .filter(|&(a, _)| a <= x)
    }

    /// Whether entering rectangle `index` of strip `strip` in direction `dir` leads into a
    /// dead end that does not hold `goal` ([`enters_dead_end`]).
    pub(super) fn dead_end(&self, strip: i32, index: usize, dir: i32, goal: (i32, i32)) -> bool {
        enters_dead_end(&self.strips, &self.dead, strip, index, dir, goal)
    }

    /// Whether the cell centre `(x, y)` is a corner cell (none outside the grid).
    pub(super) fn is_corner(&self, x: i32, y: i32) -> bool {
        x >= 0
            && y >= 0
            && x < self.width
            && y < self.height
            && self.corner.get((y * self.width + x) as usize) == Some(&true)
    }

    /// The rectangles of the strip between rows `s` and `s + 1` (none outside the grid).
    pub(super) fn strip(&self, s: i32) -> &[(i32, i32)] {
        usize::try_from(s)
            .ok()
            .and_then(|s| self.strips.get(s))
            .map_or(&[], Vec::as_slice)
    }
}

/// The maximal runs `(first, last)` of the columns `0..width` where `inside` holds.
fn runs_of(width: i32, inside: impl Fn(i32) -> bool) -> Vec<(i32, i32)> {
    let mut runs = Vec::new();
    let mut x = 0;
    while x < width {
        if inside(x) {
            let first = x;
            while x + 1 < width && inside(x + 1) {
                x += 1;
            }
            runs.push((first, x));
        }
        x += 1;
    }
    runs
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::grid::{CellXy, Occupancy};

    use super::super::dead_ends::NOT_DEAD;

    #[test]
    fn corner_flags_are_the_corner_cells() {
        // A seeded pseudo-random grid (xorshift), unknown cells passable or not.
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        for density in [1, 3, 5] {
            let mut grid = OccupancyGrid::new(23, 17, 1.0, [0.0; 2], Occupancy::Free).unwrap();
            for y in 0..17 {
                for x in 0..23 {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    match state % 10 {
                        v if v < density => grid.set(x, y, Occupancy::Occupied).unwrap(),
                        9 => grid.set(x, y, Occupancy::Unknown).unwrap(),
                        _ => {}
                    }
                }
            }
            for unknown_passable in [false, true] {
                let space = FreeSpace::new(&grid, unknown_passable);
                let flagged: Vec<CellXy> = (0..17)
                    .flat_map(|y| (0..23).map(move |x| (x, y)))
                    .filter(|&(x, y)| space.is_corner(x, y))
                    .map(|(x, y)| CellXy::new(x as usize, y as usize))
                    .collect();
                assert_eq!(
                    flagged,
                    crate::corners::corner_cells(&grid, unknown_passable)
                );
            }
        }
    }

    #[test]
    fn dead_ends_are_found() {
        // #.###
        // #.###
        // .....
        // .....
        let mut grid = OccupancyGrid::new(5, 4, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        for (x, y) in [
            (0, 0),
            (2, 0),
            (3, 0),
            (4, 0),
            (0, 1),
            (2, 1),
            (3, 1),
            (4, 1),
        ] {
            grid.set(x, y, Occupancy::Occupied).unwrap();
        }
        let space = FreeSpace::new(&grid, false);
        // Strips 0 and 1 hold the corridor's zero-width rectangle, a dead end towards row 0
        // ending there; towards row 3 it opens into rows 2 and 3, no dead end. Strip 2
        // (rows 2 and 3) is one both ways: towards row 3 the grid ends, towards row 0 the
        // run of row 2 is exactly its span and the only way on is the corridor.
        assert_eq!(space.dead[0], [[NOT_DEAD, 0]]);
        assert_eq!(space.dead[1], [[NOT_DEAD, 0]]);
        assert_eq!(space.dead[2], [[3, 0]]);
        // Entering strip 1's rectangle towards row 0 enters the dead end, unless the goal is
        // in it.
        assert!(space.dead_end(1, 0, -1, (4, 3)));
        assert!(!space.dead_end(1, 0, -1, (1, 0)));
    }
}
