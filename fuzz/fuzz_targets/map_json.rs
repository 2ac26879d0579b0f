//! A `map.json`, as `vpmap plan map.json` reads it: the map's parsing and validation,
//! rasterising (at 0.05 m, or coarser so that the grid stays about 128 cells a side),
//! inflating by the default robot radius, then A* and MBPP (with a small budget) between the
//! first and the last free cell; every path found must pass `validate_path`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vpmap_metrology::map::FloorMap;
use vpmap_plan::grid::{CellXy, Occupancy};
use vpmap_plan::planner::{Planner, PlannerKind};
use vpmap_raster::{RasterOptions, rasterize_map};
use vpmap_plan::validate::validate_path;

/// Cells a side, about, at most.
const SIDE_CELLS: f64 = 128.0;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(map) = FloorMap::from_json_str(text) else {
        return;
    };
    let (mut lo, mut hi) = map.bounds();
    for p in map.free_space.iter().flat_map(|p| &p.exterior) {
        for axis in 0..2 {
            lo[axis] = lo[axis].min(p[axis]);
            hi[axis] = hi[axis].max(p[axis]);
        }
    }
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]) + 1.0;
    let resolution_m = (span / SIDE_CELLS).max(0.05);
    if !(resolution_m.is_finite() && resolution_m < 1e12) {
        return;
    }
    let options = RasterOptions {
        resolution_m,
        hidden_free: data.len() % 2 == 1,
        ..RasterOptions::default()
    };
    let Ok(grid) = rasterize_map(&map, &options) else {
        return;
    };
    let Ok(grid) = grid.inflate(0.2) else {
        return;
    };
    let free = |i: usize| (i % grid.width(), i / grid.width());
    let cells = grid.cells();
    let (Some(a), Some(b)) = (
        cells.iter().position(|&c| c == Occupancy::Free),
        cells.iter().rposition(|&c| c == Occupancy::Free),
    ) else {
        return;
    };
    let (start, goal) = (CellXy::from(free(a)), CellXy::from(free(b)));
    for kind in [PlannerKind::Astar, PlannerKind::Mbpp] {
        let planned = kind
            .planner(false)
            .with_mbpp_budget(20_000, 4)
            .plan(&grid, start, goal);
        if let Ok(planned) = planned {
            for plan in planned.best.iter().chain(&planned.alternatives) {
                if let Err(e) = validate_path(&grid, &plan.waypoints, false) {
                    panic!("{}: invalid path: {e:?}", kind.name());
                }
            }
        }
    }
});
