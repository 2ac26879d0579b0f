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
}

/// Intersection of two lines given by point and direction (`None` when nearly parallel).
pub(crate) fn intersect(
    p1: [f64; 2],
    d1: [f64; 2],
    p2: [f64; 2],
    d2: [f64; 2],
) -> Option<[f64; 2]> {
    let den = d1[0] * d2[1] - d1[1] * d2[0];
    if den.abs() < 0.17 {
        // Less than about 10 degrees apart.
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
}

/// The score factor of a T junction against an L or Y junction.
const T_JUNCTION_WEIGHT: f64 = 0.2;

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
    let mut best: Option<(f64, usize, usize, [f64; 2])> = None;
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
            if best.is_none_or(|bst| score > bst.0) {
                best = Some((score, i, j, x));
            }
        }
    }
    let Some((_, i, j, mut x)) = best else {
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
        Some(c)
            if (c.point[0] - search.click[0]).hypot(c.point[1] - search.click[1])
                <= search.radius =>
        {
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
    let floor = search.covariance_floor * search.covariance_floor;
    cov[0][0] += floor;
    cov[1][1] += floor;
    let edge = |piece: &Piece, fit: &LineFit, points: &[super::edges::EdgePoint]| {
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
        }
    };
    Some(Corner {
        point: x,
        cov,
        edges: [edge(a, fa, pa), edge(b, fb, pb)],
    })
}
