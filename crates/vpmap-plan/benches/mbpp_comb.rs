//! MBPP on issue 40's comb (`mbpp_comb/300`): both leave rules on a 300 x 300 grid with a
//! wall every third row, each open one cell from alternate ends, from the middle of the top
//! row to the middle of the bottom row, default options (as `vpmap plan --planner mbpp`
//! and `mbpp-closer` run it; an error, such as a budget running out, is timed too).
//! Every bug walks the whole zig-zag and checks sight from its last corner at every step.
//!
//! ```text
//! cargo bench -p vpmap-plan --bench mbpp_comb
//! ```
#![allow(missing_docs)]
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use vpmap_plan::mbpp::{LeaveRule, MbppOptions, mbpp};
use vpmap_plan::{Occupancy, OccupancyGrid};

/// Issue 40's comb: a `side` x `side` grid with a wall every third row from row 2, each
/// open one cell from alternate ends (as `scripts/limits-table.sh` writes it).
fn comb(side: usize) -> OccupancyGrid {
    let mut grid = OccupancyGrid::new(side, side, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for (k, y) in (2..side - 2).step_by(3).enumerate() {
        for x in 0..side {
            let gap = if k % 2 == 0 { x == side - 2 } else { x == 1 };
            if !gap {
                grid.set(x, y, Occupancy::Occupied).unwrap();
            }
        }
    }
    grid
}

/// `mbpp_comb/300`: both MBPP rules on the 300 x 300 comb from the middle of the top row
/// to the middle of the bottom row, default options (as `vpmap plan --planner mbpp` and
/// `mbpp-closer` run it; an error, such as the sight budget running out, is timed too).
fn benches(c: &mut Criterion) {
    let grid = comb(300);
    let mut group = c.benchmark_group("mbpp_comb/300");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(20));
    group.warm_up_time(Duration::from_secs(1));
    for (name, leave) in [
        ("mbpp", LeaveRule::MLine),
        ("mbpp-closer", LeaveRule::Closer),
    ] {
        let opts = MbppOptions {
            leave,
            ..MbppOptions::default()
        };
        match mbpp(&grid, (150, 0), (150, 299), &opts) {
            Ok(p) => eprintln!("mbpp_comb/300/{name}: {:?}", p.mbpp_stats),
            Err(e) => eprintln!("mbpp_comb/300/{name}: {e}"),
        }
        group.bench_function(name, |b| {
            b.iter(|| black_box(mbpp(&grid, (150, 0), (150, 299), &opts).is_ok()));
        });
    }
    group.finish();
}

criterion_group!(comb_group, benches);
criterion_main!(comb_group);
