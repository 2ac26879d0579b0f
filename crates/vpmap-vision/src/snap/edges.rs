//! Straight edges near a click: candidate lines of each direction by a vote of the gradient,
//! then each line's points located to a fraction of a pixel along profiles across it and
//! fitted by weighted least squares, piece by piece.

use super::patch::Patch;

/// Where an edge's direction comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EdgeDirection {
    /// Towards vanishing point `index` (0-based, in the order given; a two-point scene's
    /// vertical, perpendicular to the horizon, comes after the given ones).
    VanishingPoint(usize),
    /// A direction found in the gradient around the click, towards no vanishing point (e.g. a
    /// footprint object's sides), degrees from the image's `x` axis, in `[0, 180)`.
    Free(f64),
}

impl std::fmt::Display for EdgeDirection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::VanishingPoint(i) => write!(f, "towards vanishing point {}", i + 1),
            Self::Free(a) => write!(f, "at {a:.0} deg"),
        }
    }
}

/// A pencil of image lines: through a vanishing point `(x, y, w)` (homogeneous, `w >= 0`;
/// `w = 0` is a direction).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pencil {
    pub(crate) kind: EdgeDirection,
    vp: [f64; 3],
}

impl Pencil {
    pub(crate) fn new(kind: EdgeDirection, vp: [f64; 3]) -> Option<Self> {
        let vp = if vp[2] < 0.0 { vp.map(|v| -v) } else { vp };
        vp.iter()
            .all(|v| v.is_finite())
            .then_some(Self { kind, vp })
    }

    /// The unit direction of the pencil's line through `p` (towards the vanishing point),
    /// `None` at the vanishing point.
    pub(crate) fn direction_at(&self, p: [f64; 2]) -> Option<[f64; 2]> {
        let v = [
            self.vp[0] - self.vp[2] * p[0],
            self.vp[1] - self.vp[2] * p[1],
        ];
        let n = v[0].hypot(v[1]);
        (n > 1e-12).then(|| [v[0] / n, v[1] / n])
    }

    /// Distance from `p` to the vanishing point, pixels (infinite for a direction).
    pub(crate) fn distance_from(&self, p: [f64; 2]) -> f64 {
        if self.vp[2] <= 0.0 {
            return f64::INFINITY;
        }
        let v = [
            self.vp[0] - self.vp[2] * p[0],
            self.vp[1] - self.vp[2] * p[1],
        ];
        v[0].hypot(v[1]) / self.vp[2]
    }
}

/// One point of an edge: along-line coordinate `t`, across-line offset `s` (pixels) and
/// weight (the gradient across the edge there, grey levels per pixel).
#[derive(Clone, Copy, Debug)]
pub(crate) struct EdgePoint {
    pub(crate) t: f64,
    pub(crate) s: f64,
    pub(crate) weight: f64,
    /// The width of the edge there: the standard deviation of the Gaussian through the
    /// gradient's largest sample and its neighbours across the line (the photo's blur, the
    /// smoothing and the pixel together), pixels; NaN where a neighbour is not positive.
    pub(crate) width: f64,
}

/// A straight piece of edge in a local frame: the line `origin + t u + (alpha + beta t) n`.
#[derive(Clone, Debug)]
pub(crate) struct Piece {
    pub(crate) kind: EdgeDirection,
    pub(crate) origin: [f64; 2],
    pub(crate) u: [f64; 2],
    pub(crate) n: [f64; 2],
    pub(crate) points: Vec<EdgePoint>,
}

/// A weighted least-squares line `s = alpha + beta t` with the covariance of `(alpha, beta)`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LineFit {
    pub(crate) alpha: f64,
    pub(crate) beta: f64,
    pub(crate) cov: [[f64; 2]; 2],
    pub(crate) rms: f64,
}

