//! `vpmap plan`: a path across a Moving AI map, a ROS map or a vpmap `map.json`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Result, bail};
use vpmap_pipeline::{
    Limits, OptionNames, PlanningMap, mbpp_stats, plan_json, read_planning_map, run_planner,
    smooth_json, smooth_options, smooth_text,
};
use vpmap_plan::PlanError;
use vpmap_plan::Planned;
use vpmap_plan::budget::{Budget, Stop, StopReason};
use vpmap_plan::planner::PlannerKind;
use vpmap_plan::smooth::{Pose, SmoothOutcome, plan_smooth};
use vpmap_render::{GridCoordinates, plan_svg, plan_title, smooth_svg};

use crate::output::write_file;
use vpmap_pipeline::num;

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
            "The exact shortest any-angle path (Anya-style interval search over the free space of the grid)"
        }
    }
}

/// What `--planner` names: a grid planner or the smooth planner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlannerChoice {
    /// One of [`PlannerKind::ALL`].
    Grid(PlannerKind),
    /// `smooth`: curvature-bounded paths ([`vpmap_plan::smooth`]).
    Smooth,
}

/// `--planner`: a [`PlannerKind`] by its name, read with its `FromStr`, or `smooth`; `--help`
/// lists them.
fn planner_parser() -> impl clap::builder::TypedValueParser<Value = PlannerChoice> {
    use clap::builder::{PossibleValue, TypedValueParser as _};
    let smooth = PossibleValue::new("smooth").help(
        "Curvature-bounded lines and arcs (needs --turning-radius): Dubins paths through the exact any-angle path's corners, Hybrid-A* when they fail",
    );
    clap::builder::PossibleValuesParser::new(
        PlannerKind::ALL
            .map(|k| PossibleValue::new(k.name()).help(planner_help(k)))
            .into_iter()
            .chain([smooth]),
    )
    .try_map(|name| match name.as_str() {
        "smooth" => Ok(PlannerChoice::Smooth),
        _ => name.parse::<PlannerKind>().map(PlannerChoice::Grid),
    })
}

/// Arguments of `vpmap plan`.
#[derive(clap::Args)]
pub struct PlanArgs {
    /// The map: a Moving AI `.map` (coordinates in cells), a ROS map `.yaml` or a vpmap
    /// `map.json` (coordinates in metres in the map's frame).
    map: PathBuf,
    /// Start `X,Y` (with `--planner smooth`, `X,Y,HEADING`: degrees, atan2(dy, dx) in the
    /// map's coordinates; free when left out).
    #[arg(long, allow_hyphen_values = true)]
    from: String,
    /// Goal `X,Y` (with `--planner smooth`, `X,Y,HEADING` as for `--from`).
    #[arg(long, allow_hyphen_values = true)]
    to: String,
    /// Planner.
    #[arg(long, default_value = "astar", value_parser = planner_parser())]
    planner: PlannerChoice,
    /// `--planner smooth`: the smallest turning radius (metres for ROS maps and map.json,
    /// cells for .map).
    #[arg(long, allow_negative_numbers = true)]
    turning_radius: Option<f64>,
    /// `--planner smooth`: allow driving in reverse (cusps, reported as such).
    #[arg(long)]
    reverse: bool,
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
    /// MBPP's budget: most bug steps before it stops with an error (about 10 million a
    /// second; see docs/limits.md).
    #[arg(long, default_value_t = vpmap_plan::mbpp::DEFAULT_MAX_BUG_STEPS)]
    max_bug_steps: usize,
    /// Most MBPP alternative paths kept, the shortest first.
    #[arg(long, default_value_t = vpmap_plan::mbpp::DEFAULT_MAX_ALTERNATIVES)]
    max_alternatives: usize,
    /// Most node expansions of A*, A* PS, Theta* and the exact planner before they stop
    /// with an error (see docs/limits.md).
    #[arg(long, default_value_t = vpmap_plan::budget::DEFAULT_MAX_EXPANSIONS)]
    max_expansions: usize,
    /// Most grid cells the line-of-sight checks of Theta*, A* PS and the exact planner look
    /// up before they stop with an error.
    #[arg(long, default_value_t = vpmap_plan::budget::DEFAULT_MAX_SIGHT_CELLS)]
    max_sight_cells: usize,
    /// Stop any planner that has not finished after this many seconds (default: no time
    /// limit; the counted budgets above bound the work).
    #[arg(long, value_name = "SECONDS", value_parser = parse_timeout, allow_negative_numbers = true)]
    timeout: Option<std::time::Duration>,
}

