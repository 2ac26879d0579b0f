//! Moving AI benchmark files: a `.map`'s text, a NUL byte, then a `.scen`'s text; both are
//! parsed. When both parse, the map is at most 256 x 256 cells and the first scenario fits
//! it, A* runs on it and its path must pass `validate_path`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vpmap_plan::movingai::{parse_movingai_map, parse_scen};
use vpmap_plan::planner::{Planner, PlannerKind};
use vpmap_plan::validate::validate_path;

fuzz_target!(|data: &[u8]| {
    let split = data.iter().position(|&b| b == 0).unwrap_or(data.len());
    let (map, scen) = (&data[..split], data.get(split + 1..).unwrap_or_default());
    let grid = std::str::from_utf8(map)
        .ok()
        .and_then(|t| parse_movingai_map(t).ok());
    let scenarios = std::str::from_utf8(scen)
        .ok()
        .and_then(|t| parse_scen(t).ok());
    let (Some(grid), Some(scenarios)) = (grid, scenarios) else {
        return;
    };
    let Some(s) = scenarios.first() else {
        return;
    };
    if grid.width() > 256
        || grid.height() > 256
        || (s.width, s.height) != (grid.width(), grid.height())
    {
        return;
    }
    if let Ok(planned) = PlannerKind::Astar
        .planner(false)
        .plan(&grid, s.start, s.goal)
        && let Some(plan) = planned.best
        && let Err(e) = validate_path(&grid, &plan.waypoints, false)
    {
        panic!("A*: invalid path: {e:?}");
    }
});
