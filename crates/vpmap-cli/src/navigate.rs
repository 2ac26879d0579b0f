//! `vpmap navigate`: a robot drives a believed map, senses the true one and re-plans (see
//! docs/navigation.md).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use vpmap_metrology::synth::Truth;
use vpmap_pipeline::{Coordinates, Endpoint, EndpointRules, OptionNames, endpoint_cell};
use vpmap_plan::budget::{Budget, Stop};
use vpmap_plan::grid::{CellXy, Occupancy, OccupancyGrid};
use vpmap_plan::navigate::{
    MAX_SENSOR_RANGE_CELLS, NavigateOptions, Navigation, OnlinePlanner, navigate, truth_optimum,
};
use vpmap_plan::raster::truth_grid;

use crate::num;
use crate::output::OutputSet;
use crate::plan::{PlanningMap, load_map, parse_point};

/// Arguments of `vpmap navigate`.
#[derive(clap::Args)]
pub struct NavigateArgs {
    /// The believed map: a vpmap `map.json` (built from a photo), a ROS map `.yaml` or a
    /// Moving AI `.map`. Leave out with `--unknown`.
    map: Option<PathBuf>,
    /// Start from an empty belief (every cell unknown) of the true map's grid.
    #[arg(long)]
    unknown: bool,
    /// The true map: a synthetic scene's truth (`*.truth.json`, as `vpmap synth` writes it;
    /// rasterised into the believed map's grid) or any grid map (`.map`, `.yaml`, `map.json`)
    /// of the believed map's size and resolution.
    #[arg(long)]
    truth: PathBuf,
    /// Start `X,Y` (metres in the map's frame; cells for a Moving AI map).
    #[arg(long, allow_hyphen_values = true)]
    from: String,
    /// Goal `X,Y`.
    #[arg(long, allow_hyphen_values = true)]
    to: String,
    /// Online planner: astar, astar-ps, dstar-lite or mbpp.
    #[arg(long, default_value = "dstar-lite", value_parser = parse_planner)]
    planner: OnlinePlanner,
    /// Sensor range, metres (cells for a Moving AI map); default: 10 cells.
    #[arg(long, allow_negative_numbers = true)]
    sensor_range: Option<f64>,
    /// Believe unknown cells blocked (default: free, the free-space assumption).
    #[arg(long)]
    unknown_blocked: bool,
    /// Inflate obstacles by this radius (as `vpmap plan`: metres, cells for a `.map`).
    #[arg(long, allow_negative_numbers = true)]
    robot_radius: Option<f64>,
    /// Grid resolution for a `map.json` or a truth with `--unknown`, metres.
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    resolution: f64,
    /// Most moves (cells) before the robot stops ("move limit reached").
    #[arg(long, default_value_t = 10_000_000)]
    max_moves: usize,
    /// Most re-plans before the robot stops ("re-plan limit reached").
    #[arg(long, default_value_t = 1_000_000)]
    max_replans: usize,
    /// Most node expansions (MBPP: bug steps) of each re-plan before it stops with an error.
    #[arg(long, default_value_t = vpmap_plan::budget::DEFAULT_MAX_EXPANSIONS)]
    max_expansions: usize,
    /// Most grid cells the line-of-sight checks of each re-plan (A* PS, MBPP) look up.
    #[arg(long, default_value_t = vpmap_plan::budget::DEFAULT_MAX_SIGHT_CELLS)]
    max_sight_cells: usize,
    /// Stop the whole drive (sensing, moving and planning) after this many seconds with an
    /// error (default: no time limit; the counted limits above bound the work).
    #[arg(long, value_name = "SECONDS", value_parser = crate::plan::parse_timeout, allow_negative_numbers = true)]
    timeout: Option<std::time::Duration>,
    /// Output folder: navigate.json and navigate.svg (created if missing).
    #[arg(long, short)]
    out: PathBuf,
}

fn parse_planner(s: &str) -> std::result::Result<OnlinePlanner, String> {
    s.parse::<OnlinePlanner>().map_err(|e| e.to_string())
}

/// Whether `path` names a synthetic scene's truth.
fn is_truth_file(path: &Path) -> bool {
    path.file_name().is_some_and(|n| {
        n.to_string_lossy()
            .to_ascii_lowercase()
            .ends_with(".truth.json")
    })
}

