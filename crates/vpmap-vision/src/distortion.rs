//! Lens distortion from the photo's straight edges: the one-parameter division model's `k`
//! ([`vpmap_metrology::scene::DivisionModel`]) with its standard deviation.
//!
//! Through a distorting lens a straight edge of the room bows, so the segments found along it
//! point a little away from their vanishing point, more the farther they are from the centre.
//! For a candidate `k` every supporting segment is undistorted, each vanishing point refitted
//! to its segments (Gauss-Newton on the segment-to-point residuals of
//! [`crate::uncertainty`], Cauchy-weighted so that a stray segment does not decide `k`), and
//! the robust cost summed over the three points: `k` is its minimiser (a grid over the range
//! of real lenses, then golden-section search), the profile-likelihood approach of
//! Antunes, Barreto, Aouada and Ottersten, "Unsupervised vanishing point detection and camera
//! calibration from a single Manhattan image with radial distortion", CVPR 2017.
//!
//! Its uncertainty: least squares' `sigma^2 / sum_i w_i J_i^2` over the inliers (within 3
//! sigma at the minimum), `J_i` each residual's derivative in `k` with the vanishing points
//! refitted, pieces of one physical edge weighing one edge (as for the vanishing points: an
//! edge found a little crooked errs in all its pieces), plus a model-error floor measured on
//! York Urban ([`LENS_FLOOR_SD`]). It is combined with the prior of real
//! lenses, `k ~ N(0, PRIOR_SD^2)` ([`LENS_PRIOR_SD`]): a photo with few edges away from its
//! centre says little, and the prior keeps `k` where lenses are.

use nalgebra::{Matrix2, Vector2, Vector3};
use vpmap_metrology::scene::{DivisionModel, ImageSize, MAX_DIVISION_STRETCH, VpChart};

use crate::detection::Segment;
use crate::uncertainty::{MIN_SEGMENT_SIGMA_PX, edge_weights, moved, residual};

/// The prior's standard deviation of `k`: phone and compact-camera lenses span about -0.15
/// (wide, barrel) to 0.05 in this normalisation (radius in half-diagonals).
pub const LENS_PRIOR_SD: f64 = 0.1;

/// The model-error floor of `k`'s standard deviation, added in quadrature to the segments'
/// part: what straight edges that are not quite straight, clutter and wrong assignments add.
/// Measured on York Urban's 51 training photos, all taken by one camera at one zoom (one `k`):
/// each photo's `k` against the precision-weighted mean of the 50 others, the smallest floor in
/// 0.001 steps at which at least 92 % of the photos lie within their 95 % interval in both of
/// `vpmap eval-detect`'s runs: 0.006 (92.2 / 96.1 %, normalised RMS 0.97 / 0.89; 0.005: 90.2 /
/// 92.2 %; none: 76.5 / 80.4 %, RMS 1.78 / 1.59).
pub const LENS_FLOOR_SD: f64 = 0.006;

/// A lens is applied only when its `k` is this many standard deviations from 0 (99 %,
/// two-sided): most photos are a pinhole's or close (phones correct their lenses), and a `k`
/// that is noise moves every click. Below it the photo is taken as a pinhole's, and `k`'s sd
/// still goes into the error bars.
pub const LENS_SIGNIFICANCE_Z: f64 = 2.575_829_303_548_901;

/// The range of `k` searched.
pub const K_RANGE: [f64; 2] = [-0.4, 0.3];

/// The Cauchy scale of the robust cost, pixels.
const CAUCHY_PX: f64 = 1.0;

/// Grid step of the first search over [`K_RANGE`].
const GRID_STEP: f64 = 0.05;

/// Finite-difference step of the curvature.
const CURVATURE_STEP: f64 = 0.005;

/// What [`estimate_division_k`] found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LensEstimate {
    /// The division model applied (its `k`, centre and radius unit): `k` is
    /// [`Self::estimated_k`] when the edges show it at 99 % ([`LENS_SIGNIFICANCE_Z`]), else 0
    /// (a pinhole).
    pub model: DivisionModel,
    /// The edges' estimate of `k` (segments and prior combined), applied or not.
    pub estimated_k: f64,
    /// `k`'s standard deviation (segments and prior combined).
    pub k_sd: f64,
    /// `k`'s standard deviation from the segments alone, before the floor
    /// ([`LENS_FLOOR_SD`]) and the prior (`None` when they do not fix it).
    pub segments_k_sd: Option<f64>,
    /// Supporting segments used.
    pub segments: usize,
}