/// Fit `s = alpha + beta t` to points, weights `weight^2`, Huber-reweighted.
/// `residual_floor` bounds the residual standard deviation from below (pixels).
pub(crate) fn fit_line(points: &[EdgePoint], residual_floor: f64) -> Option<LineFit> {
    if points.len() < 3 {
        return None;
    }
    let mean_w2 = points.iter().map(|p| p.weight * p.weight).sum::<f64>() / points.len() as f64;
    if mean_w2.is_nan() || mean_w2 <= 0.0 {
        return None;
    }
    let base: Vec<f64> = points
        .iter()
        .map(|p| p.weight * p.weight / mean_w2)
        .collect();
    let mut robust = vec![1.0; points.len()];
    let mut out = None;
    for _ in 0..4 {
        let (mut sw, mut st, mut ss, mut stt, mut sts) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for ((p, b), r) in points.iter().zip(&base).zip(&robust) {
            let w = b * r;
            sw += w;
            st += w * p.t;
            ss += w * p.s;
            stt += w * p.t * p.t;
            sts += w * p.t * p.s;
        }
        let det = sw * stt - st * st;
        if det.is_nan() || det <= 1e-12 * sw * sw.max(1.0) {
            return None;
        }
        let beta = (sw * sts - st * ss) / det;
        let alpha = (ss - beta * st) / sw;
        let residuals: Vec<f64> = points.iter().map(|p| p.s - alpha - beta * p.t).collect();
        let dof = (points.len() - 2).max(1) as f64;
        let chi: f64 = residuals
            .iter()
            .zip(&base)
            .zip(&robust)
            .map(|((r, b), w)| b * w * r * r)
            .sum();
        let sigma2 = (chi / dof).max(residual_floor * residual_floor);
        // (A^T W A)^-1 = [[stt, -st], [-st, sw]] / det.
        let cov = [
            [sigma2 * stt / det, -sigma2 * st / det],
            [-sigma2 * st / det, sigma2 * sw / det],
        ];
        let scale = sigma2.sqrt();
        out = Some(LineFit {
            alpha,
            beta,
            cov,
            rms: (residuals.iter().map(|r| r * r).sum::<f64>() / points.len() as f64).sqrt(),
        });
        for ((w, r), b) in robust.iter_mut().zip(&residuals).zip(&base) {
            let z = r.abs() * b.sqrt() / (1.5 * scale);
            *w = if z <= 1.0 { 1.0 } else { 1.0 / z };
        }
    }
    out
}

impl Piece {
    /// The fitted line as a point and a unit direction, in image pixels.
    pub(crate) fn line(&self, fit: &LineFit) -> ([f64; 2], [f64; 2]) {
        line_of(self.origin, self.u, self.n, fit.alpha, fit.beta)
    }

    /// Along-line coordinate of an image point.
    pub(crate) fn t_of(&self, p: [f64; 2]) -> f64 {
        (p[0] - self.origin[0]) * self.u[0] + (p[1] - self.origin[1]) * self.u[1]
    }

    /// The median width of its points' gradient profiles, pixels (`None` when no point has
    /// one): how blurred the edge is, the smoothing included.
    pub(crate) fn width_px(&self) -> Option<f64> {
        let mut w: Vec<f64> = self
            .points
            .iter()
            .map(|p| p.width)
            .filter(|w| w.is_finite())
            .collect();
        w.sort_by(f64::total_cmp);
        w.get(w.len() / 2).copied()
    }

    /// First and last `t` of its points.
    pub(crate) fn range(&self) -> (f64, f64) {
        let first = self.points.first().map_or(0.0, |p| p.t);
        let last = self.points.last().map_or(0.0, |p| p.t);
        (first, last)
    }
}

/// The line `origin + t u + (alpha + beta t) n` as a point and a unit direction.
pub(crate) fn line_of(
    origin: [f64; 2],
    u: [f64; 2],
    n: [f64; 2],
    alpha: f64,
    beta: f64,
) -> ([f64; 2], [f64; 2]) {
    let point = [origin[0] + alpha * n[0], origin[1] + alpha * n[1]];
    let d = [u[0] + beta * n[0], u[1] + beta * n[1]];
    let len = d[0].hypot(d[1]);
    (point, [d[0] / len, d[1] / len])
}

/// The settings edge finding needs.
pub(crate) struct EdgeSearch {
    pub(crate) click: [f64; 2],
    /// Largest distance of a line from the click, pixels.
    pub(crate) radius: f64,
    /// How far lines are followed from the click, pixels.
    pub(crate) reach: f64,
    /// Smallest gradient across an edge, grey levels per pixel.
    pub(crate) min_gradient: f64,
    /// `tan` of the largest angle between the gradient and a line's normal.
    pub(crate) tan_tolerance: f64,
    /// Smallest number of edge points in a piece.
    pub(crate) min_points: usize,
    /// Smallest vote of a candidate line (grey levels).
    pub(crate) min_vote: f64,
}

