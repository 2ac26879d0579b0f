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
//! true length of the same side (the sides correspond by their corners).
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
//! corners ([`VanishingPointForm::Lines`]), so the
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
//! The statistics of the results (quantiles, box-plot figures) are `vpmap_eval::stats`.

use geo::{Area, BooleanOps, Centroid, Coord, LineString, Polygon};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use crate::calibration::Perspective;
use crate::error::{MetrologyError, Result};
use crate::map::{BoxSize, BuildOptions, FloorMap, MapPoint, Units, build_map};
use crate::reconstruct::{Method, ObjectKind};
use crate::scene::{ImageSize, Scene};
use crate::synth::{
    Annotation, LongEdgeOptions, SynthOptions, Truth, TruthObject, VanishingPointForm, add_noise,
    long_edges, synthesize,
};

/// Names of the per-object metrics, in the order of [`ObjectErrors::values`]. The thesis's
/// six come first.
pub const OBJECT_METRICS: [&str; 7] = [
    "centroid_shift_pct",
    "centroid_distance_pct",
    "area_overlap_pct",
    "area_error_pct",
    "pose_error_deg",
    "skew_error_deg",
    "height_error_pct",
];

/// Suffix of the true-scale variant of a per-object metric (`centroid_shift_pct_true_scale`).
pub const TRUE_SCALE_SUFFIX: &str = "_true_scale";

/// Names of the per-scene metrics, in the order of [`MapEvaluation::scene_values`].
pub const SCENE_METRICS: [&str; 4] = [
    "pitch_error_deg",
    "roll_error_deg",
    "focal_error_pct",
    "camera_height_error_pct",
];

/// The errors of one modelled object against its actual counterpart (section 6.1.1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ObjectErrors {
    /// `d_cm / d_a * 100`: centroid shift relative to the actual centroid's distance.
    pub centroid_shift_pct: f64,
    /// `(d_m - d_a) / d_a * 100`: error of the centroid's distance from the station point.
    pub centroid_distance_pct: f64,
    /// `A_cm / A_a * 100`: the part of the actual footprint the model covers.
    pub area_overlap_pct: f64,
    /// `(A_m - A_a) / A_a * 100`: footprint area error.
    pub area_error_pct: f64,
    /// `theta_m - theta_a`, degrees in `(-180, 180]`: error of the centroid's bearing.
    pub pose_error_deg: f64,
    /// `beta_m - beta_a`, degrees in `(-90, 90]`: error of the first side's direction.
    pub skew_error_deg: f64,
    /// `(h_m - h_a) / h_a * 100`, when both heights are known.
    pub height_error_pct: Option<f64>,
}

impl ObjectErrors {
    /// The metrics in the order of [`OBJECT_METRICS`] (`NaN` for an unknown height).
    #[must_use]
    pub fn values(&self) -> [f64; 7] {
        [
            self.centroid_shift_pct,
            self.centroid_distance_pct,
            self.area_overlap_pct,
            self.area_error_pct,
            self.pose_error_deg,
            self.skew_error_deg,
            self.height_error_pct.unwrap_or(f64::NAN),
        ]
    }
}

fn polygon(points: &[MapPoint]) -> Polygon<f64> {
    Polygon::new(
        LineString::from(
            points
                .iter()
                .map(|p| Coord { x: p[0], y: p[1] })
                .collect::<Vec<_>>(),
        ),
        vec![],
    )
}

/// Wrap an angle difference in degrees into `(-half_turn, half_turn]`.
fn wrap_deg(delta: f64, half_turn: f64) -> f64 {
    half_turn - (half_turn - delta).rem_euclid(2.0 * half_turn)
}

/// `(m - a) / a * 100`.
#[must_use]
pub fn percent_error(modelled: f64, actual: f64) -> f64 {
    (modelled - actual) / actual * 100.0
}

