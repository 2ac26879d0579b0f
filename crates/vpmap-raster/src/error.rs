//! The error type of the rasterisation.

use vpmap_plan::PlanError;

/// Why a floor map or a truth could not be rasterised.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RasterError {
    /// A coordinate of the floor map is NaN or infinite.
    #[error("floor map coordinate `{field}` is not finite ({value})")]
    NonFiniteMap {
        /// Path of the coordinate, e.g. `objects[2].footprint[1][0]`.
        field: String,
        /// The value found.
        value: f64,
    },
    /// A coordinate of the floor map is further from the origin than
    /// [`crate::MAX_MAP_COORDINATE`].
    #[error(
        "floor map coordinate `{field}` is {}; coordinates must be within ±{} map units of the origin",
        vpmap_files::num(*value),
        vpmap_files::num(*limit)
    )]
    MapCoordinateOutOfRange {
        /// Path of the coordinate, e.g. `floor[0][1]`.
        field: String,
        /// The value found.
        value: f64,
        /// The limit, map units.
        limit: f64,
    },
    /// The grid refused: an option out of range ([`PlanError::InvalidParameter`], e.g.
    /// `RasterOptions.resolution_m`) or a grid too large ([`PlanError::GridTooLarge`]).
    #[error(transparent)]
    Plan(#[from] PlanError),
}

/// The result of the rasterisation.
pub type Result<T> = std::result::Result<T, RasterError>;
