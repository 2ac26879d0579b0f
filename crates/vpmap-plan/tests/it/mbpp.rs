//! MBPP against independent references: BFS reachability ([`Components`]), the path
//! validator (separating axis theorem) and the exact any-angle optimum; its bug records
//! against the movement rule and its own counters; the m-line against its definition.

use proptest::prelude::*;
use rand::RngExt;
use vpmap_plan::mbpp::{BugFate, LeaveRule, MbppOptions, m_line, mbpp};
use vpmap_plan::reach::Components;
use vpmap_plan::{
    CellXy, Occupancy, OccupancyGrid, OptimalAnyAngleOptions, PlanError, Planned,
    optimal_any_angle, path_length, validate_path,
};

use crate::grids::random_grid;
use crate::rng;

fn opts(unknown_passable: bool, leave: LeaveRule, record_tracks: bool) -> MbppOptions {
    MbppOptions {
        unknown_passable,
        record_tracks,
        leave,
        ..MbppOptions::default()
    }
}

/// Every path MBPP returns (the best and each alternative) joins `start` to `goal` through
/// clear segments, has its reported length, and is no shorter than the optimum.
fn check_paths(
    result: &Planned,
    grid: &OccupancyGrid,
    (start, goal): (impl Into<CellXy>, impl Into<CellXy>),
    unknown_passable: bool,
    optimum: f64,
    context: &str,
) {
    let (start, goal): (CellXy, CellXy) = (start.into(), goal.into());
    let best = result.best.iter();
    for (i, plan) in best.chain(&result.alternatives).enumerate() {
        assert_eq!(plan.waypoints.first(), Some(&start), "path {i} {context}");
        assert_eq!(plan.waypoints.last(), Some(&goal), "path {i} {context}");
        if let Err(e) = validate_path(grid, &plan.waypoints, unknown_passable) {
            panic!("path {i} {:?} invalid: {e}\n{context}", plan.waypoints);
        }
        assert!((plan.length_cells - path_length(&plan.waypoints)).abs() < 1e-9);
        assert!(plan.length_cells >= optimum - 1e-9, "path {i} {context}");
    }
    let lengths: Vec<f64> = result.alternatives.iter().map(|p| p.length_cells).collect();
    assert!(
        lengths.windows(2).all(|w| w[0] <= w[1]),
        "alternatives not shortest first: {lengths:?} {context}"
    );
    for (i, a) in result.alternatives.iter().enumerate() {
        for b in result.alternatives.iter().skip(i + 1) {
            assert_ne!(a.waypoints, b.waypoints, "duplicate alternative {context}");
        }
    }
}

/// The bugs' records obey the movement rule and agree with the counters: every track is a
/// chain of legal single steps (checked by the validator) from the bug's birth cell, hits
/// and leaves lie on the track, and a goal was reached exactly when a path was found.
fn check_bugs(
    result: &Planned,
    grid: &OccupancyGrid,
    start: impl Into<CellXy>,
    unknown_passable: bool,
    context: &str,
) {
    let start: CellXy = start.into();
    let bugs = &result.bugs;
    assert!(!bugs.is_empty(), "{context}");
    assert_eq!(bugs[0].parent, None, "{context}");
    assert_eq!(bugs[0].cells.first(), Some(&start), "{context}");
    for (b, bug) in bugs.iter().enumerate() {
        if let Some(p) = bug.parent {
            assert!(p < b, "bug {b} born before its parent {p} {context}");
            // A newborn starts where its parent hit.
            let born = bug.cells.first().unwrap();
            assert!(bugs[p].hits.contains(born), "bug {b} {context}");
        }
        assert_eq!(bug.cells.len(), bug.steps + 1, "bug {b} {context}");
        for step in bug.cells.windows(2) {
            let (dx, dy) = (step[0].x.abs_diff(step[1].x), step[0].y.abs_diff(step[1].y));
            assert!(
                dx <= 1 && dy <= 1 && dx + dy > 0,
                "bug {b} {step:?} {context}"
            );
            assert!(
                validate_path(grid, step, unknown_passable).is_ok(),
                "bug {b} illegal step {step:?} {context}"
            );
        }
        for c in bug.hits.iter().chain(&bug.leaves) {
            assert!(bug.cells.contains(c), "bug {b} {c:?} {context}");
        }
    }
    let reached = bugs.iter().any(|b| b.fate == BugFate::ReachedGoal);
    assert_eq!(reached, result.best.is_some(), "{context}");
    if result.mbpp_stats.replans == 0 {
        // No nested runs: the counters are the top-level bugs'.
        assert_eq!(result.mbpp_stats.bugs, bugs.len(), "{context}");
        let steps: usize = bugs.iter().map(|b| b.steps).sum();
        assert_eq!(result.mbpp_stats.bug_steps, steps, "{context}");
        // Every hit gives birth to one bug, and both note the hit in their `hit_list`.
        assert_eq!(result.mbpp_stats.hits, bugs.len() - 1, "{context}");
        let hits: usize = bugs.iter().map(|b| b.hits.len()).sum();
        assert_eq!(hits, 2 * result.mbpp_stats.hits, "{context}");
        let waits = bugs.iter().filter(|b| b.fate == BugFate::Waiting).count();
        assert_eq!(result.mbpp_stats.waits, waits, "{context}");
    }
}

