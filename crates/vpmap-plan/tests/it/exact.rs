//! The fast exact any-angle planner ([`ExactPlanner`], Anya-style interval search) against
//! the visibility-graph reference ([`visibility_graph_any_angle`]) to 1e-9 on seeded random
//! grids, against BFS connectivity, the independent validator and every other planner.

use rand::RngExt;
use vpmap_plan::{
    AstarPsOptions, Budget, ExactPlanner, OccupancyGrid, OptimalAnyAngleOptions, Plan,
    ThetaStarOptions, astar_ps, optimal::visibility_graph_any_angle, theta_star,
};

use crate::any_angle::{KINDS, check_plan, generate, traversable_cells};
use crate::rng;

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
        let grid = crate::random_grid(&mut rng, w, h, occupied, unknown);
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
