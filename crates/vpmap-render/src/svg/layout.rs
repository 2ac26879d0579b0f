//! Where everything goes: the plot frame (map units to pixels), the title band, the footer
//! with the scale bar and the legend rows.

use std::fmt::Write as _;

use vpmap_metrology::map::{FloorMap, MapPoint, PolygonWithHoles};

use super::legend::{Swatch, UnitNames, legend_entries};
use super::numbers::{decimals_for, fmt_num, grid_step, nice_at_most};
use super::style::{FloorPlanStyle, MAX_PX};
use crate::geometry::{Bounds, is_finite};
use crate::metrics::text_width_px;

/// Largest plot height / plot width; deeper maps get a wider x range instead of a taller picture.
const MAX_PLOT_ASPECT: f64 = 1.5;
/// Smallest plot height / plot width; shallow maps get a deeper y range.
const MIN_PLOT_ASPECT: f64 = 0.35;

/// Map coordinates to picture pixels: `+y` up the page.
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    /// Map x at the plot's left edge.
    pub(super) x_min: f64,
    /// Map y at the plot's top edge.
    pub(super) y_max: f64,
    /// Pixels per map unit.
    pub(super) px_per_unit: f64,
    /// Plot rectangle, pixels.
    pub(super) left: f64,
    pub(super) top: f64,
    pub(super) width: f64,
    pub(super) height: f64,
}

impl Frame {
    /// Pixel position of a map point, kept within [`MAX_PX`] of the origin (only points far
    /// outside the plot are moved; resvg overflows on coordinates beyond `i32`).
    pub(super) fn px(&self, p: MapPoint) -> (f64, f64) {
        (
            (self.left + (p[0] - self.x_min) * self.px_per_unit).clamp(-MAX_PX, MAX_PX),
            (self.top + (self.y_max - p[1]) * self.px_per_unit).clamp(-MAX_PX, MAX_PX),
        )
    }

    /// The affine transform from map coordinates to SVG user units, in SVG
    /// `matrix(a b c d e f)` order: `x_svg = a x + c y + e`, `y_svg = b x + d y + f` (what
    /// [`Frame::px`] does, before its clamping of far-away points).
    pub(super) fn svg_from_map(&self) -> [f64; 6] {
        let k = self.px_per_unit;
        [
            k,
            0.0,
            0.0,
            -k,
            self.left - self.x_min * k,
            self.top + self.y_max * k,
        ]
    }

    /// The map point is inside the plot.
    pub(super) fn shows(&self, p: MapPoint) -> bool {
        (self.x_min..=self.x_max()).contains(&p[0]) && (self.y_min()..=self.y_max).contains(&p[1])
    }

    pub(super) fn x_max(&self) -> f64 {
        self.x_min + self.width / self.px_per_unit
    }

    pub(super) fn y_min(&self) -> f64 {
        self.y_max - self.height / self.px_per_unit
    }

    pub(super) fn contains(&self, r: &Rect) -> bool {
        r.x >= self.left
            && r.y >= self.top
            && r.x + r.w <= self.left + self.width
            && r.y + r.h <= self.top + self.height
    }
}

/// A rectangle in pixels, for label placement.
#[derive(Debug, Clone, Copy)]
pub(super) struct Rect {
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) w: f64,
    pub(super) h: f64,
}

impl Rect {
    pub(super) fn overlaps(&self, o: &Rect) -> bool {
        self.x < o.x + o.w && o.x < self.x + self.w && self.y < o.y + o.h && o.y < self.y + self.h
    }

    /// Moved inside `frame` (as far as it fits).
    pub(super) fn clamped_into(self, frame: &Frame) -> Rect {
        let x = self
            .x
            .min(frame.left + frame.width - self.w)
            .max(frame.left);
        let y = self.y.min(frame.top + frame.height - self.h).max(frame.top);
        Rect { x, y, ..self }
    }

    /// Distance from a point to this rectangle (0 inside).
    pub(super) fn distance_to(&self, (px, py): (f64, f64)) -> f64 {
        let dx = (self.x - px).max(px - (self.x + self.w)).max(0.0);
        let dy = (self.y - py).max(py - (self.y + self.h)).max(0.0);
        dx.hypot(dy)
    }
}

