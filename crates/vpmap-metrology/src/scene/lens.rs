//! Lens distortion: the one-parameter division model (Fitzgibbon, "Simultaneous linear
//! estimation of multiple view geometry and lens distortion", CVPR 2001), and a scene's clicks
//! undistorted by it.
//!
//! A pixel `p_d` of the photo as taken maps to the pinhole camera's pixel
//! `p_u = c + (p_d - c) / (1 + k r^2)`, with `r = |p_d - c| / h`: `c` the distortion centre
//! (the scene's `principal_point` when given, else the image centre) and `h` half the image
//! diagonal, so `k` is dimensionless and does not depend on the resolution. Barrel distortion
//! (straight edges bowed outwards, as most phone and wide lenses show) has `k < 0`.
//!
//! In a scene with `lens_distortion`, every clicked point and every vanishing-point segment
//! (`lines`) is in the photo's pixels and is undistorted before anything is measured
//! ([`Scene::undistorted`]); vanishing points given as a `point` or `direction` are already
//! the pinhole camera's (that is what `vpmap detect` writes).

use std::borrow::Cow;

use nalgebra::{Matrix2, Vector2};
use serde::{Deserialize, Serialize};

use super::types::{ImageSize, PixelPoint, Scene};
use crate::error::{MetrologyError, Result};

/// The largest `|k|` a scene may give: beyond it the model is no longer a lens's.
pub const MAX_DIVISION_K: f64 = 1.0;

/// The most `|k| r^2` may reach at a corner of the image: at 1 the model folds the image
/// (`k > 0`: two photo pixels map to one) or sends a corner to infinity (`k < 0`).
pub const MAX_DIVISION_STRETCH: f64 = 0.9;

/// A scene's `lens_distortion`: the division model's `k` and its standard deviation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LensDistortion {
    /// The division model's `k` (see the module docs), dimensionless; barrel `k < 0`.
    pub k: f64,
    /// Its standard deviation (default 0: known, from a calibration); the map's error bars
    /// include what it moves.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_sd: Option<f64>,
}

/// The division model of one photo: `k`, the centre and the radius unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DivisionModel {
    /// The model's `k`.
    pub k: f64,
    /// The distortion centre, pixels.
    pub centre_px: Vector2<f64>,
    /// The radius unit: half the image diagonal, pixels.
    pub radius_unit_px: f64,
}

impl DivisionModel {
    /// The model for an image of `image` with distortion centre `centre` (the image centre
    /// when `None`).
    #[must_use]
    pub fn new(k: f64, image: ImageSize, centre: Option<PixelPoint>) -> Self {
        Self {
            k,
            centre_px: centre.map_or_else(|| image.centre(), |c| Vector2::new(c[0], c[1])),
            radius_unit_px: 0.5 * image.diagonal(),
        }
    }

    /// The largest `|k| r^2` over the image's corners (at least 1 means the model folds it).
    #[must_use]
    pub fn stretch(&self, image: ImageSize) -> f64 {
        let (w, h) = (f64::from(image.width), f64::from(image.height));
        [[0.0, 0.0], [w, 0.0], [0.0, h], [w, h]]
            .iter()
            .map(|p| {
                let r = (Vector2::new(p[0], p[1]) - self.centre_px).norm() / self.radius_unit_px;
                self.k.abs() * r * r
            })
            .fold(0.0, f64::max)
    }

    /// The pinhole pixel of photo pixel `p`.
    #[must_use]
    pub fn undistort(&self, p: PixelPoint) -> PixelPoint {
        let d = Vector2::new(p[0], p[1]) - self.centre_px;
        let r2 = d.norm_squared() / (self.radius_unit_px * self.radius_unit_px);
        let u = self.centre_px + d / (1.0 + self.k * r2);
        [u.x, u.y]
    }

    /// The photo pixel of pinhole pixel `p` (the inverse of [`Self::undistort`]), `None` where
    /// no photo pixel maps there (beyond the model's reach).
    #[must_use]
    pub fn distort(&self, p: PixelPoint) -> Option<PixelPoint> {
        let d = Vector2::new(p[0], p[1]) - self.centre_px;
        let ru = d.norm() / self.radius_unit_px;
        if ru == 0.0 || self.k == 0.0 {
            return Some(p);
        }
        // ru = rd / (1 + k rd^2)  <=>  k ru rd^2 - rd + ru = 0, the root nearer ru.
        let disc = 1.0 - 4.0 * self.k * ru * ru;
        if disc < 0.0 {
            return None;
        }
        let rd = 2.0 * ru / (1.0 + disc.sqrt());
        let q = self.centre_px + d * (rd / ru);
        Some([q.x, q.y])
    }

