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
//! | lens distortion | [`distortion`] | the division model's `k` minimising the segments' robust distance to their refitted vanishing points, its sd from the cost's curvature, with a prior of real lenses; the vanishing points and camera found again from the undistorted segments | Fitzgibbon, CVPR 2001 (division model); Antunes et al., CVPR 2017 |
//! | 2PP / 3PP | [`detect`] | tilt of the vertical direction against the image plane vs [`DetectOptions::two_point_tolerance_deg`] (default 0: three-point whenever the vertical point is finite) | |
//! | vanishing-point uncertainty | [`uncertainty`] | each point's covariance from its segments (robust noise estimate, 4-sigma re-selection, pieces of one edge counted once) plus a model-error floor measured on York Urban; the segments' own least-squares point, not held orthogonal (`own_point`) | Hartley and Zisserman, *Multiple View Geometry*, 2nd ed., 5.2 |
//! | scene file | [`scene`] | the detected directions made orthogonal (never levelled: the horizon written is the measured one), written as a `docs/scene-format.md` scene that calibrates | |
//! | test scenes | [`synthetic`] | ray-cast tiled floor and boxes, anti-aliased, from a known camera | |
//! | test photos | [`synthetic::photo`] | a `vpmap_metrology::synth` room ray-cast with shaded, textured faces, blur, noise and a JPEG round trip, with every click's true corner | |
//! | scene clicks | [`clicks`] | every clicked point of a scene by its field path | |
//! | snapping | [`snap`] | a click to the corner of edges along the vanishing directions: gradient votes per pencil, sub-pixel edge points (parabola across the edge), weighted line fits, their intersection and its first-order covariance | Canny, IEEE PAMI 1986; Förstner and Gülch, 1987; Hartley and Zisserman, *Multiple View Geometry*, 5.2 |
//! | box proposals | [`proposals`] | a vertical segment with base edges receding towards their vanishing points, corners snapped | |
//! | accuracy figures | [`metrics`] | direction matching, angular errors, area under the accuracy curve | Lu et al. 2017 (AUC) |
//!
//! # Modules
//! Bottom-up, each using only those before it: `error`, `detection` (the types:
//! [`Segment`], [`Detection`], [`DetectOptions`], ...), `prepare` (sizes, options, the working
//! image), [`photo`], [`segments`], [`manhattan`] (inside: `model`, `lm`, `problem`, `score`,
//! `search`, `refine`, then its `mod.rs`), [`distortion`], `detector` ([`detect`], [`detect_from_segments`]),
//! [`scene`], [`metrics`], [`clicks`], [`snap`] (inside: `patch`, `edges`, `corner`, its
//! `mod.rs`, then `scene`), [`proposals`], [`synthetic`] (then `synthetic::photo`). This file
//! only declares and re-exports them.
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

pub mod clicks;
mod detection;
mod detector;
pub mod distortion;
pub mod error;
pub mod manhattan;
pub mod metrics;
pub mod photo;
mod prepare;
pub mod proposals;
pub mod scene;
pub mod segments;
pub mod snap;
pub mod synthetic;
pub mod uncertainty;

pub use detection::{
    DetectOptions, Detection, Intrinsics, LensOption, OwnPoint, Segment, VanishingPoint,
};
pub use detector::{detect, detect_from_segments};
pub use error::{Result, VisionError};
pub use prepare::{MAX_SIDE_PX, MIN_SIDE_PX};
pub use segments::detect_segments;
/// Two-point (vertical lines parallel in the image) or three-point perspective; the one type
/// of the workspace, from `vpmap-metrology`.
pub use vpmap_metrology::calibration::Perspective;

/// The README's example, compiled and run as a doc test.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
