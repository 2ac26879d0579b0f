//! How to build: one options type for `vpmap build`, `vpmap demo` and the page's
//! `/api/build` and `/api/plan`, whose [`MapOptions::validate`] holds every range.

use std::fmt;
use std::ops::RangeInclusive;

use vpmap_metrology::reconstruct::Method;

use crate::PipelineError;

/// Accepted occupancy-grid cell sizes, metres (map units when the scene has no scale). A
/// millimetre is finer than any corner clicked in a photo; 100 m cells hold a whole building.
pub const RESOLUTION_RANGE_M: RangeInclusive<f64> = 0.001..=100.0;

/// Accepted robot radii, metres (map units when the scene has no scale).
pub const ROBOT_RADIUS_RANGE_M: RangeInclusive<f64> = 0.0..=1000.0;

/// The default robot radius, metres: 0.2 m, a small indoor robot's with a little clearance (a
/// TurtleBot 2's base or a robot vacuum is about 0.35 m across). A robot has a size: with a
/// radius of 0 paths graze every corner, which no real robot can follow.
pub const DEFAULT_ROBOT_RADIUS_M: f64 = 0.2;

/// The default occupancy-grid cell size, metres.
pub const DEFAULT_RESOLUTION_M: f64 = 0.05;

/// Accepted click noise for the fit's error bars, pixels (1 sigma per coordinate).
pub const CLICK_SIGMA_RANGE_PX: RangeInclusive<f64> = 0.0..=100.0;

/// Accepted confidence levels for growing obstacles by their uncertainty.
pub const GROW_CONFIDENCE_RANGE: RangeInclusive<f64> = 0.5..=0.9999;

/// Unknown border around the map in the occupancy grid, map units.
pub const GRID_MARGIN_M: f64 = 0.5;

/// One option of [`MapOptions`] that has a range, to name it in messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum BuildOption {
    /// [`MapOptions::resolution_m`].
    Resolution,
    /// [`MapOptions::robot_radius_m`].
    RobotRadius,
    /// [`MapOptions::click_sigma_px`].
    ClickSigma,
    /// [`MapOptions::grow_confidence`].
    GrowConfidence,
}

impl BuildOption {
    /// The option's name in the web API (`resolution`, `robot_radius`).
    #[must_use]
    pub fn key(self) -> &'static str {
        match self {
            Self::Resolution => "resolution",
            Self::RobotRadius => "robot_radius",
            Self::ClickSigma => "click_sigma",
            Self::GrowConfidence => "grow_confidence",
        }
    }

    /// The option's flag on the command line (`--resolution`, `--robot-radius`).
    #[must_use]
    pub fn flag(self) -> &'static str {
        match self {
            Self::Resolution => "--resolution",
            Self::RobotRadius => "--robot-radius",
            Self::ClickSigma => "--click-sigma",
            Self::GrowConfidence => "--grow-confidence",
        }
    }

    /// What the option's value must be, from its range: "a positive number of metres, from
    /// 0.001 to 100".
    #[must_use]
    pub fn requirement(self) -> String {
        match self {
            Self::Resolution => format!(
                "a positive number of metres, from {} to {}",
                RESOLUTION_RANGE_M.start(),
                RESOLUTION_RANGE_M.end()
            ),
            Self::RobotRadius => format!(
                "a non-negative number of metres, at most {}",
                ROBOT_RADIUS_RANGE_M.end()
            ),
            Self::ClickSigma => format!(
                "a non-negative number of pixels, at most {}",
                CLICK_SIGMA_RANGE_PX.end()
            ),
            Self::GrowConfidence => format!(
                "a confidence level from {} to {}",
                GROW_CONFIDENCE_RANGE.start(),
                GROW_CONFIDENCE_RANGE.end()
            ),
        }
    }

    fn range(self) -> RangeInclusive<f64> {
        match self {
            Self::Resolution => RESOLUTION_RANGE_M,
            Self::RobotRadius => ROBOT_RADIUS_RANGE_M,
            Self::ClickSigma => CLICK_SIGMA_RANGE_PX,
            Self::GrowConfidence => GROW_CONFIDENCE_RANGE,
        }
    }
}

impl fmt::Display for BuildOption {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.key())
    }
}

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
