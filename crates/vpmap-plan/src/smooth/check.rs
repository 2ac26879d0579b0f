//! The independent check of a smooth path ([`validate_smooth`]): for **every point** of
//! the continuous curve, not only samples, curvature at most `1 / R`, the tangent
//! continuous, and the collision rule of [`crate::los`] extended from segments between
//! cell centres to any point: the unit square centred on the robot's position (in
//! cell-centre coordinates, see [`super::curve`]) overlaps the interior of no blocked cell
//! (cells outside the grid count as blocked). Equivalently, the position is in no open
//! square of side 2 centred on a blocked cell's centre — the rule
//! [`crate::validate::validate_path`] decides for polylines, so on a polyline through cell
//! centres the two agree.
//!
//! # Method
//! Each segment is cut into pieces at most [`PIECE_CELLS`] long. Every blocked cell whose
//! open square could reach a piece (its centre within 1.5 cells of the piece's end's
//! bounding box) is tested exactly: the parameters where the piece's line or arc crosses
//! the four lines bounding the square (shrunk by [`TOUCH_TOLERANCE`]) are solved in closed
//! form (`x(s) = const` on a line is linear, on an arc `cos psi = const`), and the piece is
//! inside the square on some open interval exactly when the midpoint of one of the
//! intervals between consecutive crossings (or an end) is inside. The geometry is
//! computed here from the segments' parameters, not by [`super::curve`]'s functions.
//!
//! A path grazing a blocked square within [`TOUCH_TOLERANCE`] cells counts as touching,
//! which the rule allows.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use thiserror::Error;

use super::curve::{Gear, Pose, Segment, SmoothCurve};
use crate::grid::OccupancyGrid;
use crate::validate::passable;

/// Longest piece a segment is cut into for the collision test, cells.
pub const PIECE_CELLS: f64 = 0.5;

/// How far (cells) a path may reach into a blocked cell's square and still count as
/// touching it: floating-point round-off in the segments' ends.
pub const TOUCH_TOLERANCE: f64 = 1e-9;

/// Largest gap between a segment's end and the next one's start, cells, and between their
/// headings, radians, that still counts as continuous.
pub const JOIN_TOLERANCE: f64 = 1e-6;

/// What a smooth path must satisfy besides the grid (see [`validate_smooth`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(clippy::struct_excessive_bools)] // four independent yes/no rules of the query
pub struct SmoothRules {
    /// Smallest turning radius, cells.
    pub radius_cells: f64,
    /// The start pose (its heading checked only when `start_heading` is set).
    pub start: Pose,
    /// Whether the start heading is prescribed.
    pub start_heading: bool,
    /// The goal pose (its heading checked only when `goal_heading` is set).
    pub goal: Pose,
    /// Whether the goal heading is prescribed.
    pub goal_heading: bool,
    /// Whether reverse segments are allowed.
    pub reverse: bool,
    /// Whether unknown cells may be entered.
    pub unknown_passable: bool,
}

/// Why a smooth path is not drivable.
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum SmoothViolation {
    /// A segment has a non-finite parameter or a negative length.
    #[error("segment {segment} has a non-finite parameter or a negative length")]
    Malformed {
        /// Index of the segment.
        segment: usize,
    },
    /// A segment turns more tightly than the turning radius allows.
    #[error(
        "segment {segment} turns with radius {radius_cells:.6} cells, below the turning radius {min_radius_cells}"
    )]
    TooTight {
        /// Index of the segment.
        segment: usize,
        /// Its radius, cells.
        radius_cells: f64,
        /// The turning radius, cells.
        min_radius_cells: f64,
    },
    /// Two consecutive segments do not meet, or meet at an angle.
    #[error("segments {segment} and {} do not join: gap {gap_cells:.3e} cells, heading jump {jump_rad:.3e} rad", segment + 1)]
    Discontinuous {
        /// Index of the first segment.
        segment: usize,
        /// Distance between its end and the next start, cells.
        gap_cells: f64,
        /// Heading difference, radians.
        jump_rad: f64,
    },
    /// The path does not start or end at the asked pose.
    #[error("the path's {end} is off the asked pose by {gap_cells:.3e} cells, {jump_rad:.3e} rad")]
    WrongEnd {
        /// `start` or `goal`.
        end: &'static str,
        /// Distance, cells.
        gap_cells: f64,
        /// Heading difference (0 when the heading is free), radians.
        jump_rad: f64,
    },
    /// A reverse segment where only forward driving is allowed.
    #[error("segment {segment} is driven in reverse, which is not allowed")]
    Reverse {
        /// Index of the segment.
        segment: usize,
    },
    /// The robot's square overlaps a blocked cell.
    #[error("segment {segment} overlaps blocked cell ({}, {}) near ({:.3}, {:.3})", cell.0, cell.1, at[0], at[1])]
    Collision {
        /// Index of the segment.
        segment: usize,
        /// The blocked cell (possibly outside the grid).
        cell: (i64, i64),
        /// A point of the segment inside that cell's square, cells.
        at: [f64; 2],
    },
    /// The path has no segment but start and goal differ.
    #[error("the path is empty")]
    Empty,
}

