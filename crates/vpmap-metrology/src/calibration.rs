//! Camera calibration from vanishing points (thesis chapter 4.2-4.3, Appendix B).
//!
//! Input: two horizontal vanishing points VP1, VP2 (two-point perspective, pitch 0) or those
//! plus the vertical one VP3 (three-point perspective). Output: the principal point `O`, the
//! focal length `d` (pixels), the pitch `theta` (positive when the camera looks down), the roll
//! and the *horizon frame* in which every side-view distance is measured (see
//! `../shared/thesis/errata.md`, "Frame and signs"): `x` along the horizon towards image right,
//! `y` perpendicular to it, positive towards the sky.

use nalgebra::{Matrix2, Vector2, Vector3};

use crate::error::{MetrologyError, Result};
use crate::scene::ImageSize;

// Two- or three-point perspective: the scene file's type (it lives with the scene's types,
// which this module reads), here too where the calibration reports it.
#[doc(inline)]
pub use crate::scene::Perspective;

/// The image frame aligned with the horizon, origin at the principal point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HorizonFrame {
    /// Principal point `O`, pixels.
    pub origin_px: Vector2<f64>,
    /// Unit vector along the horizon, pointing to image right.
    pub along: Vector2<f64>,
    /// Unit vector perpendicular to the horizon, pointing to the sky (image "up").
    pub up: Vector2<f64>,
    /// Signed offset of the horizon from `O` along `up`, pixels (`OG` of eq. 4.1, positive
    /// when the camera looks down).
    pub horizon_offset_px: f64,
}

impl HorizonFrame {
    /// Horizon-frame coordinates `(x, y)` of an image point, pixels.
    #[must_use]
    pub fn coords(&self, point_px: Vector2<f64>) -> Vector2<f64> {
        let v = point_px - self.origin_px;
        Vector2::new(v.dot(&self.along), v.dot(&self.up))
    }

    /// The image point with horizon-frame coordinates `(x, y)`.
    #[must_use]
    pub fn image_point(&self, coords: Vector2<f64>) -> Vector2<f64> {
        self.origin_px + self.along * coords.x + self.up * coords.y
    }

    /// Signed perpendicular distance of an image point below the horizon, pixels
    /// (`P1G` of eq. 4.5; negative above the horizon).
    #[must_use]
    pub fn below_horizon_px(&self, point_px: Vector2<f64>) -> f64 {
        self.horizon_offset_px - self.coords(point_px).y
    }
}

/// The camera as recovered from the vanishing points.
#[derive(Debug, Clone, PartialEq)]
pub struct Calibration {
    /// 2PP or 3PP.
    pub perspective: Perspective,
    /// Focal length `d`, pixels.
    pub focal_px: f64,
    /// Pitch `theta`, radians, positive when the camera looks down (0 in 2PP).
    pub pitch_rad: f64,
    /// Roll, radians: the horizon's angle in the image, positive when it falls to the right
    /// (image y grows along it; the camera's right side is tilted up).
    pub roll_rad: f64,
    /// The vanishing points used, pixels (VP1, VP2 horizontal; VP3 vertical in 3PP).
    pub vanishing_points_px: Vec<Vector2<f64>>,
    /// The horizon frame, origin at the principal point `O`.
    pub frame: HorizonFrame,
    /// Notes for the user (e.g. a given principal point that disagrees with the VPs).
    pub warnings: Vec<String>,
}

impl Calibration {
    /// The principal point `O`, pixels.
    #[must_use]
    pub fn principal_point_px(&self) -> Vector2<f64> {
        self.frame.origin_px
    }

    /// Distance from the view point to the horizon line in the top-view construction,
    /// `D0 = d / cos(theta)` (errata, "The top view").
    #[must_use]
    pub fn top_view_distance_px(&self) -> f64 {
        self.focal_px / self.pitch_rad.cos()
    }

