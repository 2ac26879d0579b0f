//! Whether the detected scene's error bars hold the labelled truth: each labelled vanishing
//! direction against its written point's 95 % ellipse, and the labelled focal length against
//! the detected scene's 95 % interval.
//!
//! A labelled direction `d` is the pixel point `K d` of the labelled `K`; its offset from the
//! written point is measured in the scene's chart ([`vpmap_metrology::scene::VpChart`]) and
//! weighed by the written covariance: Mahalanobis distance squared `o^T C^-1 o`, inside the
//! 95 % ellipse when at most 5.991. The vertical is matched to the labelled vertical, the
//! horizontals by the assignment with the smaller total distance. The focal length's interval
//! is the camera fit of the scene alone ([`DetectedScene::camera_estimate`]), `f +- 1.96 sd`.
//!
//! The lens has no label, but York Urban's photos were all taken by one camera at one zoom
//! (one `K`), so they share one `k`: each photo's `k` is checked against the
//! precision-weighted mean of the others' ([`lens_consistency`]).

use nalgebra::{Matrix2, Vector2, Vector3};
use vpmap_vision::scene::DetectedScene;

use super::Label;
use super::horizon::Line;

/// The chi-square quantile with 2 degrees of freedom at 95 %.
pub const CHI2_2DOF_95: f64 = 5.991_464_547_107_979;

/// The normal quantile at 97.5 % (a two-sided 95 % interval).
pub const Z_95: f64 = 1.959_963_984_540_054;

/// Mahalanobis distance squared of the labelled direction `d` (camera frame, y down) from
/// written point `role` of `scene`.
fn distance2(scene: &DetectedScene, role: usize, label: &Label, d: [f64; 3]) -> Option<f64> {
    let p = scene.points_px.get(role).copied().flatten()?;
    let c = scene
        .covariances
        .get(role)
        .copied()
        .flatten()?
        .covariance_deg2;
    let truth = Vector3::new(
        label.focal_px * d[0] + label.principal_point_px[0] * d[2],
        label.focal_px * d[1] + label.principal_point_px[1] * d[2],
        d[2],
    );
    let o = scene
        .chart
        .offset_rad(Vector3::new(p[0], p[1], 1.0), truth)?;
    let o = Vector2::new(o[0].to_degrees(), o[1].to_degrees());
    let inv = Matrix2::new(c[0][0], c[0][1], c[1][0], c[1][1]).try_inverse()?;
    Some((o.transpose() * inv * o)[(0, 0)])
}

/// Each labelled vanishing direction's Mahalanobis distance squared from its written point
/// (label order; `None` when the scene writes no point for it, e.g. the vertical of a
/// two-point scene).
#[must_use]
pub fn direction_distances(scene: &DetectedScene, label: &Label) -> [Option<f64>; 3] {
    let mut out = [None; 3];
    out[label.vertical] = distance2(scene, 2, label, label.directions[label.vertical]);
    let labelled: Vec<usize> = (0..3).filter(|&i| i != label.vertical).collect();
    let d = |role: usize, l: usize| distance2(scene, role, label, label.directions[l]);
    let straight = [d(0, labelled[0]), d(1, labelled[1])];
    let crossed = [d(0, labelled[1]), d(1, labelled[0])];
    let total = |p: [Option<f64>; 2]| p.iter().map(|v| v.unwrap_or(f64::INFINITY)).sum::<f64>();
    let [a, b] = if total(straight) <= total(crossed) {
        straight
    } else {
        [crossed[1], crossed[0]]
    };
    out[labelled[0]] = a;
    out[labelled[1]] = b;
    out
}

/// The labelled focal length's distance from the detected scene's estimate, in its standard
/// deviations (`None` when the scene's camera fit fails).
#[must_use]
pub fn focal_z(scene: &DetectedScene, label: &Label) -> Option<f64> {
    let c = scene.camera_estimate()?;
    (c.focal_sd_px > 0.0).then(|| (c.focal_px - label.focal_px).abs() / c.focal_sd_px)
}

