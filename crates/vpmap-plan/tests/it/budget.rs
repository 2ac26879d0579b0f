//! Work budgets and stops of every planner (issue 13): counted budgets stop at exactly the
//! work they allow, a set cancellation flag or a passed deadline stops every planner with
//! `PlanError::Stopped`, and a budget that suffices changes no answer.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use vpmap_plan::astar::{AstarOptions, astar};
use vpmap_plan::budget::{Budget, Stop, StopReason};
use vpmap_plan::optimal::{OptimalAnyAngleOptions, visibility_graph_any_angle};
use vpmap_plan::planner::{Planner, PlannerKind};
use vpmap_plan::theta_star::{ThetaStarOptions, theta_star};
use vpmap_plan::{Occupancy, OccupancyGrid, PlanError};

/// A 120 x 120 field of one-cell pillars on a 5-cell pitch (hundreds of corner cells), with
/// the goal cell (118, 118) walled in: every planner searches the whole field in vain.
fn pillars_with_walled_goal() -> OccupancyGrid {
    let n = 120;
    let mut grid = OccupancyGrid::new(n, n, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for y in (2..n - 4).step_by(5) {
        for x in (2..n - 4).step_by(5) {
            grid.set(x, y, Occupancy::Occupied).unwrap();
        }
    }
    for (x, y) in [(117, 117), (118, 117), (119, 117), (117, 118), (117, 119)] {
        grid.set(x, y, Occupancy::Occupied).unwrap();
    }
    grid
}

#[test]
fn a_cancelled_or_late_query_stops_every_planner_with_its_reason() {
    let grid = pillars_with_walled_goal();
    let (start, goal) = ((0, 0).into(), (118, 118).into());
    for (stop, reason) in [
        (
            Stop::new().with_flag(Arc::new(AtomicBool::new(true))),
            StopReason::Cancelled,
        ),
        (
            Stop::new().with_timeout(Duration::ZERO),
            StopReason::Deadline,
        ),
    ] {
        for kind in PlannerKind::ALL {
            // Without the stop every planner finds that the goal cannot be reached.
            let mut free = kind.planner(false);
            assert_eq!(free.plan(&grid, start, goal).unwrap().best, None, "{kind}");
            let mut planner = kind.planner(false).with_stop(stop.clone());
            match planner.plan(&grid, start, goal) {
                Err(PlanError::Stopped { reason: r, .. }) => assert_eq!(r, reason, "{kind}"),
                other => panic!("{kind}: expected a stop ({reason:?}), got {other:?}"),
            }
        }
    }
}

#[test]
fn the_stop_message_names_the_planner_and_the_time_allowed() {
    let grid = pillars_with_walled_goal();
    let opts = ThetaStarOptions {
        budget: Budget {
            stop: Stop::new().with_timeout(Duration::from_millis(1500)),
            ..Budget::default()
        },
        ..ThetaStarOptions::default()
    };
    // A deadline in the future does not stop a search that ends before it.
    assert!(
        theta_star(&grid, (0, 0), (60, 40), &opts)
            .unwrap()
            .is_some()
    );
    let late = ThetaStarOptions {
        budget: Budget {
            stop: Stop::new().with_deadline(std::time::Instant::now()),
            ..Budget::default()
        },
        ..ThetaStarOptions::default()
    };
    let message = theta_star(&grid, (0, 0), (118, 118), &late)
        .unwrap_err()
        .to_string();
    assert!(
        message.starts_with("Theta* stopped: it did not finish within its time limit of 0 s"),
        "{message}"
    );
    let cancelled = PlannerKind::Mbpp
        .planner(false)
        .with_stop(Stop::new().with_flag(Arc::new(AtomicBool::new(true))))
        .plan(&grid, (0, 0).into(), (118, 118).into())
        .unwrap_err()
        .to_string();
    assert_eq!(cancelled, "MBPP stopped: the request was cancelled");
}

#[test]
fn an_expansion_budget_allows_exactly_the_expansions_it_names() {
    let grid = pillars_with_walled_goal();
    let (start, goal) = ((0, 0), (100, 80));
    let full = astar(&grid, start, goal, &AstarOptions::default())
        .unwrap()
        .unwrap();
    let expanded = full.stats.expanded;
    assert!(expanded > 50, "{expanded}");
    let with = |max_expansions| AstarOptions {
        budget: Budget {
            max_expansions,
            ..Budget::default()
        },
        ..AstarOptions::default()
    };
    let enough = astar(&grid, start, goal, &with(expanded)).unwrap().unwrap();
    assert_eq!(enough.waypoints, full.waypoints);
    let err = astar(&grid, start, goal, &with(expanded - 1)).unwrap_err();
    assert!(
        matches!(err, PlanError::BudgetExhausted { option: "max_expansions", limit, .. } if limit == expanded - 1),
        "{err}"
    );
    assert!(err.to_string().contains("A* stopped after"), "{err}");
}

#[test]
fn a_sight_budget_stops_the_visibility_graph_planner() {
    let grid = pillars_with_walled_goal();
    let (start, goal) = ((0, 0), (100, 80));
    let full = visibility_graph_any_angle(&grid, start, goal, &OptimalAnyAngleOptions::default())
        .unwrap()
        .unwrap();
    let cells = full.stats.los_cells;
    let with = |max_sight_cells| OptimalAnyAngleOptions {
        budget: Budget {
            max_sight_cells,
            ..Budget::default()
        },
        ..OptimalAnyAngleOptions::default()
    };
    // Enough for every query it made; the answer is the same.
    let enough = visibility_graph_any_angle(&grid, start, goal, &with(cells))
        .unwrap()
        .unwrap();
    assert_eq!(enough.length_cells, full.length_cells);
    let err = visibility_graph_any_angle(&grid, start, goal, &with(cells / 2)).unwrap_err();
    assert!(
        matches!(
            err,
            PlanError::BudgetExhausted {
                option: "max_sight_cells",
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn a_flag_set_while_the_search_runs_stops_it() {
    // The visibility-graph planner on a 240 x 240 pillar field with the goal walled in tries every
    // pair of its thousands of corner cells: minutes of work. Another thread cancels it.
    let n = 240;
    let mut grid = OccupancyGrid::new(n, n, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for y in (2..n - 4).step_by(5) {
        for x in (2..n - 4).step_by(5) {
            grid.set(x, y, Occupancy::Occupied).unwrap();
        }
    }
    for (x, y) in [(237, 237), (238, 237), (239, 237), (237, 238), (237, 239)] {
        grid.set(x, y, Occupancy::Occupied).unwrap();
    }
    let flag = Arc::new(AtomicBool::new(false));
    let setter = {
        let flag = Arc::clone(&flag);
        std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(50));
            flag.store(true, std::sync::atomic::Ordering::Relaxed);
        })
    };
    let opts = OptimalAnyAngleOptions {
        budget: Budget {
            stop: Stop::new().with_flag(flag),
            ..Budget::default()
        },
        ..OptimalAnyAngleOptions::default()
    };
    let result = visibility_graph_any_angle(&grid, (0, 0), (238, 238), &opts);
    setter.join().unwrap();
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
