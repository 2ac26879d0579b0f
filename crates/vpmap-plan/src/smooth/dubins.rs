//! Dubins paths: the shortest forward paths of curvature at most `1 / R` between two poses
//! (Dubins 1957), as the best of six words `LSL`, `RSR`, `LSR`, `RSL`, `RLR`, `LRL` (`L`,
//! `R`: arcs of radius `R` turning left or right, `S`: a straight line).
//!
//! [`dubins_words`] gives every feasible word, [`dubins_shortest`] the shortest. The closed
//! forms are those of Shkel and Lumelsky (2001): in the frame where the start is at the
//! origin, the goal on the positive `x` axis at distance `d` (in units of `R`), and the
//! headings `alpha`, `beta` measured from that axis, each word's three lengths `t, p, q`
//! follow from `d`, `alpha` and `beta`. [`dubins_to_point`] and [`dubins_from_point`]
//! leave one heading free.
//!
//! # References
//! - L. E. Dubins, "On Curves of Minimal Length with a Constraint on Average Curvature,
//!   and with Prescribed Initial and Terminal Positions and Tangents", American Journal of
//!   Mathematics 79(3), 1957.
//! - A. M. Shkel, V. Lumelsky, "Classification of the Dubins set", Robotics and Autonomous
//!   Systems 34, 2001.

use std::f64::consts::TAU;

use super::curve::{Gear, Pose, Segment, SmoothCurve};

/// One of a Dubins word's three letters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Steer {
    /// An arc turning left.
    Left,
    /// A straight line.
    Straight,
    /// An arc turning right.
    Right,
}

impl Steer {
    /// The signed curvature of this letter for turning radius `radius`.
    fn curvature(self, radius: f64) -> f64 {
        match self {
            Self::Left => 1.0 / radius,
            Self::Straight => 0.0,
            Self::Right => -1.0 / radius,
        }
    }
}

/// The six Dubins words.
pub const WORDS: [[Steer; 3]; 6] = {
    use Steer::{Left as L, Right as R, Straight as S};
    [
        [L, S, L],
        [R, S, R],
        [L, S, R],
        [R, S, L],
        [R, L, R],
        [L, R, L],
    ]
};

/// A Dubins path: its word and the curve.
#[derive(Clone, Debug, PartialEq)]
pub struct DubinsPath {
    /// The word (letters in driving order).
    pub word: [Steer; 3],
    /// The three segments (zero-length ones dropped).
    pub curve: SmoothCurve,
    /// Total length, cells.
    pub length: f64,
}

/// An angle wrapped into `[0, 2 pi)`, with angles within [`LOOP_SLACK`] below `2 pi`
/// taken as zero: a turn of `-1e-16` from round-off is no turn, not a full loop.
fn mod2pi(a: f64) -> f64 {
    let m = a.rem_euclid(TAU);
    if m >= TAU - LOOP_SLACK { 0.0 } else { m }
}

/// How close (radians) below a full turn an arc counts as none (see [`mod2pi`]).
const LOOP_SLACK: f64 = 1e-9;

/// Round-off slack of the words' feasibility tests: a squared length down to `-SLACK`
/// counts as zero (a word whose line vanishes, as a single arc), a cosine up to
/// `1 + SLACK` as one.
const SLACK: f64 = 1e-10;

/// Distance between the centres (in radii) below which `LSL`'s or `RSR`'s two turning
/// circles are one: the direction between them is round-off, and the path is one arc.
const SAME_CIRCLE: f64 = 1e-9;

/// A squared length, with round-off below zero taken as zero; `None` when negative.
fn touching(p2: f64) -> Option<f64> {
    (p2 >= -SLACK).then(|| p2.max(0.0))
}

/// A cosine, with round-off beyond one clamped; `None` when beyond it.
fn unit(c: f64) -> Option<f64> {
    (c.abs() <= 1.0 + SLACK).then(|| c.clamp(-1.0, 1.0))
}

/// The normalised lengths `(t, p, q)` of `word` from `(0, 0, alpha)` to `(d, 0, beta)` with
/// unit radius, or `None` when the word has no solution.
fn word_lengths(word: [Steer; 3], d: f64, alpha: f64, beta: f64) -> Option<[f64; 3]> {
    word_lengths_with(word, d, Trig::new(alpha, beta))
}

