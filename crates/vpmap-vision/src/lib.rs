//! Line segments, Manhattan vanishing points and the camera from one photo.
//!
//! [`detect`] takes a photo (JPEG or PNG, grey or colour, any size) and finds its straight
//! edges, the three vanishing points of a *Manhattan* scene (three mutually orthogonal
//! families of parallel edges: two horizontal wall directions and the vertical), and the
//! camera: focal length and principal point when they are not given, and whether the photo is
//! in two- or three-point perspective. Everything is reported in input-image pixels, origin at
//! the top-left corner of the top-left pixel, `x` right, `y` down (as in
//! `docs/scene-format.md`); camera-frame directions have `x` right, `y` down, `z` forward.
//!
//! # Algorithms
//!
//! | step | module | what | reference |
//! |---|---|---|---|
//! | reading a photo | [`photo`] | JPEG or PNG only, size checked in the header, decoder memory limited, EXIF orientation applied | |
//! | working image | [`detect`] | grey, area-average downscale to [`DetectOptions::max_side_px`] | |
//! | line segments | [`segments`] | LSD: gradient-ordered region growing, rectangles, a-contrario validation (`NFA <= 1`), via the `lsdetect` crate | Grompone von Gioi, Jakubowicz, Morel, Randall, "LSD: a Line Segment Detector", IPOL 2012 |
//! | first vanishing point | [`manhattan`] | length-weighted random segment pairs, angular consistency score, algebraic least squares | Tardif, "Non-iterative approach for fast and accurate vanishing point detection", ICCV 2009 (consistency measure) |
//! | Manhattan triplet | [`manhattan`] | 2-line search: the other two directions on the great circle orthogonal to the first, by a histogram vote, over a focal-length grid when the camera is unknown | Lu, Yao, Li, Chen, Li, "2-Line Exhaustive Searching for Real-Time Vanishing Point Estimation in Manhattan World", WACV 2017 |
//! | refinement | [`manhattan`] | joint Levenberg-Marquardt of the rotation (orthogonality built in), focal length and principal point on the segment-to-vanishing-point distances, Cauchy-reweighted | Triggs et al., "Bundle adjustment — a modern synthesis", 2000 (robust LM); Hartley and Zisserman, *Multiple View Geometry*, 2nd ed., 8.8 (calibration from vanishing points) |
//! | 2PP / 3PP | [`detect`] | tilt of the vertical direction against the image plane vs [`DetectOptions::two_point_tolerance_deg`] (default 0: three-point whenever the vertical point is finite) | |
//! | scene file | [`scene`] | the detected directions made orthogonal (never levelled: the horizon written is the measured one), written as a `docs/scene-format.md` scene that calibrates | |
//! | test scenes | [`synthetic`] | ray-cast tiled floor and boxes, anti-aliased, from a known camera | |
//! | accuracy figures | [`metrics`] | direction matching, angular errors, area under the accuracy curve | Lu et al. 2017 (AUC) |
//!
//! # Example
//! ```
//! use vpmap_vision::synthetic::{render_manhattan_scene, SceneRenderOptions};
//! use vpmap_vision::{detect, DetectOptions, Perspective};
//!
//! let scene = render_manhattan_scene(&SceneRenderOptions {
//!     width_px: 320,
//!     height_px: 240,
//!     focal_px: 300.0,
//!     pitch_rad: 25f64.to_radians(),
//!     ..SceneRenderOptions::default()
//! });
//! let found = detect(&scene.image, &DetectOptions::default())?;
//! assert_eq!(found.perspective, Perspective::ThreePoint);
//! let focal_error = found.intrinsics.focal_px / scene.intrinsics.focal_px - 1.0;
//! assert!(focal_error.abs() < 0.05, "focal length off by {focal_error}");
//! # Ok::<(), vpmap_vision::VisionError>(())
//! ```
#![deny(missing_docs)]

pub mod error;
pub mod manhattan;
pub mod metrics;
pub mod photo;
mod prepare;
pub mod scene;
pub mod segments;
pub mod synthetic;

pub use error::{Result, VisionError};
pub use prepare::{MAX_SIDE_PX, MIN_SIDE_PX};
pub use segments::detect_segments;
/// Two-point (vertical lines parallel in the image) or three-point perspective; the one type
/// of the workspace, from `vpmap-metrology`.
pub use vpmap_metrology::calibration::Perspective;

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
}

/// What [`detect`] found.
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
    /// Two- or three-point perspective, from the vertical direction's tilt:
    /// [`Perspective::TwoPoint`] when it is tilted from the image plane by less than
    /// [`DetectOptions::two_point_tolerance_deg`] (its vanishing point far towards infinity, and
    /// left out of the scene file), [`Perspective::ThreePoint`] otherwise. A report, not a
    /// correction: the directions are the measured ones either way (see [`scene`], which also
    /// writes a two-point scene when the vertical point is out of reach).
    pub perspective: Perspective,
    /// Angle between the vertical direction and the image plane, degrees: the absolute
    /// camera pitch (whatever the roll).
    pub vertical_tilt_deg: f64,
}

