//! `vpmap plan`: a path across a Moving AI map, a ROS map or a vpmap `map.json`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use vpmap_metrology::map::FloorMap;
use vpmap_pipeline::{
    Coordinates, DEFAULT_ROBOT_RADIUS_M, Endpoint, EndpointRules, OptionNames, endpoint_cell,
};
use vpmap_plan::Planned;
use vpmap_plan::grid::{Cell, OccupancyGrid};
use vpmap_plan::mbpp::{BugTrack, MbppStats};
use vpmap_plan::plan::Plan;
use vpmap_plan::planner::{Planner, PlannerKind};
use vpmap_plan::raster::{RasterOptions, rasterize_map};

use crate::num;
use crate::output::write_file;

/// What `vpmap plan --help` says of each planner.
fn planner_help(kind: PlannerKind) -> &'static str {
    match kind {
        PlannerKind::Mbpp => {
            "Multi-Bug Path Planning (the thesis's planner): bugs split at obstacles and follow walls both ways; the shortest corner list, smoothed, plus the others as alternatives"
        }
        PlannerKind::MbppCloser => {
            "MBPP leaving a wall as soon as it is closer to the goal than at its hit: more bugs, shorter paths, slower"
        }
        PlannerKind::Astar => "8-connected octile A*, no corner cutting",
        PlannerKind::AstarPs => "A* followed by line-of-sight post-smoothing",
        PlannerKind::ThetaStar => "Basic Theta* (any-angle)",
        PlannerKind::Optimal => {
            "The exact shortest any-angle path (visibility graph over obstacle-corner cells)"
        }
    }
}

/// `--planner`: a [`PlannerKind`] by its name, read with its `FromStr`; `--help` lists them.
fn planner_parser() -> impl clap::builder::TypedValueParser<Value = PlannerKind> {
    use clap::builder::TypedValueParser as _;
    clap::builder::PossibleValuesParser::new(
        PlannerKind::ALL.map(|k| clap::builder::PossibleValue::new(k.name()).help(planner_help(k))),
    )
    .try_map(|name| name.parse::<PlannerKind>())
}

/// Arguments of `vpmap plan`.
#[derive(clap::Args)]
pub struct PlanArgs {
    /// The map: a Moving AI `.map` (coordinates in cells), a ROS map `.yaml` or a vpmap
    /// `map.json` (coordinates in metres in the map's frame).
    map: PathBuf,
    /// Start `X,Y`.
    #[arg(long, allow_hyphen_values = true)]
    from: String,
    /// Goal `X,Y`.
    #[arg(long, allow_hyphen_values = true)]
    to: String,
    /// Planner.
    #[arg(long, default_value = "astar", value_parser = planner_parser())]
    planner: PlannerKind,
    /// Inflate obstacles by this radius (metres for ROS maps and map.json, cells for .map).
    /// Default: 0.2 m for a map.json (the robot radius `vpmap build` uses), 0 for a ROS map
    /// (`vpmap build` inflated its grid already) and for a Moving AI map.
    #[arg(long, allow_negative_numbers = true)]
    robot_radius: Option<f64>,
    /// Grid resolution for a `map.json`, metres.
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    resolution: f64,
    /// Let the path cross unknown cells.
    #[arg(long)]
    unknown_passable: bool,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Draw the grid and the path into this SVG file (with `--planner mbpp` also the bugs'
    /// tracks, hits, leave points and the alternative paths).
    #[arg(long)]
    svg: Option<PathBuf>,
}

/// A map ready for planning, and how its coordinates read.
pub struct PlanningMap {
    /// The grid (inflated).
    pub grid: OccupancyGrid,
    /// Coordinates are cells (Moving AI) rather than metres.
    pub in_cells: bool,
    /// The radius the obstacles were inflated by, in the map's coordinates.
    pub robot_radius: f64,
}

impl PlanningMap {
    /// The cell of `--from` or `--to`, which a path must be able to enter.
    fn endpoint(
        &self,
        name: &str,
        point: [f64; 2],
        unknown_passable: bool,
    ) -> Result<(usize, usize)> {
        let coordinates = if self.in_cells {
            Coordinates::Cells
        } else {
            Coordinates::Map { units: "m" }
        };
        let rules = EndpointRules {
            unknown_passable,
            robot_radius: self.robot_radius,
            names: OptionNames::CommandLine,
        };
        Ok(endpoint_cell(
            &self.grid,
            coordinates,
            &Endpoint { name, point },
            &rules,
        )?)
    }

    /// A waypoint in the map's coordinates.
    fn coords(&self, cell: (usize, usize)) -> [f64; 2] {
        if self.in_cells {
            [cell.0 as f64, cell.1 as f64]
        } else {
            self.grid.world_from_cell(cell.0, cell.1)
        }
    }

