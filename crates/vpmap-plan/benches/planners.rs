//! Planner benchmarks on Moving AI maps.
//!
//! - `astar_vs_pathfinding/<map>`: our reusable [`AstarSearch`] against
//!   `pathfinding::directed::astar::astar` with the same 8-connected, no-corner-cutting
//!   successors, octile costs (integers, straight 10000, diagonal 14142) and octile
//!   heuristic; each iteration runs all the map's sampled queries.
//! - `planners/<map>`: A*, A* PS, MBPP (the thesis's m-line leave rule and the
//!   closer-than-hit rule), Theta* and the exact any-angle planner over the same queries.
//! - `exact_vs_astar/<map>`: the exact any-angle planner ([`ExactPlanner`], its free space
//!   built once per map outside the timing) against our A* ([`AstarSearch`], reused) on the
//!   same queries, and `exact_build`, the one-off build alone, on one map of each Moving AI
//!   category (dao, da2, bg512, cities, mazes, random, rooms, sc1). Before timing it checks
//!   that the exact lengths equal the visibility graph's (to 1e-9) where that is fast.
//! - `line_of_sight/<map>`: the shared line-of-sight core ([`PassableGrid`], built once per
//!   map outside the timing, and built inside it) against the reference walk
//!   ([`visit_swept_cells`](vpmap_plan::los::visit_swept_cells) through [`Traversable`]) on
//!   the same segments: from each A* path's start to every fourth of its cells, clear or not.
//!
//!   The core is also timed with its box index ([`PassableGrid::index_boxes`], built
//!   outside the timing; MBPP builds it), after checking it gives the same answers.
//!
//! - `astar_per_expansion/<map>`: the cost of one A* node expansion, on the maps where the
//!   Python wheel's bench finds A* slowest against scikit-image and `pathfinding`
//!   (`maze512-32-0`, `random512-20-0`, a seeded 512 x 512 grid 20 % blocked) with far-apart
//!   queries: our reused [`AstarSearch`], the free [`astar`] (on the thread's reused arrays,
//!   as `vpmap.plan` runs it), a new [`AstarSearch`] per query (its arrays allocated and
//!   zeroed per call) and `pathfinding`'s A*, throughput counted in our A*'s expansions
//!   (criterion's `elem/s`; its inverse is the time per expansion).
//!
//! Maps come from `shared/data/movingai` next to the workspace; without it, a seeded
//! 128 x 128 random-obstacle grid with seeded queries is used instead.
#![allow(missing_docs)]
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, Throughput, criterion_group, criterion_main};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vpmap_plan::{
    AstarOptions, AstarPsOptions, AstarSearch, Budget, CellXy, ExactPlanner, Occupancy,
    OccupancyGrid, OptimalAnyAngleOptions, PassableGrid, ThetaStarOptions, Traversable, astar,
    astar_ps, line_of_sight,
    mbpp::{LeaveRule, MbppOptions, mbpp},
    optimal_any_angle, path_length, read_movingai_map, read_scen, theta_star,
};

