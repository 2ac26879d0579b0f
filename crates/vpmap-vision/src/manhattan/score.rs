//! How well a hypothesis fits the segments: the score `S` of one vanishing point or of a
//! triplet (see the consistency measure in `model.rs`), and the focal-length prior.

use nalgebra::Vector3;

use super::model::Frame;
use super::problem::{Problem, SCORE_TOLERANCE_DEG};

impl Problem<'_> {
    pub(super) fn sin2_tau() -> f64 {
        SCORE_TOLERANCE_DEG.to_radians().sin().powi(2)
    }

    /// Score of one vanishing point.
    pub(super) fn score_single(&self, v: &Vector3<f64>, sin2_tau: f64) -> f64 {
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
    pub(super) fn penalised_score(&self, frame: &Frame) -> f64 {
        let score = self.score_triplet(&frame.vps());
        if self.known_focal.is_some() {
            score
        } else {
            score
                * focal_prior(
                    frame.cam.focal,
                    self.focal_prior.centre,
                    self.focal_prior.sigma_search,
                )
        }
    }
}

/// The log-normal focal-length prior, 1 at `centre` (by default
/// [`super::problem::FOCAL_PRIOR`]).
fn focal_prior(focal: f64, centre: f64, sigma: f64) -> f64 {
    let z = (focal / centre).ln() / sigma;
    (-0.5 * z * z).exp()
}
