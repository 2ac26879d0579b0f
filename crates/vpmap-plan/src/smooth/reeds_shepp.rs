//! Reeds-Shepp paths: the shortest paths of curvature at most `1 / R` between two poses
//! when the robot may also drive in reverse (Reeds and Shepp 1990). A shortest path is one
//! of 48 words of at most five pieces (arcs `L`, `R` of radius `R` and lines `S`, each
//! driven forward `+` or in reverse `-`) with at most two cusps (`|`), in the families
//! `CSC`, `C|C|C` (and `CC|C`, `C|CC`), `CC|CC`, `C|CC|C`, `C|C_{pi/2}SC`, `CSC_{pi/2}|C`,
//! `C|C_{pi/2}SC_{pi/2}|C`.
//!
//! # Method
//! Paths are solved in the start's frame with unit radius: the goal is `(x, y, phi)`.
//! Eight closed forms, the formulas 8.1-8.11 of Reeds and Shepp (with the corrections
//! every implementation since uses), each solve one base word:
//!
//! | base word | formula | lengths |
//! |---|---|---|
//! | `L+ S+ L+` | 8.1 | `t, u, v` |
//! | `L+ S+ R+` | 8.2 | `t, u, v` |
//! | `L+ R- L` | 8.3/8.4 | `t, u, v` |
//! | `L+ R+ L- R-` | 8.7 | `t, u, -u, v` |
//! | `L+ R- L- R+` | 8.8 | `t, u, u, v` |
//! | `L+ R- S- L-` | 8.9 | `t, -pi/2, u, v` |
//! | `L+ R- S- R-` | 8.10 | `t, -pi/2, u, v` |
//! | `L+ R- S L- R+` | 8.11 | `t, -pi/2, u, -pi/2, v` |
//!
//! and the other words follow by three symmetries of the problem ([`Variant`]):
//! **time-flip** (drive the path backwards in time: solve for `(-x, y, -phi)`, negate every
//! length), **reflection** (mirror in the start's heading line: solve for `(x, -y, -phi)`,
//! swap `L` and `R`) and, for the three words that are not their own reverse,
//! **backwards** (the word's pieces in reverse order, as if driven from the goal: solve
//! for `(x cos phi + y sin phi, x sin phi - y cos phi, phi)` and reverse the order of the
//! pieces). That makes [`SLOTS`] = 44 candidate paths; each
//! is built into a curve from the start and kept only when the curve ends at the goal
//! (within [`END_TOLERANCE`] turning radii), so a formula's round-off or degenerate case
//! never yields a path to the wrong place.
//!
//! A piece's signed length `l` (radians of turn for an arc, radius units for a line) is
//! driven forward when `l >= 0`, in reverse otherwise; an arc `L` driven in reverse turns
//! the heading right, as [`super::curve`] states. Pieces shorter than [`PIECE_EPSILON`]
//! radii are dropped, so round-off never makes a spurious cusp.
//!
//! # References
//! - J. A. Reeds, L. A. Shepp, "Optimal paths for a car that goes both forwards and
//!   backwards", Pacific Journal of Mathematics 145(2), 1990.
//! - H. Sussmann, G. Tang, "Shortest paths for the Reeds-Shepp car: a worked out example of
//!   the use of geometric techniques in nonlinear optimal control", Rutgers SYCON 91-10,
//!   1991 (the sufficient family of 46 types).

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use super::curve::{Gear, Pose, Segment, SmoothCurve};
use super::dubins::Steer;

/// How many candidate paths [`rs_table`] evaluates: eight base formulas under four
/// symmetries, three of them also backwards.
pub const SLOTS: usize = 44;

/// Largest distance (in turning radii) between a candidate's built end and the goal for
/// it to be kept.
pub const END_TOLERANCE: f64 = 1e-7;

/// Pieces shorter than this many turning radii are dropped.
pub const PIECE_EPSILON: f64 = 1e-10;

/// Distance between centres (radii) below which two turning circles are one (8.1).
const SAME_CIRCLE: f64 = 1e-9;

