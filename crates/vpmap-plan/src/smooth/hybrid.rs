//! The complete fallback and the benchmark's reference: Hybrid-A* (Dolgov, Thrun,
//! Montemerlo and Diebel 2008; the planner of Nav2's Smac Hybrid-A*).
//!
//! States are continuous poses; two poses are the same search state when they share a cell
//! and one of [`HybridOptions::headings`] heading bins, and the cheaper one is kept.
//! A state expands by three motion primitives (left arc of radius `R`, straight, right
//! arc) of one length `l`, forward, and in reverse too when allowed: `l` turns the heading
//! by the smallest whole number of bins that makes it at least `sqrt(2)` cells long, so
//! every successor leaves its cell. Costs are path lengths (no penalties: the reference is
//! for length). Every primitive is tested exactly for collision by [`Field`].
//!
//! The heuristic is the larger of the obstacle-free Dubins distance to the goal pose (the
//! Reeds-Shepp distance when reverse is allowed: the Dubins one would overestimate; the
//! Euclidean distance for a free goal heading) and an obstacle-aware bound: the
//! 8-connected octile distance from the goal over free cells, computed by a Dijkstra
//! search that runs only as far as the queried cells need, divided by the largest ratio of
//! octile to Euclidean length (`(sqrt 2 - 1) ... 1.0824`) and less 1.5 cells (states are
//! not at cell centres).
//!
//! **Analytic expansion**: every [`HybridOptions::shot_every`] expansions, and at every
//! expansion within `6 R` of the goal, the Dubins words (or the free-heading paths) to the
//! goal are tried, shortest first, and with reverse allowed the Reeds-Shepp words too
//! ([`super::connect`]); the first clear one ends the search. The goal is only reached
//! this way, so the path ends exactly at the goal pose.
//!
//! Every expanded state and every state pushed on the open list counts against
//! [`Budget::max_expansions`]; at most [`MAX_STATES`] states are kept.
//!
//! # References
//! D. Dolgov, S. Thrun, M. Montemerlo, J. Diebel, "Practical Search Techniques in Path
//! Planning for Autonomous Driving", STAIR 2008.

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};
use std::f64::consts::{SQRT_2, TAU};

use super::clearance::Field;
use super::connect;
use super::curve::{Gear, Pose, Segment, SmoothCurve};
use super::dubins::{free_end_candidates, word_tables_to_headings};
use crate::budget::{Budget, STOP_CHECK_INTERVAL, Stop};
use crate::error::{PlanError, Result};

/// Most search states the Hybrid-A* keeps (about 100 bytes each).
pub const MAX_STATES: usize = 8_000_000;

/// Largest ratio of an octile grid distance to the Euclidean one: `sqrt(4 - 2 sqrt 2)`.
const OCTILE_OVER_EUCLID: f64 = 1.082_392_200_292_394;

/// The planner's name in errors.
const PLANNER: &str = "the smooth planner's Hybrid-A*";

/// Settings of the Hybrid-A*.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HybridOptions {
    /// Heading bins (default 72: 5 degrees).
    pub headings: usize,
    /// Expansions between analytic expansion attempts far from the goal (default 20).
    pub shot_every: usize,
}

impl Default for HybridOptions {
    fn default() -> Self {
        Self {
            headings: 72,
            shot_every: 20,
        }
    }
}

/// What the Hybrid-A* did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HybridStats {
    /// States expanded.
    pub expanded: usize,
    /// States pushed on the open list.
    pub generated: usize,
    /// Cells settled by the heuristic's Dijkstra search.
    pub heuristic_cells: usize,
    /// Analytic expansions tried.
    pub shots: usize,
    /// Whether some primitive left the start at all (for the "no room" reason).
    pub start_moved: bool,
}

