//! The build's warnings for the user: outlines that cross themselves, sizes the fit leaves
//! uncertain, misplaced clicks, and a camera the vanishing points fix poorly.

use nalgebra::Vector2;

use crate::fit::{CHI2_2DOF_95, Fitted};
use crate::map::{MapObject, Units};
use crate::reconstruct::{ObjectKind, Reconstruction};
use crate::scene::Scene;

/// Relative standard deviation of a size above which the build warns.
pub const WARN_RELATIVE_SD: f64 = 0.2;
/// Misfit of a clicked point, in click sigmas, above which the build warns.
pub const WARN_RESIDUAL_SIGMAS: f64 = 3.0;
/// How far off an object may lie before the build warns, metres: a quarter metre, the
/// distance at which issue 39 calls a box wrong (`docs/method.md`, "Objects placed poorly").
pub const WARN_POSITION_M: f64 = 0.25;
/// The chance, at most, that an object the build does not warn about lies more than
/// [`WARN_POSITION_M`] off (its centroid, or any corner of its outline), if its error bars are
/// right: one in a hundred.
pub const WARN_POSITION_PROBABILITY: f64 = 0.01;

/// Standard deviations, along the least certain direction, that must fit within
/// [`WARN_POSITION_M`] for `points` points at once (the centroid: 1; an outline: its corners):
/// `sqrt(2 ln(points / p))`, `p` = [`WARN_POSITION_PROBABILITY`]. A 2-D normal error whose
/// covariance has largest standard deviation `s` lies beyond `r` with probability at most
/// `exp(-r^2 / 2 s^2)` (a chi-square of two degrees of freedom, the covariance bounded by
/// `s^2 I`), so beyond this many sigmas at most `p / points` of the time, and by the union
/// bound some one of the points at most `p`. The centroid takes 3.03; a box's four corners
/// 3.46; an outline of eight vertices 3.66.
#[must_use]
pub fn warn_position_sigmas(points: usize) -> f64 {
    (2.0 * (points.max(1) as f64 / WARN_POSITION_PROBABILITY).ln()).sqrt()
}

/// The first two non-adjacent edges of a closed ring that touch or cross, as edge indices
/// (edge `i` runs from point `i` to point `i + 1`), or `None` for a simple ring.
#[must_use]
pub fn self_crossing(ring: &[Vector2<f64>]) -> Option<(usize, usize)> {
    let n = ring.len();
    if n < 4 {
        return None;
    }
    let orient = |a: Vector2<f64>, b: Vector2<f64>, c: Vector2<f64>| {
        let v = (b - a).perp(&(c - a));
        let scale = (b - a).norm() * (c - a).norm();
        if v.abs() <= 1e-12 * scale {
            0.0
        } else {
            v.signum()
        }
    };
    let on = |a: Vector2<f64>, b: Vector2<f64>, p: Vector2<f64>| {
        p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
    };
    for i in 0..n {
        let (a, b) = (ring[i], ring[(i + 1) % n]);
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let (c, d) = (ring[j], ring[(j + 1) % n]);
            let (o1, o2, o3, o4) = (
                orient(a, b, c),
                orient(a, b, d),
                orient(c, d, a),
                orient(c, d, b),
            );
            let crosses = (o1 * o2 < 0.0 && o3 * o4 < 0.0)
                || (o1 == 0.0 && on(a, b, c))
                || (o2 == 0.0 && on(a, b, d))
                || (o3 == 0.0 && on(c, d, a))
                || (o4 == 0.0 && on(c, d, b));
            if crosses {
                return Some((i, j));
            }
        }
    }
    None
}

/// Warnings for a floor outline or a footprint object that crosses itself (clicked out of
/// order): its area, and so the free space, would be wrong.
pub(super) fn crossing_warnings(scene: &Scene, rec: &Reconstruction) -> Vec<String> {
    let mut out = Vec::new();
    if let Some((i, j)) = self_crossing(&rec.floor) {
        out.push(format!(
            "the floor outline crosses itself (its edges from floor[{i}] and floor[{j}]): click the floor corners in order around the floor; the free space is wrong as it stands"
        ));
    }
    for (k, o) in rec.objects.iter().enumerate() {
        if o.kind == ObjectKind::Footprint
            && let Some((i, j)) = self_crossing(&o.footprint)
        {
            let name = scene
                .objects
                .get(k)
                .map_or(o.name.as_str(), |s| s.name.as_str());
            out.push(format!(
                "the footprint of object {name:?} crosses itself (its edges from footprint[{i}] and footprint[{j}]): click its vertices in order around it"
            ));
        }
    }
    out
}

