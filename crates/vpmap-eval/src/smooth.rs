//! The smooth planner against its Hybrid-A* reference (`vpmap bench --smooth`), side by side
//! in one run on the same queries (issue 41's benchmark).
//!
//! Maps: generated maps of Nav2's benchmark kind (by default two of 2000 x 2000 cells, 100 m x
//! 100 m at 0.05 m, seeded random rectangles of 0.5 to 2.5 m over about 10 % of the area), the
//! maps vpmap builds from scenes ([`crate::bench::maps::built_maps`]: the bundled example
//! office and two synthetic rooms at 0.05 m), and, when the Moving AI folder is found, the
//! rooms map `8room_000` and the city map `Berlin_0_256`. Turning radii 0.3, 0.5 and 1 m on
//! the maps in metres; 1 and 2 cells on the rooms (doors one cell wide), 2 and 5 cells on the
//! city.
//!
//! Queries: seeded free start and goal cells joined by an any-angle path (30 to 60 m apart on
//! the Nav2-kind maps, 1 to 7.5 m on the built maps, 10 to 80 cells on the Moving AI maps); every other query has both headings
//! given (random), the rest both free. Per query and planner: whether a path was found and
//! passed the validator ([`validate_smooth`], run again here), the length ratio `length /
//! max(exact any-angle length, Dubins distance between the poses)`, the length against the
//! reference's, the time of one call (one thread, `Instant` around it), curvature sign changes
//! against the taut path's turns + 1, max curvature, min clearance and cusps. The reference is
//! the same planner with [`SmoothMethod::HybridAstar`] and a budget of
//! [`SmoothBenchOptions::hybrid_budget`] states; a query that exhausts it counts as not solved
//! by the reference (and one that exhausts [`SmoothBenchOptions::smooth_budget`] as not
//! solved by the smooth planner). The planner's tables ([`SmoothPlanner::new`]) are built once per map,
//! outside the timing.

use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vpmap_plan::smooth::{
    Pose, SmoothMethod, SmoothOptions, SmoothOutcome, SmoothPlanner, SmoothRules, dubins_distance,
    dubins_shortest, rs_distance, rs_shortest, validate_smooth,
};
use vpmap_plan::{Budget, CellXy, ExactPlanner, Occupancy, OccupancyGrid, PlanError};

use crate::error::{Result, ResultExt as _, bail};
use crate::output::OutputSet;
use crate::progress::Progress;
use crate::stats::quantile_of;

/// The section of a results file (`docs/results.md`) the benchmark publishes into.
pub const SMOOTH_SECTION: &str = "bench-smooth";

/// The section the benchmark with reverse allowed publishes into.
pub const SMOOTH_REVERSE_SECTION: &str = "bench-smooth-reverse";

/// Options of [`run_smooth`].
#[derive(Clone, Debug)]
pub struct SmoothBenchOptions {
    /// Queries per map (each run at every radius of the map; default 6).
    pub queries: usize,
    /// Generated maps of Nav2's benchmark kind (default 2).
    pub nav2_maps: usize,
    /// Their side, cells at 0.05 m (default 2000: 100 m).
    pub nav2_side: usize,
    /// Whether to include the maps vpmap builds from scenes (default `true`).
    pub built: bool,
    /// The Moving AI folder (with `maps/rooms/8room_000.map` and
    /// `maps/cities/Berlin_0_256.map`), if any.
    pub movingai_dir: Option<PathBuf>,
    /// The reference's budget: states expanded and generated and heuristic cells settled
    /// (default 6 million, a few seconds of search).
    pub hybrid_budget: usize,
    /// The smooth planner's budget, counted the same way (default: the planners' default,
    /// [`vpmap_plan::budget::DEFAULT_MAX_EXPANSIONS`]).
    pub smooth_budget: usize,
    /// Seed of the maps and queries.
    pub seed: u64,
    /// Allow both planners to drive in reverse (Reeds-Shepp; cusps); the length ratio's
    /// bound is then the Reeds-Shepp distance instead of the Dubins one (default `false`).
    pub reverse: bool,
    /// The command line, for the report.
    pub command: String,
}