/// One search state.
#[derive(Clone, Copy, Debug)]
struct Node {
    pose: Pose,
    parent: u32,
    /// The primitive that reached it (its length is 0 for a start state).
    seg: Segment,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Open {
    f: f64,
    g: f64,
    node: u32,
}

impl Eq for Open {}
impl Ord for Open {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .f
            .total_cmp(&self.f)
            .then_with(|| self.g.total_cmp(&other.g))
    }
}
impl PartialOrd for Open {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The obstacle-aware part of the heuristic: a Dijkstra search from the goal cell over
/// free cells, 8-connected with octile costs and no corner cutting, run on demand.
struct GridHeuristic<'a> {
    field: &'a Field,
    /// Looked at every [`STOP_CHECK_INTERVAL`] settled cells: a search that settles the
    /// whole grid stops with the planner (the next expansion's check returns the error).
    stop: &'a Stop,
    dist: Vec<f32>,
    settled: Vec<bool>,
    heap: BinaryHeap<(std::cmp::Reverse<u64>, u32)>,
    settled_count: usize,
}

impl<'a> GridHeuristic<'a> {
    fn new(field: &'a Field, goal: (i64, i64), stop: &'a Stop) -> Self {
        let (w, h) = field.size();
        let mut dist = vec![f32::INFINITY; w * h];
        let mut heap = BinaryHeap::new();
        if !field.blocked(goal.0, goal.1) {
            let i = goal.1 as usize * w + goal.0 as usize;
            if let Some(d) = dist.get_mut(i) {
                *d = 0.0;
                heap.push((std::cmp::Reverse(0), i as u32));
            }
        }
        Self {
            field,
            stop,
            dist,
            settled: vec![false; w * h],
            heap,
            settled_count: 0,
        }
    }

    /// The octile distance of `(x, y)` from the goal (infinite when unreachable).
    fn octile(&mut self, x: i64, y: i64) -> f64 {
        let (w, h) = self.field.size();
        if x < 0 || y < 0 || x >= w as i64 || y >= h as i64 {
            return f64::INFINITY;
        }
        let target = y as usize * w + x as usize;
        while !self.settled.get(target).copied().unwrap_or(true) {
            if self.settled_count.is_multiple_of(STOP_CHECK_INTERVAL)
                && self.stop.check(PLANNER).is_err()
            {
                return f64::INFINITY;
            }
            let Some((_, i)) = self.heap.pop() else {
                break;
            };
            let i = i as usize;
            match self.settled.get_mut(i) {
                Some(s) if !*s => *s = true,
                _ => continue,
            }
            self.settled_count += 1;
            let di = f64::from(self.dist.get(i).copied().unwrap_or(f32::INFINITY));
            let (cx, cy) = ((i % w) as i64, (i / w) as i64);
            for (dx, dy) in [
                (1, 0),
                (-1, 0),
                (0, 1),
                (0, -1),
                (1, 1),
                (1, -1),
                (-1, 1),
                (-1, -1),
            ] {
                let (nx, ny) = (cx + dx, cy + dy);
                if self.field.blocked(nx, ny)
                    || (dx != 0
                        && dy != 0
                        && (self.field.blocked(cx + dx, cy) || self.field.blocked(cx, cy + dy)))
                {
                    continue;
                }
                let j = ny as usize * w + nx as usize;
                let step = if dx != 0 && dy != 0 { SQRT_2 } else { 1.0 };
                let nd = di + step;
                if let Some(d) = self.dist.get_mut(j)
                    && nd < f64::from(*d)
                {
                    *d = nd as f32;
                    // Distances are below 2^32 / 1024 cells: keys in fixed point.
                    self.heap
                        .push((std::cmp::Reverse((nd * 1024.0) as u64), j as u32));
                }
            }
        }
        if self.settled.get(target).copied().unwrap_or(false) {
            f64::from(self.dist.get(target).copied().unwrap_or(f32::INFINITY))
        } else {
            f64::INFINITY
        }
    }
}

/// Search inputs of [`hybrid_astar`].
#[derive(Clone, Copy, Debug)]
pub struct HybridQuery {
    /// Start pose (heading ignored when `start_free`).
    pub start: Pose,
    /// Whether the start heading is free.
    pub start_free: bool,
    /// Goal pose (heading ignored when `goal_free`).
    pub goal: Pose,
    /// Whether the goal heading is free.
    pub goal_free: bool,
    /// Turning radius, cells.
    pub radius: f64,
    /// Whether reverse primitives are allowed.
    pub reverse: bool,
}