/// Bin width of the line vote, pixels.
const BIN_PX: f64 = 0.5;
/// Candidate lines kept per direction and polarity.
const PEAKS_PER_DIRECTION: usize = 3;
/// Profile half-width across a candidate line, first pass and second pass, pixels.
const PROFILE_PX: [f64; 2] = [3.0, 1.5];
/// Profile sampling step, pixels.
const PROFILE_STEP_PX: f64 = 0.5;
/// Largest gap in an edge piece, pixels: up to three missing points in a row. A stroke, a
/// pipe or a clutter line across an edge turns the gradient over its own width and the
/// blur's on each side, so a few points in a row fail the angle test; with 2 px (one missing
/// point) every such crossing cut the edge, and the piece next to the corner was often too
/// short to keep (issue 38). Chosen on York Urban and the cluttered renders together (2, 3
/// and 4 px; `docs/snapping.md`).
const MAX_GAP_PX: f64 = 4.0;

/// Dominant gradient directions around the click that none of `pencils` explains: up to two
/// free pencils (constant directions).
pub(crate) fn free_pencils(patch: &Patch, search: &EdgeSearch, pencils: &[Pencil]) -> Vec<Pencil> {
    const BINS: usize = 36;
    let mut hist = [0.0f64; BINS];
    let reach2 = search.reach * search.reach;
    for (p, g) in patch.pixels() {
        let (dx, dy) = (p[0] - search.click[0], p[1] - search.click[1]);
        let m = g[0].hypot(g[1]);
        if dx * dx + dy * dy > reach2 || m < search.min_gradient {
            continue;
        }
        // Edge direction: the gradient turned by 90 degrees, modulo 180.
        let angle = (g[1].atan2(g[0]) + std::f64::consts::FRAC_PI_2)
            .rem_euclid(std::f64::consts::PI)
            .to_degrees();
        let bin = ((angle / (180.0 / BINS as f64)) as usize).min(BINS - 1);
        if let Some(h) = hist.get_mut(bin) {
            *h += m;
        }
    }
    let tolerance_deg = search.tan_tolerance.atan().to_degrees();
    let explained = |angle: f64| {
        pencils.iter().any(|pc| {
            pc.direction_at(search.click).is_some_and(|u| {
                let a = u[1].atan2(u[0]).to_degrees().rem_euclid(180.0);
                let d = (a - angle).rem_euclid(180.0);
                d.min(180.0 - d) < 2.0 * tolerance_deg
            })
        })
    };
    let smoothed: Vec<f64> = (0..BINS)
        .map(|i| hist[(i + BINS - 1) % BINS] + 2.0 * hist[i % BINS] + hist[(i + 1) % BINS])
        .collect();
    let mut peaks: Vec<(f64, f64)> = (0..BINS)
        .filter(|&i| {
            let v = smoothed[i];
            v > smoothed[(i + BINS - 1) % BINS] && v >= smoothed[(i + 1) % BINS]
        })
        .map(|i| {
            // Parabolic refinement of the peak's angle.
            let (a, b, c) = (
                smoothed[(i + BINS - 1) % BINS],
                smoothed[i],
                smoothed[(i + 1) % BINS],
            );
            let den = a - 2.0 * b + c;
            let off = if den.abs() > 1e-12 {
                0.5 * (a - c) / den
            } else {
                0.0
            };
            let angle = ((i as f64 + 0.5 + off) * 180.0 / BINS as f64).rem_euclid(180.0);
            (angle, b / 4.0)
        })
        .filter(|&(angle, mass)| mass >= 2.0 * search.min_vote && !explained(angle))
        .collect();
    peaks.sort_by(|a, b| b.1.total_cmp(&a.1));
    peaks
        .into_iter()
        .take(2)
        .filter_map(|(angle, _)| {
            let r = angle.to_radians();
            Pencil::new(EdgeDirection::Free(angle), [r.cos(), r.sin(), 0.0])
        })
        .collect()
}

