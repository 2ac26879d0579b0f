//! Floor plans as SVG.
//!
//! The picture is north-up in the camera's sense: `+y` (forward) points up the page, `+x` to the
//! right, so the station point sits near the bottom with the room in front of it. One map unit
//! is the same number of pixels along both axes. Points that are NaN or infinite are left out
//! (a broken map gives a partial picture, never a panic).
//!
//! The SVG is written by hand with `write!`: it is a few dozen elements, and doing it ourselves
//! keeps the dependency tree small, the number formatting under control (two decimals of a
//! pixel) and the output byte-for-byte deterministic, which snapshot tests need. The `svg`
//! crate would add a dependency without removing any of the layout work.

use std::fmt::Write as _;

use vpmap_metrology::map::{FloorMap, MapObject, MapPoint, PolygonWithHoles, Units};
use vpmap_metrology::reconstruct::ObjectKind;

use crate::geometry::{Bounds, is_finite};
use crate::metrics::text_width_px;

/// Font list of every text element. resvg needs `sans-serif` mapped to an installed family, see
/// [`crate::svg_to_png`].
pub const FONT_FAMILY: &str = "DejaVu Sans, sans-serif";

/// Largest plot height / plot width; deeper maps get a wider x range instead of a taller picture.
const MAX_PLOT_ASPECT: f64 = 1.5;
/// Smallest plot height / plot width; shallow maps get a deeper y range.
const MIN_PLOT_ASPECT: f64 = 0.35;
/// Longest object name drawn in full; longer names are cut with an ellipsis.
const MAX_NAME_CHARS: usize = 40;
/// Largest pixel coordinate written.
const MAX_PX: f64 = 1.0e6;
/// Smallest font size, pixels, before text is cut instead of shrunk.
const MIN_FONT_PX: f64 = 8.0;
/// Id of the hatch pattern of the hidden floor (defined only when the map has some).
const HIDDEN_PATTERN_ID: &str = "hidden-hatch";
/// Legend text of the hidden floor.
const HIDDEN_LEGEND: &str = "hidden from the camera";
/// Paint of the hidden floor: the hatch pattern.
const HIDDEN_PATTERN_FILL: &str = "url(#hidden-hatch)";

/// Colours of the drawing (also used in the legend).
mod colour {
    pub const PAPER: &str = "#ffffff";
    pub const PLOT: &str = "#fafafa";
    pub const FREE_FILL: &str = "#dcefd7";
    pub const FREE_STROKE: &str = "#8fbf85";
    pub const HIDDEN_FILL: &str = "#e3e3e3";
    pub const HIDDEN_HATCH: &str = "#8c8c8c";
    pub const HIDDEN_STROKE: &str = "#9a9a9a";
    pub const FLOOR: &str = "#333333";
    pub const GRID: &str = "#9a9a9a";
    pub const FOV_FILL: &str = "#ffe8a3";
    pub const FOV_RAY: &str = "#b8860b";
    pub const BOX_FILL: &str = "#a9cbe8";
    pub const BOX_STROKE: &str = "#2f6690";
    pub const FOOTPRINT_FILL: &str = "#f5c89a";
    pub const FOOTPRINT_STROKE: &str = "#b5651d";
    pub const CAMERA: &str = "#d62728";
    pub const PATH: &str = "#6a3d9a";
    pub const TEXT: &str = "#1a1a1a";
    pub const MUTED: &str = "#555555";
}

/// Options of [`floor_plan_svg`].
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

/// Unit words of a map.
struct UnitNames {
    /// After a length: "m".
    short: &'static str,
    /// After an area: "m²".
    area: &'static str,
    /// In the title: "metres".
    long: &'static str,
}

fn unit_names(units: Units) -> UnitNames {
    match units {
        Units::Meters => UnitNames {
            short: "m",
            area: "m²",
            long: "metres",
        },
        Units::CameraHeights => UnitNames {
            short: "ch",
            area: "ch²",
            long: "camera heights (ch; the camera is 1 ch above the floor)",
        },
    }
}

/// Escape the five XML special characters and drop characters XML 1.0 forbids.
#[must_use]
pub fn escape_xml(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(' '),
            c if u32::from(c) < 0x20 || c == '\u{fffe}' || c == '\u{ffff}' => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
}

/// `text` cut to at most `max_chars` characters, ending in an ellipsis when cut.
fn truncate(text: &str, max_chars: usize) -> String {
    if text.chars().count() <= max_chars {
        return text.to_owned();
    }
    let mut out: String = text.chars().take(max_chars.saturating_sub(1)).collect();
    out.push('…');
    out
}

/// A font size at most `font_px` at which `text` fits in `max_width_px`, and the text, cut if
/// even [`MIN_FONT_PX`] is too large.
fn fit_text(text: &str, font_px: f64, max_width_px: f64, bold: bool) -> (String, f64) {
    let width = text_width_px(text, font_px, bold);
    if width <= max_width_px {
        return (text.to_owned(), font_px);
    }
    let size = (font_px * max_width_px / width).max(MIN_FONT_PX);
    let mut chars = text.chars().count();
    let mut cut = text.to_owned();
    while chars > 1 && text_width_px(&cut, size, bold) > max_width_px {
        chars -= 1;
        cut = truncate(text, chars);
    }
    (cut, size)
}

/// The 1-2-5 step for grid lines over `span`: 1 when that gives 5 to 20 lines (whole metres or
/// camera heights), else the step whose line count is nearest 10.
#[must_use]
pub(crate) fn grid_step(span: f64) -> f64 {
    if !(span.is_finite() && span > 0.0) {
        return 1.0;
    }
    if (5.0..=20.0).contains(&span) {
        return 1.0;
    }
    let e = span.log10().floor() as i32;
    let mut best = (f64::INFINITY, 1.0);
    for k in (e - 2)..=(e + 1) {
        for m in [1.0, 2.0, 5.0] {
            let step = m * 10f64.powi(k);
            let score = (span / step / 10.0).ln().abs();
            if score < best.0 {
                best = (score, step);
            }
        }
    }
    best.1
}

/// The largest 1-2-5 value not above `limit` (for the scale bar).
fn nice_at_most(limit: f64) -> f64 {
    if !(limit.is_finite() && limit > 0.0) {
        return 1.0;
    }
    let e = limit.log10().floor() as i32;
    let mut best = 10f64.powi(e - 1);
    for k in (e - 1)..=e {
        for m in [1.0, 2.0, 5.0] {
            let v = m * 10f64.powi(k);
            if v <= limit * (1.0 + 1e-12) && v > best {
                best = v;
            }
        }
    }
    best
}

