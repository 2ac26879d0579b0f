//! A plan drawn on its occupancy grid: the picture `vpmap plan --svg` writes.
//!
//! One SVG unit per cell, row 0 at the top: free cells white, occupied black, unknown grey
//! (run-length rectangles per row), the path, start and goal; for MBPP also every bug's track,
//! hits and leave points, the alternatives, and a legend strip under the grid.

use std::fmt::Write as _;

use vpmap_plan::Planned;
use vpmap_plan::grid::{CellXy, Occupancy, OccupancyGrid};
use vpmap_plan::mbpp::BugTrack;

use crate::{SVG_FROM_MAP_ATTRIBUTE, escape_xml, matrix_text};

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
/// alternatives) or black (obstacles).
const BUG_COLOURS: [&str; 8] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22",
];

/// Colour of the alternative paths.
const ALTERNATIVE_COLOUR: &str = "#7f7f7f";

/// Colour of the chosen path.
const PATH_COLOUR: &str = "#d62728";

/// Opacity of the bug tracks, so that overlapping tracks and the walls stay visible.
const TRACK_OPACITY: f64 = 0.6;

/// Width of a bug track relative to the path's.
const TRACK_WIDTH: f64 = 0.7;

/// Legend text height, screen pixels.
const LEGEND_FONT_PX: f64 = 11.0;

/// The grid (free white, occupied black, unknown grey; run-length rectangles per row), the
/// path, start and goal, one SVG unit per cell, row 0 at the top. For MBPP also, under the
/// path: every bug's track (thin, one colour per bug, straight runs merged), its hits
/// (crosses) and leave points (rings), the alternatives (dashed grey), and a legend strip
/// below the map when it is wide enough for the labels. The root element carries
/// [`SVG_FROM_MAP_ATTRIBUTE`]: the transform from `coordinates` to the picture.
#[must_use]
pub fn plan_svg(
    grid: &OccupancyGrid,
    planned: &Planned,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    coordinates: GridCoordinates,
) -> String {
    let (w, h) = (grid.width(), grid.height());
    let px = (900.0 / w.max(h) as f64).clamp(0.5, 24.0);
    let legend = if planned.bugs.is_empty() {
        None
    } else {
        Legend::layout(planned, w as f64, LEGEND_FONT_PX / px)
    };
    // Without a legend the header is what it always was.
    let (total_h, view_h) = match &legend {
        Some(l) => {
            let total = h as f64 + l.height;
            (total, format!("{total:.3}"))
        }
        None => (h as f64, h.to_string()),
    };
    let mut out = format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" viewBox="0 0 {w} {view_h}" shape-rendering="crispEdges" {SVG_FROM_MAP_ATTRIBUTE}="{}">
<rect width="{w}" height="{view_h}" fill="#ffffff"/>
"##,
        w as f64 * px,
        total_h * px,
        matrix_text(svg_from_grid_coordinates(grid, coordinates))
    );
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
                Occupancy::Occupied => Some("#222222"),
                Occupancy::Unknown => Some("#b8b8b8"),
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
    for (CellXy { x, y }, colour) in [(start.into(), "#2ca02c"), (goal.into(), "#1f77b4")] {
        let _ = writeln!(
            out,
            r#"<circle cx="{x}.5" cy="{y}.5" r="{:.3}" fill="{colour}"/>"#,
            (4.0 / px).max(0.4)
        );
    }
    if let Some(l) = &legend {
        l.draw(&mut out, h as f64, stroke);
    }
    out.push_str("</svg>\n");
    out
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
#[derive(Clone, Copy)]
enum Swatch {
    Track,
    Hit,
    Leave,
    Alternative,
    Path,
}

/// The legend strip under the map: labelled symbols, packed into rows.
struct Legend {
    /// Text height, SVG units (cells).
    font: f64,
    /// Entries with their position in the strip (x, row).
    entries: Vec<(Swatch, String, f64, usize)>,
    /// Height of the strip, SVG units.
    height: f64,
}

