//! The one error type of this crate.

use thiserror::Error;

/// Everything that can go wrong while drawing or modelling a floor map.
///
/// Every variant carries the offending value so that the message alone says what to fix.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum RenderError {
    /// A coordinate or length of the map is NaN or infinite.
    #[error("map field `{field}` is not a finite number ({value})")]
    NonFinite {
        /// Dotted path of the field, e.g. `objects[2].footprint[1][0]`.
        field: String,
        /// The value found.
        value: f64,
    },
    /// A coordinate or length is too large for the 32-bit floats of a glTF model.
    #[error("map field `{field}` is {value}, beyond the range of 32-bit floats used by glTF")]
    OutOfRange {
        /// Dotted path of the field.
        field: String,
        /// The value found.
        value: f64,
    },
    /// An object's footprint has fewer than three distinct corners or no area.
    #[error(
        "object \"{name}\" has a degenerate footprint ({corners} distinct corners, area {area}); it needs at least 3 corners enclosing a positive area"
    )]
    DegenerateFootprint {
        /// The object's name.
        name: String,
        /// Number of distinct corners after removing repeats.
        corners: usize,
        /// Unsigned area of the footprint.
        area: f64,
    },
    /// A polygon could not be cut into triangles (it crosses itself or is degenerate).
    #[error("cannot triangulate {what} ({corners} corners): {reason}")]
    Triangulation {
        /// Which polygon, e.g. `the floor` or `object "desk"`.
        what: String,
        /// Number of corners of the polygon.
        corners: usize,
        /// Why it failed.
        reason: String,
    },
    /// The model's binary buffer would exceed the 4 GiB limit of the GLB format.
    #[error("the glTF binary buffer would be {bytes} bytes; GLB holds at most 4294967295")]
    TooLarge {
        /// Size the buffer would have, bytes.
        bytes: u64,
    },
    /// The glTF JSON could not be serialised.
    #[error("cannot serialise the glTF JSON: {0}")]
    Json(String),
    /// The SVG text is not a picture resvg can read.
    #[error("cannot parse the SVG: {0}")]
    Svg(String),
    /// No font was found on this system, so text would silently disappear from the PNG.
    #[error(
        "no fonts found in the system font directories; install DejaVu Sans (e.g. the fonts-dejavu-core package) to rasterise labels"
    )]
    NoFonts,
    /// The picture is empty or too large to allocate as a pixel buffer.
    #[error("cannot allocate a {width} x {height} pixel image")]
    ImageSize {
        /// Width, pixels.
        width: u32,
        /// Height, pixels.
        height: u32,
    },
    /// resvg failed while painting (e.g. coordinates beyond the range of `i32`).
    #[error("cannot rasterise the SVG: {0}")]
    Rasterise(String),
    /// PNG encoding failed.
    #[error("cannot encode the PNG: {0}")]
    Png(String),
    /// A step of drawing the detection overlay failed.
    #[error("{step}: {reason}")]
    Overlay {
        /// What was being done, e.g. `encoding the overlay as PNG`.
        step: &'static str,
        /// Why it failed: the error's message and its causes.
        reason: String,
    },
}
