//! The Manhattan frame: three orthogonal vanishing directions and the camera, from segments.
//!
//! From the longest (at most [`MAX_SEGMENTS`]) segments of at least [`MIN_SEGMENT_LENGTH_PX`];
//! pixel thresholds here are in working-image pixels (after the internal downscale). Each step
//! is described in its file:
//! 1. `model.rs`: the pinhole model in normalised coordinates, and the consistency of a
//!    segment with a vanishing point (Tardif 2009);
//! 2. `search.rs`: first vanishing point candidates from random segment pairs, then the
//!    2-line search for the other two directions over a focal-length grid (after Lu et al.
//!    2017), each hypothesis scored as in `score.rs`;
//! 3. `refine.rs`: the best few hypotheses refined by a Cauchy-reweighted Levenberg-Marquardt
//!    fit (`lm.rs`) of the rotation, focal length and, in clear three-point perspective, the
//!    principal point; the refined hypothesis with the best score wins;
//! 4. here: which direction is vertical, their support, and pixels again.
//!
//! # Which one is vertical
//! The direction closest to the image's `y` axis (largest `|d_y|` in the camera frame); the
//! two others are reported left (smaller `d_x`) first.

mod lm;
mod model;
mod refine;
mod score;
mod search;

use nalgebra::{Matrix3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::{Intrinsics, Result, Segment, VisionError};
use model::{Frame, Normaliser, Seg};
use refine::best_support;

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
    fn default_pp(&self) -> [f64; 2] {
        self.known_pp.unwrap_or([0.0, 0.0])
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

#[cfg(test)]
mod tests {
    use super::*;

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