/// Slack of the formulas' sign tests (radius units).
const ZERO: f64 = 1e-10;

/// A Reeds-Shepp path: its pieces and the curve.
#[derive(Clone, Debug, PartialEq)]
pub struct ReedsSheppPath {
    /// The pieces in driving order: letter and signed length (radians for an arc, cells
    /// for a line; negative in reverse), zero-length pieces dropped.
    pub pieces: Vec<(Steer, f64)>,
    /// The curve.
    pub curve: SmoothCurve,
    /// Total length, cells.
    pub length: f64,
    /// Changes of gear along it.
    pub cusps: usize,
}

/// One of the symmetries applied to a base word (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Variant {
    /// Negate the lengths (drive backwards in time).
    pub time_flip: bool,
    /// Swap `L` and `R`.
    pub reflect: bool,
    /// Reverse the order of the pieces (drive from the goal).
    pub backwards: bool,
}

/// The base words' letters.
const BASE_WORDS: [&[Steer]; 8] = {
    use Steer::{Left as L, Right as R, Straight as S};
    [
        &[L, S, L],
        &[L, S, R],
        &[L, R, L],
        &[L, R, L, R],
        &[L, R, L, R],
        &[L, R, S, L],
        &[L, R, S, R],
        &[L, R, S, L, R],
    ]
};

/// Whether base word `i` also needs its backwards variant (it is not its own reverse).
const fn needs_backwards(i: usize) -> bool {
    matches!(i, 2 | 5 | 6)
}

/// The (base word, variant) of every slot, in a fixed order.
fn slot(index: usize) -> Option<(usize, Variant)> {
    let mut k = 0;
    for base in 0..BASE_WORDS.len() {
        let directions: &[bool] = if needs_backwards(base) {
            &[false, true]
        } else {
            &[false]
        };
        for &backwards in directions {
            for (time_flip, reflect) in [(false, false), (true, false), (false, true), (true, true)]
            {
                if k == index {
                    return Some((
                        base,
                        Variant {
                            time_flip,
                            reflect,
                            backwards,
                        },
                    ));
                }
                k += 1;
            }
        }
    }
    None
}

/// An angle wrapped into `[-pi, pi]`.
fn wrap(a: f64) -> f64 {
    let v = a % TAU;
    if v < -PI {
        v + TAU
    } else if v > PI {
        v - TAU
    } else {
        v
    }
}

/// `(hypot, atan2)` of a vector.
fn polar(x: f64, y: f64) -> (f64, f64) {
    (x.hypot(y), y.atan2(x))
}

/// The first and last turns `(tau, omega)` of the four-arc words (8.7, 8.8).
fn tau_omega(u: f64, v: f64, xi: f64, eta: f64, phi: f64) -> (f64, f64) {
    let delta = wrap(u - v);
    let a = u.sin() - delta.sin();
    let b = u.cos() - delta.cos() - 1.0;
    let t1 = (eta * a - xi * b).atan2(xi * a + eta * b);
    let t2 = 2.0 * (delta.cos() - v.cos() - u.cos()) + 3.0;
    let tau = if t2 < 0.0 { wrap(t1 + PI) } else { wrap(t1) };
    (tau, wrap(tau - u + v - phi))
}