    /// Calibrate from resolved vanishing points.
    ///
    /// `vanishing_points_px` holds two horizontal vanishing points (two-point perspective) or
    /// three, in any order: the vertical one is the one opposite the most level side
    /// ([`vertical_index`]), the horizontal ones keep their order. `principal_point_px`
    /// defaults to the image centre (2PP) or the orthocentre of the VP triangle (3PP).
    ///
    /// * 2PP (Appendix B): `d^2 = OC1 * OC2 = -(VP1 - O).(VP2 - O)` for `O` on the horizon
    ///   (power of a point on the vanishing circle). A principal point off the horizon is moved
    ///   to its foot on the horizon (pitch 0 by definition), with a warning.
    /// * 3PP (eqs. 4.1-4.4): `O` = orthocentre, `G` = foot of the altitude from VP3 on the
    ///   horizon, `C` = VP3, `d = sqrt(OG * OC)`, `tan(theta) = sqrt(OG / OC)` (signed: a camera
    ///   looking up has the horizon below `O` and VP3 above it).
    ///
    /// # Errors
    /// Coincident vanishing points, a VP3 on the horizon, or a configuration with no real
    /// focal length (principal point outside the vanishing circle, obtuse VP triangle).
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector2;
    /// use vpmap_metrology::calibration::{Calibration, Perspective};
    /// use vpmap_metrology::scene::ImageSize;
    /// // A 2PP camera with f = 1000 px looking 30 degrees left of a room's axes.
    /// let (t, f) = (30f64.to_radians().tan(), 1000.0);
    /// let vps = [Vector2::new(800.0 - f / t, 600.0), Vector2::new(800.0 + f * t, 600.0)];
    /// let cal = Calibration::from_vanishing_points(&vps, None, ImageSize { width: 1600, height: 1200 }).unwrap();
    /// assert_eq!(cal.perspective, Perspective::TwoPoint);
    /// assert!((cal.focal_px - 1000.0).abs() < 1e-9);
    /// ```
    pub fn from_vanishing_points(
        vanishing_points_px: &[Vector2<f64>],
        principal_point_px: Option<Vector2<f64>>,
        image: ImageSize,
    ) -> Result<Self> {
        let points: Vec<Vector3<f64>> = vanishing_points_px
            .iter()
            .map(|v| Vector3::new(v.x, v.y, 1.0))
            .collect();
        Self::from_homogeneous(&points, principal_point_px, image)
    }

    /// Calibrate from vanishing points in homogeneous pixel coordinates `(x, y, w)`: `w = 1`
    /// for a point, `w = 0` for a direction (a vanishing point at infinity), as
    /// [`crate::scene::Scene::resolve_vanishing_points`] gives them; otherwise as
    /// [`Calibration::from_vanishing_points`].
    ///
    /// Of three, the vertical one may be at infinity: the camera is level (pitch 0) and is
    /// calibrated from the two horizontal ones as in two-point perspective, with a warning
    /// when the given direction is not perpendicular to their horizon.
    ///
    /// # Errors
    /// As [`Calibration::from_vanishing_points`], and a horizontal vanishing point at infinity
    /// (it fixes no focal length in closed form).
    pub fn from_homogeneous(
        vanishing_points_px: &[Vector3<f64>],
        principal_point_px: Option<Vector2<f64>>,
        image: ImageSize,
    ) -> Result<Self> {
        Self::from_listed(vanishing_points_px, principal_point_px, image, false)
    }

    /// As [`Calibration::from_homogeneous`], where `labelled` says the list's order was set by
    /// a tool that names each vanishing point (segments drawn on the page, `vpmap detect`,
    /// `vpmap eval`): then the listed order is kept unless its horizon is implausible
    /// ([`reading`]).
    ///
    /// # Errors
    /// As [`Calibration::from_homogeneous`].
    pub fn from_listed(
        vanishing_points_px: &[Vector3<f64>],
        principal_point_px: Option<Vector2<f64>>,
        image: ImageSize,
        labelled: bool,
    ) -> Result<Self> {
        let n = vanishing_points_px.len();
        if !(2..=3).contains(&n) {
            return Err(MetrologyError::VanishingPointCount(n));
        }
        let tol = 1e-9 * image.diagonal();
        for i in 0..n {
            for j in i + 1..n {
                let (a, b) = (&vanishing_points_px[i], &vanishing_points_px[j]);
                let same = match (finite_point(a), finite_point(b)) {
                    (Some(p), Some(q)) => (p - q).norm() <= tol,
                    _ => false,
                };
                if same {
                    return Err(MetrologyError::CoincidentVanishingPoints {
                        first: i + 1,
                        second: j + 1,
                        x: a.x / a.z,
                        y: a.y / a.z,
                    });
                }
            }
        }
        let mut warnings = Vec::new();
        let order = reading(vanishing_points_px, labelled).unwrap_or([0, 1, 2]);
        if n == 3 && order[2] != 2 {
            warnings.push(reorder_warning(vanishing_points_px, order));
        }
        let ordered: Vec<Vector3<f64>> =
            order[..n].iter().map(|&i| vanishing_points_px[i]).collect();
        let mut finite = Vec::with_capacity(n);
        for (k, v) in ordered.iter().enumerate() {
            match finite_point(v) {
                Some(p) => finite.push(p),
                None if k == 2 => {}
                None => {
                    return Err(MetrologyError::NoRealFocalLength(format!(
                        "horizontal vanishing point {} is given as a direction ({:.3}, {:.3}), at infinity: it fixes no focal length in closed form; give it as a point or as segments",
                        order[k] + 1,
                        v.x,
                        v.y
                    )));
                }
            }
        }
        if finite.len() == 2 && n == 3 {
            // A level camera: the vertical edges are parallel in the image, perpendicular to
            // the horizon. Calibrated as two-point perspective.
            let along = (finite[1] - finite[0]).normalize();
            let dir = Vector2::new(ordered[2].x, ordered[2].y).normalize();
            let off_deg = dir.dot(&along).abs().clamp(0.0, 1.0).asin().to_degrees();
            let mut cal = Self::from_finite(&finite, principal_point_px, image)?;
            if off_deg > LEVEL_DIRECTION_TOLERANCE_DEG {
                cal.warnings.push(format!(
                    "the vertical vanishing point's direction ({:.3}, {:.3}) is {off_deg:.2} deg from perpendicular to the horizon through the other two; the camera was taken as level (pitch 0)",
                    ordered[2].x, ordered[2].y
                ));
            }
            warnings.append(&mut cal.warnings);
            cal.warnings = warnings;
            return Ok(cal);
        }
        let mut cal = Self::from_finite(&finite, principal_point_px, image)?;
        warnings.append(&mut cal.warnings);
        cal.warnings = warnings;
        Ok(cal)
    }

