//! Poses and the pieces of a smooth path: [`Pose`], [`Segment`] (a line or a circular arc,
//! driven forward or in reverse) and [`SmoothCurve`], a chain of segments.
//!
//! Coordinates are the grid's **cell-centre coordinates**: cell `(x, y)` (column, row from
//! the top) has its centre at `(x, y)`, one unit is one cell. A heading is
//! `atan2(dy, dx)` in these coordinates, radians (a left turn increases it).
//!
//! A segment of signed curvature `kappa` (positive: steering left) driven with gear `g`
//! (`+1` forward, `-1` reverse) moves the robot's centre at unit speed along
//! `g (cos theta, sin theta)` while its heading turns at `g kappa` per unit length, so the
//! pose after a length `s` is, for `kappa != 0`,
//!
//! ```text
//! theta(s) = theta0 + g kappa s
//! p(s)     = p0 + ((sin theta(s) - sin theta0), (cos theta0 - cos theta(s))) / kappa
//! ```
//!
//! and `p0 + g s (cos theta0, sin theta0)` for a line.

use std::f64::consts::{PI, TAU};

/// A position and a heading in cell-centre coordinates (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Column coordinate, cells.
    pub x: f64,
    /// Row coordinate (down the grid), cells.
    pub y: f64,
    /// `atan2(dy, dx)` of the robot's forward direction, radians.
    pub heading_rad: f64,
}

impl Pose {
    /// A pose.
    #[must_use]
    pub const fn new(x: f64, y: f64, heading_rad: f64) -> Self {
        Self { x, y, heading_rad }
    }

    /// Distance between the positions of two poses, cells.
    #[must_use]
    pub fn distance(&self, other: &Self) -> f64 {
        (other.x - self.x).hypot(other.y - self.y)
    }
}

/// Whether a segment is driven forward or in reverse.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Gear {
    /// Driving forward.
    Forward,
    /// Driving in reverse (Reeds-Shepp paths only).
    Reverse,
}

impl Gear {
    /// `+1.0` forward, `-1.0` in reverse.
    #[must_use]
    pub fn sign(self) -> f64 {
        match self {
            Self::Forward => 1.0,
            Self::Reverse => -1.0,
        }
    }
}

/// One piece of a smooth path: a straight line (`curvature == 0`) or a circular arc of
/// radius `1 / |curvature|`, from `start`, `length` cells long (see the
/// [module docs](self) for the closed form).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Where the segment starts.
    pub start: Pose,
    /// Signed steering curvature, 1/cells: positive turns left when driving forward.
    pub curvature: f64,
    /// Length along the path, cells (non-negative).
    pub length: f64,
    /// Forward or reverse.
    pub gear: Gear,
}

impl Segment {
    /// The pose a length `s` (clamped to `0..=length`) along the segment.
    #[must_use]
    pub fn pose_at(&self, s: f64) -> Pose {
        let s = s.clamp(0.0, self.length);
        pose_along(self.start, self.curvature, self.gear.sign() * s)
    }

    /// The pose at the segment's end.
    #[must_use]
    pub fn end(&self) -> Pose {
        self.pose_at(self.length)
    }

    /// The radius of the arc, cells (`None` for a line).
    #[must_use]
    pub fn radius(&self) -> Option<f64> {
        (self.curvature != 0.0).then(|| 1.0 / self.curvature.abs())
    }

    /// The centre of the arc (`None` for a line).
    #[must_use]
    pub fn centre(&self) -> Option<[f64; 2]> {
        if self.curvature == 0.0 {
            return None;
        }
        let (sin, cos) = self.start.heading_rad.sin_cos();
        let r = 1.0 / self.curvature;
        Some([self.start.x - r * sin, self.start.y + r * cos])
    }
}

/// The pose after driving a signed length `signed_s` (negative in reverse) with curvature
/// `curvature` from `start`.
#[must_use]
pub fn pose_along(start: Pose, curvature: f64, signed_s: f64) -> Pose {
    let theta0 = start.heading_rad;
    if curvature == 0.0 {
        let (sin, cos) = theta0.sin_cos();
        return Pose::new(start.x + signed_s * cos, start.y + signed_s * sin, theta0);
    }
    let theta = theta0 + curvature * signed_s;
    Pose::new(
        start.x + (theta.sin() - theta0.sin()) / curvature,
        start.y + (theta0.cos() - theta.cos()) / curvature,
        wrap_angle(theta),
    )
}

/// An angle wrapped into `(-pi, pi]`.
#[must_use]
pub fn wrap_angle(a: f64) -> f64 {
    let w = a.rem_euclid(TAU);
    if w > PI { w - TAU } else { w }
}

/// A smooth path: segments joined end to start.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SmoothCurve {
    /// The segments, in driving order (zero-length ones are dropped by [`Self::push`]).
    pub segments: Vec<Segment>,
}

