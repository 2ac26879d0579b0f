//! Map accuracy against ground truth: the thesis's error metrics (section 6.1) and the
//! experiment set-ups that `vpmap eval` runs.
//!
//! # Frame and scale
//! Everything is compared in the map frame (origin at the station point, `+x` right, `+y`
//! forward, as in [`crate::map`]). Two scale variants:
//!
//! * **`S_k`** (eq. 6.1, the thesis's): `S_k = (L2 / L1 + B2 / B1) / 2`, with `L1`, `B1` the
//!   *modelled* length and breadth of the reference object and `L2`, `B2` its *actual* ones.
//!   The reference object is the first box of the scene (the thesis's "first object"). The
//!   truth is brought to the model's scale, every actual coordinate and height divided by
//!   `S_k`, with the station point as the fixed origin. (Multiplying the model by `S_k`
//!   instead gives the same percentages and angles: every metric is scale-free.)
//! * **true scale**: the map in metres from the scene's known length (the camera height)
//!   against the truth in metres, no fitting. Named with the suffix `_true_scale`.
//!
//! # Metrics (section 6.1.1), per object
//! With `C_m`, `C_a` the centroids of the modelled and actual footprints, `A_m`, `A_a` their
//! areas and `A_cm` the area of their intersection (`geo` boolean operations):
//!
//! | name | formula | thesis |
//! |---|---|---|
//! | `centroid_shift_pct` | `d_cm / d_a * 100`, `d_cm = |C_m - C_a|`, `d_a = |C_a|` | metric 1, figs 6.8, 6.18 |
//! | `centroid_distance_pct` | `(d_m - d_a) / d_a * 100`, `d_m = |C_m|` | metric 2, figs 6.9, 6.19 |
//! | `area_overlap_pct` | `A_cm / A_a * 100` | metric 3, figs 6.10, 6.20 |
//! | `area_error_pct` | `(A_m - A_a) / A_a * 100` | metric 4, figs 6.11, 6.21 |
//! | `pose_error_deg` | `theta_m - theta_a`, `theta` the centroid's bearing `atan2(y, x)` from the station point against `+x` (the horizontal), wrapped to `(-180, 180]` | metric 5, figs 6.12, 6.22 |
//! | `skew_error_deg` | `beta_m - beta_a`, `beta` the direction of the object's first side (a box's near-to-right base edge, a footprint's vertex 0 to vertex 1) against `+x`, wrapped to `(-90, 90]` | metric 6, figs 6.13, 6.23 |
//! | `height_error_pct` | `(h_m - h_a) / h_a * 100` | (not in the thesis's plots) |
//!
//! The skew is wrapped to `(-90, 90]` because a side is an undirected line: its direction is
//! defined modulo 180 degrees. Modelled and actual sides correspond by their annotated
//! vertices (the same corners of the photo), so the object's own symmetry (a rectangle looks
//! the same turned by 90 degrees) plays no part; any error of 90 degrees or more would be a
//! reconstruction turned over, which the builder refuses.
//!
//! # Error-bar coverage
//! For an object the builder gives error bars (method `fit`,
//! [`crate::map::ObjectUncertainty`]), [`Coverage`] says where the truth lies in them, at the
//! true scale: the squared Mahalanobis distance of the true centroid from the map's with the
//! reported centroid covariance (inside the 95 % ellipse when at most [`CHI2_2DOF_95`]), and
//! the standardised errors `(m - a) / sd` of the box's length, breadth and height (within
//! `±2 sd` when at most 2 in magnitude). The length is the map's longer side, compared with the
//! true length of the same side (the sides correspond by their corners); so is the yaw (the
//! longer side's direction against the true direction of the same side, wrapped to
//! `[-90, 90)` degrees). [`CameraCoverage`] does the same for the camera's focal length,
//! pitch and roll, once per scene.
//!
//! Per scene: `pitch_error_deg`, `roll_error_deg` (estimate minus truth) and
//! `focal_error_pct` (`(f_m - f_a) / f_a * 100`; the focal length is estimated from the
//! vanishing points in both perspectives), and `camera_height_error_pct` of the `S_k`
//! variant (how far the reference object's scale is from the true one).
//!
//! # Experiments
//! [`SETUPS`] lists nine two-point (pitch 0) and eight three-point set-ups like the thesis's
//! (figures 6.8-6.13 and 6.18-6.23): room-sized and table-top, 0.2 to 2 m camera heights,
//! pitch up to 45 degrees, some with roll, 3 to 5 objects including a pentagonal footprint.
//! Each trial draws a scene from the synthetic pinhole camera ([`crate::synth`]) with a seed
//! derived from (seed, set-up name, trial) ([`scene_seed`]); each noise level adds Gaussian
//! noise of standard deviation `sigma` pixels to every annotated point (box corners, tops,
//! footprint vertices, floor corners) with a seed derived from the scene's and `sigma`
//! ([`noise_seed`]), then writes the vanishing points as the box edges through those noisy
//! corners ([`VanishingPointForm::Lines`](crate::synth::VanishingPointForm::Lines)), so the
//! builder re-estimates them by least squares. The same noisy scene goes to every method.
//!
//! [`VIEW_SETUPS`] adds six set-ups of the views real photos showed, apart from the thesis's
//! seventeen: boxes seen nearly face-on, hidden base corners (top corners given instead) and
//! boxes with their own yaw ([`crate::synth::Annotation`]).
//!
//! [`TrialOptions::vp_edges`] chooses the edges the vanishing points are fitted to:
//! [`VpEdges::Objects`] (the default above, and the published results) or
//! [`VpEdges::Long`]: per vanishing point a few long straight room lines (floor-wall
//! junctions, wall corners) of a given length in pixels, spread over the image, each the image
//! of a 3D line in the vanishing direction in front of the true camera
//! ([`crate::synth::long_edges`], placed once per scene with [`long_edge_seed`]), their end
//! points clicked with the same noise as every other point. The objects' points get exactly
//! the same noise in both modes. Under noise the vanishing points' error sets almost all of
//! the map's error, and it falls with the length of the edges they are fitted to: the objects'
//! own edges are short (2PP median 87 px), so `Long` measures what a user who clicks the
//! room's lines gets.
//!
//! # Example
//! ```
//! use vpmap_metrology::eval::object_errors;
//! // A unit square at (0, 10), modelled 0.1 to the right.
//! let actual = [[0.0, 10.0], [1.0, 10.0], [1.0, 11.0], [0.0, 11.0]];
//! let modelled = actual.map(|p| [p[0] + 0.1, p[1]]);
//! let e = object_errors(&modelled, None, &actual, None).unwrap();
//! assert!((e.area_overlap_pct - 90.0).abs() < 1e-6); // geo snaps to 2^-29 of the extent
//! assert!(e.area_error_pct.abs() < 1e-9);
//! ```
//!
//! # References
//! - The thesis, section 6.1 (eq. 6.1, the six metrics of 6.1.1) and figures 6.8-6.23.
//! - `../shared/thesis/errata.md`, "Under noise".
//!
//! # Rooms of several photos
//! [`run_room_trial`] measures a room's joint map against the map of its first photo alone
//! and each shared object against the maps of the photos that show it alone (its module's
//! documentation says how); `vpmap eval --photos N` runs it.
//!
//! The statistics of the results (quantiles, box-plot figures) are `vpmap_eval::stats`.

mod coverage;
mod evaluate;
mod metrics;
mod room;
mod room_visibility;
mod setups;
mod trial;

pub use coverage::{
    CAMERA_COVERAGE_METRICS, CHI2_2DOF_95, COVERAGE_METRICS, CameraCoverage, Coverage,
};
pub use evaluate::{CameraErrors, MapEvaluation, ObjectEvaluation, SCENE_METRICS, evaluate_map};
pub use metrics::{
    OBJECT_METRICS, ObjectErrors, TRUE_SCALE_SUFFIX, object_errors, percent_error, rectangle_size,
    scale_factor,
};
pub use room::{
    RoomEvaluation, RoomMapErrors, RoomObjectErrors, RoomOutcome, RoomTrial, RoomTrialOptions,
    SharedObject, floor_known_share, room_scene_seed, run_room_trial,
};
pub use room_visibility::{VISIBILITY_STEP_M, visible_floor_share};
pub use setups::{SETUPS, Setup, VIEW_SETUPS};
pub use trial::{
    Failure, Trial, TrialOptions, TrialOutcome, VpEdges, failure_category, long_edge_seed,
    noise_seed, noisy_scene, run_trial, run_trial_with, scene_seed, with_long_edges,
};