    /// The closed forms on finite vanishing points in the documented order (horizontal ones,
    /// then the vertical one).
    fn from_finite(
        vanishing_points_px: &[Vector2<f64>],
        principal_point_px: Option<Vector2<f64>>,
        image: ImageSize,
    ) -> Result<Self> {
        let n = vanishing_points_px.len();
        let (v1, v2) = (vanishing_points_px[0], vanishing_points_px[1]);
        let mut along = (v2 - v1).normalize();
        if along.x < 0.0 || (along.x == 0.0 && along.y > 0.0) {
            along = -along;
        }
        // Image y grows downwards, so "up" is the horizon direction turned by -90 degrees.
        let up = Vector2::new(along.y, -along.x);
        let roll_rad = along.y.atan2(along.x);
        let mut warnings = Vec::new();

        if n == 2 {
            let given = principal_point_px.unwrap_or_else(|| image.centre());
            let offset = (v1 - given).dot(&up);
            // Foot of the principal point on the horizon.
            let o = given + up * offset;
            if offset.abs() > 0.01 * f64::from(image.height) {
                warnings.push(format!(
                    "the principal point ({:.1}, {:.1}) is {:.1} px off the horizon; two-point perspective assumes pitch 0, so it was moved onto the horizon at ({:.1}, {:.1}). If the camera was tilted, give the vertical vanishing point too",
                    given.x, given.y, offset.abs(), o.x, o.y
                ));
            }
            let f2 = -(v1 - o).dot(&(v2 - o));
            if f2 <= 0.0 || !f2.is_finite() {
                return Err(MetrologyError::NoRealFocalLength(format!(
                    "the principal point ({:.3}, {:.3}) lies outside the circle on VP1 ({:.3}, {:.3}) - VP2 ({:.3}, {:.3}) as diameter, so d^2 = -(VP1 - O).(VP2 - O) = {f2:.6e} px^2 is not positive",
                    o.x, o.y, v1.x, v1.y, v2.x, v2.y
                )));
            }
            return Ok(Self {
                perspective: Perspective::TwoPoint,
                focal_px: f2.sqrt(),
                pitch_rad: 0.0,
                roll_rad,
                vanishing_points_px: vec![v1, v2],
                frame: HorizonFrame {
                    origin_px: o,
                    along,
                    up,
                    horizon_offset_px: 0.0,
                },
                warnings,
            });
        }

        let v3 = vanishing_points_px[2];
        let off_line = (v3 - v1).dot(&up);
        if off_line.abs() <= 1e-9 * image.diagonal() {
            return Err(MetrologyError::NoRealFocalLength(format!(
                "the vertical vanishing point ({:.3}, {:.3}) lies on the horizon through VP1 and VP2",
                v3.x, v3.y
            )));
        }
        let ortho = orthocentre(v1, v2, v3).ok_or_else(|| {
            MetrologyError::NoRealFocalLength("the vanishing points are collinear".to_owned())
        })?;
        let o = match principal_point_px {
            Some(p) => {
                let gap = (p - ortho).norm();
                if gap > 0.01 * image.diagonal() {
                    warnings.push(format!(
                        "the given principal point ({:.1}, {:.1}) is {gap:.1} px from the orthocentre ({:.1}, {:.1}) of the vanishing points; the given point was used",
                        p.x, p.y, ortho.x, ortho.y
                    ));
                }
                p
            }
            None => ortho,
        };
        // Eq. 4.1: OG along `up` to the horizon, OC from O down to VP3 (both signed).
        let og = (v1 - o).dot(&up);
        let oc = -(v3 - o).dot(&up);
        let product = og * oc;
        if product <= 0.0 || !product.is_finite() {
            return Err(MetrologyError::NoRealFocalLength(format!(
                "OG * OC = {og:.6} * {oc:.6} px^2 is not positive: the orthocentre ({:.3}, {:.3}) of the vanishing-point triangle must lie between the horizon and the vertical vanishing point (the triangle must be acute). If the camera was nearly level (vertical edges almost parallel), give only the two horizontal vanishing points",
                o.x, o.y
            )));
        }
        let d = product.sqrt();
        // Eq. 4.4, signed: tan(theta) = OG / d = sqrt(OG / OC).
        let pitch_rad = og.atan2(d);
        Ok(Self {
            perspective: Perspective::ThreePoint,
            focal_px: d,
            pitch_rad,
            roll_rad,
            vanishing_points_px: vec![v1, v2, v3],
            frame: HorizonFrame {
                origin_px: o,
                along,
                up,
                horizon_offset_px: og,
            },
            warnings,
        })
    }
}

