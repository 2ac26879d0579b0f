//! The thesis's side-view method (chapters 3 and 4, Appendix B), read with the sign rules of
//! `../shared/thesis/errata.md`.
//!
//! All image distances are measured in the horizon frame ([`HorizonFrame`]): `x` along the
//! horizon from the principal point `O`, `y` perpendicular to it, positive towards the sky.
//! Depths below the horizon and the angles `beta` are *signed* (errata, "Frame and signs"),
//! which covers the thesis's "case 1/2/3" and "use -beta" remarks with one formula.
//!
//! The chapter equations produce lengths at the scale "camera height = `h1`", where `h1` is the
//! image-plane depth of the reference base corner `P1` (eq. 4.6): the reference is the
//! object base corner lowest below the horizon (thesis section 4.2: "nearest to the image
//! bottom"), or the lowest floor corner when the scene has no objects. Every result is then
//! divided by `h1`, so the output unit is the camera height.
//!
//! [`HorizonFrame`]: crate::calibration::HorizonFrame

use nalgebra::{Matrix2, Vector2};

use crate::calibration::{Calibration, Perspective};
use crate::error::{MetrologyError, Result};
use crate::reconstruct::{FloorProjection, require_below_horizon};
use crate::scene::{ObjectShape, PixelPoint, Scene};

/// The side-view construction for one calibrated scene.
#[derive(Debug, Clone)]
pub struct SideView<'a> {
    cal: &'a Calibration,
    /// Image-plane depth of the reference base corner below the horizon, pixels (eq. 4.6).
    h1: f64,
    /// Forward distance from the station point to the reference corner, at scale `h1` (eq. 4.9).
    b1: f64,
    /// Distance of the top view's view point from the horizon line, `d / cos(theta)`.
    d0: f64,
}

fn px(p: PixelPoint) -> Vector2<f64> {
    Vector2::new(p[0], p[1])
}

impl<'a> SideView<'a> {
    /// Set up the construction: choose the reference corner `P1` and compute `h1` (eq. 4.6) and
    /// `b1` (eq. 4.9; in 2PP `b1 = d`, eq. 4.34).
    #[must_use]
    pub fn new(cal: &'a Calibration, scene: &Scene) -> Self {
        let mut candidates: Vec<Vector2<f64>> = Vec::new();
        for (i, obj) in scene.objects.iter().enumerate() {
            match obj.shape(i) {
                Ok(ObjectShape::Box { base, .. }) => candidates.extend(base.near.map(px)),
                Ok(ObjectShape::Footprint { polygon, .. }) => {
                    candidates.extend(polygon.iter().map(|p| px(*p)));
                }
                Err(_) => {}
            }
        }
        if candidates.is_empty() {
            candidates.extend(scene.floor.iter().map(|p| px(*p)));
        }
        let deepest = candidates
            .iter()
            .map(|p| cal.frame.coords(*p).y)
            .min_by(f64::total_cmp);
        // Without any usable point the reference is a virtual one, one focal length below the
        // horizon; the scale cancels in every output.
        let y1 = match deepest {
            Some(y) if y < cal.frame.horizon_offset_px => y,
            _ => cal.frame.horizon_offset_px - cal.focal_px,
        };
        let mut view = Self {
            cal,
            h1: 1.0,
            b1: 0.0,
            d0: cal.top_view_distance_px(),
        };
        view.h1 = view.depth(y1);
        view.b1 = match cal.perspective {
            // Eq. 4.34: in 2PP the reference corner is `d` in front of the station point.
            Perspective::TwoPoint => cal.focal_px,
            // Eq. 4.9 with signed beta1.
            Perspective::ThreePoint => view.h1 / (cal.pitch_rad + view.beta(y1)).tan(),
        };
        view
    }

    /// Image-plane depth below the horizon of a point at horizon-frame height `y`:
    /// eq. 4.6, `h = P G cos(theta)` (in 2PP, `theta = 0`: the depth of eq. 3.1). Signed.
    fn depth(&self, y: f64) -> f64 {
        (self.cal.frame.horizon_offset_px - y) * self.cal.pitch_rad.cos()
    }

    /// Signed angle of a point against the optical axis, eq. 4.7 with the errata's sign rule:
    /// `tan(beta) = -y / d`, positive below `O`.
    fn beta(&self, y: f64) -> f64 {
        (-y / self.cal.focal_px).atan()
    }

    /// Forward distance from the station point of a floor point at depth `h` and angle `beta`,
    /// at scale `h1`.
    ///
    /// 2PP: `b = b1 + d_p`, `d_p = h_d d / h` with `h_d = h1 - h` (eqs. 3.3 and 3.6, signed).
    /// 3PP: eq. 4.19, `b = b1 + P1Q + QP'` with `P1Q = (h1 - h) tan(theta)` (4.18) and
    /// `QP' = (h1 - h) / tan(theta + beta)` (4.13 with signed beta; floor corners 4.20-4.24).
    fn forward(&self, h: f64, beta: f64) -> f64 {
        let (h1, b1, th) = (self.h1, self.b1, self.cal.pitch_rad);
        match self.cal.perspective {
            Perspective::TwoPoint => b1 + (h1 - h) * self.cal.focal_px / h,
            Perspective::ThreePoint => b1 + (h1 - h) * th.tan() + (h1 - h) / (th + beta).tan(),
        }
    }

    /// The top view (Appendix B with the errata): the view point stands `D0 = d / cos(theta)`
    /// behind the horizon line, at forward position `b1 - D0`; a point projected onto the
    /// horizon at `x` lies on the ray from the view point through it, here at forward `b`.
    fn lateral(&self, x: f64, b: f64) -> f64 {
        x * (self.d0 + b - self.b1) / self.d0
    }

