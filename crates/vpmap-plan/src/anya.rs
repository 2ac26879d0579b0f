//! The exact shortest any-angle path, fast: an Anya-style interval search (Harabor,
//! Grastien, Öz and Aksakalli 2016; the same search as Polyanya, Cui, Harabor and
//! Grastien 2017, on a mesh of rectangles) over the free space of the collision rule of
//! [`crate::los`], with the free space built once per grid ([`ExactPlanner::new`]).
//!
//! # The free space, exactly
//! In cell-centre coordinates the robot's centre may go anywhere outside the open squares
//! of side 2 centred on blocked cells (outside the grid counts as blocked; see
//! [`crate::optimal`]). Cut that closed set along the horizontal lines `Y = y` through
//! the cell centres:
//! - **on a row line** `Y = y` a point `(X, y)` is free exactly when every cell centre
//!   within Chebyshev distance below 1 of it is free: for `x < X < x + 1` the cells
//!   `(x, y)` and `(x + 1, y)`, for `X = x` the cell `(x, y)`. So the row line's free set
//!   is the union of the closed intervals `[a, b]` spanned by the maximal runs of free
//!   cells `a..=b` of row `y` (a run of one cell is a point);
//! - **in the open strip** `y < Y < y + 1` the cross-section is the same at every height:
//!   `X` is free exactly when the columns `floor(X)` and `ceil(X)` are both *double free*
//!   (the cells of rows `y` and `y + 1` free). So the strip's free set is a union of
//!   disjoint closed rectangles `[a, b] x [y, y + 1]`, one per maximal run `a..=b` of
//!   double-free columns, at least 2 apart; a run of one column is a zero-width vertical
//!   corridor. Each rectangle's top and bottom edges lie in runs of the two row lines.
//!
//! So the free space is a mesh of convex pieces (rectangles, possibly of zero width, and
//! row-line intervals, possibly of zero length) that meet only along the row lines, with
//! every vertex at a cell centre, and zero-width corridors are pieces like any other (no
//! relaxation is needed). A segment that leaves a row line into a strip stays in one
//! rectangle until the next row line (the cross-section is a union of disjoint closed
//! intervals and the segment's `X` varies continuously).
//!
//! # Search
//! A node is a root `r` (a cell centre, the start or a turning point, with the exact
//! length `g(r)` of the path that reaches it) and an interval `I` of a row line every
//! point of which `r` sees. A **cone** node (`r` off the row) is expanded into the strip
//! beyond the row: per rectangle `[a, b]` of that strip meeting `I`, the rays from `r`
//! through `I` projected onto the next row line and clipped to `[a, b]` give the
//! *observable* successor (same root); what of `[a, b]` lies left or right of that
//! projection is seen from the interval's end on that side when that end is a cell centre
//! (an integer), which becomes the root of a *non-observable* successor. A cone node also
//! turns at an integer end of its interval onto its row line (a **flat** node: root on
//! the row, the rest of the row's run beyond). A flat node turns at every rectangle side
//! beyond its root in the strips above and below (the whole top or bottom edge of that
//! rectangle, seen from that side's end). Nodes are ordered by `f = g(r) + h`, with `h`
//! the Euclidean length of the shortest path from `r` through `I` to the goal (the goal
//! mirrored through the row line when it lies on the root's side), which is admissible.
//! A node whose interval holds the goal gives a final entry with `f = g(r) + |r goal|`;
//! the first final entry taken off the open list is the answer. Polyanya's root-level
//! pruning keeps, per cell centre, the least `g` with which it has become a root, and
//! drops successors rooted there with a larger one. A cone node whose only successor is
//! its observable one (no turning point, not the goal's row) is expanded at once, row
//! after row, without the open list (Polyanya's intermediate pruning): a cone crosses an
//! open area in one step of the open list instead of one per row. A node entering a dead
//! end (a chain of rectangles with one way out, found in the build) that does not hold
//! the goal is dropped.
//!
//! Turning points are cell centres, so the path is a polyline through cell centres like
//! every other planner's, and its length is summed like theirs ([`crate::path_length`]).
//! Interval ends are `f64`; an end within `1e-9` of an integer is that integer (a
//! non-integer end is the crossing of a row line by the line through two cell centres at
//! most `height` rows apart, so it is at least `1 / height` from any integer).
//!
//! # Why it is exact
//! A shortest path is taut and bends only at cell centres ([`crate::optimal`]). Between
//! two bends it is a segment, which crosses the row lines in turn and lies in one
//! rectangle between two consecutive crossings, or runs along one row line. By induction
//! over the bends, every point `q` of a row line on a shortest path to the goal with last
//! bend `t` lies in the interval of some node rooted at `t` with `g(t)` optimal: from
//! `t`'s own node the observable successors follow the segment strip by strip, as long
//! as it stays in the projected cone; where the next bend `t'` lies at the end of that
//! cone on a row line, `t'` is an integer end of the projected interval (or a rectangle
//! side inside it), and the non-observable or flat successors rooted at `t'` contain the
//! next segment's first crossing. Bends are corner cells ([`crate::optimal`]'s proof),
//! so successors are rooted at corner cells only; generating more successors than the
//! taut ones (the planner does, where deciding tautness costs more than the node) only
//! adds feasible paths. Root-level pruning drops a node only when its root is reached by a
//! path at least as short, and any continuation from the dropped arrival is then at least
//! as long as the same continuation from the better one (Cui et al. 2017, section 5).
//! Dead-end pruning drops only paths that leave a region through the row line they
//! entered it by, which a segment along that line shortens.
//! The tests check the answer against the visibility graph of [`crate::optimal`] to
//! `1e-9` on thousands of random grids (mazes, rooms, spirals, diagonal walls with gaps,
//! cells touching at corners) and on Moving AI maps.
//!
//! # References
//! - D. Harabor, A. Grastien, D. Öz, V. Aksakalli, "Optimal Any-Angle Pathfinding In
//!   Practice", Journal of Artificial Intelligence Research 56, 2016 (Anya).
//! - M. Cui, D. Harabor, A. Grastien, "Compromise-free Pathfinding on a Navigation Mesh",
//!   IJCAI 2017 (Polyanya, root-level pruning).