impl LensEstimate {
    /// The `k` applied (0 when the edges do not show a lens at 99 %).
    #[must_use]
    pub fn k(&self) -> f64 {
        self.model.k
    }

    /// `segment` undistorted by the model.
    #[must_use]
    pub fn undistort(&self, segment: &Segment) -> Segment {
        undistorted(&self.model, segment)
    }
}

fn undistorted(model: &DivisionModel, s: &Segment) -> Segment {
    Segment {
        start_px: model.undistort(s.start_px),
        end_px: model.undistort(s.end_px),
        strength: s.strength,
    }
}

/// One vanishing point's segments and its starting direction.
struct Group<'a> {
    segments: Vec<&'a Segment>,
    start: Vector3<f64>,
    /// Edge weights of the photo's segments (fixed, so that the cost is smooth in `k`).
    weights: Vec<f64>,
}

/// The vanishing point of `segments` near direction `g` (Gauss-Newton in `chart`'s angles,
/// Cauchy weights when `robust`, each segment's weight times `weights`): the residuals.
fn refit(
    chart: &VpChart,
    g: Vector3<f64>,
    segments: &[Segment],
    weights: &[f64],
    robust: bool,
) -> Vec<f64> {
    const H: f64 = 1e-7;
    let mut delta = Vector2::zeros();
    let residuals = |delta: Vector2<f64>| -> Vec<f64> {
        let v = moved(chart, g, delta);
        segments.iter().map(|s| residual(s, v)).collect()
    };
    for _ in 0..6 {
        let r = residuals(delta);
        let cols = [Vector2::new(H, 0.0), Vector2::new(0.0, H)];
        let jac = cols.map(|c| {
            let (p, m) = (residuals(delta + c), residuals(delta - c));
            p.iter()
                .zip(&m)
                .map(|(a, b)| (a - b) / (2.0 * H))
                .collect::<Vec<f64>>()
        });
        let mut a = Matrix2::zeros();
        let mut b = Vector2::zeros();
        for i in 0..r.len() {
            let cauchy = if robust {
                1.0 / (1.0 + (r[i] / CAUCHY_PX).powi(2))
            } else {
                1.0
            };
            let w = weights[i] * cauchy;
            let j = Vector2::new(jac[0][i], jac[1][i]);
            a += j * j.transpose() * w;
            b += j * (w * r[i]);
        }
        let Some(step) = a.try_inverse().map(|inv| -(inv * b)) else {
            break;
        };
        if !(step.x.is_finite() && step.y.is_finite()) {
            break;
        }
        let limit = 0.05;
        delta += step * (limit / step.norm().max(limit));
        if step.norm() < 1e-9 {
            break;
        }
    }
    residuals(delta)
}

/// The problem: the groups, the chart, the image.
struct Problem<'a> {
    groups: Vec<Group<'a>>,
    chart: VpChart,
    image: ImageSize,
    centre: [f64; 2],
}

