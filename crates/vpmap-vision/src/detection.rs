//! What detection takes and gives: [`Segment`], [`Intrinsics`], [`VanishingPoint`] (and its
//! [`OwnPoint`]), [`Detection`] and the options [`DetectOptions`].

use vpmap_metrology::calibration::Perspective;

use crate::distortion::LensEstimate;

/// A line segment in the image, pixels: origin at the top-left corner of the top-left pixel
/// (pixel centres at `i + 0.5`), `x` right, `y` down, as in `docs/scene-format.md`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// One end, pixels `[x, y]` (x right, y down).
    pub start_px: [f64; 2],
    /// The other end, pixels.
    pub end_px: [f64; 2],
    /// Detector-specific strength (higher is more certain), e.g. `-log10(NFA)` for LSD.
    pub strength: f64,
}

/// Camera intrinsics: square pixels, no skew.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intrinsics {
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Principal point, pixels `[x, y]`.
    pub principal_point_px: [f64; 2],
}

/// One detected vanishing point.
#[derive(Clone, Debug, PartialEq)]
pub struct VanishingPoint {
    /// The point in the image, pixels (may be far outside the image; `None` only when the
    /// direction is exactly parallel to the image plane, i.e. the point is at infinity). A
    /// photo judged two-point perspective still has its measured, far, vertical point here.
    pub point_px: Option<[f64; 2]>,
    /// The unit direction in the camera frame (x right, y down, z forward), sign chosen with
    /// z >= 0 (x >= 0 when z = 0). It vanishes at `K d`:
    /// `point_px = principal_point + focal * (d_x / d_z, d_y / d_z)`.
    pub direction_camera: [f64; 3],
    /// Indices into [`Detection::segments`] of the segments that support it.
    pub segments: Vec<usize>,
    /// Whether this is the vertical direction.
    pub vertical: bool,
    /// The direction's own vanishing point: the robust least-squares point of its
    /// [`segments`](Self::segments) alone, not held orthogonal to the other two
    /// ([`crate::uncertainty::own_point`]), in the pinhole image of
    /// [`Detection::intrinsics`] (the segments undistorted by [`Detection::lens`]). `None` when
    /// the segments do not fix a point. The frame's [`point_px`](Self::point_px) is what
    /// `vpmap detect` writes: the metric fit assumes a Manhattan room.
    pub own_point: Option<OwnPoint>,
}

/// A direction's own vanishing point, from its supporting segments alone
/// ([`VanishingPoint::own_point`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OwnPoint {
    /// The point in the pinhole image, pixels (`None` when it is at infinity).
    pub point_px: Option<[f64; 2]>,
    /// Its unit direction in the camera frame of [`Detection::intrinsics`], sign chosen as
    /// [`VanishingPoint::direction_camera`]'s.
    pub direction_camera: [f64; 3],
    /// Its angle from the frame's direction, degrees.
    pub from_frame_deg: f64,
    /// The independent edges that fix it (pieces of one edge counted once; outliers dropped).
    pub edges: usize,
}

