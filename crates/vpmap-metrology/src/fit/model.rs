//! The fit's model: a pinhole camera one unit above the floor, the room's two horizontal
//! directions, and every object as parameters; the residuals of every clicked point and
//! vanishing-point segment in pixels.
//!
//! Frame: the map frame of [`crate::reconstruct`] (station point at the origin, `+y` the
//! camera's horizontal viewing direction, `+z` up, unit the camera height), so the camera
//! centre is `(0, 0, 1)`.

use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};

use crate::camera::rotation_map_from_camera;
use crate::scene::{BoxView, DivisionModel, PixelPoint, VpChart};

/// The camera as the model sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Camera {
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Principal point, pixels.
    pub principal_point_px: Vector2<f64>,
    /// Pitch, radians, positive looking down.
    pub pitch_rad: f64,
    /// Angle of the room's first horizontal direction (the scene's first vanishing point)
    /// from `+x`, radians.
    pub room_yaw_rad: f64,
    /// Camera-from-map rotation (the transpose of [`rotation_map_from_camera`]).
    from_map: Matrix3<f64>,
    /// `room_yaw_rad`'s sine and cosine.
    room_yaw_sin_cos: (f64, f64),
}

impl Camera {
    /// The camera for parameters `x` (focal length px, pitch, roll, room yaw (radians), then the
    /// principal point px); `fixed_pp` when the principal point is not among them.
    pub fn from_params(x: &[f64], fixed_pp: Option<Vector2<f64>>) -> Self {
        let principal_point_px = match fixed_pp {
            Some(p) => p,
            None => Vector2::new(x[4], x[5]),
        };
        let r = rotation_map_from_camera(x[1], x[2]);
        let map_from_camera = Matrix3::from_fn(|i, j| r[i][j]);
        Self {
            focal_px: x[0],
            principal_point_px,
            pitch_rad: x[1],
            room_yaw_rad: x[3],
            from_map: map_from_camera.transpose(),
            room_yaw_sin_cos: x[3].sin_cos(),
        }
    }

    /// The room's horizontal direction `k` (0 or 1) in the map frame.
    pub fn room_axis(&self, k: usize) -> Vector2<f64> {
        let (s, c) = self.room_yaw_sin_cos;
        if k == 0 {
            Vector2::new(c, s)
        } else {
            Vector2::new(-s, c)
        }
    }

    /// A map direction's vanishing point, homogeneous pixel coordinates.
    pub fn vanishing_point(&self, direction: Vector3<f64>) -> Vector3<f64> {
        let d = self.from_map * direction;
        Vector3::new(
            self.focal_px * d.x + self.principal_point_px.x * d.z,
            self.focal_px * d.y + self.principal_point_px.y * d.z,
            d.z,
        )
    }

    /// The pixel a map point projects to, or `None` when it is not in front of the camera.
    pub fn project(&self, point: Vector3<f64>) -> Option<Vector2<f64>> {
        let c = self.from_map * (point - Vector3::new(0.0, 0.0, 1.0));
        if c.z <= 1e-9 {
            return None;
        }
        Some(self.principal_point_px + Vector2::new(c.x, c.y) * (self.focal_px / c.z))
    }

    /// The ray through a pixel, map frame (not normalised).
    pub fn ray(&self, pixel: Vector2<f64>) -> Vector3<f64> {
        let q = (pixel - self.principal_point_px) / self.focal_px;
        self.from_map.transpose() * Vector3::new(q.x, q.y, 1.0)
    }

    /// A pixel's signed distance below the camera's horizon, pixels (negative above it).
    pub fn below_horizon_px(&self, pixel: Vector2<f64>) -> f64 {
        let up = self.from_map.transpose().row(2).transpose();
        let q = (pixel - self.principal_point_px) / self.focal_px;
        let along = up.x.hypot(up.y);
        if along <= f64::MIN_POSITIVE {
            return f64::INFINITY;
        }
        -(up.x * q.x + up.y * q.y + up.z) * self.focal_px / along
    }

    /// Where a pixel's ray meets the floor, or `None` at or above the horizon.
    pub fn floor_point(&self, pixel: Vector2<f64>) -> Option<Vector2<f64>> {
        let r = self.ray(pixel);
        if r.z >= -1e-12 {
            return None;
        }
        let t = -1.0 / r.z;
        Some(Vector2::new(r.x * t, r.y * t))
    }
}

/// One clicked corner of a box: its place `(i, j, k)` and the pixel.
#[derive(Debug, Clone)]
pub(crate) struct CornerClick {
    /// Place on the box's floor axes and level (`k = 1` at the top).
    pub place: (u8, u8, u8),
    /// The clicked pixel.
    pub pixel: Vector2<f64>,
    /// The scene's name of the point, e.g. `base.near`.
    pub name: String,
}

