//! Polishing a found path (issue 41's "no wobble" target): passes over the poses where
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
//! 3. **Anchors.** The shortcut may drop the pose at a corner's vertex (where the path
//!    touches the obstacle) for one a little past it, joined by the same curve; at that pose
//!    no other heading is clear (turning it swings the arc into the corner), so a sliver
//!    turning the other way stays (nav2-kind-1 query 2 of the 2026-11-29 bench run: 5 sign
//!    changes against the taut path's turns + 1 = 4). Each pose between the ends whose two
//!    words change curvature sign is tried at the unpolished path's segment ends near it
//!    (at most [`ANCHOR_CANDIDATES`] on either side, between its neighbours, so the vertex
//!    among them), at their own heading and at the best one there (as in 2), and moved to
//!    the one that leaves the whole path with the fewest sign changes, when that is fewer
//!    than before (looked at first without collision tests, with the shortest words at the
//!    end's own heading). Then step 2 runs again on the moved poses and their neighbours.
//!
//! A change is kept only when the new words are tested clear by [`Field`], have no more
//! cusps than what they replace, and the whole is no longer and has no more cusps; the caller validates the result and keeps the unpolished path if it fails.
//!
//! # Complexity
//! `O(n log n)` word tables and collision tests for the shortcut over `n` segments, then
//! [`HEADING_PASSES`] x `n` golden-section searches of [`GOLDEN_STEPS`] word tables each
//! (twice), and for the anchors at most `2 x` [`ANCHOR_CANDIDATES`] searches, placements and
//! `O(n)` rebuilds of the path per pose whose words change sign.