    fn unit(&self) -> &'static str {
        if self.in_cells { "cells" } else { "m" }
    }

    /// Map units per cell: lengths in cells times this are in [`Self::unit`].
    fn scale(&self) -> f64 {
        if self.in_cells {
            1.0
        } else {
            self.grid.resolution_m()
        }
    }
}

fn parse_point(what: &str, text: &str) -> Result<[f64; 2]> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let parsed: Vec<f64> = parts.iter().filter_map(|s| s.parse().ok()).collect();
    match parsed.as_slice() {
        [x, y] if parts.len() == 2 && x.is_finite() && y.is_finite() => Ok([*x, *y]),
        _ => bail!("{what} {text:?} is not a point X,Y (two numbers separated by a comma)"),
    }
}

/// Read any supported map and inflate its obstacles by `robot_radius` (by default
/// [`DEFAULT_ROBOT_RADIUS_M`] for a `map.json`, 0 for the others).
pub fn load_map(path: &Path, robot_radius: Option<f64>, resolution: f64) -> Result<PlanningMap> {
    if let Some(r) = robot_radius
        && !(r.is_finite() && r >= 0.0)
    {
        bail!(
            "--robot-radius must be a non-negative number, got {}",
            num(r)
        );
    }
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let (grid, in_cells) = match ext.as_str() {
        "map" => (vpmap_plan::movingai::read_movingai_map(path)?, true),
        "yaml" | "yml" => (vpmap_plan::ros::read_ros_map(path)?, false),
        "json" => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read map file {}", path.display()))?;
            let map = FloorMap::from_json_str(&text)
                .with_context(|| format!("{}: not a vpmap map.json", path.display()))?;
            let grid = rasterize_map(
                &map,
                &RasterOptions {
                    resolution_m: resolution,
                    ..RasterOptions::default()
                },
            )
            .with_context(|| format!("rasterising {}", path.display()))?;
            (grid, false)
        }
        _ => bail!(
            "{}: unknown map type; give a Moving AI .map, a ROS map .yaml or a vpmap map.json",
            path.display()
        ),
    };
    let robot_radius = robot_radius.unwrap_or(if ext == "json" {
        DEFAULT_ROBOT_RADIUS_M
    } else {
        0.0
    });
    let radius = if in_cells {
        robot_radius * grid.resolution_m()
    } else {
        robot_radius
    };
    let grid = grid.inflate(radius)?;
    Ok(PlanningMap {
        grid,
        in_cells,
        robot_radius,
    })
}

/// Run one planner (through the library's [`Planner`] interface) and keep everything it
/// found: the path, MBPP's alternatives and bugs (with their walked cells when
/// `record_tracks`; that costs memory in proportion to the bugs' steps, so ask only when
/// drawing them).
pub fn run_planner(
    kind: PlannerKind,
    grid: &OccupancyGrid,
    start: (usize, usize),
    goal: (usize, usize),
    unknown_passable: bool,
    record_tracks: bool,
) -> Result<Planned> {
    Ok(kind
        .planner(unknown_passable)
        .with_tracks(record_tracks)
        .plan(grid, start, goal)?)
}

/// MBPP's counters, for the MBPP planners only.
fn mbpp_stats(kind: PlannerKind, planned: &Planned) -> Option<MbppStats> {
    matches!(kind, PlannerKind::Mbpp | PlannerKind::MbppCloser).then_some(planned.mbpp_stats)
}

/// `count` followed by `noun`, with an `s` unless `count` is 1.
fn counted(count: usize, noun: &str) -> String {
    if count == 1 {
        format!("{count} {noun}")
    } else {
        format!("{count} {noun}s")
    }
}

/// `vpmap plan`.
pub fn run(args: &PlanArgs) -> Result<()> {
    let from = parse_point("--from", &args.from)?;
    let to = parse_point("--to", &args.to)?;
    let map = load_map(&args.map, args.robot_radius, args.resolution)?;
    let start = map.endpoint("--from", from, args.unknown_passable)?;
    let goal = map.endpoint("--to", to, args.unknown_passable)?;
    let began = Instant::now();
    let outcome = run_planner(
        args.planner,
        &map.grid,
        start,
        goal,
        args.unknown_passable,
        args.svg.is_some(),
    )?;
    let seconds = began.elapsed().as_secs_f64();
    if let Some(svg_path) = &args.svg {
        write_file(svg_path, path_svg(&map.grid, &outcome, start, goal))?;
    }
    if args.json {
        println!("{}", plan_json(&map, args.planner, &outcome, seconds));
    } else {
        println!("{}", plan_text(&map, args.planner, &outcome, seconds));
    }
    Ok(())
}

