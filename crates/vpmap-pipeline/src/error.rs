//! The one error type of this crate.

use std::path::PathBuf;

use thiserror::Error;
use vpmap_files::FileError;
use vpmap_metrology::MetrologyError;
use vpmap_plan::PlanError;
use vpmap_raster::RasterError;
use vpmap_render::RenderError;

use crate::ranges::BuildOption;
use crate::text::num;

/// Everything that can go wrong between a scene and its built map.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum PipelineError {
    /// A build option is outside its range (see [`BuildOption::requirement`]).
    #[error("{} is {}; it must be {}", option.key(), num(*value), option.requirement())]
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
    /// The map cannot be rasterised into an occupancy grid, or a grid (file) is refused
    /// ([`RasterError::Plan`]).
    #[error(transparent)]
    Grid(RasterError),
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
    /// Scene text that does not start as a JSON object (`{ ... }`).
    #[error("the scene is not a JSON object ({{ ... }})")]
    SceneNotAnObject,
    /// Scene text that is not JSON (with line and column).
    #[error("the scene is not valid JSON: {0}")]
    SceneJson(serde_json::Error),
    /// JSON that is not a valid scene; the unknown fields found before are kept, so that a
    /// caller can still show them.
    #[error("{error}")]
    InvalidScene {
        /// Why the scene is invalid (naming the field and value).
        error: MetrologyError,
        /// One line per unknown field, as [`crate::scene::ParsedScene::warnings`].
        warnings: Vec<String>,
    },
    /// A map file could not be read (missing, not a regular file, too large, not text).
    #[error(transparent)]
    File(FileError),
    /// A `.json` map file that is not a vpmap `map.json`.
    #[error("{}: not a vpmap map.json", path.display())]
    NotAMap {
        /// The file.
        path: PathBuf,
        /// Why it is not one.
        source: MetrologyError,
    },
    /// A map file's floor map cannot be rasterised at the resolution asked for.
    #[error("rasterising {} at {} m a cell", path.display(), num(*resolution))]
    Rasterise {
        /// The map file.
        path: PathBuf,
        /// The resolution asked for, metres a cell.
        resolution: f64,
        /// Why not.
        source: RasterError,
    },
    /// A map file of a type vpmap does not read (by its extension).
    #[error(
        "{}: unknown map type; give a Moving AI .map, a ROS map .yaml or a vpmap map.json",
        path.display()
    )]
    UnknownMapType {
        /// The file.
        path: PathBuf,
    },
    /// A `.json` file that is not a synthetic scene's truth.
    #[error("{}: not a synthetic scene's truth", path.display())]
    NotATruth {
        /// The file.
        path: PathBuf,
        /// Why it is not one.
        source: serde_json::Error,
    },
    /// A truth without a (finite) floor outline, which no grid can frame.
    #[error("the truth has no floor outline to make a grid of")]
    NoTruthFloor,
    /// A drive on a synthetic truth (in metres) with a believed map in cells.
    #[error(
        "a synthetic truth is in metres; give a believed map.json, ROS map or grid with a resolution, not a map in cells (a Moving AI map)"
    )]
    TruthWithCells,
    /// The true map of a drive could not be read.
    #[error("reading the true map {}", path.display())]
    TrueMap {
        /// The file.
        path: PathBuf,
        /// Why not.
        #[source]
        error: Box<PipelineError>,
    },
    /// A planner refused its input, ran out of its budget or was stopped.
    #[error(transparent)]
    Plan(PlanError),
}
