//! Resolving a scene's vanishing points: given points, directions, or the least-squares
//! intersection of clicked segments.

use nalgebra::{Matrix3, Vector2, Vector3};

use super::types::{ImageSize, Scene};
use crate::error::{MetrologyError, Result};

impl Scene {
    /// Whether the vanishing points' order was set by a tool that names each one: some are
    /// given only by segments (drawn on the page under their names, or written by
    /// `vpmap eval`). Vanishing points all given as points or directions may come in any
    /// data set's order ([`crate::calibration::reading`]).
    #[must_use]
    pub fn vanishing_points_labelled(&self) -> bool {
        self.vanishing_points
            .iter()
            .any(|v| v.point.is_none() && v.direction.is_none())
    }

    /// The vanishing points in homogeneous pixel coordinates `(x, y, w)`, in the order given:
    /// a given point as `(x, y, 1)`, a direction as `(dx, dy, 0)`, segments by their
    /// least-squares intersection ([`intersect_segments`]) as `(x, y, 1)`. Which one is
    /// vertical is decided by [`crate::calibration::vertical_index`].
    ///
    /// # Errors
    /// [`MetrologyError::ParallelLines`] when a set of segments meets at infinity.
    pub fn resolve_vanishing_points(&self) -> Result<Vec<Vector3<f64>>> {
        let n = self.vanishing_points.len();
        self.vanishing_points
            .iter()
            .enumerate()
            .map(|(i, vp)| {
                if let Some(d) = vp.direction {
                    return Ok(Vector3::new(d[0], d[1], 0.0));
                }
                if let Some(p) = vp.point {
                    return Ok(Vector3::new(p[0], p[1], 1.0));
                }
                intersect_segments(&vp.lines, self.image)
                    .map(|p| Vector3::new(p.x, p.y, 1.0))
                    .map_err(|fit| match fit {
                    SegmentFit::Parallel => MetrologyError::ParallelLines {
                        index: i + 1,
                        hint: if n == 3 {
                            "; for a level camera (vertical edges parallel in the photo) give the vertical vanishing point as a `direction`, or only the two horizontal ones".to_owned()
                        } else {
                            String::new()
                        },
                    },
                    SegmentFit::Collinear => MetrologyError::InvalidField {
                        field: format!("vanishing_points[{i}].lines"),
                        reason: "the segments lie on one line, so they do not fix a point: click edges on different lines that run to the vanishing point".to_owned(),
                    },
                    SegmentFit::Overflow => MetrologyError::InvalidField {
                        field: format!("vanishing_points[{i}].lines"),
                        reason: "the segments' coordinates are too large for their intersection to be computed: give them in pixels of the image".to_owned(),
                    },
                })
            })
            .collect()
    }
}

/// The least-squares intersection of the lines through two or more segments.
///
/// Each segment `[x1, y1, x2, y2]` gives a homogeneous line, normalised so that its value at a
/// point is the point's distance to it; the intersection minimises the sum of squared
/// distances in homogeneous form (smallest eigenvector of the 3x3 normal matrix), computed in
/// coordinates centred on the image and scaled by its diagonal for conditioning.
///
/// # Errors
/// [`SegmentFit::Parallel`] when the lines meet at infinity (further than 1e7 image diagonals
/// away), [`SegmentFit::Collinear`] when they all lie on one line (no single point).
///
/// # Example
/// ```
/// use vpmap_metrology::scene::{intersect_segments, ImageSize};
/// let image = ImageSize { width: 100, height: 100 };
/// let vp = intersect_segments(&[[0.0, 0.0, 1.0, 1.0], [10.0, 0.0, 9.0, 1.0]], image).unwrap();
/// assert!((vp.x - 5.0).abs() < 1e-9 && (vp.y - 5.0).abs() < 1e-9);
/// ```
pub fn intersect_segments(
    segments: &[[f64; 4]],
    image: ImageSize,
) -> std::result::Result<Vector2<f64>, SegmentFit> {
    let c = image.centre();
    let s = image.diagonal();
    let mut m = Matrix3::<f64>::zeros();
    for seg in segments {
        let a = Vector3::new((seg[0] - c.x) / s, (seg[1] - c.y) / s, 1.0);
        let b = Vector3::new((seg[2] - c.x) / s, (seg[3] - c.y) / s, 1.0);
        let l = a.cross(&b);
        let norm = l.x.hypot(l.y);
        if norm <= f64::EPSILON {
            continue;
        }
        let l = l / norm;
        m += l * l.transpose();
    }
    let eig = crate::linalg::symmetric_eigen(m).ok_or(SegmentFit::Overflow)?;
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    // Two vanishing eigenvalues: every line is the same line.
    if eig.eigenvalues[order[1]] <= 1e-12 * eig.eigenvalues.sum().max(f64::MIN_POSITIVE) {
        return Err(SegmentFit::Collinear);
    }
    let v = eig.eigenvectors.column(order[0]);
    if v.z.abs() < 1e-7 * v.x.hypot(v.y) {
        return Err(SegmentFit::Parallel);
    }
    Ok(Vector2::new(v.x / v.z * s + c.x, v.y / v.z * s + c.y))
}

/// Why a set of segments fixes no vanishing point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentFit {
    /// The lines are parallel: they meet only at infinity.
    Parallel,
    /// The segments all lie on one line.
    Collinear,
    /// The lines' coordinates are so large that their intersection overflows.
    Overflow,
}