/// `--timeout`: a positive number of seconds, at most a day.
pub(crate) fn parse_timeout(text: &str) -> std::result::Result<std::time::Duration, String> {
    const MAX_S: f64 = 86_400.0;
    match text.trim().parse::<f64>() {
        Ok(s) if s > 0.0 && s <= MAX_S => Ok(std::time::Duration::from_secs_f64(s)),
        _ => Err(format!(
            "{text:?} is not a time limit; give a number of seconds above 0 and at most {MAX_S:.0}"
        )),
    }
}

/// A point `X,Y` given on the command line as `what` (`--from`, `--to`): two finite numbers.
pub(crate) fn parse_point(what: &str, text: &str) -> Result<[f64; 2]> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let parsed: Vec<f64> = parts.iter().filter_map(|s| s.parse().ok()).collect();
    match parsed.as_slice() {
        [x, y] if parts.len() == 2 && x.is_finite() && y.is_finite() => Ok([*x, *y]),
        _ => bail!("{what} {text:?} is not a point X,Y (two numbers separated by a comma)"),
    }
}

/// A pose `X,Y[,HEADING]` given as `what`: the point and the heading in degrees, if any.
pub(crate) fn parse_pose(what: &str, text: &str) -> Result<([f64; 2], Option<f64>)> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if let [x, y, h] = parts.as_slice() {
        let point = parse_point(what, &format!("{x},{y}"))?;
        return match h.parse::<f64>() {
            Ok(h) if h.is_finite() => Ok((point, Some(h))),
            _ => bail!("{what} {text:?}: the heading {h:?} is not a finite number of degrees"),
        };
    }
    Ok((parse_point(what, text)?, None))
}

/// Read any supported map and inflate its obstacles by `robot_radius`
/// ([`vpmap_pipeline::read_planning_map`]), the radius checked first.
pub fn load_map(path: &Path, robot_radius: Option<f64>, resolution: f64) -> Result<PlanningMap> {
    check_robot_radius(robot_radius)?;
    Ok(read_planning_map(path, robot_radius, resolution)?)
}

/// `--robot-radius` in the same range as `vpmap build` and the page (in cells for a Moving AI
/// map).
pub fn check_robot_radius(robot_radius: Option<f64>) -> Result<()> {
    let range = &vpmap_pipeline::ROBOT_RADIUS_RANGE_M;
    if let Some(r) = robot_radius
        && !range.contains(&r)
    {
        bail!(
            "--robot-radius must be a non-negative number, at most {}, got {}",
            num(*range.end()),
            num(r)
        );
    }
    Ok(())
}

