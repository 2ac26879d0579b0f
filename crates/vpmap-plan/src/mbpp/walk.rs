//! The bugs' walk (see the module docs of [`super`], sections "States and moves" to
//! "`v_list` by line of sight"): the m-line, greedy steps, hits and births, wall
//! following with the hand rule, leaving, waiting, and the `v_list` tree they note.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use super::cells::{Xy, add, d2, passable, to_i, to_u};
use super::options::LeaveRule;
use crate::budget::{STOP_CHECK_INTERVAL, Stop, StopReason};
use crate::grid::CellXy;
use crate::los::{LosCounter, PassableGrid};
use crate::planned::{BugFate, BugTrack};

/// No vertex (or slot): the end of a parent chain or of an out-edge list, a removed edge.
pub(super) const NONE: u32 = u32::MAX;

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
pub fn m_line(start: impl Into<CellXy>, goal: impl Into<CellXy>) -> Vec<CellXy> {
    let line = MLine::new(to_i(start.into()), to_i(goal.into()));
    (0..=line.last).map(|k| to_u(line.cell(k))).collect()
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
    pub(super) fn new(start: Xy, goal: Xy) -> Self {
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

impl BugTrack {
    /// A bug's record at birth on `cell` (its track holds `cell` when `record`).
    pub(super) fn born(parent: Option<usize>, cell: Xy, record: bool, fate: BugFate) -> Self {
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

#[derive(Clone, Debug)]
pub(super) struct Bug {
    cell: Xy,
    anchor: u32,
    mode: Mode,
    pub(super) track: BugTrack,
}

/// A `v_list` state: a cell and the state before it (`NONE` for the start).
#[derive(Clone, Copy, Debug)]
pub(super) struct Vertex {
    pub(super) cell: Xy,
    pub(super) parent: u32,
}

/// Who first stood greedily on an m-line cell, with its anchor then, and whether that
/// anchor is the cell itself.
#[derive(Clone, Copy, Debug)]
pub(super) struct Owner {
    pub(super) anchor: u32,
    pub(super) at_cell: bool,
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
pub(super) struct Join {
    pub(super) vertex: u32,
    pub(super) owner: Owner,
}

/// The bugs and their shared `v_list` tree during the walk.
pub(super) struct Walk<'g> {
    grid: &'g PassableGrid,
    goal: Xy,
    line: MLine,
    leave: LeaveRule,
    owners: HashMap<Xy, Owner, BuildHasherDefault<CellHasher>>,
    pub(super) vertices: Vec<Vertex>,
    pub(super) bugs: Vec<Bug>,
    born: Vec<usize>,
    pub(super) joins: Vec<Join>,
    pub(super) goals: Vec<u32>,
    record: bool,
    pub(super) steps: usize,
    pub(super) hits: usize,
}

impl<'g> Walk<'g> {
    pub(super) fn new(
        grid: &'g PassableGrid,
        start: Xy,
        goal: Xy,
        record: bool,
        leave: LeaveRule,
    ) -> Self {
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
    /// bug is left to move ([`WalkEnd::Done`]), until the walk has taken `max_steps` steps
    /// ([`WalkEnd::Budget`]), until `counter` has looked up more than `max_sight_cells`
    /// cells ([`WalkEnd::SightBudget`]), or until `stop` says so ([`WalkEnd::Stopped`], looked at about
    /// every [`STOP_CHECK_INTERVAL`] steps).
    pub(super) fn run(
        &mut self,
        counter: &mut LosCounter,
        (max_steps, max_sight_cells): (usize, usize),
        stop: &Stop,
    ) -> WalkEnd {
        let mut live: Vec<usize> = vec![0];
        let mut next = Vec::new();
        let mut next_stop_check = self.steps + STOP_CHECK_INTERVAL;
        while !live.is_empty() {
            if self.steps > max_steps {
                return WalkEnd::Budget;
            }
            if counter.cells > max_sight_cells {
                return WalkEnd::SightBudget;
            }
            if self.steps >= next_stop_check {
                next_stop_check = self.steps + STOP_CHECK_INTERVAL;
                if let Some(reason) = stop.reason() {
                    return WalkEnd::Stopped(reason);
                }
            }
            for &b in &live {
                if self.step(b, counter) {
                    next.push(b);
                }
            }
            next.append(&mut self.born);
            std::mem::swap(&mut live, &mut next);
            next.clear();
        }
        WalkEnd::Done
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

/// How [`Walk::run`] ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum WalkEnd {
    /// No bug is left to move.
    Done,
    /// The step budget ran out.
    Budget,
    /// The line-of-sight budget ran out.
    SightBudget,
    /// The [`Stop`] said so.
    Stopped(StopReason),
}
