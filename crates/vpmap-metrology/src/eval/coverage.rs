//! Error-bar coverage: where the truth lies in a fitted object's own error bars (the 95 %
//! centroid ellipse, `±2 sd` on its sizes, height and yaw), and in the camera's (`±2 sd` on
//! its focal length, pitch, roll and principal point).

use geo::Centroid;
use serde::Serialize;

use super::metrics::polygon;
use crate::map::MapPoint;
use crate::reconstruct::ObjectKind;
use crate::synth::TruthObject;

/// The largest squared Mahalanobis distance inside a 2-D 95 % confidence ellipse: the 0.95
/// quantile of the chi-squared distribution with 2 degrees of freedom, `-2 ln 0.05` (the one
/// the fit draws its ellipses with).
pub use crate::fit::CHI2_2DOF_95;

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
    /// A box's yaw error over its standard deviation: the reported direction of its longer
    /// side against the true direction of the same side, wrapped to `[-90, 90)` degrees.
    pub yaw_z: Option<f64>,
}

impl Coverage {
    /// Whether the true centroid lies inside the reported 95 % ellipse
    /// (`centroid_mahalanobis_sq <= CHI2_2DOF_95`).
    #[must_use]
    pub fn centroid_in_ellipse_95(&self) -> bool {
        self.centroid_mahalanobis_sq <= CHI2_2DOF_95
    }

    /// Per quantity (centroid, length, breadth, height, yaw; the order of
    /// [`COVERAGE_METRICS`]), whether the truth lies within the error bars: inside the 95 %
    /// ellipse, within `±2 sd`. `None` where the quantity has no error bar.
    #[must_use]
    pub fn within(&self) -> [Option<bool>; 5] {
        [
            Some(self.centroid_in_ellipse_95()),
            within_2sd(self.length_z),
            within_2sd(self.breadth_z),
            within_2sd(self.height_z),
            within_2sd(self.yaw_z),
        ]
    }
}

/// Names of the coverage checks, in the order of [`Coverage::within`].
pub const COVERAGE_METRICS: [&str; 5] = [
    "centroid_in_ellipse_95",
    "length_within_2sd",
    "breadth_within_2sd",
    "height_within_2sd",
    "yaw_within_2sd",
];

/// Whether a standardised error lies within `±2 sd` (`None` without an error bar).
fn within_2sd(z: Option<f64>) -> Option<bool> {
    z.map(|z| z.abs() <= 2.0)
}

/// How far the true camera lies from the fitted one, in the camera's own error bars
/// ([`crate::map::CameraReport::uncertainty`]): standardised errors `(m - a) / sd`, `None`
/// for a value the fit held (a standard deviation of 0: a two-point photo's pitch).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CameraCoverage {
    /// The focal length's.
    pub focal_z: Option<f64>,
    /// The pitch's.
    pub pitch_z: Option<f64>,
    /// The roll's.
    pub roll_z: Option<f64>,
    /// The principal point's, `[x, y]` (`None` where the fit held it: fewer than three finite
    /// vanishing points).
    pub principal_point_z: Option<[f64; 2]>,
}

impl CameraCoverage {
    /// Per quantity (the order of [`CAMERA_COVERAGE_METRICS`]), whether the truth lies within
    /// `±2 sd` (`None` for a held value).
    #[must_use]
    pub fn within(&self) -> [Option<bool>; 5] {
        self.values().map(within_2sd)
    }

    /// The standardised errors in the order of [`CAMERA_COVERAGE_METRICS`].
    #[must_use]
    pub fn values(&self) -> [Option<f64>; 5] {
        let pp = self.principal_point_z;
        [
            self.focal_z,
            self.pitch_z,
            self.roll_z,
            pp.map(|z| z[0]),
            pp.map(|z| z[1]),
        ]
    }
}

/// Names of the camera's coverage checks, in the order of [`CameraCoverage::within`].
pub const CAMERA_COVERAGE_METRICS: [&str; 5] = [
    "focal_within_2sd",
    "pitch_within_2sd",
    "roll_within_2sd",
    "principal_point_x_within_2sd",
    "principal_point_y_within_2sd",
];