/// A planner's budget error, ending with the command-line flag that raises the budget.
pub(crate) fn name_the_flag(e: anyhow::Error) -> anyhow::Error {
    let flag = match e.downcast_ref::<PlanError>() {
        Some(PlanError::BudgetExhausted { option, .. }) => {
            format!("--{}", option.replace('_', "-"))
        }
        Some(PlanError::Stopped {
            reason: StopReason::Deadline,
            ..
        }) => "--timeout".to_owned(),
        _ => return e,
    };
    anyhow::anyhow!("{e:#} with {flag}")
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
    let planner = match args.planner {
        PlannerChoice::Smooth => return run_smooth(args),
        PlannerChoice::Grid(kind) => kind,
    };
    if args.turning_radius.is_some() || args.reverse {
        bail!("--turning-radius and --reverse are for --planner smooth");
    }
    let from = parse_point("--from", &args.from)?;
    let to = parse_point("--to", &args.to)?;
    let map = load_map(&args.map, args.robot_radius, args.resolution)?;
    let start = map.endpoint(
        "--from",
        from,
        args.unknown_passable,
        OptionNames::CommandLine,
    )?;
    let goal = map.endpoint("--to", to, args.unknown_passable, OptionNames::CommandLine)?;
    let began = Instant::now();
    let outcome = run_planner(
        planner,
        &map.grid,
        (start, goal),
        args.unknown_passable,
        args.svg.is_some(),
        &Limits {
            mbpp: Some((args.max_bug_steps, args.max_alternatives)),
            budget: Budget {
                max_expansions: args.max_expansions,
                max_sight_cells: args.max_sight_cells,
                stop: args
                    .timeout
                    .map_or_else(Stop::new, |t| Stop::new().with_timeout(t)),
            },
        },
    )
    .map_err(|e| name_the_flag(e.into()))?;
    let seconds = began.elapsed().as_secs_f64();
    if let Some(svg_path) = &args.svg {
        let coordinates = if map.in_cells {
            GridCoordinates::Cells
        } else {
            GridCoordinates::World
        };
        let title = plan_title(planner, &map_name(&args.map));
        write_file(
            svg_path,
            plan_svg(&map.grid, &outcome, start, goal, coordinates, &title),
        )?;
    }
    if args.json {
        println!("{}", plan_json(&map, planner, &outcome, seconds));
    } else {
        println!("{}", plan_text(&map, planner, &outcome, seconds));
    }
    Ok(())
}

/// The map's file name, for titles.
fn map_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// `vpmap plan --planner smooth`.
fn run_smooth(args: &PlanArgs) -> Result<()> {
    let (from, start_heading) = parse_pose("--from", &args.from)?;
    let (to, goal_heading) = parse_pose("--to", &args.to)?;
    let Some(radius) = args.turning_radius else {
        bail!("--planner smooth needs --turning-radius (metres, or cells for a Moving AI map)");
    };
    let map = load_map(&args.map, args.robot_radius, args.resolution)?;
    let headings = [start_heading, goal_heading];
    let mut opts = smooth_options(&map, radius, "--turning-radius", headings, args.reverse)?;
    let names = OptionNames::CommandLine;
    let start = map.endpoint("--from", from, args.unknown_passable, names)?;
    let goal = map.endpoint("--to", to, args.unknown_passable, names)?;
    opts.unknown_passable = args.unknown_passable;
    opts.budget = Budget {
        max_expansions: args.max_expansions,
        max_sight_cells: args.max_sight_cells,
        stop: args
            .timeout
            .map_or_else(Stop::new, |t| Stop::new().with_timeout(t)),
    };
    let began = Instant::now();
    let outcome =
        plan_smooth(&map.grid, start, goal, &opts).map_err(|e| name_the_flag(e.into()))?;
    let seconds = began.elapsed().as_secs_f64();
    let plan = match &outcome {
        SmoothOutcome::Path(p) => Some(p),
        SmoothOutcome::NoPath(_) => None,
    };
    if let Some(svg_path) = &args.svg {
        let coordinates = if map.in_cells {
            GridCoordinates::Cells
        } else {
            GridCoordinates::World
        };
        let title = format!("Smooth path on {}", map_name(&args.map));
        write_file(
            svg_path,
            smooth_svg(&map.grid, plan, start, goal, coordinates, &title),
        )?;
    }
    let poses = [
        (start, opts.start_heading_rad),
        (goal, opts.goal_heading_rad),
    ]
    .map(|(c, h)| Pose::new(c.x as f64, c.y as f64, h.unwrap_or(0.0)));
    if args.json {
        println!("{}", smooth_json(&map, &outcome, poses, seconds));
        return Ok(());
    }
    println!("{}", smooth_text(&map, &outcome, poses, seconds));
    Ok(())
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
            p.length_cells * map.scale(),
            map.unit(),
            p.waypoints.len(),
        ),
        None => format!(
            "{}: no path: start and goal are not connected ({work})",
            planner.name()
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_text_read_well() {
        assert_eq!(counted(1, "bug"), "1 bug");
        assert_eq!(counted(0, "alternative"), "0 alternatives");
    }
}