/// Candidate lines of one pencil: offsets from the click (pixels) and polarity (+1 or -1),
/// strongest first.
fn candidate_lines(patch: &Patch, search: &EdgeSearch, pencil: &Pencil) -> Vec<(f64, f64)> {
    let half = search.radius + 1.0;
    let bins = (2.0 * half / BIN_PX).ceil() as usize + 1;
    let mut votes = vec![[0.0f64; 2]; bins];
    let reach2 = search.reach * search.reach;
    for (p, g) in patch.pixels() {
        let (dx, dy) = (p[0] - search.click[0], p[1] - search.click[1]);
        if dx * dx + dy * dy > reach2 {
            continue;
        }
        let Some(u) = pencil.direction_at(p) else {
            continue;
        };
        let n = [-u[1], u[0]];
        let (gn, gu) = (g[0] * n[0] + g[1] * n[1], g[0] * u[0] + g[1] * u[1]);
        if gn.abs() < search.min_gradient || gu.abs() > search.tan_tolerance * gn.abs() {
            continue;
        }
        let s = n[0] * dx + n[1] * dy;
        if s.abs() > half {
            continue;
        }
        let bin = ((s + half) / BIN_PX).round() as usize;
        if let Some(v) = votes.get_mut(bin) {
            v[usize::from(gn < 0.0)] += gn.abs();
        }
    }
    let mut out = Vec::new();
    for polarity in 0..2 {
        let column: Vec<f64> = votes.iter().map(|v| v[polarity]).collect();
        // Mass within 1.5 px of each bin.
        let reach = (1.5 / BIN_PX) as usize;
        let mass: Vec<f64> = (0..bins)
            .map(|i| {
                column
                    .get(i.saturating_sub(reach)..(i + reach + 1).min(bins))
                    .map_or(0.0, |s| s.iter().sum())
            })
            .collect();
        let mut peaks: Vec<(f64, f64)> = (0..bins)
            .filter(|&i| {
                let m = mass[i];
                m >= search.min_vote
                    && (i == 0 || m > mass[i - 1])
                    && (i + 1 == bins || m >= mass[i + 1])
            })
            .map(|i| {
                (
                    i as f64 * BIN_PX - half,
                    mass[i] * if polarity == 0 { 1.0 } else { -1.0 },
                )
            })
            .collect();
        peaks.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
        out.extend(peaks.into_iter().take(PEAKS_PER_DIRECTION));
    }
    out.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
    out.into_iter().map(|(s, m)| (s, m.signum())).collect()
}

/// Edge points along a line, each located to a sub-pixel offset by a parabola through the
/// largest gradient across the line (of the given polarity) and its neighbours.
fn profile_points(
    patch: &Patch,
    search: &EdgeSearch,
    frame: ([f64; 2], [f64; 2], [f64; 2]),
    fit: Option<&LineFit>,
    polarity: f64,
    half_width: f64,
) -> Vec<EdgePoint> {
    let (origin, u, n) = frame;
    let steps = (half_width / PROFILE_STEP_PX).round() as i64;
    let mut points = Vec::new();
    let span = search.reach.floor() as i64;
    for ti in -span..=span {
        let t = ti as f64;
        let centre = fit.map_or(0.0, |f| f.alpha + f.beta * t);
        let mut samples = Vec::with_capacity((2 * steps + 1) as usize);
        for k in -steps..=steps {
            let s = centre + k as f64 * PROFILE_STEP_PX;
            let p = [
                origin[0] + t * u[0] + s * n[0],
                origin[1] + t * u[1] + s * n[1],
            ];
            let value = patch.gradient(p).map(|g| {
                let gn = polarity * (g[0] * n[0] + g[1] * n[1]);
                let gu = g[0] * u[0] + g[1] * u[1];
                (gn, gu)
            });
            samples.push((s, value));
        }
        let best = samples
            .iter()
            .enumerate()
            .filter_map(|(i, (_, v))| v.map(|v| (i, v)))
            .max_by(|a, b| a.1.0.total_cmp(&b.1.0));
        let Some((i, (gn, gu))) = best else {
            continue;
        };
        if i == 0 || i + 1 == samples.len() {
            continue;
        }
        if gn < search.min_gradient || gu.abs() > search.tan_tolerance * gn {
            continue;
        }
        let (Some((_, Some(a))), Some((_, Some(c)))) = (samples.get(i - 1), samples.get(i + 1))
        else {
            continue;
        };
        let den = a.0 - 2.0 * gn + c.0;
        let offset = if den < -1e-12 {
            (0.5 * (a.0 - c.0) / den).clamp(-0.5, 0.5)
        } else {
            0.0
        };
        let s = samples.get(i).map_or(0.0, |x| x.0) + offset * PROFILE_STEP_PX;
        // A Gaussian's logarithm is a parabola: `sigma^2 = -h^2 / (ln a - 2 ln b + ln c)`.
        let curvature = if a.0 > 0.0 && c.0 > 0.0 {
            a.0.ln() - 2.0 * gn.ln() + c.0.ln()
        } else {
            f64::NAN
        };
        let width = if curvature < 0.0 {
            PROFILE_STEP_PX / (-curvature).sqrt()
        } else {
            f64::NAN
        };
        points.push(EdgePoint {
            t,
            s,
            weight: gn,
            width,
        });
    }
    points
}