/// Decimals that show a multiple of `step` exactly (0 for 1 m, 1 for 0.5 m, 2 for 0.05 m).
fn decimals_for(step: f64) -> usize {
    let d = -(step.log10() + 1e-9).floor();
    if d.is_finite() && d > 0.0 {
        d.min(12.0) as usize
    } else {
        0
    }
}

/// `v` with `decimals` decimals and no minus sign on zero.
fn fmt_num(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_owned(),
        _ => s,
    }
}

/// Map coordinates to picture pixels: `+y` up the page.
#[derive(Debug, Clone, Copy)]
struct Frame {
    /// Map x at the plot's left edge.
    x_min: f64,
    /// Map y at the plot's top edge.
    y_max: f64,
    /// Pixels per map unit.
    px_per_unit: f64,
    /// Plot rectangle, pixels.
    left: f64,
    top: f64,
    width: f64,
    height: f64,
}

impl Frame {
    /// Pixel position of a map point, kept within [`MAX_PX`] of the origin (only points far
    /// outside the plot are moved; resvg overflows on coordinates beyond `i32`).
    fn px(&self, p: MapPoint) -> (f64, f64) {
        (
            (self.left + (p[0] - self.x_min) * self.px_per_unit).clamp(-MAX_PX, MAX_PX),
            (self.top + (self.y_max - p[1]) * self.px_per_unit).clamp(-MAX_PX, MAX_PX),
        )
    }

    /// The map point is inside the plot.
    fn shows(&self, p: MapPoint) -> bool {
        (self.x_min..=self.x_max()).contains(&p[0]) && (self.y_min()..=self.y_max).contains(&p[1])
    }

    fn x_max(&self) -> f64 {
        self.x_min + self.width / self.px_per_unit
    }

    fn y_min(&self) -> f64 {
        self.y_max - self.height / self.px_per_unit
    }

    fn contains(&self, r: &Rect) -> bool {
        r.x >= self.left
            && r.y >= self.top
            && r.x + r.w <= self.left + self.width
            && r.y + r.h <= self.top + self.height
    }
}

/// A rectangle in pixels, for label placement.
#[derive(Debug, Clone, Copy)]
struct Rect {
    x: f64,
    y: f64,
    w: f64,
    h: f64,
}

impl Rect {
    fn overlaps(&self, o: &Rect) -> bool {
        self.x < o.x + o.w && o.x < self.x + self.w && self.y < o.y + o.h && o.y < self.y + self.h
    }

    /// Moved inside `frame` (as far as it fits).
    fn clamped_into(self, frame: &Frame) -> Rect {
        let x = self
            .x
            .min(frame.left + frame.width - self.w)
            .max(frame.left);
        let y = self.y.min(frame.top + frame.height - self.h).max(frame.top);
        Rect { x, y, ..self }
    }

    /// Distance from a point to this rectangle (0 inside).
    fn distance_to(&self, (px, py): (f64, f64)) -> f64 {
        let dx = (self.x - px).max(px - (self.x + self.w)).max(0.0);
        let dy = (self.y - py).max(py - (self.y + self.h)).max(0.0);
        dx.hypot(dy)
    }
}

/// SVG path data of a closed ring (finite points only), or `None` below 3 points.
fn ring_path(frame: &Frame, ring: &[MapPoint]) -> Option<String> {
    let pts: Vec<(f64, f64)> = ring
        .iter()
        .filter(|p| is_finite(**p))
        .map(|p| frame.px(*p))
        .collect();
    if pts.len() < 3 {
        return None;
    }
    let mut d = String::new();
    for (i, (x, y)) in pts.iter().enumerate() {
        let cmd = if i == 0 { 'M' } else { 'L' };
        let _ = write!(d, "{cmd}{x:.2} {y:.2} ");
    }
    d.push('Z');
    Some(d)
}

/// SVG path data of a polygon with holes (to be filled with `fill-rule="evenodd"`), or `None`
/// when its outer ring has fewer than 3 finite points.
fn polygon_path(frame: &Frame, poly: &PolygonWithHoles) -> Option<String> {
    let mut d = ring_path(frame, &poly.exterior)?;
    for hole in &poly.holes {
        if let Some(h) = ring_path(frame, hole) {
            d.push(' ');
            d.push_str(&h);
        }
    }
    Some(d)
}

/// The label of an object: name line and sizes line.
fn object_label(o: &MapObject, u: &UnitNames, decimals: usize) -> (String, String) {
    let name = truncate(o.name.trim(), MAX_NAME_CHARS);
    let name = if name.is_empty() {
        "(unnamed)".to_owned()
    } else {
        name
    };
    let height = match o.height {
        Some(h) => format!("h {} {}", fmt_num(h, decimals), u.short),
        None => "h unknown".to_owned(),
    };
    let sizes = match (o.kind, o.size) {
        (ObjectKind::Box, Some(s)) => format!(
            "{} × {} {}, {height}",
            fmt_num(s.length, decimals),
            fmt_num(s.breadth, decimals),
            u.short
        ),
        _ => format!("area {} {}, {height}", fmt_num(o.area, decimals), u.area),
    };
    (name, sizes)
}

/// Where an object's label is anchored: its centroid when that is in the plot, else the mean
/// of its finite corners.
fn label_anchor(o: &MapObject, frame: &Frame) -> Option<MapPoint> {
    if is_finite(o.centroid) && frame.shows(o.centroid) {
        return Some(o.centroid);
    }
    let pts: Vec<&MapPoint> = o.footprint.iter().filter(|p| is_finite(**p)).collect();
    if pts.is_empty() {
        return None;
    }
    let n = pts.len() as f64;
    Some([
        pts.iter().map(|p| p[0]).sum::<f64>() / n,
        pts.iter().map(|p| p[1]).sum::<f64>() / n,
    ])
}

/// One legend entry: its swatch and its text.
enum Swatch {
    Fill {
        fill: &'static str,
        stroke: &'static str,
        dashed: bool,
    },
    Line {
        stroke: &'static str,
        dashed: bool,
    },
    Dot,
}

