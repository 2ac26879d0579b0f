//! Obstacle inflation against brute-force references.

use proptest::prelude::*;
use vpmap_plan::{Occupancy, OccupancyGrid};

use crate::grids::small_grid;

/// Distance, metres, from a point to the square of cell `(x, y)`, in world coordinates.
fn distance_to_cell_square(grid: &OccupancyGrid, p: [f64; 2], x: usize, y: usize) -> f64 {
    let c = grid.world_from_cell(x, y);
    let half = grid.resolution_m() / 2.0;
    let dx = ((p[0] - c[0]).abs() - half).max(0.0);
    let dy = ((p[1] - c[1]).abs() - half).max(0.0);
    dx.hypot(dy)
}

fn occupied_cells(grid: &OccupancyGrid) -> Vec<(usize, usize)> {
    (0..grid.height())
        .flat_map(|y| (0..grid.width()).map(move |x| (x, y)))
        .filter(|&(x, y)| grid.get(x, y) == Some(Occupancy::Occupied))
        .collect()
}

#[test]
fn every_cell_within_the_radius_is_occupied_and_none_much_farther() {
    let res = 0.05;
    let mut grid = OccupancyGrid::new(40, 30, res, [-1.0, -0.5], Occupancy::Free).unwrap();
    for (x, y) in [(5, 5), (6, 5), (20, 15), (39, 29), (0, 29), (30, 3)] {
        grid.set(x, y, Occupancy::Occupied).unwrap();
    }
    for y in 10..20 {
        grid.set(12, y, Occupancy::Unknown).unwrap();
    }
    let obstacles = occupied_cells(&grid);
    for radius in [0.0, 0.03, 0.05, 0.12, 0.2, 0.37] {
        let inflated = grid.inflate(radius).unwrap();
        let diagonal = res * std::f64::consts::SQRT_2;
        for y in 0..grid.height() {
            for x in 0..grid.width() {
                let centre = grid.world_from_cell(x, y);
                let nearest_centre = obstacles
                    .iter()
                    .map(|&(a, b)| {
                        let o = grid.world_from_cell(a, b);
                        (o[0] - centre[0]).hypot(o[1] - centre[1])
                    })
                    .fold(f64::INFINITY, f64::min);
                let was = grid.get(x, y).unwrap();
                let now = inflated.get(x, y).unwrap();
                if nearest_centre <= radius {
                    assert_eq!(now, Occupancy::Occupied, "({x}, {y}) r = {radius}");
                }
                if nearest_centre > radius + diagonal {
                    assert_eq!(now, was, "({x}, {y}) r = {radius}");
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// The inflation rule, cell by cell, against a brute-force distance to every obstacle's
    /// square computed in world coordinates.
    #[test]
    fn inflation_matches_brute_force(grid in small_grid(14), radius_cells in 0.0f64..6.0) {
        let radius_m = radius_cells * grid.resolution_m();
        let inflated = grid.inflate(radius_m).unwrap();
        let obstacles = occupied_cells(&grid);
        let distance = grid.obstacle_distance_m();
        for y in 0..grid.height() {
            for x in 0..grid.width() {
                let centre = grid.world_from_cell(x, y);
                let d = obstacles
                    .iter()
                    .map(|&(a, b)| distance_to_cell_square(&grid, centre, a, b))
                    .fold(f64::INFINITY, f64::min);
                let i = grid.index(x, y).unwrap();
                if d.is_finite() {
                    prop_assert!((distance[i] - d).abs() <= 1e-9 * (1.0 + d), "{} vs {}", distance[i], d);
                } else {
                    prop_assert!(distance[i].is_infinite());
                }
                if (d - radius_m).abs() < 1e-9 * (1.0 + d) {
                    continue; // a tie: rounding decides
                }
                let expected = if d <= radius_m { Occupancy::Occupied } else { grid.get(x, y).unwrap() };
                prop_assert_eq!(inflated.get(x, y).unwrap(), expected, "({}, {})", x, y);
            }
        }
    }

    /// Inflation only ever turns cells into obstacles.
    #[test]
    fn inflation_only_adds_obstacles(grid in small_grid(12), r in 0.0f64..3.0) {
        let inflated = grid.inflate(r * grid.resolution_m()).unwrap();
        for (before, after) in grid.cells().iter().zip(inflated.cells()) {
            prop_assert!(after == before || *after == Occupancy::Occupied);
        }
    }
}
