//! `vpmap navigate`: a robot drives a believed map, senses the true one and re-plans (see
//! docs/navigation.md).

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use vpmap_pipeline::{
    DriveMap, DriveReport, Endpoint, EndpointRules, OptionNames, PipelineError, PlanningMap,
    SmoothDriveReport, drive_maps, endpoint_cell, navigate_json, navigate_smooth_json,
    navigate_smooth_svg, smooth_options,
};
use vpmap_plan::budget::{Budget, Stop};
use vpmap_plan::grid::{CellXy, OccupancyGrid};
use vpmap_plan::navigate::{
    NavigateOptions, OnlinePlanner, SmoothNavigateOptions, navigate, navigate_smooth, truth_optimum,
};

use crate::output::OutputSet;
use crate::plan::{check_robot_radius, parse_point, parse_pose};
use vpmap_pipeline::num;

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
    /// Start `X,Y` (metres in the map's frame; cells for a Moving AI map); with `--planner
    /// smooth`, `X,Y,HEADING` too (degrees, atan2(dy, dx) in the map's coordinates; free
    /// when left out).
    #[arg(long, allow_hyphen_values = true)]
    from: String,
    /// Goal `X,Y` (with `--planner smooth`, `X,Y,HEADING` as for `--from`).
    #[arg(long, allow_hyphen_values = true)]
    to: String,
    /// Online planner: astar, astar-ps, dstar-lite, mbpp, astar-ties, dstar-lite-ties, or
    /// smooth (curvature-bounded curves re-planned from the robot's pose and heading; needs
    /// --turning-radius).
    #[arg(long, default_value = "dstar-lite", value_parser = parse_planner)]
    planner: NavPlanner,
    /// `--planner smooth`: the smallest turning radius (metres for ROS maps and map.json,
    /// cells for a Moving AI map).
    #[arg(long, allow_negative_numbers = true)]
    turning_radius: Option<f64>,
    /// `--planner smooth`: allow driving in reverse (cusps, reported as such).
    #[arg(long)]
    reverse: bool,
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

/// What `--planner` names: an online grid planner or the smooth planner.
#[derive(Clone, Copy, Debug)]
enum NavPlanner {
    Online(OnlinePlanner),
    Smooth,
}

fn parse_planner(s: &str) -> std::result::Result<NavPlanner, String> {
    if s == "smooth" {
        return Ok(NavPlanner::Smooth);
    }
    s.parse::<OnlinePlanner>()
        .map(NavPlanner::Online)
        .map_err(|e| format!("{e}, smooth"))
}

/// The believed and true maps of a run (same grid).
fn load_maps(args: &NavigateArgs) -> Result<(PlanningMap, OccupancyGrid)> {
    match (&args.map, args.unknown) {
        (Some(_), true) => bail!("give either a believed map or --unknown, not both"),
        (None, false) => bail!("give a believed map (map.json, .yaml or .map) or --unknown"),
        _ => {}
    }
    check_robot_radius(args.robot_radius)?;
    drive_maps(
        args.map.clone().map(DriveMap::File),
        DriveMap::File(args.truth.clone()),
        args.robot_radius,
        args.resolution,
    )
    .map_err(|e| match e {
        PipelineError::OptionOutOfRange { value, .. } => anyhow::anyhow!(
            "--resolution must be a positive number of metres, got {}",
            num(value)
        ),
        other => other.into(),
    })
}

