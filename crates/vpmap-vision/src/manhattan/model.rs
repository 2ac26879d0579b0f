//! The camera model, normalised coordinates, and how well a segment points at a vanishing
//! point.
//!
//! # Model
//! Pinhole camera with square pixels and no skew, camera frame `x` right, `y` down, `z`
//! forward. A unit direction `d` in the camera frame vanishes at the homogeneous image point
//!
//! ```text
//!     v = K d,    K = [[f, 0, c_x], [0, f, c_y], [0, 0, 1]],
//! ```
//!
//! and an image line `l` (`l . x = 0`) back-projects to the plane through the camera centre
//! with normal `n = K^T l`. The three Manhattan directions are the columns of a rotation
//! `R = [d_1 d_2 d_3]`. Internally every image quantity is in *normalised* coordinates
//! `x_n = (x_px - image centre) / longer side`, which keeps homogeneous vectors well scaled;
//! pixel thresholds are stated in working-image pixels (after the internal downscale).
//!
//! # Consistency of a segment with a vanishing point
//! The angle `theta` between the segment and the line joining its midpoint `m` to the
//! vanishing point `v = (v_1, v_2, v_3)`: with the unit segment direction `u` and
//! `w = (v_1 - v_3 m_x, v_2 - v_3 m_y)`,
//!
//! ```text
//!     sin^2 theta = (u x w)^2 / |w|^2,        residual r = (L / 2) sin theta,
//! ```
//!
//! `r` being the distance of the segment's endpoints from that line (Tardif 2009). Both are
//! measured in the image, so they do not depend on the focal length being tried; `v` may lie
//! at infinity (`v_3 = 0`).

use nalgebra::{Matrix3, Vector3};

use crate::detection::Segment;

/// A segment in normalised coordinates.
#[derive(Clone, Copy, Debug)]
pub(super) struct Seg {
    pub(super) mid: [f64; 2],
    pub(super) dir: [f64; 2],
    pub(super) half_len: f64,
    /// Homogeneous line `(a, b, c)`, `a^2 + b^2 = 1`.
    pub(super) line: Vector3<f64>,
    pub(super) weight: f64,
}

impl Seg {
    pub(super) fn new(s: &Segment, norm: &Normaliser) -> Option<Self> {
        let p = norm.norm_from_px(s.start_px);
        let q = norm.norm_from_px(s.end_px);
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let len = dx.hypot(dy);
        if !(len.is_finite() && len > 1e-12) {
            return None;
        }
        let dir = [dx / len, dy / len];
        let mid = [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])];
        // Line through p with normal (-dir_y, dir_x).
        let (a, b) = (-dir[1], dir[0]);
        let line = Vector3::new(a, b, -(a * mid[0] + b * mid[1]));
        Some(Self {
            mid,
            dir,
            half_len: 0.5 * len,
            line,
            weight: len,
        })
    }

    /// `(u x w, |w|^2)` for the vanishing point `v`.
    #[inline]
    fn cross_and_norm2(&self, v: &Vector3<f64>) -> (f64, f64) {
        let wx = v.x - v.z * self.mid[0];
        let wy = v.y - v.z * self.mid[1];
        (self.dir[0] * wy - self.dir[1] * wx, wx * wx + wy * wy)
    }

    /// `sin^2` of the angle between the segment and the line from its midpoint to `v`
    /// (1 when `v` sits on the midpoint).
    #[inline]
    pub(super) fn sin2(&self, v: &Vector3<f64>) -> f64 {
        let (c, n2) = self.cross_and_norm2(v);
        if n2 <= 1e-24 { 1.0 } else { c * c / n2 }
    }

    /// Signed distance of the endpoints from the line through the midpoint and `v`
    /// (normalised units).
    #[inline]
    pub(super) fn residual(&self, v: &Vector3<f64>) -> f64 {
        let (c, n2) = self.cross_and_norm2(v);
        if n2 <= 1e-24 {
            self.half_len
        } else {
            self.half_len * c / n2.sqrt()
        }
    }
}

/// Pixels <-> normalised coordinates.
#[derive(Clone, Copy, Debug)]
pub(super) struct Normaliser {
    /// Image centre, input pixels.
    pub(super) centre: [f64; 2],
    /// Input pixels per normalised unit (the longer side).
    pub(super) unit_px: f64,
    /// Working pixels per normalised unit.
    pub(super) work_px: f64,
}

