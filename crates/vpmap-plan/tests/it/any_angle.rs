//! A* PS, Theta* and the exact any-angle planner on seeded random grids of several kinds,
//! against BFS connectivity, the independent path validator, each other (optimum <= Theta*,
//! optimum <= A* PS <= A*), and a brute-force complete visibility graph on tiny grids.

use rand::RngExt;
use vpmap_plan::{
    AstarOptions, AstarPsOptions, AstarSearch, Occupancy, OccupancyGrid, OptimalAnyAngleOptions,
    PlanError, ThetaStarOptions, astar_ps,
    mbpp::{LeaveRule, MbppOptions, mbpp},
    optimal_any_angle, path_length, theta_star, validate_path,
};

use crate::grids::{KINDS, generate, grid_of, traversable_cells};
use crate::{check_plan, rng};

#[derive(Default)]
struct Excess {
    sum: f64,
    count: usize,
}

impl Excess {
    fn add(&mut self, length: f64, optimum: f64) {
        if optimum > 0.0 {
            self.sum += length / optimum - 1.0;
            self.count += 1;
        }
    }

    fn mean_percent(&self) -> f64 {
        100.0 * self.sum / self.count.max(1) as f64
    }
}

#[test]
fn planners_agree_with_bfs_and_are_ordered_on_random_grids() {
    let mut rng = rng(0x7e7a_57a4);
    let mut search = AstarSearch::new();
    let (mut theta_excess, mut ps_excess, mut astar_excess, mut mbpp_excess) = (
        Excess::default(),
        Excess::default(),
        Excess::default(),
        Excess::default(),
    );
    let mut mbpp_shorter_than_ps = 0;
    let mut closer_excess = Excess::default();
    let (mut queries, mut unreachable) = (0, 0);
    for round in 0..2800 {
        let kind = KINDS[round % KINDS.len()];
        let (grid, unknown_passable) = generate(&mut rng, kind, 16);
        let cells = traversable_cells(&grid, unknown_passable);
        if cells.is_empty() {
            continue;
        }
        for _ in 0..3 {
            let start = cells[rng.random_range(0..cells.len())];
            let goal = cells[rng.random_range(0..cells.len())];
            let reachable = vpmap_plan::reachable(&grid, start, goal, unknown_passable);
            queries += 1;
            unreachable += usize::from(!reachable);
            let a = search
                .search(
                    &grid,
                    start,
                    goal,
                    &AstarOptions {
                        unknown_passable,
                        ..AstarOptions::default()
                    },
                )
                .unwrap();
            let ps = astar_ps(
                &grid,
                start,
                goal,
                &AstarPsOptions {
                    unknown_passable,
                    ..AstarPsOptions::default()
                },
            )
            .unwrap();
            let th = theta_star(
                &grid,
                start,
                goal,
                &ThetaStarOptions {
                    unknown_passable,
                    ..ThetaStarOptions::default()
                },
            )
            .unwrap();
            let op = optimal_any_angle(
                &grid,
                start,
                goal,
                &OptimalAnyAngleOptions {
                    unknown_passable,
                    ..OptimalAnyAngleOptions::default()
                },
            )
            .unwrap();
            let mb = mbpp(
                &grid,
                start,
                goal,
                &MbppOptions {
                    unknown_passable,
                    ..MbppOptions::default()
                },
            )
            .unwrap();
            let mb_closer = mbpp(
                &grid,
                start,
                goal,
                &MbppOptions {
                    unknown_passable,
                    leave: LeaveRule::Closer,
                    ..MbppOptions::default()
                },
            )
            .unwrap();
            let context = format!("{kind} round {round} {start:?} -> {goal:?}\n{grid:?}");
            assert_eq!(mb.best.is_some(), reachable, "MBPP {context}");
            assert_eq!(mb_closer.best.is_some(), reachable, "MBPP closer {context}");
            if let (Some(p), Some(o)) = (&mb_closer.best, &op) {
                check_plan("MBPP closer", &grid, p, start, goal, unknown_passable);
                assert!(
                    o.length_cells <= p.length_cells + 1e-9,
                    "optimal > MBPP closer: {context}"
                );
                closer_excess.add(p.length_cells, o.length_cells);
            }
            for alt in &mb.alternatives {
                check_plan(
                    "MBPP alternative",
                    &grid,
                    alt,
                    start,
                    goal,
                    unknown_passable,
                );
                assert!(alt.length_cells + 1e-9 >= op.as_ref().map_or(0.0, |p| p.length_cells));
            }
            assert_eq!(a.is_some(), reachable, "A* {context}");
            assert_eq!(ps.is_some(), reachable, "A* PS {context}");
            assert_eq!(th.is_some(), reachable, "Theta* {context}");
            assert_eq!(op.is_some(), reachable, "optimal {context}");
            let (Some(a), Some(ps), Some(th), Some(op), Some(mb)) = (a, ps, th, op, mb.best) else {
                continue;
            };
            for (name, plan) in [
                ("A*", &a),
                ("A* PS", &ps),
                ("Theta*", &th),
                ("optimal", &op),
                ("MBPP", &mb),
            ] {
                check_plan(name, &grid, plan, start, goal, unknown_passable);
            }
            assert!(
                op.length_cells <= th.length_cells + 1e-9,
                "optimal > Theta*: {context}"
            );
            assert!(
                op.length_cells <= ps.length_cells + 1e-9,
                "optimal > A* PS: {context}"
            );
            assert!(
                ps.length_cells <= a.length_cells + 2e-9,
                "A* PS > A*: {context}"
            );
            assert!(
                op.length_cells <= mb.length_cells + 1e-9,
                "optimal > MBPP: {context}"
            );
            mbpp_shorter_than_ps += usize::from(mb.length_cells < ps.length_cells - 1e-9);
            mbpp_excess.add(mb.length_cells, op.length_cells);
            theta_excess.add(th.length_cells, op.length_cells);
            ps_excess.add(ps.length_cells, op.length_cells);
            astar_excess.add(a.length_cells, op.length_cells);
        }
    }
    eprintln!(
        "any-angle on {queries} random queries ({unreachable} unreachable): mean excess over \
         the optimum: Theta* {:.3} %, A* PS {:.3} %, A* {:.3} %, MBPP {:.3} % (shorter than \
         A* PS on {mbpp_shorter_than_ps}), MBPP closer {:.3} %",
        theta_excess.mean_percent(),
        ps_excess.mean_percent(),
        astar_excess.mean_percent(),
        mbpp_excess.mean_percent(),
        closer_excess.mean_percent(),
    );
    assert!(unreachable > 0 && unreachable < queries / 2);
    assert!(theta_excess.count > 3000);
}