#[test]
fn mbpp_solves_exactly_the_bfs_reachable_queries_on_random_grids() {
    let mut rng = rng(2024);
    let mut solved = 0;
    let mut with_alternatives = 0;
    for round in 0..250 {
        let (w, h) = (rng.random_range(3..=24), rng.random_range(3..=24));
        let occupied = rng.random_range(0.05..0.45);
        let unknown = rng.random_range(0.0..0.1);
        let grid = random_grid(&mut rng, w, h, occupied, unknown);
        let unknown_passable = rng.random_bool(0.5);
        let components = Components::label(&grid, unknown_passable);
        let mut cell = || (rng.random_range(0..w), rng.random_range(0..h));
        let (start, goal) = (cell(), cell());
        if components.of(start).is_none() || components.of(goal).is_none() {
            continue;
        }
        let reachable = components.connected(start, goal);
        let optimum = optimal_any_angle(
            &grid,
            start,
            goal,
            &OptimalAnyAngleOptions {
                unknown_passable,
                ..OptimalAnyAngleOptions::default()
            },
        )
        .unwrap()
        .map_or(f64::INFINITY, |p| p.length_cells);
        assert_eq!(optimum.is_finite(), reachable, "optimum and BFS disagree");
        for leave in [LeaveRule::MLine, LeaveRule::Closer] {
            let context = format!("round {round} {leave:?} {start:?} -> {goal:?}\n{grid:?}");
            let result = mbpp(&grid, start, goal, &opts(unknown_passable, leave, true)).unwrap();
            assert_eq!(result.best.is_some(), reachable, "{context}");
            check_paths(
                &result,
                &grid,
                (start, goal),
                unknown_passable,
                optimum,
                &context,
            );
            check_bugs(&result, &grid, start, unknown_passable, &context);
            if leave == LeaveRule::MLine && result.mbpp_stats.replans == 0 {
                // Every m-line cell is hit at most once: at most 2 n + 1 bugs.
                let n = m_line(start, goal).len() - 1;
                assert!(result.bugs.len() <= 2 * n + 1, "{context}");
            }
            // Recording tracks changes nothing else.
            let quiet = mbpp(&grid, start, goal, &opts(unknown_passable, leave, false)).unwrap();
            assert_eq!(quiet.best, result.best, "{context}");
            assert_eq!(quiet.alternatives, result.alternatives, "{context}");
            assert_eq!(quiet.mbpp_stats, result.mbpp_stats, "{context}");
            assert!(quiet.bugs.iter().all(|b| b.cells.is_empty()), "{context}");
            solved += usize::from(reachable);
            with_alternatives += usize::from(!result.alternatives.is_empty());
        }
    }
    // The generator must exercise both answers and the alternatives.
    assert!(solved > 100, "{solved}");
    assert!(with_alternatives > 20, "{with_alternatives}");
}

