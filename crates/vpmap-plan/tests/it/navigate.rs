//! The navigation simulation against independent references: the validator on the true
//! map, BFS reachability, the offline planners (perfect belief) and fresh A* on the belief
//! at every step (D* Lite).

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use vpmap_plan::navigate::{Belief, NavigateOptions, OnlinePlanner, Outcome, navigate};
use vpmap_plan::planner::{Planner, PlannerKind};
use vpmap_plan::{
    AstarOptions, CellXy, Components, DStarLite, DStarLiteOptions, Occupancy, OccupancyGrid,
    PlanError, astar, validate_path,
};

use crate::grids::random_grid;
use crate::rng;

/// A random free cell of `grid`.
fn free_cell(rng: &mut ChaCha8Rng, grid: &OccupancyGrid) -> Option<CellXy> {
    (0..1000).find_map(|_| {
        let c = CellXy::new(
            rng.random_range(0..grid.width()),
            rng.random_range(0..grid.height()),
        );
        grid.is_free(c.x, c.y).then_some(c)
    })
}

fn unknown_like(grid: &OccupancyGrid) -> OccupancyGrid {
    OccupancyGrid::new(
        grid.width(),
        grid.height(),
        grid.resolution_m(),
        grid.origin_m(),
        Occupancy::Unknown,
    )
    .unwrap()
}

/// A belief that is the truth with a fraction of cells flipped (free <-> occupied).
fn noisy(rng: &mut ChaCha8Rng, truth: &OccupancyGrid, flip: f64) -> OccupancyGrid {
    let mut g = truth.clone();
    for c in g.cells_mut() {
        if rng.random_bool(flip) {
            *c = match *c {
                Occupancy::Free => Occupancy::Occupied,
                _ => Occupancy::Free,
            };
        }
    }
    g
}

#[test]
fn driven_paths_are_valid_on_the_truth_and_reach_the_goal_iff_bfs_says_so() {
    let mut rng = rng(1515);
    let mut reached = 0;
    let mut unreachable = 0;
    for episode in 0..60 {
        let (w, h) = (rng.random_range(3..30), rng.random_range(3..30));
        let truth = random_grid(&mut rng, w, h, 0.3, 0.03);
        let (Some(start), Some(goal)) = (free_cell(&mut rng, &truth), free_cell(&mut rng, &truth))
        else {
            continue;
        };
        let connected = Components::label(&truth, false).connected(start, goal);
        let belief = if episode % 2 == 0 {
            unknown_like(&truth)
        } else {
            noisy(&mut rng, &truth, 0.2)
        };
        for planner in OnlinePlanner::ALL {
            for unknown_passable in [true, false] {
                let opts = NavigateOptions {
                    planner,
                    sensor_range_cells: rng.random_range(1.0..8.0),
                    unknown_passable,
                    ..NavigateOptions::default()
                };
                let context =
                    format!("episode {episode} {planner:?} unknown_passable {unknown_passable}");
                let run = navigate(&belief, &truth, start, goal, &opts).unwrap();
                validate_path(&truth, &run.waypoints, false)
                    .unwrap_or_else(|e| panic!("{context}: {e:?}"));
                // Every cell stood on is free on the truth, consecutive cells are neighbours.
                assert!(
                    run.cells.iter().all(|c| truth.is_free(c.x, c.y)),
                    "{context}"
                );
                assert!(
                    run.cells
                        .windows(2)
                        .all(|w| w[0].x.abs_diff(w[1].x) <= 1 && w[0].y.abs_diff(w[1].y) <= 1),
                    "{context}"
                );
                assert_eq!(run.cells.first(), Some(&start));
                assert_eq!(run.waypoints.first(), Some(&start));
                match run.outcome {
                    Outcome::Reached => {
                        assert!(connected, "{context}: reached but BFS says unreachable");
                        assert_eq!(run.waypoints.last(), Some(&goal), "{context}");
                        reached += 1;
                    }
                    Outcome::GoalUnreachable => {
                        // It gave up where the goal is unreachable on its final belief
                        // (BFS), and, since the map's obstacles it has not seen are doubted
                        // before it gives up, on the truth too: noisy maps' false obstacles
                        // included.
                        let last = *run.cells.last().unwrap();
                        assert!(
                            !Components::label(&run.belief.grid, unknown_passable)
                                .connected(last, goal),
                            "{context}: gave up but BFS on the belief says reachable"
                        );
                        assert!(!connected, "{context}: gave up but BFS says reachable");
                        unreachable += 1;
                    }
                    other => panic!("{context}: {other:?}"),
                }
                assert!(run.length_cells >= 0.0 && !run.events.is_empty());
            }
        }
    }
    assert!(
        reached > 100 && unreachable > 20,
        "reached {reached}, unreachable {unreachable}"
    );
}