/// How a box sits on the room's axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BoxAxes {
    /// Which room direction (0 or 1) the box's first axis runs along.
    pub first: usize,
    /// Sign of the first axis.
    pub sign1: f64,
    /// Sign of the second axis.
    pub sign2: f64,
}

/// An object of the model.
#[derive(Debug, Clone)]
pub(crate) enum Part {
    /// A box: parameters origin corner `x, y`, sides `a, b`, then `h` when it has top
    /// clicks, then its own yaw offset (radians) when it has one.
    Box {
        view: BoxView,
        clicks: Vec<CornerClick>,
        axes: BoxAxes,
        has_top: bool,
        own_yaw: bool,
    },
    /// A footprint prism: parameters the vertices `x, y` in order, then `h` when it has a top
    /// click above vertex `above`.
    Footprint {
        vertices: Vec<Vector2<f64>>,
        top: Option<(usize, Vector2<f64>)>,
    },
    /// A floor point (the ends of a known floor distance): parameters `x, y`.
    FloorPoint { pixel: Vector2<f64> },
}

impl Part {
    /// Number of parameters.
    pub fn len(&self) -> usize {
        match self {
            Part::Box {
                has_top, own_yaw, ..
            } => 4 + usize::from(*has_top) + usize::from(*own_yaw),
            Part::Footprint { vertices, top } => 2 * vertices.len() + usize::from(top.is_some()),
            Part::FloorPoint { .. } => 2,
        }
    }

    /// Number of residuals.
    pub fn residual_count(&self) -> usize {
        match self {
            Part::Box { clicks, .. } => 2 * clicks.len(),
            Part::Footprint { vertices, top } => 2 * (vertices.len() + usize::from(top.is_some())),
            Part::FloorPoint { .. } => 2,
        }
    }

    /// A box's unit floor axes `e1`, `e2` for camera `cam` and parameters `p`.
    pub fn box_axes(cam: &Camera, axes: BoxAxes, yaw: f64) -> (Vector2<f64>, Vector2<f64>) {
        let u1 = cam.room_axis(axes.first) * axes.sign1;
        let u2 = cam.room_axis(1 - axes.first) * axes.sign2;
        if yaw == 0.0 {
            // Along the room's directions (the rotation below by 0 gives the same bits).
            return (u1, u2);
        }
        let (s, c) = yaw.sin_cos();
        let rot = |u: Vector2<f64>| Vector2::new(c * u.x - s * u.y, s * u.x + c * u.y);
        (rot(u1), rot(u2))
    }

    /// The map point of a box corner `(i, j, k)`.
    pub fn box_corner(
        cam: &Camera,
        axes: BoxAxes,
        own_yaw: bool,
        has_top: bool,
        p: &[f64],
        place: (u8, u8, u8),
    ) -> Vector3<f64> {
        let yaw = if own_yaw {
            p[4 + usize::from(has_top)]
        } else {
            0.0
        };
        let (e1, e2) = Self::box_axes(cam, axes, yaw);
        let floor = Vector2::new(p[0], p[1])
            + e1 * (f64::from(place.0) * p[2])
            + e2 * (f64::from(place.1) * p[3]);
        let h = if has_top { p[4] } else { 0.0 };
        Vector3::new(floor.x, floor.y, f64::from(place.2) * h)
    }

    /// The colouring of a footprint's Jacobian ([`super::blocks::Coloring`]): its vertices' x
    /// together, their y together, and the height. Vertex `k`'s residuals (rows `2k`, `2k + 1`)
    /// depend on its `x`, `y` alone; the top click's on vertex `above`'s and the height. `None`
    /// for the other parts, whose parameters each reach most of their residuals.
    pub fn coloring(&self) -> Option<super::blocks::Coloring> {
        let Part::Footprint { vertices, top } = self else {
            return None;
        };
        let n = vertices.len();
        let rows = self.residual_count();
        // In the x and the y colours, a residual's vertex is its column's index in the colour.
        let vertex_of_row: Vec<Option<usize>> = (0..rows)
            .map(|r| match top {
                Some((above, _)) if r >= 2 * n => Some(*above),
                _ => Some(r / 2),
            })
            .collect();
        let mut colors = vec![
            (0..n).map(|k| 2 * k).collect::<Vec<_>>(),
            (0..n).map(|k| 2 * k + 1).collect(),
        ];
        let mut owners = vec![vertex_of_row.clone(), vertex_of_row];
        if top.is_some() {
            colors.push(vec![2 * n]);
            owners.push((0..rows).map(|r| (r >= 2 * n).then_some(0)).collect());
        }
        Some(super::blocks::Coloring { colors, owners })
    }

