//! A corner from edge pieces: the pair of pieces along different directions that meet
//! nearest the click with the most support, refitted without the blurred corner itself, their
//! intersection and its covariance (first-order propagation of the line fits').

use super::edges::{EdgeDirection, LineFit, Piece, fit_line, line_of};

/// A corner found from two edge pieces.
pub(crate) struct Corner {
    pub(crate) point: [f64; 2],
    pub(crate) cov: [[f64; 2]; 2],
    /// The two pieces' fitted lines, the number of points used and their mean gradient.
    pub(crate) edges: [CornerEdge; 2],
}

/// One edge of a corner as fitted.
pub(crate) struct CornerEdge {
    pub(crate) kind: EdgeDirection,
    pub(crate) point: [f64; 2],
    pub(crate) direction: [f64; 2],
    pub(crate) support_px: f64,
    pub(crate) strength: f64,
    pub(crate) rms_px: f64,
    /// The distance from the corner to the nearest point where the edge was seen, pixels.
    pub(crate) gap_px: f64,
    /// The part of that gap beyond what the blur hides, pixels (what the covariance's unseen
    /// term counts).
    pub(crate) unseen_px: f64,
    /// The angle between the fitted line and its pencil's direction, radians, and one
    /// standard deviation of it from the fit (`None` for a free direction).
    pub(crate) off_pencil: Option<(f64, f64)>,
}

/// Why no corner was found near the click.
pub(crate) enum NoCorner {
    /// No edge piece at all.
    NoEdge,
    /// Edge pieces along one direction only.
    OneDirection(EdgeDirection),
    /// Pieces along two or more directions that do not meet within the radius (nearest
    /// meeting point and its distance, if they meet at all).
    NoMeeting(Option<([f64; 2], f64)>),
    /// A corner within the radius that the edges do not support well enough.
    Unsure([f64; 2], Doubt),
}

/// Why a corner found near a click is not trusted (the checks of `SnapOptions::min_edge_px`,
/// `max_edge_rms_px`, `vp_direction_sd_deg` and `max_rival_ratio`, and the junction).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Doubt {
    /// One edge passes on through the corner: a T junction, mostly an edge in front hiding
    /// one behind, whose meeting point lies on no object's corner.
    TJunction,
    /// An edge has too few points on its side of the corner, pixels of support.
    ShortEdge {
        /// The shorter edge's support, pixels.
        support_px: f64,
        /// The least accepted, pixels.
        required_px: f64,
    },
    /// An edge is not straight: its points lie farther from its fitted line than the blur
    /// and the noise allow (texture, a rounded or curved edge).
    RoughEdge {
        /// The larger root-mean-square distance of an edge's points from its line, pixels.
        rms_px: f64,
        /// The largest accepted, pixels.
        allowed_px: f64,
    },
    /// An edge chosen towards a vanishing point runs off it by more than the fit and the
    /// vanishing point's uncertainty allow.
    OffVanishingPoint {
        /// The angle between the fitted edge and the line to its vanishing point, degrees.
        angle_deg: f64,
        /// Three standard deviations of that angle, degrees.
        allowed_deg: f64,
    },
    /// Another corner of nearly the same strength lies within the search radius.
    Rival {
        /// The other corner, pixels.
        other_px: [f64; 2],
        /// Its score over the chosen corner's.
        ratio: f64,
    },
}

/// The sine of the smallest angle between two edges that meet at a corner (6 degrees): a
/// corner of nearly parallel edges is found, with a covariance that says how poorly.
const MIN_SINE: f64 = 0.1;

/// Intersection of two lines given by point and direction (`None` when nearly parallel).
pub(crate) fn intersect(
    p1: [f64; 2],
    d1: [f64; 2],
    p2: [f64; 2],
    d2: [f64; 2],
) -> Option<[f64; 2]> {
    let den = d1[0] * d2[1] - d1[1] * d2[0];
    if den.abs() < MIN_SINE {
        return None;
    }
    let a = ((p2[0] - p1[0]) * d2[1] - (p2[1] - p1[1]) * d2[0]) / den;
    Some([p1[0] + a * d1[0], p1[1] + a * d1[1]])
}