/// The thesis's six metrics (section 6.1.1) and the height error of one object, from its
/// modelled and actual footprints (same frame, same scale, origin at the station point,
/// vertices in corresponding order) and heights.
///
/// # Errors
/// [`MetrologyError::Degenerate`] when a footprint has fewer than 3 vertices or a
/// non-finite coordinate, the actual footprint has zero area, or its centroid lies on the
/// station point (no distance to compare with).
///
/// # Example
/// ```
/// use vpmap_metrology::eval::object_errors;
/// let actual = [[-1.0, 4.0], [1.0, 4.0], [1.0, 6.0], [-1.0, 6.0]];
/// // The model 10 % too far out from the station point, all round.
/// let modelled = actual.map(|p| [p[0] * 1.1, p[1] * 1.1]);
/// let e = object_errors(&modelled, Some(1.1), &actual, Some(1.0)).unwrap();
/// assert!((e.centroid_distance_pct - 10.0).abs() < 1e-9);
/// assert!((e.area_error_pct - 21.0).abs() < 1e-9);
/// assert!(e.pose_error_deg.abs() < 1e-9 && e.skew_error_deg.abs() < 1e-9);
/// assert!((e.height_error_pct.unwrap() - 10.0).abs() < 1e-9);
/// ```
pub fn object_errors(
    modelled: &[MapPoint],
    modelled_height: Option<f64>,
    actual: &[MapPoint],
    actual_height: Option<f64>,
) -> Result<ObjectErrors> {
    let degenerate = |reason: String| MetrologyError::Degenerate {
        field: "eval.footprint".to_owned(),
        reason,
    };
    for (which, pts) in [("modelled", modelled), ("actual", actual)] {
        if pts.len() < 3 {
            return Err(degenerate(format!(
                "the {which} footprint has {} vertices; at least 3 are needed",
                pts.len()
            )));
        }
        if let Some([x, y]) = pts.iter().find(|[x, y]| !(x.is_finite() && y.is_finite())) {
            return Err(degenerate(format!(
                "the {which} footprint has a non-finite vertex ({x}, {y})"
            )));
        }
    }
    let (pm, pa) = (polygon(modelled), polygon(actual));
    let area_a = pa.unsigned_area();
    let area_m = pm.unsigned_area();
    let (Some(cm), Some(ca)) = (pm.centroid(), pa.centroid()) else {
        return Err(degenerate("a footprint has no centroid".to_owned()));
    };
    if area_a <= 0.0 {
        return Err(degenerate("the actual footprint has zero area".to_owned()));
    }
    let d_a = ca.x().hypot(ca.y());
    if d_a <= 0.0 {
        return Err(degenerate(
            "the actual centroid lies on the station point".to_owned(),
        ));
    }
    let d_m = cm.x().hypot(cm.y());
    let d_cm = (cm.x() - ca.x()).hypot(cm.y() - ca.y());
    let overlap = pm.intersection(&pa).unsigned_area();
    let bearing = |x: f64, y: f64| y.atan2(x).to_degrees();
    let side = |pts: &[MapPoint]| match pts {
        [a, b, ..] => bearing(b[0] - a[0], b[1] - a[1]),
        _ => f64::NAN,
    };
    Ok(ObjectErrors {
        centroid_shift_pct: d_cm / d_a * 100.0,
        centroid_distance_pct: percent_error(d_m, d_a),
        area_overlap_pct: overlap / area_a * 100.0,
        area_error_pct: percent_error(area_m, area_a),
        pose_error_deg: wrap_deg(bearing(cm.x(), cm.y()) - bearing(ca.x(), ca.y()), 180.0),
        skew_error_deg: wrap_deg(side(modelled) - side(actual), 90.0),
        height_error_pct: match (modelled_height, actual_height) {
            (Some(m), Some(a)) => Some(percent_error(m, a)),
            _ => None,
        },
    })
}

/// Length (longer side) and breadth of a rectangle given by its four corners in order.
#[must_use]
pub fn rectangle_size(corners: &[MapPoint]) -> Option<BoxSize> {
    let [p0, p1, _, p3] = corners else {
        return None;
    };
    let a = (p1[0] - p0[0]).hypot(p1[1] - p0[1]);
    let b = (p3[0] - p0[0]).hypot(p3[1] - p0[1]);
    Some(BoxSize {
        length: a.max(b),
        breadth: a.min(b),
    })
}

/// The scale factor of eq. 6.1, `S_k = (L2 / L1 + B2 / B1) / 2`: `actual` (`L2`, `B2`) over
/// `modelled` (`L1`, `B1`) dimensions of the reference object, averaged over length and
/// breadth. Dividing actual lengths by it brings them to the model's scale.
///
/// # Errors
/// [`MetrologyError::Degenerate`] when a dimension is not a positive finite number.
///
/// # Example
/// ```
/// use vpmap_metrology::{eval::scale_factor, map::BoxSize};
/// let actual = BoxSize { length: 1.2, breadth: 0.6 };
/// let modelled = BoxSize { length: 0.6, breadth: 0.4 };
/// assert!((scale_factor(actual, modelled).unwrap() - 1.75).abs() < 1e-12);
/// ```
pub fn scale_factor(actual: BoxSize, modelled: BoxSize) -> Result<f64> {
    for (which, v) in [
        ("actual length", actual.length),
        ("actual breadth", actual.breadth),
        ("modelled length", modelled.length),
        ("modelled breadth", modelled.breadth),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(MetrologyError::Degenerate {
                field: "eval.scale_factor".to_owned(),
                reason: format!(
                    "the reference object's {which} is {v}; it must be a positive number"
                ),
            });
        }
    }
    Ok(f64::midpoint(
        actual.length / modelled.length,
        actual.breadth / modelled.breadth,
    ))
}

/// Errors of the estimated camera.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CameraErrors {
    /// Estimated minus true pitch, degrees.
    pub pitch_error_deg: f64,
    /// Estimated minus true roll, degrees.
    pub roll_error_deg: f64,
    /// `(f_m - f_a) / f_a * 100`.
    pub focal_error_pct: f64,
}

/// One object's errors in both scale variants.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ObjectEvaluation {
    /// The object's name.
    pub name: String,
    /// Box or footprint.
    pub kind: ObjectKind,
    /// Whether it is the reference object of `S_k`.
    pub reference: bool,
    /// Against the truth scaled by `S_k` (eq. 6.1).
    pub sk: ObjectErrors,
    /// Against the truth at the true scale (the map in metres).
    pub true_scale: ObjectErrors,
    /// Whether the truth lies within the object's error bars (method `fit`: objects with
    /// [`crate::map::ObjectUncertainty`]; `None` otherwise).
    pub coverage: Option<Coverage>,
}

