//! The smooth planner against its Hybrid-A* reference, side by side on the same queries.
//!
//! Maps: Nav2-benchmark-like grids of 2000 x 2000 cells (100 m x 100 m at 0.05 m) with
//! seeded random rectangular obstacles, and, when `shared/data/movingai` is present, the
//! Moving AI maps `8room_000` (rooms) and `Berlin_0_256` (cities). Queries: seeded free
//! start and goal cells (on the Nav2-like maps 30-60 m apart, on Moving AI maps 10-80 cells), half with both headings
//! given, half with both free; turning radius 0.3, 0.5 and 1 m (6, 10, 20 cells) on the
//! Nav2-like maps, 1 and 2 cells on `8room_000` (rooms of 7 x 7 cells, doors one cell wide), 2 and
//! 5 cells on `Berlin_0_256`.
//!
//! Before timing, the bench prints per map and radius, for both planners: the share of
//! queries with a path, the share validated by the independent validator, the length ratio
//! `length / max(exact any-angle length, Dubins distance)` (median, p95), the share of
//! queries where the smooth planner is no longer than the reference (+1e-9), the time per
//! query (median, p95, one thread, `Instant` around each call), curvature sign changes
//! against the taut path's corners + 1, max curvature, min clearance and cusps; then
//! criterion times the smooth planner over all the queries of a map and radius
//! (`smooth/<map>/R<R>`, one iteration = every query). The reference runs once a query
//! with a budget of [`HYBRID_BUDGET`] (its expanded and generated states and heuristic
//! cells); a query it exhausts counts as not solved by it.
//!
//! The planner's tables ([`SmoothPlanner`]) are built once per map, outside the timing (the
//! build time is printed). `SMOOTH_BENCH_QUERIES` sets the queries per map and radius
//! (default 12), `SMOOTH_BENCH_MAP` keeps the maps whose name contains it,
//! `SMOOTH_BENCH_VERBOSE` prints every query.
#![allow(missing_docs)]
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::f64::consts::PI;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vpmap_plan::smooth::{
    Pose, SmoothMethod, SmoothOptions, SmoothOutcome, SmoothPlanner, SmoothRules, dubins_distance,
    validate_smooth,
};
use vpmap_plan::{Budget, CellXy, ExactPlanner, Occupancy, OccupancyGrid, read_movingai_map};

/// A Nav2-benchmark-like map: `side` x `side` cells, seeded rectangles of 0.5 to 2.5 m
/// (10 to 50 cells) covering about `density` of the area.
fn nav2_like(seed: u64, side: usize, density: f64) -> OccupancyGrid {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut grid = OccupancyGrid::new(side, side, 0.05, [0.0; 2], Occupancy::Free).unwrap();
    let mean_area = 30.0 * 30.0;
    let count = ((side * side) as f64 * density / mean_area) as usize;
    for _ in 0..count {
        let (w, h) = (rng.random_range(10..51), rng.random_range(10..51));
        let (x, y) = (rng.random_range(0..side), rng.random_range(0..side));
        for yy in y..(y + h).min(side) {
            for xx in x..(x + w).min(side) {
                grid.set(xx, yy, Occupancy::Occupied).unwrap();
            }
        }
    }
    grid
}

/// A map's name, grid, turning radii (cells) and start-goal distance range (cells).
type BenchMap = (String, OccupancyGrid, Vec<f64>, (f64, f64));

#[derive(Clone, Copy, Debug)]
struct Query {
    start: CellXy,
    goal: CellXy,
    headings: Option<(f64, f64)>,
}