/// Split points (in increasing `t`) into runs without gaps longer than [`MAX_GAP_PX`].
fn runs(points: Vec<EdgePoint>) -> Vec<Vec<EdgePoint>> {
    let mut out: Vec<Vec<EdgePoint>> = Vec::new();
    for p in points {
        match out.last_mut() {
            Some(run) if run.last().is_some_and(|q| p.t - q.t <= MAX_GAP_PX) => run.push(p),
            _ => out.push(vec![p]),
        }
    }
    out
}

/// The straight edge pieces of one pencil near the click.
pub(crate) fn pieces(patch: &Patch, search: &EdgeSearch, pencil: &Pencil) -> Vec<Piece> {
    let mut out: Vec<Piece> = Vec::new();
    let Some(uc) = pencil.direction_at(search.click) else {
        return out;
    };
    let nc = [-uc[1], uc[0]];
    for (s0, polarity) in candidate_lines(patch, search, pencil) {
        let origin = [search.click[0] + s0 * nc[0], search.click[1] + s0 * nc[1]];
        let Some(u) = pencil.direction_at(origin) else {
            continue;
        };
        let n = [-u[1], u[0]];
        let frame = (origin, u, n);
        let first = profile_points(patch, search, frame, None, polarity, PROFILE_PX[0]);
        for run in runs(first) {
            if run.len() < search.min_points {
                continue;
            }
            let Some(fit) = fit_line(&run, 0.05) else {
                continue;
            };
            // Second pass: a narrow profile around the fitted line, over the run's extent.
            let (lo, hi) = (
                run.first().map_or(0.0, |p| p.t) - MAX_GAP_PX,
                run.last().map_or(0.0, |p| p.t) + MAX_GAP_PX,
            );
            let second: Vec<EdgePoint> =
                profile_points(patch, search, frame, Some(&fit), polarity, PROFILE_PX[1])
                    .into_iter()
                    .filter(|p| p.t >= lo && p.t <= hi)
                    .collect();
            for points in runs(second) {
                if points.len() < search.min_points {
                    continue;
                }
                let piece = Piece {
                    kind: pencil.kind,
                    origin,
                    u,
                    n,
                    points,
                };
                if !out.iter().any(|o| same_piece(o, &piece)) {
                    out.push(piece);
                }
            }
        }
    }
    out
}

/// Whether two pieces are the same edge (found from two neighbouring candidates).
fn same_piece(a: &Piece, b: &Piece) -> bool {
    let (Some(fa), Some(fb)) = (fit_line(&a.points, 0.05), fit_line(&b.points, 0.05)) else {
        return false;
    };
    let (pa, _) = a.line(&fa);
    let (pb, db) = b.line(&fb);
    let off = ((pa[0] - pb[0]) * db[1] - (pa[1] - pb[1]) * db[0]).abs();
    let (a0, a1) = a.range();
    let (b0, b1) = b.range();
    let overlap = a0.max(b0) <= a1.min(b1) + MAX_GAP_PX;
    off < 1.0 && overlap
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_fit_recovers_a_known_line_and_scales_its_covariance_with_noise() {
        let pts = |noise: f64| -> Vec<EdgePoint> {
            (0..20)
                .map(|i| {
                    let t = f64::from(i) - 10.0;
                    let wiggle = if i % 2 == 0 { noise } else { -noise };
                    EdgePoint {
                        t,
                        s: 0.3 + 0.05 * t + wiggle,
                        weight: 10.0,
                        width: 1.0,
                    }
                })
                .collect()
        };
        let Some(exact) = fit_line(&pts(0.0), 0.0) else {
            panic!("no fit");
        };
        assert!((exact.alpha - 0.3).abs() < 1e-9 && (exact.beta - 0.05).abs() < 1e-9);
        let (Some(a), Some(b)) = (fit_line(&pts(0.1), 0.0), fit_line(&pts(0.2), 0.0)) else {
            panic!("no fit");
        };
        assert!((b.cov[0][0] / a.cov[0][0] - 4.0).abs() < 0.2);
    }

    #[test]
    fn a_pencil_points_at_its_vanishing_point() {
        let Some(p) = Pencil::new(EdgeDirection::VanishingPoint(0), [-200.0, -100.0, -1.0]) else {
            panic!("pencil");
        };
        let u = p.direction_at([0.0, 0.0]).unwrap_or([0.0; 2]);
        assert!((u[0] - 200f64 / 200f64.hypot(100.0)).abs() < 1e-12);
        assert!((p.distance_from([0.0, 0.0]) - 200f64.hypot(100.0)).abs() < 1e-9);
    }
}