/// The largest squared Mahalanobis distance inside a 2-D 95 % confidence ellipse: the 0.95
/// quantile of the chi-squared distribution with 2 degrees of freedom, `-2 ln 0.05`.
pub const CHI2_2DOF_95: f64 = 5.991_464_547_107_979;

/// How far the truth lies from a fitted object, in the object's own error bars (at the true
/// scale: the map in metres against the truth in metres).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Coverage {
    /// `d^T C^-1 d` with `d` the map's centroid minus the true centroid and `C` the reported
    /// centroid covariance (infinite for a singular `C` and `d != 0`).
    pub centroid_mahalanobis_sq: f64,
    /// `(L_m - L_a) / sd(L)` for a box's longer side `L_m` and the true length of the same
    /// side (sides correspond by their corners, not by which is longer).
    pub length_z: Option<f64>,
    /// The same for the shorter side.
    pub breadth_z: Option<f64>,
    /// `(h_m - h_a) / sd(h)`.
    pub height_z: Option<f64>,
}

impl Coverage {
    /// Whether the true centroid lies inside the reported 95 % ellipse
    /// (`centroid_mahalanobis_sq <= CHI2_2DOF_95`).
    #[must_use]
    pub fn centroid_in_ellipse_95(&self) -> bool {
        self.centroid_mahalanobis_sq <= CHI2_2DOF_95
    }

    /// Per quantity (centroid, length, breadth, height; the order of [`COVERAGE_METRICS`]),
    /// whether the truth lies within the error bars: inside the 95 % ellipse, within
    /// `±2 sd`. `None` where the quantity has no error bar.
    #[must_use]
    pub fn within(&self) -> [Option<bool>; 4] {
        let two_sd = |z: Option<f64>| z.map(|z| z.abs() <= 2.0);
        [
            Some(self.centroid_in_ellipse_95()),
            two_sd(self.length_z),
            two_sd(self.breadth_z),
            two_sd(self.height_z),
        ]
    }
}

/// Names of the coverage checks, in the order of [`Coverage::within`].
pub const COVERAGE_METRICS: [&str; 4] = [
    "centroid_in_ellipse_95",
    "length_within_2sd",
    "breadth_within_2sd",
    "height_within_2sd",
];

/// `d^T C^-1 d` for a 2x2 covariance (infinite when `C` is not positive definite and
/// `d != 0`, 0 when `d = 0`).
fn mahalanobis_sq(d: [f64; 2], c: [[f64; 2]; 2]) -> f64 {
    let det = c[0][0] * c[1][1] - c[0][1] * c[1][0];
    if d == [0.0, 0.0] {
        return 0.0;
    }
    if !(det.is_finite() && det > 0.0 && c[0][0] > 0.0) {
        return f64::INFINITY;
    }
    (d[0] * d[0] * c[1][1] - d[0] * d[1] * (c[0][1] + c[1][0]) + d[1] * d[1] * c[0][0]) / det
}

/// A standardised error `(m - a) / sd` (`None` without a positive standard deviation, when
/// the error is not 0; a zero error with a zero sd is 0).
fn z_score(modelled: f64, actual: f64, sd: Option<f64>) -> Option<f64> {
    let sd = sd?;
    let e = modelled - actual;
    if e == 0.0 {
        Some(0.0)
    } else if sd > 0.0 {
        Some(e / sd)
    } else {
        Some(e.signum() * f64::INFINITY)
    }
}

/// The coverage of one fitted object against its truth (same frame, metres).
fn coverage(m: &crate::map::MapObject, t: &TruthObject) -> Option<Coverage> {
    let u = m.uncertainty.as_ref()?;
    let actual = polygon(&t.footprint).centroid()?;
    let d = [m.centroid[0] - actual.x(), m.centroid[1] - actual.y()];
    let side = |p: &[MapPoint], k: usize| -> Option<f64> {
        let (a, b) = (p.first()?, p.get(k)?);
        Some((b[0] - a[0]).hypot(b[1] - a[1]))
    };
    let (mut length_z, mut breadth_z) = (None, None);
    if m.kind == ObjectKind::Box {
        // Sides (0,0)-(1,0) and (0,0)-(0,1), in the map and in the truth.
        let (ma, mb) = (side(&m.footprint, 1)?, side(&m.footprint, 3)?);
        let (ta, tb) = (side(&t.footprint, 1)?, side(&t.footprint, 3)?);
        let ((ml, tl), (mbr, tbr)) = if ma >= mb {
            ((ma, ta), (mb, tb))
        } else {
            ((mb, tb), (ma, ta))
        };
        length_z = z_score(ml, tl, u.length_sd);
        breadth_z = z_score(mbr, tbr, u.breadth_sd);
    }
    let height_z = m.height.and_then(|h| z_score(h, t.height, u.height_sd));
    Some(Coverage {
        centroid_mahalanobis_sq: mahalanobis_sq(d, u.centroid_covariance),
        length_z,
        breadth_z,
        height_z,
    })
}

