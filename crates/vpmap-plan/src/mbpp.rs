//! Multi-Bug Path Planning (MBPP, the thesis's chapter 5 and Algorithm 2): virtual bugs go
//! greedily toward the goal along the m-line, split at every obstacle they hit so that one
//! follows its wall each way, note the corner states they pass (`v_list`), leave the wall
//! where it meets the m-line again, wait where another bug has gone before, and finally
//! the shortest `v_list` — completed, line-of-sight checked and re-planned where blocked —
//! is smoothed into the path. Every other feasible `v_list` is returned as an alternative.
//!
//! `docs/mbpp.md` walks through the rules with the thesis's names; this page states them
//! exactly as implemented.
//!
//! # States and moves
//! A bug stands on a traversable cell. `rr(s) = rr_g - |s - goal|` (errata: no stored
//! matrix), so the greedy action `argmax rr` over the 8 neighbours is the neighbour
//! nearest to the goal. From the start, greedy moves in an empty grid go diagonally until
//! the bug is level with the goal, then straight (the nearest neighbour is unique for
//! integer offsets): that walk is the **m-line**, and every cell on it has a position
//! `0..=n` along it with the distance to the goal strictly falling. A bug in **greedy
//! mode** always stands on the m-line and steps to the next m-line cell when that step is
//! legal (8-connected, a diagonal step needs both orthogonal neighbours traversable — the
//! collision rule of [`crate::los`] for single steps).
//!
//! # Hit, birth and wall following (C4)
//! When the greedy step is illegal the bug **hits** the obstacle at its cell `H` (added to
//! its `hit_list`). It gives birth to a second bug with a copy of its `v_list`; the parent
//! follows the wall keeping it on its right hand, the newborn keeps it on its left, so the
//! two go round the obstacle in opposite directions (the thesis's "state on the other side
//! of its parent"). Both put their hand on the blocked cell of the greedy step (or, for a
//! diagonal step squeezed between blocked cells, on the first blocked orthogonal
//! neighbour). Wall following uses the four straight moves and the classic hand rule:
//! turn towards the hand if that cell is traversable, else go straight, else turn away,
//! else go back. (The thesis lets the bug choose among its 8 neighbours by `rr` without
//! revisiting its last two states; that rule is not well defined at concave corners and
//! can cycle in a dead end, while the hand rule traces the whole boundary of the
//! obstacle's 8-connected component, and the path's shape comes from the `v_list`, not
//! from the track.)
//!
//! # Leaving (C2) and termination (C1)
//! - **C2(a)**: a following bug that steps onto an m-line cell *further along than its
//!   hit* (closer to the goal) leaves the wall, notes the cell in its `leave_list`, and goes
//!   greedy. The thesis leaves at any m-line cell; that is Bug2 without its "closer than the
//!   hit point" test, which can circle forever between two m-line crossings, and the
//!   printed C1(b) does not always catch it. With the test, the hit positions along one
//!   bug's life strictly increase, so a bug hits at most `n` times.
//! - **C1(a)**, **C1(b)**: a following bug that cannot move, or whose (cell, heading) state
//!   repeats (it went round its obstacle without meeting the m-line beyond its hit), is
//!   terminated. The wall walk is deterministic, so a repeat means a loop; repeats are
//!   found in `O(1)` memory by Brent's cycle detection, plus a direct test for the state it
//!   started in.
//! - **C1(c)** as printed (end a following bug on *any* bug's hit state) is not applied: a
//!   bug crossing another's hit cell walks a different wall state with a different hit
//!   distance, and ending it can lose the only path (found by the random-grid tests). The
//!   waiting condition below already stops duplicate work where it is exact.
//! - A bug that reaches the goal is done; the goal ends its `v_list`.
//!
//! # Waiting (C3) and idle bugs
//! Greedy behaviour has no memory: two greedy bugs on the same m-line cell walk the same
//! states from then on. So the first bug to stand greedily on an m-line cell **owns** it;
//! a bug that would go greedy on an owned cell (by leaving there, or by a greedy step) waits
//! there instead (the thesis waits only on other bugs' leave states; a greedy step onto an
//! owned cell can only reach a leave state, and leaving onto a cell another bug walked
//! greedily would otherwise walk its path again, against Lemma 3). When all bugs are done,
//! a waiting bug is completed with the corner states the owner (and its descendants) noted
//! after that cell: its `v_list` joins every continuation of the owner's `v_list` at that
//! point.
//!
//! # `v_list` by line of sight
//! Each bug keeps the last state of its `v_list` as its anchor. After every step it checks
//! line of sight from the anchor to its new cell; when it is blocked, the previous cell —
//! visible from the anchor and one legal step from the new cell — is appended and becomes
//! the anchor (the thesis's "common neighbour of the previous and current states visible
//! from the latest state in `v_list`"). A bug leaving the wall also appends its leave cell,
//! so that bugs waiting there later join clear segments. Hence consecutive states of a
//! bug's own `v_list` are always in line of sight.
//!
//! # Selection, line-of-sight check and re-planning
//! All `v_list`s form one graph (a tree of shared prefixes plus the joins of waiting bugs).
//! Its shortest start-goal path (Dijkstra over Euclidean segment lengths) is the thesis's
//! `select_list`. Its segments are checked for line of sight; a join segment can be
//! blocked (the owner's next corner need not be visible from where the waiting bug joined).
//! A blocked segment `(u, v)` is re-planned by running MBPP from `u` to `v` and splicing the
//! result in (the thesis restarts "with the state just before the first identified
//! occupied state"; starting at `u` keeps the segment's ends on known states), and the
//! selection is repeated until the shortest path is clear. A re-planning that fails
//! (nesting deeper than [`MbppOptions::max_replan_depth`]) drops the segment; bugs' own
//! `v_list`s are clear, so a path is always left when one was found. The chosen path is
//! then smoothed by [`smooth_path`] (the thesis's `Path_smooth`: farthest visible state
//! first).
//!
//! # Completeness and bounds
//! If the goal is reachable, the m-line beyond a hit runs from the obstacle to the goal, and
//! the wall walk round the obstacle's component crosses it (an 8-connected path from inside
//! to outside meets a 4-connected closed boundary), so one of the two wall followers
//! leaves beyond its hit; hits move strictly along the m-line, so some bug reaches the goal.
//! Every m-line cell is hit at most once (it must be owned first), so there are at most
//! `2 n + 1` bugs for an m-line of `n + 1` cells, and each walks at most about three times
//! the boundary of one obstacle component plus the m-line: an unsolvable query ends with
//! `found = false` after `O(n x free cells)` steps in the worst case, and usually after one
//! walk round the enclosing wall.
//!
//! # References
//! - The thesis, chapter 5 and Appendix A.2 (Algorithm 2), read with its errata.
//! - V. J. Lumelsky, A. A. Stepanov, "Path-Planning Strategies for a Point Mobile Automaton
//!   Moving Amidst Unknown Obstacles of Arbitrary Shape", Algorithmica 2, 1987 (Bug2 and its
//!   leave rule).
//! - R. P. Brent, "An Improved Monte Carlo Factorization Algorithm", BIT 20, 1980 (cycle
//!   detection).

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};
use std::hash::{BuildHasherDefault, Hasher};