use std::collections::{BinaryHeap, HashSet};
use std::hash::{BuildHasherDefault, Hash, Hasher};

use crate::budget::Budget;
use crate::error::Result;
use crate::grid::{CellXy, OccupancyGrid};
use crate::los::{Passable, PassableGrid};
use crate::plan::{Plan, PlanStats, check_endpoint, path_length, xy};

/// The planner's name in errors.
const PLANNER: &str = "the exact any-angle planner";

/// Tolerance of interval ends, cells (see the [module docs](self)).
const EPS: f64 = 1e-9;

/// [`ExactPlanner::dead`]'s "not a dead end".
const NOT_DEAD: i32 = i32::MIN;

/// Tolerance of root-level pruning on path lengths, cells.
const G_EPS: f64 = 1e-9;

/// What a search node's interval is to its root.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// The root is on another row; expand away from it (`+1`: towards larger `y`).
    Cone(i32),
    /// The root is on the interval's row.
    Flat,
    /// The goal, seen from the root.
    Final,
}

/// A search node: an interval `[l, u]` of row line `y` seen from root `root`.
#[derive(Clone, Copy, Debug)]
struct Node {
    root: u32,
    y: i32,
    l: f64,
    u: f64,
    kind: Kind,
}

/// An open-list entry: the heap pops the largest, so the smallest `f` (non-negative, so
/// its IEEE bits order like the value; complemented), then the node pushed last.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Entry {
    key: u64,
    node: u32,
}

impl Entry {
    /// The entry of node `node` with `f` (cells).
    fn new(f: f64, node: u32) -> Self {
        Self {
            key: !f.to_bits(),
            node,
        }
    }
}

/// A root: a cell centre with the length of the path reaching it and its parent root.
#[derive(Clone, Copy, Debug)]
struct Root {
    x: i32,
    y: i32,
    g: f64,
    parent: u32,
    /// Whether its cell centre has since become a root with a shorter path (its nodes are
    /// then dropped when taken off the open list).
    superseded: bool,
}

/// The exact any-angle planner with its free space built once for a grid (see the
/// [module docs](self)): build with [`ExactPlanner::new`], then ask any number of
/// [`ExactPlanner::plan`] queries.
///
/// # Example
/// ```
/// use vpmap_plan::{Budget, Occupancy, OccupancyGrid, anya::ExactPlanner};
/// // .....
/// // ..#..
/// // .....
/// let mut grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
/// grid.set(2, 1, Occupancy::Occupied).unwrap();
/// let mut planner = ExactPlanner::new(&grid, false);
/// let plan = planner.plan((0, 1), (4, 1), &Budget::default()).unwrap().unwrap();
/// assert_eq!(plan.waypoints.len(), 4);
/// assert!((plan.length_cells - (2.0 + 2.0 * 2f64.sqrt())).abs() < 1e-12);
/// ```
#[derive(Clone, Debug)]
pub struct ExactPlanner {
    grid: OccupancyGrid,
    unknown_passable: bool,
    width: i32,
    height: i32,
    /// Per row: its maximal runs `(first, last)` of passable cells, by column.
    runs: Vec<Vec<(i32, i32)>>,
    /// Per strip `y` (between rows `y` and `y + 1`): its rectangles `(a, b)`, by `a`.
    strips: Vec<Vec<(i32, i32)>>,
    /// Per strip and rectangle (as `strips`): `[up, down]`, the last row of the dead end
    /// entered through the rectangle upwards and downwards ([`NOT_DEAD`] when it is none;
    /// see [`ExactPlanner::dead_end`]).
    dead: Vec<Vec<[i32; 2]>>,
    /// Per cell: whether it is a corner cell ([`crate::optimal::corner_cells`]), the only
    /// places a shortest path bends.
    corner: Vec<bool>,
    /// Scratch of the searches: per cell, the index of its root with the least `g` in the
    /// current search, valid only when that root is at this cell (so nothing is reset
    /// between queries, and the zeroed table costs no pass over the grid to build).
    root_of: Vec<u32>,
    /// The searches' buffers, kept between queries.
    scratch: Scratch,
}