/// The signed lengths of base word `base` to `(x, y, phi)` (unit radius), or `None`.
#[allow(clippy::many_single_char_names)] // the paper's names
fn base_lengths(base: usize, x: f64, y: f64, phi: f64) -> Option<Vec<f64>> {
    let (sp, cp) = phi.sin_cos();
    match base {
        // 8.1: L+ S+ L+.
        0 => {
            let (u, t) = polar(x - sp, y - 1.0 + cp);
            // Both circles one: the line has no direction, the path is one arc.
            let t = if u < SAME_CIRCLE { phi } else { t };
            let v = wrap(phi - t);
            (t >= -ZERO && v >= -ZERO).then(|| vec![t, u, v])
        }
        // 8.2: L+ S+ R+.
        1 => {
            let (u1, t1) = polar(x + sp, y - 1.0 - cp);
            let u1 = u1 * u1;
            if u1 < 4.0 {
                return None;
            }
            let u = (u1 - 4.0).sqrt();
            let t = wrap(t1 + 2.0_f64.atan2(u));
            let v = wrap(t - phi);
            (t >= -ZERO && v >= -ZERO).then(|| vec![t, u, v])
        }
        // 8.3: L+ R- L.
        2 => {
            let (u1, theta) = polar(x - sp, y - 1.0 + cp);
            if u1 > 4.0 {
                return None;
            }
            let u = -2.0 * (0.25 * u1).asin();
            let t = wrap(theta + 0.5 * u + PI);
            let v = wrap(phi - t + u);
            (t >= -ZERO && u <= ZERO).then(|| vec![t, u, v])
        }
        // 8.7: L+ R+ L- R-.
        3 => {
            let (xi, eta) = (x + sp, y - 1.0 - cp);
            let rho = 0.25 * (2.0 + xi.hypot(eta));
            if rho > 1.0 {
                return None;
            }
            let u = rho.acos();
            let (t, v) = tau_omega(u, -u, xi, eta, phi);
            (t >= -ZERO && v <= ZERO).then(|| vec![t, u, -u, v])
        }
        // 8.8: L+ R- L- R+.
        4 => {
            let (xi, eta) = (x + sp, y - 1.0 - cp);
            let rho = (20.0 - xi * xi - eta * eta) / 16.0;
            if !(0.0..=1.0).contains(&rho) {
                return None;
            }
            let u = -rho.acos();
            if u < -FRAC_PI_2 {
                return None;
            }
            let (t, v) = tau_omega(u, u, xi, eta, phi);
            (t >= -ZERO && v >= -ZERO).then(|| vec![t, u, u, v])
        }
        // 8.9: L+ R-(pi/2) S- L-.
        5 => {
            let (rho, theta) = polar(x - sp, y - 1.0 + cp);
            if rho < 2.0 {
                return None;
            }
            let r = (rho * rho - 4.0).sqrt();
            let u = 2.0 - r;
            let t = wrap(theta + r.atan2(-2.0));
            let v = wrap(phi - FRAC_PI_2 - t);
            (t >= -ZERO && u <= ZERO && v <= ZERO).then(|| vec![t, -FRAC_PI_2, u, v])
        }
        // 8.10: L+ R-(pi/2) S- R-.
        6 => {
            let (xi, eta) = (x + sp, y - 1.0 - cp);
            let (rho, theta) = polar(-eta, xi);
            if rho < 2.0 {
                return None;
            }
            let t = theta;
            let u = 2.0 - rho;
            let v = wrap(t + FRAC_PI_2 - phi);
            (t >= -ZERO && u <= ZERO && v <= ZERO).then(|| vec![t, -FRAC_PI_2, u, v])
        }
        // 8.11: L+ R-(pi/2) S- L-(pi/2) R+.
        7 => {
            let (xi, eta) = (x + sp, y - 1.0 - cp);
            let (rho, _) = polar(xi, eta);
            if rho < 2.0 {
                return None;
            }
            let u = 4.0 - (rho * rho - 4.0).sqrt();
            if u > ZERO {
                return None;
            }
            let t = wrap(((4.0 - u) * xi - 2.0 * eta).atan2(-2.0 * xi + (u - 4.0) * eta));
            let v = wrap(t - phi);
            (t >= -ZERO && v >= -ZERO).then(|| vec![t, -FRAC_PI_2, u, -FRAC_PI_2, v])
        }
        _ => None,
    }
}

