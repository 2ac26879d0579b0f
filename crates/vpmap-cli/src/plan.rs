//! `vpmap plan`: a path across a Moving AI map, a ROS map or a vpmap `map.json`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use vpmap_metrology::map::FloorMap;
use vpmap_plan::astar::{AstarOptions, astar};
use vpmap_plan::grid::{Cell, OccupancyGrid};
use vpmap_plan::plan::Plan;
use vpmap_plan::raster::{RasterOptions, rasterize_map};

use crate::num;
use crate::output::write_file;

/// The planners `vpmap plan` offers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum PlannerName {
    /// 8-connected octile A*, no corner cutting.
    Astar,
    /// A* followed by line-of-sight post-smoothing.
    AstarPs,
    /// Basic Theta* (any-angle).
    ThetaStar,
    /// The exact shortest any-angle path (visibility graph over obstacle-corner cells).
    Optimal,
}

impl PlannerName {
    /// The planner's name on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Self::Astar => "astar",
            Self::AstarPs => "astar-ps",
            Self::ThetaStar => "theta-star",
            Self::Optimal => "optimal",
        }
    }
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
    #[arg(long, value_enum, default_value = "astar")]
    planner: PlannerName,
    /// Inflate obstacles by this radius (metres for ROS maps and map.json, cells for .map).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    robot_radius: f64,
    /// Grid resolution for a `map.json`, metres.
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    resolution: f64,
    /// Let the path cross unknown cells.
    #[arg(long)]
    unknown_passable: bool,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Draw the grid and the path into this SVG file.
    #[arg(long)]
    svg: Option<PathBuf>,
}

/// A map ready for planning, and how its coordinates read.
pub struct PlanningMap {
    /// The grid (inflated).
    pub grid: OccupancyGrid,
    /// Coordinates are cells (Moving AI) rather than metres.
    pub in_cells: bool,
}

impl PlanningMap {
    fn cell_of(&self, what: &str, p: [f64; 2]) -> Result<(usize, usize)> {
        if self.in_cells {
            let (x, y) = (p[0], p[1]);
            if x.fract() != 0.0 || y.fract() != 0.0 || x < 0.0 || y < 0.0 {
                bail!(
                    "{what} ({}, {}) must be whole cell coordinates (column, row) for a Moving AI map",
                    num(x),
                    num(y)
                );
            }
            let (x, y) = (x as usize, y as usize);
            if x >= self.grid.width() || y >= self.grid.height() {
                bail!(
                    "{what} ({x}, {y}) is outside the {} x {} map",
                    self.grid.width(),
                    self.grid.height()
                );
            }
            Ok((x, y))
        } else {
            self.grid.cell_from_world(p).with_context(|| {
                let o = self.grid.origin_m();
                let r = self.grid.resolution_m();
                format!(
                    "{what} ({}, {}) m is outside the map, which spans x {:.2}..{:.2} m, y {:.2}..{:.2} m",
                    num(p[0]),
                    num(p[1]),
                    o[0],
                    o[0] + self.grid.width() as f64 * r,
                    o[1],
                    o[1] + self.grid.height() as f64 * r
                )
            })
        }
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
}

fn parse_point(what: &str, text: &str) -> Result<[f64; 2]> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let parsed: Vec<f64> = parts.iter().filter_map(|s| s.parse().ok()).collect();
    match parsed.as_slice() {
        [x, y] if parts.len() == 2 && x.is_finite() && y.is_finite() => Ok([*x, *y]),
        _ => bail!("{what} {text:?} is not a point X,Y (two numbers separated by a comma)"),
    }
}