/// The fixed chart in which a vanishing point's uncertainty is stated
/// ([`VanishingPointSpec::covariance_deg2`](super::VanishingPointSpec::covariance_deg2)): a
/// homogeneous pixel point `(x, y, w)` is seen as the unit direction
/// `((x - c_x w) / f, (y - c_y w) / f, w)` from a reference camera of focal length `f` and
/// principal point `c`, and a small change of it is measured in radians along two axes: *across*
/// (`z x d`, perpendicular to the line from the principal point to the vanishing point) and
/// *radial* (`across x d`, along that line, away from the principal point). The chart is a
/// way of writing the point, fixed by the scene (its `focal_px`, else the image diagonal, and
/// its `principal_point`, else the image centre), not the fitted camera: a point far off the
/// image, or at infinity, has a finite covariance in it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VpChart {
    /// Reference focal length, pixels.
    pub focal_px: f64,
    /// Reference principal point, pixels.
    pub centre_px: Vector2<f64>,
}

impl VpChart {
    /// The chart a scene states its vanishing points' covariances in.
    #[must_use]
    pub fn of_scene(scene: &Scene) -> Self {
        Self {
            focal_px: scene
                .focal_px
                .filter(|f| f.is_finite() && *f > 0.0)
                .unwrap_or_else(|| scene.image.diagonal()),
            centre_px: scene
                .principal_point
                .map_or_else(|| scene.image.centre(), |p| Vector2::new(p[0], p[1])),
        }
    }

    /// The unit direction of homogeneous pixel point `v` (sign as given; `None` for a zero or
    /// non-finite vector).
    #[must_use]
    pub fn direction(&self, v: Vector3<f64>) -> Option<Vector3<f64>> {
        let d = Vector3::new(
            (v.x - self.centre_px.x * v.z) / self.focal_px,
            (v.y - self.centre_px.y * v.z) / self.focal_px,
            v.z,
        );
        let n = d.norm();
        (n.is_finite() && n > 0.0).then(|| d / n)
    }

    /// The *across* and *radial* unit axes at unit direction `d`.
    #[must_use]
    pub fn axes(d: Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
        let a = Vector3::z().cross(&d);
        let across = if a.norm() > 1e-9 {
            a.normalize()
        } else {
            // On the optical axis: image x.
            let x = Vector3::x();
            (x - d * d.dot(&x)).normalize()
        };
        (across, across.cross(&d))
    }

    /// The offset of homogeneous pixel point `predicted` from `given`, radians, along the
    /// *across* and *radial* axes at `given` (the sign of `predicted` chosen to face `given`:
    /// a vanishing point is a line through the camera, not a ray). `None` when either point
    /// has no direction.
    #[must_use]
    pub fn offset_rad(&self, given: Vector3<f64>, predicted: Vector3<f64>) -> Option<[f64; 2]> {
        let g = self.direction(given)?;
        let mut p = self.direction(predicted)?;
        if p.dot(&g) < 0.0 {
            p = -p;
        }
        let (across, radial) = Self::axes(g);
        // The tangent-plane coordinates of `p` seen from `g` (gnomonic, exact in angle along
        // each axis for small offsets and monotone for large ones).
        let along = p.dot(&g).max(1e-12);
        Some([
            (p.dot(&across) / along).atan(),
            (p.dot(&radial) / along).atan(),
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chart_offsets_are_angles_about_the_principal_point() {
        let chart = VpChart {
            focal_px: 500.0,
            centre_px: Vector2::new(320.0, 240.0),
        };
        // A point 500 px right of the centre is 45 degrees out; moving it 1 degree further
        // out is radial, moving it about the optical axis is across.
        let given = Vector3::new(820.0, 240.0, 1.0);
        let out = Vector3::new(320.0 + 500.0 * 46f64.to_radians().tan(), 240.0, 1.0);
        let r = chart.offset_rad(given, out).unwrap_or_default();
        assert!(r[0].abs() < 1e-12, "{r:?}");
        assert!((r[1] - 1f64.to_radians()).abs() < 1e-12, "{r:?}");
        // Turned 1 degree about the optical axis: across, by asin(sin 45 deg sin 1 deg).
        let t = 1f64.to_radians();
        let turned = Vector3::new(320.0 + 500.0 * t.cos(), 240.0 + 500.0 * t.sin(), 1.0);
        let r = chart.offset_rad(given, turned).unwrap_or_default();
        assert!(r[1].abs() < 1e-4, "{r:?}");
        let expected = (45f64.to_radians().sin() * t.sin()).asin();
        assert!((r[0] - expected).abs() < 1e-6, "{r:?} vs {expected}");
        // A point at infinity and a far point along the same image direction agree.
        let inf = Vector3::new(0.0, 1.0, 0.0);
        let far = Vector3::new(320.0, 240.0 + 1e12, 1.0);
        let r = chart.offset_rad(inf, far).unwrap_or_default();
        assert!(r[0].abs() < 1e-9 && r[1].abs() < 1e-9, "{r:?}");
        // Opposite signs of one homogeneous point are the same vanishing point.
        let r = chart.offset_rad(given, -given).unwrap_or_default();
        assert!(r[0].abs() < 1e-12 && r[1].abs() < 1e-12, "{r:?}");
    }
}
