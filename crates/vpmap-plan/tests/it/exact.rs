//! The fast exact any-angle planner ([`ExactPlanner`], Anya-style interval search) against
//! the visibility-graph reference ([`visibility_graph_any_angle`]) to 1e-9 on seeded random
//! grids, against BFS connectivity, the independent validator and every other planner.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use rand::RngExt;
use vpmap_plan::{
    AstarPsOptions, Budget, CellXy, ExactPlanner, Occupancy, OccupancyGrid, OptimalAnyAngleOptions,
    Plan, PlanError, Planner, PlannerKind, Stop, StopReason, ThetaStarOptions, astar_ps,
    optimal::visibility_graph_any_angle, theta_star,
};

use crate::grids::{KINDS, generate, random_grid, traversable_cells};
use crate::{check_plan, rng};

/// Compare the two exact planners on `queries` random pairs of `grid`'s traversable cells
/// (one [`ExactPlanner`] for all of them); the number of paths compared.
fn compare(
    rng: &mut rand_chacha::ChaCha8Rng,
    grid: &OccupancyGrid,
    unknown_passable: bool,
    queries: usize,
    context: &str,
) -> usize {
    let cells = traversable_cells(grid, unknown_passable);
    if cells.is_empty() {
        return 0;
    }
    let mut planner = ExactPlanner::new(grid, unknown_passable);
    let mut compared = 0;
    for _ in 0..queries {
        let start = cells[rng.random_range(0..cells.len())];
        let goal = cells[rng.random_range(0..cells.len())];
        let context = format!("{context} {start:?} -> {goal:?}\n{grid:?}");
        let reference = visibility_graph_any_angle(
            grid,
            start,
            goal,
            &OptimalAnyAngleOptions {
                unknown_passable,
                ..OptimalAnyAngleOptions::default()
            },
        )
        .unwrap();
        let exact = planner.plan(start, goal, &Budget::default()).unwrap();
        let reachable = vpmap_plan::reachable(grid, start, goal, unknown_passable);
        assert_eq!(exact.is_some(), reachable, "reach: {context}");
        match (&exact, &reference) {
            (Some(e), Some(r)) => {
                check_plan("exact", grid, e, start, goal, unknown_passable);
                assert!(
                    (e.length_cells - r.length_cells).abs() < 1e-9,
                    "exact {} ({:?}) vs visibility graph {} ({:?}): {context}",
                    e.length_cells,
                    e.waypoints,
                    r.length_cells,
                    r.waypoints
                );
                never_beaten(grid, e, start, goal, unknown_passable, &context);
                compared += 1;
            }
            (None, None) => {}
            _ => panic!(
                "exact found {}, visibility graph found {}: {context}",
                exact.is_some(),
                reference.is_some()
            ),
        }
    }
    compared
}

/// No other planner's (valid) path is shorter than the exact one.
fn never_beaten(
    grid: &OccupancyGrid,
    exact: &Plan,
    start: (usize, usize),
    goal: (usize, usize),
    unknown_passable: bool,
    context: &str,
) {
    let th = theta_star(
        grid,
        start,
        goal,
        &ThetaStarOptions {
            unknown_passable,
            ..ThetaStarOptions::default()
        },
    )
    .unwrap()
    .unwrap();
    let ps = astar_ps(
        grid,
        start,
        goal,
        &AstarPsOptions {
            unknown_passable,
            ..AstarPsOptions::default()
        },
    )
    .unwrap()
    .unwrap();
    for (name, other) in [("Theta*", th), ("A* PS", ps)] {
        assert!(
            exact.length_cells <= other.length_cells + 1e-9,
            "exact > {name}: {context}"
        );
    }
}

#[test]
fn exact_equals_the_visibility_graph_on_random_grids_of_every_kind() {
    let mut rng = rng(0xe8ac_7a11);
    let mut compared = 0;
    for round in 0..2100 {
        let kind = KINDS[round % KINDS.len()];
        let (grid, unknown_passable) = generate(&mut rng, kind, 16);
        compared += compare(
            &mut rng,
            &grid,
            unknown_passable,
            4,
            &format!("{kind} round {round}"),
        );
    }
    assert!(compared > 5000, "{compared}");
}

#[test]
fn exact_equals_the_visibility_graph_on_random_grids_of_several_densities() {
    let mut rng = rng(0xd3e5_1717);
    let mut compared = 0;
    for round in 0..600 {
        let occupied = [0.05, 0.15, 0.25, 0.35, 0.45][round % 5];
        let (w, h) = (rng.random_range(2..=24), rng.random_range(2..=24));
        let unknown = if round % 3 == 0 { 0.1 } else { 0.0 };
        let grid = random_grid(&mut rng, w, h, occupied, unknown);
        let unknown_passable = round % 2 == 0;
        compared += compare(
            &mut rng,
            &grid,
            unknown_passable,
            5,
            &format!("density {occupied} round {round}"),
        );
    }
    assert!(compared > 1500, "{compared}");
}