/// A map compared with its truth.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MapEvaluation {
    /// `S_k` of eq. 6.1 (1 for a perfect reconstruction).
    pub scale_factor: f64,
    /// The camera's errors.
    pub camera: CameraErrors,
    /// `(H_m - H_a / S_k) / (H_a / S_k) * 100`: the camera height in the `S_k` variant (the
    /// true-scale variant's is 0 by construction).
    pub camera_height_error_pct: f64,
    /// Per object, in scene order.
    pub objects: Vec<ObjectEvaluation>,
}

impl MapEvaluation {
    /// The per-scene metrics in the order of [`SCENE_METRICS`].
    #[must_use]
    pub fn scene_values(&self) -> [f64; 4] {
        [
            self.camera.pitch_error_deg,
            self.camera.roll_error_deg,
            self.camera.focal_error_pct,
            self.camera_height_error_pct,
        ]
    }
}

/// Compare a map built at the true scale (in metres) with its truth: every object in both
/// scale variants, and the camera.
///
/// Objects are matched by position in scene order (their names must agree); the reference
/// object of `S_k` is the first box.
///
/// # Errors
/// [`MetrologyError::InvalidField`] when the map is not in metres, its objects do not match
/// the truth's or it has no box; [`MetrologyError::Degenerate`] from [`scale_factor`] and
/// [`object_errors`].
pub fn evaluate_map(map: &FloorMap, truth: &Truth) -> Result<MapEvaluation> {
    let invalid = |reason: String| MetrologyError::InvalidField {
        field: "eval".to_owned(),
        reason,
    };
    if map.units != Units::Meters {
        return Err(invalid(
            "the map must be in metres (a scene with its true scale) to compare with the truth"
                .to_owned(),
        ));
    }
    if map.objects.len() != truth.objects.len() {
        return Err(invalid(format!(
            "the map has {} objects, the truth {}",
            map.objects.len(),
            truth.objects.len()
        )));
    }
    if let Some((m, t)) = map
        .objects
        .iter()
        .zip(&truth.objects)
        .find(|(m, t)| m.name != t.name)
    {
        return Err(invalid(format!(
            "map object {:?} faces truth object {:?}",
            m.name, t.name
        )));
    }
    let reference = map
        .objects
        .iter()
        .position(|o| o.kind == ObjectKind::Box)
        .ok_or_else(|| {
            invalid("the scene has no box to serve as the reference object".to_owned())
        })?;
    let modelled_size = map
        .objects
        .get(reference)
        .and_then(|o| o.size.or_else(|| rectangle_size(&o.footprint)));
    let actual_size = truth
        .objects
        .get(reference)
        .and_then(|o| rectangle_size(&o.footprint));
    let (Some(modelled_size), Some(actual_size)) = (modelled_size, actual_size) else {
        return Err(invalid(
            "the reference box has no length and breadth".to_owned(),
        ));
    };
    let s_k = scale_factor(actual_size, modelled_size)?;
    let mut objects = Vec::with_capacity(map.objects.len());
    for (i, (m, t)) in map.objects.iter().zip(&truth.objects).enumerate() {
        let scaled: Vec<MapPoint> = t
            .footprint
            .iter()
            .map(|p| [p[0] / s_k, p[1] / s_k])
            .collect();
        objects.push(ObjectEvaluation {
            name: m.name.clone(),
            kind: m.kind,
            reference: i == reference,
            sk: object_errors(&m.footprint, m.height, &scaled, Some(t.height / s_k))?,
            true_scale: object_errors(&m.footprint, m.height, &t.footprint, Some(t.height))?,
            coverage: coverage(m, t),
        });
    }
    Ok(MapEvaluation {
        scale_factor: s_k,
        camera: CameraErrors {
            pitch_error_deg: map.camera.pitch_deg - truth.camera.pitch_deg,
            roll_error_deg: map.camera.roll_deg - truth.camera.roll_deg,
            focal_error_pct: percent_error(map.camera.focal_px, truth.camera.focal_px),
        },
        camera_height_error_pct: percent_error(map.camera.height, truth.camera.height / s_k),
        objects,
    })
}

/// One experiment set-up: a camera and the objects it sees (a row of the thesis's box plots).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Setup {
    /// Name, e.g. `2pp-3`: perspective and number in its group.
    pub name: &'static str,
    /// Two-point (pitch 0) or three-point perspective.
    pub perspective: Perspective,
    /// What the set-up stands for.
    pub description: &'static str,
    /// Camera height, metres.
    pub height_m: f64,
    /// Pitch, degrees, positive looking down (0 in 2PP).
    pub pitch_deg: f64,
    /// Roll, degrees.
    pub roll_deg: f64,
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Image size, pixels.
    pub image: ImageSize,
    /// Number of boxes (the first is the reference object of `S_k`).
    pub boxes: usize,
    /// Number of pentagonal footprint objects (the thesis's chair).
    pub prisms: usize,
    /// What is clicked on each box and how boxes are turned ([`Annotation::Thesis`] in
    /// [`SETUPS`], the other views in [`VIEW_SETUPS`]).
    pub annotation: Annotation,
}