impl Normaliser {
    pub(super) fn new(size: [u32; 2], working_scale: f64) -> Self {
        let unit_px = f64::from(size[0].max(size[1]));
        Self {
            centre: [0.5 * f64::from(size[0]), 0.5 * f64::from(size[1])],
            unit_px,
            work_px: unit_px * working_scale,
        }
    }

    pub(super) fn norm_from_px(self, p: [f64; 2]) -> [f64; 2] {
        [
            (p[0] - self.centre[0]) / self.unit_px,
            (p[1] - self.centre[1]) / self.unit_px,
        ]
    }

    pub(super) fn px_from_norm(self, p: [f64; 2]) -> [f64; 2] {
        [
            p[0] * self.unit_px + self.centre[0],
            p[1] * self.unit_px + self.centre[1],
        ]
    }
}

/// Intrinsics in normalised coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Camera {
    pub(super) focal: f64,
    pub(super) pp: [f64; 2],
}

impl Camera {
    /// The vanishing point `K d` of direction `d`.
    #[inline]
    pub(super) fn vp(&self, d: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            self.focal * d.x + self.pp[0] * d.z,
            self.focal * d.y + self.pp[1] * d.z,
            d.z,
        )
    }

    /// The unit direction `K^-1 v` of the vanishing point `v`.
    pub(super) fn direction(&self, v: &Vector3<f64>) -> Option<Vector3<f64>> {
        Vector3::new(
            (v.x - self.pp[0] * v.z) / self.focal,
            (v.y - self.pp[1] * v.z) / self.focal,
            v.z,
        )
        .try_normalize(1e-300)
    }

    /// The unit normal `K^T l` of the plane back-projecting line `l`.
    #[inline]
    pub(super) fn plane_normal(&self, l: &Vector3<f64>) -> Option<Vector3<f64>> {
        Vector3::new(
            self.focal * l.x,
            self.focal * l.y,
            self.pp[0] * l.x + self.pp[1] * l.y + l.z,
        )
        .try_normalize(1e-300)
    }
}

/// Three orthogonal directions (columns) and the camera.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    pub(super) rot: Matrix3<f64>,
    pub(super) cam: Camera,
}

impl Frame {
    pub(super) fn vps(&self) -> [Vector3<f64>; 3] {
        [0, 1, 2].map(|k| self.cam.vp(&self.rot.column(k).into_owned()))
    }
}

/// The column closest to the image's y axis (largest `|d_y|`).
pub(crate) fn vertical_index(rot: &Matrix3<f64>) -> usize {
    (0..3)
        .max_by(|&i, &j| {
            let y = |k: usize| rot.get((1, k)).map_or(0.0, |v| v.abs());
            y(i).total_cmp(&y(j))
        })
        .unwrap_or(2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg(p: [f64; 2], q: [f64; 2]) -> Segment {
        Segment {
            start_px: p,
            end_px: q,
            strength: 1.0,
        }
    }

    #[test]
    fn a_segment_pointing_at_a_vanishing_point_has_zero_residual() {
        let norm = Normaliser::new([640, 480], 1.0);
        let s = Seg::new(&seg([100.0, 100.0], [200.0, 150.0]), &norm).unwrap();
        // The line continues through (300, 200) and (500, 300).
        let v = norm.norm_from_px([500.0, 300.0]);
        let v = Vector3::new(v[0], v[1], 1.0);
        assert!(s.sin2(&v) < 1e-20);
        assert!(s.residual(&v).abs() < 1e-12);
        // At infinity along the segment.
        assert!(s.sin2(&Vector3::new(2.0, 1.0, 0.0)) < 1e-20);
        // Perpendicular: sin^2 = 1.
        assert!((s.sin2(&Vector3::new(-1.0, 2.0, 0.0)) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn camera_maps_directions_and_points_both_ways() {
        let cam = Camera {
            focal: 1.1,
            pp: [0.02, -0.03],
        };
        let d = Vector3::new(0.3, -0.4, 0.8).normalize();
        let back = cam.direction(&cam.vp(&d)).unwrap();
        assert!((back - d).norm() < 1e-12);
        // A line through two vanishing points back-projects to the plane of both directions.
        let e = Vector3::new(-0.5, 0.1, 0.6).normalize();
        let l = cam.vp(&d).cross(&cam.vp(&e));
        let n = cam.plane_normal(&l).unwrap();
        assert!(n.dot(&d).abs() < 1e-12 && n.dot(&e).abs() < 1e-12);
    }
}