/// Largest angle, degrees, between a level camera's vertical direction (a vanishing point
/// given at infinity) and the perpendicular to the horizon, before a warning.
pub const LEVEL_DIRECTION_TOLERANCE_DEG: f64 = 1.0;

/// A homogeneous pixel point as a finite point, or `None` at infinity (beyond
/// [`crate::scene::MAX_VANISHING_POINT_PX`]).
#[must_use]
pub fn finite_point(v: &Vector3<f64>) -> Option<Vector2<f64>> {
    let p = Vector2::new(v.x / v.z, v.y / v.z);
    (v.z != 0.0
        && p.x.is_finite()
        && p.y.is_finite()
        && p.norm() <= crate::scene::MAX_VANISHING_POINT_PX)
        .then_some(p)
}

/// The image direction of the line through two homogeneous points (either may be at
/// infinity, not both), or `None`.
fn line_direction(a: &Vector3<f64>, b: &Vector3<f64>) -> Option<Vector2<f64>> {
    let d = match (finite_point(a), finite_point(b)) {
        (Some(p), Some(q)) => q - p,
        (None, Some(_)) => Vector2::new(a.x, a.y),
        (Some(_), None) => Vector2::new(b.x, b.y),
        (None, None) => return None,
    };
    (d.norm() > 0.0 && d.x.is_finite() && d.y.is_finite()).then_some(d)
}

/// The angle, degrees in `[0, 90]`, between the line through two vanishing points and the
/// image's rows, or `None`.
fn tilt_deg(a: &Vector3<f64>, b: &Vector3<f64>) -> Option<f64> {
    line_direction(a, b).map(|d| (d.y.abs() / d.norm()).clamp(0.0, 1.0).asin().to_degrees())
}

/// Which of three vanishing points (homogeneous, any order) is the vertical one: the one
/// opposite the most level side, since the other two span the horizon and photos are taken
/// with a small roll. Ties keep the documented order (the last). The three are symmetric in
/// the camera's geometry (any of them fits the same focal length and principal point), so
/// this is a prior on how people hold cameras; it reads a photo looking down steeply at
/// walls nearly face-on, with a large roll, the other way. `None` for fewer than three.
#[must_use]
pub fn vertical_index(points: &[Vector3<f64>]) -> Option<usize> {
    if points.len() != 3 {
        return None;
    }
    let mut best: Option<(usize, f64)> = None;
    for k in (0..3).rev() {
        let others: Vec<&Vector3<f64>> = (0..3).filter(|&i| i != k).map(|i| &points[i]).collect();
        if let Some(t) = tilt_deg(others[0], others[1])
            && best.is_none_or(|(_, b)| t < b - TIE_DEG)
        {
            best = Some((k, t));
        }
    }
    best.map(|(k, _)| k)
}

