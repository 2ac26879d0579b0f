//! The Manhattan frame: three orthogonal vanishing directions and the camera, from segments.
//!
//! # Model
//! Pinhole camera with square pixels and no skew, camera frame `x` right, `y` down, `z`
//! forward. A unit direction `d` in the camera frame vanishes at the homogeneous image point
//!
//! ```text
//!     v = K d,    K = [[f, 0, c_x], [0, f, c_y], [0, 0, 1]],
//! ```
//!
//! and an image line `l` (`l . x = 0`) back-projects to the plane through the camera centre
//! with normal `n = K^T l`. The three Manhattan directions are the columns of a rotation
//! `R = [d_1 d_2 d_3]`. Internally every image quantity is in *normalised* coordinates
//! `x_n = (x_px - image centre) / longer side`, which keeps homogeneous vectors well scaled;
//! pixel thresholds are stated in working-image pixels (after the internal downscale).
//!
//! # Consistency of a segment with a vanishing point
//! The angle `theta` between the segment and the line joining its midpoint `m` to the
//! vanishing point `v = (v_1, v_2, v_3)`: with the unit segment direction `u` and
//! `w = (v_1 - v_3 m_x, v_2 - v_3 m_y)`,
//!
//! ```text
//!     sin^2 theta = (u x w)^2 / |w|^2,        residual r = (L / 2) sin theta,
//! ```
//!
//! `r` being the distance of the segment's endpoints from that line (Tardif 2009). Both are
//! measured in the image, so they do not depend on the focal length being tried; `v` may lie
//! at infinity (`v_3 = 0`).
//!
//! # Search (after Lu et al. 2017, with the focal length as a search dimension)
//! 1. *First vanishing point candidates*, independent of the camera: intersections
//!    `v = l_i x l_j` of random segment pairs (drawn with probability proportional to length),
//!    scored by `S(v) = sum_i L_i max(0, 1 - sin^2 theta_i / sin^2 tau)`; the best ones with
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
//!
//! # Refinement
//! The best few hypotheses are refined by Levenberg-Marquardt on the residuals `r` of the
//! segments assigned to each direction (a segment supports its best direction when
//! `|r| <= 2` working pixels and `theta <= 3` degrees), with Cauchy weights (iteratively
//! reweighted, scale 1 pixel) and orthogonality built in: the unknowns are a rotation increment
//! `R = exp([w]x) R_0` and, when not given, `ln f` (weak log-normal prior: `sigma = 1` around
//! the longer side) and the principal point (Gaussian prior around the image centre,
//! `sigma = 0.1` longer sides). Assignments are redone between rounds; the refined hypothesis
//! with the best score wins.
//!
//! The principal point is freed only in clear three-point perspective, when the vertical
//! direction is tilted from the image plane by at least [`PRINCIPAL_POINT_MIN_TILT_DEG`]:
//! the orthocentre of the three vanishing points then fixes it. Closer to two-point
//! perspective it is not determined — exactly at zero pitch it lies on the horizon but may
//! slide along it (each position with its own focal length), and near it its distance from
//! the horizon trades off against the pitch — so it stays at the image centre.
//!
//! # Which one is vertical
//! The direction closest to the image's `y` axis (largest `|d_y|` in the camera frame); the
//! two others are reported left (smaller `d_x`) first.

