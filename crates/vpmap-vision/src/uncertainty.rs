//! How well a detected vanishing point is known: its covariance from the segments that support
//! it, plus a floor for what the segments' own spread cannot show.
//!
//! Model. Each supporting segment is an observation of the vanishing point: the distance of its
//! end from the line through its midpoint and the point, times `sqrt(2)` (the fit's segment
//! residual, `vpmap_metrology`'s `fit/model.rs`), with standard deviation `sigma` under
//! independent endpoint noise. The point is parametrised by two angles in the scene's
//! [`VpChart`] (*across* and *radial*); a few Gauss-Newton steps find the least-squares point
//! of the segments, and its covariance is `sigma^2 (J^T W J)^-1`, where
//!
//! * segments farther than [`OUTLIER_SIGMAS`] `sigma` from the first fit are dropped (re-selection, `sigma`
//!   robustly 1.4826 times the residuals' median absolute value); the final `sigma` is the kept
//!   residuals' root mean square over their degrees of freedom (never below
//!   [`MIN_SEGMENT_SIGMA_PX`]), and the covariance is widened from the chi-square to the F
//!   quantile (Hotelling's `T^2`) for a noise estimated from few edges;
//! * pieces of one physical edge count as one: segments on (nearly) one line (within
//!   [`SAME_EDGE_DEG`] and [`SAME_EDGE_PX`]) share a weight of 1 (`W`), since their errors are
//!   the edge's, not independent.
//!
//! The segments' spread cannot show what moves all of them alike: edges of the scene that are
//! not quite along the room's axes, lens distortion, a focal length the chart gets wrong. That
//! is a **floor** added to the covariance, [`VP_FLOOR_SD_DEG`] (1 sd on each axis), measured on
//! York Urban's labelled photos (`docs/detection.md`, "How sure a vanishing point is").
//!
//! The least-squares point itself, not held orthogonal to the other directions, is
//! [`own_point`]: each detected direction's own vanishing point
//! ([`VanishingPoint::own_point`](crate::VanishingPoint::own_point)).
//!
//! Hartley and Zisserman, *Multiple View Geometry*, 2nd ed., 5.2 (covariance of a
//! least-squares estimate) and 8.6.1 (vanishing points from segments).

use nalgebra::{Matrix2, Vector2, Vector3};
use vpmap_metrology::scene::VpChart;

use crate::detection::{OwnPoint, Segment};

/// The model-error floor of a detected vanishing point, degrees: one standard deviation on
/// each axis of its chart, added to the segments' own covariance. Measured on the 51 York
/// Urban training photos: the smallest floor, in steps of 0.1 degrees, whose 95 % ellipses hold
/// at least 92 % of the labelled directions both with the true intrinsics given and with them
/// estimated (93.5 % and 94.1 %; 0.9 degrees gives 92.8 % and 90.2 %), measured by
/// `vpmap eval-detect` (`docs/detection.md`). It includes the labels' own error (they are
/// about a degree from orthogonal).
pub const VP_FLOOR_SD_DEG: f64 = 1.0;

/// The least endpoint noise assumed of a detected segment, pixels.
pub const MIN_SEGMENT_SIGMA_PX: f64 = 0.3;

/// Segments whose directions differ by less than this, degrees, and ...
pub const SAME_EDGE_DEG: f64 = 1.0;

/// ... whose ends lie within this of each other's line, pixels, are pieces of one edge.
pub const SAME_EDGE_PX: f64 = 2.0;

/// Segments farther than this many (robust) sigmas from the first fit are dropped: far enough
/// that a noise estimated from a dozen edges drops few good ones (which would make it small).
pub const OUTLIER_SIGMAS: f64 = 4.0;

/// The chi-square quantile with 2 degrees of freedom at 95 %.
const CHI2_2DOF_95: f64 = 5.991_464_547_107_979;

/// Gauss-Newton steps towards the segments' least-squares point.
const STEPS: usize = 5;