impl SmoothCurve {
    /// Append a segment unless it has no length.
    pub fn push(&mut self, segment: Segment) {
        if segment.length > 0.0 {
            self.segments.push(segment);
        }
    }

    /// Append every segment of `other`.
    pub fn extend(&mut self, other: &Self) {
        for &s in &other.segments {
            self.push(s);
        }
    }

    /// Total length, cells.
    #[must_use]
    pub fn length(&self) -> f64 {
        self.segments.iter().map(|s| s.length).sum::<f64>() + 0.0
    }

    /// Largest `|curvature|` of any segment, 1/cells (0 for a straight path).
    #[must_use]
    pub fn max_curvature(&self) -> f64 {
        self.segments
            .iter()
            .map(|s| s.curvature.abs())
            .fold(0.0, f64::max)
    }

    /// Number of changes of gear between consecutive segments (cusps).
    #[must_use]
    pub fn cusps(&self) -> usize {
        self.segments
            .windows(2)
            .filter(|w| matches!(w, [a, b] if a.gear != b.gear))
            .count()
    }

    /// Number of sign changes of the curvature along the path (lines do not reset it): a
    /// measure of wobble.
    #[must_use]
    pub fn curvature_sign_changes(&self) -> usize {
        let mut last = 0.0_f64;
        let mut changes = 0;
        for s in &self.segments {
            let k = s.curvature * s.gear.sign();
            if k != 0.0 {
                if last != 0.0 && (k > 0.0) != (last > 0.0) {
                    changes += 1;
                }
                last = k;
            }
        }
        changes
    }

    /// Poses along the path at most `spacing` cells apart (measured along it), the first
    /// the start of the first segment and the last the end of the last one; every segment
    /// end is among them. Empty for a path without segments.
    #[must_use]
    pub fn sample(&self, spacing: f64) -> Vec<Pose> {
        let mut poses = Vec::new();
        let spacing = if spacing.is_finite() && spacing > 0.0 {
            spacing
        } else {
            0.25
        };
        for (i, seg) in self.segments.iter().enumerate() {
            let n = (seg.length / spacing).ceil().max(1.0) as usize;
            let first = usize::from(i > 0);
            for k in first..=n {
                poses.push(seg.pose_at(seg.length * k as f64 / n as f64));
            }
        }
        poses
    }

    /// The segment with the largest `|curvature|` (the first such), if any is an arc.
    #[must_use]
    pub fn tightest_turn(&self) -> Option<usize> {
        self.segments
            .iter()
            .enumerate()
            .filter(|(_, s)| s.curvature != 0.0)
            .fold(None, |best: Option<(usize, f64)>, (i, s)| match best {
                Some((_, k)) if k >= s.curvature.abs() => best,
                _ => Some((i, s.curvature.abs())),
            })
            .map(|(i, _)| i)
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn quarter_circle_left_and_in_reverse() {
        let seg = Segment {
            start: Pose::new(0.0, 0.0, 0.0),
            curvature: 0.5,
            length: PI,
            gear: Gear::Forward,
        };
        let end = seg.end();
        assert_relative_eq!(end.x, 2.0, epsilon = 1e-12);
        assert_relative_eq!(end.y, 2.0, epsilon = 1e-12);
        assert_relative_eq!(end.heading_rad, PI / 2.0, epsilon = 1e-12);
        assert_eq!(seg.centre(), Some([0.0, 2.0]));
        let back = Segment {
            gear: Gear::Reverse,
            ..seg
        };
        let end = back.end();
        // Backing up while steering left swings the rear the other way: heading decreases.
        assert_relative_eq!(end.x, -2.0, epsilon = 1e-12);
        assert_relative_eq!(end.y, 2.0, epsilon = 1e-12);
        assert_relative_eq!(end.heading_rad, -PI / 2.0, epsilon = 1e-12);
    }

    #[test]
    fn samples_are_close_and_hit_both_ends() {
        let mut curve = SmoothCurve::default();
        let a = Segment {
            start: Pose::new(0.0, 0.0, 0.3),
            curvature: 0.0,
            length: 1.1,
            gear: Gear::Forward,
        };
        curve.push(a);
        curve.push(Segment {
            start: a.end(),
            curvature: -0.2,
            length: 2.0,
            gear: Gear::Forward,
        });
        let poses = curve.sample(0.25);
        assert_eq!(poses.first().copied(), Some(a.start));
        assert_eq!(
            poses.last().copied(),
            curve.segments.last().map(Segment::end)
        );
        for w in poses.windows(2) {
            assert!(w[0].distance(&w[1]) <= 0.25 + 1e-12);
        }
        assert_eq!(curve.tightest_turn(), Some(1));
        assert_eq!(curve.curvature_sign_changes(), 0);
    }
}
