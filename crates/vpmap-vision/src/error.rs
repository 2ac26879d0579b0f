//! Errors of the vision crate.

/// Result with [`VisionError`].
pub type Result<T> = std::result::Result<T, VisionError>;

/// What went wrong in detection.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum VisionError {
    /// The image has a zero or absurd size.
    #[error(
        "the image is {width} x {height} pixels; it must be between 16 and {max} pixels on each side"
    )]
    BadImageSize {
        /// Width, pixels.
        width: u32,
        /// Height, pixels.
        height: u32,
        /// The largest side accepted, pixels.
        max: u32,
    },
    /// Too few line segments (or too few supporting one of the directions) to fix the
    /// vanishing points.
    #[error(
        "found {found} usable line segments; at least {needed} are needed to find the vanishing points (is the photo blurred, dark, or without straight edges?)"
    )]
    NotEnoughLines {
        /// Segments found.
        found: usize,
        /// Segments needed.
        needed: usize,
    },
    /// An option is outside its valid range.
    #[error("`{field}` is {value}; it {requirement}")]
    InvalidParameter {
        /// The option.
        field: &'static str,
        /// Its value.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
}
