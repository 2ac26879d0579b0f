//! The Manhattan frame: three orthogonal vanishing directions and the camera, from segments.
//!
//! From the longest (at most [`MAX_SEGMENTS`]) segments of at least [`MIN_SEGMENT_LENGTH_PX`];
//! pixel thresholds here are in working-image pixels (after the internal downscale). In the
//! hypotheses' scores a segment weighs its length, but the pieces of one physical edge
//! together at most [`SCORE_WEIGHT_CAP_PX`] (`capped_weights`): a few long edges in one place
//! (a pole, a cable, the two sides of a thin bar in front of the room) cannot outvote many
//! short edges along the room's axes. Each step is described in its file:
//! 1. `model.rs`: the pinhole model in normalised coordinates, and the consistency of a
//!    segment with a vanishing point (Tardif 2009);
//! 2. `search.rs`: first vanishing point candidates from random segment pairs, then the
//!    2-line search for the other two directions over a focal-length grid (after Lu et al.
//!    2017), each hypothesis scored as in `score.rs`;
//! 3. `refine.rs`: the best few hypotheses refined by a Cauchy-reweighted Levenberg-Marquardt
//!    fit (`lm.rs`) of the rotation, focal length and, in clear three-point perspective, the
//!    principal point; the refined hypothesis with the best score wins;
//! 4. here, in clear three-point perspective (the principal point freed), a second pass for a
//!    photo cropped off its centre: steps 2-3 again about the principal point the first found,
//!    with its prior widened to [`OFF_CENTRE_PRIOR_SIGMA`], twice; its frame is taken when it
//!    scores [`OFF_CENTRE_SCORE_GAIN`] times the first's or more (`detect` then judges the
//!    principal point found, [`crate::Detection::principal_point_off_centre`]);
//! 5. here: which direction is vertical, their support, and pixels again.
//!
//! # Which one is vertical
//! The direction closest to the image's `y` axis (largest `|d_y|` in the camera frame); the
//! two others are reported left (smaller `d_x`) first.

mod lm;
mod model;
mod problem;
mod refine;
mod score;
mod search;

use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::detection::{Intrinsics, Segment};
use crate::error::{Result, VisionError};
use crate::uncertainty::edge_clusters;
use model::{Frame, Normaliser, Seg, vertical_index};
pub use problem::{
    CAUCHY_SCALE_PX, FOCAL_PRIOR, FOCAL_PRIOR_SIGMA_REFINE, FOCAL_PRIOR_SIGMA_SEARCH,
    INLIER_ANGLE_DEG, INLIER_DISTANCE_PX, MAX_SEGMENTS, MIN_SEGMENT_LENGTH_PX, MIN_SEGMENTS,
    OFF_CENTRE_PRIOR_SIGMA, OFF_CENTRE_SCORE_GAIN, PRINCIPAL_POINT_MIN_TILT_DEG,
    PRINCIPAL_POINT_PRIOR_SIGMA, SCORE_TOLERANCE_DEG, SCORE_WEIGHT_CAP_PX,
};
use problem::{FOCAL_STEP, FocalPrior, OFF_CENTRE_PASSES, Problem};
use refine::best_support;

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

/// Estimate the Manhattan frame and the camera from `segments` (input pixels) of an image of
/// `size` pixels analysed at `working_scale` working pixels per input pixel.
pub(crate) fn estimate(
    segments: &[Segment],
    size: [u32; 2],
    working_scale: f64,
    focal_px: Option<f64>,
    principal_point_px: Option<[f64; 2]>,
    focal_prior: Option<(f64, f64)>,
    seed: u64,
) -> Result<Estimate> {
    let norm = Normaliser::new(size, working_scale);
    let min_len = MIN_SEGMENT_LENGTH_PX / norm.work_px;
    let mut usable: Vec<(Seg, &Segment)> = segments
        .iter()
        .filter_map(|s| Some((Seg::new(s, &norm)?, s)))
        .filter(|(s, _)| 2.0 * s.half_len >= min_len)
        .collect();
    usable.sort_by(|a, b| b.0.half_len.total_cmp(&a.0.half_len));
    usable.truncate(MAX_SEGMENTS);
    let segs = capped_weights(&usable, SCORE_WEIGHT_CAP_PX / norm.work_px);
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
        focal_prior: focal_prior
            .filter(|(f, sd)| f.is_finite() && *f > 0.0 && sd.is_finite() && *sd > 0.0)
            .map_or(
                FocalPrior {
                    centre: FOCAL_PRIOR,
                    sigma_search: FOCAL_PRIOR_SIGMA_SEARCH,
                    sigma_refine: FOCAL_PRIOR_SIGMA_REFINE,
                },
                |(f, sd)| FocalPrior {
                    centre: f / norm.unit_px,
                    // The search's grid steps 6 %: a narrower prior would fall between steps.
                    sigma_search: sd.max(FOCAL_STEP - 1.0),
                    sigma_refine: sd,
                },
            ),
        all: segments,
        search_pp: principal_point_px.map_or([0.0, 0.0], |p| norm.norm_from_px(p)),
        pp_sigma: PRINCIPAL_POINT_PRIOR_SIGMA,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut best = problem.best_frame(&mut rng);
    if problem.known_pp.is_none()
        && let Some((first_score, first, true)) = best
        && let Some(second) = problem.off_centre(first, &mut rng)
        && second.0 > OFF_CENTRE_SCORE_GAIN * first_score
    {
        best = Some(second);
    }
    let Some((_, frame, pp_free)) = best else {
        return Err(VisionError::NoOrthogonalDirections {
            segments: problem.segs.len(),
        });
    };
    problem.finish(&frame, pp_free)
}