/// Heading difference wrapped into `[0, pi]`.
fn angle_gap(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    d.min(TAU - d)
}

/// The independent geometry of one segment: a line or an arc, by its own formulas.
#[derive(Clone, Copy, Debug)]
enum Shape {
    /// `p(s) = p0 + s v`.
    Line { p0: [f64; 2], v: [f64; 2] },
    /// `p(s) = c + r (cos psi(s), sin psi(s))`, `psi(s) = psi0 + w s`.
    Arc {
        c: [f64; 2],
        r: f64,
        psi0: f64,
        w: f64,
    },
}

impl Shape {
    fn of(seg: &Segment) -> Self {
        let g = match seg.gear {
            Gear::Forward => 1.0,
            Gear::Reverse => -1.0,
        };
        let th = seg.start.heading_rad;
        let p0 = [seg.start.x, seg.start.y];
        if seg.curvature == 0.0 {
            return Self::Line {
                p0,
                v: [g * th.cos(), g * th.sin()],
            };
        }
        let r = 1.0 / seg.curvature.abs();
        let side = seg.curvature.signum();
        // The centre lies on the steering side of the heading.
        let c = [
            p0[0] + side * r * (th + FRAC_PI_2).cos(),
            p0[1] + side * r * (th + FRAC_PI_2).sin(),
        ];
        let psi0 = (p0[1] - c[1]).atan2(p0[0] - c[0]);
        Self::Arc {
            c,
            r,
            psi0,
            w: g * side / r,
        }
    }

    fn at(&self, s: f64) -> [f64; 2] {
        match *self {
            Self::Line { p0, v } => [p0[0] + s * v[0], p0[1] + s * v[1]],
            Self::Arc { c, r, psi0, w } => {
                let psi = psi0 + w * s;
                [c[0] + r * psi.cos(), c[1] + r * psi.sin()]
            }
        }
    }

    /// Parameters in `(lo, hi)` where coordinate `axis` equals `value`.
    fn crossings(&self, axis: usize, value: f64, lo: f64, hi: f64, out: &mut Vec<f64>) {
        match *self {
            Self::Line { p0, v } => {
                if v[axis] != 0.0 {
                    let s = (value - p0[axis]) / v[axis];
                    if s > lo && s < hi {
                        out.push(s);
                    }
                }
            }
            Self::Arc { c, r, psi0, w } => {
                let u = (value - c[axis]) / r;
                if u.abs() > 1.0 {
                    return;
                }
                let angles = if axis == 0 {
                    let a = u.acos();
                    [a, -a]
                } else {
                    let a = u.asin();
                    [a, PI - a]
                };
                let period = TAU / w.abs();
                for a in angles {
                    // Smallest s >= 0 with psi0 + w s = a (mod 2 pi), then every period.
                    let mut s = ((a - psi0) * w.signum()).rem_euclid(TAU) / w.abs();
                    while s < hi {
                        if s > lo {
                            out.push(s);
                        }
                        s += period;
                    }
                }
            }
        }
    }
}

/// Whether the piece `lo..=hi` of `seg` enters the open square of half-side
/// `1 - TOUCH_TOLERANCE` centred on `(bx, by)`; the point inside when it does.
#[must_use]
pub fn piece_enters_square(seg: &Segment, lo: f64, hi: f64, b: (i64, i64)) -> Option<[f64; 2]> {
    piece_enters(&Shape::of(seg), lo, hi, b)
}

fn piece_enters(shape: &Shape, lo: f64, hi: f64, b: (i64, i64)) -> Option<[f64; 2]> {
    let h = 1.0 - TOUCH_TOLERANCE;
    let (bx, by) = (b.0 as f64, b.1 as f64);
    let inside = |p: [f64; 2]| (p[0] - bx).abs() < h && (p[1] - by).abs() < h;
    let mut ss = vec![lo, hi];
    for (axis, centre) in [(0, bx), (1, by)] {
        shape.crossings(axis, centre - h, lo, hi, &mut ss);
        shape.crossings(axis, centre + h, lo, hi, &mut ss);
    }
    ss.sort_by(f64::total_cmp);
    for p in [shape.at(lo), shape.at(hi)] {
        if inside(p) {
            return Some(p);
        }
    }
    ss.windows(2).find_map(|w| match w {
        [a, b] => Some(shape.at(0.5 * (a + b))).filter(|&p| inside(p)),
        _ => None,
    })
}

/// The first blocked cell a segment's swept square overlaps, with a point inside it.
pub(crate) fn segment_collision(
    grid: &OccupancyGrid,
    seg: &Segment,
    unknown_passable: bool,
) -> Option<((i64, i64), [f64; 2])> {
    let shape = Shape::of(seg);
    let pieces = (seg.length / PIECE_CELLS).ceil().max(1.0) as usize;
    for k in 0..pieces {
        let lo = seg.length * k as f64 / pieces as f64;
        let hi = seg.length * (k + 1) as f64 / pieces as f64;
        let (a, b) = (shape.at(lo), shape.at(hi));
        // Every point of the piece is within (hi - lo) / 2 <= 0.25 of an end.
        let reach = 1.0 + 0.5 * (hi - lo);
        let x0 = (a[0].min(b[0]) - reach).floor() as i64;
        let x1 = (a[0].max(b[0]) + reach).ceil() as i64;
        let y0 = (a[1].min(b[1]) - reach).floor() as i64;
        let y1 = (a[1].max(b[1]) + reach).ceil() as i64;
        for y in y0..=y1 {
            for x in x0..=x1 {
                if !passable(grid, x, y, unknown_passable)
                    && let Some(p) = piece_enters(&shape, lo, hi, (x, y))
                {
                    return Some(((x, y), p));
                }
            }
        }
    }
    None
}