/// The fit's warnings: sizes uncertain by more than [`WARN_RELATIVE_SD`] (naming the corner
/// that would help) and clicks farther than [`WARN_RESIDUAL_SIGMAS`] click sigmas from the
/// fitted model (a misplaced click).
pub(super) fn fit_warnings(
    scene: &Scene,
    fitted: &Fitted,
    u: &crate::fit::FitUncertainty,
) -> Vec<String> {
    let mut out = Vec::new();
    for &(i, what, rel) in &u.relative_size_sd {
        if rel > WARN_RELATIVE_SD
            && let Some(obj) = scene.objects.get(i)
        {
            out.push(format!(
                "object {:?}: its {what} is uncertain by +-{:.0} % (1 sigma, for {:.2} px clicks); {}",
                obj.name,
                100.0 * rel,
                u.click_sigma_px,
                crate::fit::advice_for(scene, i, what)
            ));
        }
    }
    out.extend(camera_warnings(scene, fitted, u));
    if u.click_sigma_px > 0.0 {
        for (r, weighted) in fitted
            .point_residuals
            .iter()
            .zip(&fitted.weighted_residuals)
        {
            // Pixels as pixels; sigmas of the click's own covariance when it has one.
            let sigmas = weighted / u.click_sigma_px;
            if sigmas > WARN_RESIDUAL_SIGMAS {
                out.push(format!(
                    "`{}` of object {:?} lies {:.1} px ({:.1} sigma) from the fitted box: a misplaced click?",
                    r.field, r.object, r.distance_px, sigmas
                ));
            }
        }
    }
    out
}

/// Warnings for objects whose place the fit leaves uncertain: a centroid, or the least certain
/// corner of the outline, whose standard deviation along its least certain direction,
/// [`warn_position_sigmas`] times over (for the one centroid, or for the outline's corners
/// together), exceeds [`WARN_POSITION_M`]. Only in a map in metres (a map in camera heights has
/// no metres to compare with). `advice` says what would help.
pub(super) fn position_warnings(
    objects: &[MapObject],
    units: Units,
    click_sigma_px: f64,
    advice: &str,
) -> Vec<String> {
    if units != Units::Meters {
        return Vec::new();
    }
    objects
        .iter()
        .filter_map(|o| {
            let u = o.uncertainty.as_ref()?;
            // The 95 % ellipse's long semi-axis, back to one sigma (infinite for a covariance
            // that is not finite: its place is not known at all).
            let sd = u.centroid_ellipse_95.semi_axes[0] / CHI2_2DOF_95.sqrt();
            // A corner's sd; NaN (not finite) counts as unknown, as the centroid's.
            let corner = u.corner_sd.map(|c| if c.is_nan() { f64::INFINITY } else { c });
            // NaN counted as far (a semi-axis is infinite, never NaN, for a covariance not
            // finite; a NaN corner became infinite above).
            let far = |sigmas: f64, s: f64| s.is_nan() || sigmas * s > WARN_POSITION_M;
            let corners = warn_position_sigmas(o.footprint.len());
            if far(warn_position_sigmas(1), sd) {
                Some(format!(
                    "object {:?}: its place is uncertain by +-{sd:.2} m (1 sigma along its least certain direction, {:.0} degrees from +x, for {click_sigma_px:.2} px clicks), so it may lie more than {WARN_POSITION_M} m off; {advice}",
                    o.name,
                    u.centroid_ellipse_95.angle_deg
                ))
            } else {
                corner.filter(|&c| far(corners, c)).map(|c| format!(
                    "object {:?}: its outline is uncertain by +-{c:.2} m at its least certain corner (1 sigma along that corner's least certain direction, for {click_sigma_px:.2} px clicks; its place +-{sd:.2} m), so a corner may lie more than {WARN_POSITION_M} m off; {advice}",
                    o.name
                ))
            }
        })
        .collect()
}

/// Root mean square of `values` (0 for none).
pub(super) fn rms(values: &[f64]) -> f64 {
    // Folded from +0: an empty sum of f64 is -0.
    (values.iter().map(|v| v * v).fold(0.0, |a, b| a + b) / values.len().max(1) as f64).sqrt()
}

/// Largest standard deviation of a fitted principal point, as a fraction of the image
/// diagonal, before a warning.
pub const WARN_PRINCIPAL_POINT_SD_DIAGONALS: f64 = 0.01;

