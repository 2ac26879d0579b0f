//! How numbers and units read in messages: the one number formatter of the command line's and
//! the page's error messages, and the names of a map's units.

use vpmap_metrology::map::Units;

/// A number for a message: plain when readable, scientific when huge or tiny (the one
/// formatter of numbers in the command line's and the page's error messages).
///
/// # Example
/// ```
/// assert_eq!(vpmap_pipeline::num(0.05), "0.05");
/// assert_eq!(vpmap_pipeline::num(1e300), "1e300");
/// ```
#[must_use]
pub fn num(v: f64) -> String {
    vpmap_files::num(v)
}

/// The name of a map's unit in messages and the web API: `m` or `camera_heights`.
#[must_use]
pub fn units_name(units: Units) -> &'static str {
    match units {
        Units::Meters => "m",
        Units::CameraHeights => "camera_heights",
    }
}
