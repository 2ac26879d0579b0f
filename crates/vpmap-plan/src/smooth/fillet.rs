//! The fast method: Dubins paths through the corners of the exact any-angle path, with
//! feasibility repair by a lazy shortest path over a small layered graph.
//!
//! The taut (shortest any-angle) path bends only around convex obstacle corners, at cell
//! centres where a blocked cell's square touches it. A curvature-bounded path that hugs
//! such a corner passes through the vertex tangentially on an arc of radius `R` whose
//! centre lies inside the turn: near the vertex it stays on the free side of the blocked
//! quadrant for turns up to 180 degrees. So each corner becomes a **layer** of candidate
//! poses at the vertex: the bisector of the incoming and outgoing legs, headings offset
//! from it by [`HEADING_OFFSETS_DEG`], the two legs' directions (a path through a gap one
//! cell wide must run exactly along the leg), and poses moved outward from the vertex by
//! [`OUTWARD_OFFSETS_R`] turning radii (to swing wide of a tight corner). The start and
//! the goal are layers of one pose, or of [`FREE_HEADINGS`] headings plus the leg's
//! direction when their heading is free; a fixed-heading end also gets a layer of escape
//! poses beside it (one arc of 45 to 270 degrees or one line of `R` or `2 R` away), through
//! which the path may first turn away from what the end faces.
//!
//! With reverse allowed, a corner's layer also holds the bisector's and the legs' poses
//! turned by 180 degrees (the robot backing through the corner), and the escape poses are
//! also those reached in reverse.
//!
//! An edge joins a pose of layer `i` to a pose of layer `j` for `i < j <= i + LOOKAHEAD`
//! (skipping a corner lets the path swing wide of a tight cluster of corners) and costs its
//! shortest word whose curve is clear, the words tried shortest first: the Dubins words,
//! and with reverse also the Reeds-Shepp words ([`connect`]). The search
//! is **lazy**: the shortest path over the layers is found with every edge at its shortest
//! untested word, the edges on it are then tested (exactly, by [`Field`]), a blocked word
//! is replaced by the edge's next one, and the search repeats until its path is clear or
//! [`MAX_ROUNDS`] rounds have passed or [`MAX_WORDS_TESTED`] words have been tested.
//!
//! # Complexity
//! `O(corners x LOOKAHEAD x K^2)` word tables per round (`K` poses a layer, each table six
//! closed forms, 50 with reverse), plus the collision tests of the edges on the rounds' paths.

use std::f64::consts::TAU;

use super::clearance::Field;
use super::connect::{self, MAX_WORDS};
use super::curve::{Pose, SmoothCurve, pose_along};
use crate::grid::CellXy;

/// Heading offsets from a corner's bisector tried as candidate poses, degrees.
pub const HEADING_OFFSETS_DEG: [f64; 11] = [
    0.0, -4.0, 4.0, -8.0, 8.0, -15.0, 15.0, -25.0, 25.0, -40.0, 40.0,
];

/// Distances (in turning radii) by which a corner's pose may also move away from the
/// obstacle it wraps, along the outward normal of the bisector, to swing wide of it.
pub const OUTWARD_OFFSETS_R: [f64; 2] = [0.35, 1.0];

/// Heading offsets from the bisector of the outward-moved poses, degrees.
pub const OUTWARD_HEADINGS_DEG: [f64; 3] = [0.0, -15.0, 15.0];

/// Evenly spaced headings tried at a free start or goal (besides the leg's direction).
pub const FREE_HEADINGS: usize = 24;

/// How many layers ahead an edge may reach (1: corner to next corner only).
pub const LOOKAHEAD: usize = 3;

/// Most rounds of the lazy search before it gives up (and the fallback takes over).
pub const MAX_ROUNDS: usize = 4000;

/// Most Dubins words the lazy search tests for collision before it gives up.
pub const MAX_WORDS_TESTED: usize = 5000;

/// What the fillet search did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FilletStats {
    /// Lazy search rounds.
    pub rounds: usize,
    /// Dubins words tested for collision.
    pub words_tested: usize,
}

/// An edge's state: its shortest word not yet found blocked (index into
/// [`connect::table`] and length), the words found blocked (a bit each), and whether the
/// current word is known to be clear. The table is recomputed when a word is blocked
/// rather than stored: it is a few closed forms, and 50 lengths an edge would not fit the
/// dense edge table.
#[derive(Clone, Copy, Debug)]
struct Edge {
    word: usize,
    length: f64,
    blocked: u64,
    clear: bool,
}

// Every word has a bit in `Edge::blocked`.
const _: () = assert!(MAX_WORDS <= 64);

impl Edge {
    fn new(pa: Pose, pb: Pose, radius: f64, reverse: bool) -> Self {
        let mut e = Self {
            word: 0,
            length: f64::INFINITY,
            blocked: 0,
            clear: false,
        };
        e.pick(pa, pb, radius, reverse);
        e
    }

