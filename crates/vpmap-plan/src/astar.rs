//! A* on the 8-connected grid with octile costs: the grid-path baseline.
//!
//! Semantics: the robot moves between the centres of 8-neighbouring traversable cells. A
//! straight step costs 1 and needs its target cell traversable; a diagonal step costs
//! `sqrt 2` and needs its target **and both orthogonal neighbours** traversable (no corner
//! cutting, no squeezing between two blocked cells that share a corner). These are exactly
//! the single steps that [`crate::los`] calls clear, and the movement model of the Moving
//! AI benchmarks, whose `.scen` optimal lengths this search reproduces. Cells outside the
//! grid and [`Occupancy::Occupied`](crate::Occupancy::Occupied) cells are never entered;
//! [`Occupancy::Unknown`](crate::Occupancy::Unknown) cells only with
//! [`AstarOptions::unknown_passable`].
//!
//! The search uses the octile distance heuristic (consistent, so each cell is expanded at
//! most once and the first goal expansion is optimal), an open list ordered by `f = g + h`
//! with ties broken last in, first out (the children of the node expanded last first: the
//! deepest, as a tie-break towards larger `g` picks them, without comparing `g`; a bucket
//! queue over `f`: pushes are O(1) and only the bucket of the smallest `f` is put in order,
//! when it holds more than one `f`), and flat arrays indexed by cell of a copy of the grid
//! with a blocked border (no bounds tests on neighbours): one byte of flags (traversable,
//! reached, expanded, the move that reached the cell, which names its parent) and eight of
//! step counts per cell. Path costs and heuristic values are kept as exact counts of
//! straight and diagonal steps, so the reported length is `straight + diagonal * sqrt 2` to
//! the last bit and equal priorities compare equal (the tie-break then really prefers
//! deeper nodes, which saves most expansions on open ground).

use std::cell::RefCell;
use std::collections::BinaryHeap;
use std::f64::consts::SQRT_2;

use crate::budget::{Budget, STOP_CHECK_INTERVAL};
use crate::error::Result;
use crate::grid::{CellXy, OccupancyGrid};
use crate::los::fill_padded;
use crate::plan::{Plan, PlanStats, cells_of, check_endpoint, xy};

/// Options of [`astar`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AstarOptions {
    /// Whether [`Occupancy::Unknown`](crate::Occupancy::Unknown) cells may be entered (default: no).
    pub unknown_passable: bool,
    /// Most work before the search stops with an error (default: [`Budget::default`]).
    pub budget: Budget,
}

/// Flag of a traversable cell.
const PASSABLE: u8 = 1;
/// Flag of a cell reached by the current search: its step counts and parent move are set.
const REACHED: u8 = 2;
/// Flag of a cell expanded by the current search.
const CLOSED: u8 = 4;
/// The flags' bits above this shift hold the move (0 to 7, see `search`) that reached the
/// cell, which names its parent.
const MOVE_SHIFT: u32 = 3;

/// An open-list entry: the smaller `f` (stored with its bits inverted: `f` is
/// non-negative, so the bit patterns order like the values) is the larger entry, popped
/// first. Entries of equal `f` are popped last in, first out (see [`OpenList`]); this
/// order only speaks for the overflow heap, which breaks such ties by the larger cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Entry {
    f_inv: u64,
    node: u32,
}

/// Buckets of the open list per unit of `f` (a power of two, so that scaling by it is
/// exact).
const BUCKETS_PER_CELL: f64 = 32.0;
/// Buckets in the open list's ring: a window of 4 units of `f`, more than the `2 sqrt 2`
/// that open entries span (see [`OpenList`]).
const RING: u64 = 128;

/// `2^52` as an `f64`: adding it to a value in `[0, 2^51)` rounds that value to an integer
/// held in the sum's low mantissa bits.
const ROUNDING_BIAS: f64 = 4_503_599_627_370_496.0;

/// The bucket number of `f` bits: `32 f` rounded to the nearest integer (ties to even),
/// read from the mantissa of `32 f + 2^52`, which costs an addition where a saturating
/// float-to-integer cast costs a chain of compares. Non-decreasing in `f`, which is all
/// the open list needs of it. Exact for `32 f < 2^51`: path costs stay below the grid's
/// cell count times `sqrt 2`, far less.
#[inline]
fn bucket_of(f: u64) -> u64 {
    (f64::from_bits(f) * BUCKETS_PER_CELL + ROUNDING_BIAS).to_bits() - ROUNDING_BIAS.to_bits()
}