/// Largest relative standard deviation of the fitted focal length before a warning.
pub const WARN_FOCAL_SD_FRACTION: f64 = 0.05;

/// Warnings for a camera the vanishing points fix poorly: a principal point or focal length
/// with a large error bar, naming the vanishing point farthest from the image (the one whose
/// direction a pixel of noise turns most).
fn camera_warnings(scene: &Scene, fitted: &Fitted, u: &crate::fit::FitUncertainty) -> Vec<String> {
    poorly_fixed_camera(scene, &fitted.calibration, &u.camera, u.click_sigma_px)
}

/// [`camera_warnings`] for one camera: its photo, its calibration, its error bars and the click
/// noise they are for. A principal point with a prior (`principal_point_sd_px`) is poorly fixed
/// only when it is less sure than its prior alone makes it.
pub(super) fn poorly_fixed_camera(
    photo: &Scene,
    calibration: &crate::calibration::Calibration,
    camera: &crate::uncertainty::CameraUncertainty,
    click_sigma_px: f64,
) -> Vec<String> {
    let mut out = Vec::new();
    let image = photo.image;
    let centre = image.centre();
    let prior_sd = photo
        .principal_point_sd_px
        .map_or(0.0, |sd| 1.01 * std::f64::consts::SQRT_2 * sd);
    let far = calibration
        .vanishing_points_px
        .iter()
        .enumerate()
        .map(|(k, v)| (k, (v - centre).norm()))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let far_text = far.map_or_else(String::new, |(k, d)| {
        format!(
            ": the {} vanishing point lies {d:.0} px ({:.0} image diagonals) from the image centre",
            if k == 2 { "vertical" } else { "horizontal" },
            d / image.diagonal()
        )
    });
    let cam = camera;
    if let Some([sx, sy]) = cam.principal_point_px_sd
        && sx.hypot(sy) > (WARN_PRINCIPAL_POINT_SD_DIAGONALS * image.diagonal()).max(prior_sd)
    {
        let pp = calibration.principal_point_px();
        out.push(format!(
            "the principal point ({:.1}, {:.1}) is poorly fixed, +-({sx:.1}, {sy:.1}) px (1 sigma, for {:.2} px clicks){far_text}; give longer edges towards it, or the principal point if it is known",
            pp.x, pp.y, click_sigma_px
        ));
    }
    let f = calibration.focal_px;
    if cam.focal_px_sd > WARN_FOCAL_SD_FRACTION * f {
        out.push(format!(
            "the focal length {f:.1} px is poorly fixed, +-{:.1} px ({:.0} %, 1 sigma, for {:.2} px clicks){far_text}; give longer edges towards it, or `focal_px` if it is known",
            cam.focal_px_sd,
            100.0 * cam.focal_px_sd / f,
            click_sigma_px
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::ObjectUncertainty;
    use crate::reconstruct::ObjectKind;

    /// An object at the origin whose centroid has covariance `c`, metres squared.
    fn object(c: [[f64; 2]; 2]) -> MapObject {
        MapObject {
            name: "box".to_owned(),
            kind: ObjectKind::Box,
            footprint: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            height: Some(1.0),
            size: None,
            centroid: [0.5, 0.5],
            area: 1.0,
            uncertainty: Some(ObjectUncertainty {
                centroid_covariance: c,
                centroid_ellipse_95: crate::fit::ellipse_95([0.5, 0.5], c),
                corner_sd: None,
                length_sd: None,
                breadth_sd: None,
                height_sd: None,
                yaw_deg: None,
                yaw_sd_deg: None,
            }),
        }
    }

    #[test]
    fn the_least_certain_direction_decides_a_place_warning() {
        // Eigenvalues 0.01 and 0.0001 along axes turned by 30 degrees: sd 0.1 m along the worst.
        let (a, b) = (0.01, 0.0001);
        let (cs, sn) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let c = [
            [a * cs * cs + b * sn * sn, (a - b) * cs * sn],
            [(a - b) * cs * sn, a * sn * sn + b * cs * cs],
        ];
        // 3.03 x 0.1 m > 0.25 m: named, with its sd and direction.
        let w = position_warnings(&[object(c)], Units::Meters, 1.5, "do this");
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with("object \"box\": its place is uncertain by +-0.10 m")
                && w[0].contains("30 degrees from +x")
                && w[0].contains("1.50 px clicks")
                && w[0].ends_with("; do this"),
            "{}",
            w[0]
        );
        // Just within a quarter metre at 3.03 sigma: nothing said.
        let s = 0.25 / warn_position_sigmas(1) - 1e-9;
        let fine = [[s * s, 0.0], [0.0, 1e-6]];
        assert!(position_warnings(&[object(fine)], Units::Meters, 1.0, "").is_empty());
        let s = 0.25 / warn_position_sigmas(1) + 1e-9;
        let poor = [[1e-6, 0.0], [0.0, s * s]];
        assert_eq!(
            position_warnings(&[object(poor)], Units::Meters, 1.0, "").len(),
            1
        );
        // A map in camera heights has no metres to compare with.
        assert!(position_warnings(&[object(c)], Units::CameraHeights, 1.0, "").is_empty());
        // A place not known at all (a NaN covariance) is named.
        let nan = [[f64::NAN, 0.0], [0.0, 1e-6]];
        assert_eq!(
            position_warnings(&[object(nan)], Units::Meters, 1.0, "").len(),
            1
        );
        // Without error bars (other methods) nothing is said.
        let mut bare = object(c);
        bare.uncertainty = None;
        assert!(position_warnings(&[bare], Units::Meters, 1.0, "").is_empty());
    }

    #[test]
    fn an_object_not_warned_lies_a_quarter_metre_off_at_most_one_time_in_a_hundred() {
        // Simulated: n corners with independent isotropic normal errors (the case the bound is
        // tight for) at the largest sd the warning lets pass; the share of objects with some
        // corner beyond a quarter metre must not exceed the stated probability (the exact
        // value is 1 - (1 - p / n)^n, a little under p).
        use rand::SeedableRng as _;
        use rand_distr::{Distribution as _, StandardNormal};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(39);
        for n in [1usize, 4, 8] {
            let s = WARN_POSITION_M / warn_position_sigmas(n);
            let trials = 200_000usize;
            let mut far = 0usize;
            for _ in 0..trials {
                let any = (0..n).any(|_| {
                    let (x, y): (f64, f64) = (
                        StandardNormal.sample(&mut rng),
                        StandardNormal.sample(&mut rng),
                    );
                    s * x.hypot(y) > WARN_POSITION_M
                });
                far += usize::from(any);
            }
            let share = far as f64 / trials as f64;
            let exact = 1.0 - (1.0 - WARN_POSITION_PROBABILITY / n as f64).powf(n as f64);
            // Four standard errors of the simulated share.
            let se = (exact * (1.0 - exact) / trials as f64).sqrt();
            assert!(
                (share - exact).abs() < 4.0 * se && exact <= WARN_POSITION_PROBABILITY + 1e-12,
                "{n} corners: {share} of objects beyond, {exact} exact"
            );
        }
    }

    #[test]
    fn the_least_certain_corner_decides_when_the_place_is_known() {
        // A centroid known to 1 cm whose corners a size or yaw leaves uncertain by `corner`.
        let with_corner = |corner: f64| {
            let mut o = object([[1e-4, 0.0], [0.0, 1e-4]]);
            if let Some(u) = o.uncertainty.as_mut() {
                u.corner_sd = Some(corner);
            }
            o
        };
        let w = position_warnings(&[with_corner(0.1)], Units::Meters, 2.0, "do this");
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with(
                "object \"box\": its outline is uncertain by +-0.10 m at its least certain corner"
            ) && w[0].contains("its place +-0.01 m")
                && w[0].contains("2.00 px clicks")
                && w[0].ends_with("; do this"),
            "{}",
            w[0]
        );
        // Both sides of the edge for a box's four corners (3.46 sigma); a corner not known at
        // all is named.
        let edge = 0.25 / warn_position_sigmas(4);
        assert!((warn_position_sigmas(4) - 3.4616).abs() < 1e-4);
        assert!(position_warnings(&[with_corner(edge - 1e-9)], Units::Meters, 1.0, "").is_empty());
        assert_eq!(
            position_warnings(&[with_corner(edge + 1e-9)], Units::Meters, 1.0, "").len(),
            1
        );
        assert_eq!(
            position_warnings(&[with_corner(f64::NAN)], Units::Meters, 1.0, "").len(),
            1
        );
        // A place uncertain as well: the place's message, said once.
        let mut both = object([[0.01, 0.0], [0.0, 1e-4]]);
        if let Some(u) = both.uncertainty.as_mut() {
            u.corner_sd = Some(0.2);
        }
        let w = position_warnings(&[both], Units::Meters, 1.0, "");
        assert_eq!(w.len(), 1);
        assert!(
            w[0].contains("its place is uncertain by +-0.10 m"),
            "{}",
            w[0]
        );
    }
}