#[test]
fn exact_equals_the_visibility_graph_on_larger_mazes_and_clutter() {
    let mut rng = rng(0x1a76_e000);
    let mut compared = 0;
    for round in 0..90 {
        let kind = ["maze", "cluttered", "diagonal-gaps", "rooms", "spiral"][round % 5];
        let (grid, unknown_passable) = generate(&mut rng, kind, 40);
        compared += compare(
            &mut rng,
            &grid,
            unknown_passable,
            4,
            &format!("{kind} large round {round}"),
        );
    }
    assert!(compared > 200, "{compared}");
}

/// A 60 x 60 field of pillars every 4 cells.
fn pillar_field() -> OccupancyGrid {
    let mut grid = OccupancyGrid::new(60, 60, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for y in (2..58).step_by(4) {
        for x in (2..58).step_by(4) {
            grid.set(x, y, Occupancy::Occupied).unwrap();
        }
    }
    grid
}

#[test]
fn exact_expansion_budget_allows_exactly_the_expansions_it_names() {
    let grid = pillar_field();
    let mut planner = ExactPlanner::new(&grid, false);
    let full = planner
        .plan((0, 1), (59, 57), &Budget::default())
        .unwrap()
        .unwrap();
    let expanded = full.stats.expanded;
    assert!(expanded > 10, "{expanded}");
    let with = |max_expansions| Budget {
        max_expansions,
        ..Budget::default()
    };
    let enough = planner
        .plan((0, 1), (59, 57), &with(expanded))
        .unwrap()
        .unwrap();
    assert_eq!(enough.waypoints, full.waypoints);
    let err = planner
        .plan((0, 1), (59, 57), &with(expanded - 1))
        .unwrap_err();
    assert!(
        matches!(err, PlanError::BudgetExhausted { option: "max_expansions", limit, .. } if limit == expanded - 1),
        "{err}"
    );
}

#[test]
fn exact_planner_stops_when_its_flag_is_set() {
    let grid = pillar_field();
    let flag = Arc::new(AtomicBool::new(true));
    let budget = Budget {
        stop: Stop::new().with_flag(flag),
        ..Budget::default()
    };
    let result = ExactPlanner::new(&grid, false).plan((0, 1), (59, 57), &budget);
    assert!(
        matches!(
            result,
            Err(PlanError::Stopped {
                reason: StopReason::Cancelled,
                ..
            })
        ),
        "{result:?}"
    );
}

#[test]
fn built_in_optimal_rebuilds_its_free_space_when_the_grid_changes() {
    let mut grid = pillar_field();
    let mut planner = PlannerKind::Optimal.planner(false);
    let before = planner
        .plan(&grid, CellXy::new(0, 2), CellXy::new(12, 2))
        .unwrap()
        .best
        .unwrap();
    assert!(before.length_cells > 12.0, "{:?}", before.waypoints); // round the pillars
    for x in 0..60 {
        if x != 32 {
            grid.set(x, 5, Occupancy::Occupied).unwrap();
        }
    }
    for x in [2, 6, 10] {
        grid.set(x, 2, Occupancy::Free).unwrap();
    }
    let after = planner
        .plan(&grid, CellXy::new(0, 2), CellXy::new(12, 2))
        .unwrap()
        .best
        .unwrap();
    assert_eq!(after.waypoints, [CellXy::new(0, 2), CellXy::new(12, 2)]);
    let crossing = planner
        .plan(&grid, CellXy::new(0, 0), CellXy::new(0, 59))
        .unwrap()
        .best
        .unwrap();
    vpmap_plan::validate_path(&grid, &crossing.waypoints, false).unwrap();
    let reference =
        visibility_graph_any_angle(&grid, (0, 0), (0, 59), &OptimalAnyAngleOptions::default())
            .unwrap()
            .unwrap();
    assert!((crossing.length_cells - reference.length_cells).abs() < 1e-9);
}

/// Goals inside a dead end (the corridor) and outside it are reached as the visibility graph
/// reaches them, from every free cell (moved here from the exact planner's unit test of its
/// dead-end table).
#[test]
fn dead_ends_are_pruned_and_goals_inside_them_still_reached() {
    // #.###
    // #.###
    // .....
    // .....
    let mut grid = OccupancyGrid::new(5, 4, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for (x, y) in [
        (0, 0),
        (2, 0),
        (3, 0),
        (4, 0),
        (0, 1),
        (2, 1),
        (3, 1),
        (4, 1),
    ] {
        grid.set(x, y, Occupancy::Occupied).unwrap();
    }
    let mut planner = ExactPlanner::new(&grid, false);
    let opts = OptimalAnyAngleOptions::default();
    let cells: Vec<(usize, usize)> = (0..4)
        .flat_map(|y| (0..5).map(move |x| (x, y)))
        .filter(|&(x, y)| grid.is_free(x, y))
        .collect();
    for &start in &cells {
        for &goal in &cells {
            let exact = planner
                .plan(start, goal, &Budget::default())
                .unwrap()
                .unwrap();
            let reference = visibility_graph_any_angle(&grid, start, goal, &opts)
                .unwrap()
                .unwrap();
            assert!(
                (exact.length_cells - reference.length_cells).abs() < 1e-9,
                "{start:?} -> {goal:?}"
            );
        }
    }
}

/// Every `(map path, scenario path)` pair of the shared Moving AI data, sorted.
fn movingai_pairs() -> Vec<(std::path::PathBuf, std::path::PathBuf)> {
    let dir = crate::movingai_dir();
    let mut maps = std::collections::HashMap::new();
    for set in std::fs::read_dir(dir.join("maps")).unwrap() {
        for file in std::fs::read_dir(set.unwrap().path()).unwrap() {
            let path = file.unwrap().path();
            maps.insert(path.file_name().unwrap().to_owned(), path);
        }
    }
    let mut out = Vec::new();
    for set in std::fs::read_dir(dir.join("scen")).unwrap() {
        for file in std::fs::read_dir(set.unwrap().path()).unwrap() {
            let scen = file.unwrap().path();
            let problems = vpmap_plan::read_scen(&scen).unwrap();
            let name = std::ffi::OsString::from(problems[0].map_file_name());
            out.push((maps[&name].clone(), scen));
        }
    }
    out.sort();
    out
}

/// Maps with more corner cells than this are compared on fewer problems (the reference is
/// quadratic in them: seconds a query)...
const SLOW_REFERENCE_CORNERS: usize = 10_000;
/// ... and with more than this, not at all (minutes a query; `vpmap bench` skipped it there):
/// the exact path is then checked by the validator, the octile optimum and the other
/// planners only.
const REFERENCE_CORNERS: usize = 25_000;

#[test]
#[ignore = "needs ../shared/data/movingai (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_exact_equals_the_visibility_graph_on_every_benchmark_map() {
    // Problems per scenario file, spread over its buckets (debug builds: fewer).
    let per_map: usize = if cfg!(debug_assertions) { 4 } else { 10 };
    let (mut compared, mut maps, mut out_of_budget) = (0, 0, 0);
    for (map_path, scen_path) in movingai_pairs() {
        let grid = vpmap_plan::read_movingai_map(&map_path).unwrap();
        let corners = vpmap_plan::corner_cells(&grid, false).len();
        let per_map = if corners > SLOW_REFERENCE_CORNERS {
            per_map.div_ceil(4)
        } else {
            per_map
        };
        let with_reference = corners <= REFERENCE_CORNERS;
        let mut problems = vpmap_plan::read_scen(&scen_path).unwrap();
        problems.sort_by_key(|p| p.bucket);
        let n = problems.len();
        let mut exact = ExactPlanner::new(&grid, false);
        for i in 0..per_map.min(n) {
            let p = &problems[(2 * i + 1) * n / (2 * per_map.min(n))];
            let context = format!("{} {p:?}", map_path.display());
            let e = exact
                .plan(p.start, p.goal, &Budget::default())
                .unwrap()
                .unwrap_or_else(|| panic!("no path: {context}"));
            check_plan("exact", &grid, &e, p.start, p.goal, false);
            // The scenario's octile optimum is an 8-connected path: never shorter.
            assert!(
                e.length_cells <= p.optimal_length_cells + 1e-3,
                "{context}: {}",
                e.length_cells
            );
            // The reference within its default budget; where that runs out (long problems on
            // Milan_1_1024) it does not run, and the problem is not compared.
            let reference = with_reference.then(|| {
                visibility_graph_any_angle(
                    &grid,
                    p.start,
                    p.goal,
                    &OptimalAnyAngleOptions::default(),
                )
            });
            if let Some(reference) = reference {
                let r = match reference {
                    Err(vpmap_plan::PlanError::BudgetExhausted { .. }) => {
                        out_of_budget += 1;
                        continue;
                    }
                    r => r.unwrap().unwrap(),
                };
                assert!(
                    (e.length_cells - r.length_cells).abs() < 1e-9,
                    "{context}: exact {} vs visibility graph {}",
                    e.length_cells,
                    r.length_cells
                );
                compared += 1;
            }
            never_beaten(
                &grid,
                &e,
                (p.start.x, p.start.y),
                (p.goal.x, p.goal.y),
                false,
                &context,
            );
        }
        maps += 1;
        println!(
            "{}: {} problems valid, never beaten{} ({corners} corner cells)",
            map_path.display(),
            per_map.min(n),
            if with_reference {
                ", equal to the visibility graph"
            } else {
                ""
            }
        );
    }
    println!(
        "exact equals the visibility graph on {compared} problems of {maps} maps \
         ({out_of_budget} where the reference ran out of budget)"
    );
    assert!(maps >= 18 && compared >= 16 * 2, "{maps} {compared}");
}
