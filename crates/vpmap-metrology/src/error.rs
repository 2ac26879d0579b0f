//! The one error type of this crate.

use thiserror::Error;

/// Everything that can go wrong between a scene file and a floor map.
///
/// Every variant names the offending field and value so that a user can fix the
/// scene file without reading the code.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum MetrologyError {
    /// The file is not valid JSON or does not have the expected shape.
    #[error("malformed JSON: {0}")]
    Json(String),
    /// The scene file or map.json declares a format version this library does not read.
    #[error("{file} field `version` is {version}; this vpmap reads version 1")]
    UnsupportedVersion {
        /// `scene` or `map.json`.
        file: &'static str,
        /// The version found.
        version: u64,
    },
    /// A number is NaN or infinite.
    #[error("scene field `{field}` is not a finite number ({value})")]
    NonFinite {
        /// Dotted path of the field, e.g. `objects[2].base.near[0]`.
        field: String,
        /// The value found.
        value: f64,
    },
    /// A field holds a value outside its valid range.
    #[error("scene field `{field}` is invalid: {reason}")]
    InvalidField {
        /// Dotted path of the field.
        field: String,
        /// What is wrong with it, with the value.
        reason: String,
    },
    /// A problem in one photo of a room file.
    #[error("photos[{photo}] (photo {}): {error}", photo + 1)]
    InPhoto {
        /// The photo's index in the room file, from 0.
        photo: usize,
        /// What is wrong in it.
        error: Box<MetrologyError>,
    },
    /// Two or three vanishing points are required.
    #[error(
        "scene field `vanishing_points` has {0} entries; give 2 (two-point perspective) or 3 (three-point perspective)"
    )]
    VanishingPointCount(usize),
    /// A vanishing point given by segments whose lines do not meet in a finite point.
    #[error(
        "vanishing point {index}: its lines are parallel in the image (they meet at infinity){hint}"
    )]
    ParallelLines {
        /// 1-based index of the vanishing point.
        index: usize,
        /// Extra advice for the user.
        hint: String,
    },
    /// Two vanishing points coincide (or nearly so).
    #[error("vanishing points {first} and {second} coincide at ({x:.3}, {y:.3})")]
    CoincidentVanishingPoints {
        /// 1-based index of the first point.
        first: usize,
        /// 1-based index of the second point.
        second: usize,
        /// Image x of the shared location, pixels.
        x: f64,
        /// Image y of the shared location, pixels.
        y: f64,
    },
    /// The vanishing points do not give a real, positive focal length.
    #[error("no real focal length: {0}")]
    NoRealFocalLength(String),
    /// An annotated floor point lies on or above the horizon, so its floor position is at or beyond infinity.
    #[error(
        "`{field}` at ({x:.3}, {y:.3}) is {distance_px:.3} px {side} the horizon; a point on the floor must lie below it"
    )]
    NotBelowHorizon {
        /// Dotted path of the point.
        field: String,
        /// Image x, pixels.
        x: f64,
        /// Image y, pixels.
        y: f64,
        /// Distance to the horizon, pixels.
        distance_px: f64,
        /// "on" or "above".
        side: &'static str,
    },
    /// The `scale` names an object that the scene does not have.
    #[error(
        "scene field `scale.object` names {name:?}, but the scene has no object of that name (objects: {known})"
    )]
    UnknownScaleObject {
        /// The name given.
        name: String,
        /// The names that exist, comma separated.
        known: String,
    },
    /// Long work stopped early by its [`crate::interrupt::Interrupt`] (a time limit, or a
    /// request whose client has gone).
    #[error("{work} stopped: {reason}")]
    Interrupted {
        /// What was stopped, with its size (`the room fit of 4 photos and 2000 objects`).
        work: String,
        /// Why.
        reason: crate::interrupt::Interruption,
    },
    /// A geometric construction has no solution for the given input.
    #[error("degenerate geometry at `{field}`: {reason}")]
    Degenerate {
        /// Dotted path of the input that caused it.
        field: String,
        /// What went wrong, with values.
        reason: String,
    },
    /// A room's photos fit together far worse than each alone: the joint fit's residuals
    /// fail the consistency test (`room::consistency`), and nothing is mapped.
    #[error("the room's photos do not fit together: {reason}")]
    InconsistentRoom {
        /// The test, its level, the photos and objects that disagree, the alternative's cost
        /// and what to click or rename.
        reason: String,
    },
}

/// Result alias of this crate.
pub type Result<T, E = MetrologyError> = std::result::Result<T, E>;