/// The open list: pops an entry of the smallest `f` first, and among entries of equal `f`
/// the one pushed last (on a grid, the children of the node expanded last: the deepest, as
/// a tie-break towards larger `g` would pick, without keeping `g` or comparing it).
///
/// It is a bucket queue over `f`, buckets about `1/32` wide, in a ring. With the
/// consistent octile heuristic, `f` never decreases along the search, and a node reached
/// from an expanded node of priority `F` gets at most `F + 2 sqrt 2` (the step's cost plus
/// the heuristic's change, each at most `sqrt 2`); so every open entry has `f` within
/// `2 sqrt 2` of the smallest, and a ring of 128 buckets (4 units) holds them all. Entries
/// go unsorted into their bucket, in the order pushed; the bucket of the smallest `f` (the
/// cursor's) is put in order of `f` when the cursor reaches it (a stable sort, so equal `f`
/// keep their push order, and none when the bucket holds one `f`, as most do), and a later
/// push into it goes where it is popped after every entry of smaller `f` and before those
/// of equal or larger `f` (most keep the smallest `f`: it goes to the popping end). An
/// entry outside the ring's window (not expected with this heuristic, but kept exact in
/// `f`) waits in an overflow heap that every pop also looks at.
#[derive(Clone, Debug, Default)]
struct OpenList {
    /// The entries by bucket number modulo [`RING`] (empty until the first search).
    ring: Vec<Vec<Entry>>,
    /// Bit `i % 64` of word `i / 64` set when `ring[i]` is not empty.
    occupied: [u64; 2],
    /// The smallest bucket number with entries in the ring, when the ring has entries:
    /// every ring entry's bucket number is in `cursor..cursor + RING`.
    cursor: Option<u64>,
    /// Whether the cursor's bucket is sorted ascending.
    sorted: bool,
    /// Entries outside the ring's window.
    overflow: BinaryHeap<Entry>,
}

impl OpenList {
    fn clear(&mut self) {
        if self.ring.len() != RING as usize {
            self.ring = vec![Vec::new(); RING as usize];
        }
        for bucket in &mut self.ring {
            bucket.clear();
        }
        self.occupied = [0; 2];
        self.cursor = None;
        self.sorted = false;
        self.overflow.clear();
    }

    // Inlined into the search's neighbour loop: a call there costs ~4 % on a maze.
    #[allow(clippy::inline_always)]
    #[inline(always)]
    fn push(&mut self, f: f64, node: u32) {
        let f_inv = !f.to_bits();
        let bucket = bucket_of(f.to_bits());
        let cursor = *self.cursor.get_or_insert(bucket);
        if bucket < cursor || bucket - cursor >= RING {
            self.overflow.push(Entry { f_inv, node });
            return;
        }
        let at = (bucket % RING) as usize;
        let Some(entries) = self.ring.get_mut(at) else {
            return;
        };
        if entries.len() == entries.capacity() {
            grow(entries);
        }
        // Built where it is stored (a copy through the stack would stall the store).
        if bucket == cursor && self.sorted {
            // Popped after every entry of smaller f, before those of equal or larger f
            // (the popping end is the last).
            let mut i = entries.len();
            while i > 0 && entries.get(i - 1).is_some_and(|e| e.f_inv > f_inv) {
                i -= 1;
            }
            if i == entries.len() {
                entries.push(Entry { f_inv, node });
            } else {
                entries.insert(i, Entry { f_inv, node });
            }
        } else {
            entries.push(Entry { f_inv, node });
        }
        self.mark(at, true);
    }

    /// Set or clear the `occupied` bit of ring slot `at`. Whole words are written: a
    /// narrower store (what `u128 |= 1 << at` compiles to) would stall the next wide load.
    #[inline]
    fn mark(&mut self, at: usize, occupied: bool) {
        if let Some(word) = self.occupied.get_mut(at / 64) {
            let bit = 1u64 << (at % 64);
            *word = if occupied { *word | bit } else { *word & !bit };
        }
    }

