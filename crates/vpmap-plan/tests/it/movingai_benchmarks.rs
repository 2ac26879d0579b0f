//! A* against the optimal lengths of the Moving AI benchmark scenarios (an independent
//! reference: the published octile optima), and "no path" across connected components.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use vpmap_plan::{
    AstarOptions, AstarSearch, Passable, Planner, PlannerKind, Traversable, read_movingai_map,
    read_scen, validate_path,
};

use crate::movingai_dir;
use vpmap_plan::Components;

/// Maps up to this many cells have every problem checked.
const SMALL_MAP_CELLS: usize = 25_000;
/// Maps up to this many cells have every problem checked in release builds and every
/// `MID_MAP_STRIDE`-th in debug builds; larger maps are sampled (see [`large_map_stride`]).
const MID_MAP_CELLS: usize = 70_000;
const MID_MAP_STRIDE: usize = if cfg!(debug_assertions) { 5 } else { 1 };

/// Stride through a large map's problems: 10 evenly spread problems in debug builds
/// (long problems cost ~1e5 expansions there), every 10th in release builds.
fn large_map_stride(problems: usize) -> usize {
    if cfg!(debug_assertions) {
        problems.div_ceil(10).max(1)
    } else {
        10
    }
}

/// Every `.map` file under `maps/`, by file name.
fn map_paths(dir: &Path) -> HashMap<String, PathBuf> {
    let mut out = HashMap::new();
    for set in std::fs::read_dir(dir.join("maps")).unwrap() {
        for file in std::fs::read_dir(set.unwrap().path()).unwrap() {
            let path = file.unwrap().path();
            out.insert(
                path.file_name().unwrap().to_string_lossy().into_owned(),
                path,
            );
        }
    }
    out
}

/// Every `.scen` file under `scen/`, sorted.
fn scen_paths(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for set in std::fs::read_dir(dir.join("scen")).unwrap() {
        for file in std::fs::read_dir(set.unwrap().path()).unwrap() {
            out.push(file.unwrap().path());
        }
    }
    out.sort();
    out
}

fn tolerance(length: f64) -> f64 {
    0.005f64.max(5e-6 * length)
}

/// Totals over the checked problems.
#[derive(Default)]
struct Tally {
    checked: usize,
    total: usize,
    expanded: usize,
    /// Largest `|A* - optimum| / tolerance`.
    worst: f64,
}

/// Run A* on every `stride(cells, problems)`-th problem of every scenario file whose map
/// size passes `select`, checking the length against the optimum and the path with the
/// validator.
fn check_scenarios(
    select: impl Fn(usize) -> bool,
    stride: impl Fn(usize, usize) -> usize,
) -> Tally {
    let dir = movingai_dir();
    let maps = map_paths(&dir);
    let mut search = AstarSearch::new();
    let mut tally = Tally::default();
    for scen_path in scen_paths(&dir) {
        let scen = read_scen(&scen_path).unwrap();
        let first = &scen[0];
        let cells = first.width * first.height;
        if !select(cells) {
            continue;
        }
        let t = Instant::now();
        let name = first.map_file_name().to_owned();
        let grid = read_movingai_map(&maps[&name]).unwrap();
        let mut checked = 0;
        for s in scen.iter().step_by(stride(cells, scen.len())) {
            assert_eq!(s.map_file_name(), name);
            let plan = search
                .search(&grid, s.start, s.goal, &AstarOptions::default())
                .unwrap()
                .unwrap_or_else(|| panic!("{}: no path for {s:?}", scen_path.display()));
            let error = (plan.length_cells - s.optimal_length_cells).abs();
            assert!(
                error <= tolerance(s.optimal_length_cells),
                "{}: {s:?}: A* length {} is off by {error}",
                scen_path.display(),
                plan.length_cells
            );
            validate_path(&grid, &plan.waypoints, false).unwrap();
            tally.worst = tally.worst.max(error / tolerance(s.optimal_length_cells));
            tally.expanded += plan.stats.expanded;
            checked += 1;
        }
        println!(
            "{name}: {checked} of {} problems match ({:.1} s)",
            scen.len(),
            t.elapsed().as_secs_f64()
        );
        tally.checked += checked;
        tally.total += scen.len();
    }
    println!(
        "A* matches {} of {} problems ({} expansions); largest error {:.3} of the tolerance",
        tally.checked, tally.total, tally.expanded, tally.worst
    );
    tally
}