use nalgebra::{DMatrix, DVector, Matrix3, Rotation3, SymmetricEigen, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::{Intrinsics, Result, Segment, VisionError};

/// Segments shorter than this (working pixels) are not used for the estimation.
pub const MIN_SEGMENT_LENGTH_PX: f64 = 12.0;
/// At most this many (longest) segments are used for the estimation.
pub const MAX_SEGMENTS: usize = 350;
/// Fewer usable segments than this give [`VisionError::NotEnoughLines`].
pub const MIN_SEGMENTS: usize = 8;
/// Angle tolerance `tau` of the hypothesis score, degrees.
pub const SCORE_TOLERANCE_DEG: f64 = 2.0;
/// A segment supports a vanishing point when its endpoints are within this distance of the
/// line through its midpoint and the point (working pixels)...
pub const INLIER_DISTANCE_PX: f64 = 2.0;
/// ...and its angle to that line is below this, degrees.
pub const INLIER_ANGLE_DEG: f64 = 3.0;
/// Scale of the Cauchy weights of the refinement, working pixels.
pub const CAUCHY_SCALE_PX: f64 = 1.0;
/// Prior focal length, in units of the image's longer side.
pub const FOCAL_PRIOR: f64 = 1.0;
/// Standard deviation of the focal-length prior in the search, natural log units.
pub const FOCAL_PRIOR_SIGMA_SEARCH: f64 = 1.5;
/// Standard deviation of the focal-length prior in the refinement, natural log units.
pub const FOCAL_PRIOR_SIGMA_REFINE: f64 = 1.0;
/// Standard deviation of the principal point's prior around the image centre, in units of
/// the longer side.
pub const PRINCIPAL_POINT_PRIOR_SIGMA: f64 = 0.1;
/// The principal point is estimated only when the vertical direction is tilted from the image
/// plane by at least this, degrees.
pub const PRINCIPAL_POINT_MIN_TILT_DEG: f64 = 15.0;
/// Focal-length search range, in units of the longer side.
const FOCAL_RANGE: (f64, f64) = (0.3, 3.0);
/// Ratio between neighbouring focal lengths of the search grid.
const FOCAL_STEP: f64 = 1.06;
/// Random segment pairs drawn for the first vanishing point.
const PAIR_SAMPLES: usize = 400;
/// First vanishing point candidates kept.
const CANDIDATES: usize = 6;
/// Bins of the 90-degree great-circle histogram.
const CIRCLE_BINS: usize = 90;
/// Hypotheses refined.
const REFINED_HYPOTHESES: usize = 3;
/// Assignment rounds of the refinement.
const REFINE_ROUNDS: usize = 4;
/// Levenberg-Marquardt iterations per round.
const LM_ITERATIONS: usize = 10;

/// A segment in normalised coordinates.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Seg {
    mid: [f64; 2],
    dir: [f64; 2],
    half_len: f64,
    /// Homogeneous line `(a, b, c)`, `a^2 + b^2 = 1`.
    line: Vector3<f64>,
    weight: f64,
}

impl Seg {
    fn new(s: &Segment, norm: &Normaliser) -> Option<Self> {
        let p = norm.norm_from_px(s.start_px);
        let q = norm.norm_from_px(s.end_px);
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let len = dx.hypot(dy);
        if !(len.is_finite() && len > 1e-12) {
            return None;
        }
        let dir = [dx / len, dy / len];
        let mid = [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])];
        // Line through p with normal (-dir_y, dir_x).
        let (a, b) = (-dir[1], dir[0]);
        let line = Vector3::new(a, b, -(a * mid[0] + b * mid[1]));
        Some(Self {
            mid,
            dir,
            half_len: 0.5 * len,
            line,
            weight: len,
        })
    }

    /// `(u x w, |w|^2)` for the vanishing point `v`.
    #[inline]
    fn cross_and_norm2(&self, v: &Vector3<f64>) -> (f64, f64) {
        let wx = v.x - v.z * self.mid[0];
        let wy = v.y - v.z * self.mid[1];
        (self.dir[0] * wy - self.dir[1] * wx, wx * wx + wy * wy)
    }

    /// `sin^2` of the angle between the segment and the line from its midpoint to `v`
    /// (1 when `v` sits on the midpoint).
    #[inline]
    fn sin2(&self, v: &Vector3<f64>) -> f64 {
        let (c, n2) = self.cross_and_norm2(v);
        if n2 <= 1e-24 { 1.0 } else { c * c / n2 }
    }

    /// Signed distance of the endpoints from the line through the midpoint and `v`
    /// (normalised units).
    #[inline]
    fn residual(&self, v: &Vector3<f64>) -> f64 {
        let (c, n2) = self.cross_and_norm2(v);
        if n2 <= 1e-24 {
            self.half_len
        } else {
            self.half_len * c / n2.sqrt()
        }
    }
}