/// The grid frame around a truth's floor at `resolution_m` (for `--unknown` with a truth).
fn truth_frame(truth: &Truth, resolution_m: f64) -> Result<OccupancyGrid> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &truth.floor {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if !(lo[0].is_finite() && hi[0].is_finite() && lo[1].is_finite() && hi[1].is_finite()) {
        bail!("the truth has no floor outline to make a grid of");
    }
    if !(resolution_m.is_finite() && resolution_m > 0.0) {
        bail!(
            "--resolution must be a positive number of metres, got {}",
            num(resolution_m)
        );
    }
    let cells = |k: usize| ((hi[k] - lo[k]) / resolution_m).ceil().max(1.0) as usize + 2;
    Ok(OccupancyGrid::new(
        cells(0),
        cells(1),
        resolution_m,
        [lo[0] - resolution_m, lo[1] - resolution_m],
        Occupancy::Unknown,
    )?)
}

fn read_truth(path: &Path) -> Result<Truth> {
    let text = vpmap_files::read_text(path, vpmap_files::Format::Map)?;
    serde_json::from_str(&text)
        .with_context(|| format!("{}: not a synthetic scene's truth", path.display()))
}

/// The believed and true maps of a run (same grid), and the believed map's coordinates.
fn load_maps(args: &NavigateArgs) -> Result<(PlanningMap, OccupancyGrid)> {
    match (&args.map, args.unknown) {
        (Some(_), true) => bail!("give either a believed map or --unknown, not both"),
        (None, false) => bail!("give a believed map (map.json, .yaml or .map) or --unknown"),
        _ => {}
    }
    if is_truth_file(&args.truth) {
        let truth = read_truth(&args.truth)?;
        let believed = match &args.map {
            Some(path) => load_map(path, args.robot_radius, args.resolution)?,
            None => PlanningMap {
                grid: truth_frame(&truth, args.resolution)?,
                in_cells: false,
                robot_radius: args
                    .robot_radius
                    .unwrap_or(vpmap_pipeline::DEFAULT_ROBOT_RADIUS_M),
            },
        };
        if believed.in_cells {
            bail!(
                "a synthetic truth is in metres; give a believed map.json or ROS map, not a Moving AI map"
            );
        }
        let grid = truth_grid(&truth, &believed.grid, believed.robot_radius)?;
        return Ok((believed, grid));
    }
    let truth = load_map(&args.truth, args.robot_radius, args.resolution)
        .with_context(|| format!("reading the true map {}", args.truth.display()))?;
    let believed = match &args.map {
        Some(path) => load_map(path, args.robot_radius, args.resolution)?,
        None => PlanningMap {
            grid: OccupancyGrid::new(
                truth.grid.width(),
                truth.grid.height(),
                truth.grid.resolution_m(),
                truth.grid.origin_m(),
                Occupancy::Unknown,
            )?,
            in_cells: truth.in_cells,
            robot_radius: truth.robot_radius,
        },
    };
    Ok((believed, truth.grid))
}

