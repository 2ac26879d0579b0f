//! A plan drawn on its occupancy grid: the picture `vpmap plan --svg` writes.
//!
//! One SVG unit per cell, row 0 at the top: free cells white, occupied black, unknown grey
//! (run-length rectangles per row), the path, start and goal; for MBPP also every bug's track,
//! hits and leave points and the alternatives. Around the grid: a title, axes with ticks in
//! metres (or cells) and a legend for every colour and symbol drawn.

use std::fmt::Write as _;

use vpmap_plan::Planned;
use vpmap_plan::grid::{CellXy, Occupancy, OccupancyGrid};
use vpmap_plan::mbpp::BugTrack;
use vpmap_plan::planner::PlannerKind;

use crate::metrics::text_width_px;
use crate::svg::{SVG_FROM_MAP_ATTRIBUTE, escape_xml, matrix_text};

/// How the map coordinates of a plan read, for the picture's `data-svg-from-map` transform.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridCoordinates {
    /// The grid's world frame (`+x` right, `+y` up, metres or map units; the grid's origin
    /// and resolution place it): ROS maps and `map.json`.
    World,
    /// Cell indices (column, row; row 0 at the top; a cell's centre at its index): Moving AI
    /// maps.
    Cells,
}

/// The affine transform from `coordinates` to the picture's user units (one per cell, row 0
/// at the top), in SVG `matrix(a b c d e f)` order.
#[must_use]
pub fn svg_from_grid_coordinates(grid: &OccupancyGrid, coordinates: GridCoordinates) -> [f64; 6] {
    match coordinates {
        GridCoordinates::Cells => [1.0, 0.0, 0.0, 1.0, 0.5, 0.5],
        GridCoordinates::World => {
            let k = 1.0 / grid.resolution_m();
            let [ox, oy] = grid.origin_m();
            [k, 0.0, 0.0, -k, -ox * k, grid.height() as f64 + oy * k]
        }
    }
}

/// One colour per bug, in order of birth (repeating): no red (the path), grey (the
/// alternatives), black (obstacles), green (the start) or blue (the goal).
const BUG_COLOURS: [&str; 6] = [
    "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22",
];

/// Colour of the alternative paths.
const ALTERNATIVE_COLOUR: &str = "#7f7f7f";

/// Colour of the chosen path.
const PATH_COLOUR: &str = "#d62728";

/// Colour of the start marker.
const START_COLOUR: &str = "#2ca02c";

/// Colour of the goal marker.
const GOAL_COLOUR: &str = "#1f77b4";

/// Colour of occupied cells.
const OCCUPIED_COLOUR: &str = "#222222";

/// Colour of unknown cells.
const UNKNOWN_COLOUR: &str = "#b8b8b8";

/// Colour of free cells (the paper).
const FREE_COLOUR: &str = "#ffffff";

/// Colour of text, the frame and the ticks.
const TEXT_COLOUR: &str = "#222222";

/// Colour of the subtitle and the tick labels.
const MUTED_COLOUR: &str = "#555555";

/// Colour of the hit and leave-point symbols in the legend (drawn in each bug's colour).
const MARK_LEGEND_COLOUR: &str = "#444444";

/// Opacity of the bug tracks, so that overlapping tracks and the walls stay visible.
const TRACK_OPACITY: f64 = 0.6;

/// Width of a bug track relative to the path's.
const TRACK_WIDTH: f64 = 0.7;

/// Font of every text element (see [`crate::svg_to_png`] for `sans-serif`).
const FONT_FAMILY: &str = crate::svg::FONT_FAMILY;

/// Title text height, screen pixels.
const TITLE_FONT_PX: f64 = 16.0;

/// Subtitle, axis and legend text height, screen pixels.
const TEXT_FONT_PX: f64 = 12.0;

/// Tick label text height, screen pixels.
const TICK_FONT_PX: f64 = 11.0;

/// Outer padding, screen pixels.
const PAD_PX: f64 = 10.0;

/// Start and goal marker radius, screen pixels (at least 0.4 cells).
const MARKER_PX: f64 = 5.0;