/// Where the labelled camera lies in the error bars of the camera the written scene alone
/// gives ([`DetectedScene::camera_estimate`]; `vpmap detect`'s summary and overlay show them):
/// standardised errors `(estimate - truth) / sd`. The truth's pitch, roll and horizon are
/// taken from each of the two labelled horizons ([`Label::horizon`], the labelled vertical's;
/// [`Label::horizon_of_horizontals`]), which differ because the labels are not orthogonal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraZ {
    /// The pitch's, against each labelled horizon.
    pub pitch: [f64; 2],
    /// The roll's.
    pub roll: [f64; 2],
    /// The horizon's: the labelled horizon's offset from the estimated principal point, along
    /// the estimated horizon's normal, against the estimated horizon's offset
    /// (`f tan(pitch)`), over `horizon_sd_px`: what the overlay's 95 % band claims.
    pub horizon: [f64; 2],
    /// The principal point's `[x, y]`, against the label's, where the fit placed it.
    pub principal_point: Option<[f64; 2]>,
}

/// The pitch (positive looking down) and roll, radians, of a camera with focal length
/// `focal_px` and principal point `pp` whose horizon is `line`, in the conventions of
/// `vpmap_metrology::calibration::Calibration` (roll: the horizon's angle, positive when it
/// falls to the right; the horizon `f tan(pitch)` above the principal point). `None` for a
/// vertical or degenerate line.
fn pitch_roll_of_horizon(line: Line, focal_px: f64, pp: [f64; 2]) -> Option<(f64, f64)> {
    let [a, b, _] = line;
    let n = a.hypot(b);
    if !(n.is_finite() && n > 0.0) {
        return None;
    }
    // The horizon's direction, pointing right.
    let mut along = [b / n, -a / n];
    if along[0] < 0.0 || (along[0] == 0.0 && along[1] > 0.0) {
        along = [-along[0], -along[1]];
    }
    if along[0] <= 0.0 {
        return None;
    }
    let up = [along[1], -along[0]];
    let above = offset_along(line, pp, up)?;
    Some((above.atan2(focal_px), along[1].atan2(along[0])))
}

/// How far along `dir` from `p` the line lies: `t` with `p + t dir` on it (`None` when the
/// line runs along `dir`).
fn offset_along(line: Line, p: [f64; 2], dir: [f64; 2]) -> Option<f64> {
    let [a, b, c] = line;
    let across = a * dir[0] + b * dir[1];
    (across.abs() > 1e-12 * a.hypot(b)).then(|| -(a * p[0] + b * p[1] + c) / across)
}

/// The signed difference of two angles, wrapped to `[-pi, pi)`.
fn angle_difference(a: f64, b: f64) -> f64 {
    use std::f64::consts::PI;
    (a - b + PI).rem_euclid(2.0 * PI) - PI
}

/// The labelled camera's standardised errors in the written scene's camera estimate (`None`
/// when the scene's camera fit fails or a labelled horizon is degenerate).
#[must_use]
pub fn camera_z(scene: &DetectedScene, label: &Label) -> Option<CameraZ> {
    let c = scene.camera_estimate()?;
    let (pitch, roll) = (c.pitch_deg.to_radians(), c.roll_deg.to_radians());
    let along = [roll.cos(), roll.sin()];
    let up = [along[1], -along[0]];
    let offset = c.focal_px * pitch.tan();
    let mut z = CameraZ {
        pitch: [0.0; 2],
        roll: [0.0; 2],
        horizon: [0.0; 2],
        principal_point: None,
    };
    for (k, truth) in [label.horizon(), label.horizon_of_horizontals()]
        .into_iter()
        .enumerate()
    {
        let (true_pitch, true_roll) =
            pitch_roll_of_horizon(truth, label.focal_px, label.principal_point_px)?;
        z.pitch[k] = (pitch - true_pitch).to_degrees() / c.pitch_sd_deg;
        z.roll[k] = angle_difference(roll, true_roll).to_degrees() / c.roll_sd_deg;
        let true_offset = offset_along(truth, c.principal_point_px, up)?;
        z.horizon[k] = (offset - true_offset) / c.horizon_sd_px;
    }
    z.principal_point = c
        .principal_point_sd_px
        .map(|sd| [0, 1].map(|i| (c.principal_point_px[i] - label.principal_point_px[i]) / sd[i]));
    Some(z)
}