use crate::error::Result;
use crate::grid::OccupancyGrid;
use crate::los::{LosCounter, Passable, PassableGrid};
use crate::plan::{Plan, PlanStats, check_endpoint, path_length};
use crate::smoothing::smooth_path;

/// Options of [`mbpp`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MbppOptions {
    /// Whether [`Cell::Unknown`](crate::Cell::Unknown) cells may be entered (default: no).
    pub unknown_passable: bool,
    /// Record every bug's track (the cells it walked) in [`Mbpp::bugs`] (default: no; it
    /// costs memory proportional to the bugs' steps).
    pub record_tracks: bool,
    /// How deeply re-planning may nest (default 4).
    pub max_replan_depth: usize,
    /// When a wall-following bug leaves the wall (default: the thesis's m-line rule).
    pub leave: LeaveRule,
}

/// When a wall-following bug leaves the wall for greedy moves (condition C2(a)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LeaveRule {
    /// The thesis's rule: on meeting the start-goal m-line again, further along it than the
    /// hit (Bug2). Greedy moves follow the m-line.
    #[default]
    MLine,
    /// As soon as the bug is closer to the goal than at its hit (the leave rule of
    /// DistBug-like bug algorithms); greedy moves then follow a new straight line from the
    /// leave cell to the goal. Shorter tracks, more bugs; see `docs/mbpp.md` for the
    /// comparison.
    Closer,
}

impl Default for MbppOptions {
    fn default() -> Self {
        Self {
            unknown_passable: false,
            record_tracks: false,
            max_replan_depth: 4,
            leave: LeaveRule::MLine,
        }
    }
}

/// How a bug's travel ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BugFate {
    /// It reached the goal.
    ReachedGoal,
    /// It stood on an m-line cell another bug had walked greedily and waited there (C3);
    /// its `v_list` is completed from that bug's.
    Waiting,
    /// Its wall walk repeated a state without meeting the m-line beyond its hit (C1(b)).
    Looped,
    /// It could not move at all (C1(a)).
    Stuck,
}

/// One bug's life, for drawing and statistics.
#[derive(Clone, Debug, PartialEq)]
pub struct BugTrack {
    /// The bug that gave birth to it (`None` for the first bug).
    pub parent: Option<usize>,
    /// The cells it walked, from its birth cell (empty unless
    /// [`MbppOptions::record_tracks`] is set).
    pub cells: Vec<(usize, usize)>,
    /// Where it hit obstacles (its `hit_list`).
    pub hits: Vec<(usize, usize)>,
    /// Where it left walls for the m-line (its `leave_list`).
    pub leaves: Vec<(usize, usize)>,
    /// Steps it took.
    pub steps: usize,
    /// How it ended.
    pub fate: BugFate,
}

impl BugTrack {
    /// A bug's record at birth on `cell` (its track holds `cell` when `record`).
    fn born(parent: Option<usize>, cell: Xy, record: bool, fate: BugFate) -> Self {
        Self {
            parent,
            cells: if record { vec![to_u(cell)] } else { Vec::new() },
            hits: Vec::new(),
            leaves: Vec::new(),
            steps: 0,
            fate,
        }
    }
}

/// Work counters of [`mbpp`] (including nested re-planning runs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct MbppStats {
    /// Bugs born, the first one included.
    pub bugs: usize,
    /// Steps taken by all bugs.
    pub bug_steps: usize,
    /// Obstacle hits.
    pub hits: usize,
    /// Bugs that waited (C3).
    pub waits: usize,
    /// Line-of-sight queries (during the walk, the final check and the smoothing).
    pub los_checks: usize,
    /// Cells looked up by those queries.
    pub los_cells: usize,
    /// Blocked segments re-planned.
    pub replans: usize,
}

/// The result of [`mbpp`].
#[derive(Clone, Debug, PartialEq)]
pub struct Mbpp {
    /// The shortest feasible path after smoothing, or `None` when no bug reached the goal
    /// (the goal is unreachable). Its statistics count bug steps as `expanded` and bugs as
    /// `generated`.
    pub best: Option<Plan>,
    /// Every other feasible path found: the `v_list`s of the bugs that reached the goal and
    /// of the waiting bugs completed from them whose segments are all clear, unsmoothed,
    /// shortest first, without duplicates or the path `best` was smoothed from.
    pub alternatives: Vec<Plan>,
    /// The bugs of the top-level run, in order of birth.
    pub bugs: Vec<BugTrack>,
    /// Work counters.
    pub stats: MbppStats,
}