/// Check that `curve` is drivable on `grid` under `rules` (see the [module docs](self)):
/// well-formed segments, curvature at most `1 / rules.radius_cells` (with a relative
/// tolerance of 1e-9), consecutive segments joined in position and heading (within
/// [`JOIN_TOLERANCE`]; a change of gear keeps the heading, which makes a cusp), the path
/// starting and ending at the asked poses, reverse segments only when allowed, and no
/// point of any segment in a blocked cell's square.
///
/// # Errors
/// The first [`SmoothViolation`] found, in that order of checks, segments in order.
///
/// # Complexity
/// `O(length)` pieces, each tested against the few cells around it.
pub fn validate_smooth(
    grid: &OccupancyGrid,
    curve: &SmoothCurve,
    rules: &SmoothRules,
) -> Result<(), SmoothViolation> {
    let segs = &curve.segments;
    for (i, s) in segs.iter().enumerate() {
        let finite = [
            s.start.x,
            s.start.y,
            s.start.heading_rad,
            s.curvature,
            s.length,
        ]
        .iter()
        .all(|v| v.is_finite());
        if !finite || s.length < 0.0 {
            return Err(SmoothViolation::Malformed { segment: i });
        }
        if s.curvature.abs() * rules.radius_cells > 1.0 + 1e-9 {
            return Err(SmoothViolation::TooTight {
                segment: i,
                radius_cells: 1.0 / s.curvature.abs(),
                min_radius_cells: rules.radius_cells,
            });
        }
        if s.gear == Gear::Reverse && !rules.reverse {
            return Err(SmoothViolation::Reverse { segment: i });
        }
    }
    for (i, w) in segs.windows(2).enumerate() {
        let [a, b] = w else { continue };
        let (shape, len) = (Shape::of(a), a.length);
        let end = shape.at(len);
        let end_heading = match shape {
            Shape::Line { .. } => a.start.heading_rad,
            Shape::Arc { .. } => a.start.heading_rad + a.curvature * a.gear_sign() * len,
        };
        let gap = (end[0] - b.start.x).hypot(end[1] - b.start.y);
        let jump = angle_gap(end_heading, b.start.heading_rad);
        if gap > JOIN_TOLERANCE || jump > JOIN_TOLERANCE {
            return Err(SmoothViolation::Discontinuous {
                segment: i,
                gap_cells: gap,
                jump_rad: jump,
            });
        }
    }
    let (first, last) = match (segs.first(), segs.last()) {
        (Some(f), Some(l)) => (f.start, {
            let p = Shape::of(l).at(l.length);
            let h = l.start.heading_rad + l.curvature * l.gear_sign() * l.length;
            Pose::new(p[0], p[1], h)
        }),
        _ if rules.start.distance(&rules.goal) <= JOIN_TOLERANCE
            && (!rules.start_heading
                || !rules.goal_heading
                || angle_gap(rules.start.heading_rad, rules.goal.heading_rad)
                    <= JOIN_TOLERANCE) =>
        {
            (rules.start, rules.goal)
        }
        _ => return Err(SmoothViolation::Empty),
    };
    for (end, got, want, heading) in [
        ("start", first, rules.start, rules.start_heading),
        ("goal", last, rules.goal, rules.goal_heading),
    ] {
        let gap = got.distance(&want);
        let jump = if heading {
            angle_gap(got.heading_rad, want.heading_rad)
        } else {
            0.0
        };
        if gap > JOIN_TOLERANCE || jump > JOIN_TOLERANCE {
            return Err(SmoothViolation::WrongEnd {
                end,
                gap_cells: gap,
                jump_rad: jump,
            });
        }
    }
    for (i, s) in segs.iter().enumerate() {
        if let Some((cell, at)) = segment_collision(grid, s, rules.unknown_passable) {
            return Err(SmoothViolation::Collision {
                segment: i,
                cell,
                at,
            });
        }
    }
    // A path without segments is the start itself: its square must be clear too.
    if segs.is_empty() {
        let point = Segment {
            start: rules.start,
            curvature: 0.0,
            length: 0.0,
            gear: Gear::Forward,
        };
        if let Some((cell, at)) = segment_collision(grid, &point, rules.unknown_passable) {
            return Err(SmoothViolation::Collision {
                segment: 0,
                cell,
                at,
            });
        }
    }
    Ok(())
}

impl Segment {
    fn gear_sign(&self) -> f64 {
        match self.gear {
            Gear::Forward => 1.0,
            Gear::Reverse => -1.0,
        }
    }
}
