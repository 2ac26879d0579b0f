//! Polishing a found path (issue 41's "no wobble" target): two passes over the poses where
//! its segments meet, each keeping the path clear and never making it longer.
//!
//! 1. **Shortcut.** From each kept pose, the farthest later pose (found by doubling the
//!    step, then halving it) whose shortest words ([`connect`]) are clear and no longer than
//!    the path between the two is joined to it directly, and the poses between are dropped
//!    (the Dubins analogue of A* post-smoothing). This removes the heading-bin zigzags of a
//!    Hybrid-A* path, whose primitives turn left and right by whole bins.
//! 2. **Headings.** Each kept pose whose heading is free (every pose between the ends, and
//!    an end whose heading was not asked) turns, by golden-section search within
//!    [`HEADING_WINDOW_DEG`] of its heading, to the heading that makes the distances (the
//!    shortest words) from the previous pose and to the next one shortest. The fillet's
//!    candidate headings are a discrete set, so its chosen pose is usually a little off the
//!    best one, and the words on either side then start or end with a sliver of an arc
//!    turning the other way (0.002-0.05 cells long in the benchmark's wobbly paths): a
//!    curvature sign change that steers nowhere. At the best heading that sliver shrinks to
//!    the search's round-off, and arcs shorter than [`SLIVER_CELLS`] are then left out
//!    (their ends are that close, far inside the validator's 1e-6).
//!
//! A change is kept only when the new words are tested clear by [`Field`], have no more
//! cusps than what they replace, and the whole is no longer and has no more cusps; the caller validates the result and keeps the unpolished path if it fails.
//!
//! # Complexity
//! `O(n log n)` word tables and collision tests for the shortcut over `n` segments, then
//! [`HEADING_PASSES`] x `n` golden-section searches of [`GOLDEN_STEPS`] word tables each.

use super::clearance::Field;
use super::connect;
use super::curve::{Pose, SmoothCurve};

/// Half-width of the heading search around a pose's heading, degrees.
pub const HEADING_WINDOW_DEG: f64 = 10.0;

/// Golden-section steps of the heading search (the window shrinks to about 1e-13 rad).
pub const GOLDEN_STEPS: usize = 70;

/// Passes of the heading search over the poses.
pub const HEADING_PASSES: usize = 2;

/// Segments shorter than this (cells) are left out of the polished path.
pub const SLIVER_CELLS: f64 = 1e-9;

/// A pose's new words may be this much longer (cells, round-off) than its old ones.
const TIE_CELLS: f64 = 1e-12;

/// Most words tried for one connection, shortest first.
const WORDS_TRIED: usize = 3;

/// A path as poses joined by words (index into [`connect::table`]) of known length.
struct Chain {
    poses: Vec<Pose>,
    /// `words[i]` joins `poses[i]` to `poses[i + 1]`: (word, length).
    words: Vec<(usize, f64)>,
}

/// The shortest clear word from `a` to `b` no longer than `limit` and with at most
/// `max_cusps` cusps, trying at most [`WORDS_TRIED`] words.
fn clear_word(
    field: &Field,
    (a, b): (Pose, Pose),
    radius: f64,
    reverse: bool,
    (limit, max_cusps): (f64, usize),
) -> Option<(usize, f64)> {
    let table = connect::table(a, b, radius, reverse);
    let mut order: Vec<(usize, f64)> = table
        .iter()
        .copied()
        .enumerate()
        .filter(|&(_, l)| l.is_finite() && l <= limit)
        .collect();
    order.sort_by(|x, y| x.1.total_cmp(&y.1));
    order.into_iter().take(WORDS_TRIED).find(|&(w, _)| {
        connect::curve(a, b, radius, w)
            .is_some_and(|c| c.cusps() <= max_cusps && field.curve_clear(&c))
    })
}