/// The plot frame of a map for a picture `width_px` wide, with the plot starting at `top_px`.
fn plot_frame(map: &FloorMap, style: &FloorPlanStyle, left: f64, width: f64, top: f64) -> Frame {
    let bounds = Bounds::of_map(map);
    let fallback = if map.camera.height.is_finite() && map.camera.height > 0.0 {
        map.camera.height
    } else {
        1.0
    };
    let size = bounds.size_or(0.0);
    let margin_frac = if style.margin_frac.is_finite() {
        style.margin_frac.clamp(0.0, 1.0)
    } else {
        0.06
    };
    let padded = if size > 0.0 {
        bounds.padded(size * margin_frac)
    } else {
        bounds.padded(fallback)
    };
    let [mut dx, mut dy] = padded.span();
    let cx = f64::midpoint(padded.min[0], padded.max[0]);
    let cy = f64::midpoint(padded.min[1], padded.max[1]);
    if dy > MAX_PLOT_ASPECT * dx {
        dx = dy / MAX_PLOT_ASPECT;
    }
    if dy < MIN_PLOT_ASPECT * dx {
        dy = MIN_PLOT_ASPECT * dx;
    }
    let px_per_unit = width / dx;
    Frame {
        x_min: cx - dx / 2.0,
        y_max: cy + dy / 2.0,
        px_per_unit,
        left,
        top,
        width,
        height: dy * px_per_unit,
    }
}