/// Tilts closer than this, degrees, count as a tie in [`vertical_index`].
const TIE_DEG: f64 = 1e-9;

/// The indices of three vanishing points in the documented order: the horizontal ones as
/// given, then the vertical one ([`vertical_index`]); `None` for fewer than three.
pub(crate) fn vertical_last_order(points: &[Vector3<f64>]) -> Option<[usize; 3]> {
    let v = vertical_index(points)?;
    let mut order = [0, 1, v];
    for (at, i) in (0..3).filter(|&i| i != v).enumerate() {
        order[at] = i;
    }
    Some(order)
}

/// Largest angle, degrees, between the image rows and the horizon through the first two of
/// three labelled vanishing points for the list to be read as given ([`reading`]).
pub const LISTED_HORIZON_MAX_TILT_DEG: f64 = 45.0;

/// How three vanishing points are read: the indices of the horizontal ones, then the vertical
/// one. Points given as such are facts that any data set may list in its own order (York
/// Urban lists the vertical one second): the vertical one is the one opposite the most level
/// side ([`vertical_index`]). A `labelled` list (its order set by a tool that names each one)
/// is read as listed, the vertical one last, unless the horizon through the first two is more
/// than [`LISTED_HORIZON_MAX_TILT_DEG`] from level: segments from short, noisy edges can put
/// a vanishing point where the most level side would misread them. `None` for fewer than
/// three.
#[must_use]
pub fn reading(points: &[Vector3<f64>], labelled: bool) -> Option<[usize; 3]> {
    if points.len() != 3 {
        return None;
    }
    if labelled
        && tilt_deg(&points[0], &points[1]).is_some_and(|t| t <= LISTED_HORIZON_MAX_TILT_DEG)
    {
        return Some([0, 1, 2]);
    }
    vertical_last_order(points)
}

/// The warning for vanishing points whose vertical one was not listed last.
pub(crate) fn reorder_warning(points: &[Vector3<f64>], order: [usize; 3]) -> String {
    let tilt = |i: usize, j: usize| tilt_deg(&points[i], &points[j]).unwrap_or(f64::NAN);
    format!(
        "vanishing point {} (as listed) was taken as the vertical one: the line through the other two is the most level ({:.1} deg from the image rows, against {:.1} and {:.1} deg); list the vertical one last",
        order[2] + 1,
        tilt(order[0], order[1]),
        tilt(order[0], order[2]),
        tilt(order[1], order[2]),
    )
}

/// The orthocentre of a triangle (intersection of its altitudes), or `None` when the vertices
/// are collinear.
#[must_use]
pub fn orthocentre(a: Vector2<f64>, b: Vector2<f64>, c: Vector2<f64>) -> Option<Vector2<f64>> {
    // (H - c).(b - a) = 0 and (H - a).(c - b) = 0.
    let m = Matrix2::new(b.x - a.x, b.y - a.y, c.x - b.x, c.y - b.y);
    let rhs = Vector2::new(c.dot(&(b - a)), a.dot(&(c - b)));
    let scale = (b - a).norm() * (c - b).norm();
    if m.determinant().abs() <= 1e-12 * scale {
        return None;
    }
    m.lu().solve(&rhs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn orthocentre_of_right_triangle_is_right_angle_vertex() {
        let h = orthocentre(
            Vector2::new(0.0, 0.0),
            Vector2::new(4.0, 0.0),
            Vector2::new(0.0, 3.0),
        )
        .unwrap();
        assert_relative_eq!(h, Vector2::new(0.0, 0.0), epsilon = 1e-12);
    }

    #[test]
    fn principal_point_outside_vanishing_circle_is_an_error() {
        let image = ImageSize {
            width: 100,
            height: 100,
        };
        let vps = [Vector2::new(60.0, 50.0), Vector2::new(90.0, 50.0)];
        let err = Calibration::from_vanishing_points(&vps, None, image).unwrap_err();
        assert!(matches!(err, MetrologyError::NoRealFocalLength(_)), "{err}");
    }

    #[test]
    fn obtuse_triangle_has_no_focal_length() {
        let image = ImageSize {
            width: 100,
            height: 100,
        };
        let vps = [
            Vector2::new(-100.0, 0.0),
            Vector2::new(100.0, 0.0),
            Vector2::new(0.0, 10.0),
        ];
        // Orthocentre of an obtuse triangle lies outside it, beyond VP3.
        let err = Calibration::from_vanishing_points(&vps, None, image).unwrap_err();
        assert!(matches!(err, MetrologyError::NoRealFocalLength(_)), "{err}");
    }
}
