//! Box proposals: cuboid candidates from the line segments, named by their corners as a
//! person would click them (`docs/scene-format.md`, corner view).
//!
//! [`propose_boxes`] takes the photo's segments (e.g. [`crate::Detection::segments`]) and its
//! vanishing points (two horizontal, then the vertical; with two, the vertical is taken
//! perpendicular to the horizon) and looks for a box's near vertical edge with its two base
//! edges:
//!
//! 1. every segment at least [`ProposalOptions::min_length_px`] long is assigned to the
//!    vanishing point its line runs to, within [`ProposalOptions::angle_tolerance_deg`];
//! 2. every vertical segment is a candidate near edge: its lower end is the base near corner,
//!    its upper end the top near corner;
//!    (collinear vertical pieces with gaps under 30 px are joined: LSD breaks an edge where the
//!    background changes);
//! 3. at the base near corner a horizontal segment along one or both horizontal directions
//!    must start (an end within [`ProposalOptions::join_px`]), running *towards* its vanishing
//!    point (a box's base edges recede from its near corner; a room's far corner, whose floor
//!    lines come towards the camera, is no box); their far ends are the base corners `right`
//!    and `left` (by image `x`); at the top near corner, horizontal segments that start there
//!    give `top.right` and `top.left` the same way;
//! 4. every corner is snapped ([`crate::snap::snap_click`]); a proposal needs its base corners
//!    inside the photo, keeps the top corners that snap, needs three corners in all (with one
//!    base edge, the top near corner among them), and is scored by the length of its
//!    segments times the share of its corners that snapped; proposals sharing a base near
//!    corner (within 4 px) keep the best.
//!
//! On a photo with a lens ([`ProposalOptions::lens`]) the vanishing points are the pinhole
//! camera's while the segments are the photo's: each segment, edge and corner is matched with
//! the directions the photo's bowed edges have where it lies
//! ([`crate::snap::scene::vanishing_points_at`]).
//!
//! # Bounded work
//! Only the [`ProposalOptions::max_segments`] longest segments are used, and only the
//! [`ProposalOptions::max_corners`] longest vertical edges are tried as near edges (each
//! costs up to six snaps); [`ProposalOptions::interrupt`] is looked at before each. Without
//! the caps a photo of a thousand small dark squares (11,000 segments) took 22 s in a debug
//! build.
//!
//! # Complexity
//! `O(n log n + c (n + s))` for `n` segments used, `c` near edges tried and `s` the cost of a
//! snap (a patch of about 13 x 13 pixels).

use std::borrow::Cow;

use vpmap_metrology::interrupt::Interrupt;
use vpmap_metrology::scene::{BoxCorners, DivisionModel};

use crate::detection::Segment;
use crate::error::{Result, VisionError};
use crate::snap::scene::vanishing_points_at;
use crate::snap::{SnapImage, SnapOptions, snap_click};

/// Options of [`propose_boxes`].
#[derive(Clone, Debug, PartialEq)]
pub struct ProposalOptions {
    /// Shortest segment used, pixels.
    pub min_length_px: f64,
    /// Largest angle between a segment and its vanishing direction, degrees.
    pub angle_tolerance_deg: f64,
    /// Largest gap between the segments meeting at a corner, pixels.
    pub join_px: f64,
    /// At most this many proposals, best first.
    pub max_proposals: usize,
    /// Only this many segments are used, the longest (at least 1).
    pub max_segments: usize,
    /// Only this many vertical edges are tried as a box's near edge, the longest (at least 1).
    pub max_corners: usize,
    /// Stops the search early ([`VisionError::Interrupted`]); looked at before each near edge.
    pub interrupt: Interrupt,
    /// The photo's lens (`None`: a pinhole's). With one, the vanishing points are the pinhole
    /// camera's while the segments and the photo are the lens's: each segment, edge and corner
    /// is matched with the directions the photo's bowed edges have where it lies
    /// ([`vanishing_points_at`]).
    pub lens: Option<DivisionModel>,
}

/// [`ProposalOptions::max_segments`] by default.
pub const DEFAULT_MAX_SEGMENTS: usize = 4000;
/// [`ProposalOptions::max_corners`] by default.
pub const DEFAULT_MAX_CORNERS: usize = 400;

impl Default for ProposalOptions {
    fn default() -> Self {
        Self {
            min_length_px: 12.0,
            angle_tolerance_deg: 2.0,
            join_px: 8.0,
            max_proposals: 20,
            max_segments: DEFAULT_MAX_SEGMENTS,
            max_corners: DEFAULT_MAX_CORNERS,
            interrupt: Interrupt::default(),
            lens: None,
        }
    }
}