    /// The node of the largest entry, removed. `closed` tells the nodes already
    /// expanded: their entries are stale and may be dropped unseen.
    #[inline]
    fn pop(&mut self, closed: impl Fn(u32) -> bool) -> Option<u32> {
        let from_ring = self.ring_top(closed);
        match (from_ring, self.overflow.peek()) {
            (Some((at, top)), other) if other.is_none_or(|o| top > *o) => {
                let entries = self.ring.get_mut(at)?;
                entries.pop();
                if entries.is_empty() {
                    self.mark(at, false);
                }
                Some(top.node)
            }
            _ => self.overflow.pop().map(|e| e.node),
        }
    }

    /// The ring slot of the cursor's bucket and its largest entry, moving the cursor to
    /// the first non-empty bucket and sorting it (without the entries of `closed` nodes);
    /// `None` when the ring is empty.
    #[inline]
    fn ring_top(&mut self, closed: impl Fn(u32) -> bool) -> Option<(usize, Entry)> {
        loop {
            let cursor = self.cursor?;
            let mut at = (cursor % RING) as u32;
            if self.ring.get(at as usize).is_none_or(Vec::is_empty) {
                let occupied = u128::from(self.occupied[1]) << 64 | u128::from(self.occupied[0]);
                if occupied == 0 {
                    return None;
                }
                let skip = occupied.rotate_right(at).trailing_zeros();
                self.cursor = Some(cursor + u64::from(skip));
                at = (at + skip) % RING as u32;
                self.sorted = false;
            }
            let entries = self.ring.get_mut(at as usize)?;
            if !self.sorted {
                entries.retain(|e| !closed(e.node));
                // Most buckets hold one f (a 1/32 cell wide bucket rarely meets two sums
                // of straight and diagonal steps): those need no sort.
                let first = entries.first().map(|e| e.f_inv);
                if entries.iter().any(|e| Some(e.f_inv) != first) {
                    entries.sort_by_key(|e| e.f_inv);
                }
                if entries.is_empty() {
                    self.mark(at as usize, false);
                    continue;
                }
                self.sorted = true;
            }
            return entries.last().map(|&e| (at as usize, e));
        }
    }
}

/// Make room for one more entry (out of the hot path).
#[cold]
#[inline(never)]
fn grow(entries: &mut Vec<Entry>) {
    entries.reserve(entries.len().max(64));
}

/// Length of a path of `steps[0]` straight and `steps[1]` diagonal steps, cells.
#[inline]
fn octile_length(steps: [u32; 2]) -> f64 {
    f64::from(steps[0]) + f64::from(steps[1]) * SQRT_2
}

/// Octile distance between two cells, as straight and diagonal step counts: a shortest
/// path on an empty grid.
#[inline]
fn octile_steps(a: (u32, u32), b: (u32, u32)) -> [u32; 2] {
    let dx = a.0.abs_diff(b.0);
    let dy = a.1.abs_diff(b.1);
    let (long, short) = if dx >= dy { (dx, dy) } else { (dy, dx) };
    [long - short, short]
}

/// `f = g + h` from step counts, so that equal sums give bit-identical values and ties
/// are real ties (adding two rounded lengths would not).
#[inline]
fn priority(g: [u32; 2], h: [u32; 2]) -> f64 {
    octile_length([g[0] + h[0], g[1] + h[1]])
}

/// Most padded cells of a grid whose search arrays a thread keeps between calls (2 Mi
/// cells, 18 MiB; a 1024 x 1024 Moving AI map has 1.05 Mi): a free [`astar`] call on a
/// grid up to this size reuses them instead of allocating and zeroing megabytes.
const THREAD_KEPT_CELLS: usize = 1 << 21;

thread_local! {
    /// The calling thread's reusable search (see [`AstarSearch::or_thread_search`]).
    static THREAD_SEARCH: RefCell<AstarSearch> = RefCell::new(AstarSearch::new());
}

/// Most expanded cells a search lists for the next search on the same grid to clear
/// (each with its eight neighbours), of a grid of `padded_cells`: clearing one listed cell's
/// block costs about as much as copying 64 cells of the grid (three scattered short rows
/// against a sequential copy), so past this the grid is copied again.
fn listed_limit(padded_cells: usize) -> usize {
    padded_cells / 64
}