    /// Pinhole pixel `p` of this lens moved to the lens `to`: the photo pixel it came from
    /// (this lens undistorted it there) and where `to` undistorts that photo pixel, as
    /// `(photo pixel, pinhole pixel of to)`; `None` beyond this lens's reach. The one place the
    /// fit and the room fit move a click between two values of `k` (the error bars'
    /// `k +- k_sd` refits).
    #[must_use]
    pub fn move_to(&self, to: &Self, p: PixelPoint) -> Option<(PixelPoint, PixelPoint)> {
        let raw = self.distort(p)?;
        Some((raw, to.undistort(raw)))
    }

    /// A click covariance's whitening `w` (`w^T w` the inverse covariance in this lens's
    /// pinhole pixels) moved to the lens `to` at photo pixel `raw`: the covariance in pinhole
    /// pixels is `J C J^T` with `J` the undistortion's Jacobian at the photo pixel, so the
    /// whitening follows as `w J_self J_to^-1`; `None` where `to`'s Jacobian is singular.
    #[must_use]
    pub fn whitening_moved_to(
        &self,
        to: &Self,
        raw: PixelPoint,
        w: Matrix2<f64>,
    ) -> Option<Matrix2<f64>> {
        let to_inverse = to.undistort_jacobian(raw).try_inverse()?;
        Some(w * self.undistort_jacobian(raw) * to_inverse)
    }

    /// The Jacobian of [`Self::undistort`] at photo pixel `p`.
    #[must_use]
    pub fn undistort_jacobian(&self, p: PixelPoint) -> Matrix2<f64> {
        let d = Vector2::new(p[0], p[1]) - self.centre_px;
        let s2 = self.radius_unit_px * self.radius_unit_px;
        let den = 1.0 + self.k * d.norm_squared() / s2;
        // d/dd [d / den] = I / den - d (2 k d^T / s2) / den^2
        Matrix2::identity() / den - d * d.transpose() * (2.0 * self.k / (s2 * den * den))
    }
}

impl Scene {
    /// The photo's division model, when the scene gives `lens_distortion`.
    #[must_use]
    pub fn division_model(&self) -> Option<DivisionModel> {
        self.lens_distortion
            .map(|l| DivisionModel::new(l.k, self.image, self.principal_point))
    }

    /// `lens_distortion`: `k` finite within [`MAX_DIVISION_K`], its sd finite and not
    /// negative, and the model neither folding the image nor sending a corner to infinity.
    pub(super) fn check_lens_distortion(&self) -> Result<()> {
        let Some(lens) = self.lens_distortion else {
            return Ok(());
        };
        let invalid = |field: &str, reason: String| MetrologyError::InvalidField {
            field: format!("lens_distortion.{field}"),
            reason,
        };
        if !(lens.k.is_finite() && lens.k.abs() <= MAX_DIVISION_K) {
            return Err(invalid(
                "k",
                format!(
                    "is {}; the division model's k lies within -{MAX_DIVISION_K} to {MAX_DIVISION_K} (phone lenses about -0.15 to 0)",
                    lens.k
                ),
            ));
        }
        if let Some(sd) = lens.k_sd
            && !(sd.is_finite() && (0.0..=MAX_DIVISION_K).contains(&sd))
        {
            return Err(invalid(
                "k_sd",
                format!("is {sd}; a standard deviation lies within 0 to {MAX_DIVISION_K}"),
            ));
        }
        let model = self.division_model().unwrap_or(DivisionModel::new(
            lens.k,
            self.image,
            self.principal_point,
        ));
        let stretch = model.stretch(self.image);
        if stretch > MAX_DIVISION_STRETCH {
            let what = if lens.k > 0.0 {
                "folds the image (two photo pixels on one)"
            } else {
                "sends the image's corners towards infinity"
            };
            return Err(invalid(
                "k",
                format!(
                    "{} {what}: |k| r^2 reaches {stretch:.3} at a corner of the {} x {} image (at most {MAX_DIVISION_STRETCH})",
                    lens.k, self.image.width, self.image.height
                ),
            ));
        }
        Ok(())
    }

