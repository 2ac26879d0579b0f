//! Small 3-vector helpers for camera-frame directions (x right, y down, z forward).

pub type Vec3 = [f64; 3];

pub fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub fn norm(a: Vec3) -> f64 {
    dot(a, a).sqrt()
}

pub fn scale(a: Vec3, s: f64) -> Vec3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

pub fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a / |a|`, or `None` for a (nearly) zero or non-finite vector.
pub fn normalize(a: Vec3) -> Option<Vec3> {
    let n = norm(a);
    (n.is_finite() && n > 1e-12).then(|| scale(a, 1.0 / n))
}

/// Angle between the lines along `a` and `b` (sign-free), degrees, in `[0, 90]`.
pub fn line_angle_deg(a: Vec3, b: Vec3) -> f64 {
    // atan2 of |a x b| and |a . b| is accurate at small angles, unlike acos.
    norm(cross(a, b)).atan2(dot(a, b).abs()).to_degrees()
}

/// Rotate `v` about the unit axis `k` by `angle_rad` (Rodrigues' formula).
pub fn rotate(v: Vec3, k: Vec3, angle_rad: f64) -> Vec3 {
    let (s, c) = angle_rad.sin_cos();
    add(
        add(scale(v, c), scale(cross(k, v), s)),
        scale(k, dot(k, v) * (1.0 - c)),
    )
}

/// The smallest rotation taking unit `from` to unit `to`, applied to `v`.
pub fn rotate_like(v: Vec3, from: Vec3, to: Vec3) -> Vec3 {
    match normalize(cross(from, to)) {
        Some(axis) => rotate(v, axis, norm(cross(from, to)).atan2(dot(from, to))),
        None => v,
    }
}

/// The camera-frame direction of image point `p` for focal length `f` and principal point `c`.
pub fn direction_of_pixel(p: [f64; 2], f: f64, c: [f64; 2]) -> Option<Vec3> {
    normalize([(p[0] - c[0]) / f, (p[1] - c[1]) / f, 1.0])
}

/// The image point of direction `d` (`None` when it is parallel to the image plane).
pub fn pixel_of_direction(d: Vec3, f: f64, c: [f64; 2]) -> Option<[f64; 2]> {
    (d[2].abs() > 0.0)
        .then(|| [c[0] + f * d[0] / d[2], c[1] + f * d[1] / d[2]])
        .filter(|p| p[0].is_finite() && p[1].is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotate_like_takes_one_vector_to_the_other() {
        let from = normalize([0.1, 0.9, 0.2]).unwrap_or_default();
        let to = normalize([0.1, 0.95, 0.0]).unwrap_or_default();
        let r = rotate_like(from, from, to);
        assert!(line_angle_deg(r, to) < 1e-9, "{r:?}");
        // Vectors perpendicular to both stay put.
        let k = normalize(cross(from, to)).unwrap_or_default();
        assert!(line_angle_deg(rotate_like(k, from, to), k) < 1e-9);
    }

    #[test]
    fn pixel_and_direction_round_trip() {
        let (f, c) = (700.0, [320.0, 240.0]);
        let d = direction_of_pixel([-1500.0, 400.0], f, c).unwrap_or_default();
        let p = pixel_of_direction(d, f, c).unwrap_or_default();
        assert!((p[0] + 1500.0).abs() < 1e-9 && (p[1] - 400.0).abs() < 1e-9);
        // Sign-free angles.
        assert!(line_angle_deg([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]) < 1e-12);
        assert!((line_angle_deg([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]) - 90.0).abs() < 1e-12);
    }
}
