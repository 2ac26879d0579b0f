//! How to build: one options type for `vpmap build`, `vpmap demo` and the page's
//! `/api/build` and `/api/plan`, whose [`MapOptions::validate`] holds every range (the ranges
//! themselves, and [`BuildOption`], are re-exported here from the crate's `ranges` module).

use vpmap_metrology::reconstruct::Method;

use crate::error::PipelineError;
pub use crate::ranges::{
    BuildOption, CLICK_SIGMA_RANGE_PX, DEFAULT_RESOLUTION_M, DEFAULT_ROBOT_RADIUS_M, GRID_MARGIN_M,
    GROW_CONFIDENCE_RANGE, RESOLUTION_RANGE_M, ROBOT_RADIUS_RANGE_M,
};

/// How to build a map and its occupancy grid from a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapOptions {
    /// Reconstruction method (the joint fit by default; the thesis's side-view method and
    /// the projective form on request).
    pub method: Method,
    /// Occupancy-grid cell size, metres (map units when the scene has no scale).
    pub resolution_m: f64,
    /// Obstacles in the occupancy grid are inflated by this radius, metres (map units when the
    /// scene has no scale).
    pub robot_radius_m: f64,
    /// Floor hidden behind objects is free in the grid (by default it is unknown).
    pub hidden_free: bool,
    /// Refuse maps whose occupancy grid would have more cells than this (`None`: no limit;
    /// the grid's own limit, [`vpmap_plan::MAX_CELLS`], still holds).
    pub max_grid_cells: Option<f64>,
    /// The click noise the fit's error bars are computed for, pixels (`None`: estimated from
    /// the residuals when the data over-determine the model, else 1 px).
    pub click_sigma_px: Option<f64>,
    /// Grow each obstacle in the occupancy grid by its uncertainty at this confidence (e.g.
    /// 0.95), so a robot keeps clear of what is not known well (`None`: footprints as fitted).
    /// Needs a map with error bars (method `fit`).
    pub grow_confidence: Option<f64>,
}

impl Default for MapOptions {
    fn default() -> Self {
        Self {
            method: Method::Fit,
            resolution_m: DEFAULT_RESOLUTION_M,
            robot_radius_m: DEFAULT_ROBOT_RADIUS_M,
            hidden_free: false,
            max_grid_cells: None,
            click_sigma_px: None,
            grow_confidence: None,
        }
    }
}

impl MapOptions {
    /// Check every range: [`RESOLUTION_RANGE_M`], [`ROBOT_RADIUS_RANGE_M`],
    /// [`CLICK_SIGMA_RANGE_PX`], [`GROW_CONFIDENCE_RANGE`].
    ///
    /// # Errors
    /// [`PipelineError::OptionOutOfRange`] naming the first option out of range (NaN and
    /// infinities are out of every range).
    pub fn validate(&self) -> Result<(), PipelineError> {
        for (option, value) in [
            (BuildOption::Resolution, Some(self.resolution_m)),
            (BuildOption::RobotRadius, Some(self.robot_radius_m)),
            (BuildOption::ClickSigma, self.click_sigma_px),
            (BuildOption::GrowConfidence, self.grow_confidence),
        ] {
            let Some(value) = value else { continue };
            if !(value.is_finite() && option.range().contains(&value)) {
                return Err(PipelineError::OptionOutOfRange { option, value });
            }
        }
        if self.grow_confidence.is_some() && self.method != Method::Fit {
            return Err(PipelineError::NoErrorBars {
                method: self.method,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_checked_once_with_both_names() {
        assert!(MapOptions::default().validate().is_ok());
        let bad = |resolution_m, robot_radius_m| {
            MapOptions {
                resolution_m,
                robot_radius_m,
                ..MapOptions::default()
            }
            .validate()
            .err()
            .map(|e| e.to_string())
        };
        assert_eq!(
            bad(0.0, 0.2).as_deref(),
            Some("resolution is 0; it must be a positive number of metres, from 0.001 to 100")
        );
        assert!(bad(100.5, 0.2).is_some() && bad(f64::NAN, 0.2).is_some());
        assert!(bad(100.0, 0.0).is_none() && bad(0.001, 1000.0).is_none());
        assert_eq!(
            bad(0.05, -1.0).as_deref(),
            Some("robot_radius is -1; it must be a non-negative number of metres, at most 1000")
        );
        assert!(bad(0.05, f64::INFINITY).is_some());
    }
}
