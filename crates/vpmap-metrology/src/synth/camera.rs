//! The synthetic pinhole camera above a flat floor: its axes, and the projections of world
//! points and directions to pixels and of pixels back to the floor.

use nalgebra::{Vector2, Vector3};

use crate::scene::ImageSize;

/// A pinhole camera above a flat floor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PinholeCamera {
    /// Image size.
    pub image: ImageSize,
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Principal point, pixels.
    pub principal_point_px: Vector2<f64>,
    /// Height above the floor, metres.
    pub height_m: f64,
    /// Pitch, radians, positive looking down.
    pub pitch_rad: f64,
    /// Roll, radians.
    pub roll_rad: f64,
}

impl PinholeCamera {
    /// The camera axes in the world: `(right, down, forward)`.
    #[must_use]
    pub fn axes(&self) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        let (s, c) = self.pitch_rad.sin_cos();
        let forward = Vector3::new(0.0, c, -s);
        let right0 = Vector3::new(1.0, 0.0, 0.0);
        let down0 = Vector3::new(0.0, -s, -c);
        let (sr, cr) = (-self.roll_rad).sin_cos();
        let right = right0 * cr + down0 * sr;
        let down = -right0 * sr + down0 * cr;
        (right, down, forward)
    }

    /// Depth of a world point along the viewing direction (positive in front).
    #[must_use]
    pub fn depth(&self, world: Vector3<f64>) -> f64 {
        let (_, _, f) = self.axes();
        (world - self.centre()).dot(&f)
    }

    /// The camera centre in the world.
    #[must_use]
    pub fn centre(&self) -> Vector3<f64> {
        Vector3::new(0.0, 0.0, self.height_m)
    }

    /// Project a world point to pixels (`None` behind the camera).
    #[must_use]
    pub fn project(&self, world: Vector3<f64>) -> Option<Vector2<f64>> {
        let (r, d, f) = self.axes();
        let v = world - self.centre();
        let z = v.dot(&f);
        if z <= 1e-12 {
            return None;
        }
        Some(self.principal_point_px + Vector2::new(v.dot(&r), v.dot(&d)) * (self.focal_px / z))
    }

    /// Vanishing point of a world direction (`None` when parallel to the image plane).
    #[must_use]
    pub fn vanishing_point(&self, direction: Vector3<f64>) -> Option<Vector2<f64>> {
        let (r, d, f) = self.axes();
        let z = direction.dot(&f);
        if z.abs() <= 1e-12 {
            return None;
        }
        Some(
            self.principal_point_px
                + Vector2::new(direction.dot(&r), direction.dot(&d)) * (self.focal_px / z),
        )
    }

    /// The floor point seen at a pixel (`None` at or above the horizon).
    #[must_use]
    pub fn floor_point(&self, pixel: Vector2<f64>) -> Option<Vector2<f64>> {
        let (r, d, f) = self.axes();
        let q = (pixel - self.principal_point_px) / self.focal_px;
        let ray = r * q.x + d * q.y + f;
        if ray.z >= -1e-12 {
            return None;
        }
        let t = -self.height_m / ray.z;
        Some(Vector2::new(ray.x * t, ray.y * t))
    }

    /// Whether a pixel lies inside the image.
    #[must_use]
    pub fn in_image(&self, p: Vector2<f64>) -> bool {
        p.x >= 0.0
            && p.y >= 0.0
            && p.x <= f64::from(self.image.width)
            && p.y <= f64::from(self.image.height)
    }
}