/// One proposed box.
#[derive(Clone, Debug, PartialEq)]
pub struct BoxProposal {
    /// Its base corners (corner view: `near`, `right`, `left`).
    pub base: BoxCorners,
    /// Its top corners (`near`, and `right`, `left` where found).
    pub top: BoxCorners,
    /// Higher is better: supporting segment length, pixels, times the share of corners that
    /// snapped.
    pub score: f64,
}

/// Largest gap between collinear vertical pieces taken as one edge, pixels.
const MERGE_GAP_PX: f64 = 30.0;

/// A segment with its direction index and ends.
#[derive(Clone, Copy)]
struct Edge {
    dir: usize,
    a: [f64; 2],
    b: [f64; 2],
    len: f64,
}

fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).hypot(p[1] - q[1])
}

fn towards(vp: [f64; 3], p: [f64; 2]) -> Option<[f64; 2]> {
    let vp = if vp[2] < 0.0 { vp.map(|v| -v) } else { vp };
    let v = [vp[0] - vp[2] * p[0], vp[1] - vp[2] * p[1]];
    let n = v[0].hypot(v[1]);
    (n > 1e-12).then(|| [v[0] / n, v[1] / n])
}

/// The horizontal edge of direction `dir` that starts at `corner` (an end within `join`) and
/// runs towards its vanishing point (or, with `receding` false, either way): its far end and
/// length.
fn edge_from(
    edges: &[Edge],
    vps: &[[f64; 3]],
    dir: usize,
    corner: [f64; 2],
    join: f64,
    receding: bool,
) -> Option<([f64; 2], f64)> {
    edges
        .iter()
        .filter(|e| e.dir == dir)
        .filter_map(|e| {
            let (near, far) = if dist(e.a, corner) <= dist(e.b, corner) {
                (e.a, e.b)
            } else {
                (e.b, e.a)
            };
            if dist(near, corner) > join {
                return None;
            }
            let u = towards(*vps.get(dir)?, corner)?;
            let along = (far[0] - corner[0]) * u[0] + (far[1] - corner[1]) * u[1];
            (!receding || along > 0.0).then_some((far, e.len))
        })
        .max_by(|x, y| x.1.total_cmp(&y.1))
}