impl Setup {
    /// Number of objects in each scene.
    #[must_use]
    pub fn objects(&self) -> usize {
        self.boxes + self.prisms
    }

    /// The synthetic camera's options for one scene of this set-up: exact, true scale
    /// (`camera_height_m`), vanishing points as points, principal point left to the reader
    /// (image centre in 2PP, orthocentre in 3PP, as in the thesis).
    #[must_use]
    pub fn synth_options(&self, seed: u64) -> SynthOptions {
        SynthOptions {
            seed,
            image: self.image,
            focal_px: self.focal_px,
            height_m: self.height_m,
            pitch_deg: self.pitch_deg,
            roll_deg: self.roll_deg,
            boxes: self.boxes,
            prisms: self.prisms,
            noise_px: 0.0,
            vanishing_points: VanishingPointForm::Points,
            with_scale: true,
            with_principal_point: false,
            annotation: self.annotation,
        }
    }
}

const IMAGE_4_3: ImageSize = ImageSize {
    width: 1600,
    height: 1200,
};
const IMAGE_SMALL: ImageSize = ImageSize {
    width: 1280,
    height: 960,
};

/// One row of [`SETUPS`] (positional, to keep the table one line per set-up).
#[allow(clippy::too_many_arguments)]
const fn setup(
    name: &'static str,
    description: &'static str,
    height_m: f64,
    pitch_deg: f64,
    roll_deg: f64,
    focal_px: f64,
    image: ImageSize,
    boxes: usize,
) -> Setup {
    Setup {
        name,
        perspective: if pitch_deg == 0.0 {
            Perspective::TwoPoint
        } else {
            Perspective::ThreePoint
        },
        description,
        height_m,
        pitch_deg,
        roll_deg,
        focal_px,
        image,
        boxes,
        prisms: 1,
        annotation: Annotation::Thesis,
    }
}

/// A set-up of [`VIEW_SETUPS`]: a room-sized set-up of [`SETUPS`] seen another way.
const fn view_setup(
    name: &'static str,
    description: &'static str,
    like: &Setup,
    annotation: Annotation,
) -> Setup {
    Setup {
        name,
        description,
        annotation,
        ..*like
    }
}

/// The experiment set-ups: nine in two-point perspective (pitch 0, as in figures 6.8-6.13)
/// and eight in three-point perspective (pitch 10-45 degrees, figures 6.18-6.23), room-sized
/// (camera 0.8-2 m high) and table-top (0.2-0.5 m), eight with roll (2-5 degrees), each with
/// 2-4 boxes and one pentagonal footprint object (3-5 objects). Object sizes scale with the
/// camera height (sides 0.15-0.8, heights 0.1-1.4 camera heights), and objects stand anywhere
/// on the floor seen in the lower three quarters of the image below the horizon (see
/// [`crate::synth::synthesize`]).
#[rustfmt::skip]
pub const SETUPS: [Setup; 17] = [
    setup("2pp-1", "room, 3 objects (like fig. 6.3: robot, chair, table)", 1.2, 0.0, 0.0, 1100.0, IMAGE_4_3, 2),
    setup("2pp-2", "room, 4 objects", 1.5, 0.0, 0.0, 1000.0, IMAGE_4_3, 3),
    setup("2pp-3", "room, 4 objects, roll 2 deg", 0.8, 0.0, 2.0, 1200.0, IMAGE_4_3, 3),
    setup("2pp-4", "room, 5 objects, roll -3 deg", 1.6, 0.0, -3.0, 900.0, IMAGE_4_3, 4),
    setup("2pp-5", "room, 4 objects, long lens", 1.0, 0.0, 0.0, 1400.0, IMAGE_4_3, 3),
    setup("2pp-6", "table-top, 4 objects", 0.3, 0.0, 0.0, 1100.0, IMAGE_4_3, 3),
    setup("2pp-7", "table-top, 3 objects, roll 4 deg", 0.2, 0.0, 4.0, 1000.0, IMAGE_SMALL, 2),
    setup("2pp-8", "room, 5 objects, high camera, wide lens", 2.0, 0.0, 0.0, 800.0, IMAGE_4_3, 4),
    setup("2pp-9", "table-top, 4 objects, roll -2 deg", 0.5, 0.0, -2.0, 1300.0, IMAGE_SMALL, 3),
    setup("3pp-1", "room, 5 objects (like fig. 6.14)", 1.5, 25.0, 0.0, 1100.0, IMAGE_4_3, 4),
    setup("3pp-2", "room, 5 objects, roll 3 deg", 1.6, 30.0, 3.0, 1000.0, IMAGE_4_3, 4),
    setup("3pp-3", "room, 4 objects, slight pitch", 1.2, 15.0, 0.0, 1200.0, IMAGE_4_3, 3),
    setup("3pp-4", "room, 4 objects, high camera, steep, roll -2 deg", 2.0, 45.0, -2.0, 900.0, IMAGE_4_3, 3),
    setup("3pp-5", "table-top, 4 objects", 0.4, 35.0, 0.0, 1100.0, IMAGE_4_3, 3),
    setup("3pp-6", "table-top, 3 objects, steep, roll 5 deg", 0.2, 45.0, 5.0, 1000.0, IMAGE_SMALL, 2),
    setup("3pp-7", "room, 5 objects, pitch 10 deg, roll -4 deg", 1.0, 10.0, -4.0, 1300.0, IMAGE_4_3, 4),
    setup("3pp-8", "table-top, 4 objects", 0.5, 20.0, 0.0, 1100.0, IMAGE_SMALL, 3),
];