impl Default for SmoothBenchOptions {
    fn default() -> Self {
        Self {
            queries: 6,
            nav2_maps: 2,
            nav2_side: 2000,
            built: true,
            movingai_dir: None,
            hybrid_budget: 6_000_000,
            smooth_budget: vpmap_plan::budget::DEFAULT_MAX_EXPANSIONS,
            seed: 1,
            reverse: false,
            command: String::new(),
        }
    }
}

/// A map of the benchmark.
struct SmoothMap {
    name: String,
    grid: OccupancyGrid,
    /// Radii, cells, with how to print them.
    radii: Vec<(f64, String)>,
    /// Start-goal distance range, cells.
    range: (f64, f64),
}

/// One query.
#[derive(Clone, Copy, Debug)]
struct Query {
    start: CellXy,
    goal: CellXy,
    headings: Option<(f64, f64)>,
}

/// One planner's answer to one query.
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothTrial {
    /// The map.
    pub map: String,
    /// The turning radius as printed (`0.3 m` or `2 cells`).
    pub radius: String,
    /// The turning radius, cells.
    pub radius_cells: f64,
    /// Index of the query on its map.
    pub query: usize,
    /// Whether both headings were given.
    pub headings: bool,
    /// `smooth` or `hybrid-astar` (the reference).
    pub planner: &'static str,
    /// Length, cells (`None`: no path).
    pub length_cells: Option<f64>,
    /// Whether the path passed the validator.
    pub validated: bool,
    /// Length / max(any-angle length, Dubins distance).
    pub ratio: Option<f64>,
    /// Time of the call, ms.
    pub time_ms: f64,
    /// Curvature sign changes.
    pub sign_changes: usize,
    /// The taut path's turns + 1.
    pub turns_plus_one: usize,
    /// Curvature sign changes the poses alone force: those of the shortest obstacle-free
    /// connection between the start and goal poses (Dubins, Reeds-Shepp with reverse) when
    /// both headings are given, else 0.
    pub forced_sign_changes: usize,
    /// Largest curvature, 1/cells.
    pub max_curvature: f64,
    /// Smallest clearance over every point of the curve, cells.
    pub min_clearance_cells: f64,
    /// Cusps.
    pub cusps: usize,
    /// `fillet` or `hybrid-astar`: which method found it.
    pub method: &'static str,
}

/// A map of Nav2's benchmark kind: `side` x `side` cells of 0.05 m, seeded rectangles of 10
/// to 50 cells covering about 10 % of the area.
#[must_use]
pub fn nav2_kind_map(seed: u64, side: usize) -> Option<OccupancyGrid> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut grid = OccupancyGrid::new(side, side, 0.05, [0.0; 2], Occupancy::Free).ok()?;
    let count = ((side * side) as f64 * 0.1 / 900.0) as usize;
    for _ in 0..count {
        let (w, h) = (rng.random_range(10..51), rng.random_range(10..51));
        let (x, y) = (rng.random_range(0..side), rng.random_range(0..side));
        for yy in y..(y + h).min(side) {
            for xx in x..(x + w).min(side) {
                grid.set(xx, yy, Occupancy::Occupied).ok()?;
            }
        }
    }
    Some(grid)
}

fn metric_radii(grid: &OccupancyGrid) -> Vec<(f64, String)> {
    [0.3, 0.5, 1.0]
        .iter()
        .map(|&m| (m / grid.resolution_m(), format!("{m} m")))
        .collect()
}