impl Problem<'_> {
    /// The best refined hypothesis by the penalised score: its score, frame and whether the
    /// principal point was freed.
    fn best_frame(&self, rng: &mut ChaCha8Rng) -> Option<(f64, Frame, bool)> {
        let mut best: Option<(f64, Frame, bool)> = None;
        for hypothesis in self.search(rng) {
            let (frame, pp_free) = self.refine(hypothesis);
            let score = self.penalised_score(&frame);
            if best.as_ref().is_none_or(|b| score > b.0) {
                best = Some((score, frame, pp_free));
            }
        }
        best
    }

    /// The second pass, for a photo that may be cropped off its centre: the search and the
    /// refinement again, [`OFF_CENTRE_PASSES`] times, each about the principal point the last
    /// found, with its prior widened to [`OFF_CENTRE_PRIOR_SIGMA`]. The first pass builds its
    /// hypotheses about the image centre and holds the principal point near it, so on a crop
    /// its frame is a compromise between the three directions (the renders cropped by a
    /// quarter: points 1.4-24 degrees off). The best frame of the last pass, when its
    /// principal point was freed.
    fn off_centre(&self, first: Frame, rng: &mut ChaCha8Rng) -> Option<(f64, Frame, bool)> {
        let mut at = first;
        let mut found = None;
        for _ in 0..OFF_CENTRE_PASSES {
            let pass = Problem {
                segs: self.segs.clone(),
                search_pp: at.cam.pp,
                pp_sigma: OFF_CENTRE_PRIOR_SIGMA,
                ..*self
            };
            let best = pass.best_frame(rng)?;
            at = best.1;
            found = Some(best);
        }
        found.filter(|f| f.2)
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

/// The segments of `usable` with their weights in the hypothesis score: the pieces of one
/// physical edge (within [`SAME_EDGE_DEG`](crate::uncertainty::SAME_EDGE_DEG) and
/// [`SAME_EDGE_PX`](crate::uncertainty::SAME_EDGE_PX) of each other's line) weigh together
/// their summed length, but at most `cap` (normalised units), shared in proportion to their
/// lengths. A long edge is one structure: a pole or a cable across the photo, or the two sides
/// of a thin bar, is no more evidence that its direction is a room axis than a box's edge.
fn capped_weights(usable: &[(Seg, &Segment)], cap: f64) -> Vec<Seg> {
    let originals: Vec<&Segment> = usable.iter().map(|(_, s)| *s).collect();
    let edges = edge_clusters(&originals);
    let mut totals = vec![0.0; usable.len()];
    for ((s, _), &e) in usable.iter().zip(&edges) {
        if let Some(t) = totals.get_mut(e) {
            *t += 2.0 * s.half_len;
        }
    }
    usable
        .iter()
        .zip(&edges)
        .map(|((s, _), &e)| {
            let total = totals.get(e).copied().unwrap_or(0.0);
            let length = 2.0 * s.half_len;
            let weight = if total > 0.0 {
                total.min(cap) * length / total
            } else {
                0.0
            };
            Seg { weight, ..*s }
        })
        .collect()
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
    use nalgebra::Matrix3;

    #[test]
    fn the_pieces_of_one_edge_weigh_together_at_most_the_cap() {
        let norm = Normaliser::new([640, 480], 1.0);
        let seg = |a: [f64; 2], b: [f64; 2]| Segment {
            start_px: a,
            end_px: b,
            strength: 1.0,
        };
        // Two pieces of one edge (200 and 100 px), a parallel edge 10 px away (300 px) and a
        // short edge of another direction (20 px).
        let raw = [
            seg([10.0, 100.0], [210.0, 100.0]),
            seg([230.0, 100.5], [330.0, 100.5]),
            seg([10.0, 110.0], [310.0, 110.0]),
            seg([400.0, 50.0], [400.0, 70.0]),
        ];
        let usable: Vec<(Seg, &Segment)> = raw
            .iter()
            .map(|s| (Seg::new(s, &norm).unwrap(), s))
            .collect();
        let cap_px = 48.0;
        let w: Vec<f64> = capped_weights(&usable, cap_px / norm.work_px)
            .iter()
            .map(|s| s.weight * norm.work_px)
            .collect();
        // The edge's pieces share the cap by length; the other edges are on their own.
        assert!(
            (w[0] - 32.0).abs() < 1e-9 && (w[1] - 16.0).abs() < 1e-9,
            "{w:?}"
        );
        assert!((w[2] - cap_px).abs() < 1e-9, "{w:?}");
        assert!((w[3] - 20.0).abs() < 1e-9, "{w:?}");
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