    /// The scene as a pinhole camera would have seen it: every clicked point, every
    /// vanishing-point segment and every click covariance (by the model's Jacobian) of this
    /// photo and of a room's other photos undistorted, and `lens_distortion` dropped. The scene
    /// itself when no photo gives a `k` other than 0.
    #[must_use]
    pub fn undistorted(&self) -> Cow<'_, Scene> {
        let distorted = |s: &Scene| s.lens_distortion.is_some_and(|l| l.k != 0.0);
        if !distorted(self) && !self.other_photos.iter().any(distorted) {
            return Cow::Borrowed(self);
        }
        let mut out = self.clone();
        out.undistort_photo();
        for p in &mut out.other_photos {
            p.undistort_photo();
        }
        Cow::Owned(out)
    }

    /// [`Self::undistorted`] for this photo alone, in place.
    fn undistort_photo(&mut self) {
        let Some(model) = self.division_model() else {
            return;
        };
        self.lens_distortion = None;
        if model.k == 0.0 {
            return;
        }
        // Covariances first, at the clicks as given.
        let mut covariances = std::mem::take(&mut self.click_covariances_px2);
        let clicks = self.clicks_by_field();
        for (field, m) in &mut covariances {
            if let Some(p) = clicks.get(field) {
                let j = model.undistort_jacobian(*p);
                let c = j * Matrix2::new(m[0][0], m[0][1], m[1][0], m[1][1]) * j.transpose();
                *m = [[c[(0, 0)], c[(0, 1)]], [c[(1, 0)], c[(1, 1)]]];
            }
        }
        self.click_covariances_px2 = covariances;
        let undistort = |p: &mut PixelPoint| *p = model.undistort(*p);
        for o in &mut self.objects {
            if let Some(b) = &mut o.base {
                b.points_mut().for_each(undistort);
            }
            if let Some(t) = &mut o.top {
                t.corners.points_mut().for_each(undistort);
                t.point.iter_mut().for_each(undistort);
            }
            if let Some(f) = &mut o.footprint {
                f.iter_mut().for_each(undistort);
            }
        }
        self.floor.iter_mut().for_each(undistort);
        if let Some(d) = self.scale.as_mut().and_then(|s| s.floor_distance.as_mut()) {
            undistort(&mut d.from);
            undistort(&mut d.to);
        }
        for vp in &mut self.vanishing_points {
            for l in &mut vp.lines {
                let a = model.undistort([l[0], l[1]]);
                let b = model.undistort([l[2], l[3]]);
                *l = [a[0], a[1], b[0], b[1]];
            }
        }
    }

    /// Every clicked point by its field path (the keys of `click_covariances_px2` may be
    /// any of them).
    pub(crate) fn clicks_by_field(&self) -> std::collections::BTreeMap<String, PixelPoint> {
        let mut out = std::collections::BTreeMap::new();
        for (i, o) in self.objects.iter().enumerate() {
            if let Some(b) = &o.base {
                for (c, p) in b.given() {
                    out.insert(format!("objects[{i}].base.{}", c.name()), p);
                }
            }
            if let Some(t) = &o.top {
                for (c, p) in t.corners.given() {
                    out.insert(format!("objects[{i}].top.{}", c.name()), p);
                }
                if let Some(p) = t.point {
                    out.insert(format!("objects[{i}].top.point"), p);
                }
            }
            if let Some(f) = &o.footprint {
                for (k, p) in f.iter().enumerate() {
                    out.insert(format!("objects[{i}].footprint[{k}]"), *p);
                }
            }
        }
        for (k, p) in self.floor.iter().enumerate() {
            out.insert(format!("floor[{k}]"), *p);
        }
        if let Some(d) = self.scale.as_ref().and_then(|s| s.floor_distance.as_ref()) {
            out.insert("scale.floor_distance.from".to_owned(), d.from);
            out.insert("scale.floor_distance.to".to_owned(), d.to);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image() -> ImageSize {
        ImageSize {
            width: 1600,
            height: 1200,
        }
    }

    #[test]
    fn distort_inverts_undistort_across_the_image() {
        for k in [-0.15, -0.05, 0.0, 0.08] {
            let m = DivisionModel::new(k, image(), Some([790.0, 610.0]));
            for p in [[0.0, 0.0], [1600.0, 1200.0], [800.0, 3.0], [123.4, 987.6]] {
                let u = m.undistort(p);
                let back = m.distort(u).unwrap();
                assert!(
                    (back[0] - p[0]).hypot(back[1] - p[1]) < 1e-9,
                    "k {k}: {p:?} -> {u:?} -> {back:?}"
                );
            }
        }
    }

    #[test]
    fn barrel_distortion_pushes_corners_outwards_when_undistorted() {
        // Independent numbers: at the corner r = 1, k = -0.1 moves it by 1 / 0.9.
        let m = DivisionModel::new(-0.1, image(), None);
        let u = m.undistort([1600.0, 1200.0]);
        assert!((u[0] - (800.0 + 800.0 / 0.9)).abs() < 1e-9, "{u:?}");
        assert!((u[1] - (600.0 + 600.0 / 0.9)).abs() < 1e-9, "{u:?}");
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let m = DivisionModel::new(-0.12, image(), None);
        let p = [1400.0, 200.0];
        let j = m.undistort_jacobian(p);
        let h = 1e-4;
        for axis in 0..2 {
            let mut a = p;
            let mut b = p;
            a[axis] += h;
            b[axis] -= h;
            let (ua, ub) = (m.undistort(a), m.undistort(b));
            for row in 0..2 {
                let numeric = (ua[row] - ub[row]) / (2.0 * h);
                assert!((numeric - j[(row, axis)]).abs() < 1e-6, "{numeric} vs {j}");
            }
        }
    }
}