#[test]
fn enclosed_goal_is_not_found_and_no_bug_reaches_it() {
    // .......
    // ..###..
    // ..#.#..
    // ..###..
    // .......
    let mut grid = OccupancyGrid::new(7, 5, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for (x, y) in [
        (2, 1),
        (3, 1),
        (4, 1),
        (2, 2),
        (4, 2),
        (2, 3),
        (3, 3),
        (4, 3),
    ] {
        grid.set(x, y, Occupancy::Occupied).unwrap();
    }
    for (start, goal) in [((0, 2), (3, 2)), ((3, 2), (6, 2))] {
        for leave in [LeaveRule::MLine, LeaveRule::Closer] {
            let result = mbpp(&grid, start, goal, &opts(false, leave, true)).unwrap();
            assert_eq!(result.best, None, "{leave:?} {start:?}");
            assert!(result.alternatives.is_empty());
            assert!(
                result
                    .bugs
                    .iter()
                    .all(|b| matches!(b.fate, BugFate::Looped | BugFate::Stuck)),
                "{:?}",
                result.bugs
            );
            check_bugs(&result, &grid, start, false, &format!("{leave:?}"));
        }
    }
}

#[test]
fn unknown_cells_are_walls_unless_passable() {
    // A wall of unknown cells across the grid.
    let mut grid = OccupancyGrid::new(5, 4, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for y in 0..4 {
        grid.set(2, y, Occupancy::Unknown).unwrap();
    }
    let closed = mbpp(&grid, (0, 1), (4, 2), &MbppOptions::default()).unwrap();
    assert_eq!(closed.best, None);
    let open = mbpp(&grid, (0, 1), (4, 2), &opts(true, LeaveRule::MLine, false)).unwrap();
    assert_eq!(open.best.unwrap().waypoints, [(0, 1), (4, 2)]);
}

#[test]
fn start_equal_to_goal_is_a_one_cell_path() {
    let grid = OccupancyGrid::new(3, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    let result = mbpp(&grid, (1, 2), (1, 2), &MbppOptions::default()).unwrap();
    let best = result.best.unwrap();
    assert_eq!(best.waypoints, [(1, 2)]);
    assert_eq!(best.length_cells, 0.0);
    assert_eq!(result.bugs.len(), 1);
    assert_eq!(result.bugs[0].fate, BugFate::ReachedGoal);
}

#[test]
fn bad_endpoints_are_errors() {
    let mut grid = OccupancyGrid::new(4, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    grid.set(1, 1, Occupancy::Occupied).unwrap();
    grid.set(2, 1, Occupancy::Unknown).unwrap();
    for (start, goal) in [
        ((0, 0), (4, 0)),
        ((0, 3), (0, 0)),
        ((1, 1), (0, 0)),
        ((0, 0), (2, 1)),
    ] {
        let e = mbpp(&grid, start, goal, &MbppOptions::default()).err();
        assert!(
            matches!(
                e,
                Some(PlanError::EndpointOutsideGrid { .. } | PlanError::EndpointBlocked { .. })
            ),
            "{start:?} -> {goal:?}: {e:?}"
        );
    }
    let through = opts(true, LeaveRule::MLine, false);
    assert!(
        mbpp(&grid, (0, 0), (2, 1), &through)
            .unwrap()
            .best
            .is_some()
    );
}

#[test]
#[ignore = "needs ../shared/data/movingai (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_mbpp_on_movingai_maps_is_valid_and_no_shorter_than_the_optimum() {
    let dir = crate::movingai_dir();
    let grid = vpmap_plan::read_movingai_map(dir.join("maps/mapf/room-64-64-8.map")).unwrap();
    let problems = vpmap_plan::read_scen(dir.join("scen/mapf/room-64-64-8-random-1.scen")).unwrap();
    let stride = problems.len().div_ceil(8).max(1);
    for p in problems.iter().step_by(stride) {
        let optimum = optimal_any_angle(&grid, p.start, p.goal, &OptimalAnyAngleOptions::default())
            .unwrap()
            .unwrap()
            .length_cells;
        for leave in [LeaveRule::MLine, LeaveRule::Closer] {
            let context = format!("{leave:?} {p:?}");
            let result = mbpp(&grid, p.start, p.goal, &opts(false, leave, true)).unwrap();
            assert!(result.best.is_some(), "{context}");
            check_paths(&result, &grid, (p.start, p.goal), false, optimum, &context);
            check_bugs(&result, &grid, p.start, false, &context);
        }
    }
}

proptest! {
    /// The m-line is a chain of 8-neighbour steps from start to goal, one per cell along
    /// the longer axis, each strictly closer to the goal, and the same line walked back.
    #[test]
    fn m_line_is_a_straight_8_connected_descent(
        start in (0usize..60, 0usize..60),
        goal in (0usize..60, 0usize..60),
    ) {
        let line = m_line(start, goal);
        let (start, goal) = (CellXy::from(start), CellXy::from(goal));
        prop_assert_eq!(line.first(), Some(&start));
        prop_assert_eq!(line.last(), Some(&goal));
        let long = start.x.abs_diff(goal.x).max(start.y.abs_diff(goal.y));
        prop_assert_eq!(line.len(), long + 1);
        let d2 = |c: CellXy| c.x.abs_diff(goal.x).pow(2) + c.y.abs_diff(goal.y).pow(2);
        for w in line.windows(2) {
            prop_assert!(w[0].x.abs_diff(w[1].x) <= 1 && w[0].y.abs_diff(w[1].y) <= 1);
            prop_assert!(d2(w[1]) < d2(w[0]), "{:?}", w);
        }
        // Each cell lies within half a cell of the straight segment, measured across the
        // longer axis: |cross| <= long / 2 in units of the segment's major extent.
        let (dx, dy) = (goal.x as i64 - start.x as i64, goal.y as i64 - start.y as i64);
        for &CellXy { x, y } in &line {
            let (px, py) = (x as i64 - start.x as i64, y as i64 - start.y as i64);
            let cross = (px * dy - py * dx).abs();
            prop_assert!(2 * cross <= long as i64, "{:?} off the line", (x, y));
        }
    }
}

/// A comb of walls with gaps at alternating ends: every wall splits the bugs again.
fn zig_zag(width: usize, height: usize) -> OccupancyGrid {
    let mut grid = OccupancyGrid::new(width, height, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for (k, y) in (2..height - 2).step_by(3).enumerate() {
        for x in 0..width {
            let gap = if k % 2 == 0 { x == width - 2 } else { x == 1 };
            if !gap {
                grid.set(x, y, Occupancy::Occupied).unwrap();
            }
        }
    }
    grid
}

/// Issue 40: on a comb, bugs walk corridors hundreds of cells long and check sight from the
/// corridor's first corner at every step; walked cell by cell that cost the corridor's
/// length a step (the 300 x 300 comb's MBPP-closer looked up 18 billion cells). With the
/// box index a check in open corridor costs a few look-ups, whatever the corridor's length.
#[test]
fn mbpp_sight_checks_along_a_long_corridor_cost_a_few_look_ups_a_step() {
    let grid = zig_zag(240, 41);
    let (start, goal) = ((120, 0), (120, 40));
    for leave in [LeaveRule::MLine, LeaveRule::Closer] {
        let opts = MbppOptions {
            leave,
            ..MbppOptions::default()
        };
        let planned = mbpp(&grid, start, goal, &opts).unwrap();
        let stats = planned.mbpp_stats;
        assert!(
            planned.best.is_some() && stats.bug_steps > 10_000,
            "{leave:?}: {stats:?}"
        );
        let per_check = stats.los_cells as f64 / stats.los_checks as f64;
        assert!(
            per_check < 8.0,
            "{leave:?}: {per_check:.1} look-ups a check, {stats:?}"
        );
    }
}

#[test]
fn a_bug_step_budget_stops_mbpp_with_an_error_naming_it() {
    let grid = zig_zag(60, 62);
    let (start, goal) = ((30, 0), (30, 61));
    let full = mbpp(&grid, start, goal, &MbppOptions::default()).unwrap();
    let steps = full.mbpp_stats.bug_steps;
    assert!(full.best.is_some() && steps > 1000, "{steps} steps");
    // Just enough passes; fewer stops with the budget named.
    let enough = MbppOptions {
        max_bug_steps: steps,
        ..MbppOptions::default()
    };
    assert!(mbpp(&grid, start, goal, &enough).unwrap().best.is_some());
    let tight = MbppOptions {
        max_bug_steps: steps / 2,
        ..MbppOptions::default()
    };
    let e = mbpp(&grid, start, goal, &tight).unwrap_err();
    assert!(
        matches!(e, PlanError::BudgetExhausted { limit, .. } if limit == steps / 2),
        "{e}"
    );
    assert!(e.to_string().contains("max_bug_steps"), "{e}");
}

#[test]
fn a_sight_budget_stops_mbpp_in_any_of_its_phases() {
    let grid = zig_zag(60, 62);
    let (start, goal) = ((30, 0), (30, 61));
    let full = mbpp(&grid, start, goal, &MbppOptions::default()).unwrap();
    let cells = full.mbpp_stats.los_cells;
    assert!(full.best.is_some() && cells > 10_000, "{cells} cells");
    let with = |max_sight_cells| MbppOptions {
        max_sight_cells,
        ..MbppOptions::default()
    };
    // Enough for every check it made: the same answer.
    let enough = mbpp(&grid, start, goal, &with(cells)).unwrap();
    assert_eq!(enough.best, full.best);
    assert_eq!(enough.alternatives, full.alternatives);
    // Budgets that run out during the walk and during the selection and alternatives.
    for limit in [cells / 100, cells / 2, cells - 1] {
        let e = mbpp(&grid, start, goal, &with(limit))
            .map(|p| p.mbpp_stats)
            .unwrap_err();
        assert!(
            matches!(e, PlanError::BudgetExhausted { option: "max_sight_cells", limit: l, .. } if l == limit),
            "{limit}: {e}"
        );
    }
}

#[test]
fn mbpp_keeps_the_shortest_alternatives_up_to_its_cap() {
    let grid = zig_zag(40, 32);
    let (start, goal) = ((20, 0), (20, 31));
    let all = mbpp(&grid, start, goal, &MbppOptions::default()).unwrap();
    let n = all.alternatives.len();
    assert!(n >= 3, "the comb gives several alternatives, got {n}");
    let mut lengths: Vec<f64> = all.alternatives.iter().map(|p| p.length_cells).collect();
    lengths.sort_by(f64::total_cmp);
    let capped = mbpp(
        &grid,
        start,
        goal,
        &MbppOptions {
            max_alternatives: 2,
            ..MbppOptions::default()
        },
    )
    .unwrap();
    let got: Vec<f64> = capped.alternatives.iter().map(|p| p.length_cells).collect();
    assert_eq!(got, lengths[..2]);
    assert_eq!(capped.best.unwrap().waypoints, all.best.unwrap().waypoints);
}
