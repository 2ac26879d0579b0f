//! The estimation's fixed inputs ([`Problem`], whose steps are implemented in `search.rs`,
//! `score.rs` and `refine.rs`) and every threshold of the Manhattan estimation.

use crate::detection::Segment;

use super::model::{Normaliser, Seg};

/// Segments shorter than this (working pixels) are not used for the estimation.
pub const MIN_SEGMENT_LENGTH_PX: f64 = 12.0;
/// At most this many (longest) segments are used for the estimation.
pub const MAX_SEGMENTS: usize = 350;
/// Fewer usable segments than this give [`VisionError::NotEnoughLines`](crate::VisionError::NotEnoughLines).
pub const MIN_SEGMENTS: usize = 8;
/// The most one physical edge weighs in the hypothesis score, working pixels of length (its
/// pieces share it): about a box edge's length at the working scale. Chosen on York Urban and
/// the cluttered renders together (`docs/detection.md`): 32, 48 and 77 px (0.05, 0.075 and 0.12
/// longer sides) all detect every render within 1.5 degrees, where length without a cap
/// leaves 9 of 16 renders 1.5 to 42 degrees off.
pub const SCORE_WEIGHT_CAP_PX: f64 = 48.0;
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
/// The sd of the principal point's prior in the second pass (a photo cropped off its centre;
/// step 4 of the module's description), in units of the longer side: wide enough to let the
/// edges put it anywhere in the photo.
pub const OFF_CENTRE_PRIOR_SIGMA: f64 = 0.5;
/// The second pass's frame replaces the first only when its score is higher by this factor:
/// on whole photos the freer principal point gains at most 0.5 % (the 16 cluttered renders;
/// the one York Urban photo in clear three-point perspective loses 0.1 %), on the renders
/// cropped off their centre 1.7-15 % where it finds the true one (`docs/detection.md`, "Photos
/// cropped off their centres").
pub const OFF_CENTRE_SCORE_GAIN: f64 = 1.01;
/// Searches of the second pass, each about the principal point the last one found.
pub(super) const OFF_CENTRE_PASSES: usize = 2;
/// The principal point is estimated only when the vertical direction is tilted from the image
/// plane by at least this, degrees.
pub const PRINCIPAL_POINT_MIN_TILT_DEG: f64 = 15.0;
/// Focal-length search range, in units of the longer side.
pub(super) const FOCAL_RANGE: (f64, f64) = (0.3, 3.0);
/// Ratio between neighbouring focal lengths of the search grid.
pub(super) const FOCAL_STEP: f64 = 1.06;
/// Random segment pairs drawn for the first vanishing point.
pub(super) const PAIR_SAMPLES: usize = 400;
/// First vanishing point candidates kept.
pub(super) const CANDIDATES: usize = 6;
/// Bins of the 90-degree great-circle histogram.
pub(super) const CIRCLE_BINS: usize = 90;
/// Hypotheses refined.
pub(super) const REFINED_HYPOTHESES: usize = 3;
/// Assignment rounds of the refinement.
pub(super) const REFINE_ROUNDS: usize = 4;
/// Levenberg-Marquardt iterations per round.
pub(super) const LM_ITERATIONS: usize = 10;

/// A log-normal prior on the focal length (normalised units).
#[derive(Clone, Copy, Debug)]
pub(super) struct FocalPrior {
    /// Its centre.
    pub(super) centre: f64,
    /// Its sd in `ln f` for the search's score.
    pub(super) sigma_search: f64,
    /// Its sd in `ln f` for the refinement.
    pub(super) sigma_refine: f64,
}

/// The inputs of the estimation that do not change during it.
pub(super) struct Problem<'a> {
    /// The usable segments, longest first, normalised.
    pub(super) segs: Vec<Seg>,
    /// Pixels to normalised coordinates.
    pub(super) norm: Normaliser,
    /// The known focal length, normalised.
    pub(super) known_focal: Option<f64>,
    /// The known principal point, normalised.
    pub(super) known_pp: Option<[f64; 2]>,
    /// The focal length's log-normal prior when it is estimated.
    pub(super) focal_prior: FocalPrior,
    /// Every segment, input pixels.
    pub(super) all: &'a [Segment],
    /// The principal point the search builds its hypotheses about (normalised): the known
    /// one or the image centre, or the first pass's in the second ([`super::estimate`]).
    pub(super) search_pp: [f64; 2],
    /// The sd of the refinement's principal point prior about the image centre, longer sides.
    pub(super) pp_sigma: f64,
}

impl Problem<'_> {
    /// The known principal point, else the image centre (normalised coordinates).
    pub(super) fn default_pp(&self) -> [f64; 2] {
        self.known_pp.unwrap_or([0.0, 0.0])
    }
}