fn maps(opts: &SmoothBenchOptions) -> Result<Vec<SmoothMap>> {
    let mut out = Vec::new();
    for k in 0..opts.nav2_maps {
        let seed = opts.seed.wrapping_add(k as u64);
        let Some(grid) = nav2_kind_map(seed, opts.nav2_side) else {
            bail!("could not make a {0} x {0} map", opts.nav2_side);
        };
        let side = opts.nav2_side as f64;
        out.push(SmoothMap {
            name: format!("nav2-kind-{}", k + 1),
            radii: metric_radii(&grid),
            grid,
            range: (0.3 * side, 0.6 * side),
        });
    }
    if opts.built {
        for m in crate::bench::maps::built_maps(0, opts.seed)? {
            out.push(SmoothMap {
                name: m.name,
                radii: metric_radii(&m.grid),
                grid: m.grid,
                range: (20.0, 150.0),
            });
        }
    }
    if let Some(dir) = &opts.movingai_dir {
        for (name, file, radii) in [
            ("8room_000", "rooms/8room_000.map", [1.0, 2.0]),
            ("Berlin_0_256", "cities/Berlin_0_256.map", [2.0, 5.0]),
        ] {
            let path = dir.join("maps").join(file);
            let grid = vpmap_plan::read_movingai_map(&path)
                .with_context(|| format!("reading {}", path.display()))?;
            out.push(SmoothMap {
                name: name.to_owned(),
                grid,
                radii: radii.iter().map(|&r| (r, format!("{r} cells"))).collect(),
                range: (10.0, 80.0),
            });
        }
    }
    Ok(out)
}

fn queries(map: &SmoothMap, seed: u64, n: usize) -> Result<Vec<Query>> {
    let grid = &map.grid;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut exact = ExactPlanner::new(grid, false);
    let mut out = Vec::new();
    for _ in 0..100_000 {
        if out.len() >= n {
            break;
        }
        let mut cell = || {
            CellXy::new(
                rng.random_range(0..grid.width()),
                rng.random_range(0..grid.height()),
            )
        };
        let (s, g) = (cell(), cell());
        if !grid.is_free(s.x, s.y) || !grid.is_free(g.x, g.y) {
            continue;
        }
        let d = (s.x as f64 - g.x as f64).hypot(s.y as f64 - g.y as f64);
        if d < map.range.0 || d > map.range.1 {
            continue;
        }
        if exact.plan(s, g, &Budget::default())?.is_none() {
            continue;
        }
        let headings =
            (out.len() % 2 == 0).then(|| (rng.random_range(-PI..PI), rng.random_range(-PI..PI)));
        out.push(Query {
            start: s,
            goal: g,
            headings,
        });
    }
    Ok(out)
}