/// Problems sampled per map.
const QUERIES_PER_MAP: usize = 20;
/// `(group name, map file, scenario file)` under the Moving AI folder.
///
/// Four of the maps of `vpmap bench`'s default benchmark (`DEFAULT_MAPS` in
/// `crates/vpmap-eval/src/bench/maps.rs`), kept as a table of their own on purpose: this is a
/// criterion micro-benchmark (our code against a reference side by side, a few minutes under
/// `cargo bench`), while that table is the full measurement by the thesis's categories behind
/// the published results. Sharing it would make this crate's benches depend on `vpmap-eval`,
/// which depends on this crate and on the rendering and vision stack; a map added there for
/// the results need not be timed here. Keep the names in step when a map is renamed.
const MAPS: [(&str, &str, &str); 4] = [
    (
        "room-64-64-8",
        "maps/mapf/room-64-64-8.map",
        "scen/mapf/room-64-64-8-random-1.scen",
    ),
    (
        "random-64-64-20",
        "maps/mapf/random-64-64-20.map",
        "scen/mapf/random-64-64-20-random-1.scen",
    ),
    (
        "ht_chantry",
        "maps/da2/ht_chantry.map",
        "scen/da2/ht_chantry.map.scen",
    ),
    (
        "den520d",
        "maps/dao/den520d.map",
        "scen/dao/den520d.map.scen",
    ),
];
/// `(group name, map file, scenario file)` of `exact_vs_astar`: one or two maps a category.
const EXACT_MAPS: [(&str, &str, &str); 11] = [
    (
        "den520d",
        "maps/dao/den520d.map",
        "scen/dao/den520d.map.scen",
    ),
    (
        "brc202d",
        "maps/dao/brc202d.map",
        "scen/dao/brc202d.map.scen",
    ),
    (
        "ht_chantry",
        "maps/da2/ht_chantry.map",
        "scen/da2/ht_chantry.map.scen",
    ),
    (
        "AR0500SR",
        "maps/bg512/AR0500SR.map",
        "scen/bg512/AR0500SR.map.scen",
    ),
    (
        "Berlin_0_256",
        "maps/cities/Berlin_0_256.map",
        "scen/cities/Berlin_0_256.map.scen",
    ),
    (
        "Milan_1_1024",
        "maps/cities/Milan_1_1024.map",
        "scen/cities/Milan_1_1024.map.scen",
    ),
    (
        "maze512-32-0",
        "maps/mazes/maze512-32-0.map",
        "scen/mazes/maze512-32-0.map.scen",
    ),
    (
        "maze512-2-5",
        "maps/mazes/maze512-2-5.map",
        "scen/mazes/maze512-2-5.map.scen",
    ),
    (
        "random512-20-0",
        "maps/random/random512-20-0.map",
        "scen/random/random512-20-0.map.scen",
    ),
    (
        "random-64-64-20",
        "maps/mapf/random-64-64-20.map",
        "scen/mapf/random-64-64-20-random-1.scen",
    ),
    (
        "32room_000",
        "maps/rooms/32room_000.map",
        "scen/rooms/32room_000.map.scen",
    ),
];
/// A single optimal any-angle query slower than this skips that planner on the map.
const OPTIMAL_LIMIT: Duration = Duration::from_secs(1);

type Query = (CellXy, CellXy);

struct Case {
    name: String,
    grid: OccupancyGrid,
    queries: Vec<Query>,
}

/// The maps of `maps` with ~20 problems each, spread evenly over the (bucket-sorted)
/// scenario file; a generated grid when the data folder is absent.
fn cases_of(maps: &[(&str, &str, &str)]) -> Vec<Case> {
    let dir = data_dir();
    if !dir.is_dir() {
        return vec![generated_case()];
    }
    maps.iter()
        .filter(|(_, map, _)| dir.join(map).is_file())
        .map(|&(name, map, scen)| {
            let grid = read_movingai_map(dir.join(map)).unwrap();
            let mut scen = read_scen(dir.join(scen)).unwrap();
            scen.sort_by_key(|s| s.bucket);
            let n = scen.len();
            let queries = (0..QUERIES_PER_MAP.min(n))
                .map(|i| {
                    let s = &scen[(2 * i + 1) * n / (2 * QUERIES_PER_MAP.min(n))];
                    (s.start, s.goal)
                })
                .collect();
            Case {
                name: name.to_owned(),
                grid,
                queries,
            }
        })
        .collect()
}

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/movingai")
}

/// The benchmark maps ([`MAPS`]) of [`cases_of`], saying so when the data folder is absent.
fn cases() -> Vec<Case> {
    let dir = data_dir();
    if !dir.is_dir() {
        println!(
            "Moving AI data not found at {}; using a generated 128x128 random grid",
            dir.display()
        );
    }
    cases_of(&MAPS)
}