/// A vanishing point's covariance from its segments and the floor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VpCovariance {
    /// The covariance in the chart's *across* and *radial* angles, degrees squared, floor
    /// included.
    pub covariance_deg2: [[f64; 2]; 2],
    /// The segments' part alone (`None` when they do not fix the point: fewer than three
    /// edges, which leave no residual to estimate their noise from, or all through one line).
    pub segments_deg2: Option<[[f64; 2]; 2]>,
    /// The segments' estimated endpoint noise, pixels.
    pub sigma_px: f64,
    /// Segments kept (within [`OUTLIER_SIGMAS`] sigma).
    pub inliers: usize,
    /// Independent edges among them (pieces of one edge counted once).
    pub edges: usize,
}

impl VpCovariance {
    /// The largest standard deviation (major axis of the ellipse), degrees.
    #[must_use]
    pub fn major_sd_deg(&self) -> f64 {
        let [[a, b], [_, d]] = self.covariance_deg2;
        let mean = 0.5 * (a + d);
        (mean + (0.25 * (a - d) * (a - d) + b * b).sqrt())
            .max(0.0)
            .sqrt()
    }
}

/// The point of `chart` direction `g` moved by angles `delta` along its axes, homogeneous
/// pixels.
pub(crate) fn moved(chart: &VpChart, g: Vector3<f64>, delta: Vector2<f64>) -> Vector3<f64> {
    let (across, radial) = VpChart::axes(g);
    let d = (g + across * delta.x.tan() + radial * delta.y.tan()).normalize();
    Vector3::new(
        chart.focal_px * d.x + chart.centre_px.x * d.z,
        chart.focal_px * d.y + chart.centre_px.y * d.z,
        d.z,
    )
}

/// Segment `s`'s residual for homogeneous point `v`, pixels (see the module docs).
pub(crate) fn residual(s: &Segment, v: Vector3<f64>) -> f64 {
    let m = Vector3::new(
        0.5 * (s.start_px[0] + s.end_px[0]),
        0.5 * (s.start_px[1] + s.end_px[1]),
        1.0,
    );
    let line = m.cross(&v);
    let norm = line.x.hypot(line.y);
    if norm > 0.0 {
        std::f64::consts::SQRT_2 * (line.x * s.start_px[0] + line.y * s.start_px[1] + line.z) / norm
    } else {
        0.0
    }
}

/// Residuals and their Jacobian (per radian of each axis) at angles `delta` from `g`.
fn linearise(
    chart: &VpChart,
    g: Vector3<f64>,
    delta: Vector2<f64>,
    segments: &[&Segment],
) -> (Vec<f64>, Vec<[f64; 2]>) {
    const H: f64 = 1e-7;
    let v = moved(chart, g, delta);
    let mut r = Vec::with_capacity(segments.len());
    let mut j = Vec::with_capacity(segments.len());
    let cols = [Vector2::new(H, 0.0), Vector2::new(0.0, H)];
    let plus = cols.map(|c| moved(chart, g, delta + c));
    let minus = cols.map(|c| moved(chart, g, delta - c));
    for s in segments {
        r.push(residual(s, v));
        j.push([0, 1].map(|k| (residual(s, plus[k]) - residual(s, minus[k])) / (2.0 * H)));
    }
    (r, j)
}

/// The root of `i` in a union-find forest, halving the path.
fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Each segment's weight: one over the number of segments on its edge.
pub(crate) fn edge_weights(segments: &[&Segment]) -> (Vec<f64>, usize) {
    let roots = edge_clusters(segments);
    let n = roots.len();
    let mut size = vec![0usize; n];
    for &r in &roots {
        size[r] += 1;
    }
    let edges = size.iter().filter(|&&s| s > 0).count();
    (roots.iter().map(|&r| 1.0 / size[r] as f64).collect(), edges)
}