impl Legend {
    /// Lay the entries out in rows no wider than `width`; `None` when one does not fit.
    fn layout(planned: &Planned, width: f64, font: f64) -> Option<Self> {
        let mut labels = vec![
            (
                Swatch::Track,
                format!("bug tracks ({})", planned.bugs.len()),
            ),
            (Swatch::Hit, "hits".to_owned()),
            (Swatch::Leave, "leave points".to_owned()),
        ];
        if !planned.alternatives.is_empty() {
            labels.push((
                Swatch::Alternative,
                format!("alternatives ({})", planned.alternatives.len()),
            ));
        }
        if planned.best.is_some() {
            labels.push((Swatch::Path, "path".to_owned()));
        }
        // Sans-serif glyphs average about 0.6 em; the symbol takes 2 em, then gaps.
        let margin = 0.5 * font;
        let mut entries = Vec::with_capacity(labels.len());
        let (mut x, mut row) = (margin, 0);
        for (swatch, label) in labels {
            let entry_width = 2.4 * font + 0.6 * font * label.len() as f64;
            if margin + entry_width > width - margin {
                return None;
            }
            if x > margin && x + entry_width > width - margin {
                x = margin;
                row += 1;
            }
            entries.push((swatch, label, x, row));
            x += entry_width + 1.2 * font;
        }
        Some(Self {
            font,
            entries,
            height: (row + 1) as f64 * 1.5 * font + 0.5 * font,
        })
    }

    /// Draw the strip below the map, whose height is `top`.
    fn draw(&self, out: &mut String, top: f64, stroke: f64) {
        let f = self.font;
        let _ = writeln!(
            out,
            r##"<g class="legend" font-family="sans-serif" font-size="{f:.3}" fill="#222222">"##
        );
        for (swatch, label, x, row) in &self.entries {
            // Centre line of the row.
            let y = top + 0.25 * f + (*row as f64 + 0.5) * 1.5 * f;
            let (x0, x1) = (x + 0.1 * f, x + 1.9 * f);
            let xm = x + f;
            let line = |colour: &str, width: f64, extra: &str| {
                format!(
                    r#"<line x1="{x0:.3}" y1="{y:.3}" x2="{x1:.3}" y2="{y:.3}" stroke="{colour}" stroke-width="{width:.3}"{extra}/>"#
                )
            };
            let symbol = match swatch {
                Swatch::Track => line(
                    BUG_COLOURS[0],
                    stroke * TRACK_WIDTH,
                    &format!(r#" stroke-opacity="{TRACK_OPACITY}""#),
                ),
                Swatch::Hit => {
                    let a = 0.3 * f;
                    format!(
                        r#"<path d="M{:.3} {:.3}L{:.3} {:.3}M{:.3} {:.3}L{:.3} {:.3}" stroke="{}" stroke-width="{:.3}"/>"#,
                        xm - a,
                        y - a,
                        xm + a,
                        y + a,
                        xm - a,
                        y + a,
                        xm + a,
                        y - a,
                        BUG_COLOURS[0],
                        0.12 * f
                    )
                }
                Swatch::Leave => format!(
                    r##"<circle cx="{xm:.3}" cy="{y:.3}" r="{:.3}" fill="#ffffff" stroke="{}" stroke-width="{:.3}"/>"##,
                    0.3 * f,
                    BUG_COLOURS[0],
                    0.12 * f
                ),
                Swatch::Alternative => line(
                    ALTERNATIVE_COLOUR,
                    stroke * 0.8,
                    &format!(r#" stroke-dasharray="{:.3} {:.3}""#, 0.45 * f, 0.3 * f),
                ),
                Swatch::Path => line(PATH_COLOUR, stroke, ""),
            };
            out.push_str(&symbol);
            out.push('\n');
            let _ = writeln!(
                out,
                r#"<text x="{:.3}" y="{:.3}" dominant-baseline="central">{}</text>"#,
                x + 2.4 * f,
                y,
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
    fn legend_is_left_out_when_the_map_is_too_narrow() {
        let planned = Planned {
            best: None,
            alternatives: Vec::new(),
            bugs: Vec::new(),
            mbpp_stats: MbppStats::default(),
        };
        assert!(Legend::layout(&planned, 3.0, 1.0).is_none());
        let wide = Legend::layout(&planned, 200.0, 1.0).map(|l| l.entries.len());
        assert_eq!(wide, Some(3));
    }
}
