//! What the smooth planner's polish step costs, side by side with the fillet search whose
//! paths it polishes, on the same queries.
//!
//! Map: one Nav2-benchmark-like grid of 2000 x 2000 cells (seeded rectangles of 10 to 50
//! cells over about 10 % of the area, as `vpmap bench --smooth` makes them). Queries:
//! `POLISH_BENCH_QUERIES` (default 12) seeded free start and goal cells 600-1200 cells
//! apart, every other one with both headings given, turning radius 6 cells (0.3 m). The
//! exact any-angle paths and the distance field are made once, outside the timing; then
//! `polish/fillet` times the fillet search over every query and `polish/polish` times
//! [`polish`] over the fillet's paths (one iteration = every query). Before timing it
//! prints the curvature sign changes and the total length before and after the polish.
#![allow(missing_docs)]
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vpmap_plan::smooth::clearance::Field;
use vpmap_plan::smooth::fillet::{FilletStats, fillet};
use vpmap_plan::smooth::polish::polish;
use vpmap_plan::smooth::{Pose, SmoothCurve};
use vpmap_plan::{Budget, CellXy, ExactPlanner, Occupancy, OccupancyGrid};

const RADIUS_CELLS: f64 = 6.0;

fn nav2_like(seed: u64, side: usize) -> OccupancyGrid {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut grid = OccupancyGrid::new(side, side, 0.05, [0.0; 2], Occupancy::Free).unwrap();
    let count = ((side * side) as f64 * 0.1 / 900.0) as usize;
    for _ in 0..count {
        let (w, h) = (rng.random_range(10..51), rng.random_range(10..51));
        let (x, y) = (rng.random_range(0..side), rng.random_range(0..side));
        for yy in y..(y + h).min(side) {
            for xx in x..(x + w).min(side) {
                grid.set(xx, yy, Occupancy::Occupied).unwrap();
            }
        }
    }
    grid
}

/// A query: the taut path's waypoints and the ends as the fillet takes them.
type Query = (Vec<CellXy>, (Pose, bool, Pose, bool));

fn queries(grid: &OccupancyGrid, n: usize) -> Vec<Query> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut exact = ExactPlanner::new(grid, false);
    let mut out = Vec::new();
    for _ in 0..100_000 {
        if out.len() >= n {
            break;
        }
        let mut cell = || {
            CellXy::new(
                rng.random_range(0..grid.width()),
                rng.random_range(0..grid.height()),
            )
        };
        let (s, g) = (cell(), cell());
        if !grid.is_free(s.x, s.y) || !grid.is_free(g.x, g.y) {
            continue;
        }
        let d = (s.x as f64 - g.x as f64).hypot(s.y as f64 - g.y as f64);
        if !(600.0..=1200.0).contains(&d) {
            continue;
        }
        let Some(taut) = exact.plan(s, g, &Budget::default()).unwrap() else {
            continue;
        };
        let headed = out.len() % 2 == 0;
        let (hs, hg) = (rng.random_range(-PI..PI), rng.random_range(-PI..PI));
        let ends = (
            Pose::new(s.x as f64, s.y as f64, if headed { hs } else { 0.0 }),
            !headed,
            Pose::new(g.x as f64, g.y as f64, if headed { hg } else { 0.0 }),
            !headed,
        );
        out.push((taut.waypoints, ends));
    }
    out
}

fn fillet_all(field: &Field, qs: &[Query]) -> Vec<(SmoothCurve, (bool, bool))> {
    qs.iter()
        .filter_map(|(w, ends)| {
            let mut stats = FilletStats::default();
            fillet(field, w, *ends, RADIUS_CELLS, false, &mut stats).map(|c| (c, (ends.1, ends.3)))
        })
        .collect()
}

fn bench_polish(c: &mut Criterion) {
    let n = std::env::var("POLISH_BENCH_QUERIES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(12);
    let grid = nav2_like(1, 2000);
    let field = Field::new(&grid, false);
    let qs = queries(&grid, n);
    let curves = fillet_all(&field, &qs);
    let (mut before, mut after, mut len_before, mut len_after) = (0, 0, 0.0, 0.0);
    for (curve, free) in &curves {
        let p = polish(&field, curve, *free, RADIUS_CELLS, false).unwrap_or_else(|| curve.clone());
        before += curve.curvature_sign_changes();
        after += p.curvature_sign_changes();
        len_before += curve.length();
        len_after += p.length();
    }
    println!(
        "polish: {} of {} queries filleted; curvature sign changes {before} -> {after}; total length {len_before:.4} -> {len_after:.4} cells",
        curves.len(),
        qs.len()
    );
    let mut group = c.benchmark_group("polish");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(5));
    group.bench_function("fillet", |b| b.iter(|| black_box(fillet_all(&field, &qs))));
    group.bench_function("polish", |b| {
        b.iter(|| {
            for (curve, free) in &curves {
                black_box(polish(&field, curve, *free, RADIUS_CELLS, false));
            }
        });
    });
    group.finish();
}

criterion_group!(benches, bench_polish);
criterion_main!(benches);