/// Each segment's edge: the index of one segment of the same physical edge (pieces within
/// [`SAME_EDGE_DEG`] and [`SAME_EDGE_PX`] of each other's line, joined transitively).
pub(crate) fn edge_clusters(segments: &[&Segment]) -> Vec<usize> {
    let n = segments.len();
    let mut parent: Vec<usize> = (0..n).collect();
    let lines: Vec<(Vector3<f64>, Vector2<f64>)> = segments
        .iter()
        .map(|s| {
            let a = Vector3::new(s.start_px[0], s.start_px[1], 1.0);
            let b = Vector3::new(s.end_px[0], s.end_px[1], 1.0);
            let l = a.cross(&b);
            let norm = l.x.hypot(l.y).max(f64::MIN_POSITIVE);
            let dir = Vector2::new(s.end_px[0] - s.start_px[0], s.end_px[1] - s.start_px[1]);
            (l / norm, dir.normalize())
        })
        .collect();
    let cos_same = SAME_EDGE_DEG.to_radians().cos();
    for i in 0..n {
        for k in i + 1..n {
            let ((li, di), (lk, dk)) = (lines[i], lines[k]);
            if di.dot(&dk).abs() < cos_same {
                continue;
            }
            let near = |l: Vector3<f64>, s: &Segment| {
                [s.start_px, s.end_px]
                    .iter()
                    .all(|p| (l.x * p[0] + l.y * p[1] + l.z).abs() <= SAME_EDGE_PX)
            };
            if near(li, segments[k]) || near(lk, segments[i]) {
                let (a, b) = (root(&mut parent, i), root(&mut parent, k));
                parent[a] = b;
            }
        }
    }
    (0..n).map(|i| root(&mut parent, i)).collect()
}

/// The median of `values` (0 for none).
fn median(mut values: Vec<f64>) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

/// The segments' least-squares point ([`segments_fit`]): how far it lies from the starting
/// direction, which segments it kept and their noise.
struct SegmentsFit<'a> {
    /// The point's angles from the starting direction along its chart's *across* and
    /// *radial* axes, radians ([`moved`]).
    delta: Vector2<f64>,
    /// The segments kept (within [`OUTLIER_SIGMAS`] sigma of the first fit).
    kept: Vec<&'a Segment>,
    /// The kept residuals' noise, pixels (at least [`MIN_SEGMENT_SIGMA_PX`]).
    sigma: f64,
}

/// The robust least-squares point of `segments`, from unit direction `g` of `chart` (see the
/// module docs): Gauss-Newton on the weighted segment residuals (pieces of one edge weighing
/// one), the segments beyond [`OUTLIER_SIGMAS`] robust sigmas dropped, and again.
fn segments_fit<'a>(chart: &VpChart, g: Vector3<f64>, segments: &[&'a Segment]) -> SegmentsFit<'a> {
    let mut kept: Vec<&Segment> = segments
        .iter()
        .copied()
        .filter(|s| s.length_px() > 0.0)
        .collect();
    let mut delta = Vector2::zeros();
    let mut sigma = MIN_SEGMENT_SIGMA_PX;
    // Twice: fit and estimate the noise, drop the segments beyond OUTLIER_SIGMAS, again.
    for round in 0..2 {
        let (weights, _) = edge_weights(&kept);
        for _ in 0..STEPS {
            let (r, j) = linearise(chart, g, delta, &kept);
            let mut a = Matrix2::zeros();
            let mut b = Vector2::zeros();
            for ((ri, ji), w) in r.iter().zip(&j).zip(&weights) {
                let jv = Vector2::new(ji[0], ji[1]);
                a += jv * jv.transpose() * *w;
                b += jv * (*w * ri);
            }
            let Some(step) = a.try_inverse().map(|inv| -(inv * b)) else {
                break;
            };
            if !(step.x.is_finite() && step.y.is_finite()) {
                break;
            }
            // Small steps only: the point is known to a few degrees already.
            let limit = 0.1;
            delta += step * (limit / step.norm().max(limit));
            if step.norm() < 1e-10 {
                break;
            }
        }
        let (r, _) = linearise(chart, g, delta, &kept);
        if round == 1 {
            // The final noise from the kept residuals, unbiased for the two fitted angles.
            let (w, _) = edge_weights(&kept);
            let total: f64 = w.iter().sum();
            let sum: f64 = r.iter().zip(&w).map(|(ri, wi)| wi * ri * ri).sum();
            sigma = (sum / (total - 2.0).max(1.0))
                .sqrt()
                .max(MIN_SEGMENT_SIGMA_PX);
            break;
        }
        sigma = (1.4826 * median(r.iter().map(|v| v.abs()).collect())).max(MIN_SEGMENT_SIGMA_PX);
        {
            let inside: Vec<&Segment> = kept
                .iter()
                .zip(&r)
                .filter(|(_, ri)| ri.abs() <= OUTLIER_SIGMAS * sigma)
                .map(|(s, _)| *s)
                .collect();
            if inside.len() >= 2 {
                kept = inside;
            }
        }
    }
    SegmentsFit { delta, kept, sigma }
}

