//! D* Lite against fresh A* (path costs after every batch of cell changes and robot moves),
//! the independent validator and BFS reachability.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use vpmap_plan::{
    AstarOptions, CellXy, Components, DStarLite, DStarLiteOptions, Occupancy, OccupancyGrid,
    PlanError, astar, dstar_lite, validate_path,
};

use crate::grids::random_grid;
use crate::rng;

/// A random cell of `grid` passable under `unknown_passable`.
fn passable_cell(
    rng: &mut ChaCha8Rng,
    grid: &OccupancyGrid,
    unknown_passable: bool,
) -> Option<CellXy> {
    for _ in 0..1000 {
        let c = CellXy::new(
            rng.random_range(0..grid.width()),
            rng.random_range(0..grid.height()),
        );
        match grid.get(c.x, c.y) {
            Some(Occupancy::Free) => return Some(c),
            Some(Occupancy::Unknown) if unknown_passable => return Some(c),
            _ => {}
        }
    }
    None
}

fn random_state(rng: &mut ChaCha8Rng) -> Occupancy {
    match rng.random_range(0..3) {
        0 => Occupancy::Free,
        1 => Occupancy::Occupied,
        _ => Occupancy::Unknown,
    }
}

/// Check D* Lite's current answer against a fresh A* and BFS on `grid`.
fn check_against_reference(
    planner: &mut DStarLite,
    grid: &OccupancyGrid,
    unknown_passable: bool,
    context: &str,
) -> Option<Vec<CellXy>> {
    let (start, goal) = (planner.start(), planner.goal());
    let got = planner.path().unwrap();
    let opts = AstarOptions {
        unknown_passable,
        ..AstarOptions::default()
    };
    let reference = astar(grid, start, goal, &opts).unwrap();
    let connected = Components::label(grid, unknown_passable).connected(start, goal);
    match (&got, &reference) {
        (Some(p), Some(r)) => {
            assert!(
                (p.length_cells - r.length_cells).abs() < 1e-9,
                "{context}: D* Lite {} vs A* {}",
                p.length_cells,
                r.length_cells
            );
            assert_eq!(p.waypoints.first(), Some(&start), "{context}");
            assert_eq!(p.waypoints.last(), Some(&goal), "{context}");
            validate_path(grid, &p.waypoints, unknown_passable)
                .unwrap_or_else(|e| panic!("{context}: {e:?}"));
            assert!(connected, "{context}: a path but BFS says disconnected");
        }
        (None, None) => assert!(!connected, "{context}: no path but BFS says connected"),
        _ => panic!(
            "{context}: D* Lite {:?} vs A* {:?}",
            got.as_ref().map(|p| p.length_cells),
            reference.as_ref().map(|p| p.length_cells)
        ),
    }
    got.map(|p| p.waypoints)
}

#[test]
fn dstar_lite_matches_fresh_astar_after_every_batch_of_changes() {
    let mut rng = rng(15);
    let mut episodes = 0;
    let mut found = 0;
    let mut none = 0;
    let mut same_as_fresh = 0;
    while episodes < 120 {
        let (w, h) = (rng.random_range(2..28), rng.random_range(2..28));
        let unknown_passable = rng.random_bool(0.5);
        let occupied = rng.random_range(0.0..0.35);
        let mut grid = random_grid(&mut rng, w, h, occupied, 0.15);
        let (Some(start), Some(goal)) = (
            passable_cell(&mut rng, &grid, unknown_passable),
            passable_cell(&mut rng, &grid, unknown_passable),
        ) else {
            continue;
        };
        episodes += 1;
        // Every other episode under the common tie rule. In both, costs are exact, so the
        // followed path depends on the map only: the repaired search must return exactly the
        // path of a search from scratch.
        let common_ties = episodes % 2 == 1;
        let opts = DStarLiteOptions {
            unknown_passable,
            common_ties,
            ..DStarLiteOptions::default()
        };
        let mut planner = DStarLite::new(&grid, start, goal, &opts).unwrap();
        let mut path = check_against_reference(&mut planner, &grid, unknown_passable, "initial");
        for batch in 0..12 {
            // Sometimes move the robot a few steps along its path.
            if let Some(p) = &path {
                let steps = rng.random_range(0..4).min(p.len() - 1);
                if let Some(&at) = p.get(steps) {
                    planner.move_start(at).unwrap();
                }
            }
            let robot = planner.start();
            let n = rng.random_range(1..8);
            let mut changes = Vec::new();
            for _ in 0..n {
                let c = CellXy::new(rng.random_range(0..w), rng.random_range(0..h));
                if c == robot || c == goal {
                    continue;
                }
                let state = random_state(&mut rng);
                grid.set(c.x, c.y, state).unwrap();
                changes.push((c, state));
            }
            planner.update_cells(&changes).unwrap();
            let context = format!("episode {episodes} ({w} x {h}) batch {batch}");
            path = check_against_reference(&mut planner, &grid, unknown_passable, &context);
            let fresh = dstar_lite(&grid, planner.start(), goal, &opts)
                .unwrap()
                .map(|p| p.waypoints);
            assert_eq!(path, fresh, "{context}: repaired and fresh paths differ");
            same_as_fresh += 1;
            if path.is_some() {
                found += 1;
            } else {
                none += 1;
            }
        }
    }
    // Both outcomes were exercised.
    assert!(found > 200 && none > 50, "found {found}, none {none}");
    assert!(same_as_fresh > 600, "{same_as_fresh}");
}