/// A planner's name as a plan picture's title writes it: `MBPP`, `A* PS`, `Theta*`, ...
#[must_use]
pub fn planner_title(kind: PlannerKind) -> &'static str {
    match kind {
        PlannerKind::Mbpp => "MBPP",
        PlannerKind::MbppCloser => "MBPP (closer leave rule)",
        PlannerKind::Astar => "A*",
        PlannerKind::AstarPs => "A* PS",
        PlannerKind::ThetaStar => "Theta*",
        PlannerKind::Optimal => "Shortest any-angle path",
    }
}

/// The title of a plan picture: `<planner> on <map_name>` (`vpmap plan --svg`).
#[must_use]
pub fn plan_title(kind: PlannerKind, map_name: &str) -> String {
    format!("{} on {map_name}", planner_title(kind))
}

/// The grid (free cells white, occupied black, unknown grey; run-length rectangles per row),
/// the path, start (green) and goal (blue), one SVG unit per cell, row 0 at the top, with a
/// title (`title`, then a line with the grid's size, its cell size and the path's length),
/// axes with ticks in `coordinates` (metres, or cell indices for [`GridCoordinates::Cells`])
/// and a legend under the map for every colour drawn. For MBPP also, under the path: every
/// bug's track (thin, one colour per bug, straight runs merged), its hits (crosses) and
/// leave points (rings), and the alternatives (dashed grey). The title, axes and legend lie
/// outside the grid, at negative user units or beyond the grid's size, so that a cell's
/// user units stay its indices. The root element carries [`SVG_FROM_MAP_ATTRIBUTE`]: the
/// transform from `coordinates` to the picture.
#[must_use]
pub fn plan_svg(
    grid: &OccupancyGrid,
    planned: &Planned,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    coordinates: GridCoordinates,
    title: &str,
) -> String {
    let (w, h) = (grid.width(), grid.height());
    // Screen pixels per cell.
    let px = (900.0 / w.max(h) as f64).clamp(0.5, 24.0);
    let svg_from_grid = svg_from_grid_coordinates(grid, coordinates);
    let axes = Axes::new(grid, coordinates, svg_from_grid, px);
    let subtitle = subtitle(grid, planned, coordinates);

    // The frame around the grid, screen pixels from the picture's top left.
    let left = PAD_PX + 1.4 * TEXT_FONT_PX + axes.widest_y_label_px + 8.0;
    let top = PAD_PX + TITLE_FONT_PX + 6.0 + 1.5 * TEXT_FONT_PX + 10.0;
    let grid_w_px = w as f64 * px;
    let grid_h_px = h as f64 * px;
    let title_w = text_width_px(title, TITLE_FONT_PX, true).max(text_width_px(
        &subtitle,
        TEXT_FONT_PX,
        false,
    ));
    let entries = legend_entries(grid, planned);
    let widest_entry = entries
        .iter()
        .map(|(_, label)| Legend::entry_width_px(label))
        .fold(0.0, f64::max);
    let width_px = (left + grid_w_px + PAD_PX + 0.5 * axes.widest_x_label_px)
        .max(2.0 * PAD_PX + title_w)
        .max(2.0 * PAD_PX + widest_entry)
        .ceil();
    let x_axis_bottom = top + grid_h_px + 6.0 + TICK_FONT_PX + 6.0 + TEXT_FONT_PX;
    let legend = Legend::layout(entries, width_px - 2.0 * PAD_PX);
    let legend_top = x_axis_bottom + 10.0;
    let height_px = (legend_top + legend.height_px + PAD_PX).ceil();

    // Everything below is in user units: cells, the grid's top left at (0, 0).
    let k = 1.0 / px;
    let (x0, y0) = (-left * k, -top * k);
    let (vw, vh) = (width_px * k, height_px * k);
    let mut out = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width_px:.0}" height="{height_px:.0}" viewBox="{x0:.3} {y0:.3} {vw:.3} {vh:.3}" shape-rendering="crispEdges" font-family="{FONT_FAMILY}" {SVG_FROM_MAP_ATTRIBUTE}="{}">