/// The pieces (letter, signed length in radius units) of slot `index` to `(x, y, phi)`.
fn slot_pieces(index: usize, x: f64, y: f64, phi: f64) -> Option<Vec<(Steer, f64)>> {
    let (base, var) = slot(index)?;
    let (mut x, mut y, mut phi) = (x, y, phi);
    if var.backwards {
        let (sp, cp) = phi.sin_cos();
        (x, y) = (x * cp + y * sp, x * sp - y * cp);
    }
    if var.time_flip {
        (x, phi) = (-x, -phi);
    }
    if var.reflect {
        (y, phi) = (-y, -phi);
    }
    let lengths = base_lengths(base, x, y, phi)?;
    let letters = BASE_WORDS.get(base)?;
    let mut pieces: Vec<(Steer, f64)> = letters
        .iter()
        .zip(lengths)
        .map(|(&s, l)| {
            let s = match (var.reflect, s) {
                (true, Steer::Left) => Steer::Right,
                (true, Steer::Right) => Steer::Left,
                (_, s) => s,
            };
            (s, if var.time_flip { -l } else { l })
        })
        .collect();
    if var.backwards {
        pieces.reverse();
    }
    Some(pieces)
}

/// The start's frame: `(x, y, phi)` of `goal` in units of `radius`; `None` for a
/// non-finite input or a non-positive radius.
fn frame(start: Pose, goal: Pose, radius: f64) -> Option<(f64, f64, f64)> {
    let finite = [start.x, start.y, start.heading_rad, goal.x, goal.y]
        .iter()
        .chain([goal.heading_rad, radius].iter())
        .all(|v| v.is_finite());
    if !finite || radius <= 0.0 {
        return None;
    }
    let (dx, dy) = ((goal.x - start.x) / radius, (goal.y - start.y) / radius);
    let (s, c) = start.heading_rad.sin_cos();
    Some((
        c * dx + s * dy,
        -s * dx + c * dy,
        wrap(goal.heading_rad - start.heading_rad),
    ))
}

/// The curve of `pieces` from `start`, radius `radius` (pieces below [`PIECE_EPSILON`]
/// dropped).
fn build(start: Pose, pieces: &[(Steer, f64)], radius: f64) -> SmoothCurve {
    let mut curve = SmoothCurve::default();
    let mut pose = start;
    for &(steer, l) in pieces {
        if l.abs() < PIECE_EPSILON {
            continue;
        }
        let seg = Segment {
            start: pose,
            curvature: match steer {
                Steer::Left => 1.0 / radius,
                Steer::Straight => 0.0,
                Steer::Right => -1.0 / radius,
            },
            length: l.abs() * radius,
            gear: if l >= 0.0 {
                Gear::Forward
            } else {
                Gear::Reverse
            },
        };
        pose = seg.end();
        curve.push(seg);
    }
    curve
}

/// Whether `curve` from `start` ends at `goal` within [`END_TOLERANCE`] radii.
fn ends_at(curve: &SmoothCurve, start: Pose, goal: Pose, radius: f64) -> bool {
    let end = curve.segments.last().map_or(start, Segment::end);
    let jump = wrap(end.heading_rad - goal.heading_rad).abs();
    end.distance(&goal) <= END_TOLERANCE * radius && jump <= END_TOLERANCE
}

/// The lengths (cells) of the [`SLOTS`] candidates from `start` to `goal`, infinite for a
/// slot with no solution. Cheap (no curve built), but a finite entry is only a candidate:
/// [`rs_slot_curve`] checks where its curve ends.
#[must_use]
pub fn rs_table(start: Pose, goal: Pose, radius: f64) -> [f64; SLOTS] {
    let mut out = [f64::INFINITY; SLOTS];
    if let Some((x, y, phi)) = frame(start, goal, radius) {
        for (i, slot) in out.iter_mut().enumerate() {
            if let Some(p) = slot_pieces(i, x, y, phi) {
                *slot = p.iter().map(|(_, l)| l.abs()).sum::<f64>() * radius;
            }
        }
    }
    out
}

/// The curve of candidate `index` from `start` to `goal` (`None` when it has none or its
/// curve does not end at the goal).
#[must_use]
pub fn rs_slot_curve(start: Pose, goal: Pose, radius: f64, index: usize) -> Option<SmoothCurve> {
    let (x, y, phi) = frame(start, goal, radius)?;
    let pieces = slot_pieces(index, x, y, phi)?;
    let curve = build(start, &pieces, radius);
    ends_at(&curve, start, goal, radius).then_some(curve)
}