/// One search's buffers, kept between queries so that a query allocates nothing once
/// they have grown.
#[derive(Clone, Debug, Default)]
struct Scratch {
    roots: Vec<Root>,
    nodes: Vec<Node>,
    /// Every node pushed: equal arrivals at a root share it, so their equal successors
    /// are pushed once.
    seen: HashSet<NodeKey, WordHash>,
    open: BinaryHeap<Entry>,
    /// A cone expansion's successors `(turning point, l, u)`.
    successors: Vec<(Option<i32>, f64, f64)>,
}

impl ExactPlanner {
    /// Build the free space of `grid` (unknown cells passable or not).
    ///
    /// # Complexity
    /// One pass over the grid; about 6 bytes a cell (a copy of the grid, a corner flag and a
    /// root slot per cell; the runs, rectangles and dead ends per row), 8 bytes a cell of peak
    /// memory with a search that reaches every cell (`scripts/limits-table.sh`).
    #[must_use]
    pub fn new(grid: &OccupancyGrid, unknown_passable: bool) -> Self {
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
                    if crate::corners::is_corner_cell(&passable, i64::from(x), i64::from(y))
                        && let Some(slot) = corner.get_mut((y * w + x) as usize)
                    {
                        *slot = true;
                    }
                }
            }
        }
        Self {
            grid: grid.clone(),
            corner,
            unknown_passable,
            width: w,
            height: h,
            runs,
            strips,
            dead,
            root_of: vec![0; grid.width() * grid.height()],
            scratch: Scratch::default(),
        }
    }

    /// Whether this planner was built for `grid` with `unknown_passable` (for callers that
    /// cache it across queries).
    #[must_use]
    pub fn is_for(&self, grid: &OccupancyGrid, unknown_passable: bool) -> bool {
        self.unknown_passable == unknown_passable && self.grid == *grid
    }

    /// The exact shortest any-angle path from `start` to goal under the rule of
    /// [`crate::los`], as a polyline through cell centres; `Ok(None)` when the goal cannot
    /// be reached. `budget.max_expansions` counts search nodes expanded (taken off the
    /// open list, or a cone's intermediate rows); `budget.max_sight_cells` does not apply
    /// (no line-of-sight queries); the stop is looked at every few thousand expansions.
    ///
    /// # Errors
    /// [`PlanError::EndpointOutsideGrid`](crate::PlanError::EndpointOutsideGrid),
    /// [`PlanError::EndpointBlocked`](crate::PlanError::EndpointBlocked) for a bad start
    /// or goal, [`PlanError::BudgetExhausted`](crate::PlanError::BudgetExhausted) and
    /// [`PlanError::Stopped`](crate::PlanError::Stopped) when the budget says so.
    pub fn plan(
        &mut self,
        start: impl Into<CellXy>,
        goal: impl Into<CellXy>,
        budget: &Budget,
    ) -> Result<Option<Plan>> {
        let (start, goal) = (xy(start), xy(goal));
        check_endpoint(&self.grid, "start", start, self.unknown_passable)?;
        check_endpoint(&self.grid, "goal", goal, self.unknown_passable)?;
        budget.stop.check(PLANNER)?;
        let mut scratch = std::mem::take(&mut self.scratch);
        scratch.roots.clear();
        scratch.nodes.clear();
        scratch.seen.clear();
        scratch.open.clear();
        let mut search = Search {
            space: self,
            goal: (goal.0 as i32, goal.1 as i32),
            s: scratch,
            stats: PlanStats::default(),
        };
        let found = search.run((start.0 as i32, start.1 as i32), budget);
        let (stats, scratch) = (search.stats, search.s);
        let chain = found.map(|found| found.map(|root| trace(&scratch.roots, root, goal)));
        self.scratch = scratch;
        let Some(chain) = chain? else {
            return Ok(None);
        };
        let length_cells = path_length(&chain);
        Ok(Some(Plan {
            waypoints: chain,
            length_cells,
            stats,
        }))
    }

    /// The run `(first, last)` of row `y` holding column `x`, if that cell is passable.
    fn run_at(&self, x: i32, y: i32) -> Option<(i32, i32)> {
        let runs = self.runs.get(usize::try_from(y).ok()?)?;
        runs.get(runs.partition_point(|&(_, b)| b < x))
            .copied()
            .filter(|&(a, _)| a <= x)
    }

    /// Whether entering rectangle `index` of strip `strip` in direction `dir` leads into a
    /// dead end that does not hold `goal`: a region of the free space whose only way out
    /// is the row line the rectangle was entered from (see [`dead_ends`]). A path that
    /// crosses that row line into the region and comes back crosses it twice, at `p` and
    /// `q`, and the segment `pq` along the (free, convex) crossing is no longer, so a
    /// shortest path to a goal outside never enters (Polyanya's dead-end pruning, Cui et
    /// al. 2017 section 5). The region lies in the rectangle's columns, so that is where
    /// the goal is looked for.
    fn dead_end(&self, strip: i32, index: usize, dir: i32, goal: (i32, i32)) -> bool {
        let Some(s) = usize::try_from(strip).ok() else {
            return false;
        };
        let (Some(&(a, b)), Some(&[up, down])) = (
            self.strips.get(s).and_then(|r| r.get(index)),
            self.dead.get(s).and_then(|d| d.get(index)),
        ) else {
            return false;
        };
        let (gx, gy) = goal;
        let in_columns = a <= gx && gx <= b;
        if dir > 0 {
            up != NOT_DEAD && !(in_columns && strip < gy && gy <= up)
        } else {
            down != NOT_DEAD && !(in_columns && down <= gy && gy <= strip)
        }
    }

    /// Whether the cell centre `(x, y)` is a corner cell (none outside the grid).
    fn is_corner(&self, x: i32, y: i32) -> bool {
        x >= 0
            && y >= 0
            && x < self.width
            && y < self.height
            && self.corner.get((y * self.width + x) as usize) == Some(&true)
    }

    /// The rectangles of the strip between rows `s` and `s + 1` (none outside the grid).
    fn strip(&self, s: i32) -> &[(i32, i32)] {
        usize::try_from(s)
            .ok()
            .and_then(|s| self.strips.get(s))
            .map_or(&[], Vec::as_slice)
    }
}