/// A clear curvature-bounded path by Hybrid-A* (see the [module docs](self)), or `None`
/// when the search space is exhausted.
///
/// # Errors
/// [`PlanError::BudgetExhausted`] past [`Budget::max_expansions`] states or
/// [`MAX_STATES`] kept, [`PlanError::Stopped`] by the budget's stop.
pub fn hybrid_astar(
    field: &Field,
    q: &HybridQuery,
    opts: &HybridOptions,
    budget: &Budget,
    stats: &mut HybridStats,
) -> Result<Option<SmoothCurve>> {
    let bins = opts.headings.max(4);
    let bin_rad = TAU / bins as f64;
    let r = q.radius;
    let steps = (SQRT_2 / (r * bin_rad)).ceil().max(1.0);
    let prim_len = r * bin_rad * steps;
    let (w, h) = field.size();
    let key = |p: &Pose| -> Option<u64> {
        let (cx, cy) = (p.x.round(), p.y.round());
        if !(cx >= 0.0 && cy >= 0.0 && cx < w as f64 && cy < h as f64) {
            return None;
        }
        let bin = ((p.heading_rad.rem_euclid(TAU) / bin_rad).round() as usize) % bins;
        Some(((cy as u64) * w as u64 + cx as u64) * bins as u64 + bin as u64)
    };
    let mut grid_h = GridHeuristic::new(
        field,
        (q.goal.x.round() as i64, q.goal.y.round() as i64),
        &budget.stop,
    );
    let heuristic = |p: &Pose, grid_h: &mut GridHeuristic<'_>| -> f64 {
        let free = p.distance(&q.goal);
        let pose_h = if q.goal_free {
            free
        } else {
            connect::distance(*p, q.goal, r, q.reverse)
        };
        let oct = grid_h.octile(p.x.round() as i64, p.y.round() as i64);
        let grid_bound = if oct.is_finite() {
            oct / OCTILE_OVER_EUCLID - 1.5
        } else {
            f64::INFINITY
        };
        pose_h.max(grid_bound)
    };
    let mut nodes: Vec<Node> = Vec::new();
    let mut best: HashMap<u64, (f64, u32, bool)> = HashMap::new();
    let mut open = BinaryHeap::new();
    let starts: Vec<f64> = if q.start_free {
        (0..bins).map(|k| k as f64 * bin_rad).collect()
    } else {
        vec![q.start.heading_rad]
    };
    for hd in starts {
        let pose = Pose::new(q.start.x, q.start.y, hd);
        let Some(k) = key(&pose) else { continue };
        let idx = nodes.len() as u32;
        nodes.push(Node {
            pose,
            parent: idx,
            seg: Segment {
                start: pose,
                curvature: 0.0,
                length: 0.0,
                gear: Gear::Forward,
            },
        });
        best.insert(k, (0.0, idx, false));
        let f = heuristic(&pose, &mut grid_h);
        open.push(Open {
            f,
            g: 0.0,
            node: idx,
        });
        stats.generated += 1;
    }
    let gears: &[Gear] = if q.reverse {
        &[Gear::Forward, Gear::Reverse]
    } else {
        &[Gear::Forward]
    };
    while let Some(Open { node, g, .. }) = open.pop() {
        let Some(&cur) = nodes.get(node as usize) else {
            continue;
        };
        let Some(k) = key(&cur.pose) else { continue };
        match best.get_mut(&k) {
            Some(entry) if entry.1 == node && !entry.2 => entry.2 = true,
            _ => continue,
        }
        stats.expanded += 1;
        stats.heuristic_cells = grid_h.settled_count;
        // The stop is looked at on every expansion (tick 0), not every few thousand as in the
        // grid planners: one expansion drives its motion primitives and may shoot a Dubins
        // curve, milliseconds at a large turning radius, so thousands of them overran the
        // page's 3 s by seconds. Reading the clock costs tens of nanoseconds.
        budget.check(
            PLANNER,
            stats.expanded + stats.generated + grid_h.settled_count,
            0,
            0,
        )?;
        // Analytic expansion.
        let near = cur.pose.distance(&q.goal) < 6.0 * r;
        if near || stats.expanded % opts.shot_every.max(1) == 1 {
            stats.shots += 1;
            if let Some(shot) = analytic_shot(field, cur.pose, q) {
                let mut chain = Vec::new();
                let mut i = node as usize;
                while let Some(n) = nodes.get(i) {
                    if n.parent as usize == i {
                        break;
                    }
                    chain.push(n.seg);
                    i = n.parent as usize;
                }
                let mut curve = SmoothCurve::default();
                for s in chain.into_iter().rev() {
                    curve.push(s);
                }
                curve.extend(&shot);
                return Ok(Some(curve));
            }
        }
        for &gear in gears {
            for curvature in [1.0 / r, 0.0, -1.0 / r] {
                let seg = Segment {
                    start: cur.pose,
                    curvature,
                    length: prim_len,
                    gear,
                };
                let end = seg.end();
                let Some(nk) = key(&end) else { continue };
                let ng = g + prim_len;
                if let Some(&(bg, _, _)) = best.get(&nk)
                    && bg <= ng
                {
                    continue;
                }
                if !field.segment_clear(&seg) {
                    continue;
                }
                if cur.parent == node {
                    stats.start_moved = true;
                }
                let hv = heuristic(&end, &mut grid_h);
                if !hv.is_finite() {
                    continue;
                }
                if nodes.len() >= MAX_STATES {
                    return Err(PlanError::BudgetExhausted {
                        planner: PLANNER,
                        what: "search states kept",
                        limit: MAX_STATES,
                        option: "max_expansions",
                    });
                }
                let idx = nodes.len() as u32;
                nodes.push(Node {
                    pose: end,
                    parent: node,
                    seg,
                });
                best.insert(nk, (ng, idx, false));
                open.push(Open {
                    f: ng + hv,
                    g: ng,
                    node: idx,
                });
                stats.generated += 1;
            }
        }
    }
    stats.heuristic_cells = grid_h.settled_count;
    // A heuristic cut short by the stop made states look unreachable: not a proof of no path.
    budget.stop.check(PLANNER)?;
    Ok(None)
}