/// A reusable A* search: keeps its per-cell arrays and open list between calls, so that
/// many queries on grids of one size allocate once (and need no clearing: a cell's step
/// counts are only read when its flags say this search reached it).
///
/// Internally the grid is copied into a flag map with a one-cell blocked border, which
/// lets the neighbour checks go without bounds tests. The copy is kept for the next search
/// while the grid's [revision](OccupancyGrid::revision) and `unknown_passable` stay the
/// same (then only the cells around those the last search expanded are cleared, when it
/// expanded few), and made again otherwise, so grid edits between searches are always
/// seen.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, astar::{AstarOptions, AstarSearch}};
/// let grid = OccupancyGrid::new(8, 8, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// let mut search = AstarSearch::new();
/// for goal in [(7, 7), (7, 0), (3, 5)] {
///     let plan = search.search(&grid, (0, 0), goal, &AstarOptions::default()).unwrap().unwrap();
///     assert_eq!(*plan.waypoints.last().unwrap(), goal);
/// }
/// ```
#[derive(Clone, Debug, Default)]
pub struct AstarSearch {
    /// Flags of the padded grid (`width + 2` by `height + 2`, border blocked):
    /// [`PASSABLE`], and during a search [`REACHED`], [`CLOSED`] and the move that reached
    /// the cell (above [`MOVE_SHIFT`]).
    flags: Vec<u8>,
    /// Straight and diagonal steps of the best path found to each padded cell, valid
    /// where its flags have [`REACHED`]. At least as long as `flags`.
    steps: Vec<[u32; 2]>,
    open: OpenList,
    /// The grid revision and `unknown_passable` that `flags` were filled for.
    padded_for: Option<(u64, bool)>,
    /// The padded cells the last search expanded: they and their neighbours are every cell
    /// it marked, whose flags the next search on the same grid clears. Complete only when
    /// shorter than [`listed_limit`] (a search that expands more stops listing them, and
    /// the next copies the grid).
    expanded_cells: Vec<u32>,
}

impl AstarSearch {
    /// A search with no memory allocated yet.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Run `run` on this search, or, while it holds no arrays yet and `grid` has at most
    /// [`THREAD_KEPT_CELLS`] padded cells, on the calling thread's reusable search (a
    /// search reads nothing of an earlier one: the answer is the same either way).
    pub(crate) fn or_thread_search<T>(
        &mut self,
        grid: &OccupancyGrid,
        run: impl FnOnce(&mut Self) -> T,
    ) -> T {
        let cells = (grid.width() + 2) * (grid.height() + 2);
        if !self.steps.is_empty() || cells > THREAD_KEPT_CELLS {
            return run(self);
        }
        THREAD_SEARCH.with(|kept| match kept.try_borrow_mut() {
            Ok(mut kept) => run(&mut kept),
            Err(_) => run(self),
        })
    }

    /// Fill [`Self::flags`] for `grid`, padded with a blocked border (the cells
    /// [`cell_passable`](crate::los::cell_passable) lets a robot enter), and size the
    /// step counts for as many cells.
    fn begin(&mut self, grid: &OccupancyGrid, unknown_passable: bool) {
        let key = Some((grid.revision(), unknown_passable));
        let padded_cells = (grid.width() + 2) * (grid.height() + 2);
        // The last search's list is complete when shorter than the limit (see `search`).
        let listed_all = self.expanded_cells.len() < listed_limit(padded_cells);
        if self.padded_for == key && self.flags.len() == padded_cells && listed_all {
            // The same cells as the last search's: clear what it marked, not the grid.
            // Every cell it reached is an expanded cell or a neighbour of one; a cell's
            // flags keep its traversability bit, so masking restores them.
            let pw = grid.width() + 2;
            for &cell in &self.expanded_cells {
                let cell = cell as usize;
                for row in [cell - pw, cell, cell + pw] {
                    if let Some(flags) = self.flags.get_mut(row - 1..=row + 1) {
                        for flag in flags {
                            *flag &= PASSABLE;
                        }
                    }
                }
            }
        } else {
            fill_padded(grid, unknown_passable, &mut self.flags, 0, PASSABLE);
            self.padded_for = key;
        }
        self.expanded_cells.clear();
        if self.steps.len() < self.flags.len() {
            // Zeroed memory comes from the allocator untouched: only the pages this
            // search writes are ever faulted in.
            self.steps = vec![[0; 2]; self.flags.len()];
        }
        self.open.clear();
    }