/// `vpmap navigate`.
pub fn run(args: &NavigateArgs) -> Result<()> {
    let from = parse_point("--from", &args.from)?;
    let to = parse_point("--to", &args.to)?;
    let (believed, truth) = load_maps(args)?;
    let scale = if believed.in_cells {
        1.0
    } else {
        believed.grid.resolution_m()
    };
    let unit = if believed.in_cells { "cells" } else { "m" };
    let range_cells = match args.sensor_range {
        Some(r) => {
            let cells = r / scale;
            if !(r.is_finite() && (1.0..=MAX_SENSOR_RANGE_CELLS).contains(&cells)) {
                bail!(
                    "--sensor-range {} {unit} is not a sensor range; give at least one cell ({} {unit}) and at most {} cells ({} {unit})",
                    num(r),
                    num(scale),
                    num(MAX_SENSOR_RANGE_CELLS),
                    num(MAX_SENSOR_RANGE_CELLS * scale)
                );
            }
            cells
        }
        None => 10.0,
    };
    let coordinates = if believed.in_cells {
        Coordinates::Cells
    } else {
        Coordinates::Map { units: "m" }
    };
    let rules = EndpointRules {
        unknown_passable: false,
        robot_radius: believed.robot_radius,
        names: OptionNames::CommandLine,
    };
    let on_truth = |name: &str, point| {
        endpoint_cell(&truth, coordinates, &Endpoint { name, point }, &rules)
            .with_context(|| format!("{name} on the true map {}", args.truth.display()))
    };
    let start = on_truth("--from", from)?;
    let goal = on_truth("--to", to)?;
    let opts = NavigateOptions {
        planner: args.planner,
        sensor_range_cells: range_cells,
        unknown_passable: !args.unknown_blocked,
        max_moves: args.max_moves,
        max_replans: args.max_replans,
        budget: Budget {
            max_expansions: args.max_expansions,
            max_sight_cells: args.max_sight_cells,
            stop: args
                .timeout
                .map_or_else(Stop::new, |t| Stop::new().with_timeout(t)),
        },
    };
    let run = navigate(&believed.grid, &truth, start, goal, &opts)
        .map_err(|e| crate::plan::name_the_flag(e.into()))?;
    let optimum = truth_optimum(&truth, start, goal, &opts.budget)
        .map_err(|e| crate::plan::name_the_flag(e.into()))?;
    let coords = |c: CellXy| -> [f64; 2] {
        if believed.in_cells {
            [c.x as f64, c.y as f64]
        } else {
            truth.world_from_cell(c.x, c.y)
        }
    };
    let json = navigate_json(&run, &optimum, args, range_cells, scale, unit, &coords);
    let mut outputs = OutputSet::default();
    outputs.add(
        "navigate.json",
        serde_json::to_string_pretty(&json).context("serialising navigate.json")?,
    );
    outputs.add(
        "navigate.svg",
        navigate_svg(&truth, &believed.grid, &run, start, goal, args.planner),
    );
    outputs.write_all(&args.out)?;
    println!(
        "{}: {} after {} moves, driven {:.3} {unit} (true optimum {} octile, {} any-angle), {} re-plans, planning {:.3} ms; wrote {}",
        args.planner.name(),
        run.outcome.as_str(),
        run.moves,
        run.length_cells * scale,
        optimum
            .octile_cells
            .map_or_else(|| "none".to_owned(), |l| format!("{:.3}", l * scale)),
        optimum
            .any_angle_cells
            .map_or_else(|| "none".to_owned(), |l| format!("{:.3}", l * scale)),
        run.events.len().saturating_sub(1),
        run.planning_time_s * 1e3,
        args.out.display()
    );
    Ok(())
}

/// navigate.json (format in docs/navigation.md).
fn navigate_json(
    run: &Navigation,
    optimum: &vpmap_plan::navigate::TruthOptimum,
    args: &NavigateArgs,
    range_cells: f64,
    scale: f64,
    unit: &str,
    coords: &dyn Fn(CellXy) -> [f64; 2],
) -> serde_json::Value {
    let events: Vec<serde_json::Value> = run
        .events
        .iter()
        .map(|e| {
            serde_json::json!({
                "moves": e.moves,
                "cell": [e.cell.x, e.cell.y],
                "at": coords(e.cell),
                "reason": e.reason.as_str(),
                "time_s": e.time_s,
                "expanded": e.expanded,
                "planned_length": e.planned_length_cells.map(|l| l * scale),
                "used_alternative": e.used_alternative,
                "doubted_cells": e.doubted_cells,
            })
        })
        .collect();
    let excess = |opt: Option<f64>| opt.filter(|&o| o > 0.0).map(|o| run.length_cells / o - 1.0);
    serde_json::json!({
        "version": 1,
        "planner": args.planner.name(),
        "units": unit,
        "sensor_range_cells": range_cells,
        "unknown_passable": !args.unknown_blocked,
        "outcome": run.outcome.as_str(),
        "reached": run.outcome == vpmap_plan::Outcome::Reached,
        "moves": run.moves,
        "length": run.length_cells * scale,
        "length_cells": run.length_cells,
        "length_m": if unit == "m" { Some(run.length_cells * scale) } else { None },
        "optimum_octile": optimum.octile_cells.map(|l| l * scale),
        "optimum_any_angle": optimum.any_angle_cells.map(|l| l * scale),
        "excess_over_octile": excess(optimum.octile_cells),
        "excess_over_any_angle": excess(optimum.any_angle_cells),
        "replans": run.events.len().saturating_sub(1),
        "planning_time_s": run.planning_time_s,
        "expanded": run.expanded,
        "waypoints": run.waypoints.iter().map(|&c| coords(c)).collect::<Vec<_>>(),
        "cells": run.cells.iter().map(|c| [c.x, c.y]).collect::<Vec<_>>(),
        "events": events,
        "seen_cells": run.belief.seen.iter().filter(|&&s| s).count(),
    })
}