/// Multi-Bug Path Planning from `start` to `goal` (see the [module docs](self)).
///
/// # Errors
/// [`PlanError::EndpointOutsideGrid`](crate::PlanError::EndpointOutsideGrid) when `start`
/// or `goal` is outside the grid,
/// [`PlanError::EndpointBlocked`](crate::PlanError::EndpointBlocked) when it is not
/// traversable.
///
/// # Complexity
/// At most `2 n + 1` bugs for an m-line of `n + 1` cells; each step costs one line-of-sight
/// query. See the module docs for the bound on unsolvable queries.
///
/// # Example
/// ```
/// use vpmap_plan::{Cell, OccupancyGrid, mbpp::{mbpp, MbppOptions}};
/// // ......
/// // ..#...
/// // ..#...
/// // ..#...
/// // ......
/// let mut grid = OccupancyGrid::new(6, 5, 1.0, [0.0; 2], Cell::Free).unwrap();
/// for y in 1..4 {
///     grid.set(2, y, Cell::Occupied).unwrap();
/// }
/// let result = mbpp(&grid, (0, 2), (5, 2), &MbppOptions::default()).unwrap();
/// let best = result.best.unwrap();
/// // Round the wall's top end, past the corner cells (1, 0) and (3, 0): the shortest way.
/// assert_eq!(best.waypoints, [(0, 2), (1, 0), (3, 0), (5, 2)]);
/// assert!((best.length - (5f64.sqrt() + 2.0 + 8f64.sqrt())).abs() < 1e-12);
/// // The first bug split once, at the wall; the newborn went round the bottom end and
/// // waited where the first bug had left the wall; its completed path is the alternative.
/// assert_eq!(result.bugs.len(), 2);
/// assert_eq!(result.alternatives.len(), 1);
/// assert!(result.alternatives[0].length > best.length);
/// ```
pub fn mbpp(
    grid: &OccupancyGrid,
    start: (usize, usize),
    goal: (usize, usize),
    opts: &MbppOptions,
) -> Result<Mbpp> {
    check_endpoint(grid, "start", start, opts.unknown_passable)?;
    check_endpoint(grid, "goal", goal, opts.unknown_passable)?;
    let padded = PassableGrid::new(grid, opts.unknown_passable);
    let mut stats = MbppStats::default();
    let mut counter = LosCounter::default();
    let outcome = run(
        &padded,
        to_i(start),
        to_i(goal),
        opts,
        0,
        &mut stats,
        &mut counter,
    );
    stats.los_checks = counter.checks;
    stats.los_cells = counter.cells;
    let plan_stats = PlanStats {
        expanded: stats.bug_steps,
        generated: stats.bugs,
        los_checks: counter.checks,
        los_cells: counter.cells,
    };
    let best = outcome.best.map(|waypoints| Plan {
        length: path_length(&waypoints),
        waypoints,
        stats: plan_stats,
    });
    let alternatives = outcome
        .alternatives
        .into_iter()
        .map(|waypoints| Plan {
            length: path_length(&waypoints),
            waypoints,
            stats: plan_stats,
        })
        .collect();
    Ok(Mbpp {
        best,
        alternatives,
        bugs: outcome.bugs,
        stats,
    })
}

/// The cells of the m-line from `start` to `goal`: the digital straight segment between
/// them, one cell per step along the longer axis, the other coordinate rounded to the
/// nearest cell (halves away from the start). Every step brings the bug closer to the goal
/// (`rr` rises).
///
/// # Example
/// ```
/// use vpmap_plan::mbpp::m_line;
/// assert_eq!(m_line((0, 0), (4, 1)), [(0, 0), (1, 0), (2, 1), (3, 1), (4, 1)]);
/// assert_eq!(m_line((3, 4), (1, 0)), [(3, 4), (2, 3), (2, 2), (1, 1), (1, 0)]);
/// assert_eq!(m_line((2, 2), (2, 2)), [(2, 2)]);
/// ```
#[must_use]
pub fn m_line(start: (usize, usize), goal: (usize, usize)) -> Vec<(usize, usize)> {
    let line = MLine::new(to_i(start), to_i(goal));
    (0..=line.last)
        .map(|k| {
            let (x, y) = line.cell(k);
            (x as usize, y as usize)
        })
        .collect()
}

/// Cell coordinates as signed integers.
type Xy = (i64, i64);

fn to_i(c: (usize, usize)) -> Xy {
    (c.0 as i64, c.1 as i64)
}

fn to_u(c: Xy) -> (usize, usize) {
    (c.0 as usize, c.1 as usize)
}

/// The m-line in closed form: the digital straight segment from `start` to `goal` (one
/// cell per step along the major axis, the minor coordinate rounded to the nearest cell,
/// halves away from the start).
#[derive(Clone, Copy, Debug)]
struct MLine {
    start: Xy,
    /// Whether x is the major axis.
    x_major: bool,
    /// Steps along the major axis (the position of the goal).
    last: i64,
    /// Signed extent along the minor axis.
    minor: i64,
    major_sign: i64,
}

impl MLine {
    fn new(start: Xy, goal: Xy) -> Self {
        let (dx, dy) = (goal.0 - start.0, goal.1 - start.1);
        let x_major = dx.abs() >= dy.abs();
        let (major, minor) = if x_major { (dx, dy) } else { (dy, dx) };
        Self {
            start,
            x_major,
            last: major.abs(),
            minor,
            major_sign: major.signum(),
        }
    }