/// SVG path data of a closed ring (finite points only), or `None` below 3 points.
pub(super) fn ring_path(frame: &Frame, ring: &[MapPoint]) -> Option<String> {
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
pub(super) fn polygon_path(frame: &Frame, poly: &PolygonWithHoles) -> Option<String> {
    let mut d = ring_path(frame, &poly.exterior)?;
    for hole in &poly.holes {
        if let Some(h) = ring_path(frame, hole) {
            d.push(' ');
            d.push_str(&h);
        }
    }
    Some(d)
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

/// The picture's measures, pixels unless named otherwise.
pub(super) struct Layout {
    /// Picture width.
    pub(super) width: f64,
    /// Picture height.
    pub(super) height: f64,
    /// Scale of every length relative to a 1000-pixel-wide picture.
    pub(super) f: f64,
    /// Outer padding.
    pub(super) pad: f64,
    /// Title font size.
    pub(super) title_px: f64,
    /// Subtitle font size.
    pub(super) sub_px: f64,
    /// Title baseline.
    pub(super) title_base: f64,
    /// Subtitle baseline.
    pub(super) sub_base: f64,
    /// Baseline of the fit report's line, when the map has a fit report.
    pub(super) fit_base: Option<f64>,
    /// The plot: map units to pixels.
    pub(super) frame: Frame,
    /// Bottom edge of the plot.
    pub(super) plot_bottom: f64,
    /// The plot's larger side, map units.
    pub(super) span: f64,
    /// Grid step, map units.
    pub(super) step: f64,
    /// Decimals of the tick labels.
    pub(super) tick_decimals: usize,
    /// Decimals of sizes in labels and the title.
    pub(super) size_decimals: usize,
    /// Centre line of the footer's first row.
    pub(super) footer_top: f64,
    /// Footer text size.
    pub(super) label_px: f64,
    /// Scale bar length.
    pub(super) bar_px: f64,
    /// Scale bar text ("1 m").
    pub(super) bar_label: String,
    /// Scale bar left end.
    pub(super) bar_x: f64,
    /// The camera's horizontal field of view, degrees.
    pub(super) fov_deg: [f64; 2],
    /// The field of view is an angle less than a full turn.
    pub(super) fov_ok: bool,
    /// Path data of the hidden floor.
    pub(super) hidden_paths: Vec<String>,
    /// Legend entries.
    pub(super) legend: Vec<(Swatch, String)>,
    /// Legend entries' positions.
    pub(super) legend_pos: Vec<(f64, f64)>,
    /// Legend swatch width.
    pub(super) swatch_px: f64,
    /// The station point, pixels.
    pub(super) station: (f64, f64),
    /// Radius of the station point's marker.
    pub(super) station_r: f64,
    /// The planned path's start and goal, pixels (none without a path).
    pub(super) path_ends: Vec<(f64, f64)>,
    /// Radius of the path's start and goal markers.
    pub(super) path_end_r: f64,
}

/// Lay out the picture of `map`.
pub(super) fn layout(map: &FloorMap, style: &FloorPlanStyle, u: &UnitNames) -> Layout {
    let width = f64::from(style.width_px.clamp(200, 20_000));
    let f = (width / 1000.0).clamp(0.6, 2.0);
    let pad = 16.0 * f;

    // Title band.
    let title_px = 20.0 * f;
    let sub_px = 13.0 * f;
    let title_base = pad + title_px;
    let sub_base = title_base + 1.55 * sub_px;
    // A third line for the joint fit's report (method fit only).
    let fit_base = map.fit.as_ref().map(|_| sub_base + 1.45 * sub_px);
    let plot_top = fit_base.unwrap_or(sub_base) + 18.0 * f;

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
    let label_px = 13.0 * f;
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
    let legend = legend_entries(
        map,
        style,
        u,
        !hidden_paths.is_empty(),
        fov_deg,
        fov_ok,
        step,
        tick_decimals,
    );
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

    Layout {
        width,
        height,
        f,
        pad,
        title_px,
        sub_px,
        title_base,
        sub_base,
        fit_base,
        frame,
        plot_bottom,
        span,
        step,
        tick_decimals,
        size_decimals,
        footer_top,
        label_px,
        bar_px,
        bar_label,
        bar_x,
        fov_deg,
        fov_ok,
        hidden_paths,
        legend,
        legend_pos,
        swatch_px,
        station: frame.px([0.0, 0.0]),
        station_r: 6.0 * f,
        path_ends: path_ends(style, &frame),
        path_end_r: 5.0 * f,
    }
}

/// The first and last finite point of the style's path, pixels, when it has two or more.
fn path_ends(style: &FloorPlanStyle, frame: &Frame) -> Vec<(f64, f64)> {
    let mut finite = style.path.iter().filter(|p| is_finite(**p));
    match (finite.next(), finite.next_back()) {
        (Some(a), Some(b)) => vec![frame.px(*a), frame.px(*b)],
        _ => Vec::new(),
    }
}