/// The path of `curve`'s segments, shortened by shortcuts (step 1 of the
/// [module docs](self)).
fn shortcut(field: &Field, curve: &SmoothCurve, radius: f64, reverse: bool) -> Option<Chain> {
    let segs = &curve.segments;
    let first = segs.first()?;
    let mut poses = vec![first.start];
    let mut along = vec![0.0];
    for s in segs {
        poses.push(s.end());
        along.push(along.last().copied().unwrap_or(0.0) + s.length);
    }
    let n = poses.len();
    let slack = 1e-9;
    let try_join = |a: usize, j: usize| -> Option<(usize, f64)> {
        let (pa, pj) = (*poses.get(a)?, *poses.get(j)?);
        let limit = along.get(j)? - along.get(a)? + slack;
        // No more cusps than the path it replaces (counting one where the segments meet).
        let cusps = segs
            .get(a..j)?
            .windows(2)
            .filter(|w| matches!(w, [x, y] if x.gear != y.gear))
            .count();
        clear_word(field, (pa, pj), radius, reverse, (limit, cusps))
    };
    let mut chain = Chain {
        poses: vec![first.start],
        words: Vec::new(),
    };
    let mut a = 0;
    while a + 1 < n {
        // The original segment is always a fallback.
        let seg = segs.get(a)?;
        let mut best = (a + 1, None::<(usize, f64)>);
        let mut step = 2;
        let mut fail = n;
        while a + step < n {
            let Some(w) = try_join(a, a + step) else {
                fail = a + step;
                break;
            };
            best = (a + step, Some(w));
            step *= 2;
        }
        // Binary search between the last success and the first failure (or the end).
        let (mut lo, mut hi) = (best.0, fail.min(n));
        while hi > lo + 1 {
            let mid = lo + (hi - lo) / 2;
            match try_join(a, mid) {
                Some(w) => {
                    best = (mid, Some(w));
                    lo = mid;
                }
                None => hi = mid,
            }
        }
        if let (j, Some(w)) = best {
            chain.poses.push(*poses.get(j)?);
            chain.words.push(w);
            a = j;
        } else {
            // Keep the segment as it is: the word of its own shape (it is one of them).
            let end = seg.end();
            let w = clear_word(
                field,
                (seg.start, end),
                radius,
                reverse,
                (seg.length + slack, 0),
            )
            .unwrap_or((usize::MAX, seg.length));
            chain.poses.push(end);
            chain.words.push(w);
            a += 1;
        }
    }
    Some(chain)
}

/// Golden-section search of `f` over `[lo, hi]`: the best point found.
fn golden(f: &impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..GOLDEN_STEPS {
        if f1 <= f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - g * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + g * (hi - lo);
            f2 = f(x2);
        }
    }
    if f1 <= f2 { x1 } else { x2 }
}

/// Sliver-removal steps after a heading search.
const SNAPS: usize = 8;

/// Slivers longer than this (cells) are snapped away by turning the pose.
const SNAP_CELLS: f64 = 0.05;

/// The heading change that removes a sliver arc (at most [`SNAP_CELLS`] long) at the end
/// of the shortest word from `a` to `b` (`at_end`: the sliver ends the word at `b`; else it
/// starts the word at `a`), or 0.
fn end_sliver(a: Pose, b: Pose, radius: f64, reverse: bool, at_end: bool) -> f64 {
    let table = connect::table(a, b, radius, reverse);
    let Some((w, _)) = table
        .iter()
        .copied()
        .enumerate()
        .min_by(|x, y| x.1.total_cmp(&y.1))
    else {
        return 0.0;
    };
    let Some(c) = connect::curve(a, b, radius, w) else {
        return 0.0;
    };
    let seg = if at_end {
        c.segments.last()
    } else {
        c.segments.first()
    };
    match seg {
        Some(s) if s.curvature != 0.0 && s.length >= SLIVER_CELLS && s.length <= SNAP_CELLS => {
            let turn = s.curvature * s.length * s.gear.sign();
            if at_end { -turn } else { turn }
        }
        _ => 0.0,
    }
}