    /// The shortest word not blocked (the first of equal ones).
    fn pick(&mut self, pa: Pose, pb: Pose, radius: f64, reverse: bool) {
        let (word, length) = connect::table(pa, pb, radius, reverse)
            .iter()
            .copied()
            .enumerate()
            .filter(|&(i, _)| self.blocked & (1 << i) == 0)
            .fold(
                (0, f64::INFINITY),
                |b, (i, l)| if l < b.1 { (i, l) } else { b },
            );
        (self.word, self.length) = (word, length);
    }

    fn best(&self) -> (usize, f64) {
        (self.word, self.length)
    }

    /// Mark the current word blocked and pick the next.
    fn block(&mut self, pa: Pose, pb: Pose, radius: f64, reverse: bool) {
        self.blocked |= 1 << self.word;
        self.pick(pa, pb, radius, reverse);
    }
}

/// The candidate poses of every layer.
fn layers(
    waypoints: &[CellXy],
    (start, start_free, goal, goal_free): (Pose, bool, Pose, bool),
    radius: f64,
    reverse: bool,
) -> Vec<Vec<Pose>> {
    let pts: Vec<(f64, f64)> = waypoints.iter().map(|c| (c.x as f64, c.y as f64)).collect();
    let dir = |a: (f64, f64), b: (f64, f64)| (b.1 - a.1).atan2(b.0 - a.0);
    let free = |p: (f64, f64), leg: f64| {
        let mut v = vec![Pose::new(p.0, p.1, leg)];
        for k in 0..FREE_HEADINGS {
            v.push(Pose::new(
                p.0,
                p.1,
                leg + TAU * k as f64 / FREE_HEADINGS as f64,
            ));
        }
        v
    };
    let n = pts.len();
    let mut out = Vec::with_capacity(n);
    for (i, &p) in pts.iter().enumerate() {
        if i == 0 {
            let leg = pts.get(1).map_or(start.heading_rad, |&q| dir(p, q));
            if start_free {
                out.push(free(p, leg));
            } else {
                out.push(vec![start]);
                out.push(escapes(start, radius, 1.0, reverse));
            }
        } else if i + 1 == n {
            let leg = pts.get(i - 1).map_or(goal.heading_rad, |&q| dir(q, p));
            if goal_free {
                out.push(free(p, leg));
            } else {
                out.push(escapes(goal, radius, -1.0, reverse));
                out.push(vec![goal]);
            }
        } else if let (Some(&a), Some(&b)) = (pts.get(i - 1), pts.get(i + 1)) {
            let (h_in, h_out) = (dir(a, p), dir(p, b));
            let turn = (h_out - h_in + std::f64::consts::PI).rem_euclid(TAU) - std::f64::consts::PI;
            let bisector = h_in + turn / 2.0;
            let mut poses: Vec<Pose> = HEADING_OFFSETS_DEG
                .iter()
                .map(|d| Pose::new(p.0, p.1, bisector + d.to_radians()))
                .collect();
            // The legs' own directions: a path through a gap one cell wide must run
            // exactly along the leg through it.
            poses.push(Pose::new(p.0, p.1, h_in));
            poses.push(Pose::new(p.0, p.1, h_out));
            // Backing through the corner: the same directions of travel, the robot facing
            // the other way.
            if reverse {
                for h in [bisector, h_in, h_out] {
                    poses.push(Pose::new(p.0, p.1, h + std::f64::consts::PI));
                }
            }
            // Outward: to the right of the bisector for a left turn, and back.
            let side = if turn > 0.0 { -1.0 } else { 1.0 };
            let normal = (bisector + side * std::f64::consts::FRAC_PI_2).sin_cos();
            for k in OUTWARD_OFFSETS_R {
                let (x, y) = (p.0 + k * radius * normal.1, p.1 + k * radius * normal.0);
                for d in OUTWARD_HEADINGS_DEG {
                    poses.push(Pose::new(x, y, bisector + d.to_radians()));
                }
            }
            out.push(poses);
        }
    }
    out
}

/// Turn angles of the escape poses, degrees.
const ESCAPE_TURNS_DEG: [f64; 4] = [45.0, 90.0, 180.0, 270.0];

/// Poses one arc (left or right, by [`ESCAPE_TURNS_DEG`]) or one straight line (`R`, `2 R`)
/// away from a fixed-heading end: after it (`direction` 1, the start) or before it (-1, the
/// goal); with `reverse` also those driven in reverse. They let the path first turn away
/// from an obstacle the end faces, a manoeuvre one Dubins word cannot make.
fn escapes(end: Pose, radius: f64, direction: f64, reverse: bool) -> Vec<Pose> {
    let mut v = Vec::new();
    let gears: &[f64] = if reverse { &[1.0, -1.0] } else { &[1.0] };
    for &gear in gears {
        let direction = direction * gear;
        for curvature in [1.0 / radius, -1.0 / radius] {
            for t in ESCAPE_TURNS_DEG {
                v.push(pose_along(
                    end,
                    curvature,
                    direction * t.to_radians() * radius,
                ));
            }
        }
        for l in [radius, 2.0 * radius] {
            v.push(pose_along(end, 0.0, direction * l));
        }
    }
    v
}