/// One planner on one query.
#[allow(clippy::too_many_arguments)]
fn trial(
    map: &SmoothMap,
    planner: &mut SmoothPlanner,
    exact: &mut ExactPlanner,
    (r, label): &(f64, String),
    (index, q): (usize, &Query),
    method: SmoothMethod,
    opts: &SmoothBenchOptions,
) -> Result<SmoothTrial> {
    let budget = Budget {
        max_expansions: match method {
            SmoothMethod::HybridAstar => opts.hybrid_budget,
            SmoothMethod::Auto => opts.smooth_budget,
        },
        ..Budget::default()
    };
    let opts = SmoothOptions {
        turning_radius_cells: *r,
        start_heading_rad: q.headings.map(|h| h.0),
        goal_heading_rad: q.headings.map(|h| h.1),
        method,
        budget,
        reverse: opts.reverse,
        ..SmoothOptions::default()
    };
    let began = Instant::now();
    let out = planner.plan(q.start, q.goal, &opts);
    let time_ms = began.elapsed().as_secs_f64() * 1e3;
    let planner_name = match method {
        SmoothMethod::Auto => "smooth",
        SmoothMethod::HybridAstar => "hybrid-astar",
    };
    let mut t = SmoothTrial {
        map: map.name.clone(),
        radius: label.clone(),
        radius_cells: *r,
        query: index,
        headings: q.headings.is_some(),
        planner: planner_name,
        length_cells: None,
        validated: false,
        ratio: None,
        time_ms,
        sign_changes: 0,
        turns_plus_one: 0,
        forced_sign_changes: 0,
        max_curvature: 0.0,
        min_clearance_cells: f64::INFINITY,
        cusps: 0,
        method: "",
    };
    let p = match out {
        Ok(SmoothOutcome::Path(p)) => p,
        Ok(SmoothOutcome::NoPath(_)) | Err(PlanError::BudgetExhausted { .. }) => return Ok(t),
        Err(e) => {
            return Err(e).with_context(|| format!("{} query {index} R {label}", map.name));
        }
    };
    let pose = |c: CellXy, h: Option<f64>| Pose::new(c.x as f64, c.y as f64, h.unwrap_or(0.0));
    let (start, goal) = (
        pose(q.start, q.headings.map(|h| h.0)),
        pose(q.goal, q.headings.map(|h| h.1)),
    );
    let rules = SmoothRules {
        radius_cells: *r,
        start,
        start_heading: q.headings.is_some(),
        goal,
        goal_heading: q.headings.is_some(),
        reverse: opts.reverse,
        unknown_passable: false,
    };
    let taut = exact.plan(q.start, q.goal, &Budget::default())?;
    let (taut_length, turns) = taut.map_or((0.0, 0), |t| {
        (t.length_cells, t.waypoints.len().saturating_sub(2))
    });
    t.forced_sign_changes = match (q.headings.is_some(), opts.reverse) {
        (false, _) => 0,
        (true, true) => {
            rs_shortest(start, goal, *r).map_or(0, |p| p.curve.curvature_sign_changes())
        }
        (true, false) => {
            dubins_shortest(start, goal, *r).map_or(0, |p| p.curve.curvature_sign_changes())
        }
    };
    let dubins = if q.headings.is_some() && opts.reverse {
        rs_distance(start, goal, *r)
    } else if q.headings.is_some() {
        dubins_distance(start, goal, *r)
    } else {
        0.0
    };
    t.validated = validate_smooth(&map.grid, &p.curve, &rules).is_ok();
    t.length_cells = Some(p.length_cells);
    t.ratio = Some(p.length_cells / taut_length.max(dubins).max(1e-12));
    t.sign_changes = p.curvature_sign_changes;
    t.turns_plus_one = turns + 1;
    t.max_curvature = p.max_curvature;
    t.min_clearance_cells = p.min_clearance_cells;
    t.cusps = p.cusps;
    t.method = p.method;
    Ok(t)
}

/// Run the benchmark (see the [module docs](self)): every query of every map at every
/// radius with the smooth planner and its reference, in that order.
///
/// # Errors
/// When a map cannot be made, built or read, or a planner fails otherwise than by running out
/// of its budget.
pub fn run_smooth(opts: &SmoothBenchOptions, progress: &dyn Progress) -> Result<Vec<SmoothTrial>> {
    if opts.queries == 0 {
        bail!("--queries must be at least 1");
    }
    let maps = maps(opts)?;
    let total: usize = maps.iter().map(|m| m.radii.len() * opts.queries * 2).sum();
    progress.start(total as u64);
    let began = Instant::now();
    let mut trials = Vec::new();
    for (mi, map) in maps.iter().enumerate() {
        progress.milestone(&format!(
            "map {}/{}: {} ({} x {} cells), {} queries x {} radii x 2 planners; {}/{total} planner runs done, {:.1} s",
            mi + 1,
            maps.len(),
            map.name,
            map.grid.width(),
            map.grid.height(),
            opts.queries,
            map.radii.len(),
            trials.len(),
            began.elapsed().as_secs_f64()
        ));
        let qs = queries(map, opts.seed.wrapping_mul(1000) + mi as u64, opts.queries)?;
        let mut planner = SmoothPlanner::new(&map.grid, false);
        let mut exact = ExactPlanner::new(&map.grid, false);
        for radius in &map.radii {
            for (i, q) in qs.iter().enumerate() {
                for method in [SmoothMethod::Auto, SmoothMethod::HybridAstar] {
                    progress.message(&format!("{} R {} query {i}", map.name, radius.1));
                    trials.push(trial(
                        map,
                        &mut planner,
                        &mut exact,
                        radius,
                        (i, q),
                        method,
                        opts,
                    )?);
                    progress.step();
                }
            }
            // Queries that found fewer than asked are counted in the table.
        }
        progress.note(&format!("{}: {} queries", map.name, qs.len()));
    }
    Ok(trials)
}

