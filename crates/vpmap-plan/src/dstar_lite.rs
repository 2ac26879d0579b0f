//! D* Lite: incremental re-planning on the 8-connected grid, for a robot that learns the
//! map as it moves (Koenig and Likhachev 2002, the optimized version of their Figure 4).
//!
//! Semantics: exactly the grid model of [`crate::astar`](mod@crate::astar). The robot moves
//! between the centres of 8-neighbouring passable cells; a straight step costs 1 and needs
//! both its cells passable, a diagonal step costs `sqrt 2` and needs both its cells **and
//! both orthogonal neighbours** passable (no corner cutting). Passable is
//! [`cell_passable`]: [`Occupancy::Free`], and
//! [`Occupancy::Unknown`] with [`DStarLiteOptions::unknown_passable`]. Step costs are
//! symmetric, so every cell's predecessors are its successors (its 8 neighbours). A cell
//! changing passability changes the costs of the 8 steps into and out of it, and of the 4
//! diagonal steps between its orthogonal neighbours that cut past it.
//!
//! The search runs backwards from the goal: `g(s)` and `rhs(s)` are costs from `s` to the
//! goal, the heuristic is the octile distance from the robot's cell (consistent), and the
//! priority queue holds the locally inconsistent cells (`g != rhs`) keyed by
//! `[min(g, rhs) + h(start, s) + k_m; min(g, rhs)]`, compared lexicographically. When the
//! robot moves and cells change, `k_m` grows by the heuristic distance moved since the last
//! change, so queued keys stay lower bounds and need no re-sorting. [`DStarLite::path`]
//! follows `argmin c(s, s') + g(s')` from the robot's cell: a shortest path on the current
//! map, of the same cost as a fresh A* on it.
//!
//! Costs are exact: a path's cost is its counts of straight and diagonal steps (compared
//! as `s + d sqrt 2` exactly, in integers), so equal lengths are equal and no rounding
//! decides a tie, as in [`crate::astar`](mod@crate::astar). The queue is an indexed 4-ary
//! heap (each cell knows its position: re-keying and removing are in place, no stale
//! entries) of exact integer keys: lengths in fixed point with `2^-42` cells, exact up to a
//! million steps of each kind, in 16 bytes (24 with the common tie rule's weight); once a
//! key outgrows that (a search over a million steps long, checked at every key), the search
//! widens to 48-byte keys of lengths with `2^-64` cells and tie weights, exact below `2^27`
//! steps (`k_m` is folded into the keys before either limit). The smaller keys make a
//! drive's planning about a quarter faster, a tenth under the common tie rule
//! (docs/navigation.md).
//!
//! **The common tie rule** ([`DStarLiteOptions::common_ties`]): a cost is compared by
//! length first and then by the sum of the [`tie_weight`]s of the cells the path enters
//! (fixed pseudo-random 32-bit numbers per cell). The length stays exactly optimal; among
//! equally short paths the one of the smallest weight sum is returned, which is unique
//! unless two of them have equal sums (for two given paths that differ in some cell, a chance
//! of at most `2^-32`). The heuristic (octile length, weight 0) stays consistent. A forward
//! A* under the same rule returns the same path from the same belief, so the two drive the
//! same track (the `astar-ties` planner of [`crate::navigate`](mod@crate::navigate)). Off (the default), ties fall
//! as the search meets them: smaller cost-to-goal first, then the first move in the order
//! E, S, W, N, SE, SW, NW, NE when following the path.
//!
//! Why not a crate: no Rust crate on docs.rs implements D* Lite on this grid model (no
//! corner cutting, unknown cells as an option) with the project's [`Budget`] and error
//! style; the generic graph implementations (e.g. gonum's in Go) would need the grid as an
//! explicit graph with per-edge updates. The algorithm is short enough to write to the
//! paper and test against repeated A* (`tests/it/dstar_lite.rs`).
//!
//! # Example
//! ```
//! use vpmap_plan::{CellXy, Occupancy, OccupancyGrid};
//! use vpmap_plan::dstar_lite::{DStarLite, DStarLiteOptions};
//! let grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
//! let mut planner = DStarLite::new(&grid, (0, 1), (4, 1), &DStarLiteOptions::default()).unwrap();
//! assert_eq!(planner.path().unwrap().unwrap().length_cells, 4.0);
//! // The robot learns that (2, 1) is blocked: the path bends around it.
//! planner.update_cells(&[(CellXy::new(2, 1), Occupancy::Occupied)]).unwrap();
//! let plan = planner.path().unwrap().unwrap();
//! assert!((plan.length_cells - 2.0 - 2.0 * std::f64::consts::SQRT_2).abs() < 1e-12);
//! // It moves one step and plans on from there, reusing the search.
//! planner.move_start((1, 0)).unwrap();
//! assert!((planner.path().unwrap().unwrap().length_cells - 2.0 - std::f64::consts::SQRT_2).abs() < 1e-12);
//! ```
//!
//! # References
//! S. Koenig, M. Likhachev, "D* Lite", AAAI 2002 (Figure 4, the optimized version); also
//! "Fast Replanning for Navigation in Unknown Terrain", IEEE Transactions on Robotics
//! 21(3), 2005.

use std::cmp::Ordering;
use std::f64::consts::SQRT_2;

use crate::budget::Budget;
use crate::error::{PlanError, Result};
use crate::grid::{CellXy, DIAGONAL_SIDES, MOVES, Occupancy, OccupancyGrid};
use crate::los::{cell_passable, fill_padded};
use crate::plan::{Plan, PlanStats, check_endpoint, xy};

/// Options of [`DStarLite`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DStarLiteOptions {
    /// Whether [`Occupancy::Unknown`] cells may be entered (default: no).
    pub unknown_passable: bool,
    /// Most expansions one [`DStarLite::path`] call may make (its re-planning), and the
    /// [`Stop`](crate::budget::Stop) it looks at (default: [`Budget::default`]).
    pub budget: Budget,
    /// The common tie rule (default: off): among equally short paths, the one of the
    /// smallest sum of [`tie_weight`]s of the cells it enters (see the [module docs](self)).
    /// Off, ties fall as the search meets them (smaller cost-to-goal first).
    pub common_ties: bool,
}