use super::clearance::Field;
use super::connect;
use super::curve::{Pose, Segment, SmoothCurve};

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
#[derive(Clone)]
struct Chain {
    poses: Vec<Pose>,
    /// `words[i]` joins `poses[i]` to `poses[i + 1]`: (word, length).
    words: Vec<(usize, f64)>,
    /// `orig[i]`: the index of `poses[i]` among the unpolished path's segment ends (its
    /// start first), or of the one it was moved from.
    orig: Vec<usize>,
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

/// The poses where `curve`'s segments meet, its start first and its end last.
fn segment_ends(curve: &SmoothCurve) -> Vec<Pose> {
    let mut poses: Vec<Pose> = curve
        .segments
        .first()
        .map(|s| s.start)
        .into_iter()
        .collect();
    poses.extend(curve.segments.iter().map(Segment::end));
    poses
}

/// The path of `curve`'s segments, shortened by shortcuts (step 1 of the
/// [module docs](self)).
fn shortcut(field: &Field, curve: &SmoothCurve, radius: f64, reverse: bool) -> Option<Chain> {
    let segs = &curve.segments;
    let first = segs.first()?;
    let poses = segment_ends(curve);
    let mut along = vec![0.0];
    for s in segs {
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
        orig: vec![0],
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
            chain.orig.push(j);
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
            chain.orig.push(a);
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

/// A pose placed between its neighbours: the pose, the words from the previous pose and to
/// the next one, and their total length.
struct Placed {
    pose: Pose,
    word_in: Option<(usize, f64)>,
    word_out: Option<(usize, f64)>,
    length: f64,
}

/// The heading at `p`'s position that makes the shortest words from `prev` and to `next`
/// shortest: golden-section search within [`HEADING_WINDOW_DEG`] of `p`'s heading, then
/// slivers snapped away ([`end_sliver`]).
fn best_heading(
    (prev, p, next): (Option<Pose>, Pose, Option<Pose>),
    radius: f64,
    reverse: bool,
) -> f64 {
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
    h
}

/// `p` joined to `prev` and `next` by their shortest clear words (at most [`WORDS_TRIED`]
/// each), with at most `cusps` cusps each and in all no longer than `old` (+ round-off).
fn place(
    field: &Field,
    (prev, p, next): (Option<Pose>, Pose, Option<Pose>),
    radius: f64,
    reverse: bool,
    (old, (cusps_in, cusps_out)): (f64, (usize, usize)),
) -> Option<Placed> {
    let tie = |l: f64| l <= old + TIE_CELLS;
    let word_length = |a: Pose, b: Pose| connect::distance(a, b, radius, reverse);
    let lower = prev.map_or(0.0, |q| word_length(q, p)) + next.map_or(0.0, |q| word_length(p, q));
    if !tie(lower) {
        return None;
    }
    let limit = old + 1e-9;
    let word_in = match prev {
        Some(q) => Some(clear_word(
            field,
            (q, p),
            radius,
            reverse,
            (limit, cusps_in),
        )?),
        None => None,
    };
    let word_out = match next {
        Some(q) => Some(clear_word(
            field,
            (p, q),
            radius,
            reverse,
            (limit, cusps_out),
        )?),
        None => None,
    };
    let length = word_in.map_or(0.0, |w| w.1) + word_out.map_or(0.0, |w| w.1);
    tie(length).then_some(Placed {
        pose: p,
        word_in,
        word_out,
        length,
    })
}

/// The neighbours of `chain`'s pose `i` and its words' total length and cusps, or `None`
/// where a word is a kept segment of the unpolished path (its word is not known).
#[allow(clippy::type_complexity)]
fn around(
    chain: &Chain,
    i: usize,
    radius: f64,
) -> Option<((Option<Pose>, Pose, Option<Pose>), (f64, (usize, usize)))> {
    let p = *chain.poses.get(i)?;
    let prev = i.checked_sub(1).and_then(|k| chain.poses.get(k).copied());
    let next = chain.poses.get(i + 1).copied();
    let words_in = i.checked_sub(1).and_then(|k| chain.words.get(k).copied());
    let words_out = chain.words.get(i).copied();
    if words_in.is_some_and(|w| w.0 == usize::MAX) || words_out.is_some_and(|w| w.0 == usize::MAX) {
        return None;
    }
    let old = words_in.map_or(0.0, |w| w.1) + words_out.map_or(0.0, |w| w.1);
    // No more cusps than the old words had.
    let cusps_of = |a: Pose, b: Pose, w: Option<(usize, f64)>| {
        w.and_then(|(w, _)| connect::curve(a, b, radius, w))
            .map_or(0, |c| c.cusps())
    };
    let cusps_in = prev.map_or(0, |q| cusps_of(q, p, words_in));
    let cusps_out = next.map_or(0, |q| cusps_of(p, q, words_out));
    Some(((prev, p, next), (old, (cusps_in, cusps_out))))
}

/// Put `placed` in `chain` as its pose `i`.
fn put(chain: &mut Chain, i: usize, placed: &Placed) {
    if let Some(slot) = chain.poses.get_mut(i) {
        *slot = placed.pose;
    }
    if let (Some(w), Some(slot)) = (
        placed.word_in,
        i.checked_sub(1).and_then(|k| chain.words.get_mut(k)),
    ) {
        *slot = w;
    }
    if let (Some(w), Some(slot)) = (placed.word_out, chain.words.get_mut(i)) {
        *slot = w;
    }
}

/// Step 2 of the [module docs](self) on `chain`, in place.
/// Only the poses `only` says (all when `None`).
fn headings(
    field: &Field,
    chain: &mut Chain,
    (start_free, goal_free): (bool, bool),
    radius: f64,
    reverse: bool,
    only: Option<&[usize]>,
) {
    let n = chain.poses.len();
    for _ in 0..HEADING_PASSES {
        for i in 0..n {
            if only.is_some_and(|o| !o.contains(&i)) {
                continue;
            }
            let free = if i == 0 {
                start_free
            } else if i + 1 == n {
                goal_free
            } else {
                true
            };
            if !free {
                continue;
            }
            // Only poses where the words already known are usable (not a kept segment).
            let Some(((prev, p, next), budget)) = around(chain, i, radius) else {
                continue;
            };
            let h = best_heading((prev, p, next), radius, reverse);
            let at = Pose::new(p.x, p.y, h);
            if let Some(placed) = place(field, (prev, at, next), radius, reverse, budget) {
                put(chain, i, &placed);
            }
        }
    }
}

/// Most unpolished segment ends tried on either side of a pose by the anchors step (3 of the [module docs](self)).
pub const ANCHOR_CANDIDATES: usize = 4;

/// Step 3 of the [module docs](self) on `chain`, in place: each pose between the ends whose
/// words change curvature sign is moved to a nearby segment end of the unpolished path
/// `ends` (at most [`ANCHOR_CANDIDATES`] on either side, between its neighbours), at that
/// end's heading or at the best one there ([`best_heading`]), where that leaves the whole
/// path with fewer sign changes and no longer.
fn anchors(
    field: &Field,
    chain: &mut Chain,
    (ends, curve): (&[Pose], &SmoothCurve),
    radius: f64,
    reverse: bool,
) -> Vec<usize> {
    let mut moved = Vec::new();
    for i in 1..chain.poses.len().saturating_sub(1) {
        let Some(((prev, p, next), budget)) = around(chain, i, radius) else {
            continue;
        };
        let (Some(prev), Some(next)) = (prev, next) else {
            continue;
        };
        let word_curve = |a: Pose, b: Pose, w: Option<&(usize, f64)>| {
            w.and_then(|&(w, _)| connect::curve(a, b, radius, w))
        };
        let (Some(old_in), Some(old_out)) = (
            word_curve(prev, p, chain.words.get(i - 1)),
            word_curve(p, next, chain.words.get(i)),
        ) else {
            continue;
        };
        let context = (
            last_sign(chain, curve, radius, i - 1, true),
            last_sign(chain, curve, radius, i + 1, false),
        );
        // Only where the two words, with the turns on either side, change sign.
        let changes = local_changes(context, &old_in, &old_out);
        if changes == 0 {
            continue;
        }
        let (Some(&lo), Some(&at), Some(&hi)) = (
            chain.orig.get(i - 1),
            chain.orig.get(i),
            chain.orig.get(i + 1),
        ) else {
            continue;
        };
        let from = (lo + 1).max(at.saturating_sub(ANCHOR_CANDIDATES));
        let to = (hi.saturating_sub(1)).min(at + ANCHOR_CANDIDATES);
        let shortest = |a: Pose, b: Pose| {
            let table = connect::table(a, b, radius, reverse);
            let (w, _) = table
                .iter()
                .copied()
                .enumerate()
                .min_by(|x, y| x.1.total_cmp(&y.1))?;
            connect::curve(a, b, radius, w)
        };
        let mut best: Option<(usize, f64, usize, Placed)> = None;
        for k in from..=to {
            let Some(&q) = ends.get(k) else { continue };
            if k == at {
                continue;
            }
            // A cheap first look, no collision test: the shortest words at the end's own
            // heading must already change sign less often.
            let (Some(c_in), Some(c_out)) = (shortest(prev, q), shortest(q, next)) else {
                continue;
            };
            if local_changes(context, &c_in, &c_out) >= changes {
                continue;
            }
            let tuned = Pose::new(
                q.x,
                q.y,
                best_heading((Some(prev), q, Some(next)), radius, reverse),
            );
            for cand in [tuned, q] {
                let Some(placed) = place(
                    field,
                    (Some(prev), cand, Some(next)),
                    radius,
                    reverse,
                    budget,
                ) else {
                    continue;
                };
                let (Some(c_in), Some(c_out)) = (
                    word_curve(prev, cand, placed.word_in.as_ref()),
                    word_curve(cand, next, placed.word_out.as_ref()),
                ) else {
                    continue;
                };
                let sc = local_changes(context, &c_in, &c_out);
                let better = best
                    .as_ref()
                    .is_none_or(|b| (sc, placed.length) < (b.0, b.1));
                if sc < changes && better {
                    best = Some((sc, placed.length, k, placed));
                }
            }
        }
        if let Some((_, _, k, placed)) = best {
            put(chain, i, &placed);
            if let Some(slot) = chain.orig.get_mut(i) {
                *slot = k;
            }
            moved.push(i);
        }
    }
    moved
}

/// The signed curvature (curvature x gear) of the last turning segment of `chain`'s words
/// before pose `i` (`backwards`), or of the first from pose `i` on; `None` if there is none.
/// Segments shorter than [`SLIVER_CELLS`] do not count (the polished path leaves them out).
fn last_sign(
    chain: &Chain,
    curve: &SmoothCurve,
    radius: f64,
    i: usize,
    backwards: bool,
) -> Option<f64> {
    let word = |k: usize| -> Option<SmoothCurve> {
        let one = Chain {
            poses: chain.poses.get(k..k + 2)?.to_vec(),
            words: vec![*chain.words.get(k)?],
            orig: Vec::new(),
        };
        build(&one, curve, radius)
    };
    let turning = |s: &&Segment| s.curvature != 0.0 && s.length >= SLIVER_CELLS;
    let signed = |c: &SmoothCurve, rev: bool| {
        if rev {
            c.segments.iter().rev().find(turning)
        } else {
            c.segments.iter().find(turning)
        }
        .map(|s| s.curvature * s.gear.sign())
    };
    if backwards {
        (0..i)
            .rev()
            .find_map(|k| word(k).and_then(|c| signed(&c, true)))
    } else {
        (i..chain.words.len()).find_map(|k| word(k).and_then(|c| signed(&c, false)))
    }
}

/// Curvature sign changes along `before`, the curves `a` and `b`, and `after` (signed
/// curvatures of the turns on either side), slivers left out as in [`build`].
fn local_changes(
    (before, after): (Option<f64>, Option<f64>),
    a: &SmoothCurve,
    b: &SmoothCurve,
) -> usize {
    let signs = a
        .segments
        .iter()
        .chain(&b.segments)
        .filter(|s| s.length >= SLIVER_CELLS)
        .map(|s| s.curvature * s.gear.sign())
        .chain(after);
    let mut last = before.unwrap_or(0.0);
    let mut changes = 0;
    for k in signs {
        if k != 0.0 {
            if last != 0.0 && (k > 0.0) != (last > 0.0) {
                changes += 1;
            }
            last = k;
        }
    }
    changes
}

/// The curve of `chain` (kept segments taken from `curve`), slivers left out.
fn build(chain: &Chain, curve: &SmoothCurve, radius: f64) -> Option<SmoothCurve> {
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
    Some(out)
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
    headings(field, &mut chain, free, radius, reverse, None);
    let moved = anchors(
        field,
        &mut chain,
        (&segment_ends(curve), curve),
        radius,
        reverse,
    );
    if !moved.is_empty() {
        // Again at the moved poses and their neighbours.
        let again: Vec<usize> = moved
            .iter()
            .flat_map(|&i| [i.saturating_sub(1), i, i + 1])
            .collect();
        headings(field, &mut chain, free, radius, reverse, Some(&again));
    }
    let out = build(&chain, curve, radius)?;
    (out.length() <= curve.length() + 1e-8
        && out.cusps() <= curve.cusps()
        && !out.segments.is_empty())
    .then_some(out)
}