/// The per-query CSV.
#[must_use]
pub fn smooth_csv(trials: &[SmoothTrial]) -> String {
    let mut s = String::from(
        "map,radius,radius_cells,query,headings,planner,found,validated,length_cells,ratio,time_ms,curvature_sign_changes,taut_turns_plus_one,max_curvature,min_clearance_cells,cusps,method,forced_sign_changes\n",
    );
    for t in trials {
        let opt = |v: Option<f64>| v.map_or_else(String::new, |v| format!("{v:.6}"));
        let _ = writeln!(
            s,
            "{},{},{:.6},{},{},{},{},{},{},{},{:.3},{},{},{:.6},{:.6},{},{},{}",
            t.map,
            t.radius,
            t.radius_cells,
            t.query,
            t.headings,
            t.planner,
            t.length_cells.is_some(),
            t.validated,
            opt(t.length_cells),
            opt(t.ratio),
            t.time_ms,
            t.sign_changes,
            t.turns_plus_one,
            t.max_curvature,
            t.min_clearance_cells,
            t.cusps,
            t.method,
            t.forced_sign_changes
        );
    }
    s
}

fn fmt2(a: Option<f64>, b: Option<f64>, digits: usize) -> String {
    let f = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.digits$}"));
    format!("{} / {}", f(a), f(b))
}