/// Step 2 of the [module docs](self) on `chain`, in place.
fn headings(
    field: &Field,
    chain: &mut Chain,
    (start_free, goal_free): (bool, bool),
    radius: f64,
    reverse: bool,
) {
    let n = chain.poses.len();
    for _ in 0..HEADING_PASSES {
        for i in 0..n {
            let free = if i == 0 {
                start_free
            } else if i + 1 == n {
                goal_free
            } else {
                true
            };
            // Only poses where the words already known are usable (not a kept segment).
            let prev = i.checked_sub(1).and_then(|k| chain.poses.get(k).copied());
            let next = chain.poses.get(i + 1).copied();
            let (Some(&p), true) = (chain.poses.get(i), free) else {
                continue;
            };
            let words_in = i.checked_sub(1).and_then(|k| chain.words.get(k).copied());
            let words_out = chain.words.get(i).copied();
            let old = words_in.map_or(0.0, |w| w.1) + words_out.map_or(0.0, |w| w.1);
            if words_in.is_some_and(|w| w.0 == usize::MAX)
                || words_out.is_some_and(|w| w.0 == usize::MAX)
            {
                continue;
            }
            let at = |h: f64| Pose::new(p.x, p.y, h);
            let cost = |h: f64| {
                prev.map_or(0.0, |q| connect::distance(q, at(h), radius, reverse))
                    + next.map_or(0.0, |q| connect::distance(at(h), q, radius, reverse))
            };
            let w = HEADING_WINDOW_DEG.to_radians();
            let mut h = golden(&cost, p.heading_rad - w, p.heading_rad + w);
            // The search leaves slivers of about sqrt(round-off) where the cost is flat:
            // turn the pose by each sliver's own angle until none is left.
            for _ in 0..SNAPS {
                let turn = prev.map_or(0.0, |q| end_sliver(q, at(h), radius, reverse, true))
                    + next.map_or(0.0, |q| end_sliver(at(h), q, radius, reverse, false));
                if turn == 0.0 {
                    break;
                }
                h += turn;
            }
            if cost(h) > old + TIE_CELLS {
                continue;
            }
            let limit = old + 1e-9;
            // No more cusps than the old words had.
            let cusps_of = |a: Pose, b: Pose, w: Option<(usize, f64)>| {
                w.and_then(|(w, _)| connect::curve(a, b, radius, w))
                    .map_or(0, |c| c.cusps())
            };
            let cusps_in = prev.map_or(0, |q| cusps_of(q, p, words_in));
            let cusps_out = next.map_or(0, |q| cusps_of(p, q, words_out));
            let new_in = match prev {
                Some(q) => {
                    match clear_word(field, (q, at(h)), radius, reverse, (limit, cusps_in)) {
                        Some(w) => Some(w),
                        None => continue,
                    }
                }
                None => None,
            };
            let new_out = match next {
                Some(q) => match clear_word(field, (at(h), q), radius, reverse, (limit, cusps_out))
                {
                    Some(w) => Some(w),
                    None => continue,
                },
                None => None,
            };
            let new = new_in.map_or(0.0, |w| w.1) + new_out.map_or(0.0, |w| w.1);
            if new > old + TIE_CELLS {
                continue;
            }
            if let Some(slot) = chain.poses.get_mut(i) {
                *slot = at(h);
            }
            if let (Some(w), Some(slot)) = (
                new_in,
                i.checked_sub(1).and_then(|k| chain.words.get_mut(k)),
            ) {
                *slot = w;
            }
            if let (Some(w), Some(slot)) = (new_out, chain.words.get_mut(i)) {
                *slot = w;
            }
        }
    }
}

/// `curve` polished (see the [module docs](self)): never longer, every new word tested
/// clear by `field`; `None` when nothing could be built (the caller keeps `curve`).
/// `free` says whether the start's and the goal's headings are free.
#[must_use]
pub fn polish(
    field: &Field,
    curve: &SmoothCurve,
    free: (bool, bool),
    radius: f64,
    reverse: bool,
) -> Option<SmoothCurve> {
    let mut chain = shortcut(field, curve, radius, reverse)?;
    headings(field, &mut chain, free, radius, reverse);
    let mut out = SmoothCurve::default();
    for (k, &(w, _)) in chain.words.iter().enumerate() {
        let (a, b) = (*chain.poses.get(k)?, *chain.poses.get(k + 1)?);
        let piece = if w == usize::MAX {
            // A kept segment of the original path.
            let seg = curve
                .segments
                .iter()
                .find(|s| s.start == a && s.end() == b)?;
            let mut c = SmoothCurve::default();
            c.push(*seg);
            c
        } else {
            connect::curve(a, b, radius, w)?
        };
        for s in piece.segments {
            if s.length >= SLIVER_CELLS {
                out.push(s);
            }
        }
    }
    (out.length() <= curve.length() + 1e-8
        && out.cusps() <= curve.cusps()
        && !out.segments.is_empty())
    .then_some(out)
}