<title>{}</title>
<rect x="{x0:.3}" y="{y0:.3}" width="{vw:.3}" height="{vh:.3}" fill="{FREE_COLOUR}"/>
"#,
        matrix_text(svg_from_grid),
        escape_xml(title)
    );
    let _ = writeln!(out, r#"<g class="cells">"#);
    for y in 0..h {
        let mut x = 0;
        while x < w {
            let cell = grid.get(x, y).unwrap_or(Occupancy::Unknown);
            let mut end = x + 1;
            while end < w && grid.get(end, y) == Some(cell) {
                end += 1;
            }
            let fill = match cell {
                Occupancy::Free => None,
                Occupancy::Occupied => Some(OCCUPIED_COLOUR),
                Occupancy::Unknown => Some(UNKNOWN_COLOUR),
            };
            if let Some(fill) = fill {
                let _ = writeln!(
                    out,
                    r#"<rect x="{x}" y="{y}" width="{}" height="1" fill="{fill}"/>"#,
                    end - x
                );
            }
            x = end;
        }
    }
    out.push_str("</g>\n");
    let stroke = (2.0 / px).max(0.15);
    if !planned.bugs.is_empty() {
        draw_bugs(&mut out, &planned.bugs, stroke, px);
    }
    if !planned.alternatives.is_empty() {
        let _ = writeln!(
            out,
            r#"<g class="alternatives" fill="none" stroke="{ALTERNATIVE_COLOUR}" stroke-width="{:.3}" stroke-dasharray="{:.3} {:.3}" stroke-linejoin="round">"#,
            stroke * 0.8,
            stroke * 3.0,
            stroke * 2.0
        );
        for p in &planned.alternatives {
            let _ = writeln!(out, r#"<polyline points="{}"/>"#, svg_points(&p.waypoints));
        }
        out.push_str("</g>\n");
    }
    if let Some(p) = &planned.best {
        let _ = writeln!(
            out,
            r#"<polyline points="{}" fill="none" stroke="{PATH_COLOUR}" stroke-width="{stroke:.3}" stroke-linejoin="round"/>"#,
            svg_points(&p.waypoints)
        );
    }
    for (CellXy { x, y }, class, colour) in [
        (start.into(), "start", START_COLOUR),
        (goal.into(), "goal", GOAL_COLOUR),
    ] {
        let _ = writeln!(
            out,
            r##"<circle class="{class}" cx="{x}.5" cy="{y}.5" r="{:.3}" fill="{colour}" stroke="#ffffff" stroke-width="{:.3}"/>"##,
            (MARKER_PX / px).max(0.4),
            (1.5 / px).max(0.1)
        );
    }
    axes.draw(&mut out, w as f64, h as f64, px);
    // Title and subtitle.
    let _ = writeln!(
        out,
        r#"<g class="title" shape-rendering="auto"><text x="{:.3}" y="{:.3}" font-size="{:.3}" font-weight="bold" fill="{TEXT_COLOUR}">{}</text><text x="{:.3}" y="{:.3}" font-size="{:.3}" fill="{MUTED_COLOUR}">{}</text></g>"#,
        x0 + PAD_PX * k,
        y0 + (PAD_PX + TITLE_FONT_PX) * k,
        TITLE_FONT_PX * k,
        escape_xml(title),
        x0 + PAD_PX * k,
        y0 + (PAD_PX + TITLE_FONT_PX + 6.0 + TEXT_FONT_PX) * k,
        TEXT_FONT_PX * k,
        escape_xml(&subtitle)
    );
    legend.draw(
        &mut out,
        (x0 + PAD_PX * k, y0 + legend_top * k),
        k,
        stroke,
        &planned.bugs,
    );
    out.push_str("</svg>\n");
    out
}

/// The line under the title: the grid's size and cell size, the path's length or "no path",
/// MBPP's bugs and alternatives.
fn subtitle(grid: &OccupancyGrid, planned: &Planned, coordinates: GridCoordinates) -> String {
    let (scale, unit) = match coordinates {
        GridCoordinates::World => (grid.resolution_m(), "m"),
        GridCoordinates::Cells => (1.0, "cells"),
    };
    let mut text = format!("{} × {} cells", grid.width(), grid.height());
    if coordinates == GridCoordinates::World {
        let _ = write!(text, " of {} m", grid.resolution_m());
    }
    match &planned.best {
        Some(p) => {
            let _ = write!(text, " · path {:.2} {unit}", p.length_cells * scale);
        }
        None => text.push_str(" · no path"),
    }
    if !planned.bugs.is_empty() {
        let _ = write!(
            text,
            " · {} bug{}, {} alternative{}",
            planned.bugs.len(),
            if planned.bugs.len() == 1 { "" } else { "s" },
            planned.alternatives.len(),
            if planned.alternatives.len() == 1 {
                ""
            } else {
                "s"
            }
        );
    }
    text
}

/// The ticks and their labels along the grid's bottom (x) and left (y) edges.
struct Axes {
    /// Tick positions (user units) and labels along x.
    x_ticks: Vec<(f64, String)>,
    /// Tick positions (user units) and labels along y.
    y_ticks: Vec<(f64, String)>,
    /// The x axis's title.
    x_title: &'static str,
    /// The y axis's title.
    y_title: &'static str,
    /// Widest tick label of each axis, screen pixels.
    widest_x_label_px: f64,
    widest_y_label_px: f64,
}

impl Axes {
    /// The ticks of a grid drawn at `px` screen pixels per cell, `m` from `coordinates` to
    /// cells: about ten per side, fewer when their labels would touch.
    fn new(grid: &OccupancyGrid, coordinates: GridCoordinates, m: [f64; 6], px: f64) -> Self {
        let (w, h) = (grid.width() as f64, grid.height() as f64);
        // The grid's extent in `coordinates`: the inverse of the (axis-aligned) transform at
        // the picture's edges.
        let inv = |svg: f64, scale: f64, offset: f64| (svg - offset) / scale;
        let (xa, xb) = (inv(0.0, m[0], m[4]), inv(w, m[0], m[4]));
        let (ya, yb) = (inv(0.0, m[3], m[5]), inv(h, m[3], m[5]));
        let span = (xb - xa).abs().max((yb - ya).abs());
        let mut step = crate::svg::grid_step(span);
        if coordinates == GridCoordinates::Cells {
            step = step.max(1.0).round();
        }
        let ticks = |step: f64, a: f64, b: f64, scale: f64, offset: f64| -> Vec<(f64, String)> {
            let decimals = crate::svg::decimals_for(step);
            crate::svg::grid_indices(a.min(b), a.max(b), step)
                .map(|i| {
                    let v = i * step;
                    (v * scale + offset, crate::svg::fmt_num(v, decimals))
                })
                .collect()
        };
        let widest = |t: &[(f64, String)]| {
            t.iter()
                .map(|(_, s)| text_width_px(s, TICK_FONT_PX, false))
                .fold(0.0, f64::max)
        };
        // Screen pixels between ticks.
        let spacing = |step: f64| step * m[0].abs() * px;
        let mut x_ticks = ticks(step, xa, xb, m[0], m[4]);
        // Each round at least doubles the step; 64 rounds is beyond any grid.
        for _ in 0..64 {
            let room = (widest(&x_ticks) + 8.0).max(1.6 * TICK_FONT_PX);
            if spacing(step) >= room {
                break;
            }
            step = next_1_2_5(step);
            x_ticks = ticks(step, xa, xb, m[0], m[4]);
        }
        let y_ticks = ticks(step, ya, yb, m[3], m[5]);
        let (x_title, y_title) = match coordinates {
            GridCoordinates::World => ("x (m) →", "y (m) →"),
            GridCoordinates::Cells => ("column →", "← row"),
        };
        Self {
            widest_x_label_px: widest(&x_ticks),
            widest_y_label_px: widest(&y_ticks),
            x_ticks,
            y_ticks,
            x_title,
            y_title,
        }
    }

    /// The frame around the `w` x `h` grid, the ticks, their labels and the axis titles.
    fn draw(&self, out: &mut String, w: f64, h: f64, px: f64) {
        let k = 1.0 / px;
        let _ = writeln!(
            out,
            r#"<g class="axes" shape-rendering="auto" font-size="{:.3}" fill="{MUTED_COLOUR}">"#,
            TICK_FONT_PX * k
        );
        let _ = writeln!(
            out,
            r#"<rect x="0" y="0" width="{w}" height="{h}" fill="none" stroke="{TEXT_COLOUR}" stroke-width="{k:.3}"/>"#
        );
        for (x, label) in &self.x_ticks {
            let _ = writeln!(
                out,
                r#"<line x1="{x:.3}" y1="{h}" x2="{x:.3}" y2="{:.3}" stroke="{TEXT_COLOUR}" stroke-width="{k:.3}"/><text x="{x:.3}" y="{:.3}" text-anchor="middle">{label}</text>"#,
                h + 4.0 * k,
                h + (6.0 + TICK_FONT_PX) * k
            );
        }
        for (y, label) in &self.y_ticks {
            let _ = writeln!(
                out,
                r#"<line x1="0" y1="{y:.3}" x2="{:.3}" y2="{y:.3}" stroke="{TEXT_COLOUR}" stroke-width="{k:.3}"/><text x="{:.3}" y="{:.3}" text-anchor="end">{label}</text>"#,
                -4.0 * k,
                -6.0 * k,
                y + 0.35 * TICK_FONT_PX * k
            );
        }
        let _ = writeln!(
            out,
            r#"<text x="{:.3}" y="{:.3}" text-anchor="middle" font-size="{:.3}" fill="{TEXT_COLOUR}">{}</text>"#,
            w / 2.0,
            h + (6.0 + TICK_FONT_PX + 6.0 + TEXT_FONT_PX) * k,
            TEXT_FONT_PX * k,
            self.x_title
        );
        let (tx, ty) = (
            -(8.0 + self.widest_y_label_px + 0.4 * TEXT_FONT_PX) * k,
            h / 2.0,
        );
        let _ = writeln!(
            out,
            r#"<text x="{tx:.3}" y="{ty:.3}" text-anchor="middle" font-size="{:.3}" fill="{TEXT_COLOUR}" transform="rotate(-90 {tx:.3} {ty:.3})">{}</text>"#,
            TEXT_FONT_PX * k,
            self.y_title
        );
        out.push_str("</g>\n");
    }
}

/// The 1-2-5 value after `step` (1 → 2 → 5 → 10).
fn next_1_2_5(step: f64) -> f64 {
    let e = 10f64.powf(step.log10().floor());
    let m = step / e;
    if m < 1.5 {
        2.0 * e
    } else if m < 3.5 {
        5.0 * e
    } else {
        10.0 * e
    }
}

/// Cell centres as an SVG `points` list.
fn svg_points(cells: &[CellXy]) -> String {
    let mut points = String::with_capacity(cells.len() * 10);
    for (i, CellXy { x, y }) in cells.iter().enumerate() {
        if i > 0 {
            points.push(' ');
        }
        let _ = write!(points, "{x}.5,{y}.5");
    }
    points
}

/// The cells where a walk turns: its first and last cell and every cell where the direction
/// changes (a reversal counts as a change); cells in a straight run between them, and
/// repeated cells, are left out. The polyline through them is the walk's.
fn turning_cells(cells: &[CellXy]) -> Vec<CellXy> {
    let mut out: Vec<CellXy> = Vec::new();
    for &c in cells {
        if out.last() == Some(&c) {
            continue;
        }
        if let [.., a, b] = out.as_slice() {
            let d1 = (b.x as i64 - a.x as i64, b.y as i64 - a.y as i64);
            let d2 = (c.x as i64 - b.x as i64, c.y as i64 - b.y as i64);
            let cross = d1.0 * d2.1 - d1.1 * d2.0;
            let dot = d1.0 * d2.0 + d1.1 * d2.1;
            if cross == 0 && dot > 0 {
                if let Some(last) = out.last_mut() {
                    *last = c;
                }
                continue;
            }
        }
        out.push(c);
    }
    out
}

/// Every bug's track, hits and leave points, one colour per bug.
fn draw_bugs(out: &mut String, bugs: &[BugTrack], stroke: f64, px: f64) {
    let _ = writeln!(
        out,
        r#"<g class="bug-tracks" fill="none" stroke-width="{:.3}" stroke-opacity="{TRACK_OPACITY}" stroke-linecap="round" stroke-linejoin="round">"#,
        stroke * TRACK_WIDTH
    );
    for (i, bug) in bugs.iter().enumerate() {
        let colour = BUG_COLOURS[i % BUG_COLOURS.len()];
        let mut corners = turning_cells(&bug.cells);
        if let [only] = corners.as_slice() {
            // A zero-length segment with round caps draws a dot.
            corners.push(*only);
        }
        let _ = writeln!(
            out,
            r#"<polyline class="bug-track" data-bug="{i}" stroke="{colour}" points="{}"/>"#,
            svg_points(&corners)
        );
    }
    out.push_str("</g>\n");
    let arm = (3.0 / px).max(0.3);
    let ring = (2.5 / px).max(0.25);
    let _ = writeln!(
        out,
        r#"<g class="bug-marks" fill="none" stroke-width="{:.3}">"#,
        stroke * 0.5
    );
    for (i, bug) in bugs.iter().enumerate() {
        let colour = BUG_COLOURS[i % BUG_COLOURS.len()];
        if !bug.hits.is_empty() {
            let mut d = String::new();
            for &CellXy { x, y } in &bug.hits {
                let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
                let _ = write!(
                    d,
                    "M{:.3} {:.3}L{:.3} {:.3}M{:.3} {:.3}L{:.3} {:.3}",
                    cx - arm,
                    cy - arm,
                    cx + arm,
                    cy + arm,
                    cx - arm,
                    cy + arm,
                    cx + arm,
                    cy - arm
                );
            }
            let _ = writeln!(
                out,
                r#"<path class="bug-hits" data-bug="{i}" stroke="{colour}" d="{d}"/>"#
            );
        }
        for &CellXy { x, y } in &bug.leaves {
            let _ = writeln!(
                out,
                r##"<circle class="bug-leave" data-bug="{i}" cx="{x}.5" cy="{y}.5" r="{ring:.3}" fill="#ffffff" stroke="{colour}"/>"##
            );
        }
    }
    out.push_str("</g>\n");
}

/// What a legend entry's symbol looks like.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Swatch {
    Start,
    Goal,
    Free,
    Occupied,
    Unknown,
    Path,
    Track,
    Hit,
    Leave,
    Alternative,
}