/// The settings of the corner search.
pub(crate) struct CornerSearch {
    pub(crate) click: [f64; 2],
    pub(crate) radius: f64,
    /// Points nearer the corner than this are left out of the final fits, pixels.
    pub(crate) gap: f64,
    /// How far from the corner edge points are used, pixels.
    pub(crate) length: f64,
    pub(crate) min_points: usize,
    /// Multiplier of the line fits' covariance (correlated neighbouring points).
    pub(crate) covariance_scale: f64,
    /// Added to the corner's standard deviation per axis, pixels.
    pub(crate) covariance_floor: f64,
    /// Standard deviation added per pixel of an edge not seen next to the corner.
    pub(crate) unseen_sd_per_px: f64,
    /// The least support of each edge beside the corner for a snap, pixels.
    pub(crate) min_edge_px: f64,
    /// The largest root-mean-square distance of an edge's points from its line, pixels.
    pub(crate) max_rms_px: f64,
    /// One standard deviation of the image direction of a vanishing point's line, radians.
    pub(crate) vp_direction_sd: f64,
    /// A rival corner this strong (score ratio) makes the snap unsure.
    pub(crate) max_rival_ratio: f64,
}

/// The score factor of a T junction against an L or Y junction.
const T_JUNCTION_WEIGHT: f64 = 0.2;

/// A rival corner farther than this from the chosen one makes the choice ambiguous, pixels.
const AMBIGUITY_PX: f64 = 1.0;

/// A rival corner farther than this from the chosen one can make the snap unsure, pixels.
const RIVAL_PX: f64 = 2.0;

/// The part of an edge next to a corner that blur alone hides, in edge widths: within about
/// two widths of the corner the other edge's gradient turns this one's by more than the
/// angle tolerance allows.
const UNSEEN_BLUR_WIDTHS: f64 = 2.0;

/// The spacing of an edge's points along it, pixels (one a pixel): the nearest seen point
/// may lie this much beyond where the blur stops hiding the edge.
const POINT_SPACING_PX: f64 = 1.0;

/// How far past a piece's end the corner may lie, pixels (the blur eats the last pixels).
const END_SLACK_PX: f64 = 3.0;

/// The points of a piece used for a corner at `t_corner`: at least `gap` and at most
/// `length` from it.
fn near_corner(
    piece: &Piece,
    t_corner: f64,
    gap: f64,
    length: f64,
) -> Vec<super::edges::EdgePoint> {
    piece
        .points
        .iter()
        .filter(|p| {
            let d = (p.t - t_corner).abs();
            d >= gap && d <= length
        })
        .copied()
        .collect()
}

/// The distance along a piece from `x` to its nearest point, pixels.
fn seen_gap(piece: &Piece, x: [f64; 2]) -> f64 {
    let tc = piece.t_of(x);
    piece
        .points
        .iter()
        .map(|q| (q.t - tc).abs())
        .fold(f64::INFINITY, f64::min)
}

/// Whether a piece ends at (or passes through) `t` and whether it ends there.
fn reaches(piece: &Piece, t: f64, gap: f64) -> (bool, bool) {
    let (lo, hi) = piece.range();
    let slack = END_SLACK_PX + gap;
    let inside = t >= lo - slack && t <= hi + slack;
    let ends = (t - lo).abs() <= slack || (t - hi).abs() <= slack;
    (inside, ends)
}