fn generated_case() -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed);
    let (w, h) = (128, 128);
    let cells = (0..w * h)
        .map(|_| {
            if rng.random_bool(0.2) {
                Occupancy::Occupied
            } else {
                Occupancy::Free
            }
        })
        .collect();
    let grid = OccupancyGrid::from_cells(w, h, 1.0, [0.0; 2], cells).unwrap();
    let free_cell = |rng: &mut ChaCha8Rng| loop {
        let c = CellXy::new(rng.random_range(0..w), rng.random_range(0..h));
        if grid.is_free(c.x, c.y) {
            break c;
        }
    };
    let queries = (0..QUERIES_PER_MAP)
        .map(|_| (free_cell(&mut rng), free_cell(&mut rng)))
        .collect();
    Case {
        name: "generated-128".to_owned(),
        grid,
        queries,
    }
}

const STRAIGHT: u64 = 10_000;
const DIAGONAL: u64 = 14_142;

/// Benchmark `name` in `group`: one iteration runs `plan` on every query of `queries`.
fn bench_queries<R>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    queries: &[(CellXy, CellXy)],
    mut plan: impl FnMut(CellXy, CellXy) -> R,
) {
    group.bench_function(name, |b| {
        b.iter(|| {
            for &(start, goal) in queries {
                black_box(plan(start, goal));
            }
        });
    });
}

/// The reference: `pathfinding`'s A* with 8-connected, no-corner-cutting successors.
fn reference_astar(grid: &OccupancyGrid, start: CellXy, goal: CellXy) -> Option<Vec<CellXy>> {
    let (w, h) = (grid.width() as i64, grid.height() as i64);
    let cells = grid.cells();
    let free = |x: i64, y: i64| {
        x >= 0 && y >= 0 && x < w && y < h && cells[(y * w + x) as usize] == Occupancy::Free
    };
    let goal_index = (goal.y as i64 * w + goal.x as i64) as u32;
    let (gx, gy) = (goal.x as i64, goal.y as i64);
    let start_index = (start.y as i64 * w + start.x as i64) as u32;
    let (path, _) = pathfinding::directed::astar::astar(
        &start_index,
        |&n| {
            let (x, y) = (i64::from(n) % w, i64::from(n) / w);
            let mut out = Vec::with_capacity(8);
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if (dx, dy) == (0, 0) || !free(x + dx, y + dy) {
                        continue;
                    }
                    let diagonal = dx != 0 && dy != 0;
                    if diagonal && !(free(x + dx, y) && free(x, y + dy)) {
                        continue;
                    }
                    let cost = if diagonal { DIAGONAL } else { STRAIGHT };
                    out.push((((y + dy) * w + x + dx) as u32, cost));
                }
            }
            out
        },
        |&n| {
            let (x, y) = (i64::from(n) % w, i64::from(n) / w);
            let (dx, dy) = ((x - gx).unsigned_abs(), (y - gy).unsigned_abs());
            let (lo, hi) = (dx.min(dy), dx.max(dy));
            STRAIGHT * (hi - lo) + DIAGONAL * lo
        },
        |&n| n == goal_index,
    )?;
    let width = grid.width();
    Some(
        path.into_iter()
            .map(|n| CellXy::new(n as usize % width, n as usize / width))
            .collect(),
    )
}

/// Both A*s solve the same queries with the same lengths (within 1e-3 cells).
fn check_agreement(case: &Case) {
    let mut search = AstarSearch::new();
    let opts = AstarOptions::default();
    let mut solved = 0;
    for &(start, goal) in &case.queries {
        let ours = search.search(&case.grid, start, goal, &opts).unwrap();
        let theirs = reference_astar(&case.grid, start, goal);
        match (ours, theirs) {
            (None, None) => {}
            (Some(plan), Some(path)) => {
                let reference = path_length(&path);
                assert!(
                    (plan.length_cells - reference).abs() < 1e-3,
                    "{}: {start:?} -> {goal:?}: ours {} vs pathfinding {reference}",
                    case.name,
                    plan.length_cells
                );
                solved += 1;
            }
            (ours, theirs) => panic!(
                "{}: {start:?} -> {goal:?}: ours solved {}, pathfinding solved {}",
                case.name,
                ours.is_some(),
                theirs.is_some()
            ),
        }
    }
    println!(
        "{}: {} queries, {solved} solvable, A* and pathfinding agree",
        case.name,
        case.queries.len()
    );
}