impl Problem<'_> {
    fn model(&self, k: f64) -> DivisionModel {
        DivisionModel::new(k, self.image, Some(self.centre))
    }

    /// The robust cost at `k`.
    fn robust_cost(&self, k: f64) -> f64 {
        let model = self.model(k);
        let mut total = 0.0;
        for g in &self.groups {
            let segs: Vec<Segment> = g.segments.iter().map(|s| undistorted(&model, s)).collect();
            let r = refit(&self.chart, g.start, &segs, &g.weights, true);
            total += r
                .iter()
                .zip(&g.weights)
                .map(|(ri, w)| w * CAUCHY_PX * CAUCHY_PX * (1.0 + (ri / CAUCHY_PX).powi(2)).ln())
                .sum::<f64>();
        }
        total
    }

    /// Each group's residuals at `k` (vanishing points refitted by least squares, each
    /// segment's weight 1 or 0 as `mask` says).
    fn residuals(&self, k: f64, mask: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let model = self.model(k);
        self.groups
            .iter()
            .zip(mask)
            .map(|(g, w)| {
                let segs: Vec<Segment> =
                    g.segments.iter().map(|s| undistorted(&model, s)).collect();
                refit(&self.chart, g.start, &segs, w, false)
            })
            .collect()
    }

    /// Each segment's weight at `k`: its edge's share for the inliers (within 3 robust sigmas
    /// of their refitted point), 0 for the others.
    fn inliers(&self, k: f64) -> Vec<Vec<f64>> {
        let model = self.model(k);
        let residuals: Vec<Vec<f64>> = self
            .groups
            .iter()
            .map(|g| {
                let segs: Vec<Segment> =
                    g.segments.iter().map(|s| undistorted(&model, s)).collect();
                refit(&self.chart, g.start, &segs, &g.weights, true)
            })
            .collect();
        let mut all: Vec<f64> = residuals.iter().flatten().map(|v| v.abs()).collect();
        all.sort_by(f64::total_cmp);
        let mad = all.get(all.len() / 2).copied().unwrap_or(0.0);
        let limit = 3.0 * (1.4826 * mad).max(MIN_SEGMENT_SIGMA_PX);
        self.groups
            .iter()
            .zip(&residuals)
            .map(|(g, r)| {
                g.weights
                    .iter()
                    .zip(r)
                    .map(|(w, ri)| if ri.abs() <= limit { *w } else { 0.0 })
                    .collect()
            })
            .collect()
    }

    /// `k`'s variance from the segments at `k`: `sigma^2 / sum_i w_i J_i^2`, with `J_i` the
    /// profiled derivative of residual `i` in `k` (vanishing points refitted), `w_i` the edge
    /// weights of the inliers (pieces of one edge weigh one edge) and `sigma^2` their weighted
    /// mean square residual over the degrees of freedom (two angles a vanishing point, and
    /// `k`). `None` when `k` moves no residual.
    fn variance(&self, k: f64) -> Option<f64> {
        let mask = self.inliers(k);
        let r0 = self.residuals(k, &mask);
        let plus = self.residuals(k + CURVATURE_STEP, &mask);
        let minus = self.residuals(k - CURVATURE_STEP, &mask);
        let mut information = 0.0;
        let mut squares = 0.0;
        let mut total = 0.0;
        for (g, gi) in self.groups.iter().enumerate() {
            for i in 0..gi.segments.len() {
                let w = mask[g][i];
                if w == 0.0 {
                    continue;
                }
                let j = (plus[g][i] - minus[g][i]) / (2.0 * CURVATURE_STEP);
                information += w * j * j;
                squares += w * r0[g][i] * r0[g][i];
                total += w;
            }
        }
        let dof = total - 2.0 * self.groups.len() as f64 - 1.0;
        if information.is_nan() || information <= 0.0 || dof < 1.0 {
            return None;
        }
        let sigma2 = (squares / dof).max(MIN_SEGMENT_SIGMA_PX * MIN_SEGMENT_SIGMA_PX);
        let v = sigma2 / information;
        (v.is_finite() && v > 0.0).then_some(v)
    }
}

/// Golden-section minimum of `f` in `[a, b]`.
fn golden(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64, tolerance: f64) -> f64 {
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let mut c = b - ratio * (b - a);
    let mut d = a + ratio * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    while b - a > tolerance {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - ratio * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + ratio * (b - a);
            fd = f(d);
        }
    }
    0.5 * (a + b)
}