/// The legend's entries: what the picture shows, in drawing order.
fn legend_entries(grid: &OccupancyGrid, planned: &Planned) -> Vec<(Swatch, String)> {
    let (free, occupied, unknown) = grid.counts();
    let mut entries = vec![
        (Swatch::Start, "start".to_owned()),
        (Swatch::Goal, "goal".to_owned()),
    ];
    if planned.best.is_some() {
        entries.push((Swatch::Path, "path".to_owned()));
    }
    if free > 0 {
        entries.push((Swatch::Free, "free cell".to_owned()));
    }
    if occupied > 0 {
        entries.push((Swatch::Occupied, "occupied cell".to_owned()));
    }
    if unknown > 0 {
        entries.push((Swatch::Unknown, "unknown cell".to_owned()));
    }
    if !planned.bugs.is_empty() {
        let n = planned.bugs.len();
        entries.push((
            Swatch::Track,
            format!(
                "{n} bug track{}{}",
                if n == 1 { "" } else { "s" },
                if n > 1 { ", one colour each" } else { "" }
            ),
        ));
        if planned.bugs.iter().any(|b| !b.hits.is_empty()) {
            entries.push((Swatch::Hit, "hit (bug's colour)".to_owned()));
        }
        if planned.bugs.iter().any(|b| !b.leaves.is_empty()) {
            entries.push((Swatch::Leave, "leave point (bug's colour)".to_owned()));
        }
    }
    if !planned.alternatives.is_empty() {
        entries.push((
            Swatch::Alternative,
            format!("alternatives ({})", planned.alternatives.len()),
        ));
    }
    entries
}