    /// Find a shortest 8-connected path from `start` to `goal` (see [`astar`]).
    ///
    /// # Errors
    /// As [`astar`].
    pub fn search(
        &mut self,
        grid: &OccupancyGrid,
        start: impl Into<CellXy>,
        goal: impl Into<CellXy>,
        opts: &AstarOptions,
    ) -> Result<Option<Plan>> {
        let (start, goal) = (xy(start), xy(goal));
        check_endpoint(grid, "start", start, opts.unknown_passable)?;
        check_endpoint(grid, "goal", goal, opts.unknown_passable)?;
        opts.budget.stop.check("A*")?;
        self.begin(grid, opts.unknown_passable);
        // Padded coordinates: cell (x, y) is (x + 1, y + 1) in a grid one cell larger on
        // every side. Cell counts are below MAX_CELLS, so padded indices fit in u32.
        let pw = grid.width() + 2;
        let mut stats = PlanStats::default();
        let pw32 = pw as u32;
        let start_p = ((start.0 + 1) as u32, (start.1 + 1) as u32);
        let goal_p = ((goal.0 + 1) as u32, (goal.1 + 1) as u32);
        let start_index = start_p.1 * pw32 + start_p.0;
        let goal_index = goal_p.1 * pw32 + goal_p.0;
        let listed = listed_limit(self.flags.len());
        let flags = self.flags.as_mut_slice();
        let all_steps = self.steps.as_mut_slice();
        let expanded_cells = &mut self.expanded_cells;
        if let (Some(f), Some(s)) = (
            flags.get_mut(start_index as usize),
            all_steps.get_mut(start_index as usize),
        ) {
            *f |= REACHED;
            *s = [0, 0];
        }
        let open = &mut self.open;
        open.push(octile_length(octile_steps(start_p, goal_p)), start_index);
        stats.generated += 1;
        // Index deltas of the 8 moves, in padded cells: E, S, W, N, SE, SW, NW, NE.
        let pwi = pw as isize;
        let deltas: [isize; 8] = [1, pwi, -1, -pwi, pwi + 1, pwi - 1, -pwi - 1, 1 - pwi];
        let move_dx: [i32; 8] = [1, 0, -1, 0, 1, -1, -1, 1];
        let move_dy: [i32; 8] = [0, 1, 0, -1, 1, 1, -1, -1];
        let max_expansions = opts.budget.max_expansions;
        while let Some(node) = open.pop(|n| {
            flags
                .get(n as usize)
                .is_some_and(|&flag| flag & CLOSED != 0)
        }) {
            let index = node as usize;
            let Some(flag) = flags.get_mut(index) else {
                continue;
            };
            if *flag & CLOSED != 0 {
                continue; // a stale entry: the cell was expanded with a smaller cost
            }
            *flag |= CLOSED;
            if expanded_cells.len() < listed {
                expanded_cells.push(node);
            }
            let steps = all_steps.get(index).copied().unwrap_or_default();
            stats.expanded += 1;
            if stats.expanded > max_expansions || stats.expanded.is_multiple_of(STOP_CHECK_INTERVAL)
            {
                opts.budget.check("A*", stats.expanded, 0, stats.expanded)?;
            }
            if node == goal_index {
                let plan = Self::plan(flags, &deltas, pw, (start_index, goal_index), steps);
                return Ok(Some(Plan { stats, ..plan }));
            }
            let (x, y) = (node % pw32, node / pw32);
            // Expanded cells are traversable grid cells, so every neighbour index lies
            // inside the padded grid; the border cells are blocked.
            let flag = |k: usize| {
                flags
                    .get(index.wrapping_add_signed(deltas[k]))
                    .copied()
                    .unwrap_or(0)
            };
            let around = [
                flag(0),
                flag(1),
                flag(2),
                flag(3),
                flag(4),
                flag(5),
                flag(6),
                flag(7),
            ];
            let pass = |k: usize| around[k] & PASSABLE != 0;
            let straight = [pass(0), pass(1), pass(2), pass(3)];
            let allowed = [
                straight[0],
                straight[1],
                straight[2],
                straight[3],
                straight[0] && straight[1] && pass(4),
                straight[2] && straight[1] && pass(5),
                straight[2] && straight[3] && pass(6),
                straight[0] && straight[3] && pass(7),
            ];
            let straight_steps = [steps[0] + 1, steps[1]];
            let diagonal_steps = [steps[0], steps[1] + 1];
            let g_straight = octile_length(straight_steps);
            let g_diagonal = octile_length(diagonal_steps);
            for k in 0..8 {
                if !allowed[k] || around[k] & CLOSED != 0 {
                    continue;
                }
                let next_index = index.wrapping_add_signed(deltas[k]);
                let (Some(next_flag), Some(next_steps_slot)) =
                    (flags.get_mut(next_index), all_steps.get_mut(next_index))
                else {
                    continue;
                };
                let (next_steps, g) = if k >= 4 {
                    (diagonal_steps, g_diagonal)
                } else {
                    (straight_steps, g_straight)
                };
                if around[k] & REACHED != 0 && octile_length(*next_steps_slot) <= g {
                    continue;
                }
                *next_steps_slot = next_steps;
                *next_flag = PASSABLE | REACHED | ((k as u8) << MOVE_SHIFT);
                let next_p = (
                    x.wrapping_add_signed(move_dx[k]),
                    y.wrapping_add_signed(move_dy[k]),
                );
                let h = octile_steps(next_p, goal_p);
                open.push(priority(next_steps, h), next_index as u32);
                stats.generated += 1;
            }
        }
        Ok(None)
    }

