//! Integration tests of vpmap-plan: grids against independent references (geo predicates,
//! brute-force distances) and file round trips.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::float_cmp)]

mod inflation;
mod raster;
mod ros_files;

use proptest::prelude::*;
use vpmap_plan::{Cell, OccupancyGrid};

/// Any cell state.
pub(crate) fn any_cell() -> impl Strategy<Value = Cell> {
    prop_oneof![Just(Cell::Free), Just(Cell::Occupied), Just(Cell::Unknown)]
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
