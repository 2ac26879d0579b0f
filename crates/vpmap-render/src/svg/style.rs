//! The floor plan's options ([`FloorPlanStyle`]), and what every part of the drawing shares:
//! its font, colours, limits and the hidden floor's pattern.

use vpmap_metrology::map::MapPoint;

/// Font list of every text element. resvg needs `sans-serif` mapped to an installed family, see
/// [`crate::svg_to_png`].
pub const FONT_FAMILY: &str = "DejaVu Sans, sans-serif";

/// Longest object name drawn in full; longer names are cut with an ellipsis.
pub(super) const MAX_NAME_CHARS: usize = 40;
/// Largest pixel coordinate written.
pub(super) const MAX_PX: f64 = 1.0e6;
/// Smallest font size, pixels, before text is cut instead of shrunk.
pub(super) const MIN_FONT_PX: f64 = 8.0;
/// Id of the hatch pattern of the hidden floor (defined only when the map has some).
pub(super) const HIDDEN_PATTERN_ID: &str = "hidden-hatch";
/// Legend text of the hidden floor.
pub(super) const HIDDEN_LEGEND: &str = "hidden from the camera";
/// Paint of the hidden floor: the hatch pattern.
pub(super) const HIDDEN_PATTERN_FILL: &str = "url(#hidden-hatch)";

/// Colours of the drawing (also used in the legend).
pub(super) mod colour {
    pub const PAPER: &str = "#ffffff";
    pub const PLOT: &str = "#fafafa";
    pub const FREE_FILL: &str = "#dcefd7";
    pub const FREE_STROKE: &str = "#8fbf85";
    pub const HIDDEN_FILL: &str = "#e3e3e3";
    pub const HIDDEN_HATCH: &str = "#8c8c8c";
    pub const HIDDEN_STROKE: &str = "#9a9a9a";
    pub const FLOOR: &str = "#333333";
    pub const GRID: &str = "#9a9a9a";
    /// The floor in view, opaque under the free space (so that free space shows
    /// [`FREE_FILL`] itself and the legend's swatches match what is drawn).
    pub const FOV_FILL: &str = "#fcf5e0";
    pub const FOV_RAY: &str = "#b8860b";
    pub const BOX_FILL: &str = "#a9cbe8";
    pub const BOX_STROKE: &str = "#2f6690";
    pub const FOOTPRINT_FILL: &str = "#f5c89a";
    pub const FOOTPRINT_STROKE: &str = "#b5651d";
    pub const CAMERA: &str = "#d62728";
    pub const ELLIPSE: &str = "#c2185b";
    pub const PATH: &str = "#6a3d9a";
    pub const TEXT: &str = "#1a1a1a";
    pub const MUTED: &str = "#555555";
}

/// Options of [`floor_plan_svg`](super::floor_plan_svg).
// The flags are independent layer switches, not a state machine.
#[allow(clippy::struct_excessive_bools)]
#[derive(Debug, Clone, PartialEq)]
pub struct FloorPlanStyle {
    /// Width of the picture, pixels (clamped to 200..=20000); the height follows the map.
    pub width_px: u32,
    /// First line of the title; `None` gives "Floor map".
    pub title: Option<String>,
    /// Draw the grid lines (1-2-5 steps, about 5 to 20 lines across the map).
    pub show_grid: bool,
    /// Label each object with its name and sizes.
    pub show_labels: bool,
    /// Draw the camera's horizontal field of view as a wedge from the station point.
    pub show_field_of_view: bool,
    /// Draw the legend next to the scale bar.
    pub show_legend: bool,
    /// Empty border around the map's bounds, as a fraction of their larger side.
    pub margin_frac: f64,
    /// A planned path to draw over the map (map coordinates), with its legend text; empty for
    /// none.
    pub path: Vec<MapPoint>,
    /// Legend text of `path`, e.g. "path (A*, 9.16 m)".
    pub path_label: String,
}

impl Default for FloorPlanStyle {
    fn default() -> Self {
        Self {
            width_px: 1000,
            title: None,
            show_grid: true,
            show_labels: true,
            show_field_of_view: true,
            show_legend: true,
            margin_frac: 0.06,
            path: Vec::new(),
            path_label: String::new(),
        }
    }
}