/// The best corner among the pieces, or why there is none.
pub(crate) fn find_corner(pieces: &[Piece], search: &CornerSearch) -> Result<Corner, NoCorner> {
    if pieces.is_empty() {
        return Err(NoCorner::NoEdge);
    }
    let fits: Vec<Option<LineFit>> = pieces.iter().map(|p| fit_line(&p.points, 0.05)).collect();
    let mut best: Option<(f64, usize, usize, [f64; 2], bool)> = None;
    // Every candidate corner and its score, for the ambiguity term of the covariance.
    let mut candidates: Vec<(f64, [f64; 2])> = Vec::new();
    let mut nearest: Option<([f64; 2], f64)> = None;
    let sigma_prior = search.radius / 2.5;
    for (i, (a, fa)) in pieces.iter().zip(&fits).enumerate() {
        let Some(fa) = fa else { continue };
        for (j, (b, fb)) in pieces.iter().zip(&fits).enumerate().skip(i + 1) {
            let Some(fb) = fb else { continue };
            if a.kind == b.kind {
                continue;
            }
            let (pa, da) = a.line(fa);
            let (pb, db) = b.line(fb);
            let Some(x) = intersect(pa, da, pb, db) else {
                continue;
            };
            let (ia, ea) = reaches(a, a.t_of(x), search.gap);
            let (ib, eb) = reaches(b, b.t_of(x), search.gap);

            if !(ia && ib && (ea || eb)) {
                continue;
            }
            let d = (x[0] - search.click[0]).hypot(x[1] - search.click[1]);
            if nearest.is_none_or(|n| d < n.1) {
                nearest = Some((x, d));
            }
            if d > search.radius {
                continue;
            }
            let support = |p: &Piece, t: f64| -> f64 {
                near_corner(p, t, 0.0, search.length)
                    .iter()
                    .map(|q| q.weight)
                    .sum()
            };
            // A T junction (one edge passes on) is mostly an edge in front hiding one behind;
            // it wins only without an L or Y nearby (e.g. a top corner on the horizon,
            // where both top edges lie on one image line).
            let junction = if ea && eb { 1.0 } else { T_JUNCTION_WEIGHT };
            let score = junction
                * (support(a, a.t_of(x)) * support(b, b.t_of(x))).sqrt()
                * (-0.5 * (d / sigma_prior).powi(2)).exp();
            candidates.push((score, x));
            if best.is_none_or(|bst| score > bst.0) {
                best = Some((score, i, j, x, ea && eb));
            }
        }
    }
    let Some((best_score, i, j, mut x, l_junction)) = best else {
        let kinds: Vec<EdgeDirection> = pieces.iter().map(|p| p.kind).collect();
        return Err(if kinds.iter().all(|k| *k == kinds[0]) {
            NoCorner::OneDirection(kinds[0])
        } else {
            NoCorner::NoMeeting(nearest)
        });
    };
    let (Some(a), Some(b)) = (pieces.get(i), pieces.get(j)) else {
        return Err(NoCorner::NoEdge);
    };
    // Refit without the corner's blurred neighbourhood, twice (the corner moves a little).
    let mut result = None;
    for _ in 0..2 {
        let pa = near_corner(a, a.t_of(x), search.gap, search.length);
        let pb = near_corner(b, b.t_of(x), search.gap, search.length);
        if pa.len() < search.min_points.min(4) || pb.len() < search.min_points.min(4) {
            break;
        }
        let (Some(fa), Some(fb)) = (fit_line(&pa, 0.05), fit_line(&pb, 0.05)) else {
            break;
        };
        let Some(corner) = corner_of(a, &fa, &pa, b, &fb, &pb, search) else {
            break;
        };
        x = corner.point;
        result = Some(corner);
    }
    match result {
        Some(mut c)
            if (c.point[0] - search.click[0]).hypot(c.point[1] - search.click[1])
                <= search.radius =>
        {
            if let Some(doubt) = doubt(&c, l_junction, best_score, &candidates, search) {
                return Err(NoCorner::Unsure(c.point, doubt));
            }
            // Ambiguity: the strongest rival corner more than a pixel away, taken as the
            // other component of a two-point mixture weighted by the scores, adds
            // `p (x2 - x1)(x2 - x1)^T` with `p = s2 / (s1 + s2)`.
            if let Some((s2, x2)) = candidates
                .iter()
                .filter(|(_, y)| (y[0] - c.point[0]).hypot(y[1] - c.point[1]) > AMBIGUITY_PX)
                .max_by(|a, b| a.0.total_cmp(&b.0))
            {
                let p = s2 / (best_score + s2);
                let d = [x2[0] - c.point[0], x2[1] - c.point[1]];
                for (r, dr) in d.iter().enumerate() {
                    for (k, dk) in d.iter().enumerate() {
                        c.cov[r][k] += p * dr * dk;
                    }
                }
            }
            Ok(c)
        }
        Some(c) => {
            let d = (c.point[0] - search.click[0]).hypot(c.point[1] - search.click[1]);
            Err(NoCorner::NoMeeting(Some((c.point, d))))
        }
        None => Err(NoCorner::NoMeeting(nearest)),
    }
}