/// The legend under the map: labelled symbols, packed into rows; screen pixels until drawn.
struct Legend {
    /// Entries with their position in the strip (x from its left, row).
    entries: Vec<(Swatch, String, f64, usize)>,
    /// Height of the strip, screen pixels.
    height_px: f64,
}

impl Legend {
    /// Symbol width, screen pixels.
    const SYMBOL_PX: f64 = 22.0;
    /// Gap between a symbol and its text, and between entries, screen pixels.
    const GAP_PX: f64 = 6.0;
    /// Row height, screen pixels.
    const ROW_PX: f64 = 1.6 * TEXT_FONT_PX;

    /// Width of an entry (symbol, gap, text), screen pixels.
    fn entry_width_px(label: &str) -> f64 {
        Self::SYMBOL_PX + Self::GAP_PX + text_width_px(label, TEXT_FONT_PX, false)
    }

    /// Lay the entries out in rows no wider than `width_px` (an entry wider than that gets a
    /// row of its own).
    fn layout(labels: Vec<(Swatch, String)>, width_px: f64) -> Self {
        let mut entries = Vec::with_capacity(labels.len());
        let (mut x, mut row) = (0.0, 0);
        for (swatch, label) in labels {
            let entry_width = Self::entry_width_px(&label);
            if x > 0.0 && x + entry_width > width_px {
                x = 0.0;
                row += 1;
            }
            entries.push((swatch, label, x, row));
            x += entry_width + 2.5 * Self::GAP_PX;
        }
        let rows = if entries.is_empty() { 0 } else { row + 1 };
        Self {
            entries,
            height_px: rows as f64 * Self::ROW_PX,
        }
    }