/// A path cost: exact counts of straight and diagonal steps (length
/// `straight + diagonal * sqrt 2` cells) and, under the common tie rule, the sum of the entered cells'
/// [`tie_weight`]s. Ordered by length (exactly), then by weight. [`StepCost::INF`] is
/// larger than every finite cost.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct StepCost {
    /// Straight steps (`u32::MAX`: infinite).
    pub(crate) straight: u32,
    /// Diagonal steps.
    pub(crate) diagonal: u32,
    /// Sum of tie weights.
    pub(crate) weight: u64,
}

impl StepCost {
    /// Zero.
    pub(crate) const ZERO: Self = Self {
        straight: 0,
        diagonal: 0,
        weight: 0,
    };
    /// Infinite: no path.
    pub(crate) const INF: Self = Self {
        straight: u32::MAX,
        diagonal: u32::MAX,
        weight: u64::MAX,
    };

    /// Whether the cost is finite.
    #[inline]
    pub(crate) fn is_finite(self) -> bool {
        self.straight != u32::MAX
    }

    /// The sum (infinite when either is).
    #[inline]
    pub(crate) fn add(self, other: Self) -> Self {
        if !self.is_finite() || !other.is_finite() {
            return Self::INF;
        }
        Self {
            straight: self
                .straight
                .saturating_add(other.straight)
                .min(u32::MAX - 1),
            diagonal: self.diagonal.saturating_add(other.diagonal),
            weight: self.weight.saturating_add(other.weight),
        }
    }

    /// One step: straight or diagonal, entering a cell of tie weight `weight`.
    #[inline]
    pub(crate) fn step(diagonal: bool, weight: u32) -> Self {
        Self {
            straight: u32::from(!diagonal),
            diagonal: u32::from(diagonal),
            weight: u64::from(weight),
        }
    }

    /// The octile distance between two cells (weight 0: a lower bound of every path's
    /// cost, and consistent).
    #[inline]
    pub(crate) fn octile(dx: usize, dy: usize) -> Self {
        let (long, short) = if dx >= dy { (dx, dy) } else { (dy, dx) };
        Self {
            straight: u32::try_from(long - short).unwrap_or(u32::MAX - 1),
            diagonal: u32::try_from(short).unwrap_or(u32::MAX - 1),
            weight: 0,
        }
    }

    /// Length, cells (exact to the last bit for equal step counts: like A*'s).
    #[inline]
    pub(crate) fn length(self) -> f64 {
        f64::from(self.straight) + f64::from(self.diagonal) * SQRT_2
    }

    /// Compare the lengths exactly: `s1 + d1 sqrt 2` against `s2 + d2 sqrt 2` as the sign
    /// of `x - y sqrt 2` with `x = s1 - s2`, `y = d2 - d1`, which is never zero unless both
    /// are (`sqrt 2` is irrational).
    #[inline]
    pub(crate) fn cmp_length(self, other: Self) -> Ordering {
        match (self.is_finite(), other.is_finite()) {
            (false, false) => return Ordering::Equal,
            (false, true) => return Ordering::Greater,
            (true, false) => return Ordering::Less,
            (true, true) => {}
        }
        let x = i64::from(self.straight) - i64::from(other.straight);
        let y = i64::from(other.diagonal) - i64::from(self.diagonal);
        match (x.signum(), y.signum()) {
            (0, 0) => Ordering::Equal,
            (sx, sy) if sx >= 0 && sy <= 0 => Ordering::Greater,
            (sx, sy) if sx <= 0 && sy >= 0 => Ordering::Less,
            (sx, _) => {
                // Same signs: compare x^2 with 2 y^2.
                let x2 = u128::from(x.unsigned_abs()) * u128::from(x.unsigned_abs());
                let y2 = 2 * u128::from(y.unsigned_abs()) * u128::from(y.unsigned_abs());
                if (x2 > y2) == (sx > 0) {
                    Ordering::Greater
                } else {
                    Ordering::Less
                }
            }
        }
    }
}

impl Ord for StepCost {
    #[inline]
    fn cmp(&self, other: &Self) -> Ordering {
        self.cmp_length(*other)
            .then_with(|| self.weight.cmp(&other.weight))
    }
}

impl PartialOrd for StepCost {
    #[inline]
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The tie weight of cell `(x, y)`: a fixed pseudo-random 32-bit number (the SplitMix64
/// finaliser of the cell's coordinates), the same for every map and planner.
#[must_use]
pub fn tie_weight(x: usize, y: usize) -> u32 {
    let mut z = (x as u64) ^ ((y as u64) << 32) ^ 0x9e37_79b9_7f4a_7c15;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    (z ^ (z >> 31)) as u32
}

/// `sqrt 2` in units of `2^-64`, rounded: the diagonal step of [`fixed_length`].
const SQRT_2_FIXED: u128 = 26_087_635_650_665_564_425;

/// Step counts below this (per component) keep [`fixed_length`] exactly ordered; `k_m`
/// is folded into the keys before it gets there ([`Search::rekey`]).
const FIXED_EXACT_BELOW: u32 = 1 << 27;

/// The length of `c` in units of `2^-64` cells (`sqrt 2` rounded to that unit): for
/// step counts below `2^27` its error (under `2^-37`) is far below the smallest gap between
/// two different lengths (`|x - y sqrt 2| >= 1 / (x + y sqrt 2)`, over `10^-9`), so it
/// orders lengths exactly and equal lengths (equal step counts) stay equal.
#[inline]
fn fixed_length(c: StepCost) -> u128 {
    if c.is_finite() {
        (u128::from(c.straight) << 64) + u128::from(c.diagonal) * SQRT_2_FIXED
    } else {
        u128::MAX
    }
}

/// A queue key `[k1; k2]`, compared lexicographically, held exactly: [`NarrowKey`]
/// without tie weights and while the step counts are small, [`WideKey`] otherwise.
trait QueueKey: Copy + Ord + std::fmt::Debug {
    /// Larger than every key [`QueueKey::new`] returns: the key given to a cell whose key
    /// does not fit, until the search is widened.
    const MAX: Self;
    /// `k_m`'s step counts are folded into the keys ([`Search::rekey`]) before either
    /// reaches this.
    const KM_LIMIT: u32;
    /// The key `[k1; k2]`, or `None` when this type cannot hold it exactly.
    fn new(k1: StepCost, k2: StepCost) -> Option<Self>;
    /// Whether the first part's length is at most `other`'s (tie weights aside).
    fn k1_length_le(self, other: Self) -> bool;
}

/// A key of any step counts and tie weights: each part's length ([`fixed_length`], `2^-64`
/// cells) and then its tie weight; 48 bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct WideKey {
    k1: u128,
    k1_weight: u64,
    k2: u128,
    k2_weight: u64,
}

impl QueueKey for WideKey {
    const MAX: Self = Self {
        k1: u128::MAX,
        k1_weight: u64::MAX,
        k2: u128::MAX,
        k2_weight: u64::MAX,
    };
    const KM_LIMIT: u32 = FIXED_EXACT_BELOW / 2;

