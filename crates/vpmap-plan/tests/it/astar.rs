//! A* against `pathfinding::astar` with exact octile costs, and against BFS connectivity.

use std::cmp::Ordering;
use std::ops::Add;

use pathfinding::num_traits::Zero;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use vpmap_plan::{
    AstarOptions, AstarSearch, Components, Occupancy, OccupancyGrid, Passable, PlanError,
    Traversable, astar, path_length, validate_path,
};

use crate::grids::random_grid;
use crate::rng;

/// An exact octile path cost `straight + diagonal * sqrt 2`, totally ordered.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct Octile {
    straight: i64,
    diagonal: i64,
}

impl Octile {
    fn value(self) -> f64 {
        self.straight as f64 + self.diagonal as f64 * std::f64::consts::SQRT_2
    }
}

impl Add for Octile {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            straight: self.straight + o.straight,
            diagonal: self.diagonal + o.diagonal,
        }
    }
}

impl Zero for Octile {
    fn zero() -> Self {
        Self {
            straight: 0,
            diagonal: 0,
        }
    }
    fn is_zero(&self) -> bool {
        *self == Self::zero()
    }
}

impl Ord for Octile {
    /// Sign of `p - q sqrt 2` with `p = a1 - a2`, `q = b2 - b1`, in integers.
    fn cmp(&self, other: &Self) -> Ordering {
        let p = self.straight - other.straight;
        let q = other.diagonal - self.diagonal;
        match (p.signum(), q.signum()) {
            (0, 0) => Ordering::Equal,
            (ps, qs) if ps >= 0 && qs <= 0 => Ordering::Greater,
            (ps, qs) if ps <= 0 && qs >= 0 => Ordering::Less,
            (1, _) => (p * p).cmp(&(2 * q * q)),
            _ => (2 * q * q).cmp(&(p * p)),
        }
    }
}