/// Pixels <-> normalised coordinates.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Normaliser {
    /// Image centre, input pixels.
    centre: [f64; 2],
    /// Input pixels per normalised unit (the longer side).
    unit_px: f64,
    /// Working pixels per normalised unit.
    work_px: f64,
}

impl Normaliser {
    pub(crate) fn new(size: [u32; 2], working_scale: f64) -> Self {
        let unit_px = f64::from(size[0].max(size[1]));
        Self {
            centre: [0.5 * f64::from(size[0]), 0.5 * f64::from(size[1])],
            unit_px,
            work_px: unit_px * working_scale,
        }
    }

    fn norm_from_px(self, p: [f64; 2]) -> [f64; 2] {
        [
            (p[0] - self.centre[0]) / self.unit_px,
            (p[1] - self.centre[1]) / self.unit_px,
        ]
    }

    fn px_from_norm(self, p: [f64; 2]) -> [f64; 2] {
        [
            p[0] * self.unit_px + self.centre[0],
            p[1] * self.unit_px + self.centre[1],
        ]
    }
}

/// Intrinsics in normalised coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Camera {
    focal: f64,
    pp: [f64; 2],
}

impl Camera {
    /// The vanishing point `K d` of direction `d`.
    #[inline]
    fn vp(&self, d: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            self.focal * d.x + self.pp[0] * d.z,
            self.focal * d.y + self.pp[1] * d.z,
            d.z,
        )
    }

    /// The unit direction `K^-1 v` of the vanishing point `v`.
    fn direction(&self, v: &Vector3<f64>) -> Option<Vector3<f64>> {
        Vector3::new(
            (v.x - self.pp[0] * v.z) / self.focal,
            (v.y - self.pp[1] * v.z) / self.focal,
            v.z,
        )
        .try_normalize(1e-300)
    }

    /// The unit normal `K^T l` of the plane back-projecting line `l`.
    #[inline]
    fn plane_normal(&self, l: &Vector3<f64>) -> Option<Vector3<f64>> {
        Vector3::new(
            self.focal * l.x,
            self.focal * l.y,
            self.pp[0] * l.x + self.pp[1] * l.y + l.z,
        )
        .try_normalize(1e-300)
    }
}

/// Three orthogonal directions (columns) and the camera.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frame {
    rot: Matrix3<f64>,
    cam: Camera,
}

impl Frame {
    fn vps(&self) -> [Vector3<f64>; 3] {
        [0, 1, 2].map(|k| self.cam.vp(&self.rot.column(k).into_owned()))
    }
}

/// What the estimation found, in input pixels.
#[derive(Clone, Debug)]
pub(crate) struct Estimate {
    /// The three unit directions (camera frame, `z >= 0`): two horizontal, then vertical.
    pub directions: [[f64; 3]; 3],
    /// Indices of the supporting segments, same order.
    pub support: [Vec<usize>; 3],
    /// Intrinsics, input pixels.
    pub intrinsics: Intrinsics,
    /// Whether the principal point was estimated.
    pub principal_point_estimated: bool,
}

/// The inputs of the estimation that do not change during it.
struct Problem<'a> {
    segs: Vec<Seg>,
    norm: Normaliser,
    known_focal: Option<f64>,
    known_pp: Option<[f64; 2]>,
    all: &'a [Segment],
}