/// Whether every optimal any-angle query finishes within [`OPTIMAL_LIMIT`].
fn optimal_is_fast(case: &Case) -> bool {
    let opts = OptimalAnyAngleOptions::default();
    for &(start, goal) in &case.queries {
        let t = Instant::now();
        black_box(optimal_any_angle(&case.grid, start, goal, &opts).unwrap());
        let elapsed = t.elapsed();
        if elapsed > OPTIMAL_LIMIT {
            println!(
                "{}: optimal any-angle took {elapsed:?} on {start:?} -> {goal:?}; skipping it",
                case.name
            );
            return false;
        }
    }
    true
}

fn benches(c: &mut Criterion) {
    for case in cases() {
        check_agreement(&case);
        let grid = &case.grid;
        let queries = &case.queries;

        let mut group = c.benchmark_group(format!("astar_vs_pathfinding/{}", case.name));
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(3));
        group.warm_up_time(Duration::from_secs(1));
        let mut search = AstarSearch::new();
        let opts = AstarOptions::default();
        bench_queries(&mut group, "vpmap_astar_search", queries, |s, g| {
            search.search(grid, s, g, &opts).unwrap()
        });
        bench_queries(&mut group, "pathfinding_astar", queries, |s, g| {
            reference_astar(grid, s, g)
        });
        group.finish();

        let run_optimal = optimal_is_fast(&case);
        let mut group = c.benchmark_group(format!("planners/{}", case.name));
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(3));
        group.warm_up_time(Duration::from_secs(1));
        bench_queries(&mut group, "astar", queries, |s, g| {
            astar(grid, s, g, &opts).unwrap()
        });
        let ps_opts = AstarPsOptions::default();
        bench_queries(&mut group, "astar_ps", queries, |s, g| {
            astar_ps(grid, s, g, &ps_opts).unwrap()
        });
        let mbpp_opts = MbppOptions::default();
        bench_queries(&mut group, "mbpp", queries, |s, g| {
            mbpp(grid, s, g, &mbpp_opts).unwrap()
        });
        let closer_opts = MbppOptions {
            leave: LeaveRule::Closer,
            ..MbppOptions::default()
        };
        bench_queries(&mut group, "mbpp_closer", queries, |s, g| {
            mbpp(grid, s, g, &closer_opts).unwrap()
        });
        let theta_opts = ThetaStarOptions::default();
        bench_queries(&mut group, "theta_star", queries, |s, g| {
            theta_star(grid, s, g, &theta_opts).unwrap()
        });
        if run_optimal {
            let optimal_opts = OptimalAnyAngleOptions::default();
            bench_queries(&mut group, "optimal_any_angle", queries, |s, g| {
                optimal_any_angle(grid, s, g, &optimal_opts).unwrap()
            });
        }
        group.finish();
    }
}