    fn cell(&self, k: i64) -> Xy {
        let along = k * self.major_sign;
        // round(k * |minor| / last), halves up, with the minor sign.
        let across = if self.last == 0 {
            0
        } else {
            (2 * k * self.minor.abs() + self.last) / (2 * self.last) * self.minor.signum()
        };
        if self.x_major {
            (self.start.0 + along, self.start.1 + across)
        } else {
            (self.start.0 + across, self.start.1 + along)
        }
    }

    /// The position of `c` along the m-line, if it is on it.
    fn position(&self, c: Xy) -> Option<i64> {
        let along = if self.x_major {
            c.0 - self.start.0
        } else {
            c.1 - self.start.1
        };
        let k = along * self.major_sign;
        (k >= 0 && k <= self.last && self.cell(k) == c).then_some(k)
    }
}

/// The four straight headings, clockwise on screen (y down): east, south, west, north.
const HEADINGS: [Xy; 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];

/// Which hand a wall-following bug keeps on the wall.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Hand {
    Right,
    Left,
}

impl Hand {
    /// Heading indices to try, in order: towards the hand, straight, away, back.
    fn order(self, heading: u8) -> [u8; 4] {
        let h = heading;
        match self {
            Self::Right => [(h + 1) % 4, h, (h + 3) % 4, (h + 2) % 4],
            Self::Left => [(h + 3) % 4, h, (h + 1) % 4, (h + 2) % 4],
        }
    }
}

/// A wall-walk state: cell and heading.
type WalkState = (Xy, u8);

#[derive(Clone, Copy, Debug)]
enum Mode {
    /// On a straight line to the goal (the m-line, or the bug's own line under
    /// [`LeaveRule::Closer`]) at this position.
    Greedy { line: MLine, position: i64 },
    /// Following a wall since a hit at m-line position `hit`.
    Follow {
        hand: Hand,
        heading: u8,
        hit: i64,
        /// Squared distance from the hit cell to the goal.
        hit_d2: i64,
        /// The state after the first step, once taken.
        start: Option<WalkState>,
        /// Brent's saved state, window length and steps into the window.
        saved: WalkState,
        power: u32,
        lam: u32,
    },
}

#[derive(Clone, Debug)]
struct Bug {
    cell: Xy,
    anchor: u32,
    mode: Mode,
    track: BugTrack,
}

/// A `v_list` state: a cell and the state before it (`NONE` for the start).
#[derive(Clone, Copy, Debug)]
struct Vertex {
    cell: Xy,
    parent: u32,
}

const NONE: u32 = u32::MAX;

/// Who first stood greedily on an m-line cell, with its anchor then, and whether that
/// anchor is the cell itself.
#[derive(Clone, Copy, Debug)]
struct Owner {
    anchor: u32,
    at_cell: bool,
}

/// A multiplicative (FxHash-like) hasher for the owners map: its keys are the walk's own
/// cells, not adversarial input, and SipHash cost more than the map's lookups themselves.
#[derive(Default)]
struct CellHasher(u64);

impl CellHasher {
    fn add(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
}

impl Hasher for CellHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.add(u64::from(b));
        }
    }

    fn write_i64(&mut self, i: i64) {
        self.add(i as u64);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// A waiting bug's join: its state at the cell, and the owner's anchor there.
#[derive(Clone, Copy, Debug)]
struct Join {
    vertex: u32,
    owner: Owner,
}

/// What one (possibly nested) run produces.
struct Outcome {
    best: Option<Vec<(usize, usize)>>,
    alternatives: Vec<Vec<(usize, usize)>>,
    bugs: Vec<BugTrack>,
}

/// The bugs' walk, then selection, check and re-planning.
fn run(
    grid: &PassableGrid,
    start: Xy,
    goal: Xy,
    opts: &MbppOptions,
    depth: usize,
    stats: &mut MbppStats,
    counter: &mut LosCounter,
) -> Outcome {
    if start == goal {
        stats.bugs += 1;
        return Outcome {
            best: Some(vec![to_u(start)]),
            alternatives: Vec::new(),
            bugs: vec![BugTrack::born(
                None,
                start,
                opts.record_tracks,
                BugFate::ReachedGoal,
            )],
        };
    }
    let mut walk = Walk::new(
        grid,
        start,
        goal,
        opts.record_tracks && depth == 0,
        opts.leave,
    );
    walk.run(counter);
    stats.bugs += walk.bugs.len();
    stats.bug_steps += walk.steps;
    stats.hits += walk.hits;
    stats.waits += walk.joins.len();
    let Walk {
        vertices,
        joins,
        goals,
        bugs,
        ..
    } = walk;
    let bugs: Vec<BugTrack> = bugs.into_iter().map(|b| b.track).collect();
    if goals.is_empty() {
        return Outcome {
            best: None,
            alternatives: Vec::new(),
            bugs,
        };
    }
    let mut graph = Graph::new(&vertices, &joins);
    let selected = select(&mut graph, grid, goal, opts, depth, stats, counter);
    let alternatives = alternatives(graph, &goals, &joins, grid, counter, selected.as_deref());
    let best = selected.map(|path| smooth_path(grid, &path, counter));
    Outcome {
        best,
        alternatives,
        bugs,
    }
}

/// The bugs and their shared `v_list` tree during the walk.
struct Walk<'g> {
    grid: &'g PassableGrid,
    goal: Xy,
    line: MLine,
    leave: LeaveRule,
    owners: HashMap<Xy, Owner, BuildHasherDefault<CellHasher>>,
    vertices: Vec<Vertex>,
    bugs: Vec<Bug>,
    born: Vec<usize>,
    joins: Vec<Join>,
    goals: Vec<u32>,
    record: bool,
    steps: usize,
    hits: usize,
}

