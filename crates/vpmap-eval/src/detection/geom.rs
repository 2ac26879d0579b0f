//! Small 3-vector helpers for camera-frame directions (x right, y down, z forward), used by
//! `eval-detect` to score detections independently of the vision crate's own geometry.

/// A 3-vector in the camera frame.
pub type Vec3 = [f64; 3];

/// Dot product.
#[must_use]
pub fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Cross product.
#[must_use]
pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Euclidean length.
#[must_use]
pub fn norm(a: Vec3) -> f64 {
    dot(a, a).sqrt()
}

/// `a` times `s`.
#[must_use]
pub fn scale(a: Vec3, s: f64) -> Vec3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `a / |a|`, or `None` for a (nearly) zero or non-finite vector.
#[must_use]
pub fn normalize(a: Vec3) -> Option<Vec3> {
    let n = norm(a);
    (n.is_finite() && n > 1e-12).then(|| scale(a, 1.0 / n))
}

/// Angle between the lines along `a` and `b` (sign-free), degrees, in `[0, 90]`.
#[must_use]
pub fn line_angle_deg(a: Vec3, b: Vec3) -> f64 {
    // atan2 of |a x b| and |a . b| is accurate at small angles, unlike acos.
    norm(cross(a, b)).atan2(dot(a, b).abs()).to_degrees()
}

/// The camera-frame direction of image point `p` for focal length `f` and principal point `c`.
#[must_use]
pub fn direction_of_pixel(p: [f64; 2], f: f64, c: [f64; 2]) -> Option<Vec3> {
    normalize([(p[0] - c[0]) / f, (p[1] - c[1]) / f, 1.0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixel_direction_and_angles() {
        let (f, c) = (700.0, [320.0, 240.0]);
        let d = direction_of_pixel([-1500.0, 400.0], f, c).unwrap_or_default();
        // Back to the image: c + f (dx, dy) / dz.
        let p = [c[0] + f * d[0] / d[2], c[1] + f * d[1] / d[2]];
        assert!((p[0] + 1500.0).abs() < 1e-9 && (p[1] - 400.0).abs() < 1e-9);
        // Sign-free angles.
        assert!(line_angle_deg([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]) < 1e-12);
        assert!((line_angle_deg([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]) - 90.0).abs() < 1e-12);
    }
}