/// The coverage of a fitted camera against the true one (`None` without error bars).
pub(super) fn camera_coverage(
    m: &crate::map::CameraReport,
    t: &crate::synth::TruthCamera,
) -> Option<CameraCoverage> {
    let true_pp = t.pinhole(m.image).principal_point_px;
    let u = m.uncertainty.as_ref()?;
    let z = |modelled: f64, actual: f64, sd: f64| {
        (sd > 0.0)
            .then(|| z_score(modelled, actual, Some(sd)))
            .flatten()
    };
    Some(CameraCoverage {
        focal_z: z(m.focal_px, t.focal_px, u.focal_px_sd),
        pitch_z: z(m.pitch_deg, t.pitch_deg, u.pitch_deg_sd),
        roll_z: z(m.roll_deg, t.roll_deg, u.roll_deg_sd),
        principal_point_z: u.principal_point_px_sd.and_then(|sd| {
            Some([
                z(m.principal_point[0], true_pp.x, sd[0])?,
                z(m.principal_point[1], true_pp.y, sd[1])?,
            ])
        }),
    })
}

/// The direction of the segment `a -> b`, degrees counter-clockwise from `+x`.
fn direction_deg(a: &MapPoint, b: &MapPoint) -> f64 {
    (b[1] - a[1]).atan2(b[0] - a[0]).to_degrees()
}

/// An angle's difference wrapped to `[-90, 90)` degrees (the yaw of a side is a direction
/// without a sense).
fn wrap_180(d: f64) -> f64 {
    (d + 90.0).rem_euclid(180.0) - 90.0
}

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
pub(super) fn coverage(m: &crate::map::MapObject, t: &TruthObject) -> Option<Coverage> {
    let u = m.uncertainty.as_ref()?;
    let actual = polygon(&t.footprint).centroid()?;
    let d = [m.centroid[0] - actual.x(), m.centroid[1] - actual.y()];
    let side = |p: &[MapPoint], k: usize| -> Option<f64> {
        let (a, b) = (p.first()?, p.get(k)?);
        Some((b[0] - a[0]).hypot(b[1] - a[1]))
    };
    let (mut length_z, mut breadth_z, mut yaw_z) = (None, None, None);
    if m.kind == ObjectKind::Box {
        // Sides (0,0)-(1,0) and (0,0)-(0,1), in the map and in the truth.
        let (ma, mb) = (side(&m.footprint, 1)?, side(&m.footprint, 3)?);
        let (ta, tb) = (side(&t.footprint, 1)?, side(&t.footprint, 3)?);
        let longer = if ma >= mb { 1 } else { 3 };
        let ((ml, tl), (mbr, tbr)) = if longer == 1 {
            ((ma, ta), (mb, tb))
        } else {
            ((mb, tb), (ma, ta))
        };
        length_z = z_score(ml, tl, u.length_sd);
        breadth_z = z_score(mbr, tbr, u.breadth_sd);
        // The reported yaw is the longer side's direction; the truth's is the same side's
        // (the same corners), whichever of its sides is longer.
        if let (Some(yaw), (Some(a), Some(b))) =
            (u.yaw_deg, (t.footprint.first(), t.footprint.get(longer)))
        {
            yaw_z = z_score(yaw, yaw - wrap_180(yaw - direction_deg(a, b)), u.yaw_sd_deg);
        }
    }
    let height_z = m.height.and_then(|h| z_score(h, t.height, u.height_sd));
    Some(Coverage {
        centroid_mahalanobis_sq: mahalanobis_sq(d, u.centroid_covariance),
        length_z,
        breadth_z,
        height_z,
        yaw_z,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn a_yaw_error_is_taken_modulo_a_half_turn() {
        // A side is a direction without a sense: 179 and -1 degrees are one direction.
        assert!((wrap_180(179.0 - (-1.0))).abs() < 1e-12);
        assert!((wrap_180(2.0 - 178.0) - 4.0).abs() < 1e-12);
        assert!((wrap_180(-3.0) + 3.0).abs() < 1e-12);
        assert!((wrap_180(90.0) + 90.0).abs() < 1e-12);
        assert!((direction_deg(&[1.0, 1.0], &[0.0, 2.0]) - 135.0).abs() < 1e-12);
        assert!((direction_deg(&[0.0, 0.0], &[0.0, -1.0]) + 90.0).abs() < 1e-12);
        // The reported yaw 0.5 degree (in [0, 180)) against a true side at 179.5 degrees
        // (-0.5 undirected: one degree less) with a sd of 0.5: 2 sd.
        let truth = direction_deg(&[0.0, 0.0], &[-1.0, 0.5f64.to_radians().tan()]);
        let yaw = 0.5;
        let z = z_score(yaw, yaw - wrap_180(yaw - truth), Some(0.5)).unwrap();
        assert!((z - 2.0).abs() < 1e-9, "{z}");
    }
}