impl<'g> Walk<'g> {
    fn new(grid: &'g PassableGrid, start: Xy, goal: Xy, record: bool, leave: LeaveRule) -> Self {
        let line = MLine::new(start, goal);
        let mut owners = HashMap::default();
        owners.insert(
            start,
            Owner {
                anchor: 0,
                at_cell: true,
            },
        );
        let first = Bug {
            cell: start,
            anchor: 0,
            mode: Mode::Greedy { line, position: 0 },
            track: BugTrack::born(None, start, record, BugFate::Stuck),
        };
        Self {
            grid,
            goal,
            line,
            leave,
            owners,
            vertices: vec![Vertex {
                cell: start,
                parent: NONE,
            }],
            bugs: vec![first],
            born: Vec::new(),
            joins: Vec::new(),
            goals: Vec::new(),
            record,
            steps: 0,
            hits: 0,
        }
    }

    fn push_vertex(&mut self, cell: Xy, parent: u32) -> u32 {
        let id = self.vertices.len() as u32;
        self.vertices.push(Vertex { cell, parent });
        id
    }

    fn vertex_cell(&self, id: u32) -> Xy {
        self.vertices.get(id as usize).map_or((-1, -1), |v| v.cell)
    }

    /// Every live bug takes one step per round (newborns from the next round on) until no
    /// bug is left to move.
    fn run(&mut self, counter: &mut LosCounter) {
        let mut live: Vec<usize> = vec![0];
        let mut next = Vec::new();
        while !live.is_empty() {
            for &b in &live {
                if self.step(b, counter) {
                    next.push(b);
                }
            }
            next.append(&mut self.born);
            std::mem::swap(&mut live, &mut next);
            next.clear();
        }
    }

    /// One step of bug `b`; whether it is still moving afterwards.
    fn step(&mut self, b: usize, counter: &mut LosCounter) -> bool {
        let Some(bug) = self.bugs.get(b) else {
            return false;
        };
        let (cell, mode) = (bug.cell, bug.mode);
        match mode {
            Mode::Greedy { line, position } => {
                let next = line.cell(position + 1);
                let d = (next.0 - cell.0, next.1 - cell.1);
                if !self.grid.step_clear(cell, d) {
                    self.hit(b, position, d);
                    return true;
                }
                self.move_to(b, next, counter);
                if next == self.goal {
                    self.reach_goal(b);
                    return false;
                }
                self.go_greedy(b, line, position + 1, false)
            }
            Mode::Follow {
                hand,
                heading,
                hit,
                hit_d2,
                start,
                mut saved,
                mut power,
                mut lam,
            } => {
                let Some(h) = hand
                    .order(heading)
                    .into_iter()
                    .find(|&h| passable(self.grid, add(cell, HEADINGS[usize::from(h)])))
                else {
                    self.end(b, BugFate::Stuck);
                    return false;
                };
                let next = add(cell, HEADINGS[usize::from(h)]);
                self.move_to(b, next, counter);
                if next == self.goal {
                    self.reach_goal(b);
                    return false;
                }
                let state = (next, h);
                let first = start.is_none();
                let start = start.or(Some(state));
                if !first && (start == Some(state) || state == saved) {
                    self.end(b, BugFate::Looped);
                    return false;
                }
                lam += 1;
                if lam == power {
                    saved = state;
                    power = power.saturating_mul(2);
                    lam = 0;
                }
                if let Some(bug) = self.bugs.get_mut(b) {
                    bug.mode = Mode::Follow {
                        hand,
                        heading: h,
                        hit,
                        hit_d2,
                        start,
                        saved,
                        power,
                        lam,
                    };
                }
                match self.leave {
                    LeaveRule::MLine => match self.line.position(next) {
                        Some(p) if p > hit => self.go_greedy(b, self.line, p, true),
                        _ => true,
                    },
                    LeaveRule::Closer if d2(next, self.goal) < hit_d2 => {
                        self.go_greedy(b, MLine::new(next, self.goal), 0, true)
                    }
                    LeaveRule::Closer => true,
                }
            }
        }
    }

    /// Bug `b` stands on m-line cell `position` and would go on greedily: it owns the cell,
    /// or waits when another bug owns it (C3). A bug leaving a wall notes the cell in its
    /// `leave_list` and `v_list`.
    fn go_greedy(&mut self, b: usize, line: MLine, position: i64, leaving: bool) -> bool {
        let Some(bug) = self.bugs.get(b) else {
            return false;
        };
        let (cell, anchor) = (bug.cell, bug.anchor);
        let slot = self.owners.get(&cell).copied();
        if leaving && let Some(bug) = self.bugs.get_mut(b) {
            bug.track.leaves.push(to_u(cell));
        }
        if let Some(owner) = slot {
            let vertex = if self.vertex_cell(anchor) == cell {
                anchor
            } else {
                self.push_vertex(cell, anchor)
            };
            self.joins.push(Join { vertex, owner });
            self.end(b, BugFate::Waiting);
            return false;
        }
        let anchor = if leaving && self.vertex_cell(anchor) != cell {
            self.push_vertex(cell, anchor)
        } else {
            anchor
        };
        let at_cell = self.vertex_cell(anchor) == cell;
        self.owners.insert(cell, Owner { anchor, at_cell });
        if let Some(bug) = self.bugs.get_mut(b) {
            bug.anchor = anchor;
            bug.mode = Mode::Greedy { line, position };
        }
        true
    }

