//! The thesis's error metrics of one object (section 6.1.1), and the scale factor `S_k` of
//! eq. 6.1 that brings the truth to the model's scale.

use geo::{Area, BooleanOps, Centroid, Coord, LineString, Polygon};
use serde::Serialize;

use crate::error::{MetrologyError, Result};
use crate::map::{BoxSize, MapPoint};

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

pub(super) fn polygon(points: &[MapPoint]) -> Polygon<f64> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrapping_keeps_the_documented_ranges() {
        assert!((wrap_deg(90.0, 90.0) - 90.0).abs() < 1e-12);
        assert!((wrap_deg(-90.0, 90.0) - 90.0).abs() < 1e-12);
        assert!((wrap_deg(170.0, 90.0) + 10.0).abs() < 1e-12);
        assert!((wrap_deg(-350.0, 180.0) - 10.0).abs() < 1e-12);
        assert!((wrap_deg(180.0, 180.0) - 180.0).abs() < 1e-12);
    }
}