/// Per strip and rectangle, `[up, down]`: the last row of the dead end entered through the
/// rectangle upwards (downwards), or [`NOT_DEAD`]. Upwards, rectangle `[a, b]` of strip `s`
/// is a dead end when the run of row `s + 1` over it is exactly `[a, b]` (no way sideways)
/// and strip `s + 1` has no rectangle over it (the dead end ends at row `s + 1`) or exactly
/// one, itself a dead end upwards (the dead end ends where that one's does). Downwards the
/// same, mirrored.
fn dead_ends(runs: &[Vec<(i32, i32)>], strips: &[Vec<(i32, i32)>]) -> Vec<Vec<[i32; 2]>> {
    let mut dead: Vec<Vec<[i32; 2]>> = strips
        .iter()
        .map(|rects| vec![[NOT_DEAD; 2]; rects.len()])
        .collect();
    let over = |strip: usize, a: i32, b: i32| -> Option<std::ops::Range<usize>> {
        let rects = strips.get(strip)?;
        let first = rects.partition_point(|&(_, rb)| rb < a);
        let end = rects.partition_point(|&(ra, _)| ra <= b);
        Some(first..end.max(first))
    };
    let exact_run = |row: usize, a: i32, b: i32| {
        runs.get(row)
            .is_some_and(|r| r.get(r.partition_point(|&(_, rb)| rb < a)) == Some(&(a, b)))
    };
    let n = strips.len();
    for (side, order) in [(0, true), (1, false)] {
        for k in 0..n {
            // Upwards from the top strip down; downwards from the bottom strip up.
            let s = if order { n - 1 - k } else { k };
            let (far_row, next) = if side == 0 {
                (s + 1, s.checked_add(1).filter(|&t| t < n))
            } else {
                (s, s.checked_sub(1))
            };
            let Some(rects) = strips.get(s) else { continue };
            for (i, &(a, b)) in rects.iter().enumerate() {
                if !exact_run(far_row, a, b) {
                    continue;
                }
                let until = match next.and_then(|t| Some((t, over(t, a, b)?))) {
                    None => Some(far_row as i32),
                    Some((_, range)) if range.is_empty() => Some(far_row as i32),
                    Some((t, range)) if range.len() == 1 => dead
                        .get(t)
                        .and_then(|d| d.get(range.start))
                        .map(|d| d[side])
                        .filter(|&u| u != NOT_DEAD),
                    Some(_) => None,
                };
                if let Some(until) = until
                    && let Some(slot) = dead.get_mut(s).and_then(|d| d.get_mut(i))
                {
                    slot[side] = until;
                }
            }
        }
    }
    dead
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

/// The path to `goal` through the chain of roots ending at `last`, start first.
fn trace(roots: &[Root], last: u32, goal: (usize, usize)) -> Vec<CellXy> {
    let mut chain = vec![CellXy::from(goal)];
    let mut index = last;
    // A chain of parents is at most as long as the number of roots.
    for _ in 0..=roots.len() {
        let Some(root) = roots.get(index as usize) else {
            break;
        };
        let cell = CellXy::new(root.x as usize, root.y as usize);
        if chain.last() != Some(&cell) {
            chain.push(cell);
        }
        if root.parent == index {
            break;
        }
        index = root.parent;
    }
    chain.reverse();
    chain
}

/// One query's search state.
struct Search<'a> {
    space: &'a mut ExactPlanner,
    goal: (i32, i32),
    /// The buffers, taken from the planner for the query.
    s: Scratch,
    stats: PlanStats,
}