/// The lens's consistency over photos of one camera: each photo's `k` against the
/// precision-weighted mean `m` of all the others (leave one out), `z = (k - m) / sqrt(sd^2 +
/// var(m))`. Returns the share with `|z| <= 1.96`, the root mean square of `z` (1 when the sds
/// are right), the mean of all and how many photos; `None` for fewer than three.
#[must_use]
pub fn lens_consistency(lenses: &[[f64; 2]]) -> Option<LensConsistency> {
    let usable: Vec<[f64; 2]> = lenses
        .iter()
        .copied()
        .filter(|[k, sd]| k.is_finite() && sd.is_finite() && *sd > 0.0)
        .collect();
    if usable.len() < 3 {
        return None;
    }
    let weight = |sd: f64| 1.0 / (sd * sd);
    let total_w: f64 = usable.iter().map(|l| weight(l[1])).sum();
    let total_wk: f64 = usable.iter().map(|l| weight(l[1]) * l[0]).sum();
    let mut inside = 0usize;
    let mut squares = 0.0;
    for &[k, sd] in &usable {
        let w = total_w - weight(sd);
        let m = (total_wk - weight(sd) * k) / w;
        let z = (k - m) / (sd * sd + 1.0 / w).sqrt();
        squares += z * z;
        if z.abs() <= Z_95 {
            inside += 1;
        }
    }
    let n = usable.len();
    Some(LensConsistency {
        inside: inside as f64 / n as f64,
        rms_z: (squares / n as f64).sqrt(),
        mean_k: total_wk / total_w,
        photos: n,
    })
}

/// What [`lens_consistency`] found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LensConsistency {
    /// Share of photos whose `k` lies within 1.96 sd of the others' mean.
    pub inside: f64,
    /// Root mean square of the normalised differences (1 for honest sds).
    pub rms_z: f64,
    /// The precision-weighted mean `k` of all photos.
    pub mean_k: f64,
    /// Photos with a lens estimate.
    pub photos: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pitch_and_roll_of_a_horizon_follow_the_calibration() {
        let (f, pp) = (500.0, [320.0, 240.0]);
        // Level, no roll: the horizon through the principal point.
        let (p, r) = pitch_roll_of_horizon([0.0, 1.0, -240.0], f, pp).unwrap();
        assert!(p.abs() < 1e-12 && r.abs() < 1e-12);
        // Looking down 10 degrees: the horizon f tan(10) above the principal point.
        let y = 240.0 - f * 10f64.to_radians().tan();
        let (p, r) = pitch_roll_of_horizon([0.0, 2.0, -2.0 * y], f, pp).unwrap();
        assert!((p.to_degrees() - 10.0).abs() < 1e-9 && r.abs() < 1e-12);
        // Rolled 5 degrees (falling to the right) through the principal point, either sign of
        // the line's coefficients.
        let t = 5f64.to_radians();
        let line = [t.sin(), -t.cos(), 240.0 * t.cos() - 320.0 * t.sin()];
        for l in [line, line.map(|v| -v)] {
            let (p, r) = pitch_roll_of_horizon(l, f, pp).unwrap();
            assert!(p.abs() < 1e-9, "{p}");
            assert!((r.to_degrees() - 5.0).abs() < 1e-9, "{}", r.to_degrees());
        }
        assert!(pitch_roll_of_horizon([1.0, 0.0, -3.0], f, pp).is_none());
        assert!(
            (angle_difference(179f64.to_radians(), -179f64.to_radians()).to_degrees() + 2.0).abs()
                < 1e-9
        );
    }

    #[test]
    fn lens_consistency_weighs_the_others() {
        // Three photos of sd 1: k = 0, 0, 3. The third against the mean 0 of the others
        // (variance 1/2): z = 3 / sqrt(1.5) = 2.45, outside; the first against 1.5: z = 1.22.
        let c = lens_consistency(&[[0.0, 1.0], [0.0, 1.0], [3.0, 1.0]]).unwrap();
        assert!((c.inside - 2.0 / 3.0).abs() < 1e-12);
        let expected = ((2.0 * 1.5 * 1.5 / 1.5 + 9.0 / 1.5) / 3.0f64).sqrt();
        assert!((c.rms_z - expected).abs() < 1e-12, "{}", c.rms_z);
        assert!((c.mean_k - 1.0).abs() < 1e-12);
        assert!(lens_consistency(&[[0.0, 1.0], [1.0, 1.0]]).is_none());
    }
}
