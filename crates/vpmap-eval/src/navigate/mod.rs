//! The unknown-terrain navigation benchmark (`vpmap bench --navigate`): on Moving AI maps a
//! robot starts knowing nothing (every cell unknown, believed free), senses within a range
//! and re-plans with every online planner, side by side in one run on the same episodes.
//!
//! Per map and planner: total planning time per episode, travelled length, re-plans and
//! expansions; per map the D* Lite / repeated A* time ratio of their own drives (both are
//! optimal on the belief at every step, but equally short plans may differ and reveal
//! different cells, so the drives differ), and, when `dstar-lite-ties` runs, the ratio on
//! one and the same track: the tuned repeated A* timed at every planning event of the
//! common-tie D* Lite drive, on the same belief from the same cell (see
//! [`vpmap_plan::navigate::navigate_with_astar_timed`]); with `astar-ties` too, the
//! episodes where the two common-tie drives have equal lengths.

mod eval;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vpmap_plan::navigate::{
    NavigateOptions, OnlinePlanner, Outcome, ShadowAstar, navigate, navigate_with_astar_timed,
};
use vpmap_plan::{CellXy, Components, Occupancy, OccupancyGrid};

use crate::error::{EvalError, Result};
use crate::output::OutputSet;
use crate::progress::Progress;

pub use eval::{
    EVAL_SECTION, NavEvalOptions, NavTrial, eval_published_section, eval_table, run_eval,
};

/// The default maps of the benchmark, under the Moving AI folder's `maps/`: larger maps of
/// several kinds.
pub const DEFAULT_MAPS: [&str; 5] = [
    "bg512/AR0500SR.map",
    "random/random512-20-0.map",
    "rooms/32room_000.map",
    "mazes/maze512-32-0.map",
    "da2/ht_chantry.map",
];

/// The section of a results file (`docs/results.md`) the benchmark publishes into.
pub const SECTION: &str = "bench-navigate";

/// [`DEFAULT_MAPS`] in the Moving AI folder ([`crate::bench::maps::movingai_dir`]).
///
/// # Errors
/// When the Moving AI folder is not found (the message says where it was looked for).
pub fn default_maps() -> std::result::Result<Vec<PathBuf>, String> {
    let dir = crate::bench::maps::movingai_dir()?;
    Ok(DEFAULT_MAPS
        .iter()
        .map(|m| dir.join("maps").join(m))
        .collect())
}

/// The benchmark's published section: where, when and how it was measured (`elapsed`,
/// `command`), then its [`table`].
#[must_use]
pub fn published_section(table: &str, elapsed: std::time::Duration, command: &str) -> String {
    crate::publish::published(
        "Unknown terrain: every online planner on the same episodes (`vpmap bench --navigate`)",
        &format!(
            "How the drive works and how to read this: [navigation.md](navigation.md).\n\n{table}"
        ),
        elapsed,
        command,
    )
}

/// Options of [`run`].
#[derive(Clone, Debug)]
pub struct NavBenchOptions {
    /// Moving AI `.map` files.
    pub maps: Vec<PathBuf>,
    /// Episodes (start and goal pairs) per map.
    pub episodes: usize,
    /// Sensor range, cells.
    pub sensor_range_cells: f64,
    /// The planners, run on the same episodes.
    pub planners: Vec<OnlinePlanner>,
    /// Seed of the episodes' endpoints.
    pub seed: u64,
    /// The command line, for the report.
    pub command: String,
}

/// One episode of one planner.
#[derive(Clone, Debug)]
pub struct Episode {
    /// Map file name.
    pub map: String,
    /// Episode number on its map.
    pub episode: usize,
    /// Start and goal cells.
    pub endpoints: (CellXy, CellXy),
    /// The planner.
    pub planner: OnlinePlanner,
    /// How it ended.
    pub outcome: Outcome,
    /// Travelled length, cells.
    pub length_cells: f64,
    /// Total planning time, seconds.
    pub planning_time_s: f64,
    /// Re-plans (events after the first).
    pub replans: usize,
    /// Expansions of every event.
    pub expanded: usize,
    /// `dstar-lite-ties` only: the tuned repeated A* on this same track (every planning
    /// event, same belief), forward from the robot and backward from the goal.
    pub astar_same_track: Option<ShadowAstar>,
}