fn queries(grid: &OccupancyGrid, seed: u64, n: usize, min_max: (f64, f64)) -> Vec<Query> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut exact = ExactPlanner::new(grid, false);
    let mut out = Vec::new();
    let mut tries = 0;
    while out.len() < n && tries < 100_000 {
        tries += 1;
        let s = CellXy::new(
            rng.random_range(0..grid.width()),
            rng.random_range(0..grid.height()),
        );
        let g = CellXy::new(
            rng.random_range(0..grid.width()),
            rng.random_range(0..grid.height()),
        );
        if !grid.is_free(s.x, s.y) || !grid.is_free(g.x, g.y) {
            continue;
        }
        let d = (s.x as f64 - g.x as f64).hypot(s.y as f64 - g.y as f64);
        if d < min_max.0 || d > min_max.1 {
            continue;
        }
        if exact.plan(s, g, &Budget::default()).unwrap().is_none() {
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
    out
}

/// The reference's budget: states expanded + generated + heuristic cells settled (a few
/// seconds of search); a query it exhausts counts as not solved by the reference.
const HYBRID_BUDGET: usize = 6_000_000;

fn options(r: f64, q: &Query, method: SmoothMethod) -> SmoothOptions {
    let mut budget = Budget::default();
    if method == SmoothMethod::HybridAstar {
        budget.max_expansions = HYBRID_BUDGET;
    }
    SmoothOptions {
        turning_radius_cells: r,
        start_heading_rad: q.headings.map(|h| h.0),
        goal_heading_rad: q.headings.map(|h| h.1),
        method,
        budget,
        ..SmoothOptions::default()
    }
}

#[derive(Default)]
struct Run {
    found: usize,
    valid: usize,
    ratios: Vec<f64>,
    lengths: Vec<Option<f64>>,
    times_ms: Vec<f64>,
    wobbly: usize,
    max_curvature: f64,
    min_clearance: f64,
    cusps: usize,
    fillet: usize,
}

fn quantile(v: &[f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let pos = q * (s.len() - 1) as f64;
    let (lo, hi) = (pos.floor() as usize, pos.ceil() as usize);
    s[lo] + (s[hi] - s[lo]) * (pos - lo as f64)
}

fn measure(
    grid: &OccupancyGrid,
    planner: &mut SmoothPlanner,
    qs: &[Query],
    r: f64,
    method: SmoothMethod,
) -> Run {
    let mut run = Run {
        min_clearance: f64::INFINITY,
        ..Run::default()
    };
    let mut exact = ExactPlanner::new(grid, false);
    for q in qs {
        let opts = options(r, q, method);
        let began = Instant::now();
        let out = planner.plan(q.start, q.goal, &opts);
        run.times_ms.push(began.elapsed().as_secs_f64() * 1e3);
        let Ok(SmoothOutcome::Path(p)) = out else {
            run.lengths.push(None);
            continue;
        };
        run.found += 1;
        let start = Pose::new(
            q.start.x as f64,
            q.start.y as f64,
            q.headings.map_or(0.0, |h| h.0),
        );
        let goal = Pose::new(
            q.goal.x as f64,
            q.goal.y as f64,
            q.headings.map_or(0.0, |h| h.1),
        );
        let rules = SmoothRules {
            radius_cells: r,
            start,
            start_heading: q.headings.is_some(),
            goal,
            goal_heading: q.headings.is_some(),
            reverse: false,
            unknown_passable: false,
        };
        if validate_smooth(grid, &p.curve, &rules).is_ok() {
            run.valid += 1;
        }
        let taut = exact
            .plan(q.start, q.goal, &Budget::default())
            .unwrap()
            .unwrap();
        let dubins = if q.headings.is_some() {
            dubins_distance(start, goal, r)
        } else {
            0.0
        };
        run.ratios
            .push(p.length_cells / taut.length_cells.max(dubins));
        run.lengths.push(Some(p.length_cells));
        let turns = taut.waypoints.len().saturating_sub(2);
        if p.curvature_sign_changes > turns + 1 {
            run.wobbly += 1;
        }
        run.max_curvature = run.max_curvature.max(p.max_curvature);
        run.min_clearance = run.min_clearance.min(p.min_clearance_cells);
        run.cusps += p.cusps;
        run.fillet += usize::from(p.method == "fillet");
        if std::env::var_os("SMOOTH_BENCH_VERBOSE").is_some() {
            println!(
                "  {:?} -> {:?} headings {:?}: {} {:.1} ms, ratio {:.4}, fillet rounds {} words {}, hybrid expanded {}",
                q.start,
                q.goal,
                q.headings,
                p.method,
                run.times_ms.last().unwrap(),
                run.ratios.last().unwrap(),
                p.stats.fillet.rounds,
                p.stats.fillet.words_tested,
                p.stats.hybrid.expanded
            );
        }
    }
    run
}

fn report(name: &str, r: f64, n: usize, smooth: &Run, hybrid: &Run) {
    let no_longer = smooth
        .lengths
        .iter()
        .zip(&hybrid.lengths)
        .filter(|(s, h)| matches!((s, h), (Some(s), Some(h)) if *s <= h + 1e-9))
        .count();
    let both = hybrid.lengths.iter().filter(|h| h.is_some()).count();
    let missed = smooth
        .lengths
        .iter()
        .zip(&hybrid.lengths)
        .filter(|(s, h)| s.is_none() && h.is_some())
        .count();
    for (label, run) in [("smooth", smooth), ("hybrid-A*", hybrid)] {
        println!(
            "{name} R={r} cells {label:>9}: found {}/{n} valid {}/{} | ratio median {:.4} p95 {:.4} | ms median {:.1} p95 {:.1} | wobbly {} | max kappa {:.4} (1/R {:.4}) | min clearance {:.3} | cusps {} | by fillet {}",
            run.found,
            run.valid,
            run.found,
            quantile(&run.ratios, 0.5),
            quantile(&run.ratios, 0.95),
            quantile(&run.times_ms, 0.5),
            quantile(&run.times_ms, 0.95),
            run.wobbly,
            run.max_curvature,
            1.0 / r,
            run.min_clearance,
            run.cusps,
            run.fillet,
        );
    }
    println!(
        "{name} R={r} cells: smooth no longer than hybrid-A* on {no_longer}/{both} queries the reference solved; reference found and smooth missed: {missed}"
    );
}

fn bench_smooth(c: &mut Criterion) {
    let n: usize = std::env::var("SMOOTH_BENCH_QUERIES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(12);
    let mut maps: Vec<BenchMap> = Vec::new();
    for seed in 1..=2u64 {
        maps.push((
            format!("nav2like-{seed}"),
            nav2_like(seed, 2000, 0.1),
            vec![6.0, 10.0, 20.0],
            (600.0, 1200.0),
        ));
    }
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/movingai/maps");
    for (name, file, radii) in [
        ("8room_000", "rooms/8room_000.map", [1.0, 2.0]),
        ("Berlin_0_256", "cities/Berlin_0_256.map", [2.0, 5.0]),
    ] {
        if let Ok(grid) = read_movingai_map(dir.join(file)) {
            maps.push((name.to_owned(), grid, radii.to_vec(), (10.0, 80.0)));
        }
    }
    let mut group = c.benchmark_group("smooth");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(5));
    for (mi, (name, grid, radii, range)) in maps.iter().enumerate() {
        if std::env::var("SMOOTH_BENCH_MAP").is_ok_and(|m| !name.contains(&m)) {
            continue;
        }
        let qs = queries(grid, 100 + mi as u64, n, *range);
        let began = Instant::now();
        let mut planner = SmoothPlanner::new(grid, false);
        println!(
            "{name}: planner tables built in {:.1} ms (once per map)",
            began.elapsed().as_secs_f64() * 1e3
        );
        for &r in radii {
            let smooth = measure(grid, &mut planner, &qs, r, SmoothMethod::Auto);
            let hybrid = measure(grid, &mut planner, &qs, r, SmoothMethod::HybridAstar);
            report(name, r, qs.len(), &smooth, &hybrid);
            // Criterion times the smooth planner over all the queries; the reference's
            // seconds a query are only timed above (one run each).
            group.bench_function(format!("{name}/R{r}"), |b| {
                b.iter(|| {
                    for q in &qs {
                        black_box(
                            planner
                                .plan(q.start, q.goal, &options(r, q, SmoothMethod::Auto))
                                .ok(),
                        );
                    }
                });
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench_smooth);
criterion_main!(benches);
