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
    /// A photo file or body with no bytes.
    #[error("the photo is empty, not a JPEG or PNG photo")]
    EmptyPhoto,
    /// Bytes that are no image format at all.
    #[error("the data ({bytes} bytes) is not a JPEG or PNG photo (its first bytes are neither)")]
    NotAPhoto {
        /// How many bytes were given.
        bytes: usize,
    },
    /// An image in a format vpmap does not read.
    #[error("this is a {format} image; vpmap reads JPEG and PNG photos")]
    UnsupportedFormat {
        /// The format's usual file extension.
        format: String,
    },
    /// A photo too small or too large (from its header).
    #[error(
        "the photo is {width} x {height} pixels; a photo must be {min} to {max} pixels on each side and at most {max_megapixels} megapixels"
    )]
    PhotoSize {
        /// Width, pixels.
        width: u32,
        /// Height, pixels.
        height: u32,
        /// Smallest side accepted, pixels.
        min: u32,
        /// Largest side accepted, pixels.
        max: u32,
        /// Most megapixels accepted.
        max_megapixels: u64,
    },
    /// Truncated or corrupt image data, or a decoder needing more memory than allowed.
    #[error("cannot decode the {format} photo: {message}")]
    Decode {
        /// `JPEG` or `PNG`.
        format: &'static str,
        /// The decoder's message, on one line.
        message: String,
    },
    /// Too few line segments to fix the vanishing points.
    #[error(
        "found {found} usable line segments; at least {needed} are needed to find the vanishing points (is the photo blurred, dark, or without straight edges?)"
    )]
    NotEnoughLines {
        /// Segments found.
        found: usize,
        /// Segments needed.
        needed: usize,
    },
    /// Enough line segments, but they do not point to two or more orthogonal directions
    /// (all along one direction, or no consistent frame), so the vanishing points are not
    /// determined.
    #[error(
        "the {segments} usable line segments do not point along two or more orthogonal directions, so the vanishing points are not determined (the photo needs straight edges along at least two of a room's three directions)"
    )]
    NoOrthogonalDirections {
        /// Usable segments found.
        segments: usize,
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
    /// Long work stopped early by its interrupt (a time limit, or a request whose client has
    /// gone).
    #[error("{work} stopped: {reason}")]
    Interrupted {
        /// What was stopped (`box proposals`), with how far it got.
        work: String,
        /// Why.
        reason: vpmap_metrology::interrupt::Interruption,
    },
    /// A click (or a scene's point) outside the photo, or not a finite number.
    #[error(
        "`{field}` at ({x}, {y}) lies outside the {width} x {height} photo (0 <= x <= {width}, 0 <= y <= {height})"
    )]
    ClickOutsidePhoto {
        /// The point's field path (`objects[0].base.near`), or `click`.
        field: String,
        /// Its x, pixels.
        x: f64,
        /// Its y, pixels.
        y: f64,
        /// The photo's width, pixels.
        width: u32,
        /// The photo's height, pixels.
        height: u32,
    },
    /// A scene written for a photo of another size.
    #[error(
        "the scene's image is {scene_width} x {scene_height} pixels but the photo is {photo_width} x {photo_height}: is it the scene of this photo?"
    )]
    ImageSizeMismatch {
        /// The scene's `image.width`.
        scene_width: u32,
        /// The scene's `image.height`.
        scene_height: u32,
        /// The photo's width.
        photo_width: u32,
        /// The photo's height.
        photo_height: u32,
    },
    /// A scene that cannot be read or whose vanishing points cannot be resolved.
    #[error("the scene: {message}")]
    InvalidScene {
        /// What is wrong, naming the field and value.
        message: String,
    },
}