/// Episodes' endpoints on `grid`: random free cells of its largest component, at least a
/// quarter of the map's larger side apart (octile), drawn with `rng`.
fn endpoints(grid: &OccupancyGrid, n: usize, rng: &mut ChaCha8Rng) -> Vec<(CellXy, CellXy)> {
    let components = Components::label(grid, false);
    let largest = (1..=components.count() as u32).max_by_key(|&l| components.size(l));
    let Some(largest) = largest else {
        return Vec::new();
    };
    let cells: Vec<CellXy> = components
        .labels()
        .iter()
        .enumerate()
        .filter(|&(_, &l)| l == largest)
        .map(|(i, _)| components.cell_at(i))
        .collect();
    let min_apart = grid.width().max(grid.height()) / 4;
    let mut out = Vec::new();
    for _ in 0..n * 1000 {
        if out.len() == n || cells.is_empty() {
            break;
        }
        let a = cells[rng.random_range(0..cells.len())];
        let b = cells[rng.random_range(0..cells.len())];
        if a.x.abs_diff(b.x).max(a.y.abs_diff(b.y)) >= min_apart {
            out.push((a, b));
        }
    }
    out
}

/// Run every planner on every episode of every map.
///
/// # Errors
/// A map that cannot be read, a planner error (budget), or no maps.
pub fn run(opts: &NavBenchOptions, progress: &dyn Progress) -> Result<Vec<Episode>> {
    if opts.maps.is_empty() || opts.planners.is_empty() || opts.episodes == 0 {
        return Err(EvalError::Invalid(
            "the navigation benchmark needs at least one map, one planner and one episode"
                .to_owned(),
        ));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
    let total = (opts.maps.len() * opts.episodes * opts.planners.len()) as u64;
    progress.start(total);
    let mut results = Vec::new();
    for path in &opts.maps {
        let truth = vpmap_plan::read_movingai_map(path)?;
        let name = map_name(path);
        let belief = OccupancyGrid::new(
            truth.width(),
            truth.height(),
            truth.resolution_m(),
            truth.origin_m(),
            Occupancy::Unknown,
        )?;
        for (episode, (start, goal)) in endpoints(&truth, opts.episodes, &mut rng)
            .into_iter()
            .enumerate()
        {
            for &planner in &opts.planners {
                let nav = NavigateOptions {
                    planner,
                    sensor_range_cells: opts.sensor_range_cells,
                    unknown_passable: true,
                    ..NavigateOptions::default()
                };
                let run = if planner == OnlinePlanner::DStarLiteTies {
                    navigate_with_astar_timed(&belief, &truth, start, goal, &nav)?
                } else {
                    navigate(&belief, &truth, start, goal, &nav)?
                };
                results.push(Episode {
                    map: name.clone(),
                    episode,
                    endpoints: (start, goal),
                    planner,
                    outcome: run.outcome,
                    length_cells: run.length_cells,
                    planning_time_s: run.planning_time_s,
                    replans: run.events.len().saturating_sub(1),
                    expanded: run.expanded,
                    astar_same_track: run.shadow_astar,
                });
                progress.message(&format!("{name} #{episode} {}", planner.name()));
                progress.step();
            }
        }
    }
    progress.finish();
    Ok(results)
}

fn map_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// `navigate.csv` (one row per episode and planner) and `navigate.md` (per map: mean
/// planning time per episode and mean travelled length for every planner, the D* Lite /
/// repeated A* time ratio and the episodes of equal D* Lite and A* lengths).
#[must_use]
pub fn report(results: &[Episode], opts: &NavBenchOptions) -> OutputSet {
    let mut csv = String::from(
        "map,episode,start_x,start_y,goal_x,goal_y,planner,outcome,length_cells,planning_time_s,replans,expanded,astar_same_track_time_s,astar_same_track_expanded,backward_astar_same_track_time_s,backward_astar_same_track_expanded\n",
    );
    for e in results {
        let shadow = |f: &dyn Fn(&ShadowAstar) -> String| {
            e.astar_same_track.as_ref().map_or_else(String::new, f)
        };
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            e.map,
            e.episode,
            e.endpoints.0.x,
            e.endpoints.0.y,
            e.endpoints.1.x,
            e.endpoints.1.y,
            e.planner.name(),
            e.outcome.as_str(),
            e.length_cells,
            e.planning_time_s,
            e.replans,
            e.expanded,
            shadow(&|a| a.forward_time_s.to_string()),
            shadow(&|a| a.forward_expanded.to_string()),
            shadow(&|a| a.backward_time_s.to_string()),
            shadow(&|a| a.backward_expanded.to_string()),
        );
    }
    let mut md = table(results, opts);
    md.push('\n');
    let mut files = OutputSet::default();
    files.add("navigate.csv", csv);
    files.add("navigate.md", std::mem::take(&mut md));
    files
}