/// The exact planner against our A* per query batch, and its one-off build.
fn exact_benches(c: &mut Criterion) {
    for case in cases_of(&EXACT_MAPS) {
        let grid = &case.grid;
        let queries = &case.queries;
        let built = Instant::now();
        let mut exact = ExactPlanner::new(grid, false);
        let build = built.elapsed();
        // Same answers as the reference where the reference is quick enough to ask.
        // The reference stops after OPTIMAL_LIMIT (its answer is then not compared).
        let vg_opts = || OptimalAnyAngleOptions {
            budget: Budget {
                stop: vpmap_plan::Stop::new().with_timeout(OPTIMAL_LIMIT),
                ..Budget::default()
            },
            ..OptimalAnyAngleOptions::default()
        };
        let mut checked = 0;
        // The reference is quadratic in the corner cells: asked only on maps with few.
        let small = vpmap_plan::corner_cells(grid, false).len() <= 25_000;
        for &(start, goal) in queries {
            let e = exact.plan(start, goal, &Budget::default()).unwrap();
            if checked < 5
                && small
                && let Ok(r) =
                    vpmap_plan::optimal::visibility_graph_any_angle(grid, start, goal, &vg_opts())
            {
                let (e, r) = (e.unwrap(), r.unwrap());
                assert!(
                    (e.length_cells - r.length_cells).abs() < 1e-9,
                    "{}",
                    case.name
                );
                checked += 1;
            }
        }
        println!(
            "exact_vs_astar/{}: {} queries, {checked} checked against the visibility graph; \
             build {build:?} (one run)",
            case.name,
            queries.len()
        );
        let mut group = c.benchmark_group(format!("exact_vs_astar/{}", case.name));
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(3));
        group.warm_up_time(Duration::from_secs(1));
        let mut search = AstarSearch::new();
        let opts = AstarOptions::default();
        bench_queries(&mut group, "astar", queries, |s, g| {
            search.search(grid, s, g, &opts).unwrap()
        });
        let budget = Budget::default();
        bench_queries(&mut group, "exact", queries, |s, g| {
            exact.plan(s, g, &budget).unwrap()
        });
        group.bench_function("exact_build", |b| {
            b.iter(|| black_box(ExactPlanner::new(grid, false)));
        });
        group.finish();
    }
}

/// Segments from each query's A* path start to every fourth cell of that path.
fn sight_segments(case: &Case) -> Vec<(CellXy, CellXy)> {
    let opts = AstarOptions::default();
    let mut segments = Vec::new();
    for &(start, goal) in &case.queries {
        let Some(plan) = astar(&case.grid, start, goal, &opts).unwrap() else {
            continue;
        };
        for &cell in plan.waypoints.iter().step_by(4).skip(1) {
            segments.push((start, cell));
        }
    }
    segments
}

fn sight_benches(c: &mut Criterion) {
    for case in cases() {
        let segments = sight_segments(&case);
        let grid = &case.grid;
        let reference = Traversable::new(grid, false);
        let core = PassableGrid::new(grid, false);
        let clear = segments
            .iter()
            .filter(|&&(a, b)| {
                let answer = line_of_sight(&core, a, b);
                assert_eq!(answer, line_of_sight(&reference, a, b), "{a:?} -> {b:?}");
                answer
            })
            .count();
        eprintln!(
            "line_of_sight/{}: {} segments, {clear} clear",
            case.name,
            segments.len()
        );
        let mut group = c.benchmark_group(format!("line_of_sight/{}", case.name));
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(2));
        group.warm_up_time(Duration::from_secs(1));
        group.bench_function("reference_walk", |b| {
            b.iter(|| {
                for &(a, b) in &segments {
                    black_box(line_of_sight(&reference, a, b));
                }
            });
        });
        group.bench_function("shared_core", |b| {
            b.iter(|| {
                for &(a, b) in &segments {
                    black_box(line_of_sight(&core, a, b));
                }
            });
        });
        let mut boxed = core.clone();
        boxed.index_boxes();
        for &(a, b) in &segments {
            assert_eq!(line_of_sight(&boxed, a, b), line_of_sight(&core, a, b));
        }
        group.bench_function("shared_core_box_index", |b| {
            b.iter(|| {
                for &(a, b) in &segments {
                    black_box(line_of_sight(&boxed, a, b));
                }
            });
        });
        group.bench_function("shared_core_built_in_timing", |b| {
            b.iter(|| {
                let core = PassableGrid::new(grid, false);
                for &(a, b) in &segments {
                    black_box(line_of_sight(&core, a, b));
                }
            });
        });
        group.finish();
    }
}

/// `(group name, map file, scenario file)` of `astar_per_expansion`.
const EXPANSION_MAPS: [(&str, &str, &str); 2] = [
    (
        "maze512-32-0",
        "maps/mazes/maze512-32-0.map",
        "scen/mazes/maze512-32-0.map.scen",
    ),
    (
        "random512-20-0",
        "maps/random/random512-20-0.map",
        "scen/random/random512-20-0.map.scen",
    ),
];