/// Estimate the Manhattan frame and the camera from `segments` (input pixels) of an image of
/// `size` pixels analysed at `working_scale` working pixels per input pixel.
pub(crate) fn estimate(
    segments: &[Segment],
    size: [u32; 2],
    working_scale: f64,
    focal_px: Option<f64>,
    principal_point_px: Option<[f64; 2]>,
    seed: u64,
) -> Result<Estimate> {
    let norm = Normaliser::new(size, working_scale);
    let min_len = MIN_SEGMENT_LENGTH_PX / norm.work_px;
    let mut segs: Vec<Seg> = segments
        .iter()
        .filter_map(|s| Seg::new(s, &norm))
        .filter(|s| 2.0 * s.half_len >= min_len)
        .collect();
    segs.sort_by(|a, b| b.half_len.total_cmp(&a.half_len));
    segs.truncate(MAX_SEGMENTS);
    if segs.len() < MIN_SEGMENTS {
        return Err(VisionError::NotEnoughLines {
            found: segs.len(),
            needed: MIN_SEGMENTS,
        });
    }
    let problem = Problem {
        segs,
        norm,
        known_focal: focal_px.map(|f| f / norm.unit_px),
        known_pp: principal_point_px.map(|p| norm.norm_from_px(p)),
        all: segments,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let hypotheses = problem.search(&mut rng);
    let mut best: Option<(f64, Frame, bool)> = None;
    for hypothesis in hypotheses {
        let (frame, pp_free) = problem.refine(hypothesis);
        let score = problem.penalised_score(&frame);
        if best.as_ref().is_none_or(|b| score > b.0) {
            best = Some((score, frame, pp_free));
        }
    }
    let Some((_, frame, pp_free)) = best else {
        return Err(VisionError::NoOrthogonalDirections {
            segments: problem.segs.len(),
        });
    };
    problem.finish(&frame, pp_free)
}

impl Problem<'_> {
    fn sin2_tau() -> f64 {
        SCORE_TOLERANCE_DEG.to_radians().sin().powi(2)
    }

    fn default_pp(&self) -> [f64; 2] {
        self.known_pp.unwrap_or([0.0, 0.0])
    }

    /// Score of one vanishing point.
    fn score_single(&self, v: &Vector3<f64>, sin2_tau: f64) -> f64 {
        self.segs
            .iter()
            .map(|s| {
                let e = s.sin2(v);
                if e < sin2_tau {
                    s.weight * (1.0 - e / sin2_tau)
                } else {
                    0.0
                }
            })
            .sum()
    }

    /// Score of three vanishing points: each segment counts for its best one.
    fn score_triplet(&self, vps: &[Vector3<f64>; 3]) -> f64 {
        let sin2_tau = Self::sin2_tau();
        self.segs
            .iter()
            .map(|s| {
                let e = s.sin2(&vps[0]).min(s.sin2(&vps[1])).min(s.sin2(&vps[2]));
                if e < sin2_tau {
                    s.weight * (1.0 - e / sin2_tau)
                } else {
                    0.0
                }
            })
            .sum()
    }

    /// The score with the focal-length prior when the focal length is unknown.
    fn penalised_score(&self, frame: &Frame) -> f64 {
        let score = self.score_triplet(&frame.vps());
        if self.known_focal.is_some() {
            score
        } else {
            score * focal_prior(frame.cam.focal, FOCAL_PRIOR_SIGMA_SEARCH)
        }
    }

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
            let eig = SymmetricEigen::new(m);
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
    fn search(&self, rng: &mut ChaCha8Rng) -> Vec<Frame> {
        let candidates = self.candidates(rng);
        let pp = self.default_pp();
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

    /// Whether the principal point is to be estimated for this frame.
    fn principal_point_free(&self, frame: &Frame) -> bool {
        if self.known_pp.is_some() {
            return false;
        }
        let vertical = vertical_index(&frame.rot);
        let tilt = frame
            .rot
            .get((2, vertical))
            .map_or(0.0, |z| z.abs().min(1.0).asin().to_degrees());
        tilt >= PRINCIPAL_POINT_MIN_TILT_DEG
    }

    /// Levenberg-Marquardt refinement with reassignment; returns the frame and whether the
    /// principal point was freed.
    fn refine(&self, start: Frame) -> (Frame, bool) {
        let mut frame = start;
        let mut pp_free = false;
        let focal_free = self.known_focal.is_none();
        let focal_prior_centre = FOCAL_PRIOR.ln();
        for round in 0..REFINE_ROUNDS {
            if round >= 1 {
                pp_free = self.principal_point_free(&frame);
            }
            let assigned = self.assign(&frame);
            if assigned.iter().filter(|a| a.is_some()).count() < 3 {
                break;
            }
            let base = frame;
            let pp_centre = self.default_pp();
            let work_px = self.norm.work_px;
            let build = |x: &[f64]| -> Frame {
                let w = Vector3::new(
                    x.first().copied().unwrap_or(0.0),
                    x.get(1).copied().unwrap_or(0.0),
                    x.get(2).copied().unwrap_or(0.0),
                );
                let rot = Rotation3::new(w).matrix() * base.rot;
                let mut cam = base.cam;
                let mut next = 3;
                if focal_free {
                    cam.focal = base.cam.focal * x.get(next).copied().unwrap_or(0.0).exp();
                    next += 1;
                }
                if pp_free {
                    cam.pp = [
                        base.cam.pp[0] + x.get(next).copied().unwrap_or(0.0),
                        base.cam.pp[1] + x.get(next + 1).copied().unwrap_or(0.0),
                    ];
                }
                Frame { rot, cam }
            };
            // Cauchy weights from the residuals at the start of the round.
            let start_vps = base.vps();
            let weights: Vec<f64> = self
                .segs
                .iter()
                .zip(&assigned)
                .map(|(s, a)| {
                    a.and_then(|k| start_vps.get(k)).map_or(0.0, |v| {
                        let r = s.residual(v) * work_px / CAUCHY_SCALE_PX;
                        1.0 / (1.0 + r * r)
                    })
                })
                .collect();
            let residuals = |x: &[f64], out: &mut Vec<f64>| {
                out.clear();
                let f = build(x);
                let vps = f.vps();
                for ((s, a), w) in self.segs.iter().zip(&assigned).zip(&weights) {
                    if let Some(v) = a.and_then(|k| vps.get(k)) {
                        out.push(w.sqrt() * s.residual(v) * work_px / CAUCHY_SCALE_PX);
                    }
                }
                if focal_free {
                    out.push((f.cam.focal.ln() - focal_prior_centre) / FOCAL_PRIOR_SIGMA_REFINE);
                }
                if pp_free {
                    out.push((f.cam.pp[0] - pp_centre[0]) / PRINCIPAL_POINT_PRIOR_SIGMA);
                    out.push((f.cam.pp[1] - pp_centre[1]) / PRINCIPAL_POINT_PRIOR_SIGMA);
                }
            };
            let dims = 3 + usize::from(focal_free) + 2 * usize::from(pp_free);
            let x = levenberg_marquardt(vec![0.0; dims], residuals, LM_ITERATIONS);
            let next = build(&x);
            if next.rot.iter().all(|v| v.is_finite())
                && next.cam.focal.is_finite()
                && next.cam.focal > 1e-3
                && next.cam.pp.iter().all(|v| v.is_finite())
            {
                frame = next;
            }
        }
        (frame, pp_free)
    }

    /// The direction each segment supports, if any.
    fn assign(&self, frame: &Frame) -> Vec<Option<usize>> {
        let vps = frame.vps();
        self.segs
            .iter()
            .map(|s| best_support(s, &vps, self.norm.work_px))
            .collect()
    }

    /// Order the directions, check their support and convert to pixels.
    fn finish(&self, frame: &Frame, pp_free: bool) -> Result<Estimate> {
        let vertical = vertical_index(&frame.rot);
        let mut horizontals: Vec<usize> = (0..3).filter(|&k| k != vertical).collect();
        let dirs: Vec<Vector3<f64>> = (0..3)
            .map(|k| canonical_sign(frame.rot.column(k).into_owned()))
            .collect();
        horizontals.sort_by(|&i, &j| {
            let x = |k: usize| dirs.get(k).map_or(0.0, |d| d.x);
            x(i).total_cmp(&x(j))
        });
        let order = [
            horizontals.first().copied().unwrap_or(0),
            horizontals.get(1).copied().unwrap_or(1),
            vertical,
        ];
        // Support among the working segments decides whether the frame is determined.
        let assigned = self.assign(frame);
        let counts = [0, 1, 2].map(|k| assigned.iter().filter(|a| **a == Some(k)).count());
        let supported = counts.iter().filter(|&&c| c >= 2).count();
        if supported < 2 {
            return Err(VisionError::NoOrthogonalDirections {
                segments: self.segs.len(),
            });
        }
        // Support among every segment, for the caller.
        let vps = frame.vps();
        let mut support: [Vec<usize>; 3] = Default::default();
        for (i, s) in self.all.iter().enumerate() {
            if let Some(seg) = Seg::new(s, &self.norm)
                && let Some(k) = best_support(&seg, &vps, self.norm.work_px)
                && let Some(slot) = order.iter().position(|&o| o == k)
                && let Some(list) = support.get_mut(slot)
            {
                list.push(i);
            }
        }
        let directions = order.map(|k| {
            let d = dirs.get(k).copied().unwrap_or_else(Vector3::z);
            [d.x, d.y, d.z]
        });
        Ok(Estimate {
            directions,
            support,
            intrinsics: Intrinsics {
                focal_px: frame.cam.focal * self.norm.unit_px,
                principal_point_px: self.norm.px_from_norm(frame.cam.pp),
            },
            principal_point_estimated: pp_free,
        })
    }
}

/// The vanishing point (index into `vps`) that segment `s` supports, if any.
fn best_support(s: &Seg, vps: &[Vector3<f64>; 3], work_px: f64) -> Option<usize> {
    let sin2_max = INLIER_ANGLE_DEG.to_radians().sin().powi(2);
    let mut best: Option<(usize, f64)> = None;
    for (k, v) in vps.iter().enumerate() {
        let e = s.sin2(v);
        if e < sin2_max && best.is_none_or(|b| e < b.1) {
            best = Some((k, e));
        }
    }
    let (k, _) = best?;
    let r = vps.get(k).map_or(f64::INFINITY, |v| s.residual(v)).abs() * work_px;
    (r <= INLIER_DISTANCE_PX).then_some(k)
}

/// The log-normal focal-length prior, 1 at [`FOCAL_PRIOR`].
fn focal_prior(focal: f64, sigma: f64) -> f64 {
    let z = (focal / FOCAL_PRIOR).ln() / sigma;
    (-0.5 * z * z).exp()
}

/// The column closest to the image's y axis (largest `|d_y|`).
pub(crate) fn vertical_index(rot: &Matrix3<f64>) -> usize {
    (0..3)
        .max_by(|&i, &j| {
            let y = |k: usize| rot.get((1, k)).map_or(0.0, |v| v.abs());
            y(i).total_cmp(&y(j))
        })
        .unwrap_or(2)
}

/// The sign with `z >= 0` (then `x >= 0`, then `y >= 0` when the earlier ones are zero).
pub(crate) fn canonical_sign(d: Vector3<f64>) -> Vector3<f64> {
    const EPS: f64 = 1e-12;
    let flip = if d.z.abs() > EPS {
        d.z < 0.0
    } else if d.x.abs() > EPS {
        d.x < 0.0
    } else {
        d.y < 0.0
    };
    if flip { -d } else { d }
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

/// Minimise `|r(x)|^2` by Levenberg-Marquardt with a forward-difference Jacobian.
fn levenberg_marquardt(
    mut x: Vec<f64>,
    residuals: impl Fn(&[f64], &mut Vec<f64>),
    iterations: usize,
) -> Vec<f64> {
    let n = x.len();
    let mut r = Vec::new();
    residuals(&x, &mut r);
    let mut cost: f64 = r.iter().map(|v| v * v).sum();
    if !cost.is_finite() {
        return x;
    }
    let mut lambda = 1e-3;
    let mut probe = Vec::new();
    let mut trial_r = Vec::new();
    for _ in 0..iterations {
        let m = r.len();
        let mut columns = Vec::with_capacity(n);
        for j in 0..n {
            let h = 1e-7;
            probe.clone_from(&x);
            if let Some(p) = probe.get_mut(j) {
                *p += h;
            }
            residuals(&probe, &mut trial_r);
            if trial_r.len() != m {
                return x;
            }
            columns.push(DVector::from_iterator(
                m,
                trial_r.iter().zip(&r).map(|(a, b)| (a - b) / h),
            ));
        }
        let jac = DMatrix::from_columns(&columns);
        let jt = jac.transpose();
        let jtj = &jt * &jac;
        let jtr = &jt * DVector::from_column_slice(&r);
        let mut improved = false;
        for _ in 0..8 {
            let damping = jtj.diagonal().map(|d| lambda * (d + 1e-12));
            let a = &jtj + DMatrix::from_diagonal(&damping);
            let Some(chol) = a.cholesky() else {
                lambda *= 10.0;
                continue;
            };
            let step = chol.solve(&(-&jtr));
            let trial: Vec<f64> = x.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
            residuals(&trial, &mut trial_r);
            let trial_cost: f64 = trial_r.iter().map(|v| v * v).sum();
            if trial_r.len() == m && trial_cost.is_finite() && trial_cost < cost {
                let gain = cost - trial_cost;
                x = trial;
                std::mem::swap(&mut r, &mut trial_r);
                cost = trial_cost;
                lambda = (lambda * 0.3).max(1e-9);
                improved = gain > 1e-12 * cost.max(1.0);
                break;
            }
            lambda *= 10.0;
        }
        if !improved {
            break;
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg(p: [f64; 2], q: [f64; 2]) -> Segment {
        Segment {
            start_px: p,
            end_px: q,
            strength: 1.0,
        }
    }

    #[test]
    fn a_segment_pointing_at_a_vanishing_point_has_zero_residual() {
        let norm = Normaliser::new([640, 480], 1.0);
        let s = Seg::new(&seg([100.0, 100.0], [200.0, 150.0]), &norm).unwrap();
        // The line continues through (300, 200) and (500, 300).
        let v = norm.norm_from_px([500.0, 300.0]);
        let v = Vector3::new(v[0], v[1], 1.0);
        assert!(s.sin2(&v) < 1e-20);
        assert!(s.residual(&v).abs() < 1e-12);
        // At infinity along the segment.
        assert!(s.sin2(&Vector3::new(2.0, 1.0, 0.0)) < 1e-20);
        // Perpendicular: sin^2 = 1.
        assert!((s.sin2(&Vector3::new(-1.0, 2.0, 0.0)) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn camera_maps_directions_and_points_both_ways() {
        let cam = Camera {
            focal: 1.1,
            pp: [0.02, -0.03],
        };
        let d = Vector3::new(0.3, -0.4, 0.8).normalize();
        let back = cam.direction(&cam.vp(&d)).unwrap();
        assert!((back - d).norm() < 1e-12);
        // A line through two vanishing points back-projects to the plane of both directions.
        let e = Vector3::new(-0.5, 0.1, 0.6).normalize();
        let l = cam.vp(&d).cross(&cam.vp(&e));
        let n = cam.plane_normal(&l).unwrap();
        assert!(n.dot(&d).abs() < 1e-12 && n.dot(&e).abs() < 1e-12);
    }

    #[test]
    fn levenberg_marquardt_fits_a_line() {
        let pts = [(0.0, 1.0), (1.0, 3.1), (2.0, 4.9), (3.0, 7.0)];
        let x = levenberg_marquardt(
            vec![0.0, 0.0],
            |x, out| {
                out.clear();
                out.extend(pts.iter().map(|(t, y)| x[0] * t + x[1] - y));
            },
            20,
        );
        assert!(
            (x[0] - 1.98).abs() < 1e-3 && (x[1] - 1.03).abs() < 1e-3,
            "{x:?}"
        );
    }

    #[test]
    fn the_vertical_is_the_direction_closest_to_the_image_y_axis() {
        let rot = Matrix3::from_columns(&[
            Vector3::new(0.8, 0.1, 0.59),
            Vector3::new(0.1, -0.95, 0.3),
            Vector3::new(-0.6, -0.3, 0.74),
        ]);
        assert_eq!(vertical_index(&rot), 1);
        assert!(canonical_sign(Vector3::new(0.0, 1.0, -0.5)).z > 0.0);
        assert!(canonical_sign(Vector3::new(-1.0, 0.0, 0.0)).x > 0.0);
    }
}