/// Euclidean distance between `(ax, ay)` and `(bx, by)` (a square root, not
/// `f64::hypot`: the coordinates are at most a few thousand cells, far from overflow).
#[inline]
fn dist(ax: f64, ay: f64, bx: f64, by: f64) -> f64 {
    let (dx, dy) = (ax - bx, ay - by);
    (dx * dx + dy * dy).sqrt()
}

/// The integer nearest `x` (either one at a tie), by truncation: `f64::round` is a
/// library call on the baseline x86-64 target. `x` is a coordinate on the grid or a
/// projection near it, far inside `i64`.
#[inline]
fn nearest(x: f64) -> f64 {
    let t = x as i64 as f64;
    if x - t >= 0.5 {
        t + 1.0
    } else if t - x >= 0.5 {
        t - 1.0
    } else {
        t
    }
}

/// `x` rounded when it is within [`EPS`] of an integer.
#[inline]
fn snap(x: f64) -> f64 {
    let r = nearest(x);
    if (x - r).abs() < EPS { r } else { x }
}

/// `x` as an integer when it is one (within [`EPS`]).
#[inline]
fn integral(x: f64) -> Option<i32> {
    let r = nearest(x);
    ((x - r).abs() < EPS).then_some(r as i32)
}

/// A node as the duplicate check sees it: root, row, the interval ends' bits and the
/// kind's tag.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct NodeKey {
    root: u32,
    y: i32,
    l: u64,
    u: u64,
    tag: i32,
}

impl Hash for NodeKey {
    fn hash<H: Hasher>(&self, state: &mut H) {
        state.write_u64((u64::from(self.root) << 32) | u64::from(self.y.cast_unsigned()));
        state.write_u64(self.l);
        state.write_u64(self.u);
        state.write_u32(self.tag.cast_unsigned());
    }
}

/// A multiply-rotate hash of the words written (the scheme of rustc's `FxHasher`): the
/// keys are the search's own numbers, not an adversary's, so `SipHash`'s protection is
/// not needed and its cost is (about a tenth of a query, measured).
#[derive(Clone, Copy, Debug, Default)]
struct WordHasher(u64);

impl WordHasher {
    #[inline]
    fn add(&mut self, word: u64) {
        self.0 = (self.0 ^ word).wrapping_mul(0xf135_7aea_2e62_a9c5);
    }
}

impl Hasher for WordHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.add(u64::from(b));
        }
    }

    fn write_u32(&mut self, word: u32) {
        self.add(u64::from(word));
    }

    fn write_u64(&mut self, word: u64) {
        self.add(word);
    }

    fn finish(&self) -> u64 {
        // The product's entropy is in its high bits; the table indexes by the low ones.
        self.0.rotate_left(26)
    }
}

/// Builds [`WordHasher`]s.
type WordHash = BuildHasherDefault<WordHasher>;