/// `vpmap navigate`.
pub fn run(args: &NavigateArgs) -> Result<()> {
    let planner = match args.planner {
        NavPlanner::Smooth => return run_smooth(args),
        NavPlanner::Online(p) => p,
    };
    if args.turning_radius.is_some() || args.reverse {
        bail!("--turning-radius and --reverse are for --planner smooth");
    }
    let from = parse_point("--from", &args.from)?;
    let to = parse_point("--to", &args.to)?;
    let (believed, truth) = load_maps(args)?;
    let scale = if believed.in_cells {
        1.0
    } else {
        believed.grid.resolution_m()
    };
    let unit = if believed.in_cells { "cells" } else { "m" };
    let range_cells =
        vpmap_pipeline::drive::sensor_range_cells(args.sensor_range, scale, unit, "--sensor-range")
            .map_err(anyhow::Error::msg)?;
    let (start, goal) = endpoints_on_truth(args, &believed, &truth, from, to)?;
    let opts = NavigateOptions {
        planner,
        sensor_range_cells: range_cells,
        unknown_passable: !args.unknown_blocked,
        max_moves: args.max_moves,
        max_replans: args.max_replans,
        budget: budget(args),
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
    let report = DriveReport {
        run: &run,
        optimum: &optimum,
        planner,
        unknown_passable: !args.unknown_blocked,
        sensor_range_cells: range_cells,
        scale,
        unit,
    };
    let json = navigate_json(&report, &coords);
    let mut outputs = OutputSet::default();
    outputs.add(
        "navigate.json",
        serde_json::to_string_pretty(&json).context("serialising navigate.json")?,
    );
    outputs.add(
        "navigate.svg",
        vpmap_render::navigation_svg(&truth, &believed.grid, &run, start, goal, planner),
    );
    outputs.write_all(&args.out)?;
    println!(
        "{}: {} after {} moves, driven {:.3} {unit} (true optimum {} octile, {} any-angle), {} re-plans, planning {:.3} ms; wrote {}",
        planner.name(),
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

/// The budget of each re-plan, from the flags.
fn budget(args: &NavigateArgs) -> Budget {
    Budget {
        max_expansions: args.max_expansions,
        max_sight_cells: args.max_sight_cells,
        stop: args
            .timeout
            .map_or_else(Stop::new, |t| Stop::new().with_timeout(t)),
    }
}

/// The start and the goal as cells of the true map (in the believed map's coordinates, with its
/// robot radius), named `--from` and `--to` in errors.
fn endpoints_on_truth(
    args: &NavigateArgs,
    believed: &PlanningMap,
    truth: &OccupancyGrid,
    from: [f64; 2],
    to: [f64; 2],
) -> Result<(CellXy, CellXy)> {
    let coordinates = believed.coordinates();
    let rules = EndpointRules {
        unknown_passable: false,
        robot_radius: believed.robot_radius,
        names: OptionNames::CommandLine,
    };
    let on_truth = |name: &str, point| {
        endpoint_cell(truth, coordinates, &Endpoint { name, point }, &rules)
            .with_context(|| format!("{name} on the true map {}", args.truth.display()))
    };
    let start = on_truth("--from", from)?;
    let goal = on_truth("--to", to)?;
    Ok((start, goal))
}

/// `vpmap navigate --planner smooth`.
fn run_smooth(args: &NavigateArgs) -> Result<()> {
    let (from, start_heading) = parse_pose("--from", &args.from)?;
    let (to, goal_heading) = parse_pose("--to", &args.to)?;
    let Some(radius) = args.turning_radius else {
        bail!("--planner smooth needs --turning-radius (metres, or cells for a Moving AI map)");
    };
    let (believed, truth) = load_maps(args)?;
    let (scale, unit) = (believed.scale(), believed.unit());
    let range_cells =
        vpmap_pipeline::drive::sensor_range_cells(args.sensor_range, scale, unit, "--sensor-range")
            .map_err(anyhow::Error::msg)?;
    let headings = [start_heading, goal_heading];
    let mut smooth = smooth_options(
        &believed,
        radius,
        "--turning-radius",
        headings,
        args.reverse,
    )?;
    smooth.budget = budget(args);
    let (start, goal) = endpoints_on_truth(args, &believed, &truth, from, to)?;
    let opts = SmoothNavigateOptions {
        smooth,
        sensor_range_cells: range_cells,
        unknown_passable: !args.unknown_blocked,
        max_moves: args.max_moves,
        max_replans: args.max_replans,
        ..SmoothNavigateOptions::default()
    };
    let run = navigate_smooth(&believed.grid, &truth, start, goal, &opts)
        .map_err(|e| crate::plan::name_the_flag(e.into()))?;
    let optimum = truth_optimum(&truth, start, goal, &opts.smooth.budget)
        .map_err(|e| crate::plan::name_the_flag(e.into()))?;
    let report = SmoothDriveReport {
        run: &run,
        optimum: &optimum,
        opts: &opts.smooth,
        unknown_passable: opts.unknown_passable,
        sensor_range_cells: range_cells,
    };
    let json = navigate_smooth_json(&believed, &report);
    let mut outputs = OutputSet::default();
    outputs.add(
        "navigate.json",
        serde_json::to_string_pretty(&json).context("serialising navigate.json")?,
    );
    outputs.add(
        "navigate.svg",
        navigate_smooth_svg(&believed, &truth, &report, [start, goal], radius),
    );
    outputs.write_all(&args.out)?;
    let reason = run
        .reason
        .as_ref()
        .map_or_else(String::new, |r| format!(" ({r})"));
    println!(
        "smooth: {}{reason} after {} moves, driven {:.3} {unit} (true any-angle optimum {}), {} cusps, tightest radius {}, {} re-plans, planning {:.3} ms; wrote {}",
        run.outcome.as_str(),
        run.moves,
        run.length_cells * scale,
        optimum
            .any_angle_cells
            .map_or_else(|| "none".to_owned(), |l| format!("{:.3} {unit}", l * scale)),
        run.cusps,
        if run.max_curvature > 0.0 {
            format!("{:.3} {unit}", scale / run.max_curvature)
        } else {
            "none (straight)".to_owned()
        },
        run.events.len().saturating_sub(1),
        run.planning_time_s * 1e3,
        args.out.display()
    );
    Ok(())
}