/// Shortest path lengths from `start` to every traversable cell in the complete
/// visibility graph of all traversable cell centres (edges checked by the independent
/// validator), by Dijkstra with a linear scan.
fn brute_force_lengths(
    grid: &OccupancyGrid,
    cells: &[(usize, usize)],
    start: usize,
    unknown_passable: bool,
) -> Vec<f64> {
    let n = cells.len();
    let mut visible = vec![false; n * n];
    for i in 0..n {
        for j in i..n {
            let ok =
                validate_path(grid, &[cells[i].into(), cells[j].into()], unknown_passable).is_ok();
            visible[i * n + j] = ok;
            visible[j * n + i] = ok;
        }
    }
    let mut dist = vec![f64::INFINITY; n];
    let mut done = vec![false; n];
    dist[start] = 0.0;
    while let Some(u) = (0..n)
        .filter(|&i| !done[i] && dist[i].is_finite())
        .min_by(|&i, &j| dist[i].total_cmp(&dist[j]))
    {
        done[u] = true;
        for v in 0..n {
            if !done[v] && visible[u * n + v] {
                let d = dist[u] + path_length(&[cells[u].into(), cells[v].into()]);
                if d < dist[v] {
                    dist[v] = d;
                }
            }
        }
    }
    dist
}

#[test]
fn optimal_matches_brute_force_visibility_graph_on_tiny_grids() {
    let mut rng = rng(0x0b7e_f0ce);
    let mut compared = 0;
    for round in 0..1400 {
        let kind = KINDS[round % KINDS.len()];
        let (grid, unknown_passable) = generate(&mut rng, kind, 8);
        let cells = traversable_cells(&grid, unknown_passable);
        if cells.is_empty() {
            continue;
        }
        let start = rng.random_range(0..cells.len());
        let reference = brute_force_lengths(&grid, &cells, start, unknown_passable);
        for _ in 0..3 {
            let goal = rng.random_range(0..cells.len());
            let opts = OptimalAnyAngleOptions {
                unknown_passable,
                ..OptimalAnyAngleOptions::default()
            };
            let plan = optimal_any_angle(&grid, cells[start], cells[goal], &opts).unwrap();
            let context = format!(
                "{kind} round {round} {:?} -> {:?}\n{grid:?}",
                cells[start], cells[goal]
            );
            match plan {
                Some(plan) => {
                    assert!(
                        (plan.length_cells - reference[goal]).abs() < 1e-9,
                        "optimal {} vs brute force {}: {context}",
                        plan.length_cells,
                        reference[goal]
                    );
                    compared += 1;
                }
                None => assert!(reference[goal].is_infinite(), "{context}"),
            }
        }
    }
    assert!(compared > 2500, "{compared}");
}