/// The sines and cosines [`word_lengths`] needs, computed once for all six words.
#[derive(Clone, Copy, Debug)]
struct Trig {
    alpha: f64,
    beta: f64,
    sa: f64,
    ca: f64,
    sb: f64,
    cb: f64,
    cab: f64,
}

impl Trig {
    fn new(alpha: f64, beta: f64) -> Self {
        let (sa, ca) = alpha.sin_cos();
        Self::with_alpha((alpha, sa, ca), beta)
    }

    /// With `alpha`'s sine and cosine already computed (shared by many goal headings).
    fn with_alpha((alpha, sa, ca): (f64, f64, f64), beta: f64) -> Self {
        let (sb, cb) = beta.sin_cos();
        Self {
            alpha,
            beta,
            sa,
            ca,
            sb,
            cb,
            cab: (alpha - beta).cos(),
        }
    }
}

/// [`word_lengths`] with the trigonometry given.
fn word_lengths_with(word: [Steer; 3], d: f64, trig: Trig) -> Option<[f64; 3]> {
    use Steer::{Left as L, Right as R, Straight as S};
    let Trig {
        alpha,
        beta,
        sa,
        ca,
        sb,
        cb,
        cab,
    } = trig;
    match word {
        [L, S, L] => {
            let p2 = 2.0 + d * d - 2.0 * cab + 2.0 * d * (sa - sb);
            let p2 = touching(p2)?;
            // Both circles one: the line has no direction, the path is one arc.
            let tmp = if p2.sqrt() < SAME_CIRCLE {
                alpha
            } else {
                (cb - ca).atan2(d + sa - sb)
            };
            Some([mod2pi(tmp - alpha), p2.sqrt(), mod2pi(beta - tmp)])
        }
        [R, S, R] => {
            let p2 = 2.0 + d * d - 2.0 * cab + 2.0 * d * (sb - sa);
            let p2 = touching(p2)?;
            let tmp = if p2.sqrt() < SAME_CIRCLE {
                alpha
            } else {
                (ca - cb).atan2(d - sa + sb)
            };
            Some([mod2pi(alpha - tmp), p2.sqrt(), mod2pi(tmp - beta)])
        }
        [L, S, R] => {
            let p2 = -2.0 + d * d + 2.0 * cab + 2.0 * d * (sa + sb);
            let p2 = touching(p2)?;
            let p = p2.sqrt();
            let tmp = (-ca - cb).atan2(d + sa + sb) - (-2.0_f64).atan2(p);
            Some([mod2pi(tmp - alpha), p, mod2pi(tmp - beta)])
        }
        [R, S, L] => {
            let p2 = d * d - 2.0 + 2.0 * cab - 2.0 * d * (sa + sb);
            let p2 = touching(p2)?;
            let p = p2.sqrt();
            let tmp = (ca + cb).atan2(d - sa - sb) - 2.0_f64.atan2(p);
            Some([mod2pi(alpha - tmp), p, mod2pi(beta - tmp)])
        }
        [R, L, R] => {
            let c = (6.0 - d * d + 2.0 * cab + 2.0 * d * (sa - sb)) / 8.0;
            let c = unit(c)?;
            let p = mod2pi(TAU - c.acos());
            let t = mod2pi(alpha - (ca - cb).atan2(d - sa + sb) + p / 2.0);
            Some([t, p, mod2pi(alpha - beta - t + p)])
        }
        [L, R, L] => {
            let c = (6.0 - d * d + 2.0 * cab + 2.0 * d * (sb - sa)) / 8.0;
            let c = unit(c)?;
            let p = mod2pi(TAU - c.acos());
            let t = mod2pi(-alpha - (ca - cb).atan2(d + sa - sb) + p / 2.0);
            Some([t, p, mod2pi(beta - alpha - t + p)])
        }
        _ => None,
    }
}

/// The curve of `word` with normalised lengths `lengths` from `start`, radius `radius`.
fn build(start: Pose, word: [Steer; 3], lengths: [f64; 3], radius: f64) -> SmoothCurve {
    let mut curve = SmoothCurve::default();
    let mut pose = start;
    for (steer, l) in word.into_iter().zip(lengths) {
        let seg = Segment {
            start: pose,
            curvature: steer.curvature(radius),
            length: l * radius,
            gear: Gear::Forward,
        };
        pose = seg.end();
        curve.push(seg);
    }
    curve
}