/// The intersection of two fitted pieces and its covariance.
fn corner_of(
    a: &Piece,
    fa: &LineFit,
    pa: &[super::edges::EdgePoint],
    b: &Piece,
    fb: &LineFit,
    pb: &[super::edges::EdgePoint],
    search: &CornerSearch,
) -> Option<Corner> {
    let at = |theta: [f64; 4]| -> Option<[f64; 2]> {
        let (p1, d1) = line_of(a.origin, a.u, a.n, theta[0], theta[1]);
        let (p2, d2) = line_of(b.origin, b.u, b.n, theta[2], theta[3]);
        intersect(p1, d1, p2, d2)
    };
    let theta = [fa.alpha, fa.beta, fb.alpha, fb.beta];
    let x = at(theta)?;
    // Numerical Jacobian d x / d theta (central differences).
    let mut jac = [[0.0; 4]; 2];
    for k in 0..4 {
        let h = 1e-6;
        let (mut up, mut down) = (theta, theta);
        up[k] += h;
        down[k] -= h;
        let (xu, xd) = (at(up)?, at(down)?);
        for r in 0..2 {
            jac[r][k] = (xu[r] - xd[r]) / (2.0 * h);
        }
    }
    // Block-diagonal covariance of theta.
    let mut cov_theta = [[0.0; 4]; 4];
    for r in 0..2 {
        for c in 0..2 {
            cov_theta[r][c] = fa.cov[r][c] * search.covariance_scale;
            cov_theta[r + 2][c + 2] = fb.cov[r][c] * search.covariance_scale;
        }
    }
    let mut cov = [[0.0; 2]; 2];
    for r in 0..2 {
        for c in 0..2 {
            let mut s = 0.0;
            for k in 0..4 {
                for l in 0..4 {
                    s += jac[r][k] * cov_theta[k][l] * jac[c][l];
                }
            }
            cov[r][c] = s;
        }
    }
    // Each edge's gap to the corner and the part of it the blur does not explain.
    let unseen = |piece: &Piece| -> (f64, f64) {
        let gap = seen_gap(piece, x);
        let width = piece.width_px().unwrap_or(1.0);
        (
            gap,
            (gap - UNSEEN_BLUR_WIDTHS * width - POINT_SPACING_PX).max(0.0),
        )
    };
    let (unseen_a, unseen_b) = (unseen(a), unseen(b));
    // What the edges do not show: the corner is carried along each line over the stretch
    // next to it where the edge was not seen, beyond what the blur hides; a junction's own
    // structure (a frame, a moulding, a rounded edge) can sit there.
    let kappa = search.unseen_sd_per_px;
    let floor = search.covariance_floor * search.covariance_floor
        + kappa * kappa * (unseen_a.1.powi(2) + unseen_b.1.powi(2));
    cov[0][0] += floor;
    cov[1][1] += floor;
    let edge = |piece: &Piece,
                fit: &LineFit,
                points: &[super::edges::EdgePoint],
                (gap_px, unseen_px): (f64, f64)| {
        let (p, d) = piece.line(fit);
        // The line's point nearest the corner.
        let t = (x[0] - p[0]) * d[0] + (x[1] - p[1]) * d[1];
        CornerEdge {
            kind: piece.kind,
            point: [p[0] + t * d[0], p[1] + t * d[1]],
            direction: d,
            support_px: points.len() as f64,
            strength: points.iter().map(|q| q.weight).sum::<f64>() / points.len().max(1) as f64,
            rms_px: fit.rms,
            gap_px,
            unseen_px,
            off_pencil: matches!(piece.kind, EdgeDirection::VanishingPoint(_)).then(|| {
                (
                    fit.beta.atan(),
                    (fit.cov[1][1] * search.covariance_scale).max(0.0).sqrt(),
                )
            }),
        }
    };
    Some(Corner {
        point: x,
        cov,
        edges: [edge(a, fa, pa, unseen_a), edge(b, fb, pb, unseen_b)],
    })
}

/// The first reason the chosen corner is not trusted, if any: a T junction, an edge too short
/// or too rough, an edge off its vanishing point, a rival corner nearly as strong.
fn doubt(
    c: &Corner,
    l_junction: bool,
    score: f64,
    candidates: &[(f64, [f64; 2])],
    search: &CornerSearch,
) -> Option<Doubt> {
    if !l_junction {
        return Some(Doubt::TJunction);
    }
    let shortest = c
        .edges
        .iter()
        .map(|e| e.support_px)
        .fold(f64::INFINITY, f64::min);
    if shortest < search.min_edge_px {
        return Some(Doubt::ShortEdge {
            support_px: shortest,
            required_px: search.min_edge_px,
        });
    }
    let roughest = c.edges.iter().map(|e| e.rms_px).fold(0.0, f64::max);
    if roughest > search.max_rms_px {
        return Some(Doubt::RoughEdge {
            rms_px: roughest,
            allowed_px: search.max_rms_px,
        });
    }
    for e in &c.edges {
        if let Some((angle, sd)) = e.off_pencil {
            let allowed = 3.0 * sd.hypot(search.vp_direction_sd);
            if angle.abs() > allowed {
                return Some(Doubt::OffVanishingPoint {
                    angle_deg: angle.abs().to_degrees(),
                    allowed_deg: allowed.to_degrees(),
                });
            }
        }
    }
    candidates
        .iter()
        .filter(|(_, y)| (y[0] - c.point[0]).hypot(y[1] - c.point[1]) > RIVAL_PX)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .filter(|(s2, _)| *s2 > search.max_rival_ratio * score)
        .map(|(s2, y)| Doubt::Rival {
            other_px: *y,
            ratio: s2 / score,
        })
}