    /// Bug `b` hit an obstacle at its cell, greedy step `d` being illegal: it follows the
    /// wall right-handed and a newborn follows it left-handed.
    fn hit(&mut self, b: usize, position: i64, d: Xy) {
        self.hits += 1;
        let Some(bug) = self.bugs.get(b) else {
            return;
        };
        let (cell, anchor) = (bug.cell, bug.anchor);
        let follow = |hand: Hand| Mode::Follow {
            hand,
            heading: self.initial_heading(cell, d, hand),
            hit: position,
            hit_d2: d2(cell, self.goal),
            start: None,
            saved: (cell, 4),
            power: 1,
            lam: 0,
        };
        let (right, left) = (follow(Hand::Right), follow(Hand::Left));
        let newborn = Bug {
            cell,
            anchor,
            mode: left,
            track: BugTrack {
                hits: vec![to_u(cell)],
                ..BugTrack::born(Some(b), cell, self.record, BugFate::Stuck)
            },
        };
        if let Some(bug) = self.bugs.get_mut(b) {
            bug.mode = right;
            bug.track.hits.push(to_u(cell));
        }
        self.born.push(self.bugs.len());
        self.bugs.push(newborn);
    }

    /// The heading that puts `hand` on the wall that blocks greedy step `d` from `cell`, as
    /// if the bug had just walked along it.
    fn initial_heading(&self, cell: Xy, d: Xy, hand: Hand) -> u8 {
        let orthogonal = if d.0 == 0 || d.1 == 0 {
            Some(d)
        } else if !passable(self.grid, add(cell, (d.0, 0))) {
            Some((d.0, 0))
        } else if !passable(self.grid, add(cell, (0, d.1))) {
            Some((0, d.1))
        } else {
            None
        };
        let turn_to_hand = |h: u8| match hand {
            Hand::Right => (h + 1) % 4,
            Hand::Left => (h + 3) % 4,
        };
        (0..4u8)
            .find(|&h| {
                let side = HEADINGS[usize::from(turn_to_hand(h))];
                match orthogonal {
                    // The wall cell is at the hand.
                    Some(w) => side == w,
                    // The wall cell is behind, at the hand's side.
                    None => add(side, HEADINGS[usize::from((h + 2) % 4)]) == d,
                }
            })
            .unwrap_or(0)
    }

    /// Move bug `b` one legal step to `next`, noting its previous cell in its `v_list` when
    /// `next` is out of sight of the latest noted state.
    fn move_to(&mut self, b: usize, next: Xy, counter: &mut LosCounter) {
        let Some(bug) = self.bugs.get(b) else {
            return;
        };
        let (cell, anchor) = (bug.cell, bug.anchor);
        let a = self.vertex_cell(anchor);
        let anchor = if a != cell && !self.grid.sight(a, next, counter) {
            self.push_vertex(cell, anchor)
        } else {
            anchor
        };
        self.steps += 1;
        let record = self.record;
        if let Some(bug) = self.bugs.get_mut(b) {
            bug.anchor = anchor;
            bug.cell = next;
            bug.track.steps += 1;
            if record {
                bug.track.cells.push(to_u(next));
            }
        }
    }

    fn reach_goal(&mut self, b: usize) {
        let Some(bug) = self.bugs.get(b) else {
            return;
        };
        let (cell, anchor) = (bug.cell, bug.anchor);
        let id = if self.vertex_cell(anchor) == cell {
            anchor
        } else {
            self.push_vertex(cell, anchor)
        };
        self.goals.push(id);
        self.end(b, BugFate::ReachedGoal);
    }

    fn end(&mut self, b: usize, fate: BugFate) {
        if let Some(bug) = self.bugs.get_mut(b) {
            bug.track.fate = fate;
        }
    }
}

/// Whether a bug may stand on cell `c`.
#[inline]
fn passable(grid: &PassableGrid, c: Xy) -> bool {
    grid.passable(c.0, c.1)
}

fn add(a: Xy, b: Xy) -> Xy {
    (a.0 + b.0, a.1 + b.1)
}

fn d2(a: Xy, b: Xy) -> i64 {
    (a.0 - b.0).pow(2) + (a.1 - b.1).pow(2)
}

fn dist(a: Xy, b: Xy) -> f64 {
    ((a.0 - b.0) as f64).hypot((a.1 - b.1) as f64)
}

/// A segment of the `v_list` graph; `clear` once its line of sight is known to be clear.
#[derive(Clone, Copy, Debug)]
struct Edge {
    to: u32,
    clear: bool,
}

/// One out-edge in [`Graph`]'s shared edge array, linked to the vertex's next out-edge.
#[derive(Clone, Copy, Debug)]
struct Slot {
    edge: Edge,
    /// The next slot of the same vertex (`NONE` at the end).
    next: u32,
}

/// All `v_list`s as one graph: tree edges (clear by construction) and join edges of
/// waiting bugs (clear when the owner had noted the join cell itself).
///
/// Out-edges live in one array, each vertex's as a linked list in insertion order (one
/// allocation for the whole graph instead of one per vertex). The order matters: Dijkstra
/// keeps the first of equally short ways, so it follows the order edges were added in.
/// A removed edge stays in its list as a dead slot (`to == NONE`) that iteration skips.
struct Graph {
    cells: Vec<Xy>,
    parents: Vec<u32>,
    /// First and last slot of each vertex's out-list (`NONE` when it has none).
    head: Vec<u32>,
    tail: Vec<u32>,
    slots: Vec<Slot>,
}

impl Graph {
    fn new(vertices: &[Vertex], joins: &[Join]) -> Self {
        let n = vertices.len();
        let mut graph = Self {
            cells: vertices.iter().map(|v| v.cell).collect(),
            parents: vertices.iter().map(|v| v.parent).collect(),
            head: vec![NONE; n],
            tail: vec![NONE; n],
            slots: Vec::with_capacity(n + joins.len()),
        };
        for (id, v) in vertices.iter().enumerate() {
            graph.push_edge(
                v.parent,
                Edge {
                    to: id as u32,
                    clear: true,
                },
            );
        }
        let mut targets = Vec::new();
        for join in joins {
            targets.clear();
            targets.extend(graph.out(join.owner.anchor).map(|e| e.to));
            if join.vertex as usize >= n {
                continue;
            }
            for &to in &targets {
                if to != join.vertex && !graph.out(join.vertex).any(|e| e.to == to) {
                    graph.push_edge(
                        join.vertex,
                        Edge {
                            to,
                            clear: join.owner.at_cell,
                        },
                    );
                }
            }
        }
        graph
    }