/// The views real photos showed (issue 12), each in both perspectives, apart from [`SETUPS`]
/// (whose per-perspective results are the thesis comparison): boxes seen nearly face-on
/// ([`Annotation::FaceOn`]), hidden base corners ([`Annotation::HiddenBase`]) and boxes with
/// their own yaw ([`Annotation::OwnYaw`]). Cameras, lenses and object counts are those of
/// `2pp-2` (room, 1.5 m, 1000 px, 3 boxes and a footprint object) and `3pp-1` (room, 1.5 m,
/// pitch 25 degrees, 1100 px, 4 boxes and a footprint object). The side-view method and the
/// projective form cannot read face-view or hidden-base annotations and refuse those scenes.
#[rustfmt::skip]
pub const VIEW_SETUPS: [Setup; 6] = [
    view_setup("2pp-face", "boxes seen nearly face-on: base front corners, four top corners", &SETUPS[1], Annotation::FaceOn),
    view_setup("3pp-face", "boxes seen nearly face-on: base front corners, four top corners", &SETUPS[9], Annotation::FaceOn),
    view_setup("2pp-hidden", "hidden base: base near corner, four top corners", &SETUPS[1], Annotation::HiddenBase),
    view_setup("3pp-hidden", "hidden base: base near corner, four top corners", &SETUPS[9], Annotation::HiddenBase),
    view_setup("2pp-yaw", "every second box turned by its own yaw (15-40°)", &SETUPS[1], Annotation::OwnYaw),
    view_setup("3pp-yaw", "every second box turned by its own yaw (15-40°)", &SETUPS[9], Annotation::OwnYaw),
];

/// SplitMix64's finaliser: a bijective mix of 64 bits.
fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn combine(a: u64, b: u64) -> u64 {
    splitmix(a ^ splitmix(b))
}

/// 64-bit FNV-1a of a name (stable across runs and platforms).
fn name_hash(name: &str) -> u64 {
    name.bytes().fold(0xCBF2_9CE4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01B3)
    })
}

/// The seed of one trial's scene: a function of the run's seed, the set-up's name and the
/// trial number only, so a trial draws the same scene whatever else runs (other set-ups,
/// other noise levels, thread scheduling).
#[must_use]
pub fn scene_seed(seed: u64, setup: &Setup, trial: u64) -> u64 {
    combine(combine(seed, name_hash(setup.name)), trial)
}

/// The seed of the noise added to a scene at one noise level.
#[must_use]
pub fn noise_seed(scene_seed: u64, sigma_px: f64) -> u64 {
    combine(scene_seed, sigma_px.to_bits())
}

/// The scene as a user would annotate it with `sigma_px` pixels of Gaussian noise on every
/// clicked point: [`add_noise`] on every corner, top, footprint vertex and floor corner, then
/// the vanishing points replaced by the box edges through the noisy corners (two or more per
/// vanishing point), to be re-estimated by least squares. With `sigma_px = 0` only the second
/// step applies.
#[must_use]
pub fn noisy_scene(scene: &Scene, sigma_px: f64, seed: u64) -> Scene {
    let mut noisy = scene.clone();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    add_noise(&mut noisy, sigma_px, &mut rng);
    crate::synth::vanishing_points_as_lines(&mut noisy);
    noisy
}

/// The seed of the long vanishing-point edges placed in one trial's scene
/// ([`VpEdges::Long`]): a function of the scene's seed only, so every noise level and method
/// sees the same edges.
#[must_use]
pub fn long_edge_seed(scene_seed: u64) -> u64 {
    combine(scene_seed, name_hash("long vanishing-point edges"))
}

/// Which edges the vanishing points are fitted to in an experiment.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum VpEdges {
    /// The objects' own box edges through their noisy corners ([`noisy_scene`]): short
    /// edges, the default and the published results.
    #[default]
    Objects,
    /// Long straight room lines drawn through the true camera ([`with_long_edges`]), their
    /// end points clicked with the same noise as the objects' points.
    Long(LongEdgeOptions),
}

/// Options of [`run_trial_with`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrialOptions {
    /// The edges the vanishing points are fitted to.
    pub vp_edges: VpEdges,
}