/// What [`detect`](crate::detect) found.
// Four yes-or-no facts of one detection (the focal length estimated; the principal point
// estimated, given, or found off the centre), each read on its own by the callers.
#[allow(clippy::struct_excessive_bools)]
#[derive(Clone, Debug, PartialEq)]
pub struct Detection {
    /// Image size, pixels `[width, height]` (of the input, not of any internal downscale).
    pub image_size_px: [u32; 2],
    /// Every line segment found, in input-image pixels.
    pub segments: Vec<Segment>,
    /// The three Manhattan vanishing points: the two horizontal ones first, then the
    /// vertical one.
    pub vanishing_points: Vec<VanishingPoint>,
    /// The intrinsics used or estimated.
    pub intrinsics: Intrinsics,
    /// Whether the focal length was estimated (not given).
    pub focal_estimated: bool,
    /// Whether the principal point was estimated (not given).
    pub principal_point_estimated: bool,
    /// Whether the edges put the principal point off the image centre, as in a photo cropped
    /// off its centre: estimated (clear three-point perspective) farther from the centre than
    /// [`PRINCIPAL_POINT_PRIOR_SIGMA`](crate::manhattan::PRINCIPAL_POINT_PRIOR_SIGMA) of the
    /// longer side, the search's prior sd (calibrated cameras' principal points lie within
    /// about 1.4 % of the diagonal). On a crop the search finds it with a second pass about the
    /// principal point the first found ([`manhattan`](crate::manhattan), step 4). The scene file
    /// then carries a widened prior ([`scene`](crate::scene)).
    pub principal_point_off_centre: bool,
    /// Whether the principal point was given ([`DetectOptions::principal_point_px`]); when
    /// neither given nor estimated it is the image centre.
    pub principal_point_given: bool,
    /// The focal length's prior the detection used ([`DetectOptions::focal_prior`]), when the
    /// focal length was estimated.
    pub focal_prior: Option<(f64, f64)>,
    /// Two- or three-point perspective, from the vertical direction's tilt:
    /// [`Perspective::TwoPoint`] when it is tilted from the image plane by less than
    /// [`DetectOptions::two_point_tolerance_deg`] (its vanishing point far towards infinity, and
    /// left out of the scene file), [`Perspective::ThreePoint`] otherwise. A report, not a
    /// correction: the directions are the measured ones either way (see [`scene`](crate::scene), which also
    /// writes a two-point scene when the vertical point is out of reach).
    pub perspective: Perspective,
    /// Angle between the vertical direction and the image plane, degrees: the absolute
    /// camera pitch (whatever the roll).
    pub vertical_tilt_deg: f64,
    /// The lens distortion the vanishing points and the camera were found through
    /// ([`DetectOptions::lens`]): `None` for a photo taken as a pinhole camera's. The
    /// [`segments`](Self::segments) stay in the photo's pixels; the vanishing points and the
    /// intrinsics are the pinhole camera's (segments undistorted by the model).
    pub lens: Option<LensEstimate>,
}

/// How [`detect`](crate::detect) treats lens distortion.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum LensOption {
    /// Estimate the division model's `k` from the segments ([`crate::distortion`]), with its
    /// standard deviation.
    #[default]
    Estimate,
    /// Take the photo as a pinhole camera's (already undistorted, or a lens known to be
    /// straight).
    Pinhole,
    /// A known `k` (from a calibration), held.
    Known(f64),
}

/// Options of [`detect`](crate::detect).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DetectOptions {
    /// Known focal length, pixels (default: estimate it, between 0.3 and 3 times the
    /// image's longer side, i.e. horizontal fields of view of about 160 to 19 degrees).
    pub focal_px: Option<f64>,
    /// Known principal point, pixels (default: estimate it in clear three-point perspective,
    /// with a weak prior at the image centre; the image centre otherwise, since there the
    /// vanishing points do not fix it: see [`detect`](crate::detect)).
    pub principal_point_px: Option<[f64; 2]>,
    /// The image is downscaled internally (area average) so that its longer side is at most
    /// this (default 640, at least 64); results are in input pixels. Larger values keep
    /// finer edges of big photos at a cost linear in the pixel count.
    pub max_side_px: u32,
    /// A vertical direction tilted by less than this from the image plane makes the photo
    /// two-point perspective, degrees (default 0: never, the measured vertical vanishing point
    /// is kept however far it is). It decides only whether the vertical point is reported and
    /// written, never the directions: a two-point scene still carries the measured horizon.
    pub two_point_tolerance_deg: f64,
    /// Seed of the random sampling, for reproducible results (default 0).
    pub seed: u64,
    /// A prior on the focal length when it is estimated: `(focal_px, relative sd)`, e.g. from
    /// the photo's EXIF ([`crate::photo::Photo::exif_focal_prior`]). Default: the weak
    /// log-normal prior at the image's longer side. Ignored when [`Self::focal_px`] is given.
    pub focal_prior: Option<(f64, f64)>,
    /// Lens distortion: estimated (default), none, or known.
    pub lens: LensOption,
}

impl Default for DetectOptions {
    fn default() -> Self {
        Self {
            focal_px: None,
            principal_point_px: None,
            max_side_px: 640,
            two_point_tolerance_deg: 0.0,
            seed: 0,
            focal_prior: None,
            lens: LensOption::Estimate,
        }
    }
}

impl Detection {
    /// The segments the vanishing points were found from: [`Self::segments`] undistorted by
    /// [`Self::lens`] (the same, in order, without a lens).
    #[must_use]
    pub fn pinhole_segments(&self) -> Vec<Segment> {
        match &self.lens {
            Some(lens) => self.segments.iter().map(|s| lens.undistort(s)).collect(),
            None => self.segments.clone(),
        }
    }
}

impl Segment {
    /// Length, pixels.
    #[must_use]
    pub fn length_px(&self) -> f64 {
        (self.end_px[0] - self.start_px[0]).hypot(self.end_px[1] - self.start_px[1])
    }
}