/// The `--json` answer: one object.
fn plan_json(
    map: &PlanningMap,
    planner: PlannerKind,
    outcome: &Planned,
    seconds: f64,
) -> serde_json::Value {
    let scale = map.scale();
    let plan = outcome.best.as_ref();
    let waypoints =
        |p: &Plan| -> Vec<[f64; 2]> { p.waypoints.iter().map(|c| map.coords(*c)).collect() };
    let alternatives: Vec<serde_json::Value> = outcome
        .alternatives
        .iter()
        .map(|p| serde_json::json!({ "length": p.length * scale, "waypoints": waypoints(p) }))
        .collect();
    let mut stats = serde_json::Map::new();
    if let Some(s) = mbpp_stats(planner, outcome) {
        // MBPP's own counters are there even when no path was found.
        for (key, value) in [
            ("expanded", s.bug_steps),
            ("generated", s.bugs),
            ("los_checks", s.los_checks),
            ("los_cells", s.los_cells),
            ("bugs", s.bugs),
            ("bug_steps", s.bug_steps),
            ("hits", s.hits),
            ("waits", s.waits),
            ("replans", s.replans),
        ] {
            stats.insert(key.to_owned(), value.into());
        }
    } else {
        let s = plan.map(|p| p.stats).unwrap_or_default();
        for (key, value) in [
            ("expanded", s.expanded),
            ("generated", s.generated),
            ("los_checks", s.los_checks),
            ("los_cells", s.los_cells),
        ] {
            stats.insert(key.to_owned(), value.into());
        }
    }
    stats.insert("time_s".to_owned(), seconds.into());
    serde_json::json!({
        "found": plan.is_some(),
        "length": plan.map(|p| p.length * scale),
        "units": map.unit(),
        "waypoints": plan.map(waypoints).unwrap_or_default(),
        "planner": planner.name(),
        "alternatives": alternatives,
        "stats": stats,
    })
}

