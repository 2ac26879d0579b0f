//! Integration tests of vpmap-plan: grids against independent references (brute-force
//! distances), file round trips, line of sight against the independent
//! validator, A* against `pathfinding::astar`, BFS and the Moving AI benchmark optima, MBPP
//! against BFS, the validator and the exact optimum.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::float_cmp)]

mod any_angle;
mod astar;
mod budget;
mod dstar_lite;
mod exact;
mod grids;
mod inflation;
mod line_of_sight;
mod mbpp;
mod movingai_benchmarks;
mod movingai_files;
mod navigate;
mod navigate_smooth;
mod reeds_shepp;
mod ros_files;
mod smooth;

use std::path::PathBuf;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use vpmap_plan::{CellXy, OccupancyGrid, path_length, validate_path};

/// A seeded random generator.
pub(crate) fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// The shared Moving AI benchmark folder (`../shared/data/movingai` beside the workspace).
/// The tests that read it are `#[ignore]`d, so that a plain `cargo test` counts them as
/// ignored rather than passed; run them with `cargo test -- --ignored shared_data`, which
/// fails here when the folder is absent.
pub(crate) fn movingai_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/movingai");
    assert!(
        dir.join("maps").is_dir() && dir.join("scen").is_dir(),
        "no Moving AI benchmark data at {} (maps/ and scen/): this test needs ../shared/data",
        dir.display()
    );
    dir
}

/// Check a planner's path: it runs from `start` to `goal`, the independent validator accepts
/// it on `grid`, and its length is its waypoints'.
pub(crate) fn check_plan(
    name: &str,
    grid: &OccupancyGrid,
    plan: &vpmap_plan::Plan,
    start: impl Into<CellXy>,
    goal: impl Into<CellXy>,
    unknown_passable: bool,
) {
    let (start, goal): (CellXy, CellXy) = (start.into(), goal.into());
    assert_eq!(plan.waypoints.first(), Some(&start), "{name}");
    assert_eq!(plan.waypoints.last(), Some(&goal), "{name}");
    if let Err(e) = validate_path(grid, &plan.waypoints, unknown_passable) {
        panic!("{name} path {:?} invalid: {e}\n{grid:?}", plan.waypoints);
    }
    assert!(
        (plan.length_cells - path_length(&plan.waypoints)).abs() < 1e-9,
        "{name}"
    );
}
