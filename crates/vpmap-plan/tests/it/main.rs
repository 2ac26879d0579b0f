//! Integration tests of vpmap-plan: grids against independent references (geo predicates,
//! brute-force distances), file round trips, line of sight against the independent
//! validator, A* against `pathfinding::astar`, BFS and the Moving AI benchmark optima, MBPP
//! against BFS, the validator and the exact optimum.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::float_cmp)]

mod any_angle;
mod astar;
mod budget;
mod dstar_lite;
mod exact;
mod inflation;
mod line_of_sight;
mod mbpp;
mod movingai_benchmarks;
mod movingai_files;
mod navigate;
mod raster;
mod ros_files;

use std::path::PathBuf;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use proptest::prelude::*;
use vpmap_plan::{Occupancy, OccupancyGrid};

/// Any cell state.
pub(crate) fn any_cell() -> impl Strategy<Value = Occupancy> {
    prop_oneof![
        Just(Occupancy::Free),
        Just(Occupancy::Occupied),
        Just(Occupancy::Unknown)
    ]
}

/// Small random grids with random frames.
pub(crate) fn small_grid(max_side: usize) -> impl Strategy<Value = OccupancyGrid> {
    (1..=max_side, 1..=max_side).prop_flat_map(|(w, h)| {
        (
            proptest::collection::vec(any_cell(), w * h),
            0.001f64..10.0,
            -100.0f64..100.0,
            -100.0f64..100.0,
        )
            .prop_map(move |(cells, res, ox, oy)| {
                OccupancyGrid::from_cells(w, h, res, [ox, oy], cells).unwrap()
            })
    })
}

/// A seeded random generator.
pub(crate) fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A `width x height` grid, resolution 1, each cell occupied with probability `occupied`,
/// else unknown with probability `unknown`, else free.
pub(crate) fn random_grid(
    rng: &mut ChaCha8Rng,
    width: usize,
    height: usize,
    occupied: f64,
    unknown: f64,
) -> OccupancyGrid {
    let cells = (0..width * height)
        .map(|_| {
            let r: f64 = rng.random();
            if r < occupied {
                Occupancy::Occupied
            } else if r < occupied + unknown {
                Occupancy::Unknown
            } else {
                Occupancy::Free
            }
        })
        .collect();
    OccupancyGrid::from_cells(width, height, 1.0, [0.0; 2], cells).unwrap()
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