/// A seeded `side` x `side` grid with `blocked` of its cells occupied, and `n` seeded
/// queries between free cells at least 0.3 of the side apart that A* connects (as the
/// Python bench picks them).
fn random_case(side: usize, blocked: f64, n: usize) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(512);
    let cells = (0..side * side)
        .map(|_| {
            if rng.random_bool(blocked) {
                Occupancy::Occupied
            } else {
                Occupancy::Free
            }
        })
        .collect();
    let grid = OccupancyGrid::from_cells(side, side, 1.0, [0.0; 2], cells).unwrap();
    let mut search = AstarSearch::new();
    let opts = AstarOptions::default();
    let mut queries = Vec::new();
    while queries.len() < n {
        let mut free_cell = || loop {
            let c = CellXy::new(rng.random_range(0..side), rng.random_range(0..side));
            if grid.is_free(c.x, c.y) {
                break c;
            }
        };
        let (s, g) = (free_cell(), free_cell());
        let apart = (s.x.abs_diff(g.x).pow(2) + s.y.abs_diff(g.y).pow(2)) as f64;
        if apart.sqrt() >= 0.3 * side as f64 && search.search(&grid, s, g, &opts).unwrap().is_some()
        {
            queries.push((s, g));
        }
    }
    Case {
        name: format!("random{side}-seeded"),
        grid,
        queries,
    }
}

/// The queries of [`EXPANSION_MAPS`] from the scenario files' last buckets (the longest
/// paths), and the seeded random grid.
fn expansion_cases() -> Vec<Case> {
    let dir = data_dir();
    let mut cases: Vec<Case> = EXPANSION_MAPS
        .iter()
        .filter(|(_, map, _)| dir.join(map).is_file())
        .map(|&(name, map, scen)| {
            let grid = read_movingai_map(dir.join(map)).unwrap();
            let mut scen = read_scen(dir.join(scen)).unwrap();
            scen.sort_by_key(|s| std::cmp::Reverse(s.bucket));
            let queries = scen
                .iter()
                .step_by(7)
                .take(QUERIES_PER_MAP)
                .map(|s| (s.start, s.goal))
                .collect();
            Case {
                name: name.to_owned(),
                grid,
                queries,
            }
        })
        .collect();
    cases.push(random_case(512, 0.2, QUERIES_PER_MAP));
    cases
}

/// Time per A* node expansion: ours reused, through the free function, allocating per call,
/// and `pathfinding`'s.
fn expansion_benches(c: &mut Criterion) {
    for case in expansion_cases() {
        check_agreement(&case);
        let grid = &case.grid;
        let queries = &case.queries;
        let mut search = AstarSearch::new();
        let opts = AstarOptions::default();
        let expanded: usize = queries
            .iter()
            .map(|&(s, g)| {
                let plan = search.search(grid, s, g, &opts).unwrap();
                plan.map_or(0, |p| p.stats.expanded)
            })
            .sum();
        println!(
            "astar_per_expansion/{}: {} queries, {expanded} expansions",
            case.name,
            queries.len()
        );
        let mut group = c.benchmark_group(format!("astar_per_expansion/{}", case.name));
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(3));
        group.warm_up_time(Duration::from_secs(1));
        group.throughput(Throughput::Elements(expanded as u64));
        bench_queries(&mut group, "vpmap_astar_search", queries, |s, g| {
            search.search(grid, s, g, &opts).unwrap()
        });
        bench_queries(&mut group, "vpmap_astar_free_fn", queries, |s, g| {
            astar(grid, s, g, &opts).unwrap()
        });
        bench_queries(&mut group, "vpmap_astar_new_search", queries, |s, g| {
            AstarSearch::new().search(grid, s, g, &opts).unwrap()
        });
        bench_queries(&mut group, "pathfinding_astar", queries, |s, g| {
            reference_astar(grid, s, g)
        });
        group.finish();
    }
}

criterion_group!(
    planner_benches,
    expansion_benches,
    benches,
    exact_benches,
    sight_benches
);
criterion_main!(planner_benches);