/// The segments' information about the point at angles `delta` from `g`, `J^T W J` per
/// radian squared (pieces of one edge weighing one), and the number of independent edges.
fn information(
    chart: &VpChart,
    g: Vector3<f64>,
    delta: Vector2<f64>,
    segments: &[&Segment],
) -> (Matrix2<f64>, usize) {
    let (weights, edges) = edge_weights(segments);
    let (_, j) = linearise(chart, g, delta, segments);
    let mut info = Matrix2::zeros();
    for (ji, w) in j.iter().zip(&weights) {
        let jv = Vector2::new(ji[0], ji[1]);
        info += jv * jv.transpose() * *w;
    }
    (info, edges)
}

/// The covariance of the vanishing point written at homogeneous pixel `point` (in `chart`),
/// from its supporting `segments`, plus the floor [`VP_FLOOR_SD_DEG`].
#[must_use]
pub fn vp_covariance(chart: &VpChart, point: Vector3<f64>, segments: &[&Segment]) -> VpCovariance {
    let floor_rad2 = VP_FLOOR_SD_DEG.to_radians().powi(2);
    let with_floor = |stat: Option<Matrix2<f64>>| {
        let m = stat.unwrap_or_else(Matrix2::zeros) + Matrix2::identity() * floor_rad2;
        let deg = |v: f64| v.to_degrees().to_degrees();
        [
            [deg(m[(0, 0)]), deg(m[(0, 1)])],
            [deg(m[(1, 0)]), deg(m[(1, 1)])],
        ]
    };
    let to_deg2 = |m: Matrix2<f64>| {
        let deg = |v: f64| v.to_degrees().to_degrees();
        [
            [deg(m[(0, 0)]), deg(m[(0, 1)])],
            [deg(m[(1, 0)]), deg(m[(1, 1)])],
        ]
    };
    let no_segments = |inliers: usize, edges: usize| VpCovariance {
        covariance_deg2: with_floor(None),
        segments_deg2: None,
        sigma_px: MIN_SEGMENT_SIGMA_PX,
        inliers,
        edges,
    };
    let Some(g) = chart.direction(point) else {
        return no_segments(0, 0);
    };
    let SegmentsFit { kept, sigma, .. } = segments_fit(chart, g, segments);
    // The covariance at the written point (the segments' information does not depend much
    // on where in the few-degree neighbourhood it is taken).
    let (info, edges) = information(chart, g, Vector2::zeros(), &kept);
    // With the noise estimated from few edges, the 95 % ellipse of known noise is too small:
    // widen it to the F quantile's (Hotelling), `2 F(2, nu)` for `nu = edges - 2`, whose 95 %
    // point has the closed form `nu (0.05^(-2/nu) - 1)`.
    let nu = edges as f64 - 2.0;
    let widen = if nu >= 1.0 {
        (nu * (0.05f64.powf(-2.0 / nu) - 1.0) / CHI2_2DOF_95).max(1.0)
    } else {
        1.0
    };
    let stat = if edges >= 3 {
        info.try_inverse()
            .map(|inv| inv * (sigma * sigma * widen))
            .filter(|m| m.iter().all(|v| v.is_finite()) && m[(0, 0)] > 0.0 && m[(1, 1)] > 0.0)
    } else {
        None
    };
    let Some(stat) = stat else {
        return no_segments(kept.len(), edges);
    };
    VpCovariance {
        covariance_deg2: with_floor(Some(stat)),
        segments_deg2: Some(to_deg2(stat)),
        sigma_px: sigma,
        inliers: kept.len(),
        edges,
    }
}