/// navigate.svg: the true map, the believed obstacles, the sensed area, the driven track,
/// the re-planning points, start, goal and a legend; one SVG unit per cell, row 0 at the top.
/// The animation's speed, cells a second, and its duration's bounds, seconds.
const ANIMATION_CELLS_PER_S: f64 = 40.0;
/// See [`ANIMATION_CELLS_PER_S`].
const MIN_ANIMATION_S: f64 = 4.0;
/// See [`ANIMATION_CELLS_PER_S`].
const MAX_ANIMATION_S: f64 = 30.0;

/// For each waypoint, the fraction of the track's length driven when the robot reaches it
/// (0 at the start, 1 at the end; all 0 for a track of no length).
fn track_fractions(waypoints: &[CellXy]) -> Vec<f64> {
    let mut cumulative = Vec::with_capacity(waypoints.len());
    let mut length = 0.0;
    for (i, c) in waypoints.iter().enumerate() {
        if let Some(p) = i.checked_sub(1).and_then(|j| waypoints.get(j)) {
            length += (c.x as f64 - p.x as f64).hypot(c.y as f64 - p.y as f64);
        }
        cumulative.push(length);
    }
    if length > 0.0 {
        for v in &mut cumulative {
            *v /= length;
        }
    }
    cumulative
}

