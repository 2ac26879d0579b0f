//! Error-bar coverage: where the truth lies in a fitted object's own error bars (the 95 %
//! centroid ellipse, `±2 sd` on its sizes and height).

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
pub(super) fn coverage(m: &crate::map::MapObject, t: &TruthObject) -> Option<Coverage> {
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
}