impl Search<'_> {
    /// Run the search from `start`; the root the goal was reached from, if it was.
    fn run(&mut self, start: (i32, i32), budget: &Budget) -> Result<Option<u32>> {
        let s = self.new_root(start, 0.0, None);
        let Some(s) = s else { return Ok(None) };
        if start == self.goal {
            return Ok(Some(s));
        }
        let (sx, sy) = start;
        // Flat nodes along the start's run, cone nodes into the rectangles holding it.
        if let Some((a, b)) = self.space.run_at(sx, sy) {
            if a < sx {
                self.push(s, sy, f64::from(a), f64::from(sx), Kind::Flat);
            }
            if sx < b {
                self.push(s, sy, f64::from(sx), f64::from(b), Kind::Flat);
            }
        }
        for dir in [1, -1] {
            let strip = if dir > 0 { sy } else { sy - 1 };
            if let Some((i, &(a, b))) = self
                .space
                .strip(strip)
                .iter()
                .enumerate()
                .find(|&(_, &(a, b))| a <= sx && sx <= b)
                && !self.space.dead_end(strip, i, dir, self.goal)
            {
                self.push(s, sy + dir, f64::from(a), f64::from(b), Kind::Cone(dir));
            }
        }
        while let Some(Entry { node, .. }) = self.s.open.pop() {
            let Some(&n) = self.s.nodes.get(node as usize) else {
                continue;
            };
            let Some(&root) = self.s.roots.get(n.root as usize) else {
                continue;
            };
            if root.superseded {
                continue; // the root has since been reached by a shorter path
            }
            self.stats.expanded += 1;
            budget.check(PLANNER, self.stats.expanded, 0, self.stats.expanded)?;
            match n.kind {
                Kind::Final => return Ok(Some(n.root)),
                Kind::Cone(dir) => self.expand_cone(n, root, dir, budget)?,
                Kind::Flat => self.expand_flat(n, root),
            }
        }
        Ok(None)
    }

    /// The root of cell centre `(x, y)` with the least `g` so far and that `g`, if it is a
    /// root in this search. `root_of` may hold an index from an earlier search; it is this
    /// search's only when the root it names is at `(x, y)` (every root made sets its
    /// cell's entry, so a root at `(x, y)` named there was named by this search).
    fn root_at(&self, x: i32, y: i32) -> Option<(u32, f64)> {
        if x < 0 || y < 0 || x >= self.space.width || y >= self.space.height {
            return None;
        }
        let index = *self
            .space
            .root_of
            .get((y * self.space.width + x) as usize)?;
        let root = self.s.roots.get(index as usize)?;
        (root.x == x && root.y == y).then_some((index, root.g))
    }

    /// The root at `at` reached with length `g` from `parent` (the start when `None`):
    /// a new one when `g` is the least so far, the existing one when `g` equals its length
    /// (an equally short path; its successors are still generated), `None` when `at` is
    /// already a root with a shorter path (root-level pruning).
    fn new_root(&mut self, at: (i32, i32), g: f64, parent: Option<u32>) -> Option<u32> {
        if at.0 < 0 || at.1 < 0 || at.0 >= self.space.width || at.1 >= self.space.height {
            return None;
        }
        if let Some((existing, best)) = self.root_at(at.0, at.1) {
            if g > best + G_EPS {
                return None;
            }
            if g >= best - G_EPS {
                return Some(existing);
            }
            if let Some(old) = self.s.roots.get_mut(existing as usize) {
                old.superseded = true;
            }
        }
        let index = self.s.roots.len() as u32;
        *self
            .space
            .root_of
            .get_mut((at.1 * self.space.width + at.0) as usize)? = index;
        self.s.roots.push(Root {
            x: at.0,
            y: at.1,
            g,
            parent: parent.unwrap_or(index),
            superseded: false,
        });
        Some(index)
    }

    /// A successor rooted at `c` (a cell centre on row `y`) of a node rooted at `parent`.
    fn push_turn(&mut self, parent: Root, parent_index: u32, c: i32, y: i32, node: Node) {
        // A shortest path bends only at corner cells (crate::optimal's proof).
        if !self.space.is_corner(c, y) {
            return;
        }
        let g = parent.g
            + dist(
                f64::from(parent.x),
                f64::from(parent.y),
                f64::from(c),
                f64::from(y),
            );
        if let Some(root) = self.new_root((c, y), g, Some(parent_index)) {
            self.push(root, node.y, node.l, node.u, node.kind);
        }
    }

    /// Push the node (or, when its interval holds the goal, the final entry).
    fn push(&mut self, root: u32, y: i32, l: f64, u: f64, kind: Kind) {
        let Some(&r) = self.s.roots.get(root as usize) else {
            return;
        };
        let (rx, ry) = (f64::from(r.x), f64::from(r.y));
        let (gx, gy) = (f64::from(self.goal.0), f64::from(self.goal.1));
        let yf = f64::from(y);
        let (kind, f) = if y == self.goal.1 && l - EPS <= gx && gx <= u + EPS {
            (Kind::Final, r.g + dist(rx, ry, gx, gy))
        } else if r.y == y {
            let h = [l, u]
                .map(|q| dist(rx, ry, q, yf) + dist(q, yf, gx, gy))
                .into_iter()
                .fold(f64::INFINITY, f64::min);
            (kind, r.g + h)
        } else {
            // Mirror the goal through the row when it lies on the root's side.
            let gy = if (gy - yf) * (ry - yf) > 0.0 {
                2.0 * yf - gy
            } else {
                gy
            };
            let t = (yf - ry) / (gy - ry);
            let cross = (rx + t * (gx - rx)).clamp(l, u);
            (
                kind,
                r.g + dist(rx, ry, cross, yf) + dist(cross, yf, gx, gy),
            )
        };
        let tag = match kind {
            Kind::Cone(dir) => dir,
            Kind::Flat => 0,
            Kind::Final => 2,
        };
        let key = NodeKey {
            root,
            y,
            l: l.to_bits(),
            u: u.to_bits(),
            tag,
        };
        if !self.s.seen.insert(key) {
            return;
        }
        let index = self.s.nodes.len() as u32;
        self.s.nodes.push(Node {
            root,
            y,
            l,
            u,
            kind,
        });
        self.s.open.push(Entry::new(f, index));
        self.stats.generated += 1;
    }

    /// Expand a cone node into the strip beyond its row (direction `dir`), and on, row
    /// after row, while its only successor is the observable one (no turning point, not
    /// the goal's row): those nodes are expanded at once instead of going through the open
    /// list (Polyanya's intermediate pruning, Cui et al. 2017 section 5; expanding a node
    /// early only adds nodes, and the answer is still the first final entry taken off the
    /// open list). Each counts as an expansion.
    fn expand_cone(&mut self, mut n: Node, r: Root, dir: i32, budget: &Budget) -> Result<()> {
        let mut successors = std::mem::take(&mut self.s.successors);
        let result = self.cone_rows(&mut n, r, dir, budget, &mut successors);
        if result.is_ok() {
            for &(c, l, u) in &successors {
                let node = Node {
                    root: n.root,
                    y: n.y + dir,
                    l,
                    u,
                    kind: Kind::Cone(dir),
                };
                match c {
                    None => self.push(n.root, node.y, l, u, node.kind),
                    Some(c) => self.push_turn(r, n.root, c, n.y, node),
                }
            }
            self.push_flat_turns(n, r);
        }
        self.s.successors = successors;
        result
    }

    /// Step the cone node `n` over the rows where its only successor is the observable
    /// one; leave in `successors` the cone successors `(turning point, l, u)` of the
    /// node it stops at, which `n` then is.
    fn cone_rows(
        &mut self,
        n: &mut Node,
        r: Root,
        dir: i32,
        budget: &Budget,
        successors: &mut Vec<(Option<i32>, f64, f64)>,
    ) -> Result<()> {
        let rx = f64::from(r.x);
        let (gx, gy) = (f64::from(self.goal.0), self.goal.1);
        loop {
            successors.clear();
            let y = n.y;
            let next = y + dir;
            let strip = if dir > 0 { y } else { y - 1 };
            let k = f64::from(next - r.y) / f64::from(y - r.y);
            let project = |x: f64| snap(rx + (x - rx) * k);
            let space = &*self.space;
            // A shortest path bends only at corner cells (crate::optimal's proof).
            let turn = |x: f64| integral(x).filter(|&c| space.is_corner(c, y));
            let rects = space.strip(strip);
            let first = rects.partition_point(|&(_, b)| f64::from(b) < n.l - EPS);
            for (i, &(a, b)) in rects.iter().enumerate().skip(first) {
                let (af, bf) = (f64::from(a), f64::from(b));
                if af > n.u + EPS {
                    break;
                }
                if space.dead_end(strip, i, dir, self.goal) {
                    continue;
                }
                let (lr, ur) = (n.l.max(af), n.u.min(bf));
                if lr > ur + EPS {
                    continue;
                }
                let (jl, ju) = (project(lr).max(af), project(ur).min(bf));
                if jl <= ju + EPS {
                    successors.push((None, jl, ju.max(jl)));
                    if jl > af + EPS
                        && let Some(c) = turn(lr)
                    {
                        successors.push((Some(c), af, jl));
                    }
                    if ju < bf - EPS
                        && let Some(c) = turn(ur)
                    {
                        successors.push((Some(c), ju, bf));
                    }
                } else {
                    let (cl, cu) = (turn(lr), turn(ur));
                    if cl.is_some() {
                        successors.push((cl, af, bf));
                    }
                    if cu.is_some() && cu != cl {
                        successors.push((cu, af, bf));
                    }
                }
            }
            let &[(None, l, u)] = successors.as_slice() else {
                return Ok(());
            };
            if (next == gy && l - EPS <= gx && gx <= u + EPS) || self.flat_turns(*n, r) != [None; 2]
            {
                return Ok(());
            }
            self.stats.expanded += 1;
            budget.check(PLANNER, self.stats.expanded, 0, self.stats.expanded)?;
            *n = Node {
                y: next,
                l,
                u,
                ..*n
            };
        }
    }

    /// The turns of cone node `n` onto its own row at an integer end of its interval that
    /// is a corner cell: `(turning point, l, u)` of the flat successor, beyond the upper
    /// end and beyond the lower end.
    fn flat_turns(&self, n: Node, r: Root) -> [Option<(i32, i32, i32)>; 2] {
        let space = &*self.space;
        let y = n.y;
        let upper = integral(n.u)
            .filter(|&u| r.x <= u && space.is_corner(u, y))
            .and_then(|u| {
                let (_, last) = space.run_at(u, y)?;
                (last > u).then_some((u, u, last))
            });
        let lower = integral(n.l)
            .filter(|&l| r.x >= l && space.is_corner(l, y))
            .and_then(|l| {
                let (first, _) = space.run_at(l, y)?;
                (first < l).then_some((l, first, l))
            });
        [upper, lower]
    }

    /// Push the flat successors of cone node `n` (see [`Self::flat_turns`]).
    fn push_flat_turns(&mut self, n: Node, r: Root) {
        for (c, l, u) in self.flat_turns(n, r).into_iter().flatten() {
            let node = Node {
                root: n.root,
                y: n.y,
                l: f64::from(l),
                u: f64::from(u),
                kind: Kind::Flat,
            };
            self.push_turn(r, n.root, c, n.y, node);
        }
    }

    /// Expand a flat node: turn into every rectangle above or below whose near side lies
    /// on the interval beyond the root.
    fn expand_flat(&mut self, n: Node, r: Root) {
        let y = n.y;
        let rightward = n.u > f64::from(r.x);
        let side_of = |&(a, b): &(i32, i32)| if rightward { a } else { b };
        for dir in [1, -1] {
            let strip = if dir > 0 { y } else { y - 1 };
            // The rectangles are disjoint and sorted, so their sides are too.
            let first = self
                .space
                .strip(strip)
                .partition_point(|rect| f64::from(side_of(rect)) < n.l - EPS);
            for i in first.. {
                let Some(&(a, b)) = self.space.strip(strip).get(i) else {
                    break;
                };
                let side = side_of(&(a, b));
                if f64::from(side) > n.u + EPS {
                    break;
                }
                if self.space.dead_end(strip, i, dir, self.goal) {
                    continue;
                }
                let beyond = if rightward { side > r.x } else { side < r.x };
                if beyond {
                    let node = Node {
                        root: n.root,
                        y: y + dir,
                        l: f64::from(a),
                        u: f64::from(b),
                        kind: Kind::Cone(dir),
                    };
                    self.push_turn(r, n.root, side, y, node);
                }
            }
        }
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::float_cmp)]
mod tests {
    use super::*;
    use crate::grid::Occupancy;

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
                let planner = ExactPlanner::new(&grid, unknown_passable);
                let flagged: Vec<CellXy> = (0..17)
                    .flat_map(|y| (0..23).map(move |x| (x, y)))
                    .filter(|&(x, y)| planner.is_corner(x, y))
                    .map(|(x, y)| CellXy::new(x as usize, y as usize))
                    .collect();
                assert_eq!(
                    flagged,
                    crate::optimal::corner_cells(&grid, unknown_passable)
                );
            }
        }
    }

    #[test]
    fn dead_ends_are_found_and_goals_inside_them_still_reached() {
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
        let mut planner = ExactPlanner::new(&grid, false);
        // Strips 0 and 1 hold the corridor's zero-width rectangle, a dead end towards row 0
        // ending there; towards row 3 it opens into rows 2 and 3, no dead end. Strip 2
        // (rows 2 and 3) is one both ways: towards row 3 the grid ends, towards row 0 the
        // run of row 2 is exactly its span and the only way on is the corridor.
        assert_eq!(planner.dead[0], [[NOT_DEAD, 0]]);
        assert_eq!(planner.dead[1], [[NOT_DEAD, 0]]);
        assert_eq!(planner.dead[2], [[3, 0]]);
        let opts = crate::optimal::OptimalAnyAngleOptions::default();
        let cells: Vec<(usize, usize)> = (0..4)
            .flat_map(|y| (0..5).map(move |x| (x, y)))
            .filter(|&(x, y)| grid.is_free(x, y))
            .collect();
        for &start in &cells {
            for &goal in &cells {
                let exact = planner
                    .plan(start, goal, &Budget::default())
                    .unwrap()
                    .unwrap();
                let reference =
                    crate::optimal::visibility_graph_any_angle(&grid, start, goal, &opts)
                        .unwrap()
                        .unwrap();
                assert!(
                    (exact.length_cells - reference.length_cells).abs() < 1e-9,
                    "{start:?} -> {goal:?}"
                );
            }
        }
    }

    #[test]
    fn one_cell_corridors_are_followed_along_their_centre_line() {
        // .#...
        // .#.#.
        // ...#.
        let mut grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        for (x, y) in [(1, 0), (1, 1), (3, 1), (3, 2)] {
            grid.set(x, y, Occupancy::Occupied).unwrap();
        }
        let mut planner = ExactPlanner::new(&grid, false);
        let plan = planner
            .plan((0, 0), (4, 2), &Budget::default())
            .unwrap()
            .unwrap();
        assert_eq!(
            plan.waypoints,
            [(0, 0), (0, 2), (2, 2), (2, 0), (4, 0), (4, 2)]
        );
        assert_eq!(plan.length_cells, 10.0);
        grid.set(2, 1, Occupancy::Occupied).unwrap();
        let mut planner = ExactPlanner::new(&grid, false);
        assert_eq!(
            planner.plan((0, 0), (4, 2), &Budget::default()).unwrap(),
            None
        );
    }
}