/// The first clear obstacle-free path from `from` to the goal, shortest first: the six
/// Dubins words (and with reverse the Reeds-Shepp ones) to a fixed goal heading, or to the
/// goal point at the candidate free headings.
fn analytic_shot(field: &Field, from: Pose, q: &HybridQuery) -> Option<SmoothCurve> {
    let headings: Vec<f64> = if q.goal_free {
        free_end_candidates(from, q.goal.x, q.goal.y, q.radius)
    } else {
        vec![q.goal.heading_rad]
    };
    let mut words: Vec<(f64, usize, usize)> = Vec::new();
    if q.reverse {
        for (gi, &h) in headings.iter().enumerate() {
            let g = Pose::new(q.goal.x, q.goal.y, h);
            for (wi, l) in connect::table(from, g, q.radius, true)
                .into_iter()
                .enumerate()
            {
                if l.is_finite() {
                    words.push((l, gi, wi));
                }
            }
        }
    } else {
        // The Dubins words only: their tables to every heading at once.
        let tables = word_tables_to_headings(from, q.goal.x, q.goal.y, &headings, q.radius);
        for (gi, t) in tables.iter().enumerate() {
            for (wi, &l) in t.iter().enumerate() {
                if l.is_finite() {
                    words.push((l, gi, wi));
                }
            }
        }
    }
    // A free goal heading offers hundreds of words: the shortest few decide. Ties are broken
    // by heading and word index (the order they were listed), as a stable sort would.
    let key = |a: &(f64, usize, usize), b: &(f64, usize, usize)| {
        a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2))
    };
    if words.len() > SHOTS_TRIED {
        words.select_nth_unstable_by(SHOTS_TRIED, key);
        words.truncate(SHOTS_TRIED);
    }
    words.sort_unstable_by(key);
    for &(_, gi, wi) in &words {
        let goal = Pose::new(q.goal.x, q.goal.y, *headings.get(gi)?);
        if let Some(c) = connect::curve(from, goal, q.radius, wi)
            && field.curve_clear(&c)
        {
            return Some(c);
        }
    }
    None
}

/// How many of the shortest words an analytic expansion tests for collision.
const SHOTS_TRIED: usize = 12;