    #[inline]
    fn new(k1: StepCost, k2: StepCost) -> Option<Self> {
        Some(Self {
            k1: fixed_length(k1),
            k1_weight: k1.weight,
            k2: fixed_length(k2),
            k2_weight: k2.weight,
        })
    }

    #[inline]
    fn k1_length_le(self, other: Self) -> bool {
        self.k1 <= other.k1
    }
}

/// `sqrt 2` in units of `2^-42`, rounded: the diagonal step of [`narrow_length`].
const SQRT_2_NARROW: u64 = 6_219_777_023_951;

/// Step counts up to this (per component) keep [`narrow_length`] exactly ordered and
/// within 64 bits.
const NARROW_MAX_STEPS: u32 = 1_000_000;

/// The length of `c` in units of `2^-42` cells, or `None` for a count over
/// [`NARROW_MAX_STEPS`] (infinite: `u64::MAX`). Exact order: two different lengths of
/// counts up to `n = 10^6` differ by `|x - y sqrt 2| >= 1 / (x + y sqrt 2) > 4.1e-7` cells,
/// while the rounded `sqrt 2` errs by at most `2^-43` a diagonal step, `1.2e-7` cells over
/// `10^6` of them; the longest length, `2.42e6` cells, stays below `2^22`, so the sum fits
/// in 64 bits. Equal counts give equal lengths.
#[inline]
fn narrow_length(c: StepCost) -> Option<u64> {
    if !c.is_finite() {
        Some(u64::MAX)
    } else if c.straight <= NARROW_MAX_STEPS && c.diagonal <= NARROW_MAX_STEPS {
        Some((u64::from(c.straight) << 42) + u64::from(c.diagonal) * SQRT_2_NARROW)
    } else {
        None
    }
}

/// A key without tie weights (the common tie rule off) and of step counts up to
/// [`NARROW_MAX_STEPS`]: each part's length ([`narrow_length`]); 16 bytes, a third of a
/// [`WideKey`], which makes the queue's sifting about a quarter faster.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct NarrowKey(u128);

impl QueueKey for NarrowKey {
    const MAX: Self = Self(u128::MAX);
    const KM_LIMIT: u32 = NARROW_MAX_STEPS / 4;

    #[inline]
    fn new(k1: StepCost, k2: StepCost) -> Option<Self> {
        if (k1.is_finite() && k1.weight != 0) || (k2.is_finite() && k2.weight != 0) {
            return None;
        }
        let (k1, k2) = (narrow_length(k1)?, narrow_length(k2)?);
        Some(Self((u128::from(k1) << 64) | u128::from(k2)))
    }

    #[inline]
    fn k1_length_le(self, other: Self) -> bool {
        self.0 >> 64 <= other.0 >> 64
    }
}

/// A key of step counts up to [`NARROW_MAX_STEPS`] under the common tie rule: each part's
/// length ([`narrow_length`]) and their tie weight once, ordered as `(k1 length, weight, k2
/// length)`. Both parts have the same weight (`k1 = k2 + h + k_m`, and the heuristic and
/// `k_m` are octile lengths of weight 0), so this is the order of [`WideKey`]'s four parts;
/// a key whose parts' weights differ is not held. 24 bytes (a [`NarrowKey`] and its
/// comparison are smaller still: measured, each type is the faster one for its mode).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct TieKey {
    k1: u64,
    weight: u64,
    k2: u64,
}

impl QueueKey for TieKey {
    const MAX: Self = Self {
        k1: u64::MAX,
        weight: u64::MAX,
        k2: u64::MAX,
    };
    const KM_LIMIT: u32 = NARROW_MAX_STEPS / 4;

    #[inline]
    fn new(k1: StepCost, k2: StepCost) -> Option<Self> {
        match (k1.is_finite(), k2.is_finite()) {
            (false, false) => Some(Self::MAX),
            (true, true) if k1.weight == k2.weight => Some(Self {
                k1: narrow_length(k1)?,
                weight: k1.weight,
                k2: narrow_length(k2)?,
            }),
            _ => None,
        }
    }

    #[inline]
    fn k1_length_le(self, other: Self) -> bool {
        self.k1 <= other.k1
    }
}

/// No queue position: the cell is not queued.
const NOT_QUEUED: u32 = u32::MAX;

/// A [`StepCost`] packed in 128 bits, zero for [`StepCost::INF`] (so that the per-cell
/// arrays start as zeroed memory, which the allocator hands out without writing it):
/// `straight + 1`, `diagonal`, `weight` from the top.
#[inline]
fn pack(c: StepCost) -> u128 {
    if c.is_finite() {
        (u128::from(c.straight + 1) << 96) | (u128::from(c.diagonal) << 64) | u128::from(c.weight)
    } else {
        0
    }
}

/// The [`StepCost`] of [`pack`]ed bits.
#[inline]
fn unpack(p: u128) -> StepCost {
    if p == 0 {
        StepCost::INF
    } else {
        StepCost {
            straight: ((p >> 96) as u32).wrapping_sub(1),
            diagonal: (p >> 64) as u32,
            weight: p as u64,
        }
    }
}

