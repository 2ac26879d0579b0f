//! The one error type of this crate.

use thiserror::Error;
use vpmap_metrology::MetrologyError;
use vpmap_plan::PlanError;
use vpmap_render::RenderError;

use crate::options::BuildOption;

/// Everything that can go wrong between a scene and its built map.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum PipelineError {
    /// A build option is outside its range (see [`BuildOption::requirement`]).
    #[error("{} is {}; it must be {}", option.key(), crate::num(*value), option.requirement())]
    OptionOutOfRange {
        /// Which option.
        option: BuildOption,
        /// The value given (metres, or map units when the scene has no scale).
        value: f64,
    },
    /// The scene cannot be calibrated, reconstructed or scaled.
    #[error(transparent)]
    Map(MetrologyError),
    /// The glTF model cannot be built from the map.
    #[error(transparent)]
    Model(RenderError),
    /// The occupancy grid would have more cells than the caller allows.
    #[error(
        "resolution {resolution} gives an occupancy grid of about {width:.0} x {height:.0} cells for this map ({span_x:.1} x {span_y:.1} {units}); the limit is {limit:.0} cells: use a coarser resolution"
    )]
    GridTooLarge {
        /// The resolution asked for, map units per cell.
        resolution: f64,
        /// Cells across, about.
        width: f64,
        /// Cells down, about.
        height: f64,
        /// The map's extent along x, map units.
        span_x: f64,
        /// The map's extent along y, map units.
        span_y: f64,
        /// The map's unit (`m` or `camera_heights`).
        units: &'static str,
        /// The most cells allowed.
        limit: f64,
    },
    /// The map cannot be rasterised into an occupancy grid.
    #[error(transparent)]
    Grid(PlanError),
    /// A start or goal is outside the grid, not on a cell, or on a cell a path cannot enter.
    #[error("{0}")]
    Endpoint(String),
    /// Obstacles are to be grown by their uncertainty, but the method gives no error bars.
    #[error(
        "growing obstacles by their uncertainty needs error bars, which only the fit method gives; method {method} gives none"
    )]
    NoErrorBars {
        /// The method asked for.
        method: vpmap_metrology::reconstruct::Method,
    },
}