/// The scene with its vanishing points replaced by long straight edges that run to them
/// ([`crate::synth::long_edges`] through the truth's camera, seeded by `seed`), exact: the
/// noise comes later ([`add_noise`] jitters their end points after the objects' points, so
/// the objects get the same noise as with [`noisy_scene`]).
///
/// The vanishing directions are the scene's vanishing points pulled back through the true
/// camera, so the edges' lines pass through those points to rounding.
///
/// # Errors
/// [`MetrologyError::InvalidField`] when a vanishing point is not given as a point or the
/// options are out of range; [`MetrologyError::Degenerate`] when edges of that length do not
/// fit in the image.
pub fn with_long_edges(
    scene: &Scene,
    truth: &Truth,
    options: &LongEdgeOptions,
    seed: u64,
) -> Result<Scene> {
    let camera = truth.camera.pinhole(scene.image);
    let (right, down, forward) = camera.axes();
    let mut directions = Vec::with_capacity(scene.vanishing_points.len());
    for (i, vp) in scene.vanishing_points.iter().enumerate() {
        let Some(p) = vp.point else {
            return Err(MetrologyError::InvalidField {
                field: format!("vanishing_points[{i}].point"),
                reason:
                    "long edges are drawn towards the exact vanishing point; give it as a point"
                        .to_owned(),
            });
        };
        let q = (nalgebra::Vector2::new(p[0], p[1]) - camera.principal_point_px) / camera.focal_px;
        directions.push(right * q.x + down * q.y + forward);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let edges = long_edges(&camera, &directions, options, &mut rng)?;
    let mut out = scene.clone();
    for (vp, lines) in out.vanishing_points.iter_mut().zip(edges) {
        vp.point = None;
        vp.lines = lines;
    }
    Ok(out)
}

/// A short, stable name for why a builder refused a scene (`failures.csv`, the summaries).
#[must_use]
pub fn failure_category(error: &MetrologyError) -> &'static str {
    match error {
        MetrologyError::NotBelowHorizon { .. } => "point_not_below_horizon",
        MetrologyError::NoRealFocalLength(_) => "no_real_focal_length",
        MetrologyError::ParallelLines { .. } => "parallel_edges",
        MetrologyError::CoincidentVanishingPoints { .. } => "coincident_vanishing_points",
        MetrologyError::Degenerate { reason, .. } => {
            if reason.contains("negative height") {
                "negative_height"
            } else if reason.contains("behind the camera") {
                "behind_camera"
            } else if reason.contains("too close to the horizon") {
                "near_horizon"
            } else if reason.contains("zero area") || reason.contains("no length") {
                "zero_area"
            } else {
                "degenerate"
            }
        }
        MetrologyError::InvalidField { .. } => "invalid_field",
        MetrologyError::Json(_)
        | MetrologyError::UnsupportedVersion { .. }
        | MetrologyError::NonFinite { .. }
        | MetrologyError::VanishingPointCount(_)
        | MetrologyError::UnknownScaleObject { .. } => "invalid_scene",
    }
}

/// Why a trial produced no evaluation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Failure {
    /// [`failure_category`], `scene_draw` when the set-up could not place its objects, or
    /// `vp_edges` when long vanishing-point edges did not fit in the image ([`VpEdges::Long`]).
    pub category: &'static str,
    /// The error message.
    pub message: String,
}

/// One method at one noise level on one trial's scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrialOutcome {
    /// Noise, pixels.
    pub sigma_px: f64,
    /// The reconstruction method.
    pub method: Method,
    /// The evaluation, or why the builder refused the scene.
    pub result: std::result::Result<MapEvaluation, Failure>,
}

/// Every outcome of one trial of one set-up.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Trial {
    /// Trial number.
    pub trial: u64,
    /// The seed its scene was drawn with ([`scene_seed`]).
    pub scene_seed: u64,
    /// Per noise level (outer) and method (inner), in the order given.
    pub outcomes: Vec<TrialOutcome>,
}

/// Run one trial: draw the set-up's scene for `(seed, trial)`, then for every noise level
/// add noise ([`noisy_scene`]), build the map with every method ([`build_map`]) and compare it
/// with the truth ([`evaluate_map`]). A scene a builder refuses is an outcome with a
/// [`Failure`], not an error. [`run_trial_with`] with the default [`TrialOptions`].
#[must_use]
pub fn run_trial(
    setup: &Setup,
    seed: u64,
    trial: u64,
    sigmas_px: &[f64],
    methods: &[Method],
) -> Trial {
    run_trial_with(
        setup,
        seed,
        trial,
        sigmas_px,
        methods,
        &TrialOptions::default(),
    )
}