#[test]
fn bad_endpoints_are_errors_for_every_planner() {
    let mut grid = grid_of(4, 3, Occupancy::Free);
    grid.set(1, 1, Occupancy::Occupied).unwrap();
    grid.set(2, 1, Occupancy::Unknown).unwrap();
    for (start, goal) in [((0, 0), (4, 0)), ((1, 1), (0, 0)), ((0, 0), (2, 1))] {
        let results = [
            astar_ps(&grid, start, goal, &AstarPsOptions::default()).err(),
            theta_star(&grid, start, goal, &ThetaStarOptions::default()).err(),
            optimal_any_angle(&grid, start, goal, &OptimalAnyAngleOptions::default()).err(),
        ];
        for e in results {
            assert!(
                matches!(
                    e,
                    Some(PlanError::EndpointOutsideGrid { .. } | PlanError::EndpointBlocked { .. })
                ),
                "{e:?}"
            );
        }
    }
    // Unknown endpoints are fine when unknown cells are passable.
    assert!(
        optimal_any_angle(
            &grid,
            (0, 0),
            (2, 1),
            &OptimalAnyAngleOptions {
                unknown_passable: true,
                ..OptimalAnyAngleOptions::default()
            }
        )
        .unwrap()
        .is_some()
    );
}

#[test]
#[ignore = "needs ../shared/data/movingai (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_optimal_on_movingai_room_and_random_maps() {
    let dir = crate::movingai_dir();
    let mut excess = (Excess::default(), Excess::default(), Excess::default());
    let mut solved = 0;
    for (map, scen) in [
        ("room-64-64-8.map", "room-64-64-8-random-1.scen"),
        ("random-64-64-20.map", "random-64-64-20-random-1.scen"),
    ] {
        let grid = vpmap_plan::read_movingai_map(dir.join("maps/mapf").join(map)).unwrap();
        let problems = vpmap_plan::read_scen(dir.join("scen/mapf").join(scen)).unwrap();
        let stride = problems.len().div_ceil(12).max(1);
        for p in problems.iter().step_by(stride) {
            let op = optimal_any_angle(&grid, p.start, p.goal, &OptimalAnyAngleOptions::default())
                .unwrap()
                .unwrap();
            let th = theta_star(&grid, p.start, p.goal, &ThetaStarOptions::default())
                .unwrap()
                .unwrap();
            let ps = astar_ps(&grid, p.start, p.goal, &AstarPsOptions::default())
                .unwrap()
                .unwrap();
            let mb = mbpp(&grid, p.start, p.goal, &MbppOptions::default())
                .unwrap()
                .best
                .unwrap();
            for (name, plan) in [
                ("A* PS", &ps),
                ("Theta*", &th),
                ("optimal", &op),
                ("MBPP", &mb),
            ] {
                check_plan(name, &grid, plan, p.start, p.goal, false);
            }
            assert!(op.length_cells <= mb.length_cells + 1e-9, "{map} {p:?}");
            excess.2.add(mb.length_cells, op.length_cells);
            // The octile optimum is an 8-connected path, so never shorter than the optimum.
            assert!(
                op.length_cells <= p.optimal_length_cells + 1e-3,
                "{map} {p:?}"
            );
            assert!(
                op.length_cells <= th.length_cells + 1e-9
                    && op.length_cells <= ps.length_cells + 1e-9
            );
            excess.0.add(th.length_cells, op.length_cells);
            excess.1.add(ps.length_cells, op.length_cells);
            solved += 1;
        }
    }
    eprintln!(
        "any-angle on {solved} Moving AI problems: mean excess over the optimum: Theta* {:.3} %, \
         A* PS {:.3} %, MBPP {:.3} %",
        excess.0.mean_percent(),
        excess.1.mean_percent(),
        excess.2.mean_percent(),
    );
}