    fn cell(&self, v: u32) -> Xy {
        self.cells.get(v as usize).copied().unwrap_or((-1, -1))
    }

    fn add_vertex(&mut self, cell: Xy) -> u32 {
        self.cells.push(cell);
        self.parents.push(NONE);
        self.head.push(NONE);
        self.tail.push(NONE);
        (self.cells.len() - 1) as u32
    }

    /// Append `edge` to the out-list of `from` (ignored when `from` is not a vertex).
    fn push_edge(&mut self, from: u32, edge: Edge) {
        let Some(&last) = self.tail.get(from as usize) else {
            return;
        };
        let id = self.slots.len() as u32;
        self.slots.push(Slot { edge, next: NONE });
        let link = if last == NONE {
            self.head.get_mut(from as usize)
        } else {
            self.slots.get_mut(last as usize).map(|s| &mut s.next)
        };
        if let Some(link) = link {
            *link = id;
        }
        if let Some(t) = self.tail.get_mut(from as usize) {
            *t = id;
        }
    }

    /// The slots of the live out-edges of `v`, in insertion order.
    fn out_slots(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        let mut at = self.head.get(v as usize).copied().unwrap_or(NONE);
        std::iter::from_fn(move || {
            loop {
                let slot = self.slots.get(at as usize)?;
                let id = at;
                at = slot.next;
                if slot.edge.to != NONE {
                    return Some(id);
                }
            }
        })
    }

    /// The live out-edges of `v`, in insertion order.
    fn out(&self, v: u32) -> impl Iterator<Item = Edge> + '_ {
        self.out_slots(v)
            .filter_map(|id| self.slots.get(id as usize).map(|s| s.edge))
    }

    fn edge_mut(&mut self, from: u32, to: u32) -> Option<&mut Edge> {
        let id = self
            .out_slots(from)
            .find(|&id| self.slots.get(id as usize).is_some_and(|s| s.edge.to == to))?;
        self.slots.get_mut(id as usize).map(|s| &mut s.edge)
    }

    fn remove_edge(&mut self, from: u32, to: u32) {
        let mut at = self.head.get(from as usize).copied().unwrap_or(NONE);
        while let Some(slot) = self.slots.get_mut(at as usize) {
            if slot.edge.to == to {
                slot.edge.to = NONE;
            }
            at = slot.next;
        }
    }

    fn add_edge(&mut self, from: u32, to: u32) {
        self.push_edge(from, Edge { to, clear: true });
    }

    /// The tree path from the start to `v` (parent links).
    fn tree_path(&self, v: u32) -> Vec<u32> {
        let mut path = vec![v];
        let mut at = v;
        while let Some(&p) = self.parents.get(at as usize) {
            if p == NONE {
                break;
            }
            path.push(p);
            at = p;
        }
        path.reverse();
        path
    }

    /// Shortest path (Dijkstra, Euclidean lengths) from vertex 0 to a vertex at `goal`,
    /// over clear edges only or over all.
    fn shortest(&self, goal: Xy, clear_only: bool) -> Option<Vec<u32>> {
        let n = self.cells.len();
        let mut best = vec![f64::INFINITY; n];
        let mut parent = vec![NONE; n];
        let mut heap = BinaryHeap::new();
        *best.first_mut()? = 0.0;
        heap.push(HeapEntry { cost: 0.0, node: 0 });
        while let Some(HeapEntry { cost, node }) = heap.pop() {
            if cost > best.get(node as usize).copied().unwrap_or(f64::INFINITY) {
                continue;
            }
            let here = self.cell(node);
            if here == goal {
                let mut path = vec![node];
                let mut at = node;
                while let Some(&p) = parent.get(at as usize) {
                    if p == NONE {
                        break;
                    }
                    path.push(p);
                    at = p;
                }
                path.reverse();
                return Some(path);
            }
            for e in self.out(node) {
                if clear_only && !e.clear {
                    continue;
                }
                let c = cost + dist(here, self.cell(e.to));
                if let Some(slot) = best.get_mut(e.to as usize)
                    && c < *slot
                {
                    *slot = c;
                    if let Some(p) = parent.get_mut(e.to as usize) {
                        *p = node;
                    }
                    heap.push(HeapEntry {
                        cost: c,
                        node: e.to,
                    });
                }
            }
        }
        None
    }

    /// Shortest distance from every vertex to a vertex at `goal` over clear edges, and the
    /// next vertex on that way.
    fn to_goal(&self, goal: Xy) -> (Vec<f64>, Vec<u32>) {
        let n = self.cells.len();
        // The reversed clear edges in compressed rows: the sources of the edges into `v`
        // are `sources[offsets[v]..offsets[v + 1]]`, in order of source, then of out-list.
        let mut offsets = vec![0u32; n + 1];
        for from in 0..n as u32 {
            for e in self.out(from).filter(|e| e.clear) {
                if let Some(o) = offsets.get_mut(e.to as usize + 1) {
                    *o += 1;
                }
            }
        }
        for v in 1..=n {
            let before = offsets.get(v - 1).copied().unwrap_or(0);
            if let Some(o) = offsets.get_mut(v) {
                *o += before;
            }
        }
        let mut fill = offsets.clone();
        let mut sources = vec![NONE; offsets.last().copied().unwrap_or(0) as usize];
        for from in 0..n as u32 {
            for e in self.out(from).filter(|e| e.clear) {
                if let Some(f) = fill.get_mut(e.to as usize)
                    && let Some(slot) = sources.get_mut(*f as usize)
                {
                    *slot = from;
                    *f += 1;
                }
            }
        }
        let into = |v: u32| {
            let lo = offsets.get(v as usize).copied().unwrap_or(0) as usize;
            let hi = offsets.get(v as usize + 1).copied().unwrap_or(0) as usize;
            sources.get(lo..hi).unwrap_or(&[])
        };
        let mut best = vec![f64::INFINITY; n];
        let mut next = vec![NONE; n];
        let mut heap = BinaryHeap::new();
        for (v, &c) in self.cells.iter().enumerate() {
            if c == goal
                && let Some(slot) = best.get_mut(v)
            {
                *slot = 0.0;
                heap.push(HeapEntry {
                    cost: 0.0,
                    node: v as u32,
                });
            }
        }
        while let Some(HeapEntry { cost, node }) = heap.pop() {
            if cost > best.get(node as usize).copied().unwrap_or(f64::INFINITY) {
                continue;
            }
            let here = self.cell(node);
            for &from in into(node) {
                let c = cost + dist(here, self.cell(from));
                if let Some(slot) = best.get_mut(from as usize)
                    && c < *slot
                {
                    *slot = c;
                    if let Some(nx) = next.get_mut(from as usize) {
                        *nx = node;
                    }
                    heap.push(HeapEntry {
                        cost: c,
                        node: from,
                    });
                }
            }
        }
        (best, next)
    }
}