/// Propose boxes from line segments and vanishing points (see the [module docs](self)).
///
/// # Errors
/// [`VisionError::InvalidParameter`] for options out of range or fewer than two vanishing
/// points; [`VisionError::Interrupted`] when [`ProposalOptions::interrupt`] fires.
pub fn propose_boxes(
    image: &SnapImage,
    segments: &[Segment],
    vanishing_points: &[[f64; 3]],
    opts: &ProposalOptions,
) -> Result<Vec<BoxProposal>> {
    if vanishing_points.len() < 2 {
        return Err(VisionError::InvalidParameter {
            field: "vanishing_points",
            value: vanishing_points.len() as f64,
            requirement: "must hold two or three vanishing points",
        });
    }
    if !(opts.min_length_px.is_finite()
        && opts.min_length_px > 0.0
        && opts.angle_tolerance_deg > 0.0
        && opts.angle_tolerance_deg < 45.0
        && opts.join_px.is_finite()
        && opts.join_px >= 0.0)
    {
        return Err(VisionError::InvalidParameter {
            field: "ProposalOptions",
            value: opts.min_length_px,
            requirement: "needs a positive min_length_px, an angle tolerance in (0, 45) degrees and a non-negative join_px",
        });
    }
    for (field, value) in [
        ("max_segments", opts.max_segments),
        ("max_corners", opts.max_corners),
    ] {
        if value == 0 {
            return Err(VisionError::InvalidParameter {
                field,
                value: 0.0,
                requirement: "must be at least 1",
            });
        }
    }
    // The longest segments (a stable order: equal lengths keep the caller's order).
    let mut by_length: Vec<&Segment> = segments.iter().collect();
    by_length.sort_by(|a, b| b.length_px().total_cmp(&a.length_px()));
    by_length.truncate(opts.max_segments);
    let given: Vec<[f64; 3]> = vanishing_points.iter().take(3).copied().collect();
    let mut vps = given.clone();
    if let [a, b] = vanishing_points {
        // No horizon (the two points coincide): the vertical direction is (0, 0), as before.
        vps.push(crate::snap::two_point_vertical(*a, *b).unwrap_or([0.0; 3]));
    }
    // The vanishing points as the photo shows them at `p` (the three, the vertical added).
    // Without a lens they are the same everywhere: borrowed, not copied for every segment.
    let vps_at = |p: [f64; 2]| -> Cow<'_, [[f64; 3]]> {
        match opts.lens.as_ref().filter(|l| l.k != 0.0) {
            Some(lens) => Cow::Owned(vanishing_points_at(&given, Some(lens), p)),
            None => Cow::Borrowed(&vps),
        }
    };
    let cos_tol = opts.angle_tolerance_deg.to_radians().cos();
    let edges: Vec<Edge> = by_length
        .into_iter()
        .filter_map(|s| {
            let len = s.length_px();
            if len < opts.min_length_px {
                return None;
            }
            let d = [
                (s.end_px[0] - s.start_px[0]) / len,
                (s.end_px[1] - s.start_px[1]) / len,
            ];
            let mid = [
                0.5 * (s.start_px[0] + s.end_px[0]),
                0.5 * (s.start_px[1] + s.end_px[1]),
            ];
            let (dir, c) = vps_at(mid)
                .iter()
                .enumerate()
                .filter_map(|(k, v)| {
                    towards(*v, mid).map(|u| (k, (u[0] * d[0] + u[1] * d[1]).abs()))
                })
                .max_by(|x, y| x.1.total_cmp(&y.1))?;
            (c >= cos_tol).then_some(Edge {
                dir,
                a: s.start_px,
                b: s.end_px,
                len,
            })
        })
        .collect();
    let snap_opts = SnapOptions {
        search_radius_px: 6.0,
        ..SnapOptions::default()
    };
    let (w, h) = (f64::from(image.width()), f64::from(image.height()));
    let snap = |p: [f64; 2]| -> Option<([f64; 2], bool)> {
        if !(p[0] >= 0.0 && p[1] >= 0.0 && p[0] <= w && p[1] <= h) {
            return None;
        }
        let s = snap_click(image, &vps_at(p), p, &snap_opts).ok()?;
        Some((s.point_px, s.snapped()))
    };
    let mut out: Vec<BoxProposal> = Vec::new();
    // The edges are longest first: the longest vertical edges are tried.
    for (tried, v) in edges
        .iter()
        .filter(|e| e.dir == 2)
        .take(opts.max_corners)
        .enumerate()
    {
        if let Some(reason) = opts.interrupt.check() {
            return Err(VisionError::Interrupted {
                work: format!(
                    "box proposals (after {tried} of at most {} near edges, {} found so far)",
                    opts.max_corners,
                    out.len()
                ),
                reason,
            });
        }
        let (mut bottom, mut top) = if v.a[1] >= v.b[1] {
            (v.a, v.b)
        } else {
            (v.b, v.a)
        };
        // Collinear vertical pieces with short gaps are one edge (LSD breaks edges where the
        // background changes).
        let (o, d) = (bottom, [top[0] - bottom[0], top[1] - bottom[1]]);
        let n = (d[0] * d[0] + d[1] * d[1]).sqrt().max(1e-9);
        let off = |p: [f64; 2]| ((p[0] - o[0]) * d[1] - (p[1] - o[1]) * d[0]).abs() / n;
        for w in edges.iter().filter(|e| e.dir == 2) {
            if off(w.a) > 2.0 || off(w.b) > 2.0 {
                continue;
            }
            for p in [w.a, w.b] {
                if p[1] > bottom[1] && dist(p, bottom) < MERGE_GAP_PX + w.len {
                    bottom = p;
                }
                if p[1] < top[1] && dist(p, top) < MERGE_GAP_PX + w.len {
                    top = p;
                }
            }
        }
        let at_bottom = vps_at(bottom);
        let base_a = edge_from(&edges, &at_bottom, 0, bottom, opts.join_px, true);
        let base_b = edge_from(&edges, &at_bottom, 1, bottom, opts.join_px, true);
        let (right, left, la, lb) = match (base_a, base_b) {
            (Some((fa, la)), Some((fb, lb))) => {
                if fa[0] >= fb[0] {
                    (Some(fa), Some(fb), la, lb)
                } else {
                    (Some(fb), Some(fa), la, lb)
                }
            }
            // One base edge: right or left by the side it runs to.
            (Some((f, l)), None) | (None, Some((f, l))) => {
                if f[0] >= bottom[0] {
                    (Some(f), None, l, 0.0)
                } else {
                    (None, Some(f), l, 0.0)
                }
            }
            (None, None) => continue,
        };
        let at_top = vps_at(top);
        let top_a = edge_from(&edges, &at_top, 0, top, opts.join_px, false);
        let top_b = edge_from(&edges, &at_top, 1, top, opts.join_px, false);
        let mut corners = vec![("base.near", bottom)];
        corners.extend(right.map(|p| ("base.right", p)));
        corners.extend(left.map(|p| ("base.left", p)));
        let mut length = v.len + la + lb;
        let mut optional = vec![("top.near", top)];
        let tops: Vec<([f64; 2], f64)> = [top_a, top_b].into_iter().flatten().collect();
        if let [x, y] = tops.as_slice() {
            let (r, l) = if x.0[0] >= y.0[0] { (x, y) } else { (y, x) };
            optional.push(("top.right", r.0));
            optional.push(("top.left", l.0));
            length += r.1 + l.1;
        }
        let mut snapped = 0;
        let mut base = BoxCorners::default();
        let mut topc = BoxCorners::default();
        let mut ok = true;
        let mut place = |name: &str, q: [f64; 2]| {
            let slot = match name {
                "base.near" => &mut base.near,
                "base.right" => &mut base.right,
                "base.left" => &mut base.left,
                "top.near" => &mut topc.near,
                "top.right" => &mut topc.right,
                _ => &mut topc.left,
            };
            *slot = Some(q);
        };
        for (name, p) in &corners {
            let Some((q, moved)) = snap(*p) else {
                ok = false;
                break;
            };
            snapped += usize::from(moved);
            place(name, q);
        }
        if !ok {
            continue;
        }
        let needed = corners.len();
        // Top corners only where they snap (a tall box's top may be outside the photo).
        for (name, p) in &optional {
            if let Some((q, true)) = snap(*p) {
                snapped += 1;
                place(name, q);
                corners.push((name, q));
            }
        }
        // A box needs three corners, and with one base edge its top near corner.
        if corners.len() < 3 || (needed < 3 && topc.near.is_none()) {
            continue;
        }
        let score = length * snapped as f64 / corners.len() as f64;
        let near = base.near.unwrap_or(bottom);
        if let Some(existing) = out
            .iter_mut()
            .find(|p| p.base.near.is_some_and(|q| dist(q, near) < 4.0))
        {
            if score > existing.score {
                *existing = BoxProposal {
                    base,
                    top: topc,
                    score,
                };
            }
            continue;
        }
        out.push(BoxProposal {
            base,
            top: topc,
            score,
        });
    }
    out.sort_by(|a, b| b.score.total_cmp(&a.score));
    out.truncate(opts.max_proposals);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{DynamicImage, GrayImage};
    use std::sync::Arc;
    use std::sync::atomic::AtomicBool;

    fn segment(a: [f64; 2], b: [f64; 2]) -> Segment {
        Segment {
            start_px: a,
            end_px: b,
            strength: 1.0,
        }
    }

    /// Vertical edges (and a base edge at each foot) on a blank 200 x 200 photo.
    fn edges() -> (SnapImage, Vec<Segment>, Vec<[f64; 3]>) {
        let image = SnapImage::new(&DynamicImage::ImageLuma8(GrayImage::new(200, 200)));
        let mut segments = Vec::new();
        for k in 0..10 {
            let x = 10.0 + 15.0 * f64::from(k);
            segments.push(segment([x, 150.0], [x, 100.0 - f64::from(k)]));
            segments.push(segment([x, 150.0], [x + 12.0, 150.0]));
        }
        let vps = vec![[1.0, 0.0, 0.0], [100.0, -5000.0, 1.0], [0.0, 1.0, 0.0]];
        (image, segments, vps)
    }

    #[test]
    fn a_cancelled_search_stops_before_its_first_corner() {
        let (image, segments, vps) = edges();
        let flag = Arc::new(AtomicBool::new(true));
        let opts = ProposalOptions {
            interrupt: Interrupt::default().with_flag(flag),
            ..ProposalOptions::default()
        };
        let e = propose_boxes(&image, &segments, &vps, &opts).unwrap_err();
        assert!(
            matches!(&e, VisionError::Interrupted { work, .. } if work.contains("after 0 of at most 400")),
            "{e}"
        );
        assert!(e.to_string().ends_with("the request was cancelled"), "{e}");
        // Not cancelled: the search runs to its end.
        assert!(propose_boxes(&image, &segments, &vps, &ProposalOptions::default()).is_ok());
    }

    #[test]
    fn the_caps_are_at_least_one() {
        let (image, segments, vps) = edges();
        for opts in [
            ProposalOptions {
                max_segments: 0,
                ..ProposalOptions::default()
            },
            ProposalOptions {
                max_corners: 0,
                ..ProposalOptions::default()
            },
        ] {
            let e = propose_boxes(&image, &segments, &vps, &opts).unwrap_err();
            assert!(e.to_string().contains("must be at least 1"), "{e}");
        }
        // One corner tried, with a deadline far ahead.
        let one = ProposalOptions {
            max_corners: 1,
            interrupt: Interrupt::default().with_timeout(std::time::Duration::from_secs(3600)),
            ..ProposalOptions::default()
        };
        assert!(propose_boxes(&image, &segments, &vps, &one).is_ok());
    }
}
