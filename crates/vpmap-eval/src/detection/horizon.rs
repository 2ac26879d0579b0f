//! The horizon error of Barinova et al. 2010 and Lezama et al. 2014, the standard measure of
//! horizon detection on York Urban.
//!
//! Lines are homogeneous `[a, b, c]`, the points `(x, y)` (pixels, `x` right, `y` down) with
//! `a x + b y + c = 0`. The error of a detected horizon is the largest vertical distance between
//! it and the true horizon over the image's horizontal extent, `0 <= x <= width`, divided by the
//! image height (the distance between two lines is linear in `x`, so the largest is at `x = 0`
//! or `x = width`). A horizon that is vertical in the image, or missing, has an infinite error.
//!
//! The true horizon is the image of the plane orthogonal to the true vertical direction `v`:
//! the line `K^-T v` (Hartley and Zisserman, *Multiple View Geometry*, 2nd ed., 8.6.3).
//!
//! # References
//! * Barinova, Lempitsky, Tretiak, Kohli, "Geometric image parsing in man-made environments",
//!   ECCV 2010 (the error).
//! * Lezama, Grompone von Gioi, Randall, Morel, "Finding vanishing points via point alignments
//!   in image primal and dual domains", CVPR 2014 (the area under its cumulative curve up to
//!   0.25 image heights on York Urban).

use super::geom::{Vec3, cross};

/// The horizon AUC integrates the error curve from 0 to this, in image heights.
pub const HORIZON_AUC_LIMIT: f64 = 0.25;

/// A homogeneous image line `[a, b, c]`: `a x + b y + c = 0`, pixels.
pub type Line = [f64; 3];

/// The horizon `K^-T v` of a camera with focal length `focal_px`, principal point
/// `principal_point_px` (pixels) and vertical direction `vertical` (camera frame: x right,
/// y down, z forward; any length, either sign).
#[must_use]
pub fn horizon_of_vertical(vertical: Vec3, focal_px: f64, principal_point_px: [f64; 2]) -> Line {
    // K^-T = [[1/f, 0, 0], [0, 1/f, 0], [-cx/f, -cy/f, 1]].
    let [cx, cy] = principal_point_px;
    [
        vertical[0] / focal_px,
        vertical[1] / focal_px,
        vertical[2] - (cx * vertical[0] + cy * vertical[1]) / focal_px,
    ]
}

/// The line through two image points, pixels.
#[must_use]
pub fn line_through(p: [f64; 2], q: [f64; 2]) -> Line {
    cross([p[0], p[1], 1.0], [q[0], q[1], 1.0])
}

/// The image `y` of `line` at `x`, pixels (`None` for a vertical or degenerate line).
fn y_at(line: Line, x: f64) -> Option<f64> {
    let [a, b, c] = line;
    let scale = a.hypot(b);
    // A line within about 1e-12 rad of vertical has no usable y at x.
    (scale.is_finite() && scale > 0.0 && b.abs() > 1e-12 * scale)
        .then(|| -(a * x + c) / b)
        .filter(|y| y.is_finite())
}

/// The horizon error of `detected` against `truth` on an image of `size_px` = `[width,
/// height]` pixels, in image heights (see the module documentation); infinite when either line
/// is vertical or degenerate.
#[must_use]
pub fn horizon_error(detected: Line, truth: Line, size_px: [u32; 2]) -> f64 {
    let (width, height) = (f64::from(size_px[0]), f64::from(size_px[1]));
    if height <= 0.0 {
        return f64::INFINITY;
    }
    [0.0, width]
        .into_iter()
        .map(|x| match (y_at(detected, x), y_at(truth, x)) {
            (Some(a), Some(b)) => (a - b).abs(),
            _ => f64::INFINITY,
        })
        .fold(0.0, f64::max)
        / height
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_of_two_lines_worked_by_hand() {
        // Image 640 x 480. Truth: y = 200 + 0.1 x (through (0, 200) and (640, 264)).
        // Detected: y = 230 - 0.05 x (through (0, 230) and (640, 198)).
        // At x = 0: |230 - 200| = 30 px; at x = 640: |198 - 264| = 66 px. Error 66 / 480.
        let truth = line_through([0.0, 200.0], [640.0, 264.0]);
        let detected = line_through([100.0, 225.0], [300.0, 215.0]);
        let e = horizon_error(detected, truth, [640, 480]);
        assert!((e - 66.0 / 480.0).abs() < 1e-12, "{e}");
        // Symmetric, and zero against itself.
        assert!((horizon_error(truth, detected, [640, 480]) - e).abs() < 1e-12);
        assert!(horizon_error(truth, truth, [640, 480]) < 1e-12);
        // A vertical line is a miss.
        let vertical = line_through([10.0, 0.0], [10.0, 100.0]);
        assert!(horizon_error(vertical, truth, [640, 480]).is_infinite());
    }

    #[test]
    fn horizon_of_a_pitched_camera_worked_by_hand() {
        // A camera looking down by t (tan t = 0.1) sees the world's down direction as
        // v = (0, cos t, sin t). The horizon of a level camera is y = cy; looking down by t
        // lifts it by f tan t = 80 px.
        let (f, c) = (800.0, [320.0, 240.0]);
        let t = 0.1f64.atan();
        let v = [0.0, t.cos(), t.sin()];
        let h = horizon_of_vertical(v, f, c);
        let level = line_through([0.0, 240.0], [640.0, 240.0]);
        let e = horizon_error(h, level, [640, 480]);
        assert!((e - 80.0 / 480.0).abs() < 1e-12, "{e}");
        // Its y is 240 - 80 = 160 everywhere (no roll): the line y = 160.
        let lifted = line_through([0.0, 160.0], [640.0, 160.0]);
        assert!(horizon_error(h, lifted, [640, 480]) < 1e-12);
        // Scaling or flipping v does not move the line.
        let flipped = horizon_of_vertical([0.0, -3.0 * t.cos(), -3.0 * t.sin()], f, c);
        assert!(horizon_error(flipped, lifted, [640, 480]) < 1e-12);
    }
}
