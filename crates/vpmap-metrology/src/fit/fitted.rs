//! What the fit is asked and what it returns: [`FitOptions`] and the click noise they give
//! the error bars, and [`Fitted`], the fitted camera and objects with the problem kept for the
//! error bars.

use super::solve::{Model, Problem};
use crate::calibration::Calibration;
use crate::reconstruct::Reconstruction;

/// Options of [`fit_scene`](super::fit_scene).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FitOptions {
    /// The click noise, pixels (1 sigma per coordinate). `None`: estimated from the residuals
    /// when the data over-determine the model by at least [`MIN_DOF_FOR_SIGMA`], else 1 px.
    pub click_sigma_px: Option<f64>,
}

/// The least click noise the fit assumes when it estimates it from the residuals, pixels:
/// the standard deviation of rounding to whole pixels, `1/sqrt(12)`.
pub const MIN_CLICK_SIGMA_PX: f64 = 0.288_675_134_594_812_9;

/// Fewest redundant observations (residuals minus parameters) for estimating the click
/// noise from the residuals.
pub const MIN_DOF_FOR_SIGMA: usize = 20;

/// The click noise for the error bars and where it comes from.
pub(crate) fn click_sigma<M: Model>(
    options: &FitOptions,
    cost: f64,
    problem: &M,
) -> (f64, &'static str) {
    if let Some(s) = options.click_sigma_px {
        return (s, "given");
    }
    if problem.has_click_covariances() {
        // The covariances are absolute: a weighted residual is in pixels of a 1 px click.
        return (1.0, "covariances");
    }
    let dof = problem.residual_count().saturating_sub(problem.len());
    if dof >= MIN_DOF_FOR_SIGMA {
        // Never below the rounding of a click to whole pixels (a uniform error of one pixel
        // has a standard deviation of 1/sqrt(12) px): exact synthetic clicks would otherwise
        // claim error bars of zero.
        (
            (cost / dof as f64).sqrt().max(MIN_CLICK_SIGMA_PX),
            "residuals",
        )
    } else {
        (1.0, "default")
    }
}

/// A clicked point's misfit after the fit.
#[derive(Debug, Clone, PartialEq)]
pub struct PointResidual {
    /// The object's name (or `floor distance`).
    pub object: String,
    /// The point's field, e.g. `objects[2].top.left`.
    pub field: String,
    /// Distance between the click and the fitted model's point, pixels.
    pub distance_px: f64,
}

/// The result of [`fit_scene`](super::fit_scene).
#[derive(Debug, Clone)]
pub struct Fitted {
    /// The fitted camera, as a calibration (principal point, focal length, pitch, roll and
    /// the vanishing points the fit predicts).
    pub calibration: Calibration,
    /// The objects and floor in camera heights.
    pub reconstruction: Reconstruction,
    /// Root-mean-square reprojection error of the clicked points, pixels.
    pub rms_residual_px: f64,
    /// Residuals minus parameters.
    pub degrees_of_freedom: usize,
    /// Levenberg-Marquardt iterations.
    pub iterations: usize,
    /// Whether the principal point was fitted.
    pub principal_point_fitted: bool,
    /// Every clicked point's misfit, in scene order.
    pub point_residuals: Vec<PointResidual>,
    /// Every clicked point's misfit as the fit weighs it, in the order of `point_residuals`:
    /// with a covariance (`click_covariances_px2`), the whitened residual's length (in
    /// standard deviations of that click); without, its length in pixels (a 1 px click).
    /// Equal to the `distance_px` when the scene gives no covariances.
    pub weighted_residuals: Vec<f64>,
    /// The fitted room directions' angle from `+x`, radians (the scene's first vanishing
    /// point).
    pub room_yaw_rad: f64,
    pub(crate) problem: Problem,
    pub(crate) x: Vec<f64>,
    /// Part index of each scene object.
    pub(crate) object_parts: Vec<usize>,
    /// Part indices of the scale's floor points, if the scale is a floor distance.
    pub(crate) floor_distance_parts: Option<[usize; 2]>,
}