/// Every Reeds-Shepp candidate that joins `start` to `goal` with turning radius `radius`
/// (cells, positive), shortest first; the first is the shortest path with cusps allowed.
/// Empty only for a non-positive or non-finite radius or pose.
///
/// # Example
/// ```
/// use vpmap_plan::smooth::{Pose, reeds_shepp::rs_paths, dubins_distance};
/// // Two cells straight behind: backing up is shorter than any forward loop.
/// let (start, goal) = (Pose::new(0.0, 0.0, 0.0), Pose::new(-2.0, 0.0, 0.0));
/// let best = &rs_paths(start, goal, 1.0)[0];
/// assert!((best.length - 2.0).abs() < 1e-9);
/// assert!(dubins_distance(start, goal, 1.0) > 2.0);
/// ```
#[must_use]
pub fn rs_paths(start: Pose, goal: Pose, radius: f64) -> Vec<ReedsSheppPath> {
    let Some((x, y, phi)) = frame(start, goal, radius) else {
        return Vec::new();
    };
    let mut paths: Vec<ReedsSheppPath> = (0..SLOTS)
        .filter_map(|i| {
            let pieces = slot_pieces(i, x, y, phi)?;
            let curve = build(start, &pieces, radius);
            if !ends_at(&curve, start, goal, radius) {
                return None;
            }
            let pieces: Vec<(Steer, f64)> = pieces
                .into_iter()
                .filter(|(_, l)| l.abs() >= PIECE_EPSILON)
                .map(|(s, l)| (s, if s == Steer::Straight { l * radius } else { l }))
                .collect();
            Some(ReedsSheppPath {
                pieces,
                length: curve.length(),
                cusps: curve.cusps(),
                curve,
            })
        })
        .collect();
    paths.sort_by(|a, b| a.length.total_cmp(&b.length));
    paths
}

/// The shortest Reeds-Shepp path from `start` to `goal` (see [`rs_paths`]).
#[must_use]
pub fn rs_shortest(start: Pose, goal: Pose, radius: f64) -> Option<ReedsSheppPath> {
    rs_paths(start, goal, radius).into_iter().next()
}

/// The Reeds-Shepp distance from `start` to `goal`, cells: the length of the shortest
/// curvature-bounded path with cusps allowed (infinite only for bad input).
#[must_use]
pub fn rs_distance(start: Pose, goal: Pose, radius: f64) -> f64 {
    let Some((x, y, phi)) = frame(start, goal, radius) else {
        return f64::INFINITY;
    };
    let mut best = f64::INFINITY;
    for i in 0..SLOTS {
        if let Some(p) = slot_pieces(i, x, y, phi) {
            let l = p.iter().map(|(_, l)| l.abs()).sum::<f64>() * radius;
            if l < best && ends_at(&build(start, &p, radius), start, goal, radius) {
                best = l;
            }
        }
    }
    best
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn slots_are_distinct_and_counted() {
        let all: Vec<_> = (0..SLOTS).map(|i| slot(i).unwrap()).collect();
        assert!(slot(SLOTS).is_none());
        for (i, a) in all.iter().enumerate() {
            for b in all.iter().skip(i + 1) {
                assert_ne!(a, b);
            }
        }
    }

    #[test]
    fn straight_ahead_and_behind() {
        let s = Pose::new(1.0, 2.0, 0.5);
        for d in [3.0, -3.0] {
            let g = Pose::new(1.0 + d * 0.5f64.cos(), 2.0 + d * 0.5f64.sin(), 0.5);
            let p = rs_shortest(s, g, 2.0).unwrap();
            assert_relative_eq!(p.length, 3.0, epsilon = 1e-9);
            assert_eq!(p.cusps, 0);
            let gear = p.curve.segments[0].gear;
            assert_eq!(gear == Gear::Reverse, d < 0.0);
        }
    }
}