impl PartialOrd for Octile {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The 8-connected, no-corner-cutting moves from `(x, y)`, built independently of the
/// crate's own A*.
fn successors(map: &Traversable, (x, y): (i64, i64)) -> Vec<((i64, i64), Octile)> {
    let mut out = Vec::new();
    for dy in -1..=1 {
        for dx in -1..=1 {
            if (dx, dy) == (0, 0) || !map.passable(x + dx, y + dy) {
                continue;
            }
            let diagonal = dx != 0 && dy != 0;
            if diagonal && !(map.passable(x + dx, y) && map.passable(x, y + dy)) {
                continue;
            }
            let cost = if diagonal {
                Octile {
                    straight: 0,
                    diagonal: 1,
                }
            } else {
                Octile {
                    straight: 1,
                    diagonal: 0,
                }
            };
            out.push(((x + dx, y + dy), cost));
        }
    }
    out
}

fn reference_length(
    map: &Traversable,
    start: (usize, usize),
    goal: (usize, usize),
) -> Option<Octile> {
    let goal = (goal.0 as i64, goal.1 as i64);
    let heuristic = |&(x, y): &(i64, i64)| {
        let (dx, dy) = ((x - goal.0).abs(), (y - goal.1).abs());
        Octile {
            straight: dx.max(dy) - dx.min(dy),
            diagonal: dx.min(dy),
        }
    };
    pathfinding::directed::astar::astar(
        &(start.0 as i64, start.1 as i64),
        |&n| successors(map, n),
        heuristic,
        |&n| n == goal,
    )
    .map(|(_, cost)| cost)
}

fn random_free_cell(
    rng: &mut ChaCha8Rng,
    map: &Traversable,
    w: usize,
    h: usize,
) -> Option<(usize, usize)> {
    (0..200).find_map(|_| {
        let c = (rng.random_range(0..w), rng.random_range(0..h));
        map.passable(c.0 as i64, c.1 as i64).then_some(c)
    })
}

#[test]
fn astar_matches_pathfinding_and_bfs_on_random_grids() {
    let mut rng = rng(2024);
    let mut search = AstarSearch::new();
    let (mut found, mut unreachable) = (0, 0);
    for round in 0..250 {
        let (w, h) = (rng.random_range(1..=40), rng.random_range(1..=40));
        let occupied = rng.random_range(0.0..0.45);
        let grid = random_grid(&mut rng, w, h, occupied, 0.05);
        let unknown_passable = round % 3 == 0;
        let opts = AstarOptions {
            unknown_passable,
            ..AstarOptions::default()
        };
        let map = Traversable::new(&grid, unknown_passable);
        let components = Components::label(&grid, unknown_passable);
        for _ in 0..8 {
            let (Some(start), Some(goal)) = (
                random_free_cell(&mut rng, &map, w, h),
                random_free_cell(&mut rng, &map, w, h),
            ) else {
                continue;
            };
            let plan = search.search(&grid, start, goal, &opts).unwrap();
            let reference = reference_length(&map, start, goal);
            let connected = components.connected(start, goal);
            assert_eq!(plan.is_some(), connected, "{start:?} -> {goal:?}");
            assert_eq!(reference.is_some(), connected, "{start:?} -> {goal:?}");
            let (Some(plan), Some(reference)) = (plan, reference) else {
                unreachable += 1;
                continue;
            };
            found += 1;
            assert!(
                (plan.length_cells - reference.value()).abs() < 1e-9,
                "{start:?} -> {goal:?}: {} vs {reference:?}",
                plan.length_cells
            );
            assert_eq!(plan.waypoints.first(), Some(&start.into()));
            assert_eq!(plan.waypoints.last(), Some(&goal.into()));
            for pair in plan.waypoints.windows(2) {
                let (dx, dy) = (pair[0].x.abs_diff(pair[1].x), pair[0].y.abs_diff(pair[1].y));
                assert!(dx <= 1 && dy <= 1 && dx + dy > 0, "{pair:?}");
            }
            assert!((path_length(&plan.waypoints) - plan.length_cells).abs() < 1e-9);
            validate_path(&grid, &plan.waypoints, unknown_passable).unwrap();
            assert!(plan.stats.expanded >= plan.waypoints.len());
            assert_eq!(plan.stats.los_checks, 0);
        }
    }
    println!("A* vs pathfinding: {found} paths, {unreachable} unreachable pairs");
    assert!(
        found > 800 && unreachable > 50,
        "{found} found, {unreachable} unreachable"
    );
}

#[test]
fn reused_search_matches_fresh_searches_across_grid_sizes() {
    let mut rng = rng(5);
    let mut search = AstarSearch::new();
    for _ in 0..40 {
        let (w, h) = (rng.random_range(2..=20), rng.random_range(2..=20));
        let grid = random_grid(&mut rng, w, h, 0.25, 0.0);
        let map = Traversable::new(&grid, false);
        for _ in 0..5 {
            let (Some(s), Some(g)) = (
                random_free_cell(&mut rng, &map, w, h),
                random_free_cell(&mut rng, &map, w, h),
            ) else {
                continue;
            };
            let opts = AstarOptions::default();
            assert_eq!(
                search.search(&grid, s, g, &opts).unwrap(),
                astar(&grid, s, g, &opts).unwrap()
            );
        }
    }
}

/// A kept search reuses its padded copy of the grid while the grid's revision stays the
/// same, clearing only what the last search reached: it must answer every query as a new
/// search does, through cell edits (`set`, `cells_mut`), clones, other grids, a change of
/// `unknown_passable`, and searches stopped by their budget midway.
#[test]
fn kept_search_sees_every_change_of_the_grid() {
    let mut rng = rng(27);
    let mut kept = AstarSearch::new();
    let mut grids: Vec<OccupancyGrid> = (0..3)
        .map(|_| {
            let (w, h) = (rng.random_range(20..=60), rng.random_range(20..=60));
            random_grid(&mut rng, w, h, 0.2, 0.05)
        })
        .collect();
    let (mut compared, mut short, mut stopped) = (0, 0, 0);
    for step in 0..3000 {
        let i = rng.random_range(0..grids.len());
        match rng.random_range(0..10) {
            0 => {
                let (w, h) = (grids[i].width(), grids[i].height());
                let (x, y) = (rng.random_range(0..w), rng.random_range(0..h));
                let cell = [Occupancy::Free, Occupancy::Occupied, Occupancy::Unknown]
                    [rng.random_range(0..3)];
                grids[i].set(x, y, cell).unwrap();
            }
            1 => {
                let cells = grids[i].cells_mut();
                let at = rng.random_range(0..cells.len());
                cells[at] = if cells[at] == Occupancy::Free {
                    Occupancy::Occupied
                } else {
                    Occupancy::Free
                };
            }
            2 if grids.len() < 6 => grids.push(grids[i].clone()),
            _ => {
                let grid = &grids[i];
                let unknown_passable = rng.random_bool(0.3);
                let map = Traversable::new(grid, unknown_passable);
                let (w, h) = (grid.width(), grid.height());
                let Some(start) = random_free_cell(&mut rng, &map, w, h) else {
                    continue;
                };
                // Half the goals near the start: searches that reach few cells, whose
                // marks the next search clears one by one.
                let goal = if rng.random_bool(0.5) {
                    let near = (
                        (start.0 + rng.random_range(0..4)).min(w - 1),
                        (start.1 + rng.random_range(0..4)).min(h - 1),
                    );
                    if map.passable(near.0 as i64, near.1 as i64) {
                        short += 1;
                        near
                    } else {
                        continue;
                    }
                } else {
                    let Some(goal) = random_free_cell(&mut rng, &map, w, h) else {
                        continue;
                    };
                    goal
                };
                let mut opts = AstarOptions {
                    unknown_passable,
                    ..AstarOptions::default()
                };
                if rng.random_bool(0.2) {
                    opts.budget.max_expansions = rng.random_range(1..50);
                }
                let answer = kept
                    .search(grid, start, goal, &opts)
                    .map_err(|e| e.to_string());
                let fresh = AstarSearch::new()
                    .search(grid, start, goal, &opts)
                    .map_err(|e| e.to_string());
                assert_eq!(answer, fresh, "step {step}: {start:?} -> {goal:?}");
                stopped += usize::from(answer.is_err());
                compared += 1;
            }
        }
    }
    assert!(
        compared > 1500 && short > 300 && stopped > 50,
        "{compared} compared, {short} short, {stopped} stopped by the budget"
    );
}

#[test]
fn start_equal_to_goal_is_a_one_cell_plan() {
    let grid = OccupancyGrid::new(3, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    let plan = astar(&grid, (1, 2), (1, 2), &AstarOptions::default())
        .unwrap()
        .unwrap();
    assert_eq!(plan.waypoints, [(1, 2)]);
    assert_eq!(plan.length_cells, 0.0);
}

#[test]
fn octile_costs_and_no_corner_cutting() {
    let grid = OccupancyGrid::new(10, 10, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    let plan = astar(&grid, (0, 0), (9, 5), &AstarOptions::default())
        .unwrap()
        .unwrap();
    assert!((plan.length_cells - (4.0 + 5.0 * std::f64::consts::SQRT_2)).abs() < 1e-12);
    // A wall with a one-cell gap at (5, 5): the path goes straight through the gap.
    let mut grid = grid.clone();
    for y in 0..10 {
        if y != 5 {
            grid.set(5, y, Occupancy::Occupied).unwrap();
        }
    }
    let plan = astar(&grid, (4, 4), (6, 6), &AstarOptions::default())
        .unwrap()
        .unwrap();
    assert_eq!(plan.waypoints, [(4, 4), (4, 5), (5, 5), (6, 5), (6, 6)]);
    assert_eq!(plan.length_cells, 4.0);
}

#[test]
fn bad_endpoints_are_errors_naming_the_cell() {
    let mut grid = OccupancyGrid::new(4, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    grid.set(1, 1, Occupancy::Occupied).unwrap();
    grid.set(2, 1, Occupancy::Unknown).unwrap();
    let opts = AstarOptions::default();
    let e = astar(&grid, (4, 0), (0, 0), &opts).unwrap_err();
    assert!(
        matches!(
            e,
            PlanError::EndpointOutsideGrid {
                endpoint: "start",
                x: 4,
                y: 0,
                ..
            }
        ),
        "{e}"
    );
    assert_eq!(e.to_string(), "start (4, 0) is outside the 4 x 3 grid");
    let e = astar(&grid, (0, 0), (1, 1), &opts).unwrap_err();
    assert_eq!(
        e.to_string(),
        "goal (1, 1) is an occupied cell, which is not traversable"
    );
    let e = astar(&grid, (2, 1), (0, 0), &opts).unwrap_err();
    assert!(
        e.to_string().contains("start (2, 1) is an unknown cell"),
        "{e}"
    );
    let through_unknown = AstarOptions {
        unknown_passable: true,
        ..AstarOptions::default()
    };
    let plan = astar(&grid, (2, 1), (0, 0), &through_unknown)
        .unwrap()
        .unwrap();
    validate_path(&grid, &plan.waypoints, true).unwrap();
    assert!(validate_path(&grid, &plan.waypoints, false).is_err());
}