/// Read any supported map and inflate its obstacles.
pub fn load_map(path: &Path, robot_radius: f64, resolution: f64) -> Result<PlanningMap> {
    if !(robot_radius.is_finite() && robot_radius >= 0.0) {
        bail!(
            "--robot-radius must be a non-negative number, got {}",
            num(robot_radius)
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
    let radius = if in_cells {
        robot_radius * grid.resolution_m()
    } else {
        robot_radius
    };
    let grid = grid.inflate(radius)?;
    Ok(PlanningMap { grid, in_cells })
}

/// Run one planner.
pub fn run_planner(
    planner: PlannerName,
    grid: &OccupancyGrid,
    start: (usize, usize),
    goal: (usize, usize),
    unknown_passable: bool,
) -> Result<Option<Plan>> {
    use vpmap_plan::{
        AstarPsOptions, OptimalAnyAngleOptions, ThetaStarOptions, astar_ps, optimal_any_angle,
        theta_star,
    };
    Ok(match planner {
        PlannerName::Astar => astar(grid, start, goal, &AstarOptions { unknown_passable })?,
        PlannerName::AstarPs => astar_ps(grid, start, goal, &AstarPsOptions { unknown_passable })?,
        PlannerName::ThetaStar => {
            theta_star(grid, start, goal, &ThetaStarOptions { unknown_passable })?
        }
        PlannerName::Optimal => optimal_any_angle(
            grid,
            start,
            goal,
            &OptimalAnyAngleOptions { unknown_passable },
        )?,
    })
}

/// `vpmap plan`.
pub fn run(args: &PlanArgs) -> Result<()> {
    let from = parse_point("--from", &args.from)?;
    let to = parse_point("--to", &args.to)?;
    let map = load_map(&args.map, args.robot_radius, args.resolution)?;
    let start = map.cell_of("--from", from)?;
    let goal = map.cell_of("--to", to)?;
    for (what, p, cell) in [("--from", from, start), ("--to", to, goal)] {
        let state = map.grid.get(cell.0, cell.1).unwrap_or(Cell::Unknown);
        let ok = state == Cell::Free || (state == Cell::Unknown && args.unknown_passable);
        if !ok {
            let what_is_there = match state {
                Cell::Occupied if args.robot_radius > 0.0 => {
                    "an obstacle (or within --robot-radius of one)"
                }
                Cell::Occupied => "an obstacle",
                _ => "an unknown cell (use --unknown-passable to allow it)",
            };
            bail!(
                "{what} ({}, {}) {} lies on {what_is_there}: cell ({}, {})",
                num(p[0]),
                num(p[1]),
                map.unit(),
                cell.0,
                cell.1
            );
        }
    }
    let began = Instant::now();
    let plan = run_planner(args.planner, &map.grid, start, goal, args.unknown_passable)?;
    let seconds = began.elapsed().as_secs_f64();
    let scale = if map.in_cells {
        1.0
    } else {
        map.grid.resolution_m()
    };
    if let Some(svg_path) = &args.svg {
        write_file(svg_path, path_svg(&map.grid, plan.as_ref(), start, goal))?;
    }
    let waypoints: Vec<[f64; 2]> = plan
        .as_ref()
        .map(|p| p.waypoints.iter().map(|c| map.coords(*c)).collect())
        .unwrap_or_default();
    if args.json {
        let stats = plan.as_ref().map(|p| p.stats).unwrap_or_default();
        let out = serde_json::json!({
            "found": plan.is_some(),
            "length": plan.as_ref().map(|p| p.length * scale),
            "units": map.unit(),
            "waypoints": waypoints,
            "planner": args.planner.name(),
            "alternatives": [],
            "stats": {
                "expanded": stats.expanded,
                "generated": stats.generated,
                "los_checks": stats.los_checks,
                "los_cells": stats.los_cells,
                "time_s": seconds,
            },
        });
        println!("{out}");
    } else if let Some(p) = &plan {
        println!(
            "{}: path found, length {:.3} {} through {} waypoints ({} nodes expanded, {:.3} ms)",
            args.planner.name(),
            p.length * scale,
            map.unit(),
            p.waypoints.len(),
            p.stats.expanded,
            seconds * 1e3
        );
    } else {
        println!(
            "{}: no path: start and goal are not connected ({:.3} ms)",
            args.planner.name(),
            seconds * 1e3
        );
    }
    Ok(())
}

/// The grid (free white, occupied black, unknown grey; run-length rectangles per row), the
/// path, start and goal, one SVG unit per cell, row 0 at the top.
#[must_use]
pub fn path_svg(
    grid: &OccupancyGrid,
    plan: Option<&Plan>,
    start: (usize, usize),
    goal: (usize, usize),
) -> String {
    let (w, h) = (grid.width(), grid.height());
    let px = (900.0 / w.max(h) as f64).clamp(0.5, 24.0);
    let mut out = format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" viewBox="0 0 {w} {h}" shape-rendering="crispEdges">
<rect width="{w}" height="{h}" fill="#ffffff"/>
"##,
        w as f64 * px,
        h as f64 * px
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
    if let Some(p) = plan {
        let points: Vec<String> = p
            .waypoints
            .iter()
            .map(|c| format!("{}.5,{}.5", c.0, c.1))
            .collect();
        let _ = writeln!(
            out,
            r##"<polyline points="{}" fill="none" stroke="#d62728" stroke-width="{stroke:.3}" stroke-linejoin="round"/>"##,
            points.join(" ")
        );
    }
    for ((x, y), colour) in [(start, "#2ca02c"), (goal, "#1f77b4")] {
        let _ = writeln!(
            out,
            r#"<circle cx="{x}.5" cy="{y}.5" r="{:.3}" fill="{colour}"/>"#,
            (4.0 / px).max(0.4)
        );
    }
    out.push_str("</svg>\n");
    out
}