/// A clear curvature-bounded path from `start` to `goal` along the taut path `waypoints`
/// (from the start's cell to the goal's), or `None` when the lazy search finds none
/// within [`MAX_ROUNDS`] rounds (see the [module docs](self)). With `reverse`, an edge's
/// words are the Reeds-Shepp candidates besides the Dubins words ([`connect`]), so the
/// path may back up (cusps) between two corners.
#[must_use]
pub fn fillet(
    field: &Field,
    waypoints: &[CellXy],
    ends: (Pose, bool, Pose, bool),
    radius: f64,
    reverse: bool,
    stats: &mut FilletStats,
) -> Option<SmoothCurve> {
    if waypoints.len() < 2 {
        return None;
    }
    let layers = layers(waypoints, ends, radius, reverse);
    let n = layers.len();
    // Edges in one dense table, each made when first relaxed: (i, a, j - i - 1, b).
    let k_max = layers.iter().map(Vec::len).max().unwrap_or(0);
    let slot = |(i, a, j, b): (usize, usize, usize, usize)| {
        ((i * k_max + a) * LOOKAHEAD + (j - i - 1)) * k_max + b
    };
    let mut edges: Vec<Option<Edge>> = vec![None; n * k_max * LOOKAHEAD * k_max];
    let mut dist: Vec<Vec<f64>> = layers
        .iter()
        .map(|l| vec![f64::INFINITY; l.len()])
        .collect();
    let mut back: Vec<Vec<Option<(usize, usize)>>> =
        layers.iter().map(|l| vec![None; l.len()]).collect();
    if let Some(d0) = dist.first_mut() {
        d0.fill(0.0);
    }
    // Layers before `from` keep their distances: edges only go forward, so dropping a word
    // of an edge into layer `j` changes nothing before `j`.
    let mut from = 1;
    for _ in 0..MAX_ROUNDS {
        if stats.words_tested > MAX_WORDS_TESTED {
            return None;
        }
        stats.rounds += 1;
        // Shortest path over the layers with every edge at its current shortest word.
        for j in from..n {
            let Some(lj) = layers.get(j) else { continue };
            for (b, &pb) in lj.iter().enumerate() {
                let mut best = (f64::INFINITY, None);
                for i in j.saturating_sub(LOOKAHEAD)..j {
                    let Some(li) = layers.get(i) else { continue };
                    for (a, &pa) in li.iter().enumerate() {
                        let da = dist
                            .get(i)
                            .and_then(|d| d.get(a))
                            .copied()
                            .unwrap_or(f64::INFINITY);
                        if !da.is_finite() {
                            continue;
                        }
                        let Some(entry) = edges.get_mut(slot((i, a, j, b))) else {
                            continue;
                        };
                        let edge = entry.get_or_insert_with(|| Edge::new(pa, pb, radius, reverse));
                        let cand = da + edge.best().1;
                        if cand < best.0 {
                            best = (cand, Some((i, a)));
                        }
                    }
                }
                if let (Some(d), Some(bk)) = (
                    dist.get_mut(j).and_then(|d| d.get_mut(b)),
                    back.get_mut(j).and_then(|v| v.get_mut(b)),
                ) {
                    (*d, *bk) = best;
                }
            }
        }
        from = n;
        // The best end pose, then the chain of edges back to the start.
        let last = dist.last()?;
        let (mut b, best) =
            last.iter()
                .copied()
                .enumerate()
                .fold(
                    (0, f64::INFINITY),
                    |acc, (i, d)| if d < acc.1 { (i, d) } else { acc },
                );
        if !best.is_finite() {
            return None;
        }
        let mut chain = Vec::new();
        let mut j = n - 1;
        while let Some(Some((i, a))) = back.get(j).and_then(|v| v.get(b)).copied() {
            chain.push((i, a, j, b));
            (j, b) = (i, a);
        }
        chain.reverse();
        // Test the edges not yet known clear; a blocked word is dropped from its edge.
        let mut all_clear = true;
        for key in &chain {
            let Some(Some(edge)) = edges.get_mut(slot(*key)) else {
                return None;
            };
            if edge.clear {
                continue;
            }
            let (pa, pb) = pose_pair(&layers, *key)?;
            let (w, _) = edge.best();
            stats.words_tested += 1;
            let ok = connect::curve(pa, pb, radius, w).is_some_and(|c| field.curve_clear(&c));
            if ok {
                edge.clear = true;
            } else {
                edge.block(pa, pb, radius, reverse);
                from = from.min(key.2);
                all_clear = false;
            }
        }
        if all_clear {
            let mut curve = SmoothCurve::default();
            for key in &chain {
                let (pa, pb) = pose_pair(&layers, *key)?;
                let (w, _) = edges.get(slot(*key))?.as_ref()?.best();
                curve.extend(&connect::curve(pa, pb, radius, w)?);
            }
            return Some(curve);
        }
    }
    None
}

fn pose_pair(
    layers: &[Vec<Pose>],
    (i, a, j, b): (usize, usize, usize, usize),
) -> Option<(Pose, Pose)> {
    Some((*layers.get(i)?.get(a)?, *layers.get(j)?.get(b)?))
}