    /// The plan from padded index `ends.0` to `ends.1`, following the moves recorded in
    /// `flags` (with the padded index `deltas` of the moves, the padded width `pw`) back
    /// from the goal; `steps` are the goal's step counts. Its stats are left empty.
    fn plan(
        flags: &[u8],
        deltas: &[isize; 8],
        pw: usize,
        ends: (u32, u32),
        steps: [u32; 2],
    ) -> Plan {
        let (start_index, goal_index) = (ends.0 as usize, ends.1 as usize);
        let mut waypoints = Vec::with_capacity((steps[0] + steps[1]) as usize + 1);
        let mut index = goal_index;
        // A parent chain is at most as long as the number of cells.
        for _ in 0..flags.len() {
            waypoints.push((index % pw - 1, index / pw - 1));
            if index == start_index {
                break;
            }
            let Some(&flag) = flags.get(index) else {
                break;
            };
            let k = usize::from(flag >> MOVE_SHIFT) & 7;
            index = index.wrapping_add_signed(-deltas[k]);
        }
        waypoints.reverse();
        Plan {
            waypoints: cells_of(waypoints),
            length_cells: octile_length(steps),
            stats: PlanStats::default(),
        }
    }
}

/// A shortest 8-connected grid path from `start` to `goal`, octile costs, no corner
/// cutting (see the [module docs](self)). The waypoints are every cell of the path, start
/// and goal included; `Ok(None)` when the goal cannot be reached. Runs on the calling
/// thread's reusable [`AstarSearch`] (on a fresh one for grids of over 2 Mi cells: keep an
/// [`AstarSearch`] to run many queries on those).
///
/// # Errors
/// [`PlanError::EndpointOutsideGrid`](crate::PlanError::EndpointOutsideGrid) when `start`
/// or `goal` is outside the grid,
/// [`PlanError::EndpointBlocked`](crate::PlanError::EndpointBlocked) when it is not
/// traversable.
///
/// # Complexity
/// `O(n log n)` time for `n` reachable cells plus `O(cells)` to copy the grid (only the
/// blocks around the cells the thread's last search expanded, when it searched this grid
/// at the same [revision](OccupancyGrid::revision) and expanded under 1/64 of it), 9 bytes
/// per grid cell plus 4 per expanded cell listed.
///
/// # References
/// P. E. Hart, N. J. Nilsson, B. Raphael, "A Formal Basis for the Heuristic Determination
/// of Minimum Cost Paths", IEEE Transactions on Systems Science and Cybernetics 4(2), 1968.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, OccupancyGrid, astar::{astar, AstarOptions}};
/// // .#.
/// // ...
/// let mut grid = OccupancyGrid::new(3, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// grid.set(1, 0, Occupancy::Occupied).unwrap();
/// let plan = astar(&grid, (0, 0), (2, 0), &AstarOptions::default()).unwrap().unwrap();
/// // No corner cutting around (1, 0): down, across, up.
/// assert_eq!(plan.waypoints, [(0, 0), (0, 1), (1, 1), (2, 1), (2, 0)]);
/// assert_eq!(plan.length_cells, 4.0);
/// grid.set(1, 1, Occupancy::Occupied).unwrap();
/// assert_eq!(astar(&grid, (0, 0), (2, 0), &AstarOptions::default()).unwrap(), None);
/// assert!(astar(&grid, (0, 0), (1, 1), &AstarOptions::default()).is_err());
/// ```
pub fn astar(
    grid: &OccupancyGrid,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    opts: &AstarOptions,
) -> Result<Option<Plan>> {
    AstarSearch::new().or_thread_search(grid, |search| search.search(grid, start, goal, opts))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use std::collections::BinaryHeap;

    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::{OpenList, octile_length};

    /// The open list pops what one binary heap of the same entries pops when it orders
    /// them by the smaller `f`, then the later push; also when many entries share `f` and
    /// when a bucket holds several `f`. When `f` leaves the ring's window or falls below
    /// its smallest bucket (neither happens in a search), the entry waits in the overflow
    /// heap, which still pops by `f` exactly but breaks its ties by the cell: then only
    /// the `f` popped is compared.
    #[test]
    fn open_list_pops_like_a_binary_heap() {
        let mut rng = ChaCha8Rng::seed_from_u64(30);
        let mut open = OpenList::default();
        let mut exact_rounds = 0;
        for round in 0..300 {
            open.clear();
            // (f bits inverted, node = push number): the largest is popped first.
            let mut reference: BinaryHeap<(u64, u32)> = BinaryHeap::new();
            let mut f_of: Vec<u64> = Vec::new();
            let mut steps_of: Vec<[u32; 2]> = Vec::new();
            let mut overflowed = false;
            // As in a search, pushes at or above the f last popped (the steps of the last
            // popped entry plus a few); in half the rounds, a few anywhere (below the
            // smallest bucket or beyond the window).
            let mut base = [rng.random_range(0..50u32), rng.random_range(0..50u32)];
            let pushes = rng.random_range(1..400);
            let wild = if rng.random_bool(0.5) { 0.03 } else { 0.0 };
            let mut pushed = 0;
            while pushed < pushes || !reference.is_empty() {
                if pushed == pushes || rng.random_bool(0.45) {
                    let popped = open.pop(|_| false);
                    let expected = reference.pop().map(|(_, node)| node);
                    let f = |n: Option<u32>| n.and_then(|n| f_of.get(n as usize).copied());
                    if overflowed {
                        assert_eq!(f(popped), f(expected), "round {round}");
                    } else {
                        assert_eq!(popped, expected, "round {round}");
                    }
                    if let Some(steps) = popped.and_then(|n| steps_of.get(n as usize)) {
                        base = *steps;
                    }
                    continue;
                }
                let steps = if rng.random_bool(wild) {
                    [rng.random_range(0..200), rng.random_range(0..200)]
                } else {
                    [
                        base[0] + rng.random_range(0..3),
                        base[1] + rng.random_range(0..2),
                    ]
                };
                let f = octile_length(steps);
                let node = f_of.len() as u32;
                f_of.push(!f.to_bits());
                steps_of.push(steps);
                open.push(f, node);
                pushed += 1;
                overflowed |= !open.overflow.is_empty();
                reference.push((!f.to_bits(), node));
            }
            assert_eq!(open.pop(|_| false), None);
            exact_rounds += usize::from(!overflowed);
        }
        // The rounds compared entry by entry are not a handful.
        assert!(exact_rounds >= 30, "{exact_rounds} exact rounds");
    }
}