    /// The residuals (predicted minus clicked, pixels) into `out`; `false` when a point falls
    /// behind the camera.
    pub fn residuals(&self, cam: &Camera, p: &[f64], out: &mut [f64]) -> bool {
        let mut put = |k: usize, world: Vector3<f64>, pixel: Vector2<f64>| -> bool {
            match cam.project(world) {
                Some(q) => {
                    out[2 * k] = q.x - pixel.x;
                    out[2 * k + 1] = q.y - pixel.y;
                    true
                }
                None => false,
            }
        };
        match self {
            Part::Box {
                clicks,
                axes,
                has_top,
                own_yaw,
                ..
            } => clicks.iter().enumerate().all(|(k, c)| {
                put(
                    k,
                    Self::box_corner(cam, *axes, *own_yaw, *has_top, p, c.place),
                    c.pixel,
                )
            }),
            Part::Footprint { vertices, top } => {
                let n = vertices.len();
                let ok = vertices
                    .iter()
                    .enumerate()
                    .all(|(k, v)| put(k, Vector3::new(p[2 * k], p[2 * k + 1], 0.0), *v));
                match top {
                    Some((above, pixel)) => {
                        ok && put(
                            n,
                            Vector3::new(p[2 * above], p[2 * above + 1], p[2 * n]),
                            *pixel,
                        )
                    }
                    None => ok,
                }
            }
            Part::FloorPoint { pixel } => put(0, Vector3::new(p[0], p[1], 0.0), *pixel),
        }
    }
}

/// Evidence for one vanishing point, pixels, or the priors on the camera's intrinsics (the
/// camera-only residuals of the fit).
#[derive(Debug, Clone)]
pub(crate) enum VpEvidence {
    /// Segments whose lines run to it.
    Lines(Vec<[f64; 4]>),
    /// The point with its covariance (a scene's `covariance_deg2`, as `vpmap detect` writes
    /// it, or [`super::GIVEN_POINT_SD_DEG`] for a point given without one, a fact): its
    /// residual is the offset of the predicted point in the scene's [`VpChart`], whitened,
    /// times the click noise `scale_px`, so that it weighs against the clicks as its
    /// covariance says.
    Measured {
        /// Homogeneous pixel coordinates (`w = 0` for a direction at infinity).
        at: Vector3<f64>,
        /// The chart of the covariance.
        chart: VpChart,
        /// `W` with `W^T W` the inverse covariance, per radian.
        whitening: Matrix2<f64>,
        /// The click noise the residual is expressed in, pixels.
        scale_px: f64,
    },
    /// Priors on the focal length and principal point (the scene's `focal_sd_px` and
    /// `principal_point_sd_px`): `(value - prior) / sd`, times the click noise `scale_px`.
    Intrinsics {
        /// The focal length's prior and standard deviation, pixels.
        focal_px: Option<(f64, f64)>,
        /// The principal point's prior and standard deviation (each coordinate), pixels.
        principal_point_px: Option<(Vector2<f64>, f64)>,
        /// The click noise the residual is expressed in, pixels.
        scale_px: f64,
    },
}

impl VpEvidence {
    /// Segments clicked through the lens `from` moved to the lens `to` (points, directions and
    /// priors are the pinhole camera's already and stay); `None` when an end lies beyond
    /// `from`'s reach.
    pub(crate) fn move_lens(&mut self, from: &DivisionModel, to: &DivisionModel) -> Option<()> {
        if let Self::Lines(segments) = self {
            for l in segments.iter_mut() {
                let (_, a) = from.move_to(to, [l[0], l[1]])?;
                let (_, b) = from.move_to(to, [l[2], l[3]])?;
                *l = [a[0], a[1], b[0], b[1]];
            }
        }
        Some(())
    }
}

impl VpEvidence {
    /// Express weighed evidence (with its own uncertainty) in click noise `sigma_px`.
    pub fn set_scale(&mut self, sigma_px: f64) {
        match self {
            Self::Measured { scale_px, .. } | Self::Intrinsics { scale_px, .. } => {
                *scale_px = sigma_px;
            }
            Self::Lines(_) => {}
        }
    }

    /// The click noise weighed evidence is expressed in (`None` for evidence in pixels).
    pub fn scale(&self) -> Option<f64> {
        match self {
            Self::Measured { scale_px, .. } | Self::Intrinsics { scale_px, .. } => Some(*scale_px),
            Self::Lines(_) => None,
        }
    }
}

/// The map direction of vanishing point `k`: the room's horizontal directions, then up.
pub(crate) fn vp_direction(cam: &Camera, k: usize) -> Vector3<f64> {
    if k == 2 {
        Vector3::new(0.0, 0.0, 1.0)
    } else {
        let u = cam.room_axis(k);
        Vector3::new(u.x, u.y, 0.0)
    }
}