/// The frame of [`word_lengths`] for `start`, `goal`: `(d, alpha, beta)` in units of
/// `radius`; `None` for a non-finite input or a non-positive radius.
fn frame(start: Pose, goal: Pose, radius: f64) -> Option<(f64, f64, f64)> {
    let finite = [start.x, start.y, start.heading_rad, goal.x, goal.y]
        .iter()
        .chain([goal.heading_rad, radius].iter())
        .all(|v| v.is_finite());
    if !finite || radius <= 0.0 {
        return None;
    }
    let (dx, dy) = (goal.x - start.x, goal.y - start.y);
    let d = dx.hypot(dy) / radius;
    let phi = if d > 0.0 { dy.atan2(dx) } else { 0.0 };
    Some((
        d,
        mod2pi(start.heading_rad - phi),
        mod2pi(goal.heading_rad - phi),
    ))
}

/// The lengths (cells) of the six words of [`WORDS`] from `start` to `goal`, infinite
/// for a word with no solution: cheap, no curve built.
#[must_use]
pub fn word_table(start: Pose, goal: Pose, radius: f64) -> [f64; 6] {
    let mut out = [f64::INFINITY; 6];
    if let Some((d, alpha, beta)) = frame(start, goal, radius) {
        fill_table(&mut out, d, Trig::new(alpha, beta), radius);
    }
    out
}

fn fill_table(out: &mut [f64; 6], d: f64, trig: Trig, radius: f64) {
    for (slot, word) in out.iter_mut().zip(WORDS) {
        if let Some(l) = word_lengths_with(word, d, trig) {
            *slot = l.iter().sum::<f64>() * radius;
        }
    }
}

/// [`word_table`] from `start` to the point `(x, y)` at each of `headings` (radians), the
/// trigonometry of the start's side computed once: the same numbers, fewer sines.
#[must_use]
pub fn word_tables_to_headings(
    start: Pose,
    x: f64,
    y: f64,
    headings: &[f64],
    radius: f64,
) -> Vec<[f64; 6]> {
    let Some((d, alpha, _)) = frame(start, Pose::new(x, y, 0.0), radius) else {
        return vec![[f64::INFINITY; 6]; headings.len()];
    };
    // As `frame` computes it.
    let (dx, dy) = (x - start.x, y - start.y);
    let phi = if d > 0.0 { dy.atan2(dx) } else { 0.0 };
    let (sa, ca) = alpha.sin_cos();
    headings
        .iter()
        .map(|&h| {
            let mut out = [f64::INFINITY; 6];
            if !h.is_finite() {
                return out;
            }
            let beta = mod2pi(h - phi);
            fill_table(&mut out, d, Trig::with_alpha((alpha, sa, ca), beta), radius);
            out
        })
        .collect()
}

/// The curve of word `WORDS[index]` from `start` to `goal` (`None` when it has none).
#[must_use]
pub fn word_curve(start: Pose, goal: Pose, radius: f64, index: usize) -> Option<SmoothCurve> {
    let (d, alpha, beta) = frame(start, goal, radius)?;
    let word = *WORDS.get(index)?;
    let lengths = word_lengths(word, d, alpha, beta)?;
    Some(build(start, word, lengths, radius))
}

/// Every Dubins word that joins `start` to `goal` with turning radius `radius` (cells,
/// positive), shortest first. Empty only for a non-positive or non-finite radius or pose.
///
/// # Example
/// ```
/// use vpmap_plan::smooth::{Pose, dubins::dubins_words};
/// let words = dubins_words(Pose::new(0.0, 0.0, 0.0), Pose::new(10.0, 0.0, 0.0), 2.0);
/// assert!((words[0].length - 10.0).abs() < 1e-9);
/// ```
#[must_use]
pub fn dubins_words(start: Pose, goal: Pose, radius: f64) -> Vec<DubinsPath> {
    let Some((d, alpha, beta)) = frame(start, goal, radius) else {
        return Vec::new();
    };
    let mut paths: Vec<DubinsPath> = WORDS
        .into_iter()
        .filter_map(|word| {
            let lengths = word_lengths(word, d, alpha, beta)?;
            let curve = build(start, word, lengths, radius);
            Some(DubinsPath {
                word,
                length: lengths.iter().sum::<f64>() * radius,
                curve,
            })
        })
        .collect();
    paths.sort_by(|a, b| a.length.total_cmp(&b.length));
    paths
}