#[test]
fn a_false_wall_in_the_map_is_doubted_not_given_up_on() {
    // The map has a wall across the room that is not there; the robot sees 3 cells. Without
    // doubting, no path exists on the belief and the robot would give up at the start.
    let truth = OccupancyGrid::new(30, 10, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    let mut belief = truth.clone();
    for y in 0..10 {
        belief.set(20, y, Occupancy::Occupied).unwrap();
    }
    let (start, goal) = (CellXy::new(2, 5), CellXy::new(27, 5));
    for planner in OnlinePlanner::ALL {
        let opts = NavigateOptions {
            planner,
            sensor_range_cells: 3.0,
            ..NavigateOptions::default()
        };
        let run = navigate(&belief, &truth, start, goal, &opts).unwrap();
        assert_eq!(run.outcome, Outcome::Reached, "{planner:?}");
        validate_path(&truth, &run.waypoints, false).unwrap();
        // Straight across: the wall was doubted at the first plan (10 cells).
        assert!(
            (run.length_cells - 25.0).abs() < 1e-9,
            "{planner:?}: {}",
            run.length_cells
        );
        assert_eq!(run.events[0].doubted_cells, 10, "{planner:?}");
    }
}

#[test]
fn a_set_stop_flag_ends_the_run_with_an_error_naming_it() {
    // A long drive on unknown terrain; the flag is set before it starts: the first check
    // (planner or run) stops it.
    let truth = OccupancyGrid::new(200, 200, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    let belief = OccupancyGrid::new(200, 200, 1.0, [0.0; 2], Occupancy::Unknown).unwrap();
    let flag = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(true));
    for planner in OnlinePlanner::ALL {
        let opts = NavigateOptions {
            planner,
            budget: vpmap_plan::Budget {
                stop: vpmap_plan::Stop::new().with_flag(flag.clone()),
                ..vpmap_plan::Budget::default()
            },
            ..NavigateOptions::default()
        };
        let e = navigate(
            &belief,
            &truth,
            CellXy::new(0, 0),
            CellXy::new(199, 199),
            &opts,
        )
        .unwrap_err();
        assert!(matches!(e, PlanError::Stopped { .. }), "{planner:?}: {e:?}");
    }
}

#[test]
fn walled_in_goal_stops_with_unreachable_for_every_planner() {
    // The goal sits in a closed box the belief does not know about.
    let mut truth = OccupancyGrid::new(20, 20, 0.05, [0.0; 2], Occupancy::Free).unwrap();
    for i in 12..=18 {
        for (x, y) in [(i, 12), (i, 18), (12, i), (18, i)] {
            truth.set(x, y, Occupancy::Occupied).unwrap();
        }
    }
    let (start, goal) = (CellXy::new(1, 1), CellXy::new(15, 15));
    assert!(!Components::label(&truth, false).connected(start, goal));
    let belief = unknown_like(&truth);
    for planner in OnlinePlanner::ALL {
        let opts = NavigateOptions {
            planner,
            sensor_range_cells: 4.0,
            ..NavigateOptions::default()
        };
        let run = navigate(&belief, &truth, start, goal, &opts).unwrap();
        assert_eq!(run.outcome, Outcome::GoalUnreachable, "{planner:?}");
        assert_eq!(run.outcome.as_str(), "goal unreachable after sensing");
        validate_path(&truth, &run.waypoints, false).unwrap();
        assert!(run.moves < 2000, "{planner:?}: {} moves", run.moves);
    }
}

#[test]
fn with_a_perfect_belief_the_driven_length_is_the_offline_length() {
    let mut rng = rng(1516);
    let mut checked = 0;
    for _ in 0..30 {
        let truth = random_grid(&mut rng, 40, 30, 0.25, 0.0);
        let (Some(start), Some(goal)) = (free_cell(&mut rng, &truth), free_cell(&mut rng, &truth))
        else {
            continue;
        };
        for (planner, kind) in [
            (OnlinePlanner::Astar, PlannerKind::Astar),
            (OnlinePlanner::DStarLite, PlannerKind::Astar),
            (OnlinePlanner::AstarPs, PlannerKind::AstarPs),
            (OnlinePlanner::Mbpp, PlannerKind::Mbpp),
        ] {
            let offline = kind.planner(false).plan(&truth, start, goal).unwrap().best;
            let opts = NavigateOptions {
                planner,
                sensor_range_cells: 5.0,
                ..NavigateOptions::default()
            };
            let run = navigate(&truth, &truth, start, goal, &opts).unwrap();
            match offline {
                Some(plan) => {
                    assert_eq!(run.outcome, Outcome::Reached);
                    assert!(
                        (run.length_cells - plan.length_cells).abs() < 1e-9,
                        "{planner:?}: {} vs {}",
                        run.length_cells,
                        plan.length_cells
                    );
                    assert_eq!(
                        run.events.len(),
                        1,
                        "{planner:?}: no surprises, no re-plans"
                    );
                    checked += 1;
                }
                None => assert_eq!(run.outcome, Outcome::GoalUnreachable),
            }
        }
    }
    assert!(checked > 40);
}

#[test]
fn dstar_lite_is_optimal_on_the_belief_at_every_step_of_an_unknown_terrain_drive() {
    // Lockstep: the robot senses, D* Lite is told, and its path cost from the robot's cell
    // must equal a fresh A*'s on the same belief; the robot then takes D* Lite's first step.
    // (Whole runs of D* Lite and repeated A* may drive different lengths: both are optimal
    // on the belief at every step, but among equally short paths they may pick different
    // ones, which then reveal different cells.)
    let mut rng = rng(1517);
    let mut steps = 0;
    for _ in 0..15 {
        let truth = random_grid(&mut rng, 35, 35, 0.3, 0.0);
        let (Some(start), Some(goal)) = (free_cell(&mut rng, &truth), free_cell(&mut rng, &truth))
        else {
            continue;
        };
        let mut belief = Belief::new(unknown_like(&truth), 3.0);
        belief.grid.set(goal.x, goal.y, Occupancy::Free).unwrap();
        belief.sense(&truth, start, true);
        let opts = DStarLiteOptions {
            unknown_passable: true,
            ..DStarLiteOptions::default()
        };
        let mut dstar = DStarLite::new(&belief.grid, start, goal, &opts).unwrap();
        let mut robot = start;
        for _ in 0..500 {
            let plan = dstar.path().unwrap();
            let reference = astar(
                &belief.grid,
                robot,
                goal,
                &AstarOptions {
                    unknown_passable: true,
                    ..AstarOptions::default()
                },
            )
            .unwrap();
            assert_eq!(plan.is_some(), reference.is_some());
            let (Some(plan), Some(reference)) = (plan, reference) else {
                break;
            };
            assert!((plan.length_cells - reference.length_cells).abs() < 1e-9);
            steps += 1;
            if robot == goal {
                break;
            }
            let next = plan.waypoints[1];
            // The next cell is within range and so already sensed.
            assert!(
                truth.is_free(next.x, next.y),
                "D* Lite stepped into an obstacle at {next:?}"
            );
            robot = next;
            let sensed = belief.sense(&truth, robot, true);
            dstar.move_start(robot).unwrap();
            dstar.update_cells(&sensed.changes).unwrap();
        }
    }
    assert!(steps > 200, "{steps}");
}

#[test]
fn bad_navigation_inputs_are_refused_with_the_values() {
    let truth = OccupancyGrid::new(10, 10, 0.05, [0.0; 2], Occupancy::Free).unwrap();
    let other = OccupancyGrid::new(10, 11, 0.05, [0.0; 2], Occupancy::Free).unwrap();
    let coarse = OccupancyGrid::new(10, 10, 0.1, [0.0; 2], Occupancy::Free).unwrap();
    let opts = NavigateOptions::default();
    let (s, g) = (CellXy::new(0, 0), CellXy::new(9, 9));
    let err = navigate(&other, &truth, s, g, &opts).unwrap_err();
    assert!(
        matches!(err, PlanError::MapMismatch { .. }) && err.to_string().contains("10 x 11"),
        "{err}"
    );
    let err = navigate(&coarse, &truth, s, g, &opts).unwrap_err();
    assert!(
        err.to_string().contains("0.1") && err.to_string().contains("0.05"),
        "{err}"
    );
    for bad in [0.0, -1.0, f64::NAN, 1e6] {
        let opts = NavigateOptions {
            sensor_range_cells: bad,
            ..NavigateOptions::default()
        };
        let err = navigate(&truth, &truth, s, g, &opts).unwrap_err();
        assert!(
            matches!(err, PlanError::InvalidParameter { .. }),
            "{bad}: {err}"
        );
    }
    let mut blocked = truth.clone();
    blocked.set(9, 9, Occupancy::Occupied).unwrap();
    let err = navigate(&truth, &blocked, s, g, &opts).unwrap_err();
    assert!(
        matches!(
            err,
            PlanError::EndpointBlocked {
                endpoint: "goal",
                ..
            }
        ),
        "{err}"
    );
}

/// Drive `planner` and return the run.
fn drive(
    belief: &OccupancyGrid,
    truth: &OccupancyGrid,
    start: CellXy,
    goal: CellXy,
    planner: OnlinePlanner,
    range: f64,
) -> vpmap_plan::navigate::Navigation {
    let opts = NavigateOptions {
        planner,
        sensor_range_cells: range,
        ..NavigateOptions::default()
    };
    navigate(belief, truth, start, goal, &opts).unwrap()
}

/// Whether two runs drove the same track: the same cells, waypoints, length (to 1e-9) and
/// planning events (cells, reasons, planned lengths).
fn same_drive(a: &vpmap_plan::navigate::Navigation, b: &vpmap_plan::navigate::Navigation) -> bool {
    a.outcome == b.outcome
        && a.cells == b.cells
        && a.waypoints == b.waypoints
        && (a.length_cells - b.length_cells).abs() < 1e-9
        && a.events.len() == b.events.len()
        && a.events.iter().zip(&b.events).all(|(x, y)| {
            x.cell == y.cell
                && x.moves == y.moves
                && x.reason == y.reason
                && match (x.planned_length_cells, y.planned_length_cells) {
                    (Some(p), Some(q)) => (p - q).abs() < 1e-9,
                    (p, q) => p == q,
                }
        })
}

#[test]
fn under_the_common_tie_rule_astar_and_dstar_lite_drive_identical_tracks() {
    let mut rng = rng(1516);
    let (mut episodes, mut default_ties_differ) = (0, 0);
    for episode in 0..160 {
        let (w, h) = (rng.random_range(8..48), rng.random_range(8..48));
        let density = [0.05, 0.15, 0.3][episode % 3];
        let truth = random_grid(&mut rng, w, h, density, 0.0);
        let (Some(start), Some(goal)) = (free_cell(&mut rng, &truth), free_cell(&mut rng, &truth))
        else {
            continue;
        };
        // Unknown terrain mostly; every fourth episode a noisy map as belief.
        let belief = if episode % 4 == 3 {
            noisy(&mut rng, &truth, 0.1)
        } else {
            unknown_like(&truth)
        };
        let range = [2.0, 4.0, 10.0][episode % 3];
        let a = drive(
            &belief,
            &truth,
            start,
            goal,
            OnlinePlanner::AstarTies,
            range,
        );
        let d = drive(
            &belief,
            &truth,
            start,
            goal,
            OnlinePlanner::DStarLiteTies,
            range,
        );
        assert!(
            same_drive(&a, &d),
            "episode {episode}: {w}x{h}, {start:?} -> {goal:?}: A* drove {} cells ({} events), D* Lite {} ({} events)",
            a.length_cells,
            a.events.len(),
            d.length_cells,
            d.events.len()
        );
        // Both stay optimal on the belief: with a perfect sensor history the tracks are
        // valid on the truth.
        if a.outcome == Outcome::Reached {
            assert!(validate_path(&truth, &a.waypoints, false).is_ok());
        }
        episodes += 1;
        // Without the common rule the two choose differently among equally short paths.
        let a0 = drive(&belief, &truth, start, goal, OnlinePlanner::Astar, range);
        let d0 = drive(
            &belief,
            &truth,
            start,
            goal,
            OnlinePlanner::DStarLite,
            range,
        );
        if !same_drive(&a0, &d0) {
            default_ties_differ += 1;
        }
    }
    assert!(episodes > 120, "{episodes} episodes");
    // The test can tell: with their own tie rules the planners' tracks differ often.
    assert!(
        default_ties_differ > episodes / 4,
        "{default_ties_differ} of {episodes}"
    );
}

#[test]
#[ignore = "needs ../shared/data/movingai (absent from a fresh clone): cargo test --release -- --ignored shared_data"]
fn shared_data_common_tie_drives_are_identical_on_movingai_maps() {
    let dir = crate::movingai_dir();
    let mut rng = rng(1517);
    for map in [
        "rooms/32room_000.map",
        "da2/ht_chantry.map",
        "random/random512-20-0.map",
        "bg512/AR0500SR.map",
    ] {
        let truth = vpmap_plan::read_movingai_map(dir.join("maps").join(map)).unwrap();
        let components = Components::label(&truth, false);
        let mut done = 0;
        while done < 2 {
            let (Some(start), Some(goal)) =
                (free_cell(&mut rng, &truth), free_cell(&mut rng, &truth))
            else {
                continue;
            };
            if !components.connected(start, goal) {
                continue;
            }
            let belief = unknown_like(&truth);
            let a = drive(&belief, &truth, start, goal, OnlinePlanner::AstarTies, 10.0);
            let d = drive(
                &belief,
                &truth,
                start,
                goal,
                OnlinePlanner::DStarLiteTies,
                10.0,
            );
            assert_eq!(a.outcome, Outcome::Reached, "{map}");
            assert!(
                same_drive(&a, &d),
                "{map} {start:?} -> {goal:?}: {} against {}",
                a.length_cells,
                d.length_cells
            );
            println!(
                "{map} {start:?} -> {goal:?}: identical, {:.3} cells, {} events",
                a.length_cells,
                a.events.len()
            );
            done += 1;
        }
    }
}

#[test]
fn timing_the_tuned_astar_beside_a_drive_does_not_change_it() {
    let mut rng = rng(1518);
    let truth = random_grid(&mut rng, 40, 30, 0.2, 0.0);
    let (start, goal) = (
        free_cell(&mut rng, &truth).unwrap(),
        free_cell(&mut rng, &truth).unwrap(),
    );
    let belief = unknown_like(&truth);
    let opts = NavigateOptions {
        planner: OnlinePlanner::DStarLiteTies,
        sensor_range_cells: 4.0,
        ..NavigateOptions::default()
    };
    let plain = navigate(&belief, &truth, start, goal, &opts).unwrap();
    let timed =
        vpmap_plan::navigate::navigate_with_astar_timed(&belief, &truth, start, goal, &opts)
            .unwrap();
    assert!(same_drive(&plain, &timed));
    assert_eq!(plain.shadow_astar, None);
    let shadow = timed.shadow_astar.unwrap();
    assert!(shadow.forward_time_s > 0.0 && shadow.backward_time_s > 0.0);
    assert!(shadow.forward_expanded > 0 && shadow.backward_expanded > 0);
}

#[test]
fn the_astar_beside_a_drive_searches_forward_from_the_robot_and_backward_from_the_goal() {
    // A belief equal to the truth and a reachable goal: nothing sensed changes the belief,
    // so the drive has one planning event, and the A* beside it must expand what a fresh A*
    // expands from the start to the goal, and from the goal to the start.
    let mut rng = rng(1519);
    let fresh = |grid: &OccupancyGrid, from: CellXy, to: CellXy| {
        vpmap_plan::astar::astar(grid, from, to, &vpmap_plan::astar::AstarOptions::default())
            .unwrap()
            .map(|p| p.stats.expanded)
    };
    let (mut checked, mut unreachable) = (0, 0);
    for _ in 0..40 {
        let truth = random_grid(&mut rng, 40, 30, 0.25, 0.0);
        let (Some(start), Some(goal)) = (free_cell(&mut rng, &truth), free_cell(&mut rng, &truth))
        else {
            continue;
        };
        let opts = NavigateOptions {
            planner: OnlinePlanner::DStarLiteTies,
            sensor_range_cells: 4.0,
            ..NavigateOptions::default()
        };
        let (Some(forward), Some(backward)) =
            (fresh(&truth, start, goal), fresh(&truth, goal, start))
        else {
            // Unreachable: the robot doubts the map's unseen obstacles and re-plans many
            // times; the replay of those beliefs (checked against the final belief in debug
            // builds) still runs.
            let run =
                vpmap_plan::navigate::navigate_with_astar_timed(&truth, &truth, start, goal, &opts)
                    .unwrap();
            assert_eq!(run.outcome, Outcome::GoalUnreachable);
            assert!(run.events.len() > 1 && run.shadow_astar.is_some());
            unreachable += 1;
            continue;
        };
        let run =
            vpmap_plan::navigate::navigate_with_astar_timed(&truth, &truth, start, goal, &opts)
                .unwrap();
        assert_eq!(run.outcome, Outcome::Reached);
        assert_eq!(run.events.len(), 1, "{start:?} -> {goal:?}");
        let shadow = run.shadow_astar.unwrap();
        assert_eq!(shadow.forward_expanded, forward, "{start:?} -> {goal:?}");
        assert_eq!(shadow.backward_expanded, backward, "{start:?} -> {goal:?}");
        checked += 1;
    }
    assert!(
        checked >= 15 && unreachable >= 1,
        "{checked} reachable and {unreachable} unreachable pairs"
    );
}