/// Number of residuals of one vanishing point's evidence.
pub(crate) fn vp_residual_count(e: &VpEvidence) -> usize {
    match e {
        VpEvidence::Lines(l) => l.len(),
        VpEvidence::Measured { .. } => 2,
        VpEvidence::Intrinsics {
            focal_px,
            principal_point_px,
            ..
        } => usize::from(focal_px.is_some()) + 2 * usize::from(principal_point_px.is_some()),
    }
}

/// Residuals of vanishing point `k`'s evidence into `out` (of the intrinsics' priors, for
/// that evidence, whatever `k`).
///
/// A segment's residual is the distance of its first end from the line through its midpoint
/// and the predicted vanishing point, times `sqrt(2)`: under independent noise of `sigma` on
/// each coordinate of both ends it has standard deviation `sigma`. A given point's residuals
/// are the angle between the predicted and the given vanishing directions, times a fixed focal
/// length (pixels near the image centre), in two orthogonal components. A measured point's
/// are its whitened offset in its chart ([`VpChart::offset_rad`]) times the click noise.
pub(crate) fn vp_residuals(cam: &Camera, k: usize, evidence: &VpEvidence, out: &mut [f64]) {
    if let VpEvidence::Intrinsics {
        focal_px,
        principal_point_px,
        scale_px,
    } = evidence
    {
        let mut at = 0;
        if let Some((f, sd)) = focal_px {
            out[at] = scale_px * (cam.focal_px - f) / sd;
            at += 1;
        }
        if let Some((p, sd)) = principal_point_px {
            out[at] = scale_px * (cam.principal_point_px.x - p.x) / sd;
            out[at + 1] = scale_px * (cam.principal_point_px.y - p.y) / sd;
        }
        return;
    }
    let v = cam.vanishing_point(vp_direction(cam, k));
    match evidence {
        VpEvidence::Intrinsics { .. } => {}
        VpEvidence::Measured {
            at,
            chart,
            whitening,
            scale_px,
        } => {
            let r = chart
                .offset_rad(*at, v)
                .map_or_else(Vector2::zeros, |o| whitening * Vector2::new(o[0], o[1]));
            out[0] = scale_px * r.x;
            out[1] = scale_px * r.y;
        }
        VpEvidence::Lines(lines) => {
            for (r, l) in out.iter_mut().zip(lines) {
                let m = Vector3::new(0.5 * (l[0] + l[2]), 0.5 * (l[1] + l[3]), 1.0);
                let line = m.cross(&v);
                let norm = line.x.hypot(line.y);
                *r = if norm > 0.0 {
                    std::f64::consts::SQRT_2 * (line.x * l[0] + line.y * l[1] + line.z) / norm
                } else {
                    0.0
                };
            }
        }
    }
}

/// A clicked pixel as a vector.
pub(crate) fn px(p: PixelPoint) -> Vector2<f64> {
    Vector2::new(p[0], p[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pixel_s_distance_below_the_horizon_follows_the_pinhole_camera() {
        // A level-rolled camera pitched down by 20 degrees: its horizon is the image row
        // f tan(20 deg) above the principal point (a standard pinhole's).
        let (f, pitch) = (1000.0, 20f64.to_radians());
        let pp = Vector2::new(800.0, 600.0);
        let cam = Camera::from_params(&[f, pitch, 0.0, 0.3], Some(pp));
        let horizon_y = 600.0 - f * pitch.tan();
        for (x, y) in [
            (800.0, 600.0),
            (0.0, 1200.0),
            (1600.0, horizon_y - 30.0),
            (10.0, horizon_y + 0.25),
        ] {
            let d = cam.below_horizon_px(Vector2::new(x, y));
            assert!((d - (y - horizon_y)).abs() < 1e-9, "({x}, {y}): {d}");
            assert_eq!(
                cam.floor_point(Vector2::new(x, y)).is_some(),
                d > 0.0,
                "({x}, {y})"
            );
        }
        // Rolled: floor points far away in any direction lie on the horizon, nearer ones
        // below it.
        let cam = Camera::from_params(&[f, pitch, 4f64.to_radians(), 0.3], Some(pp));
        for a in [-0.5f64, 0.0, 0.4] {
            let dir = Vector3::new(a.sin(), a.cos(), 0.0);
            let far = cam.project(dir * 1e9).map(|p| cam.below_horizon_px(p));
            let near = cam.project(dir * 5.0).map(|p| cam.below_horizon_px(p));
            assert!(far.is_some_and(|d| d.abs() < 1e-3), "{a}: {far:?}");
            assert!(near.is_some_and(|d| d > 10.0), "{a}: {near:?}");
        }
    }
}
