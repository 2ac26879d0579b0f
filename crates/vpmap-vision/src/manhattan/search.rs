//! Hypotheses: first vanishing point candidates and the 2-line search for the other two.
//!
//! # Search (after Lu et al. 2017, with the focal length as a search dimension)
//! 1. *First vanishing point candidates*, independent of the camera: intersections
//!    `v = l_i x l_j` of random segment pairs (drawn with probability proportional to their
//!    weight), scored by `S(v) = sum_i W_i max(0, 1 - sin^2 theta_i / sin^2 tau)`, `W_i` the
//!    segment's length with the pieces of one physical edge weighing together at most
//!    [`SCORE_WEIGHT_CAP_PX`](super::SCORE_WEIGHT_CAP_PX) (`mod.rs`); the best ones with
//!    different supporting segments are refitted by algebraic least squares.
//! 2. *Second and third directions*: for a candidate `v_1` and a focal length `f`,
//!    `d_1 = K^-1 v_1`; every segment not supporting `v_1` lies in a plane whose intersection
//!    with the plane orthogonal to `d_1` is the direction `n x d_1` it would give to `d_2` or
//!    `d_3`. Its angle on that great circle, modulo 90 degrees (`d_3 = d_1 x d_2` is 90
//!    degrees on), is voted into a 1-degree histogram; the peaks give `(d_2, d_3)`. This is
//!    Lu et al.'s exhaustive 2-line search with the sampled great circle replaced by a vote,
//!    which costs one pass over the segments instead of 360 hypotheses.
//! 3. Each triplet is scored with `S` summed over the segments' best direction. Without
//!    known intrinsics steps 2-3 run over a log-spaced focal-length grid (0.3 to 3 times the
//!    longer side) with the principal point at the image centre, and the score is multiplied
//!    by a weak log-normal prior around `f = longer side` (a 53 degree horizontal field of view),
//!    which decides only when the image cannot (one-point perspective).

use nalgebra::{Matrix3, Vector3};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::model::{Camera, Frame};
use super::problem::{
    CANDIDATES, CIRCLE_BINS, FOCAL_RANGE, FOCAL_STEP, PAIR_SAMPLES, Problem, REFINED_HYPOTHESES,
    SCORE_TOLERANCE_DEG,
};