/// Draw a floor map as an SVG floor plan.
///
/// Shows the free space (shaded, holes cut with `fill-rule="evenodd"`), the parts of it hidden
/// from the camera behind objects (hatched with thin grey diagonal lines on light grey, legend
/// entry "hidden from the camera"; only when the map has some), the floor outline, each
/// object as a filled polygon labelled with its name and sizes (a box's length × breadth and
/// height; a footprint's area and height), the station point, the camera's horizontal field
/// of view, a grid with labelled axes, a scale bar, a legend and a title with the camera's
/// pitch, roll and height. `+y` (forward) points up the page. Labels are moved apart when
/// they would overlap, with a leader line back to their object. Object names are
/// XML-escaped. Non-finite points are skipped.
///
/// # Example
/// ```
/// use vpmap_metrology::map::{build_map, BuildOptions};
/// use vpmap_metrology::synth::{synthesize, SynthOptions};
/// use vpmap_render::{floor_plan_svg, FloorPlanStyle};
/// let (scene, _) = synthesize(&SynthOptions::default()).unwrap();
/// let map = build_map(&scene, &BuildOptions::default()).unwrap();
/// let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
/// assert!(svg.starts_with("<?xml") && svg.contains(r#"width="1000""#));
/// assert!(svg.contains(&map.objects[0].name));
/// ```
///
/// # Complexity
/// `O(n + k²)` for `n` polygon corners and `k` objects (label placement).
#[must_use]
pub fn floor_plan_svg(map: &FloorMap, style: &FloorPlanStyle) -> String {
    let width = f64::from(style.width_px.clamp(200, 20_000));
    let f = (width / 1000.0).clamp(0.6, 2.0);
    let pad = 16.0 * f;
    let u = unit_names(map.units);

    // Title band.
    let title_px = 20.0 * f;
    let sub_px = 13.0 * f;
    let title_base = pad + title_px;
    let sub_base = title_base + 1.55 * sub_px;
    let plot_top = sub_base + 18.0 * f;

    // Plot.
    let plot_left = pad + 54.0 * f;
    let plot_width = width - plot_left - pad - 10.0 * f;
    let frame = plot_frame(map, style, plot_left, plot_width, plot_top);
    let plot_bottom = frame.top + frame.height;
    let span = (frame.x_max() - frame.x_min).max(frame.y_max - frame.y_min());
    let step = grid_step(span);
    let tick_decimals = decimals_for(step);
    let size_decimals = (tick_decimals + 1).max(2);

    // Footer: scale bar then legend, flowing onto more rows when needed.
    let footer_top = plot_bottom + 48.0 * f;
    let row_px = 24.0 * f;
    let label_px = 12.0 * f;
    let bar_units = nice_at_most(0.3 * (frame.x_max() - frame.x_min));
    let bar_px = bar_units * frame.px_per_unit;
    let bar_label = format!(
        "{} {}",
        fmt_num(bar_units, decimals_for(bar_units)),
        u.short
    );
    let bar_x = pad + text_width_px("0", label_px, false) + 5.0 * f;
    let bar_width = bar_x - pad + bar_px + 5.0 * f + text_width_px(&bar_label, label_px, false);

    let fov_deg = map.camera.horizontal_fov_deg;
    let fov_ok = fov_deg.iter().all(|a| a.is_finite())
        && fov_deg[1] > fov_deg[0]
        && fov_deg[1] - fov_deg[0] < 360.0;
    let hidden_paths: Vec<String> = map
        .hidden
        .iter()
        .filter_map(|p| polygon_path(&frame, p))
        .collect();
    let mut legend: Vec<(Swatch, String)> = Vec::new();
    if style.show_legend {
        if !map.free_space.is_empty() {
            legend.push((
                Swatch::Fill {
                    fill: colour::FREE_FILL,
                    stroke: colour::FREE_STROKE,
                    dashed: false,
                },
                "free space".to_owned(),
            ));
        }
        if !hidden_paths.is_empty() {
            legend.push((
                Swatch::Fill {
                    fill: HIDDEN_PATTERN_FILL,
                    stroke: colour::HIDDEN_STROKE,
                    dashed: false,
                },
                HIDDEN_LEGEND.to_owned(),
            ));
        }
        if map.floor.len() >= 3 {
            legend.push((
                Swatch::Line {
                    stroke: colour::FLOOR,
                    dashed: false,
                },
                "floor outline".to_owned(),
            ));
        }
        if map.objects.iter().any(|o| o.kind == ObjectKind::Box) {
            legend.push((
                Swatch::Fill {
                    fill: colour::BOX_FILL,
                    stroke: colour::BOX_STROKE,
                    dashed: false,
                },
                "box".to_owned(),
            ));
        }
        if map.objects.iter().any(|o| o.kind == ObjectKind::Footprint) {
            legend.push((
                Swatch::Fill {
                    fill: colour::FOOTPRINT_FILL,
                    stroke: colour::FOOTPRINT_STROKE,
                    dashed: false,
                },
                "footprint".to_owned(),
            ));
        }
        if map.objects.iter().any(|o| o.height.is_none()) {
            legend.push((
                Swatch::Fill {
                    fill: colour::PAPER,
                    stroke: colour::MUTED,
                    dashed: true,
                },
                "height unknown".to_owned(),
            ));
        }
        legend.push((Swatch::Dot, "camera (station point)".to_owned()));
        if style.path.len() >= 2 {
            legend.push((
                Swatch::Line {
                    stroke: colour::PATH,
                    dashed: false,
                },
                if style.path_label.is_empty() {
                    "planned path".to_owned()
                } else {
                    style.path_label.clone()
                },
            ));
        }
        if style.show_field_of_view && fov_ok {
            legend.push((
                Swatch::Line {
                    stroke: colour::FOV_RAY,
                    dashed: true,
                },
                if map.camera.view_on_floor.len() >= 3 {
                    format!(
                        "floor in view (field of view {:.0}°)",
                        fov_deg[1] - fov_deg[0]
                    )
                } else {
                    format!("field of view {:.0}°", fov_deg[1] - fov_deg[0])
                },
            ));
        }
        if style.show_grid {
            legend.push((
                Swatch::Line {
                    stroke: colour::GRID,
                    dashed: false,
                },
                format!("grid {} {}", fmt_num(step, tick_decimals), u.short),
            ));
        }
    }
    let swatch_px = 18.0 * f;
    let gap_px = 16.0 * f;
    let right_edge = width - pad;
    let mut legend_pos: Vec<(f64, f64)> = Vec::with_capacity(legend.len());
    let mut x = pad + bar_width + 2.0 * gap_px;
    let mut row = 0.0;
    for (_, text) in &legend {
        let w = swatch_px + 6.0 * f + text_width_px(text, label_px, false);
        if x + w > right_edge && x > pad {
            row += 1.0;
            x = pad;
        }
        legend_pos.push((x, footer_top + row * row_px));
        x += w + gap_px;
    }
    let height = (footer_top + (row + 1.0) * row_px + pad).ceil();

    let mut out = String::with_capacity(16 * 1024);
    let title = style.title.as_deref().unwrap_or("Floor map");
    let _ = writeln!(out, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" font-family="{FONT_FAMILY}" fill="{}">"#,
        colour::TEXT
    );
    let _ = writeln!(out, "<title>{}</title>", escape_xml(title));
    let _ = writeln!(
        out,
        "<desc>Floor plan drawn by vpmap-render: +y forward points up, +x right, units {}.</desc>",
        u.long
    );
    let _ = write!(
        out,
        r#"<defs><clipPath id="plot-clip"><rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}"/></clipPath>"#,
        frame.left, frame.top, frame.width, frame.height
    );
    if !hidden_paths.is_empty() {
        // Thin grey lines at 45° on a light grey ground, in page pixels (the same spacing in
        // the plot and in the legend swatch).
        let tile = 7.0 * f;
        let _ = write!(
            out,
            r#"<pattern id="{HIDDEN_PATTERN_ID}" patternUnits="userSpaceOnUse" x="0" y="0" width="{tile:.2}" height="{tile:.2}" patternTransform="rotate(45)"><rect x="0" y="0" width="{tile:.2}" height="{tile:.2}" fill="{}"/><line x1="{:.2}" y1="0" x2="{:.2}" y2="{tile:.2}" stroke="{}" stroke-width="{:.2}"/></pattern>"#,
            colour::HIDDEN_FILL,
            tile / 2.0,
            tile / 2.0,
            colour::HIDDEN_HATCH,
            1.1 * f
        );
    }
    let _ = writeln!(out, "</defs>");
    let _ = writeln!(
        out,
        r#"<rect x="0" y="0" width="{width:.0}" height="{height:.0}" fill="{}"/>"#,
        colour::PAPER
    );

    // Everything in map coordinates, clipped to the plot.
    let _ = writeln!(out, r#"<g id="map" clip-path="url(#plot-clip)">"#);
    let _ = writeln!(
        out,
        r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{}"/>"#,
        frame.left,
        frame.top,
        frame.width,
        frame.height,
        colour::PLOT
    );

    let _ = writeln!(out, r#"<g id="free-space">"#);
    for d in map
        .free_space
        .iter()
        .filter_map(|p| polygon_path(&frame, p))
    {
        let _ = writeln!(
            out,
            r#"<path d="{d}" fill="{}" fill-rule="evenodd" stroke="{}" stroke-width="{:.2}"/>"#,
            colour::FREE_FILL,
            colour::FREE_STROKE,
            0.8 * f
        );
    }
    let _ = writeln!(out, "</g>");

    let station = frame.px([0.0, 0.0]);
    let view: Vec<MapPoint> = map
        .camera
        .view_on_floor
        .iter()
        .copied()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .collect();
    if style.show_field_of_view && view.len() >= 3 {
        // The floor the photo shows: the image rectangle projected onto the floor.
        if let Some(d) = ring_path(&frame, &view) {
            let _ = writeln!(out, r#"<g id="field-of-view">"#);
            let _ = writeln!(
                out,
                r#"<path d="{d}" fill="{}" fill-opacity="0.3" stroke="{}" stroke-width="{:.2}" stroke-dasharray="{:.1} {:.1}"/>"#,
                colour::FOV_FILL,
                colour::FOV_RAY,
                1.2 * f,
                6.0 * f,
                4.0 * f
            );
            let _ = writeln!(out, "</g>");
        }
    } else if style.show_field_of_view && fov_ok {
        let reach = 3.0 * span;
        let arc_steps = 32;
        let mut d = format!("M{:.2} {:.2} ", station.0, station.1);
        for i in 0..=arc_steps {
            let a = (fov_deg[0] + (fov_deg[1] - fov_deg[0]) * f64::from(i) / f64::from(arc_steps))
                .to_radians();
            let (x, y) = frame.px([reach * a.sin(), reach * a.cos()]);
            let _ = write!(d, "L{x:.2} {y:.2} ");
        }
        d.push('Z');
        let _ = writeln!(out, r#"<g id="field-of-view">"#);
        let _ = writeln!(
            out,
            r#"<path d="{d}" fill="{}" fill-opacity="0.3" stroke="none"/>"#,
            colour::FOV_FILL
        );
        for a in fov_deg {
            let a = a.to_radians();
            let (x, y) = frame.px([reach * a.sin(), reach * a.cos()]);
            let _ = writeln!(
                out,
                r#"<line x1="{:.2}" y1="{:.2}" x2="{x:.2}" y2="{y:.2}" stroke="{}" stroke-width="{:.2}" stroke-dasharray="{:.1} {:.1}"/>"#,
                station.0,
                station.1,
                colour::FOV_RAY,
                1.2 * f,
                6.0 * f,
                4.0 * f
            );
        }
        let _ = writeln!(out, "</g>");
    }

    // Hidden floor: above the free space and the field of view (so its hatching is not tinted),
    // below the grid and the objects.
    if !hidden_paths.is_empty() {
        let _ = writeln!(out, r#"<g id="hidden">"#);
        for d in &hidden_paths {
            let _ = writeln!(
                out,
                r#"<path class="hidden" d="{d}" fill="{HIDDEN_PATTERN_FILL}" fill-rule="evenodd" stroke="{}" stroke-width="{:.2}" stroke-linejoin="round"/>"#,
                colour::HIDDEN_STROKE,
                0.6 * f
            );
        }
        let _ = writeln!(out, "</g>");
    }

    if style.show_grid {
        let _ = writeln!(
            out,
            r#"<g id="grid" stroke="{}" stroke-width="{:.2}" stroke-opacity="0.45">"#,
            colour::GRID,
            0.7 * f
        );
        for k in grid_indices(frame.x_min, frame.x_max(), step) {
            let (x, _) = frame.px([k * step, 0.0]);
            let _ = writeln!(
                out,
                r#"<line x1="{x:.2}" y1="{:.2}" x2="{x:.2}" y2="{plot_bottom:.2}"/>"#,
                frame.top
            );
        }
        for k in grid_indices(frame.y_min(), frame.y_max, step) {
            let (_, y) = frame.px([0.0, k * step]);
            let _ = writeln!(
                out,
                r#"<line x1="{:.2}" y1="{y:.2}" x2="{:.2}" y2="{y:.2}"/>"#,
                frame.left,
                frame.left + frame.width
            );
        }
        let _ = writeln!(out, "</g>");
    }

    if let Some(d) = ring_path(&frame, &map.floor) {
        let _ = writeln!(
            out,
            r#"<path id="floor" d="{d}" fill="none" stroke="{}" stroke-width="{:.2}" stroke-linejoin="round"/>"#,
            colour::FLOOR,
            2.2 * f
        );
    }

    let _ = writeln!(out, r#"<g id="objects" stroke-linejoin="round">"#);
    for (i, o) in map.objects.iter().enumerate() {
        let Some(d) = ring_path(&frame, &o.footprint) else {
            continue;
        };
        let (fill, stroke) = match o.kind {
            ObjectKind::Box => (colour::BOX_FILL, colour::BOX_STROKE),
            ObjectKind::Footprint => (colour::FOOTPRINT_FILL, colour::FOOTPRINT_STROKE),
        };
        let dash = if o.height.is_none() {
            format!(r#" stroke-dasharray="{:.1} {:.1}""#, 5.0 * f, 3.0 * f)
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            r#"<path id="object-{i}" class="object" d="{d}" fill="{fill}" fill-opacity="0.9" stroke="{stroke}" stroke-width="{:.2}"{dash}><title>{}</title></path>"#,
            1.5 * f,
            escape_xml(&o.name)
        );
    }
    let _ = writeln!(out, "</g>");

    let path_px: Vec<(f64, f64)> = style
        .path
        .iter()
        .filter(|p| is_finite(**p))
        .map(|p| frame.px(*p))
        .collect();
    if path_px.len() >= 2 {
        let points: Vec<String> = path_px
            .iter()
            .map(|(x, y)| format!("{x:.2},{y:.2}"))
            .collect();
        let _ = writeln!(out, r#"<g id="path">"#);
        let _ = writeln!(
            out,
            r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="{:.2}" stroke-linejoin="round" stroke-linecap="round"/>"#,
            points.join(" "),
            colour::PATH,
            3.0 * f
        );
        for (i, (x, y)) in [path_px[0], path_px[path_px.len() - 1]].iter().enumerate() {
            let _ = writeln!(
                out,
                r##"<circle class="{}" cx="{x:.2}" cy="{y:.2}" r="{:.2}" fill="{}" stroke="#ffffff" stroke-width="{:.2}"/>"##,
                if i == 0 { "path-start" } else { "path-goal" },
                5.0 * f,
                colour::PATH,
                1.5 * f
            );
        }
        let _ = writeln!(out, "</g>");
    }

    // Station point: marker with an arrow along +y, label to its right.
    let mut placed: Vec<Rect> = Vec::new();
    let r = 6.0 * f;
    let station_label = "camera";
    let station_rect = Rect {
        x: station.0 - r - 2.0,
        y: station.1 - 2.6 * r,
        w: 2.0 * r + 6.0 * f + text_width_px(station_label, label_px, false) + 4.0,
        h: 3.8 * r,
    };
    placed.push(station_rect);

    if style.show_labels {
        let name_px = 12.0 * f;
        let size_px = 11.0 * f;
        let line_gap = 1.25 * name_px;
        let _ = writeln!(out, r#"<g id="labels" text-anchor="middle">"#);
        let object_px: Vec<PixelPolygon> = map
            .objects
            .iter()
            .map(|o| {
                o.footprint
                    .iter()
                    .filter(|p| is_finite(**p))
                    .map(|p| frame.px(*p))
                    .collect()
            })
            .collect();
        for (i, o) in map.objects.iter().enumerate() {
            let Some(anchor) = label_anchor(o, &frame) else {
                continue;
            };
            let anchor_px = frame.px(anchor);
            let (name, sizes) = object_label(o, &u, size_decimals);
            let w = text_width_px(&name, name_px, true).max(text_width_px(&sizes, size_px, false))
                + 6.0 * f;
            let h = line_gap + size_px * 1.4 + 2.0 * f;
            let centred = Rect {
                x: anchor_px.0 - w / 2.0,
                y: anchor_px.1 - h / 2.0,
                w,
                h,
            };
            let rect = place_label(centred, Some(i), &object_px, &placed, &frame);
            placed.push(rect);
            if rect.distance_to(anchor_px) > 1.0 {
                let (tx, ty) = (
                    anchor_px.0.clamp(rect.x, rect.x + rect.w),
                    anchor_px.1.clamp(rect.y, rect.y + rect.h),
                );
                let _ = writeln!(
                    out,
                    r#"<line x1="{:.2}" y1="{:.2}" x2="{tx:.2}" y2="{ty:.2}" stroke="{}" stroke-width="{:.2}"/><circle cx="{:.2}" cy="{:.2}" r="{:.2}" fill="{}" stroke="none"/>"#,
                    anchor_px.0,
                    anchor_px.1,
                    colour::MUTED,
                    0.8 * f,
                    anchor_px.0,
                    anchor_px.1,
                    1.8 * f,
                    colour::MUTED
                );
            }
            let _ = writeln!(
                out,
                r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" rx="{:.1}" fill="{}" fill-opacity="0.85" stroke="{}" stroke-width="{:.2}" stroke-opacity="0.5"/>"#,
                rect.x,
                rect.y,
                rect.w,
                rect.h,
                3.0 * f,
                colour::PAPER,
                colour::MUTED,
                0.6 * f
            );
            let cx = rect.x + rect.w / 2.0;
            let name_base = rect.y + name_px + 1.5 * f;
            let _ = writeln!(
                out,
                r#"<text x="{cx:.2}" y="{name_base:.2}" font-size="{name_px:.1}" font-weight="bold">{}</text>"#,
                escape_xml(&name)
            );
            let _ = writeln!(
                out,
                r#"<text x="{cx:.2}" y="{:.2}" font-size="{size_px:.1}">{}</text>"#,
                name_base + line_gap,
                escape_xml(&sizes)
            );
        }
        let _ = writeln!(out, "</g>");
    }

    let _ = writeln!(out, r#"<g id="station-point">"#);
    let _ = writeln!(
        out,
        r#"<path d="M{:.2} {:.2} L{:.2} {:.2} L{:.2} {:.2} Z" fill="{}" stroke="none"/>"#,
        station.0,
        station.1 - 2.4 * r,
        station.0 - 0.6 * r,
        station.1 - 1.3 * r,
        station.0 + 0.6 * r,
        station.1 - 1.3 * r,
        colour::CAMERA
    );
    let _ = writeln!(
        out,
        r#"<circle cx="{:.2}" cy="{:.2}" r="{r:.2}" fill="{}" stroke="{}" stroke-width="{:.2}"/>"#,
        station.0,
        station.1,
        colour::CAMERA,
        colour::PAPER,
        1.5 * f
    );
    let _ = writeln!(
        out,
        r#"<text x="{:.2}" y="{:.2}" font-size="{label_px:.1}" stroke="{}" stroke-width="{:.2}" paint-order="stroke">{station_label}</text>"#,
        station.0 + r + 5.0 * f,
        station.1 + 0.35 * label_px,
        colour::PAPER,
        3.0 * f
    );
    let _ = writeln!(out, "</g>");
    let _ = writeln!(out, "</g>");

    // Frame, ticks and axis titles.
    let _ = writeln!(
        out,
        r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="none" stroke="{}" stroke-width="{:.2}"/>"#,
        frame.left,
        frame.top,
        frame.width,
        frame.height,
        colour::FLOOR,
        f
    );
    let tick_px = 11.0 * f;
    let _ = writeln!(
        out,
        r#"<g id="axes" font-size="{tick_px:.1}" fill="{}">"#,
        colour::MUTED
    );
    for k in grid_indices(frame.x_min, frame.x_max(), step) {
        let (x, _) = frame.px([k * step, 0.0]);
        let _ = writeln!(
            out,
            r#"<line x1="{x:.2}" y1="{plot_bottom:.2}" x2="{x:.2}" y2="{:.2}" stroke="{}"/><text x="{x:.2}" y="{:.2}" text-anchor="middle">{}</text>"#,
            plot_bottom + 4.0 * f,
            colour::FLOOR,
            plot_bottom + 6.0 * f + tick_px,
            fmt_num(k * step, tick_decimals)
        );
    }
    for k in grid_indices(frame.y_min(), frame.y_max, step) {
        let (_, y) = frame.px([0.0, k * step]);
        let _ = writeln!(
            out,
            r#"<line x1="{:.2}" y1="{y:.2}" x2="{:.2}" y2="{y:.2}" stroke="{}"/><text x="{:.2}" y="{:.2}" text-anchor="end">{}</text>"#,
            frame.left - 4.0 * f,
            frame.left,
            colour::FLOOR,
            frame.left - 6.0 * f,
            y + 0.35 * tick_px,
            fmt_num(k * step, tick_decimals)
        );
    }
    let _ = writeln!(
        out,
        r#"<text x="{:.2}" y="{:.2}" text-anchor="middle" font-size="{:.1}" fill="{}">x ({}) → right</text>"#,
        frame.left + frame.width / 2.0,
        plot_bottom + 8.0 * f + 2.4 * tick_px,
        12.0 * f,
        colour::TEXT,
        u.short
    );
    let y_title_x = pad + 12.0 * f;
    let y_title_y = frame.top + frame.height / 2.0;
    let _ = writeln!(
        out,
        r#"<text x="{y_title_x:.2}" y="{y_title_y:.2}" text-anchor="middle" font-size="{:.1}" fill="{}" transform="rotate(-90 {y_title_x:.2} {y_title_y:.2})">y ({}) → forward</text>"#,
        12.0 * f,
        colour::TEXT,
        u.short
    );
    let _ = writeln!(out, "</g>");

    // Title.
    let text_room = width - 2.0 * pad;
    let count = map.objects.len();
    let first = format!(
        "{title} — {count} object{}",
        if count == 1 { "" } else { "s" }
    );
    let (first, first_px) = fit_text(&first, title_px, text_room, true);
    let c = &map.camera;
    let second = format!(
        "camera: pitch {:.1}°, roll {:.1}°, height {} {} · {} · method {} · units: {}",
        c.pitch_deg,
        c.roll_deg,
        fmt_num(c.height, size_decimals),
        u.short,
        perspective_name(map),
        map.method,
        u.long
    );
    let (second, second_px) = fit_text(&second, sub_px, text_room, false);
    let _ = writeln!(out, r#"<g id="title">"#);
    let _ = writeln!(
        out,
        r#"<text x="{pad:.2}" y="{title_base:.2}" font-size="{first_px:.1}" font-weight="bold">{}</text>"#,
        escape_xml(&first)
    );
    let _ = writeln!(
        out,
        r#"<text x="{pad:.2}" y="{sub_base:.2}" font-size="{second_px:.1}" fill="{}">{}</text>"#,
        colour::MUTED,
        escape_xml(&second)
    );
    let _ = writeln!(out, "</g>");

    // Scale bar: "0", two alternating halves, then its length.
    let bar_h = 6.0 * f;
    let bar_y = footer_top - bar_h / 2.0;
    let half = bar_px / 2.0;
    let text_y = footer_top + 0.35 * label_px;
    let _ = writeln!(
        out,
        r#"<g id="scale-bar" font-size="{label_px:.1}" stroke="{}" stroke-width="{:.2}">"#,
        colour::TEXT,
        0.8 * f
    );
    let _ = writeln!(
        out,
        r#"<rect x="{bar_x:.2}" y="{bar_y:.2}" width="{half:.2}" height="{bar_h:.2}" fill="{}"/><rect x="{:.2}" y="{bar_y:.2}" width="{half:.2}" height="{bar_h:.2}" fill="{}"/>"#,
        colour::TEXT,
        bar_x + half,
        colour::PAPER
    );
    let _ = writeln!(
        out,
        r#"<text x="{pad:.2}" y="{text_y:.2}" stroke="none">0</text><text x="{:.2}" y="{text_y:.2}" stroke="none">{}</text>"#,
        bar_x + bar_px + 5.0 * f,
        escape_xml(&bar_label)
    );
    let _ = writeln!(out, "</g>");

    if !legend.is_empty() {
        let _ = writeln!(out, r#"<g id="legend" font-size="{label_px:.1}">"#);
        for ((swatch, text), (x, y)) in legend.iter().zip(&legend_pos) {
            let sy = y - 0.4 * swatch_px;
            match swatch {
                Swatch::Fill {
                    fill,
                    stroke,
                    dashed,
                } => {
                    let dash = if *dashed {
                        format!(r#" stroke-dasharray="{:.1} {:.1}""#, 3.0 * f, 2.0 * f)
                    } else {
                        String::new()
                    };
                    let _ = write!(
                        out,
                        r#"<rect x="{x:.2}" y="{sy:.2}" width="{swatch_px:.2}" height="{:.2}" fill="{fill}" stroke="{stroke}" stroke-width="{:.2}"{dash}/>"#,
                        0.8 * swatch_px,
                        1.2 * f
                    );
                }
                Swatch::Line { stroke, dashed } => {
                    let dash = if *dashed {
                        format!(r#" stroke-dasharray="{:.1} {:.1}""#, 4.0 * f, 2.5 * f)
                    } else {
                        String::new()
                    };
                    let _ = write!(
                        out,
                        r#"<line x1="{x:.2}" y1="{y:.2}" x2="{:.2}" y2="{y:.2}" stroke="{stroke}" stroke-width="{:.2}"{dash}/>"#,
                        x + swatch_px,
                        2.0 * f
                    );
                }
                Swatch::Dot => {
                    let _ = write!(
                        out,
                        r#"<circle cx="{:.2}" cy="{y:.2}" r="{:.2}" fill="{}"/>"#,
                        x + swatch_px / 2.0,
                        0.3 * swatch_px,
                        colour::CAMERA
                    );
                }
            }
            let _ = writeln!(
                out,
                r#"<text x="{:.2}" y="{:.2}">{}</text>"#,
                x + swatch_px + 6.0 * f,
                y + 0.35 * label_px,
                escape_xml(text)
            );
        }
        let _ = writeln!(out, "</g>");
    }
    out.push_str("</svg>\n");
    out
}

/// "2pp" or "3pp", as in the map file.
fn perspective_name(map: &FloorMap) -> String {
    serde_json::to_value(map.camera.perspective)
        .ok()
        .and_then(|v| v.as_str().map(str::to_owned))
        .unwrap_or_default()
}

/// Multiples `k` (as floats) of `step` with `k * step` in `[lo, hi]`, at most 200 of them.
fn grid_indices(lo: f64, hi: f64, step: f64) -> impl Iterator<Item = f64> {
    let first = (lo / step).ceil();
    let last = (hi / step).floor();
    let count = if first.is_finite() && last.is_finite() && last >= first {
        ((last - first) as u32 + 1).min(200)
    } else {
        0
    };
    (0..count).map(move |i| first + f64::from(i))
}

/// Polygon in pixels.
type PixelPolygon = Vec<(f64, f64)>;

/// Point in polygon by the even-odd ray test.
fn point_in_polygon((x, y): (f64, f64), poly: &[(f64, f64)]) -> bool {
    let mut inside = false;
    let next = poly.iter().cycle().skip(1);
    for (a, b) in poly.iter().zip(next) {
        if (a.1 > y) != (b.1 > y) && x < a.0 + (y - a.1) * (b.0 - a.0) / (b.1 - a.1) {
            inside = !inside;
        }
    }
    inside
}

/// Segments `p1 p2` and `q1 q2` cross (touching counts).
fn segments_cross(p1: (f64, f64), p2: (f64, f64), q1: (f64, f64), q2: (f64, f64)) -> bool {
    let orient = |a: (f64, f64), b: (f64, f64), c: (f64, f64)| {
        (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
    };
    let (d1, d2) = (orient(q1, q2, p1), orient(q1, q2, p2));
    let (d3, d4) = (orient(p1, p2, q1), orient(p1, p2, q2));
    d1 * d2 <= 0.0 && d3 * d4 <= 0.0
}

impl Rect {
    fn corners(&self) -> [(f64, f64); 4] {
        [
            (self.x, self.y),
            (self.x + self.w, self.y),
            (self.x + self.w, self.y + self.h),
            (self.x, self.y + self.h),
        ]
    }

    /// The rectangle and the polygon share any point.
    fn hits(&self, poly: &[(f64, f64)]) -> bool {
        if poly.len() < 3 {
            return false;
        }
        let corners = self.corners();
        if corners.iter().any(|c| point_in_polygon(*c, poly)) {
            return true;
        }
        if poly.iter().any(|p| {
            p.0 >= self.x && p.0 <= self.x + self.w && p.1 >= self.y && p.1 <= self.y + self.h
        }) {
            return true;
        }
        let rect_edges = corners.iter().zip(corners.iter().cycle().skip(1));
        rect_edges.into_iter().any(|(a, b)| {
            poly.iter()
                .zip(poly.iter().cycle().skip(1))
                .any(|(p, q)| segments_cross(*a, *b, *p, *q))
        })
    }

    /// The rectangle lies inside the polygon (corners inside, no edge crossing).
    fn inside(&self, poly: &[(f64, f64)]) -> bool {
        let corners = self.corners();
        corners.iter().all(|c| point_in_polygon(*c, poly))
            && !corners
                .iter()
                .zip(corners.iter().cycle().skip(1))
                .any(|(a, b)| {
                    poly.iter()
                        .zip(poly.iter().cycle().skip(1))
                        .any(|(p, q)| segments_cross(*a, *b, *p, *q))
                })
    }
}

/// Where a label goes. In order of preference:
/// 1. centred on its object, when it fits inside the object's outline and touches no other
///    label or object;
/// 2. the nearest spot (rings of 8 directions around the object) that touches no other label
///    and no object, drawn with a leader line;
/// 3. the nearest spot that touches no other label;
/// 4. centred, clamped into the plot.
///
/// `own` is the index of the label's object in `objects`.
fn place_label(
    centred: Rect,
    own: Option<usize>,
    objects: &[PixelPolygon],
    placed: &[Rect],
    frame: &Frame,
) -> Rect {
    let free_of_labels = |r: &Rect| frame.contains(r) && !placed.iter().any(|p| p.overlaps(r));
    let free_of_objects = |r: &Rect, skip: Option<usize>| {
        objects
            .iter()
            .enumerate()
            .all(|(i, poly)| Some(i) == skip || !r.hits(poly))
    };
    let own_poly = own.and_then(|i| objects.get(i));
    if own_poly.is_some_and(|poly| centred.inside(poly))
        && free_of_labels(&centred)
        && free_of_objects(&centred, own)
    {
        return centred;
    }
    let (sx, sy) = (0.5 * centred.w + 6.0, 0.5 * centred.h + 4.0);
    let mut candidates: Vec<Rect> = Vec::with_capacity(8 * 8);
    for ring in 1..=8 {
        let k = f64::from(ring);
        for (dx, dy) in [
            (0.0, -1.0),
            (0.0, 1.0),
            (1.0, 0.0),
            (-1.0, 0.0),
            (1.0, -1.0),
            (-1.0, -1.0),
            (1.0, 1.0),
            (-1.0, 1.0),
        ] {
            candidates.push(Rect {
                x: centred.x + dx * k * sx,
                y: centred.y + dy * k * sy,
                ..centred
            });
        }
    }
    let centre = (centred.x + centred.w / 2.0, centred.y + centred.h / 2.0);
    candidates.sort_by(|a, b| a.distance_to(centre).total_cmp(&b.distance_to(centre)));
    if let Some(r) = candidates
        .iter()
        .find(|r| free_of_labels(r) && free_of_objects(r, None))
    {
        return *r;
    }
    if free_of_labels(&centred) {
        return centred;
    }
    if let Some(r) = candidates.iter().find(|r| free_of_labels(r)) {
        return *r;
    }
    centred.clamped_into(frame)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn escape_covers_xml_specials_and_controls() {
        assert_eq!(escape_xml(r#"a<b>&"c'"#), "a&lt;b&gt;&amp;&quot;c&apos;");
        assert_eq!(escape_xml("x\u{1}y\nz"), "x\u{fffd}y z");
    }

    #[test]
    fn grid_step_prefers_whole_units_then_1_2_5() {
        assert_relative_eq!(grid_step(8.0), 1.0);
        assert_relative_eq!(grid_step(20.0), 1.0);
        assert_relative_eq!(grid_step(3.0), 0.2);
        assert_relative_eq!(grid_step(0.004), 0.0005, max_relative = 1e-9);
        assert_relative_eq!(grid_step(180.0), 20.0);
        assert_relative_eq!(grid_step(f64::NAN), 1.0);
        for span in [0.013, 0.7, 2.2, 4.9, 21.0, 47.0, 333.0, 1.0e5] {
            let n = span / grid_step(span);
            assert!((4.0..=21.0).contains(&n), "{span}: {n} lines");
        }
    }

    #[test]
    fn nice_at_most_is_a_1_2_5_value_not_above_the_limit() {
        assert_relative_eq!(nice_at_most(2.3), 2.0);
        assert_relative_eq!(nice_at_most(0.99), 0.5);
        assert_relative_eq!(nice_at_most(7.0), 5.0);
        assert_relative_eq!(nice_at_most(10.0), 10.0);
    }

    #[test]
    fn numbers_have_step_decimals_and_no_negative_zero() {
        assert_eq!(decimals_for(1.0), 0);
        assert_eq!(decimals_for(0.1), 1);
        assert_eq!(decimals_for(0.05), 2);
        assert_eq!(decimals_for(20.0), 0);
        assert_eq!(fmt_num(-0.0001, 2), "0.00");
        assert_eq!(fmt_num(-1.234, 1), "-1.2");
    }

    #[test]
    fn long_text_is_shrunk_then_cut() {
        let (t, px) = fit_text("short", 20.0, 500.0, false);
        assert_eq!((t.as_str(), px), ("short", 20.0));
        let long = "x".repeat(400);
        let (t, px) = fit_text(&long, 20.0, 300.0, false);
        assert!(px >= MIN_FONT_PX);
        assert!(text_width_px(&t, px, false) <= 300.0 + 1e-9);
        assert!(t.ends_with('…'));
    }

    #[test]
    fn labels_are_moved_off_each_other_and_kept_in_the_plot() {
        let frame = Frame {
            x_min: 0.0,
            y_max: 10.0,
            px_per_unit: 50.0,
            left: 0.0,
            top: 0.0,
            width: 500.0,
            height: 500.0,
        };
        let a = Rect {
            x: 200.0,
            y: 200.0,
            w: 100.0,
            h: 30.0,
        };
        let b = place_label(a, None, &[], &[a], &frame);
        assert!(!b.overlaps(&a));
        let corner = Rect {
            x: 480.0,
            y: -10.0,
            ..a
        };
        let c = place_label(corner, None, &[], &[], &frame);
        assert!(frame.contains(&c));
        // A small object under the label: the label moves off it.
        let small = vec![
            (240.0, 210.0),
            (260.0, 210.0),
            (260.0, 220.0),
            (240.0, 220.0),
        ];
        let d = place_label(a, Some(0), std::slice::from_ref(&small), &[], &frame);
        assert!(!d.hits(&small));
        // A big object: the label stays centred inside it.
        let big = vec![
            (100.0, 100.0),
            (400.0, 100.0),
            (400.0, 400.0),
            (100.0, 400.0),
        ];
        let e = place_label(a, Some(0), &[big], &[], &frame);
        assert!((e.x - a.x).abs() < 1e-9 && (e.y - a.y).abs() < 1e-9);
    }
}
