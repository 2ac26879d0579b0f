//! The camera-matrix form of the reconstruction: a pixel's ray meets the floor plane.
//!
//! `K` is built from the principal point and focal length of the [`Calibration`]; the floor's
//! normal in the camera frame is `K^T l`, with `l = VP1 x VP2` the horizon line in homogeneous
//! coordinates (the image of the floor's line at infinity). The camera stands one unit (the
//! camera height) above the floor. This shares only the calibration with the side-view method,
//! so the two cross-check each other.

use nalgebra::{Matrix2, Vector2, Vector3};

use crate::calibration::Calibration;
use crate::error::{MetrologyError, Result};
use crate::reconstruct::{FloorProjection, require_below_horizon};
use crate::scene::PixelPoint;

/// The projective reconstruction for one calibrated camera.
#[derive(Debug, Clone)]
pub struct Projective<'a> {
    cal: &'a Calibration,
    /// Floor normal (up), camera frame (x right, y down, z forward), unit length.
    up: Vector3<f64>,
    /// World `+x` (right) in the camera frame.
    right: Vector3<f64>,
    /// World `+y` (horizontal forward) in the camera frame.
    forward: Vector3<f64>,
}

impl<'a> Projective<'a> {
    /// Build the camera frame from the calibration.
    #[must_use]
    pub fn new(cal: &'a Calibration) -> Self {
        let o = cal.principal_point_px();
        let f = cal.focal_px;
        let v1 = cal.vanishing_points_px[0];
        let v2 = cal.vanishing_points_px[1];
        // Homogeneous points scaled to keep the numbers near 1.
        let a = Vector3::new((v1.x - o.x) / f, (v1.y - o.y) / f, 1.0);
        let b = Vector3::new((v2.x - o.x) / f, (v2.y - o.y) / f, 1.0);
        // In normalised coordinates K = I, so the plane normal is the line itself.
        let mut up = a.cross(&b).normalize();
        // The camera is upright (|pitch| < 90 degrees): up has a negative image-y component.
        if up.y > 0.0 {
            up = -up;
        }
        let z = Vector3::new(0.0, 0.0, 1.0);
        let forward = (z - up * z.dot(&up)).normalize();
        let right = forward.cross(&up);
        Self {
            cal,
            up,
            right,
            forward,
        }
    }

    /// The ray through a pixel, camera frame.
    fn ray(&self, p: PixelPoint) -> Vector3<f64> {
        let o = self.cal.principal_point_px();
        let f = self.cal.focal_px;
        Vector3::new((p[0] - o.x) / f, (p[1] - o.y) / f, 1.0)
    }

    /// Where a pixel's ray meets the floor, camera frame.
    fn floor_point_camera(&self, field: &str, p: PixelPoint) -> Result<Vector3<f64>> {
        require_below_horizon(self.cal, field, p)?;
        let r = self.ray(p);
        let down = r.dot(&self.up);
        if down >= 0.0 {
            return Err(MetrologyError::NotBelowHorizon {
                field: field.to_owned(),
                x: p[0],
                y: p[1],
                distance_px: 0.0,
                side: "on",
            });
        }
        Ok(r * (-1.0 / down))
    }

    /// Camera-frame point to map coordinates (station point at the origin).
    fn to_map(&self, p: Vector3<f64>) -> Vector2<f64> {
        let from_station = p + self.up;
        Vector2::new(
            from_station.dot(&self.right),
            from_station.dot(&self.forward),
        )
    }

    /// Pitch implied by the floor normal, radians (positive looking down).
    #[must_use]
    pub fn pitch_rad(&self) -> f64 {
        (-self.up.z).asin()
    }
}

impl FloorProjection for Projective<'_> {
    fn floor_point(&self, field: &str, image_px: PixelPoint) -> Result<Vector2<f64>> {
        Ok(self.to_map(self.floor_point_camera(field, image_px)?))
    }

    /// The vertical line through the base's floor point and the top pixel's ray: their closest
    /// approach (least squares in the two unknowns, exact for exact input).
    fn edge_height(&self, field: &str, base_px: PixelPoint, top_px: PixelPoint) -> Result<f64> {
        let base = self.floor_point_camera(field, base_px)?;
        let r = self.ray(top_px);
        // minimise |base + z up - s r|^2 over (z, s).
        let ur = self.up.dot(&r);
        let m = Matrix2::new(1.0, -ur, ur, -r.dot(&r));
        let rhs = Vector2::new(-base.dot(&self.up), -base.dot(&r));
        let sol = m.lu().solve(&rhs).ok_or_else(|| MetrologyError::Degenerate {
            field: field.to_owned(),
            reason: format!(
                "the top point ({:.3}, {:.3}) lies on the vertical through the base's vanishing direction",
                top_px[0], top_px[1]
            ),
        })?;
        Ok(sol.x)
    }

    fn box_footprint(
        &self,
        field: &str,
        near_px: PixelPoint,
        right_px: PixelPoint,
        left_px: PixelPoint,
    ) -> Result<[Vector2<f64>; 4]> {
        let near = self.floor_point(&format!("{field}.base.near"), near_px)?;
        let right = self.floor_point(&format!("{field}.base.right"), right_px)?;
        let left = self.floor_point(&format!("{field}.base.left"), left_px)?;
        Ok([near, right, right + left - near, left])
    }
}