impl Problem<'_> {
    /// First vanishing point candidates, camera-free.
    fn candidates(&self, rng: &mut ChaCha8Rng) -> Vec<Vector3<f64>> {
        let sin2_tau = Self::sin2_tau();
        let mut cumulative = Vec::with_capacity(self.segs.len());
        let mut total = 0.0;
        for s in &self.segs {
            total += s.weight;
            cumulative.push(total);
        }
        let draw = |rng: &mut ChaCha8Rng| {
            let t = rng.random::<f64>() * total;
            cumulative
                .partition_point(|&c| c < t)
                .min(self.segs.len() - 1)
        };
        let mut scored: Vec<(f64, Vector3<f64>)> = Vec::with_capacity(PAIR_SAMPLES);
        for _ in 0..PAIR_SAMPLES {
            let (i, j) = (draw(rng), draw(rng));
            if i == j {
                continue;
            }
            let (Some(a), Some(b)) = (self.segs.get(i), self.segs.get(j)) else {
                continue;
            };
            let Some(v) = a.line.cross(&b.line).try_normalize(1e-9) else {
                continue;
            };
            scored.push((self.score_single(&v, sin2_tau), v));
        }
        scored.sort_by(|a, b| b.0.total_cmp(&a.0));
        let mut accepted: Vec<(Vector3<f64>, Vec<bool>)> = Vec::new();
        for (_, v) in scored {
            if accepted.len() >= CANDIDATES {
                break;
            }
            let inliers: Vec<bool> = self.segs.iter().map(|s| s.sin2(&v) < sin2_tau).collect();
            let (mut mine, mut shared) = (0.0, 0.0);
            for (k, s) in self.segs.iter().enumerate() {
                if inliers.get(k).copied().unwrap_or(false) {
                    mine += s.weight;
                    if accepted
                        .iter()
                        .any(|(_, other)| other.get(k).copied().unwrap_or(false))
                    {
                        shared += s.weight;
                    }
                }
            }
            if mine <= 0.0 || shared > 0.5 * mine {
                continue;
            }
            let refined = self.refit_point(v, sin2_tau);
            let inliers = self
                .segs
                .iter()
                .map(|s| s.sin2(&refined) < sin2_tau)
                .collect();
            accepted.push((refined, inliers));
        }
        accepted.into_iter().map(|(v, _)| v).collect()
    }

    /// Algebraic least-squares vanishing point of the segments consistent with `v`.
    fn refit_point(&self, mut v: Vector3<f64>, sin2_tau: f64) -> Vector3<f64> {
        for _ in 0..2 {
            let mut m = Matrix3::zeros();
            let mut count = 0;
            for s in &self.segs {
                let e = s.sin2(&v);
                if e < sin2_tau {
                    m += s.line * s.line.transpose() * (s.weight * (1.0 - e / sin2_tau));
                    count += 1;
                }
            }
            if count < 2 {
                return v;
            }
            let Some(eig) = vpmap_metrology::linalg::symmetric_eigen(m) else {
                return v;
            };
            let (k, _) =
                eig.eigenvalues
                    .iter()
                    .enumerate()
                    .fold(
                        (0, f64::INFINITY),
                        |acc, (k, &e)| {
                            if e < acc.1 { (k, e) } else { acc }
                        },
                    );
            let candidate = eig.eigenvectors.column(k).into_owned();
            if candidate.iter().all(|x| x.is_finite()) {
                v = candidate;
            }
        }
        v
    }

    /// The focal lengths to try (normalised units).
    fn focal_grid(&self) -> Vec<f64> {
        if let Some(f) = self.known_focal {
            return vec![f];
        }
        let mut grid = Vec::new();
        let mut f = FOCAL_RANGE.0;
        while f <= FOCAL_RANGE.1 * 1.0001 {
            grid.push(f);
            f *= FOCAL_STEP;
        }
        grid
    }

    /// The best few hypotheses, distinct from each other.
    pub(super) fn search(&self, rng: &mut ChaCha8Rng) -> Vec<Frame> {
        let candidates = self.candidates(rng);
        let pp = self.search_pp;
        let mut hypotheses: Vec<(f64, Frame)> = Vec::new();
        let sin2_excl = (3.0 * SCORE_TOLERANCE_DEG).to_radians().sin().powi(2);
        for v1 in &candidates {
            let consistent: Vec<bool> = self.segs.iter().map(|s| s.sin2(v1) < sin2_excl).collect();
            for focal in self.focal_grid() {
                let cam = Camera { focal, pp };
                let Some(d1) = cam.direction(v1) else {
                    continue;
                };
                for (d2, d3) in self.circle_peaks(&cam, &d1, &consistent) {
                    let frame = Frame {
                        rot: Matrix3::from_columns(&[d1, d2, d3]),
                        cam,
                    };
                    let score = self.penalised_score(&frame);
                    hypotheses.push((score, frame));
                }
            }
        }
        hypotheses.sort_by(|a, b| b.0.total_cmp(&a.0));
        let mut kept: Vec<Frame> = Vec::new();
        for (_, frame) in hypotheses {
            if kept.len() >= REFINED_HYPOTHESES {
                break;
            }
            if kept.iter().all(|k| distinct(k, &frame)) {
                kept.push(frame);
            }
        }
        kept
    }

    /// The (d2, d3) pairs of the two highest peaks of the great-circle vote around `d1`.
    fn circle_peaks(
        &self,
        cam: &Camera,
        d1: &Vector3<f64>,
        consistent: &[bool],
    ) -> Vec<(Vector3<f64>, Vector3<f64>)> {
        let (a, b) = orthonormal_basis(d1);
        let quarter = std::f64::consts::FRAC_PI_2;
        let bin_width = quarter / CIRCLE_BINS as f64;
        let mut hist = [0.0f64; CIRCLE_BINS];
        for (s, &skip) in self.segs.iter().zip(consistent) {
            if skip {
                continue;
            }
            let Some(n) = cam.plane_normal(&s.line) else {
                continue;
            };
            let c = n.cross(d1);
            let sin = c.norm();
            if sin < 0.2 {
                continue;
            }
            let t = c.dot(&b).atan2(c.dot(&a)).rem_euclid(quarter) / bin_width;
            let i0 = (t.floor() as usize) % CIRCLE_BINS;
            let frac = t - t.floor();
            let w = s.weight * sin * sin;
            if let Some(h) = hist.get_mut(i0) {
                *h += w * (1.0 - frac);
            }
            if let Some(h) = hist.get_mut((i0 + 1) % CIRCLE_BINS) {
                *h += w * frac;
            }
        }
        let at = |h: &[f64; CIRCLE_BINS], i: usize| h.get(i % CIRCLE_BINS).copied().unwrap_or(0.0);
        let mut smooth = [0.0f64; CIRCLE_BINS];
        for (i, slot) in smooth.iter_mut().enumerate() {
            *slot = 0.25 * at(&hist, i + CIRCLE_BINS - 1)
                + 0.5 * at(&hist, i)
                + 0.25 * at(&hist, i + 1);
        }
        let mut peaks: Vec<(f64, f64)> = (0..CIRCLE_BINS)
            .filter_map(|i| {
                let (l, c, r) = (
                    at(&smooth, i + CIRCLE_BINS - 1),
                    at(&smooth, i),
                    at(&smooth, i + 1),
                );
                if c > 0.0 && c >= l && c > r {
                    let den = l - 2.0 * c + r;
                    let delta = if den < 0.0 {
                        (0.5 * (l - r) / den).clamp(-0.5, 0.5)
                    } else {
                        0.0
                    };
                    Some((c, (i as f64 + delta) * bin_width))
                } else {
                    None
                }
            })
            .collect();
        peaks.sort_by(|x, y| y.0.total_cmp(&x.0));
        peaks
            .iter()
            .take(2)
            .map(|&(_, theta)| {
                let d2 = a * theta.cos() + b * theta.sin();
                (d2, d1.cross(&d2))
            })
            .collect()
    }
}

/// Two unit vectors completing `d` to an orthonormal basis.
fn orthonormal_basis(d: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let axis = if d.x.abs() <= d.y.abs() && d.x.abs() <= d.z.abs() {
        Vector3::x()
    } else if d.y.abs() <= d.z.abs() {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let a = d
        .cross(&axis)
        .try_normalize(1e-300)
        .unwrap_or_else(Vector3::x);
    let b = d.cross(&a);
    (a, b)
}

/// Whether two frames differ (by more than 3 degrees in some direction or 5 % in focal length).
fn distinct(a: &Frame, b: &Frame) -> bool {
    let cos_max = 3.0f64.to_radians().cos();
    let focal_differs = (a.cam.focal / b.cam.focal).ln().abs() > 0.05;
    // Every direction of `a` must have a counterpart in `b` (up to sign and order).
    let matched =
        (0..3).all(|i| (0..3).any(|j| a.rot.column(i).dot(&b.rot.column(j)).abs().ge(&cos_max)));
    focal_differs || !matched
}