/// The reverse of each move.
const OPPOSITE: [usize; 8] = [2, 3, 0, 1, 6, 7, 4, 5];
/// Heap arity of the queue.
const ARITY: usize = 4;

/// How far [`DStarLite::compute_shortest_path`] goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Until {
    /// The paper's condition: the top key below the start's, or the start overconsistent.
    Paper,
    /// Also every key whose first part's length ties with the start's.
    Ties,
    /// Until the queue is empty: every cell consistent.
    Empty,
}

/// What following the search from the start gave.
enum Extracted {
    /// A path, or `None` when there is none.
    Path(Option<Plan>),
    /// A queued (possibly stale) cell was met at this padded index.
    Inconsistent(usize),
}

/// What [`Search::path`] gave.
enum Planned {
    /// The path, or `None` when there is none.
    Done(Option<Plan>),
    /// A key did not fit: the search must widen and go on.
    Widen,
}

/// A D* Lite search from a moving start to a fixed goal (see the [module docs](self)).
///
/// Its queue holds 16-byte keys (24 under the common tie rule) and widens to 48-byte ones,
/// once and for good, when a key's step counts outgrow them (cells over about a million
/// steps from the goal; see the [module docs](self)).
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

/// The D* Lite search itself, over queue keys of type `K`.
#[derive(Clone, Debug)]
struct Search<K> {
    /// Padded passability, border blocked: cell `(x, y)` at `(y + 1) pw + x + 1`.
    passable: Vec<bool>,
    /// Tie weight of each padded cell (empty without the common tie rule).
    weights: Vec<u32>,
    /// Per padded cell: the [`pack`]ed cost-to-goal estimate `g` and one-step lookahead
    /// `rhs = min c(s, s') + g(s')` (zero at the goal).
    costs: Vec<[u128; 2]>,
    /// Per padded cell: its position in the heap plus one, 0 when not queued.
    pos: Vec<u32>,
    /// The queue: a 4-ary min-heap of keys and padded cells, positions in [`Node::pos`].
    heap: Vec<(K, u32)>,
    /// Padded width.
    pw: usize,
    width: usize,
    height: usize,
    start: usize,
    last: usize,
    goal: usize,
    km: StepCost,
    opts: DStarLiteOptions,
    /// Index deltas of the 8 moves, padded cells.
    deltas: [isize; 8],
    /// Whether something changed since the last [`DStarLite::path`].
    dirty: bool,
    /// Queue insertions and re-keyings so far.
    pushes: usize,
    /// Whether a key did not fit `K` (the search must widen before it goes on).
    overflow: std::cell::Cell<bool>,
}

impl DStarLite {
    /// Set up the search on `grid` from `start` to `goal` (no search runs until
    /// [`DStarLite::path`]).
    ///
    /// # Errors
    /// [`PlanError::EndpointOutsideGrid`] or [`PlanError::EndpointBlocked`] for a `start` or
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
    /// [`PlanError::EndpointOutsideGrid`] outside the grid.
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
    /// [`PlanError::CellOutOfBounds`] for a cell outside the grid (nothing is changed).
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
    /// [`PlanError::BudgetExhausted`] or [`PlanError::Stopped`] from the budget (the
    /// search state stays valid: a later call continues it);
    /// [`PlanError::InconsistentSearch`] if the path cannot be followed (a bug).
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

impl<K: QueueKey> Search<K> {
    /// [`DStarLite::new`].
    fn new(
        grid: &OccupancyGrid,
        start: CellXy,
        goal: CellXy,
        opts: &DStarLiteOptions,
    ) -> Result<Self> {
        check_endpoint(grid, "start", start, opts.unknown_passable)?;
        check_endpoint(grid, "goal", goal, opts.unknown_passable)?;
        let (width, height) = (grid.width(), grid.height());
        let pw = width + 2;
        let mut passable = Vec::new();
        fill_padded(grid, opts.unknown_passable, &mut passable, false, true);
        let weights = if opts.common_ties {
            (0..passable.len())
                .map(|i| tie_weight((i % pw).wrapping_sub(1), (i / pw).wrapping_sub(1)))
                .collect()
        } else {
            Vec::new()
        };
        let pwi = pw as isize;
        let deltas = std::array::from_fn(|k| MOVES[k].1 * pwi + MOVES[k].0);
        let pad = |c: CellXy| (c.y + 1) * pw + c.x + 1;
        let mut this = Self {
            costs: vec![[0; 2]; passable.len()],
            pos: vec![0; passable.len()],
            passable,
            weights,
            heap: Vec::new(),
            pw,
            width,
            height,
            start: pad(start),
            last: pad(start),
            goal: pad(goal),
            km: StepCost::ZERO,
            opts: opts.clone(),
            deltas,
            dirty: true,
            pushes: 0,
            overflow: std::cell::Cell::new(false),
        };
        let goal = this.goal;
        this.set_rhs(goal, StepCost::ZERO);
        this.update_vertex(goal);
        Ok(this)
    }

    /// The same search with keys of type `K2`, this one left empty: every field moves
    /// over and each queued key is computed anew.
    fn convert<K2: QueueKey>(&mut self) -> Search<K2> {
        let cells: Vec<u32> = std::mem::take(&mut self.heap)
            .into_iter()
            .map(|(_, u)| u)
            .collect();
        let mut to = Search {
            passable: std::mem::take(&mut self.passable),
            weights: std::mem::take(&mut self.weights),
            costs: std::mem::take(&mut self.costs),
            pos: std::mem::take(&mut self.pos),
            heap: Vec::with_capacity(cells.len()),
            pw: self.pw,
            width: self.width,
            height: self.height,
            start: self.start,
            last: self.last,
            goal: self.goal,
            km: self.km,
            opts: self.opts.clone(),
            deltas: self.deltas,
            dirty: self.dirty,
            pushes: self.pushes,
            overflow: std::cell::Cell::new(false),
        };
        to.queue_afresh(&cells);
        // Converting is not searching: the re-queued keys are not counted as pushes.
        to.pushes = self.pushes;
        to
    }