/// The Markdown table of [`report`].
#[must_use]
pub fn table(results: &[Episode], opts: &NavBenchOptions) -> String {
    let mut maps: Vec<&str> = Vec::new();
    for e in results {
        if !maps.contains(&e.map.as_str()) {
            maps.push(&e.map);
        }
    }
    let mut md = String::new();
    let _ = writeln!(
        md,
        "Unknown terrain: the robot starts knowing nothing (free-space assumption), sensor range {} cells; {} episodes per map; mean planning time per episode (ms) / mean travelled length (cells).\n",
        opts.sensor_range_cells, opts.episodes
    );
    // The comparison columns that the planners run make meaningful, each with its note.
    let has = |p: OnlinePlanner| opts.planners.contains(&p);
    let own = has(OnlinePlanner::Astar) && has(OnlinePlanner::DStarLite);
    let same_track = has(OnlinePlanner::DStarLiteTies);
    let common = has(OnlinePlanner::AstarTies) && has(OnlinePlanner::DStarLiteTies);
    let mbpp = has(OnlinePlanner::Mbpp)
        && (has(OnlinePlanner::DStarLite) || has(OnlinePlanner::DStarLiteTies));
    let mut headers: Vec<&str> = vec!["map"];
    headers.extend(opts.planners.iter().map(|p| p.name()));
    if own {
        headers.extend(["D* Lite / A* time", "D* Lite = A* length"]);
    }
    if same_track {
        headers.extend([
            "same track: D* Lite / A* time",
            "same track: D* Lite / backward A* time",
        ]);
    }
    if common {
        headers.push("common ties: equal lengths");
    }
    if mbpp {
        headers.push("MBPP / D* Lite length");
    }
    let _ = writeln!(md, "| {} |", headers.join(" | "));
    let _ = writeln!(md, "|{}", "---|".repeat(headers.len()));
    for map in maps {
        let of = |p: OnlinePlanner| -> Vec<&Episode> {
            results
                .iter()
                .filter(|e| e.map == map && e.planner == p)
                .collect()
        };
        let mean = |v: &[&Episode], f: &dyn Fn(&Episode) -> f64| {
            if v.is_empty() {
                f64::NAN
            } else {
                v.iter().map(|e| f(e)).sum::<f64>() / v.len() as f64
            }
        };
        let _ = write!(md, "| {map} |");
        for &p in &opts.planners {
            let v = of(p);
            let _ = write!(
                md,
                " {:.1} / {:.1} |",
                mean(&v, &|e| e.planning_time_s * 1e3),
                mean(&v, &|e| e.length_cells)
            );
        }
        let equal_lengths = |x: &[&Episode], y: &[&Episode]| {
            let equal = x
                .iter()
                .zip(y)
                .filter(|(a, b)| (a.length_cells - b.length_cells).abs() < 1e-9)
                .count();
            format!("{equal} of {}", x.len().min(y.len()))
        };
        let (d, a) = (of(OnlinePlanner::DStarLite), of(OnlinePlanner::Astar));
        if own {
            let ratio = mean(&d, &|e| e.planning_time_s) / mean(&a, &|e| e.planning_time_s);
            let _ = write!(md, " {ratio:.2} | {} |", equal_lengths(&d, &a));
        }
        let (dt, at) = (
            of(OnlinePlanner::DStarLiteTies),
            of(OnlinePlanner::AstarTies),
        );
        if same_track {
            let shadowed: Vec<&Episode> = dt
                .iter()
                .copied()
                .filter(|e| e.astar_same_track.is_some())
                .collect();
            if shadowed.is_empty() {
                let _ = write!(md, " - | - |");
            } else {
                let d_time = mean(&shadowed, &|e| e.planning_time_s);
                let a_time = |f: fn(&ShadowAstar) -> f64| {
                    mean(&shadowed, &|e| {
                        e.astar_same_track.as_ref().map_or(f64::NAN, f)
                    })
                };
                let _ = write!(
                    md,
                    " {:.2} | {:.2} |",
                    d_time / a_time(|a| a.forward_time_s),
                    d_time / a_time(|a| a.backward_time_s)
                );
            }
        }
        if common {
            let _ = write!(md, " {} |", equal_lengths(&dt, &at));
        }
        if mbpp {
            // Online MBPP's mean travelled length over D* Lite's, with its own ties and with
            // the common tie rule (the spread between the two is what ties alone make).
            let m = of(OnlinePlanner::Mbpp);
            let length = |v: &[&Episode]| mean(v, &|e| e.length_cells);
            let over = |v: &[&Episode]| {
                if m.is_empty() || v.is_empty() {
                    "-".to_owned()
                } else {
                    format!("{:.2}", length(&m) / length(v))
                }
            };
            let _ = write!(md, " {} ; {} |", over(&d), over(&dt));
        }
        md.push('\n');
    }
    let mut notes: Vec<&str> = Vec::new();
    if own {
        notes.push(
            "D* Lite / A* time: each on its own drive (the drives differ: equally short plans differ and reveal different cells).",
        );
    }
    if same_track {
        notes.push(
            "Same track: the common-tie D* Lite drive (`dstar-lite-ties`, the drive `astar-ties` makes too), with the tuned repeated A* timed at each of its planning events on the same belief, forward from the robot's cell (as the `astar` planner plans) and backward from the goal (the direction D* Lite searches in: what D* Lite's reuse saves over searching that way from scratch).",
        );
    }
    if has(OnlinePlanner::AstarTies) {
        notes.push(
            "`astar-ties` itself is a plain A* (binary heap), slower than the tuned one; it is run for the equal lengths.",
        );
    }
    if mbpp {
        notes.push(
            "MBPP / D* Lite length: online MBPP's mean travelled length over `dstar-lite`'s ; over `dstar-lite-ties`'s (`-` for a planner not run).",
        );
    }
    if !notes.is_empty() {
        let _ = writeln!(md, "\n{}", notes.join(" "));
    }
    let _ = writeln!(
        md,
        "\nMeasured with `{}` on {}{}: times are indicative, ratios measured side by side in one run.",
        opts.command,
        crate::publish::machine_description(),
        load_average().map_or_else(String::new, |l| format!(
            " (load average {l} at the end of the run)"
        ))
    );
    md
}

/// The one-minute load average (`/proc/loadavg`), where the system reports it.
fn load_average() -> Option<String> {
    let text = std::fs::read_to_string("/proc/loadavg").ok()?;
    let first = text.split_whitespace().next()?;
    first.parse::<f64>().ok().map(|_| first.to_owned())
}