/// A direction's own vanishing point: the least-squares point of its `segments` alone,
/// starting from homogeneous pixel `point` of `chart` (the frame's point), not held
/// orthogonal to any other direction. It is the point [`vp_covariance`] moves to for the
/// segments' noise: the same robust fit (segments beyond [`OUTLIER_SIGMAS`] robust sigmas
/// dropped, pieces of one edge weighing one).
///
/// `None` when `point` has no direction, or the kept segments do not fix a point (fewer than
/// two independent edges, or all through one line).
///
/// # Example
/// Three edges meeting at (900, 200), the frame's point 20 px away:
/// ```
/// use nalgebra::{Vector2, Vector3};
/// use vpmap_metrology::scene::VpChart;
/// use vpmap_vision::Segment;
/// use vpmap_vision::uncertainty::own_point;
///
/// let chart = VpChart { focal_px: 500.0, centre_px: Vector2::new(320.0, 240.0) };
/// let edge = |y0: f64| {
///     // From (100, y0) a third of the way towards (900, 200).
///     let end = [100.0 + 800.0 / 3.0, y0 + (200.0 - y0) / 3.0];
///     Segment { start_px: [100.0, y0], end_px: end, strength: 1.0 }
/// };
/// let segments = [edge(50.0), edge(250.0), edge(420.0)];
/// let refs: Vec<&Segment> = segments.iter().collect();
/// let own = own_point(&chart, Vector3::new(920.0, 200.0, 1.0), &refs).expect("fixed");
/// let p = own.point_px.expect("finite");
/// assert!((p[0] - 900.0).abs() < 1e-6 && (p[1] - 200.0).abs() < 1e-6, "{p:?}");
/// assert_eq!(own.edges, 3);
/// ```
#[must_use]
pub fn own_point(chart: &VpChart, point: Vector3<f64>, segments: &[&Segment]) -> Option<OwnPoint> {
    let g = chart.direction(point)?;
    let SegmentsFit { delta, kept, .. } = segments_fit(chart, g, segments);
    let (info, edges) = information(chart, g, delta, &kept);
    if edges < 2
        || info
            .try_inverse()
            .is_none_or(|m| !m.iter().all(|v| v.is_finite()))
    {
        return None;
    }
    let mut d = chart.direction(moved(chart, g, delta))?;
    if d.z < 0.0 || (d.z == 0.0 && d.x < 0.0) {
        d = -d;
    }
    let from_frame_deg = g.cross(&d).norm().atan2(g.dot(&d).abs()).to_degrees();
    Some(OwnPoint {
        point_px: (d.z.abs() > 1e-12).then(|| {
            [
                chart.focal_px * d.x / d.z + chart.centre_px.x,
                chart.focal_px * d.y / d.z + chart.centre_px.y,
            ]
        }),
        direction_camera: [d.x, d.y, d.z],
        from_frame_deg,
        edges,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chart() -> VpChart {
        VpChart {
            focal_px: 500.0,
            centre_px: Vector2::new(320.0, 240.0),
        }
    }

    /// A segment of `len` px centred at `mid` pointing at `vp`, its ends moved by `noise` px
    /// across it (start +, end -).
    fn towards(vp: [f64; 2], mid: [f64; 2], len: f64, noise: f64) -> Segment {
        let d = Vector2::new(vp[0] - mid[0], vp[1] - mid[1]).normalize();
        let n = Vector2::new(-d.y, d.x);
        let a = Vector2::new(mid[0], mid[1]) - d * (0.5 * len) + n * noise;
        let b = Vector2::new(mid[0], mid[1]) + d * (0.5 * len) - n * noise;
        Segment {
            start_px: [a.x, a.y],
            end_px: [b.x, b.y],
            strength: 1.0,
        }
    }

    #[test]
    fn more_independent_edges_shrink_the_segment_part_and_pieces_of_one_edge_do_not() {
        let vp = [1500.0, 200.0];
        let point = Vector3::new(vp[0], vp[1], 1.0);
        // Ten edges at different heights, each with its own small error.
        let ten: Vec<Segment> = (0..10)
            .map(|k| {
                let noise = if k % 2 == 0 { 0.4 } else { -0.4 };
                towards(
                    vp,
                    [200.0 + 20.0 * f64::from(k), 50.0 + 40.0 * f64::from(k)],
                    80.0,
                    noise,
                )
            })
            .collect();
        let refs: Vec<&Segment> = ten.iter().collect();
        let c10 = vp_covariance(&chart(), point, &refs);
        assert_eq!(c10.edges, 10);
        let two: Vec<&Segment> = refs[..3].to_vec();
        let c2 = vp_covariance(&chart(), point, &two);
        let s10 = c10.segments_deg2.unwrap_or_default();
        let s2 = c2.segments_deg2.unwrap_or_default();
        assert!(
            s10[0][0] + s10[1][1] < s2[0][0] + s2[1][1],
            "{s10:?} vs {s2:?}"
        );
        // The same edge cut into 5 pieces: one edge, so no more information than one piece.
        let base = &ten[0];
        let pieces: Vec<Segment> = (0..5)
            .map(|k| {
                let t0 = f64::from(k) / 5.0;
                let t1 = (f64::from(k) + 0.9) / 5.0;
                let p = |t: f64| {
                    [
                        base.start_px[0] + t * (base.end_px[0] - base.start_px[0]),
                        base.start_px[1] + t * (base.end_px[1] - base.start_px[1]),
                    ]
                };
                Segment {
                    start_px: p(t0),
                    end_px: p(t1),
                    strength: 1.0,
                }
            })
            .collect();
        let mut with_pieces: Vec<&Segment> = refs[1..].to_vec();
        with_pieces.extend(pieces.iter());
        let cp = vp_covariance(&chart(), point, &with_pieces);
        assert_eq!(cp.edges, 10, "pieces of one edge count once");
        // Always at least the floor on each axis.
        let floor = VP_FLOOR_SD_DEG * VP_FLOOR_SD_DEG;
        assert!(c10.covariance_deg2[0][0] >= floor && c10.covariance_deg2[1][1] >= floor);
        assert!(c10.major_sd_deg() >= VP_FLOOR_SD_DEG);
    }

    #[test]
    fn the_segment_part_covers_the_truth_under_its_own_noise_model() {
        // Seeded endpoint noise of 0.7 px on 12 edges: the least-squares point's error, in
        // sigma units of the segment part, is chi-square with 2 degrees of freedom; over 400
        // trials about 95 % lie inside 5.99.
        let vp = [900.0, -300.0];
        let truth = Vector3::new(vp[0], vp[1], 1.0);
        let mut state = 7u64;
        let mut gauss = || {
            // Box-Muller on a xorshift.
            let mut u = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
            };
            let (a, b) = (u(), u());
            (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
        };
        let mut inside = 0;
        let trials = 400;
        for _ in 0..trials {
            let segs: Vec<Segment> = (0..12)
                .map(|k| {
                    let mut s = towards(
                        vp,
                        [60.0 + 45.0 * f64::from(k), 420.0 - 15.0 * f64::from(k)],
                        90.0,
                        0.0,
                    );
                    s.start_px[0] += 0.7 * gauss();
                    s.start_px[1] += 0.7 * gauss();
                    s.end_px[0] += 0.7 * gauss();
                    s.end_px[1] += 0.7 * gauss();
                    s
                })
                .collect();
            let refs: Vec<&Segment> = segs.iter().collect();
            // Written at the truth: the covariance is about the estimate, so measure the
            // estimate's offset by refitting from the truth.
            let c = vp_covariance(&chart(), truth, &refs);
            let Some(s) = c.segments_deg2 else { continue };
            // The least-squares point itself: Gauss-Newton from the truth.
            let g = chart().direction(truth).unwrap_or_default();
            let mut delta = Vector2::zeros();
            for _ in 0..STEPS {
                let (r, j) = linearise(&chart(), g, delta, &refs);
                let mut a = Matrix2::zeros();
                let mut b = Vector2::zeros();
                for (ri, ji) in r.iter().zip(&j) {
                    let jv = Vector2::new(ji[0], ji[1]);
                    a += jv * jv.transpose();
                    b += jv * *ri;
                }
                delta -= a.try_inverse().unwrap_or_default() * b;
            }
            let cov = Matrix2::new(s[0][0], s[0][1], s[1][0], s[1][1]);
            let e = delta.map(f64::to_degrees);
            let d2 = (e.transpose() * cov.try_inverse().unwrap_or_default() * e)[(0, 0)];
            if d2 <= 5.991 {
                inside += 1;
            }
        }
        let share = f64::from(inside) / f64::from(trials);
        assert!((0.92..=0.98).contains(&share), "coverage {share}");
    }
}
