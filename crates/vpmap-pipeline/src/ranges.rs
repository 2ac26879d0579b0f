//! Every build option's accepted range, and the option's names (web API key, command-line
//! flag) and requirement in messages: [`BuildOption`].

use std::fmt;
use std::ops::RangeInclusive;

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

/// One option of [`MapOptions`](crate::MapOptions) that has a range, to name it in messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum BuildOption {
    /// [`MapOptions::resolution_m`](crate::MapOptions::resolution_m).
    Resolution,
    /// [`MapOptions::robot_radius_m`](crate::MapOptions::robot_radius_m).
    RobotRadius,
    /// [`MapOptions::click_sigma_px`](crate::MapOptions::click_sigma_px).
    ClickSigma,
    /// [`MapOptions::grow_confidence`](crate::MapOptions::grow_confidence).
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

    /// The option's accepted values.
    #[must_use]
    pub fn range(self) -> RangeInclusive<f64> {
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