#[test]
#[ignore = "needs ../shared/data/movingai (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_astar_reproduces_the_optima_of_the_small_benchmark_maps() {
    let stride = |cells: usize, _| {
        if cells <= SMALL_MAP_CELLS {
            1
        } else {
            MID_MAP_STRIDE
        }
    };
    let tally = check_scenarios(|cells| cells <= MID_MAP_CELLS, stride);
    // 4 mapf maps and ht_chantry in full, Berlin, arena2 and den520d in part or full.
    assert!(tally.checked >= 5000, "{}", tally.checked);
}

#[test]
#[ignore = "needs ../shared/data/movingai (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_astar_reproduces_sampled_optima_of_the_large_benchmark_maps() {
    let tally = check_scenarios(
        |cells| cells > MID_MAP_CELLS,
        |_, problems| large_map_stride(problems),
    );
    assert!(tally.checked >= 100, "{}", tally.checked);
}

#[test]
#[ignore = "needs ../shared/data/movingai (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_no_path_between_components_of_benchmark_maps() {
    let dir = movingai_dir();
    let maps = map_paths(&dir);
    let mut search = AstarSearch::new();
    let mut pairs = 0;
    for name in ["Berlin_0_256.map", "AR0500SR.map"] {
        let grid = read_movingai_map(&maps[name]).unwrap();
        let map = Traversable::new(&grid, false);
        let w = grid.width();
        let components = Components::label(&grid, false);
        // The first cell of each component, in row-major order.
        let mut firsts: Vec<(usize, usize)> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for (i, &l) in components.labels().iter().enumerate() {
            if l != 0 && seen.insert(l) {
                firsts.push((i % w, i / w));
            }
        }
        assert!(firsts.len() >= 2, "{name}: {} components", firsts.len());
        for pair in firsts.windows(2).take(4) {
            assert!(map.passable(pair[0].0 as i64, pair[0].1 as i64));
            let plan = search
                .search(&grid, pair[0], pair[1], &AstarOptions::default())
                .unwrap();
            assert_eq!(plan, None, "{name}: {pair:?}");
            for kind in [
                PlannerKind::Mbpp,
                PlannerKind::AstarPs,
                PlannerKind::ThetaStar,
            ] {
                let planned = kind
                    .planner(false)
                    .plan(&grid, pair[0].into(), pair[1].into())
                    .unwrap();
                assert_eq!(planned.best, None, "{kind} {name}: {pair:?}");
                assert!(planned.alternatives.is_empty());
            }
            pairs += 1;
        }
    }
    assert!(pairs >= 4);
}

#[test]
#[ignore = "needs ../shared/data/movingai (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_every_planner_solves_samples_of_every_benchmark_map() {
    let dir = movingai_dir();
    let maps = map_paths(&dir);
    let mut solved = 0;
    for scen_path in scen_paths(&dir) {
        let scen = read_scen(&scen_path).unwrap();
        let grid = read_movingai_map(&maps[scen[0].map_file_name()]).unwrap();
        // A middle and the longest problem (files are sorted by length bucket).
        for s in [&scen[scen.len() / 2], &scen[scen.len() - 1]] {
            for kind in [
                PlannerKind::Mbpp,
                PlannerKind::AstarPs,
                PlannerKind::ThetaStar,
            ] {
                let plan = kind
                    .planner(false)
                    .plan(&grid, s.start, s.goal)
                    .unwrap()
                    .best
                    .unwrap_or_else(|| panic!("{kind}: no path for {s:?}"));
                validate_path(&grid, &plan.waypoints, false)
                    .unwrap_or_else(|e| panic!("{kind} {s:?}: {e}"));
                assert_eq!(plan.waypoints.first(), Some(&s.start));
                assert_eq!(plan.waypoints.last(), Some(&s.goal));
                let straight = (s.start.x.abs_diff(s.goal.x) as f64)
                    .hypot(s.start.y.abs_diff(s.goal.y) as f64);
                assert!(plan.length_cells >= straight - 1e-9, "{kind} {s:?}");
                // Smoothing never lengthens the octile-optimal A* path.
                if kind == PlannerKind::AstarPs {
                    assert!(
                        plan.length_cells
                            <= s.optimal_length_cells + tolerance(s.optimal_length_cells)
                    );
                }
                solved += 1;
            }
        }
    }
    println!("{solved} benchmark problems solved and validated");
    assert!(solved >= 18 * 6, "{solved}");
}