/// The division model's `k` of a photo of `image` pixels with distortion centre `centre_px`,
/// from `segments` (photo pixels) grouped by vanishing point: `groups[i]` the indices of the
/// segments of the point in direction `directions[i]` (the camera frame of `chart`, the
/// pinhole camera the vanishing points were found for).
///
/// `None` when fewer than two groups have three segments (nothing to measure bowing against).
#[must_use]
pub fn estimate_division_k(
    segments: &[Segment],
    groups: &[Vec<usize>],
    directions: &[[f64; 3]],
    chart: &VpChart,
    image: ImageSize,
    centre_px: [f64; 2],
) -> Option<LensEstimate> {
    let groups: Vec<Group> = groups
        .iter()
        .zip(directions)
        .map(|(idx, d)| {
            let segments: Vec<&Segment> = idx
                .iter()
                .filter_map(|&i| segments.get(i))
                .filter(|s| s.length_px() > 0.0)
                .collect();
            let (weights, _) = edge_weights(&segments);
            Group {
                segments,
                start: Vector3::new(d[0], d[1], d[2]).normalize(),
                weights,
            }
        })
        .filter(|g| g.segments.len() >= 3 && g.start.iter().all(|v| v.is_finite()))
        .collect();
    if groups.len() < 2 {
        return None;
    }
    let used = groups.iter().map(|g| g.segments.len()).sum();
    let problem = Problem {
        groups,
        chart: *chart,
        image,
        centre: centre_px,
    };
    let allowed = |k: f64| problem.model(k).stretch(image) <= MAX_DIVISION_STRETCH;
    // The grid, then golden-section search around its best point.
    let steps = ((K_RANGE[1] - K_RANGE[0]) / GRID_STEP).round() as usize;
    let mut best = (0.0, problem.robust_cost(0.0));
    for i in 0..=steps {
        let k = K_RANGE[0] + GRID_STEP * i as f64;
        if !allowed(k) {
            continue;
        }
        let c = problem.robust_cost(k);
        if c < best.1 {
            best = (k, c);
        }
    }
    let lo = (best.0 - GRID_STEP).max(K_RANGE[0]);
    let hi = (best.0 + GRID_STEP).min(K_RANGE[1]);
    let k_hat = golden(|k| problem.robust_cost(k), lo, hi, 1e-4);
    // The segments' information about k, with the floor of what the model leaves out.
    let segments_variance = problem.variance(k_hat);
    let segments_precision =
        segments_variance.map_or(0.0, |v| (v + LENS_FLOOR_SD * LENS_FLOOR_SD).recip());
    // Combined with the prior N(0, LENS_PRIOR_SD^2): precision-weighted.
    let prior_precision = 1.0 / (LENS_PRIOR_SD * LENS_PRIOR_SD);
    let precision = segments_precision + prior_precision;
    let estimated_k = k_hat * segments_precision / precision;
    let k_sd = precision.recip().sqrt();
    // Applied only when the edges show it at 99 %; else the pinhole, with k's sd kept.
    let applied = estimated_k.abs() >= LENS_SIGNIFICANCE_Z * k_sd;
    Some(LensEstimate {
        model: problem.model(if applied { estimated_k } else { 0.0 }),
        estimated_k,
        k_sd,
        segments_k_sd: segments_variance.map(f64::sqrt),
        segments: used,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Rotation3};
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, Normal};

    const FOCAL_PX: f64 = 900.0;
    const IMAGE: ImageSize = ImageSize {
        width: 1600,
        height: 1200,
    };

    /// Segments of a Manhattan room's edges seen by a pinhole camera (focal 900 px, centre
    /// at the image centre), through a lens of division model `k`: points along each 3-D edge
    /// projected, moved through the lens (`DivisionModel::distort`), chopped into chords of
    /// about 60 px with `noise_px` on every end; each edge turned off its direction by about
    /// 0.15 degree (shared by its pieces). The groups by direction, the directions.
    fn lens_segments(
        seed: u64,
        k: f64,
        noise_px: f64,
    ) -> (Vec<Segment>, Vec<Vec<usize>>, Vec<[f64; 3]>) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let noise = Normal::new(0.0, noise_px).unwrap();
        let edge_noise = Normal::new(0.0, 0.15f64.to_radians()).unwrap();
        let rot: Matrix3<f64> =
            *Rotation3::from_euler_angles(0.35, rng.random_range(0.3..0.8), 0.05).matrix();
        let model = DivisionModel::new(k, IMAGE, None);
        let centre = [800.0, 600.0];
        let project = |p: Vector3<f64>| -> Option<[f64; 2]> {
            (p.z > 0.5).then(|| {
                [
                    centre[0] + FOCAL_PX * p.x / p.z,
                    centre[1] + FOCAL_PX * p.y / p.z,
                ]
            })
        };
        let inside = |p: [f64; 2]| (0.0..1600.0).contains(&p[0]) && (0.0..1200.0).contains(&p[1]);
        let mut segments = Vec::new();
        let mut groups = vec![Vec::new(); 3];
        for (axis, group) in groups.iter_mut().enumerate() {
            let axis_direction = rot.column(axis).into_owned();
            for _ in 0..12 {
                // Each edge a little off the room's direction (built crooked, or not quite
                // the edge the detector followed): an error its pieces share.
                let tilt = Vector3::new(
                    edge_noise.sample(&mut rng),
                    edge_noise.sample(&mut rng),
                    edge_noise.sample(&mut rng),
                );
                let d = (axis_direction + tilt).normalize();
                let origin = Vector3::new(
                    rng.random_range(-4.0..4.0),
                    rng.random_range(-3.0..3.0),
                    rng.random_range(4.0..9.0),
                );
                // The edge sampled every 2 cm, kept where its photo point is in the image.
                let pts: Vec<[f64; 2]> = (-150..=150)
                    .filter_map(|i| project(origin + d * (0.02 * f64::from(i))))
                    .filter_map(|p| model.distort(p))
                    .filter(|p| inside(*p))
                    .collect();
                let mut start = 0;
                for i in 1..pts.len() {
                    let (a, b) = (pts[start], pts[i]);
                    if (b[0] - a[0]).hypot(b[1] - a[1]) >= 60.0 {
                        group.push(segments.len());
                        segments.push(Segment {
                            start_px: [
                                a[0] + noise.sample(&mut rng),
                                a[1] + noise.sample(&mut rng),
                            ],
                            end_px: [b[0] + noise.sample(&mut rng), b[1] + noise.sample(&mut rng)],
                            strength: 1.0,
                        });
                        start = i;
                    }
                }
            }
        }
        let directions = (0..3)
            .map(|axis| {
                let d = rot.column(axis).into_owned();
                let d = if d.z < 0.0 { -d } else { d };
                [d.x, d.y, d.z]
            })
            .collect();
        (segments, groups, directions)
    }

    fn estimate(seed: u64, k: f64) -> LensEstimate {
        let (segments, groups, directions) = lens_segments(seed, k, 0.4);
        let chart = VpChart {
            focal_px: FOCAL_PX,
            centre_px: Vector2::new(800.0, 600.0),
        };
        estimate_division_k(
            &segments,
            &groups,
            &directions,
            &chart,
            IMAGE,
            [800.0, 600.0],
        )
        .unwrap()
    }

    #[test]
    fn a_phone_lens_is_measured_from_its_bowed_edges() {
        for (seed, k) in [(1, -0.1), (2, -0.04), (3, 0.05)] {
            let e = estimate(seed, k);
            // The segments, not the prior (sd 0.1), fix it.
            assert!(e.k_sd < 0.02, "seed {seed}: sd {}", e.k_sd);
            assert!(
                (e.k() - k).abs() < 3.0 * e.k_sd,
                "seed {seed}: k {} +- {} for {k}",
                e.k(),
                e.k_sd
            );
            // Clearly there: applied.
            assert!(
                (e.k() - e.estimated_k).abs() < 1e-15,
                "seed {seed}: not applied"
            );
        }
    }

    #[test]
    fn the_interval_holds_the_lens_as_often_as_it_says() {
        // Straight photos (k = 0) and barrel ones: |k - truth| within 1.96 sd for at least 92 %
        // (the floor's calibration is York Urban's, in the shared-data test).
        let mut inside = 0;
        let trials = 100;
        for seed in 0..trials {
            let k = if seed % 2 == 0 { 0.0 } else { -0.06 };
            let e = estimate(100 + seed, k);
            // The segments' own part, before the floor measured on real photos: under this
            // noise model (independent ends, edges a little crooked) it is conservative.
            let sd = e.segments_k_sd.unwrap();
            if (e.estimated_k - k).abs() <= 1.96 * sd {
                inside += 1;
            }
        }
        eprintln!("lens interval (segments' part): {inside} of {trials} inside");
        assert!((92..=100).contains(&inside), "{inside} of {trials} inside");
    }

    #[test]
    fn too_few_segments_say_so() {
        let (segments, groups, directions) = lens_segments(4, 0.0, 0.4);
        let chart = VpChart {
            focal_px: FOCAL_PX,
            centre_px: Vector2::new(800.0, 600.0),
        };
        let one = vec![groups[0].clone(), Vec::new(), groups[2][..2].to_vec()];
        assert!(
            estimate_division_k(&segments, &one, &directions, &chart, IMAGE, [800.0, 600.0])
                .is_none()
        );
    }
}