    /// Draw the legend with its top left at `origin` (user units), `k` user units per screen
    /// pixel; `stroke` is the path's width (user units); the track symbol shows the colours
    /// of `bugs`' tracks.
    fn draw(&self, out: &mut String, origin: (f64, f64), k: f64, stroke: f64, bugs: &[BugTrack]) {
        let f = TEXT_FONT_PX * k;
        let _ = writeln!(
            out,
            r#"<g class="legend" shape-rendering="auto" font-size="{f:.3}" fill="{TEXT_COLOUR}">"#
        );
        for (swatch, label, x, row) in &self.entries {
            // Centre line of the row.
            let y = origin.1 + (*row as f64 + 0.5) * Self::ROW_PX * k;
            let x = origin.0 + x * k;
            let (x0, x1) = (x + 0.1 * Self::SYMBOL_PX * k, x + 0.9 * Self::SYMBOL_PX * k);
            let xm = x + 0.5 * Self::SYMBOL_PX * k;
            let line = |colour: &str, width: f64, extra: &str| {
                format!(
                    r#"<line x1="{x0:.3}" y1="{y:.3}" x2="{x1:.3}" y2="{y:.3}" stroke="{colour}" stroke-width="{width:.3}"{extra}/>"#
                )
            };
            let cell = |fill: &str| {
                let s = 0.7 * TEXT_FONT_PX * k;
                format!(
                    r#"<rect x="{:.3}" y="{:.3}" width="{s:.3}" height="{s:.3}" fill="{fill}" stroke="{MUTED_COLOUR}" stroke-width="{:.3}"/>"#,
                    xm - s / 2.0,
                    y - s / 2.0,
                    0.8 * k
                )
            };
            let marker = |colour: &str| {
                format!(
                    r##"<circle cx="{xm:.3}" cy="{y:.3}" r="{:.3}" fill="{colour}" stroke="#ffffff" stroke-width="{:.3}"/>"##,
                    MARKER_PX * k,
                    1.5 * k
                )
            };
            let symbol = match swatch {
                Swatch::Start => marker(START_COLOUR),
                Swatch::Goal => marker(GOAL_COLOUR),
                Swatch::Free => cell(FREE_COLOUR),
                Swatch::Occupied => cell(OCCUPIED_COLOUR),
                Swatch::Unknown => cell(UNKNOWN_COLOUR),
                Swatch::Path => line(PATH_COLOUR, 2.0 * k, ""),
                Swatch::Track => {
                    // One short stroke per colour the tracks use, side by side.
                    let n = bugs.len().clamp(1, BUG_COLOURS.len());
                    let piece = (x1 - x0) / n as f64;
                    let mut s = String::new();
                    for (i, colour) in BUG_COLOURS.iter().take(n).enumerate() {
                        let a = x0 + i as f64 * piece;
                        let _ = write!(
                            s,
                            r#"<line class="track-swatch" x1="{a:.3}" y1="{y:.3}" x2="{:.3}" y2="{y:.3}" stroke="{colour}" stroke-width="{:.3}" stroke-opacity="{TRACK_OPACITY}"/>"#,
                            a + piece,
                            (2.0 * TRACK_WIDTH * k)
                                .max(stroke * TRACK_WIDTH)
                                .min(3.0 * k)
                        );
                    }
                    s
                }
                Swatch::Hit => {
                    let a = 3.5 * k;
                    format!(
                        r#"<path d="M{:.3} {:.3}L{:.3} {:.3}M{:.3} {:.3}L{:.3} {:.3}" stroke="{MARK_LEGEND_COLOUR}" stroke-width="{:.3}"/>"#,
                        xm - a,
                        y - a,
                        xm + a,
                        y + a,
                        xm - a,
                        y + a,
                        xm + a,
                        y - a,
                        1.2 * k
                    )
                }
                Swatch::Leave => format!(
                    r##"<circle cx="{xm:.3}" cy="{y:.3}" r="{:.3}" fill="#ffffff" stroke="{MARK_LEGEND_COLOUR}" stroke-width="{:.3}"/>"##,
                    3.0 * k,
                    1.2 * k
                ),
                Swatch::Alternative => line(
                    ALTERNATIVE_COLOUR,
                    1.6 * k,
                    &format!(r#" stroke-dasharray="{:.3} {:.3}""#, 5.0 * k, 3.0 * k),
                ),
            };
            out.push_str(&symbol);
            out.push('\n');
            let _ = writeln!(
                out,
                r#"<text x="{:.3}" y="{:.3}">{}</text>"#,
                x + (Self::SYMBOL_PX + Self::GAP_PX) * k,
                y + 0.35 * f,
                escape_xml(label)
            );
        }
        out.push_str("</g>\n");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vpmap_plan::mbpp::MbppStats;

    #[test]
    fn turning_cells_merge_straight_runs_and_keep_turns_and_reversals() {
        let walk = [
            (0, 0),
            (1, 0),
            (2, 0),
            (2, 0),
            (3, 1),
            (4, 2),
            (4, 3),
            (4, 4),
            (4, 3),
            (4, 2),
        ];
        let walk = walk.map(CellXy::from);
        assert_eq!(
            turning_cells(&walk),
            [(0, 0), (2, 0), (4, 2), (4, 4), (4, 2)]
        );
        assert_eq!(turning_cells(&[CellXy::new(3, 3); 2]), [(3, 3)]);
        assert!(turning_cells(&[]).is_empty());
    }

    #[test]
    fn legend_names_start_goal_and_only_the_cell_states_the_grid_has() {
        let planned = Planned {
            best: None,
            alternatives: Vec::new(),
            bugs: Vec::new(),
            mbpp_stats: MbppStats::default(),
        };
        let mut grid = OccupancyGrid::new(4, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        grid.set(1, 1, Occupancy::Occupied).unwrap();
        let swatches: Vec<Swatch> = legend_entries(&grid, &planned)
            .into_iter()
            .map(|(s, _)| s)
            .collect();
        assert_eq!(
            swatches,
            [Swatch::Start, Swatch::Goal, Swatch::Free, Swatch::Occupied]
        );
    }

    #[test]
    fn legend_rows_wrap_at_the_width_and_keep_a_wide_entry_whole() {
        let labels = || {
            (0..6)
                .map(|i| (Swatch::Free, format!("entry {i}")))
                .collect::<Vec<_>>()
        };
        let one_row = Legend::layout(labels(), 10_000.0);
        assert!(one_row.entries.iter().all(|e| e.3 == 0));
        let narrow = Legend::layout(labels(), 1.0);
        let rows: Vec<usize> = narrow.entries.iter().map(|e| e.3).collect();
        assert_eq!(rows, [0, 1, 2, 3, 4, 5]);
        assert!(narrow.height_px > 5.0 * one_row.height_px);
    }
}