/// Options of [`detect`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DetectOptions {
    /// Known focal length, pixels (default: estimate it, between 0.3 and 3 times the
    /// image's longer side, i.e. horizontal fields of view of about 160 to 19 degrees).
    pub focal_px: Option<f64>,
    /// Known principal point, pixels (default: estimate it in clear three-point perspective,
    /// with a weak prior at the image centre; the image centre otherwise, since there the
    /// vanishing points do not fix it: see [`detect`]).
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
}

impl Default for DetectOptions {
    fn default() -> Self {
        Self {
            focal_px: None,
            principal_point_px: None,
            max_side_px: 640,
            two_point_tolerance_deg: 0.0,
            seed: 0,
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

/// Find line segments, the three Manhattan vanishing points and the camera in `image`.
///
/// The image is converted to grey and, when its longer side exceeds
/// [`DetectOptions::max_side_px`], downscaled by area averaging; segments come from LSD
/// ([`segments`]), the vanishing points and the camera from [`manhattan`]. All results are in
/// input-image pixels.
///
/// Without [`DetectOptions::focal_px`] the focal length is estimated together with the
/// vanishing points. Without [`DetectOptions::principal_point_px`] the principal point is
/// estimated only in clear three-point perspective (the vertical direction tilted by at least
/// [`manhattan::PRINCIPAL_POINT_MIN_TILT_DEG`]); otherwise the vanishing points do not fix it
/// (in two-point perspective it may slide along the horizon, and near it its distance from the
/// horizon trades off against the pitch), and the image centre is used
/// ([`Detection::principal_point_estimated`] tells which).
///
/// # Errors
/// * [`VisionError::BadImageSize`] when a side is below [`MIN_SIDE_PX`] or above
///   [`MAX_SIDE_PX`];
/// * [`VisionError::InvalidParameter`] for an invalid option;
/// * [`VisionError::NotEnoughLines`] when the image has too few straight edges to fix the
///   vanishing points (blank, noise, blurred);
/// * [`VisionError::NoOrthogonalDirections`] when its edges do not point along two or more
///   orthogonal directions (all parallel, say).
///
/// # Complexity
/// Linear in the number of pixels of the working image (LSD), plus about
/// `6 x 40 x N` segment tests for `N <= 350` segments when the focal length is searched.
/// About 30 ms for a 640 x 480 photo on one core.
pub fn detect(image: &image::DynamicImage, opts: &DetectOptions) -> Result<Detection> {
    prepare::check_size(image.width(), image.height())?;
    prepare::check_options(opts)?;
    let work = prepare::working_image(image, opts.max_side_px);
    let segments = segments::segments_of(&work);
    detect_from_segments(segments, [image.width(), image.height()], opts)
}

/// The vanishing points and the camera from segments found elsewhere (another detector, or
/// hand-labelled ones), for an image of `image_size_px` = `[width, height]` pixels.
///
/// The segments are in input-image pixels; thresholds are applied at the scale
/// [`detect`] would analyse this image at (see [`DetectOptions::max_side_px`]).
///
/// # Errors
/// As [`detect`].
pub fn detect_from_segments(
    segments: Vec<Segment>,
    image_size_px: [u32; 2],
    opts: &DetectOptions,
) -> Result<Detection> {
    prepare::check_size(image_size_px[0], image_size_px[1])?;
    prepare::check_options(opts)?;
    let scale = prepare::working_scale(image_size_px[0].max(image_size_px[1]), opts.max_side_px);
    let estimate = manhattan::estimate(
        &segments,
        image_size_px,
        scale,
        opts.focal_px,
        opts.principal_point_px,
        opts.seed,
    )?;
    let k = estimate.intrinsics;
    let vanishing_points: Vec<VanishingPoint> = estimate
        .directions
        .iter()
        .zip(estimate.support)
        .enumerate()
        .map(|(i, (d, support))| VanishingPoint {
            point_px: (d[2].abs() > 1e-12).then(|| {
                [
                    k.focal_px * d[0] / d[2] + k.principal_point_px[0],
                    k.focal_px * d[1] / d[2] + k.principal_point_px[1],
                ]
            }),
            direction_camera: *d,
            segments: support,
            vertical: i == 2,
        })
        .collect();
    let tilt_deg = estimate.directions[2][2].abs().min(1.0).asin().to_degrees();
    Ok(Detection {
        image_size_px,
        segments,
        vanishing_points,
        intrinsics: k,
        focal_estimated: opts.focal_px.is_none(),
        principal_point_estimated: estimate.principal_point_estimated,
        perspective: if tilt_deg < opts.two_point_tolerance_deg {
            Perspective::TwoPoint
        } else {
            Perspective::ThreePoint
        },
        vertical_tilt_deg: tilt_deg,
    })
}