#[test]
fn dstar_lite_one_shot_equals_astar_on_larger_grids() {
    let mut rng = rng(1502);
    for _ in 0..20 {
        let grid = random_grid(&mut rng, 90, 70, 0.3, 0.0);
        let (Some(start), Some(goal)) = (
            passable_cell(&mut rng, &grid, false),
            passable_cell(&mut rng, &grid, false),
        ) else {
            continue;
        };
        let a = astar(&grid, start, goal, &AstarOptions::default()).unwrap();
        let d = dstar_lite(&grid, start, goal, &DStarLiteOptions::default()).unwrap();
        assert_eq!(a.is_some(), d.is_some());
        if let (Some(a), Some(d)) = (a, d) {
            assert!((a.length_cells - d.length_cells).abs() < 1e-9);
            validate_path(&grid, &d.waypoints, false).unwrap();
        }
    }
}

#[test]
fn dstar_lite_refuses_bad_endpoints_and_respects_its_budget() {
    let mut grid = OccupancyGrid::new(30, 30, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    grid.set(3, 3, Occupancy::Occupied).unwrap();
    let opts = DStarLiteOptions::default();
    assert!(matches!(
        DStarLite::new(&grid, (3, 3), (0, 0), &opts),
        Err(PlanError::EndpointBlocked {
            endpoint: "start",
            ..
        })
    ));
    assert!(matches!(
        DStarLite::new(&grid, (0, 0), (30, 0), &opts),
        Err(PlanError::EndpointOutsideGrid {
            endpoint: "goal",
            ..
        })
    ));
    let mut planner = DStarLite::new(&grid, (0, 0), (29, 29), &opts).unwrap();
    assert!(planner.move_start((0, 30)).is_err());
    assert!(matches!(
        planner.update_cells(&[(CellXy::new(31, 0), Occupancy::Free)]),
        Err(PlanError::CellOutOfBounds { .. })
    ));
    let tight = DStarLiteOptions {
        budget: vpmap_plan::Budget {
            max_expansions: 10,
            ..vpmap_plan::Budget::default()
        },
        ..DStarLiteOptions::default()
    };
    let mut planner = DStarLite::new(&grid, (0, 0), (29, 29), &tight).unwrap();
    assert!(matches!(
        planner.path(),
        Err(PlanError::BudgetExhausted {
            planner: "D* Lite",
            ..
        })
    ));
}

#[test]
fn dstar_lite_goal_walled_in_then_opened() {
    // A wall with one gap; closing the gap leaves no path, reopening restores it.
    let mut grid = OccupancyGrid::new(9, 9, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for y in 0..9 {
        if y != 4 {
            grid.set(4, y, Occupancy::Occupied).unwrap();
        }
    }
    let opts = DStarLiteOptions::default();
    let mut planner = DStarLite::new(&grid, (0, 0), (8, 8), &opts).unwrap();
    let first = planner.path().unwrap().unwrap();
    assert!(first.waypoints.contains(&CellXy::new(4, 4)));
    assert_eq!(
        planner
            .update_cells(&[(CellXy::new(4, 4), Occupancy::Occupied)])
            .unwrap(),
        1
    );
    assert_eq!(planner.path().unwrap(), None);
    planner
        .update_cells(&[(CellXy::new(4, 4), Occupancy::Free)])
        .unwrap();
    let again = planner.path().unwrap().unwrap();
    assert!((again.length_cells - first.length_cells).abs() < 1e-12);
    // A change that does not change passability is no change.
    assert_eq!(
        planner
            .update_cells(&[(CellXy::new(0, 8), Occupancy::Free)])
            .unwrap(),
        0
    );
}

/// A cell listed twice in one batch takes its last state, as the grid written in order does
/// (the first state used to win).
#[test]
fn dstar_lite_takes_the_last_state_of_a_cell_listed_twice() {
    let mut grid = OccupancyGrid::new(3, 3, 1.0, [0.0; 2], Occupancy::Occupied).unwrap();
    for x in 0..3 {
        grid.set(x, 1, Occupancy::Free).unwrap();
    }
    let opts = DStarLiteOptions::default();
    let mut planner = DStarLite::new(&grid, (0, 1), (2, 1), &opts).unwrap();
    assert_eq!(planner.path().unwrap().unwrap().length_cells, 2.0);
    let c = CellXy::new(1, 1);
    // Blocked, then free again: still a path.
    planner
        .update_cells(&[(c, Occupancy::Occupied), (c, Occupancy::Free)])
        .unwrap();
    assert_eq!(planner.path().unwrap().unwrap().length_cells, 2.0);
    // Free, then unknown (not passable by default): no path.
    planner
        .update_cells(&[(c, Occupancy::Free), (c, Occupancy::Unknown)])
        .unwrap();
    assert!(planner.path().unwrap().is_none());
}

/// The experiment of docs/navigation.md ("Why open ground favours the repeated forward A*"):
/// on an empty grid, a first D* Lite search, then four cells blocked next to the robot (a
/// detour of 1.76-2.83 cells), against a fresh forward A* on the changed map. Prints the expansions;
/// checks that both find paths of the octile length before and equal lengths after.
#[test]
#[ignore = "an experiment that prints figures: cargo test --release --test it experiment_ -- --ignored --nocapture"]
#[allow(clippy::float_cmp)]
fn experiment_repair_next_to_the_robot_on_open_ground() {
    for (dx, dy) in [(380, 0), (380, 50), (380, 150), (200, 100)] {
        let grid = OccupancyGrid::new(400, 400, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        let (start, goal) = ((10, 100), (10 + dx, 100 + dy));
        let mut planner = DStarLite::new(&grid, start, goal, &DStarLiteOptions::default()).unwrap();
        let first = planner.path().unwrap().unwrap();
        let octile = (dx - dy) as f64 + dy as f64 * std::f64::consts::SQRT_2;
        assert!((first.length_cells - octile).abs() < 1e-9);
        let wall: Vec<(CellXy, Occupancy)> = (99..=102)
            .map(|y| (CellXy::new(11, y), Occupancy::Occupied))
            .collect();
        let mut changed = grid.clone();
        for &(c, state) in &wall {
            changed.set(c.x, c.y, state).unwrap();
        }
        planner.update_cells(&wall).unwrap();
        let repaired = planner.path().unwrap().unwrap();
        let fresh = astar(&changed, start, goal, &AstarOptions::default())
            .unwrap()
            .unwrap();
        assert_eq!(repaired.length_cells, fresh.length_cells);
        assert!(repaired.length_cells > first.length_cells);
        println!(
            "goal {dx} east, {dy} north: equally short paths cover {} cells; D* Lite's first \
             search {} expansions; its repair {} (length {:.2} -> {:.2}); a fresh forward A* {}",
            (dx - dy) * dy + dx + 1,
            first.stats.expanded,
            repaired.stats.expanded,
            first.length_cells,
            repaired.length_cells,
            fresh.stats.expanded
        );
    }
}