    /// The top-view view point `(0, b1 - D0)`, at scale `h1`.
    fn top_view_point(&self) -> Vector2<f64> {
        Vector2::new(0.0, self.b1 - self.d0)
    }

    /// Floor point at scale `h1`.
    fn floor_point_h1(&self, field: &str, p: PixelPoint) -> Result<Vector2<f64>> {
        require_below_horizon(self.cal, field, p)?;
        let c = self.cal.frame.coords(px(p));
        let b = self.forward(self.depth(c.y), self.beta(c.y));
        Ok(Vector2::new(self.lateral(c.x, b), b))
    }

    /// Direction on the floor of a horizontal vanishing point: the top-view line from the view
    /// point to the VP on the horizon, `(x_vp, D0)`.
    fn vp_direction(&self, k: usize) -> Vector2<f64> {
        let x = self.cal.frame.coords(self.cal.vanishing_points_px[k]).x;
        Vector2::new(x, self.d0).normalize()
    }
}

/// |sin| of the angle at `p` between the directions to `q` and to `v`.
fn misalignment(p: Vector2<f64>, q: Vector2<f64>, v: Vector2<f64>) -> f64 {
    let (a, b) = (q - p, v - p);
    let n = a.norm() * b.norm();
    if n == 0.0 {
        return 1.0;
    }
    (a.x * b.y - a.y * b.x).abs() / n
}

impl FloorProjection for SideView<'_> {
    fn floor_point(&self, field: &str, image_px: PixelPoint) -> Result<Vector2<f64>> {
        Ok(self.floor_point_h1(field, image_px)? / self.h1)
    }

    /// Height of a vertical edge, eqs. 4.25-4.31 (2PP: 3.7-3.10): with `l` the image length of
    /// the edge perpendicular to the horizon and `gamma` the signed angle of its top corner,
    /// `l_new = l d' / d` where `d' = d + OO'` and `OO' = d (h1 / h - 1)` (4.14-4.16 and the
    /// second line of 4.30, as corrected in the errata), and
    /// `height = l_new cos(theta) + l_new sin(theta) tan(theta + gamma)` (4.29 / 4.31).
    fn edge_height(&self, field: &str, base_px: PixelPoint, top_px: PixelPoint) -> Result<f64> {
        require_below_horizon(self.cal, field, base_px)?;
        let yb = self.cal.frame.coords(px(base_px)).y;
        let yt = self.cal.frame.coords(px(top_px)).y;
        let hb = self.depth(yb);
        let th = self.cal.pitch_rad;
        let height_h1 = match self.cal.perspective {
            Perspective::TwoPoint => {
                // Eq. 3.10: h1 - h3 (1 + d_p / d), with signed top depth h3.
                let dp = self.forward(hb, self.beta(yb)) - self.b1;
                self.h1 - self.depth(yt) * (1.0 + dp / self.cal.focal_px)
            }
            Perspective::ThreePoint => {
                let l = yt - yb;
                let l_new = l * self.h1 / hb;
                let gamma = self.beta(yt);
                l_new * th.cos() + l_new * th.sin() * (th + gamma).tan()
            }
        };
        Ok(height_h1 / self.h1)
    }

    /// Appendix B with the errata: the near corner `Pe` is placed by eq. 4.19 and the top view;
    /// the rectangle's sides leave `Pe` parallel to the floor directions of VP1 and VP2 and end
    /// on the view-point rays through the other two corners' projections on the horizon.
    fn box_footprint(
        &self,
        field: &str,
        near_px: PixelPoint,
        right_px: PixelPoint,
        left_px: PixelPoint,
    ) -> Result<[Vector2<f64>; 4]> {
        let pe = self.floor_point_h1(&format!("{field}.base.near"), near_px)?;
        require_below_horizon(self.cal, &format!("{field}.base.right"), right_px)?;
        require_below_horizon(self.cal, &format!("{field}.base.left"), left_px)?;
        let (p, q, r) = (px(near_px), px(right_px), px(left_px));
        let vps = &self.cal.vanishing_points_px;
        // Which vanishing point does each visible bottom edge run to?
        let straight = misalignment(p, q, vps[0]) + misalignment(p, r, vps[1]);
        let crossed = misalignment(p, q, vps[1]) + misalignment(p, r, vps[0]);
        let (kq, kr) = if straight <= crossed { (0, 1) } else { (1, 0) };
        let eye = self.top_view_point();
        let corner = |img: Vector2<f64>, k: usize, name: &str| -> Result<Vector2<f64>> {
            let u = self.vp_direction(k);
            let w = Vector2::new(self.cal.frame.coords(img).x, self.d0);
            // pe + s u = eye + t w
            let m = Matrix2::new(u.x, -w.x, u.y, -w.y);
            let det = m.determinant();
            if det.abs() <= 1e-12 * w.norm() {
                return Err(MetrologyError::Degenerate {
                    field: format!("{field}.base.{name}"),
                    reason: format!(
                        "the corner ({:.3}, {:.3}) lies on the line from the near corner to vanishing point {}, so the box side has no length",
                        img.x,
                        img.y,
                        k + 1
                    ),
                });
            }
            let st = m
                .lu()
                .solve(&(eye - pe))
                .ok_or_else(|| MetrologyError::Degenerate {
                    field: format!("{field}.base.{name}"),
                    reason: "top-view construction is singular".to_owned(),
                })?;
            Ok(pe + u * st.x)
        };
        let right = corner(q, kq, "right")?;
        let left = corner(r, kr, "left")?;
        let far = right + left - pe;
        Ok([pe, right, far, left].map(|c| c / self.h1))
    }
}