    /// [`DStarLite::move_start`].
    fn move_start(&mut self, c: CellXy) -> Result<()> {
        if c.x >= self.width || c.y >= self.height {
            return Err(PlanError::EndpointOutsideGrid {
                endpoint: "start",
                x: c.x,
                y: c.y,
                width: self.width,
                height: self.height,
            });
        }
        let index = self.pad(c);
        if index != self.start {
            self.start = index;
            self.dirty = true;
        }
        Ok(())
    }

    /// [`DStarLite::update_cells`].
    fn update_cells(&mut self, changes: &[(CellXy, Occupancy)]) -> Result<usize> {
        // (padded cell, position in `changes` reversed, passable now): a cell listed twice takes its
        // last state, as writing the changes to a grid in order would.
        let mut latest = Vec::with_capacity(changes.len());
        for (order, &(c, state)) in changes.iter().enumerate() {
            if c.x >= self.width || c.y >= self.height {
                return Err(PlanError::CellOutOfBounds {
                    x: c.x,
                    y: c.y,
                    width: self.width,
                    height: self.height,
                });
            }
            let now = cell_passable(state, self.opts.unknown_passable);
            latest.push((self.pad(c), std::cmp::Reverse(order), now));
        }
        latest.sort_unstable();
        latest.dedup_by_key(|f| f.0);
        let flips: Vec<(usize, bool)> = latest
            .into_iter()
            .filter(|&(index, _, now)| self.passable.get(index).copied() != Some(now))
            .map(|(index, _, now)| (index, now))
            .collect();
        if flips.is_empty() {
            return Ok(0);
        }
        self.km = self.km.add(self.heuristic(self.last, self.start));
        self.last = self.start;
        if self.km.straight >= K::KM_LIMIT || self.km.diagonal >= K::KM_LIMIT {
            self.rekey();
        }
        // Every directed step whose cost may change, as (from, move): into and out of each
        // flipped cell, and the diagonal steps between its orthogonal neighbours.
        let mut edges: Vec<(usize, usize)> = Vec::with_capacity(flips.len() * 24);
        for &(c, _) in &flips {
            for (k, (&delta, &back)) in self.deltas.iter().zip(&OPPOSITE).enumerate() {
                edges.push((c, k));
                edges.push((c.wrapping_add_signed(delta), back));
            }
        }
        // The diagonal moves `4 + i` from `u` that pass the flipped cell: it is one of their
        // sides `u + delta[side]`.
        for &(c, _) in &flips {
            for (i, &(s0, s1)) in DIAGONAL_SIDES.iter().enumerate() {
                for side in [s0, s1] {
                    let u = c.wrapping_add_signed(-self.deltas[side]);
                    edges.push((u, 4 + i));
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let old: Vec<StepCost> = edges.iter().map(|&(u, k)| self.cost(u, k)).collect();
        for &(c, now) in &flips {
            if let Some(p) = self.passable.get_mut(c) {
                *p = now;
            }
        }
        for (&(u, k), &c_old) in edges.iter().zip(&old) {
            let c_new = self.cost(u, k);
            if c_new == c_old {
                continue;
            }
            let v = u.wrapping_add_signed(self.deltas[k]);
            if u != self.goal {
                let g_v = self.g(v);
                let rhs_u = self.rhs(u);
                if c_old > c_new {
                    self.set_rhs(u, rhs_u.min(c_new.add(g_v)));
                } else if rhs_u == c_old.add(g_v) {
                    let best = self.best_successor(u);
                    self.set_rhs(u, best);
                }
            }
            self.update_vertex(u);
        }
        self.dirty = true;
        Ok(flips.len())
    }

    /// [`DStarLite::path`], adding to `stats`.
    fn path(&mut self, stats: &mut PlanStats) -> Result<Planned> {
        if self.dirty {
            self.compute_shortest_path(Until::Paper, stats)?;
            if self.overflow.get() {
                return Ok(Planned::Widen);
            }
        }
        self.dirty = false;
        // Following `argmin c + g` is safe through consistent cells; a cell left
        // inconsistent with a key equal to the start's (a tie, which the paper's loop does
        // not process) may hold a stale `g`. Then process the ties, and failing that every
        // queued cell, and follow again.
        for until in [Until::Ties, Until::Empty] {
            match self.extract(*stats) {
                Extracted::Path(plan) => return Ok(Planned::Done(plan)),
                Extracted::Inconsistent(_) => {
                    self.compute_shortest_path(until, stats)?;
                    if self.overflow.get() {
                        self.dirty = true;
                        return Ok(Planned::Widen);
                    }
                }
            }
        }
        match self.extract(*stats) {
            Extracted::Path(plan) => Ok(Planned::Done(plan)),
            Extracted::Inconsistent(at) => Err(self.inconsistent(at)),
        }
    }

    /// Follow `argmin c(s, s') + g(s')` from the start to the goal through consistent
    /// cells (exact ties to the first move in the order E, S, W, N, SE, SW, NW, NE).
    fn extract(&self, stats: PlanStats) -> Extracted {
        if !self.passable.get(self.start).copied().unwrap_or(false)
            || !self.rhs(self.start).is_finite()
        {
            return Extracted::Path(None);
        }
        let expected = self.rhs(self.start);
        let mut waypoints = Vec::with_capacity(
            (expected.straight as usize)
                .saturating_add(expected.diagonal as usize)
                .saturating_add(1)
                .min(self.costs.len()),
        );
        let mut xy = self.cell(self.start);
        waypoints.push(xy);
        let mut total = StepCost::ZERO;
        let mut at = self.start;
        while at != self.goal {
            if waypoints.len() > self.costs.len() {
                return Extracted::Inconsistent(at);
            }
            let mut best: Option<(StepCost, usize, StepCost, usize)> = None;
            for k in 0..8 {
                let n = at.wrapping_add_signed(self.deltas[k]);
                let g_n = self.g(n);
                if !g_n.is_finite() {
                    continue;
                }
                let c = self.cost(at, k);
                if !c.is_finite() {
                    continue;
                }
                let through = c.add(g_n);
                if best.is_none_or(|b| through < b.0) {
                    best = Some((through, n, c, k));
                }
            }
            let Some((_, next, step, k)) = best else {
                return Extracted::Inconsistent(at);
            };
            if self.queued(next) {
                return Extracted::Inconsistent(next);
            }
            total = total.add(step);
            // The next cell's coordinates by the move (no division).
            let (dx, dy) = (
                MOVES.get(k).map_or(0, |m| m.0),
                MOVES.get(k).map_or(0, |m| m.1),
            );
            xy = CellXy::new(xy.x.wrapping_add_signed(dx), xy.y.wrapping_add_signed(dy));
            waypoints.push(xy);
            at = next;
        }
        Extracted::Path(Some(Plan {
            waypoints,
            length_cells: total.length(),
            stats,
        }))
    }

    /// The paper's `ComputeShortestPath` (Figure 4, lines 10-28).
    /// `until` [`Until::Paper`] is the paper's loop; the others process more (see
    /// [`DStarLite::path`]). Adds the expansions and pushes to `stats`.
    fn compute_shortest_path(&mut self, until: Until, stats: &mut PlanStats) -> Result<()> {
        let pushes_before = self.pushes;
        while let Some(&(top, u)) = self.heap.first() {
            if self.overflow.get() {
                break;
            }
            let u = u as usize;
            let start_key = self.key(self.start);
            let more = match until {
                Until::Paper => top < start_key,
                Until::Ties => top.k1_length_le(start_key),
                Until::Empty => true,
            };
            if !(more || self.rhs(self.start) > self.g(self.start)) {
                break;
            }
            stats.expanded += 1;
            self.opts
                .budget
                .check("D* Lite", stats.expanded, 0, stats.expanded)?;
            let new_key = self.key(u);
            let (g_u, rhs_u) = (self.g(u), self.rhs(u));
            if top < new_key {
                self.queue_set(u, new_key);
            } else if g_u > rhs_u {
                self.set_g(u, rhs_u);
                self.queue_remove(u);
                for (delta, back) in self.deltas.into_iter().zip(OPPOSITE) {
                    // Predecessor s = u + delta steps to u by the opposite move.
                    let s = u.wrapping_add_signed(delta);
                    let c = self.cost(s, back);
                    if !c.is_finite() {
                        continue;
                    }
                    let via = c.add(rhs_u);
                    if s != self.goal && via < self.rhs(s) {
                        self.set_rhs(s, via);
                    }
                    self.update_vertex(s);
                }
            } else {
                let g_old = g_u;
                self.set_g(u, StepCost::INF);
                for (delta, back) in self.deltas.into_iter().zip(OPPOSITE) {
                    let s = u.wrapping_add_signed(delta);
                    let c = self.cost(s, back);
                    if !c.is_finite() {
                        continue;
                    }
                    if s != self.goal && self.rhs(s) == c.add(g_old) {
                        let best = self.best_successor(s);
                        self.set_rhs(s, best);
                    }
                    self.update_vertex(s);
                }
                self.update_vertex(u);
            }
        }
        stats.generated += self.pushes - pushes_before;
        Ok(())
    }

    /// `UpdateVertex(u)` of Figure 4: queue `u` with its current key when inconsistent
    /// (or re-key it), take it out when consistent.
    fn update_vertex(&mut self, u: usize) {
        let Some(&[g, rhs]) = self.costs.get(u) else {
            return;
        };
        if g != rhs {
            let key = self.key(u);
            self.queue_set(u, key);
        } else if self.queued(u) {
            self.queue_remove(u);
        }
    }

    /// Start `k_m` again from zero: every queued key is computed anew for the current
    /// start and the heap rebuilt (keeps the keys' step counts small; `O(queue)`, after
    /// tens of millions of cells driven).
    fn rekey(&mut self) {
        self.km = StepCost::ZERO;
        let cells: Vec<u32> = std::mem::take(&mut self.heap)
            .into_iter()
            .map(|(_, u)| u)
            .collect();
        self.queue_afresh(&cells);
    }

    /// Queue `cells`, taken out of an emptied queue, again, each with its key computed
    /// afresh ([`Search::rekey`], [`Search::convert`]).
    fn queue_afresh(&mut self, cells: &[u32]) {
        for &u in cells {
            if let Some(p) = self.pos.get_mut(u as usize) {
                *p = 0;
            }
        }
        for &u in cells {
            let key = self.key(u as usize);
            self.queue_set(u as usize, key);
        }
    }

    /// Whether `u` is queued.
    fn queued(&self, u: usize) -> bool {
        self.pos.get(u).is_some_and(|&p| p != 0)
    }

    /// Queue `u` with `key`, or change its key.
    fn queue_set(&mut self, u: usize, key: K) {
        self.pushes += 1;
        let pos = self.position(u);
        if pos == NOT_QUEUED {
            let at = self.heap.len();
            self.heap.push((key, u as u32));
            self.set_pos(u, at);
            self.sift_up(at);
        } else {
            let at = pos as usize;
            let Some(entry) = self.heap.get_mut(at) else {
                return;
            };
            let old = entry.0;
            if key == old {
                return;
            }
            entry.0 = key;
            if key < old {
                self.sift_up(at);
            } else {
                self.sift_down(at);
            }
        }
    }

    /// Take `u` out of the queue.
    fn queue_remove(&mut self, u: usize) {
        let pos = self.position(u);
        if pos == NOT_QUEUED {
            return;
        }
        let at = pos as usize;
        if let Some(p) = self.pos.get_mut(u) {
            *p = 0;
        }
        let Some(last) = self.heap.pop() else {
            return;
        };
        if at < self.heap.len() {
            let old = self.heap.get(at).map(|e| e.0);
            if let Some(slot) = self.heap.get_mut(at) {
                *slot = last;
            }
            self.set_pos(last.1 as usize, at);
            if old.is_some_and(|o| last.0 < o) {
                self.sift_up(at);
            } else {
                self.sift_down(at);
            }
        }
    }

    /// The heap position of `u`, or [`NOT_QUEUED`].
    #[inline]
    fn position(&self, u: usize) -> u32 {
        self.pos
            .get(u)
            .map_or(NOT_QUEUED, |&p| p.checked_sub(1).unwrap_or(NOT_QUEUED))
    }

    #[inline]
    fn set_pos(&mut self, u: usize, at: usize) {
        if let Some(p) = self.pos.get_mut(u) {
            *p = at as u32 + 1;
        }
    }

    fn sift_up(&mut self, mut at: usize) {
        let Some(&item) = self.heap.get(at) else {
            return;
        };
        while at > 0 {
            let parent = (at - 1) / ARITY;
            let Some(&p) = self.heap.get(parent) else {
                break;
            };
            if item.0 >= p.0 {
                break;
            }
            if let Some(slot) = self.heap.get_mut(at) {
                *slot = p;
            }
            self.set_pos(p.1 as usize, at);
            at = parent;
        }
        if let Some(slot) = self.heap.get_mut(at) {
            *slot = item;
        }
        self.set_pos(item.1 as usize, at);
    }

    fn sift_down(&mut self, mut at: usize) {
        let Some(&item) = self.heap.get(at) else {
            return;
        };
        let n = self.heap.len();
        loop {
            let first = at * ARITY + 1;
            if first >= n {
                break;
            }
            let mut best = first;
            let mut best_key = match self.heap.get(first) {
                Some(e) => e.0,
                None => break,
            };
            for c in first + 1..(first + ARITY).min(n) {
                if let Some(e) = self.heap.get(c)
                    && e.0 < best_key
                {
                    best = c;
                    best_key = e.0;
                }
            }
            if best_key >= item.0 {
                break;
            }
            let Some(&child) = self.heap.get(best) else {
                break;
            };
            if let Some(slot) = self.heap.get_mut(at) {
                *slot = child;
            }
            self.set_pos(child.1 as usize, at);
            at = best;
        }
        if let Some(slot) = self.heap.get_mut(at) {
            *slot = item;
        }
        self.set_pos(item.1 as usize, at);
    }

    /// `CalculateKey(s)`.
    fn key(&self, s: usize) -> K {
        let m = self.g(s).min(self.rhs(s));
        K::new(m.add(self.heuristic(self.start, s)).add(self.km), m).unwrap_or_else(|| {
            self.overflow.set(true);
            K::MAX
        })
    }

    /// `min over successors s' of c(u, s') + g(s')`.
    fn best_successor(&self, u: usize) -> StepCost {
        let mut best = StepCost::INF;
        for k in 0..8 {
            let n = u.wrapping_add_signed(self.deltas[k]);
            best = best.min(self.cost(u, k).add(self.g(n)));
        }
        best
    }

    /// Cost of move `k` from `u`, infinite when illegal.
    #[inline]
    fn cost(&self, u: usize, k: usize) -> StepCost {
        let pass = |i: usize| self.passable.get(i).copied().unwrap_or(false);
        let Some(&delta) = self.deltas.get(k) else {
            return StepCost::INF;
        };
        let v = u.wrapping_add_signed(delta);
        if !pass(u) || !pass(v) {
            return StepCost::INF;
        }
        let weight = self.weights.get(v).copied().unwrap_or(0);
        match k.checked_sub(4).and_then(|i| DIAGONAL_SIDES.get(i)) {
            None => StepCost::step(false, weight),
            Some(&(a, b)) => {
                let side = |s: usize| pass(u.wrapping_add_signed(self.deltas[s]));
                if side(a) && side(b) {
                    StepCost::step(true, weight)
                } else {
                    StepCost::INF
                }
            }
        }
    }

    /// Octile distance between two padded cells.
    #[inline]
    fn heuristic(&self, a: usize, b: usize) -> StepCost {
        // Padded indices fit in u32 (grids hold at most 30 million cells): 32-bit division.
        let pw = self.pw as u32;
        let (a, b) = (a as u32, b as u32);
        let dx = (a % pw).abs_diff(b % pw);
        let dy = (a / pw).abs_diff(b / pw);
        StepCost::octile(dx as usize, dy as usize)
    }

    #[inline]
    fn g(&self, u: usize) -> StepCost {
        self.costs.get(u).map_or(StepCost::INF, |c| unpack(c[0]))
    }

    #[inline]
    fn rhs(&self, u: usize) -> StepCost {
        self.costs.get(u).map_or(StepCost::INF, |c| unpack(c[1]))
    }

    #[inline]
    fn set_g(&mut self, u: usize, g: StepCost) {
        if let Some(c) = self.costs.get_mut(u) {
            c[0] = pack(g);
        }
    }

    #[inline]
    fn set_rhs(&mut self, u: usize, rhs: StepCost) {
        if let Some(c) = self.costs.get_mut(u) {
            c[1] = pack(rhs);
        }
    }

    fn pad(&self, c: CellXy) -> usize {
        (c.y + 1) * self.pw + c.x + 1
    }

    fn cell(&self, index: usize) -> CellXy {
        CellXy::new(
            (index % self.pw).saturating_sub(1),
            (index / self.pw).saturating_sub(1),
        )
    }

    fn inconsistent(&self, at: usize) -> PlanError {
        let c = self.cell(at);
        PlanError::InconsistentSearch {
            planner: "D* Lite",
            x: c.x,
            y: c.y,
        }
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

    #[test]
    #[allow(clippy::float_cmp)]
    fn open_grid_straight_line() {
        let grid = OccupancyGrid::new(5, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        let mut p = DStarLite::new(&grid, (0, 1), (4, 1), &DStarLiteOptions::default()).unwrap();
        let plan = p.path().unwrap();
        assert_eq!(plan.unwrap().length_cells, 4.0);
    }

    /// The exact length order and its integer keys agree with each other and with the
    /// lengths in high precision, also on near ties (Pell pairs: 99^2 - 2 * 70^2 = 1).
    #[test]
    fn lengths_compare_exactly_and_their_fixed_point_keys_keep_the_order() {
        let c = |straight, diagonal| StepCost {
            straight,
            diagonal,
            weight: 0,
        };
        let mut pairs = vec![c(99, 0), c(0, 70), c(3363, 0), c(0, 2378), c(1, 1), c(2, 0)];
        // Large near ties: 114243^2 - 2 * 80782^2 = -1 ... scaled into big counts.
        pairs.extend([c(114_243, 0), c(0, 80_782), c(1 << 26, 7), c(7, 1 << 26)]);
        for a in 0..40 {
            for d in 0..30 {
                pairs.push(c(a, d));
            }
        }
        for &p in &pairs {
            for &q in &pairs {
                let exact = p.cmp_length(q);
                assert_eq!(exact, q.cmp_length(p).reverse());
                assert_eq!(fixed_length(p).cmp(&fixed_length(q)), exact, "{p:?} {q:?}");
                assert_eq!(exact == Ordering::Equal, p == q);
                // f64 agrees where the values are far apart.
                if (p.length() - q.length()).abs() > 1e-6 {
                    assert_eq!(p.length().partial_cmp(&q.length()), Some(exact));
                }
            }
        }
        assert!(c(99, 0) > c(0, 70)); // 99 > 70 sqrt 2 = 98.9949...
        assert!(StepCost::INF > c(u32::MAX - 1, u32::MAX - 1));
        assert!(!c(1, 0).add(StepCost::INF).is_finite());
    }

    /// The narrow keys' lengths order exactly like the exact comparison up to
    /// [`NARROW_MAX_STEPS`], on the nearest ties there are (Pell pairs up to a million
    /// steps: `665857^2 - 2 * 470832^2 = 1`), and refuse larger counts.
    #[test]
    fn narrow_lengths_order_exactly_up_to_their_limit() {
        let c = |straight, diagonal| StepCost {
            straight,
            diagonal,
            weight: 0,
        };
        let max = NARROW_MAX_STEPS;
        let mut pairs = vec![c(0, 0), c(1, 0), c(0, 1), c(max, max), c(max, 0), c(0, max)];
        // Pell pairs (x, y) with x^2 - 2 y^2 = +-1: x straight against y diagonal steps.
        for (x, y) in [
            (3, 2),
            (7, 5),
            (99, 70),
            (3363, 2378),
            (114_243, 80_782),
            (665_857, 470_832),
        ] {
            pairs.extend([c(x, 0), c(0, y), c(x + 1, 0), c(x - 1, 0), c(0, y + 1)]);
            // The same near tie shifted to large common counts.
            pairs.extend([c(x + max - 665_857, max - y), c(max, max - y)]);
            pairs.extend([c(max - x, y), c(max - x, 0), c(max, y)]);
        }
        for a in (0..max).step_by(99_991) {
            for d in (0..max).step_by(77_773) {
                pairs.push(c(a, d));
            }
        }
        for &p in &pairs {
            for &q in &pairs {
                let (np, nq) = (narrow_length(p).unwrap(), narrow_length(q).unwrap());
                assert_eq!(np.cmp(&nq), p.cmp_length(q), "{p:?} {q:?}");
            }
        }
        assert_eq!(narrow_length(StepCost::INF), Some(u64::MAX));
        assert_eq!(narrow_length(c(max + 1, 0)), None);
        assert_eq!(narrow_length(c(0, max + 1)), None);
        assert!(narrow_length(c(max, max)).unwrap() < u64::MAX);
        // The rounded sqrt 2 against the 2^-64 one.
        let scaled = u128::from(SQRT_2_NARROW) << 22;
        assert!(scaled.abs_diff(SQRT_2_FIXED) <= 1 << 21);
        // Tie weights do not fit a narrow key; infinite costs do.
        assert!(NarrowKey::new(StepCost::step(false, 1), StepCost::ZERO).is_none());
        assert_eq!(
            NarrowKey::new(StepCost::INF, StepCost::INF),
            Some(NarrowKey::MAX)
        );
    }

    /// Tie keys order like the wide keys (lengths exactly, then the weight) and refuse parts
    /// of different weights.
    #[test]
    fn tie_keys_order_like_wide_keys() {
        let c = |straight, diagonal, weight| StepCost {
            straight,
            diagonal,
            weight,
        };
        let h = StepCost::octile(7, 3);
        let mut parts = vec![StepCost::INF];
        for (s, d) in [
            (0, 0),
            (99, 0),
            (0, 70),
            (3, 1),
            (4, 0),
            (665_857, 0),
            (0, 470_832),
        ] {
            for w in [0, 1, 5, u64::from(u32::MAX) * 3] {
                parts.push(c(s, d, w));
            }
        }
        let keys: Vec<(Option<TieKey>, WideKey)> = parts
            .iter()
            .map(|&m| {
                let k1 = m.add(h);
                (TieKey::new(k1, m), WideKey::new(k1, m).unwrap())
            })
            .collect();
        for (a, wa) in &keys {
            for (b, wb) in &keys {
                assert_eq!(a.unwrap().cmp(&b.unwrap()), wa.cmp(wb), "{wa:?} {wb:?}");
            }
        }
        assert!(TieKey::new(c(5, 0, 1), c(1, 0, 2)).is_none());
        assert!(TieKey::new(c(5, 0, 1), StepCost::INF).is_none());
        assert!(TieKey::new(c(NARROW_MAX_STEPS + 1, 0, 0), c(0, 0, 0)).is_none());
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

    #[test]
    fn tie_weights_are_fixed_and_spread() {
        assert_eq!(tie_weight(3, 4), tie_weight(3, 4));
        assert_ne!(tie_weight(3, 4), tie_weight(4, 3));
        let mut w: Vec<u32> = (0..64)
            .flat_map(|y| (0..64).map(move |x| tie_weight(x, y)))
            .collect();
        w.sort_unstable();
        w.dedup();
        assert_eq!(w.len(), 64 * 64);
        // Roughly uniform: the median near 2^31.
        let median = f64::from(w[w.len() / 2]) / f64::from(u32::MAX);
        assert!((median - 0.5).abs() < 0.05, "{median}");
    }
}