/// [`run_trial`] with a choice of the edges the vanishing points are fitted to
/// ([`TrialOptions::vp_edges`]). With [`VpEdges::Long`] the edges are placed once per scene
/// ([`with_long_edges`], [`long_edge_seed`]); a scene they do not fit in is a [`Failure`] of
/// category `vp_edges` at every noise level. At zero noise the objects carry no
/// [`Coverage`] (their error bars are zero).
#[must_use]
pub fn run_trial_with(
    setup: &Setup,
    seed: u64,
    trial: u64,
    sigmas_px: &[f64],
    methods: &[Method],
    options: &TrialOptions,
) -> Trial {
    let scene_seed = scene_seed(seed, setup, trial);
    let drawn = synthesize(&setup.synth_options(scene_seed)).map_err(|e| Failure {
        category: "scene_draw",
        message: e.to_string(),
    });
    let drawn = match (drawn, options.vp_edges) {
        (Ok((scene, truth)), VpEdges::Long(long)) => {
            with_long_edges(&scene, &truth, &long, long_edge_seed(scene_seed))
                .map(|scene| (scene, truth))
                .map_err(|e| Failure {
                    category: "vp_edges",
                    message: e.to_string(),
                })
        }
        (drawn, _) => drawn,
    };
    let mut outcomes = Vec::with_capacity(sigmas_px.len() * methods.len());
    for &sigma_px in sigmas_px {
        for &method in methods {
            let result = match &drawn {
                Ok((scene, truth)) => {
                    let noise = noise_seed(scene_seed, sigma_px);
                    let noisy = match options.vp_edges {
                        VpEdges::Objects => noisy_scene(scene, sigma_px, noise),
                        VpEdges::Long(_) => {
                            let mut noisy = scene.clone();
                            add_noise(&mut noisy, sigma_px, &mut ChaCha8Rng::seed_from_u64(noise));
                            noisy
                        }
                    };
                    build_map(
                        &noisy,
                        &BuildOptions {
                            method,
                            click_sigma_px: Some(sigma_px),
                        },
                    )
                    .and_then(|map| evaluate_map(&map, truth))
                    .map(|mut ev| {
                        // Error bars for exact clicks are zero: nothing to cover.
                        if sigma_px <= 0.0 {
                            for o in &mut ev.objects {
                                o.coverage = None;
                            }
                        }
                        ev
                    })
                    .map_err(|e| Failure {
                        category: failure_category(&e),
                        message: e.to_string(),
                    })
                }
                Err(failure) => Err(failure.clone()),
            };
            outcomes.push(TrialOutcome {
                sigma_px,
                method,
                result,
            });
        }
    }
    Trial {
        trial,
        scene_seed,
        outcomes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn setups_are_two_and_three_point_as_named() {
        assert_eq!(
            SETUPS
                .iter()
                .filter(|s| s.perspective == Perspective::TwoPoint)
                .count(),
            9
        );
        for s in &SETUPS {
            assert_eq!(s.pitch_deg == 0.0, s.name.starts_with("2pp"), "{}", s.name);
            assert!(
                (3..=5).contains(&s.objects()) && s.prisms >= 1,
                "{}",
                s.name
            );
            assert!((0.2..=2.0).contains(&s.height_m) && s.pitch_deg <= 45.0);
        }
        let mut names: Vec<_> = SETUPS.iter().map(|s| s.name).collect();
        names.dedup();
        assert_eq!(names.len(), SETUPS.len());
    }

    #[test]
    fn mahalanobis_distance_of_known_covariances() {
        // Axis-aligned: (2 / 1)^2 + (3 / 3)^2 = 5.
        assert!((mahalanobis_sq([2.0, 3.0], [[1.0, 0.0], [0.0, 9.0]]) - 5.0).abs() < 1e-12);
        // Correlated: C = [[2, 1], [1, 2]], d = (1, 1): d^T C^-1 d = 2 / 3.
        let c = [[2.0, 1.0], [1.0, 2.0]];
        assert!((mahalanobis_sq([1.0, 1.0], c) - 2.0 / 3.0).abs() < 1e-12);
        assert!((mahalanobis_sq([1.0, -1.0], c) - 2.0).abs() < 1e-12);
        assert!(mahalanobis_sq([1.0, 0.0], [[1.0, 1.0], [1.0, 1.0]]).is_infinite());
        assert!(mahalanobis_sq([0.0, 0.0], [[0.0; 2]; 2]).abs() < 1e-300);
        // The 95 % quantile of chi-squared with 2 degrees of freedom.
        assert!((CHI2_2DOF_95 - (-2.0 * 0.05f64.ln())).abs() < 1e-12);
        assert_eq!(
            z_score(1.2, 1.0, Some(0.1)).map(|z| (z * 1e9).round()),
            Some(2e9)
        );
        assert_eq!(z_score(1.0, 1.0, Some(0.0)), Some(0.0));
        assert_eq!(z_score(1.1, 1.0, None), None);
    }

    #[test]
    fn wrapping_keeps_the_documented_ranges() {
        assert!((wrap_deg(90.0, 90.0) - 90.0).abs() < 1e-12);
        assert!((wrap_deg(-90.0, 90.0) - 90.0).abs() < 1e-12);
        assert!((wrap_deg(170.0, 90.0) + 10.0).abs() < 1e-12);
        assert!((wrap_deg(-350.0, 180.0) - 10.0).abs() < 1e-12);
        assert!((wrap_deg(180.0, 180.0) - 180.0).abs() < 1e-12);
    }

    #[test]
    fn seeds_depend_on_every_input() {
        let (a, b) = (&SETUPS[0], &SETUPS[1]);
        let s = scene_seed(1, a, 0);
        assert_eq!(s, scene_seed(1, a, 0));
        assert_ne!(s, scene_seed(2, a, 0));
        assert_ne!(s, scene_seed(1, b, 0));
        assert_ne!(s, scene_seed(1, a, 1));
        assert_ne!(noise_seed(s, 1.0), noise_seed(s, 2.0));
    }
}