fn navigate_svg(
    truth: &OccupancyGrid,
    believed: &OccupancyGrid,
    run: &Navigation,
    start: CellXy,
    goal: CellXy,
    planner: OnlinePlanner,
) -> String {
    let (w, h) = (truth.width(), truth.height());
    let px = (900.0 / w.max(h) as f64).clamp(0.5, 24.0);
    let legend_h = 5.0 * 16.0 / px;
    let title_h = 40.0 / px;
    let mut s = String::new();
    let _ = write!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" viewBox="0 {:.3} {w} {:.3}" font-family="sans-serif">"#,
        w as f64 * px,
        (h as f64 + title_h + legend_h) * px,
        -title_h,
        h as f64 + title_h + legend_h
    );
    let font = 12.0 / px;
    let _ = write!(
        s,
        r##"<text x="0" y="{:.3}" font-size="{:.3}" fill="#222">{} on {w} x {h} cells: {}, driven {} cells, {} re-plans</text>"##,
        -title_h * 0.35,
        font * 1.2,
        planner.name(),
        run.outcome.as_str(),
        num((run.length_cells * 100.0).round() / 100.0),
        run.events.len().saturating_sub(1)
    );
    let _ = write!(
        s,
        r##"<rect x="0" y="0" width="{w}" height="{h}" fill="#ffffff"/>"##
    );
    // Run-length rectangles per row of cells matching `pick`.
    let rows = |s: &mut String, pick: &dyn Fn(usize, usize) -> bool, fill: &str, opacity: f64| {
        for y in 0..h {
            let mut x = 0;
            while x < w {
                if pick(x, y) {
                    let x0 = x;
                    while x < w && pick(x, y) {
                        x += 1;
                    }
                    let _ = write!(
                        s,
                        r#"<rect x="{x0}" y="{y}" width="{}" height="1" fill="{fill}" fill-opacity="{opacity}" shape-rendering="crispEdges"/>"#,
                        x - x0
                    );
                } else {
                    x += 1;
                }
            }
        }
    };
    let seen = |x: usize, y: usize| {
        truth
            .index(x, y)
            .and_then(|i| run.belief.seen.get(i).copied())
            .unwrap_or(false)
    };
    rows(
        &mut s,
        &|x, y| seen(x, y) && truth.is_free(x, y),
        "#cfe8ff",
        1.0,
    );
    rows(&mut s, &|x, y| !truth.is_free(x, y), "#222222", 1.0);
    rows(
        &mut s,
        &|x, y| believed.get(x, y) == Some(Occupancy::Occupied),
        "#ff9896",
        0.6,
    );
    let points: Vec<String> = run
        .waypoints
        .iter()
        .map(|c| format!("{}.5,{}.5", c.x, c.y))
        .collect();
    let stroke = (2.0 / px).max(0.15);
    let _ = write!(
        s,
        r##"<polyline points="{}" fill="none" stroke="#d62728" stroke-width="{stroke:.3}" stroke-linejoin="round"/>"##,
        points.join(" ")
    );
    // The animation (SMIL, played by browsers; a static renderer shows the whole drive with
    // the robot at the start): the robot moves along the track at constant speed, the track darkens behind it, and each
    // re-planning point appears when the robot reaches it. All share one duration and loop.
    let along = track_fractions(&run.waypoints);
    let total = run.length_cells;
    let duration_s = (total / ANIMATION_CELLS_PER_S).clamp(MIN_ANIMATION_S, MAX_ANIMATION_S);
    if total > 0.0 {
        let _ = write!(
            s,
            r##"<polyline points="{}" fill="none" stroke="#7f0000" stroke-width="{:.3}" stroke-linejoin="round" stroke-dasharray="{total:.3} {total:.3}" stroke-dashoffset="{total:.3}"><animate attributeName="stroke-dashoffset" from="{total:.3}" to="0" dur="{duration_s:.2}s" repeatCount="indefinite"/></polyline>"##,
            points.join(" "),
            stroke * 1.2
        );
    }
    let r = (4.0 / px).max(0.4);
    let mut from = 0;
    for e in run.events.iter().skip(1) {
        // The event's cell is a waypoint of the track (re-planning cells are), at or after
        // the previous event's.
        let found = run.waypoints[from..]
            .iter()
            .position(|&c| c == e.cell)
            .map(|k| from + k);
        let fraction = found.map_or(0.0, |k| along[k]);
        from = found.unwrap_or(from);
        let _ = write!(
            s,
            r##"<circle cx="{}.5" cy="{}.5" r="{r:.3}" fill="none" stroke="#ff7f0e" stroke-width="{:.3}"><animate attributeName="opacity" values="0;1" keyTimes="0;{fraction:.5}" calcMode="discrete" dur="{duration_s:.2}s" repeatCount="indefinite"/></circle>"##,
            e.cell.x,
            e.cell.y,
            stroke * 0.7
        );
    }
    if let (Some(first), true) = (run.waypoints.first(), total > 0.0) {
        // The centre's coordinates animated through the waypoints, key times at their
        // fractions of the length (constant speed); repeated points (no length) left out.
        let (mut xs, mut ys, mut times) = (Vec::new(), Vec::new(), Vec::<String>::new());
        let mut last = f64::NEG_INFINITY;
        for (c, &f) in run.waypoints.iter().zip(&along) {
            if f > last {
                xs.push(format!("{}.5", c.x));
                ys.push(format!("{}.5", c.y));
                times.push(format!("{f:.5}"));
                last = f;
            }
        }
        if let Some(t) = times.last_mut() {
            // Exactly 1 however the fractions round.
            "1".clone_into(t);
        }
        let times = times.join(";");
        let _ = write!(
            s,
            r##"<circle class="robot" cx="{}.5" cy="{}.5" r="{:.3}" fill="#7f0000" stroke="#ffffff" stroke-width="{:.3}"><animate attributeName="cx" values="{}" keyTimes="{times}" dur="{duration_s:.2}s" repeatCount="indefinite"/><animate attributeName="cy" values="{}" keyTimes="{times}" dur="{duration_s:.2}s" repeatCount="indefinite"/></circle>"##,
            first.x,
            first.y,
            r * 1.1,
            stroke * 0.5,
            xs.join(";"),
            ys.join(";"),
        );
    }
    for (c, colour) in [(start, "#2ca02c"), (goal, "#1f77b4")] {
        let _ = write!(
            s,
            r#"<circle cx="{}.5" cy="{}.5" r="{:.3}" fill="{colour}"/>"#,
            c.x,
            c.y,
            r * 1.2
        );
    }
    let items = [
        ("#222222", "obstacle (true map)"),
        ("#cfe8ff", "sensed free floor"),
        ("#ff9896", "obstacle on the believed map"),
        ("#d62728", "driven track"),
        ("#ff7f0e", "re-planning point (appears when reached)"),
        ("#7f0000", "robot and track driven (animated in a browser)"),
        ("#2ca02c", "start"),
        ("#1f77b4", "goal"),
    ];
    let line = 16.0 / px;
    for (i, (colour, label)) in items.iter().enumerate() {
        let col = i % 2;
        let row = i / 2;
        let x = col as f64 * (w as f64 / 2.0);
        let y = h as f64 + line * (row as f64 + 0.8);
        let _ = write!(
            s,
            r##"<rect x="{x:.3}" y="{:.3}" width="{:.3}" height="{:.3}" fill="{colour}" stroke="#555" stroke-width="{:.3}"/><text x="{:.3}" y="{y:.3}" font-size="{font:.3}" fill="#222">{label}</text>"##,
            y - font * 0.8,
            font,
            font,
            stroke * 0.2,
            x + font * 1.5
        );
    }
    s.push_str("</svg>\n");
    s
}