/// A min-heap entry (the heap is a max-heap, so the order is reversed).
#[derive(Clone, Copy, Debug)]
struct HeapEntry {
    cost: f64,
    node: u32,
}

impl PartialEq for HeapEntry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for HeapEntry {}

impl PartialOrd for HeapEntry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for HeapEntry {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .cost
            .total_cmp(&self.cost)
            .then_with(|| other.node.cmp(&self.node))
    }
}

/// The shortest `v_list` path whose segments are all clear: select, check, re-plan the
/// first blocked segment, repeat.
fn select(
    graph: &mut Graph,
    grid: &PassableGrid,
    goal: Xy,
    opts: &MbppOptions,
    depth: usize,
    stats: &mut MbppStats,
    counter: &mut LosCounter,
) -> Option<Vec<(usize, usize)>> {
    loop {
        let path = graph.shortest(goal, false)?;
        let mut blocked = None;
        for pair in path.windows(2) {
            let &[u, v] = pair else { continue };
            let (a, b) = (graph.cell(u), graph.cell(v));
            let Some(edge) = graph.edge_mut(u, v) else {
                continue;
            };
            if edge.clear {
                continue;
            }
            if grid.sight(a, b, counter) {
                edge.clear = true;
            } else {
                blocked = Some((u, v));
                break;
            }
        }
        let Some((u, v)) = blocked else {
            return Some(path.iter().map(|&v| to_u(graph.cell(v))).collect());
        };
        graph.remove_edge(u, v);
        stats.replans += 1;
        if depth < opts.max_replan_depth {
            let (a, b) = (graph.cell(u), graph.cell(v));
            let sub = run(grid, a, b, opts, depth + 1, stats, counter);
            if let Some(way) = sub.best {
                let mut from = u;
                let inner = way.get(1..way.len().saturating_sub(1)).unwrap_or(&[]);
                for &c in inner {
                    let w = graph.add_vertex(to_i(c));
                    graph.add_edge(from, w);
                    from = w;
                }
                graph.add_edge(from, v);
            }
        }
    }
}

/// The feasible paths besides the selected one: each goal-reaching bug's `v_list`, and each
/// waiting bug's `v_list` completed by the shortest clear continuation from its join.
fn alternatives(
    mut graph_clear: Graph,
    goals: &[u32],
    joins: &[Join],
    grid: &PassableGrid,
    counter: &mut LosCounter,
    selected: Option<&[(usize, usize)]>,
) -> Vec<Vec<(usize, usize)>> {
    // Decide the join segments not yet known.
    for join in joins {
        let from = join.vertex;
        let a = graph_clear.cell(from);
        let unknown: Vec<u32> = graph_clear
            .out(from)
            .filter(|e| !e.clear)
            .map(|e| e.to)
            .collect();
        for to in unknown {
            let b = graph_clear.cell(to);
            if grid.sight(a, b, counter) {
                if let Some(e) = graph_clear.edge_mut(from, to) {
                    e.clear = true;
                }
            } else {
                graph_clear.remove_edge(from, to);
            }
        }
    }
    let goal = goals.first().map(|&g| graph_clear.cell(g));
    let Some(goal) = goal else {
        return Vec::new();
    };
    let (to_goal, next) = graph_clear.to_goal(goal);
    let mut paths: Vec<Vec<(usize, usize)>> = Vec::new();
    for &g in goals {
        paths.push(
            graph_clear
                .tree_path(g)
                .iter()
                .map(|&v| to_u(graph_clear.cell(v)))
                .collect(),
        );
    }
    for join in joins {
        if !to_goal
            .get(join.vertex as usize)
            .is_some_and(|d| d.is_finite())
        {
            continue;
        }
        let mut ids = graph_clear.tree_path(join.vertex);
        let mut at = join.vertex;
        while let Some(&n) = next.get(at as usize) {
            if n == NONE || ids.len() > graph_clear.cells.len() {
                break;
            }
            ids.push(n);
            at = n;
        }
        paths.push(ids.iter().map(|&v| to_u(graph_clear.cell(v))).collect());
    }
    let mut keyed: Vec<(f64, Vec<(usize, usize)>)> =
        paths.into_iter().map(|p| (path_length(&p), p)).collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then_with(|| a.1.cmp(&b.1)));
    keyed.dedup_by(|a, b| a.1 == b.1);
    keyed
        .into_iter()
        .map(|(_, p)| p)
        .filter(|p| Some(p.as_slice()) != selected)
        .collect()
}