/// The shortest Dubins path from `start` to `goal` (see [`dubins_words`]).
#[must_use]
pub fn dubins_shortest(start: Pose, goal: Pose, radius: f64) -> Option<DubinsPath> {
    dubins_words(start, goal, radius).into_iter().next()
}

/// The Dubins distance from `start` to `goal`, cells (infinite when there is none): the
/// shortest of [`word_table`], no curve built.
#[must_use]
pub fn dubins_distance(start: Pose, goal: Pose, radius: f64) -> f64 {
    word_table(start, goal, radius)
        .into_iter()
        .fold(f64::INFINITY, f64::min)
}

/// Headings tried for a free end by [`dubins_to_point`] besides the analytic ones.
pub const FREE_HEADING_SAMPLES: usize = 72;

/// A short forward path of curvature at most `1 / radius` from `start` to the point
/// `(x, y)` with any final heading: the best of the two turn-then-straight paths (exact
/// when the point is outside the turning circle on that side) and Dubins paths to the
/// point at [`FREE_HEADING_SAMPLES`] headings and the straight-on one. `None` only for bad
/// input.
#[must_use]
pub fn dubins_to_point(start: Pose, x: f64, y: f64, radius: f64) -> Option<DubinsPath> {
    free_end_candidates(start, x, y, radius)
        .into_iter()
        .filter_map(|h| dubins_shortest(start, Pose::new(x, y, h), radius))
        .min_by(|a, b| a.length.total_cmp(&b.length))
}

/// The final headings [`dubins_to_point`] tries: the tangent-line ones, the straight-on
/// one and evenly spaced samples.
pub(crate) fn free_end_candidates(start: Pose, x: f64, y: f64, radius: f64) -> Vec<f64> {
    let mut headings = Vec::with_capacity(FREE_HEADING_SAMPLES + 3);
    headings.push((y - start.y).atan2(x - start.x));
    let (sin, cos) = start.heading_rad.sin_cos();
    for side in [1.0, -1.0] {
        // Turning circle centre on this side; the tangent from it to the point.
        let c = (start.x - side * radius * sin, start.y + side * radius * cos);
        let (vx, vy) = (x - c.0, y - c.1);
        let dist = vx.hypot(vy);
        if dist >= radius {
            let l = (dist * dist - radius * radius).sqrt();
            // The tangent point's direction from the circle centre and the line's heading.
            let base = vy.atan2(vx);
            let off = (radius / dist).acos();
            let psi = base + side * -off;
            let t = psi + side * std::f64::consts::FRAC_PI_2;
            if l >= 0.0 {
                headings.push(t);
            }
        }
    }
    for k in 0..FREE_HEADING_SAMPLES {
        headings.push(TAU * k as f64 / FREE_HEADING_SAMPLES as f64);
    }
    headings
}

/// A curve driven backwards: the same points, segments in reverse order, each starting
/// at the old end with the heading turned by pi (curvatures change sign).
#[must_use]
pub fn reversed(curve: &SmoothCurve) -> SmoothCurve {
    let mut out = SmoothCurve::default();
    for seg in curve.segments.iter().rev() {
        let end = seg.end();
        out.push(Segment {
            start: Pose::new(end.x, end.y, end.heading_rad + std::f64::consts::PI),
            curvature: -seg.curvature,
            length: seg.length,
            gear: seg.gear,
        });
    }
    out
}

/// A short forward path from the point `(x, y)`, any initial heading, to `goal`: the
/// reverse of [`dubins_to_point`] from `goal` turned around.
#[must_use]
pub fn dubins_from_point(x: f64, y: f64, goal: Pose, radius: f64) -> Option<DubinsPath> {
    let turned = Pose::new(goal.x, goal.y, goal.heading_rad + std::f64::consts::PI);
    let path = dubins_to_point(turned, x, y, radius)?;
    let word = path.word.map(|s| match s {
        Steer::Left => Steer::Right,
        Steer::Right => Steer::Left,
        Steer::Straight => Steer::Straight,
    });
    Some(DubinsPath {
        word: [word[2], word[1], word[0]],
        curve: reversed(&path.curve),
        length: path.length,
    })
}
