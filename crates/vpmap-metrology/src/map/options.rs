//! The options of building a map, shared by `build` (one photo) and `room` (several), which
//! both import them from here (neither imports the other's options).

use crate::reconstruct::Method;

/// Options of [`build_map`](super::build_map).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BuildOptions {
    /// Reconstruction method.
    pub method: Method,
    /// The click noise the fit's error bars are computed for, pixels (1 sigma per
    /// coordinate); `None`: estimated from the residuals when the data over-determine the
    /// model, else 1 px ([`crate::fit::FitOptions`]). Method `fit` only.
    pub click_sigma_px: Option<f64>,
}