/// The text answer: one line.
fn plan_text(map: &PlanningMap, planner: PlannerKind, outcome: &Planned, seconds: f64) -> String {
    let ms = seconds * 1e3;
    let work = match (mbpp_stats(planner, outcome), &outcome.best) {
        (Some(s), Some(_)) => format!(
            "{}, {}, {}, {ms:.3} ms",
            counted(s.bugs, "bug"),
            counted(s.bug_steps, "bug step"),
            counted(outcome.alternatives.len(), "alternative")
        ),
        (Some(s), None) => format!(
            "{}, {}, {ms:.3} ms",
            counted(s.bugs, "bug"),
            counted(s.bug_steps, "bug step")
        ),
        (None, Some(p)) => format!("{} nodes expanded, {ms:.3} ms", p.stats.expanded),
        (None, None) => format!("{ms:.3} ms"),
    };
    match &outcome.best {
        Some(p) => format!(
            "{}: path found, length {:.3} {} through {} waypoints ({work})",
            planner.name(),
            p.length * map.scale(),
            map.unit(),
            p.waypoints.len(),
        ),
        None => format!(
            "{}: no path: start and goal are not connected ({work})",
            planner.name()
        ),
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
/// below the map when it is wide enough for the labels.
#[must_use]
pub fn path_svg(
    grid: &OccupancyGrid,
    outcome: &Planned,
    start: (usize, usize),
    goal: (usize, usize),
) -> String {
    let (w, h) = (grid.width(), grid.height());
    let px = (900.0 / w.max(h) as f64).clamp(0.5, 24.0);
    let legend = if outcome.bugs.is_empty() {
        None
    } else {
        Legend::layout(outcome, w as f64, LEGEND_FONT_PX / px)
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
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" viewBox="0 0 {w} {view_h}" shape-rendering="crispEdges">
<rect width="{w}" height="{view_h}" fill="#ffffff"/>
"##,
        w as f64 * px,
        total_h * px
    );
    for y in 0..h {
        let mut x = 0;
        while x < w {
            let cell = grid.get(x, y).unwrap_or(Cell::Unknown);
            let mut end = x + 1;
            while end < w && grid.get(end, y) == Some(cell) {
                end += 1;
            }
            let fill = match cell {
                Cell::Free => None,
                Cell::Occupied => Some("#222222"),
                Cell::Unknown => Some("#b8b8b8"),
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
    if !outcome.bugs.is_empty() {
        draw_bugs(&mut out, &outcome.bugs, stroke, px);
    }
    if !outcome.alternatives.is_empty() {
        let _ = writeln!(
            out,
            r#"<g class="alternatives" fill="none" stroke="{ALTERNATIVE_COLOUR}" stroke-width="{:.3}" stroke-dasharray="{:.3} {:.3}" stroke-linejoin="round">"#,
            stroke * 0.8,
            stroke * 3.0,
            stroke * 2.0
        );
        for p in &outcome.alternatives {
            let _ = writeln!(out, r#"<polyline points="{}"/>"#, svg_points(&p.waypoints));
        }
        out.push_str("</g>\n");
    }
    if let Some(p) = &outcome.best {
        let _ = writeln!(
            out,
            r#"<polyline points="{}" fill="none" stroke="{PATH_COLOUR}" stroke-width="{stroke:.3}" stroke-linejoin="round"/>"#,
            svg_points(&p.waypoints)
        );
    }
    for ((x, y), colour) in [(start, "#2ca02c"), (goal, "#1f77b4")] {
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
fn svg_points(cells: &[(usize, usize)]) -> String {
    let mut points = String::with_capacity(cells.len() * 10);
    for (i, (x, y)) in cells.iter().enumerate() {
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
fn turning_cells(cells: &[(usize, usize)]) -> Vec<(usize, usize)> {
    let mut out: Vec<(usize, usize)> = Vec::new();
    for &c in cells {
        if out.last() == Some(&c) {
            continue;
        }
        if let [.., a, b] = out.as_slice() {
            let d1 = (b.0 as i64 - a.0 as i64, b.1 as i64 - a.1 as i64);
            let d2 = (c.0 as i64 - b.0 as i64, c.1 as i64 - b.1 as i64);
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
            for &(x, y) in &bug.hits {
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
        for &(x, y) in &bug.leaves {
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
    fn layout(outcome: &Planned, width: f64, font: f64) -> Option<Self> {
        let mut labels = vec![
            (
                Swatch::Track,
                format!("bug tracks ({})", outcome.bugs.len()),
            ),
            (Swatch::Hit, "hits".to_owned()),
            (Swatch::Leave, "leave points".to_owned()),
        ];
        if !outcome.alternatives.is_empty() {
            labels.push((
                Swatch::Alternative,
                format!("alternatives ({})", outcome.alternatives.len()),
            ));
        }
        if outcome.best.is_some() {
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
                vpmap_render::escape_xml(label)
            );
        }
        out.push_str("</g>\n");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        assert_eq!(
            turning_cells(&walk),
            [(0, 0), (2, 0), (4, 2), (4, 4), (4, 2)]
        );
        assert_eq!(turning_cells(&[(3, 3), (3, 3)]), [(3, 3)]);
        assert!(turning_cells(&[]).is_empty());
    }

    #[test]
    fn mbpp_tracks_are_recorded_only_when_asked() -> Result<()> {
        // A wall across the straight line, open at both ends.
        let mut grid = OccupancyGrid::new(6, 5, 1.0, [0.0; 2], Cell::Free)?;
        for y in 1..4 {
            grid.set(2, y, Cell::Occupied)?;
        }
        let (start, goal) = ((0, 2), (5, 2));
        let quiet = run_planner(PlannerKind::Mbpp, &grid, start, goal, false, false)?;
        let drawn = run_planner(PlannerKind::Mbpp, &grid, start, goal, false, true)?;
        assert!(quiet.bugs.len() >= 2 && quiet.bugs.iter().all(|b| b.cells.is_empty()));
        assert_eq!(drawn.bugs.len(), quiet.bugs.len());
        assert_eq!(
            drawn.bugs.first().and_then(|b| b.cells.first()),
            Some(&start)
        );
        assert!(drawn.bugs.iter().all(|b| !b.cells.is_empty()));
        assert_eq!(drawn.best, quiet.best);
        let best = run_planner(PlannerKind::Mbpp, &grid, start, goal, false, false)?.best;
        assert_eq!(best, quiet.best);
        assert!(best.is_some() && mbpp_stats(PlannerKind::Mbpp, &quiet).is_some());
        let other = run_planner(PlannerKind::ThetaStar, &grid, start, goal, false, true)?;
        assert!(other.bugs.is_empty() && other.alternatives.is_empty());
        assert!(mbpp_stats(PlannerKind::ThetaStar, &other).is_none());
        Ok(())
    }

    #[test]
    fn legend_is_left_out_when_the_map_is_too_narrow() {
        let outcome = Planned {
            best: None,
            alternatives: Vec::new(),
            bugs: Vec::new(),
            mbpp_stats: MbppStats::default(),
        };
        assert!(Legend::layout(&outcome, 3.0, 1.0).is_none());
        let wide = Legend::layout(&outcome, 200.0, 1.0).map(|l| l.entries.len());
        assert_eq!(wide, Some(3));
    }

    #[test]
    fn counts_and_text_read_well() {
        assert_eq!(counted(1, "bug"), "1 bug");
        assert_eq!(counted(0, "alternative"), "0 alternatives");
    }
}