/// The summary table (Markdown): per map, radius and planner, then the totals.
#[must_use]
pub fn smooth_table(trials: &[SmoothTrial]) -> String {
    let mut s = String::from(
        "| map | R | planner | found | validated | length ratio median / p95 | vs reference median / p95 | no longer than ref. | missed | ms median / p95 | wobbly | wobbly beyond headings | max curvature × R | min clearance (cells) | cusps | by fillet |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut groups: Vec<(String, String)> = Vec::new();
    for t in trials {
        let key = (t.map.clone(), t.radius.clone());
        if !groups.contains(&key) {
            groups.push(key);
        }
    }
    let pairs = |map: Option<&(String, String)>| -> Vec<(&SmoothTrial, &SmoothTrial)> {
        let of = |p: &str| -> Vec<&SmoothTrial> {
            trials
                .iter()
                .filter(|t| {
                    t.planner == p && map.is_none_or(|(m, r)| &t.map == m && &t.radius == r)
                })
                .collect()
        };
        of("smooth").into_iter().zip(of("hybrid-astar")).collect()
    };
    let rows: Vec<Option<&(String, String)>> = groups
        .iter()
        .map(Some)
        .chain(std::iter::once(None))
        .collect();
    for key in rows {
        let ps = pairs(key);
        let n = ps.len();
        let vs_ref: Vec<f64> = ps
            .iter()
            .filter_map(|(s, h)| Some(s.length_cells? / h.length_cells?))
            .collect();
        let both = vs_ref.len();
        let no_longer = vs_ref.iter().filter(|&&v| v <= 1.0 + 1e-9).count();
        let missed = ps
            .iter()
            .filter(|(s, h)| s.length_cells.is_none() && h.length_cells.is_some())
            .count();
        for (k, label) in [(0, "smooth"), (1, "hybrid-A*")] {
            let ts: Vec<&SmoothTrial> = ps.iter().map(|p| if k == 0 { p.0 } else { p.1 }).collect();
            let found: Vec<&&SmoothTrial> =
                ts.iter().filter(|t| t.length_cells.is_some()).collect();
            let ratios: Vec<f64> = found.iter().filter_map(|t| t.ratio).collect();
            let times: Vec<f64> = ts.iter().map(|t| t.time_ms).collect();
            let wobbly = found
                .iter()
                .filter(|t| t.sign_changes > t.turns_plus_one)
                .count();
            let wobbly_beyond = found
                .iter()
                .filter(|t| t.sign_changes > t.turns_plus_one + t.forced_sign_changes)
                .count();
            let kr = found
                .iter()
                .map(|t| t.max_curvature * t.radius_cells)
                .fold(0.0, f64::max);
            let clearance = found
                .iter()
                .map(|t| t.min_clearance_cells)
                .fold(f64::INFINITY, f64::min);
            let cusps: usize = found.iter().map(|t| t.cusps).sum();
            let fillet = found.iter().filter(|t| t.method == "fillet").count();
            let (map, r) = key.map_or(("all", "all"), |(m, r)| (m.as_str(), r.as_str()));
            let _ = writeln!(
                s,
                "| {map} | {r} | {label} | {}/{n} | {}/{} | {} | {} | {} | {} | {} | {wobbly} | {wobbly_beyond} | {kr:.4} | {} | {cusps} | {} |",
                found.len(),
                found.iter().filter(|t| t.validated).count(),
                found.len(),
                fmt2(quantile_of(&ratios, 0.5), quantile_of(&ratios, 0.95), 4),
                if k == 0 {
                    fmt2(quantile_of(&vs_ref, 0.5), quantile_of(&vs_ref, 0.95), 4)
                } else {
                    String::new()
                },
                if k == 0 {
                    format!("{no_longer}/{both}")
                } else {
                    String::new()
                },
                if k == 0 {
                    missed.to_string()
                } else {
                    String::new()
                },
                fmt2(quantile_of(&times, 0.5), quantile_of(&times, 0.95), 1),
                if clearance.is_finite() {
                    format!("{clearance:.3}")
                } else {
                    "-".to_owned()
                },
                if k == 0 {
                    fillet.to_string()
                } else {
                    String::new()
                },
            );
        }
    }
    s
}

/// The load average of the last minute (`/proc/loadavg`), if readable.
#[must_use]
pub fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// The report's files: `smooth.csv` (per query and planner) and `smooth.md` (the table).
#[must_use]
pub fn smooth_report(trials: &[SmoothTrial]) -> OutputSet {
    let mut files = OutputSet::default();
    files.add("smooth.csv", smooth_csv(trials));
    files.add("smooth.md", smooth_table(trials));
    files
}

/// The published section: where, when, how (`elapsed`, `command`) and at what load (`loads`:
/// the load average before and after the run), then the table.
#[must_use]
pub fn smooth_published_section(
    table: &str,
    elapsed: std::time::Duration,
    command: &str,
    loads: [Option<f64>; 2],
    reverse: bool,
) -> String {
    let load = |v: Option<f64>| v.map_or_else(|| "unknown".to_owned(), |v| format!("{v:.2}"));
    let (title, bound) = if reverse {
        (
            "Smooth paths with reverse (Reeds-Shepp) against Hybrid-A* with reverse (`vpmap bench --smooth --reverse`)",
            "Reeds-Shepp",
        )
    } else {
        (
            "Smooth paths against Hybrid-A* (`vpmap bench --smooth`)",
            "Dubins",
        )
    };
    crate::publish::published(
        title,
        &format!(
            "Method: [planning.md](planning.md#smooth-paths-a-robot-can-drive---planner-smooth); \
             maps, queries and columns: `vpmap_eval::smooth`. Load average (1 min) {} before the \
             run and {} after it: the machine is shared, the times are one thread's wall times and \
             the ratios are what compares. **length ratio** = length / max(exact any-angle \
             length, {bound} distance between the poses); **vs reference** = length / the \
             Hybrid-A*'s on the queries both solved; **missed** = solved by the reference, not by \
             the smooth planner; **wobbly** = more curvature sign changes than the taut path's \
             turns + 1; **wobbly beyond headings** = more than that plus the sign changes the \
             poses alone force when both headings are given (those of the shortest {bound} \
             path between them: 2 for a CCC word, at most 1 for a CSC word; 0 for free \
             headings); **max curvature × R** at most 1.\n\n{table}",
            load(loads[0]),
            load(loads[1])
        ),
        elapsed,
        command,
    )
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    /// The milestones and the number of steps a run reports.
    #[derive(Default)]
    struct Recorder {
        milestones: std::sync::Mutex<Vec<String>>,
        steps: std::sync::Mutex<usize>,
    }

    impl Progress for Recorder {
        fn milestone(&self, line: &str) {
            self.milestones.lock().unwrap().push(line.to_owned());
        }
        fn step(&self) {
            *self.steps.lock().unwrap() += 1;
        }
    }

    #[test]
    fn a_small_run_pairs_every_query_and_validates_every_path() {
        let opts = SmoothBenchOptions {
            queries: 3,
            nav2_maps: 1,
            nav2_side: 160,
            built: false,
            hybrid_budget: 300_000,
            smooth_budget: 300_000,
            ..SmoothBenchOptions::default()
        };
        let log = Recorder::default();
        let trials = run_smooth(&opts, &log).unwrap();
        // 1 map x 3 radii x 3 queries x 2 planners.
        assert_eq!(trials.len(), 18);
        // One milestone a map (a log without a bar sees where the run is), not one a query.
        let milestones = log.milestones.lock().unwrap().clone();
        assert_eq!(milestones.len(), 1, "{milestones:?}");
        assert!(
            milestones[0].starts_with(
                "map 1/1: nav2-kind-1 (160 x 160 cells), 3 queries x 3 radii x 2 planners; 0/18 planner runs done, "
            ),
            "{milestones:?}"
        );
        assert_eq!(*log.steps.lock().unwrap(), 18);
        for pair in trials.chunks(2) {
            assert_eq!(pair[0].planner, "smooth");
            assert_eq!(pair[1].planner, "hybrid-astar");
            assert_eq!(pair[0].query, pair[1].query);
        }
        for t in &trials {
            if let Some(l) = t.length_cells {
                assert!(t.validated, "{t:?}");
                assert!(t.ratio.unwrap() >= 1.0 - 1e-9, "{t:?}");
                assert!(t.max_curvature * t.radius_cells <= 1.0 + 1e-9);
                assert!(l > 0.0);
            }
        }
        let smooth_found = trials
            .iter()
            .filter(|t| t.planner == "smooth" && t.length_cells.is_some())
            .count();
        assert!(smooth_found >= 6, "{smooth_found} of 9");
        let table = smooth_table(&trials);
        assert!(
            table.contains("| nav2-kind-1 | 0.3 m | smooth |"),
            "{table}"
        );
        assert!(table.contains("| all | all | hybrid-A* |"), "{table}");
        let csv = smooth_csv(&trials);
        assert_eq!(csv.lines().count(), 19);
        // A 0.3 m radius on a 0.05 m grid is 6 cells, printed as such (not 5.999999999999999).
        let cells: Vec<&str> = csv
            .lines()
            .filter(|l| l.split(',').nth(1) == Some("0.3 m"))
            .filter_map(|l| l.split(',').nth(2))
            .collect();
        assert!(!cells.is_empty(), "{csv}");
        assert!(cells.iter().all(|c| *c == "6.000000"), "{csv}");
        assert!(run_smooth(&SmoothBenchOptions { queries: 0, ..opts }, &crate::Silent).is_err());
    }

    #[test]
    fn with_reverse_every_path_is_validated_with_reverse_and_no_shorter_than_the_bound() {
        let opts = SmoothBenchOptions {
            queries: 2,
            nav2_maps: 1,
            nav2_side: 120,
            built: false,
            hybrid_budget: 200_000,
            smooth_budget: 200_000,
            reverse: true,
            ..SmoothBenchOptions::default()
        };
        let trials = run_smooth(&opts, &crate::Silent).unwrap();
        assert_eq!(trials.len(), 12);
        let mut found = 0;
        for t in &trials {
            if t.length_cells.is_some() {
                found += 1;
                // Validated with reverse allowed; the ratio's bound is the Reeds-Shepp one.
                assert!(t.validated, "{t:?}");
                assert!(t.ratio.unwrap() >= 1.0 - 1e-9, "{t:?}");
            }
        }
        assert!(found >= 6, "{found} of 12");
        let section = smooth_published_section(
            &smooth_table(&trials),
            std::time::Duration::from_secs(1),
            "vpmap bench --smooth --reverse",
            [None, None],
            true,
        );
        assert!(section.contains("Reeds-Shepp distance"), "{section}");
    }

    /// Issue 41's wobbly paths of the 2026-11-29 bench run (`/tmp/bench41f`), free headings:
    /// built-office-3 query 5 at 0.5 and 1 m (corner fillets: 4 sign changes against 3) and
    /// built-office-1 query 5 at 1 m (the Hybrid-A* fallback: 23 against 17). Polished, they
    /// pass the validator (run again in `trial`), change sign no more than the taut path's
    /// turns + 1, and are no longer than the unpolished lengths of that run.
    #[test]
    fn regression_free_heading_wobble_of_the_built_maps_is_polished_away() {
        let opts = SmoothBenchOptions {
            nav2_maps: 0,
            ..SmoothBenchOptions::default()
        };
        let maps = maps(&opts).unwrap();
        for (name, label, before_cells, method) in [
            ("built-office-3", "0.5 m", 70.068_376, "fillet"),
            ("built-office-3", "1 m", 70.114_005, "fillet"),
            ("built-office-1", "1 m", 248.390_726, "hybrid-astar"),
        ] {
            let (mi, map) = maps
                .iter()
                .enumerate()
                .find(|(_, m)| m.name == name)
                .unwrap();
            // `run_smooth` numbers the maps with the Nav2-kind ones first.
            let seed = opts.seed.wrapping_mul(1000) + (mi + 2) as u64;
            let qs = queries(map, seed, opts.queries).unwrap();
            let radius = map.radii.iter().find(|r| r.1 == label).unwrap();
            let mut planner = SmoothPlanner::new(&map.grid, false);
            let mut exact = ExactPlanner::new(&map.grid, false);
            let t = trial(
                map,
                &mut planner,
                &mut exact,
                radius,
                (5, &qs[5]),
                SmoothMethod::Auto,
                &opts,
            )
            .unwrap();
            assert!(!t.headings, "{t:?}");
            assert_eq!(t.method, method, "{t:?}");
            assert!(t.validated, "{t:?}");
            assert!(t.sign_changes <= t.turns_plus_one, "{t:?}");
            assert!(t.length_cells.unwrap() <= before_cells + 1e-6, "{t:?}");
        }
    }

    /// Issue 41's wobbly paths with both headings given, of the 2026-11-29 bench run
    /// (`/tmp/bench41g`): nav2-kind-1 query 2 at 0.3 and 0.5 m, 5 curvature sign changes
    /// against the taut path's turns + 1 = 4. The shortcut of the polish had dropped the pose
    /// at the taut path's second corner for one just past it, where no heading was clear, and
    /// the out-word kept a sliver turning the other way. Now the path changes sign no more than
    /// turns + 1, passes the validator and is no longer than that run's.
    #[test]
    fn regression_nav2_kind_query_2_wobble_is_polished_away() {
        let opts = SmoothBenchOptions {
            nav2_maps: 1,
            built: false,
            ..SmoothBenchOptions::default()
        };
        let maps = maps(&opts).unwrap();
        let map = &maps[0];
        assert_eq!(map.name, "nav2-kind-1");
        let qs = queries(map, opts.seed.wrapping_mul(1000), 3).unwrap();
        let mut planner = SmoothPlanner::new(&map.grid, false);
        let mut exact = ExactPlanner::new(&map.grid, false);
        for (label, before_cells) in [("0.3 m", 1_131.795_777_85), ("0.5 m", 1_132.211_045_48)] {
            let radius = map.radii.iter().find(|r| r.1 == label).unwrap();
            let t = trial(
                map,
                &mut planner,
                &mut exact,
                radius,
                (2, &qs[2]),
                SmoothMethod::Auto,
                &opts,
            )
            .unwrap();
            assert!(t.headings, "{t:?}");
            assert_eq!(t.method, "fillet", "{t:?}");
            assert!(t.validated, "{t:?}");
            assert_eq!(t.turns_plus_one, 4, "{t:?}");
            assert!(t.sign_changes <= t.turns_plus_one, "{t:?}");
            assert!(t.length_cells.unwrap() <= before_cells + 1e-6, "{t:?}");
        }
    }
}
